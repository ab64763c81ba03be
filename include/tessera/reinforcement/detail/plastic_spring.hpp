#pragma once
// Return mapping of a one-dimensional elastic-perfectly plastic spring, shared by the truss
// element's axial law (truss.hpp) and the bond law (bond.hpp).

#include <cmath>

#include "../../core/types.hpp"

namespace tessera::reinforcement::detail {

struct plastic_return {
  real force;              ///< N, |force| <= limit
  real plastic_increment;  ///< growth of the plastic displacement this update (m); 0 when elastic
  bool limited;            ///< the trial force exceeded the limit
};

/// Force of a spring of stiffness k (N/m) at total displacement `total` (m) with plastic part
/// `plastic` (m), limited to |F| <= limit (N): the trial k (total - plastic) is returned onto the
/// limit along its own sign, and the plastic part grows so that force = k (total - plastic_new).
[[nodiscard]] inline plastic_return elastic_perfectly_plastic(real total, real plastic, real k, real limit) noexcept {
  const real trial = k * (total - plastic);
  if (std::abs(trial) <= limit) return {trial, 0.0, false};
  const real force = std::copysign(limit, trial);
  return {force, total - force / k - plastic, true};
}

}  // namespace tessera::reinforcement::detail
