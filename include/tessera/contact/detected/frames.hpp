#pragma once
// The frame of a block of detected_contacts (contact/detected_contacts.hpp): four of its vertex
// gridpoints spanning it, picked at construction (build_block_frame), and the block's motion read
// from them each step (motion_of). Not a public interface.
//
// A sub-contact is a material point p fixed in each block: its affine coordinates w (sum 1) in a
// frame of four vertex gridpoints of the block, so x(p) = sum_k w_k x_k and v(p) = sum_k w_k v_k
// exactly for a rigid motion (the secant gridpoint velocities of blocks::rigid are affine in the
// body coordinates). In the frame's terms x(p) = x0 + d l and v(p) = v0 + dv l, l = (w1, w2, w3) =
// d^-1 (x - x0) the point's local coordinates, w0 = 1 - w1 - w2 - w3; R = d D^-1 is the block's
// rotation from its reference frame D (a deformable block: the gradient F of its affine fit,
// detected/deformable_fit.hpp). The step that moves the sub-contacts: detected/step.hpp.
//
// Cost: build_block_frame O(vertices^2) once per block; the others O(1), no allocation. Thread
// safety: they read their arguments only (build_block_frame writes its block's record and lists).

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "../../core/errors.hpp"
#include "../../core/nodes.hpp"
#include "../../core/types.hpp"
#include "../../geometry/block_mesh.hpp"
#include "../../geometry/convex_polyhedron.hpp"
#include "../../geometry/tessellation.hpp"
#include "../../geometry/tessellation_queries.hpp"
#include "../detection/contact_plane.hpp"
#include "keys.hpp"

