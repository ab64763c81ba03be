#pragma once
// The crack that opens fastest after the peak (issue #41 item 4). beam_failure_mode reads the
// widest crack at the end; a diagonal crack that starts while a flexural crack is still the widest
// does not show there. So the run keeps the opening of every sub-contact on a grid of deflection
// (beam_opening_history; a finer grid and the end state where the run stopped within one grid
// step of its peak), and after the run:
//   1. the post-peak increment of each sub-contact, dw_i = w_i(end) - w_i(peak), where w is the
//      separation of its two gridpoints (m), "end" the last snapshot and "peak" the first snapshot
//      at or past the peak's deflection, on the sub-contacts past their tensile peak at the end;
//   2. the cracks of that increment field: its maxima along the span over the whole depth
//      (beam_opening_maxima: 5 mm bins, maxima closer than 0.75 block sizes one crack, each followed
//      layer by layer through the depth, its angle the increment-weighted line through that path),
//      of at least 1 % of crack_width;
//   3. the fastest inclined one: among the inclined (35 degrees or more from the vertical) in the
//      shear span (support axis to the loading plate's far edge; in the full beam the span asked
//      for, beam_shear_span_of), the largest increment, i.e. the
//      largest mean opening rate after the peak. Its opening W(j) at snapshot j is the largest
//      opening of its members (the sub-contacts along its path that gained at least 30 % of its
//      increment, beam_crack_member);
//   4. its window: from the last snapshot at which it has gained at most 10 % of its increment to
//      the first at which it has gained 90 %; its opening rate dW / d(deflection) over the window
//      (m per m), and the load it takes off: the smoothed load at the window's start less that at
//      its end (N). The same rate of the fastest flexural crack (locally vertical, in the
//      constant-moment zone) over the same window, for comparison.
// diagonal_crack_after_peak: the fastest inclined crack gains at least crack_width (a crack one
// sees) after the peak, opens faster over its window than every flexural crack (locally vertical,
// in the constant-moment zone), and the load falls by at least 5 % of the peak over that window.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rc_beam/beam.hpp"
#include "rc_beam/beam_cracks.hpp"

namespace tessera::scenes {

/// The openings (m, as float) of every sub-contact on a grid of mid-span deflection, with the
/// smoothed load (N). At most max_snapshots: when full, every other snapshot is dropped and the
/// grid step doubled, so memory stays at max_snapshots x sub-contacts x 4 bytes (250 blocks:
/// 27 000 sub-contacts, 28 MB) whatever the run's length.
/// Beside the grid it keeps the last recent_snapshots on a grid ten times finer (about 3 grid
/// steps; a tenth more memory). A brittle failure can stop the run (beam_loading::failure_drop) a
/// grid step or two after its peak: the grid then holds one or two snapshots from the peak on, the
/// last of them short of the stop, too few to see the failing crack open. finish() then puts the
/// fine snapshots and the end state in place of the grid's last ones; a run that ends more than
/// about three grid steps past its peak keeps its grid as it was.
class beam_opening_history {
 public:
  static constexpr std::size_t max_snapshots = 256;
  static constexpr std::size_t recent_snapshots = 30;
  explicit beam_opening_history(real step) : step_(step) {
    require(step > 0, "beam_opening_history: deflection step ", step, " m must be > 0");
  }
  /// Records a snapshot when the deflection (m) has passed the next grid point, and a fine one
  /// when it has passed the next point of the fine grid (a tenth of the step).
  template <class Contacts>
  void record(const Contacts& c, const node_set& gp, real deflection, real load) {
    const bool coarse = deflection_.empty() || deflection >= deflection_.back() + step_;
    const bool fine = recent_.empty() || deflection >= recent_.back().deflection + 0.1 * step_;
    if (!coarse && !fine) return;
    std::vector<float> w = openings(c, gp);
    if (fine) {
      recent_.push_back({deflection, load, w});
      if (recent_.size() > recent_snapshots) recent_.erase(recent_.begin());
    }
    if (!coarse) return;
    opening_.push_back(std::move(w));
    deflection_.push_back(deflection);
    load_.push_back(load);
    if (opening_.size() < max_snapshots) return;
    std::size_t kept = 0;
    for (std::size_t j = 0; j < opening_.size(); j += 2, ++kept) {
      opening_[kept] = std::move(opening_[j]);
      deflection_[kept] = deflection_[j];
      load_[kept] = load_[j];
    }
    opening_.resize(kept), deflection_.resize(kept), load_.resize(kept);
    step_ *= 2;
  }
  /// At the end of the run (deflection m, smoothed load N): if the peak (peak_deflection, m)
  /// lies within the fine snapshots' reach, the grid's snapshots from the first fine one on give
  /// way to the fine snapshots and the end state (class comment).
  template <class Contacts>
  void finish(const Contacts& c, const node_set& gp, real deflection, real load, real peak_deflection) {
    if (recent_.empty() || peak_deflection < recent_.front().deflection) return;
    // The end state last. As the load falls the mid-span can spring back: the end state then takes
    // the place of the fine snapshots at or past its deflection, so the grid stays increasing.
    while (!recent_.empty() && recent_.back().deflection >= deflection) recent_.pop_back();
    recent_.push_back({deflection, load, openings(c, gp)});
    while (!deflection_.empty() && deflection_.back() >= recent_.front().deflection)
      opening_.pop_back(), deflection_.pop_back(), load_.pop_back();
    for (snapshot& f : recent_) {
      opening_.push_back(std::move(f.opening));
      deflection_.push_back(f.deflection);
      load_.push_back(f.load);
    }
    recent_.clear();
  }
  /// Puts the state at deflection (m, past the grid's last snapshot) and smoothed load (N) last on
  /// the grid (beam_failure_rule.hpp's probe, after finish(), which may have put it there already).
  template <class Contacts>
  void append_end(const Contacts& c, const node_set& gp, real deflection, real load) {
    if (!deflection_.empty() && deflection <= deflection_.back()) return;
    opening_.push_back(openings(c, gp));
    deflection_.push_back(deflection);
    load_.push_back(load);
  }
  [[nodiscard]] std::size_t size() const { return opening_.size(); }
  [[nodiscard]] real deflection(std::size_t j) const { return deflection_[j]; }
  [[nodiscard]] real load(std::size_t j) const { return load_[j]; }
  [[nodiscard]] real opening(std::size_t j, index_t i) const { return opening_[j][static_cast<std::size_t>(i)]; }

