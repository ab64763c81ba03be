#pragma once
// bind_material_table<Params>: the binding of a contact::material_table of one law's params (the
// study's tie joint in bind_scene.cpp, its beam joint in bind_beam.cpp), which a plain params
// converts to, so a solver's contact_params takes either.
#include <pybind11/pybind11.h>

#include <tessera/contact/material_table.hpp>

namespace tessera::python {

/// Binds contact::material_table<Params> as `name` in module c (a params converts to it).
template <class Params>
void bind_material_table(pybind11::module_& c, const char* name, const char* doc) {
  namespace py = pybind11;
  using table = contact::material_table<Params>;
  py::class_<table>(c, name, doc)
      .def(py::init<const Params&>(), py::arg("all"), "One law for every pair")
      .def("set", &table::set, py::arg("a"), py::arg("b"), py::arg("params"), py::return_value_policy::reference_internal,
           "Bonded params for the pair {a, b} of material ids")
      .def("never_bonded", &table::never_bonded, py::arg("a"), py::arg("b"), py::arg("params"),
           py::return_value_policy::reference_internal, "The pair {a, b} starts unbonded");
  py::implicitly_convertible<Params, table>();
}

}  // namespace tessera::python
