#pragma once
// Supports, velocities and selections of a solver, on gridpoints and by block: the part of the
// solver's interface a scene calls to hold, drive and pick its blocks (s.fix_block(b),
// s.blocks_on_plane(2, 0.0, 1e-6), s.prescribe_block_velocity(b, v), ...). solver<...> derives
// from solver_supports<solver<...>> (CRTP), so these are members of the solver as a user sees
// them; they reach the gridpoints, the blocks and the mesh's block-to-gridpoint map through the
// derived class, which names this base its friend, and after a support call tell it that the
// supports changed (rigid blocks choose the time step again before the first step:
// solver/time_step.hpp).
//
// A block is held through its gridpoints, so the reactions land where recorders::reaction_sum
// reads them: on rigid blocks a prescribed component on any gridpoint prescribes the block's
// translation component and holds its rotation (blocks/rigid.hpp), and the block's reaction is
// shared among the gridpoints that prescribe it; on deformable blocks every gridpoint is held.
// Every function below refuses a bad block id or a non-finite value before changing anything.
//
// Cost: O(gridpoints of the blocks concerned) per call (a selection by plane: O(gridpoints));
// meant for setting up a scene, not for every step. Thread safety: as the solver (one thread).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "boundary.hpp"

namespace tessera {

/// The supports-by-block part of solver<...> (file comment). Solver is the derived solver type.
template <class Solver>
class solver_supports {
 public:
  // ---- boundary conditions on the gridpoints (bar nodes: use bc:: on bar_nodes()) ----
  /// Gridpoints on the plane X[axis] = value (reference configuration, tolerance tol m).
  [[nodiscard]] bc::node_group gridpoints_on_plane(int axis, real value, real tol) const {
    return bc::nodes_on_plane(self().gridpoints_, axis, value, tol);
  }
  /// Fixes components c of the gridpoints of g (bc::fix); rigid blocks: chooses the step again
  /// before the first step (solver/time_step.hpp).
  void fix(const bc::node_group& g, bc::components c = bc::components::xyz) {
    bc::fix(self().gridpoints_, g, c);
    self().supports_changed();
  }
  /// Prescribes velocity v (m/s) on components c of the gridpoints of g (bc::prescribe_velocity);
  /// rigid blocks: chooses the step again before the first step (solver/time_step.hpp).
  void prescribe_velocity(const bc::node_group& g, const vec3& v, bc::components c = bc::components::xyz) {
    bc::prescribe_velocity(self().gridpoints_, g, v, c);
    self().supports_changed();
  }

  // ---- supports, velocities and selections by block (rigid and deformable blocks) ----
  /// Number of blocks.
  [[nodiscard]] index_t block_count() const { return self().blocks_.block_count(); }
  /// All gridpoints of block b (node group named "block b"). Throws invalid_input for a bad id.
  [[nodiscard]] bc::node_group gridpoints_of_block(index_t b) const {
    require_block(b, "gridpoints_of_block");
    bc::node_group g{{}, detail::concat("block ", b)};
    for (index_t i = block_first(b); i < block_end(b); ++i) g.nodes.push_back(i);
    return g;
  }
  /// All gridpoints of the listed blocks (increasing; a block listed twice counts once). Throws
  /// invalid_input for an empty list or a bad id.
  [[nodiscard]] bc::node_group gridpoints_of_blocks(const std::vector<index_t>& list) const {
    require(!list.empty(), "solver: gridpoints_of_blocks got an empty block list");
    for (index_t b : list) require_block(b, "gridpoints_of_blocks");
    std::vector<index_t> sorted = list;
    std::sort(sorted.begin(), sorted.end());
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    bc::node_group g{{}, detail::concat(sorted.size(), " blocks (", sorted.front(), " ... ", sorted.back(), ")")};
    for (index_t b : sorted)
      for (index_t i = block_first(b); i < block_end(b); ++i) g.nodes.push_back(i);
    return g;
  }
  /// Blocks whose REFERENCE geometry reaches the plane X[axis] = value (m) within tol (m): the
  /// extent [min, max] of the block's gridpoints along axis meets [value - tol, value + tol] (a
  /// face, edge or vertex on the plane, or the block cut by it). Increasing ids. Throws
  /// invalid_input for a bad axis, a non-finite value, a negative tol or an empty selection.
  [[nodiscard]] std::vector<index_t> blocks_on_plane(int axis, real value, real tol) const {
    require_plane(axis, value, tol, "blocks_on_plane");
    std::vector<index_t> out;
    for (index_t b = 0; b < block_count(); ++b) {
      const auto [lo, hi] = block_extent(b, axis);
      if (lo - tol <= value && value <= hi + tol) out.push_back(b);
    }
    require(!out.empty(), "solver: blocks_on_plane selects no block: none of the ", block_count(),
            " blocks reaches the plane ", "xyz"[axis], " = ", value, " m (tol ", tol, " m)");
    return out;
  }
  /// Blocks whose REFERENCE geometry lies wholly at X[axis] <= value + tol (m). Increasing ids.
  /// Throws invalid_input for a bad axis, a non-finite value, a negative tol or an empty selection.
  [[nodiscard]] std::vector<index_t> blocks_below(int axis, real value, real tol = 0) const {
    require_plane(axis, value, tol, "blocks_below");
    std::vector<index_t> out;
    for (index_t b = 0; b < block_count(); ++b)
      if (block_extent(b, axis).second <= value + tol) out.push_back(b);
    require(!out.empty(), "solver: blocks_below selects no block: none of the ", block_count(), " blocks lies below ",
            "xyz"[axis], " = ", value, " m (tol ", tol, " m)");
    return out;
  }

