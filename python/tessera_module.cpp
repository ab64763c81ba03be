// The compiled part of the Python module `tessera` (python/tessera/__init__.py re-exports it;
// docs/python.md): geometry, the dry joint law, and the solvers tessera::instances compiles once,
// named as in C++. Stop conditions and quantities are the C++ classes of solver/stop_conditions.hpp
// behind a variant (any_quantity, any_condition), so a run driven from Python takes the same steps
// and gives the same bits as the C++ program that spells the condition out. State crosses as
// read-only NumPy views of the solver's arrays (valid until the next step). tessera's exceptions
// arrive as tessera.Error (and its subclasses) with the C++ message.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tessera/blocks.hpp>
#include <tessera/contact.hpp>
#include <tessera/geometry.hpp>
#include <tessera/instances.hpp>  // the solvers compiled once (linked: tessera::instances)
#include <tessera/io/vtk.hpp>
#include <tessera/io/vtk_contacts.hpp>
#include <tessera/law.hpp>
#include <tessera/presets/pulatsu2020.hpp>  // the study's presets (study_prism_params, ...)
#include <tessera/solver.hpp>

#include "tension_reference.hpp"  // the prism script in C++ (tessera._tension_reference)

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

namespace py = pybind11;
using namespace tessera;

namespace {

// ---- quantities and stop conditions: the C++ classes behind a variant ---------------------------

/// A Python callable held by C++ copies of a condition or quantity, released with the GIL taken
/// (the last copy may go in run_until, where the GIL is released).
std::shared_ptr<py::object> shared_callable(py::object fn) {
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
               std::unique_ptr<recorders::csv_recorder<instances::prism_solver>>>
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

// ---- NumPy views ---------------------------------------------------------------------------------

/// A read-only NumPy view (n x 3, no copy) of a column-major soa3 owned by `owner`.
py::array view_of(const soa3& a, py::handle owner) {
  const auto n = static_cast<py::ssize_t>(a.rows());
  const auto item = static_cast<py::ssize_t>(sizeof(real));
  py::array v(py::dtype::of<real>(), {n, py::ssize_t{3}}, {item, n * item}, a.data(), owner);
  py::detail::array_proxy(v.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return v;
}
/// A read-only NumPy view (n, no copy) of an Eigen vector owned by `owner`.
py::array view_of(const Eigen::VectorXd& a, py::handle owner) {
  py::array v(py::dtype::of<real>(), {static_cast<py::ssize_t>(a.size())}, {static_cast<py::ssize_t>(sizeof(real))},
              a.data(), owner);
  py::detail::array_proxy(v.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return v;
}

/// A NumPy copy (n x 3) of a list of 3-vectors.
py::array rows_of(const std::vector<vec3>& v) {
  py::array_t<double> out({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
  auto w = out.mutable_unchecked<2>();
  for (std::size_t k = 0; k < v.size(); ++k)
    for (py::ssize_t d = 0; d < 3; ++d) w(static_cast<py::ssize_t>(k), d) = v[k][d];
  return out;
}

// ---- one solver type -----------------------------------------------------------------------------

/// The components argument of the supports: a bc.components value; refuses one outside xyz.
bc::components checked_components(bc::components c, const char* what) {
  const auto bits = static_cast<unsigned>(c);
  require(bits <= 7u, what, ": components = ", bits, " is not a combination of x, y and z");
  return c;
}

/// Per-sub-contact state of a contact set as NumPy arrays (copies, SI): the io::vtk contact
/// snapshot (positions, normals, areas, damage, status and every state field the law declares)
/// and the blocks each sub-contact joins. Also writes itself as a .vtp.
struct contact_state {
  io::vtk::contact_snapshot snapshot;
  std::vector<index_t> block_a, block_b;
};

template <class S>
contact_state take_contact_state(const S& s) {
  contact_state out;
  const auto& c = s.contacts();
  out.snapshot.take(c, s.gridpoints());
  const auto n = static_cast<std::size_t>(c.subcontact_count());
  out.block_a.resize(n), out.block_b.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    out.block_a[k] = c.block_a(static_cast<index_t>(k));
    out.block_b[k] = c.block_b(static_cast<index_t>(k));
  }
  return out;
}

/// Binds solver type S (one of tessera::instances') as `name` in module m.
template <class S>
void bind_solver(py::module_& m, const char* name, const char* doc) {
  py::class_<S> cls(m, name, doc);
  cls.def(py::init<const geometry::tessellation&, const geometry::block_mesh&, const typename S::blocks_type::params&,
                    const typename S::contact_set_type::params&, const typename S::reinforcement_type::params&,
                    const solver_options&>(),
           py::arg("tess"), py::arg("mesh"), py::arg("block_params"), py::arg("contact_params"),
           py::arg("reinforcement_params") = typename S::reinforcement_type::params{},
           py::arg("options") = solver_options{})
      .def("fix_block", &S::fix_block, py::arg("b"), "Holds block b (all components of all its gridpoints)")
      .def("fix_blocks", &S::fix_blocks, py::arg("blocks"), "fix_block for each listed block, all or none")
      .def("blocks_below", &S::blocks_below, py::arg("axis"), py::arg("value"), py::arg("tol") = 0.0,
           "Blocks whose reference geometry lies wholly at X[axis] <= value + tol (m)")
      .def("blocks_on_plane", &S::blocks_on_plane, py::arg("axis"), py::arg("value"), py::arg("tol"),
           "Blocks whose reference geometry reaches the plane X[axis] = value (m) within tol (m)")
      .def("gridpoints_of_block", &S::gridpoints_of_block, py::arg("b"), "All gridpoints of block b (a node_group)")
      .def("gridpoints_of_blocks", &S::gridpoints_of_blocks, py::arg("blocks"), "All gridpoints of the listed blocks")
      .def(
          "gridpoints_on_plane",
          [](const S& s, int axis, real value, real tol) {
            require(axis >= 0 && axis <= 2, "gridpoints_on_plane: axis = ", axis, " must be 0, 1 or 2");
            require(std::isfinite(value), "gridpoints_on_plane: value = ", value, " m is not finite");
            require(std::isfinite(tol) && tol >= 0, "gridpoints_on_plane: tol = ", tol, " m must be finite and >= 0");
            return s.gridpoints_on_plane(axis, value, tol);
          },
          py::arg("axis"), py::arg("value"), py::arg("tol"),
          "Gridpoints whose reference position lies on the plane X[axis] = value (m) within tol (m)")
      .def(
          "fix", [](S& s, const bc::node_group& g, bc::components c) { s.fix(g, checked_components(c, "fix")); },
          py::arg("group"), py::arg("components") = bc::components::xyz,
          "Fixes the given components of the group's gridpoints (zero velocity; reactions recorded)")
      .def(
          "prescribe_velocity",
          [](S& s, const bc::node_group& g, const vec3& v, bc::components c) {
            s.prescribe_velocity(g, v, checked_components(c, "prescribe_velocity"));
          },
          py::arg("group"), py::arg("v"), py::arg("components") = bc::components::xyz,
          "Prescribes velocity v (m/s) on the given components of the group's gridpoints")
      .def(
          "update_velocity",
          [](S& s, const bc::node_group& g, const vec3& v, bc::components c) {
            bc::update_velocity(s.gridpoints(), g, v, checked_components(c, "update_velocity"));
          },
          py::arg("group"), py::arg("v"), py::arg("components") = bc::components::xyz,
          "Changes the prescribed velocity (m/s) of components already prescribed (a loading history)")
      .def(
          "prescribe_block_velocity",
          [](S& s, index_t b, const vec3& v, bc::components c) {
            s.prescribe_block_velocity(b, v, checked_components(c, "prescribe_block_velocity"));
          },
          py::arg("b"), py::arg("v"), py::arg("components") = bc::components::xyz,
          "Prescribes the translation velocity v (m/s) on the given components of block b")
      .def(
          "update_block_velocity",
          [](S& s, index_t b, const vec3& v, bc::components c) {
            s.update_block_velocity(b, v, checked_components(c, "update_block_velocity"));
          },
          py::arg("b"), py::arg("v"), py::arg("components") = bc::components::xyz,
          "Changes block b's prescribed velocity (m/s) on components already prescribed")
      .def("set_gravity", &S::set_gravity, py::arg("g"), "Acceleration of gravity (m/s^2, a 3-vector)")
      .def("step", &S::step, "One step of dt", py::call_guard<py::gil_scoped_release>())
      .def(
          "run_until",
          [](S& s, any_condition condition, std::int64_t max_steps, const std::vector<std::shared_ptr<csv_record>>& record) {
            for (auto it = record.rbegin(); it != record.rend(); ++it)  // recorders first: each sees every step
              condition = any_condition{{}, std::make_shared<any_of_node>(any_condition{{}, recording{{}, *it}}, condition)};
            return s.run_until(stop::any_of<any_condition, interrupt_check>(std::move(condition), interrupt_check{}), max_steps);
          },
          py::arg("stop"), py::arg("max_steps") = std::int64_t{100'000'000},
          py::arg("record") = std::vector<std::shared_ptr<csv_record>>{}, py::call_guard<py::gil_scoped_release>(),
          "Steps until stop holds (evaluated before every step) or max_steps were taken; a run_result. "
          "record: csv_recorders written along. Ctrl-C stops it within 1000 steps (KeyboardInterrupt)")
      .def(
          "csv_recorder",
          [](const S& s, const std::string& path, const std::vector<std::tuple<std::string, std::string, any_quantity>>& columns,
             std::int64_t every_steps, real every_seconds) {
            require((every_steps >= 1) != (std::isfinite(every_seconds) && every_seconds > 0), "csv_recorder '", path,
                    "': give one of every_steps = ", every_steps, " (>= 1) and every_seconds = ", every_seconds,
                    " s (> 0)");
            std::vector<recorders::csv_column<S>> c;
            for (const auto& [name, unit, q] : columns) c.push_back({name, unit, q});
            auto rec = std::make_shared<csv_record>();
            rec->rec = std::make_unique<recorders::csv_recorder<S>>(
                s, path, std::move(c),
                every_steps >= 1 ? recorders::every_steps(every_steps) : recorders::every_seconds(every_seconds));
            rec->last_step = s.step_count();
            return rec;
          },
          py::arg("path"), py::arg("columns"), py::arg("every_steps") = std::int64_t{0}, py::arg("every_seconds") = 0.0,
          "recorders::csv_recorder: (name, unit, quantity) columns, a row now and every every_steps steps (or "
          "every_seconds s) of the runs it is passed to (run_until(..., record=[rec])); rec.close() makes the file appear")
      .def("dt", &S::dt, "The step the next step() takes (s)")
      .def("time", &S::time, "Simulated time since the solver was built (s)")
      .def("step_count", &S::step_count, "Steps taken since the solver was built")
      .def("block_count", &S::block_count, "Number of blocks")
      .def("block_displacement", &S::block_displacement, py::arg("b"), "Displacement of block b (m, NumPy 3-vector)")
      .def("block_velocity", &S::block_velocity, py::arg("b"), "Velocity of block b (m/s, half step)")
      .def("kinetic_energy", &S::kinetic_energy, "Kinetic energy of the model (J)")
      .def("unbalanced_force", &S::unbalanced_force, "Unbalanced force of the last step over free components (N)")
      .def("mass_scaling", &S::mass_scaling, "What mass scaling did (kg)")
      .def("energies", &S::energies, "All energy terms now (J)")
      .def("contact_count", [](const S& s) { return s.contacts().subcontact_count(); }, "Number of sub-contacts")
      .def(
          "gridpoints", [](const S& s) -> const node_set& { return s.gridpoints(); },
          py::return_value_policy::reference_internal, "The gridpoints (read-only NumPy views of their arrays)");
  if constexpr (law::DeclaresStateFields<typename S::law_type>)
    cls.def("contact_state", &take_contact_state<S>,
            "Per-sub-contact state now (a copy): stresses, openings, damage, status, blocks (NumPy arrays)");
  if constexpr (!S::blocks_type::is_rigid)
    cls.def(
        "write_zones_vtu",
        [](const S& s, const std::string& path, const geometry::block_mesh& mesh) {
          require(mesh.gridpoint_count() == s.gridpoints().size(), "write_zones_vtu: the mesh has ",
                  mesh.gridpoint_count(), " gridpoints, the solver ", s.gridpoints().size());
          const zone_stress_matrix zs = s.blocks().zone_stress();
          std::vector<io::vtk::sym_tensor> stress;
          stress.reserve(static_cast<std::size_t>(zs.rows()));
          for (Eigen::Index z = 0; z < zs.rows(); ++z) stress.push_back(io::vtk::voigt_row_to_sym_tensor(zs, z));
          io::vtk::zone_fields fields;
          fields.displacement = &s.gridpoints().displacement;
          fields.stress = stress;
          io::vtk::write_zones_vtu(path, mesh, fields);
        },
        py::arg("path"), py::arg("mesh"),
        "Writes the zones (the mesh the solver was built from) with displacement (m) and stress (Pa) as a .vtu");
  if constexpr (S::blocks_type::is_rigid)
    cls.def(
        "blocks", [](const S& s) -> const typename S::blocks_type& { return s.blocks(); },
        py::return_value_policy::reference_internal, "The block model");
}

/// The README's arch (tests/consumer/arch.cpp) as C++ spells it, stop conditions written out as
/// the templates they are: the reference the Python tests compare the Python-driven arch with,
/// bit for bit. Returns steps, dt, reason, base reaction, weight, crown sag and its step count.
py::dict arch_reference() {
  constexpr int n = 20;
  std::vector<geometry::convex_polyhedron> blocks{geometry::convex_polyhedron::box(vec3(-3, -0.5, -0.5), vec3(3, 0.5, 0))};
  for (int k = 0; k < n; ++k)
    blocks.push_back(geometry::voussoir(vec3(0, 0, 0), 2.0, 2.4, std::numbers::pi * k / n, std::numbers::pi * (k + 1) / n, 1.0));
  const auto tess = geometry::separate_blocks(blocks);
  const auto mesh = geometry::zone_blocks(tess);
  using joints = contact::detected_contacts<law::dry_joint_law>;
  const joints::params joint(law::dry_joint(1e10, 1e10, law::friction_angle::from_degrees(35)), 1e-3);
  solver<blocks::rigid, joints> s(tess, mesh, blocks::rigid::params{2400}, joint);
  s.fix_blocks(s.blocks_below(2, 0.0));
  s.set_gravity(vec3(0, 0, -9.81));
  const index_t crown = n / 2;
  const auto r = s.run_until(stop::when_settled(quantity::block_displacement(crown, 2), 1e-8, stop::over_time(0.05)) ||
                                 stop::when_beyond(quantity::block_displacement_magnitude(crown), 0.05) ||
                                 stop::after_time(3.0),
                             100'000'000);
  real weight = 0;
  for (index_t b = 0; b <= n; ++b) weight += s.blocks().weight_mass(b) * 9.81;
  py::dict d;
  d["steps"] = r.steps;
  d["dt"] = s.dt();
  d["reason"] = r.reason;
  d["hit_max_steps"] = r.hit_max_steps;
  d["base"] = recorders::reaction_sum(s.gridpoints(), s.gridpoints_of_block(0)).z();
  d["weight"] = weight;
  d["sag"] = -s.block_displacement(crown).z();
  d["time"] = s.time();
  return d;
}

}  // namespace

PYBIND11_MODULE(_tessera, m) {
  m.doc() = "tessera: 3D discontinuum mechanics (the compiled part; import tessera)";

  // ---- errors: tessera::error and its kinds as Python exceptions (base first) ----
  static py::exception<tessera::error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<tessera::invalid_input> invalid(m, "InvalidInput", error.ptr());
  static py::exception<tessera::geometry_error> geometry_err(m, "GeometryError", error.ptr());
  static py::exception<tessera::io_error> io_err(m, "IoError", error.ptr());
  static py::exception<tessera::numerical_instability> unstable(m, "NumericalInstability", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const tessera::invalid_input& e) {
      invalid(e.what());
    } catch (const tessera::geometry_error& e) {
      geometry_err(e.what());
    } catch (const tessera::io_error& e) {
      io_err(e.what());
    } catch (const tessera::numerical_instability& e) {
      unstable(e.what());
    } catch (const tessera::error& e) {
      error(e.what());
    }
  });

  // ---- geometry ----
  auto g = m.def_submodule("geometry", "Convex blocks, tessellations and their zoning (m)");
  py::class_<geometry::convex_polyhedron>(g, "convex_polyhedron", "A convex polyhedron (m)")
      .def_static("box", &geometry::convex_polyhedron::box, py::arg("lo"), py::arg("hi"),
                  "The axis-aligned box between corners lo and hi (m)")
      .def("volume", &geometry::convex_polyhedron::volume, "Volume (m^3)")
      .def("centroid", &geometry::convex_polyhedron::centroid, "Centroid (m)");
  g.def("voussoir", &geometry::voussoir, py::arg("center"), py::arg("r_in"), py::arg("r_out"), py::arg("theta_0"),
        py::arg("theta_1"), py::arg("depth"),
        "An arch block between radii r_in and r_out (m) and angles theta_0 < theta_1 (rad) about center, depth deep (m)");
  py::class_<geometry::tessellation>(g, "tessellation", "Cells with their shared faces")
      .def("cell_count", &geometry::tessellation::cell_count, "Number of cells (blocks)")
      .def("face_count", &geometry::tessellation::face_count, "Number of faces")
      .def("vertex_count", &geometry::tessellation::vertex_count, "Number of vertices");
  g.def(
      "separate_blocks",
      [](const std::vector<geometry::convex_polyhedron>& blocks) { return geometry::separate_blocks(blocks); },
      py::arg("blocks"), "A tessellation of separate blocks: cell b is blocks[b]");
  py::class_<geometry::block_mesh>(g, "block_mesh", "The tessellation's blocks zoned into gridpoints and zones")
      .def("block_count", &geometry::block_mesh::block_count, "Number of blocks")
      .def("gridpoint_count", &geometry::block_mesh::gridpoint_count, "Number of gridpoints")
      .def("zone_count", &geometry::block_mesh::zone_count, "Number of zones");
  g.def(
      "zone_blocks", [](const geometry::tessellation& t) { return geometry::zone_blocks(t); }, py::arg("tess"),
      "Zones every block of tess (default zoning options)");

  // ---- laws ----
  auto l = m.def_submodule("law", "Contact laws (Pa/m, Pa, deg)");
  py::class_<law::friction_angle>(l, "friction_angle", "A friction angle")
      .def_static("from_degrees", &law::friction_angle::from_degrees, py::arg("phi_deg"), "An angle in degrees")
      .def_static("from_radians", &law::friction_angle::from_radians, py::arg("phi"), "An angle in radians")
      .def("degrees", &law::friction_angle::degrees, "phi (deg)")
      .def("radians", &law::friction_angle::radians, "phi (rad)");
  py::class_<law::dry_joint_law::params>(l, "dry_joint_params", "The params of a dry frictional joint")
      .def_readonly("k_n", &law::dry_joint_law::params::k_n, "normal stiffness (Pa/m)")
      .def_readonly("k_s", &law::dry_joint_law::params::k_s, "shear stiffness (Pa/m)");
  l.def("dry_joint", &law::dry_joint, py::arg("k_n"), py::arg("k_s"), py::arg("phi"),
        "A dry frictional joint: k_n, k_s (Pa/m, > 0), friction angle phi in [0, 90) deg");

  // ---- blocks and contacts ----
  auto b = m.def_submodule("blocks", "Block models");
  py::class_<blocks::rigid> rigid(b, "rigid", "Rigid blocks (the model of a solver)");
  rigid.def("weight_mass", &blocks::rigid::weight_mass, py::arg("b"), "The mass gravity acts on (kg) of block b");
  py::class_<blocks::rigid::params>(rigid, "params", "A rigid block material")
      .def(py::init<real>(), py::arg("density"), "density (kg/m^3)")
      .def_readwrite("density", &blocks::rigid::params::density, "density (kg/m^3)");
  auto c = m.def_submodule("contact", "Contact sets");
  using dry_contacts = contact::detected_contacts<law::dry_joint_law>;
  py::class_<dry_contacts::params>(c, "detected_dry_joints",
                                   "contact::detected_contacts<law::dry_joint_law>::params: a dry joint law and the "
                                   "contact tolerance (m)")
      .def(py::init([](const law::dry_joint_law::params& p, real tol) { return dry_contacts::params(p, tol); }),
           py::arg("law"), py::arg("tolerance"))
      .def_readwrite("tolerance", &dry_contacts::params::tolerance, "contact tolerance (m)")
      .def_readwrite("max_rebuild_interval", &dry_contacts::params::max_rebuild_interval, "steps between rebuilds")
      .def_readwrite("allow_initial_overlap", &dry_contacts::params::allow_initial_overlap,
                     "accept overlaps within the tolerance at the start");
  py::class_<reinforcement::none::params>(m, "no_reinforcement", "The params of reinforcement::none").def(py::init<>());

  // ---- solver options, state, results ----
  py::class_<solver_options>(m, "solver_options", "Run-time options of a solver (SI)")
      .def(py::init<>())
      .def_readwrite("safety", &solver_options::safety, "dt = safety x the critical step, in (0, 1]")
      .def_readwrite("dt", &solver_options::dt, "user time step (s); 0 = automatic")
      .def_readwrite("mass_scaling_dt", &solver_options::mass_scaling_dt,
                     "> 0: nodal masses raised so this step (s) is stable, and used")
      .def_readwrite("damping_gamma", &solver_options::damping_gamma, "local damping constant")
      .def_readwrite("threads", &solver_options::threads, "OpenMP threads; 0 = leave the current setting")
      .def_readwrite("check_interval", &solver_options::check_interval, "steps between step-checker passes");
  py::class_<bc::node_group>(m, "node_group", "A named group of gridpoints")
      .def_readonly("nodes", &bc::node_group::nodes, "node indices, increasing")
      .def_readonly("name", &bc::node_group::name, "the selection's name")
      .def("__len__", &bc::node_group::size);
  py::class_<node_set>(m, "node_set", "Gridpoints: read-only NumPy views (n x 3, SI), valid until the next step")
      .def("size", &node_set::size, "Number of nodes")
      .def_property_readonly("reference", [](py::object self) { return view_of(self.cast<const node_set&>().reference, self); }, "reference positions X (m)")
      .def_property_readonly("displacement", [](py::object self) { return view_of(self.cast<const node_set&>().displacement, self); }, "displacements u (m)")
      .def_property_readonly("velocity", [](py::object self) { return view_of(self.cast<const node_set&>().velocity, self); }, "velocities, half step (m/s)")
      .def_property_readonly("reaction", [](py::object self) { return view_of(self.cast<const node_set&>().reaction, self); }, "support reactions, last step (N)")
      .def_property_readonly("mass", [](py::object self) { return view_of(self.cast<const node_set&>().mass, self); }, "lumped masses (kg)");
  py::class_<run_result>(m, "run_result", "What run_until did")
      .def_readonly("steps", &run_result::steps, "steps taken by this call")
      .def_readonly("reason", &run_result::reason, "why it stopped")
      .def_readonly("hit_max_steps", &run_result::hit_max_steps, "true when max_steps ran out first")
      .def("__int__", [](const run_result& r) { return r.steps; });
  auto rec = m.def_submodule("recorders", "Sums and means over node groups");
  rec.def("reaction_sum", &recorders::reaction_sum, py::arg("nodes"), py::arg("group"),
          "Sum of the support reactions on the group (N, NumPy 3-vector)");
  rec.def("mean_displacement", &recorders::mean_displacement, py::arg("nodes"), py::arg("group"),
          "Mean displacement of the group (m, NumPy 3-vector)");

  // ---- quantities and stop conditions ----
  auto q = m.def_submodule("quantity", "Quantities the stop conditions watch (SI)");
  py::class_<any_quantity>(q, "quantity", "A quantity of tessera::quantity")
      .def("describe", &any_quantity::describe, "What it is, with its unit");
  q.def("time", [] { return any_quantity{quantity::time{}}; }, "Simulated time (s)");
  q.def("block_displacement", [](index_t bl, int axis) { return any_quantity{quantity::block_displacement(bl, axis)}; },
        py::arg("b"), py::arg("axis"), "Component axis (0 x, 1 y, 2 z) of block b's displacement (m)");
  q.def("block_displacement_magnitude", [](index_t bl) { return any_quantity{quantity::block_displacement_magnitude(bl)}; },
        py::arg("b"), "|displacement| of block b (m)");
  q.def("block_velocity", [](index_t bl, int axis) { return any_quantity{quantity::block_velocity(bl, axis)}; },
        py::arg("b"), py::arg("axis"), "Component axis of block b's velocity (m/s)");
  q.def("block_speed", [](index_t bl) { return any_quantity{quantity::block_speed(bl)}; }, py::arg("b"),
        "Speed of block b (m/s)");
  q.def("max_block_speed", [] { return any_quantity{quantity::max_block_speed{}}; }, "Largest block speed (m/s)");
  q.def("kinetic_energy", [] { return any_quantity{quantity::kinetic_energy{}}; }, "Kinetic energy (J)");
  q.def("reaction_sum", [](bc::node_group gr, int axis) { return any_quantity{quantity::reaction_sum(std::move(gr), axis)}; },
        py::arg("group"), py::arg("axis"), "Component axis of the support reactions summed over group (N)");
  q.def(
      "of",
      [](py::object fn, std::string description) {
        python_quantity pq;
        pq.fn = shared_callable(std::move(fn));
        pq.description = std::move(description);
        return any_quantity{std::move(pq)};
      },
      py::arg("fn"), py::arg("description"),
      "A quantity of your own: fn(solver) -> float, described as `description` (with its unit), called at each "
      "evaluation with the GIL (a Python call a step inside when_settled and when_beyond)");
  q.def("mean_displacement",
        [](bc::node_group gr, int axis) { return any_quantity{quantity::mean_displacement(std::move(gr), axis)}; },
        py::arg("group"), py::arg("axis"), "Component axis of the group's mean displacement (m)");

  auto st = m.def_submodule("stop", "Stop conditions for run_until; combine with | (either) and & (both)");
  py::class_<stop::window>(st, "window", "A window of when_settled");
  st.def("over_steps", &stop::over_steps, py::arg("n"), "A window of n steps");
  st.def("over_time", &stop::over_time, py::arg("t_s"), "A window of t_s seconds of simulated time");
  py::class_<any_condition>(st, "condition", "A stop condition of tessera::stop")
      .def("describe", &any_condition::describe, "What it waits for")
      .def("reason", &any_condition::reason, "Why it held at its last evaluation")
      .def("__or__", [](const any_condition& a, const any_condition& o) {
        return any_condition{{}, std::make_shared<any_of_node>(a, o)};
      })
      .def("__and__", [](const any_condition& a, const any_condition& o) {
        return any_condition{{}, std::make_shared<all_of_node>(a, o)};
      });
  st.def("after_steps", [](std::int64_t n) { return any_condition{{}, stop::after_steps(n)}; }, py::arg("n"),
         "Once n steps were taken since run_until started");
  st.def("after_time", [](real t) { return any_condition{{}, stop::after_time(t)}; }, py::arg("t_s"),
         "Once t_s (s) of simulated time passed since run_until started");
  st.def(
      "when_settled",
      [](any_quantity qu, real tol, stop::window w) {
        return any_condition{{}, stop::when_settled<any_quantity>(std::move(qu), tol, w)};
      },
      py::arg("quantity"), py::arg("tolerance"), py::arg("window"),
      "When quantity changed by at most tolerance (its unit) over the last window");
  st.def(
      "when_beyond",
      [](any_quantity qu, real limit) { return any_condition{{}, stop::when_beyond<any_quantity>(std::move(qu), limit)}; },
      py::arg("quantity"), py::arg("limit"), "When |quantity| > limit (its unit)");
  st.def(
      "when",
      [](py::object fn, std::string description, std::int64_t every) {
        require(every >= 1, "stop::when: every = ", every, " steps must be >= 1");
        python_predicate p;
        p.fn = shared_callable(std::move(fn));
        p.every = every;
        p.description = std::move(description);
        return any_condition{{}, std::move(p)};
      },
      py::arg("fn"), py::arg("description"), py::arg("every") = std::int64_t{100},
      "When fn(solver) returns True, fn called every `every` steps (the first before any step)");
  st.def("kinetic_energy_below", [](real r) { return any_condition{{}, stop::kinetic_energy_below(r)}; },
         py::arg("ratio"), "When the kinetic energy fell to ratio (in (0, 1)) of its peak");


  // ---- supports: components, selections ----
  auto bcm = m.def_submodule("bc", "Boundary conditions: the components a support or velocity acts on");
  py::enum_<bc::components>(bcm, "components", "Velocity components a support acts on")
      .value("none", bc::components::none)
      .value("x", bc::components::x)
      .value("y", bc::components::y)
      .value("z", bc::components::z)
      .value("xy", bc::components::xy)
      .value("xz", bc::components::xz)
      .value("yz", bc::components::yz)
      .value("xyz", bc::components::xyz)
      .def("__or__", [](bc::components a, bc::components o) { return a | o; });
  bcm.def(
      "transverse_to",
      [](int axis) {
        require(axis >= 0 && axis <= 2, "bc::transverse_to: axis = ", axis, " must be 0, 1 or 2");
        return bc::transverse_to(axis);
      },
      py::arg("axis"), "The two components transverse to axis (0 x, 1 y, 2 z)");
  bcm.def(
      "along",
      [](int axis) {
        require(axis >= 0 && axis <= 2, "bc::along: axis = ", axis, " must be 0, 1 or 2");
        return bc::along(axis);
      },
      py::arg("axis"), "The single component of axis (0 x, 1 y, 2 z)");

  // ---- deformable blocks and the study's bonded joints (the prism) ----
  auto zn = m.def_submodule("zones", "Zone (tetrahedron) models of deformable blocks");
  py::class_<zones::linear_elastic_tet> tet(zn, "linear_elastic_tet", "Linear elastic constant-strain tetrahedra");
  py::class_<zones::linear_elastic_tet::params>(tet, "params", "An elastic block material (Pa, -, kg/m^3)")
      .def(py::init([](real young, real poisson, real density) {
             zones::linear_elastic_tet::params p{young, poisson, density};
             zones::linear_elastic_tet::validate(p);
             return p;
           }),
           py::arg("young"), py::arg("poisson"), py::arg("density"),
           "Young's modulus E (Pa, > 0), Poisson's ratio nu in (-1, 0.5), density (kg/m^3, > 0)")
      .def_readwrite("young", &zones::linear_elastic_tet::params::young, "E (Pa)")
      .def_readwrite("poisson", &zones::linear_elastic_tet::params::poisson, "nu (-)")
      .def_readwrite("density", &zones::linear_elastic_tet::params::density, "rho (kg/m^3)");

  using tie = instances::prism_law;
  py::class_<tie> tie_law(l, "study_tie_law",
                          "The study's bonded joint: power softening in tension, elastic compression, Coulomb "
                          "friction with residual values (law::cohesive_frictional)");
  py::class_<law::power_softening::params>(l, "power_softening_params", "Tension: power softening (Pa, J/m^2)")
      .def(py::init<>())
      .def_readwrite("f_T", &law::power_softening::params::f_T, "tensile strength (Pa)")
      .def_readwrite("G_f", &law::power_softening::params::G_f, "fracture energy (J/m^2)")
      .def_readwrite("alpha", &law::power_softening::params::alpha, "softening exponent (> 1)")
      .def_readwrite("residual_ratio", &law::power_softening::params::residual_ratio, "broken once f_t <= this x f_T");
  py::class_<law::coulomb_residual::params>(l, "coulomb_residual_params", "Shear: Coulomb with residual values (Pa)")
      .def(py::init<>())
      .def_readwrite("c_0", &law::coulomb_residual::params::c_0, "initial cohesion (Pa)")
      .def_readwrite("phi_0", &law::coulomb_residual::params::phi_0, "initial friction angle")
      .def_readwrite("c_res", &law::coulomb_residual::params::c_res, "residual cohesion (Pa)")
      .def_readwrite("phi_res", &law::coulomb_residual::params::phi_res, "residual friction angle")
      .def_readwrite("slip_breaks_tension", &law::coulomb_residual::params::slip_breaks_tension,
                     "a contact failed in shear is broken in tension too");
  py::class_<tie::params>(tie_law, "params", "The params of the study's bonded joint (Pa/m, Pa, J/m^2)")
      .def(py::init<>())
      .def_readwrite("k_n", &tie::params::k_n, "normal stiffness (Pa/m)")
      .def_readwrite("k_s", &tie::params::k_s, "shear stiffness (Pa/m)")
      .def_readwrite("tension", &tie::params::tension, "power softening: f_T (Pa), G_f (J/m^2), alpha")
      .def_readwrite("shear", &tie::params::shear, "Coulomb: c_0, phi_0, c_res, phi_res")
      .def("validate", [](const tie::params& p) { tie::validate(p); }, "Refuses bad values (tessera.Error naming one)");
  l.def("study_prism_params", &presets::study_prism_params, py::arg("blocks"),
        "The study's Table 1 prism contacts for 100, 250, 500 or 750 blocks (law::study_prism_params)");
  l.def("scaled_prism_params", &presets::scaled_prism_params, py::arg("blocks"),
        "Table 1 carried to any block count >= 2 (k_n, k_s as blocks^(1/3); law::scaled_prism_params)");
  using tie_table = contact::material_table<tie::params>;
  py::class_<tie_table>(c, "study_tie_table",
                        "contact::material_table of the study's bonded joint: params per pair of block materials")
      .def(py::init<const tie::params&>(), py::arg("all"), "One law for every pair")
      .def("set", &tie_table::set, py::arg("a"), py::arg("b"), py::arg("params"), py::return_value_policy::reference_internal,
           "Bonded params for the pair {a, b} of material ids")
      .def("never_bonded", &tie_table::never_bonded, py::arg("a"), py::arg("b"), py::arg("params"),
           py::return_value_policy::reference_internal, "The pair {a, b} starts unbonded");
  py::implicitly_convertible<tie::params, tie_table>();

  // ---- more geometry: boxes, prisms, cuts, random Voronoi tessellations, zoning options ----
  py::class_<aabb>(m, "aabb", "An axis-aligned box (m)")
      .def(py::init([](const vec3& lo, const vec3& hi) {
             require(lo.allFinite() && hi.allFinite() && (lo.array() < hi.array()).all(), "aabb: lo (", lo.transpose(),
                     ") m must be finite and below hi (", hi.transpose(), ") m in every axis");
             aabb b;
             b.lo = lo, b.hi = hi;
             return b;
           }),
           py::arg("lo"), py::arg("hi"))
      .def_readonly("lo", &aabb::lo, "lower corner (m)")
      .def_readonly("hi", &aabb::hi, "upper corner (m)")
      .def("size", &aabb::size, "hi - lo (m)")
      .def("volume", &aabb::volume, "volume (m^3)");
  py::class_<geometry::plane>(g, "plane", "The half-space n . x <= offset (n a unit normal, offset m)")
      .def(py::init([](const vec3& n, real offset) { return geometry::plane{n, offset}; }), py::arg("normal"),
           py::arg("offset"));
  g.def(
      "from_vertices", [](const std::vector<vec3>& p) { return geometry::convex_polyhedron::from_vertices(p); },
      py::arg("points"), "The convex hull of the points (m)");
  g.def(
      "prism", [](const std::vector<vec3>& polygon, const vec3& e) { return geometry::prism(polygon, e); },
      py::arg("polygon"), py::arg("extrusion"), "A convex polygon (m) extruded by the vector extrusion (m)");
  g.def("cylinder_prism", &geometry::cylinder_prism, py::arg("center"), py::arg("axis"), py::arg("radius"),
        py::arg("length"), py::arg("sides"), py::arg("phase") = 0.0,
        "A right prism of `sides` faces inscribed in a cylinder of radius (m) and length (m) about axis");
  g.def(
      "cut_by_planes",
      [](const geometry::convex_polyhedron& b, const std::vector<geometry::plane>& p) {
        return geometry::cut_by_planes(b, p);
      },
      py::arg("block"), py::arg("planes"), "The part of block inside every half-space");
  py::class_<geometry::tessellation_options>(g, "tessellation_options", "Regularisation of a random tessellation")
      .def(py::init<>())
      .def_readwrite("lloyd_iterations", &geometry::tessellation_options::lloyd_iterations, "Lloyd steps")
      .def_readwrite("min_spacing", &geometry::tessellation_options::min_spacing, "least generator spacing (m)")
      .def_readwrite("min_edge_rel", &geometry::tessellation_options::min_edge_rel,
                     "collapse edges shorter than this x the mean cell size");
  g.def(
      "random_voronoi",
      [](const aabb& box, index_t n, std::uint64_t seed, const geometry::tessellation_options& o) {
        return geometry::random_voronoi(box, n, seed, o);
      },
      py::arg("box"), py::arg("n"), py::arg("seed"), py::arg("options") = geometry::tessellation_options{},
      "Voronoi tessellation of the box (m) from n random generators (seed): the same cells for the same input");
  g.def(
      "random_voronoi",
      [](const geometry::convex_polyhedron& domain, index_t n, std::uint64_t seed, const geometry::tessellation_options& o) {
        return geometry::random_voronoi(domain, n, seed, o);
      },
      py::arg("domain"), py::arg("n"), py::arg("seed"), py::arg("options") = geometry::tessellation_options{},
      "Voronoi tessellation of a convex domain (m) from n random generators (seed)");
  py::class_<geometry::zoning_options>(g, "zoning_options", "How blocks are split into tetrahedral zones")
      .def(py::init<>())
      .def_readwrite("target_edge_length", &geometry::zoning_options::target_edge_length,
                     "zone edge target (m); 0 = one zone per face triangle")
      .def_readwrite("refine_interior", &geometry::zoning_options::refine_interior, "refine inside, not only faces");
  g.def(
      "zone_blocks",
      [](const geometry::tessellation& t, const geometry::zoning_options& o) { return geometry::zone_blocks(t, o); },
      py::arg("tess"), py::arg("options"), "Zones every block of tess with the given options");

  // ---- per-sub-contact state, energies, balance ----
  py::class_<contact_state>(m, "contact_state",
                            "Per-sub-contact state at one instant (NumPy copies, SI): write(path) gives a .vtp")
      .def("size", [](const contact_state& cs) { return cs.snapshot.size(); }, "Number of sub-contacts")
      .def_property_readonly("reference", [](const contact_state& cs) { return rows_of(cs.snapshot.reference); }, "position (m)")
      .def_property_readonly("displacement", [](const contact_state& cs) { return rows_of(cs.snapshot.displacement); }, "displacement (m)")
      .def_property_readonly("normal", [](const contact_state& cs) { return rows_of(cs.snapshot.normal); }, "unit normal A->B")
      .def_property_readonly("area", [](const contact_state& cs) { return py::array(py::cast(cs.snapshot.area)); }, "area (m^2)")
      .def_property_readonly("tensile_damage", [](const contact_state& cs) { return py::array(py::cast(cs.snapshot.tensile_damage)); }, "0 intact .. 1 broken")
      .def_property_readonly("status", [](const contact_state& cs) { return py::array(py::cast(cs.snapshot.status)); }, "law::contact_status bits")
      .def_property_readonly("block_a", [](const contact_state& cs) { return py::array(py::cast(cs.block_a)); }, "block A")
      .def_property_readonly("block_b", [](const contact_state& cs) { return py::array(py::cast(cs.block_b)); }, "block B")
      .def("fields", [](const contact_state& cs) {
             std::vector<std::string> names;
             for (const auto& a : cs.snapshot.state) names.push_back(a.name);
             return names;
           }, "The names of the law's state fields, with their units (e.g. sigma_n_Pa)")
      .def("field", [](const contact_state& cs, const std::string& name) {
             const auto* a = cs.snapshot.find(name);
             require(a != nullptr, "contact_state: no field '", name, "'");
             py::array_t<double> out(a->components == 1 ? std::vector<py::ssize_t>{static_cast<py::ssize_t>(cs.snapshot.size())}
                                                       : std::vector<py::ssize_t>{static_cast<py::ssize_t>(cs.snapshot.size()), 3});
             std::copy(a->values.begin(), a->values.end(), out.mutable_data());
             return out;
           }, py::arg("name"), "One state field (n or n x 3), e.g. field('sigma_n_Pa')")
      .def("write", [](const contact_state& cs, const std::string& path) { cs.snapshot.write(path); }, py::arg("path"),
           "Writes the sub-contacts as a VTK .vtp (points with every field)");
  py::class_<out_of_balance>(m, "out_of_balance", "Unbalanced force of the last step (N)")
      .def_readonly("max_force", &out_of_balance::max_force, "largest |f| of a node over its free components (N)")
      .def_readonly("mean_force", &out_of_balance::mean_force, "mean of that magnitude (N)")
      .def_readonly("max_node", &out_of_balance::max_node, "the node of max_force");
  py::class_<integrator::mass_scaling_report>(m, "mass_scaling_report", "What mass scaling did (kg)")
      .def_readonly("added_mass", &integrator::mass_scaling_report::added_mass, "mass added (kg)")
      .def_readonly("original_mass", &integrator::mass_scaling_report::original_mass, "mass before scaling (kg)")
      .def_readonly("scaled_nodes", &integrator::mass_scaling_report::scaled_nodes, "nodes whose mass was raised");
  py::class_<energy_balance>(m, "energy_balance", "Energy terms (J)")
      .def_readonly("boundary_work", &energy_balance::boundary_work, "work of the support reactions (J)")
      .def_readonly("gravity_work", &energy_balance::gravity_work, "work of gravity (J)")
      .def_readonly("kinetic", &energy_balance::kinetic, "kinetic energy (J)")
      .def_readonly("block_elastic", &energy_balance::block_elastic, "elastic energy in the zones (J)")
      .def_readonly("contact_stored", &energy_balance::contact_stored, "elastic energy in the contact springs (J)")
      .def_readonly("contact_dissipated", &energy_balance::contact_dissipated, "dissipated by the contacts (J)")
      .def_readonly("damping_dissipated", &energy_balance::damping_dissipated, "removed by local damping (J)")
      .def("error_rel", &energy_balance::error_rel, "(supplied - accounted) / supplied");

  py::class_<csv_record, std::shared_ptr<csv_record>>(rec, "csv_recorder",
                                                      "recorders::csv_recorder written along run_until (s.csv_recorder)")
      .def("close", &csv_record::close, "Makes the file appear at its path (atomic); a second call does nothing")
      .def("rows", &csv_record::rows, "Rows written, the first included")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](csv_record& r, const py::object& kind, const py::object&, const py::object&) {
        if (kind.is_none())
          r.close();
        else
          r.discard();  // an exception left the block: no file that looks finished
        return false;
      });

