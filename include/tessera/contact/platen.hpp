#pragma once
// contact::rigid_platen<Law>: a rigid steel plate pressed on a flat face of deformable blocks, its
// contact with them evaluated by the scene's contact law (DESIGN.md §2 "Materials": the
// plate-concrete pair). The loading and support plates of a bending test, the platens of a
// compression test.
//
// Geometry. The contact plane passes through `point` with unit normal `normal`, pointing from the
// platen into the body; the footprint is the rectangle |(x - point) . u| <= half_u,
// |(x - point) . w| <= half_w in it (u = axis_u, w = normal x u). The sub-contacts are the
// gridpoints of the surface triangles that lie on the plane (every corner within `tolerance` of
// it) and face the platen (outward normal . normal < 0), with the consistent nodal share of the
// part of each triangle inside the footprint: for the clipped polygon of area A_c and centroid C,
// node k of the triangle gets A_c N_k(C) (N_k its linear shape function; exact for a uniform
// traction). The areas sum to the covered part of the footprint, and a gridpoint just outside the
// footprint whose triangle reaches under the plate carries its share.
//
// Law. One Law::state per sub-contact, platen A -> gridpoint B along the platen's current normal,
// started from Law::unbonded_state (no tensile strength, friction only; a Law without it starts
// virgin, i.e. bonded): the pair is elastic-frictional and never cracks, so the plate lifts off
// freely where the body pulls away and slides at the Coulomb limit. Per step and sub-contact,
//     du = (v_gridpoint - v_platen(x)) dt,   du_n = du . n,   du_s = du - du_n n,
// then Law::update, and the force on the gridpoint f = -area (sigma_n n + tau), on the platen -f.
// The stored shear is turned with the normal by the law; the tilt correction of face_contacts is
// not applied, which is exact for the small rotations of a plate on a beam (spurious slip of
// order rotation^2).
//
// Motion. A rigid body with three translations and one rotation, theta about `hinge_axis` through
// the moving reference point: each translation component is either prescribed (set_velocity;
// zero by default) or free, and the rotation free when hinge_axis is not zero (a roller or a
// hinge); free components are integrated by central differences from the contact force with
// local damping (gamma |F| against the velocity; none at rest, where integrator::local_damping
// takes sgn(0) = +1: the same as rc_beam's hinged_plate), with the given mass and
// inertia raised, if needed, to keep the solver's step stable against the platen's contact
// stiffness (scale_to; `added_mass` reports by how much). The velocities live at half steps.
// With platen_motion::quasi_static the free components have no inertia instead: each update moves
// them to the equilibrium of the contact force at the body's present position (force over the
// contact stiffness), for a dynamic relaxation.
//
// Use with a solver of deformable blocks (solver::applied_forces): build it, attach(solver)
// (registers its gridpoints with their contact stiffness, solver::register_applied_forces, and
// sizes the platen's mass), then
// call update(solver) before every step, e.g. as an observer of solver::run:
//
//     contact::rigid_platen<Law> top(mesh, {{0, h, 0}, {0, -1, 0}, {1, 0, 0}, 0.025, 0.1}, motion, plate_params);
//     top.attach(s);
//     top.set_velocity({0, -rate, 0});
//     top.update(s);                       // forces for the first step
//     s.run(n, [&](auto& sv) { top.update(s); });
//     top.force();                         // on the platen from the body (N), the load cell
//
// The platen sets the applied-force rows of its own gridpoints (it owns them: two platens must
// not share a gridpoint). Deterministic and serial: O(sub-contacts) per step, nothing allocated.
// Its state is not part of the solver's checkpoint.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../law/concepts.hpp"

