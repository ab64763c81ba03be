#pragma once
// The scenes of the verification cases (cases.hpp, whose file comment describes them): blocks
// under gravity on a fixed base (cell 0), rigid or deformable, with the detected contacts of the
// case's joint, stepped through a run while the last block's motion is recorded; the run's
// closing figures; and the fit of the acceleration over the second half of the run.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "tessera/blocks/deformable.hpp"
#include "tessera/blocks/linear_elastic_tet.hpp"
#include "tessera/blocks/rigid.hpp"
#include "tessera/geometry/block_mesh.hpp"
#include "tessera/geometry/convex_polyhedron.hpp"
#include "tessera/geometry/tessellation.hpp"
#include "tessera/geometry/zoning.hpp"
#include "tessera/reinforcement/none.hpp"
#include "tessera/solver/solver.hpp"
#include "tessera/solver/stop_conditions.hpp"
#include "verification/inputs.hpp"

namespace tessera::verification {

/// The tessellation with every vertex moved by its gridpoint's displacement.
[[nodiscard]] inline geometry::tessellation moved(const geometry::tessellation& tess, const geometry::block_mesh& mesh,
                                                 const node_set& gp) {
  geometry::tessellation t = tess;
  for (index_t i = 0; i < mesh.gridpoint_count(); ++i)
    if (const index_t v = mesh.gridpoint_vertex[static_cast<std::size_t>(i)]; v != invalid_index)
      t.vertices[static_cast<std::size_t>(v)] = mesh.gridpoints[static_cast<std::size_t>(i)] + gp.displacement.row(i).transpose();
  return t;
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
/// Steps s through `duration` s of simulated time (gravity(t) while t <= ramp_s), calling record()
/// about 2 000 times (every duration / 2000 s) and at the end; returns the step count and top()
/// (the moving block's displacement) at mid-run (the first step at or past duration / 2). By time,
/// not by a step count fixed at the start: rigid blocks on detected contacts choose dt again at
/// each rebuild (docs/model.md, "Stable step"). The run ends at the first step whose time reaches
/// the duration (within 1e-9 of a step, so a constant dt gives ceil(duration / dt) steps);
/// step_count bounds it. The observers run after each step in this order: the mid-run sample, the
/// record, then the gravity of the next step while the tilt ramps.
template <class Solver, class Top, class Record>
std::pair<index_t, vec3> step_through(Solver& s, real duration, const gravity_field& gravity, Top&& top, Record&& record) {
  const real t0 = s.time(), every = duration / 2000;
  // The largest count the run may take: the step may only shrink by what the contacts present can
  // add, so 100 x the steps at the start's dt is a guard against a runaway, not a limit a run meets.
  const index_t most = step_count(100 * duration, s.dt());
  const auto reached = [&](const Solver& sv, real t) { return sv.time() - t0 + 1e-9 * sv.dt() >= t; };
  vec3 at_half = vec3::Zero();
  bool half_taken = false;
  real next_sample = every;
  const auto ramp = [&] {
    if (s.time() <= ramp_s) s.set_gravity(gravity(s.time()));
  };
  ramp();  // the gravity of step 1
  const run_result run = s.run_until(
      stop::when([&](const Solver& sv) { return reached(sv, duration); }, "the duration reached"), most,
      [&](const Solver& sv) {
        if (!half_taken && reached(sv, duration / 2)) {
          at_half = top();
          half_taken = true;
        }
      },
      [&](const Solver& sv) {
        const bool end = reached(sv, duration);
        if (end || reached(sv, next_sample)) {
          record();
          while (reached(sv, next_sample)) next_sample += every;
        }
      },
      [&](const Solver&) { ramp(); });
  require(!run.hit_max_steps, "verification: ", duration, " s not reached in ", most, " steps (dt fell to ", s.dt(),
          " s)");
  return {static_cast<index_t>(run.steps), at_half};
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
/// The scene of run_scene with deformable blocks (cases.hpp's file comment).
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
  r.damping_in_force = s.damping_in_force();
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
  r.damping_in_force = s.damping_in_force();
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

}  // namespace detail

}  // namespace tessera::verification
