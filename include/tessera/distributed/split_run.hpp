#pragma once
// distributed::split_run<Solver>: the whole recipe of a split run in one object, for a scene that
// was built the same way on every rank:
//
//   distributed::split_run<decltype(s)> run(s, mesh, MPI_COMM_WORLD);   // partition, ghosts, halo
//   while (!done) {
//     run.step();                            // this rank's part of one step
//     if (s.step_count() % 100 == 0) {
//       run.gather_state();                  // every rank's s now holds the whole model's state
//       done = my_sampler(s);                // one process's code, reading one process's bits
//     }
//   }
//   const distributed::split_figures f = run.figures();   // ranks, halo bytes and time, imbalance
//
// It partitions the block graph (bonded faces, sub-contacts and, with bars, the bar elements'
// host blocks) on rank 0 with METIS (best of ten; where built in) or by recursive coordinate
// bisection, broadcasts the map, builds the rank_ownership, the distributed::stepper and the
// state_gather. gather_state() fills every rank's solver with the owners' rows and sums the work
// books over the ranks; the next step() puts the rank's own books back first. So between a
// gather and the next step the solver reads as one process's (its energies() to round-off in the
// work terms, everything else to the bit), and a checkpoint written then (on rank 0) is one of
// the whole model, loadable by one process. Per-rank checkpoints for a split restart are taken
// after step(), before any gather.
//
// What splits: as distributed::stepper (deformable blocks, bonded faces, embedded bars, applied
// forces such as a rigid platen's, whose inputs set_shared_rows / share_rows keep current on every
// rank, gravity; no rigid blocks or detected contacts). Every rank must call every member
// function, the same number of times. Only where MPI is built in (TESSERA_HAVE_MPI).

#ifdef TESSERA_HAVE_MPI
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "../core/errors.hpp"
#include "../geometry/block_mesh.hpp"
#include "block_graph.hpp"
#include "gather.hpp"
#include "ownership.hpp"
#include "partition.hpp"
#include "stepper.hpp"

namespace tessera::distributed {

/// How split_run cuts the blocks: METIS's k-way partition (fewer cut sub-contacts; needs
/// TESSERA_HAVE_METIS) or recursive coordinate bisection of the block centroids (tighter balance,
/// no dependency).
enum class partitioner { metis, rcb };

/// Solvers a split run can split (what distributed::stepper covers): deformable blocks held by
/// bonded face contacts, with or without embedded bars.
template <class Solver>
concept splittable = !Solver::blocks_type::is_rigid &&
                     requires(typename Solver::contact_set_type& c, const node_set& gp, index_t i) {
                       c.update_faces(i, i, gp, real(0));
                       c.face(i);
                     };

/// METIS where built in, otherwise recursive coordinate bisection.
[[nodiscard]] constexpr partitioner default_partitioner() noexcept {
#ifdef TESSERA_HAVE_METIS
  return partitioner::metis;
#else
  return partitioner::rcb;
#endif
}

/// "metis" or "rcb".
[[nodiscard]] inline const char* partitioner_name(partitioner p) noexcept {
  return p == partitioner::metis ? "metis" : "rcb";
}

/// The figures of a split run so far (split_run::figures), the same on every rank.
struct split_figures {
  int ranks = 1;  ///< number of ranks
  std::string partitioner;               ///< "metis" or "rcb"
  std::vector<index_t> rank_blocks;      ///< blocks of each rank
  real weight_imbalance = 1;             ///< max / mean of the ranks' block weights (zones + 2 x sub-contacts)
  real edge_cut = 0;                     ///< sub-contacts between two ranks' blocks (evaluated twice)
  std::int64_t steps = 0;                ///< steps taken by split_run::step
  double halo_bytes_per_step = 0;        ///< bytes all ranks send in one step's exchange
  double max_rank_halo_bytes_per_step = 0;  ///< the most one rank sends
  double halo_seconds_per_step = 0;      ///< the slowest rank's halo time per step (s): packing, posting, waiting
  double step_seconds_per_step = 0;      ///< the slowest rank's wall time a step (s), with its waits at the gathers
  double time_imbalance = 1;             ///< max / mean over the ranks of (step time - halo time)
  double gather_seconds = 0;             ///< the slowest rank's time gathering (s, all gather_state calls)
};

/// The block -> rank map of `g` over the ranks of `comm`: cut on rank 0 with `how` (METIS's k-way,
/// best of ten, or recursive coordinate bisection) and broadcast, so every rank holds the same map
/// (split_run's, and the one a distributed::local_model is cut with). Throws invalid_input, on
/// every rank alike, when there are fewer blocks than ranks or for partitioner::metis where METIS
/// is not built in. Every rank of `comm` must call it.
[[nodiscard]] inline std::vector<int> broadcast_partition(const block_graph& g, MPI_Comm comm,
                                                          partitioner how = default_partitioner()) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  require(g.block_count() >= ranks, "distributed::broadcast_partition: ", ranks, " ranks for ", g.block_count(),
          " blocks; every rank needs a block");
#ifndef TESSERA_HAVE_METIS
  require(how == partitioner::rcb, "distributed::broadcast_partition: partitioner 'metis' asked for, but METIS is not "
                                   "built in (CMake TESSERA_METIS); use partitioner::rcb");
#endif
  std::vector<int> map(static_cast<std::size_t>(g.block_count()), 0);
  if (rank == 0) {
#ifdef TESSERA_HAVE_METIS
    map = how == partitioner::metis ? partition_blocks_metis(g, ranks) : partition_blocks_rcb(g, ranks);
#else
    map = partition_blocks_rcb(g, ranks);
#endif
  }
  MPI_Bcast(map.data(), static_cast<int>(map.size()), MPI_INT, 0, comm);
  return map;
}

