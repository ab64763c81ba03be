#pragma once
// The direct tension test of the study's plain-concrete prism (Pulatsu et al. 2020, Sec. 3) as a
// reusable routine: supports, quasi-static loading, recorders, the stop criterion and the
// post-processing of one run. Used by the direct_tension driver (outputs, CLI) and by
// benchmarks/work_precision_tension.cpp (error against run time).
//
// Supports. Bottom gridpoints (z = 0) fixed; top gridpoints (z = L) fixed transversally (the
// study's loading platens do not rotate) and pulled along +z with the prescribed velocity v(t).
//
// Loading (quasi-static). A velocity switched on at once sends a stress wave of amplitude
// sqrt(E rho) v through the (mass-scaled) prism, and the pre-peak curve becomes a staircase of
// wave reflections. The top velocity therefore rises as a half cosine,
//     v(t) = v_0 (1 - cos(pi t / T_r)) / 2   for t < T_r,   v_0 afterwards,
// whose acceleration starts and ends at zero, over T_r = n_r t_w (default n_r = 4) axial wave
// transits t_w = L sqrt(rho_eff / E), rho_eff = (scaled total mass) / (specimen volume): the
// static response is reached with a dynamic remainder that the local damping removes within a
// few transits.
//
// Mass scaling (the study scales masses too). The cost of a run is its number of steps,
// U / (v_0 dt) for a top displacement U, so the natural control is the top displacement per
// step du* (default 2 nm, 1/900 of the opening at peak f_T/k_n = 1.85 um of the 100-block
// contacts; 5 nm overshoots the peak of the top reaction by 5 % when the crack forms): the target step is dt* = du* / v_0 and the masses of every gridpoint whose own
// stable step is below dt* are raised until it is stable (integrator/timestep.hpp). When every
// gridpoint is scaled, the scaled masses grow as dt*^2 ~ 1/v_0^2 and the equations of motion in
// the displacement variable U = v_0 t no longer depend on v_0: the inertia of the run is set by
// du* alone (m v_0^2 ~ k du*^2). A lower rate at fixed du* therefore costs the same number of
// steps and approaches the fully scaled response; du* (or dt*) itself is the convergence
// parameter of the work-precision benchmark.
//
// Softening tail. Once the stress has fallen below tail_stress_ratio (0.3) x peak, one crack is
// open and the rest of the prism unloads slowly along the long power-law tail (the cut-off
// opening is 0.5 mm against 0.08 mm at the peak); the top velocity is then raised by the same
// half cosine to tail_speedup (4) x v_0, which cuts the steps of a run to separation by ~2.5.
//
// Quasi-static indicators (reported): the largest imbalance |R_top + R_bottom| of the axial
// support reactions relative to f_T A between the end of the ramp and the peak (zero in static
// equilibrium; it is the inertia force of the specimen), and the ratio of kinetic to elastic
// (zones + contact springs) energy at the peak. (The velocity field of uniform straining itself
// carries E_kin/E_el = rho v^2 / (3 E eps^2), which is large at small strain, so that ratio is
// only meaningful at the peak.)
//
// Stop criterion. Complete separation: no chain of blocks joined by sub-contacts with tensile
// capacity (not broken in tension, and not failed in shear while carrying no tension) links a
// block touching the bottom to one touching the top (union-find over the blocks each sample).
// Then every sub-contact of the through crack that opened has been pulled past the softening
// cut-off and has dissipated its full separation energy; what the crack still transmits is
// residual friction of shear-failed faces. Also stops at `max_displacement`, or (quick runs) when the stress has
// fallen below `stop_below_peak_ratio` x peak after the peak.
//
// Post-processing. Crack areas at the end (m^2): sub-contacts broken in tension (crack_area),
// failed in shear only (shear_crack_area), and the projection of the tension-broken area on the
// cross-section, sum A |n_z| (projected_crack_area; = A for one flat through crack, more for a
// tortuous or branched one). The tensile dissipation is split into that of the broken
// sub-contacts and that of the sub-contacts that softened without breaking (process zone). At
// the peak, the axial force carried across the final crack surface is decomposed into the part
// carried by normal stresses, sum A sigma_n |n_z|, and by shear stresses, sum A tau_z sgn(n_z)
// (both over the sub-contacts with tensile damage >= 0.5 at the end, in stress units over A).

