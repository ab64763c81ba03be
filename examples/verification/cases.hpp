#pragma once
// The verification problems of contact detection (3DEC's verification set; issue #17), as
// functions the driver (main.cpp) and the tests (tests/test_rigid.cpp "[verification]") share.
// Every case is rigid blocks under gravity on a fixed base, with detected contacts of a
// frictional joint (no tension, no cohesion, friction angle phi):
//   incline  a cube on a plane at angle theta (gravity turned by theta, the scene stays level),
//            undamped: sticks for theta < phi, else slides with a = g (sin theta - cos theta tan phi)
//   topple   a block of width b (along the slope) and height h on the incline, theta < phi:
//            topples iff tan theta > b / h
//   stack    a column of cubes settling on the base with local damping: the base carries the
//            total weight, the column does not drift
//   drop     a cube dropped on the base comes to rest with overlap W / (k_n A)
//   reclose  the study's prism cracked in tension, pushed back and pulled again (reclose.hpp):
//            compression at the intact stiffness within 2 %, no tension regained
//   bond     a cube bonded to the base (detected contacts with bond_faces: the face starts
//            intact, shear strength c_0), tilted: the bond fails at a shear force of c_0 A, and
//            the broken face, carried through every rebuild with its state, is a frictional
//            incline from then on (a = g (sin theta - cos theta tan phi), no cohesion regained);
//            both within 1 %
// With `deformable` (--deformable) incline, topple, stack and drop run the same scenes with
// deformable blocks (blocks::deformable, linear elastic tetrahedral zones of edge zone_edge, Young's
// modulus young): detected contacts place their points in zones and put a face-to-face patch's
// sub-contacts at surface gridpoints (contact/detected_contacts.hpp). The closed forms are the
// same; drop reads the overlap as the contacts' mean closure (area-weighted -u_n), since the
// faces themselves deform.
// The block rests on the level base at its static overlap from the start, and the incline is
// tilted to theta over the first ramp_s (0.1 s, half-cosine), as on a tilting table: a sudden
// tilt would start the undamped block rocking on its friction moment (e.g. theta 40, phi 30 deg),
// which is a different problem. The acceleration is fitted over the second half of the run.
//
// The inputs and results: inputs.hpp; the scenes and their run: scene.hpp; the bond case:
// bond.hpp; the reclose case: reclose.hpp. This header picks a case's scene and checks its
// closed form (run).

#include <cmath>
#include <numbers>
#include <vector>

#include "tessera/tessera.hpp"
#include "verification/bond.hpp"
#include "verification/inputs.hpp"
#include "verification/reclose.hpp"
#include "verification/scene.hpp"