namespace tessera::contact {

/// Where a rigid_platen touches the body (see rigid_platen).
struct platen_geometry {
  vec3 point = vec3::Zero();    ///< a point of the contact plane: the footprint's centre and the hinge (m)
  vec3 normal = vec3::UnitZ();  ///< unit normal from the platen into the body
  vec3 axis_u = vec3::UnitX();  ///< unit, in the plane: the footprint's first side
  real half_u = 0;              ///< footprint half-length along axis_u (m)
  real half_w = 0;              ///< footprint half-length along normal x axis_u (m)
  real tolerance = 1e-9;        ///< distance from the plane of a surface triangle on it (m)
};

/// How a rigid_platen moves (see rigid_platen).
struct platen_motion {
  real mass = 1;                        ///< kg (free translations)
  real inertia = 1;                     ///< kg m^2 about the hinge axis
  std::array<bool, 3> free_translation{};  ///< world components integrated from the contact force
  vec3 hinge_axis = vec3::Zero();       ///< unit: turns freely about it; zero: does not turn
  real damping_gamma = 0.8;             ///< local damping of the free components, in [0, 1)
  /// The free components have no inertia: each update moves them by the contact force (moment)
  /// over their contact stiffness, sum max(k_n, k_s) a (about the axis: times the arm squared),
  /// one step of the platen's own equilibrium against the body's present position; mass, inertia
  /// and damping_gamma are then not used. For a dynamic relaxation (solver/relaxation.hpp), where
  /// a platen with inertia rings against the gridpoints under it between the resets (measured on
  /// rc_beam's plates, docs/performance.md); not for a dynamic run, whose platen has a mass.
  bool quasi_static = false;
};

namespace detail {
/// "(x, y, z)" for messages.
[[nodiscard]] inline std::string platen_text(const vec3& v) {
  return tessera::detail::concat("(", v.x(), ", ", v.y(), ", ", v.z(), ")");
}
}  // namespace detail

/// A rigid steel platen pressed on a face of the body through contact springs (file comment); refuses (invalid_input) a non-unit normal or axis, a non-positive half size, mass or inertia, naming them
template <law::ContactLaw Law>
class rigid_platen {
 public:
  using params_type = typename Law::params;  ///< the contact law's parameters
  using state_type = typename Law::state;  ///< the contact law's state per sub-contact

  /// Places the platen's sub-contacts on the gridpoints of the mesh under it; refuses bad geometry or motion (invalid_input naming the value)
  rigid_platen(const geometry::block_mesh& mesh, const platen_geometry& g, const platen_motion& m,
               const params_type& p)
      : geometry_(g), motion_(m), params_(p) {
    Law::validate(p);
    require(std::abs(g.normal.norm() - 1) < 1e-9 && std::abs(g.axis_u.norm() - 1) < 1e-9 &&
                std::abs(g.normal.dot(g.axis_u)) < 1e-9,
            "rigid_platen: normal ", detail::platen_text(g.normal), " and axis_u ", detail::platen_text(g.axis_u),
            " must be orthogonal unit vectors");
    require(std::isfinite(g.half_u) && g.half_u > 0 && std::isfinite(g.half_w) && g.half_w > 0,
            "rigid_platen: footprint half-lengths ", g.half_u, " x ", g.half_w, " m must be finite and > 0");
    require(std::isfinite(g.tolerance) && g.tolerance >= 0, "rigid_platen: tolerance ", g.tolerance,
            " m must be finite and >= 0");
    require(std::isfinite(m.mass) && m.mass > 0 && std::isfinite(m.inertia) && m.inertia > 0, "rigid_platen: mass ",
            m.mass, " kg and inertia ", m.inertia, " kg m^2 must be finite and > 0");
    require(m.damping_gamma >= 0 && m.damping_gamma < 1, "rigid_platen: damping_gamma = ", m.damping_gamma,
            " must lie in [0, 1)");
    const real hinge = m.hinge_axis.norm();
    require(hinge == 0 || std::abs(hinge - 1) < 1e-9, "rigid_platen: hinge_axis ", detail::platen_text(m.hinge_axis),
            " must be a unit vector or zero");
    collect(mesh);
    require(!node_.empty(), "rigid_platen: no surface triangle of the mesh lies on the plane through ",
            detail::platen_text(g.point), " with normal ", detail::platen_text(g.normal), " under the ", 2 * g.half_u,
            " x ", 2 * g.half_w, " m footprint");
    for (std::size_t j = 0; j < node_.size(); ++j) {
      const real k = contact_stiffness() * area_[j];
      k_translation_ += k;
      if (m.hinge_axis != vec3::Zero()) k_rotation_ += k * (reference_[j] - g.point).cross(m.hinge_axis).squaredNorm();
    }
    state_.resize(node_.size());
    for (state_type& s : state_) {
      if constexpr (requires { Law::unbonded_state(p); })
        s = Law::unbonded_state(p);
      else
        s = state_type{};
    }
  }

  /// Registers the platen with a solver of deformable blocks: its gridpoints, each with its
  /// sub-contact's stiffness max(k_n, k_s) x area (solver::register_applied_forces, which
  /// recomputes the step), then the
  /// platen's mass and inertia raised to keep that step stable (scale_to).
  template <class Solver>
  void attach(Solver& s) {
    std::vector<index_t> nodes(node_.begin(), node_.end());
    std::vector<real> k(node_.size());
    const real kmax = contact_stiffness();
    for (std::size_t j = 0; j < node_.size(); ++j) k[j] = kmax * area_[j];
    s.register_applied_forces(std::span<const index_t>(nodes), std::span<const real>(k));
    scale_to(s.dt(), s.options().safety, s.stiffness_amplification());
  }

