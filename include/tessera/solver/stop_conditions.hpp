#pragma once
// Stop conditions for solver::run_until, and the quantities they watch.
//
//     using namespace tessera;
//     const auto r = s.run_until(stop::when_settled(quantity::block_displacement(3, 2), 1e-6, stop::over_time(0.05)) ||
//                                    stop::when_beyond(quantity::block_displacement_magnitude(3), 0.1) ||
//                                    stop::after_time(5.0),
//                                100'000'000);
//     std::cout << r.steps << " steps: " << r.reason << '\n';   // "settled: ..." or "beyond: ..." or "after ..."
//
// A quantity is any callable real(const Solver&) (SI units). Those of namespace tessera::quantity
// also say what they are (describe()), which the conditions put in their reasons.
//
// A condition is a small callable object: `bool operator()(const Solver&)` (evaluated by run_until
// before every step; may keep state, so it is not const), `void start(const Solver&)` (run_until
// calls it once at its start: counters, windows and peaks restart there), `describe()` (what it
// waits for) and `reason()` (why it held at its last evaluation, with the measured values).
// Conditions combine with `||` (either holds) and `&&` (both hold); both sides are evaluated at
// every step (no short circuit), so a window or a peak on either side sees every step.
// Evaluation allocates nothing (a settled window is a ring buffer sized in start()); describe() and
// reason() build strings and are meant for the end of a run.
//
// Refusals (invalid_input naming the value) happen when a condition is built (a tolerance <= 0,
// a NaN limit, ...) or in start() (a window shorter than the solver's step), before any step.

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "boundary.hpp"
#include "recorders.hpp"

