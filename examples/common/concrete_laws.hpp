#pragma once
// The contact laws of the drivers' concrete (issue #63) as ONE table: every name, its one-line
// description, the parameters it takes beyond the study's set, which of them calibrate --targets
// can fit, and whether calibrate and calibrated.json take the law at all. Read by the --law flag
// and its help (concrete_set.hpp add_law_flags for compression and rc_beam, brazilian's own
// parser), rc_beam's check_beam_law, the concrete set (concrete_set.hpp with_concrete),
// calibrate --targets and calibrated.json's check (calibration.hpp). Adding a law: a row here,
// its recipe in with_concrete and its solver in rc_beam's run_beam (beam_run.hpp).
//
// | law            | G_II | G_c, residual cap, crush_shear             | in calibrated.json      | --fit beyond the common ones |
// |----------------|------|--------------------------------------------|-------------------------|------------------------------|
// | study          |      |                                            |                         |                              |
// | slip_softening | yes  |                                            | G_II                    | gii                          |
// | crushing       | yes  | yes (G_c 0 = 20000 J/m^2)                  | all four                | gii, gc                      |
// | mixed_mode     | yes  | yes, beside G_c > 0 (G_c 0 = the plastic cap) | G_II                 | gii                          |
//
// The common --fit parameters (strength, cohesion, phi0, phires, energy; cap with the beam's
// concrete) apply to every law (calibrate/targets.hpp).

#include <string>
#include <string_view>
#include <vector>

#include "tessera/core/errors.hpp"

namespace tessera::scenes {

/// A contact-law parameter beyond the study's set (bits of concrete_law::parameters and ::fits).
enum law_parameter : unsigned {
  law_g_ii = 1,          ///< mode-II fracture energy G_II (J/m^2)
  law_g_c = 2,           ///< compressive fracture energy G_c (J/m^2)
  law_cap_residual = 4,  ///< residual cap / cap
  law_crush_shear = 8,   ///< the shear limit scaled by the cap's remaining fraction
};

/// One law parameter: its driver flag, its calibrated.json key, its symbol in messages and its
/// calibrate --targets --fit name (empty: not fitted).
struct law_parameter_row {
  law_parameter id;
  const char* flag;
  const char* key;
  const char* symbol;
  const char* fit;
};
inline constexpr law_parameter_row law_parameter_rows[] = {
    {law_g_ii, "--g-ii", "G_II_J_per_m2", "G_II", "gii"},
    {law_g_c, "--g-c", "G_c_J_per_m2", "G_c", "gc"},
    {law_cap_residual, "--cap-residual", "cap_residual", "residual cap", ""},
    {law_crush_shear, "--crush-shear", "crush_shear", "crush_shear", ""}};

/// One contact law of the concrete (file comment).
struct concrete_law {
  const char* name;         ///< the --law value and calibrated.json's "law"
  const char* description;  ///< one line, for --law's help
  bool beam_only;           ///< the prism's concrete has the study's law only
  unsigned parameters;      ///< law_parameter bits it takes
  const char* g_ii_default; ///< what --g-ii 0 means with this law (parameters has law_g_ii)
  const char* g_c_zero;     ///< what --g-c 0 means with this law (parameters has law_g_c)
  bool crush_needs_g_c;     ///< --cap-residual and --crush-shear only beside --g-c > 0 (G_c 0: a cap that does not soften)
  unsigned in_file;         ///< law_parameter bits calibrated.json carries for it (calibrate writes, --params reads)
  unsigned fits;            ///< law_parameter bits calibrate --targets --fit may move
  bool calibrate;           ///< calibrate --targets --law and calibrated.json take it
  bool variants;            ///< rc_beam builds it with --compression elastic, --cohesion coupled, --slip-breaks-tension
};
inline constexpr concrete_law concrete_laws[] = {
    {"study", "the beam's (presets::study_beam_law: Coulomb shear that drops to c_res, phi_res at the first slip)",
     false, 0, "", "", false, 0, 0, true, true},
    {"slip_softening", "cohesion and friction soften with plastic slip over --g-ii (presets::slip_softening_beam_law)",
     true, law_g_ii, "500", "", false, law_g_ii, law_g_ii, true, false},
    {"crushing", "slip_softening whose cap --cap also softens with the plastic closure over --g-c "
     "(presets::crushing_beam_law)", true, law_g_ii | law_g_c | law_cap_residual | law_crush_shear, "500", "20000",
     false, law_g_ii | law_g_c | law_cap_residual | law_crush_shear, law_g_ii | law_g_c, true, false},
    {"mixed_mode", "one damage for tension and shear, driven by the plastic opening and slip over G_f and --g-ii "
     "(presets::mixed_mode_beam_law; with --g-c > 0 its cap softens with crushing too: presets::mixed_crushing_beam_law)",
     true, law_g_ii | law_g_c | law_cap_residual | law_crush_shear, "(c_0/f_T) G_f, 120 for the beam's contacts",
     "the plastic cap, which does not soften", true, law_g_ii, law_g_ii, true, false}};

/// The row of law `name`, or nullptr.
[[nodiscard]] inline const concrete_law* find_concrete_law(std::string_view name) {
  for (const concrete_law& l : concrete_laws)
    if (name == l.name) return &l;
  return nullptr;
}
/// The row of parameter p.
[[nodiscard]] inline const law_parameter_row& law_parameter_named(law_parameter p) {
  for (const law_parameter_row& r : law_parameter_rows)
    if (r.id == p) return r;
  throw invalid_input("concrete laws: unknown parameter");
}

/// The laws' names (for cli::parser::one_of).
[[nodiscard]] inline std::vector<std::string> concrete_law_names() {
  std::vector<std::string> v;
  for (const concrete_law& l : concrete_laws) v.emplace_back(l.name);
  return v;
}

/// "a, b, c or d" of the laws whose row passes keep(row) (every law by default).
template <class Keep>
[[nodiscard]] std::string concrete_law_list(Keep&& keep) {
  std::vector<const char*> names;
  for (const concrete_law& l : concrete_laws)
    if (keep(l)) names.push_back(l.name);
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i)
    s += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + std::string(names[i]);
  return s;
}
[[nodiscard]] inline std::string concrete_law_list() {
  return concrete_law_list([](const concrete_law&) { return true; });
}