  /// Raises the mass and inertia where the platen's contact stiffness needs it for the step dt
  /// to be `safety` x its critical step (2 sqrt(m / (a k)), a the damping's amplification).
  void scale_to(real dt, real safety, real amplification) {
    require(dt > 0 && safety > 0 && amplification > 0, "rigid_platen: scale_to(dt = ", dt, ", safety = ", safety,
            ", amplification = ", amplification, ") needs positive values");
    // m >= a k (dt / (2 safety))^2, k the contact stiffness (about the axis: forces of stiffness
    // max(k_n, k_s) at their arms' distance)
    const real factor = amplification * std::pow(dt / (2 * safety), 2);
    const real m_needed = factor * k_translation_, i_needed = factor * k_rotation_;
    if (m_needed > mass_) added_mass_ += m_needed - mass_, mass_ = m_needed;
    if (i_needed > inertia_) added_inertia_ += i_needed - inertia_, inertia_ = i_needed;
  }

  /// Velocity (m/s) of the prescribed translation components over the steps that follow the
  /// next update (the free components ignore it).
  void set_velocity(const vec3& v) {
    require(v.allFinite(), "rigid_platen: velocity ", detail::platen_text(v), " m/s is not finite");
    prescribed_ = v;
  }

  /// The contact forces of the solver's current state on the gridpoints (written into
  /// s.applied_forces()), then the platen advanced by one step s.dt(). Call before every step.
  template <class Solver>
  void update(Solver& s) {
    update(s.gridpoints(), s.applied_forces(), s.dt());
  }
  void update(const node_set& gp, soa3& applied, real dt) noexcept {  ///< Contact forces for this step into applied (N), then the platen advanced by dt (s)
    const vec3 n = current_normal();
    const vec3 c = geometry_.point + displacement_;
    const vec3 e = motion_.hinge_axis;
    vec3 total = vec3::Zero();
    real moment = 0;
    for (std::size_t j = 0; j < node_.size(); ++j) {
      const index_t g = node_[j];
      const vec3 x = gp.position(g);
      const vec3 v_platen = velocity_ + omega_ * e.cross(x - c);
      const vec3 du = (gp.velocity.row(g).transpose() - v_platen) * dt;
      const real du_n = du.dot(n);
      state_type& st = state_[j];
      Law::update(params_, st, du_n, vec3(du - du_n * n), n);
      const vec3 f = -area_[j] * (st.sigma_n * n + st.tau);  // on the gridpoint
      applied.row(g) = f.transpose();
      total -= f;
      moment -= (x - c).cross(f).dot(e);
    }
    force_ = total;
    moment_ = moment;
    // The platen: free components from the force at t to the velocity at t + dt/2.
    const auto damped = [&](real f, real v) {
      const real sign = v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
      return f - motion_.damping_gamma * std::abs(f) * sign;
    };
    const bool still = motion_.quasi_static;  // no inertia: to the equilibrium of this position
    for (int k = 0; k < 3; ++k)
      velocity_[k] = !motion_.free_translation[static_cast<std::size_t>(k)] ? prescribed_[k]
                     : still ? total[k] / (k_translation_ * dt)
                             : velocity_[k] + dt * damped(total[k], velocity_[k]) / mass_;
    if (e != vec3::Zero()) omega_ = still ? moment / (k_rotation_ * dt) : omega_ + dt * damped(moment, omega_) / inertia_;
    displacement_ += velocity_ * dt;
    rotation_ += omega_ * dt;
  }

