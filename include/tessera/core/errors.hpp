#pragma once
// Exceptions thrown by tessera. Every message names the offending entity, its value and
// what was expected, e.g. "contact law: tensile strength f_t = -2 Pa must be > 0".

#include <sstream>
#include <stdexcept>
#include <string>
#include <limits>
#include <utility>

namespace tessera {

/// Base of every tessera exception.
class error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
/// Bad user input detected while a scene is built (parameters, geometry, seeds, bars...).
class invalid_input : public error {
 public:
  using error::error;
};
/// A geometric construction failed (degenerate or non-convex polyhedron, unmatched face...).
class geometry_error : public error {
 public:
  using error::error;
};
/// A file could not be read, parsed or written.
class io_error : public error {
 public:
  using error::error;
};
/// A run blew up (non-finite values, energy growth); the message names the worst entity
/// and the likely cause.
class numerical_instability : public error {
 public:
  using error::error;
};

namespace detail {
/// Concatenates anything streamable into one message string.
template <class... Args>
[[nodiscard]] std::string concat(Args&&... args) {
  std::ostringstream os;
  os.precision(10);
  (os << ... << std::forward<Args>(args));
  return os.str();
}
}  // namespace detail

/// Throws `Exception` with the concatenated message when `condition` is false.
template <class Exception = invalid_input, class... Args>
void require(bool condition, Args&&... message) {
  if (!condition) throw Exception(detail::concat(std::forward<Args>(message)...));
}

/// Throws invalid_input unless `value` is finite and > 0: "<what> = <value> must be finite and > 0".
inline void require_positive(double value, const char* what) {
  if (!(value > 0.0) || value == std::numeric_limits<double>::infinity())
    throw invalid_input(detail::concat(what, " = ", value, " must be finite and > 0"));
}
/// Throws invalid_input unless `value` is finite and >= 0.
inline void require_non_negative(double value, const char* what) {
  if (!(value >= 0.0) || value == std::numeric_limits<double>::infinity())
    throw invalid_input(detail::concat(what, " = ", value, " must be finite and >= 0"));
}

}  // namespace tessera
