// brazilian: Brazilian splitting test of a concrete disc of random Voronoi blocks (public API only).
// A disc D x t (150 x 60 mm, axis z) as a 36-gon prism with flats at y = +-a, the loading strips
// 2 (D/2) sin(pi/36) = 13.1 mm = D/11.5 wide (EN 12390-6: 10 mm = D/15). --material names the concrete,
// a recipe of examples/calibrate (common/scenes.hpp concrete_recipe): its contact law and parameters, its
// mean block size and face zoning, its blocks' material. prism (the default): the study's prism concrete,
// the 100-block Table 1 contacts with f_T, c_0, c_res times --strength-scale (0.907: the calibrated
// 100-block prism peaks at f_T = 2.15 MPa), at the prism's block size (38 blocks in the disc), one zone per
// face triangle; beam: rc_beam's concrete (study_beam_params: linear softening, the 35 MPa cap; strength
// scale 1, the study verbatim as rc_beam runs it), at the 250-block beam's block size (12 blocks in the
// disc), faces zoned to 30 mm. Bottom strip fixed, top strip pushed down at 5 mm/s, 2 nm per step. P_max:
// the largest top reaction before the disc splits; f_sp = 2 P_max / (pi D t) against the concrete's f_T
// (EC2: 1/0.9 = 1.11), only for a disc that split: one that has not split by --max-displacement reports
// "split": false and no f_sp (its largest load is the wedges' under the strips). curve.csv also has the
// opening across the loaded diameter (the flats x = +-a over the middle third); summary.json the load and
// opening when the split is found. --law (beam only): study (study_beam_law), slip_softening
// (slip_softening_beam_law: c_0 and phi_0 soften with the plastic slip to c_res and --phi-res-deg over
// the mode-II fracture energy --g-ii), crushing (crushing_beam_law: slip_softening whose cap --cap softens
// with the plastic closure to --cap-residual x --cap over the compressive fracture energy --g-c;
// --crush-shear: the shear limit falls with it), as compression, or mixed_mode
// (presets::mixed_mode_beam_law: one damage for tension and shear over G_f and --g-ii); --cap (beam):
// the contacts' compressive cap (35 MPa).
// --params FILE: the concrete of a calibrated.json
// entry (calibrate; common/concrete_set.hpp), its law, scales, c_0/f_T, phi_0, phi_res, G_II and cap,
// for the recipe named by --material, --recipe-blocks and --zone-edge (refused, naming both values, if
// the file's differs). The disc itself is disc.hpp (calibrate --targets splitting runs it). Writes
// run.json, curve.csv, summary.json.
#include <tessera/io/csv.hpp>
#include <tessera/io/json.hpp>
#include <tessera/io/run_record.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "brazilian/disc.hpp"
#include "common/cli.hpp"
#include "common/concrete_set.hpp"

using namespace tessera;

namespace {

// The flags (main's --help), SI units. blocks 0: the recipe's block size; scale NaN: the recipe's default.
struct disc_flags {
  std::string out = "results/brazilian", material = "prism", law = "study", params;
  bool quick = false;
  real seed = 1, threads = 0, n_blocks = 0, sides = 36, diameter = 0.15, thickness = 0.06;
  real scale = std::numeric_limits<real>::quiet_NaN();
  real rate = 5e-3, du = 2e-9, u_max = 3e-4;  // m/s, strip displacement per step (m), last displacement (m)
  real cohesion_ratio = 2, phi_deg = 35;       // c_0 / f_T and phi_0 (deg) of the contacts (the study's)
  real phi_res_deg = 30;                       // phi_res (deg; the recipes' 30)
  real g_ii = 0;  // mode-II fracture energy with --law slip_softening (J/m^2); 0: scenes::default_g_ii
  real recipe_blocks = 0, zone_edge = -1;  // the recipe's block count (0: prism 100, beam 250); beam zoning (m, <0: 0.03)
  real cap = 35e6;  // the beam's contact compressive cap (Pa)
  real g_c = 0, cap_residual = 0.1;  // G_c (J/m^2; scenes::g_c_in_effect), residual cap / cap
  bool crush_shear = false;          // --law crushing: the shear limit times the cap's remaining fraction
};

template <class joint_law>
int run_disc(const disc_flags& o, const scenes::concrete_set& set, const scenes::concrete_recipe<joint_law>& recipe,
             io::run_record& record);

}  // namespace

