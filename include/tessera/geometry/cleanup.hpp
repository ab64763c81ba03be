#pragma once
// Cleanup of degenerate geometry: turns independently computed convex cells into one conforming
// tessellation (geometry/tessellation.hpp).
//
// Policy (all lengths relative to the mean cell size L = (V_box / N)^(1/3); the relative
// threshold is tessellation_options::cleanup_tolerance, default 1e-9, so tol = 1e-9 L):
//  1. Weld. Every cell vertex is a point; two points closer than tol in the max-norm are the
//     same vertex, and so are two points defined by the same four generators (vertex_key: the
//     cell and its three incident face tags) even if rounding put them farther apart (up to
//     1e4 tol: nearly coincident generators make ill-conditioned intersections in their
//     neighbours). Welding is transitive (connected components, built with a uniform bin grid,
//     a sort of the keys and union-find). The welded vertex takes the position of its
//     best-conditioned member (largest |det| of the three incident unit face normals), ties
//     broken by cell order, so the result does not depend on the thread count. A welded vertex
//     whose members are farther apart than tol (joined by their key: every computation was
//     ill-conditioned; or by a chain of points closer than tol: true vertices closer than tol
//     collapsed into one) is instead recomputed from its generators, the least-squares point of
//     all their pairwise power planes (recompute_ill_conditioned_vertices). Vertices within
//     tol of a domain side are then snapped exactly onto it.
//  2. Edges shorter than tol have now become repeated consecutive ids in a face loop: the
//     repeats are removed (edge collapse). Spikes a-b-a left by a collapsed sliver are removed
//     too.
//  3. Faces left with fewer than 3 distinct vertices (area of order tol^2 or a sliver thinner
//     than tol) are removed; a cell left with fewer than 4 faces (an empty Laguerre cell or a
//     cell thinner than tol) is removed and the cells are renumbered.
//  4. Faces are paired with their twins: face f of cell c tagged with neighbour n pairs with the
//     face of n tagged c; the two loops must be the same vertex ids in reverse order. A face
//     without such a twin is an error (geometry_error), never silently dropped.
// Why it is safe: the clipping kernel decides plane sides with a tolerance 1e-12 of the cell
// extent (predicates.hpp), so every feature created by a tolerance decision is three orders of
// magnitude shorter than tol and disappears in steps 1-3; features longer than tol are computed
// the same way from both sides and survive in both cells.
//
// Cost: O(total number of cell vertices) time and memory. Thread safety: pure functions.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "../core/csr.hpp"
#include "../core/errors.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "convex_polyhedron.hpp"
#include "predicates.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

/// Result of weld_vertices: `vertices[global_id[k]]` is the welded position of point k.
struct welded_points {
  std::vector<vec3> vertices;
  std::vector<index_t> global_id;
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

namespace detail {

/// Singular values of the 3x3 matrix whose columns are w[0], w[1], w[2], by one-sided (Hestenes)
/// Jacobi rotations: the columns are rotated pairwise until mutually orthogonal, and their norms
/// are then the singular values, each to a few ulps of the largest (enough for the 1e-9 ratio test
/// of power_centre; the normal equations A^T A would square the ratio to 1e-18, below rounding).
/// Returns {largest, smallest}; NaN entries give NaN.
[[nodiscard]] inline std::array<real, 2> extreme_singular_values_3x3(std::array<vec3, 3> w) {
  constexpr real eps = std::numeric_limits<real>::epsilon();
  for (int sweep = 0; sweep < 60; ++sweep) {
    bool rotated = false;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        const real alpha = w[p].squaredNorm(), beta = w[q].squaredNorm(), gamma = w[p].dot(w[q]);
        if (!(std::abs(gamma) > eps * std::sqrt(alpha * beta))) continue;  // orthogonal (or NaN)
        const real zeta = (beta - alpha) / (2 * gamma);
        const real t = std::copysign(real(1), zeta) / (std::abs(zeta) + std::sqrt(1 + zeta * zeta));
        const real c = 1 / std::sqrt(1 + t * t), s = c * t;
        const vec3 wp = w[p];
        w[p] = c * wp - s * w[q];
        w[q] = s * wp + c * w[q];
        rotated = true;
      }
    if (!rotated) break;
  }
  const real n0 = w[0].norm(), n1 = w[1].norm(), n2 = w[2].norm();
  if (!(std::isfinite(n0) && std::isfinite(n1) && std::isfinite(n2)))
    return {std::numeric_limits<real>::quiet_NaN(), std::numeric_limits<real>::quiet_NaN()};
  return {std::max({n0, n1, n2}), std::min({n0, n1, n2})};
}

}  // namespace detail

