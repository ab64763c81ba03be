#pragma once
// distributed::rigid_stepper<Solver>: the time step of a run split by blocks over MPI ranks for
// rigid blocks (blocks::rigid) on detected contacts (contact::detected_contacts): blocks that fall,
// slide and meet blocks of another rank. docs/architecture.md "Detected contacts across ranks".
//
// Every rank builds the whole model and holds every block's body state; each rank integrates its
// own blocks and evaluates the contacts that touch them:
//
//   the stable step's checks (solver::begin_rigid_step)
//   contacts (detected_contacts::update with set_own_blocks): the rebuild trigger and, when it
//     fires, the detection pass with its narrow phase split (set_detection_split: each rank the
//     common planes and patches of 1 / ranks of the candidate pairs, gather_detection the rest),
//     so every rank holds the same pairs and keys; the law update of the pairs that touch an own
//     block; the gather on the own blocks' gridpoints, in the order of one process
//   the time step chosen again after a rebuild (solver::time_step_after_contacts), alike everywhere
//   own blocks: reduction to force and moment, integration, slaved gridpoints (advance_blocks)
//   one MPI_Allgatherv of the own blocks' states after the step (29 doubles a block); each rank
//     sets the other ranks' blocks from them and slaves the gridpoints of those its pairs touch
//     as their owners did; the others' wait for sync_gridpoints (before a rebuild, a rebalance,
//     or a caller's read), which slaves them later in the step with the same bits (their
//     displacements are a function of the body state, their velocities of it and the rotation
//     before the step, which is kept); the rebuild trigger watches the own blocks and the ranks
//     reduce the largest motion (MPI_Allreduce of one double)
//   after a rebuild: the blocks cut again, the pairs that change hands sent to their new ranks
//
// Why the bits are one process's: a block's force and moment are the sums of solver::step (the
// same pairs, evaluated from the same body states, gathered in the same order), its integration
// is per block, and the copies of the other ranks' blocks are their owners' bits. So every body
// state, every gridpoint, the rebuild steps, the sub-contact keys and the time step are one
// process's on every rank, for any rank and thread count (test_distributed_step "[rigid]").
// Blocks migrate (rebalance, on by default): after a step whose contacts rebuilt, every rank cuts
// the blocks again by bisection of their centroids now (the same bits everywhere, so the same
// map), and each pair that a rank starts to evaluate takes its step state (normals, law states,
// fresh flags, forces) from the rank that owned its first block, which evaluated it: so its state
// is exact wherever it is evaluated, and the bits hold through any number of moves. Off, a block
// stays with its rank for the run; the cost is the balance as the scene moves.
//
// What is not the same bits: the energy books (the work of supports, damping and gravity, the
// contacts' dissipated energies and the rebuild exchange): each rank books its own blocks and the
// sub-contacts of pairs whose first block is its own, and summed_energies adds the shares in rank
// order, one process's values to round-off. The kinetic energy (every block's on every rank) and
// the springs' stored energy (gathered and summed in one process's order) are the same bits.
//
// Cost per step: the rank's contact pairs and blocks; at rebuilds, its part of the narrow phase,
// the gathered parts (about 56 bytes a corner) and the broad phase, the merge of the states and
// the frames of the whole scene (replicated, a few per cent of a pass); O(blocks) to set the
// other ranks' body states and O(own blocks) for the trigger, the slaving of the copies the pairs
// read, one collective exchange of 232 bytes a block and one reduction of a double. step()
// allocates only at rebuilds (the contact set's arrays, the gathered pass, the choice of the
// copies to slave, and the rebalance's map and transfer). Not thread-safe (one thread drives it;
// its loops are parallel).
// Only where MPI is built in (TESSERA_HAVE_MPI).

#ifdef TESSERA_HAVE_MPI
#include <mpi.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../integrator/concepts.hpp"
#include "../solver/energy.hpp"
#include "../solver/options.hpp"
#include "block_graph.hpp"
#include "detail/non_finite.hpp"
#include "gather_detection.hpp"
#include "partition.hpp"

