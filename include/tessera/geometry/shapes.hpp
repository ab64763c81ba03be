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
[[nodiscard]] inline convex_polyhedron prism(std::span<const vec3> polygon, const vec3& extrusion) {
  const std::size_t m = polygon.size();
  require(m >= 3, "prism: ", m, " polygon vertices given; a polygon needs at least 3");
  aabb bb;
  for (std::size_t k = 0; k < m; ++k) {
    const vec3& p = polygon[k];
    require(p.allFinite(), "prism: polygon vertex ", k, " = (", p.x(), ", ", p.y(), ", ", p.z(), ") m is not finite");
    bb.expand(p);
  }
  require(extrusion.allFinite(), "prism: extrusion (", extrusion.x(), ", ", extrusion.y(), ", ", extrusion.z(),
          ") m is not finite");
  const real size = bb.size().maxCoeff();
  const real tol = shape_tolerance_rel * std::max(size, extrusion.norm());
  std::vector<index_t> order(m);
  for (std::size_t k = 0; k < m; ++k) order[k] = static_cast<index_t>(k);
  const vec3 area = polygon_area_vector(polygon, order);  // Newell: normal x area, m^2
  require(area.norm() > tol * size, "prism: the polygon of ", m, " vertices has area ", area.norm(),
          " m^2; its vertices must span a plane");
  const vec3 n = area.normalized();
  const vec3 centre = polygon_centroid(polygon, order);
  for (std::size_t k = 0; k < m; ++k) {
    const real d = n.dot(polygon[k] - centre);
    require(std::abs(d) <= tol, "prism: polygon vertex ", k, " lies ", d, " m off the polygon's plane (tolerance ", tol,
            " m); the polygon must be planar");
  }
  // Strictly convex: a left turn at every vertex (seen along n), then every other vertex strictly
  // left of every edge, which also refuses a polygon winding more than once.
  for (std::size_t i = 0; i < m; ++i) {
    const vec3& a = polygon[i];
    const vec3& b = polygon[(i + 1) % m];
    const real length = (b - a).norm();
    require(length > tol, "prism: polygon vertices ", i, " and ", (i + 1) % m, " coincide (edge length ", length, " m)");
  }
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t prev = (k + m - 1) % m, next = (k + 1) % m;
    const vec3 inward = n.cross(polygon[k] - polygon[prev]).normalized();
    const real turn = inward.dot(polygon[next] - polygon[k]);  // > 0: a left turn at vertex k (m)
    require(turn >= -tol, "prism: polygon vertex ", k, " is reflex (vertex ", next, " lies ", -turn,
            " m outside the line of edge ", prev, " -> ", k, "); the polygon must be strictly convex");
    require(turn > tol, "prism: polygon vertex ", k, " lies on the line of its neighbours ", prev, " and ", next,
            " (within ", std::abs(turn), " m); remove it");
  }
  for (std::size_t i = 0; i < m; ++i) {
    const vec3& a = polygon[i];
    const vec3& b = polygon[(i + 1) % m];
    const vec3 inward = n.cross(b - a).normalized();  // unit, in the plane, to the left of a -> b
    for (std::size_t k = 0; k < m; ++k) {
      if (k == i || k == (i + 1) % m) continue;
      const real d = inward.dot(polygon[k] - a);
      require(d > tol, "prism: polygon vertex ", k, (d < -tol ? " lies outside" : " lies on the line of"), " edge ", i,
              " -> ", (i + 1) % m, " (", d, " m inside it, tolerance ", tol, " m); the polygon must be strictly convex");
    }
  }
  const real height = n.dot(extrusion);
  require(std::abs(height) > tol, "prism: extrusion (", extrusion.x(), ", ", extrusion.y(), ", ", extrusion.z(),
          ") m has ", height, " m along the polygon's normal (", n.x(), ", ", n.y(), ", ", n.z(),
          "); it must leave the polygon's plane");
  // Walk the polygon so that its normal points along the extrusion: then the top keeps the
  // walk's order (outward = +extrusion), the base reverses it.
  std::vector<vec3> vertices(2 * m);
  for (std::size_t k = 0; k < m; ++k) {
    vertices[k] = polygon[height > 0 ? k : (m - k) % m];
    vertices[m + k] = vertices[k] + extrusion;
  }
  const index_t mm = static_cast<index_t>(m);
  std::vector<index_t> offsets{0}, loops;
  for (index_t i = 0; i < mm; ++i) {
    const index_t j = (i + 1) % mm;
    loops.insert(loops.end(), {i, j, mm + j, mm + i});
    offsets.push_back(static_cast<index_t>(loops.size()));
  }
  for (index_t i = mm - 1; i >= 0; --i) loops.push_back(i);
  offsets.push_back(static_cast<index_t>(loops.size()));
  for (index_t i = 0; i < mm; ++i) loops.push_back(mm + i);
  offsets.push_back(static_cast<index_t>(loops.size()));
  std::vector<index_t> tags(m + 2, boundary_tag(0));
  return convex_polyhedron::from_faces(std::move(vertices), std::move(offsets), std::move(loops), std::move(tags));
}

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
[[nodiscard]] inline convex_polyhedron cylinder_prism(const vec3& center, const vec3& axis, real radius, real length,
                                                      index_t sides, real phase = 0) {
  require(sides >= 3, "cylinder_prism: sides = ", sides, " must be >= 3");
  require_positive(radius, "cylinder_prism: radius (m)");
  require_positive(length, "cylinder_prism: length (m)");
  require(center.allFinite(), "cylinder_prism: center (", center.x(), ", ", center.y(), ", ", center.z(),
          ") m is not finite");
  require(axis.allFinite() && axis.norm() > 0, "cylinder_prism: axis (", axis.x(), ", ", axis.y(), ", ", axis.z(),
          ") must be finite and non-zero");
  require(std::isfinite(phase), "cylinder_prism: phase = ", phase, " rad must be finite");
  const vec3 a = axis.normalized();
  const vec3 e1 = detail::first_normal(a), e2 = a.cross(e1);
  const vec3 base = center - real(0.5) * length * a;
  std::vector<vec3> polygon(static_cast<std::size_t>(sides));
  for (index_t k = 0; k < sides; ++k) {
    const real angle = phase + 2 * std::numbers::pi_v<real> * static_cast<real>(k) / static_cast<real>(sides);
    polygon[static_cast<std::size_t>(k)] = base + radius * (std::cos(angle) * e1 + std::sin(angle) * e2);
  }
  return prism(polygon, length * a);
}

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
[[nodiscard]] inline convex_polyhedron voussoir(const vec3& center, real r_in, real r_out, real theta_0, real theta_1,
                                                real depth) {
  require(center.allFinite(), "voussoir: center (", center.x(), ", ", center.y(), ", ", center.z(), ") m is not finite");
  require_non_negative(r_in, "voussoir: inner radius r_in (m)");
  require_positive(r_out, "voussoir: outer radius r_out (m)");
  require(r_in < r_out, "voussoir: inner radius r_in = ", r_in, " m must be < outer radius r_out = ", r_out, " m");
  require(std::isfinite(theta_0) && std::isfinite(theta_1) && theta_1 > theta_0, "voussoir: angles theta_0 = ", theta_0,
          " rad and theta_1 = ", theta_1, " rad must be finite with theta_0 < theta_1");
  require(theta_1 - theta_0 < std::numbers::pi_v<real>, "voussoir: the block spans theta_1 - theta_0 = ",
          theta_1 - theta_0, " rad; it must be < pi (a convex block)");
  require_positive(depth, "voussoir: depth (m)");
  auto at = [&](real r, real theta) {
    return vec3(center.x() + r * std::cos(theta), center.y() - real(0.5) * depth, center.z() + r * std::sin(theta));
  };
  // this order turns counter-clockwise about +y, so prism() keeps it
  std::vector<vec3> polygon;
  polygon.push_back(at(r_in, theta_0));
  if (r_in > 0) polygon.push_back(at(r_in, theta_1));
  polygon.push_back(at(r_out, theta_1));
  polygon.push_back(at(r_out, theta_0));
  return prism(polygon, vec3(0, depth, 0));
}

