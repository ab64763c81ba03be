// work_precision_figures: error against run time as DESIGN.md §7 defines it, for the plain prism
// in direct tension, the RC tie (issue #19, item 3) and the RC beam to 1 mm (issue #43).
//
// Cracking bifurcates, so one curve against one reference is not a well-posed error (two
// converged tie runs differing only in rounding differ by 3.5 %). This driver runs every
// accuracy setting of a scene (step, loading rate, tail speed-up; kinetic dynamic relaxation at
// T = 1e-3: the prism's, and with --quick 3e-4 and 1e-4; the tie's, 10 um, not with --quick) on
// K seeds and reports, per
// setting:
//   - the seed mean of each figure that converges (prism: initial modulus, peak, dissipated
//     tensile energy; tie: initial stiffness, first cracking, first drop, yield plateau, crack
//     count, contact dissipation), its error against the same figure's mean at the converged
//     setting (the first of the list: smallest step, slowest rate; over the seeds where both
//     give the figure) and against the hand value;
//   - the distance between the K-seed mean curve and the converged K-seed mean curve (RMS over
//     the common abscissa range, relative to f_T or f_y A), beside the seed band: the RMS over
//     that range of the seed-to-seed standard deviation of the converged curves, i.e. the
//     distance below which two settings cannot be told apart with K seeds;
//   - the mean run time and step count of one run.
// Writes DIR/runs.csv (one row per run), DIR/table.csv and DIR/table.md (one row per setting),
// DIR/figures.md (per figure: converged mean, seed spread, hand value, errors), and
// DIR/work_precision_figures.png (|error against converged| of every figure and the curve
// distance against run time, log-log, with the seed band as a line), and DIR/run.json.
//
//   work_precision_figures --scene prism|tie|beam [--seeds K] [--blocks N] [--settings LIST] [--seed S] [--threads N]
//                          [--out DIR] [--quick]
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "common/cli.hpp"
#include "common/rc_tie_run.hpp"
#include "common/scenes.hpp"
#include "direct_tension/tension_test.hpp"
#include "rc_beam/beam_run.hpp"
#include "tessera/analysis/curves.hpp"
#include "tessera/io/atomic_file.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/plot.hpp"
#include "tessera/io/run_record.hpp"

