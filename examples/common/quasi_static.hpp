#pragma once
// The example drivers' quasi-static criterion (docs/model.md, "Loading rate"). A run is
// quasi-static when the loaded end moves little while a stress wave crosses the specimen once:
// during one P-wave transit of the mass-scaled specimen,
//     t_transit = L sqrt(rho (1 + added) / E)      (L length, E macro modulus, rho density,
//                                                   added = added-mass ratio of the mass scaling)
// the end moves by v t_transit, and the elastic displacement at the tensile strength is
// u_el = f_T L / E. The drivers refuse q = v t_transit / u_el > quasi_static_limit (2): the end
// would travel twice the whole elastic branch while the specimen is still learning it is loaded.
// The defaults are well inside: the 100-block tie q = 0.16 (0.64 with --quick), the quick prism
// 0.08; `rc_tie --rate 1e6` gives q ~ 3e7 and `rc_tie --dt 1` (mass scaled to a 1 s step) ~ 1e5.

#include <cmath>

#include "tessera/core/errors.hpp"
#include "tessera/core/types.hpp"

namespace tessera::scenes {

inline constexpr real quasi_static_limit = 2.0;

/// q = v t_transit / u_el (see the file comment).
[[nodiscard]] inline real quasi_static_index(real rate, real length, real young, real density, real added_mass_ratio,
                                             real f_t) {
  const real transit = length * std::sqrt(density * (1 + added_mass_ratio) / young);
  return rate * transit / (f_t * length / young);
}

/// Throws invalid_input naming the rate, the index and the largest quasi-static rate.
inline void require_quasi_static(const char* program, real rate, real length, real young, real density,
                                 real added_mass_ratio, real f_t) {
  const real q = quasi_static_index(rate, length, young, density, added_mass_ratio, f_t);
  if (q <= quasi_static_limit) return;
  const real v_max = rate * quasi_static_limit / q;
  throw invalid_input(tessera::detail::concat(
      program, ": loading rate ", rate, " m/s with added mass ", added_mass_ratio, "x is not quasi-static: the end moves ",
      q, " x the elastic displacement at f_T during one wave transit (limit ", quasi_static_limit,
      "); use a rate <= ", v_max, " m/s or a smaller mass-scaled step (--dt)"));
}

}  // namespace tessera::scenes
