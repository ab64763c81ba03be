#pragma once
// Shear policy of law::cohesive_frictional whose cohesion AND friction soften with the plastic slip
// (DESIGN.md §12, the third family): coulomb_slip_softening. The Coulomb limit of shear.hpp,
//
//     tau_max(sigma_n, s) = max(0, c(s) - sigma_n tan phi(s))          sigma_n in Pa, + tension
//     c(s)       = c_res       + (c_0       - c_res)       g(s)
//     tan phi(s) = tan phi_res + (tan phi_0 - tan phi_res) g(s)
//     g(s)       = max(0, 1 - s / s_u),    s_u = 2 G_II / (c_0 - c_res)
//
// with s = state::u_slip (m) the accumulated plastic slip of the sub-contact (the sum of the
// magnitudes of its plastic slip increments). So a contact is elastic up to c_0 - sigma_n tan phi_0,
// then both parts of its strength fall linearly with plastic slip and reach the residual
// c_res - sigma_n tan phi_res at s = s_u, where they stay. Broken in tension: the residual values
// at once (g = 0), as coulomb_residual (DESIGN.md §3: a broken joint keeps residual values).
// Energy: in pure shear at zero normal stress the plastic work above the residual is
//     integral (tau - c_res) ds = (c_0 - c_res) s_u / 2 = G_II,
// so G_II is the mode-II fracture energy (J/m^2) of the interface; in tau against plastic slip it is
// the triangle above c_res (the elastic part is stored, not dissipated). At a fixed compression
// sigma_n < 0 the triangle is [(c_0 - c_res) - sigma_n (tan phi_0 - tan phi_res)] s_u / 2: the energy
// grows with the confinement, as the mode-II energy measured on joints does.
//
// Why this form (peers read before choosing). Lourenco and Rots' composite interface (masonry,
// 1997) softens c exponentially with the plastic shear work measure, c = c_0 exp(-c_0 kappa/G_II),
// and ties tan phi to the same damage, tan phi = tan phi_0 + (tan phi_r - tan phi_0)(c_0 - c)/c_0;
// 3DEC/UDEC's continuously-yielding joint degrades the mobilised friction angle with the plastic
// shear displacement; the LDPM facet law of Cusatis softens an effective stress of opening and slip
// (mode-I and mode-II energies), with the shear boundary widening with compression. We keep the
// Lourenco-Rots structure (one damage g for cohesion and friction, the slip scale set by G_II at
// zero normal stress, friction going to a residual angle as in 3DEC) with a LINEAR g: the return
// onto a limit that softens during the step is then closed-form (below), as tension.hpp's linear
// envelope; the residual values are reached exactly at a finite slip (the study's c_res, phi_res);
// and the cost per sub-contact-step stays that of a Coulomb limit (no exp in the packed path).
// Tension is not coupled: the tensile strength and its softening stay those of the Tension policy.
//
// Return onto the limit (slip_return). Trial |tau_trial| = t > tau_max(sigma_n, s): the plastic
// slip increment d solves t - k_s d = tau_max(sigma_n, s + d) (radial return, the stress direction
// kept). On the softening line, with R = c_res - sigma_n tan phi_res (the residual limit) and
// H = (c_0 - c_res) - sigma_n (tan phi_0 - tan phi_res) (its drop over s_u):
//     d = (t - R - H g(s)) / (k_s - H / s_u),
// valid while s + d <= s_u, the limit stays >= 0 and k_s > H / s_u. Otherwise on the flat part
// (the residual, or zero strength in tension): d = (t - max(0, R)) / k_s, stress max(0, R); where the
// line is steeper than the elastic unloading (k_s <= H/s_u: strong compression, a local snap-back)
// the slip jumps to at least s_u (the stress drops to the residual in one step). validate refuses a
// snap-back at zero normal stress: G_II > (c_0 - c_res)^2 / (2 k_s).
//
// Concept SlipSofteningShearLimit (optional to ShearLimit; cohesive_frictional detects it):
// | expression                                 | meaning                                             |
// |--------------------------------------------|-----------------------------------------------------|
// | S::softens_with_slip                       | constexpr bool, true: the law stores u_slip         |
// | S::validate_with_stiffness(p, k_s)         | throws invalid_input naming a bad parameter         |
// | S::slip_strength(p, sigma_n, flags, s)     | tau_max (Pa) after the plastic slip s (m)           |
// | S::lane_slip_strength(p, sigma_n, broken,s)| the same lane by lane (T real or lanes::pack)       |
// | S::lane_slip_return(p, k_s, sigma_n,       | {tau, slip}: the stress magnitude on the limit and  |
// |   broken, s, t)                            | the new slip after a trial of magnitude t > tau_max |

