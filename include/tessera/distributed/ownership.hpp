#pragma once
// distributed::rank_ownership: who owns what in a run split by blocks, from a block -> rank map
// (distributed/partition.hpp) and the scene's sub-contacts and bar elements. The rules
// (docs/architecture.md, "The distributed step"):
//
//   blocks       a block is owned by its rank; a block's gridpoints and zones follow it.
//   sub-contacts a sub-contact is owned by the rank of the lower-index block of its pair
//                (contact::face_contacts' block A): that rank books it in global sums, output and
//                checkpoints. It is EVALUATED by every rank that owns one of its blocks: a
//                sub-contact between two ranks is evaluated on both, from the same inputs in the
//                same order, so its state evolves to the same bits on both and each rank gathers
//                its force onto its own gridpoints without receiving forces.
//   ghosts       rank r's ghost blocks are the blocks of other ranks that share a sub-contact
//                with one of r's blocks; its ghost gridpoints are the gridpoints of
//                those blocks that r's evaluated sub-contacts touch (the halo r receives: their
//                displacements and velocities, each step).
//   bar nodes    a bar node is owned by the rank of its host block
//                (distributed::bar_node_host_blocks; a bar without any bonded node: rank 0); a bar
//                element is evaluated by the ranks of both its nodes, and a rank's ghost bar nodes
//                are the other ranks' nodes of the elements it evaluates.
//
// Every list is in increasing global index, so the order of a rank's sums is the order of the
// same terms in one process, and a receiver and its sender agree on the order of a halo without
// sending indices. Built once, O(sub-contacts + gridpoints + bar nodes) time, the lists and
// O(cut log cut) for the ghosts; read-only afterwards (concurrent reads are safe).

#include <algorithm>
#include <array>
#include <span>
#include <vector>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/tessellation.hpp"

namespace tessera::distributed {

/// A sub-contact as the ownership rules see it: its two blocks and its two gridpoints.
struct contact_pair {
  index_t block_a = invalid_index;  ///< the sub-contact's block A
  index_t block_b = invalid_index;  ///< the sub-contact's block B
  index_t node_a = invalid_index;  ///< its gridpoint on A
  index_t node_b = invalid_index;  ///< its gridpoint on B
};

/// The sub-contacts contact::face_contacts creates for a tessellation and its mesh, in its order
/// (shared faces in tessellation::shared_faces order, then the face's nodes: node k of face_a
/// paired with node k of face_b), without building the contact set.
[[nodiscard]] inline std::vector<contact_pair> face_contact_pairs(const geometry::tessellation& tess,
                                                                  const geometry::block_mesh& mesh) {
  std::vector<contact_pair> pairs;
  for (const auto& s : tess.shared_faces) {
    const index_t a0 = mesh.face_node_offsets[s.face_a], a1 = mesh.face_node_offsets[s.face_a + 1];
    const index_t b0 = mesh.face_node_offsets[s.face_b];
    require<geometry_error>(mesh.face_node_offsets[s.face_b + 1] - b0 == a1 - a0, "face_contact_pairs: faces ", s.face_a,
                            " and ", s.face_b, " of blocks ", s.cell_a, " and ", s.cell_b, " have ", a1 - a0, " and ",
                            mesh.face_node_offsets[s.face_b + 1] - b0, " nodes");
    for (index_t k = 0; k < a1 - a0; ++k)
      pairs.push_back({s.cell_a, s.cell_b, mesh.face_nodes[static_cast<std::size_t>(a0 + k)],
                       mesh.face_nodes[static_cast<std::size_t>(b0 + k)]});
  }
  return pairs;
}

/// The sub-contacts of any contact set that names their blocks and gridpoints (block_a, block_b,
/// node_a, node_b: contact::face_contacts, contact::detected_contacts between rebuilds), in its order.
template <class Contacts>
  requires requires(const Contacts& c, index_t i) {
    c.block_a(i);
    c.node_a(i);
  }
[[nodiscard]] std::vector<contact_pair> contact_pairs_of(const Contacts& contacts) {
  std::vector<contact_pair> pairs(static_cast<std::size_t>(contacts.subcontact_count()));
  for (index_t i = 0; i < contacts.subcontact_count(); ++i)
    pairs[static_cast<std::size_t>(i)] = {contacts.block_a(i), contacts.block_b(i), contacts.node_a(i), contacts.node_b(i)};
  return pairs;
}

/// The bar elements of an embedded reinforcement as pairs of bar node ids (element_node_a/b).
template <class Truss>
[[nodiscard]] std::vector<std::array<index_t, 2>> bar_element_pairs(const Truss& truss) {
  std::vector<std::array<index_t, 2>> elements(static_cast<std::size_t>(truss.element_count()));
  for (index_t e = 0; e < truss.element_count(); ++e)
    elements[static_cast<std::size_t>(e)] = {truss.element_node_a(e), truss.element_node_b(e)};
  return elements;
}

/// Per-rank lists in CSR form: list r is entries [offsets[r], offsets[r + 1]).
struct rank_lists {
  std::vector<index_t> offsets;  ///< start of each rank's list (size ranks + 1)
  std::vector<index_t> entries;  ///< the lists, one after another
  [[nodiscard]] std::span<const index_t> of(int r) const {  ///< List of rank r
    return {entries.data() + offsets[static_cast<std::size_t>(r)],
            static_cast<std::size_t>(offsets[static_cast<std::size_t>(r) + 1] - offsets[static_cast<std::size_t>(r)])};
  }
};
/// Which rank owns each block, gridpoint and sub-contact, and which gridpoints each rank holds as ghosts (file comment); refuses (invalid_input) a block map of the wrong size or a bad rank

class rank_ownership {
 public:
  /// Applies the rules of the file comment to a block -> rank map over `ranks` ranks, the mesh's
  /// gridpoints, the sub-contacts and, for bars, the host block of each bar node
  /// (bar_node_host_blocks; invalid_index = no host) and the elements' node pairs. Throws
  /// invalid_input naming the bad value: ranks < 1, a map whose size is not the mesh's block count,
  /// a rank outside [0, ranks), a rank without blocks, a sub-contact or bar node naming a block or
  /// gridpoint that does not exist or a gridpoint of another block, an element naming a bar node
  /// that does not exist.
  rank_ownership(std::span<const int> block_rank, int ranks, const geometry::block_mesh& mesh,
                 std::span<const contact_pair> contacts, std::span<const index_t> bar_node_host = {},
                 std::span<const std::array<index_t, 2>> bar_elements = {})
      : rank_ownership(whole_model{true, {}}, block_rank, ranks, mesh, contacts, bar_node_host, bar_elements) {}

