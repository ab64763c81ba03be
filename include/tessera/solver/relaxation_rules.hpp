#pragma once
// The adaptive-damping rule's per-node_set state for kinetic_relaxation (solver/relaxation.hpp,
// relaxation_options::method::adaptive): kept apart so the relaxation's header stays readable.

#include <cstdint>

#include "../core/nodes.hpp"
#include "../core/types.hpp"

namespace tessera::detail {

/// The adaptive rule's state of one node_set: the free components' velocities after the last
/// step and the forces of that step (m/s, N; n's layout; only the free components are kept up).
struct adaptive_damping_state {
  static constexpr auto free = static_cast<std::uint8_t>(dof_constraint::free);
  soa3 velocity, force;
  void begin(const node_set& n) { velocity = n.velocity, force = n.force; }
  /// Adds sum x^2 k and sum m x^2 over the free components (x at the step's start, u_n, counted
  /// from the displacements `origin`, m).
  void sums(const node_set& n, const soa3& origin, real dt, real& stiffness, real& mass) const {
    for (int c = 0; c < 3; ++c)
      for (index_t i = 0; i < n.size(); ++i) {
        if (n.constraint(i, c) != free) continue;
        const real x = n.displacement(i, c) - dt * n.velocity(i, c) - origin(i, c), w = velocity(i, c);
        mass += n.mass[i] * x * x;
        if (w != 0) stiffness -= x * x * (n.force(i, c) - force(i, c)) / (dt * w);
      }
  }
  /// The viscous step's velocity in place of the undamped one (damping c dt), u following it.
  void damp(node_set& n, real dt, real cdt) {
    for (int c = 0; c < 3; ++c)
      for (index_t i = 0; i < n.size(); ++i) {
        if (n.constraint(i, c) != free) continue;
        const real v = n.velocity(i, c), damped = (2 * v - cdt * velocity(i, c)) / (2 + cdt);
        n.displacement(i, c) += (damped - v) * dt;
        n.velocity(i, c) = damped;
        velocity(i, c) = damped, force(i, c) = n.force(i, c);
      }
  }
};

}  // namespace tessera::detail
