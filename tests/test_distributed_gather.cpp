// distributed::split_run and its state_gather (include/tessera/distributed/split_run.hpp,
// gather.hpp) under mpiexec, part of test_distributed_step (CTests distributed_mpi_step_2/3):
// the study's 100-block prism pulled past its first softening, stepped as one process (the
// reference) and split over the ranks. After a gather, every rank's solver holds the reference's
// state: every gridpoint's u, v, reaction and force and every sub-contact's state to the bit, the
// unbalanced force to the bit, the energies' state terms to the bit and the work books to
// round-off. A gather midway must not disturb the split (its books are put back before the next
// step), and a checkpoint rank 0 writes after a gather is one of the whole model: a one-process
// solver loads it and steps on with the reference's bits. Under gravity (each own gridpoint's force
// starts from its weight) the same bits, and the weights' work summed over the ranks. The refusals:
// applied forces registered after the split was built, a shared row that does not exist, a gather
// in chunks of 0 bytes; a gather in chunks of 100 bytes places every row as the default one does.
#include <catch2/catch.hpp>

#include <mpi.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "support/split_prism.hpp"
#include "tessera/distributed/split_run.hpp"
#include "tessera/io/checkpoint.hpp"

using namespace tessera;
using namespace split_test;

namespace {
/// Every gridpoint's row of u, v, reactions and forces whose bits differ from the reference's.
[[nodiscard]] index_t differing_gridpoints(const prism_solver& s, const prism_solver& ref) {
  std::vector<index_t> all(static_cast<std::size_t>(ref.gridpoints().size()));
  for (std::size_t g = 0; g < all.size(); ++g) all[g] = static_cast<index_t>(g);
  index_t bad = 0;
  for (soa3 node_set::*m : {&node_set::displacement, &node_set::velocity, &node_set::reaction, &node_set::force})
    bad += differing_rows(s.gridpoints().*m, ref.gridpoints().*m, all);
  return bad;
}
[[nodiscard]] index_t differing_subcontacts(const prism_solver& s, const prism_solver& ref) {
  std::vector<index_t> all(static_cast<std::size_t>(ref.contacts().subcontact_count()));
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<index_t>(i);
  return differing_states(s.contacts(), ref.contacts(), all);
}
}  // namespace

TEST_CASE("a gathered split run holds one process's state on every rank", "[mpi][step][gather]") {
  const auto [rank, size] = rank_and_size();
  const prism_scene scene;
  pulled_prism reference(scene);
  pulled_prism split(scene);
  distributed::split_run<prism_solver> run(split, scene.mesh, MPI_COMM_WORLD);
  // Chunks of 100 bytes: a few rows a collective, chunk ends inside runs of one rank's rows, and
  // 8-byte rows (reals, stored component by component) that do not divide the chunk.
  distributed::state_gather small(split, scene.mesh, run.ownership(), MPI_COMM_WORLD, 100);
  REQUIRE_THROWS_WITH(distributed::state_gather(split, scene.mesh, run.ownership(), MPI_COMM_WORLD, 0),
                      Catch::Contains("chunk_bytes = 0 must be in [1, 2^30]"));
  INFO("rank " << rank << " of " << size);

  // Before any step nothing differs; gathers midway (steps 250 and 400) must leave the split's
  // bits alone, and the one in small chunks places every row as the default one does.
  constexpr int steps = 500;
  for (int k = 1; k <= steps; ++k) {
    reference.step();
    run.step();
    if (k == 250) run.gather_state();
    if (k == 400) {
      small.gather(split);
      CHECK(differing_gridpoints(split, reference) == 0);
      CHECK(differing_subcontacts(split, reference) == 0);
    }
  }
  // Without a gather the other ranks' rows are stale on a rank: the comparison sees it.
  if (size > 1) CHECK(differing_gridpoints(split, reference) > 0);
  run.gather_state();
  CHECK(split.step_count() == reference.step_count());
  CHECK(differing_gridpoints(split, reference) == 0);
  CHECK(differing_subcontacts(split, reference) == 0);
  index_t softened = 0;
  for (index_t i = 0; i < reference.contacts().subcontact_count(); ++i)
    softened += reference.contacts().state(i).u_soft > 0 ? 1 : 0;
  CHECK(softened > 0);  // the law's softening branch is in the comparison
  const out_of_balance ub = split.unbalanced_force(), ub_ref = reference.unbalanced_force();
  CHECK(same_bits(ub.max_force, ub_ref.max_force));
  CHECK(ub.max_node == ub_ref.max_node);
  const energy_balance e = split.energies(), e_ref = reference.energies();
  CHECK(same_bits(e.kinetic, e_ref.kinetic));
  CHECK(same_bits(e.block_elastic, e_ref.block_elastic));
  CHECK(same_bits(e.contact_stored, e_ref.contact_stored));
  CHECK(same_bits(e.contact_dissipated, e_ref.contact_dissipated));
  // The books: sums over the ranks' gridpoints, another order than one process's.
  CHECK(std::abs(e.boundary_work - e_ref.boundary_work) <= 1e-12 * std::abs(e_ref.boundary_work));
  CHECK(std::abs(e.damping_dissipated - e_ref.damping_dissipated) <= 1e-12 * std::abs(e_ref.damping_dissipated));
  CHECK(e_ref.boundary_work > 0);

  // The split's figures, the same on every rank.
  const distributed::split_figures f = run.figures();
  CHECK(f.ranks == size);
  CHECK(f.steps == steps);
  CHECK(f.weight_imbalance >= 1.0);
  CHECK(f.weight_imbalance < 1.1);
  if (size > 1) CHECK(f.halo_bytes_per_step > 0);

  // A gathered checkpoint, written by rank 0, is the whole model's: one process loads it and
  // steps on with the reference's bits.
  long long id = static_cast<long long>(::getpid());
  MPI_Bcast(&id, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("tessera_gathered_" + std::to_string(id) + ".ckpt");
  if (rank == 0) io::save_checkpoint(split, file, "gathered split run");
  MPI_Barrier(MPI_COMM_WORLD);
  pulled_prism alone(scene);
  io::load_checkpoint(alone, file);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) std::filesystem::remove(file);
  for (int k = 0; k < 100; ++k) {
    alone.step();
    reference.step();
  }
  CHECK(differing_gridpoints(alone, reference) == 0);
  CHECK(differing_subcontacts(alone, reference) == 0);
}

