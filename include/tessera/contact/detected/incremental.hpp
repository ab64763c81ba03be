#pragma once
// The incremental rebuild of detected_contacts (contact/detected_contacts.hpp) with rigid blocks:
// which blocks a rebuild detects again, and the columns of the pairs it keeps. Not a public
// interface.
//
// Each block carries its own motion since it was last detected: m_b, the largest move of its
// vertices since then. A rebuild comes once some m_b passes trigger_fraction x the tolerance
// (or the rebuild interval is reached: then every block is detected again), and detects again
// only the blocks whose m_b passed redetect_fraction x the tolerance: the candidate pairs with
// one of them (detection::detect's `only`) go through the common plane and the patch, and those
// blocks' motion starts again from zero. A pair of two other blocks keeps its sub-contacts,
// tributary areas, weights, normals and states untouched (the rebuild exchanges no energy for
// it) and goes on as if no rebuild had come.
//
// Pairs that moved as one: an old pair with a block detected again is kept as it is (the pass
// leaves it out: detection::detect's `skip`) when its blocks moved together, its drift since its
// last detection (how far a point of B near A moved relative to A, from the two blocks' rigid
// motions: pair_poses) at most redetect_fraction x the tolerance, less the motion m_o of its
// other block when only one is detected again. Its sub-contacts live in the blocks' frames
// (weights, normal features, areas), which such a motion leaves as they were.
//
// Guarantee (no contact missed): a pair was last detected when the later of its two blocks was,
// at t_p; since then that block moved m(t) <= trigger and the other m(t) + m(t_p) <= trigger +
// redetect (it was not detected again at t_p, so m(t_p) <= redetect), so the two blocks came
// closer by at most 2 trigger + redetect = the tolerance: a gap above the tolerance at t_p has
// not closed. The same bound as a full rebuild at every tolerance / 2 of motion (then 2 x 1/2).
// A pair kept as one at t_r had drifted at most redetect - m_o(t_r) since its detection (m_o = 0
// when both blocks start their motion at t_r); until one of them is detected again (and the pair
// with it) the block that started moves at most trigger from its place at t_r and the other at
// most m_o(t) + m_o(t_r) <= trigger + m_o(t_r), so the pair drifts at most redetect + 2 trigger =
// the tolerance too. A pair leaves the set only through a
// pass that found it apart, at which one of its blocks starts its motion again: the first case.
//
// Placement: a rebuild places (its current shape R X + t, and the box of that) the blocks it
// detects again, and another block only when the pass reads it, as the other block of a
// candidate pair (about half the blocks of the rubble scene). The broad phase takes for such a
// block its vertices' box at its last detection grown by its motion since, m_b (grown_box): a box
// that holds the block. So every pair the broad phase would find with the block's own box it
// finds with this one, and the pairs it finds besides are more than 2 x the tolerance apart
// (its margin), which the pass finds apart: the same contacts and sub-contacts to the bit.
//
// Cost: the pass runs on the moved blocks' candidate pairs, and of those the pairs that the axis
// of their last plane still shows apart skip the full common-plane search (detect.hpp,
// reuse_axes: about three quarters of them in the rubble scene), and the face planes they read are
// the reference faces carried by the poses (placed_faces_of); the rest of a rebuild is
// O(blocks + sub-contacts) with small constants: each block's current shape and box (into its own
// storage, the blocks in parallel: place_blocks), the broad phase (every box's cells scanned, only the cells a moved block reaches binned,
// only the pairs with a moved block tested), the kept pairs' columns and their sub-contacts' copied
// in runs (keys, areas, features, poses, normals, the step bound's terms; the merge of the states looks up each
// pass pair's old pair and visits only the sub-contacts of those detected again), the tasks and
// gather slots (per block: a counting sort of the pairs' two sides, detected/tasks.hpp). The
// merge, the copies and the pairs' columns run on the threads (each pair or run writes its own
// slots); the broad phase, the new pair list, the tasks and gather slots and the
// energy sums on one. No allocation beyond a rebuild's growth.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "../../core/nodes.hpp"
#include "../../core/parallel.hpp"
#include "../../core/types.hpp"
#include "../detection/broad_phase.hpp"
#include "../detection/detect.hpp"