/// A run split over MPI ranks from one call (file comment): partition, ownership and the stepper of this rank
template <class Solver>
class split_run {
 public:
  /// Splits `s` (built from `mesh`, identically on every rank of `comm`) over the communicator's
  /// ranks with `how`. Throws invalid_input as rank_ownership and stepper do (a rank without
  /// blocks, rigid blocks), and for partitioner::metis where METIS is not built in.
  split_run(Solver& s, const geometry::block_mesh& mesh, MPI_Comm comm, partitioner how = default_partitioner())
      : solver_(&s), comm_(comm), how_(how), graph_(graph_of(s, mesh)), map_(partition(graph_, comm, how)),
        own_(make_ownership(map_, ranks_of(comm), mesh, s)), stepper_(s, mesh, own_, comm), gather_(s, mesh, own_, comm) {
    MPI_Comm_rank(comm, &rank_);
  }

  split_run(const split_run&) = delete;
  split_run& operator=(const split_run&) = delete;

  /// One step of this rank's part (distributed::stepper::step), after putting back the rank's
  /// own work books if a gather replaced them.
  void step() {
    if (gathered_) {
      gather_.put_books(*solver_, own_books_);
      gathered_ = false;
    }
    const auto t0 = std::chrono::steady_clock::now();
    stepper_.step();
    step_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++steps_;
  }

