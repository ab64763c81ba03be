// direct_tension: the reference study's plain-concrete prism pulled to complete separation
// (Pulatsu et al. 2020, Sec. 3; DESIGN.md §4).
//
// Experiment:
//   specimen  68 x 68 x 600 mm prism (long axis z), N random Voronoi blocks (--blocks 100|250|500|750)
//   blocks    deformable, semi-rigid: E_block = 10 x 28 GPa, nu = 0.2, rho = 2400 kg/m^3
//   contacts  Table 1 k_n, k_s for N; f_T = 2.15 MPa, G_f = 60 N/m, c_0 = 2 f_T, phi_0 = 35 deg;
//             power (alpha = 3, default) or linear softening (--softening)
//   supports  bottom gridpoints (z = 0) fixed; top gridpoints (z = 0.6 m) fixed transversally
//             (no rotation) and pulled along z at --rate
//   solver    central differences, local damping gamma = 0.8, masses scaled to the step --dt
//
// Outputs in --out DIR: curve.csv (top displacement m, mean axial stress Pa), contacts_peak.vtp
// and contacts_end.vtp (sub-contacts with damage, opening, normal stress, status), zones_end.vtu
// (zones with displacement and stress), curve.png, summary.json (peak stress and its error
// against f_T, initial modulus, dissipated energy, crack area, fracture-energy error, energy
// balance error, sizes, steps, runtime_s). With --seeds K > 1: curve_seed<S>.csv per
// tessellation and envelope.csv (min/max stress over the seeds on a common displacement grid).
#include <algorithm>
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
#include "tessera/io/atomic_file.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/plot.hpp"
#include "tessera/io/vtk.hpp"
#include "tessera/solver.hpp"

