#pragma once
// The record of one block of blocks::rigid (rigid.hpp's file comment defines the symbols), the
// prescriptions found on its gridpoints in a step, and the body coordinates of a gridpoint. Not a
// public interface.

#include <array>

#include <Eigen/Geometry>

#include "../../core/nodes.hpp"
#include "../../core/types.hpp"

namespace tessera::blocks::detail {

/// One block's mass, inertia and 6-DOF state (SI), read together: one record per block.
struct rigid_body {
  real mass = 0;                                     ///< m (kg, possibly scaled)
  real weight_mass = 0;                              ///< unscaled m (kg), for the weight
  vec3 inertia = vec3::Zero();                       ///< principal moments I1 <= I2 <= I3 (kg m^2, possibly scaled)
  mat3 axes = mat3::Identity();                      ///< E, principal axes in the reference configuration
  vec3 centroid = vec3::Zero();                      ///< reference centroid c (m)
  vec3 displacement = vec3::Zero();                  ///< u_c (m)
  vec3 velocity = vec3::Zero();                      ///< v (m/s), half step
  vec3 angular_velocity = vec3::Zero();              ///< w (rad/s), body frame, half step
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();       ///< q, full step
  Eigen::Quaterniond half_orientation = Eigen::Quaterniond::Identity();  ///< q exp(w dt / 4), mid-step
  mat3 rotation = mat3::Identity();                  ///< R(q)
  vec3 force = vec3::Zero(), moment = vec3::Zero();  ///< F (N), M (N m, world)
  vec3 reaction_force = vec3::Zero(), reaction_moment = vec3::Zero();
  index_t first = 0, end = 0;                          ///< gridpoints [first, end)
};

/// Prescriptions found on a block's gridpoints in the last reduction.
struct rigid_constraints {
  std::array<index_t, 3> count{0, 0, 0};               ///< gridpoints prescribing component c
  std::array<index_t, 3> first{invalid_index, invalid_index, invalid_index};     ///< the first of them
  std::array<index_t, 3> conflict{invalid_index, invalid_index, invalid_index};  ///< one disagreeing with it
  vec3 velocity = vec3::Zero();                      ///< prescribed velocity (m/s)
  [[nodiscard]] bool any() const { return count[0] + count[1] + count[2] > 0; }
};

/// Body coordinates r_i = E^T (X_i - c) of gridpoint i (m): row i of the N x 3 array.
[[nodiscard]] inline vec3 body_coordinates(const soa3& body_position, index_t i) {
  return body_position.row(i).transpose();
}

}  // namespace tessera::blocks::detail
