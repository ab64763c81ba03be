#pragma once
// Scene builders shared by the example drivers: the reference study's concrete prism
// (Pulatsu et al. 2020, Sec. 3; DESIGN.md §4) as a random Voronoi tessellation zoned into
// tetrahedra, with the study's materials. Reused by the plain-concrete direct tension test and
// the RC tie (which adds the bar).
//
//   geometry  68 x 68 x 600 mm box, long axis z, `blocks` random Voronoi blocks (seed)
//   blocks    semi-rigid: E_block = 10 E = 280 GPa, nu = 0.2, rho = 2400 kg/m^3
//   contacts  Table 1 stiffnesses for the block count, f_T = 2.15 MPa, G_f = 60 N/m,
//             c_0 = 2 f_T (prism_options::cohesion_ratio), c_res = 0.01 c_0, phi_0 = 35 deg, phi_res = 30 deg, power softening
//             (alpha = 3) or linear softening

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "tessera/blocks/linear_elastic_tet.hpp"
#include "tessera/presets.hpp"
#include "tessera/core/types.hpp"
#include "tessera/geometry/block_mesh.hpp"
#include "tessera/geometry/tessellation.hpp"
#include "tessera/geometry/voronoi.hpp"
#include "tessera/geometry/zoning.hpp"

namespace tessera::scenes {

/// Macro elastic constants of the study's concrete.
inline constexpr real concrete_young = 28e9;   ///< E (Pa)
inline constexpr real concrete_poisson = 0.2;  ///< nu
inline constexpr real concrete_density = 2400; ///< rho (kg/m^3)
/// Block modulus multiplier of the "semi-rigid" blocks (study Sec. 2.1).
inline constexpr real semi_rigid_factor = 10;

struct prism_options {
  int blocks = 100;                        ///< 100, 250, 500 or 750 (Table 1)
  std::uint64_t seed = 1;                  ///< tessellation seed
  vec3 size = vec3(0.068, 0.068, 0.6);     ///< box edge lengths (m), long axis z
  real zone_edge = 0;                      ///< zoning target edge (m), 0 = one zone per face triangle
  /// Initial cohesion of the contacts c_0 / f_T (the study and DESIGN.md: 2); c_res = 0.01 c_0.
  /// The drivers check it (finite, >= 0) before they create their output folder.
  real cohesion_ratio = 2;
  /// Calibration (DESIGN.md §5, examples/calibrate): the contact tensile strength and, with it,
  /// the cohesion are the Table 1 values times strength_scale; the contact fracture energy is
  /// G_f times fracture_energy_scale. 1 and 1 = the study verbatim. The references the figures
  /// are checked against (prism_scene::f_T, G_f) stay the macro values.
  real strength_scale = 1;
  real fracture_energy_scale = 1;
  /// Regularisation of the random tessellation (Lloyd steps, minimum generator spacing, ...);
  /// the default is a plain Poisson-Voronoi tessellation.
  geometry::tessellation_options tessellation{};
};

struct prism_scene {
  aabb box;
  geometry::tessellation tess;
  geometry::block_mesh mesh;
  zones::linear_elastic_tet::params block_material;
  law::study_tie_law::params contact;      ///< power softening (the study's choice)
  real f_T = 0;  ///< the concrete's tensile strength (Pa): the reference of the peak, whatever the contacts carry
  real G_f = 0;  ///< the concrete's fracture energy (J/m^2): the reference of the dissipated energy
  real young = concrete_young;  ///< the concrete's E (Pa): wave transit and quasi-static check of the pull
  [[nodiscard]] real cross_section() const { return box.size().x() * box.size().y(); }
  [[nodiscard]] real length() const { return box.size().z(); }
};

/// Calibration scales and the cohesion ratio on the prism's contacts: f_T x strength_scale, G_f x
/// fracture_energy_scale, c_0 = cohesion_ratio x the scaled f_T, c_res = 0.01 c_0.
inline void scale_prism_contacts(law::study_tie_law::params& c, real strength_scale, real fracture_energy_scale,
                                 real cohesion_ratio) {
  c.tension.f_T *= strength_scale;
  c.tension.G_f *= fracture_energy_scale;
  c.shear.c_0 = cohesion_ratio * c.tension.f_T;
  c.shear.c_res = 0.01 * c.shear.c_0;
}

/// A concrete of the example drivers, as examples/calibrate --material names them: the contact
/// law's parameters with the block size and face zoning they belong to, and the blocks' material.
/// "prism": the study's prism concrete (prism_concrete, below); "beam": the beam's concrete
/// (rc_beam/beam.hpp beam_concrete). A driver that measures a concrete in another specimen keeps
/// the recipe's mean block volume (blocks_in) and zoning (zoning), so its contacts are the ones
/// the recipe's parameters were set for.
template <class Law>
struct concrete_recipe {
  std::string material;          ///< "prism" or "beam"
  typename Law::params contact;  ///< the contacts, calibration scales applied
  real f_T = 0;                  ///< the concrete's tensile strength (Pa): the reference of strength figures
  real young = 0;                ///< the concrete's E (Pa)
  real cell_volume = 0;          ///< the recipe's mean block volume (m^3)
  real zone_edge = 0;            ///< face zoning target edge (m); 0 = one zone per face triangle
  bool refine_interior = true;   ///< whether the zoning refines the blocks' interiors too
  zones::linear_elastic_tet::params block_material;  ///< semi-rigid blocks: 10 E
  /// Blocks of the recipe's mean volume in `volume` (m^3), at least 2.
  [[nodiscard]] index_t blocks_in(real volume) const {
    return std::max<index_t>(2, static_cast<index_t>(std::llround(volume / cell_volume)));
  }
  /// The recipe's zoning options (zone_edge, refine_interior).
  [[nodiscard]] geometry::zoning_options zoning() const {
    geometry::zoning_options z;
    z.target_edge_length = zone_edge;
    z.refine_interior = refine_interior;
    return z;
  }
  /// The same recipe with contacts `c` of another law Other (every other field kept).
  template <class Other>
  [[nodiscard]] concrete_recipe<Other> with_contact(const typename Other::params& c) const {
    return {material, c, f_T, young, cell_volume, zone_edge, refine_interior, block_material};
  }
};

/// --g-ii 0 with --law slip_softening: the mode-II fracture energy G_II the drivers then use (J/m^2).
inline constexpr real default_g_ii = 500;
/// The G_II (J/m^2) a --g-ii flag value gives: the value, or default_g_ii for 0.
[[nodiscard]] inline real g_ii_or_default(real g_ii_flag) { return g_ii_flag > 0 ? g_ii_flag : default_g_ii; }

/// The concrete's shear and cap on contact parameters p whose f_T is already scaled: c_0 =
/// cohesion_ratio f_T, c_res = 0.01 c_0, phi_0 and phi_res (deg), and the compressive cap (Pa) where
/// the law has one. With 2, 35, 30 and 35e6 it leaves study_beam_params' contacts as they are, to the
/// bit. Used by the concrete set of brazilian, compression and calibrate (concrete_set.hpp
/// with_concrete) and by rc_beam (beam.hpp make_beam).
template <class Params>
void apply_concrete_shear(Params& p, real cohesion_ratio, real phi_0_deg, real phi_res_deg, real cap) {
  p.shear.c_0 = cohesion_ratio * p.tension.f_T;
  p.shear.c_res = 0.01 * p.shear.c_0;
  p.shear.phi_0 = law::friction_angle::from_degrees(phi_0_deg);
  p.shear.phi_res = law::friction_angle::from_degrees(phi_res_deg);
  if constexpr (requires { p.compression.f_c; }) p.compression.f_c = cap;
}

/// Refuses --g-ii `g_ii` (J/m^2) given with the study's law (slip_softening, crushing and
/// mixed_mode take it), naming the value; `driver` opens the message.
inline void require_g_ii_with_slip_softening(const char* driver, const std::string& law, real g_ii) {
  require(law != "study" || g_ii == 0, driver, ": --g-ii ", g_ii,
          " J/m^2 applies to --law slip_softening only (or --law crushing or mixed_mode; the study's law has no "
          "mode-II fracture energy)");
}

/// --g-c 0 with --law crushing: the compressive fracture energy G_c the drivers then use (J/m^2).
inline constexpr real default_g_c = 20000;

/// Refuses a crushing flag `flag` (--g-c, --cap-residual, --crush-shear) given with --law `law`
/// where it does not apply, naming the flag, the law and G_c: all three apply to crushing; with
/// mixed_mode --g-c > 0 (g_c, J/m^2) selects the softening cap (0 keeps the plastic cap) and the
/// other two apply beside it. `driver` opens the message.
inline void require_crushing_flag(const char* driver, const std::string& flag, const std::string& law, real g_c) {
  if (law == "crushing") return;
  if (law == "mixed_mode") {
    require(flag == "--g-c" || g_c > 0, driver, ": ", flag, " with --law mixed_mode needs --g-c > 0 (got --g-c ", g_c,
            ": the plastic cap, which does not soften)");
    return;
  }
  require(false, driver, ": ", flag, " applies to --law crushing or mixed_mode only (--law ", law,
          " has a cap that does not soften)");
}

/// The slip-softening concrete `slip` with its cap softening with crushing over G_c (J/m^2) to
/// residual x f_c (presets::with_softening_cap), everything else the recipe's.
[[nodiscard]] inline concrete_recipe<presets::crushing_beam_law> with_softening_cap(
    const concrete_recipe<presets::slip_softening_beam_law>& slip, real G_c, real residual, bool scales_shear) {
  return slip.with_contact<presets::crushing_beam_law>(presets::with_softening_cap(slip.contact, G_c, residual, scales_shear));
}

/// The beam's concrete `beam` with its contacts' shear made slip-softening over G_II (J/m^2):
/// presets::with_slip_softening on the recipe's contacts, everything else the recipe's.
[[nodiscard]] inline concrete_recipe<presets::slip_softening_beam_law> with_slip_softening(
    const concrete_recipe<presets::study_beam_law>& beam, real G_II) {
  return beam.with_contact<presets::slip_softening_beam_law>(presets::with_slip_softening(beam.contact, G_II));
}

/// The study's prism concrete as a recipe: the 100-block prism's contacts (Table 1) times
/// strength_scale (examples/calibrate --material prism fits it; 0.907 puts the 100-block prism's
/// mean peak at f_T = 2.15 MPa), c_0 = cohesion_ratio f_T, the 100-block prism's mean block volume
/// (68 x 68 x 600 mm / 100 = 27.7 cm^3, a 30 mm block), one zone per face triangle, blocks of
/// 10 x 28 GPa. `blocks` (calibrate --blocks) picks another prism's contacts (scaled_prism_params) and
/// block volume.
[[nodiscard]] inline concrete_recipe<law::study_tie_law> prism_concrete(real strength_scale, real cohesion_ratio = 2,
                                                                        int blocks = 100) {
  require(blocks >= 2, "prism: blocks = ", blocks, " must be >= 2");
  require(std::isfinite(strength_scale) && strength_scale > 0, "prism: strength scale = ", strength_scale,
          " must be finite and > 0");
  concrete_recipe<law::study_tie_law> r;
  r.material = "prism";
  r.contact = law::scaled_prism_params(blocks);
  r.f_T = r.contact.tension.f_T;
  scale_prism_contacts(r.contact, strength_scale, 1, cohesion_ratio);
  r.young = concrete_young;
  r.cell_volume = prism_options{}.size.prod() / blocks;
  r.block_material = {semi_rigid_factor * concrete_young, concrete_poisson, concrete_density};
  return r;
}

/// Builds the study's prism: tessellation, zoning, materials. Contacts of Table 1 for 100, 250,
/// 500 and 750 blocks, of Table 1 scaled as blocks^(1/3) for any other count (scaled_prism_params).
[[nodiscard]] inline prism_scene make_prism(const prism_options& o) {
  prism_scene s;
  require(std::isfinite(o.strength_scale) && o.strength_scale > 0, "prism: strength scale = ", o.strength_scale,
          " must be finite and > 0");
  require(std::isfinite(o.fracture_energy_scale) && o.fracture_energy_scale > 0, "prism: fracture energy scale = ",
          o.fracture_energy_scale, " must be finite and > 0");
  s.contact = law::scaled_prism_params(o.blocks);
  s.f_T = s.contact.tension.f_T;
  s.G_f = s.contact.tension.G_f;
  scale_prism_contacts(s.contact, o.strength_scale, o.fracture_energy_scale, o.cohesion_ratio);
  s.box.lo = vec3::Zero();
  s.box.hi = o.size;
  s.tess = geometry::random_voronoi(s.box, o.blocks, o.seed, o.tessellation);
  geometry::zoning_options z;
  z.target_edge_length = o.zone_edge;
  s.mesh = geometry::zone_blocks(s.tess, z);
  s.block_material = {semi_rigid_factor * concrete_young, concrete_poisson, concrete_density};
  return s;
}

}  // namespace tessera::scenes
