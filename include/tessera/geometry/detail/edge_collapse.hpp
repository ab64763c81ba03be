#pragma once
// The edge-collapse machinery of geometry::regularize (regularize.hpp documents the algorithm):
// box-side bookkeeping of vertices, loop collapse, and the collapse state with its checks
// (boundary sides, topology, triangulable faces, positive cones). Not a public interface.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <queue>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "../../core/errors.hpp"
#include "../../core/types.hpp"
#include "../polygon_triangulation.hpp"
#include "../tessellation.hpp"

namespace tessera::geometry {

namespace detail::edge_collapse {

/// A collapse may lower the smallest zone altitude of the cells it touches only while that
/// altitude stays above this fraction of l_min (measured: 0.02 refuses the fewest collapses and
/// gives the largest stable steps among 0.02, 0.1, 0.3 on the study's prisms).
inline constexpr real altitude_floor_rel = 0.02;
/// No original vertex may end farther than this multiple of l_min from its merged vertex
/// (bounded by the farthest corner of the box of the merged originals). Chains of short edges
/// otherwise merge into vertices moved by up to 0.7 L; 3 l_min (0.6 L at the study's 0.2) keeps
/// every measured case's stable step, 1 l_min cuts it up to 20-fold by refusing collapses.
inline constexpr real max_shift_rel = 3.0;

inline constexpr std::uint8_t side_bit(int side) { return static_cast<std::uint8_t>(1u << side); }

/// Box sides (bit s = side s: x-, x+, y-, y+, z-, z+) on which p lies exactly.
[[nodiscard]] inline std::uint8_t sides_of(const vec3& p, const aabb& box) {
  std::uint8_t s = 0;
  for (int a = 0; a < 3; ++a) {
    if (p[a] == box.lo[a]) s |= side_bit(2 * a);
    if (p[a] == box.hi[a]) s |= side_bit(2 * a + 1);
  }
  return s;
}

/// Removes cyclically repeated consecutive ids in place; false if an id then still occurs twice.
[[nodiscard]] inline bool collapse_loop(std::vector<index_t>& loop) {
  std::size_t w = 0;
  for (std::size_t r = 0; r < loop.size(); ++r)
    if (w == 0 || loop[w - 1] != loop[r]) loop[w++] = loop[r];
  loop.resize(w);
  while (loop.size() > 1 && loop.back() == loop.front()) loop.pop_back();
  for (std::size_t i = 0; i < loop.size(); ++i)
    for (std::size_t j = i + 1; j < loop.size(); ++j)
      if (loop[i] == loop[j]) return false;
  return true;
}

enum class verdict { ok, boundary, topology, geometry };

/// Working copy of a tessellation under edge collapses.
struct collapse_state {
  const tessellation& input;
  std::vector<vec3> position;           ///< current position of each (surviving) vertex
  std::vector<vec3> member_sum;         ///< sum of the original positions merged into it
  std::vector<index_t> member_count;
  std::vector<aabb> member_box;         ///< bounding box of the original positions merged into it
  std::vector<index_t> parent;            ///< union-find over original ids (root = kept vertex)
  std::vector<std::uint8_t> sides;
  std::vector<std::vector<index_t>> loop; ///< current loop of each face (empty = dropped)
  std::vector<std::vector<index_t>> vertex_faces;  ///< faces that contained the vertex (may be stale)
  triangulation_workspace ws;
  std::vector<std::array<index_t, 3>> tris;
  struct face_triangles {
    bool valid = false;     ///< tris/foldfree hold for the stored loop and positions
    bool foldfree = false;  ///< a valid triangulation without fold-over exists
    std::vector<std::array<index_t, 3>> tris;
  };
  std::vector<face_triangles> cache;  ///< per face
  std::vector<std::pair<index_t, index_t>> directed;
  std::vector<index_t> scratch_vertices;

