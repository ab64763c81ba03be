#pragma once
// One Laguerre (power) cell at a time, the kernel of the Voronoi and Laguerre tessellations
// (voronoi.hpp states the method): the uniform bin grid of the generators, the checks of a box,
// of a convex domain and of the generators, and the cell of one generator, clipped from the box
// or the domain by its neighbours' power planes in order of distance until the security radius
// rules out every farther one.
//
// Cost: a few tens of clips per cell for uniformly spread generators. Thread safety: pure
// functions; compute_cells runs parallel_for with a thread_local workspace per thread, each cell
// written only by its own iteration.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/csr.hpp"
#include "../core/errors.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "convex_polyhedron.hpp"
#include "predicates.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

namespace detail {

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
TESSERA_INLINE void validate_seeds(const aabb& box, std::span<const vec3> seeds, const seed_grid& grid, const char* who);

/// Per-thread scratch of the cell computation.
struct cell_workspace {
  convex_polyhedron cell;
  std::vector<std::pair<real, index_t>> candidates;  // (squared distance, generator id)
};

/// Computes the Laguerre cell of generator i into ws.cell (weights empty = Voronoi), starting from
/// the box, or from `start` (a convex domain inside the box) when it is given.
TESSERA_INLINE void compute_cell(const aabb& box, std::span<const vec3> seeds, std::span<const real> weights, real w_max,
                                 const seed_grid& grid, index_t i, cell_workspace& ws,
                                 const convex_polyhedron* start = nullptr);

/// Computes every cell in parallel; rethrows the exception of the lowest failing cell.
TESSERA_INLINE std::vector<convex_polyhedron> compute_cells(const aabb& box, std::span<const vec3> seeds,
                                                            std::span<const real> weights, const seed_grid& grid,
                                                            const convex_polyhedron* start = nullptr);

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

}  // namespace detail

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/power_cells.ipp"
#endif
