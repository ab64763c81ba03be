// Tests for the tetrahedral zoning (geometry/zoning.hpp), the I/O layer (io/*.hpp) and the
// example drivers' command-line helper (examples/common/cli.hpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../examples/common/cli.hpp"
#include "tessera/geometry/polygon_triangulation.hpp"
#include "tessera/geometry/regularize.hpp"
#include "tessera/presets.hpp"
#include "tessera/geometry/tessellation_queries.hpp"
#include "tessera/geometry/voronoi.hpp"
#include "tessera/geometry/zoning.hpp"
#include "tessera/io/atomic_file.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/json_reader.hpp"
#include "tessera/io/plot.hpp"
#include "tessera/io/vtk.hpp"

using namespace tessera;
using idx = tessera::index_t;
using geometry::block_mesh;
using geometry::tessellation;
namespace fs = std::filesystem;

namespace {

// ---- hand-built conforming tessellations ------------------------------------------------

/// Builds a tessellation from welded vertices and cells given as face loops (CCW seen from
/// outside): fills twins, neighbours, boundary tags and shared_faces by matching vertex sets.
tessellation make_tessellation(const aabb& domain, std::vector<vec3> vertices,
                               const std::vector<std::vector<std::vector<idx>>>& cells) {
  tessellation t;
  t.domain = domain;
  t.vertices = std::move(vertices);
  for (idx c = 0; c < static_cast<idx>(cells.size()); ++c) {
    for (const auto& loop : cells[static_cast<std::size_t>(c)]) {
      t.face_vertices.insert(t.face_vertices.end(), loop.begin(), loop.end());
      t.face_offsets.push_back(static_cast<idx>(t.face_vertices.size()));
      t.face_cell.push_back(c);
    }
    t.cell_face_offsets.push_back(static_cast<idx>(t.face_cell.size()));
  }
  const idx nf = t.face_count();
  t.face_neighbor.assign(static_cast<std::size_t>(nf), invalid_index);
  t.face_twin.assign(static_cast<std::size_t>(nf), invalid_index);
  std::map<std::vector<idx>, idx> by_set;
  for (idx f = 0; f < nf; ++f) {
    std::vector<idx> key(t.face(f).begin(), t.face(f).end());
    std::sort(key.begin(), key.end());
    if (const auto it = by_set.find(key); it != by_set.end()) {
      const idx g = it->second;
      t.face_twin[static_cast<std::size_t>(f)] = g;
      t.face_twin[static_cast<std::size_t>(g)] = f;
      t.face_neighbor[static_cast<std::size_t>(f)] = t.face_cell[static_cast<std::size_t>(g)];
      t.face_neighbor[static_cast<std::size_t>(g)] = t.face_cell[static_cast<std::size_t>(f)];
      t.shared_faces.push_back({t.face_cell[static_cast<std::size_t>(g)], g, t.face_cell[static_cast<std::size_t>(f)], f});
    } else {
      by_set.emplace(key, f);
    }
  }
  for (idx f = 0; f < nf; ++f) {
    if (t.face_twin[static_cast<std::size_t>(f)] != invalid_index) continue;
    for (int side = 0; side < 6; ++side) {
      const int axis = side / 2;
      const real plane = side % 2 ? domain.hi[axis] : domain.lo[axis];
      bool on = true;
      for (const idx v : t.face(f)) on = on && std::abs(t.vertices[static_cast<std::size_t>(v)][axis] - plane) < 1e-12;
      if (on) t.face_neighbor[static_cast<std::size_t>(f)] = geometry::boundary_tag(side);
    }
  }
  return t;
}

/// The box [0,lx]x[0,ly]x[0,lz] cut into nx*ny*nz equal boxes (hexahedral cells, quad faces).
tessellation box_grid(int nx, int ny, int nz, vec3 size = vec3(1, 1, 1)) {
  const auto vid = [&](int i, int j, int k) { return static_cast<idx>(i + (nx + 1) * (j + (ny + 1) * k)); };
  std::vector<vec3> v;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) v.emplace_back(size.x() * i / nx, size.y() * j / ny, size.z() * k / nz);
  std::vector<std::vector<std::vector<idx>>> cells;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const idx a = vid(i, j, k), b = vid(i + 1, j, k), c = vid(i + 1, j + 1, k), d = vid(i, j + 1, k);
        const idx e = vid(i, j, k + 1), f = vid(i + 1, j, k + 1), g = vid(i + 1, j + 1, k + 1), h = vid(i, j + 1, k + 1);
        cells.push_back({{a, d, h, e}, {b, c, g, f}, {a, e, f, b}, {d, c, g, h}, {a, b, c, d}, {e, f, g, h}});
        // fix the orientation of the x+, y+ and z+ faces (CCW seen from outside)
        auto& faces = cells.back();
        faces[1] = {b, c, g, f};
        faces[3] = {d, h, g, c};
        faces[5] = {e, f, g, h};
        faces[0] = {a, e, h, d};
        faces[2] = {a, b, f, e};
        faces[4] = {a, d, c, b};
      }
  aabb box;
  box.lo = vec3::Zero();
  box.hi = size;
  return make_tessellation(box, std::move(v), cells);
}

/// The box [0,1]x[0,1]x[0,2] cut into two cells by the slanted plane z = 0.8 + 0.2 x + 0.1 y.
tessellation slanted_split() {
  std::vector<vec3> v;
  const double xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const auto& p : xy) v.emplace_back(p[0], p[1], 0.0);                                  // 0..3 bottom
  for (const auto& p : xy) v.emplace_back(p[0], p[1], 0.8 + 0.2 * p[0] + 0.1 * p[1]);          // 4..7 cut
  for (const auto& p : xy) v.emplace_back(p[0], p[1], 2.0);                                  // 8..11 top
  const std::vector<std::vector<idx>> lower = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  const std::vector<std::vector<idx>> upper = {{4, 7, 6, 5}, {8, 9, 10, 11}, {4, 5, 9, 8}, {5, 6, 10, 9}, {6, 7, 11, 10}, {7, 4, 8, 11}};
  aabb box;
  box.lo = vec3::Zero();
  box.hi = vec3(1, 1, 2);
  return make_tessellation(box, std::move(v), {lower, upper});
}

/// Volume of cell c by the divergence theorem on its (planar) faces.
double exact_cell_volume(const tessellation& t, idx c) {
  double v6 = 0;
  for (idx f = t.first_face(c); f < t.end_face(c); ++f) {
    const auto loop = t.face(f);
    for (std::size_t i = 1; i + 1 < loop.size(); ++i)
      v6 += t.vertices[static_cast<std::size_t>(loop[0])].dot(
          t.vertices[static_cast<std::size_t>(loop[i])].cross(t.vertices[static_cast<std::size_t>(loop[i + 1])]));
  }
  return v6 / 6;
}
double exact_face_area(const tessellation& t, idx f) {
  const auto loop = t.face(f);
  vec3 s = vec3::Zero();
  for (std::size_t i = 0; i < loop.size(); ++i)
    s += t.vertices[static_cast<std::size_t>(loop[i])].cross(t.vertices[static_cast<std::size_t>(loop[(i + 1) % loop.size()])]);
  return 0.5 * s.norm();
}

/// Volume enclosed by the mesh's face triangles of block b (divergence theorem).
double triangulated_block_volume(const tessellation& t, const block_mesh& m, idx b) {
  double v6 = 0;
  for (idx f = t.first_face(b); f < t.end_face(b); ++f)
    for (idx k = m.face_triangle_offsets[f]; k < m.face_triangle_offsets[f + 1]; ++k) {
      const auto& tri = m.face_triangles[static_cast<std::size_t>(k)];
      v6 += m.gridpoints[static_cast<std::size_t>(tri[0])].dot(
          m.gridpoints[static_cast<std::size_t>(tri[1])].cross(m.gridpoints[static_cast<std::size_t>(tri[2])]));
    }
  return v6 / 6;
}