#include <algorithm>
#include <functional>
#include <limits>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "common/cli.hpp"
#include "tessera/analysis/curves.hpp"
#include "tessera/io/vtk_contacts.hpp"
#include "common/scenes.hpp"
#include "tessera/law/concepts.hpp"
#include "../common/mpi_run.hpp"
#include "../common/phase_report.hpp"
#include "../common/quasi_static.hpp"
#include "../common/relaxed_scheme.hpp"
#include "tessera/presets.hpp"
#include "tessera/solver.hpp"
#include "tessera/solver/relaxation.hpp"

namespace tessera::scenes {

/// Loading and run control of one direct tension run (SI).
struct tension_loading {
  real rate = 0.005;               ///< top velocity v_0 after the ramp (m/s), > 0
  real step_displacement = 2e-9;   ///< target top displacement per step du* (m): dt* = du* / v_0
  real dt = 0;                     ///< > 0: mass-scaling target step (s), overrides step_displacement
  bool mass_scaling = true;        ///< false: physical masses, dt = safety x stable step
  real ramp_transits = 4;          ///< half-cosine ramp duration in axial wave transits (0 = none)
  real tail_speedup = 4;           ///< velocity factor on the softening tail (1 = constant rate)
  real tail_stress_ratio = 0.3;    ///< the tail starts past the peak once stress < this x peak
  real max_displacement = 1.5e-3;  ///< stop at this top displacement (m)
  bool stop_at_separation = true;  ///< stop at complete separation (see the file comment)
  real stop_below_peak_ratio = 0;  ///< > 0: stop once past the peak with stress < ratio x peak
  index_t sample = 100;              ///< steps between curve samples
  int threads = 0;                 ///< OpenMP threads (0 = library default)
  bool platen_restraint = true;    ///< top gridpoints fixed transversally (the study); false = free (frictionless platen)
  bool keep_fields = false;        ///< keep contact and zone snapshots at the peak and the end
  std::string label = "direct_tension";  ///< progress-line label
  bool progress = true;            ///< show a progress line on stderr
  /// Kinetic dynamic relaxation (solver/relaxation.hpp) instead of the explicit ramp: the top moved
  /// in increments of relax_increment (m) over relax_ramp steps, each held until the largest nodal
  /// unbalanced force is at most relax_tolerance x f_T A (at most relax_max_steps steps), one
  /// sample per increment; rate, step_displacement, dt, ramp and tail do not apply. Deformable blocks only.
  bool relaxation = false;
  real relax_increment = 2e-6, relax_tolerance = 1e-3;
  std::int64_t relax_ramp = 10, relax_max_steps = 1'000'000;
  /// Called once the run's checks have passed, before its first step (the driver creates its
  /// output directory there, so run.json says "running" from the run's first minute).
  std::function<void()> on_start;
};

/// Per-sub-contact and per-zone fields at one instant (VTK output, peak decomposition).
struct tension_snapshot {
  real time = 0, displacement = 0, stress = 0;  ///< s, m, Pa
  /// The sub-contacts with every declared state field (io/vtk_contacts.hpp): reference
  /// positions, displacements, normals, sigma_n_Pa, tau_Pa, ...
  io::vtk::contact_snapshot contacts;
  soa3 gridpoint_displacement;     ///< m
  zone_stress_matrix zone_stress;  ///< Pa, Voigt xx yy zz yz zx xy

