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

#include <concepts>
#include <type_traits>

#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"

namespace tessera::reinforcement {

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
