#pragma once
// The half beam and the full one (rc_beam --span half|full, beam.hpp): what the analysis of a run
// reads differently when the model holds both shear spans.
//
// The half model's symmetry face forces symmetric cracks; the full beam (2 x --blocks Voronoi
// blocks over 2 L_h, no symmetry condition) can fail in its weaker span. Both its supports roll;
// it is held in x at one gridpoint, the one nearest the centre of the mid-span section, where the
// half model holds its whole symmetry face. A pin at the left support instead made the two
// reactions differ by 6.2 % in the elastic stage of the quick beam (the local damping's drag on
// the whole beam's drift towards the roller), against 1.1 % with the pin at mid-span (measured). Its figures are kept per span: span 0 the left (x < L_h, support at x = overhang),
// span 1 the right (its mirror image about mid-span x = L_h).
//   - mid-span deflection (beam_midspan_gauge): the half beam's soffit gridpoints on the symmetry
//     face; the full beam has no face at mid-span (a plane there would be a pre-made crack in the
//     constant-moment zone), so its deflection is the least-squares line u_y(x) through the soffit
//     gridpoints within one mean block size of mid-span, read at mid-span. Over that window the
//     elastic beam's curvature biases it by kappa <(x - L_h)^2> / 2: 0.3 % of the deflection for a
//     125-block beam (56 mm window, kappa = M / EI), below the scatter of the blocks.
//   - loading: the two loading plates hang from a spreader beam hinged at mid-span
//     (beam_spreader), so that they carry equal loads as the half model's one does (driven at one
//     velocity, they would share the load by the two halves' stiffness, which the blocks make unequal);
//   - load: P = the sum of the two support reactions (the half beam's 2 x its one), so that P is
//     the same total load in both models; each span's reaction is kept.
//   - cracks at the end: the widest of each half, the flexural ones over the whole constant-moment
//     zone (not mirrored), the failure mode from the widest overall in either shear span
//     (beam_failure_mode), the fastest-opening inclined crack after the peak in each shear span
//     (beam_post_peak.hpp). The failing span: the half of the beam that holds the widest crack at
//     the end (with diagonal tension, its shear span).
//   - summary.json keeps the half model's keys for the whole beam (inclined_after_peak_* the
//     faster of the two spans' cracks, shear_at_peak_* the left span's, shear_at_first_inclined_
//     crack_* the span of first_inclined_crack_span) and adds left_* and right_* per span.
//   - the elastic check (both models): the load at the deflection delta_e = P_cr / (2 K_0) (half the
//     hand deflection at first cracking, f_T-based), from a least-squares line of the raw load over
//     [delta_e / 2, 3 delta_e / 2] (a centred fit: the smoothed load lags); in the full beam, the
//     asymmetry of the two reactions over the same window, (R_0 - R_1) / (R_0 + R_1).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "rc_beam/beam.hpp"
#include "rc_beam/beam_cracks.hpp"
#include "rc_beam/beam_post_peak.hpp"
#include "rc_beam/beam_shear.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/plot.hpp"

namespace tessera::scenes {

/// The mid-span deflection (m, down +) of the half or the full beam (file comment).
class beam_midspan_gauge {
 public:
  beam_midspan_gauge(const node_set& gp, const beam_options& o, real cell, real tol) : mean_(!o.full()) {
    const real L = o.half_length();
    const real reach = o.full() ? cell : tol;
    for (index_t i = 0; i < gp.size(); ++i)
      if (std::abs(gp.reference(i, 0) - L) <= reach && std::abs(gp.reference(i, 1)) <= tol) nodes_.push_back(i);
    require(!nodes_.empty(), "rc_beam: no soffit gridpoint at mid-span (within ", reach, " m)");
    if (mean_) return;
    // The intercept at x = L of the least-squares line through (x_i - L, u_i): sum w_i u_i.
    double sd = 0, sdd = 0;
    for (index_t i : nodes_) sd += gp.reference(i, 0) - L;
    const double n = static_cast<double>(nodes_.size()), mean_d = sd / n;
    for (index_t i : nodes_) sdd += (gp.reference(i, 0) - L - mean_d) * (gp.reference(i, 0) - L - mean_d);
    require(nodes_.size() >= 3 && sdd > 0, "rc_beam: ", nodes_.size(), " soffit gridpoints within ", reach,
            " m of mid-span do not fit a line");
    for (index_t i : nodes_) weight_.push_back(1 / n - mean_d * (gp.reference(i, 0) - L - mean_d) / sdd);
  }
  [[nodiscard]] real deflection(const node_set& gp) const {
    real u = 0;
    if (mean_) {
      for (index_t n : nodes_) u += gp.displacement(n, 1);
      return -u / static_cast<real>(nodes_.size());
    }
    for (std::size_t k = 0; k < nodes_.size(); ++k) u += weight_[k] * gp.displacement(nodes_[k], 1);
    return -u;
  }
  [[nodiscard]] std::size_t size() const { return nodes_.size(); }