  /// Every rank's solver takes the whole model's state now (state_gather) and the work books
  /// summed over the ranks; also checks every rank's nodes for non-finite values first (every
  /// rank throws numerical_instability together, naming the node). Allocates; for samples.
  void gather_state() {
    // The wait for the slowest rank is the steps' imbalance: booked with the steps, not the gather.
    const auto w0 = std::chrono::steady_clock::now();
    MPI_Barrier(comm_);
    const auto t0 = std::chrono::steady_clock::now();
    step_seconds_ += std::chrono::duration<double>(t0 - w0).count();
    stepper_.check_finite(comm_);
    gather_.gather(*solver_);
    if (!gathered_)
      own_books_ = gather_.gather_books(*solver_, stepper_.initial_energy_share(), stepper_.pending_applied_work());
    gathered_ = true;
    gather_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  /// Gridpoints whose u, v and reactions a callback between steps reads on every rank (a
  /// contact::rigid_platen's contact gridpoints, a hinged plate's): share_rows() then gives every
  /// rank their owners' rows. Throws invalid_input for a gridpoint that does not exist. Allocates
  /// here, not in share_rows.
  void set_shared_rows(std::vector<index_t> gridpoints) {
    std::sort(gridpoints.begin(), gridpoints.end());
    gridpoints.erase(std::unique(gridpoints.begin(), gridpoints.end()), gridpoints.end());
    const index_t n = solver_->gridpoints().size();
    shared_by_rank_.assign(static_cast<std::size_t>(own_.ranks()), {});
    for (const index_t g : gridpoints) {
      require(g >= 0 && g < n, "distributed::split_run: shared gridpoint ", g, " is not one of the ", n);
      shared_by_rank_[static_cast<std::size_t>(own_.gridpoint_rank(g))].push_back(g);
    }
    shared_counts_.assign(static_cast<std::size_t>(own_.ranks()), 0);
    shared_offsets_.assign(static_cast<std::size_t>(own_.ranks()) + 1, 0);
    for (int r = 0; r < own_.ranks(); ++r) {
      shared_counts_[static_cast<std::size_t>(r)] = static_cast<int>(shared_by_rank_[static_cast<std::size_t>(r)].size()) * 9;
      shared_offsets_[static_cast<std::size_t>(r) + 1] = shared_offsets_[static_cast<std::size_t>(r)] + shared_counts_[static_cast<std::size_t>(r)];
    }
    shared_send_.resize(static_cast<std::size_t>(shared_counts_[static_cast<std::size_t>(rank_)]));
    shared_receive_.resize(static_cast<std::size_t>(shared_offsets_.back()));
  }
  /// Every rank's rows of the shared gridpoints (set_shared_rows) take their owners' u, v and
  /// reactions: one MPI_Allgatherv of 72 bytes a row. Every rank must call it, after step().
  void share_rows() {
    if (shared_by_rank_.empty()) return;
    node_set& gp = solver_->gridpoints();
    std::size_t k = 0;
    for (const index_t g : shared_by_rank_[static_cast<std::size_t>(rank_)])
      for (const soa3* m : {&gp.displacement, &gp.velocity, &gp.reaction})
        for (int c = 0; c < 3; ++c) shared_send_[k++] = (*m)(g, c);
    MPI_Allgatherv(shared_send_.data(), static_cast<int>(shared_send_.size()), MPI_DOUBLE, shared_receive_.data(),
                   shared_counts_.data(), shared_offsets_.data(), MPI_DOUBLE, comm_);
    for (int r = 0; r < own_.ranks(); ++r) {
      k = static_cast<std::size_t>(shared_offsets_[static_cast<std::size_t>(r)]);
      for (const index_t g : shared_by_rank_[static_cast<std::size_t>(r)])
        for (soa3* m : {&gp.displacement, &gp.velocity, &gp.reaction})
          for (int c = 0; c < 3; ++c) (*m)(g, c) = shared_receive_[k++];
    }
  }

  /// The split's figures so far, reduced over the ranks (every rank must call it).
  [[nodiscard]] split_figures figures() const {
    split_figures f;
    f.ranks = own_.ranks();
    f.partitioner = partitioner_name(how_);
    const partition_report q = partition_quality(graph_, map_, f.ranks);
    f.rank_blocks = q.rank_blocks;
    f.weight_imbalance = q.imbalance;
    f.edge_cut = q.edge_cut;
    f.steps = steps_;
    const double steps = steps_ > 0 ? static_cast<double>(steps_) : 1.0;
    const double bytes = static_cast<double>(stepper_.halo().bytes_sent());
    const double halo = stepper_.halo_seconds() / steps, step = step_seconds_ / steps;
    const double work = step - halo;
    double sums[2] = {bytes, work}, maxima[4] = {bytes, halo, step, work}, total[2] = {}, worst[4] = {};
    double gather = gather_seconds_, worst_gather = 0;
    MPI_Allreduce(sums, total, 2, MPI_DOUBLE, MPI_SUM, comm_);
    MPI_Allreduce(maxima, worst, 4, MPI_DOUBLE, MPI_MAX, comm_);
    MPI_Allreduce(&gather, &worst_gather, 1, MPI_DOUBLE, MPI_MAX, comm_);
    f.halo_bytes_per_step = total[0];
    f.max_rank_halo_bytes_per_step = worst[0];
    f.halo_seconds_per_step = worst[1];
    f.step_seconds_per_step = worst[2];
    f.time_imbalance = total[1] > 0 ? worst[3] / (total[1] / f.ranks) : 1.0;
    f.gather_seconds = worst_gather;
    return f;
  }

  [[nodiscard]] int rank() const { return rank_; }  ///< This rank
  [[nodiscard]] const rank_ownership& ownership() const { return own_; }  ///< The ownership of blocks, gridpoints and sub-contacts
  [[nodiscard]] const std::vector<int>& block_ranks() const { return map_; }  ///< The rank of every block
  [[nodiscard]] stepper<Solver>& step_of_rank() { return stepper_; }  ///< This rank's stepper

 private:
  [[nodiscard]] static int ranks_of(MPI_Comm comm) {
    int n = 1;
    MPI_Comm_size(comm, &n);
    return n;
  }
  [[nodiscard]] static block_graph graph_of(const Solver& s, const geometry::block_mesh& mesh) {
    block_graph_input in = blocks_of_mesh(mesh);
    add_subcontacts(in, s.contacts());
    if constexpr (Solver::reinforcement_type::enabled) add_bar_elements(in, mesh, s.reinforcement());
    return block_graph(in);
  }
  [[nodiscard]] static std::vector<int> partition(const block_graph& g, MPI_Comm comm, partitioner how) {
    return broadcast_partition(g, comm, how);
  }
  [[nodiscard]] static rank_ownership make_ownership(const std::vector<int>& map, int ranks,
                                                     const geometry::block_mesh& mesh, const Solver& s) {
    if constexpr (Solver::reinforcement_type::enabled)
      return rank_ownership(map, ranks, mesh, contact_pairs_of(s.contacts()), bar_node_host_blocks(mesh, s.reinforcement()),
                            bar_element_pairs(s.reinforcement()));
    else
      return rank_ownership(map, ranks, mesh, contact_pairs_of(s.contacts()));
  }

  Solver* solver_;
  MPI_Comm comm_;
  partitioner how_;
  int rank_ = 0;
  block_graph graph_;
  std::vector<int> map_;
  rank_ownership own_;
  stepper<Solver> stepper_;
  state_gather gather_;
  state_gather::books own_books_{};
  bool gathered_ = false;
  std::int64_t steps_ = 0;
  double step_seconds_ = 0, gather_seconds_ = 0;
  std::vector<std::vector<index_t>> shared_by_rank_;  ///< set_shared_rows' gridpoints by owner, increasing
  std::vector<int> shared_counts_, shared_offsets_;    ///< their doubles per rank, and offsets
  std::vector<double> shared_send_, shared_receive_;
};

}  // namespace tessera::distributed

#endif  // TESSERA_HAVE_MPI
