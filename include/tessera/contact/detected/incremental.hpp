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
// Guarantee (no contact missed): a pair was last detected when the later of its two blocks was,
// at t_p; since then that block moved m(t) <= trigger and the other m(t) + m(t_p) <= trigger +
// redetect (it was not detected again at t_p, so m(t_p) <= redetect), so the two blocks came
// closer by at most 2 trigger + redetect = the tolerance: a gap above the tolerance at t_p has
// not closed. The same bound as a full rebuild at every tolerance / 2 of motion (then 2 x 1/2).
//
// Cost: the pass runs on the moved blocks' candidate pairs, and of those the pairs that the axis
// of their last plane still shows apart skip the full common-plane search (detect.hpp,
// reuse_axes: about two thirds of them in the rubble scene); the rest of a rebuild is
// O(blocks + sub-contacts) with small constants: each block's current shape and box (into its own
// storage), the broad phase (every box's cells scanned, only the cells a moved block reaches binned,
// only the pairs with a moved block tested), the kept pairs' columns copied in runs (their keys,
// areas and stiffness terms of the step bound with them; the merge of the states visits the old
// pairs and only the sub-contacts of those detected again), the tasks and gather slots. No
// allocation beyond a rebuild's growth.

#include <array>
#include <cstdint>
#include <vector>

#include "../../core/nodes.hpp"
#include "../../core/types.hpp"

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