namespace tessera::distributed {

/// Solvers rigid_stepper splits: rigid blocks on a contact set that takes a rank's blocks
/// (contact::detected_contacts).
template <class Solver>
concept rigid_splittable = Solver::blocks_type::is_rigid && requires(typename Solver::contact_set_type& c) {
  c.set_own_blocks(std::span<const index_t>{});
  c.rebuild_count();
};

/// A block -> rank map from the blocks' centroids (m): recursive coordinate bisection with equal
/// weights (partition_blocks_rcb). Throws invalid_input for ranks < 1 or above the block count.
[[nodiscard]] inline std::vector<int> partition_centroids_rcb(std::vector<vec3> centroids, int ranks) {
  block_graph_input in;
  in.weight.assign(centroids.size(), real(1));
  in.centroid = std::move(centroids);
  return partition_blocks_rcb(block_graph(in), ranks);
}

/// A block -> rank map for a scene of moving blocks: recursive coordinate bisection of the block
/// centroids with equal weights (partition_blocks_rcb). Why not METIS here: the contact graph of
/// such a scene changes as it moves (a heap starts with no contacts at all), so a cut of today's
/// graph is no better than a cut in space, and the spatial cut keeps neighbours together while
/// blocks move little. Throws invalid_input for ranks < 1 or above the block count.
[[nodiscard]] inline std::vector<int> partition_moving_blocks(const geometry::block_mesh& mesh, int ranks) {
  return partition_centroids_rcb(blocks_of_mesh(mesh).centroid, ranks);
}

/// The step of a solver of rigid blocks split over MPI ranks by blocks (file comment): each rank steps its own blocks, the same bits as one process
template <class Solver>
class rigid_stepper {
  static_assert(rigid_splittable<Solver>,
                "distributed::rigid_stepper: rigid blocks on a detecting contact set (contact::detected_contacts)");

 public:
  /// Terms summed_energies gathers from each rank.
  static constexpr int share_count = 7;

  /// The step of this process's rank in `comm` for `s`, built on every rank from the same scene,
  /// with block b on rank block_rank[b] (the same map on every rank, e.g. partition_moving_blocks);
  /// `rebalance`: cut the blocks again after each rebuild (file comment).
  /// Call before the first step. Throws invalid_input when the map's size is not the block count,
  /// names a rank outside the communicator, or leaves a rank without blocks.
  rigid_stepper(Solver& s, std::span<const int> block_rank, MPI_Comm comm, bool rebalance = true)
      : solver_(&s), comm_(comm), rebalance_(rebalance) {
    MPI_Comm_rank(comm, &rank_);
    MPI_Comm_size(comm, &ranks_);
    const index_t n_b = s.blocks().block_count();
    require(static_cast<index_t>(block_rank.size()) == n_b, "distributed::rigid_stepper: the map has ",
            block_rank.size(), " blocks, the solver ", n_b);
    for (index_t b = 0; b < n_b; ++b) {
      const int r = block_rank[static_cast<std::size_t>(b)];
      require(r >= 0 && r < ranks_, "distributed::rigid_stepper: block ", b, " is mapped to rank ", r,
              ", outside the communicator's [0, ", ranks_, ")");
    }
    block_rank_.assign(block_rank.begin(), block_rank.end());
    apply_map();
    s.contacts_for_step().set_detection_split(rank_, ranks_, [comm](contact::detection::detection_result& part) {
      gather_detection(comm, part);
    });
    // The rebuild trigger: each rank watches its own blocks, the largest motion is reduced (MAX is
    // exact: the one-process value), and the copies are slaved before a pass reads them.
    s.contacts_for_step().set_motion_vote(
        [comm](real m2) {
          real all = 0;
          MPI_Allreduce(&m2, &all, 1, MPI_DOUBLE, MPI_MAX, comm);
          return all;
        },
        [this] { sync_gridpoints(); });
    rank_shares_.resize(static_cast<std::size_t>(share_count) * static_cast<std::size_t>(ranks_));
  }
  /// Slaves the copies left behind (sync_gridpoints); the solver's contact set detects whole
  /// passes and watches every block again (set_own_blocks stays).
  ~rigid_stepper() {
    sync_gridpoints();
    solver_->contacts_for_step().set_detection_split(0, 1, {});
    solver_->contacts_for_step().set_motion_vote({}, {});
  }
  rigid_stepper(const rigid_stepper&) = delete;
  rigid_stepper& operator=(const rigid_stepper&) = delete;

