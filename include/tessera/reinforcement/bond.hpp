#pragma once
// coulomb_bond: the steel-concrete bond law of the study (eq. 7, 9), a Coulomb-slip spring along
// the bar axis, elastic-perfectly plastic:
//
//   K_bond = xi K_axial                                         (eq. 9, per node, see below)
//   F_a = K_bond (s - s_p),  |F_a| <= F_max                     (eq. 7)
//   F_max = (c_bond + sigma_conf tan(phi_bond) * perimeter) * L_trib
//
// s = slip of the bar node relative to its host point along the bar axis (m), s_p its plastic part,
// F_a the bond force (N; the force on the bar node is -F_a a, on the host +F_a a). c_bond is a
// cohesion per unit bar length (N/m), sigma_conf the confining stress of the host zone normal to the
// bar (Pa, compression positive, never negative), phi_bond the bond friction angle (rad) and L_trib
// the tributary bar length of the node (m). A limit that drops below the current force (confinement
// lost) produces plastic slip as well. The dissipated increment of a step is
// 0.5 (F_old + F_new) Delta s_p, the trapezoidal work minus the change of the spring's energy, as in
// the contact laws and truss.hpp: exact on the plateau, energy-consistent with a trapezoidal work
// integral always (a limit that drops at fixed slip dissipates exactly the released spring energy).
//
// The per-node stiffness is given to the law by embedded_truss from xi and the stiffness basis:
//
//   per_node         K_bond,n = (xi/2) sum_adjacent K_axial        (xi K_axial on interior nodes)
//   per_unit_length  K_bond,n = (xi/2) sum_adjacent K_axial L_el   (bond modulus xi K_axial in
//                                                                    N/m per m of bar, lumped)
//
// DESIGN.md reads eq. 9 per node. The study's own numbers fit the second reading: it quotes
// K_bond = 6.19 "GPa" (N/m^2, 3DEC's cable grout stiffness is a force per unit length per unit
// slip) next to c_bond in N/m of bar, and with a per-node 6.19 GN/m the bond transfer length
// 1/lambda = sqrt(E_s A L_el / K_bond) is 3 mm, so a crack in the tie can open only by the
// stretch of the one element spanning it (~20 um at yield) and never opens fully; per unit
// length the transfer length is 40 mm and the study's load drops appear (docs/model.md §3).

#include <cmath>
#include <string>
#include <vector>
#include <numbers>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "detail/plastic_spring.hpp"

namespace tessera::reinforcement {

/// How the bond stiffness ratio xi = K_bond / K_axial (study eq. 9) turns into a spring per node.
enum class stiffness_basis {
  per_node,         ///< K_bond,n = xi K_axial (N/m) at an interior node (DESIGN.md's reading)
  per_unit_length,  ///< xi K_axial is a bond modulus in N/m per m of bar (3DEC cable grout stiffness)
};

/// Coulomb bond-slip of a bar node to its host zone (study eq. 9): elastic K_bond = xi K_axial up to c_bond, then sliding
struct coulomb_bond {
  /// xi, c_bond and the stiffness basis (validate refuses each out of range, naming it)
  struct params {
    real stiffness_ratio = 4.0;  ///< xi = K_bond / K_axial (-), eq. 9; the study uses 4
    real cohesion = 1e9;         ///< c_bond (N/m of bar length); 1e9 = the study's "perfect bond"
    real friction_angle = 0.0;   ///< phi_bond (rad), in [0, pi/2); multiplies the confining stress
    stiffness_basis basis = stiffness_basis::per_node;  ///< how xi K_axial becomes a nodal spring
  };
  /// History of one bar node; value-initialised = virgin bond.
  struct state {
    real slip = 0.0;          ///< s (m), bar node relative to its host point along the bar axis
    real plastic_slip = 0.0;  ///< s_p (m)
    real force = 0.0;         ///< F_a (N); the force on the bar node along the axis is -F_a
    real dissipated = 0.0;    ///< work of plastic slip so far (J)
    bool slipping = false;    ///< at the Coulomb limit at the last update
    bool has_slipped = false; ///< reached the Coulomb limit at least once
  };
  // Four reals and two flags (padded to a fifth real): a field added to `state` must be added
  // to checkpoint_fields.
  static_assert(sizeof(state) == 5 * sizeof(real), "coulomb_bond::state changed: update checkpoint_fields");
  /// Every field of `state`, for a checkpoint archive (io/checkpoint.hpp); a field added to
  /// `state` must be added here.
  template <class Archive>
  static void checkpoint_fields(Archive& ar, const std::string& prefix, std::vector<state>& s) {
    ar.members(prefix + "slip", s, &state::slip);
    ar.members(prefix + "plastic_slip", s, &state::plastic_slip);
    ar.members(prefix + "force", s, &state::force);
    ar.members(prefix + "dissipated", s, &state::dissipated);
    ar.members(prefix + "slipping", s, &state::slipping);
    ar.members(prefix + "has_slipped", s, &state::has_slipped);
  }

  static void validate(const params& p) {  ///< Refuses (invalid_input) xi <= 0, c_bond < 0 or a friction angle outside [0, pi/2), naming the value
    require_positive(p.stiffness_ratio, "coulomb_bond: bond stiffness ratio xi = K_bond / K_axial (-)");
    require_non_negative(p.cohesion, "coulomb_bond: bond cohesion c_bond (N/m)");
    require(p.friction_angle >= 0.0 && p.friction_angle < std::numbers::pi / 2.0,
            "coulomb_bond: bond friction angle phi_bond = ", p.friction_angle, " rad must be in [0, pi/2)");
  }
  [[nodiscard]] static real stiffness_ratio(const params& p) noexcept { return p.stiffness_ratio; }  ///< xi (-)
  /// True when xi K_axial is a modulus per unit bar length (N/m^2) rather than a nodal spring (N/m).
  [[nodiscard]] static bool stiffness_per_unit_length(const params& p) noexcept {
    return p.basis == stiffness_basis::per_unit_length;
  }

  /// F_max (N) of a node with tributary length L_trib (m) on a bar of perimeter pi d (m) under a
  /// confining stress sigma_conf (Pa, compression positive, >= 0).
  [[nodiscard]] static real strength(const params& p, real confining_stress, real perimeter,
                                     real tributary_length) noexcept {
    return (p.cohesion + confining_stress * std::tan(p.friction_angle) * perimeter) * tributary_length;
  }

  /// Return mapping for the total slip s (m) with stiffness K_bond (N/m) and limit F_max (N).
  static void update(const params&, state& st, real slip, real stiffness, real strength) noexcept {
    st.slip = slip;
    const detail::plastic_return r = detail::elastic_perfectly_plastic(slip, st.plastic_slip, stiffness, strength);
    if (r.limited) {
      st.plastic_slip += r.plastic_increment;
      st.dissipated += 0.5 * (st.force + r.force) * r.plastic_increment;
      st.has_slipped = true;
    }
    st.force = r.force;
    st.slipping = r.limited;
  }

  /// Recoverable energy of the axial bond spring F_a^2 / (2 K_bond) (J).
  [[nodiscard]] static real stored_energy(const state& st, real stiffness) noexcept {
    return 0.5 * st.force * st.force / stiffness;
  }
  [[nodiscard]] static real dissipated_energy(const state& st) noexcept { return st.dissipated; }  ///< Energy dissipated by slip (J)
};

}  // namespace tessera::reinforcement
