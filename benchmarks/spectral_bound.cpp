// spectral_bound: how sharp the Gershgorin stable step is on the quick scenes (issue #43,
// candidate 1). For the quick prism, tie and beam, built with the drivers' scene builders and
// solver types, it estimates lambda_max(M^-1 K) with the solver's own kernels
// (analysis::estimate_max_frequency_squared, Lanczos) and sets it against the Gershgorin bound the
// solver's step comes from, on the unscaled masses and on the masses the driver scales to:
//
//   dt_cr(G)  = 2 / sqrt(a lambda_G), the solver's critical step (before the safety factor)
//   dt_cr(L)  = 2 / sqrt(a lambda_max), the critical step of the estimate
//   ratio     = dt_cr(L) / dt_cr(G) = sqrt(lambda_G / lambda_max)
//   same added mass: the mass-scaled run could take dt x ratio, i.e. 1 - 1/ratio of its steps saved
//   same step: the Gershgorin target dt_g whose scaled masses have dt_cr(L) = dt* / safety (found
//            by fixed-point iteration dt_g <- dt_g dt* / (safety dt_cr(L)(dt_g))), and the mass
//            that target adds against the driver's
//
// Scenes (the drivers' --quick values): prism 100 blocks, dt* = 5 nm / 5 mm/s = 1 us, gamma 0.8,
// bottom fixed, top held; tie 100 blocks, dt* = 4 us, tie ends held (hold_tie_ends); beam 60
// blocks, 50 mm face zoning, added mass 20x, no supports and no plates (their platen springs are
// outside the model's K, so both bounds leave them out). --full: the drivers' defaults instead
// (prism dt* = 2 nm / 5 mm/s = 0.4 us, tie dt* = 1 us, beam 250 blocks with h/5 zoning).
//
//   spectral_bound [--seed N] [--iterations K] [--scene prism|tie|beam|all] [--full]
// Prints one table (markdown) on stdout.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>

#include "common/cli.hpp"
#include "common/rc_tie_run.hpp"
#include "common/scenes.hpp"
#include "rc_beam/beam.hpp"
#include "tessera/analysis/spectral_bound.hpp"
#include "tessera/integrator/timestep.hpp"
#include "tessera/presets.hpp"

