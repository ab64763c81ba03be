// The definitions of the larger functions that geometry/domain_tessellation.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../domain_tessellation.hpp"

namespace tessera::geometry {
namespace detail {

TESSERA_INLINE tessellation domain_tessellation(const convex_polyhedron& domain_in, std::span<const vec3> seeds_in,
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
}  // namespace tessera::geometry
