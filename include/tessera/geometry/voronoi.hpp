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

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <random>
#include <span>
#include <vector>

#include "../core/csr.hpp"
#include "../core/errors.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "cleanup.hpp"
#include "convex_polyhedron.hpp"
#include "predicates.hpp"
#include "regularize.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

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

/// Uniform real in [0, 1) from the 53 high bits of one mt19937_64 draw (platform independent).
[[nodiscard]] inline real uniform01(std::mt19937_64& rng) {
  return static_cast<real>(rng() >> 11) * 0x1.0p-53;
}

inline void require_valid_box(const aabb& box, const char* who) {
  const vec3 s = box.size();
  require(box.lo.allFinite() && box.hi.allFinite() && (s.array() > 0).all(), who, ": domain box size (", s.x(), ", ",
          s.y(), ", ", s.z(), ") m must be finite and > 0 in every direction");
}

/// Uniform bin grid over the box holding generator ids, about `per_bin` generators per bin.
struct seed_grid {
  vec3 lo, bin_size, inv_bin_size;
  std::array<int, 3> n{1, 1, 1};
  std::vector<index_t> offsets;  // CSR over bins, bin = i + n0 (j + n1 k)
  std::vector<index_t> members;

  seed_grid(const aabb& box, std::span<const vec3> seeds, real per_bin) {
    lo = box.lo;
    const vec3 size = box.size();
    const real h = std::cbrt(box.volume() * per_bin / static_cast<real>(seeds.size()));
    std::int64_t total = 1;
    for (int a = 0; a < 3; ++a) {
      n[static_cast<std::size_t>(a)] = static_cast<int>(std::clamp<real>(std::round(size[a] / h), 1, 1024));
      total *= n[static_cast<std::size_t>(a)];
    }
    for (int a = 0; a < 3; ++a) {
      bin_size[a] = size[a] / n[static_cast<std::size_t>(a)];
      inv_bin_size[a] = n[static_cast<std::size_t>(a)] / size[a];
    }
    std::vector<index_t> bin_of_seed(seeds.size());
    for (std::size_t s = 0; s < seeds.size(); ++s) {
      const auto b = coords(seeds[s]);
      bin_of_seed[s] = bin(b[0], b[1], b[2]);
    }
    auto entries = [&](auto&& emit) {
      for (std::size_t s = 0; s < seeds.size(); ++s)
        emit(bin_of_seed[s], [&](index_t slot) { members[static_cast<std::size_t>(slot)] = static_cast<index_t>(s); });
    };
    offsets = csr_offsets(static_cast<index_t>(total), entries);
    members.resize(seeds.size());
    csr_fill(offsets, entries);
  }
  [[nodiscard]] std::array<int, 3> coords(const vec3& p) const {
    std::array<int, 3> b{};
    for (int a = 0; a < 3; ++a)
      b[static_cast<std::size_t>(a)] = std::clamp(static_cast<int>(std::floor((p[a] - lo[a]) * inv_bin_size[a])), 0,
                                                  n[static_cast<std::size_t>(a)] - 1);
    return b;
  }
  [[nodiscard]] index_t bin(int i, int j, int k) const { return i + n[0] * (j + n[1] * k); }
  [[nodiscard]] std::span<const index_t> seeds_in(index_t b) const {
    return {members.data() + offsets[static_cast<std::size_t>(b)],
            static_cast<std::size_t>(offsets[static_cast<std::size_t>(b) + 1] - offsets[static_cast<std::size_t>(b)])};
  }
};

