#pragma once
// The solvers most scenes use, compiled once into the tessera::instances library (issue #40:
// a small scene compiled in about a minute, most of it instantiating and optimising the
// solver). Opt in by including this header and linking tessera::instances:
//
//   target_link_libraries(my_scene PRIVATE tessera::instances)   # brings tessera::tessera
//   #include <tessera/instances.hpp>
//   tessera::instances::rigid_dry_solver s(tess, mesh, blocks::rigid::params{2400},  // kg/m^3
//       {law::dry_joint(1e10, 1e10, law::friction_angle::from_degrees(30)), 1e-3});  // Pa/m, Pa/m, phi; tolerance m
//
// Each alias below is declared `extern template` here and defined once in the library
// (src/instances.cpp), so a translation unit that includes this header does not emit the
// solver's out-of-line members again; the type is the same as the one spelled out in full, so
// a scene that writes `solver<blocks::rigid, contact::detected_contacts<law::dry_joint_law>, ...>`
// gets the compiled copy too. A solver type not listed here is compiled in the user's
// translation unit as before. The library is built with the flags of the build that makes it
// (one definition per program: link one tessera::instances, built with the compiler and
// -march flags of the rest of the program).
#include "blocks/deformable.hpp"
#include "blocks/linear_elastic_tet.hpp"
#include "blocks/rigid.hpp"
#include "contact/detected_contacts.hpp"
#include "contact/face_contacts.hpp"
#include "integrator/central_difference.hpp"
#include "integrator/damping.hpp"
#include "law/cohesive_frictional.hpp"
#include "law/joints.hpp"
#include "reinforcement/none.hpp"
#include "solver/solver.hpp"

namespace tessera::instances {

/// The README's prism: deformable linear-elastic tetrahedral blocks, the tessellation's bonded
/// faces as contacts with power softening in tension (presets::study_tie_law), no bars, central
/// differences with local damping.
using prism_law = law::cohesive_frictional<law::power_softening, law::elastic_compression, law::coulomb_residual>;
using prism_solver = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<prism_law>>;

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

// Defined once in src/instances.cpp (which defines TESSERA_INSTANCES_DEFINE before including
// this header); declared here so that users' translation units take them from the library.
// The solvers are instantiated member by member, the members that carry the work (the
// constructor, step, the time step, the energy and balance reports), not as whole classes: a
// whole-class instantiation would also instantiate members a block model refuses at compile
// time (register_applied_forces on rigid blocks). The contact sets, block models and
// integrators they use are instantiated whole.
#ifndef TESSERA_INSTANCES_DEFINE
#define TESSERA_INSTANCE(...) extern template __VA_ARGS__;  ///< declares an instance extern (a user's unit takes it from tessera::instances)
#else
#define TESSERA_INSTANCE(...) template __VA_ARGS__;
#endif
/// The members of solver S that tessera::instances compiles once
#define TESSERA_SOLVER_INSTANCE(S)                                                                              \
  TESSERA_INSTANCE(S::solver(const tessera::geometry::tessellation&, const tessera::geometry::block_mesh&,     \
                             const S::block_materials&, const S::contact_set_type::params&,                     \
                             const S::reinforcement_type::params&, const tessera::solver_options&))             \
  TESSERA_INSTANCE(void S::step())                                                                              \
  TESSERA_INSTANCE(void S::compute_time_step())                                                                 \
  TESSERA_INSTANCE(void S::set_gravity(const tessera::vec3&))                                                   \
  TESSERA_INSTANCE(tessera::real S::kinetic_energy() const)                                                     \
  TESSERA_INSTANCE(tessera::out_of_balance S::unbalanced_force() const)                                         \
  TESSERA_INSTANCE(tessera::energy_balance S::energies() const)
TESSERA_SOLVER_INSTANCE(tessera::instances::prism_solver)
TESSERA_SOLVER_INSTANCE(tessera::instances::rigid_dry_solver)
TESSERA_SOLVER_INSTANCE(tessera::instances::rigid_dry_damped_solver)
TESSERA_INSTANCE(class tessera::blocks::deformable<tessera::zones::linear_elastic_tet>)
TESSERA_INSTANCE(class tessera::contact::face_contacts<tessera::instances::prism_law>)
TESSERA_INSTANCE(class tessera::contact::detected_contacts<tessera::law::dry_joint_law>)
TESSERA_INSTANCE(class tessera::integrator::central_difference<tessera::integrator::no_damping>)
TESSERA_INSTANCE(class tessera::integrator::central_difference<tessera::integrator::local_damping>)
#undef TESSERA_SOLVER_INSTANCE
#undef TESSERA_INSTANCE