  /// The ownership of one rank's local model (distributed::local_model::ownership): the same
  /// rules over the local blocks and sub-contacts, in local ids, except that a rank may own no
  /// local block (the ranks that are not this rank's neighbours). The other refusals as above.
  /// With bars, the rank of every bar node is given (`bar_node_rank`, the whole model's rule:
  /// the rank of its host block there; local_model::bar_node_ranks), since a local mesh may not
  /// hold a node's host block; `bar_elements` as above.
  [[nodiscard]] static rank_ownership of_local_model(std::span<const int> block_rank, int ranks,
                                                     const geometry::block_mesh& mesh,
                                                     std::span<const contact_pair> contacts,
                                                     std::span<const int> bar_node_rank = {},
                                                     std::span<const std::array<index_t, 2>> bar_elements = {}) {
    return rank_ownership(whole_model{false, bar_node_rank}, block_rank, ranks, mesh, contacts, {}, bar_elements);
  }

 private:
  struct whole_model {
    bool every_rank_owns;
    std::span<const int> bar_node_rank{};  ///< given ranks of the bar nodes (local models)
  };
  rank_ownership(whole_model whole, std::span<const int> block_rank, int ranks, const geometry::block_mesh& mesh,
                 std::span<const contact_pair> contacts, std::span<const index_t> bar_node_host,
                 std::span<const std::array<index_t, 2>> bar_elements)
      : ranks_(ranks), block_rank_(block_rank.begin(), block_rank.end()) {
    const index_t blocks = mesh.block_count(), gridpoints = mesh.gridpoint_count();
    require(ranks >= 1, "rank_ownership: rank count ", ranks, " must be >= 1");
    require(static_cast<index_t>(block_rank.size()) == blocks, "rank_ownership: the map has ", block_rank.size(),
            " entries for the mesh's ", blocks, " blocks");
    std::vector<index_t> owned_count(static_cast<std::size_t>(ranks), 0);
    for (index_t b = 0; b < blocks; ++b) {
      const int r = block_rank[static_cast<std::size_t>(b)];
      require(r >= 0 && r < ranks, "rank_ownership: block ", b, " has rank ", r, "; ranks are 0 .. ", ranks - 1);
      ++owned_count[static_cast<std::size_t>(r)];
    }
    for (int r = 0; r < ranks && whole.every_rank_owns; ++r)
      require(owned_count[static_cast<std::size_t>(r)] > 0, "rank_ownership: rank ", r, " of ", ranks, " owns no block");
    const auto check_node = [&](index_t i, index_t node, index_t block, const char* side) {
      require(block >= 0 && block < blocks, "rank_ownership: sub-contact ", i, " names block ", block, " (", side,
              "); blocks are 0 .. ", blocks - 1);
      require(node >= 0 && node < gridpoints, "rank_ownership: sub-contact ", i, " names gridpoint ", node, " (", side,
              "); gridpoints are 0 .. ", gridpoints - 1);
      require(mesh.gridpoint_block[static_cast<std::size_t>(node)] == block, "rank_ownership: sub-contact ", i,
              " names gridpoint ", node, " of block ", mesh.gridpoint_block[static_cast<std::size_t>(node)], " as ",
              side, " of block ", block);
    };
    for (std::size_t i = 0; i < contacts.size(); ++i) {
      check_node(static_cast<index_t>(i), contacts[i].node_a, contacts[i].block_a, "A");
      check_node(static_cast<index_t>(i), contacts[i].node_b, contacts[i].block_b, "B");
    }
    for (std::size_t k = 0; k < bar_node_host.size(); ++k)
      require(bar_node_host[k] == invalid_index || (bar_node_host[k] >= 0 && bar_node_host[k] < blocks),
              "rank_ownership: bar node ", k, " has host block ", bar_node_host[k], "; blocks are 0 .. ", blocks - 1);
    for (std::size_t k = 0; k < whole.bar_node_rank.size(); ++k)
      require(whole.bar_node_rank[k] >= 0 && whole.bar_node_rank[k] < ranks, "rank_ownership: bar node ", k,
              " has rank ", whole.bar_node_rank[k], "; ranks are 0 .. ", ranks - 1);
    const std::size_t bar_nodes = std::max(bar_node_host.size(), whole.bar_node_rank.size());
    for (std::size_t e = 0; e < bar_elements.size(); ++e)
      for (const index_t n : bar_elements[e])
        require(n >= 0 && n < static_cast<index_t>(bar_nodes), "rank_ownership: bar element ", e,
                " names bar node ", n, "; there are ", bar_nodes, " bar nodes with hosts");

    // Owned blocks, and the owner of every sub-contact and bar node.
    owned_blocks_ = bucket(blocks, [&](index_t b, auto&& put) { put(rank_of_block(b), b); });
    contact_owner_.resize(contacts.size());
    for (std::size_t i = 0; i < contacts.size(); ++i)
      contact_owner_[i] = rank_of_block(std::min(contacts[i].block_a, contacts[i].block_b));
    bar_node_rank_.resize(bar_nodes);
    for (std::size_t k = 0; k < bar_node_host.size(); ++k)
      bar_node_rank_[k] = bar_node_host[k] == invalid_index ? 0 : rank_of_block(bar_node_host[k]);
    for (std::size_t k = 0; k < whole.bar_node_rank.size(); ++k) bar_node_rank_[k] = whole.bar_node_rank[k];

    // What each rank evaluates, and its ghosts: one pass per list, each in increasing index.
    evaluated_contacts_ = bucket(static_cast<index_t>(contacts.size()), [&](index_t i, auto&& put) {
      const int ra = rank_of_block(contacts[static_cast<std::size_t>(i)].block_a);
      const int rb = rank_of_block(contacts[static_cast<std::size_t>(i)].block_b);
      put(ra, i);
      if (rb != ra) put(rb, i);
    });
    // Ghosts: (rank, item) candidates per rank, then sorted and made unique (memory O(cut)).
    std::vector<std::vector<index_t>> ghost_block(static_cast<std::size_t>(ranks)), ghost_node(ghost_block),
        ghost_bar(ghost_block);
    for (const contact_pair& c : contacts) {
      const int ra = rank_of_block(c.block_a), rb = rank_of_block(c.block_b);
      if (ra == rb) continue;
      ghost_block[static_cast<std::size_t>(ra)].push_back(c.block_b);
      ghost_node[static_cast<std::size_t>(ra)].push_back(c.node_b);
      ghost_block[static_cast<std::size_t>(rb)].push_back(c.block_a);
      ghost_node[static_cast<std::size_t>(rb)].push_back(c.node_a);
    }
    evaluated_elements_ = bucket(static_cast<index_t>(bar_elements.size()), [&](index_t e, auto&& put) {
      const index_t na = bar_elements[static_cast<std::size_t>(e)][0], nb = bar_elements[static_cast<std::size_t>(e)][1];
      const int ra = bar_node_rank_[static_cast<std::size_t>(na)], rb = bar_node_rank_[static_cast<std::size_t>(nb)];
      put(ra, e);
      if (rb == ra) return;
      put(rb, e);
      ghost_bar[static_cast<std::size_t>(ra)].push_back(nb);
      ghost_bar[static_cast<std::size_t>(rb)].push_back(na);
    });
    const auto sorted_lists = [](std::vector<std::vector<index_t>>& per) {
      rank_lists l;
      l.offsets.assign(1, 0);
      for (auto& p : per) {
        std::sort(p.begin(), p.end());
        p.erase(std::unique(p.begin(), p.end()), p.end());
        l.entries.insert(l.entries.end(), p.begin(), p.end());
        l.offsets.push_back(static_cast<index_t>(l.entries.size()));
      }
      return l;
    };
    ghost_blocks_ = sorted_lists(ghost_block);
    ghost_gridpoints_ = sorted_lists(ghost_node);
    ghost_bar_nodes_ = sorted_lists(ghost_bar);
    gridpoint_block_ = mesh.gridpoint_block;
  }

