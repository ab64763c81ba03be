#pragma once
// A convex polyhedron in boundary representation, with plane clipping: the kernel of the
// Voronoi/Laguerre tessellation and the shape of a rigid block.
//
// Representation:
//   vertices   positions (m), no two equal
//   faces      CSR loops of vertex ids, counter-clockwise seen from outside (outward normal by
//              the right-hand rule), each face a convex polygon with >= 3 vertices
//   face tags  one `index_t` per face: the id of the neighbouring cell whose bisector created the
//              face (>= 0), or boundary_tag(side) (< 0) for a side of the initial box
//
// clip(h, tag) keeps the part {x : h.normal . x <= h.offset}. Vertex sides are decided once,
// by the three-valued predicate of predicates.hpp with tolerance plane_tolerance_rel times the
// polyhedron's largest extent: vertices within the tolerance of the plane are kept where they
// are (they become vertices of the new face), so a cut through a vertex or an edge creates no
// duplicate vertex, and a cut that would remove less than the tolerance removes nothing. The
// new face is assembled from the open boundary of the kept faces, which makes the topology
// closed (Euler characteristic 2) by construction.
//
// Cost: clip is O(V + sum of loop lengths) and allocation-free once the per-thread scratch
// buffers have grown. Thread safety: distinct objects may be used from distinct threads;
// const member functions may be called concurrently.

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "convex_hull.hpp"
#include "mass_properties.hpp"
#include "predicates.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

class convex_polyhedron {
 public:
  /// Upper bound of the "on" band of clip's retries, relative to extent(): a vertex kept as on
  /// the plane may lie this far outside it. 1e-6 is the bound callers are written against
  /// (fuzz_clip checks every vertex within it of every cut made so far; in 20 000 fuzz_clip runs
  /// 4 cuts needed retries and all were settled at 1e-6), and a wider band would keep vertices
  /// visibly outside their cut (the earlier loop went on to 1e-4 and 1e-2).
  static constexpr real max_widened_tolerance_rel = 1e-6;

  convex_polyhedron() = default;

  /// The box [lo, hi] (m) with faces tagged boundary_tag(0..5) = x-, x+, y-, y+, z-, z+.
  [[nodiscard]] static convex_polyhedron box(const vec3& lo, const vec3& hi) {
    require((hi.array() > lo.array()).all() && lo.allFinite() && hi.allFinite(),
            "convex_polyhedron::box: lo = (", lo.x(), ", ", lo.y(), ", ", lo.z(), "), hi = (", hi.x(), ", ",
            hi.y(), ", ", hi.z(), ") must be finite with hi > lo in every direction");
    convex_polyhedron p;
    p.assign_box(lo, hi);
    return p;
  }

