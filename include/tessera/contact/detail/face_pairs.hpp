#pragma once
// The sub-contacts of a conforming tessellation's shared faces, paired and checked
// (contact::face_contacts, "Creation" in face_contacts.hpp): for every shared face the face nodes
// of its two sides, pairwise, with their tributary areas, the face's material-pair entry, and the
// polygon corners that give the face its frame. And the gather incidence gridpoint -> (sub-contact,
// sign) of the force kernel, built with core/csr.hpp. Construction-time only.
//
// Blocks of a conforming tessellation share faces exactly. For every shared face
// s = (cell_a < cell_b, face_a, face_b) of the tessellation the block_mesh lists the face
// gridpoints of the two sides in the same order (node k of face_a coincides with node k of
// face_b); each such pair is one sub-contact i with
//     node_a(i) = face_nodes(face_a)[k],   node_b(i) = face_nodes(face_b)[k],
//     area(i)   = face_node_area(face_a)[k]   (tributary area, m^2; equal to face_b's),
// so the sub-contact areas of a face sum to the face area. Block A is the lower cell id.
// Sub-contacts of a face are contiguous, faces in tessellation::shared_faces order, and
// "face s" below always means shared face s (not a tessellation face id).

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "../../core/csr.hpp"
#include "../../core/errors.hpp"
#include "../../core/separate_compilation.hpp"
#include "../../core/types.hpp"
#include "../kinematics.hpp"
#include "../../geometry/block_mesh.hpp"
#include "../../geometry/tessellation.hpp"
#include "../material_table.hpp"

namespace tessera::contact::detail {

/// Polygon corners of each shared face, for its frame (face_contacts' contact frame): one unit
/// normal per shared face per step, from block A to block B, the
/// normalised vector area of the face's polygon drawn through the midpoints of its corner pairs:
///     m_k = (x_a,k + x_b,k) / 2,   S = sum_{k=1}^{K-2} (m_k - m_0) x (m_{k+1} - m_0),   n = S / |S|
/// where k runs over the K polygon vertices of the tessellation face (tessellation::face(face_a),
/// counter-clockwise seen from A, so S points from A to B) and x = X + u are current positions.
/// This is the common plane of the two nearly coincident sides: (S_a - S_b)/2, the difference of
/// the Newell vectors of side A and side B, up to terms quadratic in the relative displacement of
/// the sides (microns against the face size). The vector area of a closed loop does not depend on
/// the surface spanned, so S is exact for a planar face and the mean plane of a warped one; edge
/// midpoints and interior face gridpoints of a refined zoning do not enter it. Faces are 4 to 8
/// times fewer than sub-contacts, so the frame is computed once per face per step and shared.
struct face_corners {
  /// Corners of face s (CCW seen from A): CSR [first[s], first[s + 1]), the gridpoints of each
  /// corner pair (a, b) and the reference offset X_a,k - X_a,0 from the face's first corner.
  std::vector<index_t> first{0}, a, b;
  std::array<std::vector<real>, 3> offset;

