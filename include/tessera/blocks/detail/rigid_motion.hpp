#pragma once
// The motion of one block of blocks::rigid in a step (steps 1-5 of rigid.hpp's file comment,
// which gives the equations and the decisions behind them): the reduction of its gridpoint forces
// to a force and a moment with the prescriptions found on its gridpoints, and the integration of
// its six degrees of freedom, with the gridpoints slaved to the result. Not a public interface.
//
// Cost: O(gridpoints of the block), no allocation. Thread safety: each call reads and writes one
// block's record and its own gridpoints' rows, so distinct blocks may run on distinct threads.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "../../core/separate_compilation.hpp"
#include "../../core/errors.hpp"
#include "../../core/nodes.hpp"
#include "../../core/parallel.hpp"
#include "../../core/types.hpp"
#include "../../integrator/concepts.hpp"
#include "rigid_body.hpp"
#include "rigid_rotation.hpp"

namespace tessera::blocks::detail {

/// Step 1 of rigid.hpp's file comment for block `bd`: its gridpoint forces reduced to the force
/// (N, with the weight m0 g) and the moment about the centroid (N m, world), in gridpoint order,
/// and the prescriptions of its gridpoints collected in `con`.
TESSERA_INLINE void reduce_rigid_block(const node_set& gp, const soa3& body_position, const vec3& gravity, rigid_body& bd,
                                       rigid_constraints& con) noexcept;

/// Throws invalid_input naming block b, component c, the two gridpoints and their velocities.
[[noreturn]] inline void throw_rigid_conflict(const node_set& gp, index_t b, const rigid_constraints& con, int c) {
  const index_t i = con.first[static_cast<std::size_t>(c)], j = con.conflict[static_cast<std::size_t>(c)];
  throw invalid_input(tessera::detail::concat("rigid blocks: block ", b, " has conflicting prescribed velocities in component ",
                                     "xyz"[c], ": gridpoint ", i, " prescribes ", gp.prescribed_velocity(i, c),
                                     " m/s, gridpoint ", j, " prescribes ", gp.prescribed_velocity(j, c),
                                     " m/s; a rigid block moves as one body (release one of them, or change the whole block's "
                                     "velocity with the solver's update_block_velocity(b, v, components))"));
}

/// Step 5 of rigid.hpp's file comment for block `bd`, whose record holds the step's result: its
/// gridpoints' displacements, secant velocities (from `rotation_old`, R before the step, and the
/// step's rotation vector phi = w+ dt) and reaction shares (the block's reaction_force split
/// equally among the `count[c]` gridpoints prescribing component c). The same operations whether
/// the block's own integration calls it or a copy of the block on another MPI rank
/// (blocks::rigid::read_body_states), so both get the same bits.
TESSERA_INLINE void slave_rigid_gridpoints(node_set& gp, const soa3& body_position, const rigid_body& bd,
                                           const mat3& rotation_old, const vec3& phi, real dt,
                                           const std::array<index_t, 3>& count) noexcept;

/// Steps 2-5 of rigid.hpp's file comment for block `bd` with the prescriptions `con` of its
/// reduction: translation, rotation, orientation and the slaved gridpoints (displacement, secant
/// velocity, reaction share). Returns the boundary work and damping dissipation of the step (J).
/// kick_dt (s): the step of the velocity update, (dt_before + dt) / 2 in the step where dt
/// changes (solver.hpp, "Time step"), else dt.
template <class Integrator>
[[nodiscard]] integrator::step_work integrate_rigid_block(const Integrator& integ, node_set& gp,
                                                          const soa3& body_position, rigid_body& bd,
                                                          const rigid_constraints& con, real dt, real kick_dt) noexcept {
  constexpr auto free = static_cast<std::uint8_t>(dof_constraint::free);
  constexpr auto prescribed = static_cast<std::uint8_t>(dof_constraint::prescribed);
  integrator::step_work w;

  // Translation, per world component.
  vec3 reaction = vec3::Zero();
  for (int c = 0; c < 3; ++c) {
    const std::uint8_t kind = con.count[static_cast<std::size_t>(c)] > 0 ? prescribed : free;
    bd.velocity[c] = integ.advance_dof(bd.force[c], bd.mass, bd.velocity[c], kind, con.velocity[c], kick_dt, reaction[c], w);
  }
  bd.displacement += bd.velocity * dt;
  bd.reaction_force = reaction;

  // Rotation: Euler's equations per principal component, gyroscopic term at wm (fixed point).
  const std::uint8_t rotation_kind = con.any() ? prescribed : free;
  const vec3 torque = bd.rotation.transpose() * bd.moment;
  const vec3 w_old = bd.angular_velocity;
  vec3 w_new = w_old, moment_reaction = vec3::Zero();
  integrator::step_work rotation_work;
  constexpr int max_iterations = 20;
  for (int it = 0; it < max_iterations; ++it) {
    const vec3 wm = 0.5 * (w_old + w_new);
    const vec3 t = torque - wm.cross(bd.inertia.cwiseProduct(wm));
    rotation_work = {};
    vec3 next;
    for (int k = 0; k < 3; ++k)
      next[k] = integ.advance_dof(t[k], bd.inertia[k], w_old[k], rotation_kind, 0.0, kick_dt, moment_reaction[k], rotation_work);
    const real change = (next - w_new).cwiseAbs().maxCoeff();
    w_new = next;
    if (change <= 1e-15 * w_new.cwiseAbs().maxCoeff()) break;
  }
  w.boundary += rotation_work.boundary;
  w.damping += rotation_work.damping;
  bd.angular_velocity = w_new;
  bd.reaction_moment = bd.rotation * moment_reaction;

  // Orientation by the exponential map; gridpoints slaved with the secant velocity.
  const vec3 phi = w_new * dt;
  const mat3 rotation_old = bd.rotation;
  bd.half_orientation = (bd.orientation * rotation_vector_quaternion(0.5 * phi)).normalized();
  bd.orientation = (bd.orientation * rotation_vector_quaternion(phi)).normalized();
  bd.rotation = bd.orientation.toRotationMatrix();
  slave_rigid_gridpoints(gp, body_position, bd, rotation_old, phi, dt, con.count);
  return w;
}

/// blocks::rigid::advance over n blocks, block_of(k) the k-th (k increasing): the reductions
/// (parallel), the conflicting prescriptions (in order), the integrations (parallel, each block's
/// work into work_of[b]), then `work` gets the blocks' terms in order.
template <class Integrator, class Work, class BlockOf>
void advance_rigid_blocks(const Integrator& integ, node_set& gp, const soa3& body_position, const vec3& gravity,
                          std::vector<rigid_body>& bodies, std::vector<rigid_constraints>& constraints,
                          std::vector<integrator::step_work>& work_of, real dt, Work& work, real kick_dt, index_t n,
                          BlockOf&& block_of) {
  parallel_for(n, [&](std::int64_t k) {
    const auto b = static_cast<std::size_t>(block_of(k));
    reduce_rigid_block(gp, body_position, gravity, bodies[b], constraints[b]);
  }, 16);
  for (index_t k = 0; k < n; ++k) {
    const index_t b = block_of(k);
    const rigid_constraints& con = constraints[static_cast<std::size_t>(b)];
    for (int c = 0; c < 3; ++c)
      if (con.conflict[static_cast<std::size_t>(c)] != invalid_index) throw_rigid_conflict(gp, b, con, c);
  }
  parallel_for(n, [&](std::int64_t k) {
    const auto b = static_cast<std::size_t>(block_of(k));
    work_of[b] = integrate_rigid_block(integ, gp, body_position, bodies[b], constraints[b], dt, kick_dt);
  }, 16);
  for (index_t k = 0; k < n; ++k) {
    const integrator::step_work& w = work_of[static_cast<std::size_t>(block_of(k))];
    work.boundary += w.boundary;
    work.damping += w.damping;
  }
}

}  // namespace tessera::blocks::detail

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/rigid_motion.ipp"
#endif
