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
inline tessellation domain_tessellation(const convex_polyhedron& domain_in, std::span<const vec3> seeds_in,
                                        const tessellation_options& options, const char* who) {
  const convex_polyhedron domain = tagged_domain(domain_in, who);
  require(!seeds_in.empty(), who, ": no seeds (N = 0); at least one cell is required");
  require(options.lloyd_iterations >= 0, who, ": lloyd_iterations = ", options.lloyd_iterations, " must be >= 0");
  require(std::isfinite(options.cleanup_tolerance) && options.cleanup_tolerance > 0 && options.cleanup_tolerance < 1e-2,
          who, ": cleanup_tolerance = ", options.cleanup_tolerance, " must be in (0, 1e-2)");
  require(options.min_edge_rel == 0, who, ": min_edge_rel = ", options.min_edge_rel,
          "; regularization (regularize.hpp) keeps vertices on the sides of a box only, so a tessellation of a ",
          "convex_polyhedron domain takes 0");
  const aabb box = domain.bounds();
  const real on_tol = plane_tolerance_rel * domain.extent();
  for (std::size_t s = 0; s < seeds_in.size(); ++s) {
    const vec3& p = seeds_in[s];
    require(p.allFinite() && domain.contains(p, on_tol), who, ": seed ", s, " at (", p.x(), ", ", p.y(), ", ", p.z(),
            ") m lies outside the domain (a convex polyhedron of ", domain.face_count(), " faces)");
  }
  std::vector<vec3> seeds(seeds_in.begin(), seeds_in.end());
  const real mean_size = std::cbrt(domain.volume() / static_cast<real>(seeds.size()));
  for (int it = 0;; ++it) {
    const seed_grid grid(box, seeds, 2.0);
    validate_seeds(box, seeds, grid, who);
    std::vector<convex_polyhedron> cells = compute_cells(box, seeds, {}, grid, &domain);
    if (it == options.lloyd_iterations) {
      // no seeds passed: see the comment above (the recompute would read boundary tags >= 6 as box sides)
      tessellation t = assemble_tessellation(box, cells, {}, {}, options.cleanup_tolerance * mean_size);
      require<geometry_error>(t.cell_count() == static_cast<index_t>(seeds.size()), who, ": ",
                              static_cast<index_t>(seeds.size()) - t.cell_count(),
                              " cells degenerated below the weld tolerance ", options.cleanup_tolerance * mean_size,
                              " m; move their seeds away from the domain's boundary or change the rng seed");
      t.seeds = std::move(seeds);
      return t;
    }
    // Lloyd step: the centroid of a cell lies in the convex domain.
    parallel_for(static_cast<std::int64_t>(seeds.size()), [&](std::int64_t c) {
      const convex_polyhedron& p = cells[static_cast<std::size_t>(c)];
      if (!p.empty()) seeds[static_cast<std::size_t>(c)] = p.centroid();
    }, 64);
  }
}

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
