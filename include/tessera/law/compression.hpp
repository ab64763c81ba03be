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
// Optional (a cap that softens with crushing; the law then stores u_crush and the flag `crushed`):
// the concept SofteningCompressionLimit below (softening_cap), detected by the law.
//
// softening_cap: the cap falls with the plastic normal closure kappa = state::u_crush (m, the sum
// of the compressive plastic closure increments), linearly to a residual fraction r of f_c,
//     f(kappa) = f_c [r + (1 - r) max(0, 1 - kappa / kappa_u)],   kappa_u = 2 G_c / ((1 - r) f_c),
// so the plastic work above the residual cap, integral (f - r f_c) d kappa, is the compressive
// fracture energy G_c (J/m^2), and a contact crushed in pure compression dissipates G_c + r f_c kappa.
// The form is Lourenco and Rots' composite interface cap (masonry, 1997), which softens the cap with
// its plastic work after the peak (parabolic there, G_fc the area); linear here, so the return onto a
// cap that softens during the step is closed-form as the tension and slip envelopes are:
//     trial t = -k_n (u_n - u_p) > f(kappa):  d = (t - f(kappa)) / (k_n - (1 - r) f_c / kappa_u)
// on the line (kappa + d <= kappa_u), else onto the residual, d = (t - r f_c) / k_n. validate refuses
// a line steeper than the elastic unloading (G_c <= (1 - r)^2 f_c^2 / (2 k_n), a snap-back).
// Unloading and reloading follow k_n from the crushed position and meet the softened cap again.
// scales_shear (opt-in): the shear limit is multiplied by f(kappa) / f_c, so a crushed contact also
// loses that share of its cohesion and friction (at r = 0 it ends with neither).

#include <concepts>
#include <limits>
#include <type_traits>

#include "../core/lanes.hpp"
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

/// A cap f_c that softens linearly with the plastic normal closure u_crush to residual x f_c over
/// the compressive fracture energy G_c (file comment); not the study's law (issue #63).
struct softening_cap {
  /// f_c, G_c, residual, scales_shear
  struct params {
    real f_c = 0;         ///< compressive strength of the uncrushed contact (Pa, > 0, a magnitude)
    real G_c = 0;         ///< compressive fracture energy (J/m^2, > 0): plastic work above the residual cap
    real residual = 0;    ///< residual cap as a fraction of f_c, in [0, 1] (1: plastic_cap)
    bool scales_shear = false;  ///< the shear limit times f(u_crush) / f_c (file comment)
  };
  static constexpr bool bounded = true;                 ///< compression limited by the softening cap
  static constexpr bool softens_with_crushing = true;   ///< the law stores u_crush
  /// Refuses (invalid_input) f_c or G_c not finite and > 0, or residual outside [0, 1], naming it.
  static void validate(const params& p) {
    detail::require_positive(p.f_c, "compressive strength f_c", "Pa");
    detail::require_positive(p.G_c, "compressive fracture energy G_c", "J/m^2");
    detail::require_in_closed_range(p.residual, 0, 1, "residual cap fraction", "(of f_c)", "[0, 1]");
  }
  /// validate(p), then refuses a softening steeper than the elastic unloading at normal stiffness
  /// k_n (Pa/m): G_c must exceed ((1 - residual) f_c)^2 / (2 k_n).
  static void validate_with_stiffness(const params& p, real k_n) {
    validate(p);
    const real drop = (1 - p.residual) * p.f_c, least = drop * drop / (2 * k_n);
    if (!(p.G_c > least))
      throw invalid_input(tessera::detail::concat("contact law: compressive fracture energy too small for the law: G_c = ",
                                                  p.G_c, " J/m^2 must exceed ((1 - residual) f_c)^2/(2 k_n) = ", least,
                                                  " J/m^2 (a softening steeper than the elastic unloading)"));
  }
  [[nodiscard]] static real strength(const params& p) noexcept { return p.f_c; }  ///< f_c (Pa), the uncrushed cap
  /// The residual cap f_c - (1 - residual) f_c (Pa), the least lane_strength returns (exactly).
  [[nodiscard]] static real residual_strength(const params& p) noexcept { return p.f_c - (1 - p.residual) * p.f_c; }
  /// Plastic closure at which the residual is reached: kappa_u = 2 G_c / ((1 - residual) f_c) (m; +inf at residual 1).
  [[nodiscard]] static real crushing_closure(const params& p) noexcept {
    return p.residual < 1 ? 2 * p.G_c / ((1 - p.residual) * p.f_c) : std::numeric_limits<real>::infinity();
  }
  /// The cap f(kappa) (Pa, a magnitude) after the plastic closure kappa (m), T = real or a lanes::pack.
  template <class T>
  [[nodiscard, gnu::always_inline]] static T lane_strength(const params& p, T kappa) noexcept {
    const real drop = (1 - p.residual) * p.f_c, inv_ku = drop / (2 * p.G_c);
    const T u = kappa * inv_ku;  // kappa / kappa_u; f_c exactly at kappa = 0
    return p.f_c - drop * lanes::select(u < real(1), u, lanes::splat<T>(1));
  }
  /// The cap's magnitude (Pa) and the plastic closure (m) after a return from a trial compression
  /// of magnitude t (Pa) > lane_strength(p, kappa) at normal stiffness k_n (Pa/m) (file comment).
  template <class T>
  struct crush_return_result {
    T cap;    ///< |sigma_n| after the return (Pa)
    T kappa;  ///< plastic closure after the return (m)
  };
  /// The return (file comment): on the softening line, else onto the residual; T = real or a pack.
  template <class T>
  [[nodiscard, gnu::always_inline]] static crush_return_result<T> lane_crush_return(const params& p, real k_n, T t,
                                                                                   T kappa) noexcept {
    const real drop = (1 - p.residual) * p.f_c, inv_ku = drop / (2 * p.G_c);
    const T kappa_line = kappa + (t - lane_strength(p, kappa)) / (k_n - drop * inv_ku);
    const T u = kappa_line * inv_ku;
    const T kappa_flat = kappa + (t - (p.f_c - drop)) / k_n;
    const auto on_line = u < real(1);
    return {lanes::select(on_line, p.f_c - drop * u, lanes::splat<T>(p.f_c - drop)),
            lanes::select(on_line, kappa_line, kappa_flat)};
  }
};

/// A CompressionLimit whose cap softens with the plastic closure the law stores (file comment).
template <class C>
concept SofteningCompressionLimit =
    CompressionLimit<C> && C::softens_with_crushing && requires(const typename C::params& p, real x, lanes::pack v) {
      { C::validate_with_stiffness(p, x) } -> std::same_as<void>;
      { C::lane_strength(p, x) } noexcept -> std::same_as<real>;
      { C::residual_strength(p) } noexcept -> std::same_as<real>;
      { C::lane_strength(p, v) } noexcept -> std::same_as<lanes::pack>;
      { C::lane_crush_return(p, x, v, v).cap } -> std::convertible_to<lanes::pack>;
      { p.scales_shear } -> std::convertible_to<bool>;
    };

static_assert(CompressionLimit<elastic_compression>);
static_assert(CompressionLimit<plastic_cap>);
static_assert(SofteningCompressionLimit<softening_cap>);

}  // namespace tessera::law
