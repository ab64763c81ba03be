#pragma once
// distributed::stepper<Solver>: the time step of a run split by blocks over MPI ranks
// (docs/architecture.md, "The distributed step"), for deformable blocks bonded by
// contact::face_contacts, with or without bars embedded in them (reinforcement::embedded_truss)
// and applied forces (a contact::rigid_platen's; the caller keeps their rows and whatever they are
// computed from current on every rank: split_run::share_rows) and gravity (each own gridpoint's
// force starts from its weight, as in solver::step); no detected contacts or rigid blocks yet.
// Every rank builds the whole
// model (a solver over every block: the memory of one process per rank, acceptable while a scene
// fits one machine's memory many times over) and the same rank_ownership; the stepper restricts
// the solver's step to what its rank evaluates and owns:
//
//   zone tasks of own blocks (force rows zeroed, then the block's zone sums)  ─┐ one parallel
//   faces whose two blocks are own                                           ─┘ region
//   wait for the halo (u(t), v(t - dt/2) of the ghost gridpoints and ghost bar nodes)
//   faces with a ghost block (evaluated here and on the ghost's rank, from the same inputs)
//   bars: the elements with a node here and the own nodes' bonds (serial); an element reads own
//     and ghost bar nodes, a bond its host zone (own) and that zone's stress from this step's task
//   per own block: gather each gridpoint's contact forces (face_contacts::add_force, increasing
//     global sub-contact order) and its bonds' host shares, then integrate its components (the
//     integrator's advance_dof); then the own bar nodes
//   send u(t + dt), v(t + dt/2) of own gridpoints and bar nodes that are ghosts elsewhere
//     (non-blocking, one message a neighbour; it completes in the next step, behind the zone
//     tasks and the interior faces)
//
// Why the bits are one process's: docs/architecture.md. Each own gridpoint's force is zero plus
// its block's zone sum plus its contact sum plus its bonds' host shares, the terms and order of
// solver::step; every sub-contact and bar element that touches it is evaluated on this rank from
// u and v that are the owners' bits; integration is per component. The motion of every own
// gridpoint and bar node, the state of every evaluated sub-contact and the reactions of own
// prescribed components are therefore one process's, to the bit, for any rank count and any
// thread count per rank (CTests distributed_mpi_step_2 and _3).
//
// What is not the same bits: the energy books. The boundary and damping work of a step are sums
// over every gridpoint, in one process by fixed chunks of the whole set; a rank books its own
// gridpoints' (block by block, in its solver's books), and summed_energies adds the ranks'
// shares in rank order: one process's values to round-off, not to the bit
// (docs/architecture.md says what the bits would need). Rows of other ranks' gridpoints on a rank
// are stale but for the ghosts (see finish_exchange), so the solver's energies() and
// unbalanced_force() on a rank are not the model's.
// Reaction sums over a node group spread over ranks: gathered_reaction_sum below.
//
// Cost per step: the rank's zones and evaluated sub-contacts, O(own gridpoints), one exchange;
// nothing allocated inside step(). Not thread-safe (one thread drives it; its loops are parallel).
// Only where MPI is built in (TESSERA_HAVE_MPI: link tessera::mpi).

#ifdef TESSERA_HAVE_MPI
#include <mpi.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <concepts>
#include <cstdint>
#include <vector>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../contact/concepts.hpp"
#include "../contact/detail/subcontact_energies.hpp"
#include "../integrator/concepts.hpp"
#include "../solver/applied_forces.hpp"
#include "../solver/boundary.hpp"
#include "../solver/detail/energy_books.hpp"
#include "../solver/energy.hpp"
#include "detail/non_finite.hpp"
#include "halo_exchange.hpp"
#include "ownership.hpp"

