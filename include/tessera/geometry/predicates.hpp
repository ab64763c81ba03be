#pragma once
// Geometric predicates: the one place where tessera decides on which side of a plane a point
// lies. Clipping, tessellation and containment tests all go through `classify`, so a point is
// never "inside" for one algorithm and "outside" for another.
//
// Tolerance policy (CGAL-style filter without the exact fallback):
//   A point p is ON a plane (n, offset) when |n.p - offset| <= tol, where tol is an absolute
//   length (m). Callers derive it from the size of the object they work on:
//       tol = plane_tolerance_rel * L,   L = characteristic length (bounding-box extent)
//   plane_tolerance_rel = 1e-12 sits three orders of magnitude above the rounding error of the
//   signed distance of double-precision coordinates of magnitude L (|error| <~ 4 eps L ~ 1e-15 L;
//   for coordinates much larger than the object, plane_rounding_tolerance is the floor) and three
//   orders below the vertex-welding tolerance of the tessellation cleanup (1e-9 of the cell
//   size, see cleanup.hpp). Everything a tolerance-level decision can create (sliver edges,
//   near-duplicate vertices, zero-area faces) is therefore much shorter than the welding
//   tolerance and is removed by the cleanup; nothing depends on luck.
//
// Thread safety: every function here is pure.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Geometry>

#include "../core/types.hpp"

namespace tessera::geometry {

/// Oriented plane {x : normal . x = offset}; `normal` is a unit vector (dimensionless) pointing
/// to the outside (the half-space n.x > offset is "outside"), `offset` in m.
struct plane {
  vec3 normal = vec3::UnitZ();  ///< unit normal
  real offset = 0;  ///< n.x on the plane (m)

  /// Signed distance n.p - offset (m), positive outside.
  [[nodiscard]] real signed_distance(const vec3& p) const { return normal.dot(p) - offset; }
  /// The same plane with the opposite outside.
  [[nodiscard]] plane flipped() const { return {-normal, -offset}; }
  /// Plane through `point` with unit outward normal `n`.
  [[nodiscard]] static plane through(const vec3& n, const vec3& point) { return {n, n.dot(point)}; }
};

/// Relative tolerance of the plane-side predicate; multiply by a characteristic length (m).
inline constexpr real plane_tolerance_rel = 1e-12;

/// Floor (m) of any plane-side tolerance for points with coordinates up to `coordinate_max` (m)
/// in absolute value. The rounding error of n.p - offset is about 4 eps |p|, not 4 eps L: an
/// object of size L far from the origin (|p| >~ 1e3 L, where plane_tolerance_rel L drops below
/// it) would otherwise have its vertex sides decided by rounding, which creates duplicate and
/// sub-tolerance vertices. 16 eps |p| keeps the "on" band above the error.
[[nodiscard]] inline real plane_rounding_tolerance(real coordinate_max) {
  return 16 * std::numeric_limits<real>::epsilon() * coordinate_max;
}

/// Result of a three-valued side test.
enum class side : std::int8_t {
  inside = -1,  ///< n.p - offset < -tol (kept by a clip)
  on = 0,       ///< |n.p - offset| <= tol
  outside = 1,  ///< n.p - offset > tol (removed by a clip)
};

/// Three-valued side of a signed distance d (m) for an absolute tolerance tol (m).
[[nodiscard]] inline side classify_distance(real d, real tol) {
  return d > tol ? side::outside : (d < -tol ? side::inside : side::on);
}
/// Side of point p relative to plane h with absolute tolerance tol (m).
[[nodiscard]] inline side classify(const plane& h, const vec3& p, real tol) {
  return classify_distance(h.signed_distance(p), tol);
}

/// Orientation of the tetrahedron (a, b, c, d): sign of (b-a) x (c-a) . (d-a) = 6 V.
/// Returns side::outside (> 0: d above the CCW triangle abc), side::inside (< 0) or side::on when
/// |6V| <= tol_rel * L^3 with L the longest of the three edge vectors from a.
[[nodiscard]] inline side orientation(const vec3& a, const vec3& b, const vec3& c, const vec3& d,
                                      real tol_rel = plane_tolerance_rel) {
  const vec3 u = b - a, v = c - a, w = d - a;
  const real six_v = u.cross(v).dot(w);
  const real l = std::max({u.norm(), v.norm(), w.norm()});
  return classify_distance(six_v, tol_rel * l * l * l);
}

/// Bisector plane of the power (Laguerre) diagram between generator i (position s_i, weight
/// w_i, m^2) and generator j: points x with |x - s_i|^2 - w_i = |x - s_j|^2 - w_j. The outside
/// is the side of j. With d = |s_j - s_i| and n = (s_j - s_i)/d:
///     n.x = n.(s_i + s_j)/2 + (w_i - w_j) / (2 d).
/// The expression is antisymmetric bit for bit: power_plane(j, i) == power_plane(i, j).flipped(),
/// so the two cells sharing the face cut with exactly the same plane. Weights 0 give the
/// Voronoi bisector. Requires s_i != s_j.
[[nodiscard]] inline plane power_plane(const vec3& s_i, real w_i, const vec3& s_j, real w_j) {
  const vec3 delta = s_j - s_i;
  const real d = delta.norm();
  const vec3 n = delta / d;
  const vec3 mid = real(0.5) * (s_i + s_j);
  return {n, n.dot(mid) + (w_i - w_j) / (2 * d)};
}

}  // namespace tessera::geometry
