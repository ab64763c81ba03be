// rc_tie: the reference study's reinforced-concrete tie in direct tension — tension stiffening
// (Pulatsu et al. 2020, Sec. 3.1, Figures 6-9; DESIGN.md §4).
//
// Experiment (examples/common/rc_tie_scene.hpp has the full scene description):
//   specimen  68 x 68 x 600 mm prism (long axis z), --blocks random Voronoi blocks, deformable
//             semi-rigid (10 x 28 GPa), Table 1 contacts (cohesion c_0 = --cohesion-ratio x f_T,
//             2 by default; block counts outside Table 1: its stiffnesses scaled as blocks^(1/3)),
//             power (default) or linear softening; --law mixed_mode: the mixed-mode law on the same
//             contacts, G_II --g-ii (rc_tie/concrete.hpp)
//   bar       Ø8 mm on the axis, E_s = 192.3 GPa, f_y = 400 MPa, --elements truss elements,
//             bond ratio --xi (per unit bar length by default, --bond-basis), bond cohesion
//             --cbond (N/m)
//   supports  bar ends pulled apart along z at -/+ --rate/2 (--fixed-end: first node fixed, last
//             pulled at --rate, the study verbatim) after a half-cosine ramp of --ramp s;
//             concrete end gridpoints on rollers (x, y fixed, z free). With --min-rate-factor or
//             --max-rate-factor the rate follows the out-of-balance ratio (largest nodal
//             unbalanced force / N_cr, tessera/solver/balance.hpp): --min-rate-factor x --rate
//             while it is over --balance-high, rising by --rate-growth a sample to
//             --max-rate-factor x --rate while it is under --balance-low
//   solver    central differences, local damping 0.8, masses scaled to the step --dt; or
//             (--scheme relaxation) kinetic dynamic relaxation: the bar ends moved apart by
//             --relax-increment, each increment relaxed to static equilibrium
//             (solver/relaxation.hpp; docs/guide.md)
//   stop      --post-yield x the elongation at which the tie yields past it (yield: the bar flows
//             plastically, rc_tie_run.hpp), or at --max-elongation
//
// Outputs in --out DIR:
//   curve.csv        elongation_m, force_N (force = tension at the fixed bar end), pulled_end_force_N,
//                    concrete_stress_Pa (the concrete's mean axial stress over the middle two
//                    thirds), softened_subcontacts (past their tensile peak), unbalanced_ratio
//                    (largest nodal unbalanced force / N_cr), rate_factor (on --rate, from then on;
//                    nan with --scheme relaxation, which has no rate)
//   bare_bar.csv     the bare bar, elastic-perfectly plastic (closed form) on the same range
//   curve.png        both curves (gnuplot)
//   <tag>_contacts.vtp, <tag>_bar.vtp, <tag>_zones.vtu for tag = drop1, drop2, ..., yield, end:
//                    sub-contacts (tensile damage 0..1, status flags, every declared law field),
//                    the bar as a polyline (axial force per element, slip and bond force per
//                    node, displacement), zones (displacement, stress); tie.pvd lists them
//   summary.json     inputs (law, g_ii_J_per_m2, phi_res_deg), hand checks, first_crack_force_N and its error
//                    vs f_T (A_c + n A_s),
//                    first_drop_force_N (peak of the first load drop) and its error,
//                    first_softening_force_N (first sub-contact past its peak),
//                    concrete_stress_at_first_crack_Pa (and / f_T), softened_subcontacts_at_first_crack,
//                    initial_stiffness_N_per_m and its error vs (E_c A_c + E_s A_s)/L and vs the
//                    shear-lag value of the bonded tie, load_drops,
//                    cracks (fully opened through-cracks), crack_positions_m (mean z of each
//                    surface between two separated pieces: one more than the cracks where three
//                    pieces touch pairwise, as around a slice that does not fill the section),
//                    crack_sites (those surfaces grouped where less than one mean cell size,
//                    crack_site_spacing_m, apart) and crack_site_positions_m,
//                    bar_crossing_cracks (those the bar crosses; a fragment split off by a
//                    branching crack adds a separated piece but no crossing) and their positions,
//                    softened_cracks,
//                    yield_force_N and its error vs f_y A, final_force_N (where the final branch
//                    ends) and its error vs f_y A, the rate control's settings with
//                    mean_rate_factor and max_unbalanced_ratio, energy balance error, sizes,
//                    steps, runtime_s
// Definitions: load drop, initial stiffness and through-crack in tessera/analysis/ (curves.hpp,
// cracks.hpp), first cracking and yield force in examples/common/rc_tie_run.hpp.
//
// Two defaults differ from DESIGN.md's literal reading, each measured (README, "RC tie"): the bond
// stiffness xi K_axial is a modulus per metre of bar (3DEC's grout stiffness; per node the
// transfer length is 3 mm, no crack opens fully and the yield plateau sits 12.6 % above f_y A),
// and the bar ends are pulled symmetrically (local damping otherwise drags the floating
// concrete: bar-end forces differed by up to 20 % of f_y A). summary.json reports the initial
// stiffness against both the shear-lag closed form and the perfect-bond hand value.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "common/calibration.hpp"
#include "common/cli.hpp"
#include "common/relaxed_scheme.hpp"
#include "common/rc_tie_run.hpp"
#include "common/snapshots.hpp"
#include "rc_tie/concrete.hpp"
#include "tessera/io/atomic_file.hpp"
#include "tessera/io/run_record.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/plot.hpp"

