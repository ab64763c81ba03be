// The definitions of the larger functions that blocks/detail/rigid_step_bound.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../rigid_step_bound.hpp"

namespace tessera::blocks::detail {

[[nodiscard]] TESSERA_INLINE integrator::critical_step rigid_step_bound(std::span<const rigid_body> bodies,
                                                                 const node_set& gridpoints, const soa3& body_position,
                                                                 real amplification, bool skip_prescribed) {
  integrator::critical_step out;
  for (const rigid_body& bd : bodies) {
    if (skip_prescribed && rigid_fully_prescribed(gridpoints, bd)) continue;
    const auto [k_t, k_r] = rigid_stiffness_bounds(gridpoints, body_position, bd);
    if (k_t > 0) {
      const real dt = 2 * std::sqrt(bd.mass / (2 * amplification * k_t));
      if (dt < out.dt) out = {dt, bd.first, bd.mass, 2 * k_t};
    }
    if (k_r > 0) {
      const real i_min = bd.inertia.minCoeff();
      const real dt = 2 * std::sqrt(i_min / (2 * amplification * k_r));
      if (dt < out.dt) out = {dt, bd.first, bd.mass, 2 * k_r * bd.mass / i_min};
    }
  }
  return out;
}

TESSERA_INLINE integrator::mass_scaling_report scale_rigid_masses(std::span<rigid_body> bodies, const node_set& gridpoints,
                                                                  const soa3& body_position, real target_dt, real safety,
                                                                  real amplification) {
  integrator::mass_scaling_report rep;
  // safety 2 sqrt(m / (2 a k)) >= dt*  <=>  m >= 2 a k (dt* / (2 safety))^2
  const real c = 2 * amplification * (target_dt / (2 * safety)) * (target_dt / (2 * safety));
  for (rigid_body& bd : bodies) {
    rep.original_mass += bd.mass;
    const auto [k_t, k_r] = rigid_stiffness_bounds(gridpoints, body_position, bd);
    const real factor = std::max({real(1), c * k_t / bd.mass, c * k_r / bd.inertia.minCoeff()});
    if (factor > 1) {
      rep.added_mass += (factor - 1) * bd.mass;
      bd.mass *= factor;
      bd.inertia *= factor;
      ++rep.scaled_nodes;
    }
  }
  return rep;
}

}  // namespace tessera::blocks::detail
