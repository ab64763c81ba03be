#pragma once
// The bond case of examples/verification (cases.hpp): a cube bonded to a long base (detected
// contacts with bond_faces), tilted until the bond fails in shear, then sliding on the broken
// face's friction alone.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "tessera/blocks/rigid.hpp"
#include "tessera/contact/detected_contacts.hpp"
#include "tessera/geometry/block_mesh.hpp"
#include "tessera/geometry/convex_polyhedron.hpp"
#include "tessera/geometry/tessellation.hpp"
#include "tessera/geometry/zoning.hpp"
#include "tessera/law/cohesive_frictional.hpp"
#include "tessera/law/compression.hpp"
#include "tessera/law/shear.hpp"
#include "tessera/law/tension.hpp"
#include "tessera/reinforcement/none.hpp"
#include "tessera/solver/solver.hpp"
#include "verification/inputs.hpp"
#include "verification/scene.hpp"

namespace tessera::verification::detail {

/// The bond case (cases.hpp's file comment): a cube of edge b bonded (bond_faces) on a long fixed base; the
/// bond's shear strength is its cohesion c_0 alone (phi_0 = 0), the broken face's is friction
/// alone (c_res = 0, phi_res = --friction-deg). Gravity turns linearly to theta = --angle-deg over
/// the first quarter of the run and stays; undamped. The bond fails when the shear force reaches
/// c_0 b^2 (tilt theta* = asin(c_0 b^2 / W)); from then on the cube is a block on an incline
/// (sticks while theta <= phi, else slides with a = g (sin theta - cos theta tan phi)), with its
/// four broken corners carried through every rebuild.
inline result run_bond(const inputs& in) {
  using law_type = law::cohesive_frictional<law::linear_softening, law::elastic_compression, law::coulomb_residual>;
  using bonded = contact::detected_contacts<law_type>;
  const real b = in.size, c0 = in.cohesion;
  const real theta = in.angle_deg * std::numbers::pi / 180, phi = in.friction_deg * std::numbers::pi / 180;
  const real weight = bond_weight(in), failure_force = bond_failure_force(in);
  const real duration = in.duration > 0 ? in.duration : in.quick ? 0.4 : 1.0, ramp = duration / 4;
  const real half_length = 0.5 * g * duration * duration + 2 * b;
  const real overlap = weight / (in.k_n * b * b);  // static on the level base, as for the incline
  const std::vector<geometry::convex_polyhedron> cells{
      geometry::convex_polyhedron::box({-half_length, -b, -0.5 * b}, {half_length, b, 0}),
      geometry::convex_polyhedron::box({-b / 2, -b / 2, -overlap}, {b / 2, b / 2, b - overlap})};
  const geometry::tessellation tess = geometry::separate_blocks(cells);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  law_type::params p;
  p.k_n = in.k_n;
  p.k_s = in.k_n;
  p.tension.f_T = c0;
  p.tension.G_f = c0 * b * 1e-3;  // the face stays compressed: never reached
  p.shear.c_0 = c0;
  p.shear.c_res = 0;
  p.shear.phi_0 = law::friction_angle::from_degrees(0);
  p.shear.phi_res = law::friction_angle::from_degrees(in.friction_deg);
  solver<blocks::rigid, bonded, reinforcement::none, undamped> s(tess, mesh, blocks::rigid::params{in.density},
                                                                 bonded::params(p, in.tolerance, 1000, true));
  s.fix(s.gridpoints_on_plane(2, -0.5 * b, 1e-9 * b));
  // Bounds the run (step_through's guard); the run itself goes to `duration` of simulated time,
  // since the rigid step is chosen again at each rebuild.
  const index_t most = step_count(100 * duration, s.dt());
  const real t0 = s.time(), every = duration / 2000;
  const auto reached = [&](real t) { return s.time() - t0 + 1e-9 * s.dt() >= t; };
  result r;
  r.which = in.which;
  r.dt = s.dt();
  r.damping_in_force = s.damping_in_force();
  r.bonded_at_start = s.contacts().bonded_at_start();
  // The contact force on the cube along the slope (x; the scene stays level, gravity turns).
  const auto shear_force = [&] {
    real f = 0;
    for (index_t i = 0; i < s.contacts().subcontact_count(); ++i) f += s.contacts().force(i).x();
    return -f;
  };
  const auto failed = [&] {
    for (index_t i = 0; i < s.contacts().subcontact_count(); ++i)
      if (s.contacts().state(i).flags != law::contact_status::intact) return true;
    return false;
  };
  bool broken = false;
  real force_before = 0;
  real next_sample = every;
  index_t steps = 0;
  while (!reached(duration)) {
    require(steps < most, "verification: ", duration, " s not reached in ", most, " steps (dt fell to ", s.dt(), " s)");
    ++steps;
    const real tilt = theta * std::min<real>(1, s.time() / ramp);
    s.set_gravity(vec3(g * std::sin(tilt), 0, -g * std::cos(tilt)));
    s.step();
    if (!broken && failed()) {
      broken = true;
      r.peak = force_before;  // the last shear force the intact bond carried
      r.stress_at_reversal = tilt;
    }
    force_before = shear_force();
    if (reached(duration) || reached(next_sample)) {
      record_motion(r, s, 1);
      r.force.push_back(force_before);
      while (reached(next_sample)) next_sample += every;
    }
  }
  record_end(r, s, steps, tess, mesh);
  r.slide_m = s.blocks().displacement(1).x();
  r.quantity = "shear force at which the bond failed";
  r.unit = "N";
  r.measured = r.peak;
  r.reference = failure_force;
  r.error_rel = r.peak / failure_force - 1;
  r.tolerance = 0.01;
  // After the failure: the block on an incline with the broken face's friction.
  r.acceleration = fitted_acceleration(r);
  r.acceleration_reference = theta > phi ? g * (std::sin(theta) - std::cos(theta) * std::tan(phi)) : 0;
  r.acceleration_error = (r.acceleration - r.acceleration_reference) / (theta > phi ? r.acceleration_reference : g);
  r.pass = broken && std::abs(r.error_rel) <= r.tolerance && std::abs(r.acceleration_error) <= r.tolerance;
  r.kept_last_rebuild = s.contacts().kept_last_rebuild();
  return r;
}

}  // namespace tessera::verification::detail
