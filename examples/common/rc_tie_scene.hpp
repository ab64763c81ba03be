#pragma once
// The reference study's reinforced-concrete tie (Pulatsu et al. 2020, Sec. 3.1; DESIGN.md §4),
// built on the plain prism of scenes.hpp, and everything the tie drivers share: the hand checks,
// the supports and loading, one complete run with its measurements, and the curve analyses
// (load drops, through-cracks, initial stiffness, curve error). Used by examples/rc_tie,
// examples/rc_tie_sensitivity and benchmarks/work_precision_tie.
//
//   specimen  the 68 x 68 x 600 mm prism of scenes.hpp (long axis z), N random Voronoi blocks
//   bar       one Ø8 mm bar on the axis from z = 0 to z = L, E_s = 192.3 GPa, f_y = 400 MPa
//             (f_y A = 20.1 kN), `elements` truss elements (96), bond ratio xi (4), c_bond (1e9 N/m)
//   supports  first bar node (z = 0) fixed in x, y, z; last bar node (z = L) pulled along z at
//             `rate`, held in x, y; concrete end gridpoints (z = 0 and z = L) on rollers: x and y
//             fixed, z free. The concrete is loaded only through the bond.
//   measured  force = tension in the bar at its fixed end = -(reaction z of bar node 0) (N,
//             tension +); elongation = z displacement of the pulled bar node (m).
//
// Loading history: the pulled node's velocity rises from 0 to `rate` along a half-cosine over
// `ramp_time` (smooth acceleration, so the start sends no stress wave), then stays constant.
// Time step: masses are scaled so the step `dt` is stable (solver_options::mass_scaling_dt; the
// random Voronoi zoning has sliver zones whose unscaled stable step is ~3e-9 s). The result is
// quasi-static when the loading time is long against the scaled model's lowest period; the
// drivers check that by halving the rate and the step (docs in examples/rc_tie/main.cpp).
//
// --bare: the same bar unbonded (no host, no bond) with every concrete gridpoint fixed; the run
// then measures the bare bar alone (the reference branch the cracked tie converges to).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "common/cli.hpp"
#include "common/curves.hpp"
#include "common/scenes.hpp"
#include "tessera/core/errors.hpp"
#include "phase_report.hpp"
#include "quasi_static.hpp"
#include "tessera/reinforcement/embedded_truss.hpp"
#include "tessera/presets.hpp"
#include "tessera/solver.hpp"

