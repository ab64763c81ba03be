#pragma once
// Compression policies of law::cohesive_frictional (DESIGN.md §3, study eq. 5: |sigma_compression| <= f_c).
//
// Sign: the normal stress sigma_n is positive in tension, so the compressive limit reads
// sigma_n >= -f_c. Beyond it the contact is perfectly plastic: sigma_n stays at -f_c and the
// further closure is irreversible (the law adds it to its plastic opening u_p and books the work
// as dissipated_compression). Unloading and reloading follow k_n.
//
// Concept CompressionLimit, one requirement per line:
// | expression          | meaning                                                                 |
// |---------------------|-------------------------------------------------------------------------|
// | C::params           | plain struct, SI units                                                  |
// | C::validate(p)      | throws invalid_input naming a bad parameter                             |
// | C::bounded          | constexpr bool: false = no compressive limit, compiled out of update()  |
// | C::strength(p)      | compressive strength f_c > 0 (Pa, a magnitude); +inf when unbounded     |

#include <concepts>
#include <limits>
#include <type_traits>

#include "../core/types.hpp"
#include "detail/validation.hpp"

namespace tessera::law {

template <class C>
concept CompressionLimit = requires(const typename C::params& p) {
  typename C::params;
  { C::validate(p) } -> std::same_as<void>;
  typename std::bool_constant<C::bounded>;  // bounded must be a compile-time constant
  { C::strength(p) } noexcept -> std::convertible_to<real>;
};

/// Linear elastic in compression at any stress (the study's tie: no compression limit).
struct elastic_compression {
  struct params {};
  static constexpr bool bounded = false;  ///< no limit
  static void validate(const params&) {}  ///< Nothing to refuse
  [[nodiscard]] static real strength(const params&) noexcept { return std::numeric_limits<real>::infinity(); }  ///< infinity
};

/// Elastic-perfectly plastic in compression: |sigma_n| <= f_c (the study's beam, f_c = 35 MPa).
struct plastic_cap {
  /// f_c
  struct params {
    real f_c = 0;  ///< compressive strength (Pa, > 0, a magnitude)
  };
  static constexpr bool bounded = true;  ///< compression limited by f_c
  static void validate(const params& p) { detail::require_positive(p.f_c, "compressive strength f_c", "Pa"); }  ///< Refuses (invalid_input) f_c <= 0
  [[nodiscard]] static real strength(const params& p) noexcept { return p.f_c; }  ///< f_c (Pa)
};

static_assert(CompressionLimit<elastic_compression>);
static_assert(CompressionLimit<plastic_cap>);

}  // namespace tessera::law
