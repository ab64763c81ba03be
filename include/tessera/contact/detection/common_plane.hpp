#pragma once
// Narrow phase of contact detection between two convex polyhedra (DESIGN.md section 4): the
// contact plane of the pair and the contact patch on it, from which a detecting contact set
// makes its vertex sub-contacts.
//
// Contact plane (common_plane). The plane is the one of largest separation over the separating-
// axis candidates of two convex polyhedra: the face normals of A, the reversed face normals of B
// and the cross products of one edge of each. For an axis n (unit, from A to B) the gap is
//     g(n) = min_{x in B} n.x - max_{x in A} n.x        (m; > 0 apart, < 0 overlapping)
// and the plane lies halfway, n.x = (max_A + min_B) / 2: 3DEC's common plane (Cundall 1988: the
// plane maximising the smaller of the two blocks' vertex distances to it) over a finite candidate
// set, as in Nezami et al.'s fast common plane. The candidates are the face normals of the
// Minkowski difference B - A, for which the separating axis theorem gives two guarantees:
//   - the sign of g is exact: g > 0 iff the blocks are disjoint;
//   - for overlapping blocks, -g is the penetration depth and n its direction (exact).
// For disjoint blocks g is a lower bound of their distance (equal to it when the closest features
// are a face and a vertex, edge or face, or two crossing edges; smaller when two vertices or a
// vertex and an edge are closest, e.g. two cubes corner to corner), so a pair is taken as
// touching slightly early, never late; the per-point gaps of the patch are exact.
// Edge pairs are pruned to those whose arcs on the Gauss map cross (the edge pairs that form a
// face of the Minkowski difference; Gregorius, GDC 2013), which leaves O(E) of the O(E^2) pairs
// and keeps both guarantees (test_contacts "[detection]" checks them against the unpruned search
// on 2000 random pairs). Ties within plane_tie_rel x size prefer a face of A, then of B, then an
// edge pair, so face-face contacts are classified as such under rounding.
//
// Contact patch (contact_patch). The vertices of A within `tolerance` of A's supporting plane
// (n.x >= max_A - tolerance) and those of B within it of B's (n.x <= min_B + tolerance) are
// projected on the contact plane; their convex hulls are intersected. The patch is a polygon
// (face-face contact), a segment (edge-face or parallel edges) or a point (vertex-face, crossing
// edges); its corners are the sub-contact points. Per corner: the normal gap along n between the
// surfaces of A and B through it (exact for planar faces: the exit of the line from A and its
// entry into B, from the face planes), and the tributary area (a polygon's area split between
// its corners through the mean of its corners: half of each of the two triangles (mean, corner,
// neighbour) at the corner, >= 0 however thin the polygon; zero for a segment or point, for
// which the caller supplies a nominal area: see docs/model.md). `tolerance` is the contact tolerance of 3DEC (the band in which a
// vertex counts as touching); it must exceed the tilt of nearly parallel faces over their size,
// else they read as an edge contact. A vertex of a neighbouring face that lies within the band
// joins the patch too, so a corner's gap can exceed the plane's by up to one tolerance per block
// (such a corner carries force only once it closes); no corner's gap is below the plane's.
//
// Cost: common_plane O(F_A V_B + F_B V_A + (E_A + E_B) log + K (V_A + V_B)), K the retained edge
// pairs; contact_patch O(V_A + V_B + F_A + F_B) per corner. Both allocate only in the returned
// patch (and in scratch vectors reused through a detection_workspace). Pure functions of their
// inputs: deterministic, thread-safe with one workspace per thread.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

#include "../../core/errors.hpp"
#include "../../core/types.hpp"
#include "../../geometry/convex_polyhedron.hpp"

