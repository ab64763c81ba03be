#pragma once
// Tension policies of law::cohesive_frictional: the tensile strength envelope f_t of a contact as
// its crack opens (reference study eq. 5, DESIGN.md §3 "Contact law").
//
// With the tensile strength f_T (Pa), the fracture energy G_f (J/m^2 = N/m) and the normal
// stiffness k_n (Pa/m) of the law, the study defines
//     eta  = f_T / k_n        opening at the peak (m),
//     zeta = 2 G_f / f_T      opening where the linear envelope reaches zero (m),
// and the envelope as a function of the total normal opening u_n (m, + opens):
//     linear_softening  f_t = f_T (1 - (u_n - eta)/(zeta - eta))   for eta <= u_n <= zeta, 0 beyond
//     power_softening   f_t = f_T (zeta / (zeta - eta + u_n))^alpha  for u_n >= eta
//     no_tension        f_t = 0
// (f_t = f_T for u_n <= eta in the first two).
//
// History variable. A policy evaluates the envelope as a function of the softening opening
//     w = u_n - eta >= 0   (m), the opening travelled along the softening branch past the peak,
// which the law stores per sub-contact (cohesive_frictional::state::u_soft, 0 = never softened), so
// that value-initialised state means a virgin contact and the law can return onto the envelope in
// closed form (see cohesive_frictional.hpp). In these variables
//     linear_softening  f_t(w) = f_T max(0, 1 - w/(zeta - eta))
//     power_softening   f_t(w) = f_T (zeta / (zeta + w))^alpha.
//
// When the contact is broken for good (`exhausted`):
//     linear_softening  when f_t reaches 0, i.e. u_n >= zeta;
//     power_softening   when f_t <= r f_T (r = residual_ratio, default 1e-3), i.e. beyond the cut-off
//                       u_c = zeta r^(-1/alpha) - zeta + eta. The envelope area the cut-off leaves
//                       out is f_T zeta r^((alpha-1)/alpha) / (alpha - 1): 1 % of G_f for alpha = 3;
//     no_tension        at the first tensile trial stress (zero tensile strength).
//
// Energy per unit area of a contact pulled monotonically to separation (`separation_energy`):
//     linear_softening  f_T zeta / 2 = G_f, the whole triangle under the curve (elastic part included);
//     power_softening   f_T^2/(2 k_n) + f_T zeta/(alpha - 1) - tail: the post-peak area alone is
//                       2 G_f/(alpha - 1), exactly G_f for the study's alpha = 3, so the total is
//                       G_f + f_T^2/(2 k_n) - 0.01 G_f with r = 1e-3. (For alpha != 3 the parameter G_f
//                       is therefore not the post-peak area; we keep eq. 5 as the study writes it.)
//
// Concept TensionSoftening, one requirement per line:
// | expression                 | meaning                                                              |
// |----------------------------|----------------------------------------------------------------------|
// | T::params                  | plain struct of the envelope's parameters, SI units                  |
// | T::validate(p, k_n)        | throws invalid_input naming a bad parameter (k_n already checked > 0) |
// | T::peak_strength(p)        | f_T (Pa), the strength of a virgin contact; 0 for no_tension         |
// | T::strength(p, k_n, w)     | f_t(w) >= 0 (Pa) after a softening opening w >= 0 (m); noexcept      |
// | T::exhausted(p, f_t)       | true once the strength f_t (Pa) is spent: broken in tension for good |
// Optional (cohesive_frictional's pack path then also advances softening contacts on packs):
// | T::lane_strength(p, k_n, w)| strength(p, k_n, w) to the bit, lane by lane, for w a real or a      |
// |                            | lanes::pack (core/lanes.hpp)                                         |
// | T::lane_exhausted(p, f_t)  | exhausted(p, f_t) lane by lane: a bool or a lanes::mask              |

#include <algorithm>
#include <cmath>
#include <concepts>
#include <type_traits>

#include "../core/errors.hpp"
#include "../core/lanes.hpp"
#include "../core/types.hpp"
#include "detail/validation.hpp"

