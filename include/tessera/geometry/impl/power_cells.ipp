// The definitions of the larger functions that geometry/power_cells.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../power_cells.hpp"

namespace tessera::geometry {
namespace detail {

TESSERA_INLINE void validate_seeds(const aabb& box, std::span<const vec3> seeds, const seed_grid& grid, const char* who) {
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

TESSERA_INLINE void compute_cell(const aabb& box, std::span<const vec3> seeds, std::span<const real> weights, real w_max,
                                 const seed_grid& grid, index_t i, cell_workspace& ws,
                                 const convex_polyhedron* start) {
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

TESSERA_INLINE std::vector<convex_polyhedron> compute_cells(const aabb& box, std::span<const vec3> seeds,
                                                            std::span<const real> weights, const seed_grid& grid,
                                                            const convex_polyhedron* start) {
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

}  // namespace detail
}  // namespace tessera::geometry
