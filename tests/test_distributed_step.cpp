// The distributed step (include/tessera/distributed/stepper.hpp) against one process, under
// mpiexec (CTests distributed_mpi_step_2 and _3): the study's 100-block prism (the scene of
// examples/direct_tension: deformable semi-rigid blocks, the power-softening tie law), bottom
// fixed, top pulled along z, run on every rank as one process (the reference, the
// whole model stepped by solver::step, one thread) and split over the ranks in two ways (slabs by
// bisection on one thread a rank, METIS's cut on two threads a rank). Every few steps each rank
// compares, bit for bit, u, v and the reactions of its own gridpoints, the law state of every
// sub-contact it evaluates, and the load on the pulled platen gathered over the ranks in group
// order; at the end also its ghosts after the last exchange. The run goes through the first
// softening of contacts (checked), so the law's nonlinear branches are exercised. A last section
// shows that a bit comparison sees the order of a gather: summed in another order, the contact
// forces of some gridpoint and the platen load take other bits. The second case ("[bars]") is
// the reinforced tie on the same prism (one bar on the axis, pulled by its end through the bond):
// own gridpoints and own bar nodes compared bit for bit, ghost bar nodes in the halo. The third
// ("[checkpoint]") saves a split run per rank halfway and restarts it: the same bits again; then
// a NaN on one rank makes every rank's non-finite check throw.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <mpi.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <span>
#include <utility>
#include <vector>

#include "tessera/distributed/block_graph.hpp"
#include "tessera/distributed/ownership.hpp"
#include "tessera/distributed/partition.hpp"
#include "tessera/distributed/stepper.hpp"
#include "tessera/geometry/voronoi.hpp"
#include "tessera/geometry/zoning.hpp"
#include "tessera/io/checkpoint.hpp"
#include "tessera/presets/pulatsu2020.hpp"
#include "tessera/reinforcement/embedded_truss.hpp"
#include "tessera/solver/recorders.hpp"
#include "tessera/solver/solver.hpp"

#include "support/split_prism.hpp"

using namespace tessera;
using namespace split_test;

/// One split of the model: its solver (the whole model, stepped by the ranks' stepper), the
/// ownership of a block -> rank map and the stepper, with the mismatches its comparisons found.
struct split_run {
  const char* name;
  int threads;  ///< OpenMP threads of its steps on every rank
  std::unique_ptr<pulled_prism> solver;
  std::unique_ptr<distributed::rank_ownership> own;
  std::unique_ptr<distributed::stepper<prism_solver>> step;
  index_t bad_u = 0, bad_v = 0, bad_reaction = 0, bad_state = 0, bad_load = 0;
};

