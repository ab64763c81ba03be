// The definitions of the larger functions that contact/detection/contact_plane.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include <cmath>

#include "../contact_plane.hpp"

namespace tessera::contact::detection {

[[nodiscard]] TESSERA_INLINE polyhedron_edges edges_of(const geometry::convex_polyhedron& p) {
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

/// A point inside p: the mean of its vertices (m; the centroid would need a volume integral).
[[nodiscard]] inline vec3 vertex_mean(const geometry::convex_polyhedron& p) {
  vec3 c = vec3::Zero();
  for (const vec3& x : p.vertices()) c += x;
  return c / static_cast<real>(p.vertex_count());
}

/// common_plane's refusals of its arguments.
inline void require_plane_arguments(const geometry::convex_polyhedron& a, std::span<const geometry::plane> faces_a,
                                    const geometry::convex_polyhedron& b, std::span<const geometry::plane> faces_b) {
  require(!a.empty() && !b.empty(), "detection: common_plane of an empty polyhedron");
  require(faces_a.size() == static_cast<std::size_t>(a.face_count()) && faces_b.size() == static_cast<std::size_t>(b.face_count()),
          "detection: common_plane given ", faces_a.size(), " and ", faces_b.size(), " face planes for polyhedra of ",
          a.face_count(), " and ", b.face_count(), " faces");
}

/// The edge-pair axes of common_plane in its order: visit(n, i, j) for edge i of A and edge j of B
/// with n = their unit cross product outward from A, for the pairs whose arcs on the Gauss map
/// cross (every pair: prune_edges false), parallel edges left out. The edges i of A with
/// skip_a[i] != 0 and j of B with skip_b[j] != 0 are left out too (empty: none).
template <class Visit>
void visit_edge_axes(const geometry::convex_polyhedron& a, const polyhedron_edges& edges_a,
                     std::span<const geometry::plane> faces_a, const geometry::convex_polyhedron& b,
                     const polyhedron_edges& edges_b, std::span<const geometry::plane> faces_b, bool prune_edges,
                     Visit&& visit, std::span<const std::uint8_t> skip_a = {}, std::span<const std::uint8_t> skip_b = {}) {
  const auto normal_a = [&](index_t f) -> const vec3& { return faces_a[static_cast<std::size_t>(f)].normal; };
  const auto normal_b = [&](index_t f) -> const vec3& { return faces_b[static_cast<std::size_t>(f)].normal; };
  const vec3 ca = vertex_mean(a);  // to orient the edge-pair axes outward from A
  // Per edge of B, the arc of its reversed face normals c, d and d x c as columns (computed once
  // per call), so the arc test of one edge of A against all of B's runs branch-free over them.
  thread_local std::vector<real> arcs;
  thread_local std::vector<index_t> crossing;
  thread_local std::vector<std::uint8_t> crosses;
  thread_local std::vector<index_t> edge_of;  // the edges of B in the columns
  edge_of.clear();
  for (std::size_t j = 0; j < edges_b.list.size(); ++j)
    if (skip_b.empty() || skip_b[j] == 0) edge_of.push_back(static_cast<index_t>(j));
  const std::size_t nb_edges = edge_of.size();
  arcs.resize(9 * nb_edges);
  crossing.resize(nb_edges);
  crosses.resize(nb_edges);
  real* col[9];
  for (std::size_t k = 0; k < 9; ++k) col[k] = arcs.data() + k * nb_edges;
  for (std::size_t j = 0; j < nb_edges; ++j) {
    const auto& eb = edges_b.list[static_cast<std::size_t>(edge_of[j])];
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
    if (!skip_a.empty() && skip_a[i] != 0) continue;
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
      const auto j = static_cast<std::size_t>(edge_of[static_cast<std::size_t>(crossing[k])]);
      const auto& eb = edges_b.list[j];
      const vec3 db = b.vertex(eb.v) - b.vertex(eb.u);
      vec3 n = da.cross(db);
      const real length = n.norm();
      if (!(length > 1e-9 * da.norm() * db.norm())) continue;  // parallel edges: a face axis covers them
      n /= length;
      if (n.dot(a.vertex(ea.u) - ca) < 0) n = -n;  // outward from A at its edge
      visit(n, i, j);
    }
  }
}

/// Marks the edges of A (skip_a) and of B (skip_b) whose every edge-pair axis has a gap at most
/// `level` (m), so that common_plane_above leaves them out. An edge-pair axis n that common_plane
/// keeps is, up to rounding, where the Gauss arcs of the two edges cross: a non-negative
/// combination of the edge's two face normals na, nb, along which the edge supports its block.
/// With cB a point of B (its vertex mean) and u an end of A's edge, the axis's gap
/// n.(b_u - a_u) <= n.(cB - a_u) <= max(na.(cB - a_u), nb.(cB - a_u)) when that is <= 0; for an
/// edge of B, with its reversed normals, n.(b_u - a_u) <= n.(b_u - cA) <= the same expression
/// with B's outward normals and cA - b_u. The computed n is off the
/// crossing by at most kappa = 1e9 (delta + 1e-15) + 1e-6 rad (delta: how far the face normals are
/// from normal to their edges, 1e9: the inverse of the parallel-edge cut), which moves the gap by
/// kappa x the pairs' diagonal: an edge is left out when its bound is that much under the level.
/// Returns false (nothing marked) where that is not certain: kappa > 1e-2, or A's vertex mean
/// too near its surface for the axis's orientation to be certain.
inline bool skip_far_edges(const geometry::convex_polyhedron& a, const polyhedron_edges& edges_a,
                           std::span<const geometry::plane> faces_a, const geometry::convex_polyhedron& b,
                           const polyhedron_edges& edges_b, std::span<const geometry::plane> faces_b, real level,
                           std::vector<std::uint8_t>& skip_a, std::vector<std::uint8_t>& skip_b) {
  if (!(level > -std::numeric_limits<real>::infinity())) return false;
  const vec3 ca = vertex_mean(a), cb = vertex_mean(b);
  // The bound per edge (for B, with its reversed normals and b_u - cA: the same expression with
  // its outward ones), and how far its face normals are from normal to it.
  real delta = 0;
  const auto bounds = [&](const geometry::convex_polyhedron& p, const polyhedron_edges& edges,
                          std::span<const geometry::plane> faces, const vec3& other, std::vector<real>& out) {
    out.resize(edges.list.size());
    for (std::size_t i = 0; i < edges.list.size(); ++i) {
      const auto& e = edges.list[i];
      const vec3& nl = faces[static_cast<std::size_t>(e.face_left)].normal;
      const vec3& nr = faces[static_cast<std::size_t>(e.face_right)].normal;
      const vec3 d = p.vertex(e.v) - p.vertex(e.u);
      const real length = d.norm();
      delta = std::max({delta, std::abs(nl.dot(d)) / length, std::abs(nr.dot(d)) / length});
      const vec3 w = other - p.vertex(e.u);
      out[i] = std::max(nl.dot(w), nr.dot(w));
    }
  };
  thread_local std::vector<real> bound_a, bound_b;
  bounds(a, edges_a, faces_a, cb, bound_a);
  bounds(b, edges_b, faces_b, ca, bound_b);
  const real kappa = 1e9 * (delta + 1e-15) + 1e-6;
  const aabb box_a = a.bounds(), box_b = b.bounds();
  const real diagonal = (box_a.hi.cwiseMax(box_b.hi) - box_a.lo.cwiseMin(box_b.lo)).norm();
  real inside = std::numeric_limits<real>::infinity();  // A's vertex mean to its nearest face plane
  for (const geometry::plane& f : faces_a) inside = std::min(inside, -f.signed_distance(ca));
  if (!(kappa <= 1e-2) || !(inside > 4 * kappa * diagonal)) return false;
  const real cut = level - 2 * kappa * diagonal;
  const auto mark = [&](const std::vector<real>& bound, std::vector<std::uint8_t>& skip) {
    skip.resize(bound.size());
    for (std::size_t i = 0; i < bound.size(); ++i) skip[i] = static_cast<std::uint8_t>(bound[i] <= 0 && bound[i] <= cut);
  };
  mark(bound_a, skip_a);
  mark(bound_b, skip_b);
  return true;
}

[[nodiscard]] TESSERA_INLINE contact_plane common_plane_every_axis(const geometry::convex_polyhedron& a,
                                                                   const polyhedron_edges& edges_a,
                                                                   std::span<const geometry::plane> faces_a,
                                                                   const geometry::convex_polyhedron& b,
                                                                   const polyhedron_edges& edges_b,
                                                                   std::span<const geometry::plane> faces_b,
                                                                   bool prune_edges) {
  require_plane_arguments(a, faces_a, b, faces_b);
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
  visit_edge_axes(a, edges_a, faces_a, b, edges_b, faces_b, prune_edges, [&](const vec3& n, std::size_t i, std::size_t j) {
    if (prune_edges)  // the two edges are the supporting features along n: no vertex loop
      consider_supports(n, n.dot(a.vertex(edges_a.list[i].u)), n.dot(b.vertex(edges_b.list[j].u)), plane_source::edge_edge,
                        static_cast<index_t>(i), static_cast<index_t>(j), tie);
    else
      consider(n, plane_source::edge_edge, static_cast<index_t>(i), static_cast<index_t>(j), tie);
  });
  best.offset = 0.5 * (best_a + best_b);
  return best;
}

}  // namespace detail

