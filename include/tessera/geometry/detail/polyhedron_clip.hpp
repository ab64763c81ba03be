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
inline void classify_vertices(clip_scratch& s, polyhedron_arrays p, const plane& h, real tol, bool fallback) {
  const std::size_t nv = p.vertices.size();
  s.distance.resize(nv);
  s.vertex_side.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) {
    s.distance[v] = h.signed_distance(p.vertices[v]);
    s.vertex_side[v] = classify_distance(s.distance[v], tol);
  }
  if (fallback) {
    s.used.assign(nv, 0);  // 1: an "on" vertex with an outside neighbour
    for (std::size_t f = 0; f < p.face_tags.size(); ++f) {
      const std::span<const index_t> loop(p.face_vertices.data() + p.face_offsets[f],
                                          static_cast<std::size_t>(p.face_offsets[f + 1] - p.face_offsets[f]));
      for (std::size_t k = 0; k < loop.size(); ++k) {
        const auto a = static_cast<std::size_t>(loop[k]), b = static_cast<std::size_t>(loop[(k + 1) % loop.size()]);
        if (s.vertex_side[a] == side::outside && s.vertex_side[b] == side::on) s.used[b] = 1;
        if (s.vertex_side[b] == side::outside && s.vertex_side[a] == side::on) s.used[a] = 1;
      }
    }
    for (std::size_t v = 0; v < nv; ++v)
      if (s.vertex_side[v] == side::on && !s.used[v]) s.vertex_side[v] = side::inside;
  }
}

// The kept part of every face with an inside vertex (its outside run replaced by the two
// edge intersection points), the kept vertices and the on-plane edges the cap will close.
inline void clip_kept_faces(clip_scratch& s, polyhedron_arrays p) {
  const std::size_t nv = p.vertices.size();
  // Kept vertices keep their relative order; intersection points are appended.
  s.remap.assign(nv, invalid_index);
  s.vertices.clear();
  s.on_plane.clear();
  for (std::size_t v = 0; v < nv; ++v)
    if (s.vertex_side[v] != side::outside) {
      s.remap[v] = static_cast<index_t>(s.vertices.size());
      s.vertices.push_back(p.vertices[v]);
      s.on_plane.push_back(s.vertex_side[v] == side::on);
    }
  s.edge_points.clear();
  // Intersection of edge (a kept strictly inside, b outside) with the plane, shared by the two
  // faces of the edge: p = x_a + t (x_b - x_a), t = d_a / (d_a - d_b) in (0, 1).
  auto edge_point = [&](index_t a, index_t b) {
    for (const auto& e : s.edge_points)
      if (e[0] == a && e[1] == b) return e[2];
    const real da = s.distance[static_cast<std::size_t>(a)], db = s.distance[static_cast<std::size_t>(b)];
    const real t = da / (da - db);
    const vec3& xa = p.vertices[static_cast<std::size_t>(a)];
    const vec3& xb = p.vertices[static_cast<std::size_t>(b)];
    const index_t id = static_cast<index_t>(s.vertices.size());
    s.vertices.push_back(xa + t * (xb - xa));
    s.on_plane.push_back(1);
    s.edge_points.push_back({a, b, id});
    return id;
  };

  s.face_offsets.assign(1, 0);
  s.face_vertices.clear();
  s.face_tags.clear();
  s.plane_edges.clear();
  for (std::size_t f = 0; f + 1 < p.face_offsets.size(); ++f) {
    const index_t begin = p.face_offsets[f], end = p.face_offsets[f + 1];
    const index_t n = end - begin;
    bool has_inside = false;
    for (index_t k = begin; k < end; ++k)
      has_inside |= s.vertex_side[static_cast<std::size_t>(p.face_vertices[static_cast<std::size_t>(k)])] == side::inside;
    if (!has_inside) continue;  // face outside or on the plane: replaced by the new face
    const std::size_t start = s.face_vertices.size();
    for (index_t k = 0; k < n; ++k) {
      const index_t a = p.face_vertices[static_cast<std::size_t>(begin + k)];
      const index_t b = p.face_vertices[static_cast<std::size_t>(begin + (k + 1) % n)];
      const side sa = s.vertex_side[static_cast<std::size_t>(a)];
      const side sb = s.vertex_side[static_cast<std::size_t>(b)];
      if (sa != side::outside) s.face_vertices.push_back(s.remap[static_cast<std::size_t>(a)]);
      if (sa == side::inside && sb == side::outside) s.face_vertices.push_back(edge_point(a, b));
      else if (sa == side::outside && sb == side::inside) s.face_vertices.push_back(edge_point(b, a));
    }
    const std::size_t m = s.face_vertices.size() - start;
    if (m < 3) {  // cannot happen with a face that has an inside vertex, kept as a guard
      s.face_vertices.resize(start);
      continue;
    }
    for (std::size_t k = 0; k < m; ++k) {
      const index_t a = s.face_vertices[start + k], b = s.face_vertices[start + (k + 1) % m];
      if (s.on_plane[static_cast<std::size_t>(a)] && s.on_plane[static_cast<std::size_t>(b)])
        s.plane_edges.push_back({a, b});
    }
    s.face_offsets.push_back(static_cast<index_t>(s.face_vertices.size()));
    s.face_tags.push_back(p.face_tags[f]);
  }
}