  [[nodiscard]] static constexpr std::size_t at(index_t i) noexcept { return static_cast<std::size_t>(i); }
  /// Twice the vector area of face s's polygon through the midpoints of its corner pairs (m^2),
  /// sum_k (m_k - m_0) x (m_{k+1} - m_0) (see above), from differences
  /// (X_k - X_0) + ((u_a,k + u_b,k) - (u_a,0 + u_b,0)) / 2 so the displacement is not swamped by
  /// the coordinates; X of side A stands for both sides (coincident to 1e-9 of the model size),
  /// and X_k - X_0 is the stored `offset` (the reference positions of the block_mesh).
  [[nodiscard]] kinematics::triple area_vector(index_t s, const real* const u[3]) const noexcept {
    const auto begin = at(first[at(s)]);
    const auto count = at(first[at(s) + 1]) - begin;
    const index_t* ca = a.data() + begin;
    const index_t* cb = b.data() + begin;
    const real* dX[3] = {offset[0].data() + begin, offset[1].data() + begin,
                         offset[2].data() + begin};
    real origin_u[3];
    for (int c = 0; c < 3; ++c) origin_u[c] = 0.5 * (u[c][ca[0]] + u[c][cb[0]]);
    const auto midpoint_offset = [&](std::size_t k) {
      const index_t ga = ca[k], gb = cb[k];
      real d[3];
      for (int c = 0; c < 3; ++c) d[c] = dX[c][k] + (0.5 * (u[c][ga] + u[c][gb]) - origin_u[c]);
      return kinematics::triple{d[0], d[1], d[2]};
    };
    kinematics::triple s_area{0, 0, 0};
    kinematics::triple previous = midpoint_offset(1);
    for (std::size_t k = 2; k < count; ++k) {
      const kinematics::triple next = midpoint_offset(k);
      const kinematics::triple area = kinematics::cross(previous, next);
      s_area = {s_area.x + area.x, s_area.y + area.y, s_area.z + area.z};
      previous = next;
    }
    return s_area;
  }
};

/// Sub-contacts and face data of face_contacts, in its order (faces in tessellation::shared_faces
/// order, the sub-contacts of a face contiguous).
struct face_pairs {
  std::vector<index_t> node_a, node_b, face;  ///< per sub-contact: gridpoints of sides A and B, shared face
  std::vector<real> area;                   ///< per sub-contact: tributary area (m^2)
  std::vector<index_t> first_subcontact{0};   ///< face s: sub-contacts [first_subcontact[s], first_subcontact[s + 1])
  std::vector<real> face_area;              ///< per face: sum of its sub-contact areas (m^2)
  std::vector<index_t> face_param;            ///< per face: its material_table entry
  face_corners corners;                     ///< polygon corners of each face
};

/// The block_mesh arrays face_contacts reads have the sizes of `tess` and of each other.
TESSERA_INLINE void check_face_mesh(const geometry::tessellation& tess, const geometry::block_mesh& mesh);

/// One shared face s while it is paired: its record, first face nodes of both sides, node
/// count, and the check that throws geometry_error naming it.
struct face_in_pairing {
  index_t s;
  const geometry::tessellation::shared_face& sf;
  index_t na0, nb0, n_nodes;
  template <class... Message>
  void check(bool ok, const Message&... message) const {
    if (!ok)
      throw geometry_error(tessera::detail::concat("face_contacts: shared face ", s, " (cells ", sf.cell_a, " and ",
                                                   sf.cell_b, ", tessellation faces ", sf.face_a, " and ", sf.face_b,
                                                   "): ", message...));
  }
};

/// The sub-contacts of face f: pairs of coincident face nodes of its two sides, with their areas.
TESSERA_INLINE void pair_nodes(face_pairs& r, const face_in_pairing& f, const geometry::block_mesh& mesh, real tolerance);

/// Polygon corners of face f: the face node of each tessellation vertex of face_a, in loop order,
/// and their reference offsets from the first one (side A).
TESSERA_INLINE void add_corners(face_pairs& r, const face_in_pairing& f, const geometry::tessellation& tess,
                        const geometry::block_mesh& mesh);

/// Pairs the face nodes of every shared face of `tess` (face_contacts' constructor documents the
/// checks; each throws geometry_error naming the shared face, its cells and tessellation faces).
template <class P>
[[nodiscard]] face_pairs pair_face_nodes(const geometry::tessellation& tess, const geometry::block_mesh& mesh,
                                         const material_table<P>& table) {
  const auto at = [](index_t i) { return static_cast<std::size_t>(i); };
  check_face_mesh(tess, mesh);
  const index_t n_faces = tess.face_count();
  aabb box;
  for (const vec3& x : mesh.gridpoints) box.expand(x);
  const real tolerance = 1e-9 * (mesh.gridpoints.empty() ? 1.0 : box.size().norm());
  const auto face_count = static_cast<index_t>(tess.shared_faces.size());
  face_pairs r;
  r.first_subcontact.reserve(at(face_count) + 1);
  r.corners.first.reserve(at(face_count) + 1);
  r.face_area.reserve(at(face_count));
  for (index_t s = 0; s < face_count; ++s) {
    const auto& sf = tess.shared_faces[at(s)];
    face_in_pairing f{s, sf, 0, 0, 0};
    f.check(sf.face_a >= 0 && sf.face_a < n_faces && sf.face_b >= 0 && sf.face_b < n_faces && sf.cell_a >= 0 &&
                sf.cell_a < sf.cell_b && sf.cell_b < tess.cell_count(),
            "face or cell id out of range or cells not in increasing order (", tess.cell_count(), " cells, ", n_faces,
            " faces)");
    if (static_cast<index_t>(tess.face_cell.size()) == n_faces)
      f.check(tess.face_cell[at(sf.face_a)] == sf.cell_a && tess.face_cell[at(sf.face_b)] == sf.cell_b,
              "faces belong to cells ", tess.face_cell[at(sf.face_a)], " and ", tess.face_cell[at(sf.face_b)]);
    f.na0 = mesh.face_node_offsets[at(sf.face_a)];
    f.nb0 = mesh.face_node_offsets[at(sf.face_b)];
    f.n_nodes = mesh.face_node_offsets[at(sf.face_a) + 1] - f.na0;
    const index_t n_nodes_b = mesh.face_node_offsets[at(sf.face_b) + 1] - f.nb0;
    f.check(f.n_nodes == n_nodes_b && f.n_nodes >= 3, "the sides have ", f.n_nodes, " and ", n_nodes_b,
            " face nodes, expected the same number (>= 3)");
    pair_nodes(r, f, mesh, tolerance);
    r.face_param.push_back(static_cast<index_t>(table.entry_index(mesh.material(sf.cell_a), mesh.material(sf.cell_b))));
    add_corners(r, f, tess, mesh);
  }
  return r;
}

/// Gather incidence: for each gridpoint carrying sub-contacts, in increasing id, one slot per
/// incident sub-contact in increasing sub-contact order: the sub-contact and the sign of its
/// stored force (the force on node A) on that gridpoint (+1 on node A, -1 on node B).
struct gather_slots {
  std::vector<index_t> offsets;      ///< CSR over all gridpoints (empty rows for those without sub-contacts)
  std::vector<index_t> subcontact;   ///< per slot
  std::vector<real> sign;          ///< per slot, +1 or -1
  std::vector<index_t> gridpoints;   ///< gridpoints with a non-empty row, increasing
};
[[nodiscard]] TESSERA_INLINE gather_slots build_gather(index_t n_gridpoints, const std::vector<index_t>& node_a,
                                               const std::vector<index_t>& node_b);

}  // namespace tessera::contact::detail

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/face_pairs.ipp"
#endif