  /// Advances the model by one step on every rank (file comment). Every rank of the communicator
  /// must call it, the same number of times. Throws what solver::step throws, alike on every rank.
  void step() {
    const auto started = std::chrono::steady_clock::now();
    Solver& s = *solver_;
    node_set& gp = s.gridpoints();
    s.begin_rigid_step();
    if (s.step_count() == 0) s.book_initial_energy(initial_share());  // kept by a checkpoint
    for (const index_t g : own_gridpoints_)
      for (int c = 0; c < 3; ++c) gp.force(g, c) = 0;
    const index_t rebuilds = s.contacts().rebuild_count();
    s.contacts_for_step().update(gp, s.dt());
    const bool rebuilt = s.contacts().rebuild_count() != rebuilds;
    if (rebuilt) choose_slaved();  // the copies the new pairs read
    const real kick = s.time_step_after_contacts();
    const real dt = s.dt();
    const auto integration = std::chrono::steady_clock::now();
    phases_.contacts += std::chrono::duration<double>(integration - started).count();
    integrator::step_work work;
    const auto& own = rank_blocks_[static_cast<std::size_t>(rank_)];
    s.blocks().advance_blocks(s.integrator(), gp, dt, work, kick, own);
    const real gravity_power = s.blocks().gravity_power(own);
    const auto exchange = std::chrono::steady_clock::now();
    send_.clear();
    s.blocks().write_body_states(own, send_);
    MPI_Allgatherv(send_.data(), static_cast<int>(send_.size()), MPI_DOUBLE, received_.data(), counts_.data(),
                   offsets_.data(), MPI_DOUBLE, comm_);
    // The copies this rank's pairs read are slaved now, the others when something reads them.
    for (int r = 0; r < ranks_; ++r)
      if (r != rank_)
        s.blocks().read_body_states(rank_blocks_[static_cast<std::size_t>(r)],
                                    received_.data() + offsets_[static_cast<std::size_t>(r)], gp, dt, slave_now_,
                                    rotation_before_);
    deferred_dt_ = dt;
    deferred_pending_ = true;
    if (rebalance_ && rebuilt) rebalance();
    const auto ended = std::chrono::steady_clock::now();
    s.close_external_step(work, 0, gravity_power * dt);
    phases_.integration += std::chrono::duration<double>(exchange - integration).count();
    exchange_seconds_ += std::chrono::duration<double>(ended - exchange).count();
    step_seconds_ += std::chrono::duration<double>(ended - started).count();
    ++steps_;
  }

  /// The energy balance of the whole model now (J): every rank's shares (work of supports, damping
  /// and gravity over its blocks; its sub-contacts' dissipated energies, retired energies and
  /// rebuild exchange; its initial share) added in rank order, so every rank gets the same bits,
  /// one process's to round-off; the kinetic energy of every block and the springs' stored energy
  /// (each sub-contact's from its booking rank, summed in one process's order), one process's
  /// bits. Every rank of the communicator must call it. O(sub-contacts); allocates (a call for
  /// samples).
  [[nodiscard]] energy_balance summed_energies() const {
    const energy_balance mine = solver_->energies();
    const real initial = solver_->step_count() == 0 ? initial_share() : mine.initial;
    // The stored energy is not a share: ordered_stored_energy sums it in one process's order.
    const std::array<double, share_count> share = {initial,
                                                   mine.boundary_work,
                                                   mine.damping_dissipated,
                                                   mine.gravity_work,
                                                   mine.contact_dissipated,
                                                   mine.contact_dissipated_tension,
                                                   mine.contact_rebuild_exchange};
    MPI_Allgather(share.data(), share_count, MPI_DOUBLE, rank_shares_.data(), share_count, MPI_DOUBLE, comm_);
    std::array<double, share_count> sum{};
    for (int r = 0; r < ranks_; ++r)
      for (int k = 0; k < share_count; ++k)
        sum[static_cast<std::size_t>(k)] += rank_shares_[static_cast<std::size_t>(r * share_count + k)];
    energy_balance e;
    e.initial = sum[0];
    e.boundary_work = sum[1];
    e.damping_dissipated = sum[2];
    e.gravity_work = sum[3];
    e.contact_stored = ordered_stored_energy();
    e.contact_dissipated = sum[4];
    e.contact_dissipated_tension = sum[5];
    e.contact_rebuild_exchange = sum[6];
    e.kinetic = mine.kinetic;
    return e;
  }

