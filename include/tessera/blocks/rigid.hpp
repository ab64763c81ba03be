#pragma once
// blocks::rigid — rigid polyhedral blocks with six degrees of freedom each (3DEC's rigid blocks,
// PFC's clumps) behind the BlockModel interface, so a solver composes them with the same
// contacts, reinforcement and boundary conditions as deformable blocks.
//
// Body. Block b is tessellation cell b with density rho: mass m = rho V, centroid c and inertia
// tensor about c, I = rho (tr(S) 1 - S), from the exact polyhedron moments S
// (geometry/mass_properties.hpp); principal axes E = [e1 e2 e3] (det E = +1) and principal
// moments I1 <= I2 <= I3. A gridpoint i of the block has body coordinates r_i = E^T (X_i - c) and
// current position x_i = c + u_c + R r_i, R = R(q).
//
// State (SI), per block:
//   u_c  centroid displacement (m), full step            v  centroid velocity (m/s), half step, world
//   q    orientation, unit quaternion body -> world, R(q) = E in the reference configuration, full step
//   w    angular velocity (rad/s), half step, in the BODY principal frame (Euler's equations are
//        diagonal there; angular_velocity(b) returns the world vector R w)
//   F, M force (N) and moment about the current centroid (N m, world) of the step
// Gravity (set_gravity, the solver's set_gravity): the weight m0 g of each block, m0 its unscaled
// mass, is added to F at the centroid (no moment; mass scaling does not change the weight).
//
// One step (advance; steps 5-6 of docs/architecture.md):
//  1. Reduction, fixed order over the block's gridpoints (deterministic, parallel over blocks):
//         F = sum_i f_i,   M = sum_i (x_i - c) x f_i = sum_i (R r_i) x f_i.
//  2. Translation, per WORLD component with the integrator's damping law (study eq. 1):
//         v+ = v- + (F - F_d) dt / m,   u_c += v+ dt.
//  3. Rotation, Euler's equations per PRINCIPAL component k (as 3DEC and PFC apply local
//     damping to each component of the unbalanced moment):
//         I_k (w+_k - w-_k) / dt = T_k - T_d,k,   T = R^T M - wm x (I wm),   wm = (w- + w+) / 2.
//     Decision: the gyroscopic term is evaluated at the time-centred wm (a few fixed-point
//     iterations per block, contraction ~|w| dt), not at w-: then wm . (wm x I wm) = 0 and
//     (I wm) . (wm x I wm) = 0, so a torque-free body keeps its kinetic energy 1/2 w.Iw and
//     |I w| exactly, while the forward-evaluated term w- x I w- adds energy of order
//     (|w| dt)^2 per step (secular drift). Measured over 1e4 torque-free steps at |w| dt = 8.4e-4
//     rad: kinetic-energy drift 3.6e-4 forward, 5e-15 centred; world angular momentum (at the half
//     step, angular_momentum()) 1.9e-8 (tests/test_rigid.cpp). Forces stay explicit.
//  4. Orientation by the exact exponential map of the step's rotation, renormalised:
//         q+ = q ⊗ exp(w+ dt / 2)      (R+ = R exp([w+ dt]x), body-frame increment).
//  5. Slaved gridpoints: u_i = u_c + (R+ - E) r_i, and the SECANT velocity
//         v_i = (x_i(t+dt) - x_i(t)) / dt = v+ + R (exp([w+ dt]x) - 1) r_i / dt
//             = v+ + (2 sin(θ/2) / θ) w+ x (R_mid r_i),   θ = |w+| dt,
//     i.e. the rigid velocity w x (R r) at the mid-rotation up to a factor 1 - θ^2/24. Decision:
//     the secant rather than w x (R r), so that the contacts' increment du = (v_b - v_a) dt is
//     exactly the displacement increment of the step and two blocks moving as one rigid body
//     (any rotation) give their contacts zero relative displacement to round-off.
//
// Boundary conditions (prescriptions on gridpoints, solver/boundary.hpp): a block is CONSTRAINED
// when any of its gridpoints has a prescribed component. Then each prescribed world component
// c of the translation gets that velocity and ALL rotations are held (w = 0). Two gridpoints of
// one block prescribing different velocities for the same component throw invalid_input naming
// the block, the component, both gridpoints and both values. Reactions (integrator convention,
// R = m (v_p - v-)/dt - F): the block's reaction force component c is split equally among the
// n_c gridpoints of the block that prescribe c (the others get 0), so recorders::reaction_sum over
// a group holding all of them returns the block's total; the reaction moment (N m, world, about
// the centroid) is recorded on the block only (reaction_moment(b)). A scene need not pick a
// gridpoint: solver::fix_block(b) and solver::prescribe_block_velocity(b, v, components) prescribe
// every gridpoint of the block, and solver::gridpoints_of_block(b) is the group to sum over.
//
// Stable time step (provably stable for the undamped linearised scheme; the solver calls
// critical_time_step instead of the nodal bound). With k_i the gridpoints' Gershgorin stiffness
// bounds (contacts, bonds), any block motion u_i = v + θ x ρ_i (ρ_i = R r_i) gives
//     u^T K u <= sum_i k_i |u_i|^2 <= 2 (k_t |v|^2 + k_r |θ|^2),  k_t = sum_i k_i,  k_r = sum_i k_i |ρ_i|^2,
// while u^T M u >= m |v|^2 + I1 |θ|^2, so omega_max^2 <= 2 max_b max(k_t/m, k_r/I1) and
//     dt_cr = min_b min( 2 sqrt(m / (2 a k_t)), 2 sqrt(I1 / (2 a k_r)) ),
// a = the damping's stiffness amplification (1 + gamma for local damping, as for deformable
// blocks, integrator/timestep.hpp). The solver's safety factor multiplies dt_cr. The report names
// the block's first gridpoint, m, and the equivalent stiffness k_eq (N/m) with 2 sqrt(m/(a k_eq)) = dt
// (k_eq = 2 k_t, or 2 k_r m / I1 when rotation limits).
// Fully prescribed blocks are skipped (fully_prescribed: all three translation components
// prescribed, so the rotations are held too). Their six DOFs are set, not integrated: with u_p
// the prescribed displacements, the free DOFs obey M_f a_f = -K_ff u_f - K_fp u_p(t), whose
// stability is that of M_f^-1 K_ff (the u_p term is a forcing), and the bound above restricted to
// u_p = 0 sums over the free blocks' gridpoints only, whose k_i already carry their contacts
// with the prescribed blocks (each contact puts its stiffness on both sides). So a fixed base
// no longer sets dt: on the issue #40 arch (20 voussoirs, r 4.5-5 m, on a 12 x 1 x 0.5 m slab
// held by fix_block) dt grows x6.0, from 1.58e-5 to 9.47e-5 s. When no
// free block has a stiffness, every block counts as before. A block skipped when the step was
// chosen (record_step_bound) and freed later is refused (check_step_bound, before each step of the
// solver): the step does not bound it.
// Mass scaling: a block whose bound is below the target gets m and I multiplied by ONE factor
// lambda >= 1 (radius of gyration kept), the smallest that makes both bounds reach the target.
//
// Energies: kinetic 1/2 m |v|^2 + 1/2 w.I w at the half step; no elastic energy is stored in
// rigid blocks; zone_stress() is empty (reinforcement sees no confinement).
//
// Storage: one `body` record per block (its 6-DOF state is always read together) and the
// gridpoint body coordinates as an N x 3 column-major array. advance allocates nothing.
// Thread safety: const members are safe to call concurrently; advance is not.
//
// Where each job lives: the block record and its prescriptions in detail/rigid_body.hpp, steps
// 1-5 of a block (reduction, integration, slaved gridpoints) in detail/rigid_motion.hpp, the
// stable step, the blocks it leaves out and the mass scaling in detail/rigid_step_bound.hpp, the
// rotation helpers in detail/rigid_rotation.hpp; this header holds the BlockModel and its state,
// impl/rigid.ipp the bodies of its larger members (compiled once in tessera::instances).

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "../core/errors.hpp"
#include "../core/separate_compilation.hpp"
#include "../core/nodes.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/mass_properties.hpp"
#include "../geometry/tessellation.hpp"
#include "../geometry/tessellation_queries.hpp"
#include "../integrator/concepts.hpp"
#include "../integrator/timestep.hpp"
#include "concepts.hpp"
#include "detail/rigid_body.hpp"
#include "detail/rigid_motion.hpp"
#include "detail/rigid_rotation.hpp"
#include "detail/rigid_step_bound.hpp"
#include "detail/symmetric_eigen3.hpp"

