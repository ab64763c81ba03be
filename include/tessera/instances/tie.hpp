#pragma once
// The deformable-block solver with bars of tessera::instances (tessera/instances.hpp gathers it
// with the others): the prism of instances/prism.hpp with steel bars embedded in its zones, the
// study's reinforced-concrete tie and beam family (examples/rc_tie, examples/rc_beam). Link
// tessera::instances.
#include "../reinforcement/embedded_truss.hpp"
#include "prism.hpp"

namespace tessera::instances {

/// The study's reinforced tie: deformable linear-elastic tetrahedral blocks, the tessellation's
/// bonded faces with prism_law (presets::study_tie_law), steel bars as embedded trusses bonded to
/// their host zones by a Coulomb bond (reinforcement::embedded_truss<coulomb_bond>, its params
/// from presets::tie_reinforcement), central differences with local damping.
using tie_solver = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<prism_law>,
                          reinforcement::embedded_truss<reinforcement::coulomb_bond>>;
/// The tie undamped (integrator::no_damping): the bars' and the concrete's dynamics (elastic
/// waves, free vibration) with the energy kept.
using tie_undamped_solver = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<prism_law>,
                                   reinforcement::embedded_truss<reinforcement::coulomb_bond>,
                                   integrator::central_difference<integrator::no_damping>>;

}  // namespace tessera::instances

TESSERA_SOLVER_INSTANCE(tessera::instances::tie_solver)
TESSERA_SOLVER_INSTANCE(tessera::instances::tie_undamped_solver)
TESSERA_INSTANCE(class tessera::reinforcement::embedded_truss<tessera::reinforcement::coulomb_bond>)
