// toppling: block toppling on a stepped base (Goodman & Bray 1976). Rigid columns of width dx and
// heights 1, 2, 3, 4, 3 dx (toe first), each on its step of a fixed base (steps 0.2 dx apart), the
// base plane inclined at psi (gravity turned by psi; x downslope); dry joints of friction phi. The
// driver computes the limit-equilibrium toe force P_0(phi) from the top column down and the critical
// phi_c (P_0 = 0), then bisects the simulation on phi (unstable: a column moves 2 % of dx; stable: the
// row settles or --duration ends). Writes run.json, regions.csv, summary.json in --out. Exit 0/1/2.
#include <tessera/io/run_record.hpp>
#include <tessera/tessera.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numbers>
using namespace tessera;
using contacts = contact::detected_contacts<law::dry_joint_law>;
using model = solver<blocks::rigid, contacts, reinforcement::none, integrator::central_difference<integrator::local_damping>>;
constexpr real deg = std::numbers::pi / 180, g = 9.81;

struct scene {
  real psi_deg = 20, dx = 0.1, depth = 0.05, step = 0.2, density = 2500, k = 1e8, damping = 0.5, ramp = 0.2;  // deg, m, kg/m^3, Pa/m, s
  std::vector<double> heights{1, 2, 3, 4, 3};  ///< column heights (in dx), toe first
  [[nodiscard]] real base(std::size_t n) const { return static_cast<real>(n) * step * dx; }
  [[nodiscard]] real top(std::size_t n) const { return base(n) + heights[n] * dx; }
};
struct largest_column_displacement {  // of columns first..first+count-1 (m): the quantity the stop rule watches
  index_t first, count;
  [[nodiscard]] real operator()(const model& s) const {
    real u = 0;
    for (index_t b = first; b < first + count; ++b) u = std::max(u, s.block_displacement(b).norm());
    return u;
  }
  [[nodiscard]] std::string describe() const { return "largest column displacement (m)"; }  // for the stop reason
};
struct outcome { real moved; std::string reason, damping; };  ///< largest column displacement (m), why the run stopped, its damping
// ---- scene: geometry, materials, supports, loading (the part a user writes) ----
/// Runs the row at friction phi (deg): steps 0..N-1 fixed, columns N..2N-1 (column n spans x in
/// [-(n+1) dx, -n dx]) on them, until a column moves beyond 2 % of dx (unstable), the row has
/// settled (stable) or t = duration. Adds the steps taken to `steps`.
outcome simulate(const scene& sc, real phi_deg, real duration, std::int64_t& steps) {
  const std::size_t N = sc.heights.size();
  const real w = sc.depth / 2, x = sc.dx;  // half depth, column width (m)
  std::vector<geometry::convex_polyhedron> cells;
  for (std::size_t n = 0; n < N; ++n)  // the steps, bottoms at z = -0.5 dx, tops at n x 0.2 dx
    cells.push_back(geometry::convex_polyhedron::box({-(n + 1.0) * x, -w, -0.5 * x}, {-(n + 0.0) * x, w, sc.base(n)}));
  for (std::size_t n = 0; n < N; ++n)  // the columns, each standing on its step
    cells.push_back(geometry::convex_polyhedron::box({-(n + 1.0) * x, -w, sc.base(n)}, {-(n + 0.0) * x, w, sc.top(n)}));
  const geometry::tessellation tess = geometry::separate_blocks(cells);  // blocks meet through detected contacts
  // One dry joint (phi_0 = phi_res = phi) on bases and sides; contact tolerance 1 % of dx.
  const auto joint = law::dry_joint(sc.k, sc.k, law::friction_angle::from_degrees(phi_deg));
  const solver_options options{.damping_gamma = sc.damping};  // local damping: settles a stable row
  model s(tess, geometry::zone_blocks(tess), blocks::rigid::params{sc.density}, contacts::params(joint, 0.01 * x),
          {}, options);
  s.fix_blocks(s.blocks_on_plane(2, -0.5 * x, 1e-9));  // the steps: every block on the bottom plane
  const vec3 gravity = g * vec3(std::sin(sc.psi_deg * deg), 0, -std::cos(sc.psi_deg * deg));  // slope frame: x down the base
  // Gravity grows linearly over sc.ramp s (0: at once): applied at once, its overshoot slips joints
  // near their limit, and the row needs about 1 deg more friction than limit equilibrium (+3.4 %).
  const auto ramp = [&](const model& m) { s.set_gravity(std::min<real>(1, sc.ramp > 0 ? m.time() / sc.ramp : 1) * gravity); };
  ramp(s);
  const largest_column_displacement moved{static_cast<index_t>(N), static_cast<index_t>(N)};
  const run_result r = s.run_until(stop::when_beyond(moved, 0.02 * x) ||  // unstable: a column moved 2 mm
                                       stop::when_settled(moved, 1e-5 * x, stop::over_time(0.1)) ||  // stable
                                       stop::after_time(duration),
                                   static_cast<std::int64_t>(duration / s.dt()) + 2, ramp);
  return steps += r.steps, outcome{moved(s), r.reason, r.damping};
}
// ---- end of scene ----
/// Goodman-Bray limit equilibrium from the top column down with phi on bases and sides: returns
/// P_0, the support force at the toe (N), and each column's mode in `modes` (toe first).
real support_force(const scene& sc, real phi_deg, std::string& modes) {
  const real t = std::tan(phi_deg * deg), ps = std::sin(sc.psi_deg * deg), pc = std::cos(sc.psi_deg * deg);
  const std::size_t N = sc.heights.size();
  real P = (modes.assign(N, '?'), 0.0);  // force from the column above on column n (N)
  for (std::size_t n = N; n-- > 0;) {
    const real y = sc.heights[n] * sc.dx, W = sc.density * g * sc.depth * sc.dx * y;
    const real M = (n + 1 < N ? std::min(sc.top(n), sc.top(n + 1)) : sc.top(n)) - sc.base(n);  // P_n's arm
    const real L = (n > 0 ? std::min(sc.top(n), sc.top(n - 1)) : sc.top(n)) - sc.base(n);      // P_{n-1}'s arm
    const real topple = (P * (M - sc.dx * t) + W / 2 * (y * ps - sc.dx * pc)) / L;
    const real slide = P - W * (pc * t - ps) / (1 - t * t);
    modes[n] = topple <= 0 && slide <= 0 ? 's' : topple > slide ? 'T' : 'S';  // stable, Toppling, Sliding
    P = std::max<real>({0, topple, slide});
  }
  return P;
}

