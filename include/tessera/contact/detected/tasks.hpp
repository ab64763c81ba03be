#pragma once
// The tasks and gather slots of detected_contacts (contact/detected_contacts.hpp), built from the
// pairs and sub-contacts after each rebuild (detected/rebuild.hpp) and after a checkpoint load:
// runs of consecutive pairs for the threads, and per gridpoint the slots whose forces it gathers,
// in a fixed order (the same bits for any thread count).
//
// Definitions of detected_contacts<Law>'s private members (declared in the class); it includes the
// class and the class includes it, so either header can come first.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "../../core/parallel.hpp"
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
  // On the threads, the same slots for any thread count: each of `parts` chunks of the items
  // counts its slots per gridpoint (fill_, chunk c's counts from c x gridpoints), each of `parts`
  // ranges of gridpoints turns the counts into every chunk's first slot there (the exclusive
  // prefix sums in the serial order: gridpoint, then chunk), and each chunk writes its items'
  // slots from those (no allocation once fill_ has grown).
  const std::size_t n_g = at(gridpoint_count_);
  const std::size_t parts = at(std::clamp<std::int64_t>(static_cast<std::int64_t>(items) / 128, 1, std::min(max_threads(), 64)));
  const auto part = [&](std::size_t total, std::size_t c) { return total * c / parts; };  // (chunk c: [part(c), part(c + 1)))
  fill_.resize(parts * n_g);
  slot_offsets_.resize(n_g + 1);
  slot_offsets_[0] = 0;
  std::array<index_t, 65> slots_before{}, listed_before{};  // (per range of gridpoints, then summed over the ranges before)
  const auto each_part = [&](auto&& f) { parallel_for(static_cast<std::int64_t>(parts), [&](std::int64_t c) { f(at(c)); }, 1); };
  each_part([&](std::size_t c) {
    index_t* const count = fill_.data() + c * n_g;
    std::fill_n(count, n_g, 0);
    for (std::size_t item = part(items, c); item < part(items, c + 1); ++item)
      for (int s = 0; s < 8; ++s)
        if (const index_t g = slot_gridpoint(item, s); g != invalid_index) ++count[at(g)];
  });
  const auto listed = [&](std::size_t g, index_t slots) { return slots > 0 && (own_gridpoint_.empty() || own_gridpoint_[g] != 0); };
  each_part([&](std::size_t c) {
    for (std::size_t g = part(n_g, c); g < part(n_g, c + 1); ++g) {
      index_t here = 0;
      for (std::size_t d = 0; d < parts; ++d) here += fill_[d * n_g + g];
      slots_before[c + 1] += here;
      listed_before[c + 1] += listed(g, here) ? 1 : 0;
    }
  });
  for (std::size_t c = 0; c < parts; ++c) {
    slots_before[c + 1] += slots_before[c];
    listed_before[c + 1] += listed_before[c];
  }
  contact_gridpoints_.resize(at(listed_before[parts]));
  each_part([&](std::size_t c) {
    index_t next = slots_before[c];
    auto to = at(listed_before[c]);
    for (std::size_t g = part(n_g, c); g < part(n_g, c + 1); ++g) {
      const index_t first = next;
      for (std::size_t d = 0; d < parts; ++d) next += std::exchange(fill_[d * n_g + g], next);
      slot_offsets_[g + 1] = next;
      if (listed(g, next - first)) contact_gridpoints_[to++] = static_cast<index_t>(g);
    }
  });
  slot_source_.resize(at(slot_offsets_.back()));
  slot_weight_.resize(rigid ? 0 : at(slot_offsets_.back()));
  each_part([&](std::size_t c) {
    index_t* const fill = fill_.data() + c * n_g;
    for (std::size_t item = part(items, c); item < part(items, c + 1); ++item)
      for (int s = 0; s < 8; ++s) {
        const index_t g = slot_gridpoint(item, s);
        if (g == invalid_index) continue;
        const auto e = at(fill[at(g)]++);
        if (rigid) {
          slot_source_[e] = static_cast<index_t>(24 * item + 3 * at(s));
        } else {
          slot_source_[e] = static_cast<index_t>(item);
          slot_weight_[e] = s < 4 ? weight_[at(s)][item] : -weight_[at(s)][item];
        }
      }
  });
  if (rigid) {
    pair_force_.assign(24 * n_pairs, 0.0);
    bound_present_contacts(kept_pairs);
  }
}

}  // namespace tessera::contact
