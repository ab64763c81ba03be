#pragma once
// The keys of detected_contacts' sub-contacts (contact/detected_contacts.hpp) and their merge at a
// rebuild. Not a public interface.
//
// Each corner of a touching pair's patch is one sub-contact, keyed by (block a, block b, corner
// label): a vertex of A, a vertex of B, or the crossing of an edge of A with an edge of B
// (detection::corner_label). Deformable blocks add the gridpoint sub-contacts of a face-to-face
// patch (detected/deformable_fit.hpp), labelled by the gridpoint and its side (node_label). Keys
// are kept sorted by (a, b, label); at a rebuild the new keys, sorted the same way, are merged
// with the old ones pair by pair (find_old_pair, then seek_old_label within the pair), so a corner
// that persists is found again and keeps its law state (detected/rebuild.hpp).
//
// Cost: a rebuild's merge looks up each pass pair's old pair (a binary search over the old pairs,
// as previous_node_side) and visits the sub-contacts of the old pairs the pass detects again (not
// those of the pairs it keeps); no allocation. Thread safety: they read their arguments only.

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "../../core/types.hpp"

namespace tessera::contact::detail {

/// An index handle as a std::size_t, for the detected/ headers' array subscripts.
template <std::integral I>
[[nodiscard]] constexpr std::size_t at(I i) noexcept {
  return static_cast<std::size_t>(i);
}

/// A gridpoint sub-contact of a deformable patch (collect_nodes).
struct node_contact {
  std::uint64_t label = 0;
  index_t gridpoint = 0;
  real area = 0, gap = 0;
};
/// Label of a gridpoint sub-contact: kind 3 (beside corner_label's 0-2), bit 61 the side (B),
/// the gridpoint below; and its three readers.
[[nodiscard]] constexpr std::uint64_t node_label(index_t g, bool side_b) noexcept {
  return (std::uint64_t{3} << 62) | (side_b ? std::uint64_t{1} << 61 : 0) | static_cast<std::uint64_t>(g);
}
[[nodiscard]] constexpr bool is_node_label(std::uint64_t label) noexcept { return (label >> 62) == 3; }
[[nodiscard]] constexpr bool node_label_side_b(std::uint64_t label) noexcept { return ((label >> 61) & 1U) != 0; }
[[nodiscard]] constexpr index_t node_label_gridpoint(std::uint64_t label) noexcept {
  return static_cast<index_t>(label & ((std::uint64_t{1} << 61) - 1));
}

/// The old pair (a, b) among pair_a, pair_b (sorted by (a, b)): its index, or pair_a.size() if
/// there is none (a binary search: a rebuild's pass pairs look up their old pair each on its own,
/// in parallel).
[[nodiscard]] inline std::size_t find_old_pair(index_t a, index_t b, const std::vector<index_t>& pair_a,
                                               const std::vector<index_t>& pair_b) noexcept {
  std::size_t lo = 0, hi = pair_a.size();
  while (lo < hi) {  // first old pair >= (a, b)
    const std::size_t mid = (lo + hi) / 2;
    if (pair_a[mid] < a || (pair_a[mid] == a && pair_b[mid] < b))
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < pair_a.size() && pair_a[lo] == a && pair_b[lo] == b ? lo : pair_a.size();
}

/// The side whose gridpoints pair (a, b) used at the last rebuild: 0 A, 1 B, -1 corners or no
/// such pair. Reads the old pairs (pair_a, pair_b, pair_first: sorted by (a, b)) and their
/// sub-contacts' labels, before the rebuild replaces them.
[[nodiscard]] inline int previous_node_side(const std::vector<index_t>& pair_a, const std::vector<index_t>& pair_b,
                                     const std::vector<index_t>& pair_first,
                                     const std::vector<std::uint64_t>& key_label, index_t a, index_t b) {
  const std::size_t k = find_old_pair(a, b, pair_a, pair_b);
  if (k == pair_a.size() || pair_first[k + 1] == pair_first[k]) return -1;
  const std::uint64_t label = key_label[at(pair_first[k])];
  if (!is_node_label(label)) return -1;
  return node_label_side_b(label) ? 1 : 0;
}

/// Within the old pair's sub-contacts [old, end) (find_old_pair's): advances `old` over the labels below
/// `label` and says whether the one it stops at is `label` (the sub-contact persists). Called with
/// the pair's new labels in increasing order, it visits each of the old pair's sub-contacts once.
[[nodiscard]] inline bool seek_old_label(std::size_t& old, std::size_t end, std::uint64_t label,
                                         const std::vector<std::uint64_t>& key_label) noexcept {
  while (old < end && key_label[old] < label) ++old;
  return old < end && key_label[old] == label;
}

}  // namespace tessera::contact::detail
