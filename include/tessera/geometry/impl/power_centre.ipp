// The definitions of the larger functions that geometry/power_centre.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../power_centre.hpp"

namespace tessera::geometry {
namespace detail {

[[nodiscard]] TESSERA_INLINE std::array<real, 2> extreme_singular_values_3x3(std::array<vec3, 3> w) {
  constexpr real eps = std::numeric_limits<real>::epsilon();
  for (int sweep = 0; sweep < 60; ++sweep) {
    bool rotated = false;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        const real alpha = w[p].squaredNorm(), beta = w[q].squaredNorm(), gamma = w[p].dot(w[q]);
        if (!(std::abs(gamma) > eps * std::sqrt(alpha * beta))) continue;  // orthogonal (or NaN)
        const real zeta = (beta - alpha) / (2 * gamma);
        const real t = std::copysign(real(1), zeta) / (std::abs(zeta) + std::sqrt(1 + zeta * zeta));
        const real c = 1 / std::sqrt(1 + t * t), s = c * t;
        const vec3 wp = w[p];
        w[p] = c * wp - s * w[q];
        w[q] = s * wp + c * w[q];
        rotated = true;
      }
    if (!rotated) break;
  }
  const real n0 = w[0].norm(), n1 = w[1].norm(), n2 = w[2].norm();
  if (!(std::isfinite(n0) && std::isfinite(n1) && std::isfinite(n2)))
    return {std::numeric_limits<real>::quiet_NaN(), std::numeric_limits<real>::quiet_NaN()};
  return {std::max({n0, n1, n2}), std::min({n0, n1, n2})};
}

}  // namespace detail
}  // namespace tessera::geometry

namespace tessera::geometry {

[[nodiscard]] TESSERA_INLINE bool power_centre(std::span<const index_t> ids, std::span<const vec3> seeds,
                                               std::span<const real> weights, const aabb& domain, vec3& x) {
  std::vector<std::array<real, 4>> rows;  // [n_x, n_y, n_z, offset]: n . x = offset
  auto add_row = [&](const vec3& n, real offset) { rows.push_back({n.x(), n.y(), n.z(), offset}); };
  auto weight = [&](index_t i) { return weights.empty() ? real(0) : weights[static_cast<std::size_t>(i)]; };
  for (std::size_t p = 0; p < ids.size(); ++p) {
    const index_t i = ids[p];
    if (i < 0) {
      const int side = boundary_side(i);
      add_row(vec3::Unit(side / 2), (side % 2) ? domain.hi[side / 2] : domain.lo[side / 2]);
      continue;
    }
    for (std::size_t q = p + 1; q < ids.size(); ++q) {
      const index_t j = ids[q];
      if (j < 0) continue;
      const plane h = power_plane(seeds[static_cast<std::size_t>(i)], weight(i), seeds[static_cast<std::size_t>(j)], weight(j));
      add_row(h.normal, h.offset);
    }
  }
  const std::size_t m = rows.size();
  if (m < 3) return false;
  // Householder QR of [A | b]: after column k, rows[k][k..3] is row k of [R | Q^T b].
  for (int k = 0; k < 3; ++k) {
    real norm2 = 0;
    for (std::size_t r = static_cast<std::size_t>(k); r < m; ++r) norm2 += rows[r][k] * rows[r][k];
    const real norm = std::sqrt(norm2);
    if (!(norm > 0)) return false;  // a zero (or NaN) column: no point
    const auto kk = static_cast<std::size_t>(k);
    const real alpha = rows[kk][k] > 0 ? -norm : norm;  // R_kk, of opposite sign: no cancellation
    const real v0 = rows[kk][k] - alpha;                // Householder vector v = (v0, rows[k+1..][k])
    const real v_norm2 = v0 * v0 + (norm2 - rows[kk][k] * rows[kk][k]);
    for (int j = k + 1; j < 4; ++j) {
      real dot = v0 * rows[kk][j];
      for (std::size_t r = kk + 1; r < m; ++r) dot += rows[r][k] * rows[r][j];
      const real f = 2 * dot / v_norm2;
      rows[kk][j] -= f * v0;
      for (std::size_t r = kk + 1; r < m; ++r) rows[r][j] -= f * rows[r][k];
    }
    rows[kk][k] = alpha;
    for (std::size_t r = kk + 1; r < m; ++r) rows[r][k] = 0;
  }
  // R has the singular values of A
  const std::array<vec3, 3> r_columns{vec3(rows[0][0], 0, 0), vec3(rows[0][1], rows[1][1], 0),
                                      vec3(rows[0][2], rows[1][2], rows[2][2])};
  const auto [sigma_max, sigma_min] = detail::extreme_singular_values_3x3(r_columns);
  if (!(sigma_min > 1e-9 * sigma_max)) return false;
  x[2] = rows[2][3] / rows[2][2];
  x[1] = (rows[1][3] - rows[1][2] * x[2]) / rows[1][1];
  x[0] = (rows[0][3] - rows[0][1] * x[1] - rows[0][2] * x[2]) / rows[0][0];
  return x.allFinite();
}

}  // namespace tessera::geometry