/// Every invariant the solver and the sub-contact builder rely on (block_mesh.hpp). With
/// planar_faces = false (regularized tessellations, warped faces) the block volumes and face
/// areas are compared with those of the mesh's own face triangles, which both sides share.
void check_mesh_invariants(const tessellation& t, const block_mesh& m, bool planar_faces = true) {
  REQUIRE(m.block_count() == t.cell_count());
  REQUIRE(m.face_node_offsets.size() == static_cast<std::size_t>(t.face_count()) + 1);
  REQUIRE(m.face_triangle_offsets.size() == static_cast<std::size_t>(t.face_count()) + 1);
  REQUIRE(m.gridpoint_block.size() == m.gridpoints.size());
  REQUIRE(m.gridpoint_vertex.size() == m.gridpoints.size());
  REQUIRE(m.face_node_area.size() == m.face_nodes.size());
  double total = 0;
  for (idx b = 0; b < m.block_count(); ++b) {
    double v = 0;
    for (idx z = m.block_zone_offsets[b]; z < m.block_zone_offsets[b + 1]; ++z) {
      REQUIRE(m.zone_block[static_cast<std::size_t>(z)] == b);
      const double vz = geometry::zone_volume(m, z);
      REQUIRE(vz > 0);
      for (const idx g : m.zones[static_cast<std::size_t>(z)]) REQUIRE(m.gridpoint_block[static_cast<std::size_t>(g)] == b);
      v += vz;
    }
    const double exact = planar_faces ? exact_cell_volume(t, b) : triangulated_block_volume(t, m, b);
    CHECK(v == Approx(exact).epsilon(1e-12));
    total += v;
    for (idx g = m.block_gridpoint_offsets[b]; g < m.block_gridpoint_offsets[b + 1]; ++g) {
      REQUIRE(m.gridpoint_block[static_cast<std::size_t>(g)] == b);
      const idx vtx = m.gridpoint_vertex[static_cast<std::size_t>(g)];
      if (vtx != invalid_index) CHECK(m.gridpoints[static_cast<std::size_t>(g)] == t.vertices[static_cast<std::size_t>(vtx)]);
    }
  }
  CHECK(total == Approx(t.domain.volume()).epsilon(1e-12));

  for (idx f = 0; f < t.face_count(); ++f) {
    const idx b = t.face_cell[static_cast<std::size_t>(f)];
    double area = 0;
    for (idx k = m.face_node_offsets[f]; k < m.face_node_offsets[f + 1]; ++k) {
      REQUIRE(m.gridpoint_block[static_cast<std::size_t>(m.face_nodes[static_cast<std::size_t>(k)])] == b);
      area += m.face_node_area[static_cast<std::size_t>(k)];
    }
    // Triangles are CCW seen from outside: their normals agree with the face's outward normal.
    const auto loop = t.face(f);
    vec3 n_face = vec3::Zero();  // Newell normal
    for (std::size_t i = 0; i < loop.size(); ++i)
      n_face += t.vertices[static_cast<std::size_t>(loop[i])].cross(t.vertices[static_cast<std::size_t>(loop[(i + 1) % loop.size()])]);
    double tri_area = 0;
    for (idx k = m.face_triangle_offsets[f]; k < m.face_triangle_offsets[f + 1]; ++k) {
      const auto& tri = m.face_triangles[static_cast<std::size_t>(k)];
      const vec3 n = (m.gridpoints[static_cast<std::size_t>(tri[1])] - m.gridpoints[static_cast<std::size_t>(tri[0])])
                         .cross(m.gridpoints[static_cast<std::size_t>(tri[2])] - m.gridpoints[static_cast<std::size_t>(tri[0])]);
      CHECK(n.dot(n_face) > 0);
      tri_area += 0.5 * n.norm();
    }
    CHECK(area == Approx(tri_area).epsilon(1e-12));
    if (planar_faces) {
      CHECK(tri_area == Approx(exact_face_area(t, f)).epsilon(1e-12));
    } else {
      CHECK(tri_area >= exact_face_area(t, f) * (1 - 1e-12));  // a warped surface exceeds its projection
    }

    const idx g = t.face_twin[static_cast<std::size_t>(f)];
    if (g == invalid_index) continue;
    // Twins: same node count, node k of f coincides with node k of g, identical areas.
    REQUIRE(m.face_node_offsets[f + 1] - m.face_node_offsets[f] == m.face_node_offsets[g + 1] - m.face_node_offsets[g]);
    for (idx k = 0; k < m.face_node_offsets[f + 1] - m.face_node_offsets[f]; ++k) {
      const auto kf = static_cast<std::size_t>(m.face_node_offsets[f] + k), kg = static_cast<std::size_t>(m.face_node_offsets[g] + k);
      REQUIRE(m.gridpoints[static_cast<std::size_t>(m.face_nodes[kf])] == m.gridpoints[static_cast<std::size_t>(m.face_nodes[kg])]);
      REQUIRE(m.face_node_area[kf] == m.face_node_area[kg]);
    }
    // Triangle k of f is triangle k of g with reversed orientation, at the same positions.
    REQUIRE(m.face_triangle_offsets[f + 1] - m.face_triangle_offsets[f] == m.face_triangle_offsets[g + 1] - m.face_triangle_offsets[g]);
    for (idx k = 0; k < m.face_triangle_offsets[f + 1] - m.face_triangle_offsets[f]; ++k) {
      const auto& tf = m.face_triangles[static_cast<std::size_t>(m.face_triangle_offsets[f] + k)];
      const auto& tg = m.face_triangles[static_cast<std::size_t>(m.face_triangle_offsets[g] + k)];
      const auto pos = [&](idx i) { return m.gridpoints[static_cast<std::size_t>(i)]; };
      // tg must equal reverse(tf) up to a cyclic shift.
      bool match = false;
      for (int s = 0; s < 3; ++s)
        match = match || (pos(tg[0]) == pos(tf[static_cast<std::size_t>(s)]) &&
                           pos(tg[1]) == pos(tf[static_cast<std::size_t>((s + 2) % 3)]) &&
                           pos(tg[2]) == pos(tf[static_cast<std::size_t>((s + 1) % 3)]));
      REQUIRE(match);
    }
  }
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The scratch root of this test binary run, removed when the binary exits.
struct scratch_root {
  fs::path path = fs::temp_directory_path() / ("tessera_test_zoning_io_" + std::to_string(io::detail::process_id()));
  ~scratch_root() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};
const scratch_root& scratch_base() {
  static const scratch_root root;
  return root;
}
fs::path scratch(const std::string& name) {
  const fs::path dir = scratch_base().path / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Numbers inside the <DataArray Name="name"> element of an ascii VTK XML file.
std::vector<double> vtk_array(const std::string& xml, const std::string& name) {
  const auto at = xml.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const auto begin = xml.find('>', at) + 1;
  const auto end = xml.find("</DataArray>", begin);
  std::istringstream in(xml.substr(begin, end - begin));
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}
/// Integer value of the first attribute `attribute="N"` in the file, -1 if absent.
long xml_attribute(const std::string& xml, const std::string& attribute) {
  const std::string key = attribute + "=\"";
  const auto at = xml.find(key);
  return at == std::string::npos ? -1 : std::stol(xml.substr(at + key.size()));
}

}  // namespace

// ============================================================================ zoning

TEST_CASE("zoning: unit cube as one block", "[zoning]") {
  const tessellation t = box_grid(1, 1, 1);
  const block_mesh m = geometry::zone_blocks(t);
  check_mesh_invariants(t, m);
  // 8 vertex copies + the centroid; 6 quads fan-split into 2 triangles each = 12 zones = 2V - 4.
  CHECK(m.gridpoint_count() == 9);
  CHECK(m.zone_count() == 12);
  CHECK(m.gridpoints[8].isApprox(vec3(0.5, 0.5, 0.5), 1e-15));
  for (idx g = 0; g < 8; ++g) CHECK(m.gridpoint_vertex[static_cast<std::size_t>(g)] == g);
  CHECK(m.gridpoint_vertex[8] == invalid_index);
  // Each quad face: 4 nodes; the two fan diagonal ends carry 2 triangles (area 1/3 each of 1/2).
  for (idx f = 0; f < 6; ++f) {
    REQUIRE(m.face_node_offsets[f + 1] - m.face_node_offsets[f] == 4);
    std::vector<double> a(m.face_node_area.begin() + m.face_node_offsets[f], m.face_node_area.begin() + m.face_node_offsets[f + 1]);
    std::sort(a.begin(), a.end());
    CHECK(a[0] == Approx(1.0 / 6));
    CHECK(a[1] == Approx(1.0 / 6));
    CHECK(a[2] == Approx(1.0 / 3));
    CHECK(a[3] == Approx(1.0 / 3));
  }
  const auto q = geometry::quality(m);
  CHECK(q.zones == 12);
  CHECK(q.mean_zones_per_block == 12.0);
  CHECK(q.min_zone_volume == Approx(1.0 / 12));  // each tet: base 1/2 x height 1/2 / 3
  CHECK(q.max_edge_length == Approx(std::sqrt(2.0)));
  // Tet (0,0,0),(1,0,0),(1,1,0),(0.5,0.5,0.5): the dihedral angle at the base diagonal is 45 deg,
  // the smallest one; the one along the centroid edge to (0,0,0) is 90 deg... minimum is 45.
  CHECK(q.min_dihedral_deg == Approx(45.0));
  CHECK(q.min_volume_ratio > 0.3);
  CHECK(q.min_volume_ratio <= 1.0);
}

TEST_CASE("zoning: quality metrics of a regular tetrahedron", "[zoning]") {
  // One-zone mesh by hand: the regular tet has all dihedral angles acos(1/3) and eta = 1.
  block_mesh m;
  m.gridpoints = {vec3(1, 1, 1), vec3(1, -1, -1), vec3(-1, 1, -1), vec3(-1, -1, 1)};
  m.zones = {{0, 1, 2, 3}};
  if (geometry::zone_volume(m, 0) < 0) m.zones = {{0, 2, 1, 3}};
  m.zone_block = {0};
  m.block_zone_offsets = {0, 1};
  m.block_gridpoint_offsets = {0, 4};
  const auto q = geometry::quality(m);
  CHECK(q.min_dihedral_deg == Approx(std::acos(1.0 / 3) * 180 / M_PI).epsilon(1e-12));
  CHECK(q.max_dihedral_deg == Approx(std::acos(1.0 / 3) * 180 / M_PI).epsilon(1e-12));
  CHECK(q.min_volume_ratio == Approx(1.0).epsilon(1e-12));
  CHECK(q.min_zone_volume == Approx(8.0 / 3).epsilon(1e-12));  // edge 2 sqrt 2: a^3 / (6 sqrt 2)
}

TEST_CASE("zoning: two blocks split by a slanted plane share a face exactly", "[zoning]") {
  const tessellation t = slanted_split();
  REQUIRE(t.shared_faces.size() == 1);
  CHECK(exact_cell_volume(t, 0) + exact_cell_volume(t, 1) == Approx(2.0).epsilon(1e-14));
  const block_mesh m = geometry::zone_blocks(t);
  check_mesh_invariants(t, m);
  CHECK(m.gridpoint_count() == 2 * 9);
  CHECK(m.zone_count() == 2 * 12);
  // The centroid of the lower block (a prism with a slanted top) is its volume centroid.
  vec3 c = vec3::Zero();
  double v = 0;
  for (idx z = m.block_zone_offsets[0]; z < m.block_zone_offsets[1]; ++z) {
    vec3 s = vec3::Zero();
    for (const idx g : m.zones[static_cast<std::size_t>(z)]) s += m.gridpoints[static_cast<std::size_t>(g)];
    c += geometry::zone_volume(m, z) * s / 4;
    v += geometry::zone_volume(m, z);
  }
  CHECK((c / v - m.gridpoints[8]).norm() < 1e-14);
}

TEST_CASE("zoning: 2x2x2 boxes, counts and pairing", "[zoning]") {
  const tessellation t = box_grid(2, 2, 2, vec3(0.068, 0.068, 0.6));
  REQUIRE(t.shared_faces.size() == 12);
  const block_mesh m = geometry::zone_blocks(t);
  check_mesh_invariants(t, m);
  CHECK(m.gridpoint_count() == 8 * 9);
  CHECK(m.zone_count() == 8 * 12);
  CHECK(m.face_nodes.size() == 48u * 4u);
}

TEST_CASE("zoning: refinement keeps volumes, twins and pairing", "[zoning]") {
  for (const double h : {0.45, 0.3, 0.2}) {
    for (const tessellation& t : {box_grid(2, 2, 2), slanted_split()}) {
      geometry::zoning_options opt;
      opt.target_edge_length = h;
      const block_mesh m = geometry::zone_blocks(t, opt);
      check_mesh_invariants(t, m);
      const auto q = geometry::quality(m);
      // Surface triangle edges <= h; radial edges <= h, so prism diagonals <= 2h.
      CHECK(q.max_edge_length <= 2 * h * (1 + 1e-12));
      for (const auto& tri : m.face_triangles)
        for (int i = 0; i < 3; ++i)
          CHECK((m.gridpoints[static_cast<std::size_t>(tri[static_cast<std::size_t>(i)])] -
                 m.gridpoints[static_cast<std::size_t>(tri[static_cast<std::size_t>((i + 1) % 3)])]).norm() <= h * (1 + 1e-12));
      // Measured: 0.034 (slanted split, h = 0.2) .. 0.09; the unrefined cones give 0.33.
      CHECK(q.min_volume_ratio > 0.02);
      CHECK(m.zone_count() > geometry::zone_blocks(t).zone_count());
      // Midpoint gridpoints on a shared polyhedron edge exist once per block touching it: the
      // face nodes of every face lie on the face's plane.
      for (idx f = 0; f < t.face_count(); ++f) {
        const auto loop = t.face(f);
        const vec3 x0 = t.vertices[static_cast<std::size_t>(loop[0])];
        const vec3 n = (t.vertices[static_cast<std::size_t>(loop[1])] - x0).cross(t.vertices[static_cast<std::size_t>(loop[2])] - x0).normalized();
        for (idx k = m.face_node_offsets[f]; k < m.face_node_offsets[f + 1]; ++k)
          CHECK(std::abs(n.dot(m.gridpoints[static_cast<std::size_t>(m.face_nodes[static_cast<std::size_t>(k)])] - x0)) < 1e-14);
      }
    }
  }
}

TEST_CASE("zoning: faces refined, interior coned (refine_interior = false)", "[zoning]") {
  for (const tessellation& t : {box_grid(2, 2, 2), slanted_split()}) {
    geometry::zoning_options layered, coned;
    layered.target_edge_length = coned.target_edge_length = 0.2;
    coned.refine_interior = false;
    const block_mesh m = geometry::zone_blocks(t, coned);
    const block_mesh l = geometry::zone_blocks(t, layered);
    check_mesh_invariants(t, m);
    // The faces are those of the layered zoning (same face nodes, so the same contact points) ...
    CHECK(m.face_nodes.size() == l.face_nodes.size());
    CHECK(m.face_triangles.size() == l.face_triangles.size());
    // ... and every surface triangle is one zone on the centroid: zones = face triangles, the
    // gridpoints the surface nodes plus one centroid per block.
    CHECK(m.zone_count() == static_cast<idx>(m.face_triangles.size()));
    CHECK(m.zone_count() < l.zone_count());
    std::size_t surface_nodes = 0;
    for (idx b = 0; b < t.cell_count(); ++b) {
      std::set<idx> nodes;
      for (idx f = t.first_face(b); f < t.end_face(b); ++f)
        for (idx k = m.face_node_offsets[f]; k < m.face_node_offsets[f + 1]; ++k)
          nodes.insert(m.face_nodes[static_cast<std::size_t>(k)]);
      surface_nodes += nodes.size();
    }
    CHECK(m.gridpoint_count() == static_cast<idx>(surface_nodes) + t.cell_count());
    CHECK(geometry::quality(m).min_zone_volume > 0);
  }
}

TEST_CASE("zoning: random Voronoi tessellation of the study's prism", "[zoning][voronoi]") {
  aabb prism;
  prism.lo = vec3::Zero();
  prism.hi = vec3(0.068, 0.068, 0.6);
  const tessellation t = geometry::random_voronoi(prism, 40, 7, {});
  REQUIRE(geometry::check(t).unmatched_faces == 0);
  const block_mesh m = geometry::zone_blocks(t);
  check_mesh_invariants(t, m);
  // Zones of a block = sum over faces of (n_f - 2); gridpoints = distinct vertices + 1.
  for (idx b = 0; b < t.cell_count(); ++b) {
    idx zones = 0;
    std::set<idx> vertices;
    for (idx f = t.first_face(b); f < t.end_face(b); ++f) {
      zones += static_cast<idx>(t.face(f).size()) - 2;
      vertices.insert(t.face(f).begin(), t.face(f).end());
    }
    CHECK(m.block_zone_offsets[b + 1] - m.block_zone_offsets[b] == zones);
    CHECK(m.block_gridpoint_offsets[b + 1] - m.block_gridpoint_offsets[b] == static_cast<idx>(vertices.size()) + 1);
    CHECK(zones == 2 * static_cast<idx>(vertices.size()) - 4);  // Euler, simple vertices
  }
  const auto q = geometry::quality(m);
  CHECK(q.min_zone_volume > 0);
  CHECK(q.min_dihedral_deg > 0);

  geometry::zoning_options opt;
  opt.target_edge_length = 0.02;
  const block_mesh r = geometry::zone_blocks(t, opt);
  check_mesh_invariants(t, r);
  CHECK(geometry::quality(r).max_edge_length <= 2 * 0.02 * (1 + 1e-12));
}

namespace {
/// Triangles of one face polygon with coordinates `x` and global ids `ids`, by min_angle_triangulation.
std::vector<std::array<idx, 3>> triangulate(const std::vector<vec3>& x, const std::vector<idx>& loop, double* angle = nullptr) {
  std::vector<std::array<idx, 3>> out;
  geometry::triangulation_workspace ws;
  const double a = geometry::min_angle_triangulation(x, loop, out, ws);
  if (angle != nullptr) *angle = a;
  return out;
}
/// The triangles as sorted id triples, sorted: the orientation-free identity of a triangulation.
std::vector<std::array<idx, 3>> canonical(std::vector<std::array<idx, 3>> tris) {
  for (auto& t : tris) std::sort(t.begin(), t.end());
  std::sort(tris.begin(), tris.end());
  return tris;
}
/// Checks n - 2 triangles, each CCW like the loop (normal along +z for a loop CCW in the xy plane),
/// whose areas sum to the polygon's, and the same triangles for the reversed loop and every rotation.
void check_polygon_triangulation(const std::vector<vec3>& x, std::vector<idx> loop) {
  const auto tris = triangulate(x, loop);
  REQUIRE(tris.size() == loop.size() - 2);
  double area = 0, polygon = 0;
  for (const auto& t : tris) {
    const vec3 n = (x[static_cast<std::size_t>(t[1])] - x[static_cast<std::size_t>(t[0])]).cross(x[static_cast<std::size_t>(t[2])] - x[static_cast<std::size_t>(t[0])]);
    CHECK(n.z() > 0);
    area += 0.5 * n.norm();
  }
  for (std::size_t i = 0; i < loop.size(); ++i)
    polygon += 0.5 * x[static_cast<std::size_t>(loop[i])].cross(x[static_cast<std::size_t>(loop[(i + 1) % loop.size()])]).z();
  CHECK(area == Approx(polygon).epsilon(1e-14));
  for (std::size_t r = 0; r < loop.size(); ++r) {
    std::rotate(loop.begin(), loop.begin() + 1, loop.end());
    CHECK(canonical(triangulate(x, loop)) == canonical(tris));
    std::vector<idx> reversed(loop.rbegin(), loop.rend());
    const auto twin = triangulate(x, reversed);
    CHECK(canonical(twin) == canonical(tris));
    for (const auto& t : twin) {
      const vec3 n = (x[static_cast<std::size_t>(t[1])] - x[static_cast<std::size_t>(t[0])]).cross(x[static_cast<std::size_t>(t[2])] - x[static_cast<std::size_t>(t[0])]);
      CHECK(n.z() < 0);  // the twin keeps its own (reversed) orientation
    }
  }
}
}  // namespace

TEST_CASE("triangulation: regular polygons and a thin quad get the max-min-angle triangles", "[zoning][triangulation]") {
  const double deg = M_PI / 180;
  for (const int n : {5, 6}) {
    std::vector<vec3> x;
    std::vector<idx> loop;
    for (int k = 0; k < n; ++k) {
      x.emplace_back(std::cos(2 * M_PI * k / n), std::sin(2 * M_PI * k / n), 0.3);
      loop.push_back(static_cast<idx>(k));
    }
    // Every triangulation of a regular n-gon has an ear (k-1, k, k+1) with base angles
    // 180/n deg (36 for the pentagon, 30 for the hexagon), and each reaches that bound.
    double angle = 0;
    triangulate(x, loop, &angle);
    CHECK(angle == Approx(180.0 / n * deg).epsilon(1e-12));
    check_polygon_triangulation(x, loop);
  }
  // Thin quad A(-1, 0), B(0, -0.1), C(1, 0), D(0, 0.1): the fan from A (diagonal AC) makes two
  // triangles with angle atan(0.1) = 5.7 deg at A and C; the diagonal BD gives 2 atan(0.1) = 11.4 deg.
  const std::vector<vec3> quad{vec3(-1, 0, 0), vec3(0, -0.1, 0), vec3(1, 0, 0), vec3(0, 0.1, 0)};
  double angle = 0;
  const auto tris = triangulate(quad, {0, 1, 2, 3}, &angle);
  CHECK(canonical(tris) == std::vector<std::array<idx, 3>>{{0, 1, 3}, {1, 2, 3}});
  CHECK(angle == Approx(2 * std::atan(0.1)).epsilon(1e-12));
  check_polygon_triangulation(quad, {0, 1, 2, 3});
  // A slightly non-convex (reflex at 1) quad: the only valid diagonal is the one from the reflex vertex.
  const std::vector<vec3> dart{vec3(0, 0, 0), vec3(1, 0.9, 0), vec3(2, 0, 0), vec3(1, 2, 0)};
  CHECK(canonical(triangulate(dart, {0, 1, 2, 3})) == std::vector<std::array<idx, 3>>{{0, 1, 3}, {1, 2, 3}});
  check_polygon_triangulation(dart, {0, 1, 2, 3});
}

namespace {
/// Conformity, closure, volume, boundary and short-edge checks of a regularized tessellation.
void check_regularized(const tessellation& t, const geometry::regularization_report& rep) {
  const auto report = geometry::check(t);
  CHECK(report.unmatched_faces == 0);
  CHECK(report.open_cells == 0);
  CHECK(report.volume_error_rel < 1e-12);
  for (idx f = 0; f < t.face_count(); ++f) {
    if (t.is_boundary_face(f)) {
      // boundary faces stay exactly in their box side
      const int side = geometry::boundary_side(t.face_neighbor[static_cast<std::size_t>(f)]);
      const real plane = side % 2 ? t.domain.hi[side / 2] : t.domain.lo[side / 2];
      for (const idx v : t.face(f)) REQUIRE(t.vertices[static_cast<std::size_t>(v)][side / 2] == plane);
    } else {
      REQUIRE(t.face_twin[static_cast<std::size_t>(f)] >= 0);
    }
    for (const idx v : t.face(f)) REQUIRE(t.domain.contains(t.vertices[static_cast<std::size_t>(v)]));
  }
  // the 8 box corners are still vertices
  for (int corner = 0; corner < 8; ++corner) {
    const vec3 c((corner & 1 ? t.domain.hi : t.domain.lo).x(), (corner & 2 ? t.domain.hi : t.domain.lo).y(),
                 (corner & 4 ? t.domain.hi : t.domain.lo).z());
    CHECK(std::count(t.vertices.begin(), t.vertices.end(), c) == 1);
  }
  // edges still shorter than the threshold: counted by the report, each one refused
  std::set<std::pair<idx, idx>> short_edges;
  for (idx f = 0; f < t.face_count(); ++f) {
    const auto loop = t.face(f);
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const idx a = loop[k], b = loop[(k + 1) % loop.size()];
      if ((t.vertices[static_cast<std::size_t>(a)] - t.vertices[static_cast<std::size_t>(b)]).norm() < rep.threshold)
        short_edges.emplace(std::min(a, b), std::max(a, b));
    }
  }
  CHECK(static_cast<idx>(short_edges.size()) == rep.short_edges_after);
  CHECK(rep.short_edges_after <= rep.refused_collapses);
  CHECK(rep.short_edges_after < rep.short_edges_before / 10);
  CHECK(rep.collapsed_edges > 0);
  CHECK(rep.refused_boundary + rep.refused_topology + rep.refused_geometry == rep.refused_collapses);
  CHECK(report.min_edge_length == Approx(rep.min_edge_after).epsilon(1e-12));
}
}  // namespace