  template <class Solver>
  void take(const Solver& s, bool with_zones) {
    contacts.take(s.contacts(), s.gridpoints());
    if (with_zones) {
      gridpoint_displacement = s.gridpoints().displacement;
      zone_stress = s.blocks().zone_stress();
    }
  }
};

/// Everything one run measures (SI).
struct tension_result {
  std::vector<real> displacement;                       ///< top displacement (m)
  std::vector<real> stress, stress_top, stress_bottom;  ///< axial stress: mean, from the top, from the bottom reaction (Pa)
  /// Largest nodal unbalanced force over f_T x cross-section, per sample (solver/balance.hpp).
  std::vector<real> unbalanced_ratio;
  real peak_stress = 0, peak_displacement = 0, initial_modulus = 0, residual_stress = 0;
  // energies (J)
  real boundary_work = 0, damping = 0, kinetic = 0, stored = 0;
  real dissipated = 0, dissipated_tension = 0, dissipated_shear = 0, dissipated_compression = 0;
  real dissipated_tension_broken = 0, dissipated_tension_unbroken = 0;
  real dissipated_tension_at_peak = 0, damping_at_peak = 0;  ///< distributed pre-peak cracking, damping up to the peak
  real energy_balance_error = 0;
  // crack (m^2)
  real crack_area = 0, shear_crack_area = 0, projected_crack_area = 0, process_zone_area = 0;
  bool separated = false;
  real separation_displacement = 0;  ///< m (0 if not separated)
  // Peak decomposition over the final crack, the sub-contacts with tensile damage >= 0.5 at the
  // end: axial force at the peak carried by their normal and shear stresses (Pa over the
  // cross-section), and their area and projected area sum A |n_z| (m^2).
  real peak_normal_part = 0, peak_shear_part = 0, peak_crack_area = 0, peak_crack_projected_area = 0;
  // quasi-static indicators
  real kinetic_to_elastic_at_peak = 0, reaction_imbalance_max = 0;
  // run
  real tail_displacement = 0;  ///< top displacement where the tail speed-up began (m; 0 = none)
  real dt = 0, ramp_time = 0, transit_time = 0, added_mass_ratio = 0;
  /// With loading.relaxation: increments, those that hit relax_max_steps before the tolerance,
  /// kinetic-energy resets, and the kinetic energy the resets removed (J; outside the energy books).
  std::int64_t relax_increments = 0, relax_unconverged = 0, relax_resets = 0;
  real relax_kinetic_removed = 0;
  std::int64_t steps = 0, subcontacts = 0, zones = 0, gridpoints = 0, blocks = 0;
  phase_times phases;  ///< time per phase of the step (solver::phases)
  std::string damping_in_force;  ///< the damping of the run (solver::damping_in_force())
  double runtime_s = 0;
  tension_snapshot at_peak, at_end;
};

/// Least-squares slope of stress against strain u/L over the pre-peak samples between 10 % and
/// 50 % of the peak (Pa); 0 if fewer than two samples qualify (analysis::band_slope).
[[nodiscard]] inline real initial_modulus(const tension_result& r, real length) {
  std::size_t end = 0;
  while (end < r.stress.size() && r.displacement[end] <= r.peak_displacement) ++end;
  return analysis::band_slope(r.displacement, r.stress, end, 0.1 * r.peak_stress, 0.5 * r.peak_stress, length);
}

/// Curve error of (u, s) against a reference (u_ref, s_ref): the L2 norm of the stress difference
/// over [0, u_max] divided by the reference peak,
///     e = sqrt( (1/u_max) int_0^u_max (s - s_ref)^2 du ) / max s_ref,
/// on 1000 uniform points (trapezoidal rule). u_max defaults to the shorter of the two curves.
[[nodiscard]] inline real curve_error_rel(const std::vector<real>& u, const std::vector<real>& s,
                                          const std::vector<real>& u_ref, const std::vector<real>& s_ref,
                                          real u_max = 0) {
  if (u.empty() || u_ref.empty()) return 1;
  if (!(u_max > 0)) u_max = std::min(u.back(), u_ref.back());
  const real peak = *std::max_element(s_ref.begin(), s_ref.end());
  return analysis::rms_curve_difference(u, s, u_ref, s_ref, u_max, 1000) / peak;
}

/// No load path left between the blocks on the two supports: the blocks joined by sub-contacts
/// that can still carry tension (not broken in tension, and not shear-failed without tension,
/// which hold only residual friction) form no chain from a bottom block to a top block.
class load_path_check {
 public:
  template <class Solver>
  load_path_check(index_t n_blocks, const Solver& s, const bc::node_group& bottom, const bc::node_group& top)
      : touches_bottom_(static_cast<std::size_t>(n_blocks), 0), touches_top_(touches_bottom_),
        parent_(static_cast<std::size_t>(n_blocks)) {
    for (index_t g : bottom.nodes) touches_bottom_[static_cast<std::size_t>(s.gridpoint_block(g))] = 1;
    for (index_t g : top.nodes) touches_top_[static_cast<std::size_t>(s.gridpoint_block(g))] = 1;
  }
  template <class Contacts>
  [[nodiscard]] bool separated(const Contacts& c) {
    using law = typename Contacts::law_type;
    const auto n_blocks = static_cast<index_t>(parent_.size());
    std::iota(parent_.begin(), parent_.end(), index_t{0});
    const auto root = [&](index_t b) {
      while (parent_[static_cast<std::size_t>(b)] != b)
        b = parent_[static_cast<std::size_t>(b)] = parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(b)])];
      return b;
    };
    for (index_t i = 0; i < c.size(); ++i) {
      const auto& st = c.state(i);
      const auto flags = law::status(st);
      if (tessera::law::has(flags, tessera::law::contact_status::broken_tension)) continue;
      if (tessera::law::has(flags, tessera::law::contact_status::slipped) && !(st.sigma_n > 0)) continue;
      const index_t a = root(c.block_a(i)), b = root(c.block_b(i));
      if (a != b) parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
    std::vector<char> bottom_root(static_cast<std::size_t>(n_blocks), 0);
    for (index_t b = 0; b < n_blocks; ++b)
      if (touches_bottom_[static_cast<std::size_t>(b)]) bottom_root[static_cast<std::size_t>(root(b))] = 1;
    for (index_t b = 0; b < n_blocks; ++b)
      if (touches_top_[static_cast<std::size_t>(b)] && bottom_root[static_cast<std::size_t>(root(b))]) return false;
    return true;
  }

 private:
  std::vector<char> touches_bottom_, touches_top_;
  std::vector<index_t> parent_;
};

