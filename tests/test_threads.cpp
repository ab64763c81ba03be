// The thread governor (core/thread_governor.hpp): its decision from synthetic step times (numbers
// in, thread count out), its refusals, and a solver run whose thread count the governor changes
// every few steps giving the bits of a one-thread run.
#include <catch2/catch.hpp>

#include <cstring>
#include <functional>
#include <set>
#include <tuple>
#include <utility>

#include "tessera/core/thread_governor.hpp"
#include "tessera/geometry/voronoi.hpp"
#include "tessera/geometry/zoning.hpp"
#include "tessera/presets.hpp"
#include "tessera/solver.hpp"

using namespace tessera;

namespace {
/// Settings that make the arithmetic of the cases below easy to follow: probe after 1 s of run,
/// windows of 0.2 s (quarters of 0.05 s), keep a count that is 10 % faster, back off up to 4 s.
thread_governor_params test_params() {
  thread_governor_params p;
  p.probe_interval_s = 1.0;
  p.window_s = 0.2;
  p.margin = 0.1;
  p.max_backoff = 4;
  p.settle_steps = 2;
  return p;
}

/// What a simulated run did: its run time (s) on each thread count, indexed by the count.
struct simulated_run {
  double seconds_on[3] = {0, 0, 0};
  int final_threads = 0;
};

/// Feeds `g` the step time step_seconds(threads, run time) until `run_seconds` of run have
/// passed, each step on the count the governor chose after the last one.
simulated_run simulate(thread_governor& g, double run_seconds, const std::function<double(int, double)>& step_seconds) {
  simulated_run r;
  double t = 0;
  int threads = g.threads();
  while (t < run_seconds) {
    const double dt = step_seconds(threads, t);
    r.seconds_on[threads] += dt;
    t += dt;
    threads = g.record_step(dt);
  }
  r.final_threads = threads;
  return r;
}
}  // namespace

TEST_CASE("thread governor: a lost core sends a two-thread run to one thread", "[threads][governor]") {
  // The cliff: 2 threads take 10 ms a step (the second thread's core is taken), 1 thread 1 ms.
  thread_governor g(2, 2, test_params());
  const simulated_run r = simulate(g, 60.0, [](int threads, double) { return threads == 2 ? 10e-3 : 1e-3; });
  CHECK(r.final_threads == 1);
  CHECK(g.switches() == 1);  // 2 -> 1 once; every later probe of 2 loses
  // On 2 threads: the first second and its baseline window (1.2 s), then each lost probe of 2:
  // 2 settling steps and one quarter window, already 10x slower, so the probe ends there (0.07 s),
  // the probes 2, 4, 4, ... s apart (backoff). 58.8 s on 1 thread hold about 15 probes:
  // 1.2 + 15 x 0.07 = 2.25 s (with whole windows, 1.2 + 15 x 0.22 = 4.5 s).
  CHECK(r.seconds_on[2] > 1.2);
  CHECK(r.seconds_on[2] < 2.6);
  CHECK(g.probes() >= 13);
  CHECK(g.probes() <= 18);
}

TEST_CASE("thread governor: a lost probe of a count whose steps each fill a quarter window costs one step",
          "[threads][governor]") {
  // The cliff of the quick RC tie beside a one-core load: 60 ms a step on 2 threads, 0.5 ms on 1.
  // Each probe of 2 ends at its first step (>= 0.05 s, > 2 x 0.5 ms), settling steps included:
  // about 15 probes in 60 s cost 15 x 0.06 = 0.9 s (3 steps each would be 2.7 s).
  thread_governor g(1, 2, test_params());
  const simulated_run r = simulate(g, 60.0, [](int threads, double) { return threads == 2 ? 60e-3 : 0.5e-3; });
  CHECK(r.final_threads == 1);
  CHECK(g.switches() == 0);
  CHECK(g.probes() >= 13);
  CHECK(r.seconds_on[2] < 0.06 * g.probes() + 1e-9);
  CHECK(r.seconds_on[2] > 0.06 * (g.probes() - 1) - 1e-9);  // the last probe may end the run before its step
}

