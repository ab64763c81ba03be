#pragma once
// The reclose case of examples/verification: the study's plain prism (100 blocks, deformable,
// power softening; examples/common/scenes.hpp) pulled past its peak until a crack has formed,
// pushed back through closure into compression, then pulled again:
//   - after the crack closes the prism carries compression at its intact stiffness: the slope of
//     stress against displacement between -0.5 f_T and -1.5 f_T against the slope of the first
//     pull between 10 % and 50 % of the peak (within 2 %);
//   - the closed crack carries no tension: on the last pull the stress never rises above what
//     it carried when the push began (the crack does not heal).
// The crack closes on the tessellation's own faces (contact::face_contacts keeps each broken
// face's state), which checks closure, not the hand-over of broken faces to detected contacts
// (a crack that slides onto new neighbours; the same prism on bonded detected contacts:
// tests/test_rigid.cpp "[prism]").

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "common/quasi_static.hpp"
#include "common/scenes.hpp"
#include "tessera/analysis/curves.hpp"
#include "tessera/presets.hpp"
#include "tessera/solver.hpp"

namespace tessera::verification {

struct reclose_result {
  real tensile_slope = 0, compressive_slope = 0;  ///< Pa per m of top displacement
  real peak = 0, stress_at_reversal = 0, max_stress_after_closure = 0, min_stress = 0;  ///< Pa
  real f_T = 0;
  index_t steps = 0;
  real dt = 0, energy_error_rel = 0;
  std::string damping_in_force;  ///< solver::damping_in_force() of the run
  std::vector<double> u, stress;  ///< the whole path (m, Pa)
};

/// Pulls at +rate until the stress has fallen below `crack_ratio` x peak, pushes at -rate to
/// -1.6 f_T, pulls at +rate back to the reversal displacement. 5 nm per step (mass scaling).
[[nodiscard]] inline reclose_result run_reclose(bool quick, std::uint64_t seed = 1) {
  namespace bc = tessera::bc;
  namespace rec = tessera::recorders;
  scenes::prism_options po;
  po.seed = seed;
  const scenes::prism_scene scene = scenes::make_prism(po);
  const real rate = 0.005, step_displacement = 5e-9, crack_ratio = quick ? 0.6 : 0.3;
  solver_options opt;
  opt.mass_scaling_dt = step_displacement / rate;
  prism_solver s(scene.tess, scene.mesh, scene.block_material, scene.contact, {}, opt);
  const real length = scene.length(), area = scene.cross_section(), f_t = scene.contact.tension.f_T;
  const bc::node_group bottom = s.gridpoints_on_plane(2, 0.0, 1e-9 * length);
  const bc::node_group top = s.gridpoints_on_plane(2, length, 1e-9 * length);
  s.fix(bottom);
  s.fix(top, bc::transverse_to(2));
  s.prescribe_velocity(top, vec3::Zero(), bc::components::z);
  scenes::require_quasi_static("verification reclose", rate, length, scenes::concrete_young, scenes::concrete_density,
                               s.mass_scaling().added_mass / s.mass_scaling().original_mass, f_t);
  const real total_mass = s.mass_scaling().original_mass + s.mass_scaling().added_mass;
  const real transit = length * std::sqrt(total_mass / (length * area) / scenes::concrete_young);
  const real ramp = 4 * transit;

  reclose_result r;
  r.f_T = scene.f_T;
  // Phases: 0 pull to the crack, 1 push to compression, 2 pull back. Each reversal ramps the
  // velocity from the old to the new value over `ramp` (half cosine), as the first start does.
  int phase = 0;
  real v_from = 0, v_to = rate, t_switch = 0, u_reversal = 0;
  std::size_t first_push = 0, first_pull_back = 0;
  const auto velocity = [&](const prism_solver& sv) {
    const real t = sv.time() + 0.5 * sv.dt() - t_switch;
    const real f = t >= ramp ? 1 : 0.5 * (1 - std::cos(std::numbers::pi * t / ramp));
    bc::update_velocity(s.gridpoints(), top, vec3(0, 0, v_from + (v_to - v_from) * f), bc::components::z);
  };
  bool stop = false;
  const auto observe = [&](const prism_solver& sv) {
    const real u = rec::mean_displacement(sv.gridpoints(), top).z();
    const real sigma = 0.5 * (rec::reaction_sum(sv.gridpoints(), top).z() - rec::reaction_sum(sv.gridpoints(), bottom).z()) / area;
    r.u.push_back(u);
    r.stress.push_back(sigma);
    r.peak = std::max(r.peak, sigma);
    r.min_stress = std::min(r.min_stress, sigma);
    if (phase == 0 && r.peak > 0.5 * f_t && sigma < crack_ratio * r.peak) {
      phase = 1, v_from = rate, v_to = -rate, t_switch = sv.time();
      r.stress_at_reversal = sigma;
      u_reversal = u;
      first_push = r.u.size();
    } else if (phase == 1 && sigma < -1.6 * f_t) {
      phase = 2, v_from = -rate, v_to = rate, t_switch = sv.time();
      first_pull_back = r.u.size();
    } else if (phase == 2) {
      r.max_stress_after_closure = std::max(r.max_stress_after_closure, sigma);
      if (u >= u_reversal) stop = true;
    }
    if (sv.step_count() > 20'000'000) stop = true;  // a path that never gets there
  };
  velocity(s);
  s.run_until([&](const prism_solver&) { return stop; }, std::int64_t{1} << 40, velocity, rec::every(50, observe));
  require(phase == 2 && stop, "verification reclose: the loading path did not complete (phase ", phase, ")");

  // Intact: the first pull between 10 % and 50 % of the peak. Closed crack: the push between
  // -0.5 f_T and -1.5 f_T (samples of the push phase only; it starts in tension).
  std::size_t first_peak = 0;
  for (std::size_t k = 0; k < first_push; ++k)
    if (r.stress[k] >= r.peak) first_peak = k;
  r.tensile_slope = analysis::band_slope(r.u, r.stress, first_peak, 0.1 * r.peak, 0.5 * r.peak);
  const std::vector<real> u_push(r.u.begin() + static_cast<std::ptrdiff_t>(first_push),
                                 r.u.begin() + static_cast<std::ptrdiff_t>(first_pull_back));
  const std::vector<real> s_push(r.stress.begin() + static_cast<std::ptrdiff_t>(first_push),
                                 r.stress.begin() + static_cast<std::ptrdiff_t>(first_pull_back));
  r.compressive_slope = analysis::band_slope(u_push, s_push, u_push.size(), -1.5 * f_t, -0.5 * f_t);
  r.steps = s.step_count();
  r.dt = s.dt();
  r.damping_in_force = s.damping_in_force();
  r.energy_error_rel = s.energies().error_rel();
  return r;
}

}  // namespace tessera::verification
