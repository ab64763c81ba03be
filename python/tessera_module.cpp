// The compiled part of the Python module `tessera` (python/tessera/__init__.py re-exports it;
// docs/python.md): the solvers tessera::instances compiles once, named as in C++, with the
// quantities and stop conditions run_until takes (conditions.hpp: the C++ classes behind a
// variant, so a run driven from Python takes the same steps and gives the same bits as the C++
// program that spells the condition out). The scene's parts are bound in bind_scene.cpp, files and
// calibration in bind_extras.cpp. State crosses as read-only NumPy views of the solver's arrays
// (valid until the next step). tessera's exceptions arrive as tessera.Error (and its subclasses)
// with the C++ message.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tessera/blocks.hpp>
#include <tessera/contact.hpp>
#include <tessera/geometry.hpp>
#include <tessera/instances.hpp>  // the solvers compiled once (linked: tessera::instances)
#include <tessera/io/checkpoint.hpp>
#include <tessera/io/vtk.hpp>
#include <tessera/io/vtk_contacts.hpp>
#include <tessera/law.hpp>
#include <tessera/presets/pulatsu2020.hpp>  // the study's presets (study_prism_params, ...)
#include <tessera/solver.hpp>

#include "bind_extras.hpp"        // calibration files, Neper import, contact_status (bind_extras.cpp)
#include "bind_scene.hpp"         // geometry, laws, options, state classes (bind_scene.cpp)
#include "conditions.hpp"         // any_quantity, any_condition, csv_record
#include "contact_state.hpp"      // contact_state, take_contact_state
#include "tension_reference.hpp"  // the prism script in C++ (tessera._tension_reference)

#include <cmath>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

namespace py = pybind11;
using namespace tessera;
using namespace tessera::python;

namespace {

// ---- NumPy views ---------------------------------------------------------------------------------

/// A writable NumPy view (n x 3, no copy) of a column-major soa3 owned by `owner`.
py::array writable_view_of(soa3& a, py::handle owner) {
  const auto n = static_cast<py::ssize_t>(a.rows());
  const auto item = static_cast<py::ssize_t>(sizeof(real));
  return py::array(py::dtype::of<real>(), {n, py::ssize_t{3}}, {item, n * item}, a.data(), owner);
}
/// A read-only NumPy array (zones x 6) that owns the zone stresses `m` (moved, not copied).
py::array owning_rows(zone_stress_matrix m) {
  auto* held = new zone_stress_matrix(std::move(m));
  const py::capsule owner(held, [](void* p) { delete static_cast<zone_stress_matrix*>(p); });
  const auto item = static_cast<py::ssize_t>(sizeof(real));
  py::array v(py::dtype::of<real>(), {static_cast<py::ssize_t>(held->rows()), py::ssize_t{6}},
              {item, static_cast<py::ssize_t>(held->rows()) * item}, held->data(), owner);
  py::detail::array_proxy(v.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return v;
}

// ---- one solver type -----------------------------------------------------------------------------

/// The components argument of the supports: a bc.components value; refuses one outside xyz.
bc::components checked_components(bc::components c, const char* what) {
  const auto bits = static_cast<unsigned>(c);
  require(bits <= 7u, what, ": components = ", bits, " is not a combination of x, y and z");
  return c;
}

/// Binds solver type S (one of tessera::instances') as `name` in module m.
template <class S>
void bind_solver(py::module_& m, py::module_& io, const char* name, const char* doc) {
  py::class_<S> cls(m, name, doc);
  io.def(
      "save_checkpoint",
      [](const S& s, const std::string& path, const std::string& description) {
        io::save_checkpoint(s, path, description);
      },
      py::arg("solver"), py::arg("path"), py::arg("description") = std::string{},
      "Writes the solver's state (step, time, energies, gridpoints, blocks, contacts) to path, atomically");
  io.def(
      "load_checkpoint", [](S& s, const std::string& path) { return io::load_checkpoint(s, path); },
      py::arg("solver"), py::arg("path"),
      "Fills the solver, built as the one that wrote path was, with the file's state; refuses (naming the first "
      "record that differs) before changing anything when it does not fit. Returns the file's checkpoint_info");
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
    cls.def("contact_state", &python::take_contact_state<S>,
            "Per-sub-contact state now (a copy): stresses, openings, damage, status, blocks (NumPy arrays)");
  if constexpr (!S::blocks_type::is_rigid) {
    cls.def(
        "register_applied_forces",
        [](S& s, const bc::node_group& g, real k) {
          const std::vector<real> each(g.nodes.size(), k);
          s.register_applied_forces(std::span<const index_t>(g.nodes), std::span<const real>(each));
        },
        py::arg("group"), py::arg("k") = 0.0,
        "Registers the group's gridpoints to take forces from outside the model (s.applied_forces()), each with the "
        "stiffness k (N/m, >= 0; 0 for a plain load) of what applies them (it joins the time step's bound)");
    cls.def(
        "register_applied_forces",
        [](S& s, const bc::node_group& g, const std::vector<real>& k) {
          s.register_applied_forces(std::span<const index_t>(g.nodes), std::span<const real>(k));
        },
        py::arg("group"), py::arg("k"), "The same with one stiffness per gridpoint of the group (N/m, >= 0)");
    cls.def(
        "applied_forces", [](py::object self) { return writable_view_of(self.cast<S&>().applied_forces(), self); },
        "The forces from outside the model (N), a writable NumPy view (gridpoints x 3) of the solver's array: the "
        "rows of registered gridpoints are applied by every step until changed");
    cls.def(
        "applied_nodes", [](const S& s) { return s.applied_nodes(); }, "The registered gridpoints, increasing");
    cls.def(
        "zone_stress", [](const S& s) { return owning_rows(s.blocks().zone_stress()); },
        "Cauchy stress of every zone at the last step (Pa; zones x 6, Voigt xx yy zz yz xz xy, tension +): a "
        "read-only NumPy array the call assembles");
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
  }
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

  python::bind_scene(m);

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


  auto rec = m.attr("recorders").cast<py::module_>();
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
  auto iom = m.def_submodule("io", "Checkpoints, Neper tessellations, CSV files (tessera::io)");
  python::bind_extras(m);
  bind_solver<instances::rigid_dry_damped_solver>(
      inst, iom, "rigid_dry_damped_solver",
      "Rigid blocks on detected dry joints, central differences with local damping: "
      "solver<blocks::rigid, contact::detected_contacts<law::dry_joint_law>> (quasi-static settling)");
  bind_solver<instances::rigid_dry_solver>(
      inst, iom, "rigid_dry_solver",
      "The same undamped (integrator::no_damping): dynamics whose energy the run must keep");
  bind_solver<instances::prism_solver>(
      inst, iom, "prism_solver",
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
