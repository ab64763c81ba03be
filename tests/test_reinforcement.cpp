// Tests for the reinforcement area: reinforcement::none, the truss and bond laws, host-zone
// embedding and embedded_truss<coulomb_bond> against closed forms (bare bar, shear-lag pull-out,
// Coulomb pull-out plateau), momentum conservation, stiffness bounds and input checks.
#include <catch2/catch.hpp>

#include "support/hand_meshes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "tessera/presets.hpp"
#include "tessera/reinforcement.hpp"

using namespace tessera;
using namespace tessera::reinforcement;
using truss = embedded_truss<coulomb_bond>;
using idx = tessera::index_t;  // plain `index` would be ambiguous with POSIX ::index

static_assert(Reinforcement<none>);
static_assert(!none::enabled);
static_assert(Reinforcement<truss>);
static_assert(truss::enabled);
static_assert(BondLaw<coulomb_bond>);

namespace {

// ---- a hand-made block_mesh: boxes side by side along x, each split into cubes and every cube
// into the 6 Kuhn tetrahedra around its main diagonal (conforming across cubes and blocks). Each
// block has its own copies of its gridpoints, as in geometry::zone_blocks. ----
geometry::block_mesh box_mesh(const vec3& lo, const vec3& hi, int cubes_x, int cubes_y, int cubes_z, int blocks_x = 1) {
  geometry::block_mesh m;
  const int per_block = cubes_x / blocks_x;
  const vec3 h((hi.x() - lo.x()) / cubes_x, (hi.y() - lo.y()) / cubes_y, (hi.z() - lo.z()) / cubes_z);
  for (int b = 0; b < blocks_x; ++b) {
    const idx first = m.gridpoint_count();
    const int nx = per_block + 1, ny = cubes_y + 1, nz = cubes_z + 1;
    auto id = [&](int i, int j, int k) { return first + static_cast<idx>((k * ny + j) * nx + i); };
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          m.gridpoints.push_back(vec3(lo.x() + (b * per_block + i) * h.x(), lo.y() + j * h.y(), lo.z() + k * h.z()));
          m.gridpoint_block.push_back(b);
          m.gridpoint_vertex.push_back(invalid_index);
        }
    const std::array<std::array<int, 3>, 6> orders{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
    for (int k = 0; k < cubes_z; ++k)
      for (int j = 0; j < cubes_y; ++j)
        for (int i = 0; i < per_block; ++i)
          for (const auto& o : orders) {
            std::array<int, 3> c{i, j, k};
            std::array<idx, 4> t{};
            t[0] = id(c[0], c[1], c[2]);
            for (int s = 0; s < 3; ++s) {
              ++c[static_cast<std::size_t>(o[static_cast<std::size_t>(s)])];
              t[static_cast<std::size_t>(s) + 1] = id(c[0], c[1], c[2]);
            }
            auto x = [&](int q) { return m.gridpoints[static_cast<std::size_t>(t[static_cast<std::size_t>(q)])]; };
            if ((x(1) - x(0)).cross(x(2) - x(0)).dot(x(3) - x(0)) < 0) std::swap(t[2], t[3]);
            m.zones.push_back(t);
            m.zone_block.push_back(b);
          }
    m.block_gridpoint_offsets.push_back(m.gridpoint_count());
    m.block_zone_offsets.push_back(m.zone_count());
  }
  return m;
}

node_set gridpoint_set(const geometry::block_mesh& m) {
  node_set s;
  s.resize(m.gridpoint_count());
  for (idx g = 0; g < m.gridpoint_count(); ++g) s.reference.row(g) = m.gridpoints[static_cast<std::size_t>(g)].transpose();
  s.mass.setOnes();
  return s;
}

/// The host rule of embedding.hpp by brute force over all zones.
idx brute_force_host(const geometry::block_mesh& m, const vec3& p) {
  auto min_w = [&](idx z) {
    const auto& t = m.zones[static_cast<std::size_t>(z)];
    const auto w = barycentric_weights(m.gridpoints[static_cast<std::size_t>(t[0])], m.gridpoints[static_cast<std::size_t>(t[1])],
                                       m.gridpoints[static_cast<std::size_t>(t[2])], m.gridpoints[static_cast<std::size_t>(t[3])], p);
    return *std::min_element(w.begin(), w.end());
  };
  real best = -zone_locator::tolerance;
  for (idx z = 0; z < m.zone_count(); ++z) best = std::max(best, min_w(z));
  for (idx z = 0; z < m.zone_count(); ++z)
    if (min_w(z) >= best - zone_locator::tolerance) return z;
  return invalid_index;
}

/// Deterministic pseudo-random numbers in [0, 1) (portable, unlike std:: distributions).
struct lcg {
  std::uint64_t x;
  real operator()() {
    x = x * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<real>(x >> 11) * 0x1.0p-53;
  }
};

// ---- a minimal explicit integrator for the dynamic tests (the solver's step order, study eq. 1):
// central differences on half-step velocities with local damping F_d = gamma |F| sgn(v); prescribed
// components move at their prescribed velocity and record the reaction -F (quasi-static). ----
void advance(node_set& s, real dt, real gamma) {
  for (idx i = 0; i < s.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      if (s.constraint(i, c) == static_cast<std::uint8_t>(dof_constraint::prescribed)) {
        s.velocity(i, c) = s.prescribed_velocity(i, c);
        s.reaction(i, c) = -s.force(i, c);
      } else {
        const real f = s.force(i, c), v = s.velocity(i, c);
        const real damping = gamma * std::abs(f) * static_cast<real>((v > 0) - (v < 0));
        s.velocity(i, c) += (f - damping) * dt / s.mass(i);
      }
      s.displacement(i, c) += s.velocity(i, c) * dt;
    }
}
/// One step with the gridpoints held fixed (their forces are computed and discarded).
void step(truss& r, node_set& gridpoints, real dt, real gamma = 0.8) {
  gridpoints.force.setZero();
  r.nodes().force.setZero();
  r.accumulate_forces(gridpoints, zone_stress_matrix{});
  advance(r.nodes(), dt, gamma);
}
/// 0.4 of the critical step 2 sqrt(m / k) of the bar nodes (local damping amplifies forces by up to 1 + gamma).
real stable_dt(truss& r, node_set& gridpoints) {
  r.add_stiffness_bounds(gridpoints);
  real dt = std::numeric_limits<real>::infinity();
  for (idx n = 0; n < r.node_count(); ++n) dt = std::min(dt, 2.0 * std::sqrt(r.nodes().mass(n) / r.nodes().stiffness(n)));
  return 0.4 * dt;
}
void prescribe(node_set& s, idx n, int c, real velocity) {
  s.constraint(n, c) = static_cast<std::uint8_t>(dof_constraint::prescribed);
  s.prescribed_velocity(n, c) = velocity;
}
/// Steps until the kinetic energy of the bar nodes is below `tolerance` times its peak (or max steps); returns steps.
int relax(truss& r, node_set& gridpoints, real dt, int max_steps, real tolerance = 1e-24) {
  real peak = 0.0;
  for (int s = 0; s < max_steps; ++s) {
    step(r, gridpoints, dt);
    const auto& n = r.nodes();
    real kinetic = 0.0;
    for (idx i = 0; i < n.size(); ++i) kinetic += 0.5 * n.mass(i) * n.velocity.row(i).squaredNorm();
    peak = std::max(peak, kinetic);
    if (s > 100 && kinetic <= tolerance * peak) return s;
  }
  return max_steps;
}

}  // namespace