  /// Holds block b: zero velocity in all three components on every gridpoint of the block (rigid:
  /// translations and rotations held; deformable: every gridpoint fixed). The support's force on
  /// the block is recorders::reaction_sum(gridpoints(), gridpoints_of_block(b)) (N). Throws
  /// invalid_input for a bad id or a component already prescribed with another velocity.
  void fix_block(index_t b) {
    require_block(b, "fix_block");  // named here, not as the prescribe_block_velocity it calls
    prescribe_block_velocity(b, vec3::Zero(), bc::components::xyz);
  }
  /// fix_block for each listed block, all or none (validated first).
  void fix_blocks(const std::vector<index_t>& list) {
    bc::fix(self().gridpoints_, gridpoints_of_blocks(list));
    self().supports_changed();
  }
  /// Prescribes the translation velocity v (m/s, world) on components c of block b, on every
  /// gridpoint of it: a rigid block translates at v in those components and its rotations are held
  /// (free components stay free); a deformable block's gridpoints all move at v in them. Throws
  /// invalid_input for a bad id, a non-finite v, or a component already prescribed otherwise (to
  /// change a prescribed velocity over time: update_block_velocity). Under gravity, a block driven
  /// in some components that carries another block and rests on none is refused at the first step
  /// (solver/detail/first_step_checks.hpp): prescribe its free components too.
  void prescribe_block_velocity(index_t b, const vec3& v, bc::components c = bc::components::xyz) {
    require_block(b, "prescribe_block_velocity");
    require(v.allFinite(), "solver: prescribe_block_velocity: velocity (", v.transpose(), ") m/s of block ", b,
            " is not finite");
    bc::prescribe_velocity(self().gridpoints_, gridpoints_of_block(b), v, c);
    self().supports_changed();
  }
  /// Changes the velocity (m/s, world) of block b's components c, which must be prescribed already
  /// (prescribe_block_velocity, fix_block): a loading history, e.g. a ramp or a cycle, called
  /// between steps (bc::update_velocity on every gridpoint of the block). Throws invalid_input for
  /// a bad id, a non-finite v, or a component of c not prescribed.
  void update_block_velocity(index_t b, const vec3& v, bc::components c = bc::components::xyz) {
    require_block(b, "update_block_velocity");
    require(v.allFinite(), "solver: update_block_velocity: velocity (", v.transpose(), ") m/s of block ", b,
            " is not finite");
    bc::update_velocity(self().gridpoints_, gridpoints_of_block(b), v, c);
  }
  /// Initial condition: gives block b the rigid velocity field v + omega x (x - c) (v in m/s at
  /// the centroid c, omega in rad/s, world; x the current positions), as the half-step velocities
  /// of the next step. Rigid blocks: blocks::rigid::set_velocity. Deformable blocks: every gridpoint
  /// of the block, c the mass-weighted mean of their current positions (unscaled masses).
  /// Prescribed components are overwritten by their prescription at the next step. Throws
  /// invalid_input for a bad id or a non-finite vector.
  void set_block_velocity(index_t b, const vec3& v, const vec3& omega = vec3::Zero()) {
    require_block(b, "set_block_velocity");
    require(v.allFinite() && omega.allFinite(), "solver: set_block_velocity: velocity (", v.transpose(),
            ") m/s or angular velocity (", omega.transpose(), ") rad/s of block ", b, " is not finite");
    Solver& s = self();
    if constexpr (Solver::blocks_type::is_rigid) {
      s.blocks_.set_velocity(b, v, omega, s.gridpoints_);
    } else {
      vec3 c = vec3::Zero();
      real m = 0;
      for (index_t i = block_first(b); i < block_end(b); ++i) {
        c += s.weight_mass_[i] * current_position(i);
        m += s.weight_mass_[i];
      }
      c /= m;
      for (index_t i = block_first(b); i < block_end(b); ++i)
        s.gridpoints_.velocity.row(i) = (v + omega.cross(current_position(i) - c)).transpose();
    }
  }
  /// Displacement of block b (m): rigid, its centroid's u_c; deformable, the mass-weighted mean of
  /// its gridpoints' displacements (unscaled masses, so mass scaling does not move it).
  [[nodiscard]] vec3 block_displacement(index_t b) const {
    require_block(b, "block_displacement");
    if constexpr (Solver::blocks_type::is_rigid)
      return self().blocks_.displacement(b);
    else
      return block_mean(b, self().gridpoints_.displacement);
  }
  /// Rotation of block b since the reference configuration as a rotation vector (rad, world
  /// frame: the axis times the angle in [0, pi]): rigid, the body's rotation; deformable, the
  /// polar factor of the block's deformation gradient F_b now (blocks::deformable::current_rotation,
  /// the rotation its zones' corotational forces use; a rigid motion of the block gives its rotation
  /// to round-off).
  [[nodiscard]] vec3 block_rotation(index_t b) const {
    require_block(b, "block_rotation");
    const Eigen::AngleAxis<real> turn = [&] {
      if constexpr (Solver::blocks_type::is_rigid)
        return Eigen::AngleAxis<real>(self().blocks_.rotation(b));
      else
        return Eigen::AngleAxis<real>(self().blocks_.current_rotation(self().gridpoints_, b));
    }();
    return turn.angle() * turn.axis();
  }
  /// Velocity of block b (m/s, half step): rigid, its centroid's v; deformable, the mass-weighted
  /// mean of its gridpoints' velocities (momentum over mass, unscaled masses).
  [[nodiscard]] vec3 block_velocity(index_t b) const {
    require_block(b, "block_velocity");
    if constexpr (Solver::blocks_type::is_rigid)
      return self().blocks_.velocity(b);
    else
      return block_mean(b, self().gridpoints_.velocity);
  }

