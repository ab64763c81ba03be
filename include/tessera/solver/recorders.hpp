#pragma once
// Recorders: Odeint-style observers of a running solver, and the measurements they take.
// solver::run(n, observers...) calls every observer as observer(solver) after each step;
// recorders::every(k, f) calls f only every k steps (one integer test per step, so a recorder
// never slows the loop), and the measurements below are O(group size) when they run.
// recorders::csv_recorder writes named quantities (solver/stop_conditions.hpp's tessera::quantity,
// or any callable real(const Solver&)) to a CSV file as the run goes.

#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../io/atomic_file.hpp"
#include "../io/csv.hpp"
#include "boundary.hpp"

namespace tessera::recorders {

/// Sum of the reactions (N) of a group: the force the supports exert on those nodes.
[[nodiscard]] inline vec3 reaction_sum(const node_set& nodes, const bc::node_group& group) {
  vec3 s = vec3::Zero();
  for (index_t i : group.nodes) s += nodes.reaction.row(i).transpose();
  return s;
}

/// Mean displacement (m) of a group.
[[nodiscard]] inline vec3 mean_displacement(const node_set& nodes, const bc::node_group& group) {
  vec3 s = vec3::Zero();
  for (index_t i : group.nodes) s += nodes.displacement.row(i).transpose();
  return group.empty() ? s : vec3(s / static_cast<real>(group.size()));
}

/// Observer adaptor: calls f(solver) when the solver's step count is a multiple of `interval`.
template <class F>
class every {
 public:
  every(index_t interval, F f) : interval_(interval < 1 ? 1 : interval), f_(std::move(f)) {}  ///< Calls f every interval steps (an interval below 1 counts as 1)
  template <class Solver>
  void operator()(const Solver& s) {  ///< Calls f(s) when s.step_count() is a multiple of the interval
    if (s.step_count() % interval_ == 0) f_(s);
  }

 private:
  index_t interval_;
  F f_;
};

/// When a csv_recorder writes a row: every `steps` steps, or every `seconds` of simulated time.
struct sampling {
  std::int64_t steps = 0;  ///< > 0: when the solver's step count is a multiple of it
  real seconds = 0;        ///< > 0: at the first step at or past each multiple of it since the recorder was made (s)
};
/// A row every k steps (k >= 1).
[[nodiscard]] inline sampling every_steps(std::int64_t k) {
  require(k >= 1, "recorders::every_steps: k = ", k, " must be >= 1");
  return {k, 0};
}
/// A row every dt_s of simulated time (s, > 0).
[[nodiscard]] inline sampling every_seconds(real dt_s) {
  require(std::isfinite(dt_s) && dt_s > 0, "recorders::every_seconds: interval ", dt_s, " s must be finite and > 0");
  return {0, dt_s};
}

/// One column of a csv_recorder: its name, its unit (SI; the header reads name_unit, or name when
/// the unit is empty) and the quantity, any callable real(const Solver&) (e.g. quantity::time()).
template <class Solver>
struct csv_column {
  std::string name;  ///< column name (no comma, quote or line break)
  std::string unit;  ///< SI unit, e.g. "m" (may be empty)
  std::function<real(const Solver&)> quantity;  ///< the value written, real(const Solver&)
};

/// An observer (solver::run / run_until) writing named quantities to a CSV file: a header line
/// `step,time_s,<name>_<unit>,...`, then one row per sample at full precision (io::csv_writer's
/// format), the first row the state when the recorder is made.
///
///     recorders::csv_recorder rec(s, "out/drop.csv",
///                                 {{"uz", "m", quantity::block_displacement(1, 2)},
///                                  {"Rz", "N", quantity::reaction_sum(s.gridpoints_of_block(0), 2)}},
///                                 recorders::every_steps(100));
///     s.run_until(stop::after_time(1.0), 10'000'000, rec);
///     rec.close();                                       // the file appears at out/drop.csv
///
/// The rows go to a temporary file beside the target (io::atomic_ofstream: path.tmp.<pid>),
/// renamed onto the target by close(), or by the destructor when no exception is propagating; a
/// run killed or unwound by an exception leaves no file that looks finished (the temporary is
/// removed, and a signal handler of io::run_record removes it on a kill).
/// Cost: one integer test (or one comparison of times) per step; the quantities (one std::function
/// call each) and the formatting only on the rows written. Move-only; not thread-safe.
template <class Solver>
class csv_recorder {
 public:
  /// Opens the file and writes the header and the first row (the solver's state now), so a bad
  /// quantity (e.g. a block that does not exist) throws here, before any step. Throws
  /// invalid_input for no column, an empty name, a name or unit with a comma, quote or line
  /// break, a column named twice or a quantity that is empty; io_error when the file cannot be
  /// opened.
  csv_recorder(const Solver& s, const std::filesystem::path& path, std::vector<csv_column<Solver>> columns,
               sampling when = every_steps(1))
      : columns_(std::move(columns)), when_(when), exceptions_(std::uncaught_exceptions()) {
    require(!columns_.empty(), "csv_recorder '", path.string(), "': no column given");
    require(when.steps >= 1 || (std::isfinite(when.seconds) && when.seconds > 0), "csv_recorder '", path.string(),
            "': sampling every ", when.steps, " steps / ", when.seconds,
            " s is empty; use recorders::every_steps(k) or recorders::every_seconds(dt_s)");
    std::vector<std::string> header{"step", "time_s"};
    for (const csv_column<Solver>& c : columns_) {
      require(!c.name.empty(), "csv_recorder '", path.string(), "': a column has an empty name");
      for (const std::string* text : {&c.name, &c.unit})
        require(text->find_first_of(",\"\r\n") == std::string::npos, "csv_recorder '", path.string(), "': column '",
                *text, "' contains a comma, quote or line break");
      require(static_cast<bool>(c.quantity), "csv_recorder '", path.string(), "': column '", c.name, "' has no quantity");
      std::string name = c.unit.empty() ? c.name : c.name + "_" + c.unit;
      for (const std::string& h : header)
        require(h != name, "csv_recorder '", path.string(), "': column '", name, "' is named twice");
      header.push_back(std::move(name));
    }
    values_.assign(columns_.size(), 0);
    for (std::size_t j = 0; j < columns_.size(); ++j) values_[j] = columns_[j].quantity(s);  // refusals before the file
    out_ = std::make_unique<io::atomic_ofstream>(path);
    std::ostream& os = out_->stream();
    os << std::setprecision(std::numeric_limits<double>::max_digits10);
    for (std::size_t j = 0; j < header.size(); ++j) os << (j ? "," : "") << header[j];
    os << '\n';
    next_time_ = s.time() + when_.seconds;
    write_row(s.step_count(), s.time());
  }
  csv_recorder(csv_recorder&&) noexcept = default;  ///< Moves the open file with it
  csv_recorder& operator=(csv_recorder&&) = delete;
  csv_recorder(const csv_recorder&) = delete;
  csv_recorder& operator=(const csv_recorder&) = delete;
  /// Commits the file (close()) unless an exception is propagating, in which case the temporary
  /// file is removed and the target is left as it was. Errors of a commit here are swallowed
  /// (call close() to see them).
  ~csv_recorder() {
    if (!out_) return;
    if (std::uncaught_exceptions() > exceptions_) return;  // out_'s destructor removes the temporary
    try {
      out_->commit();
    } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor must not throw; close() reports
    }
  }