TEST_CASE("the prism pulled on several ranks keeps one process's bits", "[mpi][step]") {
  const auto [rank, size] = rank_and_size();
  const prism_scene scene;
  pulled_prism reference(scene);
  const bc::node_group top = reference.gridpoints_on_plane(2, scene.length, 1e-9 * scene.length);

  // Two block -> rank maps, rank 0's, broadcast: slabs by bisection (1 thread a rank), and (where
  // built in) METIS's ragged cut through the Voronoi blocks (2 threads a rank). Both splits step
  // side by side, their halos apart by tag.
  distributed::block_graph_input in = distributed::blocks_of_mesh(scene.mesh);
  distributed::add_subcontacts(in, reference.contacts());
  const distributed::block_graph graph(in);
  const auto pairs = distributed::contact_pairs_of(reference.contacts());
  std::vector<split_run> splits;
  for (const char* name : {"RCB", "METIS"}) {
#ifndef TESSERA_HAVE_METIS
    if (name[0] != 'R') continue;
#endif
    const std::vector<int> map = broadcast_map(graph, name[0] != 'R');
    // The METIS split steps on 2 threads a rank: its bits must not depend on that either.
    split_run run{name, name[0] == 'R' ? 1 : 2, std::make_unique<pulled_prism>(scene), nullptr, nullptr};
    run.own = std::make_unique<distributed::rank_ownership>(map, size, scene.mesh, pairs);
    run.step = std::make_unique<distributed::stepper<prism_solver>>(*run.solver, scene.mesh, *run.own, MPI_COMM_WORLD,
                                                                    44 + static_cast<int>(splits.size()));
    splits.push_back(std::move(run));
  }

  constexpr int steps = 600, every = 50;
  index_t compared = 0;
  for (int k = 1; k <= steps; ++k) {
    step_side_by_side(reference, splits);
    if (k % every != 0 && k != 1) continue;
    ++compared;
    const vec3 load_ref = recorders::reaction_sum(reference.gridpoints(), top);
    for (auto& r : splits) {
      const std::vector<index_t>& mine = r.step->own_gridpoints();
      const node_set& gp = r.solver->gridpoints();
      r.bad_u += differing_rows(gp.displacement, reference.gridpoints().displacement, mine);
      r.bad_v += differing_rows(gp.velocity, reference.gridpoints().velocity, mine);
      r.bad_reaction += differing_rows(gp.reaction, reference.gridpoints().reaction, mine);
      r.bad_state += differing_states(r.solver->contacts(), reference.contacts(), r.own->evaluated_contacts(rank));
      const vec3 load = distributed::gathered_reaction_sum(gp, top, *r.own, MPI_COMM_WORLD);
      r.bad_load += same_bits(load.x(), load_ref.x()) && same_bits(load.y(), load_ref.y()) && same_bits(load.z(), load_ref.z()) ? 0 : 1;
      if (rank == 0 && k % 200 == 0)
        std::printf("step %d, %s: platen load %.6f kN (one process %.6f kN)\n", k, r.name, load.z() * 1e-3,
                    load_ref.z() * 1e-3);
    }
  }
  const energy_balance e_ref = reference.energies();
  for (auto& r : splits) {
    INFO(r.name << " split on " << size << " ranks, rank " << rank);
    const prism_solver& s = *r.solver;
    CHECK(s.step_count() == reference.step_count());
    CHECK(same_bits(s.time(), reference.time()));
    CHECK(r.bad_u == 0);
    CHECK(r.bad_v == 0);
    CHECK(r.bad_reaction == 0);
    CHECK(r.bad_state == 0);
    CHECK(r.bad_load == 0);
    // The ghosts, once the last exchange is complete, hold their owners' bits too.
    r.step->finish_exchange();
    const auto ghosts = r.own->ghost_gridpoints(rank);
    const std::vector<index_t> ghost_list(ghosts.begin(), ghosts.end());
    CHECK(differing_rows(s.gridpoints().displacement, reference.gridpoints().displacement, ghost_list) == 0);
    CHECK(differing_rows(s.gridpoints().velocity, reference.gridpoints().velocity, ghost_list) == 0);
    // Every gridpoint is compared on exactly one rank, every sub-contact on one or two.
    CHECK(summed_over_ranks(static_cast<index_t>(r.step->own_gridpoints().size())) == scene.mesh.gridpoint_count());
    CHECK(summed_over_ranks(static_cast<index_t>(r.own->evaluated_contacts(rank).size())) >=
          reference.contacts().subcontact_count());
    // The energy balance, summed over the ranks: one process's to round-off (stepper::summed_energies).
    const energy_balance e = r.step->summed_energies(MPI_COMM_WORLD);
    const real worst = worst_energy_difference(e, e_ref);
    CHECK(worst <= 1e-12);
    CHECK(e_ref.contact_dissipated > 0);  // the comparison includes softening's dissipation
    CHECK(std::abs(e.error_rel() - e_ref.error_rel()) <= 1e-9);
    if (rank == 0)
      std::printf("%s on %d ranks x %d threads, %d steps compared %lld times: rank 0 owns %zu gridpoints, evaluates %zu "
                  "sub-contacts, has %zu ghost gridpoints, sends %zu bytes a step; energy terms within %.3g of one "
                  "process's (relative), balance error %.3g (one process %.3g)\n",
                  r.name, size, r.threads, steps, static_cast<long long>(compared), r.step->own_gridpoints().size(),
                  r.own->evaluated_contacts(rank).size(), ghosts.size(), r.step->halo().bytes_sent(), worst,
                  e.error_rel(), e_ref.error_rel());
  }

  // The run reaches the law's softening: some sub-contacts carry tensile damage.
  const index_t softened = softened_subcontacts(reference.contacts());
  if (rank == 0)
    std::printf("%lld of %lld sub-contacts softened\n", static_cast<long long>(softened),
                static_cast<long long>(reference.contacts().subcontact_count()));
  CHECK(softened > 0);

  // The comparison sees the order of a gather: the contact forces on a gridpoint summed in
  // decreasing sub-contact order, and the platen's reactions summed backwards, take other bits
  // for some gridpoint and for the load, so a gather out of order would have failed above.
  const auto& c = reference.contacts();
  std::vector<std::vector<std::pair<index_t, real>>> terms(static_cast<std::size_t>(scene.mesh.gridpoint_count()));
  for (index_t i = 0; i < c.subcontact_count(); ++i) {
    terms[static_cast<std::size_t>(c.node_a(i))].push_back({i, -1});  // node A receives -force(i)
    terms[static_cast<std::size_t>(c.node_b(i))].push_back({i, +1});
  }
  index_t order_sensitive = 0;
  for (const auto& t : terms) {
    real forward = 0, backward = 0;
    for (auto it = t.begin(); it != t.end(); ++it) forward += it->second * c.force(it->first).z();
    for (auto it = t.rbegin(); it != t.rend(); ++it) backward += it->second * c.force(it->first).z();
    order_sensitive += same_bits(forward, backward) ? 0 : 1;
  }
  real load_backward = 0;
  for (auto it = top.nodes.rbegin(); it != top.nodes.rend(); ++it) load_backward += reference.gridpoints().reaction(*it, 2);
  if (rank == 0)
    std::printf("gather order: %lld gridpoints whose contact force z takes other bits summed backwards; platen load "
                "backwards %s\n",
                static_cast<long long>(order_sensitive),
                same_bits(load_backward, recorders::reaction_sum(reference.gridpoints(), top).z()) ? "the same" : "other bits");
  CHECK(order_sensitive > 0);
  CHECK_FALSE(same_bits(load_backward, recorders::reaction_sum(reference.gridpoints(), top).z()));
}

