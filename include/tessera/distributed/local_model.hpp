#pragma once
// distributed::local_model: what one rank of a split run needs to hold, cut out of the whole
// scene's tessellation and block mesh: its own blocks and their ghost blocks (the blocks of other
// ranks that share a face with one of its own), renumbered locally. A solver built on the local
// model holds, per rank, the memory of its own blocks plus one layer of ghosts, instead of the
// whole model (docs/guide.md, "Local storage per rank"):
//
//   distributed::block_graph_input in = distributed::blocks_of_mesh(mesh);
//   distributed::add_face_subcontacts(in, tess, mesh);
//   const auto map = distributed::broadcast_partition(distributed::block_graph(in), MPI_COMM_WORLD);  // split_run.hpp
//   distributed::local_model lm(tess, mesh, map, ranks, rank);       // then the whole scene may go
//   my_solver s(lm.tess, lm.mesh, block_params, contact_params, {}, options);  // options.mass_scaling_dt or dt
//   const bc::node_group top = lm.gridpoints_on_plane(s.gridpoints(), 2, length, tol, MPI_COMM_WORLD);
//   if (!top.empty()) s.prescribe_velocity(top, vec3(0, 0, rate), bc::components::z);  // a rank may hold none
//   const distributed::rank_ownership own = lm.ownership(s.contacts());
//   distributed::stepper<my_solver> step(s, lm.mesh, own, MPI_COMM_WORLD);
//   distributed::require_same_time_step(s.dt(), MPI_COMM_WORLD);     // every rank's dt alike
//   ... step.step(); lm.reaction_sum(s.gridpoints(), top, MPI_COMM_WORLD) ...
//
// Why the bits stay one process's: local ids keep the global order (blocks in increasing global
// id, a block's gridpoints and zones in their global order, faces cell by cell, the shared faces
// filtered in their global order), so every list the ownership and the halo sort by index is in
// global order on both sides of a message, and every own gridpoint sees all its zones and
// sub-contacts, summed in one process's order (its block is whole here, and so is every block
// that shares a face with it). The stepper's rules apply unchanged (stepper.hpp); the test
// "[local]" in tests/test_distributed_local.cpp compares u, v, reactions, contact states and the
// platen load with one process, bit for bit.
//
// What the local tessellation and mesh are: a valid tessellation and block_mesh of the kept
// blocks (the same cells, faces, vertices and gridpoints, compacted), except that a face whose
// neighbour is not kept has face_neighbor = outside_neighbor and face_twin = invalid_index (it is
// an interior face of the whole scene, not a side of the box). Building the local model reads the
// whole scene once (O(blocks + faces + gridpoints + zones)); the scene may then be released.
// What must agree across ranks and is not checked here: the solver options (give options.dt or
// options.mass_scaling_dt; an automatic dt or mass_scaling_ratio are resolved from the gridpoints
// a rank holds: require_same_time_step refuses a disagreement), the supports (chosen by position,
// local_model::gridpoints_on_plane, they select the same gridpoints in both numberings; a rank
// may hold none of a support's).
// Covered: deformable blocks bonded by face_contacts, embedded bars (every rank keeps every bar
// node; a node's bond lives on the rank of its host block, the only one that hosts it: bar_params),
// gravity, supports, checkpoints per rank, output per rank (distributed/local_vtk.hpp). Not yet:
// applied forces computed from the whole state (a platen's), detected contacts and rigid blocks.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/tessellation.hpp"
#include "../reinforcement/bar.hpp"
#include "../reinforcement/embedding.hpp"
#include "../solver/balance.hpp"
#include "../solver/boundary.hpp"
#include "block_graph.hpp"
#include "ownership.hpp"

#ifdef TESSERA_HAVE_MPI
#include <mpi.h>

#include "detail/non_finite.hpp"
#endif

namespace tessera::distributed {

/// face_neighbor of a local face whose neighbour block is not in the local model.
inline constexpr index_t outside_neighbor = -1000;

/// The part of a model one rank holds: its own blocks and their ghosts, with the maps to the global ids
class local_model {
 public:
  geometry::tessellation tess;  ///< the kept cells, locally numbered (file comment)
  geometry::block_mesh mesh;    ///< their gridpoints, zones and faces, locally numbered

