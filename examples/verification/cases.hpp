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

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "tessera/tessera.hpp"
#include "verification/reclose.hpp"

namespace tessera::verification {

using joint_law = law::cohesive_frictional<law::no_tension, law::elastic_compression, law::coulomb_residual>;
using contacts = contact::detected_contacts<joint_law>;
using undamped = integrator::central_difference<integrator::no_damping>;
using damped = integrator::central_difference<integrator::local_damping>;

/// Inputs of every case (SI; angles in degrees).
struct inputs {
  std::string which = "incline";
  real angle_deg = 20;      ///< incline angle theta
  real friction_deg = 30;   ///< joint friction angle phi
  real aspect = 1;          ///< topple: width / height b / h
  real size = 0.5;          ///< block edge (m); topple: the height h
  int blocks = 5;           ///< stack: blocks in the column
  real damping = -1;        ///< local damping gamma; < 0: the case's default (0 incline/topple, 0.8 stack/drop and a deformable sticking incline)
  real duration = -1;       ///< simulated time (s); < 0: the case's default
  real drop_height = 0.01;  ///< drop: initial gap (m)
  real k_n = 1e11;          ///< joint normal stiffness (Pa/m); k_s = k_n
  real density = 2400;      ///< kg/m^3
  real tolerance = 1e-3;    ///< contact tolerance (m)
  real cohesion = 3000;     ///< bond: cohesion c_0 of the bonded face (Pa); broken: friction alone
  bool deformable = false;  ///< incline, topple, stack, drop: deformable blocks instead of rigid ones
  real young = 30e9;        ///< deformable: Young's modulus (Pa); Poisson's ratio 0.2
  real zone_edge = -1;      ///< deformable: target zone edge (m); < 0: the block edge
  bool quick = false;       ///< shorter runs (tests)
};

/// What a case measured.
struct result {
  std::string which;
  real measured = 0, reference = 0, error_rel = 0, tolerance = 0;
  std::string quantity, unit;  ///< what measured/reference are
  std::string mode, expected_mode;  ///< topple: topple / slide / stable
  bool pass = false;
  real drift_m = 0;  ///< stack: motion of the top block over the second half of the run
  real energy_error_rel = 0;
  index_t steps = 0, rebuilds = 0, growths = 0, subcontacts = 0;
  real dt = 0;
  std::vector<double> t, x, z, rotation;  ///< curve: top (moving) block's centroid displacement and tilt
  // reclose: the path (top displacement m, axial stress Pa) and its figures (Pa)
  std::vector<double> u, stress;
  real peak = 0, stress_at_reversal = 0, max_stress_after_closure = 0;
  // bond: the shear force on the cube along the curve (N); the acceleration after the failure
  // (m/s^2) against the incline's, its error (relative to the reference, or to g when the block
  // should stick); the slide (m); the sub-contacts that started bonded and those that kept their
  // state at the last rebuild. peak: the shear force at failure; stress_at_reversal: the tilt then (rad)
  std::vector<double> force;
  real acceleration = 0, acceleration_reference = 0, acceleration_error = 0, slide_m = 0;
  index_t bonded_at_start = 0, kept_last_rebuild = 0;
  geometry::tessellation final_blocks;    ///< block geometry at the end (for VTK)
};

constexpr real g = 9.81;
constexpr real ramp_s = 0.1;  ///< incline and topple: time over which the tilt grows to theta (s)

/// The joint of every case.
[[nodiscard]] inline joint_law::params joint(const inputs& in) {
  joint_law::params p;
  p.k_n = in.k_n;
  p.k_s = in.k_n;
  p.shear.phi_0 = law::friction_angle::from_degrees(in.friction_deg);
  p.shear.phi_res = p.shear.phi_0;
  return p;
}

/// The tessellation with every vertex moved by its gridpoint's displacement.
[[nodiscard]] inline geometry::tessellation moved(const geometry::tessellation& tess, const geometry::block_mesh& mesh,
                                                 const node_set& gp) {
  geometry::tessellation t = tess;
  for (index_t i = 0; i < mesh.gridpoint_count(); ++i)
    if (const index_t v = mesh.gridpoint_vertex[static_cast<std::size_t>(i)]; v != invalid_index)
      t.vertices[static_cast<std::size_t>(v)] = mesh.gridpoints[static_cast<std::size_t>(i)] + gp.displacement.row(i).transpose();
  return t;
}

/// bond: the cube's weight W = rho b^3 g and the bond's failure force c_0 b^2 (N).
[[nodiscard]] inline real bond_weight(const inputs& in) { return in.density * in.size * in.size * in.size * g; }
[[nodiscard]] inline real bond_failure_force(const inputs& in) { return in.cohesion * in.size * in.size; }

/// Checks the inputs; throws invalid_input naming the value.
inline void validate(const inputs& in) {
  const auto positive = [](real v, const char* what) {
    require(std::isfinite(v) && v > 0, "verification: ", what, " = ", v, " must be finite and > 0");
  };
  require(in.which == "incline" || in.which == "topple" || in.which == "stack" || in.which == "drop" ||
              in.which == "reclose" || in.which == "bond",
          "verification: unknown case '", in.which, "' (incline, topple, stack, drop, reclose, bond)");
  require(std::isfinite(in.cohesion) && in.cohesion > 0 && in.cohesion <= 1e8, "verification: --cohesion = ",
          in.cohesion, " Pa must lie in (0, 1e8]");
  require(std::isfinite(in.angle_deg) && in.angle_deg >= 0 && in.angle_deg < 90, "verification: --angle-deg = ",
          in.angle_deg, " must lie in [0, 90)");
  require(std::isfinite(in.friction_deg) && in.friction_deg >= 0 && in.friction_deg < 90,
          "verification: --friction-deg = ", in.friction_deg, " must lie in [0, 90)");
  positive(in.aspect, "--aspect (b/h)");
  require(in.aspect <= 20, "verification: --aspect = ", in.aspect, " must be <= 20");
  positive(in.size, "--size (m)");
  positive(in.k_n, "--kn (Pa/m)");
  require(in.k_n <= 1e14, "verification: --kn = ", in.k_n, " Pa/m must be <= 1e14");
  positive(in.density, "density (kg/m^3)");
  positive(in.tolerance, "--tolerance (m)");
  require(in.tolerance < 0.1 * in.size, "verification: --tolerance = ", in.tolerance, " m must be below a tenth of the block (",
          0.1 * in.size, " m)");
  require(in.blocks >= 1 && in.blocks <= 200, "verification: --blocks = ", in.blocks, " must lie in [1, 200]");
  require(in.damping < 0 || (in.damping <= 1 && std::isfinite(in.damping)), "verification: --damping = ", in.damping,
          " must lie in [0, 1] (or be negative for the case's default)");
  require(in.duration < 0 || (in.duration > 0 && in.duration <= 100), "verification: --duration = ", in.duration,
          " s must lie in (0, 100]");
  require(std::isfinite(in.drop_height) && in.drop_height >= 0 && in.drop_height <= in.size,
          "verification: --drop-height = ", in.drop_height, " m must lie in [0, block size]");
  require(!in.deformable || (in.which != "reclose" && in.which != "bond"), "verification: --deformable applies to incline, topple, stack and drop, not to ",
          in.which, in.which == "reclose" ? " (its prism is deformable already)" : " (the bonded cube is rigid)");
  require(!in.deformable || (in.which != "incline" && in.which != "topple") || in.duration <= 2,
          "verification: --duration = ", in.duration, " s of a deformable ", in.which,
          " must be at most 2 s (its zoned base grows with the slide)");
  require(std::isfinite(in.young) && in.young > 0 && in.young <= 1e13, "verification: --young = ", in.young,
          " Pa must lie in (0, 1e13]");
  require(in.zone_edge < 0 || (std::isfinite(in.zone_edge) && in.zone_edge >= in.size / 20 && in.zone_edge <= in.size),
          "verification: --zone-edge = ", in.zone_edge, " m must lie in [", in.size / 20, ", ", in.size,
          "] (a twentieth of the block to the block; finer would take millions of zones) or be negative for the block edge");
  if (in.which == "bond") {
    const real weight = bond_weight(in), failure_force = bond_failure_force(in);
    require(weight * std::sin(in.angle_deg * std::numbers::pi / 180) > 1.05 * failure_force,
            "verification: --angle-deg = ", in.angle_deg, " never breaks the bond: it fails at a tilt of ",
            std::asin(std::min<real>(1, failure_force / weight)) * 180 / std::numbers::pi, " deg (c_0 b^2 = ",
            failure_force, " N against a weight of ", weight, " N); tilt further (5 % margin) or lower --cohesion");
  }
}

namespace detail {

/// Runs a scene of `cells` (cell 0 the base, fixed) under gravity `gravity` for `duration` s with
/// local damping gamma (0: undamped), recording the last block's motion.
/// `gravity(t)` is the acceleration of gravity at time t (m/s^2).
using gravity_field = std::function<vec3(real)>;
template <class Integrator>
result run_scene(const inputs& in, const std::vector<geometry::convex_polyhedron>& cells, const gravity_field& gravity,
                 real gamma, real duration);
inline result run_scene(const inputs& in, const std::vector<geometry::convex_polyhedron>& cells,
                        const gravity_field& gravity, real gamma, real duration) {
  return gamma > 0 ? run_scene<damped>(in, cells, gravity, gamma, duration)
                   : run_scene<undamped>(in, cells, gravity, gamma, duration);
}
/// Steps for `duration` s at the stable step dt; throws invalid_input past 2e8 (hours of run time).
inline index_t step_count(real duration, real dt) {
  const real n = std::ceil(duration / dt);
  require(n <= 2e8, "verification: ", duration, " s at the stable step ", dt, " s would take ", n,
          " steps (over 2e8, hours of run time): shorten --duration or lower --kn");
  return static_cast<index_t>(n);
}
/// Appends one curve sample of block b: time, x and z displacement, tilt about y (down the slope: +).
template <class Solver>
void record_motion(result& r, const Solver& s, index_t b) {
  const mat3 rot = s.blocks().rotation(b);
  r.t.push_back(s.time());
  r.x.push_back(s.blocks().displacement(b).x());
  r.z.push_back(s.blocks().displacement(b).z());
  r.rotation.push_back(std::atan2(rot(0, 2), rot(2, 2)));
}
/// Steps s through `duration` s (gravity(t) while t <= ramp_s), calling record() about 2 000 times
/// and at the end; returns the step count and top() (the moving block's displacement) at mid-run.
/// solver::run_until with stop::after_steps; the observers run after each step k in this order:
/// the mid-run sample, the record, then the gravity of step k + 1 while the tilt ramps.
template <class Solver, class Top, class Record>
std::pair<index_t, vec3> step_through(Solver& s, real duration, const gravity_field& gravity, Top&& top, Record&& record) {
  const index_t steps = step_count(duration, s.dt());
  const index_t every = std::max<index_t>(1, steps / 2000);
  const std::int64_t first = s.step_count();
  vec3 at_half = vec3::Zero();
  const auto ramp = [&] {
    if (s.time() <= ramp_s) s.set_gravity(gravity(s.time()));
  };
  ramp();  // the gravity of step 1
  s.run_until(
      stop::after_steps(steps), steps,
      [&](const Solver& sv) {
        if (sv.step_count() - first == steps / 2) at_half = top();
      },
      [&](const Solver& sv) {
        const std::int64_t k = sv.step_count() - first;
        if (k % every == 0 || k == steps) record();
      },
      [&](const Solver&) { ramp(); });
  return {steps, at_half};
}
/// The run's closing figures: step and contact statistics, energy balance, final geometry.
template <class Solver>
void record_end(result& r, const Solver& s, index_t steps, const geometry::tessellation& tess,
                const geometry::block_mesh& mesh) {
  r.steps = steps;
  r.rebuilds = s.contacts().rebuild_count();
  r.growths = s.contacts().growth_count();
  r.subcontacts = s.contacts().subcontact_count();
  r.energy_error_rel = s.energies().error_rel();
  r.final_blocks = moved(tess, mesh, s.gridpoints());
}
/// The scene of run_scene with deformable blocks (file comment).
template <class Integrator>
result run_scene_deformable(const inputs& in, const std::vector<geometry::convex_polyhedron>& cells,
                            const gravity_field& gravity, real gamma, real duration) {
  using elastic = blocks::deformable<zones::linear_elastic_tet>;
  const geometry::tessellation tess = geometry::separate_blocks(cells);
  geometry::zoning_options zoning;
  zoning.target_edge_length = in.zone_edge > 0 ? in.zone_edge : in.size;
  const geometry::block_mesh mesh = geometry::zone_blocks(tess, zoning);
  solver_options options;
  if (gamma > 0) options.damping_gamma = gamma;
  contacts::params cp(joint(in), in.tolerance);
  cp.deformable_blocks = true;
  solver<elastic, contacts, reinforcement::none, Integrator> s(tess, mesh, elastic::params{in.young, 0.2, in.density},
                                                               cp, {}, options);
  s.set_gravity(gravity(0));
  s.fix(s.gridpoints_on_plane(2, cells.front().bounds().lo.z(), 1e-9));
  result r;
  r.which = in.which;
  r.dt = s.dt();
  const index_t top = static_cast<index_t>(cells.size()) - 1;
  // A block's motion: the mass-weighted mean displacement of its gridpoints, its co-rotational
  // rotation for the tilt.
  const auto displacement = [&](index_t b) {
    vec3 u = vec3::Zero();
    real m = 0;
    for (index_t i = mesh.block_gridpoint_offsets[static_cast<std::size_t>(b)];
         i < mesh.block_gridpoint_offsets[static_cast<std::size_t>(b) + 1]; ++i) {
      u += s.gridpoints().mass[i] * s.gridpoints().displacement.row(i).transpose();
      m += s.gridpoints().mass[i];
    }
    return vec3(u / m);
  };
  const auto [steps, top_at_half] = step_through(s, duration, gravity, [&] { return displacement(top); }, [&] {
    const mat3& rot = s.blocks().rotation(top);
    const vec3 u = displacement(top);
    r.t.push_back(s.time());
    r.x.push_back(u.x());
    r.z.push_back(u.z());
    r.rotation.push_back(std::atan2(rot(0, 2), rot(2, 2)));
  });
  record_end(r, s, steps, tess, mesh);
  r.drift_m = (displacement(top) - top_at_half).norm();
  if (in.which == "stack") {
    // Every gridpoint's weight (no mass scaling here) against the fixed gridpoints' reactions.
    real weight = 0, reaction = 0;
    for (index_t i = 0; i < s.gridpoints().size(); ++i) {
      weight += s.gridpoints().mass[i] * g;
      reaction += s.gridpoints().reaction(i, 2);
    }
    r.measured = reaction;
    r.reference = weight;
  }
  if (in.which == "drop") {
    // The contacts' mean closure, -sum a u_n / sum a, against W / (k_n A) (the faces deform, so
    // there is no one overlap of the blocks' geometry).
    real closure = 0, area = 0, mass = 0;
    for (index_t i = 0; i < s.contacts().subcontact_count(); ++i) {
      closure -= s.contacts().area(i) * s.contacts().state(i).u_n;
      area += s.contacts().area(i);
    }
    for (index_t i = mesh.block_gridpoint_offsets[1]; i < mesh.block_gridpoint_offsets[2]; ++i) mass += s.gridpoints().mass[i];
    r.measured = closure / area;
    r.reference = mass * g / (in.k_n * in.size * in.size);
  }
  return r;
}

template <class Integrator>
result run_scene(const inputs& in, const std::vector<geometry::convex_polyhedron>& cells, const gravity_field& gravity,
                 real gamma, real duration) {
  if (in.deformable) return run_scene_deformable<Integrator>(in, cells, gravity, gamma, duration);
  const geometry::tessellation tess = geometry::separate_blocks(cells);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);
  solver_options options;
  if (gamma > 0) options.damping_gamma = gamma;
  using solver_type = solver<blocks::rigid, contacts, reinforcement::none, Integrator>;
  solver_type s(tess, mesh, blocks::rigid::params{in.density}, contacts::params(joint(in), in.tolerance), {}, options);
  s.set_gravity(gravity(0));
  s.fix(s.gridpoints_on_plane(2, cells.front().bounds().lo.z(), 1e-9));
  result r;
  r.which = in.which;
  r.dt = s.dt();
  const index_t top = s.blocks().block_count() - 1;
  const auto [steps, top_at_half] = step_through(
      s, duration, gravity, [&] { return s.blocks().displacement(top); }, [&] { record_motion(r, s, top); });
  record_end(r, s, steps, tess, mesh);
  r.drift_m = (s.blocks().displacement(top) - top_at_half).norm();
  if (in.which == "stack") {
    real weight = 0;
    for (index_t b = 0; b < s.blocks().block_count(); ++b) weight += s.blocks().weight_mass(b) * g;
    r.measured = s.blocks().reaction_force(0).z();
    r.reference = weight;
  }
  if (in.which == "drop") {
    // Overlap of the block's bottom below the base's top.
    r.measured = -(cells[1].bounds().lo.z() + s.blocks().displacement(1).z() - cells[0].bounds().hi.z());
    const real area = in.size * in.size;
    r.reference = s.blocks().weight_mass(1) * g / (in.k_n * area);
  }
  return r;
}

/// Least-squares a in x = c0 + c1 t + a t^2 / 2 over the second half of the curve.
[[nodiscard]] inline real fitted_acceleration(const result& r) {
  const std::size_t n = r.t.size(), first = n / 2;
  Eigen::MatrixXd a(static_cast<Eigen::Index>(n - first), 3);
  Eigen::VectorXd y(static_cast<Eigen::Index>(n - first));
  for (std::size_t k = first; k < n; ++k) {
    const auto row = static_cast<Eigen::Index>(k - first);
    a(row, 0) = 1;
    a(row, 1) = r.t[k];
    a(row, 2) = 0.5 * r.t[k] * r.t[k];
    y(row) = r.x[k];
  }
  return a.colPivHouseholderQr().solve(y)(2);
}

/// The bond case (file comment): a cube of edge b bonded (bond_faces) on a long fixed base; the
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
  const index_t steps = step_count(duration, s.dt());
  result r;
  r.which = in.which;
  r.dt = s.dt();
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
  const index_t every = std::max<index_t>(1, steps / 2000);
  bool broken = false;
  real force_before = 0;
  for (index_t k = 1; k <= steps; ++k) {
    const real tilt = theta * std::min<real>(1, s.time() / ramp);
    s.set_gravity(vec3(g * std::sin(tilt), 0, -g * std::cos(tilt)));
    s.step();
    if (!broken && failed()) {
      broken = true;
      r.peak = force_before;  // the last shear force the intact bond carried
      r.stress_at_reversal = tilt;
    }
    force_before = shear_force();
    if (k % every == 0 || k == steps) {
      record_motion(r, s, 1);
      r.force.push_back(force_before);
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


}  // namespace detail

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