TEST_CASE("reinforcement::none is an empty, disabled policy", "[reinforcement]") {
  none r;
  geometry::block_mesh mesh;
  node_set gp;
  r.build({}, mesh, gp);
  r.add_stiffness_bounds(gp);
  r.accumulate_forces(gp, zone_stress_matrix{});
  CHECK(r.nodes().size() == 0);
  CHECK(r.stored_energy() == 0.0);
  CHECK(r.dissipated_energy() == 0.0);
}

TEST_CASE("study tie steel: area, yield force and K_axial of 96 elements over 0.6 m", "[reinforcement]") {
  const steel s = pulatsu2020::tie_steel();
  CHECK(s.area() == Approx(50.27e-6).epsilon(1e-4));
  CHECK(s.yield_force() == Approx(20.1e3).epsilon(1e-3));
  const real k_axial = s.axial_rigidity() / (0.6 / 96);
  CHECK(k_axial == Approx(1.547e9).epsilon(1e-3));  // the study's 1.55 GN/m
  CHECK(4.0 * k_axial == Approx(6.19e9).epsilon(1e-3));  // K_bond, study: 6.19 GN/m
  CHECK(s.axial_rigidity() / 0.6 == Approx(16.1e6).epsilon(1e-3));  // bare bar 16.1 kN/mm
}

