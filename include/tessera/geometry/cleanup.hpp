#pragma once
// Cleanup of degenerate geometry: turns independently computed convex cells into one conforming
// tessellation (geometry/tessellation.hpp).
//
// Policy (all lengths relative to the mean cell size L = (V_box / N)^(1/3); the relative
// threshold is tessellation_options::cleanup_tolerance, default 1e-9, so tol = 1e-9 L):
//  1. Weld. Every cell vertex is a point; two points closer than tol in the max-norm are the
//     same vertex, and so are two points defined by the same four generators (vertex_key: the
//     cell and its three incident face tags) even if rounding put them farther apart (up to
//     1e4 tol: nearly coincident generators make ill-conditioned intersections in their
//     neighbours). Welding is transitive (connected components, built with a uniform bin grid,
//     a sort of the keys and union-find). The welded vertex takes the position of its
//     best-conditioned member (largest |det| of the three incident unit face normals), ties
//     broken by cell order, so the result does not depend on the thread count. A welded vertex
//     whose members are farther apart than tol (joined by their key: every computation was
//     ill-conditioned; or by a chain of points closer than tol: true vertices closer than tol
//     collapsed into one) is instead recomputed from its generators, the least-squares point of
//     all their pairwise power planes (recompute_ill_conditioned_vertices). Vertices within
//     tol of a domain side are then snapped exactly onto it.
//  2. Edges shorter than tol have now become repeated consecutive ids in a face loop: the
//     repeats are removed (edge collapse). Spikes a-b-a left by a collapsed sliver are removed
//     too.
//  3. Faces left with fewer than 3 distinct vertices (area of order tol^2 or a sliver thinner
//     than tol) are removed; a cell left with fewer than 4 faces (an empty Laguerre cell or a
//     cell thinner than tol) is removed and the cells are renumbered.
//  4. Faces are paired with their twins: face f of cell c tagged with neighbour n pairs with the
//     face of n tagged c; the two loops must be the same vertex ids in reverse order. A face
//     without such a twin is an error (geometry_error), never silently dropped.
// Why it is safe: the clipping kernel decides plane sides with a tolerance 1e-12 of the cell
// extent (predicates.hpp), so every feature created by a tolerance decision is three orders of
// magnitude shorter than tol and disappears in steps 1-3; features longer than tol are computed
// the same way from both sides and survive in both cells.
//
// Cost: O(total number of cell vertices) time and memory. Thread safety: pure functions.
//
// Where each step lives: welding and the recomputation of ill-conditioned vertices in
// vertex_weld.hpp (the least-squares power centre in power_centre.hpp), the loops' edge
// collapse and the twin pairing in loop_cleanup.hpp; this header gathers the cells' vertices
// with their weld keys and assembles the tessellation.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "convex_polyhedron.hpp"
#include "loop_cleanup.hpp"
#include "power_centre.hpp"
#include "tessellation.hpp"
#include "vertex_weld.hpp"

namespace tessera::geometry {

/// The vertices of every cell copied to `points` (cell c from point_offset[c]) with their weld
/// keys (the sorted tags of the three faces of a degree-3 vertex and the cell, else no_vertex_key)
/// and the conditioning |n0 . (n1 x n2)| of their first three faces. Parallel over cells.
TESSERA_INLINE void vertex_keys_of(std::span<const convex_polyhedron> cells, const std::vector<std::size_t>& point_offset,
                                   std::vector<vec3>& points, std::vector<vertex_key>& keys, std::vector<real>& conditioning);

/// Assembles a conforming tessellation from independently computed cells (cells[c] is the cell
/// of generator c, faces tagged with the neighbouring generator or boundary_tag), following the
/// cleanup policy above with absolute weld tolerance `tol` (m). `seeds` and `weights` (may be
/// empty) are stored per surviving cell. Throws geometry_error for a face without a twin.
[[nodiscard]] TESSERA_INLINE tessellation assemble_tessellation(const aabb& domain, std::span<const convex_polyhedron> cells,
                                                                std::span<const vec3> seeds, std::span<const real> weights,
                                                                real tol);

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/cleanup.ipp"
#endif
