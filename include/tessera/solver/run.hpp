#pragma once
// Running a solver: n steps, or steps until a stop condition holds (solver/stop_conditions.hpp),
// with observers (solver/recorders.hpp) called after each step. solver<...> derives from
// solver_runs<solver<...>> (CRTP), so s.run(...) and s.run_until(...) are members of the solver
// as a user sees them; each step is the solver's step(), and the observers' time is booked in
// its phase_times::recorders (the solver names this base its friend).
//
// Cost: the steps, the observers, and two clock reads per step when there are observers.
// Thread safety: as the solver (one thread).

#include <chrono>
#include <cstdint>
#include <string>
#include <utility>

#include "../core/errors.hpp"
#include "options.hpp"

namespace tessera {

/// The running part of solver<...> (file comment). Solver is the derived solver type.
template <class Solver>
class solver_runs {
 public:
  /// Runs n_steps steps, calling observer(*this) after each (wrap with recorders::every).
  template <class... Observers>
  void run(std::int64_t n_steps, Observers&&... observers) {
    for (std::int64_t k = 0; k < n_steps; ++k) {
      self().step();
      observe(observers...);
    }
  }
  /// Steps until stop(*this) is true or max_steps (>= 0) were taken, calling observer(*this)
  /// after each step. stop is evaluated before every step, the first time before any step; a
  /// condition of solver/stop_conditions.hpp (stop::after_time(1.0) || stop::when_beyond(...)) is
  /// first restarted (stop.start(*this), where the predicate has it), so it counts from this call.
  /// Returns the steps taken, the reason (stop.reason() where the predicate has it), whether
  /// max_steps ran out first and the damping in force (damping_in_force()); converts to the step
  /// count. Throws invalid_input for max_steps < 0.
  template <class Predicate, class... Observers>
  run_result run_until(Predicate&& stop, std::int64_t max_steps, Observers&&... observers) {
    require(max_steps >= 0, "solver: run_until max_steps = ", max_steps, " must be >= 0");
    const Solver& s = self();
    if constexpr (requires { stop.start(s); }) stop.start(s);
    run_result result;
    result.damping = damping_in_force();
    bool stopped = false;
    while (!(stopped = stop(s)) && result.steps < max_steps) {
      self().step();
      ++result.steps;
      observe(observers...);
    }
    result.hit_max_steps = !stopped;
    if (!stopped)
      result.reason = detail::concat("max_steps = ", max_steps, " reached");
    else if constexpr (requires { stop.reason(); })
      result.reason = stop.reason();
    else
      result.reason = "the stop predicate returned true";
    return result;
  }
  /// The damping in force, e.g. "local damping gamma = 0.8 (integrator::quasi_static: ...)" or
  /// "no damping (integrator::dynamic: ...)": the integrator's describe_damping() where it has one.
  [[nodiscard]] std::string damping_in_force() const {
    const auto& integrator = static_cast<const Solver&>(*this).integrator_;
    if constexpr (requires { integrator.describe_damping(); })
      return integrator.describe_damping();
    else
      return "the integrator's own (it has no describe_damping())";
  }

 protected:
  solver_runs() = default;  // only as the base of a solver

 private:
  [[nodiscard]] Solver& self() { return static_cast<Solver&>(*this); }

  template <class... Observers>
  void observe(Observers&... observers) {
    if constexpr (sizeof...(Observers) > 0) {
      const auto start = std::chrono::steady_clock::now();
      (observers(std::as_const(self())), ...);
      self().phases_.recorders += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
  }
};

}  // namespace tessera
