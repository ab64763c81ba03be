#pragma once
// One run of the reference study's RC tie (rc_tie_scene.hpp): supports, the pull, the samples
// and the measurements of tie_result. Used by examples/rc_tie, examples/rc_tie_sensitivity and
// benchmarks/work_precision_tie.
//
// The run in four pieces, each readable on its own:
//   hold_tie_ends    the supports: concrete end gridpoints on rollers, bar ends held transversally
//                    (z of both ends driven by the pull, or the first fixed)
//   tie_recorder     one curve sample: force, elongation, concrete stress, softened sub-contacts,
//                    load drops and the yield of the bar as they happen (events for VTK snapshots)
//   run_tie          builds the solver, checks the rate is quasi-static, pulls until the stop rule
//                    (or, with tie_loading::relaxation, relax_tie: increments relaxed to equilibrium)
//   finish_tie       the figures read off the curve and the final state: first cracking, initial
//                    stiffness, yield plateau, cracks, energies, cost per entity

#include <algorithm>
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
#include "common/relaxed_scheme.hpp"
#include "common/rc_tie_scene.hpp"
#include "tessera/analysis.hpp"
#include "tessera/solver/relaxation.hpp"

namespace tessera::scenes {

/// The bar nodes the tie is held and pulled by.
struct tie_ends {
  index_t first = 0, last = 0;  ///< first and last node of the bar
};

/// Supports (rc_tie_scene.hpp): rollers on the concrete end faces (x, y fixed, z free), bar ends
/// held in x and y with z set by the pull (run_tie); with --bare every concrete gridpoint fixed.
template <class Solver>
tie_ends hold_tie_ends(Solver& s, const tie_scene& scene) {
  const real tol = 1e-9 * scene.hand.length;
  if (scene.options.bare) {
    s.fix(bc::all_nodes(s.gridpoints()));
  } else {
    s.fix(s.gridpoints_on_plane(2, scene.prism.box.lo.z(), tol), bc::transverse_to(2));
    s.fix(s.gridpoints_on_plane(2, scene.prism.box.hi.z(), tol), bc::transverse_to(2));
  }
  const auto [first_node, end_node] = s.reinforcement().bar_nodes(0);
  const tie_ends ends{first_node, end_node - 1};
  bc::fix(s.bar_nodes(), bc::node_group{{ends.first}, "fixed bar end"});
  bc::fix(s.bar_nodes(), bc::node_group{{ends.last}, "pulled bar end"});
  return ends;
}

/// Samples one tie run into a tie_result and detects its events (load drops, yield) as they happen.
template <class Solver>
class tie_recorder {
 public:
  tie_recorder(const Solver& s, const tie_scene& scene, const tie_loading& loading, tie_ends ends)
      : scene_(scene), loading_(loading), ends_(ends), detector_(drop_threshold(scene)),
        graph_(s.contacts(), scene.prism.tess.cell_count(), vec3::UnitZ()),
        progress_(loading.progress_label.empty() ? std::string("rc_tie") : loading.progress_label) {
    const tie_bar& truss = s.reinforcement();
    if (!scene.options.bare) {
      std::vector<index_t> node_blocks;
      std::vector<real> node_z;
      for (index_t n = ends.first; n <= ends.last; ++n) {
        if (!truss.bonded(n)) continue;
        node_blocks.push_back(scene.prism.mesh.zone_block[static_cast<std::size_t>(truss.host(n).zone)]);
        node_z.push_back(s.bar_nodes().reference(n, 2));
      }
      graph_.set_bar_path(std::move(node_blocks), std::move(node_z));
    }
    // Bar elements whose midpoints lie in the middle two thirds of the tie (concrete_stress).
    const real length = scene.hand.length;
    middle_first_ = truss.element_count();
    for (index_t e = 0; e < truss.element_count(); ++e) {
      const real z = (static_cast<real>(e) + 0.5) * length / static_cast<real>(truss.element_count());
      if (z < length / 6 || z > 5 * length / 6) continue;
      middle_first_ = std::min(middle_first_, e);
      middle_end_ = e + 1;
    }
  }

