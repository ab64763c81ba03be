#pragma once
// The gather both contact sets share (face_contacts::add_force and, for deformable blocks,
// detected_contacts::add_force, detected/tasks.hpp): a gridpoint's force as the weighted sum of
// the sub-contact forces over its CSR slots, in slot order, so the bits depend on the slots only.

#include <array>
#include <cstddef>
#include <vector>

#include "../../core/nodes.hpp"
#include "../../core/types.hpp"

namespace tessera::contact::detail {

/// Adds to gridpoints.force(g) (N) sum_e weight[e] force[.][source[e]] (N) over g's CSR slots e, in increasing e.
[[gnu::always_inline]] inline void add_weighted_slot_forces(index_t g, const std::vector<index_t>& offsets,
                                                            const std::vector<index_t>& source,
                                                            const std::vector<real>& weight,
                                                            const std::array<std::vector<real>, 3>& force,
                                                            node_set& gridpoints) noexcept {
  const auto at = [](index_t i) { return static_cast<std::size_t>(i); };
  const index_t begin = offsets[at(g)], end = offsets[at(g) + 1];
  if (begin == end) return;
  const real* f[3] = {force[0].data(), force[1].data(), force[2].data()};
  real fx = 0, fy = 0, fz = 0;
  for (index_t e = begin; e < end; ++e) {
    const auto i = at(source[at(e)]);
    const real w = weight[at(e)];
    fx += w * f[0][i];
    fy += w * f[1][i];
    fz += w * f[2][i];
  }
  gridpoints.force(g, 0) += fx;
  gridpoints.force(g, 1) += fy;
  gridpoints.force(g, 2) += fz;
}

}  // namespace tessera::contact::detail