// Appends the new face; false if the on-plane edges do not form one simple loop.
inline bool close_cap(clip_scratch& s, index_t tag) {
  // The new face closes the hole: it runs along every on-plane edge that only one kept face
  // uses, in the opposite direction (a closed oriented surface uses each edge once each way).
  const std::size_t nnew = s.vertices.size();
  s.cap_next.assign(nnew, invalid_index);
  std::size_t cap_edges = 0;
  index_t cap_start = invalid_index;
  for (const auto& e : s.plane_edges) {
    bool paired = false;
    for (const auto& g : s.plane_edges)
      if (g[0] == e[1] && g[1] == e[0]) { paired = true; break; }
    if (paired) continue;
    if (s.cap_next[static_cast<std::size_t>(e[1])] != invalid_index) return false;
    s.cap_next[static_cast<std::size_t>(e[1])] = e[0];
    ++cap_edges;
    if (cap_start == invalid_index || e[1] < cap_start) cap_start = e[1];
  }
  if (cap_edges < 3) return false;
  {
    index_t v = cap_start;
    std::size_t walked = 0;
    do {
      s.face_vertices.push_back(v);
      v = s.cap_next[static_cast<std::size_t>(v)];
      ++walked;
    } while (v != invalid_index && v != cap_start && walked <= cap_edges);
    if (v != cap_start || walked != cap_edges) return false;
    s.face_offsets.push_back(static_cast<index_t>(s.face_vertices.size()));
    s.face_tags.push_back(tag);
  }
  return true;
}

// Drops vertices no face uses any more (an on-plane vertex whose faces were all removed)
// and installs the clipped polyhedron.
inline void drop_unused_vertices(clip_scratch& s, polyhedron_arrays p) {
  const std::size_t nnew = s.vertices.size();
  s.used.assign(nnew, invalid_index);
  for (index_t v : s.face_vertices) s.used[static_cast<std::size_t>(v)] = 0;
  index_t next = 0;
  p.vertices.clear();
  for (std::size_t v = 0; v < nnew; ++v)
    if (s.used[v] == 0) {
      s.used[v] = next++;
      p.vertices.push_back(s.vertices[v]);
    }
  for (index_t& v : s.face_vertices) v = s.used[static_cast<std::size_t>(v)];
  p.face_offsets.swap(s.face_offsets);
  p.face_vertices.swap(s.face_vertices);
  p.face_tags.swap(s.face_tags);
}

