// rubble: a cube cut into random Voronoi blocks (default 1 000), each shrunk about its centroid so
// no two touch, released under gravity onto a fixed floor. Rigid blocks, every contact detected
// (contact::detected_contacts): blocks fall, land, slide off the heap's flanks and meet blocks
// they were never next to. A scene to look at in ParaView and a load for contact detection.
//
// Outputs in --out (default results/rubble):
//   summary.json   the scene, steps, dt, rebuilds, storage growths, sub-contacts (final, peak),
//                  gravity work, rebuild exchange (J), energy balance error, the heap's final
//                  height and spread, runtime_s and the part of it spent in rebuilds (rebuild_s),
//                  the blocks the rebuilds detected again (redetected_blocks, summed over them) and
//                  placed (placed_blocks: those and the others the pass read),
//                  the phase split and ns_per_subcontact_step (common/phase_report.hpp; over the
//                  mean sub-contact count, with and without the rebuilds; split: rank 0's), and
//                  mpi_ranks (split: the mpi_* figures of common/mpi_run.hpp and mpi_rebalances)
//   curve.csv      t_s, kinetic_J, contact_stored_J, rebuild_exchange_J, subcontacts, rebuilds,
//                  top_z_m (highest block centroid)
//   blocks_NNNN.vtu + rubble.pvd   the blocks at --frames instants (unless --no-vtk)
// Under mpirun -np N (builds with MPI): the same run split over N ranks by blocks
// (distributed::rigid_stepper: each rank integrates its blocks and evaluates their contacts,
// detection is done whole on every rank, blocks change rank at rebuilds), the same motion to the
// bit; rank 0 writes --out.
// Exit status 0 when the run finished, 1 on an error, 2 on bad flags.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <array>
#include <string>
#include <vector>

#include "common/cli.hpp"
#include "common/mpi_run.hpp"
#include "common/phase_report.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/run_record.hpp"
#include "tessera/io/vtk.hpp"
#include "verification/cases.hpp"

#ifdef TESSERA_HAVE_MPI
#include "tessera/distributed/rigid_stepper.hpp"
#endif