namespace {

using tessera::real;
using tessera::vec3;
namespace fs = std::filesystem;

struct inputs {
  tessera::cli::standard_options common;
  int blocks = 100;
  double rate = 0.005;            // m/s, top velocity
  std::string softening = "power";
  bool rigid = false;
  int seeds = 1;
  double dt = 1e-6;               // s, mass-scaled time step (0 = unscaled stable step)
  double max_displacement = 1e-3; // m, stop here if not separated before
  int sample = 100;               // steps between curve samples
  double ramp = 2e-3;             // s, the top velocity rises linearly from 0 to --rate over this time
};

/// Per-sub-contact snapshot for the VTK output.
struct contact_snapshot {
  std::vector<vec3> position;
  std::vector<double> damage, opening, sigma_n;
  std::vector<std::int32_t> status;
  template <class Solver>
  void take(const Solver& s) {
    const auto& c = s.contacts();
    using law = typename Solver::law_type;
    const auto n = static_cast<std::size_t>(c.size());
    position.resize(n);
    damage.resize(n);
    opening.resize(n);
    sigma_n.resize(n);
    status.resize(n);
    for (tessera::index i = 0; i < c.size(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      const auto& st = c.state(i);
      position[k] = c.position(i, s.gridpoints());
      damage[k] = law::tensile_damage(c.params(), st);
      opening[k] = st.u_n;
      sigma_n[k] = st.sigma_n;
      status[k] = static_cast<std::int32_t>(law::status(st));
    }
  }
  void write(const fs::path& path) const {
    tessera::io::vtk::poly_data pd;
    pd.set_points(position);
    for (tessera::index i = 0; i < static_cast<tessera::index>(position.size()); ++i) pd.add_vertex(i);
    pd.point_data.add_scalar("damage", std::span<const double>(damage));
    pd.point_data.add_scalar("opening_m", std::span<const double>(opening));
    pd.point_data.add_scalar("sigma_n_Pa", std::span<const double>(sigma_n));
    pd.point_data.add_scalar("status", std::span<const std::int32_t>(status));
    pd.write(path);
  }
};

struct run_result {
  std::vector<double> displacement, stress;  // m, Pa
  double peak_stress = 0, peak_displacement = 0, initial_modulus = 0;
  double dissipated = 0, dissipated_tension = 0, crack_area = 0, damping = 0;
  double energy_balance_error = 0, boundary_work = 0;
  double dt = 0, added_mass_ratio = 0;
  std::int64_t steps = 0, subcontacts = 0, zones = 0, gridpoints = 0;
  double runtime_s = 0;
};

/// Slope of stress against strain u/L over the pre-peak samples between 10 % and 50 % of the peak.
double initial_modulus(const run_result& r, double length) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t k = 0; k < r.stress.size() && r.displacement[k] <= r.peak_displacement; ++k) {
    if (r.stress[k] < 0.1 * r.peak_stress || r.stress[k] > 0.5 * r.peak_stress) continue;
    const double x = r.displacement[k] / length, y = r.stress[k];
    sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
  }
  if (n < 2) return 0;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

template <class Solver, class LawParams>
run_result run_prism(const tessera::scenes::prism_scene& scene, const LawParams& law_params, const inputs& in,
                     const fs::path& out, bool write_fields, const std::string& label) {
  namespace bc = tessera::bc;
  namespace rec = tessera::recorders;
  const tessera::cli::wall_timer timer;
  tessera::solver_options opt;
  opt.mass_scaling_dt = in.dt;
  opt.threads = in.common.threads;
  Solver s(scene.tess, scene.mesh, scene.block_material, law_params, {}, opt);

  const real length = scene.length(), area = scene.cross_section(), f_t = law_params.tension.f_T;
  const real tol = 1e-9 * length;
  s.fix(s.gridpoints_on_plane(2, 0.0, tol));
  const bc::node_group top = s.gridpoints_on_plane(2, length, tol);
  s.fix(top, bc::transverse_to(2));
  // Smooth start: a sudden velocity would send a stress wave through the (mass-scaled) prism.
  s.prescribe_velocity(top, vec3::Zero(), bc::components::z);
  const auto ramp = [&](const Solver& sv) {
    if (sv.time() <= in.ramp + sv.dt())
      bc::update_velocity(s.gridpoints(), top, vec3(0, 0, in.rate * std::min(1.0, sv.time() / in.ramp)), bc::components::z);
  };

  run_result r;
  contact_snapshot at_peak;
  tessera::cli::progress_line progress(label);
  bool separated = false;
  const auto observe = [&](const Solver& sv) {
    const real u = rec::mean_displacement(sv.gridpoints(), top).z();
    const real sigma = rec::reaction_sum(sv.gridpoints(), top).z() / area;  // mean axial stress, tension +
    r.displacement.push_back(u);
    r.stress.push_back(sigma);
    if (sigma > r.peak_stress) {
      r.peak_stress = sigma;
      r.peak_displacement = u;
      if (write_fields) at_peak.take(sv);
    }
    // Complete separation: well past the peak and the stress gone (below the power law's residual).
    separated = u > 2 * r.peak_displacement && r.peak_stress > 0.5 * f_t && std::abs(sigma) < 2e-3 * f_t;
    progress.update(std::min(1.0, u / in.max_displacement),
                    tessera::detail::concat("u = ", u * 1e3, " mm, sigma = ", sigma * 1e-6, " MPa, peak ",
                                            r.peak_stress * 1e-6, " MPa"));
  };
  const auto done = [&](const Solver& sv) {
    return separated || rec::mean_displacement(sv.gridpoints(), top).z() >= in.max_displacement;
  };
  s.run_until(done, std::int64_t{1} << 40, ramp, rec::every(in.sample, observe));
  progress.finish();

  const auto e = s.energies();
  r.dissipated = e.contact_dissipated;
  r.dissipated_tension = e.contact_dissipated_tension;
  r.damping = e.damping_dissipated;
  r.boundary_work = e.boundary_work;
  r.energy_balance_error = e.error_rel();
  r.crack_area = s.contacts().broken_area();
  r.initial_modulus = initial_modulus(r, length);
  r.dt = s.dt();
  r.added_mass_ratio = s.mass_scaling().original_mass > 0 ? s.mass_scaling().added_mass / s.mass_scaling().original_mass : 0;
  r.steps = s.step_count();
  r.subcontacts = s.contacts().size();
  r.zones = scene.mesh.zone_count();
  r.gridpoints = scene.mesh.gridpoint_count();
  r.runtime_s = timer.seconds();

  if (write_fields) {
    at_peak.write(out / "contacts_peak.vtp");
    contact_snapshot at_end;
    at_end.take(s);
    at_end.write(out / "contacts_end.vtp");
    std::vector<tessera::io::vtk::sym_tensor> stress;
    const auto& zs = s.blocks().zone_stress();
    for (Eigen::Index z = 0; z < zs.rows(); ++z) stress.push_back({zs(z, 0), zs(z, 1), zs(z, 2), zs(z, 5), zs(z, 3), zs(z, 4)});
    tessera::io::vtk::zone_fields fields;
    fields.displacement = &s.gridpoints().displacement;
    fields.stress = stress;
    tessera::io::vtk::write_zones_vtu(out / "zones_end.vtu", scene.mesh, fields);
  }
  return r;
}

int run(const inputs& in) {
  namespace io = tessera::io;
  const fs::path out = in.common.out;
  io::ensure_directory(out);
  tessera::require(in.rate > 0, "direct_tension: --rate ", in.rate, " m/s must be > 0");
  tessera::require(in.seeds >= 1, "direct_tension: --seeds ", in.seeds, " must be >= 1");
  tessera::require(in.softening == "power" || in.softening == "linear", "direct_tension: --softening '", in.softening,
                   "' must be 'power' or 'linear'");
  tessera::require(!in.rigid, "direct_tension: --rigid is not available yet (blocks::rigid is unfinished)");
  const tessera::cli::wall_timer timer;

  std::vector<run_result> runs;
  double f_t = 0, g_f = 0, length = 0, area = 0;
  for (int k = 0; k < in.seeds; ++k) {
    tessera::scenes::prism_options po;
    po.blocks = in.blocks;
    po.seed = in.common.seed + static_cast<std::uint64_t>(k);
    const auto scene = tessera::scenes::make_prism(po);
    f_t = scene.contact.tension.f_T;
    g_f = scene.contact.tension.G_f;
    length = scene.length();
    area = scene.cross_section();
    const std::string label = tessera::detail::concat("direct_tension seed ", po.seed);
    if (in.softening == "power")
      runs.push_back(run_prism<tessera::prism_solver>(scene, scene.contact, in, out, k == 0, label));
    else
      runs.push_back(run_prism<tessera::prism_linear_solver>(scene, tessera::scenes::linear_softening_params(scene.contact),
                                                             in, out, k == 0, label));
    const run_result& r = runs.back();
    std::printf("seed %llu: peak %.4f MPa at %.4f mm, E0 %.2f GPa, crack area %.5f m^2, %lld steps, %.1f s\n",
                static_cast<unsigned long long>(po.seed), r.peak_stress * 1e-6, r.peak_displacement * 1e3,
                r.initial_modulus * 1e-9, r.crack_area, static_cast<long long>(r.steps), r.runtime_s);
    if (in.seeds > 1)
      io::write_csv(out / tessera::detail::concat("curve_seed", po.seed, ".csv"), {"displacement_m", "stress_Pa"},
                    {r.displacement, r.stress});
  }
  const run_result& r = runs.front();
  io::write_csv(out / "curve.csv", {"displacement_m", "stress_Pa"}, {r.displacement, r.stress});

  double peak_min = r.peak_stress, peak_max = r.peak_stress, peak_sum = 0;
  for (const auto& x : runs) {
    peak_min = std::min(peak_min, x.peak_stress);
    peak_max = std::max(peak_max, x.peak_stress);
    peak_sum += x.peak_stress;
  }
  io::plot_spec plot;
  plot.title = tessera::detail::concat("Direct tension, ", in.blocks, " blocks, ", in.softening, " softening");
  plot.xlabel = "displacement (mm)";
  plot.ylabel = "mean axial stress (MPa)";
  if (in.seeds > 1) {
    // Envelope on a common displacement grid (linear interpolation of each curve).
    double u_max = 1e300;
    for (const auto& x : runs) u_max = std::min(u_max, x.displacement.empty() ? 0.0 : x.displacement.back());
    std::vector<double> grid, lo, hi;
    for (int i = 0; i <= 400; ++i) grid.push_back(u_max * i / 400.0);
    for (double u : grid) {
      double a = 1e300, b = -1e300;
      for (const auto& x : runs) {
        const auto it = std::lower_bound(x.displacement.begin(), x.displacement.end(), u);
        const std::size_t j = std::min<std::size_t>(static_cast<std::size_t>(it - x.displacement.begin()), x.displacement.size() - 1);
        double v = x.stress[j];
        if (j > 0 && x.displacement[j] != x.displacement[j - 1]) {
          const double t = (u - x.displacement[j - 1]) / (x.displacement[j] - x.displacement[j - 1]);
          v = x.stress[j - 1] + std::clamp(t, 0.0, 1.0) * (x.stress[j] - x.stress[j - 1]);
        }
        a = std::min(a, v), b = std::max(b, v);
      }
      lo.push_back(a), hi.push_back(b);
    }
    io::write_csv(out / "envelope.csv", {"displacement_m", "stress_min_Pa", "stress_max_Pa"}, {grid, lo, hi});
    plot.series.push_back({.csv = out / "envelope.csv", .x_column = "displacement_m", .y_column = "stress_min_Pa",
                           .title = "envelope min", .style = "lines dt 2", .x_scale = 1e3, .y_scale = 1e-6});
    plot.series.push_back({.csv = out / "envelope.csv", .x_column = "displacement_m", .y_column = "stress_max_Pa",
                           .title = "envelope max", .style = "lines dt 2", .x_scale = 1e3, .y_scale = 1e-6});
  }
  plot.series.insert(plot.series.begin(), {.csv = out / "curve.csv", .x_column = "displacement_m", .y_column = "stress_Pa",
                                           .title = "tessera", .x_scale = 1e3, .y_scale = 1e-6});
  io::plot_png(out / "curve.png", plot);

  // Fracture energy: tensile dissipation of the contacts against G_f x broken (crack) area.
  const double expected_fracture = g_f * r.crack_area;
  const double fracture_error = expected_fracture > 0 ? std::abs(r.dissipated_tension - expected_fracture) / expected_fracture : 1.0;
  io::summary_json js;
  js.set("example", "direct_tension")
      .set("blocks", in.blocks)
      .set("seed", in.common.seed)
      .set("seeds", in.seeds)
      .set("softening", in.softening)
      .set("rigid", in.rigid)
      .set("rate_m_per_s", in.rate)
      .set("quick", in.common.quick)
      .set("threads", tessera::max_threads())
      .set("length_m", length)
      .set("cross_section_m2", area)
      .set("f_T_Pa", f_t)
      .set("G_f_N_per_m", g_f)
      .set("peak_stress_Pa", r.peak_stress)
      .set("peak_error_rel", std::abs(r.peak_stress - f_t) / f_t)
      .set("peak_displacement_m", r.peak_displacement)
      .set("peak_stress_min_Pa", peak_min)
      .set("peak_stress_max_Pa", peak_max)
      .set("peak_stress_mean_Pa", peak_sum / static_cast<double>(runs.size()))
      .set("initial_modulus_Pa", r.initial_modulus)
      .set("initial_modulus_error_rel", std::abs(r.initial_modulus - tessera::scenes::concrete_young) / tessera::scenes::concrete_young)
      .set("dissipated_energy_J", r.dissipated)
      .set("dissipated_tension_J", r.dissipated_tension)
      .set("damping_dissipated_J", r.damping)
      .set("boundary_work_J", r.boundary_work)
      .set("crack_area_m2", r.crack_area)
      .set("crack_area_over_cross_section", r.crack_area / area)
      .set("fracture_energy_error_rel", fracture_error)
      .set("energy_balance_error_rel", r.energy_balance_error)
      .set("subcontacts", r.subcontacts)
      .set("zones", r.zones)
      .set("gridpoints", r.gridpoints)
      .set("dt_s", r.dt)
      .set("added_mass_ratio", r.added_mass_ratio)
      .set("steps", r.steps)
      .set("runtime_s", timer.seconds());
  js.write(out / "summary.json");
  std::printf("direct_tension: peak %.4f MPa (f_T %.4f MPa, error %.2f %%), E0 %.2f GPa, fracture energy error %.2f %%, "
              "energy balance error %.3f %%\n  %lld sub-contacts, %lld zones, dt %.3g s, %lld steps, runtime %.1f s; wrote %s\n",
              r.peak_stress * 1e-6, f_t * 1e-6, 100 * std::abs(r.peak_stress - f_t) / f_t, r.initial_modulus * 1e-9,
              100 * fracture_error, 100 * r.energy_balance_error, static_cast<long long>(r.subcontacts),
              static_cast<long long>(r.zones), r.dt, static_cast<long long>(r.steps), timer.seconds(), out.string().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  inputs in;
  tessera::cli::parser cli("direct_tension",
                           "Plain-concrete prism (68 x 68 x 600 mm) pulled to complete separation\n"
                           "(Pulatsu et al. 2020, Sec. 3): peak stress vs f_T = 2.15 MPa, fracture energy.");
  cli.add_standard(in.common);
  cli.option("--blocks", in.blocks, "number of blocks: 100, 250, 500 or 750 (Table 1 stiffnesses)", "N");
  cli.option("--rate", in.rate, "top velocity (m/s)", "V");
  cli.option("--softening", in.softening, "tensile softening: power (alpha = 3) or linear", "power|linear");
  cli.flag("--rigid", in.rigid, "rigid blocks instead of deformable semi-rigid ones");
  cli.option("--seeds", in.seeds, "number of random tessellations (seed, seed+1, ...); envelope of their curves", "K");
  cli.option("--dt", in.dt, "mass-scaled time step (s); 0 = stable step of the unscaled masses", "DT");
  cli.option("--max-displacement", in.max_displacement, "stop at this top displacement (m) if not separated", "U");
  cli.option("--sample", in.sample, "steps between curve samples", "K");
  cli.option("--ramp", in.ramp, "time over which the top velocity rises from 0 to --rate (s)", "T");
  cli.parse_or_exit(argc, argv);
  if (in.common.quick) {
    in.rate = std::max(in.rate, 0.01);
    in.dt = std::max(in.dt, 1e-6);
    in.max_displacement = std::min(in.max_displacement, 2e-4);
  }
  try {
    return run(in);
  } catch (const std::exception& e) {
    std::cerr << "direct_tension: " << e.what() << '\n';
    return 1;
  }
}
