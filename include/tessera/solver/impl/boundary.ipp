// The definitions of the larger functions that solver/boundary.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../boundary.hpp"

namespace tessera::bc {

TESSERA_INLINE void prescribe_velocity(node_set& nodes, const node_group& group, const vec3& v,
                                       components which) {
  require(!group.empty(), "boundary condition on node group '", group.name, "': the group is empty");
  require(v.allFinite(), "boundary condition on node group '", group.name, "': velocity (", v.transpose(),
          ") m/s is not finite");
  constexpr auto prescribed = static_cast<std::uint8_t>(dof_constraint::prescribed);
  for (index_t i : group.nodes) {
    require(i >= 0 && i < nodes.size(), "boundary condition on node group '", group.name, "': node ", i,
            " is outside the ", nodes.size(), "-node set");
    for (int c = 0; c < 3; ++c) {
      if (!has(which, c)) continue;
      if (nodes.constraint(i, c) == prescribed)
        require(nodes.prescribed_velocity(i, c) == v[c], "conflicting boundary conditions on node ", i,
                " component ", "xyz"[c], ": already prescribed v = ", nodes.prescribed_velocity(i, c),
                " m/s, now v = ", v[c], " m/s (node group '", group.name,
                "'); to change a prescribed velocity (a loading history) call bc::update_velocity(nodes, group, v, "
                "components), or the solver's update_block_velocity(b, v, components) for a block; release() frees it");
    }
  }
  for (index_t i : group.nodes)
    for (int c = 0; c < 3; ++c) {
      if (!has(which, c)) continue;
      nodes.constraint(i, c) = prescribed;
      nodes.prescribed_velocity(i, c) = v[c];
      nodes.velocity(i, c) = v[c];
    }
}

}  // namespace tessera::bc
