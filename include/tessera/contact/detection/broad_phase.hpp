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
//                    O(n + pairs), memory O(n) cells
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
// count. Allocates only when a workspace grows.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

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
inline void sweep_and_prune(std::span<const aabb> boxes, real margin, std::vector<block_pair>& pairs, sweep_workspace& w) {
  detail::require_boxes(boxes, margin, "sweep_and_prune");
  pairs.clear();
  const auto n = static_cast<index_t>(boxes.size());
  w.order.resize(boxes.size());
  for (index_t i = 0; i < n; ++i) w.order[static_cast<std::size_t>(i)] = i;
  std::sort(w.order.begin(), w.order.end(), [&](index_t p, index_t q) {
    const real x = boxes[static_cast<std::size_t>(p)].lo.x(), y = boxes[static_cast<std::size_t>(q)].lo.x();
    return x < y || (x == y && p < q);
  });
  const real m2 = 2 * margin;
  for (std::size_t i = 0; i < w.order.size(); ++i) {
    const aabb& p = boxes[static_cast<std::size_t>(w.order[i])];
    const real reach = p.hi.x() + m2;
    for (std::size_t j = i + 1; j < w.order.size(); ++j) {
      const aabb& q = boxes[static_cast<std::size_t>(w.order[j])];
      if (q.lo.x() > reach) break;
      if (detail::boxes_overlap(p, q, m2)) {
        const index_t a = w.order[i], b = w.order[j];
        pairs.push_back({std::min(a, b), std::max(a, b)});
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
}

/// Scratch of uniform_grid (cell lists as CSR), kept between rebuilds.
struct grid_workspace {
  std::vector<std::int64_t> cell_of_entry;  ///< cell of each (box, cell) entry
  /** block of each entry, and the entries' order by cell */ /**@{*/ std::vector<index_t> block_of_entry, order; /**@}*/
  std::vector<std::size_t> starts;  ///< first entry of each cell (CSR)
};

/// The grid of uniform_grid for `boxes` enlarged by `margin`: its origin, cell size (the largest
/// enlarged box) and cells per axis.
struct grid_layout {
  vec3 lo = vec3::Zero();  ///< origin (m)
  real cell = 0;  ///< cell size (m)
  std::array<std::int64_t, 3> dims{1, 1, 1};  ///< cells per axis
  /// Cells in all (as a double: it may exceed any integer type for a degenerate layout).
  [[nodiscard]] double cells() const {
    return static_cast<double>(dims[0]) * static_cast<double>(dims[1]) * static_cast<double>(dims[2]);
  }
  /// At most 64 cells per block: otherwise a few huge boxes set the cell among many small ones
  /// and sort and sweep is the better choice.
  [[nodiscard]] bool suits(std::size_t blocks) const { return cells() <= 64.0 * static_cast<double>(blocks) + 64.0; }
};
[[nodiscard]] inline grid_layout layout_grid(std::span<const aabb> boxes, real margin) {
  grid_layout g;
  if (boxes.empty()) return g;
  aabb domain;
  for (const aabb& b : boxes) {
    domain.expand(b.lo);
    domain.expand(b.hi);
    g.cell = std::max(g.cell, b.size().maxCoeff() + 2 * margin);
  }
  g.cell = std::max(g.cell, 1e-12 * std::max(domain.size().maxCoeff(), real(1)));
  g.lo = domain.lo - vec3::Constant(margin);
  for (int c = 0; c < 3; ++c)
    g.dims[static_cast<std::size_t>(c)] = static_cast<std::int64_t>((domain.size()[c] + 2 * margin) / g.cell) + 1;
  return g;
}

/// The pairs of all_pairs by binning into the grid `g` = layout_grid(boxes, margin) (see the file
/// comment). Refuses a layout that does not suit a grid (grid_layout::suits: use sweep_and_prune).
inline void uniform_grid(std::span<const aabb> boxes, real margin, const grid_layout& g, std::vector<block_pair>& pairs,
                         grid_workspace& w) {
  detail::require_boxes(boxes, margin, "uniform_grid");
  pairs.clear();
  if (boxes.empty()) return;
  require(g.suits(boxes.size()), "uniform_grid: ", g.cells(), " cells for ", boxes.size(), " blocks (cell ", g.cell,
          " m set by the largest box): use sweep_and_prune");
  const vec3& lo = g.lo;
  const real cell = g.cell;
  const auto& dims = g.dims;
  const auto cell_coord = [&](real x, int c) {
    return std::clamp<std::int64_t>(static_cast<std::int64_t>((x - lo[c]) / cell), 0, dims[static_cast<std::size_t>(c)] - 1);
  };
  const auto cell_id = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return (k * dims[1] + j) * dims[0] + i; };
  w.cell_of_entry.clear();
  w.block_of_entry.clear();
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    const aabb& box = boxes[b];
    for (std::int64_t k = cell_coord(box.lo.z() - margin, 2); k <= cell_coord(box.hi.z() + margin, 2); ++k)
      for (std::int64_t j = cell_coord(box.lo.y() - margin, 1); j <= cell_coord(box.hi.y() + margin, 1); ++j)
        for (std::int64_t i = cell_coord(box.lo.x() - margin, 0); i <= cell_coord(box.hi.x() + margin, 0); ++i) {
          w.cell_of_entry.push_back(cell_id(i, j, k));
          w.block_of_entry.push_back(static_cast<index_t>(b));
        }
  }
  w.order.resize(w.cell_of_entry.size());
  for (std::size_t e = 0; e < w.order.size(); ++e) w.order[e] = static_cast<index_t>(e);
  std::sort(w.order.begin(), w.order.end(), [&](index_t p, index_t q) {
    const auto cp = w.cell_of_entry[static_cast<std::size_t>(p)], cq = w.cell_of_entry[static_cast<std::size_t>(q)];
    return cp < cq || (cp == cq && p < q);
  });
  const real m2 = 2 * margin;
  for (std::size_t s = 0; s < w.order.size();) {
    std::size_t e = s;
    const auto cell_here = w.cell_of_entry[static_cast<std::size_t>(w.order[s])];
    while (e < w.order.size() && w.cell_of_entry[static_cast<std::size_t>(w.order[e])] == cell_here) ++e;
    for (std::size_t x = s; x < e; ++x)
      for (std::size_t y = x + 1; y < e; ++y) {
        const index_t a0 = w.block_of_entry[static_cast<std::size_t>(w.order[x])];
        const index_t b0 = w.block_of_entry[static_cast<std::size_t>(w.order[y])];
        const aabb& p = boxes[static_cast<std::size_t>(a0)];
        const aabb& q = boxes[static_cast<std::size_t>(b0)];
        if (!detail::boxes_overlap(p, q, m2)) continue;
        // Report the pair only in the cell holding the lower corner of the enlarged boxes'
        // intersection, so a pair sharing several cells is reported once.
        const vec3 corner = (p.lo - vec3::Constant(margin)).cwiseMax(q.lo - vec3::Constant(margin));
        if (cell_id(cell_coord(corner.x(), 0), cell_coord(corner.y(), 1), cell_coord(corner.z(), 2)) != cell_here) continue;
        pairs.push_back({std::min(a0, b0), std::max(a0, b0)});
      }
    s = e;
  }
  std::sort(pairs.begin(), pairs.end());
}

/// The same, laying out the grid first.
inline void uniform_grid(std::span<const aabb> boxes, real margin, std::vector<block_pair>& pairs, grid_workspace& w) {
  uniform_grid(boxes, margin, layout_grid(boxes, margin), pairs, w);
}

}  // namespace tessera::contact::detection
