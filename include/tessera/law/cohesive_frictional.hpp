#pragma once
// law::cohesive_frictional<Tension, Compression, Shear>: the contact constitutive law of the
// reference study (eqs. 4-6, DESIGN.md §3 "Contact law"), composed from three policies in the
// manner of MercuryDPM's Species<Normal, Friction, ...>:
//     Tension      TensionSoftening  (tension.hpp):     linear_softening, power_softening, no_tension
//     Compression  CompressionLimit  (compression.hpp): elastic_compression, plastic_cap, softening_cap
//     Shear        ShearLimit        (shear.hpp):       coulomb_residual, coulomb_coupled,
//                  SlipSofteningShearLimit (slip_softening.hpp): coulomb_slip_softening
// The named combinations of the study are in aliases.hpp. The law is a pure evaluator of one
// sub-contact: stresses per unit area, the caller (contact::face_contacts) multiplies by the
// tributary area and owns loops and storage. It satisfies law::ContactLaw (concepts.hpp).
//
// Conventions: SI units; sigma_n and u_n positive in tension/opening; the contact normal n points
// from block A to block B; du_s and tau are 3-vectors in the global frame lying in the contact plane,
// tau = k_s u_s growing along the slip u_s of B relative to A. The traction on block B is
// -(sigma_n n + tau) (it resists opening and slip), the one on block A its opposite.
//
// One step, update(p, s, du_n, du_s, n):
//  1. Rotation. The stored tau is turned into the plane of the current unit normal n: its
//     n-component is removed and the remainder rescaled to the old magnitude, so a rigid rotation
//     of the contact neither creates nor destroys shear stress. (A tau exactly parallel to the new
//     n, i.e. a 90-degree turn within one step, has no direction left and is dropped.)
//  2. Normal. u_n += du_n; trial sigma = k_n (u_n - u_p): elastic loading, unloading and reloading
//     with k_n, parallel to the elastic branch, from the irreversible opening u_p.
//     Tension: the trial is capped by the current strength f_t(w) of the envelope (tension.hpp),
//     w = state::u_soft being the opening travelled along the softening branch. When the cap is
//     active the return onto the envelope is closed-form for any envelope shape:
//         w_new = w + (sigma_trial - f_t(w))/k_n,   sigma = f_t(w_new),   u_p = u_n - sigma/k_n.
//     For a contact without compressive plastic closure this is exactly f_t evaluated at the total
//     opening u_n = eta + w (study eq. 5). After a compressive plastic closure (plastic_cap) the
//     envelope is carried along with it, i.e. measured from the crushed position, so crushing
//     neither heals a softened contact nor creates a tensile plateau. (Decision recorded here;
//     DESIGN.md is silent on the interaction.)
//     Broken in tension (Tension::exhausted), for good: no tensile stress, sigma = k_n min(0, u_n - u_p)
//     with u_p reset to the compressive plastic closure (0 unless plastic_cap yielded), i.e.
//     sigma = k_n min(0, u_n): compression only once the faces overlap geometrically again.
//     While such a broken contact is open (u_n > u_p) it carries no shear stress either (step 3).
//     Compression (plastic_cap): sigma >= -f_c, perfectly plastic; the irreversible closure goes into u_p.
//     softening_cap: sigma >= -f(u_crush), the cap softening with the plastic closure u_crush (state,
//     flag `crushed` from the first crush), its closed-form return (compression.hpp); closure into u_p too.
//  3. Shear. tau_trial = tau + k_s du_s, limited by tau_max = Shear::strength(sigma_n, flags) with the
//     new sigma_n. At the first exceedance the contact is marked `slipped` for good (brittle: the
//     coulomb_residual policy then returns the residual limit) and tau is scaled back onto the limit
//     along its own direction; afterwards perfectly plastic slip on that limit. Broken in tension
//     also drops the cohesion to c_res (policy). Tension and shear are otherwise decoupled with
//     coulomb_residual (DESIGN.md); coulomb_coupled softens the cohesion with f_t/f_T as well.
//     Opt-in (shear params slip_breaks_tension = true): the first shear failure also breaks the
//     contact in tension (3DEC's brittle Coulomb joint, YADE's fragile cohesive contact), see detail::break_on_slip.
//     A slip-softening policy (slip_softening.hpp) instead takes the plastic slip state::u_slip: no
//     brittle drop at the first slip (the flag `slipped` only records it), the limit falls with
//     u_slip and the return is its closed form (Shear::lane_slip_return), u_slip advanced by it.
//
// Energy (J/m^2). Per step and mechanism the dissipated increment is the trapezoidal work minus the
// change of elastic energy,
//     d = 0.5 (stress_old + stress_new) . increment - (stored_new - stored_old),
//     stored = sigma_n^2/(2 k_n) + |tau|^2/(2 k_s),
// which factorises as d = 0.5 (sigma_old + sigma_new)(du_n - (sigma_new - sigma_old)/k_n) for the normal
// part (and likewise for shear with the rotated old tau, rotation keeping |tau|). So the trapezoidal
// work a solver integrates equals stored + dissipated to rounding and the energy balance of a run
// closes. The normal part goes to dissipated_compression when sigma_old + sigma_new < 0 and to
// dissipated_tension otherwise; the shear part to dissipated_shear. Where a kink of the response
// (peak, yield, gap closure) falls inside a step, the O(k_n du^2) quadrature error of the
// trapezoidal rule is booked as dissipation (it can be slightly negative at a gap reopening);
// with steps that land on the kinks the bookkeeping is exact: a contact pulled to separation
// dissipates Tension::separation_energy (G_f for linear softening).
//
// One physics path: the step is written once, step<T, Transitions>, in select form for T = real
// (one sub-contact) or a lanes::pack. update() is step<real, true>, which also takes the
// transitions (peak, breaking, a first slip, the compressive cap); update_elastic is
// step<T, false>, which declines the lanes whose flags would change (see below).
//
// Cost and threading: update is noexcept, allocation-free and branch-light (the softening
// envelope is evaluated only for contacts past the peak); all functions are static and pure, so
// updating distinct states from several threads is safe.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "../core/lanes.hpp"
#include "../core/contact_kinematics.hpp"
#include "../core/types.hpp"
#include "compression.hpp"
#include "concepts.hpp"
#include "detail/validation.hpp"
#include "lane_masks.hpp"
#include "shear.hpp"
#include "slip_softening.hpp"
#include "tension.hpp"
#include "detail/crush_lanes.hpp"
#include "detail/state_lanes.hpp"
#include "detail/transitions.hpp"

