#pragma once
// Shear policies of law::cohesive_frictional: the Coulomb limit on the magnitude of the shear
// stress vector (DESIGN.md §3 "Contact law", study eq. 6).
//
//     tau_max = max(0, c - sigma_n tan(phi))      sigma_n in Pa, + tension
//
// so compression raises the limit and tension lowers it, never below zero. The policy returns
// tau_max for the contact's current damage state; the law applies it: while |tau_trial| <= tau_max
// the shear response is elastic, and at the first exceedance the law marks the contact `slipped`,
// asks the policy again (now with the slipped flag) and scales tau back onto that limit.
//
// Two policies:
//   coulomb_residual  the study's law as DESIGN.md §3 states it: the cohesion stays c_0 while the
//                     contact softens in tension and drops to c_res only once it is broken.
//   coulomb_coupled   the cohesion softens with the tensile strength, c = c_res + (c_0 - c_res)
//                     f_t/f_T (one scalar damage for both, as in damage-coupled interface models).
//                     Not the DESIGN.md default: opt-in, see docs/model.md "Cohesion and tensile
//                     damage" for why it exists (a softening inclined face of a tortuous crack
//                     otherwise keeps carrying 2 f_T of cohesion, which lifts the prism's peak).
//
// Concept ShearLimit, one requirement per line:
// | expression                        | meaning                                                        |
// |-----------------------------------|----------------------------------------------------------------|
// | S::params                         | plain struct, SI units, angles as friction_angle               |
// | S::validate(p)                    | throws invalid_input naming a bad parameter                    |
// | S::couples_tension                | constexpr bool: strength depends on the tensile damage         |
// | S::strength(p, sigma_n, flags, r) | tau_max >= 0 (Pa) at normal stress sigma_n (Pa, + tension) for  |
// |                                   | a contact in damage state `flags` (contact_status) whose        |
// |                                   | tensile strength is the fraction r = f_t/f_T in [0, 1] of its   |
// |                                   | peak (1 intact; the law passes 1 when !couples_tension); noexcept|
// Optional (cohesive_frictional's elastic pack path needs it, concept PackedShearLimit):
// | S::lane_strength(p, sigma_n,      | strength(p, sigma_n, flags, r) to the bit, lane by lane, for    |
// |   slipped, broken, r)             | sigma_n and r reals or lanes::pack's (core/lanes.hpp) and the   |
// |                                   | flags given as the masks slipped and broken (bool for a real)   |
// Optional (a limit that softens with the plastic slip; the law then stores u_slip): the concept
// SlipSofteningShearLimit of slip_softening.hpp (coulomb_slip_softening), detected by the law.

#include <cmath>
#include <concepts>
#include <numbers>

#include "../core/lanes.hpp"
#include "../core/types.hpp"
#include "concepts.hpp"
#include "detail/validation.hpp"
#include "lane_masks.hpp"

namespace tessera::law {

template <class S>
concept ShearLimit = requires(const typename S::params& p, real sigma_n, contact_status flags, real r) {
  typename S::params;
  { S::validate(p) } -> std::same_as<void>;
  { S::couples_tension } -> std::convertible_to<bool>;
  { S::strength(p, sigma_n, flags, r) } noexcept -> std::convertible_to<real>;
};

/// A friction angle held in radians together with its tangent, so the Coulomb limit costs no
/// std::tan per update (a tan call would cost about as much as the whole law update). Build it with
/// friction_angle::from_degrees(35) or friction_angle::from_radians(0.61); the default is 0.
class friction_angle {
 public:
  constexpr friction_angle() = default;
  [[nodiscard]] static friction_angle from_radians(real phi) { return friction_angle(phi); }  ///< An angle in radians (a law's validate refuses one outside [0, pi/2))
  [[nodiscard]] static friction_angle from_degrees(real phi_deg) {  ///< An angle in degrees (a law's validate refuses one outside [0, 90))
    return friction_angle(phi_deg * (std::numbers::pi_v<real> / 180));
  }
  [[nodiscard]] constexpr real radians() const noexcept { return radians_; }  ///< phi (rad)
  [[nodiscard]] constexpr real degrees() const noexcept { return radians_ * (180 / std::numbers::pi_v<real>); }  ///< phi (deg)
  /// tan(phi), the friction coefficient (-).
  [[nodiscard]] constexpr real tan() const noexcept { return tan_; }

