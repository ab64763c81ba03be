#pragma once
// The deformable-block solvers on detected contacts of tessera::instances (tessera/instances.hpp
// gathers them with the others): elastic tetrahedral blocks that separate, slide and meet through
// detected dry joints (detected_contacts::params::deformable_blocks = true). Link
// tessera::instances.
#include "../blocks/deformable.hpp"
#include "../blocks/linear_elastic_tet.hpp"
#include "rigid.hpp"

namespace tessera::instances {

/// Deformable linear-elastic tetrahedral blocks on detected dry joints (law::dry_joint_law),
/// undamped central differences: dynamics of elastic blocks whose energy the run must keep. Build
/// it with contact params whose deformable_blocks is true.
using deformable_dry_solver =
    solver<blocks::deformable<zones::linear_elastic_tet>, contact::detected_contacts<law::dry_joint_law>,
           reinforcement::none, integrator::central_difference<integrator::no_damping>>;
/// The same with local damping (solver_options::damping_gamma): quasi-static settling of elastic
/// blocks on detected contacts.
using deformable_dry_damped_solver =
    solver<blocks::deformable<zones::linear_elastic_tet>, contact::detected_contacts<law::dry_joint_law>,
           reinforcement::none, integrator::central_difference<integrator::local_damping>>;

}  // namespace tessera::instances

TESSERA_SOLVER_INSTANCE(tessera::instances::deformable_dry_solver)
TESSERA_SOLVER_INSTANCE(tessera::instances::deformable_dry_damped_solver)
