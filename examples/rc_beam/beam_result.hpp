#pragma once
// The beam run's inputs (beam_loading) and figures (beam_result); for rc_beam --checkpoint and
// --resume (beam_run.hpp) the checkpoint of the figures its samples build (checkpoint_beam_samples),
// the flags that define a run (beam_run_key) and their checks (check_beam_checkpoint_flags).

#include <array>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "common/cli.hpp"
#include "rc_beam/beam.hpp"
#include "rc_beam/beam_cracks.hpp"
#include "rc_beam/beam_post_peak.hpp"
#include "rc_beam/beam_shear.hpp"
#include "rc_beam/beam_span.hpp"
#include "tessera/io/checkpoint.hpp"
#include "tessera/io/json.hpp"
#include "tessera/solver/options.hpp"

namespace tessera::scenes {

struct beam_loading {
  real rate = 5e-3;            ///< loading plate velocity (m/s)
  real ramp_time = -1;         ///< half-cosine ramp of the plate velocity (s); < 0: the period T_1 of the first bending mode
  real added_mass_ratio = 0;   ///< > 0: mass scaling to this added-mass multiple
  real dt = 0;                 ///< > 0 (instead): mass-scaled target step (s)
  real max_deflection = 0.006; ///< stop here at the latest (m)
  real failure_drop = 0.25;    ///< stop once the load has fallen this fraction below its peak
  /// m: the drop must hold over this much further mid-span deflection before the run stops (the
  /// load staying below (1 - failure_drop) x the peak at every sample); a load that climbs back
  /// above it was a transient dip and the run goes on. 0 = the first sample below stops (the rule
  /// every recorded figure was taken with).
  real failure_confirm = 0;
  /// --failure-crack diagonal: a drop of failure_drop is the failure only when a diagonal crack
  /// opened since the peak, else a dip and the run goes on (beam_failure_rule.hpp); false: every
  /// drop is (the rule every recorded figure was taken with).
  bool failure_needs_diagonal = false;
  real first_crack_only = 0;   ///< > 0: stop at this multiple of the developed-crack deflection (quick runs)
  index_t sample = 50;           ///< steps between samples
  index_t crack_every = 10;      ///< samples between crack analyses during the run
  real smoothing = 2e-5;       ///< deflection window of the smoothed load (m)
  real crack_width = 1e-4;     ///< opening at which a crack counts at the end of the run (m)
  real history_step = 5e-5;    ///< deflection between the opening snapshots of beam_opening_history (m)
  real damping_gamma = 0.8;
  /// Kinetic dynamic relaxation (solver/relaxation.hpp) instead of the explicit loading: the
  /// loading plate moved down by relax_increment (m) per increment over relax_ramp steps, each
  /// increment held until the largest nodal unbalanced force and the largest block resultant are
  /// at most relax_tolerance x the hand first-cracking load (or relax_max_steps were taken), one
  /// sample per increment; rate, ramp_time, dt, added_mass_ratio and sample are not used, and the
  /// plates keep damping_gamma. The study's contact law only; no checkpoints; one process.
  bool relaxation = false;
  real relax_increment = 1e-5, relax_tolerance = 1e-3;
  std::int64_t relax_ramp = 10, relax_max_steps = 1'000'000;
  int threads = 0;
  bool progress = true;
  /// Checkpoints (one process; run_beam's run_state): non-empty, the run's state is saved to
  /// this file (atomically: a killed run leaves the last complete one) when the run ends and
  /// every checkpoint_every seconds of wall time before, at a sample.
  std::string checkpoint_file;
  real checkpoint_every = 600;  ///< s of wall time between checkpoints; 0: at the end only
  /// Non-empty: the run continues from this checkpoint, saved by a run of the same scene and
  /// loading (run_key must equal the one stored), to the same bits as a run that never stopped.
  std::string resume_file;
  /// What defines the run (the driver's flags but those free to differ on resume): stored as the
  /// checkpoint's description and required equal on resume.
  std::string run_key;
};

struct beam_result {
  /// --plates contact: the support and loading plates' sub-contacts, those in contact at the end,
  /// their rotations (rad) and the mass added to the plates for the step (kg); [2], [3] the full
  /// beam's right support and loading plates
  std::array<std::size_t, 4> plate_subcontacts{}, plate_in_contact{};
  std::array<real, 4> plate_rotation{};
  real plate_added_mass = 0;
  /// With beam_loading::relaxation: increments, those that hit relax_max_steps before the ratio,
  /// kinetic-energy resets, and the kinetic energy they removed (J of pseudo-time); 0 otherwise.
  std::int64_t relax_increments = 0, relax_unconverged = 0, relax_resets = 0;
  real relax_kinetic_removed = 0;
  /// load = P = 2 x the support reaction; plate_load = 2 x the force on the loading plate
  std::vector<real> deflection, load, plate_load, load_point_deflection;
  /// load averaged over the last beam_loading::smoothing of deflection: the plate force carries the
  /// oscillations of a mass-scaled explicit run; the events (first crack, peak, failure) read this
  std::vector<real> smoothed_load;
  std::vector<real> crack_count;  ///< vertical + inclined softened cracks at each crack analysis (sample-aligned, -1 between)
  /// First cracking (N): the smoothed load at which the soffit of the constant-moment zone
  /// (sub-contacts with y <= h/10) reaches its contacts' tensile strength (f_T, or s f_T with
  /// calibrated contacts: at the concrete's f_T the event rises as the contacts weaken, since the
  /// soffit of a calibrated beam peaks below f_T; measured 250 blocks, s = 0.852: soffit peak
  /// 2.42 MPa, read at 20.98 kN, after the crack h/4 deep at 11.92 kN) on average: the area-weighted
  /// mean bending stress of its sub-contacts, sum A t_x n_x / sum A n_x^2, first >= f_T; if
  /// cracking sets in before (that mean peaks below f_T and falls 5 % under its peak), the load at
  /// the peak; at the end of a run without either, the load at the highest mean so far. The event
  /// the hand value M_cr = f_T I / (h - y_c) predicts, read at the scale of the section rather than
  /// of one sub-contact (single sub-contacts of a Voronoi assembly soften far earlier: the
  /// 250-block beam's first at 5.6 kN, half the hand value).
  real first_crack_load = 0, first_crack_deflection = 0;
  real soffit_peak_stress = 0;  ///< Pa
  /// The first developed crack: the first vertical crack (beam_cracks) that starts in the soffit's
  /// quarter of the depth; its load (highest smoothed load so far), deflection, position, angle.
  real developed_crack_load = 0, developed_crack_deflection = 0, first_crack_x = 0, first_crack_angle_deg = 0;
  /// The first inclined crack (35 degrees or more from the vertical) in the shear span.
  real first_inclined_crack_load = 0, first_inclined_crack_deflection = -1, first_inclined_crack_x = 0;
  bool inclined_before_vertical = false;  ///< an inclined crack came first (or with the first)
  real initial_stiffness = 0;
  bool steel_yielded = false;
  real yield_load = 0, yield_deflection = 0;
  /// The highest smoothed load of the run and its deflection (N, m): the peak where the run reached
  /// failure (failure_reached), else the highest load carried before the stop.
  real peak_load = 0, peak_deflection = 0;
  /// The load fell by beam_loading::failure_drop below its peak after first cracking: the run
  /// stopped at the failure it measures (false: it stopped at --max-deflection or the quick stop).
  bool failure_reached = false;
  /// Where failure was reached: the deflection at which the load fell below (1 - failure_drop) x
  /// the peak for good (m; with beam_loading::failure_confirm 0 the stop's own); -1 otherwise.
  real failure_deflection = -1;
  /// The run stopped (at --max-deflection) with the load below the drop since this deflection (m),
  /// not yet held over beam_loading::failure_confirm: not a failure; -1 otherwise.
  real unconfirmed_drop_deflection = -1;
  /// With beam_loading::failure_needs_diagonal: where the load fell failure_drop below its peak
  /// without a diagonal crack opening since the peak (m), the drops the run went on through.
  std::vector<real> dip_deflections;
  std::vector<float> damage_at_peak;  ///< with failure_needs_diagonal: each sub-contact's tensile damage at the peak
  std::vector<beam_crack> final_cracks;  ///< cracks at the end (beam_crack_profile)
  std::vector<real> flexural_crack_positions;  ///< in the modelled constant-moment zone, m
  int flexural_cracks = 0;               ///< in the whole beam's constant-moment zone (half: mirrored)
  real mean_crack_spacing = 0;           ///< m, 0 with fewer than two
  /// The widest crack's classification at the end (beam_failure_mode: none, flexure,
  /// diagonal_tension, crushing), whether or not the run reached failure (failure_reached).
  std::string failure_mode = "none";
  beam_crack widest;
  beam_post_peak_crack after_peak;  ///< the fastest-opening inclined crack after the peak (beam_post_peak.hpp)
  /// The shear across sections at a quarter, half and three quarters of the shear span
  /// (beam_shear.hpp), at the first inclined crack in the shear span and at the peak (empty if none)
  std::vector<beam_shear_split> shear_at_inclined_crack, shear_at_peak;
  int first_inclined_crack_span = -1;  ///< the shear span of the first inclined crack (beam_shear_span_of)
  /// The full beam's spans (beam_span.hpp): each one's reaction, inclined cracks, widest crack and
  /// shear at the peak; failing_span "left", "right" or "none"
  std::array<beam_span_figures, 2> spans;
  std::string failing_span = "none";
  beam_elastic_check elastic;  ///< the load at half the hand first-cracking deflection (beam_span.hpp)
  /// boundary_work: the work of the supports and, with --plates contact, of the plates (J)
  real energy_balance_error = 0, boundary_work = 0, contact_dissipated = 0, compression_dissipated = 0,
       tension_dissipated = 0, damping_dissipated = 0;
  real dt = 0, added_mass_ratio = 0, quasi_static_index = 0, ramp_time = 0;
  std::int64_t steps = 0;
  index_t subcontacts = 0, zones = 0, gridpoints = 0;
  real contact_points_over_depth = 0;
  real trusses_per_block = 0;
  phase_times phases;  ///< of this process's steps only (a resumed run's from the checkpoint on)
  std::string damping_in_force;  ///< the damping of the run (solver::damping_in_force())
  double runtime_s = 0;  ///< wall time of the run, a resumed run's with the time before its checkpoint
  std::int64_t resumed_at_step = -1;  ///< the checkpoint's step of a resumed run, -1 otherwise
  double runtime_before_resume_s = 0;  ///< a resumed run's wall time before its checkpoint
  int checkpoints_written = 0;
};

/// The beam_shear_split rows of a table whose length is state (io/checkpoint.hpp sized_records).
template <class Archive>
void checkpoint_shear_table(Archive& ar, const std::string& name, std::vector<beam_shear_split>& v) {
  ar.sized_records(name + "/size", v, [&](std::vector<beam_shear_split>& t) {
    ar.members(name + "/x", t, &beam_shear_split::x);
    ar.members(name + "/intact", t, &beam_shear_split::intact);
    ar.members(name + "/softening", t, &beam_shear_split::softening);
    ar.members(name + "/broken_or_slipped", t, &beam_shear_split::broken_or_slipped);
    ar.members(name + "/bars", t, &beam_shear_split::bars);
    ar.members(name + "/reaction", t, &beam_shear_split::reaction);
  });
}

/// The figures of beam_result the samples build (the rest are read at the end).
template <class Archive>
void checkpoint_beam_samples(Archive& ar, beam_result& r) {
  for (auto [name, v] : {std::pair{"deflection", &r.deflection}, std::pair{"load", &r.load},
                         std::pair{"plate_load", &r.plate_load}, std::pair{"load_point_deflection", &r.load_point_deflection},
                         std::pair{"smoothed_load", &r.smoothed_load}, std::pair{"crack_count", &r.crack_count}})
    ar.sized_array(std::string("beam/samples/") + name, *v);
  for (auto [name, x] : {std::pair{"first_crack_load", &r.first_crack_load},
                         std::pair{"first_crack_deflection", &r.first_crack_deflection},
                         std::pair{"soffit_peak_stress", &r.soffit_peak_stress},
                         std::pair{"developed_crack_load", &r.developed_crack_load},
                         std::pair{"developed_crack_deflection", &r.developed_crack_deflection},
                         std::pair{"first_crack_x", &r.first_crack_x},
                         std::pair{"first_crack_angle_deg", &r.first_crack_angle_deg},
                         std::pair{"first_inclined_crack_load", &r.first_inclined_crack_load},
                         std::pair{"first_inclined_crack_deflection", &r.first_inclined_crack_deflection},
                         std::pair{"first_inclined_crack_x", &r.first_inclined_crack_x},
                         std::pair{"yield_load", &r.yield_load}, std::pair{"yield_deflection", &r.yield_deflection},
                         std::pair{"peak_load", &r.peak_load}, std::pair{"peak_deflection", &r.peak_deflection}})
    ar.scalar(std::string("beam/events/") + name, *x);
  ar.scalar("beam/events/inclined_before_vertical", r.inclined_before_vertical);
  ar.scalar("beam/events/steel_yielded", r.steel_yielded);
  ar.scalar("beam/events/first_inclined_crack_span", r.first_inclined_crack_span);
  checkpoint_shear_table(ar, "beam/shear_at_inclined_crack", r.shear_at_inclined_crack);
  checkpoint_shear_table(ar, "beam/shear_at_peak", r.shear_at_peak);
  for (int k = 0; k < 2; ++k) {
    beam_span_figures& f = r.spans[static_cast<std::size_t>(k)];
    const std::string p = std::string("beam/span") + char('0' + k) + "/";
    ar.sized_array(p + "reaction", f.reaction);
    ar.sized_array(p + "plate_load", f.plate_load);
    ar.scalar(p + "reaction_at_peak", f.reaction_at_peak);
    ar.scalar(p + "plate_load_at_peak", f.plate_load_at_peak);
    ar.scalar(p + "first_inclined_crack_load", f.first_inclined_crack_load);
    ar.scalar(p + "first_inclined_crack_deflection", f.first_inclined_crack_deflection);
    ar.scalar(p + "first_inclined_crack_x", f.first_inclined_crack_x);
    checkpoint_shear_table(ar, p + "shear_at_peak", f.shear_at_peak);
  }
}

/// The flags that define a run, for --checkpoint and --resume: argv but the program and the flags
/// free to differ between a run and its continuation (with their values).
[[nodiscard]] inline std::string beam_run_key(int argc, char** argv) {
  static const char* const free_with_value[] = {"--threads", "--out", "--max-deflection", "--failure-drop",
                                                "--failure-confirm", "--checkpoint", "--checkpoint-every", "--resume"};
  std::string key = "rc_beam";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--no-vtk") continue;
    bool skip = false;
    for (const char* f : free_with_value) {
      if (a == f) skip = true, ++i;  // its value follows
      if (a.rfind(std::string(f) + "=", 0) == 0) skip = true;
    }
    if (!skip) key += " " + a;
  }
  return key;
}

