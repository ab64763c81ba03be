// Tests for contact/: sub-contact creation from a conforming tessellation, contact kinematics and
// the per-step force kernel of contact::face_contacts (include/tessera/contact/face_contacts.hpp).
//
// Scenes are built by hand so the tests depend only on the tessellation/block_mesh data layout:
// brick_tessellation() makes an nx x ny x nz grid of hexahedral cells with welded vertices
// (optionally jittered, which keeps faces conforming but makes them non-planar), and
// face_mesh() gives each cell its own copies of its vertices plus a centroid gridpoint, face
// nodes sorted by global vertex id (so twins pair coincident gridpoints in the same order),
// fan triangles and one-third tributary areas, exactly as block_mesh.hpp specifies.
#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <new>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <tessera/analysis.hpp>
#include <tessera/contact/detection/broad_phase.hpp>
#include <tessera/contact/detection/common_plane.hpp>
#include <tessera/contact/detection/detect.hpp>
#include <tessera/contact/face_contacts.hpp>
#include <tessera/io/vtk_contacts.hpp>
#include <tessera/presets.hpp>
#include <tessera/tessera.hpp>
#include <tessera/geometry/voronoi.hpp>
#include <tessera/geometry/zoning.hpp>
#include <vector>

// ---- allocation counter: replaces the global operator new of this test executable ----
namespace {
std::atomic<long> allocation_count{0};
std::atomic<bool> count_allocations{false};
}  // namespace
// GCC flags free() on memory from the (replaced) operator new once both are inlined into a
// new/delete pair; malloc/free are matched here by construction.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t size) {
  if (count_allocations.load(std::memory_order_relaxed)) allocation_count.fetch_add(1);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
// The nothrow and array forms must be replaced too: the library's defaults of those allocate
// with their own operator new, and freeing that memory with free() above is a mismatch
// (AddressSanitizer: alloc-dealloc-mismatch on memory Catch2 allocates with new(nothrow)).
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  if (count_allocations.load(std::memory_order_relaxed)) allocation_count.fetch_add(1);
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size) { return ::operator new(size); }
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept { return ::operator new(size, tag); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

// Everything below lives in a namespace nested in tessera, so `index` means tessera::index and
// not POSIX ::index from <strings.h>.
namespace tessera::test_contacts {
namespace {

using Catch::Matchers::Contains;

/// Linear elastic contact that breaks for good (no tension, no shear) once sigma_n exceeds f_t:
/// a closed-form reference law independent of law/. The stored shear stress is turned into the
/// new contact plane keeping its magnitude, as law::ContactLaw requires.
struct elastic_brittle_law {
  struct params {
    real k_n = 0;                                      ///< Pa/m
    real k_s = 0;                                      ///< Pa/m
    real f_t = std::numeric_limits<real>::infinity();  ///< Pa
  };
  struct state {
    real sigma_n = 0;
    vec3 tau = vec3::Zero();
    real u_n = 0;
    bool broken = false;
    real dissipated_tension = 0, dissipated_shear = 0, dissipated_compression = 0;
  };
  static void validate(const params& p) {
    require_positive(p.k_n, "elastic_brittle_law: k_n (Pa/m)");
    require_positive(p.k_s, "elastic_brittle_law: k_s (Pa/m)");
  }
  static real normal_stiffness(const params& p) { return p.k_n; }
  static real shear_stiffness(const params& p) { return p.k_s; }
  static void update(const params& p, state& s, real du_n, const vec3& du_s, const vec3& n) noexcept {
    const real magnitude = s.tau.norm();
    s.tau -= s.tau.dot(n) * n;
    if (s.tau.norm() > 0) s.tau *= magnitude / s.tau.norm();
    s.u_n += du_n;
    s.sigma_n += p.k_n * du_n;
    s.tau += p.k_s * du_s;
    if (!s.broken && s.sigma_n > p.f_t) {
      s.broken = true;
      s.dissipated_tension += stored_energy(p, s);
    }
    if (s.broken) {
      s.sigma_n = std::min(0.0, p.k_n * s.u_n);
      s.tau.setZero();
    }
  }
  static law::contact_status status(const state& s) {
    return s.broken ? law::contact_status::broken_tension : law::contact_status::intact;
  }
  static real tensile_damage(const params&, const state& s) { return s.broken ? 1.0 : 0.0; }
  static real dissipated_energy(const state& s) { return s.dissipated_tension; }
  static real stored_energy(const params& p, const state& s) {
    return 0.5 * s.sigma_n * s.sigma_n / p.k_n + 0.5 * s.tau.squaredNorm() / p.k_s;
  }
};
static_assert(law::ContactLaw<elastic_brittle_law>);
static_assert(contact::ContactSet<contact::face_contacts<elastic_brittle_law>>);
static_assert(contact::ContactSet<contact::face_contacts<law::with_elastic_packs<law::study_tie_law>>>);

/// nx x ny x nz hexahedral cells filling [0, size]; interior vertices moved by up to `jitter`
/// times the cell size in each direction (faces stay conforming, no longer planar).
geometry::tessellation brick_tessellation(int nx, int ny, int nz, const vec3& size, real jitter = 0,
                                          unsigned seed = 1) {
  geometry::tessellation t;
  t.domain.expand(vec3::Zero());
  t.domain.expand(size);
  const vec3 h(size.x() / nx, size.y() / ny, size.z() / nz);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<real> uni(-1.0, 1.0);
  const auto vid = [&](int i, int j, int k) { return static_cast<index_t>((i * (ny + 1) + j) * (nz + 1) + k); };
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= ny; ++j)
      for (int k = 0; k <= nz; ++k) {
        vec3 x(i * h.x(), j * h.y(), k * h.z());
        const bool interior = i > 0 && i < nx && j > 0 && j < ny && k > 0 && k < nz;
        if (interior && jitter > 0)
          for (int c = 0; c < 3; ++c) x[c] += jitter * h[c] * uni(rng);
        t.vertices.push_back(x);
      }
  const auto cid = [&](int i, int j, int k) { return static_cast<index_t>((i * ny + j) * nz + k); };
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) {
        const index_t c = cid(i, j, k);
        const auto v = [&](int dx, int dy, int dz) { return vid(i + dx, j + dy, k + dz); };
        // CCW seen from outside, sides x-, x+, y-, y+, z-, z+.
        const std::array<std::array<index_t, 4>, 6> loops{{{v(0, 0, 0), v(0, 0, 1), v(0, 1, 1), v(0, 1, 0)},
                                                         {v(1, 0, 0), v(1, 1, 0), v(1, 1, 1), v(1, 0, 1)},
                                                         {v(0, 0, 0), v(1, 0, 0), v(1, 0, 1), v(0, 0, 1)},
                                                         {v(0, 1, 0), v(0, 1, 1), v(1, 1, 1), v(1, 1, 0)},
                                                         {v(0, 0, 0), v(0, 1, 0), v(1, 1, 0), v(1, 0, 0)},
                                                         {v(0, 0, 1), v(1, 0, 1), v(1, 1, 1), v(0, 1, 1)}}};
        const std::array<index_t, 6> neighbor{i > 0 ? cid(i - 1, j, k) : geometry::boundary_tag(0),
                                            i + 1 < nx ? cid(i + 1, j, k) : geometry::boundary_tag(1),
                                            j > 0 ? cid(i, j - 1, k) : geometry::boundary_tag(2),
                                            j + 1 < ny ? cid(i, j + 1, k) : geometry::boundary_tag(3),
                                            k > 0 ? cid(i, j, k - 1) : geometry::boundary_tag(4),
                                            k + 1 < nz ? cid(i, j, k + 1) : geometry::boundary_tag(5)};
        for (int side = 0; side < 6; ++side) {
          const index_t f = t.face_count();
          t.face_vertices.insert(t.face_vertices.end(), loops[side].begin(), loops[side].end());
          t.face_offsets.push_back(static_cast<index_t>(t.face_vertices.size()));
          t.face_cell.push_back(c);
          t.face_neighbor.push_back(neighbor[side]);
          const index_t twin = neighbor[side] >= 0 ? neighbor[side] * 6 + (side ^ 1) : invalid_index;
          t.face_twin.push_back(twin);
          if (neighbor[side] > c) t.shared_faces.push_back({c, f, neighbor[side], twin});
        }
        t.cell_face_offsets.push_back(t.face_count());
      }
  return t;
}

/// Gridpoints and face data (no zones) per block_mesh.hpp: vertex copies sorted by global id plus
/// the vertex centroid, face nodes sorted by global vertex id, fan triangles from the face's
/// smallest vertex id, tributary area = 1/3 of each touching triangle.
geometry::block_mesh face_mesh(const geometry::tessellation& t) {
  geometry::block_mesh m;
  for (index_t c = 0; c < t.cell_count(); ++c) {
    std::vector<index_t> ids;
    for (index_t f = t.first_face(c); f < t.end_face(c); ++f)
      for (index_t v : t.face(f)) ids.push_back(v);
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    const auto base = static_cast<index_t>(m.gridpoints.size());
    const auto local = [&](index_t v) {
      return base + static_cast<index_t>(std::lower_bound(ids.begin(), ids.end(), v) - ids.begin());
    };
    vec3 centroid = vec3::Zero();
    for (index_t v : ids) {
      m.gridpoints.push_back(t.vertices[static_cast<std::size_t>(v)]);
      m.gridpoint_block.push_back(c);
      m.gridpoint_vertex.push_back(v);
      centroid += t.vertices[static_cast<std::size_t>(v)] / static_cast<real>(ids.size());
    }
    m.gridpoints.push_back(centroid);
    m.gridpoint_block.push_back(c);
    m.gridpoint_vertex.push_back(invalid_index);
    m.block_gridpoint_offsets.push_back(static_cast<index_t>(m.gridpoints.size()));
    m.block_zone_offsets.push_back(0);
    for (index_t f = t.first_face(c); f < t.end_face(c); ++f) {
      const auto loop = t.face(f);
      const auto n = static_cast<index_t>(loop.size());
      std::vector<index_t> sorted(loop.begin(), loop.end());
      std::sort(sorted.begin(), sorted.end());
      const index_t start = static_cast<index_t>(std::min_element(loop.begin(), loop.end()) - loop.begin());
      std::vector<real> area(static_cast<std::size_t>(n), 0.0);
      for (index_t i = 1; i + 1 < n; ++i) {
        const std::array<index_t, 3> tri{loop[static_cast<std::size_t>(start)],
                                       loop[static_cast<std::size_t>((start + i) % n)],
                                       loop[static_cast<std::size_t>((start + i + 1) % n)]};
        const auto& x = t.vertices;
        const real a = 0.5 * (x[static_cast<std::size_t>(tri[1])] - x[static_cast<std::size_t>(tri[0])])
                                 .cross(x[static_cast<std::size_t>(tri[2])] - x[static_cast<std::size_t>(tri[0])])
                                 .norm();
        for (index_t v : tri)
          area[static_cast<std::size_t>(std::lower_bound(sorted.begin(), sorted.end(), v) - sorted.begin())] += a / 3;
        m.face_triangles.push_back({local(tri[0]), local(tri[1]), local(tri[2])});
      }
      for (std::size_t k = 0; k < sorted.size(); ++k) {
        m.face_nodes.push_back(local(sorted[k]));
        m.face_node_area.push_back(area[k]);
      }
      m.face_node_offsets.push_back(static_cast<index_t>(m.face_nodes.size()));
      m.face_triangle_offsets.push_back(static_cast<index_t>(m.face_triangles.size()));
    }
  }
  return m;
}

/// what() of the E thrown by f, or a marker when f throws nothing (other exceptions propagate).
template <class E, class F>
std::string thrown_message(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "<nothing thrown>";
}

node_set gridpoints_of(const geometry::block_mesh& m) {
  node_set g;
  g.resize(m.gridpoint_count());
  for (index_t i = 0; i < m.gridpoint_count(); ++i)
    g.reference.row(i) = m.gridpoints[static_cast<std::size_t>(i)].transpose();
  return g;
}

/// One explicit step as the solver does it around contacts: u += v dt (velocities at the half
/// step just set), zero the forces, contact update.
template <class Set>
void step(Set& contacts, node_set& g, real dt) {
  g.displacement += g.velocity * dt;
  g.force.setZero();
  contacts.update(g, dt);
}

/// Sum of the contact forces on the gridpoints of block b (N).
vec3 block_force(const node_set& g, const geometry::block_mesh& m, index_t b) {
  vec3 f = vec3::Zero();
  for (index_t i = m.block_gridpoint_offsets[static_cast<std::size_t>(b)];
       i < m.block_gridpoint_offsets[static_cast<std::size_t>(b) + 1]; ++i)
    f += g.force.row(i).transpose();
  return f;
}

void set_block_velocity(node_set& g, const geometry::block_mesh& m, index_t b, const vec3& v) {
  for (index_t i = m.block_gridpoint_offsets[static_cast<std::size_t>(b)];
       i < m.block_gridpoint_offsets[static_cast<std::size_t>(b) + 1]; ++i)
    g.velocity.row(i) = v.transpose();
}

/// Two unit cubes sharing the face x = 1: cell 0 = [0,1]^3 (block A), cell 1 = [1,2]x[0,1]^2 (block B).
struct two_cubes {
  geometry::tessellation tess = brick_tessellation(2, 1, 1, vec3(2, 1, 1));
  geometry::block_mesh mesh = face_mesh(tess);
  node_set gridpoints = gridpoints_of(mesh);
};

}  // namespace

TEST_CASE("two cubes: one sub-contact per face node pair, areas sum to the face area, normal +x", "[contacts]") {
  two_cubes scene;
  REQUIRE(scene.tess.shared_faces.size() == 1);
  const contact::face_contacts<elastic_brittle_law> set(scene.tess, scene.mesh, {1e12, 4e11});
  REQUIRE(set.size() == 4);
  REQUIRE(set.face_count() == 1);
  real total = 0;
  for (index_t i = 0; i < set.size(); ++i) {
    CHECK(set.block_a(i) == 0);
    CHECK(set.block_b(i) == 1);
    CHECK(scene.mesh.gridpoint_block[static_cast<std::size_t>(set.node_a(i))] == 0);
    CHECK(scene.mesh.gridpoint_block[static_cast<std::size_t>(set.node_b(i))] == 1);
    const vec3 xa = scene.mesh.gridpoints[static_cast<std::size_t>(set.node_a(i))];
    CHECK(xa.x() == 1.0);
    CHECK((scene.mesh.gridpoints[static_cast<std::size_t>(set.node_b(i))] - xa).norm() == 0.0);
    CHECK((set.position(i, scene.gridpoints) - xa).norm() == 0.0);
    // Two triangles of area 1/2: the two diagonal nodes touch both (area 1/3), the others one (1/6).
    const bool on_diagonal = std::abs(set.area(i) - 1.0 / 3) < 1e-15;
    CHECK((on_diagonal || std::abs(set.area(i) - 1.0 / 6) < 1e-15));
    CHECK((set.normal(i) - vec3(1, 0, 0)).norm() < 1e-15);
    total += set.area(i);
  }
  CHECK(total == Approx(1.0).epsilon(1e-15));
  CHECK(set.face_area(0) == Approx(1.0).epsilon(1e-15));
  CHECK(set.first_subcontact(0) == 0);
  CHECK(set.first_subcontact(1) == 4);
}

TEST_CASE("areas sum to the face area and normals are unit A->B on a jittered brick grid", "[contacts]") {
  const auto tess = brick_tessellation(3, 3, 2, vec3(0.3, 0.3, 0.2), 0.2, 7);
  const auto mesh = face_mesh(tess);
  const contact::face_contacts<elastic_brittle_law> set(tess, mesh, {1e12, 4e11});
  REQUIRE(set.face_count() == static_cast<index_t>(tess.shared_faces.size()));
  REQUIRE(set.size() == 4 * set.face_count());
  for (index_t s = 0; s < set.face_count(); ++s) {
    // Face area = sum of its two fan triangles' areas.
    const auto loop = tess.face(tess.shared_faces[static_cast<std::size_t>(s)].face_a);
    const index_t start = static_cast<index_t>(std::min_element(loop.begin(), loop.end()) - loop.begin());
    real area = 0;
    vec3 area_vector = vec3::Zero();
    for (int i = 1; i < 3; ++i) {
      const vec3& x0 = tess.vertices[static_cast<std::size_t>(loop[static_cast<std::size_t>(start)])];
      const vec3& x1 = tess.vertices[static_cast<std::size_t>(loop[static_cast<std::size_t>((start + i) % 4)])];
      const vec3& x2 = tess.vertices[static_cast<std::size_t>(loop[static_cast<std::size_t>((start + i + 1) % 4)])];
      area += 0.5 * (x1 - x0).cross(x2 - x0).norm();
      area_vector += (x1 - x0).cross(x2 - x0);
    }
    real sum = 0;
    for (index_t i = set.first_subcontact(s); i < set.first_subcontact(s + 1); ++i) sum += set.area(i);
    CHECK(sum == Approx(area).epsilon(1e-13));
    const vec3 n = set.face_normal(s);
    CHECK(n.norm() == Approx(1.0).epsilon(1e-14));
    CHECK((n - area_vector.normalized()).norm() < 1e-14);  // outward of block A, pointing to B
    // A -> B: the centroid of block B lies on the positive side.
    const auto& sf = tess.shared_faces[static_cast<std::size_t>(s)];
    const vec3 ca = mesh.gridpoints[static_cast<std::size_t>(
        mesh.block_gridpoint_offsets[static_cast<std::size_t>(sf.cell_a) + 1] - 1)];
    const vec3 cb = mesh.gridpoints[static_cast<std::size_t>(
        mesh.block_gridpoint_offsets[static_cast<std::size_t>(sf.cell_b) + 1] - 1)];
    CHECK((cb - ca).dot(n) > 0);
  }
}

TEST_CASE("opening: restoring force k_n u_n area while elastic, on both nodes, with the stored energy", "[contacts]") {
  two_cubes scene;
  const real k_n = 1e12, k_s = 4e11;
  contact::face_contacts<elastic_brittle_law> set(scene.tess, scene.mesh, {k_n, k_s});
  const real dt = 1e-6, speed = 1e-3;  // opening 1e-9 m per step
  set_block_velocity(scene.gridpoints, scene.mesh, 1, vec3(speed, 0, 0));
  for (int k = 1; k <= 20; ++k) {
    step(set, scene.gridpoints, dt);
    const real opening = k * speed * dt;
    const vec3 on_b = block_force(scene.gridpoints, scene.mesh, 1);
    const vec3 on_a = block_force(scene.gridpoints, scene.mesh, 0);
    // Pulling B away from A (+x) is resisted: B is pulled back (-x), A is pulled toward B (+x).
    CHECK(on_b.x() == Approx(-k_n * opening * 1.0).epsilon(1e-10));
    CHECK(std::abs(on_b.y()) + std::abs(on_b.z()) < 1e-12 * k_n * opening);
    CHECK((on_a + on_b).norm() < 1e-12 * k_n * opening);
    for (index_t i = 0; i < set.size(); ++i) {
      CHECK(set.state(i).u_n == Approx(opening).epsilon(1e-10));
      CHECK(set.force(i).x() == Approx(-k_n * opening * set.area(i)).epsilon(1e-10));
      CHECK(scene.gridpoints.force(set.node_b(i), 0) == set.force(i).x());
      CHECK(scene.gridpoints.force(set.node_a(i), 0) == -set.force(i).x());
    }
    CHECK(set.stored_energy() == Approx(0.5 * k_n * opening * opening * 1.0).epsilon(1e-10));
  }
  // Closing past the initial position: compression pushes B away from A (+x).
  set_block_velocity(scene.gridpoints, scene.mesh, 1, vec3(-speed, 0, 0));
  for (int k = 0; k < 30; ++k) step(set, scene.gridpoints, dt);
  const vec3 on_b = block_force(scene.gridpoints, scene.mesh, 1);
  CHECK(on_b.x() == Approx(k_n * 10 * speed * dt).epsilon(1e-9));
  CHECK(set.state(0).sigma_n == Approx(-k_n * 10 * speed * dt).epsilon(1e-9));
}

TEST_CASE("shear slide: force k_s slip area against the slip, no normal force", "[contacts]") {
  two_cubes scene;
  const real k_n = 1e12, k_s = 4e11;
  contact::face_contacts<elastic_brittle_law> set(scene.tess, scene.mesh, {k_n, k_s});
  const real dt = 1e-6;
  const vec3 v(0, 2e-3, -1e-3);
  set_block_velocity(scene.gridpoints, scene.mesh, 1, v);
  for (int k = 1; k <= 10; ++k) {
    step(set, scene.gridpoints, dt);
    const vec3 slip = k * dt * v;
    const vec3 on_b = block_force(scene.gridpoints, scene.mesh, 1);
    CHECK((on_b + k_s * slip * 1.0).norm() < 1e-10 * k_s * slip.norm());
    CHECK(std::abs(set.state(0).sigma_n) < 1e-6);
  }
}

