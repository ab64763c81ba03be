#pragma once
// direct_tension's concrete (issue #63 item 6: the prism with the set the beam runs with), the
// interface compression and brazilian have (common/concrete_set.hpp):
//   --material prism  the study's prism (the default, unchanged): 68 x 68 x 600 mm, --blocks Voronoi
//                     blocks with the Table 1 contacts for that count, law::study_tie_law; --law study
//                     only, --phi-deg / --phi-res-deg applied to its contacts when given; --params
//                     applies a prism entry's two scales (load_calibration, as before).
//   --material beam   rc_beam's concrete on the prism calibrate --targets tension pulls
//                     (rc_beam/beam.hpp make_beam_prism: 150 x 150 x 600 mm, the recipe's mean block
//                     volume, faces zoned to the recipe's edge), the recipe --recipe-blocks (0: 250) and
//                     --zone-edge (0.03), any law of common/concrete_laws.hpp with its flags (--law,
//                     --g-ii, --g-c, --cap-residual, --crush-shear, --phi-deg, --phi-res-deg, --cap,
//                     --cohesion-ratio) through scenes::with_concrete; --blocks N puts N Voronoi blocks
//                     in the prism instead of the recipe's count (155 for the 250-block beam) with the
//                     recipe's contacts; --params applies a beam entry whole (load_concrete_params).
// The beam's run is calibrate's tension target's (targets.hpp evaluate_targets): the same scene and
// solver (run_direct_tension on solver<deformable, presets::bonded_faces<Law>>), so on the same seed,
// step and rate its peak is calibrate's to the bit.

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "common/cli.hpp"
#include "common/concrete_set.hpp"
#include "direct_tension/tension_test.hpp"
#include "tessera/io/json.hpp"

