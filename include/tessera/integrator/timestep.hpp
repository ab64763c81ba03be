#pragma once
// Stable time step of the explicit central-difference scheme (study eq. 3) and mass scaling.
//
// Bound. Undamped central differences are stable when dt <= 2 / omega_max, omega_max^2 =
// lambda_max(M^-1 K). With a lumped (diagonal, isotropic per node) mass M, Gershgorin's theorem
// applied to M^-1 K gives
//     lambda_max(M^-1 K) <= max_i sum_j |K_ij| / m_i = max_i k_i / m_i,
// k_i = the largest absolute row sum over the node's three rows ("nodal stiffness", assembled
// by add_stiffness_bounds of zones, contacts and bonds as sums of element row sums, which bound
// the row sums of the assembled |K|). Hence
//     dt_cr = min_i 2 sqrt(m_i / k_i) <= 2 / omega_max,
// is provably stable for the undamped linear scheme, and dt = safety dt_cr with safety = 0.9
// leaves margin for the stiffness changes during a step (contacts re-closing, rotations of
// contact frames). Local damping LOWERS the limit: in the phase where the force opposes the
// velocity the update sees (1 + gamma) K (integrator/damping.hpp), so every function here takes
// the damping's stiffness amplification a and uses k_i -> a k_i:
//     dt_cr = min_i 2 sqrt(m_i / (a k_i)).
//
// Mass scaling (quasi-static runs, the study scales masses too): for a target step dt*, every
// node with 2 safety sqrt(m_i / (a k_i)) < dt* gets m_i = a k_i (dt* / (2 safety))^2, so the target
// step is exactly the scaled stable step of those nodes. The added mass is reported; inertia
// effects stay small when the loading is slow compared with the scaled wave speed.

#include <cmath>
#include <limits>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"

namespace tessera::integrator {

/// Default safety factor on the Gershgorin critical step.
inline constexpr real default_safety = 0.9;

/// The critical step of a node set and the node that limits it.
struct critical_step {
  real dt = std::numeric_limits<real>::infinity();  ///< min_i 2 sqrt(m_i / (a k_i)) (s), unscaled by safety
  index_t node = invalid_index;                       ///< limiting node
  real mass = 0;                                    ///< its mass (kg)
  real stiffness = 0;                               ///< its stiffness bound (N/m)
};

/// min_i 2 sqrt(m_i / (a k_i)) over the nodes with k_i > 0 (s), a = stiffness amplification of the
/// damping (1 undamped). Throws invalid_input naming the node for a non-finite or negative
/// stiffness bound, a non-finite mass, or a positive stiffness on a non-positive mass.
[[nodiscard]] inline critical_step critical_time_step(const node_set& nodes, real amplification = 1) {
  require(amplification >= 1, "time step: stiffness amplification a = ", amplification, " must be >= 1");
  critical_step out;
  for (index_t i = 0; i < nodes.size(); ++i) {
    const real k = nodes.stiffness[i];
    const real m = nodes.mass[i];
    require(std::isfinite(k) && k >= 0, "time step: node ", i, " has stiffness bound k = ", k,
            " N/m; expected finite and >= 0 (a non-finite stiffness, modulus or area upstream)");
    require(std::isfinite(m), "time step: node ", i, " has mass ", m, " kg; expected finite and > 0");
    if (k == 0) continue;
    require(m > 0, "time step: node ", i, " has stiffness ", k, " N/m but mass ", m, " kg; expected mass > 0");
    const real dt = 2 * std::sqrt(m / (amplification * k));
    if (dt < out.dt) out = {dt, i, m, k};
  }
  return out;
}

/// Result of scale_masses.
struct mass_scaling_report {
  real added_mass = 0;     ///< sum of the mass added (kg)
  real original_mass = 0;  ///< sum of the masses before scaling (kg)
  index_t scaled_nodes = 0;  ///< number of nodes whose mass was raised
  /// Adds another node set's report (e.g. the bar nodes' to the gridpoints').
  mass_scaling_report& operator+=(const mass_scaling_report& o) noexcept {
    added_mass += o.added_mass;
    original_mass += o.original_mass;
    scaled_nodes += o.scaled_nodes;
    return *this;
  }
};

namespace detail {
/// The loop of scale_masses; with Apply = false it only reports what scaling would add.
template <bool Apply, class Nodes>
mass_scaling_report scale_masses_impl(Nodes& nodes, real target_dt, real safety, real amplification) {
  require_positive(target_dt, "mass scaling: target time step (s)");
  require(safety > 0 && safety <= 1, "mass scaling: safety factor = ", safety, " must lie in (0, 1]");
  require(amplification >= 1, "mass scaling: stiffness amplification a = ", amplification, " must be >= 1");
  mass_scaling_report rep;
  const real c = amplification * (target_dt / (2 * safety)) * (target_dt / (2 * safety));
  for (index_t i = 0; i < nodes.size(); ++i) {
    rep.original_mass += nodes.mass[i];
    const real needed = nodes.stiffness[i] * c;
    if (needed > nodes.mass[i]) {
      rep.added_mass += needed - nodes.mass[i];
      if constexpr (Apply) nodes.mass[i] = needed;
      ++rep.scaled_nodes;
    }
  }
  return rep;
}
}  // namespace detail

/// Raises m_i to a k_i (target_dt / (2 safety))^2 where that is larger, so that
/// safety * 2 sqrt(m_i / (a k_i)) >= target_dt for every node (see the file comment).
inline mass_scaling_report scale_masses(node_set& nodes, real target_dt, real safety = default_safety,
                                        real amplification = 1) {
  return detail::scale_masses_impl<true>(nodes, target_dt, safety, amplification);
}

/// What scale_masses(nodes, target_dt, safety, amplification) would add, leaving the nodes alone.
[[nodiscard]] inline mass_scaling_report preview_mass_scaling(const node_set& nodes, real target_dt,
                                                              real safety = default_safety, real amplification = 1) {
  return detail::scale_masses_impl<false>(nodes, target_dt, safety, amplification);
}

/// The mass-scaling target step at which the added mass is `ratio` times the original mass.
/// `added_ratio(dt)` returns added / original mass for a target step dt (e.g. from
/// preview_mass_scaling); it is 0 up to the unscaled stable step `stable_dt` and grows with dt
/// (each scaled node's mass goes as dt^2), so the step is found by bracketing and bisection to a
/// relative width of 1e-12. Why a ratio: the inertia that mass scaling adds to a quasi-static run
/// is what its error depends on, and a fixed step adds very different amounts to meshes of
/// different fineness (the RC tie at 2 us: 69x for 100 blocks, 403x for 500).
template <class AddedRatio>
[[nodiscard]] real step_for_added_mass(real ratio, real stable_dt, AddedRatio&& added_ratio) {
  require(std::isfinite(ratio) && ratio > 0, "mass scaling: target added-mass ratio = ", ratio, " must be finite and > 0");
  require_positive(stable_dt, "mass scaling: unscaled stable time step (s)");
  real lo = stable_dt, hi = 2 * stable_dt;
  for (int k = 0; added_ratio(hi) < ratio; ++k) {
    require(k < 200, "mass scaling: no time step reaches an added-mass ratio of ", ratio);
    lo = hi;
    hi *= 2;
  }
  while (hi - lo > 1e-12 * hi) {
    const real mid = 0.5 * (lo + hi);
    (added_ratio(mid) < ratio ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace tessera::integrator
