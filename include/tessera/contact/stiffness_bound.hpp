#pragma once
// Gershgorin row bound of a sub-contact spring, for the stable time step of any contact set: the
// pair (node_a, node_b) is coupled by [K -K; -K K] with K = area (k_s I + (k_n - k_s) n n^T), whose
// absolute row sum is at most 2 area stiffness_row_bound_per_area(params) for every orientation n.

#include <cmath>
#include <numbers>

#include "../core/types.hpp"
#include "../law/concepts.hpp"

namespace tessera::contact {

/// max over unit normals n of the absolute row sum of (k_s I + (k_n - k_s) n n^T), per unit
/// area (Pa/m). Row i: |k_s + (k_n - k_s) n_i^2| + sum_{j != i} |k_n - k_s| |n_i n_j|
/// <= k_s + |k_n - k_s| |n_i| ||n||_1, and max over unit n of |n_i| ||n||_1 = (1 + sqrt 3) / 2
/// (n_i = cos a, the other two sin a / sqrt 2: cos^2 a + sqrt 2 sin a cos a peaks at
/// 1/2 + sqrt(3)/2). The bound is attained, and holds for every orientation the contact may
/// rotate to, so a rotation never invalidates the time step computed from it.
template <law::ContactLaw Law>
[[nodiscard]] real stiffness_row_bound_per_area(const typename Law::params& p) {
  const real k_n = Law::normal_stiffness(p);
  const real k_s = Law::shear_stiffness(p);
  return k_s + std::abs(k_n - k_s) * (1.0 + std::numbers::sqrt3) / 2.0;
}

}  // namespace tessera::contact
