#pragma once
// The study's 100-block prism pulled along z (and the tie: the same prism with its bar), and the bit
// comparisons, shared by the distributed tests run under mpiexec (test_distributed_step.cpp,
// test_distributed_gather.cpp, test_distributed_local.cpp).
#include <mpi.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "tessera/distributed/block_graph.hpp"
#include "tessera/distributed/partition.hpp"
#include "tessera/geometry/voronoi.hpp"
#include "tessera/geometry/zoning.hpp"
#include "tessera/presets/pulatsu2020.hpp"
#include "tessera/reinforcement/embedded_truss.hpp"
#include "tessera/solver.hpp"

namespace split_test {
using namespace tessera;
using prism_law = prism_solver::law_type;

/// The direct tension prism of examples/common/scenes.hpp (make_prism, 100 blocks, seed 1):
/// 68 x 68 x 600 mm, blocks of 10 x concrete (E 28 GPa, nu 0.2, 2400 kg/m^3), Table 1's contacts
/// with cohesion 2 f_T and residual cohesion 0.01 c_0.
struct prism_scene {
  geometry::tessellation tess;
  geometry::block_mesh mesh;
  zones::linear_elastic_tet::params block{10 * 28e9, 0.2, 2400};
  law::study_tie_law::params contact = law::scaled_prism_params(100);
  real length = 0.6;
  prism_scene() {
    tess = geometry::random_voronoi(aabb{vec3::Zero(), vec3(0.068, 0.068, length)}, 100, 1);
    mesh = geometry::zone_blocks(tess);
    contact.shear.c_0 = 2 * contact.tension.f_T;
    contact.shear.c_res = 0.01 * contact.shear.c_0;
  }
};

/// The pull: top velocity (m/s) and top displacement per step (m), the latter setting the mass
/// scaling's target step dt = du / rate. Larger than the driver's quick 5 nm a step so that
/// contacts soften within a few hundred steps of a test.
constexpr real pull_rate = 0.005;
constexpr real pull_step_displacement = 50e-9;

inline solver_options pull_options() {
  solver_options o;
  o.mass_scaling_dt = pull_step_displacement / pull_rate;
  return o;
}

/// Bottom fixed, top fixed transversally and pulled along z (examples/direct_tension's supports).
inline void support_and_pull(prism_solver& s, real length) {
  const real tol = 1e-9 * length;
  s.fix(s.gridpoints_on_plane(2, 0.0, tol));
  const bc::node_group top = s.gridpoints_on_plane(2, length, tol);
  s.fix(top, bc::transverse_to(2));
  s.prescribe_velocity(top, vec3(0, 0, pull_rate), bc::components::z);
}

/// A prism solver of `scene` with the pull's options, supported and pulled (support_and_pull): the
/// solver every split test starts from, the reference as well as each rank's.
struct pulled_prism : prism_solver {
  explicit pulled_prism(const prism_scene& scene)
      : prism_solver(scene.tess, scene.mesh, scene.block, scene.contact, {}, pull_options()) {
    support_and_pull(*this, scene.length);
  }
};

/// The study's tie (examples/common/rc_tie_scene.hpp) on the test prism: one 8 mm bar on the axis
/// in 96 elements, bonded to the zones; rollers on the concrete end faces; the first bar node
/// fixed, the last pulled along z.
using tie_truss = reinforcement::embedded_truss<reinforcement::coulomb_bond>;
using tie_solver = solver<blocks::deformable<zones::linear_elastic_tet>, presets::bonded_faces<law::study_tie_law>, tie_truss>;
constexpr real tie_pull_rate = 0.05;  ///< m/s: with dt = 1 us, 50 nm a step (cracks within 2 000 steps)
constexpr real tie_dt = 1e-6;         ///< s, the tie driver's mass-scaling target

/// The tie's bar on the test prism's axis, and its options (masses scaled to tie_dt).
inline tie_truss::params tie_bar_of(const prism_scene& scene) {
  return reinforcement::pulatsu2020::tie_reinforcement(vec3(0.034, 0.034, 0), vec3(0.034, 0.034, scene.length));
}
inline solver_options tie_options() {
  solver_options o;
  o.mass_scaling_dt = tie_dt;
  return o;
}

/// One step of `reference` on one thread and of each split (members `threads` and `step`, a
/// stepper) on its own thread count, side by side; back to one thread after.
template <class Reference, class Splits>
void step_side_by_side(Reference& reference, Splits& splits) {
  set_threads(1);
  reference.step();
  for (auto& r : splits) {
    set_threads(r.threads);
    r.step->step();
  }
  set_threads(1);
}

/// The largest relative difference between the terms of two energy balances (a split's summed
/// over the ranks against one process's): initial, boundary and damping work, kinetic, block
/// elastic, contact stored and dissipated (all, and in tension).
[[nodiscard]] inline real worst_energy_difference(const energy_balance& e, const energy_balance& ref) {
  const auto relative = [](real a, real b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); };
  const std::array<std::pair<real, real>, 8> terms{{{e.initial, ref.initial},
                                                    {e.boundary_work, ref.boundary_work},
                                                    {e.damping_dissipated, ref.damping_dissipated},
                                                    {e.kinetic, ref.kinetic},
                                                    {e.block_elastic, ref.block_elastic},
                                                    {e.contact_stored, ref.contact_stored},
                                                    {e.contact_dissipated, ref.contact_dissipated},
                                                    {e.contact_dissipated_tension, ref.contact_dissipated_tension}}};
  real worst = 0;
  for (const auto& [split_value, one_process] : terms) worst = std::max(worst, relative(split_value, one_process));
  return worst;
}

