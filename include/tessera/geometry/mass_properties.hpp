#pragma once
// Mass properties of closed polyhedra and of planar polygons, as small free functions over
// plain arrays (libigl style), so convex_polyhedron, tessellation cells and blocks share one
// implementation.
//
// A polyhedron is given as
//   [in] vertices      positions (m), any number; only the referenced ones are used
//   [in] face_offsets  CSR offsets, size F + 1: face f is face_vertices[face_offsets[f] .. face_offsets[f+1])
//                      (absolute positions into face_vertices, so a sub-range of a tessellation's
//                      face_offsets selects the faces of one cell)
//   [in] face_vertices vertex ids, each loop counter-clockwise seen from outside (outward normal)
//
// Method: divergence theorem on a fan triangulation. Each face is split into triangles from its
// vertex of smallest id (the "consistent vertex": a face and its reversed twin get the same
// triangles, so the volumes of two cells sharing a slightly non-planar face add up exactly to
// the volume of their union). Each triangle (a, b, c), taken relative to a reference point r,
// spans the signed tetrahedron (r, a, b, c) with
//     6 V_t = a . (b x c)
//     int x dV    = V_t (a + b + c) / 4
//     int x x^T dV = V_t / 20 (a a^T + b b^T + c c^T + (a + b + c)(a + b + c)^T)
// (Tonon 2004, exact for polyhedra). Summing gives the exact volume, first and second moments
// of the polyhedron for any closed, consistently oriented surface, convex or not.
//
// Cost: O(total loop length), no allocation. Thread safety: pure functions.

#include <span>

#include <Eigen/Geometry>

#include "../core/separate_compilation.hpp"
#include "../core/types.hpp"

namespace tessera::geometry {

/// Volume, centroid and second moment of a homogeneous body of unit density.
struct mass_properties {
  real volume = 0;                          ///< V (m^3)
  vec3 centroid = vec3::Zero();             ///< c (m)
  mat3 second_moment = mat3::Zero();        ///< int (x - c)(x - c)^T dV about the centroid (m^5)
};

/// Inertia tensor about the centroid (kg m^2): I = rho (tr(S) 1 - S), S = second moment (m^5),
/// rho = density (kg/m^3).
[[nodiscard]] inline mat3 inertia_tensor(const mat3& second_moment, real density) {
  return density * (second_moment.trace() * mat3::Identity() - second_moment);
}

/// Position in `loop` of its vertex of smallest id: the apex of the face's fan triangulation.
[[nodiscard]] inline std::size_t fan_apex(std::span<const index_t> loop) {
  std::size_t k0 = 0;
  for (std::size_t k = 1; k < loop.size(); ++k)
    if (loop[k] < loop[k0]) k0 = k;
  return k0;
}

/// Area vector of a planar polygon loop (m^2): (1/2) sum over the fan triangles of (b - a) x (c - a);
/// its norm is the area and its direction the unit normal by the right-hand rule of the loop.
[[nodiscard]] inline vec3 polygon_area_vector(std::span<const vec3> vertices, std::span<const index_t> loop) {
  const std::size_t n = loop.size();
  if (n < 3) return vec3::Zero();
  const std::size_t k0 = fan_apex(loop);
  const vec3& a = vertices[static_cast<std::size_t>(loop[k0])];
  vec3 s = vec3::Zero();
  for (std::size_t t = 1; t + 1 < n; ++t) {
    const vec3& b = vertices[static_cast<std::size_t>(loop[(k0 + t) % n])];
    const vec3& c = vertices[static_cast<std::size_t>(loop[(k0 + t + 1) % n])];
    s += (b - a).cross(c - a);
  }
  return real(0.5) * s;
}

/// Area-weighted centroid of a polygon loop (m), from the same fan triangulation.
[[nodiscard]] TESSERA_INLINE vec3 polygon_centroid(std::span<const vec3> vertices, std::span<const index_t> loop);

namespace detail {
/// Reference point of the volume integrals: the first vertex of the first face. Coordinates
/// relative to it keep the moments free of cancellation against the absolute position.
[[nodiscard]] inline vec3 reference_point(std::span<const vec3> vertices, std::span<const index_t> face_offsets,
                                          std::span<const index_t> face_vertices) {
  return vertices[static_cast<std::size_t>(face_vertices[static_cast<std::size_t>(face_offsets[0])])];
}
/// Calls visit(a, b, c) for every triangle of every face, fan-triangulated from fan_apex, with
/// a, b, c relative to r: the tetrahedra (r, a, b, c) decompose the polyhedron with signed volumes
/// a.(b x c)/6. Faces with fewer than 3 vertices are skipped.
template <class Visit>
void for_each_fan_tetrahedron(std::span<const vec3> vertices, std::span<const index_t> face_offsets,
                              std::span<const index_t> face_vertices, const vec3& r, Visit&& visit) {
  for (std::size_t f = 0; f + 1 < face_offsets.size(); ++f) {
    const auto loop = face_vertices.subspan(static_cast<std::size_t>(face_offsets[f]),
                                            static_cast<std::size_t>(face_offsets[f + 1] - face_offsets[f]));
    const std::size_t n = loop.size();
    if (n < 3) continue;
    const std::size_t k0 = fan_apex(loop);
    const vec3 a = vertices[static_cast<std::size_t>(loop[k0])] - r;
    for (std::size_t t = 1; t + 1 < n; ++t) {
      const vec3 b = vertices[static_cast<std::size_t>(loop[(k0 + t) % n])] - r;
      const vec3 c = vertices[static_cast<std::size_t>(loop[(k0 + t + 1) % n])] - r;
      visit(a, b, c);
    }
  }
}
}  // namespace detail

/// Volume, centroid and second moment of a closed polyhedron with outward-oriented face loops
/// (see the file comment for the argument layout). Returns volume 0 and the vertex average as
/// centroid for an empty polyhedron.
[[nodiscard]] TESSERA_INLINE mass_properties polyhedron_mass_properties(std::span<const vec3> vertices,
                                                                        std::span<const index_t> face_offsets,
                                                                        std::span<const index_t> face_vertices);

/// Volume (m^3) of a closed polyhedron (same layout as polyhedron_mass_properties).
[[nodiscard]] inline real polyhedron_volume(std::span<const vec3> vertices, std::span<const index_t> face_offsets,
                                            std::span<const index_t> face_vertices) {
  if (face_offsets.size() < 2) return 0;
  const vec3 r = detail::reference_point(vertices, face_offsets, face_vertices);
  real six_v = 0;
  detail::for_each_fan_tetrahedron(vertices, face_offsets, face_vertices, r,
                                   [&](const vec3& a, const vec3& b, const vec3& c) { six_v += a.dot(b.cross(c)); });
  return six_v / 6;
}

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/mass_properties.ipp"
#endif