namespace tessera::contact::detection {

/// Relative size of a tie between two candidate axes' gaps (x the pair's size).
inline constexpr real plane_tie_rel = 1e-9;

/// Where the contact plane's normal came from.
enum class plane_source : std::uint8_t { face_a, face_b, edge_edge };

/// The contact plane of a pair: normal (unit, from A to B), offset (n.x = offset on the plane)
/// and the gap g (m) of the best axis.
struct contact_plane {
  vec3 normal = vec3::UnitZ();
  real offset = 0;
  real gap = 0;
  plane_source source = plane_source::face_a;
  index_t feature_a = invalid_index;  ///< face of A (face_a), or edge of A (edge_edge)
  index_t feature_b = invalid_index;  ///< face of B (face_b), or edge of B (edge_edge)
};

/// The edges of a convex polyhedron with their two faces: face_left holds the loop u -> v,
/// face_right the loop v -> u (outward CCW loops).
struct polyhedron_edges {
  struct edge {
    index_t u, v, face_left, face_right;
  };
  std::vector<edge> list;
};

/// Edges of p from its face loops; throws geometry_error if an edge does not have exactly two
/// faces (an open or non-manifold polyhedron).
[[nodiscard]] inline polyhedron_edges edges_of(const geometry::convex_polyhedron& p) {
  struct half {
    index_t lo, hi, face;
    bool forward;  ///< lo -> hi in the face's loop
  };
  std::vector<half> halves;
  for (index_t f = 0; f < p.face_count(); ++f) {
    const auto loop = p.face(f);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const index_t a = loop[i], b = loop[(i + 1) % loop.size()];
      halves.push_back({std::min(a, b), std::max(a, b), f, a < b});
    }
  }
  std::sort(halves.begin(), halves.end(),
            [](const half& x, const half& y) { return std::tie(x.lo, x.hi, x.forward) < std::tie(y.lo, y.hi, y.forward); });
  polyhedron_edges e;
  for (std::size_t i = 0; i < halves.size(); i += 2) {
    const bool pair = i + 1 < halves.size() && halves[i].lo == halves[i + 1].lo && halves[i].hi == halves[i + 1].hi &&
                      halves[i].forward != halves[i + 1].forward;
    require<geometry_error>(pair, "detection: edge (", halves[i].lo, ", ", halves[i].hi,
                            ") of a polyhedron does not have exactly two faces with opposite loops");
    // halves[i] is the backward one (hi -> lo), halves[i + 1] the forward one (lo -> hi).
    e.list.push_back({halves[i].lo, halves[i].hi, halves[i + 1].face, halves[i].face});
  }
  return e;
}

namespace detail {

/// max_{x in p} n.x, in four running maxima rather than one chain of dependent ones (common
/// plane 64.9 -> 61.0 ms over bench_detection's 11 927 pairs; a maximum is exact, so the order
/// does not change the value).
[[nodiscard]] inline real support_max(const geometry::convex_polyhedron& p, const vec3& n) {
  constexpr real lowest = -std::numeric_limits<real>::infinity();
  real m[4] = {lowest, lowest, lowest, lowest};
  const std::vector<vec3>& x = p.vertices();
  std::size_t i = 0;
  for (; i + 4 <= x.size(); i += 4)
    for (std::size_t k = 0; k < 4; ++k) m[k] = std::max(m[k], n.dot(x[i + k]));
  for (; i < x.size(); ++i) m[0] = std::max(m[0], n.dot(x[i]));
  return std::max(std::max(m[0], m[1]), std::max(m[2], m[3]));
}
/// min_{x in p} n.x (as support_max).
[[nodiscard]] inline real support_min(const geometry::convex_polyhedron& p, const vec3& n) {
  return -support_max(p, -n);
}

}  // namespace detail

/// Appends p's outward face planes, face by face (face_plane), to `out`: what a detection pass
/// computes once per block (detect.hpp) instead of once per candidate pair.
inline void append_face_planes(const geometry::convex_polyhedron& p, std::vector<geometry::plane>& out) {
  for (index_t f = 0; f < p.face_count(); ++f) out.push_back(p.face_plane(f));
}

