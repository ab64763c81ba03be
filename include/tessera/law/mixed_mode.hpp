#pragma once
// law::mixed_mode_cohesive<Compression>: a contact law with ONE damage variable for tension and
// shear (issue #63, the second candidate family: damage driven by an effective opening of normal
// opening and slip, Camacho and Ortiz 1996; the facet law of Cusatis' LDPM). Not the study's law.
//
// Why a law class and not a policy of cohesive_frictional: there the tension policy owns u_soft and
// the shear policy its own limit; each is returned onto its own envelope in turn (normal first, then
// shear). Here one damage D is advanced by the normal and the shear plastic displacement together
// and lowers both strengths at once, so the normal and the shear stress are returned together.
// The parameters are cohesive_frictional's (linear_softening tension, a Compression policy,
// coulomb_slip_softening shear: f_T, G_f = G_I, c_0, phi_0, phi_res, G_II), so the drivers' code for
// the beam's contacts applies unchanged; c_res must be 0 (both strengths reach zero together).
//
// Damage and strengths. D in [0, 1] (state::u_soft = D l_I, m: in pure tension the plastic opening),
//     l_I  = 2 G_I / f_T       (m)  plastic opening at which pure tension has lost its strength,
//     l_II = 2 G_II / c_0      (m)  plastic slip at which pure shear (sigma_n = 0) has lost its cohesion,
//     f_t = f_T (1 - D),  c = c_0 (1 - D),  tan phi = tan phi_res + (tan phi_0 - tan phi_res)(1 - D).
// Tension side (trial sigma_n > 0): the elliptic interaction (Cusatis' facet law in tension)
//     sigma_n^2 + alpha^2 |tau|^2 <= f_t^2,   alpha = f_T / c_0,
// f_T in pure tension, c_0 in pure shear. Beyond it, a radial return sigma = lam sigma_tr, tau = lam
// tau_tr: the plastic increments are dp = (1 - lam) sigma_tr / k_n, ds = (1 - lam) |tau_tr| / k_s and
// the damage grows by the effective plastic opening
//     dD = sqrt((dp / l_I)^2 + (ds / l_II)^2) = (1 - lam) B,   B = sqrt((sigma_tr/(k_n l_I))^2 + (|tau_tr|/(k_s l_II))^2),
// so lam E_tr = f_T (1 - D - (1 - lam) B), E_tr = sqrt(sigma_tr^2 + alpha^2 |tau_tr|^2), in closed form
//     lam = f_T (1 - D - B) / (E_tr - f_T B);   lam <= 0: D = 1, broken (no tension, no cohesion).
// With l_II = l_I (G_II = (c_0/f_T) G_I) dD is Camacho-Ortiz's effective opening with beta = 1.
// Compression side (trial sigma_n <= 0): the normal stress is elastic up to the Compression cap
// (plastic_cap: perfectly plastic at f_c; softening_cap: the cap falls with the plastic closure
// u_crush to its residual over G_c, compression.hpp, its closed-form return, flag `crushed`, as in
// cohesive_frictional; the damage D is not touched by crushing); the
// shear limit is coulomb_slip_softening's with c_res = 0 at the slip s = D l_II,
//     |tau| <= c_0 (1 - D) - sigma_n tan phi(D),
// whose closed-form return (slip_softening.hpp) advances D by the plastic slip / l_II. With
// softening_cap's scales_shear this Coulomb limit (not the tension side's ellipse) is multiplied by
// f(u_crush) / f_c, so a crushed contact also loses that share of its cohesion and friction.
// Broken (D = 1, flag broken_tension): sigma_n = k_n min(0, u_n - u_p), no shear while open (u_n >
// u_p), Coulomb friction phi_res when closed. A break on the tension side resets u_p to min(u_p, 0)
// (faces carry compression again from the geometric overlap; an earlier plastic opening is
// forgotten, an earlier crushing closure kept as far as it exceeds it); on the compression side u_p stays.
//
// Energy (closed forms, tests/test_laws.cpp "[mixed]"). Pulled to separation in pure tension the
// contact dissipates G_I = f_T l_I / 2 (tension.hpp's linear_softening: the same envelope, the same
// opening); slid at sigma_n = 0 it dissipates G_II = c_0 l_II / 2 (then friction-free); along a
// fixed displacement direction whose elastic stress direction is (a, b), a^2 + alpha^2 b^2 = 1, it
// peaks at (f_T a, f_T b) and dissipates (mixed_separation_energy)
//     G(a, b) = (f_T / 2)(a^2/k_n + b^2/k_s) / sqrt((a/(k_n l_I))^2 + (b/(k_s l_II))^2).
// Bookkeeping as cohesive_frictional's: trapezoidal work minus the change of stored energy, the
// normal part to dissipated_tension / _compression by sign, the shear part to dissipated_shear.
//
// Flags: softening (0 < D < 1), broken_tension (D = 1), slipped (a plastic slip on the compression
// side, a record only). Pack path (law::ElasticPackLaw): one function step<T, Transitions> for a
// sub-contact and a lanes::pack; update_elastic keeps the lanes whose flags the step leaves
// unchanged and that do not reach the cap, as cohesive_frictional's does.

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "../core/contact_kinematics.hpp"
#include "../core/lanes.hpp"
#include "../core/types.hpp"
#include "compression.hpp"
#include "concepts.hpp"
#include "detail/crush_lanes.hpp"
#include "detail/state_lanes.hpp"
#include "detail/validation.hpp"
#include "lane_masks.hpp"
#include "slip_softening.hpp"
#include "tension.hpp"

