// The definitions of the larger functions that contact/detection/contact_patch.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../contact_patch.hpp"
#include "../../detail/convex_polygon2.hpp"

namespace tessera::contact::detection {
namespace detail {

/// Parameter t where the line x + t n leaves a convex polyhedron with outward face planes
/// `faces`: the least bound of the faces facing along n; +inf if none does.
[[nodiscard]] inline real exit_along(std::span<const geometry::plane> faces, const vec3& x, const vec3& n) {
  real t = std::numeric_limits<real>::infinity();
  for (const geometry::plane& f : faces) {
    const real c = f.normal.dot(n);
    if (c > 1e-12) t = std::min(t, (f.offset - f.normal.dot(x)) / c);
  }
  return t;
}

/// Index of the point nearest to q (the first of equals).
[[nodiscard]] inline std::size_t nearest_point(const point2& q, const std::vector<point2>& points) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < points.size(); ++i)
    if ((points[i] - q).squaredNorm() < (points[best] - q).squaredNorm()) best = i;
  return best;
}
/// Vertex id of the touching point equal to hull corner h (hull2 keeps input points as they are).
[[nodiscard]] inline index_t hull_vertex(const point2& h, const std::vector<point2>& points, const std::vector<index_t>& ids) {
  return ids[nearest_point(h, points)];
}

/// corner_label of patch corner q: the nearest touching vertex of A, else of B, when q lies on it
/// (within 1e-6 of the hull's size); else the crossing of the nearest hull edges of A and B.
[[nodiscard]] TESSERA_INLINE std::uint64_t label_corner(const point2& q, const std::vector<point2>& pa, const std::vector<index_t>& ids_a,
                                                        const std::vector<point2>& hull_a, const std::vector<point2>& pb,
                                                        const std::vector<index_t>& ids_b, const std::vector<point2>& hull_b) {
  real size = 0;
  for (const point2& h : hull_a) size = std::max(size, (h - hull_a.front()).norm());
  for (const point2& h : hull_b) size = std::max(size, (h - hull_b.front()).norm());
  const real on = 1e-6 * std::max(size, std::numeric_limits<real>::min());
  if (const std::size_t i = nearest_point(q, pa); (pa[i] - q).norm() <= on) return corner_label::vertex_a(ids_a[i]);
  if (const std::size_t i = nearest_point(q, pb); (pb[i] - q).norm() <= on) return corner_label::vertex_b(ids_b[i]);
  // The hull edge (i, i + 1) nearest to q; a 1- or 2-point hull is its own edge.
  const auto nearest_edge = [&](const std::vector<point2>& hull) {
    std::size_t best = 0;
    real best_d = std::numeric_limits<real>::infinity();
    const std::size_t edges = hull.size() >= 3 ? hull.size() : 1;
    for (std::size_t i = 0; i < edges; ++i) {
      const point2& p = hull[i];
      const point2 d = hull[(i + 1) % hull.size()] - p;
      const real t = d.squaredNorm() > 0 ? std::clamp((q - p).dot(d) / d.squaredNorm(), real(0), real(1)) : real(0);
      if (const real dist = (p + t * d - q).squaredNorm(); dist < best_d) {
        best_d = dist;
        best = i;
      }
    }
    return std::pair{hull[best], hull[(best + 1) % hull.size()]};
  };
  const auto [a0, a1] = nearest_edge(hull_a);
  const auto [b0, b1] = nearest_edge(hull_b);
  return corner_label::crossing(hull_vertex(a0, pa, ids_a), hull_vertex(a1, pa, ids_a), hull_vertex(b0, pb, ids_b),
                                hull_vertex(b1, pb, ids_b));
}

}  // namespace detail
}  // namespace tessera::contact::detection