/// The contact plane of A and B (see the file comment). `edges_a`, `edges_b`: edges_of(a), (b),
/// which a caller keeps with its blocks; `faces_a`, `faces_b`: their face planes
/// (append_face_planes). `prune_edges` false tries every edge pair (the reference the tests
/// compare with). Throws invalid_input for an empty polyhedron or a face list of another size.
[[nodiscard]] inline contact_plane common_plane(const geometry::convex_polyhedron& a, const polyhedron_edges& edges_a,
                                                std::span<const geometry::plane> faces_a,
                                                const geometry::convex_polyhedron& b, const polyhedron_edges& edges_b,
                                                std::span<const geometry::plane> faces_b, bool prune_edges = true) {
  require(!a.empty() && !b.empty(), "detection: common_plane of an empty polyhedron");
  require(faces_a.size() == static_cast<std::size_t>(a.face_count()) && faces_b.size() == static_cast<std::size_t>(b.face_count()),
          "detection: common_plane given ", faces_a.size(), " and ", faces_b.size(), " face planes for polyhedra of ",
          a.face_count(), " and ", b.face_count(), " faces");
  const real size = std::max(a.extent(), b.extent());
  const real tie = plane_tie_rel * size;
  contact_plane best;
  best.gap = -std::numeric_limits<real>::infinity();
  real best_a = 0, best_b = 0;
  // Candidate n with A's support value max_a and B's min_b along it.
  const auto consider_supports = [&](const vec3& n, real max_a, real min_b, plane_source source, index_t fa, index_t fb,
                                     real margin) {
    const real g = min_b - max_a;
    if (g > best.gap + margin) {
      best = {n, 0, g, source, fa, fb};
      best_a = max_a;
      best_b = min_b;
    }
  };
  const auto consider = [&](const vec3& n, plane_source source, index_t fa, index_t fb, real margin) {
    consider_supports(n, detail::support_max(a, n), detail::support_min(b, n), source, fa, fb, margin);
  };
  const auto normal_a = [&](index_t f) -> const vec3& { return faces_a[static_cast<std::size_t>(f)].normal; };
  const auto normal_b = [&](index_t f) -> const vec3& { return faces_b[static_cast<std::size_t>(f)].normal; };
  // Faces first, edges last: a later candidate must beat the best by `tie` to replace it.
  for (index_t f = 0; f < a.face_count(); ++f)
    consider(normal_a(f), plane_source::face_a, f, invalid_index, tie);
  for (index_t f = 0; f < b.face_count(); ++f)
    consider(-normal_b(f), plane_source::face_b, invalid_index, f, tie);
  // A point inside A (the vertex mean; the centroid would need a volume integral) to orient the
  // edge-pair axes outward from A.
  vec3 ca = vec3::Zero();
  for (const vec3& x : a.vertices()) ca += x;
  ca /= static_cast<real>(a.vertex_count());
  // Per edge of B, the arc of its reversed face normals c, d and d x c as columns (computed once
  // per call), so the arc test of one edge of A against all of B's runs branch-free over them.
  thread_local std::vector<real> arcs;
  thread_local std::vector<index_t> crossing;
  thread_local std::vector<std::uint8_t> crosses;
  const std::size_t nb_edges = edges_b.list.size();
  arcs.resize(9 * nb_edges);
  crossing.resize(nb_edges);
  crosses.resize(nb_edges);
  real* col[9];
  for (std::size_t k = 0; k < 9; ++k) col[k] = arcs.data() + k * nb_edges;
  for (std::size_t j = 0; j < nb_edges; ++j) {
    const auto& eb = edges_b.list[j];
    const vec3 c = -normal_b(eb.face_left);
    const vec3 d = -normal_b(eb.face_right);
    const vec3 d_x_c = d.cross(c);
    for (int k = 0; k < 3; ++k) {
      col[k][j] = c[k];
      col[3 + k][j] = d[k];
      col[6 + k][j] = d_x_c[k];
    }
  }
  for (std::size_t i = 0; i < edges_a.list.size(); ++i) {
    const auto& ea = edges_a.list[i];
    const vec3 da = a.vertex(ea.v) - a.vertex(ea.u);
    const vec3& na = normal_a(ea.face_left);
    const vec3& nb = normal_a(ea.face_right);
    const vec3 b_x_a = nb.cross(na);
    std::size_t count = 0;
    if (prune_edges) {
      // The arc (na, nb) of A's edge and the arc (c, d) of B's reversed normals cross on the unit
      // sphere iff c, d lie on opposite sides of the plane of (na, nb), na, nb on opposite sides
      // of that of (c, d), and the crossing is on the near hemisphere (Gregorius, GDC 2013), with
      // b_x_a = nb x na and d x c; for every edge of B, without branches: the test in one loop
      // (which the compiler vectorises), the list of crossing edges in a second (the compacting
      // store in the same loop kept the test scalar).
      std::uint8_t* const hit = crosses.data();
      const real bx = b_x_a.x(), by = b_x_a.y(), bz = b_x_a.z();
      const real nax = na.x(), nay = na.y(), naz = na.z(), nbx = nb.x(), nby = nb.y(), nbz = nb.z();
      for (std::size_t j = 0; j < nb_edges; ++j) {
        const real cba = col[0][j] * bx + col[1][j] * by + col[2][j] * bz;
        const real dba = col[3][j] * bx + col[4][j] * by + col[5][j] * bz;
        const real adc = nax * col[6][j] + nay * col[7][j] + naz * col[8][j];
        const real bdc = nbx * col[6][j] + nby * col[7][j] + nbz * col[8][j];
        hit[j] = static_cast<std::uint8_t>((cba * dba < 0) & (adc * bdc < 0) & (cba * bdc > 0));
      }
      for (std::size_t j = 0; j < nb_edges; ++j) {
        crossing[count] = static_cast<index_t>(j);
        count += hit[j];
      }
    } else {
      for (std::size_t j = 0; j < nb_edges; ++j) crossing[count++] = static_cast<index_t>(j);
    }
    for (std::size_t k = 0; k < count; ++k) {
      const auto j = static_cast<std::size_t>(crossing[k]);
      const auto& eb = edges_b.list[j];
      const vec3 db = b.vertex(eb.v) - b.vertex(eb.u);
      vec3 n = da.cross(db);
      const real length = n.norm();
      if (!(length > 1e-9 * da.norm() * db.norm())) continue;  // parallel edges: a face axis covers them
      n /= length;
      if (n.dot(a.vertex(ea.u) - ca) < 0) n = -n;  // outward from A at its edge
      if (prune_edges)  // the two edges are the supporting features along n: no vertex loop
        consider_supports(n, n.dot(a.vertex(ea.u)), n.dot(b.vertex(eb.u)), plane_source::edge_edge,
                          static_cast<index_t>(i), static_cast<index_t>(j), tie);
      else
        consider(n, plane_source::edge_edge, static_cast<index_t>(i), static_cast<index_t>(j), tie);
    }
  }
  best.offset = 0.5 * (best_a + best_b);
  return best;
}