  /// Slaves the gridpoints of the other ranks' blocks that the last step left as they were (those
  /// no pair of this rank touches), from their body states: afterwards every gridpoint on this
  /// rank is one process's, to the bit. step() slaves only the copies its pairs read; call this
  /// before reading another rank's gridpoints (a VTK snapshot of the whole model, a checkpoint to
  /// restart from). Local (no communication); O(their gridpoints); allocates nothing.
  void sync_gridpoints() noexcept {
    if (!deferred_pending_) return;
    Solver& s = *solver_;
    for (const index_t b : deferred_)
      s.blocks().slave_gridpoints(b, rotation_before_[static_cast<std::size_t>(b)], s.gridpoints(), deferred_dt_);
    deferred_pending_ = false;
  }

  /// Throws numerical_instability on every rank, naming the smallest gridpoint of the model with a
  /// non-finite displacement or velocity (each rank scans its own blocks'; reduced over the
  /// ranks), so no rank is left waiting in the next exchange. Every rank must call it, at the same
  /// steps. O(own gridpoints); allocates nothing.
  void check_finite() const {
    const node_set& gp = solver_->gridpoints();
    long long mine = detail::all_finite;
    for (const index_t g : own_gridpoints_)
      if (!gp.displacement.row(g).allFinite() || !gp.velocity.row(g).allFinite()) {
        mine = g;
        break;
      }
    detail::throw_first_non_finite(mine, detail::all_finite, solver_->step_count(), solver_->time(),
                                   tessera::detail::concat("distributed run, ", ranks_, " ranks"), comm_);
  }

