#pragma once
// One detection pass over a set of convex blocks: the broad phase (uniform grid, or sort and
// sweep where the grid refuses the layout), then for every candidate pair the common plane and,
// when its gap is within the contact tolerance, the contact patch (broad_phase.hpp,
// common_plane.hpp). This is what a detecting contact set runs at each rebuild.
//
// Result (detection_result), deterministic for any thread count: the touching pairs in
// increasing (a, b) order, each with its plane, and their patch corners as one list (pair k owns
// corners [first_corner[k], first_corner[k + 1])) with point, gap and tributary area.
// The narrow phase runs in parallel over the candidate pairs (each pair writes its own slot),
// and the slots are concatenated in pair order. A pass can evaluate one contiguous part of the
// candidates (detection_share), for ranks that split the narrow phase and gather the parts.
// With detection_options::reuse_axes the workspace keeps each candidate pair's plane axis, and
// the next pass tries it first (hinted_plane): a pair it still shows apart by more than the
// tolerance skips the full common-plane search. The result is the same to the bit (the axis is
// one of the search's candidates, so the search's gap is at least the axis's); a checkpoint's
// restart or a new workspace only runs more full searches. A pair the axis does not show apart
// starts its search from the axis's gap (common_plane_above: the same plane, fewer loops).
//
// Cost: see docs/performance.md ("Contact detection kernels"). Allocates only when an array
// grows: the result's and the workspace's, each candidate slot's patch and each thread's patch
// scratch (contact_patch_into); they keep their capacity between passes. The narrow phase hands
// the pairs to the threads in runs of 16 as they come free (parallel_for_dynamic). A pass runs
// at rebuilds only, never in the step loop.

#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "../../core/separate_compilation.hpp"
#include "../../core/errors.hpp"
#include "../../core/parallel.hpp"
#include "../../core/types.hpp"
#include "../../geometry/convex_polyhedron.hpp"
#include "broad_phase.hpp"
#include "common_plane.hpp"

