#pragma once
// Sub-contact kinematics, shared by every contact set (face_contacts, a detecting set) and by the
// contact laws: the relative motion of the two sides of a sub-contact over one step, its split
// into opening and slip, and the turn of a stored shear stress into a new contact plane.
//
// At one sub-contact with gridpoints (or material points) a on block A and b on block B, unit
// normal n from A to B (this step) and n_prev (last step), the increment of the relative
// displacement over the last step is
//     du = (v_b - v_a) dt  -  (n_prev x n) x (u_b - u_a)
// with velocities at t - dt/2 and displacements at t (docs/architecture.md). The first term is
// exactly u(t) - u(t - dt) for a constant step; the second removes, to first order, the part due
// to the rigid tilt of the contact plane acting on the current gap, so a rigidly turned open
// contact registers no spurious slip (face_contacts.hpp, "Kinematics", test "rigid rotation").
// Then
//     du_n = du . n   (m, + opens),      du_s = du - du_n n   (m, in the contact plane).
// The law turns the stored shear stress into the new plane (the tilt) but not about n, so the
// twist about n is deliberately left in du: for an elastic contact it turns tau with the blocks.
// Together, a rigid rotation of both blocks by any axis and total angle theta in steps dtheta
// leaves sigma_n and tau (turned with the blocks) unchanged up to a relative drift of order
// theta dtheta (test_contacts "rigid rotation": 2e-4 for 1.2 rad in 4000 steps; 33 % without the
// tilt term). The reference positions of a bonded pair coincide, so X_b - X_a is dropped from the
// gap; a detecting set whose pair points do not coincide passes the full current gap.
// For a point of a rigid body the velocity is v + omega x (x - x_c) (rigid_point_velocity).
// A contact law first turns its stored shear stress into the plane of the current n, keeping
// its magnitude (rotate_into_plane, templated on a scalar or a lanes::pack so the scalar and the
// packed law paths run the same code).
//
// Arithmetic: on scalars (`triple`), dots as (x + y) + z, term by term what face_contacts did
// inline before, so its results are unchanged to the bit. Everything is constexpr-free, noexcept,
// allocation-free and always inlined.
// Room: core/, below both the contact sets (contact/) and the laws (law/) that use it, so no
// include runs up the house; contact/kinematics.hpp forwards here for the contact room's readers.

#include "lanes.hpp"
#include "types.hpp"

namespace tessera::contact::kinematics {

/// A 3-vector as three scalars for the per-sub-contact loops: GCC keeps them in registers, where
/// a vec3 in Eigen's 2 + 1 SSE packets went through the stack and stalled on store forwarding.
struct triple {
  /** the components */ /**@{*/ real x, y, z; /**@}*/
};
[[nodiscard, gnu::always_inline]] inline triple cross(const triple& a, const triple& b) noexcept {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
[[nodiscard, gnu::always_inline]] inline real dot(const triple& a, const triple& b) noexcept {
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
[[nodiscard, gnu::always_inline]] inline triple minus(const triple& a, const triple& b) noexcept {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}

/// Velocity (m/s) of the point at offset r = x - x_c from the centre of a rigid body moving with
/// v and angular velocity omega (rad/s): v + omega x r.
[[nodiscard, gnu::always_inline]] inline triple rigid_point_velocity(const triple& v, const triple& omega,
                                                                    const triple& r) noexcept {
  const triple w = cross(omega, r);
  return {v.x + w.x, v.y + w.y, v.z + w.z};
}

/// First-order rotation vector of the contact plane from n_prev to n (rad): n_prev x n.
[[nodiscard, gnu::always_inline]] inline triple tilt(const triple& n_prev, const triple& n) noexcept {
  return cross(n_prev, n);
}

/// Increment of the relative displacement of B against A over the last step (m):
/// dv dt - tilt x gap, with dv = v_b - v_a (m/s) and gap = u_b - u_a (m).
[[nodiscard, gnu::always_inline]] inline triple relative_increment(const triple& dv, const triple& gap,
                                                                  const triple& tilt_vector, real dt) noexcept {
  const triple turn = cross(tilt_vector, gap);
  return {dv.x * dt - turn.x, dv.y * dt - turn.y, dv.z * dt - turn.z};
}

/// An increment split along the unit normal n: opening du_n (m, + opens) and slip du_s (m, in
/// the contact plane).
struct normal_split {
  real du_n;  ///< opening along n (m, + opens)
  triple du_s;  ///< slip in the contact plane (m)
};
[[nodiscard, gnu::always_inline]] inline normal_split split(const triple& du, const triple& n) noexcept {
  const real du_n = dot(du, n);
  return {du_n, {du.x - du_n * n.x, du.y - du_n * n.y, du.z - du_n * n.z}};
}

/// Turns the stored shear stress t into the plane of the unit normal n, keeping |t|: its
/// n-component is removed and the rest rescaled (a t parallel to n has no direction left and
/// becomes 0). T = real or a lanes::pack; dots as (x + y) + z.
template <class T>
[[gnu::always_inline]] inline void rotate_into_plane(T& t0, T& t1, T& t2, T n0, T n1, T n2) noexcept {
  const T tau_sq = (t0 * t0 + t1 * t1) + t2 * t2;
  const T along = (n0 * t0 + n1 * t1) + n2 * t2;
  const T o0 = t0 - n0 * along, o1 = t1 - n1 * along, o2 = t2 - n2 * along;
  const T in_plane_sq = (o0 * o0 + o1 * o1) + o2 * o2;
  const T keep = lanes::select(in_plane_sq > real(0), lanes::sqrt(tau_sq / in_plane_sq), T{});
  t0 = o0 * keep;
  t1 = o1 * keep;
  t2 = o2 * keep;
}

}  // namespace tessera::contact::kinematics