/// The part of `block` inside every plane of `half_spaces` (each keeps {x : n . x <= offset},
/// n a unit outward normal, offset in m), cut with the tessellation's clipping kernel
/// (convex_polyhedron::clip); new faces are tagged boundary_tag(0). Throws invalid_input for a
/// plane with a non-finite or non-unit normal (|n| - 1 beyond 1e-9) or a non-finite offset, and
/// geometry_error when nothing is left (the plane that emptied it named).
[[nodiscard]] inline convex_polyhedron cut_by_planes(const convex_polyhedron& block, std::span<const plane> half_spaces) {
  require<geometry_error>(!block.empty(), "cut_by_planes: the block is empty");
  convex_polyhedron out = block;
  for (std::size_t k = 0; k < half_spaces.size(); ++k) {
    const plane& h = half_spaces[k];
    require(h.normal.allFinite() && std::abs(h.normal.norm() - 1) <= 1e-9 && std::isfinite(h.offset), "cut_by_planes: plane ",
            k, " has normal (", h.normal.x(), ", ", h.normal.y(), ", ", h.normal.z(), ") and offset ", h.offset,
            " m; the normal must be a finite unit vector and the offset finite");
    out.clip(h, boundary_tag(0));
    require<geometry_error>(!out.empty(), "cut_by_planes: nothing of the block is left inside plane ", k, " (normal (",
                            h.normal.x(), ", ", h.normal.y(), ", ", h.normal.z(), "), offset ", h.offset, " m)");
  }
  return out;
}

/// The wedge of `block` between two planes: the part inside both `first` and `second` (each
/// keeps {x : n . x <= offset}; for a wedge the two outward normals point away from each other
/// across the wedge). cut_by_planes with the two planes.
[[nodiscard]] inline convex_polyhedron wedge_between_planes(const convex_polyhedron& block, const plane& first,
                                                            const plane& second) {
  const plane both[2] = {first, second};
  return cut_by_planes(block, both);
}

}  // namespace tessera::geometry
