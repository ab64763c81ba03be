// The definitions of the larger functions that geometry/cleanup.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../cleanup.hpp"

namespace tessera::geometry {

TESSERA_INLINE void vertex_keys_of(std::span<const convex_polyhedron> cells, const std::vector<std::size_t>& point_offset,
                                   std::vector<vec3>& points, std::vector<vertex_key>& keys, std::vector<real>& conditioning) {
  const std::size_t ncells = cells.size();
  parallel_for(static_cast<std::int64_t>(ncells), [&](std::int64_t ci) {
    const auto c = static_cast<std::size_t>(ci);
    const convex_polyhedron& p = cells[c];
    const std::size_t base = point_offset[c];
    std::copy(p.vertices().begin(), p.vertices().end(), points.begin() + static_cast<std::ptrdiff_t>(base));
    // incident faces of each vertex: count and the first three (keys[] used as scratch)
    thread_local std::vector<int> degree;
    thread_local std::vector<vec3> normal;
    degree.assign(static_cast<std::size_t>(p.vertex_count()), 0);
    normal.resize(static_cast<std::size_t>(p.face_count()));
    for (index_t f = 0; f < p.face_count(); ++f) normal[static_cast<std::size_t>(f)] = p.face_normal(f);
    for (index_t f = 0; f < p.face_count(); ++f)
      for (index_t v : p.face(f)) {
        int& d = degree[static_cast<std::size_t>(v)];
        if (d < 3) keys[base + static_cast<std::size_t>(v)][static_cast<std::size_t>(d)] = f;
        ++d;
      }
    for (index_t v = 0; v < p.vertex_count(); ++v) {
      vertex_key& key = keys[base + static_cast<std::size_t>(v)];
      if (degree[static_cast<std::size_t>(v)] < 3) { key = no_vertex_key; continue; }
      const vec3& n0 = normal[static_cast<std::size_t>(key[0])];
      const vec3& n1 = normal[static_cast<std::size_t>(key[1])];
      const vec3& n2 = normal[static_cast<std::size_t>(key[2])];
      conditioning[base + static_cast<std::size_t>(v)] = std::abs(n0.dot(n1.cross(n2)));
      if (degree[static_cast<std::size_t>(v)] != 3) { key = no_vertex_key; continue; }
      key = {p.face_tag(key[0]), p.face_tag(key[1]), p.face_tag(key[2]), static_cast<index_t>(c)};
      std::sort(key.begin(), key.end());
    }
  }, 64);
}

[[nodiscard]] TESSERA_INLINE tessellation assemble_tessellation(const aabb& domain, std::span<const convex_polyhedron> cells,
                                                                std::span<const vec3> seeds, std::span<const real> weights,
                                                                real tol) {
  const std::size_t ncells = cells.size();
  std::vector<std::size_t> point_offset(ncells + 1, 0);
  for (std::size_t c = 0; c < ncells; ++c)
    point_offset[c + 1] = point_offset[c] + static_cast<std::size_t>(cells[c].vertex_count());
  std::vector<vec3> points(point_offset[ncells]);
  std::vector<vertex_key> keys(point_offset[ncells], no_vertex_key);
  std::vector<real> conditioning(point_offset[ncells], 0);
  vertex_keys_of(cells, point_offset, points, keys, conditioning);
  welded_points welded = weld_vertices(points, tol, domain, keys, conditioning);
  if (!seeds.empty()) recompute_ill_conditioned_vertices(welded, points, keys, seeds, weights, tol, domain);

  // Global loops per cell, cleaned; cells with < 4 faces are dropped.
  struct raw_face { index_t neighbor; std::size_t begin, end; };
  std::vector<index_t> loops;
  std::vector<raw_face> faces;
  std::vector<std::size_t> cell_faces(ncells + 1, 0);
  std::vector<index_t> new_id(ncells, invalid_index);
  std::vector<index_t> loop;
  index_t kept = 0;
  for (std::size_t c = 0; c < ncells; ++c) {
    const std::size_t faces_before = faces.size(), loops_before = loops.size();
    const convex_polyhedron& p = cells[c];
    for (index_t f = 0; f < p.face_count(); ++f) {
      loop.clear();
      for (index_t v : p.face(f)) loop.push_back(welded.global_id[point_offset[c] + static_cast<std::size_t>(v)]);
      clean_loop(loop);
      if (loop.empty()) continue;
      faces.push_back({p.face_tag(f), loops.size(), loops.size() + loop.size()});
      loops.insert(loops.end(), loop.begin(), loop.end());
    }
    if (faces.size() - faces_before < 4) {
      faces.resize(faces_before);
      loops.resize(loops_before);
    } else {
      new_id[c] = kept++;
    }
    cell_faces[c + 1] = faces.size();
  }

  tessellation t;
  t.domain = domain;
  // Only vertices used by a surviving face are kept, renumbered in order of first use.
  std::vector<index_t> vertex_id(welded.vertices.size(), invalid_index);
  for (index_t& v : loops) {
    index_t& g = vertex_id[static_cast<std::size_t>(v)];
    if (g == invalid_index) {
      g = static_cast<index_t>(t.vertices.size());
      t.vertices.push_back(welded.vertices[static_cast<std::size_t>(v)]);
    }
    v = g;
  }
  for (std::size_t c = 0; c < ncells; ++c) {
    if (new_id[c] == invalid_index) continue;
    if (!seeds.empty()) t.seeds.push_back(seeds[c]);
    if (!weights.empty()) t.weights.push_back(weights[c]);
    for (std::size_t f = cell_faces[c]; f < cell_faces[c + 1]; ++f) {
      const raw_face& rf = faces[f];
      t.face_vertices.insert(t.face_vertices.end(), loops.begin() + static_cast<std::ptrdiff_t>(rf.begin),
                             loops.begin() + static_cast<std::ptrdiff_t>(rf.end));
      t.face_offsets.push_back(static_cast<index_t>(t.face_vertices.size()));
      t.face_cell.push_back(new_id[c]);
      index_t nb = rf.neighbor;
      if (nb >= 0) {
        nb = new_id[static_cast<std::size_t>(nb)];
        require<geometry_error>(nb != invalid_index, "tessellation cleanup: cell ", c, " keeps a face of ",
                                rf.end - rf.begin, " vertices toward cell ", rf.neighbor,
                                ", which degenerated below the weld tolerance ", tol, " m");
      }
      t.face_neighbor.push_back(nb);
    }
    t.cell_face_offsets.push_back(static_cast<index_t>(t.face_cell.size()));
  }

  match_twins(t);
  return t;
}

}  // namespace tessera::geometry
