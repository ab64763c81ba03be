// Contact detection kernels (contact/detection/): the broad phase by sort and sweep and by the
// uniform grid, the common plane alone, and a whole detection pass (detect.hpp: grid, common
// plane, patches) on 1 and 2 threads, on the blocks of a random Voronoi tessellation of blocks
// of about 50 mm, each shrunk by 1 % about its centroid (the blocks "moved apart by 1 %": faces
// open by 1 % of their two centroids' distances). Margin and contact tolerance: 5 % of a block,
// which takes in every opened face (test_contacts "detection pass").
// Args: blocks (1 000, 10 000), threads.
//
// Counters: pairs / candidates (of the broad phase), touching pairs, subcontacts (patch corners
// created), time_per_block (broad phase), time_per_pair, time_per_candidate, time_per_subcontact.
//
//   build/bench/benchmarks/bench_detection --benchmark_repetitions=3 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include <tessera/contact/detection/broad_phase.hpp>
#include <tessera/contact/detection/common_plane.hpp>
#include <tessera/contact/detection/detect.hpp>
#include <tessera/core/parallel.hpp>
#include <tessera/geometry.hpp>

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
  std::vector<aabb> boxes;
  real size = 0;  ///< mean block size (m)
};

const scene& scene_of(tessera::index n) {
  static std::map<tessera::index, std::unique_ptr<scene>> cache;
  auto& s = cache[n];
  if (s) return *s;
  s = std::make_unique<scene>();
  s->size = 0.05;
  const real side = s->size * std::cbrt(static_cast<real>(n));
  const auto tess = geometry::random_voronoi({vec3::Zero(), vec3::Constant(side)}, n, 1);
  for (tessera::index c = 0; c < tess.cell_count(); ++c) {
    const geometry::convex_polyhedron cell = geometry::cell_polyhedron(tess, c);
    const vec3 centre = cell.centroid();
    s->blocks.push_back(cell.transformed(0.99 * mat3::Identity(), 0.01 * centre));
    s->edges.push_back(detection::edges_of(s->blocks.back()));
    s->boxes.push_back(s->blocks.back().bounds());
  }
  return *s;
}

/// A broad phase run(boxes, margin, pairs) on the scene of state.range(0) blocks.
template <class Run>
void broad_phase(benchmark::State& state, Run&& run) {
  const scene& s = scene_of(static_cast<tessera::index>(state.range(0)));
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
  const scene& s = scene_of(static_cast<tessera::index>(state.range(0)));
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

/// The common plane alone, every candidate pair.
void BM_common_plane(benchmark::State& state) {
  const scene& s = scene_of(static_cast<tessera::index>(state.range(0)));
  detection::sweep_workspace w;
  std::vector<detection::block_pair> pairs;
  detection::sweep_and_prune(s.boxes, 0.05 * s.size, pairs, w);
  for (auto _ : state) {
    real sum = 0;
    for (const auto& p : pairs)
      sum += detection::common_plane(s.blocks[static_cast<std::size_t>(p.a)], s.edges[static_cast<std::size_t>(p.a)],
                                     s.blocks[static_cast<std::size_t>(p.b)], s.edges[static_cast<std::size_t>(p.b)])
                 .gap;
    benchmark::DoNotOptimize(sum);
  }
  state.counters["pairs"] = static_cast<double>(pairs.size());
  state.counters["time_per_pair"] = benchmark::Counter(static_cast<double>(pairs.size()),
                                                       benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK(BM_common_plane)->ArgName("blocks")->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_broad_sweep_and_prune)->ArgName("blocks")->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_broad_uniform_grid)->ArgName("blocks")->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_detection_pass)->ArgNames({"blocks", "threads"})->Args({1000, 1})->Args({1000, 2})->Args({10000, 1})->Args({10000, 2})->UseRealTime()->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
