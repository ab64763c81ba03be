// The definitions of the larger functions that geometry/convex_hull.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../convex_hull.hpp"

namespace tessera::geometry::detail {

[[nodiscard]] TESSERA_INLINE hull_loops compute_hull_loops(std::span<const vec3> points, const char* who) {
  const std::size_t n = points.size();
  require(n >= 4, who, ": ", n, " points given; a convex polyhedron needs at least 4 points not all in one plane");
  aabb bb;
  real coordinate_max = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const vec3& p = points[k];
    require(p.allFinite(), who, ": point ", k, " = (", p.x(), ", ", p.y(), ", ", p.z(), ") m is not finite");
    bb.expand(p);
    coordinate_max = std::max(coordinate_max, p.cwiseAbs().maxCoeff());
  }
  const real tol = std::max(plane_tolerance_rel * bb.size().maxCoeff(), plane_rounding_tolerance(coordinate_max));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const real d = (points[i] - points[j]).norm();
      require(d > tol, who, ": points ", i, " and ", j, " coincide at (", points[j].x(), ", ", points[j].y(), ", ",
              points[j].z(), ") m (distance ", d, " m <= tolerance ", tol, " m); give each vertex once");
    }

  // ---- initial tetrahedron of extreme points --------------------------------------------
  auto farthest = [&](auto&& distance) {
    std::size_t best = 0;
    real best_d = -1;
    for (std::size_t k = 0; k < n; ++k)
      if (const real d = distance(points[k]); d > best_d) best_d = d, best = k;
    return std::pair{best, best_d};
  };
  std::size_t i0 = 0;
  for (std::size_t k = 1; k < n; ++k)
    if (points[k].x() < points[i0].x()) i0 = k;
  const vec3 a = points[i0];
  const std::size_t i1 = farthest([&](const vec3& p) { return (p - a).norm(); }).first;
  const vec3 u = (points[i1] - a).normalized();
  const auto [i2, line_distance] = farthest([&](const vec3& p) { return (p - a).cross(u).norm(); });
  require(line_distance > tol, who, ": all ", n, " points lie within ", line_distance, " m of the line through points ",
          i0, " and ", i1, " (tolerance ", tol, " m); a convex polyhedron needs volume");
  const vec3 normal = (points[i1] - a).cross(points[i2] - a).normalized();
  const auto [i3, plane_distance] = farthest([&](const vec3& p) { return std::abs(normal.dot(p - a)); });
  require(plane_distance > tol, who, ": all ", n, " points lie within ", plane_distance, " m of one plane, through points ",
          i0, ", ", i1, ", ", i2, " with normal (", normal.x(), ", ", normal.y(), ", ", normal.z(), ") (tolerance ", tol,
          " m); a convex polyhedron needs volume");

  // ---- incremental hull of triangles ---------------------------------------------------
  struct triangle {
    std::array<index_t, 3> v;
    plane h;
    bool alive;
  };
  std::vector<triangle> tris;
  std::map<std::pair<index_t, index_t>, index_t> edge_face;  // directed edge -> triangle using it
  auto point = [&](index_t k) -> const vec3& { return points[static_cast<std::size_t>(k)]; };
  auto add_triangle = [&](index_t p, index_t q, index_t r) {
    const vec3 nrm = (point(q) - point(p)).cross(point(r) - point(p)).normalized();
    const index_t id = static_cast<index_t>(tris.size());
    tris.push_back({{p, q, r}, plane::through(nrm, (point(p) + point(q) + point(r)) / 3), true});
    for (int e = 0; e < 3; ++e) {
      const auto key = std::pair{tris.back().v[static_cast<std::size_t>(e)], tris.back().v[static_cast<std::size_t>((e + 1) % 3)]};
      require<geometry_error>(edge_face.emplace(key, id).second, who, ": inconsistent hull near points ", key.first,
                              " and ", key.second, " (edge used twice in one direction); points closer than ",
                              "the tolerance to several hull planes");
    }
  };
  {
    const index_t t0 = static_cast<index_t>(i0), t1 = static_cast<index_t>(i1), t2 = static_cast<index_t>(i2),
                  t3 = static_cast<index_t>(i3);
    // (t0, t1, t2) outward means t3 below it
    const bool flip = normal.dot(points[i3] - a) > 0;
    const index_t p1 = flip ? t2 : t1, p2 = flip ? t1 : t2;
    add_triangle(t0, p1, p2);
    add_triangle(t0, t3, p1);
    add_triangle(p1, t3, p2);
    add_triangle(p2, t3, t0);
  }
  std::vector<index_t> visible;
  std::vector<std::pair<index_t, index_t>> horizon;
  for (std::size_t k = 0; k < n; ++k) {
    if (k == i0 || k == i1 || k == i2 || k == i3) continue;
    const vec3& p = points[k];
    visible.clear();
    for (std::size_t f = 0; f < tris.size(); ++f)
      if (tris[f].alive && classify(tris[f].h, p, tol) == side::outside) visible.push_back(static_cast<index_t>(f));
    if (visible.empty()) continue;  // inside the hull or within tol of it: not an extreme point
    horizon.clear();
    for (index_t f : visible)
      for (int e = 0; e < 3; ++e) {
        const auto& v = tris[static_cast<std::size_t>(f)].v;
        const index_t s = v[static_cast<std::size_t>(e)], t = v[static_cast<std::size_t>((e + 1) % 3)];
        const index_t g = edge_face.at({t, s});
        if (!std::binary_search(visible.begin(), visible.end(), g)) horizon.emplace_back(s, t);
      }
    for (index_t f : visible) {
      tris[static_cast<std::size_t>(f)].alive = false;
      const auto& v = tris[static_cast<std::size_t>(f)].v;
      for (int e = 0; e < 3; ++e) edge_face.erase({v[static_cast<std::size_t>(e)], v[static_cast<std::size_t>((e + 1) % 3)]});
    }
    for (const auto& [s, t] : horizon) add_triangle(s, t, static_cast<index_t>(k));
    // the fan closes only if the horizon is one loop: every new edge has its reverse
    for (const auto& [s, t] : horizon)
      require<geometry_error>(edge_face.count({static_cast<index_t>(k), s}) == 1 && edge_face.count({t, static_cast<index_t>(k)}) == 1,
                              who, ": the horizon of point ", k, " is not one loop (near-coplanar points within the ",
                              "tolerance ", tol, " m); remove the points that are nearly on other hull faces");
  }

  // ---- merge coplanar triangles into faces -----------------------------------------------
  std::vector<index_t> live;
  for (std::size_t f = 0; f < tris.size(); ++f)
    if (tris[f].alive) live.push_back(static_cast<index_t>(f));
  std::vector<index_t> parent(tris.size());
  std::iota(parent.begin(), parent.end(), index_t{0});
  auto find = [&](index_t x) {
    while (parent[static_cast<std::size_t>(x)] != x) x = parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    return x;
  };
  auto opposite = [&](index_t f, index_t s, index_t t) {
    for (index_t v : tris[static_cast<std::size_t>(f)].v)
      if (v != s && v != t) return v;
    return invalid_index;
  };
  for (index_t f : live) {
    const triangle& tf = tris[static_cast<std::size_t>(f)];
    for (int e = 0; e < 3; ++e) {
      const index_t s = tf.v[static_cast<std::size_t>(e)], t = tf.v[static_cast<std::size_t>((e + 1) % 3)];
      const index_t g = edge_face.at({t, s});
      if (g < f) continue;
      const triangle& tg = tris[static_cast<std::size_t>(g)];
      if (tf.h.normal.dot(tg.h.normal) > 0 && classify(tf.h, point(opposite(g, t, s)), tol) == side::on &&
          classify(tg.h, point(opposite(f, s, t)), tol) == side::on) {
        const index_t ra = find(f), rb = find(g);
        if (ra != rb) parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
      }
    }
  }

  // ---- face loops: the boundary of each group, collinear vertices dropped ----------------
  std::vector<std::vector<index_t>> loops;
  std::map<index_t, index_t> next;
  for (index_t root : live) {
    if (find(root) != root) continue;
    next.clear();
    std::size_t edges = 0;
    for (index_t f : live) {
      if (find(f) != root) continue;
      const auto& v = tris[static_cast<std::size_t>(f)].v;
      for (int e = 0; e < 3; ++e) {
        const index_t s = v[static_cast<std::size_t>(e)], t = v[static_cast<std::size_t>((e + 1) % 3)];
        if (find(edge_face.at({t, s})) == root) continue;  // inner edge of the face
        require<geometry_error>(next.emplace(s, t).second, who, ": a hull face pinches at point ", s,
                                " (coplanar points within the tolerance ", tol, " m)");
        ++edges;
      }
    }
    std::vector<index_t> loop;
    index_t v = next.begin()->first;
    do {
      loop.push_back(v);
      const auto it = next.find(v);
      v = it == next.end() ? invalid_index : it->second;
    } while (v != invalid_index && v != loop.front() && loop.size() <= edges);
    require<geometry_error>(v == loop.front() && loop.size() == edges, who,
                            ": a hull face is not one loop (coplanar points within the tolerance ", tol, " m)");
    loops.push_back(std::move(loop));
  }
  // A vertex on the straight line of its loop neighbours lies inside a hull edge and is in the two
  // loops of that edge with the same neighbours (reversed): the symmetric test drops it from both.
  for (bool changed = true; changed;) {
    changed = false;
    for (auto& loop : loops)
      for (std::size_t k = 0; k < loop.size() && loop.size() > 3; ++k) {
        const vec3& p = point(loop[(k + loop.size() - 1) % loop.size()]);
        const vec3& q = point(loop[k]);
        const vec3& r = point(loop[(k + 1) % loop.size()]);
        if ((q - p).cross(r - p).norm() <= tol * (r - p).norm()) {
          loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(k));
          changed = true;
        }
      }
  }

  // ---- vertices in input order, loops renumbered ------------------------------------------
  hull_loops out;
  std::vector<index_t> id(n, invalid_index);
  for (const auto& loop : loops)
    for (index_t v : loop) id[static_cast<std::size_t>(v)] = 0;
  for (std::size_t k = 0; k < n; ++k)
    if (id[k] == 0) {
      id[k] = static_cast<index_t>(out.vertices.size());
      out.vertices.push_back(points[k]);
      out.input_index.push_back(static_cast<index_t>(k));
    }
  for (const auto& loop : loops) {
    for (index_t v : loop) out.face_vertices.push_back(id[static_cast<std::size_t>(v)]);
    out.face_offsets.push_back(static_cast<index_t>(out.face_vertices.size()));
  }
  const index_t euler = static_cast<index_t>(out.vertices.size()) - static_cast<index_t>(out.face_vertices.size()) / 2 +
                        static_cast<index_t>(loops.size());
  require<geometry_error>(out.face_vertices.size() % 2 == 0 && euler == 2, who, ": the hull of ", n,
                          " points is not a closed surface (V - E + F = ", euler,
                          "); points within the tolerance ", tol, " m of several hull planes");
  return out;
}

}  // namespace tessera::geometry::detail