TEST_CASE("linear softening: force-opening curve = law x face area, separation dissipates G_f x area", "[contacts]") {
  two_cubes scene;
  law::linear_tie_law::params p;
  p.k_n = 1e12;
  p.k_s = 4e11;
  p.tension.f_T = 2e6;  // eta = f_T/k_n = 2e-6 m
  p.tension.G_f = 60;   // zeta = 2 G_f/f_T = 6e-5 m = 30 eta
  p.shear.c_0 = 4e6;
  p.shear.c_res = 4e4;
  p.shear.phi_0 = law::friction_angle::from_degrees(35);
  p.shear.phi_res = law::friction_angle::from_degrees(30);
  contact::face_contacts<law::linear_tie_law> set(scene.tess, scene.mesh, p);
  const real dt = 1e-6;
  const real du = 2e-7;  // eta / 10: steps land on the peak and on zeta (exact trapezoidal bookkeeping)
  set_block_velocity(scene.gridpoints, scene.mesh, 1, vec3(du / dt, 0, 0));
  const real eta = 2e-6, zeta = 6e-5;
  int broken_step = -1;
  for (int k = 1; k <= 320; ++k) {
    step(set, scene.gridpoints, dt);
    const real u = k * du;
    const real envelope = u <= eta ? p.k_n * u : (u < zeta ? p.tension.f_T * (zeta - u) / (zeta - eta) : 0.0);
    const vec3 on_b = block_force(scene.gridpoints, scene.mesh, 1);
    CHECK(-on_b.x() == Approx(envelope * 1.0).margin(1e-6 * p.tension.f_T));
    if (broken_step < 0 && set.broken_area() > 0) broken_step = k;
  }
  // zeta is reached at step 300 up to the rounding of the accumulated opening.
  CHECK((broken_step == 300 || broken_step == 301));
  CHECK(set.broken_area() == Approx(1.0).epsilon(1e-14));
  CHECK(set.face_fully_broken(0));
  CHECK(set.broken_face_count() == 1);
  const auto e = set.energies();
  CHECK(e.dissipated_tension == Approx(p.tension.G_f * 1.0).epsilon(1e-6));
  CHECK(e.dissipated == Approx(p.tension.G_f * 1.0).epsilon(1e-6));
  CHECK(std::abs(e.dissipated_shear) < 1e-12);
  CHECK(e.dissipated_compression == 0);
  CHECK(e.stored == 0);
}

TEST_CASE("Coulomb shear: k_s slip area up to c_0 - sigma_n tan phi_0, then the residual limit", "[contacts]") {
  two_cubes scene;
  law::linear_tie_law::params p;
  p.k_n = 1e12;
  p.k_s = 4e11;
  p.tension.f_T = 2e6;
  p.tension.G_f = 60;
  p.shear.c_0 = 4e6;
  p.shear.c_res = 4e4;
  p.shear.phi_0 = law::friction_angle::from_degrees(35);
  p.shear.phi_res = law::friction_angle::from_degrees(30);
  contact::face_contacts<law::linear_tie_law> set(scene.tess, scene.mesh, p);
  const real dt = 1e-6;
  // Precompress by 1e-6 m (sigma_n = -1 MPa) in one step, then slide B along +y.
  set_block_velocity(scene.gridpoints, scene.mesh, 1, vec3(-1.0, 0, 0));
  step(set, scene.gridpoints, dt);
  const real sigma_n = -1e6;
  REQUIRE(set.state(0).sigma_n == Approx(sigma_n).epsilon(1e-9));
  const real tau_peak = p.shear.c_0 - sigma_n * p.shear.phi_0.tan();
  const real tau_residual = p.shear.c_res - sigma_n * p.shear.phi_res.tan();
  const real ds = 1e-7;  // slip per step
  set_block_velocity(scene.gridpoints, scene.mesh, 1, vec3(0, ds / dt, 0));
  bool slipped = false;
  for (int k = 1; k <= 200; ++k) {
    step(set, scene.gridpoints, dt);
    const vec3 on_b = block_force(scene.gridpoints, scene.mesh, 1);
    const real elastic = p.k_s * k * ds;
    if (!slipped && elastic <= tau_peak) {
      CHECK(-on_b.y() == Approx(elastic * 1.0).epsilon(1e-9));
    } else {
      slipped = true;
      CHECK(-on_b.y() == Approx(tau_residual * 1.0).epsilon(1e-9));
      CHECK(law::has(law::linear_tie_law::status(set.state(0)), law::contact_status::slipped));
    }
    CHECK(on_b.x() == Approx(-sigma_n * 1.0).epsilon(1e-9));  // compression keeps pushing B away
  }
  CHECK(slipped);
  CHECK(set.dissipated_shear() > 0);
  CHECK(set.broken_area() == 0);
}

TEST_CASE("rigid rotation of both blocks: stresses objective, normal turns with the blocks", "[contacts]") {
  const real k_n = 1e12, k_s = 4e11, dt = 1e-6;
  const vec3 axis = vec3(0.3, -0.5, 0.8).normalized();
  const vec3 pivot(0.7, 0.2, -0.4);
  const real angle = 1.2;  // rad
  const int steps = 4000;
  const auto rotation = [&](real a) { return Eigen::AngleAxis<real>(a, axis).toRotationMatrix(); };

  for (const bool preload : {false, true}) {
    DYNAMIC_SECTION((preload ? "open and sheared contact" : "unloaded contact")) {
      two_cubes scene;
      contact::face_contacts<elastic_brittle_law> set(scene.tess, scene.mesh, {k_n, k_s});
      const vec3 opening(2e-7, 0, 0), slip(0, 1e-7, -0.5e-7);
      if (preload) {
        set_block_velocity(scene.gridpoints, scene.mesh, 1, (opening + slip) / dt);
        step(set, scene.gridpoints, dt);
      }
      const soa3 x0 = scene.gridpoints.reference + scene.gridpoints.displacement;
      const auto rotated = [&](real a) {
        soa3 x = x0;
        const mat3 r = rotation(a);
        for (index_t i = 0; i < x.rows(); ++i) x.row(i) = (pivot + r * (x0.row(i).transpose() - pivot)).transpose();
        return x;
      };
      soa3 previous = x0;
      for (int k = 1; k <= steps; ++k) {
        const soa3 next = rotated(angle * k / steps);
        scene.gridpoints.velocity = (next - previous) / dt;
        previous = next;
        step(set, scene.gridpoints, dt);
      }
      const mat3 r = rotation(angle);
      const vec3 sigma0_n = preload ? vec3(k_n * opening) : vec3::Zero();
      const vec3 tau0 = preload ? vec3(k_s * slip) : vec3::Zero();
      for (index_t i = 0; i < set.size(); ++i) {
        CHECK((set.normal(i) - r * vec3(1, 0, 0)).norm() < 1e-12);
        if (!preload) {
          CHECK(set.state(i).sigma_n == 0);
          CHECK(set.state(i).tau.norm() == 0);
          continue;
        }
        // First-order frame correction: relative drift O(angle x angle/steps) = O(4e-4).
        CHECK(set.state(i).sigma_n == Approx(sigma0_n.x()).epsilon(1e-3));
        CHECK((set.state(i).tau - r * tau0).norm() < 1e-3 * tau0.norm());
        CHECK((set.force(i) + set.area(i) * r * (sigma0_n + tau0)).norm() <
              2e-3 * set.area(i) * (sigma0_n + tau0).norm());
      }
    }
  }
}

TEST_CASE("initialize_frames: frames from displaced positions, no spurious increment on the next step", "[contacts]") {
  two_cubes scene;
  contact::face_contacts<elastic_brittle_law> set(scene.tess, scene.mesh, {1e12, 4e11});
  const mat3 r = Eigen::AngleAxis<real>(std::numbers::pi / 2, vec3(0, 0, 1)).toRotationMatrix();
  for (index_t i = 0; i < scene.gridpoints.size(); ++i) {
    const vec3 x = scene.gridpoints.reference.row(i).transpose();
    scene.gridpoints.displacement.row(i) = (r * x - x).transpose();
  }
  set.initialize_frames(scene.gridpoints);
  CHECK((set.face_normal(0) - vec3(0, 1, 0)).norm() < 1e-15);
  set_block_velocity(scene.gridpoints, scene.mesh, 1, vec3(0, 1e-3, 0));  // opens along the rotated normal
  step(set, scene.gridpoints, 1e-6);
  for (index_t i = 0; i < set.size(); ++i) {
    CHECK(set.state(i).sigma_n == Approx(1e12 * 1e-9).epsilon(1e-9));
    CHECK(set.state(i).tau.norm() < 1e-9 * 1e3);
  }
  node_set wrong;
  wrong.resize(2);
  CHECK_THROWS_AS(set.initialize_frames(wrong), invalid_input);
}

TEST_CASE("stiffness bound: Gershgorin row sum for any normal, attained, accumulated on both nodes", "[contacts]") {
  const real k_n = 1e12, k_s = 4e11;
  using set_type = contact::face_contacts<elastic_brittle_law>;
  const real bound = set_type::stiffness_row_bound_per_area({k_n, k_s});
  CHECK(bound == Approx(k_s + (k_n - k_s) * (1 + std::sqrt(3.0)) / 2).epsilon(1e-15));
  const auto row_max = [&](const vec3& n) {
    const mat3 k = k_s * mat3::Identity() + (k_n - k_s) * n * n.transpose();
    return k.cwiseAbs().rowwise().sum().maxCoeff();
  };
  std::mt19937 rng(3);
  std::normal_distribution<real> normal;
  for (int trial = 0; trial < 2000; ++trial) {
    const vec3 n = vec3(normal(rng), normal(rng), normal(rng)).normalized();
    CHECK(row_max(n) <= bound * (1 + 1e-14));
  }
  const real a = 0.5 * std::atan(std::sqrt(2.0));  // maximiser of cos^2 a + sqrt 2 sin a cos a
  CHECK(row_max(vec3(std::cos(a), std::sin(a) / std::sqrt(2.0), std::sin(a) / std::sqrt(2.0))) ==
        Approx(bound).epsilon(1e-14));
  CHECK(row_max(vec3(1, 0, 0)) == Approx(k_n).epsilon(1e-15));

  two_cubes scene;
  const set_type set(scene.tess, scene.mesh, {k_n, k_s});
  set.add_stiffness_bounds(scene.gridpoints);
  for (index_t i = 0; i < set.size(); ++i) {
    CHECK(scene.gridpoints.stiffness[set.node_a(i)] == Approx(2 * bound * set.area(i)).epsilon(1e-15));
    CHECK(scene.gridpoints.stiffness[set.node_b(i)] == Approx(2 * bound * set.area(i)).epsilon(1e-15));
  }
  node_set wrong;
  wrong.resize(3);
  CHECK_THROWS_AS(set.add_stiffness_bounds(wrong), invalid_input);
}

TEST_CASE("brittle break: broken area, fully broken faces and dissipated energy per sub-contact", "[contacts]") {
  two_cubes scene;
  const real k_n = 1e12, k_s = 4e11, f_t = 1e6;
  contact::face_contacts<elastic_brittle_law> set(scene.tess, scene.mesh, {k_n, k_s, f_t});
  const real dt = 1e-6;
  // B opens along x, tilting about the z axis: v_x = w (y + 0.5), so nodes at y = 1 open 3x faster.
  const real w = 2e-3;
  for (index_t i = scene.mesh.block_gridpoint_offsets[1]; i < scene.mesh.block_gridpoint_offsets[2]; ++i)
    scene.gridpoints.velocity(i, 0) = w * (scene.mesh.gridpoints[static_cast<std::size_t>(i)].y() + 0.5);
  bool saw_partial = false;
  for (int k = 0; k < 2000 && !set.face_fully_broken(0); ++k) {
    step(set, scene.gridpoints, dt);
    real broken = 0;
    for (index_t i = 0; i < set.size(); ++i)
      if (set.state(i).broken) broken += set.area(i);
    CHECK(set.broken_area() == broken);
    if (broken > 0 && broken < 1) {
      saw_partial = true;
      CHECK_FALSE(set.face_fully_broken(0));
      CHECK(set.broken_face_count() == 0);
    }
  }
  CHECK(saw_partial);
  REQUIRE(set.face_fully_broken(0));
  CHECK(set.broken_face_count() == 1);
  CHECK(set.broken_area() == Approx(1.0).epsilon(1e-15));
  real expected = 0;
  for (index_t i = 0; i < set.size(); ++i) expected += set.area(i) * set.state(i).dissipated_tension;
  CHECK(set.dissipated_tension() == Approx(expected).epsilon(1e-15));
  CHECK(set.dissipated_tension() >= 0.5 * f_t * f_t / k_n * 1.0);
  CHECK(set.stored_energy() == 0);
}

TEST_CASE("bad pairing and bad input throw with the shared face, its cells and the value", "[contacts]") {
  using set_type = contact::face_contacts<elastic_brittle_law>;
  const elastic_brittle_law::params p{1e12, 4e11};
  const auto tess = brick_tessellation(2, 2, 1, vec3(2, 2, 1));
  const auto good = face_mesh(tess);
  REQUIRE_NOTHROW(set_type(tess, good, p));
  // Shared face 2 is cell 1 (x+1,y) against cell 3; its twin is face_b.
  const auto& sf = tess.shared_faces[2];

  SECTION("twin nodes in a different order") {
    auto mesh = good;
    const index_t o = mesh.face_node_offsets[static_cast<std::size_t>(sf.face_b)];
    std::swap(mesh.face_nodes[static_cast<std::size_t>(o)], mesh.face_nodes[static_cast<std::size_t>(o) + 2]);
    CHECK_THAT(thrown_message<geometry_error>([&] { (void)set_type(tess, mesh, p); }),
               Contains("shared face 2 (cells 1 and 3") && Contains("coincident"));
  }
  SECTION("different node counts on the two sides") {
    auto mesh = good;
    const auto o = static_cast<std::size_t>(mesh.face_node_offsets[static_cast<std::size_t>(sf.face_b)]);
    mesh.face_nodes.erase(mesh.face_nodes.begin() + static_cast<std::ptrdiff_t>(o));
    mesh.face_node_area.erase(mesh.face_node_area.begin() + static_cast<std::ptrdiff_t>(o));
    for (std::size_t f = static_cast<std::size_t>(sf.face_b) + 1; f < mesh.face_node_offsets.size(); ++f)
      --mesh.face_node_offsets[f];
    CHECK_THAT(thrown_message<geometry_error>([&] { (void)set_type(tess, mesh, p); }),
               Contains("shared face 2") && Contains("4 and 3 face nodes"));
  }
  SECTION("tributary areas that differ") {
    auto mesh = good;
    mesh.face_node_area[static_cast<std::size_t>(mesh.face_node_offsets[static_cast<std::size_t>(sf.face_b)]) + 1] *=
        1.01;
    CHECK_THAT(thrown_message<geometry_error>([&] { (void)set_type(tess, mesh, p); }),
               Contains("shared face 2") && Contains("tributary areas"));
  }
  SECTION("a gridpoint of the wrong block") {
    auto mesh = good;
    const auto oa = static_cast<std::size_t>(mesh.face_node_offsets[static_cast<std::size_t>(sf.face_a)]);
    const auto ob = static_cast<std::size_t>(mesh.face_node_offsets[static_cast<std::size_t>(sf.face_b)]);
    mesh.face_nodes[ob] = mesh.face_nodes[oa];
    CHECK_THAT(thrown_message<geometry_error>([&] { (void)set_type(tess, mesh, p); }),
               Contains("shared face 2") && Contains("belong to blocks 1 and 1"));
  }
  SECTION("mesh of another tessellation") {
    const auto other = face_mesh(brick_tessellation(3, 1, 1, vec3(3, 1, 1)));
    CHECK_THROWS_AS(set_type(tess, other, p), geometry_error);
  }
  SECTION("non-positive stiffness") {
    CHECK_THAT(thrown_message<invalid_input>([&] {
                 (void)set_type(tess, good, {-1.0, 4e11});
               }),
               Contains("k_n") && Contains("-1"));
  }
}

namespace {
/// Runs 40 steps with random gridpoint velocities (seeded) on `tess`/`mesh` with `threads`
/// threads and the study's tie law; returns the final gridpoint forces and, per sub-contact,
/// sigma_n and tau, followed by the stored and dissipated energies and the broken area.
std::pair<soa3, std::vector<real>> random_run(int threads, const geometry::tessellation& tess,
                                              const geometry::block_mesh& mesh, real speed) {
  const int previous_threads = max_threads();
  set_threads(threads);
  auto g = gridpoints_of(mesh);
  contact::face_contacts<law::study_tie_law> set(tess, mesh, law::study_prism_params(100));
  std::mt19937 rng(5);
  std::uniform_real_distribution<real> uni(-1.0, 1.0);
  const real dt = 1e-7;
  for (int k = 0; k < 40; ++k) {
    for (index_t i = 0; i < g.size(); ++i)
      for (int c = 0; c < 3; ++c) g.velocity(i, c) = speed * uni(rng);
    step(set, g, dt);
  }
  std::vector<real> stresses;
  for (index_t i = 0; i < set.size(); ++i) {
    stresses.push_back(set.state(i).sigma_n);
    for (int c = 0; c < 3; ++c) stresses.push_back(set.state(i).tau[c]);
  }
  stresses.push_back(set.stored_energy());
  stresses.push_back(set.dissipated_energy());
  stresses.push_back(set.broken_area());
  set_threads(previous_threads);
  return {g.force, stresses};
}

void check_thread_independence(const geometry::tessellation& tess, const geometry::block_mesh& mesh, real speed) {
  const auto [force1, state1] = random_run(1, tess, mesh, speed);
  const auto [force2, state2] = random_run(2, tess, mesh, speed);
  REQUIRE(force1.rows() == force2.rows());
  CHECK(std::memcmp(force1.data(), force2.data(), sizeof(real) * static_cast<std::size_t>(force1.size())) == 0);
  REQUIRE(state1.size() == state2.size());
  CHECK(std::memcmp(state1.data(), state2.data(), sizeof(real) * state1.size()) == 0);
  // The run must exercise the nonlinear law (softening, slip: dissipation), and forces cancel pairwise.
  CHECK(state1[state1.size() - 2] > 0);
  const vec3 total = force1.colwise().sum().transpose();
  CHECK(total.norm() < 1e-9 * force1.cwiseAbs().sum());
}

/// Random Voronoi tessellation of the 68 x 68 x 300 mm half prism.
geometry::tessellation half_prism_voronoi(index_t blocks, unsigned seed) {
  aabb box;
  box.expand(vec3::Zero());
  box.expand(vec3(0.068, 0.068, 0.3));
  return geometry::random_voronoi(box, blocks, seed);
}

/// Area vector (m^2) of polygon `loop` of the tessellation, Newell's formula.
vec3 polygon_area_vector(const geometry::tessellation& t, std::span<const index_t> loop) {
  vec3 s = vec3::Zero();
  const vec3& x0 = t.vertices[static_cast<std::size_t>(loop[0])];
  for (std::size_t k = 1; k + 1 < loop.size(); ++k)
    s += (t.vertices[static_cast<std::size_t>(loop[k])] - x0)
             .cross(t.vertices[static_cast<std::size_t>(loop[k + 1])] - x0);
  return 0.5 * s;
}
}  // namespace

TEST_CASE("determinism: same bits with 1 and 2 threads, forces balance", "[contacts]") {
  SECTION("jittered brick grid, 120 blocks") {
    const auto tess = brick_tessellation(6, 5, 4, vec3(0.6, 0.5, 0.4), 0.2, 11);
    check_thread_independence(tess, face_mesh(tess), 5.0);
  }
  SECTION("random Voronoi prism, 50 blocks, zone_blocks") {
    const auto tess = half_prism_voronoi(50, 42);
    check_thread_independence(tess, geometry::zone_blocks(tess), 5.0);
  }
}

TEST_CASE("random Voronoi + zone_blocks: face areas and normals of every shared face", "[contacts]") {
  const auto tess = half_prism_voronoi(50, 7);
  for (const real h : {0.0, 0.01}) {
    DYNAMIC_SECTION("zoning target edge length " << h << " m") {
      const auto mesh = geometry::zone_blocks(tess, {h});
      const contact::face_contacts<law::study_tie_law> set(tess, mesh, law::study_prism_params(100));
      REQUIRE(set.face_count() == static_cast<index_t>(tess.shared_faces.size()));
      index_t expected_size = 0, polygon_vertices = 0;
      for (index_t s = 0; s < set.face_count(); ++s) {
        const auto& sf = tess.shared_faces[static_cast<std::size_t>(s)];
        const vec3 a = polygon_area_vector(tess, tess.face(sf.face_a));
        CHECK(set.face_area(s) == Approx(a.norm()).epsilon(1e-9));
        CHECK((set.face_normal(s) - a.normalized()).norm() < 1e-9);
        expected_size += mesh.face_node_offsets[static_cast<std::size_t>(sf.face_a) + 1] -
                         mesh.face_node_offsets[static_cast<std::size_t>(sf.face_a)];
        polygon_vertices += static_cast<index_t>(tess.face(sf.face_a).size());
      }
      CHECK(set.size() == expected_size);
      // Unrefined: one sub-contact per polygon vertex; refined: edge midpoints add more.
      if (h == 0) CHECK(set.size() == polygon_vertices);
      if (h > 0) CHECK(set.size() > polygon_vertices);
    }
  }
}

TEST_CASE("update allocates nothing", "[contacts]") {
  const auto tess = brick_tessellation(6, 5, 4, vec3(0.6, 0.5, 0.4), 0.2, 13);
  const auto mesh = face_mesh(tess);
  auto g = gridpoints_of(mesh);
  contact::face_contacts<law::study_tie_law> set(tess, mesh, law::study_prism_params(100));
  g.velocity.setConstant(1e-3);
  step(set, g, 1e-7);  // warm up (thread pool)
  allocation_count = 0;
  count_allocations = true;
  for (int k = 0; k < 50; ++k) step(set, g, 1e-7);
  count_allocations = false;
  CHECK(allocation_count.load() == 0);
}

