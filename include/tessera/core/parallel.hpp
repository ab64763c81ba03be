#pragma once
// Deterministic parallel loops. Every parallel loop in tessera writes only to the entries
// of the index it owns (gather, never racing scatter), so results are bit-identical for any
// thread count. Reductions go through fixed-order per-chunk partial sums.

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <vector>
#if defined(_OPENMP)
#include <omp.h>
#endif

/// `#pragma omp simd` where OpenMP is enabled, nothing otherwise (so builds without OpenMP, such
/// as the sanitizer presets, do not warn about an unknown pragma). Put it right before a loop.
#if defined(_OPENMP)
#define TESSERA_PRAGMA_SIMD _Pragma("omp simd")
#define TESSERA_DETAIL_PRAGMA(x) _Pragma(#x)
/// `#pragma omp simd reduction(+ : a, b)` where OpenMP is enabled, nothing otherwise.
#define TESSERA_PRAGMA_SIMD_REDUCTION(a, b) TESSERA_DETAIL_PRAGMA(omp simd reduction(+ : a, b))
#else
#define TESSERA_PRAGMA_SIMD
/// nothing without OpenMP
#define TESSERA_PRAGMA_SIMD_REDUCTION(a, b)
#endif

namespace tessera {

/// Number of threads parallel loops use (1 without OpenMP).
inline int max_threads() {
#if defined(_OPENMP)
  return omp_get_max_threads();
#else
  return 1;
#endif
}
/// Sets the number of threads used by subsequent parallel loops (no-op without OpenMP).
inline void set_threads(int n) {
#if defined(_OPENMP)
  if (n > 0) omp_set_num_threads(n);
#else
  (void)n;
#endif
}

/// Calls f(i) for i in [0, n), in parallel when n is large enough. f must only write to
/// state owned by index i.
template <class F>
void parallel_for(std::int64_t n, F&& f, std::int64_t grain = 256) {
#if defined(_OPENMP)
  if (n >= 2 * grain && omp_get_max_threads() > 1) {
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) f(i);
    return;
  }
#endif
  (void)grain;
  for (std::int64_t i = 0; i < n; ++i) f(i);
}

/// parallel_for for items of uneven cost (a detection pass's candidate pairs: some cost a kept
/// axis's test, some a full search): the threads take runs of `chunk` items as they finish their
/// last, rather than one fixed share each. f must only write to state owned by index i (so the
/// results do not depend on which thread ran which item). Serial below 2 x chunk or one thread.
template <class F>
void parallel_for_dynamic(std::int64_t n, F&& f, std::int64_t chunk = 16) {
#if defined(_OPENMP)
  if (n >= 2 * chunk && omp_get_max_threads() > 1) {
#pragma omp parallel for schedule(dynamic, chunk)
    for (std::int64_t i = 0; i < n; ++i) f(i);
    return;
  }
#endif
  (void)chunk;
  for (std::int64_t i = 0; i < n; ++i) f(i);
}
/// Two independent loops of a step in ONE parallel region (one fork/join instead of two): each
/// thread gets its share of [0, n) as one contiguous range, f(begin, end) (thread t of T:
/// [n t / T, n (t + 1) / T)), so f can prepare per-range data (say, the block rotations its items
/// need) without a barrier, then runs its statically scheduled share of g(j), j in [0, m), with
/// no barrier in between. f must only write state owned by its range and g state owned by j, and
/// neither may depend on the other's results. Serial f(0, n) then g when n + m < 2 grain or one
/// thread.
/// Seconds spent in the two loops of parallel_range_pair, summed over threads (so on one thread
/// the wall time of each loop, on several the thread time: a per-core cost).
struct range_pair_times {
  double first = 0;  ///< s in the first loop
  double second = 0;  ///< s in the second loop
};

template <class F, class G>
void parallel_range_pair(std::int64_t n, F&& f, std::int64_t m, G&& g, std::int64_t grain = 16,
                         range_pair_times* times = nullptr) {
  using clock = std::chrono::steady_clock;
  const auto seconds = [](clock::time_point a, clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
#if defined(_OPENMP)
  if (n + m >= 2 * grain && omp_get_max_threads() > 1) {
#pragma omp parallel
    {
      const std::int64_t threads = omp_get_num_threads(), t = omp_get_thread_num();
      const std::int64_t begin = n * t / threads, end = n * (t + 1) / threads;
      const auto t0 = times != nullptr ? clock::now() : clock::time_point{};
      if (begin < end) f(begin, end);
      const auto t1 = times != nullptr ? clock::now() : clock::time_point{};
#pragma omp for schedule(static) nowait
      for (std::int64_t j = 0; j < m; ++j) g(j);
      if (times != nullptr) {
        const double first = seconds(t0, t1), second = seconds(t1, clock::now());
#pragma omp atomic
        times->first += first;
#pragma omp atomic
        times->second += second;
      }
    }
    return;
  }
#endif
  (void)grain;
  const auto t0 = times != nullptr ? clock::now() : clock::time_point{};
  if (n > 0) f(std::int64_t{0}, n);
  const auto t1 = times != nullptr ? clock::now() : clock::time_point{};
  for (std::int64_t j = 0; j < m; ++j) g(j);
  if (times != nullptr) {
    times->first += seconds(t0, t1);
    times->second += seconds(t1, clock::now());
  }
}

/// Sum of f(i) over [0, n) with a result independent of the thread count: partial sums
/// over fixed chunks of `chunk` indices, added in chunk order. Up to 64 chunks (64 x chunk
/// terms) the partial sums live on the stack, so a call inside solver::step (the deformable
/// blocks' gravity work) allocates nothing.
template <class F>
double deterministic_sum(std::int64_t n, F&& f, std::int64_t chunk = 1024) {
  const std::int64_t chunks = std::max<std::int64_t>((n + chunk - 1) / chunk, 0);
  constexpr std::int64_t on_stack = 64;
  std::array<double, on_stack> local{};
  std::vector<double> heap;
  if (chunks > on_stack) heap.assign(static_cast<std::size_t>(chunks), 0.0);
  double* const partial = chunks > on_stack ? heap.data() : local.data();
  parallel_for(chunks, [&](std::int64_t c) {
    double s = 0.0;
    const std::int64_t end = std::min(n, (c + 1) * chunk);
    for (std::int64_t i = c * chunk; i < end; ++i) s += f(i);
    partial[c] = s;
  }, 1);
  double total = 0.0;
  for (std::int64_t c = 0; c < chunks; ++c) total += partial[c];
  return total;
}

}  // namespace tessera
