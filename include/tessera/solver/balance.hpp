#pragma once
// Out-of-balance measure and a loading rate driven by it.
//
// The unbalanced force of a node is what its free components are accelerated by in the last
// step: the zone, contact, bar and body forces before damping (node_set::force after a step;
// prescribed components carry reactions instead and are left out). In a quasi-static loading at a
// steady rate it is small against the forces the supports carry; a contact that softens, a crack
// that opens or a sudden change of the loading rate throws it up. 3DEC and FLAC call a model in
// equilibrium when the ratio of the unbalanced force to the applied forces falls below a
// tolerance; here the ratio (of the largest nodal unbalanced force to a reference force the
// caller chooses, e.g. the load a crack section carries) sets how fast the loading may go:
//
//   adaptive_rate   factor f in [min_factor, max_factor] (min <= 1 <= max) on a base rate,
//                   starting at 1. At each sample: ratio above `high` -> f = min_factor at once
//                   (a crack forming is run at the slow rate, whose accuracy the caller has
//                   measured); ratio below `low` -> f grows by `growth` (a geometric ramp, so the
//                   loading accelerates smoothly); in between f is held. The fastest rate must
//                   pass the scene's quasi-static check.
//
// Measured on the 100-block RC tie (docs/validation.md, "error against run time"): the ratio
// marks a crack forming, but stays high through the whole cracking phase, so the control saves
// few steps there (9 % against the fixed slow rate of about the same accuracy).
//
// Costs O(nodes) per call; call it at samples, not every step. The result does not depend on the
// thread count (a serial loop over the nodes in index order).

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"

namespace tessera {

/// Unbalanced force of the last step over free node components (N).
struct out_of_balance {
  real max_force = 0;    ///< largest |f| of a node over its free components
  real mean_force = 0;   ///< mean of that magnitude over nodes with a free component
  index_t max_node = -1;   ///< the node of max_force (-1 when none is free)
  index_t nodes = 0;       ///< nodes with at least one free component

  /// Adds node i of `n` under the label `node` (default i): its force over the free components;
  /// none free: skipped.
  void add(const node_set& n, index_t i, index_t node = -1) {
    constexpr auto free = static_cast<std::uint8_t>(dof_constraint::free);
    add_free(node < 0 ? i : node, [&](int c) { return n.constraint(i, c) == free; },
             [&](int c) { return n.force(i, c); });
  }
  /// Adds the magnitude of force(c) over the components c with is_free(c); none free: skipped.
  template <class IsFree, class Force>
  void add_free(index_t node, IsFree&& is_free, Force&& force) {
    real sq = 0;
    bool any = false;
    for (int c = 0; c < 3; ++c)
      if (is_free(c)) {
        sq += force(c) * force(c);
        any = true;
      }
    if (any) add_magnitude(std::sqrt(sq), node);
  }
  /// Adds one node's unbalanced force magnitude (N).
  void add_magnitude(real f, index_t node) {
    if (f > max_force || max_node < 0) {
      max_force = f;
      max_node = node;
    }
    mean_force += (f - mean_force) / static_cast<real>(++nodes);
  }
};

/// The out-of-balance of every node of `n` (serial, in index order).
[[nodiscard]] inline out_of_balance unbalanced_force(const node_set& n) {
  out_of_balance b;
  for (index_t i = 0; i < n.size(); ++i) b.add(n, i);
  return b;
}

/// Loading rate set by the out-of-balance ratio (see the file comment).
class adaptive_rate {
 public:
  /// Bounds and gains of the rate control (each refused by adaptive_rate's constructor when out of range)
  struct params {
    real min_factor = 1;  ///< slowest rate over the base rate, taken while out of balance (<= 1)
    real max_factor = 1;  ///< fastest rate over the base rate (>= 1; min = max = 1: a fixed rate)
    real low = 0.01;      ///< ratio under which the factor grows
    real high = 0.03;     ///< ratio over which the factor drops to min_factor
    real growth = 1.02;   ///< factor on the factor per quiet sample
  };

  adaptive_rate() = default;
  /// Refuses not 0 < min_factor <= 1 <= max_factor, growth <= 1 (when the factor can move), or
  /// not 0 < low < high.
  explicit adaptive_rate(const params& p) : p_(p) {
    require(p.min_factor > 0 && p.min_factor <= 1, "adaptive rate: minimum factor ", p.min_factor,
            " must lie in (0, 1]");
    require(std::isfinite(p.max_factor) && p.max_factor >= 1, "adaptive rate: maximum factor ", p.max_factor,
            " must be >= 1");
    require(p.max_factor == p.min_factor || (std::isfinite(p.growth) && p.growth > 1), "adaptive rate: growth ",
            p.growth, " must be > 1");
    require(std::isfinite(p.high) && p.low > 0 && p.low < p.high, "adaptive rate: ratios low ", p.low, " and high ",
            p.high, " must satisfy 0 < low < high");
  }

  /// Feeds one sample's out-of-balance ratio; returns the factor on the base rate from now on.
  real update(real ratio) {
    if (!(ratio <= p_.high))  // NaN counts as out of balance
      factor_ = p_.min_factor;
    else if (ratio < p_.low)
      factor_ = std::min(p_.max_factor, factor_ * p_.growth);
    return factor_;
  }
  [[nodiscard]] real factor() const { return factor_; }  ///< Current factor on the base loading rate (-), in [min_factor, 1]

 private:
  params p_{};
  real factor_ = 1;
};

}  // namespace tessera
