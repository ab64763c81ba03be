#pragma once
// calibrate --targets: the flags, the fit (targets.hpp) and the outputs. Writes in --out:
//   calibrated.json  the recipe and one entry with the whole concrete (law, scales, c_0/f_T, phi_0,
//                    phi_res, cap; G_II with a law that takes it, its default written out; with --law
//                    crushing G_c, the residual cap, crush_shear), which brazilian, compression and
//                    rc_beam load with --params
//   residuals.csv    per target: reference (in the value's unit: Pa, J/m^2, 1, m/m; shear: the hand load
//                    in N), tolerance, weight, the fit seeds' value and residual, the held-out seeds'
//                    value, residual and met / not met
//   targets.csv      every evaluation of the search: the set, each target's value and residual, J, time
//   summary.json     flat: the fitted set, per target its reference and fit_/holdout_ value, residual, met, reached;
//                    the wall-clock seconds of one evaluation of each target (one seed; on a loaded
//                    host several times its CPU time), evaluations, refused_moves (moves the law
//                    refused, printed with its reason and not run), runtime

#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

#include "calibrate/targets.hpp"
#include "common/cli.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/run_record.hpp"

namespace tessera::scenes {

/// A --weights / --tolerances list aligned with --targets: one positive number per target.
[[nodiscard]] inline std::vector<real> target_numbers(const std::string& text, const char* flag, std::size_t count) {
  std::vector<real> v;
  for (std::size_t from = 0; from <= text.size();) {  // repeats are fine here (1,1,1), split_list refuses them
    const std::size_t comma = std::min(text.find(',', from), text.size());
    const std::string item = text.substr(from, comma - from);
    from = comma + 1;
    char* end = nullptr;
    const real x = std::strtod(item.c_str(), &end);
    require(*end == 0 && std::isfinite(x) && x > 0, "calibrate: ", flag, " '", text, "': '", item,
            "' is not a positive number");
    v.push_back(x);
  }
  require(v.size() == count, "calibrate: ", flag, " '", text, "' has ", v.size(), " values for ", count, " targets");
  return v;
}

/// The set's values as calibrated.json's entry fields (calibration.hpp file comment) on j.
inline void set_concrete_fields(io::summary_json& j, const concrete_set& c) {
  const real none = std::numeric_limits<real>::quiet_NaN();
  j.set("blocks", c.blocks()).set("strength_scale", c.scale()).set("fracture_energy_scale", c.fracture_energy_scale)
      .set("law", c.law).set("cohesion_ratio", c.cohesion_ratio).set("phi_0_deg", c.phi_0_deg)
      .set("phi_res_deg", c.phi_res_deg).set("G_II_J_per_m2", g_ii_in_effect(c))  // null for a law without G_II
      .set("cap_Pa", c.material == "beam" ? c.cap : none);
  if (law_in_file(c.law, law_g_c)) j.set("G_c_J_per_m2", c.g_c > 0 ? c.g_c : default_g_c);
  if (law_in_file(c.law, law_cap_residual)) j.set("cap_residual", c.cap_residual);
  if (law_in_file(c.law, law_crush_shear)) j.set("crush_shear", c.crush_shear);
}

inline void write_target_outputs(const std::filesystem::path& out, const targets_options& o, const evaluation& fit,
                                 const evaluation& held, const std::vector<evaluation>& trail, int refused_moves,
                                 double runtime_s) {
  const concrete_set& c = fit.set;
  {
    std::ofstream csv(out / "residuals.csv");  // a text column (the target), so not io::csv_writer
    csv << "target,reference,tolerance_rel,weight,fit_value,fit_residual,fit_met,holdout_value,holdout_residual,holdout_met,"
           "holdout_reached,holdout_runs\n";
    csv.precision(10);
    for (std::size_t i = 0; i < held.values.size(); ++i) {
      const target_value &f = fit.values[i], &h = held.values[i];
      csv << h.name << ',' << h.reference << ',' << h.tolerance << ',' << h.weight << ',' << f.value << ',' << f.residual()
          << ',' << (f.met() ? "met" : "not met") << ',' << h.value << ',' << h.residual() << ','
          << (h.met() ? "met" : "not met") << ',' << h.reached << ',' << h.runs << '\n';
    }
    require(static_cast<bool>(csv), "calibrate: cannot write ", (out / "residuals.csv").string());
  }
  {
    std::vector<std::string> head = {"evaluation", "strength_scale", "fracture_energy_scale", "cohesion_ratio", "phi_0_deg",
                                     "phi_res_deg", "G_II_J_per_m2", "cap_Pa", "G_c_J_per_m2"};
    for (const target_value& v : fit.values) head.push_back(v.name + "_value"), head.push_back(v.name + "_residual");
    head.push_back("objective");
    head.push_back("wall_s");
    io::csv_writer csv(out / "targets.csv", head);
    for (std::size_t k = 0; k < trail.size(); ++k) {
      const evaluation& e = trail[k];
      std::vector<double> row = {static_cast<double>(k), e.set.scale(), e.set.fracture_energy_scale, e.set.cohesion_ratio,
                                 e.set.phi_0_deg, e.set.phi_res_deg,
                                 law_takes(e.set.law, law_g_ii) ? g_ii_in_effect(e.set) : 0.0, e.set.cap,
                                 law_in_file(e.set.law, law_g_c) ? (e.set.g_c > 0 ? e.set.g_c : default_g_c) : 0.0};
      for (const target_value& v : e.values) row.push_back(v.value), row.push_back(v.residual());
      row.push_back(e.objective);
      row.push_back(e.cpu_s);
      csv.row(std::span<const double>(row));
    }
    csv.commit();
  }
  const calibration_recipe r = c.recipe(o.tension_step, o.tension_rate);
  io::summary_json recipe;
  recipe.set("material", r.material).set("softening", r.softening).set("cohesion_ratio", c.cohesion_ratio)
      .set("step_displacement_m", r.step_displacement).set("rate_m_per_s", r.rate).set("rigid", false)
      .set("zone_edge_m", r.zone_edge).set("beam_volume_m3", r.beam_volume);
  io::summary_json entry, summary;
  set_concrete_fields(entry, c);
  std::vector<double> fit_seeds, held_seeds;
  for (int k = 0; k < o.seeds; ++k) fit_seeds.push_back(static_cast<double>(o.seed + static_cast<std::uint64_t>(k)));
  for (int k = 0; k < o.holdout; ++k) held_seeds.push_back(static_cast<double>(o.seed + static_cast<std::uint64_t>(o.seeds + k)));
  entry.set("seeds", fit_seeds).set("holdout_seeds", held_seeds).set("objective", fit.objective)
      .set("holdout_objective", held.objective);
  int met = 0;
  std::string targets;
  for (const target_spec& t : o.targets) targets += (targets.empty() ? "" : ",") + t.name;
  summary.set("program", "calibrate").set("mode", "targets").set("material", c.material).set("targets", targets)
      .set("quick", o.quick).set("seed", static_cast<std::int64_t>(o.seed)).set("seeds", o.seeds)
      .set("holdout", o.holdout).set("iterations", o.iterations).set("evaluations", static_cast<int>(trail.size()))
      .set("refused_moves", refused_moves).set("objective", fit.objective).set("holdout_objective", held.objective);
  set_concrete_fields(summary, c);
  for (std::size_t i = 0; i < held.values.size(); ++i) {
    const target_value &f = fit.values[i], &h = held.values[i];
    for (const auto& [tag, v] : {std::pair{"fit_", &f}, std::pair{"holdout_", &h}}) {
      const std::string k = tag + v->name;
      summary.set(k + "_value", v->value).set(k + "_residual", v->residual()).set(k + "_met", v->met())
          .set(k + "_reached", v->reached);
      entry.set(k + "_value", v->value).set(k + "_met", v->met());
    }
    summary.set(h.name + "_reference", h.reference);
    met += h.met() ? 1 : 0;
  }
  for (std::size_t i = 0; i < o.targets.size() && i < trail.front().seconds.size(); ++i)
    summary.set("wall_s_" + o.targets[i].name + "_per_seed", trail.front().seconds[i] / o.seeds);
  summary.set("disc_blocks", o.disc.blocks).set("disc_diameter_m", o.disc.diameter).set("disc_step_m", o.disc.step_displacement)
      .set("compression_blocks", o.compression.blocks).set("compression_step_m", o.compression.step_displacement)
      .set("shear_blocks", o.shear.blocks).set("shear_zone_edge_m", o.shear.zone_edge).set("shear_rate_m_per_s", o.shear.rate)
      .set("shear_max_deflection_m", o.shear.max_deflection)
      .set("shear_failure_crack", std::string(o.shear.failure_needs_diagonal ? "diagonal" : "any"))
      .set("holdout_met_count", met).set("residual_count", static_cast<int>(held.values.size()))
      .set("runtime_s", runtime_s);
  summary.write(out / "summary.json");
  io::summary_json doc;
  doc.set("format", calibration_format).set("recipe", recipe).set("entries", std::vector<io::summary_json>{entry});
  doc.write(out / "calibrated.json");
}

/// calibrate --targets ... (the driver's main for this mode).
inline int run_targets_main(int argc, char** argv) {
  targets_options o;
  cli::standard_options common;
  std::string targets, weights, tolerances, fit = "strength";
  concrete_set& c = o.start;
  c.material = "beam";
  cli::parser cli("calibrate", "calibrate --targets: fits ONE concrete of a recipe (--material, --blocks, --zone-edge) to several\n"
                  "targets at once (calibrate/targets.hpp): tension f_t, energy G_f, splitting f_sp/f_T in [1.0, 1.4], compression\n"
                  "f_c and its peak strain, shear (rc_beam with bars that cannot yield: P at failure over the mean of EC2's and\n"
                  "Zsutty's 2 V_c, --material beam; about 100 s of CPU a seed), by compass search on the weighted squared residuals over the fit seeds, and reports\n"
                  "every residual on held-out seeds. Writes calibrated.json (brazilian, compression, rc_beam --params), residuals.csv,\n"
                  "targets.csv, summary.json. --quick: the beam recipe of calibrate --quick (60 blocks, 50 mm zoning), a 12-block\n"
                  "disc, a 23-block 100 x 100 x 200 mm prism, 1 seed, 1 held\n"
                  "out, 1 iteration, 5 nm per step (4 nm in compression); the shear beam keeps its --shear-* flags.\n"
                  "--law: every law of common/concrete_laws.hpp; the file holds the G_II (and G_c) the fit ran, its default\n"
                  "written out (a mixed_mode entry without G_II is refused on loading). --fit gii moves G_II (slip_softening,\n"
                  "crushing, mixed_mode) against the targets given; with shear, the figure it mostly sets.");
  cli.add_standard(common);
  cli.option("--targets", targets, "comma-separated: tension, energy, splitting, compression, shear", "LIST");
  cli.option("--weights", weights, "one weight per target (default 1 each)", "LIST");
  cli.option("--tolerances", tolerances, "one relative tolerance per target (default 0.05, 0.15, 1/6, 0.15, 0.2)", "LIST");
  cli.option("--fit", fit, fit_flag_help(), "LIST");
  cli.option("--material", c.material, "the recipe's concrete", "prism|beam").one_of({"prism", "beam"});
  cli.option("--blocks", c.recipe_blocks, "the recipe's block count (0: prism 100, beam 250)", "N").within(0, 750);
  cli.option("--zone-edge", c.zone_edge, "beam: the recipe's face zoning edge (m; default 0.03)", "M").within(0, 1);
  cli.option("--law", c.law, tessera::detail::concat("the contact law (all but study: --material beam only); ", law_flag_help()),
             "L").one_of(calibrated_law_names());
  cli.option("--strength-scale", c.strength_scale, "start: contact f_T and c_0 x this (default prism 0.907, beam 1)", "S").within(0.1, 10);
  cli.option("--energy-scale", c.fracture_energy_scale, "start: contact G_f x this", "G").within(0.1, 10);
  cli.option("--cohesion-ratio", c.cohesion_ratio, "start: c_0 / f_T", "R").within(0.3, 10);
  cli.option("--phi-deg", c.phi_0_deg, "start: phi_0 (deg)", "DEG").within(10, 75);
  cli.option("--phi-res-deg", c.phi_res_deg, "start: phi_res (deg)", "DEG").within(0, 75);
  cli.option("--g-ii", c.g_ii, "start: " + g_ii_flag_help(), "J").within(0, 1e5);
  cli.option("--g-c", c.g_c, "start: " + g_c_flag_help(), "J").within(0, 1e8);
  cli.option("--cap-residual", c.cap_residual, cap_residual_flag_help() + "; not fitted", "R").within(0, 1);
  cli.flag("--crush-shear", c.crush_shear, crush_shear_flag_help());
  cli.option("--cap", c.cap, "start: contact compressive cap (Pa, beam)", "PA").within(5e6, 1e9);
  cli.option("--seeds", o.seeds, "fit seeds (seed .. seed+K-1)", "K").within(1, 50);
  cli.option("--holdout", o.holdout, "held-out seeds after the fit seeds", "K").within(1, 50);
  cli.option("--iterations", o.iterations, "compass-search iterations", "N").within(0, 50);
  cli.option("--step", o.step, "initial relative step h", "H").within(0.01, 1);
  cli.option("--f-c", o.f_c, "the compression target (Pa)", "PA").within(1e6, 1e9);
  cli.option("--disc-diameter", o.disc.diameter, "disc diameter (m), as brazilian --diameter", "M").within(0.02, 2);
  cli.option("--disc-thickness", o.disc.thickness, "disc thickness (m)", "M").within(0.005, 2);
  cli.option("--disc-blocks", o.disc.blocks, "disc blocks (0: the recipe's block size)", "N").within(0, 2000);
  cli.option("--disc-max-displacement", o.disc.max_displacement, "the disc's last strip travel (m)", "M").within(1e-6, 0.01);
  cli.option("--compression-shape", o.compression.shape, "cylinder or prism", "S").one_of({"cylinder", "prism"});
  cli.option("--compression-diameter", o.compression.width, "diameter or side (m)", "M").within(0.02, 2);
  cli.option("--compression-height", o.compression.height, "height (m)", "M").within(0.02, 4);
  cli.option("--compression-blocks", o.compression.blocks, "blocks (0: the recipe's block size)", "N").within(0, 5000);
  cli.option("--compression-max-strain", o.compression.max_strain, "strain at which a run without a peak ends", "EPS").within(1e-4, 0.05);
  cli.option("--shear-blocks", o.shear.blocks, "shear: blocks of the half beam (rc_beam --blocks)", "N").within(8, 500);
  cli.option("--shear-max-deflection", o.shear.max_deflection, "shear: the last mid-span deflection (m); a beam that "
             "has not failed by here has not reached its event", "U").within(1e-4, 0.05);
  std::string shear_failure_crack = "any";
  cli.option("--shear-failure-crack", shear_failure_crack, "shear: any (every 25 % drop is the failure) or diagonal "
             "(only a drop as a shear crack or band breaks: rc_beam --failure-crack)", "any|diagonal").one_of({"any", "diagonal"});
  cli.option("--step-displacement", o.tension_step, "travel per step (m) of every scene", "DU").within(1e-10, 1e-7);
  cli.parse_or_exit(argc, argv);
  o.shear.failure_needs_diagonal = shear_failure_crack == "diagonal";
  o.quick = common.quick;
  if (common.quick) {
    if (!cli.given("--seeds")) o.seeds = 1;
    if (!cli.given("--iterations")) o.iterations = 1;
    if (!cli.given("--step-displacement")) o.tension_step = 5e-9;
    if (!cli.given("--blocks")) c.recipe_blocks = c.material == "beam" ? 60 : 100;  // calibrate --quick's recipe
    if (!cli.given("--zone-edge") && c.material == "beam") c.zone_edge = 0.05;
    if (!cli.given("--disc-blocks")) o.disc.blocks = 12;
    if (!cli.given("--compression-shape")) o.compression.shape = "prism";
    if (!cli.given("--compression-diameter")) o.compression.width = 0.1;
    if (!cli.given("--compression-height")) o.compression.height = 0.2;
    if (!cli.given("--compression-blocks")) o.compression.blocks = 23;
  }
  o.disc.step_displacement = o.tension_step;
  // the compression specimen's own quasi-static check wants a finer step than 5 nm on some seeds
  o.compression.step_displacement = std::min(o.tension_step, 4e-9);
  o.compression.no_vtk = true;
  o.compression.common.quick = true;  // no progress line
  o.compression.drop = 0.1;
  o.threads = common.threads;
  o.shear.threads = common.threads;
  o.compression.common.threads = common.threads;
  o.seed = common.seed;
  try {
    require(!targets.empty(), "calibrate: --targets is empty");
    for (const std::string& t : cli::split_list(targets, "calibrate: --targets")) o.targets.push_back({t, 1, default_tolerance(t)});
    if (!weights.empty()) {
      const auto w = target_numbers(weights, "--weights", o.targets.size());
      for (std::size_t i = 0; i < w.size(); ++i) o.targets[i].weight = w[i];
    }
    if (!tolerances.empty()) {
      const auto t = target_numbers(tolerances, "--tolerances", o.targets.size());
      for (std::size_t i = 0; i < t.size(); ++i) o.targets[i].tolerance = t[i];
    }
    o.fit = cli::split_list(fit, "calibrate: --fit");
    for (const std::string& p : o.fit) {
      (void)fit_parameter_named(p);
      require_law_fits(c.law, p);
      require(p != "cap" || c.material == "beam", "calibrate: --fit cap needs --material beam (the prism's contacts have no cap)");
    }
    require(c.material == "beam" || !has_target(o, "shear"), "calibrate: --targets shear needs --material beam (rc_beam "
            "runs the beam's concrete, linear softening with a compressive cap; the prism's concrete, --material ", c.material,
            ", is the study's prism law, which the beam does not take)");
    require(c.material == "beam" || !cli.given("--zone-edge"), "calibrate: --zone-edge ", c.zone_edge,
            " applies to --material beam only (the prism's recipe has one zone per face triangle)");
    require(!concrete_law_named(c.law, "calibrate").beam_only || c.material == "beam", "calibrate: --law ", c.law,
            " applies to --material beam only");
    require_g_ii_with_law("calibrate", c.law, c.g_ii);
    for (const law_parameter_row& r : law_parameter_rows)  // what calibrated.json carries for the law
      require(r.id == law_g_ii || !cli.given(r.flag) || law_in_file(c.law, r.id), "calibrate: ", r.flag,
              " applies to --law ", laws_in_file_taking(r.id), " only (--law ", c.law, " has no ", r.symbol,
              " in calibrated.json)");
    require(c.phi_res_deg <= c.phi_0_deg, "calibrate: --phi-res-deg ", c.phi_res_deg, " must not exceed --phi-deg ", c.phi_0_deg);
    require_targets_accept(o, c);  // refuses a bad start before any run
  } catch (const std::exception& e) {
    cli::print_error("calibrate", e);
    return 2;
  }
  const std::filesystem::path out = common.out;
  o.compression.common.out = (out / "scratch").string();  // the specimen's curve.csv (overwritten each run)
  io::run_record record(common.out, "calibrate", argc, argv);
  try {
    const cli::wall_timer timer;
    std::vector<evaluation> trail;
    const auto log = [&](const evaluation& e, int it, const std::string& move) {
      trail.push_back(e);
      std::printf("calibrate: iteration %d (%s): s %.4f, g %.3f, c0/fT %.3f, phi %.1f/%.1f%s, J %.3f [", it, move.c_str(),
                  e.set.scale(), e.set.fracture_energy_scale, e.set.cohesion_ratio, e.set.phi_0_deg, e.set.phi_res_deg,
                  law_takes(e.set.law, law_g_ii) ? tessera::detail::concat(", G_II ", g_ii_in_effect(e.set)).c_str() : "",
                  e.objective);
      for (const target_value& v : e.values) std::printf(" %s %.4g (r %+.2f)", v.name.c_str(), v.value, v.residual());
      std::printf(" ] %.1f s\n", e.cpu_s);
      std::fflush(stdout);
    };
    int refused = 0;
    const auto skipped = [&](int it, const std::string& move, const std::string& why) {
      ++refused;
      std::printf("calibrate: iteration %d (%s): not run, the law refuses it: %s\n", it, move.c_str(), why.c_str());
      std::fflush(stdout);
    };
    io::ensure_directory(out);
    const evaluation best = fit_targets(o, log, skipped);
    const evaluation held = evaluate_targets(o, best.set, o.seed + static_cast<std::uint64_t>(o.seeds), o.holdout);
    write_target_outputs(out, o, best, held, trail, refused, timer.seconds());
    std::printf("calibrate: held-out seeds:");
    for (const target_value& v : held.values)
      std::printf(" %s %.4g (residual %+.2f, %s)", v.name.c_str(), v.value, v.residual(),
                  v.met() ? "met" : v.reached < v.runs ? "NOT met: event not reached" : "NOT met");
    std::printf("; %zu evaluations, %.1f s; wrote %s\n", trail.size(), timer.seconds(), (out / "calibrated.json").string().c_str());
    record.complete();
    return 0;
  } catch (const std::exception& e) {
    cli::print_error("calibrate", e);
    return 1;
  }
}

}  // namespace tessera::scenes