TEST_CASE("law state declared once: column storage and VTK arrays follow law::cohesive_frictional::state_fields", "[contacts][pack]") {
  using packed_law = law::with_elastic_packs<law::study_tie_law>;
  using columns = contact::detail::state_columns<packed_law>;
  // Ten real columns (tau takes three) and the flags; columns in declaration order.
  STATIC_REQUIRE(columns::real_count == 10);
  STATIC_REQUIRE(columns::column("sigma_n") == 0);
  STATIC_REQUIRE(columns::column("tau") == 1);
  STATIC_REQUIRE(columns::column("u_n") == 4);
  STATIC_REQUIRE(columns::column("dissipated_compression") == 9);
  // A state with ten distinct values and two flags round-trips through the columns bit for bit.
  packed_law::state st{};
  st.sigma_n = 1.5, st.tau = vec3(2.5, -3.5, 4.5), st.u_n = 5.5e-6, st.u_p = 6.5e-7, st.u_soft = 7.5e-8;
  st.dissipated_tension = 8.5, st.dissipated_shear = 9.5, st.dissipated_compression = 10.5;
  st.flags = law::contact_status::softening | law::contact_status::slipped;
  const auto p = law::study_prism_params(100);
  columns c;
  c.assign(3, p);
  c.set(1, st, p);
  const auto back = c.get(1);
  CHECK(std::memcmp(&back, &st, sizeof st) == 0);
  CHECK(c.col(columns::column("tau") + 2)[1] == 4.5);
  CHECK(io::vtk::state_array_name(packed_law::state_fields[5]) == "dissipated_tension_J_per_m2");

  // A damaged run: the snapshot's arrays are the states of the set, field by field.
  const auto tess = brick_tessellation(4, 3, 3, vec3(0.4, 0.3, 0.3), 0.2, 3);
  const auto mesh = face_mesh(tess);
  auto g = gridpoints_of(mesh);
  contact::face_contacts<packed_law> set(tess, mesh, p);
  std::mt19937 rng(11);
  std::uniform_real_distribution<real> uni(-1.0, 1.0);
  for (int k = 0; k < 40; ++k) {
    for (index_t i = 0; i < g.size(); ++i)
      for (int d = 0; d < 3; ++d) g.velocity(i, d) = 5.0 * uni(rng);
    step(set, g, 1e-7);
  }
  io::vtk::contact_snapshot snap;
  snap.take(set, g);
  REQUIRE(snap.size() == static_cast<std::size_t>(set.size()));
  REQUIRE(snap.state.size() == 8);  // nine fields, the flags shown as status
  const auto* sigma = snap.find("sigma_n_Pa");
  const auto* tau = snap.find("tau_Pa");
  const auto* w = snap.find("u_soft_m");
  REQUIRE((sigma != nullptr && tau != nullptr && w != nullptr));
  CHECK(tau->components == 3);
  index_t damaged = 0;
  for (index_t i = 0; i < set.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto& s_i = set.state(i);
    CHECK(sigma->values[k] == s_i.sigma_n);
    CHECK(tau->values[3 * k + 1] == s_i.tau[1]);
    CHECK(w->values[k] == s_i.u_soft);
    CHECK(snap.status[k] == static_cast<std::int32_t>(s_i.flags));
    damaged += s_i.flags != law::contact_status::intact ? 1 : 0;
  }
  CHECK(damaged > 0);  // the run reached the nonlinear law
}

// ---- the elastic pack path (law::ElasticPackLaw) against the scalar law ----

namespace {

static_assert(law::ElasticPackLaw<law::study_tie_law> && law::ElasticPackLaw<law::study_beam_law> &&
              law::ElasticPackLaw<law::coupled_tie_law>);

/// study_tie_law without its pack path: face_contacts runs Law::update on every sub-contact.
struct scalar_tie_law : law::study_tie_law {
  static constexpr bool elastic_pack = false;
};
static_assert(law::ContactLaw<scalar_tie_law> && !law::ElasticPackLaw<scalar_tie_law>);

/// Bitwise equality of two reals (so -0 != +0 and a NaN equals itself).
bool same_bits(real a, real b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// The plastic slip u_slip of two states, where the law stores it (slip_softening.hpp), to the bit.
template <class State>
bool same_slip(const State& a, const State& b) {
  if constexpr (requires { requires std::is_same_v<decltype(a.u_slip), real>; }) return same_bits(a.u_slip, b.u_slip);
  else return true;
}
/// The plastic closure u_crush of two states, where the law stores it (compression.hpp softening_cap), to the bit.
template <class State>
bool same_crush(const State& a, const State& b) {
  if constexpr (requires { requires std::is_same_v<decltype(a.u_crush), real>; }) return same_bits(a.u_crush, b.u_crush);
  else return true;
}
template <class State>
bool same_state(const State& a, const State& b) {
  return same_bits(a.sigma_n, b.sigma_n) && same_bits(a.tau[0], b.tau[0]) && same_bits(a.tau[1], b.tau[1]) &&
         same_bits(a.tau[2], b.tau[2]) && same_bits(a.u_n, b.u_n) && same_bits(a.u_p, b.u_p) &&
         same_bits(a.u_soft, b.u_soft) && same_bits(a.dissipated_tension, b.dissipated_tension) &&
         same_bits(a.dissipated_shear, b.dissipated_shear) &&
         same_bits(a.dissipated_compression, b.dissipated_compression) && a.flags == b.flags && same_slip(a, b) &&
         same_crush(a, b);
}

/// One step of `count` sub-contacts of a mixed population: each is driven by Law::update from a
/// virgin state through a history of its kind (elastic, at the tensile peak, softening, broken,
/// slipped, at the Coulomb limit, at the compressive cap), and the step's increment lands within
/// a few ulps of a threshold for the "near" kinds, on both sides.
template <class Law>
struct population {
  std::vector<typename Law::state> states;
  std::vector<real> du_n, area;
  std::vector<vec3> du_s, n;

  population(const typename Law::params& p, std::size_t count, unsigned seed) {
    using Tension = typename Law::tension_policy;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<real> uni(-1.0, 1.0);
    const real eta = p.k_n > 0 ? Tension::peak_strength(p.tension) / p.k_n : 0;
    const real f_peak = Tension::peak_strength(p.tension);
    const auto random_unit = [&] {
      vec3 v;
      do v = vec3(uni(rng), uni(rng), uni(rng));
      while (v.norm() < 0.1);
      return vec3(v.normalized());
    };
    const auto in_plane = [](const vec3& v, const vec3& normal) { return vec3(v - v.dot(normal) * normal); };
    for (std::size_t i = 0; i < count; ++i) {
      typename Law::state s{};
      const vec3 n0 = random_unit();
      const auto drive = [&](real total_n, const vec3& total_s, int steps) {
        for (int k = 0; k < steps; ++k) Law::update(p, s, total_n / steps, in_plane(total_s, n0) / steps, n0);
      };
      const real ulps = std::round(4 * uni(rng));  // -4 .. 4
      const real nudge = 1 + ulps * std::numeric_limits<real>::epsilon();
      // The step: a slightly turned normal (rotation of the stored tau), a small increment.
      const vec3 n1 = vec3(n0 + 1e-4 * random_unit()).normalized();
      real step_n = 1e-3 * eta * uni(rng);
      vec3 step_s = in_plane(1e-3 * eta * random_unit(), n1);
      // Kinds cycle through 0-7; every fourth run of 16 holds only contacts past the peak,
      // broken or slipped, so whole packs without an intact lane occur (advance_states sends
      // them to Law::update directly).
      switch ((i / 16) % 4 == 3 ? 3 + i % 3 : i % 8) {
        case 0:  // virgin
          break;
        case 1:  // elastic history, tension or compression, with shear
          drive(0.5 * eta * uni(rng), 0.5 * eta * random_unit(), 3);
          break;
        case 2:  // the trial lands on f_T within a few ulps
          drive(0.5 * eta, vec3::Zero(), 2);
          step_n = f_peak / p.k_n * nudge - s.u_n + s.u_p;
          step_s = vec3::Zero();
          break;
        case 3:  // softening, then unloading or reloading, the trial within a few ulps of f_t(u_soft), or broken
          drive(eta * (1.5 + uni(rng)), vec3::Zero(), 5);
          step_n = 0.2 * eta * uni(rng);
          if (i % 3 == 0) step_n = Law::tensile_strength(p, s) / p.k_n * nudge - s.u_n + s.u_p;
          if (i % 3 == 1 && uni(rng) > 0) step_n = 1e3 * eta;  // breaks it
          break;
        case 4:  // broken in tension, open or closed, the gap within a few ulps of closing, or sheared
          drive(1e3 * eta, vec3::Zero(), 20);
          step_n = (uni(rng) > 0 ? 1 : -1) * (s.u_n - s.u_p) * (1 + 0.01 * uni(rng));
          if (i % 3 == 0) step_n = -(s.u_n - s.u_p) * nudge;
          if (i % 3 == 2) {  // closed onto the gap, the shear trial within a few ulps of the residual limit
            step_n = -(s.u_n - s.u_p);
            const real tau_max = Law::shear_policy::strength(p.shear, 0, s.flags, 1);
            step_s = in_plane(random_unit(), n1).normalized() * (tau_max * nudge / p.k_s);
          }
          break;
        case 5:  // slipped, or its shear trial within a few ulps of the residual limit (same normal)
          drive(0, 1e3 * eta * random_unit(), 10);
          if (i % 3 == 0) {
            const real tau_now = s.tau.norm();
            step_n = 0;
            step_s = s.tau / tau_now * ((Law::shear_strength(p, s) * nudge - tau_now) / p.k_s);
            n.push_back(n0);
          }
          break;
        case 6: {  // the shear trial lands on the Coulomb limit within a few ulps (same normal)
          drive(0.3 * eta * uni(rng), 0.3 * eta * random_unit(), 2);
          const real tau_max = Law::shear_policy::strength(p.shear, s.sigma_n, law::contact_status::intact, 1);
          const real tau_now = s.tau.norm();
          const vec3 direction = tau_now > 0 ? vec3(s.tau / tau_now) : in_plane(random_unit(), n0).normalized();
          step_n = 0;
          step_s = direction * ((tau_max * nudge - tau_now) / p.k_s);
          n.push_back(n0);
          break;
        }
        case 7:  // deep compression (at a compressive cap, if the law has one; softened, if it softens)
          drive(-1e2 * eta * (1 + uni(rng)), vec3::Zero(), 4);
          if constexpr (Law::compression_policy::bounded) {
            const real f_c = Law::compressive_strength(p, s);
            step_n = -f_c / p.k_n * nudge - s.u_n + s.u_p;
          }
          break;
      }
      if (n.size() == states.size()) n.push_back(n1);
      states.push_back(s);
      du_n.push_back(step_n);
      du_s.push_back(in_plane(step_s, n.back()));
      area.push_back(1e-4 * (1.5 + uni(rng)));
    }
  }
};

/// Checks the pack path against Law::update on a population, with [0, count) cut at `cut`.
template <class Law>
void check_pack_against_scalar(const typename Law::params& p, std::size_t count, std::size_t cut, unsigned seed) {
  const population<Law> pop(p, count, seed);
  // Scalar reference.
  std::vector<typename Law::state> expected = pop.states;
  std::vector<vec3> expected_force(count);
  for (std::size_t i = 0; i < count; ++i) {
    Law::update(p, expected[i], pop.du_n[i], pop.du_s[i], pop.n[i]);
    expected_force[i] = pop.area[i] * (expected[i].sigma_n * pop.n[i] + vec3(expected[i].tau));
  }
  // Pack path.
  contact::detail::state_columns<Law> columns;
  columns.assign(count, p);
  contact::detail::step_columns step;
  step.resize(count);
  std::array<std::vector<real>, 3> force;
  for (auto& column : force) column.assign(count, 0.0);
  for (std::size_t i = 0; i < count; ++i) {
    columns.set(i, pop.states[i], p);
    step.du_n[i] = pop.du_n[i];
    step.ds0[i] = pop.du_s[i][0];
    step.ds1[i] = pop.du_s[i][1];
    step.ds2[i] = pop.du_s[i][2];
    step.n0[i] = pop.n[i][0];
    step.n1[i] = pop.n[i][1];
    step.n2[i] = pop.n[i][2];
  }
  real* const f[3] = {force[0].data(), force[1].data(), force[2].data()};
  contact::detail::advance_states<Law>(p, columns, step, pop.area.data(), 0, cut, f);
  contact::detail::advance_states<Law>(p, columns, step, pop.area.data(), cut, count, f);

  // Sub-contacts by their state before the step and what the step did to them, and their path:
  // [kind][0] declined (Law::update), [kind][1] accepted by update_elastic.
  enum { intact, softening, softening_further, slipped, sliding, broken_open, broken_closed, kinds };
  std::size_t path[kinds][2] = {};
  std::size_t accepted = 0, status_seen[8] = {};
  for (std::size_t i = 0; i < count; ++i) {
    INFO("sub-contact " << i);
    CHECK(same_state(columns.get(i), expected[i]));
    for (int c = 0; c < 3; ++c) CHECK(same_bits(force[static_cast<std::size_t>(c)][i], expected_force[i][c]));
    const bool accept = step.elastic[i] != 0;
    accepted += accept ? 1 : 0;
    ++status_seen[static_cast<int>(expected[i].flags) & 7];
    const auto& before = pop.states[i];
    const int kind = law::has(before.flags, law::contact_status::broken_tension)
                         ? (expected[i].u_n > expected[i].u_p ? broken_open : broken_closed)
                     : law::has(before.flags, law::contact_status::slipped)
                         ? (expected[i].dissipated_shear != before.dissipated_shear ? sliding : slipped)
                     : law::has(before.flags, law::contact_status::softening)
                         ? (expected[i].u_soft != before.u_soft ? softening_further : softening)
                         : intact;
    ++path[kind][accept ? 1 : 0];
    // The pack's f_t column is the law's tensile strength of the state it holds.
    CHECK(same_bits(columns.f_t[i], Law::tensile_strength(p, expected[i])));
  }
  // A cap that softens: contacts crushed before crush further on the pack path (the flag stays).
  if constexpr (Law::softens_with_crushing) {
    std::size_t crushing_on_pack = 0;
    for (std::size_t i = 0; i < count; ++i)
      crushing_on_pack += step.elastic[i] != 0 && law::has(pop.states[i].flags, law::contact_status::crushed) &&
                          expected[i].u_crush > pop.states[i].u_crush;
    CHECK(crushing_on_pack > 0);
  }
  // Both paths ran, and the population holds intact, softening, broken and slipped contacts.
  CHECK(accepted > count / 8);
  CHECK(accepted < count);
  CHECK(status_seen[0] > 0);
  CHECK(status_seen[static_cast<int>(law::contact_status::softening)] > 0);
  CHECK(status_seen[static_cast<int>(law::contact_status::broken_tension)] > 0);
  CHECK(status_seen[static_cast<int>(law::contact_status::slipped)] > 0);
  // Every kind of contact took the pack path; intact ones that reach the peak, and softening ones
  // whose step exhausts the envelope, Law::update.
  for (int kind = intact; kind < kinds; ++kind) {
    INFO("kind " << kind << " (intact, softening, further along the envelope, slipped, sliding, broken open, "
                 << "broken closed): declined " << path[kind][0] << ", accepted " << path[kind][1]);
    CHECK(path[kind][1] > 0);
    if (kind == intact || kind == softening_further) CHECK(path[kind][0] > 0);
  }
}

}  // namespace

TEST_CASE("elastic pack path: the same states and forces as Law::update, to the bit", "[contacts][pack]") {
  // The packs are the widest the build's instruction set offers (core/lanes.hpp): 8 lanes with
  // AVX-512 and 4 with AVX (the native-tests preset, -march=native), 2 with SSE2 (the release
  // preset's x86-64 baseline). `test_contacts "[pack]" -s` prints the width.
#if defined(__AVX512F__)
  CHECK(lanes::width == 8);
#elif defined(__AVX__)
  CHECK(lanes::width == 4);
#elif defined(__SSE2__)
  CHECK(lanes::width == 2);
#endif
  // 203 sub-contacts: not a multiple of any pack width, cut at 37 (both ranges end in a partial pack).
  SECTION("study_tie_law (power softening, no compression limit, residual Coulomb)") {
    check_pack_against_scalar<law::study_tie_law>(law::study_prism_params(100), 203, 37, 1);
  }
  SECTION("study_beam_law (linear softening, compressive cap)") {
    check_pack_against_scalar<law::study_beam_law>(law::study_beam_params(250), 203, 37, 2);
  }
  SECTION("study_tie_law with alpha = 2.5 (std::pow lane by lane)") {
    auto p = law::study_prism_params(100);
    p.tension.alpha = 2.5;
    check_pack_against_scalar<law::study_tie_law>(p, 203, 37, 4);
  }
  SECTION("slip_softening_beam_law (cohesion and friction soften with the plastic slip u_slip)") {
    // G_II = 6000 J/m^2: s_u = 2.4 mm, so the slid population (0.5-5 mm) holds contacts on the
    // softening line and on the residual.
    check_pack_against_scalar<law::slip_softening_beam_law>(law::with_slip_softening(law::study_beam_params(250), 6000),
                                                            203, 37, 5);
  }
  SECTION("crushing_beam_law (the cap softens with the plastic closure u_crush, shear scaled with it)") {
    // G_c = 1e4 J/m^2, residual 0.2: kappa_u = 0.71 mm, so the compressed population (0.5-1 mm of
    // closure) holds contacts on the softening cap and on its residual.
    const auto slip = law::with_slip_softening(law::study_beam_params(250), 6000);
    check_pack_against_scalar<law::crushing_beam_law>(law::with_softening_cap(slip, 1e4, 0.2, true), 203, 37, 6);
    check_pack_against_scalar<law::crushing_beam_law>(law::with_softening_cap(slip, 1e4, 0.2, false), 203, 37, 7);
  }
  SECTION("mixed_mode_beam_law (one damage for tension and shear, law/mixed_mode.hpp)") {
    // G_II = 6000 J/m^2: l_II = 2.4 mm, so slid contacts (0.5-5 mm) are softening or broken.
    check_pack_against_scalar<presets::mixed_mode_beam_law>(presets::with_mixed_mode(law::study_beam_params(250), 6000),
                                                            203, 37, 8);
  }
  SECTION("mixed_crushing_beam_law (the mixed law whose cap softens with u_crush, shear scaled with it or not)") {
    // G_c = 1e4 J/m^2, residual 0.2: kappa_u = 0.71 mm, so the compressed population (0.5-1 mm of
    // closure) holds contacts on the softening cap and on its residual.
    const auto mixed = presets::with_mixed_mode(law::study_beam_params(250), 6000);
    // Seed 8 as mixed_mode_beam_law's: the same population (its displacements do not depend on the law).
    check_pack_against_scalar<presets::mixed_crushing_beam_law>(presets::with_softening_cap(mixed, 1e4, 0.2, true), 203,
                                                                37, 8);
    check_pack_against_scalar<presets::mixed_crushing_beam_law>(presets::with_softening_cap(mixed, 1e4, 0.2, false), 203,
                                                                37, 8);
  }
  SECTION("coupled_tie_law (cohesion softens with the tensile strength)") {
    check_pack_against_scalar<law::coupled_tie_law>(law::with_coupled_cohesion(law::study_prism_params(100)), 203,
                                                    37, 3);
  }
}

TEST_CASE("elastic pack path: a set with it and one without give the same bits over a random run",
          "[contacts][pack]") {
  const auto tess = half_prism_voronoi(50, 42);
  const auto mesh = geometry::zone_blocks(tess);
  auto g_pack = gridpoints_of(mesh);
  auto g_scalar = gridpoints_of(mesh);
  contact::face_contacts<law::with_elastic_packs<law::study_tie_law>> pack(tess, mesh, law::study_prism_params(100));
  contact::face_contacts<law::study_tie_law> scalar(tess, mesh, law::study_prism_params(100));
  static_assert(decltype(pack)::packed && !decltype(scalar)::packed);
  static_assert(!contact::face_contacts<law::with_elastic_packs<scalar_tie_law>>::packed);
  std::mt19937 rng(9);
  std::uniform_real_distribution<real> uni(-1.0, 1.0);
  bool all_same = true;
  for (int k = 0; k < 60; ++k) {
    for (index_t i = 0; i < g_pack.size(); ++i)
      for (int c = 0; c < 3; ++c) g_pack.velocity(i, c) = g_scalar.velocity(i, c) = 2.0 * uni(rng);
    step(pack, g_pack, 1e-7);
    step(scalar, g_scalar, 1e-7);
    all_same = all_same && std::memcmp(g_pack.force.data(), g_scalar.force.data(),
                                       sizeof(real) * static_cast<std::size_t>(g_pack.force.size())) == 0;
    for (index_t i = 0; i < pack.size(); ++i) {
      all_same = all_same && same_state(pack.state(i), scalar.state(i));
      for (int c = 0; c < 3; ++c) all_same = all_same && same_bits(pack.force(i)[c], scalar.force(i)[c]);
    }
  }
  CHECK(all_same);
  // The run reached the nonlinear law: some sub-contacts softened, broke or slipped.
  index_t damaged = 0;
  for (index_t i = 0; i < pack.size(); ++i) damaged += pack.state(i).flags != law::contact_status::intact ? 1 : 0;
  CHECK(damaged > 0);
  CHECK(damaged < pack.size());
}

}  // namespace tessera::test_contacts

