#pragma once
// Checkpoints of detected_contacts (contact/detected_contacts.hpp, io/checkpoint.hpp): checkpoint(Archive&)
// saves the sub-contacts and pairs with their sizes (the tasks and gather slots are derived again on
// load), the rebuild trigger's state and the books, so a restarted run rebuilds at the same steps
// with the same bits. The record names ("detected/...") are the file format: keep them.
//
// Cost: O(sub-contacts + pairs + watched gridpoints) per save or load; a load allocates.
//
// The definition of detected_contacts<Law>::checkpoint (declared, with what it saves, in the
// class); it includes the class and the class includes it, so either header can come first.

#include <cstdint>
#include <string>
#include <type_traits>

#include "../../core/types.hpp"
#include "../../law/concepts.hpp"
#include "../detected_contacts.hpp"

namespace tessera::contact {

template <law::ContactLaw Law>
template <class Archive>
inline void detected_contacts<Law>::checkpoint(Archive& ar) {
  static_assert(law::DeclaresStateFields<Law>, "checkpoints need a law that declares state_fields");
  ar.same("detected/blocks", static_cast<std::int64_t>(blocks_.size()));
  ar.same("detected/gridpoints", static_cast<std::int64_t>(gridpoint_count_));
  ar.same("detected/tolerance", options_.tolerance);
  ar.same("detected/max_rebuild_interval", static_cast<std::int64_t>(options_.max_rebuild_interval));
  std::int64_t n_pairs = pair_count(), n = size();
  ar.count("detected/pairs", n_pairs);
  ar.count("detected/subcontacts", n);
  // Variable-size arrays: the dry pass checks the records against the file's sizes on scratch
  // arrays; the copy pass resizes the model's.
  const auto sized = [&](const std::string& name, auto& v, std::int64_t count) {
    using V = std::remove_reference_t<decltype(v)>;
    constexpr bool rows = std::is_same_v<V, soa3>;  // n x 3 matrices: count rows
    const auto pass = [&](V& x) {
      if constexpr (rows) {
        x.resize(static_cast<index_t>(count), 3);
        ar.matrix(name, x);
      } else {
        x.resize(static_cast<std::size_t>(count));
        ar.array(name, x);
      }
    };
    if (ar.saving() || ar.loading()) {
      pass(v);
    } else {
      V dry;
      pass(dry);
    }
  };
  // per pair
  sized("detected/pair/a", pair_a_, n_pairs);
  sized("detected/pair/b", pair_b_, n_pairs);
  sized("detected/pair/param", pair_param_, n_pairs);
  sized("detected/pair/first", pair_first_, n_pairs + 1);
  sized("detected/pair/feature", feature_, n_pairs);
  sized("detected/pair/feature_a", feature_a_, n_pairs);
  sized("detected/pair/feature_b", feature_b_, n_pairs);
  sized("detected/pair/side_a", side_a_, n_pairs);
  sized("detected/pair/side_b", side_b_, n_pairs);
  for (int j = 0; j < 3; ++j) sized("detected/pair/normal/" + std::to_string(j), normal_[at(j)], n_pairs);
  sized("detected/pair/pose_rotation", poses_.rot, n_pairs);  // (the blocks' relative pose at the pair's detection)
  sized("detected/pair/pose_shift", poses_.shift, n_pairs);
  // per sub-contact
  sized("detected/subcontact/pair", pair_, n);
  sized("detected/subcontact/label", key_label_, n);
  sized("detected/subcontact/normal", corner_normal_, n);
  sized("detected/subcontact/area", area_, n);
  sized("detected/subcontact/fresh", fresh_, n);
  for (int k = 0; k < 8; ++k) sized("detected/subcontact/weight/" + std::to_string(k), weight_[at(k)], n);
  for (int c = 0; c < 3; ++c) sized(std::string("detected/subcontact/force_a/") + "xyz"[c], force_[at(c)], n);
  if (options_.deformable_blocks) {
    for (int k = 0; k < 8; ++k) sized("detected/subcontact/gridpoint/" + std::to_string(k), node_[at(k)], n);
    ar.scalar("detected/max_deviation", max_deviation_);
  }
  if (ar.loading()) state_.resize(static_cast<std::size_t>(n));
  law::checkpoint_states<Law>(
      ar, "detected/state/", static_cast<std::size_t>(n), [&](std::size_t i) { return state_[i]; },
      [&](std::size_t i, const state_type& st) { state_[i] = st; });
  // rebuild trigger, books, statistics
  ar.matrix("detected/rebuild_displacement", rebuild_u_);
  ar.scalar("detected/steps_since_rebuild", steps_since_rebuild_);
  ar.scalar("detected/retired/stored", retired_.stored);
  ar.scalar("detected/retired/dissipated", retired_.dissipated);
  ar.scalar("detected/retired/dissipated_tension", retired_.dissipated_tension);
  ar.scalar("detected/retired/dissipated_shear", retired_.dissipated_shear);
  ar.scalar("detected/retired/dissipated_compression", retired_.dissipated_compression);
  ar.scalar("detected/retired/rebuild_exchange", retired_.rebuild_exchange);
  ar.scalar("detected/rebuilds", rebuilds_);
  ar.scalar("detected/growths", growths_);
  ar.scalar("detected/peak_subcontacts", peak_subcontacts_);
  ar.scalar("detected/kept_last_rebuild", kept_last_);
  // Tasks and gather slots follow from the pairs and weights.
  if (ar.loading()) index_subcontacts();
  // The boxes at detection follow from rebuild_u_.
  if (ar.loading() && !options_.deformable_blocks)
    for (std::size_t b = 0; b < blocks_.size(); ++b) detected_box_[b] = box_at_detection(b);
}

}  // namespace tessera::contact