namespace tessera::distributed {

/// The step of a solver of deformable blocks split over MPI ranks by blocks (file comment): each rank steps its own blocks and exchanges its ghosts, the same bits as one process
template <class Solver>
class stepper {
  static_assert(!Solver::blocks_type::is_rigid, "distributed::stepper: rigid blocks split with distributed::rigid_stepper");
  /// Bars embedded in the blocks (reinforcement::embedded_truss): their nodes owned by the rank of
  /// their host block, their elements evaluated by the ranks of both nodes (rank_ownership).
  static constexpr bool bars = Solver::reinforcement_type::enabled;
  static_assert(!bars || requires(typename Solver::reinforcement_type& rf, const node_set& gp, node_set& out, index_t i) {
    rf.compute_forces(gp, zone_stress_matrix{});
    rf.add_host_forces(i, i, out);
  }, "distributed::stepper: reinforcement must hand its host forces to the gather (embedded_truss)");
  static_assert(requires(typename Solver::contact_set_type& c, const node_set& gp, index_t i) {
    c.update_faces(i, i, gp, real(0));
    c.face(i);
  }, "distributed::stepper: the contact set must be a face_contacts (bonded faces); detected contacts on rigid blocks split with distributed::rigid_stepper");

 public:
  /// The step of this process's rank in `comm` for `s`, built on every rank from the same scene
  /// (`mesh` the block_mesh it was built from), under `own`, built on every rank from the same
  /// map and the solver's sub-contacts (contact_pairs_of(s.contacts())). `tag` keeps the halo's
  /// messages apart. Throws invalid_input when the communicator's size is not own.ranks(), when
  /// the mesh or the ownership do not match the solver (gridpoints, blocks, sub-contacts), or when a
  /// block has no zones.
  stepper(Solver& s, const geometry::block_mesh& mesh, const rank_ownership& own, MPI_Comm comm, int tag = 44)
      : solver_(&s), halo_(own, comm, tag, bars) {
    MPI_Comm_rank(comm, &rank_);
    MPI_Comm_size(comm, &ranks_);
    rank_shares_.resize(static_cast<std::size_t>(share_count) * static_cast<std::size_t>(ranks_));
    own_displacement_.resize(s.gridpoints().size());
    const auto& contacts = s.contacts();
    require(mesh.gridpoint_count() == s.gridpoints().size(), "distributed::stepper: the mesh has ",
            mesh.gridpoint_count(), " gridpoints, the solver ", s.gridpoints().size());
    require(mesh.block_count() == s.blocks().block_count(), "distributed::stepper: the mesh has ", mesh.block_count(),
            " blocks, the solver ", s.blocks().block_count());
    // Zone task t is block t when every block has zones (blocks::deformable: one task per block
    // with zones, in block order).
    require(s.blocks().zone_task_count() == s.blocks().block_count(), "distributed::stepper: ",
            s.blocks().block_count() - s.blocks().zone_task_count(), " block(s) have no zones");
    // Applied forces (a contact::rigid_platen's): each own registered gridpoint starts its force
    // from its applied row, as solver::step does; the caller keeps the rows current on every rank.
    applied_count_ = s.applied_nodes().size();
    applied_slot_.assign(static_cast<std::size_t>(s.gridpoints().size()), invalid_index);
    for (std::size_t j = 0; j < s.applied_nodes().size(); ++j) applied_slot_[at(s.applied_nodes()[j])] = static_cast<index_t>(j);
    std::vector<char> evaluated_face(static_cast<std::size_t>(contacts.face_count()), 0);
    for (const index_t i : own.evaluated_contacts(rank_)) {
      require(i >= 0 && i < contacts.subcontact_count(), "distributed::stepper: the ownership names sub-contact ", i,
              "; the solver has ", contacts.subcontact_count());
      evaluated_face[static_cast<std::size_t>(contacts.face(i))] = 1;
      if (own.contact_owner(i) == rank_) owned_contacts_.push_back(i);
    }
    // Own blocks, and the blocks' gridpoint ranges (contiguous per block in the mesh).
    const auto owned = own.owned_blocks(rank_);
    own_blocks_.assign(owned.begin(), owned.end());
    block_gridpoint_offsets_ = mesh.block_gridpoint_offsets;
    for (const index_t b : own_blocks_)
      for (index_t g = block_gridpoint_offsets_[at(b)]; g < block_gridpoint_offsets_[at(b) + 1]; ++g) own_gridpoints_.push_back(g);
    is_own_block_.assign(static_cast<std::size_t>(mesh.block_count()), 0);
    for (const index_t b : own_blocks_) is_own_block_[at(b)] = 1;
    // Evaluated faces split into those with both blocks here (no ghost: they overlap the halo)
    // and those with a ghost block, each cut into tasks of consecutive faces with about
    // face_task_subcontacts sub-contacts.
    for (index_t f = 0; f < contacts.face_count(); ++f) {
      if (!evaluated_face[at(f)]) continue;
      const auto& sf = contacts.shared_face(f);
      const bool interior = is_own_block_[at(sf.cell_a)] && is_own_block_[at(sf.cell_b)];
      std::vector<index_t>& tasks = interior ? interior_faces_ : boundary_faces_;
      std::vector<index_t>& last = interior ? interior_last_ : boundary_last_;
      const bool extends = !tasks.empty() && last.back() == f &&
                           contacts.first_subcontact(f) - contacts.first_subcontact(tasks.back()) < face_task_subcontacts;
      if (extends) {
        last.back() = f + 1;
      } else {
        tasks.push_back(f);
        last.push_back(f + 1);
      }
    }
    for (const index_t g : own_gridpoints_)
      if (applied_slot_[at(g)] != invalid_index) own_applied_.push_back(g);
    applied_previous_.setZero(static_cast<index_t>(own_applied_.size()), 3);
    block_work_.resize(own_blocks_.size());
    block_gravity_power_.resize(own_blocks_.size());
    if constexpr (bars) {
      require(own.bar_node_count() == s.bar_nodes().size(), "distributed::stepper: the ownership has ",
              own.bar_node_count(), " bar nodes, the solver ", s.bar_nodes().size(),
              "; build it with bar_node_host_blocks and bar_element_pairs");
      for (index_t n = 0; n < own.bar_node_count(); ++n)
        if (own.bar_node_rank(n) == rank_) own_bar_nodes_.push_back(n);
      // An element is booked on the rank of its first node (rank_ownership's rule), and evaluated
      // on the ranks of both; the bond springs are the own nodes'.
      const auto& truss = s.reinforcement();
      for (index_t e = 0; e < truss.element_count(); ++e)
        if (own.bar_node_rank(truss.element_node_a(e)) == rank_) own_bar_elements_.push_back(e);
      const auto evaluated = own.evaluated_elements(rank_);
      evaluated_bar_elements_.assign(evaluated.begin(), evaluated.end());
      for (const index_t n : own_bar_nodes_)
        if (truss.bonded(n)) own_bonded_bar_nodes_.push_back(n);
    }
  }