/// Sub-contacts of `c` with tensile damage: a run that compares bits must reach the softening.
template <class Contacts>
[[nodiscard]] index_t softened_subcontacts(const Contacts& c) {
  index_t n = 0;
  for (index_t i = 0; i < c.subcontact_count(); ++i) n += prism_law::tensile_damage(c.subcontact_params(i), c.state(i)) > 0;
  return n;
}

inline void hold_and_pull_bar(tie_solver& s, real length) {
  const real tol = 1e-9 * length;
  s.fix(s.gridpoints_on_plane(2, 0.0, tol), bc::transverse_to(2));
  s.fix(s.gridpoints_on_plane(2, length, tol), bc::transverse_to(2));
  const auto [first, end] = s.reinforcement().bar_nodes(0);
  bc::fix(s.bar_nodes(), bc::node_group{{first}, "fixed bar end"});
  bc::prescribe_velocity(s.bar_nodes(), bc::node_group{{end - 1}, "pulled bar end"}, vec3(0, 0, tie_pull_rate));
}

/// The tie solver of `scene` with its bar and options, held and pulled (hold_and_pull_bar).
struct pulled_tie : tie_solver {
  explicit pulled_tie(const prism_scene& scene)
      : tie_solver(scene.tess, scene.mesh, scene.block, scene.contact, tie_bar_of(scene), tie_options()) {
    hold_and_pull_bar(*this, scene.length);
  }
};

[[nodiscard]] inline bool same_bits(real a, real b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

/// Rows of `rows` (u, v or reactions) of the gridpoints in `which` whose bits differ from `ref`'s.
[[nodiscard]] inline index_t differing_rows(const soa3& rows, const soa3& ref, const std::vector<index_t>& which) {
  index_t n = 0;
  for (const index_t g : which) {
    bool same = true;
    for (int c = 0; c < 3; ++c) same = same && same_bits(rows(g, c), ref(g, c));
    n += same ? 0 : 1;
  }
  return n;
}

/// Sub-contacts in `which` whose law state (sigma_n, tau, u_n, tensile damage) differs in bits.
template <class Contacts>
[[nodiscard]] index_t differing_states(const Contacts& c, const Contacts& ref, std::span<const index_t> which) {
  index_t n = 0;
  for (const index_t i : which) {
    const auto& a = c.state(i);
    const auto& b = ref.state(i);
    const bool same = same_bits(a.sigma_n, b.sigma_n) && same_bits(a.tau.x(), b.tau.x()) &&
                      same_bits(a.tau.y(), b.tau.y()) && same_bits(a.tau.z(), b.tau.z()) &&
                      same_bits(a.u_n, b.u_n) && same_bits(a.u_soft, b.u_soft) &&
                      same_bits(a.dissipated_tension, b.dissipated_tension) &&
                      same_bits(prism_law::tensile_damage(c.subcontact_params(i), a),
                                prism_law::tensile_damage(ref.subcontact_params(i), b));
    n += same ? 0 : 1;
  }
  return n;
}

/// This process's rank in MPI_COMM_WORLD and the number of ranks.
[[nodiscard]] inline std::pair<int, int> rank_and_size() {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return {rank, size};
}

/// Rank 0's block -> rank map of `graph` over the communicator's ranks, broadcast: METIS's
/// (where built in, when asked) or slabs by bisection.
[[nodiscard]] inline std::vector<int> broadcast_map(const distributed::block_graph& graph, bool metis) {
  const auto [rank, size] = rank_and_size();
  std::vector<int> map(static_cast<std::size_t>(graph.block_count()), -1);
  if (rank == 0) {
#ifdef TESSERA_HAVE_METIS
    map = metis ? distributed::partition_blocks_metis(graph, size) : distributed::partition_blocks_rcb(graph, size);
#else
    (void)metis;
    map = distributed::partition_blocks_rcb(graph, size);
#endif
  }
  MPI_Bcast(map.data(), graph.block_count(), MPI_INT, 0, MPI_COMM_WORLD);
  return map;
}

[[nodiscard]] inline index_t summed_over_ranks(index_t n) {
  long long mine = n, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  return static_cast<index_t>(all);
}
}  // namespace split_test
