#pragma once
// Rotation factor R of the polar decomposition F = R U (R proper orthogonal, U symmetric
// positive definite) by Higham's Newton iteration X <- (X + X^-T) / 2, warm-started from the
// previous rotation: with X0 = R_prev^T F the iteration starts next to its limit (the rotation
// increment of one step is tiny), so a few iterations reach round-off (X0 ~ U ~ 1 + strain: the
// changes go strain, strain^2, then below 1e-15). Converges quadratically from any non-singular
// start; for the 90-degree jump of a test from the identity, X0 is already orthogonal and the
// first iterate is exact.
//
// The iteration is a serial chain (determinant, nine divisions, next iterate), so one block at a
// time leaves the core waiting on latencies. polar_rotations() runs the blocks in lock-step, one
// block per lane of a lanes::pack, with every lane doing exactly the scalar arithmetic of
// polar_rotation() and stopping at the scalar iteration count: the same rotations to the bit
// (tests/test_mechanics.cpp checks it), about six times less time per block on AVX-512.

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "../../core/lanes.hpp"
#include "../../core/types.hpp"

namespace tessera::blocks::detail {

/// One Newton step on x (row-major x[3 r + c]) for T = real or a lanes::pack: next = (x + x^-T)/2
/// with x^-T = cofactor(x)/det, det = det(x) (Eigen's 3x3 determinant, term by term) and the
/// largest change |next - x| over the nine entries.
/// Compiled without contraction into fused multiply-adds (as a build without FMA computes it), so
/// the scalar and pack instantiations cannot fuse differently: GCC picks which product of a * b -
/// c * d it fuses from the expression's context, and it did not pick alike in the two.
template <class T>
#if defined(__GNUC__) && !defined(__clang__)
__attribute__((optimize("fp-contract=off")))
#endif
inline void polar_newton_step(const T (&x)[9], T (&next)[9], T& det, T& change) noexcept {
#if defined(__clang__)
#pragma clang fp contract(off)
#endif
  const auto at = [&](int r, int c) -> const T& { return x[3 * r + c]; };
  det = at(0, 0) * (at(1, 1) * at(2, 2) - at(1, 2) * at(2, 1)) - at(0, 1) * (at(1, 0) * at(2, 2) - at(1, 2) * at(2, 0)) +
        at(0, 2) * (at(1, 0) * at(2, 1) - at(1, 1) * at(2, 0));
  T cof[9];
  cof[0] = at(1, 1) * at(2, 2) - at(1, 2) * at(2, 1);
  cof[1] = at(1, 2) * at(2, 0) - at(1, 0) * at(2, 2);
  cof[2] = at(1, 0) * at(2, 1) - at(1, 1) * at(2, 0);
  cof[3] = at(0, 2) * at(2, 1) - at(0, 1) * at(2, 2);
  cof[4] = at(0, 0) * at(2, 2) - at(0, 2) * at(2, 0);
  cof[5] = at(0, 1) * at(2, 0) - at(0, 0) * at(2, 1);
  cof[6] = at(0, 1) * at(1, 2) - at(0, 2) * at(1, 1);
  cof[7] = at(0, 2) * at(1, 0) - at(0, 0) * at(1, 2);
  cof[8] = at(0, 0) * at(1, 1) - at(0, 1) * at(1, 0);
  for (int k = 0; k < 9; ++k) next[k] = 0.5 * (x[k] + cof[k] / det);
  T m = next[0] - x[0];
  m = m < 0 ? -m : m;
  change = m;
  for (int k = 1; k < 9; ++k) {
    T d = next[k] - x[k];
    d = d < 0 ? -d : d;
    change = change < d ? d : change;
  }
}

/// Largest number of Newton steps; a start that has not converged by then keeps the last iterate.
inline constexpr int polar_max_steps = 12;
/// Convergence: the largest entry change of a step below this ends the iteration after that step.
inline constexpr real polar_tolerance = 1e-15;

/// x0 = r_prev^T f, row-major.
inline void polar_start(const mat3& f, const mat3& r_prev, real (&x)[9]) noexcept {
  const mat3 x0 = r_prev.transpose() * f;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) x[3 * r + c] = x0(r, c);
}
/// r_prev x (x row-major).
[[nodiscard]] inline mat3 polar_finish(const mat3& r_prev, const real (&x)[9]) noexcept {
  mat3 xm;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) xm(r, c) = x[3 * r + c];
  return r_prev * xm;
}

/// Orthogonal polar factor of f, given a previous estimate r_prev (rotation). Returns r_prev when
/// f is singular or inverted (det <= 0), which only happens in a run that is already unstable.
[[nodiscard]] inline mat3 polar_rotation(const mat3& f, const mat3& r_prev) noexcept {
  real x[9];
  polar_start(f, r_prev, x);
  for (int it = 0; it < polar_max_steps; ++it) {
    real next[9], det, change;
    polar_newton_step(x, next, det, change);
    if (!(det > 0)) return r_prev;
    std::copy(next, next + 9, x);
    if (change < polar_tolerance) break;
  }
  return polar_finish(r_prev, x);
}

/// r[k] = polar_rotation(f[k], r[k]) for k < n (n <= lanes::width), in lock-step over the lanes
/// of a pack; the same bits as n calls of polar_rotation.
template <class pack = lanes::pack>
inline void polar_rotations(const mat3* f, mat3* r, int n) noexcept {
  if constexpr (lanes::width == 1) {
    for (int k = 0; k < n; ++k) r[k] = polar_rotation(f[k], r[k]);
  } else {
    pack x[9];
    for (int k = 0; k < lanes::width; ++k) {
      real xk[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // lanes past n: the identity, converged at once
      if (k < n) polar_start(f[k], r[k], xk);
      for (int e = 0; e < 9; ++e) x[e][k] = xk[e];
    }
    // active: still iterating; failed: det <= 0 met (keeps r_prev, as polar_rotation)
    auto active = pack{} == pack{};
    auto failed = pack{} != pack{};
    for (int it = 0; it < polar_max_steps; ++it) {
      pack next[9], det, change;
      polar_newton_step(x, next, det, change);
      const auto bad = active & ((det > 0) == 0);
      failed |= bad;
      active &= (bad == 0);
      for (int e = 0; e < 9; ++e) x[e] = lanes::select(active, next[e], x[e]);
      active &= ((change < polar_tolerance) == 0);
      if (!lanes::any(active)) break;
    }
    for (int k = 0; k < n; ++k) {
      if (failed[k]) continue;
      real xk[9];
      for (int e = 0; e < 9; ++e) xk[e] = x[e][k];
      r[k] = polar_finish(r[k], xk);
    }
  }
}

}  // namespace tessera::blocks::detail