TEST_CASE("thread governor: an idle machine takes the faster count and keeps it", "[threads][governor]") {
  // Idle: 2 threads 0.6 ms a step, 1 thread 1 ms; starting on 1, the first probe (after 1 s) wins.
  thread_governor g(1, 2, test_params());
  const simulated_run r = simulate(g, 30.0, [](int threads, double) { return threads == 2 ? 0.6e-3 : 1e-3; });
  CHECK(r.final_threads == 2);
  CHECK(g.switches() == 1);
  // On 1 thread: the first second, its baseline window and each lost probe of 1 (0.2 s plus
  // 2 ms of settling), about 8 of them 1-4 s apart.
  CHECK(r.seconds_on[1] > 1.2);
  CHECK(r.seconds_on[1] < 3.2);
}

TEST_CASE("thread governor: a load that comes and goes: down to one thread, then back up", "[threads][governor]") {
  // 2 threads 0.6 ms a step except between 10 s and 40 s of run, when another program takes a
  // core and a 2-thread step costs 10 ms; 1 thread always 1 ms.
  thread_governor g(2, 2, test_params());
  const auto cost = [](int threads, double t) { return threads == 1 ? 1e-3 : (t >= 10 && t < 40 ? 10e-3 : 0.6e-3); };
  const simulated_run before = simulate(g, 10.0, cost);
  CHECK(before.final_threads == 2);
  // The load came: two slow quarter windows (0.1 s) start a probe at once, and after its baseline
  // window (0.2 s), 2 settling steps and a window on 1 thread (0.2 s) the run is on 1, well within
  // 1 s rather than a probe interval (up to 4 s) later.
  const simulated_run loaded = simulate(g, 1.0, [&](int threads, double t) { return cost(threads, t + 10); });
  CHECK(loaded.final_threads == 1);
  CHECK(loaded.seconds_on[2] < 0.6);
  simulate(g, 29.0, [&](int threads, double t) { return cost(threads, t + 11); });
  CHECK(g.threads() == 1);
  // The core freed at 40 s: back on 2 within 4.5 s (the longest interval plus two windows).
  const simulated_run freed = simulate(g, 4.5, [&](int threads, double t) { return cost(threads, t + 40); });
  CHECK(freed.final_threads == 2);
}

TEST_CASE("thread governor: a gain below the margin and single slow steps change nothing", "[threads][governor]") {
  SECTION("2 threads 5 % faster than 1, margin 10 %: stays on 1") {
    thread_governor g(1, 2, test_params());
    const simulated_run r = simulate(g, 30.0, [](int threads, double) { return threads == 2 ? 0.95e-3 : 1e-3; });
    CHECK(r.final_threads == 1);
    CHECK(g.switches() == 0);
    CHECK(g.probes() >= 6);  // 1 + 2 + 4 + 4 ... s apart, each after two 0.2 s windows: 7 in 30 s
    CHECK(g.probes() <= 8);
  }
  SECTION("equal counts, a 0.3 s step every 997 steps (a snapshot written): no switch") {
    // About one step in a thousand is slow, so some windows hold one; a window's mean would then
    // be 2.5x the other's and decide, the median of its quarter means does not.
    thread_governor g(2, 2, test_params());
    int steps = 0;
    simulate(g, 100.0, [&](int, double) { return ++steps % 997 == 0 ? 0.3 : 1e-3; });
    CHECK(steps > 60000);
    CHECK(g.switches() == 0);
    // Probes come by the interval (about 23 in 100 s), not at each of the 77 slow steps: one slow
    // step fills one quarter window, and a probe out of turn needs two slow quarters in a row.
    CHECK(g.probes() >= 20);
    CHECK(g.probes() <= 30);
  }
  SECTION("one core: never probes") {
    thread_governor g(1, 1, test_params());
    simulate(g, 10.0, [](int, double) { return 1e-3; });
    CHECK(g.probes() == 0);
  }
}

TEST_CASE("thread governor: the ladder halves and doubles within [1, max]", "[threads][governor]") {
  // 8 cores, only 1 - 4 threads help: from 8 the run halves to 4 and stays (2 and 8 are slower).
  thread_governor g(8, 8, test_params());
  const auto cost = [](int threads, double) {
    switch (threads) {
      case 4: return 0.3e-3;
      case 2: return 0.5e-3;
      case 8: return 3e-3;
      default: return 1e-3;
    }
  };
  double t = 0;
  std::set<int> seen;
  while (t < 60) {
    const int threads = g.threads();
    seen.insert(threads);
    t += cost(threads, t);
    g.record_step(cost(threads, t));
  }
  CHECK(g.threads() == 4);
  CHECK(seen == std::set<int>{2, 4, 8});  // 4 probes both neighbours; 1, 3, 5-7 are never tried
  CHECK(g.switches() == 1);
}

