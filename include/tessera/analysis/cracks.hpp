#pragma once
// Crack analysis of a contact set along any axis: through-cracks as cuts of the block graph,
// their positions along the axis, the cracks a bar crosses, and crack sites (surfaces grouped
// along the axis). Works on any contact::ContactSet whose sub-contacts know their blocks
// (block_a, block_b) and position (face_contacts; a detecting set that offers the same).
//
// Model. The sub-contacts are grouped into faces by their block pair (two convex blocks share at
// most one face). A face is *cracked* when every sub-contact on it satisfies a predicate; the
// pieces are the connected components of the block graph whose edges are the faces that are not
// cracked; a through-crack is a surface of cracked faces that separates the specimen into two
// pieces, so cracks = pieces - 1 (a bar, which crosses every crack, is not part of the graph).
// Its position is the area-weighted mean of position . axis over the cracked sub-contacts between
// the two pieces: z for the study's prism and tie (axis (0, 0, 1)), x for a beam's span.
// Three predicates are offered:
//  - softened: every sub-contact is past its tensile peak (softening or broken): a crack has
//    formed across the section and the section's tensile capacity is falling;
//  - opened: every sub-contact is softened and its two gridpoints have separated by at least
//    w_open (the drivers use 2 G_f / f_T, where linear softening has no strength left), the
//    separation being the whole displacement jump |x_B - x_A| (opening and slip), the
//    crack-opening displacement: faces of a tortuous crack that lie steeply to the axis open
//    mostly by sliding (a face at 65 deg to the section sees 0.42 of the axial opening as u_n);
//  - opened_normal_only: the normal opening u_n >= w_open on every sub-contact (stricter).
// Cost: construction O(S log S) for S sub-contacts; each evaluation O(S + blocks) with union-find
// and allocates its report. Not for the step loop: call it at samples or at the end of a run.

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../law/concepts.hpp"

namespace tessera::analysis {

/// Through-cracks of a specimen (crack_graph).
struct crack_report {
  int pieces = 1;  ///< connected pieces of the block graph
  int cracks = 0;  ///< pieces - 1
  /// Position along the axis of each surface between two separated pieces (m), ascending: more
  /// surfaces than cracks where three pieces touch pairwise (a slice that does not fill the section).
  std::vector<real> positions;
  /// Cracks the bar crosses: changes of piece from one bar node's host block to the next, walking
  /// the bar (-1 without a bar path). A fragment split off by a branching crack (a piece the bar
  /// does not pass through) adds a piece but no crossing.
  int bar_crossings = -1;
  std::vector<real> bar_crossing_positions;  ///< along the axis: the surface between the two pieces (m)
  real opening_threshold = 0;                ///< w_open (m)
  index_t open_subcontacts = 0;                ///< sub-contacts that satisfy the predicate
};

/// Crack sites: crack surface positions (any order) grouped where neighbouring positions lie less
/// than `spacing` apart, each group reported by its mean, ascending. With spacing = the mean cell
/// size, a crack that runs around a slice of blocks thinner than one cell, and so has two
/// separating surfaces, is one site, as it is one crack to the eye. Throws invalid_input for a
/// spacing that is not finite and > 0.
[[nodiscard]] TESSERA_INLINE std::vector<real> crack_sites(std::vector<real> positions, real spacing);

/// The block graph of a contact set and its through-cracks along `axis` (file comment).
class crack_graph {
 public:
  /// Groups the sub-contacts of `contacts` into faces by block pair. `blocks`: number of blocks;
  /// `axis`: the direction positions are measured along (normalised here). Throws invalid_input
  /// for a zero or non-finite axis, or a sub-contact naming a block outside [0, blocks).
  template <class Contacts>
  crack_graph(const Contacts& contacts, index_t blocks, const vec3& axis) : blocks_(blocks) {
    require(axis.allFinite() && axis.norm() > 0, "crack_graph: axis (", axis.x(), ", ", axis.y(), ", ", axis.z(),
            ") must be finite and non-zero");
    axis_ = axis / axis.norm();
    const index_t n = contacts.subcontact_count();
    order_.resize(static_cast<std::size_t>(n));
    std::iota(order_.begin(), order_.end(), index_t{0});
    const auto pair_of = [&](index_t i) { return std::pair<index_t, index_t>(contacts.block_a(i), contacts.block_b(i)); };
    for (index_t i = 0; i < n; ++i) {
      const auto [a, b] = pair_of(i);
      require(a >= 0 && a < blocks && b >= 0 && b < blocks, "crack_graph: sub-contact ", i, " joins blocks ", a,
              " and ", b, ", outside [0, ", blocks, ")");
    }
    std::stable_sort(order_.begin(), order_.end(), [&](index_t a, index_t b) { return pair_of(a) < pair_of(b); });
    for (std::size_t k = 0; k < order_.size();) {
      std::size_t e = k;
      while (e < order_.size() && pair_of(order_[e]) == pair_of(order_[k])) ++e;
      faces_.push_back(
          {pair_of(order_[k]).first, pair_of(order_[k]).second, static_cast<index_t>(k), static_cast<index_t>(e)});
      k = e;
    }
    parent_.resize(static_cast<std::size_t>(blocks));
  }

  /// The unit axis positions are measured along.
  [[nodiscard]] const vec3& axis() const { return axis_; }

  /// A bar's path through the specimen: host block and position along the axis of each bar node,
  /// in bar order (enables crack_report::bar_crossings).
  void set_bar_path(std::vector<index_t> node_blocks, std::vector<real> node_positions) {
    require(node_blocks.size() == node_positions.size(), "crack_graph: ", node_blocks.size(), " host blocks for ",
            node_positions.size(), " bar nodes");
    for (const index_t b : node_blocks)
      require(b >= 0 && b < blocks_, "crack_graph: bar host block ", b, " outside [0, ", blocks_, ")");
    bar_blocks_ = std::move(node_blocks);
    bar_positions_ = std::move(node_positions);
  }

