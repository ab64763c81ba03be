// The definitions of the larger functions that geometry/detail/polyhedron_clip.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../polyhedron_clip.hpp"

namespace tessera::geometry::detail {

TESSERA_INLINE void classify_vertices(clip_scratch& s, polyhedron_arrays p, const plane& h, real tol, bool fallback) {
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

TESSERA_INLINE void clip_kept_faces(clip_scratch& s, polyhedron_arrays p) {
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

TESSERA_INLINE bool close_cap(clip_scratch& s, index_t tag) {
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

TESSERA_INLINE void drop_unused_vertices(clip_scratch& s, polyhedron_arrays p) {
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

TESSERA_INLINE bool merge_coincident_cap_vertices(clip_scratch& s, bool may_drop_new_face) {
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

TESSERA_INLINE clip_result try_clip(polyhedron_arrays p, const plane& h, index_t tag, real tol, bool fallback) {
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
