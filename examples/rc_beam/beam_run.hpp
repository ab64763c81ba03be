#pragma once
// One run of the RC beam (beam.hpp): supports and loading, the samples, the events and the
// figures of beam_result. The crack analysis and the failure mode: beam_cracks.hpp; the tied
// plates (--plates tied): beam_plates.hpp.
//
// The load. P = twice the support reaction (both half-spans; the full beam, --span full: the sum of
// its two, beam_span.hpp): the force the beam delivers to its supports, the load cell of a test.
// The force on the loading plate's gridpoints is larger by the local damping's drag on the beam, which moves down as it deflects (F_d = -0.8 |F| sgn(v)
// opposes the motion even in steady deflection; measured on the 250-block beam: 10 kN on a 56 kN
// plateau). curve.csv keeps both. The events (first crack, peak, failure) read the load smoothed
// over beam_loading::smoothing of deflection (the reactions of a mass-scaled explicit run
// oscillate).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/mpi_run.hpp"
#include "rc_beam/beam.hpp"
#include "rc_beam/beam_cracks.hpp"
#include "rc_beam/beam_plates.hpp"
#include "rc_beam/beam_relaxed.hpp"
#include "rc_beam/beam_failure_rule.hpp"
#include "rc_beam/beam_result.hpp"
#include "rc_beam/beam_shear.hpp"
#include "rc_beam/beam_span.hpp"
#include "tessera/contact/platen.hpp"
#include "tessera/io/checkpoint.hpp"