TEST_CASE("truss and bond return mappings: plateau and energy-consistent plastic work", "[reinforcement]") {
  const real k = 2e8, n_y = 1e4;
  const real e_y = n_y / k;  // yield elongation (m)
  truss_element::state s;
  // Steps landing on the kinks: load to 3 e_y (plastic 2 e_y), unload to -3 e_y through compressive
  // yield at e = 1 e_y (plastic -4 e_y): plastic work N_y (2 + 4) e_y, exact.
  for (real e : {0.5 * e_y, 1.0 * e_y, 3.0 * e_y}) truss_element::update(s, e, k, n_y);
  CHECK(s.axial_force == n_y);
  CHECK(s.yielding);
  CHECK(s.plastic_elongation == Approx(2.0 * e_y).epsilon(1e-14));
  truss_element::update(s, 2.5 * e_y, k, n_y);  // elastic unloading
  CHECK(s.axial_force == Approx(0.5 * n_y).epsilon(1e-12));
  CHECK_FALSE(s.yielding);
  CHECK(s.has_yielded);
  truss_element::update(s, 1.0 * e_y, k, n_y);
  truss_element::update(s, -3.0 * e_y, k, n_y);
  CHECK(s.axial_force == -n_y);
  CHECK(s.dissipated == Approx(6.0 * n_y * e_y).epsilon(1e-9));
  CHECK(truss_element::stored_energy(s, k) == Approx(0.5 * n_y * e_y).epsilon(1e-12));

  // Any path, any step size: trapezoidal work = stored + dissipated to rounding.
  truss_element::state r;
  lcg rng{3};
  real work = 0.0, e_old = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const real e = e_old + (rng() - 0.45) * 0.7 * e_y;
    const real n_old = r.axial_force;
    truss_element::update(r, e, k, n_y);
    work += 0.5 * (n_old + r.axial_force) * (e - e_old);
    e_old = e;
  }
  CHECK(r.dissipated > 10 * n_y * e_y);
  CHECK(work == Approx(truss_element::stored_energy(r, k) + r.dissipated).epsilon(1e-12));

  coulomb_bond::params p{4.0, 2e4, std::numbers::pi / 6};
  coulomb_bond::validate(p);
  // F_max = (c + sigma tan(phi) pi d) L_trib
  const real f_max = coulomb_bond::strength(p, 1e6, std::numbers::pi * 0.008, 0.01);
  CHECK(f_max == Approx((2e4 + 1e6 * std::tan(std::numbers::pi / 6) * std::numbers::pi * 0.008) * 0.01).epsilon(1e-14));
  coulomb_bond::state b;
  coulomb_bond::update(p, b, f_max / k, k, f_max);
  CHECK_FALSE(b.has_slipped);
  coulomb_bond::update(p, b, 3.0 * f_max / k, k, f_max);
  CHECK(b.force == f_max);
  CHECK(b.slipping);
  CHECK(b.dissipated == Approx(2.0 * f_max * f_max / k).epsilon(1e-12));
  // Confinement lost at fixed slip: the limit halves and the released spring energy
  // (f^2 - f^2/4) / (2 k) is dissipated.
  coulomb_bond::update(p, b, 3.0 * f_max / k, k, 0.5 * f_max);
  CHECK(b.force == 0.5 * f_max);
  CHECK(b.dissipated == Approx(2.375 * f_max * f_max / k).epsilon(1e-12));
}

TEST_CASE("confining stress: mean compression in the plane normal to the bar", "[reinforcement]") {
  Eigen::Matrix<real, 1, 6> s;
  s << -3e6, -5e6, 2e6, 1e6, -0.5e6, 0.7e6;  // xx yy zz yz zx xy
  mat3 sigma;
  sigma << s(0), s(5), s(4), s(5), s(1), s(3), s(4), s(3), s(2);
  for (const vec3& a : {vec3(1, 0, 0), vec3(1, 1, 0).normalized(), vec3(0.3, -0.4, 0.8).normalized()}) {
    const real expected = std::max(0.0, -0.5 * (sigma.trace() - a.dot(sigma * a)));
    CHECK(truss::confining_stress(s, a) == Approx(expected).margin(1e-6));
  }
  CHECK(truss::confining_stress(s, vec3(1, 0, 0)) == Approx(1.5e6).epsilon(1e-14));  // -(yy + zz)/2
  CHECK(truss::confining_stress(-s, vec3(1, 0, 0)) == 0.0);                          // tension: no confinement
}

TEST_CASE("embedding: weights sum to 1, reproduce linear fields and match the brute-force host", "[reinforcement][embedding]") {
  const auto mesh = box_mesh(vec3(-0.2, 0.1, 0.0), vec3(0.4, 0.5, 0.3), 4, 3, 2);
  const zone_locator locator(mesh.gridpoints, mesh.zones);
  mat3 grad;
  grad << 0.3, -1.2, 0.7, 2.1, 0.4, -0.9, -0.6, 1.5, 0.2;
  const vec3 shift(0.01, -0.02, 0.03);
  auto field = [&](const vec3& x) -> vec3 { return shift + grad * x; };
  lcg rng{42};
  for (int q = 0; q < 500; ++q) {
    const vec3 p(-0.2 + 0.6 * rng(), 0.1 + 0.4 * rng(), 0.3 * rng());
    const auto host = locator.locate(p);
    REQUIRE(host.has_value());
    CHECK(host->zone == brute_force_host(mesh, p));
    real sum = 0.0;
    vec3 x = vec3::Zero(), u = vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      const real w = host->weights[static_cast<std::size_t>(i)];
      CHECK(w >= -zone_locator::tolerance);
      const vec3& xi = mesh.gridpoints[static_cast<std::size_t>(host->gridpoints[static_cast<std::size_t>(i)])];
      sum += w;
      x += w * xi;
      u += w * field(xi);
    }
    CHECK(std::abs(sum - 1.0) < 1e-14);
    CHECK((x - p).norm() < 1e-15);
    CHECK((u - field(p)).norm() < 1e-12 * field(p).norm());
  }
  CHECK_FALSE(locator.locate(vec3(0.41, 0.2, 0.1)).has_value());
  CHECK_FALSE(locator.locate(vec3(0.0, 0.2, -1e-6)).has_value());
  CHECK(locator.locate(vec3(0.4, 0.5, 0.3)).has_value());  // a corner of the box
}