[[nodiscard]] TESSERA_INLINE contact_plane common_plane(const geometry::convex_polyhedron& a, const polyhedron_edges& edges_a,
                                                        std::span<const geometry::plane> faces_a,
                                                        const geometry::convex_polyhedron& b, const polyhedron_edges& edges_b,
                                                        std::span<const geometry::plane> faces_b, bool prune_edges) {
  return prune_edges ? common_plane_above(a, edges_a, faces_a, b, edges_b, faces_b, -std::numeric_limits<real>::infinity())
                     : detail::common_plane_every_axis(a, edges_a, faces_a, b, edges_b, faces_b, false);
}

[[nodiscard]] TESSERA_INLINE contact_plane common_plane_above(const geometry::convex_polyhedron& a,
                                                              const polyhedron_edges& edges_a,
                                                              std::span<const geometry::plane> faces_a,
                                                              const geometry::convex_polyhedron& b,
                                                              const polyhedron_edges& edges_b,
                                                              std::span<const geometry::plane> faces_b, real floor) {
  detail::require_plane_arguments(a, faces_a, b, faces_b);
  constexpr real lowest = -std::numeric_limits<real>::infinity();
  if (std::isnan(floor)) floor = lowest;
  const aabb box_a = a.bounds(), box_b = b.bounds();
  const real size = std::max(box_a.size().maxCoeff(), box_b.size().maxCoeff());  // (as extent())
  const real tie = plane_tie_rel * size;
  // An early drop needs its partial gap 1e-12 x (size + largest coordinate) under the level, so
  // that it holds whatever the rounding of its dot products against the full loops' (e.g. their
  // contraction into fused multiply-adds under -march=native).
  const real reach = std::max({box_a.lo.cwiseAbs().maxCoeff(), box_a.hi.cwiseAbs().maxCoeff(),
                               box_b.lo.cwiseAbs().maxCoeff(), box_b.hi.cwiseAbs().maxCoeff()});
  const real clear = 1e-12 * (size + reach);
  contact_plane best;
  best.gap = lowest;
  real best_a = 0, best_b = 0;
  bool taken = false, ambiguous = false;
  // common_plane's rule once an axis is taken; before, a gap at most `floor` is dropped, and one
  // within the tie above it could lose to a dropped one in the full search: that runs instead.
  const auto take = [&](const vec3& n, real max_a, real min_b, plane_source source, index_t fa, index_t fb) {
    const real g = min_b - max_a;
    if (taken ? !(g > best.gap + tie) : !(g > floor)) return;
    if (!taken && !(g > floor + tie)) {
      ambiguous = true;
      return;
    }
    best = {n, 0, g, source, fa, fb};
    best_a = max_a;
    best_b = min_b;
    taken = true;
  };
  // Whether the gap along n is certainly at most the level, from the start value `first` of one
  // block's support (a vertex of the face: at most A's max, at least B's min) and a running
  // extreme over the other block's vertices, stopped as soon as it shows it.
  const auto drops = [&](const vec3& n, real first, const geometry::convex_polyhedron& other, bool other_is_b) {
    const real level = (taken ? best.gap + tie : floor) - clear;
    if (!(level > lowest)) return false;
    real extreme = other_is_b ? std::numeric_limits<real>::infinity() : lowest;
    for (const vec3& x : other.vertices()) {
      const real d = n.dot(x);
      if (other_is_b ? (extreme = std::min(extreme, d)) - first <= level : first - (extreme = std::max(extreme, d)) <= level)
        return true;
    }
    return false;
  };
  for (index_t f = 0; f < a.face_count(); ++f) {
    const vec3& n = faces_a[static_cast<std::size_t>(f)].normal;
    if (!drops(n, n.dot(a.vertex(a.face(f)[0])), b, true))
      take(n, detail::support_max(a, n), detail::support_min(b, n), plane_source::face_a, f, invalid_index);
  }
  for (index_t f = 0; f < b.face_count(); ++f) {
    const vec3 n = -faces_b[static_cast<std::size_t>(f)].normal;
    if (!drops(n, n.dot(b.vertex(b.face(f)[0])), a, false))
      take(n, detail::support_max(a, n), detail::support_min(b, n), plane_source::face_b, invalid_index, f);
  }
  thread_local std::vector<std::uint8_t> skip_a, skip_b;
  const bool skips = detail::skip_far_edges(a, edges_a, faces_a, b, edges_b, faces_b,
                                            (taken ? best.gap + tie : floor) - clear, skip_a, skip_b);
  detail::visit_edge_axes(
      a, edges_a, faces_a, b, edges_b, faces_b, true,
      [&](const vec3& n, std::size_t i, std::size_t j) {
        take(n, n.dot(a.vertex(edges_a.list[i].u)), n.dot(b.vertex(edges_b.list[j].u)), plane_source::edge_edge,
             static_cast<index_t>(i), static_cast<index_t>(j));
      },
      skips ? std::span<const std::uint8_t>(skip_a) : std::span<const std::uint8_t>(),
      skips ? std::span<const std::uint8_t>(skip_b) : std::span<const std::uint8_t>());
  if (ambiguous || !taken) return detail::common_plane_every_axis(a, edges_a, faces_a, b, edges_b, faces_b, true);
  best.offset = 0.5 * (best_a + best_b);
  return best;
}

