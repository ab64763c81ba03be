#pragma once
// calibrated.json: the strength (and fracture-energy) scales examples/calibrate fits for a prism
// recipe, one entry per block count (DESIGN.md §5), and how the drivers load it (--params FILE).
//
//   {
//     "format": "tessera-calibration-1",
//     "recipe": {"material": "prism", "softening": "power", "cohesion_ratio": 2,
//                "step_displacement_m": 2e-09, "rate_m_per_s": 0.005, "rigid": false,
//                "zone_edge_m": 0, "beam_volume_m3": 0},
//     "entries": [
//       {"blocks": 100, "strength_scale": 0.91, "fracture_energy_scale": 1, "seeds": [1, 2, 3],
//        "iterations": 3, "peak_mean_Pa": 2.151e6, "peak_spread_rel": 0.02,
//        "initial_modulus_mean_Pa": 2.9e10, ...},
//       ...
//     ]
//   }
//
// strength_scale multiplies the contacts' Table 1 tensile strength and with it the cohesion
// (c_0 = cohesion_ratio x scaled f_T); fracture_energy_scale multiplies the contacts' G_f;
// initial_modulus_mean_Pa (optional) is the mean initial modulus of the fit's last pulls, the
// stiffness the contacts' k_n gives these blocks (rc_beam's hand stiffness at the model's own
// modulus). The reference values the drivers check against stay the concrete's f_T and G_f. A
// driver refuses a file whose recipe's law differs from its own (softening, cohesion ratio, rigid
// blocks): the scales would not mean the same thing; it prints a note when only the step or rate
// differ.
//
// material: "prism" = the study's prism concrete (Table 1 contacts, 100-750 blocks; direct_tension,
// rc_tie), "beam" = the beam's concrete (study_beam_params, fitted on the beam-recipe prism of
// rc_beam/beam.hpp make_beam_prism; entries keyed by the beam's block count; rc_beam). zone_edge_m:
// the zoning's target face edge the fit used (0 = one zone per face triangle, the prism's), which
// sets the sub-contacts' density; a driver refuses a file fitted at another. beam_volume_m3: the
// beam recipe's half-beam volume (the default beam's dimensions), whose cell volume the prism's
// blocks have; rc_beam refuses a file fitted for another (0 = not recorded, the prism's). Files
// written before these fields existed are read as "prism", 0 and 0.
//
// The concrete of an entry (calibrate --targets writes every field; each is optional, an absent
// one is the study's): "law" (a law of concrete_laws.hpp whose row has calibrate: "study" |
// "slip_softening" | "crushing" | "mixed_mode", all but study beam only), "cohesion_ratio" (c_0 / f_T;
// absent: the recipe's), "phi_0_deg", "phi_res_deg" (absent: 35, 30), "G_II_J_per_m2" (the laws that
// take G_II: slip_softening, crushing, mixed_mode; required, in [1e-3, 1e6] J/m^2, and above the
// law's own bound c_0^2 / (2 k_s), checked when the driver builds the contacts; refused with the
// study's law), "cap_Pa" (the contacts' compressive cap
// f_c; beam only, absent: 35 MPa), with crushing "G_c_J_per_m2" (the compressive fracture energy,
// required), "cap_residual" (the residual cap over the cap, in [0, 1]; absent: 0.1) and
// "crush_shear" (true: the shear limit falls with the cap; absent: false).
// brazilian, compression, rc_beam and direct_tension --material beam --params apply the whole set
// (load_concrete); rc_tie and direct_tension with the prism's concrete apply the two scales only
// (load_calibration) and so refuse an entry whose set is not the study's, naming the field.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "common/scenes.hpp"
#include "tessera/core/errors.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/json_reader.hpp"

