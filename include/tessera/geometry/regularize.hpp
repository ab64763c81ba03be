#pragma once
// Regularization of a conforming tessellation: removal of short edges by edge collapse, as
// Neper's "-regularization" does for the same reason (Quey et al. 2011). Random Voronoi cells
// have edges far shorter than the cell size (0.1 mm in 12 mm cells of the study's prism); every
// zone touching such an edge is a sliver whatever the face triangulation, and slivers are stiff
// for their mass, so they set the explicit stable time step (3e-9 s unscaled for the 100-block
// prism). Collapsing the short edges removes them at the price of slightly warped faces.
//
// Algorithm (serial, deterministic):
//  1. Threshold l_min = min_edge_rel x L, L = (V_box / N_cells)^(1/3) the mean cell size.
//  2. Every edge shorter than l_min enters a queue, shortest first (ties by vertex ids). For the
//     edge (a, b) at the head, first the whole cluster of vertices joined to a by chains of short
//     edges, then the edge alone, is merged into its vertex of smallest GLOBAL id (union-find
//     over global ids): a tiny face then shrinks to a point in one step, without the needle
//     triangles of its intermediate states. The merged vertex is placed at the best of these
//     candidates: the mean of all original vertices merged into it, or the position of one of
//     the merged vertices (which keeps that vertex's faces planar); "best" = the largest
//     smallest zone altitude (see 5). Candidates that would leave an original vertex farther
//     than max_shift_rel x l_min from its merged vertex are skipped.
//  3. Box sides: each vertex carries the set of box sides it lies on (exactly, as welded by
//     cleanup.hpp). A collapse is allowed only if one endpoint's side set contains the other's;
//     the merged vertex then takes the larger set and is projected exactly onto those sides.
//     Hence box corners never move, vertices on a box edge stay on that edge, two different
//     corners (or two points on different box edges) are never merged, and every boundary face
//     stays exactly in its side plane. (Merging a vertex of side x- with one of side y- would put
//     a new vertex on the x-/y- box edge in the middle of an existing boundary edge: a
//     zero-thickness overlap of boundary faces.)
//  4. In every face loop the removed id is replaced by the kept one and consecutive repeats are
//     removed; a face left with fewer than 3 vertices is dropped. The two sides of an interior
//     face use the same global ids, so they change identically: twins stay twins, and a dropped
//     face drops on both sides.
//  5. A collapse is refused (and counted) if any cell touching a or b would afterwards
//       - have fewer than 4 faces, or a face visiting a vertex twice (a pinched face);
//       - not be a closed 2-manifold: every directed edge once, with its reverse, and Euler
//         characteristic V - E + F = 2;
//       - have a face without a valid triangulation (geometry/polygon_triangulation.hpp: no
//         triangle normal opposing the face's Newell normal, no zero angle) or with two of
//         its triangles' normals more than 90 degrees apart (a fold-over); this also refuses
//         faces that would become zero-area;
//       - have a face triangle whose cone to the cell's volume centroid is not positive by a
//         margin of 1e-10 of the cell volume, i.e. the cell must stay star-shaped from its
//         centroid with respect to the same triangles geometry::zone_blocks will use, so the
//         zoning of a regularized tessellation never meets a non-positive zone;
//       - lower the smallest altitude h = 3 V / A_max of those zones (which sets their stable
//         time step) below min(its value before, altitude_floor_rel x l_min). Without this rule
//         a collapse can warp a large face so that one of its triangles passes almost through
//         the centroid (measured: a 2e-5 m high zone in a 30 mm cell).
//     Edges next to a successful collapse are re-queued (their length changed, and an edge
//     refused before may now be collapsible).
//  6. The tessellation is rebuilt: surviving vertices renumbered in increasing old id (so the
//     "smallest global id" rules of the triangulations keep their meaning), dropped faces
//     removed, twins, shared_faces and CSR offsets rebuilt. Cells are never removed.
//
// Guarantees: the result is conforming (every interior face has its reversed twin), every cell
// is a closed 2-manifold with positive volume, the cell volumes sum to the box volume up to
// rounding (the boundary faces stay in their side planes and interior faces cancel pairwise in
// the divergence theorem), and boundary vertices stay on the box. Faces may be slightly warped
// and cells slightly non-convex: geometry::check() measures both (max_face_warp,
// max_nonconvexity), and the zoning and the mass properties handle warped faces because both
// sides of a face use the same triangles. Edges shorter than l_min can remain where every
// collapse was refused; regularization_report counts them.
//
// Cost: O(number of short edges x candidates x cells per vertex x face size^3): 0.1-0.2 s for
// 500 cells at min_edge_rel = 0.2 (serial). Not thread-safe on the same tessellation.

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

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "detail/edge_collapse.hpp"
#include "polygon_triangulation.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