// ---- analysis/: crack graph along any axis, curve figures, dissipation checks ----
namespace {
/// Three blocks in a row along x (0 | 1 | 2), faces at x = 1 and x = 2, two sub-contacts per face
/// at z = 0.3 (area 0.25) and z = 0.7 (area 0.75); node pairs with their own gridpoints.
struct row_of_blocks {
  tessera::node_set gridpoints;
  std::vector<tessera::law::contact_status> flags;
  struct state_view {
    tessera::law::contact_status flags;
    tessera::real u_n;
  };
  row_of_blocks() : flags(4, tessera::law::contact_status::intact) {
    gridpoints.resize(8);
    for (int i = 0; i < 4; ++i) {
      const tessera::vec3 x(i < 2 ? 1.0 : 2.0, 0.5, i % 2 == 0 ? 0.3 : 0.7);
      gridpoints.reference.row(2 * i) = x.transpose();
      gridpoints.reference.row(2 * i + 1) = x.transpose();
    }
  }
  [[nodiscard]] tessera::index_t subcontact_count() const { return 4; }
  [[nodiscard]] tessera::index_t block_a(tessera::index_t i) const { return i < 2 ? 0 : 1; }
  [[nodiscard]] tessera::index_t block_b(tessera::index_t i) const { return i < 2 ? 1 : 2; }
  [[nodiscard]] tessera::index_t node_a(tessera::index_t i) const { return 2 * i; }
  [[nodiscard]] tessera::index_t node_b(tessera::index_t i) const { return 2 * i + 1; }
  [[nodiscard]] tessera::real area(tessera::index_t i) const { return i % 2 == 0 ? 0.25 : 0.75; }
  [[nodiscard]] tessera::vec3 position(tessera::index_t i, const tessera::node_set& gp) const {
    return 0.5 * (gp.position(node_a(i)) + gp.position(node_b(i)));
  }
  [[nodiscard]] state_view state(tessera::index_t i) const {
    const auto node = node_b(i);
    return {flags[static_cast<std::size_t>(i)], (gridpoints.position(node) - gridpoints.position(node - 1)).x()};
  }
};
}  // namespace

TEST_CASE("crack graph: through-cracks along the axis given, bar crossings, crack sites", "[analysis]") {
  using tessera::vec3;
  using tessera::law::contact_status;
  row_of_blocks row;
  tessera::analysis::crack_graph along_x(row, 3, vec3(2, 0, 0)), along_z(row, 3, vec3::UnitZ());
  CHECK(along_x.axis().isApprox(vec3::UnitX()));
  // Intact: one piece.
  auto r = along_x.softened(row, row.gridpoints);
  CHECK(r.pieces == 1);
  CHECK(r.cracks == 0);
  // One sub-contact of the face at x = 2 softened: the face still holds.
  row.flags[2] = contact_status::softening;
  r = along_x.softened(row, row.gridpoints);
  CHECK(r.cracks == 0);
  CHECK(r.open_subcontacts == 1);
  // The whole face softened: one through-crack at x = 2 (along x), at the area-weighted
  // z = 0.25 * 0.3 + 0.75 * 0.7 = 0.6 (along z).
  row.flags[3] = contact_status::broken_tension;
  r = along_x.softened(row, row.gridpoints);
  REQUIRE(r.cracks == 1);
  REQUIRE(r.positions.size() == 1);
  CHECK(r.positions[0] == Approx(2.0).epsilon(1e-15));
  r = along_z.softened(row, row.gridpoints);
  REQUIRE(r.positions.size() == 1);
  CHECK(r.positions[0] == Approx(0.6).epsilon(1e-15));
  // A bar through the three blocks crosses it once, at the surface's position.
  along_x.set_bar_path({0, 1, 2}, {0.5, 1.5, 2.5});
  r = along_x.softened(row, row.gridpoints);
  CHECK(r.bar_crossings == 1);
  REQUIRE(r.bar_crossing_positions.size() == 1);
  CHECK(r.bar_crossing_positions[0] == Approx(2.0).epsilon(1e-15));
  // Opened: softened and separated by at least w_open; 0.1 mm apart on one sub-contact only.
  row.gridpoints.displacement(5, 0) = 1e-4;
  CHECK(along_x.opened(row, row.gridpoints, 5e-5).cracks == 0);
  row.gridpoints.displacement(7, 0) = 1e-4;
  CHECK(along_x.opened(row, row.gridpoints, 5e-5).cracks == 1);
  CHECK(along_x.opened(row, row.gridpoints, 2e-4).cracks == 0);
  CHECK(along_x.opened_normal_only(row, row.gridpoints, 5e-5).cracks == 1);
  // Crack sites: surfaces closer than the spacing are one site, reported by their mean.
  const auto sites = tessera::analysis::crack_sites({0.5, 0.1, 0.12}, 0.05);
  REQUIRE(sites.size() == 2);
  CHECK(sites[0] == Approx(0.11).epsilon(1e-14));
  CHECK(sites[1] == 0.5);
  CHECK_THROWS_WITH(tessera::analysis::crack_sites({0.1}, 0), Catch::Contains("spacing = 0"));
  CHECK_THROWS_WITH(tessera::analysis::crack_graph(row, 3, vec3::Zero()), Catch::Contains("axis (0, 0, 0)"));
  CHECK_THROWS_WITH(tessera::analysis::crack_graph(row, 2, vec3::UnitX()), Catch::Contains("outside [0, 2)"));
}

TEST_CASE("curve analysis: load drops with hysteresis, linear-branch slope, plateau, dissipation check", "[analysis]") {
  using tessera::real;
  namespace an = tessera::analysis;
  // Rise to 10, drop to 5 (a drop), rise to 12, dip by 0.4 < threshold 0.5 (noise), rise to 13,
  // drop to 8 (a second drop).
  const std::vector<real> f{0, 4, 8, 10, 7, 5, 9, 12, 11.6, 13, 8};
  std::vector<real> u(f.size());
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = 1e-4 * static_cast<real>(k);
  const auto drops = an::find_load_drops(u, f, 0.5, f.size());
  REQUIRE(drops.size() == 2);
  CHECK(drops[0].peak_force == 10);
  CHECK(drops[0].sample == 3);
  CHECK(drops[0].trough_force == 5);
  CHECK(drops[1].peak_force == 13);
  CHECK(drops[1].peak_elongation == Approx(9e-4).epsilon(1e-15));
  CHECK(an::find_load_drops(u, f, 0.5, 5).size() == 1);  // the first five samples only
  CHECK_THROWS_WITH(an::load_drop_detector(-1), Catch::Contains("threshold = -1"));
  // Slope of y = 3e6 x + 100 through the samples with 1000 <= y <= 2000 (x / 2 as abscissa: 6e6).
  std::vector<real> x, y;
  for (int k = 0; k < 100; ++k) {
    x.push_back(1e-5 * k);
    y.push_back(3e6 * x.back() + 100 + (k > 80 ? -500.0 : 0.0));  // a softened tail outside the band
  }
  CHECK(an::band_slope(x, y, x.size(), 1000, 2000) == Approx(3e6).epsilon(1e-9));
  CHECK(an::band_slope(x, y, x.size(), 1000, 2000, 2.0) == Approx(6e6).epsilon(1e-9));
  CHECK(an::band_slope(x, y, 3, 1000, 2000) == 0);  // no sample qualifies
  CHECK(an::tail_mean({1, 2, 3, 5}, 2) == 4);
  CHECK(an::tail_mean({1, 2}, 7) == 2);
  // Curve error: a curve 1 % above its reference everywhere on [0, 1] with ordinate 1 -> 0.01.
  const std::vector<real> xr{0, 1}, yr{1, 1}, yc{1.01, 1.01};
  CHECK(an::curve_error(xr, yc, xr, yr, 1.0) == Approx(0.01).epsilon(1e-12));
  CHECK(an::running_max({0, 2, 1, 3}) == std::vector<real>{0, 2, 2, 3});
  // Dissipation: 12 J against 5 J/m^2 x 2 m^2 = 10 J -> +20 %; nothing expected without area.
  const auto c = an::check_dissipation(12, 5, 2);
  CHECK(c.expected == 10);
  CHECK(c.error_rel == Approx(0.2).epsilon(1e-15));
  CHECK_FALSE(an::check_dissipation(12, 5, 0).defined());
  // Energy shares of a balance that closes to 1 %: 100 J in, 60 stored, 39 dissipated.
  tessera::energy_balance e;
  e.boundary_work = 100;
  e.contact_stored = 60;
  e.contact_dissipated = 39;
  const auto s = an::shares_of(e);
  CHECK(s.contact_stored == Approx(0.6).epsilon(1e-15));
  CHECK(s.residual == Approx(0.01).epsilon(1e-12));
}

// =============================================================================================
// Detection narrow phase (contact/detection/common_plane.hpp): the contact plane and patch of
// two convex polyhedra against hand values, and the pruned edge-pair search against the full one.
// =============================================================================================

namespace tessera::test_detection {
namespace {

using geometry::convex_polyhedron;
namespace detection = contact::detection;

mat3 rotation_about(const vec3& axis, real angle) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

/// Unit cube [0,1]^3 moved so its corner sits at `lo`.
convex_polyhedron unit_cube_at(const vec3& lo) { return convex_polyhedron::box(lo, lo + vec3::Ones()); }

real sum_of(const std::vector<real>& v) { return std::accumulate(v.begin(), v.end(), real(0)); }

}  // namespace

TEST_CASE("detection: face-face patches of two cubes, offset, overlapping, turned and tilted", "[detection]") {
  const convex_polyhedron a = unit_cube_at(vec3::Zero());
  const real tol = 1e-3;
  SECTION("offset by (0.3, 0.2), 10 mm apart: a 0.7 x 0.8 rectangle, gap 10 mm at every corner") {
    const convex_polyhedron b = unit_cube_at(vec3(0.3, 0.2, 1.01));
    const auto plane = detection::common_plane(a, b);
    CHECK(plane.source == detection::plane_source::face_a);  // ties prefer A's face
    CHECK((plane.normal - vec3::UnitZ()).norm() < 1e-15);
    CHECK(plane.gap == Approx(0.01).margin(1e-14));
    CHECK(plane.offset == Approx(1.005).margin(1e-14));
    const auto patch = detection::contact_patch_of(a, b, plane, tol);
    REQUIRE(patch.type == detection::patch_type::polygon);
    CHECK(patch.points.size() == 4);
    CHECK(patch.total_area == Approx(0.56).epsilon(1e-12));
    CHECK(sum_of(patch.area) == Approx(0.56).epsilon(1e-12));
    for (real g : patch.gap) CHECK(g == Approx(0.01).margin(1e-13));
    for (const vec3& p : patch.points) CHECK(p.z() == Approx(1.005).margin(1e-14));
  }
  SECTION("overlapping by 2 mm: gap -2 mm, same rectangle") {
    const convex_polyhedron b = unit_cube_at(vec3(0.3, 0.2, 0.998));
    const auto plane = detection::common_plane(a, b);
    CHECK(plane.gap == Approx(-0.002).margin(1e-14));
    const auto patch = detection::contact_patch_of(a, b, plane, tol);
    CHECK(patch.total_area == Approx(0.56).epsilon(1e-12));
    for (real g : patch.gap) CHECK(g == Approx(-0.002).margin(1e-13));
  }
  SECTION("turned 45 deg about the vertical: the octagon of area 2 (sqrt 2 - 1)") {
    const convex_polyhedron centred = convex_polyhedron::box(vec3(-0.5, -0.5, 0), vec3(0.5, 0.5, 1));
    const convex_polyhedron b = centred.transformed(rotation_about(vec3::UnitZ(), std::numbers::pi / 4), vec3(0.5, 0.5, 1.001));
    const auto plane = detection::common_plane(a, b);
    const auto patch = detection::contact_patch_of(a, b, plane, tol);
    REQUIRE(patch.type == detection::patch_type::polygon);
    CHECK(patch.points.size() == 8);
    CHECK(patch.total_area == Approx(2 * (std::numbers::sqrt2 - 1)).epsilon(1e-12));
    CHECK(sum_of(patch.area) == Approx(patch.total_area).epsilon(1e-12));
    for (real area : patch.area) CHECK(area > 0);
  }
  SECTION("tilted by 1e-4 rad: still face-face, gaps follow the tilted plane") {
    const real theta = 1e-4;
    const mat3 r = rotation_about(vec3::UnitY(), theta);
    const vec3 pivot(0.8, 0.7, 1.0005);  // B's bottom-face centre
    const convex_polyhedron centred = convex_polyhedron::box(vec3(-0.5, -0.5, 0), vec3(0.5, 0.5, 1));
    const convex_polyhedron b = centred.transformed(r, pivot);
    const auto plane = detection::common_plane(a, b);
    const auto patch = detection::contact_patch_of(a, b, plane, tol);
    REQUIRE(patch.type == detection::patch_type::polygon);
    CHECK(patch.total_area == Approx(0.7 * 0.8).epsilon(1e-6));
    // Independent of the code's ray casting: A's top is z = 1, B's bottom the plane through the
    // pivot with normal r e_z; the gap along n between them through each corner.
    const vec3 n = plane.normal;
    const vec3 nb = r * vec3::UnitZ();
    for (std::size_t i = 0; i < patch.points.size(); ++i) {
      const vec3& x = patch.points[i];
      const real t_a = (1 - x.z()) / n.z();
      const real t_b = nb.dot(pivot - x) / nb.dot(n);
      CHECK(patch.gap[i] == Approx(t_b - t_a).margin(1e-14));
      CHECK(patch.gap[i] > 0);
    }
    const auto [lo, hi] = std::minmax_element(patch.gap.begin(), patch.gap.end());
    CHECK(*hi - *lo == Approx(0.7 * std::tan(theta)).epsilon(1e-6));  // the tilt across the 0.7 m overlap
  }
}

TEST_CASE("detection: edge-face, vertex-face and crossing edges", "[detection]") {
  const convex_polyhedron a = unit_cube_at(vec3::Zero());
  const real g = 0.003, tol = 1e-4;
  const convex_polyhedron centred = convex_polyhedron::box(vec3(-0.5, -0.5, -0.5), vec3(0.5, 0.5, 0.5));
  SECTION("a cube on its edge: a segment over A's top, gap g at both ends") {
    const real half_diagonal = 0.5 * std::numbers::sqrt2;
    const convex_polyhedron b =
        centred.transformed(rotation_about(vec3::UnitX(), std::numbers::pi / 4), vec3(0.7, 0.5, 1 + g + half_diagonal));
    const auto plane = detection::common_plane(a, b);
    CHECK(plane.gap == Approx(g).margin(1e-14));
    const auto patch = detection::contact_patch_of(a, b, plane, tol);
    REQUIRE(patch.type == detection::patch_type::segment);
    CHECK((patch.points[0] - patch.points[1]).norm() == Approx(0.8).epsilon(1e-12));  // x from 0.2 to 1 (A's edge)
    for (real gap : patch.gap) CHECK(gap == Approx(g).margin(1e-14));
    CHECK(sum_of(patch.area) == 0);
  }
  SECTION("a cube on its corner: one point, gap g") {
    // Turn the body diagonal (1,1,1) onto -z: corner (-0.5,-0.5,-0.5) becomes the lowest.
    const vec3 diagonal = vec3(1, 1, 1).normalized();
    const mat3 r = Eigen::Quaterniond::FromTwoVectors(diagonal, vec3::UnitZ()).toRotationMatrix();
    const real half_body_diagonal = 0.5 * std::sqrt(3.0);
    const convex_polyhedron b = centred.transformed(r, vec3(0.4, 0.6, 1 + g + half_body_diagonal));
    const auto plane = detection::common_plane(a, b);
    CHECK(plane.gap == Approx(g).margin(1e-13));
    const auto patch = detection::contact_patch_of(a, b, plane, tol);
    REQUIRE(patch.type == detection::patch_type::point);
    CHECK((patch.points[0] - vec3(0.4, 0.6, 1 + 0.5 * g)).norm() < 1e-12);
    CHECK(patch.gap[0] == Approx(g).margin(1e-13));
  }
  SECTION("two bars on their edges, crossing at right angles: the plane comes from the edge pair") {
    const real h = 0.1 * std::numbers::sqrt2;  // half-diagonal of the 0.2 x 0.2 section
    const convex_polyhedron bar_x = convex_polyhedron::box(vec3(-1, -0.1, -0.1), vec3(1, 0.1, 0.1))
                                        .transformed(rotation_about(vec3::UnitX(), std::numbers::pi / 4), vec3::Zero());
    for (real gap : {g, -g}) {
      const convex_polyhedron bar_y = convex_polyhedron::box(vec3(-0.1, -1, -0.1), vec3(0.1, 1, 0.1))
                                          .transformed(rotation_about(vec3::UnitY(), std::numbers::pi / 4), vec3(0, 0, 2 * h + gap));
      const auto plane = detection::common_plane(bar_x, bar_y);
      CHECK(plane.source == detection::plane_source::edge_edge);
      CHECK((plane.normal - vec3::UnitZ()).norm() < 1e-12);
      CHECK(plane.gap == Approx(gap).margin(1e-14));
      const auto patch = detection::contact_patch_of(bar_x, bar_y, plane, tol);
      REQUIRE(patch.type == detection::patch_type::point);
      CHECK(patch.points[0].head<2>().norm() < 1e-12);
      CHECK(patch.gap[0] == Approx(gap).margin(1e-13));
    }
  }
  SECTION("apart sideways: no patch on the plane") {
    const convex_polyhedron b = unit_cube_at(vec3(1.5, 0, 0));
    const auto plane = detection::common_plane(a, b);
    CHECK((plane.normal - vec3::UnitX()).norm() < 1e-15);
    CHECK(plane.gap == Approx(0.5).margin(1e-14));
    const convex_polyhedron far_corner = unit_cube_at(vec3(1.5, 1.5, 1.5));
    const auto diagonal = detection::common_plane(a, far_corner);
    CHECK(diagonal.gap == Approx(0.5).margin(1e-14));  // the best single axis, not the Euclidean distance
  }
  CHECK_THROWS_AS(detection::contact_patch_of(a, a, detection::common_plane(a, a), 0.0), invalid_input);
}

TEST_CASE("detection: the pruned edge-pair search keeps the separation test and the penetration depth on 2000 random pairs", "[detection]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<real> u(-1, 1);
  const auto random_block = [&] {
    convex_polyhedron p = convex_polyhedron::box(vec3(-0.5, -0.4, -0.3), vec3(0.5, 0.4, 0.3));
    for (int k = 0; k < 4; ++k) {  // cut off random corners
      const vec3 n = vec3(u(rng), u(rng), u(rng)).normalized();
      p.clip(geometry::plane{n, 0.25 + 0.1 * u(rng)}, 100 + k);
    }
    const vec3 axis = vec3(u(rng), u(rng), u(rng)).normalized();
    return p.transformed(rotation_about(axis, std::numbers::pi * u(rng)), vec3::Zero());
  };
  int edge_planes = 0, separated = 0, polygons = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const convex_polyhedron a = random_block();
    const convex_polyhedron b0 = random_block();
    const vec3 direction = vec3(u(rng), u(rng), u(rng)).normalized();
    const convex_polyhedron b = b0.transformed(mat3::Identity(), direction * (0.5 + 0.6 * (u(rng) + 1) / 2));
    const auto ea = detection::edges_of(a), eb = detection::edges_of(b);
    REQUIRE(static_cast<index_t>(ea.list.size()) == a.vertex_count() + a.face_count() - 2);  // Euler
    const auto pruned = detection::common_plane(a, ea, b, eb, true);
    const auto full = detection::common_plane(a, ea, b, eb, false);
    INFO("trial " << trial << ": pruned gap " << pruned.gap << ", full " << full.gap);
    // Overlapping: both find the penetration depth (a face of the Minkowski difference). Apart:
    // both see the separation; the unpruned search may find a non-face axis with a larger gap.
    CHECK((pruned.gap > 0) == (full.gap > 0));
    if (full.gap <= 0)
      CHECK(pruned.gap == Approx(full.gap).margin(1e-12));
    else
      CHECK(pruned.gap <= full.gap + 1e-12);
    CHECK(std::abs(pruned.normal.norm() - 1) < 1e-14);
    edge_planes += full.source == detection::plane_source::edge_edge ? 1 : 0;
    separated += full.gap > 0 ? 1 : 0;
    // Every vertex of A is on or below the plane's A side and every vertex of B above its B side.
    for (const vec3& x : a.vertices()) CHECK(pruned.normal.dot(x) <= pruned.offset - 0.5 * pruned.gap + 1e-12);
    for (const vec3& x : b.vertices()) CHECK(pruned.normal.dot(x) >= pruned.offset + 0.5 * pruned.gap - 1e-12);
    // The patch in a wide band (random polygons, some of them slivers): every tributary area is
    // >= 0 and they sum to the patch area (a centroid fan split slivers into huge +- areas).
    if (pruned.gap < 0.02) {
      const auto patch = detection::contact_patch_of(a, b, pruned, 0.05);
      real sum = 0;
      for (const real area : patch.area) {
        CHECK(area >= 0);
        sum += area;
      }
      CHECK(sum == Approx(patch.total_area).margin(1e-14));
      CHECK(patch.total_area <= 1.0);  // at most the largest face, 1 x 0.8 m
      polygons += patch.type == detection::patch_type::polygon ? 1 : 0;
    }
  }
  INFO(polygons << " polygon patches");
  CHECK(polygons > 100);
  INFO(edge_planes << " edge-edge planes, " << separated << " separated pairs");
  CHECK(edge_planes > 100);  // the edge-pair branch is exercised
  CHECK(separated > 200);
  CHECK(separated < 1900);
}