namespace tessera::law {

/// One damage for tension and shear, driven by the effective plastic opening (file comment);
/// stresses in Pa, displacements in m, sigma_n positive in tension. Compression: elastic_compression,
/// plastic_cap or softening_cap (the cap softening with the plastic closure u_crush).
template <CompressionLimit Compression>
struct mixed_mode_cohesive {
  using compression_policy = Compression;  ///< the compression part
  /// The policies whose parameters and checks the law takes (its limits are its own, file comment)
  using tension_policy = linear_softening;
  using shear_policy = coulomb_slip_softening;  ///< see tension_policy
  static constexpr bool softens_with_slip = false;      ///< no u_slip stored: the damage is u_soft
  /// True when the cap softens with the plastic closure (softening_cap): the state then stores u_crush.
  static constexpr bool softens_with_crushing = SofteningCompressionLimit<Compression>;

  /// k_n, k_s and the parts' parameters, as cohesive_frictional<linear_softening, Compression, coulomb_slip_softening>
  struct params {
    real k_n = 0;  ///< normal stiffness (Pa/m)
    real k_s = 0;  ///< shear stiffness (Pa/m)
    linear_softening::params tension{};  ///< f_T (Pa) and G_f = G_I (J/m^2)
    typename Compression::params compression{};  ///< the compressive cap (plastic_cap: f_c, Pa)
    coulomb_slip_softening::params shear{};  ///< c_0 (Pa), phi_0, c_res (must be 0), phi_res, G_II (J/m^2)
  };

