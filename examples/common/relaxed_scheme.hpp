#pragma once
// The --scheme switch the drivers share (direct_tension, rc_tie, rc_beam): explicit (central differences
// with local damping along a ramped load) or relaxation (kinetic dynamic relaxation,
// tessera/solver/relaxation.hpp). One check of the flags given beside it, the loop of relaxed
// increments, and the keys it adds to summary.json.

#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "tessera/core/errors.hpp"
#include "tessera/core/types.hpp"
#include "tessera/io/json.hpp"
#include "tessera/solver/relaxation.hpp"

namespace tessera::scenes {

/// What a driver's --scheme refuses, before anything is built or written (invalid_input naming
/// the flag or value): a scheme other than explicit or relaxation; a relaxation flag
/// (relax_given) without --scheme relaxation; and with it, a flag of the explicit loading
/// (explicit_given), rigid blocks, or an increment above the run's last displacement.
struct scheme_flags {
  const char* driver = "";       ///< "direct_tension", "rc_tie", "rc_beam"
  std::string scheme;            ///< --scheme's value
  std::vector<std::string> explicit_given, relax_given;
  bool rigid = false;
  const char* explicit_load = "";  ///< "ramp", "pull", "loading"
  const char* moves = "";          ///< "the top moves", "the bar ends move", "the loading plate moves"
  real increment = 0, last = 0;    ///< --relax-increment and the run's last displacement (m)
  const char* last_flag = "";      ///< "--max-displacement", "--max-elongation", "--max-deflection"
};

inline void check_scheme_flags(const scheme_flags& f) {
  require(f.scheme == "explicit" || f.scheme == "relaxation", f.driver, ": --scheme '", f.scheme,
          "' must be 'explicit' or 'relaxation'");
  require(f.scheme == "relaxation" || f.relax_given.empty(), f.driver, ": ",
          f.relax_given.empty() ? "" : f.relax_given.front(), " applies to --scheme relaxation, and this run is --scheme ",
          f.scheme);
  if (f.scheme != "relaxation") return;
  require(!f.rigid, f.driver, ": --scheme relaxation relaxes deformable blocks; --rigid is not relaxed");
  require(f.explicit_given.empty(), f.driver, ": ", f.explicit_given.empty() ? "" : f.explicit_given.front(),
          " sets the explicit ", f.explicit_load, "; with --scheme relaxation ", f.moves, " by --relax-increment instead");
  require(f.increment <= f.last, f.driver, ": --relax-increment ", f.increment, " m exceeds ", f.last_flag, " ", f.last,
          " m");
}

/// What a relaxed run's sampler reports after each increment.
struct relaxed_sample {
  bool done = false;     ///< the run ends here
  bool dropped = false;  ///< the load has dropped (a crack): the linear predictor is off from now on
};

/// The relaxed run of both drivers: increments of kinetic_relaxation::advance(increment m,
/// ramp steps, o) with the linear predictor on the ramps (o.extrapolate) until the sampler first
/// reports a load drop, then off (past a snap the predictor would repeat it: the ramps follow the
/// load dynamically); `sample(s)` (const Solver&) after each increment, until it reports done.
/// The counts go to r (Result's relax_increments, relax_unconverged, relax_resets,
/// relax_kinetic_removed). `before_step(s, rate, resetting)` before every step: kinetic_relaxation's hook,
/// for loads outside the prescribed velocities (rc_beam's plates).
template <class Solver, class Sample, class Result, class BeforeStep = no_before_step>
void relax_increments(Solver& s, real increment, std::int64_t ramp, relaxation_options o, Sample&& sample, Result& r,
                      BeforeStep before_step = {}) {
  kinetic_relaxation<Solver, BeforeStep> k(s, std::move(before_step));
  for (bool done = false; !done;) {
    const relaxation_result step = k.advance(increment, ramp, o);
    ++r.relax_increments;
    r.relax_unconverged += step.converged ? 0 : 1;
    const relaxed_sample seen = sample(std::as_const(s));
    done = seen.done;
    if (seen.dropped) o.extrapolate = false;
  }
  r.relax_resets = k.totals().resets;
  r.relax_kinetic_removed = k.totals().kinetic_removed;
}

/// The report's line of a relaxed run (Result: relax_increments, relax_unconverged,
/// relax_resets); nothing when relax_increments is 0 (an explicit run).
template <class Result>
void print_relaxation_counts(const Result& r) {
  if (r.relax_increments > 0)
    std::printf("  kinetic relaxation: %lld increments (%lld not converged), %lld kinetic-energy resets\n",
                static_cast<long long>(r.relax_increments), static_cast<long long>(r.relax_unconverged),
                static_cast<long long>(r.relax_resets));
}

/// summary.json's keys of the scheme: scheme, the damping in force (Result::damping_in_force,
/// solver::damping_in_force()), the relaxation's increment (m) and tolerance, and the run's counts
/// (Result: relax_increments, relax_unconverged, relax_resets, relax_kinetic_removed; zero in an
/// explicit run).
template <class Result>
void set_scheme_figures(io::summary_json& js, const std::string& scheme, real increment, real tolerance,
                        const Result& r) {
  js.set("scheme", scheme)
      .set("damping_in_force", r.damping_in_force)
      .set("relaxation_increment_m", increment)
      .set("relaxation_tolerance", tolerance)
      .set("relaxation_increments", r.relax_increments)
      .set("relaxation_unconverged_increments", r.relax_unconverged)
      .set("relaxation_resets", r.relax_resets)
      .set("relaxation_kinetic_removed_J", r.relax_kinetic_removed);
}

}  // namespace tessera::scenes
