#pragma once
// The module's bindings outside the solvers (python/bind_extras.cpp): calibrated parameter files
// (examples/common/calibration.hpp's reader), checkpoint headers, Neper .tess import, CSV files,
// law.contact_status. A
// translation unit of its own, so the solvers' bindings (tessera_module.cpp) do not recompile
// for it and each compiles in less memory.
#include <pybind11/pybind11.h>

namespace tessera::python {

/// Adds tessera.calibration, tessera.io's checkpoint_info, read_checkpoint_info, read_neper_tess
/// and write_csv, and tessera.law.contact_status to module m
/// (whose submodules io and law exist).
void bind_extras(pybind11::module_& m);

}  // namespace tessera::python
