#pragma once
// Convex sets in a plane for the contact patch (contact/detection/contact_patch.hpp): the convex
// hull of points (Andrew's monotone chain) and the intersection of two convex hulls of 1, 2 or
// >= 3 corners (Sutherland-Hodgman clipping, segment overlaps and crossings), each dropping what
// lies within a length tolerance `tol` (m). Pure functions of their inputs; the _into forms write
// into buffers the caller keeps (polygon_scratch), so that a detection pass allocates nothing once
// they have grown, and the others allocate their results.

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "../../core/types.hpp"

namespace tessera::contact::detection::detail {

using point2 = Eigen::Matrix<real, 2, 1>;
[[nodiscard]] inline real cross2(const point2& o, const point2& a, const point2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// Buffers of the functions below (each keeps its capacity: no allocation once grown).
struct polygon_scratch {
  std::vector<point2> sorted, unique, clipped, spare;
};

/// Convex hull (CCW, Andrew's monotone chain) of points `p` into `h`, dropping points within `tol`
/// (m) of the hull's edges; 1 or 2 points for a degenerate set. `p` is left as it was (its copy is
/// sorted in s.sorted); `h` must not be `p` nor a buffer of `s`.
inline void hull2_into(const std::vector<point2>& p, real tol, polygon_scratch& s, std::vector<point2>& h) {
  s.sorted.assign(p.begin(), p.end());
  std::sort(s.sorted.begin(), s.sorted.end(),
            [](const point2& x, const point2& y) { return x.x() < y.x() || (x.x() == y.x() && x.y() < y.y()); });
  std::vector<point2>& unique = s.unique;
  unique.clear();
  for (const point2& x : s.sorted)
    if (unique.empty() || (x - unique.back()).norm() > tol) unique.push_back(x);
  if (unique.size() < 3) {
    h.assign(unique.begin(), unique.end());
    return;
  }
  h.resize(2 * unique.size());
  std::size_t k = 0;
  // A point is kept only if it turns left by more than tol x the edge length.
  const auto turns_left = [&](const point2& o, const point2& a, const point2& b) {
    return cross2(o, a, b) > tol * (b - o).norm();
  };
  for (const point2& x : unique) {
    while (k >= 2 && !turns_left(h[k - 2], h[k - 1], x)) --k;
    h[k++] = x;
  }
  for (std::size_t i = unique.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && !turns_left(h[k - 2], h[k - 1], unique[i])) --k;
    h[k++] = unique[i];
  }
  h.resize(k - 1);
  if (h.size() < 3) h = {unique.front(), unique.back()};  // collinear: the extremes of the sorted points
}

/// Convex hull (hull2_into), returned.
[[nodiscard]] inline std::vector<point2> hull2(const std::vector<point2>& p, real tol) {
  polygon_scratch s;
  std::vector<point2> h;
  hull2_into(p, tol, s, h);
  return h;
}

/// Part of convex polygon (CCW, >= 3 corners), segment (2) or point (1) `subject` inside convex
/// polygon `clip` (CCW, >= 3 corners), by Sutherland-Hodgman against clip's edges; the result in
/// `subject` (`spare`: the other buffer of the passes).
inline void clip_convex_into(std::vector<point2>& subject, const std::vector<point2>& clip, real tol, std::vector<point2>& spare) {
  const bool closed = subject.size() >= 3;
  for (std::size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
    const point2& p = clip[e];
    const point2& q = clip[(e + 1) % clip.size()];
    const real len = (q - p).norm();
    const auto side = [&](const point2& x) { return cross2(p, q, x) / len; };  // > 0 inside
    const std::size_t n = subject.size();
    if (n == 1) {
      if (!(side(subject[0]) >= -tol)) subject.clear();
      continue;
    }
    if (!closed) {
      const real s0 = side(subject[0]), s1 = side(subject[1]);
      if (s0 >= -tol && s1 >= -tol) continue;
      if (s0 < -tol && s1 < -tol) {
        subject.clear();
        continue;
      }
      const point2 cut = subject[0] + (subject[1] - subject[0]) * (s0 / (s0 - s1));
      (s0 >= -tol ? subject[1] : subject[0]) = cut;
      continue;
    }
    spare.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const point2& a = subject[i];
      const point2& b = subject[(i + 1) % n];
      const real sa = side(a), sb = side(b);
      if (sa >= -tol) spare.push_back(a);
      if ((sa >= -tol) != (sb >= -tol)) spare.push_back(a + (b - a) * (sa / (sa - sb)));
    }
    subject.swap(spare);
  }
}

