#pragma once
// bind_solver<S>: the binding of one solver type of tessera::instances, shared by the translation
// units that bind solvers (tessera_module.cpp: the rigid ones and the prism; bind_solvers.cpp:
// the tie with bars and the deformable blocks on detected contacts; bind_twins.cpp: rigid blocks
// on bonded joints, the undamped prism and tie), so each unit instantiates
// only its own solvers and compiles in less memory. What a solver type has decides what it gets:
// deformable blocks the applied forces and zone stresses, bars (reinforcement enabled) their
// nodes, supports and read-only NumPy views of the element and bond states.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tessera/io/checkpoint.hpp>
#include <tessera/io/vtk.hpp>
#include <tessera/solver.hpp>

#include "bind_bars.hpp"      // bind_bars<S>: bar nodes, supports and state views
#include "conditions.hpp"     // any_quantity, any_condition, csv_record
#include "contact_state.hpp"  // contact_state, take_contact_state

#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <tuple>
#include <vector>

namespace tessera::python {

namespace py = pybind11;

/// A (blocks, 3) NumPy array whose row b is row(b), a vec3 (a copy: block quantities are computed).
template <class S, class Row>
py::array_t<double> per_block_rows(const S& s, Row&& row) {
  const index_t n = s.block_count();
  py::array_t<double> out({static_cast<py::ssize_t>(n), py::ssize_t{3}});
  auto o = out.template mutable_unchecked<2>();
  for (index_t b = 0; b < n; ++b) {
    const vec3 v = row(b);
    for (py::ssize_t c = 0; c < 3; ++c) o(b, c) = v[c];
  }
  return out;
}

// ---- NumPy views ---------------------------------------------------------------------------------

/// A writable NumPy view (n x 3, no copy) of a column-major soa3 owned by `owner`.
inline py::array writable_view_of(soa3& a, py::handle owner) {
  const auto n = static_cast<py::ssize_t>(a.rows());
  const auto item = static_cast<py::ssize_t>(sizeof(real));
  return py::array(py::dtype::of<real>(), {n, py::ssize_t{3}}, {item, n * item}, a.data(), owner);
}
/// A read-only NumPy array (zones x 6) that owns the zone stresses `m` (moved, not copied).
inline py::array owning_rows(zone_stress_matrix m) {
  auto* held = new zone_stress_matrix(std::move(m));
  const py::capsule owner(held, [](void* p) { delete static_cast<zone_stress_matrix*>(p); });
  const auto item = static_cast<py::ssize_t>(sizeof(real));
  py::array v(py::dtype::of<real>(), {static_cast<py::ssize_t>(held->rows()), py::ssize_t{6}},
              {item, static_cast<py::ssize_t>(held->rows()) * item}, held->data(), owner);
  py::detail::array_proxy(v.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return v;
}

// ---- one solver type -----------------------------------------------------------------------------

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
      .def("block_rotation", &S::block_rotation, py::arg("b"),
           "Rotation of block b since the reference as a rotation vector (rad; axis times angle in [0, pi]; "
           "deformable: the polar factor of its deformation gradient now)")
      .def(
          "block_displacements",
          [](const S& s) { return per_block_rows(s, [&](index_t b) { return s.block_displacement(b); }); },
          "Every block's displacement (m): a new (blocks, 3) NumPy array")
      .def(
          "block_rotations",
          [](const S& s) { return per_block_rows(s, [&](index_t b) { return s.block_rotation(b); }); },
          "Every block's rotation vector (rad): a new (blocks, 3) NumPy array")
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
  if constexpr (S::reinforcement_type::enabled) bind_bars<S>(cls);
}

}  // namespace tessera::python
