#pragma once
// distributed::halo_exchange: the one exchange per step of the distributed step
// (docs/architecture.md, "The distributed step"): each rank sends the displacements u and
// velocities v of its own gridpoints that are ghosts on a neighbour rank, and receives those of
// its ghosts, non-blocking, so the caller overlaps it with the work that needs no ghost (the zone
// tasks, the faces between two own blocks).
//
// Order without indices: both sides list a neighbour's share in increasing global gridpoint id
// (rank_ownership::ghost_gridpoints_from), so a message is 6 reals per gridpoint (u then v, x y z
// each), 48 bytes, and nothing else. MPI copies the bytes, so a ghost holds its owner's bits.
// With reinforcement, the ghost bar nodes (rank_ownership::ghost_bar_nodes_from) ride in the same
// message after the gridpoints, 48 bytes each: still one message per neighbour and step.
//
// This is the foundation's form: the node_set is indexed by global gridpoint id on every rank
// (its rows of other ranks' blocks that are not ghosts are left alone); a rank's local numbering
// comes with the distributed step. Buffers and requests are sized at construction; start() and
// finish() allocate nothing. One exchange at a time; not thread-safe (call from one thread).
//
// Only where MPI is built in (TESSERA_HAVE_MPI: link tessera::mpi); without it this header
// declares nothing, so it still compiles alone.

#ifdef TESSERA_HAVE_MPI
#include <mpi.h>

#include <cstddef>
#include <type_traits>
#include <vector>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "ownership.hpp"

namespace tessera::distributed {

/// Exchanges the forces and states of the gridpoints ranks share (ghosts) over MPI, in a fixed order so every rank gets the same bits
class halo_exchange {
  static_assert(std::is_same_v<real, double>, "halo_exchange sends reals as MPI_DOUBLE");

 public:
  /// The exchange of this process's rank in `comm` under `own` (which every rank builds from the
  /// same map). `tag` keeps its messages apart from the caller's. Throws invalid_input when the
  /// communicator's size is not own.ranks() or the tag is negative.
  /// With `with_bar_nodes`, the ghost bar nodes too (start and finish then take the bar nodes).
  halo_exchange(const rank_ownership& own, MPI_Comm comm, int tag = 44, bool with_bar_nodes = false)
      : comm_(comm), tag_(tag), with_bar_nodes_(with_bar_nodes) {
    int size = 0;
    MPI_Comm_rank(comm, &rank_);
    MPI_Comm_size(comm, &size);
    require(size == own.ranks(), "halo_exchange: the communicator has ", size, " ranks, the ownership ", own.ranks());
    require(tag >= 0, "halo_exchange: tag = ", tag, " must be >= 0");
    for (int peer = 0; peer < size; ++peer) {
      if (peer == rank_) continue;
      neighbour n{peer, own.ghost_gridpoints_from(peer, rank_), own.ghost_gridpoints_from(rank_, peer), {}, {}, {}, {}};
      if (with_bar_nodes) {
        n.send_bars = own.ghost_bar_nodes_from(peer, rank_);  // ours, ghosts there
        n.receive_bars = own.ghost_bar_nodes_from(rank_, peer);
      }
      if (n.send.empty() && n.receive.empty() && n.send_bars.empty() && n.receive_bars.empty()) continue;
      n.send_buffer.resize(values_per_gridpoint * (n.send.size() + n.send_bars.size()));
      n.receive_buffer.resize(values_per_gridpoint * (n.receive.size() + n.receive_bars.size()));
      neighbours_.push_back(std::move(n));
    }
    requests_.resize(2 * neighbours_.size());
  }

  /// Posts the receives of the ghosts' u and v and the sends of this rank's (packed from
  /// `gridpoints` now). Every rank of the communicator must call it.
  void start(const node_set& gridpoints) {
    require(!with_bar_nodes_, "halo_exchange: built with bar nodes; call start(gridpoints, bar_nodes)");
    start_exchange(gridpoints, nullptr);
  }
  /// The same with the ghost bar nodes (an exchange built with_bar_nodes).
  void start(const node_set& gridpoints, const node_set& bar_nodes) {
    require(with_bar_nodes_, "halo_exchange: built without bar nodes; call start(gridpoints)");
    start_exchange(gridpoints, &bar_nodes);
  }