 private:
  bool mean_;
  std::vector<index_t> nodes_;
  std::vector<real> weight_;
};

/// The full beam's loading: a spreader beam on the actuator, hinged at mid-span, so that the two
/// loading plates carry equal loads (the test's spreader; the half model's symmetry face gives
/// the same) instead of moving down together. Its one freedom, the tilt rate w (m/s): the left
/// plate moves down at v + w, the right one at v - w. The tilt follows the imbalance of the plate
/// loads, m dw/dt = F_1 - F_0 (N, each plate's downward force on the beam), with local damping as
/// every other freedom, from the loads of the last step (one step behind, as hinged_plate). Its
/// mass m: a tenth of the beam's mass-scaled mass, heavy enough that the lag stays stable
/// (omega^2 dt^2 = 2 k_plate dt^2 / m ~ 1e-4 for the steel plates' contact stiffness), light
/// enough that it tilts faster than the beam's first mode (period about T_1 / 3).
class beam_spreader {
 public:
  explicit beam_spreader(real mass) : mass_(mass) {
    require(std::isfinite(mass) && mass > 0, "beam_spreader: mass ", mass, " kg must be finite and > 0");
  }
  /// Advances the tilt rate by dt (s) from the plate loads f0, f1 (N); returns it (m/s).
  real advance(real f0, real f1, real dt, real gamma) {
    const real f = f1 - f0, sign = tilt_ > 0 ? 1.0 : (tilt_ < 0 ? -1.0 : 0.0);
    tilt_ += dt * (f - gamma * std::abs(f) * sign) / mass_;
    return tilt_;
  }
  [[nodiscard]] real tilt_rate() const { return tilt_; }
  /// Stops the tilt (a relaxation's reset).
  void stop() { tilt_ = 0; }
  /// Saves or loads the tilt rate (io/checkpoint.hpp).
  template <class Archive>
  void checkpoint(Archive& ar) {
    ar.same("beam/spreader/mass", mass_);
    ar.scalar("beam/spreader/tilt_rate", tilt_);
  }

