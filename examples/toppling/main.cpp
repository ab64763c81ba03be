// toppling: block toppling on a stepped base (Goodman & Bray 1976). Rigid columns of width dx and
// heights 1, 2, 3, 4, 3 dx (toe first), each on its step of a fixed base (steps 0.2 dx apart), the
// base plane inclined at psi (gravity turned by psi; x downslope); dry joints of friction phi. The
// driver computes the limit-equilibrium support force at the toe P_0(phi) from the top column down
// (each toppling or sliding) and the critical phi_c (P_0 = 0), then bisects the simulation on phi
// (unstable: a column moves 2 % of dx within --duration). Writes run.json, regions.csv and
// summary.json (phi_c simulated and reference, error_rel, steps, runtime_s) in --out. Exit 0/1/2.
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
#include <cstdio>
#include <numbers>
using namespace tessera;
using contacts = contact::detected_contacts<law::dry_joint_law>;
using model = solver<blocks::rigid, contacts, reinforcement::none, integrator::central_difference<integrator::local_damping>>;
constexpr real deg = std::numbers::pi / 180, g = 9.81;

struct scene {
  real psi_deg = 20, dx = 0.1, depth = 0.05, step = 0.2, density = 2500, k = 1e8, damping = 0.5;  // deg, m, kg/m^3, Pa/m
  std::vector<real> heights{1, 2, 3, 4, 3};  ///< column heights (in dx), toe first
  [[nodiscard]] real base(std::size_t n) const { return static_cast<real>(n) * step * dx; }
  [[nodiscard]] real top(std::size_t n) const { return base(n) + heights[n] * dx; }
};

