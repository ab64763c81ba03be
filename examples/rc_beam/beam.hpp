#pragma once
// The reference study's RC beam in four-point bending (Pulatsu et al. 2020, Sec. 4; DESIGN.md §6):
// the half-symmetric scene, its hand values, one run and the crack analysis of a beam. Used by
// examples/rc_beam.
//
//   geometry  half beam (--span half, the default), x along the span from the beam end (0) to the
//             symmetry face (L_h = overhang + shear span + half the constant-moment zone), y up
//             from the soffit, z across the width; --span full: the whole beam, x from 0 to 2 L_h,
//             both shear spans (beam_span.hpp). Default: Walraven's series-A1 beam as DESIGN.md decides it,
//             PROVISIONAL (the study's Figure 16 is not in its text): b = 200, h = 150,
//             d = 125 mm, support 100 mm from the end, shear span a = 375 mm, constant-moment zone
//             500 mm (L_h = 725 mm), 50 mm plates at support and load
//   blocks    --blocks random Voronoi blocks (250 / 500) in the half beam (2 x --blocks in the full
//             beam, so that the block size and the contacts are the half model's), their faces refined to a 30 mm target
//             edge so that faces carry gridpoints inside them (about 16 contact points over the
//             depth; the study: at least ten), semi-rigid: 10 E = 250 GPa, nu = 0.2, 2400 kg/m^3
//   contacts  study_beam_params: k_n 500 / 625 GPa/m, k_s = k_n / 2.4, f_T 2.5 MPa, c = 2 f_T,
//             phi 35 deg, G_f 60 N/m, linear softening, plastic cap f_c = 35 MPa (--compression
//             elastic: no cap); --law slip_softening (cohesion and friction soften with slip over
//             G_II), --phi-deg, --phi-res-deg, --cap: beam_law.hpp
//   bars      4 Ø8 (201 mm^2) at y = h - d, evenly across the width, from x = end cover to the
//             symmetry face; 210 GPa, 440 MPa; about four trusses per block along the bar; bond
//             xi = 4 per unit length, c_bond = 1e9 N/m
//   supports  half beam: symmetry face x = L_h: every gridpoint and the bars' last nodes held in x
//             (rollers); full beam: no symmetry condition, both supports roll, the beam held in x
//             at the one gridpoint nearest the centre of the mid-span section (beam_span.hpp);
//             plates (--plates contact, the default): two rigid steel plates, 50 x 200 x 20 mm
//             (--plate, --plate-thickness), each a contact::rigid_platen hinged at its axis (free
//             to turn about z and to roll in x, held in z) and touching the concrete through the
//             plate-concrete pair: the beam's k_n and k_s, friction at phi_0 = 35 deg, no
//             cohesion, never bonded, so a plate edge lifts off where the concrete pulls away.
//             The support plate's axis is held, the loading plate's driven down at --rate after a
//             half-cosine ramp. --plates tied: the gridpoints under each plate moved as one rigid
//             plate hinged at its axis (beam_plates.hpp hinged_plate), the support's held in z: what
//             the study did ("nodes are subjected to a fixed velocity boundary condition ... the
//             reaction forces are recorded from upper nodes", Sec. 4).
//   measured  total load P = 2 x the support reaction of the half beam, the sum of the two of the
//             full beam (both half-spans; beam_run.hpp says why not the plate force); mid-span
//             deflection = mean y displacement (down +) of the soffit gridpoints on the symmetry
//             face (half), at mid-span on a line fitted to the soffit near it (full, beam_span.hpp).
//
// Quasi-static check (beam_quasi_static_index): during one period T_1 of the beam's first
// bending mode with the mass-scaled masses, T_1 = 2 pi sqrt(M (1 + added) / (2 K_0)) (M the whole
// beam's mass, half of it modal, K_0 the hand stiffness), the plate travels v T_1; the elastic
// deflection at first cracking is P_cr / K_0. Refused above quasi_static_limit (2), as the ties.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/cli.hpp"
#include "common/phase_report.hpp"
#include "common/quasi_static.hpp"
#include "common/scenes.hpp"
#include "tessera/analysis.hpp"
#include "tessera/blocks/linear_elastic_tet.hpp"
#include "tessera/core/errors.hpp"
#include "tessera/geometry/voronoi.hpp"
#include "tessera/geometry/zoning.hpp"
#include "tessera/presets.hpp"
#include "tessera/reinforcement/embedded_truss.hpp"
#include "tessera/solver.hpp"
#ifdef TESSERA_SEPARATE_COMPILATION  // linked with tessera::instances (examples/CMakeLists.txt)
#include "tessera/instances/beam.hpp"
#endif

