#pragma once
// distributed::state_gather: makes every rank's solver hold the whole model's state, as one
// process would have it at the same step, so that anything written for one process (a driver's
// sampler, a recorder, a VTK snapshot, a checkpoint of the whole model, the end-of-run figures)
// reads a split run unchanged. A call for sampling instants, not for every step.
//
// How: the solver's own checkpoint(Archive&) (io/checkpoint.hpp) lists every evolving field by
// name; this archive answers each field by gathering, over all ranks, the rows whose owner is
// each rank (MPI_Allgatherv of their bytes, placed back in row order), a record at a time and in
// chunks of at most chunk_bytes of rows (default 32 MiB), so what a gather holds beside the model
// is bounded (2 x chunk_bytes) whatever the model's size, and no count passes MPI's int. The
// owner of a row follows rank_ownership:
//   gridpoints/...                      a gridpoint: the rank of its block
//   bars/nodes/..., bars/bond/..., bars/transverse_gap, bars/confining_stress
//                                       a bar node: the rank of its host block
//   bars/element/...                    a bar element: the rank of its first node
//   contacts/state/..., contacts/tensile_strength, contacts/force_a/...
//                                       a sub-contact: contact_owner (its lower block's rank)
//   contacts/normal, contacts/previous_normal
//                                       a shared face: the rank of its lower block
//   blocks/deformable/rotation          a block: its rank
//   blocks/deformable/local_stress      a zone: the rank of its block
// plus the force rows of gridpoints and bar nodes (not checkpoint state). Every owner computed
// its rows with one process's bits (distributed::stepper), so after the gather every rank's rows
// are one process's. A record with no rule above is refused by name, so a field added to a
// checkpoint cannot be left stale silently.
//
// The work books (boundary and damping work, gravity and applied work, the initial energy) are
// sums over each rank's own gridpoints: gather_books() replaces them by the ranks' sum in rank
// order (one process's value to round-off, not to the bit; docs/architecture.md) and returns the
// rank's own, which split_run puts back before the next step.
//
// Cost: O(model) bytes over the communicator per call, in one collective call per record and
// chunk (about 40 records for a tie with bars); allocates its two chunk buffers at the first call.
// Every rank of the communicator must call it. Only where MPI is built in (TESSERA_HAVE_MPI).

#ifdef TESSERA_HAVE_MPI
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "ownership.hpp"

namespace tessera::distributed {

/// The owner of every row of every kind of state (file comment), built once for a solver and its
/// ownership; gather(solver) then fills every rank's solver with the owners' rows.
class state_gather {
 public:
  /// The work books of a solver (J): boundary, damping, gravity and applied work, initial energy.
  using books = std::array<double, 5>;
  /// The default of the most bytes of rows (all ranks together) one collective of a gather
  /// moves: the bound on each of its two buffers.
  static constexpr std::size_t default_chunk_bytes = std::size_t{32} << 20;

