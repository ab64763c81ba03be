#pragma once
// What a verification case takes and gives (examples/verification, cases.hpp): the joint of the
// detected contacts, the inputs of every case with their checks (validate), and the result a case
// returns, its figures and curves.

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "tessera/contact/detected_contacts.hpp"
#include "tessera/core/errors.hpp"
#include "tessera/core/types.hpp"
#include "tessera/geometry/tessellation.hpp"
#include "tessera/integrator/central_difference.hpp"
#include "tessera/integrator/damping.hpp"
#include "tessera/law/cohesive_frictional.hpp"
#include "tessera/law/compression.hpp"
#include "tessera/law/shear.hpp"
#include "tessera/law/tension.hpp"

namespace tessera::verification {

using joint_law = law::cohesive_frictional<law::no_tension, law::elastic_compression, law::coulomb_residual>;
using contacts = contact::detected_contacts<joint_law>;
using undamped = integrator::central_difference<integrator::no_damping>;
using damped = integrator::central_difference<integrator::local_damping>;

/// Inputs of every case (SI; angles in degrees).
struct inputs {
  std::string which = "incline";
  real angle_deg = 20;      ///< incline angle theta
  real friction_deg = 30;   ///< joint friction angle phi
  real aspect = 1;          ///< topple: width / height b / h
  real size = 0.5;          ///< block edge (m); topple: the height h
  int blocks = 5;           ///< stack: blocks in the column
  real damping = -1;        ///< local damping gamma; < 0: the case's default (0 incline/topple, 0.8 stack/drop and a deformable sticking incline)
  real duration = -1;       ///< simulated time (s); < 0: the case's default
  real drop_height = 0.01;  ///< drop: initial gap (m)
  real k_n = 1e11;          ///< joint normal stiffness (Pa/m); k_s = k_n
  real density = 2400;      ///< kg/m^3
  real tolerance = 1e-3;    ///< contact tolerance (m)
  real cohesion = 3000;     ///< bond: cohesion c_0 of the bonded face (Pa); broken: friction alone
  bool deformable = false;  ///< incline, topple, stack, drop: deformable blocks instead of rigid ones
  real young = 30e9;        ///< deformable: Young's modulus (Pa); Poisson's ratio 0.2
  real zone_edge = -1;      ///< deformable: target zone edge (m); < 0: the block edge
  bool quick = false;       ///< shorter runs (tests)
};

/// What a case measured.
struct result {
  std::string which;
  real measured = 0, reference = 0, error_rel = 0, tolerance = 0;
  std::string quantity, unit;  ///< what measured/reference are
  std::string mode, expected_mode;  ///< topple: topple / slide / stable
  bool pass = false;
  real drift_m = 0;  ///< stack: motion of the top block over the second half of the run
  real energy_error_rel = 0;
  index_t steps = 0, rebuilds = 0, growths = 0, subcontacts = 0;
  real dt = 0;
  std::string damping_in_force;  ///< solver::damping_in_force() of the run
  std::vector<double> t, x, z, rotation;  ///< curve: top (moving) block's centroid displacement and tilt
  // reclose: the path (top displacement m, axial stress Pa) and its figures (Pa)
  std::vector<double> u, stress;
  real peak = 0, stress_at_reversal = 0, max_stress_after_closure = 0;
  // bond: the shear force on the cube along the curve (N); the acceleration after the failure
  // (m/s^2) against the incline's, its error (relative to the reference, or to g when the block
  // should stick); the slide (m); the sub-contacts that started bonded and those that kept their
  // state at the last rebuild. peak: the shear force at failure; stress_at_reversal: the tilt then (rad)
  std::vector<double> force;
  real acceleration = 0, acceleration_reference = 0, acceleration_error = 0, slide_m = 0;
  index_t bonded_at_start = 0, kept_last_rebuild = 0;
  geometry::tessellation final_blocks;    ///< block geometry at the end (for VTK)
};

constexpr real g = 9.81;
constexpr real ramp_s = 0.1;  ///< incline and topple: time over which the tilt grows to theta (s)

/// The joint of every case.
[[nodiscard]] inline joint_law::params joint(const inputs& in) {
  joint_law::params p;
  p.k_n = in.k_n;
  p.k_s = in.k_n;
  p.shear.phi_0 = law::friction_angle::from_degrees(in.friction_deg);
  p.shear.phi_res = p.shear.phi_0;
  return p;
}

/// bond: the cube's weight W = rho b^3 g and the bond's failure force c_0 b^2 (N).
[[nodiscard]] inline real bond_weight(const inputs& in) { return in.density * in.size * in.size * in.size * g; }
[[nodiscard]] inline real bond_failure_force(const inputs& in) { return in.cohesion * in.size * in.size; }

/// Checks the inputs; throws invalid_input naming the value.
inline void validate(const inputs& in) {
  const auto positive = [](real v, const char* what) {
    require(std::isfinite(v) && v > 0, "verification: ", what, " = ", v, " must be finite and > 0");
  };
  require(in.which == "incline" || in.which == "topple" || in.which == "stack" || in.which == "drop" ||
              in.which == "reclose" || in.which == "bond",
          "verification: unknown case '", in.which, "' (incline, topple, stack, drop, reclose, bond)");
  require(std::isfinite(in.cohesion) && in.cohesion > 0 && in.cohesion <= 1e8, "verification: --cohesion = ",
          in.cohesion, " Pa must lie in (0, 1e8]");
  require(std::isfinite(in.angle_deg) && in.angle_deg >= 0 && in.angle_deg < 90, "verification: --angle-deg = ",
          in.angle_deg, " must lie in [0, 90)");
  require(std::isfinite(in.friction_deg) && in.friction_deg >= 0 && in.friction_deg < 90,
          "verification: --friction-deg = ", in.friction_deg, " must lie in [0, 90)");
  positive(in.aspect, "--aspect (b/h)");
  require(in.aspect <= 20, "verification: --aspect = ", in.aspect, " must be <= 20");
  positive(in.size, "--size (m)");
  positive(in.k_n, "--kn (Pa/m)");
  require(in.k_n <= 1e14, "verification: --kn = ", in.k_n, " Pa/m must be <= 1e14");
  positive(in.density, "density (kg/m^3)");
  positive(in.tolerance, "--tolerance (m)");
  require(in.tolerance < 0.1 * in.size, "verification: --tolerance = ", in.tolerance, " m must be below a tenth of the block (",
          0.1 * in.size, " m)");
  require(in.blocks >= 1 && in.blocks <= 200, "verification: --blocks = ", in.blocks, " must lie in [1, 200]");
  require(in.damping < 0 || (in.damping <= 1 && std::isfinite(in.damping)), "verification: --damping = ", in.damping,
          " must lie in [0, 1] (or be negative for the case's default)");
  require(in.duration < 0 || (in.duration > 0 && in.duration <= 100), "verification: --duration = ", in.duration,
          " s must lie in (0, 100]");
  require(std::isfinite(in.drop_height) && in.drop_height >= 0 && in.drop_height <= in.size,
          "verification: --drop-height = ", in.drop_height, " m must lie in [0, block size]");
  require(!in.deformable || (in.which != "reclose" && in.which != "bond"), "verification: --deformable applies to incline, topple, stack and drop, not to ",
          in.which, in.which == "reclose" ? " (its prism is deformable already)" : " (the bonded cube is rigid)");
  require(!in.deformable || (in.which != "incline" && in.which != "topple") || in.duration <= 2,
          "verification: --duration = ", in.duration, " s of a deformable ", in.which,
          " must be at most 2 s (its zoned base grows with the slide)");
  require(std::isfinite(in.young) && in.young > 0 && in.young <= 1e13, "verification: --young = ", in.young,
          " Pa must lie in (0, 1e13]");
  require(in.zone_edge < 0 || (std::isfinite(in.zone_edge) && in.zone_edge >= in.size / 20 && in.zone_edge <= in.size),
          "verification: --zone-edge = ", in.zone_edge, " m must lie in [", in.size / 20, ", ", in.size,
          "] (a twentieth of the block to the block; finer would take millions of zones) or be negative for the block edge");
  if (in.which == "bond") {
    const real weight = bond_weight(in), failure_force = bond_failure_force(in);
    require(weight * std::sin(in.angle_deg * std::numbers::pi / 180) > 1.05 * failure_force,
            "verification: --angle-deg = ", in.angle_deg, " never breaks the bond: it fails at a tilt of ",
            std::asin(std::min<real>(1, failure_force / weight)) * 180 / std::numbers::pi, " deg (c_0 b^2 = ",
            failure_force, " N against a weight of ", weight, " N); tilt further (5 % margin) or lower --cohesion");
  }
}

}  // namespace tessera::verification