  /// Cuts rank `rank`'s local model out of the whole scene (`whole_tess`, `whole_mesh` built from
  /// it) under the block -> rank map `block_rank` over `ranks` ranks (the same on every rank).
  /// Throws invalid_input naming the bad value: ranks < 1, rank outside [0, ranks), a map whose
  /// size is not the mesh's block count or that names a rank outside [0, ranks), a rank that owns
  /// no block, a mesh whose block count is not the tessellation's cell count.
  local_model(const geometry::tessellation& whole_tess, const geometry::block_mesh& whole_mesh,
              std::span<const int> block_rank, int ranks, int rank)
      : local_model(whole_tess, whole_mesh, block_rank, ranks, rank, std::vector<reinforcement::bar>{}) {}

  /// The same for a scene with bars embedded (reinforcement::embedded_truss, `bars` its
  /// params.bars): every rank keeps every bar node (a bar has O(100) of them), and each node's
  /// rank is the whole model's rule (distributed/ownership.hpp: the rank of its host block,
  /// located here in the whole mesh; an unhosted node takes its bar's nearest hosted node's).
  /// Build the solver with bar_params(params) and the ownership with ownership(contacts, truss).
  /// Throws as above, and invalid_input (the truss's message) for a node of a bonded bar outside
  /// every zone of the whole mesh.
  local_model(const geometry::tessellation& whole_tess, const geometry::block_mesh& whole_mesh,
              std::span<const int> block_rank, int ranks, int rank, const std::vector<reinforcement::bar>& bars)
      : rank_(rank), ranks_(ranks) {
    const index_t blocks = whole_mesh.block_count();
    require(ranks >= 1, "local_model: rank count ", ranks, " must be >= 1");
    require(rank >= 0 && rank < ranks, "local_model: rank ", rank, " is outside 0 .. ", ranks - 1);
    require(static_cast<index_t>(block_rank.size()) == blocks, "local_model: the map has ", block_rank.size(),
            " entries for the mesh's ", blocks, " blocks");
    require(whole_tess.cell_count() == blocks, "local_model: the tessellation has ", whole_tess.cell_count(),
            " cells, the mesh ", blocks, " blocks");
    index_t owned = 0;
    for (index_t b = 0; b < blocks; ++b) {
      const int r = block_rank[at(b)];
      require(r >= 0 && r < ranks, "local_model: block ", b, " has rank ", r, "; ranks are 0 .. ", ranks - 1);
      owned += r == rank ? 1 : 0;
    }
    require(owned > 0, "local_model: rank ", rank, " of ", ranks, " owns no block");
    global_block_count_ = blocks;
    global_gridpoint_count_ = whole_mesh.gridpoint_count();

    // Kept blocks: own ones and those sharing a face with one, in increasing global id.
    std::vector<index_t> local_of_block(at(blocks), invalid_index);
    std::vector<char> keep(at(blocks), 0);
    for (index_t b = 0; b < blocks; ++b) keep[at(b)] = block_rank[at(b)] == rank ? 1 : 0;
    for (const auto& sf : whole_tess.shared_faces) {
      const bool a = block_rank[at(sf.cell_a)] == rank, b = block_rank[at(sf.cell_b)] == rank;
      if (a && !b) keep[at(sf.cell_b)] = 1;
      if (b && !a) keep[at(sf.cell_a)] = 1;
    }
    for (index_t b = 0; b < blocks; ++b)
      if (keep[at(b)]) {
        local_of_block[at(b)] = static_cast<index_t>(global_block_.size());
        global_block_.push_back(b);
        block_rank_.push_back(block_rank[at(b)]);
      }
    cut_tessellation(whole_tess, local_of_block);
    cut_mesh(whole_mesh, local_of_block);
    if (!bars.empty()) rank_bar_nodes(whole_mesh, block_rank, bars);
  }

