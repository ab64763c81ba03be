#pragma once
// calibrate --targets (issue #63 item 4): ONE concrete per recipe (material + block count + zoning)
// fitted to several targets at once, each evaluated by the drivers' own scene code:
//
//   tension      f_t: the mean peak of the recipe's direct tension prism (direct_tension/tension_test.hpp;
//                the study's 68 x 68 x 600 mm prism, or the beam recipe's 150 x 150 x 600 mm one) against
//                the concrete's f_T (default tolerance 5 %)
//   energy       G_f: the prism's dissipated energy per cross-section, run to separation (15 %)
//   splitting    f_sp / f_T of the Brazilian disc (brazilian/disc.hpp; EN 12390-6: the maximum load, the
//                split's) against the band [1.0, 1.4]: centre 1.2, relative tolerance 1/6
//   compression  f_c of the compression specimen (compression/run.hpp, frictionless ends) against
//                --f-c (35 MPa, the beam's concrete; 15 %), and its peak strain against [1.5e-3, 3.5e-3]
//                (centre 2.5e-3, relative tolerance 0.4) as a second residual of the same weight
//   shear        P at failure of rc_beam with bars that cannot yield (rc_beam/beam_shear_figure.hpp: the
//                60-block beam, 50 mm zoning, 10 mm/s, to 12 mm at most; --shear-* flags) against the
//                mean of EC2's and Zsutty's 2 V_c (51.69 kN for the default beam; 20 %), the set's
//                concrete on the beam's own block count and zoning (material beam only: rc_beam runs
//                the beam's concrete); about 100 s of CPU a seed, docs/studies/multi_target_calibration.md.
//
// Each residual is r = (mean over the seeds / reference - 1) / tolerance; met when |r| <= 1. A target
// whose run did not reach its event on every seed (no split by the disc's last displacement, no
// compression peak by the last strain, no separation with the energy target, no failure of the beam
// by its last deflection) is NOT met and enters the objective as r = 10, never as the value at the cap.
//
// The law (--law) is any row of common/concrete_laws.hpp with calibrate set: study, slip_softening,
// crushing, mixed_mode; its row says which law parameters --fit may move (gii, gc), and the set's
// G_II starts at the law's default when --g-ii is 0 (mixed_mode: (c_0/f_T) G_f of the contacts).
//
// Search: compass (coordinate pattern) search on J = sum_i w_i r_i^2 over the parameters of --fit
// (strength scale, c_0/f_T, phi_0, phi_res, G_f scale, G_II, cap, G_c). From the start set, each
// iteration tries every parameter in turn one step up, then one step down, and keeps the first
// move that lowers J; an iteration without a move halves the step (a move the law refuses, such as
// a G_c below its snap-back bound for the cap or a strength whose G_II falls under c_0^2/(2 k_s), is
// skipped and printed with the law's reason). Scales, c_0/f_T, G_II, G_c and the
// cap move by a factor (1 + h), the angles by 25 h degrees, h = --step (0.2) at first; each stays
// in its bounds (fit_bounds). Derivative-free, so a noisy objective (Voronoi seeds, a peak found on
// a sampled curve) cannot mislead it with a bad gradient; every evaluation is one run of each
// target's scene on each fit seed, so its cost is known in advance: at most (1 + 2 P) evaluations
// an iteration for P parameters, plus one on the held-out seeds, which the search never sees.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "brazilian/disc.hpp"
#include "common/cli.hpp"
#include "common/concrete_set.hpp"
#include "compression/specimen.hpp"
#include "direct_tension/tension_test.hpp"
#include "rc_beam/beam_shear_figure.hpp"

