// The machine's own limits, for the roofline note in docs/performance.md: memory bandwidth of a
// STREAM-like triad a[i] = b[i] + s c[i] (24 bytes moved per element, 2 flops) at sizes that
// live in L1, L2, L3 and DRAM, and the floating-point throughput of independent multiply-add
// chains (8 accumulators, so the loop is bound by issue width, not latency). One thread; the
// kernels of tessera run one per core, so these are the per-core ceilings they are measured
// against.
//
//   build/bench/benchmarks/bench_machine --benchmark_counters_tabular=true
//
// Counters: bytes_per_second (triad, 24 bytes per element as STREAM counts them; the write
// allocate traffic is not counted) and flops_per_second (2 flops per element for the triad,
// 2 per multiply-add for the chains).
#include <benchmark/benchmark.h>

#include <cstddef>
#include <vector>

namespace {

void triad(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  const double s = 1.0000001;
  for (auto _ : state) {
    double* __restrict pa = a.data();
    const double* __restrict pb = b.data();
    const double* __restrict pc = c.data();
    for (std::size_t i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
    benchmark::DoNotOptimize(pa);
    benchmark::ClobberMemory();
  }
  const auto elements = static_cast<double>(n);
  state.counters["bytes_per_second"] = benchmark::Counter(24 * elements, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["flops_per_second"] = benchmark::Counter(2 * elements, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["working_set_KiB"] = 24 * elements / 1024;
}
// 1 Ki elements = 24 KiB (L1), 16 Ki = 384 KiB (L2), 256 Ki = 6 MiB (L3), 8 Mi = 192 MiB (DRAM).
BENCHMARK(triad)->Arg(1 << 10)->Arg(1 << 14)->Arg(1 << 18)->Arg(1 << 23)->Unit(benchmark::kMicrosecond);

void fma_chains(benchmark::State& state) {
  // 8 independent chains of x = x * m + c, each element of a small array: compilers vectorise the
  // inner loop over the 64-element array, so this measures what the build's ISA gives (SSE2 for
  // the portable build, AVX2/AVX-512 with -march=native).
  constexpr int width = 64;
  alignas(64) double x[width];
  for (int k = 0; k < width; ++k) x[k] = 1.0 + 1e-3 * k;
  const double m = 0.999999, c = 1e-7;
  constexpr int repeats = 256;
  for (auto _ : state) {
    for (int r = 0; r < repeats; ++r)
      for (int k = 0; k < width; ++k) x[k] = x[k] * m + c;
    benchmark::DoNotOptimize(x);
  }
  state.counters["flops_per_second"] =
      benchmark::Counter(2.0 * width * repeats, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(fma_chains);

}  // namespace

BENCHMARK_MAIN();
