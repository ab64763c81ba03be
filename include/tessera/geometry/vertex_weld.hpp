#pragma once
// Step 1 of the tessellation cleanup (cleanup.hpp states the whole policy): the cell vertices
// computed independently by each cell are welded into shared vertices, by distance (max-norm
// tol) and by their topological key, at the position of the best-conditioned member; a welded
// vertex whose members are farther apart than tol is then recomputed from its generators
// (power_centre.hpp).
//
// Cost: O(number of points) time and memory (uniform bin grid, a sort of the keys,
// union-find). Thread safety: pure functions.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "../core/csr.hpp"
#include "../core/types.hpp"
#include "power_centre.hpp"

namespace tessera::geometry {

/// Result of weld_vertices: `vertices[global_id[k]]` is the welded position of point k.
struct welded_points {
  std::vector<vec3> vertices;  ///< the distinct points (m)
  std::vector<index_t> global_id;  ///< for each input point, its index in vertices
};

/// Topological identity of a cell vertex where exactly three faces meet: the sorted ids of the
/// four generators whose planes define it (the cell and its three face tags, boundary tags
/// included). Two cells see the same vertex under the same key however ill-conditioned its
/// position is (e.g. two generators 1e-9 apart make nearly parallel bisectors in their
/// neighbours). no_vertex_key marks vertices with more than three faces.
using vertex_key = std::array<index_t, 4>;
inline constexpr vertex_key no_vertex_key{invalid_index, invalid_index, invalid_index, invalid_index};

/// Welds `points` (m) into shared vertices: points closer than `tol` (m, max-norm), and points
/// with the same vertex key (when `keys` is not empty) that are closer than 1e4 tol, are the
/// same vertex (transitively). The welded position is that of the member with the largest
/// `conditioning` (when given; |det| of its three unit face normals, i.e. the best-conditioned
/// computation), ties and no conditioning resolved by the lowest point index. Coordinates within
/// tol of a side of `domain` are then snapped onto that side. Deterministic for fixed input.
[[nodiscard]] inline welded_points weld_vertices(std::span<const vec3> points, real tol, const aabb& domain,
                                                 std::span<const vertex_key> keys = {},
                                                 std::span<const real> conditioning = {}) {
  welded_points out;
  const std::size_t n = points.size();
  out.global_id.assign(n, invalid_index);
  if (n == 0) return out;
  // Bin grid over the points' bounding box with about 2 points per bin and bins >= 4 tol wide.
  aabb bb;
  for (const vec3& p : points) bb.expand(p);
  const vec3 size = bb.size().cwiseMax(vec3::Constant(4 * tol));
  const real target_bins = std::max<real>(1, static_cast<real>(n) / 2);
  real h = std::cbrt(size.prod() / target_bins);
  h = std::max(h, 4 * tol);
  std::array<std::int64_t, 3> nb{};
  for (int a = 0; a < 3; ++a) nb[static_cast<std::size_t>(a)] = std::clamp<std::int64_t>(
      static_cast<std::int64_t>(std::ceil(size[a] / h)), 1, 1 << 20);
  while (nb[0] * nb[1] * nb[2] > 8 * static_cast<std::int64_t>(n) + 64)
    for (auto& x : nb) x = std::max<std::int64_t>(1, x / 2);
  vec3 inv_h;
  for (int a = 0; a < 3; ++a) inv_h[a] = static_cast<real>(nb[static_cast<std::size_t>(a)]) / size[a];
  auto bin_coord = [&](real x, int a) {
    return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((x - bb.lo[a]) * inv_h[a])), 0,
                                    nb[static_cast<std::size_t>(a)] - 1);
  };
  auto bin_of = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return i + nb[0] * (j + nb[1] * k); };
  const std::int64_t bins = nb[0] * nb[1] * nb[2];
  std::vector<std::int64_t> point_bin(n);
  for (std::size_t k = 0; k < n; ++k) {
    const vec3& p = points[k];
    point_bin[k] = bin_of(bin_coord(p.x(), 0), bin_coord(p.y(), 1), bin_coord(p.z(), 2));
  }
  std::vector<index_t> members(n);
  auto entries = [&](auto&& emit) {
    for (std::size_t k = 0; k < n; ++k)
      emit(point_bin[k], [&](index_t slot) { members[static_cast<std::size_t>(slot)] = static_cast<index_t>(k); });
  };
  const std::vector<index_t> offsets = csr_offsets(static_cast<index_t>(bins), entries);
  csr_fill(offsets, entries);
  // Union-find; the root of a component is its smallest point index.
  std::vector<index_t> parent(n);
  for (std::size_t k = 0; k < n; ++k) parent[k] = static_cast<index_t>(k);
  auto find = [&](index_t x) {
    while (parent[static_cast<std::size_t>(x)] != x) {
      parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
      x = parent[static_cast<std::size_t>(x)];
    }
    return x;
  };
  for (std::size_t k = 0; k < n; ++k) {
    const vec3& p = points[k];
    std::array<std::int64_t, 3> b0{}, b1{};
    for (int a = 0; a < 3; ++a) {
      b0[static_cast<std::size_t>(a)] = bin_coord(p[a] - tol, a);
      b1[static_cast<std::size_t>(a)] = bin_coord(p[a] + tol, a);
    }
    for (std::int64_t bk = b0[2]; bk <= b1[2]; ++bk)
      for (std::int64_t bj = b0[1]; bj <= b1[1]; ++bj)
        for (std::int64_t bi = b0[0]; bi <= b1[0]; ++bi) {
          const std::int64_t b = bin_of(bi, bj, bk);
          for (index_t q = offsets[static_cast<std::size_t>(b)]; q < offsets[static_cast<std::size_t>(b) + 1]; ++q) {
            const index_t m = members[static_cast<std::size_t>(q)];
            if (m >= static_cast<index_t>(k)) break;  // members are in increasing order
            if ((points[static_cast<std::size_t>(m)] - p).cwiseAbs().maxCoeff() > tol) continue;
            const index_t ra = find(m), rb = find(static_cast<index_t>(k));
            if (ra != rb) parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
          }
        }
  }
  if (!keys.empty()) {
    std::vector<std::pair<vertex_key, index_t>> by_key;
    by_key.reserve(n);
    for (std::size_t k = 0; k < n; ++k)
      if (keys[k] != no_vertex_key) by_key.emplace_back(keys[k], static_cast<index_t>(k));
    std::sort(by_key.begin(), by_key.end());
    const real loose = 1e4 * tol;
    for (std::size_t q = 1; q < by_key.size(); ++q) {
      if (by_key[q].first != by_key[q - 1].first) continue;
      const index_t a = by_key[q - 1].second, b = by_key[q].second;
      if ((points[static_cast<std::size_t>(a)] - points[static_cast<std::size_t>(b)]).cwiseAbs().maxCoeff() > loose) continue;
      const index_t ra = find(a), rb = find(b);
      if (ra != rb) parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
    }
  }
  // Representative position: best-conditioned member (first in index order among equals).
  std::vector<index_t> best(n, invalid_index);
  for (std::size_t k = 0; k < n; ++k) {
    const index_t r = find(static_cast<index_t>(k));
    index_t& b = best[static_cast<std::size_t>(r)];
    if (b == invalid_index || (!conditioning.empty() && conditioning[k] > conditioning[static_cast<std::size_t>(b)]))
      b = static_cast<index_t>(k);
  }
  for (std::size_t k = 0; k < n; ++k) {
    const index_t r = find(static_cast<index_t>(k));
    if (r == static_cast<index_t>(k)) {
      out.global_id[k] = static_cast<index_t>(out.vertices.size());
      out.vertices.push_back(points[static_cast<std::size_t>(best[k])]);
    } else {
      out.global_id[k] = out.global_id[static_cast<std::size_t>(r)];
    }
  }
  for (vec3& v : out.vertices)
    for (int a = 0; a < 3; ++a) {
      if (std::abs(v[a] - domain.lo[a]) <= tol) v[a] = domain.lo[a];
      if (std::abs(v[a] - domain.hi[a]) <= tol) v[a] = domain.hi[a];
    }
  return out;
}

