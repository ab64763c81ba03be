#pragma once
// The compression driver's specimen (main.cpp says what it measures): options, scene, run and
// summary. The beam's concrete at the beam's block size: the default 250-block half beam
// (725 x 150 x 200 mm) gives a mean cell volume of 8.7e-5 m^3 (a 44 mm block), which --blocks 0
// keeps; another block count scales the contact stiffness with 1 / block size (k_n = E / t) and
// the face zoning edge with the block size, so the macro modulus and the sub-contacts per face
// stay the recipe's. --law picks the contact law: study (the beam's, study_beam_law) or
// slip_softening (slip_softening_beam_law: cohesion and friction soften with the plastic slip
// over the mode-II fracture energy --g-ii); the specimen is a template on it.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <type_traits>
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
#include "compression/curve.hpp"

namespace tessera::scenes {

/// The compression driver's flags (main.cpp --help), SI units.
struct compression_options {
  cli::standard_options common;
  std::string shape = "cylinder", ends = "frictionless";
  real width = 0.15, height = 0.3;  ///< cylinder diameter or prism side, height (m)
  int blocks = 0;                   ///< 0: the beam's block size
  real friction = 0.15, confinement = 0;  ///< platen friction coefficient; lateral pressure (Pa)
  real f_t = 0, cohesion_ratio = 2, phi_deg = 35, phi_res_deg = 30, cap = 35e6;  ///< contact law (Pa, -, deg)
  std::string law = "study";  ///< study or slip_softening
  real g_ii = 0;              ///< mode-II fracture energy with --law slip_softening (J/m^2; 0 = the default below)
  real rate = 5e-3, step_displacement = 2e-9, max_strain = 6e-3, drop = 0.2;     ///< m/s, m, -, -
  bool no_vtk = false;
};

/// The beam recipe's mean cell volume (m^3): the default half beam over its 250 blocks.
inline constexpr real beam_cell_volume = 0.725 * 0.15 * 0.2 / 250;
inline constexpr real beam_face_zone_edge = 0.03;  ///< m, the beam's h / 5
inline constexpr int compression_sides = 36;       ///< the cylinder's polygon

inline constexpr real default_g_ii = 500;            ///< J/m^2, --g-ii 0 with --law slip_softening

/// The specimen under contact law Law (presets::study_beam_law or presets::slip_softening_beam_law).
template <class Law>
class compression_specimen {
 public:
  using law_type = Law;  ///< the contacts' law
  using solver_type = solver<blocks::deformable<zones::linear_elastic_tet>, presets::bonded_faces<Law>>;  ///< the scene's solver

  explicit compression_specimen(const compression_options& o) : o_(o) {
    require(o.law == "slip_softening" || o.g_ii == 0, "compression: --g-ii ", o.g_ii,
            " J/m^2 applies to --law slip_softening only (the study's law has no mode-II fracture energy)");
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
    blocks_ = o.blocks > 0 ? o.blocks : std::max<index_t>(2, std::llround(volume / beam_cell_volume));
    size_ratio_ = std::cbrt(beam_cell_volume / (volume / static_cast<real>(blocks_)));  // beam block / this block
    zone_edge_ = beam_face_zone_edge / size_ratio_;
    // Zones grow as the square of 1 / edge over the faces (rc_beam: 29 082 zones for 250 blocks at 30 mm).
    const real zones = 29082 * (beam_face_zone_edge / zone_edge_) * (beam_face_zone_edge / zone_edge_) *
                       (volume / (250 * beam_cell_volume)) * std::cbrt(blocks_ / 250.0);
    require(zones <= 5e6, "compression: ", blocks_, " blocks in ", volume, " m^3 would need about ", zones,
            " zones (~", zones * 1e-6, " GB); the limit is 5e6 zones: use a smaller specimen or fewer --blocks");
    tess_ = geometry::random_voronoi(domain, blocks_, o.common.seed);
    geometry::zoning_options z;
    z.target_edge_length = zone_edge_;
    z.refine_interior = false;
    mesh_ = geometry::zone_blocks(tess_, z);
    auto beam = presets::study_beam_params(250);
    if constexpr (std::is_same_v<Law, presets::study_beam_law>)
      law_ = beam;
    else
      law_ = presets::with_slip_softening(beam, o.g_ii > 0 ? o.g_ii : default_g_ii);
    law_.k_n *= size_ratio_, law_.k_s *= size_ratio_;
    if (o.f_t > 0) law_.tension.f_T = o.f_t;
    law_.shear.c_0 = o.cohesion_ratio * law_.tension.f_T;
    law_.shear.c_res = 0.01 * law_.shear.c_0;
    law_.shear.phi_0 = law::friction_angle::from_degrees(o.phi_deg);
    law_.shear.phi_res = law::friction_angle::from_degrees(o.phi_res_deg);
    law_.compression.f_c = o.cap;
    Law::validate(law_);  // names a bad parameter (c_res, phi_res, G_II) before the scene is built
  }

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
  geometry::tessellation tess_;
  geometry::block_mesh mesh_;
  typename Law::params law_;
  index_t blocks_ = 0;
  real section_ = 0, apothem_ = 0, size_ratio_ = 1, zone_edge_ = beam_face_zone_edge;
};

}  // namespace tessera::scenes

#include "compression/run.hpp"
