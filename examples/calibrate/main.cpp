// calibrate: fits the contact strength of the study's prism so that the mean peak of the direct
// tension test equals the concrete's f_T, and optionally the contact fracture energy so that the
// mean dissipated energy per cross-section equals G_f (DESIGN.md §5). Writes calibrated.json,
// which direct_tension and rc_tie load with --params FILE.
//
// Why: Voronoi blocks with the study's law peak above f_T (an inclined face peaks at
// f_T (1 + k_s/k_n tan^2 theta), and the crack is tortuous), by 10-25 % depending on the block
// count (docs/validation.md). 3DEC and YADE users calibrate the micro-strength against the macro
// test; this is that step, reproducible and recorded.
//
// The fit, per block count N (--blocks 100,250,500):
//   strength   s scales the contacts' tensile strength and cohesion together (c_0 / f_T stays
//              --cohesion-ratio). K seeds (--seed, --seed+1, ...) run to just past the peak
//              (stopped once the stress falls below 0.9 x peak); their mean peak P(s) is driven
//              to f_T by the secant method on P(s) - f_T, starting from s = 1 and the
//              proportional step s f_T / P; a step is limited to a factor of 2 (the peak is
//              nearly proportional to s, so the limit only guards against a wild secant).
//              Converged when |P/f_T - 1| <= --tolerance.
//   energy     (--energy) with s fixed, g scales the contacts' G_f; the K seeds run to complete
//              separation and the mean contact dissipation / cross-section D(g) is driven to
//              G_f the same way (--energy-tolerance). A lower G_f lowers the peak as well
//              (quick 100-block prism: g = 0.39 takes the peak from +0.2 % to -15.8 %), so the
//              strength is fitted again and the two alternate, at most 4 rounds, until one set
//              of full runs meets both tolerances; otherwise the entry is not converged.
//
// Materials (--material): prism = the study's prism concrete (Table 1 contacts on the 68 x 68 x
// 600 mm prism; block counts 100, 250, 500, 750; loaded by direct_tension and rc_tie); beam = the
// beam's concrete (study_beam_params, linear softening, the beam's face zoning) on the prism of
// rc_beam/beam.hpp make_beam_prism, a 150 x 150 x 600 mm prism with the beam's mean cell volume
// (block counts are the beam's: 250 -> 155 prism blocks, 500 -> 310); loaded by rc_beam. The
// scale is a property of the law and of the block and sub-contact sizes, so each material and
// block count has its own.
//
// Outputs in --out DIR: calibrated.json (recipe and one entry per block count: scales, seeds,
// iterations, converged, mean peak and its error, seed spread, energy figures), calibration.csv
// (every iteration), summary.json (flat: per block count and overall), run.json.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "calibrate/targets_run.hpp"
#include "common/calibration.hpp"
#include "common/cli.hpp"
#include "common/scenes.hpp"
#include "direct_tension/tension_test.hpp"
#include "rc_beam/beam.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/run_record.hpp"
#include "tessera/solver.hpp"

