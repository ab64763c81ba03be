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
// opening when the split is found. --law (beam only): study (study_beam_law) or slip_softening
// (slip_softening_beam_law: c_0 and phi_0 soften with the plastic slip to c_res and --phi-res-deg over
// the mode-II fracture energy --g-ii), as compression. Writes run.json, curve.csv, summary.json.
#include <tessera/core/parallel.hpp>
#include <tessera/geometry/shapes.hpp>
#include <tessera/geometry/voronoi.hpp>
#include <tessera/geometry/zoning.hpp>
#include <tessera/io/csv.hpp>
#include <tessera/io/json.hpp>
#include <tessera/io/run_record.hpp>
#include <tessera/presets/pulatsu2020.hpp>
#include <tessera/solver/recorders.hpp>
#include <tessera/solver/solver.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "common/cli.hpp"
#include "common/scenes.hpp"
#include "rc_beam/beam.hpp"

using namespace tessera;

namespace {

// The flags (main's --help), SI units. blocks 0: the recipe's block size; scale NaN: the recipe's default.
struct disc_options {
  std::string out = "results/brazilian", material = "prism", law = "study";
  bool quick = false;
  real seed = 1, threads = 0, n_blocks = 0, sides = 36, diameter = 0.15, thickness = 0.06;
  real scale = std::numeric_limits<real>::quiet_NaN();
  real rate = 5e-3, du = 2e-9, u_max = 3e-4;  // m/s, strip displacement per step (m), last displacement (m)
  real cohesion_ratio = 2, phi_deg = 35;       // c_0 / f_T and phi_0 (deg) of the contacts (the study's)
  real phi_res_deg = std::numeric_limits<real>::quiet_NaN();  // phi_res (deg); NaN: the recipe's (30)
  real g_ii = 0;  // mode-II fracture energy with --law slip_softening (J/m^2); 0: scenes::default_g_ii
};

template <class joint_law>
int run_disc(disc_options& o, scenes::concrete_recipe<joint_law> recipe, io::run_record& record);

}  // namespace