namespace {

using tessera::real;
namespace fs = std::filesystem;
namespace sc = tessera::scenes;
constexpr real nan = std::numeric_limits<real>::quiet_NaN();

/// One accuracy setting. Prism: step = top displacement per step (m), tail = tail speed-up; or,
/// with relax_tolerance > 0, kinetic dynamic relaxation (direct_tension --scheme relaxation):
/// step = the increment (m), relax_tolerance the unbalanced ratio (rate and tail unused);
/// tie: step = mass-scaling target dt (s), tail unused, and the out-of-balance rate control
/// (solver/balance.hpp; min_factor = max_factor = 1: the fixed rate); or, with relax_tolerance
/// > 0, rc_tie --scheme relaxation: step = the increment of elongation (m).
struct setting {
  std::string name;
  real step = 0, rate = 0, tail = 1;
  real min_factor = 1, max_factor = 1;
  real relax_tolerance = 0;
};

/// A figure that converges: its name, unit scale for printing, and hand value (NaN: none).
struct figure {
  std::string name, unit;
  real print_scale = 1, hand = nan;
};

/// What one run gives: the figures (NaN where undefined), the curve and the cost.
struct run_output {
  std::vector<real> values;
  std::vector<real> x, y;  ///< the curve, abscissa made monotone
  double runtime_s = 0;
  std::int64_t steps = 0;
};

/// A scene under test: its settings (converged first), figures, curve scale and runner.
struct scene_def {
  std::string title, x_label;
  std::vector<setting> settings;
  std::vector<figure> figures;
  real curve_scale = 1;  ///< the curve distance is relative to this (f_T or f_y A)
  std::string curve_scale_name;
  std::function<run_output(const setting&, std::uint64_t seed)> run;
};

scene_def prism_def(int blocks, bool quick, int threads) {
  scene_def d;
  d.title = tessera::detail::concat("plain prism in direct tension, ", blocks, " blocks");
  d.x_label = "top displacement (m)";
  // Kinetic dynamic relaxation at three tolerances, 2 um increments (issue #43, candidate 2).
  const std::vector<setting> relaxed = {{"kdr_2um_T1e-3", 2e-6, 0, 1, 1, 1, 1e-3},
                                        {"kdr_2um_T3e-4", 2e-6, 0, 1, 1, 1, 3e-4},
                                        {"kdr_2um_T1e-4", 2e-6, 0, 1, 1, 1, 1e-4}};
  if (quick)  // stopped at 70 % of the peak on the softening branch: no energy figure
    d.settings = {{"du_2nm", 2e-9, 0.005, 4}, {"du_5nm", 5e-9, 0.005, 4}, {"du_10nm", 1e-8, 0.005, 4}};
  else
    d.settings = {{"du_1nm_tail_2", 1e-9, 0.005, 2}, {"du_2nm_tail_4", 2e-9, 0.005, 4},
                  {"du_2nm_tail_8", 2e-9, 0.005, 8}, {"du_5nm_tail_4", 5e-9, 0.005, 4},
                  {"du_10nm_tail_4", 1e-8, 0.005, 4}};
  // To separation a relaxed run costs 2.9x the explicit one's steps (159 s at T = 1e-3, seed 1):
  // the full figure keeps the driver's default tolerance, the quick one all three.
  d.settings.insert(d.settings.end(), relaxed.begin(), quick ? relaxed.end() : relaxed.begin() + 1);
  const sc::prism_scene probe = [&] {
    sc::prism_options po;
    po.blocks = blocks;
    return sc::make_prism(po);
  }();
  d.figures = {{"initial_modulus_Pa", "GPa", 1e-9, sc::concrete_young},
               {"peak_stress_Pa", "MPa", 1e-6, probe.f_T},
               {"peak_displacement_m", "um", 1e6, nan},
               {"dissipated_tension_over_Gf_crack_area", "", 1, 1.0}};
  d.curve_scale = probe.f_T;
  d.curve_scale_name = "f_T";
  d.run = [blocks, quick, threads](const setting& s, std::uint64_t seed) {
    sc::prism_options po;
    po.blocks = blocks;
    po.seed = seed;
    const sc::prism_scene scene = sc::make_prism(po);
    sc::tension_loading ld;
    if (s.relax_tolerance > 0) {
      ld.relaxation = true;
      ld.relax_increment = s.step;
      ld.relax_tolerance = s.relax_tolerance;
    } else {
      ld.rate = s.rate;
      ld.step_displacement = s.step;
      ld.tail_speedup = s.tail;
    }
    ld.threads = threads;
    ld.label = tessera::detail::concat("prism ", s.name, " seed ", seed);
    if (quick) {
      ld.stop_at_separation = false;
      ld.stop_below_peak_ratio = 0.7;
      ld.max_displacement = 2e-4;
    }
    const tessera::cli::wall_timer timer;
    const sc::tension_result r = sc::run_direct_tension<tessera::prism_solver>(scene, scene.contact, ld);
    run_output o;
    o.runtime_s = timer.seconds();
    o.steps = r.steps;
    const real energy = r.separated && r.crack_area > 0 ? r.dissipated_tension / (scene.G_f * r.crack_area) : nan;
    o.values = {r.initial_modulus, r.peak_stress, r.peak_displacement, energy};
    o.x = tessera::analysis::running_max(r.displacement);
    o.y = r.stress;
    return o;
  };
  return d;
}

scene_def tie_def(int blocks, bool quick, int threads) {
  scene_def d;
  d.title = tessera::detail::concat("RC tie, ", blocks, " blocks");
  d.x_label = "elongation (m)";
  if (quick)
    d.settings = {{"dt_2us_rate_10mm", 2e-6, 0.01}, {"dt_4us_rate_10mm", 4e-6, 0.01}};
  else
    d.settings = {{"dt_1us_rate_2.5mm", 1e-6, 0.0025}, {"dt_1us_rate_5mm", 1e-6, 0.005},
                  {"dt_2us_rate_5mm", 2e-6, 0.005},   {"dt_2us_rate_10mm", 2e-6, 0.01},
                  {"dt_4us_rate_5mm", 4e-6, 0.005},   {"dt_4us_rate_10mm", 4e-6, 0.01},
                  {"dt_8us_rate_10mm", 8e-6, 0.01},
                  {"dt_2us_rate_2.5mm", 2e-6, 0.0025},
                  {"dt_2us_rate_5mm_balance_0.5", 2e-6, 0.005, 1, 0.5, 1},
                  {"dt_2us_rate_5mm_balance_0.5_2", 2e-6, 0.005, 1, 0.5, 2},
                  {"dt_2us_rate_5mm_balance_0.25", 2e-6, 0.005, 1, 0.25, 1},
                  // Kinetic dynamic relaxation (issue #43, candidate 2); not in --quick, where it
                  // would add a minute to the CI smoke (its code path has rc_tie's CTest tests).
                  {"kdr_10um_T1e-3", 1e-5, 0, 1, 1, 1, 1e-3}};
  sc::tie_options to;
  to.blocks = blocks;
  const sc::tie_hand_checks hand = sc::make_tie(to).hand;
  d.figures = {{"initial_stiffness_N_per_m", "kN/mm", 1e-6, hand.bonded_stiffness},
               {"first_crack_force_N", "kN", 1e-3, hand.cracking_force},
               {"first_drop_force_N", "kN", 1e-3, hand.cracking_force},
               {"yield_force_N", "kN", 1e-3, hand.yield_force},
               {"cracks", "", 1, nan},
               {"contact_dissipated_J", "J", 1, nan}};
  d.curve_scale = hand.yield_force;
  d.curve_scale_name = "f_y A_s";
  d.run = [blocks, threads](const setting& s, std::uint64_t seed) {
    sc::tie_options o;
    o.blocks = blocks;
    o.seed = seed;
    const sc::tie_scene scene = sc::make_tie(o);
    sc::tie_loading ld;
    ld.dt = s.step;
    ld.rate = s.rate;
    ld.rate_control.min_factor = s.min_factor;
    ld.rate_control.max_factor = s.max_factor;
    ld.threads = threads;
    ld.progress_label = tessera::detail::concat("tie ", s.name, " seed ", seed);
    ld.relaxation = s.relax_tolerance > 0;
    if (ld.relaxation) ld.relax_increment = s.step, ld.relax_tolerance = s.relax_tolerance;
    const auto quiet = [](const auto&, const std::string&) {};
    const sc::tie_result r = ld.relaxation ? sc::run_tie<true>(scene, ld, quiet) : sc::run_tie<false>(scene, ld, quiet);
    run_output out;
    out.runtime_s = r.runtime_s;
    out.steps = r.steps;
    const auto positive = [](real v) { return v > 0 ? v : nan; };
    out.values = {r.initial_stiffness, positive(r.first_crack_force), positive(r.first_drop_force),
                  positive(r.yield_force), static_cast<real>(r.cracks.cracks), r.contact_dissipated};
    out.x = tessera::analysis::running_max(r.elongation);
    out.y = r.force;
    return out;
  };
  return d;
}

/// The RC beam in four-point bending (rc_beam), its quick geometry at 60 blocks (50 mm face
/// zoning), loaded to 1 mm of mid-span deflection (0.5 mm with --quick): past the first flexural
/// cracks, before yield. Explicit settings: plate rate at the driver's 20x added mass (step =
/// rate, m/s); relaxation: rc_beam --scheme relaxation, step = the plate's increment (m).
scene_def beam_def(int blocks, bool quick, int threads) {
  scene_def d;
  d.title = tessera::detail::concat("RC beam (provisional geometry), ", blocks, " blocks, to ", quick ? 0.5 : 1, " mm");
  d.x_label = "mid-span deflection (m)";
  if (quick)
    d.settings = {{"rate_2.5mm", 2.5e-3}, {"rate_5mm", 5e-3}, {"kdr_10um_T1e-3", 1e-5, 0, 1, 1, 1, 1e-3}};
  else
    d.settings = {{"rate_1.25mm", 1.25e-3},
                  {"rate_2.5mm", 2.5e-3},
                  {"rate_5mm", 5e-3},
                  {"kdr_10um_T1e-3", 1e-5, 0, 1, 1, 1, 1e-3},
                  {"kdr_10um_T3e-4", 1e-5, 0, 1, 1, 1, 3e-4}};
  sc::beam_options bo;
  bo.blocks = blocks;
  bo.zone_edge = blocks <= 60 ? 0.05 : 0;  // rc_beam --quick's zoning at 60 blocks, h/5 above
  const sc::beam_hand_checks hand = sc::make_beam(bo).hand;
  d.figures = {{"initial_stiffness_N_per_m", "kN/mm", 1e-6, hand.initial_stiffness},
               {"first_crack_load_N", "kN", 1e-3, hand.flexural_crack_load},
               {"first_crack_h4_deep_load_N", "kN", 1e-3, nan},
               {"elastic_check_load_N", "kN", 1e-3, nan},
               {"load_at_end_N", "kN", 1e-3, nan},
               {"cracks", "", 1, nan}};
  d.curve_scale = hand.flexural_crack_load;
  d.curve_scale_name = "P_cr (flexural strength, hand)";
  d.run = [bo, quick, threads](const setting& s, std::uint64_t seed) {
    sc::beam_options o = bo;
    o.seed = seed;
    const sc::beam_scene scene = sc::make_beam(o);
    sc::beam_loading ld;
    ld.added_mass_ratio = 20;  // rc_beam's default
    ld.max_deflection = quick ? 5e-4 : 1e-3;
    ld.threads = threads;
    ld.progress = false;
    ld.relaxation = s.relax_tolerance > 0;
    if (ld.relaxation)
      ld.relax_increment = s.step, ld.relax_tolerance = s.relax_tolerance;
    else
      ld.rate = s.step;
    const sc::beam_result r = sc::run_beam(scene, ld, [](const auto&, const std::string&) {});
    run_output out;
    out.runtime_s = r.runtime_s;
    out.steps = r.steps;
    const auto positive = [](real v) { return v > 0 ? v : nan; };
    out.values = {r.initial_stiffness, positive(r.first_crack_load), positive(r.developed_crack_load),
                  r.elastic.load, r.smoothed_load.empty() ? nan : r.smoothed_load.back(),
                  static_cast<real>(r.final_cracks.size())};
    out.x = tessera::analysis::running_max(r.deflection);
    out.y = r.smoothed_load;
    return out;
  };
  return d;
}

/// Mean and sample standard deviation of the finite values (NaN when none).
struct stats {
  real mean = nan, sd = nan;
  int n = 0;
};
stats stats_of(const std::vector<real>& v) {
  stats s;
  double sum = 0;
  for (real x : v)
    if (std::isfinite(x)) sum += x, ++s.n;
  if (s.n == 0) return s;
  s.mean = sum / s.n;
  double ss = 0;
  for (real x : v)
    if (std::isfinite(x)) ss += (x - s.mean) * (x - s.mean);
  s.sd = s.n > 1 ? std::sqrt(ss / (s.n - 1)) : 0;
  return s;
}

/// The runs of one setting, reduced: figure statistics, the mean curve on the common grid, cost.
struct setting_result {
  std::vector<stats> figures;
  std::vector<std::vector<real>> curves;  ///< each seed's curve on the grid
  std::vector<real> mean_curve;
  double runtime_s = 0;  ///< mean over the seeds
  double steps = 0;
  real curve_distance = nan;  ///< RMS(mean curve - converged mean curve) / curve_scale
  /// Per figure: (mean - converged mean) / |converged mean| over the seeds where both runs give
  /// the figure (a figure undefined for a seed, e.g. no separation, drops that seed on both sides).
  std::vector<real> vs_converged;
  std::vector<real> vs_converged_se;  ///< its paired standard error (paired_error)
};

/// The paired error of setting s's figure f against the converged setting (runs[0]), and its
/// standard error: with d_k = (v_k - c_k) / |mean c| over the n seeds where both runs give the
/// figure, the error is the mean of d_k (= (sum v - sum c) / |sum c|) and its standard error
/// sd(d) / sqrt(n) (NaN with fewer than two seeds). Pairing by seed takes the tessellation's
/// share out of the seed-to-seed spread; what is left is how far one setting's cracking path
/// wanders from the other's on the same blocks, so an error under about two standard errors is
/// not resolved by K seeds.
struct paired {
  real error = nan, standard_error = nan;
};

paired paired_error(const std::vector<std::vector<run_output>>& runs, std::size_t s, std::size_t f) {
  double sum = 0, sum_conv = 0;
  std::vector<real> diff;
  for (std::size_t k = 0; k < std::min(runs[s].size(), runs[0].size()); ++k) {
    const real v = runs[s][k].values[f], c = runs[0][k].values[f];
    if (std::isfinite(v) && std::isfinite(c)) sum += v, sum_conv += c, diff.push_back(v - c);
  }
  paired p;
  if (diff.empty() || sum_conv == 0) return p;
  const double n = static_cast<double>(diff.size()), scale = std::abs(sum_conv) / n;
  p.error = (sum - sum_conv) / std::abs(sum_conv);
  if (diff.size() > 1) p.standard_error = stats_of(diff).sd / std::sqrt(n) / scale;
  return p;
}

std::vector<real> mean_of_curves(const std::vector<std::vector<real>>& curves) {
  std::vector<real> m(curves.front().size(), 0);
  for (const auto& c : curves)
    for (std::size_t k = 0; k < m.size(); ++k) m[k] += c[k] / static_cast<real>(curves.size());
  return m;
}

real rms_difference(const std::vector<real>& a, const std::vector<real>& b) {
  double s = 0;
  for (std::size_t k = 0; k < a.size(); ++k) s += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(s / static_cast<double>(a.size()));
}

/// RMS over the grid of the seed-to-seed standard deviation (0 with one seed).
real seed_band(const std::vector<std::vector<real>>& curves, const std::vector<real>& mean) {
  if (curves.size() < 2) return 0;
  double s = 0;
  for (std::size_t k = 0; k < mean.size(); ++k)
    for (const auto& c : curves) s += (c[k] - mean[k]) * (c[k] - mean[k]);
  return std::sqrt(s / static_cast<double>(mean.size() * (curves.size() - 1)));
}

real rel(real value, real against) {
  return std::isfinite(value) && std::isfinite(against) && against != 0 ? (value - against) / std::abs(against) : nan;
}

std::string percent(real e) {
  if (!std::isfinite(e)) return "—";
  char b[32];
  std::snprintf(b, sizeof b, "%+.2f %%", 100 * e);
  return b;
}

/// A magnitude in per cent, no sign (a spread, a distance).
std::string magnitude(real e) {
  if (!std::isfinite(e)) return "—";
  char b[32];
  std::snprintf(b, sizeof b, "%.2f %%", 100 * e);
  return b;
}

std::string value_text(real v, const figure& f) {
  if (!std::isfinite(v)) return "—";
  char b[48];
  std::snprintf(b, sizeof b, f.unit.empty() ? "%.3f" : "%.4g %s", v * f.print_scale, f.unit.c_str());
  return b;
}

/// Keeps the converged setting and those named in the comma-separated `list`; throws
/// invalid_input naming an unknown name (before any run).
void select_settings(scene_def& d, const std::string& list) {
  std::vector<setting> kept{d.settings.front()};
  for (const std::string& name : tessera::cli::split_list(list, "--settings")) {
    if (name == d.settings.front().name) continue;
    const auto it = std::find_if(d.settings.begin(), d.settings.end(), [&](const setting& s) { return s.name == name; });
    if (it == d.settings.end()) {
      std::string names;
      for (const setting& s : d.settings) names += (names.empty() ? "" : ", ") + s.name;
      throw tessera::invalid_input(tessera::detail::concat("--settings: '", name, "' is not a setting of this scene (",
                                                           names, ")"));
    }
    kept.push_back(*it);
  }
  d.settings = std::move(kept);
}

/// The runs of every setting, and for each setting the reason it was refused (empty: it ran).
struct all_runs {
  std::vector<std::vector<run_output>> runs;
  std::vector<std::string> refused;
};

/// Runs every setting on seeds seed0 .. seed0 + K - 1 (one line each), writing runs.csv as it goes.
/// A setting the driver refuses for one seed (a rate that is not quasi-static once the mass
/// scaling of that tessellation is known, say) is dropped with the reason; the converged setting
/// must run.
all_runs run_all(const scene_def& d, std::uint64_t seed0, int seeds, const fs::path& out) {
  std::vector<std::string> header{"setting", "seed", "steps", "runtime_s"};
  for (const figure& f : d.figures) header.push_back(f.name);
  tessera::io::atomic_ofstream file(out / "runs.csv");
  std::ostream& os = file.stream();
  os.precision(10);
  for (std::size_t i = 0; i < header.size(); ++i) os << (i ? "," : "") << header[i];
  os << '\n';
  all_runs all{std::vector<std::vector<run_output>>(d.settings.size()), std::vector<std::string>(d.settings.size())};
  auto& runs = all.runs;
  for (std::size_t s = 0; s < d.settings.size(); ++s)
    for (int k = 0; k < seeds; ++k) {
      const std::uint64_t seed = seed0 + static_cast<std::uint64_t>(k);
      try {
        runs[s].push_back(d.run(d.settings[s], seed));
      } catch (const tessera::invalid_input& e) {
        if (s == 0) throw;
        all.refused[s] = tessera::detail::concat("seed ", seed, ": ", e.what());
        runs[s].clear();
        std::printf("%-20s seed %llu: refused (%s)\n", d.settings[s].name.c_str(), static_cast<unsigned long long>(seed),
                    e.what());
        break;
      }
      const run_output& o = runs[s].back();
      os << d.settings[s].name << ',' << seed << ',' << o.steps << ',' << o.runtime_s;
      std::printf("%-20s seed %llu: %9lld steps %8.1f s", d.settings[s].name.c_str(),
                  static_cast<unsigned long long>(seed), static_cast<long long>(o.steps), o.runtime_s);
      for (std::size_t f = 0; f < d.figures.size(); ++f) {
        os << ',' << o.values[f];
        std::printf("  %s", value_text(o.values[f], d.figures[f]).c_str());
      }
      os << '\n';
      std::printf("\n");
      std::fflush(stdout);
    }
  file.commit();
  return all;
}

/// Reduces the runs: figure statistics, curves on a common grid over [0, shortest curve end],
/// mean curves and their distances to the converged one (setting 0). Returns the seed band.
real reduce(const scene_def& d, const std::vector<std::vector<run_output>>& runs, std::vector<setting_result>& res) {
  real x_end = std::numeric_limits<real>::infinity();
  for (const auto& rs : runs)
    for (const run_output& o : rs) x_end = std::min(x_end, o.x.empty() ? real(0) : o.x.back());
  tessera::require(x_end > 0, "work_precision_figures: a run produced an empty curve");
  constexpr int points = 1000;
  res.assign(runs.size(), {});
  for (std::size_t s = 0; s < runs.size(); ++s) {
    setting_result& r = res[s];
    for (std::size_t f = 0; f < d.figures.size(); ++f) {
      std::vector<real> v;
      for (const run_output& o : runs[s]) v.push_back(o.values[f]);
      r.figures.push_back(stats_of(v));
      const paired p = paired_error(runs, s, f);
      r.vs_converged.push_back(p.error);
      r.vs_converged_se.push_back(p.standard_error);
    }
    for (const run_output& o : runs[s]) {
      r.runtime_s += o.runtime_s / static_cast<double>(runs[s].size());
      r.steps += static_cast<double>(o.steps) / static_cast<double>(runs[s].size());
      std::vector<real> c(points + 1);
      for (int k = 0; k <= points; ++k) c[static_cast<std::size_t>(k)] = tessera::analysis::interpolate_curve(o.x, o.y, x_end * k / points);
      r.curves.push_back(std::move(c));
    }
    r.mean_curve = mean_of_curves(r.curves);
  }
  for (setting_result& r : res) r.curve_distance = rms_difference(r.mean_curve, res.front().mean_curve) / d.curve_scale;
  return seed_band(res.front().curves, res.front().mean_curve) / d.curve_scale;
}

void write_tables(const scene_def& d, const std::vector<setting_result>& res, real band, int seeds,
                  const std::vector<std::string>& notes, const fs::path& out) {
  const std::size_t nf = d.figures.size();
  tessera::io::atomic_ofstream csv(out / "table.csv");
  std::ostream& c = csv.stream();
  c.precision(10);
  c << "setting,step,rate_m_per_s,tail_speedup,steps,runtime_s";
  for (const figure& f : d.figures) c << ',' << f.name << "_mean," << f.name << "_sd," << f.name << "_vs_converged_rel," << f.name << "_vs_converged_se_rel," << f.name << "_vs_hand_rel";
  c << ",mean_curve_distance_rel,seed_band_rel\n";
  tessera::io::atomic_ofstream md(out / "table.md");
  std::ostream& m = md.stream();
  m << "| setting | steps | run time | ";
  for (const figure& f : d.figures) m << f.name << " | ";
  m << "mean-curve distance |\n|---|---|---|";
  for (std::size_t f = 0; f <= nf; ++f) m << "---|";
  m << '\n';
  for (std::size_t s = 0; s < res.size(); ++s) {
    const setting& st = d.settings[s];
    const setting_result& r = res[s];
    c << st.name << ',' << st.step << ',' << st.rate << ',' << st.tail << ',' << r.steps << ',' << r.runtime_s;
    char head[160];
    std::snprintf(head, sizeof head, "| %s%s | %.0f | %.1f s | ", st.name.c_str(), s == 0 ? " (converged)" : "", r.steps,
                  r.runtime_s);
    m << head;
    for (std::size_t f = 0; f < nf; ++f) {
      const real conv = r.vs_converged[f];
      const real se = r.vs_converged_se[f];
      c << ',' << r.figures[f].mean << ',' << r.figures[f].sd << ',' << conv << ',' << se << ','
        << rel(r.figures[f].mean, d.figures[f].hand);
      m << value_text(r.figures[f].mean, d.figures[f])
        << (s == 0 ? "" : " (" + percent(conv) + (std::isfinite(se) ? " ± " + magnitude(se) : "") + ")");
      if (r.figures[f].n > 0 && r.figures[f].n < seeds) m << " [" << r.figures[f].n << " of " << seeds << " seeds]";
      m << " | ";
    }
    c << ',' << r.curve_distance << ',' << band << '\n';
    m << (s == 0 ? "—" : magnitude(r.curve_distance)) << " |\n";
  }
  m << "\nMeans over " << seeds << " seeds; in brackets the difference from the converged mean ± its paired standard error "
       "(seed by seed differences: an error under about two of them is not resolved by these seeds). Mean-curve distance: RMS "
       "difference from the converged mean curve over the common range, relative to "
    << d.curve_scale_name << "; the seed band (RMS of the seed-to-seed standard deviation at the converged setting) is "
    << magnitude(band) << ".\n";
  for (const std::string& n : notes) m << "\n" << n << '\n';
  csv.commit();
  md.commit();
}

/// figures.md: per figure, the converged mean and seed spread, the hand value and every
/// setting's error against it.
void write_figures(const scene_def& d, const std::vector<setting_result>& res, int seeds, const fs::path& out) {
  tessera::io::atomic_ofstream md(out / "figures.md");
  std::ostream& m = md.stream();
  m << "| figure | hand | converged mean | seed sd / mean |";
  for (const setting& s : d.settings) m << ' ' << s.name << " vs hand |";
  m << "\n|---|---|---|---|";
  for (std::size_t s = 0; s < d.settings.size(); ++s) m << "---|";
  m << '\n';
  for (std::size_t f = 0; f < d.figures.size(); ++f) {
    const stats& conv = res.front().figures[f];
    m << "| " << d.figures[f].name << " | " << value_text(d.figures[f].hand, d.figures[f]) << " | "
      << value_text(conv.mean, d.figures[f]) << " | " << magnitude(conv.sd / std::abs(conv.mean)) << " |";
    for (const setting_result& r : res) m << ' ' << percent(rel(r.figures[f].mean, d.figures[f].hand)) << " |";
    m << '\n';
  }
  m << "\n" << seeds << " seeds per setting; the first setting is the converged one.\n";
  md.commit();
}

/// The log-log plot: |error against converged| of each figure and the mean-curve distance
/// against the mean run time (errors below 1e-4 drawn at 1e-4), the seed band as a line. Each
/// scheme is its own series: the explicit settings, and the relaxation ones (dashed) beside them.
void write_plot(const scene_def& d, const std::vector<setting_result>& res, real band, const fs::path& out) {
  constexpr real floor = 1e-4;
  tessera::io::plot_spec plot;
  plot.title = d.title + ": error against the converged setting vs run time";
  plot.xlabel = "run time of one run (s)";
  plot.ylabel = "|error| against the converged mean (floor 1e-4)";
  plot.log_x = plot.log_y = true;
  const auto series = [&](const std::string& name, const std::function<real(const setting_result&)>& error,
                          const std::string& style) {
    for (const bool relaxed : {false, true}) {
      std::vector<std::pair<double, real>> pts;  // (run time, error), drawn in order of run time
      for (std::size_t s = 1; s < res.size(); ++s)
        if ((d.settings[s].relax_tolerance > 0) == relaxed)
          pts.emplace_back(res[s].runtime_s, std::max(std::abs(error(res[s])), floor));
      if (pts.empty()) continue;
      std::sort(pts.begin(), pts.end());
      const std::string file = "points_" + name + (relaxed ? "_relaxation" : "") + ".csv";
      tessera::io::csv_writer w(out / file, {"runtime_s", "error"});
      for (const auto& [t, e] : pts) w.row(t, e);
      w.commit();
      plot.series.push_back({.csv = out / file, .x_column = "runtime_s", .y_column = "error",
                             .title = relaxed ? name + ", relaxation" : name,
                             .style = relaxed ? style + " dt 2" : style});
    }
  };
  int pt = 4;
  for (std::size_t f = 0; f < d.figures.size(); ++f) {
    if (!std::isfinite(res.front().figures[f].mean)) continue;
    series(d.figures[f].name, [&, f](const setting_result& r) {
      const real e = r.vs_converged[f];
      return std::isfinite(e) ? e : real(1);
    }, tessera::detail::concat("linespoints pt ", pt++, " ps 1.5"));
  }
  series("mean_curve_distance", [](const setting_result& r) { return r.curve_distance; }, "linespoints lw 3 pt 7 ps 2");
  real t_lo = res.front().runtime_s, t_hi = t_lo;
  for (const setting_result& r : res) t_lo = std::min(t_lo, r.runtime_s), t_hi = std::max(t_hi, r.runtime_s);
  tessera::io::csv_writer w(out / "points_seed_band.csv", {"runtime_s", "error"});
  w.row(t_lo, std::max(band, floor));
  w.row(t_hi, std::max(band, floor));
  w.commit();
  plot.series.push_back({.csv = out / "points_seed_band.csv", .x_column = "runtime_s", .y_column = "error",
                         .title = "seed band of the curve", .style = "lines dt 2 lw 2"});
  tessera::io::plot_png(out / "work_precision_figures.png", plot);
}

}  // namespace

