#pragma once
// The example drivers under mpirun (docs/guide.md, "Splitting a run over MPI ranks"):
//
//     mpirun -np 2 build/release/examples/direct_tension --quick --out results/split
//
// takes the same flags as one process and writes the same curve.csv, to the bit. How:
// - mpi_session (in main, before parsing) calls MPI_Init only when the process was started by an
//   MPI launcher (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK in the environment), so a driver run
//   by hand never starts MPI. Rank 0 writes --out and the console; every other rank writes into a
//   scratch directory it removes at exit, its stdout goes to /dev/null and its progress line is off
//   (errors stay on stderr).
// - run_sampled replaces the driver's `s.run_until(done, ..., per_step, every(sample, sampler))`:
//   one process runs exactly that; split over ranks, each rank steps its part
//   (distributed::split_run) and, at every sample, gathers the whole model's state, so the
//   driver's sampler and everything after the run read one process's bits (the work books of
//   the energy balance to round-off; distributed/gather.hpp).
// - The split's figures (ranks, partition, halo bytes and time per step, imbalance) go into
//   summary.json through set_split_figures; "mpi_ranks" is there in every run.
// What splits through run_sampled is what distributed::stepper covers: deformable blocks with
// bonded faces and embedded bars; rubble steps its rigid blocks on detected contacts with
// distributed::rigid_stepper itself. Any other rigid-block or detected-contact scene under more
// than one rank is refused.

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "tessera/core/errors.hpp"
#include "tessera/geometry/block_mesh.hpp"
#include "tessera/io/json.hpp"
#include "tessera/solver/recorders.hpp"

#include <unistd.h>

#ifdef TESSERA_HAVE_MPI
#include <mpi.h>

#include "tessera/distributed/split_run.hpp"
#endif

namespace tessera::scenes {

/// The figures summary.json reports for a split (ranks = 1 when the run was one process).
struct split_summary {
  int ranks = 1;
#ifdef TESSERA_HAVE_MPI
  distributed::split_figures figures;
#endif
};

/// The driver's MPI session (file comment). One per process, in main, before anything is read.
class mpi_session {
 public:
  mpi_session(int& argc, char**& argv) {
    current() = this;
#ifdef TESSERA_HAVE_MPI
    if (!launched_by_mpi()) return;
    MPI_Init(&argc, &argv);
    initialised_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks_);
#else
    (void)argc;
    (void)argv;
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
      if (const char* n = std::getenv(v); n != nullptr) launched_ranks_ = std::atoi(n);
#endif
  }
  mpi_session(const mpi_session&) = delete;
  mpi_session& operator=(const mpi_session&) = delete;
  ~mpi_session() {
    std::error_code ignored;
    if (!scratch_.empty()) std::filesystem::remove_all(scratch_, ignored);
#ifdef TESSERA_HAVE_MPI
    if (initialised_) MPI_Finalize();
#endif
    current() = nullptr;
  }

  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int ranks() const { return ranks_; }
  /// More than one rank: the run is split.
  [[nodiscard]] bool split() const { return ranks_ > 1; }

  /// Refuses, before anything is written, a run that cannot be split: started by an MPI launcher
  /// with more than one rank where the driver was built without MPI (every rank would run the
  /// whole model and write the same files), or a scene or scheme that does not split (`splits`
  /// false; `why` says what: rigid blocks on bonded faces, kinetic relaxation). Throws
  /// invalid_input naming the rank count.
  void require_splittable(bool splits, const char* what,
                          const char* why = "rigid blocks on bonded faces are not distributed yet") const {
    require(launched_ranks_ <= 1, "started on ", launched_ranks_, " MPI ranks, but this driver was built without MPI "
            "(CMake TESSERA_MPI off); run it as one process, or build with Open MPI installed");
    require(!split() || splits, what, " cannot run split over ", ranks_, " MPI ranks: ", why, "; run it as one process");
  }

  /// On ranks other than 0: `out` becomes a scratch directory (removed when the session ends)
  /// and stdout /dev/null, so only rank 0's outputs and report are seen. Call after parsing.
  void route_output(std::string& out) {
    if (rank_ == 0) return;
    scratch_ = std::filesystem::temp_directory_path() /
               tessera::detail::concat("tessera_rank", rank_, "_", static_cast<long long>(::getpid()));
    out = scratch_.string();
    if (std::freopen("/dev/null", "w", stdout) == nullptr) std::perror("mpi_session: stdout to /dev/null");
    ::setenv("TESSERA_PROGRESS", "0", 1);  // rank 0's progress line is the run's
  }

