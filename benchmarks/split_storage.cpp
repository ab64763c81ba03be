// split_storage: what a rank of a split run holds, and what that costs, with every rank holding
// the whole model (distributed::stepper on a solver of the whole scene, as split_run and the
// drivers under mpirun do) or its local model only (distributed::local_model: its own blocks and
// one layer of ghosts). The scene is the study's prism of --blocks Voronoi blocks (the drivers'
// scene builder, 68 x 68 x 600 mm), bottom fixed, top pulled along z at 5 mm/s, or (--scene tie)
// the RC tie of examples/rc_tie on it (ends on rollers, the bar's first node fixed and its last
// pulled at 5 mm/s), masses scaled to dt = 1 us (issue #44; docs/performance.md, "Local storage
// per rank"):
//
//   mpirun -np 2 build/bench-portable/benchmarks/split_storage --blocks 10000 --steps 200 --storage local
//
// Prints, per rank, the blocks it holds (and owns), its gridpoints, zones and sub-contacts, the
// resident memory the whole scene's tessellation and mesh took while they were built, its
// peak resident set (getrusage, which includes building the whole scene once) and its resident
// set after the steps (/proc/self/statm: what it holds while it runs), and the seconds per step;
// on rank 0 the load after the last step (the prism's platen, the tie's bar end) in hex (%a): the same bits for either storage,
// any rank count, thread count and partitioner (the check of a run made by hand). `--storage
// solver` steps the whole model with solver::step in one process instead (the one-process
// reference of the stepper's cost; the same bits).
#include <mpi.h>

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/cli.hpp"
#include "common/rc_tie_scene.hpp"
#include "common/scenes.hpp"
#include "tessera/distributed/block_graph.hpp"
#include "tessera/distributed/local_model.hpp"
#include "tessera/distributed/local_vtk.hpp"
#include "tessera/distributed/split_run.hpp"
#include "tessera/distributed/stepper.hpp"
#include "tessera/presets.hpp"

namespace {
using namespace tessera;
constexpr real rate = 0.005;  ///< m/s, the drivers' pull
constexpr real dt = 1e-6;     ///< s, the mass-scaling target

/// Resident set now (kB), from /proc/self/statm.
long resident_kb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}
/// Peak resident set so far (kB).
long peak_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

solver_options pull_options() {
  solver_options o;
  o.mass_scaling_dt = dt;
  return o;
}

struct rank_line {
  long long held_blocks, own_blocks, gridpoints, zones, subcontacts, scene_kb, peak_kb, resident_kb;
  double seconds_per_step;
};

/// What the command line chose.
struct setup {
  int blocks = 10000, steps = 200, threads = 1;
  index_t elements = 192;
  std::uint64_t seed = 1;
  std::string scene = "prism", storage = "local", how, vtk;
};

/// The whole scene: the prism, or the tie (the prism with its bar).
struct whole_scene {
  scenes::prism_scene prism;
  std::optional<scenes::tie_bar::params> bar;
};

/// The supports: concrete ends on rollers, the prism's bottom fixed; the prism's top, or the
/// tie's last bar node, pulled along z at `rate`; the tie's first bar node fixed. `plane(s, z)`
/// selects a rank's gridpoints on a plane (possibly none); returns the pulled concrete face (prism)
/// or an empty group (tie: its load is the bar end's reaction).
template <class Solver, class Plane>
bc::node_group support(Solver& s, bool tie, real length, Plane&& plane) {
  const bc::node_group bottom = plane(s, 0.0), top = plane(s, length);
  if (!bottom.empty()) tie ? s.fix(bottom, bc::transverse_to(2)) : s.fix(bottom);
  if (!top.empty()) s.fix(top, bc::transverse_to(2));
  if constexpr (Solver::reinforcement_type::enabled) {
    const auto [first, end] = s.reinforcement().bar_nodes(0);
    bc::fix(s.bar_nodes(), bc::node_group{{first}, "fixed bar end"});
    bc::prescribe_velocity(s.bar_nodes(), bc::node_group{{end - 1}, "pulled bar end"}, vec3(0, 0, rate));
    return {};
  } else {
    if (!top.empty()) s.prescribe_velocity(top, vec3(0, 0, rate), bc::components::z);
    return top;
  }
}