TEST_CASE("a split run under gravity keeps one process's bits and books the weights' work", "[mpi][step][gather]") {
  const auto [rank, size] = rank_and_size();
  INFO("rank " << rank << " of " << size);
  const prism_scene scene;
  // A sideways part, so the weights move the free gridpoints across the pull as well as along it.
  const vec3 g(2.0, 0, -9.81);
  pulled_prism reference(scene), split(scene), weightless(scene);
  reference.set_gravity(g);
  split.set_gravity(g);
  distributed::split_run<prism_solver> run(split, scene.mesh, MPI_COMM_WORLD);
  constexpr int steps = 300;
  for (int k = 0; k < steps; ++k) {
    reference.step();
    weightless.step();
    run.step();
  }
  const energy_balance summed = run.step_of_rank().summed_energies(MPI_COMM_WORLD);
  run.gather_state();
  CHECK(differing_gridpoints(weightless, reference) > 0);  // the weights are in the comparison
  CHECK(differing_gridpoints(split, reference) == 0);
  CHECK(differing_subcontacts(split, reference) == 0);
  const energy_balance e = split.energies(), e_ref = reference.energies();
  CHECK(e_ref.gravity_work != 0);
  CHECK(std::abs(e.gravity_work - e_ref.gravity_work) <= 1e-12 * std::abs(e_ref.gravity_work));
  CHECK(std::abs(summed.gravity_work - e_ref.gravity_work) <= 1e-12 * std::abs(e_ref.gravity_work));
  CHECK(same_bits(e.kinetic, e_ref.kinetic));
  CHECK(std::abs(e.error_rel() - e_ref.error_rel()) <= 1e-9);
}

TEST_CASE("a split run with applied forces books their work in the summed balance", "[mpi][step][gather]") {
  const auto [rank, size] = rank_and_size();
  INFO("rank " << rank << " of " << size);
  const prism_scene scene;
  pulled_prism reference(scene), split(scene);
  // A sideways push on the x = 0 face, registered before the split is built (as the beam's load).
  for (prism_solver* s : {static_cast<prism_solver*>(&reference), static_cast<prism_solver*>(&split)}) {
    const bc::node_group face = s->gridpoints_on_plane(0, 0.0, 1e-9);
    const std::vector<index_t>& loaded = face.nodes;
    s->register_applied_forces(loaded, std::vector<real>(loaded.size(), 0.0));
    for (const index_t g : loaded) s->applied_forces()(g, 0) = 50.0;  // N, along +x
  }
  distributed::split_run<prism_solver> run(split, scene.mesh, MPI_COMM_WORLD);
  for (int k = 0; k < 300; ++k) {
    reference.step();
    run.step();
  }
  const energy_balance summed = run.step_of_rank().summed_energies(MPI_COMM_WORLD), e_ref = reference.energies();
  CHECK(e_ref.applied_work > 0);
  CHECK(std::abs(summed.applied_work - e_ref.applied_work) <= 1e-12 * e_ref.applied_work);
  CHECK(std::abs(summed.error_rel() - e_ref.error_rel()) <= 1e-9);
  run.gather_state();
  CHECK(differing_gridpoints(split, reference) == 0);
}

TEST_CASE("split_run refuses applied forces registered after it was built", "[mpi][step][gather]") {
  const prism_scene scene;
  pulled_prism s(scene);
  distributed::split_run<prism_solver> run(s, scene.mesh, MPI_COMM_WORLD);
  run.step();
  const std::vector<index_t> loaded{0};
  const std::vector<real> stiffness{0.0};
  s.register_applied_forces(loaded, stiffness);
  CHECK_THROWS_WITH(run.step(), Catch::Matchers::Contains("1 gridpoints carry applied forces, 0 when the stepper was built"));
  CHECK_THROWS_WITH(run.set_shared_rows({s.gridpoints().size()}), Catch::Matchers::Contains("is not one of the"));
  run.step_of_rank().finish_exchange();  // the first step's halo, still in flight
}