TEST_CASE("embedding: a node on a shared block face, edge or vertex gets one deterministic host", "[reinforcement][embedding]") {
  // Two blocks [0,0.5] and [0.5,1] x [0,1]^2, each with its own gridpoints; zones of block 0 come first.
  const auto mesh = box_mesh(vec3(0, 0, 0), vec3(1, 1, 1), 4, 2, 2, 2);
  const zone_locator locator(mesh.gridpoints, mesh.zones);
  const std::array<vec3, 4> on_shared{vec3(0.5, 0.3, 0.7), vec3(0.5, 0.5, 0.5), vec3(0.5, 0.25, 0.5), vec3(0.25, 0.5, 0.5)};
  for (const vec3& p : on_shared) {
    const auto host = locator.locate(p);
    REQUIRE(host.has_value());
    CHECK(host->zone == brute_force_host(mesh, p));
    CHECK(mesh.zone_block[static_cast<std::size_t>(host->zone)] == 0);
    // every zone touching p is tied at min weight 0, so the lowest id containing p wins
    idx lowest = invalid_index;
    for (idx z = 0; z < mesh.zone_count() && lowest == invalid_index; ++z) {
      const auto& t = mesh.zones[static_cast<std::size_t>(z)];
      const auto w = barycentric_weights(mesh.gridpoints[static_cast<std::size_t>(t[0])], mesh.gridpoints[static_cast<std::size_t>(t[1])],
                                         mesh.gridpoints[static_cast<std::size_t>(t[2])], mesh.gridpoints[static_cast<std::size_t>(t[3])], p);
      if (*std::min_element(w.begin(), w.end()) >= -zone_locator::tolerance) lowest = z;
    }
    CHECK(host->zone == lowest);
    CHECK(locator.locate(p)->zone == host->zone);
  }
  // A point strictly inside block 1 goes to block 1.
  CHECK(mesh.zone_block[static_cast<std::size_t>(locator.locate(vec3(0.8, 0.3, 0.6))->zone)] == 1);
  // A bar whose node 2 sits exactly on the shared face: one host, in block 0.
  truss r;
  truss::params p{pulatsu2020::tie_steel(), pulatsu2020::tie_bond(), {bar{vec3(0.1, 0.3, 0.7), vec3(0.9, 0.3, 0.7), 4, true}}};
  r.build(p, mesh, gridpoint_set(mesh));
  CHECK(r.host(2).zone == locator.locate(vec3(0.5, 0.3, 0.7))->zone);
  CHECK(mesh.zone_block[static_cast<std::size_t>(r.host(3).zone)] == 1);
}