namespace tessera::law {

/// A contact law of three parts, tension softening, a compression limit and a shear limit (file comment); stresses in Pa, displacements in m, normal stress positive in tension
template <TensionSoftening Tension, CompressionLimit Compression, ShearLimit Shear>
struct cohesive_frictional {
  using tension_policy = Tension;  ///< the tension part
  using compression_policy = Compression;  ///< the compression part
  using shear_policy = Shear;  ///< the shear part
  /// True when the shear limit softens with the plastic slip: the state then stores u_slip.
  static constexpr bool softens_with_slip = SlipSofteningShearLimit<Shear>;
  /// True when the compressive cap softens with the plastic closure: the state then stores u_crush.
  static constexpr bool softens_with_crushing = SofteningCompressionLimit<Compression>;

  /// The stiffnesses and each part's parameters (validate refuses any out of range, naming it)
  struct params {
    real k_n = 0;  ///< normal stiffness (Pa/m), k_n = E/t
    real k_s = 0;  ///< shear stiffness (Pa/m), k_s = G/t
    typename Tension::params tension{};  ///< the tension part's parameters
    typename Compression::params compression{};  ///< the compression part's parameters
    typename Shear::params shear{};  ///< the shear part's parameters
  };

  /// History of one sub-contact; value-initialised (`state{}`) = virgin, unloaded contact.
  /// 88 bytes (8 more with each of u_slip, u_crush). Plain data (not formally std::is_trivially_copyable only because Eigen's vec3
  /// declares its copy constructor; copying it is a plain memberwise copy).
  struct state {
    real sigma_n = 0;                  ///< normal stress (Pa, + tension)
    vec3 tau = vec3::Zero();           ///< shear stress vector (Pa, global frame, in the contact plane)
    real u_n = 0;                      ///< total normal opening accumulated from du_n (m, + opens)
    real u_p = 0;                      ///< irreversible opening: sigma_n = k_n (u_n - u_p) below the limits (m)
    real u_soft = 0;                   ///< opening travelled along the softening branch, w = u_n - eta (m)
    real dissipated_tension = 0;       ///< energy dissipated on the tensile side (J/m^2)
    real dissipated_shear = 0;         ///< energy dissipated by shear failure and slip (J/m^2)
    real dissipated_compression = 0;   ///< energy dissipated on the compressive side (J/m^2)
    contact_status flags = contact_status::intact;  ///< softening / broken_tension / slipped
    /// plastic slip accumulated on the shear limit (m); a real only when softens_with_slip
    [[no_unique_address]] std::conditional_t<softens_with_slip, real, detail::no_slip> u_slip{};
    /// plastic normal closure on the softening cap (m, >= 0); a real only when softens_with_crushing
    [[no_unique_address]] std::conditional_t<softens_with_crushing, real, detail::no_crush> u_crush{};
  };
  static_assert(std::is_trivially_destructible_v<state>);
  /// The state's fields, declared once (law::state_field): contact::face_contacts stores them as
  /// columns from this list and io::vtk::contact_snapshot writes one array each.
  /// "u_slip" (m, softens_with_slip) and "u_crush" (m, softens_with_crushing) follow the dissipated energies.
  static constexpr auto state_fields = [] {
    using f = state_field<state>;
    std::array<f, 9 + softens_with_slip + softens_with_crushing> a{
        {{"sigma_n", "Pa", &state::sigma_n}, {"tau", "Pa", &state::tau}, {"u_n", "m", &state::u_n},
         {"u_p", "m", &state::u_p}, {"u_soft", "m", &state::u_soft},
         {"dissipated_tension", "J/m^2", &state::dissipated_tension},
         {"dissipated_shear", "J/m^2", &state::dissipated_shear},
         {"dissipated_compression", "J/m^2", &state::dissipated_compression}, {"flags", "contact_status bits", &state::flags}}};
    std::size_t i = 8;
    if constexpr (softens_with_slip) a[i++] = f{"u_slip", "m", &state::u_slip};
    if constexpr (softens_with_crushing) a[i++] = f{"u_crush", "m", &state::u_crush};
    a[i] = f{"flags", "contact_status bits", &state::flags};
    return a;
  }();
  // Ten reals (one more with each of u_slip, u_crush) and the flags (padded to one more): a field added to `state` must be declared above.
  static_assert(sizeof(state) == (real_column_count(state_fields) + 1) * sizeof(real),
                "state has a field that state_fields does not declare");
  /// Throws invalid_input naming the first bad parameter: k_n, k_s finite and > 0, then the
  /// tension, compression and shear policies' checks (tension.hpp, compression.hpp, shear.hpp).
  static void validate(const params& p) {
    detail::require_positive(p.k_n, "normal stiffness k_n", "Pa/m");
    detail::require_positive(p.k_s, "shear stiffness k_s", "Pa/m");
    Tension::validate(p.tension, p.k_n);
    if constexpr (softens_with_crushing)
      Compression::validate_with_stiffness(p.compression, p.k_n);
    else
      Compression::validate(p.compression);
    if constexpr (softens_with_slip)
      Shear::validate_with_stiffness(p.shear, p.k_s);
    else
      Shear::validate(p.shear);
  }

