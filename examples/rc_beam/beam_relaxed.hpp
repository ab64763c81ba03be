#pragma once
// rc_beam --scheme relaxation (beam_loading::relaxation): the loading plate moved in increments,
// each relaxed to static equilibrium by kinetic dynamic relaxation (solver/relaxation.hpp); the
// rest of the run (samples, events, figures) is beam_run.hpp's.

#include <algorithm>

#include "common/relaxed_scheme.hpp"
#include "rc_beam/beam.hpp"
#include "rc_beam/beam_result.hpp"
#include "tessera/solver/relaxation.hpp"

namespace tessera::scenes {

/// What a relaxed beam refuses (invalid_input naming the flag), before anything is built: a law
/// other than the study's (the relaxed solver is compiled for it alone) and checkpoints (the
/// relaxation's own state, its predictor and pattern, is not saved). Nothing for an explicit run.
inline void check_beam_relaxation(const beam_options& o, const beam_loading& l) {
  if (!l.relaxation) return;
  require(o.compression == "plastic" && o.cohesion == "decoupled" && o.law == "study", "rc_beam: --scheme relaxation is "
          "built for the study's law (--law study, --compression plastic, --cohesion decoupled), got --law ", o.law,
          ", --compression ", o.compression, ", --cohesion ", o.cohesion);
  require(l.checkpoint_file.empty() && l.resume_file.empty(),
          "rc_beam: --scheme relaxation keeps no checkpoint; drop --checkpoint and --resume");
}

/// The loading by kinetic relaxation (beam_loading::relaxation; solver/relaxation.hpp): the
/// loading plate(s) moved down by relax_increment per increment over relax_ramp steps through
/// `drive_at(solver, v, resetting)` before every step (the plates are no prescribed velocities:
/// the relaxation's hook; the steel plates have no inertia, platen_motion::quasi_static, and a
/// tied plate's turn stops at each reset), each increment held until the largest nodal unbalanced force and the
/// largest block resultant are relax_tolerance x P_cr (hand) at most. The ramps use the linear
/// predictor until the first load drop of 5 % P_cr, then follow the load dynamically (the tie's
/// rule, rc_tie_run.hpp relax_tie). `sample(s)` after each increment, until it sets `done`; the
/// counts go to r.
template <class Solver, class DriveAt, class Sample>
void relax_beam(Solver& s, const beam_hand_checks& hand, const beam_loading& loading, DriveAt drive_at,
                Sample& sample, const bool& done, beam_result& r) {
  relaxation_options o;
  o.reference_force = hand.first_crack_load;
  o.ratio_tolerance = loading.relax_tolerance;
  o.max_steps = loading.relax_max_steps;
  o.extrapolate = true;
  o.block_resultant = true;
  real peak = 0;
  relax_increments(
      s, loading.relax_increment, loading.relax_ramp, o,
      [&](const Solver& sv) {
        sample(sv);
        peak = std::max(peak, r.load.back());
        return relaxed_sample{done, r.load.back() < peak - 0.05 * hand.first_crack_load};
      },
      r, drive_at);  // the hook: the plate's pattern is 1 m/s
}

}  // namespace tessera::scenes