namespace tessera::verification {

/// Runs one case (validate(in) first).
[[nodiscard]] inline result run(const inputs& in) {
  validate(in);
  if (in.which == "reclose") {
    const reclose_result c = run_reclose(in.quick);
    result r;
    r.which = in.which;
    r.quantity = "stiffness in compression after the crack closed";
    r.unit = "Pa/m";
    r.measured = c.compressive_slope;
    r.reference = c.tensile_slope;  // the intact prism's, on the first pull
    r.error_rel = c.compressive_slope / c.tensile_slope - 1;
    r.tolerance = 0.02;
    // and no tension regained: the re-pull never carries more than the crack did at the push
    r.pass = std::abs(r.error_rel) <= r.tolerance && c.max_stress_after_closure <= c.stress_at_reversal;
    r.peak = c.peak;
    r.stress_at_reversal = c.stress_at_reversal;
    r.max_stress_after_closure = c.max_stress_after_closure;
    r.u = c.u;
    r.stress = c.stress;
    r.steps = c.steps;
    r.dt = c.dt;
    r.damping_in_force = c.damping_in_force;
    r.energy_error_rel = c.energy_error_rel;
    return r;
  }
  if (in.which == "bond") return detail::run_bond(in);
  const real theta = in.angle_deg * std::numbers::pi / 180, phi = in.friction_deg * std::numbers::pi / 180;
  const real s = in.size;
  // Deformable blocks: a base as deep as the block and no longer than the slide needs (a <= g sin
  // theta), so its zones stay few and well shaped.
  const auto base = [&](real half_length) {
    return geometry::convex_polyhedron::box({-half_length, in.deformable ? -0.75 * s : -s, in.deformable ? -s : -0.5 * s},
                                            {half_length, in.deformable ? 0.75 * s : s, 0});
  };
  if (in.which == "incline" || in.which == "topple") {
    const real h = s, b = in.which == "topple" ? in.aspect * h : s, d = s;
    const real weight = in.density * b * h * d * g;
    const real overlap = weight / (in.k_n * b * d);  // static on the level base
    // Deformable: 0.4 s (0.25 s quick), since the base must be as long as the slide and its
    // zones grow with it (1 s at theta 40 deg: a base of 7.8 m).
    const real duration = in.duration > 0 ? in.duration
                          : in.deformable ? (in.quick ? 0.25 : 0.4)
                          : in.quick      ? 0.4
                                          : 1.0;
    // Long enough for the slide at any angle: x = a T^2 / 2 with a <= g.
    const real half_length = in.deformable ? 0.5 * g * std::sin(theta) * duration * duration + 0.75 * (b + h)
                                           : 0.5 * g * duration * duration + 2 * (b + h);
    const std::vector<geometry::convex_polyhedron> cells{
        base(half_length), geometry::convex_polyhedron::box({-b / 2, -d / 2, -overlap}, {b / 2, d / 2, h - overlap})};
    const auto gravity = [theta](real t) {
      const real tilt = t < ramp_s ? theta * 0.5 * (1 - std::cos(std::numbers::pi * t / ramp_s)) : theta;
      return vec3(g * std::sin(tilt), 0, -g * std::cos(tilt));
    };
    // A deformable block set down at the rigid static overlap vibrates: undamped, its chatter
    // walks a sticking block down the slope (0.5 mm in 0.4 s at theta 20, phi 30 deg). Sticking
    // is a static question, so the deformable sticking incline takes local damping by default.
    const bool sticks = in.which == "incline" && theta < phi;
    const real gamma = in.damping >= 0 ? in.damping : in.deformable && sticks ? 0.8 : 0;
    result r = detail::run_scene(in, cells, gravity, gamma, duration);
    if (in.which == "incline") {
      if (theta < phi) {
        r.quantity = "slip after the run";
        r.unit = "m";
        r.measured = std::abs(r.x.back());
        r.reference = 0;
        r.tolerance = 1e-6;
        r.error_rel = r.measured / s;
        r.pass = r.measured < r.tolerance;
      } else {
        r.quantity = "acceleration down the slope";
        r.unit = "m/s^2";
        r.measured = detail::fitted_acceleration(r);
        r.reference = g * (std::sin(theta) - std::cos(theta) * std::tan(phi));
        r.tolerance = 0.01;
        r.error_rel = r.reference != 0 ? (r.measured - r.reference) / r.reference : r.measured;
        r.pass = std::abs(r.error_rel) < r.tolerance;
      }
    } else {
      r.quantity = "tilt of the block after the run";
      r.unit = "rad";
      r.measured = r.rotation.back();
      r.reference = std::atan(b / h);  // the tilt at which its centroid passes over the edge
      r.expected_mode = std::tan(theta) > b / h ? "topple" : theta > phi ? "slide" : "stable";
      r.mode = std::abs(r.measured) > 0.01 ? "topple" : std::abs(r.x.back()) > 1e-3 ? "slide" : "stable";
      r.error_rel = r.mode == r.expected_mode ? 0 : 1;
      r.pass = r.mode == r.expected_mode;
    }
    return r;
  }
  if (in.which == "stack") {
    std::vector<geometry::convex_polyhedron> cells{base(s)};
    for (int k = 0; k < in.blocks; ++k)
      cells.push_back(geometry::convex_polyhedron::box({-s / 2, -s / 2, k * s}, {s / 2, s / 2, (k + 1) * s}));
    const real duration = in.duration > 0 ? in.duration : in.quick ? 0.2 : 1.0;
    result r = detail::run_scene(in, cells, [](real) { return vec3(0, 0, -g); }, in.damping >= 0 ? in.damping : 0.8, duration);
    r.quantity = "vertical reaction of the base";
    r.unit = "N";
    r.tolerance = 1e-6;
    r.error_rel = (r.measured - r.reference) / r.reference;
    r.pass = std::abs(r.error_rel) < r.tolerance;
    return r;
  }
  // drop
  const std::vector<geometry::convex_polyhedron> cells{
      base(s), geometry::convex_polyhedron::box({-s / 2, -s / 2, in.drop_height}, {s / 2, s / 2, in.drop_height + s})};
  const real duration = in.duration > 0 ? in.duration : in.quick ? 0.3 : 1.0;
  result r = detail::run_scene(in, cells, [](real) { return vec3(0, 0, -g); }, in.damping >= 0 ? in.damping : 0.8, duration);
  r.quantity = "overlap at rest";
  r.unit = "m";
  r.tolerance = 0.01;
  r.error_rel = (r.measured - r.reference) / r.reference;
  r.pass = std::abs(r.error_rel) < r.tolerance;
  return r;
}

}  // namespace tessera::verification

