#pragma once
// Step 1 of the tessellation cleanup (cleanup.hpp states the whole policy): the cell vertices
// computed independently by each cell are welded into shared vertices, by distance (max-norm
// tol) and by their topological key, at the position of the best-conditioned member; a welded
// vertex whose members are farther apart than tol is then recomputed from its generators
// (power_centre.hpp).
//
// Cost: O(number of points) time and memory (uniform bin grid, a sort of the keys,
// union-find). Thread safety: pure functions.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/csr.hpp"
#include "../core/types.hpp"
#include "power_centre.hpp"

namespace tessera::geometry {

/// Result of weld_vertices: `vertices[global_id[k]]` is the welded position of point k.
struct welded_points {
  std::vector<vec3> vertices;  ///< the distinct points (m)
  std::vector<index_t> global_id;  ///< for each input point, its index in vertices
};

/// Topological identity of a cell vertex where exactly three faces meet: the sorted ids of the
/// four generators whose planes define it (the cell and its three face tags, boundary tags
/// included). Two cells see the same vertex under the same key however ill-conditioned its
/// position is (e.g. two generators 1e-9 apart make nearly parallel bisectors in their
/// neighbours). no_vertex_key marks vertices with more than three faces.
using vertex_key = std::array<index_t, 4>;
inline constexpr vertex_key no_vertex_key{invalid_index, invalid_index, invalid_index, invalid_index};

/// Welds `points` (m) into shared vertices: points closer than `tol` (m, max-norm), and points
/// with the same vertex key (when `keys` is not empty) that are closer than 1e4 tol, are the
/// same vertex (transitively). The welded position is that of the member with the largest
/// `conditioning` (when given; |det| of its three unit face normals, i.e. the best-conditioned
/// computation), ties and no conditioning resolved by the lowest point index. Coordinates within
/// tol of a side of `domain` are then snapped onto that side. Deterministic for fixed input.
[[nodiscard]] TESSERA_INLINE welded_points weld_vertices(std::span<const vec3> points, real tol, const aabb& domain,
                                                         std::span<const vertex_key> keys = {},
                                                         std::span<const real> conditioning = {});

/// Step 1 for ill-conditioned vertices. A welded vertex whose members are farther apart than
/// tol was joined by its vertex key (weld_vertices), i.e. every cell computed it from nearly
/// parallel planes: two generators 1e-9 L apart make nearly identical bisectors in each of
/// their neighbours; or by a chain of points each within tol of the next, i.e. several true
/// vertices closer than tol were collapsed into one (fuzz_tessellation: a generator 7.7e-8 m =
/// 1e-9 L from one of eight cospherical generators has a cell with eight vertices within 1.9e-7
/// m of the sphere centre; welded at one of them, the vertex moved 1.9e-7 m and its neighbours'
/// cells were 2.1e-9 of their extent non-convex). Its best-conditioned member can then still be 1e-7 L off the bisector of
/// the close pair (fuzz_tessellation, two such pairs sharing a vertex: every one of its four
/// computations had two nearly parallel planes), which tilts the faces through it by more than
/// the 1e-9 convexity tolerance of check(). Such a vertex is recomputed from what it is by
/// definition, the point of equal power distance to the generators of its keys (and on their box
/// sides), from all pairwise planes at once: the close pair's own bisector is well defined
/// (its normal is the exact difference of the two generators), so the system is well
/// conditioned although every single cell's three planes were not. Vertices whose members agree
/// within tol, i.e. every vertex of a tessellation without near-coincident generators, keep
/// the member's position bit for bit. The generators of every member's key are used, however
/// many: each pair of them has cells with points in the welded cluster, so their plane crosses
/// the segment between those points and passes within the cluster's diameter (9 generators and
/// 36 planes in the example above: the recomputed vertex is at most 6.5e-8 m = 0.84 tol off
/// any of them, the member it had before 1.3e-7 m, and the cells are non-convex by at most
/// 5.5e-10 of their extent instead of 2.1e-9).
TESSERA_INLINE void recompute_ill_conditioned_vertices(welded_points& welded, std::span<const vec3> points,
                                                       std::span<const vertex_key> keys, std::span<const vec3> seeds,
                                                       std::span<const real> weights, real tol, const aabb& domain);

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/vertex_weld.ipp"
#endif
