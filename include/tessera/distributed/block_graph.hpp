#pragma once
// distributed::block_graph: the graph a domain decomposition by blocks partitions
// (docs/architecture.md, "The distributed step"). A vertex per block, weighted by the work a
// step spends on it; an edge per pair of blocks that a step couples (bonded faces, contacts,
// bar elements whose nodes have hosts in two blocks), weighted by the data a split of that pair
// would put in the halo. Nothing here needs MPI.
//
// Weights, in work units of one entity-step (zones and sub-contacts cost about the same per
// step, 20-35 ns each: docs/performance.md):
//   vertex  zones of the block + sub-contacts touching it + bar nodes hosted in it (a sub-contact
//           between two ranks is evaluated on both, so it counts on both of its blocks);
//   edge    sub-contacts between the two blocks + bar elements joining them.
// A caller with its own measure of cost (rigid blocks, a measured per-block time) sets the
// vertex weights of a block_graph_input before it builds the graph.
//
// Centroids (m): the mean of the block's gridpoints' reference positions, what a coordinate
// bisection needs (not the volume centroid; it only has to place the block).
//
// Building: a block_graph_input collects weights, centroids and edges (in any order, pairs
// repeated); the block_graph constructor validates them and merges each pair's edges into one
// symmetric CSR entry, summing the weights in input order, so the same input gives the same graph
// to the bit. Cost O(blocks + edges log edges). Read-only after construction: concurrent reads
// are safe.

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/tessellation.hpp"

