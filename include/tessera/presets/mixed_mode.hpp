#pragma once
// presets/mixed_mode.hpp: the beam's concrete with the mixed-mode law (law::mixed_mode_cohesive,
// issue #63's second candidate family; not the study's law): one damage for tension and shear,
// driven by the effective plastic opening, with the study's beam contacts' f_T, G_f (= G_I), c_0,
// phi_0, phi_res, cap and stiffnesses; and the same law on the study's prism and tie contacts
// (Table 1: f_T, G_f, c_0, phi_0, phi_res, stiffnesses; no cap, as the study's tie law has none).
//
// | alias                | law                                  | use                                  |
// |----------------------|--------------------------------------|--------------------------------------|
// | mixed_mode_beam_law  | mixed_mode_cohesive<plastic_cap>     | rc_beam / brazilian --law mixed_mode |
// | mixed_crushing_beam_law | mixed_mode_cohesive<softening_cap> | --law mixed_mode --g-c G (the cap   |
// |                      |                                      | softens with crushing, issue #63)    |
// | mixed_mode_tie_law   | mixed_mode_cohesive<elastic_compression> | rc_tie --law mixed_mode          |

#include "../law/mixed_mode.hpp"
#include "pulatsu2020.hpp"

namespace tessera::presets {

using mixed_mode_beam_law = law::mixed_mode_cohesive<law::plastic_cap>;
static_assert(law::ElasticPackLaw<mixed_mode_beam_law>);
using mixed_crushing_beam_law = law::mixed_mode_cohesive<law::softening_cap>;
static_assert(law::ElasticPackLaw<mixed_crushing_beam_law> && mixed_crushing_beam_law::softens_with_crushing);
using mixed_mode_tie_law = law::mixed_mode_cohesive<law::elastic_compression>;
static_assert(law::ElasticPackLaw<mixed_mode_tie_law>);

/// The default mode-II fracture energy of the mixed-mode law on a contact `c` of the study's law
/// (J/m^2): (c_0 / f_T) G_I, which makes the shear softening length l_II = 2 G_II / c_0 equal to
/// the tensile one l_I = 2 G_I / f_T, so the damage grows with the Euclidean norm of the plastic
/// opening and slip (Camacho and Ortiz's effective opening with beta = 1). 120 J/m^2 for the
/// study's beam contacts (study_beam_law::params) and for its prism and tie contacts (Table 1,
/// study_tie_law::params): c_0 = 2 f_T, G_f = 60 J/m^2.
template <class StudyContact>
  requires requires(const StudyContact& c) {
    real(c.shear.c_0);
    real(c.tension.f_T);
    real(c.tension.G_f);
  }
[[nodiscard]] real mixed_mode_default_g_ii(const StudyContact& c) noexcept {
  return c.shear.c_0 / c.tension.f_T * c.tension.G_f;
}

/// The beam's contact `beam` with the mixed-mode law: its stiffnesses, f_T, G_f (as G_I), cap,
/// c_0, phi_0 and phi_res, the residual cohesion 0 (the law has none), and G_II (J/m^2; 0 = the
/// default above). The law's validate refuses G_II <= c_0^2 / (2 k_s) and phi_res > phi_0.
[[nodiscard]] inline mixed_mode_beam_law::params with_mixed_mode(const study_beam_law::params& beam, real G_II = 0) {
  mixed_mode_beam_law::params p;
  p.k_n = beam.k_n;
  p.k_s = beam.k_s;
  p.tension = beam.tension;
  p.compression = beam.compression;
  p.shear = {beam.shear.c_0, beam.shear.phi_0, 0, beam.shear.phi_res, G_II > 0 ? G_II : mixed_mode_default_g_ii(beam)};
  return p;
}

/// The study's prism or tie contact `prism` (Table 1, study_prism_params or scaled_prism_params)
/// with the mixed-mode law: its stiffnesses, f_T and G_f (as G_I; the power softening's alpha and
/// residual ratio are dropped, the law softens linearly over G_f), no compressive limit (as the
/// study's tie law), c_0, phi_0 and phi_res, the residual cohesion 0, and G_II (J/m^2; 0 = (c_0/f_T)
/// G_f, 120 J/m^2 for Table 1's contacts). The law's validate refuses G_II <= c_0^2 / (2 k_s) (19.2
/// J/m^2 for the 100-block contacts) and phi_res > phi_0.
[[nodiscard]] inline mixed_mode_tie_law::params with_mixed_mode(const study_tie_law::params& prism, real G_II = 0) {
  mixed_mode_tie_law::params p;
  p.k_n = prism.k_n;
  p.k_s = prism.k_s;
  p.tension = {prism.tension.f_T, prism.tension.G_f};
  p.shear = {prism.shear.c_0, prism.shear.phi_0, 0, prism.shear.phi_res, G_II > 0 ? G_II : mixed_mode_default_g_ii(prism)};
  return p;
}

/// The mixed-mode contact `mixed` whose cap f_c softens with the plastic closure (softening_cap,
/// compression.hpp): G_c the compressive fracture energy above the residual (J/m^2), residual the
/// residual cap as a fraction of f_c in [0, 1], scales_shear: the compression side's Coulomb limit
/// times the cap's remaining fraction. The law's validate refuses G_c <= ((1 - residual) f_c)^2/(2 k_n).
[[nodiscard]] inline mixed_crushing_beam_law::params with_softening_cap(const mixed_mode_beam_law::params& mixed,
                                                                       real G_c, real residual,
                                                                       bool scales_shear = false) {
  return {mixed.k_n, mixed.k_s, mixed.tension, {mixed.compression.f_c, G_c, residual, scales_shear}, mixed.shear};
}

}  // namespace tessera::presets
