#pragma once
// Voronoi tessellation of a convex polyhedral domain (a disc as cylinder_prism, a slab as prism,
// any convex_polyhedron): every cell starts from the domain instead of its bounding box (power
// cells of power_cells.hpp), and the cells are welded by the cleanup of cleanup.hpp. A face on
// domain face k is tagged boundary_tag(6 + k).
//
// Cost and determinism: see voronoi.hpp. Thread safety: the free functions may be called
// concurrently.

#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "cleanup.hpp"
#include "convex_polyhedron.hpp"
#include "power_cells.hpp"
#include "power_tessellation.hpp"
#include "predicates.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

namespace detail {

/// Voronoi tessellation of a convex polyhedral domain: as power_tessellation, every cell starting
/// from the domain instead of its bounding box. The cleanup does not recompute ill-conditioned
/// vertices (cleanup.hpp's recompute knows box sides only; it acts on generators within 1e-9 of
/// the cell size of each other, which random seeds practically never are) and no regularization
/// is applied (it keeps vertices on box sides only).
TESSERA_INLINE tessellation domain_tessellation(const convex_polyhedron& domain_in, std::span<const vec3> seeds_in,
                                                const tessellation_options& options, const char* who);

}  // namespace detail

/// Voronoi tessellation of the convex polyhedral domain `domain` (m; e.g. cylinder_prism for a
/// disc, prism for a slab of any convex outline, convex_polyhedron::from_vertices) by the
/// generators `seeds` (m), after options.lloyd_iterations Lloyd steps. Each cell is computed as
/// for a box, starting from the domain instead of the box, and the cells are welded by the same
/// cleanup (cleanup.hpp), so the result is conforming (check(): no unmatched faces, no open or
/// non-convex cells) and can be zoned by zone_blocks. Differences from the box overload:
///  - tessellation::domain is the domain's bounding box; the cell volumes sum to the
///    polyhedron's volume(), not the box's, so check()'s volume_error_rel there is the box's
///    excess over the domain, not an error;
///  - a face on domain face k has face_neighbor = boundary_tag(6 + k) (boundary_side = 6 + k);
///  - options.min_edge_rel must be 0 (regularization keeps vertices on box sides only).
/// Throws invalid_input for an empty or flat domain, no seeds, a seed outside the domain,
/// coincident seeds or min_edge_rel != 0; geometry_error when a cell degenerates below the weld
/// tolerance.
[[nodiscard]] inline tessellation voronoi(const convex_polyhedron& domain, std::span<const vec3> seeds,
                                          const tessellation_options& options = {}) {
  return detail::domain_tessellation(domain, seeds, options, "voronoi");
}

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/domain_tessellation.ipp"
#endif
