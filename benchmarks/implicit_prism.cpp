// implicit_prism: the implicit quasi-static solve (include/tessera/solver/implicit/, issue #43
// candidate 3) against the explicit run on the elastic branch of the direct tension prism.
//
// Scene: examples/direct_tension's prism (common/scenes.hpp make_prism, power softening, 100
// blocks by default), bottom fixed, top fixed transversally and pulled along z.
//
// Implicit: the model is made from the solver's blocks, contacts and supports (the top's
// prescribed velocity 1 m/s, so pseudo-time is top displacement); a first increment of
// --probe metres (elastic), whose sub-contact stresses give, by linearity, the top displacement
// U_el at which the first sub-contact reaches f_T (or its Coulomb limit); a second increment to
// (1 - 1e-6) U_el, checked to leave every sub-contact intact. Times: assembly (zone K once,
// contact K per factorisation), factorisation, solves, force evaluations.
//
// Explicit: scenes::run_direct_tension<prism_solver> with the driver's defaults (2 nm per step,
// mass scaling, half-cosine ramp) and --threads, stopped at the first sample with top
// displacement >= U_el: its run time and steps, and its stress-displacement curve.
//
// Stiffness both ways: the mean axial stress 0.5 (R_top - R_bottom) / A over the strain U / L
// (Pa); the explicit one as the least-squares slope of its samples between 0.3 and 1 U_el (past
// the ramp) and as the secant at its last sample; its inertia error is |R_top + R_bottom| / 2 A
// over the stress at the last sample.
//
// --through-peak: the implicit solve continues past U_el in increments of --increment x U_el; an
// increment whose secant iterations do not converge is retried with the line search
// (increment_options::line_search) and then at half the size, up to 6 times; it
// reports per increment the stress, iterations and softening / broken sub-contacts, until the
// stress has fallen below 0.5 x its peak or an increment fails at the smallest size.
//
// --path-following: past U_el, displacement increments of --increment x U_el while the stress
// rises and the increment converges (no line search), then increments under crack-opening control
// (quasi_static::solve_controlled_increment: the work of the committed crack tractions on the
// opening increment, --crack-work J to start, x 1.5 after an increment of at most 6 iterations,
// up to 8 halvings on failure, at most --max-crack-work) until the top displacement reaches
// --until; per increment U, stress, pseudo-time, dissipated energy, iterations into --curve FILE
// (csv) and a summary with counts and CPU time.
//
//   implicit_prism [--blocks N] [--seed N] [--threads N] [--no-explicit] [--through-peak]
//                  [--path-following] [--until U] [--crack-work J] [--max-crack-work J] [--curve FILE]
//                  [--increment R] [--tolerance R] [--max-iterations K] [--refactor] [--no-aitken] [--line-search]
//                  [--no-fallback] [--factorization simplicial|supernodal] [--tie [--tie-increment M]] [--beam]
// --tie: the RC tie (100 blocks, its bars in the implicit solve) pulled at its bar ends instead
// (run_tie below); --until is then the last elongation, --tolerance a fraction of N_cr.
// --beam: rc_beam's half beam on its elastic branch, plates clamped (run_beam_elastic below).
// The out-of-balance tolerance (default 1e-6 f_T A per free component) lies far below the
// explicit run's own inertia error (|R_top + R_bottom| / 2 of 1e-2 of the stress, printed).
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
#include "direct_tension/tension_test.hpp"
#include "rc_beam/beam.hpp"
#include "rc_beam/beam_plates.hpp"
#include "rc_beam/beam_span.hpp"
#include "tessera/presets.hpp"
#include "tessera/solver.hpp"
#include "tessera/solver/implicit/quasi_static.hpp"

