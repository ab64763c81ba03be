#pragma once
// One run of the RC beam (beam.hpp): supports and loading, the samples, the crack analysis of a
// beam and the figures of beam_result.
//
// Cracks of a beam. Flexural and diagonal cracks do not cut the beam into pieces, so the
// through-crack analysis of the ties (analysis::crack_graph) does not apply.
// During the run (beam_cracks, for the first developed crack and the first inclined one):
//   - a sub-contact is cracked when it is past its tensile peak (softened);
//   - a face (the sub-contacts of one block pair) is cracked when at least half its area is;
//   - cracked faces that share a block and whose centres lie within 1.5 mean block sizes belong
//     to the same crack (union-find); a crack is kept when it spans at least a quarter of the
//     depth; its inclination is the angle from the vertical of the area-weighted least-squares
//     line x(y) through its sub-contacts (below 35 degrees: vertical, else inclined); its position
//     the mean x of its lowest third.
//   Once many faces have softened (past yield) these clusters merge into one, so:
// At the end (beam_crack_profile): the opening profile along the span; a crack is a local maximum
// of the opening in the lower third of the depth that reaches beam_loading::crack_width (0.1 mm,
// a crack one sees), maxima closer than 0.75 block sizes being one crack. A flexural crack is a
// vertical one in the constant-moment zone; the count and mean spacing are over that zone
// mirrored about the symmetry face (the whole beam's zone, as the study counts).
// Failure mode, from the widest crack: none when no crack reaches crack_width; inclined (35
// degrees or more) and in the shear span -> diagonal_tension; else crushing when the compressive
// cap has dissipated more than tensile cracking; else flexure.
//
// The load. P = twice the support reaction (both half-spans): the force the beam delivers to its
// supports, the load cell of a test. The force on the loading plate's gridpoints is larger by the
// local damping's drag on the beam, which moves down as it deflects (F_d = -0.8 |F| sgn(v)
// opposes the motion even in steady deflection; measured on the 250-block beam: 10 kN on a 56 kN
// plateau). curve.csv keeps both. The events (first crack, peak, failure) read the load smoothed
// over beam_loading::smoothing of deflection (the reactions of a mass-scaled explicit run
// oscillate).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rc_beam/beam.hpp"
#include "tessera/contact/platen.hpp"

namespace tessera::scenes {

struct beam_crack {
  real x = 0;             ///< position along the span: mean x of its lowest third (m)
  real y_min = 0, y_max = 0;
  real angle_deg = 0;     ///< from the vertical
  real width = 0;         ///< largest separation of its sub-contacts (m)
  real area = 0;          ///< cracked face area (m^2)
  [[nodiscard]] bool vertical() const { return angle_deg < 35; }
};

/// Opening of sub-contact i: the separation of its two gridpoints, opening and slip (m).
template <class Contacts>
[[nodiscard]] real subcontact_opening(const Contacts& c, const node_set& gp, index_t i) {
  return (gp.position(c.node_b(i)) - gp.position(c.node_a(i))).norm();
}

/// Weighted least-squares line x(y) through points of a crack; its angle from the vertical.
struct crack_line_fit {
  double sw = 0, sx = 0, sy = 0, sxy = 0, syy = 0;
  void add(double w, const vec3& p) {
    sw += w, sx += w * p.x(), sy += w * p.y(), sxy += w * p.x() * p.y(), syy += w * p.y() * p.y();
  }
  /// Degrees from the vertical; 90 when the points lie at one height.
  [[nodiscard]] real angle_deg() const {
    const double my = sy / sw, var_y = syy / sw - my * my, cov = sxy / sw - (sx / sw) * my;
    return var_y > 0 ? std::atan(std::abs(cov / var_y)) * 180 / std::numbers::pi : 90;
  }
};

/// Crack analysis of a beam (see the file comment). Built once from the contact set; evaluate()
/// allocates its report (not for the step loop).
class beam_cracks {
 public:
  template <class Contacts>
  beam_cracks(const Contacts& c, const node_set& gp, real height, real cell_size)
      : height_(height), cell_(cell_size) {
    // Faces: contiguous runs of one block pair.
    for (index_t i = 0; i < c.size(); ++i) {
      const index_t a = c.block_a(i), b = c.block_b(i);
      if (faces_.empty() || faces_.back().a != a || faces_.back().b != b || faces_.back().end != i)
        faces_.push_back({a, b, i, i, vec3::Zero(), 0});
      face& f = faces_.back();
      f.end = i + 1;
      f.centre += c.area(i) * c.position(i, gp);
      f.area += c.area(i);
    }
    index_t blocks = 0;
    for (face& f : faces_) {
      if (f.area > 0) f.centre /= f.area;
      blocks = std::max({blocks, f.a + 1, f.b + 1});
    }
    block_faces_.assign(static_cast<std::size_t>(blocks), {});
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      block_faces_[static_cast<std::size_t>(faces_[k].a)].push_back(k);
      block_faces_[static_cast<std::size_t>(faces_[k].b)].push_back(k);
    }
  }

