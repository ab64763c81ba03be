// The module's second unit of solvers (bind_solvers.hpp): the reinforcement's parameter classes,
// the tie with bars and the deformable blocks on detected contacts, each through bind_solver<S>
// (bind_solver.hpp), named as in C++ (tessera::instances).
#include "bind_solvers.hpp"

#include <tessera/instances/deformable_detected.hpp>  // compiled once (linked: tessera::instances)
#include <tessera/instances/tie.hpp>
#include <tessera/presets/pulatsu2020.hpp>  // tie_steel, tie_bond, tie_reinforcement

#include "bind_solver.hpp"

#include <vector>

namespace py = pybind11;

namespace tessera::python {

namespace {

/// tessera.reinforcement: the steel, the bars, the Coulomb bond and the study's tie presets.
void bind_reinforcement(py::module_& m) {
  namespace rf = reinforcement;
  auto r = m.def_submodule("reinforcement", "Steel bars embedded in deformable blocks (Pa, m, N/m)");
  py::class_<rf::steel>(r, "steel", "Bar material and diameter (Pa, kg/m^3, m)")
      .def(py::init([](real young_modulus, real yield_stress, real diameter, real density) {
             return rf::steel{young_modulus, yield_stress, density, diameter};
           }),
           py::arg("young_modulus"), py::arg("yield_stress"), py::arg("diameter"), py::arg("density") = 7850.0,
           "E_s (Pa), f_y (Pa), d (m), rho_s (kg/m^3); checked when a solver is built")
      .def_readwrite("young_modulus", &rf::steel::young_modulus, "E_s (Pa)")
      .def_readwrite("yield_stress", &rf::steel::yield_stress, "f_y (Pa), in tension and compression")
      .def_readwrite("density", &rf::steel::density, "rho_s (kg/m^3)")
      .def_readwrite("diameter", &rf::steel::diameter, "d (m)")
      .def("area", &rf::steel::area, "A = pi d^2 / 4 (m^2)")
      .def("yield_force", &rf::steel::yield_force, "f_y A (N)")
      .def("axial_rigidity", &rf::steel::axial_rigidity, "E_s A (N)");
  py::class_<rf::bar>(r, "bar", "One straight bar of equal truss elements (m)")
      .def(py::init([](const vec3& start, const vec3& end, index_t elements, bool bonded) {
             return rf::bar{start, end, elements, bonded};
           }),
           py::arg("start"), py::arg("end"), py::arg("elements"), py::arg("bonded") = true,
           "From start to end (m), `elements` truss elements (>= 1); bonded False: no host, no bond")
      .def_readwrite("start", &rf::bar::start, "first node (m)")
      .def_readwrite("end", &rf::bar::end, "last node (m)")
      .def_readwrite("elements", &rf::bar::elements, "truss elements (the bar has one node more)")
      .def_readwrite("bonded", &rf::bar::bonded, "embedded and bonded to its host zones");
  py::enum_<rf::stiffness_basis>(r, "stiffness_basis", "How xi K_axial becomes a nodal bond spring")
      .value("per_node", rf::stiffness_basis::per_node, "xi K_axial (N/m) at an interior node")
      .value("per_unit_length", rf::stiffness_basis::per_unit_length,
             "xi K_axial is a bond modulus per metre of bar (N/m per m; the study's tie)");
  using bond = rf::coulomb_bond::params;
  py::class_<bond>(r, "coulomb_bond_params", "The Coulomb bond of a bar node (-, N/m, rad)")
      .def(py::init([](real xi, real cohesion, real friction_angle, rf::stiffness_basis basis) {
             return bond{xi, cohesion, friction_angle, basis};
           }),
           py::arg("stiffness_ratio") = 4.0, py::arg("cohesion") = 1e9, py::arg("friction_angle") = 0.0,
           py::arg("basis") = rf::stiffness_basis::per_node,
           "xi = K_bond / K_axial (-), c_bond (N per m of bar), phi_bond (rad), the stiffness basis")
      .def_readwrite("stiffness_ratio", &bond::stiffness_ratio, "xi (-)")
      .def_readwrite("cohesion", &bond::cohesion, "c_bond (N/m of bar)")
      .def_readwrite("friction_angle", &bond::friction_angle, "phi_bond (rad)")
      .def_readwrite("basis", &bond::basis, "stiffness_basis");
  using truss = rf::embedded_truss<rf::coulomb_bond>::params;
  py::class_<truss>(r, "embedded_truss_params",
                    "reinforcement::embedded_truss<coulomb_bond>::params: the steel, the bond and the bars")
      .def(py::init([](const rf::steel& s, const bond& b, const std::vector<rf::bar>& bars) { return truss{s, b, bars, {}}; }),
           py::arg("steel"), py::arg("bond"), py::arg("bars"))
      .def_readwrite("steel", &truss::steel, "the steel (all bars)")
      .def_readwrite("bond", &truss::bond, "the bond law's parameters")
      .def_readwrite("bars", &truss::bars, "the bars (a copy: assign a new list to change them)");
  r.def("tie_steel", &presets::tie_steel, "The study's steel: E_s 192.3 GPa, f_y 400 MPa, 7850 kg/m^3, d 8 mm");
  r.def("tie_bond", &presets::tie_bond, py::arg("basis") = rf::stiffness_basis::per_unit_length,
        "The study's bond: xi 4, c_bond 1e9 N/m (perfect bond), phi_bond 0, per unit length by default");
  r.def("tie_reinforcement", &presets::tie_reinforcement, py::arg("start"), py::arg("end"), py::arg("elements") = 96,
        "The study's tie bar from start to end (m) with `elements` truss elements, tie_steel and tie_bond");
}

}  // namespace

void bind_solvers(py::module_& m, py::module_& inst, py::module_& io) {
  bind_reinforcement(m);
  bind_solver<instances::tie_solver>(
      inst, io, "tie_solver",
      "The study's reinforced tie: the prism (deformable linear-elastic tetrahedral blocks, bonded faces with "
      "law.study_tie_law) with steel bars embedded in its zones (reinforcement.embedded_truss_params, e.g. "
      "reinforcement.tie_reinforcement), central differences with local damping");
  bind_solver<instances::deformable_dry_damped_solver>(
      inst, io, "deformable_dry_damped_solver",
      "Deformable linear-elastic tetrahedral blocks on detected dry joints (contact.detected_dry_joints with "
      "deformable_blocks = True), central differences with local damping (quasi-static settling)");
  bind_solver<instances::deformable_dry_solver>(
      inst, io, "deformable_dry_solver",
      "The same undamped (integrator::no_damping): dynamics of elastic blocks whose energy the run must keep");
}

}  // namespace tessera::python
