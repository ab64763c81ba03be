#pragma once
// The step of detected_contacts' sub-contacts between rebuilds (contact/detected_contacts.hpp,
// run_task): each pair's normals turned with its blocks, then each sub-contact's relative motion,
// law update and force, handed to the frame gridpoints.
//
// The pair's unit normal n turns with the feature the plane came from: a face of A (R_a n0), a
// face of B (-R_b n0), or an edge of each (R_a e_a x R_b e_b), R = the block's rotation from its
// frame (detected/frames.hpp; deformable blocks: face normals through F^-T, edges through F). A
// pair keeps three normals: the plane's, and those of A's and B's faces parallel to the plane,
// which push B's and A's vertices. Then, as for face_contacts (kinematics.hpp), du = (v_b(p) -
// v_a(p)) dt - (n_prev x n) x (x_b(p) - x_a(p)), split along n, Law::update, and the force area
// (sigma_n n + tau) on A's side (B gets its opposite), handed to the frame gridpoints with the
// weights w: resultant and moment about any point are exact. Each pair sums its sub-contacts'
// shares per frame gridpoint (eight sums), which the gather reads.
//
// Cost: O(sub-contacts of the pair), no allocation. Thread safety: a pair writes only its own
// normals, sub-contacts and frame-gridpoint sums, so distinct pairs may run on distinct threads.
//
// Definitions of detected_contacts<Law>'s members of the step (declared in the class); it includes the
// class and the class includes it, so either header can come first.

#include <algorithm>
#include <array>
#include <cstddef>
#include <iterator>

#include "../../core/nodes.hpp"
#include "../../core/parallel.hpp"
#include "../../core/types.hpp"
#include "../kinematics.hpp"
#include "../detected_contacts.hpp"
#include "refusals.hpp"

