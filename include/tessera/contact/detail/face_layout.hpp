#pragma once
// Construction-time layout of contact::face_contacts after the pairing of the face nodes
// (face_pairs.hpp): the face blocks, runs of consecutive faces that are the unit of the parallel
// face loop, and the faces' frames in the reference configuration.

#include <vector>

#include "../../core/errors.hpp"
#include "../../core/nodes.hpp"
#include "../../core/types.hpp"
#include "../../geometry/tessellation.hpp"
#include "face_pairs.hpp"

namespace tessera::contact::detail {

/// Face blocks of `face_count` faces: runs of consecutive faces with at least `block_subcontacts`
/// sub-contacts (the last one may have fewer) and one material-pair entry (face_param), as
/// offsets: faces [blocks[b], blocks[b + 1]) form block b. first_subcontact: the faces'
/// sub-contact ranges (face s has [first_subcontact[s], first_subcontact[s + 1])).
[[nodiscard]] inline std::vector<index_t> face_blocks_of(index_t face_count, const std::vector<index_t>& face_param,
                                                       const std::vector<index_t>& first_subcontact,
                                                       index_t block_subcontacts) {
  const auto at = [](index_t i) { return static_cast<std::size_t>(i); };
  std::vector<index_t> blocks(1, 0);
  for (index_t s = 0; s < face_count; ++s)
    if (s + 1 == face_count || face_param[at(s) + 1] != face_param[at(s)] ||
        first_subcontact[at(s) + 1] - first_subcontact[at(blocks.back())] >= block_subcontacts)
      blocks.push_back(s + 1);
  return blocks;
}

/// Unit normals (A -> B) of `face_count` faces in the reference configuration (zero displacements
/// of `n_gridpoints` gridpoints), one row per face, from their corners' vector areas. Throws
/// geometry_error, naming the shared face and its cells, for a face whose two sides cancel (its
/// polygon has no plane).
[[nodiscard]] inline soa3 reference_normals(const face_corners& corners,
                                            const std::vector<geometry::tessellation::shared_face>& shared_faces,
                                            index_t face_count, index_t n_gridpoints) {
  soa3 normal;
  normal.setZero(face_count, 3);
  const soa3 u = soa3::Zero(n_gridpoints, 3);
  const real* up[3] = {u.col(0).data(), u.col(1).data(), u.col(2).data()};
  for (index_t s = 0; s < face_count; ++s) {
    const kinematics::triple area = corners.area_vector(s, up);
    const vec3 d(area.x, area.y, area.z);
    const auto& sf = shared_faces[static_cast<std::size_t>(s)];
    require<geometry_error>(d.norm() > 0, "face_contacts: shared face ", s, " (cells ", sf.cell_a, " and ", sf.cell_b,
                            "): zero vector area, the face polygon has no plane (degenerate face)");
    normal.row(s) = d.normalized().transpose();
  }
  return normal;
}

}  // namespace tessera::contact::detail