namespace tessera::contact::detail {

/// Share of the tolerance (rigid blocks): a block's motion since it was last detected that
/// brings a rebuild, and the motion past which a rebuild detects a block again (2 x trigger +
/// redetect = 1: the guarantee above). Measured against 0.35 / 0.3, 0.4 / 0.2 and 0.45 / 0.1 on
/// the 300-block rubble scene (docs/studies/incremental_detection.md); 0.4 / 0.2 put a rebuild
/// of the verification drop at its moment of impact (a round number of triggers: energy balance
/// 2.5e-6 against 2.7e-8), 0.39 / 0.22 does not.
inline constexpr real trigger_fraction = 0.39;
inline constexpr real redetect_fraction = 0.22;
static_assert(2 * trigger_fraction + redetect_fraction <= 1.0);

/// The pairs a rebuild keeps although both their blocks are detected again (the file comment).
/// Per pair, the relative pose of its blocks when it was last detected (B's reference frame in
/// A's: G = R_a^T R_b, h = R_a^T (t_b - t_a), a block's reference point X being at R X + t); the
/// pair's drift is how far a material point X of B near A has moved relative to A since then,
/// |(G - G_p) X + (h - h_p)| (m), bounded over a sphere about either block's reference vertices
/// (the lower bound; the field is affine in X).
struct pair_poses {
  std::vector<mat3> rot, prev_rot;     // per pair: G at its detection (and the last rebuild's)
  std::vector<vec3> shift, prev_shift; // per pair: h at its detection (m)
  std::vector<vec3> center;            // per block: the reference vertices' mean (m)
  std::vector<real> radius;            // per block: its vertices' largest distance from it (m)
  std::vector<mat3> block_rot;         // per block, this rebuild: R
  std::vector<vec3> block_shift;       //   and t (m)
  std::vector<index_t> face_first;     // rigid blocks: CSR over blocks into the reference faces'
  std::vector<vec3> face_normal, face_centroid;  // unit normals and centroids (m; detection::placed_faces)
  std::vector<std::uint8_t> keep;      // per old pair: kept though both blocks are detected again
  std::vector<detection::block_pair> skip;  // those pairs, increasing (detection::detect's skip)
  std::int64_t kept_as_one = 0;        // those pairs, summed over the rebuilds