  /// Owners for `s` (built from `mesh`, split by `own`) in `comm`; a gather moves at most
  /// `chunk_bytes` (>= 1, the same on every rank) of rows a collective. Throws invalid_input when
  /// the mesh or the ownership do not match the solver, the ranks' models differ in size, or
  /// chunk_bytes is 0 or over 1 GiB. Every rank of the communicator must call it.
  template <class Solver>
  state_gather(const Solver& s, const geometry::block_mesh& mesh, const rank_ownership& own, MPI_Comm comm,
               std::size_t chunk_bytes = default_chunk_bytes)
      : comm_(comm), chunk_bytes_(chunk_bytes) {
    require(chunk_bytes >= 1 && chunk_bytes <= (std::size_t{1} << 30), "distributed::state_gather: chunk_bytes = ",
            chunk_bytes, " must be in [1, 2^30]");
    MPI_Comm_rank(comm, &rank_);
    MPI_Comm_size(comm, &ranks_);
    require(ranks_ == own.ranks(), "distributed::state_gather: the communicator has ", ranks_, " ranks, the ownership ",
            own.ranks());
    require(mesh.gridpoint_count() == s.gridpoints().size(), "distributed::state_gather: the mesh has ",
            mesh.gridpoint_count(), " gridpoints, the solver ", s.gridpoints().size());
    const auto fill = [](std::vector<int>& to, index_t n, auto&& rank_of) {
      to.resize(static_cast<std::size_t>(n));
      for (index_t i = 0; i < n; ++i) to[static_cast<std::size_t>(i)] = rank_of(i);
    };
    fill(owner_[gridpoint], s.gridpoints().size(), [&](index_t g) { return own.gridpoint_rank(g); });
    fill(owner_[block], mesh.block_count(), [&](index_t b) { return own.block_rank(b); });
    fill(owner_[zone], static_cast<index_t>(mesh.zone_block.size()),
         [&](index_t z) { return own.block_rank(mesh.zone_block[static_cast<std::size_t>(z)]); });
    const auto& c = s.contacts();
    fill(owner_[subcontact], c.subcontact_count(), [&](index_t i) { return own.contact_owner(i); });
    fill(owner_[face], c.face_count(), [&](index_t f) {
      const auto& sf = c.shared_face(f);
      return own.block_rank(std::min(sf.cell_a, sf.cell_b));
    });
    fill(owner_[bar_node], own.bar_node_count(), [&](index_t n) { return own.bar_node_rank(n); });
    if constexpr (Solver::reinforcement_type::enabled) {
      const auto pairs = bar_element_pairs(s.reinforcement());
      fill(owner_[bar_element], static_cast<index_t>(pairs.size()),
           [&](index_t e) { return own.bar_node_rank(pairs[static_cast<std::size_t>(e)][0]); });
    }
    // Every rank must visit the same records in the same chunks: the models' sizes must agree.
    std::array<long long, kind_count> sizes{};
    for (std::size_t k = 0; k < kind_count; ++k) sizes[k] = static_cast<long long>(owner_[k].size());
    std::vector<long long> all(static_cast<std::size_t>(ranks_) * kind_count);
    MPI_Allgather(sizes.data(), kind_count, MPI_LONG_LONG, all.data(), kind_count, MPI_LONG_LONG, comm);
    constexpr std::array<const char*, kind_count> kinds = {"gridpoints", "blocks", "zones", "sub-contacts",
                                                           "faces", "bar nodes", "bar elements"};
    for (int r = 0; r < ranks_; ++r)
      for (std::size_t k = 0; k < kind_count; ++k)
        require(all[static_cast<std::size_t>(r) * kind_count + k] == sizes[k], "distributed::state_gather: rank ", r,
                " has ", all[static_cast<std::size_t>(r) * kind_count + k], " ", kinds[k], " where rank ", rank_,
                " has ", sizes[k], " (the ranks built different models)");
    counts_.resize(static_cast<std::size_t>(ranks_));
    offsets_.assign(static_cast<std::size_t>(ranks_) + 1, 0);
  }

  /// Every rank's `s` takes the owners' rows of every evolving field and of the nodal forces
  /// (file comment); the books are left as they are (gather_books). One pass of the solver's
  /// checkpoint(): for each record, chunk by chunk, this rank packs its rows, one MPI_Allgatherv
  /// exchanges them, and every row is written from its owner's part, as a checkpoint load does.
  /// Every rank must call it.
  template <class Solver>
  void gather(Solver& s) {
    mode_ = pass::rows;
    visit(s);
  }

  /// Replaces `s`'s work books by their sum over the ranks (in rank order; initial_share is this
  /// rank's share of the initial energy, distributed::stepper::initial_energy_share, and
  /// applied_pending the work of its applied forces over the last step, not booked yet:
  /// stepper::pending_applied_work) and returns this rank's own books, for put_books. Every rank
  /// must call it.
  template <class Solver>
  [[nodiscard]] books gather_books(Solver& s, double initial_share, double applied_pending = 0) {
    mode_ = pass::read_books;
    s.checkpoint(*this);
    const books mine = own_books_;  // as the rank's solver holds them, to put back
    books share = mine;
    share[3] += applied_pending;
    share[4] = initial_share;
    std::vector<double> all(static_cast<std::size_t>(ranks_) * share.size());
    MPI_Allgather(share.data(), static_cast<int>(share.size()), MPI_DOUBLE, all.data(), static_cast<int>(share.size()),
                  MPI_DOUBLE, comm_);
    books sum{};
    for (int r = 0; r < ranks_; ++r)
      for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += all[static_cast<std::size_t>(r) * sum.size() + k];
    put_books(s, sum);
    return mine;
  }
  /// Sets `s`'s work books to `b` (the order of `books`).
  template <class Solver>
  void put_books(Solver& s, const books& b) {
    mode_ = pass::write_books;
    own_books_ = b;
    s.checkpoint(*this);
  }

