#pragma once
// Eigenvalues and eigenvectors of a symmetric 3x3 matrix by cyclic Jacobi rotations, for the
// principal moments and axes of a rigid block's inertia tensor (blocks::rigid::build).
//
// Why not Eigen::SelfAdjointEigenSolver<mat3>: rigid::build is an ordinary (non-template) inline
// function, so GCC 12 at -O2 instantiated and compiled Eigen's tridiagonalisation + implicit QR in
// every translation unit including blocks/rigid.hpp, called or not (about 4 s of CPU each, issue
// #40 item 9, notes/h6_compile.md "rigid eigen solver"). A 3x3 Jacobi sweep is a few dozen
// scalar operations and costs nothing to compile.
//
// Method: cyclic sweeps over the pairs (0,1), (0,2), (1,2); each rotation zeroes a(p,q) with the
// smaller of the two angles (Rutishauser's formulas, t = tan(angle), |angle| <= pi/4). An
// off-diagonal entry is negligible, and set to zero without a rotation, once
// |a(p,q)| <= eps sqrt(|a(p,p) a(q,q)|) (Demmel and Veselic's criterion: the eigenvalues of a
// positive definite matrix then keep their relative accuracy) or it is below the smallest normal
// number over eps. Convergence is quadratic: 3-6 sweeps from any symmetric start; the loop stops at
// the first sweep that leaves every off-diagonal entry zero (at most 50 sweeps, never reached).
// Then the eigenvalues are sorted ascending (ties keep Jacobi's order), each of the first two
// eigenvectors is signed so that its entry of largest magnitude (the first such entry on a tie) is
// positive, and the third is flipped if needed so that det[e1 e2 e3] = +1. Only fixed operations in
// a fixed order: the same input gives the same bits on every run and thread.

#include <cmath>
#include <limits>
#include <utility>

#include "../../core/types.hpp"

namespace tessera::blocks::detail {

/// Eigen decomposition a = vectors diag(values) vectors^T of a symmetric 3x3 matrix.
struct symmetric_eigen3 {
  vec3 values = vec3::Zero();             ///< eigenvalues, ascending (units of the matrix)
  mat3 vectors = mat3::Identity();        ///< unit eigenvectors as columns, orthonormal, det = +1
  int sweeps = 0;                         ///< Jacobi sweeps made (diagnostics)
};

/// Cyclic Jacobi eigen solver for a symmetric 3x3 matrix (only the lower triangle of a is read,
/// as Eigen's SelfAdjointEigenSolver does). See the file comment for conventions.
inline symmetric_eigen3 symmetric_eigen_3x3(const mat3& a_in) noexcept {
  constexpr real eps = std::numeric_limits<real>::epsilon();
  constexpr real tiny = std::numeric_limits<real>::min() / std::numeric_limits<real>::epsilon();
  constexpr int max_sweeps = 50;
  // Symmetric working copy from the lower triangle.
  real a[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c <= r; ++c) a[r][c] = a[c][r] = a_in(r, c);
  real v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  constexpr int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};

  symmetric_eigen3 out;
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    if (a[0][1] == 0 && a[0][2] == 0 && a[1][2] == 0) break;
    out.sweeps = sweep + 1;
    for (const auto& pq : pairs) {
      const int p = pq[0];
      const int q = pq[1];
      const real apq = a[p][q];
      if (apq == 0) continue;
      if (std::abs(apq) <= eps * std::sqrt(std::abs(a[p][p] * a[q][q])) || std::abs(apq) <= tiny) {
        a[p][q] = a[q][p] = 0;
        continue;
      }
      // t = tan(angle) of the rotation zeroing a(p,q): the root of t^2 + 2 theta t - 1 = 0 of
      // smaller magnitude, theta = (a_qq - a_pp) / (2 a_pq).
      const real theta = (a[q][q] - a[p][p]) / (2 * apq);
      const real t = (theta >= 0 ? real(1) : real(-1)) / (std::abs(theta) + std::sqrt(theta * theta + 1));
      const real c = 1 / std::sqrt(t * t + 1);
      const real s = t * c;
      const real tau = s / (1 + c);
      a[p][p] -= t * apq;
      a[q][q] += t * apq;
      a[p][q] = a[q][p] = 0;
      const int r = 3 - p - q;  // the third index
      const real arp = a[r][p];
      const real arq = a[r][q];
      a[r][p] = a[p][r] = arp - s * (arq + tau * arp);
      a[r][q] = a[q][r] = arq + s * (arp - tau * arq);
      for (int k = 0; k < 3; ++k) {
        const real vkp = v[k][p];
        const real vkq = v[k][q];
        v[k][p] = vkp - s * (vkq + tau * vkp);
        v[k][q] = vkq + s * (vkp - tau * vkq);
      }
    }
  }

  // Ascending order of the eigenvalues: a 3-element sorting network on the column indices,
  // swapping only when strictly greater (ties keep their order).
  int order[3] = {0, 1, 2};
  const auto sort2 = [&](int i, int j) {
    if (a[order[i]][order[i]] > a[order[j]][order[j]]) std::swap(order[i], order[j]);
  };
  sort2(0, 1);
  sort2(1, 2);
  sort2(0, 1);
  for (int j = 0; j < 3; ++j) {
    out.values[j] = a[order[j]][order[j]];
    for (int k = 0; k < 3; ++k) out.vectors(k, j) = v[k][order[j]];
  }
  // Signs: e1 and e2 with their largest-magnitude entry positive, e3 making the basis right-handed.
  for (int j = 0; j < 2; ++j) {
    int largest = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(out.vectors(k, j)) > std::abs(out.vectors(largest, j))) largest = k;
    if (out.vectors(largest, j) < 0) out.vectors.col(j) = -out.vectors.col(j);
  }
  if (out.vectors.determinant() < 0) out.vectors.col(2) = -out.vectors.col(2);
  return out;
}

}  // namespace tessera::blocks::detail
