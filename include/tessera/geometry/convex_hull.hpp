#pragma once
// Convex hull of a point set as planar convex face loops: the kernel of
// convex_polyhedron::from_vertices and geometry::convex_hull (convex_polyhedron.hpp).
//
// Algorithm: incremental (Clarkson-Shor without the conflict graph), O(n^2) for n points,
// meant for blocks of tens to a few thousand vertices. Start from the tetrahedron of four
// extreme points; add the other points in input order; a point sees a hull triangle when it is
// outside its plane by more than the plane tolerance; the visible triangles are replaced by a
// fan from the point to the horizon (the edges between visible and hidden triangles). When all
// points are in, adjacent triangles each of whose opposite vertex lies on the other's plane are
// merged into one face, and face-loop vertices on the straight line of their two neighbours
// (a point in the middle of a hull edge) are dropped, so every loop is a strictly convex polygon
// and every vertex an extreme point.
//
// Tolerance policy: the plane-side decisions use classify() of predicates.hpp with the tolerance
// the clipping kernel uses, tol = plane_tolerance_rel x (largest bounding-box extent), raised to
// plane_rounding_tolerance of the largest coordinate. A point within tol of the hull is inside
// (it is dropped); points within tol of each other are refused as duplicates, all points within
// tol of one line or plane are refused as collinear or coplanar.
//
// Orientation: loops are counter-clockwise seen from outside (outward normal by the right-hand
// rule), as in convex_polyhedron::box and from_faces.
// Thread safety: pure function. Cost: O(n F) plane tests and O(F log F) for the edge map.

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <span>
#include <utility>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "predicates.hpp"

namespace tessera::geometry::detail {

/// Vertices (the extreme points, in input order) and outward CCW face loops (CSR) of a hull.
struct hull_loops {
  std::vector<vec3> vertices;
  std::vector<index_t> face_offsets{0};
  std::vector<index_t> face_vertices;
  std::vector<index_t> input_index;  ///< input point id of each vertex
};

/// Convex hull of `points` (m). `who` prefixes the messages. Throws invalid_input for fewer than
/// 4 points, a non-finite point, two points within the tolerance of each other, or all points
/// within it of one line or plane; throws geometry_error when the tolerance decisions turn out
/// inconsistent (a horizon that is not one loop, a face that is not one loop).
[[nodiscard]] TESSERA_INLINE hull_loops compute_hull_loops(std::span<const vec3> points, const char* who);

}  // namespace tessera::geometry::detail

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/convex_hull.ipp"
#endif
