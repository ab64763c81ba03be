#pragma once
// The crack analysis of the RC beam (beam.hpp) and the classification of its failure.
//
// Cracks of a beam. Flexural and diagonal cracks do not cut the beam into pieces, so the
// through-crack analysis of the ties (analysis::crack_graph) does not apply.
// During the run (beam_cracks, for the first developed crack and the first inclined one):
//   - a sub-contact is cracked when it is past its tensile peak (softened);
//   - a face (the sub-contacts of one block pair) is cracked when at least half its area is;
//   - cracked faces that share a block and whose centres lie within 1.5 mean block sizes belong
//     to the same crack (union-find); a crack is kept when it spans at least a quarter of the
//     depth; its inclination is the angle from the vertical of the area-weighted least-squares
//     line x(y) through its sub-contacts (below 35 degrees: vertical, else inclined); its position
//     the mean x of its lowest third.
//   Once many faces have softened (past yield) these clusters merge into one, so:
// At the end (beam_crack_profile): the opening profile along the span; a crack is a local maximum
// of the opening in the lower third of the depth that reaches beam_loading::crack_width (0.1 mm,
// a crack one sees), maxima closer than 0.75 block sizes being one crack, each followed layer by
// layer up the depth (beam_opening_maxima), its angle that of its path. A flexural crack is one
// in the constant-moment zone vertical about its x (beam_crack::locally_vertical); the count and
// mean spacing are over that zone mirrored about the symmetry face (the whole beam's zone, as the
// study counts; the full beam's zone as it is).
// Failure mode (beam_failure_mode), from the widest crack: none when no crack reaches crack_width;
// its path inclined (35 degrees or more) and in the shear span -> diagonal_tension; else crushing
// when the compressive cap has dissipated more than tensile cracking; else flexure.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "rc_beam/beam.hpp"

namespace tessera::scenes {

struct beam_crack {
  real x = 0;             ///< position along the span: mean x of its lowest third (m)
  real y_min = 0, y_max = 0;
  real angle_deg = 0;     ///< from the vertical, of its path (beam_opening_maxima) where it has one
  /// From the vertical, of the sub-contacts within 1.5 block sizes of x over the whole depth
  /// (beam_opening_maxima; the flexural crack count's reading, as angle_deg for beam_cracks).
  real local_angle_deg = 0;
  real width = 0;         ///< largest separation of its sub-contacts (m)
  real area = 0;          ///< cracked face area (m^2)
  /// Its path through the depth (beam_opening_maxima): x (m) in each layer ridge_layer (m) high
  /// from y = 0, NaN in the layers it does not reach; empty for the cracks of beam_cracks.
  std::vector<real> ridge_x;
  real ridge_layer = 0;
  [[nodiscard]] bool vertical() const { return angle_deg < 35; }
  /// Vertical about its foot's x (local_angle_deg): a crack of the constant-moment zone the study
  /// would count, whatever its path does in the crushed zone under the loading plate.
  [[nodiscard]] bool locally_vertical() const { return local_angle_deg < 35; }
};

/// The layer (of `layers`, each `layer` m high from y = 0) that height y (m) falls in; below 0 the
/// first, above the top the last.
[[nodiscard]] inline std::size_t beam_layer_of(real y, real layer, std::size_t layers) {
  return std::min(layers - 1, static_cast<std::size_t>(std::max(real(0), y) / layer));
}

/// Whether a sub-contact at p with value w (beam_opening_maxima's opening; < 0 left out) belongs to
/// crack cr: within 0.75 block sizes `cell` (m) of its path in its layer and at least 30 % of its width.
[[nodiscard]] inline bool beam_crack_member(const beam_crack& cr, real cell, const vec3& p, real w) {
  if (w < 0 || w < 0.3 * cr.width || cr.ridge_x.empty()) return false;
  const std::size_t l = beam_layer_of(p.y(), cr.ridge_layer, cr.ridge_x.size());
  return std::abs(p.x() - cr.ridge_x[l]) <= 0.75 * cell;  // false in a layer it does not reach (NaN)
}

/// Opening of sub-contact i: the separation of its two gridpoints, opening and slip (m).
template <class Contacts>
[[nodiscard]] real subcontact_opening(const Contacts& c, const node_set& gp, index_t i) {
  return (gp.position(c.node_b(i)) - gp.position(c.node_a(i))).norm();
}

/// Weighted least-squares line x(y) through points of a crack; its angle from the vertical.
struct crack_line_fit {
  double sw = 0, sx = 0, sy = 0, sxy = 0, syy = 0;
  void add(double w, const vec3& p) {
    sw += w, sx += w * p.x(), sy += w * p.y(), sxy += w * p.x() * p.y(), syy += w * p.y() * p.y();
  }
  /// Degrees from the vertical; 90 when the points lie at one height.
  [[nodiscard]] real angle_deg() const {
    const double my = sy / sw, var_y = syy / sw - my * my, cov = sxy / sw - (sx / sw) * my;
    return var_y > 0 ? std::atan(std::abs(cov / var_y)) * 180 / std::numbers::pi : 90;
  }
};

/// Crack analysis of a beam (see the file comment). Built once from the contact set; evaluate()
/// allocates its report (not for the step loop).
class beam_cracks {
 public:
  template <class Contacts>
  beam_cracks(const Contacts& c, const node_set& gp, real height, real cell_size)
      : height_(height), cell_(cell_size) {
    // Faces: contiguous runs of one block pair.
    for (index_t i = 0; i < c.size(); ++i) {
      const index_t a = c.block_a(i), b = c.block_b(i);
      if (faces_.empty() || faces_.back().a != a || faces_.back().b != b || faces_.back().end != i)
        faces_.push_back({a, b, i, i, vec3::Zero(), 0});
      face& f = faces_.back();
      f.end = i + 1;
      f.centre += c.area(i) * c.position(i, gp);
      f.area += c.area(i);
    }
    index_t blocks = 0;
    for (face& f : faces_) {
      if (f.area > 0) f.centre /= f.area;
      blocks = std::max({blocks, f.a + 1, f.b + 1});
    }
    block_faces_.assign(static_cast<std::size_t>(blocks), {});
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      block_faces_[static_cast<std::size_t>(faces_[k].a)].push_back(k);
      block_faces_[static_cast<std::size_t>(faces_[k].b)].push_back(k);
    }
  }

