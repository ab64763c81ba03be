#pragma once
// Rotation factor R of the polar decomposition F = R U (R proper orthogonal, U symmetric
// positive definite) by Higham's Newton iteration X <- (X + X^-T) / 2, warm-started from the
// previous rotation: with X0 = R_prev^T F the iteration starts next to its limit (the rotation
// increment of one step is tiny), so one or two iterations reach round-off. Converges
// quadratically from any non-singular start; for the 90-degree jump of a test from the identity,
// X0 is already orthogonal and the first iterate is exact.

#include <cmath>

#include "../../core/types.hpp"

namespace tessera::blocks::detail {

/// Orthogonal polar factor of f, given a previous estimate r_prev (rotation). Returns r_prev when
/// f is singular or inverted (det <= 0), which only happens in a run that is already unstable.
[[nodiscard]] inline mat3 polar_rotation(const mat3& f, const mat3& r_prev) noexcept {
  mat3 x = r_prev.transpose() * f;
  for (int it = 0; it < 12; ++it) {
    const real det = x.determinant();
    if (!(det > 0)) return r_prev;
    // X^-T = cofactor(X) / det
    mat3 cof;
    cof(0, 0) = x(1, 1) * x(2, 2) - x(1, 2) * x(2, 1);
    cof(0, 1) = x(1, 2) * x(2, 0) - x(1, 0) * x(2, 2);
    cof(0, 2) = x(1, 0) * x(2, 1) - x(1, 1) * x(2, 0);
    cof(1, 0) = x(0, 2) * x(2, 1) - x(0, 1) * x(2, 2);
    cof(1, 1) = x(0, 0) * x(2, 2) - x(0, 2) * x(2, 0);
    cof(1, 2) = x(0, 1) * x(2, 0) - x(0, 0) * x(2, 1);
    cof(2, 0) = x(0, 1) * x(1, 2) - x(0, 2) * x(1, 1);
    cof(2, 1) = x(0, 2) * x(1, 0) - x(0, 0) * x(1, 2);
    cof(2, 2) = x(0, 0) * x(1, 1) - x(0, 1) * x(1, 0);
    const mat3 next = 0.5 * (x + cof / det);
    const real change = (next - x).cwiseAbs().maxCoeff();
    x = next;
    if (change < 1e-15) break;
  }
  return r_prev * x;
}

}  // namespace tessera::blocks::detail
