#pragma once
// Boundary conditions on node sets: groups of nodes selected by geometry, and prescribed
// velocities (0 = fixed) per Cartesian component. A roller is a group with only its normal (or
// transverse) components prescribed. Prescriptions are data in the node_set (constraint and
// prescribed_velocity), so the integrator applies them and records the reactions (N, the force
// the support exerts on the node) in node_set::reaction at every step.
//
// On rigid blocks (blocks::rigid) a prescription on any gridpoint of a block acts on the whole
// block: its translation component gets that velocity and its rotation is held (see rigid.hpp).
// Supports by block, for rigid and deformable blocks alike, are the solver's: fix_block(s),
// prescribe_block_velocity, blocks_on_plane, blocks_below, gridpoints_of_block(s) (solver.hpp).
//
// Errors: an empty group throws invalid_input naming the selection; prescribing a component
// that is already prescribed with a different velocity throws invalid_input naming the node,
// the component and both values (update_velocity changes a prescribed velocity, e.g. along a
// loading history; release() frees the component).

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"

namespace tessera::bc {

/// Set of Cartesian components as bit flags.
enum class components : std::uint8_t { none = 0, x = 1, y = 2, z = 4, xy = 3, xz = 5, yz = 6, xyz = 7 };
[[nodiscard]] constexpr components operator|(components a, components b) {
  return static_cast<components>(static_cast<std::uint8_t>(a) | static_cast<std::uint8_t>(b));
}
[[nodiscard]] constexpr bool has(components set, int c) { return (static_cast<std::uint8_t>(set) >> c) & 1u; }
/// The two components transverse to axis (0, 1, 2), e.g. for rollers on a plane normal to it.
[[nodiscard]] constexpr components transverse_to(int axis) {
  return static_cast<components>(7u & ~(1u << axis));
}
/// The single component of an axis (0, 1, 2).
[[nodiscard]] constexpr components along(int axis) { return static_cast<components>(1u << axis); }

/// Indices of nodes of one node_set (increasing), with a name used in messages.
struct node_group {
  std::vector<index_t> nodes;  ///< node indices, increasing
  std::string name;  ///< the selection's name, used in messages
  [[nodiscard]] index_t size() const { return static_cast<index_t>(nodes.size()); }  ///< Number of nodes
  [[nodiscard]] bool empty() const { return nodes.empty(); }  ///< True when no node is selected
};

/// Nodes whose REFERENCE position satisfies predicate(vec3 X). Throws invalid_input when none does.
template <class Predicate>
[[nodiscard]] node_group nodes_where(const node_set& nodes, Predicate&& predicate, std::string name = "nodes_where") {
  node_group g{{}, std::move(name)};
  for (index_t i = 0; i < nodes.size(); ++i)
    if (predicate(vec3(nodes.reference.row(i).transpose()))) g.nodes.push_back(i);
  require(!g.empty(), "node group '", g.name, "' selects no node of the ", nodes.size(), "-node set");
  return g;
}

/// Nodes with |X[axis] - value| <= tol (m). Throws invalid_input when none lies on the plane.
[[nodiscard]] inline node_group nodes_on_plane(const node_set& nodes, int axis, real value, real tol) {
  require(axis >= 0 && axis < 3, "nodes_on_plane: axis = ", axis, " must be 0 (x), 1 (y) or 2 (z)");
  require_non_negative(tol, "nodes_on_plane: tolerance (m)");
  return nodes_where(
      nodes, [&](const vec3& x) { return std::abs(x[axis] - value) <= tol; },
      detail::concat("plane ", "xyz"[axis], " = ", value, " m (tol ", tol, " m)"));
}

/// Every node of the set.
[[nodiscard]] inline node_group all_nodes(const node_set& nodes) {
  return nodes_where(nodes, [](const vec3&) { return true; }, "all nodes");
}

/// Prescribes velocity v (m/s) on the selected components of every node of the group.
TESSERA_INLINE void prescribe_velocity(node_set& nodes, const node_group& group, const vec3& v,
                                       components which = components::xyz);

/// Changes the velocity (m/s) of components that are already prescribed (a loading history, e.g.
/// a ramp): no conflict check, but every selected component must be prescribed already. Throws
/// invalid_input for a non-finite v or a component that is not prescribed.
inline void update_velocity(node_set& nodes, const node_group& group, const vec3& v,
                            components which = components::xyz) {
  require(v.allFinite(), "update_velocity on node group '", group.name, "': velocity (", v.transpose(),
          ") m/s is not finite");
  constexpr auto prescribed = static_cast<std::uint8_t>(dof_constraint::prescribed);
  for (index_t i : group.nodes)
    for (int c = 0; c < 3; ++c) {
      if (!has(which, c)) continue;
      require(nodes.constraint(i, c) == prescribed, "update_velocity on node group '", group.name, "': node ", i,
              " component ", "xyz"[c], " is not prescribed; use prescribe_velocity first");
      nodes.prescribed_velocity(i, c) = v[c];
    }
}

/// Fixes (zero velocity) the selected components of the group.
inline void fix(node_set& nodes, const node_group& group, components which = components::xyz) {
  prescribe_velocity(nodes, group, vec3::Zero(), which);
}

/// Frees the selected components of the group (their reactions are reset to 0).
inline void release(node_set& nodes, const node_group& group, components which = components::xyz) {
  for (index_t i : group.nodes)
    for (int c = 0; c < 3; ++c) {
      if (!has(which, c)) continue;
      nodes.constraint(i, c) = static_cast<std::uint8_t>(dof_constraint::free);
      nodes.prescribed_velocity(i, c) = 0;
      nodes.reaction(i, c) = 0;
    }
}

}  // namespace tessera::bc

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/boundary.ipp"
#endif