namespace tessera::scenes {

/// Runs the beam with contact law Law, by the explicit loading (Relaxed = false) or by kinetic
/// relaxation (Relaxed = true, loading.relaxation: relax_beam). on_event(solver, tag) at "start"
/// (every check passed, the first step next), "first_crack", "yield", "end" (the peak is not
/// known until the end).
template <class Law, bool Relaxed = false, class OnEvent>
[[nodiscard]] beam_result run_beam(const beam_scene& scene, const typename Law::params& law_params,
                                   const beam_loading& loading, OnEvent&& on_event) {
  using solver_type = std::conditional_t<Relaxed, beam_solver<Law, checks::no_step_checker>, beam_solver<Law>>;
  require(loading.relaxation == Relaxed, "rc_beam: run_beam<", Relaxed ? "relaxed" : "explicit",
          "> called with beam_loading::relaxation ", loading.relaxation ? "true" : "false");
  if constexpr (Relaxed) check_beam_relaxation(scene.options, loading);
  const cli::wall_timer timer;
  const beam_options& o = scene.options;
  const beam_hand_checks& hand = scene.hand;
  solver_options opt;
  opt.mass_scaling_ratio = loading.dt > 0 ? 0 : loading.added_mass_ratio;
  opt.mass_scaling_dt = loading.dt;
  opt.threads = loading.threads;
  opt.damping_gamma = loading.damping_gamma;
  if constexpr (Relaxed) opt = kinetic_relaxation_options(opt);  // no damping, masses at dt = 1 s; the plates keep theirs
  solver_type s(scene.tess, scene.mesh, scene.block_material, law_params, scene.bar, opt);
  const real L = o.half_length(), tol = 1e-9 * L;
  // Steel plates of their own (--plates contact): registered before the mass scaling is read,
  // since their contact springs join the gridpoints' stiffness bounds.
  const bool contact_plates = o.plates == "contact";
  const int sides = o.full() ? 2 : 1;  // the full beam's right support and loading plate: side 1
  std::array<std::optional<contact::rigid_platen<Law>>, 2> support_platen, loading_platen;
  if (contact_plates) {
    auto plate = law_params;  // the plate-concrete pair: frictional at the study's phi_0, no cohesion, never bonded
    plate.shear.c_res = 0;
    plate.shear.phi_res = law::friction_angle::from_degrees(beam_plate_friction_deg);
    if (plate.shear.phi_res.radians() > plate.shear.phi_0.radians()) plate.shear.phi_0 = plate.shear.phi_res;
    if constexpr (Law::softens_with_slip)  // never bonded, so only the residual acts: G_II just has to pass validate
      plate.shear.G_II = std::max(plate.shear.G_II, plate.shear.c_0 * plate.shear.c_0 / plate.k_s);
    if constexpr (Law::softens_with_crushing) plate.compression.residual = 1;  // steel on concrete does not crush
    contact::platen_motion m;
    m.mass = 7850 * o.plate * o.width * o.plate_thickness;
    m.inertia = m.mass * (o.plate * o.plate / 12 + o.plate_thickness * o.plate_thickness / 3);  // about the contact face's axis
    m.free_translation = {true, false, false};  // rolls in x, driven or held in y, held in z
    m.hinge_axis = vec3::UnitZ();
    m.damping_gamma = loading.damping_gamma;
    m.quasi_static = Relaxed;  // a relaxation's plates follow the concrete without ringing (platen.hpp)
    const real z = 0.5 * o.width;
    for (int k = 0; k < sides; ++k) {
      const real xs = o.on_side(k, o.support_x()), xl = o.on_side(k, o.load_x());
      support_platen[k].emplace(scene.mesh,
                                contact::platen_geometry{vec3(xs, 0, z), vec3::UnitY(), vec3::UnitX(), 0.5 * o.plate,
                                                         0.5 * o.width, tol},
                                m, plate);
      loading_platen[k].emplace(scene.mesh,
                                contact::platen_geometry{vec3(xl, o.height, z), -vec3::UnitY(), vec3::UnitX(),
                                                         0.5 * o.plate, 0.5 * o.width, tol},
                                m, plate);
      support_platen[k]->attach(s);
      loading_platen[k]->attach(s);
    }
  }
  beam_result r;
  const auto& ms = s.mass_scaling();
  r.added_mass_ratio = ms.original_mass > 0 ? ms.added_mass / ms.original_mass : 0;
  r.quasi_static_index = Relaxed ? std::numeric_limits<real>::quiet_NaN()  // no rate: every sample is static
                                 : beam_quasi_static_index(scene, loading.rate, r.added_mass_ratio);
  if (r.quasi_static_index > quasi_static_limit)
    throw invalid_input(tessera::detail::concat(
        "rc_beam: loading rate ", loading.rate, " m/s with added mass ", r.added_mass_ratio,
        "x is not quasi-static: the plate moves ", r.quasi_static_index,
        " x the deflection at first cracking during one period of the first bending mode (limit ", quasi_static_limit,
        "); use a rate <= ", loading.rate * quasi_static_limit / r.quasi_static_index,
        " m/s or less mass scaling (--added-mass / --dt)"));

  node_set& gp = s.gridpoints();
  if (!o.full()) s.fix(s.gridpoints_on_plane(0, L, tol), bc::along(0));
  std::array<bc::node_group, 2> support, plate;  // the gridpoints under each plate, [1] the full beam's right
  std::array<std::optional<hinged_plate>, 2> support_plate, loading_plate;
  for (int k = 0; k < sides; ++k) {
    const real xs = o.on_side(k, o.support_x()), xl = o.on_side(k, o.load_x());
    support[k] = beam_strip(gp, 0, xs - o.plate / 2, xs + o.plate / 2, tol, "support plate");
    plate[k] = beam_strip(gp, o.height, xl - o.plate / 2, xl + o.plate / 2, tol, "loading plate");
    require(!support[k].nodes.empty() && !plate[k].nodes.empty(), "rc_beam: no gridpoints under a plate");
    if (contact_plates) continue;
    s.fix(support[k], bc::along(1) | bc::along(2));
    bc::prescribe_velocity(gp, plate[k], vec3::Zero(), bc::along(1));
    support_plate[k].emplace(gp, support[k], xs);
    loading_plate[k].emplace(gp, plate[k], xl);
  }
  if (o.full()) {  // held in x: the gridpoint nearest the middle of the mid-span section (beam_span.hpp)
    const vec3 centre(L, 0.5 * o.height, 0.5 * o.width);
    const auto distance2 = [&](index_t i) { return (gp.reference.row(i).transpose() - centre).squaredNorm(); };
    index_t pin = 0;
    for (index_t i = 1; i < gp.size(); ++i)
      if (distance2(i) < distance2(pin)) pin = i;
    s.fix(bc::node_group{{pin}, "mid-span pin"}, bc::along(0));
  }
  if (!o.full())
    for (int b = 0; b < o.bars; ++b) {
      const index_t last = s.reinforcement().bar_nodes(b).second - 1;
      bc::fix(s.bar_nodes(), bc::node_group{{last}, "bar end on the symmetry face"}, bc::along(0));
    }
  const beam_midspan_gauge midspan(gp, o, hand.mean_block_size, tol);

  const real ramp = loading.ramp_time >= 0 ? loading.ramp_time : beam_first_mode_period(scene, r.added_mass_ratio);
  r.ramp_time = Relaxed ? std::numeric_limits<real>::quiet_NaN() : ramp;  // a relaxation has no ramp in time
  std::optional<beam_spreader> spreader;
  if (o.full()) spreader.emplace(0.1 * (ms.original_mass + ms.added_mass));
  // The plates before a step, the loading plate(s) moving down at v (m/s); stopped: a
  // relaxation's reset, whose step starts every free body from rest (solver/relaxation.hpp).
  const auto drive_at = [&](const solver_type& sv, real v, bool stopped) {
    if (stopped) {  // the steel plates of a relaxation have no inertia (m.quasi_static)
      if (spreader) spreader->stop();
      for (int k = 0; k < sides && !contact_plates; ++k) support_plate[k]->stop(), loading_plate[k]->stop();
    }
    real tilt = 0;  // the full beam's spreader: the left plate moves down at v + tilt, the right at v - tilt
    if (o.full()) {
      std::array<real, 2> f{};  // each loading plate's downward force on the beam at the last step
      for (int k = 0; k < 2; ++k)
        if (contact_plates)
          f[k] = loading_platen[k]->force().y();
        else
          for (index_t n : plate[k].nodes) f[k] -= gp.reaction(n, 1);
      tilt = spreader->advance(f[0], f[1], sv.dt(), loading.damping_gamma);
    }
    for (int k = 0; k < sides; ++k) {
      const real down = o.full() ? v + (k == 0 ? tilt : -tilt) : v;  // plate k's downward speed (m/s)
      if (contact_plates) {
        loading_platen[k]->set_velocity(vec3(0, -down, 0));
        loading_platen[k]->update(s);
        support_platen[k]->update(s);
      } else {
        loading_plate[k]->drive(gp, -down, sv.dt(), loading.damping_gamma);
        support_plate[k]->drive(gp, 0, sv.dt(), loading.damping_gamma);
      }
    }
  };
  const auto drive = [&](const solver_type& sv) {  // the explicit loading: a half-cosine ramp to the rate
    const real t = sv.time() + 0.5 * sv.dt();
    drive_at(sv, t >= ramp ? loading.rate : 0.5 * loading.rate * (1 - std::cos(std::numbers::pi * t / ramp)), false);
  };
  const beam_cracks analyser(s.contacts(), gp, o.height, hand.mean_block_size);
  cli::progress_line progress("rc_beam");
  bool done = false, first_found = false, inclined_found = false, yield_reported = false;
  const std::size_t window = Relaxed ? 1 : std::max<std::size_t>(  // a relaxed sample is static: no smoothing
      1, static_cast<std::size_t>(std::llround(loading.smoothing / (loading.rate * s.dt() * static_cast<real>(loading.sample)))));
  double window_sum = 0;
  real max_load = 0;
  index_t samples = 0;
  std::vector<index_t> soffit;  // sub-contacts of the constant-moment zone's soffit (y <= h/10)
  for (index_t i = 0; i < s.contacts().size(); ++i)
    if (s.contacts().position(i, gp).y() <= 0.1 * o.height && beam_in_moment_zone(o, s.contacts().position(i, gp).x()))
      soffit.push_back(i);
  real soffit_peak_load = 0, soffit_peak_deflection = 0;
  beam_opening_history history(loading.history_step);
  std::array<std::optional<beam_shear_sections>, 2> shear_sections;  // [1] the full beam's right span
  for (int k = 0; k < sides; ++k) {
    std::vector<real> xs;
    for (real f : {0.25, 0.5, 0.75}) xs.push_back(o.on_side(k, o.support_x() + f * o.shear_span));
    shear_sections[k].emplace(scene.tess, s.contacts(), s.reinforcement(), s.bar_nodes(), xs, k == 1);
  }
  // The run's whole state for a checkpoint, taken at a sample (after the plates' drive for the
  // next step): the solver's (with the forces the steel plates wrote for the next step), the
  // plates' and the spreader's motion, and the samples and events so far.
  double runtime_before = 0;  // s: the wall time before the checkpoint a resumed run started from
  const auto run_state = [&](auto& ar) {
    s.checkpoint(ar);
    for (int k = 0; k < sides; ++k) {
      const std::string side = k == 0 ? "" : "right_";
      if (contact_plates) {
        support_platen[k]->checkpoint(ar, "beam/" + side + "support_platen");
        loading_platen[k]->checkpoint(ar, "beam/" + side + "loading_platen");
      } else {
        support_plate[k]->checkpoint(ar, "beam/" + side + "support_plate");
        loading_plate[k]->checkpoint(ar, "beam/" + side + "loading_plate");
      }
    }
    if (spreader) spreader->checkpoint(ar);
    checkpoint_beam_samples(ar, r);
    checkpoint_failure_rule(ar, loading, r);
    history.checkpoint(ar);
    ar.scalar("beam/run/window_sum", window_sum);
    ar.scalar("beam/run/max_load", max_load);
    ar.scalar("beam/run/samples", samples);
    ar.scalar("beam/run/first_found", first_found);
    ar.scalar("beam/run/inclined_found", inclined_found);
    ar.scalar("beam/run/yield_reported", yield_reported);
    ar.scalar("beam/run/soffit_peak_load", soffit_peak_load);
    ar.scalar("beam/run/soffit_peak_deflection", soffit_peak_deflection);
    double runtime = runtime_before + timer.seconds();
    ar.scalar("beam/run/runtime_s", runtime);
    if (ar.loading()) runtime_before = runtime;
  };
  double last_checkpoint = 0;  // s of this process's wall time
  const auto save_state = [&] {
    io::save_checkpoint(io::checkpoint_of(run_state), loading.checkpoint_file, loading.run_key);
    ++r.checkpoints_written;
    last_checkpoint = timer.seconds();
  };
  if (!loading.resume_file.empty()) {
    // The flags first, for a refusal that names them; then the state, every record checked
    // against this model before anything is copied (io::load_checkpoint).
    require_beam_run_key(loading);
    auto model = io::checkpoint_of(run_state);
    (void)io::load_checkpoint(model, loading.resume_file);
    r.resumed_at_step = s.step_count();
    r.runtime_before_resume_s = runtime_before;
  } else if (contact_plates && !Relaxed) {
    drive(s);  // the plates' forces for the first step (a relaxation drives them before every step)
  }
  on_event(std::as_const(s), std::string("start"));  // every check has passed: the run (re)starts
  const auto sample = [&](const solver_type& sv) {
    // Per side: the loading and support plates' forces on the concrete, the loading plate's travel
    std::array<real, 2> fp{}, fs{}, up{};
    for (int k = 0; k < sides; ++k)
      if (contact_plates) {
        fp[k] = -loading_platen[k]->force().y();
        fs[k] = -support_platen[k]->force().y();
        up[k] = loading_platen[k]->displacement().y();
      } else {
        for (index_t n : plate[k].nodes) fp[k] += sv.gridpoints().reaction(n, 1), up[k] += sv.gridpoints().displacement(n, 1);
        up[k] /= static_cast<real>(plate[k].nodes.size());  // the mean over the tied gridpoints
        for (index_t n : support[k].nodes) fs[k] += sv.gridpoints().reaction(n, 1);
      }
    const real raw = o.full() ? fs[0] + fs[1] : 2 * fs[0], defl = midspan.deflection(sv.gridpoints());
    if (o.full())
      for (int k = 0; k < 2; ++k) r.spans[k].reaction.push_back(fs[k]), r.spans[k].plate_load.push_back(-fp[k]);
    r.deflection.push_back(defl);
    r.load.push_back(raw);
    window_sum += raw;
    if (r.load.size() > window) window_sum -= r.load[r.load.size() - 1 - window];
    const real load = window_sum / static_cast<real>(std::min(window, r.load.size()));
    r.smoothed_load.push_back(load);
    r.plate_load.push_back(o.full() ? -(fp[0] + fp[1]) : -2 * fp[0]);
    r.load_point_deflection.push_back(o.full() ? -0.5 * (up[0] + up[1]) : -up[0]);
    if (load > max_load) {
      max_load = load, r.peak_load = load, r.peak_deflection = defl;
      r.shear_at_peak = shear_sections[0]->split(sv.contacts(), sv.reinforcement(), sv.bar_nodes(), fs[0]);
      for (int k = 0; k < sides && o.full(); ++k) {
        r.spans[k].reaction_at_peak = fs[k];
        r.spans[k].plate_load_at_peak = -fp[k];
        r.spans[k].shear_at_peak = shear_sections[k]->split(sv.contacts(), sv.reinforcement(), sv.bar_nodes(), fs[k]);
      }
    }
    history.record(sv.contacts(), sv.gridpoints(), defl, load);
    if (r.first_crack_load == 0) {
      // Mean bending stress of the soffit: sum A t_x n_x / sum A n_x^2 over its sub-contacts
      // (t = sigma_n n + tau; equals sigma_xx for a uniform stress field).
      double num = 0, den = 0;
      for (index_t i : soffit) {
        const auto& st = sv.contacts().state(i);
        const vec3 n = sv.contacts().normal(i);
        const real a = sv.contacts().area(i);
        num += a * (st.sigma_n * n.x() + st.tau.x()) * n.x();
        den += a * n.x() * n.x();
      }
      const real sigma = den > 0 ? num / den : 0;
      if (sigma >= law_params.tension.f_T && load >= 0.2 * hand.first_crack_load) {
        r.first_crack_load = load;
        r.first_crack_deflection = defl;
        if (Relaxed && sigma > r.soffit_peak_stress && soffit_peak_load > 0) {  // samples an increment apart:
          const real w = (law_params.tension.f_T - r.soffit_peak_stress) / (sigma - r.soffit_peak_stress);  // f_T between
          r.first_crack_load = soffit_peak_load + w * (load - soffit_peak_load);
          r.first_crack_deflection = soffit_peak_deflection + w * (defl - soffit_peak_deflection);
        }
        r.soffit_peak_stress = sigma;
      } else if (sigma > r.soffit_peak_stress) {
        r.soffit_peak_stress = sigma;
        soffit_peak_load = load;
        soffit_peak_deflection = defl;
      } else if (sigma < 0.95 * r.soffit_peak_stress && load >= 0.2 * hand.first_crack_load) {
        r.first_crack_load = soffit_peak_load;
        r.first_crack_deflection = soffit_peak_deflection;
      }
    }
    r.crack_count.push_back(-1);
    const bool spans_open = o.full() && (r.spans[0].first_inclined_crack_deflection < 0 ||
                                         r.spans[1].first_inclined_crack_deflection < 0);
    if (samples++ % (Relaxed ? 1 : loading.crack_every) == 0 && (!first_found || !inclined_found || spans_open)) {
      const auto cracks = analyser.evaluate(sv.contacts(), sv.gridpoints(), 0);
      r.crack_count.back() = static_cast<real>(cracks.size());
      for (const beam_crack& c : cracks) {
        if (c.vertical() && !first_found && c.y_min <= 0.25 * o.height) {
          first_found = true;
          r.developed_crack_load = max_load;
          r.developed_crack_deflection = defl;
          r.first_crack_x = c.x;
          r.first_crack_angle_deg = c.angle_deg;
          on_event(sv, std::string("first_crack"));
        }
        // An inclined crack in the shear span: a diagonal (shear) crack. A short tortuous crack in
        // the constant-moment zone can fit an inclined line too; it is a flexural crack.
        const int span = c.vertical() ? -1 : beam_shear_span_of(o, c.x, 0);
        if (span >= 0 && o.full() && r.spans[span].first_inclined_crack_deflection < 0) {
          r.spans[span].first_inclined_crack_load = load;
          r.spans[span].first_inclined_crack_deflection = defl;
          r.spans[span].first_inclined_crack_x = c.x;
        }
        if (span >= 0 && !inclined_found) {
          inclined_found = true;
          r.first_inclined_crack_load = load;
          r.first_inclined_crack_deflection = defl;
          r.first_inclined_crack_x = c.x;
          r.first_inclined_crack_span = span;
          r.shear_at_inclined_crack = shear_sections[span]->split(sv.contacts(), sv.reinforcement(), sv.bar_nodes(), fs[span]);
          if (!first_found) r.inclined_before_vertical = true;
        }
      }
    }
    if (!r.steel_yielded) {
      const beam_bar& bar = sv.reinforcement();
      for (index_t e = 0; e < bar.element_count(); ++e)
        if (bar.plastic_elongation(e) > 0) {
          r.steel_yielded = true;
          r.yield_load = load;
          r.yield_deflection = defl;
          break;
        }
      if (r.steel_yielded && !yield_reported) {
        yield_reported = true;
        on_event(sv, std::string("yield"));
      }
    }
    const bool failed = beam_failure_at_sample(r, loading, first_found, load, defl, max_load, sv.contacts(), sv.gridpoints(), history, o, hand.mean_block_size);
    const bool quick_done = loading.first_crack_only > 0 && first_found &&
                            defl >= loading.first_crack_only * r.developed_crack_deflection;
    r.failure_reached = failed;  // the last sample's: whether the run stopped at the load drop
    done = defl >= loading.max_deflection || failed || quick_done;
    if (loading.progress)
      progress.update(std::min(1.0, defl / loading.max_deflection),
                      tessera::detail::concat("deflection ", defl * 1e3, " mm, P = ", load * 1e-3, " kN",
                                              first_found ? ", cracked" : "", r.steel_yielded ? ", yielded" : ""));
    // The run's last state is saved after the loop (it is this sample's).
    if (!done && !loading.checkpoint_file.empty() && loading.checkpoint_every > 0 &&
        timer.seconds() - last_checkpoint >= loading.checkpoint_every)
      save_state();
  };
  if constexpr (Relaxed) {
    relax_beam(s, hand, loading, drive_at, sample, done, r);
  } else {
    // One process: s.run_until; split over MPI ranks, the plates' gridpoints kept current on every rank.
    run_sampled(s, scene.mesh, done, drive, loading.sample, sample,
                beam_plate_rows(sides, support_platen, loading_platen, support, plate));
  }
  // The end state, before the end's analysis changes the history: a resume with a larger
  // --max-deflection continues from it as if the run had not stopped.
  if (!loading.checkpoint_file.empty()) save_state();
  progress.finish();
  on_event(std::as_const(s), std::string("end"));

  // Curve figures. A run that ends before the soffit stress has fallen 5 % keeps its peak so far.
  if (r.first_crack_load == 0 && soffit_peak_load >= 0.2 * hand.first_crack_load) {
    r.first_crack_load = soffit_peak_load;
    r.first_crack_deflection = soffit_peak_deflection;
  }
  std::size_t first_peak = r.load.size();
  for (std::size_t k = 0; k < r.smoothed_load.size(); ++k)
    if (r.smoothed_load[k] >= r.developed_crack_load && r.developed_crack_load > 0) {
      first_peak = k + 1;
      break;
    }
  const real p1 = r.developed_crack_load > 0 ? r.developed_crack_load : max_load;
  r.initial_stiffness = analysis::band_slope(r.deflection, r.smoothed_load, std::min(first_peak, r.load.size()), 0.1 * p1, 0.6 * p1);

  // Final cracks: the opening profile along the span (beam_crack_profile).
  r.final_cracks = beam_crack_profile(s.contacts(), gp, o.height, hand.mean_block_size, loading.crack_width);
  std::vector<real> mirrored;
  for (const beam_crack& c : r.final_cracks) {
    if (c.width > r.widest.width) r.widest = c;
    beam_crack& half_widest = r.spans[c.x < L ? 0 : 1].widest;
    if (o.full() && c.width > half_widest.width) half_widest = c;
    if (!c.locally_vertical() || !beam_in_moment_zone(o, c.x)) continue;
    r.flexural_crack_positions.push_back(c.x);
    mirrored.push_back(c.x);
    if (!o.full() && L - c.x > 0.5 * hand.mean_block_size) mirrored.push_back(2 * L - c.x);  // its twin across the symmetry face
  }
  std::sort(mirrored.begin(), mirrored.end());
  r.flexural_cracks = static_cast<int>(mirrored.size());
  if (mirrored.size() >= 2) r.mean_crack_spacing = (mirrored.back() - mirrored.front()) / static_cast<real>(mirrored.size() - 1);
  const energy_balance e = s.energies();
  const contact::contact_energies ce = s.contacts().energies();
  r.compression_dissipated = ce.dissipated_compression;
  r.tension_dissipated = ce.dissipated_tension;
  if (!r.deflection.empty())
    history.finish(s.contacts(), gp, r.deflection.back(), r.smoothed_load.back(), r.peak_deflection);
  r.after_peak = beam_fastest_inclined_after_peak(s.contacts(), gp, history, o, hand.mean_block_size,
                                                  loading.crack_width, r.peak_load, r.peak_deflection);
  for (int k = 0; k < sides && o.full(); ++k) {
    r.spans[k].after_peak = k == 0 ? r.after_peak
                                   : beam_fastest_inclined_after_peak(s.contacts(), gp, history, o, hand.mean_block_size,
                                                                      loading.crack_width, r.peak_load, r.peak_deflection, 1);
    if (k == 1) r.after_peak = beam_faster_span(r.after_peak, r.spans[1].after_peak, false);  // the larger opening
  }
  r.failure_mode = beam_failure_mode(r.widest, o, loading.crack_width, r.compression_dissipated, r.tension_dissipated);
  r.failing_span = beam_failing_span(o, r.widest, r.failure_mode);
  r.elastic = beam_elastic_load(r.deflection, r.load, hand, o.full() ? &r.spans : nullptr);
  r.energy_balance_error = e.error_rel();
  r.boundary_work = e.boundary_work + e.applied_work;
  if constexpr (Relaxed)  // the resets and ramps move the model outside the books (solver/relaxation.hpp)
    r.energy_balance_error = r.boundary_work = std::numeric_limits<real>::quiet_NaN();
  for (int k = 0; k < sides && contact_plates; ++k) {
    const auto j = static_cast<std::size_t>(2 * k);
    r.plate_subcontacts[j] = support_platen[k]->size(), r.plate_subcontacts[j + 1] = loading_platen[k]->size();
    r.plate_in_contact[j] = support_platen[k]->in_contact(), r.plate_in_contact[j + 1] = loading_platen[k]->in_contact();
    r.plate_rotation[j] = support_platen[k]->rotation(), r.plate_rotation[j + 1] = loading_platen[k]->rotation();
    r.plate_added_mass += support_platen[k]->added_mass() + loading_platen[k]->added_mass();
  }
  r.contact_dissipated = e.contact_dissipated;
  r.damping_dissipated = e.damping_dissipated;
  r.dt = s.dt();
  r.steps = s.step_count();
  r.phases = s.phases();
  r.damping_in_force = s.damping_in_force();
  r.subcontacts = s.contacts().size();
  r.zones = scene.mesh.zone_count();
  r.gridpoints = scene.mesh.gridpoint_count();
  std::vector<real> areas;
  for (index_t i = 0; i < s.contacts().size(); ++i) areas.push_back(s.contacts().area(i));
  std::nth_element(areas.begin(), areas.begin() + static_cast<std::ptrdiff_t>(areas.size() / 2), areas.end());
  r.contact_points_over_depth = areas.empty() ? 0 : o.height / std::sqrt(areas[areas.size() / 2]);
  r.trusses_per_block = static_cast<real>(scene.elements_per_bar) * hand.mean_block_size /
                        ((o.full() ? o.mirror(o.end_cover) : L) - o.end_cover);
  r.runtime_s = runtime_before + timer.seconds();
  return r;
}

/// run_beam with the law of the scene's options: the study's (linear softening, plastic cap, decoupled
/// cohesion), --compression elastic (linear_tie_law) or --cohesion coupled (coupled_beam_law), each
/// with the options' slip_breaks_tension; or --law slip_softening, crushing, mixed_mode (G_II 0 =
/// (c_0/f_T) G_f; with --g-c > 0 mixed_crushing_beam_law): concrete_laws.hpp.
template <class OnEvent>
[[nodiscard]] beam_result run_beam(const beam_scene& scene, const beam_loading& loading, OnEvent&& on_event) {
  const beam_options& o = scene.options;
  auto contact = scene.contact;
  contact.shear.slip_breaks_tension = o.slip_breaks_tension;
  if (loading.relaxation)  // run_beam<..., true> refuses another law (check_beam_relaxation)
    return run_beam<presets::study_beam_law, true>(scene, contact, loading, on_event);
  require(o.cohesion == "decoupled" || o.compression == "plastic", "rc_beam: --cohesion ", o.cohesion,
          " is built with --compression plastic only, got --compression ", o.compression);
  if (o.law == "crushing")  // the same, its cap softening with crushing over G_c (check_beam_law)
    return run_beam<presets::crushing_beam_law>(
        scene, presets::with_softening_cap(presets::with_slip_softening(scene.contact, g_ii_or_default(o.g_ii)),
                                           o.g_c > 0 ? o.g_c : default_g_c, o.cap_residual, o.crush_shear),
        loading, on_event);
  if (o.law == "slip_softening")  // built with the plastic cap and decoupled cohesion only (check_beam_law)
    return run_beam<presets::slip_softening_beam_law>(
        scene, presets::with_slip_softening(scene.contact, g_ii_or_default(o.g_ii)), loading, on_event);
  if (o.law == "mixed_mode" && o.g_c > 0)  // its cap softening with crushing over G_c (check_beam_law)
    return run_beam<presets::mixed_crushing_beam_law>(
        scene, presets::with_softening_cap(presets::with_mixed_mode(scene.contact, o.g_ii), o.g_c, o.cap_residual,
                                           o.crush_shear),
        loading, on_event);
  if (o.law == "mixed_mode")  // built with the plastic cap and decoupled cohesion only (check_beam_law)
    return run_beam<presets::mixed_mode_beam_law>(scene, presets::with_mixed_mode(scene.contact, o.g_ii), loading, on_event);
  if (o.compression == "elastic")
    return run_beam<presets::linear_tie_law>(scene, beam_elastic_compression(contact), loading, on_event);
  if (o.cohesion == "coupled")
    return run_beam<presets::coupled_beam_law>(scene, presets::with_coupled_cohesion(contact), loading, on_event);
  return run_beam<presets::study_beam_law>(scene, contact, loading, on_event);
}

}  // namespace tessera::scenes