  stepper(const stepper&) = delete;
  stepper& operator=(const stepper&) = delete;

  /// Advances this rank's part of the model by one step (file comment). Every rank of the
  /// communicator must call it, the same number of times. Throws invalid_input, before anything
  /// changes, when applied forces were registered since the stepper was built (every rank throws
  /// alike: the model is the same on all). Gravity set or changed between steps is taken as
  /// solver::step takes it.
  void step() {
    Solver& s = *solver_;
    require(s.applied_nodes().size() == applied_count_, "distributed::stepper: ", s.applied_nodes().size(),
            " gridpoints carry applied forces, ", applied_count_, " when the stepper was built; build it after them");
    node_set& gp = s.gridpoints();
    auto& contacts = s.contacts_for_step();
    const real dt = s.dt();
    if (s.step_count() == 0) {
      // The balance's initial energy, this rank's share (summed_energies), before anything moves.
      const auto share = rank_share();
      initial_ = share[3] + share[4] + share[5] + share[10];
    }
    if (!in_flight_) start_exchange();  // the first step: the ghosts as they stand now
    // The last step's work of the own applied forces, booked now (solver::step).
    const real applied_work = pending_applied_work();
    if (!own_applied_.empty()) {
      const soa3& applied = s.applied_forces();
      for (std::size_t j = 0; j < own_applied_.size(); ++j) applied_previous_.row(static_cast<index_t>(j)) = applied.row(own_applied_[j]);
      applied_active_ = true;
    }
    contacts.prepare_step(gp, dt);
    const bool weighted = s.gravity() != vec3::Zero();
    const auto own_block_count = static_cast<std::int64_t>(own_blocks_.size());
    parallel_range_pair(
        own_block_count, [&](std::int64_t k0, std::int64_t k1) { add_zone_forces(k0, k1, gp); },
        static_cast<std::int64_t>(interior_faces_.size()),
        [&](std::int64_t j) { contacts.update_faces(interior_faces_[at(j)], interior_last_[at(j)], gp, dt); }, 16);
    finish_halo();
    parallel_for(static_cast<std::int64_t>(boundary_faces_.size()),
                 [&](std::int64_t j) { contacts.update_faces(boundary_faces_[at(j)], boundary_last_[at(j)], gp, dt); }, 2);
    if constexpr (bars) {
      // The elements with a node here (they read own and ghost u only) and the own nodes' bond
      // springs, in one process's order; the other nodes' forces stay 0 and nothing reads them.
      s.bar_nodes().force.setZero();
      s.reinforcement().compute_forces_of(evaluated_bar_elements_, own_bonded_bar_nodes_, gp, s.blocks().zone_stress_rows());
    }
    const auto& integ = s.integrator();
    parallel_for(own_block_count, [&](std::int64_t k) {
      const index_t b = own_blocks_[at(k)];
      const index_t g0 = block_gridpoint_offsets_[at(b)], g1 = block_gridpoint_offsets_[at(b) + 1];
      for (index_t g = g0; g < g1; ++g) contacts.add_force(g, gp);
      if constexpr (bars) s.reinforcement().add_host_forces(g0, g1, gp);  // after the contacts, as the solver
      integrator::step_work w;
      for (index_t g = g0; g < g1; ++g) advance_node(integ, gp, g, dt, w);
      block_work_[at(k)] = w;
      if (weighted) block_gravity_power_[at(k)] = gravity_power(gp, g0, g1);
    }, 4);
    integrator::step_work work;
    real gravity_work = 0;  // weight x half-step velocity x dt, as solver::step books it
    for (std::size_t k = 0; k < block_work_.size(); ++k) {
      work.boundary += block_work_[k].boundary;
      work.damping += block_work_[k].damping;
      if (weighted) gravity_work += block_gravity_power_[k] * dt;
    }
    if constexpr (bars)
      for (const index_t n : own_bar_nodes_) advance_node(integ, s.bar_nodes(), n, dt, work);
    s.close_external_step(work, applied_work, gravity_work);
    start_exchange();
  }

