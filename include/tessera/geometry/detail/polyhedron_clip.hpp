#pragma once
// The plane clipping of a convex polyhedron (convex_polyhedron::clip, which states the policy:
// one attempt per "on" band, widened on inconsistent sides, then the fallback mode): one attempt
// classifies the vertices, keeps the inside part of every face, closes the hole with the new
// face, merges its exactly coincident vertices and drops unused vertices. Works on the
// boundary representation's arrays in place. Not a public interface.
//
// Cost: O(V + sum of loop lengths) per attempt (close_cap: O(E^2) in the on-plane edges of the
// new face) and allocation-free once the per-thread scratch buffers have grown. Thread safety:
// one scratch per thread; distinct polyhedra may be clipped from distinct threads.

#include <algorithm>
#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "../../core/separate_compilation.hpp"
#include "../../core/types.hpp"
#include "../predicates.hpp"

namespace tessera::geometry::detail {

/// The boundary representation of a convex_polyhedron, by reference: positions (m), CSR face
/// loops and one tag per face.
struct polyhedron_arrays {
  std::vector<vec3>& vertices;
  std::vector<index_t>& face_offsets;
  std::vector<index_t>& face_vertices;
  std::vector<index_t>& face_tags;
};

/// What one attempt did: nothing outside the plane, a cut, or sides that rounding made
/// inconsistent (clip then widens the "on" band).
enum class clip_result { unchanged, cut, inconsistent };

/// The buffers of one attempt, reused across attempts and polyhedra (one per thread).
struct clip_scratch {
  std::vector<real> distance;
  std::vector<side> vertex_side;
  std::vector<index_t> remap;             // old vertex -> new vertex id (or invalid)
  std::vector<std::array<index_t, 3>> edge_points;  // (kept vertex, removed vertex, new vertex)
  std::vector<vec3> vertices;
  std::vector<index_t> face_offsets, face_vertices, face_tags;
  std::vector<char> on_plane;           // per new vertex
  std::vector<std::array<index_t, 2>> plane_edges;  // directed edges of kept faces lying on the plane
  std::vector<index_t> cap_next;          // per new vertex: successor on the new face, or invalid
  std::vector<index_t> used;
  std::vector<index_t> alias;             // per new vertex: the vertex it is merged into (itself if none)
};

[[nodiscard]] inline clip_scratch& clip_workspace() {
  thread_local clip_scratch s;
  return s;
}

// Signed distances and sides of the vertices; in fallback mode an "on" vertex without an
// outside neighbour counts as inside (rule (1) of try_clip).
TESSERA_INLINE void classify_vertices(clip_scratch& s, polyhedron_arrays p, const plane& h, real tol, bool fallback);

// The kept part of every face with an inside vertex (its outside run replaced by the two
// edge intersection points), the kept vertices and the on-plane edges the cap will close.
TESSERA_INLINE void clip_kept_faces(clip_scratch& s, polyhedron_arrays p);

// Appends the new face; false if the on-plane edges do not form one simple loop.
TESSERA_INLINE bool close_cap(clip_scratch& s, index_t tag);

// Drops vertices no face uses any more (an on-plane vertex whose faces were all removed)
// and installs the clipped polyhedron.
TESSERA_INLINE void drop_unused_vertices(clip_scratch& s, polyhedron_arrays p);

// Two nearly parallel edges (the long sides of a sliver face) cut close to where they meet
// give intersection points closer than the coordinates resolve: they round to the same
// position (fuzz_clip: a 1000 m sliver 5e-6 m wide cut 2e-6 m from its tip, points 1e-14 m
// apart, below the 1e-13 m spacing of doubles near 1000). Consecutive vertices of the new face
// (the last face) at exactly the same position are merged into one; repeats this leaves in a
// loop are removed and a face left with fewer than 3 vertices (of zero area) is dropped. Only
// exact coincidences are merged, so no vertex moves and any other cut is unchanged bit for bit.
// Returns false when the new face itself degenerates (the caller then widens the tolerance),
// unless may_drop_new_face (try_clip's fallback), or when fewer than 4 faces are left.
TESSERA_INLINE bool merge_coincident_cap_vertices(clip_scratch& s, bool may_drop_new_face);

// One attempt of clip with "on" band tol. The fallback mode, used only after every band
// failed without it (so cuts that succeeded before are unchanged bit for bit), differs twice:
// (1) A vertex "on" the plane none of whose neighbours (along face edges) is outside counts as inside:
// it stays where it is, as every "on" vertex does, but the faces through it are kept instead
// of being replaced by the new face. In exact arithmetic such a vertex cannot exist while
// anything is outside (the polyhedron lies in the cone of the edges at the vertex, and all of
// them point inside or along the plane), so it marks a feature below the plane tolerance
// lying on the plane. fuzz_clip: a plane through an edge of a 0.023 m polyhedron and, within
// 1e-14 m, through a triangle face with 3.5e-11 m edges that touches the cross-section at one
// vertex; removing that face as "on" pinches the outline of the new face there (two
// successors), while keeping it leaves the new face the cross-section triangle and the tiny
// face where it was. No vertex moves and no face changes its plane.
// (2) A new face whose vertices merge into fewer than 3 (merge_coincident_cap_vertices) is
// dropped instead of failing: the part cut off ends in an edge or a point that the
// coordinates cannot resolve. fuzz_clip: a 133 m needle whose tip is three vertices 5e-13 m
// apart, shaved 9.4e-4 m: the three intersection points near the tip round to two positions.
// The surface stays closed: the faces around a dropped face of two vertices a, b use the
// edge as a->b and b->a.
TESSERA_INLINE clip_result try_clip(polyhedron_arrays p, const plane& h, index_t tag, real tol, bool fallback);

}  // namespace tessera::geometry::detail

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/polyhedron_clip.ipp"
#endif