/// Refuses a --resume file that cannot be read, is damaged (io_error, invalid_input) or was saved
/// by a run whose flags (its description) are not l.run_key (invalid_input naming both).
inline void require_beam_run_key(const beam_loading& l) {
  const io::checkpoint_info info = io::read_checkpoint_info(l.resume_file);
  require(info.description == l.run_key, "rc_beam: --resume ", l.resume_file,
          " was saved by a run with other flags than this one's (only --threads, --out, --no-vtk, --max-deflection, "
          "--failure-drop, --failure-confirm, --checkpoint and --checkpoint-every may differ):\n  saved: ",
          info.description, "\n  now:   ", l.run_key);
}

/// Refuses bad checkpoint flags before anything is written (invalid_input naming the value):
/// --checkpoint-every without --checkpoint, an empty file name, a split run, and a --resume file
/// that cannot be read, is damaged or was saved by a run with other flags.
inline void check_beam_checkpoint_flags(const cli::parser& cli, const beam_loading& l, int ranks) {
  require(!cli.given("--checkpoint") || !l.checkpoint_file.empty(), "rc_beam: --checkpoint needs a file name");
  require(!cli.given("--resume") || !l.resume_file.empty(), "rc_beam: --resume needs a file name");
  require(!cli.given("--checkpoint-every") || cli.given("--checkpoint"), "rc_beam: --checkpoint-every ",
          l.checkpoint_every, " s sets how often --checkpoint saves; give --checkpoint FILE too");
  require(ranks <= 1 || (l.checkpoint_file.empty() && l.resume_file.empty()),
          "rc_beam: --checkpoint and --resume run in one process; this run is split over ", ranks, " MPI ranks");
  if (!l.resume_file.empty()) require_beam_run_key(l);
}