namespace {

using tessera::real;
namespace fs = std::filesystem;
namespace scenes = tessera::scenes;

struct inputs {
  tessera::cli::standard_options common;
  std::string blocks = "100,250,500";
  int seeds = 6;  // 3 left the 250-block prism at -6.4 % on unseen seeds, 6 at -2.3 % (docs/validation.md)
  bool energy = false;
  double tolerance = 0.01;         // on the mean peak, relative to f_T
  double energy_tolerance = 0.03;  // on the mean dissipation per section, relative to G_f
  int max_iterations = 8;
  scenes::calibration_recipe recipe;
  std::vector<int> block_counts;   // parsed from `blocks`
};

// "100,250,500" -> {100, 250, 500} (cli::split_list: no empty item, no repeat). Prism: each a
// Table 1 block count; beam: a block count rc_beam accepts (250, 500, or 8..249 for a coarse beam).
std::vector<int> parse_block_counts(const std::string& text, const std::string& material) {
  std::vector<int> counts;
  for (const std::string& item : tessera::cli::split_list(text, "calibrate: --blocks")) {
    if (material == "prism") {
      tessera::require(item == "100" || item == "250" || item == "500" || item == "750", "calibrate: --blocks '", text,
                       "': '", item, "' is not one of 100, 250, 500, 750 (Table 1)");
    } else {
      const bool digits = item.size() <= 3 && std::all_of(item.begin(), item.end(), [](char c) { return c >= '0' && c <= '9'; });
      const int v = digits ? std::stoi(item) : -1;
      tessera::require(v == 250 || v == 500 || (v >= 8 && v < 250), "calibrate: --blocks '", text, "': '", item,
                       "' is not a beam block count (250, 500, or 8..249 for a coarse beam)");
    }
    const int n = std::stoi(item);
    tessera::require(std::find(counts.begin(), counts.end(), n) == counts.end(), "calibrate: --blocks '", text,
                     "' lists ", n, " twice");
    counts.push_back(n);
  }
  return counts;
}

// The beam's contacts (linear softening, plastic cap) on deformable blocks, without bars.
using beam_prism_solver = tessera::solver<tessera::blocks::deformable<tessera::zones::linear_elastic_tet>,
                                         tessera::presets::bonded_faces<tessera::presets::study_beam_law>>;

// The beam recipe's prism for `blocks` beam blocks (make_beam_prism), at the recipe's zoning.
scenes::beam_prism_scene beam_prism(const inputs& in, int blocks, std::uint64_t seed, real s, real g) {
  scenes::beam_options bo;
  bo.blocks = blocks;
  bo.seed = seed;
  bo.zone_edge = in.recipe.zone_edge;
  bo.strength_scale = s;
  bo.fracture_energy_scale = g;
  return scenes::make_beam_prism(bo);
}

// The study prism recipe's options for `blocks` blocks.
scenes::prism_options prism_options_for(const inputs& in, int blocks, std::uint64_t seed, real s, real g) {
  scenes::prism_options po;
  po.blocks = blocks;
  po.seed = seed;
  po.cohesion_ratio = in.recipe.cohesion_ratio;
  po.strength_scale = s;
  po.fracture_energy_scale = g;
  return po;
}

// The reference prism of a block count: the concrete's f_T, G_f and the cross-section.
scenes::prism_scene reference_prism(const inputs& in, int blocks) {
  if (in.recipe.material == "beam") return beam_prism(in, blocks, in.common.seed, 1, 1).prism;
  return scenes::make_prism(prism_options_for(in, blocks, in.common.seed, 1, 1));
}

// One seed at strength scale s and fracture-energy scale g: to just past the peak, or (full) to
// separation.
scenes::tension_result run_seed(const inputs& in, int blocks, std::uint64_t seed, real s, real g, bool full) {
  scenes::tension_loading ld;
  ld.rate = in.recipe.rate;
  ld.step_displacement = in.recipe.step_displacement;
  ld.threads = in.common.threads;
  ld.stop_at_separation = full;
  if (!full) {
    ld.stop_below_peak_ratio = 0.9;
    ld.max_displacement = 3e-4;
  }
  ld.label = tessera::detail::concat("calibrate ", in.recipe.material, " ", blocks, " blocks seed ", seed, " s ", s);
  if (in.recipe.material == "beam") {
    const scenes::beam_prism_scene b = beam_prism(in, blocks, seed, s, g);
    return scenes::run_direct_tension<beam_prism_solver>(b.prism, b.contact, ld);
  }
  const scenes::prism_scene scene = scenes::make_prism(prism_options_for(in, blocks, seed, s, g));
  return scenes::run_prism_variant(scene, in.recipe.softening, in.recipe.rigid, ld);
}

// The K seeds at one (s, g): mean and spread of the peak, mean dissipation per cross-section.
struct ensemble {
  std::vector<double> peaks;  // Pa
  double peak_mean = 0, peak_spread = 0, energy_mean = 0;  // Pa, (max - min)/mean, J/m^2
  /// Mean initial modulus of the seeds' pulls (Pa; tension_test.hpp initial_modulus): the
  /// stiffness the contacts' k_n gives the recipe's blocks, which rc_beam's hand stiffness can use.
  double modulus_mean = 0;
  std::int64_t steps = 0;
  bool all_separated = true;
  std::string damping_in_force;  // the seeds' damping (solver::damping_in_force())
};

ensemble run_ensemble(const inputs& in, int blocks, real s, real g, bool full, real area) {
  ensemble e;
  for (int k = 0; k < in.seeds; ++k) {
    const scenes::tension_result r =
        run_seed(in, blocks, in.common.seed + static_cast<std::uint64_t>(k), s, g, full);
    e.peaks.push_back(r.peak_stress);
    e.peak_mean += r.peak_stress / in.seeds;
    e.energy_mean += r.dissipated / area / in.seeds;
    e.modulus_mean += r.initial_modulus / in.seeds;
    e.steps += r.steps;
    e.all_separated = e.all_separated && r.separated;
    e.damping_in_force = r.damping_in_force;
  }
  const auto [lo, hi] = std::minmax_element(e.peaks.begin(), e.peaks.end());
  e.peak_spread = (*hi - *lo) / e.peak_mean;
  return e;
}

// The secant step for f(x) = target on the last two points, limited to a factor of 2.
real next_scale(real x, real fx, real x_prev, real f_prev, bool have_prev, real target) {
  real next = x * target / fx;  // proportional step
  if (have_prev && fx != f_prev) next = x + (target - fx) * (x - x_prev) / (fx - f_prev);
  return std::clamp(next, 0.5 * x, 2 * x);
}

struct fit_row {
  int blocks = 0;
  std::string phase;
  int iteration = 0;
  real s = 1, g = 1;
  ensemble e;
  double wall_s = 0;
};

struct fit_result {
  int blocks = 0;
  int prism_blocks = 0;  // Voronoi blocks of the prism fitted on (the beam recipe's differ from `blocks`)
  real s = 1, g = 1;
  int strength_iterations = 0, energy_iterations = 0;
  bool converged = false;
  ensemble last;               // the ensemble at the final scales (full runs with --energy)
  double peak_error = 0, energy_error = 0;
};

// Drives measure(x) to `target` by the secant method from x, until |measure/target - 1| <= tol
// and measure's `acceptable` flag holds; returns whether it converged within max_iterations.
template <class Measure>
bool secant_fit(real& x, real target, double tol, int max_iterations, int& iterations, Measure&& measure) {
  real x_prev = 0, f_prev = 0;
  for (int it = 1; it <= max_iterations; ++it) {
    iterations = it;
    bool acceptable = true;
    const real fx = measure(x, it, acceptable);
    if (std::abs(fx / target - 1) <= tol && acceptable) return true;
    const real next = next_scale(x, fx, x_prev, f_prev, it > 1, target);
    x_prev = x;
    f_prev = fx;
    x = next;
  }
  return false;
}

fit_result fit_block_count(const inputs& in, int blocks, const scenes::prism_scene& reference,
                           std::vector<fit_row>& rows, std::int64_t& steps) {
  fit_result f;
  f.blocks = blocks;
  const real f_t = reference.f_T, g_f = reference.G_f, area = reference.cross_section();
  const auto measure = [&](bool full) {
    return [&, full](real x, int it, bool& acceptable) {
      const tessera::cli::wall_timer t;
      (full ? f.g : f.s) = x;
      const ensemble e = run_ensemble(in, blocks, f.s, f.g, full, area);
      steps += e.steps;
      rows.push_back({blocks, full ? "energy" : "strength", it, f.s, f.g, e, t.seconds()});
      f.last = e;
      f.peak_error = e.peak_mean / f_t - 1;
      f.energy_error = e.energy_mean / g_f - 1;
      acceptable = !full || e.all_separated;
      if (full)
        std::printf("calibrate: %d blocks, energy iteration %d: g = %.6f, dissipated %.2f N/m (%+.2f %%), peak %+.2f %%%s\n",
                    blocks, it, f.g, e.energy_mean, 100 * f.energy_error, 100 * f.peak_error,
                    e.all_separated ? "" : " (a seed did not separate)");
      else
        std::printf("calibrate: %d blocks, strength iteration %d: s = %.6f, mean peak %.4f MPa (%+.2f %%), spread %.1f %%\n",
                    blocks, it, f.s, e.peak_mean * 1e-6, 100 * f.peak_error, 100 * e.peak_spread);
      std::fflush(stdout);
      return full ? e.energy_mean : e.peak_mean;
    };
  };
  // Strength on peak-only runs; with --energy, alternately G_f on full runs and strength again
  // (a lower G_f lowers the peak too), until one set of full runs meets both tolerances.
  constexpr int max_rounds = 4;
  const auto fit_strength = [&] {
    real s = f.s;
    int n = 0;
    const bool ok = secant_fit(s, f_t, in.tolerance, in.max_iterations, n, measure(false));
    f.strength_iterations += n;
    return ok;
  };
  f.converged = fit_strength();
  if (!in.energy || !f.converged) return f;
  for (int round = 1; round <= max_rounds; ++round) {
    real g = f.g;
    int n = 0;
    f.converged = secant_fit(g, g_f, in.energy_tolerance, in.max_iterations, n, measure(true));
    f.energy_iterations += n;
    if (!f.converged) return f;
    if (std::abs(f.peak_error) <= in.tolerance) return f;  // the last full runs meet both
    std::printf("calibrate: %d blocks: the fracture-energy scale moved the peak to %+.2f %%; strength again\n", blocks,
                100 * f.peak_error);
    f.converged = fit_strength();
    if (!f.converged) return f;
  }
  f.converged = false;
  f.energy_error = std::numeric_limits<double>::quiet_NaN();  // the last runs stopped at the peak: no energy figure
  return f;
}

void check_inputs(inputs& in) {
  tessera::require(in.recipe.material == "prism" || in.recipe.material == "beam", "calibrate: --material '",
                   in.recipe.material, "' must be 'prism' or 'beam'");
  in.block_counts = parse_block_counts(in.blocks, in.recipe.material);
  tessera::require(in.recipe.softening == "power" || in.recipe.softening == "linear", "calibrate: --softening '",
                   in.recipe.softening, "' must be 'power' or 'linear'");
  if (in.recipe.material == "beam") {
    // The recipe must be the law rc_beam runs: study_beam_params (linear softening, c_0 = 2 f_T)
    // on deformable blocks.
    tessera::require(in.recipe.softening == "linear", "calibrate: --material beam uses the beam's linear softening, got "
                     "--softening ", in.recipe.softening);
    tessera::require(!in.recipe.rigid, "calibrate: --material beam has deformable blocks (rc_beam has no rigid ones); "
                     "drop --rigid");
    tessera::require(in.recipe.cohesion_ratio == 2, "calibrate: --material beam: rc_beam's contacts have c_0 = 2 f_T, "
                     "got --cohesion-ratio ", in.recipe.cohesion_ratio);
  } else {
    tessera::require(in.recipe.zone_edge == 0, "calibrate: --zone-edge ", in.recipe.zone_edge,
                     " applies to --material beam only (the prism has one zone per face triangle)");
  }
  // The loading is checked quasi-static by run_direct_tension itself, before the first step.
}

void write_outputs(const fs::path& out, const inputs& in, const std::vector<fit_result>& fits,
                   const std::vector<fit_row>& rows, std::int64_t steps, const tessera::cli::wall_timer& timer) {
  namespace io = tessera::io;
  {
    io::csv_writer csv(out / "calibration.csv",
                       {"blocks", "energy_phase", "iteration", "strength_scale", "fracture_energy_scale", "peak_mean_Pa",
                        "peak_spread_rel", "dissipated_per_section_J_per_m2", "initial_modulus_mean_Pa", "wall_s"});
    for (const fit_row& r : rows)
      csv.row(r.blocks, r.phase == "energy" ? 1 : 0, r.iteration, r.s, r.g, r.e.peak_mean, r.e.peak_spread, r.e.energy_mean,
              r.e.modulus_mean, r.wall_s);
    csv.commit();
  }
  io::summary_json recipe;
  recipe.set("material", in.recipe.material)
      .set("softening", in.recipe.softening)
      .set("cohesion_ratio", in.recipe.cohesion_ratio)
      .set("step_displacement_m", in.recipe.step_displacement)
      .set("rate_m_per_s", in.recipe.rate)
      .set("rigid", in.recipe.rigid)
      .set("zone_edge_m", in.recipe.zone_edge)
      .set("beam_volume_m3", in.recipe.beam_volume);
  std::vector<io::summary_json> entries;
  io::summary_json summary;
  summary.set("program", "calibrate").set("quick", in.common.quick).set("seed", in.common.seed)
      .set("seeds", in.seeds).set("energy", in.energy).set("tolerance", in.tolerance)
      .set("energy_tolerance", in.energy_tolerance).set("softening", in.recipe.softening)
      .set("cohesion_ratio", in.recipe.cohesion_ratio).set("step_displacement_m", in.recipe.step_displacement)
      .set("rate_m_per_s", in.recipe.rate).set("rigid", in.recipe.rigid).set("material", in.recipe.material)
      .set("zone_edge_m", in.recipe.zone_edge);
  int converged = 0;
  double worst_peak = 0;
  for (const fit_result& f : fits) {
    std::vector<double> seeds;
    for (int k = 0; k < in.seeds; ++k) seeds.push_back(static_cast<double>(in.common.seed + static_cast<std::uint64_t>(k)));
    io::summary_json e;
    e.set("blocks", f.blocks).set("strength_scale", f.s).set("fracture_energy_scale", f.g).set("seeds", seeds)
        .set("strength_iterations", f.strength_iterations).set("energy_iterations", f.energy_iterations)
        .set("converged", f.converged).set("peak_mean_Pa", f.last.peak_mean).set("peak_error_rel", f.peak_error)
        .set("peak_spread_rel", f.last.peak_spread).set("peaks_Pa", f.last.peaks)
        .set("prism_blocks", f.prism_blocks).set("initial_modulus_mean_Pa", f.last.modulus_mean);
    if (in.energy) e.set("dissipated_per_section_J_per_m2", f.last.energy_mean).set("energy_error_rel", f.energy_error);
    scenes::concrete_set set;  // the whole concrete (law, c_0 / f_T, angles, cap), as calibrate --targets writes it
    set.material = in.recipe.material, set.recipe_blocks = f.blocks, set.strength_scale = f.s;
    set.fracture_energy_scale = f.g, set.cohesion_ratio = in.recipe.cohesion_ratio;
    scenes::set_concrete_fields(e, set);
    entries.push_back(e);
    const std::string b = "b" + std::to_string(f.blocks) + "_";
    summary.set(b + "strength_scale", f.s).set(b + "fracture_energy_scale", f.g)
        .set(b + "peak_error_rel", f.peak_error).set(b + "peak_spread_rel", f.last.peak_spread)
        .set(b + "iterations", f.strength_iterations + f.energy_iterations).set(b + "converged", f.converged)
        .set(b + "prism_blocks", f.prism_blocks).set(b + "initial_modulus_Pa", f.last.modulus_mean)
        .set(b + "damping_in_force", f.last.damping_in_force);
    if (in.energy) summary.set(b + "energy_error_rel", f.energy_error);
    converged += f.converged ? 1 : 0;
    worst_peak = std::max(worst_peak, std::abs(f.peak_error));
  }
  io::summary_json doc;
  doc.set("format", scenes::calibration_format).set("recipe", recipe).set("entries", entries);
  doc.write(out / "calibrated.json");
  summary.set("block_counts", static_cast<int>(fits.size())).set("converged_count", converged)
      .set("peak_error_rel_max_abs", worst_peak).set("steps", steps).set("runtime_s", timer.seconds());
  summary.write(out / "summary.json");
}

int run(inputs& in) {
  check_inputs(in);
  const fs::path out = in.common.out;
  const tessera::cli::wall_timer timer;
  std::vector<fit_result> fits;
  std::vector<fit_row> rows;
  std::int64_t steps = 0;
  for (const int blocks : in.block_counts) {
    const scenes::prism_scene reference = reference_prism(in, blocks);  // f_T, G_f of the concrete
    fits.push_back(fit_block_count(in, blocks, reference, rows, steps));
    fits.back().prism_blocks = static_cast<int>(reference.tess.cell_count());
    tessera::io::ensure_directory(out);  // after the first runs' own checks: bad input leaves no directory
  }
  write_outputs(out, in, fits, rows, steps, timer);
  for (const fit_result& f : fits)
    std::printf("calibrate: %s %d blocks: strength scale %.4f, fracture-energy scale %.4f, mean peak %+.2f %% of f_T "
                "(seed spread %.1f %%)%s, %s\n",
                in.recipe.material.c_str(), f.blocks, f.s, f.g, 100 * f.peak_error, 100 * f.last.peak_spread,
                in.energy ? tessera::detail::concat(", dissipated ", 100 * f.energy_error, " % from G_f").c_str() : "",
                f.converged ? "converged" : "NOT converged");
  std::printf("calibrate: %lld steps, runtime %.1f s; wrote %s\n", static_cast<long long>(steps), timer.seconds(),
              (out / "calibrated.json").string().c_str());
  for (const fit_result& f : fits)
    if (!f.converged) return 3;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)  // the multi-target fit (targets_run.hpp) has its own flags
    if (std::string(argv[i]) == "--targets") return tessera::scenes::run_targets_main(argc, argv);
  inputs in;
  tessera::cli::parser cli(
      "calibrate",
      "Fits the contact strength (and with --energy the contact fracture energy) of a prism in direct tension so that\n"
      "the mean peak over K seeds equals the concrete's f_T (and the dissipated energy G_f x section).\n"
      "--material prism: the study's prism (f_T = 2.15 MPa), for direct_tension/rc_tie --params; --material beam: the\n"
      "beam's concrete (f_T = 2.5 MPa, linear softening) on a 150 x 150 x 600 mm prism with the beam's block size,\n"
      "for rc_beam --params. Writes calibrated.json. Exit 3 if a block count did not converge.\n"
      "--quick: prism 100 blocks (beam: 60 blocks, 50 mm zoning, as rc_beam --quick), 1 seed, 5 nm per step.\n"
      "calibrate --targets LIST [...] fits one concrete to several targets (tension, energy, splitting, compression, shear);\n"
      "calibrate --targets tension --help lists its flags.");
  cli.add_standard(in.common);
  cli.option("--material", in.recipe.material, "prism: the study's prism concrete (for direct_tension, rc_tie); beam: the beam's concrete on a prism of the "
             "beam's block size (for rc_beam)", "prism|beam")
      .one_of({"prism", "beam"});
  cli.option("--blocks", in.blocks,
             "comma-separated block counts: prism 100, 250, 500 or 750; beam 250, 500 or 8..249 (with --material "
             "beam the default is 250,500)", "LIST");
  cli.option("--seeds", in.seeds,
             "seeds per block count (seed, seed+1, ...); the fit is on their mean (6 keeps unseen seeds within 5 % of f_T)",
             "K").within(1, 100);
  cli.flag("--energy", in.energy, "also fit the contact fracture energy (runs to separation: slower)");
  cli.option("--tolerance", in.tolerance, "convergence on the mean peak, |P/f_T - 1|", "T").within(1e-4, 0.2);
  cli.option("--energy-tolerance", in.energy_tolerance, "convergence on the mean dissipation, |D/G_f - 1|", "T")
      .within(1e-3, 0.5);
  cli.option("--max-iterations", in.max_iterations, "iterations per fit before giving up", "N").within(1, 50);
  cli.option("--softening", in.recipe.softening, "tensile softening of the recipe (beam: linear, the default there)",
             "power|linear").one_of({"power", "linear"});
  cli.option("--zone-edge", in.recipe.zone_edge,
             "beam only: target face edge of the zoning (m), as rc_beam --zone-edge; 0 = h/5 = 0.03", "M").within(0, 1);
  cli.option("--cohesion-ratio", in.recipe.cohesion_ratio, "c_0 / f_T of the recipe (the study: 2)", "R").greater_than(0);
  cli.option("--step-displacement", in.recipe.step_displacement, "top displacement per step (m) of the recipe", "DU")
      .greater_than(0);
  cli.option("--rate", in.recipe.rate, "top velocity (m/s) of the recipe", "V").greater_than(0);
  cli.flag("--rigid", in.recipe.rigid, "rigid blocks instead of deformable ones");
  cli.parse_or_exit(argc, argv);
  const bool beam = in.recipe.material == "beam";
  if (beam) {
    if (!cli.given("--blocks")) in.blocks = "250,500";
    if (!cli.given("--softening")) in.recipe.softening = "linear";
  }
  if (in.common.quick) {
    if (!cli.given("--blocks")) in.blocks = beam ? "60" : "100";
    if (beam && !cli.given("--zone-edge")) in.recipe.zone_edge = 0.05;  // rc_beam --quick's zoning
    if (!cli.given("--seeds")) in.seeds = 1;
    if (!cli.given("--step-displacement")) in.recipe.step_displacement = 5e-9;
  }
  // The beam's zoning in effect (rc_beam: 0 = h/5), recorded in the recipe and matched on loading.
  if (beam && in.recipe.zone_edge == 0) in.recipe.zone_edge = tessera::scenes::beam_options{}.face_zone_edge();
  if (beam) in.recipe.beam_volume = tessera::scenes::beam_options{}.half_volume();  // make_beam_prism's cell volume
  tessera::io::run_record record(in.common.out, "calibrate", argc, argv);
  try {
    const int status = run(in);
    if (status == 0 || status == 3) record.complete();  // 3: every file written, a fit short of its tolerance
    return status;
  } catch (const std::exception& e) {
    tessera::cli::print_error("calibrate", e);
    return 1;
  }
}
