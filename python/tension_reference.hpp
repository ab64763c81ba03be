#pragma once
// examples/python/direct_tension.py in C++, statement for statement: the study's prism (100
// Voronoi blocks, seed 1) on tessera::instances::prism_solver, pulled as examples/direct_tension
// --quick pulls it (half-cosine ramp, 5 nm per step, stopped at 70 % of the peak). Compiled into
// the program tessera_python_tension_cpp (python/tension_reference.cpp: writes curve.csv) and
// into the module as tessera._tension_reference(), so benchmarks/python_speed.py times the script
// against the same work in another process and in the same one; python/tests compares the curves.
#include <tessera/geometry.hpp>
#include <tessera/instances/prism.hpp>  // its solver compiled once: link tessera::instances
#include <tessera/presets/pulatsu2020.hpp>
#include <tessera/solver.hpp>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace tessera::python_reference {

/// The curve's columns: top displacement (m), mean axial stress, the stresses from the top and
/// the bottom reactions (Pa), largest unbalanced force over f_T A; one row every 100 steps.
inline std::vector<std::vector<double>> tension_curve(int threads) {
  // 1. geometry
  aabb box;
  box.lo = vec3(0, 0, 0);
  box.hi = vec3(0.068, 0.068, 0.6);
  const auto tess = geometry::random_voronoi(box, 100, 1);
  const auto mesh = geometry::zone_blocks(tess);
  // 2. materials
  const zones::linear_elastic_tet::params block{10 * 28e9, 0.2, 2400.0};
  auto contact = presets::scaled_prism_params(100);
  contact.shear.c_0 = 2 * contact.tension.f_T;
  contact.shear.c_res = 0.01 * contact.shear.c_0;
  // 3. the solver
  const real rate = 5e-3;
  const std::int64_t sample = 100;  // steps between curve rows
  solver_options options;
  options.mass_scaling_dt = 5e-9 / rate;
  options.threads = threads;
  instances::prism_solver s(tess, mesh, block, contact, {}, options);
  // 4. supports
  const real length = box.size().z(), area = box.size().x() * box.size().y(), tol = 1e-9 * length;
  const auto bottom = s.gridpoints_on_plane(2, 0.0, tol);
  const auto top = s.gridpoints_on_plane(2, length, tol);
  s.fix(bottom);
  s.fix(top, bc::transverse_to(2));
  s.prescribe_velocity(top, vec3(0, 0, 0), bc::components::z);
  // 5. loading
  const real f_t = contact.tension.f_T;
  const real mass = s.mass_scaling().original_mass + s.mass_scaling().added_mass;
  const real ramp_time = 4 * (length * std::sqrt(mass / (length * area) / 28e9));
  const real tail_speedup = 4, tail_stress_ratio = 0.3;
  real tail_start = -1, peak_stress = 0, peak_displacement = 0;
  bool stop = false;
  std::vector<std::vector<double>> curve(5);
  const auto half_cosine = [&](real t) {
    return t >= ramp_time ? real(1) : real(0.5) * (1 - std::cos(std::numbers::pi * t / ramp_time));
  };
  const auto ramp = [&](const instances::prism_solver& sv) {
    const real t_mid = sv.time() + 0.5 * sv.dt();
    real factor = 1;
    if (tail_start >= 0) {
      if (t_mid - tail_start > ramp_time + sv.dt()) return;
      factor = 1 + (tail_speedup - 1) * half_cosine(t_mid - tail_start);
    } else {
      if (t_mid > ramp_time + sv.dt()) return;
      factor = half_cosine(t_mid);
    }
    bc::update_velocity(s.gridpoints(), top, vec3(0, 0, rate * factor), bc::components::z);
  };
  const auto observe = [&](const instances::prism_solver& sv) {
    const real u = recorders::mean_displacement(sv.gridpoints(), top).z();
    const real r_top = recorders::reaction_sum(sv.gridpoints(), top).z();
    const real r_bottom = recorders::reaction_sum(sv.gridpoints(), bottom).z();
    const real sigma = 0.5 * (r_top - r_bottom) / area;
    curve[0].push_back(u), curve[1].push_back(sigma), curve[2].push_back(r_top / area);
    curve[3].push_back(-r_bottom / area), curve[4].push_back(sv.unbalanced_force().max_force / (f_t * area));
    if (sigma > peak_stress) peak_stress = sigma, peak_displacement = u;
    const bool past_peak = u > 1.2 * peak_displacement && peak_stress > 0.5 * f_t;
    if (tail_start < 0 && past_peak && sigma < tail_stress_ratio * peak_stress) tail_start = sv.time();
    if ((past_peak && sigma < 0.7 * peak_stress) || u >= 2e-4) stop = true;
  };
  // 6. run: the ramp after every step (and before the first), a curve row every 100 steps
  ramp(s);
  s.run_until([&](const instances::prism_solver&) { return stop; }, std::int64_t{1} << 40,
              [&](const instances::prism_solver& sv) {
                ramp(sv);
                if (sv.step_count() % sample == 0) observe(sv);
              });
  return curve;
}

}  // namespace tessera::python_reference
