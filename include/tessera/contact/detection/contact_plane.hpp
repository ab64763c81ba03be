#pragma once
// The contact plane of two convex polyhedra (DESIGN.md section 4), the first half of the narrow
// phase of contact detection; the contact patch on it is contact_patch.hpp.
//
// Contact plane (common_plane). The plane is the one of largest separation over the separating-
// axis candidates of two convex polyhedra: the face normals of A, the reversed face normals of B
// and the cross products of one edge of each. For an axis n (unit, from A to B) the gap is
//     g(n) = min_{x in B} n.x - max_{x in A} n.x        (m; > 0 apart, < 0 overlapping)
// and the plane lies halfway, n.x = (max_A + min_B) / 2: 3DEC's common plane (Cundall 1988: the
// plane maximising the smaller of the two blocks' vertex distances to it) over a finite candidate
// set, as in Nezami et al.'s fast common plane. The candidates are the face normals of the
// Minkowski difference B - A, for which the separating axis theorem gives two guarantees:
//   - the sign of g is exact: g > 0 iff the blocks are disjoint;
//   - for overlapping blocks, -g is the penetration depth and n its direction (exact).
// For disjoint blocks g is a lower bound of their distance (equal to it when the closest features
// are a face and a vertex, edge or face, or two crossing edges; smaller when two vertices or a
// vertex and an edge are closest, e.g. two cubes corner to corner), so a pair is taken as
// touching slightly early, never late; the per-point gaps of the patch are exact.
// Edge pairs are pruned to those whose arcs on the Gauss map cross (the edge pairs that form a
// face of the Minkowski difference; Gregorius, GDC 2013), which leaves O(E) of the O(E^2) pairs
// and keeps both guarantees (test_contacts "[detection]" checks them against the unpruned search
// on 2000 random pairs). Ties within plane_tie_rel x size prefer a face of A, then of B, then an
// edge pair, so face-face contacts are classified as such under rounding.
//
// Cost: common_plane O(F_A V_B + F_B V_A + (E_A + E_B) log + K (V_A + V_B)), K the retained edge
// pairs; it allocates only in scratch vectors reused by the calling thread. A pure function of
// its inputs: deterministic, thread-safe.

#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>
#include <tuple>
#include <vector>

#include "../../core/separate_compilation.hpp"
#include "../../core/errors.hpp"
#include "../../core/types.hpp"
#include "../../geometry/convex_polyhedron.hpp"

