// Tests for the geometry area: convex polyhedra, clipping, mass properties, Voronoi/Laguerre
// tessellations and the Neper reader (see tests/CMakeLists.txt).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <vector>

#include <tessera/geometry/convex_polyhedron.hpp>
#include <tessera/geometry/tessellation_queries.hpp>
#include <tessera/geometry/voronoi.hpp>

using namespace tessera::geometry;
using tessera::aabb;
using tessera::mat3;
using tessera::real;
using tessera::vec3;
using Catch::Matchers::Contains;

namespace {

// Every invariant of a conforming tessellation, with the tolerances of the issue.
void require_valid(const tessellation& t) {
  const tessellation_report r = check(t);
  CHECK(r.volume_error_rel < 1e-12);
  CHECK(r.unmatched_faces == 0);
  CHECK(r.open_cells == 0);
  CHECK(r.nonconvex_cells == 0);
  CHECK(r.min_face_area > 0);
  for (tessera::index c = 0; c < t.cell_count(); ++c) CHECK(cell_volume(t, c) > 0);
  // twins: opposite normals, same area; every interior face listed exactly once in shared_faces
  tessera::index interior = 0;
  for (tessera::index f = 0; f < t.face_count(); ++f) {
    if (t.is_boundary_face(f)) continue;
    ++interior;
    const tessera::index g = t.face_twin[static_cast<std::size_t>(f)];
    REQUIRE(g >= 0);
    CHECK((face_normal(t, f) + face_normal(t, g)).norm() < 1e-9);
    CHECK(face_area(t, f) == Approx(face_area(t, g)).epsilon(1e-12));
  }
  CHECK(static_cast<tessera::index>(t.shared_faces.size()) * 2 == interior);
  std::set<tessera::index> listed;
  for (const auto& s : t.shared_faces) {
    CHECK(s.cell_a < s.cell_b);
    CHECK(t.face_cell[static_cast<std::size_t>(s.face_a)] == s.cell_a);
    CHECK(t.face_cell[static_cast<std::size_t>(s.face_b)] == s.cell_b);
    CHECK(listed.insert(s.face_a).second);
    CHECK(listed.insert(s.face_b).second);
  }
  // boundary faces lie on the side their tag names
  for (tessera::index f = 0; f < t.face_count(); ++f) {
    const int side = boundary_side(t.face_neighbor[static_cast<std::size_t>(f)]);
    if (side < 0) continue;
    const int axis = side / 2;
    const real x = (side % 2) ? t.domain.hi[axis] : t.domain.lo[axis];
    for (tessera::index v : t.face(f)) CHECK(t.vertices[static_cast<std::size_t>(v)][axis] == x);
  }
}

}  // namespace

TEST_CASE("box: volume, centroid and inertia against closed forms", "[geometry][polyhedron]") {
  const auto b = convex_polyhedron::box({0, 0, 0}, {1, 2, 3});
  CHECK(b.volume() == Approx(6.0).epsilon(1e-14));
  CHECK((b.centroid() - vec3(0.5, 1, 1.5)).norm() < 1e-14);
  // I_xx = m (b^2 + c^2) / 12 with m = rho V
  const real rho = 2400, m = rho * 6;
  const mat3 inertia = b.inertia(rho);
  CHECK(inertia(0, 0) == Approx(m * (4 + 9) / 12).epsilon(1e-13));
  CHECK(inertia(1, 1) == Approx(m * (1 + 9) / 12).epsilon(1e-13));
  CHECK(inertia(2, 2) == Approx(m * (1 + 4) / 12).epsilon(1e-13));
  CHECK(std::abs(inertia(0, 1)) < 1e-9 * m);
  CHECK(b.euler_characteristic() == 2);
  CHECK(b.face_count() == 6);
  for (int s = 0; s < 6; ++s) {
    const vec3 n = b.face_normal(s);
    vec3 expected = vec3::Zero();
    expected[s / 2] = (s % 2) ? 1 : -1;
    CHECK((n - expected).norm() < 1e-15);
    CHECK(b.face_tag(s) == boundary_tag(s));
  }
  CHECK(b.contains({0.5, 1, 1.5}));
  CHECK_FALSE(b.contains({1.5, 1, 1.5}));
}