  /// State of a sub-contact that was never bonded (contact::material_table::never_bonded): broken
  /// in tension and slipped from the start, so it carries no tension, no shear while open, and
  /// shears on the residual limit c_res + sigma_c tan phi_res when closed (give c_res = 0 for a
  /// purely frictional interface such as a steel plate resting on concrete).
  [[nodiscard]] static state unbonded_state(const params& /*p*/) noexcept {
    state s{};
    s.flags = contact_status::broken_tension | contact_status::slipped;
    return s;
  }

  /// Scales the stresses by r in (0, 1]: contact::detected_contacts keeps a sub-contact's force
  /// when a rebuild grows its tributary area by 1/r. tau times r; in compression, and in tension
  /// while the contact has not started to soften (a bonded face, detected_contacts'
  /// params::bond_faces), sigma_n times r and the opening with it (sigma_n = k_n (u_n - u_p) on
  /// those branches); a softening contact keeps its tension, which lies on its envelope. The
  /// stored energy per area drops by r^2, or stays for a softening contact.
  static void scale_stresses(const params& p, state& s, real r) noexcept {
    s.tau *= r;
    const bool elastic_tension = s.sigma_n > 0 && !has(s.flags, contact_status::softening) &&
                                 !has(s.flags, contact_status::broken_tension);
    if (s.sigma_n < 0 || elastic_tension) {
      s.sigma_n *= r;
      s.u_n = s.u_p + s.sigma_n / p.k_n;
    }
  }

