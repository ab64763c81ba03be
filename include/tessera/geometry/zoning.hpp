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
inline void refine_triangle(const triangle& t, real h2, surface_registry& reg, std::vector<triangle>& out,
                            index_t max_nodes) {
  std::vector<triangle> work{t};
  int guard = 0;
  while (!work.empty()) {
    const triangle tri = work.back();
    work.pop_back();
    // split[i]: edge (tri[i], tri[i+1]) is longer than h.
    std::array<bool, 3> split{};
    int n_split = 0;
    for (int i = 0; i < 3; ++i) {
      split[i] = reg.length2(tri[i], tri[(i + 1) % 3]) > h2;
      n_split += split[i];
    }
    if (n_split == 0) {
      out.push_back(tri);
      continue;
    }
    require<geometry_error>(++guard < (1 << 26), "zone_blocks: surface refinement does not terminate");
    std::array<surface_key, 3> m{};
    for (int i = 0; i < 3; ++i)
      if (split[i]) m[i] = reg.midpoint(tri[i], tri[(i + 1) % 3], max_nodes);
    if (n_split == 3) {  // red: four similar triangles
      work.push_back({tri[0], m[0], m[2]});
      work.push_back({m[0], tri[1], m[1]});
      work.push_back({m[2], m[1], tri[2]});
      work.push_back({m[0], m[1], m[2]});
    } else if (n_split == 1) {  // green: bisect the long edge towards the opposite vertex
      const int i = split[0] ? 0 : (split[1] ? 1 : 2);
      const surface_key a = tri[i], b = tri[(i + 1) % 3], c = tri[(i + 2) % 3];
      work.push_back({a, m[i], c});
      work.push_back({m[i], b, c});
    } else {  // blue: corner triangle at the vertex between the two split edges + a quad
      const int k = !split[0] ? 0 : (!split[1] ? 1 : 2);  // unsplit edge (a, b)
      const surface_key a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
      const surface_key mbc = m[(k + 1) % 3], mca = m[(k + 2) % 3];
      work.push_back({mbc, c, mca});
      // Quad (a, b, mbc, mca): take the shorter diagonal, ties broken by keys, so the choice
      // does not depend on the face orientation.
      const real d1 = reg.length2(a, mbc), d2 = reg.length2(b, mca);
      const bool diag_a = d1 < d2 || (d1 == d2 && std::min(a, mbc) < std::min(b, mca));
      if (diag_a) {
        work.push_back({a, b, mbc});
        work.push_back({a, mbc, mca});
      } else {
        work.push_back({a, b, mca});
        work.push_back({b, mbc, mca});
      }
    }
  }
}

/// Sorted copy of a triangle's keys: the canonical identity shared by a face and its twin.
[[nodiscard]] inline triangle sorted(triangle t) {
  std::sort(t.begin(), t.end());
  return t;
}

/// The triangulation of every face (min-angle, refined to edge h = options.target_edge_length
/// when h > 0), its triangles sorted by their sorted keys so the two sides of a face agree.
[[nodiscard]] inline std::vector<std::vector<triangle>> triangulate_faces(const tessellation& tess,
                                                                          const zoning_options& options,
                                                                          surface_registry& reg) {
  const real h = options.target_edge_length;
  const index_t n_faces = tess.face_count();
  std::vector<std::vector<triangle>> face_tris(static_cast<std::size_t>(n_faces));
  std::vector<triangle> coarse;
  triangulation_workspace workspace;
  for (index_t f = 0; f < n_faces; ++f) {
    const auto loop = tess.face(f);
    const auto n = static_cast<index_t>(loop.size());
    require<geometry_error>(n >= 3, "zone_blocks: face ", f, " of block ", tess.face_cell[f], " has ", n,
                            " vertices, expected >= 3");
    coarse.clear();
    min_angle_triangulation(tess.vertices, loop, coarse, workspace);
    auto& tris = face_tris[static_cast<std::size_t>(f)];
    if (h > 0) {
      for (const auto& t : coarse) refine_triangle(t, h * h, reg, tris, options.max_gridpoints);
    } else {
      tris = coarse;
    }
    std::sort(tris.begin(), tris.end(), [](const triangle& a, const triangle& b) { return sorted(a) < sorted(b); });
  }
  return face_tris;
}

