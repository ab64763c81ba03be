// The definitions of the larger functions that solver/options.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../options.hpp"

namespace tessera {
namespace detail {

TESSERA_INLINE void require_valid_options(const solver_options& options, bool rigid_blocks) {
  require(options.safety > 0 && options.safety <= 1, "solver: safety factor = ", options.safety,
          " must lie in (0, 1]");
  require_non_negative(options.dt, "solver: user time step dt (s)");
  require_non_negative(options.mass_scaling_dt, "solver: mass-scaling target time step (s)");
  require(std::isfinite(options.mass_scaling_ratio) && options.mass_scaling_ratio >= 0,
          "solver: mass-scaling added-mass ratio = ", options.mass_scaling_ratio, " must be finite and >= 0");
  require(options.mass_scaling_ratio == 0 || options.mass_scaling_dt == 0,
          "solver: give a mass-scaling time step (", options.mass_scaling_dt, " s) or an added-mass ratio (",
          options.mass_scaling_ratio, "), not both");
  require(options.mass_scaling_ratio == 0 || !rigid_blocks, "solver: an added-mass ratio (",
          options.mass_scaling_ratio, ") is for deformable blocks; give rigid blocks a mass-scaling time step");
  require(options.check_interval >= 1, "solver: check_interval = ", options.check_interval, " must be >= 1");
}

}  // namespace detail
}  // namespace tessera