namespace tessera::blocks {

/// Rigid blocks: six degrees of freedom each, moved by the resultant of their gridpoint forces (file comment)
class rigid {
 public:
  /// Block material of rigid blocks: only the density.
  struct params {
    real density = 2400;  ///< mass density rho (kg/m^3)

    constexpr params() = default;
    constexpr params(real rho) : density(rho) {}  ///< rho (kg/m^3). NOLINT(google-explicit-constructor): params{2400}
    /// From any block material with a density (e.g. zones::linear_elastic_tet::params), so a scene
    /// built for deformable blocks runs with rigid ones unchanged; the elastic constants are unused.
    template <class Material>
      requires requires(const Material& m) { { m.density } -> std::convertible_to<real>; }
    constexpr params(const Material& m) : density(m.density) {}  // NOLINT(google-explicit-constructor)
  };
  static constexpr bool is_rigid = true;  ///< rigid

  rigid() = default;

  /// Throws invalid_input unless the density is finite and > 0.
  static void validate(const params& p) { require_positive(p.density, "rigid blocks: density rho (kg/m^3)"); }

  /// Validates p, computes every block's mass, centroid, principal moments and axes from the
  /// tessellation cell with the same id, and sizes `gridpoints` (reference positions from the mesh,
  /// zero state). Each gridpoint gets the mass m_b / n_b (its block's mass shared equally; used only by
  /// diagnostics, the dynamics uses the block's m and I). Throws geometry_error when the mesh and
  /// the tessellation disagree on the block count or a cell has non-positive volume.
  void build(const geometry::tessellation& tess, const geometry::block_mesh& mesh, const params& p,
             node_set& gridpoints) {
    build(tess, mesh, std::span<const params>(&p, 1), gridpoints);
  }
  /// The same with one material per material id: block b takes materials[mesh.material(b)]
  /// (geometry::block_mesh::block_material); invalid_input for a block whose id has no entry.
  void build(const geometry::tessellation& tess, const geometry::block_mesh& mesh, std::span<const params> materials,
             node_set& gridpoints);