  /// Cracks whose sub-contacts are softened, and separated by w_open if w_open > 0.
  template <class Contacts>
  [[nodiscard]] std::vector<beam_crack> evaluate(const Contacts& c, const node_set& gp, real w_open) const {
    const auto jump = [&](index_t i) { return subcontact_opening(c, gp, i); };
    std::vector<char> cracked(faces_.size(), 0);
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      real a = 0;
      for (index_t i = faces_[k].first; i < faces_[k].end; ++i)
        if (analysis::crack_graph::past_peak(c.state(i).flags) && (w_open <= 0 || jump(i) >= w_open)) a += c.area(i);
      cracked[k] = a >= 0.5 * faces_[k].area && faces_[k].area > 0;
    }
    std::vector<std::size_t> parent(faces_.size());
    for (std::size_t k = 0; k < parent.size(); ++k) parent[k] = k;
    const auto find = [&](std::size_t k) {
      while (parent[k] != k) k = parent[k] = parent[parent[k]];
      return k;
    };
    const real reach2 = (1.5 * cell_) * (1.5 * cell_);
    for (const auto& list : block_faces_)
      for (std::size_t p = 0; p < list.size(); ++p)
        for (std::size_t q = p + 1; q < list.size(); ++q) {
          const std::size_t f = list[p], g = list[q];
          if (cracked[f] && cracked[g] && (faces_[f].centre - faces_[g].centre).squaredNorm() <= reach2)
            parent[find(f)] = find(g);
        }
    std::map<std::size_t, std::vector<std::size_t>> groups;
    for (std::size_t k = 0; k < faces_.size(); ++k)
      if (cracked[k]) groups[find(k)].push_back(k);
    std::vector<beam_crack> out;
    for (const auto& [root, list] : groups) {
      beam_crack cr;
      crack_line_fit fit;
      cr.y_min = height_;
      cr.y_max = 0;
      for (std::size_t k : list) {
        cr.area += faces_[k].area;
        for (index_t i = faces_[k].first; i < faces_[k].end; ++i) {
          const vec3 p = c.position(i, gp);
          fit.add(c.area(i), p);
          cr.y_min = std::min(cr.y_min, p.y());
          cr.y_max = std::max(cr.y_max, p.y());
          cr.width = std::max(cr.width, jump(i));
        }
      }
      if (cr.y_max - cr.y_min < 0.25 * height_ || fit.sw <= 0) continue;
      cr.angle_deg = fit.angle_deg();
      double lw = 0, lx = 0;
      const real low = cr.y_min + (cr.y_max - cr.y_min) / 3;
      for (std::size_t k : list)
        for (index_t i = faces_[k].first; i < faces_[k].end; ++i) {
          const vec3 p = c.position(i, gp);
          if (p.y() <= low) lw += c.area(i), lx += c.area(i) * p.x();
        }
      cr.x = lw > 0 ? lx / lw : fit.sx / fit.sw;
      out.push_back(cr);
    }
    std::sort(out.begin(), out.end(), [](const beam_crack& p, const beam_crack& q) { return p.x < q.x; });
    return out;
  }

 private:
  struct face {
    index_t a, b, first, end;
    vec3 centre;
    real area;
  };
  real height_, cell_;
  std::vector<face> faces_;
  std::vector<std::vector<std::size_t>> block_faces_;
};