  explicit collapse_state(const tessellation& t) : input(t) {
    const auto nv = static_cast<std::size_t>(t.vertex_count());
    position = t.vertices;
    member_sum = t.vertices;
    member_count.assign(nv, 1);
    member_box.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) member_box[v].expand(t.vertices[v]);
    parent.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) parent[v] = static_cast<index_t>(v);
    sides.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) sides[v] = sides_of(t.vertices[v], t.domain);
    loop.resize(static_cast<std::size_t>(t.face_count()));
    cache.resize(static_cast<std::size_t>(t.face_count()));
    vertex_faces.resize(nv);
    for (index_t f = 0; f < t.face_count(); ++f) {
      const auto l = t.face(f);
      loop[static_cast<std::size_t>(f)].assign(l.begin(), l.end());
      for (const index_t v : l) vertex_faces[static_cast<std::size_t>(v)].push_back(f);
    }
  }

  [[nodiscard]] index_t find(index_t v) const {
    while (parent[static_cast<std::size_t>(v)] != v) v = parent[static_cast<std::size_t>(v)];
    return v;
  }
  [[nodiscard]] real length(index_t a, index_t b) const {
    if (a > b) std::swap(a, b);
    return (position[static_cast<std::size_t>(b)] - position[static_cast<std::size_t>(a)]).norm();
  }
  /// True if a and b are consecutive in some live face loop.
  [[nodiscard]] bool is_edge(index_t a, index_t b) const {
    for (const index_t f : vertex_faces[static_cast<std::size_t>(a)]) {
      const auto& l = loop[static_cast<std::size_t>(f)];
      for (std::size_t k = 0; k < l.size(); ++k)
        if (l[k] == a && (l[(k + 1) % l.size()] == b || l[(k + l.size() - 1) % l.size()] == b)) return true;
    }
    return false;
  }

  /// The vertices joined to v by chains of live edges shorter than l_min (sorted, v included).
  void short_edge_cluster(index_t v, real l_min, std::vector<index_t>& out) const {
    out.assign(1, v);
    for (std::size_t head = 0; head < out.size(); ++head) {
      const index_t u = out[head];
      for (const index_t f : vertex_faces[static_cast<std::size_t>(u)]) {
        const auto& l = loop[static_cast<std::size_t>(f)];
        for (std::size_t k = 0; k < l.size(); ++k) {
          if (l[k] != u) continue;
          for (const index_t w : {l[(k + 1) % l.size()], l[(k + l.size() - 1) % l.size()]})
            if (length(u, w) < l_min && std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
        }
      }
    }
    std::sort(out.begin(), out.end());
  }

  /// Checks cell c whose faces have the loops `loops_of(f)` (current positions) and lowers
  /// `min_altitude` (m) to the smallest altitude of the zones geometry::zone_blocks would make.
  template <class Loops>
  [[nodiscard]] verdict check_cell(index_t c, const Loops& loops_of, real& min_altitude) {
    index_t faces = 0;
    directed.clear();
    scratch_vertices.clear();
    for (index_t f = input.first_face(c); f < input.end_face(c); ++f) {
      const std::vector<index_t>& l = loops_of(f);
      if (l.empty()) continue;
      ++faces;
      for (std::size_t k = 0; k < l.size(); ++k) {
        directed.emplace_back(l[k], l[(k + 1) % l.size()]);
        scratch_vertices.push_back(l[k]);
      }
    }
    if (faces < 4) return verdict::topology;
    std::sort(directed.begin(), directed.end());
    for (std::size_t e = 0; e < directed.size(); ++e) {
      if (e > 0 && directed[e] == directed[e - 1]) return verdict::topology;
      const std::pair<index_t, index_t> reverse{directed[e].second, directed[e].first};
      if (!std::binary_search(directed.begin(), directed.end(), reverse)) return verdict::topology;
    }
    std::sort(scratch_vertices.begin(), scratch_vertices.end());
    const auto n_vertices =
        static_cast<index_t>(std::unique(scratch_vertices.begin(), scratch_vertices.end()) - scratch_vertices.begin());
    if (n_vertices - static_cast<index_t>(directed.size()) / 2 + faces != 2) return verdict::topology;

    // Triangulate every face as the zoning will; no fold-over; volume centroid of the triangles.
    // Faces of the current state (loops_of returns the stored loop) are cached: only the faces
    // around the merged vertex change from one candidate to the next.
    tris.clear();
    for (index_t f = input.first_face(c); f < input.end_face(c); ++f) {
      const std::vector<index_t>& l = loops_of(f);
      if (l.empty()) continue;
      const bool current = &l == &loop[static_cast<std::size_t>(f)];
      face_triangles& cached = cache[static_cast<std::size_t>(f)];
      if (current && cached.valid) {
        if (!cached.foldfree) return verdict::geometry;
        tris.insert(tris.end(), cached.tris.begin(), cached.tris.end());
        continue;
      }
      const std::size_t first = tris.size();
      bool foldfree = min_angle_triangulation(position, l, tris, ws) > 0;
      for (std::size_t i = first; i < tris.size() && foldfree; ++i)
        for (std::size_t j = i + 1; j < tris.size() && foldfree; ++j) foldfree = normal(tris[i]).dot(normal(tris[j])) > 0;
      if (current) {
        cached.valid = true;
        cached.foldfree = foldfree;
        cached.tris.assign(tris.begin() + static_cast<std::ptrdiff_t>(first), tris.end());
      }
      if (!foldfree) return verdict::geometry;
    }
    const vec3 p0 = position[static_cast<std::size_t>(tris.front()[0])];
    real volume6 = 0;
    vec3 moment = vec3::Zero();
    for (const auto& t : tris) {
      const vec3 a = position[static_cast<std::size_t>(t[0])] - p0, b = position[static_cast<std::size_t>(t[1])] - p0,
                 cc = position[static_cast<std::size_t>(t[2])] - p0;
      const real v6 = a.dot(b.cross(cc));
      volume6 += v6;
      moment += v6 * (a + b + cc) / 4;
    }
    if (!(volume6 > 0)) return verdict::geometry;
    const vec3 centroid = p0 + moment / volume6;
    for (const auto& t : tris) {
      const vec3& a = position[static_cast<std::size_t>(t[0])];
      const vec3& b = position[static_cast<std::size_t>(t[1])];
      const vec3& cc = position[static_cast<std::size_t>(t[2])];
      const real cone6 = (b - a).cross(cc - a).dot(a - centroid);
      if (!(cone6 > 1e-10 * volume6)) return verdict::geometry;
      // zone altitude h = 3 V / A_max = 6V / (2 A_max); twice the face areas are cross-product norms
      const real twice_area_max = std::max({(b - a).cross(cc - a).norm(), (b - a).cross(centroid - a).norm(),
                                            (cc - b).cross(centroid - b).norm(), (a - cc).cross(centroid - cc).norm()});
      min_altitude = std::min(min_altitude, cone6 / twice_area_max);
    }
    return verdict::ok;
  }
  [[nodiscard]] vec3 normal(const std::array<index_t, 3>& t) const {
    const vec3& a = position[static_cast<std::size_t>(t[0])];
    return (position[static_cast<std::size_t>(t[1])] - a).cross(position[static_cast<std::size_t>(t[2])] - a);
  }
};

}  // namespace detail::edge_collapse

}  // namespace tessera::geometry