/// The failure rule at one sample (load and defl: this sample's load, N, and mid-span deflection, m;
/// max_load: the peak so far, N): the load below (1 - failure_drop) x the peak, past the peak, and
/// with failure_confirm > 0 below it at every sample over that much further deflection. max_load
/// cannot change over such a run of samples (a load above the peak ends it), so the run is found by
/// scanning back over r's samples: exact, and the same after a --resume (the samples are in the
/// checkpoint). Sets r.failure_deflection (where the drop began) and r.unconfirmed_drop_deflection.
[[nodiscard]] inline bool update_failure(beam_result& r, const beam_loading& loading, bool first_found, real load,
                                         real defl, real max_load) {
  const real threshold = (1 - loading.failure_drop) * max_load;
  const bool below = first_found && load < threshold && defl > r.peak_deflection;
  real drop_from = defl;
  if (below && loading.failure_confirm > 0)
    for (std::size_t i = r.deflection.size() - 1;
         i > 0 && r.smoothed_load[i - 1] < threshold && r.deflection[i - 1] > r.peak_deflection; --i)
      drop_from = r.deflection[i - 1];
  const bool failed = below && defl >= drop_from + loading.failure_confirm;
  if (failed) r.failure_deflection = drop_from;
  r.unconfirmed_drop_deflection = below && !failed ? drop_from : -1;
  return failed;
}

