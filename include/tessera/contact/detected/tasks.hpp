#pragma once
// The tasks and gather slots of detected_contacts (contact/detected_contacts.hpp), built from the
// pairs and sub-contacts after each rebuild (detected/rebuild.hpp) and after a checkpoint load:
// runs of consecutive pairs for the threads, and per gridpoint the slots whose forces it gathers,
// in a fixed order (the same bits for any thread count).
//
// Definitions of detected_contacts<Law>'s private members (declared in the class); it includes the
// class and the class includes it, so either header can come first.

#include <cstddef>
#include <cstdint>

#include "../../core/types.hpp"
#include "../detected_contacts.hpp"

namespace tessera::contact {
/// Tasks (runs of pairs with at least task_subcontacts sub-contacts) and gather slots, from the
/// pairs' first sub-contacts and the sub-contacts' pairs and weights: after a rebuild or a load.
/// `kept_pairs`: a rebuild's call (bound_present_contacts reuses its kept pairs' terms).
template <law::ContactLaw Law>
inline void detected_contacts<Law>::index_subcontacts(bool kept_pairs) {
  const std::size_t n_pairs = pair_a_.size(), n = pair_.size();
  // Runs of consecutive pairs this rank evaluates (all, without set_own_blocks), each closed once
  // it holds task_subcontacts sub-contacts.
  pair_tasks_.clear();
  task_end_.clear();
  bool open = false;
  for (std::size_t k = 0; k < n_pairs; ++k) {
    if (!own_block_.empty() && own_block_[at(pair_a_[k])] == 0 && own_block_[at(pair_b_[k])] == 0) continue;
    if (open && at(task_end_.back()) == k) {
      task_end_.back() = static_cast<index_t>(k + 1);
    } else {
      pair_tasks_.push_back(static_cast<index_t>(k));
      task_end_.push_back(static_cast<index_t>(k + 1));
    }
    open = pair_first_[k + 1] - pair_first_[at(pair_tasks_.back())] < task_subcontacts;
  }

  // Gather slots, by a counting sort over slot (item, s), s = 0-7 (A's four, then B's four), so
  // that each gridpoint's slots come in increasing item order. Rigid blocks: the items are the
  // pairs, slot s the offset of the pair's sum for its block's frame gridpoint s % 4 in
  // pair_force_. Deformable blocks: the items are the sub-contacts, slot s gridpoint node_[s]
  // (none: invalid_index) with its weight (A's +w, B's -w: force_ holds the force on A).
  const bool rigid = !options_.deformable_blocks;
  const std::size_t items = rigid ? n_pairs : n;
  const auto slot_gridpoint = [&](std::size_t item, int s) {
    return rigid ? blocks_[at(s < 4 ? pair_a_[item] : pair_b_[item])].frame[at(s % 4)] : node_[at(s)][item];
  };
  slot_offsets_.assign(at(gridpoint_count_) + 1, 0);
  for (std::size_t item = 0; item < items; ++item)
    for (int s = 0; s < 8; ++s)
      if (const index_t g = slot_gridpoint(item, s); g != invalid_index) ++slot_offsets_[at(g) + 1];
  for (std::size_t g = 0; g < at(gridpoint_count_); ++g) slot_offsets_[g + 1] += slot_offsets_[g];
  slot_source_.resize(at(slot_offsets_.back()));
  slot_weight_.resize(rigid ? 0 : at(slot_offsets_.back()));
  fill_.assign(slot_offsets_.begin(), slot_offsets_.end() - 1);
  for (std::size_t item = 0; item < items; ++item)
    for (int s = 0; s < 8; ++s) {
      const index_t g = slot_gridpoint(item, s);
      if (g == invalid_index) continue;
      const auto e = at(fill_[at(g)]++);
      if (rigid) {
        slot_source_[e] = static_cast<index_t>(24 * item + 3 * at(s));
      } else {
        slot_source_[e] = static_cast<index_t>(item);
        slot_weight_[e] = s < 4 ? weight_[at(s)][item] : -weight_[at(s)][item];
      }
    }
  if (rigid) {
    pair_force_.assign(24 * n_pairs, 0.0);
    bound_present_contacts(kept_pairs);
  }
  contact_gridpoints_.clear();
  for (index_t g = 0; g < gridpoint_count_; ++g)
    if (slot_offsets_[at(g) + 1] > slot_offsets_[at(g)] && (own_gridpoint_.empty() || own_gridpoint_[at(g)] != 0))
      contact_gridpoints_.push_back(g);
}

}  // namespace tessera::contact