  /// Step 2: rigid blocks have no internal forces.
  void accumulate_forces(node_set& /*gridpoints*/) noexcept {}

  /// Rigid blocks add no internal stiffness; their stable step comes from critical_time_step.
  void add_stiffness_bounds(node_set& /*gridpoints*/) const {}

  /// Steps 5-6 (see the file comment): reduces the gridpoint forces to block forces and moments,
  /// integrates the 6 DOF of every block with `integ`, slaves the gridpoints and adds the boundary
  /// work and damping dissipation of the step to `work`. Throws invalid_input for conflicting
  /// prescriptions within one block (before any state changes).
  template <class Integrator, class Work>
  void advance(const Integrator& integ, node_set& gridpoints, real dt, Work& work) {
    advance(integ, gridpoints, dt, work, dt);
  }
  /// The same with the velocity update over kick_dt (s, > 0): (dt_before + dt) / 2 in the step
  /// where the solver changes dt (solver.hpp, "Time step"), the variable-step central
  /// difference v(t + dt/2) = v(t - dt_before/2) + a(t) (dt_before + dt) / 2.
  template <class Integrator, class Work>
  void advance(const Integrator& integ, node_set& gridpoints, real dt, Work& work, real kick_dt) {
    detail::advance_rigid_blocks(integ, gridpoints, body_position_, gravity_, bodies_, constraints_, work_, dt, work, kick_dt,
                                 block_count(), [](std::int64_t k) { return static_cast<index_t>(k); });
  }
  /// The same for the listed blocks only (increasing ids; the others keep their state): a rank's
  /// own blocks in a run split over MPI ranks (distributed::rigid_stepper). The listed blocks get
  /// the bits advance gives them, and `work` their terms in list order. Throws invalid_input for
  /// an id out of range.
  template <class Integrator, class Work>
  void advance_blocks(const Integrator& integ, node_set& gridpoints, real dt, Work& work, real kick_dt,
                      std::span<const index_t> blocks) {
    for (const index_t b : blocks) (void)at(b);
    detail::advance_rigid_blocks(integ, gridpoints, body_position_, gravity_, bodies_, constraints_, work_, dt, work, kick_dt,
                                 static_cast<index_t>(blocks.size()),
                                 [&](std::int64_t k) { return blocks[static_cast<std::size_t>(k)]; });
  }