int main(int argc, char** argv) {
  disc_options o;
  auto& [out, material, law, quick, seed, threads, n_blocks, sides, diameter, thickness, scale, rate, du, u_max, cohesion_ratio,
         phi_deg, phi_res_deg, g_ii] = o;
  struct flag { const char* name; real* value; real lo, hi; bool integer; };  // a number flag and its range
  const flag flags[] = {{"--seed", &seed, 1, 1e9, true}, {"--threads", &threads, 0, 256, true},
      {"--blocks", &n_blocks, 0, 2000, true}, {"--sides", &sides, 8, 360, true}, {"--diameter", &diameter, 0.02, 2, false},
      {"--thickness", &thickness, 0.005, 2, false}, {"--strength-scale", &scale, 0.1, 10, false},
      {"--rate", &rate, 1e-5, 0.1, false}, {"--step-displacement", &du, 1e-10, 1e-7, false},
      {"--max-displacement", &u_max, 1e-6, 0.01, false}, {"--cohesion-ratio", &cohesion_ratio, 0.1, 20, false},
      {"--phi-deg", &phi_deg, 0, 80, false}, {"--phi-res-deg", &phi_res_deg, 0, 80, false}, {"--g-ii", &g_ii, 0, 1e6, false}};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const flag* f = std::find_if(std::begin(flags), std::end(flags), [&](const flag& g) { return a == g.name; });
    if (a == "--help") {
      std::puts("brazilian [--out DIR] [--quick] [--material prism|beam] [--seed 1..1e9] [--threads 0..256]\n"
                "  [--blocks 0..2000] [--diameter 0.02..2 m] [--thickness 0.005..2 m] [--sides 8..360, a multiple of 4]\n"
                "  [--strength-scale 0.1..10] [--rate 1e-5..0.1 m/s] [--step-displacement 1e-10..1e-7 m]\n"
                "  [--max-displacement 1e-6..0.01 m] [--cohesion-ratio c_0/f_T 0.1..20] [--phi-deg phi_0 0..80]\n"
                "  [--phi-res-deg phi_res 0..80, the recipe's 30] [--law study|slip_softening] [--g-ii 0..1e6 J/m^2]:\n"
                "  f_sp = 2 P_max / (pi D t) against the concrete's f_T, null for a disc not split by --max-displacement.\n"
                "  --material: the concrete of examples/calibrate --material, its law, parameters, block size and zoning:\n"
                "  prism (default; the study's prism, f_T 2.15 MPa, strength scale 0.907, 38 blocks in the default disc)\n"
                "  or beam (rc_beam's, f_T 2.5 MPa, linear softening, 35 MPa cap, strength scale 1, 12 blocks, 30 mm\n"
                "  face zoning). --blocks 0: the material's block size. --quick: 5 nm per step.");
      std::printf("  --law: %s; --material beam only.\n  --g-ii: %s.\n", scenes::law_flag_help, scenes::g_ii_flag_help);
      return 0;
    } else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--material" && i + 1 < argc) material = argv[++i];
    else if (a == "--law" && i + 1 < argc) law = argv[++i];
    else if (a == "--quick") quick = true;
    else if (f != std::end(flags)) {
      const char* v = i + 1 < argc ? argv[++i] : "";
      char* end = nullptr;
      const real x = std::strtod(v, &end);
      if (*v == 0 || *end != 0 || !(x >= f->lo && x <= f->hi) || (f->integer && x != std::floor(x)))
        return std::fprintf(stderr, "brazilian: %s = '%s' must be %s in [%g, %g]\n", f->name, v,
                            f->integer ? "an integer" : "a number", f->lo, f->hi), 2;
      *f->value = x;
    } else return std::fprintf(stderr, "brazilian: unknown or incomplete argument '%s' (see --help)\n", a.c_str()), 2;
  }
  if (material != "prism" && material != "beam")
    return std::fprintf(stderr, "brazilian: --material '%s' is not a concrete recipe (expected prism or beam)\n",
                        material.c_str()), 2;
  if (law != "study" && law != "slip_softening")
    return std::fprintf(stderr, "brazilian: --law: invalid value '%s' (expected study or slip_softening)\n", law.c_str()), 2;
  if (material == "prism" && law != "study")
    return std::fprintf(stderr, "brazilian: --law %s applies to --material beam only (the prism's concrete has the study's law)\n",
                        law.c_str()), 2;
  try {
    scenes::require_g_ii_with_slip_softening("brazilian", law, g_ii);
  } catch (const std::exception& e) {
    cli::print_error("brazilian", e);
    return 2;
  }
  if (static_cast<int>(sides) % 4 != 0)  // a flat at the top and at the bottom needs sides = 4k
    return std::fprintf(stderr, "brazilian: --sides = %g must be a multiple of 4 (flats at top and bottom)\n", sides), 2;
  if (quick) du = std::max<real>(du, 5e-9);
  if (std::isnan(scale)) scale = material == "prism" ? 0.907 : 1;
  if (n_blocks == 1) return std::fprintf(stderr, "brazilian: --blocks = 1 must be 0 (the material's block size) or >= 2\n"), 2;
  if (threads > 0) set_threads(static_cast<int>(threads));
  io::run_record record(out, "brazilian", argc, argv);
  try {
    if (material == "prism") return run_disc(o, scenes::prism_concrete(scale, cohesion_ratio), record);
    scenes::beam_options beam;
    beam.strength_scale = scale;
    auto recipe = scenes::beam_concrete(beam);
    recipe.contact.shear.c_0 = cohesion_ratio * recipe.contact.tension.f_T, recipe.contact.shear.c_res = 0.01 * recipe.contact.shear.c_0;
    if (law == "slip_softening")
      return run_disc(o, scenes::with_slip_softening(recipe, scenes::g_ii_or_default(g_ii)), record);
    return run_disc(o, recipe, record);
  } catch (const std::exception& e) {
    cli::print_error("brazilian", e);  // one "brazilian: " before the message
    return 1;
  }
}

