// The definitions of the larger functions that geometry/shapes.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../shapes.hpp"

namespace tessera::geometry {

[[nodiscard]] TESSERA_INLINE convex_polyhedron prism(std::span<const vec3> polygon, const vec3& extrusion) {
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

[[nodiscard]] TESSERA_INLINE convex_polyhedron cylinder_prism(const vec3& center, const vec3& axis, real radius, real length,
                                                              index_t sides, real phase) {
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

[[nodiscard]] TESSERA_INLINE convex_polyhedron voussoir(const vec3& center, real r_in, real r_out, real theta_0, real theta_1,
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

[[nodiscard]] TESSERA_INLINE convex_polyhedron cut_by_planes(const convex_polyhedron& block, std::span<const plane> half_spaces) {
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

}  // namespace tessera::geometry