/// summary.json's peak and failure keys: failure_reached; peak_load_N and peak_deflection_m (the
/// highest load so far where failure was not reached); load_at_stop_N and end_deflection_m;
/// peak_over_ec2_shear, peak_over_zsutty_shear and peak_over_shear_reference against the hand
/// values h, null when failure was not reached (a capped load is not a capacity); failure_mode
/// (the widest crack's classification, reached or not) and the widest crack.
inline void set_failure_figures(io::summary_json& js, const beam_result& r, const beam_hand_checks& h) {
  const real none = std::numeric_limits<real>::quiet_NaN(), peak = r.failure_reached ? r.peak_load : none;
  js.set("failure_reached", r.failure_reached)
      .set("failure_deflection_m", r.failure_reached ? r.failure_deflection : none)
      .set("unconfirmed_drop_deflection_m", r.unconfirmed_drop_deflection >= 0 ? r.unconfirmed_drop_deflection : none)
      .set("dip_deflections_m", r.dip_deflections)
      .set("peak_load_N", r.peak_load)
      .set("peak_deflection_m", r.peak_deflection)
      .set("load_at_stop_N", r.smoothed_load.empty() ? 0.0 : r.smoothed_load.back())
      .set("end_deflection_m", r.deflection.empty() ? 0.0 : r.deflection.back())
      .set("peak_over_ec2_shear", peak / h.ec2_shear_load)
      .set("peak_over_zsutty_shear", peak / h.zsutty_shear_load)
      .set("peak_over_shear_reference", peak / h.shear_reference_load())
      .set("failure_mode", r.failure_mode)
      .set("failure_mode_rule", std::string("the widest crack's classification at the end of the run, its angle "
                                            "along its path (beam_cracks.hpp), whether or not failure_reached (the "
                                            "load fell by --failure-drop)"))
      .set("widest_crack_x_m", r.widest.x)
      .set("widest_crack_angle_deg", r.widest.angle_deg)
      .set("widest_crack_width_m", r.widest.width);
}