TEST_CASE("the reinforced tie on several ranks keeps one process's bits", "[mpi][step][bars]") {
  const auto [rank, size] = rank_and_size();
  const prism_scene scene;
  pulled_tie reference(scene), split(scene);

  // METIS's map where built in, over the graph with the bar elements' edges.
  distributed::block_graph_input in = distributed::blocks_of_mesh(scene.mesh);
  distributed::add_subcontacts(in, split.contacts());
  distributed::add_bar_elements(in, scene.mesh, split.reinforcement());
  const distributed::block_graph graph(in);
  const std::vector<int> map = broadcast_map(graph, true);
  const distributed::rank_ownership own(map, size, scene.mesh, distributed::contact_pairs_of(split.contacts()),
                                        distributed::bar_node_host_blocks(scene.mesh, split.reinforcement()),
                                        distributed::bar_element_pairs(split.reinforcement()));
  distributed::stepper<tie_solver> step(split, scene.mesh, own, MPI_COMM_WORLD);
  std::vector<index_t> own_bar_nodes;
  for (index_t n = 0; n < own.bar_node_count(); ++n)
    if (own.bar_node_rank(n) == rank) own_bar_nodes.push_back(n);

  constexpr int steps = 2000, every = 100;
  index_t bad_gridpoints = 0, bad_bar_nodes = 0, bad_state = 0;
  for (int k = 1; k <= steps; ++k) {
    reference.step();
    step.step();
    if (k % every != 0) continue;
    const node_set &gp = split.gridpoints(), &gp_ref = reference.gridpoints();
    const node_set &bars = split.bar_nodes(), &bars_ref = reference.bar_nodes();
    for (soa3 node_set::*m : {&node_set::displacement, &node_set::velocity, &node_set::reaction}) {
      bad_gridpoints += differing_rows(gp.*m, gp_ref.*m, step.own_gridpoints());
      bad_bar_nodes += differing_rows(bars.*m, bars_ref.*m, own_bar_nodes);
    }
    bad_state += differing_states(split.contacts(), reference.contacts(), own.evaluated_contacts(rank));
  }
  INFO("rank " << rank << " of " << size);
  CHECK(bad_gridpoints == 0);
  CHECK(bad_bar_nodes == 0);
  CHECK(bad_state == 0);
  step.finish_exchange();
  const auto ghost_bars = own.ghost_bar_nodes(rank);
  const std::vector<index_t> ghost_bar_list(ghost_bars.begin(), ghost_bars.end());
  CHECK(!ghost_bar_list.empty());  // the bar crosses this rank's cut: bar nodes travel in the halo
  CHECK(differing_rows(split.bar_nodes().displacement, reference.bar_nodes().displacement, ghost_bar_list) == 0);
  CHECK(summed_over_ranks(static_cast<index_t>(own_bar_nodes.size())) == reference.bar_nodes().size());
  // The balance summed over the ranks has the bars' energies (each element on the rank of its
  // first node, each bond spring on its node's): one process's to round-off.
  const energy_balance e = step.summed_energies(MPI_COMM_WORLD), e_ref = reference.energies();
  CHECK(e_ref.reinforcement_stored > 0);
  CHECK(std::abs(e.reinforcement_stored - e_ref.reinforcement_stored) <= 1e-12 * e_ref.reinforcement_stored);
  CHECK(std::abs(e.reinforcement_dissipated - e_ref.reinforcement_dissipated) <= 1e-12 * e_ref.accounted());
  CHECK(std::abs(e.kinetic - e_ref.kinetic) <= 1e-12 * e_ref.accounted());
  CHECK(std::abs(e.error_rel() - e_ref.error_rel()) <= 1e-9);
  const index_t softened = softened_subcontacts(reference.contacts());
  CHECK(softened > 0);
  const real bar_force = -reference.bar_nodes().reaction(reference.reinforcement().bar_nodes(0).first, 2);
  if (rank == 0)
    std::printf("tie on %d ranks, %d steps: rank 0 owns %zu of %lld bar nodes, has %zu ghost bar nodes, sends %zu "
                "bytes a step; bar force at the fixed end %.3f kN, %lld sub-contacts softened\n",
                size, steps, own_bar_nodes.size(), static_cast<long long>(reference.bar_nodes().size()),
                ghost_bar_list.size(), step.halo().bytes_sent(), bar_force * 1e-3, static_cast<long long>(softened));
}