  /// Load-drop threshold: 5 % of the hand cracking force (N).
  [[nodiscard]] static real drop_threshold(const tie_scene& scene) { return 0.05 * scene.hand.cracking_force; }

  /// Records the state of `sv` as the next sample; on_event(sv, tag) at a drop or at the yield.
  /// Returns true when the run should stop.
  template <class OnEvent>
  bool sample(const Solver& sv, OnEvent& on_event) {
    const node_set& bar = sv.bar_nodes();
    const real u = bar.displacement(ends_.last, 2) - bar.displacement(ends_.first, 2);  // elongation
    const real f = -bar.reaction(ends_.first, 2);
    r_.elongation.push_back(u);
    r_.force.push_back(f);
    r_.pulled_force.push_back(bar.reaction(ends_.last, 2));
    record_concrete(sv, f);
    r_.unbalanced_ratio.push_back(sv.unbalanced_force().max_force / scene_.hand.cracking_force);
    r_.max_imbalance = std::max(r_.max_imbalance, std::abs(r_.pulled_force.back() - f) / scene_.hand.yield_force);
    max_force_ = std::max(max_force_, f);
    if (!r_.yielded && r_.elongation.size() % 4 == 0) {
      const int c = graph_.softened(sv.contacts(), sv.gridpoints()).cracks;
      if (c > softened_count_) {
        softened_count_ = c;
        r_.crack_formation.emplace_back(u, max_force_);
      }
    }
    if (!r_.yielded) {
      if (bar_flows(sv, f)) {
        r_.yielded = true;
        r_.yield_elongation = u;
        yield_sample_ = r_.elongation.size() - 1;
      }
      if (detector_.push(u, f)) on_event(sv, "drop" + std::to_string(++drops_reported_));
      if (r_.yielded) on_event(sv, std::string("yield"));
    }
    const bool done =
        u >= loading_.max_elongation || (r_.yielded && u >= (1 + loading_.post_yield) * r_.yield_elongation);
    if (!loading_.progress_label.empty()) {
      const real target = r_.yielded ? std::min(loading_.max_elongation, (1 + loading_.post_yield) * r_.yield_elongation)
                                     : loading_.max_elongation;
      progress_.update(std::min(1.0, u / target), detail::concat("u = ", u * 1e3, " mm, F = ", f * 1e-3, " kN, drops ",
                                                                 drops_reported_, r_.yielded ? ", yielded" : ""));
    }
    return done;
  }

  void finish_progress() { progress_.finish(); }
  [[nodiscard]] tie_result& result() { return r_; }
  [[nodiscard]] analysis::crack_graph& graph() { return graph_; }
  /// Sample index of the yield (meaningful when result().yielded).
  [[nodiscard]] std::size_t yield_sample() const { return yield_sample_; }

 private:
  /// Concrete stress over the middle two thirds and softened sub-contacts of this sample.
  void record_concrete(const Solver& sv, real f) {
    const tie_bar& truss = sv.reinforcement();
    real bar_sum = 0;
    for (index_t e = middle_first_; e < middle_end_; ++e) bar_sum += truss.axial_force(e);
    const index_t bar_count = std::max<index_t>(0, middle_end_ - middle_first_);
    r_.concrete_stress.push_back(bar_count > 0 ? (f - bar_sum / static_cast<real>(bar_count)) / scene_.hand.concrete_area
                                               : 0);
    index_t softened = 0;
    for (index_t i = 0; i < sv.contacts().size(); ++i)
      if (analysis::crack_graph::past_peak(sv.contacts().state(i).flags)) ++softened;
    r_.softened_subcontacts.push_back(softened);
    if (r_.first_softening_force == 0 && softened > 0 && f >= 0.1 * scene_.hand.cracking_force)
      r_.first_softening_force = f;
  }

