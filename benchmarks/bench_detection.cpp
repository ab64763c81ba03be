// Contact detection kernels (contact/detection/): the broad phase by sort and sweep and by the
// uniform grid, the common plane alone, and a whole detection pass (detect.hpp: grid, common
// plane, patches) on 1 and 2 threads, on the blocks of a random Voronoi tessellation of blocks
// of about 50 mm, each shrunk by 1 % about its centroid (the blocks "moved apart by 1 %": faces
// open by 1 % of their two centroids' distances). Margin and contact tolerance: 5 % of a block,
// which takes in every opened face (test_contacts "detection pass").
// Args: blocks (1 000, 10 000), threads.
// Last, a whole solver step of 1 000 rigid blocks with fixed face contacts and with detected
// contacts (at the default rebuild policy, and with a pass forced every step), and the step of
// the README's arch (21 blocks) and of a 5-block stack: see below.
//
// Counters: pairs / candidates (of the broad phase), touching pairs, subcontacts (patch corners
// created), time_per_block (broad phase), time_per_pair, time_per_candidate, time_per_subcontact.
//
//   build/bench/benchmarks/bench_detection --benchmark_repetitions=3 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <vector>

#include <tessera/contact/detected_contacts.hpp>
#include <tessera/contact/detection/broad_phase.hpp>
#include <tessera/contact/detection/common_plane.hpp>
#include <tessera/contact/detection/detect.hpp>
#include <tessera/core/parallel.hpp>
#include <tessera/geometry.hpp>
#include <tessera/law.hpp>
#include <tessera/solver/solver.hpp>

#include "verification/cases.hpp"

