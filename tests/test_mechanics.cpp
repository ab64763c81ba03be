// Tests for the mechanics core: zones, deformable blocks, integrator, time step, boundary
// conditions, energy balance, solver composition (see tests/CMakeLists.txt).
#include <catch2/catch.hpp>

#include "support/elastic_contact.hpp"
#include "support/hand_meshes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "tessera/blocks.hpp"
#include "tessera/contact/platen.hpp"
#include "tessera/integrator.hpp"
#include "tessera/presets.hpp"
#include "tessera/solver.hpp"
#include "tessera/geometry/voronoi.hpp"
#include "tessera/geometry/zoning.hpp"

using namespace tessera;
// <strings.h> declares a global index(); the tests spell tessera's handle type as idx.
using idx = tessera::index_t;

namespace {

using test::box_tessellation;
/// Column [0,a]x[0,a]x[0,2a] split at z = a into two cells (cell 0 below, cell 1 above) sharing one face.
geometry::tessellation two_cell_column(real a) { return test::box_column(vec3::Zero(), vec3(a, a, a), 2); }

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

namespace {
// Checks that every gridpoint strictly inside the box [0, 0.068]^2 x [0, 0.1] carries a force
// of at most tol (N) per component; returns how many there are.
int check_interior_equilibrium(const node_set& gp, real tol) {
  int interior = 0;
  for (idx i = 0; i < gp.size(); ++i) {
    const vec3 x = gp.reference.row(i).transpose();
    const bool on_surface = (x.array() < 1e-12).any() || std::abs(x.x() - 0.068) < 1e-12 ||
                            std::abs(x.y() - 0.068) < 1e-12 || std::abs(x.z() - 0.1) < 1e-12;
    if (on_surface) continue;
    ++interior;
    CHECK(gp.force.row(i).cwiseAbs().maxCoeff() <= tol);
  }
  return interior;
}
}  // namespace

TEST_CASE("watched zones: the stress a zone task forms is the one formed on demand, bit for bit", "[mechanics][zones]") {
  // The bars read their host zones' global stress from the zone tasks (watch_zone_stress); any
  // other zone's is formed on the call. Both must be the same numbers, in a rotated block too.
  const auto mesh = kuhn_cube(0.1);
  blocks::deformable<zones::linear_elastic_tet> b;
  node_set gp;
  b.build(geometry::tessellation{}, mesh, concrete_block, gp);
  b.watch_zone_stress({4, 1, 4});  // a repeated zone counts once
  mat3 e;
  e << 1.0e-4, 0.3e-4, -0.2e-4, 0.3e-4, -0.5e-4, 0.7e-4, -0.2e-4, 0.7e-4, 2.0e-4;
  const mat3 q = Eigen::AngleAxis<real>(0.7, vec3(1, 2, 3).normalized()).toRotationMatrix();
  impose(gp, q, e);
  b.accumulate_forces(gp);
  const zone_stress_matrix all = b.zone_stress();
  const auto rows = b.zone_stress_rows();
  REQUIRE(rows.rows() == 6);
  for (idx z = 0; z < 6; ++z) {
    INFO("zone " << z);
    CHECK((rows.row(z) - all.row(z)).cwiseAbs().maxCoeff() == 0);
    CHECK((rows.row(z) - b.global_stress(z)).cwiseAbs().maxCoeff() == 0);
  }
  // The rotated block carries the rotated Hooke stress q sigma q^T.
  const mat3 expected = q * from_voigt(hooke(concrete_block, e)) * q.transpose();
  CHECK((from_voigt(all.row(1).transpose()) - expected).cwiseAbs().maxCoeff() <= 1e-9 * expected.cwiseAbs().maxCoeff());
  REQUIRE_THROWS_WITH(b.watch_zone_stress({6}), Catch::Contains("watched zone 6 is not a zone (6 zones)"));
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
  SECTION("zoned box cell with interior gridpoints") {
    // A coarse and a fine zoning of one block (the fine one: over 256 zones, at least 10 interior
    // gridpoints, each summing corners of many zones).
    for (const real h : {0.03, 0.012}) {
      INFO("target zone edge h = " << h << " m");
      const auto tess = box_tessellation(vec3(0, 0, 0), vec3(0.068, 0.068, 0.1));
      const auto mesh = geometry::zone_blocks(tess, {h});
      blocks::deformable<zones::linear_elastic_tet> b;
      node_set gp;
      b.build(tess, mesh, concrete_block, gp);
      if (h < 0.02) REQUIRE(b.zone_count() > 256);
      impose(gp, mat3::Identity(), e);
      b.accumulate_forces(gp);
      for (idx z = 0; z < b.zone_count(); ++z)
        CHECK((b.zone_stress().row(z).transpose() - expected).cwiseAbs().maxCoeff() <= 1e-10 * ref);
      // Interior gridpoints (not on the box surface) are in equilibrium; the resultant is zero.
      const real face_force = ref * 0.068 * 0.068;
      CHECK(check_interior_equilibrium(gp, 1e-10 * face_force) >= (h < 0.02 ? 10 : 1));
      CHECK(gp.force.colwise().sum().cwiseAbs().maxCoeff() <= 1e-10 * face_force);
      // Elastic energy = 1/2 sigma : eps V.
      const real energy = 0.5 * (from_voigt(expected).cwiseProduct(e)).sum() * 0.068 * 0.068 * 0.1;
      CHECK(b.stored_energy(gp) == Approx(energy).epsilon(1e-10));
    }
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

TEST_CASE("block rotations in lock-step over lanes equal the scalar polar iteration to the bit", "[mechanics][zones]") {
  // deformable::update_rotations runs lanes::width blocks per pack (blocks/detail/polar.hpp); every
  // lane must reproduce polar_rotation, iteration count included. Starts: the warm start of a
  // run (F a few 1e-5 away from the previous rotation, so the lanes need different numbers of
  // Newton steps), large strains, a 90-degree jump, a singular and an inverted F (det <= 0: the
  // previous rotation is kept), and part-filled packs.
  INFO("lanes::width = " << lanes::width);
  std::mt19937_64 rng(20261121);
  std::uniform_real_distribution<real> unit(-1, 1);
  std::vector<mat3> f, r_prev;
  for (int k = 0; k < 200; ++k) {
    const real scale = k % 4 == 0 ? 1e-2 : k % 4 == 1 ? 1e-5 : k % 4 == 2 ? 1e-9 : 0.0;
    const mat3 q = skew_rotation(180 * unit(rng), vec3(unit(rng), unit(rng), unit(rng)));
    const mat3 dq = skew_rotation(1e-3 * unit(rng), vec3(unit(rng), unit(rng), unit(rng)));
    mat3 u = mat3::Identity();
    for (int e = 0; e < 9; ++e) u(e / 3, e % 3) += scale * unit(rng);
    f.push_back(dq * q * u);
    r_prev.push_back(q);
  }
  f.push_back(skew_rotation(90, vec3::UnitZ()));
  r_prev.push_back(mat3::Identity());
  f.push_back(mat3::Zero());  // singular
  r_prev.push_back(skew_rotation(10, vec3::UnitX()));
  f.push_back(mat3(vec3(1, 1, -1).asDiagonal()));  // inverted
  r_prev.push_back(mat3::Identity());
  const auto n = static_cast<int>(f.size());
  std::vector<mat3> expected(f.size());
  for (int k = 0; k < n; ++k) expected[static_cast<std::size_t>(k)] = blocks::detail::polar_rotation(f[static_cast<std::size_t>(k)], r_prev[static_cast<std::size_t>(k)]);
  for (const int fill : {lanes::width, 1, std::max(1, lanes::width - 1)}) {
    std::vector<mat3> r = r_prev;
    for (int first = 0; first < n; first += fill) {
      const int m = std::min(fill, n - first);
      blocks::detail::polar_rotations(f.data() + first, r.data() + first, m);
    }
    int mismatches = 0;
    for (int k = 0; k < n; ++k)
      if (std::memcmp(r[static_cast<std::size_t>(k)].data(), expected[static_cast<std::size_t>(k)].data(), sizeof(mat3)) != 0) ++mismatches;
    INFO("blocks per pack " << fill);
    CHECK(mismatches == 0);
  }
  // And they are rotations with R^T F symmetric (the polar factor), the degenerate starts aside.
  for (int k = 0; k < 200; ++k) {
    const mat3& r = expected[static_cast<std::size_t>(k)];
    CHECK((r.transpose() * r - mat3::Identity()).cwiseAbs().maxCoeff() <= 1e-14);
    CHECK(r.determinant() == Approx(1).epsilon(1e-14));
    const mat3 u = r.transpose() * f[static_cast<std::size_t>(k)];
    CHECK((u - u.transpose()).cwiseAbs().maxCoeff() <= 1e-14);
  }
  CHECK(expected[static_cast<std::size_t>(n - 2)] == r_prev[static_cast<std::size_t>(n - 2)]);
  CHECK(expected[static_cast<std::size_t>(n - 1)] == r_prev[static_cast<std::size_t>(n - 1)]);
  CHECK((expected[static_cast<std::size_t>(n - 3)] - f[static_cast<std::size_t>(n - 3)]).cwiseAbs().maxCoeff() <= 1e-15);
}

TEST_CASE("deformable blocks reject inverted zones", "[mechanics][zones]") {
  auto mesh = kuhn_cube(0.1);
  std::swap(mesh.zones[2][1], mesh.zones[2][2]);
  blocks::deformable<zones::linear_elastic_tet> b;
  node_set gp;
  CHECK_THROWS_AS(b.build(geometry::tessellation{}, mesh, concrete_block, gp), geometry_error);
  CHECK_THROWS_WITH(b.build(geometry::tessellation{}, mesh, concrete_block, gp), Catch::Contains("zone 2"));
}

// ---------------------------------------------------------------------------------------------
// Integrator, time step, boundary conditions, solver
// ---------------------------------------------------------------------------------------------

namespace {

using deformable_blocks = blocks::deformable<zones::linear_elastic_tet>;
using undamped_solver = solver<deformable_blocks, contact::face_contacts<law::study_tie_law>, reinforcement::none,
                               integrator::central_difference<integrator::no_damping>, checks::no_step_checker>;

}  // namespace

static_assert(integrator::Integrator<integrator::central_difference<integrator::local_damping>>);
static_assert(integrator::Damping<integrator::no_damping>);

TEST_CASE("local damping opposes the previous velocity with gamma |F|", "[mechanics][integrator]") {
  const integrator::local_damping d{0.8};
  CHECK(d.force(10.0, 2.0) == Approx(8.0));
  CHECK(d.force(-10.0, 2.0) == Approx(8.0));
  CHECK(d.force(10.0, -1.0) == Approx(-8.0));
  CHECK(d.force(-10.0, 0.0) == Approx(8.0));  // sgn(0) = +1 (study eq. 1)
  CHECK_THROWS_AS((integrator::central_difference<integrator::local_damping>(integrator::local_damping{1.2})),
                  invalid_input);
}

TEST_CASE("central differences: free, damped and prescribed components", "[mechanics][integrator]") {
  node_set n;
  n.resize(2);
  n.mass << 2.0, 3.0;
  n.force.row(0) << 4.0, -4.0, 0.0;
  n.velocity.row(0) << 1.0, 1.0, 0.0;
  n.constraint(1, 2) = static_cast<std::uint8_t>(dof_constraint::prescribed);
  n.prescribed_velocity(1, 2) = 0.5;
  n.force(1, 2) = -6.0;
  integrator::step_work w;
  const real dt = 0.1;
  integrator::central_difference<integrator::local_damping> cd(integrator::local_damping{0.5});
  cd.advance(n, dt, w);
  // v+ = v- + (F - 0.5 |F| sgn(v-)) dt / m
  CHECK(n.velocity(0, 0) == Approx(1.0 + (4.0 - 2.0) * dt / 2.0));
  CHECK(n.velocity(0, 1) == Approx(1.0 + (-4.0 - 2.0) * dt / 2.0));
  CHECK(n.displacement(0, 0) == Approx(n.velocity(0, 0) * dt));
  // Prescribed: v = 0.5, reaction R = m (v_p - v-) / dt - F.
  CHECK(n.velocity(1, 2) == 0.5);
  CHECK(n.reaction(1, 2) == Approx(3.0 * 0.5 / dt + 6.0));
  CHECK(w.boundary == Approx(n.reaction(1, 2) * 0.25 * dt));
  CHECK(w.damping == Approx(2.0 * 0.5 * (1.0 + n.velocity(0, 0)) * dt + 2.0 * 0.5 * (1.0 + n.velocity(0, 1)) * dt));
}

namespace {

/// Bitwise equality of two matrices of the same shape (so -0 != +0).
template <class M>
bool same_bits(const M& a, const M& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(typename M::Scalar)) == 0;
}

/// Runs `steps` steps of cd.advance on a node set and of cd.advance_dof, dof by dof in advance's
/// order (component-major, then nodes), on a copy of it, and checks that the two give the same
/// velocities, displacements and reactions to the bit after every step, and the same boundary work
/// and damping dissipation to rounding (advance sums per chunk, and per vector lane where it
/// vectorises). 1237 nodes: three chunks of advance's parallel loop (512, 512, 213), the last one
/// not a multiple of any vector width. Random masses over six decades; every step new random forces,
/// a tenth of them +0 or -0, and a twentieth of the velocities set to +0 or -0 in both sets (the
/// sign of the damping force is sgn(v), sgn(0) = +1); a fifth of the dofs prescribed, redrawn every
/// 50 steps, a third of them at velocity 0; the reactions start as noise, which advance must keep
/// at free dofs as advance_dof does.
template <integrator::Damping D>
void check_advance_against_advance_dof(const integrator::central_difference<D>& cd, unsigned seed, int steps) {
  constexpr idx n = 1237;
  const real dt = 1e-3;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<real> uni(-1.0, 1.0), unit(0.0, 1.0);
  node_set a;
  a.resize(n);
  for (idx i = 0; i < n; ++i) {
    a.mass[i] = std::pow(10.0, 3 * uni(rng));
    for (int c = 0; c < 3; ++c) a.reaction(i, c) = 1e3 * uni(rng);
  }
  const auto draw_constraints = [&] {
    for (idx i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        const bool prescribed = unit(rng) < 0.2;
        a.constraint(i, c) = static_cast<std::uint8_t>(prescribed ? dof_constraint::prescribed : dof_constraint::free);
        a.prescribed_velocity(i, c) = unit(rng) < 1.0 / 3 ? 0.0 : uni(rng);
      }
  };
  draw_constraints();
  node_set b = a;
  int mismatched_steps = 0, first_mismatch = -1;
  idx zero_velocity_free = 0, zero_force_free = 0, prescribed_dofs = 0;
  for (int step = 0; step < steps; ++step) {
    if (step > 0 && step % 50 == 0) {
      draw_constraints();
      b.constraint = a.constraint;
      b.prescribed_velocity = a.prescribed_velocity;
    }
    for (idx i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        const real r = unit(rng);
        a.force(i, c) = r < 0.05 ? 0.0 : r < 0.1 ? -0.0 : uni(rng) * std::pow(10.0, 2 * uni(rng));
        if (const real z = unit(rng); z < 0.05) a.velocity(i, c) = b.velocity(i, c) = z < 0.025 ? 0.0 : -0.0;
        const bool free = a.constraint(i, c) == static_cast<std::uint8_t>(dof_constraint::free);
        zero_velocity_free += free && a.velocity(i, c) == 0 && a.force(i, c) != 0 ? 1 : 0;
        zero_force_free += free && a.force(i, c) == 0 ? 1 : 0;
        prescribed_dofs += free ? 0 : 1;
      }
    b.force = a.force;

    integrator::step_work wa, wb, scale;
    cd.advance(a, dt, wa);
    for (int c = 0; c < 3; ++c)
      for (idx i = 0; i < n; ++i) {
        integrator::step_work one;
        b.velocity(i, c) = cd.advance_dof(b.force(i, c), b.mass[i], b.velocity(i, c), b.constraint(i, c),
                                          b.prescribed_velocity(i, c), dt, b.reaction(i, c), one);
        b.displacement(i, c) += b.velocity(i, c) * dt;
        wb.boundary += one.boundary;
        wb.damping += one.damping;
        scale.boundary += std::abs(one.boundary);
        scale.damping += std::abs(one.damping);
      }
    const bool same = same_bits(a.velocity, b.velocity) && same_bits(a.displacement, b.displacement) &&
                      same_bits(a.reaction, b.reaction) &&
                      std::abs(wa.boundary - wb.boundary) <= 1e-12 * scale.boundary &&
                      std::abs(wa.damping - wb.damping) <= 1e-12 * scale.damping;
    if (!same && mismatched_steps++ == 0) first_mismatch = step;
  }
  INFO("first step where advance and advance_dof differ: " << first_mismatch);
  CHECK(mismatched_steps == 0);
  // The run reached the cases the comment lists.
  CHECK(zero_velocity_free > 0);
  CHECK(zero_force_free > 0);
  CHECK(prescribed_dofs > 0);
}

}  // namespace

TEST_CASE("central differences: advance gives advance_dof's velocities and displacements to the bit",
          "[mechanics][integrator]") {
  // Builds with AVX2 or AVX-512 (the native-tests preset) run advance's branch-free vectorised
  // loop, which this compares with the per-dof advance_dof over 300 steps. In baseline x86-64
  // builds (release, asan) advance itself calls advance_dof, so there this checks only the
  // chunking of the loop and the energy sums.
  SECTION("local damping, gamma = 0.8") {
    check_advance_against_advance_dof(integrator::central_difference<integrator::local_damping>(), 1, 300);
  }
  SECTION("local damping, gamma = 0.35") {
    check_advance_against_advance_dof(
        integrator::central_difference<integrator::local_damping>(integrator::local_damping{0.35}), 2, 300);
  }
  SECTION("no damping") {
    check_advance_against_advance_dof(integrator::central_difference<integrator::no_damping>(), 3, 300);
  }
}

TEST_CASE("boundary conditions: groups, conflicts, reactions", "[mechanics][boundary]") {
  const auto tess = box_tessellation(vec3(0, 0, 0), vec3(0.1, 0.1, 0.2));
  const auto mesh = geometry::zone_blocks(tess);
  deformable_blocks b;
  node_set gp;
  b.build(tess, mesh, concrete_block, gp);
  const auto top = bc::nodes_on_plane(gp, 2, 0.2, 1e-9);
  CHECK(top.size() == 4);
  CHECK_THROWS_AS(bc::nodes_on_plane(gp, 2, 0.5, 1e-9), invalid_input);
  CHECK_THROWS_WITH(bc::nodes_on_plane(gp, 2, 0.5, 1e-9), Catch::Contains("z = 0.5"));
  bc::prescribe_velocity(gp, top, vec3(0, 0, 1e-3), bc::components::z);
  CHECK_NOTHROW(bc::prescribe_velocity(gp, top, vec3(0, 0, 1e-3), bc::components::z));  // same value: no conflict
  CHECK_THROWS_AS(bc::fix(gp, top, bc::components::z), invalid_input);
  CHECK_THROWS_WITH(bc::fix(gp, top, bc::components::z),
                    Catch::Contains("node " + std::to_string(top.nodes[0])) && Catch::Contains("0.001") &&
                        Catch::Contains("component z"));
  CHECK_NOTHROW(bc::fix(gp, top, bc::transverse_to(2)));  // rollers: x, y fixed
  bc::release(gp, top, bc::components::z);
  CHECK_NOTHROW(bc::fix(gp, top, bc::components::z));
}

TEST_CASE("undamped elastic vibration of a zoned block conserves energy", "[mechanics][integrator]") {
  // Leapfrog conserves, for a linear system, the time-centred energy
  //     E_n = V(u_n) + 1/2 v_{n-1/2}^T M v_{n+1/2}
  // exactly; the co-rotational zones are nonlinear only through the block rotation, so E_n must
  // stay constant to well below 1e-3 over 1e5 steps at 0.9 of the Gershgorin step.
  const auto tess = box_tessellation(vec3(0, 0, 0), vec3(0.068, 0.068, 0.1));
  const auto mesh = geometry::zone_blocks(tess);
  undamped_solver s(tess, mesh, concrete_block, test::elastic_contact(1e12, 4e11));
  // Initial velocity: a twisting + stretching field plus a slow spin (no loads, no supports).
  for (idx i = 0; i < s.gridpoints().size(); ++i) {
    const vec3 x = s.gridpoints().reference.row(i).transpose() - vec3(0.034, 0.034, 0.05);
    s.gridpoints().velocity.row(i) << -x.y() * x.z() * 2.0 - 0.1 * x.y(), x.x() * x.z() * 2.0 + 0.1 * x.x(), 0.05 * x.z();
  }
  // After step k the solver holds u_k and v_{k-1/2}: E_{k-1} needs V(u_{k-1}) and v_{k-3/2}
  // from the previous step.
  soa3 v_before;
  real potential_before = 0;
  const auto remember = [&](const auto& sv) {
    v_before = sv.gridpoints().velocity;
    potential_before = sv.blocks().stored_energy(sv.gridpoints());
  };
  const auto centred_energy = [&](const auto& sv) {
    const node_set& gp = sv.gridpoints();
    real kinetic = 0;
    for (idx i = 0; i < gp.size(); ++i) kinetic += 0.5 * gp.mass[i] * gp.velocity.row(i).dot(v_before.row(i));
    return kinetic + potential_before;
  };
  remember(s);
  s.step();
  const real e0 = centred_energy(s);
  REQUIRE(e0 > 0);
  real worst = 0;
  s.run(100000, [&](const auto& sv) {
    if (sv.step_count() % 97 == 96) remember(sv);
    if (sv.step_count() % 97 == 0) worst = std::max(worst, std::abs(centred_energy(sv) - e0) / e0);
  });
  INFO("largest relative drift of the centred energy: " << worst);
  CHECK(worst < 1e-3);
}

TEST_CASE("a block on a contact spring oscillates with period 2 pi sqrt(m/k)", "[mechanics][solver]") {
  const real a = 0.05;
  const auto tess = two_cell_column(a);
  const auto mesh = geometry::zone_blocks(tess);
  const real k_n = 1e12;  // Pa/m
  // Blocks far stiffer than the contact, so block 1 moves as a rigid mass on the spring k_n A.
  const zones::linear_elastic_tet::params stiff{1e5 * k_n * a, 0.2, 2400};
  undamped_solver s(tess, mesh, stiff, test::elastic_contact(k_n, 0.4 * k_n));
  bc::fix(s.gridpoints(), bc::nodes_where(s.gridpoints(), [&](const vec3& x) { return x.z() < a - 1e-9; }, "block 0"));
  bc::node_group upper = bc::nodes_where(s.gridpoints(), [&](const vec3& x) { return x.z() > a + 1e-9; }, "upper");
  for (idx i = 0; i < mesh.gridpoint_count(); ++i)
    if (mesh.gridpoint_block[static_cast<std::size_t>(i)] == 1) s.gridpoints().velocity(i, 2) = 1e-4;
  real mass = 0;
  for (idx i = 0; i < mesh.gridpoint_count(); ++i)
    if (mesh.gridpoint_block[static_cast<std::size_t>(i)] == 1) mass += s.gridpoints().mass[i];
  const real expected_period = 2 * std::numbers::pi * std::sqrt(mass / (k_n * a * a));
  // Upward zero crossings of the mean displacement of the upper nodes.
  std::vector<real> crossings;
  real previous = 0;
  const auto n_steps = static_cast<std::int64_t>(5.2 * expected_period / s.dt());
  s.run(n_steps, [&](const auto& sv) {
    const real u = recorders::mean_displacement(sv.gridpoints(), upper).z();
    if (previous < 0 && u >= 0) crossings.push_back(sv.time() - sv.dt() * u / (u - previous));
    previous = u;
  });
  REQUIRE(crossings.size() >= 4);
  const real period = (crossings.back() - crossings.front()) / static_cast<real>(crossings.size() - 1);
  CHECK(period == Approx(expected_period).epsilon(1e-3));
}

TEST_CASE("Gershgorin time step is below the true critical step", "[mechanics][timestep]") {
  const real a = 0.05;
  const auto tess = two_cell_column(a);
  const auto mesh = geometry::zone_blocks(tess);
  undamped_solver s(tess, mesh, concrete_block, test::elastic_contact(1.16e12, 0.482e12));
  // Dense K by central finite differences of the (linear near the reference) internal forces.
  const idx n = s.gridpoints().size();
  Eigen::MatrixXd k(3 * n, 3 * n);
  const real h = 1e-9;
  for (idx j = 0; j < 3 * n; ++j) {
    Eigen::VectorXd f[2];
    for (int side = 0; side < 2; ++side) {
      undamped_solver probe = s;
      node_set& gp = probe.gridpoints();
      const real dx = side == 0 ? h : -h;
      gp.displacement(j / 3, j % 3) = dx;
      gp.velocity(j / 3, j % 3) = dx / probe.dt();  // the contact increment of this "step"
      gp.force.setZero();
      deformable_blocks blocks = probe.blocks();
      blocks.accumulate_forces(gp);
      auto contacts = probe.contacts();
      contacts.update(gp, probe.dt());
      f[side].resize(3 * n);
      for (idx i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) f[side][3 * i + c] = gp.force(i, c);
    }
    k.col(j) = -(f[0] - f[1]) / (2 * h);
  }
  const Eigen::MatrixXd ks = 0.5 * (k + k.transpose());
  CHECK((k - ks).cwiseAbs().maxCoeff() <= 1e-5 * k.cwiseAbs().maxCoeff());
  Eigen::VectorXd inv_sqrt_m(3 * n);
  for (idx i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) inv_sqrt_m[3 * i + c] = 1 / std::sqrt(s.gridpoints().mass[i]);
  const Eigen::MatrixXd a_mat = inv_sqrt_m.asDiagonal() * ks * inv_sqrt_m.asDiagonal();
  const real lambda_max = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a_mat).eigenvalues().maxCoeff();
  const real true_critical = 2 / std::sqrt(lambda_max);
  INFO("Gershgorin " << s.critical_step().dt << " s, eigen " << true_critical << " s");
  CHECK(s.critical_step().dt <= true_critical);
  CHECK(s.critical_step().dt >= 0.2 * true_critical);  // a bound, but not a uselessly loose one
  CHECK(s.dt() == Approx(0.9 * s.critical_step().dt));
}

TEST_CASE("solver: time step options and mass scaling", "[mechanics][timestep]") {
  const real a = 0.05;
  const auto tess = two_cell_column(a);
  const auto mesh = geometry::zone_blocks(tess);
  const auto law_params = test::elastic_contact(1.16e12, 0.482e12);
  const prism_solver automatic(tess, mesh, concrete_block, law_params);
  solver_options too_large;
  too_large.dt = 2 * automatic.dt();
  CHECK_THROWS_AS(prism_solver(tess, mesh, concrete_block, law_params, {}, too_large), invalid_input);
  CHECK_THROWS_WITH(prism_solver(tess, mesh, concrete_block, law_params, {}, too_large),
                    Catch::Contains("gridpoint") && Catch::Contains("of block") && Catch::Contains("stable limit"));
  solver_options scaled;
  scaled.mass_scaling_dt = 10 * automatic.dt();
  const prism_solver s(tess, mesh, concrete_block, law_params, {}, scaled);
  CHECK(s.dt() == Approx(scaled.mass_scaling_dt));
  CHECK(s.options().safety * s.critical_step().dt >= s.dt() * (1 - 1e-12));
  CHECK(s.mass_scaling().added_mass > 0);
  CHECK(s.gridpoints().mass.sum() == Approx(s.mass_scaling().original_mass + s.mass_scaling().added_mass));

  // A target added-mass ratio instead of a step: the solver finds the step that adds it, and the
  // same step given directly adds the same mass.
  for (const real ratio : {0.5, 10.0, 250.0}) {
    solver_options by_ratio;
    by_ratio.mass_scaling_ratio = ratio;
    const prism_solver r(tess, mesh, concrete_block, law_params, {}, by_ratio);
    INFO("ratio " << ratio << ", dt " << r.dt());
    CHECK(r.mass_scaling().added_mass / r.mass_scaling().original_mass == Approx(ratio).epsilon(1e-9));
    CHECK(r.options().mass_scaling_dt == r.dt());
    CHECK(r.dt() > automatic.dt());
    solver_options by_step;
    by_step.mass_scaling_dt = r.dt();
    const prism_solver d(tess, mesh, concrete_block, law_params, {}, by_step);
    CHECK(d.mass_scaling().added_mass == Approx(r.mass_scaling().added_mass).epsilon(1e-12));
  }
  // preview_mass_scaling reports what scale_masses does without doing it.
  node_set nodes = automatic.gridpoints();
  const auto preview = integrator::preview_mass_scaling(nodes, 10 * automatic.dt());
  CHECK(nodes.mass.sum() == Approx(preview.original_mass).epsilon(1e-15));
  const auto applied = integrator::scale_masses(nodes, 10 * automatic.dt());
  CHECK(applied.added_mass == preview.added_mass);
  CHECK(applied.scaled_nodes == preview.scaled_nodes);
  // Bad input names the option and the value.
  solver_options both;
  both.mass_scaling_dt = 1e-6;
  both.mass_scaling_ratio = 10;
  CHECK_THROWS_WITH(prism_solver(tess, mesh, concrete_block, law_params, {}, both), Catch::Contains("not both"));
  solver_options negative;
  negative.mass_scaling_ratio = -1;
  CHECK_THROWS_WITH(prism_solver(tess, mesh, concrete_block, law_params, {}, negative),
                    Catch::Contains("added-mass ratio = -1"));
}

TEST_CASE("step checker stops a run whose masses are too small", "[mechanics][checker]") {
  const real a = 0.05;
  const auto tess = two_cell_column(a);
  const auto mesh = geometry::zone_blocks(tess);
  prism_solver s(tess, mesh, concrete_block, test::elastic_contact(1.16e12, 0.482e12));
  s.fix(s.gridpoints_on_plane(2, 0, 1e-9));
  s.prescribe_velocity(s.gridpoints_on_plane(2, 2 * a, 1e-9), vec3(0, 0, 1e-3), bc::components::z);
  s.gridpoints().mass *= 1e-3;  // dt now ~30 x above the stable limit
  CHECK_THROWS_AS(s.run(5000), numerical_instability);
  prism_solver s2(tess, mesh, concrete_block, test::elastic_contact(1.16e12, 0.482e12));
  s2.gridpoints().mass *= 1e-3;
  s2.gridpoints().velocity.setConstant(1e-6);
  try {
    s2.run(5000);
    FAIL("no numerical_instability");
  } catch (const numerical_instability& e) {
    const std::string what = e.what();
    CHECK_THAT(what, Catch::Contains("of block") && Catch::Contains("time step above the stable limit"));
  }
}

TEST_CASE("two blocks pulled apart follow the contact law times the face area", "[mechanics][solver]") {
  const real a = 0.05, area = a * a;
  const auto tess = two_cell_column(a);
  const auto mesh = geometry::zone_blocks(tess);
  const auto law_params = law::study_prism_params(100);
  solver_options opt;
  opt.mass_scaling_dt = 2e-6;
  prism_solver s(tess, mesh, concrete_block, law_params, {}, opt);
  s.fix(s.gridpoints_on_plane(2, 0, 1e-9));
  const auto top = s.gridpoints_on_plane(2, 2 * a, 1e-9);
  const real rate = 0.001;  // m/s
  s.fix(top, bc::transverse_to(2));
  s.prescribe_velocity(top, vec3(0, 0, rate), bc::components::z);
  real peak = 0;
  real worst_law_error = 0;
  const real f_t = law_params.tension.f_T;
  const auto envelope = [&](real u_n) {  // power softening, eq. 5
    const real eta = f_t / law_params.k_n, zeta = 2 * law_params.tension.G_f / f_t;
    return u_n <= eta ? law_params.k_n * u_n : f_t * std::pow(zeta / (zeta - eta + u_n), 3);
  };
  const auto stop = [&](const auto& sv) { return sv.contacts().broken_area() >= area * (1 - 1e-9); };
  s.run_until(stop, 2'000'000, recorders::every(10, [&](const auto& sv) {
    const real stress = recorders::reaction_sum(sv.gridpoints(), top).z() / area;
    peak = std::max(peak, stress);
    // Monotonic opening: every sub-contact sits on the envelope at its own opening.
    real law_stress = 0;
    for (idx i = 0; i < sv.contacts().size(); ++i)
      law_stress += envelope(sv.contacts().state(i).u_n) * sv.contacts().area(i) / area;
    // The sudden start of the loading rings for a few hundred steps; compare past it.
    if (recorders::mean_displacement(sv.gridpoints(), top).z() > 0.5 * f_t / law_params.k_n)
      worst_law_error = std::max(worst_law_error, std::abs(stress - law_stress) / f_t);
  }));
  CHECK(s.contacts().broken_area() == Approx(area));
  CHECK(peak == Approx(f_t).epsilon(0.01));
  CHECK(worst_law_error < 0.01);
  const auto e = s.energies();
  const real expected = law::power_softening::separation_energy(law_params.tension, law_params.k_n) * area;
  CHECK(e.contact_dissipated_tension == Approx(expected).epsilon(0.01));
  INFO("W = " << e.boundary_work << " J, accounted " << e.accounted() << " J");
  CHECK(e.error_rel() < 0.01);
}

// Materials per block and per contact pair (contact::material_table): a column of three concrete
// blocks between two steel end plates, compressed along its axis. Blocks of edge a stacked along
// z; each block is a spring E A / a, each interface k_n A, all in series:
//     1/K = 2 a/(E_s A) + 3 a/(E_c A) + 2/(k_cc A) + 2/(k_pc A)
// (two plates, three concrete blocks, two concrete-concrete and two plate-concrete interfaces).
// Poisson's ratio is zero in both materials, so no lateral mismatch shears the interfaces and the
// series value is exact; the dynamic-relaxation run settles to it (checked within 1 %).
// A never-bonded plate-concrete pair then carries no tension when the column is pulled.
TEST_CASE("materials: concrete column between steel plates has the series stiffness, never-bonded pairs carry no tension",
          "[mechanics][solver][materials]") {
  const real a = 0.05, area = a * a;
  const auto tess = test::box_column(vec3::Zero(), vec3(a, a, a), 5);
  auto mesh = geometry::zone_blocks(tess);
  mesh.block_material = {1, 0, 0, 0, 1};  // 0 concrete, 1 steel
  const zones::linear_elastic_tet::params concrete{30e9, 0.0, 2400}, steel{200e9, 0.0, 7850};
  auto concrete_concrete = law::study_prism_params(100);
  auto plate_concrete = concrete_concrete;
  plate_concrete.k_n = 300e9;  // the plate interfaces on their own (softer) stiffness, Pa/m
  plate_concrete.k_s = 120e9;
  using column_solver = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<law::study_tie_law>>;
  const column_solver::block_materials materials{{concrete, steel}};
  solver_options opt;
  opt.mass_scaling_dt = 2e-6;

  const auto run = [&](const contact::material_table<law::study_tie_law::params>& table, real velocity, int steps) {
    column_solver s(tess, mesh, materials, table, {}, opt);
    s.fix(s.gridpoints_on_plane(2, 0, 1e-9));
    const auto top = s.gridpoints_on_plane(2, 5 * a, 1e-9);
    s.fix(top, bc::transverse_to(2));
    s.prescribe_velocity(top, vec3(0, 0, velocity), bc::components::z);
    s.run(steps);
    bc::release(s.gridpoints(), top, bc::components::z);  // hold, let the damping settle
    s.fix(top, bc::components::z);
    s.run(4 * steps);
    const real force = recorders::reaction_sum(s.gridpoints(), top).z();
    const real displacement = recorders::mean_displacement(s.gridpoints(), top).z();
    return std::pair{force, displacement};
  };

  contact::material_table<law::study_tie_law::params> table(concrete_concrete);
  table.set(0, 1, plate_concrete);
  const auto [force, displacement] = run(table, -0.002, 5000);  // 10 um of shortening
  REQUIRE(displacement < 0);
  const real compliance = 2 * a / (steel.young * area) + 3 * a / (concrete.young * area) + 2 / (concrete_concrete.k_n * area) +
                          2 / (plate_concrete.k_n * area);
  INFO("F = " << force << " N, u = " << displacement << " m");
  CHECK(force / displacement == Approx(1 / compliance).epsilon(0.01));
  // The plate interfaces matter: with concrete-concrete stiffness everywhere the column is stiffer.
  const real uniform = 2 * a / (steel.young * area) + 3 * a / (concrete.young * area) + 4 / (concrete_concrete.k_n * area);
  CHECK(1 / uniform > 1.05 / compliance);

  // Never bonded (c_res = 0: frictional only): pulled apart, the plate leaves the concrete with no force.
  auto frictional = plate_concrete;
  frictional.shear.c_res = 0;
  contact::material_table<law::study_tie_law::params> unbonded(concrete_concrete);
  unbonded.never_bonded(0, 1, frictional);
  const auto [pull_force, pull_displacement] = run(unbonded, 0.002, 5000);
  REQUIRE(pull_displacement > 0);
  CHECK(std::abs(pull_force) < 1e-9 * std::abs(force));
  // The same pull on the bonded table is resisted (the interfaces are bonded in tension).
  const auto [bonded_force, bonded_displacement] = run(table, 0.002, 5000);
  CHECK(bonded_force / bonded_displacement == Approx(1 / compliance).epsilon(0.01));
}

// A crack face inclined at theta to the cross-section, between two ends that cannot move
// transversally (the direct tension platens), opens by delta cos(theta) and slips by
// delta sin(theta) when the top moves by delta. With (nearly) rigid blocks the mean axial stress
// over the cross-section A is (sigma_n cos(theta) + tau sin(theta)) / cos(theta), so the contact
// reaches f_T at
//     sigma_peak = f_T (1 + (k_s / k_n) tan^2(theta))
// (+5.5 % at 20 deg with the Table 1 stiffnesses): the shear a tortuous crack carries while its
// faces are at the tension cap is why the Voronoi prism peaks above f_T (docs/architecture.md,
// "Direct tension results").
TEST_CASE("an inclined crack face under restrained ends peaks at f_T (1 + k_s/k_n tan^2 theta)", "[mechanics][solver]") {
  const real a = 0.05, area = a * a;
  const auto law_params = law::study_prism_params(100);
  const real f_t = law_params.tension.f_T;
  // Blocks 1000 x stiffer than the semi-rigid ones: block strains negligible against the contacts.
  const zones::linear_elastic_tet::params rigid_like{28e12, 0.2, 2400};
  for (const real theta_deg : {0.0, 20.0}) {
    const real theta = theta_deg * std::numbers::pi / 180;
    aabb box;
    box.lo = vec3::Zero();
    box.hi = vec3(a, a, 2 * a);
    const vec3 n(std::sin(theta), 0, std::cos(theta));
    const vec3 c(a / 2, a / 2, a);
    const std::vector<vec3> seeds{c - 0.2 * a * n, c + 0.2 * a * n};
    const auto tess = geometry::voronoi(box, seeds);
    REQUIRE(tess.shared_faces.size() == 1);
    const auto mesh = geometry::zone_blocks(tess);
    solver_options opt;
    opt.mass_scaling_dt = 2e-6;
    prism_solver s(tess, mesh, rigid_like, law_params, {}, opt);
    const auto bottom = s.gridpoints_on_plane(2, 0, 1e-9);
    s.fix(bottom);
    const auto top = s.gridpoints_on_plane(2, 2 * a, 1e-9);
    s.fix(top, bc::transverse_to(2));
    s.prescribe_velocity(top, vec3::Zero(), bc::components::z);
    // Quasi-static: the velocity rises as a half cosine over 2000 steps to 1 mm/s (2 nm per step).
    const real rate = 0.001, ramp = 5000 * s.dt();
    const auto load = [&](const auto& sv) {
      const real t = sv.time() + 0.5 * sv.dt();
      const real v = t < ramp ? 0.5 * rate * (1 - std::cos(std::numbers::pi * t / ramp)) : rate;
      bc::update_velocity(s.gridpoints(), top, vec3(0, 0, v), bc::components::z);
    };
    load(s);
    const real delta_peak = f_t / (law_params.k_n * std::cos(theta));
    real peak = 0;
    const auto stop = [&](const auto& sv) { return recorders::mean_displacement(sv.gridpoints(), top).z() > 2 * delta_peak; };
    s.run_until(stop, 100'000, load, [&](const auto& sv) {
      const real r_top = recorders::reaction_sum(sv.gridpoints(), top).z();
      const real r_bottom = recorders::reaction_sum(sv.gridpoints(), bottom).z();
      peak = std::max(peak, 0.5 * (r_top - r_bottom) / area);
    });
    const real tan_theta = std::tan(theta);
    const real expected = f_t * (1 + law_params.k_s / law_params.k_n * tan_theta * tan_theta);
    INFO("theta = " << theta_deg << " deg: peak " << peak << " Pa, expected " << expected << " Pa");
    CHECK(peak == Approx(expected).epsilon(0.01));
  }
}

