// The crack reading behind rc_beam's failure mode (examples/rc_beam/beam_cracks.hpp,
// beam_opening_maxima): where a crack is along the span and how steep it runs. The 500-block shear
// beam's diagonal band (docs/studies/one_concrete.md, "Less residual friction") left the soffit
// beside a flexural crack and ran to the loading plate at about 60 degrees from the vertical; the
// old reading fitted its line to the sub-contacts within 1.5 block sizes of its foot and called it
// 17 degrees, a flexural crack. These scenes draw such cracks with point sub-contacts whose opening
// is given, and check the angle against the one drawn.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "rc_beam/beam_cracks.hpp"

namespace {

using tessera::index_t;
using tessera::real;
using tessera::vec3;

/// Sub-contacts as points with an area of 1 mm^2 and an opening (m); gridpoints unused.
struct point_contacts {
  std::vector<vec3> p;
  std::vector<real> w;
  [[nodiscard]] index_t size() const { return static_cast<index_t>(p.size()); }
  [[nodiscard]] vec3 position(index_t i, const tessera::node_set&) const { return p[static_cast<std::size_t>(i)]; }
  [[nodiscard]] real area(index_t) const { return 1e-6; }
  /// A straight crack from (x0, y0) to (x1, y1) (m), a point every 2 mm, each opened by w (m).
  void line(real x0, real y0, real x1, real y1, real width) {
    const real length = std::hypot(x1 - x0, y1 - y0);
    const auto n = static_cast<int>(length / 0.002);
    for (int k = 0; k <= n; ++k) {
      const real t = static_cast<real>(k) / n;
      p.emplace_back(x0 + t * (x1 - x0), y0 + t * (y1 - y0), 0.05);
      w.push_back(width);
    }
  }
  /// Starts with shut sub-contacts (opening 0) on a 10 mm grid over the beam's half, 725 x 150 mm.
  point_contacts() {
    for (real x = 0.005; x < 0.725; x += 0.01)
      for (real y = 0.005; y < 0.15; y += 0.01) p.emplace_back(x, y, 0.05), w.push_back(0);
  }
  /// The cracks of at least 0.1 mm in the lower third, for blocks of size `cell` (m).
  [[nodiscard]] std::vector<tessera::scenes::beam_crack> cracks(real cell) const {
    const tessera::node_set gp;
    return tessera::scenes::beam_opening_maxima(*this, gp, 0.15, cell, 1e-4, 0.05,
                                                [&](index_t i) { return w[static_cast<std::size_t>(i)]; });
  }
  /// The crack nearest x (m).
  [[nodiscard]] tessera::scenes::beam_crack crack_near(real cell, real x) const {
    const auto cs = cracks(cell);
    REQUIRE(!cs.empty());
    tessera::scenes::beam_crack best = cs.front();
    for (const auto& c : cs)
      if (std::abs(c.x - x) < std::abs(best.x - x)) best = c;
    return best;
  }
};

constexpr real cell = 0.028;  // the 500-block beam's mean block size (m)

real degrees(real dx, real dy) { return std::atan(dx / dy) * 180 / std::numbers::pi; }

}  // namespace

TEST_CASE("beam_opening_maxima reads a vertical crack as vertical, over the depth it runs", "[beam_cracks]") {
  point_contacts s;
  s.line(0.60, 0.0, 0.60, 0.12, 1e-3);
  const auto c = s.crack_near(cell, 0.60);
  CHECK(c.x == Approx(0.60).margin(0.005));
  CHECK(c.width == 1e-3);
  CHECK(c.angle_deg < 2);
  CHECK(c.local_angle_deg < 2);
  CHECK(c.vertical());
  CHECK(c.y_min == 0);
  CHECK(c.y_max == Approx(0.12).margin(cell / 2));  // to the layer it ends in
}

TEST_CASE("beam_opening_maxima follows a diagonal crack from its foot to its top", "[beam_cracks]") {
  // A flexure-shear crack as the 500-block beam's band: vertical and 1 mm open from the soffit at
  // x = 300 mm to 40 mm up, then 0.6 mm open to the loading plate's edge at 500 mm, 130 mm up (an
  // inclined branch at 65.8 degrees from the vertical).
  point_contacts s;
  s.line(0.30, 0.0, 0.30, 0.04, 1e-3);
  s.line(0.30, 0.04, 0.50, 0.13, 0.6e-3);
  const auto c = s.crack_near(cell, 0.30);
  CHECK(c.x == Approx(0.30).margin(0.005));
  CHECK(c.width == 1e-3);
  CHECK(c.y_max >= 0.12);  // it reaches the top, along the inclined branch
  CHECK(c.angle_deg > 45);  // inclined: diagonal tension in the shear span
  CHECK(!c.vertical());
  CHECK(c.local_angle_deg < 35);  // about its foot it reads vertical (the flexural count's reading)
  CHECK(c.locally_vertical());
  SECTION("a straight band: the angle drawn") {
    point_contacts band;
    band.line(0.26, 0.0, 0.50, 0.13, 0.6e-3);
    CHECK(band.crack_near(cell, 0.26).angle_deg == Approx(degrees(0.24, 0.13)).margin(3));
  }
  SECTION("a 45-degree crack") {
    point_contacts band;
    band.line(0.20, 0.0, 0.34, 0.14, 0.5e-3);
    CHECK(band.crack_near(cell, 0.20).angle_deg == Approx(45).margin(3));
  }
  SECTION("a band apart from the flexural crack at its foot is a crack of its own") {
    point_contacts two;
    two.line(0.26, 0.0, 0.50, 0.13, 0.6e-3);
    two.line(0.20, 0.0, 0.20, 0.06, 1e-3);  // 60 mm beside its foot
    CHECK(two.crack_near(cell, 0.20).angle_deg < 2);
    CHECK(two.crack_near(cell, 0.26).angle_deg == Approx(degrees(0.24, 0.13)).margin(3));
  }
}

TEST_CASE("beam_opening_maxima keeps flexural cracks 90 mm apart, each vertical", "[beam_cracks]") {
  point_contacts s;
  for (const real x : {0.45, 0.54, 0.63, 0.72}) s.line(x, 0.0, x, 0.11, 0.8e-3);
  const auto cs = s.cracks(cell);
  REQUIRE(cs.size() == 4);
  for (const auto& c : cs) {
    CHECK(c.angle_deg < 2);
    CHECK(c.y_max == Approx(0.11).margin(cell / 2));
  }
}

TEST_CASE("beam_opening_maxima stops a crack where it closes below 30 % of its width", "[beam_cracks]") {
  // A vertical crack 1 mm open to 50 mm, then 0.2 mm (20 %) above: it ends at 50 mm.
  point_contacts s;
  s.line(0.40, 0.0, 0.40, 0.05, 1e-3);
  s.line(0.40, 0.052, 0.40, 0.14, 0.2e-3);
  const auto c = s.crack_near(cell, 0.40);
  CHECK(c.y_max == Approx(0.05).margin(cell / 2));
  SECTION("its members: along its path, at least 30 % of its width") {
    CHECK(tessera::scenes::beam_crack_member(c, cell, vec3(0.41, 0.02, 0.05), 0.5e-3));
    CHECK(!tessera::scenes::beam_crack_member(c, cell, vec3(0.41, 0.02, 0.05), 0.2e-3));  // too narrow
    CHECK(!tessera::scenes::beam_crack_member(c, cell, vec3(0.45, 0.02, 0.05), 1e-3));    // 50 mm off its path
    CHECK(!tessera::scenes::beam_crack_member(c, cell, vec3(0.40, 0.12, 0.05), 1e-3));    // above its end
  }
}