/// Overload that computes the face planes.
[[nodiscard]] inline contact_plane common_plane(const geometry::convex_polyhedron& a, const polyhedron_edges& edges_a,
                                                const geometry::convex_polyhedron& b, const polyhedron_edges& edges_b,
                                                bool prune_edges = true) {
  std::vector<geometry::plane> faces_a, faces_b;
  append_face_planes(a, faces_a);
  append_face_planes(b, faces_b);
  return common_plane(a, edges_a, faces_a, b, edges_b, faces_b, prune_edges);
}

/// Overload that builds the edge lists and face planes (for one-off queries and tests).
[[nodiscard]] inline contact_plane common_plane(const geometry::convex_polyhedron& a, const geometry::convex_polyhedron& b) {
  return common_plane(a, edges_of(a), b, edges_of(b));
}

/// Dimension of a contact patch.
enum class patch_type : std::uint8_t { none, point, segment, polygon };

/// The contact patch of a pair on its contact plane (see the file comment).
struct contact_patch {
  patch_type type = patch_type::none;
  std::vector<vec3> points;  ///< corners on the contact plane (CCW about the normal for a polygon)
  std::vector<real> gap;     ///< normal gap B - A through each corner (m; < 0 overlapping)
  std::vector<real> area;    ///< tributary area of each corner (m^2; 0 for a segment or point)
  /// What each corner is, as a corner_label: a vertex of A, a vertex of B, or the crossing of an
  /// edge of A's touching hull with one of B's (vertex ids local to each polyhedron). A corner
  /// keeps its label while the blocks move, so a detecting set keys its law state by it.
  std::vector<std::uint64_t> label;
  real total_area = 0;       ///< area of the polygon (m^2)
};

/// Labels of patch corners (contact_patch::label): the top two bits give the kind, the rest the
/// vertex ids (15 bits each, so a polyhedron may have up to 32 767 vertices).
namespace corner_label {
inline constexpr int id_bits = 15;
inline constexpr index_t max_vertices = (index_t{1} << id_bits) - 1;
enum class kind : std::uint64_t { vertex_a = 0, vertex_b = 1, crossing = 2 };
[[nodiscard]] constexpr std::uint64_t vertex_a(index_t v) noexcept { return static_cast<std::uint64_t>(v); }
[[nodiscard]] constexpr std::uint64_t vertex_b(index_t v) noexcept {
  return (std::uint64_t{1} << 62) | static_cast<std::uint64_t>(v);
}
/// Crossing of A's hull edge (a0, a1) with B's (b0, b1); each edge's ids in increasing order.
[[nodiscard]] constexpr std::uint64_t crossing(index_t a0, index_t a1, index_t b0, index_t b1) noexcept {
  const auto u = static_cast<std::uint64_t>(std::min(a0, a1)), v = static_cast<std::uint64_t>(std::max(a0, a1));
  const auto x = static_cast<std::uint64_t>(std::min(b0, b1)), y = static_cast<std::uint64_t>(std::max(b0, b1));
  return (std::uint64_t{2} << 62) | (u << 45) | (v << 30) | (x << 15) | y;
}
[[nodiscard]] constexpr kind kind_of(std::uint64_t label) noexcept { return static_cast<kind>(label >> 62); }
}  // namespace corner_label