  // ---- the solvers compiled once (tessera::instances) ----
  auto inst = m.def_submodule("instances", "The solvers compiled once (tessera::instances)");
  bind_solver<instances::rigid_dry_damped_solver>(
      inst, "rigid_dry_damped_solver",
      "Rigid blocks on detected dry joints, central differences with local damping: "
      "solver<blocks::rigid, contact::detected_contacts<law::dry_joint_law>> (quasi-static settling)");
  bind_solver<instances::rigid_dry_solver>(
      inst, "rigid_dry_solver",
      "The same undamped (integrator::no_damping): dynamics whose energy the run must keep");
  bind_solver<instances::prism_solver>(
      inst, "prism_solver",
      "The README's prism: deformable linear-elastic tetrahedral blocks on the tessellation's bonded faces with "
      "the study's law (law.study_tie_law), central differences with local damping");

  m.attr("__version__") = TESSERA_VERSION_STRING;
  m.def(
      "_tension_reference",
      [](int threads) {
        std::vector<std::vector<double>> curve;
        {
          py::gil_scoped_release released;
          curve = python_reference::tension_curve(threads);
        }
        return curve;
      },
      py::arg("threads") = 1, "examples/python/direct_tension.py's run in C++: its curve's columns (for the tests)");
  m.def("_arch_reference", &arch_reference, "The README's arch run in C++ (for the tests)");
}
