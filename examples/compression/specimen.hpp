#pragma once
// The compression driver's specimen (main.cpp says what it measures): options, scene, run and
// summary. The concrete is a recipe of examples/calibrate --material (common/scenes.hpp
// concrete_recipe): beam (the default) the beam's concrete at the beam's block size, the default
// 250-block half beam (725 x 150 x 200 mm) giving a mean cell volume of 8.7e-5 m^3 (a 44 mm
// block); prism the study's prism concrete at the 100-block prism's (2.8e-5 m^3, a 30 mm block,
// one zone per face triangle, no contact cap). --blocks 0 keeps the recipe's block size; another
// block count scales the contact stiffness with 1 / block size (k_n = E / t) and the face zoning
// edge with the block size, so the macro modulus and the sub-contacts per face stay the recipe's.
// --law picks the beam concrete's contact law, a row of common/concrete_laws.hpp (study_beam_law,
// slip_softening_beam_law, crushing_beam_law, mixed_mode_beam_law); the specimen is a template on the law.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "common/cli.hpp"
#include "tessera/contact/platen.hpp"
#include "tessera/geometry/shapes.hpp"
#include "tessera/geometry/voronoi.hpp"
#include "tessera/geometry/zoning.hpp"
#include "tessera/io/json.hpp"
#include "tessera/presets/pulatsu2020.hpp"
#include "tessera/solver/recorders.hpp"
#include "tessera/solver/solver.hpp"
#include "common/concrete_set.hpp"
#include "common/scenes.hpp"
#include "compression/curve.hpp"
#include "rc_beam/beam.hpp"