/// The report's peak: the peak against the hand shear values h where the load fell by `drop` (a
/// fraction; held over `confirm` m of deflection, beam_loading::failure_confirm), else the highest
/// load before the stop and the load at it, without ratios.
[[nodiscard]] inline std::string beam_peak_text(const beam_result& r, const beam_hand_checks& h, real drop,
                                                real confirm = 0) {
  char buf[320];
  if (r.failure_reached)
    std::snprintf(buf, sizeof buf, "failure (the load fell %.0f %% below its peak): peak %.2f kN at %.2f mm (shear "
                  "capacity, hand %.1f kN; %.2fx EC2's %.1f kN, %.2fx Zsutty's %.1f kN)", 100 * drop, r.peak_load * 1e-3,
                  r.peak_deflection * 1e3, h.shear_capacity_load * 1e-3, r.peak_load / h.ec2_shear_load,
                  h.ec2_shear_load * 1e-3, r.peak_load / h.zsutty_shear_load, h.zsutty_shear_load * 1e-3);
  else if (r.unconfirmed_drop_deflection >= 0)
    std::snprintf(buf, sizeof buf, "no failure by %.2f mm (the load fell %.0f %% below its peak at %.2f mm, not held "
                  "over --failure-confirm by the stop): highest load %.2f kN at %.2f mm, %.2f kN at the stop",
                  (r.deflection.empty() ? 0.0 : r.deflection.back()) * 1e3, 100 * drop,
                  r.unconfirmed_drop_deflection * 1e3, r.peak_load * 1e-3, r.peak_deflection * 1e3,
                  (r.smoothed_load.empty() ? 0.0 : r.smoothed_load.back()) * 1e-3);
  else if (!r.dip_deflections.empty())
    std::snprintf(buf, sizeof buf, "no failure by %.2f mm (the load fell %.0f %% below its peak %zu time%s, first at "
                  "%.2f mm, without a diagonal crack: a dip): highest load %.2f kN at %.2f mm, %.2f kN at the stop",
                  (r.deflection.empty() ? 0.0 : r.deflection.back()) * 1e3, 100 * drop, r.dip_deflections.size(),
                  r.dip_deflections.size() == 1 ? "" : "s", r.dip_deflections.front() * 1e3, r.peak_load * 1e-3, r.peak_deflection * 1e3,
                  (r.smoothed_load.empty() ? 0.0 : r.smoothed_load.back()) * 1e-3);
  else if (confirm > 0)
    std::snprintf(buf, sizeof buf, "no failure by %.2f mm (the load never stayed %.0f %% below its peak over %.2f mm): "
                  "highest load %.2f kN at %.2f mm, %.2f kN at the stop (hand EC2 %.1f kN, Zsutty %.1f kN)",
                  (r.deflection.empty() ? 0.0 : r.deflection.back()) * 1e3, 100 * drop, confirm * 1e3, r.peak_load * 1e-3,
                  r.peak_deflection * 1e3, (r.smoothed_load.empty() ? 0.0 : r.smoothed_load.back()) * 1e-3,
                  h.ec2_shear_load * 1e-3, h.zsutty_shear_load * 1e-3);
  else
    std::snprintf(buf, sizeof buf, "no failure by %.2f mm (the load never fell %.0f %% below its peak): highest load "
                  "%.2f kN at %.2f mm, %.2f kN at the stop (hand EC2 %.1f kN, Zsutty %.1f kN)",
                  (r.deflection.empty() ? 0.0 : r.deflection.back()) * 1e3, 100 * drop, r.peak_load * 1e-3,
                  r.peak_deflection * 1e3, (r.smoothed_load.empty() ? 0.0 : r.smoothed_load.back()) * 1e-3,
                  h.ec2_shear_load * 1e-3, h.zsutty_shear_load * 1e-3);
  return buf;
}

