#pragma once
// Decomposition by blocks: which rank owns each block of a distributed run (docs/architecture.md,
// "The distributed step"). Two partitioners of a distributed::block_graph, each returning a
// block -> rank vector, and the figures that judge a partition. Nothing here needs MPI: rank 0 (or
// every rank, to the same bits) partitions before the run.
//
//   partition_blocks_rcb    recursive coordinate bisection of the block centroids by weight: no
//                           dependency, geometric slabs, blind to the edges (a cut follows a
//                           plane whatever the blocks' couplings across it);
//   partition_blocks_metis  METIS's multilevel k-way partition of the graph (METIS_PartGraphKway),
//                           which minimises the edge cut (the halo) under a balance constraint;
//                           only where TESSERA_HAVE_METIS (CMake: TESSERA_METIS, tessera::metis).
// Why both: a bonded tessellation's halo is its cut sub-contacts, which METIS minimises and RCB
// only bounds by a plane's area; RCB needs no library and is the fallback, and the choice for
// scenes whose blocks move far (detected contacts), where a geometric cut is recomputed cheaply
// as blocks migrate. Both are deterministic: the same graph and rank count give the same map on
// every rank and every run (METIS with a fixed seed).
//
// partition_quality: the edge cut (sum of the weights of the edges whose blocks have two ranks,
// work units: the sub-contacts evaluated twice) and the load imbalance max_r W_r / mean_r W_r.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "block_graph.hpp"

#ifdef TESSERA_HAVE_METIS
#include <metis.h>
#endif