  // ---- read-out ----
  /// Force on the platen from the body at the last update (N): the load cell.
  [[nodiscard]] const vec3& force() const { return force_; }
  /// Moment on the platen about its hinge axis at the last update (N m).
  [[nodiscard]] real moment() const { return moment_; }
  /// Displacement of the reference point (m) and rotation about the hinge axis (rad) after the
  /// last update; their rates (m/s, rad/s) at the half step.
  [[nodiscard]] const vec3& displacement() const { return displacement_; }
  [[nodiscard]] real rotation() const { return rotation_; }  ///< Rotation about the hinge (rad)
  [[nodiscard]] const vec3& velocity() const { return velocity_; }  ///< Velocity of the reference point (m/s)
  [[nodiscard]] real rotation_rate() const { return omega_; }  ///< Rotation rate (rad/s)
  /// The current unit normal (from the platen into the body).
  [[nodiscard]] vec3 current_normal() const {
    const vec3& n0 = geometry_.normal;
    const vec3& e = motion_.hinge_axis;
    if (e == vec3::Zero() || rotation_ == 0) return n0;
    const real cs = std::cos(rotation_), sn = std::sin(rotation_);
    return n0 * cs + e.cross(n0) * sn + e * e.dot(n0) * (1 - cs);  // Rodrigues
  }
  [[nodiscard]] std::size_t size() const { return node_.size(); }  ///< Number of sub-contacts
  [[nodiscard]] index_t node(std::size_t j) const { return node_[j]; }  ///< Gridpoint of sub-contact j
  [[nodiscard]] real area(std::size_t j) const { return area_[j]; }  ///< Tributary area of sub-contact j (m^2)
  [[nodiscard]] real total_area() const {  ///< Contact area (m^2)
    real a = 0;
    for (real x : area_) a += x;
    return a;
  }
  [[nodiscard]] const state_type& state(std::size_t j) const { return state_[j]; }  ///< Law state of sub-contact j
  /// Sub-contacts in contact (sigma_n < 0) at the last update.
  [[nodiscard]] std::size_t in_contact() const {
    return static_cast<std::size_t>(
        std::count_if(state_.begin(), state_.end(), [](const state_type& s) { return s.sigma_n < 0; }));
  }
  /// Energy stored in, and dissipated by, the platen's contact springs (J).
  [[nodiscard]] real stored_energy() const {
    real e = 0;
    for (std::size_t j = 0; j < node_.size(); ++j) e += area_[j] * Law::stored_energy(params_, state_[j]);
    return e;
  }
  [[nodiscard]] real dissipated_energy() const {  ///< Energy dissipated (J)
    real e = 0;
    for (std::size_t j = 0; j < node_.size(); ++j) e += area_[j] * Law::dissipated_energy(state_[j]);
    return e;
  }
  [[nodiscard]] real mass() const { return mass_; }  ///< Mass (kg)
  [[nodiscard]] real inertia() const { return inertia_; }  ///< Rotary inertia about the hinge (kg m^2)
  /// Mass (kg) and inertia (kg m^2) added by scale_to.
  [[nodiscard]] real added_mass() const { return added_mass_; }
  [[nodiscard]] real added_inertia() const { return added_inertia_; }  ///< Inertia added by scale_to (kg m^2)

  /// Saves or loads the platen's evolving state through a checkpoint archive (io/checkpoint.hpp)
  /// under "<prefix>/...": its sub-contacts' law states (the law's declared fields), its motion
  /// (velocity, prescribed velocity, displacement, rotation and rate) and the last update's force
  /// and moment. The footprint's gridpoints and the masses set by scale_to must be the file's (a
  /// platen built on another face or with another step is refused). Save it beside the solver's
  /// own checkpoint (the solver keeps the forces the platen wrote for the next step), with the
  /// same archive, so both restart to the same bits.
  template <class Archive>
  void checkpoint(Archive& ar, const std::string& prefix) {
    static_assert(law::DeclaresStateFields<Law>, "checkpoints need a law that declares state_fields");
    ar.same(prefix + "/subcontacts", static_cast<std::int64_t>(node_.size()));
    std::int64_t first = node_.empty() ? -1 : node_.front(), last = node_.empty() ? -1 : node_.back();
    ar.same(prefix + "/first_gridpoint", first);
    ar.same(prefix + "/last_gridpoint", last);
    ar.same(prefix + "/mass", mass_);
    ar.same(prefix + "/inertia", inertia_);
    law::checkpoint_states<Law>(
        ar, prefix + "/state/", node_.size(), [&](std::size_t j) { return state_[j]; },
        [&](std::size_t j, const state_type& st) { state_[j] = st; });
    ar.scalar(prefix + "/velocity", velocity_);
    ar.scalar(prefix + "/prescribed_velocity", prescribed_);
    ar.scalar(prefix + "/displacement", displacement_);
    ar.scalar(prefix + "/force", force_);
    ar.scalar(prefix + "/rotation_rate", omega_);
    ar.scalar(prefix + "/rotation", rotation_);
    ar.scalar(prefix + "/moment", moment_);
  }