namespace tessera::scenes {

using tie_bar = reinforcement::embedded_truss<reinforcement::coulomb_bond>;
/// Blocks (deformable semi-rigid tets, or rigid 6-DOF bodies), the given contact law with the
/// contact set's pack path (law::with_elastic_packs: same bits as Law without FMA contraction,
/// faster on the tie), the embedded bar.
template <class Blocks, class Law>
using tie_solver = solver<Blocks, presets::bonded_faces<Law>, tie_bar>;
using deformable_blocks = blocks::deformable<zones::linear_elastic_tet>;

struct tie_options {
  int blocks = 100;          ///< 100, 250, 500 or 750 (Table 1 contact stiffnesses)
  std::uint64_t seed = 1;    ///< tessellation seed
  index elements = 96;       ///< truss elements along the bar
  real xi = 4;               ///< bond stiffness ratio K_bond / K_axial (study eq. 9)
  real c_bond = 1e9;         ///< bond cohesion (N per m of bar)
  /// How xi K_axial becomes a nodal bond spring (reinforcement/bond.hpp): per unit bar length is
  /// 3DEC's grout stiffness and reproduces the study's load drops; per node is DESIGN.md's reading.
  reinforcement::stiffness_basis bond_basis = reinforcement::stiffness_basis::per_unit_length;
  /// Short-edge regularization of the Voronoi cells (geometry/regularize.hpp), relative to the
  /// mean cell size; 0 = plain Voronoi.
  real regularize = 0;
  /// Lloyd relaxation steps of the tessellation (each generator moved to its cell centroid;
  /// geometry/voronoi.hpp): more uniform, rounder cells; 0 = plain random Voronoi.
  int lloyd = 0;
  /// Initial cohesion of the concrete contacts c_0 / f_T (the study and DESIGN.md: 2; c_res =
  /// 0.01 c_0 either way).
  real cohesion_ratio = 2;
  bool bare = false;         ///< unbonded bar, concrete fixed (bare-bar reference run)
  bool rigid = false;        ///< rigid blocks (blocks::rigid; bond hosts are still the zones, no confinement)
};

/// Closed-form references of the tie (DESIGN.md §4). A_c is the net concrete area b^2 - A_s of
/// the transformed section (the modelled concrete fills the gross b^2, which raises N_cr and the
/// uncracked stiffness by about 1 %).
struct tie_hand_checks {
  real length = 0;               ///< L (m)
  real steel_area = 0;           ///< A_s = pi d^2 / 4 (m^2)
  real concrete_area = 0;        ///< A_c = b^2 - A_s (m^2)
  real modular_ratio = 0;        ///< n = E_s / E_c
  real cracking_force = 0;       ///< N_cr = f_T (A_c + n A_s) (N)
  real uncracked_stiffness = 0;  ///< (E_c A_c + E_s A_s) / L (N/m)
  real bare_bar_stiffness = 0;   ///< E_s A_s / L (N/m)
  real bond_modulus = 0;         ///< k_b, bond stiffness per unit bar length per unit slip (N/m^2)
  /// Uncracked stiffness of the tie loaded through its bar ends with a bond of modulus k_b
  /// (shear lag): delta / P = L / EA + (EA_c / EA) (2 / (lambda EA_s)) tanh(lambda L / 2), with
  /// EA = EA_s + EA_c and lambda^2 = k_b (1/EA_s + 1/EA_c). The bar alone carries P at its ends and
  /// hands it to the concrete over a transfer length 1/lambda; uncracked_stiffness is the limit
  /// k_b -> infinity (N/m).
  real bonded_stiffness = 0;
  real yield_force = 0;          ///< f_y A_s (N)
  /// Bare bar, elastic-perfectly plastic: F(u) = min(E_s A_s u / L, f_y A_s) for u >= 0 (N).
  [[nodiscard]] real bare_bar_force(real elongation) const {
    return std::min(bare_bar_stiffness * elongation, yield_force);
  }
};

struct tie_scene {
  prism_scene prism;
  tie_bar::params bar;
  tie_hand_checks hand;
  tie_options options;
};

/// Builds the tie: the prism of scenes.hpp (Voronoi, zoning, Table 1 contacts) and the bar on its
/// axis with the study's steel and bond. Throws invalid_input naming a bad option.
[[nodiscard]] inline tie_scene make_tie(const tie_options& o) {
  require(o.elements >= 1, "rc_tie: truss elements = ", o.elements, " must be >= 1");
  require_positive(o.xi, "rc_tie: bond stiffness ratio xi");
  require_positive(o.c_bond, "rc_tie: bond cohesion c_bond (N/m)");
  require(o.lloyd >= 0, "rc_tie: Lloyd steps (--lloyd) = ", o.lloyd, " must be >= 0");
  require(std::isfinite(o.cohesion_ratio) && o.cohesion_ratio >= 0, "rc_tie: --cohesion-ratio ", o.cohesion_ratio,
          " must be finite and >= 0");
  tie_scene t;
  t.options = o;
  prism_options po;
  po.blocks = o.blocks;
  po.seed = o.seed;
  po.tessellation.min_edge_rel = o.regularize;
  po.tessellation.lloyd_iterations = o.lloyd;
  po.cohesion_ratio = o.cohesion_ratio;
  t.prism = make_prism(po);
  const vec3 lo = t.prism.box.lo, hi = t.prism.box.hi;
  const vec3 start(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), lo.z());
  const vec3 end(start.x(), start.y(), hi.z());
  t.bar = reinforcement::pulatsu2020::tie_reinforcement(start, end, o.elements);
  t.bar.bond.stiffness_ratio = o.xi;
  t.bar.bond.cohesion = o.c_bond;
  t.bar.bond.basis = o.bond_basis;
  t.bar.bars.front().bonded = !o.bare;

  tie_hand_checks& h = t.hand;
  const reinforcement::steel& s = t.bar.steel;
  h.length = t.prism.length();
  h.steel_area = s.area();
  h.concrete_area = t.prism.cross_section() - h.steel_area;
  h.modular_ratio = s.young_modulus / concrete_young;
  h.cracking_force = t.prism.contact.tension.f_T * (h.concrete_area + h.modular_ratio * h.steel_area);
  h.uncracked_stiffness = (concrete_young * h.concrete_area + s.young_modulus * h.steel_area) / h.length;
  h.bare_bar_stiffness = s.young_modulus * h.steel_area / h.length;
  {
    const real ea_s = s.young_modulus * h.steel_area, ea_c = concrete_young * h.concrete_area, ea = ea_s + ea_c;
    const real l_el = h.length / static_cast<real>(o.elements);
    const real k_axial = ea_s / l_el;  // eq. 8
    // eq. 9: xi K_axial is the modulus per unit length (per_unit_length) or a spring per node of
    // tributary length L_el (per_node), see reinforcement/bond.hpp
    h.bond_modulus = o.bond_basis == reinforcement::stiffness_basis::per_unit_length ? o.xi * k_axial
                                                                                    : o.xi * k_axial / l_el;
    const real lambda = std::sqrt(h.bond_modulus * (1 / ea_s + 1 / ea_c));
    const real compliance = h.length / ea + (ea_c / ea) * (2 / (lambda * ea_s)) * std::tanh(0.5 * lambda * h.length);
    h.bonded_stiffness = 1 / compliance;
  }
  h.yield_force = s.yield_force();
  return t;
}

