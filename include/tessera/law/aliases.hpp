#pragma once
// Named contact laws: the combinations the reference study uses, and only those (the full cross
// product of policies is never instantiated). Parameters are law::cohesive_frictional::params.
//
// | alias          | tension          | compression         | shear            | study use                    |
// |----------------|------------------|---------------------|------------------|------------------------------|
// | study_tie_law  | power_softening  | elastic_compression | coulomb_residual | plain prism, RC tie (Sec. 3) |
// | linear_tie_law | linear_softening | elastic_compression | coulomb_residual | tie, LS vs PS (Sec. 3.2)     |
// | study_beam_law | linear_softening | plastic_cap         | coulomb_residual | RC beam (Sec. 4)             |
// | coupled_tie_law| power_softening  | elastic_compression | coulomb_coupled  | opt-in: cohesion softens with |
// |                |                  |                     |                  | f_t (docs/model.md)           |
// with_elastic_packs<L>: L with the pack path of contact::subcontact_set switched on (below).

#include "../core/errors.hpp"
#include "cohesive_frictional.hpp"
#include "compression.hpp"
#include "concepts.hpp"
#include "shear.hpp"
#include "tension.hpp"

namespace tessera::law {

using study_tie_law = cohesive_frictional<power_softening, elastic_compression, coulomb_residual>;
using linear_tie_law = cohesive_frictional<linear_softening, elastic_compression, coulomb_residual>;
using study_beam_law = cohesive_frictional<linear_softening, plastic_cap, coulomb_residual>;
using coupled_tie_law = cohesive_frictional<power_softening, elastic_compression, coulomb_coupled>;

/// Law with its elastic pack path switched on in contact::subcontact_set (states stored as
/// columns, the sub-contacts whose damage flags a step leaves unchanged updated 8 per AVX-512
/// instruction; same bits as Law without FMA contraction). The named solvers (solver.hpp) and the
/// examples' tie use it. With -march=native, one thread: bench_contacts' elastic prism 17.8-18.1 ns
/// per sub-contact-step against 26.0-28.8 ns; the RC tie 15.0-15.4 s against 17.1-17.5 s
/// (README, "Kernels and geometry"). Use it as the Law of a solver or subcontact_set:
///     solver<blocks::deformable<...>, law::with_elastic_packs<law::study_tie_law>, ...>
template <ContactLaw L>
struct with_elastic_packs : L {
  static constexpr bool use_elastic_packs = true;
};

static_assert(ContactLaw<study_tie_law>);
static_assert(ContactLaw<linear_tie_law>);
static_assert(ContactLaw<study_beam_law>);
static_assert(ContactLaw<coupled_tie_law>);

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
    p.shear.phi_0 = friction_angle::from_degrees(35);
    p.shear.phi_res = friction_angle::from_degrees(30);
    return p;
  }
  throw invalid_input(tessera::detail::concat("study_prism_params: blocks = ", blocks,
                                              " is not a block count of the study's Table 1 (100, 250, 500, 750)"));
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

/// The same contact with its cohesion softening together with the tensile strength
/// (coulomb_coupled): identical stiffnesses, tension, compression and shear parameters.
[[nodiscard]] inline coupled_tie_law::params with_coupled_cohesion(const study_tie_law::params& decoupled) {
  coupled_tie_law::params p;
  p.k_n = decoupled.k_n;
  p.k_s = decoupled.k_s;
  p.tension = decoupled.tension;
  p.compression = decoupled.compression;
  p.shear = decoupled.shear;
  return p;
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
  p.shear.phi_0 = friction_angle::from_degrees(35);
  p.shear.phi_res = friction_angle::from_degrees(30);
  return p;
}

}  // namespace tessera::law
