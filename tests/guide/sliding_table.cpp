// The dynamic scene of docs/guide.md ("A dynamic scene worked through"), verbatim between the
// scene markers: a slab (0.4 x 0.2 x 0.1 m) on a table that starts at 1 m/s, is driven for 0.5 s and stops.
// Coulomb friction (mu = tan 30 deg) drags the slab: it lags the table by v^2 / (2 mu g) while
// the table moves, then slides on by as much when it stops, so it ends where the table did,
// v t_move. (A slab, not a cube: the friction's moment, applied at once, would lift a cube's
// trailing edge, and the undamped contacts would then let it rock and hop.) Exits non-zero unless the undamped run gives both within 1 %, and unless the run with
// local damping is far off (the damping resists every motion, so it is no model of dynamics).
#include <tessera/blocks.hpp>
#include <tessera/contact.hpp>
#include <tessera/geometry.hpp>
#include <tessera/law.hpp>
#include <tessera/solver.hpp>
#include <tessera/instances.hpp>  // rigid_dry_solver compiled once: link tessera::instances

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

using namespace tessera;

struct slide {
  double x_at_stop, x_end;  // the slab's displacement along x when the table stops and at the end (m)
};

// ---- scene
template <class Solver>
slide sliding_table() {
  const real rho = 2400, g = 9.81, k = 1e9, v = 1.0, t_move = 0.5;   // kg/m^3, m/s^2, Pa/m, m/s, s
  const real sink = rho * 0.1 * g / k;  // the slab placed at its static overlap W / (k_n A) (m)
  const std::vector<geometry::convex_polyhedron> blocks{
      geometry::convex_polyhedron::box(vec3(-1, -0.5, -0.1), vec3(2, 0.5, 0)),                // block 0: the table
      geometry::convex_polyhedron::box(vec3(0, -0.1, -sink), vec3(0.4, 0.1, 0.1 - sink))};  // block 1: the slab
  const auto tess = geometry::separate_blocks(blocks);
  const auto mesh = geometry::zone_blocks(tess);
  Solver s(tess, mesh, blocks::rigid::params{rho},
           {law::dry_joint(k, k, law::friction_angle::from_degrees(30)), /*tolerance, m*/ 1e-3});
  s.set_gravity(vec3(0, 0, -g));
  s.prescribe_block_velocity(0, vec3(v, 0, 0), bc::components::xyz);  // every component driven
  while (s.time() < t_move) s.step();                                  // the run loop by hand
  const real x_at_stop = s.block_displacement(1).x();
  bc::update_velocity(s.gridpoints(), s.gridpoints_of_block(0), vec3::Zero(), bc::components::x);
  const auto r = s.run_until(stop::after_time(0.5), 10'000'000);       // the slab slides on, stops
  std::printf("t = %.4f s (dt = %.3g s, %lld steps after the stop: %s)\n", s.time(), s.dt(),
              static_cast<long long>(r.steps), r.reason.c_str());
  return {x_at_stop, s.block_displacement(1).x()};
}
// ---- end of scene

int main() {
  const double mu = std::tan(std::numbers::pi / 6), lag = 1.0 / (2 * mu * 9.81);  // v^2 / (2 mu g), m
  const double x_stop = 0.5 - lag, x_end = 0.5;                                  // closed forms (m)
  const slide free = sliding_table<instances::rigid_dry_solver>();
  const slide damped = sliding_table<instances::rigid_dry_damped_solver>();
  const double e_stop = free.x_at_stop / x_stop - 1, e_end = free.x_end / x_end - 1;
  std::printf("undamped: x = %.5f m at the stop (closed form %.5f, %+.2e), %.5f m at the end (%.5f, %+.2e)\n",
              free.x_at_stop, x_stop, e_stop, free.x_end, x_end, e_end);
  std::printf("local damping 0.8: x = %.5f m at the stop, %.5f m at the end\n", damped.x_at_stop, damped.x_end);
  const bool ok = std::abs(e_stop) < 0.01 && std::abs(e_end) < 0.01 && std::abs(damped.x_end / x_end - 1) > 0.05;
  return ok ? 0 : 1;
}
