#pragma once
// presets/pulatsu2020.hpp: the reference study's data (Pulatsu et al., "Numerical modeling of the
// tension stiffening in reinforced concrete members via discontinuum models", Comp. Part. Mech.
// 2020; DESIGN.md §6): its named contact laws, Table 1 (prism and tie contacts; scaled_prism_params
// carries it to other block counts), the tie's
// steel and bond (Sec. 3.1), the beam's contacts (Sec. 4, Table 3), the regularisation the
// examples offer, and named solvers composed from them. Generic rooms (core, geometry, blocks,
// contact, law, reinforcement, integrator, solver, io, analysis) never include this header.
//
// | alias          | tension          | compression         | shear            | study use                    |
// |----------------|------------------|---------------------|------------------|------------------------------|
// | study_tie_law  | power_softening  | elastic_compression | coulomb_residual | plain prism, RC tie (Sec. 3) |
// | linear_tie_law | linear_softening | elastic_compression | coulomb_residual | tie, LS vs PS (Sec. 3.2)     |
// | study_beam_law | linear_softening | plastic_cap         | coulomb_residual | RC beam (Sec. 4)             |
// | coupled_tie_law| power_softening  | elastic_compression | coulomb_coupled  | opt-in: cohesion softens with |
// |                |                  |                     |                  | f_t (docs/model.md)           |
// | coupled_beam_law| linear_softening| plastic_cap         | coulomb_coupled  | opt-in: the beam, cohesion    |
// |                |                  |                     |                  | softening with f_t (rc_beam)  |
// | slip_softening_beam_law | linear_softening | plastic_cap | coulomb_slip_softening | not the study's: cohesion |
// |                |                  |                     |                  | and friction soften with slip |
// |                |                  |                     |                  | (G_II; issue #63, compression)|
// | crushing_beam_law | linear_softening | softening_cap    | coulomb_slip_softening | not the study's: slip     |
// |                |                  |                     |                  | softening and a cap softening |
// |                |                  |                     |                  | with crushing (G_c; issue #63)|
//
// The names live in tessera::presets; the end of this file also makes them reachable under the
// names the examples and tests have always used (tessera::law::study_tie_law,
// tessera::prism_solver, tessera::reinforcement::pulatsu2020::tie_steel, ...).

#include <cmath>

#include "../blocks/deformable.hpp"
#include "../blocks/linear_elastic_tet.hpp"
#include "../blocks/rigid.hpp"
#include "../contact/face_contacts.hpp"
#include "../core/errors.hpp"
#include "../law/cohesive_frictional.hpp"
#include "../law/compression.hpp"
#include "../law/shear.hpp"
#include "../law/slip_softening.hpp"
#include "../law/tension.hpp"
#include "../law/with_elastic_packs.hpp"
#include "../reinforcement/embedded_truss.hpp"
#include "../solver/solver.hpp"

