#pragma once
// Random Voronoi and Laguerre (power) tessellations of a box into convex polyhedral cells: the
// blocks of a scene (the reference study used Neper for the same purpose). Voronoi
// tessellations of any convex polyhedral domain (a disc as cylinder_prism, a slab as prism) are
// the overloads taking a convex_polyhedron.
//
// Cell i of a Laguerre tessellation with generators s_j and weights w_j (m^2) is
//     C_i = { x in box : |x - s_i|^2 - w_i <= |x - s_j|^2 - w_j  for all j },
// and a Voronoi tessellation is the case w = 0. Each cell is computed independently, Voro++
// style: start from the box, clip with the power plane of each nearby generator (geometry::
// power_plane) in order of increasing distance, found through a uniform bin grid searched in
// shells, and stop once no farther generator can cut: with R the largest distance from s_i to
// a vertex of the current cell, a generator at distance d cuts only if
//     d < R + sqrt(R^2 - w_i + w_max)      (= 2 R for Voronoi),
// the "security radius". The cells are then welded into a conforming tessellation by
// geometry::assemble_tessellation (cleanup.hpp, which documents the degenerate-geometry policy).
//
// Determinism: cells are computed with parallel_for, each writing only its own output; welding
// and numbering are serial in cell order. The result is bit-identical for any thread count and,
// with random_seeds, for a fixed rng seed on any platform (std::mt19937_64 is fully specified;
// the uniform mapping is our own, not std::uniform_real_distribution).
//
// Cost: O(N) expected for uniformly spread generators (a few tens of clips per cell); 100 000
// cells of a unit cube take 2.6-3.7 s of single-thread CPU time, about 75 % of it in the
// parallel cell computation (benchmarks/bench_tessellation.cpp).
// Thread safety: the free functions may be called concurrently.
//
// Where each job lives: the random generators in random_seeds.hpp, the cell of one generator in
// power_cells.hpp, the tessellation of a box by given generators (voronoi, laguerre) in
// power_tessellation.hpp, of a convex domain in domain_tessellation.hpp; this header draws random
// generators and tessellates with them (random_voronoi).

#include <cstdint>
#include <vector>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "convex_polyhedron.hpp"
#include "domain_tessellation.hpp"
#include "power_tessellation.hpp"
#include "random_seeds.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

/// Voronoi tessellation of n random generators (random_seeds with options.min_spacing) followed
/// by options.lloyd_iterations Lloyd steps. The generators are numbered along a Morton curve of
/// the box (cell i has generator tessellation::seeds[i]), so neighbouring cells have nearby ids. The same (box, n, rng_seed, options) always gives
/// the same tessellation, bit for bit, for any thread count.
[[nodiscard]] inline tessellation random_voronoi(const aabb& box, index_t n, std::uint64_t rng_seed,
                                                 const tessellation_options& options = {}) {
  require(n > 0, "random_voronoi: number of cells N = ", n, " must be > 0");
  std::vector<vec3> seeds = random_seeds(box, n, rng_seed, options.min_spacing);
  detail::sort_along_morton_curve(box, seeds);
  return detail::power_tessellation(box, seeds, {}, options, "random_voronoi");
}

/// Voronoi tessellation of n random generators uniformly distributed inside the convex
/// polyhedral domain `domain` (random_seeds(domain, n, rng_seed, options.min_spacing)), numbered
/// along a Morton curve of its bounding box, then voronoi(domain, seeds, options). The cell
/// volumes sum to domain.volume() up to rounding. The same (domain, n, rng_seed, options) always
/// gives the same tessellation, bit for bit, for any thread count.
[[nodiscard]] inline tessellation random_voronoi(const convex_polyhedron& domain, index_t n, std::uint64_t rng_seed,
                                                 const tessellation_options& options = {}) {
  require(n > 0, "random_voronoi: number of cells N = ", n, " must be > 0");
  std::vector<vec3> seeds = random_seeds(domain, n, rng_seed, options.min_spacing);
  detail::sort_along_morton_curve(domain.bounds(), seeds);
  return detail::domain_tessellation(domain, seeds, options, "random_voronoi");
}

}  // namespace tessera::geometry
