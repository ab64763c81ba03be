// work_precision_tension: error against run time for the plain-concrete direct tension test
// (issue 3, "Error against run time"; the scene and its loading are direct_tension/tension_test.hpp).
//
// Each variant runs the prism from rest to a top displacement u_max that covers the elastic
// branch, the peak and the first softening (0.15 mm; --quick 0.11 mm), and is compared with a
// reference run of the same tessellation and block count:
//     curve_error_rel = sqrt( (1/u_max) int_0^u_max (sigma - sigma_ref)^2 du ) / max sigma_ref
// (scenes::curve_error_rel), next to its wall time and number of steps. The accuracy knobs:
//   - displacement per step du* (the mass-scaling target dt* = du*/rate): the inertia of a
//     mass-scaled quasi-static run is set by du* alone (tension_test.hpp);
//   - loading rate at a fixed du* (more or less physical mass left unscaled);
//   - block count (its own reference: a different model, not a finer one);
//   - mass scaling off: the physical stable step is tiny (sliver zones), so the run is not made;
//     its step count is estimated from the stable step and reported with wall time = estimate
//     (steps x measured time per step of the reference);
//   - rigid vs deformable blocks: the same tessellation with rigid 6-DOF blocks (blocks::rigid),
//     compared with the deformable reference of its block count (so its error includes the
//     modelling difference, not only the discretisation).
// Writes DIR/work_precision_tension.csv and DIR/work_precision_tension.png (curve error against
// wall time, log-log). Wall times are measured on a shared machine: compare them within one
// table only.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "common/cli.hpp"
#include "common/scenes.hpp"
#include "direct_tension/tension_test.hpp"
#include "tessera/io/atomic_file.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/plot.hpp"
#include "tessera/solver.hpp"