namespace tessera::presets {

using study_tie_law = law::cohesive_frictional<law::power_softening, law::elastic_compression, law::coulomb_residual>;
using linear_tie_law = law::cohesive_frictional<law::linear_softening, law::elastic_compression, law::coulomb_residual>;
using study_beam_law = law::cohesive_frictional<law::linear_softening, law::plastic_cap, law::coulomb_residual>;
using coupled_tie_law = law::cohesive_frictional<law::power_softening, law::elastic_compression, law::coulomb_coupled>;
using coupled_beam_law = law::cohesive_frictional<law::linear_softening, law::plastic_cap, law::coulomb_coupled>;
using slip_softening_beam_law =
    law::cohesive_frictional<law::linear_softening, law::plastic_cap, law::coulomb_slip_softening>;

static_assert(law::ContactLaw<study_tie_law>);
static_assert(law::ContactLaw<linear_tie_law>);
static_assert(law::ContactLaw<study_beam_law>);
static_assert(law::ContactLaw<coupled_tie_law>);
static_assert(law::ContactLaw<coupled_beam_law>);
static_assert(law::ContactLaw<slip_softening_beam_law> && slip_softening_beam_law::softens_with_slip);
using crushing_beam_law =
    law::cohesive_frictional<law::linear_softening, law::softening_cap, law::coulomb_slip_softening>;
static_assert(law::ContactLaw<crushing_beam_law> && crushing_beam_law::softens_with_crushing);

/// Contact parameters of the study's plain concrete prism (Table 1, DESIGN.md §4) for a
/// tessellation of `blocks` blocks (100, 250, 500 or 750): k_n = 1160/1570/1980/2260 GPa/m,
/// k_s = 482/654/824/943 GPa/m, f_T = 2.15 MPa, G_f = 60 N/m, power softening alpha = 3
/// (residual_ratio 1e-3), c_0 = 2 f_T, c_res = 0.01 c_0, phi_0 = 35 deg, phi_res = 30 deg, no
/// compression limit (with_linear_softening gives the Sec. 3.2 linear-softening variant).
/// Throws invalid_input for any other block count.
[[nodiscard]] inline study_tie_law::params study_prism_params(int blocks) {
  struct table_row {
    int blocks;
    real k_n;  // Pa/m
    real k_s;  // Pa/m
  };
  constexpr table_row table1[] = {
      {100, 1160e9, 482e9}, {250, 1570e9, 654e9}, {500, 1980e9, 824e9}, {750, 2260e9, 943e9}};
  for (const table_row& row : table1) {
    if (row.blocks != blocks) continue;
    study_tie_law::params p;
    p.k_n = row.k_n;
    p.k_s = row.k_s;
    p.tension.f_T = 2.15e6;
    p.tension.G_f = 60;
    p.tension.alpha = 3;
    p.tension.residual_ratio = 1e-3;
    p.shear.c_0 = 2 * p.tension.f_T;
    p.shear.c_res = 0.01 * p.shear.c_0;
    p.shear.phi_0 = law::friction_angle::from_degrees(35);
    p.shear.phi_res = law::friction_angle::from_degrees(30);
    return p;
  }
  throw invalid_input(tessera::detail::concat("study_prism_params: blocks = ", blocks,
                                              " is not a block count of the study's Table 1 (100, 250, 500, 750)"));
}

/// Table 1's stiffnesses carried to any block count: the row itself for 100, 250, 500 and 750
/// blocks, else the 100-block row times (blocks / 100)^(1/3). The study's rows follow that law to
/// within 1 % (k_n and k_s inversely proportional to the mean cell size, i.e. one macroscopic
/// modulus whatever the block size), so this is the stiffness the study would have chosen; it is
/// not a value the study gives. Everything else as study_prism_params. Throws invalid_input for
/// blocks < 2. in_table1(n): whether n is one of Table 1's block counts.
[[nodiscard]] constexpr bool in_table1(int blocks) noexcept {
  return blocks == 100 || blocks == 250 || blocks == 500 || blocks == 750;
}
[[nodiscard]] inline study_tie_law::params scaled_prism_params(int blocks) {
  require<invalid_input>(blocks >= 2, "scaled_prism_params: blocks = ", blocks, " must be >= 2");
  if (in_table1(blocks)) return study_prism_params(blocks);
  study_tie_law::params p = study_prism_params(100);
  const real scale = std::cbrt(static_cast<real>(blocks) / 100);
  p.k_n *= scale;
  p.k_s *= scale;
  return p;
}

/// The same contact with linear instead of power softening (study Sec. 3.2, Fig. 10): identical
/// stiffnesses, f_T, G_f and shear parameters, so both dissipate the same fracture energy.
[[nodiscard]] inline linear_tie_law::params with_linear_softening(const study_tie_law::params& power) {
  linear_tie_law::params p;
  p.k_n = power.k_n;
  p.k_s = power.k_s;
  p.tension.f_T = power.tension.f_T;
  p.tension.G_f = power.tension.G_f;
  p.compression = power.compression;
  p.shear = power.shear;
  return p;
}

namespace detail {
/// The params of law Coupled with the stiffnesses, tension, compression and shear parameters of
/// `decoupled` (the two laws differ in their shear policy only).
template <class Coupled, class DecoupledParams>
[[nodiscard]] typename Coupled::params copy_to_coupled(const DecoupledParams& decoupled) {
  typename Coupled::params p;
  p.k_n = decoupled.k_n;
  p.k_s = decoupled.k_s;
  p.tension = decoupled.tension;
  p.compression = decoupled.compression;
  p.shear = decoupled.shear;
  return p;
}
}  // namespace detail

/// The same contact with its cohesion softening together with the tensile strength
/// (coulomb_coupled): identical stiffnesses, tension, compression and shear parameters.
[[nodiscard]] inline coupled_tie_law::params with_coupled_cohesion(const study_tie_law::params& decoupled) {
  return detail::copy_to_coupled<coupled_tie_law>(decoupled);
}

/// The beam's contact with its cohesion softening together with the tensile strength
/// (coulomb_coupled): identical stiffnesses, tension, compressive cap and shear parameters.
[[nodiscard]] inline coupled_beam_law::params with_coupled_cohesion(const study_beam_law::params& decoupled) {
  return detail::copy_to_coupled<coupled_beam_law>(decoupled);
}

/// Contact parameters of the study's RC beam in four-point bending (Sec. 4, Table 3) for 250 or
/// 500 blocks: k_n = 500 / 625 GPa/m, f_T = 2.5 MPa, c_0 = 2 f_T, phi = 35 deg, f_c = 35 MPa,
/// G_f = 60 N/m, linear softening. The study gives no shear stiffness for the beam; k_s = k_n G/E =
/// k_n / (2 (1 + nu)) with nu = 0.2, the ratio Table 1 uses for the prism (k_s/k_n = 0.416). The
/// residual values follow the prism (c_res = 0.01 c_0, phi_res = 30 deg). Throws invalid_input
/// for any other block count.
[[nodiscard]] inline study_beam_law::params study_beam_params(int blocks) {
  require<invalid_input>(blocks == 250 || blocks == 500, "study_beam_params: blocks = ", blocks,
                         " is not a block count of the study's beam (250, 500)");
  study_beam_law::params p;
  p.k_n = blocks == 250 ? 500e9 : 625e9;
  p.k_s = p.k_n / (2 * 1.2);
  p.tension.f_T = 2.5e6;
  p.tension.G_f = 60;
  p.compression.f_c = 35e6;
  p.shear.c_0 = 2 * p.tension.f_T;
  p.shear.c_res = 0.01 * p.shear.c_0;
  p.shear.phi_0 = law::friction_angle::from_degrees(35);
  p.shear.phi_res = law::friction_angle::from_degrees(30);
  return p;
}

/// The beam's contact with cohesion and friction softening with the plastic slip
/// (coulomb_slip_softening, slip_softening.hpp; not the study's law): the stiffnesses, tension and
/// compressive cap of `beam`, its c_0, c_res, phi_0 and phi_res, and the mode-II fracture energy
/// G_II (J/m^2, the plastic work above c_res in pure shear at zero normal stress). The law's
/// validate refuses c_res >= c_0, phi_res > phi_0 and G_II <= (c_0 - c_res)^2/(2 k_s).
[[nodiscard]] inline slip_softening_beam_law::params with_slip_softening(const study_beam_law::params& beam, real G_II) {
  slip_softening_beam_law::params p;
  p.k_n = beam.k_n;
  p.k_s = beam.k_s;
  p.tension = beam.tension;
  p.compression = beam.compression;
  p.shear = {beam.shear.c_0, beam.shear.phi_0, beam.shear.c_res, beam.shear.phi_res, G_II};
  return p;
}

/// The slip-softening contact `slip` with its cap f_c softening with the plastic closure
/// (softening_cap, compression.hpp; not the study's law): linearly to residual x f_c (residual in
/// [0, 1]) over the compressive fracture energy G_c (J/m^2, the plastic work above the residual cap);
/// scales_shear also scales the shear limit by the cap's remaining fraction. Everything else is
/// `slip`'s. The law's validate refuses G_c <= ((1 - residual) f_c)^2 / (2 k_n).
[[nodiscard]] inline crushing_beam_law::params with_softening_cap(const slip_softening_beam_law::params& slip, real G_c,
                                                                  real residual, bool scales_shear = false) {
  crushing_beam_law::params p;
  p.k_n = slip.k_n;
  p.k_s = slip.k_s;
  p.tension = slip.tension;
  p.compression = {slip.compression.f_c, G_c, residual, scales_shear};
  p.shear = slip.shear;
  return p;
}

// ---- the RC tie's bar (Sec. 3.1) ----
/// E_s = 192.3 GPa, f_y = 400 MPa, d = 8 mm: A = 50.27 mm^2, yield force f_y A = 20.1 kN,
/// E_s A = 9.666 MN. With 96 elements over the 0.6 m prism, L_el = 6.25 mm and
/// K_axial = E_s A / L_el = 1.547 GN/m, the study's "1.55 GN/m"; bare bar E_s A / L = 16.1 kN/mm.
[[nodiscard]] inline reinforcement::steel tie_steel() { return reinforcement::steel{192.3e9, 400e6, 7850.0, 0.008}; }
/// xi = 4, c_bond = 1e9 N/m ("perfect bond"), bond stiffness per unit bar length: xi K_axial =
/// 6.19e9 N/m per m of bar, 3DEC's cable grout stiffness (bond.hpp gives the evidence; pass
/// stiffness_basis::per_node for DESIGN.md's reading, 6.19 GN/m per interior node). The study gives
/// no bond friction angle; with c_bond = 1e9 N/m it cannot matter, so phi_bond = 0.
[[nodiscard]] inline reinforcement::coulomb_bond::params tie_bond(
    reinforcement::stiffness_basis basis = reinforcement::stiffness_basis::per_unit_length) {
  return reinforcement::coulomb_bond::params{4.0, 1e9, 0.0, basis};
}
/// The tie's bar from `start` to `end` (the prism axis) with `elements` truss elements (96).
[[nodiscard]] inline reinforcement::embedded_truss<reinforcement::coulomb_bond>::params tie_reinforcement(const vec3& start, const vec3& end,
                                                                            index_t elements = 96) {
  return {tie_steel(), tie_bond(), {reinforcement::bar{start, end, elements, true}}};
}

// ---- tessellation ----
/// Relative short-edge threshold of the examples: edges shorter than 0.2 of the mean cell size L
/// are collapsed. Measured on the study's prism (100, 250, 500 blocks, seeds 1-3, min-angle
/// zoning): the unscaled stable step of the deformable prism rises from 1e-10..8e-9 s to
/// 1.5e-8..8e-8 s (every case), the zones with volume ratio < 0.1 fall from 17-22 % to 1.4-2.6 %,
/// at the price of 20-30 % fewer sub-contacts, faces warped by up to 0.1 L and merged vertices
/// moved by up to 0.6 L (clusters; the max_shift_rel cap). 0.1 L leaves 4e-9 s (500 blocks, seed 2);
/// below 0.2 a few refused collapses keep slivers.
inline constexpr real study_regularization = 0.2;

// ---- named solvers: the face-pair contact set with the law's pack path (law::with_elastic_packs:
// the same bits as the plain law without FMA contraction; faster on the cracking tie and on the
// elastic prism, docs/performance.md) ----
template <class Law>
using bonded_faces = contact::face_contacts<law::with_elastic_packs<Law>>;
/// The study's plain-concrete prism / tie concrete: deformable semi-rigid blocks, power softening.
using prism_solver = solver<blocks::deformable<zones::linear_elastic_tet>, bonded_faces<study_tie_law>>;
/// Linear-softening variant (sensitivity study, Sec. 3.2).
using prism_linear_solver = solver<blocks::deformable<zones::linear_elastic_tet>, bonded_faces<linear_tie_law>>;
/// The prism with rigid 6-DOF blocks (blocks::rigid, density only) and the study's tie law.
using rigid_prism_solver = solver<blocks::rigid, bonded_faces<study_tie_law>>;
/// Opt-in variants whose cohesion softens with the tensile strength (coupled_tie_law).
using coupled_prism_solver = solver<blocks::deformable<zones::linear_elastic_tet>, bonded_faces<coupled_tie_law>>;
using coupled_rigid_prism_solver = solver<blocks::rigid, bonded_faces<coupled_tie_law>>;

}  // namespace tessera::presets

// ---- the names examples and tests have always used ----
namespace tessera::law {
using presets::coupled_beam_law;
using presets::coupled_tie_law;
using presets::crushing_beam_law;
using presets::in_table1;
using presets::linear_tie_law;
using presets::scaled_prism_params;
using presets::slip_softening_beam_law;
using presets::study_beam_law;
using presets::study_beam_params;
using presets::study_prism_params;
using presets::study_tie_law;
using presets::with_coupled_cohesion;
using presets::with_linear_softening;
using presets::with_softening_cap;
using presets::with_slip_softening;
}  // namespace tessera::law
namespace tessera::reinforcement::pulatsu2020 {
using presets::tie_bond;
using presets::tie_reinforcement;
using presets::tie_steel;
}  // namespace tessera::reinforcement::pulatsu2020
namespace tessera::geometry {
using presets::study_regularization;
}  // namespace tessera::geometry
namespace tessera {
using presets::coupled_prism_solver;
using presets::coupled_rigid_prism_solver;
using presets::prism_linear_solver;
using presets::prism_solver;
using presets::rigid_prism_solver;
}  // namespace tessera