  /// History of one sub-contact; value-initialised = virgin. cohesive_frictional's fields, u_soft = D l_I
  /// (u_crush only with a softening cap).
  struct state {
    real sigma_n = 0;                 ///< normal stress (Pa, + tension)
    vec3 tau = vec3::Zero();          ///< shear stress vector (Pa, global frame, in the contact plane)
    real u_n = 0;                     ///< total normal opening (m, + opens)
    real u_p = 0;                     ///< irreversible opening: sigma_n = k_n (u_n - u_p) below the limits (m)
    real u_soft = 0;                  ///< damage times l_I = 2 G_I / f_T (m): the mode-I-equivalent plastic opening
    real dissipated_tension = 0;      ///< energy dissipated on the tensile side (J/m^2)
    real dissipated_shear = 0;        ///< energy dissipated in shear (J/m^2)
    real dissipated_compression = 0;  ///< energy dissipated on the compressive side (J/m^2)
    contact_status flags = contact_status::intact;  ///< softening / broken_tension / slipped / crushed
    /// plastic normal closure on the softening cap (m, >= 0); a real only when softens_with_crushing
    [[no_unique_address]] std::conditional_t<softens_with_crushing, real, detail::no_crush> u_crush{};
  };
  /// The state's fields (law::state_field), as cohesive_frictional's ("u_crush", m, after the
  /// dissipated energies when softens_with_crushing).
  static constexpr auto state_fields = [] {
    using f = state_field<state>;
    std::array<f, 9 + softens_with_crushing> a{
        {{"sigma_n", "Pa", &state::sigma_n}, {"tau", "Pa", &state::tau}, {"u_n", "m", &state::u_n},
         {"u_p", "m", &state::u_p}, {"u_soft", "m", &state::u_soft},
         {"dissipated_tension", "J/m^2", &state::dissipated_tension},
         {"dissipated_shear", "J/m^2", &state::dissipated_shear},
         {"dissipated_compression", "J/m^2", &state::dissipated_compression},
         {"flags", "contact_status bits", &state::flags}}};
    if constexpr (softens_with_crushing) {
      a[8] = f{"u_crush", "m", &state::u_crush};
      a[9] = f{"flags", "contact_status bits", &state::flags};
    }
    return a;
  }();
  static_assert(sizeof(state) == (real_column_count(state_fields) + 1) * sizeof(real));

