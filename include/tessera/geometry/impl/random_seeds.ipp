// The definitions of the larger functions that geometry/random_seeds.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../random_seeds.hpp"

namespace tessera::geometry {
namespace detail {

TESSERA_INLINE void sort_along_morton_curve(const aabb& box, std::vector<vec3>& points) {
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

}  // namespace detail
}  // namespace tessera::geometry
