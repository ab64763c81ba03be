#pragma once
// Analysis of sampled load-displacement curves (any scene, any axis): interpolation, the RMS
// difference of two curves, the slope of a linear branch, load drops (cracks forming) and plateau
// means. Pure functions of the samples; no solver types. The examples' summaries are built from
// these (rc_tie, direct_tension, rc_tie_sensitivity; docs/validation.md says which figure uses which).
//
// | function                          | what it returns                                                  |
// |-----------------------------------|------------------------------------------------------------------|
// | interpolate_curve(u, s, x)        | s at x, linear between samples, clamped at the ends              |
// | rms_curve_difference(...)         | sqrt((1/U) int_0^U (s - s_ref)^2 du), trapezoidal, in s's unit   |
// | curve_error(x, y, xr, yr, scale)  | RMS difference over the common range on 2000 intervals / scale   |
// | running_max(x)                    | a monotone copy of a sampled abscissa                            |
// | band_slope(x, y, end, lo, hi)     | least-squares dy/dx over samples [0, end) with lo <= y <= hi     |
// | load_drop_detector, find_load_drops | local peaks followed by a drop of more than a threshold        |
// | tail_mean(y, from)                | mean of y[from..], e.g. a yield plateau                          |

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "../core/errors.hpp"
#include "../core/types.hpp"

namespace tessera::analysis {

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

/// Curve error of (x, y) against a reference (xr, yr): the RMS ordinate difference over the common
/// abscissa range [0, min(x_end, xr_end)] on 2000 equal intervals (trapezoidal), relative to
/// `scale`:  e = sqrt( (1/U) int_0^U (y - y_ref)^2 dx ) / scale. Abscissae must be ascending
/// (running_max makes them so). 1 when either curve has fewer than two samples or U <= 0.
[[nodiscard]] inline real curve_error(const std::vector<real>& x, const std::vector<real>& y,
                                      const std::vector<real>& xr, const std::vector<real>& yr, real scale) {
  if (x.size() < 2 || xr.size() < 2) return 1;
  const real u_end = std::min(x.back(), xr.back());
  if (u_end <= 0) return 1;
  return rms_curve_difference(x, y, xr, yr, u_end, 2000) / scale;
}

/// A monotone copy of a sampled abscissa (running maximum), so curves sampled during a start-up
/// ramp or small reversals can be interpolated.
[[nodiscard]] inline std::vector<real> running_max(std::vector<real> x) {
  for (std::size_t k = 1; k < x.size(); ++k) x[k] = std::max(x[k], x[k - 1]);
  return x;
}

/// Least-squares slope dy/dx through the samples k < end with lo <= y[k] <= hi, abscissae taken
/// as x[k] / x_divisor (e.g. a length, to fit stress against strain): the linear branch of a
/// curve between two fractions of its first peak, away from the start-up ramp and from pre-peak
/// softening. 0 when fewer than two samples qualify or their abscissae coincide.
[[nodiscard]] inline real band_slope(const std::vector<real>& x, const std::vector<real>& y, std::size_t end, real lo,
                                     real hi, real x_divisor = 1) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  end = std::min({end, x.size(), y.size()});
  for (std::size_t k = 0; k < end; ++k) {
    if (y[k] < lo || y[k] > hi) continue;
    const double xv = x[k] / x_divisor, yv = y[k];
    sx += xv, sy += yv, sxx += xv * xv, sxy += xv * yv, ++n;
  }
  if (n < 2 || n * sxx - sx * sx <= 0) return 0;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/// Mean of y[from], ..., y[size - 1] (a plateau, e.g. the yield force after yielding); the last
/// sample when from is past the end, 0 for an empty y.
[[nodiscard]] inline real tail_mean(const std::vector<real>& y, std::size_t from) {
  if (y.empty()) return 0;
  if (from >= y.size()) return y.back();
  double sum = 0;
  for (std::size_t k = from; k < y.size(); ++k) sum += y[k];
  return sum / static_cast<double>(y.size() - from);
}

/// One local peak of the force followed by a drop (a crack forming).
struct load_drop {
  real peak_force = 0;       ///< N
  real peak_elongation = 0;  ///< m
  real trough_force = 0;     ///< lowest force before the curve rose again (N)
  std::size_t sample = 0;    ///< curve index of the peak
};

/// Streaming detector of load drops: a local peak of the force followed by a drop of more than
/// `threshold` (N) before the force rises by more than `threshold` above the trough again
/// (hysteresis, so noise below the threshold is no drop). Throws invalid_input for a threshold
/// that is not finite and > 0.
class load_drop_detector {
 public:
  explicit load_drop_detector(real threshold) : threshold_(threshold) {  ///< Refuses (invalid_input) a threshold that is not finite and > 0
    require(std::isfinite(threshold) && threshold > 0, "load_drop_detector: threshold = ", threshold,
            " N must be finite and > 0");
  }
  /// Adds sample k = (elongation, force); returns true when it completes a new drop.
  bool push(real elongation, real force) {
    const std::size_t k = count_++;
    if (rising_) {
      if (k == 0 || force >= peak_force_) {
        peak_force_ = force, peak_elongation_ = elongation, peak_sample_ = k;
      } else if (force < peak_force_ - threshold_) {
        drops_.push_back({peak_force_, peak_elongation_, force, peak_sample_});
        rising_ = false;
        return true;
      }
    } else {
      load_drop& d = drops_.back();
      d.trough_force = std::min(d.trough_force, force);
      if (force > d.trough_force + threshold_) {
        rising_ = true;
        peak_force_ = force, peak_elongation_ = elongation, peak_sample_ = k;
      }
    }
    return false;
  }
  [[nodiscard]] const std::vector<load_drop>& drops() const { return drops_; }  ///< The drops found so far

 private:
  real threshold_;
  std::size_t count_ = 0, peak_sample_ = 0;
  bool rising_ = true;
  real peak_force_ = 0, peak_elongation_ = 0;
  std::vector<load_drop> drops_;
};

/// The load drops of samples [0, end) of a curve (load_drop_detector).
[[nodiscard]] inline std::vector<load_drop> find_load_drops(const std::vector<real>& elongation,
                                                            const std::vector<real>& force, real threshold,
                                                            std::size_t end) {
  load_drop_detector d(threshold);
  end = std::min(end, force.size());
  for (std::size_t k = 0; k < end; ++k) d.push(elongation[k], force[k]);
  return d.drops();
}

}  // namespace tessera::analysis
