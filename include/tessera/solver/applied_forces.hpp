#pragma once
// Forces from outside the model on the gridpoints of deformable blocks (a contact::rigid_platen,
// a point load): their registration with the stiffness of whatever applies them, the rows the
// caller writes between steps, and their work. solver<...> derives from
// solver_applied_forces<solver<...>> (CRTP), so s.register_applied_forces(...) and
// s.applied_forces() are members of the solver as a user sees them; the list, the forces and the
// booked work are the solver's state (it names this base its friend), which its step reads.
//
// The work of a step is booked by the trapezoidal rule, (F(t - dt) + F(t)) / 2 . v(t - dt/2) dt,
// once the step's closing forces F(t) are written (applied_work_of_step): exact for a linear
// spring, where a one-sided rule gains 1/2 k du^2 per step (1.7 % of a platen's work on a column
// that springs back, test "rigid platen").
//
// Cost: registration O(gridpoints + registered log registered) and a new time step (solver::
// compute_time_step); the work O(registered gridpoints). Thread safety: as the solver (one thread).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"

namespace tessera {

namespace detail {

/// (F(t - dt) + F(t)) / 2 . v(t - dt/2) dt (J) summed over the applied-force gridpoints `nodes`:
/// the work of the last step, F(t - dt) the forces it applied (`previous`, one row per entry of
/// nodes), F(t) the forces now written (`force`, one row per gridpoint), v the gridpoints'
/// half-step velocities (m/s), dt (s) the step.
[[nodiscard]] inline real applied_work_of_step(const std::vector<index_t>& nodes, const soa3& previous,
                                               const soa3& force, const node_set& gridpoints, real dt) {
  real w = 0;
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    const index_t g = nodes[j];
    for (int c = 0; c < 3; ++c)
      w += 0.5 * (previous(static_cast<index_t>(j), c) + force(g, c)) * gridpoints.velocity(g, c);
  }
  return w * dt;
}

}  // namespace detail

/// The applied-forces part of solver<...> (file comment). Solver is the derived solver type.
template <class Solver>
class solver_applied_forces {
 public:
  /// Registers gridpoints that take forces from outside the model (deformable blocks; a
  /// contact::rigid_platen, a point load), with the stiffness k[j] (N/m, >= 0; 0 for a plain
  /// load) of whatever applies them, which joins the gridpoint's bound: the time step is
  /// recomputed (compute_time_step; with mass scaling the masses are raised where the spring
  /// needs it). Throws invalid_input for an unknown gridpoint or a bad k.
  void register_applied_forces(std::span<const index_t> nodes, std::span<const real> k) {
    static_assert(!Solver::blocks_type::is_rigid, "register_applied_forces: rigid blocks take loads on their bodies");
    Solver& s = static_cast<Solver&>(*this);
    const node_set& gridpoints = s.gridpoints_;
    require(nodes.size() == k.size(), "solver: register_applied_forces got ", nodes.size(), " gridpoints and ",
            k.size(), " stiffnesses");
    if (s.applied_active_) s.applied_work_ += s.applied_work_of_last_step();  // booked before the list changes
    s.applied_active_ = false;
    if (s.applied_stiffness_.size() != gridpoints.size()) s.applied_stiffness_.setZero(gridpoints.size());
    if (s.applied_force_.rows() != gridpoints.size()) s.applied_force_.setZero(gridpoints.size(), 3);
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      require(nodes[j] >= 0 && nodes[j] < gridpoints.size(), "solver: applied force on gridpoint ", nodes[j],
              ", not one of the ", gridpoints.size());
      require(std::isfinite(k[j]) && k[j] >= 0, "solver: applied-force stiffness ", k[j], " N/m on gridpoint ",
              nodes[j], " must be finite and >= 0");
      s.applied_stiffness_[nodes[j]] += k[j];
      s.applied_nodes_.push_back(nodes[j]);
    }
    std::vector<index_t>& applied = s.applied_nodes_;
    std::sort(applied.begin(), applied.end());
    applied.erase(std::unique(applied.begin(), applied.end()), applied.end());
    s.applied_previous_.setZero(static_cast<index_t>(applied.size()), 3);
    for (std::size_t j = 0; j < applied.size(); ++j)
      s.applied_previous_.row(static_cast<index_t>(j)) = s.applied_force_.row(applied[j]);
    s.compute_time_step();
  }
  /// Forces from outside the model (N), one row per gridpoint, of which the rows registered by
  /// register_applied_forces are read (the others stay unread): each step starts from them (with
  /// the weights), so a caller that computes them from the state, such as a
  /// contact::rigid_platen, writes them between steps. Their work enters the energy balance as
  /// energy_balance::applied_work, booked by the trapezoidal rule (file comment).
  [[nodiscard]] soa3& applied_forces() { return static_cast<Solver&>(*this).applied_force_; }
  [[nodiscard]] const soa3& applied_forces() const { return static_cast<const Solver&>(*this).applied_force_; }  ///< The forces written from outside the model per gridpoint (N), those the next step applies
  /// The registered gridpoints, increasing.
  [[nodiscard]] const std::vector<index_t>& applied_nodes() const {
    return static_cast<const Solver&>(*this).applied_nodes_;
  }

 protected:
  solver_applied_forces() = default;  // only as the base of a solver
};

}  // namespace tessera