/// n_cells random Voronoi blocks (tessellation seed `seed`) of a 0.1 m cube as deformable blocks,
/// displaced by a rotation of `angle` rad about `axis` plus uniform noise of +-1e-6 m (noise seed
/// `noise_seed`; zone strains ~1e-4).
struct rotated_voronoi_blocks {
  geometry::block_mesh mesh;
  blocks::deformable<zones::linear_elastic_tet> model;
  node_set gp;
  Eigen::Matrix3d q;
  rotated_voronoi_blocks(idx n_cells, std::uint64_t seed, real angle, const vec3& axis, std::uint64_t noise_seed,
                         const zones::linear_elastic_tet::params& material) {
    aabb box;
    box.expand(vec3::Zero());
    box.expand(vec3(0.1, 0.1, 0.1));
    const auto tess = geometry::random_voronoi(box, n_cells, seed);
    mesh = geometry::zone_blocks(tess);
    model.build(tess, mesh, material, gp);
    q = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    std::mt19937_64 rng(noise_seed);
    std::uniform_real_distribution<real> noise(-1e-6, 1e-6);
    for (idx i = 0; i < gp.size(); ++i) {
      const vec3 x = gp.reference.row(i).transpose();
      const vec3 u = q * x - x + vec3(noise(rng), noise(rng), noise(rng));
      gp.displacement.row(i) = u.transpose();
    }
  }
};