namespace tessera::distributed {

namespace detail {

inline void require_rank_count(const block_graph& g, int ranks, const char* who) {
  require(ranks >= 1 && ranks <= g.block_count(), who, ": rank count ", ranks, " must be >= 1 and <= the ",
          g.block_count(), " blocks (every rank owns at least one block)");
}

/// Assigns ranks [r0, r0 + k) to blocks[begin, end) by recursive bisection (partition_blocks_rcb).
inline void bisect(const block_graph& g, std::vector<index_t>& blocks, std::size_t begin, std::size_t end, int r0, int k,
                   std::vector<int>& rank) {
  if (k == 1) {
    for (std::size_t i = begin; i < end; ++i) rank[static_cast<std::size_t>(blocks[i])] = r0;
    return;
  }
  // The longest extent of the centroids' bounding box (the lowest axis on a tie).
  vec3 lo = g.centroid(blocks[begin]), hi = lo;
  for (std::size_t i = begin; i < end; ++i) {
    lo = lo.cwiseMin(g.centroid(blocks[i]));
    hi = hi.cwiseMax(g.centroid(blocks[i]));
  }
  int axis = 0;
  for (int d = 1; d < 3; ++d)
    if (hi[d] - lo[d] > hi[axis] - lo[axis]) axis = d;
  const auto first = blocks.begin() + static_cast<std::ptrdiff_t>(begin);
  const auto last = blocks.begin() + static_cast<std::ptrdiff_t>(end);
  std::sort(first, last, [&](index_t a, index_t b) {
    const real xa = g.centroid(a)[axis], xb = g.centroid(b)[axis];
    return xa != xb ? xa < xb : a < b;
  });
  // Split where the prefix weight comes closest to k1/k of the total (the first such place),
  // leaving each side at least as many blocks as ranks. All weights zero: count blocks instead.
  const int k1 = k / 2;
  real total = 0;
  for (std::size_t i = begin; i < end; ++i) total += g.weight(blocks[i]);
  const bool by_count = !(total > 0);
  const auto weight_of = [&](std::size_t i) { return by_count ? real(1) : g.weight(blocks[i]); };
  if (by_count) total = static_cast<real>(end - begin);
  const real target = total * k1 / k;
  const std::size_t s_min = begin + static_cast<std::size_t>(k1), s_max = end - static_cast<std::size_t>(k - k1);
  real prefix = 0;
  for (std::size_t i = begin; i < s_min; ++i) prefix += weight_of(i);
  std::size_t split = s_min;
  real best = std::abs(prefix - target);
  for (std::size_t s = s_min + 1; s <= s_max; ++s) {
    prefix += weight_of(s - 1);
    if (std::abs(prefix - target) < best) {
      best = std::abs(prefix - target);
      split = s;
    }
  }
  bisect(g, blocks, begin, split, r0, k1, rank);
  bisect(g, blocks, split, end, r0 + k1, k - k1, rank);
}

}  // namespace detail

/// Recursive coordinate bisection of the blocks into `ranks` parts (file comment): a set of blocks
/// for k ranks is sorted along the longest extent of its centroids (ties by block id) and cut
/// where the weight before the cut comes closest to floor(k/2)/k of the set's weight; each side
/// recurses with floor(k/2) and k - floor(k/2) ranks. Returns the rank of each block. Equal
/// weights on a regular grid whose layers divide evenly give slabs of equal block counts.
/// O(blocks log blocks log ranks). Throws invalid_input for ranks < 1 or > the block count.
[[nodiscard]] inline std::vector<int> partition_blocks_rcb(const block_graph& g, int ranks) {
  detail::require_rank_count(g, ranks, "partition_blocks_rcb");
  std::vector<index_t> blocks(static_cast<std::size_t>(g.block_count()));
  std::iota(blocks.begin(), blocks.end(), index_t{0});
  std::vector<int> rank(blocks.size(), 0);
  detail::bisect(g, blocks, 0, blocks.size(), 0, ranks, rank);
  return rank;
}

/// The balance and the seed of partition_blocks_metis.
struct metis_options {
  /// METIS_OPTION_UFACTOR: the largest part may weigh (1 + ufactor/1000) times the mean (30: 3 %).
  int ufactor = 30;
  /// METIS_OPTION_SEED: METIS is deterministic for a given seed (and single-threaded).
  int seed = 1;
  /// METIS_OPTION_NCUTS: partitions computed, the one of least cut kept. With one, METIS cut a
  /// 20 x 20 grid 10-15 % worse than a bisection's straight lines for 2 and 4 ranks; with ten it
  /// matches them there and cuts a 1 000-block Voronoi cube 13 % less than bisection for 2-4 ranks
  /// (test_distributed "[metis]"). Partitioning runs once per run, so ten times its cost is cheap.
  int attempts = 10;
};

#ifdef TESSERA_HAVE_METIS
namespace detail {
/// METIS takes integer weights: values that are all integers and sum to at most 2^30 are passed
/// as they are, others are scaled so that they sum to 2^30 and rounded to the nearest integer.
inline std::vector<idx_t> metis_weights(std::span<const real> w) {
  const real total = std::accumulate(w.begin(), w.end(), real(0));
  const real limit = real(1 << 30);
  const bool integral = std::all_of(w.begin(), w.end(), [](real x) { return x == std::floor(x); });
  const real scale = integral && total <= limit ? 1 : (total > 0 ? limit / total : 1);
  std::vector<idx_t> out(w.size());
  for (std::size_t i = 0; i < w.size(); ++i) out[i] = static_cast<idx_t>(std::llround(w[i] * scale));
  return out;
}
}  // namespace detail

/// METIS's k-way partition of the block graph into `ranks` parts (METIS_PartGraphKway: vertex
/// weights = block weights, edge weights = coupling weights, made integers by
/// detail::metis_weights; options: ufactor, seed and attempts, all else METIS's defaults). Returns the rank
/// of each block; the same graph, ranks and options give the same map. Throws invalid_input for
/// ranks < 1 or > the block count or a bad option, geometry_error if METIS fails (naming its
/// return code) or leaves a rank without blocks.
[[nodiscard]] inline std::vector<int> partition_blocks_metis(const block_graph& g, int ranks, const metis_options& o = {}) {
  detail::require_rank_count(g, ranks, "partition_blocks_metis");
  require(o.ufactor >= 1, "partition_blocks_metis: ufactor = ", o.ufactor, " must be >= 1 (per mille above the mean)");
  require(o.attempts >= 1, "partition_blocks_metis: attempts = ", o.attempts, " must be >= 1");
  const index_t n = g.block_count();
  std::vector<int> rank(static_cast<std::size_t>(n), 0);
  if (ranks == 1) return rank;
  idx_t nvtxs = n, ncon = 1, nparts = ranks, objval = 0;
  std::vector<idx_t> xadj(g.offsets().begin(), g.offsets().end());
  std::vector<idx_t> adjncy(g.adjacency().begin(), g.adjacency().end());
  std::vector<idx_t> vwgt = detail::metis_weights(g.weights());
  std::vector<idx_t> adjwgt = detail::metis_weights(g.adjacency_weights());
  std::vector<idx_t> part(static_cast<std::size_t>(n), 0);
  std::vector<idx_t> options(METIS_NOPTIONS);
  METIS_SetDefaultOptions(options.data());
  options[METIS_OPTION_NUMBERING] = 0;
  options[METIS_OPTION_UFACTOR] = o.ufactor;
  options[METIS_OPTION_SEED] = o.seed;
  options[METIS_OPTION_NCUTS] = o.attempts;
  const int rc = METIS_PartGraphKway(&nvtxs, &ncon, xadj.data(), adjncy.empty() ? nullptr : adjncy.data(), vwgt.data(),
                                     nullptr, adjwgt.empty() ? nullptr : adjwgt.data(), &nparts, nullptr, nullptr,
                                     options.data(), &objval, part.data());
  require<geometry_error>(rc == METIS_OK, "partition_blocks_metis: METIS_PartGraphKway returned ", rc,
                          " (METIS_OK = ", METIS_OK, ") for ", n, " blocks and ", ranks, " ranks");
  std::vector<index_t> owned(static_cast<std::size_t>(ranks), 0);
  for (index_t b = 0; b < n; ++b) {
    rank[static_cast<std::size_t>(b)] = static_cast<int>(part[static_cast<std::size_t>(b)]);
    ++owned[static_cast<std::size_t>(part[static_cast<std::size_t>(b)])];
  }
  for (int r = 0; r < ranks; ++r)
    require<geometry_error>(owned[static_cast<std::size_t>(r)] > 0, "partition_blocks_metis: METIS left rank ", r, " of ",
                            ranks, " without blocks (", n, " blocks); use fewer ranks or partition_blocks_rcb");
  return rank;
}
#endif

/// The figures of a partition (partition_quality).
struct partition_report {
  real edge_cut = 0;             ///< sum of the weights of the edges between two ranks (work units)
  index_t cut_pairs = 0;         ///< number of coupled block pairs between two ranks
  real imbalance = 1;            ///< max_r W_r / mean_r W_r (1 = perfect; 1 when the total is 0)
  std::vector<real> rank_weight; ///< W_r, the block weights owned by each rank (work units)
  std::vector<index_t> rank_blocks;  ///< blocks owned by each rank
};

/// Edge cut and load imbalance of a block -> rank map over `ranks` ranks. Throws invalid_input for
/// ranks < 1, a map whose size is not the block count, or a rank outside [0, ranks).
[[nodiscard]] inline partition_report partition_quality(const block_graph& g, std::span<const int> block_rank, int ranks) {
  require(ranks >= 1, "partition_quality: rank count ", ranks, " must be >= 1");
  require(static_cast<index_t>(block_rank.size()) == g.block_count(), "partition_quality: the map has ",
          block_rank.size(), " entries for ", g.block_count(), " blocks");
  partition_report q;
  q.rank_weight.assign(static_cast<std::size_t>(ranks), 0);
  q.rank_blocks.assign(static_cast<std::size_t>(ranks), 0);
  for (index_t b = 0; b < g.block_count(); ++b) {
    const int r = block_rank[static_cast<std::size_t>(b)];
    require(r >= 0 && r < ranks, "partition_quality: block ", b, " has rank ", r, "; ranks are 0 .. ", ranks - 1);
    q.rank_weight[static_cast<std::size_t>(r)] += g.weight(b);
    ++q.rank_blocks[static_cast<std::size_t>(r)];
  }
  for (index_t b = 0; b < g.block_count(); ++b) {
    const auto nb = g.neighbours(b);
    const auto w = g.edge_weights(b);
    for (std::size_t k = 0; k < nb.size(); ++k)
      if (nb[k] > b && block_rank[static_cast<std::size_t>(nb[k])] != block_rank[static_cast<std::size_t>(b)]) {
        q.edge_cut += w[k];
        ++q.cut_pairs;
      }
  }
  const real total = std::accumulate(q.rank_weight.begin(), q.rank_weight.end(), real(0));
  if (total > 0) q.imbalance = *std::max_element(q.rank_weight.begin(), q.rank_weight.end()) / (total / ranks);
  return q;
}

}  // namespace tessera::distributed
