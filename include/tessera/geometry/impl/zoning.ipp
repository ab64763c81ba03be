// The definitions of the larger functions that geometry/zoning.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../zoning.hpp"

namespace tessera::geometry {
namespace detail::zoning {

TESSERA_INLINE void refine_triangle(const triangle& t, real h2, surface_registry& reg, std::vector<triangle>& out,
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

[[nodiscard]] TESSERA_INLINE std::vector<std::vector<triangle>> triangulate_faces(const tessellation& tess,
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

[[nodiscard]] TESSERA_INLINE vec3 block_centroid(const tessellation& tess, index_t b, const std::vector<surface_key>& keys,
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

}  // namespace detail::zoning
}  // namespace tessera::geometry

namespace tessera::geometry {

[[nodiscard]] TESSERA_INLINE block_mesh zone_blocks(const tessellation& tess, const zoning_options& options) {
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

[[nodiscard]] TESSERA_INLINE zone_quality quality(const block_mesh& mesh) {
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