namespace {

using tessera::aabb;
using tessera::mat3;
using tessera::real;
using tessera::vec3;
namespace geometry = tessera::geometry;
namespace detection = tessera::contact::detection;

/// Blocks of a Voronoi tessellation of n cells of about 50 mm, shrunk by 1 % about their centroids.
struct scene {
  std::vector<geometry::convex_polyhedron> blocks;
  std::vector<detection::polyhedron_edges> edges;
  std::vector<std::vector<tessera::geometry::plane>> faces;  ///< face planes, as a pass computes them once per block
  std::vector<aabb> boxes;
  real size = 0;  ///< mean block size (m)
};

const scene& scene_of(tessera::index_t n) {
  static std::map<tessera::index_t, std::unique_ptr<scene>> cache;
  auto& s = cache[n];
  if (s) return *s;
  s = std::make_unique<scene>();
  s->size = 0.05;
  const real side = s->size * std::cbrt(static_cast<real>(n));
  const auto tess = geometry::random_voronoi({vec3::Zero(), vec3::Constant(side)}, n, 1);
  for (tessera::index_t c = 0; c < tess.cell_count(); ++c) {
    const geometry::convex_polyhedron cell = geometry::cell_polyhedron(tess, c);
    const vec3 centre = cell.centroid();
    s->blocks.push_back(cell.transformed(0.99 * mat3::Identity(), 0.01 * centre));
    s->edges.push_back(detection::edges_of(s->blocks.back()));
    detection::append_face_planes(s->blocks.back(), s->faces.emplace_back());
    s->boxes.push_back(s->blocks.back().bounds());
  }
  return *s;
}

/// A broad phase run(boxes, margin, pairs) on the scene of state.range(0) blocks.
template <class Run>
void broad_phase(benchmark::State& state, Run&& run) {
  const scene& s = scene_of(static_cast<tessera::index_t>(state.range(0)));
  std::vector<detection::block_pair> pairs;
  for (auto _ : state) {
    run(s.boxes, 0.05 * s.size, pairs);
    benchmark::DoNotOptimize(pairs.data());
  }
  state.counters["pairs"] = static_cast<double>(pairs.size());
  state.counters["time_per_block"] = benchmark::Counter(static_cast<double>(s.boxes.size()),
                                                        benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_broad_sweep_and_prune(benchmark::State& state) {
  detection::sweep_workspace w;
  broad_phase(state, [&](const auto& boxes, real margin, auto& pairs) { detection::sweep_and_prune(boxes, margin, pairs, w); });
}

void BM_broad_uniform_grid(benchmark::State& state) {
  detection::grid_workspace w;
  broad_phase(state, [&](const auto& boxes, real margin, auto& pairs) { detection::uniform_grid(boxes, margin, pairs, w); });
}

/// A whole pass (detect.hpp: grid broad phase, common plane, patches), on 1 or 2 threads.
void BM_detection_pass(benchmark::State& state) {
  const scene& s = scene_of(static_cast<tessera::index_t>(state.range(0)));
  const int saved = tessera::max_threads();
  tessera::set_threads(static_cast<int>(state.range(1)));
  detection::detection_options options;
  options.margin = 0.05 * s.size;
  options.tolerance = 0.05 * s.size;  // takes in every face opened by the 1 % shrink (test_contacts)
  detection::detection_result r;
  detection::detection_workspace w;
  for (auto _ : state) {
    detection::detect(s.blocks, s.edges, s.boxes, options, r, w);
    benchmark::DoNotOptimize(r.point.data());
  }
  tessera::set_threads(saved);
  state.counters["candidates"] = static_cast<double>(r.candidates);
  state.counters["touching"] = static_cast<double>(r.pairs.size());
  state.counters["subcontacts"] = static_cast<double>(r.point.size());
  state.counters["time_per_candidate"] = benchmark::Counter(
      static_cast<double>(r.candidates), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["time_per_subcontact"] = benchmark::Counter(
      static_cast<double>(r.point.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// The common plane alone, every candidate pair (face planes computed once per block, as in a pass).
void BM_common_plane(benchmark::State& state) {
  const scene& s = scene_of(static_cast<tessera::index_t>(state.range(0)));
  detection::sweep_workspace w;
  std::vector<detection::block_pair> pairs;
  detection::sweep_and_prune(s.boxes, 0.05 * s.size, pairs, w);
  for (auto _ : state) {
    real sum = 0;
    for (const auto& p : pairs) {
      const auto a = static_cast<std::size_t>(p.a), b = static_cast<std::size_t>(p.b);
      sum += detection::common_plane(s.blocks[a], s.edges[a], s.faces[a], s.blocks[b], s.edges[b], s.faces[b]).gap;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.counters["pairs"] = static_cast<double>(pairs.size());
  state.counters["time_per_pair"] = benchmark::Counter(static_cast<double>(pairs.size()),
                                                       benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// ---- a solver step with and without detection (issue: detection adds under 50 % per step) ----
// The 1 000 blocks of scene_of(1000) unshrunk (their shared faces touch), rigid, under gravity,
// the blocks touching z = 0 fixed, the verification joint (k_n = k_s = 1e11 Pa/m, phi 30 deg):
//   fixed     contact::face_contacts: the tessellation's shared faces, one sub-contact per face vertex
//   detected  contact::detected_contacts on separate_blocks(cells), tolerance 1 % of a block: the
//             same faces found by detection (polygon patches), rebuilt at the default policy
//   rebuild   detected, a rebuild forced every step (max_rebuild_interval 1): the cost of a pass
// Counters: subcontacts, rebuilds (during the timed steps), time per step.
struct step_scene {
  geometry::tessellation tess, separate;
  geometry::block_mesh mesh, separate_mesh;
};
const step_scene& step_scene_of() {
  static const step_scene s = [] {
    step_scene r;
    const real side = 0.05 * std::cbrt(1000.0);
    r.tess = geometry::random_voronoi({vec3::Zero(), vec3::Constant(side)}, 1000, 1);
    std::vector<geometry::convex_polyhedron> cells;
    for (tessera::index_t c = 0; c < r.tess.cell_count(); ++c) cells.push_back(geometry::cell_polyhedron(r.tess, c));
    r.separate = geometry::separate_blocks(cells);
    r.mesh = geometry::zone_blocks(r.tess);
    r.separate_mesh = geometry::zone_blocks(r.separate);
    return r;
  }();
  return s;
}
template <class Solver>
void time_steps(benchmark::State& state, Solver& s) {
  s.set_gravity(vec3(0, 0, -9.81));
  s.fix(s.gridpoints_on_plane(2, 0, 1e-9));
  s.run(10);
  for (auto _ : state) s.step();
  state.counters["time_per_step"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
void BM_step_fixed_contacts(benchmark::State& state) {
  const step_scene& sc = step_scene_of();
  const int saved = tessera::max_threads();
  tessera::set_threads(static_cast<int>(state.range(0)));
  namespace ver = tessera::verification;
  tessera::solver<tessera::blocks::rigid, tessera::contact::face_contacts<ver::joint_law>> s(sc.tess, sc.mesh, {2400},
                                                                                             ver::joint({}));
  time_steps(state, s);
  state.counters["subcontacts"] = static_cast<double>(s.contacts().subcontact_count());
  tessera::set_threads(saved);
}
void BM_step_detected_contacts(benchmark::State& state) {
  const step_scene& sc = step_scene_of();
  const int saved = tessera::max_threads();
  tessera::set_threads(static_cast<int>(state.range(0)));
  namespace ver = tessera::verification;
  const tessera::index_t interval = state.range(1) > 0 ? state.range(1) : 1000;
  ver::contacts::params p(ver::joint({}), 0.01 * 0.05, interval);
  tessera::solver<tessera::blocks::rigid, ver::contacts> s(sc.separate, sc.separate_mesh, {2400}, p);
  const tessera::index_t before = s.contacts().rebuild_count();
  time_steps(state, s);
  state.counters["subcontacts"] = static_cast<double>(s.contacts().subcontact_count());
  state.counters["rebuilds"] = static_cast<double>(s.contacts().rebuild_count() - before);
  tessera::set_threads(saved);
}

// ---- a small scene's step (issue #65: 5-50 rigid blocks, the cost outside the contacts) ----
// The README's arch (tests/consumer/arch.cpp: a 6 x 1 x 0.5 m base held and 20 voussoirs between
// radii 2.0 and 2.4 m, dry joints k_n = k_s = 1e10 Pa/m, 35 deg, tolerance 1 mm, gravity) and a
// stack of four 0.5 m cubes on the same base (5 blocks), on detected contacts at the default
// rebuild policy. One step taken before the timed ones (the construction's pass is not timed).
// Counters: subcontacts, rebuilds (during the timed steps), time per step (wall; on a loaded
// host read the CPU column: these scenes run every loop serially, below its grain, on 2 threads too).
void BM_step_small_scene(benchmark::State& state) {
  namespace law = tessera::law;
  std::vector<geometry::convex_polyhedron> blocks{geometry::convex_polyhedron::box(vec3(-3, -0.5, -0.5), vec3(3, 0.5, 0))};
  if (state.range(0) == 5) {
    for (int k = 0; k < 4; ++k)
      blocks.push_back(geometry::convex_polyhedron::box(vec3(-0.25, -0.25, 0.5 * k), vec3(0.25, 0.25, 0.5 * k + 0.5)));
  } else {
    for (int k = 0; k < 20; ++k)
      blocks.push_back(geometry::voussoir(vec3(0, 0, 0), 2.0, 2.4, std::numbers::pi * k / 20, std::numbers::pi * (k + 1) / 20, 1.0));
  }
  const auto tess = geometry::separate_blocks(blocks);
  const auto mesh = geometry::zone_blocks(tess);
  const int saved = tessera::max_threads();
  tessera::set_threads(static_cast<int>(state.range(1)));
  using joints = tessera::contact::detected_contacts<law::dry_joint_law>;
  const joints::params joint(law::dry_joint(1e10, 1e10, law::friction_angle::from_degrees(35)), 1e-3);
  tessera::solver<tessera::blocks::rigid, joints> s(tess, mesh, tessera::blocks::rigid::params{2400}, joint);
  s.fix_blocks(s.blocks_below(2, 0.0));
  s.set_gravity(vec3(0, 0, -9.81));
  s.step();
  const tessera::index_t before = s.contacts().rebuild_count();
  for (auto _ : state) s.step();
  state.counters["subcontacts"] = static_cast<double>(s.contacts().subcontact_count());
  state.counters["rebuilds"] = static_cast<double>(s.contacts().rebuild_count() - before);
  state.counters["time_per_step"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  tessera::set_threads(saved);
}

}  // namespace

BENCHMARK(BM_step_small_scene)->ArgNames({"blocks", "threads"})->Args({5, 1})->Args({21, 1})->Args({5, 2})->Args({21, 2})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_step_fixed_contacts)->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_step_detected_contacts)->ArgNames({"threads", "interval"})->Args({1, 0})->Args({2, 0})->Args({1, 1})->Args({2, 1})->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_common_plane)->ArgName("blocks")->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_broad_sweep_and_prune)->ArgName("blocks")->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_broad_uniform_grid)->ArgName("blocks")->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_detection_pass)->ArgNames({"blocks", "threads"})->Args({1000, 1})->Args({1000, 2})->Args({10000, 1})->Args({10000, 2})->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
