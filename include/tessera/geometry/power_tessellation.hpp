#pragma once
// Voronoi and Laguerre (power) tessellations of a box by given generators (voronoi.hpp states the
// method): the cells of power_cells.hpp, optional Lloyd relaxation, the cleanup of cleanup.hpp
// that welds them into a conforming tessellation, and the optional regularization of
// regularize.hpp.
//
// Cost and determinism: see voronoi.hpp. Thread safety: the free functions may be called
// concurrently.

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "cleanup.hpp"
#include "convex_polyhedron.hpp"
#include "power_cells.hpp"
#include "regularize.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

/// Options of the Voronoi and power tessellations (each checked where used, invalid_input naming it)
struct tessellation_options {
  /// Lloyd relaxation steps: each moves every generator to the centroid of its cell, which
  /// makes cell sizes more uniform (0 = plain random tessellation).
  int lloyd_iterations = 0;
  /// Minimum distance between random generators (m); 0 = none (Poisson process).
  real min_spacing = 0;
  /// Weld tolerance relative to the mean cell size (V_box / N)^(1/3); see cleanup.hpp.
  real cleanup_tolerance = 1e-9;
  /// Regularization: edges shorter than min_edge_rel x the mean cell size are collapsed
  /// (geometry/regularize.hpp; 0 = off; the examples take it as --regularize, default 0, and the
  /// regularised runs of the examples use presets::study_regularization).
  real min_edge_rel = 0;
};

namespace detail {

TESSERA_INLINE tessellation power_tessellation(const aabb& box, std::span<const vec3> seeds_in, std::span<const real> weights,
                                               const tessellation_options& options, const char* who);

}  // namespace detail

/// Voronoi tessellation of `box` by the generators `seeds` (m), after options.lloyd_iterations
/// Lloyd steps (the returned tessellation stores the relaxed generators). Throws invalid_input
/// for an empty or non-finite box, no seeds, a seed outside the box or coincident seeds.
[[nodiscard]] inline tessellation voronoi(const aabb& box, std::span<const vec3> seeds,
                                          const tessellation_options& options = {}) {
  return detail::power_tessellation(box, seeds, {}, options, "voronoi");
}

/// Laguerre (power) tessellation: generator i has weight weights[i] (m^2); a larger weight
/// grows the cell (the bisector with j moves by (w_i - w_j)/(2 d) toward j). Generators whose
/// cell is empty are dropped (the tessellation then has fewer cells than seeds; `seeds` and
/// `weights` of the result list the surviving generators). Throws invalid_input as voronoi(),
/// and for a weight count different from the seed count or a non-finite weight.
[[nodiscard]] inline tessellation laguerre(const aabb& box, std::span<const vec3> seeds, std::span<const real> weights,
                                           const tessellation_options& options = {}) {
  require(weights.size() == seeds.size(), "laguerre: ", weights.size(), " weights for ", seeds.size(),
          " seeds; one weight (m^2) per seed is required");
  for (std::size_t i = 0; i < weights.size(); ++i)
    require(std::isfinite(weights[i]), "laguerre: weight ", i, " = ", weights[i], " m^2 must be finite");
  return detail::power_tessellation(box, seeds, weights, options, "laguerre");
}

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/power_tessellation.ipp"
#endif
