#pragma once
// Step checkers: the policy that watches a run for numerical blow-up (Odeint's checker idea:
// a separate policy, not code inside the stepper). The solver calls check(solver) every
// `interval` steps; no_step_checker removes the call at compile time.
//
// default_step_checker throws numerical_instability when
//  - a displacement, velocity or force of a gridpoint or bar node is not finite, or
//  - the kinetic energy exceeds growth_factor x (initial energy + boundary work) + floor: an
//    explicit scheme run stably can never hold more kinetic energy than it was given.
// The message names the worst node (first non-finite, else fastest), its block, its own stable
// step 2 sqrt(m/(a k)) against the step in use (a = damping's stiffness amplification), and the
// likely cause.
//
// | expression          | meaning                                                    |
// |---------------------|------------------------------------------------------------|
// | C::enabled          | constexpr bool; false removes every check                  |
// | c.interval          | steps between checks (>= 1)                                |
// | c.check(solver)     | throws numerical_instability with a diagnostic             |

#include <cmath>
#include <concepts>
#include <limits>
#include <string>
#include <type_traits>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"

namespace tessera::checks {

struct default_step_checker {
  static constexpr bool enabled = true;
  index interval = 100;       ///< steps between checks
  real growth_factor = 2.0;   ///< allowed ratio of kinetic energy to energy supplied
  real floor = 1e-12;         ///< J, absolute allowance (round-off before any loading)

  template <class Solver>
  void check(const Solver& s) const {
    struct worst_node {
      const char* set = "gridpoint";
      index node = invalid_index;
      bool non_finite = false;
      real speed = -1;
    } worst;
    const auto scan = [&](const node_set& nodes, const char* set) {
      for (index i = 0; i < nodes.size(); ++i) {
        const bool finite = nodes.displacement.row(i).allFinite() && nodes.velocity.row(i).allFinite() &&
                            nodes.force.row(i).allFinite();
        if (!finite) {
          if (!worst.non_finite) worst = {set, i, true, std::numeric_limits<real>::infinity()};
          continue;
        }
        const real v = nodes.velocity.row(i).norm();
        if (!worst.non_finite && v > worst.speed) worst = {set, i, false, v};
      }
    };
    scan(s.gridpoints(), "gridpoint");
    scan(s.bar_nodes(), "bar node");
    const auto e = s.energies();
    const real supplied = e.initial + std::abs(e.boundary_work);
    const bool energy_growth = !(e.kinetic <= growth_factor * supplied + floor);
    if (!worst.non_finite && !energy_growth) return;

    const bool is_gridpoint = std::string(worst.set) == "gridpoint";
    const node_set& nodes = is_gridpoint ? s.gridpoints() : s.bar_nodes();
    const index i = worst.node;
    const real m = i >= 0 ? nodes.mass[i] : 0, k = i >= 0 ? nodes.stiffness[i] : 0;
    const real a = s.stiffness_amplification();
    const real own_dt = k > 0 ? 2 * std::sqrt(m / (a * k)) : std::numeric_limits<real>::infinity();
    const char* cause = s.dt() > own_dt ? "time step above the stable limit of this node (raise its mass or lower dt)"
                        : m <= 0        ? "mass too small (zero or negative)"
                                        : "stiffness too high for the time step (a law or bond stiffer than the "
                                          "bound used for dt), or a load applied too fast";
    throw numerical_instability(detail::concat(
        "numerical instability at step ", s.step_count(), " (t = ", s.time(), " s): ",
        worst.non_finite ? "non-finite state at " : "kinetic energy ", worst.non_finite ? "" : std::to_string(e.kinetic),
        worst.non_finite ? "" : " J exceeds the energy supplied ", worst.non_finite ? "" : std::to_string(supplied),
        worst.non_finite ? "" : " J; fastest node is ", worst.set, " ", i,
        is_gridpoint && i >= 0 ? detail::concat(" of block ", s.gridpoint_block(i)) : std::string(),
        " (m = ", m, " kg, k = ", k, " N/m, its stable step 2 sqrt(m/(a k)) = ", own_dt, " s, dt = ", s.dt(),
        " s); likely cause: ", cause));
  }
};

struct no_step_checker {
  static constexpr bool enabled = false;
  index interval = std::numeric_limits<index>::max();
  template <class Solver>
  void check(const Solver&) const {}
};

}  // namespace tessera::checks
