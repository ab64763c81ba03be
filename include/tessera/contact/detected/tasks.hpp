#pragma once
// Parts of a rebuild of detected_contacts (contact/detected_contacts.hpp, detected/rebuild.hpp)
// that run on the threads: the pass's corners sorted by label per pair, and the tasks and gather
// slots built from the pairs and sub-contacts (after each rebuild and after a checkpoint load):
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
/// The pass's corners, per pass pair sorted by label, a label met twice kept once (with the two
/// areas): new_label_, new_area_, new_point_, new_gap_, pass pair k's from pass_first_[k]
/// (deformable blocks: a face-to-face patch's at surface gridpoints). Rigid blocks: each pass pair
/// sorts its corners (order_, in its range of the pass's corners) and counts its labels, then writes
/// them from its place (the pairs in parallel, each its own slots; the same bits for any thread count).
template <law::ContactLaw Law>
inline void detected_contacts<Law>::list_pass_corners(const node_set* gp) {
  const std::size_t n_found = result_.pairs.size();
  order_.resize(at(result_.first_corner[n_found]));
  pass_first_.assign(n_found + 1, 0);
  const auto sort_corners = [&](std::size_t k) {
    const auto first = at(result_.first_corner[k]), last = at(result_.first_corner[k + 1]);
    for (std::size_t j = first; j < last; ++j) order_[j] = j;
    std::sort(order_.begin() + static_cast<std::ptrdiff_t>(first), order_.begin() + static_cast<std::ptrdiff_t>(last),
              [&](std::size_t x, std::size_t y) {
                return result_.label[x] < result_.label[y] || (result_.label[x] == result_.label[y] && x < y);
              });
    for (std::size_t j = first; j < last; ++j)  // (a label met twice: a corner within round-off of another)
      pass_first_[k + 1] += j == first || result_.label[order_[j]] != result_.label[order_[j - 1]] ? 1 : 0;
  };
  const auto write_corners = [&](std::size_t k) {
    const auto first = at(result_.first_corner[k]), last = at(result_.first_corner[k + 1]);
    const bool polygon = result_.type[k] == detection::patch_type::polygon;
    const real nominal =
        std::min(blocks_[at(result_.pairs[k].a)].nominal_area, blocks_[at(result_.pairs[k].b)].nominal_area);
    std::size_t to = at(pass_first_[k]);
    for (std::size_t o = first; o < last; ++o) {
      const std::size_t j = order_[o];
      // A sliver polygon's corner keeps a floor of 1e-6 of the nominal area, so that areas stay
      // > 0 and the ratios of a rebuild (below) stay finite.
      const real a = polygon ? std::max(result_.area[j], 1e-6 * nominal) : nominal;
      // A label met twice keeps its first point and takes the other's area.
      if (o > first && result_.label[j] == result_.label[order_[o - 1]]) {
        if (polygon) new_area_[to - 1] += a;
        continue;
      }
      new_label_[to] = result_.label[j];
      new_area_[to] = a;
      new_point_[to] = result_.point[j];
      new_gap_[to++] = result_.gap[j];
    }
  };
  const auto resize_corners = [&](std::size_t size) {
    new_label_.resize(size);
    new_area_.resize(size);
    new_point_.resize(size);
    new_gap_.resize(size);
  };
  if (!options_.deformable_blocks) {
    parallel_for_dynamic(static_cast<std::int64_t>(n_found), [&](std::int64_t k) { sort_corners(at(k)); });
    for (std::size_t k = 0; k < n_found; ++k) pass_first_[k + 1] += pass_first_[k];
    resize_corners(at(pass_first_[n_found]));
    parallel_for_dynamic(static_cast<std::int64_t>(n_found), [&](std::int64_t k) { write_corners(at(k)); });
  } else {
    resize_corners(0);
    for (std::size_t k = 0; k < n_found; ++k) {
      // Deformable blocks: a face-to-face patch's sub-contacts at surface gridpoints.
      if (result_.type[k] == detection::patch_type::polygon && collect_nodes(k, gp)) {
        pass_first_[k + 1] = pass_first_[k] + static_cast<index_t>(node_scratch_.size());
        resize_corners(at(pass_first_[k + 1]));
        for (std::size_t i = 0; i < node_scratch_.size(); ++i) {
          const node_contact& c = node_scratch_[i];
          const std::size_t to = at(pass_first_[k]) + i;
          new_label_[to] = c.label;
          new_area_[to] = c.area;
          new_point_[to] = position(c.gridpoint, gp);
          new_gap_[to] = c.gap;
        }
        continue;
      }
      sort_corners(k);
      pass_first_[k + 1] += pass_first_[k];
      resize_corners(at(pass_first_[k + 1]));
      write_corners(k);
    }
  }
}

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
