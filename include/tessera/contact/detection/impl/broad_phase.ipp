// The definitions of the larger functions that contact/detection/broad_phase.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../../../core/parallel.hpp"
#include "../broad_phase.hpp"

namespace tessera::contact::detection {

TESSERA_INLINE void sweep_and_prune(std::span<const aabb> boxes, real margin, std::vector<block_pair>& pairs, sweep_workspace& w) {
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

[[nodiscard]] TESSERA_INLINE grid_layout layout_grid(std::span<const aabb> boxes, real margin) {
  grid_layout g;
  if (boxes.empty()) return g;
  real mean = 0;
  for (const aabb& b : boxes) mean += b.size().maxCoeff() + 2 * margin;
  g.big = big_box_ratio * mean / static_cast<real>(boxes.size());
  aabb domain;
  for (const aabb& b : boxes) {
    if (const real size = b.size().maxCoeff() + 2 * margin; size <= g.big) {
      domain.expand(b.lo);
      domain.expand(b.hi);
      g.cell = std::max(g.cell, size);
    }
  }
  g.cell = std::max(g.cell, 1e-12 * std::max(domain.size().maxCoeff(), real(1)));
  g.lo = domain.lo - vec3::Constant(margin);
  for (int c = 0; c < 3; ++c)
    g.dims[static_cast<std::size_t>(c)] = static_cast<std::int64_t>((domain.size()[c] + 2 * margin) / g.cell) + 1;
  return g;
}

TESSERA_INLINE void uniform_grid(std::span<const aabb> boxes, real margin, const grid_layout& g, std::vector<block_pair>& pairs,
                                 grid_workspace& w, std::span<const std::uint8_t> only) {
  detail::require_boxes(boxes, margin, "uniform_grid");
  require(only.empty() || only.size() == boxes.size(), "uniform_grid: ", only.size(), " marks for ", boxes.size(),
          " boxes: give one per box, or none");
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
  // An incremental pass: the cells a marked box reaches, where its pairs are; only their entries
  // are binned.
  const bool marks = !only.empty();
  const auto marked = [&](index_t b) { return !marks || only[static_cast<std::size_t>(b)] != 0; };
  const auto for_cells = [&](const aabb& box, auto&& visit) {
    for (std::int64_t k = cell_coord(box.lo.z() - margin, 2); k <= cell_coord(box.hi.z() + margin, 2); ++k)
      for (std::int64_t j = cell_coord(box.lo.y() - margin, 1); j <= cell_coord(box.hi.y() + margin, 1); ++j)
        for (std::int64_t i = cell_coord(box.lo.x() - margin, 0); i <= cell_coord(box.hi.x() + margin, 0); ++i)
          visit(cell_id(i, j, k));
  };
  const auto n_cells = static_cast<std::size_t>(g.cells());
  const auto is_big = [&](std::size_t b) { return boxes[b].size().maxCoeff() + 2 * margin > g.big; };
  w.reached.assign(marks ? n_cells : 0, 0);
  if (marks)
    for (std::size_t b = 0; b < boxes.size(); ++b)
      if (only[b] != 0 && !is_big(b)) for_cells(boxes[b], [&](std::int64_t c) { w.reached[static_cast<std::size_t>(c)] = 1; });
  w.cell_of_entry.clear();
  w.block_of_entry.clear();
  for (std::size_t b = 0; b < boxes.size(); ++b)
    if (!is_big(b)) for_cells(boxes[b], [&](std::int64_t c) {
      if (marks && w.reached[static_cast<std::size_t>(c)] == 0) return;
      w.cell_of_entry.push_back(c);
      w.block_of_entry.push_back(static_cast<index_t>(b));
    });
  // The entries by cell, then by entry (a counting sort: at most 64 cells a block, grid_layout::suits).
  w.starts.assign(n_cells + 1, 0);
  for (const std::int64_t c : w.cell_of_entry) ++w.starts[static_cast<std::size_t>(c) + 1];
  for (std::size_t c = 1; c < w.starts.size(); ++c) w.starts[c] += w.starts[c - 1];
  w.order.resize(w.cell_of_entry.size());
  for (std::size_t e = 0; e < w.order.size(); ++e)
    w.order[w.starts[static_cast<std::size_t>(w.cell_of_entry[e])]++] = static_cast<index_t>(e);
  const real m2 = 2 * margin;
  // The pairs of the cells whose entries start in [first, last) of the order (a cell's entries
  // all go to the share holding its first one), and of the big boxes against boxes [x0, x1).
  const auto share = [&](std::size_t first, std::size_t last, std::size_t x0, std::size_t x1, std::vector<block_pair>& out) {
    out.clear();
    const auto cell_at = [&](std::size_t i) { return w.cell_of_entry[static_cast<std::size_t>(w.order[i])]; };
    std::size_t s = first;
    while (s > 0 && s < w.order.size() && cell_at(s - 1) == cell_at(s)) ++s;
    while (s < last) {
      std::size_t e = s;
      const auto cell_here = cell_at(s);
      while (e < w.order.size() && cell_at(e) == cell_here) ++e;
      // Each unordered pair of the cell's entries once, and (marks) only those with a marked
      // block: entry x marked, then y any other entry but a marked one before x.
      for (std::size_t x = s; x < e; ++x) {
        const index_t a0 = w.block_of_entry[static_cast<std::size_t>(w.order[x])];
        if (!marked(a0)) continue;
        for (std::size_t y = marks ? s : x + 1; y < e; ++y) {
          const index_t b0 = w.block_of_entry[static_cast<std::size_t>(w.order[y])];
          if (marks && (y == x || (y < x && marked(b0)))) continue;
          const aabb& p = boxes[static_cast<std::size_t>(a0)];
          const aabb& q = boxes[static_cast<std::size_t>(b0)];
          if (!detail::boxes_overlap(p, q, m2)) continue;
          // Report the pair only in the cell holding the lower corner of the enlarged boxes'
          // intersection, so a pair sharing several cells is reported once.
          const vec3 corner = (p.lo - vec3::Constant(margin)).cwiseMax(q.lo - vec3::Constant(margin));
          if (cell_id(cell_coord(corner.x(), 0), cell_coord(corner.y(), 1), cell_coord(corner.z(), 2)) != cell_here) continue;
          out.push_back({std::min(a0, b0), std::max(a0, b0)});
        }
      }
      s = e;
    }
    // The big boxes, against every box (two big ones once).
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      if (!is_big(b)) continue;
      const auto a0 = static_cast<index_t>(b);
      for (std::size_t x = x0; x < x1; ++x) {
        const auto b0 = static_cast<index_t>(x);
        if (x == b || (x < b && is_big(x)) || (!marked(a0) && !marked(b0))) continue;
        if (detail::boxes_overlap(boxes[b], boxes[x], m2)) out.push_back({std::min(a0, b0), std::max(a0, b0)});
      }
    }
    std::sort(out.begin(), out.end());
  };
  // Several threads: each its share of the entries and of the boxes, its pairs sorted, and the
  // sorted lists merged in share order (the pairs are distinct: the one thread's list).
  const std::size_t entries = w.order.size(), n = boxes.size();
  const auto shares = static_cast<std::size_t>(entries >= 64 && max_threads() > 1 ? max_threads() : 1);
  if (shares == 1) return share(0, entries, 0, n, pairs);
  if (w.share_pairs.size() < shares) w.share_pairs.resize(shares);
  parallel_for(static_cast<std::int64_t>(shares), [&](std::int64_t t) {
    const auto i = static_cast<std::size_t>(t);
    share(entries * i / shares, entries * (i + 1) / shares, n * i / shares, n * (i + 1) / shares, w.share_pairs[i]);
  }, 1);
  const auto& first = w.share_pairs[0];
  const auto& second = w.share_pairs[1];
  pairs.resize(first.size() + second.size());
  std::merge(first.begin(), first.end(), second.begin(), second.end(), pairs.begin());
  for (std::size_t i = 2; i < shares; ++i) {
    const auto& more = w.share_pairs[i];
    w.merged.resize(pairs.size() + more.size());
    std::merge(pairs.begin(), pairs.end(), more.begin(), more.end(), w.merged.begin());
    pairs.swap(w.merged);
  }
}

}  // namespace tessera::contact::detection
