#pragma once
// The ContactSet concept: everything a solver relies on from the policy that owns the
// sub-contacts of a scene (their creation, storage, kinematics, the loop that calls the contact
// law, and the gather of their forces onto gridpoints). The solver knows no concrete contact set;
// contact::face_contacts (the bonded faces of a tessellation) is one, a detecting set another.
//
// One time step, as the solver drives it (docs/architecture.md):
//   c.prepare_step(gp, dt)            serial; the only call that may allocate (a detecting set
//                                     rebuilds its pairs here and reports the growth)
//   c.run_task(t, gp, dt), t < c.task_count()
//                                     concurrently for distinct t, in one parallel region with
//                                     the zone tasks; each writes only the sub-contacts it owns
//   c.add_force(g, gp)                concurrently for distinct gridpoints g: the gather, in a
//                                     fixed order so results are bit-identical for any thread count
// c.update(gp, dt) does the three in order (the unfused path, tests).
//
// | expression                          | meaning                                                         |
// |-------------------------------------|-----------------------------------------------------------------|
// | C::law_type                         | the ContactLaw evaluated per sub-contact                        |
// | C::params                           | what the constructor takes (face_contacts: material_table)      |
// | C(tess, mesh, params)               | builds the set for the blocks of `mesh`; throws invalid_input / |
// |                                     | geometry_error naming the entity                                |
// | c.prepare_step(cgp, dt)             | once per step before the tasks (displacements at t, velocities  |
// |                                     | at t - dt/2, dt in s)                                           |
// | cc.task_count()                     | number of independent force tasks this step                     |
// | c.run_task(t, cgp, dt)              | noexcept: kinematics, law update and force of task t's          |
// |                                     | sub-contacts (stored in the set, not yet on gridpoints)         |
// | cc.add_force(g, gp)                 | adds the contact force on gridpoint g to gp.force (N)           |
// | c.update(gp, dt)                    | prepare_step + every task + the gather of every gridpoint       |
// | cc.add_stiffness_bounds(gp)         | adds Gershgorin row bounds (N/m) to gp.stiffness, valid for any |
// |                                     | orientation the contacts may take                               |
// | cc.energies()                       | contact_energies (J), summed in a fixed order                   |
// | cc.subcontact_count()               | number of sub-contacts now                                      |
// | cc.state(i), cc.area(i), cc.normal(i), cc.force(i), cc.node_a(i), cc.node_b(i)                       |
// |                                     | per sub-contact read access: law state, tributary area (m^2),   |
// |                                     | unit normal A->B, force on node B (N), gridpoints of A and B    |
// | cc.subcontact_params(i)             | the law parameters sub-contact i is evaluated with              |
// | c.checkpoint(ar)       (optional)   | saves or loads the sub-contact states from Law::state_fields    |
// |                                     | (law::checkpoint_states) and whatever else the set evolves      |
// |                                     | (io/checkpoint.hpp); needed by save/load_checkpoint             |

#include <concepts>

#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/tessellation.hpp"
#include "../law/concepts.hpp"

namespace tessera::contact {

/// Energies held by a contact set (J): sums over sub-contacts of area x the law's per-area
/// energies, accumulated in sub-contact order (deterministic).
struct contact_energies {
  real stored = 0;                  ///< recoverable elastic energy, area x Law::stored_energy
  real dissipated_tension = 0;      ///< by tensile softening (state field dissipated_tension)
  real dissipated_shear = 0;        ///< by Coulomb slip and shear failure (dissipated_shear)
  real dissipated_compression = 0;  ///< by compressive plasticity (dissipated_compression)
  real dissipated = 0;              ///< all mechanisms, area x Law::dissipated_energy
  /// Energy put into the springs (+) or taken out (-) when a detecting set re-discretises its
  /// patches at rebuilds (new corners, changed tributary areas, dropped corners); 0 for a fixed set.
  real rebuild_exchange = 0;
};

template <class C>
concept ContactSet = requires(C& c, const C& cc, const geometry::tessellation& tess, const geometry::block_mesh& mesh,
                              const typename C::params& p, node_set& gp, const node_set& cgp, real dt, index_t i) {
  typename C::law_type;
  requires law::ContactLaw<typename C::law_type>;
  typename C::params;
  requires std::constructible_from<C, const geometry::tessellation&, const geometry::block_mesh&,
                                   const typename C::params&>;
  { c.prepare_step(cgp, dt) } -> std::same_as<void>;
  { cc.task_count() } -> std::convertible_to<index_t>;
  { c.run_task(i, cgp, dt) } noexcept -> std::same_as<void>;
  { cc.add_force(i, gp) } noexcept -> std::same_as<void>;
  { c.update(gp, dt) } -> std::same_as<void>;
  { cc.add_stiffness_bounds(gp) } -> std::same_as<void>;
  { cc.energies() } -> std::same_as<contact_energies>;
  { cc.subcontact_count() } -> std::convertible_to<index_t>;
  cc.state(i);
  { cc.area(i) } -> std::convertible_to<real>;
  { cc.normal(i) } -> std::convertible_to<vec3>;
  { cc.force(i) } -> std::convertible_to<vec3>;
  { cc.node_a(i) } -> std::convertible_to<index_t>;
  { cc.node_b(i) } -> std::convertible_to<index_t>;
  { cc.subcontact_params(i) } -> std::convertible_to<const typename C::law_type::params&>;
};

/// Current position (m) of sub-contact i of contact set c with gridpoints gp: the mean of the two
/// material points on its blocks for a detecting set (c.position_a, c.position_b: node_a and
/// node_b are frame gridpoints there, not points of the contact), else the set's own position
/// (face contacts: the mean of the two gridpoints' positions). The one definition the VTK
/// snapshot (io/vtk_contacts.hpp) and the Python module's contact state share.
template <class C>
[[nodiscard]] vec3 subcontact_position(const C& c, index_t i, const node_set& gp) {
  if constexpr (requires { c.position_a(i, gp); })
    return 0.5 * (c.position_a(i, gp) + c.position_b(i, gp));
  else
    return c.position(i, gp);
}

}  // namespace tessera::contact