struct beam_loading {
  real rate = 5e-3;            ///< loading plate velocity (m/s)
  real ramp_time = -1;         ///< half-cosine ramp of the plate velocity (s); < 0: the period T_1 of the first bending mode
  real added_mass_ratio = 0;   ///< > 0: mass scaling to this added-mass multiple
  real dt = 0;                 ///< > 0 (instead): mass-scaled target step (s)
  real max_deflection = 0.006; ///< stop here at the latest (m)
  real failure_drop = 0.25;    ///< stop once the load has fallen this fraction below its peak
  real first_crack_only = 0;   ///< > 0: stop at this multiple of the developed-crack deflection (quick runs)
  index_t sample = 50;           ///< steps between samples
  index_t crack_every = 10;      ///< samples between crack analyses during the run
  real smoothing = 2e-5;       ///< deflection window of the smoothed load (m)
  real crack_width = 1e-4;     ///< opening at which a crack counts at the end of the run (m)
  real damping_gamma = 0.8;
  int threads = 0;
  bool progress = true;
};

struct beam_result {
  /// --plates contact: the support and loading plates' sub-contacts, those in contact at the end,
  /// their rotations (rad) and the mass added to the two plates for the step (kg)
  std::array<std::size_t, 2> plate_subcontacts{}, plate_in_contact{};
  std::array<real, 2> plate_rotation{};
  real plate_added_mass = 0;
  /// load = P = 2 x the support reaction; plate_load = 2 x the force on the loading plate
  std::vector<real> deflection, load, plate_load, load_point_deflection;
  /// load averaged over the last beam_loading::smoothing of deflection: the plate force carries the
  /// oscillations of a mass-scaled explicit run; the events (first crack, peak, failure) read this
  std::vector<real> smoothed_load;
  std::vector<real> crack_count;  ///< vertical + inclined softened cracks at each crack analysis (sample-aligned, -1 between)
  /// First cracking (N): the smoothed load at which the soffit of the constant-moment zone
  /// (sub-contacts with y <= h/10) reaches its contacts' tensile strength (f_T, or s f_T with
  /// calibrated contacts: at the concrete's f_T the event rises as the contacts weaken, since the
  /// soffit of a calibrated beam peaks below f_T; measured 250 blocks, s = 0.852: soffit peak
  /// 2.42 MPa, read at 20.98 kN, after the crack h/4 deep at 11.92 kN) on average: the area-weighted
  /// mean bending stress of its sub-contacts, sum A t_x n_x / sum A n_x^2, first >= f_T; if
  /// cracking sets in before (that mean peaks below f_T and falls 5 % under its peak), the load at
  /// the peak; at the end of a run without either, the load at the highest mean so far. The event
  /// the hand value M_cr = f_T I / (h - y_c) predicts, read at the scale of the section rather than
  /// of one sub-contact (single sub-contacts of a Voronoi assembly soften far earlier: the
  /// 250-block beam's first at 5.6 kN, half the hand value).
  real first_crack_load = 0, first_crack_deflection = 0;
  real soffit_peak_stress = 0;  ///< Pa
  /// The first developed crack: the first vertical crack (beam_cracks) that starts in the soffit's
  /// quarter of the depth; its load (highest smoothed load so far), deflection, position, angle.
  real developed_crack_load = 0, developed_crack_deflection = 0, first_crack_x = 0, first_crack_angle_deg = 0;
  /// The first inclined crack (35 degrees or more from the vertical) in the shear span.
  real first_inclined_crack_load = 0, first_inclined_crack_deflection = -1, first_inclined_crack_x = 0;
  bool inclined_before_vertical = false;  ///< an inclined crack came first (or with the first)
  real initial_stiffness = 0;
  bool steel_yielded = false;
  real yield_load = 0, yield_deflection = 0;
  real peak_load = 0, peak_deflection = 0;
  std::vector<beam_crack> final_cracks;  ///< cracks at the end (beam_crack_profile)
  std::vector<real> flexural_crack_positions;  ///< in the constant-moment zone (half model), m
  int flexural_cracks = 0;               ///< in the whole beam's constant-moment zone (mirrored)
  real mean_crack_spacing = 0;           ///< m, 0 with fewer than two
  std::string failure_mode = "none";
  beam_crack widest;
  /// boundary_work: the work of the supports and, with --plates contact, of the plates (J)
  real energy_balance_error = 0, boundary_work = 0, contact_dissipated = 0, compression_dissipated = 0,
       tension_dissipated = 0, damping_dissipated = 0;
  real dt = 0, added_mass_ratio = 0, quasi_static_index = 0, ramp_time = 0;
  std::int64_t steps = 0;
  index_t subcontacts = 0, zones = 0, gridpoints = 0;
  real contact_points_over_depth = 0;
  real trusses_per_block = 0;
  phase_times phases;
  double runtime_s = 0;
};

