#pragma once
// The module's bindings of the scene's parts (python/bind_scene.cpp): errors, geometry, laws,
// block and contact parameters, options, gridpoints, supports' components, per-sub-contact state
// and energies; a translation unit of its own beside the solvers' (tessera_module.cpp).
#include <pybind11/pybind11.h>

namespace tessera::python {

/// Adds the exception types and the submodules geometry, law, zones, blocks, contact, recorders
/// (its functions) and bc, with the option, state and result classes, to module m: first, since
/// the solvers' bindings name these types in their defaults.
void bind_scene(pybind11::module_& m);

}  // namespace tessera::python
