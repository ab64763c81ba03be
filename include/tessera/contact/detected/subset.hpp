#pragma once
// A rank's part of detected_contacts (contact/detected_contacts.hpp) in a run split over MPI ranks
// (distributed::rigid_stepper, docs/architecture.md "Detected contacts across ranks"), and the
// energies, which book that part only.
//
// Every rank detects the whole scene from the same geometry, so every rank holds the same pairs
// and keys in the same order. set_own_blocks then restricts the step: the tasks hold the pairs
// that touch an own block (a pair across the cut is evaluated on both of its ranks, from the same
// inputs), and the gather visits the own blocks' gridpoints, whose slots all come from those
// pairs, in the order of one process. The other pairs' states go stale and nothing reads them for
// a force; the books (energies(), and the retired energies and rebuild exchange of the rebuilds
// after the call) count a sub-contact on the rank of its pair's first block only, so the ranks'
// books add up to one process's to round-off.
//
// Definitions of detected_contacts<Law>'s members declared in the class; it includes the class and
// the class includes it, so either header can come first.

#include <cstddef>
#include <span>

#include "../../core/errors.hpp"
#include "../../core/types.hpp"
#include "../detected_contacts.hpp"

namespace tessera::contact {

template <law::ContactLaw Law>
inline void detected_contacts<Law>::set_own_blocks(std::span<const index_t> own) {
  require(!options_.deformable_blocks,
          "detected_contacts::set_own_blocks: deformable blocks on detected contacts are not split over ranks");
  own_block_.clear();
  own_gridpoint_.clear();
  if (!own.empty()) {
    own_block_.assign(blocks_.size(), 0);
    own_gridpoint_.assign(at(gridpoint_count_), 0);
    index_t last = -1;
    for (const index_t b : own) {
      require(b > last && b < static_cast<index_t>(blocks_.size()), "detected_contacts::set_own_blocks: block ", b,
              " is out of range [0, ", blocks_.size(), ") or not after ", last, " (the list must increase)");
      last = b;
      own_block_[at(b)] = 1;
      const block_data& bd = blocks_[at(b)];
      for (index_t k = bd.vertex_begin; k < bd.vertex_end; ++k) own_gridpoint_[at(vertex_gridpoints_[at(k)])] = 1;
    }
  }
  index_subcontacts();
}

template <law::ContactLaw Law>
inline contact_energies detected_contacts<Law>::energies() const {
  contact_energies e = retired_;
  for (index_t i = 0; i < size(); ++i) {
    if (!counted(at(i))) continue;
    const contact_energies c = energies_of(at(i));
    e.stored += c.stored;
    e.dissipated += c.dissipated;
    e.dissipated_tension += c.dissipated_tension;
    e.dissipated_shear += c.dissipated_shear;
    e.dissipated_compression += c.dissipated_compression;
  }
  return e;
}

}  // namespace tessera::contact