namespace tessera::law {

template <class T>
concept TensionSoftening = requires(const typename T::params& p, real k_n, real w, real f_t) {
  typename T::params;
  { T::validate(p, k_n) } -> std::same_as<void>;
  { T::peak_strength(p) } noexcept -> std::convertible_to<real>;
  { T::strength(p, k_n, w) } noexcept -> std::convertible_to<real>;
  { T::exhausted(p, f_t) } noexcept -> std::same_as<bool>;
};

namespace detail {
/// Checks f_T and G_f and that the envelope has a softening branch: zeta > eta, i.e.
/// G_f > f_T^2/(2 k_n) (otherwise the elastic branch alone would store more than G_f).
inline void validate_envelope(real f_T, real G_f, real k_n) {
  require_positive(f_T, "tensile strength f_T", "Pa");
  require_positive(G_f, "fracture energy G_f", "N/m");
  const real eta = f_T / k_n;
  const real zeta = 2 * G_f / f_T;
  if (!(zeta > eta))
    throw invalid_input(tessera::detail::concat(
        "contact law: fracture energy too small for the law: G_f = ", G_f, " N/m gives zeta = 2 G_f/f_T = ", zeta,
        " m <= eta = f_T/k_n = ", eta, " m (f_T = ", f_T, " Pa, k_n = ", k_n, " Pa/m); G_f must exceed f_T^2/(2 k_n) = ",
        f_T * f_T / (2 * k_n), " N/m"));
}
}  // namespace detail

/// Linear tension softening (study eq. 5, first form): f_t falls linearly from f_T at u_n = eta to
/// 0 at u_n = zeta = 2 G_f/f_T, where the contact breaks; area under the whole curve = G_f.
struct linear_softening {
  /// f_T and G_f
  struct params {
    real f_T = 0;  ///< tensile strength (Pa)
    real G_f = 0;  ///< mode-I fracture energy (J/m^2 = N/m)
  };
  static void validate(const params& p, real k_n) { detail::validate_envelope(p.f_T, p.G_f, k_n); }  ///< Refuses (invalid_input) f_T, G_f <= 0 or an envelope whose softening length is not positive at this k_n
  [[nodiscard]] static real peak_strength(const params& p) noexcept { return p.f_T; }  ///< f_T (Pa)
  /// strength and exhausted for T = real or a lanes::pack (std::max(0, v) is v > 0 ? v : 0).
  template <class T>
  [[nodiscard, gnu::always_inline]] static T lane_strength(const params& p, real k_n, T w) noexcept {
    const real softening_length = 2 * p.G_f / p.f_T - p.f_T / k_n;  // zeta - eta (m)
    const T v = 1 - w / softening_length;
    return p.f_T * lanes::select(real(0) < v, v, T{});
  }
  template <class T>
  [[nodiscard, gnu::always_inline]] static auto lane_exhausted(const params&, T f_t) noexcept {  ///< True where the envelope is spent (f_t = 0)
    return f_t <= real(0);
  }
  /// f_t(w) = f_T max(0, 1 - w/(zeta - eta)) (Pa), w = u_n - eta (m).
  [[nodiscard]] static real strength(const params& p, real k_n, real w) noexcept { return lane_strength(p, k_n, w); }
  [[nodiscard]] static bool exhausted(const params& p, real f_t) noexcept { return lane_exhausted(p, f_t); }  ///< True when the envelope is spent (f_t = 0)
  /// Total opening at which the contact breaks: zeta (m).
  [[nodiscard]] static real cutoff_opening(const params& p, real /*k_n*/) noexcept { return 2 * p.G_f / p.f_T; }
  /// Energy dissipated per unit area by a contact pulled monotonically to separation (J/m^2): G_f.
  [[nodiscard]] static real separation_energy(const params& p, real /*k_n*/) noexcept { return p.G_f; }
};

/// Power-law (polynomial) tension softening (study eq. 5, second form):
/// f_t = f_T (zeta/(zeta - eta + u_n))^alpha for u_n >= eta, with a documented cut-off u_c where
/// the envelope has dropped to residual_ratio f_T (see the file comment). alpha = 3 (the study's
/// value) is evaluated without std::pow.
struct power_softening {
  /// f_T, G_f, alpha, residual ratio
  struct params {
    real f_T = 0;                ///< tensile strength (Pa)
    real G_f = 0;                ///< fracture energy (J/m^2); post-peak area = 2 G_f/(alpha-1)
    real alpha = 3;              ///< softening exponent (-), > 1
    real residual_ratio = 1e-3;  ///< r in (0, 1): broken once f_t <= r f_T
  };
  static void validate(const params& p, real k_n) {  ///< Refuses (invalid_input) f_T, G_f <= 0, alpha <= 1 or an envelope impossible at this k_n
    detail::validate_envelope(p.f_T, p.G_f, k_n);
    if (!(p.alpha > 1) || !std::isfinite(p.alpha))
      throw invalid_input(tessera::detail::concat("contact law: power softening exponent alpha = ", p.alpha,
                                                  " must be finite and > 1 (finite fracture energy)"));
    if (!(p.residual_ratio > 0 && p.residual_ratio < 1))
      throw invalid_input(tessera::detail::concat("contact law: power softening residual_ratio = ", p.residual_ratio,
                                                  " must be in (0, 1)"));
  }
  [[nodiscard]] static real peak_strength(const params& p) noexcept { return p.f_T; }  ///< f_T (Pa)
  /// strength and exhausted for T = real or a lanes::pack (std::pow lane by lane).
  template <class T>
  [[nodiscard, gnu::always_inline]] static T lane_strength(const params& p, real /*k_n*/, T w) noexcept {
    const real zeta = 2 * p.G_f / p.f_T;
    const T ratio = zeta / (zeta + w);
    if (p.alpha == 3) return p.f_T * ratio * ratio * ratio;
    if constexpr (std::is_same_v<T, real>) {
      return p.f_T * std::pow(ratio, p.alpha);
    } else {
      T power;
      for (int k = 0; k < lanes::width; ++k) power[k] = std::pow(ratio[k], p.alpha);
      return p.f_T * power;
    }
  }
  template <class T>
  [[nodiscard, gnu::always_inline]] static auto lane_exhausted(const params& p, T f_t) noexcept {  ///< True where the envelope is spent
    return f_t <= p.residual_ratio * p.f_T;
  }
  /// f_t(w) = f_T (zeta/(zeta + w))^alpha (Pa), w = u_n - eta (m).
  [[nodiscard]] static real strength(const params& p, real k_n, real w) noexcept { return lane_strength(p, k_n, w); }
  [[nodiscard]] static bool exhausted(const params& p, real f_t) noexcept { return lane_exhausted(p, f_t); }  ///< True when the envelope is spent
  /// Total opening at which the contact breaks: u_c = zeta r^(-1/alpha) - zeta + eta (m).
  [[nodiscard]] static real cutoff_opening(const params& p, real k_n) noexcept {
    const real zeta = 2 * p.G_f / p.f_T;
    return zeta * std::pow(p.residual_ratio, -1 / p.alpha) - zeta + p.f_T / k_n;
  }
  /// Envelope area beyond the cut-off, which a broken contact never dissipates (J/m^2):
  /// f_T zeta r^((alpha-1)/alpha)/(alpha-1).
  [[nodiscard]] static real cutoff_tail_energy(const params& p) noexcept {
    const real zeta = 2 * p.G_f / p.f_T;
    return p.f_T * zeta * std::pow(p.residual_ratio, (p.alpha - 1) / p.alpha) / (p.alpha - 1);
  }
  /// Energy dissipated per unit area by a contact pulled monotonically to separation (J/m^2):
  /// f_T^2/(2 k_n) + f_T zeta/(alpha-1) - cutoff_tail_energy (= G_f + f_T^2/(2 k_n) - 0.01 G_f for the
  /// study's alpha = 3, r = 1e-3).
  [[nodiscard]] static real separation_energy(const params& p, real k_n) noexcept {
    const real zeta = 2 * p.G_f / p.f_T;
    return p.f_T * p.f_T / (2 * k_n) + p.f_T * zeta / (p.alpha - 1) - cutoff_tail_energy(p);
  }
};

/// No tensile strength (a dry joint): the first tensile trial stress breaks the contact, which then
/// also loses its cohesion to the residual value (as a Coulomb joint with a zero tension cut-off).
struct no_tension {
  struct params {};
  static void validate(const params&, real /*k_n*/) {}  ///< Nothing to refuse
  [[nodiscard]] static real peak_strength(const params&) noexcept { return 0; }  ///< 0
  [[nodiscard]] static real strength(const params&, real /*k_n*/, real /*w*/) noexcept { return 0; }  ///< 0: no tension
  [[nodiscard]] static bool exhausted(const params&, real /*f_t*/) noexcept { return true; }  ///< Always spent
  [[nodiscard]] static real cutoff_opening(const params&, real /*k_n*/) noexcept { return 0; }  ///< 0
  [[nodiscard]] static real separation_energy(const params&, real /*k_n*/) noexcept { return 0; }  ///< 0
};

static_assert(TensionSoftening<linear_softening>);
static_assert(TensionSoftening<power_softening>);
static_assert(TensionSoftening<no_tension>);

}  // namespace tessera::law