  [[nodiscard]] static real normal_stiffness(const params& p) noexcept { return p.k_n; }  ///< k_n (Pa/m)
  [[nodiscard]] static real shear_stiffness(const params& p) noexcept { return p.k_s; }  ///< k_s (Pa/m)

  // ---- elastic path over packs of sub-contacts (opt-in of law::ElasticPackLaw, concepts.hpp) ----
  // In almost every step of almost every sub-contact the damage flags stay as they are: the
  // contact is elastic (intact, or softened, broken or slipped but below its current limits),
  // advances along its softening envelope, or slides on its residual Coulomb limit. Only reaching
  // the peak, breaking, a first slip and a compressive cap change them. contact::face_contacts
  // runs update_elastic over lanes::pack's of sub-contacts, keeps the lanes it accepts and runs
  // update() on the others from their unchanged state. Both are the one function step<>, so an
  // accepted lane is update()'s result to the bit (test_contacts "[pack]").

  /// True: update_elastic exists (the shear policy evaluates its strength on packs).
  static constexpr bool elastic_pack = PackedShearLimit<Shear>;

  /// Lanes of update_elastic: T = real (one sub-contact) or lanes::pack.
  template <class T>
  struct elastic_lanes {
    /** in: update()'s du_n (m) and du_s (m) */ /**@{*/ T du_n, ds0, ds1, ds2; /**@}*/
    /** in: update()'s unit normal n */ /**@{*/ T n0, n1, n2; /**@}*/
    /** in/out: state fields */ /**@{*/ T sigma_n, tau0, tau1, tau2, u_n, dissipated_tension, dissipated_shear,
        dissipated_compression, u_p, u_soft; /**@}*/
    T f_t;       ///< in/out: tensile_strength(p, state), a function of u_soft and the flags
    /// in/out: the state's u_slip (m) when softens_with_slip (set after the aggregate's other members)
    [[no_unique_address]] std::conditional_t<softens_with_slip, T, detail::no_slip> u_slip{};
    /// in/out: the state's u_crush (m) when softens_with_crushing
    [[no_unique_address]] std::conditional_t<softens_with_crushing, T, detail::no_crush> u_crush{};
  };

  /// Advances `s` by one step (see the file comment). du_n: opening increment (m, + opens);
  /// du_s: tangential relative displacement increment of B w.r.t. A (m, in the plane of n);
  /// n: current unit contact normal, A -> B. The one physics path, step<real, true> (below),
  /// with every transition (peak, breaking, a first slip, the compressive cap) taken.
  [[gnu::always_inline]] static inline void update(const params& p, state& s, real du_n, const vec3& du_s,
                                                  const vec3& n) noexcept {
    auto x = detail::load_state_lanes<elastic_lanes<real>>(s, du_n, du_s, n, tensile_strength(p, s));
    if constexpr (softens_with_slip) x.u_slip = s.u_slip;
    if constexpr (softens_with_crushing) x.u_crush = s.u_crush;
    auto flags = static_cast<lanes::mask_lane>(s.flags);
    static_cast<void>(step<real, true>(p, flags, x));  // takes every lane: nothing declined
    detail::store_state_lanes(x, s);
    if constexpr (softens_with_slip) s.u_slip = x.u_slip;
    if constexpr (softens_with_crushing) s.u_crush = x.u_crush;
    s.flags = static_cast<contact_status>(flags);
  }