namespace tessera::scenes {

inline constexpr const char* calibration_format = "tessera-calibration-1";
/// Scales outside this range are refused on reading: a fit that needs them has gone wrong.
inline constexpr real min_calibration_scale = 0.1, max_calibration_scale = 10;

struct calibration_recipe {
  std::string softening = "power";  ///< "power" or "linear"
  real cohesion_ratio = 2;
  real step_displacement = 2e-9;  ///< m
  real rate = 0.005;              ///< m/s
  bool rigid = false;
  std::string material = "prism";   ///< "prism" or "beam" (the file comment)
  real zone_edge = 0;               ///< m; 0 = one zone per face triangle
  real beam_volume = 0;             ///< m^3; beam recipe: the half beam's volume, 0 = not recorded
};

struct calibration_entry {
  int blocks = 100;
  real strength_scale = 1;
  real fracture_energy_scale = 1;
  /// The recipe prism's mean initial modulus at the fitted scales (Pa; 0 = not recorded, files
  /// written before it existed): the modulus the contacts' stiffness gives these blocks.
  real initial_modulus = 0;
  // The concrete beyond the scales (file comment); the defaults are the study's.
  std::string law = "study";  ///< a law of concrete_laws.hpp (all but study beam only)
  real cohesion_ratio = 0;    ///< c_0 / f_T; 0 = the recipe's (files without the field)
  real phi_0_deg = 35, phi_res_deg = 30;  ///< contact friction angles (deg)
  real g_ii = 0;              ///< mode-II fracture energy (J/m^2) of a law that takes it
  real cap = 35e6;            ///< the contacts' compressive cap f_c (Pa), beam only
  real g_c = 0;               ///< compressive fracture energy (J/m^2), crushing only
  real cap_residual = 0.1;    ///< residual cap / cap, crushing only
  bool crush_shear = false;   ///< crushing only: the shear limit times the cap's remaining fraction
};

/// The study's value of the first field of entry e (of recipe r) that a driver applying the scales
/// only would ignore, as "name = value (the study's: x)"; empty when the set is the study's.
[[nodiscard]] inline std::string non_study_field(const calibration_entry& e, const calibration_recipe& r) {
  using tessera::detail::concat;
  if (e.law != "study") return concat("law = ", e.law, " (the study's: study)");
  if (e.cohesion_ratio != 0 && std::abs(e.cohesion_ratio - r.cohesion_ratio) > 1e-12 * r.cohesion_ratio)
    return concat("cohesion_ratio = ", e.cohesion_ratio, " (the recipe's: ", r.cohesion_ratio, ")");
  if (e.phi_0_deg != 35) return concat("phi_0_deg = ", e.phi_0_deg, " (the study's: 35)");
  if (e.phi_res_deg != 30) return concat("phi_res_deg = ", e.phi_res_deg, " (the study's: 30)");
  if (r.material == "beam" && e.cap != 35e6) return concat("cap_Pa = ", e.cap, " (the study's: 3.5e+07)");
  return {};
}

struct calibration {
  calibration_recipe recipe;
  std::vector<calibration_entry> entries;

