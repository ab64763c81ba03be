#pragma once
// lanes: several values of `real` processed by one instruction, for kernels that run the same
// arithmetic over packs of entities (contact::face_contacts's elastic path).
//
// A pack is a GCC/Clang vector-extension type of `width` reals: + - * / and comparisons act lane by
// lane with exactly the IEEE operations of scalar code (no reassociation), so a lane of a pack
// computes the same bits as the scalar expression it is written from (with -ffp-contract the
// compiler may fuse a * b + c in either form; the release preset's x86-64 baseline has no FMA).
// Kernels are written once as templates on T = real (one entity) or T = pack; the helpers below
// (select, sqrt, load, store) have both forms.
//
// width: 8 with AVX-512, 4 with AVX, 2 otherwise (SSE2 on the x86-64 baseline, NEON, ...); 1 with a
// compiler without vector extensions, where a pack is a plain real and the pack kernels run scalar.
// A comparison of packs gives a `mask` (lanes all ones or zero); combine masks with & and |, negate
// with `m == 0` (which is also `!m` for a scalar bool), never with && or ||.
//
// Why vector extensions and not `#pragma omp simd` over a scalar loop body: with the default
// -fmath-errno and -ftrapping-math GCC does not vectorise std::sqrt, nor a division or square
// root whose result a lane may discard, so such a loop stays scalar in a default build. Written on
// packs, every lane evaluates every operation (a discarded lane may compute a NaN or an infinity,
// which nothing traps), and sqrt goes through the vector square-root instruction where there is
// one (correctly rounded, as std::sqrt).

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "types.hpp"

// The intrinsics of the widest instruction set in use only: <immintrin.h> declares every x86
// extension's (AVX-512 included) and costs a scene about 1 s and 100 MB of compile (GCC 12), while
// the x86-64 baseline needs SSE2's alone (docs/studies/compile_time.md).
#if defined(__GNUC__) && (defined(__AVX512F__) || defined(__AVX__))
#include <immintrin.h>
#elif defined(__GNUC__) && defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace tessera::lanes {

#if defined(__GNUC__)
#if defined(__AVX512F__)
inline constexpr int width = 8;
#elif defined(__AVX__)
inline constexpr int width = 4;
#else
inline constexpr int width = 2;
#endif
/// `width` reals, one per lane.
using pack = real __attribute__((vector_size(width * sizeof(real))));
#else
inline constexpr int width = 1;
using pack = real;
#endif
/// Result of a comparison of packs: a lane is all ones (true) or zero (false).
using mask = decltype(pack{} < pack{});

/// Lane-wise m ? a : b (scalar: the plain conditional).
template <class M, class T>
[[nodiscard, gnu::always_inline]] inline T select(M m, T a, T b) noexcept {
  return m ? a : b;
}

/// Correctly rounded square root, lane by lane.
[[nodiscard, gnu::always_inline]] inline real sqrt(real x) noexcept { return std::sqrt(x); }
#if defined(__GNUC__)
[[nodiscard, gnu::always_inline]] inline pack sqrt(pack x) noexcept {
#if defined(__AVX512F__)
  return _mm512_sqrt_pd(x);
#elif defined(__AVX__)
  return _mm256_sqrt_pd(x);
#elif defined(__SSE2__)
  return _mm_sqrt_pd(x);
#else
  pack r;
  for (int k = 0; k < width; ++k) r[k] = std::sqrt(x[k]);
  return r;
#endif
}
#endif

/// The lanes of T (real or pack) from p[0 ..) (no alignment needed).
template <class T>
[[nodiscard, gnu::always_inline]] inline T load(const real* p) noexcept {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
/// Stores the lanes of v (a real or a pack) to p[0 ..) (no alignment needed).
template <class T>
[[gnu::always_inline]] inline void store(real* p, const T& v) noexcept {
  std::memcpy(p, &v, sizeof v);
}
/// Integer of a mask lane (all ones = true, 0 = false); a column of them loads as a mask.
#if defined(__GNUC__)
using mask_lane = std::remove_cvref_t<decltype(mask{}[0])>;
#else
using mask_lane = std::int64_t;
#endif

/// x in every lane of T (real or pack).
template <class T>
[[nodiscard, gnu::always_inline]] inline T splat(real x) noexcept {
  if constexpr (std::is_same_v<T, real>) {
    return x;
  } else {
    T v;
    for (int k = 0; k < width; ++k) v[k] = x;
    return v;
  }
}

/// The mask lanes b[0 ..) as integers: a mask_lane for T = real, a mask for T = pack (bit tests
/// `(m & bits) != 0` then give a bool or a mask).
template <class T>
[[nodiscard, gnu::always_inline]] inline auto load_lanes(const mask_lane* b) noexcept {
  if constexpr (std::is_same_v<T, real>) {
    return b[0];
  } else {
    decltype(T{} < T{}) m;
    std::memcpy(&m, b, sizeof m);
    return m;
  }
}

/// True when any lane of m (a bool or a mask) is set.
template <class M>
[[nodiscard, gnu::always_inline]] inline bool any(const M& m) noexcept {
  if constexpr (std::is_same_v<M, bool>) {
    return m;
  } else {
    mask_lane bits = 0;
    for (int k = 0; k < width; ++k) bits |= m[k];
    return bits != 0;
  }
}
/// Stores the lanes of m (a bool or a mask) to b[0 ..) as mask lanes: all ones (-1) or 0.
template <class M>
[[gnu::always_inline]] inline void store_mask(mask_lane* b, const M& m) noexcept {
  if constexpr (std::is_same_v<M, bool>) {
    b[0] = m ? -1 : 0;
  } else {
    std::memcpy(b, &m, sizeof m);
  }
}

}  // namespace tessera::lanes