 protected:
  solver_supports() = default;  // only as the base of a solver

 private:
  [[nodiscard]] Solver& self() { return static_cast<Solver&>(*this); }
  [[nodiscard]] const Solver& self() const { return static_cast<const Solver&>(*this); }

  // ---- blocks' gridpoints (block b owns gridpoints [block_first(b), block_end(b)), mesh CSR) ----
  void require_block(index_t b, const char* what) const {
    require(b >= 0 && b < block_count(), "solver: ", what, ": block ", b, " does not exist (", block_count(), " blocks)");
  }
  [[nodiscard]] index_t block_first(index_t b) const {
    return self().block_gridpoint_offsets_[static_cast<std::size_t>(b)];
  }
  [[nodiscard]] index_t block_end(index_t b) const {
    return self().block_gridpoint_offsets_[static_cast<std::size_t>(b) + 1];
  }
  static void require_plane(int axis, real value, real tol, const char* what) {
    require(axis >= 0 && axis < 3, "solver: ", what, ": axis = ", axis, " must be 0 (x), 1 (y) or 2 (z)");
    require(std::isfinite(value), "solver: ", what, ": plane position ", value, " m is not finite");
    require(std::isfinite(tol) && tol >= 0, "solver: ", what, ": tolerance ", tol, " m must be finite and >= 0");
  }
  /// Smallest and largest reference coordinate along axis of block b's gridpoints (m).
  [[nodiscard]] std::pair<real, real> block_extent(index_t b, int axis) const {
    const node_set& gridpoints = self().gridpoints_;
    real lo = std::numeric_limits<real>::infinity(), hi = -lo;
    for (index_t i = block_first(b); i < block_end(b); ++i) {
      lo = std::min(lo, gridpoints.reference(i, axis));
      hi = std::max(hi, gridpoints.reference(i, axis));
    }
    return {lo, hi};
  }
  [[nodiscard]] vec3 current_position(index_t i) const {
    const node_set& gridpoints = self().gridpoints_;
    return (gridpoints.reference.row(i) + gridpoints.displacement.row(i)).transpose();
  }
  /// Mass-weighted mean (unscaled masses) of rows of `field` over block b's gridpoints (deformable).
  [[nodiscard]] vec3 block_mean(index_t b, const soa3& field) const {
    const auto& weight_mass = self().weight_mass_;
    vec3 sum = vec3::Zero();
    real m = 0;
    for (index_t i = block_first(b); i < block_end(b); ++i) {
      sum += weight_mass[i] * field.row(i).transpose();
      m += weight_mass[i];
    }
    return sum / m;
  }
};

}  // namespace tessera