  /// Yield of the tie: the bar flows plastically, i.e. its total plastic elongation has reached 2 %
  /// of the bare bar's yield elongation, with the force at the fixed end at 90 % of f_y A or more.
  /// An element touching f_y A is not enough: the force jump a crack throws onto the bar overshoots
  /// dynamically and can yield one element for a moment at 0.9 f_y A (measured: 18.2 kN at
  /// dt = 1 us), long before the tie's plateau.
  [[nodiscard]] bool bar_flows(const Solver& sv, real f) const {
    const tie_bar& truss = sv.reinforcement();
    const real yield_flow = 0.02 * scene_.hand.yield_force / scene_.hand.bare_bar_stiffness;  // m
    real plastic = 0;
    if (f >= 0.9 * scene_.hand.yield_force)
      for (index_t e = 0; e < truss.element_count(); ++e) plastic += std::max(real(0), truss.plastic_elongation(e));
    return plastic >= yield_flow;
  }

  const tie_scene& scene_;
  const tie_loading& loading_;
  tie_ends ends_;
  tie_result r_;
  analysis::load_drop_detector detector_;
  analysis::crack_graph graph_;
  cli::progress_line progress_;
  std::size_t drops_reported_ = 0, yield_sample_ = 0;
  real max_force_ = 0;
  int softened_count_ = 0;
  index_t middle_first_ = 0, middle_end_ = 0;
};

/// The curve figures of a finished tie run: load drops before yield, first cracking (the highest
/// force before the first softened through-crack formed past N_cr / 2; else the first drop's peak,
/// else the maximum before yield), the first drop past N_cr / 2, the initial stiffness (slope of
/// the branch between 0.1 and 0.6 of the first peak) and the yield plateau.
inline void read_tie_curve(tie_result& r, const tie_hand_checks& hand, std::size_t yield_sample) {
  const std::size_t pre_yield = r.yielded ? yield_sample : r.force.size();
  r.drops = analysis::find_load_drops(r.elongation, r.force, 0.05 * hand.cracking_force, pre_yield);
  std::size_t first_peak = 0;
  if (!r.drops.empty())
    first_peak = r.drops.front().sample;
  else
    for (std::size_t k = 0; k < pre_yield; ++k)
      if (r.force[k] > r.force[first_peak]) first_peak = k;
  r.first_crack_force = r.force.empty() ? 0 : r.force[first_peak];
  std::size_t first_crack_sample = first_peak;
  for (const auto& [u, f] : r.crack_formation)
    if (f >= 0.5 * hand.cracking_force) {  // ignore start-up transients at the pulled end
      r.first_crack_force = f;
      for (std::size_t k = 0; k < r.force.size() && r.elongation[k] <= u; ++k)
        if (r.force[k] == f) first_crack_sample = k;
      break;
    }
  if (first_crack_sample < r.force.size()) {
    r.concrete_stress_at_first_crack = r.concrete_stress[first_crack_sample];
    r.softened_at_first_crack = r.softened_subcontacts[first_crack_sample];
  }
  for (const analysis::load_drop& d : r.drops)
    if (d.peak_force >= 0.5 * hand.cracking_force) {
      r.first_drop_force = d.peak_force;
      break;
    }
  const real f1 = r.force.empty() ? 0 : r.force[std::min(first_peak, r.force.size() - 1)];
  r.initial_stiffness = analysis::band_slope(r.elongation, r.force, first_peak + 1, 0.1 * f1, 0.6 * f1);
  if (r.yielded) {
    // Plateau: mean over the second half of the post-yield samples (the bar at f_y A in the crack).
    r.yield_force = analysis::tail_mean(r.force, yield_sample + (r.force.size() - yield_sample) / 2);
    const real u_last = r.elongation.back();
    double end_sum = 0;
    std::size_t end_count = 0;
    for (std::size_t k = r.force.size(); k-- > yield_sample && r.elongation[k] >= 0.98 * u_last;) {
      end_sum += 0.5 * (r.force[k] + r.pulled_force[k]);
      ++end_count;
    }
    r.final_force = end_count > 0 ? end_sum / static_cast<double>(end_count) : 0;
  }
  r.end_elongation = r.elongation.empty() ? 0 : r.elongation.back();
}

/// The figures of the final state: cracks (opened beyond w_open = 2 G_f / f_T, by u_n alone,
/// softened), energies, step and model counts, cost per phase.
template <class Solver, class LawParams>
void read_tie_state(tie_result& r, const Solver& s, const tie_scene& scene, const LawParams& law_params,
                    analysis::crack_graph& graph) {
  const real w_open = 2 * law_params.tension.G_f / law_params.tension.f_T;
  r.cracks = graph.opened(s.contacts(), s.gridpoints(), w_open);
  r.cracks_normal_only = graph.opened_normal_only(s.contacts(), s.gridpoints(), w_open);
  r.softened_cracks = graph.softened(s.contacts(), s.gridpoints());
  const energy_balance e = s.energies();
  r.energy_balance_error = e.error_rel();
  r.boundary_work = e.boundary_work;
  r.contact_dissipated = e.contact_dissipated;
  r.damping_dissipated = e.damping_dissipated;
  r.bar_dissipated = e.reinforcement_dissipated;
  r.dt = s.dt();
  const auto& ms = s.mass_scaling();
  r.added_mass_ratio = ms.original_mass > 0 ? ms.added_mass / ms.original_mass : 0;
  r.steps = s.step_count();
  r.phases = s.phases();
  r.damping_in_force = s.damping_in_force();
  r.subcontacts = s.contacts().size();
  r.zones = scene.prism.mesh.zone_count();
  r.gridpoints = scene.prism.mesh.gridpoint_count();
}

/// The pull by kinetic relaxation (tie_loading::relaxation; solver/relaxation.hpp): the bar ends
/// moved apart by relax_increment per increment over relax_ramp steps, each increment relaxed
/// until the largest nodal unbalanced force and the largest block resultant
/// (relaxation_options::block_resultant) are both relax_tolerance x N_cr at most. The ramps use
/// the linear predictor until the first load drop of 5 % N_cr, then follow the load dynamically.
/// Both rules are measured (docs/performance.md, "Kinetic dynamic relaxation"): with the nodal
/// ratio alone, or with the predictor on past the first crack (off only for the increment after
/// each drop), the relaxed states keep a self-equilibrated residual stress after the cracks form
/// (seed 1: the bar at a crack carrying 16 kN while its ends carry 8.6 kN), and the bar yields
/// early (0.77 mm and 18.3 kN against the explicit run's 0.95 mm and 20.8 kN). `sample(s)` after
/// each increment, until it returns true; the counts go to r.
template <class Solver, class Sample>
void relax_tie(Solver& s, const tie_scene& scene, const tie_loading& loading, Sample&& sample, tie_result& r) {
  relaxation_options o;
  o.reference_force = scene.hand.cracking_force;
  o.ratio_tolerance = loading.relax_tolerance;
  o.max_steps = loading.relax_max_steps;
  o.extrapolate = true;
  o.block_resultant = true;
  const real drop = tie_recorder<Solver>::drop_threshold(scene);  // the recorder's load drop
  real peak = 0;
  scenes::relax_increments(s, loading.relax_increment, loading.relax_ramp, o, [&](const Solver& sv) {
    const bool done = sample(sv);
    peak = std::max(peak, r.force.back());
    return scenes::relaxed_sample{done, r.force.back() < peak - drop};
  }, r);
}

/// Runs the tie with contact law Law (law parameters `law_params`) under `loading`, by the
/// explicit pull (Relaxed = false) or by kinetic relaxation (Relaxed = true, loading.relaxation;
/// deformable blocks, the solver without the step checker, since the resets and ramps move the
/// model outside the energy books). `on_event`
/// is called as on_event(solver, tag) once the checks have passed and the first step is next
/// ("start"), at each load drop ("drop1", "drop2", ...), at the first
/// yield of the bar ("yield") and at the end ("end"), e.g. to write VTK snapshots. Throws
/// invalid_input for a bad loading or a rate that is not quasi-static (quasi_static.hpp).
template <class Blocks, class Law, bool Relaxed = false, class OnEvent>
[[nodiscard]] tie_result run_tie(const tie_scene& scene, const typename Law::params& law_params,
                                 const tie_loading& loading, OnEvent&& on_event) {
  using solver_type = std::conditional_t<Relaxed, tie_solver<Blocks, Law, checks::no_step_checker>, tie_solver<Blocks, Law>>;
  static_assert(!Relaxed || !Blocks::is_rigid, "rc_tie: kinetic relaxation takes deformable blocks");
  require(loading.relaxation == Relaxed, "rc_tie: run_tie<", Relaxed ? "relaxed" : "explicit",
          "> called with tie_loading::relaxation ", loading.relaxation ? "true" : "false");
  if constexpr (Relaxed) {  // before anything is built; the options as kinetic_relaxation checks them
    require_positive(loading.relax_increment, "rc_tie: relaxation increment (m)");
    require(loading.relax_increment <= loading.max_elongation, "rc_tie: relaxation increment ", loading.relax_increment,
            " m exceeds the maximum elongation ", loading.max_elongation, " m");
    require(loading.relax_ramp >= 1, "rc_tie: relaxation ramp ", loading.relax_ramp, " steps must be >= 1");
    require_valid_relaxation(
        {.reference_force = 1, .ratio_tolerance = loading.relax_tolerance, .max_steps = loading.relax_max_steps});
  } else {
    require_positive(loading.rate, "rc_tie: pull rate (m/s)");
    require_non_negative(loading.ramp_time, "rc_tie: ramp time (s)");
  }
  require_positive(loading.max_elongation, "rc_tie: maximum elongation (m)");
  const cli::wall_timer timer;
  solver_options opt;
  opt.mass_scaling_dt = loading.added_mass_ratio > 0 ? 0 : loading.dt;
  opt.mass_scaling_ratio = loading.added_mass_ratio;
  opt.threads = loading.threads;
  opt.damping_gamma = loading.damping_gamma;
  if constexpr (Relaxed) opt = kinetic_relaxation_options(opt);  // no damping, masses at dt = 1 s
  solver_type s(scene.prism.tess, scene.prism.mesh, scene.prism.block_material, law_params, scene.bar, opt);
  const adaptive_rate::params& rc = loading.rate_control;
  // The explicit pull's out-of-balance rate control (refuses bad factors and ratios); relaxation
  // has no rate (the driver refuses the rate flags with it), so nothing is built for it there.
  std::optional<adaptive_rate> control;
  if constexpr (!Relaxed) control.emplace(rc);
  if (!scene.options.bare && !Relaxed) {
    // The fastest rate the control may reach must be quasi-static too.
    const auto& ms = s.mass_scaling();
    const std::string who = rc.max_factor > 1 ? "rc_tie: the fastest rate of the out-of-balance control "
                                                "(--max-rate-factor x --rate)"
                                              : "rc_tie";
    require_quasi_static(who.c_str(), loading.rate * rc.max_factor, scene.hand.length, concrete_young, concrete_density,
                         ms.original_mass > 0 ? ms.added_mass / ms.original_mass : 0, law_params.tension.f_T);
  }
  const tie_ends ends = hold_tie_ends(s, scene);

  // Both bar ends move (symmetric) or the last alone.
  node_set& bar = s.bar_nodes();
  const real pulled_share = loading.symmetric ? 0.5 : 1.0;  // of the elongation rate
  double factor_steps = 0;  // sum over the steps of the rate factor in force (explicit pull)

  tie_recorder<solver_type> recorder(s, scene, loading, ends);
  on_event(std::as_const(s), std::string("start"));  // every check has passed: the run begins
  if constexpr (Relaxed) {
    // 1 m/s of pseudo-time: the load pattern kinetic_relaxation moves in increments.
    bar.prescribed_velocity(ends.last, 2) = pulled_share;
    if (loading.symmetric) bar.prescribed_velocity(ends.first, 2) = -(1 - pulled_share);
    relax_tie(s, scene, loading, [&](const solver_type& sv) {
      const bool stop = recorder.sample(sv, on_event);
      recorder.result().rate_factor.push_back(std::numeric_limits<real>::quiet_NaN());  // no rate
      return stop;
    }, recorder.result());
  } else {
    // The pull: the elongation rate rises along a half-cosine over the ramp, then stays, times
    // the control's factor (set at the samples).
    const real ramp = loading.ramp_time;
    const auto pull_velocity = [&](real t) {
      if (t >= ramp) return loading.rate;
      return 0.5 * loading.rate * (1 - std::cos(std::numbers::pi * t / ramp));
    };
    const auto pull = [&](const solver_type& sv) {
      const real factor = control->factor();
      factor_steps += factor;
      const real v = factor * pull_velocity(sv.time() + 0.5 * sv.dt());
      bar.prescribed_velocity(ends.last, 2) = pulled_share * v;
      if (loading.symmetric) bar.prescribed_velocity(ends.first, 2) = -(1 - pulled_share) * v;
    };
    // s.run_until in one process; split over MPI ranks under mpirun (common/mpi_run.hpp).
    bool done = false;
    run_sampled(s, scene.prism.mesh, done, pull, loading.sample, [&](const solver_type& sv) {
      done = recorder.sample(sv, on_event);
      tie_result& rr = recorder.result();
      if (sv.time() > ramp) {
        control->update(rr.unbalanced_ratio.back());
        rr.max_unbalanced_ratio = std::max(rr.max_unbalanced_ratio, rr.unbalanced_ratio.back());
      }
      rr.rate_factor.push_back(control->factor());
    });
  }
  recorder.finish_progress();
  on_event(std::as_const(s), std::string("end"));

  tie_result& r = recorder.result();
  read_tie_curve(r, scene.hand, recorder.yield_sample());
  read_tie_state(r, s, scene, law_params, recorder.graph());
  r.mean_rate_factor = r.steps > 0 ? factor_steps / static_cast<double>(r.steps) : 1;
  if constexpr (Relaxed) {
    // No rate, and the resets remove kinetic energy the books do not see while the ramps move the
    // relaxation masses (about 1e13 x the physical ones): no boundary work or balance (null).
    r.mean_rate_factor = r.boundary_work = r.energy_balance_error = std::numeric_limits<real>::quiet_NaN();
    r.max_unbalanced_ratio = *std::max_element(r.unbalanced_ratio.begin(), r.unbalanced_ratio.end());
  }
  r.runtime_s = timer.seconds();
  return std::move(r);
}

/// run_tie with the block model of scene.options.rigid and the softening law named in
/// loading.softening ("power" or "linear"); Relaxed: by kinetic relaxation (loading.relaxation;
/// rigid blocks refused). Relaxed is a template argument so that a driver that never relaxes
/// does not compile the relaxed solvers.
template <bool Relaxed = false, class OnEvent>
[[nodiscard]] tie_result run_tie(const tie_scene& scene, const tie_loading& loading, OnEvent&& on_event) {
  require(loading.softening == "power" || loading.softening == "linear", "rc_tie: softening '", loading.softening,
          "' must be 'power' or 'linear'");
  require(loading.cohesion == "decoupled" || loading.cohesion == "coupled", "rc_tie: cohesion '", loading.cohesion,
          "' must be 'decoupled' or 'coupled'");
  const bool power = loading.softening == "power";
  auto contact = scene.prism.contact;
  contact.shear.slip_breaks_tension = loading.slip_breaks_tension;
  if (loading.cohesion == "coupled") {
    require(power && !scene.options.rigid,
            "rc_tie: coupled cohesion is built for power softening and deformable blocks only (got softening ",
            loading.softening, scene.options.rigid ? ", rigid blocks)" : ")");
    return run_tie<deformable_blocks, law::coupled_tie_law, Relaxed>(scene, law::with_coupled_cohesion(contact), loading,
                                                                    on_event);
  }
  const auto linear = tessera::law::with_linear_softening(contact);
  if constexpr (Relaxed) {
    require(!scene.options.rigid, "rc_tie: kinetic relaxation relaxes deformable blocks; rigid blocks are not relaxed");
  } else if (scene.options.rigid) {
    return power ? run_tie<blocks::rigid, law::study_tie_law>(scene, contact, loading, on_event)
                 : run_tie<blocks::rigid, law::linear_tie_law>(scene, linear, loading, on_event);
  }
  return power ? run_tie<deformable_blocks, law::study_tie_law, Relaxed>(scene, contact, loading, on_event)
               : run_tie<deformable_blocks, law::linear_tie_law, Relaxed>(scene, linear, loading, on_event);
}

/// run_tie without event callbacks.
[[nodiscard]] inline tie_result run_tie(const tie_scene& scene, const tie_loading& loading) {
  return run_tie(scene, loading, [](const auto&, const std::string&) {});
}

}  // namespace tessera::scenes