namespace tessera::quantity {

namespace detail {
inline void require_axis(int axis, const char* what) {
  require(axis >= 0 && axis < 3, "quantity::", what, ": axis = ", axis, " must be 0 (x), 1 (y) or 2 (z)");
}
inline void require_block_id(index_t b, const char* what) {
  require(b >= 0, "quantity::", what, ": block ", b, " does not exist (ids are >= 0)");
}
}  // namespace detail

/// Simulated time t (s).
struct time {
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const { return s.time(); }  ///< q(s) = s.time() (s)
  [[nodiscard]] std::string describe() const { return "time (s)"; }  ///< "time (s)", for the stop conditions' reasons
};

/// Component `axis` (0 x, 1 y, 2 z) of block b's displacement (m; solver::block_displacement:
/// rigid, the centroid's; deformable, the mass-weighted mean of its gridpoints'). A bad block id
/// is refused at the first evaluation (run_until's first, before any step).
struct block_displacement {
  index_t block;  ///< block id (>= 0)
  int axis;  ///< 0 x, 1 y, 2 z
  block_displacement(index_t b, int axis_) : block(b), axis(axis_) {  ///< Refuses (invalid_input) a negative block id or an axis outside 0..2
    detail::require_block_id(b, "block_displacement");
    detail::require_axis(axis_, "block_displacement");
  }
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const { return s.block_displacement(block)[axis]; }  ///< The displacement component (m)
  [[nodiscard]] std::string describe() const {  ///< E.g. "z displacement of block 3 (m)"
    return tessera::detail::concat("xyz"[axis], " displacement of block ", block, " (m)");
  }
};

/// |displacement| of block b (m).
struct block_displacement_magnitude {
  index_t block;  ///< block id (>= 0)
  explicit block_displacement_magnitude(index_t b) : block(b) { detail::require_block_id(b, "block_displacement_magnitude"); }  ///< Refuses (invalid_input) a negative block id
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const { return s.block_displacement(block).norm(); }  ///< |u| (m)
  [[nodiscard]] std::string describe() const { return tessera::detail::concat("|displacement| of block ", block, " (m)"); }  ///< E.g. "|displacement| of block 3 (m)"
};

/// Component `axis` of block b's velocity (m/s, half step; solver::block_velocity).
struct block_velocity {
  index_t block;  ///< block id (>= 0)
  int axis;  ///< 0 x, 1 y, 2 z
  block_velocity(index_t b, int axis_) : block(b), axis(axis_) {  ///< Refuses (invalid_input) a negative block id or an axis outside 0..2
    detail::require_block_id(b, "block_velocity");
    detail::require_axis(axis_, "block_velocity");
  }
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const { return s.block_velocity(block)[axis]; }  ///< The velocity component (m/s)
  [[nodiscard]] std::string describe() const {  ///< E.g. "z velocity of block 3 (m/s)"
    return tessera::detail::concat("xyz"[axis], " velocity of block ", block, " (m/s)");
  }
};

/// Speed |v| of block b (m/s, half step).
struct block_speed {
  index_t block;  ///< block id (>= 0)
  explicit block_speed(index_t b) : block(b) { detail::require_block_id(b, "block_speed"); }  ///< Refuses (invalid_input) a negative block id
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const { return s.block_velocity(block).norm(); }  ///< |v| (m/s)
  [[nodiscard]] std::string describe() const { return tessera::detail::concat("speed of block ", block, " (m/s)"); }  ///< E.g. "speed of block 3 (m/s)"
};

/// Largest speed of any block (m/s, half step); O(gridpoints) for deformable blocks.
struct max_block_speed {
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const {  ///< max over blocks of |v| (m/s)
    real v = 0;
    for (index_t b = 0; b < s.block_count(); ++b) v = std::max(v, s.block_velocity(b).norm());
    return v;
  }
  [[nodiscard]] std::string describe() const { return "largest block speed (m/s)"; }  ///< "largest block speed (m/s)"
};

/// Kinetic energy of the model (J; solver::kinetic_energy).
struct kinetic_energy {
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const { return s.kinetic_energy(); }  ///< E_k (J)
  [[nodiscard]] std::string describe() const { return "kinetic energy (J)"; }  ///< "kinetic energy (J)"
};

/// Component `axis` of the sum of the support reactions on a group of gridpoints (N; the force
/// the supports exert on them, recorders::reaction_sum), e.g. of solver::gridpoints_of_block(0).
struct reaction_sum {
  bc::node_group group;  ///< the gridpoints summed over
  int axis;  ///< 0 x, 1 y, 2 z
  reaction_sum(bc::node_group g, int axis_) : group(std::move(g)), axis(axis_) {  ///< Refuses (invalid_input) an axis outside 0..2 or an empty group
    detail::require_axis(axis_, "reaction_sum");
    require(!group.empty(), "quantity::reaction_sum: node group '", group.name, "' is empty");
  }
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const { return recorders::reaction_sum(s.gridpoints(), group)[axis]; }  ///< The reaction component summed over the group (N)
  [[nodiscard]] std::string describe() const {  ///< E.g. "z reaction on 'block 0' (N)"
    return tessera::detail::concat("xyz"[axis], " reaction on '", group.name, "' (N)");
  }
};

/// Component `axis` of the mean displacement of a group of gridpoints (m).
struct mean_displacement {
  bc::node_group group;  ///< the gridpoints averaged over
  int axis;  ///< 0 x, 1 y, 2 z
  mean_displacement(bc::node_group g, int axis_) : group(std::move(g)), axis(axis_) {  ///< Refuses (invalid_input) an axis outside 0..2 or an empty group
    detail::require_axis(axis_, "mean_displacement");
    require(!group.empty(), "quantity::mean_displacement: node group '", group.name, "' is empty");
  }
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const {  ///< The mean displacement component (m)
    return recorders::mean_displacement(s.gridpoints(), group)[axis];
  }
  [[nodiscard]] std::string describe() const {  ///< E.g. "z mean displacement of 'top' (m)"
    return tessera::detail::concat("xyz"[axis], " mean displacement of '", group.name, "' (m)");
  }
};

/// What a quantity is, for messages: its describe() where it has one, else "quantity".
template <class Q>
[[nodiscard]] std::string describe(const Q& q) {
  if constexpr (requires { { q.describe() } -> std::convertible_to<std::string>; })
    return q.describe();
  else
    return "quantity";
}

}  // namespace tessera::quantity