  /// Throws invalid_input naming the first bad parameter: k_n, k_s finite and > 0; f_T, G_I with
  /// G_I > f_T^2/(2 k_n); the cap (softening_cap: with G_c > ((1 - residual) f_c)^2/(2 k_n)); c_0 > 0, phi_0, phi_res <= phi_0, G_II > c_0^2/(2 k_s); c_res = 0.
  static void validate(const params& p) {
    detail::require_positive(p.k_n, "normal stiffness k_n", "Pa/m");
    detail::require_positive(p.k_s, "shear stiffness k_s", "Pa/m");
    linear_softening::validate(p.tension, p.k_n);
    if constexpr (softens_with_crushing)
      Compression::validate_with_stiffness(p.compression, p.k_n);
    else
      Compression::validate(p.compression);
    if (p.shear.c_res != 0)
      throw invalid_input(tessera::detail::concat("contact law: residual cohesion c_res = ", p.shear.c_res,
                                                  " Pa must be 0 for the mixed-mode law (one damage takes tension and "
                                                  "cohesion to zero together; the residual is friction phi_res)"));
    coulomb_slip_softening::validate_with_stiffness(p.shear, p.k_s);
  }
  [[nodiscard]] static real normal_stiffness(const params& p) noexcept { return p.k_n; }  ///< k_n (Pa/m)
  [[nodiscard]] static real shear_stiffness(const params& p) noexcept { return p.k_s; }  ///< k_s (Pa/m)
  /// l_I = 2 G_I / f_T (m): the plastic opening that spends pure tension.
  [[nodiscard]] static real mode_one_length(const params& p) noexcept { return 2 * p.tension.G_f / p.tension.f_T; }
  /// l_II = 2 G_II / c_0 (m): the plastic slip that spends pure shear at sigma_n = 0.
  [[nodiscard]] static real mode_two_length(const params& p) noexcept { return 2 * p.shear.G_II / p.shear.c_0; }
  /// The damage D in [0, 1] of a state (1 when broken).
  [[nodiscard]] static real damage(const params& p, const state& s) noexcept {
    if (has(s.flags, contact_status::broken_tension)) return 1;
    return has(s.flags, contact_status::softening) ? s.u_soft * (1 / mode_one_length(p)) : real(0);
  }
  /// Current tensile strength f_T (1 - D) (Pa), 0 once broken: a function of u_soft and the flags.
  [[nodiscard]] static real tensile_strength(const params& p, const state& s) noexcept {
    if (has(s.flags, contact_status::broken_tension)) return 0;
    return p.tension.f_T * (1 - s.u_soft * (1 / mode_one_length(p)));
  }
  /// D in [0, 1]: 0 intact, 1 broken (one damage for tension and shear).
  [[nodiscard]] static real tensile_damage(const params& p, const state& s) noexcept {
    return std::clamp(damage(p, s), real(0), real(1));
  }
  /// The shear limit (Pa) at the stored normal stress: c (1 - (sigma_n/f_t)^2)^(1/2) in tension,
  /// c - sigma_n tan phi in compression (friction phi_res alone once broken; times f(u_crush)/f_c
  /// with softening_cap's scales_shear).
  [[nodiscard]] static real shear_strength(const params& p, const state& s) noexcept {
    const real d = damage(p, s), f_t = p.tension.f_T * (1 - d);
    if (s.sigma_n > 0) return f_t > s.sigma_n ? p.shear.c_0 * (1 - d) * std::sqrt(1 - (s.sigma_n / f_t) * (s.sigma_n / f_t)) : 0;
    return crush_fraction(p, s) * coulomb_slip_softening::lane_slip_strength(
                                      p.shear, s.sigma_n, false, d * mode_two_length(p));
  }
  /// Current compressive cap (Pa, a magnitude): f_c, or f(u_crush) with softening_cap; +inf unbounded.
  [[nodiscard]] static real compressive_strength(const params& p, const state& s) noexcept {
    if constexpr (softens_with_crushing) return Compression::lane_strength(p.compression, s.u_crush);
    else return Compression::strength(p.compression);
  }
  /// The factor of the compression side's Coulomb limit: f(u_crush)/f_c with softening_cap's
  /// scales_shear, else 1.
  [[nodiscard]] static real crush_fraction(const params& p, const state& s) noexcept {
    if constexpr (softens_with_crushing)
      if (p.compression.scales_shear)
        return Compression::lane_strength(p.compression, s.u_crush) * (1 / Compression::strength(p.compression));
    return 1;
  }
  /// Energy dissipated per area (J/m^2) by a contact driven to separation along a fixed displacement
  /// direction whose elastic stress direction is (a, b) (normal, shear; scaled inside to a^2 +
  /// alpha^2 b^2 = 1): G_I for (1, 0), G_II for (0, 1) (file comment).
  [[nodiscard]] static real mixed_separation_energy(const params& p, real a, real b) noexcept {
    const real alpha = p.tension.f_T / p.shear.c_0, norm = std::sqrt(a * a + alpha * alpha * b * b);
    a /= norm;
    b /= norm;
    const real x = a / (p.k_n * mode_one_length(p)), y = b / (p.k_s * mode_two_length(p));
    return 0.5 * p.tension.f_T * (a * a / p.k_n + b * b / p.k_s) / std::sqrt(x * x + y * y);
  }
  /// A never-bonded sub-contact: broken and slipped, friction phi_res only.
  [[nodiscard]] static state unbonded_state(const params& /*p*/) noexcept {
    state s{};
    s.flags = contact_status::broken_tension | contact_status::slipped;
    return s;
  }
  /// Scales the stresses by r in (0, 1] (contact::detected_contacts' rebuild), as cohesive_frictional's.
  static void scale_stresses(const params& p, state& s, real r) noexcept {
    s.tau *= r;
    const bool elastic_tension = s.sigma_n > 0 && s.flags == contact_status::intact;
    if (s.sigma_n < 0 || elastic_tension) {
      s.sigma_n *= r;
      s.u_n = s.u_p + s.sigma_n / p.k_n;
    }
  }
  [[nodiscard]] static contact_status status(const state& s) noexcept { return s.flags; }  ///< The flags
  /// Energy dissipated so far by all mechanisms (J/m^2).
  [[nodiscard]] static real dissipated_energy(const state& s) noexcept {
    return s.dissipated_tension + s.dissipated_shear + s.dissipated_compression;
  }
  /// Recoverable elastic energy sigma_n^2/(2 k_n) + |tau|^2/(2 k_s) (J/m^2).
  [[nodiscard]] static real stored_energy(const params& p, const state& s) noexcept {
    return s.sigma_n * s.sigma_n / (2 * p.k_n) + s.tau.squaredNorm() / (2 * p.k_s);
  }