  [[nodiscard]] int rank() const { return rank_; }  ///< This rank
  [[nodiscard]] int ranks() const { return ranks_; }  ///< Number of ranks
  /// Blocks, gridpoints of the whole scene.
  [[nodiscard]] index_t global_block_count() const { return global_block_count_; }
  [[nodiscard]] index_t global_gridpoint_count() const { return global_gridpoint_count_; }  ///< Gridpoints of the whole model
  /// Global id of local block b, gridpoint g, zone z (each increasing in the local id).
  [[nodiscard]] index_t global_block(index_t b) const { return global_block_[at(b)]; }
  [[nodiscard]] index_t global_gridpoint(index_t g) const { return global_gridpoint_[at(g)]; }  ///< Global id of local gridpoint g
  [[nodiscard]] index_t global_zone(index_t z) const { return global_zone_[at(z)]; }  ///< Global id of local zone z
  /// Global ids of the local blocks / gridpoints, in local order.
  [[nodiscard]] std::span<const index_t> global_blocks() const { return global_block_; }
  [[nodiscard]] std::span<const index_t> global_gridpoints() const { return global_gridpoint_; }  ///< Global ids of the local gridpoints
  /// The rank owning local block b, and the local block -> rank map.
  [[nodiscard]] int block_rank(index_t b) const { return block_rank_[at(b)]; }
  [[nodiscard]] std::span<const int> block_ranks() const { return block_rank_; }  ///< The rank of every block of the whole model
  /// Blocks this rank owns (the rest of the local blocks are ghosts).
  [[nodiscard]] index_t own_block_count() const {
    return static_cast<index_t>(std::count(block_rank_.begin(), block_rank_.end(), rank_));
  }
  /// Whether local gridpoint g belongs to an own block.
  [[nodiscard]] bool owns_gridpoint(index_t g) const { return block_rank_[at(mesh.gridpoint_block[at(g)])] == rank_; }

  /// The rank_ownership of the local model, in local ids, for a distributed::stepper of a solver
  /// built on it (`contacts`: its contact set, e.g. s.contacts()). Ranks that own no local
  /// block are allowed (they are not neighbours).
  template <class Contacts>
  [[nodiscard]] rank_ownership ownership(const Contacts& contacts) const {
    require(bar_node_rank_.empty(), "local_model::ownership: the model has ", bar_node_rank_.size(),
            " bar nodes; pass the solver's reinforcement too (ownership(s.contacts(), s.reinforcement()))");
    return rank_ownership::of_local_model(block_rank_, ranks_, mesh, contact_pairs_of(contacts));
  }
  /// The same with the bars of an embedded_truss built from bar_params: each bar node on the rank
  /// the whole model gives it. Throws invalid_input when the truss has another node count.
  template <class Contacts, class Truss>
  [[nodiscard]] rank_ownership ownership(const Contacts& contacts, const Truss& truss) const {
    require(truss.node_count() == static_cast<index_t>(bar_node_rank_.size()), "local_model::ownership: the truss has ",
            truss.node_count(), " bar nodes, the local model ", bar_node_rank_.size(),
            " (build the model with the truss's bars)");
    return rank_ownership::of_local_model(block_rank_, ranks_, mesh, contact_pairs_of(contacts), bar_node_rank_,
                                          bar_element_pairs(truss));
  }

