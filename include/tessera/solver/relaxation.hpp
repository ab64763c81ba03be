#pragma once
// Kinetic dynamic relaxation (KDR; Barnes 1977, Topping and Khan 1994): the static equilibrium of
// a solver's model, found with the solver's own undamped explicit steps whose free velocities are
// zeroed at every peak of the kinetic energy, and load increments of prescribed displacement each
// held until the unbalanced-force ratio falls below a tolerance, as 3DEC's `solve ratio` (issue
// #43, candidate 2; measured against the explicit ramp and the implicit solve in
// docs/performance.md).
//
// Why it converges. Undamped, the model oscillates about its equilibrium; the kinetic energy of
// the dominant mode peaks where that mode passes through it. Zeroing every velocity there drops
// the mode's energy and restarts the motion from near the equilibrium, so each reset removes most
// of the energy left; the higher modes, which peak at other steps, go at later resets. Steps to a
// tolerance grow with the lowest mode's period in steps, sqrt(lambda_max / lambda_min) of
// M^-1 K, so the masses should all sit at their stability limit (Underwood's fictitious masses):
// kinetic_relaxation_options scales every gridpoint to one step and turns the local damping off.
//
// The peak and the correction. After step n the solver holds u_{n+1}, v_{n+1/2} and F_n (the
// unbalanced force of the step). When the free kinetic energy of v_{n+1/2} is below that of
// v_{n-1/2}, the peak was at the half step n - 1/2, where the displacement was about
// u* = u_n - dt/2 v_{n-1/2} = u_{n+1} - 1.5 dt v_{n+1/2} + 0.5 dt^2 M^-1 F_n (Topping and Khan's
// correction; exact for the undamped step, since v_{n+1/2} - v_{n-1/2} = dt M^-1 F_n; with local
// damping F_n is short of the force that moved v by the damping force, an error of at most
// gamma dt^2 |F| / 2m per component). With back_up_to_peak false, u* = u_{n+1} (plain zeroing).
//
// Consistency with the contact laws. The solver's contacts advance their states by the relative
// velocity of the last half step times dt (contact/face_contacts.hpp), and the step that follows
// step n is the one that hands them the increment u_{n+1} - u_n. Writing u* and v = 0 straight
// into the node_set would leave the contact springs out of step with the displacements. So a reset
// writes u = u* and v = w = (u* - u_n) / dt on every free component, takes one solver step (the
// contacts advance by exactly u* - u_n, the zones see u*), and then takes w back out of that step's
// update and halves its kick (v = dt M^-1 F* / 2, u = u* + v dt: the leapfrog start from rest; a
// full kick makes frequent resets unstable at the solver's step). The model ends the step as if it
// had started from rest at u*, and its contacts followed every displacement it had
// (test_relaxation). The reset step is counted.
// Prescribed components are never touched; rigid blocks are refused (their velocities live in the
// block model).
//
// The ratio. max over free nodes of the unbalanced force (solver::unbalanced_force, solver/
// balance.hpp) over a reference force the caller gives (N; e.g. f_T A of a cracking section, or the
// reaction of the load), checked every check_interval steps; when it holds, the velocities are
// zeroed once more (one reset step, without back-up) so the next increment starts from rest, and
// the ratio of that step is the one returned. 3DEC divides by the mean applied gridpoint force
// instead; a caller's reference keeps the tolerance a statement about the figures read.
//
// FIRE (relaxation_options::velocity_rule = fire; Bitzek et al. 2006) in place of the resets:
// after each step the free velocities are mixed towards the unbalanced force's acceleration and a
// step of non-positive power resets them; the step is the solver's, not grown (options comment).
// Measured on the prism and the tie against KDR in docs/performance.md: it takes more steps.
// Adaptive damping (velocity_rule = adaptive; Underwood 1983) instead keeps a viscous damping at
// the critical value of the mode the displacement is in, from a Rayleigh quotient of local
// stiffnesses the forces of successive steps give (options comment; no resets). The velocities
// are replaced after the solver's undamped step and the displacements follow them, as FIRE's.
//
// Energy books: the resets remove kinetic energy the solver's books do not see;
// relaxation_result::kinetic_removed adds it up (J of pseudo-time with the scaled masses: the
// 1/2 m v^2 of the zeroed half-step velocities; the back-up also changes the stored energy a
// little, and an extrapolated ramp moves the free components by a motion no force did work for;
// neither is booked), so the solver's energy balance no longer closes in a relaxed run. The
// default step checker bounds the kinetic energy by the booked work, so it can stop a relaxation
// that is sound (measured on the RC tie past its first cracks): relax with
// checks::no_step_checker, or check the run by its unbalanced ratio.
//
// Cost: one pass over the free components per step (kinetic energy) and one serial pass over the
// nodes per check; the steps are the solver's. Thread safety: as the solver (one thread).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "options.hpp"
#include "relaxation_options.hpp"
#include "relaxation_rules.hpp"

