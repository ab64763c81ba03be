#pragma once
// rc_tie's contact law (issue #63 item 6: the tie with the mixed-mode set the beam runs with, beside
// the study's), on the tie's own contacts either way (Table 1's stiffnesses for --blocks, f_T =
// 2.15 MPa, G_f = 60 J/m^2, c_0 = --cohesion-ratio x f_T, phi_0 = 35 deg, phi_res = 30 deg, no
// compressive limit):
//   --law study       the study's tie law (law::study_tie_law; the default, unchanged to the bit):
//                     power softening (--softening linear: linear), cohesion decoupled (--cohesion
//                     coupled), --slip-breaks-tension, --rigid, --params, --scheme relaxation
//   --law mixed_mode  the mixed-mode law (presets::mixed_mode_tie_law, law/mixed_mode.hpp): one damage
//                     for tension and shear, linear softening over G_f as G_I, cohesion and friction
//                     softening with the same damage, G_II = --g-ii (J/m^2; 0 = (c_0/f_T) G_f, 120);
//                     the beam's mixed-mode set is --g-ii 70; --phi-res-deg sets the spent contact's
//                     friction phi_res (deg; the study's 30, the beam's less-friction set 15).
//                     Deformable blocks, explicit pull: the study law's flags above are refused with
//                     it, naming the value.
// The hand checks (N_cr = f_T (A_c + n A_s), f_y A_s) are the same for both laws: the same f_T.

#include <limits>
#include <string>
#include <utility>

#include "common/cli.hpp"
#include "common/rc_tie_run.hpp"
#include "tessera/io/json.hpp"
#include "tessera/presets/mixed_mode.hpp"