/// Largest accepted min_edge_rel: larger thresholds would collapse whole cells.
inline constexpr real max_regularization = 0.5;

/// What regularize() did.
struct regularization_report {
  real threshold = 0;              ///< l_min (m)
  index_t short_edges_before = 0;    ///< edges shorter than l_min before
  index_t collapsed_edges = 0;       ///< successful collapses (= vertices removed)
  index_t refused_collapses = 0;     ///< collapse attempts refused by a check (an edge may be retried)
  index_t refused_boundary = 0;      ///< of which: incompatible box sides
  index_t refused_topology = 0;      ///< of which: pinched face, < 4 faces, not a closed manifold
  index_t refused_geometry = 0;      ///< of which: untriangulable/folded face, non-positive cone
  index_t dropped_faces = 0;         ///< faces removed (each side of an interior face counts)
  index_t short_edges_after = 0;     ///< edges still shorter than l_min (each was refused)
  real min_edge_before = 0;        ///< shortest edge before (m)
  real min_edge_after = 0;         ///< shortest edge after (m)
  real max_vertex_shift = 0;       ///< largest distance of an original vertex from its merged vertex (m)
};

namespace detail::edge_collapse {

using edge_queue = std::priority_queue<std::tuple<real, index_t, index_t>, std::vector<std::tuple<real, index_t, index_t>>,
                                       std::greater<>>;  // (length, a < b), shortest first

/// Shortest edge of the current loops; the edges shorter than l_min are pushed on `queue`
/// (if given) and counted in `n_short` (if given).
TESSERA_INLINE real shortest_edge(const collapse_state& st, real l_min, edge_queue* queue, index_t* n_short);

/// The tessellation of the collapsed loops: used vertices renumbered, dropped faces removed,
/// twins and shared faces rebuilt. `max_vertex_shift` receives the largest distance of an
/// original vertex from its merged vertex.
TESSERA_INLINE tessellation rebuilt(const tessellation& tess, const collapse_state& st, real& max_vertex_shift);

/// One regularization pass: pops short edges shortest first and merges each vertex cluster
/// (or the single edge) when every check of the file comment passes.
class merge_pass {
 public:
  merge_pass(const tessellation& tess, collapse_state& st, real l_min, regularization_report& rep)
      : tess_(tess), st_(st), l_min_(l_min), rep_(rep),
        altitude_floor_(altitude_floor_rel * l_min), max_shift_(max_shift_rel * l_min),
        cell_stamp_(static_cast<std::size_t>(tess.cell_count()), 0) {}

  edge_queue& queue() { return queue_; }

  void run() {
    std::vector<index_t> cluster;
    while (!queue_.empty()) {
      const auto [len, a, b] = queue_.top();
      queue_.pop();
      if (st_.parent[static_cast<std::size_t>(a)] != a || st_.parent[static_cast<std::size_t>(b)] != b) continue;
      if (st_.length(a, b) != len || !st_.is_edge(a, b)) continue;  // stale entry
      if (refused_and_unchanged(a, b)) continue;
      // First the whole cluster of vertices joined to a by short edges (a tiny face shrinks to
      // a point in one step, without the needle triangles of its intermediate states), then
      // the single edge.
      st_.short_edge_cluster(a, l_min_, cluster);
      verdict v = cluster.size() > 2 ? try_merge(cluster) : verdict::topology;
      if (v != verdict::ok) v = try_merge({a, b});
      if (v == verdict::ok) continue;
      refused_at_[{a, b}] = commits_;
      ++rep_.refused_collapses;
      ++(v == verdict::boundary ? rep_.refused_boundary
                                : v == verdict::topology ? rep_.refused_topology : rep_.refused_geometry);
    }
  }

 private:
  // A refused edge is re-evaluated only after a commit touched one of its cells.
  bool refused_and_unchanged(index_t a, index_t b) const {
    const auto it = refused_at_.find({a, b});
    if (it == refused_at_.end()) return false;
    for (const index_t v : {a, b})
      for (const index_t f : st_.vertex_faces[static_cast<std::size_t>(v)])
        if (cell_stamp_[static_cast<std::size_t>(tess_.face_cell[static_cast<std::size_t>(f)])] > it->second)
          return false;
    return true;
  }

