#pragma once
// The copies between one sub-contact's state and its lanes (a law's elastic_lanes<real>), for the
// fields every pack law shares (cohesive_frictional, mixed_mode_cohesive): the increments, the
// stresses, openings and dissipated energies. The flags and a law's own fields are the law's to copy.

#include "../../core/types.hpp"

namespace tessera::law::detail {

/// The member u_slip (u_crush) of a law whose shear limit (cap) does not soften with slip (crushing): nothing stored.
struct no_slip {};
struct no_crush {};  ///< see no_slip

/// The lanes of one sub-contact's step: the increments du_n (m), du_s (m), the normal n, the state
/// s's stresses, openings and dissipated energies, and its current tensile strength f_t (Pa).
template <class Lanes, class State, class Vec>
[[nodiscard, gnu::always_inline]] inline Lanes load_state_lanes(const State& s, real du_n, const Vec& du_s, const Vec& n,
                                                               real f_t) noexcept {
  return Lanes{du_n,     du_s[0],  du_s[1],  du_s[2], n[0],  n[1],  n[2],  s.sigma_n, s.tau[0],
               s.tau[1], s.tau[2], s.u_n,    s.dissipated_tension, s.dissipated_shear,
               s.dissipated_compression, s.u_p, s.u_soft, f_t};
}

/// s.sigma_n, s.tau, s.u_n, s.u_p, s.u_soft and the three dissipated energies from the lanes x.
template <class Lanes, class State>
[[gnu::always_inline]] inline void store_state_lanes(const Lanes& x, State& s) noexcept {
  s.sigma_n = x.sigma_n;
  s.tau[0] = x.tau0;
  s.tau[1] = x.tau1;
  s.tau[2] = x.tau2;
  s.u_n = x.u_n;
  s.u_p = x.u_p;
  s.u_soft = x.u_soft;
  s.dissipated_tension = x.dissipated_tension;
  s.dissipated_shear = x.dissipated_shear;
  s.dissipated_compression = x.dissipated_compression;
}

}  // namespace tessera::law::detail
