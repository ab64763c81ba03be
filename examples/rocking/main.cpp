// rocking: free rocking of a rectangular rigid block (Housner 1963). A block of width 2b and height
// 2h (default h = 4 b, alpha = atan(b/h) = 14.0 deg), tilted by --tilt x alpha about its right
// bottom edge and released on a fixed base: it rocks from one bottom edge to the other, losing
// energy at each impact. Housner's closed form, from angular momentum about the new edge
// (I_O = 4/3 m R^2, R = sqrt(b^2 + h^2)): r = omega_after / omega_before = 1 - 3/2 sin^2(alpha).
// Measured from the amplitudes theta_k of successive half-cycles (energy before and after each
// impact): r_k^2 = (cos(alpha - theta_k+1) - cos alpha) / (cos(alpha - theta_k) - cos alpha), and
// from the peak angular velocities on either side of each impact. Undamped, dry joint, detected
// contacts. Outputs in --out: run.json, curve.csv (t_s, tilt_rad, omega_rad_per_s), summary.json
// (r measured and Housner's, error_rel, per impact, steps, runtime_s). Exit 0/1/2.
#include <tessera/blocks.hpp>
#include <tessera/contact.hpp>
#include <tessera/geometry.hpp>
#include <tessera/integrator.hpp>
#include <tessera/io/csv.hpp>
#include <tessera/io/json.hpp>
#include <tessera/io/run_record.hpp>
#include <tessera/law.hpp>
#include <tessera/reinforcement.hpp>
#include <tessera/solver.hpp>

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
  real aspect = 4, tilt = 0.5, k = 1e9, safety = 0.8, duration = 3, b = 0.1;  // h/b, theta_0/alpha, Pa/m, -, s, m
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto number = [&](real lo, real hi) {
      const char* v = i + 1 < argc ? argv[++i] : "";
      char* end = nullptr;
      const real x = std::strtod(v, &end);
      if (*v == 0 || *end != 0 || !(x >= lo && x <= hi)) {
        std::fprintf(stderr, "rocking: %s = '%s' must be a number in [%g, %g]\n", a.c_str(), v, lo, hi);
        std::exit(2);
      }
      return x;
    };
    if (a == "--help") {
      std::puts("rocking [--out DIR] [--quick] [--aspect h/b 1.5..20] [--tilt theta0/alpha 0.05..0.95]\n"
                "  [--kn 1e6..1e13 Pa/m] [--safety 0.05..1] [--duration 0.2..60 s]: Housner's rocking block,\n"
                "  coefficient of restitution measured against r = 1 - 3/2 sin^2(alpha).");
      return 0;
    } else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--quick") quick = true;
    else if (a == "--aspect") aspect = number(1.5, 20);
    else if (a == "--tilt") tilt = number(0.05, 0.95);
    else if (a == "--kn") k = number(1e6, 1e13);
    else if (a == "--safety") safety = number(0.05, 1);
    else if (a == "--duration") duration = number(0.2, 60);
    else {
      std::fprintf(stderr, "rocking: unknown or incomplete argument '%s' (see --help)\n", a.c_str());
      return 2;
    }
  }
  if (quick) duration = std::min<real>(duration, 2.5);  // three impacts
  io::run_record record(out, "rocking", argc, argv);
  try {
    // ---- scene: geometry, materials, supports, loading ----
    const real h = aspect * b, alpha = std::atan(b / h), theta0 = tilt * alpha;
    // The block 2b x 2h (0.1 m deep), turned by theta0 about its right bottom edge (x = b, z = 0).
    const mat3 turn = Eigen::AngleAxisd(theta0, vec3::UnitY()).toRotationMatrix();  // lifts the left edge
    const vec3 edge(b, 0, 0);
    const std::vector<geometry::convex_polyhedron> cells{
        geometry::convex_polyhedron::box({-4 * b, -0.1, -0.1}, {4 * b, 0.1, 0}),  // the base
        geometry::convex_polyhedron::box({-b, -0.05, 0}, {b, 0.05, 2 * h}).transformed(turn, edge - turn * edge)};
    const geometry::tessellation tess = geometry::separate_blocks(cells);
    const auto joint = law::dry_joint(k, k, law::friction_angle::from_degrees(40));  // high enough not to slide
    solver_options options;
    options.safety = safety;
    model s(tess, geometry::zone_blocks(tess), blocks::rigid::params{2500}, contacts::params(joint, 0.002 * b), {},
            options);
    s.fix(s.gridpoints_on_plane(2, -0.1, 1e-9));  // one fixed gridpoint holds the rigid base
    s.set_gravity(vec3(0, 0, -9.81));
    // ---- end of scene ----
    io::ensure_directory(out);  // run.json "running"
    const auto start = std::chrono::steady_clock::now();
    std::vector<double> t, theta, omega;
    s.run(static_cast<std::int64_t>(std::ceil(duration / s.dt())), [&](const model& m) {
      const mat3 r = m.blocks().rotation(1) * turn;  // rotation from upright
      t.push_back(m.time());
      theta.push_back(std::atan2(r(0, 2), r(2, 2)));
      omega.push_back(m.blocks().angular_velocity(1).y());
    });
    const double runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // Half-cycles: runs of one sign of the tilt (crossings within 2 % of theta0 of zero ignored);
    // each gives its peak |theta| (amplitude) and peak |omega| (the angular velocity at impact).
    std::vector<double> amplitude{0}, peak_omega{0};
    int side = 1;
    for (std::size_t n = 0; n < t.size(); ++n) {
      if (theta[n] * side < -0.02 * theta0) side = -side, amplitude.push_back(0), peak_omega.push_back(0);
      amplitude.back() = std::max(amplitude.back(), std::abs(theta[n]));
      peak_omega.back() = std::max(peak_omega.back(), std::abs(omega[n]));
    }
    const real housner = 1 - 1.5 * std::sin(alpha) * std::sin(alpha), c = std::cos(alpha);
    std::vector<double> r_amplitude, r_omega;
    for (std::size_t k = 0; k + 2 < amplitude.size(); ++k) {  // the last half-cycle may be unfinished
      r_amplitude.push_back(std::sqrt((std::cos(alpha - amplitude[k + 1]) - c) / (std::cos(alpha - amplitude[k]) - c)));
      r_omega.push_back(peak_omega[k + 1] / peak_omega[k]);
    }
    require(r_amplitude.size() >= 2, "rocking: ", r_amplitude.size(), " impacts in --duration = ", duration,
            " s; at least 2 are needed (lengthen --duration)");
    const std::size_t used = std::min<std::size_t>(3, r_amplitude.size());  // the first impacts, at the largest amplitudes
    real measured = 0, measured_omega = 0;
    for (std::size_t k = 0; k < used; ++k) measured += r_amplitude[k] / used, measured_omega += r_omega[k] / used;
    io::write_csv(std::filesystem::path(out) / "curve.csv", {"t_s", "tilt_rad", "omega_rad_per_s"}, {t, theta, omega});
    io::summary_json j;
    j.set("example", "rocking").set("quick", quick).set("aspect_h_over_b", aspect).set("alpha_deg", alpha * 180 / M_PI)
        .set("tilt_over_alpha", tilt).set("k_n_Pa_per_m", k).set("safety", safety).set("dt_s", s.dt())
        .set("duration_s", duration).set("impacts", static_cast<std::int64_t>(r_amplitude.size()))
        .set("amplitudes_rad", amplitude).set("r_per_impact_amplitude", r_amplitude).set("r_per_impact_omega", r_omega)
        .set("restitution", measured).set("restitution_omega", measured_omega).set("impacts_averaged", static_cast<std::int64_t>(used))
        .set("reference_restitution", housner).set("error_rel", (measured - housner) / housner)
        .set("error_omega_rel", (measured_omega - housner) / housner).set("steps", s.step_count()).set("runtime_s", runtime_s);
    // Where the rocking energy went (J): the penalty contact dissipates only by slip; the rest stays.
    const energy_balance e = s.energies();
    j.set("rocking_energy_start_J", s.blocks().weight_mass(1) * 9.81 * std::hypot(b, h) * (std::cos(alpha - theta0) - c))
        .set("gravity_work_J", e.gravity_work).set("slip_dissipated_J", e.contact_dissipated).set("kinetic_end_J", e.kinetic)
        .set("contact_stored_end_J", e.contact_stored).set("rebuild_exchange_J", e.contact_rebuild_exchange)
        .set("energy_error_rel", e.error_rel());
    j.write(std::filesystem::path(out) / "summary.json");
    record.complete();
    std::printf("rocking: alpha %.2f deg, %zu impacts; r from amplitudes %.4f, from peak angular velocities %.4f, "
                "Housner %.4f (error %+.2f %%, %+.2f %%)\n  %lld steps of %.3g s, %.2f s\n", alpha * 180 / M_PI,
                r_amplitude.size(), measured, measured_omega, housner, 100 * (measured - housner) / housner,
                100 * (measured_omega - housner) / housner, static_cast<long long>(s.step_count()), s.dt(), runtime_s);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rocking: %s\n", e.what());
    return 1;
  }
}
