#pragma once
// Free functions over a tessellation (geometry/tessellation.hpp): mass properties of a cell,
// face geometry, extraction of a cell as a convex_polyhedron, and a validity check.
//
// All cell quantities use the welded global vertices and the fan triangulation of
// mass_properties.hpp (apex = smallest vertex id of the face), so the volumes of all cells sum
// to the volume of the box up to rounding, and a face and its twin give the same area and
// opposite normals.
//
// Cost: O(size of the cell or face). Thread safety: pure functions of a const tessellation.

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "convex_polyhedron.hpp"
#include "mass_properties.hpp"
#include "predicates.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

namespace detail {
/// Face offsets of cell c as a sub-range of the tessellation's CSR offsets (absolute positions).
[[nodiscard]] inline std::span<const index_t> cell_face_offsets(const tessellation& t, index_t c) {
  const auto begin = static_cast<std::size_t>(t.first_face(c));
  return std::span<const index_t>(t.face_offsets).subspan(begin, static_cast<std::size_t>(t.end_face(c)) - begin + 1);
}
}  // namespace detail

/// Volume (m^3) of cell c.
[[nodiscard]] inline real cell_volume(const tessellation& t, index_t c) {
  return polyhedron_volume(t.vertices, detail::cell_face_offsets(t, c), t.face_vertices);
}
/// Volume, centroid and second moment (unit density) of cell c.
[[nodiscard]] inline mass_properties cell_mass_properties(const tessellation& t, index_t c) {
  return polyhedron_mass_properties(t.vertices, detail::cell_face_offsets(t, c), t.face_vertices);
}
/// Centroid (m) of cell c.
[[nodiscard]] inline vec3 cell_centroid(const tessellation& t, index_t c) { return cell_mass_properties(t, c).centroid; }
/// Inertia tensor (kg m^2) of cell c about its centroid for a density in kg/m^3.
[[nodiscard]] inline mat3 cell_inertia(const tessellation& t, index_t c, real density) {
  return inertia_tensor(cell_mass_properties(t, c).second_moment, density);
}

/// Area (m^2) of face f.
[[nodiscard]] inline real face_area(const tessellation& t, index_t f) { return polygon_area_vector(t.vertices, t.face(f)).norm(); }
/// Unit normal of face f, outward from face_cell[f].
[[nodiscard]] inline vec3 face_normal(const tessellation& t, index_t f) {
  return polygon_area_vector(t.vertices, t.face(f)).normalized();
}
/// Area-weighted centroid (m) of face f.
[[nodiscard]] inline vec3 face_centroid(const tessellation& t, index_t f) { return polygon_centroid(t.vertices, t.face(f)); }

/// Cell c as a stand-alone convex_polyhedron (local vertex ids in order of first use; face tags
/// = face_neighbor). Allocates.
[[nodiscard]] TESSERA_INLINE convex_polyhedron cell_polyhedron(const tessellation& t, index_t c);

/// Validity measures of a tessellation (all should be zero / tiny for a good one).
struct tessellation_report {
  real volume_error_rel = 0;  ///< |sum of cell volumes - box volume| / box volume
  index_t unmatched_faces = 0;  ///< interior faces without a twin whose loop is the reversed loop
  index_t open_cells = 0;       ///< cells with Euler characteristic V - E + F != 2
  index_t nonconvex_cells = 0;  ///< cells with a vertex outside a face plane by more than 1e-9 of the cell extent
  real min_face_area = 0;     ///< smallest face area (m^2)
  real min_edge_length = 0;   ///< shortest face edge (m)
  /// Largest distance of a face vertex from its face's mean plane (Newell normal through the
  /// vertex mean) (m): 0 for planar faces; a regularized tessellation (regularize.hpp) has
  /// slightly warped faces.
  real max_face_warp = 0;
  /// Largest distance of a cell vertex outside one of its cell's face planes (m): 0 for convex
  /// cells (nonconvex_cells counts those above 1e-9 of the cell extent).
  real max_nonconvexity = 0;
};

/// Checks the invariants of a conforming tessellation. O(sum over cells of V x F).
[[nodiscard]] TESSERA_INLINE tessellation_report check(const tessellation& t);

/// A model of separate convex blocks (not a space-filling tessellation): cell c is blocks[c] with
/// its own vertices (nothing welded, no shared faces, every face a boundary face tagged
/// boundary_tag(0)), the domain their bounding box. For scenes whose blocks only meet through
/// detected contacts (contact::detected_contacts): a block on a base, a stack, a wall. Blocks may
/// touch or be apart; they must not overlap (not checked). Throws geometry_error for an empty list
/// or an empty polyhedron.
[[nodiscard]] TESSERA_INLINE tessellation separate_blocks(std::span<const convex_polyhedron> blocks);

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/tessellation_queries.ipp"
#endif
