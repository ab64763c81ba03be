#pragma once
// Hand-made tessellations for the tests: boxes stacked along z, built directly as the
// geometry::tessellation arrays (no Voronoi), so a test can know every vertex, face and twin.
//
// Vertex numbering: vertex (l, k) = 4 l + k with k = x bit + 2 y bit, l the layer along z.
// Faces of each cell, in this order, CCW seen from outside: x-, x+, y-, y+, z-, z+ (so cell c's
// z- face is 6 c + 4 and its z+ face 6 c + 5). Neighbouring cells share their z faces.

#include <initializer_list>

#include "tessera/geometry/tessellation.hpp"

namespace tessera::test {

/// n boxes of edge lengths `cell` stacked along z from `lo`: cell c occupies
/// [lo, lo + cell] shifted by c cell.z() along z and shares its top face with cell c + 1.
[[nodiscard]] inline geometry::tessellation box_column(const vec3& lo, const vec3& cell, int n) {
  geometry::tessellation t;
  t.domain.expand(lo);
  t.domain.expand(lo + vec3(cell.x(), cell.y(), n * cell.z()));
  for (int l = 0; l <= n; ++l)
    for (int k = 0; k < 4; ++k)
      t.vertices.push_back(lo + vec3(cell.x() * (k & 1), cell.y() * ((k >> 1) & 1), cell.z() * l));
  const auto add_face = [&](std::initializer_list<int> loop, index_t owner, index_t neighbor) {
    for (int v : loop) t.face_vertices.push_back(v);
    t.face_offsets.push_back(static_cast<index_t>(t.face_vertices.size()));
    t.face_cell.push_back(owner);
    t.face_neighbor.push_back(neighbor);
    t.face_twin.push_back(invalid_index);
  };
  for (int c = 0; c < n; ++c) {
    const int b = 4 * c, u = 4 * (c + 1);  // bottom and top layer of cell c
    add_face({b + 0, u + 0, u + 2, b + 2}, c, geometry::boundary_tag(0));
    add_face({b + 1, b + 3, u + 3, u + 1}, c, geometry::boundary_tag(1));
    add_face({b + 0, b + 1, u + 1, u + 0}, c, geometry::boundary_tag(2));
    add_face({b + 2, u + 2, u + 3, b + 3}, c, geometry::boundary_tag(3));
    add_face({b + 0, b + 2, b + 3, b + 1}, c, c == 0 ? geometry::boundary_tag(4) : c - 1);
    add_face({u + 0, u + 1, u + 3, u + 2}, c, c == n - 1 ? geometry::boundary_tag(5) : c + 1);
    t.cell_face_offsets.push_back(static_cast<index_t>(t.face_cell.size()));
  }
  for (int c = 0; c + 1 < n; ++c) {
    const index_t top = 6 * c + 5, bottom = 6 * (c + 1) + 4;
    t.face_twin[static_cast<std::size_t>(top)] = bottom;
    t.face_twin[static_cast<std::size_t>(bottom)] = top;
    t.shared_faces.push_back({c, top, c + 1, bottom});
  }
  return t;
}

/// One box [lo, hi] as a single-cell tessellation.
[[nodiscard]] inline geometry::tessellation box_tessellation(const vec3& lo, const vec3& hi) {
  return box_column(lo, hi - lo, 1);
}

}  // namespace tessera::test