/// T_1 of the beam's first bending mode with masses scaled by (1 + added) (beam.hpp file comment).
[[nodiscard]] inline real beam_first_mode_period(const beam_scene& s, real added) {
  const real mass = 2 * s.box.volume() * s.block_material.density;  // whole beam, half of it modal
  return 2 * std::numbers::pi * std::sqrt(mass * (1 + added) / (2 * s.hand.initial_stiffness));
}

/// q of the beam (beam.hpp file comment).
[[nodiscard]] inline real beam_quasi_static_index(const beam_scene& s, real rate, real added) {
  return rate * beam_first_mode_period(s, added) / (s.hand.first_crack_load / s.hand.initial_stiffness);
}

/// Gridpoints within [x0, x1] on the plane y = value.
[[nodiscard]] inline bc::node_group beam_strip(const node_set& gp, real y, real x0, real x1, real tol,
                                               const std::string& name) {
  bc::node_group g;
  g.name = name;
  for (index_t i = 0; i < gp.size(); ++i) {
    const real x = gp.reference(i, 0);
    if (std::abs(gp.reference(i, 1) - y) <= tol && x >= x0 - tol && x <= x1 + tol) g.nodes.push_back(i);
  }
  return g;
}

/// The cracks of a beam at the end of a run, from its opening profile along the span: in bins of
/// 5 mm along x, the largest opening (gridpoint separation) of the softened sub-contacts in the
/// lower third of the depth; a crack is a bin whose opening is at least `width` and the largest
/// within +-0.75 mean block sizes (neighbouring maxima closer than that are one crack). Its angle
/// from the vertical: the opening-weighted least-squares line x(y) through the sub-contacts within
/// 1.5 block sizes of it that opened at least 30 % of its width, over the whole depth.
template <class Contacts>
[[nodiscard]] std::vector<beam_crack> beam_crack_profile(const Contacts& c, const node_set& gp, real height,
                                                         real cell, real width) {
  constexpr real bin = 0.005;
  real x_max = 0;
  for (index_t i = 0; i < c.size(); ++i) x_max = std::max(x_max, c.position(i, gp).x());
  const auto bins = static_cast<std::size_t>(x_max / bin) + 1;
  std::vector<real> opening(bins, 0);
  const auto jump = [&](index_t i) { return subcontact_opening(c, gp, i); };
  for (index_t i = 0; i < c.size(); ++i) {
    const vec3 p = c.position(i, gp);
    if (p.y() > height / 3 || !analysis::crack_graph::past_peak(c.state(i).flags)) continue;
    const auto k = std::min(bins - 1, static_cast<std::size_t>(std::max(real(0), p.x()) / bin));
    opening[k] = std::max(opening[k], jump(i));
  }
  const auto reach = static_cast<std::size_t>(std::ceil(0.75 * cell / bin));
  std::vector<beam_crack> out;
  for (std::size_t k = 0; k < bins; ++k) {
    if (opening[k] < width) continue;
    bool peak = true;
    for (std::size_t j = k > reach ? k - reach : 0; j <= std::min(bins - 1, k + reach) && peak; ++j)
      peak = opening[j] < opening[k] || (opening[j] == opening[k] && j >= k);
    if (!peak) continue;
    beam_crack cr;
    cr.x = (static_cast<real>(k) + 0.5) * bin;
    cr.width = opening[k];
    crack_line_fit fit;
    cr.y_min = height;
    for (index_t i = 0; i < c.size(); ++i) {
      const vec3 p = c.position(i, gp);
      if (std::abs(p.x() - cr.x) > 1.5 * cell || !analysis::crack_graph::past_peak(c.state(i).flags)) continue;
      const real w = jump(i);
      if (w < 0.3 * cr.width) continue;
      fit.add(w, p);
      cr.y_min = std::min(cr.y_min, p.y());
      cr.y_max = std::max(cr.y_max, p.y());
      cr.area += c.area(i);
    }
    if (fit.sw > 0) cr.angle_deg = fit.angle_deg();
    out.push_back(cr);
  }
  return out;
}