/// summary.json's shear_at_first_inclined_crack_* and shear_at_peak_* (beam_shear.hpp).
inline void set_shear_figures(io::summary_json& js, const beam_result& r) {
  // Where the shear goes (beam_shear.hpp): per section in the shear span, at the first inclined
  // crack there and at the peak; bars: the trusses' vertical share (axial only: no dowel action).
  for (const auto& [when, table] : {std::pair{std::string("shear_at_first_inclined_crack_"), &r.shear_at_inclined_crack},
                                    std::pair{std::string("shear_at_peak_"), &r.shear_at_peak}}) {
    const char* names[] = {"x_m", "intact_N", "softening_N", "broken_or_slipped_N", "bars_N", "total_N", "reaction_N"};
    std::vector<real> col[7];
    real closure = 0;  // the largest |total / reaction - 1|: what the split leaves out (beam_shear.hpp)
    for (const auto& sp : *table) {
      const real row[7] = {sp.x, sp.intact, sp.softening, sp.broken_or_slipped, sp.bars, sp.total(), sp.reaction};
      for (int k = 0; k < 7; ++k) col[k].push_back(row[k]);
      if (sp.reaction > 0) closure = std::max(closure, std::abs(sp.total() / sp.reaction - 1));
    }
    for (int k = 0; k < 7; ++k) js.set(when + names[k], col[k]);
    js.set(when + "closure_error_rel", closure);
  }
}

}  // namespace tessera::scenes