TEST_CASE("detection: a contact patch written into a used slot with the thread's used scratch is the fresh one to the bit",
          "[detection]") {
  // contact_patch_into reuses its output's vectors and a per-thread scratch (touching points,
  // hulls, facing faces): a value left over from the pair before must never reach a patch. The
  // same 400 random pairs, in one order into one slot, then in reverse order each into a new
  // patch: the same corners, gaps, areas and labels to the bit.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<real> u(-1, 1);
  const auto random_block = [&] {
    convex_polyhedron p = convex_polyhedron::box(vec3(-0.5, -0.4, -0.3), vec3(0.5, 0.4, 0.3));
    for (int k = 0; k < 1 + static_cast<int>(4 * (u(rng) + 1)); ++k) {  // 1-8 random corners cut off
      const vec3 n = vec3(u(rng), u(rng), u(rng)).normalized();
      p.clip(geometry::plane{n, 0.25 + 0.1 * u(rng)}, 100 + k);
    }
    const vec3 axis = vec3(u(rng), u(rng), u(rng)).normalized();
    return p.transformed(rotation_about(axis, std::numbers::pi * u(rng)), vec3::Zero());
  };
  struct trial {
    convex_polyhedron a, b;
    detection::contact_plane plane;
  };
  std::vector<trial> trials;
  while (trials.size() < 400) {
    convex_polyhedron a = random_block(), b0 = random_block();
    const vec3 direction = vec3(u(rng), u(rng), u(rng)).normalized();
    convex_polyhedron b = b0.transformed(mat3::Identity(), direction * (0.5 + 0.6 * (u(rng) + 1) / 2));
    const auto plane = detection::common_plane(a, b);
    if (plane.gap < 0.02) trials.push_back({std::move(a), std::move(b), plane});
  }
  const auto same = [](const detection::contact_patch& x, const detection::contact_patch& y) {
    return x.type == y.type && x.points.size() == y.points.size() && x.gap == y.gap && x.area == y.area &&
           x.label == y.label && x.total_area == y.total_area &&
           std::memcmp(x.points.data(), y.points.data(), x.points.size() * sizeof(vec3)) == 0;
  };
  std::vector<detection::contact_patch> first(trials.size());
  detection::contact_patch slot;
  int kinds[4] = {0, 0, 0, 0};
  for (std::size_t t = 0; t < trials.size(); ++t) {
    std::vector<geometry::plane> fa, fb;
    detection::append_face_planes(trials[t].a, fa);
    detection::append_face_planes(trials[t].b, fb);
    detection::contact_patch_into(trials[t].a, trials[t].b, trials[t].plane, 0.05, fa, fb, slot);
    first[t] = slot;
    ++kinds[static_cast<int>(slot.type)];
    CHECK(slot.gap.size() == slot.points.size());
    CHECK(slot.area.size() == slot.points.size());
    CHECK(slot.label.size() == slot.points.size());
  }
  int differ = 0;
  for (std::size_t t = trials.size(); t-- > 0;)
    differ += same(first[t], detection::contact_patch_of(trials[t].a, trials[t].b, trials[t].plane, 0.05)) ? 0 : 1;
  CHECK(differ == 0);
  INFO(kinds[1] << " points, " << kinds[2] << " segments, " << kinds[3] << " polygons, " << kinds[0] << " none");
  CHECK(kinds[1] > 50);  // (149 points, 177 segments, 74 polygons with this seed)
  CHECK(kinds[2] > 50);
  CHECK(kinds[3] > 50);
}

TEST_CASE("detection broad phase: sweep and prune and the uniform grid give the all-pairs list", "[detection]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<real> u(0, 1);
  std::vector<aabb> boxes;
  for (int i = 0; i < 600; ++i) {
    const vec3 lo(u(rng), u(rng), u(rng));
    const real size = i % 100 == 0 ? 0.3 : 0.02 + 0.05 * u(rng);  // a few large boxes among small ones
    boxes.push_back({lo, lo + size * vec3(0.5 + u(rng), 0.5 + u(rng), 0.5 + u(rng))});
  }
  boxes.push_back({vec3(0.5, 0.5, 0.5), vec3(0.5, 0.5, 0.5)});  // a point box
  detection::sweep_workspace sw;
  detection::grid_workspace gw;
  for (real margin : {0.0, 0.004, 0.05}) {
    std::vector<detection::block_pair> reference, swept, gridded;
    detection::all_pairs(boxes, margin, reference);
    detection::sweep_and_prune(boxes, margin, swept, sw);
    detection::uniform_grid(boxes, margin, gridded, gw);
    INFO("margin " << margin << ": " << reference.size() << " pairs");
    CHECK(reference.size() > 100);
    CHECK(swept == reference);
    CHECK(gridded == reference);
  }
  // Blocks of a Voronoi tessellation: every pair sharing a face is a candidate at zero margin.
  const auto tess = geometry::random_voronoi({vec3::Zero(), vec3(0.1, 0.1, 0.3)}, 300, 5);
  std::vector<aabb> cells(static_cast<std::size_t>(tess.cell_count()));
  for (index_t c = 0; c < tess.cell_count(); ++c) cells[static_cast<std::size_t>(c)] = geometry::cell_polyhedron(tess, c).bounds();
  std::vector<detection::block_pair> pairs;
  detection::sweep_and_prune(cells, 0, pairs, sw);
  for (const auto& f : tess.shared_faces)
    CHECK(std::binary_search(pairs.begin(), pairs.end(), detection::block_pair{f.cell_a, f.cell_b}));
  const aabb bad{vec3(0, 0, 0), vec3(-1, 0, 0)};
  CHECK_THROWS_AS(detection::sweep_and_prune(std::span<const aabb>(&bad, 1), 0, pairs, sw), invalid_input);
  CHECK_THROWS_AS(detection::uniform_grid(boxes, -1, pairs, gw), invalid_input);
}

TEST_CASE("detection broad phase: the grid with marked blocks gives the all-pairs list of the marked pairs", "[detection]") {
  // An incremental pass bins only the cells a marked box reaches and pairs only marked entries,
  // and a big box (a floor, a wall) is tested against every box instead of setting the cell:
  // the list must be the O(n^2) list filtered to the pairs with a marked block, whatever the
  // share marked, the margin, or the workspace's earlier passes (one workspace throughout).
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<real> u(0, 1);
  std::vector<aabb> boxes;
  for (int i = 0; i < 800; ++i) {
    const vec3 lo(1.2 * u(rng), 0.8 * u(rng), 0.4 * u(rng));
    const real size = i % 97 == 0 ? 0.25 : 0.02 + 0.08 * u(rng);  // a few large boxes among small ones
    boxes.push_back({lo, lo + size * vec3(0.5 + u(rng), 0.5 + u(rng), 0.5 + u(rng))});
  }
  boxes.push_back({vec3(1, 0.5, 0.25), vec3(1, 0.5, 0.25)});  // a point box
  // A floor under them and a wall beside them (big boxes, not binned: tested against every box).
  boxes.push_back({vec3(-0.5, -0.5, -0.1), vec3(2, 2, 0.02)});
  boxes.push_back({vec3(-0.05, -0.5, -0.1), vec3(0.01, 2, 1)});
  detection::grid_workspace gw;
  std::vector<std::uint8_t> only(boxes.size());
  std::size_t checked = 0, floor_pairs = 0;
  for (const real share : {0.0, 0.02, 0.2, 0.7, 1.0})
    for (const real margin : {0.0, 0.003, 0.04}) {
      for (std::size_t b = 0; b < only.size(); ++b) only[b] = u(rng) < share ? 1 : 0;
      std::vector<detection::block_pair> all, reference, gridded, full;
      detection::all_pairs(boxes, margin, all);
      for (const auto& c : all)
        if (only[static_cast<std::size_t>(c.a)] != 0 || only[static_cast<std::size_t>(c.b)] != 0) reference.push_back(c);
      const detection::grid_layout g = detection::layout_grid(boxes, margin);
      REQUIRE(g.suits(boxes.size()));
      CHECK(g.big < 2.5);  // the floor and the wall are big
      CHECK(g.cell < 0.5);  // and do not set the cell
      detection::uniform_grid(boxes, margin, g, gridded, gw, only);
      INFO("share " << share << ", margin " << margin << ": " << reference.size() << " of " << all.size() << " pairs");
      CHECK(gridded == reference);
      // A full pass on the same workspace afterwards still gives the whole list.
      detection::uniform_grid(boxes, margin, g, full, gw);
      CHECK(full == all);
      CHECK(all.size() > 500);
      // On 1 and 3 threads (a share of the cells and of the big boxes' tests each, the sorted
      // lists merged), the same lists; the full pass's entries are enough for the shares.
      CHECK(gw.order.size() >= 1024);
      for (const int threads : {1, 3}) {
        const int saved = max_threads();
        set_threads(threads);
        std::vector<detection::block_pair> marked_again, full_again;
        detection::uniform_grid(boxes, margin, g, marked_again, gw, only);
        detection::uniform_grid(boxes, margin, g, full_again, gw);
        set_threads(saved);
        CHECK(marked_again == reference);
        CHECK(full_again == all);
      }
      if (share > 0 && share < 1) CHECK(reference.size() < all.size());
      if (share == 0) CHECK(reference.empty());
      checked += reference.size();
      floor_pairs += static_cast<std::size_t>(std::count_if(reference.begin(), reference.end(), [&](const auto& c) {
        return c.b + 2 >= static_cast<index_t>(boxes.size());
      }));
    }
  CHECK(checked > 5000);
  CHECK(floor_pairs > 100);  // the big boxes' pairs are among them
  const std::vector<std::uint8_t> short_marks(3, 1);
  std::vector<detection::block_pair> pairs;
  CHECK_THROWS_AS(detection::uniform_grid(boxes, 0, detection::layout_grid(boxes, 0), pairs, gw, short_marks), invalid_input);
}

TEST_CASE("detection broad phase: with the rebuild margin no pair that comes to touch is missed", "[detection]") {
  // 400 boxes drift and spin at bounded speeds for `steps` steps; every pair whose boxes overlap
  // at any step must have been a candidate at the rebuild (margin = rebuild_margin).
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<real> u(-1, 1);
  const index_t n = 400, steps = 50;
  const real dt = 1e-3, v_max = 0.2, omega_max = 5, r = 0.02;
  std::vector<vec3> centre(n), velocity(n), axis(n);
  std::vector<real> omega(n);
  for (index_t i = 0; i < n; ++i) {
    centre[static_cast<std::size_t>(i)] = vec3(u(rng), u(rng), u(rng)) * 0.3;
    velocity[static_cast<std::size_t>(i)] = vec3(u(rng), u(rng), u(rng)).normalized() * v_max;  // at the bounds
    axis[static_cast<std::size_t>(i)] = vec3(u(rng), u(rng), u(rng)).normalized();
    omega[static_cast<std::size_t>(i)] = u(rng) < 0 ? -omega_max : omega_max;
  }
  // A block: the cube of half-width r / sqrt(3) (vertices at distance r from its centre), turned.
  const convex_polyhedron cube = convex_polyhedron::box(vec3::Constant(-r / std::sqrt(3.0)), vec3::Constant(r / std::sqrt(3.0)));
  const auto boxes_at = [&](real t) {
    std::vector<aabb> b(static_cast<std::size_t>(n));
    for (index_t i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      b[k] = cube.transformed(rotation_about(axis[k], omega[k] * t), centre[k] + velocity[k] * t).bounds();
    }
    return b;
  };
  const real margin = detection::rebuild_margin(v_max, omega_max, r, dt, steps);
  detection::sweep_workspace w;
  std::vector<detection::block_pair> candidates, touching;
  detection::sweep_and_prune(boxes_at(0), margin, candidates, w);
  // A quarter of the margin is too little: some touching pair is missed (the test can fail).
  std::vector<detection::block_pair> too_few;
  detection::sweep_and_prune(boxes_at(0), 0.25 * margin, too_few, w);
  std::size_t checked = 0, missed_with_less = 0;
  for (index_t s = 1; s <= steps; ++s) {
    detection::sweep_and_prune(boxes_at(static_cast<real>(s) * dt), 0, touching, w);
    for (const auto& p : touching) {
      CHECK(std::binary_search(candidates.begin(), candidates.end(), p));
      missed_with_less += std::binary_search(too_few.begin(), too_few.end(), p) ? 0 : 1;
    }
    checked += touching.size();
  }
  CHECK(missed_with_less > 0);
  std::vector<detection::block_pair> later;
  detection::sweep_and_prune(boxes_at(static_cast<real>(steps) * dt), 0, later, w);
  std::vector<detection::block_pair> at_start;
  detection::sweep_and_prune(boxes_at(0), 0, at_start, w);
  INFO(checked << " touching pairs checked, " << candidates.size() << " candidates");
  CHECK(later != at_start);  // the motion did change which boxes touch
  CHECK(checked > 0);
  CHECK_THROWS_AS(detection::rebuild_margin(-1, 0, 0, dt, steps), invalid_input);
  CHECK_THROWS_AS(detection::rebuild_margin(1, 0, 0, dt, 0), invalid_input);
}

TEST_CASE("detection pass: every face of a Voronoi tessellation moved apart by 1 % is found, same bits on 1 and 2 threads",
          "[detection]") {
  const auto tess = geometry::random_voronoi({vec3::Zero(), vec3(0.15, 0.15, 0.3)}, 300, 9);
  std::vector<convex_polyhedron> blocks;
  std::vector<detection::polyhedron_edges> edges;
  std::vector<aabb> boxes;
  for (index_t c = 0; c < tess.cell_count(); ++c) {
    const convex_polyhedron cell = geometry::cell_polyhedron(tess, c);
    blocks.push_back(cell.transformed(0.99 * mat3::Identity(), 0.01 * cell.centroid()));
    edges.push_back(detection::edges_of(blocks.back()));
    boxes.push_back(blocks.back().bounds());
  }
  const real size = std::cbrt(0.15 * 0.15 * 0.3 / 300);
  detection::detection_options options;
  // Shrinking each side by 1 % opens a face by 1 % of its two centroids' distances to it, up to
  // about 3 % of the mean size for elongated cells: a 5 % tolerance takes every face in.
  options.margin = 0.05 * size;
  options.tolerance = 0.05 * size;
  const int saved = max_threads();
  const auto run = [&](int threads) {
    set_threads(threads);
    detection::detection_result r;
    detection::detection_workspace w;
    detection::detect(blocks, edges, boxes, options, r, w);
    return r;
  };
  const auto one = run(1), two = run(2);
  set_threads(saved);
  REQUIRE(one.pairs == two.pairs);
  REQUIRE(one.point.size() == two.point.size());
  CHECK(std::memcmp(one.point.data(), two.point.data(), one.point.size() * sizeof(vec3)) == 0);
  CHECK(std::memcmp(one.area.data(), two.area.data(), one.area.size() * sizeof(real)) == 0);
  // Every shared face is a touching pair with a polygon patch whose corners are apart by a
  // positive gap; the patches cover the faces but for the 1 % shrink of each side.
  real face_area = 0, patch_area = 0;
  for (const auto& f : tess.shared_faces) {
    const auto it = std::lower_bound(one.pairs.begin(), one.pairs.end(), detection::block_pair{f.cell_a, f.cell_b});
    REQUIRE(it != one.pairs.end());
    REQUIRE(*it == (detection::block_pair{f.cell_a, f.cell_b}));
    const auto k = static_cast<std::size_t>(it - one.pairs.begin());
    CHECK(one.type[k] == detection::patch_type::polygon);
    for (index_t i = one.first_corner[k]; i < one.first_corner[k + 1]; ++i) {
      CHECK(one.gap[static_cast<std::size_t>(i)] > 0);
      // A corner taken from either block's tolerance band (a vertex of a neighbouring face just
      // off the contact face) is up to one tolerance per block further apart than the plane's gap.
      CHECK(one.gap[static_cast<std::size_t>(i)] >= one.planes[k].gap - 1e-12);
      CHECK(one.gap[static_cast<std::size_t>(i)] <= one.planes[k].gap + 2 * options.tolerance);
      patch_area += one.area[static_cast<std::size_t>(i)];
    }
  }
  for (const auto& f : tess.shared_faces) face_area += geometry::face_area(tess, f.face_a);
  INFO(one.candidates << " candidates, " << one.pairs.size() << " touching pairs, " << tess.shared_faces.size()
                      << " shared faces; patch area / face area = " << patch_area / face_area);
  CHECK(one.pairs.size() >= tess.shared_faces.size());
  CHECK(patch_area / face_area > 0.95);
  CHECK(patch_area / face_area < 1.0);
  // The pass computes each block's face planes once and hands them to every pair: the planes
  // and corners are those of the one-off functions, which compute them per call, to the bit.
  for (std::size_t k = 0; k < one.pairs.size(); k += 7) {
    const auto a = static_cast<std::size_t>(one.pairs[k].a), b = static_cast<std::size_t>(one.pairs[k].b);
    const auto plane = detection::common_plane(blocks[a], edges[a], blocks[b], edges[b]);
    CHECK(std::memcmp(&plane.normal, &one.planes[k].normal, sizeof(vec3)) == 0);
    CHECK(plane.gap == one.planes[k].gap);
    const auto patch = detection::contact_patch_of(blocks[a], blocks[b], plane, options.tolerance);
    REQUIRE(static_cast<index_t>(patch.points.size()) == one.first_corner[k + 1] - one.first_corner[k]);
    CHECK(std::memcmp(patch.points.data(), one.point.data() + one.first_corner[k], patch.points.size() * sizeof(vec3)) == 0);
  }
  {
    std::vector<geometry::plane> faces_0;
    detection::append_face_planes(blocks[0], faces_0);
    CHECK_THROWS_AS(detection::common_plane(blocks[0], edges[0], faces_0, blocks[1], edges[1], {}), invalid_input);
    CHECK_THROWS_AS(detection::contact_patch_of(blocks[0], blocks[1], one.planes[0], options.tolerance, faces_0, {}),
                    invalid_input);
  }
  // The parts of a split pass (detection_share, one per rank of a split run), concatenated in
  // part order, are the whole pass to the bit; each part evaluates about a third of the
  // candidates, so each holds a share of the pairs.
  {
    detection::detection_result whole_again;
    whole_again.first_corner.clear();
    whole_again.first_corner.push_back(0);
    detection::detection_workspace w;
    for (int part = 0; part < 3; ++part) {
      detection::detection_result r;
      detection::detect(blocks, edges, boxes, options, r, w, {part, 3});
      CHECK(r.candidates == one.candidates);
      CHECK(r.pairs.size() > one.pairs.size() / 5);
      CHECK(r.pairs.size() < one.pairs.size() / 2);
      whole_again.pairs.insert(whole_again.pairs.end(), r.pairs.begin(), r.pairs.end());
      whole_again.point.insert(whole_again.point.end(), r.point.begin(), r.point.end());
      whole_again.gap.insert(whole_again.gap.end(), r.gap.begin(), r.gap.end());
      whole_again.label.insert(whole_again.label.end(), r.label.begin(), r.label.end());
      for (std::size_t k = 0; k + 1 < r.first_corner.size(); ++k)
        whole_again.first_corner.push_back(whole_again.first_corner.back() + r.first_corner[k + 1] - r.first_corner[k]);
    }
    REQUIRE(whole_again.pairs == one.pairs);
    CHECK(whole_again.first_corner == one.first_corner);
    CHECK(whole_again.label == one.label);
    REQUIRE(whole_again.point.size() == one.point.size());
    CHECK(std::memcmp(whole_again.point.data(), one.point.data(), one.point.size() * sizeof(vec3)) == 0);
    CHECK(std::memcmp(whole_again.gap.data(), one.gap.data(), one.gap.size() * sizeof(real)) == 0);
    detection::detection_result r;
    CHECK_THROWS_WITH(detection::detect(blocks, edges, boxes, options, r, w, {3, 3}), Catch::Contains("part 3 of 3"));
    CHECK_THROWS_WITH(detection::detect(blocks, edges, boxes, options, r, w, {0, 0}), Catch::Contains("part 0 of 0"));
    CHECK_THROWS_AS(detection::detect(blocks, edges, boxes, options, r, w, {-1, 2}), invalid_input);
  }
  // Rigidly placed blocks (placed_faces, a detecting contact set's rigid blocks): the face planes
  // carried from the reference faces by each block's pose give the pass of the planes computed
  // from the moved vertices, to round-off: the same pairs and corner labels, gaps within 1e-12 of
  // the block size, normals within 1e-10 and corners within 1e-10 of the block size (measured:
  // 1.1e-12, 1.2e-11; a face a small fraction of the block wide turns its normal by round-off
  // over its width, either way).
  {
    const mat3 rot = Eigen::AngleAxisd(0.7, vec3(1, 2, 3).normalized()).toRotationMatrix();
    std::vector<convex_polyhedron> moved;
    std::vector<aabb> moved_boxes;
    std::vector<index_t> first{0};
    std::vector<vec3> normal, centroid, shift;
    std::vector<mat3> rots;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      shift.push_back(vec3(0.3, -0.2, 0.1));
      rots.push_back(rot);
      moved.push_back(blocks[b].transformed(rot, shift.back()));
      moved_boxes.push_back(moved.back().bounds());
      for (index_t f = 0; f < blocks[b].face_count(); ++f) {
        normal.push_back(blocks[b].face_normal(f));
        centroid.push_back(blocks[b].face_centroid(f));
      }
      first.push_back(static_cast<index_t>(normal.size()));
    }
    const detection::placed_faces placed{first, normal, centroid, rots, shift};
    detection::detection_result from_vertices, carried;
    detection::detection_workspace w1, w2;
    detection::detect(moved, edges, moved_boxes, options, from_vertices, w1);
    detection::detect(moved, edges, moved_boxes, options, carried, w2, {}, {}, {}, placed);
    REQUIRE(carried.pairs == from_vertices.pairs);
    CHECK(carried.pairs.size() == one.pairs.size());
    CHECK(carried.label == from_vertices.label);
    REQUIRE(carried.point.size() == from_vertices.point.size());
    real normal_diff = 0, gap_diff = 0, point_diff = 0;
    for (std::size_t k = 0; k < carried.pairs.size(); ++k) {
      normal_diff = std::max(normal_diff, (carried.planes[k].normal - from_vertices.planes[k].normal).norm());
      gap_diff = std::max(gap_diff, std::abs(carried.planes[k].gap - from_vertices.planes[k].gap));
    }
    for (std::size_t i = 0; i < carried.point.size(); ++i)
      point_diff = std::max(point_diff, (carried.point[i] - from_vertices.point[i]).norm());
    INFO("normals " << normal_diff << ", gaps " << gap_diff << " m, corners " << point_diff << " m");
    CHECK(normal_diff < 1e-10);
    CHECK(gap_diff < 1e-12 * size);
    CHECK(point_diff < 1e-10 * size);
    // Refusals: a CSR of another block count, a block whose placed faces are not its faces.
    detection::detection_result r;
    detection::placed_faces short_csr = placed;
    short_csr.first = std::span<const index_t>(first).first(first.size() - 1);
    CHECK_THROWS_WITH(detection::detect(moved, edges, moved_boxes, options, r, w2, {}, {}, {}, short_csr),
                      Catch::Contains("placed faces for") && Catch::Contains("blocks"));
    std::vector<index_t> shifted = first;
    shifted[1] += 1;
    detection::placed_faces wrong_block = placed;
    wrong_block.first = shifted;
    CHECK_THROWS_WITH(detection::detect(moved, edges, moved_boxes, options, r, w2, {}, {}, {}, wrong_block),
                      Catch::Contains("block 0 has") && Catch::Contains("placed faces"));
  }
  detection::detection_result r;
  detection::detection_workspace w;
  options.tolerance = 0;
  CHECK_THROWS_AS(detection::detect(blocks, edges, boxes, options, r, w), invalid_input);
}

}  // namespace tessera::test_detection

