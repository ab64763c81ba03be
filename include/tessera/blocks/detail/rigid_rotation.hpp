#pragma once
// Rotation helpers of blocks::rigid: the exponential map of a rotation vector as a unit
// quaternion, and the coefficient functions of Rodrigues' formula, accurate for small angles.

#include <cmath>

#include <Eigen/Geometry>

#include "../../core/types.hpp"

namespace tessera::blocks::detail {

/// sin(x) / x, by its Taylor series below |x| = 1e-4 (relative error < 1e-20 there).
[[nodiscard]] inline real sinc(real x) noexcept {
  const real x2 = x * x;
  return std::abs(x) < 1e-4 ? 1 - x2 / 6 * (1 - x2 / 20) : std::sin(x) / x;
}

/// Unit quaternion of the rotation by angle |phi| about phi / |phi| (phi in rad):
/// exp(phi / 2) = (cos(|phi|/2), sin(|phi|/2) phi / |phi|). Exact for any angle; identity for phi = 0.
[[nodiscard]] inline Eigen::Quaterniond rotation_vector_quaternion(const vec3& phi) noexcept {
  const real half = 0.5 * phi.norm();
  const vec3 xyz = 0.5 * sinc(half) * phi;
  return Eigen::Quaterniond(std::cos(half), xyz.x(), xyz.y(), xyz.z());
}

/// (exp([phi]x) - 1) r for a rotation vector phi (rad), by Rodrigues' formula with the
/// coefficients sin t / t and (1 - cos t) / t^2 = sinc(t/2)^2 / 2 (t = |phi|), so the increment of
/// a rotated vector is computed without cancellation against r for small angles.
[[nodiscard]] inline vec3 rotation_increment(const vec3& phi, const vec3& r) noexcept {
  const real t = phi.norm();
  const real s = sinc(0.5 * t);
  const vec3 phi_x_r = phi.cross(r);
  return sinc(t) * phi_x_r + (0.5 * s * s) * phi.cross(phi_x_r);
}

}  // namespace tessera::blocks::detail
