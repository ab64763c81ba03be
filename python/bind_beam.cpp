// The module's fourth unit of solvers (bind_beam.hpp): the study's RC beam with bars
// (instances::beam_solver and its undamped twin, through bind_solver<S>), its law and presets,
// and the rigid steel plates of a bending test (contact::rigid_platen<study_beam_law>), named as
// in C++.
#include "bind_beam.hpp"

#include <tessera/contact/platen.hpp>
#include <tessera/instances/beam.hpp>  // compiled once (linked: tessera::instances)
#include <tessera/presets/pulatsu2020.hpp>  // study_beam_law, study_beam_params

#include "bind_solver.hpp"
#include "bind_table.hpp"  // bind_material_table

#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace py = pybind11;

namespace tessera::python {

namespace {

using beam = instances::beam_law;
static_assert(std::is_same_v<beam, presets::study_beam_law>, "instances::beam_law is the study's beam law");
using platen = contact::rigid_platen<beam>;

/// law.study_beam_law, its params and parts, law.study_beam_params; contact.study_beam_table.
void bind_beam_law(py::module_& l, py::module_& c) {
  py::class_<beam> beam_law(l, "study_beam_law",
                            "The study's beam joint (Sec. 4): linear softening in tension, a plastic compressive cap, "
                            "Coulomb friction with residual values (law::cohesive_frictional; instances::beam_law)");
  py::class_<law::linear_softening::params>(l, "linear_softening_params", "Tension: linear softening (Pa, J/m^2)")
      .def(py::init<>())
      .def_readwrite("f_T", &law::linear_softening::params::f_T, "tensile strength (Pa)")
      .def_readwrite("G_f", &law::linear_softening::params::G_f, "mode-I fracture energy (J/m^2)");
  py::class_<law::plastic_cap::params>(l, "plastic_cap_params", "Compression: perfectly plastic cap (Pa)")
      .def(py::init<>())
      .def_readwrite("f_c", &law::plastic_cap::params::f_c, "compressive strength (Pa, a magnitude)");
  py::class_<beam::params>(beam_law, "params", "The params of the study's beam joint (Pa/m, Pa, J/m^2)")
      .def(py::init<>())
      .def_readwrite("k_n", &beam::params::k_n, "normal stiffness (Pa/m)")
      .def_readwrite("k_s", &beam::params::k_s, "shear stiffness (Pa/m)")
      .def_readwrite("tension", &beam::params::tension, "linear softening: f_T (Pa), G_f (J/m^2)")
      .def_readwrite("compression", &beam::params::compression, "plastic cap: f_c (Pa)")
      .def_readwrite("shear", &beam::params::shear, "Coulomb: c_0, phi_0, c_res, phi_res")
      .def("validate", [](const beam::params& p) { beam::validate(p); }, "Refuses bad values (tessera.Error naming one)")
      .def("__copy__", [](const beam::params& p) { return p; }, "A copy (copy.copy)");
  l.def("study_beam_params", &presets::study_beam_params, py::arg("blocks"),
        "The study's beam contacts (Sec. 4, Table 3) for 250 or 500 blocks: k_n 500 / 625 GPa/m, k_s = k_n / 2.4, "
        "f_T 2.5 MPa, G_f 60 J/m^2, f_c 35 MPa, c_0 = 2 f_T, c_res = 0.01 c_0, phi_0 35 deg, phi_res 30 deg "
        "(law::study_beam_params)");
  bind_material_table<beam::params>(
      c, "study_beam_table", "contact::material_table of the study's beam joint: params per pair of block materials");
}

/// platen.attach(s) and platen.update(s) for solver type S.
template <class S>
void bind_platen_solver(py::class_<platen>& cls) {
  cls.def(
         "attach", [](platen& p, S& s) { p.attach(s); }, py::arg("solver"),
         "Registers the plate's gridpoints with the solver (register_applied_forces, each with its sub-contact's "
         "stiffness max(k_n, k_s) x area, N/m; the step is recomputed) and raises the plate's mass and inertia to keep "
         "that step stable")
      .def(
          "update", [](platen& p, S& s) { p.update(s); }, py::arg("solver"),
          "The contact forces of the solver's current state on the plate's gridpoints (into s.applied_forces(), N), "
          "then the plate advanced by one step s.dt(): call before every step");
}

/// contact.platen_geometry, contact.platen_motion, contact.rigid_platen (the beam law's).
void bind_platen(py::module_& c) {
  using geo = contact::platen_geometry;
  py::class_<geo>(c, "platen_geometry", "Where a rigid_platen touches the body (m)")
      .def(py::init([](const vec3& point, const vec3& normal, const vec3& axis_u, real half_u, real half_w,
                       real tolerance) { return geo{point, normal, axis_u, half_u, half_w, tolerance}; }),
           py::arg("point"), py::arg("normal"), py::arg("axis_u"), py::arg("half_u"), py::arg("half_w"),
           py::arg("tolerance") = 1e-9,
           "The contact plane through point (m, the footprint's centre and the hinge) with unit normal from the plate "
           "into the body; the footprint |(x - point) . axis_u| <= half_u, |(x - point) . (normal x axis_u)| <= "
           "half_w (m); tolerance: distance from the plane of a surface triangle on it (m)")
      .def_readwrite("point", &geo::point, "footprint centre and hinge (m)")
      .def_readwrite("normal", &geo::normal, "unit normal from the plate into the body")
      .def_readwrite("axis_u", &geo::axis_u, "unit, in the plane: the footprint's first side")
      .def_readwrite("half_u", &geo::half_u, "footprint half-length along axis_u (m)")
      .def_readwrite("half_w", &geo::half_w, "footprint half-length along normal x axis_u (m)")
      .def_readwrite("tolerance", &geo::tolerance, "distance from the plane of a triangle on it (m)");
  using motion = contact::platen_motion;
  // hinge_axis as a plain array: an Eigen default value would import NumPy when the module loads
  py::class_<motion>(c, "platen_motion", "How a rigid_platen moves (kg, kg m^2)")
      .def(py::init([](real mass, real inertia, const std::array<bool, 3>& free_translation,
                       const std::array<real, 3>& hinge_axis, real damping_gamma, bool quasi_static) {
             motion m;
             m.mass = mass, m.inertia = inertia, m.free_translation = free_translation;
             m.hinge_axis = vec3(hinge_axis[0], hinge_axis[1], hinge_axis[2]);
             m.damping_gamma = damping_gamma, m.quasi_static = quasi_static;
             return m;
           }),
           py::arg("mass") = 1.0, py::arg("inertia") = 1.0, py::arg("free_translation") = std::array<bool, 3>{},
           py::arg("hinge_axis") = std::array<real, 3>{}, py::arg("damping_gamma") = 0.8, py::arg("quasi_static") = false,
           "mass (kg, free translations), inertia (kg m^2 about the hinge), free_translation: the world components "
           "integrated from the contact force (the others prescribed: set_velocity), hinge_axis (unit; zero: no "
           "turn), local damping gamma in [0, 1), quasi_static: no inertia (a dynamic relaxation's plates)")
      .def_readwrite("mass", &motion::mass, "kg")
      .def_readwrite("inertia", &motion::inertia, "kg m^2 about the hinge axis")
      .def_readwrite("free_translation", &motion::free_translation, "world components integrated from the force")
      .def_readwrite("hinge_axis", &motion::hinge_axis, "unit axis it turns about freely; zero: it does not turn")
      .def_readwrite("damping_gamma", &motion::damping_gamma, "local damping of the free components")
      .def_readwrite("quasi_static", &motion::quasi_static, "no inertia: each update to the force's equilibrium");
  py::class_<platen> cls(c, "rigid_platen",
                         "contact::rigid_platen<study_beam_law>: a rigid steel plate pressed on a flat face of "
                         "deformable blocks through the beam law's never-bonded contact springs (the plate-concrete "
                         "pair: friction only, lifts off freely); the loading and support plates of a bending test");
  cls.def(py::init<const geometry::block_mesh&, const contact::platen_geometry&, const contact::platen_motion&,
                   const beam::params&>(),
          py::arg("mesh"), py::arg("geometry"), py::arg("motion"), py::arg("params"),
          "Places the plate's sub-contacts on the mesh's gridpoints under it; refuses bad geometry, motion or params "
          "(tessera.Error naming the value)")
      .def("set_velocity", &platen::set_velocity, py::arg("v"),
           "Velocity (m/s) of the prescribed translation components after the next update")
      .def("force", &platen::force, "Force on the plate from the body at the last update (N): the load cell")
      .def("moment", &platen::moment, "Moment on the plate about its hinge axis at the last update (N m)")
      .def("displacement", &platen::displacement, "Displacement of the reference point (m)")
      .def("rotation", &platen::rotation, "Rotation about the hinge axis (rad)")
      .def("velocity", &platen::velocity, "Velocity of the reference point (m/s, half step)")
      .def("rotation_rate", &platen::rotation_rate, "Rotation rate (rad/s, half step)")
      .def("current_normal", &platen::current_normal, "The current unit normal, from the plate into the body")
      .def("size", &platen::size, "Number of sub-contacts (gridpoints under the plate)")
      .def(
          "nodes",
          [](const platen& p) {
            std::vector<index_t> n(p.size());
            for (std::size_t j = 0; j < p.size(); ++j) n[j] = p.node(j);
            return n;
          },
          "The gridpoints of the sub-contacts, increasing")
      .def(
          "areas",
          [](const platen& p) {
            std::vector<real> a(p.size());
            for (std::size_t j = 0; j < p.size(); ++j) a[j] = p.area(j);
            return a;
          },
          "Tributary area of each sub-contact (m^2)")
      .def("total_area", &platen::total_area, "Contact area (m^2)")
      .def("in_contact", &platen::in_contact, "Sub-contacts in compression (sigma_n < 0) at the last update")
      .def("stored_energy", &platen::stored_energy, "Energy stored in the plate's contact springs (J)")
      .def("dissipated_energy", &platen::dissipated_energy, "Energy the plate's contact springs dissipated (J)")
      .def("mass", &platen::mass, "Mass (kg), after attach's scaling")
      .def("inertia", &platen::inertia, "Rotary inertia about the hinge (kg m^2), after attach's scaling")
      .def("added_mass", &platen::added_mass, "Mass attach added for the step (kg)")
      .def("added_inertia", &platen::added_inertia, "Inertia attach added for the step (kg m^2)");
  bind_platen_solver<instances::beam_solver>(cls);
  bind_platen_solver<instances::beam_undamped_solver>(cls);
}

}  // namespace

void bind_beam(py::module_& m, py::module_& inst, py::module_& io) {
  auto l = m.attr("law").cast<py::module_>();
  auto c = m.attr("contact").cast<py::module_>();
  bind_beam_law(l, c);
  bind_platen(c);
  bind_solver<instances::beam_solver>(
      inst, io, "beam_solver",
      "The study's RC beam: deformable linear-elastic tetrahedral blocks on the tessellation's bonded faces with the "
      "beam's law (law.study_beam_law, law.study_beam_params), steel bars embedded in the zones "
      "(reinforcement.embedded_truss_params), central differences with local damping: examples/rc_beam's solver");
  bind_solver<instances::beam_undamped_solver>(
      inst, io, "beam_undamped_solver",
      "The beam undamped (integrator::no_damping): the reinforced beam's dynamics with the energy kept");
}

}  // namespace tessera::python