/// The row of law `name`; throws invalid_input "`who`: law 'name' must be study, ..." otherwise.
[[nodiscard]] inline const concrete_law& concrete_law_named(std::string_view name, std::string_view who) {
  if (const concrete_law* l = find_concrete_law(name)) return *l;
  throw invalid_input(tessera::detail::concat(who, ": law '", name, "' must be ", concrete_law_list()));
}

/// Whether law `name` takes parameter p (false for an unknown law).
[[nodiscard]] inline bool law_takes(std::string_view name, law_parameter p) {
  const concrete_law* l = find_concrete_law(name);
  return l != nullptr && (l->parameters & p) != 0;
}

/// "a, b or c": the laws that take parameter p.
[[nodiscard]] inline std::string laws_taking(law_parameter p) {
  return concrete_law_list([p](const concrete_law& l) { return (l.parameters & p) != 0; });
}

/// Whether calibrated.json carries parameter p for law `name` (false for an unknown law).
[[nodiscard]] inline bool law_in_file(std::string_view name, law_parameter p) {
  const concrete_law* l = find_concrete_law(name);
  return l != nullptr && (l->in_file & p) != 0;
}
/// "a, b or c": the laws whose calibrated.json entry carries parameter p.
[[nodiscard]] inline std::string laws_in_file_taking(law_parameter p) {
  return concrete_law_list([p](const concrete_law& l) { return (l.in_file & p) != 0; });
}

/// Refuses parameter p given (`given`) with law `law` that does not take it: throws invalid_input
/// "`driver`: `shown` applies to --law <the laws that take it> only (--law `law` has no <symbol>)";
/// `shown` is the flag as the user gave it (e.g. "--g-ii 100 J/m^2"), empty = the parameter's flag.
inline void require_law_takes(std::string_view driver, const std::string& law, law_parameter p, bool given,
                              std::string_view shown = {}) {
  if (!given || law_takes(law, p)) return;
  const law_parameter_row& r = law_parameter_named(p);
  throw invalid_input(tessera::detail::concat(
      driver, ": ", shown.empty() ? std::string_view(r.flag) : shown, " applies to --law ", laws_taking(p),
      " only (--law ", law, " has no ", r.symbol, ")"));
}