namespace tessera::scenes {

/// The compression driver's flags (main.cpp --help), SI units.
struct compression_options {
  cli::standard_options common;
  std::string material = "beam", shape = "cylinder", ends = "frictionless";
  std::string law = "study";  ///< study, slip_softening or crushing (--material beam only)
  real g_ii = 0;              ///< mode-II fracture energy with --law slip_softening (J/m^2; 0 = default_g_ii)
  real g_c = 0;               ///< G_c (J/m^2) with --law crushing (0 = default_g_c) or mixed_mode (0 = the plastic cap)
  real cap_residual = 0.1;    ///< residual cap / --cap with --law crushing
  bool crush_shear = false;   ///< --crush-shear: the shear limit falls with the crushed cap
  real width = 0.15, height = 0.3;  ///< cylinder diameter or prism side, height (m)
  int blocks = 0;                   ///< 0: the beam's block size
  real friction = 0.15, confinement = 0;  ///< platen friction coefficient; lateral pressure (Pa)
  real f_t = 0, cohesion_ratio = 2, phi_deg = 35, phi_res_deg = 30, cap = 35e6;  ///< contact law (Pa, -, deg)
  real rate = 5e-3, step_displacement = 2e-9, max_strain = 6e-3, drop = 0.2;     ///< m/s, m, -, -
  bool no_vtk = false;
};

/// The concrete flags of o (law, G_II, c_0 / f_T, phi_0, phi_res, cap, and the crushing law's) into c.
inline void concrete_set_from(const compression_options& o, concrete_set& c) {
  c.law = o.law, c.g_ii = o.g_ii, c.cohesion_ratio = o.cohesion_ratio, c.phi_0_deg = o.phi_deg;
  c.phi_res_deg = o.phi_res_deg, c.cap = o.cap, c.g_c = o.g_c, c.cap_residual = o.cap_residual;
  c.crush_shear = o.crush_shear;
}
/// c's concrete into the flags of o (--params: the specimen applies them over the recipe's contacts).
inline void concrete_set_to(const concrete_set& c, compression_options& o) {
  o.law = c.law, o.g_ii = c.g_ii, o.cohesion_ratio = c.cohesion_ratio, o.phi_deg = c.phi_0_deg;
  o.phi_res_deg = c.phi_res_deg, o.cap = c.cap, o.f_t = 0;
  o.g_c = c.g_c, o.cap_residual = c.cap_residual, o.crush_shear = c.crush_shear;
}

inline constexpr int compression_sides = 36;  ///< the cylinder's polygon
template <class Law>
using compression_solver = solver<blocks::deformable<zones::linear_elastic_tet>, presets::bonded_faces<Law>>;

/// The specimen of `recipe`'s concrete (presets::study_beam_law for beam, law::study_tie_law for prism).
template <class Law>
class compression_specimen {
 public:
  compression_specimen(const compression_options& o, const concrete_recipe<Law>& recipe) : o_(o), recipe_(recipe) {
    require_g_ii_with_law("compression", o.law, o.g_ii);
    require(o.ends != "friction" || o.friction > 0, "compression: --friction ", o.friction,
            " must be > 0 with --ends friction (use --ends frictionless for none)");
    require(o.phi_res_deg <= o.phi_deg, "compression: --phi-res-deg ", o.phi_res_deg, " must not exceed --phi-deg ",
            o.phi_deg);
    const real pi = std::numbers::pi, R = o.width / 2;
    const bool cylinder = o.shape == "cylinder";
    const auto domain = cylinder ? geometry::cylinder_prism(vec3(0, 0, o.height / 2), vec3::UnitZ(), R, o.height,
                                                            compression_sides, pi / compression_sides)
                                 : geometry::convex_polyhedron::box(vec3(-R, -R, 0), vec3(R, R, o.height));
    section_ = cylinder ? 0.5 * compression_sides * R * R * std::sin(2 * pi / compression_sides) : o.width * o.width;
    apothem_ = cylinder ? R * std::cos(pi / compression_sides) : R;
    const real volume = section_ * o.height;
    const real cell = recipe.cell_volume;
    blocks_ = o.blocks > 0 ? o.blocks : recipe.blocks_in(volume);
    size_ratio_ = std::cbrt(cell / (volume / static_cast<real>(blocks_)));  // recipe block / this block
    zone_edge_ = recipe.zone_edge / size_ratio_;  // 0 stays 0: one zone per face triangle
    // Zones grow as the square of 1 / edge over the faces (rc_beam: 29 082 zones for 250 blocks at 30 mm;
    // one zone per face triangle: about 115 a block).
    const real zones = recipe.zone_edge > 0 ? 29082 * (recipe.zone_edge / zone_edge_) * (recipe.zone_edge / zone_edge_) *
                                                  (volume / (250 * cell)) * std::cbrt(blocks_ / 250.0)
                                            : 115.0 * static_cast<real>(blocks_);
    require(zones <= 5e6, "compression: ", blocks_, " blocks in ", volume, " m^3 would need about ", zones,
            " zones (~", zones * 1e-6, " GB); the limit is 5e6 zones: use a smaller specimen or fewer --blocks");
    tess_ = geometry::random_voronoi(domain, blocks_, o.common.seed);
    geometry::zoning_options z = recipe.zoning();
    z.target_edge_length = zone_edge_;
    mesh_ = geometry::zone_blocks(tess_, z);
    law_ = recipe.contact;
    law_.k_n *= size_ratio_, law_.k_s *= size_ratio_;
    if (o.f_t > 0) law_.tension.f_T = o.f_t;
    law_.shear.c_0 = o.cohesion_ratio * law_.tension.f_T;
    law_.shear.c_res = recipe.contact.shear.c_res == 0 ? 0 : 0.01 * law_.shear.c_0;  // 0: the mixed-mode law has none
    law_.shear.phi_0 = law::friction_angle::from_degrees(o.phi_deg);
    law_.shear.phi_res = law::friction_angle::from_degrees(o.phi_res_deg);
    if constexpr (has_cap) law_.compression.f_c = o.cap;
    Law::validate(law_);  // names a bad parameter (c_res, phi_res, G_II) before the scene is built
  }

  /// Whether the law caps the contacts' compression (the beam's; the prism's contacts have no cap).
  static constexpr bool has_cap = requires(typename Law::params p) { p.compression.f_c; };
  [[nodiscard]] const concrete_recipe<Law>& recipe() const { return recipe_; }

  [[nodiscard]] index_t block_count() const { return blocks_; }
  [[nodiscard]] index_t zone_count() const { return mesh_.zone_count(); }
  [[nodiscard]] real section() const { return section_; }
  [[nodiscard]] real size_ratio() const { return size_ratio_; }
  [[nodiscard]] real zone_edge() const { return zone_edge_; }
  [[nodiscard]] const typename Law::params& contact_params() const { return law_; }

  /// Builds the solver, confines, loads and runs to the post-peak drop or --max-strain.
  [[nodiscard]] compression_result run() const;

 private:
  compression_options o_;
  concrete_recipe<Law> recipe_;
  geometry::tessellation tess_;
  geometry::block_mesh mesh_;
  typename Law::params law_;
  index_t blocks_ = 0;
  real section_ = 0, apothem_ = 0, size_ratio_ = 1, zone_edge_ = 0;
};

}  // namespace tessera::scenes

#include "compression/run.hpp"