 public:
  [[nodiscard]] int ranks() const { return ranks_; }  ///< Number of ranks
  [[nodiscard]] int block_rank(index_t b) const { return rank_of_block(b); }  ///< Rank that owns block b
  [[nodiscard]] int gridpoint_rank(index_t g) const {  ///< Rank that owns gridpoint g
    return rank_of_block(gridpoint_block_[static_cast<std::size_t>(g)]);
  }
  /// The rank that books sub-contact i: the rank of the lower-index block of its pair.
  [[nodiscard]] int contact_owner(index_t i) const { return contact_owner_[static_cast<std::size_t>(i)]; }
  /// The rank that owns bar node n: the rank of its host block (rank 0 without one).
  [[nodiscard]] int bar_node_rank(index_t n) const { return bar_node_rank_[static_cast<std::size_t>(n)]; }
  [[nodiscard]] std::span<const index_t> owned_blocks(int r) const { return owned_blocks_.of(r); }  ///< Blocks rank r owns
  /// The sub-contacts rank r evaluates: those with a block of r (its own and the shared ones).
  [[nodiscard]] std::span<const index_t> evaluated_contacts(int r) const { return evaluated_contacts_.of(r); }
  /// The bar elements rank r evaluates: those with a node of r.
  [[nodiscard]] std::span<const index_t> evaluated_elements(int r) const { return evaluated_elements_.of(r); }
  /// Blocks of other ranks that share a sub-contact with one of r's blocks, increasing.
  [[nodiscard]] std::span<const index_t> ghost_blocks(int r) const { return ghost_blocks_.of(r); }
  /// Gridpoints of other ranks that r's evaluated sub-contacts touch: r's halo.
  [[nodiscard]] std::span<const index_t> ghost_gridpoints(int r) const { return ghost_gridpoints_.of(r); }
  /// Bar nodes of other ranks that r's evaluated elements touch.
  [[nodiscard]] std::span<const index_t> ghost_bar_nodes(int r) const { return ghost_bar_nodes_.of(r); }
  /// Rank r's ghost gridpoints owned by rank s, increasing: what s sends r each step, in the
  /// order both sides use.
  [[nodiscard]] std::vector<index_t> ghost_gridpoints_from(int r, int s) const {
    std::vector<index_t> out;
    for (const index_t g : ghost_gridpoints(r))
      if (gridpoint_rank(g) == s) out.push_back(g);
    return out;
  }
  /// Rank r's ghost bar nodes owned by rank s, increasing: the bar part of what s sends r.
  [[nodiscard]] std::vector<index_t> ghost_bar_nodes_from(int r, int s) const {
    std::vector<index_t> out;
    for (const index_t n : ghost_bar_nodes(r))
      if (bar_node_rank(n) == s) out.push_back(n);
    return out;
  }
  /// Bar nodes the ownership was built with (0 without reinforcement).
  [[nodiscard]] index_t bar_node_count() const { return static_cast<index_t>(bar_node_rank_.size()); }
  /// Rank r's ghost blocks owned by rank s, increasing.
  [[nodiscard]] std::vector<index_t> ghost_blocks_from(int r, int s) const {
    std::vector<index_t> out;
    for (const index_t b : ghost_blocks(r))
      if (block_rank(b) == s) out.push_back(b);
    return out;
  }

 private:
  [[nodiscard]] int rank_of_block(index_t b) const { return block_rank_[static_cast<std::size_t>(b)]; }
  /// Lists per rank from items visited in increasing order: each(item, put) calls put(rank, item).
  template <class Each>
  [[nodiscard]] rank_lists bucket(index_t items, Each&& each) const {
    std::vector<std::vector<index_t>> per(static_cast<std::size_t>(ranks_));
    for (index_t i = 0; i < items; ++i) each(i, [&](int r, index_t v) { per[static_cast<std::size_t>(r)].push_back(v); });
    rank_lists l;
    l.offsets.assign(1, 0);
    for (const auto& p : per) {
      l.entries.insert(l.entries.end(), p.begin(), p.end());
      l.offsets.push_back(static_cast<index_t>(l.entries.size()));
    }
    return l;
  }

  int ranks_ = 1;
  std::vector<int> block_rank_;
  std::vector<index_t> gridpoint_block_;
  std::vector<int> contact_owner_;
  std::vector<int> bar_node_rank_;
  rank_lists owned_blocks_, evaluated_contacts_, evaluated_elements_, ghost_blocks_, ghost_gridpoints_, ghost_bar_nodes_;
};

}  // namespace tessera::distributed
