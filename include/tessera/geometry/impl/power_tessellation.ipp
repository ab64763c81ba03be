// The definitions of the larger functions that geometry/power_tessellation.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../power_tessellation.hpp"

namespace tessera::geometry {
namespace detail {

TESSERA_INLINE tessellation power_tessellation(const aabb& box, std::span<const vec3> seeds_in, std::span<const real> weights,
                                               const tessellation_options& options, const char* who) {
  require_valid_box(box, who);
  require(!seeds_in.empty(), who, ": no seeds (N = 0); at least one cell is required");
  require(options.lloyd_iterations >= 0, who, ": lloyd_iterations = ", options.lloyd_iterations, " must be >= 0");
  require(std::isfinite(options.cleanup_tolerance) && options.cleanup_tolerance > 0 && options.cleanup_tolerance < 1e-2,
          who, ": cleanup_tolerance = ", options.cleanup_tolerance, " must be in (0, 1e-2)");
  std::vector<vec3> seeds(seeds_in.begin(), seeds_in.end());
  const real mean_size = std::cbrt(box.volume() / static_cast<real>(seeds.size()));
  for (int it = 0;; ++it) {
    const seed_grid grid(box, seeds, 2.0);
    validate_seeds(box, seeds, grid, who);
    std::vector<convex_polyhedron> cells = compute_cells(box, seeds, weights, grid);
    if (it == options.lloyd_iterations) {
      tessellation t = assemble_tessellation(box, cells, seeds, weights, options.cleanup_tolerance * mean_size);
      if (options.min_edge_rel != 0) regularize(t, options.min_edge_rel);  // throws for < 0, > 0.5, NaN
      return t;
    }
    // Lloyd step: x_i <- centroid of C_i (an empty Laguerre cell keeps its generator).
    parallel_for(static_cast<std::int64_t>(seeds.size()), [&](std::int64_t c) {
      const convex_polyhedron& p = cells[static_cast<std::size_t>(c)];
      if (!p.empty()) seeds[static_cast<std::size_t>(c)] = p.centroid().cwiseMax(box.lo).cwiseMin(box.hi);
    }, 64);
  }
}

}  // namespace detail
}  // namespace tessera::geometry
