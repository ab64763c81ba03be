// rocking: free rocking of a rectangular rigid block (Housner 1963). A block of width 2b and height
// 2h (default h = 4 b, alpha = atan(b/h) = 14.0 deg), tilted by --tilt x alpha about its right
// bottom edge and released on a fixed base: it rocks from one bottom edge to the other, losing
// energy at each impact. Housner's closed form, from angular momentum about the new edge
// (I_O = 4/3 m R^2, R = sqrt(b^2 + h^2)): r = omega_after / omega_before = 1 - 3/2 sin^2(alpha).
// Measured from the amplitudes theta_k of successive half-cycles (energy before and after each
// impact): r_k^2 = (cos(alpha - theta_k+1) - cos alpha) / (cos(alpha - theta_k) - cos alpha), and
// from the peak angular velocities on either side of each impact. Undamped, dry joint, detected
// contacts: the impact is an undamped penalty spring, elastic, where Housner's is plastic, so r
// differs from his by a few per cent and depends on k_n (summary.json says so: "impact_model").
// Outputs in --out: run.json, curve.csv (step, t_s, tilt_rad, omega_rad_per_s every 1 ms),
// summary.json (r measured and Housner's, error_rel, per impact, energies, steps). Exit 0/1/2.
#include <tessera/io/run_record.hpp>
#include <tessera/tessera.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>
using namespace tessera;
using contacts = contact::detected_contacts<law::dry_joint_law>;
using model = solver<blocks::rigid, contacts, reinforcement::none, integrator::central_difference<integrator::no_damping>>;

