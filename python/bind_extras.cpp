// The module's bindings outside the solvers (bind_extras.hpp): calibrated parameter files read by
// the drivers' own reader (examples/common/calibration.hpp, so a file a driver refuses is refused
// here with the same message), Neper .tess tessellations, and the contact status bits.
#include "bind_extras.hpp"

#include <pybind11/stl.h>

#include <tessera/io/checkpoint.hpp>
#include <tessera/io/csv.hpp>
#include <tessera/io/neper.hpp>
#include <tessera/law/concepts.hpp>

#include "common/calibration.hpp"  // examples/common: read_calibration, load_calibration

#include <string>
#include <vector>

namespace py = pybind11;

namespace tessera::python {

void bind_extras(py::module_& m) {
  // ---- checkpoint headers, Neper, CSV ----
  auto iom = m.attr("io").cast<py::module_>();
  py::class_<io::checkpoint_info>(iom, "checkpoint_info", "What a checkpoint file says about itself")
      .def_readonly("format", &io::checkpoint_info::format, "file format version")
      .def_readonly("version", &io::checkpoint_info::version, "tessera version that wrote it")
      .def_readonly("commit", &io::checkpoint_info::commit, "git commit of the build that wrote it")
      .def_readonly("description", &io::checkpoint_info::description, "the text given to save_checkpoint")
      .def_readonly("records", &io::checkpoint_info::records, "number of records")
      .def_readonly("bytes", &io::checkpoint_info::bytes, "size of the file (bytes)");
  iom.def(
      "read_checkpoint_info", [](const std::string& path) { return io::read_checkpoint_info(path); }, py::arg("path"),
      "The header of a checkpoint file, its structure and hash checked");
  iom.def(
      "write_csv",
      [](const std::string& path, const std::vector<std::string>& names, const std::vector<std::vector<double>>& columns) {
        io::write_csv(path, names, columns);
      },
      py::arg("path"), py::arg("names"), py::arg("columns"),
      "Columns of equal length as one CSV file, a header of names then 17 significant digits (the drivers' "
      "curve.csv), written atomically");
  iom.def(
      "read_neper_tess", [](const std::string& path) { return io::read_neper_tess(path); }, py::arg("path"),
      "A Neper .tess (format 3.x) tessellation (m): its cells as blocks (tessera.IoError naming the line on a bad file)");

  // ---- contact status bits ----
  auto l = m.attr("law").cast<py::module_>();
  py::enum_<law::contact_status>(l, "contact_status", py::arithmetic(),
                                 "law::contact_status bits of contact_state.status (combine with |, test with &)")
      .value("intact", law::contact_status::intact)
      .value("softening", law::contact_status::softening, "past the tensile strength, on the softening branch")
      .value("broken_tension", law::contact_status::broken_tension, "tensile strength exhausted for good")
      .value("slipped", law::contact_status::slipped, "failed in shear, on the residual Coulomb limit")
      .value("crushed", law::contact_status::crushed, "past the compressive cap of a softening_cap (law::crushing_beam_law)")
      .def("__or__", [](law::contact_status a, law::contact_status b) { return a | b; });

  // ---- calibrated parameter files (examples/calibrate's calibrated.json) ----
  auto c = m.def_submodule("calibration", "calibrated.json of examples/calibrate (examples/common/calibration.hpp)");
  using scenes::calibration_entry, scenes::calibration_recipe;
  py::class_<calibration_recipe>(c, "calibration_recipe", "The recipe a calibration was fitted with (SI)")
      .def(py::init<>())
      .def_readwrite("material", &calibration_recipe::material, "'prism' or 'beam'")
      .def_readwrite("softening", &calibration_recipe::softening, "'power' or 'linear'")
      .def_readwrite("cohesion_ratio", &calibration_recipe::cohesion_ratio, "c_0 / f_T")
      .def_readwrite("step_displacement", &calibration_recipe::step_displacement, "pull per step (m)")
      .def_readwrite("rate", &calibration_recipe::rate, "pull rate (m/s)")
      .def_readwrite("rigid", &calibration_recipe::rigid, "rigid blocks")
      .def_readwrite("zone_edge", &calibration_recipe::zone_edge, "face zoning edge (m; 0 = one zone per face triangle)")
      .def_readwrite("beam_volume", &calibration_recipe::beam_volume, "the beam recipe's half-beam volume (m^3; 0 = none)");
  py::class_<calibration_entry>(c, "calibration_entry", "The concrete fitted for one block count: its scales and, from calibrate --targets, the whole set")
      .def_readonly("blocks", &calibration_entry::blocks, "block count of the fitted prism")
      .def_readonly("strength_scale", &calibration_entry::strength_scale, "x Table 1's f_T (and the cohesion)")
      .def_readonly("fracture_energy_scale", &calibration_entry::fracture_energy_scale, "x Table 1's G_f")
      .def_readonly("initial_modulus", &calibration_entry::initial_modulus, "mean initial modulus (Pa; 0 = not recorded)")
      .def_readonly("law", &calibration_entry::law, "'study', 'slip_softening', 'crushing' or 'mixed_mode' (examples/common/concrete_laws.hpp)")
      .def_readonly("cohesion_ratio", &calibration_entry::cohesion_ratio, "c_0 / f_T (0 = the recipe's)")
      .def_readonly("phi_0_deg", &calibration_entry::phi_0_deg, "peak friction angle (deg)")
      .def_readonly("phi_res_deg", &calibration_entry::phi_res_deg, "residual friction angle (deg)")
      .def_readonly("g_ii", &calibration_entry::g_ii, "mode-II fracture energy (J/m^2; slip_softening, crushing, mixed_mode; 0 = none)")
      .def_readonly("cap", &calibration_entry::cap, "compressive cap f_c (Pa; the beam's concrete)");
  py::class_<scenes::calibration>(c, "calibration", "A calibrated.json: its recipe and one entry per block count")
      .def_readonly("recipe", &scenes::calibration::recipe, "the recipe it was fitted with")
      .def_readonly("entries", &scenes::calibration::entries, "one per block count")
      .def("entry_for", &scenes::calibration::entry_for, py::arg("blocks"), py::arg("file") = std::string("calibrated.json"),
           "The entry for `blocks`; tessera.InvalidInput listing the block counts the file has");
  c.def(
      "read_calibration", [](const std::string& path) { return scenes::read_calibration(path); }, py::arg("path"),
      "Reads and checks a calibrated.json (tessera.IoError naming the file and the field)");
  c.def(
      "load_calibration",
      [](const std::string& path, int blocks, const calibration_recipe& run, const std::string& program) {
        return scenes::load_calibration(path, blocks, run, program.c_str());
      },
      py::arg("path"), py::arg("blocks"), py::arg("recipe"), py::arg("program") = std::string("python"),
      "A driver's --params FILE: the entry for `blocks` after checking the file was fitted with the run's recipe "
      "(tessera.InvalidInput naming the mismatch)");
  c.def("scale_prism_contacts", &scenes::scale_prism_contacts, py::arg("params"), py::arg("strength_scale"),
        py::arg("fracture_energy_scale"), py::arg("cohesion_ratio"),
        "In place: f_T x strength_scale, G_f x fracture_energy_scale, c_0 = cohesion_ratio x the scaled f_T, "
        "c_res = 0.01 c_0 (scenes::scale_prism_contacts)");
}

}  // namespace tessera::python
