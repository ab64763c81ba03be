#pragma once
// What a solver reports about its state (solver/solver.hpp calls these; not a public interface):
// the state terms of its energy books (solver/energy.hpp: kinetic, stored and dissipated energies
// of blocks, contacts and bars), the work of gravity over one step, and the out-of-balance of the
// last step (solver/balance.hpp). The accumulated terms (boundary, damping, gravity and applied
// work) are the solver's own state; these functions read the parts they are given.
//
// Cost: O(zones + sub-contacts + nodes) for the books, O(nodes) for the rest. Thread safety: pure
// functions; the parallel sums are deterministic (bit-identical for any thread count).

#include <cstdint>

#include "../../core/nodes.hpp"
#include "../../core/parallel.hpp"
#include "../../core/types.hpp"
#include "../balance.hpp"
#include "../energy.hpp"

namespace tessera::detail {

/// 1/2 m v^2 of the bar nodes (J; half-step velocities, scaled masses), a deterministic parallel sum.
[[nodiscard]] inline real bar_kinetic_energy(const node_set& bars) {
  return deterministic_sum(bars.size(),
                           [&](std::int64_t i) { return 0.5 * bars.mass[i] * bars.velocity.row(i).squaredNorm(); });
}

/// Kinetic plus stored energy of blocks, contacts and bars (J): energy_balance::initial at the
/// first step (the bars' kinetic energy summed serially, in index order).
template <class Blocks, class Contacts, class Reinforcement>
[[nodiscard]] real stored_and_kinetic(const Blocks& blocks, const node_set& gridpoints, const Contacts& contacts,
                                      const Reinforcement& reinforcement) {
  real e = blocks.kinetic_energy(gridpoints) + blocks.stored_energy(gridpoints) + contacts.energies().stored;
  if constexpr (Reinforcement::enabled) {
    const node_set& bars = reinforcement.nodes();
    for (index_t i = 0; i < bars.size(); ++i) e += 0.5 * bars.mass[i] * bars.velocity.row(i).squaredNorm();
    e += reinforcement.stored_energy();
  }
  return e;
}

/// Fills the state terms of e (J): kinetic (blocks and bar nodes), block_elastic, the contact
/// set's stored, dissipated and rebuild terms, the bars' stored and dissipated energy.
template <class Blocks, class Contacts, class Reinforcement>
void add_state_energies(energy_balance& e, const Blocks& blocks, const node_set& gridpoints, const Contacts& contacts,
                        const Reinforcement& reinforcement) {
  e.kinetic = blocks.kinetic_energy(gridpoints);
  e.block_elastic = blocks.stored_energy(gridpoints);
  const auto c = contacts.energies();
  e.contact_stored = c.stored;
  e.contact_dissipated = c.dissipated;
  e.contact_dissipated_tension = c.dissipated_tension;
  e.contact_rebuild_exchange = c.rebuild_exchange;
  if constexpr (Reinforcement::enabled) {
    e.kinetic += bar_kinetic_energy(reinforcement.nodes());
    e.reinforcement_stored = reinforcement.stored_energy();
    e.reinforcement_dissipated = reinforcement.dissipated_energy();
  }
}

/// Power of gridpoint i's weight (W): (m0_i g) . v_i, the term gravity_work_of_step sums.
[[nodiscard]] inline real weight_power(const soa3& gravity_force, const node_set& gridpoints, std::int64_t i) {
  return (gravity_force(i, 0) * gridpoints.velocity(i, 0) + gravity_force(i, 1) * gridpoints.velocity(i, 1)) +
         gravity_force(i, 2) * gridpoints.velocity(i, 2);
}

/// Work of the gridpoints' weights over one step (J): sum_i (m0_i g) . v_i(t + dt/2) dt, the exact
/// work of a constant force (deformable blocks; gravity_force one row per gridpoint, N).
[[nodiscard]] inline real gravity_work_of_step(const soa3& gravity_force, const node_set& gridpoints, real dt) {
  return deterministic_sum(gridpoints.size(), [&](std::int64_t i) { return weight_power(gravity_force, gridpoints, i); }) * dt;
}

/// Unbalanced force of the last step over free components (solver::unbalanced_force): of the
/// gridpoints (deformable blocks) or of the blocks' translations (rigid blocks), then of the bar
/// nodes, whose max_node counts on from the gridpoints or blocks. Serial, in index order.
template <class Blocks, class Reinforcement>
[[nodiscard]] out_of_balance unbalanced_force(const Blocks& blocks, const node_set& gridpoints,
                                              const Reinforcement& reinforcement) {
  out_of_balance b;
  if constexpr (Blocks::is_rigid) {
    for (index_t k = 0; k < blocks.block_count(); ++k)
      b.add_free(k, [&](int c) { return !blocks.translation_prescribed(k, c); },
                 [&](int c) { return blocks.force(k)[c]; });
  } else {
    for (index_t i = 0; i < gridpoints.size(); ++i) b.add(gridpoints, i);
  }
  if constexpr (Reinforcement::enabled) {
    const index_t offset = Blocks::is_rigid ? blocks.block_count() : gridpoints.size();
    const node_set& bars = reinforcement.nodes();
    for (index_t i = 0; i < bars.size(); ++i) b.add(bars, i, offset + i);
  }
  return b;
}

}  // namespace tessera::detail