  /// Doubles per block in write_body_states: u_c, v, w, q, q at the half step, F, M, reactions.
  static constexpr int body_state_size = 29;
  /// Appends the state of each listed block after its step (body_state_size doubles a block) to
  /// `out`, for read_body_states on another rank.
  void write_body_states(std::span<const index_t> blocks, std::vector<double>& out) const;
  /// Takes the listed blocks' states from `in` (write_body_states' layout, one step of `dt` s on
  /// from the states held here) and slaves their gridpoints as their owner's step did, so a copy
  /// of a block has its owner's bits. With `slave_now` (per block of the model), a block whose
  /// flag is 0 keeps its gridpoints and puts its rotation before the step in rotation_before[b],
  /// for slave_gridpoints later in the same step. Returns the doubles read.
  std::size_t read_body_states(std::span<const index_t> blocks, const double* in, node_set& gridpoints, real dt,
                               std::span<const std::uint8_t> slave_now = {}, std::span<mat3> rotation_before = {});
  /// Block b's gridpoints after a step of `dt` s from its body state now and its rotation before
  /// that step (the slaving of the integration, read_body_states): the owner's bits.
  void slave_gridpoints(index_t b, const mat3& rotation_before, node_set& gridpoints, real dt) const noexcept;

  /// Empty: rigid blocks have no zones (reinforcement sees no confinement).
  [[nodiscard]] const zone_stress_matrix& zone_stress() const { return zone_stress_; }

  /// Saves or loads each body's motion (io/checkpoint.hpp): displacement, velocity, angular
  /// velocity, orientation at the full and half step, rotation matrix, last force, moment and
  /// reactions. Masses and inertias are rebuilt with the model.
  template <class Archive>
  void checkpoint(Archive& ar) {
    ar.same("blocks/rigid/count", static_cast<std::int64_t>(bodies_.size()));
    ar.members("blocks/rigid/displacement", bodies_, &body::displacement);
    ar.members("blocks/rigid/velocity", bodies_, &body::velocity);
    ar.members("blocks/rigid/angular_velocity", bodies_, &body::angular_velocity);
    ar.members("blocks/rigid/orientation", bodies_, &body::orientation);
    ar.members("blocks/rigid/half_orientation", bodies_, &body::half_orientation);
    ar.members("blocks/rigid/rotation", bodies_, &body::rotation);
    ar.members("blocks/rigid/force", bodies_, &body::force);
    ar.members("blocks/rigid/moment", bodies_, &body::moment);
    ar.members("blocks/rigid/reaction_force", bodies_, &body::reaction_force);
    ar.members("blocks/rigid/reaction_moment", bodies_, &body::reaction_moment);
  }
  /// Rigid blocks store no elastic energy (J).
  [[nodiscard]] real stored_energy(const node_set& /*gridpoints*/) const { return 0; }
  /// sum_b 1/2 m |v|^2 + 1/2 sum_k I_k w_k^2 (J) at the half step (scaled masses).
  [[nodiscard]] real kinetic_energy(const node_set& gridpoints) const;
  [[nodiscard]] index_t block_count() const { return static_cast<index_t>(bodies_.size()); }  ///< Number of blocks

