#pragma once
// Concepts of the blocks/ folder: the material of a constant-strain tetrahedral zone
// (ZoneModel) and the block model a solver is composed with (BlockModel).
//
// ZoneModel — a pure evaluator of the zone material in the co-rotated frame of its block
// (small strain there, see blocks/deformable.hpp). The block model owns loops and storage.
//
// | expression                     | meaning                                                              |
// |--------------------------------|----------------------------------------------------------------------|
// | Z::params                      | plain struct of material parameters, SI units                        |
// | Z::validate(p)                 | throws tessera::invalid_input naming the bad parameter and its value |
// | Z::density(p)                  | mass density rho (kg/m^3), for the lumped mass rho V / 4 per corner  |
// | Z::constants, Z::prepare(p)    | derived constants computed once per zone loop (e.g. Lame constants)  |
// | Z::stress(c, eps)              | Cauchy stress (Pa, tension +, Voigt xx yy zz yz zx xy) from the      |
// |                                | small strain eps (Voigt, engineering shears 2 eps_ij), c = prepare(p)|
// | Z::elasticity_matrix(p)        | 6x6 tangent C (Pa) in the same Voigt convention, for the time step   |
// | Z::strain_energy_density(p,e)  | stored elastic energy per unit volume (J/m^3) at strain e            |
//
// BlockModel — what a solver needs from its blocks (deformable zones or rigid bodies). The
// block gridpoints are one node_set built from geometry::block_mesh (same gridpoint ids).
//
// | expression                          | meaning                                                         |
// |-------------------------------------|-----------------------------------------------------------------|
// | B::params                           | block material (zone material or density), SI units             |
// | B::is_rigid                         | constexpr bool: true when gridpoints are slaved to 6-DOF bodies |
// | b.build(tess, mesh, p, gridpoints)  | validates p, precomputes, sizes gridpoints, sets reference       |
// |                                     | positions and lumped masses (kg); throws on bad input            |
// | b.build(tess, mesh, ms, gridpoints) | the same with a std::span of params, one per material id:       |
// |                                     | block b takes ms[mesh.material(b)]                              |
// | b.accumulate_forces(gridpoints)     | step 2: adds internal (zone) forces to gridpoints.force (N)      |
// | b.add_stiffness_bounds(gridpoints)  | adds the Gershgorin row-sum bound of the block stiffness (N/m)   |
// | b.advance(integ, gp, dt, work)      | steps 5-6: integrates the block DOFs with integrator `integ`,   |
// |                                     | adds boundary work and damping dissipation of the step to work |
// | b.zone_stress()                     | zone_stress_matrix (Pa), one row per zone; empty for rigid       |
// | b.stored_energy(gridpoints)         | elastic energy stored in the blocks (J)                          |
// | b.kinetic_energy(gridpoints)        | kinetic energy of the blocks (J), at the half step               |
// | b.block_count()                     | number of blocks                                                 |
// | b.checkpoint(ar)       (optional)    | saves or loads the blocks' evolving state (io/checkpoint.hpp);   |
// |                                     | needed by io::save_checkpoint / load_checkpoint                  |

#include <concepts>
#include <span>
#include <type_traits>

#include <Eigen/Core>

#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/tessellation.hpp"

namespace tessera {

/// Symmetric tensor in Voigt order (xx, yy, zz, yz, zx, xy).
using voigt6 = Eigen::Matrix<real, 6, 1>;

namespace zones {

template <class Z>
concept ZoneModel = requires(const typename Z::params& p, const typename Z::constants& c, const voigt6& eps) {
  typename Z::params;
  typename Z::constants;
  { Z::validate(p) } -> std::same_as<void>;
  { Z::density(p) } -> std::convertible_to<real>;
  { Z::prepare(p) } -> std::convertible_to<typename Z::constants>;
  { Z::stress(c, eps) } noexcept -> std::convertible_to<voigt6>;
  { Z::elasticity_matrix(p) } -> std::convertible_to<Eigen::Matrix<real, 6, 6>>;
  { Z::strain_energy_density(p, eps) } -> std::convertible_to<real>;
};

}  // namespace zones

namespace blocks {

template <class B>
concept BlockModel = requires(B& b, const B& cb, const geometry::tessellation& tess, const geometry::block_mesh& mesh,
                              const typename B::params& p, node_set& gp, const node_set& cgp) {
  typename B::params;
  typename std::bool_constant<B::is_rigid>;  // must be a compile-time constant
  { b.build(tess, mesh, p, gp) } -> std::same_as<void>;
  { b.build(tess, mesh, std::span<const typename B::params>(&p, 1), gp) } -> std::same_as<void>;
  { b.accumulate_forces(gp) } noexcept -> std::same_as<void>;
  { cb.add_stiffness_bounds(gp) } -> std::same_as<void>;
  { cb.zone_stress() } -> std::convertible_to<const zone_stress_matrix&>;
  { cb.stored_energy(cgp) } -> std::convertible_to<real>;
  { cb.kinetic_energy(cgp) } -> std::convertible_to<real>;
  { cb.block_count() } -> std::convertible_to<index_t>;
  // b.advance(integrator, gp, dt, work) is a member template (any Integrator), checked where
  // the solver instantiates it.
};

}  // namespace blocks
}  // namespace tessera