namespace {

using namespace tessera;
using tessera::index_t;  // not strings.h's index()
namespace ver = tessera::verification;

struct inputs {
  cli::standard_options common;
  int blocks = 1000;
  real size = 1.0;          ///< cube edge (m)
  real gap = 0.01;          ///< each block shrunk by this fraction about its centroid
  real lift = 0.02;         ///< the cube starts this far above the floor (m)
  real friction_deg = 20;
  real k_n = 1e9;           ///< joint stiffness (Pa/m), k_s = k_n
  real density = 2400;      ///< kg/m^3
  real damping = 0.1;       ///< local damping gamma
  real duration = 1.0;      ///< simulated time (s)
  real tolerance = 0;       ///< contact tolerance (m); 0 = 2 % of the mean block size
  int frames = 20;          ///< VTK snapshots
  bool vtk = true;
};

using solver_type = solver<blocks::rigid, ver::contacts, reinforcement::none, ver::damped>;

/// The floor (cell 0, fixed) and the shrunk Voronoi cells of the cube, lifted.
std::vector<geometry::convex_polyhedron> scene_cells(const inputs& in) {
  const real L = in.size;
  std::vector<geometry::convex_polyhedron> cells{
      geometry::convex_polyhedron::box({-1.5 * L, -1.5 * L, -0.2 * L}, {2.5 * L, 2.5 * L, 0})};
  const auto voronoi = geometry::random_voronoi({vec3::Zero(), vec3(L, L, L)}, in.blocks, in.common.seed);
  for (index_t c = 0; c < voronoi.cell_count(); ++c) {
    const auto cell = geometry::cell_polyhedron(voronoi, c);
    const vec3 centre = cell.centroid();
    cells.push_back(cell.transformed((1 - in.gap) * mat3::Identity(), in.gap * centre + vec3(0, 0, in.lift)));
  }
  return cells;
}

/// The run's steps: solver::step as one process; under mpirun over N ranks, this rank's part
/// (distributed::rigid_stepper, blocks cut by partition_moving_blocks) with the energies summed
/// over the ranks and the split's figures for summary.json (common/mpi_run.hpp).
class split_stepping {
 public:
  split_stepping(solver_type& s, [[maybe_unused]] const geometry::block_mesh& mesh) {
#ifdef TESSERA_HAVE_MPI
    const scenes::mpi_session* session = scenes::mpi_session::current();
    if (session != nullptr && session->split()) {
      map_ = distributed::partition_moving_blocks(mesh, session->ranks());
      stepper_ = std::make_unique<distributed::rigid_stepper<solver_type>>(s, map_, MPI_COMM_WORLD);
    }
#else
    (void)s;
#endif
  }
  void step(solver_type& s) {
#ifdef TESSERA_HAVE_MPI
    if (stepper_) return stepper_->step();
#endif
    s.step();
  }
  /// The balance at a sample, after a check that every gridpoint is finite (split: every rank
  /// throws alike on a NaN; one process: solver::step checks). Every rank must call it at the
  /// same steps when split (a collective).
  [[nodiscard]] energy_balance checked_energies(const solver_type& s) const {
#ifdef TESSERA_HAVE_MPI
    if (stepper_) {
      stepper_->check_finite();
      return stepper_->summed_energies();
    }
#endif
    return s.energies();
  }
  /// Every gridpoint current on this rank (rigid_stepper::sync_gridpoints), before a snapshot.
  void sync_gridpoints() {
#ifdef TESSERA_HAVE_MPI
    if (stepper_) stepper_->sync_gridpoints();
#endif
  }
  /// Rebuilds after which blocks changed rank (rigid_stepper::rebalances); -1 as one process.
  [[nodiscard]] std::int64_t rebalances() const {
#ifdef TESSERA_HAVE_MPI
    if (stepper_) return stepper_->rebalances();
#endif
    return -1;
  }
  /// Time in the steps' phases: solver::phases(), or this rank's (rigid_stepper::phases).
  [[nodiscard]] const phase_times& phases(const solver_type& s) const {
#ifdef TESSERA_HAVE_MPI
    if (stepper_) return stepper_->phases();
#endif
    return s.phases();
  }
  /// The split's figures into the session, for set_split_figures (a collective when split).
  void report() const {
#ifdef TESSERA_HAVE_MPI
    if (!stepper_) return;
    scenes::mpi_session& session = *scenes::mpi_session::current();
    distributed::split_figures& f = session.last_split.figures;
    session.last_split.ranks = stepper_->ranks();
    f.ranks = stepper_->ranks();
    f.partitioner = "rcb";
    f.rank_blocks.clear();
    for (int r = 0; r < f.ranks; ++r) f.rank_blocks.push_back(static_cast<index_t>(stepper_->rank_blocks(r).size()));
    const auto most = *std::max_element(f.rank_blocks.begin(), f.rank_blocks.end());
    f.weight_imbalance = static_cast<real>(most) * f.ranks / static_cast<real>(map_.size());
    f.edge_cut = 0;  // the contacts across the cut change as blocks move
    f.steps = stepper_->steps();
    f.halo_bytes_per_step = stepper_->exchange_bytes_per_step();
    f.max_rank_halo_bytes_per_step = static_cast<double>(most) * blocks::rigid::body_state_size * sizeof(double) * (f.ranks - 1);
    const double steps = std::max<double>(1, static_cast<double>(f.steps));
    std::array<double, 3> mine{stepper_->exchange_seconds() / steps, stepper_->step_seconds() / steps,
                               (stepper_->step_seconds() - stepper_->exchange_seconds()) / steps},
        most_s{}, sum{};
    MPI_Allreduce(mine.data(), most_s.data(), 3, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    MPI_Allreduce(mine.data(), sum.data(), 3, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    f.halo_seconds_per_step = most_s[0];
    f.step_seconds_per_step = most_s[1];
    f.time_imbalance = sum[2] > 0 ? most_s[2] * f.ranks / sum[2] : 1.0;
    f.gather_seconds = 0;
#endif
  }

 private:
#ifdef TESSERA_HAVE_MPI
  std::vector<int> map_;
  std::unique_ptr<distributed::rigid_stepper<solver_type>> stepper_;
#endif
};

void validate(const inputs& in) {
  require(in.blocks >= 2 && in.blocks <= 20000, "rubble: --blocks = ", in.blocks, " must lie in [2, 20000]");
  require(std::isfinite(in.size) && in.size > 0 && in.size <= 1000, "rubble: --size = ", in.size,
          " m must lie in (0, 1000]");
  require(std::isfinite(in.gap) && in.gap > 0 && in.gap <= 0.2, "rubble: --gap = ", in.gap, " must lie in (0, 0.2]");
  require(std::isfinite(in.lift) && in.lift >= 0 && in.lift <= in.size, "rubble: --lift = ", in.lift,
          " m must lie in [0, --size]");
  require(in.frames >= 1 && in.frames <= 1000, "rubble: --frames = ", in.frames, " must lie in [1, 1000]");
}

int run(const inputs& in) {
  validate(in);
  ver::inputs joint_in;
  joint_in.k_n = in.k_n;
  joint_in.friction_deg = in.friction_deg;
  const auto cells = scene_cells(in);
  const real mean_size = in.size / std::cbrt(static_cast<real>(in.blocks));
  const real tolerance = in.tolerance > 0 ? in.tolerance : 0.02 * mean_size;
  require(tolerance <= 0.2 * mean_size, "rubble: --tolerance = ", tolerance, " m must be at most a fifth of the mean block (",
          0.2 * mean_size, " m)");
  const geometry::tessellation tess = geometry::separate_blocks(cells);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  solver_options options;
  options.damping_gamma = in.damping;
  if (in.common.threads > 0) set_threads(in.common.threads);
  const cli::wall_timer timer;
  solver_type s(tess, mesh, blocks::rigid::params{in.density}, ver::contacts::params(ver::joint(joint_in), tolerance),
                {}, options);
  s.set_gravity(vec3(0, 0, -ver::g));
  s.fix(s.gridpoints_on_plane(2, -0.2 * in.size, 1e-9));
  const real step_count = std::ceil(in.duration / s.dt());
  require(step_count <= 1e8, "rubble: ", in.duration, " s at the stable step ", s.dt(), " s would take ", step_count,
          " steps (over 1e8): shorten --duration or lower --kn");
  const auto steps = static_cast<index_t>(step_count);

  // Everything checked: now the outputs.
  const std::filesystem::path out = in.common.out;
  io::ensure_directory(out);
  io::vtk::pvd_collection pvd;
  std::vector<double> t, kinetic, stored, exchange, subs, rebuilds, top;
  const index_t every = std::max<index_t>(1, steps / 500), frame_every = std::max<index_t>(1, steps / in.frames);
  // The blocks' centroids at the start, once (a polyhedron's centroid is its mass properties:
  // recomputed at every sample they took 7 of the 10 000-block scene's 258 s, on one thread).
  std::vector<vec3> centroid0(cells.size());
  for (std::size_t b = 0; b < cells.size(); ++b) centroid0[b] = cells[b].centroid();
  const auto top_z = [&] {
    real z = -1e300;
    for (index_t b = 1; b < s.blocks().block_count(); ++b)
      z = std::max(z, centroid0[static_cast<std::size_t>(b)].z() + s.blocks().displacement(b).z());
    return z;
  };
  const auto snapshot = [&](index_t k) {
    if (!in.vtk) return;
    char name[32];
    std::snprintf(name, sizeof name, "blocks_%04lld.vtu", static_cast<long long>(k / frame_every));
    io::vtk::write_blocks_vtu(out / name, ver::moved(tess, mesh, s.gridpoints()), io::vtk::format::binary);
    pvd.add(s.time(), out / name);
  };
  // Under mpirun: this rank's blocks (common/mpi_run.hpp, distributed/rigid_stepper.hpp).
  split_stepping split(s, mesh);
  snapshot(0);
  double subcontact_steps = 0;  // sum over the steps of the sub-contacts the step updated
  for (index_t k = 1; k <= steps; ++k) {
    split.step(s);
    subcontact_steps += static_cast<double>(s.contacts().subcontact_count());
    if (k % every == 0 || k == steps) {
      t.push_back(s.time());
      const energy_balance e = split.checked_energies(s);
      kinetic.push_back(e.kinetic);
      stored.push_back(e.contact_stored);
      exchange.push_back(e.contact_rebuild_exchange);
      subs.push_back(static_cast<double>(s.contacts().subcontact_count()));
      rebuilds.push_back(static_cast<double>(s.contacts().rebuild_count()));
      top.push_back(top_z());
    }
    if (k % frame_every == 0 || k == steps) {
      split.sync_gridpoints();  // the blocks of other ranks that no pair here touches
      snapshot(k);
    }
  }
  const double runtime_s = timer.seconds();
  const energy_balance end = split.checked_energies(s);
  split.report();

  // The heap: height of the highest centroid, horizontal spread of the centroids beyond the cube.
  real spread = 0;
  for (index_t b = 1; b < s.blocks().block_count(); ++b) {
    const vec3 x = centroid0[static_cast<std::size_t>(b)] + s.blocks().displacement(b);
    spread = std::max({spread, -x.x(), x.x() - in.size, -x.y(), x.y() - in.size});
  }
  io::write_csv(out / "curve.csv",
                {"t_s", "kinetic_J", "contact_stored_J", "rebuild_exchange_J", "subcontacts", "rebuilds", "top_z_m"},
                {t, kinetic, stored, exchange, subs, rebuilds, top});
  if (in.vtk) pvd.write(out / "rubble.pvd");
  io::summary_json j;
  j.set("example", "rubble")
      .set("quick", in.common.quick)
      .set("seed", static_cast<std::int64_t>(in.common.seed))
      .set("blocks", in.blocks)
      .set("size_m", in.size)
      .set("gap", in.gap)
      .set("lift_m", in.lift)
      .set("friction_deg", in.friction_deg)
      .set("k_n_Pa_per_m", in.k_n)
      .set("damping", in.damping)
      .set("damping_in_force", s.damping_in_force())
      .set("tolerance_m", tolerance)
      .set("duration_s", in.duration)
      .set("dt_s", s.dt())
      .set("steps", static_cast<std::int64_t>(steps))
      .set("rebuilds", static_cast<std::int64_t>(s.contacts().rebuild_count()))
      .set("steps_per_rebuild", static_cast<double>(steps) / std::max<index_t>(1, s.contacts().rebuild_count()))
      .set("storage_growths", static_cast<std::int64_t>(s.contacts().growth_count()))
      .set("subcontacts", static_cast<std::int64_t>(s.contacts().subcontact_count()))
      .set("subcontacts_peak", static_cast<std::int64_t>(s.contacts().peak_subcontacts()))
      .set("kinetic_end_J", end.kinetic)
      .set("gravity_work_J", end.gravity_work)
      .set("contact_rebuild_exchange_J", end.contact_rebuild_exchange)
      .set("energy_error_rel", end.error_rel())
      .set("top_z_start_m", top.empty() ? 0.0 : top.front())
      .set("top_z_end_m", top_z())
      .set("spread_m", spread)
      .set("threads", max_threads())
      .set("rebuild_s", s.contacts().rebuild_seconds())
      .set("redetected_blocks", s.contacts().redetected_blocks())
      .set("placed_blocks", s.contacts().placed_blocks())
      .set("narrow_phase_pairs", s.contacts().narrow_phase_pairs())
      .set("pairs_apart_by_kept_axis", s.contacts().pairs_apart_by_kept_axis())
      .set("pairs_kept_as_one", s.contacts().pairs_kept_as_one())
      .set("runtime_s", runtime_s);
  tessera::scenes::set_split_figures(j);
  if (split.rebalances() >= 0) j.set("mpi_rebalances", split.rebalances());
  // Per-entity cost (common/phase_report.hpp) over the mean sub-contact count; the contact phase
  // includes the rebuilds, so the per-step cost without them is given beside.
  const double mean_subcontacts = steps > 0 ? subcontact_steps / static_cast<double>(steps) : 0.0;
  tessera::scenes::set_phase_figures(j, split.phases(s), 0, static_cast<index_t>(std::llround(mean_subcontacts)),
                                     static_cast<std::int64_t>(steps));
  j.set("mean_subcontacts", mean_subcontacts)
      .set("ns_per_subcontact_step_without_rebuilds",
           subcontact_steps > 0 ? (split.phases(s).contacts - s.contacts().rebuild_seconds()) * 1e9 / subcontact_steps : 0.0);
  j.write(out / "summary.json");
  std::printf("rubble: %d blocks, %lld steps of %.3g s, %lld rebuilds (%.1f steps each), %lld sub-contacts (peak %lld)\n",
              in.blocks, static_cast<long long>(steps), s.dt(), static_cast<long long>(s.contacts().rebuild_count()),
              static_cast<double>(steps) / std::max<index_t>(1, s.contacts().rebuild_count()),
              static_cast<long long>(s.contacts().subcontact_count()),
              static_cast<long long>(s.contacts().peak_subcontacts()));
  std::printf("  highest centroid %.4g m, spread beyond the cube %.4g m, runtime_s %.2f (rebuilds %.2f s, %lld blocks "
              "detected again)\n",
              top_z(), spread, runtime_s, s.contacts().rebuild_seconds(),
              static_cast<long long>(s.contacts().redetected_blocks()));
  std::printf("  gravity work %.4g J, rebuild exchange %.3g J, energy balance error %.2g\n", end.gravity_work,
              end.contact_rebuild_exchange, end.error_rel());
  std::printf("  wrote %s/{summary.json, curve.csv%s}\n", out.string().c_str(), in.vtk ? ", rubble.pvd, blocks_*.vtu" : "");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  tessera::scenes::mpi_session mpi(argc, argv);
  inputs in;
  bool no_vtk = false;
  cli::parser cli("rubble",
                  "A cube of random Voronoi blocks, each shrunk by --gap so none touch, dropped --lift onto a floor\n"
                  "under gravity: rigid blocks, all contacts detected (frictional joints, no cohesion). VTK series\n"
                  "for ParaView, sub-contact and rebuild counts, run time. --quick: 100 blocks for 0.1 s.\n"
                  "Under mpirun -np N (builds with MPI): the same run split over N ranks by blocks, the same motion\n"
                  "to the bit (energy books to round-off); rank 0 writes --out.");
  cli.add_standard(in.common);
  cli.option("--blocks", in.blocks, "number of Voronoi blocks", "N").within(2, 20000);
  cli.option("--size", in.size, "cube edge (m)", "M").greater_than(0).at_most(1000);
  cli.option("--gap", in.gap, "each block shrunk by this fraction about its centroid", "F").greater_than(0).at_most(0.2);
  cli.option("--lift", in.lift, "height of the cube above the floor at the start (m)", "M").at_least(0);
  cli.option("--friction-deg", in.friction_deg, "joint friction angle (deg)", "DEG").within(0, 89.9);
  cli.option("--kn", in.k_n, "joint stiffness k_n = k_s (Pa/m)", "K").greater_than(0).at_most(1e14);
  cli.option("--density", in.density, "block density (kg/m^3)", "RHO").greater_than(0).at_most(1e5);
  cli.option("--damping", in.damping, "local damping gamma", "G").within(0, 1);
  cli.option("--duration", in.duration, "simulated time (s)", "S").greater_than(0).at_most(100);
  cli.option("--tolerance", in.tolerance, "contact tolerance (m); 0 = 2 % of the mean block size", "M").at_least(0);
  cli.option("--frames", in.frames, "VTK snapshots", "N").within(1, 1000);
  cli.flag("--no-vtk", no_vtk, "write no VTK files");
  cli.parse_or_exit(argc, argv);
  in.vtk = !no_vtk;
  if (in.common.quick) {  // reduced run; a value given on the command line is kept
    if (!cli.given("--blocks")) in.blocks = 100;
    if (!cli.given("--duration")) in.duration = 0.1;
  }
  try {
    mpi.require_splittable(true, "rubble");
  } catch (const std::exception& e) {
    if (mpi.rank() == 0) cli::print_error("rubble", e);
    return 2;
  }
  mpi.route_output(in.common.out);  // under mpirun: rank 0 writes --out
  io::run_record record(in.common.out, "rubble", argc, argv);
  try {
    const int status = run(in);
    if (status == 0) record.complete();
    return status;
  } catch (const std::exception& e) {
    cli::print_error("rubble", e);
    return 1;
  }
}