namespace tessera {

/// kinetic_relaxation's default hook: nothing happens before a step.
struct no_before_step {
  template <class Solver>
  void operator()(Solver&, real, bool) const noexcept {}  ///< Does nothing
};

/// Kinetic dynamic relaxation of a solver of deformable blocks (file comment). The prescribed
/// velocities of gridpoints and bar nodes when it is built are the pattern of the load (m/s):
/// advance(duration, ...) moves each prescribed component by pattern x duration; they are set to
/// zero (held) at once.
///
/// Loads the prescribed velocities cannot express (a rigid platen moved by set_velocity and
/// advanced by update before every step, contact/platen.hpp; a plate turning about its hinge) go
/// through `before_step(solver, rate, resetting)`, called before every solver step the relaxation
/// takes, with rate the factor on the pattern in that step (dimensionless: a component of pattern
/// p m/s moves at p x rate m/s; duration / (ramp_steps x dt) during an advance's ramp, 0 while the
/// model is held) and resetting true for a reset step (the free velocities are being zeroed; a
/// body with a velocity of its own, such as a hinged plate's turn, stops too). A platen driven at
/// rate x 1 m/s moves by `duration` m per increment, as a prescribed component of pattern 1 m/s
/// does. A platen with inertia does not relax well: its turn rings against the gridpoints under it
/// near the step's frequency, and the resets come every three or four steps (measured on rc_beam's
/// steel plates, damped or not, stopped at the resets or not: one increment still short of 1e-3
/// after 26 000 steps); give it none (platen_motion::quasi_static), and it settles in 100-600
/// steps an increment. The hook sees the free velocities
/// the step is about to move the gridpoints by (a reset's w, the predictor's imposed motion), so a
/// platen that advances its contacts by them stays consistent with the solver's own contacts (file
/// comment). It runs on the calling thread; it must not allocate if the relaxation is to stay
/// allocation-free.
template <class Solver, class BeforeStep = no_before_step>
class kinetic_relaxation {
 public:
  explicit kinetic_relaxation(Solver& s, BeforeStep before_step = {}) : s_(s), before_step_(std::move(before_step)) {  ///< Reads the load pattern (the prescribed velocities) from s and holds its supports; before_step(s, rate, resetting) is called before every step
    static_assert(!Solver::blocks_type::is_rigid, "kinetic_relaxation: rigid blocks keep their velocities in the "
                                                  "block model; only deformable blocks are relaxed");
    pattern_ = s_.gridpoints().prescribed_velocity;
    s_.gridpoints().prescribed_velocity.setZero();
    offset_.setZero(s_.gridpoints().size(), 3);
    if constexpr (Solver::reinforcement_type::enabled) {
      bar_pattern_ = s_.bar_nodes().prescribed_velocity;
      s_.bar_nodes().prescribed_velocity.setZero();
      bar_offset_.setZero(s_.bar_nodes().size(), 3);
    }
  }

