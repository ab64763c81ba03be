#pragma once
// Tetrahedral zoning of the blocks of a tessellation: geometry::zone_blocks fills a block_mesh
// (geometry/block_mesh.hpp) with constant-strain tetrahedra; geometry::quality reports how good
// they are.
//
// Construction (no refinement, zoning_options::target_edge_length = 0):
//  - each block gets its own copy of each of its polyhedron vertices as gridpoints, plus one
//    interior gridpoint at the block's volume centroid;
//  - each face is triangulated so that its smallest triangle angle is as large as possible
//    (geometry/polygon_triangulation.hpp: dynamic programming over the face polygon, run on a
//    canonical vertex order that starts at the smallest GLOBAL vertex id, so the two sides of a
//    shared face produce the same triangles, reversed). Why not the fan from one vertex: every
//    face triangle is coned to the centroid, and a fan over a face with a short edge or a
//    vertex close to a diagonal makes needle triangles, hence sliver zones, that a better choice
//    of diagonals avoids. What it cannot avoid are zones over a short polyhedron edge itself:
//    those need geometry/regularize.hpp. Slightly warped faces (regularized tessellations) are
//    fine: both sides use the same triangles, so the zoned blocks still fill the box exactly;
//  - each face triangle and the centroid form one zone. A block with V vertices, E edges and
//    F faces gets sum_f (n_f - 2) = 2E - 2F = 2V - 4 zones (Euler), e.g. about 26 for the
//    average random Voronoi cell (V ~ 27); the reference study used about 20 per block.
//
// Refinement (target_edge_length = h > 0):
//  - surface: every face triangle edge longer than h is bisected at its midpoint, and triangles
//    are split by the red-green-blue templates (3, 1 or 2 edges split), repeatedly until no
//    surface edge exceeds h. The decision depends only on the edge itself, so shared polyhedron
//    edges and twin faces are split identically (the tessellation stays conforming face to face);
//  - interior: each block is cut into m = ceil(max_x |x - c| / h) homothetic layers about its
//    centroid c; the innermost layer is a cone of tetrahedra on c, every outer layer a stack of
//    triangular prisms, each split into 3 tetrahedra with the quad-face diagonal joining the
//    inner node of the lower surface key to the outer node of the higher one (the standard
//    conforming prism split). Radial and surface-parallel zone edges are then <= h; prism
//    diagonals are <= 2h (triangle inequality). Rays from the centroid shorter than the longest
//    get proportionally thinner layers, so refined zones near the middle of large faces are
//    flatter than the unrefined cone (see quality() and the measured ratios in the tests).
//    zoning_options::refine_interior = false keeps one layer: the refined surface coned to c.
//
// Gridpoint order inside a block: its surface nodes by increasing surface key (polyhedron
// vertices first, by global vertex id, then edge midpoints), the centroid, then the interior
// layers from the centroid outwards, each in surface-node order. gridpoint_vertex is the global
// vertex id for vertex copies and invalid_index for midpoints and interior gridpoints.
//
// face_nodes of a face are ordered by surface key (global vertex id first, then midpoint keys,
// which are shared by the two sides), face_triangles are listed in a canonical order shared by
// twins (sorted vertex-key triples), so triangle t of face f is triangle t of its twin reversed,
// and face_node_area is accumulated in the same order on both sides (bitwise identical).
//
// Cost: O(number of zones) time and memory; not thread-safe on the same output object.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "block_mesh.hpp"
#include "polygon_triangulation.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

/// Options of zone_blocks (each refused out of range, invalid_input naming it)
struct zoning_options {
  /// Target zone edge length h (m); 0 = no refinement (one zone per face triangle).
  real target_edge_length = 0.0;
  /// false: refine the faces only and cone every surface triangle to the centroid (one layer),
  /// so faces carry more contact points (a gridpoint per face node) without the interior's
  /// layers of zones: what a scene needs for "ten contact points over the depth" (DESIGN.md §6)
  /// at a fraction of the zones (the study's beam: 250 blocks, 30 mm edges: about 8x fewer).
  bool refine_interior = true;
  /// Safety cap on the number of gridpoints created by refinement, so a tiny h fails loudly
  /// instead of exhausting memory.
  index_t max_gridpoints = 50'000'000;
};

