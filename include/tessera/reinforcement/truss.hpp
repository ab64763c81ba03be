#pragma once
// Axial law of one 2-node truss element (study eq. 7-8): elastic-perfectly plastic, same yield
// force in tension and compression, no rupture.
//
//   K_axial = E_s A / L_el                                  (eq. 8)
//   N = K_axial (e - e_p),  |N| <= N_y = f_y A              (N > 0 in tension)
//
// e is the total elongation (current chord length - reference length), e_p the plastic elongation.
// The law is written in total form with a return mapping: a trial force beyond N_y is brought back
// to +-N_y and e_p absorbs the excess. Plastic flow happens only at |N| = N_y, so the energy
// dissipated in a step, N Delta e_p, is exact (not an approximation of the path). The element
// axis is the current chord direction, so the law holds for large rotations of the element.

#include <cmath>
#include <string>
#include <vector>

#include "../core/types.hpp"
#include "detail/plastic_spring.hpp"

namespace tessera::reinforcement {

/// A steel truss element between two bar nodes: elastic-perfectly plastic in tension and compression
struct truss_element {
  /// History of one element; value-initialised = virgin element.
  struct state {
    real axial_force = 0.0;         ///< N (N), tension positive
    real plastic_elongation = 0.0;  ///< e_p (m), tension positive
    real dissipated = 0.0;          ///< plastic work so far (J)
    bool yielding = false;          ///< on the yield plateau at the last update
    bool has_yielded = false;       ///< reached the yield force at least once
  };
  // Three reals and two flags (padded to a fourth real): a field added to `state` must be added
  // to checkpoint_fields.
  static_assert(sizeof(state) == 4 * sizeof(real), "truss_element::state changed: update checkpoint_fields");
  /// Every field of `state`, for a checkpoint archive (io/checkpoint.hpp); a field added to
  /// `state` must be added here.
  template <class Archive>
  static void checkpoint_fields(Archive& ar, const std::string& prefix, std::vector<state>& s) {
    ar.members(prefix + "axial_force", s, &state::axial_force);
    ar.members(prefix + "plastic_elongation", s, &state::plastic_elongation);
    ar.members(prefix + "dissipated", s, &state::dissipated);
    ar.members(prefix + "yielding", s, &state::yielding);
    ar.members(prefix + "has_yielded", s, &state::has_yielded);
  }

  /// Cancellation-free elongation e = |d0 + du| - |d0| (m) of a chord with reference vector d0
  /// and relative end displacement du = u_b - u_a: e = (2 d0.du + du.du) / (|d0 + du| + |d0|).
  [[nodiscard]] static real elongation(const vec3& reference_chord, real reference_length, const vec3& relative_displacement,
                                       real current_length) noexcept {
    return (2.0 * reference_chord.dot(relative_displacement) + relative_displacement.squaredNorm()) /
           (current_length + reference_length);
  }

  /// Return mapping for total elongation e (m): sets N, e_p, the yielding flag and adds the
  /// dissipated increment 0.5 (N_old + N_new) Delta e_p (J).
  static void update(state& s, real elongation, real axial_stiffness, real yield_force) noexcept {
    const detail::plastic_return r =
        detail::elastic_perfectly_plastic(elongation, s.plastic_elongation, axial_stiffness, yield_force);
    if (r.limited) {
      s.plastic_elongation += r.plastic_increment;
      s.dissipated += 0.5 * (s.axial_force + r.force) * r.plastic_increment;
      s.has_yielded = true;
    }
    s.axial_force = r.force;
    s.yielding = r.limited;
  }

  /// Recoverable elastic energy N^2 / (2 K_axial) (J).
  [[nodiscard]] static real stored_energy(const state& s, real axial_stiffness) noexcept {
    return 0.5 * s.axial_force * s.axial_force / axial_stiffness;
  }
};

}  // namespace tessera::reinforcement