  /// Cracks whose sub-contacts are softened, and separated by w_open if w_open > 0.
  template <class Contacts>
  [[nodiscard]] std::vector<beam_crack> evaluate(const Contacts& c, const node_set& gp, real w_open) const {
    const auto jump = [&](index_t i) { return subcontact_opening(c, gp, i); };
    std::vector<char> cracked(faces_.size(), 0);
    for (std::size_t k = 0; k < faces_.size(); ++k) {
      real a = 0;
      for (index_t i = faces_[k].first; i < faces_[k].end; ++i)
        if (analysis::crack_graph::past_peak(c.state(i).flags) && (w_open <= 0 || jump(i) >= w_open)) a += c.area(i);
      cracked[k] = a >= 0.5 * faces_[k].area && faces_[k].area > 0;
    }
    std::vector<std::size_t> parent(faces_.size());
    for (std::size_t k = 0; k < parent.size(); ++k) parent[k] = k;
    const auto find = [&](std::size_t k) {
      while (parent[k] != k) k = parent[k] = parent[parent[k]];
      return k;
    };
    const real reach2 = (1.5 * cell_) * (1.5 * cell_);
    for (const auto& list : block_faces_)
      for (std::size_t p = 0; p < list.size(); ++p)
        for (std::size_t q = p + 1; q < list.size(); ++q) {
          const std::size_t f = list[p], g = list[q];
          if (cracked[f] && cracked[g] && (faces_[f].centre - faces_[g].centre).squaredNorm() <= reach2)
            parent[find(f)] = find(g);
        }
    std::map<std::size_t, std::vector<std::size_t>> groups;
    for (std::size_t k = 0; k < faces_.size(); ++k)
      if (cracked[k]) groups[find(k)].push_back(k);
    std::vector<beam_crack> out;
    for (const auto& [root, list] : groups) {
      beam_crack cr;
      crack_line_fit fit;
      cr.y_min = height_;
      cr.y_max = 0;
      for (std::size_t k : list) {
        cr.area += faces_[k].area;
        for (index_t i = faces_[k].first; i < faces_[k].end; ++i) {
          const vec3 p = c.position(i, gp);
          fit.add(c.area(i), p);
          cr.y_min = std::min(cr.y_min, p.y());
          cr.y_max = std::max(cr.y_max, p.y());
          cr.width = std::max(cr.width, jump(i));
        }
      }
      if (cr.y_max - cr.y_min < 0.25 * height_ || fit.sw <= 0) continue;
      cr.angle_deg = cr.local_angle_deg = fit.angle_deg();
      double lw = 0, lx = 0;
      const real low = cr.y_min + (cr.y_max - cr.y_min) / 3;
      for (std::size_t k : list)
        for (index_t i = faces_[k].first; i < faces_[k].end; ++i) {
          const vec3 p = c.position(i, gp);
          if (p.y() <= low) lw += c.area(i), lx += c.area(i) * p.x();
        }
      cr.x = lw > 0 ? lx / lw : fit.sx / fit.sw;
      out.push_back(cr);
    }
    std::sort(out.begin(), out.end(), [](const beam_crack& p, const beam_crack& q) { return p.x < q.x; });
    return out;
  }

