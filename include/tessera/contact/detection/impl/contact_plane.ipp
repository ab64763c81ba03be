// The definitions of the larger functions that contact/detection/contact_plane.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

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

[[nodiscard]] TESSERA_INLINE contact_plane common_plane(const geometry::convex_polyhedron& a, const polyhedron_edges& edges_a,
                                                        std::span<const geometry::plane> faces_a,
                                                        const geometry::convex_polyhedron& b, const polyhedron_edges& edges_b,
                                                        std::span<const geometry::plane> faces_b, bool prune_edges) {
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