// A rigid platen (contact/platen.hpp) on a column of three 50 mm cubes whose base is fixed, its
// contact the never-bonded plate-concrete pair of the law (k_n 300 GPa/m, friction only):
// pressed, the column answers with the series stiffness of three cubes, two bonded faces and the
// platen's contact; sheared under that load, the platen slides at tan(phi_res) x the normal
// force; lifted, it leaves the column with no force. The applied forces' work closes the balance.
TEST_CASE("rigid platen: series stiffness in compression, Coulomb sliding, no tension, the balance closes",
          "[mechanics][solver][platen]") {
  const real a = 0.05, area = a * a;
  const auto tess = test::box_column(vec3::Zero(), vec3(a, a, a), 3);
  const auto mesh = geometry::zone_blocks(tess);
  const zones::linear_elastic_tet::params concrete{30e9, 0.0, 2400};
  const auto concrete_concrete = law::study_prism_params(100);
  auto plate = concrete_concrete;
  plate.k_n = 300e9;
  plate.k_s = 120e9;
  plate.shear.c_res = 0;
  using column_solver = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<law::study_tie_law>>;
  solver_options opt;
  opt.mass_scaling_dt = 2e-6;
  column_solver s(tess, mesh, {concrete}, concrete_concrete, {}, opt);
  s.fix(s.gridpoints_on_plane(2, 0, 1e-9));
  const contact::platen_geometry top{vec3(a / 2, a / 2, 3 * a), vec3(0, 0, -1), vec3(1, 0, 0), 0.6 * a, 0.6 * a};
  contact::rigid_platen<law::study_tie_law> platen(mesh, top, {}, plate);
  CHECK(platen.total_area() == Approx(area).epsilon(1e-12));
  // Half the footprint: half the face, whatever the triangulation.
  contact::platen_geometry half = top;
  half.half_u = a / 4;
  CHECK(contact::rigid_platen<law::study_tie_law>(mesh, half, {}, plate).total_area() == Approx(area / 2).epsilon(1e-12));
  const real dt_before = s.dt();
  platen.attach(s);
  CHECK(s.dt() == dt_before);  // mass scaling keeps its step: the platen's springs add mass, not steps
  const auto run = [&](const vec3& v, int steps) {
    platen.set_velocity(v);
    for (int k = 0; k < steps; ++k) {
      platen.update(s);
      s.step();
    }
  };
  run(vec3(0, 0, -0.002), 2500);  // 10 um down (dt = 2 us)
  run(vec3::Zero(), 20000);
  const real pressed = platen.force().z();
  const real shortening = -platen.displacement().z();
  REQUIRE(s.dt() == 2e-6);
  REQUIRE(shortening == Approx(1e-5).epsilon(1e-9));
  const real compliance = 3 * a / (concrete.young * area) + 2 / (concrete_concrete.k_n * area) + 1 / (plate.k_n * area);
  INFO("F = " << pressed << " N over " << shortening << " m");
  CHECK(pressed / shortening == Approx(1 / compliance).epsilon(0.01));
  CHECK(platen.in_contact() == platen.size());
  CHECK(s.energies().applied_work > 0);
  CHECK(s.energies().error_rel() < 1e-3);

  // 0.4 mm along x under the load: the column bends (its tip stiffness 3 E I / L^3 = 14 kN/mm),
  // then the platen slides over it.
  run(vec3(0.01, 0, 0), 20000);
  const vec3 sliding = platen.force();
  INFO("sliding: F = (" << sliding.transpose() << ") N");
  CHECK(std::hypot(sliding.x(), sliding.y()) == Approx(plate.shear.phi_res.tan() * sliding.z()).epsilon(1e-3));
  {
    const auto e = s.energies();
    INFO("applied work " << e.applied_work << " J, damping " << e.damping_dissipated << " J, stored "
                         << e.block_elastic + e.contact_stored << " J");
    CHECK(e.error_rel() < 1e-3);
  }
  CHECK(platen.force().z() > 0.5 * pressed);
  CHECK(platen.dissipated_energy() > 0);

  run(vec3(0, 0, 0.004), 2500);  // 20 um up: twice the shortening
  run(vec3::Zero(), 20000);
  CHECK(platen.in_contact() == 0);
  CHECK(platen.force().norm() == 0);
  CHECK(platen.stored_energy() == 0);
  {
    const auto e = s.energies();
    INFO("applied work " << e.applied_work << " J, damping " << e.damping_dissipated << " J, stored "
                         << e.block_elastic + e.contact_stored << " J");
    CHECK(e.error_rel() < 1e-3);
  }

  // Refused: a plane the mesh has no face on, and a normal that is not a unit vector.
  contact::platen_geometry off = top;
  off.point.z() = 4 * a;
  CHECK_THROWS_AS(contact::rigid_platen<law::study_tie_law>(mesh, off, {}, plate), invalid_input);
  contact::platen_geometry bent = top;
  bent.normal = vec3(0, 0, -2);
  CHECK_THROWS_AS(contact::rigid_platen<law::study_tie_law>(mesh, bent, {}, plate), invalid_input);
}