int main(int argc, char** argv) {
  disc_flags o;
  auto& [out, material, law, params, quick, seed, threads, n_blocks, sides, diameter, thickness, scale, rate, du, u_max,
         cohesion_ratio, phi_deg, phi_res_deg, g_ii, recipe_blocks, zone_edge, cap, g_c, cap_residual, crush_shear] = o;
  struct flag { const char* name; real* value; real lo, hi; bool integer; };  // a number flag and its range
  const flag flags[] = {{"--seed", &seed, 1, 1e9, true}, {"--threads", &threads, 0, 256, true},
      {"--blocks", &n_blocks, 0, 2000, true}, {"--sides", &sides, 8, 360, true}, {"--diameter", &diameter, 0.02, 2, false},
      {"--thickness", &thickness, 0.005, 2, false}, {"--strength-scale", &scale, 0.1, 10, false},
      {"--rate", &rate, 1e-5, 0.1, false}, {"--step-displacement", &du, 1e-10, 1e-7, false},
      {"--max-displacement", &u_max, 1e-6, 0.01, false},
      {"--cohesion-ratio", &cohesion_ratio, scenes::min_cohesion_ratio, scenes::max_cohesion_ratio, false},
      {"--phi-deg", &phi_deg, 0, 80, false}, {"--phi-res-deg", &phi_res_deg, 0, 80, false}, {"--g-ii", &g_ii, 0, 1e6, false},
      {"--recipe-blocks", &recipe_blocks, 0, 750, true}, {"--zone-edge", &zone_edge, 0, 1, false}, {"--cap", &cap, 1e6, 1e10, false},
      {"--g-c", &g_c, 0, 1e8, false}, {"--cap-residual", &cap_residual, 0, 1, false}};
  std::vector<std::string> concrete_flags;  // flags --params replaces
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const flag* f = std::find_if(std::begin(flags), std::end(flags), [&](const flag& g) { return a == g.name; });
    if (a == "--help") {
      std::puts("brazilian [--out DIR] [--quick] [--material prism|beam] [--seed 1..1e9] [--threads 0..256]\n"
                "  [--blocks 0..2000] [--diameter 0.02..2 m] [--thickness 0.005..2 m] [--sides 8..360, a multiple of 4]\n"
                "  [--strength-scale 0.1..10] [--rate 1e-5..0.1 m/s] [--step-displacement 1e-10..1e-7 m]\n"
                "  [--max-displacement 1e-6..0.01 m] [--cohesion-ratio c_0/f_T 0.1..20] [--phi-deg phi_0 0..80]\n"
                "  [--phi-res-deg phi_res 0..80, the recipe's 30] [--law L, a law below]\n"
                "  [--g-ii 0..1e6 J/m^2] [--g-c 0..1e8 J/m^2] [--cap-residual 0..1] [--crush-shear]\n"
                "  [--recipe-blocks 0 or 8..750] [--zone-edge 0..1 m] [--cap 1e6..1e10 Pa, beam: 35e6] [--params FILE]:\n"
                "  f_sp = 2 P_max / (pi D t) against the concrete's f_T, null for a disc not split by --max-displacement.\n"
                "  --material: the concrete of examples/calibrate --material, its law, parameters, block size and zoning:\n"
                "  prism (default; the study's prism, f_T 2.15 MPa, strength scale 0.907, 38 blocks in the default disc)\n"
                "  or beam (rc_beam's, f_T 2.5 MPa, linear softening, 35 MPa cap, strength scale 1, 12 blocks, 30 mm\n"
                "  face zoning). --recipe-blocks: the recipe's block count (calibrate --blocks; 0 = prism 100, beam 250):\n"
                "  its contacts and block size; --zone-edge (beam): its face zoning (0 = 0.03 m). --params FILE: the\n"
                "  concrete of calibrate's calibrated.json for that recipe (law, scales, c_0/f_T, phi_0, phi_res, G_II,\n"
                "  cap, G_c, residual cap), instead of --strength-scale, --cohesion-ratio, --phi-deg, --phi-res-deg, --law,\n"
                "  --g-ii, --cap, --g-c, --cap-residual and --crush-shear.\n"
                "  --blocks 0: the material's block size. --quick: 5 nm per step.");
      std::printf("  --law: %s; every law but study: --material beam only.\n  --g-ii: %s.\n  --g-c: %s.\n  --cap-residual: %s.\n"
                  "  --crush-shear: %s.\n", scenes::law_flag_help().c_str(), scenes::g_ii_flag_help().c_str(),
                  scenes::g_c_flag_help().c_str(), scenes::cap_residual_flag_help().c_str(),
                  scenes::crush_shear_flag_help().c_str());
      return 0;
    } else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--material" && i + 1 < argc) material = argv[++i];
    else if (a == "--law" && i + 1 < argc) law = argv[++i], concrete_flags.push_back(a);
    else if (a == "--params" && i + 1 < argc) params = argv[++i];
    else if (a == "--quick") quick = true;
    else if (a == "--crush-shear") crush_shear = true, concrete_flags.push_back(a);
    else if (f != std::end(flags)) {
      const char* v = i + 1 < argc ? argv[++i] : "";
      char* end = nullptr;
      const real x = std::strtod(v, &end);
      if (*v == 0 || *end != 0 || !(x >= f->lo && x <= f->hi) || (f->integer && x != std::floor(x)))
        return std::fprintf(stderr, "brazilian: %s = '%s' must be %s in [%g, %g]\n", f->name, v,
                            f->integer ? "an integer" : "a number", f->lo, f->hi), 2;
      *f->value = x;
      if (f->value == &scale || f->value == &cohesion_ratio || f->value == &phi_deg || f->value == &phi_res_deg || f->value == &g_ii ||
          f->value == &cap || f->value == &g_c || f->value == &cap_residual)
        concrete_flags.push_back(a);
    } else return std::fprintf(stderr, "brazilian: unknown or incomplete argument '%s' (see --help)\n", a.c_str()), 2;
  }
  if (material != "prism" && material != "beam")
    return std::fprintf(stderr, "brazilian: --material '%s' is not a concrete recipe (expected prism or beam)\n",
                        material.c_str()), 2;
  const scenes::concrete_law* law_row = scenes::find_concrete_law(law);
  if (law_row == nullptr)
    return std::fprintf(stderr, "brazilian: --law: invalid value '%s' (expected %s)\n", law.c_str(),
                        scenes::concrete_law_list().c_str()), 2;
  const auto given = [&](const char* flag) {
    return std::find(concrete_flags.begin(), concrete_flags.end(), flag) != concrete_flags.end();
  };
  try {
    scenes::require_law_parameters("brazilian", law, g_c, given);
    scenes::require_g_ii_with_law("brazilian", law, g_ii);
    scenes::require_recipe_blocks("brazilian", static_cast<int>(recipe_blocks));
  } catch (const std::exception& e) {
    cli::print_error("brazilian", e);
    return 2;
  }
  if (material == "prism" && law_row->beam_only)
    return std::fprintf(stderr, "brazilian: --law %s applies to --material beam only (the prism's concrete has the study's law)\n",
                        law.c_str()), 2;
  if (material == "prism" && given("--cap"))
    return std::fprintf(stderr, "brazilian: --cap %g applies to --material beam only (the prism's contacts have no cap)\n", cap), 2;
  if (material == "prism" && zone_edge >= 0)
    return std::fprintf(stderr, "brazilian: --zone-edge %g applies to --material beam only (the prism's recipe has one "
                        "zone per face triangle)\n", zone_edge), 2;
  if (!params.empty() && !concrete_flags.empty())
    return std::fprintf(stderr, "brazilian: %s with --params %s: the file sets the concrete (drop the flag)\n",
                        concrete_flags.front().c_str(), params.c_str()), 2;
  if (static_cast<int>(sides) % 4 != 0)  // a flat at the top and at the bottom needs sides = 4k
    return std::fprintf(stderr, "brazilian: --sides = %g must be a multiple of 4 (flats at top and bottom)\n", sides), 2;
  if (quick) du = std::max<real>(du, 5e-9);
  if (n_blocks == 1) return std::fprintf(stderr, "brazilian: --blocks = 1 must be 0 (the material's block size) or >= 2\n"), 2;
  if (threads > 0) set_threads(static_cast<int>(threads));
  scenes::concrete_set set;
  set.material = material, set.recipe_blocks = static_cast<int>(recipe_blocks), set.zone_edge = zone_edge;
  set.law = law, set.strength_scale = scale, set.cohesion_ratio = cohesion_ratio, set.phi_0_deg = phi_deg;
  set.phi_res_deg = phi_res_deg, set.g_ii = g_ii, set.cap = cap;
  set.g_c = g_c, set.cap_residual = cap_residual, set.crush_shear = crush_shear;
  try {
    if (!params.empty()) scenes::load_concrete_params(set, params, du, rate, "brazilian");
    require(set.phi_res_deg <= set.phi_0_deg, "brazilian: --phi-deg ", set.phi_0_deg, " must not be below the residual ",
            set.phi_res_deg, " deg");
  } catch (const std::exception& e) {
    cli::print_error("brazilian", e);
    return 2;
  }
  io::run_record record(out, "brazilian", argc, argv);
  try {
    return scenes::with_concrete(set, [&](const auto& recipe) { return run_disc(o, set, recipe, record); });
  } catch (const std::exception& e) {
    cli::print_error("brazilian", e);  // one "brazilian: " before the message
    return 1;
  }
}