namespace tessera::scenes {

/// The concrete flags of direct_tension (the names add_law_flags fills, and the recipe's).
struct tension_concrete {
  std::string material = "prism";
  std::string law = "study";
  double g_ii = 0, g_c = 0, cap_residual = 0.1;
  bool crush_shear = false;
  double phi_deg = 35, phi_res_deg = 30, cap = 35e6;
  int recipe_blocks = 0;  ///< beam: the recipe's block count (0 = 250)
  double zone_edge = -1;  ///< beam: the recipe's face zoning edge (m; < 0 = 0.03)
  concrete_set set;       ///< beam: the set run (finish_concrete)
};

/// Registers --material, the law flags (add_law_flags), --recipe-blocks and --zone-edge.
inline void add_concrete_flags(cli::parser& cli, tension_concrete& c) {
  cli.option("--material", c.material, "the concrete, a recipe of calibrate --material: prism (the study's prism, the "
             "default) or beam (rc_beam's concrete on calibrate's 150 x 150 x 600 mm beam-recipe prism)", "M")
      .one_of({"prism", "beam"});
  add_law_flags(cli, c, "--material beam only");
  cli.option("--recipe-blocks", c.recipe_blocks, "beam: the recipe's block count (calibrate --blocks): its contacts and "
             "block size; 0 = 250; else at least 8", "N").within(0, 500);
  cli.option("--zone-edge", c.zone_edge, "beam: the recipe's face zoning edge (m; calibrate --zone-edge); default 0.03",
             "M").within(0, 1);
}

/// The flags that do not apply with c.material, or beside --params (`params`). Throws invalid_input
/// naming the flag and its value.
inline void require_concrete_flags(const cli::parser& cli, const tension_concrete& c, const std::string& params) {
  const bool beam = c.material == "beam";
  const char* d = "direct_tension";
  if (!beam) {
    require(!cli.given("--recipe-blocks"), d, ": --recipe-blocks ", c.recipe_blocks, " applies to --material beam only "
            "(the prism's recipe is --blocks)");
    require(!cli.given("--zone-edge"), d, ": --zone-edge ", c.zone_edge, " applies to --material beam only (the prism's "
            "recipe has one zone per face triangle)");
    require(!cli.given("--cap"), d, ": --cap ", c.cap, " applies to --material beam only (the prism's contacts have no cap)");
    require(!concrete_law_named(c.law, d).beam_only, d, ": --law ", c.law, " applies to --material beam only (the "
            "prism's concrete has the study's law)");
  } else {
    for (const char* f : {"--softening", "--cohesion", "--slip-breaks-tension", "--rigid", "--lloyd", "--regularize"})
      require(!cli.given(f), d, ": ", f, " applies to --material prism only (the beam's concrete is its law's: linear "
              "softening, decoupled cohesion, deformable blocks on a plain Voronoi tessellation)");
    require_recipe_blocks(d, c.recipe_blocks);
  }
  require_g_ii_with_law(d, c.law, c.g_ii);
  require_law_flags(cli, d, c.law, c.g_c);
  require(c.phi_res_deg <= c.phi_deg, d, ": --phi-res-deg ", c.phi_res_deg, " must not exceed --phi-deg ", c.phi_deg);
  if (params.empty()) return;
  std::vector<const char*> flags = {"--phi-deg", "--phi-res-deg", "--law", "--g-ii", "--cap", "--g-c", "--cap-residual",
                                    "--crush-shear"};
  if (beam) flags.push_back("--cohesion-ratio");  // the prism's file is checked against it (load_calibration)
  for (const char* f : flags)
    require(!cli.given(f), d, ": ", f, " with --params ", params, ": the file sets the concrete (drop the flag)");
}

/// Fills c.set for --material beam from the flags, then (--params) from the file's entry for the
/// recipe (refused naming both values if another recipe's), and builds its contacts once so that a
/// bad value (a G_II below the law's bound, ...) is refused before anything is written.
inline void finish_concrete(tension_concrete& c, double cohesion_ratio, const std::string& params, real step, real rate) {
  concrete_set& s = c.set;
  s.material = "beam", s.recipe_blocks = c.recipe_blocks, s.zone_edge = c.zone_edge;
  s.law = c.law, s.g_ii = c.g_ii, s.g_c = c.g_c, s.cap_residual = c.cap_residual, s.crush_shear = c.crush_shear;
  s.phi_0_deg = c.phi_deg, s.phi_res_deg = c.phi_res_deg, s.cap = c.cap, s.cohesion_ratio = cohesion_ratio;
  if (!params.empty()) load_concrete_params(s, params, step, rate, "direct_tension");
  require(s.phi_res_deg <= s.phi_0_deg, "direct_tension: phi_res ", s.phi_res_deg, " deg must not exceed phi_0 ",
          s.phi_0_deg, " deg");
  (void)with_concrete(s, [](const auto&) { return 0; });
}

/// What the driver reports of the contacts of a run beyond the prism_scene (SI).
struct tension_contacts {
  real k_n = 0;                ///< Pa/m
  real separation_energy = 0;  ///< J/m^2 of one contact pulled to separation (the softening's)
  real g_ii = std::numeric_limits<real>::quiet_NaN();  ///< J/m^2; NaN for a law without G_II
};

/// One pull of set c's concrete (--material beam) on `seed`: the beam-recipe prism with `blocks` Voronoi
/// blocks (0 = the recipe's), the set's law, calibrate's solver. Fills scene and k.
[[nodiscard]] inline tension_result run_beam_tension(const concrete_set& c, int blocks, std::uint64_t seed,
                                                     const tension_loading& loading, prism_scene& scene,
                                                     tension_contacts& k) {
  beam_options b = c.beam();
  b.seed = seed;
  scene = make_beam_prism(b, blocks).prism;
  k.g_ii = g_ii_in_effect(c);
  return with_concrete(c, [&](const auto& recipe) {
    using Law = typename recipe_law<std::remove_cvref_t<decltype(recipe)>>::type;
    k.k_n = recipe.contact.k_n;
    // the beam's laws soften linearly (G_f); with_concrete also instantiates the prism's power softening
    if constexpr (std::is_same_v<std::remove_cvref_t<decltype(recipe.contact.tension)>, law::power_softening::params>)
      k.separation_energy = law::power_softening::separation_energy(recipe.contact.tension, recipe.contact.k_n);
    else
      k.separation_energy = law::linear_softening::separation_energy(recipe.contact.tension, recipe.contact.k_n);
    using beam_prism_solver = solver<blocks::deformable<zones::linear_elastic_tet>, presets::bonded_faces<Law>>;
    return run_direct_tension<beam_prism_solver>(scene, recipe.contact, loading);
  });
}

/// summary.json's concrete: material, law, G_II (null without), phi_0 and phi_res, energy_over_G_f
/// (every contact's dissipation per cross-section over the concrete's G_f, calibrate's energy target;
/// null for a run stopped before separation) and, with the beam's, its recipe, cap and G_c.
inline void set_concrete_figures(io::summary_json& js, const tension_concrete& c, const tension_contacts& k,
                                 double energy_over_g_f) {
  const bool beam = c.material == "beam";
  const concrete_set& s = c.set;
  js.set("material", c.material)
      .set("law", beam ? s.law : c.law)
      .set("g_ii_J_per_m2", k.g_ii)
      .set("phi_0_deg", beam ? s.phi_0_deg : c.phi_deg)
      .set("phi_res_deg", beam ? s.phi_res_deg : c.phi_res_deg)
      .set("energy_over_G_f", energy_over_g_f);
  if (beam)
    js.set("recipe_blocks", s.blocks())
        .set("zone_edge_m", s.beam().face_zone_edge())
        .set("cap_Pa", s.cap)
        .set("G_c_J_per_m2", g_c_in_effect(s));
}

}  // namespace tessera::scenes