  // ---- the archive calls of io/checkpoint.hpp ----
  // A checkpoint's save and load each visit a record once; the gather does both in that visit.
  [[nodiscard]] bool saving() const { return mode_ == pass::rows; }  ///< As a checkpoint writer in its row pass
  [[nodiscard]] bool loading() const { return mode_ == pass::rows; }  ///< As a checkpoint reader in its row pass
  template <class T>
  void same(std::string_view, const T&) {}  ///< Nothing to gather
  void count(std::string_view, std::int64_t&) {}  ///< Nothing to gather
  template <class T>
  void scalar(std::string_view name, T& x) {  ///< Gathers or scatters a scalar record
    const int k = book_index(name);
    if (k < 0) return;  // step, time, dt: the same on every rank
    if constexpr (std::is_floating_point_v<T>) {
      if (mode_ == pass::read_books) own_books_[static_cast<std::size_t>(k)] = x;
      if (mode_ == pass::write_books) x = own_books_[static_cast<std::size_t>(k)];
    }
  }
  template <class T>
  void array(std::string_view name, std::vector<T>& v) {  ///< Gathers or scatters an array record by rows
    if (!rows_pass()) return;
    const std::vector<int>& owner = owners_of(name);
    const std::size_t n = owner.size();
    // n rows, or n x k values stored component-major (a law's vector fields), or n rows and padding.
    const bool component_major = n > 0 && v.size() > n && v.size() % n == 0;
    gather_rows(v.size(), [&](std::size_t i) { return i < n || component_major ? owner[i % n] : -1; },
                [&](std::size_t i) { return reinterpret_cast<unsigned char*>(&v[i]); }, sizeof(T));
  }
  template <class S, class M>
  void members(std::string_view name, std::vector<S>& v, M S::*m) {  ///< Gathers or scatters one member of each element of v
    if (!rows_pass()) return;
    const std::vector<int>& owner = owners_of(name);
    require(owner.size() == v.size(), "distributed::state_gather: record '", name, "' has ", v.size(), " rows, the ",
            owner.size(), " of its owners");
    gather_rows(v.size(), [&](std::size_t i) { return owner[i]; },
                [&](std::size_t i) { return reinterpret_cast<unsigned char*>(&(v[i].*m)); }, sizeof(M));
  }
  template <class Mat>
  void matrix(std::string_view name, Mat& m) {  ///< Gathers or scatters a matrix record by rows
    if (!rows_pass()) return;
    // The forces applied from outside (a platen's, solver/applied_*): the per-step callback
    // writes them on every rank from rows every rank holds (split_run::share_rows), so they are
    // every rank's already and are not gathered.
    if (name.starts_with("solver/applied_")) return;
    const std::vector<int>& owner = owners_of(name);
    require(static_cast<std::size_t>(m.rows()) == owner.size(), "distributed::state_gather: record '", name, "' has ",
            m.rows(), " rows, the ", owner.size(), " of its owners");
    const auto rows = static_cast<std::size_t>(m.rows());
    gather_rows(static_cast<std::size_t>(m.size()), [&](std::size_t k) { return owner[k % rows]; },
                [&](std::size_t k) {
                  const auto r = static_cast<Eigen::Index>(k % rows), c = static_cast<Eigen::Index>(k / rows);
                  return reinterpret_cast<unsigned char*>(&m(r, c));
                },
                sizeof(typename Mat::Scalar));
  }

 private:
  enum kind { gridpoint, block, zone, subcontact, face, bar_node, bar_element, kind_count };
  enum class pass { rows, read_books, write_books };
  [[nodiscard]] bool rows_pass() const { return mode_ == pass::rows; }

  /// The records of one pass: the solver's checkpoint and the nodal forces.
  template <class Solver>
  void visit(Solver& s) {
    s.checkpoint(*this);
    matrix("gridpoints/force", s.gridpoints().force);
    if constexpr (Solver::reinforcement_type::enabled) matrix("bars/nodes/force", s.bar_nodes().force);
  }

  [[nodiscard]] static int book_index(std::string_view name) {
    constexpr std::array<std::string_view, 5> names = {"solver/boundary_work", "solver/damping_dissipated",
                                                       "solver/gravity_work", "solver/applied_work",
                                                       "solver/initial_energy"};
    for (std::size_t k = 0; k < names.size(); ++k)
      if (name == names[k]) return static_cast<int>(k);
    return -1;
  }

