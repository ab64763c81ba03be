#pragma once
// rc_beam's contact law (issue #63): --law (a law of common/concrete_laws.hpp), --g-ii, --phi-deg,
// --phi-res-deg, --cap and --cohesion-ratio on the beam's concrete (beam_options; registered by
// add_beam_law_flags here through concrete_set.hpp add_law_flags, as compression's); what rc_beam
// refuses with them (beam.hpp check_beam_law, check_beam_law_flags here); and the summary keys
// that record the law a run used.
//
//   study           presets::study_beam_law: linear tension softening, the plastic cap, Coulomb
//                   shear that drops to (c_res, phi_res) at the first slip (the study's)
//   slip_softening  presets::slip_softening_beam_law: the same tension and cap, cohesion and
//                   friction softening linearly with the plastic slip from (c_0, phi_0) to
//                   (c_res, phi_res) over s_u = 2 G_II / (c_0 - c_res) (docs/model.md)
//   crushing        presets::crushing_beam_law: slip_softening whose cap --cap softens linearly with
//                   the plastic closure to --cap-residual x --cap over G_c (--g-c); --crush-shear
//                   scales the shear limit by the cap's remaining fraction (law::softening_cap)
//   mixed_mode      presets::mixed_mode_beam_law (presets/mixed_mode.hpp): one damage for tension and
//                   shear, grown by the plastic opening over G_f and the plastic slip over G_II
//                   (--g-ii; 0 = (c_0/f_T) G_f), the same cap; c_res 0 (docs/model.md)
//
// In pure tension the two laws are the same law. The hand values (cracking, yield, EC2's and
// Zsutty's shear) keep the concrete's f_c = 35 MPa whatever --cap the contacts take: the cap is a
// contact parameter, and with the slip-softening set of the compression meeting (phi_0 58 deg,
// phi_res 15 deg, G_II 300 J/m^2, cap 100 MPa) the cylinder's f_c is 35.0-38.9 MPa.

#include <limits>
#include <string>

#include "common/cli.hpp"
#include "common/concrete_set.hpp"
#include "common/scenes.hpp"
#include "rc_beam/beam.hpp"
#include "tessera/io/json.hpp"

