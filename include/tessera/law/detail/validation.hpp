#pragma once
// Parameter checks shared by the contact-law policies. Every message starts with "contact law:",
// names the parameter in the field's words and symbol, gives its value and unit, and says what
// was expected, e.g. "contact law: normal stiffness k_n = -1 Pa/m must be finite and > 0".

#include <cmath>

#include "../../core/errors.hpp"
#include "../../core/types.hpp"

namespace tessera::law::detail {

/// Throws invalid_input unless `value` is finite and > 0.
inline void require_positive(real value, const char* name, const char* unit) {
  if (!(value > 0) || !std::isfinite(value))
    throw invalid_input(tessera::detail::concat("contact law: ", name, " = ", value, " ", unit,
                                                " must be finite and > 0"));
}

/// Throws invalid_input unless lo <= value <= hi (both bounds inclusive; NaN fails).
inline void require_in_closed_range(real value, real lo, real hi, const char* name, const char* unit,
                                    const char* range_text) {
  if (!(value >= lo && value <= hi))
    throw invalid_input(tessera::detail::concat("contact law: ", name, " = ", value, " ", unit, " must be in ",
                                                range_text));
}

}  // namespace tessera::law::detail