TEST_CASE("a split run saved per rank restarts to the same bits", "[mpi][step][checkpoint]") {
  const auto [rank, size] = rank_and_size();
  const prism_scene scene;
  pulled_prism run(scene);
  pulled_prism restarted(scene);
  distributed::block_graph_input in = distributed::blocks_of_mesh(scene.mesh);
  distributed::add_subcontacts(in, run.contacts());
  const distributed::rank_ownership own(broadcast_map(distributed::block_graph(in), true), size, scene.mesh,
                                        distributed::contact_pairs_of(run.contacts()));
  distributed::stepper<prism_solver> step(run, scene.mesh, own, MPI_COMM_WORLD);
  // One file per rank, each its rank's whole solver (stale rows of other ranks' blocks included:
  // they restart as they were), in a folder named after rank 0's process.
  long long id = static_cast<long long>(::getpid());
  MPI_Bcast(&id, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("tessera_split_" + std::to_string(id));
  std::filesystem::create_directories(folder);
  const std::filesystem::path file = folder / ("rank_" + std::to_string(rank) + ".ckpt");
  constexpr int before = 300, after = 300;  // the second half crosses the peak (the first test)
  for (int k = 0; k < before; ++k) step.step();
  step.finish_exchange();  // the ghosts' rows current, so the file holds what the next step reads
  io::save_checkpoint(run, file, "distributed step test");
  for (int k = 0; k < after; ++k) step.step();
  io::load_checkpoint(restarted, file);
  distributed::stepper<prism_solver> step_again(restarted, scene.mesh, own, MPI_COMM_WORLD, 46);
  for (int k = 0; k < after; ++k) step_again.step();
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) std::filesystem::remove_all(folder);
  INFO("rank " << rank << " of " << size);
  CHECK(restarted.step_count() == run.step_count());
  index_t bad = 0;
  for (soa3 node_set::*m : {&node_set::displacement, &node_set::velocity, &node_set::reaction})
    bad += differing_rows(restarted.gridpoints().*m, run.gridpoints().*m, step.own_gridpoints());
  CHECK(bad == 0);
  CHECK(differing_states(restarted.contacts(), run.contacts(), own.evaluated_contacts(rank)) == 0);

  // The non-finite check across ranks: a velocity made NaN on the last rank's first gridpoint
  // makes every rank throw, naming that gridpoint; a finite model passes on every rank.
  CHECK_NOTHROW(step_again.check_finite(MPI_COMM_WORLD));
  const auto last_blocks = own.owned_blocks(size - 1);
  const index_t victim = scene.mesh.block_gridpoint_offsets[static_cast<std::size_t>(last_blocks.front())];
  if (rank == size - 1) restarted.gridpoints().velocity(victim, 1) = std::numeric_limits<real>::quiet_NaN();
  CHECK_THROWS_WITH(step_again.check_finite(MPI_COMM_WORLD),
                    Catch::Matchers::Contains("gridpoint " + std::to_string(victim) + " "));
}

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  set_threads(1);  // ranks share the machine's cores: one thread but where a split asks for two
  const int failed = Catch::Session().run(argc, argv);
  int any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return any == 0 ? 0 : 1;
}
