#pragma once
// The shear figure of a concrete (issue #63 item 3; docs/guide.md, "A shear figure"): rc_beam with bars
// that cannot yield, run by the scene code rc_beam runs (make_beam, run_beam), so that
//
//   rc_beam --steel-yield 1e12 --zone-edge 0.05 --rate 0.01 --max-deflection 0.012 --threads 1 --no-vtk
//           --blocks 60 [the concrete's law flags] [--failure-crack diagonal] --seed S
//
// and calibrate --targets shear (calibrate/targets.hpp) give the same peak to the bit. The figure is
// P at failure (the smoothed load 25 % below its peak, summary.json failure_reached; peak_load_N)
// over the mean of EC2's and Zsutty's 2 V_c (beam_hand_checks::shear_reference_load, 51.69 kN for the
// default beam, whatever the concrete's cap). A run with no failure by the last deflection has not
// reached its event: it has no figure (its peak is a lower bound, never a capacity).

#include <cstdint>
#include <string>

#include "common/concrete_set.hpp"
#include "rc_beam/beam.hpp"
#include "rc_beam/beam_law.hpp"
#include "rc_beam/beam_run.hpp"

namespace tessera::scenes {

/// rc_beam's added mass (beam_loading::added_mass_ratio): 20 x the original mass, quasi-static index
/// 0.63 at 5 mm/s (beam.hpp), 1.27 at the shear figure's 10 mm/s.
inline constexpr real rc_beam_added_mass_ratio = 20;

/// The shear figure's beam and loading (SI); the defaults are docs/guide.md's cheap figure.
struct shear_figure_options {
  int blocks = 60;              ///< Voronoi blocks of the half beam (rc_beam --blocks; 8..500)
  real zone_edge = 0.05;        ///< face zoning edge (m; rc_beam --zone-edge)
  real rate = 0.01;             ///< loading plate velocity (m/s; rc_beam --rate)
  real max_deflection = 0.012;  ///< the last mid-span deflection (m): no failure by here = event not reached
  real steel_yield = 1e12;      ///< the bars' f_y (Pa): bars that cannot yield
  /// rc_beam --failure-crack diagonal: a drop is the failure only when a shear crack or band broke
  /// since the peak, else a dip and the run goes on (beam_failure_rule.hpp); false: every drop is.
  bool failure_needs_diagonal = false;
  int threads = 1;
};

/// One run's shear figure: the peak (N) where the load fell 25 % below it, against the hand reference (N).
struct shear_figure {
  bool failure_reached = false;  ///< the load fell by beam_loading::failure_drop before the last deflection
  real peak_load = 0;            ///< P at failure (N); without failure the highest load before the stop
  real reference_load = 0;       ///< the mean of EC2's and Zsutty's 2 V_c (N)
  real end_deflection = 0;       ///< where the run stopped (m)
};

/// The beam of the shear figure s with set c's concrete (concrete_set_to: law, scales, c_0 / f_T,
/// angles, G_II, cap, G_c) for `seed`: rc_beam's beam of the same flags.
[[nodiscard]] inline beam_options shear_beam_options(const concrete_set& c, const shear_figure_options& s,
                                                     std::uint64_t seed) {
  beam_options b;
  b.blocks = s.blocks;
  b.zone_edge = s.zone_edge;
  b.steel_yield = s.steel_yield;
  b.seed = seed;
  concrete_set_to(c, b);
  return b;
}

/// rc_beam's explicit loading (its defaults and rc_beam_added_mass_ratio) at s's rate, last deflection
/// and threads, without the progress line.
[[nodiscard]] inline beam_loading shear_beam_loading(const shear_figure_options& s) {
  beam_loading l;
  l.added_mass_ratio = rc_beam_added_mass_ratio;
  l.rate = s.rate;
  l.max_deflection = s.max_deflection;
  l.threads = s.threads;
  l.failure_needs_diagonal = s.failure_needs_diagonal;
  l.progress = false;
  return l;
}

/// Runs the shear figure's beam with set c's concrete on `seed` (check_beam_law_set first: throws
/// invalid_input naming a value the beam's law refuses).
[[nodiscard]] inline shear_figure run_shear_figure(const concrete_set& c, const shear_figure_options& s,
                                                   std::uint64_t seed) {
  const beam_options o = shear_beam_options(c, s, seed);
  check_beam_law_set(o);
  const beam_scene scene = make_beam(o);
  const beam_result r = run_beam(scene, shear_beam_loading(s), [](const auto&, const std::string&) {});
  return {r.failure_reached, r.peak_load, scene.hand.shear_reference_load(),
          r.deflection.empty() ? real(0) : r.deflection.back()};
}

}  // namespace tessera::scenes