  // ---- the step, for one sub-contact and for lanes::pack's (law::ElasticPackLaw) ----
  static constexpr bool elastic_pack = true;  ///< update_elastic exists
  /// Lanes of update_elastic (T = real or lanes::pack): cohesive_frictional's layout.
  template <class T>
  struct elastic_lanes {
    /** in: update()'s du_n (m) and du_s (m) */ /**@{*/ T du_n, ds0, ds1, ds2; /**@}*/
    /** in: update()'s unit normal n */ /**@{*/ T n0, n1, n2; /**@}*/
    /** in/out: state fields */ /**@{*/ T sigma_n, tau0, tau1, tau2, u_n, dissipated_tension, dissipated_shear,
        dissipated_compression, u_p, u_soft; /**@}*/
    T f_t;  ///< in/out: tensile_strength(p, state)
    /// in/out: the state's u_crush (m) when softens_with_crushing (set after the aggregate's other members)
    [[no_unique_address]] std::conditional_t<softens_with_crushing, T, detail::no_crush> u_crush{};
  };

  /// Advances s by one step: du_n opening increment (m), du_s slip increment of B w.r.t. A (m, in
  /// the plane of n), n the unit normal A -> B; every transition taken (step<real, true>).
  static void update(const params& p, state& s, real du_n, const vec3& du_s, const vec3& n) noexcept {
    auto x = detail::load_state_lanes<elastic_lanes<real>>(s, du_n, du_s, n, tensile_strength(p, s));
    if constexpr (softens_with_crushing) x.u_crush = s.u_crush;
    auto flags = static_cast<lanes::mask_lane>(s.flags);
    static_cast<void>(step<real, true>(p, flags, x));
    detail::store_state_lanes(x, s);
    if constexpr (softens_with_crushing) s.u_crush = x.u_crush;
    s.flags = static_cast<contact_status>(flags);
  }
  /// update() of the lanes whose flags the step leaves unchanged and that stay above the cap
  /// (softening_cap: that do not crush for the first time; a crushed lane crushes on in the pack);
  /// returns their mask (their outputs are update()'s to the bit; the others' are meaningless).
  template <class T, class F>
  [[nodiscard, gnu::always_inline]] static inline auto update_elastic(const params& p, F flags,
                                                                     elastic_lanes<T>& x) noexcept {
    return step<T, false>(p, flags, x);
  }