/// Centroid of block b: volume V and centroid c of the polyhedron from the cones of its face
/// triangles on a point p0 inside it (vertex average), V = sum V_t, c = sum V_t c_t / V. Throws
/// geometry_error for fewer than 4 vertices or a non-positive volume.
[[nodiscard]] inline vec3 block_centroid(const tessellation& tess, index_t b, const std::vector<surface_key>& keys,
                                         const surface_registry& reg,
                                         const std::vector<std::vector<triangle>>& face_tris) {
  vec3 p0 = vec3::Zero();
  index_t n_vertices = 0;
  for (const surface_key k : keys)
    if (k < tess.vertex_count()) { p0 += reg.position[static_cast<std::size_t>(k)]; ++n_vertices; }
  require<geometry_error>(n_vertices >= 4, "zone_blocks: block ", b, " has ", n_vertices, " vertices, expected >= 4");
  p0 /= n_vertices;
  real volume6 = 0.0;
  vec3 moment = vec3::Zero();
  for (index_t f = tess.first_face(b); f < tess.end_face(b); ++f)
    for (const auto& t : face_tris[static_cast<std::size_t>(f)]) {
      const vec3& x0 = reg.position[static_cast<std::size_t>(t[0])];
      const vec3& x1 = reg.position[static_cast<std::size_t>(t[1])];
      const vec3& x2 = reg.position[static_cast<std::size_t>(t[2])];
      const real v6 = tet_volume6(x0, x1, x2, p0) * -1.0;  // triangle CCW outward: p0 is behind it
      volume6 += v6;
      moment += v6 * (x0 + x1 + x2 + p0) / 4.0;
    }
  require<geometry_error>(volume6 > 0, "zone_blocks: block ", b, " has volume ", volume6 / 6.0,
                          " m^3, expected > 0 (faces must be CCW seen from outside)");
  return moment / volume6;
}

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
[[nodiscard]] inline block_mesh zone_blocks(const tessellation& tess, const zoning_options& options = {}) {
  using namespace detail::zoning;
  const real h = options.target_edge_length;
  require_non_negative(h, "zoning_options::target_edge_length (m)");
  const index_t n_faces = tess.face_count();
  const index_t n_cells = tess.cell_count();
  require<geometry_error>(static_cast<index_t>(tess.face_cell.size()) == n_faces, "zone_blocks: face_cell has ",
                          tess.face_cell.size(), " entries, expected one per face (", n_faces, ")");

  // ---- surface triangulation of every face, canonical for twins ----
  surface_registry reg;
  reg.position = tess.vertices;
  const std::vector<std::vector<triangle>> face_tris = triangulate_faces(tess, options, reg);

  block_mesh mesh;
  mesh.block_gridpoint_offsets.reserve(static_cast<std::size_t>(n_cells) + 1);
  mesh.block_zone_offsets.reserve(static_cast<std::size_t>(n_cells) + 1);
  mesh.face_node_offsets.assign(static_cast<std::size_t>(n_faces) + 1, 0);
  mesh.face_triangle_offsets.assign(static_cast<std::size_t>(n_faces) + 1, 0);
  // Face data are filled per block but indexed by face id; faces of a block are contiguous
  // and blocks are processed in order, so appending keeps face order.
  std::vector<surface_key> keys;
  for (index_t b = 0; b < n_cells; ++b) {
    // Surface nodes of the block, by key.
    keys.clear();
    for (index_t f = tess.first_face(b); f < tess.end_face(b); ++f)
      for (const auto& t : face_tris[static_cast<std::size_t>(f)]) keys.insert(keys.end(), t.begin(), t.end());
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    const auto n_surface = static_cast<index_t>(keys.size());
    const auto local = [&](surface_key k) {
      return static_cast<index_t>(std::lower_bound(keys.begin(), keys.end(), k) - keys.begin());
    };

    const vec3 centroid = block_centroid(tess, b, keys, reg, face_tris);

    // Interior layers: m homothetic copies of the surface about the centroid.
    index_t layers = 1;
    if (h > 0 && options.refine_interior) {
      real r_max = 0.0;
      for (const surface_key k : keys) r_max = std::max(r_max, (reg.position[static_cast<std::size_t>(k)] - centroid).norm());
      layers = std::max<index_t>(1, static_cast<index_t>(std::ceil(r_max / h)));
    }
    const auto base = static_cast<index_t>(mesh.gridpoints.size());
    require<geometry_error>(static_cast<double>(base) + static_cast<double>(n_surface) * layers + 1 <=
                                static_cast<double>(options.max_gridpoints),
                            "zone_blocks: block ", b, " would exceed ", options.max_gridpoints,
                            " gridpoints; zoning_options::target_edge_length = ", h, " m is too small");
    for (const surface_key k : keys) {
      mesh.gridpoints.push_back(reg.position[static_cast<std::size_t>(k)]);
      mesh.gridpoint_block.push_back(b);
      mesh.gridpoint_vertex.push_back(k < tess.vertex_count() ? k : invalid_index);
    }
    const index_t centroid_gp = base + n_surface;
    mesh.gridpoints.push_back(centroid);
    mesh.gridpoint_block.push_back(b);
    mesh.gridpoint_vertex.push_back(invalid_index);
    for (index_t layer = 1; layer < layers; ++layer) {
      const real s = static_cast<real>(layer) / static_cast<real>(layers);
      for (const surface_key k : keys) {
        mesh.gridpoints.push_back(centroid + s * (reg.position[static_cast<std::size_t>(k)] - centroid));
        mesh.gridpoint_block.push_back(b);
        mesh.gridpoint_vertex.push_back(invalid_index);
      }
    }
    mesh.block_gridpoint_offsets.push_back(static_cast<index_t>(mesh.gridpoints.size()));
    // Gridpoint of local surface node i on layer l (1 = innermost ring, layers = the surface).
    const auto on_layer = [&](index_t l, index_t i) {
      return l == layers ? base + i : base + n_surface + 1 + (l - 1) * n_surface + i;
    };

    const auto add_zone = [&](std::array<index_t, 4> z) {
      const auto& x = mesh.gridpoints;
      const real v6 = tet_volume6(x[static_cast<std::size_t>(z[0])], x[static_cast<std::size_t>(z[1])],
                                  x[static_cast<std::size_t>(z[2])], x[static_cast<std::size_t>(z[3])]);
      require<geometry_error>(v6 > 0, "zone_blocks: block ", b, " zone ", mesh.zones.size(), " has volume ",
                              v6 / 6.0, " m^3, expected > 0 (degenerate or non-convex block)");
      mesh.zones.push_back(z);
      mesh.zone_block.push_back(b);
    };

    for (index_t f = tess.first_face(b); f < tess.end_face(b); ++f)
      zone_face(mesh, f, face_tris[static_cast<std::size_t>(f)], reg, base, centroid_gp, layers, local, on_layer,
                add_zone);
    mesh.block_zone_offsets.push_back(static_cast<index_t>(mesh.zones.size()));
  }
  return mesh;
}

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
[[nodiscard]] inline zone_quality quality(const block_mesh& mesh) {
  zone_quality q;
  q.zones = mesh.zone_count();
  const index_t n_blocks = mesh.block_count();
  if (n_blocks > 0) {
    q.min_zones_per_block = std::numeric_limits<index_t>::max();
    for (index_t b = 0; b < n_blocks; ++b) {
      const index_t n = mesh.block_zone_offsets[static_cast<std::size_t>(b) + 1] - mesh.block_zone_offsets[static_cast<std::size_t>(b)];
      q.min_zones_per_block = std::min(q.min_zones_per_block, n);
      q.max_zones_per_block = std::max(q.max_zones_per_block, n);
    }
    q.mean_zones_per_block = static_cast<double>(q.zones) / n_blocks;
  }
  if (q.zones == 0) return q;
  q.min_zone_volume = std::numeric_limits<real>::infinity();
  q.min_dihedral_deg = 180.0;
  q.min_volume_ratio = std::numeric_limits<real>::infinity();
  double ratio_sum = 0.0;
  index_t below = 0;
  // Face k of a tet is the face opposite node k; edge (i, j) is shared by the faces opposite the
  // two other nodes.
  constexpr std::array<std::array<int, 3>, 4> opposite{{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
  for (index_t z = 0; z < q.zones; ++z) {
    const auto& node = mesh.zones[static_cast<std::size_t>(z)];
    std::array<vec3, 4> x;
    for (int i = 0; i < 4; ++i) x[static_cast<std::size_t>(i)] = mesh.gridpoints[static_cast<std::size_t>(node[static_cast<std::size_t>(i)])];
    const real v = detail::zoning::tet_volume6(x[0], x[1], x[2], x[3]) / 6.0;
    if (v < q.min_zone_volume) { q.min_zone_volume = v; q.min_volume_zone = z; }
    // Outward face normals (unit), faces listed CCW seen from outside for a positive tet.
    std::array<vec3, 4> normal;
    for (int k = 0; k < 4; ++k) {
      const auto& o = opposite[static_cast<std::size_t>(k)];
      normal[static_cast<std::size_t>(k)] = (x[static_cast<std::size_t>(o[1])] - x[static_cast<std::size_t>(o[0])])
                                                .cross(x[static_cast<std::size_t>(o[2])] - x[static_cast<std::size_t>(o[0])])
                                                .normalized();
    }
    real l2_sum = 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const real l2 = (x[static_cast<std::size_t>(j)] - x[static_cast<std::size_t>(i)]).squaredNorm();
        l2_sum += l2;
        q.max_edge_length = std::max(q.max_edge_length, std::sqrt(l2));
        // The two faces containing edge (i, j) are those opposite the other two nodes k, l.
        int k = 0;
        while (k == i || k == j) ++k;
        const int l = 6 - i - j - k;
        const real cos_angle = std::clamp(-normal[static_cast<std::size_t>(k)].dot(normal[static_cast<std::size_t>(l)]), -1.0, 1.0);
        const real angle = std::acos(cos_angle) * 180.0 / std::numbers::pi;
        q.min_dihedral_deg = std::min(q.min_dihedral_deg, angle);
        q.max_dihedral_deg = std::max(q.max_dihedral_deg, angle);
      }
    const real l_rms = std::sqrt(l2_sum / 6.0);
    const real ratio = 6.0 * std::numbers::sqrt2 * v / (l_rms * l_rms * l_rms);
    q.min_volume_ratio = std::min(q.min_volume_ratio, ratio);
    ratio_sum += ratio;
    below += ratio < 0.1;
  }
  q.mean_volume_ratio = ratio_sum / q.zones;
  q.fraction_below_ratio_0_1 = static_cast<real>(below) / q.zones;
  return q;
}

}  // namespace tessera::geometry