namespace {
namespace sc = tessera::scenes;
namespace an = tessera::analysis;
using tessera::real;

/// The added-mass ratio of scaling the unscaled solver `s` to the Gershgorin target dt (s).
template <class Solver>
real added_ratio(const Solver& s, real dt) {
  const real a = s.stiffness_amplification(), safety = s.options().safety;
  auto r = tessera::integrator::preview_mass_scaling(s.gridpoints(), dt, safety, a);
  if constexpr (Solver::reinforcement_type::enabled)
    r += tessera::integrator::preview_mass_scaling(s.bar_nodes(), dt, safety, a);
  return r.added_mass / r.original_mass;
}

/// A copy of the unscaled solver `s` with its masses scaled to the Gershgorin target dt (s).
template <class Solver>
Solver scaled_copy(const Solver& s, real dt) {
  Solver c = s;
  const real a = s.stiffness_amplification(), safety = s.options().safety;
  (void)tessera::integrator::scale_masses(c.gridpoints(), dt, safety, a);
  if constexpr (Solver::reinforcement_type::enabled)
    (void)tessera::integrator::scale_masses(c.bar_nodes(), dt, safety, a);
  c.compute_time_step();  // the critical step of the scaled masses (options carry no scaling)
  return c;
}

void print_row(const char* scene, const char* masses, tessera::index_t dofs, const an::stable_step_sharpness& r,
               const std::string& meaning) {
  std::printf("| %s | %s | %lld | %.4g | %.4g | %.3f | %.3f | %d | %.1e | %s |\n", scene, masses,
              static_cast<long long>(dofs), r.gershgorin_step(), r.spectral_step(), r.spectral_step() / r.gershgorin_step(),
              r.ratio(), r.estimate.iterations, r.estimate.residual, meaning.c_str());
  std::fflush(stdout);
}

/// Unscaled row, then the mass-scaled rows for the driver's target step dt* (s) (or, with
/// target_ratio > 0, the step that adds that multiple of the mass, as the driver resolves it).
template <class Solver, class Supports>
void study(const char* scene, const Solver& unscaled, real target_dt, real target_ratio, const an::spectral_options& o,
           Supports&& supports) {
  const real safety = unscaled.options().safety;
  {
    Solver s = unscaled;
    supports(s);
    const auto r = an::estimate_max_frequency_squared(s, o);
    char m[200];
    std::snprintf(m, sizeof m, "physical masses: dt %.3g s -> %.3g s, %.0f %% fewer steps", safety * r.gershgorin_step(),
                  safety * r.spectral_step(), 100 * (1 - r.gershgorin_step() / r.spectral_step()));
    print_row(scene, "unscaled", r.estimate.dofs, r, m);
  }
  if (target_ratio > 0) {
    // As the solver resolves --added-mass: the Gershgorin target step that adds target_ratio.
    real unscaled_dt = unscaled.critical_step().dt;
    if constexpr (Solver::reinforcement_type::enabled)
      unscaled_dt = std::min(unscaled_dt, tessera::integrator::critical_time_step(unscaled.bar_nodes(),
                                                                                  unscaled.stiffness_amplification()).dt);
    target_dt = tessera::integrator::step_for_added_mass(target_ratio, safety * unscaled_dt,
                                                         [&](real dt) { return added_ratio(unscaled, dt); });
  }
  const real driver_added = added_ratio(unscaled, target_dt);
  Solver scaled = scaled_copy(unscaled, target_dt);
  supports(scaled);
  const auto r = an::estimate_max_frequency_squared(scaled, o);
  {
    // Another random start must find the same lambda_max (a Ritz value that converged to a
    // lesser eigenvalue would differ).
    an::spectral_options other = o;
    other.seed = o.seed + 1;
    const real again = an::estimate_max_frequency_squared(scaled, other).estimate.lambda_max;
    std::fprintf(stderr, "%s, scaled to dt*: lambda_max %.9g (Lanczos start %llu) and %.9g (start %llu), relative difference %.1e\n",
                 scene, r.estimate.lambda_max, static_cast<unsigned long long>(o.seed), again,
                 static_cast<unsigned long long>(other.seed), std::abs(again - r.estimate.lambda_max) / r.estimate.lambda_max);
  }
  char m[240];
  std::snprintf(m, sizeof m, "same added mass (%.2fx): dt %.3g s -> %.3g s, %.0f %% fewer steps", driver_added,
                target_dt, safety * r.spectral_step(), 100 * (1 - r.gershgorin_step() / r.spectral_step()));
  print_row(scene, "scaled to dt*", r.estimate.dofs, r, m);
  // Same step: the Gershgorin target dt_g < dt* whose masses the estimate finds stable at dt*.
  real dt_g = target_dt * r.gershgorin_step() / r.spectral_step();
  an::stable_step_sharpness at{};
  for (int k = 0; k < 4; ++k) {
    Solver c = scaled_copy(unscaled, dt_g);
    supports(c);
    at = an::estimate_max_frequency_squared(c, o);
    const real next = dt_g * target_dt / (safety * at.spectral_step());
    const bool settled = std::abs(next - dt_g) <= 1e-3 * dt_g;
    dt_g = next;
    if (settled) break;
  }
  std::snprintf(m, sizeof m, "same dt* = %.3g s: added mass %.2fx -> %.2fx (Gershgorin target %.3g s)", target_dt,
                driver_added, added_ratio(unscaled, dt_g), dt_g);
  print_row(scene, "scaled, same dt*", at.estimate.dofs, at, m);
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t seed = 1;
  int iterations = 300;
  std::string scene = "all";
  bool full = false;
  tessera::cli::parser cli("spectral_bound",
                           "lambda_max(M^-1 K) by Lanczos on the solver's kernels against the Gershgorin bound of the\n"
                           "stable step, on the quick prism, tie and beam, unscaled and mass-scaled (issue #43).");
  cli.option("--seed", seed, "tessellation seed", "N");
  cli.option("--iterations", iterations, "most Lanczos steps per estimate", "K").within(1, 5000);
  cli.option("--scene", scene, "which scene", "prism|tie|beam|all").one_of({"prism", "tie", "beam", "all"});
  cli.flag("--full", full, "the drivers' default runs instead of their --quick ones");
  cli.parse_or_exit(argc, argv);
  try {
    an::spectral_options o;
    o.iterations = iterations;
    o.tolerance = 1e-6;
    std::printf("| scene | masses | free dofs | dt_cr Gershgorin (s) | dt_cr Lanczos (s) | dt ratio | lambda_G / lambda_max "
                "| iterations | residual | what it means |\n|---|---|---|---|---|---|---|---|---|---|\n");
    if (scene == "prism" || scene == "all") {
      sc::prism_options po;
      po.seed = seed;
      const sc::prism_scene p = sc::make_prism(po);
      const tessera::prism_solver s(p.tess, p.mesh, p.block_material, p.contact);
      study("prism 100", s, (full ? 2e-9 : 5e-9) / 0.005, 0, o, [&](tessera::prism_solver& v) {
        const real tol = 1e-9 * p.length();
        v.fix(v.gridpoints_on_plane(2, 0.0, tol));
        const auto top = v.gridpoints_on_plane(2, p.length(), tol);
        v.fix(top, tessera::bc::transverse_to(2));
        v.prescribe_velocity(top, tessera::vec3::Zero(), tessera::bc::components::z);
      });
    }
    if (scene == "tie" || scene == "all") {
      sc::tie_options to;
      to.seed = seed;
      const sc::tie_scene t = sc::make_tie(to);
      using tie = sc::tie_solver<sc::deformable_blocks, tessera::presets::study_tie_law>;
      const tie s(t.prism.tess, t.prism.mesh, t.prism.block_material, t.prism.contact, t.bar);
      study("tie 100", s, full ? sc::default_tie_dt : 4e-6, 0, o, [&](tie& v) { (void)sc::hold_tie_ends(v, t); });
    }
    if (scene == "beam" || scene == "all") {
      sc::beam_options bo;
      bo.seed = seed;
      bo.blocks = full ? 250 : 60;
      bo.zone_edge = full ? 0 : 0.05;
      const sc::beam_scene b = sc::make_beam(bo);
      using beam = sc::beam_solver<tessera::presets::study_beam_law>;
      const beam s(b.tess, b.mesh, b.block_material, b.contact, b.bar);
      study(full ? "beam 250" : "beam 60", s, 0, 20, o, [](beam&) {});
    }
  } catch (const std::exception& e) {
    tessera::cli::print_error("spectral_bound", e);
    return 1;
  }
  return 0;
}
