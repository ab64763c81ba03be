#pragma once
// Gridpoints and constant-strain tetrahedral zones of deformable blocks, built from a
// tessellation by geometry::zone_blocks (geometry/zoning.hpp).
//
// Each block has its own copy of each of its polyhedron's vertices (blocks are distinct
// bodies joined only by contacts), plus interior gridpoints (at least the block centroid).
// Every face of the tessellation is triangulated the same way from both sides, so the face
// gridpoints of two neighbours coincide one to one and sub-contacts can pair them.

#include <array>
#include <span>
#include <vector>

#include "../core/types.hpp"

namespace tessera::geometry {

/// The gridpoints and tetrahedral zones of every block of a tessellation (geometry::zone_blocks), with each face's surface nodes
struct block_mesh {
  // ---- gridpoints (all blocks, grouped by block) ----
  std::vector<vec3> gridpoints;                ///< reference positions (m)
  std::vector<index_t> gridpoint_block;          ///< owning block
  std::vector<index_t> gridpoint_vertex;         ///< tessellation vertex it copies, invalid_index if interior
  std::vector<index_t> block_gridpoint_offsets{0};  ///< CSR: gridpoints of block b

  // ---- materials ----
  /// Material id of each block (>= 0), indexing the block model's per-material parameters and the
  /// contact set's material-pair table (contact::material_table); empty means material 0 for
  /// every block. Set it after zoning, e.g. mesh.block_material[b] = 1 for a steel plate.
  std::vector<int> block_material;
  [[nodiscard]] int material(index_t block) const {  ///< Material id of block (0 without block_material)
    return block_material.empty() ? 0 : block_material[static_cast<std::size_t>(block)];
  }

  // ---- zones: 4-node tetrahedra, positive orientation ((x1-x0)x(x2-x0)).(x3-x0) > 0 ----
  std::vector<std::array<index_t, 4>> zones;     ///< gridpoint ids
  std::vector<index_t> zone_block;               ///< owning block
  std::vector<index_t> block_zone_offsets{0};    ///< CSR: zones of block b

  // ---- tessellation faces seen by the mesh (same face ids as the tessellation) ----
  /// Surface nodes of face f: face_nodes[face_node_offsets[f] .. face_node_offsets[f+1]) are the
  /// distinct gridpoints (of the face's own block) lying on face f. Twin faces list their
  /// coincident gridpoints in the same order, so node k of face f pairs with node k of its twin:
  /// that pair is one sub-contact.
  std::vector<index_t> face_node_offsets{0};
  std::vector<index_t> face_nodes;  ///< gridpoint ids of each face's surface nodes (CSR by face_node_offsets)
  /// Tributary area (m^2) of each entry of face_nodes: one third of the area of every face
  /// triangle touching the node (the consistent nodal share of a uniform traction on linear
  /// triangles). The areas of a face sum to the face area; twins carry identical areas.
  std::vector<real> face_node_area;
  /// Surface triangles of face f: face_triangles[face_triangle_offsets[f] .. face_triangle_offsets[f+1]),
  /// gridpoint ids, CCW seen from outside the block; twin faces are triangulated identically.
  std::vector<index_t> face_triangle_offsets{0};
  std::vector<std::array<index_t, 3>> face_triangles;  ///< gridpoint ids of each face's triangles (CSR by face_triangle_offsets)

  [[nodiscard]] index_t gridpoint_count() const { return static_cast<index_t>(gridpoints.size()); }  ///< Number of gridpoints
  [[nodiscard]] index_t zone_count() const { return static_cast<index_t>(zones.size()); }  ///< Number of zones
  [[nodiscard]] index_t block_count() const { return static_cast<index_t>(block_gridpoint_offsets.size()) - 1; }  ///< Number of blocks
};

}  // namespace tessera::geometry