TEST_CASE("embedded_truss: bond forces conserve momentum, stiffness bounds dominate the block rows", "[reinforcement]") {
  const auto mesh = box_mesh(vec3(0, 0, 0), vec3(1, 0.6, 0.6), 4, 2, 2, 2);
  node_set gp = gridpoint_set(mesh);
  truss r;
  truss::params p{pulatsu2020::tie_steel(), coulomb_bond::params{4.0, 2e5, 0.5}, {bar{vec3(0.05, 0.1, 0.2), vec3(0.95, 0.5, 0.45), 13, true},
                                                                                  bar{vec3(0.2, 0.3, 0.05), vec3(0.3, 0.3, 0.55), 3, true}}};
  r.build(p, mesh, gp);
  REQUIRE(r.node_count() == 14 + 4);
  REQUIRE(r.element_count() == 16);

  // Stiffness bounds: assemble the elastic stiffness by central differences (bar nodes then
  // gridpoints) and check each bound against the block row sum of spectral norms.
  r.add_stiffness_bounds(gp);
  const idx nb = r.node_count(), ng = gp.size(), n = nb + ng;
  Eigen::MatrixXd k(3 * n, 3 * n);
  const real h = 1e-9;
  auto forces = [&](idx node, int c, real delta) {
    truss probe = r;
    node_set g = gp;
    if (node < nb) probe.nodes().displacement(node, c) += delta; else g.displacement(node - nb, c) += delta;
    probe.nodes().force.setZero();
    g.force.setZero();
    probe.accumulate_forces(g, zone_stress_matrix{});
    Eigen::VectorXd f(3 * n);
    for (idx i = 0; i < nb; ++i) for (int d = 0; d < 3; ++d) f(3 * i + d) = probe.nodes().force(i, d);
    for (idx i = 0; i < ng; ++i) for (int d = 0; d < 3; ++d) f(3 * (nb + i) + d) = g.force(i, d);
    return f;
  };
  for (idx j = 0; j < n; ++j)
    for (int c = 0; c < 3; ++c) k.col(3 * j + c) = -(forces(j, c, h) - forces(j, c, -h)) / (2 * h);
  for (idx i = 0; i < n; ++i) {
    real row = 0.0;
    for (idx j = 0; j < n; ++j) row += Eigen::Matrix3d(k.block(3 * i, 3 * j, 3, 3)).jacobiSvd().singularValues()(0);
    const real bound = i < nb ? r.nodes().stiffness(i) : gp.stiffness(i - nb);
    CHECK(row <= bound * (1 + 1e-5) + 1e-3);
  }
  // The bound is reached on a bar node (it is a row sum, not an overestimate).
  CHECK(r.nodes().stiffness(5) == Approx(4.0 * r.axial_stiffness(5) + 2.0 * r.bond_stiffness(5)).epsilon(1e-12));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (k + k.transpose()));
  real max_bound = std::max(r.nodes().stiffness.maxCoeff(), gp.stiffness.maxCoeff());
  CHECK(eig.eigenvalues().maxCoeff() <= max_bound * (1 + 1e-6));

  // Momentum: random displacements of gridpoints and bar nodes, random confinement; the sum of all
  // forces vanishes to rounding at every call, through elastic and slipping states.
  lcg rng{7};
  zone_stress_matrix stress(mesh.zone_count(), 6);
  for (idx z = 0; z < mesh.zone_count(); ++z) for (int c = 0; c < 6; ++c) stress(z, c) = -2e6 * rng() + (c < 3 ? -1e6 : 0.0);
  bool some_slip = false;
  for (int call = 0; call < 5; ++call) {
    const real scale = 1e-4 * (call + 1);
    for (idx i = 0; i < ng; ++i) for (int c = 0; c < 3; ++c) gp.displacement(i, c) = scale * (rng() - 0.5);
    for (idx i = 0; i < nb; ++i) for (int c = 0; c < 3; ++c) r.nodes().displacement(i, c) = scale * (rng() - 0.5);
    gp.force.setZero();
    r.nodes().force.setZero();
    // The split used by the solver's fused gather (compute_forces, then add_host_forces over
    // gridpoint ranges) must give the same bits, also on top of forces already gathered.
    truss split = r;
    node_set gp_split = gp;
    soa3 preload(ng, 3);
    for (idx i = 0; i < ng; ++i) for (int c = 0; c < 3; ++c) preload(i, c) = rng() - 0.5;
    gp_split.force = preload;
    split.compute_forces(gp_split, stress);
    for (idx g = 0; g < ng; g += 3) split.add_host_forces(g, std::min(ng, g + 3), gp_split);
    node_set gp_whole = gp;
    gp_whole.force = preload;
    truss whole = r;
    whole.accumulate_forces(gp_whole, stress);
    CHECK(gp_split.force == gp_whole.force);
    CHECK(split.nodes().force == whole.nodes().force);
    r.accumulate_forces(gp, stress);
    const vec3 total = (gp.force.colwise().sum() + r.nodes().force.colwise().sum()).transpose();
    const real magnitude = gp.force.cwiseAbs().maxCoeff() + r.nodes().force.cwiseAbs().maxCoeff();
    CHECK(total.norm() <= 1e-13 * magnitude);
    for (idx i = 0; i < nb; ++i) {
      some_slip = some_slip || r.bond_slipping(i);
      CHECK(r.confining_stress(i) >= 0.0);
    }
  }
  CHECK(some_slip);
  CHECK(r.dissipated_bond() > 0.0);
}

TEST_CASE("bare bar pulled at one end: exact elastic-plastic force-elongation", "[reinforcement][dynamic]") {
  // Node 0 fixed, node N pulled along the bar slowly in stages; after each stage the end is held
  // and the bar relaxes (local damping only damps oscillations whose velocity changes sign,
  // so the end force is read in equilibrium, not while the bar drifts).
  const real length = 0.6;
  const steel s = pulatsu2020::tie_steel();
  truss r;
  r.build({s, pulatsu2020::tie_bond(), {bar{vec3(0, 0, 0), vec3(length, 0, 0), 10, false}}}, geometry::block_mesh{}, node_set{});
  node_set gp;
  const idx last = r.node_count() - 1;
  for (int c = 0; c < 3; ++c) {
    prescribe(r.nodes(), 0, c, 0.0);
    prescribe(r.nodes(), last, c, 0.0);
  }
  const real e_y = s.yield_force() * length / s.axial_rigidity();  // yield elongation (m)
  const real dt = stable_dt(r, gp);
  std::vector<real> elongation, force, force_at_fixed_end;
  real target_old = 0.0;
  for (real target : {0.3 * e_y, 0.8 * e_y, 1.2 * e_y, 1.6 * e_y, 2.0 * e_y}) {
    // Smooth velocity pulse v(t) = (Delta / T)(1 - cos(2 pi t / T)): no velocity jump, so neither
    // a stress wave nor a dynamic overshoot beyond the yield force.
    const int steps = 20000;
    for (int i = 0; i < steps; ++i) {
      const real phase = 2.0 * std::numbers::pi * (i + 0.5) / steps;
      r.nodes().prescribed_velocity(last, 0) = (target - target_old) / (steps * dt) * (1.0 - std::cos(phase));
      step(r, gp, dt);
    }
    r.nodes().prescribed_velocity(last, 0) = 0.0;
    relax(r, gp, dt, 200000);
    target_old = target;
    elongation.push_back(r.nodes().displacement(last, 0));
    force.push_back(r.nodes().reaction(last, 0));
    force_at_fixed_end.push_back(-r.nodes().reaction(0, 0));
  }
  CHECK(elongation[1] == Approx(0.8 * e_y).epsilon(1e-9));
  const real slope = (force[1] - force[0]) / (elongation[1] - elongation[0]);
  CHECK(slope == Approx(s.axial_rigidity() / length).epsilon(1e-6));
  CHECK(force[1] == Approx(s.axial_rigidity() / length * elongation[1]).epsilon(1e-6));
  for (std::size_t i = 0; i < force.size(); ++i) CHECK(force_at_fixed_end[i] == Approx(force[i]).epsilon(1e-9));
  // Plateau at f_y A, exact; plastic work = f_y A x plastic elongation (up to the kink steps).
  // (residual inertia of the slow pulses leaves ~1e-8 below the plateau)
  for (std::size_t i = 2; i < force.size(); ++i) CHECK(force[i] == Approx(s.yield_force()).epsilon(1e-7));
  const real plastic = elongation.back() - e_y;
  CHECK(r.dissipated_axial() == Approx(s.yield_force() * plastic).epsilon(1e-4));
  bool any_yielded = false;
  for (idx e = 0; e < r.element_count(); ++e) any_yielded = any_yielded || r.yielded(e);
  CHECK(any_yielded);
}