/// Intersection of two convex 2-D sets given as hulls (1, 2 or >= 3 CCW corners), into `out`
/// (not `p`, `q` nor a buffer of `s`).
inline void intersect_hulls_into(const std::vector<point2>& p, const std::vector<point2>& q, real tol, polygon_scratch& s,
                                 std::vector<point2>& out) {
  out.clear();
  if (p.empty() || q.empty()) return;
  if (q.size() >= 3 || p.size() >= 3) {
    const bool p_in_q = q.size() >= 3;
    s.clipped.assign((p_in_q ? p : q).begin(), (p_in_q ? p : q).end());
    clip_convex_into(s.clipped, p_in_q ? q : p, tol, s.spare);
    hull2_into(s.clipped, tol, s, out);
    return;
  }
  // Both segments or points.
  if (p.size() == 1 || q.size() == 1) {
    const point2 x = p.size() == 1 ? p[0] : q[0];
    const std::vector<point2>& seg = p.size() == 1 ? q : p;
    if (seg.size() == 1) {
      if ((x - seg[0]).norm() <= tol) out.push_back(x);
      return;
    }
    const point2 d = seg[1] - seg[0];
    const real t = std::clamp((x - seg[0]).dot(d) / d.squaredNorm(), real(0), real(1));
    if ((seg[0] + t * d - x).norm() <= tol) out.push_back(x);
    return;
  }
  const point2 d1 = p[1] - p[0], d2 = q[1] - q[0];
  const real denom = d1.x() * d2.y() - d1.y() * d2.x();
  const real l1 = d1.norm(), l2 = d2.norm();
  if (std::abs(denom) <= tol * std::max(l1, l2)) {
    // Parallel: overlap along the common line, if the lines coincide.
    const point2 u = d1 / l1;
    const point2 off = q[0] - p[0];
    if (std::abs(off.x() * u.y() - off.y() * u.x()) > tol) return;
    const real a0 = 0, a1 = l1;
    const real b0 = off.dot(u), b1 = (q[1] - p[0]).dot(u);
    const real lo = std::max(a0, std::min(b0, b1)), hi = std::min(a1, std::max(b0, b1));
    if (hi < lo - tol) return;
    if (hi - lo <= tol) {
      out.push_back(p[0] + u * (0.5 * (lo + hi)));
      return;
    }
    out.push_back(p[0] + u * lo);
    out.push_back(p[0] + u * hi);
    return;
  }
  const point2 w = q[0] - p[0];
  const real t = (w.x() * d2.y() - w.y() * d2.x()) / denom;
  const real sp = (w.x() * d1.y() - w.y() * d1.x()) / denom;
  const real ta = tol / l1, sa = tol / l2;
  if (t < -ta || t > 1 + ta || sp < -sa || sp > 1 + sa) return;
  out.push_back(p[0] + std::clamp(t, real(0), real(1)) * d1);
}

/// Intersection of two convex 2-D sets (intersect_hulls_into), returned.
[[nodiscard]] inline std::vector<point2> intersect_hulls(const std::vector<point2>& p, const std::vector<point2>& q, real tol) {
  polygon_scratch s;
  std::vector<point2> out;
  intersect_hulls_into(p, q, tol, s, out);
  return out;
}

}  // namespace tessera::contact::detection::detail