// ---- named joints and the refusals of detected contacts (issue #40 items 3 and 5) ----

namespace tessera::test_joints {
namespace {

using Catch::Matchers::Contains;
using geometry::convex_polyhedron;
using joint_contacts = contact::detected_contacts<law::dry_joint_law>;

/// The joint as examples/verification fills it by hand (cases.hpp joint()).
law::dry_joint_law::params hand_filled(real k_n, real k_s, real phi_deg) {
  law::dry_joint_law::params p;
  p.k_n = k_n;
  p.k_s = k_s;
  p.shear.phi_0 = law::friction_angle::from_degrees(phi_deg);
  p.shear.phi_res = p.shear.phi_0;
  return p;
}

/// A b = 0.5 m cube whose bottom lies `overlap` (m) below the top z = 0 of a 4 x 2 x 0.5 m base.
geometry::tessellation cube_on_base(real overlap) {
  const real b = 0.5;
  return geometry::separate_blocks(std::vector<convex_polyhedron>{
      convex_polyhedron::box({-2, -1, -0.5}, {2, 1, 0}), convex_polyhedron::box({-b / 2, -b / 2, -overlap}, {b / 2, b / 2, b - overlap})});
}

/// The depth (m) that an overlap refusal names: the number after "overlap by ".
real named_depth(const std::string& message) {
  const auto at = message.find("overlap by ");
  REQUIRE(at != std::string::npos);
  return std::stod(message.substr(at + 11));
}

}  // namespace

TEST_CASE("joints: law::dry_joint fills the hand-filled dry joint, refuses bad values", "[joints]") {
  const auto p = law::dry_joint(1e9, 4e8, law::friction_angle::from_degrees(30));
  const auto q = hand_filled(1e9, 4e8, 30);
  CHECK(p.k_n == q.k_n);
  CHECK(p.k_s == q.k_s);
  CHECK(p.shear.c_0 == 0);
  CHECK(p.shear.c_res == 0);
  CHECK(p.shear.phi_0.radians() == q.shear.phi_0.radians());
  CHECK(p.shear.phi_res.radians() == q.shear.phi_res.radians());
  CHECK(p.shear.phi_res.tan() == Approx(std::tan(std::numbers::pi / 6)).epsilon(1e-15));
  CHECK(p.shear.slip_breaks_tension == q.shear.slip_breaks_tension);
  const auto deg = [](real d) { return law::friction_angle::from_degrees(d); };
  CHECK_THROWS_WITH(law::dry_joint(0, 1e9, deg(30)), Contains("law::dry_joint: normal stiffness k_n = 0 Pa/m"));
  CHECK_THROWS_WITH(law::dry_joint(1e9, -1, deg(30)), Contains("shear stiffness k_s = -1 Pa/m"));
  CHECK_THROWS_WITH(law::dry_joint(1e9, 1e9, deg(90)), Contains("friction angle = 90 deg must be in [0, 90) deg"));
  CHECK_THROWS_WITH(law::dry_joint(1e9, 1e9, deg(-5)), Contains("friction angle = -5 deg"));
  CHECK_NOTHROW(law::dry_joint(1e9, 1e9, deg(0)));  // frictionless, when meant
}

TEST_CASE("joints: law::bonded_joint names every field, refuses one not given", "[joints]") {
  const auto deg = [](real d) { return law::friction_angle::from_degrees(d); };
  law::bonded_joint_values v{.k_n = 2e10,
                             .k_s = 8e9,
                             .tensile_strength = 1.5e5,
                             .fracture_energy = 12,
                             .cohesion = 3e5,
                             .friction = deg(35),
                             .residual_cohesion = 3e3,
                             .residual_friction = deg(30)};
  const law::bonded_joint_law::params p = law::bonded_joint(v);
  CHECK(p.k_n == 2e10);
  CHECK(p.k_s == 8e9);
  CHECK(p.tension.f_T == 1.5e5);
  CHECK(p.tension.G_f == 12);
  CHECK(p.shear.c_0 == 3e5);
  CHECK(p.shear.phi_0.degrees() == Approx(35).epsilon(1e-14));
  CHECK(p.shear.c_res == 3e3);
  CHECK(p.shear.phi_res.degrees() == Approx(30).epsilon(1e-14));
  // The law it feeds: the intact limit under 1 MPa of compression is c_0 + 1e6 tan 35.
  CHECK(law::bonded_joint_law::shear_strength(p, {.sigma_n = -1e6}) ==
        Approx(3e5 + 1e6 * std::tan(35 * std::numbers::pi / 180)).epsilon(1e-12));
  auto missing = v;
  missing.residual_friction.reset();
  CHECK_THROWS_WITH(law::bonded_joint(missing), Contains("residual_friction (phi_res) was not given"));
  missing = v;
  missing.residual_cohesion = std::numeric_limits<real>::quiet_NaN();
  CHECK_THROWS_WITH(law::bonded_joint(missing), Contains("residual_cohesion c_res (Pa) was not given"));
  auto bad = v;
  bad.residual_cohesion = 4e5;
  CHECK_THROWS_WITH(law::bonded_joint(bad), Contains("residual_cohesion c_res = 400000 Pa must be in [0, cohesion c_0 = 300000 Pa]"));
  bad = v;
  bad.fracture_energy = 1e-3;  // below f_T^2/(2 k_n) = 0.5625 N/m
  CHECK_THROWS_WITH(law::bonded_joint(bad), Contains("G_f must exceed f_T^2/(2 k_n) = 0.5625 N/m"));
  bad = v;
  bad.tensile_strength = 0;
  CHECK_THROWS_WITH(law::bonded_joint(bad), Contains("tensile_strength f_T = 0 Pa must be finite and > 0"));
}

TEST_CASE("joints: a cube on a 20 deg incline with a 30 deg dry joint sticks, and phi_res left 0 is refused", "[joints]") {
  // The level base and tilted gravity g (sin 20, 0, -cos 20), as examples/verification's incline.
  // Undamped, 0.2 s: a joint that sticks moves the cube only by its elastic shear W sin 20/(k_s A)
  // = 4 um (k_s = 1e9 Pa/m, A = 0.25 m^2), up to twice that as the undamped spring swings
  // (measured 9.7 um down the slope); frictionless joints (the trap, phi_res = 0) would slide it
  // g sin 20 t^2 / 2 = 67 mm.
  const real theta = 20 * std::numbers::pi / 180, g = 9.81, b = 0.5, k = 1e9;
  const real overlap = 2400 * b * b * b * g * std::cos(theta) / (k * b * b);  // static, W cos / (k_n A)
  const geometry::tessellation tess = cube_on_base(overlap);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  using rigid_solver = solver<blocks::rigid, joint_contacts>;
  rigid_solver s(tess, mesh, blocks::rigid::params{2400},
                 joint_contacts::params(law::dry_joint(k, k, law::friction_angle::from_degrees(30)), 1e-3));
  s.fix(s.gridpoints_on_plane(2, -0.5, 1e-9));
  s.set_gravity(vec3(g * std::sin(theta), 0, -g * std::cos(theta)));
  const auto steps = static_cast<std::int64_t>(std::ceil(0.2 / s.dt()));
  s.run(steps);
  const vec3 u = s.blocks().displacement(1);
  INFO(steps << " steps, cube displacement " << u.transpose() << " m");
  CHECK(s.time() >= 0.2);
  CHECK(std::abs(u.x()) < 2e-5);  // 5 x the elastic shear; sliding would be 3 000 x more
  CHECK(std::abs(u.z()) < 2e-5);
  // The same joint with only phi_0 written: refused before anything runs, naming phi_res.
  auto trap = hand_filled(k, k, 30);
  trap.shear.phi_res = law::friction_angle{};
  CHECK_THROWS_WITH((rigid_solver(tess, mesh, blocks::rigid::params{2400}, joint_contacts::params(trap, 1e-3))),
                    Contains("material pair (0, 0) has residual friction phi_res = 0 deg while phi_0 = 30 deg") &&
                        Contains("law::dry_joint"));
  // Frictionless joints written as such are accepted.
  CHECK_NOTHROW(joint_contacts(tess, mesh, joint_contacts::params(hand_filled(k, k, 0), 1e-3)));
  // A cohesion c_0 that unbonded contacts would never use is refused; bonded faces use it.
  auto cohesive = hand_filled(k, k, 30);
  cohesive.shear.c_0 = 1e4;
  CHECK_THROWS_WITH(joint_contacts(tess, mesh, joint_contacts::params(cohesive, 1e-3)),
                    Contains("residual cohesion c_res = 0 Pa while c_0 = 10000 Pa") && Contains("bond_faces is false"));
  CHECK_NOTHROW(joint_contacts(tess, mesh, joint_contacts::params(cohesive, 1e-3, 1000, /*bond_faces=*/true)));
}

TEST_CASE("joints: an initial overlap deeper than the tolerance is refused naming the blocks and the depth", "[joints]") {
  const real tol = 1e-3;
  const auto joint = law::dry_joint(1e9, 1e9, law::friction_angle::from_degrees(30));
  for (const bool deformable : {false, true}) {
    INFO("deformable_blocks = " << deformable);
    // 10 x the tolerance: refused, the depth read from the common plane (exact for convex blocks).
    const geometry::tessellation deep = cube_on_base(10 * tol);
    const geometry::block_mesh deep_mesh = geometry::zone_blocks(deep);
    joint_contacts::params p(joint, tol, 1000, false, deformable);
    std::string message;
    try {
      const joint_contacts c(deep, deep_mesh, p);
      static_cast<void>(c);
    } catch (const invalid_input& e) {
      message = e.what();
    }
    CHECK_THAT(message, Contains("blocks 0 and 1 overlap by") && Contains("more than the contact tolerance 0.001 m") &&
                            Contains("allow_initial_overlap"));
    if (!message.empty()) CHECK(named_depth(message) == Approx(10 * tol).epsilon(1e-9));
    // Opted in: accepted, the corners start at their overlap (u_n = -10 tol).
    p.allow_initial_overlap = true;
    const joint_contacts opted(deep, deep_mesh, p);
    REQUIRE(opted.subcontact_count() >= 4);
    for (index_t i = 0; i < opted.subcontact_count(); ++i) CHECK(opted.state(i).u_n == Approx(-10 * tol).epsilon(1e-9));
    // Half the tolerance (more than any static overlap W/(k_n A) of the verification cases):
    // accepted without the flag.
    const geometry::tessellation shallow = cube_on_base(0.5 * tol);
    const geometry::block_mesh shallow_mesh = geometry::zone_blocks(shallow);
    const joint_contacts c(shallow, shallow_mesh, joint_contacts::params(joint, tol, 1000, false, deformable));
    REQUIRE(c.subcontact_count() >= 4);
    for (index_t i = 0; i < c.subcontact_count(); ++i) CHECK(c.state(i).u_n == Approx(-0.5 * tol).epsilon(1e-9));
  }
}

TEST_CASE("joints: a tolerance above a quarter of the thinnest block is refused naming both sizes and the fraction",
          "[joints]") {
  // The 4 x 2 x 0.5 m base and a 0.5 m cube on it, then a 0.1 m thin slab under the cube: the
  // thinnest width is 0.5 m (the base's, found first), then the slab's 0.1 m. A tolerance that reaches across a
  // block puts its far side's vertices into its patches; a quarter of the thinnest width is allowed.
  const auto joint = law::dry_joint(1e9, 1e9, law::friction_angle::from_degrees(30));
  const geometry::tessellation tess = cube_on_base(0);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  CHECK(contact::max_tolerance_fraction == 0.25);
  CHECK_NOTHROW(joint_contacts(tess, mesh, joint_contacts::params(joint, 0.125)));  // exactly a quarter of 0.5 m
  std::string message;
  try {
    const joint_contacts c(tess, mesh, joint_contacts::params(joint, 0.2));
    static_cast<void>(c);
  } catch (const invalid_input& e) {
    message = e.what();
  }
  if (std::getenv("TESSERA_PRINT_ERRORS")) std::cout << message << '\n';
  CHECK_THAT(message, Contains("contact tolerance 0.2 m is 0.4 x the width 0.5 m of block 0, the thinnest block") &&
                          Contains("at most contact::max_tolerance_fraction = 0.25 of it (0.125 m)"));
  const geometry::tessellation slab = geometry::separate_blocks(std::vector<convex_polyhedron>{
      convex_polyhedron::box({-2, -1, -0.5}, {2, 1, 0}), convex_polyhedron::box({-1, -1, 0}, {1, 1, 0.1}),
      convex_polyhedron::box({-0.25, -0.25, 0.1}, {0.25, 0.25, 0.6})});
  const geometry::block_mesh slab_mesh = geometry::zone_blocks(slab);
  CHECK_NOTHROW(joint_contacts(slab, slab_mesh, joint_contacts::params(joint, 0.02)));
  CHECK_THROWS_WITH(joint_contacts(slab, slab_mesh, joint_contacts::params(joint, 0.03)),
                    Contains("0.3 x the width 0.1 m of block 1") && Contains("(0.025 m) is accepted"));
  // Deformable blocks are refused by the same rule.
  CHECK_THROWS_WITH(joint_contacts(slab, geometry::zone_blocks(slab), joint_contacts::params(joint, 0.03, 1000, false, true)),
                    Contains("0.3 x the width 0.1 m of block 1"));
}

}  // namespace tessera::test_joints

// ---- the rooms of detected_contacts that hold behaviour of their own (contact/detected/) ----

namespace tessera::test_detected {
namespace {
using geometry::convex_polyhedron;
}  // namespace

TEST_CASE("detected keys: the merge of sorted keys finds each persisting corner once, gridpoint labels read back",
          "[detected]") {
  using contact::detail::node_label;
  // Gridpoint labels: kind 3 in the top two bits, the side in bit 61, the gridpoint below; the
  // corner labels' kinds 0-2 are not gridpoint labels.
  const std::uint64_t on_b = node_label(123456789, true), on_a = node_label(123456789, false);
  CHECK(contact::detail::is_node_label(on_b));
  CHECK(contact::detail::node_label_side_b(on_b));
  CHECK_FALSE(contact::detail::node_label_side_b(on_a));
  CHECK(contact::detail::node_label_gridpoint(on_b) == 123456789);
  CHECK(contact::detail::node_label_gridpoint(on_a) == 123456789);
  CHECK_FALSE(contact::detail::is_node_label(std::uint64_t{2} << 62));
  CHECK(on_a < on_b);  // side A's gridpoint labels sort first
  // Old sub-contacts, sorted by (a, b, label): pairs (0, 1), (0, 2), (1, 2).
  const std::vector<index_t> pair_a{0, 0, 1}, pair_b{1, 2, 2}, pair_first{0, 3, 4, 6};
  const std::vector<std::uint64_t> label{5, 9, 12, on_b, 1, 7};
  // New keys in increasing order: (0,1,9) persists as old 1, (0,1,10) is new (the cursor stops at
  // (0,1,12)), (0,2,on_b) persists as old 3, (1,2,7) as old 5, (1,3,0) is new past the end (no
  // old pair (1, 3): find_old_pair gives pair_a.size()).
  struct key {
    index_t a, b;
    std::uint64_t label;
    bool pair_found, found;
    std::size_t old_pair, old;
  };
  const std::vector<key> keys{{0, 1, 9, true, true, 0, 1}, {0, 1, 10, true, false, 0, 2},
                              {0, 2, on_b, true, true, 1, 3}, {1, 2, 7, true, true, 2, 5},
                              {1, 3, 0, false, false, 3, 0}};
  std::size_t old_pair = 0, old = 0, end = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const key& k = keys[i];
    INFO("key (" << k.a << ", " << k.b << ", " << k.label << ")");
    const bool new_pair = i == 0 || keys[i - 1].a != k.a || keys[i - 1].b != k.b;
    if (new_pair) {
      old_pair = contact::detail::find_old_pair(k.a, k.b, pair_a, pair_b);  // (none: pair_a.size())
      CHECK((old_pair < pair_a.size()) == k.pair_found);
      old = k.pair_found ? static_cast<std::size_t>(pair_first[old_pair]) : 0;
      end = k.pair_found ? static_cast<std::size_t>(pair_first[old_pair + 1]) : 0;
    }
    CHECK(old_pair == k.old_pair);
    CHECK(contact::detail::seek_old_label(old, end, k.label, label) == k.found);
    CHECK(old == k.old);
  }
  // The side a pair's gridpoint sub-contacts used at the last rebuild: B for (0, 2), none for the
  // corners of (0, 1) and for a pair that did not exist.
  CHECK(contact::detail::previous_node_side(pair_a, pair_b, pair_first, label, 0, 2) == 1);
  CHECK(contact::detail::previous_node_side(pair_a, pair_b, pair_first, label, 0, 1) == -1);
  CHECK(contact::detail::previous_node_side(pair_a, pair_b, pair_first, label, 1, 3) == -1);
  const std::vector<std::uint64_t> on_a_side{5, 9, 12, on_a, 1, 7};
  CHECK(contact::detail::previous_node_side(pair_a, pair_b, pair_first, on_a_side, 0, 2) == 0);
}

TEST_CASE("detected frames: a block's affine weights reproduce a point, which moves with a rigid motion of the frame",
          "[detected]") {
  // One 2 x 1 x 0.5 m box: 8 vertices, 12 edges, surface S = 7 m^2, centroid (1, 0.5, 0.25) m.
  const geometry::tessellation tess = geometry::separate_blocks(std::vector<convex_polyhedron>{
      convex_polyhedron::box({0, 0, 0}, {2, 1, 0.5})});
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  soa3 reference(mesh.gridpoint_count(), 3);
  for (index_t g = 0; g < mesh.gridpoint_count(); ++g)
    reference.row(g) = mesh.gridpoints[static_cast<std::size_t>(g)].transpose();
  std::vector<index_t> vertex_gridpoints;
  contact::detail::detected_block bd;
  convex_polyhedron shape;
  contact::detection::polyhedron_edges edges;
  contact::detail::build_block_frame(tess, mesh, 0, vertex_gridpoints, bd, shape, edges);
  CHECK(vertex_gridpoints.size() == 8);
  CHECK(edges.list.size() == 12);
  CHECK(bd.surface == Approx(7).epsilon(1e-14));
  CHECK(bd.nominal_area == Approx(7.0 / 24).epsilon(1e-14));  // S / (3 V)
  CHECK((bd.centroid - vec3(1, 0.5, 0.25)).norm() < 1e-14);
  // The farthest vertex from the centroid is a corner: sqrt(1 + 0.25 + 0.0625) m away.
  CHECK((reference.row(bd.farthest).transpose() - bd.centroid).norm() == Approx(std::sqrt(1.3125)).epsilon(1e-14));
  // The frame spans the block: a corner, the far end of its diagonal, the corner farthest from
  // that line and the one farthest from their plane; |det d| = 1 m^3 whichever corner starts.
  CHECK(std::abs(contact::detail::frame_matrix(reference, bd, nullptr).determinant()) == Approx(1).epsilon(1e-14));
  // A point's affine weights (sum 1) reproduce it: x = sum_k w_k x_k.
  const vec3 p(0.3, 0.7, 0.1);
  const vec3 x0 = contact::detail::gridpoint_position(reference, bd.frame[0], nullptr);
  const vec3 l = contact::detail::frame_inverse(reference, bd, nullptr) * (p - x0);
  const std::array<real, 4> w{1 - l.sum(), l.x(), l.y(), l.z()};
  vec3 x = vec3::Zero();
  for (std::size_t k = 0; k < 4; ++k) x += w[k] * reference.row(bd.frame[k]).transpose();
  CHECK((x - p).norm() < 1e-14);
  // A rigid motion of the gridpoints (30 deg about z, then a shift) moves the point with the same
  // weights to R p + t, and the frame's rotation and the block's motion read R and the velocity.
  const mat3 r = Eigen::AngleAxis<real>(std::numbers::pi / 6, vec3::UnitZ()).toRotationMatrix();
  const vec3 t(0.4, -0.2, 1.5), omega(0, 0, 2.0), v_t(1.0, 0.5, 0);  // rad/s, m/s
  node_set gp;
  gp.resize(mesh.gridpoint_count());
  for (index_t g = 0; g < mesh.gridpoint_count(); ++g) {
    const vec3 xg = reference.row(g).transpose();
    gp.displacement.row(g) = (r * xg + t - xg).transpose();
    gp.velocity.row(g) = (v_t + omega.cross(r * xg + t)).transpose();
  }
  CHECK((contact::detail::frame_rotation(reference, bd, &gp) - r).norm() < 1e-14);
  const contact::detail::block_motion m = contact::detail::motion_of(reference, bd, gp, false);
  CHECK((m.rotation - r).norm() < 1e-14);
  CHECK((m.normal_map - r).norm() < 1e-14);
  vec3 moved = vec3::Zero(), velocity = vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    const index_t g = bd.frame[static_cast<std::size_t>(k)];
    moved += w[static_cast<std::size_t>(k)] * contact::detail::gridpoint_position(reference, g, &gp);
    velocity += w[static_cast<std::size_t>(k)] * gp.velocity.row(g).transpose();
  }
  CHECK((moved - (r * p + t)).norm() < 1e-14);
  CHECK((m.x0 + m.d * l - (r * p + t)).norm() < 1e-14);
  CHECK((m.v0 + m.dv * l - (v_t + omega.cross(r * p + t))).norm() < 1e-13);
  CHECK((velocity - (v_t + omega.cross(r * p + t))).norm() < 1e-13);
  // A deformable block's face normals turn with F^-T: for a rigid motion F^-T = R as well.
  CHECK((contact::detail::motion_of(reference, bd, gp, true).normal_map - r).norm() < 1e-14);
}

}  // namespace tessera::test_detected