namespace {

template <class joint_law>
int run_disc(const disc_flags& o, const scenes::concrete_set& set, const scenes::concrete_recipe<joint_law>& recipe,
             io::run_record& record) {
  scenes::disc_options d;
  d.seed = static_cast<std::uint64_t>(o.seed), d.blocks = static_cast<int>(o.n_blocks), d.sides = static_cast<int>(o.sides);
  d.diameter = o.diameter, d.thickness = o.thickness, d.rate = o.rate, d.step_displacement = o.du, d.max_displacement = o.u_max;
  io::ensure_directory(o.out);  // run.json "running"
  const scenes::disc_result r = scenes::run_brazilian_disc(d, recipe);
  const real none = std::numeric_limits<real>::quiet_NaN(), f_t = r.f_t;
  const real g_ii = scenes::g_ii_in_effect(set);  // NaN for a law without G_II
  const real g_c_used = scenes::g_c_in_effect(set);  // NaN for a cap that does not soften
  const bool crush = !std::isnan(g_c_used);
  const std::filesystem::path out(o.out);
  io::write_csv(out / "curve.csv", {"u_m", "P_top_N", "P_bottom_N", "opening_m"}, {r.u, r.p_top, r.p_bottom, r.opening});
  io::summary_json j;
  j.set("example", "brazilian").set("material", set.material).set("law", set.law).set("g_ii_J_per_m2", g_ii)
      .set("G_c_J_per_m2", g_c_used).set("cap_residual", crush ? set.cap_residual : none)
      .set("crush_shear", crush && set.crush_shear)
      .set("params", o.params.empty() ? "flags" : o.params).set("recipe_blocks", set.blocks())
      .set("fracture_energy_scale", set.fracture_energy_scale).set("cap_Pa", set.material == "beam" ? set.cap : none)
      .set("phi_res_deg", r.phi_res_deg).set("quick", o.quick).set("seed", o.seed).set("blocks", r.blocks).set("sides", o.sides)
      .set("zone_edge_m", recipe.zone_edge).set("diameter_m", o.diameter).set("thickness_m", o.thickness).set("strip_over_diameter", r.strip / o.diameter)
      .set("strength_scale", set.scale()).set("cohesion_ratio", set.cohesion_ratio).set("phi_0_deg", set.phi_0_deg).set("rate_m_per_s", o.rate)
      .set("dt_s", r.dt).set("steps", r.steps).set("damping_in_force", r.damping)
      .set("peak_load_N", r.split ? r.p_max : none).set("largest_load_N", r.p_max).set("peak_displacement_m", r.u_peak)
      .set("split", r.split).set("split_by_hinge", r.split_by_hinge).set("split_displacement_m", r.split ? r.u_split : none).set("split_load_N", r.split ? r.p_split : none)
      .set("opening_at_split_m", r.split ? r.w_split : none).set("opening_at_end_m", r.opening_end)
      .set("crack_opening_load_N", r.p_crack).set("crack_opening_m", r.w_crack).set("f_sp_crack_opening_Pa", r.f_crack)
      .set("f_sp_crack_opening_over_f_T", r.f_crack / f_t)
      .set("bottom_over_top_at_peak_rel", r.mismatch).set("f_sp_Pa", r.f_sp).set("f_T_Pa", f_t).set("f_sp_over_f_T", r.ratio())
      .set("ec2_ratio", 1 / 0.9).set("cracked_area_over_diametral", r.cracked / (o.diameter * o.thickness))
      .set("crack_near_diameter_share", r.cracked > 0 ? r.near / r.cracked : 0.0).set("energy_balance_error_rel", r.energy_error)
      .set("threads", max_threads()).set("runtime_s", r.runtime_s);
  j.write(out / "summary.json");
  record.complete();
  const char *m = set.material.c_str(), *l = set.law.c_str();
  char at_opening[48] = "no crack opening measured";  // f_sp_crack_opening_Pa null
  if (std::isfinite(r.f_crack)) std::snprintf(at_opening, sizeof at_opening, "at the crack's opening %.3f f_T", r.f_crack / f_t);
  if (r.split)
    std::printf("brazilian: %s concrete (%s law), %d blocks, seed %d, P_max %.2f kN at %.1f um (split%s at %.1f um, %.2f kN, opening %.2f um), f_sp %.3f MPa = "
                "%.3f f_T (EC2 1.11; %s), bottom/top %+.2f %%, crack near the diameter %.0f %%, energy error %.1e, %.1f s\n",
                m, l, r.blocks, static_cast<int>(o.seed), r.p_max * 1e-3, r.u_peak * 1e6,
                r.split_by_hinge ? " in the middle third, the load past its peak," : "", r.u_split * 1e6, r.p_split * 1e-3, r.w_split * 1e6,
                r.f_sp * 1e-6, r.ratio(), at_opening, 100 * r.mismatch, 100 * (r.cracked > 0 ? r.near / r.cracked : 0.0),
                r.energy_error, r.runtime_s);
  else
    std::printf("brazilian: %s concrete (%s law), %d blocks, seed %d did NOT split by --max-displacement %.1f um: no f_sp (the largest load, %.2f kN, is "
                "the load at that displacement, not a splitting strength); %.1f s\n",
                m, l, r.blocks, static_cast<int>(o.seed), o.u_max * 1e6, r.p_max * 1e-3, r.runtime_s);
  return 0;
}

}  // namespace
