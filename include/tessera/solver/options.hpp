#pragma once
// The plain types a scene hands to a solver and reads back from it: solver_options (run-time
// options, SI), run_result (what solver::run_until did) and phase_times (where the step's time
// went), and the check of the options that the solver (solver/solver.hpp) makes when it is built.

#include <cmath>
#include <cstdint>
#include <ostream>
#include <string>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "../integrator/timestep.hpp"

namespace tessera {

/// Time spent in each phase of the step since the solver was built (s). zones and contacts are
/// summed over threads (on one thread their wall time; on several the thread time, so
/// zones / (zone count x steps) is the per-core cost of a zone-step), the others are wall time:
/// bars (their axial and bond forces), integration (gather of the contact and bar host forces
/// and the integrator; on the unfused path the integrator alone), recorders (the observers of run
/// and run_until). A few clock reads per step and thread (about 0.1 us).
struct phase_times {
  double zones = 0;  ///< s in the zone forces
  double contacts = 0;  ///< s in the contact forces
  double bars = 0;  ///< s in the bars' axial and bond forces
  double integration = 0;  ///< s gathering host forces and integrating
  double recorders = 0;  ///< s in the observers of run and run_until
};

/// What solver::run_until did: the steps it took, why it stopped, whether max_steps ran out
/// first, and the damping in force (so a damped run is never taken for dynamics). Converts to the
/// step count, so `std::int64_t n = s.run_until(...)` still reads it; `std::cout << r` prints all.
struct run_result {
  std::int64_t steps = 0;      ///< steps taken by this call
  std::string reason;          ///< the stop condition's reason() (e.g. "t - t0 = 0.5 s >= 0.5 s"), or "max_steps = N reached"
  bool hit_max_steps = false;  ///< true when max_steps ran out before the condition held
  /// The damping in force (solver::damping_in_force()): "local damping gamma = 0.8 (...)" for the
  /// default integrator::quasi_static, "no damping (...)" for integrator::dynamic.
  std::string damping;
  /// The steps taken, so that an integer reads the result
  operator std::int64_t() const { return steps; }  // NOLINT(google-explicit-constructor): old callers read the count
};
/// "N steps (<reason>[, max_steps ran out]); damping: <damping>".
inline std::ostream& operator<<(std::ostream& os, const run_result& r) {
  return os << r.steps << " steps (" << r.reason << (r.hit_max_steps ? ", max_steps ran out" : "")
            << "); damping: " << r.damping;
}

/// Run-time options of a solver (SI).
struct solver_options {
  real safety = integrator::default_safety;  ///< dt = safety x min_i 2 sqrt(m_i / k_i), in (0, 1]
  real dt = 0;                 ///< user time step (s); 0 = automatic. Above the stable limit -> invalid_input
  real mass_scaling_dt = 0;    ///< > 0: raise nodal masses so this step (s) is stable, and use it
  /// > 0 (instead of mass_scaling_dt): scale masses to the step at which the added mass is this
  /// multiple of the original mass (integrator::step_for_added_mass; deformable blocks). Resolved
  /// into mass_scaling_dt when the solver is built (options().mass_scaling_dt then holds the step).
  real mass_scaling_ratio = 0;
  real damping_gamma = 0.8;    ///< local damping constant (integrator::quasi_static; ignored by integrator::dynamic)
  int threads = 0;             ///< OpenMP threads; 0 = leave the current setting
  index_t check_interval = 100;  ///< steps between step-checker passes
};

namespace detail {

/// The solver's refusals of bad options (invalid_input naming the value), before anything is
/// built; rigid_blocks: the solver's blocks are rigid (an added-mass ratio is for deformable ones).
TESSERA_INLINE void require_valid_options(const solver_options& options, bool rigid_blocks);

}  // namespace detail

}  // namespace tessera

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/options.ipp"
#endif
