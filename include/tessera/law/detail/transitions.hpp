#pragma once
// The tension transitions of law::cohesive_frictional that change a sub-contact's flags, taken one
// sub-contact at a time by its step<real, true> (cohesive_frictional.hpp's file comment, steps 2-3):
// the peak reached or the envelope exhausted (tension_transition), and the opt-in break of the
// tensile strength at a first shear failure (break_on_slip). Law = the cohesive_frictional
// instance (its tension_policy, compression_policy, params and elastic_lanes).

#include <algorithm>
#include <cstdint>

#include "../../core/lanes.hpp"
#include "../../core/types.hpp"
#include "../concepts.hpp"

namespace tessera::law::detail {

/// The flags s without `flag`.
[[nodiscard]] constexpr contact_status without(contact_status s, contact_status flag) noexcept {
  return static_cast<contact_status>(static_cast<std::uint8_t>(s) & ~static_cast<std::uint8_t>(flag));
}

/// Shear failure that also ends the tensile strength (opt-in, Shear::params::slip_breaks_tension):
/// the contact is marked broken in tension and u_p is reset to the compressive plastic closure,
/// so from the next step on it carries compression only, and no shear while its faces are apart.
/// The normal stress of this step stands; its stored energy is released, and booked as
/// dissipated in tension, by the next step's trapezoidal increment.
template <class Law, class F>
void break_on_slip(const typename Law::params& p, typename Law::template elastic_lanes<real>& x, F& flags) noexcept {
  using Tension = typename Law::tension_policy;
  using Compression = typename Law::compression_policy;
  if ((flags & static_cast<lanes::mask_lane>(contact_status::broken_tension)) != 0) return;
  real closure = 0;
  if constexpr (Compression::bounded) {
    // u_p = closure + w + (f_T - f_t(w))/k_n on or below the envelope, closure alone while intact
    const real f_peak = Tension::peak_strength(p.tension);
    closure = x.u_soft > 0 ? x.u_p - x.u_soft - (f_peak - Tension::strength(p.tension, p.k_n, x.u_soft)) / p.k_n
                           : x.u_p;
  }
  x.u_p = closure;
  flags = static_cast<F>(without(static_cast<contact_status>(flags), contact_status::softening) |
                         contact_status::broken_tension);
}

/// The tension transitions of one sub-contact whose trial stress `trial` > 0 exceeds its current
/// strength x.f_t and that step<> did not return onto its envelope: the peak reached (softening
/// starts) or the envelope exhausted (broken for good). Returns the normal stress and updates
/// u_soft, u_p, f_t and the flags.
template <class Law, class F>
real tension_transition(const typename Law::params& p, typename Law::template elastic_lanes<real>& x, F& flags,
                        real trial) noexcept {
  using Tension = typename Law::tension_policy;
  using Compression = typename Law::compression_policy;
  const real k_n = p.k_n;
  const real f_peak = Tension::peak_strength(p.tension);
  x.u_soft += (trial - x.f_t) / k_n;
  const real f_new = Tension::strength(p.tension, k_n, x.u_soft);
  const auto status = static_cast<contact_status>(flags);
  if (Tension::exhausted(p.tension, f_new)) [[unlikely]] {
    // Broken: the faces separate from the position they had before any tension, shifted by the
    // compressive plastic closure (u_n = eta + u_soft + closure on the envelope).
    real closure = 0;
    if constexpr (Compression::bounded) closure = x.u_n - x.u_soft - f_peak / k_n;
    x.u_p = closure;
    x.f_t = 0;
    flags = static_cast<F>(without(status, contact_status::softening) | contact_status::broken_tension);
    return std::min(real(0), k_n * (x.u_n - x.u_p));
  }
  x.u_p = x.u_n - f_new / k_n;
  x.f_t = f_new;
  flags = static_cast<F>(status | contact_status::softening);
  return f_new;
}

}  // namespace tessera::law::detail
