#pragma once
// The concrete of brazilian, compression and calibrate --targets as one set of values (issue #63
// item 4): the recipe (material, its block count and face zoning: the contacts' stiffness table,
// the mean block size, the sub-contacts' density) and the parameters a calibration may fit (the
// law, the strength and fracture-energy scales, c_0 / f_T, phi_0, phi_res, G_II, the cap). The
// drivers fill it from their flags or from a calibrated.json entry (--params, load_concrete), and
// with_concrete builds the concrete_recipe of the set's law with every value applied, so a driver
// that loads a file runs exactly the fitted concrete.

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <utility>

#include "common/calibration.hpp"
#include "common/cli.hpp"
#include "common/scenes.hpp"
#include "rc_beam/beam.hpp"
#include "tessera/presets/mixed_mode.hpp"

namespace tessera::scenes {

struct concrete_set {
  std::string material = "beam";  ///< "prism" (the study's prism concrete) or "beam" (rc_beam's)
  int recipe_blocks = 0;          ///< the recipe's block count (calibrate --blocks); 0 = prism 100, beam 250
  real zone_edge = -1;            ///< beam: face zoning edge (m); < 0 = the beam's h/5 = 0.03 (prism: 0 always)
  /// A law of concrete_laws.hpp: "study", "slip_softening", "crushing" or "mixed_mode" (the latter three beam only)
  std::string law = "study";
  /// Contact f_T (and c_0) x strength_scale; NaN = the material's (prism 0.907, its calibrated 100-block
  /// scale; beam 1, the study verbatim).
  real strength_scale = std::numeric_limits<real>::quiet_NaN();
  real fracture_energy_scale = 1;     ///< contact G_f x this
  real cohesion_ratio = 2;            ///< c_0 / f_T; c_res = 0.01 c_0
  real phi_0_deg = 35, phi_res_deg = 30;  ///< contact friction angles (deg)
  /// mode-II fracture energy (J/m^2) of a law that takes it (concrete_laws.hpp); 0 = the law's default
  real g_ii = 0;
  real cap = 35e6;                    ///< contact compressive cap (Pa), beam only
  real g_c = 0;                       ///< G_c (J/m^2) with law crushing (0 = default_g_c) or mixed_mode (0 = plastic cap)
  real cap_residual = 0.1;            ///< residual cap / cap with law crushing, in [0, 1]
  bool crush_shear = false;           ///< law crushing: the shear limit times the cap's remaining fraction

