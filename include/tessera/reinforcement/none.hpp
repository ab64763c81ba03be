#pragma once
// reinforcement::none — the policy of a scene without bars (plain concrete). `enabled` is false,
// so a solver guards every reinforcement call with `if constexpr (R::enabled)` and none of this
// is compiled into the time step; the members exist only so generic code type-checks. Its node
// set is empty.

#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "concepts.hpp"

namespace tessera::reinforcement {

/// No reinforcement: nothing built, nothing stepped, no energy
class none {
 public:
  /// No parameters.
  struct params {};
  static constexpr bool enabled = false;  ///< no bars

  void build(const params&, const geometry::block_mesh&, const node_set&) {}  ///< Nothing to build
  [[nodiscard]] node_set& nodes() { return nodes_; }  ///< No nodes
  [[nodiscard]] const node_set& nodes() const { return nodes_; }  ///< No nodes
  void add_stiffness_bounds(node_set&) {}  ///< Nothing to add
  void accumulate_forces(node_set&, const zone_stress_matrix&) noexcept {}  ///< No forces
  [[nodiscard]] real stored_energy() const { return 0.0; }  ///< 0
  [[nodiscard]] real dissipated_energy() const { return 0.0; }  ///< 0
  /// Nothing to save (io/checkpoint.hpp).
  template <class Archive>
  void checkpoint(Archive&) {}

 private:
  node_set nodes_;  ///< always empty
};

static_assert(Reinforcement<none>, "reinforcement::none must satisfy the Reinforcement concept");

}  // namespace tessera::reinforcement
