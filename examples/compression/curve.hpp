#pragma once
// The compression curve's figures (main.cpp): the peak and whether it is one, the secant modulus
// between 10 % and 40 % of the peak, Poisson's ratio at 40 %, from samples of axial strain eps
// (shortening positive), axial stress sigma (compression positive, Pa) and lateral strain
// (expansion positive).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "tessera/core/types.hpp"

namespace tessera::scenes {

struct compression_result {
  std::vector<double> strain, stress, lateral_strain;  ///< the curve (-, Pa, -)
  bool peak = false;            ///< the stress fell to (1 - drop) of its largest value after it
  real peak_stress = 0;         ///< f_c if peak, else the largest stress seen (Pa)
  real peak_strain = 0;         ///< axial strain at the largest stress
  real last_strain = 0;         ///< where the run ended
  real young = std::numeric_limits<real>::quiet_NaN();    ///< secant 10-40 % of the peak (Pa)
  real poisson = std::numeric_limits<real>::quiet_NaN();  ///< lateral expansion / axial shortening at 40 % of the peak
  real lateral_at_peak = 0;     ///< lateral strain at the peak
  real residual_ratio = 0;      ///< last stress / largest stress
  real cracked_area = 0, axial_crack_share = 0;  ///< m^2 of cracked or slipped sub-contacts; share with near-horizontal normals
  real confinement_stress = 0;  ///< axial stress on the specimen when the axial loading began (Pa)
  real quasi_static_index = 0;  ///< end travel in one period of the first axial mode / travel to 40 % of the peak
  real energy_error_rel = 0, added_mass_ratio = 0, dt = 0, runtime_s = 0;
  std::int64_t steps = 0;
  std::string stop_reason;
  std::string damping;  ///< solver::damping_in_force()
};

/// Fills young and poisson from the curve up to the peak: the first samples at or above 10 %
/// and 40 % of the largest stress. NaN where the curve has no such samples.
inline void compression_moduli(compression_result& r) {
  const auto first_at = [&](real level) -> std::ptrdiff_t {
    for (std::size_t i = 0; i < r.stress.size() && r.strain[i] <= r.peak_strain; ++i)
      if (r.stress[i] >= level) return static_cast<std::ptrdiff_t>(i);
    return -1;
  };
  const std::ptrdiff_t lo = first_at(0.1 * r.peak_stress), hi = first_at(0.4 * r.peak_stress);
  if (lo < 0 || hi <= lo) return;
  const auto a = static_cast<std::size_t>(lo), b = static_cast<std::size_t>(hi);
  r.young = (r.stress[b] - r.stress[a]) / (r.strain[b] - r.strain[a]);
  r.poisson = r.strain[b] > 0 ? (r.lateral_strain[b] - r.lateral_strain[0]) / r.strain[b] : r.poisson;
}

}  // namespace tessera::scenes
