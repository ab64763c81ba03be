// The definitions of the larger functions that blocks/detail/symmetric_eigen3.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../symmetric_eigen3.hpp"

namespace tessera::blocks::detail {

TESSERA_INLINE symmetric_eigen3 symmetric_eigen_3x3(const mat3& a_in) noexcept {
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