/// The figures of the final state: energies, crack areas and the dissipation on and off the
/// crack, the peak decomposition over the final crack, the end snapshot, initial modulus, counts.
template <class Solver>
void read_tension_end(tension_result& r, const Solver& s, const prism_scene& scene, const tension_loading& in) {
  using law = typename Solver::law_type;
  const real length = scene.length(), area = scene.cross_section();
  const auto e = s.energies();
  const auto ce = s.contacts().energies();
  r.boundary_work = e.boundary_work;
  r.damping = e.damping_dissipated;
  r.kinetic = e.kinetic;
  r.stored = e.block_elastic + e.contact_stored;
  r.dissipated = ce.dissipated;
  r.dissipated_tension = ce.dissipated_tension;
  r.dissipated_shear = ce.dissipated_shear;
  r.dissipated_compression = ce.dissipated_compression;
  r.energy_balance_error = e.error_rel();
  r.residual_stress = r.stress.empty() ? 0 : r.stress.back();

  const auto& c = s.contacts();
  // The peak decomposition reads the peak snapshot's declared fields (io/vtk_contacts.hpp names).
  const auto* peak_sigma_n = r.at_peak.contacts.find("sigma_n_Pa");
  const auto* peak_tau = r.at_peak.contacts.find("tau_Pa");
  require(r.at_peak.contacts.size() == 0 || (peak_sigma_n != nullptr && peak_tau != nullptr),
          "direct_tension: the contact law declares no sigma_n or tau field");
  for (index_t i = 0; i < c.size(); ++i) {
    const auto& st = c.state(i);
    const auto flags = law::status(st);
    const real a = c.area(i), nz = c.normal(i).z();
    if (tessera::law::has(flags, tessera::law::contact_status::broken_tension)) {
      r.crack_area += a;
      r.projected_crack_area += a * std::abs(nz);
      r.dissipated_tension_broken += a * st.dissipated_tension;
    } else {
      r.dissipated_tension_unbroken += a * st.dissipated_tension;
      if (tessera::law::has(flags, tessera::law::contact_status::softening)) r.process_zone_area += a;
      if (tessera::law::has(flags, tessera::law::contact_status::slipped)) r.shear_crack_area += a;
    }
    const auto k = static_cast<std::size_t>(i);
    if (k < r.at_peak.contacts.size() && law::tensile_damage(c.subcontact_params(i), st) >= 0.5) {
      const real nz_peak = r.at_peak.contacts.normal[k].z();
      r.peak_crack_area += a;
      r.peak_crack_projected_area += a * std::abs(nz_peak);
      r.peak_normal_part += a * peak_sigma_n->values[k] * std::abs(nz_peak) / area;
      r.peak_shear_part += a * peak_tau->values[3 * k + 2] * (nz_peak >= 0 ? 1 : -1) / area;
    }
  }
  if (in.keep_fields) {
    r.at_end.take(s, true);
    r.at_end.time = s.time(), r.at_end.displacement = r.displacement.empty() ? 0 : r.displacement.back();
    r.at_end.stress = r.residual_stress;
  }
  r.initial_modulus = initial_modulus(r, length);
  r.dt = s.dt();
  r.added_mass_ratio = s.mass_scaling().original_mass > 0 ? s.mass_scaling().added_mass / s.mass_scaling().original_mass : 0;
  r.steps = s.step_count();
  r.phases = s.phases();
  r.damping_in_force = s.damping_in_force();
  r.subcontacts = c.size();
  r.zones = scene.mesh.zone_count();
  r.gridpoints = scene.mesh.gridpoint_count();
  r.blocks = scene.tess.cell_count();
}

