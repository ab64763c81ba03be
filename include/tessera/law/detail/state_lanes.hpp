#pragma once
// The copy of one sub-contact's lanes (a law's elastic_lanes<real>) back into its state, for the
// fields every pack law shares (cohesive_frictional, mixed_mode_cohesive): the stresses, openings
// and dissipated energies. The flags and a law's own fields are the law's to copy.

namespace tessera::law::detail {

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
