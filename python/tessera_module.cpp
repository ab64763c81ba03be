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
#include <tessera/law.hpp>
#include <tessera/solver.hpp>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <variant>
#include <vector>

namespace py = pybind11;
using namespace tessera;

namespace {

// ---- quantities and stop conditions: the C++ classes behind a variant ---------------------------

/// One of tessera::quantity's quantities, chosen at run time; evaluated as the quantity itself.
struct any_quantity {
  std::variant<quantity::time, quantity::block_displacement, quantity::block_displacement_magnitude,
               quantity::block_velocity, quantity::block_speed, quantity::max_block_speed, quantity::kinetic_energy,
               quantity::reaction_sum, quantity::mean_displacement>
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
    return (*fn)(py::cast(&s, py::return_value_policy::reference)).template cast<bool>();
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

struct any_condition;
using any_of_node = stop::any_of<any_condition, any_condition>;
using all_of_node = stop::all_of<any_condition, any_condition>;

/// One of tessera::stop's conditions, or `a | b`, `a & b` of two; evaluated as the condition.
struct any_condition : stop::condition_tag {
  std::variant<stop::after_steps, stop::after_time, stop::when_settled<any_quantity>, stop::when_beyond<any_quantity>,
               stop::kinetic_energy_below, python_predicate, std::shared_ptr<any_of_node>, std::shared_ptr<all_of_node>>
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

// ---- one solver type -----------------------------------------------------------------------------

/// Binds solver type S (one of tessera::instances') as `name` in module m.
template <class S>
void bind_solver(py::module_& m, const char* name, const char* doc) {
  py::class_<S>(m, name, doc)
      .def(py::init<const geometry::tessellation&, const geometry::block_mesh&, const typename S::blocks_type::params&,
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
      .def("set_gravity", &S::set_gravity, py::arg("g"), "Acceleration of gravity (m/s^2, a 3-vector)")
      .def("step", &S::step, "One step of dt", py::call_guard<py::gil_scoped_release>())
      .def(
          "run_until",
          [](S& s, any_condition condition, std::int64_t max_steps) {
            return s.run_until(stop::any_of<any_condition, interrupt_check>(std::move(condition), interrupt_check{}), max_steps);
          },
          py::arg("stop"), py::arg("max_steps") = std::int64_t{100'000'000}, py::call_guard<py::gil_scoped_release>(),
          "Steps until stop holds (evaluated before every step) or max_steps were taken; a run_result. "
          "Ctrl-C stops it within 1000 steps (KeyboardInterrupt)")
      .def("dt", &S::dt, "The step the next step() takes (s)")
      .def("time", &S::time, "Simulated time since the solver was built (s)")
      .def("step_count", &S::step_count, "Steps taken since the solver was built")
      .def("block_count", &S::block_count, "Number of blocks")
      .def("block_displacement", &S::block_displacement, py::arg("b"), "Displacement of block b (m, NumPy 3-vector)")
      .def("block_velocity", &S::block_velocity, py::arg("b"), "Velocity of block b (m/s, half step)")
      .def("kinetic_energy", &S::kinetic_energy, "Kinetic energy of the model (J)")
      .def(
          "blocks", [](const S& s) -> const typename S::blocks_type& { return s.blocks(); },
          py::return_value_policy::reference_internal, "The block model")
      .def(
          "gridpoints", [](const S& s) -> const node_set& { return s.gridpoints(); },
          py::return_value_policy::reference_internal, "The gridpoints (read-only NumPy views of their arrays)");
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
        p.fn = std::shared_ptr<py::object>(new py::object(std::move(fn)), [](py::object* o) {
          py::gil_scoped_acquire gil;
          delete o;
        });
        p.every = every;
        p.description = std::move(description);
        return any_condition{{}, std::move(p)};
      },
      py::arg("fn"), py::arg("description"), py::arg("every") = std::int64_t{100},
      "When fn(solver) returns True, fn called every `every` steps (the first before any step)");
  st.def("kinetic_energy_below", [](real r) { return any_condition{{}, stop::kinetic_energy_below(r)}; },
         py::arg("ratio"), "When the kinetic energy fell to ratio (in (0, 1)) of its peak");

  // ---- the solvers compiled once (tessera::instances) ----
  auto inst = m.def_submodule("instances", "The solvers compiled once (tessera::instances)");
  bind_solver<instances::rigid_dry_damped_solver>(
      inst, "rigid_dry_damped_solver",
      "Rigid blocks on detected dry joints, central differences with local damping: "
      "solver<blocks::rigid, contact::detected_contacts<law::dry_joint_law>> (quasi-static settling)");
  bind_solver<instances::rigid_dry_solver>(
      inst, "rigid_dry_solver",
      "The same undamped (integrator::no_damping): dynamics whose energy the run must keep");

  m.def("_arch_reference", &arch_reference, "The README's arch run in C++ (for the tests)");
}