  // The cluster's merged data: side set, member sums and the box of the original vertices.
  struct cluster_data {
    std::uint8_t sides = 0;
    vec3 sum = vec3::Zero();
    index_t count = 0;
    aabb originals;
  };

  // Merges the vertices `members` (sorted, >= 2) into members[0] if every check passes.
  verdict try_merge(const std::vector<index_t>& members) {
    // Box sides: the union of the members' side sets must be one of them (see the file comment).
    cluster_data d;
    for (const index_t m : members) d.sides |= st_.sides[static_cast<std::size_t>(m)];
    bool realized = false;
    for (const index_t m : members) realized = realized || st_.sides[static_cast<std::size_t>(m)] == d.sides;
    if (!realized) return verdict::boundary;
    for (const index_t m : members) {
      d.originals.expand(st_.member_box[static_cast<std::size_t>(m)].lo);
      d.originals.expand(st_.member_box[static_cast<std::size_t>(m)].hi);
      d.sum += st_.member_sum[static_cast<std::size_t>(m)];
      d.count += st_.member_count[static_cast<std::size_t>(m)];
    }
    if (!tentative_loops(members)) return verdict::topology;
    vec3 merged;
    const verdict v = best_position(members, d, merged);
    if (v != verdict::ok) return v;
    commit(members, d, merged);
    return verdict::ok;
  }

  // Tentative loops of the faces touching a member (faces_, new_loops_) and the cells to check
  // (cells_); false if a loop pinches.
  bool tentative_loops(const std::vector<index_t>& members) {
    const index_t keep = members.front();
    const auto is_member = [&](index_t v) { return std::binary_search(members.begin(), members.end(), v); };
    faces_.clear();
    for (const index_t m : members)
      for (const index_t f : st_.vertex_faces[static_cast<std::size_t>(m)])
        if (!st_.loop[static_cast<std::size_t>(f)].empty()) faces_.push_back(f);
    std::sort(faces_.begin(), faces_.end());
    faces_.erase(std::unique(faces_.begin(), faces_.end()), faces_.end());
    new_loops_.resize(faces_.size());
    bool pinched = false;
    for (std::size_t i = 0; i < faces_.size(); ++i) {
      new_loops_[i] = st_.loop[static_cast<std::size_t>(faces_[i])];
      for (index_t& v : new_loops_[i])
        if (is_member(v)) v = keep;
      pinched = pinched || !collapse_loop(new_loops_[i]);
      if (new_loops_[i].size() < 3) new_loops_[i].clear();
    }
    if (pinched) return false;
    cells_.clear();
    for (const index_t f : faces_) cells_.push_back(tess_.face_cell[static_cast<std::size_t>(f)]);
    std::sort(cells_.begin(), cells_.end());
    cells_.erase(std::unique(cells_.begin(), cells_.end()), cells_.end());
    return true;
  }

  // Candidate positions of the merged vertex: the cluster mean, then each member's own
  // position (which keeps that member's faces planar); the one whose worst zone is best wins.
  // The quality rule: the worst zone may not get worse than before, unless it stays above the
  // floor.
  verdict best_position(const std::vector<index_t>& members, const cluster_data& d, vec3& merged) {
    const index_t keep = members.front();
    const auto on_sides = [&](vec3 x) {
      for (int s = 0; s < 6; ++s)
        if (d.sides & side_bit(s)) x[s / 2] = s % 2 ? tess_.domain.hi[s / 2] : tess_.domain.lo[s / 2];
      return x;
    };
    const auto loops_of = [&](index_t f) -> const std::vector<index_t>& {
      const auto it = std::lower_bound(faces_.begin(), faces_.end(), f);
      if (it != faces_.end() && *it == f) return new_loops_[static_cast<std::size_t>(it - faces_.begin())];
      return st_.loop[static_cast<std::size_t>(f)];
    };
    const vec3 old_position = st_.position[static_cast<std::size_t>(keep)];
    verdict best_verdict = verdict::geometry;
    real best_altitude = -1;
    merged = old_position;
    for (std::size_t candidate = 0; candidate <= members.size(); ++candidate) {
      const vec3 x = on_sides(candidate == 0 ? vec3(d.sum / static_cast<real>(d.count))
                                             : st_.position[static_cast<std::size_t>(members[candidate - 1])]);
      // no original vertex may move farther than l_min (bound: farthest corner of their box)
      if ((x - d.originals.lo).cwiseAbs().cwiseMax((x - d.originals.hi).cwiseAbs()).norm() > max_shift_) continue;
      st_.position[static_cast<std::size_t>(keep)] = x;
      real altitude = std::numeric_limits<real>::infinity();
      verdict v = verdict::ok;
      for (std::size_t i = 0; i < cells_.size() && v == verdict::ok; ++i) v = st_.check_cell(cells_[i], loops_of, altitude);
      if (v != verdict::ok) {
        if (best_altitude < 0 && v == verdict::topology) best_verdict = v;
        continue;
      }
      if (altitude > best_altitude) {
        best_altitude = altitude;
        merged = x;
        best_verdict = verdict::ok;
      }
    }
    st_.position[static_cast<std::size_t>(keep)] = old_position;
    if (best_verdict != verdict::ok) return best_verdict;
    if (best_altitude < altitude_floor_) {
      real altitude_before = std::numeric_limits<real>::infinity();
      const auto current_loop = [&](index_t f) -> const std::vector<index_t>& { return st_.loop[static_cast<std::size_t>(f)]; };
      for (const index_t c : cells_) static_cast<void>(st_.check_cell(c, current_loop, altitude_before));
      if (best_altitude < altitude_before) return verdict::geometry;
    }
    return verdict::ok;
  }

