#pragma once
// Common block shapes as convex_polyhedron: a prism over a convex polygon, a many-sided prism
// approximating a cylinder, an arch voussoir, and a block cut by half-spaces (a wedge between
// two planes). With convex_polyhedron::box (an axis-aligned box) and
// convex_polyhedron::from_vertices (the convex hull of any points) they cover the blocks of
// hand-built scenes: an arch, a wall, a stack, a specimen.
//
// A block set: geometry::separate_blocks(std::span<const convex_polyhedron>) (tessellation_
// queries.hpp) turns a list of blocks into a tessellation whose cell b is blocks[b], each with its
// own vertices and every face a boundary face; the blocks then meet through detected contacts
// (contact::detected_contacts). To cut a domain into random blocks instead, use
// geometry::random_voronoi(domain, n, seed) (voronoi.hpp), which takes any convex polyhedron.
//
// Every shape here has outward CCW face loops, every face tagged boundary_tag(0) (as
// separate_blocks tags them), and is checked before it is built: degenerate input (a polygon
// vertex on its neighbours' line, a vertex off the polygon's plane, a zero extrusion) is refused
// with the offending vertex or value named. The tolerance of those checks is
// shape_tolerance_rel times the shape's size. Thread safety: pure functions. Cost: O(m^2) for an
// m-gon (the convexity check), otherwise O(m).

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "convex_polyhedron.hpp"
#include "mass_properties.hpp"
#include "predicates.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

/// Relative tolerance of the shape checks (times the shape's largest extent, m): a polygon vertex
/// closer than this to its neighbours' line, or farther than this from the polygon's plane, is
/// refused. 1e-9 is the tessellation's weld tolerance (cleanup.hpp): anything smaller would be
/// collapsed by the cleanup of a tessellation cut from the shape.
inline constexpr real shape_tolerance_rel = 1e-9;

/// Prism over the planar convex polygon `polygon` (m; vertices in order, either orientation,
/// no vertex repeated) extruded by `extrusion` (m): the vertices are the polygon's (ids 0..m-1,
/// in the given order when the polygon turns counter-clockwise about the extrusion, else in
/// reverse order starting at vertex 0) and the same moved by `extrusion` (ids m..2m-1). Faces:
/// 0..m-1 the sides (face i over edge i -> i+1 of the stored order), m the base (the polygon),
/// m+1 the top. The extrusion need not be
/// normal to the polygon (an oblique prism); volume = polygon area x |n . extrusion|.
/// Throws invalid_input for fewer than 3 vertices, a non-finite vertex or extrusion, a vertex off
/// the polygon's plane, a polygon that is not strictly convex (the vertex named, with the edge it
/// lies outside of or on), or an extrusion parallel to the polygon's plane.
[[nodiscard]] TESSERA_INLINE convex_polyhedron prism(std::span<const vec3> polygon, const vec3& extrusion);

namespace detail {
/// A unit vector normal to the unit vector `axis`: the x axis projected off `axis`, or the y axis
/// when `axis` is within 25 degrees of x (so the z axis gives e1 = x).
[[nodiscard]] inline vec3 first_normal(const vec3& axis) {
  const vec3 ref = std::abs(axis.x()) < 0.9 ? vec3::UnitX() : vec3::UnitY();
  return (ref - axis.dot(ref) * axis).normalized();
}
}  // namespace detail

/// A right prism of `sides` faces approximating a cylinder: the regular `sides`-gon inscribed in
/// the circle of `radius` (m) about `axis` (any non-zero direction, normalized here), extruded
/// over `length` (m) and centred on `center` (m, midway along the axis). Vertex k of the base
/// lies at angle phase + 2 pi k / sides (rad) from e1 toward e2 = axis x e1, where e1 is the x
/// axis projected off the axis (the y axis when the axis is within 25 degrees of x); a phase of
/// pi / sides puts a face, not an edge, across e1. Faces as prism(): the sides, then the base
/// (at center - axis length / 2), then the top. Volume = sides / 2 radius^2 sin(2 pi / sides)
/// length. Throws invalid_input for sides < 3, a non-positive or non-finite radius or length, a
/// zero or non-finite axis, a non-finite center or phase.
[[nodiscard]] TESSERA_INLINE convex_polyhedron cylinder_prism(const vec3& center, const vec3& axis, real radius, real length,
                                                              index_t sides, real phase = 0);

/// The voussoir of a circular arch ring: the block between the radii r_in and r_out (m) and the
/// two radial planes at angles theta_0 < theta_1 (rad), its inner and outer surfaces the chords
/// (flat faces), depth (m) out of the arch's plane. The arch lies in the x-z plane about `center`
/// (m): angle theta measured from +x toward +z (theta = pi/2 is the crown), the block spanning
/// center.y - depth/2 .. center.y + depth/2. Other planes: convex_polyhedron::transformed.
/// Vertices: inner at theta_0, inner at theta_1, outer at theta_1, outer at theta_0 (at
/// -depth/2), then the same at +depth/2; r_in = 0 gives a wedge (3 vertices a side, the first
/// at the centre). Faces as prism(): face 0 the inner chord, 1 the joint at theta_1, 2 the outer
/// chord, 3 the joint at theta_0, then the two planes of the arch. Volume = (r_out^2 - r_in^2) / 2 sin(theta_1 - theta_0) depth. Throws
/// invalid_input for r_in < 0, r_in >= r_out, theta_1 <= theta_0, theta_1 - theta_0 >= pi,
/// depth <= 0 or a non-finite value.
[[nodiscard]] TESSERA_INLINE convex_polyhedron voussoir(const vec3& center, real r_in, real r_out, real theta_0, real theta_1,
                                                        real depth);

/// The part of `block` inside every plane of `half_spaces` (each keeps {x : n . x <= offset},
/// n a unit outward normal, offset in m), cut with the tessellation's clipping kernel
/// (convex_polyhedron::clip); new faces are tagged boundary_tag(0). Throws invalid_input for a
/// plane with a non-finite or non-unit normal (|n| - 1 beyond 1e-9) or a non-finite offset, and
/// geometry_error when nothing is left (the plane that emptied it named).
[[nodiscard]] TESSERA_INLINE convex_polyhedron cut_by_planes(const convex_polyhedron& block, std::span<const plane> half_spaces);

/// The wedge of `block` between two planes: the part inside both `first` and `second` (each
/// keeps {x : n . x <= offset}; for a wedge the two outward normals point away from each other
/// across the wedge). cut_by_planes with the two planes.
[[nodiscard]] inline convex_polyhedron wedge_between_planes(const convex_polyhedron& block, const plane& first,
                                                            const plane& second) {
  const plane both[2] = {first, second};
  return cut_by_planes(block, both);
}

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/shapes.ipp"
#endif
