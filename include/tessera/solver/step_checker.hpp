#pragma once
// Step checkers: the policy that watches a run for numerical blow-up (Odeint's checker idea:
// a separate policy, not code inside the stepper). The solver calls check(solver) every
// `interval` steps; no_step_checker removes the call at compile time (benchmarks).
//
// default_step_checker throws numerical_instability when
//  - a displacement, velocity or force component of a gridpoint or bar node, or the force of a
//    sub-contact, is not finite; or
//  - the kinetic energy exceeds the energy supplied by more than a stable scheme allows:
//        E_kin > growth_factor x (E_initial + W_peak + |E_rebuild|) / (1 - min(q, q_max)) + floor,
//        q = (dt/2)^2 max_i k_i/m_i   (over gridpoints and bar nodes),
//        W_peak = the largest |W_boundary| + |W_gravity| + |W_applied| after any step so far
//    (energy_balance::peak_work, tracked by the solver every step). The works of now would not do:
//    an undamped block dropped on a contact swings back to where it started, gravity's work with
//    it returns to zero, while the half-step kinetic energy there is not zero (a 1 m cube on a
//    stiff contact was stopped at step 2 000 of a sound run); the energy a run holds is never
//    more than the most it was given.
//    Why this tolerance: a stable run never holds more energy than it was given (initial kinetic +
//    stored energy plus the work of the supports and of gravity), but the solver's kinetic energy is taken at the
//    half step, and for leapfrog a mode u_n = A cos(n theta) conserves E = 1/2 k A^2 (1 - (omega dt/2)^2)
//    while its half-step kinetic energy peaks at 1/2 k A^2 = E / (1 - (omega dt/2)^2). By Gershgorin
//    (omega dt/2)^2 <= q, so the bound holds for any stable step; growth_factor = 2 covers the
//    transfer of the support work and round-off. With the default step (0.9 x the bound with local
//    damping, a = 1.8) q <= 0.45, the allowance is 3.6 x the supplied energy; an undamped run at
//    0.95 x its critical step is allowed 20.5 x (q = 0.9025), q_max = 0.99 caps it at 200 x. An
//    unstable mode grows geometrically (the undamped mass-spring at 1.05 x its critical step by a
//    factor 1.88 per step), so it passes any of these factors within a few dozen steps: the check
//    catches it at its next pass, long before the numbers overflow.
//
// The message names the worst entity (first non-finite one, else the fastest node), its block,
// its value, the node's mass m, stiffness bound k and own stable step 2 sqrt(m/(a k)) (a = the
// damping's stiffness amplification) against the step in use, and the likely cause with what to
// change: the time step above the node's stable limit (lower dt or scale masses), a mass too small
// (zero, negative or non-finite), a non-finite value set after construction, or a stiffness above
// the bound the step was computed from (parameters or masses changed after construction: call
// compute_time_step(); or a load applied too fast).
//
// Cost: one pass over nodes and sub-contacts plus one energies() evaluation per `interval` steps.
// Measured on the 100-block prism (1 thread, 2000 steps): 0.77 s without the checker, 0.78-0.81 s
// with it at interval = 100, i.e. one check costs about 3 steps and the checker 1-4 % of the run.
// No allocation besides what energies() does; no message is built unless the check fails.
//
// | expression          | meaning                                                    |
// |---------------------|------------------------------------------------------------|
// | C::enabled          | constexpr bool; false removes every check                  |
// | c.interval          | steps between checks (>= 1)                                |
// | c.check(solver)     | throws numerical_instability with a diagnostic             |
//
// check(s) reads s.gridpoints(), s.bar_nodes(), s.energies() (initial, boundary_work, kinetic),
// s.stiffness_amplification(), s.dt(), s.step_count(), s.time(), s.gridpoint_block(i), and, when
// the solver has them, s.contacts() (size, force, node_a/b, block_a/b) and s.reinforcement()
// (node_bar, bonded, host).

#include <algorithm>
#include <cmath>
#include <concepts>
#include <limits>
#include <string>
#include <type_traits>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"

namespace tessera::checks {

/// Stops a run (numerical_instability naming the node or sub-contact) on a non-finite state or on kinetic energy beyond growth_factor x the energy supplied
struct default_step_checker {
  static constexpr bool enabled = true;  ///< checks run
  index_t interval = 100;       ///< steps between checks
  real growth_factor = 2.0;   ///< allowed ratio of kinetic energy to energy supplied (-)
  real floor = 1e-12;         ///< J, absolute allowance (round-off before any loading)
  static constexpr real q_max = 0.99;  ///< cap of (dt/2)^2 max k/m in the allowance (see above)

