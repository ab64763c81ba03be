// Random Voronoi tessellation of the unit cube: cells per second, including seed generation,
// the parallel cell computation and the serial welding/twin pairing.
//   cmake -S . -B build/x -DCMAKE_BUILD_TYPE=Release -DTESSERA_BUILD_BENCHMARKS=ON
//   cmake --build build/x --target bench_tessellation && build/x/benchmarks/bench_tessellation
// Anchors: Voro++ computes about 1e5 cells/s per core for the cell geometry alone; Neper's
// tessellation of 1e5 cells takes tens of seconds. Target: 100 000 cells in < 5 s on 2 cores.
#include <benchmark/benchmark.h>

#include <tessera/geometry/tessellation_queries.hpp>
#include <tessera/geometry/voronoi.hpp>

namespace {

void random_voronoi_unit_cube(benchmark::State& state) {
  const auto n = static_cast<tessera::index_t>(state.range(0));
  const tessera::aabb box{tessera::vec3(0, 0, 0), tessera::vec3(1, 1, 1)};
  std::uint64_t seed = 1;
  tessera::index_t faces = 0;
  for (auto _ : state) {
    const auto t = tessera::geometry::random_voronoi(box, n, seed++);
    faces = t.face_count();
    benchmark::DoNotOptimize(t.vertices.data());
  }
  state.counters["cells/s"] = benchmark::Counter(static_cast<double>(n) * static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
  state.counters["faces/cell"] = static_cast<double>(faces) / n;
}
BENCHMARK(random_voronoi_unit_cube)->Arg(100)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();

// The study's prism (68 x 68 x 600 mm) with 100 blocks, as built by every tie scene.
void random_voronoi_tie_prism(benchmark::State& state) {
  const tessera::aabb box{tessera::vec3(0, 0, 0), tessera::vec3(0.068, 0.068, 0.6)};
  for (auto _ : state) {
    const auto t = tessera::geometry::random_voronoi(box, static_cast<tessera::index_t>(state.range(0)), 7);
    benchmark::DoNotOptimize(t.vertices.data());
  }
}
BENCHMARK(random_voronoi_tie_prism)->Arg(100)->Arg(500)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