  /// update() of a contact broken in tension whose faces are apart without stress (sigma_n = 0,
  /// tau = 0) and stay apart over the step (u_n + du_n > u_p): the opening u_n advances by du_n
  /// (m), sigma_n and tau stay 0 (+0), nothing is dissipated, no flag changes; returns true. Any
  /// other contact: returns false, s untouched (call update()). The result is update()'s to the
  /// bit for a finite step (test_laws "[open]"): there the trial k_n (u_n - u_p) > 0 of a broken contact gives
  /// sigma_n = +0, the open crack drops its (zero) shear to +0, and every energy term it books is
  /// a signed zero, which leaves the sums as they are. A detecting contact set calls it first:
  /// most of a loose heap's sub-contacts are such gaps within the tolerance (the rubble scene:
  /// 88 % of its sub-contact steps), and it skips the law's divisions and square roots.
  [[nodiscard, gnu::always_inline]] static inline bool open_step(state& s, real du_n) noexcept {
    if (!has(s.flags, contact_status::broken_tension) || s.sigma_n != 0 || s.tau[0] != 0 || s.tau[1] != 0 ||
        s.tau[2] != 0)
      return false;
    const real u_n = s.u_n + du_n;
    if (!(u_n > s.u_p)) return false;
    s.u_n = u_n;
    s.sigma_n = 0;
    s.tau[0] = 0;
    s.tau[1] = 0;
    s.tau[2] = 0;
    return true;
  }

  /// update() of the lanes whose flags this step leaves unchanged, whatever their damage (`flags`:
  /// the lanes' contact_status bits, a lanes::mask for packs, an integer for T = real):
  ///   normal, not broken in tension: the trial normal stress k_n (u_n - u_p) at most the current
  ///     strength f_t (f_T before any softening; at least -f_c when bounded), or beyond it for a
  ///     softening contact (u_soft > 0) whose envelope is not exhausted by the step: returned onto
  ///     the envelope, u_soft, u_p and f_t advanced (if Tension has lane_strength, tension.hpp);
  ///   normal, broken in tension: sigma = min(0, k_n (u_n - u_p)) (not below -f_c when bounded);
  ///   shear: faces of a broken contact apart (u_n > u_p): no shear, its stored energy booked as
  ///     dissipated, as update() does; otherwise the shear trial within the Coulomb limit of the
  ///     lane's state (intact, softened with coulomb_coupled, broken, slipped), or beyond it for a
  ///     lane that has slipped before: scaled back onto the limit, the slip dissipation booked.
  /// Returns the mask of those lanes; for them the outputs are update()'s to the bit (it is the
  /// same function, step). The outputs of the other lanes are meaningless.
  template <class T, class F>
  [[nodiscard, gnu::always_inline]] static inline auto update_elastic(const params& p, F flags,
                                                                     elastic_lanes<T>& x) noexcept {
    return step<T, false>(p, flags, x);
  }