TEST_CASE("regularize: 100 and 2000 random Voronoi cells stay conforming, closed and box-filling", "[zoning][regularize]") {
  aabb prism;
  prism.lo = vec3::Zero();
  prism.hi = vec3(0.068, 0.068, 0.6);
  tessellation t = geometry::random_voronoi(prism, 100, 1);
  const tessellation raw = t;
  const auto rep = geometry::regularize(t, geometry::study_regularization);
  check_regularized(t, rep);
  CHECK(rep.threshold == Approx(geometry::study_regularization * std::cbrt(prism.volume() / 100)).epsilon(1e-15));
  CHECK(t.cell_count() == 100);
  CHECK(t.vertex_count() == raw.vertex_count() - rep.collapsed_edges);
  CHECK(rep.min_edge_before < 0.01 * rep.threshold / geometry::study_regularization);  // raw Voronoi: 0.1 mm in 30 mm cells
  // Same result through tessellation_options (the hook in voronoi.hpp).
  geometry::tessellation_options options;
  options.min_edge_rel = geometry::study_regularization;
  const tessellation hooked = geometry::random_voronoi(prism, 100, 1, options);
  CHECK(hooked.vertices == t.vertices);
  CHECK(hooked.face_vertices == t.face_vertices);

  // Zoning: every invariant holds with the warped faces, and the slivers are (mostly) gone.
  const block_mesh m = geometry::zone_blocks(t);
  check_mesh_invariants(t, m, false);
  const auto before = geometry::quality(geometry::zone_blocks(raw));
  const auto after = geometry::quality(m);
  // Measured (seed 1): min dihedral 0.15 -> 0.8 deg, volume ratio < 0.1: 22 % -> 2.6 %.
  CHECK(after.min_dihedral_deg > 3 * before.min_dihedral_deg);
  CHECK(after.fraction_below_ratio_0_1 < 0.25 * before.fraction_below_ratio_0_1);

  aabb cube;
  cube.lo = vec3::Zero();
  cube.hi = vec3(1, 1, 1);
  tessellation big = geometry::random_voronoi(cube, 2000, 3);
  const auto rep_big = geometry::regularize(big, geometry::study_regularization);
  check_regularized(big, rep_big);
  CHECK(big.cell_count() == 2000);
  REQUIRE_NOTHROW(geometry::zone_blocks(big));  // every zone positive (the star-shape rule)
}

