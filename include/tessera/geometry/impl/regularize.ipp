// The definitions of the larger functions that geometry/regularize.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../regularize.hpp"

namespace tessera::geometry {
namespace detail::edge_collapse {

TESSERA_INLINE real shortest_edge(const collapse_state& st, real l_min, edge_queue* queue, index_t* n_short) {
  std::vector<std::pair<index_t, index_t>> edges;
  for (const auto& l : st.loop)
    for (std::size_t k = 0; k < l.size(); ++k)
      edges.emplace_back(std::min(l[k], l[(k + 1) % l.size()]), std::max(l[k], l[(k + 1) % l.size()]));
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  real shortest = std::numeric_limits<real>::infinity();
  index_t count = 0;
  for (const auto& [a, b] : edges) {
    const real len = st.length(a, b);
    shortest = std::min(shortest, len);
    if (len < l_min) {
      ++count;
      if (queue != nullptr) queue->emplace(len, a, b);
    }
  }
  if (n_short != nullptr) *n_short = count;
  return shortest;
}

TESSERA_INLINE tessellation rebuilt(const tessellation& tess, const collapse_state& st, real& max_vertex_shift) {
  const index_t nv = tess.vertex_count();
  std::vector<index_t> new_vertex(static_cast<std::size_t>(nv), invalid_index);
  tessellation out;
  out.domain = tess.domain;
  out.seeds = tess.seeds;
  out.weights = tess.weights;
  for (const auto& l : st.loop)
    for (const index_t v : l) new_vertex[static_cast<std::size_t>(v)] = 0;  // used
  for (index_t v = 0; v < nv; ++v)
    if (new_vertex[static_cast<std::size_t>(v)] == 0) {
      new_vertex[static_cast<std::size_t>(v)] = static_cast<index_t>(out.vertices.size());
      out.vertices.push_back(st.position[static_cast<std::size_t>(v)]);
    }
  for (index_t v = 0; v < nv; ++v)
    max_vertex_shift = std::max(max_vertex_shift, (tess.vertices[static_cast<std::size_t>(v)] -
                                                   st.position[static_cast<std::size_t>(st.find(v))]).norm());
  std::vector<index_t> new_face(static_cast<std::size_t>(tess.face_count()), invalid_index);
  for (index_t c = 0; c < tess.cell_count(); ++c) {
    for (index_t f = tess.first_face(c); f < tess.end_face(c); ++f) {
      const auto& l = st.loop[static_cast<std::size_t>(f)];
      if (l.empty()) continue;
      new_face[static_cast<std::size_t>(f)] = out.face_count();
      for (const index_t v : l) {
        const index_t nvid = new_vertex[static_cast<std::size_t>(v)];
        require<geometry_error>(nvid != invalid_index, "regularize: face ", f, " of cell ", c,
                                " refers to removed vertex ", v);
        out.face_vertices.push_back(nvid);
      }
      out.face_offsets.push_back(static_cast<index_t>(out.face_vertices.size()));
      out.face_cell.push_back(c);
      out.face_neighbor.push_back(tess.face_neighbor[static_cast<std::size_t>(f)]);
    }
    out.cell_face_offsets.push_back(out.face_count());
  }
  out.face_twin.assign(static_cast<std::size_t>(out.face_count()), invalid_index);
  for (index_t f = 0; f < tess.face_count(); ++f) {
    const index_t nf = new_face[static_cast<std::size_t>(f)];
    const index_t g = tess.face_twin[static_cast<std::size_t>(f)];
    if (nf == invalid_index || g == invalid_index) continue;
    const index_t ng = new_face[static_cast<std::size_t>(g)];
    require<geometry_error>(ng != invalid_index, "regularize: face ", f, " survived but its twin ", g, " was dropped");
    out.face_twin[static_cast<std::size_t>(nf)] = ng;
  }
  for (index_t f = 0; f < out.face_count(); ++f) {
    const index_t c = out.face_cell[static_cast<std::size_t>(f)], n = out.face_neighbor[static_cast<std::size_t>(f)];
    if (n > c) out.shared_faces.push_back({c, f, n, out.face_twin[static_cast<std::size_t>(f)]});
  }
  return out;
}

}  // namespace detail::edge_collapse
}  // namespace tessera::geometry

namespace tessera::geometry {

TESSERA_INLINE regularization_report regularize(tessellation& tess, real min_edge_rel) {
  using namespace detail::edge_collapse;
  require(std::isfinite(min_edge_rel) && min_edge_rel >= 0 && min_edge_rel <= max_regularization,
          "regularize: min_edge_rel = ", min_edge_rel, " must lie in [0, ", max_regularization,
          "] (relative to the mean cell size)");
  regularization_report rep;
  if (tess.cell_count() <= 0) return rep;
  rep.threshold = min_edge_rel * std::cbrt(tess.domain.volume() / tess.cell_count());
  collapse_state st(tess);
  merge_pass pass(tess, st, rep.threshold, rep);
  rep.min_edge_before = shortest_edge(st, rep.threshold, &pass.queue(), &rep.short_edges_before);
  pass.run();
  tessellation out = rebuilt(tess, st, rep.max_vertex_shift);
  rep.min_edge_after = shortest_edge(st, rep.threshold, nullptr, &rep.short_edges_after);
  tess = std::move(out);
  return rep;
}

}  // namespace tessera::geometry
