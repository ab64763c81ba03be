#pragma once
// The Reinforcement concept: the policy that adds embedded bars to a solver (DESIGN.md §3
// "Reinforcement"). A reinforcement owns its bar nodes as a node_set, which the solver integrates
// exactly like the block gridpoints (same central-difference update, damping and boundary
// conditions), and adds its forces in step 4 of the step order (bar axial + bond forces, after the
// contacts, before the integrator).
//
// | expression                          | meaning                                                        |
// |-------------------------------------|----------------------------------------------------------------|
// | R::params                           | plain struct: steel, bond law and bar geometry, SI units       |
// | R::enabled                          | constexpr bool; false for reinforcement::none, so the solver   |
// |                                     | removes every reinforcement call with `if constexpr`           |
// | r.build(p, mesh, gridpoints)        | validates p, discretises the bars, locates each bar node in    |
// |                                     | its host zone, sets bar-node masses; throws invalid_input      |
// | r.nodes()                           | node_set of the bar nodes (m, kg, N), integrated by the solver |
// | r.add_stiffness_bounds(gridpoints)  | sets nodes().stiffness and adds the bond contribution to the   |
// |                                     | host gridpoints' stiffness (N/m, Gershgorin row-sum bounds)    |
// | r.accumulate_forces(gp, zone_stress)| step 4: adds axial and bond forces to nodes().force and the    |
// |                                     | host gridpoints' force (N); advances the plastic histories.    |
// |                                     | zone_stress: one Voigt row per zone (Pa, tension +), or empty  |
// | r.stored_energy()                   | recoverable elastic energy of bars and bond springs (J)        |
// | r.dissipated_energy()               | energy dissipated by bar yielding and bond slip so far (J)     |
// | r.checkpoint(ar)       (optional)    | saves or loads bar nodes, element and bond states              |
// |                                     | (io/checkpoint.hpp); needed by save/load_checkpoint            |

#include <concepts>
#include <type_traits>

#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"

namespace tessera::reinforcement {

/// A bond law: a pure evaluator of the bond spring of one bar node along the bar axis (the
/// embedded_truss owns the loop, the per-node state and the transverse tie).
///
/// | expression                        | meaning                                                     |
/// |-----------------------------------|-------------------------------------------------------------|
/// | B::params, B::state               | parameters (SI); per-node history, value-init = virgin      |
/// | B::validate(p)                    | throws invalid_input naming a bad parameter and its value   |
/// | B::stiffness_ratio(p)             | xi = K_bond / K_axial (-), study eq. 9                      |
/// | B::strength(p, sigma_conf, per, L)| F_max (N) for confinement sigma_conf (Pa, compression +),   |
/// |                                   | bar perimeter per (m) and tributary length L (m)            |
/// | B::update(p, s, slip, K, F_max)   | return mapping for total slip (m) with stiffness K (N/m)    |
/// | s.slip, s.force                   | slip (m) and bond force F_a (N, force on the node is -F_a a)|
/// | s.slipping                        | at the strength limit at the last update                    |
/// | B::stored_energy(s, K)            | recoverable energy of the axial spring (J)                  |
/// | B::dissipated_energy(s)           | work of plastic slip so far (J)                             |
template <class B>
concept BondLaw = requires(const typename B::params& p, typename B::state& s, const typename B::state& cs, real x) {
  typename B::params;
  typename B::state;
  { B::validate(p) } -> std::same_as<void>;
  { B::stiffness_ratio(p) } -> std::convertible_to<real>;
  { B::stiffness_per_unit_length(p) } -> std::convertible_to<bool>;
  { B::strength(p, x, x, x) } -> std::convertible_to<real>;
  { B::update(p, s, x, x, x) } noexcept -> std::same_as<void>;
  { cs.slip } -> std::convertible_to<real>;
  { cs.force } -> std::convertible_to<real>;
  { cs.slipping } -> std::convertible_to<bool>;
  { B::stored_energy(cs, x) } -> std::convertible_to<real>;
  { B::dissipated_energy(cs) } -> std::convertible_to<real>;
};

template <class R>
concept Reinforcement = requires(R& r, const R& cr, const typename R::params& p, const geometry::block_mesh& mesh,
                                 const node_set& reference_gridpoints, node_set& gridpoints,
                                 const zone_stress_matrix& zone_stress) {
  typename R::params;
  typename std::bool_constant<R::enabled>;  // enabled must be a compile-time constant
  { r.build(p, mesh, reference_gridpoints) } -> std::same_as<void>;
  { r.nodes() } -> std::same_as<node_set&>;
  { cr.nodes() } -> std::same_as<const node_set&>;
  { r.add_stiffness_bounds(gridpoints) } -> std::same_as<void>;
  { r.accumulate_forces(gridpoints, zone_stress) } noexcept -> std::same_as<void>;
  { cr.stored_energy() } -> std::convertible_to<real>;
  { cr.dissipated_energy() } -> std::convertible_to<real>;
};

}  // namespace tessera::reinforcement
