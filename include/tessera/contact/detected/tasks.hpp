#pragma once
// The tasks and gather slots of detected_contacts (contact/detected_contacts.hpp), built from the
// pairs and sub-contacts after each rebuild (detected/rebuild.hpp), after a checkpoint load and
// after set_own_blocks: runs of consecutive pairs for the threads, and the slots whose forces the
// gather sums, in a fixed order (the same bits for any thread count), and the gather itself.
//
// Rigid blocks: slots per block. Each pair puts its sums for A's four frame gridpoints, then B's,
// in pair_force_ (24 reals, detected/step.hpp update_pair); block b's slots are the offsets of its
// side of the pairs that touch it (24 pair + 12 side), in increasing pair order, and its frame
// gridpoint s gathers pair_force_[slot + 3 s + c] over them. A frame gridpoint belongs to one block
// only: build_block_frame (detected/frames.hpp) takes it from its block's range of the mesh's
// gridpoints, and those ranges are disjoint (each block needs its four or more vertex
// gridpoints, so the offsets increase). So the sums are those of a counting sort per gridpoint
// (each frame gridpoint's slots in pair order), to the bit, for 2 entries per pair instead of 8
// and a sort over blocks instead of gridpoints. Deformable blocks: slots per gridpoint, one per
// (sub-contact, gridpoint of its weights), in sub-contact order, each with its weight.
//
// Definitions of detected_contacts<Law>'s private members (declared in the class); it includes the
// class and the class includes it, so either header can come first.

#include <cstddef>
#include <cstdint>

#include "../../core/nodes.hpp"
#include "../../core/parallel.hpp"
#include "../../core/types.hpp"
#include "../detail/slot_gather.hpp"
#include "../detected_contacts.hpp"