namespace {

template <class joint_law>
int run_disc(disc_options& o, scenes::concrete_recipe<joint_law> recipe, io::run_record& record) {
  using model = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<joint_law>>;
  auto& [out, material, law, quick, seed, threads, n_blocks, sides, diameter, thickness, scale, rate, du, u_max, cohesion_ratio,
         phi_deg, phi_res_deg, g_ii] = o;
  {
    // ---- scene: geometry, materials, supports, loading ----
    const real pi = std::numbers::pi, R = diameter / 2, a = R * std::cos(pi / sides), strip = 2 * R * std::sin(pi / sides);
    // phase pi / sides puts a face across x and, with sides = 4k, across y: the strips at y = +-a.
    const auto disc = geometry::cylinder_prism(vec3::Zero(), vec3::UnitZ(), R, thickness, static_cast<index_t>(sides), pi / sides);
    const real disc_volume = 0.5 * sides * R * R * std::sin(2 * pi / sides) * thickness;
    if (n_blocks == 0) n_blocks = static_cast<real>(recipe.blocks_in(disc_volume));  // the recipe's block size
    typename joint_law::params joint = recipe.contact;  // the recipe's contacts, at its block size
    joint.shear.phi_0 = law::friction_angle::from_degrees(phi_deg);
    if (!std::isnan(phi_res_deg)) joint.shear.phi_res = law::friction_angle::from_degrees(phi_res_deg);
    require(joint.shear.phi_res.degrees() <= phi_deg, "brazilian: --phi-deg ", phi_deg, " must not be below the residual ",
            joint.shear.phi_res.degrees(), " deg");
    joint_law::validate(joint);  // names a bad parameter (c_res, phi_res, G_II) before the scene is built
    const auto tess = geometry::random_voronoi(disc, static_cast<index_t>(n_blocks), static_cast<std::uint64_t>(seed));
    const auto mesh = geometry::zone_blocks(tess, recipe.zoning());  // the recipe's zoning
    const zones::linear_elastic_tet::params concrete = recipe.block_material;  // semi-rigid: 10 x the macro E
    solver_options options;
    options.mass_scaling_dt = du / rate;  // quasi-static: masses scaled so the strip moves du per step
    model s(tess, mesh, concrete, contact::material_table<typename joint_law::params>(joint), {}, options);
    const auto bottom = s.gridpoints_on_plane(1, -a, 1e-9 * diameter), top = s.gridpoints_on_plane(1, a, 1e-9 * diameter);
    s.fix(bottom);                                 // bottom strip held
    s.prescribe_velocity(top, vec3(0, -rate, 0));  // top strip pushed down at the rate
    // ---- end of scene ----
    io::ensure_directory(out);  // run.json "running"
    const auto start = std::chrono::steady_clock::now();
    std::vector<double> u, p_top, p_bottom;
    real p_max = 0, u_peak = 0, p_bottom_at_peak = 0, u_split = 0;  // u_split 0: not split yet
    bool done = false;
    const auto every = static_cast<index_t>(std::max<real>(1, std::round(2e-7 / du)));  // a sample per 0.2 um
    // Split: across the middle two thirds of the diameter (|y| < D/3; the strips' wedges aside) no chain of
    // intact contacts (tensile damage < 0.5, not slipped) joins a block on the flat x = -a to one on x = +a.
    const auto left = s.blocks_on_plane(0, -a, 1e-9 * diameter), right = s.blocks_on_plane(0, a, 1e-9 * diameter);
    std::vector<std::size_t> root(static_cast<std::size_t>(s.block_count()));
    const auto split = [&](const model& m) {
      std::iota(root.begin(), root.end(), std::size_t{0});
      const auto find = [&](index_t block) {  // union-find root, halving the path
        for (auto b = static_cast<std::size_t>(block);; b = root[b] = root[root[b]]) if (root[b] == b) return b;
      };
      const auto& c = m.contacts();
      for (index_t i = 0; i < c.size(); ++i)
        if (std::abs(c.position(i, m.gridpoints()).y()) < diameter / 3 &&
            joint_law::tensile_damage(c.subcontact_params(i), c.state(i)) < 0.5 &&
            !law::has(joint_law::status(c.state(i)), law::contact_status::slipped))
          root[find(c.block_a(i))] = find(c.block_b(i));
      for (index_t l : left)
        for (index_t r : right)
          if (find(l) == find(r)) return false;
      return true;
    };
    // The opening across the loaded diameter: the mean x displacement of the gridpoints on the flat
    // x = +a minus that on x = -a, over the middle third of the height (|y| < D/6).
    std::vector<index_t> flank[2];
    for (index_t g = 0; g < s.gridpoints().size(); ++g)
      if (const real x = s.gridpoints().reference(g, 0); std::abs(std::abs(x) - a) <= 1e-9 * diameter &&
                                                        std::abs(s.gridpoints().reference(g, 1)) < diameter / 6)
        flank[x > 0 ? 1 : 0].push_back(g);
    require(!flank[0].empty() && !flank[1].empty(), "brazilian: no gridpoint on the flats x = +-a across the middle");
    const auto opening = [&](const model& m) {
      real w = 0;
      for (int k = 0; k < 2; ++k) {
        real mean = 0;
        for (index_t g : flank[k]) mean += m.gridpoints().displacement(g, 0);
        w += (k == 1 ? 1 : -1) * mean / static_cast<real>(flank[k].size());
      }
      return w;
    };
    std::vector<double> w_open;
    real p_split = 0, w_split = 0;
    const auto observe = [&](const model& m) {
      const real p = -recorders::reaction_sum(m.gridpoints(), top).y(), pb = recorders::reaction_sum(m.gridpoints(), bottom).y();
      u.push_back(rate * m.time()), p_top.push_back(p), p_bottom.push_back(pb), w_open.push_back(opening(m));
      if (p > p_max && u_split == 0) p_max = p, u_peak = u.back(), p_bottom_at_peak = pb;
      if (u_split == 0 && split(m)) u_split = u.back(), p_split = p, w_split = w_open.back();
      done = u.back() >= u_max || (u_split > 0 && u.back() > 1.2 * u_split);
    };
    s.run_until([&](const model&) { return done; }, static_cast<std::int64_t>(2 * u_max / du), recorders::every(every, observe));
    const double runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // The crack: sub-contacts with tensile damage >= 0.5 by area; near: within D/6 of the loaded diameter.
    const auto& c = s.contacts();
    real cracked = 0, near = 0;
    for (index_t i = 0; i < c.size(); ++i)
      if (joint_law::tensile_damage(c.subcontact_params(i), c.state(i)) >= 0.5)
        cracked += c.area(i), near += std::abs(c.position(i, s.gridpoints()).x()) <= diameter / 6 ? c.area(i) : 0;
    // f_sp only for a disc that split: the largest load of one that did not is the cap's, not a strength.
    const bool did_split = u_split > 0;
    const real none = std::numeric_limits<real>::quiet_NaN();
    const real f_sp = did_split ? 2 * p_max / (pi * diameter * thickness) : none;
    const real f_t = recipe.f_T;  // the concrete's tensile strength (the prism: its calibrated peak)
    const real mismatch = (p_max - p_bottom_at_peak) / p_max;
    // The diametral crack opening: the first load at which the opening across the diameter exceeds twice
    // its elastic value (the compliance w / P at the first sample above 20 % of P_max, before the split).
    // The load after it, up to P_max, is carried by the wedges under the strips as the crack opens.
    real p_crack = none, w_crack = none;
    for (std::size_t k = 0, k0 = 0; k < u.size() && (!did_split || u[k] <= u_split); ++k) {
      if (k0 == 0 && p_top[k] >= 0.2 * p_max) k0 = k;
      if (k0 > 0 && p_top[k] > 0.2 * p_max && w_open[k] > 2 * (w_open[k0] / p_top[k0]) * p_top[k]) {
        p_crack = p_top[k], w_crack = w_open[k];
        break;
      }
    }
    const real f_crack = 2 * p_crack / (pi * diameter * thickness);
    io::write_csv(std::filesystem::path(out) / "curve.csv", {"u_m", "P_top_N", "P_bottom_N", "opening_m"}, {u, p_top, p_bottom, w_open});
    io::summary_json j;
    j.set("example", "brazilian").set("material", material).set("law", law).set("g_ii_J_per_m2", law == "slip_softening" ? scenes::g_ii_or_default(g_ii) : none)
        .set("phi_res_deg", joint.shear.phi_res.degrees()).set("quick", quick).set("seed", seed).set("blocks", n_blocks).set("sides", sides)
        .set("zone_edge_m", recipe.zone_edge).set("diameter_m", diameter).set("thickness_m", thickness).set("strip_over_diameter", strip / diameter)
        .set("strength_scale", scale).set("cohesion_ratio", cohesion_ratio).set("phi_0_deg", phi_deg).set("rate_m_per_s", rate).set("dt_s", s.dt()).set("steps", s.step_count())
        .set("damping_in_force", s.damping_in_force())
        .set("peak_load_N", did_split ? p_max : none).set("largest_load_N", p_max).set("peak_displacement_m", u_peak)
        .set("split", did_split).set("split_displacement_m", did_split ? u_split : none).set("split_load_N", did_split ? p_split : none)
        .set("opening_at_split_m", did_split ? w_split : none).set("opening_at_end_m", opening(s))
        .set("crack_opening_load_N", p_crack).set("crack_opening_m", w_crack).set("f_sp_crack_opening_Pa", f_crack)
        .set("f_sp_crack_opening_over_f_T", f_crack / f_t)
        .set("bottom_over_top_at_peak_rel", mismatch).set("f_sp_Pa", f_sp).set("f_T_Pa", f_t).set("f_sp_over_f_T", f_sp / f_t)
        .set("ec2_ratio", 1 / 0.9).set("cracked_area_over_diametral", cracked / (diameter * thickness))
        .set("crack_near_diameter_share", cracked > 0 ? near / cracked : 0.0).set("energy_balance_error_rel", s.energies().error_rel())
        .set("threads", max_threads()).set("runtime_s", runtime_s);
    j.write(std::filesystem::path(out) / "summary.json");
    record.complete();
    if (did_split)
      std::printf("brazilian: %s concrete (%s law), %d blocks, seed %d, P_max %.2f kN at %.1f um (split at %.1f um, %.2f kN, opening %.2f um), f_sp %.3f MPa = "
                  "%.3f f_T (EC2 1.11; at the crack's opening %.3f f_T), bottom/top %+.2f %%, crack near the diameter %.0f %%, energy error %.1e, %.1f s\n",
                  material.c_str(), law.c_str(), static_cast<int>(n_blocks), static_cast<int>(seed), p_max * 1e-3, u_peak * 1e6, u_split * 1e6, p_split * 1e-3, w_split * 1e6,
                  f_sp * 1e-6, f_sp / f_t, f_crack / f_t, 100 * mismatch, 100 * (cracked > 0 ? near / cracked : 0.0),
                  s.energies().error_rel(), runtime_s);
    else
      std::printf("brazilian: %s concrete (%s law), %d blocks, seed %d did NOT split by --max-displacement %.1f um: no f_sp (the largest load, %.2f kN, is "
                  "the load at that displacement, not a splitting strength); %.1f s\n",
                  material.c_str(), law.c_str(), static_cast<int>(n_blocks), static_cast<int>(seed), u_max * 1e6, p_max * 1e-3, runtime_s);
    return 0;
  }
}

}  // namespace
