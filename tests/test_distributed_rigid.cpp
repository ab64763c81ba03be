// distributed::rigid_stepper against one process, under mpiexec on 2 and 3 ranks (CTests
// distributed_mpi_step_2 and _3): a small heap of rigid Voronoi blocks dropped on a floor, every
// contact detected, stepped split and as one process side by side on every rank. Through the fall,
// the first contacts, rebuilds and the heap's settling, every block's body state and every
// gridpoint of the split run must be one process's to the bit (blocks migrating between ranks at
// rebuilds, and not), with the same rebuilds, keys and
// time step; the kinetic and stored energies the same bits, the summed work books and contact
// dissipation within 1e-10 of one process's (another summation order). A split heap saved per
// rank restarts to the same bits ("[checkpoint]").

#include <catch2/catch.hpp>

#include <mpi.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "tessera/blocks/rigid.hpp"
#include "tessera/contact/detected_contacts.hpp"
#include "tessera/distributed/rigid_stepper.hpp"
#include "tessera/geometry/shapes.hpp"
#include "tessera/geometry/voronoi.hpp"
#include "tessera/geometry/zoning.hpp"
#include "tessera/io/checkpoint.hpp"
#include "tessera/solver/solver.hpp"
#include "verification/inputs.hpp"

using namespace tessera;
namespace ver = tessera::verification;

namespace {

using heap_solver = solver<blocks::rigid, ver::contacts, reinforcement::none, ver::damped>;

/// 40 Voronoi blocks of a 0.5 m cube, shrunk 2 % about their centroids, 5 mm above a fixed floor
/// (block 0): the rubble example's scene, small.
struct heap_scene {
  geometry::tessellation tess;
  geometry::block_mesh mesh;
  real tolerance = 0;
  heap_scene() {
    std::vector<geometry::convex_polyhedron> cells{geometry::convex_polyhedron::box({-0.5, -0.5, -0.1}, {1.0, 1.0, 0})};
    const auto voronoi = geometry::random_voronoi({vec3::Zero(), vec3(0.5, 0.5, 0.5)}, 40, 7);
    for (index_t c = 0; c < voronoi.cell_count(); ++c) {
      const auto cell = geometry::cell_polyhedron(voronoi, c);
      cells.push_back(cell.transformed(0.98 * mat3::Identity(), 0.02 * cell.centroid() + vec3(0, 0, 0.005)));
    }
    tess = geometry::separate_blocks(cells);
    mesh = geometry::zone_blocks(tess);
    tolerance = 0.02 * 0.5 / std::cbrt(40.0);
  }
  [[nodiscard]] heap_solver make() const {
    ver::inputs in;
    in.k_n = 1e9;
    in.friction_deg = 25;
    solver_options o;
    o.damping_gamma = 0.1;
    heap_solver s(tess, mesh, blocks::rigid::params{2400}, ver::contacts::params(ver::joint(in), tolerance), {}, o);
    s.set_gravity(vec3(0.3, 0, -9.81));
    s.fix(s.gridpoints_on_plane(2, -0.1, 1e-9));
    return s;
  }
};

template <class T>
[[nodiscard]] bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

/// Gridpoint components whose displacement or velocity differ in their bits between x and y.
[[nodiscard]] index_t differing_components(const heap_solver& x, const heap_solver& y) {
  index_t bad = 0;
  for (index_t g = 0; g < x.gridpoints().size(); ++g)
    for (int c = 0; c < 3; ++c)
      if (!same_bits(x.gridpoints().displacement(g, c), y.gridpoints().displacement(g, c)) ||
          !same_bits(x.gridpoints().velocity(g, c), y.gridpoints().velocity(g, c)))
        ++bad;
  return bad;
}

/// This process's rank and the ranks of MPI_COMM_WORLD.
[[nodiscard]] std::pair<int, int> world() {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return {rank, size};
}

}  // namespace