namespace tessera::contact::detection {

[[nodiscard]] TESSERA_INLINE contact_patch contact_patch_of(const geometry::convex_polyhedron& a, const geometry::convex_polyhedron& b,
                                                            const contact_plane& plane, real tolerance,
                                                            std::span<const geometry::plane> faces_a,
                                                            std::span<const geometry::plane> faces_b) {
  require(std::isfinite(tolerance) && tolerance > 0, "detection: contact tolerance = ", tolerance,
          " m must be finite and > 0");
  require(faces_a.size() == static_cast<std::size_t>(a.face_count()) && faces_b.size() == static_cast<std::size_t>(b.face_count()),
          "detection: contact_patch_of given ", faces_a.size(), " and ", faces_b.size(), " face planes for polyhedra of ",
          a.face_count(), " and ", b.face_count(), " faces");
  const vec3 n = plane.normal;
  // Frame of the plane.
  const vec3 t1 = (std::abs(n.x()) < 0.9 ? vec3::UnitX() : vec3::UnitY()).cross(n).normalized();
  const vec3 t2 = n.cross(t1);
  const auto to2 = [&](const vec3& x) { return detail::point2(t1.dot(x), t2.dot(x)); };
  const real max_a = detail::support_max(a, n), min_b = detail::support_min(b, n);
  require(a.vertex_count() <= corner_label::max_vertices && b.vertex_count() <= corner_label::max_vertices,
          "detection: polyhedra of ", a.vertex_count(), " and ", b.vertex_count(), " vertices; at most ",
          corner_label::max_vertices, " are supported");
  std::vector<detail::point2> pa, pb;
  std::vector<index_t> ids_a, ids_b;  // vertex id of each touching point
  for (index_t v = 0; v < a.vertex_count(); ++v)
    if (n.dot(a.vertex(v)) >= max_a - tolerance) {
      pa.push_back(to2(a.vertex(v)));
      ids_a.push_back(v);
    }
  for (index_t v = 0; v < b.vertex_count(); ++v)
    if (n.dot(b.vertex(v)) <= min_b + tolerance) {
      pb.push_back(to2(b.vertex(v)));
      ids_b.push_back(v);
    }
  const real tol2 = 1e-9 * std::max(a.extent(), b.extent());
  const std::vector<detail::point2> hull_a = detail::hull2(pa, tol2), hull_b = detail::hull2(pb, tol2);
  const std::vector<detail::point2> patch = detail::intersect_hulls(hull_a, hull_b, tol2);

  contact_patch out;
  if (patch.empty()) return out;
  out.type = patch.size() == 1 ? patch_type::point : patch.size() == 2 ? patch_type::segment : patch_type::polygon;
  for (const detail::point2& q : patch) {
    const vec3 x = plane.offset * n + q.x() * t1 + q.y() * t2;
    // The line x + t n leaves A at t_a and enters B at t_b (B's entry along n is its exit along -n).
    const real t_a = detail::exit_along(faces_a, x, n);
    const real t_b = -detail::exit_along(faces_b, x, -n);
    out.points.push_back(x);
    out.gap.push_back(t_b - t_a);
    out.label.push_back(detail::label_corner(q, pa, ids_a, hull_a, pb, ids_b, hull_b));
  }
  out.area.assign(patch.size(), 0.0);
  if (out.type == patch_type::polygon) {
    // Fan from the mean of the corners: it lies inside a convex polygon however thin, so every
    // triangle has the polygon's orientation and every tributary area is >= 0. (The area
    // centroid divides by the area: for a sliver it lands far outside and splits a near-zero
    // area into huge areas of both signs.)
    detail::point2 c = detail::point2::Zero();
    for (const detail::point2& p : patch) c += p;
    c /= static_cast<real>(patch.size());
    real signed_total = 0;
    for (std::size_t i = 0; i < patch.size(); ++i) signed_total += detail::cross2(c, patch[i], patch[(i + 1) % patch.size()]);
    const real orientation = signed_total < 0 ? -1.0 : 1.0;
    for (std::size_t i = 0; i < patch.size(); ++i) {
      const std::size_t j = (i + 1) % patch.size();
      const real tri = std::max<real>(0, 0.5 * orientation * detail::cross2(c, patch[i], patch[j]));
      out.area[i] += 0.5 * tri;
      out.area[j] += 0.5 * tri;
      out.total_area += tri;
    }
  }
  return out;
}

}  // namespace tessera::contact::detection