/// Loading and run control of one tie run.
struct tie_loading {
  real rate = 5e-3;             ///< elongation rate of the bar (m/s)
  /// true: the bar ends move at -rate/2 and +rate/2 (the study's setup up to a rigid translation);
  /// false: first bar node fixed, last pulled at rate (the study's setup verbatim). Local damping
  /// (F_d = gamma |F| sgn(v)) is not Galilean invariant: with one end fixed the concrete, free
  /// along z on its rollers, drifts at about rate/2 and the damping drags it, so the forces at the
  /// two bar ends differ (measured: up to 20 % of f_y A at gamma = 0.8). Pulling both ends keeps
  /// the concrete's mean velocity at zero; the elongation is the same.
  bool symmetric = true;
  real ramp_time = 2e-3;        ///< half-cosine velocity ramp from 0 to rate (s)
  real dt = 2e-6;               ///< mass-scaling target step (s); 0 = unscaled stable step
  /// > 0: instead of `dt`, the step at which mass scaling adds this multiple of the original mass
  /// (solver_options::mass_scaling_ratio; deformable blocks)
  real added_mass_ratio = 0;
  real max_elongation = 2e-3;   ///< stop here at the latest (m)
  real post_yield = 0.25;       ///< after the tie yields at elongation u_y (see yield_elongation), stop at (1 + this) u_y
  index sample = 25;            ///< steps between curve samples
  real damping_gamma = 0.8;     ///< local damping constant (study and 3DEC default 0.8)
  int threads = 0;              ///< OpenMP threads (0 = default)
  std::string softening = "power";  ///< "power" (alpha = 3) or "linear"
  /// "decoupled" (cohesion c_0 until broken, DESIGN.md) or "coupled" (cohesion softens with f_t/f_T,
  /// law::coulomb_coupled; power softening and deformable blocks only)
  std::string cohesion = "decoupled";
  /// Shear failure also breaks a contact in tension (law shear params slip_breaks_tension; opt-in,
  /// DESIGN.md keeps the tensile strength of a contact that slipped).
  bool slip_breaks_tension = false;
  std::string progress_label;   ///< non-empty: a progress line on stderr with this label
};

/// Mass-scaled time step for a tie of `blocks` blocks that keeps the added mass near the
/// 100-block value (about 70x at 2 us). The stable step falls with the block size and the Table 1
/// contact stiffness: at a fixed 2 us the masses are scaled 69x (100 blocks), 218x (250) and 403x
/// (500), and the 500-block response turns inertia-dominated (first crack +78 % against +16 % at
/// 0.5 us). Added mass grows as dt^2, and 2 us x (100/blocks)^0.55 gives 2, 1.2 and 0.83 us.
[[nodiscard]] inline real scaled_tie_dt(int blocks, real dt_100 = 2e-6) {
  return dt_100 * std::pow(100.0 / static_cast<real>(blocks), 0.55);
}

/// One local peak of the force followed by a drop (a crack forming).
struct load_drop {
  real peak_force = 0;        ///< N
  real peak_elongation = 0;   ///< m
  real trough_force = 0;      ///< lowest force before the curve rose again (N)
  std::size_t sample = 0;     ///< curve index of the peak
};

/// Through-cracks of the concrete (see count_through_cracks).
struct crack_report {
  int pieces = 1;                     ///< connected concrete pieces
  int cracks = 0;                     ///< pieces - 1
  /// Mean z of each surface between two separated pieces (m), ascending: more surfaces than
  /// cracks where three pieces touch pairwise (a slice that does not fill the section).
  std::vector<real> positions;
  /// Cracks the bar crosses: changes of concrete piece from one bar node's host block to the
  /// next, walking the bar (-1 when the graph has no bar path). A fragment split off by a
  /// branching crack (a piece the bar does not pass through) adds a piece but no crossing.
  int bar_crossings = -1;
  std::vector<real> bar_crossing_positions;  ///< z of each crossing: mean z of the surface between the two pieces (m)
  real opening_threshold = 0;         ///< w_open (m)
  index open_subcontacts = 0;         ///< sub-contacts opened beyond w_open
};

struct tie_result {
  std::vector<real> elongation, force;  ///< the curve (m, N), one row per sample
  /// Tension at the pulled end (N): equals `force` in a quasi-static state (the concrete, free
  /// along z, carries no net force), so |pulled_force - force| measures the inertia and damping
  /// forces still in the model.
  std::vector<real> pulled_force;
  /// Mean axial stress of the concrete over the middle two thirds of the tie (Pa): (F - mean bar
  /// force there) / A_c, i.e. the concrete's share of the load where the bond has handed it over.
  std::vector<real> concrete_stress;
  std::vector<index> softened_subcontacts;  ///< sub-contacts past their tensile peak, per sample
  real max_imbalance = 0;               ///< max |pulled_force - force| / f_y A over the run
  std::vector<load_drop> drops;         ///< before the first yield
  crack_report cracks;                  ///< fully opened through-cracks at the end of the run
  crack_report cracks_normal_only;      ///< the same counted by the normal opening u_n alone
  crack_report softened_cracks;         ///< softened through-cracks at the end of the run
  /// Softened through-cracks as they form: (elongation m, highest force so far N) when the count rises.
  std::vector<std::pair<real, real>> crack_formation;
  /// First cracking (N): the highest force reached before the first softened through-crack has
  /// formed (the macro-crack forms at or just after the peak), counting only cracks formed once
  /// the force has passed N_cr / 2 (a coarse, fast start-up can soften a section at the pulled
  /// end earlier); without one, the first drop's peak, else the maximum before yield.
  real first_crack_force = 0;
  /// Peak of the first load drop whose peak is above N_cr / 2 (N); 0 without one. Differs from
  /// first_crack_force when the first crack drops the load before it has softened across the whole
  /// section (500 blocks: first drop 12.29 kN, first softened through-crack 15.67 kN).
  real first_drop_force = 0;
  /// Force when the first sub-contact passed its tensile peak (N), after the force has passed
  /// N_cr / 10 (start-up): the onset of (distributed) cracking, long before a through-crack.
  real first_softening_force = 0;
  real concrete_stress_at_first_crack = 0;  ///< concrete_stress at the first_crack_force sample (Pa)
  index softened_at_first_crack = 0;        ///< softened_subcontacts at that sample
  real initial_stiffness = 0;           ///< N/m (initial_stiffness())
  real yield_force = 0;                 ///< mean force over the second half of the post-yield samples (N), 0 if not yielded
  /// Elongation at yield (m): the bar's plastic elongation has reached 2 % of the bare bar's yield
  /// elongation with F >= 0.9 f_y A (sustained flow, not a transient yield of one element).
  real yield_elongation = 0;
  /// Where the final branch has got to: the mean of the two bar-end forces over the last 2 % of the
  /// elongation (N); 0 if not yielded. The two ends differ by the damping and inertia forces on the
  /// floating concrete, so their mean is the better estimate of the quasi-static force.
  real final_force = 0;
  real end_elongation = 0;              ///< m
  real energy_balance_error = 0;
  real boundary_work = 0, contact_dissipated = 0, damping_dissipated = 0, bar_dissipated = 0;  ///< J
  real dt = 0, added_mass_ratio = 0;
  std::int64_t steps = 0;
  index subcontacts = 0, zones = 0, gridpoints = 0;
  phase_times phases;  ///< time per phase of the step (solver::phases)
  double runtime_s = 0;
  bool yielded = false;
};