TEST_CASE("regularize: threshold 0 changes nothing, bad thresholds are rejected", "[zoning][regularize]") {
  aabb cube;
  cube.lo = vec3::Zero();
  cube.hi = vec3(1, 1, 1);
  tessellation t = geometry::random_voronoi(cube, 30, 2);
  const tessellation raw = t;
  const auto rep = geometry::regularize(t, 0.0);
  CHECK(rep.collapsed_edges == 0);
  CHECK(t.vertices == raw.vertices);
  CHECK(t.face_vertices == raw.face_vertices);
  CHECK(t.face_twin == raw.face_twin);
  for (const double bad : {-0.1, 0.6, std::nan("")}) {
    REQUIRE_THROWS_AS(geometry::regularize(t, bad), invalid_input);
    REQUIRE_THROWS_WITH(geometry::regularize(t, bad), Catch::Contains("min_edge_rel"));
    geometry::tessellation_options options;
    options.min_edge_rel = bad;
    REQUIRE_THROWS_AS(geometry::random_voronoi(cube, 30, 2, options), invalid_input);
  }
}

TEST_CASE("zoning: a block turned inside out is rejected naming the block", "[zoning]") {
  tessellation t = box_grid(2, 1, 1);
  // Reverse every face loop of block 1: its faces now point inwards.
  for (idx f = t.first_face(1); f < t.end_face(1); ++f)
    std::reverse(t.face_vertices.begin() + t.face_offsets[f], t.face_vertices.begin() + t.face_offsets[f + 1]);
  REQUIRE_THROWS_AS(geometry::zone_blocks(t), geometry_error);
  REQUIRE_THROWS_WITH(geometry::zone_blocks(t), Catch::Contains("block 1"));
  geometry::zoning_options bad;
  bad.target_edge_length = -1;
  REQUIRE_THROWS_AS(geometry::zone_blocks(box_grid(1, 1, 1), bad), invalid_input);
}