  // ---- time step and mass scaling (called by the solver instead of the nodal versions) ----

  /// min over blocks of the translational and rotational bounds (s; see the file comment) from
  /// the gridpoints' stiffness bounds k_i (N/m) assembled by contacts and bonds; a = stiffness
  /// amplification of the damping. Blocks without stiffness are skipped, and so are fully
  /// prescribed blocks (fully_prescribed, as the gridpoints' constraints stand now) unless no
  /// other block has a stiffness. Throws invalid_input for a < 1.
  [[nodiscard]] integrator::critical_step critical_time_step(const node_set& gridpoints, real amplification = 1) const;
  /// True when every translation component of block b is prescribed on some gridpoint of it (then
  /// its rotations are held too: all six DOFs are set, none integrated). Reads the gridpoints'
  /// constraints as they stand. Throws invalid_input for a bad id.
  [[nodiscard]] bool fully_prescribed(const node_set& gridpoints, index_t b) const {
    return detail::rigid_fully_prescribed(gridpoints, at(b));
  }
  /// Remembers which blocks critical_time_step(gridpoints) leaves out (fully prescribed, while a
  /// free block has a stiffness), for check_step_bound. The solver calls it when it sets dt.
  void record_step_bound(const node_set& gridpoints);
  /// Throws invalid_input when a block left out of the step in use (record_step_bound) is no
  /// longer fully prescribed: that step does not bound it. The solver calls it before each step
  /// (O(gridpoints of the blocks left out), nothing when none was).
  void check_step_bound(const node_set& gridpoints) const;

  /// Multiplies m and I of every block whose bound is below target_dt by the smallest common
  /// factor that makes safety x its bound reach target_dt; updates the gridpoints' shared masses.
  /// The report counts blocks in `scaled_nodes`.
  integrator::mass_scaling_report scale_masses(node_set& gridpoints, real target_dt, real safety = integrator::default_safety,
                                               real amplification = 1);

  // ---- gravity ----

  /// Acceleration of gravity g (m/s^2, world): each block gets its weight m0 g at the centroid
  /// (m0 its unscaled mass). Throws invalid_input for a non-finite vector.
  void set_gravity(const vec3& g);
  [[nodiscard]] const vec3& gravity() const { return gravity_; }  ///< Acceleration of gravity (m/s^2)
  /// Power of the weights at the half-step velocities, sum_b m0_b g . v_b (W); the solver
  /// multiplies it by dt for the work of gravity over the step.
  [[nodiscard]] real gravity_power(const node_set& /*gridpoints*/) const {
    real p = 0;
    for (const body& bd : bodies_) p += bd.weight_mass * gravity_.dot(bd.velocity);
    return p;
  }
  /// The same over the listed blocks, in their order (W): a rank's share in a split run.
  [[nodiscard]] real gravity_power(std::span<const index_t> blocks) const {
    real p = 0;
    for (const index_t b : blocks) p += at(b).weight_mass * gravity_.dot(at(b).velocity);
    return p;
  }
  /// Unscaled mass m0 of block b (kg), the mass its weight is computed from.
  [[nodiscard]] real weight_mass(index_t b) const { return at(b).weight_mass; }

  // ---- initial conditions ----

  /// Sets the centroid velocity v (m/s) and the angular velocity omega (rad/s, world frame) of
  /// block b as the half-step velocities of the next step, and the gridpoint velocities to the
  /// rigid field v + omega x (x_i - c). Throws invalid_input for a bad block id or a non-finite vector.
  void set_velocity(index_t b, const vec3& v, const vec3& omega, node_set& gridpoints);

  // ---- state of block b ----