  /// Steps with the supports held until the ratio is at most o.ratio_tolerance or o.max_steps
  /// were taken, zeroing the free velocities at every kinetic-energy peak. Throws invalid_input
  /// for bad options (require_valid_relaxation) before anything changes.
  relaxation_result relax(const relaxation_options& o) {
    require_valid_relaxation(o);
    if (o.velocity_rule == relaxation_options::method::adaptive) save_start();  // its origin
    return hold(o);
  }

  /// One load increment: the prescribed components move by pattern x duration (m; duration in s
  /// of pseudo-time, >= 0) at a constant speed over ramp_steps (>= 1) steps, with resets at the
  /// kinetic-energy peaks, then are held while the model relaxes (relax). Throws invalid_input for
  /// a bad duration, ramp or options before anything changes.
  relaxation_result advance(real duration, std::int64_t ramp_steps, const relaxation_options& o) {
    require(std::isfinite(duration) && duration >= 0, "relaxation: increment duration = ", duration,
            " s must be finite and >= 0");
    require(ramp_steps >= 1, "relaxation: ramp_steps = ", ramp_steps, " must be >= 1");
    require_valid_relaxation(o);
    relaxation_result r;
    begin_rule(o);
    const real speed = 1 / (static_cast<real>(ramp_steps) * s_.dt());  // 1/s: a displacement over the ramp
    load_rate_ = duration * speed;
    s_.gridpoints().prescribed_velocity = pattern_ * (duration * speed);
    if constexpr (Solver::reinforcement_type::enabled)
      s_.bar_nodes().prescribed_velocity = bar_pattern_ * (duration * speed);
    const bool predict = o.extrapolate && last_duration_ > 0;
    const real scale = predict ? duration / last_duration_ * speed : 0;
    save_start();
    while (r.steps < ramp_steps) {
      if (!predict) {
        step_with_resets(o, r);
        continue;
      }
      step_solver();
      ++r.steps;
      impose_free_velocity(s_.gridpoints(), change_, scale);
      if constexpr (Solver::reinforcement_type::enabled) impose_free_velocity(s_.bar_nodes(), bar_change_, scale);
    }
    s_.gridpoints().prescribed_velocity.setZero();
    if constexpr (Solver::reinforcement_type::enabled) s_.bar_nodes().prescribed_velocity.setZero();
    load_rate_ = 0;
    if (predict) reset(false, r);  // from the imposed motion to rest
    r.ramp_steps = r.steps;
    time_ += duration;
    totals_.add(r);
    const relaxation_result held = hold(o);
    r.add(held);
    change_ = s_.gridpoints().displacement - start_;
    if constexpr (Solver::reinforcement_type::enabled) bar_change_ = s_.bar_nodes().displacement - bar_start_;
    last_duration_ = duration;
    return r;
  }

  /// Pseudo-time of the increments so far (s): prescribed components moved by pattern x this.
  [[nodiscard]] real prescribed_time() const { return time_; }
  /// Everything every relax and advance did (steps, resets, kinetic energy removed).
  [[nodiscard]] const relaxation_result& totals() const { return totals_; }

 private:
  /// One solver step, after the hook (class comment); resetting: a reset's step.
  void step_solver(bool resetting = false) {
    before_step_(s_, load_rate_, resetting);
    s_.step();
  }

  /// The displacements at the start of the increment (or of relax()): the predictor's and the
  /// adaptive rule's origin.
  void save_start() {
    start_ = s_.gridpoints().displacement;
    if constexpr (Solver::reinforcement_type::enabled) bar_start_ = s_.bar_nodes().displacement;
  }

  /// The relaxation loop of relax() and of an increment's hold.
  relaxation_result hold(const relaxation_options& o) {
    relaxation_result r;
    begin_rule(o);
    std::int64_t next_check = o.check_interval;
    while (r.steps < o.max_steps) {
      step_with_resets(o, r);
      if (r.steps < next_check) continue;
      next_check = r.steps + o.check_interval;
      r.ratio = ratio(o);
      if (r.ratio <= o.ratio_tolerance) {
        reset(false, r);  // at rest for what follows
        r.ratio = ratio(o);
        r.converged = true;
        break;
      }
    }
    totals_.add(r);
    return r;
  }