namespace {

using tessera::index_t;
using tessera::real;
using tessera::vec3;
namespace fs = std::filesystem;

struct inputs {
  tessera::cli::standard_options common;
  tessera::scenes::tie_options tie;
  tessera::scenes::tie_loading loading;
  tessera::scenes::tie_law law;  // --law, --g-ii (rc_tie/concrete.hpp)
  bool write_vtk = true;
  std::string params;  // calibrated.json (examples/calibrate); empty = the study verbatim
  std::string scheme = "explicit";                // explicit | relaxation (kinetic dynamic relaxation)
  std::vector<std::string> explicit_flags_given;  // flags of the explicit pull on the command line
  std::vector<std::string> relax_flags_given;     // flags of the relaxation on the command line
};

/// |value - reference| / |reference|.
double rel(double value, double reference) { return std::abs(value - reference) / std::abs(reference); }

/// A sampled curve (elongation m, force N).
struct sampled_curve {
  std::vector<double> u, f;
};

/// The bare bar, F = min(E_s A_s u / L, f_y A_s), on 201 points to past the run's end and the yield.
sampled_curve bare_bar_curve(const tessera::scenes::tie_hand_checks& hand, real end_elongation) {
  sampled_curve bare;
  const real u_end = std::max(end_elongation, 1.2 * hand.yield_force / hand.bare_bar_stiffness);
  for (int i = 0; i <= 200; ++i) {
    bare.u.push_back(u_end * i / 200.0);
    bare.f.push_back(hand.bare_bar_force(bare.u.back()));
  }
  return bare;
}

/// curve.csv, bare_bar.csv and curve.png.
void write_curves(const fs::path& out, const inputs& in, const tessera::scenes::tie_scene& scene,
                  const tessera::scenes::tie_result& r, const sampled_curve& bare) {
  namespace io = tessera::io;
  std::vector<real> softened(r.softened_subcontacts.begin(), r.softened_subcontacts.end());
  io::write_csv(out / "curve.csv",
                {"elongation_m", "force_N", "pulled_end_force_N", "concrete_stress_Pa", "softened_subcontacts",
                 "unbalanced_ratio", "rate_factor"},
                {r.elongation, r.force, r.pulled_force, r.concrete_stress, softened, r.unbalanced_ratio,
                 r.rate_factor});
  io::write_csv(out / "bare_bar.csv", {"elongation_m", "force_N"}, {bare.u, bare.f});
  io::plot_spec plot;
  plot.title = tessera::detail::concat("RC tie, ", in.tie.blocks, " blocks, ", in.tie.elements, " elements, xi ",
                                       in.tie.xi, ", c_bond ", in.tie.c_bond, " N/m, ",
                                       tessera::scenes::tie_law_text(scene, in.law, in.loading),
                                       in.tie.bare ? " (bare bar run)" : "");
  plot.xlabel = "elongation (mm)";
  plot.ylabel = "force (kN)";
  plot.series.push_back({.csv = out / "curve.csv", .x_column = "elongation_m", .y_column = "force_N",
                         .title = in.tie.bare ? "tessera, bare bar" : "tessera", .x_scale = 1e3, .y_scale = 1e-3});
  plot.series.push_back({.csv = out / "bare_bar.csv", .x_column = "elongation_m", .y_column = "force_N",
                         .title = "bare bar (elastic-perfectly plastic)", .style = "lines dt 2 lw 2", .x_scale = 1e3,
                         .y_scale = 1e-3});
  io::plot_png(out / "curve.png", plot);
}

/// Where the cracks are: the opened through-cracks grouped into sites one mean cell size apart.
struct crack_sites_of_run {
  real cell_size = 0;       ///< (box volume / blocks)^(1/3) (m)
  std::vector<real> sites;  ///< z of each site (m)
};

/// summary.json: the inputs, the hand checks, every measured figure beside its reference and
/// the run's cost (one key per line: the list is the file's schema, so it stays in one piece).
void write_summary(const fs::path& out, const inputs& in, const tessera::scenes::tie_scene& scene,
                   const tessera::scenes::tie_result& r, const sampled_curve& bare, const crack_sites_of_run& c,
                   const tessera::cli::wall_timer& timer) {
  namespace io = tessera::io;
  const auto& hand = scene.hand;
  const real cell_size = c.cell_size;
  const std::vector<real>& sites = c.sites;
  std::vector<double> drop_forces, drop_elongations;
  for (const auto& d : r.drops) drop_forces.push_back(d.peak_force), drop_elongations.push_back(d.peak_elongation);
  std::vector<double> formation_u, formation_f;
  for (const auto& [u, f] : r.crack_formation) formation_u.push_back(u), formation_f.push_back(f);
  const real bare_error = tessera::analysis::curve_error(tessera::analysis::running_max(r.elongation), r.force, bare.u,
                                                       bare.f, hand.yield_force);
  io::summary_json js;
  js.set("example", "rc_tie")
      .set("blocks", in.tie.blocks)
      .set("contact_stiffness", std::string(tessera::law::in_table1(in.tie.blocks) ? "table1" : "table1_scaled_cbrt"))
      .set("k_n_Pa_per_m", scene.prism.contact.k_n)
      .set("seed", in.tie.seed)
      .set("elements", in.tie.elements)
      .set("regularize", in.tie.regularize)
      .set("lloyd_iterations", in.tie.lloyd)
      .set("xi", in.tie.xi)
      .set("bond_basis", std::string(in.tie.bond_basis == tessera::reinforcement::stiffness_basis::per_node ? "node" : "length"))
      .set("symmetric_pull", in.loading.symmetric)
      .set("c_bond_N_per_m", in.tie.c_bond)
      .set("softening", in.loading.softening)
      .set("cohesion", in.loading.cohesion)
      .set("cohesion_ratio", in.tie.cohesion_ratio)
      .set("params", in.params)
      .set("strength_scale", in.tie.strength_scale)
      .set("fracture_energy_scale", in.tie.fracture_energy_scale)
      .set("slip_breaks_tension", in.loading.slip_breaks_tension)
      .set("rigid", in.tie.rigid)
      .set("bare", in.tie.bare)
      .set("rate_m_per_s", in.loading.rate)
      .set("min_rate_factor", in.loading.rate_control.min_factor)
      .set("max_rate_factor", in.loading.rate_control.max_factor)
      .set("balance_low", in.loading.rate_control.low)
      .set("balance_high", in.loading.rate_control.high)
      .set("rate_growth", in.loading.rate_control.growth)
      .set("mean_rate_factor", r.mean_rate_factor)
      .set("max_unbalanced_ratio", r.max_unbalanced_ratio)
      .set("ramp_s", in.loading.ramp_time)
      .set("quick", in.common.quick)
      .set("threads", tessera::max_threads())
      .set("length_m", hand.length)
      .set("steel_area_m2", hand.steel_area)
      .set("concrete_area_m2", hand.concrete_area)
      .set("modular_ratio", hand.modular_ratio)
      .set("hand_cracking_force_N", hand.cracking_force)
      .set("hand_uncracked_stiffness_N_per_m", hand.uncracked_stiffness)
      .set("hand_bare_bar_stiffness_N_per_m", hand.bare_bar_stiffness)
      .set("hand_yield_force_N", hand.yield_force)
      .set("first_crack_force_N", r.first_crack_force)
      .set("first_crack_error_rel", rel(r.first_crack_force, hand.cracking_force))
      .set("first_drop_force_N", r.first_drop_force)
      .set("first_drop_error_rel", rel(r.first_drop_force, hand.cracking_force))
      .set("first_softening_force_N", r.first_softening_force)
      .set("concrete_stress_at_first_crack_Pa", r.concrete_stress_at_first_crack)
      .set("concrete_stress_at_first_crack_over_f_T", r.concrete_stress_at_first_crack / scene.prism.f_T)
      .set("softened_subcontacts_at_first_crack", r.softened_at_first_crack)
      .set("initial_stiffness_N_per_m", r.initial_stiffness)
      .set("initial_stiffness_error_rel",
           rel(r.initial_stiffness, in.tie.bare ? hand.bare_bar_stiffness : hand.uncracked_stiffness))
      .set("initial_stiffness_shear_lag_N_per_m", in.tie.bare ? hand.bare_bar_stiffness : hand.bonded_stiffness)
      .set("initial_stiffness_shear_lag_error_rel",
           rel(r.initial_stiffness, in.tie.bare ? hand.bare_bar_stiffness : hand.bonded_stiffness))
      .set("load_drops", static_cast<std::int64_t>(r.drops.size()))
      .set("load_drop_peak_forces_N", drop_forces)
      .set("load_drop_elongations_m", drop_elongations)
      .set("cracks", r.cracks.cracks)
      .set("crack_positions_m", r.cracks.positions)
      .set("crack_sites", static_cast<std::int64_t>(sites.size()))
      .set("crack_site_positions_m", sites)
      .set("crack_site_spacing_m", cell_size)
      .set("bar_crossing_cracks", r.cracks.bar_crossings)
      .set("bar_crossing_crack_positions_m", r.cracks.bar_crossing_positions)
      .set("crack_opening_threshold_m", r.cracks.opening_threshold)
      .set("cracks_normal_opening_only", r.cracks_normal_only.cracks)
      .set("softened_cracks", r.softened_cracks.cracks)
      .set("softened_crack_positions_m", r.softened_cracks.positions)
      .set("crack_formation_elongations_m", formation_u)
      .set("crack_formation_forces_N", formation_f)
      .set("open_subcontacts", r.cracks.open_subcontacts)
      .set("yielded", r.yielded)
      .set("yield_elongation_m", r.yield_elongation)
      .set("yield_force_N", r.yield_force)
      .set("yield_force_error_rel", rel(r.yield_force, hand.yield_force))
      .set("final_force_N", r.final_force)
      .set("final_force_error_rel", rel(r.final_force, hand.yield_force))
      .set("end_elongation_m", r.end_elongation)
      .set("bare_bar_curve_error_rel", bare_error)
      .set("boundary_work_J", r.boundary_work)
      .set("contact_dissipated_J", r.contact_dissipated)
      .set("bar_dissipated_J", r.bar_dissipated)
      .set("damping_dissipated_J", r.damping_dissipated)
      .set("energy_balance_error_rel", r.energy_balance_error)
      .set("max_end_force_imbalance_rel", r.max_imbalance)
      .set("subcontacts", r.subcontacts)
      .set("zones", r.zones)
      .set("gridpoints", r.gridpoints)
      .set("dt_s", r.dt)
      .set("added_mass_target", in.loading.added_mass_ratio)
      .set("added_mass_ratio", r.added_mass_ratio)
      .set("steps", r.steps)
      .set("runtime_s", timer.seconds());
  tessera::scenes::set_scheme_figures(js, in.scheme, in.loading.relax_increment, in.loading.relax_tolerance, r);
  tessera::scenes::set_phase_figures(js, r.phases, r.zones, r.subcontacts, r.steps);
  tessera::scenes::set_split_figures(js);
  tessera::scenes::set_tie_law_figures(js, scene, in.law, in.loading);  // law, G_II; softening, cohesion in place
  js.write(out / "summary.json");
}

/// The run's figures on stdout, each beside its reference.
void print_report(const fs::path& out, const tessera::scenes::tie_scene& scene, const tessera::scenes::tie_result& r,
                  const crack_sites_of_run& c, const tessera::cli::wall_timer& timer) {
  const auto& hand = scene.hand;
  const real cell_size = c.cell_size;
  const std::vector<real>& sites = c.sites;

  std::printf("rc_tie: first crack %.2f kN (hand %.2f kN, error %.1f %%), K0 %.1f kN/mm (shear lag %.1f, error %.1f %%;"
              " perfect compatibility %.1f, error %.1f %%)\n"
              "  load drops %zu, softened through-cracks %d, fully opened through-cracks %d (%d by u_n alone), %zu"
              " separating surfaces at z =",
              r.first_crack_force * 1e-3, hand.cracking_force * 1e-3, 100 * rel(r.first_crack_force, hand.cracking_force),
              r.initial_stiffness * 1e-6, hand.bonded_stiffness * 1e-6, 100 * rel(r.initial_stiffness, hand.bonded_stiffness),
              hand.uncracked_stiffness * 1e-6, 100 * rel(r.initial_stiffness, hand.uncracked_stiffness), r.drops.size(),
              r.softened_cracks.cracks, r.cracks.cracks, r.cracks_normal_only.cracks, r.cracks.positions.size());
  for (real z : r.cracks.positions) std::printf(" %.3f", z);
  std::printf(" m;\n  %zu crack sites (surfaces less than one cell size, %.1f mm, apart merged) at z =", sites.size(),
              cell_size * 1e3);
  for (real z : sites) std::printf(" %.3f", z);
  std::printf(" m\n  first sub-contact softened at %.2f kN; at first crack the concrete carries %.2f MPa (%.2f f_T) with %lld"
              " of %lld sub-contacts past their peak\n  yield",
              r.first_softening_force * 1e-3, r.concrete_stress_at_first_crack * 1e-6,
              r.concrete_stress_at_first_crack / scene.prism.f_T, static_cast<long long>(r.softened_at_first_crack),
              static_cast<long long>(r.subcontacts));
  std::printf(" %.2f kN (f_y A %.2f kN, error %.2f %%) at %.3f mm, final branch %.2f kN (error %.2f %%); "
              "energy balance error %.2g\n"
              "  %lld sub-contacts, %lld zones, dt %.3g s (added mass %.1fx), %lld steps, runtime %.1f s; wrote %s\n",
              r.yield_force * 1e-3, hand.yield_force * 1e-3, 100 * rel(r.yield_force, hand.yield_force),
              r.yield_elongation * 1e3, r.final_force * 1e-3, 100 * rel(r.final_force, hand.yield_force),
              r.energy_balance_error, static_cast<long long>(r.subcontacts),
              static_cast<long long>(r.zones), r.dt, r.added_mass_ratio, static_cast<long long>(r.steps), timer.seconds(),
              out.string().c_str());
  tessera::scenes::print_relaxation_counts(r);  // a relaxed run: its dt and added mass above are at 1 s of pseudo-time
}

int run(inputs in) {
  namespace io = tessera::io;
  const fs::path out = in.common.out;
  const tessera::cli::wall_timer timer;
  in.tie.seed = in.common.seed;
  in.loading.threads = in.common.threads;
  in.loading.progress_label = in.tie.bare ? "rc_tie (bare bar)" : "rc_tie";
  if (!in.params.empty()) {
    const tessera::scenes::calibration_recipe recipe{"power", in.tie.cohesion_ratio, in.loading.rate * in.loading.dt,
                                                     in.loading.rate, in.tie.rigid};
    const auto e = tessera::scenes::load_calibration(in.params, in.tie.blocks, recipe, "rc_tie");
    in.tie.strength_scale = e.strength_scale;
    in.tie.fracture_energy_scale = e.fracture_energy_scale;
  }
  tessera::scenes::check_scheme_flags({.driver = "rc_tie",
                                       .scheme = in.scheme,
                                       .explicit_given = in.explicit_flags_given,
                                       .relax_given = in.relax_flags_given,
                                       .rigid = in.tie.rigid,
                                       .explicit_load = "pull",
                                       .moves = "the bar ends move",
                                       .increment = in.loading.relax_increment,
                                       .last = in.loading.max_elongation,
                                       .last_flag = "--max-elongation"});
  const tessera::scenes::tie_scene scene = tessera::scenes::make_tie(in.tie);  // checks the options first
  const auto& hand = scene.hand;

  tessera::scenes::bar_snapshots snapshots(out, scene.prism.mesh, "tie.pvd", in.write_vtk && !in.tie.bare);
  const tessera::scenes::tie_result r =
      in.loading.relaxation ? tessera::scenes::run_tie_with_law<true>(scene, in.loading, in.law, snapshots)
                            : tessera::scenes::run_tie_with_law<false>(scene, in.loading, in.law, snapshots);
  io::ensure_directory(out);  // after the run's own checks (quasi-static rate, stable step) passed

  const sampled_curve bare = bare_bar_curve(hand, r.end_elongation);
  write_curves(out, in, scene, r, bare);
  crack_sites_of_run c;
  c.cell_size = std::cbrt(scene.prism.box.volume() / in.tie.blocks);  // mean cell size (m)
  c.sites = tessera::analysis::crack_sites(r.cracks.positions, c.cell_size);
  write_summary(out, in, scene, r, bare, c, timer);
  print_report(out, scene, r, c, timer);
  if (in.law.mixed()) std::printf("  law: %s\n", tessera::scenes::tie_law_text(scene, in.law, in.loading).c_str());
  return 0;
}

}  // namespace