  template <class Solver>
  void check(const Solver& s) const {  ///< Throws numerical_instability with a diagnosis when the state is non-finite or the kinetic energy grows beyond the allowance
    // 1. Non-finite state: the first offending node or sub-contact.
    for (int set = 0; set < 2; ++set) {
      const node_set& nodes = set == 0 ? s.gridpoints() : s.bar_nodes();
      for (index_t i = 0; i < nodes.size(); ++i)
        for (int c = 0; c < 3; ++c) {
          const real values[3] = {nodes.displacement(i, c), nodes.velocity(i, c), nodes.force(i, c)};
          for (int q = 0; q < 3; ++q)
            if (!std::isfinite(values[q])) {
              const char* quantity[3] = {"displacement", "velocity", "force"};
              const char* unit[3] = {"m", "m/s", "N"};
              fail(s, set == 1, i, true,
                   detail::concat("non-finite ", quantity[q], " ", "xyz"[c], " = ", values[q], " ", unit[q], " at "));
            }
        }
    }
    if constexpr (requires { s.contacts().force(index_t{0}); s.contacts().block_a(index_t{0}); }) {
      const auto& contacts = s.contacts();
      for (index_t i = 0; i < contacts.size(); ++i) {
        const vec3 f = contacts.force(i);
        if (!f.allFinite()) {
          const index_t a = contacts.node_a(i), b = contacts.node_b(i);
          fail(s, false, b, true,
               detail::concat("non-finite force (", f.x(), ", ", f.y(), ", ", f.z(), ") N of sub-contact ", i,
                              " between gridpoint ", a, " of block ", contacts.block_a(i), " and "));
        }
      }
    }
    // 2. Kinetic energy beyond the energy supplied: name the fastest node.
    const auto e = s.energies();
    const real works = std::abs(e.boundary_work) + std::abs(e.gravity_work) + std::abs(e.applied_work);
    const real supplied = e.initial + std::max(works, e.peak_work) + std::abs(e.contact_rebuild_exchange);
    if (e.kinetic <= growth_factor * supplied + floor) return;  // cheap path: q >= 0
    real q = 0;
    for (int set = 0; set < 2; ++set) {
      const node_set& nodes = set == 0 ? s.gridpoints() : s.bar_nodes();
      for (index_t i = 0; i < nodes.size(); ++i)
        if (nodes.mass[i] > 0) q = std::max(q, nodes.stiffness[i] / nodes.mass[i]);
    }
    q *= 0.25 * s.dt() * s.dt();
    const real allowed = growth_factor * supplied / (1 - std::min(q, q_max)) + floor;
    if (e.kinetic <= allowed) return;
    bool is_bar = false;
    index_t fastest = invalid_index;
    real speed = -1;
    for (int set = 0; set < 2; ++set) {
      const node_set& nodes = set == 0 ? s.gridpoints() : s.bar_nodes();
      for (index_t i = 0; i < nodes.size(); ++i) {
        const real v = nodes.velocity.row(i).norm();
        if (v > speed) {
          speed = v;
          fastest = i;
          is_bar = set == 1;
        }
      }
    }
    // The terms of `supplied`; gravity, applied work and the rebuild exchange only when a run has them.
    std::string terms = detail::concat("initial ", e.initial, " J + |boundary work| ", std::abs(e.boundary_work), " J");
    if (e.gravity_work != 0) terms += detail::concat(" + |gravity work| ", std::abs(e.gravity_work), " J");
    if (e.applied_work != 0) terms += detail::concat(" + |applied work| ", std::abs(e.applied_work), " J");
    if (e.peak_work > works) terms += detail::concat(" (the works' largest sum so far: ", e.peak_work, " J)");
    if (e.contact_rebuild_exchange != 0)
      terms += detail::concat(" + |rebuild exchange| ", std::abs(e.contact_rebuild_exchange), " J");
    fail(s, is_bar, fastest, false,
         detail::concat("kinetic energy ", e.kinetic, " J exceeds the allowed ", allowed, " J (energy supplied: ", terms,
                        "); the fastest node, at ", speed, " m/s, is "));
  }

 private:
  /// "<entity> of block B (m = .., k = .., its stable step .. s, dt = .. s); likely cause: .."
  template <class Solver>
  [[noreturn]] static void fail(const Solver& s, bool is_bar, index_t i, bool non_finite, const std::string& what) {
    const node_set& nodes = is_bar ? s.bar_nodes() : s.gridpoints();
    const real m = i >= 0 ? nodes.mass[i] : 0, k = i >= 0 ? nodes.stiffness[i] : 0;
    const real a = s.stiffness_amplification();
    const real own_dt = k > 0 && m > 0 ? 2 * std::sqrt(m / (a * k)) : std::numeric_limits<real>::infinity();
    std::string entity;
    if (!is_bar) {
      entity = detail::concat("gridpoint ", i, " of block ", s.gridpoint_block(i));
    } else {
      entity = detail::concat("bar node ", i);
      if constexpr (requires { s.reinforcement().node_bar(i); s.reinforcement().host(i).gridpoints; }) {
        const auto& r = s.reinforcement();
        entity += detail::concat(" (bar ", r.node_bar(i), ")");
        if (r.bonded(i)) entity += detail::concat(" hosted in block ", s.gridpoint_block(r.host(i).gridpoints[0]));
      }
    }
    const char* cause =
        !(m > 0) || !std::isfinite(m)
            ? "mass too small (zero, negative or non-finite): check the density and the zoning of this block"
        : s.dt() > own_dt * (1 + 1e-12)
            ? "time step above the stable limit of this node: lower dt or raise its mass (solver_options::"
              "mass_scaling_dt), and call compute_time_step() after changing masses or stiffnesses"
        : non_finite
            ? "a non-finite value set after construction (initial displacement or velocity, a prescribed "
              "velocity), or a stiffness above the bound k the step was computed from (parameters or masses "
              "changed after construction: call compute_time_step())"
            : "stiffness too high for the time step: a zone, contact or bond stiffer than the bound k the step "
              "was computed from (parameters changed after construction: call compute_time_step()), or a load "
              "applied too fast (a velocity jump at a support: ramp it)";
    throw numerical_instability(detail::concat("numerical instability at step ", s.step_count(), " (t = ", s.time(),
                                               " s): ", what, entity, " (m = ", m, " kg, k = ", k,
                                               " N/m, its stable step 2 sqrt(m/(a k)) = ", own_dt, " s with a = ", a,
                                               ", dt = ", s.dt(), " s); likely cause: ", cause));
  }
};

/// No checks: for runs whose energy books do not close by design (relaxation resets)
struct no_step_checker {
  static constexpr bool enabled = false;  ///< no checks
  index_t interval = std::numeric_limits<index_t>::max();  ///< never due
  template <class Solver>
  void check(const Solver&) const {}  ///< Checks nothing
};

}  // namespace tessera::checks