  /// The rank of every bar node (discretisation order; empty without bars).
  [[nodiscard]] std::span<const int> bar_node_ranks() const { return bar_node_rank_; }
  /// `p` (an embedded_truss's params, with the bars the model was built with) for a solver on
  /// this model: only this rank's bar nodes are hosted in the local mesh (params::hosted_nodes),
  /// so every host zone is an own block's and is the one the whole model finds. Throws
  /// invalid_input when p's bars discretise to other nodes than the model's.
  template <class Params>
  [[nodiscard]] Params bar_params(Params p) const {
    const reinforcement::bar_discretisation d = reinforcement::discretise_bars(p.bars);
    require(d.nodes == bar_nodes_, "local_model::bar_params: the bars give ", d.node_count(),
            " nodes that are not the ", bar_nodes_.size(), " the local model was built with");
    p.hosted_nodes.assign(bar_node_rank_.size(), 0);
    for (std::size_t k = 0; k < bar_node_rank_.size(); ++k) p.hosted_nodes[k] = bar_node_rank_[k] == rank_ ? 1 : 0;
    return p;
  }

#ifdef TESSERA_HAVE_MPI
  /// The local gridpoints (of own and ghost blocks) whose reference position lies on the plane
  /// X[axis] = value within tol (m), in increasing id: a rank's part of a support. Unlike
  /// solver::gridpoints_on_plane, a rank may select none (apply the support where the group is
  /// not empty: `if (!g.empty()) s.fix(g)`); throws invalid_input, on every rank alike, when no
  /// rank selects any gridpoint, or for a bad axis or tolerance. Every rank of `comm` must call it.
  [[nodiscard]] bc::node_group gridpoints_on_plane(const node_set& gridpoints, int axis, real value, real tol,
                                                   MPI_Comm comm) const {
    require(axis >= 0 && axis < 3, "local_model::gridpoints_on_plane: axis = ", axis, " must be 0 (x), 1 (y) or 2 (z)");
    require(tol >= 0 && std::isfinite(tol), "local_model::gridpoints_on_plane: tolerance ", tol, " m must be >= 0");
    require(gridpoints.size() == mesh.gridpoint_count(), "local_model::gridpoints_on_plane: the node_set has ",
            gridpoints.size(), " gridpoints, the local model ", mesh.gridpoint_count());
    bc::node_group g{{}, tessera::detail::concat("plane ", "xyz"[axis], " = ", value, " m (tol ", tol, " m), rank ", rank_)};
    for (index_t i = 0; i < gridpoints.size(); ++i)
      if (std::abs(gridpoints.reference(i, axis) - value) <= tol) g.nodes.push_back(i);
    long long mine = static_cast<long long>(g.nodes.size()), all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_LONG_LONG, MPI_SUM, comm);
    require(all > 0, "local_model::gridpoints_on_plane: the plane ", "xyz"[axis], " = ", value, " m (tol ", tol,
            " m) selects no gridpoint on any of the ", ranks_, " ranks");
    return g;
  }

  /// The non-finite check of a run on local models: each rank scans the u and v of its own
  /// gridpoints and bar nodes (`s`: the solver built on this model), the smallest offending GLOBAL
  /// id (gridpoint, or bar node after all gridpoints) is reduced over the ranks, and every rank
  /// throws numerical_instability naming it together (stepper::check_finite names local ids,
  /// which differ from rank to rank here). Every rank of `comm` must call it, at the same steps.
  /// O(own nodes); allocates nothing.
  template <class Solver>
  void check_finite(const Solver& s, MPI_Comm comm) const {
    const node_set& gp = s.gridpoints();
    require(gp.size() == mesh.gridpoint_count(), "local_model::check_finite: the solver has ", gp.size(),
            " gridpoints, the local model ", mesh.gridpoint_count());
    const auto bad = [](const node_set& n, index_t i) {
      return !n.displacement.row(i).allFinite() || !n.velocity.row(i).allFinite();
    };
    long long mine = detail::all_finite;
    for (index_t g = 0; g < gp.size() && mine == detail::all_finite; ++g)
      if (owns_gridpoint(g) && bad(gp, g)) mine = global_gridpoint(g);
    if constexpr (Solver::reinforcement_type::enabled)
      for (index_t n = 0; n < s.bar_nodes().size() && mine == detail::all_finite; ++n)
        if (bar_node_rank_[at(n)] == rank_ && bad(s.bar_nodes(), n)) mine = global_gridpoint_count_ + n;
    detail::throw_first_non_finite(mine, global_gridpoint_count_, s.step_count(), s.time(),
                                   tessera::detail::concat("whole-model id; a run on local models over ", ranks_, " ranks"),
                                   comm);
  }