 private:
  explicit friction_angle(real phi) : radians_(phi), tan_(std::tan(phi)) {}
  real radians_ = 0;
  real tan_ = 0;
};

namespace detail {
inline void require_friction_angle(const friction_angle& phi, const char* name) {
  if (!(phi.radians() >= 0 && phi.radians() < std::numbers::pi_v<real> / 2))
    throw invalid_input(tessera::detail::concat("contact law: friction angle ", name, " = ", phi.degrees(),
                                                " deg must be in [0, 90) deg"));
}
/// max(0, c - sigma_n tan_phi) (Pa) for T = real or a lanes::pack (c and tan_phi reals or packs of T).
template <class C, class T>
[[nodiscard, gnu::always_inline]] inline T coulomb_line(C c, C tan_phi, T sigma_n) noexcept {
  const T limit = c - sigma_n * tan_phi;
  return lanes::select(limit > real(0), limit, T{});
}

/// The Coulomb limit max(0, c - sigma_n tan(phi)) lane by lane (T = real or lanes::pack, M its mask
/// or a bool), the damage state given as the masks slipped and broken (in tension): residual
/// cohesion and friction once slipped or broken in tension (DESIGN.md §3: a broken joint keeps
/// residual values, as in 3DEC), otherwise the cohesion `c_intact` the policy gives and phi_0.
template <class Params, class T, class M>
[[nodiscard, gnu::always_inline]] inline T coulomb_limit_lanes(const Params& p, T sigma_n, M slipped, M broken,
                                                              T c_intact) noexcept {
  const T c = mask_select(slipped | broken, lanes::splat<T>(p.c_res), c_intact);
  const T tan_phi = mask_select(slipped | broken, lanes::splat<T>(p.phi_res.tan()), lanes::splat<T>(p.phi_0.tan()));
  return coulomb_line(c, tan_phi, sigma_n);
}
/// coulomb_limit_lanes of one contact in damage state `flags`.
template <class Params>
[[nodiscard]] inline real coulomb_limit(const Params& p, real sigma_n, contact_status flags, real c_intact) noexcept {
  return coulomb_limit_lanes(p, sigma_n, has(flags, contact_status::slipped), has(flags, contact_status::broken_tension),
                             c_intact);
}
}  // namespace detail

/// Coulomb limit with brittle shear failure and residual strength (study eq. 6, DESIGN.md §3):
/// intact: c = c_0, phi = phi_0; broken in tension or slipped (failed in shear), for good: c = c_res and
/// phi = phi_res. Setting c_res = c_0 and phi_res = phi_0 gives a
/// perfectly plastic Coulomb contact.
struct coulomb_residual {
  static constexpr bool couples_tension = false;  ///< shear strength does not depend on the tension state
  /// c_0, phi_0, c_res, phi_res
  struct params {
    real c_0 = 0;              ///< initial cohesion (Pa, >= 0)
    friction_angle phi_0{};    ///< initial friction angle, [0, 90) deg
    real c_res = 0;            ///< residual cohesion (Pa, in [0, c_0])
    friction_angle phi_res{};  ///< residual friction angle, [0, 90) deg
    /// false (DESIGN.md, the study): a contact that fails in shear keeps its tensile strength and
    /// softening state. true: the first shear failure also breaks it in tension for good, as the
    /// brittle Coulomb joints of 3DEC and YADE's fragile cohesive contacts do (opt-in; see
    /// docs/model.md "Shear failure and tension").
    bool slip_breaks_tension = false;
  };
  static void validate(const params& p) {  ///< Refuses (invalid_input) a negative cohesion, c_res > c_0 or an angle out of range, naming it
    if (!(p.c_0 >= 0) || !std::isfinite(p.c_0))
      throw invalid_input(tessera::detail::concat("contact law: cohesion c_0 = ", p.c_0, " Pa must be finite and >= 0"));
    detail::require_in_closed_range(p.c_res, 0, p.c_0, "residual cohesion c_res", "Pa",
                                    tessera::detail::concat("[0, c_0 = ", p.c_0, " Pa]").c_str());
    detail::require_friction_angle(p.phi_0, "phi_0");
    detail::require_friction_angle(p.phi_res, "phi_res");
  }
  /// tau_max = max(0, c - sigma_n tan(phi)) (Pa) with (c, phi) chosen by the damage state; the
  /// tensile fraction is ignored (decoupled).
  [[nodiscard]] static real strength(const params& p, real sigma_n, contact_status flags,
                                     real /*tensile_fraction*/ = 1) noexcept {
    return detail::coulomb_limit(p, sigma_n, flags, p.c_0);
  }
  /// strength(p, sigma_n, flags) lane by lane (T = real or a lanes::pack, M its mask), to the bit.
  template <class T, class M>
  [[nodiscard, gnu::always_inline]] static T lane_strength(const params& p, T sigma_n, M slipped, M broken,
                                                          T /*tensile_fraction*/) noexcept {
    return detail::coulomb_limit_lanes(p, sigma_n, slipped, broken, lanes::splat<T>(p.c_0));
  }
};

/// coulomb_residual whose cohesion softens together with the tensile strength: while the contact
/// is neither slipped nor broken, c = c_res + (c_0 - c_res) r with r = f_t/f_T the remaining
/// fraction of the tensile strength, so c = c_0 for an intact contact and c -> c_res as the
/// contact breaks (continuous, where coulomb_residual jumps from c_0 to c_res at the break). The
/// friction angle and the brittle shear failure are those of coulomb_residual. Same parameters.
struct coulomb_coupled {
  static constexpr bool couples_tension = true;  ///< shear strength coupled to the tension state
  using params = coulomb_residual::params;  ///< as coulomb_residual's
  static void validate(const params& p) { coulomb_residual::validate(p); }  ///< As coulomb_residual's
  /// The shear strength (Pa) at normal stress sigma_n (Pa, positive in tension) in this state
  [[nodiscard]] static real strength(const params& p, real sigma_n, contact_status flags,
                                     real tensile_fraction = 1) noexcept {
    return detail::coulomb_limit(p, sigma_n, flags, p.c_res + (p.c_0 - p.c_res) * tensile_fraction);
  }
  /// strength(p, sigma_n, flags, tensile_fraction) lane by lane (T = real or a lanes::pack, M its
  /// mask), to the bit.
  template <class T, class M>
  [[nodiscard, gnu::always_inline]] static T lane_strength(const params& p, T sigma_n, M slipped, M broken,
                                                          T tensile_fraction) noexcept {
    return detail::coulomb_limit_lanes(p, sigma_n, slipped, broken, p.c_res + (p.c_0 - p.c_res) * tensile_fraction);
  }
};

/// A ShearLimit whose strength can be evaluated on lanes::pack's.
template <class S>
concept PackedShearLimit = ShearLimit<S> && requires(const typename S::params& p, lanes::pack sigma_n, lanes::mask m) {
  { S::lane_strength(p, sigma_n, m, m, sigma_n) } noexcept -> std::same_as<lanes::pack>;
};

static_assert(ShearLimit<coulomb_residual>);
static_assert(ShearLimit<coulomb_coupled>);
static_assert(PackedShearLimit<coulomb_residual> && PackedShearLimit<coulomb_coupled>);

}  // namespace tessera::law