namespace tessera::contact::detail {

/// A block of detected_contacts: its frame, its vertex and watched gridpoints, its bounds.

struct detected_block {
  std::array<index_t, 4> frame{};  ///< vertex gridpoints spanning the block
  mat3 reference_inverse = mat3::Identity();  ///< [X1-X0 X2-X0 X3-X0]^-1
  index_t vertex_begin = 0, vertex_end = 0;     ///< into the vertex gridpoints list (local vertex order)
  index_t farthest = 0;                         ///< vertex gridpoint farthest from the centroid
  real stiffness_bound = 0;                   ///< N/m, on `farthest`
  real nominal_area = 0;                      ///< S / (3 V), m^2
  real surface = 0;                           ///< S, m^2
  vec3 centroid = vec3::Zero();               ///< reference centroid (m)
  index_t watch_begin = 0, watch_end = 0;  ///< its watched gridpoints (rigid: vertices; deformable: surface)
  // rigid blocks only: the trigger's bound (moved_bound)
  std::array<index_t, 4> frame_watch{};  ///< the frame gridpoints' rows in the watch list
  real frame_reach = std::numeric_limits<real>::infinity();  ///< largest |l| of a vertex's local coordinates
  // deformable blocks only
  index_t zone_begin = 0, zone_end = 0;    ///< its surface zones, into the surface zones list
  index_t face_begin = 0;                  ///< its first tessellation face (local face f = face_begin + f)
};

/// Position (m) of gridpoint g: its reference position (row g of `reference`) plus its
/// displacement in gp (none when gp is null).
[[nodiscard]] inline vec3 gridpoint_position(const soa3& reference, index_t g, const node_set* gp) {
  vec3 x = reference.row(g).transpose();
  if (gp != nullptr) x += gp->displacement.row(g).transpose();
  return x;
}
/// Block b's frame now, [x1-x0 x2-x0 x3-x0] (reference positions when gp is null).
[[nodiscard]] inline mat3 frame_matrix(const soa3& reference, const detected_block& b, const node_set* gp) {
  const vec3 x0 = gridpoint_position(reference, b.frame[0], gp);
  mat3 d;
  d << gridpoint_position(reference, b.frame[1], gp) - x0, gridpoint_position(reference, b.frame[2], gp) - x0,
      gridpoint_position(reference, b.frame[3], gp) - x0;
  return d;
}
/// Rotation of block b from its reference frame D: d D^-1.
[[nodiscard]] inline mat3 frame_rotation(const soa3& reference, const detected_block& b, const node_set* gp) {
  return frame_matrix(reference, b, gp) * b.reference_inverse;
}
/// d^-1 of block b's frame now: a point's local coordinates are d^-1 (x - x0).
[[nodiscard]] inline mat3 frame_inverse(const soa3& reference, const detected_block& b, const node_set* gp) {
  return frame_matrix(reference, b, gp).inverse();
}

/// A block's frame now: x(p) = x0 + d l, v(p) = v0 + dv l for the local coordinates l of a
/// point (its weights 1..3), and the rotation d D^-1 from the reference frame D.
/// For a deformable block `rotation` is the affine fit's gradient F = d D^-1 and normal_map
/// F^-T (a face normal in the reference frame maps to F^-T n0, normalised); for a rigid one
/// both are its rotation.
struct block_motion {
  vec3 x0 = vec3::Zero(), v0 = vec3::Zero();
  mat3 d = mat3::Identity(), dv = mat3::Zero(), rotation = mat3::Identity(), normal_map = mat3::Identity();
};
/// Block b's motion this step from its frame gridpoints in gp, written into every member of m
/// (a block's record in place, no temporary); `deformable`: normal_map is F^-T.
inline void motion_into(block_motion& m, const soa3& reference, const detected_block& b, const node_set& gp,
                        bool deformable) {
  // The columns read through raw pointers: the same sums and differences as gridpoint_position
  // and frame_matrix (the same bits), without a call and a row gather per gridpoint.
  const index_t* f = b.frame.data();
  for (int c = 0; c < 3; ++c) {
    const real* x = reference.col(c).data();
    const real* u = gp.displacement.col(c).data();
    const real* v = gp.velocity.col(c).data();
    const real x0 = x[f[0]] + u[f[0]], v0 = v[f[0]];
    m.x0[c] = x0;
    m.v0[c] = v0;
    for (int k = 1; k < 4; ++k) {
      m.d(c, k - 1) = (x[f[k]] + u[f[k]]) - x0;
      m.dv(c, k - 1) = v[f[k]] - v0;
    }
  }
  m.rotation = m.d * b.reference_inverse;
  if (deformable)
    m.normal_map = mat3(m.rotation.inverse().transpose());
  else
    m.normal_map = m.rotation;
}
/// The same, returned.
[[nodiscard]] inline block_motion motion_of(const soa3& reference, const detected_block& b, const node_set& gp,
                                            bool deformable) {
  block_motion m;
  motion_into(m, reference, b, gp, deformable);
  return m;
}

/// Rigid blocks: block b watches its vertices (watch list = vertex list), and the trigger's bound
/// (moved_bound) learns where its frame gridpoints sit in that list and the largest |l| of a
/// vertex's local coordinates l = D^-1 (X - X0) (infinite, so never used, if a frame gridpoint is
/// not a vertex or the frame is so skewed that |l| > 1e3).
inline void watch_vertices(detected_block& bd, const std::vector<index_t>& watch, const soa3& reference) {
  bd.watch_begin = bd.vertex_begin;
  bd.watch_end = bd.vertex_end;
  const vec3 x0 = reference.row(bd.frame[0]).transpose();
  real reach = 0;
  int found = 0;
  for (index_t k = bd.watch_begin; k < bd.watch_end; ++k) {
    const index_t g = watch[at(k)];
    for (int j = 0; j < 4; ++j)
      if (bd.frame[at(j)] == g) {
        bd.frame_watch[at(j)] = k;
        ++found;
      }
    reach = std::max(reach, (bd.reference_inverse * (reference.row(g).transpose() - x0)).norm());
  }
  bd.frame_reach = found == 4 && reach <= 1e3 ? reach : std::numeric_limits<real>::infinity();
}

/// Rigid blocks: a bound (m) on how far any vertex of block `bd` moved since it was last detected
/// (rebuild_u, the watched gridpoints' displacements then). Every vertex moves as
/// du = du0 + [du1 - du0, du2 - du0, du3 - du0] l with its local coordinates l (|l| <= frame_reach)
/// and du0..du3 the frame vertices' moves, up to the round-off of the slaved displacements
/// (~1e-16 of them), so |du| <= |du0| + |[...]|_F frame_reach. O(1): four gridpoints, not every vertex.
[[nodiscard]] inline real moved_bound(const detected_block& bd, const node_set& gp, const soa3& rebuild_u) noexcept {
  real du[4][3];
  for (int j = 0; j < 4; ++j)
    for (int c = 0; c < 3; ++c)
      du[j][c] = gp.displacement.col(c).data()[bd.frame[at(j)]] - rebuild_u.col(c).data()[bd.frame_watch[at(j)]];
  real a2 = 0, d2 = 0;
  for (int c = 0; c < 3; ++c) {
    a2 += du[0][c] * du[0][c];
    for (int j = 1; j < 4; ++j) d2 += (du[j][c] - du[0][c]) * (du[j][c] - du[0][c]);
  }
  return bd.frame_reach <= 1e3 ? std::sqrt(a2) + std::sqrt(d2) * bd.frame_reach : std::numeric_limits<real>::infinity();
}

/// Vertex gridpoints (appended to vertex_gridpoints), shape, edges, frame and bounds of block b
/// of `tess`, whose gridpoints `mesh` holds: fills its record `bd` (all but its watched gridpoints
/// and surface zones). Throws geometry_error when a vertex has no gridpoint or the block is flat.
inline void build_block_frame(const geometry::tessellation& tess, const geometry::block_mesh& mesh, index_t b,
                              std::vector<index_t>& vertex_gridpoints, detected_block& bd,
                              geometry::convex_polyhedron& shape, detection::polyhedron_edges& edges) {
  // The tessellation vertex -> gridpoint map of this block.
  std::vector<std::pair<index_t, index_t>> vertex_gp;
  for (index_t g = mesh.block_gridpoint_offsets[at(b)]; g < mesh.block_gridpoint_offsets[at(b) + 1]; ++g)
    if (const index_t v = mesh.gridpoint_vertex[at(g)]; v != invalid_index) vertex_gp.emplace_back(v, g);
  std::sort(vertex_gp.begin(), vertex_gp.end());
  bd.vertex_begin = static_cast<index_t>(vertex_gridpoints.size());
  // Local vertices in order of first use, as geometry::cell_polyhedron numbers them.
  std::vector<index_t> local;
  for (index_t f = tess.first_face(b); f < tess.end_face(b); ++f)
    for (index_t v : tess.face(f))
      if (std::find(local.begin(), local.end(), v) == local.end()) {
        local.push_back(v);
        const auto it =
            std::lower_bound(vertex_gp.begin(), vertex_gp.end(), std::pair<index_t, index_t>{v, index_t{-1}});
        require<geometry_error>(it != vertex_gp.end() && it->first == v, "detected_contacts: vertex ", v,
                                " of block ", b, " has no gridpoint in the block_mesh");
        vertex_gridpoints.push_back(it->second);
      }
  bd.vertex_end = static_cast<index_t>(vertex_gridpoints.size());
  shape = geometry::cell_polyhedron(tess, b);
  edges = detection::edges_of(shape);
  const geometry::convex_polyhedron& s = shape;
  // Frame: the first vertex, the farthest from it, the farthest from their line, the farthest
  // from their plane.
  const auto gp = [&](index_t k) { return vertex_gridpoints[at(bd.vertex_begin + k)]; };
  const index_t nv = bd.vertex_end - bd.vertex_begin;
  const auto arg_max = [&](auto&& score) {
    index_t best = 0;
    for (index_t k = 1; k < nv; ++k)
      if (score(s.vertex(k)) > score(s.vertex(best))) best = k;
    return best;
  };
  const vec3 x0 = s.vertex(0);
  const index_t k1 = arg_max([&](const vec3& x) { return (x - x0).squaredNorm(); });
  const vec3 d1 = (s.vertex(k1) - x0).normalized();
  const index_t k2 = arg_max([&](const vec3& x) { return (x - x0 - d1 * d1.dot(x - x0)).squaredNorm(); });
  const vec3 n12 = d1.cross(s.vertex(k2) - x0).normalized();
  const index_t k3 = arg_max([&](const vec3& x) { return std::abs(n12.dot(x - x0)); });
  bd.frame = {gp(0), gp(k1), gp(k2), gp(k3)};
  mat3 d;
  d << s.vertex(k1) - x0, s.vertex(k2) - x0, s.vertex(k3) - x0;
  require<geometry_error>(std::abs(d.determinant()) > 1e-12 * std::pow(s.extent(), 3), "detected_contacts: block ", b,
                          " is flat (its vertices span no volume)");
  bd.reference_inverse = d.inverse();
  // Bounds.
  const vec3 c = s.centroid();
  real surface = 0;
  for (index_t f = 0; f < s.face_count(); ++f) surface += s.face_area(f);
  bd.farthest = gp(arg_max([&](const vec3& x) { return (x - c).squaredNorm(); }));
  bd.centroid = c;
  bd.surface = surface;
  bd.nominal_area = surface / (3 * static_cast<real>(nv));
}

}  // namespace tessera::contact::detail
