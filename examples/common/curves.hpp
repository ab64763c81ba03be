#pragma once
// Curve utilities shared by the example drivers and work-precision benchmarks: interpolation of
// a sampled load-displacement curve and the RMS difference of two curves.

#include <algorithm>
#include <cmath>
#include <vector>

#include "tessera/core/types.hpp"

namespace tessera::scenes {

/// Ordinate of the curve (u, s) at abscissa x by linear interpolation, clamped at the ends.
/// u must be ascending (repeated values allowed).
[[nodiscard]] inline real interpolate_curve(const std::vector<real>& u, const std::vector<real>& s, real x) {
  if (u.empty()) return 0;
  const auto it = std::lower_bound(u.begin(), u.end(), x);
  if (it == u.begin()) return s.front();
  if (it == u.end()) return s.back();
  const auto j = static_cast<std::size_t>(it - u.begin());
  const real t = (x - u[j - 1]) / std::max(u[j] - u[j - 1], real(1e-300));
  return s[j - 1] + t * (s[j] - s[j - 1]);
}

/// RMS difference of two curves over [0, u_end] with the trapezoidal rule on `intervals` equal
/// intervals: sqrt( (1/u_end) int_0^u_end (s - s_ref)^2 du ), in the ordinates' unit.
[[nodiscard]] inline real rms_curve_difference(const std::vector<real>& u, const std::vector<real>& s,
                                               const std::vector<real>& u_ref, const std::vector<real>& s_ref,
                                               real u_end, int intervals) {
  double sum = 0;
  for (int k = 0; k <= intervals; ++k) {
    const real x = u_end * k / intervals;
    const real d = interpolate_curve(u, s, x) - interpolate_curve(u_ref, s_ref, x);
    sum += (k == 0 || k == intervals ? 0.5 : 1.0) * d * d;
  }
  return std::sqrt(sum / intervals);
}

}  // namespace tessera::scenes