namespace tessera::contact {
/// Tasks (runs of pairs with at least task_subcontacts sub-contacts) and gather slots, from the
/// pairs' first sub-contacts and the sub-contacts' pairs and weights: after a rebuild or a load.
/// `kept_pairs`: a rebuild's call (bound_present_contacts reuses its kept pairs' terms).
template <law::ContactLaw Law>
inline void detected_contacts<Law>::index_subcontacts(bool kept_pairs) {
  const std::size_t n_pairs = pair_a_.size(), n = pair_.size();
  const auto own = [&](index_t b) { return own_block_.empty() || own_block_[at(b)] != 0; };
  // Runs of consecutive pairs this rank evaluates (all, without set_own_blocks), each closed once
  // it holds task_subcontacts sub-contacts.
  pair_tasks_.clear();
  task_end_.clear();
  bool open = false;
  for (std::size_t k = 0; k < n_pairs; ++k) {
    if (!own(pair_a_[k]) && !own(pair_b_[k])) continue;
    if (open && at(task_end_.back()) == k) {
      task_end_.back() = static_cast<index_t>(k + 1);
    } else {
      pair_tasks_.push_back(static_cast<index_t>(k));
      task_end_.push_back(static_cast<index_t>(k + 1));
    }
    open = pair_first_[k + 1] - pair_first_[at(pair_tasks_.back())] < task_subcontacts;
  }

  if (!options_.deformable_blocks) {
    // Rigid blocks (file comment): a counting sort of (pair, side) onto the blocks this rank
    // gathers (the own blocks: every pair that touches one is in the tasks above).
    const std::size_t n_b = blocks_.size();
    slot_offsets_.assign(n_b + 1, 0);
    for (std::size_t k = 0; k < n_pairs; ++k) {
      if (own(pair_a_[k])) ++slot_offsets_[at(pair_a_[k]) + 1];
      if (own(pair_b_[k])) ++slot_offsets_[at(pair_b_[k]) + 1];
    }
    for (std::size_t b = 0; b < n_b; ++b) slot_offsets_[b + 1] += slot_offsets_[b];
    slot_source_.resize(at(slot_offsets_.back()));
    fill_.assign(slot_offsets_.begin(), slot_offsets_.end() - 1);
    for (std::size_t k = 0; k < n_pairs; ++k) {
      if (own(pair_a_[k])) slot_source_[at(fill_[at(pair_a_[k])]++)] = static_cast<index_t>(24 * k);
      if (own(pair_b_[k])) slot_source_[at(fill_[at(pair_b_[k])]++)] = static_cast<index_t>(24 * k + 12);
    }
    // No fill: update_pair writes every evaluated pair's 24 sums before a gather reads them (the
    // step's order; the gather reads only own blocks' slots, whose pairs are all evaluated).
    pair_force_.resize(24 * n_pairs);
    bound_present_contacts(kept_pairs);
    contact_blocks_.clear();
    for (std::size_t b = 0; b < n_b; ++b)
      if (slot_offsets_[b + 1] > slot_offsets_[b]) contact_blocks_.push_back(static_cast<index_t>(b));
    return;
  }

  // Deformable blocks: a counting sort over slot (sub-contact i, s), s = 0-7 (A's four, then B's
  // four), so that each gridpoint's slots come in increasing sub-contact order: slot s gridpoint
  // node_[s] (none: invalid_index) with its weight (A's +w, B's -w: force_ holds the force on A).
  slot_offsets_.assign(at(gridpoint_count_) + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (int s = 0; s < 8; ++s)
      if (const index_t g = node_[at(s)][i]; g != invalid_index) ++slot_offsets_[at(g) + 1];
  for (std::size_t g = 0; g < at(gridpoint_count_); ++g) slot_offsets_[g + 1] += slot_offsets_[g];
  slot_source_.resize(at(slot_offsets_.back()));
  slot_weight_.resize(at(slot_offsets_.back()));
  fill_.assign(slot_offsets_.begin(), slot_offsets_.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    for (int s = 0; s < 8; ++s) {
      const index_t g = node_[at(s)][i];
      if (g == invalid_index) continue;
      const auto e = at(fill_[at(g)]++);
      slot_source_[e] = static_cast<index_t>(i);
      slot_weight_[e] = s < 4 ? weight_[at(s)][i] : -weight_[at(s)][i];
    }
  contact_gridpoints_.clear();
  for (index_t g = 0; g < gridpoint_count_; ++g)
    if (slot_offsets_[at(g) + 1] > slot_offsets_[at(g)]) contact_gridpoints_.push_back(g);
}

/// Rigid blocks: per gridpoint, 4 b + s when it is frame gridpoint s of block b, else -1 (the
/// table add_force looks a gridpoint up in). Once, at construction.
template <law::ContactLaw Law>
inline void detected_contacts<Law>::index_frames() {
  frame_of_.assign(at(gridpoint_count_), -1);
  for (std::size_t b = 0; b < blocks_.size(); ++b)
    for (int s = 0; s < 4; ++s) frame_of_[at(blocks_[b].frame[at(s)])] = static_cast<index_t>(4 * b + at(s));
}

template <law::ContactLaw Law>
inline void detected_contacts<Law>::add_force(index_t g, node_set& gridpoints) const noexcept {
  if (options_.deformable_blocks) {
    // Slots per gridpoint, in sub-contact order, weight +-w (index_subcontacts).
    detail::add_weighted_slot_forces(g, slot_offsets_, slot_source_, slot_weight_, force_, gridpoints);
    return;
  }
  const index_t f = frame_of_[at(g)];
  if (f < 0) return;
  const index_t begin = slot_offsets_[at(f / 4)], end = slot_offsets_[at(f / 4) + 1];
  if (begin == end) return;
  const std::size_t s3 = 3 * at(f % 4);
  real fx = 0, fy = 0, fz = 0;
  for (index_t e = begin; e < end; ++e) {
    const real* p = pair_force_.data() + slot_source_[at(e)] + s3;
    fx += p[0];
    fy += p[1];
    fz += p[2];
  }
  gridpoints.force(g, 0) += fx;
  gridpoints.force(g, 1) += fy;
  gridpoints.force(g, 2) += fz;
}

/// update()'s gather: rigid blocks, per block with slots its four frame gridpoints in one pass
/// over its slots (each gridpoint's sum in the order add_force takes, so the same bits);
/// deformable blocks, add_force on every gridpoint with slots. Blocks / gridpoints in parallel.
template <law::ContactLaw Law>
inline void detected_contacts<Law>::gather_forces(node_set& gridpoints) const {
  if (options_.deformable_blocks) {
    parallel_for(static_cast<std::int64_t>(contact_gridpoints_.size()),
                 [&](std::int64_t j) { add_force(contact_gridpoints_[at(j)], gridpoints); });
    return;
  }
  parallel_for(
      static_cast<std::int64_t>(contact_blocks_.size()),
      [&](std::int64_t j) {
        const auto b = at(contact_blocks_[at(j)]);
        real f[12] = {};
        for (index_t e = slot_offsets_[b]; e < slot_offsets_[b + 1]; ++e) {
          const real* p = pair_force_.data() + slot_source_[at(e)];
          for (int c = 0; c < 12; ++c) f[c] += p[c];
        }
        for (int s = 0; s < 4; ++s)
          for (int c = 0; c < 3; ++c) gridpoints.force(blocks_[b].frame[at(s)], c) += f[3 * s + c];
      },
      64);
}

}  // namespace tessera::contact
