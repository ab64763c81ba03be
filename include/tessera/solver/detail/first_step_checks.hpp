#pragma once
// What solver::step refuses before its first step, once every support and the gravity are set:
// two scenes under gravity that the steps would otherwise turn into a wrong result, or into a
// message about the time step that sends the user to the wrong knob. Each reads the solver's
// public interface only (block_count, gridpoints, gridpoints_of_block, blocks, gravity,
// gravity_forces, contacts). Not a public interface.
//
//   refuse_falling_supports  a block driven in some translation components and free in one along
//                            which gravity acts (prescribe_block_velocity(b, v, components::x)),
//                            that carries another block and rests on none: it would fall under
//                            its weight and theirs. A block driven in x that rests on another (a
//                            sheared block free to dilate) or carries nothing (a block thrown
//                            sideways while it falls) is accepted.
//   refuse_soft_contacts     detected contacts (those with a tolerance) that let a block sink
//                            into what it rests on by more than the tolerance under its own
//                            weight alone: W / (k_n A) > tolerance, A the area of its bearing
//                            sub-contacts that touch (opening u_n within the contact set's
//                            bond_gap_fraction of the tolerance). A lower bound of the sinking (a block also carries
//                            those above it), so only joints surely too soft are refused; left to
//                            the steps, their overlap would outrun the rebuilds and be refused as
//                            a motion too fast for the step. A sub-contact still open at the
//                            start (blocks shrunk apart, as rubble's) bears nothing yet: its area
//                            within the tolerance, a corner's sliver, is not the area the block
//                            will land on, so it is not counted (it refused the 10 000-block
//                            rubble scene on a 8.7e-9 m^2 sliver of a 2.3 N block).
// Which block rests on which: a sub-contact whose normal, from the block towards the other, has
// a component along gravity above `bearing` (the other block is below; a wall's contacts carry
// no weight).
//
// Cost: O(gridpoints + sub-contacts), once per solver. Thread safety: reads the solver only.

#include <cmath>
#include <concepts>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "../../core/errors.hpp"
#include "../../core/nodes.hpp"
#include "../../core/types.hpp"

