// The definitions of the larger functions that contact/detail/face_pairs.hpp declares (their
// documentation is there): included at the end of that header, or compiled once into
// tessera::instances under TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../face_pairs.hpp"

namespace tessera::contact::detail {

TESSERA_INLINE void check_face_mesh(const geometry::tessellation& tess, const geometry::block_mesh& mesh) {
  const index_t n_faces = tess.face_count();
  const index_t n_gridpoints = mesh.gridpoint_count();
  require<geometry_error>(static_cast<index_t>(mesh.face_node_offsets.size()) == n_faces + 1,
                          "face_contacts: block_mesh has face nodes for ", mesh.face_node_offsets.size() - 1,
                          " faces, expected one entry per tessellation face (", n_faces, ")");
  require<geometry_error>(static_cast<index_t>(mesh.gridpoint_vertex.size()) == n_gridpoints,
                          "face_contacts: block_mesh has ", mesh.gridpoint_vertex.size(),
                          " gridpoint_vertex entries, expected one per gridpoint (", n_gridpoints, ")");
  require<geometry_error>(mesh.face_node_area.size() == mesh.face_nodes.size(), "face_contacts: block_mesh has ",
                          mesh.face_node_area.size(), " face node areas for ", mesh.face_nodes.size(), " face nodes");
  require<geometry_error>(mesh.block_material.empty() || static_cast<index_t>(mesh.block_material.size()) == mesh.block_count(),
                          "face_contacts: block_mesh has ", mesh.block_material.size(), " block materials for ",
                          mesh.block_count(), " blocks (give one id per block, or none for all 0)");
}

TESSERA_INLINE void pair_nodes(face_pairs& r, const face_in_pairing& f, const geometry::block_mesh& mesh, real tolerance) {
  const auto at = [](index_t i) { return static_cast<std::size_t>(i); };
  const index_t n_gridpoints = mesh.gridpoint_count();
  real face_area = 0;
  for (index_t k = 0; k < f.n_nodes; ++k) {
    const index_t a = mesh.face_nodes[at(f.na0 + k)];
    const index_t b = mesh.face_nodes[at(f.nb0 + k)];
    f.check(a >= 0 && a < n_gridpoints && b >= 0 && b < n_gridpoints, "face node ", k, " refers to gridpoints ", a,
            " and ", b, ", expected ids in [0, ", n_gridpoints, ")");
    if (static_cast<index_t>(mesh.gridpoint_block.size()) == n_gridpoints)
      f.check(mesh.gridpoint_block[at(a)] == f.sf.cell_a && mesh.gridpoint_block[at(b)] == f.sf.cell_b, "face node ",
              k, ": gridpoints ", a, " and ", b, " belong to blocks ", mesh.gridpoint_block[at(a)], " and ",
              mesh.gridpoint_block[at(b)]);
    const vec3& xa = mesh.gridpoints[at(a)];
    const vec3& xb = mesh.gridpoints[at(b)];
    const real gap = (xb - xa).norm();
    f.check(gap <= tolerance, "face node ", k, ": gridpoint ", a, " at (", xa.x(), ", ", xa.y(), ", ", xa.z(),
            ") and gridpoint ", b, " at (", xb.x(), ", ", xb.y(), ", ", xb.z(), ") are ", gap,
            " m apart, expected coincident (tolerance ", tolerance,
            " m); the twin faces list their nodes in different orders");
    const real area_a = mesh.face_node_area[at(f.na0 + k)];
    const real area_b = mesh.face_node_area[at(f.nb0 + k)];
    f.check(area_a > 0 && std::isfinite(area_a) && std::abs(area_a - area_b) <= 1e-9 * std::max(area_a, area_b),
            "face node ", k, ": tributary areas ", area_a, " and ", area_b, " m^2, expected equal and > 0");
    r.node_a.push_back(a);
    r.node_b.push_back(b);
    r.face.push_back(f.s);
    r.area.push_back(area_a);
    face_area += area_a;
  }
  r.first_subcontact.push_back(static_cast<index_t>(r.node_a.size()));
  r.face_area.push_back(face_area);
}

TESSERA_INLINE void add_corners(face_pairs& r, const face_in_pairing& f, const geometry::tessellation& tess,
                        const geometry::block_mesh& mesh) {
  const auto at = [](index_t i) { return static_cast<std::size_t>(i); };
  const auto loop = tess.face(f.sf.face_a);
  f.check(loop.size() >= 3, "the polygon has ", loop.size(), " vertices, expected >= 3");
  for (const index_t vertex : loop) {
    index_t corner = invalid_index;
    for (index_t k = 0; k < f.n_nodes && corner == invalid_index; ++k)
      if (mesh.gridpoint_vertex[at(mesh.face_nodes[at(f.na0 + k)])] == vertex &&
          mesh.gridpoint_vertex[at(mesh.face_nodes[at(f.nb0 + k)])] == vertex)
        corner = r.first_subcontact[at(f.s)] + k;
    f.check(corner != invalid_index, "tessellation vertex ", vertex,
            " has no face node copying it on both sides (block_mesh::gridpoint_vertex)");
    r.corners.a.push_back(r.node_a[at(corner)]);
    r.corners.b.push_back(r.node_b[at(corner)]);
  }
  r.corners.first.push_back(static_cast<index_t>(r.corners.a.size()));
  const vec3& x0 = mesh.gridpoints[at(r.corners.a[at(r.corners.first[at(f.s)])])];
  for (index_t k = r.corners.first[at(f.s)]; k < r.corners.first[at(f.s) + 1]; ++k)
    for (int c = 0; c < 3; ++c) r.corners.offset[at(c)].push_back(mesh.gridpoints[at(r.corners.a[at(k)])][c] - x0[c]);
}

[[nodiscard]] TESSERA_INLINE gather_slots build_gather(index_t n_gridpoints, const std::vector<index_t>& node_a,
                                               const std::vector<index_t>& node_b) {
  gather_slots g;
  const std::size_t n = node_a.size();
  const auto slots = [&](auto&& emit) {
    for (std::size_t i = 0; i < n; ++i) {
      emit(node_b[i], [&, i](index_t slot) {
        g.subcontact[static_cast<std::size_t>(slot)] = static_cast<index_t>(i);
        g.sign[static_cast<std::size_t>(slot)] = -1;
      });
      emit(node_a[i], [&, i](index_t slot) {
        g.subcontact[static_cast<std::size_t>(slot)] = static_cast<index_t>(i);
        g.sign[static_cast<std::size_t>(slot)] = 1;
      });
    }
  };
  g.offsets = csr_offsets(n_gridpoints, slots);
  g.subcontact.resize(2 * n);
  g.sign.resize(2 * n);
  csr_fill(g.offsets, slots);
  for (index_t v = 0; v < n_gridpoints; ++v)
    if (g.offsets[static_cast<std::size_t>(v) + 1] > g.offsets[static_cast<std::size_t>(v)]) g.gridpoints.push_back(v);
  return g;
}

}  // namespace tessera::contact::detail