// A platen hinged 5 mm off the centre of a 50 mm column's top face and free to roll along x,
// pressed down at its hinge: once settled, the free components carry nothing (no moment about
// the hinge, no force along x), so the platen has tilted until its resultant passes through the
// hinge. Linear springs under a tilted rigid plate give a linear pressure, whose centroid moves
// to the hinge while every sub-contact stays closed (the offset is below a / 6). Measured: 4.75 kN,
// a moment of 1.8e-14 N m, the resultant 5e-9 m from the hinge, a tilt of 77 urad.
TEST_CASE("rigid platen: a hinged, rolling platen settles with its resultant through the hinge",
          "[mechanics][solver][platen]") {
  const real a = 0.05, offset = 0.005;
  const auto tess = test::box_column(vec3::Zero(), vec3(a, a, a), 2);
  const auto mesh = geometry::zone_blocks(tess);
  const zones::linear_elastic_tet::params concrete{30e9, 0.0, 2400};
  auto plate = law::study_prism_params(100);
  plate.shear.c_res = 0;
  using column_solver = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<law::study_tie_law>>;
  solver_options opt;
  opt.mass_scaling_dt = 2e-6;
  column_solver s(tess, mesh, {concrete}, law::study_prism_params(100), {}, opt);
  s.fix(s.gridpoints_on_plane(2, 0, 1e-9));
  contact::platen_motion m;
  m.mass = 0.4;  // a 50 x 50 x 20 mm steel plate
  m.inertia = 1e-4;
  m.free_translation = {true, false, false};
  m.hinge_axis = vec3::UnitY();
  contact::rigid_platen<law::study_tie_law> platen(
      mesh, {vec3(a / 2 + offset, a / 2, 2 * a), vec3(0, 0, -1), vec3(1, 0, 0), 0.6 * a, 0.6 * a}, m, plate);
  platen.attach(s);
  platen.set_velocity(vec3(0, 0, -0.002));
  for (int k = 0; k < 2500; ++k) platen.update(s), s.step();  // 10 um down at the hinge
  platen.set_velocity(vec3::Zero());
  for (int k = 0; k < 40000; ++k) platen.update(s), s.step();
  const vec3 f = platen.force();
  INFO("force (" << f.transpose() << ") N, moment " << platen.moment() << " N m, rotation " << platen.rotation()
                 << " rad, " << platen.in_contact() << " of " << platen.size() << " in contact");
  REQUIRE(f.z() > 0);
  CHECK(std::abs(platen.moment()) < 1e-4 * f.z() * a);
  CHECK(std::abs(f.x()) < 1e-4 * f.z());
  CHECK(platen.in_contact() == platen.size());
  // The footprint, clipped to the top face, is centred 5 mm on the -x side of the hinge: to bring
  // the resultant to the hinge the platen presses harder on its +x side, so it turns that side
  // down, a positive rotation about +y (y x x = -z, into the column).
  CHECK(platen.rotation() > 1e-5);
  // The resultant's line: sum x_i f_i / sum f_i over the sub-contacts, at the hinge.
  real fx = 0, fz = 0;
  for (std::size_t j = 0; j < platen.size(); ++j) {
    const real fj = -platen.area(j) * platen.state(j).sigma_n;
    fz += fj;
    fx += fj * s.gridpoints().position(platen.node(j)).x();
  }
  CHECK(fx / fz == Approx(a / 2 + offset + platen.displacement().x()).margin(1e-5 * a));
  CHECK(s.energies().error_rel() < 1e-3);
}

