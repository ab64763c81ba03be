#pragma once
// The beam's failure rule at one sample (issue #63): the default, the load --failure-drop below
// its peak (update_failure, beam_result.hpp, with --failure-confirm), or --failure-crack diagonal:
// a drop is the failure only when what broke since the peak (the crack that opened, or the band that softened) is shear.
//
// Why. On the 60-block beam with bars that cannot yield, the load can fall 25 % at the first
// flexural cracks under the loading plate and climb back to three times as much (a transient dip),
// while the drop at the diagonal cracking, the shear figure's event, may hold for less deflection
// than such a dip: no window of deflection tells them apart (docs/studies/one_concrete.md, "How long
// a drop holds"). The crack that opens as the load falls does.
//
// The rule. A drop is judged once, at its first sample below (1 - failure_drop) x the peak, by two
// readings of what happened since the peak:
//   - the opening: the opening history (beam_opening_history) with the present state as its last
//     snapshot, read by beam_fastest_inclined_after_peak (beam_post_peak.hpp) on each shear span:
//     diagonal when an inclined crack in the shear span gained at least crack_width since the peak,
//     opening faster than every flexural crack of the constant-moment zone, while the load fell at
//     least 5 % of the peak (diagonal_crack_after_peak);
//   - the damage: each sub-contact's tensile damage gain since the peak (the damage kept at every
//     new peak), its maxima along the span (beam_opening_maxima, at least half a damage), and the
//     band of the largest area: a shear band when it lies in a shear span (support axis to the
//     loading plate's far edge), whatever its angle.
// The drop is the failure when the opening is diagonal or the band is a shear band. Else it is a
// dip: its deflection goes to beam_result::dip_deflections and the run goes on; the later samples
// of the same drop are not judged again (the load must climb back above the threshold, or a new
// peak be set, before another drop can be judged). The judgement reads only the samples, the
// history and the damage at the peak, all in the checkpoint, so a resumed run judges as one that
// never stopped.
//
// What it sees (60-block beam, bars that cannot yield, mixed-mode law, G_II 70 J/m^2; docs/studies/
// one_concrete.md, "Judging a drop by its crack"): seed 1's drop at 3.67 mm, a crack at x = 198 mm,
// 37 deg, opening 0.18 mm (damage band x = 218 mm, 41 deg): the failure; seed 2's dip at 0.89 mm, no
// inclined crack and the band at x = 558 mm in the constant-moment zone: a dip; seed 3's drop at
// 3.42 mm, whose crack has opened 5 micrometres (the contacts soften before the crack opens) but
// whose band runs from the soffit to the top face at x = 248 mm: the failure.

#include <cstddef>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

#include "rc_beam/beam_post_peak.hpp"
#include "rc_beam/beam_result.hpp"

