// direct_tension: the reference study's plain-concrete prism pulled to complete separation
// (Pulatsu et al. 2020, Sec. 3, Table 1, Figure 5; DESIGN.md §4).
//
// Experiment:
//   specimen  68 x 68 x 600 mm prism (long axis z), N random Voronoi blocks (--blocks 100|250|500|750)
//   blocks    deformable, semi-rigid: E_block = 10 x 28 GPa, nu = 0.2, rho = 2400 kg/m^3;
//             or rigid 6-DOF blocks of the same density (--rigid)
//   contacts  Table 1 k_n, k_s for N; f_T = 2.15 MPa, G_f = 60 N/m, c_0 = 2 f_T, phi_0 = 35 deg;
//             power (alpha = 3, default) or linear softening (--softening)
//   supports  bottom gridpoints (z = 0) fixed; top gridpoints (z = 0.6 m) fixed transversally
//             (no rotation) and pulled along z at --rate after a half-cosine ramp
//   solver    central differences, local damping gamma = 0.8, masses scaled so that one step
//             moves the top by --step-displacement (dt* = du* / rate); quasi-static loading and
//             the stop criterion are explained in direct_tension/tension_test.hpp; or
//             (--scheme relaxation) kinetic dynamic relaxation: the top moved in increments,
//             each relaxed to static equilibrium (solver/relaxation.hpp)
//
// Concrete (--material; direct_tension/concrete.hpp): prism, the study's above (the default), or beam,
// rc_beam's concrete on calibrate's 150 x 150 x 600 mm beam-recipe prism with any law of
// common/concrete_laws.hpp (--law, --g-ii, ... as compression and brazilian take them) and --params
// applying a beam entry whole; its run is calibrate --targets tension's, to the bit.
//
// Outputs in --out DIR: curve.csv (top displacement m, mean axial stress from the top and the
// bottom reactions Pa, the largest nodal unbalanced force over f_T A), contacts_{peak,end}.vtp (sub-contacts with status, damage and every field
// the law declares), zones_{peak,end}.vtu (zones with displacement and stress), direct_tension.pvd
// (both instants), curve.png, summary.json. With --seeds K > 1: curve_seed<S>.csv per
// tessellation and envelope.csv (min/max stress over the seeds on a common displacement grid,
// the study's "computational model envelope").
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <iostream>
#include <string>
#include <vector>

#include "common/calibration.hpp"
#include "common/cli.hpp"
#include "common/relaxed_scheme.hpp"
#include "common/scenes.hpp"
#include "direct_tension/concrete.hpp"
#include "direct_tension/fields.hpp"
#include "direct_tension/tension_test.hpp"
#include "tessera/io/atomic_file.hpp"
#include "tessera/io/run_record.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/plot.hpp"
#include "tessera/io/vtk.hpp"
#include "tessera/analysis/energy.hpp"
#include "tessera/solver.hpp"

