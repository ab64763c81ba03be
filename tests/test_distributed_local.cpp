// Local storage per rank (include/tessera/distributed/local_model.hpp) against one process, under
// mpiexec (CTests distributed_mpi_step_2 and _3): the 100-block prism of test_distributed_step,
// pulled past the first softening, is split by bisection (one thread a rank) and, where built in,
// by METIS (two threads a rank); each rank builds its solver on its local model only (own blocks
// and one layer of ghost blocks, locally numbered) and steps it with distributed::stepper. Every
// few steps each rank compares, bit for bit and through the local -> global maps, the u, v and
// reactions of its own gridpoints, the law state of every sub-contact it evaluates and the platen
// load summed over the ranks (local_model::reaction_sum), with a whole model stepped by
// solver::step on the same rank. It also checks that the local model is smaller than the whole
// (the point of it), that the zones written as a parallel VTK dataset (distributed::write_zones_pvtu)
// hold every gridpoint once with one process's displacement, and that ranks whose automatic time
// steps differ are refused. A second case
// runs test_distributed_step's reinforced tie the same way: every rank keeps every bar node and
// hosts the bonds of its own ones only.
#include <catch2/catch.hpp>

#include <mpi.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <memory>
#include <utility>
#include <vector>

#include "tessera/distributed/block_graph.hpp"
#include "tessera/distributed/local_model.hpp"
#include "tessera/distributed/local_vtk.hpp"
#include "tessera/distributed/ownership.hpp"
#include "tessera/distributed/stepper.hpp"
#include "tessera/io/checkpoint.hpp"
#include "tessera/reinforcement/embedded_truss.hpp"
#include "tessera/solver/recorders.hpp"

#include "support/split_prism.hpp"

using namespace tessera;
using namespace split_test;

namespace {
/// One split stepping local models: the local model, its solver, ownership and stepper, and the
/// local -> global sub-contact map.
struct local_split {
  const char* name;
  int threads;
  std::unique_ptr<distributed::local_model> model;
  std::unique_ptr<prism_solver> solver;
  std::unique_ptr<distributed::rank_ownership> own;
  std::unique_ptr<distributed::stepper<prism_solver>> step;
  std::vector<index_t> global_contact;
  index_t bad_u = 0, bad_v = 0, bad_reaction = 0, bad_state = 0, bad_load = 0, bad_sample = 0;
};

/// Rows `which` (local ids) of `rows` whose bits differ from `ref`'s rows at their global ids.
index_t differing_local_rows(const soa3& rows, const soa3& ref, const distributed::local_model& lm,
                             const std::vector<index_t>& which) {
  index_t n = 0;
  for (const index_t g : which) {
    const index_t G = lm.global_gridpoint(g);
    bool same = true;
    for (int c = 0; c < 3; ++c) same = same && same_bits(rows(g, c), ref(G, c));
    n += same ? 0 : 1;
  }
  return n;
}
/// The numbers of the ascii DataArray `name` of a VTK XML file's text.
std::vector<double> ascii_array(const std::string& text, const std::string& name) {
  const std::size_t at = text.find("Name=\"" + name + "\"");
  REQUIRE(at != std::string::npos);
  const std::size_t begin = text.find('>', at) + 1, end = text.find("</DataArray>", begin);
  std::istringstream in(text.substr(begin, end - begin));
  std::vector<double> values;
  for (double v = 0; in >> v;) values.push_back(v);
  return values;
}
}  // namespace