namespace tessera::contact {

/// Normal j of pair k now (0 the plane's feature, 1 A's parallel face, 2 B's), from the
/// blocks' motions: face normals through normal_map, edges through rotation.
template <law::ContactLaw Law>
[[nodiscard]] inline typename detected_contacts<Law>::triple detected_contacts<Law>::pair_normal(
    std::size_t k, int j, const block_motion& ma, const block_motion& mb) const {
  vec3 n;
  if (j == 1 && side_a_[k].squaredNorm() > 0) {
    n = ma.normal_map * side_a_[k];
  } else if (j == 2 && side_b_[k].squaredNorm() > 0) {
    n = -(mb.normal_map * side_b_[k]);
  } else {
    switch (feature_[k]) {
      case feature_kind::face_a: n = ma.normal_map * feature_a_[k]; break;
      case feature_kind::face_b: n = -(mb.normal_map * feature_b_[k]); break;
      default: n = (ma.rotation * feature_a_[k]).cross(mb.rotation * feature_b_[k]);
    }
  }
  const real len = n.norm();
  const auto row = static_cast<index_t>(k);
  if (!(len > 0)) return {normal_[at(j)](row, 0), normal_[at(j)](row, 1), normal_[at(j)](row, 2)};
  return {n.x() / len, n.y() / len, n.z() / len};
}

/// Whether normal j (1 or 2) of pair k is the plane's normal to the bit: the pair has no face
/// parallel to the plane on that side (pair_normal takes the feature's branch), or the
/// parallel face is the plane's own feature (a face pair: the same body-frame vector through
/// the same map). The rebuild starts such a normal from the plane's.
template <law::ContactLaw Law>
[[nodiscard]] inline bool detected_contacts<Law>::normal_is_plane(std::size_t k, int j) const noexcept {
  if (j == 1)
    return side_a_[k].squaredNorm() == 0 || (feature_[k] == feature_kind::face_a && side_a_[k] == feature_a_[k]);
  return side_b_[k].squaredNorm() == 0 || (feature_[k] == feature_kind::face_b && side_b_[k] == feature_b_[k]);
}

/// The largest squared move (m^2) of block b's watched gridpoints since it was last detected.
template <law::ContactLaw Law>
[[nodiscard]] inline real detected_contacts<Law>::moved2_of(std::size_t b, const node_set& gp) const noexcept {
  const real* u[3] = {gp.displacement.col(0).data(), gp.displacement.col(1).data(), gp.displacement.col(2).data()};
  const block_data& bd = blocks_[b];
  real m2 = 0;
  for (index_t k = bd.watch_begin; k < bd.watch_end; ++k) {
    const auto g = at(watch_gridpoints_[at(k)]);
    const real dx = u[0][g] - rebuild_u_(k, 0), dy = u[1][g] - rebuild_u_(k, 1), dz = u[2][g] - rebuild_u_(k, 2);
    m2 = std::max(m2, (dx * dx + dy * dy) + dz * dz);
  }
  return m2;
}

/// prepare_step (declared, with what it does, in the class).
template <law::ContactLaw Law>
inline void detected_contacts<Law>::prepare_step(const node_set& gridpoints, real /*dt*/) {
  ++steps_since_rebuild_;
  const bool vote = static_cast<bool>(largest_motion_) && !own_block_.empty();
  // Rigid blocks outside a split run: first a bound per block from its four frame vertices
  // (detail::moved_bound); while every bound stays below 0.9 x the trigger (a margin far above
  // the bound's round-off), no vertex can have reached the trigger and its exact move is not
  // needed: no rebuild, no refusal, the same steps as the test over every vertex. Once a bound
  // passes that, every block's exact move until the next rebuild (a scene in motion does not
  // pay for both), as below; the exact moves also at a rebuild of the interval.
  const real tol = options_.tolerance;
  if (!options_.deformable_blocks && !largest_motion_ && !before_rebuild_ && bound_passed_at_ != rebuilds_) {
    parallel_for(
        static_cast<std::int64_t>(blocks_.size()),
        [&](std::int64_t b) {
          detail::motion_into(motion_[at(b)], reference_, blocks_[at(b)], gridpoints, false);
          moved_bound_[at(b)] = detail::moved_bound(blocks_[at(b)], gridpoints, rebuild_u_);
        },
        64);
    const real limit = 0.9 * detail::trigger_fraction * tol;
    bool below = true;
    for (const real m : moved_bound_) below = below && m <= limit;  // false for NaN too
    if (below && steps_since_rebuild_ < options_.max_rebuild_interval) return;
    if (!below) bound_passed_at_ = rebuilds_;
    parallel_for(
        static_cast<std::int64_t>(blocks_.size()), [&](std::int64_t b) { moved_[at(b)] = moved2_of(at(b), gridpoints); },
        64);
  } else {
    // Per block, in one parallel loop: its affine motion this step (the pairs read it, rather
    // than gathering the four frame gridpoints of both blocks at every corner) and how far its
    // watched gridpoints moved since it was last detected (a rebuild leaves the motion as it is).
    // A split run's vote (set_motion_vote) watches the own blocks; the ranks reduce the largest.
    parallel_for(
        static_cast<std::int64_t>(blocks_.size()),
        [&](std::int64_t b) {
          detail::motion_into(motion_[at(b)], reference_, blocks_[at(b)], gridpoints, options_.deformable_blocks);
          moved_[at(b)] = !vote || own_block_[at(b)] != 0 ? moved2_of(at(b), gridpoints) : real(0);
        },
        64);
  }
  real moved2 = moved_.empty() ? real(0) : *std::max_element(moved_.begin(), moved_.end());
  if (largest_motion_) moved2 = largest_motion_(moved2);
  // Rigid blocks: the incremental trigger (detected/incremental.hpp). Deformable blocks: every
  // block at tolerance / 2; detection read each block's affine fit, within max_deviation_ of
  // its surface gridpoints, so the trigger keeps that much in reserve.
  const real trigger = options_.deformable_blocks ? 0.5 * tol - max_deviation_ : detail::trigger_fraction * tol;
  // Past the tolerance (deformable: twice the trigger), one step covered more than the tolerance
  // less the trigger: refuse (detected/refusals.hpp).
  const real refuse = options_.deformable_blocks ? 2 * trigger : tol;
  if (trigger > 0 && moved2 > refuse * refuse)
    detail::refuse_fast_motion(moved_, moved2, steps_since_rebuild_, tol, trigger);
  const bool interval = steps_since_rebuild_ >= options_.max_rebuild_interval;
  if (moved2 > trigger * trigger || interval) {
    if (before_rebuild_) {
      // A split run's copies of other ranks' blocks are current now: their motions again.
      before_rebuild_();
      parallel_for(static_cast<std::int64_t>(blocks_.size()), [&](std::int64_t b) {
        detail::motion_into(motion_[at(b)], reference_, blocks_[at(b)], gridpoints, options_.deformable_blocks);
        moved_[at(b)] = moved2_of(at(b), gridpoints);
      }, 64);
    }
    rebuild(&gridpoints, interval || options_.deformable_blocks);
  }
}

/// The pair's three normals now (stored for the next step) and their tilts since the last.
template <law::ContactLaw Law>
inline void detected_contacts<Law>::turn_normals(std::size_t k, std::array<triple, 3>& normals,
                                                 std::array<triple, 3>& tilts) noexcept {
  const auto row = static_cast<index_t>(k);
  const block_motion& ma = motion_[at(pair_a_[k])];
  const block_motion& mb = motion_[at(pair_b_[k])];
  for (int j = 0; j < 3; ++j) {
    soa3& m = normal_[at(j)];
    // A normal that is the plane's to the bit (normal_is_plane's) is copied, not computed again.
    if (j > 0 && normal_is_plane(k, j)) {
      m(row, 0) = normals[0].x;
      m(row, 1) = normals[0].y;
      m(row, 2) = normals[0].z;
      normals[at(j)] = normals[0];
      tilts[at(j)] = tilts[0];
      continue;
    }
    const triple n_prev{m(row, 0), m(row, 1), m(row, 2)};
    const triple n = pair_normal(k, j, ma, mb);
    m(row, 0) = n.x;
    m(row, 1) = n.y;
    m(row, 2) = n.z;
    normals[at(j)] = n;
    tilts[at(j)] = kinematics::tilt(n_prev, n);
  }
}

/// update_pair for deformable blocks: each material point is its four gridpoints' weighted sum
/// (a zone's barycentric interpolation, or one surface gridpoint), read from the gridpoints.
template <law::ContactLaw Law>
inline void detected_contacts<Law>::update_pair_zoned(index_t pk, real dt, const node_set& gp,
                                                      const std::array<triple, 3>& normals,
                                                      const std::array<triple, 3>& tilts) noexcept {
  const auto k = at(pk);
  const params_type& p = law_params_[at(pair_param_[k])];
  for (auto i = at(pair_first_[k]); i < at(pair_first_[k + 1]); ++i) {
    real gap[3] = {0, 0, 0}, dv[3] = {0, 0, 0};
    for (int slot = 0; slot < 8; ++slot) {
      const index_t g = node_[at(slot)][i];
      if (g == invalid_index) continue;
      const real w = slot < 4 ? -weight_[at(slot)][i] : weight_[at(slot)][i];
      for (int c = 0; c < 3; ++c) {
        gap[c] += w * (reference_(g, c) + gp.displacement(g, c));
        dv[c] += w * gp.velocity(g, c);
      }
    }
    const triple& n = normals[corner_normal_[i]];
    advance_split(i, p, increment(i, {dv[0], dv[1], dv[2]}, {gap[0], gap[1], gap[2]}, n, tilts[corner_normal_[i]], dt), n);
  }
}

/// The sub-contacts of pair pk (rigid blocks), with the pair's normals and tilts this step.
/// In chunks of up to subcontact_batch sub-contacts, three loops: each one's relative increment,
/// then each one's law update and force, then the sums per frame gridpoint. The same arithmetic
/// per sub-contact and the same order of the sums as one loop doing all three (the same bits);
/// the law's chain (a division and square roots) of several sub-contacts then overlaps, where in
/// one loop of some 450 instructions a sub-contact each waited on its own. A law with open_step
/// (cohesive_frictional) skips the law for the gaps that stay open without stress (advance_split),
/// and their zero forces skip the sums.
template <law::ContactLaw Law>
inline void detected_contacts<Law>::update_pair(index_t pk, real dt, const std::array<triple, 3>& normals,
                                                const std::array<triple, 3>& tilts) noexcept {
  const auto k = at(pk);
  const block_motion& ma = motion_[at(pair_a_[k])];
  const block_motion& mb = motion_[at(pair_b_[k])];
  const params_type& p = law_params_[at(pair_param_[k])];
  // The two bodies' points relative to A's frame origin: x_b(p) - x_a(p) and v_b(p) - v_a(p).
  const vec3 dx0 = mb.x0 - ma.x0, dv0 = mb.v0 - ma.v0;
  // The force on each frame gridpoint of the two blocks, summed here over the pair's
  // sub-contacts (the gather then reads 8 sums per pair, not 8 weights per sub-contact).
  real sum[24] = {};
  const auto first = at(pair_first_[k]), last = at(pair_first_[k + 1]);
  for (auto i0 = first; i0 < last; i0 += subcontact_batch) {
    const auto n_i = std::min<std::size_t>(subcontact_batch, last - i0);
    std::array<kinematics::normal_split, subcontact_batch> du;
    std::array<triple, subcontact_batch> f;
    for (std::size_t j = 0; j < n_i; ++j) {
      const auto i = i0 + j;
      const vec3 la(weight_[1][i], weight_[2][i], weight_[3][i]), lb(weight_[5][i], weight_[6][i], weight_[7][i]);
      const vec3 g = dx0 + mb.d * lb - ma.d * la, w = dv0 + mb.dv * lb - ma.dv * la;
      du[j] = increment(i, {w.x(), w.y(), w.z()}, {g.x(), g.y(), g.z()}, normals[corner_normal_[i]], tilts[corner_normal_[i]], dt);
    }
    for (std::size_t j = 0; j < n_i; ++j) f[j] = advance_split(i0 + j, p, du[j], normals[corner_normal_[i0 + j]]);
    for (std::size_t j = 0; j < n_i; ++j) {
      // A zero force (an open gap) adds +-0 to each sum, which leaves a sum as it is: skipped.
      if (f[j].x == 0 && f[j].y == 0 && f[j].z == 0) continue;
      const auto i = i0 + j;
      for (int s = 0; s < 8; ++s) {
        const real ws = s < 4 ? weight_[at(s)][i] : -weight_[at(s)][i];
        sum[3 * s] += ws * f[j].x;
        sum[3 * s + 1] += ws * f[j].y;
        sum[3 * s + 2] += ws * f[j].z;
      }
    }
  }
  std::copy(std::begin(sum), std::end(sum), pair_force_.begin() + static_cast<std::ptrdiff_t>(24 * k));
}

/// Sub-contact i's relative displacement increment this step (m), split on the normal n, from
/// its relative velocity dv (m/s), its gap (m) and the tilt of its plane: zero for a sub-contact
/// created at this step's rebuild, which already holds its gap at t.
template <law::ContactLaw Law>
[[gnu::always_inline]] inline kinematics::normal_split detected_contacts<Law>::increment(
    std::size_t i, const triple& dv, const triple& gap, const triple& n, const triple& tilt, real dt) const noexcept {
  if (fresh_[i] != 0) [[unlikely]]
    return {0, {0, 0, 0}};
  return kinematics::split(kinematics::relative_increment(dv, gap, tilt, dt), n);
}

/// The law step and force of sub-contact i from its split increment s (increment's), on the
/// normal n. The law advances a copy of the state
/// kept in registers, so the traction is not read back from state_[i] right after the law
/// stored it (perf annotate showed that load stalled on store forwarding: a 32-byte store read
/// by a 16-byte load at offset 8; the step time did not move measurably, the law's division
/// took the stall's place).
/// Returns the force on A's side (N), also stored in force_.
template <law::ContactLaw Law>
[[gnu::always_inline]] inline typename detected_contacts<Law>::triple detected_contacts<Law>::advance_split(
    std::size_t i, const params_type& p, const kinematics::normal_split& s, const triple& n) noexcept {
  fresh_[i] = 0;
  // An open gap without stress that stays open (Law::open_step, the law's result to the bit):
  // its opening advanced, its force +0, the law's divisions and square roots skipped.
  if constexpr (requires(state_type& st) { Law::open_step(st, real(0)); }) {
    if (Law::open_step(state_[i], s.du_n)) {
      force_[0][i] = force_[1][i] = force_[2][i] = 0;
      return {0, 0, 0};
    }
  }
  const vec3 normal(n.x, n.y, n.z);
  state_type st = state_[i];
  Law::update(p, st, s.du_n, vec3(s.du_s.x, s.du_s.y, s.du_s.z), normal);
  state_[i] = st;
  const vec3 traction = st.sigma_n * normal + vec3(st.tau);
  const triple f{area_[i] * traction[0], area_[i] * traction[1], area_[i] * traction[2]};
  force_[0][i] = f.x;
  force_[1][i] = f.y;
  force_[2][i] = f.z;
  return f;
}

}  // namespace tessera::contact