int main(int argc, char** argv) {
  scene sc;
  std::string out = "results/toppling";  // --out; --quick: 5 bisections, 0.7 s per run (CI)
  bool quick = false;
  real duration = 1, iterations = 8, threads = 0;  // s, bisection steps, OpenMP threads (0: as set)
  struct flag { std::string name; real* value; real lo, hi; };  // every number range-checked, named when refused
  const flag flags[] = {{"--psi-deg", &sc.psi_deg, 10, 30}, {"--duration", &duration, 0.5, 60}, {"--iterations", &iterations, 1, 20},
                        {"--damping", &sc.damping, 0, 0.95}, {"--kn", &sc.k, 1e5, 1e12}, {"--step", &sc.step, 0, 0.5},
                        {"--ramp", &sc.ramp, 0, 1}, {"--threads", &threads, 0, 256}};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const flag* f = std::find_if(std::begin(flags), std::end(flags), [&](const flag& x) { return x.name == a; });
    if (a == "--help")
      return std::puts("toppling [--out DIR] [--quick] [--psi-deg 10..30] [--duration 0.5..60 s] [--iterations 1..20] [--damping 0..0.95]\n"
                       "  [--kn 1e5..1e12 Pa/m] [--step 0..0.5 (riser, x dx)] [--ramp 0..1 s] [--threads 0..256]: the Goodman-Bray row's critical friction"), 0;
    if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--quick") quick = true;
    else if (f == std::end(flags)) return std::fprintf(stderr, "toppling: unknown or incomplete argument '%s' (see --help)\n", a.c_str()), 2;
    else {
      const char* v = i + 1 < argc ? argv[++i] : "";  // the number must be the whole argument
      char* end = nullptr;
      *f->value = std::strtod(v, &end);
      if (*v == 0 || *end != 0 || !(*f->value >= f->lo && *f->value <= f->hi))
        return std::fprintf(stderr, "toppling: %s = '%s' must be a number in [%g, %g]\n", a.c_str(), v, f->lo, f->hi), 2;
    }
  }
  if (quick) iterations = std::min<real>(iterations, 5), duration = std::min<real>(duration, 0.7);
  if (std::round(threads) > 0) set_threads(static_cast<int>(std::round(threads)));  // a 10-block row: 1 thread is fastest
  io::run_record record(out, "toppling", argc, argv);
  try {
    std::string modes;  // P_0(psi) > 0 (the toe slides); P_0(44.9 deg) = 0 is required
    real lo = sc.psi_deg, reference = 44.9;  // bisected on the closed form to 1e-15 deg
    require(support_force(sc, reference, modes) <= 0, "toppling: --psi-deg = ", sc.psi_deg, " leaves the row unstable at 45 deg");
    for (int k = 0; k < 60; ++k) (support_force(sc, (lo + reference) / 2, modes) > 0 ? lo : reference) = (lo + reference) / 2;
    io::ensure_directory(out);  // run.json "running"
    const auto start = std::chrono::steady_clock::now();
    std::int64_t steps = 0;  // over every run
    real s_lo = sc.psi_deg, s_hi = 44.9;  // bracket of the simulated critical friction (deg)
    for (int k = 0; k < std::round(iterations); ++k)
      (simulate(sc, (s_lo + s_hi) / 2, duration, steps).moved > 0.02 * sc.dx ? s_lo : s_hi) = (s_lo + s_hi) / 2;
    const real measured = (s_lo + s_hi) / 2;
    std::vector<double> phis{sc.psi_deg - 5, reference + 5}, p0s, moved;  // the regions: sliding row, stable row
    if (!quick) phis.insert(phis.begin() + 1, {(sc.psi_deg + reference) / 2, reference - 1, reference + 1});
    std::vector<std::string> rows, reasons;  // limit-equilibrium modes, why each run stopped
    std::string damping_in_force;  // the runs' damping (run_result::damping)
    for (const real phi : phis) {
      const outcome o = simulate(sc, phi, duration, steps);
      p0s.push_back(support_force(sc, phi, modes)), rows.push_back(modes), moved.push_back(o.moved), reasons.push_back(o.reason);
      damping_in_force = o.damping;
      std::printf("  phi %5.2f deg: limit equilibrium %s (s stable, T toppling, S sliding; toe first), P_0 %.4g N; simulated: %s\n",
                  phi, modes.c_str(), p0s.back(), o.reason.c_str());
    }
    io::write_csv(std::filesystem::path(out) / "regions.csv", {"phi_deg", "P0_N", "max_displacement_m"}, {phis, p0s, moved});
    const double runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const real error = (measured - reference) / reference;  // of the critical friction angle
    io::summary_json().set("example", "toppling").set("quick", quick).set("psi_deg", sc.psi_deg).set("heights_dx", sc.heights).set("step_dx", sc.step)
        .set("dx_m", sc.dx).set("k_n_Pa_per_m", sc.k).set("damping", sc.damping).set("gravity_ramp_s", sc.ramp).set("duration_s", duration)
        .set("damping_in_force", damping_in_force)
        .set("iterations", std::round(iterations)).set("critical_friction_deg", measured).set("critical_friction_bracket_deg", std::vector<double>{s_lo, s_hi})
        .set("reference_critical_friction_deg", reference).set("error_rel", error).set("regions_phi_deg", phis).set("regions_modes", rows)
        .set("regions_P0_N", p0s).set("regions_max_displacement_m", moved).set("regions_stop_reason", reasons).set("steps", steps)
        .set("threads", max_threads()).set("runtime_s", runtime_s).write(std::filesystem::path(out) / "summary.json");
    record.complete();
    std::printf("toppling: critical friction %.3f deg simulated (%.3f..%.3f), %.3f deg limit equilibrium, error %+.2f %%; "
                "%lld steps, %.1f s\n", measured, s_lo, s_hi, reference, 100 * error, static_cast<long long>(steps), runtime_s);
    return 0;
  } catch (const std::exception& e) {
    return std::fprintf(stderr, "toppling: %s\n", e.what()), 1;
  }
}
