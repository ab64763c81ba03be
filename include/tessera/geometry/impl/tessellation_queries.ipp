// The definitions of the larger functions that geometry/tessellation_queries.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../tessellation_queries.hpp"

namespace tessera::geometry {

[[nodiscard]] TESSERA_INLINE convex_polyhedron cell_polyhedron(const tessellation& t, index_t c) {
  std::vector<vec3> vertices;
  std::vector<index_t> offsets{0}, loops, tags;
  std::vector<std::pair<index_t, index_t>> local;  // (global, local), small: linear search
  for (index_t f = t.first_face(c); f < t.end_face(c); ++f) {
    for (index_t g : t.face(f)) {
      auto it = std::find_if(local.begin(), local.end(), [g](const auto& p) { return p.first == g; });
      if (it == local.end()) {
        local.emplace_back(g, static_cast<index_t>(vertices.size()));
        vertices.push_back(t.vertices[static_cast<std::size_t>(g)]);
        loops.push_back(local.back().second);
      } else {
        loops.push_back(it->second);
      }
    }
    offsets.push_back(static_cast<index_t>(loops.size()));
    tags.push_back(t.face_neighbor[static_cast<std::size_t>(f)]);
  }
  return convex_polyhedron::from_faces(std::move(vertices), std::move(offsets), std::move(loops), std::move(tags));
}

[[nodiscard]] TESSERA_INLINE tessellation_report check(const tessellation& t) {
  tessellation_report r;
  r.min_face_area = std::numeric_limits<real>::infinity();
  r.min_edge_length = std::numeric_limits<real>::infinity();
  real total = 0;
  for (index_t c = 0; c < t.cell_count(); ++c) total += cell_volume(t, c);
  r.volume_error_rel = std::abs(total - t.domain.volume()) / t.domain.volume();

  for (index_t f = 0; f < t.face_count(); ++f) {
    const auto loop = t.face(f);
    r.min_face_area = std::min(r.min_face_area, face_area(t, f));
    {
      const vec3 n = face_normal(t, f);
      vec3 mean = vec3::Zero();
      for (index_t v : loop) mean += t.vertices[static_cast<std::size_t>(v)];
      mean /= static_cast<real>(loop.size());
      for (index_t v : loop) r.max_face_warp = std::max(r.max_face_warp, std::abs(n.dot(t.vertices[static_cast<std::size_t>(v)] - mean)));
    }
    for (std::size_t k = 0; k < loop.size(); ++k)
      r.min_edge_length = std::min(r.min_edge_length, (t.vertices[static_cast<std::size_t>(loop[(k + 1) % loop.size()])] -
                                                       t.vertices[static_cast<std::size_t>(loop[k])]).norm());
    if (t.is_boundary_face(f)) continue;
    const index_t g = t.face_twin[static_cast<std::size_t>(f)];
    bool matched = g >= 0 && g < t.face_count() && t.face_twin[static_cast<std::size_t>(g)] == f &&
                   t.face_cell[static_cast<std::size_t>(g)] == t.face_neighbor[static_cast<std::size_t>(f)] &&
                   t.face_neighbor[static_cast<std::size_t>(g)] == t.face_cell[static_cast<std::size_t>(f)];
    if (matched) {
      const auto other = t.face(g);
      const std::size_t m = loop.size();
      matched = other.size() == m;
      const auto start = std::find(other.begin(), other.end(), loop[0]);
      matched = matched && start != other.end();
      if (matched) {
        const std::size_t s = static_cast<std::size_t>(start - other.begin());
        for (std::size_t k = 0; k < m && matched; ++k) matched = loop[k] == other[(s + m - k) % m];
      }
    }
    if (!matched) ++r.unmatched_faces;
  }

  std::vector<index_t> seen;
  for (index_t c = 0; c < t.cell_count(); ++c) {
    seen.clear();
    index_t loop_total = 0;
    for (index_t f = t.first_face(c); f < t.end_face(c); ++f) {
      for (index_t v : t.face(f)) seen.push_back(v);
      loop_total += static_cast<index_t>(t.face(f).size());
    }
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    const index_t faces = t.end_face(c) - t.first_face(c);
    if (loop_total % 2 != 0 || static_cast<index_t>(seen.size()) - loop_total / 2 + faces != 2) ++r.open_cells;
    aabb bb;
    for (index_t v : seen) bb.expand(t.vertices[static_cast<std::size_t>(v)]);
    const real tol = 1e-9 * bb.size().maxCoeff();
    bool convex = true;
    for (index_t f = t.first_face(c); f < t.end_face(c); ++f) {
      const plane h = plane::through(face_normal(t, f), face_centroid(t, f));
      for (index_t v : seen) {
        const real d = h.signed_distance(t.vertices[static_cast<std::size_t>(v)]);
        r.max_nonconvexity = std::max(r.max_nonconvexity, d);
        if (d > tol) convex = false;
      }
    }
    if (!convex) ++r.nonconvex_cells;
  }
  return r;
}

[[nodiscard]] TESSERA_INLINE tessellation separate_blocks(std::span<const convex_polyhedron> blocks) {
  require<geometry_error>(!blocks.empty(), "separate_blocks: no block given");
  tessellation t;
  for (std::size_t c = 0; c < blocks.size(); ++c) {
    const convex_polyhedron& p = blocks[c];
    require<geometry_error>(!p.empty() && p.vertex_count() >= 4, "separate_blocks: block ", c, " is empty (",
                            p.vertex_count(), " vertices)");
    const auto first = static_cast<index_t>(t.vertices.size());
    for (const vec3& x : p.vertices()) {
      t.vertices.push_back(x);
      t.domain.expand(x);
    }
    for (index_t f = 0; f < p.face_count(); ++f) {
      for (index_t v : p.face(f)) t.face_vertices.push_back(first + v);
      t.face_offsets.push_back(static_cast<index_t>(t.face_vertices.size()));
      t.face_cell.push_back(static_cast<index_t>(c));
      t.face_neighbor.push_back(boundary_tag(0));
      t.face_twin.push_back(invalid_index);
    }
    t.cell_face_offsets.push_back(static_cast<index_t>(t.face_cell.size()));
  }
  return t;
}

}  // namespace tessera::geometry