  /// Through-cracks of faces whose every sub-contact i satisfies cracked(i).
  template <class Contacts, class Cracked>
  [[nodiscard]] crack_report evaluate(const Contacts& contacts, const node_set& gridpoints, Cracked&& cracked,
                                      real opening_threshold = 0) {
    crack_report r;
    r.opening_threshold = opening_threshold;
    std::iota(parent_.begin(), parent_.end(), index_t{0});
    std::vector<std::size_t> cracked_faces;
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      bool all = true;
      for (index_t k = faces_[f].first; k < faces_[f].last; ++k) {
        if (cracked(order_[static_cast<std::size_t>(k)]))
          ++r.open_subcontacts;
        else
          all = false;
      }
      if (all)
        cracked_faces.push_back(f);
      else
        parent_[static_cast<std::size_t>(find(faces_[f].a))] = find(faces_[f].b);
    }
    r.pieces = 0;
    for (index_t b = 0; b < blocks_; ++b)
      if (find(b) == b) ++r.pieces;
    r.cracks = r.pieces - 1;
    std::vector<std::pair<std::pair<index_t, index_t>, std::pair<double, double>>> surfaces;  // pieces -> (sum A x, sum A)
    const auto surface_between = [&](index_t pa, index_t pb) {  // the surface separating two pieces, or end()
      const std::pair<index_t, index_t> key = std::minmax(pa, pb);
      return std::find_if(surfaces.begin(), surfaces.end(), [&](const auto& x) { return x.first == key; });
    };
    for (std::size_t f : cracked_faces) {
      index_t pa = find(faces_[f].a), pb = find(faces_[f].b);
      if (pa == pb) continue;  // a cracked face inside one piece: the crack does not separate there
      if (pa > pb) std::swap(pa, pb);
      auto it = surface_between(pa, pb);
      if (it == surfaces.end()) {
        surfaces.push_back({{pa, pb}, {0.0, 0.0}});
        it = surfaces.end() - 1;
      }
      for (index_t k = faces_[f].first; k < faces_[f].last; ++k) {
        const index_t i = order_[static_cast<std::size_t>(k)];
        it->second.first += contacts.area(i) * coordinate(contacts.position(i, gridpoints));
        it->second.second += contacts.area(i);
      }
    }
    for (const auto& x : surfaces)
      if (x.second.second > 0) r.positions.push_back(x.second.first / x.second.second);
    std::sort(r.positions.begin(), r.positions.end());
    if (!bar_blocks_.empty()) {
      r.bar_crossings = 0;
      for (std::size_t k = 1; k < bar_blocks_.size(); ++k) {
        const index_t pa = find(bar_blocks_[k - 1]), pb = find(bar_blocks_[k]);
        if (pa == pb) continue;
        ++r.bar_crossings;
        const auto it = surface_between(pa, pb);
        r.bar_crossing_positions.push_back(it != surfaces.end() && it->second.second > 0
                                               ? it->second.first / it->second.second
                                               : 0.5 * (bar_positions_[k - 1] + bar_positions_[k]));
      }
    }
    return r;
  }

  /// Fully opened through-cracks: every sub-contact of the faces softened (or broken) and its
  /// gridpoints separated by |x_B - x_A| >= w_open.
  template <class Contacts>
  [[nodiscard]] crack_report opened(const Contacts& contacts, const node_set& gridpoints, real w_open) {
    return evaluate(
        contacts, gridpoints,
        [&](index_t i) {
          const real jump = (gridpoints.position(contacts.node_b(i)) - gridpoints.position(contacts.node_a(i))).norm();
          return past_peak(contacts.state(i).flags) && jump >= w_open;
        },
        w_open);
  }
  /// The stricter count: the normal opening u_n >= w_open on every sub-contact of the faces.
  template <class Contacts>
  [[nodiscard]] crack_report opened_normal_only(const Contacts& contacts, const node_set& gridpoints, real w_open) {
    return evaluate(contacts, gridpoints, [&](index_t i) { return contacts.state(i).u_n >= w_open; }, w_open);
  }
  /// Softened through-cracks (every sub-contact of the faces past its tensile peak).
  template <class Contacts>
  [[nodiscard]] crack_report softened(const Contacts& contacts, const node_set& gridpoints) {
    return evaluate(contacts, gridpoints, [&](index_t i) { return past_peak(contacts.state(i).flags); });
  }
  /// A sub-contact past its tensile peak: softening or broken in tension.
  [[nodiscard]] static bool past_peak(law::contact_status flags) {
    return law::has(flags, law::contact_status::softening) || law::has(flags, law::contact_status::broken_tension);
  }

 private:
  struct face {
    index_t a, b, first, last;
  };
  /// Position along the axis (exactly the coordinate for a coordinate axis: the other products are 0).
  [[nodiscard]] real coordinate(const vec3& x) const { return x.dot(axis_); }
  index_t find(index_t b) {
    while (parent_[static_cast<std::size_t>(b)] != b) {
      parent_[static_cast<std::size_t>(b)] = parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(b)])];
      b = parent_[static_cast<std::size_t>(b)];
    }
    return b;
  }
  index_t blocks_;
  vec3 axis_ = vec3::UnitZ();
  std::vector<index_t> order_;
  std::vector<face> faces_;
  std::vector<index_t> parent_;
  std::vector<index_t> bar_blocks_;     ///< host block of each bar node, in bar order (empty: no bar path)
  std::vector<real> bar_positions_;  ///< position of each bar node along the axis (m)
};

}  // namespace tessera::analysis

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/cracks.ipp"
#endif