  /// The step of one sub-contact (T = real) or a pack, written once (file comment). Transitions:
  /// flags updated (T = real); otherwise lanes whose flags would change are declined.
  template <class T, bool Transitions, class F>
  [[nodiscard, gnu::always_inline]] static inline auto step(const params& p, F& flags, elastic_lanes<T>& x) noexcept {
    using M = decltype(T{} < T{});
    using detail::mask_not;
    using detail::mask_select;
    constexpr auto bit = [](contact_status b) { return static_cast<lanes::mask_lane>(b); };
    const real k_n = p.k_n, k_s = p.k_s, f_T = p.tension.f_T, alpha = f_T / p.shear.c_0;
    const real l_I = mode_one_length(p), l_II = mode_two_length(p), inv_l_I = 1 / l_I;
    contact::kinematics::rotate_into_plane(x.tau0, x.tau1, x.tau2, x.n0, x.n1, x.n2);
    const T sigma_old = x.sigma_n, t0 = x.tau0, t1 = x.tau1, t2 = x.tau2;
    x.u_n = x.u_n + x.du_n;
    const T trial = k_n * (x.u_n - x.u_p);
    const M broken = detail::flag_mask<M>(flags, bit(contact_status::broken_tension));
    const M softening = detail::flag_mask<M>(flags, bit(contact_status::softening));
    const M slipped = detail::flag_mask<M>(flags, bit(contact_status::slipped));
    T c0 = x.tau0 + k_s * x.ds0, c1 = x.tau1 + k_s * x.ds1, c2 = x.tau2 + k_s * x.ds2;
    const T trial_sq = (c0 * c0 + c1 * c1) + c2 * c2;
    const M tension_side = mask_not(broken) & (trial > real(0));
    // Normal stress before the returns: the trial, min(0, trial) when broken, the cap in compression.
    T sigma = mask_select(broken & (trial > real(0)), T{}, trial);
    M keep = T{} == T{};  // lanes accepted (Transitions = false): all so far
    if constexpr (softens_with_crushing) {  // the cap softened by u_crush; a first crush sets `crushed`
      detail::crush_lanes<Compression, Transitions>(p.compression, k_n, flags, x, sigma, keep);
    } else if constexpr (Compression::bounded) {
      const real f_c = Compression::strength(p.compression);
      const M capped = sigma < -f_c;
      if constexpr (Transitions) {
        if (capped) {
          sigma = -f_c;
          x.u_p = x.u_n + f_c / k_n;
        }
      } else {
        keep = keep & mask_not(capped);
      }
    }
    // The limits at the current damage D = u_soft / l_I (f_t = f_T (1 - D) is x.f_t).
    // D = 0 unless softening (an intact pack, flags constant zero, folds it away); broken: friction only.
    const T d = mask_select(softening, x.u_soft * inv_l_I, T{});
    const T slip = d * l_II;
    T coulomb = detail::coulomb_line(lanes::splat<T>(p.shear.c_0), lanes::splat<T>(p.shear.phi_0.tan()), sigma);
    const M damaged_before = softening | broken;
    if (lanes::any(damaged_before))
      coulomb = mask_select(damaged_before, coulomb_slip_softening::lane_slip_strength(p.shear, sigma, broken, slip),
                            coulomb);
    T crush_scale = lanes::splat<T>(1);  // f(u_crush)/f_c with softening_cap's scales_shear
    if constexpr (softens_with_crushing)
      if (p.compression.scales_shear) {
        crush_scale = Compression::lane_strength(p.compression, x.u_crush) * (1 / Compression::strength(p.compression));
        coulomb = crush_scale * coulomb;
      }
    const T tension_sq = sigma * sigma + alpha * alpha * trial_sq;
    const M beyond_tension = tension_side & (tension_sq > x.f_t * x.f_t);
    const M open = broken & (x.u_n > x.u_p);
    const M beyond_coulomb = mask_not(tension_side) & mask_not(open) & (trial_sq > coulomb * coulomb);
    const M sliding = beyond_coulomb | open;
    const M limited = beyond_tension | sliding;
    if (lanes::any(limited)) [[unlikely]] {  // the returns; D, the flags and the shear dissipation advance
      T d_new = d, tau_scale = lanes::splat<T>(1);
      if (lanes::any(beyond_tension)) {  // the radial return onto the ellipse (file comment)
        const T e_tr = lanes::sqrt(tension_sq);
        const T bx = sigma * (1 / (k_n * l_I));
        const real inv_y = 1 / (k_s * l_II);
        const T b = lanes::sqrt(bx * bx + trial_sq * (inv_y * inv_y));
        const T lam_raw = f_T * ((1 - d) - b) / (e_tr - f_T * b);
        const M breaks = mask_not(lam_raw > real(0));
        const T lam = mask_select(breaks, T{}, lam_raw);
        sigma = mask_select(beyond_tension, lam * sigma, sigma);
        tau_scale = mask_select(beyond_tension, lam, tau_scale);
        d_new = mask_select(beyond_tension, mask_select(breaks, lanes::splat<T>(1), d + (1 - lam) * b), d_new);
        const T closure = lanes::select(x.u_p < real(0), x.u_p, T{});  // min(u_p, 0): kept at a break
        x.u_p = mask_select(beyond_tension, mask_select(breaks, closure, x.u_n - sigma * (1 / k_n)), x.u_p);
      }
      tau_scale = mask_select(open, T{}, tau_scale);  // an open crack carries no shear
      if (lanes::any(beyond_coulomb)) {  // slip-softening Coulomb return (broken: friction alone)
        const T t_tr = lanes::sqrt(trial_sq);
        T limit = coulomb;
        const M softens = beyond_coulomb & mask_not(broken);
        if (lanes::any(softens)) {
          const auto r = coulomb_slip_softening::lane_slip_return(p.shear, k_s, sigma, broken, slip, t_tr, crush_scale);
          limit = mask_select(broken, coulomb, r.tau);
          const T s_new = r.slip * (1 / l_II);
          d_new = mask_select(softens, lanes::select(s_new < real(1), s_new, lanes::splat<T>(1)), d_new);
        }
        const T ratio = limit / t_tr;
        const T scale = lanes::select(ratio < real(1), ratio, lanes::splat<T>(1));
        tau_scale = mask_select(beyond_coulomb, scale, tau_scale);
      }
      // New flags: softening while 0 < D < 1, broken at D = 1, slipped after a Coulomb slide.
      const M now_broken = broken | (d_new >= real(1));
      const M now_softening = mask_not(now_broken) & (d_new > real(0));
      const M now_slipped = slipped | (beyond_coulomb & mask_not(broken));
      if constexpr (Transitions) {
        lanes::mask_lane f = flags & ~(bit(contact_status::softening) | bit(contact_status::broken_tension) |
                                       bit(contact_status::slipped));
        if (now_broken) f |= bit(contact_status::broken_tension);
        if (now_softening) f |= bit(contact_status::softening);
        if (now_slipped) f |= bit(contact_status::slipped);
        flags = static_cast<F>(f);
      } else {
        keep = keep & mask_not(now_broken ^ broken) & mask_not(now_softening ^ softening) &
               mask_not(now_slipped ^ slipped);
      }
      const M damaged = beyond_tension | (beyond_coulomb & mask_not(broken));  // D advanced this step
      x.u_soft = mask_select(damaged, d_new * l_I, x.u_soft);
      x.f_t = mask_select(now_broken, T{}, mask_select(damaged, f_T * (1 - x.u_soft * inv_l_I), x.f_t));
      c0 = c0 * tau_scale, c1 = c1 * tau_scale, c2 = c2 * tau_scale;
      const real inv_k_s = 1 / k_s;
      const T w0 = x.ds0 - (c0 - t0) * inv_k_s, w1 = x.ds1 - (c1 - t1) * inv_k_s, w2 = x.ds2 - (c2 - t2) * inv_k_s;
      const T dissipated = x.dissipated_shear + real(0.5) * (((t0 + c0) * w0 + (t1 + c1) * w1) + (t2 + c2) * w2);
      x.dissipated_shear = mask_select(limited, dissipated, x.dissipated_shear);
    }
    x.sigma_n = sigma;
    // Energy: the normal part by sign (file comment); the shear part above, for the limited lanes.
    const T sigma_sum = sigma_old + sigma;
    const T normal = real(0.5) * sigma_sum * (x.du_n - (sigma - sigma_old) * (1 / k_n));
    const M compressive = sigma_sum < real(0);
    x.dissipated_compression = mask_select(compressive, x.dissipated_compression + normal, x.dissipated_compression);
    x.dissipated_tension = mask_select(compressive, x.dissipated_tension, x.dissipated_tension + normal);
    x.tau0 = c0;
    x.tau1 = c1;
    x.tau2 = c2;
    if constexpr (Transitions) return true;
    else return keep;
  }
};

}  // namespace tessera::law