 private:
  struct face {
    index_t a, b, first, end;
    vec3 centre;
    real area;
  };
  real height_, cell_;
  std::vector<face> faces_;
  std::vector<std::vector<std::size_t>> block_faces_;
};

/// Cracks as the maxima of an opening field along the span: in bins of 5 mm along x, the largest
/// value opening(i) (m) of the sub-contacts at or below y_top; a crack is a bin whose value is at
/// least `width` (> 0) and the largest within +-0.75 mean block sizes `cell` (neighbouring maxima
/// closer than that are one crack). opening(i) < 0 leaves sub-contact i out.
/// Its path (beam_crack::ridge_x): the depth cut in layers half a block size high; from the layer
/// where the crack's bin opens most, layer by layer up and down, the bin of the largest value within
/// 1.5 block sizes of the last one (an inclination up to 72 degrees from the vertical; three block
/// sizes over a layer with nothing), as long as that value is at least 30 % of the crack's own.
/// Its angle from the vertical: the opening-weighted least-squares line x(y) through that path (a
/// diagonal crack that leaves the soffit steeply is followed up to the loading plate, not read from
/// the sub-contacts above its foot); its members (beam_crack_member): the sub-contacts within 0.75
/// block sizes of the path whose value is at least 30 % of its own, their area its area. Its local
/// angle (beam_crack::local_angle_deg): the same line through the sub-contacts within 1.5 block
/// sizes of its x whose value is at least 30 % of its own, over the whole depth.
template <class Contacts, class Opening>
[[nodiscard]] std::vector<beam_crack> beam_opening_maxima(const Contacts& c, const node_set& gp, real height, real cell,
                                                          real width, real y_top, Opening&& opening_of) {
  constexpr real bin = 0.005;
  real x_max = 0;
  for (index_t i = 0; i < c.size(); ++i) x_max = std::max(x_max, c.position(i, gp).x());
  const auto bins = static_cast<std::size_t>(x_max / bin) + 1;
  const real layer = cell / 2;
  const auto layers = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(height / layer)));
  const auto bin_of = [&](real x) { return std::min(bins - 1, static_cast<std::size_t>(std::max(real(0), x) / bin)); };
  std::vector<real> opening(bins, 0), field(layers * bins, -1);  // field: the largest value per layer and bin
  for (index_t i = 0; i < c.size(); ++i) {
    const vec3 p = c.position(i, gp);
    const real w = opening_of(i);
    if (w < 0) continue;
    real& f = field[beam_layer_of(p.y(), layer, layers) * bins + bin_of(p.x())];
    f = std::max(f, w);
    if (p.y() <= y_top) opening[bin_of(p.x())] = std::max(opening[bin_of(p.x())], w);
  }
  const auto reach = static_cast<std::size_t>(std::ceil(0.75 * cell / bin));
  const auto step = static_cast<std::size_t>(std::ceil(1.5 * cell / bin));
  std::vector<beam_crack> out;
  for (std::size_t k = 0; k < bins; ++k) {
    if (opening[k] < width) continue;
    bool peak = true;
    for (std::size_t j = k > reach ? k - reach : 0; j <= std::min(bins - 1, k + reach) && peak; ++j)
      peak = opening[j] < opening[k] || (opening[j] == opening[k] && j >= k);
    if (!peak) continue;
    beam_crack cr;
    cr.x = (static_cast<real>(k) + 0.5) * bin;
    cr.width = opening[k];
    cr.ridge_layer = layer;
    cr.ridge_x.assign(layers, std::numeric_limits<real>::quiet_NaN());
    std::size_t l0 = 0;  // the layer where bin k opens most, at or below y_top
    for (std::size_t l = 0; l < layers && static_cast<real>(l) * layer <= y_top; ++l)
      if (field[l * bins + k] > field[l0 * bins + k]) l0 = l;
    cr.ridge_x[l0] = cr.x;
    crack_line_fit fit;
    fit.add(field[l0 * bins + k], vec3(cr.x, (static_cast<real>(l0) + 0.5) * layer, 0));
    std::size_t lo = l0, hi = l0;
    for (const int dir : {1, -1}) {
      std::size_t at = k, misses = 0;
      const auto top = static_cast<std::ptrdiff_t>(layers);
      for (auto l = static_cast<std::ptrdiff_t>(l0) + dir; l >= 0 && l < top && misses < 2; l += dir) {
        const std::size_t span = (misses + 1) * step, row = static_cast<std::size_t>(l) * bins;
        std::size_t best = bins;
        for (std::size_t j = at > span ? at - span : 0; j <= std::min(bins - 1, at + span); ++j)
          if (field[row + j] >= 0.3 * cr.width && (best == bins || field[row + j] > field[row + best])) best = j;
        if (best == bins) {
          ++misses;
          continue;
        }
        misses = 0;
        at = best;
        const real xr = (static_cast<real>(best) + 0.5) * bin;
        cr.ridge_x[static_cast<std::size_t>(l)] = xr;
        fit.add(field[row + best], vec3(xr, (static_cast<real>(l) + 0.5) * layer, 0));
        (dir > 0 ? hi : lo) = static_cast<std::size_t>(l);
      }
    }
    cr.y_min = static_cast<real>(lo) * layer;
    cr.y_max = std::min(height, static_cast<real>(hi + 1) * layer);
    cr.angle_deg = hi > lo ? fit.angle_deg() : 0;  // one layer: no line to fit, read as vertical
    crack_line_fit local;  // and the members' area, in the same pass
    for (index_t i = 0; i < c.size(); ++i) {
      const vec3 p = c.position(i, gp);
      const real w = opening_of(i);
      if (std::abs(p.x() - cr.x) <= 1.5 * cell && w >= 0 && w >= 0.3 * cr.width) local.add(w, p);
      if (beam_crack_member(cr, cell, p, w)) cr.area += c.area(i);
    }
    if (local.sw > 0) cr.local_angle_deg = local.angle_deg();
    out.push_back(std::move(cr));
  }
  return out;
}

