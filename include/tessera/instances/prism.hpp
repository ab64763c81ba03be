#pragma once
// The deformable-block solver of tessera::instances (tessera/instances.hpp gathers it with the
// rigid ones): the README's prism. A deformable scene that includes this header instead of
// <tessera/instances.hpp> does not parse the rigid blocks' detected contacts. Link
// tessera::instances.
#include "../blocks/deformable.hpp"
#include "../blocks/linear_elastic_tet.hpp"
#include "../contact/face_contacts.hpp"
#include "../law/cohesive_frictional.hpp"
#include "../reinforcement/none.hpp"
#include "../solver/solver.hpp"
#include "detail/declare.hpp"

namespace tessera::instances {

/// The README's prism: deformable linear-elastic tetrahedral blocks, the tessellation's bonded
/// faces as contacts with power softening in tension (presets::study_tie_law), no bars, central
/// differences with local damping.
using prism_law = law::cohesive_frictional<law::power_softening, law::elastic_compression, law::coulomb_residual>;
/// The solver of the README's prism (prism_law on bonded faces, deformable tetrahedral blocks).
using prism_solver = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<prism_law>>;
/// The prism undamped (integrator::no_damping): elastic waves, free vibration and dynamic loading
/// of deformable blocks on bonded faces, whose energy the run must keep.
using prism_undamped_solver = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<prism_law>,
                                     reinforcement::none, integrator::central_difference<integrator::no_damping>>;

}  // namespace tessera::instances

TESSERA_SOLVER_INSTANCE(tessera::instances::prism_solver)
TESSERA_SOLVER_INSTANCE(tessera::instances::prism_undamped_solver)
TESSERA_INSTANCE(class tessera::blocks::deformable<tessera::zones::linear_elastic_tet>)
TESSERA_INSTANCE(class tessera::contact::face_contacts<tessera::instances::prism_law>)