int main(int argc, char** argv) {
  std::string out = "results/rocking";
  bool quick = false;
  real aspect = 4, tilt0 = 0.5, k = 1e9, safety = 0.8, duration = 3, b = 0.1, threads = 0;  // h/b, theta_0/alpha, Pa/m, -, s, m
  real tolerance = 0.002, interval = 1000, edge_pieces = 1, width_pieces = 1;  // tolerance / b, steps, base pieces
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto number = [&](real lo, real hi) {
      const char* v = i + 1 < argc ? argv[++i] : "";
      char* end = nullptr;  // the number must be the whole argument
      const real x = std::strtod(v, &end);
      if (*v != 0 && *end == 0 && x >= lo && x <= hi) return x;
      std::fprintf(stderr, "rocking: %s = '%s' must be a number in [%g, %g]\n", a.c_str(), v, lo, hi);
      std::exit(2);
    };
    if (a == "--help")
      return std::puts("rocking [--out DIR] [--quick] [--aspect h/b 1.5..20] [--tilt theta0/alpha 0.05..0.95] [--kn 1e6..1e13 Pa/m]\n"
                       "  [--safety 0.05..1] [--duration 0.2..60 s] [--threads 0..256] [--tolerance 1e-4..0.05 (x b)]\n"
                       "  [--rebuild-interval 1..1e6 steps] [--edge-pieces 1..20] [--width-pieces 1..40] (base split along\n"
                       "  y / x): Housner's rocking block, restitution against r = 1 - 3/2 sin^2(alpha)."), 0;
    else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--quick") quick = true;
    else if (a == "--aspect") aspect = number(1.5, 20);
    else if (a == "--tilt") tilt0 = number(0.05, 0.95);
    else if (a == "--kn") k = number(1e6, 1e13);
    else if (a == "--safety") safety = number(0.05, 1);
    else if (a == "--duration") duration = number(0.2, 60);
    else if (a == "--threads") threads = std::round(number(0, 256));
    else if (a == "--tolerance") tolerance = number(1e-4, 0.05);
    else if (a == "--rebuild-interval") interval = std::round(number(1, 1e6));
    else if (a == "--edge-pieces") edge_pieces = std::round(number(1, 20));
    else if (a == "--width-pieces") width_pieces = std::round(number(1, 40));
    else return std::fprintf(stderr, "rocking: unknown or incomplete argument '%s' (see --help)\n", a.c_str()), 2;
  }
  if (quick) duration = std::min<real>(duration, 2.5);  // four impacts
  if (threads > 0) set_threads(static_cast<int>(threads));  // a 2-block scene: 1 thread is fastest
  io::run_record record(out, "rocking", argc, argv);
  try {
    // ---- scene: geometry, materials, supports, loading ----
    const real h = aspect * b, alpha = std::atan(b / h), theta0 = tilt0 * alpha;
    std::vector<geometry::convex_polyhedron> cells;  // the base 0.8 x 0.2 x 0.1 m, in pieces along x and y
    const int nx = static_cast<int>(width_pieces), ny = static_cast<int>(edge_pieces);
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j)
        cells.push_back(geometry::convex_polyhedron::box({-4 * b + 8 * b * i / nx, -0.1 + 0.2 * j / ny, -0.1},
                                                         {-4 * b + 8 * b * (i + 1) / nx, -0.1 + 0.2 * (j + 1) / ny, 0}));
    // The block 2b x 2h (0.1 m deep), turned by theta0 about its right bottom edge (x = b, z = 0).
    const mat3 turn = Eigen::AngleAxisd(theta0, vec3::UnitY()).toRotationMatrix();  // lifts the left edge
    const vec3 edge(b, 0, 0);
    cells.push_back(geometry::convex_polyhedron::box({-b, -0.05, 0}, {b, 0.05, 2 * h}).transformed(turn, edge - turn * edge));
    const auto rocker = static_cast<index_t>(cells.size() - 1);
    const geometry::tessellation tess = geometry::separate_blocks(cells);
    const auto joint = law::dry_joint(k, k, law::friction_angle::from_degrees(40));  // high enough not to slide
    solver_options options;
    options.safety = safety;
    // The impact is an undamped penalty spring that the step must resolve, not only keep stable:
    // the step of the whole-surface bound. The step of the contacts present (the default) is
    // 4.9x longer here and takes the energy error from 3e-5 to 4e-3 (docs/performance.md).
    contacts::params contact_params(joint, tolerance * b, static_cast<index_t>(interval));
    contact_params.step_bound = contact::step_bound_scope::whole_surface;
    model s(tess, geometry::zone_blocks(tess), blocks::rigid::params{2500}, contact_params, {}, options);
    s.fix_blocks(s.blocks_below(2, 0.0));  // the base: every block under z = 0
    s.set_gravity(vec3(0, 0, -9.81));
    // ---- end of scene ----
    const auto tilt = [&](const model& m) {  // tilt from upright (rad), positive towards +x
      const mat3 r = m.blocks().rotation(rocker) * turn;
      return std::atan2(r(0, 2), r(2, 2));
    };
    const auto omega = [&](const model& m) { return m.blocks().angular_velocity(rocker).y(); };  // rad/s
    io::ensure_directory(out);  // run.json "running"
    recorders::csv_recorder<model> curve(s, std::filesystem::path(out) / "curve.csv",
                                         {{"tilt", "rad", tilt}, {"omega", "rad_per_s", omega}}, recorders::every_seconds(1e-3));
    // Half-cycles: runs of one sign of the tilt (crossings within 2 % of theta0 of zero ignored);
    // each gives its peak |theta| (amplitude) and peak |omega| (the angular velocity at impact).
    std::vector<double> amplitude{0}, peak_omega{0};
    real first_impact = 0;  // time (s) the tilt first changes sign
    auto half_cycles = [&, side = 1](const model& m) mutable {
      const real theta = tilt(m);
      if (first_impact == 0 && theta <= 0) first_impact = m.time();
      if (theta * side < -0.02 * theta0) side = -side, amplitude.push_back(0), peak_omega.push_back(0);
      amplitude.back() = std::max<double>(amplitude.back(), std::abs(theta));
      peak_omega.back() = std::max<double>(peak_omega.back(), std::abs(omega(m)));
    };
    const auto start = std::chrono::steady_clock::now();
    const run_result run = s.run_until(stop::after_time(duration), static_cast<std::int64_t>(duration / s.dt()) + 2,
                                       curve, half_cycles);
    curve.close();
    const double runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const real housner = 1 - 1.5 * std::sin(alpha) * std::sin(alpha), c = std::cos(alpha);
    // Between impacts the block turns about a rigid edge: theta(t) = alpha - (alpha - theta0) cosh(p t),
    // p = sqrt(3 g / (4 R)), so the first impact (theta = 0) comes at acosh(alpha / (alpha - theta0)) / p.
    const real first_impact_housner = std::acosh(alpha / (alpha - theta0)) / std::sqrt(3 * 9.81 / (4 * std::hypot(b, h)));
    std::vector<double> r_amplitude, r_omega;
    for (std::size_t n = 0; n + 2 < amplitude.size(); ++n) {  // the last half-cycle may be unfinished
      r_amplitude.push_back(std::sqrt((std::cos(alpha - amplitude[n + 1]) - c) / (std::cos(alpha - amplitude[n]) - c)));
      r_omega.push_back(peak_omega[n + 1] / peak_omega[n]);
    }
    require(r_amplitude.size() >= 2, "rocking: ", r_amplitude.size(), " impacts in --duration = ", duration,
            " s; at least 2 are needed (lengthen --duration)");
    const std::size_t used = std::min<std::size_t>(3, r_amplitude.size());  // the first impacts, at the largest amplitudes
    real measured = 0, measured_omega = 0;
    for (std::size_t n = 0; n < used; ++n) measured += r_amplitude[n] / used, measured_omega += r_omega[n] / used;
    const energy_balance e = s.energies();  // where the rocking energy went (J)
    io::summary_json j;
    j.set("example", "rocking").set("quick", quick).set("aspect_h_over_b", aspect).set("alpha_deg", alpha * 180 / M_PI)
        .set("tilt_over_alpha", tilt0).set("k_n_Pa_per_m", k).set("tolerance_m", tolerance * b).set("max_rebuild_interval", interval)
        .set("base_pieces_x", width_pieces).set("base_pieces_y", edge_pieces).set("safety", safety).set("dt_s", s.dt())
        .set("duration_s", duration).set("stop_reason", run.reason).set("damping_in_force", run.damping).set("impacts", static_cast<std::int64_t>(r_amplitude.size()))
        .set("amplitudes_rad", amplitude).set("r_per_impact_amplitude", r_amplitude).set("r_per_impact_omega", r_omega)
        .set("restitution", measured).set("restitution_omega", measured_omega).set("impacts_averaged", static_cast<std::int64_t>(used))
        .set("reference_restitution", housner).set("error_rel", (measured - housner) / housner)
        .set("error_omega_rel", (measured_omega - housner) / housner).set("first_impact_s", first_impact)
        .set("reference_first_impact_s", first_impact_housner).set("first_impact_error_rel", first_impact / first_impact_housner - 1)
        .set("impact_model", "elastic: undamped penalty springs at the patch corners, where Housner's impact is plastic; the "
                             "error moves with k_n, tolerance and base pieces (-1 % .. +9 %), see docs/validation.md")
        .set("rocking_energy_start_J", s.blocks().weight_mass(rocker) * 9.81 * std::hypot(b, h) * (std::cos(alpha - theta0) - c))
        .set("gravity_work_J", e.gravity_work).set("slip_dissipated_J", e.contact_dissipated).set("kinetic_end_J", e.kinetic)
        .set("contact_stored_end_J", e.contact_stored).set("rebuild_exchange_J", e.contact_rebuild_exchange)
        .set("energy_error_rel", e.error_rel()).set("steps", s.step_count()).set("threads", max_threads()).set("runtime_s", runtime_s);
    j.write(std::filesystem::path(out) / "summary.json");
    record.complete();
    std::printf("rocking: alpha %.2f deg, %zu impacts; r from amplitudes %.4f, from peak angular velocities %.4f, "
                "Housner %.4f (error %+.2f %%, %+.2f %%)\n  rebuild exchange %.3f J, slip %.3f J; %lld steps of %.3g s, %.2f s\n",
                alpha * 180 / M_PI, r_amplitude.size(), measured, measured_omega, housner, 100 * (measured - housner) / housner,
                100 * (measured_omega - housner) / housner, e.contact_rebuild_exchange, e.contact_dissipated,
                static_cast<long long>(s.step_count()), s.dt(), runtime_s);
    return 0;
  } catch (const std::exception& e) {
    return std::fprintf(stderr, "rocking: %s\n", e.what()), 1;
  }
}
