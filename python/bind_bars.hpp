#pragma once
// bind_bars<S>: what a solver with bars (reinforcement::embedded_truss, instances::tie_solver)
// adds to its binding (bind_solver.hpp): the bar nodes and their supports, and the elements' and
// bonds' state as read-only NumPy views without copies (strided over the state structs), valid
// until the next step.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tessera/core/errors.hpp>
#include <tessera/solver/boundary.hpp>

#include <cstddef>
#include <utility>
#include <vector>

namespace tessera::python {

namespace py = pybind11;

/// A read-only NumPy view (n, no copy) of the real member at byte offset `offset` of each of the n
/// structs of `Struct` starting at `first` (stride sizeof(Struct)), kept alive by `owner`.
template <class Struct>
py::array strided_view(const Struct* first, std::size_t n, std::size_t offset, py::handle owner) {
  const auto* base = reinterpret_cast<const char*>(first) + offset;
  py::array v(py::dtype::of<real>(), {static_cast<py::ssize_t>(n)}, {static_cast<py::ssize_t>(sizeof(Struct))},
              reinterpret_cast<const real*>(base), owner);
  py::detail::array_proxy(v.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return v;
}

/// The components argument of the supports (bind_solver.hpp's and the bars'): a bc.components
/// value; refuses one outside xyz.
inline bc::components checked_components(bc::components c, const char* what) {
  const auto bits = static_cast<unsigned>(c);
  require(bits <= 7u, what, ": components = ", bits, " is not a combination of x, y and z");
  return c;
}

/// The bar nodes `nodes` of solver s as a group, each checked against the bar node count.
template <class S>
bc::node_group bar_group(const S& s, const std::vector<index_t>& nodes, const char* what) {
  const index_t n = s.bar_nodes().size();
  require(!nodes.empty(), what, ": no bar nodes given");
  for (const index_t i : nodes) require(i >= 0 && i < n, what, ": bar node ", i, " is outside [0, ", n, ")");
  return bc::node_group{nodes, "bar nodes"};
}

/// A read-only view of the real member at byte offset `offset` of the bond state of every bar node
/// of solver `self` (an S).
template <class S>
py::array bond_view(py::object self, std::size_t offset) {
  const auto st = self.cast<const S&>().reinforcement().bond_states();
  return strided_view(st.data(), st.size(), offset, self);
}

/// Adds to the binding of solver S (whose reinforcement has bars) the bar nodes, their supports
/// and the views of the bars' state.
template <class S>
void bind_bars(py::class_<S>& cls) {
  using truss = typename S::reinforcement_type;
  using element_state = typename decltype(std::declval<const truss&>().element_states())::value_type;
  using bond_state = typename truss::bond_state;
  cls.def(
         "bar_nodes", [](const S& s) -> const node_set& { return s.bar_nodes(); },
         py::return_value_policy::reference_internal,
         "The bar nodes (a node_set: read-only NumPy views of reference, displacement, velocity, reaction; m, m/s, N)")
      .def(
          "bar_count", [](const S& s) { return s.reinforcement().bar_count(); }, "Number of bars")
      .def(
          "bar_node_range",
          [](const S& s, index_t b) {
            require(b >= 0 && b < s.reinforcement().bar_count(), "bar_node_range: bar ", b, " is outside [0, ",
                    s.reinforcement().bar_count(), ")");
            return s.reinforcement().bar_nodes(b);
          },
          py::arg("b"), "Bar b's node ids [first, end), from its start to its end")
      .def(
          "bar_element_range",
          [](const S& s, index_t b) {
            require(b >= 0 && b < s.reinforcement().bar_count(), "bar_element_range: bar ", b, " is outside [0, ",
                    s.reinforcement().bar_count(), ")");
            return s.reinforcement().bar_elements(b);
          },
          py::arg("b"), "Bar b's element ids [first, end), from its start to its end")
      .def(
          "fix_bar_nodes",
          [](S& s, const std::vector<index_t>& nodes, bc::components c) {
            bc::fix(s.bar_nodes(), bar_group(s, nodes, "fix_bar_nodes"), checked_components(c, "fix_bar_nodes"));
          },
          py::arg("nodes"), py::arg("components") = bc::components::xyz,
          "Fixes the given components of the listed bar nodes (zero velocity; reactions in bar_nodes().reaction, N)")
      .def(
          "prescribe_bar_velocity",
          [](S& s, const std::vector<index_t>& nodes, const vec3& v, bc::components c) {
            bc::prescribe_velocity(s.bar_nodes(), bar_group(s, nodes, "prescribe_bar_velocity"), v,
                                   checked_components(c, "prescribe_bar_velocity"));
          },
          py::arg("nodes"), py::arg("v"), py::arg("components") = bc::components::xyz,
          "Prescribes velocity v (m/s) on the given components of the listed bar nodes (a pulled bar end)")
      .def(
          "update_bar_velocity",
          [](S& s, const std::vector<index_t>& nodes, const vec3& v, bc::components c) {
            bc::update_velocity(s.bar_nodes(), bar_group(s, nodes, "update_bar_velocity"), v,
                                checked_components(c, "update_bar_velocity"));
          },
          py::arg("nodes"), py::arg("v"), py::arg("components") = bc::components::xyz,
          "Changes the prescribed velocity (m/s) of bar-node components already prescribed (a loading history)")
      .def(
          "bar_axial_force",
          [](py::object self) {
            const auto st = self.cast<const S&>().reinforcement().element_states();
            return strided_view(st.data(), st.size(), offsetof(element_state, axial_force), self);
          },
          "Axial force of every truss element at the last step (N, tension +; elements in bar order, "
          "bar_element_range): a read-only NumPy view of the solver's storage, no copy, valid until the next step")
      .def(
          "bar_slip", [](py::object self) { return bond_view<S>(self, offsetof(bond_state, slip)); },
          "Slip of every bar node relative to its host point along the bar at the last step (m; 0 on unbonded "
          "bars): a read-only NumPy view, no copy, valid until the next step")
      .def(
          "bar_bond_force", [](py::object self) { return bond_view<S>(self, offsetof(bond_state, force)); },
          "Axial bond force F_a of every bar node at the last step (N; the bar node takes -F_a along its axis): a "
          "read-only NumPy view, no copy, valid until the next step");
}

}  // namespace tessera::python