/// The pull by kinetic relaxation (tension_loading::relaxation): increments of the top with the
/// linear predictor on the ramps until the stress has fallen 5 % below its peak (past a snap the
/// predictor would repeat it; relaxation_options::extrapolate), `observe` after each, until `stop`.
template <class Solver, class Observe>
void relax_tension(Solver& s, const tension_loading& in, real reference_force, const bool& stop, Observe&& observe,
                   tension_result& r) {
  if (stop) return;
  relaxation_options o;
  o.reference_force = reference_force;
  o.ratio_tolerance = in.relax_tolerance;
  o.max_steps = in.relax_max_steps;
  o.extrapolate = true;
  scenes::relax_increments(s, in.relax_increment, in.relax_ramp, o, [&](const Solver& sv) {
    observe(sv);
    return scenes::relaxed_sample{stop, r.stress.back() < 0.95 * r.peak_stress};
  }, r);
}

/// Runs the direct tension test on `scene` with solver type Solver and contact parameters
/// `law_params` (see the file comment). Throws what the solver throws (invalid_input,
/// numerical_instability).
/// One function on purpose (about 120 lines): the pull (ramp and tail speed-up) and the sampler
/// share the run's state (tail start, peak snapshot, stop rules), so the loading history reads
/// in one place; the separation test and the end-of-run figures are their own pieces.
template <class Solver, class LawParams>
[[nodiscard]] tension_result run_direct_tension(const prism_scene& scene, const LawParams& law_params,
                                                const tension_loading& in) {
  namespace bc = tessera::bc;
  namespace rec = tessera::recorders;
  require_positive(in.rate, "direct tension: loading rate (m/s)");
  require_positive(in.step_displacement, "direct tension: displacement per step (m)");
  require_non_negative(in.ramp_transits, "direct tension: ramp duration (wave transits)");
  require_positive(in.tail_speedup, "direct tension: tail speed-up factor");
  if (in.relaxation) {  // before anything is built or written; the options as advance checks them
    require(!Solver::blocks_type::is_rigid, "direct tension: kinetic relaxation takes deformable blocks, not rigid ones");
    require_positive(in.relax_increment, "direct tension: relaxation increment (m)");
    require_valid_relaxation({.reference_force = 1, .ratio_tolerance = in.relax_tolerance, .max_steps = in.relax_max_steps});
  }
  const cli::wall_timer timer;

  solver_options opt;
  if (in.mass_scaling) opt.mass_scaling_dt = in.dt > 0 ? in.dt : in.step_displacement / in.rate;
  if (in.relaxation) opt = kinetic_relaxation_options(opt);  // no damping, masses at dt = 1 s
  opt.threads = in.threads;
  Solver s(scene.tess, scene.mesh, scene.block_material, law_params, {}, opt);

  const real length = scene.length(), area = scene.cross_section(), f_t = law_params.tension.f_T;
  const real tol = 1e-9 * length;
  const bc::node_group bottom = s.gridpoints_on_plane(2, 0.0, tol);
  const bc::node_group top = s.gridpoints_on_plane(2, length, tol);
  s.fix(bottom);
  if (in.platen_restraint) s.fix(top, bc::transverse_to(2));
  // Relaxation: 1 m/s of pseudo-time, the load pattern kinetic_relaxation moves in increments.
  s.prescribe_velocity(top, vec3(0, 0, in.relaxation ? 1 : 0), bc::components::z);

  tension_result r;
  const real total_mass = s.mass_scaling().original_mass + s.mass_scaling().added_mass;
  const real mass = total_mass > 0 ? total_mass : s.gridpoints().mass.sum();
  r.transit_time = length * std::sqrt(mass / (length * area) / scene.young);
  r.ramp_time = in.relaxation ? 0 : in.ramp_transits * r.transit_time;
  if (!in.relaxation)
    require_quasi_static("direct_tension", in.rate, length, scene.young, concrete_density,
                       s.mass_scaling().original_mass > 0 ? s.mass_scaling().added_mass / s.mass_scaling().original_mass : 0,
                       f_t);
  // v(t) = v0 (1 - cos(pi t / T_r)) / 2 over the ramp, and on the tail (from t_tail) the same
  // half cosine from v0 to tail_speedup x v0; applied before each step to the half-step
  // velocity v(t + dt/2).
  real tail_start = -1;  // s, < 0: not on the tail yet
  const auto half_cosine = [&](real t) {
    return t >= r.ramp_time ? real(1) : real(0.5) * (1 - std::cos(std::numbers::pi * t / r.ramp_time));
  };
  const auto ramp = [&](const Solver& sv) {
    const real t_mid = sv.time() + 0.5 * sv.dt();
    real factor = 1;
    if (tail_start >= 0) {
      if (t_mid - tail_start > r.ramp_time + sv.dt()) return;
      factor = 1 + (in.tail_speedup - 1) * half_cosine(t_mid - tail_start);
    } else {
      if (t_mid > r.ramp_time + sv.dt()) return;
      factor = half_cosine(t_mid);
    }
    bc::update_velocity(s.gridpoints(), top, vec3(0, 0, in.rate * factor), bc::components::z);
  };
  if (!in.relaxation) ramp(s);

  // The separation test: no load path left between the blocks on the two supports.
  const index_t n_blocks = scene.tess.cell_count();
  load_path_check load_path(n_blocks, s, bottom, top);
  const auto separated_now = [&](const Solver& sv) { return load_path.separated(sv.contacts()); };

  std::vector<real> imbalance;
  std::size_t indicator_samples_to_peak = 0;
  if (in.on_start) in.on_start();
  cli::progress_line progress(in.label);
  bool stop = false;
  const auto observe = [&](const Solver& sv) {
    const real u = rec::mean_displacement(sv.gridpoints(), top).z();
    const real r_top = rec::reaction_sum(sv.gridpoints(), top).z();
    const real r_bottom = rec::reaction_sum(sv.gridpoints(), bottom).z();
    // Mean axial stress (tension +) from the two support reactions: R_top + R_bottom = -sum m a,
    // the inertia force of the specimen, so their mean is the static estimate and their
    // difference the quasi-static indicator below.
    const real sigma = 0.5 * (r_top - r_bottom) / area;
    r.displacement.push_back(u);
    r.stress.push_back(sigma);
    r.stress_top.push_back(r_top / area);
    r.stress_bottom.push_back(-r_bottom / area);
    r.unbalanced_ratio.push_back(sv.unbalanced_force().max_force / (f_t * area));
    if (sigma > r.peak_stress) {
      r.peak_stress = sigma;
      r.peak_displacement = u;
      r.at_peak.take(sv, in.keep_fields);
      r.at_peak.time = sv.time(), r.at_peak.displacement = u, r.at_peak.stress = sigma;
      const auto ce = sv.contacts().energies();
      r.dissipated_tension_at_peak = ce.dissipated_tension;
      r.damping_at_peak = sv.energies().damping_dissipated;
    }
    // Quasi-static indicators between the end of the ramp and the peak (past the peak the crack
    // releases elastic energy dynamically, which is physics, not a loading artefact).
    if (sv.time() > r.ramp_time && sigma > 0.9 * r.peak_stress) {
      const auto e = sv.energies();
      const real elastic = e.block_elastic + e.contact_stored;
      imbalance.push_back(std::abs(r_top + r_bottom) / (f_t * area));
      if (sigma >= r.peak_stress) {
        indicator_samples_to_peak = imbalance.size();
        r.kinetic_to_elastic_at_peak = elastic > 0 ? e.kinetic / elastic : 0;
      }
    }
    const bool past_peak = u > 1.2 * r.peak_displacement && r.peak_stress > 0.5 * f_t;
    if (tail_start < 0 && in.tail_speedup != 1 && past_peak && sigma < in.tail_stress_ratio * r.peak_stress) {
      tail_start = sv.time();
      r.tail_displacement = u;
    }
    if (in.stop_at_separation && past_peak && separated_now(sv)) {
      r.separated = true;
      r.separation_displacement = u;
      stop = true;
    }
    if (in.stop_below_peak_ratio > 0 && past_peak && sigma < in.stop_below_peak_ratio * r.peak_stress) stop = true;
    if (u >= in.max_displacement) stop = true;
    if (in.progress)
      progress.update(std::min(1.0, u / in.max_displacement),
                      tessera::detail::concat("u = ", u * 1e3, " mm, sigma = ", sigma * 1e-6, " MPa, peak ",
                                              r.peak_stress * 1e-6, " MPa"));
  };
  if (!in.relaxation) {
    run_sampled(s, scene.mesh, stop, ramp, in.sample, observe);  // split over MPI ranks under mpirun
  } else if constexpr (!Solver::blocks_type::is_rigid) {
    relax_tension(s, in, f_t * area, stop, observe, r);
  }
  progress.finish();

  for (std::size_t k = 0; k < indicator_samples_to_peak; ++k)
    r.reaction_imbalance_max = std::max(r.reaction_imbalance_max, imbalance[k]);
  read_tension_end(r, s, scene, in);
  if (in.relaxation) {
    // The resets remove kinetic energy, and the ramps move the huge relaxation masses of the top:
    // neither the boundary work nor the balance is a figure of the model (non-finite: null).
    r.boundary_work = r.energy_balance_error = std::numeric_limits<real>::quiet_NaN();
  }
  r.runtime_s = timer.seconds();
  return r;
}

/// The study's law on deformable or rigid blocks, power or linear softening (`softening` is
/// "power" or "linear"): the one dispatch direct_tension and calibrate share.
[[nodiscard]] inline tension_result run_prism_variant(const prism_scene& scene, const std::string& softening, bool rigid,
                                                      const tension_loading& loading) {
  const bool power = softening == "power";
  if (rigid) {
    if (power) return run_direct_tension<rigid_prism_solver>(scene, scene.contact, loading);
    return run_direct_tension<solver<blocks::rigid, contact::face_contacts<law::linear_tie_law>>>(
        scene, law::with_linear_softening(scene.contact), loading);
  }
  if (power) return run_direct_tension<prism_solver>(scene, scene.contact, loading);
  return run_direct_tension<prism_linear_solver>(scene, law::with_linear_softening(scene.contact), loading);
}

}  // namespace tessera::scenes