 private:
  real mass_, tilt_ = 0;
};

/// The figures of one span of the full beam (file comment).
struct beam_span_figures {
  std::vector<real> reaction;            ///< its support reaction at every sample (N)
  std::vector<real> plate_load;          ///< its loading plate's downward force on the beam at every sample (N)
  real reaction_at_peak = 0, plate_load_at_peak = 0;  ///< N
  real first_inclined_crack_load = 0, first_inclined_crack_deflection = -1, first_inclined_crack_x = 0;
  beam_crack widest;                     ///< the widest crack of this half at the end
  beam_post_peak_crack after_peak;       ///< the fastest-opening inclined crack of its shear span
  std::vector<beam_shear_split> shear_at_peak;
};

/// The elastic check of the file comment.
struct beam_elastic_check {
  real deflection = 0;          ///< delta_e (m)
  real load = 0;                ///< P at delta_e from the fitted line (N)
  real reaction_asymmetry = 0;  ///< (R_0 - R_1) / (R_0 + R_1) over the window (full beam)
  real plate_load_asymmetry = 0;  ///< the same of the two loading plates' forces (full beam)
  int samples = 0;
};

/// The elastic check from the samples; `span_reaction` the spans' reactions (empty: half beam).
[[nodiscard]] inline beam_elastic_check beam_elastic_load(const std::vector<real>& deflection,
                                                          const std::vector<real>& load, const beam_hand_checks& h,
                                                          const std::array<beam_span_figures, 2>* spans) {
  beam_elastic_check e;
  e.deflection = 0.5 * h.first_crack_load / h.initial_stiffness;
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, r0 = 0, r1 = 0, p0 = 0, p1 = 0;
  for (std::size_t k = 0; k < deflection.size() && k < load.size(); ++k) {
    const double d = deflection[k];
    if (d < 0.5 * e.deflection || d > 1.5 * e.deflection) continue;
    n += 1, sx += d, sy += load[k], sxx += d * d, sxy += d * load[k];
    if (spans)
      r0 += (*spans)[0].reaction[k], r1 += (*spans)[1].reaction[k], p0 += (*spans)[0].plate_load[k],
          p1 += (*spans)[1].plate_load[k];
  }
  e.samples = static_cast<int>(n);
  const double det = n * sxx - sx * sx;
  if (n >= 2 && det > 0) {
    const double slope = (n * sxy - sx * sy) / det;
    e.load = (sy - slope * sx) / n + slope * e.deflection;
  }
  if (r0 + r1 != 0) e.reaction_asymmetry = (r0 - r1) / (r0 + r1);
  if (p0 + p1 != 0) e.plate_load_asymmetry = (p0 - p1) / (p0 + p1);
  return e;
}

/// The failing span (file comment): "left", "right" or "none" (no crack reaches crack width).
[[nodiscard]] inline std::string beam_failing_span(const beam_options& o, const beam_crack& widest,
                                                   const std::string& failure_mode) {
  if (failure_mode == "none") return "none";
  return widest.x < o.half_length() ? "left" : "right";
}

/// The crack map cracks.png from DIR/cracks.csv (side view, point size by opening; `w_max` the
/// largest opening, m): the modelled beam with its support and loading plates.
inline void plot_beam_crack_map(const std::filesystem::path& out, const beam_options& o, real w_max) {
  io::plot_spec cp;
  cp.title = detail::concat("cracked contacts at the end (side view; point size grows with the opening, largest ",
                                     w_max * 1e3, " mm), ", o.model_blocks(), " blocks");
  cp.xlabel = o.full() ? "x along the span from the left beam end (mm); mid-span at the middle"
                       : "x along the span from the beam end (mm); symmetry face on the right";
  cp.ylabel = "y (mm)";
  cp.width_px = o.full() ? 2400 : 1400;
  cp.height_px = 520;
  const real Lm = o.model_length();
  cp.preamble = {detail::concat("set size ratio -1"),
                 detail::concat("set xrange [-5:", Lm * 1e3 + 5, "]"),
                 detail::concat("set yrange [-25:", o.height * 1e3 + 25, "]"),
                 detail::concat("set object 1 rect from 0,0 to ", Lm * 1e3, ",", o.height * 1e3,
                                         " fs empty border lc rgb 'gray40'"),
                 "set key off"};
  for (int k = 0; k < (o.full() ? 2 : 1); ++k) {  // the plates: support below, loading above
    const real xs = o.on_side(k, o.support_x()), xl = o.on_side(k, o.load_x());
    cp.preamble.push_back(detail::concat("set object ", 2 + 2 * k, " rect from ", (xs - o.plate / 2) * 1e3,
                                                  ",-8 to ", (xs + o.plate / 2) * 1e3, ",0 fs solid 0.6 lc rgb 'gray20'"));
    cp.preamble.push_back(detail::concat("set object ", 3 + 2 * k, " rect from ", (xl - o.plate / 2) * 1e3, ",",
                                                  o.height * 1e3, " to ", (xl + o.plate / 2) * 1e3, ",",
                                                  o.height * 1e3 + 8, " fs solid 0.6 lc rgb 'gray20'"));
  }
  cp.series.push_back({.csv = out / "cracks.csv", .x_column = "x_m", .y_column = "y_m", .title = "opened",
                       .style = "points pt 7 ps variable lc rgb 'red'", .x_scale = 1e3, .y_scale = 1e3});
  cp.variable_sizes.push_back({0, "point_size", 1.0});
  io::plot_png(out / "cracks.png", cp);
}

/// The full beam's per-span figures in summary.json: left_* and right_* keys.
inline void set_span_figures(io::summary_json& js, const std::array<beam_span_figures, 2>& spans) {
  for (int k = 0; k < 2; ++k) {
    const beam_span_figures& f = spans[static_cast<std::size_t>(k)];
    const std::string s = k == 0 ? "left_" : "right_";
    const beam_post_peak_crack& p = f.after_peak;
    js.set(s + "support_reaction_at_peak_N", f.reaction_at_peak)
        .set(s + "loading_plate_load_at_peak_N", f.plate_load_at_peak)
        .set(s + "first_inclined_crack_load_N", f.first_inclined_crack_load)
        .set(s + "first_inclined_crack_deflection_m", f.first_inclined_crack_deflection)
        .set(s + "first_inclined_crack_x_m", f.first_inclined_crack_x)
        .set(s + "widest_crack_x_m", f.widest.x)
        .set(s + "widest_crack_angle_deg", f.widest.angle_deg)
        .set(s + "widest_crack_width_m", f.widest.width)
        .set(s + "inclined_after_peak_found", p.found)
        .set(s + "inclined_after_peak_x_m", p.x)
        .set(s + "inclined_after_peak_angle_deg", p.angle_deg)
        .set(s + "inclined_after_peak_top_m", p.y_max)
        .set(s + "inclined_after_peak_opening_increase_m", p.opening_increase)
        .set(s + "inclined_after_peak_opening_rate", p.opening_rate)
        .set(s + "inclined_after_peak_load_drop_N", p.load_drop)
        .set(s + "diagonal_crack_after_peak", p.diagonal);
    std::vector<real> x, total, intact;
    for (const beam_shear_split& sp : f.shear_at_peak)
      x.push_back(sp.x), total.push_back(sp.total()), intact.push_back(sp.intact);
    js.set(s + "shear_at_peak_x_m", x).set(s + "shear_at_peak_total_N", total).set(s + "shear_at_peak_intact_N", intact);
  }
}

}  // namespace tessera::scenes
