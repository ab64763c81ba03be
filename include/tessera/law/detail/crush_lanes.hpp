#pragma once
// The step's cap that softens with crushing (compression.hpp softening_cap), written once for the
// laws that take it (cohesive_frictional, mixed_mode_cohesive): on the lanes' normal stress after
// their tension limits, the return onto the cap f(u_crush), u_p and u_crush advanced, the flag
// `crushed` set at a first crush (or that lane declined on the pack path).

#include "../../core/lanes.hpp"
#include "../../core/types.hpp"
#include "../concepts.hpp"
#include "../lane_masks.hpp"

namespace tessera::law::detail {

/// Returns the lanes x (a law's elastic_lanes: u_n, u_p, u_crush) whose normal stress `sigma` (Pa,
/// + tension) lies beyond the cap f(x.u_crush) of `Compression` (a SofteningCompressionLimit) with
/// parameters c, at normal stiffness k_n (Pa/m), onto it. Transitions: a first crush sets the flag
/// `crushed` in `flags`; otherwise such a lane is cleared from `accepted`. T = real or a lanes::pack.
template <class Compression, bool Transitions, class T, class M, class F, class Lanes>
[[gnu::always_inline]] inline void crush_lanes(const typename Compression::params& c, real k_n, F& flags, Lanes& x,
                                              T& sigma, M& accepted) noexcept {
  constexpr auto crushed_bit = static_cast<lanes::mask_lane>(contact_status::crushed);
  // No lane below the residual cap (almost always): none can crush, nothing to evaluate.
  if (!lanes::any(sigma < -Compression::residual_strength(c))) [[likely]]
    return;
  // Uncrushed lanes (u_crush = 0, flag unset) have the cap f_c exactly: no envelope evaluated.
  const M crushed = flag_mask<M>(flags, crushed_bit);
  T cap = lanes::splat<T>(Compression::strength(c));
  if (lanes::any(crushed)) cap = mask_select(crushed, Compression::lane_strength(c, x.u_crush), cap);
  const M crushing = sigma < -cap;
  if constexpr (Transitions) {
    if (crushing) flags = static_cast<F>(flags | crushed_bit);
  } else {
    accepted = accepted & mask_not(crushing & mask_not(crushed));
  }
  if (lanes::any(crushing)) [[unlikely]] {
    const auto r = Compression::lane_crush_return(c, k_n, -sigma, x.u_crush);
    sigma = mask_select(crushing, -r.cap, sigma);
    x.u_p = mask_select(crushing, x.u_n + r.cap / k_n, x.u_p);
    x.u_crush = mask_select(crushing, r.kappa, x.u_crush);
  }
}

}  // namespace tessera::law::detail