// ---- scene: geometry, materials, supports, loading (the part a user writes) ----
/// Cells 0..N-1: the fixed steps; N..2N-1: the columns. Column n spans x in [-(n+1) dx, -n dx].
std::vector<geometry::convex_polyhedron> cells(const scene& sc) {
  std::vector<geometry::convex_polyhedron> c;
  const std::size_t N = sc.heights.size();
  const real w = sc.depth / 2, x = sc.dx;  // half depth, column width (m)
  for (std::size_t n = 0; n < N; ++n)  // the steps, bottoms at z = -0.5 dx
    c.push_back(geometry::convex_polyhedron::box({-(n + 1.0) * x, -w, -0.5 * x}, {-(n + 0.0) * x, w, sc.base(n)}));
  for (std::size_t n = 0; n < N; ++n)  // the columns, each standing on its step
    c.push_back(geometry::convex_polyhedron::box({-(n + 1.0) * x, -w, sc.base(n)}, {-(n + 0.0) * x, w, sc.top(n)}));
  return c;
}
/// Runs the row at friction phi (deg) until a column moves beyond 2 % of dx or t = duration;
/// returns the largest column displacement (m) and adds the steps taken to `steps`.
real simulate(const scene& sc, real phi_deg, real duration, std::int64_t& steps) {
  const geometry::tessellation tess = geometry::separate_blocks(cells(sc));
  const auto joint = law::dry_joint(sc.k, sc.k, law::friction_angle::from_degrees(phi_deg));  // bases and sides
  const solver_options options{.damping_gamma = sc.damping};  // local damping: settles a stable row
  model s(tess, geometry::zone_blocks(tess), blocks::rigid::params{sc.density}, contacts::params(joint, 0.01 * sc.dx),
          {}, options);
  s.fix(s.gridpoints_on_plane(2, -0.5 * sc.dx, 1e-9));  // one fixed gridpoint holds a rigid step
  s.set_gravity(g * vec3(std::sin(sc.psi_deg * deg), 0, -std::cos(sc.psi_deg * deg)));
  const auto N = static_cast<index_t>(sc.heights.size());
  auto largest = [&, u = real(0)]() mutable {  // the largest column displacement (m)
    for (index_t b = N; b < 2 * N; ++b) u = std::max(u, s.blocks().displacement(b).norm());
    return u;
  };
  steps += s.run_until([&](const model& m) { return largest() > 0.02 * sc.dx || m.time() >= duration; },
                       static_cast<std::int64_t>(duration / s.dt()) + 2);
  return largest();
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
  std::string out = "results/toppling";  // --out
  bool quick = false;
  real duration = 1, iterations = 8;  // s, bisection steps
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto number = [&](real lo, real hi) {
      const char* v = i + 1 < argc ? argv[++i] : "";
      char* end = nullptr;  // the number must be the whole argument
      const real x = std::strtod(v, &end);
      if (*v != 0 && *end == 0 && x >= lo && x <= hi) return x;
      std::fprintf(stderr, "toppling: %s = '%s' must be a number in [%g, %g]\n", a.c_str(), v, lo, hi);
      std::exit(2);
    };
    if (a == "--help")
      return std::puts("toppling [--out DIR] [--quick] [--psi-deg 10..30] [--duration 0.5..60 s] [--iterations 1..20]\n"
                       "  [--damping 0..0.95] [--kn 1e5..1e12 Pa/m]: the Goodman-Bray row's critical friction"), 0;
    else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--quick") quick = true;
    else if (a == "--psi-deg") sc.psi_deg = number(10, 30);
    else if (a == "--duration") duration = number(0.5, 60);
    else if (a == "--iterations") iterations = std::round(number(1, 20));
    else if (a == "--damping") sc.damping = number(0, 0.95);
    else if (a == "--kn") sc.k = number(1e5, 1e12);
    else return std::fprintf(stderr, "toppling: unknown or incomplete argument '%s' (see --help)\n", a.c_str()), 2;
  }
  if (quick) iterations = std::min<real>(iterations, 5), duration = std::min<real>(duration, 0.7);
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
    for (int k = 0; k < iterations; ++k)
      (simulate(sc, (s_lo + s_hi) / 2, duration, steps) > 0.02 * sc.dx ? s_lo : s_hi) = (s_lo + s_hi) / 2;
    const real measured = (s_lo + s_hi) / 2;
    std::vector<double> phis{sc.psi_deg - 5, reference + 5}, p0s, moved;  // the regions: sliding row, stable row
    if (!quick) phis.insert(phis.begin() + 1, {(sc.psi_deg + reference) / 2, reference - 1, reference + 1});
    std::vector<std::string> rows;  // limit-equilibrium modes per region
    for (const real phi : phis) {
      p0s.push_back(support_force(sc, phi, modes)), rows.push_back(modes), moved.push_back(simulate(sc, phi, duration, steps));
      std::printf("  phi %5.2f deg: limit equilibrium %s (toe first; s stable, T toppling, S sliding), P_0 %.4g N, "
                  "simulated max displacement %.3g m\n", phi, modes.c_str(), p0s.back(), moved.back());
    }
    io::write_csv(std::filesystem::path(out) / "regions.csv", {"phi_deg", "P0_N", "max_displacement_m"}, {phis, p0s, moved});
    const double runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const real error = (measured - reference) / reference;  // of the critical friction angle
    io::summary_json j;  // the figures, then the regions
    j.set("example", "toppling").set("quick", quick).set("psi_deg", sc.psi_deg).set("heights_dx", std::vector<double>(sc.heights.begin(), sc.heights.end()))
        .set("step_dx", sc.step).set("dx_m", sc.dx).set("k_n_Pa_per_m", sc.k).set("damping", sc.damping).set("duration_s", duration).set("iterations", iterations)
        .set("critical_friction_deg", measured).set("critical_friction_bracket_deg", std::vector<double>{s_lo, s_hi})
        .set("reference_critical_friction_deg", reference).set("error_rel", error).set("regions_phi_deg", phis)
        .set("regions_modes", rows).set("regions_P0_N", p0s).set("regions_max_displacement_m", moved)
        .set("steps", steps).set("runtime_s", runtime_s);
    j.write(std::filesystem::path(out) / "summary.json");
    record.complete();
    std::printf("toppling: critical friction %.3f deg simulated (%.3f..%.3f), %.3f deg limit equilibrium, error %+.2f %%; "
                "%lld steps, %.1f s\n", measured, s_lo, s_hi, reference, 100 * error, static_cast<long long>(steps), runtime_s);
    return 0;
  } catch (const std::exception& e) {
    return std::fprintf(stderr, "toppling: %s\n", e.what()), 1;
  }
}