namespace tessera::detail {

/// |n . g_hat| above which a contact carries weight (about 6 degrees off a vertical plane).
inline constexpr real bearing = 0.1;

/// Translation components of block b (bit c = component c): those prescribed (rigid: on some
/// gridpoint, which drives the whole block; deformable: on every gridpoint) and those free (on
/// no gridpoint).
struct block_constraints {
  unsigned driven = 0;
  unsigned free = 0;
};
template <class Solver>
[[nodiscard]] block_constraints constraints_of_block(const Solver& s, const std::vector<index_t>& gridpoints) {
  constexpr auto prescribed = static_cast<std::uint8_t>(dof_constraint::prescribed);
  block_constraints out;
  for (int c = 0; c < 3; ++c) {
    index_t held = 0;
    for (index_t i : gridpoints) held += s.gridpoints().constraint(i, c) == prescribed;
    const bool driven = Solver::blocks_type::is_rigid ? held > 0 : held == static_cast<index_t>(gridpoints.size());
    if (driven) out.driven |= 1u << c;
    if (held == 0) out.free |= 1u << c;
  }
  return out;
}
/// "x, z" for the components of mask.
[[nodiscard]] inline std::string component_names(unsigned mask) {
  std::string out;
  for (int c = 0; c < 3; ++c)
    if ((mask >> c) & 1u) out += out.empty() ? std::string(1, "xyz"[c]) : std::string(", ") + "xyz"[c];
  return out;
}
/// The components along which g acts.
[[nodiscard]] inline unsigned gravity_components(const vec3& g) {
  unsigned out = 0;
  for (int c = 0; c < 3; ++c)
    if (g[c] != 0) out |= 1u << c;
  return out;
}
/// For sub-contact i of a contact set with block ids and normals: the component along g_hat of
/// the direction from block b (one of its blocks) towards the other block.
template <class Contacts>
[[nodiscard]] real towards_other_along(const Contacts& contacts, index_t i, index_t b, const vec3& g_hat) {
  const real along = contacts.normal(i).dot(g_hat);  // normal A -> B
  return contacts.block_a(i) == b ? along : -along;
}

/// refuse_falling_supports (file comment); throws invalid_input naming the block, its driven and
/// free components, gravity and a block it carries.
template <class Solver>
void refuse_falling_supports(const Solver& s) {
  const vec3 g = s.gravity();
  const auto& contacts = s.contacts();
  if constexpr (requires(index_t i) {
                  contacts.size();
                  contacts.block_a(i);
                  contacts.block_b(i);
                  { contacts.normal(i) } -> std::convertible_to<vec3>;
                }) {
    if (g == vec3::Zero()) return;
    const vec3 g_hat = g.normalized();
    const index_t n_b = s.block_count();
    std::vector<block_constraints> held(static_cast<std::size_t>(n_b));
    for (index_t b = 0; b < n_b; ++b) held[static_cast<std::size_t>(b)] = constraints_of_block(s, s.gridpoints_of_block(b).nodes);
    const unsigned along_g = gravity_components(g);
    for (index_t b = 0; b < n_b; ++b) {
      const block_constraints& h = held[static_cast<std::size_t>(b)];
      if (h.driven == 0 || (h.free & along_g) == 0) continue;
      index_t carried = invalid_index;
      bool rests = false;
      for (index_t i = 0; i < contacts.size(); ++i) {
        if (contacts.block_a(i) != b && contacts.block_b(i) != b) continue;
        const index_t other = contacts.block_a(i) == b ? contacts.block_b(i) : contacts.block_a(i);
        const real towards = towards_other_along(contacts, i, b, g_hat);
        if (towards > bearing) rests = true;
        // The other block is above and falls with it: b carries it.
        if (towards < -bearing && (held[static_cast<std::size_t>(other)].free & along_g) != 0) carried = other;
      }
      if (rests || carried == invalid_index) continue;
      throw invalid_input(concat(
          "solver: block ", b, " is driven in ", component_names(h.driven), " but free in ", component_names(h.free),
          ", and gravity (", g.x(), ", ", g.y(), ", ", g.z(), ") m/s^2 acts along ", component_names(h.free & along_g), ": it carries block ",
          carried, " and rests on no block, so this support would fall under its weight and theirs. Prescribe its "
          "free components too: prescribe_block_velocity(", b, ", v, bc::components::xyz) with v's free components "
          "the velocity to hold them at (0 to fix them); a loading history then changes v by update_block_velocity"));
    }
  }
}

/// refuse_soft_contacts (file comment); throws invalid_input naming the block, its weight, k_n
/// (the area-weighted mean of its bearing sub-contacts), their area, the overlap and the tolerance.
template <class Solver>
void refuse_soft_contacts(const Solver& s) {
  const vec3 g = s.gravity();
  const auto& contacts = s.contacts();
  using contact_set = std::remove_cvref_t<decltype(contacts)>;
  if constexpr (requires(index_t i) {
                  real(contacts.tolerance());
                  real(contact_set::bond_gap_fraction);
                  real(contacts.subcontact_params(i).k_n);
                  real(contacts.area(i));
                  real(contacts.state(i).u_n);
                  contacts.block_a(i);
                  { contacts.normal(i) } -> std::convertible_to<vec3>;
                }) {
    if (g == vec3::Zero() || contacts.size() == 0) return;
    const vec3 g_hat = g.normalized();
    const index_t n_b = s.block_count();
    const real tolerance = contacts.tolerance();
    // A sub-contact touches when its opening is within the gap at which construction bonds two
    // faces (they coincide up to round-off); an open one bears nothing yet.
    const real touching = contact_set::bond_gap_fraction * tolerance;
    std::vector<real> stiffness(static_cast<std::size_t>(n_b), 0), area(static_cast<std::size_t>(n_b), 0);
    for (index_t i = 0; i < contacts.size(); ++i) {
      if (!(contacts.state(i).u_n <= touching)) continue;
      for (index_t b : {contacts.block_a(i), contacts.block_b(i)})
        if (towards_other_along(contacts, i, b, g_hat) > bearing) {
          stiffness[static_cast<std::size_t>(b)] += contacts.subcontact_params(i).k_n * contacts.area(i);
          area[static_cast<std::size_t>(b)] += contacts.area(i);
        }
    }
    for (index_t b = 0; b < n_b; ++b) {
      const real k = stiffness[static_cast<std::size_t>(b)];
      if (!(k > 0)) continue;
      const auto gridpoints = s.gridpoints_of_block(b).nodes;
      if ((constraints_of_block(s, gridpoints).free & gravity_components(g)) == 0) continue;  // held along g
      real weight = 0;
      if constexpr (Solver::blocks_type::is_rigid) {
        weight = s.blocks().weight_mass(b) * g.norm();
      } else {
        vec3 w = vec3::Zero();
        for (index_t i : gridpoints) w += s.gravity_forces().row(i).transpose();
        weight = w.norm();
      }
      const real overlap = weight / k, a = area[static_cast<std::size_t>(b)];
      if (overlap <= tolerance) continue;
      throw invalid_input(concat(
          "solver: contact stiffness too soft for the loads: block ", b, " (weight ", weight, " N) rests on contacts of k_n = ",
          k / a, " Pa/m over ", a, " m^2, which let it sink W / (k_n A) = ", overlap,
          " m into its support under its own weight alone, more than the contact tolerance ", tolerance,
          " m (the contacts cannot follow such an overlap). Raise k_n to at least W / (A tolerance) = ", weight / (a * tolerance),
          " Pa/m (stone and concrete joints: 1e9 to 1e11 Pa/m); the time step is not the problem"));
    }
  }
}

/// Both checks, in the order of the file comment (solver::step, before its first step).
template <class Solver>
void refuse_first_step_traps(const Solver& s) {
  refuse_falling_supports(s);
  refuse_soft_contacts(s);
}

}  // namespace tessera::detail