// main: one declaration per flag (about 85 lines, the command line's reference, kept together).
int main(int argc, char** argv) {
  tessera::scenes::mpi_session mpi(argc, argv);
  inputs in;
  std::string softening = in.loading.softening;
  tessera::cli::parser cli("rc_tie",
                           "Reinforced-concrete tie (68 x 68 x 600 mm, one 8 mm bar) pulled by its bar to past yield\n"
                           "(Pulatsu et al. 2020, Sec. 3.1): load drops as cracks form, yield at f_y A = 20.1 kN.\n"
                           "Under mpirun -np N (builds with MPI): the same run split over N ranks, the same curve.csv\n"
                           "to the bit; rank 0 writes --out (not with --rigid).");
  cli.add_standard(in.common);
  int elements = static_cast<int>(in.tie.elements);
  bool no_vtk = false, fixed_end = false;
  std::string bond_basis = "length";
  cli.option("--blocks", in.tie.blocks,
             "number of blocks: 100, 250, 500 or 750 take the study's Table 1 stiffnesses; any other count takes them "
             "scaled as blocks^(1/3) (not the study's; about 45 kB per block)",
             "N").within(20, tessera::scenes::max_tie_blocks);
  cli.option("--regularize", in.tie.regularize, "collapse Voronoi edges shorter than REL x mean cell size (0 = off; 0.2 = presets::study_regularization)", "REL").within(0, tessera::geometry::max_regularization);
  cli.option("--lloyd", in.tie.lloyd, "Lloyd relaxation steps of the tessellation (0 = plain Voronoi)", "K").within(0, 1000);
  cli.option("--elements", elements, "truss elements along the bar", "N").within(2, 100000);
  cli.option("--xi", in.tie.xi, "bond stiffness ratio K_bond / K_axial", "XI").greater_than(0);
  cli.option("--cbond", in.tie.c_bond, "bond cohesion (N per m of bar)", "C").greater_than(0);
  cli.option("--softening", softening, "contact tensile softening with --law study: power (alpha = 3) or linear", "power|linear").one_of({"power", "linear"});
  cli.option("--cohesion", in.loading.cohesion,
             "cohesion under tensile softening with --law study: decoupled (c_0 until broken, DESIGN.md) or coupled (softens with "
             "f_t/f_T; power softening, deformable blocks)",
             "decoupled|coupled").one_of({"decoupled", "coupled"});
  tessera::scenes::add_tie_law_flags(cli, in.law);  // --law study|mixed_mode, --g-ii
  cli.option("--params", in.params,
             "calibrated.json from examples/calibrate: scale the concrete contacts' strength (and G_f) by its entry for --blocks "
             "(--law study)",
             "FILE");
  cli.option("--cohesion-ratio", in.tie.cohesion_ratio, "initial cohesion c_0 / f_T of the concrete contacts (c_res = 0.01 c_0; --law mixed_mode: 0)", "R").greater_than(0);
  cli.flag("--slip-breaks-tension", in.loading.slip_breaks_tension,
           "a contact that fails in shear is broken in tension too (3DEC/YADE brittle joints; DESIGN.md keeps its tension)");
  cli.option("--scheme", in.scheme,
             "explicit: central differences with local damping along a ramped pull (the study's scheme); "
             "relaxation: kinetic dynamic relaxation, the bar ends moved apart in increments each relaxed to static "
             "equilibrium (docs/guide.md; not with --rigid or under mpirun)",
             "explicit|relaxation").one_of({"explicit", "relaxation"});
  cli.option("--relax-increment", in.loading.relax_increment,
             "with --scheme relaxation: elongation per increment (m)", "M").greater_than(0);
  cli.option("--relax-tolerance", in.loading.relax_tolerance,
             "with --scheme relaxation: an increment is relaxed once the largest nodal unbalanced force and the "
             "largest block resultant are at most this x N_cr",
             "R").greater_than(0).at_most(1);
  cli.option("--rate", in.loading.rate, "elongation rate of the bar (m/s)", "V").greater_than(0);
  cli.option("--min-rate-factor", in.loading.rate_control.min_factor,
             "out-of-balance rate control: the rate drops to F x --rate as soon as the largest nodal unbalanced "
             "force exceeds --balance-high x N_cr (1 = never slower than --rate)",
             "F").greater_than(0).at_most(1);
  cli.option("--max-rate-factor", in.loading.rate_control.max_factor,
             "out-of-balance rate control: the rate may rise to F x --rate while that force stays under "
             "--balance-low x N_cr (1 = never faster than --rate)",
             "F").at_least(1);
  cli.option("--balance-low", in.loading.rate_control.low, "out-of-balance ratio under which the rate grows", "R")
      .greater_than(0);
  cli.option("--balance-high", in.loading.rate_control.high, "out-of-balance ratio over which the rate drops", "R")
      .greater_than(0);
  cli.option("--rate-growth", in.loading.rate_control.growth, "factor on the rate per sample under --balance-low",
             "G").greater_than(1);
  cli.flag("--fixed-end", fixed_end, "first bar node fixed, last pulled at --rate (default: both ends pulled at -/+ rate/2)");
  cli.option("--bond-basis", bond_basis, "bond stiffness xi K_axial per unit bar length (3DEC, default) or per node", "length|node").one_of({"length", "node"});
  cli.option("--ramp", in.loading.ramp_time, "half-cosine ramp time of the pull velocity (s)", "T").at_least(0);
  std::string dt_text = "auto";
  cli.option("--dt", dt_text,
             "mass-scaled time step (s); auto = 1e-6 x (100/blocks)^0.55 (1, 0.60, 0.41 us for 100, 250, 500 "
             "blocks: about the same added mass, 16x for seed 1); 0 = stable step of the unscaled masses",
             "DT|auto");
  cli.option("--added-mass", in.loading.added_mass_ratio,
             "instead of --dt: the mass-scaled step at which the added mass is R x the original mass (0 = off; "
             "deformable blocks; the 100-block default step adds 16.4x on seed 1)",
             "R").at_least(0);
  cli.option("--max-elongation", in.loading.max_elongation, "stop at this elongation (m) at the latest", "U").greater_than(0);
  cli.option("--post-yield", in.loading.post_yield, "after first yield at u_y, stop at (1 + this) u_y", "R").greater_than(0);
  cli.option("--damping", in.loading.damping_gamma, "local damping constant gamma", "G").within(0, 0.99);
  cli.option("--sample", in.loading.sample, "steps between curve samples", "K").at_least(1);
  cli.flag("--rigid", in.tie.rigid, "rigid 6-DOF blocks instead of deformable semi-rigid ones");
  cli.flag("--bare", in.tie.bare, "the bar alone (unbonded, concrete fixed): simulated bare-bar curve");
  cli.flag("--no-vtk", no_vtk, "skip the VTK snapshots");
  cli.parse_or_exit(argc, argv);
  in.tie.elements = elements;
  in.loading.softening = softening;
  in.loading.symmetric = !fixed_end;
  if (bond_basis != "length" && bond_basis != "node") {
    std::cerr << "rc_tie: --bond-basis '" << bond_basis << "' must be 'length' or 'node'\n";
    return 2;
  }
  in.tie.bond_basis = bond_basis == "node" ? tessera::reinforcement::stiffness_basis::per_node
                                           : tessera::reinforcement::stiffness_basis::per_unit_length;
  in.write_vtk = !no_vtk;
  in.loading.relaxation = in.scheme == "relaxation";
  for (const char* f : {"--rate", "--min-rate-factor", "--max-rate-factor", "--balance-low", "--balance-high",
                        "--rate-growth", "--ramp", "--dt", "--added-mass", "--damping", "--sample"})
    if (cli.given(f)) in.explicit_flags_given.emplace_back(f);
  for (const char* f : {"--relax-increment", "--relax-tolerance"})
    if (cli.given(f)) in.relax_flags_given.emplace_back(f);
  if (dt_text == "auto") {
    in.loading.dt = tessera::scenes::scaled_tie_dt(in.tie.blocks);  // same added mass for every block count
  } else {
    try {
      in.loading.dt = tessera::cli::detail::parse_value<double>("--dt", dt_text);
    } catch (const tessera::cli::usage_error&) {
      in.loading.dt = -1;  // not a number: reported below
    }
    if (!(in.loading.dt >= 0)) {
      std::cerr << "rc_tie: --dt '" << dt_text << "' must be 'auto' or a time step >= 0 (s)\n";
      return 2;
    }
  }
  if (in.common.quick) {
    // Reduced run (CTest): coarser mass-scaled step, 10 mm/s, shorter ramp; a value given on the
    // command line is kept.
    if (!cli.given("--dt") && !cli.given("--added-mass")) in.loading.dt = 4e-6;
    if (!cli.given("--rate")) in.loading.rate = 0.01;
    if (!cli.given("--ramp")) in.loading.ramp_time = std::min(in.loading.ramp_time, 5e-3);
  }
  // run.json is written when the output directory is created (after the checks), listing each
  // file as it is written; "complete" after summary.json, "interrupted" on SIGINT/SIGTERM.
  try {
    if (in.loading.relaxation)
      mpi.require_splittable(false, "rc_tie --scheme relaxation", "kinetic relaxation is not distributed");
    mpi.require_splittable(!in.tie.rigid, "rc_tie --rigid");
    tessera::scenes::require_tie_law_flags(cli, in.law, in.loading, in.tie, in.params, in.scheme);
  } catch (const std::exception& e) {
    if (mpi.rank() == 0) tessera::cli::print_error("rc_tie", e);
    return 2;
  }
  mpi.route_output(in.common.out);  // under mpirun: rank 0 writes --out
  tessera::io::run_record record(in.common.out, "rc_tie", argc, argv);
  try {
    const int status = run(in);
    if (status == 0) record.complete();
    return status;
  } catch (const std::exception& e) {
    tessera::cli::print_error("rc_tie", e);
    return 1;
  }
}
