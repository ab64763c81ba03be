#pragma once
// The options and the result of kinetic_relaxation (solver/relaxation.hpp), their checks, and the
// solver options a relaxation runs with; apart so that the relaxation's header stays readable.

#include <cmath>
#include <cstdint>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "options.hpp"

namespace tessera {

/// How a relaxation runs and when it stops (SI).
struct relaxation_options {
  real reference_force = 0;            ///< N, > 0: the ratio is max nodal unbalanced force / this
  real ratio_tolerance = 1e-4;         ///< > 0: equilibrium when the ratio is at most this
  std::int64_t max_steps = 1'000'000;  ///< >= 1: steps one relaxation (one increment) may take
  std::int64_t check_interval = 10;    ///< >= 1: steps between ratio checks
  bool back_up_to_peak = true;         ///< displacements moved back to the kinetic-energy peak at each reset
  /// advance: during the ramp the free components move along the last increment's change of
  /// displacement scaled to this increment (a linear predictor), instead of following the load
  /// dynamically; the first increment, with no last one, follows it dynamically. Switch it off
  /// for the increment after a load drop: extrapolating an increment in which a crack snapped
  /// open repeats the snap (measured on the prism: the blocks unloaded into compression).
  bool extrapolate = false;
  /// The ratio also takes each block's resultant: the sum over a block's gridpoints of their
  /// unbalanced forces (free components), largest over the blocks, over reference_force. A slow
  /// mode (a run of blocks sliding along a bar, a floating piece) leaves every nodal force small
  /// while they add up over a block; this catches it at one pass over the gridpoints a check.
  bool block_resultant = false;
  /// The velocity rule between the ratio checks: kinetic (zero the free velocities at every
  /// kinetic-energy peak, the file comment) or fire (FIRE, Bitzek et al. 2006, at the solver's
  /// fixed step: after each step the free velocity turns towards the unbalanced force's
  /// acceleration in the mass metric, v = (1 - a) v + a |v|_M (M^-1 F) / |M^-1 F|_M with
  /// |x|_M^2 = sum m x^2; `a` starts at fire_alpha_start and is multiplied by fire_alpha_decay at
  /// every step with positive power F . v once more than fire_delay such steps have passed; a
  /// step with power <= 0 zeroes the free velocities as a kinetic reset does (back_up_to_peak
  /// applies) and restarts `a`). FIRE's growth of the step is not used: the fictitious masses
  /// already put every step at its stability limit. The mixing never raises |v|_M; the kinetic
  /// energy it takes is not added to relaxation_result::kinetic_removed (the resets' is).
  /// adaptive (Underwood 1983's adaptive dynamic relaxation): no resets; after each step the free
  /// velocities are those of a viscous step, v = (2 v_step - c dt v_old) / (2 + c dt), with
  /// c = adaptive_damping_scale x 2 sqrt(lambda) and lambda = sum x_i^2 k_i / sum m_i x_i^2 the
  /// Rayleigh quotient of the current displacement x since the increment began, k_i the local
  /// stiffness -(F_i - F_i,old) / (dt v_i,old) (components with v_old = 0 left out); c = 0 when
  /// the quotient is not positive (softening), c dt at most 2.
  enum class method { kinetic, fire, adaptive } velocity_rule = method::kinetic;  ///< the velocity rule between resets (above); kinetic by default
  real adaptive_damping_scale = 1;  ///< in (0, 10]: factor on the critical damping of lambda
  real fire_alpha_start = 0.1;    ///< in (0, 1]: FIRE's mixing after a reset
  real fire_alpha_decay = 0.99;   ///< in (0, 1]: FIRE's factor on the mixing per downhill step
  std::int64_t fire_delay = 5;    ///< >= 0: downhill steps after a reset before the mixing decays
};

/// What a relaxation (or an increment and its relaxation) did.
struct relaxation_result {
  std::int64_t steps = 0;       ///< solver steps taken, reset steps and the ramp included
  std::int64_t ramp_steps = 0;  ///< of them, the steps that moved the prescribed components
  std::int64_t resets = 0;      ///< kinetic-energy peaks at which the free velocities were zeroed
  real ratio = 0;               ///< unbalanced ratio at the end
  bool converged = false;       ///< ratio <= tolerance within max_steps
  real kinetic_removed = 0;     ///< J: kinetic energy the resets zeroed

  void add(const relaxation_result& r) {  ///< Adds the counts of a later increment; ratio and converged become its
    steps += r.steps, ramp_steps += r.ramp_steps, resets += r.resets, kinetic_removed += r.kinetic_removed;
    ratio = r.ratio, converged = r.converged;
  }
};

/// Refuses options that cannot stop a relaxation (invalid_input naming the value).
TESSERA_INLINE void require_valid_relaxation(const relaxation_options& o);

/// Solver options for kinetic relaxation from `base`: no local damping (damping_gamma = 0) and
/// every gridpoint's mass scaled so that a step of 1 s of pseudo-time is stable, which makes each
/// mass proportional to its nodal stiffness bound (the time is then no physical time; the contact
/// laws do not depend on it).
[[nodiscard]] inline solver_options kinetic_relaxation_options(solver_options base) {
  base.damping_gamma = 0;
  base.mass_scaling_ratio = 0;
  base.mass_scaling_dt = 1;
  base.dt = 0;
  return base;
}

}  // namespace tessera

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/relaxation_options.ipp"
#endif
