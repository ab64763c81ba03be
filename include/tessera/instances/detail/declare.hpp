#pragma once
// How tessera::instances declares its solvers (instances/rigid.hpp, instances/prism.hpp): extern
// in a user's translation unit, defined once in src/instances.cpp (which defines
// TESSERA_INSTANCES_DEFINE before it includes <tessera/instances.hpp>), and the integrators both
// families use, declared here once. The solvers are instantiated member by member, the members
// that carry the work (the constructor, step, the time step, the energy and balance reports,
// defined out of the class in solver/detail/solver_members.hpp so that an extern declaration keeps
// them out of the user's file), not as whole classes: a whole-class instantiation would also
// instantiate members a block model refuses at compile time (register_applied_forces on rigid
// blocks). The contact sets, block models and integrators they use are instantiated whole.
#include "../../integrator/central_difference.hpp"
#include "../../integrator/damping.hpp"
#include "../../solver/solver.hpp"

#ifndef TESSERA_INSTANCES_DEFINE
/// Declares an instance extern (a user's unit takes it from tessera::instances).
#define TESSERA_INSTANCE(...) extern template __VA_ARGS__;
#else
/// Defines an instance (src/instances.cpp only).
#define TESSERA_INSTANCE(...) template __VA_ARGS__;
#endif
/// The members of solver S that tessera::instances compiles once.
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

TESSERA_INSTANCE(class tessera::integrator::central_difference<tessera::integrator::no_damping>)
TESSERA_INSTANCE(class tessera::integrator::central_difference<tessera::integrator::local_damping>)
