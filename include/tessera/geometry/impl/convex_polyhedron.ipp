// The definitions of the larger members that geometry/convex_polyhedron.hpp declares (their
// documentation is there): included at the end of that header, or compiled once into
// tessera::instances under TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp), so a
// scene's unit neither parses them nor instantiates the Eigen expressions they use.
#pragma once

#include "../convex_polyhedron.hpp"
#include "../convex_hull.hpp"
#include "../detail/polyhedron_clip.hpp"

namespace tessera::geometry {

TESSERA_INLINE convex_polyhedron convex_polyhedron::box(const vec3& lo, const vec3& hi) {
  require((hi.array() > lo.array()).all() && lo.allFinite() && hi.allFinite(),
          "convex_polyhedron::box: lo = (", lo.x(), ", ", lo.y(), ", ", lo.z(), "), hi = (", hi.x(), ", ",
          hi.y(), ", ", hi.z(), ") must be finite with hi > lo in every direction");
  convex_polyhedron p;
  p.assign_box(lo, hi);
  return p;
}

TESSERA_INLINE void convex_polyhedron::assign_box(const vec3& lo, const vec3& hi) {
  vertices_.clear();
  // vertex k has x = hi if bit 0, y = hi if bit 1, z = hi if bit 2
  for (int k = 0; k < 8; ++k)
    vertices_.emplace_back((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
  static constexpr std::array<std::array<index_t, 4>, 6> loops{{
      {0, 4, 6, 2},  // x-  (normal -x)
      {1, 3, 7, 5},  // x+
      {0, 1, 5, 4},  // y-
      {2, 6, 7, 3},  // y+
      {0, 2, 3, 1},  // z-
      {4, 5, 7, 6},  // z+
  }};
  face_offsets_.assign(1, 0);
  face_vertices_.clear();
  face_tags_.clear();
  for (int s = 0; s < 6; ++s) {
    face_vertices_.insert(face_vertices_.end(), loops[static_cast<std::size_t>(s)].begin(),
                          loops[static_cast<std::size_t>(s)].end());
    face_offsets_.push_back(static_cast<index_t>(face_vertices_.size()));
    face_tags_.push_back(boundary_tag(s));
  }
}

TESSERA_INLINE convex_polyhedron convex_polyhedron::from_faces(std::vector<vec3> vertices, std::vector<index_t> face_offsets,
                                                  std::vector<index_t> face_vertices, std::vector<index_t> face_tags) {
  require<geometry_error>(face_offsets.size() >= 2 && face_offsets.front() == 0 &&
                              face_offsets.back() == static_cast<index_t>(face_vertices.size()),
                          "convex_polyhedron::from_faces: face_offsets must start at 0 and end at the loop length ",
                          face_vertices.size());
  require<geometry_error>(face_tags.size() + 1 == face_offsets.size(), "convex_polyhedron::from_faces: ",
                          face_tags.size(), " face tags for ", face_offsets.size() - 1, " faces");
  for (index_t v : face_vertices)
    require<geometry_error>(v >= 0 && v < static_cast<index_t>(vertices.size()),
                            "convex_polyhedron::from_faces: vertex id ", v, " out of range [0, ", vertices.size(), ")");
  convex_polyhedron p;
  p.vertices_ = std::move(vertices);
  p.face_offsets_ = std::move(face_offsets);
  p.face_vertices_ = std::move(face_vertices);
  p.face_tags_ = std::move(face_tags);
  return p;
}

TESSERA_INLINE convex_polyhedron convex_polyhedron::from_vertices(std::span<const vec3> points) {
  detail::hull_loops h = detail::compute_hull_loops(points, "convex_polyhedron::from_vertices");
  std::vector<index_t> tags(h.face_offsets.size() - 1, boundary_tag(0));
  return from_faces(std::move(h.vertices), std::move(h.face_offsets), std::move(h.face_vertices), std::move(tags));
}

TESSERA_INLINE convex_polyhedron convex_polyhedron::transformed(const mat3& map, const vec3& translation) const {
  convex_polyhedron p;
  p.assign_transformed(*this, map, translation);
  return p;
}

TESSERA_INLINE void convex_polyhedron::assign_transformed(const convex_polyhedron& source, const mat3& map,
                                                          const vec3& translation) {
  require(map.allFinite() && map.determinant() > 0 && translation.allFinite(),
          "convex_polyhedron::transformed: the map must be finite with a positive determinant (it is ",
          map.determinant(), ")");
  if (this != &source) {
    vertices_.resize(source.vertices_.size());
    face_offsets_.assign(source.face_offsets_.begin(), source.face_offsets_.end());
    face_vertices_.assign(source.face_vertices_.begin(), source.face_vertices_.end());
    face_tags_.assign(source.face_tags_.begin(), source.face_tags_.end());
  }
  for (std::size_t v = 0; v < vertices_.size(); ++v) vertices_[v] = map * source.vertices_[v] + translation;
}

TESSERA_INLINE bool convex_polyhedron::clip(const plane& h, index_t tag, real tol) {
  if (empty()) return false;
  if (tol < 0) tol = plane_tolerance_rel * extent();
  real coordinate_max = std::abs(h.offset);
  for (const vec3& v : vertices_) coordinate_max = std::max(coordinate_max, v.cwiseAbs().maxCoeff());
  tol = std::max(tol, plane_rounding_tolerance(coordinate_max));
  const real narrowest = tol, widest = std::max(tol, max_widened_tolerance_rel * extent());
  for (const bool fallback : {false, true}) {
    for (tol = narrowest;; tol = std::min(100 * tol, widest)) {  // rounding broke the bitonic side pattern of a face: widen the "on" band
      const detail::clip_result r =
          detail::try_clip({vertices_, face_offsets_, face_vertices_, face_tags_}, h, tag, tol, fallback);
      if (r != detail::clip_result::inconsistent) return r == detail::clip_result::cut;
      if (tol >= widest) break;
    }
  }
  throw geometry_error(tessera::detail::concat("convex_polyhedron::clip: no consistent cut by plane n = (", h.normal.x(),
                                      ", ", h.normal.y(), ", ", h.normal.z(), "), offset = ", h.offset,
                                      " m (tag ", tag, ") on a polyhedron of ", vertex_count(),
                                      " vertices, even with the plane tolerance widened to ", tol, " m"));
}

}  // namespace tessera::geometry