  /// Every rule starts afresh at each relaxation and ramp: the kinetic energy to compare with,
  /// FIRE's mixing, and the adaptive rule's last velocities and forces.
  void begin_rule(const relaxation_options& o) {
    previous_ = free_kinetic_energy();
    alpha_ = o.fire_alpha_start, downhill_ = 0;
    if (o.velocity_rule != relaxation_options::method::adaptive) return;
    adaptive_.begin(s_.gridpoints());
    if constexpr (Solver::reinforcement_type::enabled) bar_adaptive_.begin(s_.bar_nodes());
  }

  /// One solver step, then a reset if the free kinetic energy fell (the peak was at the last half
  /// step); counts into r.
  void step_with_resets(const relaxation_options& o, relaxation_result& r) {
    step_solver();
    ++r.steps;
    if (o.velocity_rule == relaxation_options::method::fire) {
      fire_mix(o, r);
      return;
    }
    if (o.velocity_rule == relaxation_options::method::adaptive) {
      adaptive_damp(o);
      return;
    }
    const real now = free_kinetic_energy();
    if (now < previous_) {
      reset(o.back_up_to_peak, r);
      previous_ = free_kinetic_energy();
    } else {
      previous_ = now;
    }
  }

  /// FIRE after a step (relaxation_options::velocity_rule): the power of the step's unbalanced
  /// force on the free velocities decides between a reset (power <= 0) and the mixing; the mixed
  /// velocity replaces the step's in the displacement too (u += (v' - v) dt), so the contacts of
  /// the next step see the increment the displacements took. Serial passes over the free
  /// components of gridpoints and bar nodes (the same bits for every thread count).
  void fire_mix(const relaxation_options& o, relaxation_result& r) {
    real power = 0, v_m = 0, a_m = 0;  // F . v, |v|_M^2, |M^-1 F|_M^2 = sum F^2 / m
    const auto sums = [&](const node_set& n) {
      for (int c = 0; c < 3; ++c)
        for (index_t i = 0; i < n.size(); ++i)
          if (n.constraint(i, c) == free_) {
            const real f = n.force(i, c), v = n.velocity(i, c);
            power += f * v, v_m += n.mass[i] * v * v, a_m += f * f / n.mass[i];
          }
    };
    sums(s_.gridpoints());
    if constexpr (Solver::reinforcement_type::enabled) sums(s_.bar_nodes());
    if (!(power > 0)) {
      reset(o.back_up_to_peak, r);
      alpha_ = o.fire_alpha_start, downhill_ = 0;
      return;
    }
    if (++downhill_ > o.fire_delay) alpha_ *= o.fire_alpha_decay;
    if (a_m <= 0) return;
    const real keep = 1 - alpha_, turn = alpha_ * std::sqrt(v_m / a_m), dt = s_.dt();
    const auto mix = [&](node_set& n) {
      for (int c = 0; c < 3; ++c)
        for (index_t i = 0; i < n.size(); ++i)
          if (n.constraint(i, c) == free_) {
            const real v = n.velocity(i, c), mixed = keep * v + turn * n.force(i, c) / n.mass[i];
            n.displacement(i, c) += (mixed - v) * dt;
            n.velocity(i, c) = mixed;
          }
    };
    mix(s_.gridpoints());
    if constexpr (Solver::reinforcement_type::enabled) mix(s_.bar_nodes());
  }

