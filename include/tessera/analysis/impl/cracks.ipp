// The definitions of the larger functions that analysis/cracks.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../cracks.hpp"

namespace tessera::analysis {

[[nodiscard]] TESSERA_INLINE std::vector<real> crack_sites(std::vector<real> positions, real spacing) {
  require(std::isfinite(spacing) && spacing > 0, "crack_sites: spacing = ", spacing, " m must be finite and > 0");
  std::sort(positions.begin(), positions.end());
  std::vector<real> sites;
  real sum = 0;
  int count = 0;
  for (std::size_t k = 0; k < positions.size(); ++k) {
    if (count > 0 && positions[k] - positions[k - 1] >= spacing) {
      sites.push_back(sum / count);
      sum = 0;
      count = 0;
    }
    sum += positions[k];
    ++count;
  }
  if (count > 0) sites.push_back(sum / count);
  return sites;
}

}  // namespace tessera::analysis