// ============================================================================ I/O

TEST_CASE("io: atomic file commits by rename and leaves no temporary", "[io]") {
  const fs::path dir = scratch("atomic");
  const fs::path target = dir / "a.txt";
  {
    io::atomic_ofstream out(target);
    out << "hello " << 42;
    CHECK(fs::exists(out.temporary()));
    CHECK_FALSE(fs::exists(target));
    out.commit();
  }
  CHECK(read_text(target) == "hello 42");
  {
    io::atomic_ofstream out(target);
    out << "half-written";
    // destroyed without commit(): the old content stays, the temporary is removed
  }
  CHECK(read_text(target) == "hello 42");
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().filename() == "a.txt");
}

TEST_CASE("io: writing into an unusable directory throws io_error naming the path", "[io]") {
  const fs::path dir = scratch("unwritable");
  // A regular file used as a directory fails even for root (ENOTDIR), unlike permission bits.
  const fs::path blocker = dir / "not_a_dir";
  io::write_file_atomically(blocker, "x");
  const fs::path target = blocker / "summary.json";
  REQUIRE_THROWS_AS(io::write_file_atomically(target, "{}"), io_error);
  REQUIRE_THROWS_WITH(io::write_file_atomically(target, "{}"), Catch::Contains(target.string()));
  REQUIRE_THROWS_WITH(io::summary_json{}.write(target), Catch::Contains(target.string()) && Catch::Contains("Not a directory"));
  REQUIRE_THROWS_AS(io::ensure_directory(blocker / "sub"), io_error);
  REQUIRE_THROWS_WITH(io::ensure_directory(blocker / "sub"), Catch::Contains((blocker / "sub").string()));
  io::ensure_directory(dir / "new" / "nested");
  CHECK(fs::is_directory(dir / "new" / "nested"));
}