// ---------------------------------------------------------------- curve analyses

/// Streaming detector of load drops: a local peak of the force followed by a drop of more than
/// `threshold` (N) before the force rises by more than `threshold` above the trough again
/// (hysteresis, so noise below the threshold is no drop).
class load_drop_detector {
 public:
  explicit load_drop_detector(real threshold) : threshold_(threshold) {}
  /// Adds sample k = (elongation, force); returns true when it completes a new drop.
  bool push(real elongation, real force) {
    const std::size_t k = count_++;
    if (rising_) {
      if (k == 0 || force >= peak_force_) {
        peak_force_ = force, peak_elongation_ = elongation, peak_sample_ = k;
      } else if (force < peak_force_ - threshold_) {
        drops_.push_back({peak_force_, peak_elongation_, force, peak_sample_});
        rising_ = false;
        return true;
      }
    } else {
      load_drop& d = drops_.back();
      d.trough_force = std::min(d.trough_force, force);
      if (force > d.trough_force + threshold_) {
        rising_ = true;
        peak_force_ = force, peak_elongation_ = elongation, peak_sample_ = k;
      }
    }
    return false;
  }
  [[nodiscard]] const std::vector<load_drop>& drops() const { return drops_; }

 private:
  real threshold_;
  std::size_t count_ = 0, peak_sample_ = 0;
  bool rising_ = true;
  real peak_force_ = 0, peak_elongation_ = 0;
  std::vector<load_drop> drops_;
};

/// The load drops of samples [0, end) of a curve (load_drop_detector).
[[nodiscard]] inline std::vector<load_drop> find_load_drops(const std::vector<real>& elongation,
                                                            const std::vector<real>& force, real threshold,
                                                            std::size_t end) {
  load_drop_detector d(threshold);
  end = std::min(end, force.size());
  for (std::size_t k = 0; k < end; ++k) d.push(elongation[k], force[k]);
  return d.drops();
}

/// Least-squares slope (N/m) of force against elongation through the samples with
/// 0.1 F_1 <= F <= 0.6 F_1 before the first peak F_1 (the linear branch, away from the start-up
/// ramp and from the pre-peak softening of the first crack).
[[nodiscard]] inline real initial_stiffness(const std::vector<real>& elongation, const std::vector<real>& force,
                                            std::size_t first_peak) {
  const real f1 = force.empty() ? 0 : force[std::min(first_peak, force.size() - 1)];
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t k = 0; k <= first_peak && k < force.size(); ++k) {
    if (force[k] < 0.1 * f1 || force[k] > 0.6 * f1) continue;
    sx += elongation[k], sy += force[k], sxx += elongation[k] * elongation[k], sxy += elongation[k] * force[k];
    ++n;
  }
  if (n < 2 || n * sxx - sx * sx <= 0) return 0;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/// Curve error of (x, y) against a reference (xr, yr): the RMS force difference over the common
/// elongation range [0, min(x_end, xr_end)] on 2000 equal intervals (trapezoidal), relative to
/// `scale` (the yield force f_y A):  e = sqrt( (1/U) int_0^U (F - F_ref)^2 du ) / scale.
/// Curves must have ascending abscissae (elongation under monotonic pulling).
[[nodiscard]] inline real curve_error(const std::vector<real>& x, const std::vector<real>& y,
                                      const std::vector<real>& xr, const std::vector<real>& yr, real scale) {
  if (x.size() < 2 || xr.size() < 2) return 1;
  const real u_end = std::min(x.back(), xr.back());
  if (u_end <= 0) return 1;
  return rms_curve_difference(x, y, xr, yr, u_end, 2000) / scale;
}