namespace tessera::distributed {

/// An edge of the block graph: blocks a and b (a != b, any order) and its weight (work units).
struct block_edge {
  index_t a = invalid_index;  ///< one block
  index_t b = invalid_index;  ///< the other block
  real weight = 0;  ///< work units the edge carries
};

/// What a block_graph is built from; the add_* functions below append to it.
struct block_graph_input {
  std::vector<real> weight;      ///< per block, work units per step (>= 0)
  std::vector<vec3> centroid;    ///< per block (m)
  std::vector<block_edge> edges; ///< pairs may repeat; their weights are summed
};

/// The blocks of a mesh as graph vertices: weight = the block's zone count (0 for a mesh without
/// zones), centroid = the mean of
/// its gridpoints' reference positions (m). No edges yet.
[[nodiscard]] inline block_graph_input blocks_of_mesh(const geometry::block_mesh& mesh) {
  const index_t n = mesh.block_count();
  require(n > 0, "blocks_of_mesh: the mesh has ", n, " blocks");
  block_graph_input in;
  in.weight.resize(static_cast<std::size_t>(n));
  in.centroid.resize(static_cast<std::size_t>(n));
  // A mesh of rigid blocks may carry no zones (block_zone_offsets = {0}): weight 0 then.
  const bool zoned = mesh.block_zone_offsets.size() == static_cast<std::size_t>(n) + 1;
  for (index_t b = 0; b < n; ++b) {
    if (zoned) in.weight[static_cast<std::size_t>(b)] = mesh.block_zone_offsets[b + 1] - mesh.block_zone_offsets[b];
    vec3 sum = vec3::Zero();
    const index_t g0 = mesh.block_gridpoint_offsets[b], g1 = mesh.block_gridpoint_offsets[b + 1];
    require(g1 > g0, "blocks_of_mesh: block ", b, " has no gridpoints");
    for (index_t g = g0; g < g1; ++g) sum += mesh.gridpoints[static_cast<std::size_t>(g)];
    in.centroid[static_cast<std::size_t>(b)] = sum / static_cast<real>(g1 - g0);
  }
  return in;
}

/// Adds the bonded faces' sub-contacts as contact::face_contacts creates them (one per face node
/// of every shared face): +1 work unit to both blocks of each, and an edge per shared face
/// weighted by its sub-contact count. Throws invalid_input when the input does not have the
/// tessellation's cell count.
inline void add_face_subcontacts(block_graph_input& in, const geometry::tessellation& tess,
                                 const geometry::block_mesh& mesh) {
  require(static_cast<index_t>(in.weight.size()) == tess.cell_count(), "add_face_subcontacts: the graph has ",
          in.weight.size(), " blocks, the tessellation ", tess.cell_count(), " cells");
  for (const auto& s : tess.shared_faces) {
    const index_t count = mesh.face_node_offsets[s.face_a + 1] - mesh.face_node_offsets[s.face_a];
    in.weight[static_cast<std::size_t>(s.cell_a)] += count;
    in.weight[static_cast<std::size_t>(s.cell_b)] += count;
    in.edges.push_back({s.cell_a, s.cell_b, static_cast<real>(count)});
  }
}

/// The same from any contact set that names the blocks of its sub-contacts (block_a(i),
/// block_b(i): contact::face_contacts, contact::detected_contacts): +1 to both blocks per
/// sub-contact and one edge per sub-contact (the graph sums a pair's edges).
template <class Contacts>
  requires requires(const Contacts& c, index_t i) {
    c.subcontact_count();
    c.block_a(i);
    c.block_b(i);
  }
void add_subcontacts(block_graph_input& in, const Contacts& contacts) {
  const auto n = static_cast<index_t>(in.weight.size());
  for (index_t i = 0; i < contacts.subcontact_count(); ++i) {
    const index_t a = contacts.block_a(i), b = contacts.block_b(i);
    require(a >= 0 && a < n && b >= 0 && b < n, "add_subcontacts: sub-contact ", i, " joins blocks ", a, " and ", b,
            "; the graph has ", n, " blocks");
    in.weight[static_cast<std::size_t>(a)] += 1;
    in.weight[static_cast<std::size_t>(b)] += 1;
    in.edges.push_back({a, b, 1});
  }
}

/// The owner rule's fill for bar nodes without a host (`host[k]` invalid_index, `bar_of(k)` the
/// bar of node k; nodes of one bar consecutive, as embedded_truss numbers them): each takes the
/// host of the nearest hosted node before it on its bar, else after it; a bar with no hosted node
/// keeps invalid_index. Shared by bar_node_host_blocks and distributed::local_model.
template <class BarOf>
void fill_unhosted_bar_nodes(std::vector<index_t>& host, BarOf&& bar_of) {
  const auto n = static_cast<index_t>(host.size());
  for (index_t k = 1; k < n; ++k)
    if (host[static_cast<std::size_t>(k)] == invalid_index && bar_of(k) == bar_of(k - 1))
      host[static_cast<std::size_t>(k)] = host[static_cast<std::size_t>(k - 1)];
  for (index_t k = n - 2; k >= 0; --k)
    if (host[static_cast<std::size_t>(k)] == invalid_index && bar_of(k) == bar_of(k + 1))
      host[static_cast<std::size_t>(k)] = host[static_cast<std::size_t>(k + 1)];
}

/// The block hosting each bar node of an embedded reinforcement (reinforcement::embedded_truss:
/// host(n).zone, node_bar(n), element_node_a/b): the block of its host zone; a node outside the
/// concrete (unbonded) takes the host block of the nearest bonded node before it on its bar, else
/// after it; a bar with no bonded node gives invalid_index. This is the bar nodes' owner rule
/// of distributed/ownership.hpp.
template <class Truss>
[[nodiscard]] std::vector<index_t> bar_node_host_blocks(const geometry::block_mesh& mesh, const Truss& truss) {
  const index_t n = truss.node_count();
  std::vector<index_t> host(static_cast<std::size_t>(n), invalid_index);
  for (index_t k = 0; k < n; ++k) {
    const index_t z = truss.host(k).zone;
    if (z != invalid_index) host[static_cast<std::size_t>(k)] = mesh.zone_block[static_cast<std::size_t>(z)];
  }
  fill_unhosted_bar_nodes(host, [&](index_t k) { return truss.node_bar(k); });
  return host;
}

/// Adds the bars: +1 work unit per bar node to its host block (bar_node_host_blocks) and, for each
/// element whose two nodes have hosts in two blocks, an edge of weight 1 between them.
template <class Truss>
void add_bar_elements(block_graph_input& in, const geometry::block_mesh& mesh, const Truss& truss) {
  const std::vector<index_t> host = bar_node_host_blocks(mesh, truss);
  const auto n = static_cast<index_t>(in.weight.size());
  for (const index_t b : host)
    if (b != invalid_index) {
      require(b < n, "add_bar_elements: a bar node's host block ", b, " is not one of the graph's ", n, " blocks");
      in.weight[static_cast<std::size_t>(b)] += 1;
    }
  for (index_t e = 0; e < truss.element_count(); ++e) {
    const index_t a = host[static_cast<std::size_t>(truss.element_node_a(e))];
    const index_t b = host[static_cast<std::size_t>(truss.element_node_b(e))];
    if (a != invalid_index && b != invalid_index && a != b) in.edges.push_back({a, b, 1});
  }
}

/// The block graph: symmetric CSR adjacency with one entry per coupled pair (both directions),
/// neighbours in increasing block order.
class block_graph {
 public:
  block_graph() = default;

