// Tests for the mechanics core: zones, deformable blocks, integrator, time step, boundary
// conditions, energy balance, solver composition (see tests/CMakeLists.txt).
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "tessera/blocks.hpp"
#include "tessera/geometry/zoning.hpp"

using namespace tessera;
// <strings.h> declares a global index(); the tests spell tessera's handle type as idx.
using idx = tessera::index;

namespace {

/// One box [lo, hi] as a single-cell tessellation (faces CCW seen from outside).
geometry::tessellation box_tessellation(const vec3& lo, const vec3& hi) {
  geometry::tessellation t;
  t.domain.expand(lo);
  t.domain.expand(hi);
  for (int k = 0; k < 8; ++k)
    t.vertices.emplace_back((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (int f = 0; f < 6; ++f) {
    for (int k = 0; k < 4; ++k) t.face_vertices.push_back(faces[f][k]);
    t.face_offsets.push_back(static_cast<idx>(t.face_vertices.size()));
    t.face_cell.push_back(0);
    t.face_neighbor.push_back(geometry::boundary_tag(f));
    t.face_twin.push_back(invalid_index);
  }
  t.cell_face_offsets.push_back(6);
  return t;
}

/// Unit cube split into the 6 tetrahedra of the Kuhn (Freudenthal) triangulation: every
/// gridpoint is a corner, no interior node.
geometry::block_mesh kuhn_cube(real edge) {
  geometry::block_mesh m;
  for (int k = 0; k < 8; ++k) {
    m.gridpoints.emplace_back(edge * (k & 1), edge * ((k >> 1) & 1), edge * ((k >> 2) & 1));
    m.gridpoint_block.push_back(0);
    m.gridpoint_vertex.push_back(k);
  }
  m.block_gridpoint_offsets.push_back(8);
  // Paths 0 -> 7 through the cube's edges, one per permutation of the axes.
  const int axes[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& p : axes) {
    std::array<idx, 4> z{};
    int id = 0;
    z[0] = 0;
    for (int s = 0; s < 3; ++s) {
      id |= 1 << p[s];
      z[static_cast<std::size_t>(s + 1)] = id;
    }
    const vec3 a = m.gridpoints[static_cast<std::size_t>(z[0])], b = m.gridpoints[static_cast<std::size_t>(z[1])],
               c = m.gridpoints[static_cast<std::size_t>(z[2])], d = m.gridpoints[static_cast<std::size_t>(z[3])];
    if ((b - a).cross(c - a).dot(d - a) < 0) std::swap(z[1], z[2]);
    m.zones.push_back(z);
    m.zone_block.push_back(0);
  }
  m.block_zone_offsets.push_back(6);
  return m;
}

const zones::linear_elastic_tet::params concrete_block{280e9, 0.2, 2400};

/// Imposes u = (Q (1 + E) - 1) X on every gridpoint.
void impose(node_set& gp, const mat3& q, const mat3& strain) {
  const mat3 f = q * (mat3::Identity() + strain);
  for (idx i = 0; i < gp.size(); ++i) {
    const vec3 x = gp.reference.row(i).transpose();
    gp.displacement.row(i) = (f * x - x).transpose();
  }
}

voigt6 hooke(const zones::linear_elastic_tet::params& p, const mat3& e) {
  voigt6 v;
  v << e(0, 0), e(1, 1), e(2, 2), 2 * e(1, 2), 2 * e(2, 0), 2 * e(0, 1);
  return zones::linear_elastic_tet::stress(p, v);
}

mat3 from_voigt(const voigt6& s) {
  mat3 m;
  m << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
  return m;
}

mat3 skew_rotation(real degrees, vec3 axis) {
  return Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis.normalized()).toRotationMatrix();
}

}  // namespace

static_assert(zones::ZoneModel<zones::linear_elastic_tet>);
static_assert(blocks::BlockModel<blocks::deformable<zones::linear_elastic_tet>>);

TEST_CASE("linear_elastic_tet validates its parameters", "[mechanics][zones]") {
  using z = zones::linear_elastic_tet;
  CHECK_NOTHROW(z::validate(concrete_block));
  CHECK_THROWS_AS(z::validate({-1, 0.2, 2400}), invalid_input);
  CHECK_THROWS_AS(z::validate({1e9, 0.5, 2400}), invalid_input);
  CHECK_THROWS_AS(z::validate({1e9, -1.0, 2400}), invalid_input);
  CHECK_THROWS_AS(z::validate({1e9, 0.2, 0}), invalid_input);
  CHECK_THROWS_WITH(z::validate({1e9, 0.7, 2400}), Catch::Contains("0.7"));
}

TEST_CASE("patch test: uniform strain gives Hooke's stress and interior equilibrium", "[mechanics][zones]") {
  mat3 e;
  e << 1.0e-4, 0.3e-4, -0.2e-4, 0.3e-4, -0.5e-4, 0.7e-4, -0.2e-4, 0.7e-4, 2.0e-4;
  const voigt6 expected = hooke(concrete_block, e);
  const real ref = expected.cwiseAbs().maxCoeff();

  SECTION("Kuhn cube (6 zones, all gridpoints on the surface)") {
    const auto mesh = kuhn_cube(0.1);
    blocks::deformable<zones::linear_elastic_tet> b;
    node_set gp;
    b.build(geometry::tessellation{}, mesh, concrete_block, gp);
    REQUIRE(b.zone_count() == 6);
    CHECK(gp.mass.sum() == Approx(2400 * 1e-3).epsilon(1e-12));
    impose(gp, mat3::Identity(), e);
    b.accumulate_forces(gp);
    for (idx z = 0; z < b.zone_count(); ++z)
      CHECK((b.zone_stress().row(z).transpose() - expected).cwiseAbs().maxCoeff() <= 1e-10 * ref);
    // Boundary nodal forces are the consistent nodal share of the traction: their resultant is zero.
    CHECK(gp.force.colwise().sum().cwiseAbs().maxCoeff() <= 1e-10 * ref * 0.01);
  }
  SECTION("zoned box cell with an interior centroid gridpoint") {
    const auto tess = box_tessellation(vec3(0, 0, 0), vec3(0.068, 0.068, 0.1));
    const auto mesh = geometry::zone_blocks(tess, {0.03});
    blocks::deformable<zones::linear_elastic_tet> b;
    node_set gp;
    b.build(tess, mesh, concrete_block, gp);
    impose(gp, mat3::Identity(), e);
    b.accumulate_forces(gp);
    for (idx z = 0; z < b.zone_count(); ++z)
      CHECK((b.zone_stress().row(z).transpose() - expected).cwiseAbs().maxCoeff() <= 1e-10 * ref);
    // Interior gridpoints (not on the box surface) are in equilibrium.
    const real face_force = ref * 0.068 * 0.068;
    int interior = 0;
    for (idx i = 0; i < gp.size(); ++i) {
      const vec3 x = gp.reference.row(i).transpose();
      const bool on_surface = (x.array() < 1e-12).any() || std::abs(x.x() - 0.068) < 1e-12 ||
                              std::abs(x.y() - 0.068) < 1e-12 || std::abs(x.z() - 0.1) < 1e-12;
      if (on_surface) continue;
      ++interior;
      CHECK(gp.force.row(i).cwiseAbs().maxCoeff() <= 1e-10 * face_force);
    }
    CHECK(interior >= 1);
    // Elastic energy = 1/2 sigma : eps V.
    const real energy = 0.5 * (from_voigt(expected).cwiseProduct(e)).sum() * 0.068 * 0.068 * 0.1;
    CHECK(b.stored_energy(gp) == Approx(energy).epsilon(1e-10));
  }
}

TEST_CASE("co-rotational zones carry no stress under rigid rotation", "[mechanics][zones]") {
  const auto tess = box_tessellation(vec3(0, 0, 0), vec3(0.068, 0.068, 0.1));
  const auto mesh = geometry::zone_blocks(tess, {0.03});
  blocks::deformable<zones::linear_elastic_tet> b;
  node_set gp;
  b.build(tess, mesh, concrete_block, gp);
  const real reference_stress = 1e-3 * concrete_block.young;
  for (const mat3& q : {skew_rotation(90, vec3::UnitZ()), skew_rotation(37, vec3(1, 2, -0.5))}) {
    impose(gp, q, mat3::Zero());
    b.accumulate_forces(gp);
    CHECK(b.zone_stress().cwiseAbs().maxCoeff() <= 1e-9 * reference_stress);
    CHECK(gp.force.cwiseAbs().maxCoeff() <= 1e-9 * reference_stress * 0.068 * 0.068);
    CHECK(b.stored_energy(gp) <= 1e-18);
    gp.force.setZero();
    // Rotation + strain: the global stress is the rotated Hooke stress Q sigma(E) Q^T.
    mat3 e = mat3::Zero();
    e(2, 2) = 1e-4;
    e(0, 1) = e(1, 0) = 0.5e-4;
    impose(gp, q, e);
    b.accumulate_forces(gp);
    const mat3 expected = q * from_voigt(hooke(concrete_block, e)) * q.transpose();
    for (idx z = 0; z < b.zone_count(); ++z)
      CHECK((from_voigt(b.zone_stress().row(z).transpose()) - expected).cwiseAbs().maxCoeff() <=
            1e-9 * expected.cwiseAbs().maxCoeff());
    gp.force.setZero();
  }
}

TEST_CASE("deformable blocks reject inverted zones", "[mechanics][zones]") {
  auto mesh = kuhn_cube(0.1);
  std::swap(mesh.zones[2][1], mesh.zones[2][2]);
  blocks::deformable<zones::linear_elastic_tet> b;
  node_set gp;
  CHECK_THROWS_AS(b.build(geometry::tessellation{}, mesh, concrete_block, gp), geometry_error);
  CHECK_THROWS_WITH(b.build(geometry::tessellation{}, mesh, concrete_block, gp), Catch::Contains("zone 2"));
}