namespace tessera::stop {

/// Marks the types of this header as stop conditions (for `||` and `&&`).
struct condition_tag {};
template <class C>
concept Condition = std::derived_from<std::remove_cvref_t<C>, condition_tag>;

/// Stops once n steps were taken since run_until started (n >= 0).
class after_steps : public condition_tag {
 public:
  explicit after_steps(std::int64_t n) : n_(n) { require(n >= 0, "stop::after_steps: n = ", n, " must be >= 0"); }  ///< Refuses (invalid_input) n < 0
  template <class Solver>
  void start(const Solver& s) { first_ = s.step_count(); }  ///< Counts from the solver's step count now
  template <class Solver>
  bool operator()(const Solver& s) {  ///< True once n steps were taken since start()
    taken_ = s.step_count() - first_;
    return taken_ >= n_;
  }
  [[nodiscard]] std::string describe() const { return tessera::detail::concat("after ", n_, " steps"); }  ///< "after n steps"
  [[nodiscard]] std::string reason() const { return tessera::detail::concat("after ", taken_, " steps (limit ", n_, ")"); }  ///< The steps taken and the limit

 private:
  std::int64_t n_, first_ = 0, taken_ = 0;
};

/// Stops once t_s (s, >= 0) of simulated time passed since run_until started: at the first step
/// whose time t satisfies t - t0 >= t_s.
class after_time : public condition_tag {
 public:
  explicit after_time(real t_s) : t_(t_s) {  ///< Refuses (invalid_input) a negative or non-finite t_s (s)
    require(std::isfinite(t_s) && t_s >= 0, "stop::after_time: t = ", t_s, " s must be finite and >= 0");
  }
  template <class Solver>
  void start(const Solver& s) { t0_ = s.time(); }  ///< Counts from the solver's time now
  template <class Solver>
  bool operator()(const Solver& s) {  ///< True once t - t0 >= t_s
    elapsed_ = s.time() - t0_;
    return elapsed_ >= t_;
  }
  [[nodiscard]] std::string describe() const { return tessera::detail::concat("after ", t_, " s"); }  ///< "after t_s s"
  [[nodiscard]] std::string reason() const {  ///< The simulated time elapsed and the limit (s)
    return tessera::detail::concat("after ", elapsed_, " s of simulated time (limit ", t_, " s)");
  }

