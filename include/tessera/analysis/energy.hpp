#pragma once
// Summaries of a run's energy bookkeeping (solver/energy.hpp): where the supports' work went, and
// a dissipation checked against its closed-form value (a crack pulled to separation dissipates
// the law's separation energy per unit area: G_f for linear softening).

#include <cmath>
#include <limits>

#include "../core/separate_compilation.hpp"
#include "../core/types.hpp"
#include "../solver/energy.hpp"

namespace tessera::analysis {

/// A dissipated energy against its expected value.
struct dissipation_check {
  real dissipated = 0;  ///< J
  real expected = 0;    ///< energy per unit area x area (J)
  /// (dissipated - expected) / expected; NaN when nothing was expected (area 0: e.g. no crack
  /// opened), so a summary can say "none" instead of a figure.
  real error_rel = std::numeric_limits<real>::quiet_NaN();
  [[nodiscard]] bool defined() const { return std::isfinite(error_rel); }  ///< False when there was nothing to compare (error_rel not finite)
};

/// `dissipated` (J) against energy_per_area (J/m^2) x area (m^2).
[[nodiscard]] inline dissipation_check check_dissipation(real dissipated, real energy_per_area, real area) {
  dissipation_check c;
  c.dissipated = dissipated;
  c.expected = energy_per_area * area;
  if (c.expected > 0) c.error_rel = (dissipated - c.expected) / c.expected;
  return c;
}

/// The supplied energy (initial + boundary work) split into the terms that hold it, as fractions
/// of the supplied energy (all 0 when nothing was supplied); `residual` is the balance error with
/// its sign (supplied - accounted) / supplied.
struct energy_shares {
  /** fractions of the supplied energy (-), named by the term */ /**@{*/ real kinetic = 0, block_elastic = 0,
       contact_stored = 0, contact_dissipated = 0, damping_dissipated = 0, reinforcement_stored = 0,
       reinforcement_dissipated = 0, residual = 0; /**@}*/
};
[[nodiscard]] TESSERA_INLINE energy_shares shares_of(const energy_balance& e);

}  // namespace tessera::analysis

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/energy.ipp"
#endif
