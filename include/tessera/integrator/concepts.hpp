#pragma once
// Concepts of the integrator/ folder: the damping policy and the time integrator.
//
// Damping — the artificial damping of dynamic relaxation, applied per degree of freedom.
//
// | expression              | meaning                                                              |
// |-------------------------|----------------------------------------------------------------------|
// | D::enabled              | constexpr bool; false removes the damping term at compile time       |
// | d.force(f, v)           | damping force (N or N m) opposing motion for unbalanced force f and  |
// |                         | velocity v at the previous half step (study eq. 1)                   |
// | d.stiffness_amplification() | factor a >= 1 on the stiffness seen by the update in its worst   |
// |                         | phase; the stable step is 2 sqrt(m / (a k)) (integrator/timestep.hpp)|
// | d.describe() (optional) | std::string naming the damping and when it is right; the solver's    |
// |                         | run results carry it (a policy without it is named as a user policy) |
//
// Integrator — advances a node_set (gridpoints or bar nodes) or a set of 6-DOF bodies by one
// explicit step. Prescribed components are set to their velocity and their reaction recorded.
//
// | expression                       | meaning                                                     |
// |----------------------------------|-------------------------------------------------------------|
// | I::damping_type                  | the Damping policy                                          |
// | i.advance(nodes, dt, work)       | v(t+dt/2) from v(t-dt/2) and nodes.force, u += v dt; adds   |
// |                                  | boundary work and damping dissipation of the step to work   |
// | i.advance_dof(f, m, v, c, vp,    | the same update of one scalar degree of freedom (used by    |
// |   dt, reaction, work)            | rigid bodies for their 6 DOF); returns v(t+dt/2)            |
// | i.stiffness_amplification()      | the damping's factor a on the stiffness (1 when undamped)   |

#include <concepts>
#include <cstdint>
#include <type_traits>

#include "../core/nodes.hpp"
#include "../core/types.hpp"

namespace tessera::integrator {

/// Energy increments of one step (J), accumulated by the integrator inside its loop.
struct step_work {
  real boundary = 0;  ///< work of the reactions at prescribed components, sum R v_mid dt (trapezoidal)
  real damping = 0;   ///< energy removed by the damping forces, sum F_d v_mid dt
};

template <class D>
concept Damping = requires(const D& d, real f, real v) {
  typename std::bool_constant<D::enabled>;  // must be a compile-time constant
  { d.force(f, v) } noexcept -> std::convertible_to<real>;
  { d.stiffness_amplification() } noexcept -> std::convertible_to<real>;
};

template <class I>
concept Integrator = requires(const I& i, node_set& nodes, real dt, step_work& work, real f, real m, real v,
                              std::uint8_t c, real& reaction) {
  typename I::damping_type;
  requires Damping<typename I::damping_type>;
  { i.advance(nodes, dt, work) } noexcept -> std::same_as<void>;
  { i.advance_dof(f, m, v, c, v, dt, reaction, work) } noexcept -> std::convertible_to<real>;
  { i.stiffness_amplification() } noexcept -> std::convertible_to<real>;
};

}  // namespace tessera::integrator