TEST_CASE("io: summary_json is one flat ordered object", "[io]") {
  io::summary_json s;
  s.set("blocks", 100).set("volume_error_rel", 2.5e-16).set("quick", true).set("name", "tie \"A\"\n");
  s.set("curve", std::vector<double>{1.0, 0.5, std::nan("")}).set("laws", std::vector<std::string>{"linear", "power"});
  s.set("inf", std::numeric_limits<double>::infinity()).set("steps", std::int64_t{1234567890123});
  s.set("blocks", 250);  // replaces in place
  const std::string text = s.str();
  CHECK(text ==
        "{\n"
        "  \"blocks\": 250,\n"
        "  \"volume_error_rel\": 2.5000000000000002e-16,\n"
        "  \"quick\": true,\n"
        "  \"name\": \"tie \\\"A\\\"\\n\",\n"
        "  \"curve\": [1, 0.5, null],\n"
        "  \"laws\": [\"linear\", \"power\"],\n"
        "  \"inf\": null,\n"
        "  \"steps\": 1234567890123\n"
        "}\n");
  const fs::path p = scratch("json") / "summary.json";
  s.write(p);
  CHECK(read_text(p) == text);
  // 17 significant digits round-trip a double exactly.
  const double x = 0.1 + 0.2;
  CHECK(std::stod(io::summary_json::number(x)) == x);
}

TEST_CASE("io: nested summary_json reads back through read_json exactly", "[io]") {
  io::summary_json recipe, a, b, doc;
  recipe.set("softening", "power").set("rigid", false);
  a.set("blocks", 100).set("scale", 0.83042188182091758).set("seeds", std::vector<double>{1, 2});
  b.set("blocks", 250).set("scale", 1e-300).set("note", "tab\there \"quoted\"");
  doc.set("format", "f").set("recipe", recipe).set("entries", std::vector<io::summary_json>{a, b});
  doc.set("empty", std::vector<io::summary_json>{});
  const fs::path p = scratch("json_nested") / "doc.json";
  doc.write(p);
  const io::json_value v = io::read_json(p);
  CHECK(v.at("format").string() == "f");
  CHECK(v.at("recipe").at("softening").string() == "power");
  CHECK_FALSE(v.at("recipe").at("rigid").boolean());
  const auto& e = v.at("entries").items();
  REQUIRE(e.size() == 2);
  CHECK(e[0].at("blocks").integer(1, 1000) == 100);
  CHECK(e[0].at("scale").number() == 0.83042188182091758);  // 17 digits: the same double
  CHECK(e[0].at("seeds").items()[1].number() == 2);
  CHECK(e[1].at("scale").number() == 1e-300);
  CHECK(e[1].at("note").string() == "tab\there \"quoted\"");
  CHECK(v.at("empty").items().empty());
  // Errors name the key path, or the file, line and column.
  const auto message = [](auto&& f) {
    try {
      f();
    } catch (const io_error& x) {
      return std::string(x.what());
    }
    return std::string("no error");
  };
  CHECK(message([&] { (void)e[0].at("missing"); }).find("doc.json: entries[0]: missing key \"missing\"") !=
        std::string::npos);
  CHECK(message([&] { (void)e[0].at("blocks").string(); }).find("entries[0].blocks must be a string, got a number") !=
        std::string::npos);
  CHECK(message([&] { (void)e[0].at("scale").integer(0, 10); }).find("must be a whole number") != std::string::npos);
  CHECK(message([] { (void)io::parse_json("{\"a\": 1,\n \"a\": 2}", "x.json"); }) == "x.json:2:2: duplicate key \"a\"");
  CHECK(message([] { (void)io::parse_json("[1, 2] 3", "x.json"); }) == "x.json:1:8: unexpected text after the JSON value");
  CHECK(message([] { (void)io::parse_json("{\"a\": [1, 2", "x.json"); }).find("expected ',' or ']'") != std::string::npos);
  CHECK(message([] { (void)io::parse_json("01", "x.json"); }).find("unexpected text") != std::string::npos);
  CHECK(message([] { (void)io::parse_json("1e999", "x.json"); }) == "x.json:1:1: number out of range");
  CHECK(message([] { (void)io::parse_json("-", "x.json"); }).find("malformed number") != std::string::npos);
  CHECK(message([] { (void)io::parse_json("\"a\\u00e9\"", "x.json"); }).find("beyond ASCII") != std::string::npos);
  CHECK(message([] { (void)io::parse_json(std::string(100, '[') + std::string(100, ']'), "x.json"); })
            .find("nesting deeper than 64") != std::string::npos);
  CHECK(message([] { (void)io::parse_json("", "x.json"); }).find("unexpected end of file") != std::string::npos);
  CHECK(message([] { (void)io::read_json("/nonexistent/x.json"); }).find("cannot read '/nonexistent/x.json'") !=
        std::string::npos);
  CHECK(io::parse_json(" [true, null, -0.5e-3, \"\\u0041\\n\"] ", "x").items()[3].string() == "A\n");
  CHECK(io::parse_json("[-0.5e-3]", "x").items()[0].number() == -0.5e-3);
}

TEST_CASE("io: csv writer has a header row and full precision", "[io]") {
  const fs::path p = scratch("csv") / "curve.csv";
  io::csv_writer csv(p, {"u_m", "F_N"});
  const double u = 1.0 / 3.0;
  csv.row(u, 10);
  csv.row(2e-300, -std::numeric_limits<double>::infinity());
  REQUIRE_THROWS_AS(csv.row(1.0), invalid_input);
  CHECK_FALSE(fs::exists(p));
  csv.commit();
  std::ifstream in(p);
  std::string header, row1, row2, extra;
  std::getline(in, header);
  std::getline(in, row1);
  std::getline(in, row2);
  CHECK(header == "u_m,F_N");
  CHECK(std::stod(row1.substr(0, row1.find(','))) == u);
  CHECK(row1.substr(row1.find(',') + 1) == "10");
  CHECK(row2 == "2.0000000000000001e-300,-inf");
  CHECK_FALSE(std::getline(in, extra));
}