TEST_CASE("thread governor: refuses bad settings and step times, naming the value", "[threads][governor]") {
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(thread_governor(1, 0), Contains("max_threads = 0"));
  CHECK_THROWS_WITH(thread_governor(3, 2), Contains("threads = 3"));
  CHECK_THROWS_WITH(thread_governor(0, 2), Contains("threads = 0"));
  thread_governor_params p;
  p.window_s = 0;
  CHECK_THROWS_WITH(thread_governor(1, 2, p), Contains("window_s"));
  p = {};
  p.margin = 1;
  CHECK_THROWS_WITH(thread_governor(1, 2, p), Contains("margin = 1"));
  p = {};
  p.max_backoff = 0;
  CHECK_THROWS_WITH(thread_governor(1, 2, p), Contains("max_backoff = 0"));
  thread_governor g(1, 2);
  CHECK_THROWS_WITH(g.record_step(-1e-3), Contains("-0.001"));
  CHECK_THROWS_WITH(g.restart_at(5), Contains("threads = 5"));
  CHECK_THROWS_AS(start_thread_governor(0, 2), invalid_input);
  CHECK(running_thread_governor() == nullptr);
}

TEST_CASE("thread governor: a prism run whose thread count changes every few steps has the bits of one thread",
          "[threads][governor][determinism]") {
  // A 60-block Voronoi half prism (68 x 68 x 300 mm, seed 7), mass-scaled to 5e-7 s, bottom
  // fixed, top pulled at 20 mm/s: 200 steps. With windows and an interval of 1 ns every phase
  // lasts one step (a window four), so the governor probes the other count every 9 steps and
  // keeps whichever measured faster.
  const int saved_threads = max_threads();
  const auto tess = geometry::random_voronoi(aabb{vec3::Zero(), vec3(0.068, 0.068, 0.3)}, 60, 7);
  const auto mesh = geometry::zone_blocks(tess);
  const auto run = [&](bool governed) {
    solver_options one_thread;
    one_thread.threads = 1;
    one_thread.mass_scaling_dt = 5e-7;
    prism_solver s(tess, mesh, zones::linear_elastic_tet::params{280e9, 0.2, 2400}, law::study_prism_params(100), {},
                   one_thread);
    s.fix(s.gridpoints_on_plane(2, 0, 1e-9));
    s.prescribe_velocity(s.gridpoints_on_plane(2, 0.3, 1e-9), vec3(0, 0, 2e-2));
    std::set<int> counts;
    if (governed) {
      thread_governor_params p;
      p.probe_interval_s = 1e-9;
      p.window_s = 1e-9;
      p.margin = 0;
      p.max_backoff = 1;
      p.settle_steps = 0;
      start_thread_governor(1, 2, p);
    }
    s.run(200, [&](const auto&) { counts.insert(max_threads()); });
    const int probes = governed ? running_thread_governor()->probes() : 0;
    stop_thread_governor();
    return std::make_tuple(s.gridpoints().displacement, s.energies().contact_dissipated + s.energies().kinetic, counts,
                           probes);
  };
  const auto [x1, e1, counts1, probes1] = run(false);
  const auto [xg, eg, countsg, probesg] = run(true);
  set_threads(saved_threads);
  CHECK(counts1 == std::set<int>{1});
  CHECK(countsg == std::set<int>{1, 2});  // the governor did move between the counts
  CHECK(probesg >= 20);                   // 200 steps / 9
  REQUIRE(x1.size() == xg.size());
  CHECK(x1.cwiseAbs().maxCoeff() > 1e-7);  // the run did move
  CHECK(std::memcmp(x1.data(), xg.data(), static_cast<std::size_t>(x1.size()) * sizeof(real)) == 0);
  CHECK(std::memcmp(&e1, &eg, sizeof(real)) == 0);
}