/// A monotone copy of a sampled elongation history (running maximum), so curves sampled during
/// the start-up ramp or small reversals can be interpolated.
[[nodiscard]] inline std::vector<real> running_max(std::vector<real> x) {
  for (std::size_t k = 1; k < x.size(); ++k) x[k] = std::max(x[k], x[k - 1]);
  return x;
}

/// Crack sites along the tie: the through-crack surfaces (their mean z, any order) grouped where
/// neighbouring surfaces lie less than `spacing` apart along the axis, each group reported by its
/// mean z, ascending. With spacing = the mean cell size (box volume / blocks)^(1/3), a crack that
/// runs around a slice of blocks thinner than one cell, and so has two separating surfaces, is one
/// site, as it is one crack to the eye (and in the study's figures). Throws invalid_input for
/// spacing <= 0.
[[nodiscard]] inline std::vector<real> crack_sites(std::vector<real> positions, real spacing) {
  require(std::isfinite(spacing) && spacing > 0, "crack_sites: spacing = ", spacing, " m must be finite and > 0");
  std::sort(positions.begin(), positions.end());
  std::vector<real> sites;
  real sum = 0;
  int count = 0;
  for (std::size_t k = 0; k < positions.size(); ++k) {
    if (count > 0 && positions[k] - positions[k - 1] >= spacing) {
      sites.push_back(sum / count);
      sum = 0;
      count = 0;
    }
    sum += positions[k];
    ++count;
  }
  if (count > 0) sites.push_back(sum / count);
  return sites;
}

/// Through-cracks. The sub-contacts are grouped into faces by their block pair (two convex cells
/// share at most one face). A face is *cracked* when every sub-contact on it satisfies a
/// predicate; the concrete pieces are the connected components of the block graph whose edges
/// are the faces that are not cracked; a through-crack is a surface of cracked faces that
/// separates the prism into two pieces, so cracks = pieces - 1 (the bar, which crosses every
/// crack, is not part of the graph). Its position is the area-weighted mean z of the cracked
/// sub-contacts between the two pieces. Two predicates are used:
///  - softened: every sub-contact is past its tensile peak (softening or broken) — a crack has
///    formed across the section and the section's tensile capacity is falling;
///  - opened: every sub-contact is softened and its two gridpoints have separated by at least
///    w_open = 2 G_f / f_T (56 µm for the study's concrete; linear softening has no strength left
///    there, power softening (alpha = 3) at most f_T / 8) — a fully opened crack. The separation
///    is the whole displacement jump |x_B - x_A| (opening and slip), the crack-opening
///    displacement: faces of a tortuous crack that lie steeply to the bar open mostly by sliding
///    (a face at 65 deg to the section sees 0.42 of the axial opening as u_n), and measured
///    by u_n alone such a face would keep a 100 µm crack from counting. (Counted by u_n alone,
///    the baseline has 0 opened through-cracks: crack_report::opened_normal_only.)
class crack_graph {
 public:
  template <class Contacts>
  explicit crack_graph(const Contacts& contacts, index blocks) : blocks_(blocks) {
    const index n = contacts.size();
    order_.resize(static_cast<std::size_t>(n));
    std::iota(order_.begin(), order_.end(), index{0});
    const auto pair_of = [&](index i) { return std::pair<index, index>(contacts.block_a(i), contacts.block_b(i)); };
    std::stable_sort(order_.begin(), order_.end(), [&](index a, index b) { return pair_of(a) < pair_of(b); });
    for (std::size_t k = 0; k < order_.size();) {
      std::size_t e = k;
      while (e < order_.size() && pair_of(order_[e]) == pair_of(order_[k])) ++e;
      faces_.push_back({pair_of(order_[k]).first, pair_of(order_[k]).second, static_cast<index>(k), static_cast<index>(e)});
      k = e;
    }
    parent_.resize(static_cast<std::size_t>(blocks));
  }

  /// The bar's path through the concrete: host block and z of each bar node, in bar order
  /// (enables crack_report::bar_crossings).
  void set_bar_path(std::vector<index> node_blocks, std::vector<real> node_z) {
    require(node_blocks.size() == node_z.size(), "crack_graph: ", node_blocks.size(), " host blocks for ", node_z.size(),
            " bar nodes");
    bar_blocks_ = std::move(node_blocks);
    bar_z_ = std::move(node_z);
  }