 private:
  /// The stiffness per unit area that bounds a sub-contact's springs, max(k_n, k_s) (Pa/m).
  [[nodiscard]] real contact_stiffness() const {
    return std::max(Law::normal_stiffness(params_), Law::shear_stiffness(params_));
  }
  /// The sub-contacts: the nodal shares of the surface triangles on the plane, clipped to the
  /// footprint (file comment), in increasing gridpoint order.
  void collect(const geometry::block_mesh& mesh) {
    const vec3& n = geometry_.normal;
    const vec3& u = geometry_.axis_u;
    const vec3 w = n.cross(u);
    std::map<index_t, real> share;
    const auto on_plane = [&](const vec3& x) { return std::abs((x - geometry_.point).dot(n)) <= geometry_.tolerance; };
    for (const auto& tri : mesh.face_triangles) {
      const vec3& a = mesh.gridpoints[static_cast<std::size_t>(tri[0])];
      const vec3& b = mesh.gridpoints[static_cast<std::size_t>(tri[1])];
      const vec3& c = mesh.gridpoints[static_cast<std::size_t>(tri[2])];
      if (!on_plane(a) || !on_plane(b) || !on_plane(c) || (b - a).cross(c - a).dot(n) >= 0) continue;
      // In-plane coordinates, clipped by the footprint's four half-planes (Sutherland-Hodgman).
      std::vector<std::array<real, 2>> poly;
      for (const vec3* p : {&a, &b, &c}) poly.push_back({(*p - geometry_.point).dot(u), (*p - geometry_.point).dot(w)});
      const std::array<std::array<real, 3>, 4> planes{{{1, 0, geometry_.half_u},
                                                      {-1, 0, geometry_.half_u},
                                                      {0, 1, geometry_.half_w},
                                                      {0, -1, geometry_.half_w}}};  // s . p <= h
      for (const auto& pl : planes) {
        std::vector<std::array<real, 2>> out;
        for (std::size_t i = 0; i < poly.size(); ++i) {
          const auto& p = poly[i];
          const auto& q = poly[(i + 1) % poly.size()];
          const real dp = pl[0] * p[0] + pl[1] * p[1] - pl[2], dq = pl[0] * q[0] + pl[1] * q[1] - pl[2];
          if (dp <= 0) out.push_back(p);
          if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) {
            const real t = dp / (dp - dq);
            out.push_back({p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])});
          }
        }
        poly = std::move(out);
        if (poly.size() < 3) break;
      }
      if (poly.size() < 3) continue;
      // Area and centroid of the clipped polygon (shoelace).
      real area2 = 0, cx = 0, cy = 0;
      for (std::size_t i = 0; i < poly.size(); ++i) {
        const auto& p = poly[i];
        const auto& q = poly[(i + 1) % poly.size()];
        const real cr = p[0] * q[1] - q[0] * p[1];
        area2 += cr;
        cx += (p[0] + q[0]) * cr;
        cy += (p[1] + q[1]) * cr;
      }
      if (std::abs(area2) <= 0) continue;
      const real clipped = 0.5 * std::abs(area2);
      cx /= 3 * area2;
      cy /= 3 * area2;
      // Barycentric coordinates of the centroid in the triangle (in-plane).
      const std::array<real, 2> A{(a - geometry_.point).dot(u), (a - geometry_.point).dot(w)};
      const std::array<real, 2> B{(b - geometry_.point).dot(u), (b - geometry_.point).dot(w)};
      const std::array<real, 2> C{(c - geometry_.point).dot(u), (c - geometry_.point).dot(w)};
      const real det = (B[0] - A[0]) * (C[1] - A[1]) - (C[0] - A[0]) * (B[1] - A[1]);
      const real lb = ((cx - A[0]) * (C[1] - A[1]) - (C[0] - A[0]) * (cy - A[1])) / det;
      const real lc = ((B[0] - A[0]) * (cy - A[1]) - (cx - A[0]) * (B[1] - A[1])) / det;
      const std::array<real, 3> N{1 - lb - lc, lb, lc};
      for (int k = 0; k < 3; ++k)
        if (N[static_cast<std::size_t>(k)] * clipped > 0) share[tri[static_cast<std::size_t>(k)]] += N[static_cast<std::size_t>(k)] * clipped;
    }
    for (const auto& [g, a] : share) {
      node_.push_back(g);
      area_.push_back(a);
      reference_.push_back(mesh.gridpoints[static_cast<std::size_t>(g)]);
    }
  }

  platen_geometry geometry_;
  platen_motion motion_;
  params_type params_;
  std::vector<index_t> node_;
  std::vector<real> area_;
  std::vector<vec3> reference_;
  std::vector<state_type> state_;
  real mass_ = motion_.mass, inertia_ = motion_.inertia, added_mass_ = 0, added_inertia_ = 0;
  real k_translation_ = 0, k_rotation_ = 0;  ///< sum of max(k_n, k_s) a (N/m); about the axis, x arm^2 (N m)
  vec3 velocity_ = vec3::Zero(), prescribed_ = vec3::Zero(), displacement_ = vec3::Zero(), force_ = vec3::Zero();
  real omega_ = 0, rotation_ = 0, moment_ = 0;
};

}  // namespace tessera::contact