TEST_CASE("gravity on deformable blocks: a settled column puts its weight on the base, the balance closes",
          "[solver][gravity]") {
  // Three 50 mm concrete cubes bonded in a column on a fixed base, mass-scaled, local damping:
  // once at rest the base reaction is the weight from the unscaled masses (scaling adds inertia,
  // not weight), and the work of gravity is in the energy balance. Out of balance: at the first
  // step nothing is strained, so each free gridpoint's unbalanced force is its weight, and those
  // weights plus the base's reaction are the column's weight; once settled they vanish.
  const real a = 0.05;
  const auto tess = test::box_column(vec3::Zero(), vec3(a, a, a), 3);
  const auto mesh = geometry::zone_blocks(tess);
  const zones::linear_elastic_tet::params concrete{30e9, 0.2, 2400};
  solver_options opt;
  opt.mass_scaling_dt = 2e-5;
  solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<law::study_tie_law>> s(
      tess, mesh, {concrete}, law::study_prism_params(100), {}, opt);
  REQUIRE(s.mass_scaling().added_mass > 0);
  const auto base = s.gridpoints_on_plane(2, 0, 1e-9);
  s.fix(base);
  s.set_gravity(vec3(0, 0, -9.81));
  const real weight = 2400 * 3 * a * a * a * 9.81;
  s.run(1);
  const out_of_balance first = s.unbalanced_force();
  CHECK(first.nodes == mesh.gridpoint_count() - base.size());
  CHECK(first.mean_force * static_cast<real>(first.nodes) + recorders::reaction_sum(s.gridpoints(), base).z() ==
        Approx(weight).epsilon(1e-12));
  s.run(19999);
  const out_of_balance settled = s.unbalanced_force();
  INFO("settled: largest unbalanced force " << settled.max_force << " N against a weight of " << weight << " N");
  CHECK(settled.max_force < 1e-6 * weight);
  CHECK(settled.max_force < 1e-3 * first.max_force);
  const real reaction = recorders::reaction_sum(s.gridpoints(), base).z();
  INFO("reaction " << reaction << " N, weight " << weight << " N");
  CHECK(reaction == Approx(weight).epsilon(1e-6));
  const auto e = s.energies();
  CHECK(e.gravity_work > 0);
  CHECK(e.error_rel() < 1e-3);
  CHECK_THROWS_AS(s.set_gravity(vec3(0, 0, std::numeric_limits<real>::quiet_NaN())), invalid_input);
}