TEST_CASE("a heap of rigid blocks on detected contacts keeps one process's bits on several ranks", "[mpi][step][rigid]") {
  const auto [rank, size] = world();
  const heap_scene scene;
  heap_solver one = scene.make();
  heap_solver split = scene.make();
  heap_solver fixed = scene.make();  // the same split with every block on its first rank throughout
  const std::vector<int> map = distributed::partition_moving_blocks(scene.mesh, size);
  distributed::rigid_stepper<heap_solver> stepper(split, map, MPI_COMM_WORLD);
  distributed::rigid_stepper<heap_solver> fixed_stepper(fixed, map, MPI_COMM_WORLD, false);
  index_t first_contact_one = -1, first_contact_split = -1;
  index_t bad_blocks = 0, bad_gridpoints = 0, bad_steps = 0;
  for (index_t k = 1; k <= 6000; ++k) {
    one.step();
    stepper.step();
    fixed_stepper.step();
    if (first_contact_one < 0 && one.contacts().energies().stored > 0) first_contact_one = k;
    if (first_contact_split < 0 && stepper.summed_energies().contact_stored > 0) first_contact_split = k;
    if (!same_bits(one.dt(), split.dt()) || one.contacts().rebuild_count() != split.contacts().rebuild_count() ||
        one.contacts().subcontact_count() != split.contacts().subcontact_count())
      ++bad_steps;
  }
  stepper.check_finite();
  const auto& a = one.blocks();
  const auto& b = split.blocks();
  for (index_t blk = 0; blk < a.block_count(); ++blk) {
    const bool same = same_bits(a.displacement(blk), b.displacement(blk)) && same_bits(a.velocity(blk), b.velocity(blk)) &&
                      same_bits(a.body_angular_velocity(blk), b.body_angular_velocity(blk)) &&
                      same_bits(a.orientation(blk).coeffs(), b.orientation(blk).coeffs()) &&
                      same_bits(a.force(blk), b.force(blk)) && same_bits(a.moment(blk), b.moment(blk));
    bad_blocks += same ? 0 : 1;
  }
  // step() slaves only the copies this rank's pairs read; the others are behind until synced.
  const index_t stale = differing_components(one, split);
  CHECK(stepper.deferred_block_count() > 0);
  long long stale_all = stale;
  MPI_Allreduce(MPI_IN_PLACE, &stale_all, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  if (size > 1) CHECK(stale_all > 0);
  stepper.sync_gridpoints();
  fixed_stepper.sync_gridpoints();
  bad_gridpoints = differing_components(one, split) + differing_components(one, fixed);
  INFO("rank " << rank << " of " << size << ": " << bad_blocks << " blocks, " << bad_gridpoints
               << " gridpoint components and " << bad_steps << " steps differ from one process");
  CHECK(bad_blocks == 0);
  CHECK(bad_gridpoints == 0);
  CHECK(bad_steps == 0);
  // The scene did what it is here for: blocks met, detection rebuilt, every rank owns blocks.
  CHECK(one.contacts().rebuild_count() > 5);
  CHECK(one.contacts().subcontact_count() > 50);
  CHECK(first_contact_one > 0);
  CHECK(first_contact_split == first_contact_one);
  CHECK(stepper.rank_blocks(rank).size() >= 10);
  // Each rank evaluated its part of the last pass's candidates (the rest came by the gather).
  const auto& dc = split.contacts();
  unsigned long long evaluated = dc.evaluated_candidate_count(), all_evaluated = 0;
  MPI_Allreduce(&evaluated, &all_evaluated, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  CHECK(all_evaluated == dc.candidate_count());
  CHECK(dc.candidate_count() == one.contacts().candidate_count());
  CHECK(one.contacts().evaluated_candidate_count() == one.contacts().candidate_count());
  if (size > 1) CHECK(evaluated <= dc.candidate_count() / static_cast<std::size_t>(size) + 1);
  // Blocks changed rank at rebuilds (the pairs that changed hands took their state along), and
  // some block now sits on another rank than at the start.
  CHECK(stepper.rebalances() > 0);
  index_t moved = 0;
  for (index_t blk = 0; blk < a.block_count(); ++blk) moved += stepper.block_rank(blk) != map[static_cast<std::size_t>(blk)];
  CHECK(moved > 0);
  CHECK(fixed_stepper.rebalances() == 0);

  // The books: one process's to round-off.
  const energy_balance e1 = one.energies(), e2 = stepper.summed_energies();
  const real scale = std::abs(e1.gravity_work);
  INFO("gravity work " << e1.gravity_work << " J one process, " << e2.gravity_work << " split");
  CHECK(scale > 1e-3);
  CHECK(e2.kinetic == e1.kinetic);  // every block's body state, the same bits
  CHECK(e2.contact_stored == e1.contact_stored);  // summed in one process's order
  for (const auto& [x, y] : {std::pair{e1.gravity_work, e2.gravity_work}, {e1.damping_dissipated, e2.damping_dissipated},
                             {e1.boundary_work, e2.boundary_work}, {e1.contact_stored, e2.contact_stored},
                             {e1.contact_dissipated, e2.contact_dissipated},
                             {e1.contact_rebuild_exchange, e2.contact_rebuild_exchange}, {e1.initial, e2.initial}})
    CHECK(std::abs(x - y) <= 1e-10 * scale);
  CHECK(std::abs(e2.error_rel() - e1.error_rel()) <= 1e-8);
  CHECK(e1.error_rel() < 1e-2);
}

TEST_CASE("a split heap saved per rank restarts to the same bits", "[mpi][step][rigid][checkpoint]") {
  const auto [rank, size] = world();
  const heap_scene scene;
  heap_solver run = scene.make();
  heap_solver restarted = scene.make();
  const std::vector<int> map = distributed::partition_moving_blocks(scene.mesh, size);
  distributed::rigid_stepper<heap_solver> step(run, map, MPI_COMM_WORLD);
  // One file per rank, each its rank's whole solver (the other ranks' pairs stale: they restart
  // as they were), in a folder named after rank 0's process.
  long long id = static_cast<long long>(::getpid());
  MPI_Bcast(&id, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("tessera_heap_" + std::to_string(id));
  std::filesystem::create_directories(folder);
  const std::filesystem::path file = folder / ("rank_" + std::to_string(rank) + ".ckpt");
  constexpr int before = 2500, after = 2500;  // the first contacts come at about 1 700 steps
  for (int k = 0; k < before; ++k) step.step();
  step.sync_gridpoints();  // every copy current in the file
  io::save_checkpoint(run, file, "distributed rigid test");
  const std::vector<int> saved_map = step.map();  // blocks may have changed rank since the start
  for (int k = 0; k < after; ++k) step.step();
  io::load_checkpoint(restarted, file);
  distributed::rigid_stepper<heap_solver> step_again(restarted, saved_map, MPI_COMM_WORLD);
  for (int k = 0; k < after; ++k) step_again.step();
  step.sync_gridpoints();
  step_again.sync_gridpoints();
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) std::filesystem::remove_all(folder);
  INFO("rank " << rank << " of " << size);
  CHECK(restarted.step_count() == run.step_count());
  CHECK(restarted.contacts().rebuild_count() == run.contacts().rebuild_count());
  CHECK(run.contacts().subcontact_count() > 50);
  CHECK(differing_components(run, restarted) == 0);
  // The books came back with the file, the initial share included: the same sums to the bit.
  const energy_balance e1 = step.summed_energies(), e2 = step_again.summed_energies();
  CHECK(same_bits(e1.initial, e2.initial));
  CHECK(same_bits(e1.gravity_work, e2.gravity_work));
  CHECK(same_bits(e1.damping_dissipated, e2.damping_dissipated));
  CHECK(same_bits(e1.contact_stored, e2.contact_stored));
  CHECK(e1.error_rel() < 1e-2);

  // The non-finite check across ranks: a NaN velocity on the last rank's first block makes every
  // rank throw, naming its first gridpoint.
  CHECK_NOTHROW(step_again.check_finite());
  const index_t victim = restarted.gridpoints_of_block(step_again.rank_blocks(size - 1).front()).nodes.front();
  if (rank == size - 1) restarted.gridpoints().velocity(victim, 2) = std::numeric_limits<real>::quiet_NaN();
  CHECK_THROWS_WITH(step_again.check_finite(), Catch::Matchers::Contains("gridpoint " + std::to_string(victim) + " "));
}