  /// Through-cracks of faces whose every sub-contact i satisfies cracked(i).
  template <class Contacts, class Cracked>
  [[nodiscard]] crack_report evaluate(const Contacts& contacts, const node_set& gridpoints, Cracked&& cracked,
                                      real opening_threshold = 0) {
    crack_report r;
    r.opening_threshold = opening_threshold;
    std::iota(parent_.begin(), parent_.end(), index{0});
    std::vector<std::size_t> cracked_faces;
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      bool all = true;
      for (index k = faces_[f].first; k < faces_[f].last; ++k) {
        if (cracked(order_[static_cast<std::size_t>(k)])) ++r.open_subcontacts;
        else all = false;
      }
      if (all) cracked_faces.push_back(f);
      else parent_[static_cast<std::size_t>(find(faces_[f].a))] = find(faces_[f].b);
    }
    r.pieces = 0;
    for (index b = 0; b < blocks_; ++b)
      if (find(b) == b) ++r.pieces;
    r.cracks = r.pieces - 1;
    std::vector<std::pair<std::pair<index, index>, std::pair<double, double>>> surfaces;  // pieces -> (sum A z, sum A)
    const auto surface_between = [&](index pa, index pb) {  // the surface separating two pieces, or end()
      const std::pair<index, index> key = std::minmax(pa, pb);
      return std::find_if(surfaces.begin(), surfaces.end(), [&](const auto& x) { return x.first == key; });
    };
    for (std::size_t f : cracked_faces) {
      index pa = find(faces_[f].a), pb = find(faces_[f].b);
      if (pa == pb) continue;  // a cracked face inside one piece: the crack does not separate there
      if (pa > pb) std::swap(pa, pb);
      auto it = surface_between(pa, pb);
      if (it == surfaces.end()) {
        surfaces.push_back({{pa, pb}, {0.0, 0.0}});
        it = surfaces.end() - 1;
      }
      for (index k = faces_[f].first; k < faces_[f].last; ++k) {
        const index i = order_[static_cast<std::size_t>(k)];
        it->second.first += contacts.area(i) * contacts.position(i, gridpoints).z();
        it->second.second += contacts.area(i);
      }
    }
    for (const auto& x : surfaces)
      if (x.second.second > 0) r.positions.push_back(x.second.first / x.second.second);
    std::sort(r.positions.begin(), r.positions.end());
    if (!bar_blocks_.empty()) {
      r.bar_crossings = 0;
      for (std::size_t k = 1; k < bar_blocks_.size(); ++k) {
        const index pa = find(bar_blocks_[k - 1]), pb = find(bar_blocks_[k]);
        if (pa == pb) continue;
        ++r.bar_crossings;
        const auto it = surface_between(pa, pb);
        r.bar_crossing_positions.push_back(it != surfaces.end() && it->second.second > 0
                                               ? it->second.first / it->second.second
                                               : 0.5 * (bar_z_[k - 1] + bar_z_[k]));
      }
    }
    return r;
  }

  /// Fully opened through-cracks: every sub-contact of the faces softened (or broken) and its
  /// gridpoints separated by |x_B - x_A| >= w_open.
  template <class Contacts>
  [[nodiscard]] crack_report opened(const Contacts& contacts, const node_set& gridpoints, real w_open) {
    return evaluate(
        contacts, gridpoints,
        [&](index i) {
          const real jump = (gridpoints.position(contacts.node_b(i)) - gridpoints.position(contacts.node_a(i))).norm();
          return past_peak(contacts.state(i).flags) && jump >= w_open;
        },
        w_open);
  }
  /// The stricter count: the normal opening u_n >= w_open on every sub-contact of the faces.
  template <class Contacts>
  [[nodiscard]] crack_report opened_normal_only(const Contacts& contacts, const node_set& gridpoints, real w_open) {
    return evaluate(contacts, gridpoints, [&](index i) { return contacts.state(i).u_n >= w_open; }, w_open);
  }
  /// Softened through-cracks (every sub-contact of the faces past its tensile peak).
  template <class Contacts>
  [[nodiscard]] crack_report softened(const Contacts& contacts, const node_set& gridpoints) {
    return evaluate(contacts, gridpoints, [&](index i) { return past_peak(contacts.state(i).flags); });
  }
  /// A sub-contact past its tensile peak: softening or broken in tension.
  [[nodiscard]] static bool past_peak(law::contact_status flags) {
    return law::has(flags, law::contact_status::softening) || law::has(flags, law::contact_status::broken_tension);
  }

 private:
  struct face {
    index a, b, first, last;
  };
  index find(index b) {
    while (parent_[static_cast<std::size_t>(b)] != b) {
      parent_[static_cast<std::size_t>(b)] = parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(b)])];
      b = parent_[static_cast<std::size_t>(b)];
    }
    return b;
  }
  index blocks_;
  std::vector<index> order_;
  std::vector<face> faces_;
  std::vector<index> parent_;
  std::vector<index> bar_blocks_;  ///< host block of each bar node, in bar order (empty: no bar path)
  std::vector<real> bar_z_;
};

// ---------------------------------------------------------------- one run