namespace tessera::scenes {

using beam_bar = reinforcement::embedded_truss<reinforcement::coulomb_bond>;
/// The beam's solver; Checker = checks::no_step_checker for kinetic relaxation (its resets and
/// ramps move the model outside the energy books the default checker reads).
template <class Law, class Checker = checks::default_step_checker>
using beam_solver = solver<blocks::deformable<zones::linear_elastic_tet>, presets::bonded_faces<Law>, beam_bar,
                           integrator::central_difference<integrator::local_damping>, Checker>;
#ifdef TESSERA_SEPARATE_COMPILATION
// The study's law gives the solver tessera::instances compiles and the Python module binds
// (tessera.instances.beam_solver, examples/python/rc_beam.py): its steps are the library's.
static_assert(std::is_same_v<beam_solver<presets::study_beam_law>, instances::beam_solver>);
#endif

struct beam_options {
  int blocks = 250;              ///< 250 or 500 (study Table 3 stiffnesses)
  std::uint64_t seed = 1;
  real width = 0.2;              ///< b (m)
  real height = 0.15;            ///< h (m)
  real effective_depth = 0.125;  ///< d (m): bars at y = h - d
  real overhang = 0.1;           ///< beam end to support axis (m)
  real shear_span = 0.375;       ///< support axis to load axis, a (m)
  real moment_zone = 0.5;        ///< between the two load axes (m); the half model holds half of it
  real plate = 0.05;             ///< plate length along the span, support and load (m)
  /// "contact": steel plates of their own (contact::rigid_platen) touching the concrete through
  /// the plate-concrete pair (the beam's k_n, k_s, friction at phi_0, never bonded); "tied": the
  /// gridpoints under each plate moved as one hinged plate (beam_plates.hpp hinged_plate).
  std::string plates = "contact";
  real plate_thickness = 0.02;   ///< steel plate thickness (m): its mass and inertia ("contact")
  int bars = 4;                  ///< bars across the width
  real bar_diameter = 0.008;     ///< m
  real end_cover = 0.02;         ///< bars start this far from the beam end (m)
  real trusses_per_block = 4;    ///< truss elements per mean block size along the bar
  /// Zoning target edge (m): faces are refined until no edge is longer (the interior is not:
  /// zoning_options::refine_interior = false), and every face gridpoint is a contact point. 0 =
  /// h / 5 = 30 mm, which puts the median sub-contact spacing (the square root of its tributary
  /// area) at 9 mm, about 16 contact points over the depth (the study: at least ten).
  real zone_edge = 0;
  real regularize = 0;           ///< short-edge regularisation of the Voronoi cells (0 = plain)
  std::string compression = "plastic";  ///< "plastic" (cap at f_c, the study) or "elastic"
  /// "decoupled" (the study, DESIGN.md: cohesion c_0 until the contact breaks) or "coupled" (the
  /// cohesion softens with the tensile strength, law::coulomb_coupled; built with the plastic cap
  /// only: presets::coupled_beam_law)
  std::string cohesion = "decoupled";
  /// A shear failure also breaks the contact in tension (the law's slip_breaks_tension: 3DEC's
  /// brittle Coulomb joint; opt-in, the study keeps its tension)
  bool slip_breaks_tension = false;
  /// Yield stress of the bars (Pa): the study's 440 MPa; a large value (1e12) keeps them elastic,
  /// so that the beam can only fail in its concrete (issue #41 item 1)
  real steel_yield = 440e6;
  /// Calibration (examples/calibrate --material beam, rc_beam --params): the contacts' tensile
  /// strength and with it the cohesion (c_0 = 2 x the scaled f_T) are study_beam_params' times
  /// strength_scale, their G_f times fracture_energy_scale; 1 and 1 = the study verbatim. The
  /// hand values stay at the concrete's f_T.
  real strength_scale = 1;
  real fracture_energy_scale = 1;
  /// The contacts' law (rc_beam --law, beam_law.hpp): "study" (study_beam_law), "slip_softening"
  /// (slip_softening_beam_law: cohesion and friction soften with the plastic slip over g_ii) or
  /// "mixed_mode" (presets::mixed_mode_beam_law: one damage for tension and shear over G_f and g_ii)
  std::string law = "study";
  real g_ii = 0;          ///< G_II with law slip_softening or crushing (J/m^2; 0 = default_g_ii) or mixed_mode (0 = (c_0/f_T) G_f)
  /// law "crushing" (crushing_beam_law: slip_softening whose cap softens with crushing), or
  /// "mixed_mode" with g_c > 0 (mixed_crushing_beam_law; g_c 0: its plastic cap): the
  /// compressive fracture energy G_c (J/m^2; 0 = default_g_c), the residual cap over the cap, and
  /// whether the shear limit falls with the cap's remaining fraction
  real g_c = 0, cap_residual = 0.1;
  bool crush_shear = false;
  /// c_0 / f_T of the contacts (c_res = 0.01 c_0): the study's 2; a --params entry of the
  /// slip-softening law sets its own (concrete_set.hpp)
  real cohesion_ratio = 2;
  real phi_deg = 35;      ///< the contacts' friction angle phi_0 (deg; the study's 35)
  real phi_res_deg = 30;  ///< their residual friction angle phi_res (deg; the study's 30)
  /// Their compressive cap f_c (Pa; the study's 35 MPa). The hand values keep the concrete's 35 MPa.
  real cap = 35e6;
  /// "half" (the half beam with its symmetry face) or "full" (the whole beam, 2 x `blocks` blocks:
  /// `blocks` stays the count of one half, so block size, contacts and hand values are the half's)
  std::string span = "half";
  [[nodiscard]] bool full() const { return span == "full"; }
  /// Length of the modelled concrete along x (m): L_h, or 2 L_h for the full beam.
  [[nodiscard]] real model_length() const { return full() ? 2 * half_length() : half_length(); }
  [[nodiscard]] int model_blocks() const { return full() ? 2 * blocks : blocks; }
  /// The twin of x across mid-span (m): the right span's position of a left-span one.
  [[nodiscard]] real mirror(real x) const { return 2 * half_length() - x; }
  /// A left-span position x (m) on side k of the full beam: x itself for k = 0, mirrored for k = 1.
  [[nodiscard]] real on_side(int k, real x) const { return k == 0 ? x : mirror(x); }
  [[nodiscard]] real half_length() const { return overhang + shear_span + 0.5 * moment_zone; }
  /// The half beam's volume (m^3).
  [[nodiscard]] real half_volume() const { return half_length() * height * width; }
  [[nodiscard]] real support_x() const { return overhang; }
  [[nodiscard]] real load_x() const { return overhang + shear_span; }
  /// The zoning target edge in effect: zone_edge, or h / 5 when it is 0.
  [[nodiscard]] real face_zone_edge() const { return zone_edge > 0 ? zone_edge : height / 5; }
};

/// The shear span holding x (m): 0 the left one (from the support axis to `reach` m past the load
/// axis), 1 its twin in the full beam, -1 neither.
[[nodiscard]] inline int beam_shear_span_of(const beam_options& o, real x, real reach) {
  if (x > o.support_x() && x < o.load_x() + reach) return 0;
  if (o.full() && x > o.mirror(o.load_x()) - reach && x < o.mirror(o.support_x())) return 1;
  return -1;
}
/// Whether x (m) lies in the constant-moment zone: from the load axis to the symmetry face (half)
/// or to the other load axis (full).
[[nodiscard]] inline bool beam_in_moment_zone(const beam_options& o, real x) {
  return x >= o.load_x() && (!o.full() || x <= o.mirror(o.load_x()));
}

inline constexpr real beam_concrete_young = 25e9;  ///< E (study Sec. 4)
inline constexpr real beam_steel_young = 210e9;
inline constexpr real beam_steel_yield = 440e6;  ///< the study's f_y (beam_options::steel_yield's default)

/// Closed-form references of the default beam (elastic beam theory, total load P on two plates).
struct beam_hand_checks {
  real span = 0;                 ///< L, between the support axes (m)
  real steel_area = 0;           ///< A_s (m^2)
  real modular_ratio = 0;        ///< n = E_s / E_c
  real uncracked_inertia = 0;    ///< I of the transformed uncracked section (m^4)
  real uncracked_centroid = 0;   ///< its centroid below the top face (m)
  /// First cracking: M_cr = f_T I / (h - y_c), P_cr = 2 M_cr / a (N).
  real first_crack_load = 0;
  /// The same with the flexural tensile strength of a beam of depth h instead of f_T (fib Model
  /// Code 2010, eq. 5.1-8: f_ct,fl = f_T (1 + 0.06 h^0.7) / (0.06 h^0.7), h in mm; 1.50 f_T for
  /// h = 150 mm): a softening material cracks through its tension zone only after the extreme
  /// fibre has passed f_T, the more so the shallower the beam (N).
  real flexural_crack_load = 0;
  /// P / delta_mid of the uncracked beam, bending plus shear (kappa = 5/6, G = E / 2.4):
  /// delta = (P/2) a (3 L^2 - 4 a^2) / (24 E I) + (P/2) a / (kappa G b h) (N/m).
  real initial_stiffness = 0;
  real lever_arm = 0;            ///< z = d - x/3 of the cracked elastic section (m)
  real steel_yield = 0;          ///< f_y of the bars (Pa): beam_options::steel_yield
  real yield_load = 0;           ///< P_y = 2 A_s f_y z / a (N)
  /// Shear capacity without stirrups, P = 2 V_c with V_c = 0.15 k (100 rho f_c)^(1/3) b d
  /// (Eurocode 2's form, mean-value coefficient 0.15, k = min(2, 1 + sqrt(200 / d_mm))) (N).
  real shear_capacity_load = 0;
  /// The shear figure's hand values (issue #63; docs/studies/beam_failure_mode.md), P = 2 V_c (N):
  /// EC2 6.2.a without partial factor, V_c = 0.18 k (100 rho f_c)^(1/3) b d with k = min(2, 1 +
  /// sqrt(200 / d_mm)), f_c the contacts' cap as f_ck; and Zsutty's mean fit for a/d >= 2.5,
  /// v_c = 2.14 (f_c rho d / a)^(1/3) MPa. For the default beam 54.75 and 48.62 kN.
  real ec2_shear_load = 0;
  real zsutty_shear_load = 0;
  /// The reference of the shear figure: the mean of ec2_shear_load and zsutty_shear_load (N).
  [[nodiscard]] real shear_reference_load() const { return 0.5 * (ec2_shear_load + zsutty_shear_load); }
  real mean_block_size = 0;      ///< (V / N)^(1/3) (m)
};

struct beam_scene {
  aabb box;
  geometry::tessellation tess;
  geometry::block_mesh mesh;
  zones::linear_elastic_tet::params block_material;
  presets::study_beam_law::params contact;  ///< after calibration (beam_options::strength_scale)
  beam_bar::params bar;
  beam_hand_checks hand;
  beam_options options;
  index_t elements_per_bar = 0;
};

[[nodiscard]] inline beam_hand_checks beam_hand(const beam_options& o, const presets::study_beam_law::params& c) {
  beam_hand_checks h;
  const real b = o.width, hh = o.height, d = o.effective_depth, a = o.shear_span;
  h.span = 2 * (o.half_length() - o.overhang);
  h.steel_area = o.bars * std::numbers::pi * o.bar_diameter * o.bar_diameter / 4;
  h.modular_ratio = beam_steel_young / beam_concrete_young;
  const real n = h.modular_ratio, as = h.steel_area;
  const real area = b * hh + (n - 1) * as;
  const real yc = (b * hh * hh / 2 + (n - 1) * as * d) / area;
  h.uncracked_centroid = yc;
  h.uncracked_inertia = b * hh * hh * hh / 12 + b * hh * (hh / 2 - yc) * (hh / 2 - yc) + (n - 1) * as * (d - yc) * (d - yc);
  h.first_crack_load = 2 * c.tension.f_T * h.uncracked_inertia / (hh - yc) / a;
  const real depth_term = 0.06 * std::pow(hh * 1e3, 0.7);
  h.flexural_crack_load = h.first_crack_load * (1 + depth_term) / depth_term;
  const real L = h.span, E = beam_concrete_young, G = E / (2 * 1.2);
  const real compliance = 0.5 * a * (3 * L * L - 4 * a * a) / (24 * E * h.uncracked_inertia) + 0.5 * a / (5.0 / 6.0 * G * b * hh);
  h.initial_stiffness = 1 / compliance;
  const real rho = as / (b * d);
  const real x = d * (-n * rho + std::sqrt(n * rho * n * rho + 2 * n * rho));
  h.lever_arm = d - x / 3;
  h.steel_yield = o.steel_yield;
  h.yield_load = 2 * as * o.steel_yield * h.lever_arm / a;
  const real d_mm = d * 1e3, k = std::min(2.0, 1 + std::sqrt(200 / d_mm));
  const real vc_mpa = 0.15 * k * std::cbrt(100 * rho * c.compression.f_c * 1e-6);
  h.shear_capacity_load = 2 * vc_mpa * 1e6 * b * d;
  const real f_c_mpa = c.compression.f_c * 1e-6;
  h.ec2_shear_load = 2 * 0.18 * k * std::cbrt(100 * rho * f_c_mpa) * 1e6 * b * d;
  h.zsutty_shear_load = 2 * 2.14 * std::cbrt(f_c_mpa * rho * d / a) * 1e6 * b * d;
  h.mean_block_size = std::cbrt(o.half_volume() / o.blocks);
  return h;
}

/// Refuses a face zoning of `volume` (m^3) in `blocks` blocks that would exhaust memory. Zones grow
/// as the square of 1 / edge (surface refinement): measured 29 082 zones for 250 blocks at 30 mm,
/// 103 106 at 15 mm; about 1 kB per zone with its gridpoints and contacts.
inline void require_zone_budget(const beam_options& o, real volume, int blocks, const char* program) {
  const real edge = o.face_zone_edge();
  const real zones = 29082 * (0.03 / edge) * (0.03 / edge) * (volume / 0.02175) * std::cbrt(blocks / 250.0);
  require(zones <= 5e6, program, ": --zone-edge ", edge, " m would need about ", zones, " zones (~", zones * 1e-6,
          " GB); the limit is 5e6 zones: use a zone edge >= ", edge * std::sqrt(zones / 5e6), " m");
}


/// Refuses a strength or fracture-energy scale that is not finite and positive, naming `program`.
inline void require_calibration_scales(const beam_options& o, const char* program) {
  require(std::isfinite(o.strength_scale) && o.strength_scale > 0 && std::isfinite(o.fracture_energy_scale) &&
              o.fracture_energy_scale > 0,
          program, ": strength scale ", o.strength_scale, " and fracture-energy scale ", o.fracture_energy_scale,
          " must be finite and > 0");
}

/// Calibration scales on the beam's contacts: f_T x s, c_0 = 2 f_T (study_beam_params' ratio)
/// and c_res = 0.01 c_0 follow it, G_f x g.
inline void scale_beam_contacts(presets::study_beam_law::params& c, real s, real g) {
  const real ratio = c.shear.c_0 / c.tension.f_T, residual = c.shear.c_res / c.shear.c_0;
  c.tension.f_T *= s;
  c.tension.G_f *= g;
  c.shear.c_0 = ratio * c.tension.f_T;
  c.shear.c_res = residual * c.shear.c_0;
}

/// The plate-concrete pair's friction angle (deg): the study's phi_0, whatever --phi-deg the
/// concrete's own contacts take (steel on concrete is not the concrete's interface).
inline constexpr real beam_plate_friction_deg = 35;

/// Refuses (invalid_input naming the value) a contact law that rc_beam cannot run: phi_res above
/// phi_0, --g-ii without --law slip_softening, --cap with --compression elastic (no cap), and the
/// slip-softening law with --compression elastic, --cohesion coupled or --slip-breaks-tension
/// (no such variant is built); then the law's own check of the contacts `c` (G_II above the
/// elastic unloading's bound). --scheme relaxation: check_beam_relaxation; --params: check_beam_law_flags.
inline void check_beam_law(const beam_options& o, const presets::study_beam_law::params& c) {
  const concrete_law& law = concrete_law_named(o.law, "rc_beam: --law");
  require(o.phi_res_deg <= o.phi_deg, "rc_beam: --phi-res-deg ", o.phi_res_deg, " must not exceed --phi-deg ", o.phi_deg);
  require_g_ii_with_law("rc_beam", o.law, o.g_ii);
  require(o.compression == "plastic" || o.cap == 35e6, "rc_beam: --cap ", o.cap,
          " Pa applies to --compression plastic (--compression elastic has no cap)");
  const bool slip = o.law == "slip_softening" || o.law == "crushing", mixed = o.law == "mixed_mode";
  require(law.variants || (o.compression == "plastic" && o.cohesion == "decoupled" && !o.slip_breaks_tension),
          "rc_beam: --law ", o.law, " is built with --compression plastic, --cohesion decoupled and without "
          "--slip-breaks-tension (presets::", o.law, "_beam_law), got --compression ", o.compression, ", --cohesion ",
          o.cohesion, o.slip_breaks_tension ? ", --slip-breaks-tension" : "");
  if (o.law == "crushing")
    presets::crushing_beam_law::validate(presets::with_softening_cap(presets::with_slip_softening(c, g_ii_or_default(o.g_ii)),
                                                                     o.g_c > 0 ? o.g_c : default_g_c, o.cap_residual,
                                                                     o.crush_shear));
  else if (slip)
    presets::slip_softening_beam_law::validate(presets::with_slip_softening(c, g_ii_or_default(o.g_ii)));
  else if (mixed && o.g_c > 0)  // the mixed law whose cap softens with crushing
    presets::mixed_crushing_beam_law::validate(
        presets::with_softening_cap(presets::with_mixed_mode(c, o.g_ii), o.g_c, o.cap_residual, o.crush_shear));
  else if (mixed)
    presets::mixed_mode_beam_law::validate(presets::with_mixed_mode(c, o.g_ii));
  else
    presets::study_beam_law::validate(c);
}

/// The beam's concrete as a recipe (common/scenes.hpp concrete_recipe; examples/calibrate
/// --material beam fits it, rc_beam runs it): study_beam_params for o.blocks (250 below 500)
/// with o's calibration scales, the mean block volume of the half beam over o.blocks (87 cm^3, a
/// 44 mm block, for the default 250), the faces zoned to o.face_zone_edge() (h/5 = 30 mm) with the
/// interior left coarse, blocks of 10 x 25 GPa.
[[nodiscard]] inline concrete_recipe<presets::study_beam_law> beam_concrete(const beam_options& o = {}) {
  require_calibration_scales(o, "beam concrete");
  require(o.blocks >= 8, "beam concrete: blocks = ", o.blocks, " must be >= 8");
  concrete_recipe<presets::study_beam_law> r;
  r.material = "beam";
  r.contact = presets::study_beam_params(o.blocks >= 500 ? 500 : 250);
  r.f_T = r.contact.tension.f_T;
  scale_beam_contacts(r.contact, o.strength_scale, o.fracture_energy_scale);
  r.young = beam_concrete_young;
  r.cell_volume = o.half_volume() / o.blocks;
  r.zone_edge = o.face_zone_edge();
  r.refine_interior = false;
  r.block_material = {semi_rigid_factor * beam_concrete_young, 0.2, 2400};
  return r;
}

/// The beam's concrete in `box`: `blocks` Voronoi blocks (seed and regularisation of `o`), their
/// faces zoned to the beam's face edge with the interior left coarse, semi-rigid zones of 10 E
/// (beam_concrete's zoning and block material).
inline void beam_concrete_blocks(const aabb& box, int blocks, const beam_options& o, geometry::tessellation& tess,
                                 geometry::block_mesh& mesh, zones::linear_elastic_tet::params& material) {
  geometry::tessellation_options to;
  to.min_edge_rel = o.regularize;
  tess = geometry::random_voronoi(box, blocks, o.seed, to);
  const concrete_recipe<presets::study_beam_law> recipe = beam_concrete(o);
  mesh = geometry::zone_blocks(tess, recipe.zoning());
  material = recipe.block_material;
}

/// Builds the beam. Throws invalid_input naming a bad option.
[[nodiscard]] inline beam_scene make_beam(const beam_options& o) {
  require(o.blocks == 250 || o.blocks == 500 || o.blocks < 250,
          "rc_beam: blocks = ", o.blocks, " must be 250 or 500 (the study's Table 3), or fewer for a quick run");
  require(o.blocks >= 8, "rc_beam: blocks = ", o.blocks, " must be >= 8");
  for (const auto& [v, name] : {std::pair{o.width, "--width"}, {o.height, "--height"}, {o.effective_depth, "--depth"},
                                {o.overhang, "--overhang"}, {o.shear_span, "--shear-span"},
                                {o.moment_zone, "--moment-zone"}, {o.plate, "--plate"},
                                {o.bar_diameter, "--bar-diameter"}, {o.trusses_per_block, "--trusses-per-block"},
                                {o.plate_thickness, "--plate-thickness"}})
    require(std::isfinite(v) && v > 0, "rc_beam: ", name, " = ", v, " must be finite and > 0");
  require(o.effective_depth < o.height, "rc_beam: effective depth d = ", o.effective_depth, " m must be below h = ",
          o.height, " m");
  require(o.height - o.effective_depth > o.bar_diameter / 2, "rc_beam: the bars (d = ", o.effective_depth,
          " m, diameter ", o.bar_diameter, " m) stick out of the soffit");
  require(o.plate < 2 * o.overhang && o.plate < o.moment_zone, "rc_beam: plate length ", o.plate,
          " m must be below twice the overhang (", o.overhang, " m) and the constant-moment zone (", o.moment_zone,
          " m)");
  require(o.bars >= 1 && o.bars * o.bar_diameter < o.width, "rc_beam: ", o.bars, " bars of ", o.bar_diameter,
          " m do not fit in the width ", o.width, " m");
  require(std::isfinite(o.end_cover) && o.end_cover >= 0 && o.end_cover < o.support_x(), "rc_beam: --end-cover ",
          o.end_cover, " m must lie in [0, overhang = ", o.overhang, " m)");
  require(std::isfinite(o.zone_edge) && o.zone_edge >= 0, "rc_beam: --zone-edge ", o.zone_edge, " must be >= 0");
  require(std::isfinite(o.steel_yield) && o.steel_yield > 0, "rc_beam: --steel-yield ", o.steel_yield,
          " Pa must be finite and > 0");
  require(o.cohesion == "decoupled" || o.cohesion == "coupled", "rc_beam: --cohesion '", o.cohesion,
          "' must be decoupled or coupled");
  require(o.cohesion == "decoupled" || o.compression == "plastic",
          "rc_beam: --cohesion coupled is built with --compression plastic only (presets::coupled_beam_law), got "
          "--compression ", o.compression);
  require(o.compression == "plastic" || o.compression == "elastic", "rc_beam: --compression '", o.compression,
          "' must be plastic or elastic");
  require(o.plates == "contact" || o.plates == "tied", "rc_beam: --plates '", o.plates, "' must be contact or tied");
  require(o.span == "half" || o.span == "full", "rc_beam: --span '", o.span, "' must be half or full");
  require_zone_budget(o, o.full() ? 2 * o.half_volume() : o.half_volume(), o.model_blocks(), "rc_beam");
  beam_scene s;
  s.options = o;
  require_calibration_scales(o, "rc_beam");
  s.contact = presets::study_beam_params(o.blocks >= 500 ? 500 : 250);
  s.hand = beam_hand(o, s.contact);  // at the concrete's f_T, before the calibration scales
  scale_beam_contacts(s.contact, o.strength_scale, o.fracture_energy_scale);
  // o's shear and cap (the concrete set's setter; the defaults leave the study's contacts to the bit),
  // after the hand values: they keep the concrete's f_c = 35 MPa
  apply_concrete_shear(s.contact, o.cohesion_ratio, o.phi_deg, o.phi_res_deg, o.cap);
  check_beam_law(o, s.contact);
  s.box.lo = vec3::Zero();
  s.box.hi = vec3(o.model_length(), o.height, o.width);
  beam_concrete_blocks(s.box, o.model_blocks(), o, s.tess, s.mesh, s.block_material);
  s.bar.steel = reinforcement::steel{beam_steel_young, o.steel_yield, 7850.0, o.bar_diameter};
  s.bar.bond = presets::tie_bond();
  const real bar_end = o.full() ? o.mirror(o.end_cover) : o.half_length();  // the far cover or the symmetry face
  const real bar_length = bar_end - o.end_cover;
  s.elements_per_bar = std::max<index_t>(2, std::llround(o.trusses_per_block * bar_length / s.hand.mean_block_size));
  for (int i = 0; i < o.bars; ++i) {
    const real zc = o.width * (2 * i + 1) / (2.0 * o.bars);
    const real y = o.height - o.effective_depth;
    s.bar.bars.push_back(reinforcement::bar{vec3(o.end_cover, y, zc), vec3(bar_end, y, zc), s.elements_per_bar, true});
  }
  return s;
}

/// The prism examples/calibrate --material beam fits the beam's contacts on (DESIGN.md §5): the
/// beam's concrete (study_beam_params for options.blocks, semi-rigid zones of 10 E, the faces zoned
/// to the beam's face edge with the interior left coarse) in a square prism of the beam's depth h
/// on a side and 4 h long, pulled along its length like the study's prism. It holds as many
/// Voronoi blocks as give the beam's mean cell volume (half-beam volume / options.blocks): 155 for
/// the default 250-block beam, 310 for 500, so the blocks, their faces and the sub-contacts on
/// them have the beam's sizes (`blocks` > 0: that many instead, direct_tension --material beam
/// --blocks). The prism's own contacts field is not used: the law is `contact`.
struct beam_prism_scene {
  prism_scene prism;                        ///< geometry, zoning, block material, references f_T, G_f, E
  presets::study_beam_law::params contact;  ///< the beam's contacts, scaled
};

[[nodiscard]] inline beam_prism_scene make_beam_prism(const beam_options& o, int blocks = 0) {
  require(o.blocks >= 8 && o.blocks <= 500, "calibrate: beam blocks = ", o.blocks, " must lie in [8, 500]");
  require_calibration_scales(o, "calibrate");
  beam_prism_scene b;
  b.contact = presets::study_beam_params(o.blocks >= 500 ? 500 : 250);
  prism_scene& p = b.prism;
  p.f_T = b.contact.tension.f_T;
  p.G_f = b.contact.tension.G_f;
  p.young = beam_concrete_young;
  scale_beam_contacts(b.contact, o.strength_scale, o.fracture_energy_scale);
  const real h = o.height;
  p.box.lo = vec3::Zero();
  p.box.hi = vec3(h, h, 4 * h);
  const real cell_volume = o.half_volume() / o.blocks;
  const int prism_blocks =
      blocks > 0 ? blocks : static_cast<int>(std::max<long>(8, std::lround(p.box.volume() / cell_volume)));
  require_zone_budget(o, p.box.volume(), prism_blocks, "calibrate");
  beam_concrete_blocks(p.box, prism_blocks, o, p.tess, p.mesh, p.block_material);
  return b;
}

/// T_1 of the beam's first bending mode with masses scaled by (1 + added) (file comment).
[[nodiscard]] inline real beam_first_mode_period(const beam_scene& s, real added) {
  // the whole beam (the half model's twice), half of it modal
  const real mass = (s.options.full() ? 1 : 2) * s.box.volume() * s.block_material.density;
  return 2 * std::numbers::pi * std::sqrt(mass * (1 + added) / (2 * s.hand.initial_stiffness));
}

/// q of the beam (file comment).
[[nodiscard]] inline real beam_quasi_static_index(const beam_scene& s, real rate, real added) {
  return rate * beam_first_mode_period(s, added) / (s.hand.first_crack_load / s.hand.initial_stiffness);
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

}  // namespace tessera::scenes