/// Quality of the zones of a block_mesh (see quality()).
struct zone_quality {
  index_t zones = 0;  ///< number of zones
  index_t min_zones_per_block = 0;  ///< fewest zones in a block
  double mean_zones_per_block = 0.0;  ///< mean zones per block
  index_t max_zones_per_block = 0;  ///< most zones in a block
  real min_zone_volume = 0.0;      ///< smallest zone volume (m^3)
  index_t min_volume_zone = invalid_index;  ///< the zone of min_zone_volume
  real min_dihedral_deg = 0.0;     ///< smallest dihedral angle of any zone (degrees; 70.53 for a regular tet)
  real max_dihedral_deg = 0.0;     ///< largest dihedral angle of any zone (degrees)
  /// Smallest volume ratio eta = 6 sqrt(2) V / l_rms^3, l_rms = root mean square of the six edge
  /// lengths: 1 for the regular tetrahedron, -> 0 for slivers and needles.
  real min_volume_ratio = 0.0;
  real mean_volume_ratio = 0.0;  ///< mean volume ratio
  /// Fraction of zones with volume ratio below 0.1 (slivers, e.g. cones over the thin face
  /// triangles that short Voronoi edges produce).
  real fraction_below_ratio_0_1 = 0.0;
  real max_edge_length = 0.0;      ///< longest zone edge (m)
};

namespace detail::zoning {

/// Signed six-fold volume of tet (a, b, c, d): ((b - a) x (c - a)) . (d - a).
[[nodiscard]] inline real tet_volume6(const vec3& a, const vec3& b, const vec3& c, const vec3& d) {
  return (b - a).cross(c - a).dot(d - a);
}

/// Node of a refined face triangulation: global vertex id (< vertex_count) or an edge-midpoint key.
using surface_key = index_t;

/// Registry of the surface nodes of all faces: the tessellation vertices plus the edge midpoints
/// created by refinement, one key per midpoint shared by every face and block touching the edge.
struct surface_registry {
  std::vector<vec3> position;  ///< indexed by surface key
  std::unordered_map<std::uint64_t, surface_key> midpoint_of;