  /// The split figures of the last run_sampled (ranks = 1 when it ran as one process).
  split_summary last_split;

  /// The session of this process, or nullptr outside main's lifetime of one.
  [[nodiscard]] static mpi_session*& current() {
    static mpi_session* s = nullptr;
    return s;
  }

 private:
  [[nodiscard]] static bool launched_by_mpi() {
    return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr ||
           std::getenv("PMIX_RANK") != nullptr;
  }
  int rank_ = 0, ranks_ = 1;
  int launched_ranks_ = 1;  ///< ranks of a launcher that started a driver built without MPI
  bool initialised_ = false;
  std::filesystem::path scratch_;
};

/// Steps `s` (built from `mesh`) until `done` is set, calling per_step(s) after every step and
/// sampler(s) every `sample` steps (by step count): s.run_until in one process; split over the
/// session's ranks with the whole model's state gathered before each sample (file comment), and
/// once more at the end. per_step may read the u, v and reactions of `rows_per_step` (gridpoints:
/// a rigid platen's, a hinged plate's) and write applied forces; split, those rows are made
/// current on every rank after each step (split_run::share_rows). Throws invalid_input when the
/// session has more than one rank and the solver cannot be split (rigid blocks, detected contacts).
template <class Solver, class PerStep, class Sampler>
void run_sampled(Solver& s, [[maybe_unused]] const geometry::block_mesh& mesh, const bool& done, PerStep&& per_step,
                 index_t sample, Sampler&& sampler, [[maybe_unused]] const std::vector<index_t>& rows_per_step = {}) {
  mpi_session* session = mpi_session::current();
  if (session == nullptr || !session->split()) {
    s.run_until([&](const Solver&) { return done; }, std::int64_t{1} << 40, per_step,
                recorders::every(sample, sampler));
    if (session != nullptr) session->last_split = {};
    return;
  }
#ifdef TESSERA_HAVE_MPI
  if constexpr (distributed::splittable<Solver>) {
    distributed::split_run<Solver> run(s, mesh, MPI_COMM_WORLD);
    run.set_shared_rows(rows_per_step);
    bool gathered = false;
    while (!done) {
      run.step();
      run.share_rows();
      per_step(std::as_const(s));
      gathered = s.step_count() % sample == 0;
      if (gathered) {
        run.gather_state();
        sampler(std::as_const(s));
      }
    }
    if (!gathered) run.gather_state();
    session->last_split.ranks = session->ranks();
    session->last_split.figures = run.figures();
  } else {
    throw invalid_input(tessera::detail::concat(
        "this scene cannot run split over ", session->ranks(),
        " MPI ranks: only deformable blocks on bonded faces split through run_sampled (rigid blocks on "
        "detected contacts: distributed::rigid_stepper); run it with one rank"));
  }
#endif
}

/// summary.json's figures of the split: "mpi_ranks" always; with more than one rank also the
/// partitioner, blocks per rank, the partition's weight imbalance and cut, the halo's bytes per
/// step (all ranks, and the most one rank sends), the slowest rank's halo and step time per
/// step, the measured imbalance of the ranks' work (max / mean of step minus halo time), and the
/// time spent gathering the samples.
inline void set_split_figures(io::summary_json& js) {
  const mpi_session* session = mpi_session::current();
  const split_summary none;
  const split_summary& s = session != nullptr ? session->last_split : none;
  js.set("mpi_ranks", s.ranks);
#ifdef TESSERA_HAVE_MPI
  if (s.ranks <= 1) return;
  const distributed::split_figures& f = s.figures;
  std::vector<double> blocks(f.rank_blocks.begin(), f.rank_blocks.end());
  js.set("mpi_partitioner", f.partitioner)
      .set("mpi_rank_blocks", blocks)
      .set("mpi_weight_imbalance", f.weight_imbalance)
      .set("mpi_edge_cut_subcontacts", f.edge_cut)
      .set("mpi_halo_bytes_per_step", f.halo_bytes_per_step)
      .set("mpi_max_rank_halo_bytes_per_step", f.max_rank_halo_bytes_per_step)
      .set("mpi_halo_s_per_step", f.halo_seconds_per_step)
      .set("mpi_step_s_per_step", f.step_seconds_per_step)
      .set("mpi_time_imbalance", f.time_imbalance)
      .set("mpi_gather_s", f.gather_seconds);
#endif
}

}  // namespace tessera::scenes
