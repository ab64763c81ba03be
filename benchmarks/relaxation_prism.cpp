// relaxation_prism: kinetic dynamic relaxation (include/tessera/solver/relaxation.hpp, issue #43
// candidate 2) on the direct tension prism, beside the implicit solve's elastic branch.
//
// Scene: examples/direct_tension's prism (common/scenes.hpp make_prism, power softening, 100
// blocks by default), bottom fixed, top fixed transversally and pulled along z; the solver built
// with kinetic_relaxation_options (no local damping, every mass scaled to one step).
//
// Reference: implicit::quasi_static on the same scene finds the elastic limit U_el (the top
// displacement at which the first sub-contact reaches f_T, by linearity from a probe increment)
// and the modulus sigma / (U / L) there.
//
// KDR: increments to (1 - 1e-6) U_el, one or two (--first x U_el, then the rest; steps, resets,
// CPU time, modulus against the implicit one), then increments of --increment m each, every increment a ramp of --ramp steps
// and a relaxation to the unbalanced ratio --tolerance (max nodal unbalanced force / f_T A), until
// the top displacement reaches --until or the stress has fallen below --stop-below x its peak.
// --extrapolate: the ramps move the free gridpoints along the last increment's field
// (relaxation_options::extrapolate) until the stress has fallen 5 % below its peak.
// Per increment: U, stress, steps, resets, ratio, cumulative CPU time; the curve into --curve.
// Stress: 0.5 (R_top - R_bottom) / A from the last step's support reactions.
//
//   relaxation_prism [--blocks N] [--seed N] [--threads N] [--increment M] [--ramp K] [--first R] [--gamma G]
//                    [--elastic-tolerance R]
//                    [--tolerance R] [--max-steps N] [--until M] [--stop-below R] [--plain-zeroing]
//                    [--extrapolate] [--fire] [--fire-alpha A] [--fire-decay F] [--fire-delay N]
//                    [--adaptive] [--adaptive-scale S] [--elastic-only] [--curve FILE]
// --fire: FIRE's velocity rule (relaxation_options::velocity_rule) instead of the kinetic resets;
// --adaptive: Underwood's adaptive damping instead (--adaptive-scale: factor on its damping).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <exception>
#include <string>

#include "common/cli.hpp"
#include "common/rc_tie_run.hpp"
#include "common/scenes.hpp"
#include "tessera/analysis/curves.hpp"
#include "tessera/presets.hpp"
#include "tessera/solver.hpp"
#include "tessera/solver/implicit/quasi_static.hpp"
#include "tessera/solver/relaxation.hpp"