  static std::uint64_t edge_id(surface_key a, surface_key b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  }
  /// Squared length of edge (a, b), evaluated in key order so both sides get the same bits.
  [[nodiscard]] real length2(surface_key a, surface_key b) const {
    if (a > b) std::swap(a, b);
    return (position[static_cast<std::size_t>(b)] - position[static_cast<std::size_t>(a)]).squaredNorm();
  }
  surface_key midpoint(surface_key a, surface_key b, index_t max_nodes) {
    const auto [it, inserted] = midpoint_of.try_emplace(edge_id(a, b), static_cast<surface_key>(position.size()));
    if (inserted) {
      require<geometry_error>(static_cast<index_t>(position.size()) < max_nodes, "zone_blocks: refinement exceeds ",
                              max_nodes, " surface nodes; zoning_options::target_edge_length is too small");
      if (a > b) std::swap(a, b);
      position.push_back(0.5 * (position[static_cast<std::size_t>(a)] + position[static_cast<std::size_t>(b)]));
    }
    return it->second;
  }
};

using triangle = std::array<surface_key, 3>;

/// Splits triangle t (CCW outward) by red-green-blue templates until no edge exceeds h
/// (squared: h2), appending the result to out.
TESSERA_INLINE void refine_triangle(const triangle& t, real h2, surface_registry& reg, std::vector<triangle>& out,
                                    index_t max_nodes);

/// Sorted copy of a triangle's keys: the canonical identity shared by a face and its twin.
[[nodiscard]] inline triangle sorted(triangle t) {
  std::sort(t.begin(), t.end());
  return t;
}

/// The triangulation of every face (min-angle, refined to edge h = options.target_edge_length
/// when h > 0), its triangles sorted by their sorted keys so the two sides of a face agree.
[[nodiscard]] TESSERA_INLINE std::vector<std::vector<triangle>> triangulate_faces(const tessellation& tess,
                                                                                  const zoning_options& options,
                                                                                  surface_registry& reg);

/// Centroid of block b: volume V and centroid c of the polyhedron from the cones of its face
/// triangles on a point p0 inside it (vertex average), V = sum V_t, c = sum V_t c_t / V. Throws
/// geometry_error for fewer than 4 vertices or a non-positive volume.
[[nodiscard]] TESSERA_INLINE vec3 block_centroid(const tessellation& tess, index_t b, const std::vector<surface_key>& keys,
                                                 const surface_registry& reg,
                                                 const std::vector<std::vector<triangle>>& face_tris);

/// Face f of a block: its face nodes (by key, then renumbered to the block's gridpoints from
/// `base`), their tributary areas (a third of each triangle, in canonical triangle order), its
/// surface triangles and the zones below them: the innermost cone on the centroid (gridpoint
/// centroid_gp) and three
/// tetrahedra per triangle and layer, split on the key order so neighbours agree.
template <class Local, class OnLayer, class AddZone>
void zone_face(block_mesh& mesh, index_t f, const std::vector<triangle>& tris, const surface_registry& reg, index_t base,
               index_t centroid_gp, index_t layers, Local&& local, OnLayer&& on_layer, AddZone&& add_zone) {
  // Face data: nodes by key, areas accumulated in canonical triangle order.
  const auto node_begin = static_cast<std::size_t>(mesh.face_nodes.size());
  for (const auto& t : tris)
    for (const surface_key k : t) mesh.face_nodes.push_back(k);
  std::sort(mesh.face_nodes.begin() + static_cast<std::ptrdiff_t>(node_begin), mesh.face_nodes.end());
  mesh.face_nodes.erase(std::unique(mesh.face_nodes.begin() + static_cast<std::ptrdiff_t>(node_begin),
                                    mesh.face_nodes.end()),
                        mesh.face_nodes.end());
  mesh.face_node_area.resize(mesh.face_nodes.size(), 0.0);
  const auto face_node_entry = [&](surface_key k) {
    return static_cast<std::size_t>(
        std::lower_bound(mesh.face_nodes.begin() + static_cast<std::ptrdiff_t>(node_begin), mesh.face_nodes.end(), k) -
        mesh.face_nodes.begin());
  };
  for (const auto& t : tris) {
    const triangle s = sorted(t);
    const vec3& x0 = reg.position[static_cast<std::size_t>(s[0])];
    const real third_area =
        (reg.position[static_cast<std::size_t>(s[1])] - x0).cross(reg.position[static_cast<std::size_t>(s[2])] - x0).norm() / 6.0;
    for (const surface_key k : s) mesh.face_node_area[face_node_entry(k)] += third_area;
  }
  for (std::size_t e = node_begin; e < mesh.face_nodes.size(); ++e) mesh.face_nodes[e] = base + local(mesh.face_nodes[e]);
  mesh.face_node_offsets[static_cast<std::size_t>(f) + 1] = static_cast<index_t>(mesh.face_nodes.size());

  for (const auto& t : tris) {
    const index_t a = local(t[0]), bb = local(t[1]), c = local(t[2]);
    mesh.face_triangles.push_back({base + a, base + bb, base + c});
    // Innermost cone: (a, c, b) is CW seen from outside, so (a, c, b, centroid) is positive.
    add_zone({on_layer(1, a), on_layer(1, c), on_layer(1, bb), centroid_gp});
    // Prisms between layers l and l+1, split on the key order p < q < r of the triangle.
    if (layers > 1) {
      std::array<index_t, 3> pqr{a, bb, c};
      std::sort(pqr.begin(), pqr.end());
      // (p, q, r) has the orientation of (a, b, c) iff it is a cyclic rotation of it.
      const bool ccw = (pqr[0] == a && pqr[1] == bb) || (pqr[0] == bb && pqr[1] == c) || (pqr[0] == c && pqr[1] == a);
      for (index_t l = 1; l < layers; ++l) {
        const index_t p = on_layer(l, pqr[0]), q = on_layer(l, pqr[1]), r = on_layer(l, pqr[2]);
        const index_t po = on_layer(l + 1, pqr[0]), qo = on_layer(l + 1, pqr[1]), ro = on_layer(l + 1, pqr[2]);
        if (ccw) {
          add_zone({p, q, r, ro});
          add_zone({p, q, ro, qo});
          add_zone({p, po, qo, ro});
        } else {
          add_zone({q, p, r, ro});
          add_zone({q, p, ro, qo});
          add_zone({po, p, qo, ro});
        }
      }
    }
  }
  mesh.face_triangle_offsets[static_cast<std::size_t>(f) + 1] = static_cast<index_t>(mesh.face_triangles.size());
}

}  // namespace detail::zoning

/// Splits every block of `tess` into positive constant-strain tetrahedra (see the file comment).
/// Throws geometry_error naming the block and zone if a zone has non-positive volume (a
/// non-convex or degenerate block), and invalid_input for a negative or non-finite target length.
[[nodiscard]] TESSERA_INLINE block_mesh zone_blocks(const tessellation& tess, const zoning_options& options = {});

/// Volume of zone z (m^3), positive for a valid mesh.
[[nodiscard]] inline real zone_volume(const block_mesh& mesh, index_t z) {
  const auto& n = mesh.zones[static_cast<std::size_t>(z)];
  const auto& x = mesh.gridpoints;
  return detail::zoning::tet_volume6(x[static_cast<std::size_t>(n[0])], x[static_cast<std::size_t>(n[1])],
                                     x[static_cast<std::size_t>(n[2])], x[static_cast<std::size_t>(n[3])]) / 6.0;
}

/// Zone counts per block, smallest volume, dihedral angles and volume ratio of every zone.
/// Dihedral angle at edge (i, j): pi minus the angle between the outward normals of the two
/// faces sharing the edge.
[[nodiscard]] TESSERA_INLINE zone_quality quality(const block_mesh& mesh);

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/zoning.ipp"
#endif