namespace {
/// Pull-out stiffness (N/m) of a bar on the axis of a fixed 0.6 m block: the end node x is moved by
/// `pull` m, the rest relaxes; returns reaction / pull.
real pull_out_stiffness(idx elements, real xi, real* relax_steps = nullptr) {
  const real length = 0.6;
  const auto mesh = box_mesh(vec3(0, 0, 0), vec3(length, 0.05, 0.05), 12, 1, 1);
  node_set gp = gridpoint_set(mesh);
  truss r;
  r.build({pulatsu2020::tie_steel(), coulomb_bond::params{xi, 1e12, 0.0}, {bar{vec3(0, 0.02, 0.03), vec3(length, 0.02, 0.03), elements, true}}},
          mesh, gp);
  const idx last = r.node_count() - 1;
  prescribe(r.nodes(), last, 0, 0.0);
  const real pull = 1e-5;
  r.nodes().displacement(last, 0) = pull;
  const real dt = stable_dt(r, gp);
  const int steps = relax(r, gp, dt, 400000);
  if (relax_steps) *relax_steps = steps;
  return r.nodes().reaction(last, 0) / pull;
}
}  // namespace

TEST_CASE("pull-out of a bar from a fixed host: discrete and shear-lag closed forms", "[reinforcement][dynamic]") {
  const steel s = pulatsu2020::tie_steel();
  const real length = 0.6, ea = s.axial_rigidity();
  SECTION("study's xi = 4, 96 elements: exact discrete chain solution") {
    // Chain of springs K_axial with bond springs xi K_axial (interior) and xi K_axial / 2 (ends) to a
    // fixed host, free far end: u_i = C cosh(mu i) with cosh(mu) = 1 + xi / 2, so the end stiffness
    // is K = K_axial sinh(mu) tanh(mu N).
    const idx n = 96;
    const real xi = 4.0, k_axial = ea / (length / n), mu = std::acosh(1.0 + xi / 2);
    CHECK(pull_out_stiffness(n, xi) == Approx(k_axial * std::sinh(mu) * std::tanh(mu * n)).epsilon(1e-6));
    // The continuum shear-lag value E A lambda with lambda = sqrt(xi) / L_el is 29 % lower here:
    // at xi = 4 the transfer length 1 / lambda = L_el / 2 is shorter than an element.
  }
  SECTION("fixed bond modulus k_b, refined: converges to E A lambda tanh(lambda L) at O(L_el^2)") {
    const real lambda = 8.0 / length;  // lambda L = 8
    const real continuum = ea * lambda * std::tanh(lambda * length);
    std::vector<real> error;
    for (idx n : {24, 48, 96}) {
      const real element = length / n;
      const real xi = lambda * lambda * element * element;  // k_b = K_bond / L_el = xi E A / L_el^2
      error.push_back(pull_out_stiffness(n, xi) / continuum - 1.0);
      UNSCOPED_INFO("N = " << n << ": relative error " << error.back());
    }
    // Observed: +1.39e-2 (N = 24), +3.47e-3 (48), +8.68e-4 (96); leading term (lambda L_el)^2 / 8.
    CHECK(std::abs(error[2]) < 1e-3);
    CHECK(error[0] / error[1] == Approx(4.0).epsilon(0.02));
    CHECK(error[1] / error[2] == Approx(4.0).epsilon(0.02));
  }
}