  [[nodiscard]] const std::vector<int>& owners_of(std::string_view name) const {
    const auto starts = [&](std::string_view p) { return name.substr(0, p.size()) == p; };
    if (starts("gridpoints/")) return owner_[gridpoint];
    if (starts("bars/nodes/") || starts("bars/bond/") || name == "bars/transverse_gap" || name == "bars/confining_stress")
      return owner_[bar_node];
    if (starts("bars/element/")) return owner_[bar_element];
    if (starts("contacts/state/") || name == "contacts/tensile_strength" || starts("contacts/force_a/"))
      return owner_[subcontact];
    if (name == "contacts/normal" || name == "contacts/previous_normal") return owner_[face];
    if (name == "blocks/deformable/rotation") return owner_[block];
    if (name == "blocks/deformable/local_stress") return owner_[zone];
    throw invalid_input(tessera::detail::concat("distributed::state_gather: no owner rule for the checkpoint record '",
                                                name, "'; add one (distributed/gather.hpp)"));
  }

  /// Rows [0, count) (element i at at(i), `size` bytes) whose owner(i) is a rank (-1: not
  /// gathered), in chunks of at most chunk_bytes: each chunk's rows of this rank are packed into
  /// send_, one MPI_Allgatherv brings every rank's into received_, and every other rank's rows
  /// are copied from their owner's part.
  template <class Owner, class At>
  void gather_rows(std::size_t count, Owner&& owner, At&& at, std::size_t size) {
    const std::size_t chunk = std::max<std::size_t>(1, chunk_bytes_ / size);
    for (std::size_t begin = 0; begin < count; begin += chunk) {
      const std::size_t end = std::min(count, begin + chunk);
      // Every rank knows every row's owner, so each works out the others' counts itself.
      send_.clear();
      std::fill(counts_.begin(), counts_.end(), 0);
      for_runs(begin, end, owner, at, size, [&](int r, unsigned char* first, std::size_t bytes) {
        counts_[static_cast<std::size_t>(r)] += static_cast<int>(bytes);
        if (r == rank_) send_.insert(send_.end(), first, first + bytes);
      });
      const int mine = static_cast<int>(send_.size());
      for (std::size_t r = 0; r < counts_.size(); ++r) offsets_[r + 1] = offsets_[r] + counts_[r];
      received_.resize(static_cast<std::size_t>(offsets_.back()));
      MPI_Allgatherv(send_.data(), mine, MPI_BYTE, received_.data(), counts_.data(), offsets_.data(), MPI_BYTE, comm_);
      cursor_.assign(offsets_.begin(), offsets_.end() - 1);
      for_runs(begin, end, owner, at, size, [&](int r, unsigned char* first, std::size_t bytes) {
        int& k = cursor_[static_cast<std::size_t>(r)];
        if (r != rank_) std::memcpy(first, received_.data() + k, bytes);
        k += static_cast<int>(bytes);
      });
    }
  }

  /// f(owner, first byte, bytes) for each run of rows [begin, end) with one owner (>= 0) and
  /// adjacent bytes (the rows of a block's gridpoints, a rank's sub-contacts): one copy a run.
  template <class Owner, class At, class F>
  static void for_runs(std::size_t begin, std::size_t end, Owner& owner, At& at, std::size_t size, F&& f) {
    for (std::size_t i = begin; i < end;) {
      const int r = owner(i);
      unsigned char* first = at(i);
      std::size_t n = 1;
      while (i + n < end && owner(i + n) == r && at(i + n) == first + n * size) ++n;
      if (r >= 0) f(r, first, n * size);
      i += n;
    }
  }

  MPI_Comm comm_;
  std::size_t chunk_bytes_;
  int rank_ = 0, ranks_ = 1;
  pass mode_ = pass::rows;
  books own_books_{};
  std::array<std::vector<int>, kind_count> owner_;
  std::vector<unsigned char> send_, received_;  ///< a chunk's rows of this rank; of every rank, in rank order
  std::vector<int> counts_, offsets_, cursor_;   ///< each rank's bytes, start, and next byte to copy in a chunk
};

}  // namespace tessera::distributed

#endif  // TESSERA_HAVE_MPI