namespace tessera::scenes {

/// The study's residual friction angle phi_res (deg): the tie's contacts' own, --phi-res-deg's default.
inline constexpr double study_phi_res_deg = 30;

/// The tie's contact law: its name, G_II and phi_res.
struct tie_law {
  std::string name = "study";  ///< "study" (law::study_tie_law and its variants) or "mixed_mode"
  double g_ii = 0;             ///< mixed_mode: mode-II fracture energy (J/m^2); 0 = (c_0/f_T) G_f
  /// mixed_mode: the spent contact's friction phi_res (deg); the study's law refuses --phi-res-deg
  /// and keeps study_phi_res_deg, its contacts' value (presets::study_prism_params)
  double phi_res_deg = study_phi_res_deg;
  [[nodiscard]] bool mixed() const { return name == "mixed_mode"; }
};

/// Registers --law, --g-ii and --phi-res-deg.
inline void add_tie_law_flags(cli::parser& cli, tie_law& law) {
  cli.option("--law", law.name,
             "contact law of the tie's concrete (its Table 1 contacts, f_T 2.15 MPa, G_f 60 J/m^2 either way): study, "
             "the study's (power or --softening linear, --cohesion); mixed_mode, one damage for tension and shear "
             "driven by the plastic opening and slip over G_f and --g-ii (presets::mixed_mode_tie_law: linear "
             "softening; deformable blocks, explicit pull)",
             "study|mixed_mode").one_of({"study", "mixed_mode"});
  cli.option("--g-ii", law.g_ii,
             "mode-II fracture energy G_II (J/m^2) with --law mixed_mode (0 = (c_0/f_T) G_f, 120; the beam's "
             "mixed-mode set: 70)",
             "J").within(0, 1e6);
  cli.option("--phi-res-deg", law.phi_res_deg,
             "friction angle phi_res of a spent contact (deg) with --law mixed_mode (the study's 30; at most phi_0 = "
             "35; the beam's less-friction set: 15)",
             "DEG").within(0, 35);
}

/// Refuses the flags that do not apply with the law: with mixed_mode the study law's variants
/// (--softening, --cohesion, --slip-breaks-tension), --params (calibrate fits the study's law),
/// --rigid and --scheme relaxation (the mixed-mode tie is built on deformable blocks, explicit
/// pull); with study, --g-ii. Throws invalid_input "rc_tie: <flag and value> applies to --law ...".
inline void require_tie_law_flags(const cli::parser& cli, const tie_law& law, const tie_loading& loading,
                                  const tie_options& tie, const std::string& params, const std::string& scheme) {
  const char* d = "rc_tie";
  if (!law.mixed()) {
    require(!cli.given("--g-ii"), d, ": --g-ii ", law.g_ii, " J/m^2 applies to --law mixed_mode only (--law ", law.name,
            " has no G_II)");
    require(!cli.given("--phi-res-deg"), d, ": --phi-res-deg ", law.phi_res_deg,
            " applies to --law mixed_mode only (--law ", law.name, " keeps the study's 30 deg)");
    return;
  }
  const char* only = " applies to --law study only (--law mixed_mode ";
  require(!cli.given("--softening"), d, ": --softening ", loading.softening, only, "softens linearly over G_f)");
  require(!cli.given("--cohesion"), d, ": --cohesion ", loading.cohesion, only,
          "softens its cohesion with the same damage as f_t)");
  require(!cli.given("--slip-breaks-tension"), d, ": --slip-breaks-tension", only,
          "breaks tension and shear together with its one damage)");
  require(params.empty(), d, ": --params ", params, only, "has no calibrated entry: calibrate fits the study's law)");
  require(!tie.rigid, d, ": --rigid", only, "is built on deformable blocks)");
  require(scheme != "relaxation", d, ": --scheme ", scheme, only, "is built for the explicit pull)");
}

/// The mixed-mode contacts of `scene` (its Table 1 contacts with law.g_ii and law.phi_res_deg),
/// validated: throws invalid_input naming a G_II below the law's bound c_0^2 / (2 k_s).
[[nodiscard]] inline presets::mixed_mode_tie_law::params mixed_tie_contacts(const tie_scene& scene, const tie_law& law) {
  auto p = presets::with_mixed_mode(scene.prism.contact, law.g_ii);
  p.shear.phi_res = tessera::law::friction_angle::from_degrees(law.phi_res_deg);  // study_phi_res_deg: the preset's own bits
  presets::mixed_mode_tie_law::validate(p);
  return p;
}

/// The G_II (J/m^2) the run's contacts take; NaN with the study's law.
[[nodiscard]] inline real g_ii_in_effect(const tie_scene& scene, const tie_law& law) {
  return law.mixed() ? mixed_tie_contacts(scene, law).shear.G_II : std::numeric_limits<real>::quiet_NaN();
}

/// run_tie (rc_tie_run.hpp) with the law: the study's and its variants by tie_loading, or the
/// mixed-mode law on deformable blocks by the explicit pull (Relaxed refused).
template <bool Relaxed, class OnEvent>
[[nodiscard]] tie_result run_tie_with_law(const tie_scene& scene, const tie_loading& loading, const tie_law& law,
                                          OnEvent&& on_event) {
  if (!law.mixed()) return run_tie<Relaxed>(scene, loading, std::forward<OnEvent>(on_event));
  require(!Relaxed && !scene.options.rigid, "rc_tie: --law mixed_mode is built on deformable blocks, explicit pull");
  if constexpr (Relaxed) {
    return {};
  } else {
    return run_tie<deformable_blocks, presets::mixed_mode_tie_law>(scene, mixed_tie_contacts(scene, law), loading,
                                                                   std::forward<OnEvent>(on_event));
  }
}

/// "power softening", "linear softening" or "mixed-mode law, G_II 70 J/m^2" (plot title, report).
[[nodiscard]] inline std::string tie_law_text(const tie_scene& scene, const tie_law& law, const tie_loading& loading) {
  if (!law.mixed()) return loading.softening + " softening";
  std::string text = tessera::detail::concat("mixed-mode law, G_II ", g_ii_in_effect(scene, law), " J/m^2");
  if (law.phi_res_deg != study_phi_res_deg) text += tessera::detail::concat(", phi_res ", law.phi_res_deg, " deg");
  return text;
}

/// summary.json's law: "law", "g_ii_J_per_m2" (null with the study's), "phi_res_deg" (the contacts'
/// residual friction, deg), and "softening" and "cohesion"
/// as the mixed law has them (linear; coupled: c / c_0 = f_t / f_T = 1 - D).
inline void set_tie_law_figures(io::summary_json& js, const tie_scene& scene, const tie_law& law,
                                const tie_loading& loading) {
  js.set("law", law.name)
      .set("g_ii_J_per_m2", g_ii_in_effect(scene, law))
      .set("phi_res_deg", law.phi_res_deg)
      .set("softening", law.mixed() ? std::string("linear") : loading.softening)
      .set("cohesion", law.mixed() ? std::string("coupled") : loading.cohesion);
}

}  // namespace tessera::scenes