  /// The step of one sub-contact (T = real) or of a lanes::pack of them, written once.
  /// Transitions = false: lanes whose flags the step would change are declined (the mask returned
  /// says which were kept); Transitions = true (T = real only, update()): the peak, breaking, a
  /// first slip and the compressive cap are taken here too and `flags` is updated. The shared
  /// arithmetic is the file comment's steps 1-3 in select form; the transitions add the branches
  /// of tension_transition, the cap and the first slip. x.f_t must hold tensile_strength(p, state).
  /// One function on purpose (about 95 lines): it is the law's single physics path, the same
  /// text for one sub-contact and for a pack; split, the shared arithmetic would be spread again.
  template <class T, bool Transitions, class F>
  [[nodiscard, gnu::always_inline]] static inline auto step(const params& p, F& flags,
                                                           elastic_lanes<T>& x) noexcept {
    static_assert(!Transitions || std::is_same_v<T, real>, "transitions are taken one sub-contact at a time");
    using M = decltype(T{} < T{});
    constexpr auto bit = [](contact_status b) { return static_cast<lanes::mask_lane>(b); };
    const real k_n = p.k_n;
    // 1. Rotation of the stored shear stress into the current plane.
    contact::kinematics::rotate_into_plane(x.tau0, x.tau1, x.tau2, x.n0, x.n1, x.n2);
    // 2. Normal: elastic trial from the irreversible opening, then the limits.
    const T sigma_old = x.sigma_n;
    x.u_n = x.u_n + x.du_n;
    const T trial = k_n * (x.u_n - x.u_p);
    // Masks by bitwise operations only (lane_masks.hpp: integer lane compares are slow on SSE2).
    using detail::mask_not;
    using detail::mask_select;
    M broken = detail::flag_mask<M>(flags, bit(contact_status::broken_tension));
    M slipped = detail::flag_mask<M>(flags, bit(contact_status::slipped));
    const M softening = detail::flag_mask<M>(flags, bit(contact_status::softening));
    // Not broken: returned onto the envelope when trial > 0 and trial > f_t; broken: min(0, trial).
    T sigma = mask_select(broken & mask_not(trial < real(0)), T{}, trial);
    const M beyond_envelope = mask_not(broken) & (trial > real(0)) & (trial > x.f_t);
    M elastic = mask_not(beyond_envelope);
    if constexpr (requires { Tension::lane_strength(p.tension, k_n, x.u_soft); }) {
      // A softening contact pushed further along its envelope, unless the step exhausts it. The
      // softening flag, which every unbroken state with u_soft > 0 carries, lets a caller that
      // passes constant zero flags (all lanes intact) have the branch folded away.
      const M advance = beyond_envelope & softening & (x.u_soft > real(0));
      if (lanes::any(advance)) [[unlikely]] {
        const T u_soft = x.u_soft + (trial - x.f_t) / k_n;
        const T f_new = Tension::lane_strength(p.tension, k_n, u_soft);
        const M on_envelope = advance & mask_not(Tension::lane_exhausted(p.tension, f_new));
        x.u_soft = mask_select(on_envelope, u_soft, x.u_soft);
        x.u_p = mask_select(on_envelope, x.u_n - f_new / k_n, x.u_p);
        x.f_t = mask_select(on_envelope, f_new, x.f_t);
        sigma = mask_select(on_envelope, f_new, sigma);
        elastic = elastic | on_envelope;
      }
    }
    if constexpr (Transitions) {
      if (!elastic) [[unlikely]]  // the peak reached, or the envelope exhausted: flags change
        sigma = detail::tension_transition<cohesive_frictional>(p, x, flags, trial);
      broken = detail::flag_mask<M>(flags, bit(contact_status::broken_tension));
    }
    if constexpr (softens_with_crushing) {  // the cap softened by u_crush; a first crush sets `crushed`
      detail::crush_lanes<Compression, Transitions>(p.compression, k_n, flags, x, sigma, elastic);
    } else if constexpr (Compression::bounded) {
      const real f_c = Compression::strength(p.compression);
      if constexpr (Transitions) {
        if (sigma < -f_c) {
          sigma = -f_c;
          x.u_p = x.u_n + f_c / k_n;
        }
      } else {
        elastic = elastic & mask_not(sigma < -f_c);
      }
    }
    x.sigma_n = sigma;
    book_normal_dissipation(k_n, sigma_old, sigma, x.du_n, x.dissipated_tension, x.dissipated_compression);
    // 3. Shear: trial against the Coulomb limit of the state; an open crack (broken, faces apart)
    //    carries none and its stored shear energy is booked as dissipated.
    const real k_s = p.k_s;
    T c0 = x.tau0 + k_s * x.ds0, c1 = x.tau1 + k_s * x.ds1, c2 = x.tau2 + k_s * x.ds2;
    const T trial_sq = (c0 * c0 + c1 * c1) + c2 * c2;
    T fraction = lanes::splat<T>(1);  // tensile_fraction()
    if constexpr (Shear::couples_tension) {
      const real f_peak = Tension::peak_strength(p.tension);
      const T softened = f_peak > 0 ? x.f_t / f_peak : T{};
      fraction = mask_select((x.u_soft > real(0)) & mask_not(broken), softened, fraction);
    }
    T tau_max, crush_scale = lanes::splat<T>(1);  // f(u_crush)/f_c with softening_cap's scales_shear
    if constexpr (softens_with_slip)
      tau_max = Shear::lane_slip_strength(p.shear, sigma, broken, x.u_slip);
    else
      tau_max = Shear::lane_strength(p.shear, sigma, slipped, broken, fraction);
    if constexpr (softens_with_crushing)
      if (p.compression.scales_shear) {
        crush_scale = Compression::lane_strength(p.compression, x.u_crush) * (1 / Compression::strength(p.compression));
        tau_max = crush_scale * tau_max;
      }
    const M open = broken & (x.u_n > x.u_p);
    // Beyond the limit: a lane that has slipped before slides on it; a first slip changes the flags.
    const M beyond = mask_not(open) & (trial_sq > tau_max * tau_max);
    if constexpr (Transitions) {
      if (beyond && !slipped) [[unlikely]] {
        flags = flags | bit(contact_status::slipped);
        slipped = true;
        if constexpr (!softens_with_slip) tau_max = crush_scale * Shear::lane_strength(p.shear, sigma, slipped, broken, fraction);
        if constexpr (requires { p.shear.slip_breaks_tension; })
          if (p.shear.slip_breaks_tension) detail::break_on_slip<cohesive_frictional>(p, x, flags);
      }
    } else {
      elastic = elastic & mask_not(beyond & mask_not(slipped));
    }
    const M limited = open | (beyond & slipped);
    if (lanes::any(limited)) [[unlikely]] {
      // Never above 1: at a first slip the residual limit can exceed the trial (phi_res > phi_0
      // under compression), and scaling the stress up would create energy; the stress then stays.
      const T trial_norm = lanes::sqrt(trial_sq);
      if constexpr (softens_with_slip) {  // the limit softens during the step: its closed-form return
        const M sliding = beyond & slipped;  // not the open cracks alone (their stress is dropped)
        if (lanes::any(sliding)) {
          const auto r = Shear::lane_slip_return(p.shear, k_s, sigma, broken, x.u_slip, trial_norm, crush_scale);
          tau_max = mask_select(sliding, r.tau, tau_max);
          x.u_slip = mask_select(sliding, r.slip, x.u_slip);
        }
      }
      const T ratio = tau_max / trial_norm;
      const T scale = lanes::select(ratio < real(1), ratio, lanes::splat<T>(1));
      c0 = mask_select(open, T{}, mask_select(beyond, c0 * scale, c0));
      c1 = mask_select(open, T{}, mask_select(beyond, c1 * scale, c1));
      c2 = mask_select(open, T{}, mask_select(beyond, c2 * scale, c2));
      const real inv_k_s = 1 / k_s;
      const T w0 = x.ds0 - (c0 - x.tau0) * inv_k_s, w1 = x.ds1 - (c1 - x.tau1) * inv_k_s,
              w2 = x.ds2 - (c2 - x.tau2) * inv_k_s;
      const T dissipated = x.dissipated_shear +
                           real(0.5) * (((x.tau0 + c0) * w0 + (x.tau1 + c1) * w1) + (x.tau2 + c2) * w2);
      x.dissipated_shear = mask_select(limited, dissipated, x.dissipated_shear);
    }
    x.tau0 = c0;
    x.tau1 = c1;
    x.tau2 = c2;
    return elastic;
  }

