#pragma once
// Host-zone embedding of bar nodes (study eq. 10). Each bar node is tied to the constant-strain
// tetrahedral zone that contains it; the host point moves with the zone's four gridpoints through
// the barycentric (volume) weights w_i = V_i / V_T:
//
//   u_host = sum_i w_i u_i                       (eq. 10, applied to total displacements)
//
// and a force f acting on the host point is returned to the gridpoints as w_i f, so the bond
// exchanges no net force (momentum is conserved exactly up to rounding). The weights are linear in
// the point, so they reproduce any linear displacement field exactly.
//
// Tolerance policy: a point belongs to a zone when its smallest weight is >= -tolerance
// (tolerance = 1e-9, dimensionless, i.e. relative to the zone's size). A point on a face, edge or
// vertex shared by several zones (within the same block or on a face shared by two blocks, whose
// gridpoints are distinct copies) gets exactly one host, chosen deterministically: the zone with
// the largest smallest weight (the one the point is most inside); zones whose smallest weight is
// within the tolerance of the best count as tied, and the lowest zone id among them wins.

#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <span>

#include "../core/types.hpp"
#include "detail/zone_grid.hpp"

namespace tessera::reinforcement {

/// Barycentric weights w_i = V_i / V_T (-) of point p in the tetrahedron (x0, x1, x2, x3), V_i being
/// the signed volume of the tetrahedron with corner i replaced by p. They are computed from the
/// corner vectors relative to p (no cancellation against absolute coordinates) and divided by their
/// sum, so they sum to 1 up to rounding whatever the orientation. All are in [0, 1] iff p is inside.
[[nodiscard]] inline std::array<real, 4> barycentric_weights(const vec3& x0, const vec3& x1, const vec3& x2,
                                                             const vec3& x3, const vec3& p) {
  const vec3 a0 = x0 - p, a1 = x1 - p, a2 = x2 - p, a3 = x3 - p;
  // 6 V_i as triple products of the corner vectors, corner i replaced by p (a_i -> 0).
  const std::array<real, 4> v{a1.dot(a2.cross(a3)), -a0.dot(a2.cross(a3)), a0.dot(a1.cross(a3)),
                              -a0.dot(a1.cross(a2))};
  const real total = v[0] + v[1] + v[2] + v[3];  // 6 V_T
  return {v[0] / total, v[1] / total, v[2] / total, v[3] / total};
}

/// Where a bar node sits in the block mesh: its host zone, the zone's 4 gridpoints and the weights.
struct host_point {
  index_t zone = invalid_index;                                            ///< host zone id
  std::array<index_t, 4> gridpoints{invalid_index, invalid_index, invalid_index, invalid_index};  ///< the host zone's gridpoints
  std::array<real, 4> weights{0.0, 0.0, 0.0, 0.0};                       ///< w_i = V_i / V_T, sum 1
};

/// Finds host zones of points among the tetrahedral zones of a mesh (uniform bucket grid, see
/// detail/zone_grid.hpp). Build O(zones); each query tests the few zones of one grid cell.
/// Read-only after construction, so concurrent locate() calls are safe.
class zone_locator {
 public:
  /// Dimensionless inside tolerance on the barycentric weights (see the header comment).
  static constexpr real tolerance = 1e-9;

  /// gridpoints: reference positions (m); zones: gridpoint ids (positive orientation not required).
  /// Both arrays are referenced, not copied: they must outlive the locator.
  zone_locator(std::span<const vec3> gridpoints, std::span<const std::array<index_t, 4>> zones)
      : gridpoints_(gridpoints), zones_(zones), grid_(gridpoints, zones, 4.0 * tolerance) {}

  /// The host of p by the rule in the header comment, or nullopt when p is outside every zone.
  [[nodiscard]] std::optional<host_point> locate(const vec3& p) const {
    const std::span<const index_t> candidates = grid_.candidates(p);
    real best = -tolerance;
    bool found = false;
    for (index_t z : candidates) {
      const real m = min_weight(weights_in(z, p));
      if (m >= best) { best = m; found = true; }
    }
    if (!found) return std::nullopt;
    for (index_t z : candidates) {  // ascending id: the first zone tied with the best wins
      const std::array<real, 4> w = weights_in(z, p);
      if (min_weight(w) >= best - tolerance) return host_point{z, zones_[static_cast<std::size_t>(z)], w};
    }
    return std::nullopt;  // unreachable: the best zone itself qualifies
  }

 private:
  [[nodiscard]] std::array<real, 4> weights_in(index_t z, const vec3& p) const {
    const auto& g = zones_[static_cast<std::size_t>(z)];
    auto x = [&](int i) -> const vec3& { return gridpoints_[static_cast<std::size_t>(g[static_cast<std::size_t>(i)])]; };
    return barycentric_weights(x(0), x(1), x(2), x(3), p);
  }
  [[nodiscard]] static real min_weight(const std::array<real, 4>& w) {
    real m = w[0];
    for (real wi : w) m = (wi < m || wi != wi) ? wi : m;  // NaN (degenerate zone) propagates: never inside
    return m;
  }

  std::span<const vec3> gridpoints_;
  std::span<const std::array<index_t, 4>> zones_;
  detail::zone_grid grid_;
};

}  // namespace tessera::reinforcement