  /// The energy balance of the whole model now (J), from every rank's share: the work of the
  /// support reactions, the local damping and gravity summed over the steps (each rank books its own
  /// gridpoints, block by block), the kinetic energy of its gridpoints (1/2 m v^2, half-step v),
  /// the elastic energy of its blocks' zones (blocks' stored_energy, with rotations of the
  /// current displacements), the contact energies of the sub-contacts it owns (stored,
  /// dissipated, its tensile part) and, as `initial`, the kinetic and stored energy before the
  /// first step, the work of its applied forces; bars: their nodes' kinetic energy, and the
  /// stored and dissipated energies of the elements whose first node is its own and of its bar
  /// nodes' bond springs (in `initial` too). The shares are gathered and added in
  /// rank order, so every rank gets the same bits; they are one process's (solver::energies) to
  /// round-off only, another summation order (test_distributed_step holds every term within
  /// 1e-12 relative after 600 steps). Every rank of `comm` must call it. O(own gridpoints, zones,
  /// sub-contacts and bar entities); allocates (the zones' rotations, as blocks' stored_energy
  /// does): a call for samples, not for every step.
  [[nodiscard]] energy_balance summed_energies(MPI_Comm comm) const {
    const std::array<double, share_count> mine = rank_share();
    MPI_Allgather(mine.data(), share_count, MPI_DOUBLE, rank_shares_.data(), share_count, MPI_DOUBLE, comm);
    std::array<double, share_count> sum{};
    for (int r = 0; r < ranks_; ++r)
      for (int k = 0; k < share_count; ++k) sum[at(k)] += rank_shares_[at(r * share_count + k)];
    energy_balance e;
    e.initial = sum[0];
    e.boundary_work = sum[1];
    e.damping_dissipated = sum[2];
    e.kinetic = sum[3];
    e.block_elastic = sum[4];
    e.contact_stored = sum[5];
    e.contact_dissipated = sum[6];
    e.contact_dissipated_tension = sum[7];
    e.gravity_work = sum[8];
    e.applied_work = sum[9];
    e.reinforcement_stored = sum[10];
    e.reinforcement_dissipated = sum[11];
    return e;
  }

