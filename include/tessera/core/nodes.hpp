#pragma once
// Structure-of-arrays kinematic state of a set of 3-DOF nodes: the gridpoints of the blocks
// or the nodes of the reinforcement bars. Everything that moves in tessera moves through a
// node_set, so contacts, bonds, boundary conditions, recorders and the integrator work on one
// representation.
//
// Layout: each soa3 is an N x 3 column-major Eigen matrix, so column c holds component c of
// every node contiguously (x of all nodes, then y, then z).
//
// Precision: the current position is reference + displacement; the displacement is kept on its
// own so relative displacements across a contact (where the reference positions coincide) are
// computed without cancellation against the absolute coordinates.

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "hash.hpp"
#include "types.hpp"

namespace tessera {

using soa3 = Eigen::Matrix<real, Eigen::Dynamic, 3, Eigen::ColMajor>;

/// Cauchy stress of every zone of a block_mesh, one row per zone, Voigt order
/// (xx, yy, zz, yz, zx, xy), Pa, tension positive. Empty for rigid blocks (no zone stress).
using zone_stress_matrix = Eigen::Matrix<real, Eigen::Dynamic, 6>;

/// Per-component boundary-condition flags of a node.
enum class dof_constraint : std::uint8_t {
  free = 0,        ///< integrated from its force
  prescribed = 1,  ///< velocity prescribed (0 = fixed); its reaction is recorded in `reaction`
};

/// A set of nodes (gridpoints or bar nodes) as structure-of-arrays columns: positions, motion, forces, masses, constraints and reactions
struct node_set {
  soa3 reference;     ///< reference position X (m)
  soa3 displacement;  ///< total displacement u (m); current position = X + u
  soa3 velocity;      ///< velocity at the half step t - dt/2 (m/s)
  soa3 force;         ///< unbalanced force accumulated during the current step (N)
  soa3 reaction;      ///< force needed to enforce prescribed components, last step (N)
  Eigen::VectorXd mass;            ///< lumped (possibly scaled) mass (kg)
  Eigen::VectorXd stiffness;       ///< nodal stiffness bound for the time step (N/m), see integrator/timestep.hpp
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 3> constraint;  ///< dof_constraint per component
  soa3 prescribed_velocity;        ///< used where constraint == prescribed (m/s)

  [[nodiscard]] index_t size() const { return static_cast<index_t>(reference.rows()); }  ///< Number of nodes
  [[nodiscard]] vec3 position(index_t i) const { return (reference.row(i) + displacement.row(i)).transpose(); }  ///< Current position X + u of node i (m)

  /// Allocates every array for n nodes, zero-initialised and unconstrained.
  void resize(index_t n) {
    reference.setZero(n, 3);
    displacement.setZero(n, 3);
    velocity.setZero(n, 3);
    force.setZero(n, 3);
    reaction.setZero(n, 3);
    mass.setZero(n);
    stiffness.setZero(n);
    constraint.setZero(n, 3);
    prescribed_velocity.setZero(n, 3);
  }

  /// Saves or loads the evolving arrays through a checkpoint archive (io/checkpoint.hpp), under
  /// the names "<prefix>/...": displacement, velocity, reaction, mass (as scaled), constraint
  /// flags and prescribed velocities. The count and a fingerprint of the reference positions
  /// must match (a checkpoint of another tessellation is refused); force and stiffness are not
  /// stored (force is rebuilt every step, stiffness when the model is built).
  template <class Archive>
  void checkpoint(Archive& ar, const std::string& prefix) {
    ar.same(prefix + "/count", static_cast<std::int64_t>(size()));
    fnv1a fingerprint;
    fingerprint.add(reference.data(), static_cast<std::size_t>(reference.size()) * sizeof(real));
    ar.same(prefix + "/reference_fingerprint", static_cast<std::int64_t>(fingerprint.value));
    ar.matrix(prefix + "/displacement", displacement);
    ar.matrix(prefix + "/velocity", velocity);
    ar.matrix(prefix + "/reaction", reaction);
    ar.matrix(prefix + "/mass", mass);
    ar.matrix(prefix + "/constraint", constraint);
    ar.matrix(prefix + "/prescribed_velocity", prescribed_velocity);
  }
};

}  // namespace tessera