namespace detail {

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

/// Parameter t where the line x + t n leaves a convex polyhedron with outward face planes
/// `faces`: the least bound of the faces facing along n; +inf if none does.
[[nodiscard]] inline real exit_along(std::span<const geometry::plane> faces, const vec3& x, const vec3& n) {
  real t = std::numeric_limits<real>::infinity();
  for (const geometry::plane& f : faces) {
    const real c = f.normal.dot(n);
    if (c > 1e-12) t = std::min(t, (f.offset - f.normal.dot(x)) / c);
  }
  return t;
}

/// Index of the point nearest to q (the first of equals).
[[nodiscard]] inline std::size_t nearest_point(const point2& q, const std::vector<point2>& points) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < points.size(); ++i)
    if ((points[i] - q).squaredNorm() < (points[best] - q).squaredNorm()) best = i;
  return best;
}
/// Vertex id of the touching point equal to hull corner h (hull2 keeps input points as they are).
[[nodiscard]] inline index_t hull_vertex(const point2& h, const std::vector<point2>& points, const std::vector<index_t>& ids) {
  return ids[nearest_point(h, points)];
}

/// corner_label of patch corner q: the nearest touching vertex of A, else of B, when q lies on it
/// (within 1e-6 of the hull's size); else the crossing of the nearest hull edges of A and B.
[[nodiscard]] inline std::uint64_t label_corner(const point2& q, const std::vector<point2>& pa, const std::vector<index_t>& ids_a,
                                                const std::vector<point2>& hull_a, const std::vector<point2>& pb,
                                                const std::vector<index_t>& ids_b, const std::vector<point2>& hull_b) {
  real size = 0;
  for (const point2& h : hull_a) size = std::max(size, (h - hull_a.front()).norm());
  for (const point2& h : hull_b) size = std::max(size, (h - hull_b.front()).norm());
  const real on = 1e-6 * std::max(size, std::numeric_limits<real>::min());
  if (const std::size_t i = nearest_point(q, pa); (pa[i] - q).norm() <= on) return corner_label::vertex_a(ids_a[i]);
  if (const std::size_t i = nearest_point(q, pb); (pb[i] - q).norm() <= on) return corner_label::vertex_b(ids_b[i]);
  // The hull edge (i, i + 1) nearest to q; a 1- or 2-point hull is its own edge.
  const auto nearest_edge = [&](const std::vector<point2>& hull) {
    std::size_t best = 0;
    real best_d = std::numeric_limits<real>::infinity();
    const std::size_t edges = hull.size() >= 3 ? hull.size() : 1;
    for (std::size_t i = 0; i < edges; ++i) {
      const point2& p = hull[i];
      const point2 d = hull[(i + 1) % hull.size()] - p;
      const real t = d.squaredNorm() > 0 ? std::clamp((q - p).dot(d) / d.squaredNorm(), real(0), real(1)) : real(0);
      if (const real dist = (p + t * d - q).squaredNorm(); dist < best_d) {
        best_d = dist;
        best = i;
      }
    }
    return std::pair{hull[best], hull[(best + 1) % hull.size()]};
  };
  const auto [a0, a1] = nearest_edge(hull_a);
  const auto [b0, b1] = nearest_edge(hull_b);
  return corner_label::crossing(hull_vertex(a0, pa, ids_a), hull_vertex(a1, pa, ids_a), hull_vertex(b0, pb, ids_b),
                                hull_vertex(b1, pb, ids_b));
}

}  // namespace detail

