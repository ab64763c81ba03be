#pragma once
// Deformable blocks in detected_contacts (contact/detected_contacts.hpp, params::deformable_blocks):
// their surfaces, the affine fit detection reads and the sub-contacts at surface gridpoints.
//
// Deformable blocks (params::deformable_blocks). Detection reads each block's affine fit: the map
// F = d D^-1 of its frame (four vertex gridpoints) applied to its reference polyhedron, so the
// shapes stay convex with planar faces. A rebuild measures how far every surface gridpoint lies
// from its block's fit (max_deviation()) and refuses a block farther than a quarter of the
// tolerance (geometry_error: raise the tolerance); the trigger then reads every surface gridpoint
// and fires at tolerance / 2 - deviation, so the guarantee of detected/rebuild.hpp ("Rebuilds")
// holds for the real surfaces. A
// face-to-face patch puts its sub-contacts at surface gridpoints (block_mesh::face_nodes) rather
// than at its corners, as 3DEC does for zoned blocks: those of A's faces that face the plane and
// lie within tolerance / 2 of the patch, or those of B's, whichever side's tributary areas
// (block_mesh::face_node_area) sum closer to the patch area (a small face on a large one: the
// small face's; the side of the last rebuild while it fits within 5 %), each labelled by its
// gridpoint, their areas scaled to sum to the patch area; a side needs three such gridpoints,
// else the patch keeps its corners. Each material point is the gridpoint itself on its own side
// and, on the other, the surface zone holding it (largest smallest barycentric weight): four
// gridpoints and their weights, fixed between rebuilds, so a point moves with the zone's linear
// field exactly and its force goes to those gridpoints. Corners of segment and point patches are
// located in both blocks' zones the same way. Face normals turn with F^-T, edges with F. Stable step: every
// surface gridpoint g carries 4 k_row (a_g + 2 T_g + 2 a_max), a_g its own tributary area, T_g the
// surface area of the zones around it (where other blocks' points can land), a_max the largest
// tributary or nominal area in the scene.
//
// Cost: build_surfaces once (O(surface triangles x block zones)); locate O(surface zones of the
// block) per material point and collect_nodes O(surface gridpoints of the two blocks) per polygon
// patch, at rebuilds only (collect_nodes reuses its scratch arrays).
//
// Definitions of detected_contacts<Law>'s private members (declared in the class); it includes the
// class and the class includes it, so either header can come first.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Dense>

#include "../../core/errors.hpp"
#include "../../core/nodes.hpp"
#include "../../core/types.hpp"
#include "../../geometry/block_mesh.hpp"
#include "../../geometry/tessellation.hpp"
#include "../detected_contacts.hpp"
#include "keys.hpp"