int main(int argc, char** argv) {
  tessera::cli::standard_options common;
  std::string scene = "tie";
  int seeds = 5, blocks = 100;
  tessera::cli::parser cli("work_precision_figures",
                           "Error against run time as DESIGN.md section 7 defines it: every accuracy setting of a scene on K\n"
                           "seeds; figure by figure (seed means) against the converged setting and the hand values, the\n"
                           "distance between K-seed mean curves beside the seed band, run time and steps.\n"
                           "--quick: 2 seeds, two or three coarse settings (and the prism's three relaxation settings), the prism\n"
                           "stopped at 70 % of its peak.");
  cli.add_standard(common);
  cli.option("--scene", scene, "scene").one_of({"prism", "tie", "beam"});
  cli.option("--seeds", seeds, "seeds per setting (seed, seed+1, ...)", "K").within(1, 100);
  cli.option("--blocks", blocks, "number of blocks (default 100; the beam's 60)", "N").one_of_numbers({60, 100, 250, 500});
  std::string only;
  cli.option("--settings", only,
             "comma-separated names of the settings to run besides the converged one (empty = all; the names are "
             "printed in table.md)",
             "LIST");
  cli.parse_or_exit(argc, argv);
  if (common.quick && !cli.given("--seeds")) seeds = 2;
  if (scene == "beam" && !cli.given("--blocks")) blocks = 60;
  // run.json: "running" when the output directory is made, "complete" after the last table,
  // "interrupted" on SIGINT/SIGTERM (cmake/validate.sh --resume reads it).
  tessera::io::run_record record(common.out, "work_precision_figures", argc, argv);
  try {
    scene_def d = scene == "prism"  ? prism_def(blocks, common.quick, common.threads)
                  : scene == "tie" ? tie_def(blocks, common.quick, common.threads)
                                   : beam_def(blocks, common.quick, common.threads);
    if (!only.empty()) select_settings(d, only);
    const fs::path out = common.out;
    tessera::io::ensure_directory(out);
    std::printf("%s: %zu settings x %d seeds\n", d.title.c_str(), d.settings.size(), seeds);
    const all_runs all = run_all(d, common.seed, seeds, out);
    scene_def ran = d;  // the settings that ran on every seed
    ran.settings.clear();
    std::vector<std::vector<run_output>> runs;
    std::vector<std::string> notes;
    for (std::size_t s = 0; s < d.settings.size(); ++s) {
      if (all.refused[s].empty()) {
        ran.settings.push_back(d.settings[s]);
        runs.push_back(all.runs[s]);
      } else {
        notes.push_back("Setting " + d.settings[s].name + " refused by the driver, " + all.refused[s]);
      }
    }
    std::vector<setting_result> res;
    const real band = reduce(ran, runs, res);
    write_tables(ran, res, band, seeds, notes, out);
    write_figures(ran, res, seeds, out);
    write_plot(ran, res, band, out);
    std::printf("wrote %s (table.md, figures.md, work_precision_figures.png)\n", out.string().c_str());
    record.complete();
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "work_precision_figures: " << e.what() << '\n';
    return 1;
  }
}