  /// The entry for `blocks`; throws invalid_input listing the block counts the file has.
  [[nodiscard]] const calibration_entry& entry_for(int blocks, const std::string& file) const {
    std::string have;
    for (const calibration_entry& e : entries) {
      if (e.blocks == blocks) return e;
      have += (have.empty() ? "" : ", ") + std::to_string(e.blocks);
    }
    throw invalid_input(tessera::detail::concat(file, " has no entry for ", blocks, " blocks (it has ", have,
                                                "); run examples/calibrate with --blocks ", blocks));
  }
};

namespace calibration_checks {
inline real scale_in_range(const io::json_value& v) {
  const real x = v.number();
  if (!(x >= min_calibration_scale && x <= max_calibration_scale))
    throw io_error(tessera::detail::concat(v.path(), " = ", x, " must lie in [", min_calibration_scale, ", ",
                                           max_calibration_scale, "]"));
  return x;
}
/// x's concrete fields from entry e of a `material` file (file comment; absent = the study's).
inline void read_concrete_fields(const io::json_value& e, const std::string& material, calibration_entry& x) {
  const auto number_in = [&](const char* key, real lo, real hi, real& to) {
    const io::json_value* v = e.find(key);
    if (v == nullptr) return;
    to = v->number();
    if (!(to >= lo && to <= hi)) throw io_error(tessera::detail::concat(v->path(), " = ", to, " must lie in [", lo, ", ", hi, "]"));
  };
  if (const io::json_value* v = e.find("law")) {
    x.law = v->string();
    const concrete_law* law = find_concrete_law(x.law);
    if (law == nullptr || !law->calibrate)
      throw io_error(tessera::detail::concat(v->path(), " = '", x.law, "' must be ",
                                             concrete_law_list([](const concrete_law& l) { return l.calibrate; })));
    if (law->beam_only && material != "beam")
      throw io_error(tessera::detail::concat(v->path(), " = '", x.law, "' is built for the beam recipe, this file's is '",
                                             material, "'"));
  }
  number_in("cohesion_ratio", 0.1, 20, x.cohesion_ratio);
  number_in("phi_0_deg", 0, 80, x.phi_0_deg);
  number_in("phi_res_deg", 0, x.phi_0_deg, x.phi_res_deg);
  // The law's own parameters (concrete_laws.hpp): G_II and G_c required where the law takes them (the
  // file says the value the fit ran, never a default that would move with the scales); a parameter of
  // another law refused, naming the key and the entry's law (null and false read as absent).
  for (const law_parameter_row& r : law_parameter_rows) {
    const io::json_value* v = e.find(r.key);
    if (!law_in_file(x.law, r.id)) {
      if (v != nullptr && !v->is_null() && !(v->type() == io::json_value::kind::boolean && !v->boolean()))
        throw io_error(tessera::detail::concat(v->path(), ": applies to law ", laws_in_file_taking(r.id),
                                               " only (this entry's law is ", x.law, ")"));
      continue;
    }
    if (r.id == law_g_ii || r.id == law_g_c) {
      real& to = r.id == law_g_ii ? x.g_ii : x.g_c;
      to = 0;
      number_in(r.key, 1e-3, r.id == law_g_ii ? 1e6 : 1e8, to);
      if (to == 0) throw io_error(tessera::detail::concat(e.path(), ": law ", x.law, " needs \"", r.key, "\""));
    } else if (r.id == law_cap_residual) {
      number_in(r.key, 0, 1, x.cap_residual);
    } else if (v != nullptr) {
      x.crush_shear = v->boolean();
    }
  }
  if (const io::json_value* v = e.find("cap_Pa"); v != nullptr && !v->is_null()) {
    if (material != "beam")
      throw io_error(tessera::detail::concat(v->path(), ": the ", material, " recipe's contacts have no compressive cap"));
    number_in("cap_Pa", 1e6, 1e10, x.cap);
  }
}
}  // namespace calibration_checks

/// Reads and checks calibrated.json (throws io_error naming the file and the field).
[[nodiscard]] inline calibration read_calibration(const std::filesystem::path& path) {
  const io::json_value doc = io::read_json(path);
  if (doc.at("format").string() != calibration_format)
    throw io_error(tessera::detail::concat(path.string(), ": format '", doc.at("format").string(), "', expected '",
                                           calibration_format, "'"));
  calibration c;
  const io::json_value& r = doc.at("recipe");
  c.recipe.softening = r.at("softening").string();
  if (c.recipe.softening != "power" && c.recipe.softening != "linear")
    throw io_error(tessera::detail::concat(r.at("softening").path(), " = '", c.recipe.softening,
                                           "' must be 'power' or 'linear'"));
  c.recipe.cohesion_ratio = r.at("cohesion_ratio").number();
  c.recipe.step_displacement = r.at("step_displacement_m").number();
  c.recipe.rate = r.at("rate_m_per_s").number();
  c.recipe.rigid = r.at("rigid").boolean();
  if (const io::json_value* m = r.find("material")) {
    c.recipe.material = m->string();
    if (c.recipe.material != "prism" && c.recipe.material != "beam")
      throw io_error(tessera::detail::concat(m->path(), " = '", c.recipe.material, "' must be 'prism' or 'beam'"));
  }
  if (const io::json_value* z = r.find("zone_edge_m")) {
    c.recipe.zone_edge = z->number();
    if (!(c.recipe.zone_edge >= 0 && c.recipe.zone_edge <= 1))
      throw io_error(tessera::detail::concat(z->path(), " = ", c.recipe.zone_edge, " must lie in [0, 1] m"));
  }
  if (const io::json_value* v = r.find("beam_volume_m3")) {
    c.recipe.beam_volume = v->number();
    if (!(c.recipe.beam_volume >= 0 && c.recipe.beam_volume <= 1e3))
      throw io_error(tessera::detail::concat(v->path(), " = ", c.recipe.beam_volume, " must lie in [0, 1000] m^3"));
  }
  for (const auto* v : {&r.at("cohesion_ratio"), &r.at("step_displacement_m"), &r.at("rate_m_per_s")})
    if (!(v->number() > 0)) throw io_error(tessera::detail::concat(v->path(), " = ", v->number(), " must be > 0"));
  for (const io::json_value& e : doc.at("entries").items()) {
    calibration_entry x;
    x.blocks = static_cast<int>(e.at("blocks").integer(1, 1'000'000));
    for (const calibration_entry& y : c.entries)
      if (y.blocks == x.blocks)
        throw io_error(tessera::detail::concat(e.at("blocks").path(), ": a second entry for ", x.blocks, " blocks"));
    x.strength_scale = calibration_checks::scale_in_range(e.at("strength_scale"));
    x.fracture_energy_scale = calibration_checks::scale_in_range(e.at("fracture_energy_scale"));
    if (const io::json_value* m = e.find("initial_modulus_mean_Pa")) {
      x.initial_modulus = m->number();
      if (!(x.initial_modulus >= 1e6 && x.initial_modulus <= 1e13))
        throw io_error(tessera::detail::concat(m->path(), " = ", x.initial_modulus, " must lie in [1e6, 1e13] Pa"));
    }
    calibration_checks::read_concrete_fields(e, c.recipe.material, x);
    c.entries.push_back(x);
  }
  if (c.entries.empty()) throw io_error(tessera::detail::concat(path.string(), ": \"entries\" is empty"));
  return c;
}

namespace calibration_checks {
/// The entry of `c` (read from `f`) for `blocks`, after checking its recipe against the run's
/// (load_calibration's checks bar the cohesion ratio).
[[nodiscard]] inline calibration_entry matching_entry(const calibration& c, const std::string& f, int blocks,
                                                      const calibration_recipe& run, const char* program) {
  require(c.recipe.material == run.material, program, ": ", f, " was fitted on the ", c.recipe.material,
          " recipe, this run needs the ", run.material, " recipe (examples/calibrate --material ", run.material, ")");
  require(c.recipe.softening == run.softening, program, ": ", f, " was fitted with ", c.recipe.softening,
          " softening, this run uses ", run.softening);
  require(c.recipe.rigid == run.rigid, program, ": ", f, " was fitted with ", c.recipe.rigid ? "rigid" : "deformable",
          " blocks, this run uses ", run.rigid ? "rigid" : "deformable", " ones");
  require(std::abs(c.recipe.zone_edge - run.zone_edge) <= 1e-12 * std::max(run.zone_edge, real(1e-3)), program, ": ", f,
          " was fitted with a face zoning edge of ", c.recipe.zone_edge, " m, this run uses ", run.zone_edge, " m");
  require(c.recipe.beam_volume == 0 || run.beam_volume == 0 ||
              std::abs(c.recipe.beam_volume - run.beam_volume) <= 1e-9 * run.beam_volume,
          program, ": ", f, " was fitted with the blocks of a half beam of ", c.recipe.beam_volume,
          " m^3 (the default dimensions), this beam is ", run.beam_volume,
          " m^3: its blocks have another size; calibrate has no geometry flags yet");
  const calibration_entry e = c.entry_for(blocks, f);
  if (run.step_displacement == 0)
    std::printf("%s: note: %s was fitted at %.3g m per step and %.3g m/s\n", program, f.c_str(),
                c.recipe.step_displacement, c.recipe.rate);
  else if (c.recipe.step_displacement != run.step_displacement || c.recipe.rate != run.rate)
    std::printf("%s: note: %s was fitted at %.3g m per step and %.3g m/s; this run uses %.3g m per step and %.3g m/s\n",
                program, f.c_str(), c.recipe.step_displacement, c.recipe.rate, run.step_displacement, run.rate);
  return e;
}

}  // namespace calibration_checks

/// A driver's --params FILE: the entry for its block count, after checking that the file was
/// fitted with the same law (throws invalid_input naming the mismatch). A different step or
/// rate is allowed (the scales were fitted at one; the peak moves a few per cent with the step,
/// docs/validation.md) and printed as a note on stdout; run.step_displacement = 0 says the run's
/// step is set later (by its mass scaling), and the note gives the fitted step only.
[[nodiscard]] inline calibration_entry load_calibration(const std::filesystem::path& file, int blocks,
                                                        const calibration_recipe& run, const char* program) {
  const calibration c = read_calibration(file);
  const std::string f = file.string();
  require(std::abs(c.recipe.cohesion_ratio - run.cohesion_ratio) <= 1e-12 * run.cohesion_ratio, program, ": ", f,
          " was fitted with cohesion ratio ", c.recipe.cohesion_ratio, ", this run uses ", run.cohesion_ratio);
  const calibration_entry e = calibration_checks::matching_entry(c, f, blocks, run, program);
  const std::string extra = non_study_field(e, c.recipe);
  require(extra.empty(), program, ": ", f, " entry for ", blocks, " blocks has ", extra, ", which ", program,
          " does not apply (it applies the strength and fracture-energy scales only; brazilian, compression and "
          "rc_beam --params apply the whole set)");
  return e;
}

/// brazilian's, compression's and rc_beam's --params FILE: the entry for the recipe's block count with its
/// whole concrete (law, scales, c_0 / f_T, phi_0, phi_res, G_II, cap), after the recipe checks of
/// load_calibration (material, softening, blocks, zoning, beam volume; throws invalid_input naming
/// both values). The entry's cohesion ratio is the file's (its recipe's when the entry has none).
[[nodiscard]] inline calibration_entry load_concrete(const std::filesystem::path& file, int blocks,
                                                     const calibration_recipe& run, const char* program) {
  const calibration c = read_calibration(file);
  calibration_entry e = calibration_checks::matching_entry(c, file.string(), blocks, run, program);
  if (e.cohesion_ratio == 0) e.cohesion_ratio = c.recipe.cohesion_ratio;
  return e;
}

}  // namespace tessera::scenes
