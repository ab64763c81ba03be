#pragma once
// Stop conditions and quantities as the module hands them to run_until (tessera_module.cpp): the
// C++ classes of solver/stop_conditions.hpp behind a variant (any_quantity, any_condition), Python
// callables as a quantity (quantity.of) or a condition (stop.when), the Ctrl-C check, and the CSV
// recorders of the bound solver types run along (csv_record). So a run driven from Python takes
// the same steps and gives the same bits as the C++ program that spells the condition out.
#include <pybind11/pybind11.h>

#include <tessera/instances.hpp>  // the solver types a csv_record may record
#include <tessera/solver.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <variant>

namespace tessera::python {

namespace py = pybind11;

// ---- quantities and stop conditions: the C++ classes behind a variant ---------------------------

/// A Python callable held by C++ copies of a condition or quantity, released with the GIL taken
/// (the last copy may go in run_until, where the GIL is released).
inline std::shared_ptr<py::object> shared_callable(py::object fn) {
  return {new py::object(std::move(fn)), [](py::object* o) {
            py::gil_scoped_acquire gil;
            delete o;
          }};
}

/// A Python callable fn(solver) -> float as a quantity (quantity.of): called with the GIL taken
/// at each evaluation (every step inside when_settled or when_beyond), so it costs a Python call
/// a step; the C++ quantities cost none.
struct python_quantity {
  std::shared_ptr<py::object> fn;  // shared: copies of a quantity call the same function
  std::string description;
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const {
    py::gil_scoped_acquire gil;
    const py::object v = (*fn)(py::cast(&s, py::return_value_policy::reference));
    const double x = PyFloat_AsDouble(v.ptr());  // float(v): any real number
    if (x == -1.0 && PyErr_Occurred() != nullptr) {
      PyErr_Clear();
      throw invalid_input(detail::concat("quantity.of '", description, "': returned ",
                                         py::repr(v).cast<std::string>(), ", not a number"));
    }
    return x;
  }
  [[nodiscard]] std::string describe() const { return description; }
};

/// One of tessera::quantity's quantities, chosen at run time; evaluated as the quantity itself.
struct any_quantity {
  std::variant<quantity::time, quantity::block_displacement, quantity::block_displacement_magnitude,
               quantity::block_velocity, quantity::block_speed, quantity::max_block_speed, quantity::kinetic_energy,
               quantity::reaction_sum, quantity::mean_displacement, python_quantity>
      q;
  template <class Solver>
  [[nodiscard]] real operator()(const Solver& s) const {
    return std::visit([&](const auto& x) { return static_cast<real>(x(s)); }, q);
  }
  [[nodiscard]] std::string describe() const {
    return std::visit([](const auto& x) { return quantity::describe(x); }, q);
  }
};

/// A Python callable fn(solver) -> bool as a stop condition (stop.when), called at every
/// `every`-th evaluation since run_until started (the first before any step), with the GIL taken
/// there; the interpreter's signals are checked at the same moments (Ctrl-C: KeyboardInterrupt).
struct python_predicate : stop::condition_tag {
  std::shared_ptr<py::object> fn;  // shared: copies of a condition call the same function
  std::int64_t every = 100;
  std::string description;
  std::int64_t evaluations = 0;
  template <class Solver>
  void start(const Solver& /*s*/) { evaluations = 0; }
  [[nodiscard]] std::string describe() const { return description; }
  [[nodiscard]] std::string reason() const { return description; }
  template <class Solver>
  bool operator()(const Solver& s) {
    if (evaluations++ % every != 0) return false;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    const py::object held = (*fn)(py::cast(&s, py::return_value_policy::reference));
    const int truth = PyObject_IsTrue(held.ptr());  // bool(held)
    if (truth < 0) throw py::error_already_set();
    return truth == 1;
  }
};

/// Checks the interpreter's signals every 1000 evaluations (run_until's Ctrl-C); never holds.
struct interrupt_check : stop::condition_tag {
  std::int64_t evaluations = 0;
  template <class Solver>
  void start(const Solver& /*s*/) { evaluations = 0; }
  template <class Solver>
  bool operator()(const Solver& /*s*/) {
    if (++evaluations % 1000 != 0) return false;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    return false;
  }
  [[nodiscard]] std::string describe() const { return "interrupted"; }
  [[nodiscard]] std::string reason() const { return "interrupted"; }
};

/// The C++ recorders::csv_recorder of one bound solver type, run inside run_until (its
/// `record` list) as a stop condition that never holds: called at the condition's evaluations
/// (before each step, and once after the last), at most once per step count, so it writes the
/// rows the C++ observer writes after the steps (its first row when it is made).
struct csv_record {
  std::variant<std::unique_ptr<recorders::csv_recorder<instances::rigid_dry_damped_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::rigid_dry_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::prism_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::tie_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::deformable_dry_damped_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::deformable_dry_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::rigid_bonded_damped_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::rigid_bonded_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::prism_undamped_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::tie_undamped_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::beam_solver>>,
               std::unique_ptr<recorders::csv_recorder<instances::beam_undamped_solver>>>
      rec;
  std::int64_t last_step = -1;  ///< the step count of the last call (the row made with it)
  template <class Solver>
  void observe(const Solver& s) {
    auto* r = std::get_if<std::unique_ptr<recorders::csv_recorder<Solver>>>(&rec);
    require(r != nullptr && *r != nullptr, "csv_recorder: passed to a run of another solver type, or closed");
    if (s.step_count() == last_step) return;
    last_step = s.step_count();
    (**r)(s);
  }
  void close() {
    std::visit([](auto& p) { if (p) p->close(); }, rec);
  }
  [[nodiscard]] std::int64_t rows() const {
    return std::visit([](const auto& p) { return p ? p->rows() : std::int64_t{0}; }, rec);
  }
  /// Drops the recorder as an exception would: its rows' temporary file is removed and the
  /// target left as it was (recorders::csv_recorder's destructor during unwinding).
  void discard() {
    std::visit(
        [](auto& p) {
          struct drop_while_unwinding {
            std::remove_reference_t<decltype(p)>& q;
            ~drop_while_unwinding() { q.reset(); }
          };
          try {
            const drop_while_unwinding d{p};
            throw 0;
          } catch (int) {  // NOLINT(bugprone-empty-catch): only the unwinding was wanted
          }
        },
        rec);
  }
};

/// A csv_record as a stop condition that never holds (run_until's `record` list).
struct recording : stop::condition_tag {
  std::shared_ptr<csv_record> rec;
  template <class Solver>
  void start(const Solver& /*s*/) {}
  template <class Solver>
  bool operator()(const Solver& s) {
    rec->observe(s);
    return false;
  }
  [[nodiscard]] std::string describe() const { return "recording"; }
  [[nodiscard]] std::string reason() const { return "recording"; }
};

struct any_condition;
using any_of_node = stop::any_of<any_condition, any_condition>;
using all_of_node = stop::all_of<any_condition, any_condition>;

/// One of tessera::stop's conditions, or `a | b`, `a & b` of two; evaluated as the condition.
struct any_condition : stop::condition_tag {
  std::variant<stop::after_steps, stop::after_time, stop::when_settled<any_quantity>, stop::when_beyond<any_quantity>,
               stop::kinetic_energy_below, python_predicate, recording, std::shared_ptr<any_of_node>,
               std::shared_ptr<all_of_node>>
      c;
  /// Calls f on the condition held (through the pointer for a composite), const or not as self.
  template <class Self, class F>
  static decltype(auto) visit(Self& self, F&& f) {
    return std::visit(
        [&](auto& x) -> decltype(auto) {
          if constexpr (requires { *x; })
            return f(*x);
          else
            return f(x);
        },
        self.c);
  }
  template <class Solver>
  void start(const Solver& s) {
    visit(*this, [&](auto& x) { x.start(s); });
  }
  template <class Solver>
  bool operator()(const Solver& s) {
    return visit(*this, [&](auto& x) { return static_cast<bool>(x(s)); });
  }
  [[nodiscard]] std::string describe() const {
    return visit(*this, [](const auto& x) { return x.describe(); });
  }
  [[nodiscard]] std::string reason() const {
    return visit(*this, [](const auto& x) { return x.reason(); });
  }
};

}  // namespace tessera::python
