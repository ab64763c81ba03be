#pragma once
// zones::linear_elastic_tet — isotropic linear elasticity of a constant-strain tetrahedral zone,
// evaluated in the co-rotated frame of its block (blocks/deformable.hpp), where strains are
// small. Hooke's law with the Lame constants
//     lambda = E nu / ((1 + nu)(1 - 2 nu)),   mu = G = E / (2 (1 + nu)),
//     sigma = lambda tr(eps) 1 + 2 mu eps.
// Voigt order (xx, yy, zz, yz, zx, xy); strain shears are engineering shears gamma_ij = 2 eps_ij.
// Stress positive in tension. Pure functions, thread-safe.

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "concepts.hpp"

namespace tessera::zones {

/// Linear elastic constant-strain tetrahedra (small strain, co-rotated by the block model)
struct linear_elastic_tet {
  /// The zone material: E, nu, rho
  struct params {
    real young = 0;      ///< Young's modulus E (Pa), > 0
    real poisson = 0;    ///< Poisson's ratio nu, -1 < nu < 0.5
    real density = 0;    ///< mass density rho (kg/m^3), > 0
  };

  static void validate(const params& p) {  ///< Refuses (invalid_input) E <= 0, nu outside (-1, 0.5) or rho <= 0, naming the value
    require_positive(p.young, "linear_elastic_tet: Young's modulus E (Pa)");
    require(p.poisson > -1.0 && p.poisson < 0.5, "linear_elastic_tet: Poisson's ratio nu = ", p.poisson,
            " must lie in (-1, 0.5)");
    require_positive(p.density, "linear_elastic_tet: density rho (kg/m^3)");
  }
  [[nodiscard]] static real density(const params& p) { return p.density; }  ///< rho (kg/m^3)
  [[nodiscard]] static real lame_lambda(const params& p) {  ///< Lame's lambda = E nu / ((1 + nu)(1 - 2 nu)) (Pa)
    return p.young * p.poisson / ((1 + p.poisson) * (1 - 2 * p.poisson));
  }
  [[nodiscard]] static real shear_modulus(const params& p) { return p.young / (2 * (1 + p.poisson)); }  ///< Shear modulus G = E / (2 (1 + nu)) (Pa)

  /// Lame constants, computed once per zone loop (no divisions in the zone kernel).
  struct constants {
    real lambda = 0;  ///< Pa
    real mu = 0;      ///< Pa
  };
  [[nodiscard]] static constants prepare(const params& p) { return {lame_lambda(p), shear_modulus(p)}; }  ///< lambda and G, once per material

  /// sigma = lambda tr(eps) 1 + 2 mu eps (Pa), eps in Voigt with engineering shears.
  [[nodiscard]] static voigt6 stress(const constants& c, const voigt6& eps) noexcept {
    const real volumetric = c.lambda * (eps[0] + eps[1] + eps[2]);
    voigt6 s;
    s[0] = volumetric + 2 * c.mu * eps[0];
    s[1] = volumetric + 2 * c.mu * eps[1];
    s[2] = volumetric + 2 * c.mu * eps[2];
    s[3] = c.mu * eps[3];
    s[4] = c.mu * eps[4];
    s[5] = c.mu * eps[5];
    return s;
  }
  [[nodiscard]] static voigt6 stress(const params& p, const voigt6& eps) noexcept { return stress(prepare(p), eps); }  ///< sigma = C eps (Pa), Voigt order, engineering shear strains
  /// The same on plain arrays: lets blocks::deformable vectorise its zone loop (no Eigen
  /// temporaries inside it).
  static void stress(const constants& c, const real (&eps)[6], real (&sigma)[6]) noexcept {
    const real volumetric = c.lambda * (eps[0] + eps[1] + eps[2]);
    for (int k = 0; k < 3; ++k) sigma[k] = volumetric + 2 * c.mu * eps[k];
    for (int k = 3; k < 6; ++k) sigma[k] = c.mu * eps[k];
  }
  [[nodiscard]] static Eigen::Matrix<real, 6, 6> elasticity_matrix(const params& p) {  ///< The 6 x 6 elasticity matrix C (Pa), Voigt order
    const real lambda = lame_lambda(p), mu = shear_modulus(p);
    Eigen::Matrix<real, 6, 6> c = Eigen::Matrix<real, 6, 6>::Zero();
    c.topLeftCorner<3, 3>().setConstant(lambda);
    for (int i = 0; i < 3; ++i) c(i, i) += 2 * mu;
    for (int i = 3; i < 6; ++i) c(i, i) = mu;
    return c;
  }
  /// W = 1/2 sigma : eps (J/m^3).
  [[nodiscard]] static real strain_energy_density(const params& p, const voigt6& eps) {
    return 0.5 * stress(p, eps).dot(eps);
  }
};

static_assert(ZoneModel<linear_elastic_tet>, "linear_elastic_tet must satisfy ZoneModel");

}  // namespace tessera::zones
