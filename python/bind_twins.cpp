// The module's third unit of solvers (bind_twins.hpp): rigid blocks on detected bonded joints,
// with and without local damping, and the prism and the tie without local damping, each through
// bind_solver<S> (bind_solver.hpp), named as in C++ (tessera::instances).
#include "bind_twins.hpp"

#include <tessera/instances/prism.hpp>  // compiled once (linked: tessera::instances)
#include <tessera/instances/rigid.hpp>
#include <tessera/instances/tie.hpp>

#include "bind_solver.hpp"

namespace tessera::python {

void bind_twins(pybind11::module_& inst, pybind11::module_& io) {
  bind_solver<instances::rigid_bonded_damped_solver>(
      inst, io, "rigid_bonded_damped_solver",
      "Rigid blocks on detected bonded joints (contact.detected_bonded_joints with law.bonded_joint; bond_faces = "
      "True bonds the faces the blocks start on), central differences with local damping (quasi-static loading "
      "to cracking)");
  bind_solver<instances::rigid_bonded_solver>(
      inst, io, "rigid_bonded_solver",
      "The same undamped (integrator::no_damping): dynamics of a bonded assembly whose energy the run must keep");
  bind_solver<instances::prism_undamped_solver>(
      inst, io, "prism_undamped_solver",
      "The prism undamped: deformable linear-elastic tetrahedral blocks on the tessellation's bonded faces with the "
      "study's law (law.study_tie_law), central differences without damping (elastic waves, free vibration)");
  bind_solver<instances::tie_undamped_solver>(
      inst, io, "tie_undamped_solver",
      "The tie with bars undamped: the prism with steel bars embedded in its zones "
      "(reinforcement.embedded_truss_params), central differences without damping");
}

}  // namespace tessera::python
