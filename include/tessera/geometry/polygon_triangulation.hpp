#pragma once
// Triangulation of one face polygon that maximises the smallest triangle angle, identical for a
// face and its reversed twin. Used by the zoning (geometry/zoning.hpp: every face triangle is
// coned to the block centroid, so a thin face triangle makes a sliver zone) and by the
// regularization (geometry/regularize.hpp) to check that a collapse leaves every face
// triangulable.
//
// Method: dynamic programming over the diagonals of the polygon q_0 .. q_{n-1} (the classic
// optimal-polygon-triangulation recursion, O(n^3) time, O(n^2) memory):
//     S(i, i+1) = +inf,
//     S(i, j)   = max_{i<k<j} min( S(i, k), S(k, j), a(i, k, j) ),
// where a(i, k, j) is the smallest corner angle of triangle (q_i, q_k, q_j), or -1 if the
// triangle's normal does not agree with the polygon's Newell normal (dot product <= 0: a
// diagonal outside a slightly non-convex polygon, or a flipped triangle of a warped one). S(0, n-1)
// is the best smallest angle; a triangulation whose triangles all agree with the normal
// covers a simple polygon without overlap (a locally orientation-preserving map of the disk with
// a simple boundary is one-to-one). Ties are broken by the smallest k, so the result is a
// deterministic function of the canonical sequence below.
//
// Twin invariance: the polygon is first put in canonical order, which depends only on the SET of
// global ids and their cyclic adjacency, not on the loop direction: start at the smallest global
// id and go towards the smaller of its two loop neighbours. A face and its reversed twin
// therefore run the recursion on the same sequence with the same floating-point operations and
// get the same triangles; only their orientation is flipped back to each loop's own.
//
// Faces need not be planar (a regularized tessellation has slightly warped faces): angles and
// normals are those of the 3D triangles. If no triangulation has all triangles agreeing with the
// Newell normal (a badly folded face), the fan from the canonical start vertex is returned with
// a non-positive score, and the caller decides.
//
// Cost: O(n^3) for an n-gon (n ~ 5-6 for random Voronoi faces); allocates its O(n^2) table in a
// caller-owned workspace. Thread safety: pure, given a workspace per thread.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "../core/separate_compilation.hpp"
#include "../core/types.hpp"

namespace tessera::geometry {

/// Smallest corner angle (rad) of triangle (a, b, c); 0 for a degenerate triangle. It is the
/// angle opposite the shortest side (law of sines), atan2(|u x v|, u . v) of the two other sides.
[[nodiscard]] inline real min_corner_angle(const vec3& a, const vec3& b, const vec3& c) {
  const vec3 ab = b - a, bc = c - b, ca = a - c;
  const real lab = ab.squaredNorm(), lbc = bc.squaredNorm(), lca = ca.squaredNorm();
  const real twice_area = ab.cross(ca).norm();
  if (lab <= lbc && lab <= lca) return std::atan2(twice_area, -bc.dot(ca));  // at c
  if (lbc <= lca) return std::atan2(twice_area, -ca.dot(ab));                // at a
  return std::atan2(twice_area, -ab.dot(bc));                                // at b
}

/// Scratch memory of min_angle_triangulation (reuse it across faces to avoid reallocation).
struct triangulation_workspace {
  std::vector<index_t> sequence;  ///< canonical vertex order
  std::vector<vec3> points;     ///< their positions
  std::vector<real> score;      ///< S(i, j), row-major n x n
  std::vector<int> split;       ///< argmax k of S(i, j)
  std::vector<std::array<int, 2>> stack;  ///< scratch of the ear clipping
};

/// Triangulates face `loop` (global ids into `vertices`, counter-clockwise seen from outside)
/// maximising the smallest angle (see the file comment), appending n - 2 triangles of global ids,
/// each oriented like `loop`, to `out`. Returns the smallest angle (rad) of the result, or a
/// value <= 0 if no triangulation agrees with the Newell normal (the fan was returned).
/// Requires n >= 3 distinct ids.
TESSERA_INLINE real min_angle_triangulation(std::span<const vec3> vertices, std::span<const index_t> loop,
                                            std::vector<std::array<index_t, 3>>& out, triangulation_workspace& ws);

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/polygon_triangulation.ipp"
#endif