TEST_CASE("clip: tetrahedron and triangular prism mass properties", "[geometry][polyhedron]") {
  SECTION("corner tetrahedron x + y + z <= 1 of the unit cube") {
    auto p = convex_polyhedron::box({0, 0, 0}, {1, 1, 1});
    CHECK(p.clip({vec3(1, 1, 1).normalized(), 1 / std::sqrt(3.0)}, 7));
    CHECK(p.vertex_count() == 4);  // the cut passes through three cube vertices: no new vertex
    CHECK(p.face_count() == 4);
    CHECK(p.euler_characteristic() == 2);
    CHECK(p.volume() == Approx(1.0 / 6).epsilon(1e-14));
    CHECK((p.centroid() - vec3::Constant(0.25)).norm() < 1e-15);
    // unit right tetrahedron: int x^2 dV = 1/60, int x y dV = 1/120 about the origin
    const real rho = 1, V = 1.0 / 6;
    const mat3 I = p.inertia(rho);
    const real sxx = 1.0 / 60 - V * 0.0625, sxy = 1.0 / 120 - V * 0.0625;
    CHECK(I(0, 0) == Approx(2 * sxx).epsilon(1e-13));
    CHECK(I(0, 1) == Approx(-sxy).epsilon(1e-13));
    CHECK(p.face_tag(p.face_count() - 1) == 7);
    CHECK((p.face_normal(p.face_count() - 1) - vec3(1, 1, 1).normalized()).norm() < 1e-15);
  }
  SECTION("triangular prism: box [0,2]x[0,1]x[0,3] cut by x + 2y <= 2") {
    auto p = convex_polyhedron::box({0, 0, 0}, {2, 1, 3});
    CHECK(p.clip({vec3(1, 2, 0).normalized(), 2 / std::sqrt(5.0)}, 3));
    CHECK(p.vertex_count() == 6);
    CHECK(p.face_count() == 5);
    CHECK(p.euler_characteristic() == 2);
    // triangle legs a = 2 (x), b = 1 (y), length L = 3 (z): V = a b L / 2, centroid (a/3, b/3, L/2)
    CHECK(p.volume() == Approx(3.0).epsilon(1e-14));
    CHECK((p.centroid() - vec3(2.0 / 3, 1.0 / 3, 1.5)).norm() < 1e-14);
    // I_zz = rho L * (polar moment of the triangle about its centroid) = rho L a b (a^2 + b^2) / 36
    const real rho = 7850;
    const mat3 I = p.inertia(rho);
    CHECK(I(2, 2) == Approx(rho * 3 * 2 * 1 * (4 + 1) / 36).epsilon(1e-13));
    // I_xy = -rho L * (product of inertia of the triangle) = -rho L * (-(a b)^2 / 72)
    CHECK(I(0, 1) == Approx(rho * 3 * 4.0 / 72).epsilon(1e-13));
    // I_xx = rho [ L * I_yy_triangle + A L^3 / 12 ],  I_yy_triangle = a b^3 / 36
    CHECK(I(0, 0) == Approx(rho * (3 * 2 * 1.0 / 36 + 1.0 * 27 / 12)).epsilon(1e-13));
  }
}