 private:
  real t_, t0_ = 0, elapsed_ = 0;
};

/// A window of when_settled: a number of steps or a span of simulated time.
struct window {
  std::int64_t steps = 0;  ///< > 0: this many steps
  real seconds = 0;        ///< > 0: ceil(seconds / dt) steps (dt read in start())
};
/// A window of n steps (n >= 1).
[[nodiscard]] inline window over_steps(std::int64_t n) {
  require(n >= 1, "stop::over_steps: window of ", n, " steps must be >= 1");
  return {n, 0};
}
/// A window of t_s seconds of simulated time (t_s > 0), counted as ceil(t_s / dt) steps of the dt
/// in use when run_until starts. Rigid blocks on detected contacts with an automatic step choose dt
/// again at each rebuild (docs/model.md, "Stable step"), so there the window spans t_s x (dt now /
/// dt at the start): longer when the step grew, shorter when contacts appeared. over_steps(n)
/// counts steps whatever dt does.
[[nodiscard]] inline window over_time(real t_s) {
  require(std::isfinite(t_s) && t_s > 0, "stop::over_time: window of ", t_s, " s must be finite and > 0");
  return {0, t_s};
}

/// Stops when quantity q has changed by at most `tolerance` (its unit, > 0) over the last window:
/// max - min of q over the window's samples <= tolerance, once a whole window has passed since
/// run_until started. q is sampled at every evaluation (every step) while the window is at most
/// max_samples steps long; a longer window is sampled every ceil(window / max_samples) steps (so
/// a change faster than that stride can be missed). The running max and min are kept in
/// preallocated ring buffers (monotonic queues, O(1) per step, no allocation after start()).
template <class Q>
class when_settled : public condition_tag {
 public:
  static constexpr std::int64_t max_samples = 4096;  ///< The most samples the window keeps (longer windows are strided)
  when_settled(Q quantity, real tolerance, window w) : q_(std::move(quantity)), tolerance_(tolerance), window_(w) {  ///< Refuses (invalid_input) a tolerance that is not finite and > 0, or an empty window
    require(std::isfinite(tolerance) && tolerance > 0, "stop::when_settled: tolerance = ", tolerance,
            " must be finite and > 0");
    require(w.steps > 0 || (std::isfinite(w.seconds) && w.seconds > 0), "stop::when_settled: window of ", w.steps,
            " steps / ", w.seconds, " s is empty; use stop::over_steps(n) or stop::over_time(t_s)");
  }
  template <class Solver>
  void start(const Solver& s) {  ///< Counts the window in steps of the solver's dt now (at least one; refuses a window of more than 1e15 steps) and empties it
    window_steps_ = window_.steps;
    if (window_steps_ == 0) {
      const real n = std::ceil(window_.seconds / s.dt() * (1 - 1e-12));
      require(n <= 1e15, "stop::when_settled: window of ", window_.seconds, " s is ", n, " steps of ", s.dt(), " s");
      window_steps_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(n));
    }
    stride_ = (window_steps_ + max_samples - 1) / max_samples;
    span_ = (window_steps_ + stride_ - 1) / stride_;  // samples apart of the window's ends
    const auto capacity = static_cast<std::size_t>(span_ + 1);
    high_.reset(capacity);
    low_.reset(capacity);
    evaluations_ = 0;
    samples_ = 0;
    change_ = std::numeric_limits<real>::infinity();
    latest_ = 0;
  }
  template <class Solver>
  bool operator()(const Solver& s) {  ///< Samples q; true once a whole window has passed with max - min <= tolerance
    if (stride_ == 0) start(s);  // used outside run_until without start()
    const bool sample = evaluations_ % stride_ == 0;
    ++evaluations_;
    if (!sample) return false;
    latest_ = static_cast<real>(q_(s));
    const std::int64_t k = samples_++;
    // Drop the samples that leave the window first, so at most span_ + 1 are held.
    high_.drop_before(k - span_);
    low_.drop_before(k - span_);
    high_.push(k, latest_, [](real a, real b) { return a <= b; });
    low_.push(k, latest_, [](real a, real b) { return a >= b; });
    if (samples_ <= span_) return false;  // the window is not full yet
    change_ = high_.front() - low_.front();
    return change_ <= tolerance_;
  }
  [[nodiscard]] std::string describe() const {  ///< What it waits for: q, the tolerance and the window
    return tessera::detail::concat("settled: ", quantity::describe(q_), " changes by at most ", tolerance_, " over ",
                                   window_.steps > 0 ? tessera::detail::concat(window_.steps, " steps")
                                                     : tessera::detail::concat(window_.seconds, " s"));
  }
  [[nodiscard]] std::string reason() const {  ///< q's latest value and its change over the window
    return tessera::detail::concat("settled: ", quantity::describe(q_), " = ", latest_, " changed by ", change_,
                                   " (<= ", tolerance_, ") over the last ", span_ * stride_, " steps");
  }
  [[nodiscard]] const Q& quantity() const { return q_; }  ///< The watched quantity

 private:
  /// Fixed-capacity monotonic queue of (sample index, value): front() is the max (or min, by
  /// `keep`) of the samples still in the window.
  class monotonic_ring {
   public:
    void reset(std::size_t capacity) {
      index_.assign(capacity, 0);
      value_.assign(capacity, 0);
      head_ = 0;
      size_ = 0;
    }
    template <class Dominated>
    void push(std::int64_t k, real v, Dominated&& dominated) {
      // Entries that v dominates can never be the window's extreme again.
      while (size_ > 0 && dominated(value_[slot(size_ - 1)], v)) --size_;
      index_[slot(size_)] = k;
      value_[slot(size_)] = v;
      ++size_;
    }
    void drop_before(std::int64_t first) {
      while (size_ > 0 && index_[head_] < first) {
        head_ = (head_ + 1) % index_.size();
        --size_;
      }
    }
    [[nodiscard]] real front() const { return value_[head_]; }

