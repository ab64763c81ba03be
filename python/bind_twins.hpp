#pragma once
// The module's third unit of solvers (python/bind_twins.cpp): the rigid blocks on detected bonded
// joints (instances::rigid_bonded_solver, rigid_bonded_damped_solver) and the undamped twins of
// the prism and the tie (instances::prism_undamped_solver, tie_undamped_solver); a translation
// unit of its own beside tessera_module.cpp and bind_solvers.cpp, so each compiles in less memory.
#include <pybind11/pybind11.h>

namespace tessera::python {

/// Adds the solvers rigid_bonded_solver, rigid_bonded_damped_solver, prism_undamped_solver and
/// tie_undamped_solver to `instances`, their checkpoint functions to `io`. After bind_scene and
/// bind_solvers (the parameter types their constructors and defaults name).
void bind_twins(pybind11::module_& instances, pybind11::module_& io);

}  // namespace tessera::python