template <class Solver>
int measure(const setup& o, std::unique_ptr<whole_scene> scene, long scene_kb, int rank, int ranks) {
  constexpr bool tie = Solver::reinforcement_type::enabled;
  const auto part = o.how == "metis" ? distributed::partitioner::metis : distributed::partitioner::rcb;
  const real length = scene->prism.length(), tol = 1e-9 * length;
  distributed::block_graph_input in = distributed::blocks_of_mesh(scene->prism.mesh);
  distributed::add_face_subcontacts(in, scene->prism.tess, scene->prism.mesh);
  const std::vector<int> map = distributed::broadcast_partition(distributed::block_graph(in), MPI_COMM_WORLD, part);
  typename Solver::reinforcement_type::params bar{};
  if constexpr (tie) bar = *scene->bar;

  std::unique_ptr<distributed::local_model> lm;
  std::unique_ptr<Solver> s;
  std::unique_ptr<distributed::rank_ownership> own;
  bc::node_group top;
  if (o.storage == "local") {
    if constexpr (tie)
      lm = std::make_unique<distributed::local_model>(scene->prism.tess, scene->prism.mesh, map, ranks, rank, bar.bars);
    else
      lm = std::make_unique<distributed::local_model>(scene->prism.tess, scene->prism.mesh, map, ranks, rank);
    const auto block = scene->prism.block_material;
    const auto contact = scene->prism.contact;
    scene.reset();  // the whole scene is not needed any more
    if constexpr (tie)
      s = std::make_unique<Solver>(lm->tess, lm->mesh, block, contact, lm->bar_params(bar), pull_options());
    else
      s = std::make_unique<Solver>(lm->tess, lm->mesh, block, contact, bar, pull_options());
    top = support(*s, tie, length,
                  [&](const Solver& v, real z) { return lm->gridpoints_on_plane(v.gridpoints(), 2, z, tol, MPI_COMM_WORLD); });
    distributed::require_same_time_step(s->dt(), MPI_COMM_WORLD);
    if constexpr (tie)
      own = std::make_unique<distributed::rank_ownership>(lm->ownership(s->contacts(), s->reinforcement()));
    else
      own = std::make_unique<distributed::rank_ownership>(lm->ownership(s->contacts()));
  } else {
    const scenes::prism_scene& p = scene->prism;
    s = std::make_unique<Solver>(p.tess, p.mesh, p.block_material, p.contact, bar, pull_options());
    top = support(*s, tie, length, [&](const Solver& v, real z) { return v.gridpoints_on_plane(2, z, tol); });
    if constexpr (tie)
      own = std::make_unique<distributed::rank_ownership>(map, ranks, p.mesh, distributed::contact_pairs_of(s->contacts()),
                                                          distributed::bar_node_host_blocks(p.mesh, s->reinforcement()),
                                                          distributed::bar_element_pairs(s->reinforcement()));
    else
      own = std::make_unique<distributed::rank_ownership>(map, ranks, p.mesh, distributed::contact_pairs_of(s->contacts()));
  }
  const geometry::block_mesh& mesh = lm ? lm->mesh : scene->prism.mesh;
  distributed::stepper<Solver> step(*s, mesh, *own, MPI_COMM_WORLD);
  MPI_Barrier(MPI_COMM_WORLD);
  const auto t0 = std::chrono::steady_clock::now();
  if (o.storage == "solver")
    for (int k = 0; k < o.steps; ++k) s->step();
  else
    for (int k = 0; k < o.steps; ++k) step.step();
  step.finish_exchange();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!o.vtk.empty()) distributed::write_zones_pvtu(o.vtk, *lm, *s, MPI_COMM_WORLD);
  // The load: the pulled face's reactions summed over the ranks (prism), or the pulled bar end's
  // reaction, read on its rank (tie).
  real load = 0;
  if constexpr (tie) {
    const index_t last = s->reinforcement().bar_nodes(0).second - 1;
    const int owner = own->bar_node_rank(last);
    double mine = rank == owner ? s->bar_nodes().reaction(last, 2) : 0.0;
    MPI_Bcast(&mine, 1, MPI_DOUBLE, owner, MPI_COMM_WORLD);
    load = mine;
  } else {
    load = (lm ? lm->reaction_sum(s->gridpoints(), top, MPI_COMM_WORLD)
               : distributed::gathered_reaction_sum(s->gridpoints(), top, *own, MPI_COMM_WORLD))
               .z();
  }

  const rank_line mine{static_cast<long long>(mesh.block_count()),
                       static_cast<long long>(step.own_blocks().size()),
                       static_cast<long long>(mesh.gridpoint_count()),
                       static_cast<long long>(mesh.zone_count()),
                       static_cast<long long>(s->contacts().subcontact_count()),
                       scene_kb,
                       peak_kb(),
                       resident_kb(),
                       seconds / o.steps};
  std::vector<rank_line> all(static_cast<std::size_t>(ranks));
  MPI_Gather(&mine, sizeof(rank_line), MPI_BYTE, all.data(), sizeof(rank_line), MPI_BYTE, 0, MPI_COMM_WORLD);
  if (rank == 0) {
    std::printf("split_storage: %s of %d blocks, seed %llu, %d ranks x %d threads, storage %s, partitioner %s, %d steps\n",
                o.scene.c_str(), o.blocks, static_cast<unsigned long long>(o.seed), ranks, o.threads, o.storage.c_str(),
                o.how.c_str(), o.steps);
    std::printf("| rank | blocks held (own) | gridpoints | zones | sub-contacts | whole scene's geometry (MB) | peak RSS (MB) "
                "| RSS after the steps (MB) | s a step |\n|---|---|---|---|---|---|---|---|---|\n");
    for (int r = 0; r < ranks; ++r) {
      const rank_line& l = all[static_cast<std::size_t>(r)];
      std::printf("| %d | %lld (%lld) | %lld | %lld | %lld | %.1f | %.1f | %.1f | %.4g |\n", r, l.held_blocks, l.own_blocks,
                  l.gridpoints, l.zones, l.subcontacts, l.scene_kb / 1024.0, l.peak_kb / 1024.0, l.resident_kb / 1024.0,
                  l.seconds_per_step);
    }
    std::printf("%s after %d steps: %.9g N (%a)\n", tie ? "bar end load" : "platen load", o.steps, load, load);
  }
  return 0;
}