// ---- incremental rebuilds of detected contacts (contact/detected/incremental.hpp) ----
namespace tessera::test_incremental {
namespace {

using geometry::convex_polyhedron;
using joint_contacts = contact::detected_contacts<law::dry_joint_law>;

/// Moves every gridpoint of block b by `du` (m) this step, its velocity du / dt.
void move_block(node_set& gp, const geometry::block_mesh& mesh, index_t b, const vec3& du, real dt) {
  for (index_t g = mesh.block_gridpoint_offsets[static_cast<std::size_t>(b)];
       g < mesh.block_gridpoint_offsets[static_cast<std::size_t>(b) + 1]; ++g) {
    gp.displacement.row(g) += du.transpose();
    gp.velocity.row(g) = (du / dt).transpose();
  }
}
void hold_all(node_set& gp) { gp.velocity.setZero(); }

/// Dry joints (k_n = k_s = 1e9 Pa/m, 30 deg) on a scene whose blocks may start pressed together.
joint_contacts pressed_contacts(const geometry::tessellation& tess, const geometry::block_mesh& mesh, real tol,
                                index_t interval) {
  joint_contacts::params p(law::dry_joint(1e9, 1e9, law::friction_angle::from_degrees(30)), tol, interval);
  p.allow_initial_overlap = true;
  return joint_contacts(tess, mesh, p);
}

/// The start of the pressed-block tests: pressed_contacts (tolerance `tol` m, rebuild interval
/// `interval` updates) on (tess, mesh) and a node_set for its gridpoints, at rest, after the
/// set's first update of `dt` s.
struct pressed_start {
  joint_contacts c;
  node_set gp;
};
pressed_start pressed_at_rest(const geometry::tessellation& tess, const geometry::block_mesh& mesh, real tol,
                              index_t interval, real dt) {
  pressed_start s{pressed_contacts(tess, mesh, tol, interval), node_set{}};
  s.gp.resize(mesh.gridpoint_count());
  s.c.update(s.gp, dt);
  return s;
}

/// A 4 x 2 x 0.5 m base (block 0, top z = 0); block 1, a 0.5 m cube overhanging the base's edge
/// x = 2 by half; block 2, a 0.5 m cube on the base far from it; both pressed `overlap` m in.
geometry::tessellation pressed_cubes(real overlap) {
  return geometry::separate_blocks(std::vector<convex_polyhedron>{
      convex_polyhedron::box({-2, -1, -0.5}, {2, 1, 0}), convex_polyhedron::box({1.75, -0.25, -overlap}, {2.25, 0.25, 0.5}),
      convex_polyhedron::box({-1.5, -0.25, -overlap}, {-1, 0.25, 0.5})});
}

struct kept_corner {
  std::uint64_t label;
  real area, sigma_n;
};
/// The sub-contacts of pair (a, b): label, area and normal stress.
std::vector<kept_corner> corners_of(const joint_contacts& c, index_t a, index_t b) {
  std::vector<kept_corner> out;
  for (index_t i = 0; i < c.size(); ++i)
    if (c.block_a(i) == a && c.block_b(i) == b) out.push_back({c.label(i), c.area(i), c.state(i).sigma_n});
  return out;
}

}  // namespace

TEST_CASE("incremental rebuild: a pair whose blocks stayed inside their margins keeps its sub-contacts to the bit",
          "[detected][incremental]") {
  // A 4 x 2 x 0.5 m base (block 0, never moves); block 1, a 0.5 m cube overhanging the base's
  // edge x = 2 by half, pressed 0.2 mm into it; block 2, a 0.5 m cube on the base far from it,
  // also pressed in. Tolerance 1 mm. Block 1 slides 0.15 mm onto the base (inside its 0.22 mm
  // margin: the patch grows, so a pass would change its tributary areas); then block 2 jumps
  // 0.45 mm a step (past the 0.39 mm trigger) five times: five rebuilds, each of block 2's pairs.
  const real tol = 1e-3, overlap = 2e-4, dt = 1e-4;
  const geometry::tessellation tess = pressed_cubes(overlap);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  const auto run = [&](index_t interval) {
    auto [c, gp] = pressed_at_rest(tess, mesh, tol, interval, dt);
    const auto before = corners_of(c, 0, 1);
    const index_t rebuilds = c.rebuild_count();
    const real exchange = c.retired_energies().rebuild_exchange;
    move_block(gp, mesh, 1, vec3(-1.5e-4, 0, 0), dt);
    c.update(gp, dt);
    hold_all(gp);
    for (int k = 0; k < 5; ++k) {
      move_block(gp, mesh, 2, vec3(0.45 * tol, 0, 0), dt);
      c.update(gp, dt);
      hold_all(gp);
    }
    return std::tuple{before, corners_of(c, 0, 1), c.rebuild_count() - rebuilds,
                      c.retired_energies().rebuild_exchange - exchange, c.untouched_pairs_last_rebuild()};
  };
  // The incremental rebuilds: pair (0, 1) is untouched, its corners keep their areas to the bit
  // and the rebuilds exchange no energy (block 2 slides inside the base's face: same corners,
  // same areas).
  const auto [before, after, rebuilds, exchange, untouched] = run(1000);
  CHECK(rebuilds == 5);
  CHECK(untouched == 1);
  REQUIRE(before.size() == after.size());
  REQUIRE(before.size() >= 4);
  for (std::size_t i = 0; i < before.size(); ++i) {
    CHECK(after[i].label == before[i].label);
    CHECK(after[i].area == before[i].area);
    CHECK(after[i].sigma_n == before[i].sigma_n);  // pressed, not moved along the normal
    CHECK(after[i].sigma_n < 0);
  }
  // (The re-detected pair's areas differ from its last pass's in the last bits, so its
  // exchange is round-off; a full pass moves energy because pair (0, 1) changed.)
  // A full pass at every step (interval 1) finds the grown patch: other areas, and energy out of
  // the springs (a grown area keeps the corner's force, so its spring holds less).
  const auto [before_full, after_full, rebuilds_full, exchange_full, untouched_full] = run(1);
  CHECK(untouched_full == 0);
  CHECK(rebuilds_full == 6);  // the slide's step too
  real area_before = 0, area_after = 0;
  for (const auto& k : before_full) area_before += k.area;
  for (const auto& k : after_full) area_after += k.area;
  // 0.5 m wide strip 0.25 m long grown by 0.15 mm: +0.075 mm^2... = 7.5e-5 m^2
  CHECK(area_after - area_before == Approx(0.5 * 1.5e-4).epsilon(1e-6));
  CHECK(exchange_full < 0);
  CHECK(std::abs(exchange) < 1e-9 * std::abs(exchange_full));
}

TEST_CASE("incremental rebuild: blocks moving at different speeds meet no neighbour unseen, same bits on 1 and 2 threads",
          "[detected][incremental]") {
  // A 4 x 4 layer of 0.2 m cubes 2 tolerances apart on a fixed base (block 0); each cube slides
  // at its own speed and direction: two at 0.35 tolerance a step, which bring a rebuild every
  // other step, the others at 0, 0.03 or 0.06, which stay inside their margins across several. At every step every pair of
  // blocks that touches (the common plane's gap <= 0, from the blocks' current geometry) must
  // be a pair of the contact set.
  const real tol = 1e-3, dt = 1e-4, edge = 0.2, gap = 2 * tol;
  std::vector<convex_polyhedron> shapes{convex_polyhedron::box({-0.5, -0.5, -0.3}, {1.5, 1.5, 0})};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const vec3 lo(i * (edge + gap), j * (edge + gap), 0);
      shapes.push_back(convex_polyhedron::box(lo, lo + vec3(edge, edge, edge)));
    }
  const geometry::tessellation tess = geometry::separate_blocks(shapes);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  std::mt19937 rng(7);
  std::uniform_real_distribution<real> unit(-1, 1);
  std::vector<vec3> step_of(shapes.size(), vec3::Zero());
  for (std::size_t b = 1; b < shapes.size(); ++b)
    step_of[b] = vec3(unit(rng), unit(rng), 0).normalized() * (b % 8 == 1 ? 0.35 * tol : 0.03 * tol * (b % 3));
  const auto run = [&](int threads, bool check) {
    set_threads(threads);
    joint_contacts c(tess, mesh, joint_contacts::params(law::dry_joint(1e9, 1e9, law::friction_angle::from_degrees(30)), tol));
    node_set gp;
    gp.resize(mesh.gridpoint_count());
    std::vector<vec3> at(shapes.size(), vec3::Zero());
    index_t missed = 0, touching = 0;
    for (int k = 0; k < 60; ++k) {
      for (std::size_t b = 1; b < shapes.size(); ++b) {
        move_block(gp, mesh, static_cast<index_t>(b), step_of[b], dt);
        at[b] += step_of[b];
      }
      c.update(gp, dt);
      if (!check) continue;
      for (std::size_t a = 0; a < shapes.size(); ++a)
        for (std::size_t b = a + 1; b < shapes.size(); ++b) {
          const auto pa = shapes[a].transformed(mat3::Identity(), at[a]), pb = shapes[b].transformed(mat3::Identity(), at[b]);
          if (contact::detection::common_plane(pa, pb).gap > 0) continue;
          ++touching;
          bool found = false;
          for (index_t q = 0; q < c.pair_count(); ++q)
            found = found || (c.pair_blocks(q)[0] == static_cast<index_t>(a) && c.pair_blocks(q)[1] == static_cast<index_t>(b));
          missed += found ? 0 : 1;
        }
    }
    std::vector<real> states;
    for (index_t i = 0; i < c.size(); ++i) states.push_back(c.state(i).sigma_n), states.push_back(c.state(i).u_n);
    return std::tuple{missed, touching, c.rebuild_count(), c.redetected_blocks(), states, gp.force, c.placed_blocks()};
  };
  const int before = max_threads();
  const auto one = run(1, true);
  const auto two = run(2, false);
  set_threads(before);
  INFO(std::get<1>(one) << " touching pair-steps, " << std::get<2>(one) << " rebuilds, " << std::get<3>(one)
                        << " blocks detected again");
  CHECK(std::get<0>(one) == 0);
  CHECK(std::get<1>(one) > 100);  // the layer closes up: many pair-steps in touch
  CHECK(std::get<2>(one) > 20);
  // Incremental: fewer blocks detected again than 17 per rebuild (a full pass each).
  CHECK(std::get<3>(one) < 17 * std::get<2>(one) / 2);
  // Placed: every block detected again, and of the others only those the pass read (the blocks
  // of a candidate pair), so fewer than every block at every rebuild; the same on 2 threads.
  INFO(std::get<6>(one) << " blocks placed");
  CHECK(std::get<6>(one) >= std::get<3>(one));
  CHECK(std::get<6>(one) < 17 * std::get<2>(one) * 3 / 4);
  CHECK(std::get<6>(one) == std::get<6>(two));
  CHECK(std::get<4>(one) == std::get<4>(two));
  CHECK((std::get<5>(one).array() == std::get<5>(two).array()).all());
}

TEST_CASE("incremental rebuild: the blocks placed in parallel refuse the first bad pose in block order",
          "[detected][incremental]") {
  // 200 unit cubes placed by contact::detail::place_blocks (a rebuild's current shapes and boxes,
  // the blocks shared between the threads): block 30 gets a mirror (determinant -1) and block 150
  // a map scaled by -2 (determinant -8), poses assign_transformed refuses, one in each thread's
  // share on 2 threads. On 1 and 2 threads the refusal names block 30's determinant (the first in
  // block order, as a serial loop refused), and the blocks before it are placed.
  const std::size_t n = 200;
  const std::vector<convex_polyhedron> shapes(n, convex_polyhedron::box(vec3::Zero(), vec3::Ones()));
  const auto place = [&](int threads) {
    set_threads(threads);
    std::vector<convex_polyhedron> current(n);
    std::vector<aabb> boxes(n);
    contact::detail::pair_poses pp;
    std::string message = "<nothing thrown>";
    try {
      contact::detail::place_blocks(pp, shapes, current, boxes, [&](std::size_t b, mat3& map, vec3& shift) {
        map = b == 30 ? mat3(vec3(-1, 1, 1).asDiagonal()) : b == 150 ? mat3(-2 * mat3::Identity()) : mat3::Identity();
        shift = vec3(static_cast<real>(b), 0, 0);
      });
    } catch (const std::exception& e) {
      message = e.what();
    }
    return std::pair{message, boxes};
  };
  const int before = max_threads();
  for (const int threads : {1, 2}) {
    INFO(threads << " threads");
    const auto [message, boxes] = place(threads);
    CHECK_THAT(message, Catch::Matchers::Contains("positive determinant (it is -1)"));
    for (const std::size_t b : {std::size_t{0}, std::size_t{29}}) {
      CHECK(boxes[b].lo.x() == static_cast<real>(b));
      CHECK(boxes[b].hi.x() == static_cast<real>(b) + 1);
    }
  }
  // Marked blocks only (an incremental rebuild's): the others get bound_of's box and keep their
  // shapes as they were.
  set_threads(2);
  std::vector<convex_polyhedron> current(n, convex_polyhedron::box(vec3::Zero(), vec3::Ones()));
  std::vector<aabb> boxes(n);
  std::vector<std::uint8_t> only(n, 0);
  for (std::size_t b = 0; b < n; b += 3) only[b] = 1;
  contact::detail::pair_poses pp;
  aabb sentinel;
  sentinel.expand(vec3::Constant(-7));
  contact::detail::place_blocks(
      pp, shapes, current, boxes,
      [&](std::size_t b, mat3& map, vec3& shift) { map = mat3::Identity(), shift = vec3(static_cast<real>(b), 0, 0); },
      only, [&](std::size_t) { return sentinel; });
  for (const std::size_t b : {std::size_t{0}, std::size_t{1}, std::size_t{3}, std::size_t{199}}) {
    INFO("block " << b);
    CHECK(boxes[b].lo.x() == (only[b] != 0 ? static_cast<real>(b) : -7.0));
    CHECK(current[b].vertex(0).x() == shapes[b].vertex(0).x() + (only[b] != 0 ? static_cast<real>(b) : 0.0));
    CHECK(pp.block_shift[b].x() == static_cast<real>(b));  // (every block's pose)
  }
  set_threads(before);
}


namespace {
/// Places block b at rotation `turn` about `centre` followed by translation `shift` (m) from its
/// reference position, its velocity the change of displacement over dt.
void place_block(node_set& gp, const geometry::block_mesh& mesh, index_t b, const mat3& turn, const vec3& centre,
                 const vec3& shift, real dt) {
  for (index_t g = mesh.block_gridpoint_offsets[static_cast<std::size_t>(b)];
       g < mesh.block_gridpoint_offsets[static_cast<std::size_t>(b) + 1]; ++g) {
    const vec3 x0 = mesh.gridpoints[static_cast<std::size_t>(g)];
    const vec3 u = turn * (x0 - centre) + centre + shift - x0;
    gp.velocity.row(g) = ((u - gp.displacement.row(g).transpose()) / dt).transpose();
    gp.displacement.row(g) = u.transpose();
  }
}
/// Two 0.5 m cubes pressed `overlap` (m) together face to face (blocks 1 and 2), 0.1 m above a
/// fixed base (block 0).
geometry::tessellation pressed_cube_pair(real overlap) {
  return geometry::separate_blocks(std::vector<convex_polyhedron>{
      convex_polyhedron::box({-2, -1, -0.5}, {2, 1, 0}), convex_polyhedron::box({-0.5, -0.25, 0.1}, {overlap, 0.25, 0.6}),
      convex_polyhedron::box({0, -0.25, 0.1}, {0.5, 0.25, 0.6})});
}
}  // namespace

TEST_CASE("incremental rebuild: a pair whose blocks move together keeps its sub-contacts without a pass and a pair that slides is detected again",
          "[detected][incremental]") {
  // Two 0.5 m cubes pressed 0.2 mm together face to face (blocks 1 and 2), 0.1 m above a fixed
  // base (block 0), tolerance 1 mm. The two move as one rigid body, 0.45 tolerance a step (past
  // the 0.39 trigger, so both are detected again at every step), turning about their common face
  // too: their pair drifted nothing relative to its detection, so it keeps its corners (labels,
  // areas to the bit, normal stresses to round-off) and no narrow phase runs. Then block 2 also
  // slides 0.25 tolerance along the face: drift 0.25 > 0.22 tolerance, the pair goes through the pass.
  const real tol = 1e-3, overlap = 2e-4, dt = 1e-4;
  const geometry::tessellation tess = pressed_cube_pair(overlap);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  auto [c, gp] = pressed_at_rest(tess, mesh, tol, 1000, dt);
  const auto before = corners_of(c, 1, 2);
  REQUIRE(before.size() >= 4);
  const index_t rebuilds = c.rebuild_count();
  const std::int64_t narrow = c.narrow_phase_pairs();
  const vec3 centre(0, 0, 0.35);
  vec3 shift = vec3::Zero(), slide = vec3::Zero();
  real angle = 0;
  // The farthest vertex is 0.56 m from the centre: a turn of 0.2 tolerance / 0.56 m a step.
  const auto move_pair = [&](bool slides) {
    shift += vec3(0.45 * tol, 0.1 * tol, -0.05 * tol);
    angle += 0.2 * tol / 0.56;
    if (slides) slide += vec3(0, 0.25 * tol, 0);
    const mat3 turn = Eigen::AngleAxis<real>(angle, vec3::UnitX()).toRotationMatrix();
    place_block(gp, mesh, 1, turn, centre, shift, dt);
    place_block(gp, mesh, 2, turn, centre, shift + turn * slide, dt);
    c.update(gp, dt);
  };
  for (int k = 0; k < 5; ++k) move_pair(false);
  const auto together = corners_of(c, 1, 2);
  CHECK(c.rebuild_count() - rebuilds == 5);
  CHECK(c.redetected_blocks() == 3 + 2 * 5);  // (the construction's three, then both moving blocks each time)
  CHECK(c.narrow_phase_pairs() == narrow);  // the base is 0.1 m away: no candidate, and the pair was kept
  CHECK(c.untouched_pairs_last_rebuild() == 1);
  REQUIRE(together.size() == before.size());
  for (std::size_t i = 0; i < before.size(); ++i) {
    CHECK(together[i].label == before[i].label);
    CHECK(together[i].area == before[i].area);
    CHECK(together[i].sigma_n == Approx(before[i].sigma_n).epsilon(1e-9));  // (round-off of the moved frames)
    CHECK(together[i].sigma_n < 0);
  }
  // The slide: the pair's drift passes 0.22 tolerance at the first step, so it is detected again.
  move_pair(true);
  CHECK(c.rebuild_count() - rebuilds == 6);
  CHECK(c.narrow_phase_pairs() == narrow + 1);
  CHECK(c.untouched_pairs_last_rebuild() == 0);
  CHECK(corners_of(c, 1, 2).size() >= 4);
}

TEST_CASE("incremental rebuild: a pair with one block detected again is kept when it drifted less than the margin "
          "left by the other block's own motion", "[detected][incremental]") {
  // The two pressed cubes of the test above turn as one about a vertical axis through block 1's
  // centre by 0.57e-3 rad: block 2's farthest vertex (0.79 m from the axis) moves 0.45 tolerance,
  // past the 0.39 trigger, and block 1's (0.354 m) 0.20, below the 0.22 margin, so only block 2 is
  // detected again. The pair drifted nothing (round-off), at most 0.22 - 0.20 tolerance: kept,
  // no narrow phase. The same turn with block 2 also sliding 0.05 tolerance along the face
  // drifts 0.05 > 0.02: the pair goes through the pass (0.22 alone would have kept it).
  const real tol = 1e-3, overlap = 2e-4, dt = 1e-4;
  const geometry::tessellation tess = pressed_cube_pair(overlap);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  for (const bool slides : {false, true}) {
    auto [c, gp] = pressed_at_rest(tess, mesh, tol, 1000, dt);
    const auto before = corners_of(c, 1, 2);
    REQUIRE(before.size() >= 4);
    const index_t rebuilds = c.rebuild_count();
    const std::int64_t narrow = c.narrow_phase_pairs(), redetected = c.redetected_blocks(), kept = c.pairs_kept_as_one();
    const vec3 axis_point(-0.25, 0, 0.35);
    const real angle = 0.45 * tol / std::hypot(0.75, 0.25);
    const mat3 turn = Eigen::AngleAxis<real>(angle, vec3::UnitZ()).toRotationMatrix();
    place_block(gp, mesh, 1, turn, axis_point, vec3::Zero(), dt);
    place_block(gp, mesh, 2, turn, axis_point, turn * vec3(0, slides ? 0.05 * tol : 0.0, 0), dt);
    c.update(gp, dt);
    INFO((slides ? "sliding 0.05 tolerance" : "turning as one"));
    CHECK(c.rebuild_count() - rebuilds == 1);
    CHECK(c.redetected_blocks() - redetected == 1);  // block 2 only
    CHECK(c.pairs_kept_as_one() - kept == (slides ? 0 : 1));
    CHECK(c.narrow_phase_pairs() - narrow == (slides ? 1 : 0));
    CHECK(c.untouched_pairs_last_rebuild() == (slides ? 0 : 1));
    const auto after = corners_of(c, 1, 2);
    REQUIRE(after.size() >= 4);
    if (!slides) {
      REQUIRE(after.size() == before.size());
      for (std::size_t i = 0; i < before.size(); ++i) {
        CHECK(after[i].label == before[i].label);
        CHECK(after[i].area == before[i].area);
      }
    }
  }
}