/// Step 1 for ill-conditioned vertices. A welded vertex whose members are farther apart than
/// tol was joined by its vertex key (weld_vertices), i.e. every cell computed it from nearly
/// parallel planes: two generators 1e-9 L apart make nearly identical bisectors in each of
/// their neighbours; or by a chain of points each within tol of the next, i.e. several true
/// vertices closer than tol were collapsed into one (fuzz_tessellation: a generator 7.7e-8 m =
/// 1e-9 L from one of eight cospherical generators has a cell with eight vertices within 1.9e-7
/// m of the sphere centre; welded at one of them, the vertex moved 1.9e-7 m and its neighbours'
/// cells were 2.1e-9 of their extent non-convex). Its best-conditioned member can then still be 1e-7 L off the bisector of
/// the close pair (fuzz_tessellation, two such pairs sharing a vertex: every one of its four
/// computations had two nearly parallel planes), which tilts the faces through it by more than
/// the 1e-9 convexity tolerance of check(). Such a vertex is recomputed from what it is by
/// definition, the point of equal power distance to the generators of its keys (and on their box
/// sides), from all pairwise planes at once: the close pair's own bisector is well defined
/// (its normal is the exact difference of the two generators), so the system is well
/// conditioned although every single cell's three planes were not. Vertices whose members agree
/// within tol, i.e. every vertex of a tessellation without near-coincident generators, keep
/// the member's position bit for bit. The generators of every member's key are used, however
/// many: each pair of them has cells with points in the welded cluster, so their plane crosses
/// the segment between those points and passes within the cluster's diameter (9 generators and
/// 36 planes in the example above: the recomputed vertex is at most 6.5e-8 m = 0.84 tol off
/// any of them, the member it had before 1.3e-7 m, and the cells are non-convex by at most
/// 5.5e-10 of their extent instead of 2.1e-9).
inline void recompute_ill_conditioned_vertices(welded_points& welded, std::span<const vec3> points,
                                               std::span<const vertex_key> keys, std::span<const vec3> seeds,
                                               std::span<const real> weights, real tol, const aabb& domain) {
  const std::size_t nv = welded.vertices.size();
  std::vector<aabb> spread(nv);
  for (std::size_t k = 0; k < points.size(); ++k) spread[static_cast<std::size_t>(welded.global_id[k])].expand(points[k]);
  std::vector<std::vector<index_t>> ids;  // per spread vertex: its key ids (filled lazily)
  std::vector<index_t> spread_vertex(nv, invalid_index);
  for (std::size_t g = 0; g < nv; ++g)
    if (spread[g].size().maxCoeff() > tol) {
      spread_vertex[g] = static_cast<index_t>(ids.size());
      ids.emplace_back();
    }
  if (ids.empty()) return;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const index_t sv = spread_vertex[static_cast<std::size_t>(welded.global_id[k])];
    if (sv == invalid_index || keys[k] == no_vertex_key) continue;
    auto& list = ids[static_cast<std::size_t>(sv)];
    list.insert(list.end(), keys[k].begin(), keys[k].end());
  }
  for (std::size_t g = 0; g < nv; ++g) {
    const index_t sv = spread_vertex[g];
    if (sv == invalid_index) continue;
    auto& list = ids[static_cast<std::size_t>(sv)];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    if (list.size() < 4) continue;  // no keyed member
    vec3 x;
    if (!power_centre(list, seeds, weights, domain, x)) continue;
    // the defining point must lie where its computations are (within the key-weld radius)
    const vec3 centre = 0.5 * (spread[g].lo + spread[g].hi);
    if ((x - centre).cwiseAbs().maxCoeff() > 1e4 * tol) continue;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(x[a] - domain.lo[a]) <= tol) x[a] = domain.lo[a];
      if (std::abs(x[a] - domain.hi[a]) <= tol) x[a] = domain.hi[a];
    }
    welded.vertices[g] = x;
  }
}

}  // namespace tessera::geometry
