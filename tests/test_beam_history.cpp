// The opening history behind rc_beam's post-peak crack rule (examples/rc_beam/beam_post_peak.hpp,
// issue #41 item 4): which snapshots the grid keeps, how it thins itself when full, and how
// finish() puts the fine snapshots and the end state in place of the grid's last ones when the run
// stopped within their reach of its peak (the fix of bf42e1e: a 60-block run that stopped two grid
// steps past its peak read its diagonal crack only from them).
//
// The model is two sub-contacts between four gridpoints: sub-contact 0 opens as d^2 with the
// deflection d (its second gridpoint moves along x), sub-contact 1 stays shut. The grid step is 1
// and the deflections are multiples of 1/8, so every comparison the class makes is exact in
// binary floating point and the expected snapshot lists can be written out.
#include <catch2/catch.hpp>

#include <cstddef>
#include <limits>
#include <vector>

#include "rc_beam/beam_post_peak.hpp"

namespace {

using tessera::index_t;
using tessera::real;
using history = tessera::scenes::beam_opening_history;

/// The two sub-contacts: 0 between gridpoints 0 and 1, 1 between 2 and 3.
struct two_subcontacts {
  [[nodiscard]] index_t size() const { return 2; }
  [[nodiscard]] index_t node_a(index_t i) const { return 2 * i; }
  [[nodiscard]] index_t node_b(index_t i) const { return 2 * i + 1; }
};

struct scene {
  two_subcontacts contacts;
  tessera::node_set gp;
  scene() {
    gp.resize(4);
    gp.reference.setZero();
    gp.displacement.setZero();
    gp.reference(2, 1) = gp.reference(3, 1) = 1;  // sub-contact 1 sits elsewhere, shut
  }
  /// Moves to deflection d (sub-contact 0 open by d^2) and records it with the load 100 d (N).
  void record(history& h, real d) {
    gp.displacement(1, 0) = d * d;
    h.record(contacts, gp, d, 100 * d);
  }
};

/// Records d = 0, 1/8, ..., last.
void record_up_to(scene& s, history& h, real last) {
  for (int k = 0; k / 8.0 <= last; ++k) s.record(h, k / 8.0);
}

/// Every snapshot's deflection, in order.
std::vector<real> deflections(const history& h) {
  std::vector<real> d;
  for (std::size_t j = 0; j < h.size(); ++j) d.push_back(h.deflection(j));
  return d;
}

}  // namespace

TEST_CASE("beam_opening_history keeps one snapshot per grid step, with its openings and load", "[beam_history]") {
  scene s;
  history h(1.0);
  record_up_to(s, h, 10);
  REQUIRE(h.size() == 11);  // d = 0, 1, ..., 10; the eighths between are fine snapshots only
  for (std::size_t j = 0; j < h.size(); ++j) {
    const real d = static_cast<real>(j);
    CHECK(h.deflection(j) == d);
    CHECK(h.load(j) == 100 * d);
    CHECK(h.opening(j, 0) == static_cast<float>(d * d));
    CHECK(h.opening(j, 1) == 0);
  }
}

TEST_CASE("beam_opening_history drops every other snapshot and doubles its step when full", "[beam_history]") {
  scene s;
  history h(1.0);
  for (std::size_t k = 0; k + 1 < history::max_snapshots; ++k) s.record(h, static_cast<real>(k));
  REQUIRE(h.size() == history::max_snapshots - 1);
  s.record(h, static_cast<real>(history::max_snapshots - 1));  // the grid is full: thinned to half
  REQUIRE(h.size() == history::max_snapshots / 2);
  for (std::size_t j = 0; j < h.size(); ++j) CHECK(h.deflection(j) == 2.0 * static_cast<real>(j));
  // The step is now 2: the next snapshot is due at the last kept one (254) + 2.
  s.record(h, 255);
  CHECK(h.size() == history::max_snapshots / 2);
  s.record(h, 256);
  REQUIRE(h.size() == history::max_snapshots / 2 + 1);
  CHECK(h.deflection(h.size() - 1) == 256);
  CHECK(h.opening(h.size() - 1, 0) == static_cast<float>(256.0 * 256.0));
}

TEST_CASE("beam_opening_history::finish puts the fine snapshots and the end state after a peak within their reach",
          "[beam_history]") {
  scene s;
  history h(1.0);
  record_up_to(s, h, 10);
  // The 30 fine snapshots span d = 10 - 29/8 = 6.375 ... 10; the grid's 7 ... 10 give way to them.
  const real first_fine = 10 - static_cast<real>(history::recent_snapshots - 1) / 8;
  REQUIRE(first_fine == 6.375);

  SECTION("the run ends past its last sample") {
    s.gp.displacement(1, 0) = 0.5;  // the end state's own opening, not d^2
    h.finish(s.contacts, s.gp, 10.0625, 42.0, 9.0);
    REQUIRE(h.size() == 7 + history::recent_snapshots + 1);  // grid 0..6, 30 fine, the end
    const std::vector<real> d = deflections(h);
    for (std::size_t j = 0; j < 7; ++j) CHECK(d[j] == static_cast<real>(j));
    for (std::size_t j = 0; j < history::recent_snapshots; ++j) {
      const real fine = first_fine + static_cast<real>(j) / 8;
      CHECK(d[7 + j] == fine);
      CHECK(h.opening(7 + j, 0) == static_cast<float>(fine * fine));
      CHECK(h.load(7 + j) == 100 * fine);
    }
    CHECK(d.back() == 10.0625);
    CHECK(h.load(h.size() - 1) == 42.0);
    CHECK(h.opening(h.size() - 1, 0) == 0.5f);
  }
  SECTION("the mid-span sprang back: fine snapshots at or past the end deflection give way to the end state") {
    s.gp.displacement(1, 0) = 0.25;
    h.finish(s.contacts, s.gp, 9.5, 40.0, 9.0);
    // Of the fine snapshots 9.5, 9.625, 9.75, 9.875 and 10 go; the end state follows 9.375.
    REQUIRE(h.size() == 7 + history::recent_snapshots - 5 + 1);
    const std::vector<real> d = deflections(h);
    for (std::size_t j = 1; j < d.size(); ++j) CHECK(d[j] > d[j - 1]);
    CHECK(d[d.size() - 2] == 9.375);
    CHECK(d.back() == 9.5);
    CHECK(h.opening(h.size() - 1, 0) == 0.25f);
  }
  SECTION("a peak before the fine snapshots leaves the grid as it was") {
    h.finish(s.contacts, s.gp, 10.0625, 42.0, first_fine - 0.125);
    REQUIRE(h.size() == 11);
    CHECK(h.deflection(10) == 10);
    CHECK(h.opening(10, 0) == 100.0f);
  }
}

TEST_CASE("beam_opening_history refuses a grid step that is not > 0", "[beam_history]") {
  CHECK_THROWS_AS(history(0.0), tessera::invalid_input);
  CHECK_THROWS_AS(history(-1e-5), tessera::invalid_input);
  CHECK_THROWS_AS(history(std::numeric_limits<real>::quiet_NaN()), tessera::invalid_input);
  CHECK_THROWS_WITH(history(-1e-5), Catch::Contains("-1e-05"));
}