  /// The non-finite check of the step checker across ranks: each rank scans the u and v of its
  /// gridpoints (and bar nodes), the smallest offending global gridpoint id (or bar node, after
  /// all gridpoints) is reduced over the ranks, and every rank throws numerical_instability
  /// naming it together, so none is left waiting in the next exchange. Every rank of `comm` must
  /// call it (at the same steps). O(own nodes); allocates nothing.
  void check_finite(MPI_Comm comm) const {
    const Solver& s = *solver_;
    const auto first_bad = [](const node_set& nodes, const std::vector<index_t>& list) {
      for (const index_t i : list)
        if (!nodes.displacement.row(i).allFinite() || !nodes.velocity.row(i).allFinite()) return i;
      return invalid_index;
    };
    const index_t gridpoints = s.gridpoints().size();
    long long mine = detail::all_finite;
    if (const index_t g = first_bad(s.gridpoints(), own_gridpoints_); g != invalid_index) mine = g;
    if constexpr (bars)
      if (mine == detail::all_finite)
        if (const index_t n = first_bad(s.bar_nodes(), own_bar_nodes_); n != invalid_index) mine = gridpoints + n;
    detail::throw_first_non_finite(mine, gridpoints, s.step_count(), s.time(),
                                   tessera::detail::concat("distributed run, ", ranks_, " ranks"), comm);
  }

  /// Completes the exchange the last step started, so the ghosts' rows hold u(t) and v(t - dt/2)
  /// of their owners now (for a reader of ghost rows between steps; step() completes it anyway).
  /// Every rank must call it.
  void finish_exchange() {
    if (in_flight_) finish_halo();
  }

  [[nodiscard]] int rank() const { return rank_; }  ///< This rank
  /// The work of the own applied forces over the last step (J), booked at the next step once
  /// their closing values are written (solver::energies adds the same pending share).
  [[nodiscard]] real pending_applied_work() const {
    if (!applied_active_ || own_applied_.empty()) return 0;
    const Solver& s = *solver_;
    return tessera::detail::applied_work_of_step(own_applied_, applied_previous_, s.applied_forces(), s.gridpoints(), s.dt());
  }
  /// This rank's share of the kinetic and stored energy before the first step (J; 0 before it).
  [[nodiscard]] real initial_energy_share() const { return initial_; }
  /// Wall time this rank spent in the halo since it was built (s): packing and posting the
  /// sends, and waiting for and unpacking what arrives (the wait includes a slower neighbour's
  /// lag, so it measures imbalance too).
  [[nodiscard]] double halo_seconds() const { return halo_seconds_; }
  /// Blocks of this rank, increasing.
  [[nodiscard]] const std::vector<index_t>& own_blocks() const { return own_blocks_; }
  /// Gridpoints of this rank's blocks, increasing.
  [[nodiscard]] const std::vector<index_t>& own_gridpoints() const { return own_gridpoints_; }
  [[nodiscard]] bool owns_block(index_t b) const { return is_own_block_[at(b)] != 0; }  ///< True when this rank owns block b
  [[nodiscard]] const halo_exchange& halo() const { return halo_; }  ///< The exchange of ghost gridpoints
  /// Face tasks this rank evaluates without ghosts and with a ghost block.
  [[nodiscard]] std::size_t interior_face_tasks() const { return interior_faces_.size(); }
  [[nodiscard]] std::size_t boundary_face_tasks() const { return boundary_faces_.size(); }  ///< Shared-face tasks on the rank boundary

 private:
  template <std::integral I>
  [[nodiscard]] static constexpr std::size_t at(I i) noexcept {
    return static_cast<std::size_t>(i);
  }

  /// Zone forces of own blocks own_blocks_[k0, k1): each run of consecutive block ids at once
  /// (one task per block, so their rotations are computed in lane packs as the solver does).
  void add_zone_forces(std::int64_t k0, std::int64_t k1, node_set& gp) {
    auto& blocks = solver_->blocks();
    for (std::int64_t k = k0; k < k1;) {
      std::int64_t e = k + 1;
      while (e < k1 && own_blocks_[at(e)] == own_blocks_[at(e - 1)] + 1) ++e;
      const index_t b0 = own_blocks_[at(k)], b1 = own_blocks_[at(e - 1)] + 1;
      // solver::step starts the forces from the weights (zero without gravity) plus the applied forces.
      const soa3* applied = applied_count_ > 0 ? &solver_->applied_forces() : nullptr;
      const soa3* weight = solver_->gravity() != vec3::Zero() ? &solver_->gravity_forces() : nullptr;
      for (index_t g = block_gridpoint_offsets_[at(b0)]; g < block_gridpoint_offsets_[at(b1)]; ++g) {
        for (int c = 0; c < 3; ++c) gp.force(g, c) = weight != nullptr ? (*weight)(g, c) : real(0);
        if (applied != nullptr && applied_slot_[at(g)] != invalid_index)
          for (int c = 0; c < 3; ++c) gp.force(g, c) += (*applied)(g, c);
      }
      blocks.add_zone_forces_of_tasks(b0, b1, gp);
      k = e;
    }
  }

