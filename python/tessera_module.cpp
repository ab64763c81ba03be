// The compiled part of the Python module `tessera` (python/tessera/__init__.py re-exports it;
// docs/python.md): the solvers tessera::instances compiles once, named as in C++, with the
// quantities and stop conditions run_until takes (conditions.hpp: the C++ classes behind a
// variant, so a run driven from Python takes the same steps and gives the same bits as the C++
// program that spells the condition out). The scene's parts are bound in bind_scene.cpp, files and
// calibration in bind_extras.cpp, one solver type in bind_solver.hpp; the rigid solvers and the
// prism are bound here, the tie with bars and the deformable blocks on detected contacts in
// bind_solvers.cpp, the rigid blocks on bonded joints and the undamped prism and tie in
// bind_twins.cpp. State crosses as read-only NumPy views of the solver's arrays
// (valid until the next step). tessera's exceptions arrive as tessera.Error (and its subclasses)
// with the C++ message.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tessera/blocks.hpp>
#include <tessera/contact.hpp>
#include <tessera/geometry.hpp>
#include <tessera/instances/prism.hpp>  // the solvers compiled once (linked: tessera::instances)
#include <tessera/instances/rigid.hpp>
#include <tessera/law.hpp>
#include <tessera/presets/pulatsu2020.hpp>  // the study's presets (study_prism_params, ...)
#include <tessera/solver.hpp>

#include "bind_beam.hpp"          // the study's RC beam, its law and the rigid plates (bind_beam.cpp)
#include "bind_extras.hpp"        // calibration files, Neper import, contact_status (bind_extras.cpp)
#include "bind_scene.hpp"         // geometry, laws, options, state classes (bind_scene.cpp)
#include "bind_solver.hpp"        // bind_solver<S>
#include "bind_solvers.hpp"       // the tie and the deformable blocks on detected contacts (bind_solvers.cpp)
#include "bind_twins.hpp"         // rigid blocks on bonded joints, the undamped prism and tie (bind_twins.cpp)
#include "conditions.hpp"         // any_quantity, any_condition, csv_record
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
  python::bind_solvers(m, inst, iom);
  python::bind_twins(inst, iom);
  python::bind_beam(m, inst, iom);

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