  /// Saves or loads the snapshots (io/checkpoint.hpp; "beam/history/..."): the grid's step, its
  /// snapshots and the fine ones, each opening as the float it is kept in.
  template <class Archive>
  void checkpoint(Archive& ar) {
    ar.scalar("beam/history/step", step_);
    ar.sized_array("beam/history/deflection", deflection_);
    ar.sized_array("beam/history/load", load_);
    ar.sized_records("beam/history/grid/count", opening_, [&](std::vector<std::vector<float>>& t) {
      for (std::size_t j = 0; j < t.size(); ++j) ar.sized_array("beam/history/grid/" + std::to_string(j), t[j]);
    });
    std::vector<real> d, l;
    for (const snapshot& f : recent_) d.push_back(f.deflection), l.push_back(f.load);
    ar.sized_array("beam/history/fine/deflection", d);
    ar.sized_array("beam/history/fine/load", l);
    if (ar.loading()) {
      recent_.resize(d.size());
      for (std::size_t j = 0; j < d.size(); ++j) recent_[j].deflection = d[j], recent_[j].load = l[j];
    }
    ar.sized_records("beam/history/fine/count", recent_, [&](std::vector<snapshot>& t) {
      for (std::size_t j = 0; j < t.size(); ++j) ar.sized_array("beam/history/fine/" + std::to_string(j), t[j].opening);
    });
  }

