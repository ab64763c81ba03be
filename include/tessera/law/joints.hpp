#pragma once
// Named constructors for the joints people build scenes with, so that every strength a contact
// uses is one the user wrote (issue #40 item 3):
//
//     law::dry_joint(k_n, k_s, phi)        a dry frictional joint: no tension, no cohesion, Coulomb
//                                          friction phi from the first contact on (phi_0 = phi_res),
//                                          law dry_joint_law
//     law::bonded_joint({...})             a bonded cohesive joint: tensile strength and fracture
//                                          energy (linear softening), cohesion and friction while
//                                          intact, residual cohesion and friction once broken or
//                                          slipped, every one named; law bonded_joint_law
//
// Why: contact::detected_contacts starts the corners it finds unbonded (Law::unbonded_state), on
// the residual limit c_res + sigma_c tan(phi_res); a hand-filled params struct whose residual
// fields were left at 0 gives frictionless, cohesionless joints. dry_joint fills both friction
// angles; bonded_joint refuses a field that was not given. Both refuse bad values naming them.

#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "cohesive_frictional.hpp"
#include "compression.hpp"
#include "shear.hpp"
#include "tension.hpp"

namespace tessera::law {

/// A dry joint: no tensile strength, linear elastic in compression, Coulomb friction with a
/// residual value (what law::dry_joint fills).
using dry_joint_law = cohesive_frictional<no_tension, elastic_compression, coulomb_residual>;
/// A bonded joint: linear tension softening (f_T, G_f), elastic in compression, Coulomb limit with
/// brittle shear failure to residual cohesion and friction (what law::bonded_joint fills).
using bonded_joint_law = cohesive_frictional<linear_softening, elastic_compression, coulomb_residual>;

namespace detail {
inline void require_joint_stiffness(real k, const char* who, const char* name) {
  if (!(std::isfinite(k) && k > 0))
    throw invalid_input(tessera::detail::concat(who, ": ", name, " = ", k, " Pa/m must be finite and > 0"));
}
inline void require_joint_angle(const friction_angle& phi, const char* who, const char* name) {
  if (!(phi.radians() >= 0 && phi.radians() < std::numbers::pi_v<real> / 2))
    throw invalid_input(tessera::detail::concat(who, ": ", name, " = ", phi.degrees(), " deg must be in [0, 90) deg"));
}
}  // namespace detail

/// The params of a dry frictional joint (dry_joint_law): normal stiffness k_n (Pa/m, > 0), shear
/// stiffness k_s (Pa/m, > 0), friction angle phi in [0, 90) deg (friction coefficient tan(phi)).
/// No tension, no cohesion; phi_0 = phi_res = phi, so a contact slides at tan(phi) whether it
/// starts intact (face_contacts) or unbonded (detected_contacts). phi = 0 is a frictionless joint.
/// Throws invalid_input naming the bad value.
[[nodiscard]] inline dry_joint_law::params dry_joint(real k_n, real k_s, friction_angle phi) {
  constexpr const char* who = "law::dry_joint";
  detail::require_joint_stiffness(k_n, who, "normal stiffness k_n");
  detail::require_joint_stiffness(k_s, who, "shear stiffness k_s");
  detail::require_joint_angle(phi, who, "friction angle");
  dry_joint_law::params p;
  p.k_n = k_n;
  p.k_s = k_s;
  p.shear.c_0 = 0;
  p.shear.c_res = 0;
  p.shear.phi_0 = phi;
  p.shear.phi_res = phi;
  dry_joint_law::validate(p);
  return p;
}

/// The values of a bonded joint, each named (SI). Every field must be given: the reals default to
/// NaN and the angles to "not given", and law::bonded_joint refuses one left so (write 0 where 0 is
/// meant, e.g. residual_cohesion = 0 for a crack that keeps friction only).
struct bonded_joint_values {
  real k_n = std::numeric_limits<real>::quiet_NaN();               ///< normal stiffness (Pa/m, > 0), E/t
  real k_s = std::numeric_limits<real>::quiet_NaN();               ///< shear stiffness (Pa/m, > 0), G/t
  real tensile_strength = std::numeric_limits<real>::quiet_NaN();  ///< f_T (Pa, > 0)
  real fracture_energy = std::numeric_limits<real>::quiet_NaN();   ///< G_f (J/m^2 = N/m, > f_T^2/(2 k_n))
  real cohesion = std::numeric_limits<real>::quiet_NaN();          ///< c_0 of the intact joint (Pa, >= 0)
  std::optional<friction_angle> friction;                          ///< phi_0 of the intact joint, [0, 90) deg
  real residual_cohesion = std::numeric_limits<real>::quiet_NaN(); ///< c_res once broken or slipped (Pa, [0, c_0])
  std::optional<friction_angle> residual_friction;                 ///< phi_res once broken or slipped, [0, 90) deg
};

/// The params of a bonded cohesive joint (bonded_joint_law) from its named values: tensile
/// strength f_T (Pa) softening linearly to zero over the fracture energy G_f (N/m), Coulomb limit
/// c_0 + sigma_c tan(phi_0) while intact, c_res + sigma_c tan(phi_res) once broken in tension or
/// slipped (DESIGN.md §3). Faces that start bonded (face_contacts, or detected_contacts with
/// bond_faces) use all of them; corners that detected contacts find later start on the residual
/// values. Throws invalid_input naming a value that was not given or is out of range.
[[nodiscard]] inline bonded_joint_law::params bonded_joint(const bonded_joint_values& v) {
  constexpr const char* who = "law::bonded_joint";
  const auto given = [&](real x, const char* name) {
    if (std::isnan(x))
      throw invalid_input(tessera::detail::concat(who, ": ", name, " was not given (every field of bonded_joint_values "
                                                  "must be set; write 0 where 0 is meant)"));
  };
  given(v.k_n, "k_n (Pa/m)");
  given(v.k_s, "k_s (Pa/m)");
  given(v.tensile_strength, "tensile_strength f_T (Pa)");
  given(v.fracture_energy, "fracture_energy G_f (N/m)");
  given(v.cohesion, "cohesion c_0 (Pa)");
  given(v.residual_cohesion, "residual_cohesion c_res (Pa)");
  if (!v.friction)
    throw invalid_input(tessera::detail::concat(who, ": friction (phi_0) was not given (every field of "
                                                "bonded_joint_values must be set)"));
  if (!v.residual_friction)
    throw invalid_input(tessera::detail::concat(who, ": residual_friction (phi_res) was not given: it is the friction of "
                                                "a broken or slipped joint and of every contact detected contacts find "
                                                "after the start; write friction_angle::from_degrees(0) for a "
                                                "frictionless crack"));
  detail::require_joint_stiffness(v.k_n, who, "normal stiffness k_n");
  detail::require_joint_stiffness(v.k_s, who, "shear stiffness k_s");
  if (!(std::isfinite(v.tensile_strength) && v.tensile_strength > 0))
    throw invalid_input(tessera::detail::concat(who, ": tensile_strength f_T = ", v.tensile_strength,
                                                " Pa must be finite and > 0 (law::dry_joint has none)"));
  if (!(std::isfinite(v.cohesion) && v.cohesion >= 0))
    throw invalid_input(tessera::detail::concat(who, ": cohesion c_0 = ", v.cohesion, " Pa must be finite and >= 0"));
  if (!(v.residual_cohesion >= 0 && v.residual_cohesion <= v.cohesion))
    throw invalid_input(tessera::detail::concat(who, ": residual_cohesion c_res = ", v.residual_cohesion,
                                                " Pa must be in [0, cohesion c_0 = ", v.cohesion, " Pa]"));
  detail::require_joint_angle(*v.friction, who, "friction phi_0");
  detail::require_joint_angle(*v.residual_friction, who, "residual_friction phi_res");
  bonded_joint_law::params p;
  p.k_n = v.k_n;
  p.k_s = v.k_s;
  p.tension.f_T = v.tensile_strength;
  p.tension.G_f = v.fracture_energy;
  p.shear.c_0 = v.cohesion;
  p.shear.phi_0 = *v.friction;
  p.shear.c_res = v.residual_cohesion;
  p.shear.phi_res = *v.residual_friction;
  bonded_joint_law::validate(p);  // G_f > f_T^2/(2 k_n), named by the envelope's check
  return p;
}

}  // namespace tessera::law