   private:
    [[nodiscard]] std::size_t slot(std::size_t i) const { return (head_ + i) % index_.size(); }
    std::vector<std::int64_t> index_;
    std::vector<real> value_;
    std::size_t head_ = 0, size_ = 0;
  };

  Q q_;
  real tolerance_;
  window window_;
  std::int64_t window_steps_ = 0, stride_ = 0, span_ = 0, evaluations_ = 0, samples_ = 0;
  real change_ = std::numeric_limits<real>::infinity(), latest_ = 0;
  monotonic_ring high_, low_;
};

/// Stops when |q| > limit (q's unit, finite, >= 0): "collapsed", "ran away", e.g. a displacement
/// or a speed beyond what the scene allows. Evaluated before every step, so run_until returns at
/// the first step after which |q| exceeds the limit.
template <class Q>
class when_beyond : public condition_tag {
 public:
  when_beyond(Q quantity, real limit) : q_(std::move(quantity)), limit_(limit) {  ///< Refuses (invalid_input) a limit that is not finite and >= 0
    require(std::isfinite(limit) && limit >= 0, "stop::when_beyond: limit = ", limit, " must be finite and >= 0");
  }
  template <class Solver>
  void start(const Solver& /*s*/) {}  ///< Nothing to restart
  template <class Solver>
  bool operator()(const Solver& s) {  ///< True when |q| > limit
    latest_ = static_cast<real>(q_(s));
    return std::abs(latest_) > limit_;
  }
  [[nodiscard]] std::string describe() const {  ///< "beyond: |q| > limit"
    return tessera::detail::concat("beyond: |", quantity::describe(q_), "| > ", limit_);
  }
  [[nodiscard]] std::string reason() const {  ///< q's value and the limit it passed
    return tessera::detail::concat("beyond: ", quantity::describe(q_), " = ", latest_, ", beyond the limit ", limit_);
  }
  [[nodiscard]] const Q& quantity() const { return q_; }  ///< The watched quantity

 private:
  Q q_;
  real limit_;
  real latest_ = 0;
};

/// Stops when the kinetic energy E_k (solver::kinetic_energy) has fallen to `ratio` (in (0, 1)) of
/// the largest E_k seen since run_until started: E_k <= ratio x max E_k, with max E_k > 0.
/// Decision: the peak, not the work done, is the reference, because a settling scene (blocks
/// dropped or released under gravity, with damping) gains its kinetic energy and then loses it,
/// and the peak is what "came to rest" is measured against in any units; the work of gravity keeps
/// growing with the creep of a scene that never settles. A scene that bounces passes through
/// E_k = 0 at the top of each bounce: combine it with a minimum time (stop::after_time(t) && ...)
/// or use when_settled on a displacement there.
class kinetic_energy_below : public condition_tag {
 public:
  explicit kinetic_energy_below(real ratio) : ratio_(ratio) {  ///< Refuses (invalid_input) a ratio outside (0, 1)
    require(std::isfinite(ratio) && ratio > 0 && ratio < 1, "stop::kinetic_energy_below: ratio = ", ratio,
            " must lie in (0, 1)");
  }
  template <class Solver>
  void start(const Solver& /*s*/) {  ///< Forgets the peak: it is measured from this run_until on
    peak_ = 0;
    latest_ = 0;
  }
  template <class Solver>
  bool operator()(const Solver& s) {  ///< True once E_k <= ratio x the peak E_k (> 0)
    latest_ = s.kinetic_energy();
    peak_ = std::max(peak_, latest_);
    return peak_ > 0 && latest_ <= ratio_ * peak_;
  }
  [[nodiscard]] std::string describe() const {  ///< What it waits for: the ratio
    return tessera::detail::concat("kinetic energy below ", ratio_, " of its peak");
  }
  [[nodiscard]] std::string reason() const {  ///< E_k, its peak and the ratio
    return tessera::detail::concat("kinetic energy ", latest_, " J <= ", ratio_, " x its peak ", peak_, " J");
  }