  /// Resets *this to the box [lo, hi], reusing the storage (no allocation once grown).
  void assign_box(const vec3& lo, const vec3& hi) {
    vertices_.clear();
    // vertex k has x = hi if bit 0, y = hi if bit 1, z = hi if bit 2
    for (int k = 0; k < 8; ++k)
      vertices_.emplace_back((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
    static constexpr std::array<std::array<index_t, 4>, 6> loops{{
        {0, 4, 6, 2},  // x-  (normal -x)
        {1, 3, 7, 5},  // x+
        {0, 1, 5, 4},  // y-
        {2, 6, 7, 3},  // y+
        {0, 2, 3, 1},  // z-
        {4, 5, 7, 6},  // z+
    }};
    face_offsets_.assign(1, 0);
    face_vertices_.clear();
    face_tags_.clear();
    for (int s = 0; s < 6; ++s) {
      face_vertices_.insert(face_vertices_.end(), loops[static_cast<std::size_t>(s)].begin(),
                            loops[static_cast<std::size_t>(s)].end());
      face_offsets_.push_back(static_cast<index_t>(face_vertices_.size()));
      face_tags_.push_back(boundary_tag(s));
    }
  }

  /// Builds a polyhedron from vertices and outward CCW face loops (CSR), e.g. a block read from
  /// a file. Checks sizes and ids; convexity and closedness are the caller's promise (see
  /// euler_characteristic and tessellation check()).
  [[nodiscard]] static convex_polyhedron from_faces(std::vector<vec3> vertices, std::vector<index_t> face_offsets,
                                                    std::vector<index_t> face_vertices, std::vector<index_t> face_tags) {
    require<geometry_error>(face_offsets.size() >= 2 && face_offsets.front() == 0 &&
                                face_offsets.back() == static_cast<index_t>(face_vertices.size()),
                            "convex_polyhedron::from_faces: face_offsets must start at 0 and end at the loop length ",
                            face_vertices.size());
    require<geometry_error>(face_tags.size() + 1 == face_offsets.size(), "convex_polyhedron::from_faces: ",
                            face_tags.size(), " face tags for ", face_offsets.size() - 1, " faces");
    for (index_t v : face_vertices)
      require<geometry_error>(v >= 0 && v < static_cast<index_t>(vertices.size()),
                              "convex_polyhedron::from_faces: vertex id ", v, " out of range [0, ", vertices.size(), ")");
    convex_polyhedron p;
    p.vertices_ = std::move(vertices);
    p.face_offsets_ = std::move(face_offsets);
    p.face_vertices_ = std::move(face_vertices);
    p.face_tags_ = std::move(face_tags);
    return p;
  }

  /// The convex hull of `points` (m): a block from its vertices, in any order, interior points
  /// allowed (they are dropped, and so are points inside a hull edge or face). Coplanar hull
  /// triangles are merged into one planar convex face; loops are outward CCW as in box() and
  /// from_faces; vertices keep the input order of the extreme points; every face is tagged
  /// boundary_tag(0). Plane-side decisions use predicates.hpp with the clipping tolerance
  /// (plane_tolerance_rel x largest extent; see convex_hull.hpp). Throws invalid_input for fewer
  /// than 4 points, a non-finite point (its index and value), two coincident points (both
  /// indices), or all points on one line or plane. O(n^2).
  [[nodiscard]] static convex_polyhedron from_vertices(std::span<const vec3> points) {
    detail::hull_loops h = detail::compute_hull_loops(points, "convex_polyhedron::from_vertices");
    std::vector<index_t> tags(h.face_offsets.size() - 1, boundary_tag(0));
    return from_faces(std::move(h.vertices), std::move(h.face_offsets), std::move(h.face_vertices), std::move(tags));
  }

  /// Every vertex x mapped to map x + translation: a rigid move for a rotation `map`, a scaling
  /// about a point for a multiple of the identity. `map` must have a positive determinant (the
  /// face loops stay outward CCW; convexity is kept by any linear map).
  [[nodiscard]] convex_polyhedron transformed(const mat3& map, const vec3& translation) const {
    require(map.allFinite() && map.determinant() > 0 && translation.allFinite(),
            "convex_polyhedron::transformed: the map must be finite with a positive determinant (it is ",
            map.determinant(), ")");
    convex_polyhedron p = *this;
    for (vec3& x : p.vertices_) x = map * x + translation;
    return p;
  }

  // ---- topology and geometry access ------------------------------------------------------
  [[nodiscard]] bool empty() const { return face_tags_.empty(); }
  [[nodiscard]] index_t vertex_count() const { return static_cast<index_t>(vertices_.size()); }
  [[nodiscard]] index_t face_count() const { return static_cast<index_t>(face_tags_.size()); }
  [[nodiscard]] const std::vector<vec3>& vertices() const { return vertices_; }
  [[nodiscard]] const vec3& vertex(index_t v) const { return vertices_[static_cast<std::size_t>(v)]; }
  [[nodiscard]] const std::vector<index_t>& face_offsets() const { return face_offsets_; }
  [[nodiscard]] const std::vector<index_t>& face_vertices() const { return face_vertices_; }
  [[nodiscard]] const std::vector<index_t>& face_tags() const { return face_tags_; }
  /// Vertex ids of face f, CCW seen from outside.
  [[nodiscard]] std::span<const index_t> face(index_t f) const {
    return {face_vertices_.data() + face_offsets_[static_cast<std::size_t>(f)],
            static_cast<std::size_t>(face_offsets_[static_cast<std::size_t>(f) + 1] -
                                     face_offsets_[static_cast<std::size_t>(f)])};
  }
  /// Neighbour cell id (>= 0) or boundary_tag(side) (< 0) of face f.
  [[nodiscard]] index_t face_tag(index_t f) const { return face_tags_[static_cast<std::size_t>(f)]; }

  /// Area (m^2) of face f.
  [[nodiscard]] real face_area(index_t f) const { return polygon_area_vector(vertices_, face(f)).norm(); }
  /// Unit outward normal of face f (from its area vector).
  [[nodiscard]] vec3 face_normal(index_t f) const { return polygon_area_vector(vertices_, face(f)).normalized(); }
  /// Area-weighted centroid (m) of face f.
  [[nodiscard]] vec3 face_centroid(index_t f) const { return polygon_centroid(vertices_, face(f)); }
  /// Supporting plane of face f: outward unit normal, offset = n . (face centroid).
  [[nodiscard]] plane face_plane(index_t f) const { return plane::through(face_normal(f), face_centroid(f)); }

  /// Volume (m^3).
  [[nodiscard]] real volume() const { return polyhedron_volume(vertices_, face_offsets_, face_vertices_); }
  /// Centroid (m).
  [[nodiscard]] vec3 centroid() const { return mass().centroid; }
  /// Volume, centroid and second moment about the centroid (unit density).
  [[nodiscard]] mass_properties mass() const {
    return polyhedron_mass_properties(vertices_, face_offsets_, face_vertices_);
  }
  /// Inertia tensor about the centroid (kg m^2) for a density in kg/m^3; exact for polyhedra.
  [[nodiscard]] mat3 inertia(real density) const { return inertia_tensor(mass().second_moment, density); }

  /// Axis-aligned bounding box (m).
  [[nodiscard]] aabb bounds() const {
    aabb b;
    for (const vec3& v : vertices_) b.expand(v);
    return b;
  }
  /// Largest bounding-box extent (m): the length scale of the plane-side tolerance.
  [[nodiscard]] real extent() const { return empty() ? real(0) : bounds().size().maxCoeff(); }

  /// True when p is inside or within tol (m) of every face plane.
  [[nodiscard]] bool contains(const vec3& p, real tol = 0) const {
    if (empty()) return false;
    for (index_t f = 0; f < face_count(); ++f)
      if (face_plane(f).signed_distance(p) > tol) return false;
    return true;
  }

  /// V - E + F with E = (sum of loop lengths) / 2; 2 for a closed polyhedron of genus 0.
  [[nodiscard]] index_t euler_characteristic() const {
    return vertex_count() - static_cast<index_t>(face_vertices_.size()) / 2 + face_count();
  }

  /// Keeps the part {x : h.normal . x <= h.offset}; the new face gets `tag`. Returns whether
  /// anything was cut off. Vertices within `tol` (m) of the plane count as on it; tol < 0 selects
  /// plane_tolerance_rel * extent(). Either is raised to plane_rounding_tolerance of the largest
  /// coordinate, so a small polyhedron far from the origin is not cut by rounding noise. When every vertex is outside or on the plane, the result is
  /// empty. When rounding makes the sides inconsistent (a face loop that leaves and re-enters
  /// the plane), the "on" band is widened 100x per attempt up to max_widened_tolerance_rel
  /// (1e-6) of extent(). When no band gives a consistent cut, the attempts are repeated in
  /// fallback mode, which settles features below the tolerance (see try_clip); throws
  /// geometry_error when that fails too.
  bool clip(const plane& h, index_t tag, real tol = -1) {
    if (empty()) return false;
    if (tol < 0) tol = plane_tolerance_rel * extent();
    real coordinate_max = std::abs(h.offset);
    for (const vec3& v : vertices_) coordinate_max = std::max(coordinate_max, v.cwiseAbs().maxCoeff());
    tol = std::max(tol, plane_rounding_tolerance(coordinate_max));
    const real narrowest = tol, widest = std::max(tol, max_widened_tolerance_rel * extent());
    for (const bool fallback : {false, true}) {
      for (tol = narrowest;; tol = std::min(100 * tol, widest)) {  // rounding broke the bitonic side pattern of a face: widen the "on" band
        const clip_result r = try_clip(h, tag, tol, fallback);
        if (r != clip_result::inconsistent) return r == clip_result::cut;
        if (tol >= widest) break;
      }
    }
    throw geometry_error(tessera::detail::concat("convex_polyhedron::clip: no consistent cut by plane n = (", h.normal.x(),
                                        ", ", h.normal.y(), ", ", h.normal.z(), "), offset = ", h.offset,
                                        " m (tag ", tag, ") on a polyhedron of ", vertex_count(),
                                        " vertices, even with the plane tolerance widened to ", tol, " m"));
  }

  /// Squared distance (m^2) from p to the farthest vertex.
  [[nodiscard]] real max_squared_distance(const vec3& p) const {
    real r2 = 0;
    for (const vec3& v : vertices_) r2 = std::max(r2, (v - p).squaredNorm());
    return r2;
  }

 private:
  enum class clip_result { unchanged, cut, inconsistent };

  struct scratch {
    std::vector<real> distance;
    std::vector<side> vertex_side;
    std::vector<index_t> remap;             // old vertex -> new vertex id (or invalid)
    std::vector<std::array<index_t, 3>> edge_points;  // (kept vertex, removed vertex, new vertex)
    std::vector<vec3> vertices;
    std::vector<index_t> face_offsets, face_vertices, face_tags;
    std::vector<char> on_plane;           // per new vertex
    std::vector<std::array<index_t, 2>> plane_edges;  // directed edges of kept faces lying on the plane
    std::vector<index_t> cap_next;          // per new vertex: successor on the new face, or invalid
    std::vector<index_t> used;
    std::vector<index_t> alias;             // per new vertex: the vertex it is merged into (itself if none)
  };
  static scratch& workspace() {
    thread_local scratch s;
    return s;
  }

  // One attempt of clip with "on" band tol. The fallback mode, used only after every band
  // failed without it (so cuts that succeeded before are unchanged bit for bit), differs twice:
  // (1) A vertex "on" the plane none of whose neighbours (along face edges) is outside counts as inside:
  // it stays where it is, as every "on" vertex does, but the faces through it are kept instead
  // of being replaced by the new face. In exact arithmetic such a vertex cannot exist while
  // anything is outside (the polyhedron lies in the cone of the edges at the vertex, and all of
  // them point inside or along the plane), so it marks a feature below the plane tolerance
  // lying on the plane. fuzz_clip: a plane through an edge of a 0.023 m polyhedron and, within
  // 1e-14 m, through a triangle face with 3.5e-11 m edges that touches the cross-section at one
  // vertex; removing that face as "on" pinches the outline of the new face there (two
  // successors), while keeping it leaves the new face the cross-section triangle and the tiny
  // face where it was. No vertex moves and no face changes its plane.
  // (2) A new face whose vertices merge into fewer than 3 (merge_coincident_cap_vertices) is
  // dropped instead of failing: the part cut off ends in an edge or a point that the
  // coordinates cannot resolve. fuzz_clip: a 133 m needle whose tip is three vertices 5e-13 m
  // apart, shaved 9.4e-4 m: the three intersection points near the tip round to two positions.
  // The surface stays closed: the faces around a dropped face of two vertices a, b use the
  // edge as a->b and b->a.
  clip_result try_clip(const plane& h, index_t tag, real tol, bool fallback) {
    scratch& s = workspace();
    classify_vertices(s, h, tol, fallback);
    const std::size_t nv = vertices_.size();
    bool any_outside = false, any_inside = false;
    for (std::size_t v = 0; v < nv; ++v) {
      any_outside |= s.vertex_side[v] == side::outside;
      any_inside |= s.vertex_side[v] == side::inside;
    }
    if (!any_outside) return clip_result::unchanged;
    if (!any_inside) {  // everything outside or on the plane: nothing of positive volume is left
      vertices_.clear();
      face_offsets_.assign(1, 0);
      face_vertices_.clear();
      face_tags_.clear();
      return clip_result::cut;
    }

    clip_kept_faces(s);
    if (!close_cap(s, tag)) return clip_result::inconsistent;
    if (!merge_coincident_cap_vertices(s, fallback)) return clip_result::inconsistent;
    drop_unused_vertices(s);
    return clip_result::cut;
  }

  // Signed distances and sides of the vertices; in fallback mode an "on" vertex without an
  // outside neighbour counts as inside (rule (1) above).
  void classify_vertices(scratch& s, const plane& h, real tol, bool fallback) const {
    const std::size_t nv = vertices_.size();
    s.distance.resize(nv);
    s.vertex_side.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) {
      s.distance[v] = h.signed_distance(vertices_[v]);
      s.vertex_side[v] = classify_distance(s.distance[v], tol);
    }
    if (fallback) {
      s.used.assign(nv, 0);  // 1: an "on" vertex with an outside neighbour
      for (index_t f = 0; f < face_count(); ++f) {
        const auto loop = face(f);
        for (std::size_t k = 0; k < loop.size(); ++k) {
          const auto a = static_cast<std::size_t>(loop[k]), b = static_cast<std::size_t>(loop[(k + 1) % loop.size()]);
          if (s.vertex_side[a] == side::outside && s.vertex_side[b] == side::on) s.used[b] = 1;
          if (s.vertex_side[b] == side::outside && s.vertex_side[a] == side::on) s.used[a] = 1;
        }
      }
      for (std::size_t v = 0; v < nv; ++v)
        if (s.vertex_side[v] == side::on && !s.used[v]) s.vertex_side[v] = side::inside;
    }
  }

  // The kept part of every face with an inside vertex (its outside run replaced by the two
  // edge intersection points), the kept vertices and the on-plane edges the cap will close.
  void clip_kept_faces(scratch& s) const {
    const std::size_t nv = vertices_.size();
    // Kept vertices keep their relative order; intersection points are appended.
    s.remap.assign(nv, invalid_index);
    s.vertices.clear();
    s.on_plane.clear();
    for (std::size_t v = 0; v < nv; ++v)
      if (s.vertex_side[v] != side::outside) {
        s.remap[v] = static_cast<index_t>(s.vertices.size());
        s.vertices.push_back(vertices_[v]);
        s.on_plane.push_back(s.vertex_side[v] == side::on);
      }
    s.edge_points.clear();
    // Intersection of edge (a kept strictly inside, b outside) with the plane, shared by the two
    // faces of the edge: p = x_a + t (x_b - x_a), t = d_a / (d_a - d_b) in (0, 1).
    auto edge_point = [&](index_t a, index_t b) {
      for (const auto& e : s.edge_points)
        if (e[0] == a && e[1] == b) return e[2];
      const real da = s.distance[static_cast<std::size_t>(a)], db = s.distance[static_cast<std::size_t>(b)];
      const real t = da / (da - db);
      const vec3& xa = vertices_[static_cast<std::size_t>(a)];
      const vec3& xb = vertices_[static_cast<std::size_t>(b)];
      const index_t id = static_cast<index_t>(s.vertices.size());
      s.vertices.push_back(xa + t * (xb - xa));
      s.on_plane.push_back(1);
      s.edge_points.push_back({a, b, id});
      return id;
    };

    s.face_offsets.assign(1, 0);
    s.face_vertices.clear();
    s.face_tags.clear();
    s.plane_edges.clear();
    for (std::size_t f = 0; f + 1 < face_offsets_.size(); ++f) {
      const index_t begin = face_offsets_[f], end = face_offsets_[f + 1];
      const index_t n = end - begin;
      bool has_inside = false;
      for (index_t k = begin; k < end; ++k)
        has_inside |= s.vertex_side[static_cast<std::size_t>(face_vertices_[static_cast<std::size_t>(k)])] == side::inside;
      if (!has_inside) continue;  // face outside or on the plane: replaced by the new face
      const std::size_t start = s.face_vertices.size();
      for (index_t k = 0; k < n; ++k) {
        const index_t a = face_vertices_[static_cast<std::size_t>(begin + k)];
        const index_t b = face_vertices_[static_cast<std::size_t>(begin + (k + 1) % n)];
        const side sa = s.vertex_side[static_cast<std::size_t>(a)];
        const side sb = s.vertex_side[static_cast<std::size_t>(b)];
        if (sa != side::outside) s.face_vertices.push_back(s.remap[static_cast<std::size_t>(a)]);
        if (sa == side::inside && sb == side::outside) s.face_vertices.push_back(edge_point(a, b));
        else if (sa == side::outside && sb == side::inside) s.face_vertices.push_back(edge_point(b, a));
      }
      const std::size_t m = s.face_vertices.size() - start;
      if (m < 3) {  // cannot happen with a face that has an inside vertex, kept as a guard
        s.face_vertices.resize(start);
        continue;
      }
      for (std::size_t k = 0; k < m; ++k) {
        const index_t a = s.face_vertices[start + k], b = s.face_vertices[start + (k + 1) % m];
        if (s.on_plane[static_cast<std::size_t>(a)] && s.on_plane[static_cast<std::size_t>(b)])
          s.plane_edges.push_back({a, b});
      }
      s.face_offsets.push_back(static_cast<index_t>(s.face_vertices.size()));
      s.face_tags.push_back(face_tags_[f]);
    }
  }

  // Appends the new face; false if the on-plane edges do not form one simple loop.
  static bool close_cap(scratch& s, index_t tag) {
    // The new face closes the hole: it runs along every on-plane edge that only one kept face
    // uses, in the opposite direction (a closed oriented surface uses each edge once each way).
    const std::size_t nnew = s.vertices.size();
    s.cap_next.assign(nnew, invalid_index);
    std::size_t cap_edges = 0;
    index_t cap_start = invalid_index;
    for (const auto& e : s.plane_edges) {
      bool paired = false;
      for (const auto& g : s.plane_edges)
        if (g[0] == e[1] && g[1] == e[0]) { paired = true; break; }
      if (paired) continue;
      if (s.cap_next[static_cast<std::size_t>(e[1])] != invalid_index) return false;
      s.cap_next[static_cast<std::size_t>(e[1])] = e[0];
      ++cap_edges;
      if (cap_start == invalid_index || e[1] < cap_start) cap_start = e[1];
    }
    if (cap_edges < 3) return false;
    {
      index_t v = cap_start;
      std::size_t walked = 0;
      do {
        s.face_vertices.push_back(v);
        v = s.cap_next[static_cast<std::size_t>(v)];
        ++walked;
      } while (v != invalid_index && v != cap_start && walked <= cap_edges);
      if (v != cap_start || walked != cap_edges) return false;
      s.face_offsets.push_back(static_cast<index_t>(s.face_vertices.size()));
      s.face_tags.push_back(tag);
    }
    return true;
  }

  // Drops vertices no face uses any more (an on-plane vertex whose faces were all removed)
  // and installs the clipped polyhedron.
  void drop_unused_vertices(scratch& s) {
    const std::size_t nnew = s.vertices.size();
    s.used.assign(nnew, invalid_index);
    for (index_t v : s.face_vertices) s.used[static_cast<std::size_t>(v)] = 0;
    index_t next = 0;
    vertices_.clear();
    for (std::size_t v = 0; v < nnew; ++v)
      if (s.used[v] == 0) {
        s.used[v] = next++;
        vertices_.push_back(s.vertices[v]);
      }
    for (index_t& v : s.face_vertices) v = s.used[static_cast<std::size_t>(v)];
    face_offsets_.swap(s.face_offsets);
    face_vertices_.swap(s.face_vertices);
    face_tags_.swap(s.face_tags);
  }

  // Two nearly parallel edges (the long sides of a sliver face) cut close to where they meet
  // give intersection points closer than the coordinates resolve: they round to the same
  // position (fuzz_clip: a 1000 m sliver 5e-6 m wide cut 2e-6 m from its tip, points 1e-14 m
  // apart, below the 1e-13 m spacing of doubles near 1000). Consecutive vertices of the new face
  // (the last face) at exactly the same position are merged into one; repeats this leaves in a
  // loop are removed and a face left with fewer than 3 vertices (of zero area) is dropped. Only
  // exact coincidences are merged, so no vertex moves and any other cut is unchanged bit for bit.
  // Returns false when the new face itself degenerates (the caller then widens the tolerance),
  // unless may_drop_new_face (try_clip's fallback), or when fewer than 4 faces are left.
  static bool merge_coincident_cap_vertices(scratch& s, bool may_drop_new_face) {
    const std::size_t faces = s.face_tags.size();
    const index_t cap_begin = s.face_offsets[faces - 1], cap_end = s.face_offsets[faces];
    const index_t m = cap_end - cap_begin;
    bool any = false;
    for (index_t k = 0; k < m && !any; ++k)
      any = s.vertices[static_cast<std::size_t>(s.face_vertices[static_cast<std::size_t>(cap_begin + k)])] ==
            s.vertices[static_cast<std::size_t>(s.face_vertices[static_cast<std::size_t>(cap_begin + (k + 1) % m)])];
    if (!any) return true;
    s.alias.resize(s.vertices.size());
    for (std::size_t v = 0; v < s.alias.size(); ++v) s.alias[v] = static_cast<index_t>(v);
    auto root = [&](index_t v) {
      while (s.alias[static_cast<std::size_t>(v)] != v) v = s.alias[static_cast<std::size_t>(v)];
      return v;
    };
    for (index_t k = 0; k < m; ++k) {
      const index_t a = root(s.face_vertices[static_cast<std::size_t>(cap_begin + k)]);
      const index_t b = root(s.face_vertices[static_cast<std::size_t>(cap_begin + (k + 1) % m)]);
      if (a != b && s.vertices[static_cast<std::size_t>(a)] == s.vertices[static_cast<std::size_t>(b)])
        s.alias[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
    // Rewrite every loop in place (the write position never passes the read position).
    std::size_t write = 0, kept_faces = 0;
    index_t begin = 0;
    bool cap_kept = false;
    for (std::size_t f = 0; f < faces; ++f) {
      const index_t end = s.face_offsets[f + 1];
      const std::size_t start = write;
      for (index_t k = begin; k < end; ++k) {
        const index_t v = root(s.face_vertices[static_cast<std::size_t>(k)]);
        if (write > start && s.face_vertices[write - 1] == v) continue;
        s.face_vertices[write++] = v;
      }
      while (write - start > 1 && s.face_vertices[write - 1] == s.face_vertices[start]) --write;
      begin = end;
      if (write - start < 3) {  // a zero-area face between the merged vertices
        write = start;
        continue;
      }
      s.face_offsets[kept_faces + 1] = static_cast<index_t>(write);
      s.face_tags[kept_faces++] = s.face_tags[f];
      cap_kept = f + 1 == faces;
    }
    s.face_vertices.resize(write);
    s.face_offsets.resize(kept_faces + 1);
    s.face_tags.resize(kept_faces);
    return (cap_kept || may_drop_new_face) && kept_faces >= 4;
  }

  std::vector<vec3> vertices_;
  std::vector<index_t> face_offsets_{0};
  std::vector<index_t> face_vertices_;
  std::vector<index_t> face_tags_;
};

/// The convex hull of `points` (m) as a convex_polyhedron: convex_polyhedron::from_vertices.
[[nodiscard]] inline convex_polyhedron convex_hull(std::span<const vec3> points) {
  return convex_polyhedron::from_vertices(points);
}

}  // namespace tessera::geometry