/// Checks generators: inside the box, pairwise farther apart than 1e-12 of the mean spacing.
inline void validate_seeds(const aabb& box, std::span<const vec3> seeds, const seed_grid& grid, const char* who) {
  require(!seeds.empty(), who, ": no seeds (N = 0); at least one cell is required");
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const vec3& p = seeds[s];
    require(p.allFinite() && box.contains(p), who, ": seed ", s, " at (", p.x(), ", ", p.y(), ", ", p.z(),
            ") m lies outside the domain box [(", box.lo.x(), ", ", box.lo.y(), ", ", box.lo.z(), "), (", box.hi.x(),
            ", ", box.hi.y(), ", ", box.hi.z(), ")]");
  }
  const real coincidence = plane_tolerance_rel * std::cbrt(box.volume() / static_cast<real>(seeds.size()));
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const auto b = grid.coords(seeds[s]);
    for (int k = std::max(0, b[2] - 1); k <= std::min(grid.n[2] - 1, b[2] + 1); ++k)
      for (int j = std::max(0, b[1] - 1); j <= std::min(grid.n[1] - 1, b[1] + 1); ++j)
        for (int i = std::max(0, b[0] - 1); i <= std::min(grid.n[0] - 1, b[0] + 1); ++i)
          for (index_t o : grid.seeds_in(grid.bin(i, j, k))) {
            if (o >= static_cast<index_t>(s)) continue;
            const real d = (seeds[static_cast<std::size_t>(o)] - seeds[s]).norm();
            require(d > coincidence, who, ": seeds ", o, " and ", s, " coincide at (", seeds[s].x(), ", ",
                    seeds[s].y(), ", ", seeds[s].z(), ") m (distance ", d, " m <= ", coincidence,
                    " m); their bisector plane is undefined");
          }
  }
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
inline void sort_along_morton_curve(const aabb& box, std::vector<vec3>& points) {
  std::vector<std::pair<std::uint64_t, index_t>> key(points.size());
  const vec3 size = box.size();
  for (std::size_t k = 0; k < points.size(); ++k) {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const real u = std::clamp<real>((points[k][a] - box.lo[a]) / size[a], 0, 1);
      code |= spread_bits(static_cast<std::uint64_t>(u * real(0x1fffff))) << a;
    }
    key[k] = {code, static_cast<index_t>(k)};
  }
  std::sort(key.begin(), key.end());
  std::vector<vec3> sorted(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) sorted[k] = points[static_cast<std::size_t>(key[k].second)];
  points.swap(sorted);
}

/// Per-thread scratch of the cell computation.
struct cell_workspace {
  convex_polyhedron cell;
  std::vector<std::pair<real, index_t>> candidates;  // (squared distance, generator id)
};

/// Computes the Laguerre cell of generator i into ws.cell (weights empty = Voronoi), starting from
/// the box, or from `start` (a convex domain inside the box) when it is given.
inline void compute_cell(const aabb& box, std::span<const vec3> seeds, std::span<const real> weights, real w_max,
                         const seed_grid& grid, index_t i, cell_workspace& ws,
                         const convex_polyhedron* start = nullptr) {
  // Plane-side tolerance: plane_tolerance_rel of four mean cell sizes, fixed for the whole
  // tessellation (a cell is rarely larger than that; see predicates.hpp and cleanup.hpp).
  const real clip_tolerance = 4 * plane_tolerance_rel * std::cbrt(box.volume() / static_cast<real>(seeds.size()));
  convex_polyhedron& cell = ws.cell;
  if (start != nullptr) cell = *start;
  else cell.assign_box(box.lo, box.hi);
  const vec3& s = seeds[static_cast<std::size_t>(i)];
  const real w_i = weights.empty() ? real(0) : weights[static_cast<std::size_t>(i)];
  const real w_excess = weights.empty() ? real(0) : w_max - w_i;  // >= 0
  real r = std::sqrt(cell.max_squared_distance(s));
  auto security_radius = [&] { return r + std::sqrt(std::max<real>(0, r * r + w_excess)); };
  real stop = security_radius();
  const auto b = grid.coords(s);
  // distance from s to the lower/upper wall of its own bin, per axis
  std::array<real, 3> wall{};
  for (int a = 0; a < 3; ++a) {
    const real rel = (s[a] - grid.lo[a]) - b[static_cast<std::size_t>(a)] * grid.bin_size[a];
    wall[static_cast<std::size_t>(a)] = std::max<real>(0, std::min(rel, grid.bin_size[a] - rel));
  }
  const int max_shell = std::max({grid.n[0], grid.n[1], grid.n[2]});
  for (int k = 0; k <= max_shell; ++k) {
    // Lower bound of the distance to any generator in shell k (bins at Chebyshev distance k):
    // along an axis where the shell exists it is at least (k - 1) bins plus the wall gap.
    if (k > 0) {
      real lower = std::numeric_limits<real>::infinity();
      for (int a = 0; a < 3; ++a) {
        const std::size_t ua = static_cast<std::size_t>(a);
        if (b[ua] - k >= 0 || b[ua] + k < grid.n[ua])
          lower = std::min(lower, (k - 1) * grid.bin_size[a] + wall[ua]);
      }
      if (lower >= stop) break;  // also ends the search once no shell is left in the grid
    }
    ws.candidates.clear();
    const real stop2 = stop * stop;
    for (int bk = std::max(0, b[2] - k); bk <= std::min(grid.n[2] - 1, b[2] + k); ++bk)
      for (int bj = std::max(0, b[1] - k); bj <= std::min(grid.n[1] - 1, b[1] + k); ++bj) {
        // inner rows of the shell only contribute their two end bins
        const bool full_row = std::abs(bk - b[2]) == k || std::abs(bj - b[1]) == k;
        const int step = full_row ? 1 : 2 * k;
        for (int bi = b[0] - k; bi <= b[0] + k; bi += std::max(step, 1)) {
          if (bi < 0 || bi >= grid.n[0]) continue;
          for (index_t j : grid.seeds_in(grid.bin(bi, bj, bk))) {
            const real d2 = (seeds[static_cast<std::size_t>(j)] - s).squaredNorm();
            if (j != i && d2 < stop2) ws.candidates.emplace_back(d2, j);
          }
        }
      }
    std::sort(ws.candidates.begin(), ws.candidates.end());
    for (const auto& [d2, j] : ws.candidates) {
      if (d2 >= stop * stop) break;
      const real w_j = weights.empty() ? real(0) : weights[static_cast<std::size_t>(j)];
      const plane h = power_plane(s, w_i, seeds[static_cast<std::size_t>(j)], w_j);
      if (-h.signed_distance(s) >= r) continue;  // the plane lies beyond every vertex
      if (cell.clip(h, j, clip_tolerance)) {
        if (cell.empty()) return;  // Laguerre cell swallowed by its neighbours
        r = std::sqrt(cell.max_squared_distance(s));
        stop = security_radius();
      }
    }
  }
}