  // Applies the merge and re-queues the short edges of the cells around the merged vertex.
  void commit(const std::vector<index_t>& members, const cluster_data& d, const vec3& merged) {
    const index_t keep = members.front();
    st_.position[static_cast<std::size_t>(keep)] = merged;
    ++commits_;
    for (const index_t c : cells_) cell_stamp_[static_cast<std::size_t>(c)] = commits_;
    rep_.collapsed_edges += static_cast<index_t>(members.size()) - 1;
    for (const index_t m : members) {
      if (m == keep) continue;
      st_.parent[static_cast<std::size_t>(m)] = keep;
      st_.vertex_faces[static_cast<std::size_t>(m)].clear();
    }
    st_.member_sum[static_cast<std::size_t>(keep)] = d.sum;
    st_.member_count[static_cast<std::size_t>(keep)] = d.count;
    st_.member_box[static_cast<std::size_t>(keep)] = d.originals;
    st_.sides[static_cast<std::size_t>(keep)] = d.sides;
    for (std::size_t i = 0; i < faces_.size(); ++i) {
      st_.cache[static_cast<std::size_t>(faces_[i])].valid = false;
      if (new_loops_[i].empty()) ++rep_.dropped_faces;
      st_.loop[static_cast<std::size_t>(faces_[i])] = std::move(new_loops_[i]);
    }
    auto& kept_faces = st_.vertex_faces[static_cast<std::size_t>(keep)];
    kept_faces.clear();
    for (const index_t f : faces_)
      if (!st_.loop[static_cast<std::size_t>(f)].empty()) kept_faces.push_back(f);
    for (const index_t c : cells_)
      for (index_t f = tess_.first_face(c); f < tess_.end_face(c); ++f) {
        const auto& l = st_.loop[static_cast<std::size_t>(f)];
        for (std::size_t k = 0; k < l.size(); ++k) {
          const index_t p = std::min(l[k], l[(k + 1) % l.size()]), q = std::max(l[k], l[(k + 1) % l.size()]);
          const real lq = st_.length(p, q);
          if (lq < l_min_) queue_.emplace(lq, p, q);
        }
      }
  }

  const tessellation& tess_;
  collapse_state& st_;
  real l_min_;
  regularization_report& rep_;
  real altitude_floor_, max_shift_;
  edge_queue queue_;
  index_t commits_ = 0;
  std::vector<index_t> cell_stamp_;
  std::map<std::pair<index_t, index_t>, index_t> refused_at_;
  std::vector<index_t> faces_, cells_;
  std::vector<std::vector<index_t>> new_loops_;
};

}  // namespace detail::edge_collapse

/// Collapses the edges of `tess` shorter than min_edge_rel x (V_box / N_cells)^(1/3) in place,
/// following the rules and guarantees of the file comment; min_edge_rel = 0 does nothing.
/// Throws invalid_input for min_edge_rel outside [0, 0.5] (larger thresholds would collapse
/// whole cells).
TESSERA_INLINE regularization_report regularize(tessellation& tess, real min_edge_rel);

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/regularize.ipp"
#endif