 private:
  real ratio_, peak_ = 0, latest_ = 0;
};

/// Any predicate bool(const Solver&) as a condition, with a description for its reason.
template <class P>
class when : public condition_tag {
 public:
  when(P predicate, std::string description) : p_(std::move(predicate)), description_(std::move(description)) {}  ///< predicate: bool(const Solver&); description: what it waits for
  template <class Solver>
  void start(const Solver& /*s*/) {}  ///< Nothing to restart
  template <class Solver>
  bool operator()(const Solver& s) { return static_cast<bool>(p_(s)); }  ///< The predicate's value
  [[nodiscard]] std::string describe() const { return description_; }  ///< The description given
  [[nodiscard]] std::string reason() const { return description_; }  ///< The description given

 private:
  P p_;
  std::string description_;
};

/// a || b: holds when either holds; both are evaluated every time. reason(): the reasons of the
/// sides that held, joined by "; ".
template <class A, class B>
class any_of : public condition_tag {
 public:
  any_of(A a, B b) : a_(std::move(a)), b_(std::move(b)) {}  ///< Either of a and b (any_of: operator||)
  template <class Solver>
  void start(const Solver& s) {  ///< Restarts both sides
    a_.start(s);
    b_.start(s);
  }
  template <class Solver>
  bool operator()(const Solver& s) {  ///< Evaluates both sides (no short circuit); true when either holds
    held_a_ = a_(s);
    held_b_ = b_(s);
    return held_a_ || held_b_;
  }
  [[nodiscard]] std::string describe() const { return "(" + a_.describe() + ") or (" + b_.describe() + ")"; }  ///< "(a) or (b)"
  [[nodiscard]] std::string reason() const {  ///< The reasons of the sides that held, joined by "; "
    if (held_a_ && held_b_) return a_.reason() + "; " + b_.reason();
    return held_a_ ? a_.reason() : held_b_ ? b_.reason() : "neither (" + describe() + ") held";
  }
  [[nodiscard]] const A& first() const { return a_; }  ///< The left side
  [[nodiscard]] const B& second() const { return b_; }  ///< The right side

 private:
  A a_;
  B b_;
  bool held_a_ = false, held_b_ = false;
};

/// a && b: holds when both hold; both are evaluated every time. reason(): both reasons, "; ".
template <class A, class B>
class all_of : public condition_tag {
 public:
  all_of(A a, B b) : a_(std::move(a)), b_(std::move(b)) {}  ///< Both of a and b (all_of: operator&&)
  template <class Solver>
  void start(const Solver& s) {  ///< Restarts both sides
    a_.start(s);
    b_.start(s);
  }
  template <class Solver>
  bool operator()(const Solver& s) {  ///< Evaluates both sides; true when both hold
    const bool a = a_(s);
    const bool b = b_(s);
    held_ = a && b;
    return held_;
  }
  [[nodiscard]] std::string describe() const { return "(" + a_.describe() + ") and (" + b_.describe() + ")"; }  ///< "(a) and (b)"
  [[nodiscard]] std::string reason() const {  ///< Both reasons, joined by "; "
    return held_ ? a_.reason() + "; " + b_.reason() : "not both of (" + describe() + ")";
  }
  [[nodiscard]] const A& first() const { return a_; }  ///< The left side
  [[nodiscard]] const B& second() const { return b_; }  ///< The right side

 private:
  A a_;
  B b_;
  bool held_ = false;
};

template <Condition A, Condition B>
[[nodiscard]] any_of<std::remove_cvref_t<A>, std::remove_cvref_t<B>> operator||(A&& a, B&& b) {
  return {std::forward<A>(a), std::forward<B>(b)};
}
template <Condition A, Condition B>
[[nodiscard]] all_of<std::remove_cvref_t<A>, std::remove_cvref_t<B>> operator&&(A&& a, B&& b) {
  return {std::forward<A>(a), std::forward<B>(b)};
}

}  // namespace tessera::stop
