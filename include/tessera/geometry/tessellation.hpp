#pragma once
// A conforming tessellation of a box into convex polyhedral cells (the blocks of a scene).
//
// Produced by geometry::voronoi / geometry::laguerre (geometry/voronoi.hpp) or
// io::read_neper_tess (io/neper.hpp); consumed by the zoning (geometry/zoning.hpp), the
// rigid-block model and the sub-contact builder.
//
// Storage: flat arrays behind index handles (CSR for variable-length lists).
//  - vertices are global and welded: two cells that touch at a point use the same vertex id,
//    so a shared face is the same vertex set seen from both sides (loops reversed).
//  - every cell owns a contiguous run of faces; a face is a loop of global vertex ids,
//    counter-clockwise seen from outside its cell (outward normal by the right-hand rule).
//  - an interior face has a twin: the same face stored by the neighbouring cell.
//  - each interior face pair is also listed once in `shared_faces` (cell_a < cell_b).

#include <span>
#include <vector>

#include "../core/types.hpp"

namespace tessera::geometry {

/// Boundary tag of a face on the side of the domain box: side 0..5 = x-, x+, y-, y+, z-, z+.
/// Stored in face_neighbor as a negative value.
[[nodiscard]] constexpr index_t boundary_tag(int side) { return -1 - side; }
/// Inverse of boundary_tag: the box side of a boundary face's neighbor value (0..5), or -1.
[[nodiscard]] constexpr int boundary_side(index_t neighbor) { return neighbor < 0 ? -1 - neighbor : -1; }

/// A conforming tessellation of convex cells (m): vertices, faces as CCW loops, each cell's faces and each face's neighbour
struct tessellation {
  aabb domain;                       ///< the tessellated box (m)
  std::vector<vec3> seeds;           ///< generator of each cell (m); empty when read from a file without them
  std::vector<real> weights;         ///< Laguerre weights (m^2), empty for a plain Voronoi tessellation

  std::vector<vec3> vertices;        ///< welded global vertex positions (m)

  std::vector<index_t> face_offsets{0};  ///< CSR: face f's loop is face_vertices[face_offsets[f] .. face_offsets[f+1])
  std::vector<index_t> face_vertices;    ///< global vertex ids, CCW seen from outside face_cell[f]
  std::vector<index_t> face_cell;        ///< owning cell of each face
  std::vector<index_t> face_neighbor;    ///< neighbouring cell id (>= 0) or boundary_tag(side) (< 0)
  std::vector<index_t> face_twin;        ///< the twin face stored by the neighbour, invalid_index on the boundary

  std::vector<index_t> cell_face_offsets{0};  ///< CSR: faces of cell c are [cell_face_offsets[c], cell_face_offsets[c+1])

  /// An interior face as its two twin faces
  struct shared_face {
    /** lower cell id and its face */ /**@{*/ index_t cell_a, face_a; /**@}*/
    /** higher cell id and its (reversed) twin face */ /**@{*/ index_t cell_b, face_b; /**@}*/
  };
  std::vector<shared_face> shared_faces;  ///< every interior face once

  [[nodiscard]] index_t cell_count() const { return static_cast<index_t>(cell_face_offsets.size()) - 1; }  ///< Number of cells
  [[nodiscard]] index_t face_count() const { return static_cast<index_t>(face_offsets.size()) - 1; }  ///< Number of faces (each interior face twice)
  [[nodiscard]] index_t vertex_count() const { return static_cast<index_t>(vertices.size()); }  ///< Number of vertices
  /// Global vertex ids of face f, CCW seen from outside its cell.
  [[nodiscard]] std::span<const index_t> face(index_t f) const {
    return {face_vertices.data() + face_offsets[f],
            static_cast<std::size_t>(face_offsets[f + 1] - face_offsets[f])};
  }
  [[nodiscard]] index_t first_face(index_t c) const { return cell_face_offsets[c]; }  ///< First face of cell c
  [[nodiscard]] index_t end_face(index_t c) const { return cell_face_offsets[c + 1]; }  ///< One past the last face of cell c
  [[nodiscard]] bool is_boundary_face(index_t f) const { return face_neighbor[f] < 0; }  ///< True when face f lies on the domain's boundary
};

}  // namespace tessera::geometry