/// Computes every cell in parallel; rethrows the exception of the lowest failing cell.
inline std::vector<convex_polyhedron> compute_cells(const aabb& box, std::span<const vec3> seeds,
                                                    std::span<const real> weights, const seed_grid& grid,
                                                    const convex_polyhedron* start = nullptr) {
  const real w_max = weights.empty() ? real(0) : *std::max_element(weights.begin(), weights.end());
  std::vector<convex_polyhedron> cells(seeds.size());
  std::vector<std::exception_ptr> failure(seeds.size());
  parallel_for(static_cast<std::int64_t>(seeds.size()), [&](std::int64_t c) {
    thread_local cell_workspace ws;
    try {
      compute_cell(box, seeds, weights, w_max, grid, static_cast<index_t>(c), ws, start);
      cells[static_cast<std::size_t>(c)] = ws.cell;
    } catch (...) {
      failure[static_cast<std::size_t>(c)] = std::current_exception();
    }
  }, 16);
  for (const auto& e : failure)
    if (e) std::rethrow_exception(e);
  return cells;
}

inline tessellation power_tessellation(const aabb& box, std::span<const vec3> seeds_in, std::span<const real> weights,
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

/// First boundary tag of a non-box domain: face k of the domain tags its cells' faces
/// boundary_tag(domain_side_base + k), i.e. boundary_side = 6 + k, past the six box sides.
inline constexpr int domain_side_base = 6;

/// Checks a convex domain and returns a copy whose face k is tagged boundary_tag(6 + k).
inline convex_polyhedron tagged_domain(const convex_polyhedron& domain, const char* who) {
  require(!domain.empty() && domain.vertex_count() >= 4, who, ": the domain is empty (", domain.vertex_count(),
          " vertices)");
  for (index_t v = 0; v < domain.vertex_count(); ++v)
    require(domain.vertex(v).allFinite(), who, ": domain vertex ", v, " is not finite");
  const real volume = domain.volume();
  require(std::isfinite(volume) && volume > 0, who, ": the domain has volume ", volume,
          " m^3; it must be a closed convex polyhedron with outward face loops");
  std::vector<index_t> tags(static_cast<std::size_t>(domain.face_count()));
  for (index_t f = 0; f < domain.face_count(); ++f) tags[static_cast<std::size_t>(f)] = boundary_tag(domain_side_base + f);
  return convex_polyhedron::from_faces(domain.vertices(), domain.face_offsets(), domain.face_vertices(), std::move(tags));
}

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