/// Runs the tie with contact law Law (law parameters `law_params`) under `loading`. `on_event`
/// is called as on_event(solver, tag) at each load drop ("drop1", "drop2", ...), at the first
/// yield of the bar ("yield") and at the end ("end"), e.g. to write VTK snapshots.
template <class Blocks, class Law, class OnEvent>
[[nodiscard]] tie_result run_tie(const tie_scene& scene, const typename Law::params& law_params,
                                 const tie_loading& loading, OnEvent&& on_event) {
  using solver_type = tie_solver<Blocks, Law>;
  namespace bc = tessera::bc;
  require_positive(loading.rate, "rc_tie: pull rate (m/s)");
  require_non_negative(loading.ramp_time, "rc_tie: ramp time (s)");
  require_positive(loading.max_elongation, "rc_tie: maximum elongation (m)");
  const cli::wall_timer timer;
  solver_options opt;
  opt.mass_scaling_dt = loading.added_mass_ratio > 0 ? 0 : loading.dt;
  opt.mass_scaling_ratio = loading.added_mass_ratio;
  opt.threads = loading.threads;
  opt.damping_gamma = loading.damping_gamma;
  solver_type s(scene.prism.tess, scene.prism.mesh, scene.prism.block_material, law_params, scene.bar, opt);
  if (!scene.options.bare) {
    const auto& ms = s.mass_scaling();
    require_quasi_static("rc_tie", loading.rate, scene.hand.length, concrete_young, concrete_density,
                         ms.original_mass > 0 ? ms.added_mass / ms.original_mass : 0, law_params.tension.f_T);
  }

  const real length = scene.hand.length, tol = 1e-9 * length;
  if (scene.options.bare) {
    s.fix(bc::all_nodes(s.gridpoints()));
  } else {
    s.fix(s.gridpoints_on_plane(2, scene.prism.box.lo.z(), tol), bc::transverse_to(2));
    s.fix(s.gridpoints_on_plane(2, scene.prism.box.hi.z(), tol), bc::transverse_to(2));
  }
  node_set& bar = s.bar_nodes();
  const auto [first_node, end_node] = s.reinforcement().bar_nodes(0);
  const index last_node = end_node - 1;
  const bc::node_group fixed_end{{first_node}, "fixed bar end"}, pulled_end{{last_node}, "pulled bar end"};
  bc::fix(bar, fixed_end);   // x, y held; z held, or set by the ramp below when symmetric
  bc::fix(bar, pulled_end);  // x, y held; z velocity set by the ramp below
  const real pulled_share = loading.symmetric ? 0.5 : 1.0;  // of the elongation rate
  const real ramp = loading.ramp_time;
  const auto pull_velocity = [&](real t) {
    if (t >= ramp) return loading.rate;
    return 0.5 * loading.rate * (1 - std::cos(std::numbers::pi * t / ramp));
  };

  tie_result r;
  const tie_bar& truss = s.reinforcement();
  const real drop_threshold = 0.05 * scene.hand.cracking_force;
  load_drop_detector detector(drop_threshold);
  std::size_t drops_reported = 0;
  std::size_t yield_sample = 0;
  cli::progress_line progress(loading.progress_label.empty() ? std::string("rc_tie") : loading.progress_label);
  const bool show = !loading.progress_label.empty();
  bool done = false;
  crack_graph graph(s.contacts(), scene.prism.tess.cell_count());
  if (!scene.options.bare) {
    std::vector<index> node_blocks;
    std::vector<real> node_z;
    for (index n = first_node; n < end_node; ++n) {
      if (!truss.bonded(n)) continue;
      node_blocks.push_back(scene.prism.mesh.zone_block[static_cast<std::size_t>(truss.host(n).zone)]);
      node_z.push_back(bar.reference(n, 2));
    }
    graph.set_bar_path(std::move(node_blocks), std::move(node_z));
  }
  real max_force = 0;
  int softened_count = 0;
  const real yield_flow = 0.02 * scene.hand.yield_force / scene.hand.bare_bar_stiffness;  // m
  // Bar elements whose midpoints lie in the middle two thirds of the tie (concrete_stress).
  index middle_first = truss.element_count(), middle_end = 0;
  for (index e = 0; e < truss.element_count(); ++e) {
    const real z = (static_cast<real>(e) + 0.5) * length / static_cast<real>(truss.element_count());
    if (z < length / 6 || z > 5 * length / 6) continue;
    middle_first = std::min(middle_first, e);
    middle_end = e + 1;
  }
  const auto sample = [&](const solver_type& sv) {
    const real u = bar.displacement(last_node, 2) - bar.displacement(first_node, 2);  // elongation
    const real f = -bar.reaction(first_node, 2);
    r.elongation.push_back(u);
    r.force.push_back(f);
    r.pulled_force.push_back(bar.reaction(last_node, 2));
    {
      real bar_sum = 0;
      for (index e = middle_first; e < middle_end; ++e) bar_sum += truss.axial_force(e);
      const index bar_count = std::max<index>(0, middle_end - middle_first);
      r.concrete_stress.push_back(bar_count > 0 ? (f - bar_sum / static_cast<real>(bar_count)) / scene.hand.concrete_area : 0);
      index softened = 0;
      for (index i = 0; i < sv.contacts().size(); ++i)
        if (crack_graph::past_peak(sv.contacts().state(i).flags)) ++softened;
      r.softened_subcontacts.push_back(softened);
      if (r.first_softening_force == 0 && softened > 0 && f >= 0.1 * scene.hand.cracking_force)
        r.first_softening_force = f;
    }
    r.max_imbalance = std::max(r.max_imbalance, std::abs(r.pulled_force.back() - f) / scene.hand.yield_force);
    max_force = std::max(max_force, f);
    if (!r.yielded && r.elongation.size() % 4 == 0) {
      const int c = graph.softened(sv.contacts(), sv.gridpoints()).cracks;
      if (c > softened_count) {
        softened_count = c;
        r.crack_formation.emplace_back(u, max_force);
      }
    }
    if (!r.yielded) {
      // Yield of the tie: the bar flows plastically, i.e. its total plastic elongation has reached
      // yield_flow (2 % of the bare bar's yield elongation), with the force at the fixed end at
      // 90 % of f_y A or more. An element touching f_y A is not enough: the force jump a crack
      // throws onto the bar overshoots dynamically and can yield one element for a moment at
      // 0.9 f_y A (measured: 18.2 kN at dt = 1 us), long before the tie's plateau.
      real plastic = 0;
      if (f >= 0.9 * scene.hand.yield_force)
        for (index e = 0; e < truss.element_count(); ++e) plastic += std::max(real(0), truss.plastic_elongation(e));
      if (plastic >= yield_flow) {
        r.yielded = true;
        r.yield_elongation = u;
        yield_sample = r.elongation.size() - 1;
      }
      if (detector.push(u, f)) on_event(sv, "drop" + std::to_string(++drops_reported));
      if (r.yielded) on_event(sv, std::string("yield"));
    }
    done = u >= loading.max_elongation || (r.yielded && u >= (1 + loading.post_yield) * r.yield_elongation);
    if (show) {
      const real target = r.yielded ? std::min(loading.max_elongation, (1 + loading.post_yield) * r.yield_elongation)
                                    : loading.max_elongation;
      progress.update(std::min(1.0, u / target),
                      detail::concat("u = ", u * 1e3, " mm, F = ", f * 1e-3, " kN, drops ", drops_reported,
                                     r.yielded ? ", yielded" : ""));
    }
  };
  s.run_until([&](const solver_type&) { return done; }, std::int64_t{1} << 40,
              [&](const solver_type& sv) {
                if (sv.time() <= ramp + sv.dt()) {
                  const real v = pull_velocity(sv.time() + 0.5 * sv.dt());
                  bar.prescribed_velocity(last_node, 2) = pulled_share * v;
                  if (loading.symmetric) bar.prescribed_velocity(first_node, 2) = -(1 - pulled_share) * v;
                }
              },
              recorders::every(loading.sample, sample));
  progress.finish();
  on_event(std::as_const(s), std::string("end"));

  const std::size_t pre_yield = r.yielded ? yield_sample : r.force.size();
  r.drops = find_load_drops(r.elongation, r.force, drop_threshold, pre_yield);
  std::size_t first_peak = 0;
  if (!r.drops.empty()) first_peak = r.drops.front().sample;
  else
    for (std::size_t k = 0; k < pre_yield; ++k)
      if (r.force[k] > r.force[first_peak]) first_peak = k;
  r.first_crack_force = r.force.empty() ? 0 : r.force[first_peak];
  std::size_t first_crack_sample = first_peak;
  for (const auto& [u, f] : r.crack_formation)
    if (f >= 0.5 * scene.hand.cracking_force) {  // ignore start-up transients at the pulled end
      r.first_crack_force = f;
      for (std::size_t k = 0; k < r.force.size() && r.elongation[k] <= u; ++k)
        if (r.force[k] == f) first_crack_sample = k;
      break;
    }
  if (first_crack_sample < r.force.size()) {
    r.concrete_stress_at_first_crack = r.concrete_stress[first_crack_sample];
    r.softened_at_first_crack = r.softened_subcontacts[first_crack_sample];
  }
  for (const load_drop& d : r.drops)
    if (d.peak_force >= 0.5 * scene.hand.cracking_force) {
      r.first_drop_force = d.peak_force;
      break;
    }
  r.initial_stiffness = initial_stiffness(r.elongation, r.force, first_peak);
  if (r.yielded) {
    // Plateau: mean over the second half of the post-yield samples (the bar at f_y A in the crack).
    const std::size_t from = yield_sample + (r.force.size() - yield_sample) / 2;
    double sum = 0;
    for (std::size_t k = from; k < r.force.size(); ++k) sum += r.force[k];
    r.yield_force = r.force.size() > from ? sum / static_cast<double>(r.force.size() - from) : r.force.back();
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
  r.added_mass_ratio = s.mass_scaling().original_mass > 0 ? s.mass_scaling().added_mass / s.mass_scaling().original_mass : 0;
  r.steps = s.step_count();
  r.phases = s.phases();
  r.subcontacts = s.contacts().size();
  r.zones = scene.prism.mesh.zone_count();
  r.gridpoints = scene.prism.mesh.gridpoint_count();
  r.runtime_s = timer.seconds();
  return r;
}

/// run_tie with the block model of scene.options.rigid and the softening law named in
/// loading.softening ("power" or "linear").
template <class OnEvent>
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
    return run_tie<deformable_blocks, law::coupled_tie_law>(scene, law::with_coupled_cohesion(contact),
                                                           loading, on_event);
  }
  const auto linear = tessera::law::with_linear_softening(contact);
  if (scene.options.rigid)
    return power ? run_tie<blocks::rigid, law::study_tie_law>(scene, contact, loading, on_event)
                 : run_tie<blocks::rigid, law::linear_tie_law>(scene, linear, loading, on_event);
  return power ? run_tie<deformable_blocks, law::study_tie_law>(scene, contact, loading, on_event)
               : run_tie<deformable_blocks, law::linear_tie_law>(scene, linear, loading, on_event);
}

/// run_tie without event callbacks.
[[nodiscard]] inline tie_result run_tie(const tie_scene& scene, const tie_loading& loading) {
  return run_tie(scene, loading, [](const auto&, const std::string&) {});
}

}  // namespace tessera::scenes