/// The power centre of the generators and box sides in `ids` (generator ids >= 0, boundary
/// tags < 0): the least-squares point of every pairwise power plane and every side plane.
/// Returns false when those planes do not fix a point (smallest singular value of the rows x 3
/// system below 1e-9 of the largest), e.g. fewer than three independent directions; the point is
/// then unique and is solved by Householder QR (the rows are unit normals, offsets in m) and back
/// substitution. Written out by hand rather than with an Eigen decomposition: this non-template
/// inline function is compiled in every translation unit that includes geometry.hpp, and Eigen's
/// JacobiSVD<MatrixXd> it used cost ~4 s of compile time in each (issue #40 item 9).
[[nodiscard]] inline bool power_centre(std::span<const index_t> ids, std::span<const vec3> seeds,
                                       std::span<const real> weights, const aabb& domain, vec3& x) {
  std::vector<std::array<real, 4>> rows;  // [n_x, n_y, n_z, offset]: n . x = offset
  auto add_row = [&](const vec3& n, real offset) { rows.push_back({n.x(), n.y(), n.z(), offset}); };
  auto weight = [&](index_t i) { return weights.empty() ? real(0) : weights[static_cast<std::size_t>(i)]; };
  for (std::size_t p = 0; p < ids.size(); ++p) {
    const index_t i = ids[p];
    if (i < 0) {
      const int side = boundary_side(i);
      add_row(vec3::Unit(side / 2), (side % 2) ? domain.hi[side / 2] : domain.lo[side / 2]);
      continue;
    }
    for (std::size_t q = p + 1; q < ids.size(); ++q) {
      const index_t j = ids[q];
      if (j < 0) continue;
      const plane h = power_plane(seeds[static_cast<std::size_t>(i)], weight(i), seeds[static_cast<std::size_t>(j)], weight(j));
      add_row(h.normal, h.offset);
    }
  }
  const std::size_t m = rows.size();
  if (m < 3) return false;
  // Householder QR of [A | b]: after column k, rows[k][k..3] is row k of [R | Q^T b].
  for (int k = 0; k < 3; ++k) {
    real norm2 = 0;
    for (std::size_t r = static_cast<std::size_t>(k); r < m; ++r) norm2 += rows[r][k] * rows[r][k];
    const real norm = std::sqrt(norm2);
    if (!(norm > 0)) return false;  // a zero (or NaN) column: no point
    const auto kk = static_cast<std::size_t>(k);
    const real alpha = rows[kk][k] > 0 ? -norm : norm;  // R_kk, of opposite sign: no cancellation
    const real v0 = rows[kk][k] - alpha;                // Householder vector v = (v0, rows[k+1..][k])
    const real v_norm2 = v0 * v0 + (norm2 - rows[kk][k] * rows[kk][k]);
    for (int j = k + 1; j < 4; ++j) {
      real dot = v0 * rows[kk][j];
      for (std::size_t r = kk + 1; r < m; ++r) dot += rows[r][k] * rows[r][j];
      const real f = 2 * dot / v_norm2;
      rows[kk][j] -= f * v0;
      for (std::size_t r = kk + 1; r < m; ++r) rows[r][j] -= f * rows[r][k];
    }
    rows[kk][k] = alpha;
    for (std::size_t r = kk + 1; r < m; ++r) rows[r][k] = 0;
  }
  // R has the singular values of A
  const std::array<vec3, 3> r_columns{vec3(rows[0][0], 0, 0), vec3(rows[0][1], rows[1][1], 0),
                                      vec3(rows[0][2], rows[1][2], rows[2][2])};
  const auto [sigma_max, sigma_min] = detail::extreme_singular_values_3x3(r_columns);
  if (!(sigma_min > 1e-9 * sigma_max)) return false;
  x[2] = rows[2][3] / rows[2][2];
  x[1] = (rows[1][3] - rows[1][2] * x[2]) / rows[1][1];
  x[0] = (rows[0][3] - rows[0][1] * x[1] - rows[0][2] * x[2]) / rows[0][0];
  return x.allFinite();
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

/// Removes repeated consecutive ids (cyclically) and spikes a-b-a from a face loop, in place.
inline void clean_loop(std::vector<index_t>& loop) {
  bool changed = true;
  while (changed && !loop.empty()) {
    changed = false;
    std::size_t w = 0;
    for (std::size_t r = 0; r < loop.size(); ++r) {
      const index_t v = loop[r];
      if (w > 0 && loop[w - 1] == v) { changed = true; continue; }
      if (w > 1 && loop[w - 2] == v) { --w; changed = true; continue; }
      loop[w++] = v;
    }
    loop.resize(w);
    // wrap-around: last == first, or spike across the seam
    if (loop.size() > 1 && loop.back() == loop.front()) { loop.pop_back(); changed = true; }
    else if (loop.size() > 2 && loop[loop.size() - 2] == loop.front()) { loop.pop_back(); changed = true; }
    else if (loop.size() > 2 && loop.back() == loop[1]) { loop.erase(loop.begin()); changed = true; }
    if (loop.size() < 3) { loop.clear(); return; }
  }
}

/// Pairs every interior face of `t` with its twin, the face of the neighbour tagged with this cell
/// and the reversed loop, and lists the shared faces; throws geometry_error for a face without one.
inline void match_twins(tessellation& t) {
  t.face_twin.assign(t.face_cell.size(), invalid_index);
  for (index_t f = 0; f < t.face_count(); ++f) {
    const index_t c = t.face_cell[static_cast<std::size_t>(f)], n = t.face_neighbor[static_cast<std::size_t>(f)];
    if (n < 0 || c > n) continue;
    index_t g = invalid_index;
    for (index_t h = t.first_face(n); h < t.end_face(n); ++h)
      if (t.face_neighbor[static_cast<std::size_t>(h)] == c) { g = h; break; }
    require<geometry_error>(g != invalid_index, "tessellation cleanup: face ", f, " of cell ", c,
                            " has no twin in neighbour cell ", n, " (area ",
                            polygon_area_vector(t.vertices, t.face(f)).norm(), " m^2); increase cleanup_tolerance");
    const auto a = t.face(f), b = t.face(g);
    bool reversed = a.size() == b.size();
    if (reversed) {
      const std::size_t m = a.size();
      const auto start = std::find(b.begin(), b.end(), a[0]);
      reversed = start != b.end();
      if (reversed) {
        const std::size_t s = static_cast<std::size_t>(start - b.begin());
        for (std::size_t k = 0; k < m && reversed; ++k) reversed = a[k] == b[(s + m - k) % m];
      }
    }
    require<geometry_error>(reversed, "tessellation cleanup: face ", f, " of cell ", c, " (", a.size(),
                            " vertices) and its twin ", g, " of cell ", n, " (", b.size(),
                            " vertices) are not the same loop reversed; increase cleanup_tolerance");
    t.face_twin[static_cast<std::size_t>(f)] = g;
    t.face_twin[static_cast<std::size_t>(g)] = f;
    t.shared_faces.push_back({c, f, n, g});
  }
  for (index_t f = 0; f < t.face_count(); ++f)
    require<geometry_error>(t.face_neighbor[static_cast<std::size_t>(f)] < 0 || t.face_twin[static_cast<std::size_t>(f)] >= 0,
                            "tessellation cleanup: face ", f, " of cell ", t.face_cell[static_cast<std::size_t>(f)],
                            " toward cell ", t.face_neighbor[static_cast<std::size_t>(f)], " has no twin");
}

/// The vertices of every cell copied to `points` (cell c from point_offset[c]) with their weld
/// keys (the sorted tags of the three faces of a degree-3 vertex and the cell, else no_vertex_key)
/// and the conditioning |n0 . (n1 x n2)| of their first three faces. Parallel over cells.
inline void vertex_keys_of(std::span<const convex_polyhedron> cells, const std::vector<std::size_t>& point_offset,
                           std::vector<vec3>& points, std::vector<vertex_key>& keys, std::vector<real>& conditioning) {
  const std::size_t ncells = cells.size();
  parallel_for(static_cast<std::int64_t>(ncells), [&](std::int64_t ci) {
    const auto c = static_cast<std::size_t>(ci);
    const convex_polyhedron& p = cells[c];
    const std::size_t base = point_offset[c];
    std::copy(p.vertices().begin(), p.vertices().end(), points.begin() + static_cast<std::ptrdiff_t>(base));
    // incident faces of each vertex: count and the first three (keys[] used as scratch)
    thread_local std::vector<int> degree;
    thread_local std::vector<vec3> normal;
    degree.assign(static_cast<std::size_t>(p.vertex_count()), 0);
    normal.resize(static_cast<std::size_t>(p.face_count()));
    for (index_t f = 0; f < p.face_count(); ++f) normal[static_cast<std::size_t>(f)] = p.face_normal(f);
    for (index_t f = 0; f < p.face_count(); ++f)
      for (index_t v : p.face(f)) {
        int& d = degree[static_cast<std::size_t>(v)];
        if (d < 3) keys[base + static_cast<std::size_t>(v)][static_cast<std::size_t>(d)] = f;
        ++d;
      }
    for (index_t v = 0; v < p.vertex_count(); ++v) {
      vertex_key& key = keys[base + static_cast<std::size_t>(v)];
      if (degree[static_cast<std::size_t>(v)] < 3) { key = no_vertex_key; continue; }
      const vec3& n0 = normal[static_cast<std::size_t>(key[0])];
      const vec3& n1 = normal[static_cast<std::size_t>(key[1])];
      const vec3& n2 = normal[static_cast<std::size_t>(key[2])];
      conditioning[base + static_cast<std::size_t>(v)] = std::abs(n0.dot(n1.cross(n2)));
      if (degree[static_cast<std::size_t>(v)] != 3) { key = no_vertex_key; continue; }
      key = {p.face_tag(key[0]), p.face_tag(key[1]), p.face_tag(key[2]), static_cast<index_t>(c)};
      std::sort(key.begin(), key.end());
    }
  }, 64);
}

/// Assembles a conforming tessellation from independently computed cells (cells[c] is the cell
/// of generator c, faces tagged with the neighbouring generator or boundary_tag), following the
/// cleanup policy above with absolute weld tolerance `tol` (m). `seeds` and `weights` (may be
/// empty) are stored per surviving cell. Throws geometry_error for a face without a twin.
[[nodiscard]] inline tessellation assemble_tessellation(const aabb& domain, std::span<const convex_polyhedron> cells,
                                                        std::span<const vec3> seeds, std::span<const real> weights,
                                                        real tol) {
  const std::size_t ncells = cells.size();
  std::vector<std::size_t> point_offset(ncells + 1, 0);
  for (std::size_t c = 0; c < ncells; ++c)
    point_offset[c + 1] = point_offset[c] + static_cast<std::size_t>(cells[c].vertex_count());
  std::vector<vec3> points(point_offset[ncells]);
  std::vector<vertex_key> keys(point_offset[ncells], no_vertex_key);
  std::vector<real> conditioning(point_offset[ncells], 0);
  vertex_keys_of(cells, point_offset, points, keys, conditioning);
  welded_points welded = weld_vertices(points, tol, domain, keys, conditioning);
  if (!seeds.empty()) recompute_ill_conditioned_vertices(welded, points, keys, seeds, weights, tol, domain);

  // Global loops per cell, cleaned; cells with < 4 faces are dropped.
  struct raw_face { index_t neighbor; std::size_t begin, end; };
  std::vector<index_t> loops;
  std::vector<raw_face> faces;
  std::vector<std::size_t> cell_faces(ncells + 1, 0);
  std::vector<index_t> new_id(ncells, invalid_index);
  std::vector<index_t> loop;
  index_t kept = 0;
  for (std::size_t c = 0; c < ncells; ++c) {
    const std::size_t faces_before = faces.size(), loops_before = loops.size();
    const convex_polyhedron& p = cells[c];
    for (index_t f = 0; f < p.face_count(); ++f) {
      loop.clear();
      for (index_t v : p.face(f)) loop.push_back(welded.global_id[point_offset[c] + static_cast<std::size_t>(v)]);
      clean_loop(loop);
      if (loop.empty()) continue;
      faces.push_back({p.face_tag(f), loops.size(), loops.size() + loop.size()});
      loops.insert(loops.end(), loop.begin(), loop.end());
    }
    if (faces.size() - faces_before < 4) {
      faces.resize(faces_before);
      loops.resize(loops_before);
    } else {
      new_id[c] = kept++;
    }
    cell_faces[c + 1] = faces.size();
  }

  tessellation t;
  t.domain = domain;
  // Only vertices used by a surviving face are kept, renumbered in order of first use.
  std::vector<index_t> vertex_id(welded.vertices.size(), invalid_index);
  for (index_t& v : loops) {
    index_t& g = vertex_id[static_cast<std::size_t>(v)];
    if (g == invalid_index) {
      g = static_cast<index_t>(t.vertices.size());
      t.vertices.push_back(welded.vertices[static_cast<std::size_t>(v)]);
    }
    v = g;
  }
  for (std::size_t c = 0; c < ncells; ++c) {
    if (new_id[c] == invalid_index) continue;
    if (!seeds.empty()) t.seeds.push_back(seeds[c]);
    if (!weights.empty()) t.weights.push_back(weights[c]);
    for (std::size_t f = cell_faces[c]; f < cell_faces[c + 1]; ++f) {
      const raw_face& rf = faces[f];
      t.face_vertices.insert(t.face_vertices.end(), loops.begin() + static_cast<std::ptrdiff_t>(rf.begin),
                             loops.begin() + static_cast<std::ptrdiff_t>(rf.end));
      t.face_offsets.push_back(static_cast<index_t>(t.face_vertices.size()));
      t.face_cell.push_back(new_id[c]);
      index_t nb = rf.neighbor;
      if (nb >= 0) {
        nb = new_id[static_cast<std::size_t>(nb)];
        require<geometry_error>(nb != invalid_index, "tessellation cleanup: cell ", c, " keeps a face of ",
                                rf.end - rf.begin, " vertices toward cell ", rf.neighbor,
                                ", which degenerated below the weld tolerance ", tol, " m");
      }
      t.face_neighbor.push_back(nb);
    }
    t.cell_face_offsets.push_back(static_cast<index_t>(t.face_cell.size()));
  }

  match_twins(t);
  return t;
}

}  // namespace tessera::geometry