namespace {

using tessera::real;
namespace fs = std::filesystem;
namespace scenes = tessera::scenes;

struct inputs {
  tessera::cli::standard_options common;
  int blocks = 100;     // prism: the Table 1 count; beam: the prism's Voronoi blocks, 0 = the recipe's
  scenes::tension_concrete concrete;  // --material, the law flags, the beam's recipe and set
  std::string softening = "power";
  std::string cohesion = "decoupled";  // decoupled (DESIGN.md) | coupled (softens with f_t)
  bool slip_breaks_tension = false;    // shear failure also breaks the contact in tension (opt-in)
  double cohesion_ratio = 2;           // c_0 / f_T (the study: 2), c_res = 0.01 c_0
  bool rigid = false;
  int seeds = 1;
  int lloyd = 0;                  // Lloyd steps of the tessellation
  double regularize = 0;          // short-edge regularization (relative to the mean cell size)
  std::string params;             // calibrated.json (examples/calibrate); empty = the study verbatim
  scenes::calibration_entry calibrated;  // its entry for --blocks (scales 1 without --params)
  scenes::tension_loading loading;
  std::string scheme = "explicit";  // explicit | relaxation (kinetic dynamic relaxation)
  std::vector<std::string> explicit_flags_given;  // flags of the explicit ramp on the command line
  std::vector<std::string> relax_flags_given;     // flags of the relaxation on the command line
  bool phi_given = false, phi_res_given = false;  // prism: --phi-deg, --phi-res-deg given
};

[[nodiscard]] bool beam(const inputs& in) { return in.concrete.material == "beam"; }

/// One tessellation: builds the scene, runs the chosen block and law variant; k: the contacts' figures.
scenes::tension_result run_one(const inputs& in, std::uint64_t seed, bool keep_fields, scenes::prism_scene& scene,
                               scenes::tension_contacts& k) {
  scenes::tension_loading loading = in.loading;
  loading.keep_fields = keep_fields;
  loading.threads = in.common.threads;
  loading.label = tessera::detail::concat("direct_tension seed ", seed);
  if (beam(in)) return scenes::run_beam_tension(in.concrete.set, in.blocks, seed, loading, scene, k);
  scenes::prism_options po;
  po.blocks = in.blocks;
  po.seed = seed;
  po.tessellation.lloyd_iterations = in.lloyd;
  po.tessellation.min_edge_rel = in.regularize;
  po.cohesion_ratio = in.cohesion_ratio;
  po.strength_scale = in.calibrated.strength_scale;
  po.fracture_energy_scale = in.calibrated.fracture_energy_scale;
  scene = scenes::make_prism(po);
  scene.contact.shear.slip_breaks_tension = in.slip_breaks_tension;
  // --phi-deg, --phi-res-deg on the study's contacts, where given (the default run keeps them to the bit)
  if (in.phi_given) scene.contact.shear.phi_0 = tessera::law::friction_angle::from_degrees(in.concrete.phi_deg);
  if (in.phi_res_given) scene.contact.shear.phi_res = tessera::law::friction_angle::from_degrees(in.concrete.phi_res_deg);
  k.k_n = scene.contact.k_n;
  // Block model: deformable semi-rigid blocks, or rigid 6-DOF blocks (--rigid) with the same law.
  if (in.cohesion == "coupled") {
    const auto contact = tessera::law::with_coupled_cohesion(scene.contact);
    if (in.rigid) return scenes::run_direct_tension<tessera::coupled_rigid_prism_solver>(scene, contact, loading);
    return scenes::run_direct_tension<tessera::coupled_prism_solver>(scene, contact, loading);
  }
  return scenes::run_prism_variant(scene, in.softening, in.rigid, loading);
}

/// The flags that cannot be checked one at a time (combinations) and those checked again later
/// inside the library, before anything is written; loads --params.
void check_inputs(inputs& in) {
  tessera::require(in.seeds >= 1, "direct_tension: --seeds ", in.seeds, " must be >= 1");
  tessera::require(beam(in) || in.blocks == 100 || in.blocks == 250 || in.blocks == 500 || in.blocks == 750,
                   "direct_tension: --blocks ", in.blocks, " must be 100, 250, 500 or 750 with --material prism (Table 1 "
                   "stiffnesses)");
  tessera::require(in.lloyd >= 0, "direct_tension: --lloyd ", in.lloyd, " must be >= 0");
  // geometry::regularize checks this too, but only once the first scene is built, after --out exists.
  tessera::require(std::isfinite(in.regularize) && in.regularize >= 0 &&
                       in.regularize <= tessera::geometry::max_regularization,
                   "direct_tension: --regularize ", in.regularize, " must lie in [0, ",
                   tessera::geometry::max_regularization, "]");
  tessera::require(std::isfinite(in.cohesion_ratio) && in.cohesion_ratio >= 0, "direct_tension: --cohesion-ratio ",
                   in.cohesion_ratio, " must be finite and >= 0");
  tessera::require(in.softening == "power" || in.softening == "linear", "direct_tension: --softening '", in.softening,
                   "' must be 'power' or 'linear'");
  tessera::require(in.cohesion == "decoupled" || in.cohesion == "coupled", "direct_tension: --cohesion '", in.cohesion,
                   "' must be 'decoupled' or 'coupled'");
  tessera::require(in.cohesion == "decoupled" || in.softening == "power",
                   "direct_tension: --cohesion coupled is built with power softening only, got --softening ", in.softening);
  tessera::scenes::check_scheme_flags({.driver = "direct_tension",
                                       .scheme = in.scheme,
                                       .explicit_given = in.explicit_flags_given,
                                       .relax_given = in.relax_flags_given,
                                       .rigid = in.rigid,
                                       .explicit_load = "ramp",
                                       .moves = "the top moves",
                                       .increment = in.loading.relax_increment,
                                       .last = in.loading.max_displacement,
                                       .last_flag = "--max-displacement"});
  if (beam(in)) {  // the set from the flags or the file's entry, its contacts built once (bad values refused)
    scenes::finish_concrete(in.concrete, in.cohesion_ratio, in.params, in.loading.step_displacement, in.loading.rate);
  } else if (!in.params.empty()) {
    tessera::require(in.cohesion == "decoupled", "direct_tension: --params ", in.params,
                     ": calibrations are fitted with decoupled cohesion, this run uses --cohesion ", in.cohesion);
    const scenes::calibration_recipe run{in.softening, in.cohesion_ratio, in.loading.step_displacement, in.loading.rate,
                                         in.rigid};
    in.calibrated = scenes::load_calibration(in.params, in.blocks, run, "direct_tension");
  }
}

/// curve.csv of the first seed, envelope.csv over the seeds (when more than one) and curve.png.
void write_curves(const fs::path& out, const inputs& in, const std::vector<scenes::tension_result>& runs) {
  namespace io = tessera::io;
  const auto& r = runs.front();
  io::write_csv(out / "curve.csv", {"displacement_m", "stress_Pa", "stress_top_Pa", "stress_bottom_Pa", "unbalanced_ratio"},
                {r.displacement, r.stress, r.stress_top, r.stress_bottom, r.unbalanced_ratio});
  io::plot_spec plot;
  plot.title = tessera::detail::concat("Direct tension, ", beam(in) ? r.blocks : in.blocks, " blocks, ",
                                       beam(in) ? "the beam's concrete, " + in.concrete.set.law + " law"
                                                : in.softening + " softening", ", ", in.loading.rate * 1e3, " mm/s");
  plot.xlabel = "top displacement (mm)";
  plot.ylabel = "mean axial stress (MPa)";
  plot.series.push_back({.csv = out / "curve.csv", .x_column = "displacement_m", .y_column = "stress_Pa",
                         .title = tessera::detail::concat("tessera, seed ", in.common.seed), .x_scale = 1e3,
                         .y_scale = 1e-6});
  if (in.seeds > 1) {
    // Envelope on a common displacement grid up to the shortest curve (linear interpolation).
    double u_max = 1e300;
    for (const auto& x : runs) u_max = std::min(u_max, x.displacement.empty() ? 0.0 : x.displacement.back());
    std::vector<double> grid, lo, hi;
    for (int i = 0; i <= 400; ++i) grid.push_back(u_max * i / 400.0);
    for (double u : grid) {
      double a = 1e300, b = -1e300;
      for (const auto& x : runs) {
        const double v = tessera::analysis::interpolate_curve(x.displacement, x.stress, u);
        a = std::min(a, v), b = std::max(b, v);
      }
      lo.push_back(a), hi.push_back(b);
    }
    io::write_csv(out / "envelope.csv", {"displacement_m", "stress_min_Pa", "stress_max_Pa"}, {grid, lo, hi});
    plot.series.push_back({.csv = out / "envelope.csv", .x_column = "displacement_m", .y_column = "stress_min_Pa",
                           .title = tessera::detail::concat("envelope of ", in.seeds, " tessellations: min"),
                           .style = "lines dt 2", .x_scale = 1e3, .y_scale = 1e-6});
    plot.series.push_back({.csv = out / "envelope.csv", .x_column = "displacement_m", .y_column = "stress_max_Pa",
                           .title = "max", .style = "lines dt 2", .x_scale = 1e3, .y_scale = 1e-6});
  }
  io::plot_png(out / "curve.png", plot);
}

/// Dissipated tension against the fracture energy (file comment of the block below).
struct fracture_figures {
  double expected_fracture = 0, fracture_error = 0, separation_energy = 0, broken_error = 0;
  std::string fracture_note;
};
fracture_figures fracture_of(const inputs& in, const scenes::prism_scene& scene, const scenes::tension_contacts& k,
                             const scenes::tension_result& r) {
  const real g_f = scene.G_f;
  // Fracture energy: tensile dissipation against G_f x (area broken in tension). For power
  // softening a sub-contact pulled to separation dissipates separation_energy = G_f +
  // f_T^2/(2 k_n) - cut-off tail per unit area (+2.3 % for 100 blocks), and sub-contacts off the
  // crack that softened without breaking add theirs; both are reported separately.
  // No crack fully opened (the run stopped before separation, e.g. --quick): no fracture-energy
  // figure; summary.json writes null and says why.
  const auto fracture = tessera::analysis::check_dissipation(r.dissipated_tension, g_f, r.crack_area);
  const double expected_fracture = fracture.expected, fracture_error = fracture.error_rel;
  const std::string fracture_note = fracture.defined() ? "dissipated tension against G_f x area broken in tension"
                                                       : "no crack fully opened (the run stopped before separation)";
  const double separation_energy =
      beam(in) ? k.separation_energy
      : in.softening == "power" ? tessera::law::power_softening::separation_energy(scene.contact.tension, scene.contact.k_n)
                              : tessera::law::linear_softening::separation_energy(
                                    tessera::law::with_linear_softening(scene.contact).tension, scene.contact.k_n);
  // The same for the sub-contacts broken in tension alone (null without any).
  const double broken_error =
      tessera::analysis::check_dissipation(r.dissipated_tension_broken, separation_energy, r.crack_area).error_rel;
  return {expected_fracture, fracture_error, separation_energy, broken_error, fracture_note};
}

/// summary.json (one key per line: the list is the file's schema, so it stays in one piece).
void write_summary(const fs::path& out, const inputs& in, const scenes::prism_scene& scene,
                   const scenes::tension_contacts& k, const std::vector<scenes::tension_result>& runs, const fracture_figures& fr,
                   const tessera::cli::wall_timer& timer) {
  namespace io = tessera::io;
  const auto& r = runs.front();
  const real f_t = scene.f_T, g_f = scene.G_f, area = scene.cross_section();
  const double separation_energy = fr.separation_energy, fracture_error = fr.fracture_error, broken_error = fr.broken_error;
  const std::string& fracture_note = fr.fracture_note;
  double peak_min = r.peak_stress, peak_max = r.peak_stress, peak_sum = 0;
  for (const auto& x : runs) {
    peak_min = std::min(peak_min, x.peak_stress);
    peak_max = std::max(peak_max, x.peak_stress);
    peak_sum += x.peak_stress;
  }
  io::summary_json js;
  js.set("example", "direct_tension")
      .set("blocks", beam(in) ? r.blocks : std::int64_t{in.blocks})
      .set("seed", in.common.seed)
      .set("seeds", in.seeds)
      .set("softening", beam(in) ? "linear" : in.softening)
      .set("cohesion", in.cohesion)
      .set("slip_breaks_tension", in.slip_breaks_tension)
      .set("cohesion_ratio", in.cohesion_ratio)
      .set("params", in.params)
      .set("strength_scale", beam(in) ? in.concrete.set.scale() : in.calibrated.strength_scale)
      .set("fracture_energy_scale",
           beam(in) ? in.concrete.set.fracture_energy_scale : in.calibrated.fracture_energy_scale)
      .set("rigid", in.rigid)
      .set("lloyd_iterations", in.lloyd)
      .set("regularize", in.regularize)
      .set("platen_restraint", in.loading.platen_restraint)
      .set("rate_m_per_s", in.loading.rate)
      .set("step_displacement_m", in.loading.dt > 0 ? in.loading.rate * in.loading.dt : in.loading.step_displacement)
      .set("quick", in.common.quick)
      .set("threads", tessera::max_threads())
      .set("length_m", scene.length())
      .set("cross_section_m2", area)
      .set("f_T_Pa", f_t)
      .set("G_f_N_per_m", g_f)
      .set("k_n_Pa_per_m", k.k_n)
      .set("peak_stress_Pa", r.peak_stress)
      .set("peak_error_rel", (r.peak_stress - f_t) / f_t)
      .set("peak_displacement_m", r.peak_displacement)
      .set("peak_stress_min_Pa", peak_min)
      .set("peak_stress_max_Pa", peak_max)
      .set("peak_stress_mean_Pa", peak_sum / static_cast<double>(runs.size()))
      .set("peak_normal_part_Pa", r.peak_normal_part)
      .set("peak_shear_part_Pa", r.peak_shear_part)
      .set("peak_crack_projected_area_over_cross_section", r.peak_crack_projected_area / area)
      .set("initial_modulus_Pa", r.initial_modulus)
      .set("initial_modulus_error_rel", (r.initial_modulus - scenes::concrete_young) / scenes::concrete_young)
      .set("residual_stress_Pa", r.residual_stress)
      .set("separated", r.separated)
      .set("separation_displacement_m", r.separation_displacement)
      .set("boundary_work_J", r.boundary_work)
      .set("dissipated_energy_J", r.dissipated)
      .set("dissipated_tension_J", r.dissipated_tension)
      .set("dissipated_shear_J", r.dissipated_shear)
      .set("dissipated_compression_J", r.dissipated_compression)
      .set("damping_dissipated_J", r.damping)
      .set("kinetic_energy_end_J", r.kinetic)
      .set("elastic_energy_end_J", r.stored)
      .set("dissipated_tension_at_peak_J", r.dissipated_tension_at_peak)
      .set("damping_dissipated_at_peak_J", r.damping_at_peak)
      .set("dissipated_tension_broken_J", r.dissipated_tension_broken)
      .set("dissipated_tension_process_zone_J", r.dissipated_tension_unbroken)
      .set("crack_area_m2", r.crack_area)
      .set("crack_projected_area_m2", r.projected_crack_area)
      .set("crack_area_over_cross_section", r.crack_area / area)
      .set("shear_crack_area_m2", r.shear_crack_area)
      .set("process_zone_area_m2", r.process_zone_area)
      .set("separation_energy_per_area_J_per_m2", separation_energy)
      .set("fracture_energy_error_rel", fracture_error)
      .set("fracture_energy_note", fracture_note)
      .set("broken_separation_energy_error_rel", broken_error)
      .set("energy_balance_error_rel", r.energy_balance_error)
      .set("kinetic_to_elastic_at_peak", r.kinetic_to_elastic_at_peak)
      .set("reaction_imbalance_max", r.reaction_imbalance_max)
      .set("subcontacts", r.subcontacts)
      .set("zones", r.zones)
      .set("gridpoints", r.gridpoints)
      .set("dt_s", r.dt)
      .set("added_mass_ratio", r.added_mass_ratio)
      .set("transit_time_s", r.transit_time)
      .set("ramp_time_s", r.ramp_time)
      .set("tail_speedup", in.loading.tail_speedup)
      .set("tail_start_displacement_m", r.tail_displacement)
      .set("steps", r.steps)
      .set("runtime_s", timer.seconds());
  scenes::set_concrete_figures(js, in.concrete, k,
                               r.separated ? r.dissipated / (area * g_f) : std::numeric_limits<double>::quiet_NaN());
  tessera::scenes::set_scheme_figures(js, in.scheme, in.loading.relax_increment, in.loading.relax_tolerance, r);
  tessera::scenes::set_phase_figures(js, r.phases, r.zones, r.subcontacts, r.steps);
  tessera::scenes::set_split_figures(js);
  js.write(out / "summary.json");
}

/// The first seed's figures on stdout, each beside its reference.
void print_report(const fs::path& out, const scenes::prism_scene& scene, const scenes::tension_result& r,
                  const fracture_figures& fr, const tessera::cli::wall_timer& timer) {
  const real f_t = scene.f_T, area = scene.cross_section();
  const double expected_fracture = fr.expected_fracture, fracture_error = fr.fracture_error;
  std::printf(
      "direct_tension: peak %.4f MPa (f_T %.4f MPa, error %+.2f %%; normal %.3f + shear %.3f MPa over the crack), "
      "E0 %.2f GPa\n  crack %.5f m^2 (%.2f x A, projected %.2f x A), separated %s; dissipated tension %.4f J "
      "(G_f x crack %.4f J, error %s; broken %.4f J, process zone %.4f J), shear %.4f J, damping %.4f J\n"
      "  energy balance error %.2e, kinetic/elastic at peak %.2e, reaction imbalance max %.2e f_T A\n"
      "  %lld sub-contacts, %lld zones, dt %.3g s (added mass %.1fx), ramp %.3g s, %lld steps, runtime %.1f s; wrote %s\n",
      r.peak_stress * 1e-6, f_t * 1e-6, 100 * (r.peak_stress - f_t) / f_t, r.peak_normal_part * 1e-6,
      r.peak_shear_part * 1e-6, r.initial_modulus * 1e-9, r.crack_area, r.crack_area / area,
      r.projected_crack_area / area, r.separated ? "yes" : "no", r.dissipated_tension, expected_fracture,
      std::isfinite(fracture_error) ? tessera::detail::concat(100 * fracture_error, " %").c_str() : "none, no crack fully opened",
      r.dissipated_tension_broken, r.dissipated_tension_unbroken, r.dissipated_shear, r.damping,
      r.energy_balance_error, r.kinetic_to_elastic_at_peak, r.reaction_imbalance_max, static_cast<long long>(r.subcontacts),
      static_cast<long long>(r.zones), r.dt, r.added_mass_ratio, r.ramp_time, static_cast<long long>(r.steps),
      timer.seconds(), out.string().c_str());
}

int run(inputs& in) {
  namespace io = tessera::io;
  const fs::path out = in.common.out;
  check_inputs(in);
  const tessera::cli::wall_timer timer;

  in.loading.on_start = [out] { io::ensure_directory(out); };  // the first run's checks have passed
  std::vector<scenes::tension_result> runs;
  scenes::prism_scene first_scene;
  scenes::tension_contacts contacts;  // the first seed's
  for (int k = 0; k < in.seeds; ++k) {
    const std::uint64_t seed = in.common.seed + static_cast<std::uint64_t>(k);
    scenes::prism_scene scene;
    scenes::tension_contacts kc;
    runs.push_back(run_one(in, seed, k == 0, scene, kc));
    if (k == 0) contacts = kc;
    io::ensure_directory(out);  // after the checks and the run's own (quasi-static rate): bad input leaves no directory
    const auto& r = runs.back();
    if (k == 0) first_scene = std::move(scene);
    std::printf("seed %llu: peak %.4f MPa at %.4f mm, E0 %.2f GPa, crack area %.5f m^2, separated %s, %lld steps, %.1f s\n",
                static_cast<unsigned long long>(seed), r.peak_stress * 1e-6, r.peak_displacement * 1e3,
                r.initial_modulus * 1e-9, r.crack_area, r.separated ? "yes" : "no", static_cast<long long>(r.steps),
                r.runtime_s);
    if (in.seeds > 1)
      io::write_csv(out / tessera::detail::concat("curve_seed", seed, ".csv"), {"displacement_m", "stress_Pa"},
                    {r.displacement, r.stress});
  }
  const auto& r = runs.front();
  const auto& scene = first_scene;
  write_curves(out, in, runs);
  scenes::write_tension_fields(out, scene, r);
  const fracture_figures fr = fracture_of(in, scene, contacts, r);
  write_summary(out, in, scene, contacts, runs, fr, timer);
  print_report(out, scene, r, fr, timer);
  std::printf("  %s concrete, %s law%s: peak / f_T %.4f, dissipated / (A G_f) %s\n", in.concrete.material.c_str(),
              beam(in) ? in.concrete.set.law.c_str() : "study",
              std::isnan(contacts.g_ii) ? "" : tessera::detail::concat(" (G_II ", contacts.g_ii, " J/m^2)").c_str(),
              r.peak_stress / scene.f_T,
              r.separated ? tessera::detail::concat(r.dissipated / (scene.cross_section() * scene.G_f)).c_str()
                          : "none (not separated)");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  tessera::scenes::mpi_session mpi(argc, argv);
  inputs in;
  auto& ld = in.loading;
  tessera::cli::parser cli(
      "direct_tension",
      "Plain-concrete prism (68 x 68 x 600 mm) pulled to complete separation (Pulatsu et al. 2020, Sec. 3):\n"
      "peak stress vs f_T = 2.15 MPa, fracture energy vs G_f x crack area, energy balance.\n"
      "--quick: 5 nm per step (peak +3 % against 2 nm), stopped at 70 % of the peak on the softening\n"
      "branch (no separation, so no fracture-energy figure); about 17 000 steps.\n"
      "--material beam: rc_beam's concrete on calibrate's 150 x 150 x 600 mm beam-recipe prism (f_T = 2.5 MPa, the\n"
      "recipe --recipe-blocks / --zone-edge) with any --law and its flags, as compression and brazilian take them;\n"
      "the run of calibrate --targets tension, to the bit.\n"
      "Under mpirun -np N (builds with MPI): the same run split over N ranks, the same curve.csv to the bit;\n"
      "rank 0 writes --out (not with --rigid or --material beam).");
  cli.add_standard(in.common);
  cli.option("--blocks", in.blocks, "number of blocks: 100, 250, 500 or 750 (Table 1 stiffnesses); --material beam: "
             "the prism's Voronoi blocks with the recipe's contacts (default: the recipe's block size, 155 for 250)", "N")
      .within(8, 5000);
  cli.option("--seeds", in.seeds, "number of random tessellations (seed, seed+1, ...); envelope of their curves", "K").within(1, 1000);
  cli.option("--softening", in.softening, "tensile softening: power (alpha = 3) or linear", "power|linear").one_of({"power", "linear"});
  cli.option("--cohesion", in.cohesion,
             "cohesion under tensile softening: decoupled (c_0 until broken, DESIGN.md) or coupled "
             "(c softens with f_t/f_T; power softening only)",
             "decoupled|coupled").one_of({"decoupled", "coupled"});
  cli.option("--cohesion-ratio", in.cohesion_ratio, "initial cohesion c_0 / f_T (c_res = 0.01 c_0)", "R").greater_than(0);
  cli.option("--params", in.params,
             "calibrated.json from examples/calibrate: prism, scale the contact strength (and G_f) by its entry for "
             "--blocks; beam, the whole concrete (law, scales, c_0/f_T, phi_0, phi_res, G_II, cap) of its entry for the "
             "recipe, instead of the concrete flags", "FILE");
  scenes::add_concrete_flags(cli, in.concrete);  // --material, --law, --g-ii, ..., --recipe-blocks, --zone-edge
  cli.flag("--slip-breaks-tension", in.slip_breaks_tension,
           "a contact that fails in shear is broken in tension too (3DEC/YADE brittle joints; DESIGN.md keeps its tension)");
  cli.option("--scheme", in.scheme,
             "explicit: central differences with local damping along a ramped pull (the study's scheme); "
             "relaxation: kinetic dynamic relaxation, the top moved in increments each relaxed to static "
             "equilibrium (docs/guide.md; not with --rigid or under mpirun)",
             "explicit|relaxation").one_of({"explicit", "relaxation"});
  cli.option("--relax-increment", ld.relax_increment, "with --scheme relaxation: top displacement per increment (m)", "M")
      .greater_than(0);
  cli.option("--relax-tolerance", ld.relax_tolerance,
             "with --scheme relaxation: an increment is relaxed once the largest nodal unbalanced force is at most "
             "this x f_T A",
             "R").greater_than(0).at_most(1);
  cli.option("--rate", ld.rate, "top velocity after the ramp (m/s)", "V").greater_than(0);
  cli.flag("--rigid", in.rigid, "rigid blocks instead of deformable semi-rigid ones");
  cli.option("--step-displacement", ld.step_displacement,
             "top displacement per step (m): mass-scaling target dt* = this / rate", "DU").greater_than(0);
  cli.option("--dt", ld.dt, "mass-scaling target step (s); overrides --step-displacement (0 = use it)", "DT").at_least(0);
  cli.option("--ramp-transits", ld.ramp_transits, "half-cosine velocity ramp, in axial wave-transit times", "N").at_least(0);
  cli.option("--tail-speedup", ld.tail_speedup, "velocity factor on the softening tail (stress < 0.3 x peak)", "F").at_least(1);
  cli.option("--max-displacement", ld.max_displacement, "stop at this top displacement (m) if not separated", "U").greater_than(0);
  cli.option("--sample", ld.sample, "steps between curve samples", "K").at_least(1);
  bool free_platen = false;
  cli.flag("--free-platen", free_platen, "top gridpoints free transversally (frictionless platen; diagnostic)");
  cli.option("--lloyd", in.lloyd, "Lloyd relaxation steps of the tessellation (0 = plain Voronoi)", "K").within(0, 1000);
  cli.option("--regularize", in.regularize,
             "collapse Voronoi edges shorter than REL x mean cell size (0 = off; 0.2 = presets::study_regularization)",
             "REL").within(0, tessera::geometry::max_regularization);
  cli.parse_or_exit(argc, argv);
  in.phi_given = cli.given("--phi-deg"), in.phi_res_given = cli.given("--phi-res-deg");
  if (in.concrete.material == "beam" && !cli.given("--blocks")) in.blocks = 0;  // the recipe's block size
  try {
    scenes::require_concrete_flags(cli, in.concrete, in.params);
  } catch (const std::exception& e) {
    tessera::cli::print_error("direct_tension", e);
    return 2;
  }
  ld.platen_restraint = !free_platen;
  ld.relaxation = in.scheme == "relaxation";
  for (const char* f : {"--rate", "--step-displacement", "--dt", "--ramp-transits", "--tail-speedup", "--sample"})
    if (cli.given(f)) in.explicit_flags_given.emplace_back(f);
  for (const char* f : {"--relax-increment", "--relax-tolerance"})
    if (cli.given(f)) in.relax_flags_given.emplace_back(f);
  if (in.common.quick) {  // reduced run; a value given on the command line is kept
    if (!cli.given("--step-displacement") && !cli.given("--dt")) ld.step_displacement = 5e-9;
    ld.stop_at_separation = false;
    ld.stop_below_peak_ratio = 0.7;
    if (!cli.given("--max-displacement")) ld.max_displacement = std::min(ld.max_displacement, 2e-4);
  }
  // run.json is written when the output directory is created (after the checks), listing each
  // file as it is written; "complete" after summary.json, "interrupted" on SIGINT/SIGTERM.
  try {
    if (in.rigid) mpi.require_splittable(false, "direct_tension --rigid");
    if (in.concrete.material == "beam")
      mpi.require_splittable(false, "direct_tension --material beam", "the beam's concrete is run as one process only");
    if (ld.relaxation)
      mpi.require_splittable(false, "direct_tension --scheme relaxation", "kinetic relaxation is not distributed");
    mpi.require_splittable(true, "direct_tension");
  } catch (const std::exception& e) {
    if (mpi.rank() == 0) tessera::cli::print_error("direct_tension", e);
    return 2;
  }
  mpi.route_output(in.common.out);  // under mpirun: rank 0 writes --out
  tessera::io::run_record record(in.common.out, "direct_tension", argc, argv);
  try {
    const int status = run(in);
    if (status == 0) record.complete();
    return status;
  } catch (const std::exception& e) {
    tessera::cli::print_error("direct_tension", e);
    return 1;
  }
}