int run(int argc, char** argv) {
  setup o;
  o.how = distributed::partitioner_name(distributed::default_partitioner());
  cli::parser cli("split_storage",
                  "Memory and step time of a split run holding the whole model on every rank or each rank's local\n"
                  "model only (distributed::local_model), on the study's prism or tie pulled at 5 mm/s (issue #44).\n"
                  "Run it under mpirun -np N.");
  cli.option("--scene", o.scene, "the prism pulled by its top face, or the tie pulled by its bar", "prism|tie")
      .one_of({"prism", "tie"});
  cli.option("--blocks", o.blocks, "Voronoi blocks of the prism", "N").within(20, 200000);
  cli.option("--elements", o.elements, "truss elements of the tie's bar", "N").within(1, 1000000);
  cli.option("--seed", o.seed, "tessellation seed", "N");
  cli.option("--steps", o.steps, "steps to take", "N").within(1, 100000000);
  cli.option("--threads", o.threads, "OpenMP threads a rank", "T").within(1, 256);
  cli.option("--storage", o.storage, "what a rank holds; 'solver': one process stepped by solver::step, no stepper",
             "local|whole|solver")
      .one_of({"local", "whole", "solver"});
  cli.option("--partitioner", o.how, "how the blocks are cut", "metis|rcb").one_of({"metis", "rcb"});
  cli.option("--vtk", o.vtk, "with --storage local: write the zones after the steps as FILE.pvtu, one piece a rank",
             "FILE.pvtu");
  cli.parse_or_exit(argc, argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  set_threads(o.threads);
  require(o.storage != "solver" || ranks == 1, "split_storage: --storage solver is one process, not ", ranks, " ranks");
  require(o.vtk.empty() || (o.storage == "local" && std::filesystem::path(o.vtk).extension() == ".pvtu"),
          "split_storage: --vtk '", o.vtk, "' needs --storage local and a name ending in .pvtu");
  const long before_scene_kb = resident_kb();
  auto scene = std::make_unique<whole_scene>();
  if (o.scene == "tie") {
    scenes::tie_options to;
    to.blocks = o.blocks;
    to.seed = o.seed;
    to.elements = o.elements;
    scenes::tie_scene t = scenes::make_tie(to);
    scene->prism = std::move(t.prism);
    scene->bar = std::move(t.bar);
  } else {
    scenes::prism_options po;
    po.blocks = o.blocks;
    po.seed = o.seed;
    scene->prism = scenes::make_prism(po);
  }
  const long scene_kb = resident_kb() - before_scene_kb;  // the whole tessellation and mesh
  if (o.scene == "tie")
    return measure<scenes::tie_solver<scenes::deformable_blocks, presets::study_tie_law>>(o, std::move(scene), scene_kb,
                                                                                            rank, ranks);
  return measure<prism_solver>(o, std::move(scene), scene_kb, rank, ranks);
}
}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int code = 0;
  try {
    code = run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "split_storage: %s\n", e.what());
    code = 2;
  }
  MPI_Finalize();
  return code;
}
