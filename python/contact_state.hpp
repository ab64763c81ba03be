#pragma once
// Per-sub-contact state as the module hands it out (contact_state: copies, SI), shared by the
// solvers' bindings (tessera_module.cpp, take_contact_state) and the class's binding
// (bind_scene.cpp).
#include <tessera/contact/concepts.hpp>  // subcontact_position
#include <tessera/core/types.hpp>
#include <tessera/io/vtk_contacts.hpp>

#include <cstddef>
#include <vector>

namespace tessera::python {

/// Per-sub-contact state of a contact set as NumPy arrays (copies, SI): the io::vtk contact
/// snapshot (positions, normals, areas, damage, status and every state field the law declares)
/// and the blocks each sub-contact joins. Also writes itself as a .vtp.
struct contact_state {
  io::vtk::contact_snapshot snapshot;
  std::vector<index_t> block_a, block_b;
  std::vector<vec3> position;  ///< current position (m): contact::subcontact_position
  std::vector<vec3> force;     ///< force on block B's side in the last step (N; A's side took its opposite)
};

template <class S>
contact_state take_contact_state(const S& s) {
  contact_state out;
  const auto& c = s.contacts();
  out.snapshot.take(c, s.gridpoints());
  const auto n = static_cast<std::size_t>(c.subcontact_count());
  out.block_a.resize(n), out.block_b.resize(n), out.position.resize(n), out.force.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    out.block_a[k] = c.block_a(static_cast<index_t>(k));
    out.block_b[k] = c.block_b(static_cast<index_t>(k));
    const auto i = static_cast<index_t>(k);
    out.position[k] = contact::subcontact_position(c, i, s.gridpoints());
    out.force[k] = c.force(i);
  }
  return out;
}

}  // namespace tessera::python
