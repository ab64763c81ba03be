#pragma once
// The module's second unit of solvers (python/bind_solvers.cpp): the tie with bars
// (instances::tie_solver) with the reinforcement's parameter classes, and the deformable blocks on
// detected contacts (instances::deformable_dry_solver, deformable_dry_damped_solver); a
// translation unit of its own beside tessera_module.cpp's rigid solvers and prism, so each
// compiles in less memory.
#include <pybind11/pybind11.h>

namespace tessera::python {

/// Adds the submodule reinforcement (steel, bar, coulomb_bond_params, embedded_truss_params,
/// tie_reinforcement) to module m and the solvers tie_solver, deformable_dry_solver and
/// deformable_dry_damped_solver to `instances`, their checkpoint functions to `io`. After
/// bind_scene (the types their defaults name).
void bind_solvers(pybind11::module_& m, pybind11::module_& instances, pybind11::module_& io);

}  // namespace tessera::python