namespace {
namespace sc = tessera::scenes;
namespace im = tessera::implicit;
using tessera::index_t;
using tessera::real;
using tessera::vec3;
using model = im::quasi_static<tessera::zones::linear_elastic_tet, tessera::prism_solver::law_type>;

/// Processor time of this process since `start` (s): the machine is shared, so wall-clock
/// times are printed beside it.
double cpu_seconds_since(std::clock_t start) { return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC; }

/// U at which the most loaded sub-contact of `q` reaches its tensile strength or its shear limit,
/// from its stresses at the present (elastic) top displacement u (m), by linearity.
template <class Model, class Solver>
real elastic_limit(const Model& q, const Solver& s, real u) {
  using law = typename Solver::law_type;
  real ratio = 0;
  for (index_t i = 0; i < s.contacts().size(); ++i) {
    const auto& st = q.state(i);
    const auto& p = s.contacts().subcontact_params(i);
    ratio = std::max(ratio, st.sigma_n / law::tension_policy::peak_strength(p.tension));
    // Coulomb limit c_0 - sigma_n tan(phi_0) scales with U too: |tau| = r (c_0 - sigma_n tan) at r
    const real tan_phi = p.shear.phi_0.tan();
    const real tau = st.tau.norm();
    if (tau > 0) ratio = std::max(ratio, (tau + st.sigma_n * tan_phi) / p.shear.c_0);
  }
  return u / ratio;
}

/// --tie: the RC tie (common/rc_tie_scene.hpp, 100 blocks, rc_tie's supports) pulled
/// symmetrically at its bar ends in increments of `increment` m of elongation, each solved to
/// `tolerance` x N_cr with the iteration of `base` (--refactor --line-search: what bars on a
/// plateau need, docs/guide.md; --max-iterations), halved up to 4 times when it does not converge, until `until` or an increment
/// that does not converge at 1/16 of its size. Prints the curve every 10 increments, then K0 (the
/// first increment's secant), the elastic limit (the elongation and force at which the first
/// sub-contact reaches its strength, by the first increment's linearity), the last force, counts and
/// CPU time.
int run_tie(std::uint64_t seed, real increment, real until, real tolerance, im::factorization kind, const im::increment_options& base) {
  const sc::tie_scene scene = sc::make_tie({.blocks = 100, .seed = seed});
  using tie_type = tessera::solver<sc::deformable_blocks, tessera::presets::bonded_faces<tessera::law::study_tie_law>, sc::tie_bar>;
  using tie_model = im::quasi_static<tessera::zones::linear_elastic_tet, tie_type::law_type, sc::tie_bar>;
  const std::clock_t cpu = std::clock();
  tie_type s(scene.prism.tess, scene.prism.mesh, scene.prism.block_material, scene.prism.contact, scene.bar);
  const sc::tie_ends ends = sc::hold_tie_ends(s, scene);
  s.bar_nodes().prescribed_velocity(ends.last, 2) = 0.5;  // elongation rate 1 m/s of pseudo-time
  s.bar_nodes().prescribed_velocity(ends.first, 2) = -0.5;
  tie_model q(scene.prism.mesh, s.blocks(), s.contacts(), s.gridpoints(), s.reinforcement(), kind);
  const double build_s = cpu_seconds_since(cpu);
  im::increment_options o = base;
  o.force_tolerance = tolerance * scene.hand.cracking_force;
  const tessera::bc::node_group first{{ends.first}, "first bar end"}, last{{ends.last}, "last bar end"};
  const auto pull_force = [&] { return 0.5 * (q.bar_reaction_sum(last).z() - q.bar_reaction_sum(first).z()); };
  std::printf("## RC tie, 100 blocks (seed %llu), implicit (%s factorisation%s%s): N_cr %.5g N, f_y A_s %.5g N, "
              "K (shear lag) %.5g N/m; increments of %.3g m, tolerance %.3g x N_cr; %lld free dofs, %.2f s to build\n\n"
              "| elongation (mm) | force (kN) | iterations | factorisations | CPU (s) |\n|---|---|---|---|---|\n",
              static_cast<unsigned long long>(seed), std::string(im::factorization_name(kind)).c_str(),
              o.refactor_each_iteration ? ", refactorised" : "", o.line_search ? ", line search" : "", scene.hand.cracking_force, scene.hand.yield_force, scene.hand.bonded_stiffness, increment, tolerance,
              static_cast<long long>(q.free_dof_count()), build_s);
  real elongation = 0, k0 = 0, limit_u = 0;
  int done = 0;
  bool stopped = false;
  while (elongation < until * (1 - 1e-12) && !stopped) {
    real step = std::min(increment, until - elongation);
    im::increment_result r;
    for (int halving = 0;; ++halving) {
      r = q.solve_increment(step, o);
      if (r.converged || halving == 4) break;
      step *= 0.5;
    }
    if (!r.converged) {
      std::printf("| %.5f | %.4f | not converged at %.3g m (residual %.3g N) | | %.2f |\n", (elongation + step) * 1e3,
                  pull_force() * 1e-3, step, r.max_residual, cpu_seconds_since(cpu));
      stopped = true;
      break;
    }
    elongation += step;
    if (done++ == 0) {
      k0 = pull_force() / elongation;
      limit_u = elastic_limit(q, s, elongation);
    }
    if (done % 10 == 0 || elongation >= until * (1 - 1e-12))
      std::printf("| %.5f | %.4f | %d | %lld | %.2f |\n", elongation * 1e3, pull_force() * 1e-3, r.iterations,
                  static_cast<long long>(q.counts().factorizations), cpu_seconds_since(cpu));
    std::fflush(stdout);
  }
  const auto& c = q.counts();
  std::printf("\n- K0 %.5g N/m (%+.2f %% against the shear-lag stiffness); elastic limit at %.4g mm, %.5g N (%.3f N_cr)\n"
              "- last converged: %.5g mm, %.5g N (%.3f N_cr)%s\n- %lld increments, %lld iterations, %lld factorisations (%lld symbolic), "
              "CPU %.2f s (assembly %.2f, factorisation %.2f, solves %.2f, forces %.2f s of wall time)\n",
              k0, 100 * (k0 / scene.hand.bonded_stiffness - 1), limit_u * 1e3, k0 * limit_u, k0 * limit_u / scene.hand.cracking_force,
              elongation * 1e3, pull_force(), pull_force() / scene.hand.cracking_force,
              stopped ? "; stopped at an increment that did not converge" : "", static_cast<long long>(c.increments),
              static_cast<long long>(c.iterations), static_cast<long long>(c.factorizations),
              static_cast<long long>(c.analyses), cpu_seconds_since(cpu), c.assembly_s, c.factorization_s, c.solve_s, c.force_s);
  return 0;
}

/// --beam: rc_beam's half beam (60 blocks at rc_beam --quick's 50 mm face zoning, or N at h/5),
/// with its bars, on the elastic branch: one increment of `increment` m of loading-plate travel
/// solved to `tolerance` x P_cr (hand). The implicit solve has no platens and no hinged plates, so
/// the plates are tied and clamped: the gridpoints under the support held in y and z, those under
/// the loading plate moved down in y; the symmetry face and the bars' ends there held in x. The
/// clamped plates make it stiffer than rc_beam's hinged ones (measured: 5.4x on the quick beam),
/// so the stiffness printed is this model's, not the driver's; what the run measures is the cost
/// of the beam's factorisation (free dofs, the factor's non-zeros, its time).
int run_beam_elastic(int blocks, std::uint64_t seed, real increment, real tolerance, im::factorization kind) {
  sc::beam_options bo;
  bo.blocks = blocks;
  bo.seed = seed;
  bo.zone_edge = blocks <= 60 ? 0.05 : 0;
  bo.plates = "tied";
  const sc::beam_scene scene = sc::make_beam(bo);
  using beam_type = sc::beam_solver<tessera::presets::study_beam_law>;
  using beam_model = im::quasi_static<tessera::zones::linear_elastic_tet, beam_type::law_type, sc::beam_bar>;
  const std::clock_t cpu = std::clock();
  beam_type s(scene.tess, scene.mesh, scene.block_material, scene.contact, scene.bar);
  const sc::beam_options& o = scene.options;
  const real L = o.half_length(), tol = 1e-9 * L;
  namespace bc = tessera::bc;
  s.fix(s.gridpoints_on_plane(0, L, tol), bc::along(0));
  const real xs = o.support_x(), xl = o.load_x();
  const bc::node_group support = sc::beam_strip(s.gridpoints(), 0, xs - o.plate / 2, xs + o.plate / 2, tol, "support");
  const bc::node_group plate = sc::beam_strip(s.gridpoints(), o.height, xl - o.plate / 2, xl + o.plate / 2, tol, "plate");
  s.fix(support, bc::along(1) | bc::along(2));
  s.prescribe_velocity(plate, vec3(0, -1, 0), bc::along(1));  // 1 m/s of pseudo-time: plate travel
  for (int b = 0; b < o.bars; ++b)
    bc::fix(s.bar_nodes(), bc::node_group{{s.reinforcement().bar_nodes(b).second - 1}, "bar end"}, bc::along(0));
  beam_model q(scene.mesh, s.blocks(), s.contacts(), s.gridpoints(), s.reinforcement(), kind);
  const double build_s = cpu_seconds_since(cpu);
  im::increment_options io;
  io.force_tolerance = tolerance * scene.hand.first_crack_load;
  const im::increment_result r = q.solve_increment(increment, io);
  tessera::node_set& gp = s.gridpoints();
  for (tessera::index_t i = 0; i < gp.size(); ++i)
    for (int c = 0; c < 3; ++c) gp.displacement(i, c) = q.displacement(i, c);
  const real deflection = sc::beam_midspan_gauge(gp, o, scene.hand.mean_block_size, tol).deflection(gp);
  const real load = 2 * q.reaction_sum(support).y();  // P: both half-spans
  const auto& c = q.counts();
  std::printf("## RC beam, %d blocks (seed %llu), elastic branch, plates tied and clamped, implicit (%s factorisation)\n\n"
              "- %lld free dofs, %zu sub-contacts; factor %lld non-zeros; built in %.2f s of CPU\n"
              "- one increment of %.3g m plate travel: %s in %d iterations, %lld factorisations (%lld symbolic): "
              "factorisation %.3f s, assembly %.3f s, solves %.3f s (wall), %.2f s CPU in all\n"
              "- P %.5g N at mid-span deflection %.5g m: %.4g kN/mm (hand, hinged plates: %.4g kN/mm)\n",
              blocks, static_cast<unsigned long long>(seed), std::string(im::factorization_name(kind)).c_str(),
              static_cast<long long>(q.free_dof_count()), static_cast<std::size_t>(s.contacts().size()),
              static_cast<long long>(q.factor_nonzeros()), build_s, increment, r.converged ? "converged" : "NOT converged",
              r.iterations, static_cast<long long>(c.factorizations), static_cast<long long>(c.analyses),
              c.factorization_s, c.assembly_s, c.solve_s, cpu_seconds_since(cpu), load, deflection,
              load / deflection * 1e-6, scene.hand.initial_stiffness * 1e-6);
  return r.converged ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  int blocks = 100, threads = 1, max_iterations = 300;
  std::uint64_t seed = 1;
  bool no_explicit = false, through_peak = false, refactor = false, no_aitken = false, line_search = false,
       no_fallback = false;
  real increment = 0.1, probe = 1e-6, tolerance = 1e-6, until = 150e-6, crack_work = 1e-3, max_crack_work = 1e-2;
  bool path_following = false;
  real control_fraction = 0;
  bool unload_outside = false;
  std::string curve_file, factorization = std::string(im::factorization_name(im::default_factorization()));
  tessera::cli::parser cli("implicit_prism",
                           "The implicit quasi-static solve against the explicit run on the elastic branch of the\n"
                           "direct tension prism (issue #43, candidate 3).");
  cli.option("--blocks", blocks, "prism blocks", "N").within(2, 2000);
  cli.option("--seed", seed, "tessellation seed", "N");
  cli.option("--threads", threads, "threads of the explicit run", "N").within(1, 64);
  cli.option("--probe", probe, "top displacement of the first (elastic) increment (m)", "M").within(1e-9, 1e-4);
  cli.option("--increment", increment, "increments past the elastic limit, x U_el", "R").within(1e-4, 1);
  cli.option("--tolerance", tolerance, "out-of-balance tolerance per component, x f_T A", "R").within(1e-14, 1e-2);
  cli.option("--max-iterations", max_iterations, "secant iterations per increment", "K").within(1, 10000);
  cli.flag("--no-explicit", no_explicit, "skip the explicit run");
  bool tie = false;
  real tie_increment = 5e-6;
  cli.flag("--tie", tie, "the RC tie, bar ends pulled, instead of the prism (--until: last elongation (m); --tolerance: "
           "x N_cr)");
  cli.option("--tie-increment", tie_increment, "with --tie: elongation per increment (m)", "M").within(1e-9, 1e-3);
  bool beam = false;
  cli.flag("--beam", beam, "rc_beam's half beam (--blocks: 60 or more), its elastic branch with the plates tied and "
           "clamped: one increment of --probe m of plate travel (--tolerance: x P_cr); the cost of its factorisation");
  cli.option("--factorization", factorization, "sparse factorisation of K_sec: simplicial (Eigen's LDL^T) or supernodal "
             "(CHOLMOD, where built with TESSERA_CHOLMOD)", "simplicial|supernodal").one_of({"simplicial", "supernodal"});
  cli.flag("--through-peak", through_peak, "carry the implicit solve past the elastic limit");
  cli.flag("--refactor", refactor, "factorise in every iteration, not once per increment");
  cli.flag("--no-aitken", no_aitken, "plain secant steps, without Aitken's relaxation");
  cli.flag("--line-search", line_search, "secant steps lengthened or shortened by a line search on the energy");
  cli.flag("--path-following", path_following, "past U_el, crack-opening control after the peak (file comment)");
  cli.option("--until", until, "path following: stop at this top displacement (m)", "U").within(1e-6, 1e-2);
  cli.option("--crack-work", crack_work, "path following: first crack work per increment (J)", "J").within(1e-9, 1);
  cli.option("--max-crack-work", max_crack_work, "path following: largest crack work per increment (J)", "J")
      .within(1e-9, 1);
  cli.option("--control-fraction", control_fraction, "path following: control set, the sub-contacts that opened at least "
             "this x the widest in the last increment (0: every softening one)", "R").within(0, 1);
  cli.flag("--unload-outside", unload_outside, "path following: softening sub-contacts outside the control set enter K "
           "with k_n, k_s (expected to unload)");
  cli.option("--curve", curve_file, "path following: write the curve here (csv)", "FILE");
  cli.flag("--no-fallback", no_fallback, "past U_el, no retry of a failed increment with the line search");
  cli.parse_or_exit(argc, argv);
  try {
    const im::factorization kind = im::parse_factorization(factorization);  // refused before any output
    if (beam) return run_beam_elastic(blocks, seed, probe, tolerance, kind);
    if (tie) {
      im::increment_options o;
      o.max_iterations = max_iterations;
      o.refactor_each_iteration = refactor;
      o.aitken = !no_aitken;
      o.line_search = line_search;
      return run_tie(seed, tie_increment, until, tolerance, kind, o);
    }
    sc::prism_options po;
    po.blocks = blocks;
    po.seed = seed;
    const sc::prism_scene scene = sc::make_prism(po);
    const real length = scene.length(), area = scene.cross_section(), f_t = scene.contact.tension.f_T;

    // ---- implicit ----
    const tessera::cli::wall_timer build_timer;
    tessera::prism_solver s(scene.tess, scene.mesh, scene.block_material, scene.contact);
    const real tol = 1e-9 * length;
    const auto bottom = s.gridpoints_on_plane(2, 0.0, tol);
    const auto top = s.gridpoints_on_plane(2, length, tol);
    s.fix(bottom);
    s.fix(top, tessera::bc::transverse_to(2));
    s.prescribe_velocity(top, vec3(0, 0, 1), tessera::bc::components::z);
    const double solver_build_s = build_timer.seconds();
    const tessera::cli::wall_timer implicit_timer;
    const std::clock_t implicit_cpu = std::clock();
    model q(scene.mesh, s.blocks(), s.contacts(), s.gridpoints(), kind);
    im::increment_options o;
    o.force_tolerance = tolerance * f_t * area;  // per component, against the prism's strength
    o.max_iterations = max_iterations;
    o.refactor_each_iteration = refactor;
    o.aitken = !no_aitken;
    o.line_search = line_search;
    const auto stress = [&] { return 0.5 * (q.reaction_sum(top).z() - q.reaction_sum(bottom).z()) / area; };
    auto r = q.solve_increment(probe, o);
    tessera::require(r.converged && r.softening == 0 && r.slipped == 0, "implicit_prism: the probe increment of ",
                     probe, " m is not elastic; give a smaller --probe");
    const real u_el = elastic_limit(q, s, probe);
    r = q.solve_increment((1 - 1e-6) * u_el - probe, o);
    const double implicit_s = implicit_timer.seconds();
    const double implicit_cpu_s = cpu_seconds_since(implicit_cpu);
    const real sigma_el = stress();
    const real modulus_implicit = sigma_el / (q.mean_displacement(top).z() / length);
    const auto& c = q.counts();
    std::printf("## Implicit, %d blocks (seed %llu): %lld gridpoints, %lld zones, %lld sub-contacts, %lld free dofs\n\n",
                blocks, static_cast<unsigned long long>(seed), static_cast<long long>(scene.mesh.gridpoint_count()),
                static_cast<long long>(scene.mesh.zone_count()), static_cast<long long>(s.contacts().size()),
                static_cast<long long>(q.free_dof_count()));
    std::printf("- elastic limit: U_el = %.6g m (first sub-contact at f_T or its Coulomb limit), stress %.6g Pa there\n",
                u_el, sigma_el);
    std::printf("- at (1 - 1e-6) U_el: converged %d, softening %lld, slipped %lld, residual %.3g N\n", r.converged,
                static_cast<long long>(r.softening), static_cast<long long>(r.slipped), r.max_residual);
    std::printf("- modulus sigma / (U / L) = %.8g Pa\n", modulus_implicit);
    std::printf("- time %.3f s, CPU %.3f s (model assembly and 2 increments; solver and supports %.3f s before): assembly %.3f s, "
                "factorisation %.3f s (%lld, %lld symbolic), solves %.3f s (%lld), force evaluations %.3f s (%lld); "
                "factor L %lld non-zeros (%s)\n\n",
                implicit_s, implicit_cpu_s, solver_build_s, c.assembly_s, c.factorization_s, static_cast<long long>(c.factorizations),
                static_cast<long long>(c.analyses), c.solve_s, static_cast<long long>(c.solves), c.force_s,
                static_cast<long long>(c.force_evaluations), static_cast<long long>(q.factor_nonzeros()),
                std::string(im::factorization_name(q.factorization_kind())).c_str());
    std::fflush(stdout);

    // ---- explicit ----
    if (!no_explicit) {
      sc::tension_loading in;
      in.threads = threads;
      in.max_displacement = u_el;
      in.stop_at_separation = false;
      in.progress = false;
      const std::clock_t explicit_cpu = std::clock();
      const sc::tension_result e = sc::run_direct_tension<tessera::prism_solver>(scene, scene.contact, in);
      const double explicit_cpu_s = cpu_seconds_since(explicit_cpu);
      const std::size_t last = e.displacement.size() - 1;
      const real u_last = e.displacement[last], sigma_last = e.stress[last];
      real sxx = 0, sxy = 0, sx = 0, sy = 0, n = 0;
      for (std::size_t k = 0; k <= last; ++k) {
        const real x = e.displacement[k] / length, y = e.stress[k];
        if (e.displacement[k] < 0.3 * u_el) continue;
        sxx += x * x, sxy += x * y, sx += x, sy += y, n += 1;
      }
      const real slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
      const real inertia = 0.5 * std::abs(e.stress_top[last] - e.stress_bottom[last]) / std::abs(sigma_last);
      std::printf("## Explicit to U_el (direct_tension defaults: %.3g m per step, dt %.4g s, %d thread(s))\n\n",
                  in.step_displacement, e.dt, threads);
      std::printf("- %lld steps, %.3f s, CPU %.3f s (solver construction and mass scaling included), stopped at U = "
                  "%.6g m\n",
                  static_cast<long long>(e.steps), e.runtime_s, explicit_cpu_s, u_last);
      std::printf("- stress there %.6g Pa (implicit at that U: %.6g Pa, %+.3e relative); inertia |R_top + R_bottom| / 2 "
                  "over the stress: %.3e\n",
                  sigma_last, modulus_implicit * u_last / length,
                  sigma_last / (modulus_implicit * u_last / length) - 1, inertia);
      std::printf("- modulus: least-squares slope over 0.3-1 U_el %.8g Pa (%+.3e against the implicit), secant at the "
                  "last sample %.8g Pa (%+.3e)\n",
                  slope, slope / modulus_implicit - 1, sigma_last / (u_last / length),
                  sigma_last / (u_last / length) / modulus_implicit - 1);
      std::printf("- softening area at the stop %.4g m^2, tensile dissipation %.4g J\n\n", e.process_zone_area,
                  e.dissipated_tension);
      std::fflush(stdout);
    }

    // ---- implicit past the elastic limit, path following ----
    if (path_following) {
      const std::clock_t pf_cpu = std::clock();
      std::FILE* curve = curve_file.empty() ? nullptr : std::fopen(curve_file.c_str(), "w");
      tessera::require(curve_file.empty() || curve != nullptr, "implicit_prism: cannot open ", curve_file);
      if (curve) std::fprintf(curve, "displacement_m,stress_Pa,pseudo_time_s,dissipated_tension_J,dissipated_shear_J,"
                                     "iterations,controlled\n");
      const auto sample = [&](int iterations, int controlled) {
        if (curve)
          std::fprintf(curve, "%.9g,%.9g,%.9g,%.9g,%.9g,%d,%d\n", q.mean_displacement(top).z(), stress(),
                       q.prescribed_time(), q.dissipated_tension(), q.dissipated_shear(), iterations, controlled);
      };
      sample(r.iterations, 0);
      // Displacement control while the stress rises.
      real previous = stress(), peak = previous, u_peak = q.mean_displacement(top).z();
      std::int64_t displacement_increments = 0, controlled_increments = 0, failed_attempts = 0;
      o.control_fraction = control_fraction;
      o.unload_outside_control = unload_outside;
      im::increment_options plain = o;
      plain.line_search = false;
      for (;;) {
        const auto step = q.solve_increment(increment * u_el, plain);
        if (!step.converged) {
          ++failed_attempts;
          break;
        }
        ++displacement_increments;
        sample(step.iterations, 0);
        const real now = stress();
        if (now > peak) peak = now, u_peak = q.mean_displacement(top).z();
        if (now < previous) break;
        previous = now;
      }
      std::printf("## Path following: displacement control to U = %.6g m (stress %.6g Pa), then crack-opening control\n\n",
                  q.mean_displacement(top).z(), stress());
      std::printf("| U (m) | stress (Pa) | crack work (J) | iterations | dissipated tension (J) | softening | broken |\n"
                  "|---|---|---|---|---|---|---|\n");
      real work = crack_work;
      bool failed = false;
      int line = 0;
      while (q.mean_displacement(top).z() < until) {
        im::increment_result step;
        int halvings = 0;
        for (;; ++halvings) {
          step = q.solve_controlled_increment(work, o);
          if (step.converged || halvings == 8) break;
          ++failed_attempts;
          work *= 0.5;
        }
        if (!step.converged) {
          failed = true;
          std::printf("| stopped: no convergence at crack work %.3g J, residual %.3g N, %lld advancing, %lld reversals |\n",
                      work, step.max_residual, static_cast<long long>(step.advancing),
                      static_cast<long long>(step.reversals));
          break;
        }
        ++controlled_increments;
        sample(step.iterations, 1);
        const real now = stress();
        if (now > peak) peak = now, u_peak = q.mean_displacement(top).z();
        if (line++ % 10 == 0)
          std::printf("| %.6g | %.6g | %.3g | %d | %.6g | %lld | %lld |\n", q.mean_displacement(top).z(), now, work,
                      step.iterations, q.dissipated_tension(), static_cast<long long>(step.softening),
                      static_cast<long long>(step.broken));
        std::fflush(stdout);
        if (step.iterations <= 6) work = std::min(max_crack_work, 1.5 * work);
      }
      if (curve) std::fclose(curve);
      const auto& t = q.counts();
      std::printf("\n- %s at U = %.6g m, stress %.6g Pa; peak %.6g Pa at U = %.6g m\n",
                  failed ? "stopped (no convergence)" : "reached --until", q.mean_displacement(top).z(), stress(), peak,
                  u_peak);
      std::printf("- dissipated: tension %.6g J, shear %.6g J\n", q.dissipated_tension(), q.dissipated_shear());
      std::printf("- increments: %lld under displacement control, %lld under crack-opening control, %lld failed attempts; "
                  "in all %lld increments, %lld iterations, %lld factorisations, %lld solves\n",
                  static_cast<long long>(displacement_increments), static_cast<long long>(controlled_increments),
                  static_cast<long long>(failed_attempts), static_cast<long long>(t.increments),
                  static_cast<long long>(t.iterations), static_cast<long long>(t.factorizations),
                  static_cast<long long>(t.solves));
      std::printf("- CPU %.2f s past U_el (%.2f s from the start); work %.2f s (assembly %.2f, factorisation %.2f, "
                  "solves %.2f, forces %.2f)\n",
                  cpu_seconds_since(pf_cpu), implicit_cpu_s + cpu_seconds_since(pf_cpu), t.total_s(), t.assembly_s,
                  t.factorization_s, t.solve_s, t.force_s);
    }

    // ---- implicit past the elastic limit ----
    if (through_peak) {
      std::printf("## Implicit past U_el: increments of %.3g U_el, retried with the line search and halved up to 6 "
                  "times on failure%s\n\n", increment,
                  refactor ? ", factorised in every iteration" : "");
      std::printf("| U (m) | stress (Pa) | increment (m) | iterations | softening | broken | slipped | time (s) |\n"
                  "|---|---|---|---|---|---|---|---|\n");
      const std::clock_t peak_cpu = std::clock();
      real peak = sigma_el, u = (1 - 1e-6) * u_el, u_peak = u;
      double time_to_peak_s = c.total_s(), cpu_to_peak_s = implicit_cpu_s;
      const auto report_failure = [&](real at, real size, const im::increment_result& step, const char* how) {
        std::printf("| (%.6g) | not converged%s, residual %.3g N after %d iterations; %lld advancing, %lld reversals "
                    "in the last | %.3g | | %lld | %lld | %lld | %.2f |\n",
                    at, how, step.max_residual, step.iterations, static_cast<long long>(step.advancing),
                    static_cast<long long>(step.reversals), size, static_cast<long long>(step.softening),
                    static_cast<long long>(step.broken), static_cast<long long>(step.slipped), q.counts().total_s());
      };
      bool failed = false;
      while (!failed) {
        real du = increment * u_el;
        im::increment_result step;
        int halvings = 0;
        for (;; ++halvings) {
          // The options as given, then (unless they search already) the same increment with the
          // line search, which settles where the plain or Aitken steps hop between cracks.
          bool searched = o.line_search;
          step = q.solve_increment(du, o);
          if (!step.converged && !searched && !no_fallback) {
            report_failure(u + du, du, step, "");
            im::increment_options with_search = o;
            with_search.line_search = true;
            step = q.solve_increment(du, with_search);
            searched = true;
          }
          if (step.converged || halvings == 6) break;
          report_failure(u + du, du, step, searched ? ", line search" : "");
          du *= 0.5;
        }
        if (!step.converged) {
          failed = true;
          break;
        }
        u += du;
        const real sigma = stress();
        if (sigma > peak) {
          peak = sigma;
          u_peak = u;
          time_to_peak_s = q.counts().total_s();
          cpu_to_peak_s = implicit_cpu_s + cpu_seconds_since(peak_cpu);
        }
        std::printf("| %.6g | %.6g | %.3g | %d | %lld | %lld | %lld | %.2f |\n", u, sigma, du, step.iterations,
                    static_cast<long long>(step.softening), static_cast<long long>(step.broken),
                    static_cast<long long>(step.slipped), q.counts().total_s());
        std::fflush(stdout);
        if (sigma < 0.5 * peak) break;
      }
      const auto& t = q.counts();
      std::printf("\n- peak %.6g Pa at U = %.6g m, reached after %.2f s (CPU %.2f s) of implicit work from the start\n",
                  peak, u_peak, time_to_peak_s, cpu_to_peak_s);
      std::printf("- %s; peak %.6g Pa; %lld increments, %lld iterations, %lld factorisations, %lld solves; time %.2f s "
                  "(assembly %.2f, factorisation %.2f, solves %.2f, forces %.2f)\n",
                  failed ? "stopped: an increment did not converge at 1/64 of its size" : "reached 0.5 x peak", peak,
                  static_cast<long long>(t.increments), static_cast<long long>(t.iterations),
                  static_cast<long long>(t.factorizations), static_cast<long long>(t.solves), t.total_s(), t.assembly_s,
                  t.factorization_s, t.solve_s, t.force_s);
    }
  } catch (const std::exception& e) {
    tessera::cli::print_error("implicit_prism", e);
    return 1;
  }
  return 0;
}