/// A rigid plate on a hinge: the gridpoints under it move as one rigid plate that translates at a
/// prescribed vertical velocity v_0 at its axis and turns freely about it (a roller bearing).
/// Each step, before the update, the plate's rotation rate omega (v_y = v_0 + omega (x - x_c)) is
/// advanced from the moment the concrete exerts on the plate, recovered from the last step's
/// reactions (R = m dv/dt - F, central_difference.hpp), with the plate's inertia I = sum m_i
/// (x_i - x_c)^2 (the gridpoints' own, mass-scaled, masses) and local damping, like any other
/// degree of freedom. Without it the tied gridpoints of a 50 mm plate clamp the beam's rotation
/// at the support and under the load (measured: the quick beam 5.4x stiffer than the hand value).
class hinged_plate {
 public:
  hinged_plate(const node_set& gp, bc::node_group group, real axis) : group_(std::move(group)) {
    for (index_t n : group_.nodes) {
      arm_.push_back(gp.reference(n, 0) - axis);
      inertia_ += gp.mass(n) * arm_.back() * arm_.back();
    }
    v_last_.assign(arm_.size(), 0);
  }
  [[nodiscard]] const bc::node_group& group() const { return group_; }
  /// Sets the next step's velocities; call before each step with the axis velocity v0.
  void drive(node_set& gp, real v0, real dt, real gamma) {
    if (inertia_ > 0 && dt > 0) {
      real moment = 0;  // on the plate from the concrete, about the axis
      for (std::size_t k = 0; k < arm_.size(); ++k) {
        const index_t n = group_.nodes[k];
        const real internal = gp.mass(n) * (gp.prescribed_velocity(n, 1) - v_last_[k]) / dt - gp.reaction(n, 1);
        moment += internal * arm_[k];
      }
      const real sign = omega_ > 0 ? 1.0 : (omega_ < 0 ? -1.0 : 0.0);
      omega_ += dt * (moment - gamma * std::abs(moment) * sign) / inertia_;
    }
    for (std::size_t k = 0; k < arm_.size(); ++k) {
      const index_t n = group_.nodes[k];
      v_last_[k] = gp.prescribed_velocity(n, 1);
      gp.prescribed_velocity(n, 1) = v0 + omega_ * arm_[k];
    }
  }
  [[nodiscard]] real rotation_rate() const { return omega_; }

 private:
  bc::node_group group_;
  std::vector<real> arm_, v_last_;
  real inertia_ = 0, omega_ = 0;
};

