// The definitions of the larger functions that blocks/detail/rigid_motion.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../rigid_motion.hpp"

namespace tessera::blocks::detail {

TESSERA_INLINE void reduce_rigid_block(const node_set& gp, const soa3& body_position, const vec3& gravity, rigid_body& bd,
                                       rigid_constraints& con) noexcept {
  con = rigid_constraints{};
  constexpr auto prescribed = static_cast<std::uint8_t>(dof_constraint::prescribed);
  vec3 f_sum = vec3::Zero(), m_sum = vec3::Zero();
  for (index_t i = bd.first; i < bd.end; ++i) {
    const vec3 f(gp.force(i, 0), gp.force(i, 1), gp.force(i, 2));
    const vec3 rho = bd.rotation * body_coordinates(body_position, i);
    f_sum += f;
    m_sum += rho.cross(f);
    for (int c = 0; c < 3; ++c) {
      if (gp.constraint(i, c) != prescribed) continue;
      const auto cs = static_cast<std::size_t>(c);
      if (con.count[cs]++ == 0) {
        con.first[cs] = i;
        con.velocity[c] = gp.prescribed_velocity(i, c);
      } else if (gp.prescribed_velocity(i, c) != con.velocity[c] && con.conflict[cs] == invalid_index) {
        con.conflict[cs] = i;
      }
    }
  }
  bd.force = f_sum + bd.weight_mass * gravity;
  bd.moment = m_sum;
}

TESSERA_INLINE void slave_rigid_gridpoints(node_set& gp, const soa3& body_position, const rigid_body& bd,
                                           const mat3& rotation_old, const vec3& phi, real dt,
                                           const std::array<index_t, 3>& count) noexcept {
  constexpr auto prescribed = static_cast<std::uint8_t>(dof_constraint::prescribed);
  const vec3& reaction = bd.reaction_force;
  const mat3 change = bd.rotation - bd.axes;
  const real inv_dt = 1 / dt;
  // rotation_increment(phi, r) = sinc(t) phi x r + (sinc(t/2)^2 / 2) phi x (phi x r),
  // t = |phi|, with its scalars taken out of the gridpoint loop (the same operations, so the
  // same bits; a square root and two sincs less per gridpoint).
  const real t = phi.norm(), s = sinc(0.5 * t);
  const real along = sinc(t), across = 0.5 * s * s;
  for (index_t i = bd.first; i < bd.end; ++i) {
    const vec3 r = body_coordinates(body_position, i);
    const vec3 u = bd.displacement + change * r;
    const vec3 phi_x_r = phi.cross(r);
    const vec3 increment = along * phi_x_r + across * phi.cross(phi_x_r);
    const vec3 v = bd.velocity + rotation_old * increment * inv_dt;
    for (int c = 0; c < 3; ++c) {
      gp.displacement(i, c) = u[c];
      gp.velocity(i, c) = v[c];
      const auto cs = static_cast<std::size_t>(c);
      gp.reaction(i, c) = gp.constraint(i, c) == prescribed ? reaction[c] / static_cast<real>(count[cs]) : 0.0;
    }
  }
}

}  // namespace tessera::blocks::detail