namespace {

using tessera::real;
namespace fs = std::filesystem;
namespace scenes = tessera::scenes;

struct variant {
  std::string name;
  int blocks = 100;
  real rate = 0.005;               // m/s
  real step_displacement = 2e-9;   // m
  bool mass_scaling = true;
  bool reference = false;          // the reference of its block count
  bool rigid = false;              // rigid 6-DOF blocks instead of deformable ones
};

struct row {
  variant v;
  scenes::tension_result r;
  real curve_error = 0, peak_difference = 0, wall_s = 0;
  bool estimated = false;
};

// The variants of the table (the first of each block count is its reference).
std::vector<variant> variants_for(bool quick) {
  if (quick)
    return {{"ref_100_2nm", 100, 0.005, 2e-9, true, true},
            {"du_5nm", 100, 0.005, 5e-9, true, false},
            {"du_10nm", 100, 0.005, 1e-8, true, false},
            {"du_20nm", 100, 0.005, 2e-8, true, false},
            {"rigid_du_5nm", 100, 0.005, 5e-9, true, false, true},
            {"no_mass_scaling", 100, 0.005, 2e-9, false, false}};
  return {{"ref_100_1nm", 100, 0.005, 1e-9, true, true},
          {"du_2nm", 100, 0.005, 2e-9, true, false},
          {"du_5nm", 100, 0.005, 5e-9, true, false},
          {"du_10nm", 100, 0.005, 1e-8, true, false},
          {"du_20nm", 100, 0.005, 2e-8, true, false},
          {"rate_20mm_du_2nm", 100, 0.02, 2e-9, true, false},
          {"rate_1mm_du_2nm", 100, 0.001, 2e-9, true, false},
          {"rigid_du_2nm", 100, 0.005, 2e-9, true, false, true},
          {"rigid_du_5nm", 100, 0.005, 5e-9, true, false, true},
          {"no_mass_scaling", 100, 0.005, 2e-9, false, false},
          {"ref_250_2nm", 250, 0.005, 2e-9, true, true},
          {"b250_du_5nm", 250, 0.005, 5e-9, true, false},
          {"b250_du_10nm", 250, 0.005, 1e-8, true, false}};
}

// Runs one variant (or, without mass scaling, estimates its cost from the physical stable step
// and the reference's time per step; the ramp is ignored) and prints its line.
row run_variant(const variant& v, const scenes::prism_scene& scene, const row* ref, real u_max, int threads) {
  row w{v, {}, 0, 0, 0, false};
  scenes::tension_loading ld;
  ld.rate = v.rate;
  ld.step_displacement = v.step_displacement;
  ld.max_displacement = u_max;
  ld.stop_at_separation = false;
  ld.threads = threads;
  ld.label = v.name;
  if (!v.mass_scaling) {
    tessera::solver_options opt;
    const tessera::prism_solver probe(scene.tess, scene.mesh, scene.block_material, scene.contact, {}, opt);
    w.r.dt = probe.dt();
    w.r.steps = static_cast<std::int64_t>(u_max / (v.rate * probe.dt()));
    w.estimated = true;
    const real per_step = ref != nullptr && ref->r.steps > 0 ? ref->wall_s / static_cast<real>(ref->r.steps) : 0;
    w.wall_s = per_step * static_cast<real>(w.r.steps);
    std::printf("%-18s not run: physical stable step %.3g s -> %lld steps, about %.0f s\n", v.name.c_str(), w.r.dt,
                static_cast<long long>(w.r.steps), w.wall_s);
    return w;
  }
  const tessera::cli::wall_timer timer;
  w.r = v.rigid ? scenes::run_direct_tension<tessera::rigid_prism_solver>(scene, scene.contact, ld)
                : scenes::run_direct_tension<tessera::prism_solver>(scene, scene.contact, ld);
  w.wall_s = timer.seconds();
  const row& against = (v.reference || ref == nullptr || ref->v.blocks != v.blocks) ? w : *ref;
  if (&against != &w) {
    w.curve_error = scenes::curve_error_rel(w.r.displacement, w.r.stress, against.r.displacement, against.r.stress, u_max);
    w.peak_difference = (w.r.peak_stress - against.r.peak_stress) / against.r.peak_stress;
  }
  std::printf("%-18s %8lld steps %7.1f s  dt %.3g s  added mass %5.1fx  peak %.4f MPa  curve error %.4f  peak vs ref %+.4f\n",
              v.name.c_str(), static_cast<long long>(w.r.steps), w.wall_s, w.r.dt, w.r.added_mass_ratio,
              w.r.peak_stress * 1e-6, w.curve_error, w.peak_difference);
  std::fflush(stdout);
  return w;
}

// One CSV row per variant.
void write_table(const fs::path& file_path, const std::vector<row>& rows, real f_t) {
  tessera::io::atomic_ofstream file(file_path);
  std::ostream& os = file.stream();
  os << "variant,blocks,blocks_model,rate_m_per_s,step_displacement_m,mass_scaling,dt_s,added_mass_ratio,steps,wall_s,"
        "estimated,peak_Pa,peak_error_rel,peak_vs_reference_rel,curve_error_rel\n";
  os.precision(6);
  for (const row& x : rows)
    os << x.v.name << ',' << x.v.blocks << ',' << (x.v.rigid ? "rigid" : "deformable") << ',' << x.v.rate << ',' << x.v.step_displacement << ','
       << (x.v.mass_scaling ? 1 : 0) << ',' << x.r.dt << ',' << x.r.added_mass_ratio << ',' << x.r.steps << ','
       << x.wall_s << ',' << (x.estimated ? 1 : 0) << ',' << x.r.peak_stress << ','
       << (x.estimated ? 0.0 : (x.r.peak_stress - f_t) / f_t) << ',' << x.peak_difference << ',' << x.curve_error
       << '\n';
  file.commit();
}

// The log-log plot: one point per measured non-reference variant, one series per block model.
void write_plot(const fs::path& out, const std::vector<row>& rows) {
  tessera::io::plot_spec plot;
  plot.title = "Direct tension: curve error vs wall time (reference rows and estimates excluded)";
  plot.xlabel = "wall time (s)";
  plot.ylabel = "L2 curve error / reference peak";
  plot.log_x = true;
  plot.log_y = true;
  for (const bool rigid : {false, true}) {
    const std::string name = rigid ? "work_precision_tension_points_rigid.csv" : "work_precision_tension_points.csv";
    tessera::io::csv_writer pts(out / name, {"wall_s", "curve_error"});
    int n = 0;
    for (const row& x : rows)
      if (x.v.rigid == rigid && !x.v.reference && !x.estimated && x.curve_error > 0) {
        pts.row(x.wall_s, x.curve_error);
        ++n;
      }
    pts.commit();
    if (n > 0)
      plot.series.push_back({.csv = out / name, .x_column = "wall_s", .y_column = "curve_error",
                             .title = rigid ? "rigid blocks" : "deformable blocks",
                             .style = rigid ? "points pt 5 ps 1.5" : "points pt 7 ps 1.5"});
  }
  tessera::io::plot_png(out / "work_precision_tension.png", plot);
}

}  // namespace

int main(int argc, char** argv) {
  tessera::cli::standard_options common;
  tessera::cli::parser cli("work_precision_tension",
                           "Direct tension (100 and 250 blocks): curve error against a reference run vs wall time,\n"
                           "for displacement per step (mass scaling), loading rate, block count, mass scaling off.\n"
                           "--quick: 100 blocks only, reference at 2 nm per step, to 0.11 mm.");
  cli.add_standard(common);
  if (common.out.empty()) common.out = "results/work_precision_tension";
  cli.parse_or_exit(argc, argv);
  try {
    const fs::path out = common.out;
    tessera::io::ensure_directory(out);
    const real u_max = common.quick ? 1.1e-4 : 1.5e-4;
    const std::vector<variant> variants = variants_for(common.quick);
    std::vector<row> rows;
    rows.reserve(variants.size());  // no reallocation: `ref` stays valid
    const row* ref = nullptr;
    scenes::prism_scene scene;
    int scene_blocks = 0;
    for (const variant& v : variants) {
      if (v.blocks != scene_blocks) {
        scenes::prism_options po;
        po.blocks = v.blocks;
        po.seed = common.seed;
        scene = scenes::make_prism(po);
        scene_blocks = v.blocks;
      }
      rows.push_back(run_variant(v, scene, ref, u_max, common.threads));
      if (v.reference) ref = &rows.back();
    }
    write_table(out / "work_precision_tension.csv", rows, scene.f_T);
    write_plot(out, rows);
    std::printf("wrote %s\n", (out / "work_precision_tension.csv").string().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "work_precision_tension: " << e.what() << '\n';
    return 1;
  }
}