/// Runs the beam with contact law Law. on_event(solver, tag) at "start" (every check passed, the
/// first step next), "first_crack", "yield", "end" (the peak is not known until the end).
template <class Law, class OnEvent>
[[nodiscard]] beam_result run_beam(const beam_scene& scene, const typename Law::params& law_params,
                                   const beam_loading& loading, OnEvent&& on_event) {
  using solver_type = beam_solver<Law>;
  const cli::wall_timer timer;
  const beam_options& o = scene.options;
  const beam_hand_checks& hand = scene.hand;
  solver_options opt;
  opt.mass_scaling_ratio = loading.dt > 0 ? 0 : loading.added_mass_ratio;
  opt.mass_scaling_dt = loading.dt;
  opt.threads = loading.threads;
  opt.damping_gamma = loading.damping_gamma;
  solver_type s(scene.tess, scene.mesh, scene.block_material, law_params, scene.bar, opt);
  const real L = o.half_length(), tol = 1e-9 * L;
  // Steel plates of their own (--plates contact): registered before the mass scaling is read,
  // since their contact springs join the gridpoints' stiffness bounds.
  const bool contact_plates = o.plates == "contact";
  std::optional<contact::rigid_platen<Law>> support_platen, loading_platen;
  if (contact_plates) {
    auto plate = law_params;  // the plate-concrete pair: frictional at phi_0, no cohesion, never bonded
    plate.shear.c_res = 0;
    plate.shear.phi_res = law_params.shear.phi_0;
    contact::platen_motion m;
    m.mass = 7850 * o.plate * o.width * o.plate_thickness;
    m.inertia = m.mass * (o.plate * o.plate / 12 + o.plate_thickness * o.plate_thickness / 3);  // about the contact face's axis
    m.free_translation = {true, false, false};  // rolls in x, driven or held in y, held in z
    m.hinge_axis = vec3::UnitZ();
    m.damping_gamma = loading.damping_gamma;
    const real z = 0.5 * o.width;
    support_platen.emplace(scene.mesh,
                           contact::platen_geometry{vec3(o.support_x(), 0, z), vec3::UnitY(), vec3::UnitX(), 0.5 * o.plate,
                                                    0.5 * o.width, tol},
                           m, plate);
    loading_platen.emplace(scene.mesh,
                           contact::platen_geometry{vec3(o.load_x(), o.height, z), -vec3::UnitY(), vec3::UnitX(),
                                                    0.5 * o.plate, 0.5 * o.width, tol},
                           m, plate);
    support_platen->attach(s);
    loading_platen->attach(s);
  }
  beam_result r;
  const auto& ms = s.mass_scaling();
  r.added_mass_ratio = ms.original_mass > 0 ? ms.added_mass / ms.original_mass : 0;
  r.quasi_static_index = beam_quasi_static_index(scene, loading.rate, r.added_mass_ratio);
  if (r.quasi_static_index > quasi_static_limit)
    throw invalid_input(tessera::detail::concat(
        "rc_beam: loading rate ", loading.rate, " m/s with added mass ", r.added_mass_ratio,
        "x is not quasi-static: the plate moves ", r.quasi_static_index,
        " x the deflection at first cracking during one period of the first bending mode (limit ", quasi_static_limit,
        "); use a rate <= ", loading.rate * quasi_static_limit / r.quasi_static_index,
        " m/s or less mass scaling (--added-mass / --dt)"));

  node_set& gp = s.gridpoints();
  s.fix(s.gridpoints_on_plane(0, L, tol), bc::along(0));
  const bc::node_group support =
      beam_strip(gp, 0, o.support_x() - o.plate / 2, o.support_x() + o.plate / 2, tol, "support plate");
  const bc::node_group plate = beam_strip(gp, o.height, o.load_x() - o.plate / 2, o.load_x() + o.plate / 2, tol, "loading plate");
  require(!support.nodes.empty() && !plate.nodes.empty(), "rc_beam: no gridpoints under a plate");
  std::optional<hinged_plate> support_plate, loading_plate;
  if (!contact_plates) {
    s.fix(support, bc::along(1) | bc::along(2));
    bc::prescribe_velocity(gp, plate, vec3::Zero(), bc::along(1));
    support_plate.emplace(gp, support, o.support_x());
    loading_plate.emplace(gp, plate, o.load_x());
  }
  for (int b = 0; b < o.bars; ++b) {
    const index_t last = s.reinforcement().bar_nodes(b).second - 1;
    bc::fix(s.bar_nodes(), bc::node_group{{last}, "bar end on the symmetry face"}, bc::along(0));
  }
  std::vector<index_t> midspan;
  for (index_t i = 0; i < gp.size(); ++i)
    if (std::abs(gp.reference(i, 0) - L) <= tol && std::abs(gp.reference(i, 1)) <= tol) midspan.push_back(i);
  require(!midspan.empty(), "rc_beam: no soffit gridpoint on the symmetry face");

  const real ramp = loading.ramp_time >= 0 ? loading.ramp_time : beam_first_mode_period(scene, r.added_mass_ratio);
  r.ramp_time = ramp;
  const auto drive = [&](const solver_type& sv) {
    const real t = sv.time() + 0.5 * sv.dt();
    const real v = t >= ramp ? loading.rate : 0.5 * loading.rate * (1 - std::cos(std::numbers::pi * t / ramp));
    if (contact_plates) {
      loading_platen->set_velocity(vec3(0, -v, 0));
      loading_platen->update(s);
      support_platen->update(s);
    } else {
      loading_plate->drive(gp, -v, sv.dt(), loading.damping_gamma);
      support_plate->drive(gp, 0, sv.dt(), loading.damping_gamma);
    }
  };
  if (contact_plates) drive(s);  // the plates' forces for the first step

  const beam_cracks analyser(s.contacts(), gp, o.height, hand.mean_block_size);
  on_event(std::as_const(s), std::string("start"));  // every check has passed: the run begins
  cli::progress_line progress("rc_beam");
  bool done = false, first_found = false, inclined_found = false, yield_reported = false;
  const std::size_t window = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::llround(loading.smoothing / (loading.rate * s.dt() * static_cast<real>(loading.sample)))));
  double window_sum = 0;
  real max_load = 0;
  index_t samples = 0;
  std::vector<index_t> soffit;  // sub-contacts of the constant-moment zone's soffit (y <= h/10)
  for (index_t i = 0; i < s.contacts().size(); ++i)
    if (s.contacts().position(i, gp).y() <= 0.1 * o.height && s.contacts().position(i, gp).x() >= o.load_x())
      soffit.push_back(i);
  real soffit_peak_load = 0, soffit_peak_deflection = 0;
  const auto sample = [&](const solver_type& sv) {
    real fp = 0, fs = 0, u = 0, up = 0;  // up: the loading plate's vertical displacement
    if (contact_plates) {
      // The forces the plates put on the concrete, and the loading plate's own travel.
      fp = -loading_platen->force().y();
      fs = -support_platen->force().y();
      up = loading_platen->displacement().y();
    } else {
      for (index_t n : plate.nodes) fp += sv.gridpoints().reaction(n, 1), up += sv.gridpoints().displacement(n, 1);
      up /= static_cast<real>(plate.nodes.size());  // the mean over the tied gridpoints
      for (index_t n : support.nodes) fs += sv.gridpoints().reaction(n, 1);
    }
    for (index_t n : midspan) u += sv.gridpoints().displacement(n, 1);
    const real raw = 2 * fs, defl = -u / static_cast<real>(midspan.size());
    r.deflection.push_back(defl);
    r.load.push_back(raw);
    window_sum += raw;
    if (r.load.size() > window) window_sum -= r.load[r.load.size() - 1 - window];
    const real load = window_sum / static_cast<real>(std::min(window, r.load.size()));
    r.smoothed_load.push_back(load);
    r.plate_load.push_back(-2 * fp);
    r.load_point_deflection.push_back(-up);
    if (load > max_load) max_load = load, r.peak_load = load, r.peak_deflection = defl;
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
        r.soffit_peak_stress = sigma;
        r.first_crack_load = load;
        r.first_crack_deflection = defl;
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
    if (samples++ % loading.crack_every == 0 && (!first_found || !inclined_found)) {
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
        if (!c.vertical() && !inclined_found && c.x > o.support_x() && c.x < o.load_x()) {
          inclined_found = true;
          r.first_inclined_crack_load = load;
          r.first_inclined_crack_deflection = defl;
          r.first_inclined_crack_x = c.x;
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
    const bool failed = first_found && load < (1 - loading.failure_drop) * max_load &&
                        defl > r.peak_deflection;
    const bool quick_done = loading.first_crack_only > 0 && first_found &&
                            defl >= loading.first_crack_only * r.developed_crack_deflection;
    done = defl >= loading.max_deflection || failed || quick_done;
    if (loading.progress)
      progress.update(std::min(1.0, defl / loading.max_deflection),
                      tessera::detail::concat("deflection ", defl * 1e3, " mm, P = ", load * 1e-3, " kN",
                                              first_found ? ", cracked" : "", r.steel_yielded ? ", yielded" : ""));
  };
  s.run_until([&](const solver_type&) { return done; }, std::int64_t{1} << 40, drive,
              recorders::every(loading.sample, sample));
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
  const real zone0 = o.load_x();
  std::vector<real> mirrored;
  for (const beam_crack& c : r.final_cracks) {
    if (c.width > r.widest.width) r.widest = c;
    if (!c.vertical() || c.x < zone0) continue;
    r.flexural_crack_positions.push_back(c.x);
    mirrored.push_back(c.x);
    if (L - c.x > 0.5 * hand.mean_block_size) mirrored.push_back(2 * L - c.x);  // its twin across the symmetry face
  }
  std::sort(mirrored.begin(), mirrored.end());
  r.flexural_cracks = static_cast<int>(mirrored.size());
  if (mirrored.size() >= 2) r.mean_crack_spacing = (mirrored.back() - mirrored.front()) / static_cast<real>(mirrored.size() - 1);
  const energy_balance e = s.energies();
  const contact::contact_energies ce = s.contacts().energies();
  r.compression_dissipated = ce.dissipated_compression;
  r.tension_dissipated = ce.dissipated_tension;
  if (r.widest.width < loading.crack_width)
    r.failure_mode = "none";
  else if (!r.widest.vertical() && r.widest.x > o.support_x() && r.widest.x < o.load_x() + o.plate / 2)
    r.failure_mode = "diagonal_tension";
  else if (r.compression_dissipated > r.tension_dissipated)
    r.failure_mode = "crushing";
  else
    r.failure_mode = "flexure";
  r.energy_balance_error = e.error_rel();
  r.boundary_work = e.boundary_work + e.applied_work;
  if (contact_plates) {
    r.plate_subcontacts = {support_platen->size(), loading_platen->size()};
    r.plate_in_contact = {support_platen->in_contact(), loading_platen->in_contact()};
    r.plate_rotation = {support_platen->rotation(), loading_platen->rotation()};
    r.plate_added_mass = support_platen->added_mass() + loading_platen->added_mass();
  }
  r.contact_dissipated = e.contact_dissipated;
  r.damping_dissipated = e.damping_dissipated;
  r.dt = s.dt();
  r.steps = s.step_count();
  r.phases = s.phases();
  r.subcontacts = s.contacts().size();
  r.zones = scene.mesh.zone_count();
  r.gridpoints = scene.mesh.gridpoint_count();
  std::vector<real> areas;
  for (index_t i = 0; i < s.contacts().size(); ++i) areas.push_back(s.contacts().area(i));
  std::nth_element(areas.begin(), areas.begin() + static_cast<std::ptrdiff_t>(areas.size() / 2), areas.end());
  r.contact_points_over_depth = areas.empty() ? 0 : o.height / std::sqrt(areas[areas.size() / 2]);
  r.trusses_per_block = static_cast<real>(scene.elements_per_bar) * hand.mean_block_size / (L - o.end_cover);
  r.runtime_s = timer.seconds();
  return r;
}

/// The elastic-compression variant of the beam's contact parameters (no cap).
[[nodiscard]] inline presets::linear_tie_law::params beam_elastic_compression(const presets::study_beam_law::params& p) {
  presets::linear_tie_law::params q;
  q.k_n = p.k_n;
  q.k_s = p.k_s;
  q.tension = p.tension;
  q.shear = p.shear;
  return q;
}

template <class OnEvent>
[[nodiscard]] beam_result run_beam(const beam_scene& scene, const beam_loading& loading, OnEvent&& on_event) {
  if (scene.options.compression == "elastic")
    return run_beam<presets::linear_tie_law>(scene, beam_elastic_compression(scene.contact), loading, on_event);
  return run_beam<presets::study_beam_law>(scene, scene.contact, loading, on_event);
}

}  // namespace tessera::scenes