TEST_CASE("incremental rebuild: a pair sliding at its friction limit keeps its shear state through its rebuilds as "
          "a full pass does", "[detected][incremental]") {
  // A 4 x 2 x 0.5 m base (block 0, fixed); block 1, a 0.5 m cube pressed 0.2 mm into it, slid
  // along x (or spun about its vertical axis: its corners 0.354 m from it) by 0.1 tolerance a
  // step: its pair re-detected at every fourth step (0.4 > 0.39 tolerance), 10 times in 40
  // steps; block 2, a 0.5 m cube pressed in far from it, never moves (its pair untouched by the
  // incremental rebuilds). The same run with max_rebuild_interval 4 rebuilds by full passes at
  // the same steps. k_n = k_s = 1e9 Pa/m, phi 30 deg: sigma_n = -2e5 Pa, the slip limit
  // tan(30) x 2e5 = 1.155e5 Pa is reached in the second step (elastic shear 0.1155 mm).
  const real tol = 1e-3, overlap = 2e-4, dt = 1e-4, k = 1e9, mu = std::tan(std::numbers::pi / 6);
  const geometry::tessellation tess = geometry::separate_blocks(std::vector<convex_polyhedron>{
      convex_polyhedron::box({-2, -1, -0.5}, {2, 1, 0}), convex_polyhedron::box({-1.5, -0.25, -overlap}, {-1, 0.25, 0.5}),
      convex_polyhedron::box({1, -0.25, -overlap}, {1.5, 0.25, 0.5})});
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  const vec3 centre(-1.25, 0, 0.25);
  const real radius = 0.25 * std::sqrt(2.0), per_step = 0.1 * tol;
  struct outcome {
    std::vector<typename joint_contacts::state_type> states;  // pair (0, 1)'s, in key order
    std::vector<index_t> rebuild_steps;
    Eigen::MatrixXd cube_force;  // block 1's gridpoint forces
    real dissipated = 0;
    index_t untouched = 0;
  };
  const auto run = [&](bool spin, index_t interval) {
    joint_contacts::params p(law::dry_joint(k, k, law::friction_angle::from_degrees(30)), tol, interval);
    p.allow_initial_overlap = true;
    joint_contacts c(tess, mesh, p);
    node_set gp;
    gp.resize(mesh.gridpoint_count());
    outcome o;  // (the interval counts the updates since the last rebuild: step 4 is the 4th)
    for (int step = 1; step <= 40; ++step) {
      const index_t before = c.rebuild_count();
      const real angle = spin ? step * per_step / radius : 0;
      place_block(gp, mesh, 1, Eigen::AngleAxisd(angle, vec3::UnitZ()).toRotationMatrix(), centre,
                  vec3(spin ? 0 : step * per_step, 0, 0), dt);
      c.update(gp, dt);
      if (c.rebuild_count() != before) o.rebuild_steps.push_back(step);
    }
    for (index_t i = 0; i < c.size(); ++i)
      if (c.block_b(i) == 1) o.states.push_back(c.state(i));
    const index_t first = mesh.block_gridpoint_offsets[1], count = mesh.block_gridpoint_offsets[2] - first;
    o.cube_force = gp.force.middleRows(first, count);
    o.dissipated = c.energies().dissipated;
    o.untouched = c.untouched_pairs_last_rebuild();
    return o;
  };
  for (const bool spin : {false, true}) {
    INFO((spin ? "spun" : "slid"));
    const outcome incremental = run(spin, 1000), full = run(spin, 4);
    CHECK(incremental.rebuild_steps == std::vector<index_t>{4, 8, 12, 16, 20, 24, 28, 32, 36, 40});
    CHECK(full.rebuild_steps == incremental.rebuild_steps);
    CHECK(incremental.untouched == 1);  // block 2's pair
    CHECK(full.untouched == 0);
    // The closed form: every corner at its slip limit, the shear along the corner's path (-x, or
    // against the spin), and the energy dissipated tan(phi) N (s - tau / k_s) with N = 2e5 Pa x
    // 0.25 m^2 and s the path the springs saw, 3.9 mm (the construction's sub-contacts take their
    // first update without an increment: their gap holds the motion up to then), within 0.3 %
    // (the law's trapezoid over the first slipping step counts its elastic part at the mean
    // stress, 0.15 % of the total). A rebuild that started the shear again from zero would lose
    // 10 x 0.1155 mm of the 3.78 mm of slip (30 %).
    REQUIRE(incremental.states.size() == 4);
    for (const auto& st : incremental.states) {
      CHECK(st.sigma_n == Approx(-k * overlap).epsilon(1e-12));
      CHECK(st.tau.norm() == Approx(mu * k * overlap).epsilon(1e-9));
      CHECK(std::abs(st.tau.z()) < 1e-9 * st.tau.norm());
      if (!spin) CHECK(st.tau.x() == Approx(mu * k * overlap).epsilon(1e-9));  // on A: B slides +x
    }
    const real path = 39 * per_step;
    CHECK(incremental.dissipated == Approx(mu * k * overlap * 0.25 * (path - mu * overlap)).epsilon(3e-3));
    // The incremental path and the full pass give the sliding pair the same bits.
    REQUIRE(full.states.size() == incremental.states.size());
    for (std::size_t i = 0; i < full.states.size(); ++i) {
      CHECK(full.states[i].sigma_n == incremental.states[i].sigma_n);
      CHECK((full.states[i].tau.array() == incremental.states[i].tau.array()).all());
      CHECK(full.states[i].u_n == incremental.states[i].u_n);
      CHECK(full.states[i].dissipated_shear == incremental.states[i].dissipated_shear);
    }
    CHECK((full.cube_force.array() == incremental.cube_force.array()).all());
  }
}

TEST_CASE("detected gather: rigid blocks' slots per block give add_force's forces and a rank's own blocks theirs to the bit",
          "[detected][gather]") {
  // Rigid blocks gather per block (contact/detected/tasks.hpp): the base (block 0), block 1
  // overhanging its edge by half and block 2 on it, both 0.5 m cubes pressed 0.2 mm in, k_n =
  // 1e9 Pa/m. Block 2 slides 0.45 mm a step for 6 steps (past the trigger: rebuilds). After each
  // update (its gather per block), add_force on every gridpoint (its per-gridpoint lookup) gives
  // the same force rows to the bit, and only frame gridpoints get any. The base carries the two
  // cubes' k_n x overlap x area = 1e9 x 2e-4 x (0.125 + 0.25) = 7.5e4 N down. A set restricted
  // to one block (set_own_blocks, a split run's rank) gives that block's gridpoints the whole
  // set's forces to the bit and no other gridpoint any.
  const real tol = 1e-3, overlap = 2e-4, dt = 1e-4;
  const geometry::tessellation tess = pressed_cubes(overlap);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  const index_t n_g = mesh.gridpoint_count();
  const auto block_of = [&](index_t g) { return mesh.gridpoint_block[static_cast<std::size_t>(g)]; };
  const auto run = [&](index_t own) {
    joint_contacts c = pressed_contacts(tess, mesh, tol, 1000);
    if (own >= 0) c.set_own_blocks(std::vector<index_t>{own});
    node_set gp;
    gp.resize(n_g);
    std::vector<soa3> rows;
    for (int k = 0; k < 7; ++k) {
      if (k > 0) move_block(gp, mesh, 2, vec3(0.45 * tol, 0, 0), dt);
      gp.force.setZero();
      c.update(gp, dt);
      hold_all(gp);
      rows.push_back(gp.force);
      if (own >= 0) continue;
      gp.force.setZero();
      for (index_t g = 0; g < n_g; ++g) c.add_force(g, gp);
      CHECK((gp.force.array() == rows.back().array()).all());
    }
    return std::pair{rows, c.rebuild_count()};
  };
  const auto [whole, rebuilds] = run(-1);
  CHECK(rebuilds >= 6);
  const soa3& last = whole.back();
  index_t loaded = 0;
  real base_z = 0;
  for (index_t g = 0; g < n_g; ++g) {
    loaded += last.row(g).squaredNorm() > 0 ? 1 : 0;
    if (block_of(g) == 0) base_z += last(g, 2);
  }
  CHECK(loaded == 12);  // the three blocks' four frame gridpoints
  CHECK(base_z == Approx(-1e9 * overlap * (0.125 + 0.25)).epsilon(1e-9));
  for (const index_t own : {0, 1, 2}) {
    const auto [mine, rebuilds_own] = run(own);
    CHECK(rebuilds_own == rebuilds);
    bool same = true;
    for (std::size_t k = 0; k < mine.size(); ++k)
      for (index_t g = 0; g < n_g; ++g)
        for (int c = 0; c < 3; ++c)
          same = same && mine[k](g, c) == (block_of(g) == own ? whole[k](g, c) : 0.0);
    CHECK(same);
  }
}

}  // namespace tessera::test_incremental

namespace tessera::test_kept_axes {
namespace {
using geometry::convex_polyhedron;
namespace detection = contact::detection;

/// The cells of `tess`, each shrunk by the fraction `shrink` about its centroid c
/// (x -> (1 - shrink) x + shrink c; 1 - shrink is exact for the 0.01 and 0.03 below), gaps opened
/// between neighbours.
std::vector<convex_polyhedron> shrunk_cells(const geometry::tessellation& tess, real shrink) {
  std::vector<convex_polyhedron> cells;
  for (index_t c = 0; c < tess.cell_count(); ++c) {
    const convex_polyhedron cell = geometry::cell_polyhedron(tess, c);
    cells.push_back(cell.transformed((1 - shrink) * mat3::Identity(), shrink * cell.centroid()));
  }
  return cells;
}
}  // namespace

TEST_CASE("detection pass with kept axes: the full search's result to the bit over moving passes, most apart pairs shown apart by their last axis",
          "[detection]") {
  // 300 Voronoi cells shrunk 1 % about their centroids, then each turned and moved a little more
  // at every pass (up to 3 % of the mean size: pairs come into and out of the tolerance).
  const auto tess = geometry::random_voronoi({vec3::Zero(), vec3(0.15, 0.15, 0.3)}, 300, 11);
  const std::vector<convex_polyhedron> start = shrunk_cells(tess, 0.01);
  const real size = std::cbrt(0.15 * 0.15 * 0.3 / 300);
  std::vector<detection::polyhedron_edges> edges;
  for (const convex_polyhedron& p : start) edges.push_back(detection::edges_of(p));
  std::mt19937 rng(5);
  std::uniform_real_distribution<real> unit(-1, 1);
  std::vector<vec3> drift, spin;
  for (std::size_t b = 0; b < start.size(); ++b) {
    drift.emplace_back(unit(rng), unit(rng), unit(rng));
    spin.emplace_back(unit(rng), unit(rng), unit(rng));
  }
  detection::detection_options full;
  full.margin = full.tolerance = 0.05 * size;
  detection::detection_options kept = full;
  kept.reuse_axes = true;
  detection::detection_workspace w_kept;
  std::size_t skipped_before = 0, apart_total = 0, skipped_total = 0;
  for (int pass = 0; pass < 6; ++pass) {
    std::vector<convex_polyhedron> blocks;
    std::vector<aabb> boxes;
    std::vector<std::uint8_t> only(start.size(), 1);
    for (std::size_t b = 0; b < start.size(); ++b) {
      const real s = 0.006 * size * pass;
      const mat3 turn = Eigen::AngleAxis<real>(0.02 * pass, spin[b].normalized()).toRotationMatrix();
      const vec3 c = start[b].centroid();
      blocks.push_back(start[b].transformed(turn, c - turn * c + s * drift[b]));
      boxes.push_back(blocks.back().bounds());
      only[b] = pass % 2 == 1 && b % 3 == 0 ? 0 : 1;  // odd passes: an incremental pass without every third block
    }
    const std::span<const std::uint8_t> marks = pass % 2 == 1 ? std::span<const std::uint8_t>(only) : std::span<const std::uint8_t>();
    detection::detection_result a, b;
    detection::detection_workspace w_full;
    detection::detect(blocks, edges, boxes, full, a, w_full, {}, marks);
    detection::detect(blocks, edges, boxes, kept, b, w_kept, {}, marks);
    REQUIRE(a.pairs == b.pairs);
    REQUIRE(a.first_corner == b.first_corner);
    CHECK(a.label == b.label);
    CHECK(a.type == b.type);
    REQUIRE(a.point.size() == b.point.size());
    CHECK(std::memcmp(a.point.data(), b.point.data(), a.point.size() * sizeof(vec3)) == 0);
    CHECK(std::memcmp(a.gap.data(), b.gap.data(), a.gap.size() * sizeof(real)) == 0);
    CHECK(std::memcmp(a.area.data(), b.area.data(), a.area.size() * sizeof(real)) == 0);
    for (std::size_t k = 0; k < a.pairs.size(); ++k) {
      CHECK(std::memcmp(&a.planes[k].normal, &b.planes[k].normal, sizeof(vec3)) == 0);
      CHECK(a.planes[k].gap == b.planes[k].gap);
      CHECK(a.planes[k].offset == b.planes[k].offset);
    }
    // Every skipped candidate is apart by the full search, and the bound it was skipped on is
    // below the full search's gap.
    for (std::size_t i = 0; i < w_kept.candidates.size(); ++i) {
      if (w_full.planes[i].gap > full.tolerance) ++apart_total;
      if (w_kept.skipped[i] == 0) continue;
      CHECK(w_full.planes[i].gap > full.tolerance);
      CHECK(w_kept.planes[i].gap <= w_full.planes[i].gap);
    }
    if (pass > 0) skipped_total += w_kept.axis_skips - skipped_before;
    skipped_before = w_kept.axis_skips;
  }
  // The first pass has no axes to try; the later ones skip most of the apart candidates.
  INFO(skipped_total << " of " << apart_total << " apart candidates skipped");
  CHECK(static_cast<double>(skipped_total) > 0.6 * static_cast<double>(apart_total));
}

TEST_CASE("hinted plane: any face or edge pair's bound is below the common plane's gap, and a hint that is not a candidate gives none",
          "[detection]") {
  const auto tess = geometry::random_voronoi({vec3::Zero(), vec3(0.1, 0.1, 0.1)}, 40, 3);
  const std::vector<convex_polyhedron> cells = shrunk_cells(tess, 0.03);
  std::vector<detection::polyhedron_edges> edges;
  std::vector<std::vector<geometry::plane>> faces;
  for (const convex_polyhedron& cell : cells) {
    edges.push_back(detection::edges_of(cell));
    faces.emplace_back();
    detection::append_face_planes(cell, faces.back());
  }
  std::size_t bounds = 0, edge_bounds = 0, attained = 0;
  for (std::size_t a = 0; a < cells.size(); ++a)
    for (std::size_t b = a + 1; b < cells.size(); b += 3) {
      const auto plane = detection::common_plane(cells[a], edges[a], faces[a], cells[b], edges[b], faces[b]);
      const auto hinted = [&](detection::axis_hint h) {
        return detection::hinted_plane(cells[a], edges[a], faces[a], cells[b], edges[b], faces[b], h);
      };
      // The plane's own axis: its gap less the margin (2e-9 x size).
      const auto own = hinted(detection::axis_hint::of(plane));
      if (own.gap > -std::numeric_limits<real>::infinity()) {
        ++attained;
        CHECK(own.gap <= plane.gap);
        CHECK(own.gap >= plane.gap - 1e-8 * 0.1);
      }
      for (index_t f = 0; f < cells[a].face_count(); ++f) {
        CHECK(hinted({detection::plane_source::face_a, f, invalid_index}).gap <= plane.gap);
        ++bounds;
      }
      for (index_t f = 0; f < cells[b].face_count(); ++f) {
        CHECK(hinted({detection::plane_source::face_b, invalid_index, f}).gap <= plane.gap);
        ++bounds;
      }
      for (std::size_t i = 0; i < edges[a].list.size(); i += 2)
        for (std::size_t j = 0; j < edges[b].list.size(); j += 2) {
          const real g = hinted({detection::plane_source::edge_edge, static_cast<index_t>(i), static_cast<index_t>(j)}).gap;
          CHECK(g <= plane.gap);
          if (g > -std::numeric_limits<real>::infinity()) ++edge_bounds;
        }
      // Features out of range name no axis.
      CHECK(hinted({detection::plane_source::face_a, cells[a].face_count(), invalid_index}).gap ==
            -std::numeric_limits<real>::infinity());
      CHECK(hinted({detection::plane_source::edge_edge, 0, static_cast<index_t>(edges[b].list.size())}).gap ==
            -std::numeric_limits<real>::infinity());
    }
  INFO(bounds << " face bounds, " << edge_bounds << " edge-pair bounds, " << attained << " planes' own axes");
  CHECK(edge_bounds > 100);  // the edge pairs whose arcs cross are checked, not only refused
  CHECK(attained > 200);
}

// The warm start of a rebuild (detect.hpp): common_plane_above from the gap of the pair's last axis
// drops most candidate axes after a few vertices; its plane must be the full search's to the bit.
TEST_CASE("warm start: common_plane_above gives the full search's plane to the bit for any floor on rotated Voronoi pairs",
          "[detection]") {
  const auto tess = geometry::random_voronoi({vec3::Zero(), vec3(0.1, 0.1, 0.1)}, 40, 5);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<real> u(-1, 1);
  const std::vector<convex_polyhedron> cells = shrunk_cells(tess, 0.01);
  const auto bits = [](real x) { return std::bit_cast<std::uint64_t>(x); };
  const auto same = [&](const detection::contact_plane& p, const detection::contact_plane& q) {
    return bits(p.normal.x()) == bits(q.normal.x()) && bits(p.normal.y()) == bits(q.normal.y()) &&
           bits(p.normal.z()) == bits(q.normal.z()) && bits(p.offset) == bits(q.offset) && bits(p.gap) == bits(q.gap) &&
           p.source == q.source && p.feature_a == q.feature_a && p.feature_b == q.feature_b;
  };
  constexpr real lowest = -std::numeric_limits<real>::infinity();
  std::size_t pairs = 0, warm = 0, overlapping = 0, edge_planes = 0;
  for (std::size_t a = 0; a < cells.size(); ++a)
    for (std::size_t b = a + 1; b < cells.size(); ++b) {
      const auto ea = detection::edges_of(cells[a]);
      std::vector<geometry::plane> fa;
      detection::append_face_planes(cells[a], fa);
      // B as it was at the last rebuild, and now: turned by up to 0.05 rad about its centroid and
      // moved up to 1 mm, so neighbours overlap, touch or open.
      const auto eb0 = detection::edges_of(cells[b]);
      std::vector<geometry::plane> fb0;
      detection::append_face_planes(cells[b], fb0);
      const auto before = detection::common_plane(cells[a], ea, fa, cells[b], eb0, fb0);
      if (before.gap > 0.01) continue;  // not a neighbour
      const vec3 c = cells[b].centroid();
      const mat3 turn = Eigen::AngleAxisd(0.05 * u(rng), vec3(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
      const convex_polyhedron moved = cells[b].transformed(turn, c - turn * c + 1e-3 * vec3(u(rng), u(rng), u(rng)));
      const auto eb = detection::edges_of(moved);
      std::vector<geometry::plane> fb;
      detection::append_face_planes(moved, fb);
      const auto full = detection::detail::common_plane_every_axis(cells[a], ea, fa, moved, eb, fb, true);
      const real floor = detection::hinted_plane(cells[a], ea, fa, moved, eb, fb, detection::axis_hint::of(before)).gap;
      const real tie = detection::plane_tie_rel * std::max(cells[a].extent(), moved.extent());
      INFO("cells " << a << ", " << b << ": gap " << full.gap << ", warm floor " << floor);
      ++pairs;
      warm += floor > lowest && floor > full.gap - 1e-3 ? 1 : 0;
      overlapping += full.gap < 0 ? 1 : 0;
      edge_planes += full.source == detection::plane_source::edge_edge ? 1 : 0;
      // Cold (the default search), warm, and floors at, within a tie of, above and far below the
      // gap (those force the fallback or drop nothing).
      CHECK(same(detection::common_plane(cells[a], ea, fa, moved, eb, fb), full));
      for (const real f : {floor, lowest, std::numeric_limits<real>::quiet_NaN(), full.gap, full.gap - 0.5 * tie,
                           full.gap - 3 * tie, full.gap + 1e-3, full.gap - 1e-4, full.gap - 1.0})
        CHECK(same(detection::common_plane_above(cells[a], ea, fa, moved, eb, fb, f), full));
    }
  INFO(pairs << " neighbour pairs, " << warm << " warm floors within 1 mm of the gap, " << overlapping
             << " overlapping, " << edge_planes << " edge-pair planes");
  CHECK(pairs > 150);
  CHECK(warm > pairs / 2);  // the warm start is exercised on most pairs
  CHECK(overlapping > 20);
  CHECK(edge_planes > 5);
}

}  // namespace tessera::test_kept_axes