  /// The springs' elastic energy (J), summed in sub-contact order as detected_contacts::energies
  /// does in one process: each rank sends the energies of the sub-contacts it books (their pair's
  /// first block is its own), every rank sums them all in order. Every rank must call it.
  [[nodiscard]] real ordered_stored_energy() const {
    const auto& c = solver_->contacts();
    using law = typename Solver::contact_set_type::law_type;
    std::vector<double> mine;
    for (index_t i = 0; i < c.subcontact_count(); ++i)
      if (is_own_block(c.block_a(i))) mine.push_back(c.area(i) * law::stored_energy(c.subcontact_params(i), c.state(i)));
    const int n = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(ranks_)), offsets(static_cast<std::size_t>(ranks_) + 1, 0);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
    for (int r = 0; r < ranks_; ++r)
      offsets[static_cast<std::size_t>(r) + 1] = offsets[static_cast<std::size_t>(r)] + counts[static_cast<std::size_t>(r)];
    std::vector<double> all(static_cast<std::size_t>(offsets.back()));
    MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, comm_);
    real sum = 0;  // detected_contacts::energies starts from the retired books' stored energy, 0
    for (index_t i = 0; i < c.subcontact_count(); ++i)
      sum += all[static_cast<std::size_t>(offsets[static_cast<std::size_t>(block_rank_[static_cast<std::size_t>(c.block_a(i))])]++)];
    return sum;
  }

  [[nodiscard]] bool is_own_block(index_t b) const { return block_rank_[static_cast<std::size_t>(b)] == rank_; }  ///< True when this rank owns block b
  [[nodiscard]] int rank() const { return rank_; }  ///< This rank
  [[nodiscard]] int ranks() const { return ranks_; }  ///< Number of ranks
  /// Blocks of rank r, increasing.
  [[nodiscard]] const std::vector<index_t>& rank_blocks(int r) const { return rank_blocks_.at(static_cast<std::size_t>(r)); }
  /// Bytes all ranks send in one step's exchange (each rank's block states, sent to every other).
  [[nodiscard]] double exchange_bytes_per_step() const {
    double doubles = 0;
    for (const int c : counts_) doubles += static_cast<double>(c) * (ranks_ - 1);
    return doubles * sizeof(double);
  }
  /// This rank's wall time in the exchange (with the rebalances) and in whole steps since it was
  /// built (s); the exchange includes the wait for the slowest rank, so it measures imbalance too.
  [[nodiscard]] double exchange_seconds() const { return exchange_seconds_; }
  [[nodiscard]] double step_seconds() const { return step_seconds_; }  ///< Wall time of the steps so far (s)
  /// This rank's time in its steps' contact update (with the rebuilds) and in integrating its
  /// blocks (s; zones, bars and recorders 0), as solver::phases() reports a one-process run's.
  [[nodiscard]] const phase_times& phases() const { return phases_; }
  [[nodiscard]] std::int64_t steps() const { return steps_; }  ///< Steps taken
  /// Other ranks' blocks whose copies step() leaves to sync_gridpoints (no pair here touches them).
  [[nodiscard]] std::size_t deferred_block_count() const { return deferred_.size(); }
  /// Rebuilds after which blocks changed rank (rebalance).
  [[nodiscard]] std::int64_t rebalances() const { return rebalances_; }
  /// The block -> rank map now (after the rebalances so far): a restart from checkpoints builds its
  /// stepper with the map of the save.
  [[nodiscard]] const std::vector<int>& map() const { return block_rank_; }
  /// Rank of block b now.
  [[nodiscard]] int block_rank(index_t b) const { return block_rank_.at(static_cast<std::size_t>(b)); }

 private:
  /// The lists, exchange sizes and contact subset of block_rank_. Throws invalid_input when a rank
  /// has no blocks.
  void apply_map() {
    Solver& s = *solver_;
    rank_blocks_.assign(static_cast<std::size_t>(ranks_), {});
    for (std::size_t b = 0; b < block_rank_.size(); ++b)
      rank_blocks_[static_cast<std::size_t>(block_rank_[b])].push_back(static_cast<index_t>(b));
    counts_.assign(static_cast<std::size_t>(ranks_), 0);
    offsets_.assign(static_cast<std::size_t>(ranks_), 0);
    int total = 0;
    for (int r = 0; r < ranks_; ++r) {
      const auto& list = rank_blocks_[static_cast<std::size_t>(r)];
      require(!list.empty(), "distributed::rigid_stepper: rank ", r, " has no blocks (", block_rank_.size(),
              " blocks over ", ranks_, " ranks)");
      counts_[static_cast<std::size_t>(r)] = static_cast<int>(list.size()) * Solver::blocks_type::body_state_size;
      offsets_[static_cast<std::size_t>(r)] = total;
      total += counts_[static_cast<std::size_t>(r)];
    }
    received_.resize(static_cast<std::size_t>(total));
    send_.reserve(static_cast<std::size_t>(counts_[static_cast<std::size_t>(rank_)]));
    const auto& own = rank_blocks_[static_cast<std::size_t>(rank_)];
    own_gridpoints_.clear();
    for (const index_t b : own)
      for (const index_t g : s.gridpoints_of_block(b).nodes) own_gridpoints_.push_back(g);
    s.contacts_for_step().set_own_blocks(own);
    choose_slaved();
  }

  /// Which other ranks' blocks step() slaves (those in a pair with an own block, whose frames the
  /// pairs read) and which it leaves to sync_gridpoints. After each rebuild and map.
  void choose_slaved() {
    const Solver& s = *solver_;
    const auto& c = s.contacts();
    slave_now_.assign(block_rank_.size(), 0);
    rotation_before_.resize(block_rank_.size());
    for (index_t k = 0; k < c.pair_count(); ++k) {
      const auto [a, b] = c.pair_blocks(k);
      if (is_own_block(a) || is_own_block(b)) slave_now_[static_cast<std::size_t>(a)] = slave_now_[static_cast<std::size_t>(b)] = 1;
    }
    deferred_.clear();
    for (std::size_t b = 0; b < block_rank_.size(); ++b)
      if (block_rank_[b] != rank_ && slave_now_[b] == 0) deferred_.push_back(static_cast<index_t>(b));
  }

  /// After a step whose contacts rebuilt, with every body state current on every rank: the blocks
  /// cut again by bisection of their centroids now, alike on every rank. Each pair that a rank
  /// starts to evaluate takes its step state from the rank that owned its first block (which
  /// evaluated it), in one MPI_Allgatherv; then the new map applies. Allocates (at rebuilds only).
  void rebalance() {
    Solver& s = *solver_;
    std::vector<vec3> centroids;
    for (index_t b = 0; b < s.blocks().block_count(); ++b) centroids.push_back(s.blocks().centroid(b));
    const std::vector<int> next = partition_centroids_rcb(std::move(centroids), ranks_);
    if (next == block_rank_) return;
    sync_gridpoints();  // blocks that come here are integrated from their gridpoints' frames
    auto& c = s.contacts_for_step();
    // Pair k moves state when one of its new ranks did not evaluate it: from its first block's old rank.
    const auto gains = [&](index_t k) {
      const auto [a, b] = c.pair_blocks(k);
      const int oa = block_rank_[static_cast<std::size_t>(a)], ob = block_rank_[static_cast<std::size_t>(b)];
      const int na = next[static_cast<std::size_t>(a)], nb = next[static_cast<std::size_t>(b)];
      return (na != oa && na != ob) || (nb != oa && nb != ob);
    };
    std::vector<unsigned char> mine;
    for (index_t k = 0; k < c.pair_count(); ++k)
      if (gains(k) && block_rank_[static_cast<std::size_t>(c.pair_blocks(k)[0])] == rank_) c.write_pair_state(k, mine);
    const int n = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(ranks_)), offsets(static_cast<std::size_t>(ranks_) + 1, 0);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
    for (int r = 0; r < ranks_; ++r)
      offsets[static_cast<std::size_t>(r) + 1] = offsets[static_cast<std::size_t>(r)] + counts[static_cast<std::size_t>(r)];
    std::vector<unsigned char> all(static_cast<std::size_t>(offsets.back()));
    MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, comm_);
    for (index_t k = 0; k < c.pair_count(); ++k) {
      if (!gains(k)) continue;
      const auto [a, b] = c.pair_blocks(k);
      int& at = offsets[static_cast<std::size_t>(block_rank_[static_cast<std::size_t>(a)])];
      const bool was = block_rank_[static_cast<std::size_t>(a)] == rank_ || block_rank_[static_cast<std::size_t>(b)] == rank_;
      const bool is = next[static_cast<std::size_t>(a)] == rank_ || next[static_cast<std::size_t>(b)] == rank_;
      if (is && !was) c.read_pair_state(k, all.data() + at);
      at += static_cast<int>(c.pair_state_bytes(k));
    }
    block_rank_ = next;
    apply_map();
    ++rebalances_;
  }

  /// This rank's share of the balance's initial energy (J): its sub-contacts' springs and, on rank
  /// 0, the kinetic energy, which every rank holds whole.
  [[nodiscard]] real initial_share() const {
    return solver_->contacts().energies().stored + (rank_ == 0 ? solver_->blocks().kinetic_energy(solver_->gridpoints()) : 0.0);
  }

  Solver* solver_;
  MPI_Comm comm_;
  int rank_ = 0, ranks_ = 1;
  std::vector<std::vector<index_t>> rank_blocks_;  ///< per rank, its blocks, increasing
  std::vector<int> block_rank_;                    ///< per block, its rank
  std::vector<index_t> own_gridpoints_;            ///< gridpoints of this rank's blocks, increasing
  std::vector<int> counts_, offsets_;              ///< per rank, its doubles in the exchange and their offset
  std::vector<double> send_, received_;
  std::vector<std::uint8_t> slave_now_;            ///< per block: step() slaves its copy (choose_slaved)
  std::vector<index_t> deferred_;                  ///< other ranks' blocks it does not, increasing
  std::vector<mat3> rotation_before_;              ///< per deferred block: its rotation before the last step
  real deferred_dt_ = 0;                           ///< the step the deferred copies are behind by (s)
  bool deferred_pending_ = false;                  ///< they are (sync_gridpoints has not run since)
  phase_times phases_;                             ///< phases()
  mutable std::vector<double> rank_shares_;        ///< summed_energies' gathered shares
  double exchange_seconds_ = 0, step_seconds_ = 0;
  std::int64_t steps_ = 0;
  bool rebalance_ = true;
  std::int64_t rebalances_ = 0;
};

}  // namespace tessera::distributed

#endif  // TESSERA_HAVE_MPI