namespace tessera::scenes {

/// The diagonal crack that opened since the peak, judged at a sample of deflection defl (m) and
/// smoothed load (N), on a copy of the history with the present state last; both shear spans of
/// the full beam (beam_faster_span: a diagonal one, of two the larger opening since the peak).
/// cell: the mean block size (m).
template <class Contacts>
[[nodiscard]] beam_post_peak_crack beam_crack_of_drop(const Contacts& c, const node_set& gp,
                                                      const beam_opening_history& history, const beam_options& o,
                                                      real cell, real crack_width, const beam_result& r, real defl,
                                                      real load) {
  beam_opening_history probe = history;
  probe.finish(c, gp, defl, load, r.peak_deflection);
  probe.append_end(c, gp, defl, load);
  const beam_post_peak_crack left =
      beam_fastest_inclined_after_peak(c, gp, probe, o, cell, crack_width, r.peak_load, r.peak_deflection);
  if (!o.full()) return left;
  const beam_post_peak_crack right =
      beam_fastest_inclined_after_peak(c, gp, probe, o, cell, crack_width, r.peak_load, r.peak_deflection, 1);
  return beam_faster_span(left, right, true);
}

/// The band of sub-contacts that lost the most tensile strength since the peak: the maxima along the
/// span of each sub-contact's tensile damage gain since the peak (damage_at_peak; at least 0.05),
/// of at least half a damage, the one of the largest area (its members' area, beam_opening_maxima).
template <class Contacts>
[[nodiscard]] beam_crack beam_damage_band_of_drop(const Contacts& c, const node_set& gp, const beam_options& o, real cell,
                                                  const std::vector<float>& damage_at_peak) {
  using law_t = typename std::decay_t<Contacts>::law_type;
  const auto gain = [&](index_t i) {
    const auto k = static_cast<std::size_t>(i);
    if (k >= damage_at_peak.size()) return real(-1);
    const real d = law_t::tensile_damage(c.subcontact_params(i), c.state(i)) - real(damage_at_peak[k]);
    return d >= 0.05 ? d : real(-1);
  };
  beam_crack best;
  for (const beam_crack& b : beam_opening_maxima(c, gp, o.height, cell, 0.5, o.height, gain))
    if (b.area > best.area) best = b;
  return best;
}

/// Keeps the tensile damage of every sub-contact at the peak (the rule's damage reading).
template <class Contacts>
void beam_keep_damage_at_peak(const Contacts& c, std::vector<float>& damage_at_peak) {
  using law_t = typename std::decay_t<Contacts>::law_type;
  damage_at_peak.resize(static_cast<std::size_t>(c.size()));
  for (index_t i = 0; i < c.size(); ++i)
    damage_at_peak[static_cast<std::size_t>(i)] = static_cast<float>(law_t::tensile_damage(c.subcontact_params(i), c.state(i)));
}

/// One line on the crack read at a drop (beam_crack_of_drop): where it is, how fast it opened, and
/// whether that reading alone is diagonal (the verdict also weighs the damage band).
[[nodiscard]] inline std::string beam_drop_crack_text(const beam_post_peak_crack& k) {
  if (!k.found) return "no inclined crack in the shear span opened since the peak";
  char buf[320];
  std::snprintf(buf, sizeof buf, "the fastest inclined crack since the peak, x = %.0f mm at %.0f deg, opened %.3f mm at "
                "%.2f mm per mm of deflection (the flexural cracks' fastest %.2f) while the load fell %.2f kN: %s",
                k.x * 1e3, k.angle_deg, k.opening_increase * 1e3, k.opening_rate, k.flexural_opening_rate,
                k.load_drop * 1e-3, k.diagonal ? "diagonal" : "not diagonal");
  return buf;
}

/// The failure rule at one sample (file comment): r holds this sample last (load N, defl m),
/// max_load the peak so far (N), first_found whether the first flexural crack was found. Returns
/// whether the run failed here; with loading.failure_needs_diagonal a drop judged a dip is added to
/// r.dip_deflections.
template <class Contacts>
[[nodiscard]] bool beam_failure_at_sample(beam_result& r, const beam_loading& loading, bool first_found, real load,
                                          real defl, real max_load, const Contacts& c, const node_set& gp,
                                          const beam_opening_history& history, const beam_options& o, real cell) {
  if (!loading.failure_needs_diagonal) return update_failure(r, loading, first_found, load, defl, max_load);
  if (load >= max_load && defl == r.peak_deflection) beam_keep_damage_at_peak(c, r.damage_at_peak);  // a new peak
  const real threshold = (1 - loading.failure_drop) * max_load;
  if (!first_found || load >= threshold || defl <= r.peak_deflection) return false;
  // Judged already at the drop's first sample (a dip, or the run would have stopped there).
  const std::size_t n = r.deflection.size();
  if (n >= 2 && r.smoothed_load[n - 2] < threshold && r.deflection[n - 2] > r.peak_deflection) return false;
  const beam_post_peak_crack k = beam_crack_of_drop(c, gp, history, o, cell, loading.crack_width, r, defl, load);
  const beam_crack band = beam_damage_band_of_drop(c, gp, o, cell, r.damage_at_peak);
  const bool shear_band = band.area > 0 && beam_shear_span_of(o, band.x, o.plate / 2) >= 0;
  if (loading.progress)  // the reading, beside the progress line: what the rule saw
    std::fprintf(stderr, "\nrc_beam: the load fell %.0f %% below its peak (%.2f kN at %.3f mm) at %.3f mm: %s; the band "
                 "that lost the most tensile strength since the peak: x = %.0f mm (%s), %.0f deg, y = %.0f-%.0f mm, "
                 "%.0f mm2: %s\n", 100 * loading.failure_drop, r.peak_load * 1e-3, r.peak_deflection * 1e3, defl * 1e3,
                 beam_drop_crack_text(k).c_str(), band.x * 1e3, shear_band ? "the shear span" : "not the shear span",
                 band.angle_deg, band.y_min * 1e3, band.y_max * 1e3, band.area * 1e6,
                 k.diagonal || shear_band ? "the failure" : "a dip, the run goes on");
  if (k.diagonal || shear_band) {
    r.failure_deflection = defl;
    return true;
  }
  r.dip_deflections.push_back(defl);
  return false;
}

/// The rule's state in a checkpoint (with failure_needs_diagonal only): the dips so far and the
/// damage at the peak.
template <class Archive>
void checkpoint_failure_rule(Archive& ar, const beam_loading& loading, beam_result& r) {
  if (!loading.failure_needs_diagonal) return;
  ar.sized_array("beam/run/dip_deflections", r.dip_deflections);
  ar.sized_array("beam/run/damage_at_peak", r.damage_at_peak);
}

}  // namespace tessera::scenes
