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
inline void vertex_keys_of(std::span<const convex_polyhedron> cells, const std::vector<std::size_t>& point_offset,
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

/// Assembles a conforming tessellation from independently computed cells (cells[c] is the cell
/// of generator c, faces tagged with the neighbouring generator or boundary_tag), following the
/// cleanup policy above with absolute weld tolerance `tol` (m). `seeds` and `weights` (may be
/// empty) are stored per surviving cell. Throws geometry_error for a face without a twin.
[[nodiscard]] inline tessellation assemble_tessellation(const aabb& domain, std::span<const convex_polyhedron> cells,
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