/// The cracks of a beam at the end of a run, from its opening profile along the span
/// (beam_opening_maxima): the opening (gridpoint separation) of the softened sub-contacts, located
/// in the lower third of the depth, reaching `width` (m).
template <class Contacts>
[[nodiscard]] std::vector<beam_crack> beam_crack_profile(const Contacts& c, const node_set& gp, real height,
                                                         real cell, real width) {
  return beam_opening_maxima(c, gp, height, cell, width, height / 3, [&](index_t i) {
    return analysis::crack_graph::past_peak(c.state(i).flags) ? subcontact_opening(c, gp, i) : real(-1);
  });
}

/// The failure mode of a beam from its widest crack at the end (file comment): "none" when it is
/// narrower than `crack_width` (m); "diagonal_tension" when it is inclined and lies in the shear
/// span (between the support axis and the loading plate's far edge, either span of the full beam);
/// else "crushing" when the
/// compressive cap dissipated more than tensile cracking (J), else "flexure".
[[nodiscard]] inline std::string beam_failure_mode(const beam_crack& widest, const beam_options& o, real crack_width,
                                                   real compression_dissipated, real tension_dissipated) {
  if (widest.width < crack_width) return "none";
  if (!widest.vertical() && beam_shear_span_of(o, widest.x, o.plate / 2) >= 0) return "diagonal_tension";
  if (compression_dissipated > tension_dissipated) return "crushing";
  return "flexure";
}

}  // namespace tessera::scenes