  /// The observer: writes a row when the sampling says so.
  void operator()(const Solver& s) {
    if (when_.steps > 0) {
      if (s.step_count() % when_.steps != 0) return;
    } else {
      if (s.time() < next_time_) return;
      // The next multiple of the interval past t, counted from the recorder's start.
      while (next_time_ <= s.time()) next_time_ += when_.seconds;
    }
    record(s);
  }
  /// Writes a row now (e.g. the final state); throws invalid_input after close().
  void record(const Solver& s) {
    require(static_cast<bool>(out_) && !closed_, "csv_recorder: record() after close()");
    for (std::size_t j = 0; j < columns_.size(); ++j) values_[j] = columns_[j].quantity(s);
    write_row(s.step_count(), s.time());
  }
  /// Flushes the rows and renames the temporary file onto the target (io_error on failure). A
  /// second call does nothing.
  void close() {
    if (!out_ || closed_) return;
    out_->commit();
    closed_ = true;
  }
  /// Rows written, the first (construction) row included.
  [[nodiscard]] std::int64_t rows() const { return rows_; }
  /// The file the rows appear in after close().
  [[nodiscard]] const std::filesystem::path& path() const { return out_->target(); }
  /// The temporary file the rows go to until close().
  [[nodiscard]] const std::filesystem::path& temporary_path() const { return out_->temporary(); }

 private:
  void write_row(std::int64_t step, real t) {
    std::ostream& os = out_->stream();
    os << step << ',';
    io::csv_writer::write_number(os, t);
    for (const real v : values_) {
      os << ',';
      io::csv_writer::write_number(os, v);
    }
    os << '\n';
    ++rows_;
  }

  std::vector<csv_column<Solver>> columns_;
  sampling when_;
  int exceptions_;                            ///< uncaught exceptions when made (a destructor during unwinding discards)
  std::unique_ptr<io::atomic_ofstream> out_;
  std::vector<real> values_;                  ///< one row's values, reused (no allocation per row)
  real next_time_ = 0;                        ///< every_seconds: time of the next row (s)
  std::int64_t rows_ = 0;
  bool closed_ = false;
};

}  // namespace tessera::recorders