namespace tessera::contact {

/// Deformable blocks: surface gridpoints, surface zones and the per-gridpoint stiffness bounds
/// (file comment).
template <law::ContactLaw Law>
inline void detected_contacts<Law>::build_surfaces(const geometry::tessellation& tess, const geometry::block_mesh& mesh,
                                                   real row_max) {
  const index_t n_faces = static_cast<index_t>(mesh.face_node_offsets.size()) - 1;
  require<geometry_error>(
      n_faces == static_cast<index_t>(tess.face_cell.size()) && mesh.face_node_area.size() == mesh.face_nodes.size() &&
          static_cast<index_t>(mesh.face_triangle_offsets.size()) == n_faces + 1,
      "detected_contacts: the block_mesh has surface nodes for ", n_faces, " faces, the tessellation ",
      tess.face_cell.size(), " (zone the blocks with geometry::zone_blocks)");
  face_node_offsets_ = mesh.face_node_offsets;
  face_nodes_ = mesh.face_nodes;
  face_node_area_ = mesh.face_node_area;
  zones_ = mesh.zones;
  std::vector<real> own(at(gridpoint_count_), 0.0), around(at(gridpoint_count_), 0.0);
  std::vector<std::uint8_t> on_surface(at(gridpoint_count_), 0);
  real a_max = 0;
  for (real a : face_node_area_) a_max = std::max(a_max, a);
  for (const block_data& bd : blocks_) a_max = std::max(a_max, bd.nominal_area);
  std::vector<index_t> nodes;
  std::vector<real> zone_area;
  for (index_t b = 0; b < static_cast<index_t>(blocks_.size()); ++b) {
    block_data& bd = blocks_[at(b)];
    bd.face_begin = tess.first_face(b);
    nodes.clear();
    for (index_t f = tess.first_face(b); f < tess.end_face(b); ++f)
      for (index_t e = face_node_offsets_[at(f)]; e < face_node_offsets_[at(f) + 1]; ++e) {
        nodes.push_back(face_nodes_[at(e)]);
        own[at(face_nodes_[at(e)])] += face_node_area_[at(e)];
      }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    bd.watch_begin = static_cast<index_t>(watch_gridpoints_.size());
    watch_gridpoints_.insert(watch_gridpoints_.end(), nodes.begin(), nodes.end());
    bd.watch_end = static_cast<index_t>(watch_gridpoints_.size());
    // The zone of each surface triangle (the one holding its three gridpoints) and the area of
    // the surface it carries.
    const index_t z0 = mesh.block_zone_offsets[at(b)], z1 = mesh.block_zone_offsets[at(b) + 1];
    zone_area.assign(at(z1 - z0), 0.0);
    for (index_t f = tess.first_face(b); f < tess.end_face(b); ++f)
      for (index_t t = mesh.face_triangle_offsets[at(f)]; t < mesh.face_triangle_offsets[at(f) + 1]; ++t) {
        const auto& tri = mesh.face_triangles[at(t)];
        index_t found = invalid_index;
        for (index_t z = z0; z < z1 && found == invalid_index; ++z) {
          const auto& zn = zones_[at(z)];
          const auto has = [&](index_t g) { return std::find(zn.begin(), zn.end(), g) != zn.end(); };
          if (has(tri[0]) && has(tri[1]) && has(tri[2])) found = z;
        }
        require<geometry_error>(found != invalid_index, "detected_contacts: surface triangle ", t, " of block ", b,
                                " belongs to none of its zones");
        const vec3 x0 = reference_.row(tri[0]).transpose();
        zone_area[at(found - z0)] += 0.5 * (vec3(reference_.row(tri[1]).transpose()) - x0)
                                               .cross(vec3(reference_.row(tri[2]).transpose()) - x0)
                                               .norm();
      }
    bd.zone_begin = static_cast<index_t>(surface_zones_.size());
    for (index_t z = z0; z < z1; ++z)
      if (zone_area[at(z - z0)] > 0) {
        surface_zones_.push_back(z);
        for (index_t g : zones_[at(z)]) {
          around[at(g)] += zone_area[at(z - z0)];
          on_surface[at(g)] = 1;
        }
      }
    bd.zone_end = static_cast<index_t>(surface_zones_.size());
    require<geometry_error>(bd.zone_end > bd.zone_begin, "detected_contacts: block ", b, " has no surface zones");
  }
  // Gridpoint g carries its own gridpoint sub-contacts (area own) and the material points that
  // land in its surface zones (at most the surface they carry, plus the largest tributary area
  // of a gridpoint or corner straddling their edge, on either side): 4 k_row x that area.
  gridpoint_bound_.assign(at(gridpoint_count_), 0.0);
  for (index_t g = 0; g < gridpoint_count_; ++g)
    if (on_surface[at(g)] != 0) gridpoint_bound_[at(g)] = 4 * row_max * (own[at(g)] + 2 * around[at(g)] + 2 * a_max);
}

/// Deformable blocks: the surface zone of block b holding x (the largest smallest barycentric
/// weight, so a point just outside the surface takes the zone below it) and x's weights in it.
template <law::ContactLaw Law>
inline void detected_contacts<Law>::locate(index_t b, const vec3& x, const node_set* gp, std::array<index_t, 4>& nodes,
                                           std::array<real, 4>& w) const {
  const block_data& bd = blocks_[at(b)];
  real best = -std::numeric_limits<real>::infinity();
  for (index_t s = bd.zone_begin; s < bd.zone_end; ++s) {
    const auto& zn = zones_[at(surface_zones_[at(s)])];
    const vec3 x0 = position(zn[0], gp);
    mat3 d;
    d << position(zn[1], gp) - x0, position(zn[2], gp) - x0, position(zn[3], gp) - x0;
    const vec3 l = d.inverse() * (x - x0);
    const real smallest = std::min({1 - l.sum(), l.x(), l.y(), l.z()});
    if (smallest > best) {
      best = smallest;
      nodes = zn;
      w = {1 - l.sum(), l.x(), l.y(), l.z()};
    }
  }
}

/// Deformable blocks: the gridpoints and weights of sub-contact i of pair (a, b): a gridpoint
/// sub-contact is its own gridpoint on its side and located in the other block's zones; a corner
/// is located in both.
template <law::ContactLaw Law>
inline void detected_contacts<Law>::place_zoned(std::size_t i, index_t a, index_t b, const node_set* gp) {
  std::array<index_t, 4> na{}, nb{};
  std::array<real, 4> wa{}, wb{};
  const std::uint64_t label = key_label_[i];
  const bool node = detail::is_node_label(label);
  const bool node_side_b = node && detail::node_label_side_b(label);
  const auto own = [&](std::array<index_t, 4>& nodes, std::array<real, 4>& w) {
    nodes = {detail::node_label_gridpoint(label), invalid_index, invalid_index, invalid_index};
    w = {1, 0, 0, 0};
  };
  if (node && !node_side_b)
    own(na, wa);
  else
    locate(a, new_point_[i], gp, na, wa);
  if (node && node_side_b)
    own(nb, wb);
  else
    locate(b, new_point_[i], gp, nb, wb);
  for (int k = 0; k < 4; ++k) {
    node_[at(k)][i] = na[at(k)];
    node_[at(4 + k)][i] = nb[at(k)];
    weight_[at(k)][i] = wa[at(k)];
    weight_[at(4 + k)][i] = wb[at(k)];
  }
}

/// Deformable blocks at a rebuild: a block is detected by its affine fit (the frame's map of its
/// reference shape, poses_' rotation and shift this rebuild); how far its surface gridpoints are
/// from it, into max_deviation_. Throws geometry_error past max_deviation_fraction x the tolerance.
template <law::ContactLaw Law>
inline void detected_contacts<Law>::check_affine_fit(const node_set* gp) {
  real deviation = 0;
  for (std::size_t b = 0; b < blocks_.size(); ++b)
    for (index_t w = blocks_[b].watch_begin; w < blocks_[b].watch_end; ++w) {
      const index_t g = watch_gridpoints_[at(w)];
      const vec3 fit = poses_.block_rot[b] * reference_.row(g).transpose() + poses_.block_shift[b];
      deviation = std::max(deviation, (position(g, gp) - fit).norm());
    }
  require<geometry_error>(deviation <= max_deviation_fraction * options_.tolerance,
                          "detected_contacts: a deformable block's surface lies ", deviation,
                          " m from its affine fit, more than ", max_deviation_fraction,
                          " x the contact tolerance (", options_.tolerance,
                          " m); detection reads the fit, so raise the tolerance (or stiffen the blocks)");
  max_deviation_ = deviation;
}

/// Deformable blocks, polygon patch of pair k: the surface gridpoints on A's faces that face the
/// plane (within parallel_cos) and lie inside the patch, and those on B's; keeps in
/// node_scratch_, sorted by label, the side whose tributary areas (block_mesh::face_node_area)
/// fit the patch area (below), each with its area scaled and its gap to the other block. false
/// (the patch keeps its corners) when the side has fewer than three.
template <law::ContactLaw Law>
inline bool detected_contacts<Law>::collect_nodes(std::size_t k, const node_set* gp) {
  const vec3 n = result_.planes[k].normal;
  const vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
  const auto first = at(result_.first_corner[k]), last = at(result_.first_corner[k + 1]);
  using point2 = Eigen::Matrix<real, 2, 1>;
  polygon_.clear();
  point2 centre = point2::Zero();
  for (std::size_t j = first; j < last; ++j) {
    polygon_.emplace_back(t1.dot(result_.point[j]), t2.dot(result_.point[j]));
    centre += polygon_.back();
  }
  centre /= static_cast<real>(polygon_.size());
  std::sort(polygon_.begin(), polygon_.end(), [&](const point2& p, const point2& q) {
    return std::atan2(p.y() - centre.y(), p.x() - centre.x()) < std::atan2(q.y() - centre.y(), q.x() - centre.x());
  });
  real extent = 0;
  for (const point2& p : polygon_) extent = std::max(extent, (p - centre).norm());
  // A gridpoint counts when it lies within half the tolerance of the patch: the patch comes
  // from the affine fits, from which a face's own gridpoints (its edge ones among them) may
  // stand off by max_deviation_.
  const real eps = std::max(1e-6 * extent, 0.5 * options_.tolerance);
  const auto inside = [&](const point2& q) {
    for (std::size_t e = 0; e < polygon_.size(); ++e) {
      const point2& p0 = polygon_[e];
      const point2& p1 = polygon_[(e + 1) % polygon_.size()];
      const real cross = (p1.x() - p0.x()) * (q.y() - p0.y()) - (p1.y() - p0.y()) * (q.x() - p0.x());
      if (cross < -eps * (p1 - p0).norm()) return false;  // farther than eps outside edge e
    }
    return true;
  };
  const index_t a = result_.pairs[k].a, b = result_.pairs[k].b;
  std::array<std::vector<node_contact>*, 2> found{&node_scratch_, &node_other_};
  for (int side = 0; side < 2; ++side) {
    std::vector<node_contact>& out = *found[at(side)];
    out.clear();
    const index_t self = side == 0 ? a : b, other = side == 0 ? b : a;
    const real sign = side == 0 ? 1.0 : -1.0;
    // The other block's extreme along -sign n: its face that the patch lies on.
    const real support = side == 0 ? detection::detail::support_min(current_[at(other)], n)
                                   : detection::detail::support_max(current_[at(other)], n);
    const auto faces = workspace_.faces_of(at(self));  // this pass's face planes
    for (index_t f = 0; f < static_cast<index_t>(faces.size()); ++f) {
      if (sign * faces[at(f)].normal.dot(n) <= parallel_cos) continue;
      const index_t tf = blocks_[at(self)].face_begin + f;
      for (index_t e = face_node_offsets_[at(tf)]; e < face_node_offsets_[at(tf) + 1]; ++e) {
        const index_t g = face_nodes_[at(e)];
        const vec3 x = position(g, gp);
        if (!inside(point2(t1.dot(x), t2.dot(x)))) continue;
        out.push_back({detail::node_label(g, side == 1), g, face_node_area_[at(e)], sign * (support - n.dot(x))});
      }
    }
  }
  // The side whose gridpoints' tributary areas cover the patch best: the face that lies inside
  // the other (a small block on a large one) has areas summing to the patch's, while the large
  // face's gridpoints on the patch edge carry areas reaching beyond it. A side needs three
  // gridpoints; on a tie, A. Its areas are then scaled to sum to the patch's area.
  real patch_area = 0;
  for (std::size_t e = 0; e < polygon_.size(); ++e) {
    const point2& p0 = polygon_[e];
    const point2& p1 = polygon_[(e + 1) % polygon_.size()];
    patch_area += 0.5 * (p0.x() * p1.y() - p1.x() * p0.y());
  }
  const auto misfit = [&](const std::vector<node_contact>& side) {
    if (side.size() < 3) return std::numeric_limits<real>::infinity();
    real sum = 0;
    for (const node_contact& c : side) sum += c.area;
    return std::abs(sum - patch_area);
  };
  // Keep the side the pair used at the last rebuild while it still fits within 5 % of the patch
  // area of the other: on coinciding faces both sides fit to round-off, and a flip would drop
  // every sub-contact's state (a bonded face would come back unbonded). Else the better fit,
  // A unless B is better by more than round-off.
  const real fit_a = misfit(node_scratch_), fit_b = misfit(node_other_), slack = 0.05 * patch_area;
  const int previous = detail::previous_node_side(pair_a_, pair_b_, pair_first_, key_label_, a, b);
  const bool use_b = previous == 1 && std::isfinite(fit_b)   ? fit_b <= fit_a + slack
                     : previous == 0 && std::isfinite(fit_a) ? fit_a > fit_b + slack
                                                             : fit_b < fit_a - 1e-9 * patch_area;
  if (use_b) node_scratch_.swap(node_other_);
  if (node_scratch_.size() < 3 || !(patch_area > 0)) return false;
  real covered = 0;
  for (const node_contact& c : node_scratch_) covered += c.area;
  for (node_contact& c : node_scratch_) c.area *= patch_area / covered;
  std::sort(node_scratch_.begin(), node_scratch_.end(),
            [](const node_contact& x, const node_contact& y) { return x.label < y.label; });
  // A gridpoint on two faces that both face the plane cannot occur (convex, parallel_cos), but
  // keep labels unique whatever the input.
  node_scratch_.erase(std::unique(node_scratch_.begin(), node_scratch_.end(),
                                  [](const node_contact& x, const node_contact& y) { return x.label == y.label; }),
                      node_scratch_.end());
  return true;
}

}  // namespace tessera::contact
