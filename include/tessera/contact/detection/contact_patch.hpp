#pragma once
// The contact patch of two convex polyhedra on their contact plane (contact_plane.hpp), the second
// half of the narrow phase of contact detection: the corners from which a detecting contact set
// makes its vertex sub-contacts, with their gaps, tributary areas and labels.
//
// Contact patch (contact_patch). The vertices of A within `tolerance` of A's supporting plane
// (n.x >= max_A - tolerance) and those of B within it of B's (n.x <= min_B + tolerance) are
// projected on the contact plane; their convex hulls are intersected. The patch is a polygon
// (face-face contact), a segment (edge-face or parallel edges) or a point (vertex-face, crossing
// edges); its corners are the sub-contact points. Per corner: the normal gap along n between the
// surfaces of A and B through it (exact for planar faces: the exit of the line from A and its
// entry into B, from the face planes), and the tributary area (a polygon's area split between
// its corners through the mean of its corners: half of each of the two triangles (mean, corner,
// neighbour) at the corner, >= 0 however thin the polygon; zero for a segment or point, for
// which the caller supplies a nominal area: see docs/model.md). `tolerance` is the contact tolerance of 3DEC (the band in which a
// vertex counts as touching); it must exceed the tilt of nearly parallel faces over their size,
// else they read as an edge contact. A vertex of a neighbouring face that lies within the band
// joins the patch too, so a corner's gap can exceed the plane's by up to one tolerance per block
// (such a corner carries force only once it closes); no corner's gap is below the plane's.
//
// Cost: contact_patch_of O(V_A + V_B + F_A + F_B) per pair and O(V_A + V_B + the faces facing
// along n) per corner; contact_patch_into allocates nothing once its output's and its thread's
// scratch (the touching points and their hulls) have grown. A pure function of its inputs:
// deterministic, thread-safe.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "../../core/separate_compilation.hpp"
#include "../../core/errors.hpp"
#include "../../core/types.hpp"
#include "../../geometry/convex_polyhedron.hpp"
#include "contact_plane.hpp"

namespace tessera::contact::detection {

/// Dimension of a contact patch.
enum class patch_type : std::uint8_t { none, point, segment, polygon };

/// The contact patch of a pair on its contact plane (see the file comment).
struct contact_patch {
  patch_type type = patch_type::none;  ///< point, segment or polygon (none: no contact)
  std::vector<vec3> points;  ///< corners on the contact plane (CCW about the normal for a polygon)
  std::vector<real> gap;     ///< normal gap B - A through each corner (m; < 0 overlapping)
  std::vector<real> area;    ///< tributary area of each corner (m^2; 0 for a segment or point)
  /// What each corner is, as a corner_label: a vertex of A, a vertex of B, or the crossing of an
  /// edge of A's touching hull with one of B's (vertex ids local to each polyhedron). A corner
  /// keeps its label while the blocks move, so a detecting set keys its law state by it.
  std::vector<std::uint64_t> label;
  real total_area = 0;       ///< area of the polygon (m^2)
  /// No contact (type none, no corners); the vectors keep their capacity.
  void clear() {
    type = patch_type::none;
    points.clear();
    gap.clear();
    area.clear();
    label.clear();
    total_area = 0;
  }
};

/// Labels of patch corners (contact_patch::label): the top two bits give the kind, the rest the
/// vertex ids (15 bits each, so a polyhedron may have up to 32 767 vertices).
namespace corner_label {
inline constexpr int id_bits = 15;  ///< bits per vertex id
inline constexpr index_t max_vertices = (index_t{1} << id_bits) - 1;  ///< largest vertex id a label holds
/** a vertex of A, a vertex of B, or an edge crossing */ enum class kind : std::uint64_t { vertex_a = 0, vertex_b = 1, crossing = 2 };
[[nodiscard]] constexpr std::uint64_t vertex_a(index_t v) noexcept { return static_cast<std::uint64_t>(v); }  ///< Label of vertex v of A
[[nodiscard]] constexpr std::uint64_t vertex_b(index_t v) noexcept {  ///< Label of vertex v of B
  return (std::uint64_t{1} << 62) | static_cast<std::uint64_t>(v);
}
/// Crossing of A's hull edge (a0, a1) with B's (b0, b1); each edge's ids in increasing order.
[[nodiscard]] constexpr std::uint64_t crossing(index_t a0, index_t a1, index_t b0, index_t b1) noexcept {
  const auto u = static_cast<std::uint64_t>(std::min(a0, a1)), v = static_cast<std::uint64_t>(std::max(a0, a1));
  const auto x = static_cast<std::uint64_t>(std::min(b0, b1)), y = static_cast<std::uint64_t>(std::max(b0, b1));
  return (std::uint64_t{2} << 62) | (u << 45) | (v << 30) | (x << 15) | y;
}
[[nodiscard]] constexpr kind kind_of(std::uint64_t label) noexcept { return static_cast<kind>(label >> 62); }  ///< The kind of a label
}  // namespace corner_label

/// The contact patch of A and B on `plane` (common_plane's result), with vertices within
/// `tolerance` (m, > 0) of either block's supporting plane counted as touching, written into `out`
/// (its vectors keep their capacity: a detection pass reuses each slot's). An empty patch (type
/// none) when the touching sets do not overlap on the plane. `faces_a`, `faces_b`: the blocks'
/// face planes (append_face_planes); a list of another size is refused. Its scratch (the touching
/// points, their hulls) is the calling thread's own, kept between calls.
TESSERA_INLINE void contact_patch_into(const geometry::convex_polyhedron& a, const geometry::convex_polyhedron& b,
                                       const contact_plane& plane, real tolerance, std::span<const geometry::plane> faces_a,
                                       std::span<const geometry::plane> faces_b, contact_patch& out);

/// The contact patch of A and B (contact_patch_into), returned.
[[nodiscard]] inline contact_patch contact_patch_of(const geometry::convex_polyhedron& a, const geometry::convex_polyhedron& b,
                                                    const contact_plane& plane, real tolerance,
                                                    std::span<const geometry::plane> faces_a,
                                                    std::span<const geometry::plane> faces_b) {
  contact_patch out;
  contact_patch_into(a, b, plane, tolerance, faces_a, faces_b, out);
  return out;
}

/// Overload that computes the face planes (for one-off queries and tests).
[[nodiscard]] inline contact_patch contact_patch_of(const geometry::convex_polyhedron& a, const geometry::convex_polyhedron& b,
                                                    const contact_plane& plane, real tolerance) {
  std::vector<geometry::plane> faces_a, faces_b;
  append_face_planes(a, faces_a);
  append_face_planes(b, faces_b);
  return contact_patch_of(a, b, plane, tolerance, faces_a, faces_b);
}

}  // namespace tessera::contact::detection

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/contact_patch.ipp"
#endif
