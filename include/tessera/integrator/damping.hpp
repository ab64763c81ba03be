#pragma once
// Damping policies of the central-difference integrator.
//
// local_damping (study eq. 1, Cundall's local non-viscous damping): per degree of freedom,
//     F_d = gamma |F| sgn(v(t - dt/2)),   sgn(0) = +1 as in the study,
// a force proportional to the unbalanced force that opposes the motion of the previous half
// step. It vanishes in equilibrium, does not depend on the mass or the frequency, and so does
// not need tuning; gamma = 0.8 is the study's (and 3DEC's) default. It removes a fraction of the
// kinetic energy of each oscillation, which suits quasi-static (dynamic relaxation) runs.
//
// no_damping: F_d = 0, removed at compile time (undamped dynamics, energy-conservation tests).
//
// Stability (decision, docs/architecture.md "Time step"): while the unbalanced force opposes the
// previous velocity, F - F_d = (1 + gamma) F, i.e. the update sees the stiffness (1 + gamma) K.
// The stable step therefore shrinks by 1 / sqrt(1 + gamma) (0.745 for gamma = 0.8):
// stiffness_amplification() = 1 + gamma enters the time step and mass scaling. Measured: the
// 100-block prism with gamma = 0.8 blows up within 200 steps at 0.9 x the undamped Gershgorin
// step, and runs stably at 0.9 x the amplified one.

#include <string>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "concepts.hpp"

namespace tessera::integrator {

/// Cundall's local damping, F_d = gamma abs(F) sgn(v) against the motion (file comment): for quasi-static runs
struct local_damping {
  static constexpr bool enabled = true;  ///< damping force computed
  real gamma = 0.8;  ///< damping constant, 0 <= gamma < 1

  void validate() const {  ///< Refuses (invalid_input) gamma outside [0, 1)
    require(gamma >= 0 && gamma < 1, "local_damping: damping constant gamma = ", gamma, " must lie in [0, 1)");
  }
  /// Factor on the stiffness seen by the update in the worst phase (see the file comment).
  [[nodiscard]] real stiffness_amplification() const noexcept { return 1 + gamma; }
  /// The damping in force, for run results and summaries (solver::damping_in_force()).
  [[nodiscard]] std::string describe() const {
    if (gamma == 0)
      return "local damping gamma = 0 (integrator::quasi_static with no damping force: the motion is undamped)";
    return tessera::detail::concat("local damping gamma = ", gamma, " (integrator::quasi_static: a force ", gamma,
                                   " |F| against the motion removes kinetic energy, right for settling and quasi-static "
                                   "loading, wrong for dynamics: use integrator::dynamic there)");
  }
  [[nodiscard]] real force(real f, real v) const noexcept {  ///< Damping force of a component (N) for unbalanced force f (N) and half-step velocity v
    const real magnitude = gamma * (f < 0 ? -f : f);
    return v >= 0 ? magnitude : -magnitude;
  }
};

/// No damping: dynamics whose energy the run must keep
struct no_damping {
  static constexpr bool enabled = false;  ///< no damping force
  void validate() const {}  ///< Nothing to refuse
  [[nodiscard]] real stiffness_amplification() const noexcept { return 1; }  ///< 1
  /// The damping in force, for run results and summaries (solver::damping_in_force()).
  [[nodiscard]] std::string describe() const {
    return "no damping (integrator::dynamic: undamped central differences, the motion is dynamics)";
  }
  [[nodiscard]] real force(real, real) const noexcept { return 0; }  ///< 0
};

static_assert(Damping<local_damping>);
static_assert(Damping<no_damping>);

}  // namespace tessera::integrator