  /// sum over gridpoints [g0, g1) of their weight . v (W): the gravity power of a block.
  [[nodiscard]] real gravity_power(const node_set& gp, index_t g0, index_t g1) const {
    real p = 0;
    for (index_t g = g0; g < g1; ++g) p += tessera::detail::weight_power(solver_->gravity_forces(), gp, g);
    return p;
  }

  static constexpr int share_count = 12;  ///< the terms summed_energies gathers from each rank
  /// This rank's shares, in summed_energies' order: initial, boundary work, damping, kinetic,
  /// zones' elastic energy, contact stored, dissipated and dissipated in tension, gravity work,
  /// applied work (the pending step's included), bars' stored and dissipated energy (J).
  [[nodiscard]] std::array<double, share_count> rank_share() const {
    const Solver& s = *solver_;
    const node_set& gp = s.gridpoints();
    real kinetic = 0;
    for (const index_t g : own_gridpoints_) kinetic += 0.5 * gp.mass[g] * gp.velocity.row(g).squaredNorm();
    if constexpr (bars)
      for (const index_t n : own_bar_nodes_)
        kinetic += 0.5 * s.bar_nodes().mass[n] * s.bar_nodes().velocity.row(n).squaredNorm();
    // The zones' energy from a copy of the displacements in which every other rank's gridpoint is
    // at rest: their blocks, whose rotations this rank never updates (the identity, also after
    // loading this rank's own checkpoint), then add exact zeros, and the sum is that of this
    // rank's zones.
    for (const index_t g : own_gridpoints_) own_displacement_.displacement.row(g) = gp.displacement.row(g);
    const real zones = s.blocks().stored_energy(own_displacement_);
    contact::contact_energies c;
    for (const index_t i : owned_contacts_)
      contact::detail::add_subcontact_energies<typename Solver::law_type>(c, s.contacts().subcontact_params(i),
                                                                        s.contacts().state(i), s.contacts().area(i));
    // The work books are the solver's (close_external_step adds each step's rank share), so a
    // checkpoint of the solver keeps them.
    const energy_balance books = s.energies();
    std::array<real, 2> bars_energy{0.0, 0.0};
    if constexpr (bars) bars_energy = s.reinforcement().stored_and_dissipated_of(own_bar_elements_, own_bar_nodes_);
    return {initial_,       books.boundary_work, books.damping_dissipated,
            kinetic,        zones,               c.stored,
            c.dissipated,   c.dissipated_tension, books.gravity_work,
            books.applied_work + pending_applied_work(), bars_energy[0], bars_energy[1]};
  }

  /// The three components of node i, each as the integrator's advance does it (advance_dof).
  template <class Integrator>
  static void advance_node(const Integrator& integ, node_set& nodes, index_t i, real dt, integrator::step_work& w) {
    for (int c = 0; c < 3; ++c) {
      nodes.velocity(i, c) = integ.advance_dof(nodes.force(i, c), nodes.mass[i], nodes.velocity(i, c),
                                               nodes.constraint(i, c), nodes.prescribed_velocity(i, c), dt,
                                               nodes.reaction(i, c), w);
      nodes.displacement(i, c) += nodes.velocity(i, c) * dt;
    }
  }