  /// B's pose in A's reference frame now (this rebuild's block poses).
  void relative(index_t a, index_t b, mat3& g, vec3& h) const {
    const mat3& ra = block_rot[static_cast<std::size_t>(a)];
    g = ra.transpose() * block_rot[static_cast<std::size_t>(b)];
    h = ra.transpose() * (block_shift[static_cast<std::size_t>(b)] - block_shift[static_cast<std::size_t>(a)]);
  }
  /// Old pair k's drift since its detection (m; before the rebuild swaps rot and shift with the
  /// prev_ buffers): a point of B that touches A before the pair's next pass lies within `reach`
  /// (m) of B's sphere, and of A's at the pair's detection or now.
  [[nodiscard]] real drift(std::size_t k, index_t a, index_t b, real reach) const {
    mat3 g;
    vec3 h;
    relative(a, b, g, h);
    const mat3 dg = g - rot[k];
    const vec3 dh = h - shift[k];
    const real spread = dg.norm();  // (Frobenius: >= the largest stretch of dg)
    const auto sa = static_cast<std::size_t>(a), sb = static_cast<std::size_t>(b);
    const real over_b = (dg * center[sb] + dh).norm() + spread * (radius[sb] + reach);
    // A's sphere in B's reference frame, at the detection and now.
    const vec3 then = rot[k].transpose() * (center[sa] - shift[k]), now = g.transpose() * (center[sa] - h);
    const real over_a = std::max((dg * then + dh).norm(), (dg * now + dh).norm()) + spread * (radius[sa] + reach);
    return std::min(over_a, over_b);
  }
};

/// Each block's pose this rebuild (pose_of(b, R, t) sets them) into pp.block_rot and block_shift,
/// and its current shape R X + t (assign_transformed, into its own storage) with its box, in
/// parallel (each block writes its own). `only` (empty: every block) places the marked blocks
/// only and gives each other block b the box bound_of(b), a box that holds it: its shape is
/// placed when the pass reads it (place_block, from detection::detect's prepare). A pose
/// assign_transformed refuses is refused after the loop, in block order, as a serial loop would
/// refuse it.
template <class Shapes, class Boxes, class PoseOf, class BoundOf>
void place_blocks(pair_poses& pp, const Shapes& shapes, Shapes& current, Boxes& boxes, PoseOf&& pose_of,
                  std::span<const std::uint8_t> only, BoundOf&& bound_of) {
  pp.block_rot.resize(shapes.size());
  pp.block_shift.resize(shapes.size());
  const auto refused = [&](std::size_t b) {
    const mat3& r = pp.block_rot[b];
    return !(r.allFinite() && r.determinant() > 0 && pp.block_shift[b].allFinite());
  };
  parallel_for(static_cast<std::int64_t>(shapes.size()), [&](std::int64_t k) {
    const auto b = static_cast<std::size_t>(k);
    pose_of(b, pp.block_rot[b], pp.block_shift[b]);
    if (refused(b)) return;
    if (!only.empty() && only[b] == 0) {
      boxes[b] = bound_of(b);
      return;
    }
    current[b].assign_transformed(shapes[b], pp.block_rot[b], pp.block_shift[b]);
    boxes[b] = current[b].bounds();
  }, 64);
  for (std::size_t b = 0; b < shapes.size(); ++b)
    if (refused(b)) current[b].assign_transformed(shapes[b], pp.block_rot[b], pp.block_shift[b]);  // (throws)
}

/// place_blocks of every block.
template <class Shapes, class Boxes, class PoseOf>
void place_blocks(pair_poses& pp, const Shapes& shapes, Shapes& current, Boxes& boxes, PoseOf&& pose_of) {
  place_blocks(pp, shapes, current, boxes, pose_of, {}, [](std::size_t) { return aabb{}; });
}

/// A box that holds a rigid block whose vertices had the box `box` (m) and have moved at most
/// sqrt(moved2) (m) since: the box grown by that, and a slack (a millionth of the tolerance, and
/// the round-off between a vertex gridpoint and the placement R X + t).
[[nodiscard]] inline aabb grown_box(aabb box, real moved2, real tolerance) {
  const real scale = std::max(box.lo.cwiseAbs().maxCoeff(), box.hi.cwiseAbs().maxCoeff());
  const real grow = std::sqrt(moved2) + 1e-6 * tolerance + 64 * std::numeric_limits<real>::epsilon() * scale;
  box.lo.array() -= grow;
  box.hi.array() += grow;
  return box;
}

/// Each shape's vertex mean and its vertices' largest distance from it (the spheres of pair_poses).
template <class Shapes>
void reference_spheres(const Shapes& shapes, std::vector<vec3>& center, std::vector<real>& radius) {
  center.assign(shapes.size(), vec3::Zero());
  radius.assign(shapes.size(), 0);
  for (std::size_t b = 0; b < shapes.size(); ++b) {
    const index_t n = shapes[b].vertex_count();
    for (index_t v = 0; v < n; ++v) center[b] += shapes[b].vertex(v);
    if (n > 0) center[b] /= static_cast<real>(n);
    for (index_t v = 0; v < n; ++v) radius[b] = std::max(radius[b], (shapes[b].vertex(v) - center[b]).norm());
  }
}

/// Rigid blocks at a rebuild: their face planes are the reference shapes' faces (unit normals
/// and centroids, each shape's in its face order, computed at the first call) carried by this
/// rebuild's poses (place_blocks'); detection::detect's placed_faces.
template <class Shapes>
[[nodiscard]] detection::placed_faces placed_faces_of(const Shapes& shapes, pair_poses& pp) {
  if (pp.face_first.size() != shapes.size() + 1) {
    pp.face_first.assign(1, 0);
    pp.face_normal.clear();
    pp.face_centroid.clear();
    for (const auto& shape : shapes) {
      for (index_t f = 0; f < shape.face_count(); ++f) {
        pp.face_normal.push_back(shape.face_normal(f));
        pp.face_centroid.push_back(shape.face_centroid(f));
      }
      pp.face_first.push_back(static_cast<index_t>(pp.face_normal.size()));
    }
  }
  return {pp.face_first, pp.face_normal, pp.face_centroid, pp.block_rot, pp.block_shift};
}

/// Whether a kept pair (old pair `pair_from` with sub-contacts from `from`, new pair `pair_to`
/// with sub-contacts from `to`) continues the last run of kept pairs in both lists.
template <class Run>
[[nodiscard]] bool continues_run(const std::vector<Run>& runs, std::size_t from, std::size_t to, std::size_t pair_from,
                                 std::size_t pair_to) {
  if (runs.empty()) return false;
  const Run& r = runs.back();
  return r.from + r.count == from && r.to + r.count == to && r.pair_from + r.pairs == pair_from && r.pair_to + r.pairs == pair_to;
}

/// The pair and sub-contact columns of the last rebuild that a rebuild copies for the pairs it
/// keeps (the class swaps its own columns in here, then fills them again).
template <class Feature>
struct previous_columns {
  std::vector<index_t> param;
  std::vector<Feature> feature;
  std::vector<vec3> feature_a, feature_b, side_a, side_b;
  std::array<soa3, 3> normal;
  std::vector<std::uint8_t> corner_normal;
  std::array<std::vector<real>, 8> weight;
  std::array<std::vector<real>, 3> force;
  std::vector<real> stiffness;                 // bound_present_contacts' terms
  std::vector<std::array<real, 2>> reach2;
  std::vector<std::uint64_t> label;            // the sub-contacts' keys and areas
  std::vector<real> area;
};

}  // namespace tessera::contact::detail