TEST_CASE("a split run on local models keeps one process's bits", "[mpi][step][local]") {
  const auto [rank, size] = rank_and_size();
  const prism_scene scene;
  pulled_prism reference(scene);
  const bc::node_group top_ref = reference.gridpoints_on_plane(2, scene.length, 1e-9 * scene.length);
  // The whole model's sub-contacts by their global gridpoints, to map the local ones.
  std::map<std::pair<index_t, index_t>, index_t> contact_of;
  for (index_t i = 0; i < reference.contacts().subcontact_count(); ++i)
    contact_of[{reference.contacts().node_a(i), reference.contacts().node_b(i)}] = i;

  distributed::block_graph_input in = distributed::blocks_of_mesh(scene.mesh);
  distributed::add_subcontacts(in, reference.contacts());
  const distributed::block_graph graph(in);
  std::vector<local_split> splits;
  for (const char* name : {"RCB", "METIS"}) {
#ifndef TESSERA_HAVE_METIS
    if (name[0] != 'R') continue;
#endif
    const std::vector<int> map = broadcast_map(graph, name[0] != 'R');
    local_split run{name, name[0] == 'R' ? 1 : 2, nullptr, nullptr, nullptr, nullptr, {}};
    run.model = std::make_unique<distributed::local_model>(scene.tess, scene.mesh, map, size, rank);
    const distributed::local_model& lm = *run.model;
    run.solver = std::make_unique<prism_solver>(lm.tess, lm.mesh, scene.block, scene.contact,
                                                prism_solver::reinforcement_type::params{}, pull_options());
    // The supports of support_and_pull, each rank's part (a rank may hold none of a plane).
    const real tol = 1e-9 * scene.length;
    prism_solver& s = *run.solver;
    const bc::node_group bottom = lm.gridpoints_on_plane(s.gridpoints(), 2, 0.0, tol, MPI_COMM_WORLD);
    const bc::node_group top = lm.gridpoints_on_plane(s.gridpoints(), 2, scene.length, tol, MPI_COMM_WORLD);
    if (!bottom.empty()) s.fix(bottom);
    if (!top.empty()) {
      s.fix(top, bc::transverse_to(2));
      s.prescribe_velocity(top, vec3(0, 0, pull_rate), bc::components::z);
    }
    distributed::require_same_time_step(run.solver->dt(), MPI_COMM_WORLD);
    run.own = std::make_unique<distributed::rank_ownership>(lm.ownership(run.solver->contacts()));
    run.step = std::make_unique<distributed::stepper<prism_solver>>(*run.solver, lm.mesh, *run.own, MPI_COMM_WORLD,
                                                                    54 + static_cast<int>(splits.size()));
    const auto& c = run.solver->contacts();
    for (index_t i = 0; i < c.subcontact_count(); ++i) {
      const auto it = contact_of.find({lm.global_gridpoint(c.node_a(i)), lm.global_gridpoint(c.node_b(i))});
      REQUIRE(it != contact_of.end());
      run.global_contact.push_back(it->second);
    }
    // The local model is the rank's own blocks and a layer of ghosts, not the whole model; the
    // own blocks of all ranks are the model once over.
    INFO(name << " on " << size << " ranks, rank " << rank);
    CHECK(summed_over_ranks(lm.own_block_count()) == scene.mesh.block_count());
    CHECK(lm.mesh.block_count() < scene.mesh.block_count());
    CHECK(lm.mesh.gridpoint_count() < scene.mesh.gridpoint_count());
    CHECK(std::is_sorted(lm.global_gridpoints().begin(), lm.global_gridpoints().end()));
    CHECK(std::is_sorted(run.global_contact.begin(), run.global_contact.end()));
    // The masses of own gridpoints, scaled to the target step, are the whole model's bits.
    index_t bad_mass = 0;
    for (const index_t g : run.step->own_gridpoints())
      bad_mass += same_bits(run.solver->gridpoints().mass[g], reference.gridpoints().mass[lm.global_gridpoint(g)]) ? 0 : 1;
    CHECK(bad_mass == 0);
    CHECK(same_bits(run.solver->dt(), reference.dt()));
    splits.push_back(std::move(run));
  }

  constexpr int steps = 600, every = 50;
  for (int k = 1; k <= steps; ++k) {
    step_side_by_side(reference, splits);
    if (k % every != 0 && k != 1) continue;
    const vec3 load_ref = recorders::reaction_sum(reference.gridpoints(), top_ref);
    for (auto& r : splits) {
      const distributed::local_model& lm = *r.model;
      const std::vector<index_t>& mine = r.step->own_gridpoints();
      const node_set& gp = r.solver->gridpoints();
      r.bad_u += differing_local_rows(gp.displacement, reference.gridpoints().displacement, lm, mine);
      r.bad_v += differing_local_rows(gp.velocity, reference.gridpoints().velocity, lm, mine);
      r.bad_reaction += differing_local_rows(gp.reaction, reference.gridpoints().reaction, lm, mine);
      for (const index_t i : r.own->evaluated_contacts(rank)) {
        const auto& a = r.solver->contacts().state(i);
        const auto& b = reference.contacts().state(r.global_contact[static_cast<std::size_t>(i)]);
        const bool same = same_bits(a.sigma_n, b.sigma_n) && same_bits(a.tau.x(), b.tau.x()) &&
                          same_bits(a.tau.y(), b.tau.y()) && same_bits(a.tau.z(), b.tau.z()) &&
                          same_bits(a.u_n, b.u_n) && same_bits(a.u_soft, b.u_soft) &&
                          same_bits(a.dissipated_tension, b.dissipated_tension);
        r.bad_state += same ? 0 : 1;
      }
      const bc::node_group top = lm.gridpoints_on_plane(gp, 2, scene.length, 1e-9 * scene.length, MPI_COMM_WORLD);
      const vec3 load = lm.reaction_sum(gp, top, MPI_COMM_WORLD);
      r.bad_load += same_bits(load.x(), load_ref.x()) && same_bits(load.y(), load_ref.y()) && same_bits(load.z(), load_ref.z()) ? 0 : 1;
      // The other samples by reduction: the platen's mean displacement (bits) and the unbalanced
      // force (its largest and where, bits; its mean to round-off).
      const vec3 u_top = lm.mean_displacement(gp, top, MPI_COMM_WORLD);
      const vec3 u_top_ref = recorders::mean_displacement(reference.gridpoints(), top_ref);
      const out_of_balance ub = lm.unbalanced_force(*r.solver, MPI_COMM_WORLD), ub_ref = reference.unbalanced_force();
      r.bad_sample += same_bits(u_top.z(), u_top_ref.z()) && same_bits(u_top.x(), u_top_ref.x()) &&
                              same_bits(ub.max_force, ub_ref.max_force) && ub.max_node == ub_ref.max_node &&
                              ub.nodes == ub_ref.nodes && std::abs(ub.mean_force - ub_ref.mean_force) <= 1e-12 * ub_ref.mean_force
                          ? 0
                          : 1;
      if (rank == 0 && k % 200 == 0)
        std::printf("step %d, local %s: platen load %.6f kN (one process %.6f kN)\n", k, r.name, load.z() * 1e-3,
                    load_ref.z() * 1e-3);
    }
  }
  const energy_balance e_ref = reference.energies();
  long long id = static_cast<long long>(::getpid());
  MPI_Bcast(&id, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("tessera_pvtu_" + std::to_string(id));
  if (rank == 0) std::filesystem::create_directories(folder);
  MPI_Barrier(MPI_COMM_WORLD);
  const index_t softened = softened_subcontacts(reference.contacts());
  CHECK(softened > 0);  // the comparison covers the law's softening branch
  for (auto& r : splits) {
    INFO(r.name << " on local models, " << size << " ranks, rank " << rank);
    CHECK(r.solver->step_count() == reference.step_count());
    // Every comparison, through the local -> global maps: u, v, reactions, contact states, load.
    const std::array<index_t, 6> bad{r.bad_u, r.bad_v, r.bad_reaction, r.bad_state, r.bad_load, r.bad_sample};
    CHECK(bad == std::array<index_t, 6>{});
    // The ghosts hold their owners' bits once the last exchange is complete.
    r.step->finish_exchange();
    const auto ghosts = r.own->ghost_gridpoints(rank);
    const std::vector<index_t> ghost_list(ghosts.begin(), ghosts.end());
    CHECK_FALSE(ghost_list.empty());
    CHECK(differing_local_rows(r.solver->gridpoints().velocity, reference.gridpoints().velocity, *r.model, ghost_list) +
              differing_local_rows(r.solver->gridpoints().displacement, reference.gridpoints().displacement, *r.model,
                                   ghost_list) ==
          0);
    CHECK(summed_over_ranks(static_cast<index_t>(r.step->own_gridpoints().size())) == scene.mesh.gridpoint_count());
    // The balance summed over the ranks: one process's to round-off, as with the whole model a rank.
    const energy_balance e = r.step->summed_energies(MPI_COMM_WORLD);
    const real worst = worst_energy_difference(e, e_ref);
    CHECK(worst <= 1e-12);
    // The zones as a parallel VTK dataset, each rank its own blocks' piece (ascii, exact round
    // trip): every gridpoint of the whole model in exactly one piece, with one process's
    // displacement bits, and every zone once.
    const std::filesystem::path pvtu = folder / (std::string(r.name) + "_zones.pvtu");
    distributed::write_zones_pvtu(pvtu, *r.model, *r.solver, MPI_COMM_WORLD, io::vtk::format::ascii);
    if (rank == 0) {
      std::ifstream index(pvtu);
      const std::string listing((std::istreambuf_iterator<char>(index)), std::istreambuf_iterator<char>());
      std::vector<int> seen(static_cast<std::size_t>(scene.mesh.gridpoint_count()), 0);
      index_t bad_displacement = 0, cells = 0;
      for (int q = 0; q < size; ++q) {
        CHECK(listing.find(distributed::pvtu_piece(pvtu, q).filename().string()) != std::string::npos);
        std::ifstream piece(distributed::pvtu_piece(pvtu, q));
        const std::string text((std::istreambuf_iterator<char>(piece)), std::istreambuf_iterator<char>());
        const std::vector<double> ids = ascii_array(text, "gridpoint"), u = ascii_array(text, "displacement");
        REQUIRE(u.size() == 3 * ids.size());
        for (std::size_t k = 0; k < ids.size(); ++k) {
          const auto g = static_cast<index_t>(ids[k]);
          ++seen[static_cast<std::size_t>(g)];
          for (int c = 0; c < 3; ++c)
            bad_displacement += same_bits(u[3 * k + static_cast<std::size_t>(c)], reference.gridpoints().displacement(g, c)) ? 0 : 1;
        }
        cells += static_cast<index_t>(ascii_array(text, "block").size());
      }
      CHECK(std::count(seen.begin(), seen.end(), 1) == scene.mesh.gridpoint_count());
      CHECK(bad_displacement == 0);
      CHECK(cells == scene.mesh.zone_count());
    }
    if (rank == 0)
      std::printf("local %s on %d ranks x %d threads: rank 0 holds %lld of %lld blocks (%lld own), %lld of %lld "
                  "gridpoints, %lld of %lld zones; energy terms within %.3g of one process's\n",
                  r.name, size, r.threads, static_cast<long long>(r.model->mesh.block_count()),
                  static_cast<long long>(scene.mesh.block_count()), static_cast<long long>(r.model->own_block_count()),
                  static_cast<long long>(r.model->mesh.gridpoint_count()),
                  static_cast<long long>(scene.mesh.gridpoint_count()),
                  static_cast<long long>(r.model->mesh.zone_count()), static_cast<long long>(scene.mesh.zone_count()),
                  worst);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) std::filesystem::remove_all(folder);
}

TEST_CASE("the reinforced tie on local models keeps one process's bits", "[mpi][step][local][bars]") {
  // test_distributed_step's tie: the bar of examples/rc_tie on the axis, pulled by its end, split
  // by METIS over the graph with the bar's edges; here each rank holds its local model only, every
  // bar node, and hosts the bonds of its own bar nodes alone.
  const auto [rank, size] = rank_and_size();
  const prism_scene scene;
  pulled_tie reference(scene);
  const auto bar = tie_bar_of(scene);
  distributed::block_graph_input in = distributed::blocks_of_mesh(scene.mesh);
  distributed::add_subcontacts(in, reference.contacts());
  distributed::add_bar_elements(in, scene.mesh, reference.reinforcement());
  const std::vector<int> map = broadcast_map(distributed::block_graph(in), true);

  const distributed::local_model lm(scene.tess, scene.mesh, map, size, rank, bar.bars);
  tie_solver s(lm.tess, lm.mesh, scene.block, scene.contact, lm.bar_params(bar), tie_options());
  const real tol = 1e-9 * scene.length;
  for (const real z : {0.0, scene.length})
    if (const bc::node_group end = lm.gridpoints_on_plane(s.gridpoints(), 2, z, tol, MPI_COMM_WORLD); !end.empty())
      s.fix(end, bc::transverse_to(2));
  const auto [first, last] = s.reinforcement().bar_nodes(0);
  bc::fix(s.bar_nodes(), bc::node_group{{first}, "fixed bar end"});
  bc::prescribe_velocity(s.bar_nodes(), bc::node_group{{last - 1}, "pulled bar end"}, vec3(0, 0, tie_pull_rate));
  distributed::require_same_time_step(s.dt(), MPI_COMM_WORLD);
  const distributed::rank_ownership own = lm.ownership(s.contacts(), s.reinforcement());
  distributed::stepper<tie_solver> step(s, lm.mesh, own, MPI_COMM_WORLD);
  // The bar nodes' ranks are the whole model's rule, and each is hosted only on its own rank.
  const distributed::rank_ownership whole_own(map, size, scene.mesh, distributed::contact_pairs_of(reference.contacts()),
                                              distributed::bar_node_host_blocks(scene.mesh, reference.reinforcement()),
                                              distributed::bar_element_pairs(reference.reinforcement()));
  std::vector<index_t> own_bar_nodes;
  index_t bad_rank = 0, bad_host = 0;
  for (index_t n = 0; n < own.bar_node_count(); ++n) {
    bad_rank += own.bar_node_rank(n) == whole_own.bar_node_rank(n) ? 0 : 1;
    const bool mine = own.bar_node_rank(n) == rank;
    if (mine) own_bar_nodes.push_back(n);
    const index_t z = s.reinforcement().host(n).zone;
    if (mine) {
      const auto& h = s.reinforcement().host(n);
      const auto& hr = reference.reinforcement().host(n);
      bool same = z != invalid_index && lm.global_zone(z) == hr.zone;
      for (int i = 0; i < 4 && same; ++i)
        same = lm.global_gridpoint(h.gridpoints[static_cast<std::size_t>(i)]) == hr.gridpoints[static_cast<std::size_t>(i)] &&
               same_bits(h.weights[static_cast<std::size_t>(i)], hr.weights[static_cast<std::size_t>(i)]);
      bad_host += same ? 0 : 1;
    } else {
      bad_host += z == invalid_index ? 0 : 1;
    }
  }
  CHECK(bad_rank == 0);
  CHECK(bad_host == 0);
  CHECK(lm.mesh.block_count() < scene.mesh.block_count());

  constexpr int steps = 2000, every = 100;
  index_t bad_gridpoints = 0, bad_bar_nodes = 0, bad_mass = 0;
  for (const index_t g : step.own_gridpoints())
    bad_mass += same_bits(s.gridpoints().mass[g], reference.gridpoints().mass[lm.global_gridpoint(g)]) ? 0 : 1;
  for (const index_t n : own_bar_nodes) bad_mass += same_bits(s.bar_nodes().mass[n], reference.bar_nodes().mass[n]) ? 0 : 1;
  CHECK(bad_mass == 0);
  for (int k = 1; k <= steps; ++k) {
    reference.step();
    step.step();
    if (k % every != 0) continue;
    for (soa3 node_set::*m : {&node_set::displacement, &node_set::velocity, &node_set::reaction}) {
      bad_gridpoints += differing_local_rows(s.gridpoints().*m, reference.gridpoints().*m, lm, step.own_gridpoints());
      bad_bar_nodes += differing_rows(s.bar_nodes().*m, reference.bar_nodes().*m, own_bar_nodes);
    }
  }
  INFO("rank " << rank << " of " << size);
  CHECK(bad_gridpoints == 0);
  CHECK(bad_bar_nodes == 0);
  // The unbalanced force over gridpoints and bar nodes, reduced over the ranks (bar nodes after
  // every gridpoint, as one process labels them).
  const out_of_balance ub = lm.unbalanced_force(s, MPI_COMM_WORLD), ub_ref = reference.unbalanced_force();
  CHECK(same_bits(ub.max_force, ub_ref.max_force));
  CHECK(ub.max_node == ub_ref.max_node);
  CHECK(ub.nodes == ub_ref.nodes);
  CHECK(ub.mean_force == Approx(ub_ref.mean_force).epsilon(1e-12));
  step.finish_exchange();
  const auto ghost_bars = own.ghost_bar_nodes(rank);
  const std::vector<index_t> ghost_bar_list(ghost_bars.begin(), ghost_bars.end());
  CHECK(!ghost_bar_list.empty());  // the bar crosses this rank's cut
  CHECK(differing_rows(s.bar_nodes().displacement, reference.bar_nodes().displacement, ghost_bar_list) == 0);
  CHECK(summed_over_ranks(static_cast<index_t>(own_bar_nodes.size())) == reference.bar_nodes().size());
  const energy_balance e = step.summed_energies(MPI_COMM_WORLD), e_ref = reference.energies();
  CHECK(e_ref.reinforcement_stored > 0);
  CHECK(std::abs(e.reinforcement_stored - e_ref.reinforcement_stored) <= 1e-12 * e_ref.reinforcement_stored);
  CHECK(std::abs(e.error_rel() - e_ref.error_rel()) <= 1e-9);
  const index_t softened = softened_subcontacts(reference.contacts());
  CHECK(softened > 0);
  if (rank == 0)
    std::printf("tie on local models, %d ranks, %d steps: rank 0 holds %lld of %lld blocks, owns %zu of %lld bar nodes "
                "(%zu ghost bar nodes); %lld sub-contacts softened\n",
                size, steps, static_cast<long long>(lm.mesh.block_count()), static_cast<long long>(scene.mesh.block_count()),
                own_bar_nodes.size(), static_cast<long long>(reference.bar_nodes().size()), ghost_bar_list.size(),
                static_cast<long long>(softened));
  // A truss with other bars than the model's is refused.
  auto other = bar;
  other.bars[0].elements += 1;
  CHECK_THROWS_WITH(lm.bar_params(other), Catch::Contains("not the"));
  CHECK_THROWS_WITH(lm.ownership(s.contacts()), Catch::Contains("bar nodes; pass the solver's reinforcement"));
}

TEST_CASE("a run on local models saved per rank restarts to the same bits", "[mpi][step][local][checkpoint]") {
  // Each rank saves its local solver halfway (io::save_checkpoint: the file is the local model's,
  // checked against its gridpoints on loading) and a second local solver, built the same way,
  // loads it and steps on beside the first: the same bits. Then a NaN on the last rank makes
  // every rank throw, naming the gridpoint by its whole-model id.
  const auto [rank, size] = rank_and_size();
  const prism_scene scene;
  distributed::block_graph_input in = distributed::blocks_of_mesh(scene.mesh);
  distributed::add_face_subcontacts(in, scene.tess, scene.mesh);
  const std::vector<int> map = broadcast_map(distributed::block_graph(in), true);
  const distributed::local_model lm(scene.tess, scene.mesh, map, size, rank);
  const auto build = [&] {
    auto s = std::make_unique<prism_solver>(lm.tess, lm.mesh, scene.block, scene.contact,
                                            prism_solver::reinforcement_type::params{}, pull_options());
    const real tol = 1e-9 * scene.length;
    const bc::node_group bottom = lm.gridpoints_on_plane(s->gridpoints(), 2, 0.0, tol, MPI_COMM_WORLD);
    const bc::node_group top = lm.gridpoints_on_plane(s->gridpoints(), 2, scene.length, tol, MPI_COMM_WORLD);
    if (!bottom.empty()) s->fix(bottom);
    if (!top.empty()) {
      s->fix(top, bc::transverse_to(2));
      s->prescribe_velocity(top, vec3(0, 0, pull_rate), bc::components::z);
    }
    return s;
  };
  const auto run = build(), restarted = build();
  const distributed::rank_ownership own = lm.ownership(run->contacts());
  distributed::stepper<prism_solver> step(*run, lm.mesh, own, MPI_COMM_WORLD, 64);
  long long id = static_cast<long long>(::getpid());
  MPI_Bcast(&id, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("tessera_local_" + std::to_string(id));
  std::filesystem::create_directories(folder);
  const std::filesystem::path file = folder / ("rank_" + std::to_string(rank) + ".ckpt");
  constexpr int before = 300, after = 300;
  for (int k = 0; k < before; ++k) step.step();
  step.finish_exchange();
  io::save_checkpoint(*run, file, "local model test");
  for (int k = 0; k < after; ++k) step.step();
  io::load_checkpoint(*restarted, file);
  distributed::stepper<prism_solver> step_again(*restarted, lm.mesh, own, MPI_COMM_WORLD, 65);
  for (int k = 0; k < after; ++k) step_again.step();
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) std::filesystem::remove_all(folder);
  INFO("rank " << rank << " of " << size);
  CHECK(restarted->step_count() == run->step_count());
  index_t bad = 0;
  for (soa3 node_set::*m : {&node_set::displacement, &node_set::velocity, &node_set::reaction})
    bad += differing_rows(restarted->gridpoints().*m, run->gridpoints().*m, step.own_gridpoints());
  CHECK(bad == 0);
  CHECK(differing_states(restarted->contacts(), run->contacts(), own.evaluated_contacts(rank)) == 0);
  // Output refusals: a name that is not .pvtu (every rank alike), and a missing folder, which
  // fails every rank's piece: every rank throws and no .pvtu appears.
  CHECK_THROWS_WITH(distributed::write_zones_pvtu(folder / "zones.vtu", lm, *run, MPI_COMM_WORLD),
                    Catch::Matchers::Contains("must end in .pvtu"));
  const std::filesystem::path nowhere = folder / "no_such_folder" / "zones.pvtu";
  CHECK_THROWS_WITH(distributed::write_zones_pvtu(nowhere, lm, *run, MPI_COMM_WORLD),
                    Catch::Matchers::Contains("a piece failed on rank(s) 0"));
  CHECK_FALSE(std::filesystem::exists(nowhere));
  // The non-finite check names the whole model's gridpoint, on every rank.
  CHECK_NOTHROW(lm.check_finite(*restarted, MPI_COMM_WORLD));
  long long victim = 0;
  if (rank == size - 1) {
    const index_t g = step_again.own_gridpoints().front();
    victim = lm.global_gridpoint(g);
    restarted->gridpoints().velocity(g, 1) = std::numeric_limits<real>::quiet_NaN();
  }
  MPI_Bcast(&victim, 1, MPI_LONG_LONG, size - 1, MPI_COMM_WORLD);
  CHECK_THROWS_WITH(lm.check_finite(*restarted, MPI_COMM_WORLD),
                    Catch::Matchers::Contains("gridpoint " + std::to_string(victim) + " (whole-model id"));
}

TEST_CASE("local models refuse what would break the bits", "[mpi][step][local]") {
  const auto [rank, size] = rank_and_size();
  const prism_scene scene;
  const std::vector<int> map = [&] {
    distributed::block_graph_input in = distributed::blocks_of_mesh(scene.mesh);
    return broadcast_map(distributed::block_graph(in), false);
  }();
  // A time step that differs between ranks (an automatic one is the smallest over the gridpoints a
  // rank holds) is refused on every rank; the same step passes.
  CHECK_THROWS_WITH(distributed::require_same_time_step(1e-6 * (1 + rank), MPI_COMM_WORLD),
                    Catch::Contains("options.dt") && Catch::Contains("1e-06 s to"));
  CHECK_NOTHROW(distributed::require_same_time_step(1e-6, MPI_COMM_WORLD));
  CHECK_THROWS_WITH(distributed::local_model(scene.tess, scene.mesh, map, size, size), Catch::Contains("outside 0 .. "));
  std::vector<int> bad = map;
  bad[7] = size;
  CHECK_THROWS_WITH(distributed::local_model(scene.tess, scene.mesh, bad, size, rank), Catch::Contains("block 7 has rank"));
  // A plane no rank holds is refused everywhere; one only some ranks hold is not.
  const distributed::local_model lm(scene.tess, scene.mesh, map, size, rank);
  node_set gp;
  gp.resize(lm.mesh.gridpoint_count());
  for (index_t g = 0; g < gp.size(); ++g) gp.reference.row(g) = lm.mesh.gridpoints[static_cast<std::size_t>(g)].transpose();
  CHECK_THROWS_WITH(lm.gridpoints_on_plane(gp, 2, 2 * scene.length, 1e-9, MPI_COMM_WORLD),
                    Catch::Contains("selects no gridpoint on any"));
  const bc::node_group bottom = lm.gridpoints_on_plane(gp, 2, 0.0, 1e-9, MPI_COMM_WORLD);
  CHECK(summed_over_ranks(bottom.size()) > 0);
}