  void start_exchange() {
    const auto t0 = std::chrono::steady_clock::now();
    if constexpr (bars)
      halo_.start(solver_->gridpoints(), solver_->bar_nodes());
    else
      halo_.start(solver_->gridpoints());
    in_flight_ = true;
    halo_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  void finish_halo() {
    const auto t0 = std::chrono::steady_clock::now();
    if constexpr (bars)
      halo_.finish(solver_->gridpoints(), solver_->bar_nodes());
    else
      halo_.finish(solver_->gridpoints());
    in_flight_ = false;
    halo_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  /// Sub-contacts per face task (at least, but for the last task of a run of faces).
  static constexpr index_t face_task_subcontacts = 64;

  Solver* solver_;
  halo_exchange halo_;
  int rank_ = 0;
  bool in_flight_ = false;
  std::vector<index_t> own_blocks_;
  std::vector<index_t> own_gridpoints_;
  std::vector<char> is_own_block_;
  std::vector<index_t> block_gridpoint_offsets_;
  std::vector<index_t> interior_faces_, interior_last_;  ///< face tasks [first, last) with both blocks own
  std::vector<index_t> boundary_faces_, boundary_last_;  ///< face tasks [first, last) with a ghost block
  std::vector<integrator::step_work> block_work_;        ///< per own block: its integration work this step
  std::vector<real> block_gravity_power_;                ///< per own block: its gravity power this step (W)
  real initial_ = 0;                                     ///< this rank's kinetic + stored energy before step 1 (J)
  std::vector<index_t> owned_contacts_;                  ///< sub-contacts this rank books, increasing
  std::vector<index_t> own_bar_nodes_;                   ///< bar nodes of this rank, increasing
  std::vector<index_t> own_bar_elements_, evaluated_bar_elements_;  ///< first node own; a node here
  std::vector<index_t> own_bonded_bar_nodes_;            ///< own bar nodes with a bond spring, increasing
  mutable node_set own_displacement_;                    ///< rank_share's copy: own rows' u, the rest 0
  int ranks_ = 1;                                        ///< ranks of the communicator
  double halo_seconds_ = 0;                              ///< halo_seconds()
  std::size_t applied_count_ = 0;                        ///< the solver's applied gridpoints when built
  std::vector<index_t> applied_slot_;                    ///< per gridpoint: its applied_nodes() index, or invalid
  std::vector<index_t> own_applied_;                     ///< own applied gridpoints, increasing
  soa3 applied_previous_;                                ///< their forces applied by the last step (N)
  bool applied_active_ = false;                          ///< the last step applied them (their work is pending)
  mutable std::vector<double> rank_shares_;              ///< summed_energies' gathered shares
};

/// The sum over `group` (in its order, as recorders::reaction_sum) of the support reactions (N)
/// of a node group spread over ranks: each rank sends the rows of its own gridpoints, every rank
/// receives all rows in group order and sums them as one process does, so the result is one
/// process's to the bit on every rank. Every rank of `comm` must call it with the same group.
/// Allocates (a sampling call, not one for every step).
[[nodiscard]] inline vec3 gathered_reaction_sum(const node_set& gridpoints, const bc::node_group& group,
                                                const rank_ownership& own, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  require(size == own.ranks(), "gathered_reaction_sum: the communicator has ", size, " ranks, the ownership ",
          own.ranks());
  std::vector<double> mine;
  std::vector<int> counts(static_cast<std::size_t>(size), 0), offsets(static_cast<std::size_t>(size) + 1, 0);
  for (const index_t g : group.nodes) {
    const int r = own.gridpoint_rank(g);
    counts[static_cast<std::size_t>(r)] += 3;
    if (r == rank)
      for (int c = 0; c < 3; ++c) mine.push_back(gridpoints.reaction(g, c));
  }
  for (int r = 0; r < size; ++r) offsets[static_cast<std::size_t>(r) + 1] = offsets[static_cast<std::size_t>(r)] + counts[static_cast<std::size_t>(r)];
  std::vector<double> all(static_cast<std::size_t>(offsets.back()));
  MPI_Allgatherv(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                 MPI_DOUBLE, comm);
  // Each rank's rows arrived in group order: walk the group, taking the next row of its owner.
  std::vector<int> next(offsets.begin(), offsets.end() - 1);
  vec3 sum = vec3::Zero();
  for (const index_t g : group.nodes) {
    int& k = next[static_cast<std::size_t>(own.gridpoint_rank(g))];
    sum += vec3(all[static_cast<std::size_t>(k)], all[static_cast<std::size_t>(k) + 1], all[static_cast<std::size_t>(k) + 2]);
    k += 3;
  }
  return sum;
}

}  // namespace tessera::distributed

#endif  // TESSERA_HAVE_MPI