#include <cmath>
#include <concepts>

#include "../core/lanes.hpp"
#include "../core/types.hpp"
#include "concepts.hpp"
#include "detail/validation.hpp"
#include "lane_masks.hpp"
#include "shear.hpp"

namespace tessera::law {

/// Coulomb limit whose cohesion and friction soften linearly with the plastic slip u_slip, from
/// (c_0, phi_0) to (c_res, phi_res) over s_u = 2 G_II / (c_0 - c_res) (file comment).
struct coulomb_slip_softening {
  static constexpr bool couples_tension = false;   ///< the tensile state does not enter (beyond broken: residual)
  static constexpr bool softens_with_slip = true;  ///< the law stores the plastic slip u_slip
  /// c_0, phi_0, c_res, phi_res, G_II
  struct params {
    real c_0 = 0;              ///< initial cohesion (Pa, > c_res)
    friction_angle phi_0{};    ///< initial friction angle, [0, 90) deg
    real c_res = 0;            ///< residual cohesion (Pa, in [0, c_0))
    friction_angle phi_res{};  ///< residual friction angle, [0, phi_0] deg
    real G_II = 0;             ///< mode-II fracture energy (J/m^2): plastic work above c_res in pure shear at sigma_n = 0
  };
  /// Refuses (invalid_input) a negative or non-finite cohesion, c_res outside [0, c_0), an angle out of
  /// range, phi_res > phi_0, or G_II not finite and > 0, naming it.
  static void validate(const params& p) {
    if (!(p.c_0 > 0) || !std::isfinite(p.c_0))
      throw invalid_input(tessera::detail::concat("contact law: cohesion c_0 = ", p.c_0, " Pa must be finite and > 0"));
    if (!(p.c_res >= 0 && p.c_res < p.c_0))
      throw invalid_input(tessera::detail::concat("contact law: residual cohesion c_res = ", p.c_res,
                                                  " Pa must be in [0, c_0 = ", p.c_0,
                                                  " Pa) for slip softening (coulomb_residual has none)"));
    detail::require_friction_angle(p.phi_0, "phi_0");
    detail::require_friction_angle(p.phi_res, "phi_res");
    if (!(p.phi_res.radians() <= p.phi_0.radians()))
      throw invalid_input(tessera::detail::concat("contact law: residual friction angle phi_res = ", p.phi_res.degrees(),
                                                  " deg must not exceed phi_0 = ", p.phi_0.degrees(),
                                                  " deg (friction softens with slip)"));
    detail::require_positive(p.G_II, "mode-II fracture energy G_II", "J/m^2");
  }
  /// validate(p), then refuses a softening line steeper than the elastic unloading at zero normal
  /// stress (a local snap-back): G_II must exceed (c_0 - c_res)^2 / (2 k_s) (k_s in Pa/m).
  static void validate_with_stiffness(const params& p, real k_s) {
    validate(p);
    const real drop = p.c_0 - p.c_res;
    if (!(p.G_II > drop * drop / (2 * k_s)))
      throw invalid_input(tessera::detail::concat(
          "contact law: mode-II fracture energy too small for the law: G_II = ", p.G_II, " J/m^2 gives s_u = ",
          2 * p.G_II / drop, " m, a softening steeper than the elastic unloading (c_0 - c_res)/k_s = ", drop / k_s,
          " m; G_II must exceed (c_0 - c_res)^2/(2 k_s) = ", drop * drop / (2 * k_s), " J/m^2"));
  }
  /// Plastic slip at which the residual is reached: s_u = 2 G_II / (c_0 - c_res) (m).
  [[nodiscard]] static real softening_slip(const params& p) noexcept { return 2 * p.G_II / (p.c_0 - p.c_res); }

