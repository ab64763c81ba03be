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
/// Rigid blocks on detected bonded joints (law::bonded_joint_law: linear tension softening f_T,
/// G_f; Coulomb limit c_0 + sigma_c tan(phi_0) while intact, c_res + sigma_c tan(phi_res) once
/// broken or slipped), undamped central differences: the faces the blocks start on are bonded
/// when the contact params' bond_faces is true (detected_contacts::bond_gap_fraction), every
/// contact found later starts on the residual values. Dynamics of a bonded assembly that cracks.
using rigid_bonded_solver = solver<blocks::rigid, contact::detected_contacts<law::bonded_joint_law>,
                                   reinforcement::none, integrator::central_difference<integrator::no_damping>>;
/// The same with local damping (solver_options::damping_gamma): quasi-static loading of bonded
/// rigid blocks to cracking.
using rigid_bonded_damped_solver = solver<blocks::rigid, contact::detected_contacts<law::bonded_joint_law>,
                                          reinforcement::none, integrator::central_difference<integrator::local_damping>>;

}  // namespace tessera::instances

TESSERA_SOLVER_INSTANCE(tessera::instances::rigid_dry_solver)
TESSERA_SOLVER_INSTANCE(tessera::instances::rigid_dry_damped_solver)
TESSERA_SOLVER_INSTANCE(tessera::instances::rigid_bonded_solver)
TESSERA_SOLVER_INSTANCE(tessera::instances::rigid_bonded_damped_solver)
TESSERA_INSTANCE(class tessera::contact::detected_contacts<tessera::law::dry_joint_law>)
TESSERA_INSTANCE(class tessera::contact::detected_contacts<tessera::law::bonded_joint_law>)
