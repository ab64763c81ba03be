// The definitions of the larger functions that solver/relaxation_options.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../relaxation_options.hpp"

namespace tessera {

TESSERA_INLINE void require_valid_relaxation(const relaxation_options& o) {
  require(std::isfinite(o.reference_force) && o.reference_force > 0, "relaxation: reference force = ",
          o.reference_force, " N must be finite and > 0");
  require(std::isfinite(o.ratio_tolerance) && o.ratio_tolerance > 0, "relaxation: ratio tolerance = ",
          o.ratio_tolerance, " must be finite and > 0");
  require(o.max_steps >= 1, "relaxation: max_steps = ", o.max_steps, " must be >= 1");
  require(o.check_interval >= 1, "relaxation: check_interval = ", o.check_interval, " must be >= 1");
  const auto rule = static_cast<int>(o.velocity_rule);
  require(rule >= 0 && rule <= 2, "relaxation: velocity_rule = ", rule, " is not kinetic (0), fire (1) or adaptive (2)");
  require(std::isfinite(o.adaptive_damping_scale) && o.adaptive_damping_scale > 0 && o.adaptive_damping_scale <= 10,
          "relaxation: adaptive_damping_scale = ", o.adaptive_damping_scale, " must be in (0, 10]");
  require(std::isfinite(o.fire_alpha_start) && o.fire_alpha_start > 0 && o.fire_alpha_start <= 1,
          "relaxation: fire_alpha_start = ", o.fire_alpha_start, " must be in (0, 1]");
  require(std::isfinite(o.fire_alpha_decay) && o.fire_alpha_decay > 0 && o.fire_alpha_decay <= 1,
          "relaxation: fire_alpha_decay = ", o.fire_alpha_decay, " must be in (0, 1]");
  require(o.fire_delay >= 0, "relaxation: fire_delay = ", o.fire_delay, " must be >= 0");
}

}  // namespace tessera
