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
  // Columns through raw pointers, the same arithmetic as the Eigen rows (the same bits); the
  // prescriptions of a gridpoint looked at only when one of its components is prescribed.
  const real* f_col[3] = {gp.force.col(0).data(), gp.force.col(1).data(), gp.force.col(2).data()};
  const real* r_col[3] = {body_position.col(0).data(), body_position.col(1).data(), body_position.col(2).data()};
  const std::uint8_t* c_col[3] = {gp.constraint.col(0).data(), gp.constraint.col(1).data(), gp.constraint.col(2).data()};
  const mat3 rotation = bd.rotation;
  vec3 f_sum = vec3::Zero(), m_sum = vec3::Zero();
  for (index_t i = bd.first; i < bd.end; ++i) {
    const vec3 f(f_col[0][i], f_col[1][i], f_col[2][i]);
    const vec3 rho = rotation * vec3(r_col[0][i], r_col[1][i], r_col[2][i]);
    f_sum += f;
    m_sum += rho.cross(f);
    if ((c_col[0][i] == prescribed) | (c_col[1][i] == prescribed) | (c_col[2][i] == prescribed)) [[unlikely]] {
      for (int c = 0; c < 3; ++c) {
        if (c_col[c][i] != prescribed) continue;
        const auto cs = static_cast<std::size_t>(c);
        if (con.count[cs]++ == 0) {
          con.first[cs] = i;
          con.velocity[c] = gp.prescribed_velocity(i, c);
        } else if (gp.prescribed_velocity(i, c) != con.velocity[c] && con.conflict[cs] == invalid_index) {
          con.conflict[cs] = i;
        }
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
  // Columns through raw pointers, the same Eigen arithmetic on fixed-size vectors (the same
  // bits); a gridpoint's reaction share is its component's share or 0, the share divided once.
  const bool held = count[0] + count[1] + count[2] > 0;
  real share[3] = {0, 0, 0};
  for (int c = 0; c < 3; ++c)
    if (count[static_cast<std::size_t>(c)] > 0) share[c] = reaction[c] / static_cast<real>(count[static_cast<std::size_t>(c)]);
  const real* r_col[3] = {body_position.col(0).data(), body_position.col(1).data(), body_position.col(2).data()};
  real* u_col[3] = {gp.displacement.col(0).data(), gp.displacement.col(1).data(), gp.displacement.col(2).data()};
  real* v_col[3] = {gp.velocity.col(0).data(), gp.velocity.col(1).data(), gp.velocity.col(2).data()};
  real* reaction_col[3] = {gp.reaction.col(0).data(), gp.reaction.col(1).data(), gp.reaction.col(2).data()};
  const std::uint8_t* c_col[3] = {gp.constraint.col(0).data(), gp.constraint.col(1).data(), gp.constraint.col(2).data()};
  // (Local copies: the stores to the gridpoints cannot alias them, so they stay in registers.)
  const vec3 displacement = bd.displacement, velocity = bd.velocity, turn = phi;
  const mat3 before = rotation_old;
  for (index_t i = bd.first; i < bd.end; ++i) {
    const vec3 r(r_col[0][i], r_col[1][i], r_col[2][i]);
    const vec3 u = displacement + change * r;
    const vec3 phi_x_r = turn.cross(r);
    const vec3 increment = along * phi_x_r + across * turn.cross(phi_x_r);
    const vec3 v = velocity + before * increment * inv_dt;
    for (int c = 0; c < 3; ++c) {
      u_col[c][i] = u[c];
      v_col[c][i] = v[c];
      reaction_col[c][i] = held && c_col[c][i] == prescribed ? share[c] : 0.0;
    }
  }
}

}  // namespace tessera::blocks::detail
