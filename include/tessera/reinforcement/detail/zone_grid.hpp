#pragma once
// Uniform bucket grid over the bounding boxes of the tetrahedral zones of a block_mesh, used to
// find the host zone of thousands of bar nodes in O(1) candidates each. Built once; read-only and
// thread-safe afterwards.
//
// Correctness does not depend on the cell size: a zone is listed in every cell its (slightly
// padded) bounding box overlaps, and a point is looked up in the cell that contains it, with the
// same monotone coordinate-to-cell map for both, so every zone whose padded box contains the point
// is a candidate. Candidates come in ascending zone id.

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "../../core/csr.hpp"
#include "../../core/types.hpp"

namespace tessera::reinforcement::detail {

class zone_grid {
 public:
  zone_grid() = default;

  /// gridpoints: reference positions (m); zones: 4 gridpoint ids each; padding: absolute growth
  /// of each zone's box, as a fraction of that box's largest edge (dimensionless).
  zone_grid(std::span<const vec3> gridpoints, std::span<const std::array<index_t, 4>> zones, real padding) {
    const auto zone_count = static_cast<std::int64_t>(zones.size());
    if (zone_count == 0) return;
    std::vector<aabb> boxes(zones.size());
    aabb all;
    for (std::size_t z = 0; z < zones.size(); ++z) {
      for (index_t g : zones[z]) boxes[z].expand(gridpoints[static_cast<std::size_t>(g)]);
      const real pad = padding * boxes[z].size().maxCoeff();
      boxes[z].lo.array() -= pad;
      boxes[z].hi.array() += pad;
      all.expand(boxes[z].lo);
      all.expand(boxes[z].hi);
    }
    origin_ = all.lo;
    // Cell edge from the mean zone volume share of the (non-degenerate) bounding box, enlarged
    // until the grid has at most ~8 cells per zone.
    const vec3 size = all.size().cwiseMax(1e-3 * all.size().maxCoeff());
    cell_ = std::cbrt(size.prod() / static_cast<real>(zone_count));
    for (;;) {
      std::int64_t cells = 1;
      for (int d = 0; d < 3; ++d) {
        dims_[d] = static_cast<index_t>(std::clamp<real>(std::ceil(all.size()[d] / cell_), 1.0, 1 << 20));
        cells *= dims_[d];
      }
      if (cells <= 8 * zone_count + 64) break;
      cell_ *= 1.26;
    }
    // Two-pass CSR fill in ascending zone id: counts, prefix sum, entries.
    auto for_cells = [&](const aabb& box, auto&& visit) {
      const auto lo = cell_of(box.lo);
      const auto hi = cell_of(box.hi);
      for (index_t k = lo[2]; k <= hi[2]; ++k)
        for (index_t j = lo[1]; j <= hi[1]; ++j)
          for (index_t i = lo[0]; i <= hi[0]; ++i) visit(linear(i, j, k));
    };
    auto entries = [&](auto&& emit) {
      for (std::size_t z = 0; z < boxes.size(); ++z)
        for_cells(boxes[z], [&](std::size_t c) {
          emit(c, [&](index_t slot) { zone_ids_[static_cast<std::size_t>(slot)] = static_cast<index_t>(z); });
        });
    };
    offsets_ = csr_offsets(static_cast<index_t>(dims_[0] * dims_[1] * dims_[2]), entries);
    zone_ids_.resize(static_cast<std::size_t>(offsets_.back()));
    csr_fill(offsets_, entries);
  }

  /// Zone ids (ascending) whose padded box may contain p; empty when the grid is empty.
  [[nodiscard]] std::span<const index_t> candidates(const vec3& p) const {
    if (offsets_.empty() || !p.allFinite()) return {};
    const auto c = cell_of(p);
    const std::size_t l = linear(c[0], c[1], c[2]);
    return {zone_ids_.data() + offsets_[l], static_cast<std::size_t>(offsets_[l + 1] - offsets_[l])};
  }

 private:
  [[nodiscard]] std::array<index_t, 3> cell_of(const vec3& p) const {
    std::array<index_t, 3> c{};
    for (int d = 0; d < 3; ++d)
      c[d] = static_cast<index_t>(std::clamp<real>(std::floor((p[d] - origin_[d]) / cell_), 0.0, dims_[d] - 1));
    return c;
  }
  [[nodiscard]] std::size_t linear(index_t i, index_t j, index_t k) const {
    return (static_cast<std::size_t>(k) * dims_[1] + static_cast<std::size_t>(j)) * dims_[0] + static_cast<std::size_t>(i);
  }

  vec3 origin_ = vec3::Zero();
  real cell_ = 1.0;
  std::array<index_t, 3> dims_{1, 1, 1};
  std::vector<index_t> offsets_;   ///< CSR over cells (empty: no zones)
  std::vector<index_t> zone_ids_;
};

}  // namespace tessera::reinforcement::detail