TEST_CASE("pull-out with a weak Coulomb bond plateaus at c_bond L", "[reinforcement][dynamic]") {
  const real length = 0.6, c_bond = 1e4;  // total bond strength 6 kN < yield force 20.1 kN
  const auto mesh = box_mesh(vec3(0, 0, 0), vec3(length, 0.05, 0.05), 12, 1, 1);
  node_set gp = gridpoint_set(mesh);
  truss r;
  r.build({pulatsu2020::tie_steel(), coulomb_bond::params{4.0, c_bond, 0.0}, {bar{vec3(0, 0.025, 0.025), vec3(length, 0.025, 0.025), 48, true}}},
          mesh, gp);
  const idx last = r.node_count() - 1;
  const real dt = stable_dt(r, gp);
  prescribe(r.nodes(), last, 0, 0.0);
  // Pull in stages, relaxing after each: the end force grows while slip spreads from the loaded
  // end, then stays at c_bond L once every node slips.
  std::vector<real> force;
  real pulled_old = 0.0;
  for (real pulled : {2e-5, 5e-5, 1e-4, 2e-4, 4e-4}) {
    const int steps = 2000;
    r.nodes().prescribed_velocity(last, 0) = (pulled - pulled_old) / (steps * dt);
    for (int i = 0; i < steps; ++i) step(r, gp, dt);
    r.nodes().prescribed_velocity(last, 0) = 0.0;
    relax(r, gp, dt, 200000);
    pulled_old = pulled;
    force.push_back(r.nodes().reaction(last, 0));
    UNSCOPED_INFO("end displacement " << pulled << " m: force " << force.back() << " N");
  }
  CHECK(force[0] < 0.9 * c_bond * length);  // partial slip
  for (std::size_t i = 1; i < force.size(); ++i) CHECK(force[i] >= force[i - 1] * (1 - 1e-9));
  CHECK(force.back() == Approx(c_bond * length).epsilon(1e-6));
  for (idx n = 0; n < r.node_count(); ++n) CHECK(r.bond(n).has_slipped);
  // Plastic slip of node n is u_n - F_a / K_bond; the work of slip is c_bond L_trib per unit slip.
  real expected = 0.0;
  for (idx n = 0; n < r.node_count(); ++n) expected += r.bond_force(n) * (r.slip(n) - r.bond_force(n) / r.bond_stiffness(n));
  CHECK(r.dissipated_bond() == Approx(expected).epsilon(0.05));
}

TEST_CASE("embedded_truss rejects bad input with a message naming it", "[reinforcement][input]") {
  const auto mesh = box_mesh(vec3(0, 0, 0), vec3(1, 1, 1), 2, 2, 2);
  const node_set gp = gridpoint_set(mesh);
  auto build = [&](truss::params p) { truss r; r.build(p, mesh, gp); };
  const bar inside{vec3(0.1, 0.5, 0.5), vec3(0.9, 0.5, 0.5), 8, true};
  truss::params ok{pulatsu2020::tie_steel(), pulatsu2020::tie_bond(), {inside}};
  CHECK_NOTHROW(build(ok));

  auto p = ok;
  p.bars.push_back(bar{vec3(0.5, 0.5, 0.5), vec3(1.5, 0.5, 0.5), 4, true});
  CHECK_THROWS_AS(build(p), invalid_input);
  CHECK_THROWS_WITH(build(p), Catch::Contains("bar 1 node 3") && Catch::Contains("(1.25, 0.5, 0.5)") && Catch::Contains("outside every zone"));
  p = ok;
  p.bars[0].end = p.bars[0].start;
  CHECK_THROWS_WITH(build(p), Catch::Contains("bar 0") && Catch::Contains("element length = 0"));
  p = ok;
  p.bars[0].elements = 0;
  CHECK_THROWS_WITH(build(p), Catch::Contains("bar 0") && Catch::Contains("elements = 0"));
  p = ok;
  p.steel.diameter = 0.0;
  CHECK_THROWS_WITH(build(p), Catch::Contains("diameter") && Catch::Contains("must be finite and > 0"));
  p = ok;
  p.steel.young_modulus = -1.0;
  CHECK_THROWS_WITH(build(p), Catch::Contains("Young's modulus") && Catch::Contains("= -1"));
  p = ok;
  p.steel.yield_stress = 0.0;
  CHECK_THROWS_WITH(build(p), Catch::Contains("yield stress"));
  p = ok;
  p.bond.stiffness_ratio = 0.0;
  CHECK_THROWS_WITH(build(p), Catch::Contains("xi") && Catch::Contains("= 0"));
  p = ok;
  p.bond.cohesion = -5.0;
  CHECK_THROWS_WITH(build(p), Catch::Contains("c_bond") && Catch::Contains("= -5"));
  p = ok;
  p.bars.clear();
  CHECK_THROWS_WITH(build(p), Catch::Contains("no bars"));
  // A bar exactly on the surface of the mesh is inside (within the tolerance).
  p = ok;
  p.bars[0] = bar{vec3(0, 0, 0), vec3(1, 1, 1), 5, true};
  CHECK_NOTHROW(build(p));
}

// ---- through the solver (tessera::solver composes blocks, contacts and this reinforcement) ----
#if __has_include("tessera/solver/solver.hpp") && __has_include("tessera/geometry/zoning.hpp")
#include "tessera/geometry/zoning.hpp"
#include "tessera/solver.hpp"

namespace {
/// One box [lo, hi] as a single-cell tessellation.
geometry::tessellation box_cell(const vec3& lo, const vec3& hi) { return test::box_tessellation(lo, hi); }
}  // namespace

