// The definitions of the larger functions that analysis/energy.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../energy.hpp"

namespace tessera::analysis {

[[nodiscard]] TESSERA_INLINE energy_shares shares_of(const energy_balance& e) {
  energy_shares s;
  const real supplied = e.initial + e.boundary_work;
  if (!(std::abs(supplied) > 0)) return s;
  s.kinetic = e.kinetic / supplied;
  s.block_elastic = e.block_elastic / supplied;
  s.contact_stored = e.contact_stored / supplied;
  s.contact_dissipated = e.contact_dissipated / supplied;
  s.damping_dissipated = e.damping_dissipated / supplied;
  s.reinforcement_stored = e.reinforcement_stored / supplied;
  s.reinforcement_dissipated = e.reinforcement_dissipated / supplied;
  s.residual = (supplied - e.accounted()) / supplied;
  return s;
}

}  // namespace tessera::analysis
