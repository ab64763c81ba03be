#pragma once
// Lane masks of the contact law's pack path built from bitwise operations only.
//
// Why: on the x86-64 baseline (SSE2, lanes::width 2) there is no 64-bit integer compare, so GCC
// evaluates `(flags & bit) != 0`, `m == 0` and `m ? a : b` for a mask m that is not itself a
// floating-point comparison one lane at a time in general registers (extract, neg/sbb, reinsert).
// A pack with a damaged lane paid for it: 229-265 instructions per sub-contact-step against 134.5
// for an intact one with lanes::select and `!= 0`, 189-226.5 against 127 with these helpers
// (callgrind, benchmarks/bench_contact_states.cpp). They give the same lanes with shifts and
// bitwise operations, and are plain bool operations for one sub-contact (T = real).
// Masks here have every lane all ones (true) or zero (false), as comparisons of packs give.

#include <bit>
#include <type_traits>

#include "../core/lanes.hpp"

#if defined(__SSE2__) && !defined(__AVX__)
#include <emmintrin.h>
#endif

namespace tessera::law::detail {

using unsigned_lane = std::make_unsigned_t<lanes::mask_lane>;
#if defined(__GNUC__)
/// The lanes of a lanes::mask as unsigned integers: shifted right, they shift in zeros, which
/// SSE2 does for 64-bit lanes (it has no arithmetic shift of them).
using unsigned_mask = unsigned_lane __attribute__((vector_size(sizeof(lanes::mask))));
#endif

/// Not m, lane by lane (m: a bool, or an integer used as one, or a lanes::mask).
template <class M>
[[nodiscard, gnu::always_inline]] inline auto mask_not(M m) noexcept {
  if constexpr (std::is_arithmetic_v<M>)
    return !m;
  else
    return ~m;
}

/// m ? a : b lane by lane, as lanes::select, for any mask m (for a pack: a bitwise blend, which
/// the compiler may simplify, e.g. to one and when a or b is zero).
template <class M, class T>
[[nodiscard, gnu::always_inline]] inline T mask_select(M m, T a, T b) noexcept {
  if constexpr (std::is_arithmetic_v<M>) {
    return m ? a : b;
  } else {
    static_assert(sizeof(M) == sizeof(T), "mask_select: a mask and a pack of the same width");
    return std::bit_cast<T>((std::bit_cast<M>(a) & m) | (std::bit_cast<M>(b) & ~m));
  }
}

/// mask_select as the instructions xor, and, xor on SSE2: where GCC recognises the bitwise
/// blend as a select again it evaluates m != 0 lane by lane (advance_states' stores).
template <class M, class T>
[[nodiscard, gnu::always_inline]] inline T mask_blend(M m, T a, T b) noexcept {
#if defined(__SSE2__) && !defined(__AVX__)
  if constexpr (!std::is_arithmetic_v<M>) {
    static_assert(std::is_same_v<T, lanes::pack> && sizeof(M) == sizeof(__m128d), "mask_blend: SSE2 packs");
    // b ^ ((a ^ b) & m): three instructions, and m is not overwritten (andnot would).
    const __m128d bits = _mm_castsi128_pd(std::bit_cast<__m128i>(m));
    const __m128d b_bits = std::bit_cast<__m128d>(b);
    return std::bit_cast<T>(_mm_xor_pd(b_bits, _mm_and_pd(_mm_xor_pd(std::bit_cast<__m128d>(a), b_bits), bits)));
  }
#endif
  return mask_select(m, a, b);
}

/// The lanes whose flags have bit `bit` (one power of two) set, as a mask M (bool for one
/// sub-contact): (flags & bit) != 0, computed as 0 - ((flags >> log2 bit) & 1).
template <class M, class F>
[[nodiscard, gnu::always_inline]] inline M flag_mask(F flags, lanes::mask_lane bit) noexcept {
  if constexpr (std::is_same_v<M, bool>) {
    return (flags & bit) != 0;
  } else {
    static_assert(std::is_same_v<M, lanes::mask> && std::is_same_v<F, lanes::mask>, "flag_mask: flags of a pack");
    const int shift = std::countr_zero(static_cast<unsigned_lane>(bit));
    return M{} - std::bit_cast<M>((std::bit_cast<unsigned_mask>(flags) >> shift) & unsigned_lane{1});
  }
}

}  // namespace tessera::law::detail