// Two nearly parallel edges (the long sides of a sliver face) cut close to where they meet
// give intersection points closer than the coordinates resolve: they round to the same
// position (fuzz_clip: a 1000 m sliver 5e-6 m wide cut 2e-6 m from its tip, points 1e-14 m
// apart, below the 1e-13 m spacing of doubles near 1000). Consecutive vertices of the new face
// (the last face) at exactly the same position are merged into one; repeats this leaves in a
// loop are removed and a face left with fewer than 3 vertices (of zero area) is dropped. Only
// exact coincidences are merged, so no vertex moves and any other cut is unchanged bit for bit.
// Returns false when the new face itself degenerates (the caller then widens the tolerance),
// unless may_drop_new_face (try_clip's fallback), or when fewer than 4 faces are left.
inline bool merge_coincident_cap_vertices(clip_scratch& s, bool may_drop_new_face) {
  const std::size_t faces = s.face_tags.size();
  const index_t cap_begin = s.face_offsets[faces - 1], cap_end = s.face_offsets[faces];
  const index_t m = cap_end - cap_begin;
  bool any = false;
  for (index_t k = 0; k < m && !any; ++k)
    any = s.vertices[static_cast<std::size_t>(s.face_vertices[static_cast<std::size_t>(cap_begin + k)])] ==
          s.vertices[static_cast<std::size_t>(s.face_vertices[static_cast<std::size_t>(cap_begin + (k + 1) % m)])];
  if (!any) return true;
  s.alias.resize(s.vertices.size());
  for (std::size_t v = 0; v < s.alias.size(); ++v) s.alias[v] = static_cast<index_t>(v);
  auto root = [&](index_t v) {
    while (s.alias[static_cast<std::size_t>(v)] != v) v = s.alias[static_cast<std::size_t>(v)];
    return v;
  };
  for (index_t k = 0; k < m; ++k) {
    const index_t a = root(s.face_vertices[static_cast<std::size_t>(cap_begin + k)]);
    const index_t b = root(s.face_vertices[static_cast<std::size_t>(cap_begin + (k + 1) % m)]);
    if (a != b && s.vertices[static_cast<std::size_t>(a)] == s.vertices[static_cast<std::size_t>(b)])
      s.alias[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
  // Rewrite every loop in place (the write position never passes the read position).
  std::size_t write = 0, kept_faces = 0;
  index_t begin = 0;
  bool cap_kept = false;
  for (std::size_t f = 0; f < faces; ++f) {
    const index_t end = s.face_offsets[f + 1];
    const std::size_t start = write;
    for (index_t k = begin; k < end; ++k) {
      const index_t v = root(s.face_vertices[static_cast<std::size_t>(k)]);
      if (write > start && s.face_vertices[write - 1] == v) continue;
      s.face_vertices[write++] = v;
    }
    while (write - start > 1 && s.face_vertices[write - 1] == s.face_vertices[start]) --write;
    begin = end;
    if (write - start < 3) {  // a zero-area face between the merged vertices
      write = start;
      continue;
    }
    s.face_offsets[kept_faces + 1] = static_cast<index_t>(write);
    s.face_tags[kept_faces++] = s.face_tags[f];
    cap_kept = f + 1 == faces;
  }
  s.face_vertices.resize(write);
  s.face_offsets.resize(kept_faces + 1);
  s.face_tags.resize(kept_faces);
  return (cap_kept || may_drop_new_face) && kept_faces >= 4;
}

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
inline clip_result try_clip(polyhedron_arrays p, const plane& h, index_t tag, real tol, bool fallback) {
  clip_scratch& s = clip_workspace();
  classify_vertices(s, p, h, tol, fallback);
  const std::size_t nv = p.vertices.size();
  bool any_outside = false, any_inside = false;
  for (std::size_t v = 0; v < nv; ++v) {
    any_outside |= s.vertex_side[v] == side::outside;
    any_inside |= s.vertex_side[v] == side::inside;
  }
  if (!any_outside) return clip_result::unchanged;
  if (!any_inside) {  // everything outside or on the plane: nothing of positive volume is left
    p.vertices.clear();
    p.face_offsets.assign(1, 0);
    p.face_vertices.clear();
    p.face_tags.clear();
    return clip_result::cut;
  }

  clip_kept_faces(s, p);
  if (!close_cap(s, tag)) return clip_result::inconsistent;
  if (!merge_coincident_cap_vertices(s, fallback)) return clip_result::inconsistent;
  drop_unused_vertices(s, p);
  return clip_result::cut;
}

}  // namespace tessera::geometry::detail
