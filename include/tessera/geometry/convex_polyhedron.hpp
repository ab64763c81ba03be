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
// The clipping itself (one attempt: sides, kept faces, the new face) is in
// detail/polyhedron_clip.hpp; this header holds construction, queries and clip's retry policy
// (the construction's and clip's bodies in impl/convex_polyhedron.ipp).
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
#include "../core/separate_compilation.hpp"
#include "../core/types.hpp"
#include "mass_properties.hpp"
#include "predicates.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

/// A convex polyhedron (m): vertices and planar convex face loops, CCW seen from outside; from_vertices and box build one and refuse degenerate input (geometry_error naming it)
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
  [[nodiscard]] static convex_polyhedron box(const vec3& lo, const vec3& hi);

  /// Resets *this to the box [lo, hi], reusing the storage (no allocation once grown).
  void assign_box(const vec3& lo, const vec3& hi);

  /// Builds a polyhedron from vertices and outward CCW face loops (CSR), e.g. a block read from
  /// a file. Checks sizes and ids; convexity and closedness are the caller's promise (see
  /// euler_characteristic and tessellation check()).
  [[nodiscard]] static convex_polyhedron from_faces(std::vector<vec3> vertices, std::vector<index_t> face_offsets,
                                                    std::vector<index_t> face_vertices, std::vector<index_t> face_tags);

  /// The convex hull of `points` (m): a block from its vertices, in any order, interior points
  /// allowed (they are dropped, and so are points inside a hull edge or face). Coplanar hull
  /// triangles are merged into one planar convex face; loops are outward CCW as in box() and
  /// from_faces; vertices keep the input order of the extreme points; every face is tagged
  /// boundary_tag(0). Plane-side decisions use predicates.hpp with the clipping tolerance
  /// (plane_tolerance_rel x largest extent; see convex_hull.hpp). Throws invalid_input for fewer
  /// than 4 points, a non-finite point (its index and value), two coincident points (both
  /// indices), or all points on one line or plane. O(n^2).
  [[nodiscard]] static convex_polyhedron from_vertices(std::span<const vec3> points);

  /// Every vertex x mapped to map x + translation: a rigid move for a rotation `map`, a scaling
  /// about a point for a multiple of the identity. `map` must have a positive determinant (the
  /// face loops stay outward CCW; convexity is kept by any linear map).
  [[nodiscard]] convex_polyhedron transformed(const mat3& map, const vec3& translation) const;

  /// Resets *this to source.transformed(map, translation) (the same vertices to the bit),
  /// reusing the storage: no allocation once *this has held a polyhedron as large (a detecting
  /// contact set's current geometry at each rebuild). `source` may be *this. The same refusal.
  void assign_transformed(const convex_polyhedron& source, const mat3& map, const vec3& translation);

  // ---- topology and geometry access ------------------------------------------------------
  [[nodiscard]] bool empty() const { return face_tags_.empty(); }  ///< True when it has no face
  [[nodiscard]] index_t vertex_count() const { return static_cast<index_t>(vertices_.size()); }  ///< Number of vertices
  [[nodiscard]] index_t face_count() const { return static_cast<index_t>(face_tags_.size()); }  ///< Number of faces
  [[nodiscard]] const std::vector<vec3>& vertices() const { return vertices_; }  ///< Vertex positions (m)
  [[nodiscard]] const vec3& vertex(index_t v) const { return vertices_[static_cast<std::size_t>(v)]; }  ///< Position of vertex v (m)
  [[nodiscard]] const std::vector<index_t>& face_offsets() const { return face_offsets_; }  ///< CSR offsets of the face loops into face_vertices()
  [[nodiscard]] const std::vector<index_t>& face_vertices() const { return face_vertices_; }  ///< Vertex ids of the face loops, CCW seen from outside
  [[nodiscard]] const std::vector<index_t>& face_tags() const { return face_tags_; }  ///< Tag of each face (its source plane or neighbour)
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
  /// fallback mode, which settles features below the tolerance (see detail::try_clip); throws
  /// geometry_error when that fails too.
  bool clip(const plane& h, index_t tag, real tol = -1);

  /// Squared distance (m^2) from p to the farthest vertex.
  [[nodiscard]] real max_squared_distance(const vec3& p) const {
    real r2 = 0;
    for (const vec3& v : vertices_) r2 = std::max(r2, (v - p).squaredNorm());
    return r2;
  }

 private:
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

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/convex_polyhedron.ipp"
#endif
