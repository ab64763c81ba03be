#pragma once
// The module's fourth unit of solvers (python/bind_beam.cpp): the study's RC beam
// (instances::beam_solver, beam_undamped_solver) with its law (law.study_beam_law: linear
// softening, the plastic cap, Coulomb with residual values; law.study_beam_params) and the rigid
// steel plates that load and support it (contact::rigid_platen<study_beam_law>); a translation
// unit of its own beside the other solvers', so each compiles in less memory.
#include <pybind11/pybind11.h>

namespace tessera::python {

/// Adds to module m the beam's law classes (law.study_beam_law and its params,
/// law.linear_softening_params, law.plastic_cap_params, law.study_beam_params), its material table
/// (contact.study_beam_table), the plates (contact.platen_geometry, contact.platen_motion,
/// contact.rigid_platen), and the solvers beam_solver and beam_undamped_solver to `instances`,
/// their checkpoint functions to `io`. After bind_scene and bind_solvers (the parameter types
/// their constructors and defaults name: coulomb_residual_params, embedded_truss_params).
void bind_beam(pybind11::module_& m, pybind11::module_& instances, pybind11::module_& io);

}  // namespace tessera::python