  /// The sum of the support reactions (N) of `group` (local ids, as the solver's supports give:
  /// gridpoints_on_plane and the like) over all ranks, added in increasing GLOBAL gridpoint id, as
  /// recorders::reaction_sum adds a group in one process when the group is in increasing id (the
  /// order of every node group the solver's selectors return). Each rank sends its own rows; every
  /// rank gets the same bits, one process's. Every rank of `comm` must call it. Allocates (a
  /// sampling call).
  [[nodiscard]] vec3 reaction_sum(const node_set& gridpoints, const bc::node_group& group, MPI_Comm comm) const {
    return ordered_sum(gridpoints.reaction, group, comm, "reaction_sum").first;
  }
  /// The mean displacement (m) of `group` over all ranks, as recorders::mean_displacement on the
  /// whole group (summed in increasing global id, divided by the group's size over the ranks):
  /// one process's bits. Every rank of `comm` must call it.
  [[nodiscard]] vec3 mean_displacement(const node_set& gridpoints, const bc::node_group& group, MPI_Comm comm) const {
    const auto [sum, count] = ordered_sum(gridpoints.displacement, group, comm, "mean_displacement");
    return count == 0 ? sum : vec3(sum / static_cast<real>(count));
  }
  /// The unbalanced force of the last step (solver::unbalanced_force) over the own gridpoints and,
  /// with bars, the own bar nodes of every rank: max_force and max_node (the whole model's label:
  /// gridpoint id, or gridpoint count + bar node) are one process's, to the bit (the largest, the
  /// first in id order on a tie); mean_force is one process's to round-off (the ranks' means
  /// weighted by their node counts); nodes is exact. `s` must be stepped by a distributed::stepper
  /// (its ghosts' forces are not the model's and are left out). Every rank of `comm` must call it.
  template <class Solver>
  [[nodiscard]] out_of_balance unbalanced_force(const Solver& s, MPI_Comm comm) const {
    out_of_balance mine;
    const node_set& gp = s.gridpoints();
    for (index_t g = 0; g < gp.size(); ++g)
      if (owns_gridpoint(g)) mine.add(gp, g, global_gridpoint(g));
    if constexpr (Solver::reinforcement_type::enabled)
      for (index_t n = 0; n < s.bar_nodes().size(); ++n)
        if (bar_node_rank_[at(n)] == rank_) mine.add(s.bar_nodes(), n, global_gridpoint_count_ + n);
    // Largest force first, then the smallest label: (max, -label) compared lexicographically.
    std::array<double, 4> local{mine.max_node < 0 ? -1.0 : mine.max_force, -static_cast<double>(mine.max_node),
                                mine.mean_force * static_cast<double>(mine.nodes), static_cast<double>(mine.nodes)};
    std::vector<double> all(4 * at(ranks_));
    MPI_Allgather(local.data(), 4, MPI_DOUBLE, all.data(), 4, MPI_DOUBLE, comm);
    out_of_balance b;
    double weighted = 0;
    for (int r = 0; r < ranks_; ++r) {
      const double* x = &all[4 * at(r)];
      const bool better = x[3] > 0 && (b.max_node < 0 || x[0] > b.max_force || (x[0] == b.max_force && -x[1] < b.max_node));
      if (better) {
        b.max_force = x[0];
        b.max_node = static_cast<index_t>(-x[1]);
      }
      weighted += x[2];
      b.nodes += static_cast<index_t>(x[3]);
    }
    b.mean_force = b.nodes > 0 ? weighted / static_cast<double>(b.nodes) : 0;
    return b;
  }
#endif

 private:
  template <class I>
  [[nodiscard]] static std::size_t at(I i) {
    return static_cast<std::size_t>(i);
  }

#ifdef TESSERA_HAVE_MPI
  /// The rows of `rows` (N x 3) of the own gridpoints of `group`, gathered from every rank and
  /// summed in increasing global id, and how many there were over the ranks.
  [[nodiscard]] std::pair<vec3, index_t> ordered_sum(const soa3& rows, const bc::node_group& group, MPI_Comm comm,
                                                     const char* who) const {
    std::vector<double> mine;  // (global id, x, y, z) per own gridpoint of the group
    for (const index_t g : group.nodes) {
      require(g >= 0 && g < mesh.gridpoint_count(), "local_model::", who, ": gridpoint ", g, " is outside 0 .. ",
              mesh.gridpoint_count() - 1);
      if (!owns_gridpoint(g)) continue;
      mine.push_back(static_cast<double>(global_gridpoint(g)));
      for (int c = 0; c < 3; ++c) mine.push_back(rows(g, c));
    }
    std::vector<int> counts(at(ranks_)), offsets(at(ranks_) + 1, 0);
    const int n = static_cast<int>(mine.size());
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
    for (int r = 0; r < ranks_; ++r) offsets[at(r) + 1] = offsets[at(r)] + counts[at(r)];
    std::vector<double> all(at(offsets.back()));
    MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, comm);
    std::vector<std::size_t> order(all.size() / 4);
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all[4 * a] < all[4 * b]; });
    vec3 sum = vec3::Zero();
    for (const std::size_t k : order) sum += vec3(all[4 * k + 1], all[4 * k + 2], all[4 * k + 3]);
    return {sum, static_cast<index_t>(order.size())};
  }