TEST_CASE("out of balance: free components only, prescribed ones left out", "[solver][balance]") {
  // Hand values on a node set: (3, 4, 0) free -> 5; (1, 2, 2) with z prescribed -> sqrt(5); a node
  // with every component prescribed is left out.
  node_set n;
  n.resize(3);
  n.force.row(0) << 3, 4, 0;
  n.force.row(1) << 1, 2, 2;
  n.force.row(2) << 7, 7, 7;
  n.constraint(1, 2) = static_cast<std::uint8_t>(dof_constraint::prescribed);
  n.constraint.row(2).setConstant(static_cast<std::uint8_t>(dof_constraint::prescribed));
  const out_of_balance hand = unbalanced_force(n);
  CHECK(hand.nodes == 2);
  CHECK(hand.max_node == 0);
  CHECK(hand.max_force == 5);
  CHECK(hand.mean_force == Approx((5 + std::sqrt(5.0)) / 2).epsilon(1e-15));
}

TEST_CASE("adaptive rate: out of balance drops to the slowest factor at once, quiet samples grow it to the fastest",
          "[solver][balance]") {
  adaptive_rate rate({.min_factor = 0.5, .max_factor = 2, .low = 0.01, .high = 0.02, .growth = 1.5});
  CHECK(rate.factor() == 1);
  CHECK(rate.update(0.005) == 1.5);   // quiet: grows
  CHECK(rate.update(0.005) == 2);     // capped at the fastest
  CHECK(rate.update(0.015) == 2);     // between the bands: held
  CHECK(rate.update(0.03) == 0.5);    // out of balance: the slowest at once
  CHECK(rate.update(std::numeric_limits<real>::quiet_NaN()) == 0.5);  // NaN counts as out of balance
  CHECK(rate.update(0) == 0.75);
  CHECK(adaptive_rate().update(1e9) == 1);  // the default is a fixed rate
  using p = adaptive_rate::params;
  CHECK_THROWS_AS(adaptive_rate(p{.min_factor = 0}), invalid_input);
  CHECK_THROWS_AS(adaptive_rate(p{.min_factor = 1.5, .max_factor = 2}), invalid_input);
  CHECK_THROWS_AS(adaptive_rate(p{.max_factor = 0.9}), invalid_input);
  CHECK_THROWS_AS(adaptive_rate(p{.max_factor = 2, .growth = 1}), invalid_input);
  CHECK_THROWS_AS(adaptive_rate(p{.low = 0.02, .high = 0.02}), invalid_input);
  CHECK_THROWS_AS(adaptive_rate(p{.low = 0.01, .high = std::numeric_limits<real>::infinity()}), invalid_input);
}

