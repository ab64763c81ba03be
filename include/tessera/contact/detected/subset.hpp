#pragma once
// A rank's part of detected_contacts (contact/detected_contacts.hpp) in a run split over MPI ranks
// (distributed::rigid_stepper, docs/architecture.md "Detected contacts across ranks"), and the
// energies, which book that part only.
//
// Every rank holds the whole scene's pairs and keys in the same order: each rebuild's detection
// pass is one process's, either run whole on every rank or, with set_detection_split, its candidate
// pairs cut into one contiguous part per rank, each rank evaluating its part (the common planes and
// patches, nearly all of a pass) and a gather (distributed::gather_detection) concatenating the
// parts in rank order, which is the whole pass's result to the bit. The broad phase, the merge of
// the states and the frames stay whole on every rank (a few per cent of a pass). set_own_blocks
// then restricts the step: the tasks hold the pairs that touch an own block (a pair across the cut
// is evaluated on both of its ranks, from the same inputs), and the gather visits the own blocks'
// frame gridpoints (the other blocks get no slots), whose slots all come from those pairs, in the
// order of one process. The other pairs' states go stale and nothing reads them for a force; the
// books (energies(), and the retired energies and rebuild exchange of the rebuilds after the call)
// count a sub-contact on the rank of its pair's first block only, so the ranks' books add up to one
// process's to round-off. When a block changes rank, the pairs a rank starts to evaluate take their
// step state (normals now, law states, fresh flags, forces) from a rank that evaluated them:
// write_pair_state and read_pair_state.
//
// Definitions of detected_contacts<Law>'s members declared in the class; it includes the class and
// the class includes it, so either header can come first.

#include <cstddef>
#include <cstring>
#include <functional>
#include <utility>
#include <type_traits>
#include <vector>
#include <span>

#include "../../core/errors.hpp"
#include "../../core/types.hpp"
#include "../detected_contacts.hpp"

namespace tessera::contact {

/// Capacity of the arrays a rebuild grows with the sub-contacts, pairs and gather slots (the
/// growth count compares it before and after; the keys and pairs with the buffers a rebuild
/// swaps them with, so that the sum grows only when one of them does).
template <law::ContactLaw Law>
[[nodiscard]] inline std::size_t detected_contacts<Law>::storage_capacity() const noexcept {
  return key_label_.capacity() + prev_.label.capacity() + pair_a_.capacity() + new_pair_a_.capacity() +
         slot_source_.capacity() + pair_force_.capacity();
}

/// Elastic energy of the current sub-contacts this rank books (J; all without set_own_blocks),
/// summed in sub-contact order.
template <law::ContactLaw Law>
[[nodiscard]] inline real detected_contacts<Law>::stored_energy() const {
  real e = 0;
  for (index_t i = 0; i < size(); ++i)
    if (counted(at(i))) e += energies_of(at(i)).stored;
  return e;
}

template <law::ContactLaw Law>
[[nodiscard]] inline contact_energies detected_contacts<Law>::energies_of(std::size_t i) const {
  contact_energies e;
  const state_type& st = state_[i];
  const real a = area_[i];
  e.stored = a * Law::stored_energy(law_params_[at(pair_param_[at(pair_[i])])], st);
  e.dissipated = a * Law::dissipated_energy(st);
  if constexpr (detail::has_dissipation_split<state_type>) {
    e.dissipated_tension = a * st.dissipated_tension;
    e.dissipated_shear = a * st.dissipated_shear;
    e.dissipated_compression = a * st.dissipated_compression;
  }
  return e;
}

template <law::ContactLaw Law>
inline void detected_contacts<Law>::set_own_blocks(std::span<const index_t> own) {
  require(!options_.deformable_blocks,
          "detected_contacts::set_own_blocks: deformable blocks on detected contacts are not split over ranks");
  own_block_.clear();
  if (!own.empty()) {
    own_block_.assign(blocks_.size(), 0);
    index_t last = -1;
    for (const index_t b : own) {
      require(b > last && b < static_cast<index_t>(blocks_.size()), "detected_contacts::set_own_blocks: block ", b,
              " is out of range [0, ", blocks_.size(), ") or not after ", last, " (the list must increase)");
      last = b;
      own_block_[at(b)] = 1;
    }
  }
  index_subcontacts();
}

template <law::ContactLaw Law>
inline void detected_contacts<Law>::set_detection_split(int part, int parts,
                                                        std::function<void(detection::detection_result&)> gather) {
  require(parts >= 1 && part >= 0 && part < parts, "detected_contacts::set_detection_split: part ", part, " of ",
          parts, " parts: need parts >= 1 and 0 <= part < parts");
  require(parts == 1 || static_cast<bool>(gather),
          "detected_contacts::set_detection_split: ", parts, " parts need a gather of the other parts' results");
  share_ = {part, parts};
  gather_ = parts > 1 ? std::move(gather) : nullptr;
}

template <law::ContactLaw Law>
inline void detected_contacts<Law>::set_motion_vote(std::function<real(real)> largest, std::function<void()> before_rebuild) {
  require(static_cast<bool>(largest) == static_cast<bool>(before_rebuild),
          "detected_contacts::set_motion_vote: give both functions or neither");
  largest_motion_ = std::move(largest);
  before_rebuild_ = std::move(before_rebuild);
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

template <law::ContactLaw Law>
inline std::size_t detected_contacts<Law>::pair_state_bytes(index_t k) const {
  const auto n = static_cast<std::size_t>(pair_first_[at(k) + 1] - pair_first_[at(k)]);
  return 9 * sizeof(real) + n * (sizeof(state_type) + 1 + 3 * sizeof(real));
}

/// f(address, bytes) for each field of pair k's step state in a fixed order: its three normals
/// now, then per sub-contact its law state, fresh flag and force on A.
template <law::ContactLaw Law>
template <class F>
inline void detected_contacts<Law>::visit_pair_state(index_t k, F&& f) {
  for (int j = 0; j < 3; ++j)
    for (int c = 0; c < 3; ++c) f(&normal_[at(j)](k, c), sizeof(real));
  for (auto i = at(pair_first_[at(k)]); i < at(pair_first_[at(k) + 1]); ++i) {
    f(&state_[i], sizeof(state_type));
    f(&fresh_[i], std::size_t{1});
    for (int c = 0; c < 3; ++c) f(&force_[at(c)][i], sizeof(real));
  }
}

template <law::ContactLaw Law>
inline void detected_contacts<Law>::write_pair_state(index_t k, std::vector<unsigned char>& out) const {
  // A law state's bytes are its value (reals, fixed-size Eigen vectors, flags; Eigen's copy
  // constructor makes it non-trivially copyable only formally), as the state gather also copies it.
  static_assert(std::is_trivially_destructible_v<state_type>, "a law state moves between ranks as bytes");
  // The visit only reads here.
  const_cast<detected_contacts&>(*this).visit_pair_state(k, [&](const void* p, std::size_t bytes) {
    const auto* b = static_cast<const unsigned char*>(p);
    out.insert(out.end(), b, b + bytes);
  });
}

template <law::ContactLaw Law>
inline void detected_contacts<Law>::read_pair_state(index_t k, const unsigned char* in) {
  visit_pair_state(k, [&](void* p, std::size_t bytes) {
    std::memcpy(p, in, bytes);
    in += bytes;
  });
}

}  // namespace tessera::contact