namespace tessera::contact::detection {

/// Parameters of a detection pass (SI).
struct detection_options {
  real margin = 0;     ///< broad-phase enlargement of each box (m): rebuild_margin
  real tolerance = 0;  ///< contact tolerance (m, > 0): pairs with a gap up to it touch
  /// Try each candidate pair's axis of the workspace's earlier passes first (hinted_plane): a
  /// pair that axis still separates by more than the tolerance is not touching, without the
  /// full common-plane search. The same result as without; the workspace keeps the axes.
  bool reuse_axes = false;
};

/// Which contiguous part of the broad phase's candidate list a pass evaluates: part `part` of
/// `parts` equal runs, [n part / parts, n (part + 1) / parts) of the n candidates. The parts of one
/// pass, concatenated in part order, are the whole pass's result to the bit (each candidate's
/// plane and patch depend on its two blocks only); the ranks of a split run each take one
/// (distributed::gather_detection). {0, 1}: the whole list.
struct detection_share {
  int part = 0;  ///< this part, in [0, parts)
  int parts = 1;  ///< number of parts (>= 1)
};

/// What a pass found (see the file comment).
struct detection_result {
  std::vector<block_pair> pairs;       ///< touching pairs, increasing
  std::vector<contact_plane> planes;   ///< plane of each touching pair
  std::vector<index_t> first_corner{0};  ///< CSR over pairs into the corner arrays
  std::vector<vec3> point;             ///< corner on the contact plane (m)
  std::vector<real> gap;               ///< normal gap B - A through it (m)
  std::vector<real> area;              ///< tributary area (m^2; 0 for segment and point patches)
  std::vector<std::uint64_t> label;    ///< what the corner is (corner_label, common_plane.hpp)
  std::vector<patch_type> type;        ///< patch type of each touching pair
  std::size_t candidates = 0;          ///< pairs the broad phase passed on
  std::size_t evaluated = 0;           ///< of them, those this pass evaluated (its detection_share part)
  /// No pairs and no corners (the counts stay); keeps the capacity.
  void clear_pairs() {
    pairs.clear();
    planes.clear();
    type.clear();
    first_corner.assign(1, 0);
    point.clear();
    gap.clear();
    area.clear();
    label.clear();
  }
};

/// Scratch of a pass, kept between passes.
struct detection_workspace {
  grid_workspace grid;  ///< broad phase grid scratch
  sweep_workspace sweep;  ///< sweep and prune scratch
  std::vector<block_pair> candidates;  ///< candidate pairs
  std::vector<contact_plane> planes;  ///< contact plane of each candidate
  std::vector<contact_patch> patches;  ///< contact patch of each candidate
  std::vector<index_t> face_first{0};         ///< CSR over blocks into faces
  std::vector<geometry::plane> faces;       ///< the blocks' face planes (append_face_planes), this pass
  std::vector<std::uint8_t> needs_faces;    ///< per block, whether this pass computed its face planes
  /// The pairs whose plane axis the passes keep (detection_options::reuse_axes), increasing, and
  /// those axes: each candidate of the last pass and the kept pairs of two blocks it did not mark,
  /// with the axis of the pass that last evaluated the pair.
  std::vector<block_pair> axis_pairs;
  std::vector<axis_hint> axes;  ///< (see axis_pairs)
  std::vector<axis_hint> hints;  ///< per candidate of this pass: its pair's kept axis (none: none kept)
  /** scratch of the axes' merge */ /**@{*/ std::vector<block_pair> next_pairs;
  std::vector<axis_hint> next_axes; /**@}*/
  std::vector<std::uint8_t> skipped;  ///< per candidate of this pass: whether its kept axis showed it apart
  std::size_t axis_skips = 0;  ///< candidates the kept axes showed apart, over the workspace's passes
  /// Block b's face planes as the last pass computed them (valid where needs_faces[b]).
  [[nodiscard]] std::span<const geometry::plane> faces_of(std::size_t b) const {
    const auto first = static_cast<std::size_t>(face_first[b]), last = static_cast<std::size_t>(face_first[b + 1]);
    return std::span<const geometry::plane>(faces).subspan(first, last - first);
  }
};

/// Blocks placed rigidly from reference shapes (a detecting contact set's rigid blocks at a
/// rebuild): block b is its reference shape carried by x -> rotation[b] x + shift[b], and the
/// plane of its face f is the reference face's (outward unit normal, centroid) carried the same
/// way: a rotation per face, where computing the plane from the current vertices takes the
/// face's area vector and centroid (about ten times the work; the same plane to round-off, not
/// to the bit). Empty spans: the planes from the current vertices.
struct placed_faces {
  std::span<const index_t> first;  ///< CSR over blocks into normal and centroid (a block's faces in its order)
  std::span<const vec3> normal;    ///< each reference face's outward unit normal
  std::span<const vec3> centroid;  ///< each reference face's centroid (m)
  std::span<const mat3> rotation;  ///< per block: its rotation from the reference shape
  std::span<const vec3> shift;     ///< per block: its translation (m)
  [[nodiscard]] bool empty() const noexcept { return first.empty(); }  ///< No placement given (planes from the vertices)
};

/// Detects the contacts of `blocks` (their current geometry; `edges[i]` = edges_of(blocks[i]),
/// `boxes[i]` = blocks[i].bounds()). `only` (empty: every pair) restricts the pass to the candidate
/// pairs with at least one block b marked only[b] != 0 (an incremental rebuild: the pairs of the
/// blocks that moved); the face planes are then computed for those pairs' blocks only. `skip`
/// (increasing; with `only`) names pairs the pass leaves out although a block of theirs is marked
/// (the caller keeps what it had for them; their kept axes stay). `placed` (non-empty): the
/// blocks are placed rigidly, their face planes carried from the reference faces (placed_faces;
/// the caller vouches that blocks[b] is that placement). `prepare` (empty: none) is called once
/// for each block the pass reads, before the pass reads it, on the pass's threads (a call may
/// write block b's own storage only): an incremental rebuild places there the blocks it did not
/// place, whose boxes were only bounds. Throws invalid_input for mismatched sizes or a bad option.
TESSERA_INLINE void detect(std::span<const geometry::convex_polyhedron> blocks, std::span<const polyhedron_edges> edges,
                           std::span<const aabb> boxes, const detection_options& options, detection_result& out,
                           detection_workspace& w, detection_share share = {}, std::span<const std::uint8_t> only = {},
                           std::span<const block_pair> skip = {}, const placed_faces& placed = {},
                           const std::function<void(std::size_t)>& prepare = {});

}  // namespace tessera::contact::detection

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/detect.ipp"
#endif