TEST_CASE("io: vtu of blocks and zones parses back", "[io][vtk]") {
  const fs::path dir = scratch("vtk");
  const tessellation t = slanted_split();
  io::vtk::write_blocks_vtu(dir / "blocks.vtu", t);
  const std::string blocks = read_text(dir / "blocks.vtu");
  CHECK(xml_attribute(blocks, "NumberOfPoints") == 12);
  CHECK(xml_attribute(blocks, "NumberOfCells") == 2);
  const auto types = vtk_array(blocks, "types");
  CHECK(types == std::vector<double>{42, 42});
  const auto volume = vtk_array(blocks, "volume");
  REQUIRE(volume.size() == 2);
  CHECK(volume[0] == Approx(exact_cell_volume(t, 0)).epsilon(1e-15));
  CHECK(volume[0] + volume[1] == Approx(2.0).epsilon(1e-15));
  // faces stream: per cell [n_faces, (n, ids...) x n_faces] = 1 + 6 * 5 entries; faceoffsets end there.
  CHECK(vtk_array(blocks, "faces").size() == 2u * 31u);
  CHECK(vtk_array(blocks, "faceoffsets") == std::vector<double>{31, 62});
  CHECK(vtk_array(blocks, "connectivity").size() == 16u);  // 8 distinct points per cell

  const block_mesh m = geometry::zone_blocks(t);
  soa3 u(m.gridpoint_count(), 3);
  for (idx g = 0; g < m.gridpoint_count(); ++g) u.row(g) = 1e-3 * m.gridpoints[static_cast<std::size_t>(g)].transpose();
  std::vector<io::vtk::sym_tensor> stress(static_cast<std::size_t>(m.zone_count()), io::vtk::sym_tensor{1e6, 2e6, 3e6, 4, 5, 6});
  io::vtk::write_zones_vtu(dir / "zones.vtu", m, {&u, stress});
  const std::string zones = read_text(dir / "zones.vtu");
  CHECK(xml_attribute(zones, "NumberOfPoints") == m.gridpoint_count());
  CHECK(xml_attribute(zones, "NumberOfCells") == m.zone_count());
  const auto disp = vtk_array(zones, "displacement");
  REQUIRE(disp.size() == 3u * static_cast<std::size_t>(m.gridpoint_count()));
  CHECK(disp[3 * 8 + 2] == 1e-3 * m.gridpoints[8].z());  // exact: 17 digits
  const auto s = vtk_array(zones, "stress");
  REQUIRE(s.size() == 6u * static_cast<std::size_t>(m.zone_count()));
  CHECK(s[6 + 2] == 3e6);
  const auto pts = vtk_array(zones, "Points");
  REQUIRE(pts.size() == 3u * static_cast<std::size_t>(m.gridpoint_count()));
  CHECK(pts[3 * 5 + 0] == m.gridpoints[5].x());
  CHECK(vtk_array(zones, "offsets").back() == 4.0 * m.zone_count());
  CHECK(zones.find("NumberOfComponents=\"6\"") != std::string::npos);

  // A wrongly sized array is reported, and no file is left behind.
  io::vtk::unstructured_grid bad;
  bad.add_point(vec3::Zero());
  bad.add_cell(io::vtk::cell_type::vertex, {0});
  const std::vector<double> two{1, 2};
  bad.cell_data.add_scalar("x", std::span<const double>(two));
  REQUIRE_THROWS_WITH(bad.write(dir / "bad.vtu"), Catch::Contains("'x'") && Catch::Contains("expected 1"));
  CHECK_FALSE(fs::exists(dir / "bad.vtu"));
}

TEST_CASE("io: binary vtu encodes the same numbers as ascii", "[io][vtk]") {
  const fs::path dir = scratch("vtk_binary");
  io::vtk::unstructured_grid g;
  g.set_points({vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)});
  g.add_cell(io::vtk::cell_type::triangle, {0, 1, 2});
  g.write(dir / "tri.vtu", io::vtk::format::binary);
  const std::string text = read_text(dir / "tri.vtu");
  CHECK(text.find("format=\"binary\"") != std::string::npos);
  CHECK(text.find("header_type=\"UInt64\"") != std::string::npos);
  // types: header = 1 byte count (UInt64 1) + one UInt8 5 -> 9 bytes -> base64 "AQAAAAAAAAAF"
  CHECK(text.find("AQAAAAAAAAAF") != std::string::npos);
}

TEST_CASE("io: vtp polydata and pvd collection", "[io][vtk]") {
  const fs::path dir = scratch("vtp");
  io::vtk::poly_data bars;
  for (int i = 0; i < 4; ++i) bars.add_point(vec3(0, 0, 0.1 * i));
  const std::vector<idx> chain{0, 1, 2, 3};
  bars.add_line(chain);
  bars.add_vertex(0);
  const std::vector<double> force{1.0, 2.0};  // cell order: the vertex, then the line
  bars.cell_data.add_scalar("axial_force", std::span<const double>(force));
  const std::vector<double> slip{0, 1e-5, 2e-5, 3e-5};
  bars.point_data.add_scalar("slip", std::span<const double>(slip));
  bars.write(dir / "bars_0000.vtp");
  const std::string text = read_text(dir / "bars_0000.vtp");
  CHECK(xml_attribute(text, "NumberOfPoints") == 4);
  CHECK(xml_attribute(text, "NumberOfLines") == 1);
  CHECK(xml_attribute(text, "NumberOfVerts") == 1);
  CHECK(vtk_array(text, "slip")[3] == 3e-5);
  CHECK(text.find("<Lines>") != std::string::npos);

  io::vtk::pvd_collection series;
  series.add(0.0, dir / "bars_0000.vtp");
  series.add(0.5, "bars_0001.vtp");
  series.write(dir / "bars.pvd");
  const std::string pvd = read_text(dir / "bars.pvd");
  CHECK(pvd.find("timestep=\"0\" group=\"\" part=\"0\" file=\"bars_0000.vtp\"") != std::string::npos);
  CHECK(pvd.find("timestep=\"0.5\"") != std::string::npos);
}

TEST_CASE("io: gnuplot plot never fails the run", "[io][plot]") {
  const fs::path dir = scratch("plot");
  io::write_csv(dir / "model.csv", {"u", "F"}, {{0, 1, 2}, {0, 1, 4}});
  io::write_csv(dir / "ref.csv", {"u", "F"}, {{0, 2}, {0, 4}});
  io::plot_spec spec{"test", "u (mm)", "F (kN)", {}, 640, 480};
  spec.series.push_back({dir / "model.csv", "u", "F", "model", "lines lw 2", 1e3, 1e-3});
  spec.series.push_back({dir / "ref.csv", "u", "F", "reference", "lines dt 2", 1e3, 1e-3});
  spec.series.push_back({dir / "ref.csv", "u", "missing", "bad column", "lines", 1, 1});
  spec.preamble = {"set size ratio -1"};
  spec.variable_sizes.push_back({0, "F", 2.0});  // point size from column F (3rd), times 2
  const bool drawn = io::plot_png(dir / "curve.png", spec);
  CHECK(fs::exists(dir / "curve.gp"));
  CHECK(read_text(dir / "curve.gp").find("skip 1 using ($1*(1000)):($2*(0.001)):($2*(2))") != std::string::npos);
  CHECK(read_text(dir / "curve.gp").find("\nset size ratio -1\n") != std::string::npos);
  if (io::detail::gnuplot_available()) {
    CHECK(drawn);
    CHECK(fs::file_size(dir / "curve.png") > 1000);
  } else {
    CHECK_FALSE(drawn);
  }
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().string().find(".tmp.") == std::string::npos);
  CHECK_FALSE(io::plot_png(dir / "nothing.png", io::plot_spec{}));
}

// ============================================================================ CLI

namespace {
struct driver_options {
  cli::standard_options std_opts;
  int blocks = 100;
  double rate = 5e-3;
  std::string law = "power";
  std::array<double, 3> size{0.068, 0.068, 0.6};
  bool verbose = false;
};
cli::parser make_parser(driver_options& o) {
  cli::parser p("tessellate", "Random Voronoi tessellation.");
  p.add_standard(o.std_opts);
  p.option("--blocks", o.blocks, "number of blocks");
  p.option("--rate", o.rate, "loading rate (m/s)", "V");
  p.option("--law", o.law, "softening law", "NAME");
  p.option("--size", o.size, "box edge lengths (m)", {"LX", "LY", "LZ"});
  p.flag("--verbose", o.verbose, "more output");
  return p;
}
bool parse(cli::parser& p, std::vector<const char*> args) {
  args.insert(args.begin(), "prog");
  return p.parse(static_cast<int>(args.size()), args.data());
}
}  // namespace

