#pragma once
// The RC beam's supports and loading without plates of their own (--plates tied, beam.hpp): the
// gridpoints under a plate (beam_strip) moved as one rigid plate hinged at its axis (hinged_plate).

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rc_beam/beam.hpp"

namespace tessera::scenes {

/// Gridpoints within [x0, x1] on the plane y = value.
[[nodiscard]] inline bc::node_group beam_strip(const node_set& gp, real y, real x0, real x1, real tol,
                                               const std::string& name) {
  bc::node_group g;
  g.name = name;
  for (index_t i = 0; i < gp.size(); ++i) {
    const real x = gp.reference(i, 0);
    if (std::abs(gp.reference(i, 1) - y) <= tol && x >= x0 - tol && x <= x1 + tol) g.nodes.push_back(i);
  }
  return g;
}

/// A rigid plate on a hinge: the gridpoints under it move as one rigid plate that translates at a
/// prescribed vertical velocity v_0 at its axis and turns freely about it (a roller bearing).
/// Each step, before the update, the plate's rotation rate omega (v_y = v_0 + omega (x - x_c)) is
/// advanced from the moment the concrete exerts on the plate, recovered from the last step's
/// reactions (R = m dv/dt - F, central_difference.hpp), with the plate's inertia I = sum m_i
/// (x_i - x_c)^2 (the gridpoints' own, mass-scaled, masses) and local damping, like any other
/// degree of freedom. Without it the tied gridpoints of a 50 mm plate clamp the beam's rotation
/// at the support and under the load (measured: the quick beam 5.4x stiffer than the hand value).
class hinged_plate {
 public:
  hinged_plate(const node_set& gp, bc::node_group group, real axis) : group_(std::move(group)) {
    for (index_t n : group_.nodes) {
      arm_.push_back(gp.reference(n, 0) - axis);
      inertia_ += gp.mass(n) * arm_.back() * arm_.back();
    }
    v_last_.assign(arm_.size(), 0);
  }
  [[nodiscard]] const bc::node_group& group() const { return group_; }
  /// Sets the next step's velocities; call before each step with the axis velocity v0.
  void drive(node_set& gp, real v0, real dt, real gamma) {
    if (inertia_ > 0 && dt > 0) {
      real moment = 0;  // on the plate from the concrete, about the axis
      for (std::size_t k = 0; k < arm_.size(); ++k) {
        const index_t n = group_.nodes[k];
        const real internal = gp.mass(n) * (gp.prescribed_velocity(n, 1) - v_last_[k]) / dt - gp.reaction(n, 1);
        moment += internal * arm_[k];
      }
      const real sign = omega_ > 0 ? 1.0 : (omega_ < 0 ? -1.0 : 0.0);
      omega_ += dt * (moment - gamma * std::abs(moment) * sign) / inertia_;
    }
    for (std::size_t k = 0; k < arm_.size(); ++k) {
      const index_t n = group_.nodes[k];
      v_last_[k] = gp.prescribed_velocity(n, 1);
      gp.prescribed_velocity(n, 1) = v0 + omega_ * arm_[k];
    }
  }
  [[nodiscard]] real rotation_rate() const { return omega_; }
  /// Stops the plate's turn (a relaxation's reset).
  void stop() { omega_ = 0; }
  /// Saves or loads the plate's motion (io/checkpoint.hpp) under "<prefix>/...".
  template <class Archive>
  void checkpoint(Archive& ar, const std::string& prefix) {
    ar.same(prefix + "/gridpoints", static_cast<std::int64_t>(arm_.size()));
    ar.same(prefix + "/inertia", inertia_);
    ar.array(prefix + "/last_velocity", v_last_);
    ar.scalar(prefix + "/rotation_rate", omega_);
  }

 private:
  bc::node_group group_;
  std::vector<real> arm_, v_last_;
  real inertia_ = 0, omega_ = 0;
};

/// The gridpoints the plates' update reads between steps, side by side: those under each steel
/// plate (contact::rigid_platen, where built) or each tied plate's strip. A run split over MPI
/// ranks keeps their rows current on every rank (common/mpi_run.hpp run_sampled).
template <class Platen>
[[nodiscard]] std::vector<index_t> beam_plate_rows(int sides, const std::array<std::optional<Platen>, 2>& support_platen,
                                                   const std::array<std::optional<Platen>, 2>& loading_platen,
                                                   const std::array<bc::node_group, 2>& support,
                                                   const std::array<bc::node_group, 2>& plate) {
  std::vector<index_t> rows;
  for (int k = 0; k < sides; ++k) {
    if (support_platen[k] && loading_platen[k]) {
      for (const Platen* p : {&*support_platen[k], &*loading_platen[k]})
        for (std::size_t j = 0; j < p->size(); ++j) rows.push_back(p->node(j));
    } else {
      for (const bc::node_group* g : {&support[k], &plate[k]}) rows.insert(rows.end(), g->nodes.begin(), g->nodes.end());
    }
  }
  return rows;
}

}  // namespace tessera::scenes
