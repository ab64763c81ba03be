#pragma once
// Energy bookkeeping of a run (J). The work supplied by the supports must equal the energy
// held and dissipated in the model:
//     initial + W_boundary + W_gravity + W_applied = E_kinetic + E_blocks + E_contacts,stored + D_contacts + D_damping
//                            + E_bars,stored + D_bars
// W_boundary (reaction x velocity at prescribed components, trapezoidal), W_gravity (weight x
// half-step velocity x dt, exact for a constant force), W_applied (solver::applied_forces, booked
// the same way) and D_damping (local
// damping force x velocity) are accumulated every step inside the integrator loop; the other
// terms are state functions evaluated on demand. The residual measures the time-discretisation
// error and any missing physics, so it is the run's first sanity check.

#include <algorithm>
#include <cmath>

#include "../core/types.hpp"

namespace tessera {

/// The energy books of a run (J): what went in, what is stored, what left; error_rel() closes them
struct energy_balance {
  real initial = 0;                   ///< kinetic + stored energy when the run started
  real boundary_work = 0;             ///< work of the support reactions (J)
  real gravity_work = 0;              ///< work of gravity on blocks (J; solver::set_gravity)
  real applied_work = 0;              ///< work of the applied forces (J; solver::applied_forces)
  real kinetic = 0;                   ///< 1/2 m v^2 of gridpoints, bar nodes (and rigid bodies)
  real block_elastic = 0;             ///< elastic energy in the zones (1/2 V sigma : eps)
  real contact_stored = 0;            ///< elastic energy in the contact springs
  real contact_dissipated = 0;        ///< dissipated by contact softening, slip and crushing
  real contact_dissipated_tension = 0;  ///< the tensile part of contact_dissipated
  real damping_dissipated = 0;        ///< removed by the local damping
  real reinforcement_stored = 0;      ///< elastic energy of bars and bond springs
  real reinforcement_dissipated = 0;  ///< bar yielding and bond slip
  real contact_rebuild_exchange = 0;  ///< put into contact springs by re-discretising detected patches (J)
  /// The largest |W_boundary| + |W_gravity| + |W_applied| after any step so far (J): not a term of
  /// the balance but the step checker's measure of the energy a run was given (checks::default_step_checker),
  /// since the works themselves return to zero with every swing of an undamped block back to its start.
  /// Not checkpointed: a resumed run starts it again from its current works.
  real peak_work = 0;

  /// Energy accounted for in the model (J).
  [[nodiscard]] real accounted() const {
    return kinetic + block_elastic + contact_stored + contact_dissipated + damping_dissipated + reinforcement_stored +
           reinforcement_dissipated;
  }
  /// Energy supplied: initial + W_boundary + W_gravity + W_applied + the rebuild exchange of detected
  /// contacts (J; the last is no physical work: it is booked so the balance measures the
  /// integration, and reported on its own).
  [[nodiscard]] real supplied() const { return initial + boundary_work + gravity_work + applied_work + contact_rebuild_exchange; }
  /// |supplied - accounted| / max(|supplied|, tiny): relative energy balance error.
  [[nodiscard]] real error_rel() const {
    const real supplied = this->supplied();
    return std::abs(supplied - accounted()) / std::max(std::abs(supplied), 1e-300);
  }
};

}  // namespace tessera
