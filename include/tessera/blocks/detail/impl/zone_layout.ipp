// The definitions of the larger functions that blocks/detail/zone_layout.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../zone_layout.hpp"

namespace tessera::blocks::detail {

[[nodiscard]] TESSERA_INLINE tet_shape linear_tet(const std::array<vec3, 4>& x, index_t z, index_t block) {
  mat3 j;
  j.col(0) = x[1] - x[0];
  j.col(1) = x[2] - x[0];
  j.col(2) = x[3] - x[0];
  const real det = j.determinant();
  tet_shape t;
  t.volume = det / 6;
  const real scale = std::cbrt(std::abs(j.col(0).dot(j.col(0)) * j.col(1).dot(j.col(1)) * j.col(2).dot(j.col(2))));
  require<geometry_error>(det > 1e-12 * std::pow(scale, 1.5), "deformable blocks: zone ", z, " of block ", block,
                          " has volume ", t.volume, " m^3; expected a positively oriented tetrahedron of non-zero volume");
  const mat3 j_inv = j.inverse();
  for (int a = 1; a < 4; ++a)
    for (int k = 0; k < 3; ++k) t.gradient[static_cast<std::size_t>(3 * a + k)] = j_inv(a - 1, k);
  for (std::size_t k = 0; k < 3; ++k) t.gradient[k] = -(t.gradient[3 + k] + t.gradient[6 + k] + t.gradient[9 + k]);
  return t;
}

[[nodiscard]] TESSERA_INLINE zone_runs runs_of(const std::vector<index_t>& zone_block, index_t blocks) {
  zone_runs r;
  const auto n_z = static_cast<index_t>(zone_block.size());
  for (index_t z = 0; z < n_z; ++z) {
    const index_t b = zone_block[static_cast<std::size_t>(z)];
    if (z > 0 && b == r.run_block.back()) continue;
    if (z > 0) r.run_offsets.push_back(z);
    r.run_block.push_back(b);
  }
  r.run_offsets.push_back(n_z);
  std::vector<std::vector<index_t>> runs_of_block(static_cast<std::size_t>(blocks));
  for (index_t run = 0; run < static_cast<index_t>(r.run_block.size()); ++run)
    runs_of_block[static_cast<std::size_t>(r.run_block[static_cast<std::size_t>(run)])].push_back(run);
  for (index_t b = 0; b < blocks; ++b) {
    const auto& runs = runs_of_block[static_cast<std::size_t>(b)];
    if (runs.empty()) continue;
    r.task_runs.insert(r.task_runs.end(), runs.begin(), runs.end());
    r.task_run_offsets.push_back(static_cast<index_t>(r.task_runs.size()));
    r.task_block.push_back(b);
  }
  return r;
}

}  // namespace tessera::blocks::detail
