// The definitions of blocks::rigid's larger members, which blocks/rigid.hpp declares (their
// documentation is there): included at the end of that header, or compiled once into
// tessera::instances under TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp), so a
// scene's unit neither parses them nor instantiates the Eigen expressions they use.
#pragma once

#include "../rigid.hpp"

namespace tessera::blocks {

TESSERA_INLINE void rigid::build(const geometry::tessellation& tess, const geometry::block_mesh& mesh, std::span<const params> materials,
           node_set& gridpoints) {
  require(!materials.empty(), "rigid blocks: no block material given");
  for (const params& m : materials) validate(m);
  materials_.assign(materials.begin(), materials.end());
  const index_t n_b = mesh.block_count();
  const index_t n_gp = mesh.gridpoint_count();
  require<geometry_error>(n_b > 0 && n_gp > 0, "rigid blocks: block_mesh has ", n_b, " blocks and ", n_gp,
                          " gridpoints; build it with geometry::zone_blocks");
  require<geometry_error>(tess.cell_count() == n_b, "rigid blocks: the tessellation has ", tess.cell_count(),
                          " cells but the block_mesh ", n_b, " blocks; block b must be cell b");
  gridpoints.resize(n_gp);
  for (index_t i = 0; i < n_gp; ++i) gridpoints.reference.row(i) = mesh.gridpoints[static_cast<std::size_t>(i)];
  gridpoint_block_ = mesh.gridpoint_block;
  bodies_.assign(static_cast<std::size_t>(n_b), body{});
  body_position_.setZero(n_gp, 3);
  for (index_t b = 0; b < n_b; ++b) {
    body& bd = bodies_[static_cast<std::size_t>(b)];
    bd.first = mesh.block_gridpoint_offsets[static_cast<std::size_t>(b)];
    bd.end = mesh.block_gridpoint_offsets[static_cast<std::size_t>(b) + 1];
    require<geometry_error>(bd.end > bd.first, "rigid blocks: block ", b, " has no gridpoint");
    const int id = mesh.material(b);
    require(id >= 0 && static_cast<std::size_t>(id) < materials_.size(), "rigid blocks: block ", b,
            " has material id ", id, ", but ", materials_.size(), " block material(s) were given");
    const params& p = materials_[static_cast<std::size_t>(id)];
    const geometry::mass_properties mp = geometry::cell_mass_properties(tess, b);
    require<geometry_error>(mp.volume > 0, "rigid blocks: cell ", b, " has volume ", mp.volume,
                            " m^3; expected > 0 (faces CCW seen from outside)");
    const mat3 inertia = geometry::inertia_tensor(mp.second_moment, p.density);
    // Principal moments ascending and axes with det = +1 by 3x3 Jacobi rotations, not Eigen's
    // SelfAdjointEigenSolver: this non-template function made GCC compile that solver in every
    // translation unit including this header (issue #40 item 9).
    const detail::symmetric_eigen3 eig = detail::symmetric_eigen_3x3(inertia);
    const mat3& axes = eig.vectors;
    bd.mass = p.density * mp.volume;
    bd.weight_mass = bd.mass;
    bd.inertia = eig.values;
    require<geometry_error>(bd.inertia.minCoeff() > 0, "rigid blocks: cell ", b, " has principal moments (",
                            bd.inertia.transpose(), ") kg m^2; expected all > 0");
    bd.centroid = mp.centroid;
    bd.axes = axes;
    bd.orientation = Eigen::Quaterniond(axes);
    bd.orientation.normalize();
    bd.half_orientation = bd.orientation;
    bd.rotation = bd.orientation.toRotationMatrix();
    for (index_t i = bd.first; i < bd.end; ++i) {
      require<geometry_error>(gridpoint_block_[static_cast<std::size_t>(i)] == b, "rigid blocks: gridpoint ", i,
                              " lies in the range of block ", b, " but belongs to block ",
                              gridpoint_block_[static_cast<std::size_t>(i)]);
      body_position_.row(i) = (bd.rotation.transpose() * (mesh.gridpoints[static_cast<std::size_t>(i)] - bd.centroid)).transpose();
    }
  }
  share_masses(gridpoints);
  constraints_.assign(static_cast<std::size_t>(n_b), block_constraints{});
  work_.assign(static_cast<std::size_t>(n_b), integrator::step_work{});
  zone_stress_.resize(0, 6);
}

TESSERA_INLINE void rigid::write_body_states(std::span<const index_t> blocks, std::vector<double>& out) const {
  for (const index_t b : blocks) {
    const body& bd = at(b);
    for (const vec3* v : {&bd.displacement, &bd.velocity, &bd.angular_velocity, &bd.force, &bd.moment,
                          &bd.reaction_force, &bd.reaction_moment})
      out.insert(out.end(), v->data(), v->data() + 3);
    out.insert(out.end(), bd.orientation.coeffs().data(), bd.orientation.coeffs().data() + 4);
    out.insert(out.end(), bd.half_orientation.coeffs().data(), bd.half_orientation.coeffs().data() + 4);
  }
}

TESSERA_INLINE std::size_t rigid::read_body_states(std::span<const index_t> blocks, const double* in, node_set& gridpoints, real dt,
                             std::span<const std::uint8_t> slave_now, std::span<mat3> rotation_before) {
  const double* p = in;
  for (const index_t b : blocks) {
    body& bd = bodies_[static_cast<std::size_t>(b)];
    const mat3 rotation_old = bd.rotation;
    for (vec3* v : {&bd.displacement, &bd.velocity, &bd.angular_velocity, &bd.force, &bd.moment, &bd.reaction_force,
                    &bd.reaction_moment}) {
      *v = vec3(p[0], p[1], p[2]);
      p += 3;
    }
    bd.orientation.coeffs() = Eigen::Vector4d(p[0], p[1], p[2], p[3]);
    bd.half_orientation.coeffs() = Eigen::Vector4d(p[4], p[5], p[6], p[7]);
    p += 8;
    bd.rotation = bd.orientation.toRotationMatrix();
    if (slave_now.empty() || slave_now[static_cast<std::size_t>(b)] != 0)
      slave_gridpoints(b, rotation_old, gridpoints, dt);
    else
      rotation_before[static_cast<std::size_t>(b)] = rotation_old;
  }
  return static_cast<std::size_t>(p - in);
}

TESSERA_INLINE void rigid::slave_gridpoints(index_t b, const mat3& rotation_before, node_set& gridpoints, real dt) const noexcept {
  const body& bd = bodies_[static_cast<std::size_t>(b)];
  std::array<index_t, 3> count{0, 0, 0};
  for (index_t i = bd.first; i < bd.end; ++i)
    for (int c = 0; c < 3; ++c)
      count[static_cast<std::size_t>(c)] += gridpoints.constraint(i, c) == static_cast<std::uint8_t>(dof_constraint::prescribed);
  detail::slave_rigid_gridpoints(gridpoints, body_position_, bd, rotation_before, bd.angular_velocity * dt, dt, count);
}

TESSERA_INLINE real rigid::kinetic_energy(const node_set& /*gridpoints*/) const {
  real e = 0;
  for (const body& bd : bodies_)
    e += 0.5 * (bd.mass * bd.velocity.squaredNorm() + bd.angular_velocity.dot(bd.inertia.cwiseProduct(bd.angular_velocity)));
  return e;
}

TESSERA_INLINE integrator::critical_step rigid::critical_time_step(const node_set& gridpoints, real amplification) const {
  require(amplification >= 1, "rigid blocks: stiffness amplification a = ", amplification, " must be >= 1");
  const integrator::critical_step free =
      detail::rigid_step_bound(bodies_, gridpoints, body_position_, amplification, true);
  return std::isfinite(free.dt) ? free
                                : detail::rigid_step_bound(bodies_, gridpoints, body_position_, amplification, false);
}

TESSERA_INLINE void rigid::record_step_bound(const node_set& gridpoints) {
  unbounded_.clear();
  // every block counts when no free block has a stiffness
  if (!std::isfinite(detail::rigid_step_bound(bodies_, gridpoints, body_position_, 1, true).dt)) return;
  for (index_t b = 0; b < block_count(); ++b)
    if (fully_prescribed(gridpoints, b)) unbounded_.push_back(b);
}

TESSERA_INLINE void rigid::check_step_bound(const node_set& gridpoints) const {
  for (index_t b : unbounded_)
    if (!fully_prescribed(gridpoints, b)) detail::throw_rigid_unbounded(gridpoints, b, at(b));
}

TESSERA_INLINE integrator::mass_scaling_report rigid::scale_masses(node_set& gridpoints, real target_dt, real safety,
                                             real amplification) {
  require_positive(target_dt, "rigid blocks: mass-scaling target time step (s)");
  require(safety > 0 && safety <= 1, "rigid blocks: mass-scaling safety factor = ", safety, " must lie in (0, 1]");
  require(amplification >= 1, "rigid blocks: stiffness amplification a = ", amplification, " must be >= 1");
  const integrator::mass_scaling_report rep =
      detail::scale_rigid_masses(bodies_, gridpoints, body_position_, target_dt, safety, amplification);
  share_masses(gridpoints);
  return rep;
}

TESSERA_INLINE void rigid::set_gravity(const vec3& g) {
  require(g.allFinite(), "rigid blocks: gravity (", g.transpose(), ") m/s^2 is not finite");
  gravity_ = g;
}

TESSERA_INLINE void rigid::set_velocity(index_t b, const vec3& v, const vec3& omega, node_set& gridpoints) {
  require(b >= 0 && b < block_count(), "rigid blocks: block ", b, " does not exist (", block_count(), " blocks)");
  require(v.allFinite() && omega.allFinite(), "rigid blocks: velocity (", v.transpose(), ") m/s or angular velocity (",
          omega.transpose(), ") rad/s of block ", b, " is not finite");
  body& bd = bodies_[static_cast<std::size_t>(b)];
  bd.velocity = v;
  bd.angular_velocity = bd.rotation.transpose() * omega;
  for (index_t i = bd.first; i < bd.end; ++i)
    gridpoints.velocity.row(i) = (v + omega.cross(bd.rotation * body_position(i))).transpose();
}

TESSERA_INLINE mat3 rigid::inertia(index_t b) const {
  const body& bd = at(b);
  return bd.rotation * bd.inertia.asDiagonal() * bd.rotation.transpose();
}

TESSERA_INLINE vec3 rigid::angular_velocity(index_t b) const {
  return at(b).half_orientation.toRotationMatrix() * at(b).angular_velocity;
}

TESSERA_INLINE vec3 rigid::angular_momentum(index_t b) const {
  return at(b).half_orientation.toRotationMatrix() * at(b).inertia.cwiseProduct(at(b).angular_velocity);
}

TESSERA_INLINE void rigid::share_masses(node_set& gridpoints) const {
  for (const body& bd : bodies_)
    for (index_t i = bd.first; i < bd.end; ++i) gridpoints.mass[i] = bd.mass / static_cast<real>(bd.end - bd.first);
}

}  // namespace tessera::blocks