  /// Validates and builds (file comment). Throws invalid_input naming the bad value: no blocks,
  /// weight and centroid counts that differ, a negative or non-finite weight, a non-finite
  /// centroid, an edge to a block that does not exist, an edge from a block to itself.
  explicit block_graph(const block_graph_input& in) {
    const auto n = static_cast<index_t>(in.weight.size());
    require(n > 0, "block_graph: no blocks");
    require(in.centroid.size() == in.weight.size(), "block_graph: ", in.weight.size(), " weights but ",
            in.centroid.size(), " centroids");
    for (index_t b = 0; b < n; ++b) {
      const real w = in.weight[static_cast<std::size_t>(b)];
      require(std::isfinite(w) && w >= 0, "block_graph: block ", b, " has weight ", w, "; weights must be finite and >= 0");
      require(in.centroid[static_cast<std::size_t>(b)].allFinite(), "block_graph: block ", b, " has centroid (",
              in.centroid[static_cast<std::size_t>(b)].transpose(), ") m, not finite");
    }
    for (std::size_t e = 0; e < in.edges.size(); ++e) {
      const block_edge& d = in.edges[e];
      require(d.a >= 0 && d.a < n && d.b >= 0 && d.b < n, "block_graph: edge ", e, " joins blocks ", d.a, " and ", d.b,
              "; blocks are 0 .. ", n - 1);
      require(d.a != d.b, "block_graph: edge ", e, " joins block ", d.a, " to itself");
      require(std::isfinite(d.weight) && d.weight >= 0, "block_graph: edge ", e, " (blocks ", d.a, ", ", d.b,
              ") has weight ", d.weight, "; weights must be finite and >= 0");
    }
    weight_ = in.weight;
    centroid_ = in.centroid;
    // Both directions of every edge, stably sorted by (from, to): each pair's weights are summed in
    // input order.
    struct directed {
      index_t from, to;
      real weight;
    };
    std::vector<directed> all;
    all.reserve(2 * in.edges.size());
    for (const block_edge& d : in.edges) {
      all.push_back({d.a, d.b, d.weight});
      all.push_back({d.b, d.a, d.weight});
    }
    std::stable_sort(all.begin(), all.end(),
                     [](const directed& x, const directed& y) { return x.from != y.from ? x.from < y.from : x.to < y.to; });
    offsets_.assign(static_cast<std::size_t>(n) + 1, 0);
    for (std::size_t k = 0; k < all.size();) {
      std::size_t j = k;
      real w = 0;
      for (; j < all.size() && all[j].from == all[k].from && all[j].to == all[k].to; ++j) w += all[j].weight;
      neighbours_.push_back(all[k].to);
      edge_weight_.push_back(w);
      ++offsets_[static_cast<std::size_t>(all[k].from) + 1];
      k = j;
    }
    for (index_t b = 0; b < n; ++b) offsets_[static_cast<std::size_t>(b) + 1] += offsets_[static_cast<std::size_t>(b)];
  }

  [[nodiscard]] index_t block_count() const { return static_cast<index_t>(weight_.size()); }  ///< Number of blocks
  /// Work units of block b per step.
  [[nodiscard]] real weight(index_t b) const { return weight_[static_cast<std::size_t>(b)]; }
  [[nodiscard]] const std::vector<real>& weights() const { return weight_; }  ///< Work units per block
  /// Mean reference position of block b's gridpoints (m).
  [[nodiscard]] const vec3& centroid(index_t b) const { return centroid_[static_cast<std::size_t>(b)]; }
  /// The blocks coupled to b, increasing.
  [[nodiscard]] std::span<const index_t> neighbours(index_t b) const {
    return {neighbours_.data() + offsets_[static_cast<std::size_t>(b)], count(b)};
  }
  /// The weight of each of b's couplings, in neighbours(b) order (work units).
  [[nodiscard]] std::span<const real> edge_weights(index_t b) const {
    return {edge_weight_.data() + offsets_[static_cast<std::size_t>(b)], count(b)};
  }
  /// Number of coupled pairs (each counted once).
  [[nodiscard]] index_t edge_count() const { return static_cast<index_t>(neighbours_.size() / 2); }
  /// CSR offsets: block b's couplings are entries [offsets()[b], offsets()[b + 1]).
  [[nodiscard]] const std::vector<index_t>& offsets() const { return offsets_; }
  [[nodiscard]] const std::vector<index_t>& adjacency() const { return neighbours_; }  ///< Neighbours of each block, CSR (METIS's adjncy)
  [[nodiscard]] const std::vector<real>& adjacency_weights() const { return edge_weight_; }  ///< Weight of each adjacency entry (METIS's adjwgt)

 private:
  [[nodiscard]] std::size_t count(index_t b) const {
    return static_cast<std::size_t>(offsets_[static_cast<std::size_t>(b) + 1] - offsets_[static_cast<std::size_t>(b)]);
  }
  std::vector<real> weight_;
  std::vector<vec3> centroid_;
  std::vector<index_t> offsets_{0};
  std::vector<index_t> neighbours_;
  std::vector<real> edge_weight_;
};

}  // namespace tessera::distributed