TEST_CASE("solver with embedded_truss: Coulomb pull-out from a fixed zoned block, energy balance", "[reinforcement][solver]") {
  using tie_solver = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<law::study_tie_law>, truss>;
  const real a = 0.068, length = 0.3, c_bond = 1e4;
  const auto tess = box_cell(vec3(0, 0, 0), vec3(a, a, length));
  const auto mesh = geometry::zone_blocks(tess);  // one zone per face triangle: hosts are large tets
  truss::params bars{pulatsu2020::tie_steel(), coulomb_bond::params{4.0, c_bond, 0.0},
                     {bar{vec3(a / 2, a / 2, 0), vec3(a / 2, a / 2, length), 48, true}}};
  // Mass scaling to about the bar's own critical step (~7e-7 s): the block is fixed anyway, and
  // the pull becomes quasi-static in few steps.
  solver_options options;
  options.mass_scaling_dt = 5e-7;
  tie_solver s(tess, mesh, zones::linear_elastic_tet::params{280e9, 0.2, 2400}, law::study_prism_params(100), bars,
               options);
  CHECK(s.dt() == Approx(5e-7).epsilon(1e-12));
  s.fix(bc::all_nodes(s.gridpoints()));
  node_set& nodes = s.bar_nodes();
  const idx last = nodes.size() - 1;
  bc::fix(nodes, bc::node_group{{last}, "pulled bar end"}, bc::components::z);
  REQUIRE(s.dt() > 0);
  real pulled_old = 0.0;
  std::vector<real> force;
  for (real pulled : {2e-5, 2e-4}) {
    const int steps = 8000;
    for (int i = 0; i < steps; ++i) {
      const real phase = 2.0 * std::numbers::pi * (i + 0.5) / steps;
      nodes.prescribed_velocity(last, 2) = (pulled - pulled_old) / (steps * s.dt()) * (1.0 - std::cos(phase));
      s.step();
    }
    nodes.prescribed_velocity(last, 2) = 0.0;
    s.run(8000);
    pulled_old = pulled;
    force.push_back(nodes.reaction(last, 2));
  }
  CHECK(nodes.displacement(last, 2) == Approx(2e-4).epsilon(1e-9));
  CHECK(force[0] < 0.9 * c_bond * length);
  CHECK(force[1] == Approx(c_bond * length).epsilon(1e-6));
  const energy_balance e = s.energies();
  INFO("boundary work " << e.boundary_work << " J, bars stored " << e.reinforcement_stored << " J, dissipated "
                        << e.reinforcement_dissipated << " J, damping " << e.damping_dissipated << " J");
  CHECK(e.reinforcement_dissipated > 0.5 * e.boundary_work);
  CHECK(e.error_rel() < 1e-6);
}
#endif

TEST_CASE("coulomb_bond: stiffness basis per node and per unit bar length", "[reinforcement]") {
  // Eq. 9 read per node: K_bond = xi K_axial at an interior node, half at the ends. Read as 3DEC's
  // grout stiffness (a modulus per metre of bar): K_bond = xi K_axial L_el at an interior node.
  const auto mesh = box_mesh(vec3(0, 0, 0), vec3(1, 0.6, 0.6), 4, 2, 2, 2);
  const node_set gp = gridpoint_set(mesh);
  const bar b{vec3(0.05, 0.3, 0.3), vec3(0.95, 0.3, 0.3), 9, true};
  const real l_el = 0.9 / 9;
  for (const auto basis : {stiffness_basis::per_node, stiffness_basis::per_unit_length}) {
    truss r;
    r.build({pulatsu2020::tie_steel(), pulatsu2020::tie_bond(basis), {b}}, mesh, gp);
    const real k_axial = r.axial_stiffness(0);
    REQUIRE(k_axial == Approx(pulatsu2020::tie_steel().axial_rigidity() / l_el).epsilon(1e-12));
    const real interior = basis == stiffness_basis::per_node ? 4.0 * k_axial : 4.0 * k_axial * l_el;
    for (idx n = 1; n < 9; ++n) CHECK(r.bond_stiffness(n) == Approx(interior).epsilon(1e-12));
    CHECK(r.bond_stiffness(0) == Approx(0.5 * interior).epsilon(1e-12));
    CHECK(r.bond_stiffness(9) == Approx(0.5 * interior).epsilon(1e-12));
  }
  // The study's tie: 96 elements over 0.6 m, xi = 4: 6.19 GN/m per node, or 6.19e9 N/m per metre
  // of bar, i.e. 38.7 MN/m per interior node with L_el = 6.25 mm.
  truss tie;
  const auto tie_mesh = box_mesh(vec3(-0.034, -0.034, 0), vec3(0.034, 0.034, 0.6), 2, 2, 8, 1);
  tie.build(pulatsu2020::tie_reinforcement(vec3(0, 0, 0), vec3(0, 0, 0.6)), tie_mesh, gridpoint_set(tie_mesh));
  CHECK(tie.bond_stiffness(50) == Approx(4.0 * 1.547e9 * 0.00625).epsilon(1e-3));
  CHECK(pulatsu2020::tie_bond().basis == stiffness_basis::per_unit_length);
}