  /// slip_strength lane by lane (T = real or a lanes::pack, M its mask): tau_max (Pa) at sigma_n (Pa,
  /// + tension) after the plastic slip s (m); broken (in tension): the residual limit.
  template <class T, class M>
  [[nodiscard, gnu::always_inline]] static T lane_slip_strength(const params& p, T sigma_n, M broken, T s) noexcept {
    const real inv_su = (p.c_0 - p.c_res) / (2 * p.G_II);
    const T v = 1 - s * inv_su;
    const T g = detail::mask_select(broken, T{}, lanes::select(v > real(0), v, T{}));
    const T c = p.c_res + (p.c_0 - p.c_res) * g;
    const T tan_phi = p.phi_res.tan() + (p.phi_0.tan() - p.phi_res.tan()) * g;
    return detail::coulomb_line(c, tan_phi, sigma_n);
  }
  /// tau_max (Pa) at sigma_n (Pa, + tension) of a contact in damage state `flags` after the plastic slip s (m).
  [[nodiscard]] static real slip_strength(const params& p, real sigma_n, contact_status flags, real s) noexcept {
    return lane_slip_strength(p, sigma_n, has(flags, contact_status::broken_tension), s);
  }
  /// The ShearLimit strength: that of a contact that has not slipped yet (s = 0), residual when broken.
  [[nodiscard]] static real strength(const params& p, real sigma_n, contact_status flags,
                                     real /*tensile_fraction*/ = 1) noexcept {
    return slip_strength(p, sigma_n, flags, 0);
  }
  /// strength(p, sigma_n, flags) lane by lane (the flags as masks; `slipped` is ignored: the slip
  /// itself, not the flag, softens this limit).
  template <class T, class M>
  [[nodiscard, gnu::always_inline]] static T lane_strength(const params& p, T sigma_n, M /*slipped*/, M broken,
                                                          T /*tensile_fraction*/) noexcept {
    return lane_slip_strength(p, sigma_n, broken, T{});
  }

  /// The stress magnitude on the limit and the plastic slip after the return (file comment).
  template <class T>
  struct slip_return_result {
    T tau;   ///< |tau| after the return (Pa)
    T slip;  ///< accumulated plastic slip after the return (m)
  };
  /// Return of a trial of magnitude t (Pa) beyond tau_max(sigma_n, s) at shear stiffness k_s (Pa/m):
  /// closed form on the softening line, else on the flat part (file comment). T = real or a pack.
  /// `scale` (in [0, 1], default 1) multiplies the whole limit (the law's softening_cap with scales_shear).
  template <class T, class M>
  [[nodiscard, gnu::always_inline]] static slip_return_result<T> lane_slip_return(const params& p, real k_s, T sigma_n,
                                                                                 M broken, T s, T t,
                                                                                 T scale = lanes::splat<T>(1)) noexcept {
    using detail::mask_not;
    using detail::mask_select;
    const real drop_c = p.c_0 - p.c_res, drop_tan = p.phi_0.tan() - p.phi_res.tan();
    const real s_u = 2 * p.G_II / drop_c, inv_su = drop_c / (2 * p.G_II);
    const T R = scale * (p.c_res - sigma_n * p.phi_res.tan());  // residual limit (before the clamp at 0)
    const T H = scale * (drop_c - sigma_n * drop_tan);          // its drop over s_u
    const T slope = k_s - H * inv_su;                  // k_s - H/s_u
    const T v = 1 - s * inv_su;
    const T line_now = R + H * lanes::select(v > real(0), v, T{});
    const T d_line = (t - line_now) / slope;
    const T s_line = s + d_line;
    const T tau_line = R + H * (1 - s_line * inv_su);
    const M on_line = mask_not(broken) & (s < s_u) & (slope > real(0)) & mask_not(s_line > s_u) &
                      mask_not(tau_line < real(0));
    const T flat = lanes::select(R > real(0), R, T{});
    const T excess = t - flat;
    T s_flat = s + lanes::select(excess > real(0), excess, T{}) * (1 / k_s);
    const M snap_back = mask_not(broken) & mask_not(slope > real(0)) & (s_flat < s_u);
    s_flat = mask_select(snap_back, lanes::splat<T>(s_u), s_flat);
    return {mask_select(on_line, tau_line, flat), mask_select(on_line, s_line, s_flat)};
  }
};

/// A ShearLimit whose strength softens with the plastic slip the law stores (file comment).
template <class S>
concept SlipSofteningShearLimit =
    ShearLimit<S> && S::softens_with_slip &&
    requires(const typename S::params& p, real x, contact_status flags, bool b, lanes::pack v, lanes::mask m) {
      { S::validate_with_stiffness(p, x) } -> std::same_as<void>;
      { S::slip_strength(p, x, flags, x) } noexcept -> std::convertible_to<real>;
      { S::lane_slip_strength(p, x, b, x) } noexcept -> std::same_as<real>;
      { S::lane_slip_strength(p, v, m, v) } noexcept -> std::same_as<lanes::pack>;
      { S::lane_slip_return(p, x, v, m, v, v).tau } -> std::convertible_to<lanes::pack>;
    };

static_assert(ShearLimit<coulomb_slip_softening> && PackedShearLimit<coulomb_slip_softening>);
static_assert(SlipSofteningShearLimit<coulomb_slip_softening>);

}  // namespace tessera::law