/// Refuses the law parameters given (given(flag): whether the user gave that flag) with law `law` that
/// does not take them, and --cap-residual or --crush-shear with a law whose cap softens only beside
/// --g-c > 0 (`g_c`, J/m^2) when --g-c is 0: throws invalid_input naming the flag, the law and G_c.
/// --g-ii is require_g_ii_with_law's (with its value).
template <class Given>
void require_law_parameters(std::string_view driver, const std::string& law, double g_c, Given&& given) {
  const concrete_law* l = find_concrete_law(law);
  for (const law_parameter_row& r : law_parameter_rows) {
    if (r.id == law_g_ii) continue;
    require_law_takes(driver, law, r.id, given(r.flag));
    if (r.id != law_g_c && given(r.flag) && l != nullptr && l->crush_needs_g_c && !(g_c > 0))
      throw invalid_input(tessera::detail::concat(driver, ": ", r.flag, " with --law ", law, " needs --g-c > 0 (got --g-c ",
                                                  g_c, ": ", l->g_c_zero, ")"));
  }
}

/// Refuses --g-ii `g_ii` (J/m^2; 0 = not given) with a law without G_II, naming the value.
inline void require_g_ii_with_law(std::string_view driver, const std::string& law, double g_ii) {
  require_law_takes(driver, law, law_g_ii, g_ii != 0, tessera::detail::concat("--g-ii ", g_ii, " J/m^2"));
}

/// --law's help: every law with its description.
[[nodiscard]] inline std::string law_flag_help() {
  std::string s = "contact law of the beam's concrete:";
  for (const concrete_law& l : concrete_laws)
    s += tessera::detail::concat(&l == concrete_laws ? " " : "; ", l.name, ", ", l.description);
  return s;
}
/// " a (0 = x), b (0 = y)": the laws that take parameter p, each with what 0 means (its `zero` field).
[[nodiscard]] inline std::string laws_with_zero(law_parameter p, const char* concrete_law::*zero) {
  std::string s;
  for (const concrete_law& l : concrete_laws)
    if ((l.parameters & p) != 0) s += tessera::detail::concat(s.empty() ? " " : ", ", l.name, " (0 = ", l.*zero, ")");
  return s;
}
/// --g-ii's help: the laws that take G_II and what 0 means with each.
[[nodiscard]] inline std::string g_ii_flag_help() {
  return "mode-II fracture energy G_II (J/m^2) with --law" + laws_with_zero(law_g_ii, &concrete_law::g_ii_default);
}

/// --g-c's, --cap-residual's and --crush-shear's help (the laws that take each).
[[nodiscard]] inline std::string g_c_flag_help() {
  return "compressive fracture energy G_c, the plastic work per contact area above the residual cap (J/m^2), with "
         "--law" + laws_with_zero(law_g_c, &concrete_law::g_c_zero);
}
/// " (mixed_mode: beside --g-c > 0)": the laws whose crushing flags need G_c > 0.
[[nodiscard]] inline std::string crush_flags_note() {
  const std::string laws = concrete_law_list([](const concrete_law& l) { return l.crush_needs_g_c; });
  return laws.empty() ? std::string() : tessera::detail::concat(" (", laws, ": beside --g-c > 0)");
}
[[nodiscard]] inline std::string cap_residual_flag_help() {
  return tessera::detail::concat("residual cap with --law ", laws_taking(law_cap_residual), crush_flags_note(),
                                 ", a fraction of --cap (0.1)");
}
[[nodiscard]] inline std::string crush_shear_flag_help() {
  return tessera::detail::concat("with --law ", laws_taking(law_crush_shear), crush_flags_note(),
                                 ": the shear limit (mixed_mode: its Coulomb limit in compression) falls with the cap's "
                                 "remaining fraction too");
}

}  // namespace tessera::scenes