TEST_CASE("zone tasks split at any block give the bits of accumulate_forces, parallel_range_pair covers each index once",
          "[mechanics][zones][parallel]") {
  // The fused solver step runs the zone tasks in one range per thread, each range computing the
  // rotations of its own blocks first (packs of lanes::width blocks starting at the range's first
  // block, not at a multiple of the width). Every split must give the bits of the unsplit pass.
  rotated_voronoi_blocks scene(21, 5, 0.4, vec3(3, -1, 2), 11, concrete_block);
  const auto& model = scene.model;
  const node_set& gp = scene.gp;
  REQUIRE(model.zone_task_count() == 21);
  const int saved_threads = max_threads();
  set_threads(1);
  auto reference_model = model;
  node_set reference = gp;
  reference_model.accumulate_forces(reference);
  const auto bytes = static_cast<std::size_t>(reference.force.size()) * sizeof(real);
  CHECK(reference.force.cwiseAbs().maxCoeff() > 0);
  for (idx split : {1, 3, 7, 8, 9, 13, 20}) {
    auto m = model;
    node_set split_gp = gp;
    m.add_zone_forces_of_tasks(split, m.zone_task_count(), split_gp);  // the later range first
    m.add_zone_forces_of_tasks(0, split, split_gp);
    INFO("split at task " << split);
    CHECK(std::memcmp(split_gp.force.data(), reference.force.data(), bytes) == 0);
    CHECK(std::memcmp(m.zone_stress().data(), reference_model.zone_stress().data(),
                      static_cast<std::size_t>(reference_model.zone_stress().size()) * sizeof(real)) == 0);
  }
  // parallel_range_pair: the ranges of f tile [0, n) and g sees each j once, on two threads.
  set_threads(2);
  for (std::int64_t n : {0, 1, 5, 40}) {
    std::vector<int> f_hits(static_cast<std::size_t>(n), 0), g_hits(37, 0);
    parallel_range_pair(
        n, [&](std::int64_t b, std::int64_t e) { for (std::int64_t i = b; i < e; ++i) ++f_hits[static_cast<std::size_t>(i)]; },
        37, [&](std::int64_t j) { ++g_hits[static_cast<std::size_t>(j)]; }, 1);
    INFO("n = " << n);
    CHECK(std::count(f_hits.begin(), f_hits.end(), 1) == n);
    CHECK(std::count(g_hits.begin(), g_hits.end(), 1) == 37);
  }
  set_threads(saved_threads);
}

