#pragma once
// Broad phase of contact detection (DESIGN.md section 4): the pairs of blocks whose bounding
// boxes, each enlarged by a margin, overlap. Two algorithms with one result (the same sorted
// pair list, checked against the all-pairs test in test_contacts "[detection]"):
//   sweep_and_prune  sort the boxes by their lower x bound and sweep, testing y and z for the
//                    boxes whose x intervals overlap (YADE's InsertionSortCollider family);
//                    O(n log n + n k), k the boxes crossing a box's x interval
//   uniform_grid     bin every box into the cells of a grid whose cell is the largest enlarged
//                    box, and test the pairs sharing a cell, each pair once (in the cell of the
//                    lower corner of the two boxes' intersection; Munjiza and Andrews' NBS idea);
//                    O(n + pairs), memory O(n) cells. A box more than big_box_ratio times the
//                    mean size (a floor under a heap) is not binned but tested against every box,
//                    so that it does not set the cell: O(n) for each such box
// bench_detection measures both on Voronoi blocks; docs/model.md gives the choice.
//
// Rebuild margin (rebuild_margin): a pair whose enlarged boxes do not overlap at a rebuild
// cannot touch before the next one if every point of every block moves by at most the margin in
// the meantime: margin = steps x dt x (v_max + omega_max r_max) x safety, v_max the largest
// translational speed, omega_max the largest angular speed, r_max the largest distance of a block
// vertex from its centroid (each box is enlarged by the margin, so two approaching blocks may
// close 2 x margin, which covers both moving by their own bound). A detecting contact set
// rebuilds when a block has moved by more than the margin since the last rebuild, or after
// `steps` steps, whichever comes first.
//
// Deterministic: the pair list is sorted (a < b, by a then b) whatever the algorithm or thread
// count (uniform_grid on several threads: each thread's share of the cells and of the big boxes'
// tests gives its own sorted list, merged in share order; the pairs are distinct, so the sorted
// list is the one thread's). Allocates only when a workspace grows.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "../../core/separate_compilation.hpp"
#include "../../core/errors.hpp"
#include "../../core/types.hpp"

