#pragma once
// Convex sets in a plane for the contact patch (contact/detection/contact_patch.hpp): the convex
// hull of points (Andrew's monotone chain) and the intersection of two convex hulls of 1, 2 or
// >= 3 corners (Sutherland-Hodgman clipping, segment overlaps and crossings), each dropping what
// lies within a length tolerance `tol` (m). Pure functions; they allocate their results.

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

/// Convex hull (CCW, Andrew's monotone chain) of points, dropping points within `tol` (m) of the
/// hull's edges; 1 or 2 points for a degenerate set.
[[nodiscard]] inline std::vector<point2> hull2(std::vector<point2> p, real tol) {
  std::sort(p.begin(), p.end(), [](const point2& x, const point2& y) { return x.x() < y.x() || (x.x() == y.x() && x.y() < y.y()); });
  std::vector<point2> unique;
  for (const point2& x : p)
    if (unique.empty() || (x - unique.back()).norm() > tol) unique.push_back(x);
  if (unique.size() < 3) return unique;
  std::vector<point2> h(2 * unique.size());
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
  if (h.size() < 3) return {unique.front(), unique.back()};  // collinear: the extremes of the sorted points
  return h;
}

/// Part of convex polygon (CCW, >= 3 corners), segment (2) or point (1) `subject` inside convex
/// polygon `clip` (CCW, >= 3 corners), by Sutherland-Hodgman against clip's edges.
[[nodiscard]] inline std::vector<point2> clip_convex(std::vector<point2> subject, const std::vector<point2>& clip, real tol) {
  const bool closed = subject.size() >= 3;
  for (std::size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
    const point2& p = clip[e];
    const point2& q = clip[(e + 1) % clip.size()];
    const real len = (q - p).norm();
    const auto side = [&](const point2& x) { return cross2(p, q, x) / len; };  // > 0 inside
    std::vector<point2> out;
    const std::size_t n = subject.size();
    if (n == 1) {
      if (side(subject[0]) >= -tol) out.push_back(subject[0]);
      subject = std::move(out);
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
      subject = s0 >= -tol ? std::vector<point2>{subject[0], cut} : std::vector<point2>{cut, subject[1]};
      continue;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const point2& a = subject[i];
      const point2& b = subject[(i + 1) % n];
      const real sa = side(a), sb = side(b);
      if (sa >= -tol) out.push_back(a);
      if ((sa >= -tol) != (sb >= -tol)) out.push_back(a + (b - a) * (sa / (sa - sb)));
    }
    subject = std::move(out);
  }
  return subject;
}

/// Intersection of two convex 2-D sets given as hulls (1, 2 or >= 3 CCW corners).
[[nodiscard]] inline std::vector<point2> intersect_hulls(const std::vector<point2>& p, const std::vector<point2>& q, real tol) {
  if (p.empty() || q.empty()) return {};
  if (q.size() >= 3) return hull2(clip_convex(p, q, tol), tol);
  if (p.size() >= 3) return hull2(clip_convex(q, p, tol), tol);
  // Both segments or points.
  if (p.size() == 1 || q.size() == 1) {
    const point2 x = p.size() == 1 ? p[0] : q[0];
    const std::vector<point2>& s = p.size() == 1 ? q : p;
    if (s.size() == 1) return (x - s[0]).norm() <= tol ? std::vector<point2>{x} : std::vector<point2>{};
    const point2 d = s[1] - s[0];
    const real t = std::clamp((x - s[0]).dot(d) / d.squaredNorm(), real(0), real(1));
    return (s[0] + t * d - x).norm() <= tol ? std::vector<point2>{x} : std::vector<point2>{};
  }
  const point2 d1 = p[1] - p[0], d2 = q[1] - q[0];
  const real denom = d1.x() * d2.y() - d1.y() * d2.x();
  const real l1 = d1.norm(), l2 = d2.norm();
  if (std::abs(denom) <= tol * std::max(l1, l2)) {
    // Parallel: overlap along the common line, if the lines coincide.
    const point2 u = d1 / l1;
    const point2 off = q[0] - p[0];
    if (std::abs(off.x() * u.y() - off.y() * u.x()) > tol) return {};
    const real a0 = 0, a1 = l1;
    const real b0 = off.dot(u), b1 = (q[1] - p[0]).dot(u);
    const real lo = std::max(a0, std::min(b0, b1)), hi = std::min(a1, std::max(b0, b1));
    if (hi < lo - tol) return {};
    if (hi - lo <= tol) return {p[0] + u * (0.5 * (lo + hi))};
    return {p[0] + u * lo, p[0] + u * hi};
  }
  const point2 w = q[0] - p[0];
  const real t = (w.x() * d2.y() - w.y() * d2.x()) / denom;
  const real s = (w.x() * d1.y() - w.y() * d1.x()) / denom;
  const real ta = tol / l1, sa = tol / l2;
  if (t < -ta || t > 1 + ta || s < -sa || s > 1 + sa) return {};
  return {p[0] + std::clamp(t, real(0), real(1)) * d1};
}

}  // namespace tessera::contact::detection::detail