namespace {
namespace sc = tessera::scenes;
using tessera::index_t;
using tessera::real;
using tessera::vec3;
using law = tessera::prism_solver::law_type;
using model = tessera::implicit::quasi_static<tessera::zones::linear_elastic_tet, law>;

/// Processor seconds since `start` (the machine is shared: wall times are inflated by its load).
double cpu_seconds_since(std::clock_t start) { return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC; }

/// The prism's supports on s: bottom fixed, top fixed transversally and prescribed along z at
/// 1 m/s (pseudo-time is top displacement). Returns {bottom, top}.
std::pair<tessera::bc::node_group, tessera::bc::node_group> support(tessera::prism_solver& s, real length) {
  const real tol = 1e-9 * length;
  auto bottom = s.gridpoints_on_plane(2, 0.0, tol);
  auto top = s.gridpoints_on_plane(2, length, tol);
  s.fix(bottom);
  s.fix(top, tessera::bc::transverse_to(2));
  s.prescribe_velocity(top, vec3(0, 0, 1), tessera::bc::components::z);
  return {bottom, top};
}

/// U at which the most loaded sub-contact of q reaches its tensile strength, by linearity from
/// its normal stresses at the present elastic top displacement u (m). (Tension governs the
/// prism's first damage; the KDR run reports the sub-contacts softened or slipped there.)
real tensile_limit(const model& q, const tessera::prism_solver& s, real u) {
  real most = 0;
  for (index_t i = 0; i < s.contacts().size(); ++i)
    most = std::max(most, q.state(i).sigma_n / law::tension_policy::peak_strength(s.contacts().subcontact_params(i).tension));
  return u / most;
}

/// The RC tie (common/rc_tie_scene.hpp, 100 blocks, its supports) pulled symmetrically at the bar
/// ends by KDR increments of `increment` m of elongation to `until`, each relaxed to `tolerance`
/// x N_cr (the ratio's reference), ramps extrapolated (o.extrapolate) except right after a load
/// drop. Prints K0 (band slope 10-60 % of the first peak), the first drop (> 5 % N_cr) and the
/// plateau (mean force over the last quarter of the elongation), steps, resets, CPU time.
int run_tie_mode(std::uint64_t seed, int threads, real increment, real until, const tessera::relaxation_options& base) {
  namespace an = tessera::analysis;
  const sc::tie_scene scene = sc::make_tie({.blocks = 100, .seed = seed});
  tessera::solver_options so = tessera::kinetic_relaxation_options({});
  so.threads = threads;
  // The tie's solver without the step checker: its energy bound counts only the booked work, and
  // the extrapolated ramps move the model outside the books (solver/relaxation.hpp).
  using tie_type = tessera::solver<sc::deformable_blocks, tessera::presets::bonded_faces<tessera::law::study_tie_law>,
                                   sc::tie_bar, tessera::integrator::central_difference<tessera::integrator::local_damping>,
                                   tessera::checks::no_step_checker>;
  const std::clock_t cpu = std::clock();
  tie_type s(scene.prism.tess, scene.prism.mesh, scene.prism.block_material, scene.prism.contact, scene.bar, so);
  const sc::tie_ends ends = sc::hold_tie_ends(s, scene);
  s.bar_nodes().prescribed_velocity(ends.last, 2) = 0.5;  // elongation rate 1 m/s of pseudo-time
  s.bar_nodes().prescribed_velocity(ends.first, 2) = -0.5;
  tessera::kinetic_relaxation<tie_type> k(s);
  tessera::relaxation_options o = base;
  o.reference_force = scene.hand.cracking_force;
  std::vector<real> elongation{0}, force{0};
  const real drop = 0.05 * scene.hand.cracking_force;
  std::printf("## RC tie, 100 blocks (seed %llu): N_cr %.5g N, f_y A_s %.5g N, K (shear lag) %.5g N/m; increments of "
              "%.3g m, tolerance %.3g x N_cr\n\n| elongation (mm) | force (kN) | steps | resets | CPU (s) |\n|---|---|---|---|---|\n",
              static_cast<unsigned long long>(seed), scene.hand.cracking_force, scene.hand.yield_force,
              scene.hand.bonded_stiffness, increment, o.ratio_tolerance);
  std::int64_t failures = 0;
  while (elongation.back() < until) {
    const auto r = k.advance(increment, 10, o);
    if (!r.converged) ++failures;
    const auto& bar = s.bar_nodes();
    elongation.push_back(bar.displacement(ends.last, 2) - bar.displacement(ends.first, 2));
    force.push_back(0.5 * (bar.reaction(ends.last, 2) - bar.reaction(ends.first, 2)));
    // A load drop: the next ramp follows the load dynamically (extrapolating a snap repeats it).
    o.extrapolate = base.extrapolate && force.back() > force[force.size() - 2] - drop;
    if (elongation.size() % 10 == 0 || !r.converged)
      std::printf("| %.4f | %.4f | %lld | %lld%s | %.2f |\n", elongation.back() * 1e3, force.back() * 1e-3,
                  static_cast<long long>(r.steps), static_cast<long long>(r.resets), r.converged ? "" : " (not converged)",
                  cpu_seconds_since(cpu));
    std::fflush(stdout);
  }
  const auto drops = an::find_load_drops(elongation, force, drop, force.size());
  real first_drop = 0;
  std::size_t first_peak = force.size() - 1;
  for (const auto& d : drops)
    if (d.peak_force >= 0.5 * scene.hand.cracking_force) {
      first_drop = d.peak_force, first_peak = d.sample;
      break;
    }
  const real k0 = an::band_slope(elongation, force, first_peak + 1, 0.1 * first_drop, 0.6 * first_drop);
  std::size_t tail = 0;
  while (tail < elongation.size() && elongation[tail] < 0.75 * elongation.back()) ++tail;
  const auto& t = k.totals();
  std::printf("\n- K0 %.5g N/m (%+.2f %% against the shear-lag stiffness), first drop %.5g N (%.3f N_cr), %zu drops, "
              "plateau %.5g N (%.3f f_y A_s)\n- %lld steps (%lld in ramps), %lld resets, %lld increments not converged, "
              "CPU %.2f s\n",
              k0, 100 * (k0 / scene.hand.bonded_stiffness - 1), first_drop, first_drop / scene.hand.cracking_force,
              drops.size(), an::tail_mean(force, tail), an::tail_mean(force, tail) / scene.hand.yield_force,
              static_cast<long long>(t.steps), static_cast<long long>(t.ramp_steps), static_cast<long long>(t.resets),
              static_cast<long long>(failures), cpu_seconds_since(cpu));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int blocks = 100, threads = 1, ramp = 100;
  std::uint64_t seed = 1;
  real increment = 2e-6, tolerance = 1e-3, until = 9e-5, stop_below = 0.5, first_fraction = 1, gamma = 0,
       elastic_tolerance = 0;
  std::int64_t max_steps = 200000;
  bool plain = false, extrapolate = false, elastic_only = false, tie = false, fire = false,
       adaptive = false;
  std::string curve_file;
  tessera::cli::parser cli("relaxation_prism",
                           "Kinetic dynamic relaxation on the direct tension prism (issue #43, candidate 2).");
  cli.option("--blocks", blocks, "prism blocks", "N").within(2, 2000);
  cli.option("--seed", seed, "tessellation seed", "N");
  cli.option("--threads", threads, "threads", "N").within(1, 64);
  cli.option("--increment", increment, "top displacement per increment past U_el (m)", "M").within(1e-10, 1e-3);
  cli.option("--ramp", ramp, "steps over which an increment moves the top", "K").within(1, 1000000);
  cli.option("--tolerance", tolerance, "unbalanced ratio, max nodal force / f_T A", "R").within(1e-14, 1);
  cli.option("--elastic-tolerance", elastic_tolerance, "the ratio for the increments to U_el (0: --tolerance)", "R")
      .within(0, 1);
  cli.option("--max-steps", max_steps, "steps one relaxation may take", "N").within(1, 100000000);
  cli.option("--until", until, "stop at this top displacement (m)", "M").within(1e-7, 1e-2);
  cli.option("--stop-below", stop_below, "stop past the peak once stress < this x peak", "R").within(0, 1);
  cli.option("--first", first_fraction, "first increment, x U_el (the rest to U_el is a second one)", "R").within(0.01, 1);
  cli.option("--gamma", gamma, "local damping constant beside the resets (0: pure KDR)", "G").within(0, 0.95);
  cli.flag("--plain-zeroing", plain, "zero the velocities without backing up to the kinetic-energy peak");
  cli.flag("--extrapolate", extrapolate, "free gridpoints follow the last increment's field during the ramp");
  cli.flag("--elastic-only", elastic_only, "stop at the elastic limit");
  cli.flag("--fire", fire, "FIRE's velocity mixing and power resets instead of the kinetic-energy resets");
  const tessera::relaxation_options defaults;  // the library's FIRE and adaptive defaults
  real fire_alpha = defaults.fire_alpha_start, fire_decay = defaults.fire_alpha_decay;
  std::int64_t fire_delay = defaults.fire_delay;
  cli.option("--fire-alpha", fire_alpha, "FIRE's mixing after a reset", "A").within(1e-6, 1);
  cli.option("--fire-decay", fire_decay, "FIRE's factor on the mixing per downhill step", "F").within(1e-6, 1);
  cli.option("--fire-delay", fire_delay, "FIRE's downhill steps before the mixing decays", "N").within(0, 1000000);
  cli.flag("--adaptive", adaptive, "Underwood's adaptive damping instead of the kinetic-energy resets");
  real adaptive_scale = defaults.adaptive_damping_scale;
  cli.option("--adaptive-scale", adaptive_scale, "factor on the adaptive rule's critical damping", "S").within(1e-6, 10);
  cli.flag("--tie", tie, "the RC tie instead of the prism (--increment: elongation; --until: last elongation)");
  cli.option("--curve", curve_file, "write U, stress, steps per increment here (csv)", "FILE");
  cli.parse_or_exit(argc, argv);
  if (fire && adaptive) {
    std::fprintf(stderr, "relaxation_prism: --fire and --adaptive are two velocity rules; give one\n");
    return 2;
  }
  const auto set_velocity_rule = [&](tessera::relaxation_options& o) {
    using rule = tessera::relaxation_options::method;
    o.velocity_rule = fire ? rule::fire : adaptive ? rule::adaptive : rule::kinetic;
    o.fire_alpha_start = fire_alpha, o.fire_alpha_decay = fire_decay, o.fire_delay = fire_delay;
    o.adaptive_damping_scale = adaptive_scale;
  };
  try {
    if (tie) {
      tessera::relaxation_options o;
      o.ratio_tolerance = tolerance;
      o.max_steps = max_steps;
      o.back_up_to_peak = !plain;
      o.extrapolate = extrapolate;
      set_velocity_rule(o);
      return run_tie_mode(seed, threads, increment, until, o);
    }
    const sc::prism_scene scene = sc::make_prism({.blocks = blocks, .seed = seed});
    const real length = scene.length(), area = scene.cross_section(), f_t = scene.contact.tension.f_T;

    // ---- implicit reference: U_el and the modulus ----
    real u_el = 0, modulus_implicit = 0;
    {
      tessera::prism_solver s(scene.tess, scene.mesh, scene.block_material, scene.contact);
      const auto [bottom, top] = support(s, length);
      model q(scene.mesh, s.blocks(), s.contacts(), s.gridpoints());
      tessera::implicit::increment_options o;
      o.force_tolerance = 1e-6 * f_t * area;
      const real probe = 1e-6;
      tessera::require(q.solve_increment(probe, o).converged, "relaxation_prism: implicit probe failed");
      u_el = tensile_limit(q, s, probe);
      tessera::require(q.solve_increment((1 - 1e-6) * u_el - probe, o).converged, "relaxation_prism: implicit failed");
      const real sigma = 0.5 * (q.reaction_sum(top).z() - q.reaction_sum(bottom).z()) / area;
      modulus_implicit = sigma / (q.mean_displacement(top).z() / length);
    }
    std::printf("## %d blocks (seed %llu): implicit U_el = %.6g m, modulus %.8g Pa\n\n", blocks,
                static_cast<unsigned long long>(seed), u_el, modulus_implicit);

    // ---- kinetic dynamic relaxation ----
    const std::clock_t cpu = std::clock();
    tessera::solver_options so = tessera::kinetic_relaxation_options({});
    so.threads = threads;
    so.damping_gamma = gamma;
    tessera::prism_solver s(scene.tess, scene.mesh, scene.block_material, scene.contact, {}, so);
    const auto [bottom, top] = support(s, length);
    tessera::kinetic_relaxation<tessera::prism_solver> k(s);
    tessera::relaxation_options o;
    o.reference_force = f_t * area;
    o.ratio_tolerance = tolerance;
    o.max_steps = max_steps;
    o.back_up_to_peak = !plain;
    o.extrapolate = extrapolate;
    set_velocity_rule(o);
    const double build_s = cpu_seconds_since(cpu);
    const auto stress = [&] {
      namespace rec = tessera::recorders;
      return 0.5 * (rec::reaction_sum(s.gridpoints(), top).z() - rec::reaction_sum(s.gridpoints(), bottom).z()) / area;
    };
    const auto u_top = [&] { return tessera::recorders::mean_displacement(s.gridpoints(), top).z(); };
    std::printf("- %s: dt %.3g s (pseudo), gamma %.2g, %s, ramp %d steps, tolerance %.3g x f_T A = %.4g N%s; solver "
                "built in %.3f s CPU\n",
                fire ? "FIRE" : adaptive ? "adaptive damping" : "KDR", s.dt(), gamma,
                plain ? "plain zeroing" : "backed up to the kinetic peak", ramp,
                tolerance, o.reference_force, extrapolate ? ", extrapolated ramp" : "", build_s);
    std::FILE* curve = curve_file.empty() ? nullptr : std::fopen(curve_file.c_str(), "w");
    tessera::require(curve_file.empty() || curve != nullptr, "relaxation_prism: cannot open ", curve_file);
    if (curve) std::fprintf(curve, "displacement_m,stress_Pa,steps,resets,ratio,converged,cpu_s\n");
    const std::clock_t run_cpu = std::clock();
    const auto record = [&](const tessera::relaxation_result& r) {
      if (curve)
        std::fprintf(curve, "%.9g,%.9g,%lld,%lld,%.4g,%d,%.4f\n", u_top(), stress(), static_cast<long long>(r.steps),
                     static_cast<long long>(r.resets), r.ratio, r.converged ? 1 : 0, cpu_seconds_since(run_cpu));
    };
    // To U_el in one increment, or in two (first x U_el, then the rest), at --elastic-tolerance.
    o.ratio_tolerance = elastic_tolerance > 0 ? elastic_tolerance : tolerance;
    tessera::relaxation_result first = k.advance((first_fraction < 1 ? first_fraction : 1 - 1e-6) * u_el, ramp, o);
    record(first);
    if (first_fraction < 1) {
      const auto second = k.advance((1 - 1e-6 - first_fraction) * u_el, ramp, o);
      record(second);
      first.add(second);
    }
    const real sigma_el = stress();
    o.ratio_tolerance = tolerance;
    index_t damaged = 0;  // sub-contacts softened, slipped or broken at U_el (0 on the static path)
    for (index_t i = 0; i < s.contacts().size(); ++i)
      if (law::status(s.contacts().state(i)) != tessera::law::contact_status::intact) ++damaged;
    const real modulus = sigma_el / (u_top() / length);
    std::printf("- to U_el: %lld steps (%lld ramp), %lld resets, ratio %.3g%s, CPU %.3f s; modulus %.8g Pa (%+.3e "
                "against the implicit); %lld sub-contacts damaged\n",
                static_cast<long long>(first.steps), static_cast<long long>(first.ramp_steps),
                static_cast<long long>(first.resets), first.ratio, first.converged ? "" : " (NOT converged)",
                cpu_seconds_since(run_cpu), modulus, modulus / modulus_implicit - 1, static_cast<long long>(damaged));
    std::fflush(stdout);
    if (!elastic_only) {
      std::printf("\n| U (um) | stress (MPa) | steps | resets | ratio | CPU (s) |\n|---|---|---|---|---|---|\n");
      real peak = sigma_el, u_peak = u_top();
      std::int64_t to_peak_steps = first.steps, to_peak_resets = first.resets, failures = 0;
      double to_peak_cpu = cpu_seconds_since(run_cpu);
      int line = 0;
      while (u_top() < until) {
        const auto r = k.advance(increment, ramp, o);
        record(r);
        if (!r.converged) ++failures;
        const real now = stress();
        // Extrapolating an increment in which a crack snapped open repeats the snap (the blocks
        // unload into compression): past the peak, once the stress fell 5 %, the free gridpoints
        // follow the ramp dynamically.
        if (now < 0.95 * peak) o.extrapolate = false;
        if (now > peak) {
          peak = now, u_peak = u_top();
          to_peak_steps = k.totals().steps, to_peak_resets = k.totals().resets;
          to_peak_cpu = cpu_seconds_since(run_cpu);
        }
        if (line++ % 5 == 0 || !r.converged)
          std::printf("| %.4f | %.5f | %lld | %lld | %.3g%s | %.2f |\n", u_top() * 1e6, now * 1e-6,
                      static_cast<long long>(r.steps), static_cast<long long>(r.resets), r.ratio,
                      r.converged ? "" : " (not converged)", cpu_seconds_since(run_cpu));
        std::fflush(stdout);
        if (u_top() > 1.05 * u_peak && now < stop_below * peak) break;
      }
      const auto& t = k.totals();
      std::printf("\n- peak %.6g Pa at U = %.6g m: %lld steps, %lld resets, CPU %.2f s from the start\n", peak, u_peak,
                  static_cast<long long>(to_peak_steps), static_cast<long long>(to_peak_resets), to_peak_cpu);
      std::printf("- end U = %.6g m, stress %.6g Pa: %lld steps (%lld in ramps), %lld resets, %lld increments not "
                  "converged, CPU %.2f s; kinetic energy removed %.4g J, tensile dissipation %.4g J\n",
                  u_top(), stress(), static_cast<long long>(t.steps), static_cast<long long>(t.ramp_steps),
                  static_cast<long long>(t.resets), static_cast<long long>(failures), cpu_seconds_since(run_cpu),
                  t.kinetic_removed, s.contacts().energies().dissipated_tension);
    }
    if (curve) std::fclose(curve);
  } catch (const std::exception& e) {
    tessera::cli::print_error("relaxation_prism", e);
    return 1;
  }
  return 0;
}