  [[nodiscard]] int blocks() const { return recipe_blocks > 0 ? recipe_blocks : material == "prism" ? 100 : 250; }
  [[nodiscard]] real scale() const { return std::isnan(strength_scale) ? (material == "prism" ? 0.907 : 1.0) : strength_scale; }
  /// The beam options whose concrete this is (block count, zoning, scales).
  [[nodiscard]] beam_options beam() const {
    beam_options b;
    b.blocks = blocks();
    if (zone_edge >= 0) b.zone_edge = zone_edge;
    b.strength_scale = scale();
    b.fracture_energy_scale = fracture_energy_scale;
    return b;
  }
  /// The recipe a calibrated.json must have been fitted on to be loaded into this set (the step and
  /// rate are the run's, step_displacement m, rate m/s: a difference is a note, not a refusal).
  [[nodiscard]] calibration_recipe recipe(real step_displacement, real rate) const {
    calibration_recipe r;
    r.material = material;
    r.softening = material == "prism" ? "power" : "linear";
    r.cohesion_ratio = cohesion_ratio;
    r.step_displacement = step_displacement;
    r.rate = rate;
    r.zone_edge = material == "prism" ? 0 : beam().face_zone_edge();
    r.beam_volume = material == "prism" ? 0 : beam().half_volume();
    return r;
  }
  /// The entry's concrete over this set's (material, recipe blocks and zoning kept).
  void apply(const calibration_entry& e) {
    law = e.law;
    strength_scale = e.strength_scale;
    fracture_energy_scale = e.fracture_energy_scale;
    cohesion_ratio = e.cohesion_ratio;
    phi_0_deg = e.phi_0_deg;
    phi_res_deg = e.phi_res_deg;
    g_ii = law_in_file(e.law, law_g_ii) ? e.g_ii : 0;
    cap = e.cap;
    g_c = law_in_file(e.law, law_g_c) ? e.g_c : 0;
    cap_residual = law_in_file(e.law, law_cap_residual) ? e.cap_residual : real(0.1);
    crush_shear = law_in_file(e.law, law_crush_shear) && e.crush_shear;
  }
};

/// The law of a concrete_recipe type (recipe_law<concrete_recipe<L>>::type is L).
template <class Recipe>
struct recipe_law;
template <class Law>
struct recipe_law<concrete_recipe<Law>> {
  using type = Law;
};

/// --params FILE for brazilian, compression and rc_beam (`program`): the entry for c's recipe
/// (material, block count, zoning, the half beam's volume; refused with both values named
/// otherwise, load_concrete) applied to c, and returned. step_displacement (m; 0 = set later by the
/// run) and rate (m/s) only print a note where they differ from the fit's; beam_volume (m^3): the
/// run's half beam (rc_beam), 0 = the default beam's.
inline calibration_entry load_concrete_params(concrete_set& c, const std::filesystem::path& file, real step_displacement,
                                              real rate, const char* program, real beam_volume = 0) {
  calibration_recipe r = c.recipe(step_displacement, rate);
  if (beam_volume > 0) r.beam_volume = beam_volume;
  const calibration_entry e = load_concrete(file, c.blocks(), r, program);
  c.apply(e);
  return e;
}

/// The recipe `beam` with the mixed-mode law (presets::with_mixed_mode: G_II in J/m^2, 0 = (c_0/f_T) G_f),
/// everything else the recipe's.
[[nodiscard]] inline concrete_recipe<presets::mixed_mode_beam_law> with_mixed_mode(
    const concrete_recipe<presets::study_beam_law>& beam, real G_II) {
  return beam.with_contact<presets::mixed_mode_beam_law>(presets::with_mixed_mode(beam.contact, G_II));
}

/// Registers the contact-law flags of the drivers built on cli::parser (compression, rc_beam) into
/// o.law (--law, a name of concrete_laws.hpp), o.g_ii (--g-ii, J/m^2), o.g_c (--g-c,
/// J/m^2), o.cap_residual (--cap-residual), o.crush_shear (--crush-shear), o.phi_deg and o.phi_res_deg
/// (--phi-deg, --phi-res-deg, deg) and o.cap (--cap, Pa), with one set of ranges; `cap_note` ends
/// --cap's help (what the driver does with the cap). brazilian parses its own flags with the same
/// ranges and help texts (law_flag_help); calibrate's start flags differ on purpose. A parameter given
/// with a law that does not take it is refused by require_law_flags.
template <class Options>
void add_law_flags(cli::parser& cli, Options& o, const char* cap_note) {
  cli.option("--law", o.law, law_flag_help(), "L").one_of(concrete_law_names());
  cli.option("--g-ii", o.g_ii, g_ii_flag_help(), "J").within(0, 1e6);
  cli.option("--g-c", o.g_c, g_c_flag_help(), "J").within(0, 1e8);
  cli.option("--cap-residual", o.cap_residual, cap_residual_flag_help(), "R").within(0, 1);
  cli.flag("--crush-shear", o.crush_shear, crush_shear_flag_help());
  cli.option("--phi-deg", o.phi_deg, "contact friction angle phi_0 (deg; the study's 35)", "DEG").within(0, 80);
  cli.option("--phi-res-deg", o.phi_res_deg, "residual contact friction angle phi_res (deg; the study's 30)", "DEG")
      .within(0, 80);
  cli.option("--cap", o.cap, tessera::detail::concat("contact compressive cap f_c (Pa; the study's 35e6; ", cap_note, ")"),
             "PA").within(1e6, 1e10);
}

/// The range of --cohesion-ratio (c_0 / f_T) on the drivers of one concrete (compression, brazilian,
/// rc_beam): a tenth of the study's 2 to ten times it.
inline constexpr real min_cohesion_ratio = 0.1, max_cohesion_ratio = 20;

/// Registers --cohesion-ratio (c_0 / f_T, min_cohesion_ratio..max_cohesion_ratio) into `ratio` on `cli`:
/// compression's and rc_beam's (brazilian's range table reads the same bounds).
inline void add_cohesion_ratio_flag(cli::parser& cli, real& ratio) {
  cli.option("--cohesion-ratio", ratio,
             "contact cohesion c_0 / f_T (the study's 2; c_res = 0.01 c_0, 0 with --law mixed_mode)", "R")
      .within(min_cohesion_ratio, max_cohesion_ratio);
}

/// Refuses a law parameter's flag (law_parameter_rows: --g-c, --cap-residual, --crush-shear; --g-ii
/// is require_g_ii_with_law's, with its value) given on `cli` with law `law` that does not take it, or
/// beside --g-c `g_c` (J/m^2) 0 where the law softens its cap only with G_c > 0 (require_law_parameters),
/// throwing invalid_input "`driver`: --g-c applies to --law crushing or mixed_mode only (--law study has no G_c)".
inline void require_law_flags(const cli::parser& cli, std::string_view driver, const std::string& law, double g_c) {
  require_law_parameters(driver, law, g_c, [&](const char* flag) { return cli.given(flag); });
}

/// The smallest recipe block count (calibrate's and rc_beam's smallest specimen).
inline constexpr int min_recipe_blocks = 8;

/// Refuses --recipe-blocks `n` between 1 and min_recipe_blocks - 1 (0 is the material's own),
/// throwing invalid_input "`driver`: --recipe-blocks 5 must be 0 (the material's) or >= 8".
inline void require_recipe_blocks(std::string_view driver, int n) {
  require(n == 0 || n >= min_recipe_blocks, driver, ": --recipe-blocks ", n, " must be 0 (the material's) or >= ",
          min_recipe_blocks, " (calibrate's and rc_beam's smallest specimen)");
}

/// Calls f(recipe) with the concrete_recipe of c's material and law, every value of c applied
/// (law::study_tie_law for prism; presets::study_beam_law, slip_softening_beam_law,
/// crushing_beam_law or mixed_mode_beam_law for beam: concrete_laws.hpp), and returns its result.
/// Throws invalid_input naming a bad combination or value (a law not in the table, a beam-only law
/// on the prism, the law's validate; the drivers check phi_res <= phi_0 themselves, naming their flags).
template <class F>
decltype(auto) with_concrete(const concrete_set& c, F&& f) {
  require(c.material == "prism" || c.material == "beam", "concrete: material '", c.material, "' must be prism or beam");
  const concrete_law& law = concrete_law_named(c.law, "concrete");
  require(c.material == "beam" || !law.beam_only, "concrete: law ", c.law,
          " applies to the beam's concrete only (the prism's concrete has the study's law)");
  if (c.material == "prism") {
    auto r = prism_concrete(c.scale(), c.cohesion_ratio, c.blocks());
    r.contact.tension.G_f *= c.fracture_energy_scale;
    apply_concrete_shear(r.contact, c.cohesion_ratio, c.phi_0_deg, c.phi_res_deg, c.cap);
    law::study_tie_law::validate(r.contact);
    return std::forward<F>(f)(r);
  }
  auto r = beam_concrete(c.beam());
  apply_concrete_shear(r.contact, c.cohesion_ratio, c.phi_0_deg, c.phi_res_deg, c.cap);
  if (c.law == "mixed_mode") {
    auto m = with_mixed_mode(r, c.g_ii);
    if (c.g_c > 0) {  // the cap softens with crushing (law/mixed_mode.hpp with softening_cap)
      auto k = m.with_contact<presets::mixed_crushing_beam_law>(
          presets::with_softening_cap(m.contact, c.g_c, c.cap_residual, c.crush_shear));
      presets::mixed_crushing_beam_law::validate(k.contact);
      return std::forward<F>(f)(k);
    }
    presets::mixed_mode_beam_law::validate(m.contact);
    return std::forward<F>(f)(m);
  }
  if (c.law == "slip_softening" || c.law == "crushing") {
    auto s = with_slip_softening(r, g_ii_or_default(c.g_ii));
    if (c.law == "crushing") {
      auto k = with_softening_cap(s, c.g_c > 0 ? c.g_c : default_g_c, c.cap_residual, c.crush_shear);
      presets::crushing_beam_law::validate(k.contact);
      return std::forward<F>(f)(k);
    }
    presets::slip_softening_beam_law::validate(s.contact);
    return std::forward<F>(f)(s);
  }
  require(c.law == "study", "concrete: law ", c.law, " is a row of concrete_laws.hpp without a recipe here (with_concrete)");
  presets::study_beam_law::validate(r.contact);
  return std::forward<F>(f)(r);
}

/// The G_c (J/m^2) over which the cap of set c's contacts softens with crushing: the flag's value or
/// the law's default (concrete_laws.hpp: crushing 0 = default_g_c; mixed_mode softens only with
/// g_c > 0); NaN for a cap that does not soften.
[[nodiscard]] inline real g_c_in_effect(const concrete_set& c) {
  const concrete_law* l = find_concrete_law(c.law);
  if (l == nullptr || (l->parameters & law_g_c) == 0 || (l->crush_needs_g_c && !(c.g_c > 0)))
    return std::numeric_limits<real>::quiet_NaN();
  return c.g_c > 0 ? c.g_c : default_g_c;
}

/// The G_II (J/m^2) set c's contacts take: the flag's value or the law's default (concrete_laws.hpp:
/// 500 for slip_softening and crushing, (c_0/f_T) G_f of the scaled contacts for mixed_mode); NaN
/// for a law without G_II. Throws what with_concrete throws.
[[nodiscard]] inline real g_ii_in_effect(const concrete_set& c) {
  if (!law_takes(c.law, law_g_ii)) return std::numeric_limits<real>::quiet_NaN();
  if (c.law != "mixed_mode") return g_ii_or_default(c.g_ii);
  return with_concrete(c, [](const auto& recipe) -> real {
    if constexpr (requires { recipe.contact.shear.G_II; }) return recipe.contact.shear.G_II;
    else return 0;
  });
}

}  // namespace tessera::scenes