#endif

  /// bar_node_rank_: the rank of each bar node's host block in the whole mesh (the rule of
  /// distributed::bar_node_host_blocks, its fill shared), found with the truss's own locator.
  void rank_bar_nodes(const geometry::block_mesh& w, std::span<const int> block_rank,
                      const std::vector<reinforcement::bar>& bars) {
    const reinforcement::bar_discretisation d = reinforcement::discretise_bars(bars);
    bar_nodes_ = d.nodes;
    const index_t n = d.node_count();
    std::vector<index_t> host(at(n), invalid_index);
    const reinforcement::zone_locator locator(w.gridpoints, w.zones);
    for (index_t k = 0; k < n; ++k) {
      const index_t b = d.node_bar[at(k)];
      if (!bars[at(b)].bonded) continue;
      const std::optional<reinforcement::host_point> h = locator.locate(d.nodes[at(k)]);
      require(h.has_value(), "embedded_truss: bar ", b, " node ", k - d.bar_node_offsets[at(b)], " at ",
              reinforcement::detail::point_string(d.nodes[at(k)]), " m lies outside every zone of the block mesh");
      host[at(k)] = w.zone_block[at(h->zone)];
    }
    fill_unhosted_bar_nodes(host, [&](index_t k) { return d.node_bar[at(k)]; });
    bar_node_rank_.resize(at(n));
    for (index_t k = 0; k < n; ++k) bar_node_rank_[at(k)] = host[at(k)] == invalid_index ? 0 : block_rank[at(host[at(k)])];
  }

  void cut_tessellation(const geometry::tessellation& w, const std::vector<index_t>& local_of_block) {
    tess.domain = w.domain;
    std::vector<index_t> local_vertex(at(w.vertex_count()), invalid_index);
    local_face_.assign(at(w.face_count()), invalid_index);
    for (const index_t b : global_block_) {
      if (!w.seeds.empty()) tess.seeds.push_back(w.seeds[at(b)]);
      if (!w.weights.empty()) tess.weights.push_back(w.weights[at(b)]);
      for (index_t f = w.first_face(b); f < w.end_face(b); ++f) {
        local_face_[at(f)] = static_cast<index_t>(global_face_.size());
        global_face_.push_back(f);
      }
      tess.cell_face_offsets.push_back(static_cast<index_t>(global_face_.size()));
    }
    for (const index_t f : global_face_) {
      for (const index_t v : w.face(f)) {
        if (local_vertex[at(v)] == invalid_index) {
          local_vertex[at(v)] = static_cast<index_t>(tess.vertices.size());
          tess.vertices.push_back(w.vertices[at(v)]);
        }
        tess.face_vertices.push_back(local_vertex[at(v)]);
      }
      tess.face_offsets.push_back(static_cast<index_t>(tess.face_vertices.size()));
      tess.face_cell.push_back(local_of_block[at(w.face_cell[at(f)])]);
      const index_t nb = w.face_neighbor[at(f)];
      tess.face_neighbor.push_back(nb < 0 ? nb : (local_of_block[at(nb)] == invalid_index ? outside_neighbor : local_of_block[at(nb)]));
      const index_t twin = w.face_twin.empty() ? invalid_index : w.face_twin[at(f)];
      tess.face_twin.push_back(twin == invalid_index ? invalid_index : local_face_[at(twin)]);
    }
    if (w.face_twin.empty()) tess.face_twin.clear();
    for (const auto& sf : w.shared_faces) {
      const index_t a = local_of_block[at(sf.cell_a)], b = local_of_block[at(sf.cell_b)];
      if (a == invalid_index || b == invalid_index) continue;
      tess.shared_faces.push_back({a, local_face_[at(sf.face_a)], b, local_face_[at(sf.face_b)]});
    }
    local_vertex_ = std::move(local_vertex);
  }

  void cut_mesh(const geometry::block_mesh& w, const std::vector<index_t>& local_of_block) {
    require(static_cast<index_t>(w.face_node_offsets.size()) == static_cast<index_t>(local_face_.size()) + 1,
            "local_model: the mesh has face nodes for ", w.face_node_offsets.size() - 1, " faces, the tessellation ",
            local_face_.size());
    // Gridpoint g of block b sits at the same offset in its block in both numberings.
    const auto local_gridpoint = [&](index_t g) {
      const index_t b = w.gridpoint_block[at(g)], lb = local_of_block[at(b)];
      return mesh.block_gridpoint_offsets[at(lb)] + (g - w.block_gridpoint_offsets[at(b)]);
    };
    for (const index_t b : global_block_) {
      for (index_t g = w.block_gridpoint_offsets[at(b)]; g < w.block_gridpoint_offsets[at(b) + 1]; ++g) {
        mesh.gridpoints.push_back(w.gridpoints[at(g)]);
        mesh.gridpoint_block.push_back(local_of_block[at(b)]);
        const index_t v = w.gridpoint_vertex[at(g)];
        mesh.gridpoint_vertex.push_back(v == invalid_index ? invalid_index : local_vertex_[at(v)]);
        global_gridpoint_.push_back(g);
      }
      mesh.block_gridpoint_offsets.push_back(static_cast<index_t>(mesh.gridpoints.size()));
      if (!w.block_material.empty()) mesh.block_material.push_back(w.block_material[at(b)]);
    }
    for (const index_t b : global_block_) {
      for (index_t z = w.block_zone_offsets[at(b)]; z < w.block_zone_offsets[at(b) + 1]; ++z) {
        const auto& zone = w.zones[at(z)];
        mesh.zones.push_back({local_gridpoint(zone[0]), local_gridpoint(zone[1]), local_gridpoint(zone[2]),
                              local_gridpoint(zone[3])});
        mesh.zone_block.push_back(local_of_block[at(b)]);
        global_zone_.push_back(z);
      }
      mesh.block_zone_offsets.push_back(static_cast<index_t>(mesh.zones.size()));
    }
    const bool triangles = w.face_triangle_offsets.size() == w.face_node_offsets.size();
    for (const index_t f : global_face_) {
      for (index_t k = w.face_node_offsets[at(f)]; k < w.face_node_offsets[at(f) + 1]; ++k) {
        mesh.face_nodes.push_back(local_gridpoint(w.face_nodes[at(k)]));
        mesh.face_node_area.push_back(w.face_node_area[at(k)]);
      }
      mesh.face_node_offsets.push_back(static_cast<index_t>(mesh.face_nodes.size()));
      if (!triangles) continue;
      for (index_t k = w.face_triangle_offsets[at(f)]; k < w.face_triangle_offsets[at(f) + 1]; ++k) {
        const auto& t = w.face_triangles[at(k)];
        mesh.face_triangles.push_back({local_gridpoint(t[0]), local_gridpoint(t[1]), local_gridpoint(t[2])});
      }
      mesh.face_triangle_offsets.push_back(static_cast<index_t>(mesh.face_triangles.size()));
    }
    local_vertex_.clear();
    local_vertex_.shrink_to_fit();
    local_face_.clear();
    local_face_.shrink_to_fit();
  }

  int rank_ = 0, ranks_ = 1;
  index_t global_block_count_ = 0, global_gridpoint_count_ = 0;
  std::vector<index_t> global_block_, global_gridpoint_, global_zone_, global_face_;
  std::vector<int> block_rank_;
  std::vector<int> bar_node_rank_;  ///< rank of each bar node (empty without bars)
  std::vector<vec3> bar_nodes_;     ///< their reference positions (m), to check bar_params' bars
  std::vector<index_t> local_vertex_, local_face_;  ///< construction scratch (released)
};

#ifdef TESSERA_HAVE_MPI
/// Refuses (invalid_input, on every rank alike) a time step `dt` (s) that differs between the ranks
/// of `comm`, naming the smallest and largest: a local model's solver chooses an automatic dt, or
/// resolves options.mass_scaling_ratio, from the gridpoints it holds; give options.dt or
/// options.mass_scaling_dt. Every rank must call it.
inline void require_same_time_step(real dt, MPI_Comm comm) {
  double lo = dt, hi = dt;
  MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_DOUBLE, MPI_MAX, comm);
  require(lo == hi, "require_same_time_step: the ranks' time steps range from ", lo, " s to ", hi,
          " s; a local model's solver needs options.dt or options.mass_scaling_dt, not an automatic step");
}
#endif

}  // namespace tessera::distributed