  /// Waits for the exchange and writes the received u and v into the ghosts' rows.
  void finish(node_set& gridpoints) {
    require(!with_bar_nodes_, "halo_exchange: built with bar nodes; call finish(gridpoints, bar_nodes)");
    finish_exchange(gridpoints, nullptr);
  }
  /// The same with the ghost bar nodes.
  void finish(node_set& gridpoints, node_set& bar_nodes) {
    require(with_bar_nodes_, "halo_exchange: built without bar nodes; call finish(gridpoints)");
    finish_exchange(gridpoints, &bar_nodes);
  }

  /// Ranks this rank exchanges with.
  [[nodiscard]] std::size_t neighbour_count() const { return neighbours_.size(); }
  /// Bytes this rank sends in one exchange (48 per gridpoint or bar node it shares).
  [[nodiscard]] std::size_t bytes_sent() const {
    std::size_t b = 0;
    for (const auto& n : neighbours_) b += n.send_buffer.size() * sizeof(double);
    return b;
  }
  /// Bytes this rank receives in one exchange.
  [[nodiscard]] std::size_t bytes_received() const {
    std::size_t b = 0;
    for (const auto& n : neighbours_) b += n.receive_buffer.size() * sizeof(double);
    return b;
  }

  static constexpr std::size_t values_per_gridpoint = 6;  ///< u and v, x y z each

 private:
  struct neighbour {
    int peer;
    std::vector<index_t> send;     ///< own gridpoints that are ghosts on peer, increasing
    std::vector<index_t> receive;  ///< ghosts owned by peer, increasing
    std::vector<index_t> send_bars, receive_bars;  ///< the same for bar nodes (with_bar_nodes_)
    std::vector<double> send_buffer, receive_buffer;
  };

  void start_exchange(const node_set& gridpoints, const node_set* bar_nodes) {
    require(!in_flight_, "halo_exchange: start() called again before finish()");
    std::size_t r = 0;
    for (auto& n : neighbours_)
      MPI_Irecv(n.receive_buffer.data(), static_cast<int>(n.receive_buffer.size()), MPI_DOUBLE, n.peer, tag_, comm_,
                &requests_[r++]);
    for (auto& n : neighbours_) {
      std::size_t k = 0;
      pack(gridpoints, n.send, n.send_buffer, k);
      if (bar_nodes != nullptr) pack(*bar_nodes, n.send_bars, n.send_buffer, k);
      MPI_Isend(n.send_buffer.data(), static_cast<int>(n.send_buffer.size()), MPI_DOUBLE, n.peer, tag_, comm_,
                &requests_[r++]);
    }
    in_flight_ = true;
  }

  void finish_exchange(node_set& gridpoints, node_set* bar_nodes) {
    require(in_flight_, "halo_exchange: finish() without start()");
    MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
    for (const auto& n : neighbours_) {
      std::size_t k = 0;
      unpack(n.receive_buffer, k, n.receive, gridpoints);
      if (bar_nodes != nullptr) unpack(n.receive_buffer, k, n.receive_bars, *bar_nodes);
    }
    in_flight_ = false;
  }
  /// u then v of each node of `list` into buffer from k on.
  static void pack(const node_set& nodes, const std::vector<index_t>& list, std::vector<double>& buffer, std::size_t& k) {
    for (const index_t g : list) {
      for (int d = 0; d < 3; ++d) buffer[k++] = nodes.displacement(g, d);
      for (int d = 0; d < 3; ++d) buffer[k++] = nodes.velocity(g, d);
    }
  }
  static void unpack(const std::vector<double>& buffer, std::size_t& k, const std::vector<index_t>& list, node_set& nodes) {
    for (const index_t g : list) {
      for (int d = 0; d < 3; ++d) nodes.displacement(g, d) = buffer[k++];
      for (int d = 0; d < 3; ++d) nodes.velocity(g, d) = buffer[k++];
    }
  }

  MPI_Comm comm_;
  int tag_ = 44;
  int rank_ = 0;
  std::vector<neighbour> neighbours_;
  std::vector<MPI_Request> requests_;
  bool in_flight_ = false;
  bool with_bar_nodes_ = false;
};

}  // namespace tessera::distributed

#endif  // TESSERA_HAVE_MPI
