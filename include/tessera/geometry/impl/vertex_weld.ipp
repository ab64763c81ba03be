// The definitions of the larger functions that geometry/vertex_weld.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../vertex_weld.hpp"

namespace tessera::geometry {

[[nodiscard]] TESSERA_INLINE welded_points weld_vertices(std::span<const vec3> points, real tol, const aabb& domain,
                                                         std::span<const vertex_key> keys,
                                                         std::span<const real> conditioning) {
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

TESSERA_INLINE void recompute_ill_conditioned_vertices(welded_points& welded, std::span<const vec3> points,
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