  /// Underwood's adaptive damping after a step (relaxation_options::velocity_rule); serial passes
  /// over the free components of gridpoints and bar nodes (the same bits for every thread count).
  void adaptive_damp(const relaxation_options& o) {
    const real dt = s_.dt();
    real stiffness = 0, mass = 0;
    adaptive_.sums(s_.gridpoints(), start_, dt, stiffness, mass);
    if constexpr (Solver::reinforcement_type::enabled) bar_adaptive_.sums(s_.bar_nodes(), bar_start_, dt, stiffness, mass);
    const real lambda = mass > 0 && stiffness > 0 ? stiffness / mass : 0;
    const real cdt = std::min<real>(2, o.adaptive_damping_scale * 2 * std::sqrt(lambda) * dt);
    adaptive_.damp(s_.gridpoints(), dt, cdt);
    if constexpr (Solver::reinforcement_type::enabled) bar_adaptive_.damp(s_.bar_nodes(), dt, cdt);
  }

  [[nodiscard]] real ratio(const relaxation_options& o) {
    real worst = s_.unbalanced_force().max_force;
    if (o.block_resultant) worst = std::max(worst, largest_block_resultant());
    return worst / o.reference_force;
  }

  /// Largest |sum of a block's gridpoint forces over their free components| (N); serial, in
  /// gridpoint order (the same bits for every thread count).
  [[nodiscard]] real largest_block_resultant() {
    const node_set& g = s_.gridpoints();
    if (block_sum_.rows() == 0) {
      index_t blocks = 0;
      for (index_t i = 0; i < g.size(); ++i) blocks = std::max(blocks, s_.gridpoint_block(i) + 1);
      block_sum_.setZero(blocks, 3);
    }
    block_sum_.setZero();
    for (index_t i = 0; i < g.size(); ++i) {
      const index_t b = s_.gridpoint_block(i);
      for (int c = 0; c < 3; ++c)
        if (g.constraint(i, c) == free_) block_sum_(b, c) += g.force(i, c);
    }
    real worst = 0;
    for (index_t b = 0; b < block_sum_.rows(); ++b) worst = std::max(worst, block_sum_.row(b).norm());
    return worst;
  }

  /// Sum of 1/2 m v^2 over the free components of gridpoints and bar nodes (J).
  [[nodiscard]] real free_kinetic_energy() const {
    real e = free_kinetic_energy(s_.gridpoints());
    if constexpr (Solver::reinforcement_type::enabled) e += free_kinetic_energy(s_.bar_nodes());
    return e;
  }
  [[nodiscard]] static real free_kinetic_energy(const node_set& n) {
    real e = 0;
    for (int c = 0; c < 3; ++c)
      for (index_t i = 0; i < n.size(); ++i)
        if (n.constraint(i, c) == free_) e += n.mass[i] * n.velocity(i, c) * n.velocity(i, c);
    return 0.5 * e;
  }

  /// Zeroes the free velocities at the displacement of the kinetic-energy peak (back_up) or at
  /// the present one, through one solver step that hands the contacts the matching increment
  /// (file comment); counts the step and the reset into r.
  void reset(bool back_up, relaxation_result& r) {
    r.kinetic_removed += free_kinetic_energy();
    prepare_reset(s_.gridpoints(), offset_, back_up);
    if constexpr (Solver::reinforcement_type::enabled) prepare_reset(s_.bar_nodes(), bar_offset_, back_up);
    step_solver(true);
    finish_reset(s_.gridpoints(), offset_);
    if constexpr (Solver::reinforcement_type::enabled) finish_reset(s_.bar_nodes(), bar_offset_);
    ++r.steps;
    ++r.resets;
  }
  /// u = u*, v = w = (u* - u_n) / dt on the free components; w kept in `offset` (0 elsewhere).
  void prepare_reset(node_set& n, soa3& offset, bool back_up) const {
    const real dt = s_.dt();
    for (int c = 0; c < 3; ++c)
      for (index_t i = 0; i < n.size(); ++i) {
        if (n.constraint(i, c) != free_) {
          offset(i, c) = 0;
          continue;
        }
        const real v = n.velocity(i, c);
        // u* - u_{n+1}: back to the peak, or nothing.
        const real shift = back_up ? dt * (-1.5 * v + 0.5 * dt * n.force(i, c) / n.mass[i]) : real(0);
        n.displacement(i, c) += shift;
        offset(i, c) = v + shift / dt;
        n.velocity(i, c) = offset(i, c);
      }
  }
  /// After a step: the free components of `n` moved at velocity w = scale x change (m/s) instead
  /// of what the step gave (v_step): v = w, u -= (v_step - w) dt, so the contacts of the next step
  /// see the increment w dt that the displacements took.
  void impose_free_velocity(node_set& n, const soa3& change, real scale) const {
    const real dt = s_.dt();
    for (int c = 0; c < 3; ++c)
      for (index_t i = 0; i < n.size(); ++i) {
        if (n.constraint(i, c) != free_) continue;
        const real w = scale * change(i, c);
        n.displacement(i, c) -= (n.velocity(i, c) - w) * dt;
        n.velocity(i, c) = w;
      }
  }