  [[nodiscard]] static contact_status status(const state& s) noexcept { return s.flags; }  ///< The state's flags (broken, slipped, ...)

  /// Current tensile strength f_t (Pa): f_T for a virgin contact, f_t(u_soft) while softening, 0 once broken.
  [[nodiscard]] static real tensile_strength(const params& p, const state& s) noexcept {
    if (has(s.flags, contact_status::broken_tension)) return 0;
    return s.u_soft > 0 ? Tension::strength(p.tension, p.k_n, s.u_soft) : Tension::peak_strength(p.tension);
  }
  /// 1 - f_t/f_T in [0, 1]: 0 intact, 1 broken in tension (a no_tension contact: 0 until broken).
  [[nodiscard]] static real tensile_damage(const params& p, const state& s) noexcept {
    if (has(s.flags, contact_status::broken_tension)) return 1;
    const real f_peak = Tension::peak_strength(p.tension);
    return f_peak > 0 ? std::clamp(1 - tensile_strength(p, s) / f_peak, real(0), real(1)) : real(0);
  }
  /// Current Coulomb limit tau_max (Pa) at the stored normal stress (and plastic slip, when it softens with it;
  /// times f(u_crush)/f_c with softening_cap's scales_shear).
  [[nodiscard]] static real shear_strength(const params& p, const state& s) noexcept {
    real scale = 1;
    if constexpr (softens_with_crushing)
      if (p.compression.scales_shear) scale = compressive_strength(p, s) * (1 / Compression::strength(p.compression));
    if constexpr (softens_with_slip) return scale * Shear::slip_strength(p.shear, s.sigma_n, s.flags, s.u_slip);
    else return scale * Shear::strength(p.shear, s.sigma_n, s.flags, tensile_fraction(p, s));
  }
  /// Current compressive cap (Pa, a magnitude): f_c, or f(u_crush) with softening_cap; +inf unbounded.
  [[nodiscard]] static real compressive_strength(const params& p, const state& s) noexcept {
    if constexpr (softens_with_crushing) return Compression::lane_strength(p.compression, s.u_crush);
    else return Compression::strength(p.compression);
  }
  /// Energy dissipated so far by all mechanisms (J/m^2).
  [[nodiscard]] static real dissipated_energy(const state& s) noexcept {
    return s.dissipated_tension + s.dissipated_shear + s.dissipated_compression;
  }
  /// Recoverable elastic energy sigma_n^2/(2 k_n) + |tau|^2/(2 k_s) (J/m^2).
  [[nodiscard]] static real stored_energy(const params& p, const state& s) noexcept {
    return s.sigma_n * s.sigma_n / (2 * p.k_n) + s.tau.squaredNorm() / (2 * p.k_s);
  }