[[nodiscard]] TESSERA_INLINE contact_plane hinted_plane(const geometry::convex_polyhedron& a, const polyhedron_edges& edges_a,
                                                        std::span<const geometry::plane> faces_a,
                                                        const geometry::convex_polyhedron& b, const polyhedron_edges& edges_b,
                                                        std::span<const geometry::plane> faces_b, const axis_hint& hint) {
  contact_plane out;
  out.gap = -std::numeric_limits<real>::infinity();
  out.source = hint.source;
  out.feature_a = hint.feature_a;
  out.feature_b = hint.feature_b;
  if (a.empty() || b.empty() || faces_a.size() != static_cast<std::size_t>(a.face_count()) ||
      faces_b.size() != static_cast<std::size_t>(b.face_count()))
    return out;
  const auto in_range = [](index_t f, std::size_t n) { return f >= 0 && static_cast<std::size_t>(f) < n; };
  const real margin = 2 * plane_tie_rel * std::max(a.extent(), b.extent());
  // A face axis: common_plane's consider() for it, the same expressions.
  if (hint.source != plane_source::edge_edge) {
    const bool of_a = hint.source == plane_source::face_a;
    if (!(of_a ? in_range(hint.feature_a, faces_a.size()) : in_range(hint.feature_b, faces_b.size()))) return out;
    const vec3 n = of_a ? faces_a[static_cast<std::size_t>(hint.feature_a)].normal
                        : vec3(-faces_b[static_cast<std::size_t>(hint.feature_b)].normal);
    out.normal = n;
    out.gap = detail::support_min(b, n) - detail::support_max(a, n) - margin;
    return out;
  }
  if (!in_range(hint.feature_a, edges_a.list.size()) || !in_range(hint.feature_b, edges_b.list.size())) return out;
  const auto& ea = edges_a.list[static_cast<std::size_t>(hint.feature_a)];
  const auto& eb = edges_b.list[static_cast<std::size_t>(hint.feature_b)];
  // The arc test of common_plane's pruned edge loop, with its three signs held 1e-12 clear of
  // zero so that no rounding of the vectorised loop can take the pair out of its candidates.
  const vec3& na = faces_a[static_cast<std::size_t>(ea.face_left)].normal;
  const vec3& nb = faces_a[static_cast<std::size_t>(ea.face_right)].normal;
  const vec3 c = -faces_b[static_cast<std::size_t>(eb.face_left)].normal;
  const vec3 d = -faces_b[static_cast<std::size_t>(eb.face_right)].normal;
  const vec3 b_x_a = nb.cross(na), d_x_c = d.cross(c);
  const real cba = c.dot(b_x_a), dba = d.dot(b_x_a), adc = na.dot(d_x_c), bdc = nb.dot(d_x_c);
  constexpr real clear = 1e-12;
  if (!(cba * dba < -clear && adc * bdc < -clear && cba * bdc > clear)) return out;
  const vec3 da = a.vertex(ea.v) - a.vertex(ea.u);
  const vec3 db = b.vertex(eb.v) - b.vertex(eb.u);
  vec3 n = da.cross(db);
  const real length = n.norm();
  if (!(length > 2e-9 * da.norm() * db.norm())) return out;  // (common_plane skips below 1e-9)
  n /= length;
  vec3 ca = vec3::Zero();
  for (const vec3& x : a.vertices()) ca += x;
  ca /= static_cast<real>(a.vertex_count());
  const real side = n.dot(a.vertex(ea.u) - ca);
  if (!(std::abs(side) > margin)) return out;
  if (side < 0) n = -n;  // outward from A at its edge
  out.normal = n;
  out.gap = n.dot(b.vertex(eb.u)) - n.dot(a.vertex(ea.u)) - margin;
  return out;
}

}  // namespace tessera::contact::detection