 private:
  struct snapshot {
    real deflection, load;
    std::vector<float> opening;
  };
  template <class Contacts>
  [[nodiscard]] static std::vector<float> openings(const Contacts& c, const node_set& gp) {
    std::vector<float> w(static_cast<std::size_t>(c.size()));
    for (index_t i = 0; i < c.size(); ++i) w[static_cast<std::size_t>(i)] = static_cast<float>(subcontact_opening(c, gp, i));
    return w;
  }
  real step_;
  std::vector<real> deflection_, load_;
  std::vector<std::vector<float>> opening_;
  std::vector<snapshot> recent_;
};

/// The fastest-opening inclined crack after the peak (file comment).
struct beam_post_peak_crack {
  bool found = false;                 ///< an inclined crack in the shear span opened after the peak
  real x = 0, angle_deg = 0;          ///< its position (m) and angle from the vertical (deg)
  real y_min = 0, y_max = 0;          ///< the height range of its sub-contacts (m)
  real opening_increase = 0;          ///< W(end) - W(peak) (m)
  real window_start_deflection = 0, window_end_deflection = 0;  ///< m
  real opening_rate = 0;              ///< dW / d(deflection) over the window (m/m = mm per mm)
  real load_drop = 0;                 ///< smoothed load at the window's start less at its end (N)
  real flexural_opening_rate = 0;     ///< the fastest vertical crack of the moment zone, same window
  bool diagonal = false;              ///< diagonal_crack_after_peak (file comment)
};

/// The full beam's two shear spans read as one: the right span's crack when it counts (diagonal_only:
/// it is diagonal; else: it was found) and the left's does not or opened less since the peak, else
/// the left's. The drop's verdict (beam_failure_rule.hpp) asks for a diagonal crack, the end of the
/// run (beam_run.hpp) for the fastest one.
[[nodiscard]] inline const beam_post_peak_crack& beam_faster_span(const beam_post_peak_crack& left,
                                                                  const beam_post_peak_crack& right,
                                                                  bool diagonal_only) {
  const auto counts = [&](const beam_post_peak_crack& k) { return diagonal_only ? k.diagonal : k.found; };
  return counts(right) && (!counts(left) || right.opening_increase > left.opening_increase) ? right : left;
}

/// Finds the crack of the file comment from the history and the end state; peak_load (N) and
/// peak_deflection (m) of the run, crack_width (m) beam_loading's, shear_span the one to search
/// (0 the left, 1 the full beam's right: beam_shear_span_of).
template <class Contacts>
[[nodiscard]] beam_post_peak_crack beam_fastest_inclined_after_peak(const Contacts& c, const node_set& gp,
                                                                    const beam_opening_history& h,
                                                                    const beam_options& o, real cell,
                                                                    real crack_width, real peak_load,
                                                                    real peak_deflection, int shear_span = 0) {
  beam_post_peak_crack out;
  std::size_t jp = 0;
  while (jp < h.size() && h.deflection(jp) < peak_deflection) ++jp;
  if (h.size() < 2 || jp + 1 >= h.size()) return out;  // no snapshot after the peak
  const std::size_t je = h.size() - 1;
  const auto increment = [&](index_t i) {
    if (!analysis::crack_graph::past_peak(c.state(i).flags)) return real(-1);
    return std::max(real(0), h.opening(je, i) - h.opening(jp, i));
  };
  const std::vector<beam_crack> cracks = beam_opening_maxima(c, gp, o.height, cell, 0.01 * crack_width, o.height, increment);
  // The members of a crack (beam_crack_member: along its path) and their opening W(j).
  const auto members = [&](const beam_crack& cr) {
    std::vector<index_t> m;
    for (index_t i = 0; i < c.size(); ++i)
      if (beam_crack_member(cr, cell, c.position(i, gp), increment(i))) m.push_back(i);
    return m;
  };
  const auto opening_at = [&](const std::vector<index_t>& m, std::size_t j) {
    real w = 0;
    for (index_t i : m) w = std::max(w, h.opening(j, i));
    return w;
  };
  const beam_crack* best = nullptr;
  for (const beam_crack& cr : cracks)
    if (!cr.vertical() && beam_shear_span_of(o, cr.x, o.plate / 2) == shear_span && (!best || cr.width > best->width))
      best = &cr;
  if (!best) return out;
  const std::vector<index_t> m = members(*best);
  const real w0 = opening_at(m, jp), dw = opening_at(m, je) - w0;
  if (dw <= 0) return out;
  std::size_t ja = jp, jb = je;
  for (std::size_t j = jp; j <= je; ++j)
    if (opening_at(m, j) - w0 <= 0.1 * dw) ja = j;
  for (std::size_t j = je + 1; j-- > ja;)
    if (opening_at(m, j) - w0 >= 0.9 * dw) jb = j;
  if (jb <= ja) jb = std::min(je, ja + 1);
  const real span = h.deflection(jb) - h.deflection(ja);
  out.found = true;
  out.x = best->x;
  out.angle_deg = best->angle_deg;
  out.y_min = best->y_min;
  out.y_max = best->y_max;
  out.opening_increase = dw;
  out.window_start_deflection = h.deflection(ja);
  out.window_end_deflection = h.deflection(jb);
  out.opening_rate = span > 0 ? (opening_at(m, jb) - opening_at(m, ja)) / span : 0;
  out.load_drop = h.load(ja) - h.load(jb);
  for (const beam_crack& cr : cracks)
    if (cr.locally_vertical() && beam_in_moment_zone(o, cr.x) && span > 0) {
      const std::vector<index_t> v = members(cr);
      out.flexural_opening_rate = std::max(out.flexural_opening_rate, (opening_at(v, jb) - opening_at(v, ja)) / span);
    }
  out.diagonal = dw >= crack_width && out.opening_rate > out.flexural_opening_rate && out.load_drop >= 0.05 * peak_load;
  return out;
}

}  // namespace tessera::scenes
