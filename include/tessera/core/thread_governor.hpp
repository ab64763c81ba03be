#pragma once
// A thread governor: picks the OpenMP thread count of a run from the run's own step times.
//
// Why: a solver step meets a few fork/joins, and a thread that shares its core with another
// process waits up to a scheduler time slice at each one, so on a machine where another program
// takes a core, 2 threads run 10-30x slower than 1 (docs/performance.md, "Threads on a busy
// machine"). Counting idle cores once at start misses a load that comes later and a core that
// frees later. Results do not depend on the thread count (core/parallel.hpp: gathers and
// fixed-order sums), so the count may change between two steps without changing a bit.
//
// How: the governor runs the current count for a probe interval of run time, then measures the
// time per step over one window on the current count and over one window on a neighbouring count
// (half or double, within [1, max]), and keeps the neighbour when it is faster by the margin. A
// lost probe doubles the interval (up to max_backoff x), a won one resets it, so a run that loses
// a core falls back to fewer threads within seconds and climbs back when the core frees. A probe
// whose first quarter window (or one step as long) is already twice as slow ends there; a quarter
// window on the current count twice as slow as its last measurement starts a probe at once (a load
// that came since is met within about half a second, not a probe interval).
// A window's time per step is the mean of the middle two of its four quarter means (each quarter
// at least window_s / 4 of run time), so one slow step (a rebuild, a snapshot written by an
// observer) does not decide.
//
// thread_governor is the decision alone (numbers in, thread count out); the process-wide
// governor below (start_thread_governor, thread_governor_step) feeds it with the wall time
// between the solver's steps and applies its choice. No allocation after construction.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "tessera/core/errors.hpp"
#include "tessera/core/parallel.hpp"

namespace tessera {

/// Settings of thread_governor. Times are seconds of run (the sum of the step times fed).
struct thread_governor_params {
  double probe_interval_s = 2.0;  ///< run time on a count before probing another (s), times the backoff
  double window_s = 0.2;          ///< length of each of the two measurement windows (s)
  double margin = 0.1;            ///< a probed count is kept when its time per step < (1 - margin) x the current's
  int max_backoff = 4;            ///< a lost probe doubles the interval, up to max_backoff x probe_interval_s
  int settle_steps = 2;           ///< steps after a switch that no window counts (threads waking, caches)
};

/// The governor's decision logic. Not thread-safe: feed it from the one thread that steps the run.
class thread_governor {
 public:
  /// Starts on `threads` threads, never going above `max_threads` or below 1. Throws invalid_input
  /// for max_threads < 1, threads outside [1, max_threads], or params with a probe interval or
  /// window that is not > 0, a margin outside [0, 1), max_backoff < 1 or settle_steps < 0.
  thread_governor(int threads, int max_threads, const thread_governor_params& params = {})
      : params_(params), max_(max_threads), current_(threads) {
    require(max_threads >= 1, "thread_governor: max_threads = ", max_threads, " must be >= 1");
    require(threads >= 1 && threads <= max_threads, "thread_governor: threads = ", threads, " must be in [1, ",
            max_threads, "]");
    require_positive(params.probe_interval_s, "thread_governor: probe_interval_s (s)");
    require_positive(params.window_s, "thread_governor: window_s (s)");
    require(params.margin >= 0 && params.margin < 1, "thread_governor: margin = ", params.margin,
            " must be in [0, 1)");
    require(params.max_backoff >= 1, "thread_governor: max_backoff = ", params.max_backoff, " must be >= 1");
    require(params.settle_steps >= 0, "thread_governor: settle_steps = ", params.settle_steps, " must be >= 0");
  }

  /// Feeds the wall time of one step (s, >= 0; a negative or non-finite time is refused with
  /// invalid_input) and returns the thread count for the next step.
  int record_step(double step_seconds) {
    require(step_seconds >= 0 && std::isfinite(step_seconds), "thread_governor: step time = ", step_seconds,
            " s must be finite and >= 0");
    if (max_ == 1) return current_;
    switch (phase_) {
      case phase::running:
        since_probe_ += step_seconds;
        if (since_probe_ >= params_.probe_interval_s * backoff_ || slowed_down(step_seconds))
          start_window(phase::measuring_current, 0);
        break;
      case phase::measuring_current:
        if (!add_to_window(step_seconds)) break;
        current_time_ = window_time();
        previous_ = current_;
        current_ = probe_count();
        ++probes_;
        start_window(phase::measuring_probe, params_.settle_steps);
        break;
      case phase::measuring_probe: {
        // A probe of a count on the cliff (a core taken) ends as soon as it is clearly slower: after
        // one step (settling steps included) that alone fills a quarter window at twice the
        // current count's time per step, or after a first quarter window twice as slow. Such a
        // probe costs a step or a quarter window, not a whole window.
        const bool slow_step = step_seconds >= 0.25 * params_.window_s && step_seconds > 2 * current_time_;
        const bool done = !slow_step && add_to_window(step_seconds);
        const bool hopeless =
            slow_step || (quarter_ == 1 && quarter_steps_ == 0 && quarter_mean_[0] > 2 * current_time_);
        if (!done && !hopeless) break;
        if (done && window_time() < (1 - params_.margin) * current_time_) {
          reference_time_ = window_time();
          backoff_ = 1;  // a change of load: look again soon
          ++switches_;
        } else {
          reference_time_ = current_time_;
          current_ = previous_;
          backoff_ = std::min(2 * backoff_, params_.max_backoff);
        }
        start_window(phase::running, 0);
        since_probe_ = 0;
        break;
      }
    }
    return current_;
  }

