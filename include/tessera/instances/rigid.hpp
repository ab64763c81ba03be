#pragma once
// The rigid-block solvers of tessera::instances (tessera/instances.hpp gathers them with the
// prism's): a rigid scene that includes this header instead of <tessera/instances.hpp> does not
// parse the deformable blocks and the face contacts. Link tessera::instances.
#include "../blocks/rigid.hpp"
#include "../contact/detected_contacts.hpp"
#include "../law/joints.hpp"
#include "../reinforcement/none.hpp"
#include "../solver/solver.hpp"
#include "detail/declare.hpp"

namespace tessera::instances {

/// Rigid blocks that separate and meet through detected dry joints (law::dry_joint_law: no
/// tension, elastic compression, Coulomb friction), undamped central differences: dynamics
/// (toppling, sliding, impact) whose energy the run must keep.
using rigid_dry_solver = solver<blocks::rigid, contact::detected_contacts<law::dry_joint_law>, reinforcement::none,
                                integrator::central_difference<integrator::no_damping>>;
/// The same with local damping (solver_options::damping_gamma): quasi-static settling and
/// stability of rigid block assemblies.
using rigid_dry_damped_solver = solver<blocks::rigid, contact::detected_contacts<law::dry_joint_law>, reinforcement::none,
                                       integrator::central_difference<integrator::local_damping>>;

}  // namespace tessera::instances

TESSERA_SOLVER_INSTANCE(tessera::instances::rigid_dry_solver)
TESSERA_SOLVER_INSTANCE(tessera::instances::rigid_dry_damped_solver)
TESSERA_INSTANCE(class tessera::contact::detected_contacts<tessera::law::dry_joint_law>)
