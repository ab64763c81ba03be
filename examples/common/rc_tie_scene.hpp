#pragma once
// The reference study's reinforced-concrete tie (Pulatsu et al. 2020, Sec. 3.1; DESIGN.md §4),
// built on the plain prism of scenes.hpp: its options, the hand checks, the loading and what one
// run measures (tie_result). One run is in rc_tie_run.hpp; the curve and crack analyses it uses
// are the library's (tessera/analysis/). Used by examples/rc_tie, examples/rc_tie_sensitivity
// and benchmarks/work_precision_tie.
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
#include "tessera/analysis.hpp"
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
/// faster on the tie), the embedded bar. Checker: the step checker (checks::no_step_checker for a
/// kinetic relaxation, whose resets and ramps move the model outside the energy books).
template <class Blocks, class Law, class Checker = checks::default_step_checker>
using tie_solver = solver<Blocks, presets::bonded_faces<Law>, tie_bar,
                          integrator::central_difference<integrator::local_damping>, Checker>;
using deformable_blocks = blocks::deformable<zones::linear_elastic_tet>;

struct tie_options {
  /// 100, 250, 500 or 750 take Table 1's contact stiffnesses; any other count from 20 to
  /// max_tie_blocks takes them scaled as blocks^(1/3) (law::scaled_prism_params)
  int blocks = 100;
  std::uint64_t seed = 1;    ///< tessellation seed
  index_t elements = 96;       ///< truss elements along the bar
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
  /// Calibrated contact strength and fracture-energy scales (prism_options; 1 = the study verbatim).
  real strength_scale = 1;
  real fracture_energy_scale = 1;
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

/// The largest tie make_tie builds, and its memory: about tie_bytes_per_block per block all-in
/// (zones, gridpoints, sub-contacts, the tessellation; measured on the 10 000-block tie,
/// docs/performance.md), so max_tie_blocks needs about 9 GB of this machine's 24 GiB.
inline constexpr int max_tie_blocks = 200000;
inline constexpr double tie_bytes_per_block = 45e3;

/// Builds the tie: the prism of scenes.hpp (Voronoi, zoning, Table 1 contacts) and the bar on its
/// axis with the study's steel and bond. Throws invalid_input naming a bad option.
[[nodiscard]] inline tie_scene make_tie(const tie_options& o) {
  require(o.blocks >= 20, "rc_tie: blocks = ", o.blocks, " must be >= 20");
  require(o.blocks <= max_tie_blocks, "rc_tie: blocks = ", o.blocks, " would need about ",
          o.blocks * tie_bytes_per_block / 1e9, " GB (", tie_bytes_per_block / 1e3, " kB per block); the limit is ",
          max_tie_blocks, " blocks");
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
  po.strength_scale = o.strength_scale;
  po.fracture_energy_scale = o.fracture_energy_scale;
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
  h.cracking_force = t.prism.f_T * (h.concrete_area + h.modular_ratio * h.steel_area);
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

/// The 100-block tie's mass-scaling target step (s): 1 us at 5 mm/s (5 nm of elongation a step)
/// keeps every figure of the 100-block tie that five seeds resolve within 2 % of the converged
/// setting (1 us at 2.5 mm/s); 2 us, the default before, put the first drop +5.0 % over it
/// (docs/validation.md "Error against run time").
inline constexpr real default_tie_dt = 1e-6;

/// Loading and run control of one tie run.
struct tie_loading {
  real rate = 5e-3;             ///< elongation rate of the bar (m/s)
  /// Out-of-balance rate control (tessera/solver/balance.hpp) on the ratio of the largest nodal
  /// unbalanced force to N_cr, sampled every `sample` steps after the ramp: min_factor x rate as
  /// soon as it exceeds `high`, growing by `growth` a sample up to max_factor x rate while it is
  /// under `low`. min = max = 1: the fixed rate.
  adaptive_rate::params rate_control{.min_factor = 1, .max_factor = 1, .low = 0.0015, .high = 0.002, .growth = 1.02};
  /// true: the bar ends move at -rate/2 and +rate/2 (the study's setup up to a rigid translation);
  /// false: first bar node fixed, last pulled at rate (the study's setup verbatim). Local damping
  /// (F_d = gamma |F| sgn(v)) is not Galilean invariant: with one end fixed the concrete, free
  /// along z on its rollers, drifts at about rate/2 and the damping drags it, so the forces at the
  /// two bar ends differ (measured: up to 20 % of f_y A at gamma = 0.8). Pulling both ends keeps
  /// the concrete's mean velocity at zero; the elongation is the same.
  bool symmetric = true;
  real ramp_time = 2e-3;        ///< half-cosine velocity ramp from 0 to rate (s)
  real dt = default_tie_dt;     ///< mass-scaling target step (s); 0 = unscaled stable step
  /// > 0: instead of `dt`, the step at which mass scaling adds this multiple of the original mass
  /// (solver_options::mass_scaling_ratio; deformable blocks)
  real added_mass_ratio = 0;
  real max_elongation = 2e-3;   ///< stop here at the latest (m)
  real post_yield = 0.25;       ///< after the tie yields at elongation u_y (see yield_elongation), stop at (1 + this) u_y
  index_t sample = 25;            ///< steps between curve samples
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
  /// Kinetic dynamic relaxation (solver/relaxation.hpp) instead of the explicit pull: the bar ends
  /// moved apart by relax_increment (m of elongation) over relax_ramp steps, each increment held
  /// until the largest nodal unbalanced force is at most relax_tolerance x N_cr (at most
  /// relax_max_steps steps), one sample per increment; rate, ramp_time, dt, added_mass_ratio,
  /// damping_gamma, sample and rate_control are not used. Deformable blocks, one process.
  bool relaxation = false;
  real relax_increment = 1e-5, relax_tolerance = 1e-3;
  std::int64_t relax_ramp = 10, relax_max_steps = 1'000'000;
};

/// Mass-scaled time step for a tie of `blocks` blocks that keeps the added mass near the
/// 100-block value. The stable step falls with the block size and the Table 1 contact stiffness:
/// at a fixed 2 us the masses are scaled 69x (100 blocks), 218x (250) and 403x (500), and the
/// 500-block response turns inertia-dominated (first crack +78 % against +16 % at 0.5 us). Added
/// mass grows as dt^2, and dt_100 x (100/blocks)^0.55 keeps it: 1, 0.60 and 0.41 us for the
/// default dt_100 = default_tie_dt.
[[nodiscard]] inline real scaled_tie_dt(int blocks, real dt_100 = default_tie_dt) {
  return dt_100 * std::pow(100.0 / static_cast<real>(blocks), 0.55);
}

struct tie_result {
  std::vector<real> elongation, force;  ///< the curve (m, N), one row per sample
  /// Tension at the pulled end (N): equals `force` in a quasi-static state (the concrete, free
  /// along z, carries no net force), so |pulled_force - force| measures the inertia and damping
  /// forces still in the model.
  std::vector<real> pulled_force;
  /// Mean axial stress of the concrete over the middle two thirds of the tie (Pa): (F - mean bar
  /// force there) / A_c, i.e. the concrete's share of the load where the bond has handed it over.
  std::vector<real> concrete_stress;
  std::vector<index_t> softened_subcontacts;  ///< sub-contacts past their tensile peak, per sample
  /// Out-of-balance ratio per sample: the largest nodal unbalanced force over N_cr (balance.hpp).
  std::vector<real> unbalanced_ratio;
  std::vector<real> rate_factor;  ///< factor on the rate from the sample on (tie_loading::rate_control)
  real max_unbalanced_ratio = 0;  ///< over the samples after the ramp
  real mean_rate_factor = 0;      ///< the factor on the rate averaged over the steps (1: the fixed rate)
  real max_imbalance = 0;               ///< max |pulled_force - force| / f_y A over the run
  std::vector<analysis::load_drop> drops;         ///< before the first yield
  analysis::crack_report cracks;                  ///< fully opened through-cracks at the end of the run
  analysis::crack_report cracks_normal_only;      ///< the same counted by the normal opening u_n alone
  analysis::crack_report softened_cracks;         ///< softened through-cracks at the end of the run
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
  index_t softened_at_first_crack = 0;        ///< softened_subcontacts at that sample
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
  index_t subcontacts = 0, zones = 0, gridpoints = 0;
  phase_times phases;  ///< time per phase of the step (solver::phases)
  std::string damping_in_force;  ///< the damping of the run (solver::damping_in_force())
  double runtime_s = 0;
  bool yielded = false;
  /// With tie_loading::relaxation: increments, those that hit relax_max_steps before the
  /// tolerance, kinetic-energy resets, and the kinetic energy they removed (J of pseudo-time).
  std::int64_t relax_increments = 0, relax_unconverged = 0, relax_resets = 0;
  real relax_kinetic_removed = 0;
};

}  // namespace tessera::scenes