namespace tessera::scenes {

inline constexpr real unreached_residual = 10;  ///< normalised residual of a target whose event was not reached

/// One target: its name, weight and tolerance (relative, as the file comment defines it).
struct target_spec {
  std::string name;
  real weight = 1, tolerance = 0;
};

/// The default tolerance of target `name` (file comment).
[[nodiscard]] inline real default_tolerance(const std::string& name) {
  if (name == "tension") return 0.05;
  if (name == "energy") return 0.15;
  if (name == "splitting") return 0.2 / 1.2;  // [1.0, 1.4]
  if (name == "compression") return 0.15;
  if (name == "shear") return 0.2;
  throw invalid_input(tessera::detail::concat("calibrate: --targets: '", name,
                                              "' is not a target (tension, energy, splitting, compression, shear)"));
}

/// The flags of calibrate --targets (SI).
struct targets_options {
  std::vector<target_spec> targets;
  std::vector<std::string> fit = {"strength"};  ///< parameters (fit_parameter names)
  concrete_set start;                           ///< the recipe and the starting values
  std::uint64_t seed = 1;                       ///< fit seeds seed .. seed + seeds - 1, held out the next `holdout`
  int seeds = 2, holdout = 1, iterations = 4;
  real step = 0.2;                              ///< initial relative step h
  real f_c = 35e6;                              ///< the compression reference (Pa)
  real tension_step = 2e-9, tension_rate = 0.005;  ///< the prism's step (m) and rate (m/s)
  disc_options disc;                            ///< the disc (--disc-* flags; seed set per run)
  compression_options compression;              ///< the specimen (--compression-* flags; seed set per run)
  shear_figure_options shear;                    ///< the beam of the shear target (--shear-* flags)
  int threads = 1;
  bool quick = false;
};

/// One fitted parameter: its value in a concrete_set, bounds, and whether it moves additively (deg).
struct fit_parameter {
  const char* name;
  real concrete_set::*field;
  real lo, hi;
  bool angle;
};
[[nodiscard]] inline const std::vector<fit_parameter>& fit_parameters() {
  static const std::vector<fit_parameter> p = {
      {"strength", &concrete_set::strength_scale, 0.1, 10, false},
      {"cohesion", &concrete_set::cohesion_ratio, 0.3, 10, false},
      {"phi0", &concrete_set::phi_0_deg, 10, 75, true},
      {"phires", &concrete_set::phi_res_deg, 0, 75, true},
      {"energy", &concrete_set::fracture_energy_scale, 0.1, 10, false},
      {"gii", &concrete_set::g_ii, 10, 1e5, false},
      {"cap", &concrete_set::cap, 5e6, 1e9, false},
      {"gc", &concrete_set::g_c, 100, 1e8, false}};
  return p;
}
[[nodiscard]] inline const fit_parameter& fit_parameter_named(const std::string& name) {
  for (const fit_parameter& p : fit_parameters())
    if (name == p.name) return p;
  throw invalid_input(tessera::detail::concat("calibrate: --fit: '", name,
                                              "' is not a parameter (strength, cohesion, phi0, phires, energy, gii, cap, gc)"));
}

/// The laws calibrate --targets --law takes (concrete_laws.hpp rows with calibrate).
[[nodiscard]] inline std::vector<std::string> calibrated_law_names() {
  std::vector<std::string> v;
  for (const concrete_law& l : concrete_laws)
    if (l.calibrate) v.emplace_back(l.name);
  return v;
}

/// --fit's help: the common parameters, then each law parameter's fit name with the laws that fit it.
[[nodiscard]] inline std::string fit_flag_help() {
  std::string s = "parameters: strength, cohesion, phi0, phires, energy, cap (--material beam)";
  for (const law_parameter_row& r : law_parameter_rows)
    if (*r.fit != 0)
      s += tessera::detail::concat(", ", r.fit, " (", r.symbol, "; --law ",
                                   concrete_law_list([&r](const concrete_law& l) { return (l.fits & r.id) != 0; }), ")");
  return s;
}

/// Refuses --fit `name` with law `law` when name is a law parameter's fit (gii, gc) that law does not
/// fit (concrete_laws.hpp: its row's fits), naming both: "calibrate: --fit gc needs --law crushing
/// (--law slip_softening has no G_c)".
inline void require_law_fits(const std::string& law, const std::string& name) {
  for (const law_parameter_row& r : law_parameter_rows) {
    if (name != r.fit) continue;
    const concrete_law* l = find_concrete_law(law);
    require(l != nullptr && (l->fits & r.id) != 0, "calibrate: --fit ", name, " needs --law ",
            concrete_law_list([&r](const concrete_law& x) { return (x.fits & r.id) != 0; }), " (--law ", law,
            law_takes(law, r.id) ? " cannot fit " : " has no ", r.symbol, ")");
  }
}

/// One target's figure over a set of seeds.
struct target_value {
  std::string name;        ///< tension, energy, splitting, compression, compression_strain, shear
  real reference = 0;      ///< the value aimed at
  real tolerance = 0, weight = 1;
  real value = std::numeric_limits<real>::quiet_NaN();  ///< mean over the seeds (NaN: the event not reached on one)
  int reached = 0, runs = 0;                            ///< seeds that reached the event, seeds run
  [[nodiscard]] real residual() const {  ///< (value / reference - 1) / tolerance, or unreached_residual
    return reached == runs && runs > 0 ? (value / reference - 1) / tolerance : unreached_residual;
  }
  [[nodiscard]] bool met() const { return reached == runs && runs > 0 && std::abs(residual()) <= 1; }
};

/// One evaluation: the set, its figures, J, and the time it took.
struct evaluation {
  concrete_set set;
  std::vector<target_value> values;
  real objective = 0;
  double cpu_s = 0;
  std::vector<double> seconds;  ///< wall-clock s per target in the order of --targets (summed over the seeds)
};

[[nodiscard]] inline bool has_target(const targets_options& o, const std::string& name) {
  return std::any_of(o.targets.begin(), o.targets.end(), [&](const target_spec& t) { return t.name == name; });
}

/// The tension prism of recipe c (its geometry: the study's prism or the beam recipe's) for `seed`.
[[nodiscard]] inline prism_scene tension_prism(const concrete_set& c, std::uint64_t seed) {
  if (c.material == "beam") {
    beam_options b = c.beam();
    b.seed = seed;
    return make_beam_prism(b).prism;
  }
  prism_options p;
  p.blocks = c.blocks();
  p.seed = seed;
  return make_prism(p);
}

/// Runs every target's scene of o for set c on seeds first .. first + count - 1 (the tension prism
/// once a seed for both tension and energy: to separation when energy is a target).
[[nodiscard]] inline evaluation evaluate_targets(const targets_options& o, const concrete_set& c, std::uint64_t first,
                                                 int count) {
  evaluation ev;
  ev.set = c;
  const cli::wall_timer timer;
  with_concrete(c, [&](const auto& recipe) {
    using Law = typename recipe_law<std::remove_cvref_t<decltype(recipe)>>::type;
    std::vector<tension_result> pulls;  // a seed each, when tension or energy is a target
    real g_f = 0, area = 0;
    double pull_s = 0;
    if (has_target(o, "tension") || has_target(o, "energy")) {
      const cli::wall_timer tt;
      for (int k = 0; k < count; ++k) {
        const prism_scene scene = tension_prism(c, first + static_cast<std::uint64_t>(k));
        g_f = scene.G_f, area = scene.cross_section();
        tension_loading ld;
        ld.rate = o.tension_rate, ld.step_displacement = o.tension_step, ld.threads = o.threads, ld.progress = false;
        ld.stop_at_separation = has_target(o, "energy");
        if (!ld.stop_at_separation) ld.stop_below_peak_ratio = 0.9, ld.max_displacement = 3e-4;
        ld.label = "calibrate tension";
        pulls.push_back(run_direct_tension<compression_solver<Law>>(scene, recipe.contact, ld));
      }
      pull_s = tt.seconds();
    }
    for (const target_spec& t : o.targets) {
      const cli::wall_timer tt;
      target_value v{t.name, 0, t.tolerance, t.weight}, strain{"compression_strain", 2.5e-3, 0.4, t.weight};
      real sum = 0, strain_sum = 0;
      for (int k = 0; k < count; ++k) {
        const std::uint64_t seed = first + static_cast<std::uint64_t>(k);
        ++v.runs;
        if (t.name == "tension") {
          v.reference = recipe.f_T, sum += pulls[static_cast<std::size_t>(k)].peak_stress, ++v.reached;
        } else if (t.name == "energy") {
          const tension_result& r = pulls[static_cast<std::size_t>(k)];
          v.reference = g_f;
          if (r.separated) sum += r.dissipated / area, ++v.reached;
        } else if (t.name == "splitting") {
          disc_options d = o.disc;
          d.seed = seed;
          const disc_result r = run_brazilian_disc(d, recipe);
          v.reference = 1.2;
          if (r.split) sum += r.ratio(), ++v.reached;
        } else if (t.name == "shear") {
          const shear_figure f = run_shear_figure(c, o.shear, seed);
          v.reference = f.reference_load;
          if (f.failure_reached) sum += f.peak_load, ++v.reached;
        } else {  // compression
          compression_options co = o.compression;
          co.common.seed = seed;
          co.material = c.material;
          concrete_set_to(c, co);
          const compression_specimen<Law> sp(co, recipe);
          const compression_result r = sp.run();
          v.reference = o.f_c;
          ++strain.runs;
          if (r.peak) sum += r.peak_stress, strain_sum += r.peak_strain, ++v.reached, ++strain.reached;
        }
      }
      if (v.reached > 0) v.value = sum / v.reached;
      ev.values.push_back(v);
      if (t.name == "compression") {
        if (strain.reached > 0) strain.value = strain_sum / strain.reached;
        ev.values.push_back(strain);
      }
      // the prism's time goes to the first of tension and energy
      const bool first_pull = (t.name == "tension" || t.name == "energy") && pull_s > 0;
      ev.seconds.push_back(tt.seconds() + (first_pull ? pull_s : 0));
      if (first_pull) pull_s = 0;
    }
    return 0;
  });
  for (const target_value& v : ev.values) ev.objective += v.weight * v.residual() * v.residual();
  ev.cpu_s = timer.seconds();
  return ev;
}

/// c with parameter p moved one step of size h in direction dir (+1, -1), within its bounds.
[[nodiscard]] inline concrete_set moved(concrete_set c, const fit_parameter& p, real h, int dir) {
  real& x = c.*p.field;
  if (p.field == &concrete_set::strength_scale) x = c.scale();
  if (p.field == &concrete_set::g_ii) x = g_ii_in_effect(c);  // the law's default made explicit
  if (p.field == &concrete_set::g_c && x == 0) x = default_g_c;
  const real hi = p.field == &concrete_set::phi_res_deg ? std::min(p.hi, c.phi_0_deg) : p.hi;
  const real lo = p.field == &concrete_set::phi_0_deg ? std::max(p.lo, c.phi_res_deg) : p.lo;
  x = p.angle ? x + dir * 25 * h : x * (dir > 0 ? 1 + h : 1 / (1 + h));
  x = std::clamp(x, lo, hi);
  return c;
}

/// Refuses set c where a scene of o's targets would (with_concrete's checks, e.g. G_c above its bound
/// for the cap; with the shear target, the beam's: check_beam_law_set on its contacts). Throws invalid_input.
inline void require_targets_accept(const targets_options& o, const concrete_set& c) {
  with_concrete(c, [](const auto&) { return 0; });
  if (has_target(o, "shear")) check_beam_law_set(shear_beam_options(c, o.shear, o.seed));
}

/// Why a scene of o's targets refuses set c (require_targets_accept's message), or "" if every one
/// accepts it.
[[nodiscard]] inline std::string law_refusal(const targets_options& o, const concrete_set& c) {
  try {
    require_targets_accept(o, c);
    return {};
  } catch (const invalid_input& e) {
    return e.what();
  }
}

/// The compass search of the file comment; `log` prints and records every evaluation, `skipped`
/// every move the law refuses (iteration, move, the refusal's message).
template <class Log, class Skipped>
[[nodiscard]] evaluation fit_targets(const targets_options& o, Log&& log, Skipped&& skipped) {
  evaluation best = evaluate_targets(o, o.start, o.seed, o.seeds);
  log(best, 0, "start");
  real h = o.step;
  for (int it = 1; it <= o.iterations; ++it) {
    bool improved = false;
    for (const std::string& name : o.fit) {
      const fit_parameter& p = fit_parameter_named(name);
      for (const int dir : {+1, -1}) {
        const concrete_set trial = moved(best.set, p, h, dir);
        if (trial.*p.field == best.set.*p.field) continue;  // at a bound
        const std::string move = tessera::detail::concat(name, dir > 0 ? " +" : " -", h);
        if (const std::string why = law_refusal(o, trial); !why.empty()) {
          skipped(it, move, why);
          continue;
        }
        const evaluation ev = evaluate_targets(o, trial, o.seed, o.seeds);
        log(ev, it, move);
        if (ev.objective < best.objective) {
          best = ev, improved = true;
          break;
        }
      }
    }
    if (!improved) h /= 2;
  }
  return best;
}

}  // namespace tessera::scenes
