// Contact detection kernels (contact/detection/): the broad phase by sort and sweep and by the
// uniform grid, and the narrow phase (common plane, then the contact patch of the pairs within
// the contact tolerance), on the blocks of a random Voronoi tessellation each shrunk by 1 % of
// its size about its centroid (the blocks "moved apart by 1 %": neighbours face each other across
// gaps of about 1 % of a block). Arg = number of blocks (1 000, 10 000).
//
// Counters: pairs (candidates of the broad phase), subcontacts (patch corners created),
// time_per_block (broad phase), time_per_pair and time_per_subcontact (narrow phase).
//
//   build/bench/benchmarks/bench_detection --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include <tessera/contact/detection/broad_phase.hpp>
#include <tessera/contact/detection/common_plane.hpp>
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

void BM_broad_sweep_and_prune(benchmark::State& state) {
  const scene& s = scene_of(static_cast<tessera::index>(state.range(0)));
  detection::sweep_workspace w;
  std::vector<detection::block_pair> pairs;
  for (auto _ : state) {
    detection::sweep_and_prune(s.boxes, 0.02 * s.size, pairs, w);
    benchmark::DoNotOptimize(pairs.data());
  }
  state.counters["pairs"] = static_cast<double>(pairs.size());
  state.counters["time_per_block"] = benchmark::Counter(static_cast<double>(s.boxes.size()),
                                                        benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_broad_uniform_grid(benchmark::State& state) {
  const scene& s = scene_of(static_cast<tessera::index>(state.range(0)));
  detection::grid_workspace w;
  std::vector<detection::block_pair> pairs;
  for (auto _ : state) {
    detection::uniform_grid(s.boxes, 0.02 * s.size, pairs, w);
    benchmark::DoNotOptimize(pairs.data());
  }
  state.counters["pairs"] = static_cast<double>(pairs.size());
  state.counters["time_per_block"] = benchmark::Counter(static_cast<double>(s.boxes.size()),
                                                        benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_narrow_phase(benchmark::State& state) {
  const scene& s = scene_of(static_cast<tessera::index>(state.range(0)));
  detection::sweep_workspace w;
  std::vector<detection::block_pair> pairs;
  detection::sweep_and_prune(s.boxes, 0.02 * s.size, pairs, w);
  const real tolerance = 0.02 * s.size;  // the 1 % gaps are inside it
  std::size_t subcontacts = 0;
  for (auto _ : state) {
    subcontacts = 0;
    for (const auto& p : pairs) {
      const auto& a = s.blocks[static_cast<std::size_t>(p.a)];
      const auto& b = s.blocks[static_cast<std::size_t>(p.b)];
      const auto plane = detection::common_plane(a, s.edges[static_cast<std::size_t>(p.a)], b, s.edges[static_cast<std::size_t>(p.b)]);
      if (plane.gap > tolerance) continue;
      subcontacts += detection::contact_patch_of(a, b, plane, tolerance).points.size();
    }
    benchmark::DoNotOptimize(subcontacts);
  }
  state.counters["pairs"] = static_cast<double>(pairs.size());
  state.counters["subcontacts"] = static_cast<double>(subcontacts);
  state.counters["time_per_pair"] = benchmark::Counter(static_cast<double>(pairs.size()),
                                                       benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["time_per_subcontact"] = benchmark::Counter(
      static_cast<double>(subcontacts), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// The common plane alone, every candidate pair.
void BM_common_plane(benchmark::State& state) {
  const scene& s = scene_of(static_cast<tessera::index>(state.range(0)));
  detection::sweep_workspace w;
  std::vector<detection::block_pair> pairs;
  detection::sweep_and_prune(s.boxes, 0.02 * s.size, pairs, w);
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
BENCHMARK(BM_narrow_phase)->ArgName("blocks")->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