namespace tessera::contact::detection {

/// A candidate pair of blocks, a < b.
struct block_pair {
  /** block ids, a < b */ /**@{*/ index_t a = 0, b = 0; /**@}*/
  friend bool operator==(const block_pair&, const block_pair&) = default;
  friend bool operator<(const block_pair& x, const block_pair& y) { return x.a < y.a || (x.a == y.a && x.b < y.b); }
};

/// Margin (m) by which each bounding box is enlarged so that no contact is missed over `steps`
/// steps of dt (s) by blocks moving at most v_max (m/s) and turning at most omega_max (rad/s)
/// with vertices at most r_max (m) from their centroids; safety >= 1. Throws invalid_input for a
/// negative or non-finite input.
[[nodiscard]] inline real rebuild_margin(real v_max, real omega_max, real r_max, real dt, index_t steps, real safety = 1.5) {
  require_non_negative(v_max, "detection: largest block speed v_max (m/s)");
  require_non_negative(omega_max, "detection: largest angular speed omega_max (rad/s)");
  require_non_negative(r_max, "detection: largest vertex distance r_max (m)");
  require_positive(dt, "detection: time step dt (s)");
  require(steps >= 1, "detection: rebuild interval = ", steps, " steps must be >= 1");
  require(std::isfinite(safety) && safety >= 1, "detection: margin safety factor = ", safety, " must be finite and >= 1");
  return static_cast<real>(steps) * dt * (v_max + omega_max * r_max) * safety;
}

namespace detail {
[[nodiscard]] inline bool boxes_overlap(const aabb& p, const aabb& q, real margin2) {
  return p.lo.x() <= q.hi.x() + margin2 && q.lo.x() <= p.hi.x() + margin2 && p.lo.y() <= q.hi.y() + margin2 &&
         q.lo.y() <= p.hi.y() + margin2 && p.lo.z() <= q.hi.z() + margin2 && q.lo.z() <= p.hi.z() + margin2;
}
inline void require_boxes(std::span<const aabb> boxes, real margin, const char* who) {
  require_non_negative(margin, "detection: broad-phase margin (m)");
  for (std::size_t i = 0; i < boxes.size(); ++i)
    require(boxes[i].lo.allFinite() && boxes[i].hi.allFinite() && (boxes[i].hi.array() >= boxes[i].lo.array()).all(), who,
            ": bounding box of block ", i, " is empty or not finite");
}
}  // namespace detail

/// All pairs (a < b) whose boxes enlarged by `margin` overlap, by testing every pair: O(n^2), the
/// reference of the tests.
inline void all_pairs(std::span<const aabb> boxes, real margin, std::vector<block_pair>& pairs) {
  detail::require_boxes(boxes, margin, "all_pairs");
  pairs.clear();
  const auto n = static_cast<index_t>(boxes.size());
  for (index_t a = 0; a < n; ++a)
    for (index_t b = a + 1; b < n; ++b)
      if (detail::boxes_overlap(boxes[static_cast<std::size_t>(a)], boxes[static_cast<std::size_t>(b)], 2 * margin))
        pairs.push_back({a, b});
}

/// Scratch of sweep_and_prune, kept between rebuilds so they do not allocate.
struct sweep_workspace {
  std::vector<index_t> order;  ///< sort order of the boxes' lower ends
};

/// The pairs of all_pairs by sort and sweep along x (see the file comment).
TESSERA_INLINE void sweep_and_prune(std::span<const aabb> boxes, real margin, std::vector<block_pair>& pairs, sweep_workspace& w);

/// Scratch of uniform_grid (cell lists as CSR), kept between rebuilds.
struct grid_workspace {
  std::vector<std::int64_t> cell_of_entry;  ///< cell of each (box, cell) entry
  /** block of each entry, and the entries' order by cell */ /**@{*/ std::vector<index_t> block_of_entry, order; /**@}*/
  std::vector<std::size_t> starts;  ///< first entry of each cell (CSR of the counting sort by cell)
  std::vector<std::uint8_t> reached;  ///< per cell, whether a marked box reaches it (a pass with marks)
  /// On several threads, each share's pairs (sorted), then merged into the result in place of one sort.
  std::vector<std::vector<block_pair>> share_pairs;
  std::vector<block_pair> merged;  ///< the merge's other buffer (more than two shares)
};

/// An enlarged box whose largest side exceeds this many times the mean of all boxes' is a big
/// box of the grid (grid_layout::big).
inline constexpr real big_box_ratio = 8;

/// The grid of uniform_grid for `boxes` enlarged by `margin`: its origin, cell size (the largest
/// enlarged box but the big ones) and cells per axis, over the boxes but the big ones.
struct grid_layout {
  vec3 lo = vec3::Zero();  ///< origin (m)
  real cell = 0;  ///< cell size (m)
  /// Enlarged boxes whose largest side exceeds this (m: big_box_ratio x the mean) are not binned
  /// but tested against every box (a floor among blocks would otherwise make the cell its size).
  real big = std::numeric_limits<real>::infinity();
  std::array<std::int64_t, 3> dims{1, 1, 1};  ///< cells per axis
  /// Cells in all (as a double: it may exceed any integer type for a degenerate layout).
  [[nodiscard]] double cells() const {
    return static_cast<double>(dims[0]) * static_cast<double>(dims[1]) * static_cast<double>(dims[2]);
  }
  /// At most 64 cells per block: otherwise a few huge boxes set the cell among many small ones
  /// and sort and sweep is the better choice.
  [[nodiscard]] bool suits(std::size_t blocks) const { return cells() <= 64.0 * static_cast<double>(blocks) + 64.0; }
};
[[nodiscard]] TESSERA_INLINE grid_layout layout_grid(std::span<const aabb> boxes, real margin);

/// The pairs of all_pairs by binning into the grid `g` = layout_grid(boxes, margin) (see the file
/// comment). Refuses a layout that does not suit a grid (grid_layout::suits: use sweep_and_prune).
/// `only` (empty: every pair) keeps the pairs with at least one block b marked only[b] != 0 (an
/// incremental pass's), the same pairs as filtering the whole list afterwards: it bins only the
/// cells a marked box reaches and tests only the pairs with a marked entry, O(n + marked pairs).
TESSERA_INLINE void uniform_grid(std::span<const aabb> boxes, real margin, const grid_layout& g, std::vector<block_pair>& pairs,
                                 grid_workspace& w, std::span<const std::uint8_t> only = {});

/// The same, laying out the grid first.
inline void uniform_grid(std::span<const aabb> boxes, real margin, std::vector<block_pair>& pairs, grid_workspace& w) {
  uniform_grid(boxes, margin, layout_grid(boxes, margin), pairs, w);
}

}  // namespace tessera::contact::detection

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/broad_phase.ipp"
#endif