  /// Restarts on `threads` (in [1, max_threads], else invalid_input), e.g. when something else
  /// set the thread count; the next probe comes a full interval later.
  void restart_at(int threads) {
    require(threads >= 1 && threads <= max_, "thread_governor: threads = ", threads, " must be in [1, ", max_, "]");
    current_ = threads;
    start_window(phase::running, 0);
    since_probe_ = 0;
    reference_time_ = 0;
  }

  [[nodiscard]] int threads() const { return current_; }  ///< Threads in use now
  [[nodiscard]] int max_threads() const { return max_; }  ///< Most threads it may use
  /// Probes started and probes that won (the count changed for good), for a run's summary.
  [[nodiscard]] int probes() const { return probes_; }
  [[nodiscard]] int switches() const { return switches_; }  ///< Changes of the thread count so far

 private:
  enum class phase { running, measuring_current, measuring_probe };

  /// Half or double the current count within [1, max]; alternates between the two where both exist.
  int probe_count() {
    const int down = std::max(1, current_ / 2), up = std::min(max_, 2 * current_);
    if (current_ == max_) return down;
    if (current_ == 1) return up;
    probe_up_ = !probe_up_;
    return probe_up_ ? up : down;
  }
  void start_window(phase p, int skip) {
    phase_ = p;
    skip_ = skip;
    quarter_ = 0;
    slow_quarters_ = 0;
    quarter_time_ = 0;
    quarter_steps_ = 0;
  }
  /// Adds a step to the window; true when its fourth quarter is complete.
  bool add_to_window(double step_seconds) {
    if (skip_ > 0) {
      --skip_;
      return false;
    }
    quarter_time_ += step_seconds;
    ++quarter_steps_;
    if (quarter_time_ < 0.25 * params_.window_s) return false;
    quarter_mean_[static_cast<std::size_t>(quarter_)] = quarter_time_ / quarter_steps_;
    quarter_time_ = 0;
    quarter_steps_ = 0;
    return ++quarter_ == 4;
  }
  /// While running: true when two quarter windows in a row have a time per step above twice the
  /// current count's last measured one (a core was taken since; one slow step fills one quarter
  /// at most), so the next probe comes now rather than after the interval. Needs a measurement
  /// first (none before the first probe ends).
  bool slowed_down(double step_seconds) {
    if (reference_time_ <= 0) return false;
    quarter_time_ += step_seconds;
    ++quarter_steps_;
    if (quarter_time_ < 0.25 * params_.window_s) return false;
    slow_quarters_ = quarter_time_ / quarter_steps_ > 2 * reference_time_ ? slow_quarters_ + 1 : 0;
    quarter_time_ = 0;
    quarter_steps_ = 0;
    return slow_quarters_ >= 2;
  }
  /// Time per step of the window (s): mean of the middle two quarter means.
  [[nodiscard]] double window_time() {
    std::sort(quarter_mean_.begin(), quarter_mean_.end());
    return 0.5 * (quarter_mean_[1] + quarter_mean_[2]);
  }

  thread_governor_params params_;
  int max_;
  int current_;
  int previous_ = 1;
  phase phase_ = phase::running;
  double since_probe_ = 0;
  int backoff_ = 1;
  bool probe_up_ = false;
  int skip_ = 0;
  int quarter_ = 0;
  int slow_quarters_ = 0;  ///< quarter windows in a row, while running, above twice reference_time_
  double quarter_time_ = 0;
  int quarter_steps_ = 0;
  std::array<double, 4> quarter_mean_{};
  double current_time_ = 0;
  double reference_time_ = 0;  ///< the current count's time per step at the last probe (s); 0 = none yet
  int probes_ = 0;
  int switches_ = 0;
};

namespace detail {
/// The process-wide governor the solver's steps feed (one OpenMP thread count per process).
struct process_thread_governor {
  bool on = false;
  thread_governor governor{1, 1};
  std::chrono::steady_clock::time_point last_step{};
  bool has_last_step = false;
};
inline process_thread_governor& process_governor() {
  static process_thread_governor g;
  return g;
}
}  // namespace detail

/// Lets the process-wide governor choose the thread count of every later solver step, starting
/// on `threads` and never above `max_threads` (say, the machine's cores); sets `threads` now.
/// Throws invalid_input as thread_governor's constructor does. Call it from the thread that
/// steps the solvers (the governor is not thread-safe), before the run.
inline void start_thread_governor(int threads, int max_threads, const thread_governor_params& params = {}) {
  detail::process_thread_governor& g = detail::process_governor();
  g.governor = thread_governor(threads, max_threads, params);
  g.on = true;
  g.has_last_step = false;
  set_threads(threads);
}

/// Stops the process-wide governor; the thread count stays where it is.
inline void stop_thread_governor() { detail::process_governor().on = false; }

/// The process-wide governor while it runs, else nullptr (for a run's summary: probes, switches).
[[nodiscard]] inline const thread_governor* running_thread_governor() {
  const detail::process_thread_governor& g = detail::process_governor();
  return g.on ? &g.governor : nullptr;
}

/// Called once per solver step (solver::step() does): while the governor runs, feeds it the wall
/// time since the previous call and applies the thread count it returns; otherwise does nothing.
/// A thread count changed by someone else (set_threads, a solver's options.threads) restarts the
/// governor on that count. Never changes results (file comment); allocates nothing.
inline void thread_governor_step() {
  detail::process_thread_governor& g = detail::process_governor();
  if (!g.on) return;
  const auto now = std::chrono::steady_clock::now();
  const int actual = std::clamp(max_threads(), 1, g.governor.max_threads());
  if (actual != g.governor.threads()) g.governor.restart_at(actual);
  if (g.has_last_step) {
    const int wanted = g.governor.record_step(std::chrono::duration<double>(now - g.last_step).count());
    if (wanted != actual) set_threads(wanted);
  }
  g.last_step = now;
  g.has_last_step = true;
}

}  // namespace tessera