TEST_CASE("clip: edge cases keep the polyhedron closed and free of duplicates", "[geometry][polyhedron]") {
  auto no_duplicates = [](const convex_polyhedron& p) {
    for (tessera::index a = 0; a < p.vertex_count(); ++a)
      for (tessera::index b = a + 1; b < p.vertex_count(); ++b)
        if ((p.vertex(a) - p.vertex(b)).norm() < 1e-12) return false;
    return true;
  };
  const auto cube = convex_polyhedron::box({0, 0, 0}, {1, 1, 1});
  SECTION("cut removing nothing (plane on a face, plane outside)") {
    auto p = cube;
    CHECK_FALSE(p.clip({vec3::UnitX(), 1.0}, 9));
    CHECK_FALSE(p.clip({vec3::UnitX(), 1.5}, 9));
    CHECK_FALSE(p.clip({vec3::UnitX(), 1.0 + 1e-15}, 9));
    CHECK(p.volume() == 1.0);
    CHECK(p.face_count() == 6);
  }
  SECTION("cut removing everything") {
    auto p = cube;
    CHECK(p.clip({-vec3::UnitX(), -1.0}, 9));  // keeps x >= 1: the face only
    CHECK(p.empty());
    CHECK(p.volume() == 0);
    CHECK_FALSE(p.clip({vec3::UnitX(), 0.5}, 9));
  }
  SECTION("cut through an edge: removes a wedge, no new vertex") {
    auto p = cube;
    CHECK(p.clip({vec3(1, 1, 0).normalized(), 1 / std::sqrt(2.0)}, 9));  // x + y <= 1, through edges
    CHECK(p.vertex_count() == 6);
    CHECK(p.face_count() == 5);
    CHECK(p.euler_characteristic() == 2);
    CHECK(p.volume() == Approx(0.5).epsilon(1e-14));
    CHECK(no_duplicates(p));
  }
  SECTION("cut through one vertex only") {
    auto p = cube;
    // x + y + z <= 2.5 cuts off the corner (1,1,1): a tetrahedron with legs 0.5, volume 0.5^3 / 6
    CHECK(p.clip({vec3(1, 1, 1).normalized(), 2.5 / std::sqrt(3.0)}, 9));
    CHECK(p.vertex_count() == 10);
    CHECK(p.volume() == Approx(1 - 0.125 / 6).epsilon(1e-14));
    auto q = cube;  // plane touching vertex (1,1,1) from outside: nothing removed
    CHECK_FALSE(q.clip({vec3(1, 1, 1).normalized(), 3 / std::sqrt(3.0)}, 9));
    // x + y - z <= 1 passes through the vertices (1,0,0), (0,1,0), (1,1,1) and cuts off the
    // tetrahedron (1,0,0), (0,1,0), (1,1,1), (1,1,0) of volume 1/6
    auto r = cube;
    CHECK(r.clip({vec3(1, 1, -1).normalized(), 1 / std::sqrt(3.0)}, 9));
    CHECK(r.euler_characteristic() == 2);
    CHECK(r.volume() == Approx(1 - 1.0 / 6).epsilon(1e-14));
    CHECK(no_duplicates(r));
  }
  SECTION("near-coplanar cuts at the tolerance scale") {
    for (real eps : {1e-16, 1e-14, 1e-13, 1e-11, 1e-9}) {
      auto p = cube;
      // plane tilted by eps from the face x = 1: at most a sliver of thickness eps is cut off
      p.clip({vec3(1, eps, 0).normalized(), 1 / std::sqrt(1 + eps * eps)}, 9);
      CHECK(p.euler_characteristic() == 2);
      CHECK(no_duplicates(p));
      CHECK(p.volume() == Approx(1.0).margin(eps));
      CHECK(p.volume() <= 1.0);
    }
  }
  SECTION("many random cuts keep a closed convex polyhedron") {
    std::mt19937_64 rng(11);
    auto p = cube;
    const vec3 center(0.5, 0.5, 0.5);
    for (int k = 0; k < 200; ++k) {
      vec3 n(detail::uniform01(rng) - 0.5, detail::uniform01(rng) - 0.5, detail::uniform01(rng) - 0.5);
      n.normalize();
      const real before = p.volume();
      p.clip(plane::through(n, center + (0.2 + 0.3 * detail::uniform01(rng)) * n), k);
      CHECK(p.euler_characteristic() == 2);
      CHECK(p.volume() <= before + 1e-15);
      CHECK(p.volume() > 0);
      for (tessera::index f = 0; f < p.face_count(); ++f)
        for (tessera::index v = 0; v < p.vertex_count(); ++v) REQUIRE(p.face_plane(f).signed_distance(p.vertex(v)) < 1e-12);
    }
    CHECK(no_duplicates(p));
    CHECK(p.contains(center));
  }
}

TEST_CASE("tessellations of 1, 2, 100 and 2000 cells are conforming", "[geometry][voronoi]") {
  const aabb box{vec3(0, 0, 0), vec3(1, 1, 1)};
  SECTION("one cell is the box") {
    const std::vector<vec3> seeds{vec3(0.3, 0.6, 0.2)};
    const tessellation t = voronoi(box, seeds);
    CHECK(t.cell_count() == 1);
    CHECK(t.face_count() == 6);
    CHECK(t.vertex_count() == 8);
    require_valid(t);
  }
  SECTION("two cells split at the bisector") {
    const std::vector<vec3> seeds{vec3(0.25, 0.5, 0.5), vec3(0.75, 0.5, 0.5)};
    const tessellation t = voronoi(box, seeds);
    CHECK(t.cell_count() == 2);
    CHECK(t.vertex_count() == 12);
    CHECK(t.shared_faces.size() == 1);
    CHECK(cell_volume(t, 0) == Approx(0.5).epsilon(1e-14));
    CHECK((cell_centroid(t, 1) - vec3(0.75, 0.5, 0.5)).norm() < 1e-14);
    require_valid(t);
  }
  for (tessera::index n : {100, 2000}) {
    DYNAMIC_SECTION(n << " random cells") {
      const tessellation t = random_voronoi(box, n, 42);
      CHECK(t.cell_count() == n);
      require_valid(t);
      // Poisson-Voronoi: about 15.5 faces per interior cell on average
      const real faces_per_cell = static_cast<real>(t.face_count()) / n;
      CHECK(faces_per_cell > 10);
      CHECK(faces_per_cell < 17);
    }
  }
}