TEST_CASE("vectorised zone kernel matches a direct per-zone evaluation, bit-identical for 1 and 2 threads",
          "[mechanics][zones]") {
  // 20 random Voronoi blocks (several zones each, so the kernel's per-block runs and vector
  // remainders are exercised), rotated by 0.3 rad about a skew axis plus a random 1e-6 m
  // displacement field (zone strains ~1e-4). Reference: for every zone, from the mesh alone and the block rotation R
  // the kernel used, H = sum_a u_a (x) grad N_a, eps = sym(R^T (1 + H)) - 1, sigma' = Hooke(eps),
  // f_a = -V R sigma' grad N_a assembled per gridpoint, Sigma = R sigma' R^T.
  const zones::linear_elastic_tet::params material{280e9, 0.2, 2400};
  rotated_voronoi_blocks scene(20, 3, 0.3, vec3(1, 2, 3), 7, material);
  const auto& mesh = scene.mesh;
  auto& model = scene.model;
  const node_set& gp = scene.gp;
  auto model2 = model;  // same warm start of the block rotations
  const int saved_threads = max_threads();
  set_threads(1);
  node_set one = gp;
  model.accumulate_forces(one);
  set_threads(2);
  node_set two = gp;
  model2.accumulate_forces(two);
  set_threads(saved_threads);
  CHECK(std::memcmp(one.force.data(), two.force.data(), static_cast<std::size_t>(one.force.size()) * sizeof(real)) == 0);

  const real lambda = zones::linear_elastic_tet::lame_lambda(material);
  const real mu = zones::linear_elastic_tet::shear_modulus(material);
  soa3 expected = soa3::Zero(gp.size(), 3);
  real stress_scale = 0, max_stress_error = 0;
  for (idx z = 0; z < model.zone_count(); ++z) {
    const auto& c = mesh.zones[static_cast<std::size_t>(z)];
    Eigen::Matrix3d j;
    for (int a = 1; a < 4; ++a)
      j.col(a - 1) = mesh.gridpoints[static_cast<std::size_t>(c[static_cast<std::size_t>(a)])] -
                     mesh.gridpoints[static_cast<std::size_t>(c[0])];
    const Eigen::Matrix3d j_inv = j.inverse();
    std::array<vec3, 4> grad;
    for (int a = 1; a < 4; ++a) grad[static_cast<std::size_t>(a)] = j_inv.row(a - 1).transpose();
    grad[0] = -(grad[1] + grad[2] + grad[3]);
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 4; ++a)
      h += gp.displacement.row(c[static_cast<std::size_t>(a)]).transpose() * grad[static_cast<std::size_t>(a)].transpose();
    const Eigen::Matrix3d r = model.rotation(mesh.zone_block[static_cast<std::size_t>(z)]);
    const Eigen::Matrix3d m = r.transpose() * (Eigen::Matrix3d::Identity() + h);
    const Eigen::Matrix3d eps = 0.5 * (m + m.transpose()) - Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d sigma = lambda * eps.trace() * Eigen::Matrix3d::Identity() + 2 * mu * eps;
    const Eigen::Matrix3d global = r * sigma * r.transpose();
    const real v = j.determinant() / 6;
    for (int a = 0; a < 4; ++a)
      expected.row(c[static_cast<std::size_t>(a)]) += (-v * r * sigma * grad[static_cast<std::size_t>(a)]).transpose();
    const auto& s = model.zone_stress();
    const real computed[6] = {s(z, 0), s(z, 1), s(z, 2), s(z, 3), s(z, 4), s(z, 5)};
    const real reference[6] = {global(0, 0), global(1, 1), global(2, 2), global(1, 2), global(2, 0), global(0, 1)};
    for (int k = 0; k < 6; ++k) {
      stress_scale = std::max(stress_scale, std::abs(reference[k]));
      max_stress_error = std::max(max_stress_error, std::abs(computed[k] - reference[k]));
    }
  }
  const real force_scale = expected.cwiseAbs().maxCoeff();
  REQUIRE(stress_scale > 1e6);  // the random field strains the zones
  CHECK(max_stress_error <= 1e-9 * stress_scale);
  CHECK((one.force - expected).cwiseAbs().maxCoeff() <= 1e-9 * force_scale);
}