  [[nodiscard]] real mass(index_t b) const { return at(b).mass; }                       ///< m (kg, scaled)
  [[nodiscard]] const vec3& principal_moments(index_t b) const { return at(b).inertia; } ///< I1 <= I2 <= I3 (kg m^2, scaled)
  /// Principal axes E (columns) in the reference configuration.
  [[nodiscard]] const mat3& principal_axes(index_t b) const { return at(b).axes; }
  /// Inertia tensor about the centroid in the current orientation, R diag(I) R^T (kg m^2).
  [[nodiscard]] mat3 inertia(index_t b) const;
  [[nodiscard]] const vec3& reference_centroid(index_t b) const { return at(b).centroid; }  ///< c (m)
  [[nodiscard]] vec3 centroid(index_t b) const { return at(b).centroid + at(b).displacement; }  ///< c + u_c (m)
  [[nodiscard]] const vec3& displacement(index_t b) const { return at(b).displacement; }  ///< u_c (m)
  [[nodiscard]] const vec3& velocity(index_t b) const { return at(b).velocity; }  ///< v (m/s), half step
  /// Angular velocity (rad/s) in the body principal frame, half step.
  [[nodiscard]] const vec3& body_angular_velocity(index_t b) const { return at(b).angular_velocity; }
  /// Angular velocity (rad/s) in the world frame, R(q_half) w, half step.
  [[nodiscard]] vec3 angular_velocity(index_t b) const;
  /// Angular momentum about the centroid (kg m^2/s, world) at the half step: R(q_half) I w, with
  /// q_half the orientation halfway through the last step's rotation.
  [[nodiscard]] vec3 angular_momentum(index_t b) const;
  /// Orientation q (body principal frame -> world), full step.
  [[nodiscard]] const Eigen::Quaterniond& orientation(index_t b) const { return at(b).orientation; }
  /// Rotation of the block since the reference configuration, R(q) E^T.
  [[nodiscard]] mat3 rotation(index_t b) const { return at(b).rotation * at(b).axes.transpose(); }
  [[nodiscard]] const vec3& force(index_t b) const { return at(b).force; }    ///< F of the last step (N)
  [[nodiscard]] const vec3& moment(index_t b) const { return at(b).moment; }  ///< M about c, last step (N m, world)
  /// True when a gridpoint of block b prescribed world translation component c in the last step.
  [[nodiscard]] bool translation_prescribed(index_t b, int c) const {
    return constraints_[static_cast<std::size_t>(b)].count[static_cast<std::size_t>(c)] > 0;
  }
  /// Support reaction on the block, last step (N, world); zero in unprescribed components.
  [[nodiscard]] const vec3& reaction_force(index_t b) const { return at(b).reaction_force; }
  /// Support moment about the centroid holding a constrained block's rotation, last step (N m, world).
  [[nodiscard]] const vec3& reaction_moment(index_t b) const { return at(b).reaction_moment; }
  /// Body coordinates r_i = E^T (X_i - c) of gridpoint i (m).
  [[nodiscard]] vec3 body_position(index_t i) const { return body_position_.row(i).transpose(); }
  [[nodiscard]] index_t gridpoint_block(index_t i) const { return gridpoint_block_[static_cast<std::size_t>(i)]; }  ///< The block of gridpoint i
  /// The block materials, by material id.
  [[nodiscard]] std::span<const params> materials() const { return materials_; }

 private:
  using body = detail::rigid_body;
  using block_constraints = detail::rigid_constraints;

  [[nodiscard]] const body& at(index_t b) const {
    require(b >= 0 && b < block_count(), "rigid blocks: block ", b, " does not exist (", block_count(), " blocks)");
    return bodies_[static_cast<std::size_t>(b)];
  }

  void share_masses(node_set& gridpoints) const;

  std::vector<params> materials_;
  vec3 gravity_ = vec3::Zero();                 ///< acceleration of gravity (m/s^2)
  std::vector<body> bodies_;
  std::vector<block_constraints> constraints_;  ///< per block, rebuilt every step
  std::vector<integrator::step_work> work_;     ///< per block energy increments of the step (summed in block order)
  std::vector<index_t> unbounded_;              ///< blocks left out of the step in use (record_step_bound)
  std::vector<index_t> gridpoint_block_;
  soa3 body_position_;                          ///< r_i in the body principal frame (m)
  zone_stress_matrix zone_stress_;              ///< empty
};

static_assert(BlockModel<rigid>);

}  // namespace tessera::blocks

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/rigid.ipp"
#endif
