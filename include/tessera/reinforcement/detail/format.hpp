#pragma once
// Formatting of points in error messages: "(x, y, z)".

#include <string>

#include "../../core/errors.hpp"
#include "../../core/types.hpp"

namespace tessera::reinforcement::detail {

[[nodiscard]] inline std::string point_string(const vec3& p) {
  return tessera::detail::concat("(", p.x(), ", ", p.y(), ", ", p.z(), ")");
}

}  // namespace tessera::reinforcement::detail