namespace tessera::contact::detection {

/// Relative size of a tie between two candidate axes' gaps (x the pair's size).
inline constexpr real plane_tie_rel = 1e-9;

/// Where the contact plane's normal came from.
enum class plane_source : std::uint8_t { face_a, face_b, edge_edge };

/// The contact plane of a pair: normal (unit, from A to B), offset (n.x = offset on the plane)
/// and the gap g (m) of the best axis.
struct contact_plane {
  vec3 normal = vec3::UnitZ();  ///< unit normal, A to B
  real offset = 0;  ///< n.x on the plane (m)
  real gap = 0;  ///< gap along the normal (m; < 0 overlapping)
  plane_source source = plane_source::face_a;  ///< where the normal came from
  index_t feature_a = invalid_index;  ///< face of A (face_a), or edge of A (edge_edge)
  index_t feature_b = invalid_index;  ///< face of B (face_b), or edge of B (edge_edge)
};

/// The axis of a pair's last contact plane, which a later pass tries first (separating_axis_hint):
/// where it came from and its features (contact_plane's source, feature_a, feature_b).
struct axis_hint {
  plane_source source = plane_source::face_a;  ///< face of A, face of B, or an edge of each
  index_t feature_a = invalid_index;  ///< face or edge of A (invalid_index: none)
  index_t feature_b = invalid_index;  ///< face or edge of B (invalid_index: none)
  /// Whether the hint names an axis (a default hint names none).
  [[nodiscard]] bool names_axis() const noexcept { return feature_a != invalid_index || feature_b != invalid_index; }
  /// The axis of `plane`.
  [[nodiscard]] static axis_hint of(const contact_plane& plane) noexcept {
    return {plane.source, plane.feature_a, plane.feature_b};
  }
};

/// The edges of a convex polyhedron with their two faces: face_left holds the loop u -> v,
/// face_right the loop v -> u (outward CCW loops).
struct polyhedron_edges {
  /// One edge: its vertices u, v and the faces on its left and right
  struct edge {
    /** vertex ids and the faces left (loop u -> v) and right */ /**@{*/ index_t u, v, face_left, face_right; /**@}*/
  };
  std::vector<edge> list;  ///< every edge once
};

/// Edges of p from its face loops; throws geometry_error if an edge does not have exactly two
/// faces (an open or non-manifold polyhedron).
[[nodiscard]] TESSERA_INLINE polyhedron_edges edges_of(const geometry::convex_polyhedron& p);

namespace detail {

/// max_{x in p} n.x, in four running maxima rather than one chain of dependent ones (common
/// plane 64.9 -> 61.0 ms over bench_detection's 11 927 pairs; a maximum is exact, so the order
/// does not change the value).
[[nodiscard]] inline real support_max(const geometry::convex_polyhedron& p, const vec3& n) {
  constexpr real lowest = -std::numeric_limits<real>::infinity();
  real m[4] = {lowest, lowest, lowest, lowest};
  const std::vector<vec3>& x = p.vertices();
  std::size_t i = 0;
  for (; i + 4 <= x.size(); i += 4)
    for (std::size_t k = 0; k < 4; ++k) m[k] = std::max(m[k], n.dot(x[i + k]));
  for (; i < x.size(); ++i) m[0] = std::max(m[0], n.dot(x[i]));
  return std::max(std::max(m[0], m[1]), std::max(m[2], m[3]));
}
/// min_{x in p} n.x (as support_max).
[[nodiscard]] inline real support_min(const geometry::convex_polyhedron& p, const vec3& n) {
  return -support_max(p, -n);
}

}  // namespace detail

/// Appends p's outward face planes, face by face (face_plane), to `out`: what a detection pass
/// computes once per block (detect.hpp) instead of once per candidate pair.
inline void append_face_planes(const geometry::convex_polyhedron& p, std::vector<geometry::plane>& out) {
  for (index_t f = 0; f < p.face_count(); ++f) out.push_back(p.face_plane(f));
}

/// The contact plane of A and B (see the file comment). `edges_a`, `edges_b`: edges_of(a), (b),
/// which a caller keeps with its blocks; `faces_a`, `faces_b`: their face planes
/// (append_face_planes). `prune_edges` false tries every edge pair (the reference the tests
/// compare with). Throws invalid_input for an empty polyhedron or a face list of another size.
[[nodiscard]] TESSERA_INLINE contact_plane common_plane(const geometry::convex_polyhedron& a, const polyhedron_edges& edges_a,
                                                        std::span<const geometry::plane> faces_a,
                                                        const geometry::convex_polyhedron& b, const polyhedron_edges& edges_b,
                                                        std::span<const geometry::plane> faces_b, bool prune_edges = true);

/// common_plane's plane (pruned edge pairs), to the bit, for any `floor` (m); faster when floor is
/// a little below the plane's gap, e.g. the gap of the pair's axis at an earlier pass
/// (hinted_plane; detect.hpp's warm start). A candidate axis is tried in common_plane's order, and
/// one whose gap a few vertices already show at most the level is dropped without its full
/// vertex loops: the level is the best gap so far plus the tie (common_plane keeps the best over
/// it), or `floor` before any axis is taken. Dropping candidates below `floor` is the full
/// search's result as long as the first axis taken clears floor + the tie (every dropped one
/// then loses to it, and the state after it is the full search's); otherwise (or when none is
/// taken) the full search runs. -infinity (or NaN): the plain search with the early drops.
/// Arguments and refusals as common_plane's; no allocation beyond its scratch vectors.
[[nodiscard]] TESSERA_INLINE contact_plane common_plane_above(const geometry::convex_polyhedron& a,
                                                              const polyhedron_edges& edges_a,
                                                              std::span<const geometry::plane> faces_a,
                                                              const geometry::convex_polyhedron& b,
                                                              const polyhedron_edges& edges_b,
                                                              std::span<const geometry::plane> faces_b, real floor);

namespace detail {
/// common_plane's search over every candidate axis, each with its full vertex loops (the
/// reference that common_plane_above is tested against to the bit; arguments as common_plane's).
[[nodiscard]] TESSERA_INLINE contact_plane common_plane_every_axis(const geometry::convex_polyhedron& a,
                                                                   const polyhedron_edges& edges_a,
                                                                   std::span<const geometry::plane> faces_a,
                                                                   const geometry::convex_polyhedron& b,
                                                                   const polyhedron_edges& edges_b,
                                                                   std::span<const geometry::plane> faces_b,
                                                                   bool prune_edges);
}  // namespace detail

/// A lower bound (m) of common_plane(a, ..., b, ...).gap from one of its candidate axes, the one
/// `hint` names (a face of A, a face of B, or an edge of each: the axis of the pair's plane at an
/// earlier pass, its features being the same in the blocks' current geometry): that axis's gap,
/// computed as common_plane computes it, less 2 plane_tie_rel x size (common_plane keeps an
/// earlier axis within plane_tie_rel x size of a later one, and the margin covers the rounding).
/// The returned plane carries the axis and the bound as its gap (offset 0). Its gap is -infinity
/// where the axis is not certainly one of common_plane's candidates now (a feature out of range,
/// an edge pair whose arcs on the Gauss map do not cross, or cross within 1e-12 of not crossing,
/// parallel edges, an orientation within rounding of flipping): a caller then runs common_plane.
/// A pass that finds the bound above its tolerance knows the pair is not touching without the
/// full search (detect.hpp's detection_options::reuse_axes: the same result, cheaper). Arguments
/// as common_plane's. Cost O(V_A + V_B); no allocation.
[[nodiscard]] TESSERA_INLINE contact_plane hinted_plane(const geometry::convex_polyhedron& a, const polyhedron_edges& edges_a,
                                                        std::span<const geometry::plane> faces_a,
                                                        const geometry::convex_polyhedron& b, const polyhedron_edges& edges_b,
                                                        std::span<const geometry::plane> faces_b, const axis_hint& hint);

/// Overload that computes the face planes.
[[nodiscard]] inline contact_plane common_plane(const geometry::convex_polyhedron& a, const polyhedron_edges& edges_a,
                                                const geometry::convex_polyhedron& b, const polyhedron_edges& edges_b,
                                                bool prune_edges = true) {
  std::vector<geometry::plane> faces_a, faces_b;
  append_face_planes(a, faces_a);
  append_face_planes(b, faces_b);
  return common_plane(a, edges_a, faces_a, b, edges_b, faces_b, prune_edges);
}

/// Overload that builds the edge lists and face planes (for one-off queries and tests).
[[nodiscard]] inline contact_plane common_plane(const geometry::convex_polyhedron& a, const geometry::convex_polyhedron& b) {
  return common_plane(a, edges_of(a), b, edges_of(b));
}

}  // namespace tessera::contact::detection

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/contact_plane.ipp"
#endif