TEST_CASE("cli: defaults and parsing", "[cli]") {
  driver_options o;
  auto p = make_parser(o);
  CHECK(parse(p, {}));
  CHECK(o.std_opts.out == "results/tessellate");
  CHECK_FALSE(o.std_opts.quick);
  CHECK(o.std_opts.seed == 1u);
  CHECK(o.blocks == 100);

  CHECK(parse(p, {"--blocks", "250", "--quick", "--size", "0.1", "0.2", "0.3", "--seed=7", "--rate", "1e-3", "--out",
                  "/tmp/x", "--law", "linear", "--verbose", "--threads", "2"}));
  CHECK(o.blocks == 250);
  CHECK(o.std_opts.quick);
  CHECK(o.size == std::array<double, 3>{0.1, 0.2, 0.3});
  CHECK(o.std_opts.seed == 7u);
  CHECK(o.rate == 1e-3);
  CHECK(o.std_opts.out == "/tmp/x");
  CHECK(o.law == "linear");
  CHECK(o.verbose);
  CHECK(o.std_opts.threads == 2);
  CHECK_FALSE(parse(p, {"--blocks", "3", "--help"}));
}

TEST_CASE("cli: errors name the flag and the value", "[cli]") {
  driver_options o;
  auto p = make_parser(o);
  REQUIRE_THROWS_WITH(parse(p, {"--blocs", "3"}), Catch::Contains("unknown option '--blocs'"));
  REQUIRE_THROWS_WITH(parse(p, {"--blocks", "ten"}), Catch::Contains("--blocks") && Catch::Contains("'ten'"));
  REQUIRE_THROWS_WITH(parse(p, {"--blocks", "3.5"}), Catch::Contains("'3.5'"));
  REQUIRE_THROWS_WITH(parse(p, {"--seed", "-4"}), Catch::Contains("--seed") && Catch::Contains("'-4'"));
  REQUIRE_THROWS_WITH(parse(p, {"--rate", "1e-3x"}), Catch::Contains("'1e-3x'"));
  REQUIRE_THROWS_WITH(parse(p, {"--size", "1", "2"}), Catch::Contains("--size: missing value"));
  REQUIRE_THROWS_WITH(parse(p, {"--quick=1"}), Catch::Contains("--quick takes no value"));
  REQUIRE_THROWS_AS(parse(p, {"--blocks", "99999999999"}), cli::usage_error);
}

TEST_CASE("cli: split_list keeps the order and refuses empty items and repeats", "[cli]") {
  CHECK(cli::split_list("100", "x") == std::vector<std::string>{"100"});
  CHECK(cli::split_list("xi,cbond,rate", "x") == std::vector<std::string>{"xi", "cbond", "rate"});
  for (const char* bad : {"", ",", "a,", ",a", "a,,b"})
    REQUIRE_THROWS_WITH(cli::split_list(bad, "calibrate: --blocks"),
                        Catch::Contains("calibrate: --blocks '" + std::string(bad) + "'") &&
                            Catch::Contains("without empty items"));
  REQUIRE_THROWS_WITH(cli::split_list("250,500,250", "--blocks"), Catch::Contains("lists '250' twice"));
  REQUIRE_THROWS_AS(cli::split_list("a,a", "--blocks"), tessera::invalid_input);
}

TEST_CASE("cli: strict syntax, finite reals, ranges, known words, non-empty --out, bounded --threads", "[cli]") {
  driver_options o;
  auto p = make_parser(o);
  // hexadecimal integers and hex floats, white space, non-finite reals, 1e6 for an integer
  REQUIRE_THROWS_WITH(parse(p, {"--blocks", "0x10"}), Catch::Contains("--blocks") && Catch::Contains("'0x10'"));
  REQUIRE_THROWS_WITH(parse(p, {"--rate", "0x1p3"}), Catch::Contains("--rate") && Catch::Contains("'0x1p3'"));
  REQUIRE_THROWS_WITH(parse(p, {"--blocks", " 5"}), Catch::Contains("' 5'"));
  REQUIRE_THROWS_WITH(parse(p, {"--blocks", "1e6"}), Catch::Contains("'1e6'"));
  REQUIRE_THROWS_WITH(parse(p, {"--rate", "nan"}), Catch::Contains("--rate") && Catch::Contains("'nan'"));
  REQUIRE_THROWS_WITH(parse(p, {"--rate", "inf"}), Catch::Contains("'inf'"));
  REQUIRE_THROWS_WITH(parse(p, {"--rate", "-inf"}), Catch::Contains("'-inf'"));
  REQUIRE_THROWS_WITH(parse(p, {"--size", "1", "nan", "1"}), Catch::Contains("--size") && Catch::Contains("'nan'"));
  // --threads in [0, max_threads]; --out must not be empty
  REQUIRE_THROWS_WITH(parse(p, {"--threads", "1000"}),
                      Catch::Contains("--threads: value '1000' must be <= 256"));
  REQUIRE_THROWS_WITH(parse(p, {"--threads", "-1"}), Catch::Contains("--threads: value '-1' must be >= 0"));
  CHECK(parse(p, {"--threads", "256"}));
  REQUIRE_THROWS_WITH(parse(p, {"--out", ""}), Catch::Contains("--out: value '' must be not empty"));
  // ranges, listed numbers and words declared where the option is registered; a refused value
  // leaves the target unchanged only if checked before assignment, so the driver must not run
  double dt = 1e-6;
  int blocks = 100;
  std::string law = "power";
  bool verbose = false;
  cli::parser q("prog", "");
  q.option("--dt", dt, "time step (s)", "S").greater_than(0).at_most(1e-3);
  q.option("--blocks", blocks, "blocks", "N").one_of_numbers({100, 250});
  q.option("--law", law, "softening", "NAME").one_of({"power", "linear"});
  q.flag("--verbose", verbose, "more output");
  REQUIRE_THROWS_WITH(parse(q, {"--dt", "1"}), Catch::Contains("--dt: value '1' must be <= 0.001"));
  REQUIRE_THROWS_WITH(parse(q, {"--dt", "0"}), Catch::Contains("--dt: value '0' must be > 0"));
  REQUIRE_THROWS_WITH(parse(q, {"--blocks", "123"}), Catch::Contains("--blocks: value '123' must be one of 100, 250"));
  REQUIRE_THROWS_WITH(parse(q, {"--law", "foo"}), Catch::Contains("--law: invalid value 'foo' (expected power or linear)"));
  CHECK(parse(q, {"--dt", "2e-6", "--blocks", "250", "--law", "linear"}));
  CHECK(dt == 2e-6);
  CHECK(blocks == 250);
  CHECK(law == "linear");
  CHECK_THAT(q.usage(), Catch::Contains("[> 0] [<= 0.001]") && Catch::Contains("(power|linear)"));
  // given(): what --quick may change
  CHECK(q.given("--dt"));
  CHECK_FALSE(q.given("--verbose"));
}

TEST_CASE("cli: --help lists every option with its default", "[cli]") {
  driver_options o;
  const auto p = make_parser(o);
  const std::string u = p.usage();
  for (const char* name : {"--out DIR", "--quick", "--seed N", "--threads N", "--blocks N", "--rate V", "--law NAME",
                           "--size LX LY LZ", "--verbose", "--help"})
    CHECK(u.find(name) != std::string::npos);
  CHECK(u.find("[default: results/tessellate]") != std::string::npos);
  CHECK(u.find("[default: 0.068 0.068 0.6]") != std::string::npos);
  CHECK(u.find("[default: 100]") != std::string::npos);
}