/// The contact patch of A and B on `plane` (common_plane's result), with vertices within
/// `tolerance` (m, > 0) of either block's supporting plane counted as touching. An empty patch
/// (type none) when the touching sets do not overlap on the plane. `faces_a`, `faces_b`: the
/// blocks' face planes (append_face_planes); a list of another size is refused.
[[nodiscard]] inline contact_patch contact_patch_of(const geometry::convex_polyhedron& a, const geometry::convex_polyhedron& b,
                                                    const contact_plane& plane, real tolerance,
                                                    std::span<const geometry::plane> faces_a,
                                                    std::span<const geometry::plane> faces_b) {
  require(std::isfinite(tolerance) && tolerance > 0, "detection: contact tolerance = ", tolerance,
          " m must be finite and > 0");
  require(faces_a.size() == static_cast<std::size_t>(a.face_count()) && faces_b.size() == static_cast<std::size_t>(b.face_count()),
          "detection: contact_patch_of given ", faces_a.size(), " and ", faces_b.size(), " face planes for polyhedra of ",
          a.face_count(), " and ", b.face_count(), " faces");
  const vec3 n = plane.normal;
  // Frame of the plane.
  const vec3 t1 = (std::abs(n.x()) < 0.9 ? vec3::UnitX() : vec3::UnitY()).cross(n).normalized();
  const vec3 t2 = n.cross(t1);
  const auto to2 = [&](const vec3& x) { return detail::point2(t1.dot(x), t2.dot(x)); };
  const real max_a = detail::support_max(a, n), min_b = detail::support_min(b, n);
  require(a.vertex_count() <= corner_label::max_vertices && b.vertex_count() <= corner_label::max_vertices,
          "detection: polyhedra of ", a.vertex_count(), " and ", b.vertex_count(), " vertices; at most ",
          corner_label::max_vertices, " are supported");
  std::vector<detail::point2> pa, pb;
  std::vector<index_t> ids_a, ids_b;  // vertex id of each touching point
  for (index_t v = 0; v < a.vertex_count(); ++v)
    if (n.dot(a.vertex(v)) >= max_a - tolerance) {
      pa.push_back(to2(a.vertex(v)));
      ids_a.push_back(v);
    }
  for (index_t v = 0; v < b.vertex_count(); ++v)
    if (n.dot(b.vertex(v)) <= min_b + tolerance) {
      pb.push_back(to2(b.vertex(v)));
      ids_b.push_back(v);
    }
  const real tol2 = 1e-9 * std::max(a.extent(), b.extent());
  const std::vector<detail::point2> hull_a = detail::hull2(pa, tol2), hull_b = detail::hull2(pb, tol2);
  const std::vector<detail::point2> patch = detail::intersect_hulls(hull_a, hull_b, tol2);

  contact_patch out;
  if (patch.empty()) return out;
  out.type = patch.size() == 1 ? patch_type::point : patch.size() == 2 ? patch_type::segment : patch_type::polygon;
  for (const detail::point2& q : patch) {
    const vec3 x = plane.offset * n + q.x() * t1 + q.y() * t2;
    // The line x + t n leaves A at t_a and enters B at t_b (B's entry along n is its exit along -n).
    const real t_a = detail::exit_along(faces_a, x, n);
    const real t_b = -detail::exit_along(faces_b, x, -n);
    out.points.push_back(x);
    out.gap.push_back(t_b - t_a);
    out.label.push_back(detail::label_corner(q, pa, ids_a, hull_a, pb, ids_b, hull_b));
  }
  out.area.assign(patch.size(), 0.0);
  if (out.type == patch_type::polygon) {
    // Fan from the mean of the corners: it lies inside a convex polygon however thin, so every
    // triangle has the polygon's orientation and every tributary area is >= 0. (The area
    // centroid divides by the area: for a sliver it lands far outside and splits a near-zero
    // area into huge areas of both signs.)
    detail::point2 c = detail::point2::Zero();
    for (const detail::point2& p : patch) c += p;
    c /= static_cast<real>(patch.size());
    real signed_total = 0;
    for (std::size_t i = 0; i < patch.size(); ++i) signed_total += detail::cross2(c, patch[i], patch[(i + 1) % patch.size()]);
    const real orientation = signed_total < 0 ? -1.0 : 1.0;
    for (std::size_t i = 0; i < patch.size(); ++i) {
      const std::size_t j = (i + 1) % patch.size();
      const real tri = std::max<real>(0, 0.5 * orientation * detail::cross2(c, patch[i], patch[j]));
      out.area[i] += 0.5 * tri;
      out.area[j] += 0.5 * tri;
      out.total_area += tri;
    }
  }
  return out;
}

/// Overload that computes the face planes (for one-off queries and tests).
[[nodiscard]] inline contact_patch contact_patch_of(const geometry::convex_polyhedron& a, const geometry::convex_polyhedron& b,
                                                    const contact_plane& plane, real tolerance) {
  std::vector<geometry::plane> faces_a, faces_b;
  append_face_planes(a, faces_a);
  append_face_planes(b, faces_b);
  return contact_patch_of(a, b, plane, tolerance, faces_a, faces_b);
}

}  // namespace tessera::contact::detection