  /// Takes the offset back out of the step just taken and halves its kick: with v' the velocity
  /// the step gave, v = (v' - w) / 2 = dt M^-1 F / 2, the leapfrog start from rest, and
  /// u = u* + v dt. (The full kick, v = dt M^-1 F, makes a reset in every step the iteration
  /// u += dt^2 M^-1 F, unstable above dt = sqrt(2 / lambda_max); the half kick is stable up to the
  /// leapfrog limit 2 / sqrt(lambda_max), and the solver's step is just under it.)
  void finish_reset(node_set& n, const soa3& offset) const {
    const real dt = s_.dt();
    for (int c = 0; c < 3; ++c)
      for (index_t i = 0; i < n.size(); ++i) {
        if (n.constraint(i, c) != free_) continue;
        const real v_step = n.velocity(i, c), v = 0.5 * (v_step - offset(i, c));
        n.displacement(i, c) += (v - v_step) * dt;
        n.velocity(i, c) = v;
      }
  }

  static constexpr auto free_ = static_cast<std::uint8_t>(dof_constraint::free);
  Solver& s_;
  BeforeStep before_step_;
  real load_rate_ = 0;  ///< the factor on the pattern in the steps now taken (before_step's rate)
  soa3 pattern_, bar_pattern_;  ///< prescribed velocities when built: the load pattern (m/s)
  soa3 offset_;      ///< w of the reset step, gridpoints (m/s)
  soa3 bar_offset_;  ///< w of the reset step, bar nodes (m/s)
  soa3 start_, bar_start_;    ///< displacements at the start of the increment or relax() (m)
  soa3 change_, bar_change_;  ///< their change over the last increment (m)
  real last_duration_ = 0;    ///< the last increment's duration (s; 0 before the first)
  real previous_ = 0;  ///< free kinetic energy after the last step (J)
  detail::adaptive_damping_state adaptive_, bar_adaptive_;  ///< the adaptive rule's, gridpoints and bar nodes
  real alpha_ = 0;              ///< FIRE's mixing now
  std::int64_t downhill_ = 0;   ///< FIRE: steps with positive power since the last reset
  soa3 block_sum_;     ///< per block: resultant of the free gridpoint forces (N; block_resultant)
  real time_ = 0;
  relaxation_result totals_;
};

/// Relaxes `s` to the ratio o.ratio_tolerance with its prescribed components held still
/// (kinetic_relaxation::relax; file comment); their prescribed velocities are restored after.
/// Throws invalid_input for bad options before anything changes.
template <class Solver>
relaxation_result relax_to_equilibrium(Solver& s, const relaxation_options& o) {
  require_valid_relaxation(o);
  const soa3 held = s.gridpoints().prescribed_velocity;
  soa3 bars_held;
  if constexpr (Solver::reinforcement_type::enabled) bars_held = s.bar_nodes().prescribed_velocity;
  kinetic_relaxation<Solver> k(s);
  const relaxation_result r = k.relax(o);
  s.gridpoints().prescribed_velocity = held;
  if constexpr (Solver::reinforcement_type::enabled) s.bar_nodes().prescribed_velocity = bars_held;
  return r;
}

}  // namespace tessera
