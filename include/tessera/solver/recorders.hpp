#pragma once
// Recorders: Odeint-style observers of a running solver, and the measurements they take.
// solver::run(n, observers...) calls every observer as observer(solver) after each step;
// recorders::every(k, f) calls f only every k steps (one integer test per step, so a recorder
// never slows the loop), and the measurements below are O(group size) when they run.

#include <utility>

#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "boundary.hpp"

namespace tessera::recorders {

/// Sum of the reactions (N) of a group: the force the supports exert on those nodes.
[[nodiscard]] inline vec3 reaction_sum(const node_set& nodes, const bc::node_group& group) {
  vec3 s = vec3::Zero();
  for (index_t i : group.nodes) s += nodes.reaction.row(i).transpose();
  return s;
}

/// Mean displacement (m) of a group.
[[nodiscard]] inline vec3 mean_displacement(const node_set& nodes, const bc::node_group& group) {
  vec3 s = vec3::Zero();
  for (index_t i : group.nodes) s += nodes.displacement.row(i).transpose();
  return group.empty() ? s : vec3(s / static_cast<real>(group.size()));
}

/// Observer adaptor: calls f(solver) when the solver's step count is a multiple of `interval`.
template <class F>
class every {
 public:
  every(index_t interval, F f) : interval_(interval < 1 ? 1 : interval), f_(std::move(f)) {}
  template <class Solver>
  void operator()(const Solver& s) {
    if (s.step_count() % interval_ == 0) f_(s);
  }

 private:
  index_t interval_;
  F f_;
};

}  // namespace tessera::recorders
