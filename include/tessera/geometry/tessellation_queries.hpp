#pragma once
// Free functions over a tessellation (geometry/tessellation.hpp): mass properties of a cell,
// face geometry, extraction of a cell as a convex_polyhedron, and a validity check.
//
// All cell quantities use the welded global vertices and the fan triangulation of
// mass_properties.hpp (apex = smallest vertex id of the face), so the volumes of all cells sum
// to the volume of the box up to rounding, and a face and its twin give the same area and
// opposite normals.
//
// Cost: O(size of the cell or face). Thread safety: pure functions of a const tessellation.

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "convex_polyhedron.hpp"
#include "mass_properties.hpp"
#include "predicates.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

namespace detail {
/// Face offsets of cell c as a sub-range of the tessellation's CSR offsets (absolute positions).
[[nodiscard]] inline std::span<const index_t> cell_face_offsets(const tessellation& t, index_t c) {
  const auto begin = static_cast<std::size_t>(t.first_face(c));
  return std::span<const index_t>(t.face_offsets).subspan(begin, static_cast<std::size_t>(t.end_face(c)) - begin + 1);
}
}  // namespace detail

/// Volume (m^3) of cell c.
[[nodiscard]] inline real cell_volume(const tessellation& t, index_t c) {
  return polyhedron_volume(t.vertices, detail::cell_face_offsets(t, c), t.face_vertices);
}
/// Volume, centroid and second moment (unit density) of cell c.
[[nodiscard]] inline mass_properties cell_mass_properties(const tessellation& t, index_t c) {
  return polyhedron_mass_properties(t.vertices, detail::cell_face_offsets(t, c), t.face_vertices);
}
/// Centroid (m) of cell c.
[[nodiscard]] inline vec3 cell_centroid(const tessellation& t, index_t c) { return cell_mass_properties(t, c).centroid; }
/// Inertia tensor (kg m^2) of cell c about its centroid for a density in kg/m^3.
[[nodiscard]] inline mat3 cell_inertia(const tessellation& t, index_t c, real density) {
  return inertia_tensor(cell_mass_properties(t, c).second_moment, density);
}

/// Area (m^2) of face f.
[[nodiscard]] inline real face_area(const tessellation& t, index_t f) { return polygon_area_vector(t.vertices, t.face(f)).norm(); }
/// Unit normal of face f, outward from face_cell[f].
[[nodiscard]] inline vec3 face_normal(const tessellation& t, index_t f) {
  return polygon_area_vector(t.vertices, t.face(f)).normalized();
}
/// Area-weighted centroid (m) of face f.
[[nodiscard]] inline vec3 face_centroid(const tessellation& t, index_t f) { return polygon_centroid(t.vertices, t.face(f)); }

/// Cell c as a stand-alone convex_polyhedron (local vertex ids in order of first use; face tags
/// = face_neighbor). Allocates.
[[nodiscard]] inline convex_polyhedron cell_polyhedron(const tessellation& t, index_t c) {
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

/// Validity measures of a tessellation (all should be zero / tiny for a good one).
struct tessellation_report {
  real volume_error_rel = 0;  ///< |sum of cell volumes - box volume| / box volume
  index_t unmatched_faces = 0;  ///< interior faces without a twin whose loop is the reversed loop
  index_t open_cells = 0;       ///< cells with Euler characteristic V - E + F != 2
  index_t nonconvex_cells = 0;  ///< cells with a vertex outside a face plane by more than 1e-9 of the cell extent
  real min_face_area = 0;     ///< smallest face area (m^2)
  real min_edge_length = 0;   ///< shortest face edge (m)
  /// Largest distance of a face vertex from its face's mean plane (Newell normal through the
  /// vertex mean) (m): 0 for planar faces; a regularized tessellation (regularize.hpp) has
  /// slightly warped faces.
  real max_face_warp = 0;
  /// Largest distance of a cell vertex outside one of its cell's face planes (m): 0 for convex
  /// cells (nonconvex_cells counts those above 1e-9 of the cell extent).
  real max_nonconvexity = 0;
};

/// Checks the invariants of a conforming tessellation. O(sum over cells of V x F).
[[nodiscard]] inline tessellation_report check(const tessellation& t) {
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

/// A model of separate convex blocks (not a space-filling tessellation): cell c is blocks[c] with
/// its own vertices (nothing welded, no shared faces, every face a boundary face tagged
/// boundary_tag(0)), the domain their bounding box. For scenes whose blocks only meet through
/// detected contacts (contact::detected_contacts): a block on a base, a stack, a wall. Blocks may
/// touch or be apart; they must not overlap (not checked). Throws geometry_error for an empty list
/// or an empty polyhedron.
[[nodiscard]] inline tessellation separate_blocks(std::span<const convex_polyhedron> blocks) {
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