namespace tessera::scenes {

/// The flags --params replaces: the file sets the concrete.
inline constexpr const char* beam_law_flags[] = {"--law", "--g-ii", "--phi-deg", "--phi-res-deg", "--cap",
                                                 "--g-c", "--cap-residual", "--crush-shear", "--cohesion-ratio"};

/// Registers rc_beam's concrete flags on `cli` for beam `b`: add_law_flags' (--law, --g-ii, --g-c,
/// --cap-residual, --crush-shear, --phi-deg, --phi-res-deg, --cap) and add_cohesion_ratio_flag's
/// --cohesion-ratio (c_0 / f_T, as compression and brazilian take it).
inline void add_beam_law_flags(cli::parser& cli, beam_options& b) {
  add_law_flags(cli, b, "the hand values keep the concrete's 35 MPa");
  add_cohesion_ratio_flag(cli, b.cohesion_ratio);
}

/// Set c's concrete on beam o: law, strength and fracture-energy scales, c_0 / f_T, phi_0, phi_res
/// (deg), G_II (J/m^2), cap (Pa), G_c (J/m^2), residual cap, crush_shear; o's block count, zoning,
/// geometry, bars and seed stay (rc_beam --params and calibrate's shear target: the same beam).
inline void concrete_set_to(const concrete_set& c, beam_options& o) {
  o.law = c.law;
  o.strength_scale = c.scale();
  o.fracture_energy_scale = c.fracture_energy_scale;
  o.cohesion_ratio = c.cohesion_ratio;
  o.phi_deg = c.phi_0_deg;
  o.phi_res_deg = c.phi_res_deg;
  o.g_ii = c.g_ii;
  o.cap = c.cap;
  o.g_c = c.g_c;
  o.cap_residual = c.cap_residual;
  o.crush_shear = c.crush_shear;
}

/// rc_beam --params FILE (`file`): the entry of calibrated.json for o's recipe (the beam material,
/// o.blocks, o's face zoning and this beam's half volume; refused with both values named otherwise,
/// load_concrete_params) with its whole concrete (law, strength and fracture-energy scales, c_0 /
/// f_T, phi_0, phi_res, G_II, cap) applied to o through concrete_set. rate: the plate's (m/s, for the
/// note on the fitted rate). Returns the entry's initial modulus (Pa; 0 = not recorded).
inline real load_beam_params(beam_options& o, const std::string& file, real rate) {
  concrete_set c;
  c.recipe_blocks = o.blocks;
  c.zone_edge = o.face_zone_edge();
  // the step is set later by the mass scaling (0: the note gives the fitted one)
  const calibration_entry e = load_concrete_params(c, file, 0, rate, "rc_beam", o.half_volume());
  concrete_set_to(c, o);
  return e.initial_modulus;
}

/// Refuses a law flag (beam_law_flags) given beside --params `params`: the file sets the concrete;
/// and a law parameter's flag with a --law `law` that does not take it, or beside --g-c `g_c` (J/m^2) 0
/// where the law needs it (require_law_flags). Throws invalid_input naming the flag and the file or law.
inline void check_beam_law_flags(const cli::parser& cli, const std::string& params, const std::string& law, real g_c) {
  for (const char* flag : beam_law_flags)
    require(params.empty() || !cli.given(flag), "rc_beam: ", flag, " with --params ", params,
            ": the file sets the concrete (drop the flag)");
  require_law_flags(cli, "rc_beam", law, g_c);
}

/// The refusals of check_beam_law on the study's contacts for o.blocks with o's law set and
/// scales (the flags', or a --params file's), before anything is built. Throws invalid_input
/// naming the value.
inline void check_beam_law_set(const beam_options& o) {
  require_calibration_scales(o, "rc_beam");
  auto c = presets::study_beam_params(o.blocks >= 500 ? 500 : 250);
  scale_beam_contacts(c, o.strength_scale, o.fracture_energy_scale);
  apply_concrete_shear(c, o.cohesion_ratio, o.phi_deg, o.phi_res_deg, o.cap);
  check_beam_law(o, c);
}

/// summary.json's law keys: law, g_ii_J_per_m2 and softening_slip_m (l_II = 2 G_II / c_0 with
/// mixed_mode; null for the study's law), G_c_J_per_m2, cap_residual and crush_shear (null, null,
/// false but with law crushing, or mixed_mode and --g-c > 0),
/// phi_0_deg, phi_res_deg, cap_Pa, contact_c_0_Pa, contact_c_res_Pa of the scene's contacts (after
/// calibration), plate_friction_deg.
inline void set_beam_law_figures(io::summary_json& js, const beam_scene& s) {
  const beam_options& o = s.options;
  const bool slip = o.law == "slip_softening" || o.law == "crushing", mixed = o.law == "mixed_mode";
  const bool crush = o.law == "crushing" || (mixed && o.g_c > 0);  // a cap softening with crushing
  const real none = std::numeric_limits<real>::quiet_NaN();
  const real g_ii = slip ? g_ii_or_default(o.g_ii) : mixed ? presets::with_mixed_mode(s.contact, o.g_ii).shear.G_II : none;
  js.set("law", o.law)
      .set("g_ii_J_per_m2", g_ii)
      .set("G_c_J_per_m2", crush ? (o.g_c > 0 ? o.g_c : default_g_c) : none)
      .set("cap_residual", crush ? o.cap_residual : none)
      .set("crush_shear", crush && o.crush_shear)
      .set("softening_slip_m", slip ? 2 * g_ii / (s.contact.shear.c_0 - s.contact.shear.c_res) : mixed ? 2 * g_ii / s.contact.shear.c_0 : none)
      .set("phi_0_deg", s.contact.shear.phi_0.degrees())
      .set("phi_res_deg", s.contact.shear.phi_res.degrees())
      .set("cap_Pa", s.contact.compression.f_c)
      .set("contact_c_0_Pa", s.contact.shear.c_0)
      .set("contact_c_res_Pa", s.contact.shear.c_res)
      .set("plate_friction_deg", beam_plate_friction_deg);
}

/// The run's law and calibration for rc_beam's report line: empty for the study's law verbatim.
[[nodiscard]] inline std::string beam_law_label(const beam_options& o, bool calibrated) {
  std::string label = calibrated ? tessera::detail::concat(" (contact strength x ", o.strength_scale, ")") : "";
  if (o.law == "slip_softening")
    label += tessera::detail::concat(", slip-softening law (G_II ", g_ii_or_default(o.g_ii), " J/m^2)");
  if (o.law == "crushing")
    label += tessera::detail::concat(", crushing law (G_II ", g_ii_or_default(o.g_ii), " J/m^2, G_c ",
                                     o.g_c > 0 ? o.g_c : default_g_c, " J/m^2, residual cap ", o.cap_residual,
                                     o.crush_shear ? ", shear scaled" : "", ")");
  if (o.law == "mixed_mode") label += ", mixed-mode law";
  if (o.law == "mixed_mode" && o.g_c > 0)
    label += tessera::detail::concat(" (cap softening over G_c ", o.g_c, " J/m^2 to ", o.cap_residual,
                                     o.crush_shear ? ", shear scaled" : "", ")");
  if (o.phi_deg != 35 || o.phi_res_deg != 30 || o.cap != 35e6)
    label += tessera::detail::concat(", phi_0 ", o.phi_deg, " deg, phi_res ", o.phi_res_deg, " deg, cap ", o.cap * 1e-6,
                                     " MPa");
  return label;
}

}  // namespace tessera::scenes
