// The definitions of the larger functions that contact/detection/contact_patch.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../contact_patch.hpp"
#include "../../detail/convex_polygon2.hpp"

namespace tessera::contact::detection {
namespace detail {

/// A face plane of a block that faces along the patch's normal: its plane and c = normal . n.
struct facing_plane {
  geometry::plane plane;
  real c;
};
/// The faces of `faces` facing along n (c = normal . n > 1e-12), in order, into `out`.
inline void facing_along(std::span<const geometry::plane> faces, const vec3& n, std::vector<facing_plane>& out) {
  out.clear();
  for (const geometry::plane& f : faces)
    if (const real c = f.normal.dot(n); c > 1e-12) out.push_back({f, c});
}
/// Parameter t where the line x + t n leaves a convex polyhedron whose faces facing along n are
/// `facing` (facing_along): the least bound of those faces; +inf if none faces along n.
[[nodiscard]] inline real exit_along(std::span<const facing_plane> facing, const vec3& x) {
  real t = std::numeric_limits<real>::infinity();
  for (const facing_plane& f : facing) t = std::min(t, (f.plane.offset - f.plane.normal.dot(x)) / f.c);
  return t;
}

/// Buffers of contact_patch_into, kept per thread between pairs (no allocation once grown).
struct patch_scratch {
  std::vector<point2> pa, pb, hull_a, hull_b, patch;
  std::vector<index_t> ids_a, ids_b;  // vertex id of each touching point
  std::vector<real> dots;  // n . x of each vertex of a block
  std::vector<facing_plane> facing_a, facing_b;
  polygon_scratch polygons;
};
/// This thread's patch_scratch.
[[nodiscard]] inline patch_scratch& thread_patch_scratch() {
  thread_local patch_scratch s;
  return s;
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

/// The distance within which a patch corner lies on a touching vertex: 1e-6 of the hulls' size
/// (the largest distance of a hull corner from the hull's first).
[[nodiscard]] inline real on_vertex_distance(const std::vector<point2>& hull_a, const std::vector<point2>& hull_b) {
  real size = 0;
  for (const point2& h : hull_a) size = std::max(size, (h - hull_a.front()).norm());
  for (const point2& h : hull_b) size = std::max(size, (h - hull_b.front()).norm());
  return 1e-6 * std::max(size, std::numeric_limits<real>::min());
}

/// corner_label of patch corner q: the nearest touching vertex of A, else of B, when q lies on it
/// (within `on`, on_vertex_distance); else the crossing of the nearest hull edges of A and B.
[[nodiscard]] TESSERA_INLINE std::uint64_t label_corner(const point2& q, real on, const std::vector<point2>& pa,
                                                        const std::vector<index_t>& ids_a, const std::vector<point2>& hull_a,
                                                        const std::vector<point2>& pb, const std::vector<index_t>& ids_b,
                                                        const std::vector<point2>& hull_b) {
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

TESSERA_INLINE void contact_patch_into(const geometry::convex_polyhedron& a, const geometry::convex_polyhedron& b,
                                       const contact_plane& plane, real tolerance, std::span<const geometry::plane> faces_a,
                                       std::span<const geometry::plane> faces_b, contact_patch& out) {
  require(std::isfinite(tolerance) && tolerance > 0, "detection: contact tolerance = ", tolerance,
          " m must be finite and > 0");
  require(faces_a.size() == static_cast<std::size_t>(a.face_count()) && faces_b.size() == static_cast<std::size_t>(b.face_count()),
          "detection: contact_patch_of given ", faces_a.size(), " and ", faces_b.size(), " face planes for polyhedra of ",
          a.face_count(), " and ", b.face_count(), " faces");
  require(a.vertex_count() <= corner_label::max_vertices && b.vertex_count() <= corner_label::max_vertices,
          "detection: polyhedra of ", a.vertex_count(), " and ", b.vertex_count(), " vertices; at most ",
          corner_label::max_vertices, " are supported");
  out.clear();
  detail::patch_scratch& s = detail::thread_patch_scratch();
  const vec3 n = plane.normal;
  // Frame of the plane.
  const vec3 t1 = (std::abs(n.x()) < 0.9 ? vec3::UnitX() : vec3::UnitY()).cross(n).normalized();
  const vec3 t2 = n.cross(t1);
  const auto to2 = [&](const vec3& x) { return detail::point2(t1.dot(x), t2.dot(x)); };
  // The touching vertices of each block (n . x within the tolerance of its extreme: support_max,
  // support_min), each n . x computed once.
  const auto touching = [&](const geometry::convex_polyhedron& p, real sign, std::vector<detail::point2>& pts,
                            std::vector<index_t>& ids) {
    const std::vector<vec3>& x = p.vertices();
    s.dots.resize(x.size());
    const vec3 m = sign * n;  // (n, or -n as support_min reads it)
    real extreme = -std::numeric_limits<real>::infinity();
    for (std::size_t v = 0; v < x.size(); ++v) extreme = std::max(extreme, s.dots[v] = m.dot(x[v]));
    pts.clear();
    ids.clear();
    for (std::size_t v = 0; v < x.size(); ++v)
      if (s.dots[v] >= extreme - tolerance) {
        pts.push_back(to2(x[v]));
        ids.push_back(static_cast<index_t>(v));
      }
  };
  touching(a, 1, s.pa, s.ids_a);
  touching(b, -1, s.pb, s.ids_b);
  const real tol2 = 1e-9 * std::max(a.extent(), b.extent());
  detail::hull2_into(s.pa, tol2, s.polygons, s.hull_a);
  detail::hull2_into(s.pb, tol2, s.polygons, s.hull_b);
  detail::intersect_hulls_into(s.hull_a, s.hull_b, tol2, s.polygons, s.patch);
  const std::vector<detail::point2>& patch = s.patch;
  if (patch.empty()) return;
  out.type = patch.size() == 1 ? patch_type::point : patch.size() == 2 ? patch_type::segment : patch_type::polygon;
  detail::facing_along(faces_a, n, s.facing_a);
  detail::facing_along(faces_b, -n, s.facing_b);
  const real on = detail::on_vertex_distance(s.hull_a, s.hull_b);
  for (const detail::point2& q : patch) {
    const vec3 x = plane.offset * n + q.x() * t1 + q.y() * t2;
    // The line x + t n leaves A at t_a and enters B at t_b (B's entry along n is its exit along -n).
    const real t_a = detail::exit_along(s.facing_a, x);
    const real t_b = -detail::exit_along(s.facing_b, x);
    out.points.push_back(x);
    out.gap.push_back(t_b - t_a);
    out.label.push_back(detail::label_corner(q, on, s.pa, s.ids_a, s.hull_a, s.pb, s.ids_b, s.hull_b));
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
}

}  // namespace tessera::contact::detection
