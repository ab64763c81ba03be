#pragma once
// Random generators of a tessellation: uniform in a box or in a convex polyhedral domain, with an
// optional minimum spacing (random sequential addition), reproducible bit for bit on every
// platform (std::mt19937_64 is fully specified; the uniform mapping is our own, not
// std::uniform_real_distribution); and their order along a Morton curve, so that cells close in
// space are close in memory.
//
// Cost: O(n) expected draws without a spacing; with one, each draw checks the 27 bins around it.
// Thread safety: pure functions.

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "convex_polyhedron.hpp"
#include "power_cells.hpp"
#include "predicates.hpp"

namespace tessera::geometry {

namespace detail {

/// Uniform real in [0, 1) from the 53 high bits of one mt19937_64 draw (platform independent).
[[nodiscard]] inline real uniform01(std::mt19937_64& rng) {
  return static_cast<real>(rng() >> 11) * 0x1.0p-53;
}

/// Interleaves the low 21 bits of x with two zero bits between consecutive bits.
[[nodiscard]] inline std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

/// Reorders points along a Morton (Z-order) curve of the box, ties kept in input order, so that
/// cells close in space are close in memory (cache locality of the tessellation and of every
/// later loop over blocks and contacts).
TESSERA_INLINE void sort_along_morton_curve(const aabb& box, std::vector<vec3>& points);

/// Uniform draws in `box` from std::mt19937_64(rng_seed), kept when `accept(p)` and, with
/// min_spacing > 0 (m), farther than min_spacing from every kept point (random sequential
/// addition). Throws invalid_input when n points are not placed in 1000 n + 100 000 draws.
template <class Accept>
[[nodiscard]] std::vector<vec3> random_points(const aabb& box, index_t n, std::uint64_t rng_seed, real min_spacing,
                                              Accept&& accept, const char* who) {
  std::mt19937_64 rng(rng_seed);
  const vec3 size = box.size();
  auto draw = [&] {
    vec3 p;
    for (int a = 0; a < 3; ++a) p[a] = std::min(box.lo[a] + uniform01(rng) * size[a], box.hi[a]);
    return p;
  };
  std::vector<vec3> seeds;
  seeds.reserve(static_cast<std::size_t>(n));
  const std::int64_t max_attempts = 1000 * static_cast<std::int64_t>(n) + 100000;
  std::int64_t attempts = 0;
  if (min_spacing == 0) {
    while (static_cast<index_t>(seeds.size()) < n) {
      require(++attempts <= max_attempts, who, ": placed only ", seeds.size(), " of ", n, " seeds inside the domain after ",
              max_attempts, " draws in its bounding box of (", size.x(), ", ", size.y(), ", ", size.z(), ") m");
      const vec3 p = draw();
      if (accept(p)) seeds.push_back(p);
    }
    return seeds;
  }
  // Bins no smaller than min_spacing: a conflicting generator is in the 27 surrounding bins.
  std::array<int, 3> nb{};
  for (int a = 0; a < 3; ++a)
    nb[static_cast<std::size_t>(a)] = static_cast<int>(std::clamp<real>(std::floor(size[a] / min_spacing), 1, 512));
  std::vector<std::vector<index_t>> bins(static_cast<std::size_t>(nb[0]) * static_cast<std::size_t>(nb[1]) *
                                       static_cast<std::size_t>(nb[2]));
  auto coord = [&](const vec3& p, int a) {
    return std::clamp(static_cast<int>((p[a] - box.lo[a]) / size[a] * nb[static_cast<std::size_t>(a)]), 0,
                      nb[static_cast<std::size_t>(a)] - 1);
  };
  while (static_cast<index_t>(seeds.size()) < n) {
    require(++attempts <= max_attempts, who, ": placed only ", seeds.size(), " of ", n,
            " seeds with min_spacing = ", min_spacing, " m in a box of (", size.x(), ", ", size.y(), ", ", size.z(),
            ") m after ", max_attempts, " attempts; lower min_spacing or N");
    const vec3 p = draw();
    if (!accept(p)) continue;
    const int ci = coord(p, 0), cj = coord(p, 1), ck = coord(p, 2);
    bool free = true;
    for (int k = std::max(0, ck - 1); free && k <= std::min(nb[2] - 1, ck + 1); ++k)
      for (int j = std::max(0, cj - 1); free && j <= std::min(nb[1] - 1, cj + 1); ++j)
        for (int i = std::max(0, ci - 1); free && i <= std::min(nb[0] - 1, ci + 1); ++i)
          for (index_t o : bins[static_cast<std::size_t>(i + nb[0] * (j + nb[1] * k))])
            if ((seeds[static_cast<std::size_t>(o)] - p).squaredNorm() < min_spacing * min_spacing) {
              free = false;
              break;
            }
    if (!free) continue;
    bins[static_cast<std::size_t>(ci + nb[0] * (cj + nb[1] * ck))].push_back(static_cast<index_t>(seeds.size()));
    seeds.push_back(p);
  }
  return seeds;
}

}  // namespace detail

/// n generators uniformly distributed in `box` from std::mt19937_64(rng_seed), reproducible bit
/// for bit on every platform. With min_spacing > 0 (m), candidates closer than min_spacing to an
/// accepted generator are rejected (random sequential addition); throws invalid_input when the
/// box cannot take n generators at that spacing.
[[nodiscard]] inline std::vector<vec3> random_seeds(const aabb& box, index_t n, std::uint64_t rng_seed,
                                                    real min_spacing = 0) {
  detail::require_valid_box(box, "random_seeds");
  require(n > 0, "random_seeds: number of seeds N = ", n, " must be > 0");
  require_non_negative(min_spacing, "random_seeds: min_spacing (m)");
  return detail::random_points(box, n, rng_seed, min_spacing, [](const vec3&) { return true; }, "random_seeds");
}

/// n generators uniformly distributed inside the convex polyhedron `domain` (m): uniform draws
/// in its bounding box from std::mt19937_64(rng_seed), those outside the domain or within
/// plane_tolerance_rel of its extent from its boundary rejected, reproducible bit for bit on
/// every platform. min_spacing (m) as for a box. Throws invalid_input for an empty or flat
/// domain, n <= 0, a negative min_spacing, or when n generators cannot be placed.
[[nodiscard]] inline std::vector<vec3> random_seeds(const convex_polyhedron& domain, index_t n, std::uint64_t rng_seed,
                                                    real min_spacing = 0) {
  const convex_polyhedron checked = detail::tagged_domain(domain, "random_seeds");
  require(n > 0, "random_seeds: number of seeds N = ", n, " must be > 0");
  require_non_negative(min_spacing, "random_seeds: min_spacing (m)");
  const real margin = plane_tolerance_rel * checked.extent();
  return detail::random_points(checked.bounds(), n, rng_seed, min_spacing,
                               [&](const vec3& p) { return checked.contains(p, -margin); }, "random_seeds");
}

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/random_seeds.ipp"
#endif