 private:
  /// The normal part of the dissipated increment (file comment, "Energy"), booked to compression
  /// when sigma_old + sigma < 0 and to tension otherwise; T = real or a lanes::pack.
  template <class T>
  [[gnu::always_inline]] static inline void book_normal_dissipation(real k_n, T sigma_old, T sigma, T du_n, T& tension,
                                                                   T& compression) noexcept {
    const T sigma_sum = sigma_old + sigma;
    const T dissipation = real(0.5) * sigma_sum * (du_n - (sigma - sigma_old) / k_n);
    const auto compressive = sigma_sum < real(0);
    compression = lanes::select(compressive, compression + dissipation, compression);
    tension = lanes::select(compressive, tension, tension + dissipation);
  }

  /// f_t/f_T for the shear policy: 1 unless the policy couples cohesion to tension and the contact
  /// has softened (then the envelope is evaluated; a decoupled law never pays for it).
  [[nodiscard]] static real tensile_fraction(const params& p, const state& s) noexcept {
    if constexpr (Shear::couples_tension) {
      if (s.u_soft > 0 && !has(s.flags, contact_status::broken_tension)) {
        const real f_peak = Tension::peak_strength(p.tension);
        return f_peak > 0 ? Tension::strength(p.tension, p.k_n, s.u_soft) / f_peak : real(0);
      }
    }
    return 1;
  }
};

}  // namespace tessera::law
