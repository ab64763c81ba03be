#pragma once
// The stable step of detected_contacts (contact/detected_contacts.hpp): the stiffness bounds it
// adds to the gridpoints for the solver's time step.
//
// Stable step (rigid blocks). add_stiffness_bounds puts a bound per block on its vertex farthest
// from its centroid (distance r_max), from which blocks::rigid's 6-DOF bound takes k_t = k and
// k_r = k r_max^2. params::step_bound chooses which contacts it covers:
// - present_contacts (default): the sub-contacts that exist until the next rebuild. Each
//   sub-contact i couples its two material points by [K -K; -K K], K = a_i (k_s I + (k_n - k_s)
//   n n^T), whose row sum is at most 2 k_row a_i on either side (stiffness_bound.hpp; k_row of
//   the pair's own table entry, a_i the tributary or nominal area its springs use, so no margin
//   for nominal areas is needed). So the block carries k = sum_i 2 k_row a_i over the
//   sub-contacts of its pairs, times max(1, max_i |rho_i|^2 / r_max^2) (rho_i: centroid to the
//   material point, fixed in the body; a corner of a patch can lie up to the tolerance outside
//   the block), and k_r = k r_max^2 >= sum_i 2 k_row a_i |rho_i|^2 as the proof in
//   blocks/rigid.hpp needs. Why this is stable until the next rebuild: between rebuilds the
//   sub-contact set, its areas, its material points and its pairs' law entries are fixed, and new
//   contacts appear only at rebuilds; every sub-contact's stiffness stays within its row bound for
//   any normal it turns to. The bound changes at every rebuild (recomputed there, and after a
//   checkpoint load, from the sub-contacts' areas and weights), so the solver chooses dt again
//   after each rebuild (solver.hpp, "Time step"). With no sub-contact at all it falls back to:
// - whole_surface: every contact the block could ever carry: k = 4 k_row A, A = min(S, sum of the
//   other blocks' S) bounds its contact area (x 2 for the nominal areas of corner contacts and
//   overlapping patches), k_row the row bound of the stiffest material entry. It holds for any
//   contacts that appear later, so a dt chosen once from it stays stable for the whole run: the
//   solver uses it when dt does not follow the rebuilds (a given solver_options::dt, mass scaling).
//
// Deformable blocks: every surface gridpoint's bound is fixed at construction
// (detected/deformable_fit.hpp, build_surfaces).
//
// Cost: add_bounds O(blocks) (deformable: O(gridpoints)); bound_present_contacts O(sub-contacts),
// after each rebuild and checkpoint load (the pairs' terms in parallel, the blocks' sums in pair
// order); no allocation.
//
// Definitions of detected_contacts<Law>'s private members (declared in the class); it includes the
// class and the class includes it, so either header can come first.

#include <algorithm>
#include <array>
#include <cstddef>

#include "../../core/parallel.hpp"
#include "../detected_contacts.hpp"

namespace tessera::contact {

/// add_stiffness_bounds for the scope given: rigid blocks, per block on its farthest vertex, the
/// present sub-contacts' bound (when there is any and the scope asks for it) or the whole surface's;
/// deformable blocks, the per-gridpoint bounds whatever the scope.
template <law::ContactLaw Law>
inline void detected_contacts<Law>::add_bounds(node_set& gridpoints, step_bound_scope scope) const {
  require(gridpoints.size() == gridpoint_count_ && gridpoints.stiffness.size() == gridpoint_count_,
          "detected_contacts::add_stiffness_bounds: node_set has ", gridpoints.size(), " gridpoints, expected ",
          gridpoint_count_);
  if (options_.deformable_blocks) {
    for (index_t g = 0; g < gridpoint_count_; ++g) gridpoints.stiffness[g] += gridpoint_bound_[at(g)];
    return;
  }
  const bool present = scope == step_bound_scope::present_contacts && size() > 0;
  for (std::size_t b = 0; b < blocks_.size(); ++b)
    gridpoints.stiffness[blocks_[b].farthest] += present ? present_bound_[b] : blocks_[b].stiffness_bound;
}

/// Rigid blocks: per block, the bound of its present sub-contacts on its farthest vertex (file
/// comment), from the pairs' law entries, the areas and the weights (so a
/// checkpoint load gets the same bits as the rebuild). `kept_pairs` (a rebuild's call): the pairs
/// it kept have their terms already (copied with their sub-contacts); the others are computed.
/// Allocates only when the per-pair terms grow.
template <law::ContactLaw Law>
inline void detected_contacts<Law>::bound_present_contacts(bool kept_pairs) {
  std::fill(present_bound_.begin(), present_bound_.end(), 0.0);
  std::fill(present_reach2_.begin(), present_reach2_.end(), 0.0);
  pair_stiffness_.resize(pair_a_.size());
  pair_reach2_.resize(pair_a_.size());
  // Each pair's terms (the pairs in parallel: each writes its own), then the blocks' sums in pair order.
  parallel_for_dynamic(static_cast<std::int64_t>(pair_a_.size()), [&](std::int64_t kk) {
    const auto k = at(kk);
    if (kept_pairs && new_source_[k] < 0) return;
    const std::array<index_t, 2> ab{pair_a_[k], pair_b_[k]};
    const real per_area = 2 * entry_row_bound_[at(pair_param_[k])];
    for (int side = 0; side < 2; ++side) {
      const block_data& bd = blocks_[at(ab[at(side)])];
      // The material point in the block's reference frame: X0 + D (w1, w2, w3), rigid motion
      // keeps its distance from the centroid.
      const mat3 d = frame_matrix(bd, nullptr);
      const vec3 x0 = reference_.row(bd.frame[0]).transpose();
      real k_sum = 0, reach2 = 0;
      for (auto i = at(pair_first_[k]); i < at(pair_first_[k + 1]); ++i) {
        k_sum += per_area * area_[i];
        const int w = 4 * side;
        const vec3 local(weight_[at(w + 1)][i], weight_[at(w + 2)][i], weight_[at(w + 3)][i]);
        reach2 = std::max(reach2, (x0 + d * local - bd.centroid).squaredNorm());
      }
      pair_stiffness_[k] = k_sum;  // (the same sum on both sides)
      pair_reach2_[k][at(side)] = reach2;
    }
  }, 64);
  for (std::size_t k = 0; k < pair_a_.size(); ++k) {
    const std::array<index_t, 2> ab{pair_a_[k], pair_b_[k]};
    for (int side = 0; side < 2; ++side) {
      present_bound_[at(ab[at(side)])] += pair_stiffness_[k];
      present_reach2_[at(ab[at(side)])] = std::max(present_reach2_[at(ab[at(side)])], pair_reach2_[k][at(side)]);
    }
  }
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    const real far2 = (reference_.row(blocks_[b].farthest).transpose() - blocks_[b].centroid).squaredNorm();
    if (present_reach2_[b] > far2) present_bound_[b] *= present_reach2_[b] / far2;
  }
}

}  // namespace tessera::contact
