#pragma once
// Construction-time layout of deformable blocks (blocks::deformable::build): the shape of one
// linear tetrahedral zone, the runs of consecutive zones of one block with the zone tasks the
// solver schedules (one task per block that has zones), and zone_geometry, the reference geometry
// blocks::deformable inherits.

#include <array>
#include <concepts>
#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>  // mat3::inverse (the zone Jacobian)

#include "../../core/separate_compilation.hpp"
#include "../../core/errors.hpp"
#include "../../core/nodes.hpp"
#include "../../core/csr.hpp"
#include "../../core/types.hpp"
#include "../../geometry/block_mesh.hpp"

namespace tessera::blocks::detail {

/// Reference volume (m^3) and shape-function gradients (1/m) of a linear tetrahedron; gradient
/// entry 3 a + k is d N_a / d x_k.
struct tet_shape {
  real volume = 0;
  std::array<real, 12> gradient{};
};

/// The shape of the tetrahedron with corners x (zone z of block `block`, for the message): with
/// J = [x1 - x0, x2 - x0, x3 - x0], grad N_{1,2,3} are the rows of J^-1 and grad N_0 = -(sum of
/// the others). Throws geometry_error for a tetrahedron that is inverted or of (relatively) zero
/// volume: det J <= 1e-12 (|e1|^2 |e2|^2 |e3|^2)^(1/2).
[[nodiscard]] TESSERA_INLINE tet_shape linear_tet(const std::array<vec3, 4>& x, index_t z, index_t block);

/// Runs of consecutive zones of one block (the zoning numbers zones block by block, so normally
/// one run per block: the kernel loops over a run with that block's rotation in registers), and
/// the zone tasks: the runs of each block that has zones, in increasing zone order (CSR over
/// tasks, blocks in increasing order).
struct zone_runs {
  std::vector<index_t> run_offsets{0};       ///< run r: zones [run_offsets[r], run_offsets[r + 1])
  std::vector<index_t> run_block;            ///< block of run r
  std::vector<index_t> task_run_offsets{0};  ///< task t: runs task_runs[task_run_offsets[t] ..]
  std::vector<index_t> task_runs;
  std::vector<index_t> task_block;           ///< block of task t
};

[[nodiscard]] TESSERA_INLINE zone_runs runs_of(const std::vector<index_t>& zone_block, index_t blocks);

/// The reference geometry of deformable blocks, the base of blocks::deformable: per zone its
/// corners, shape-function gradients and volume (structure of arrays, hot in the zone kernel),
/// zone runs and tasks, gridpoint ranges per block, the block-average gradient weights w_i
/// (F_b = 1 + sum_i u_i (x) w_i) and the gridpoint -> zone-corner incidence of the gather.
struct zone_geometry {
  std::array<std::vector<index_t>, 4> corner_;        ///< corner_[a][z]: gridpoint at corner a of zone z
  /// gradient_[3 a + k][z]: d N_a / d X_k (1/m), a = 0..3; grad N_0 = -(grad N_1 + grad N_2 +
  /// grad N_3) is stored too: 3 loads per zone instead of 9 additions in the zone kernel.
  std::array<std::vector<real>, 12> gradient_;
  std::vector<real> volume_;                        ///< reference volume V_z (m^3)
  std::vector<index_t> zone_block_;                   ///< owning block of each zone
  std::vector<index_t> run_offsets_{0};               ///< zones [run_offsets_[r], run_offsets_[r + 1]) belong to one block
  std::vector<index_t> run_block_;                    ///< that block
  std::vector<index_t> gridpoint_block_;              ///< owning block of each gridpoint
  std::vector<index_t> block_gridpoint_offsets_;      ///< CSR: gridpoints of block b
  soa3 block_gradient_;                             ///< w_i (1/m): F_b = 1 + sum_i u_i (x) w_i
  std::vector<index_t> task_run_offsets_{0};          ///< CSR: runs of zone task t (one block)
  std::vector<index_t> task_runs_;                    ///< those runs, in increasing zone order
  std::vector<index_t> task_block_;                   ///< the block of zone task t
  std::vector<index_t> corner_offsets_;               ///< CSR: gridpoint -> zone-corner slots
  std::vector<index_t> corner_slots_;                 ///< offset 3 a n_z + z of corner a of zone z in the corner forces

  template <std::integral I>
  [[nodiscard]] static constexpr std::size_t at(I i) noexcept {
    return static_cast<std::size_t>(i);
  }
  /// Gridpoint at corner a (0..3) of zone z.
  [[nodiscard]] index_t corner(index_t z, int a) const noexcept { return corner_[at(a)][at(z)]; }
  /// Reference shape-function gradients (1/m) of the 4 corners of zone z, corner-major, with
  /// grad N_0 = -(grad N_1 + grad N_2 + grad N_3).
  [[nodiscard]] std::array<real, 12> gradients(index_t z) const noexcept {
    std::array<real, 12> g{};
    for (std::size_t k = 0; k < 12; ++k) g[k] = gradient_[k][at(z)];
    return g;
  }

  /// Builds the above from `mesh` (zoned blocks). Throws geometry_error naming the zone, block or
  /// gridpoint for a zone corner outside its block, an inverted or flat zone, or a gridpoint
  /// outside its block's range.
  void build_geometry(const geometry::block_mesh& mesh) {
    const index_t n_gp = mesh.gridpoint_count();
    const index_t n_z = mesh.zone_count();
    const index_t n_b = mesh.block_count();
    zone_block_ = mesh.zone_block;
    gridpoint_block_ = mesh.gridpoint_block;
    block_gridpoint_offsets_ = mesh.block_gridpoint_offsets;
    for (int a = 0; a < 4; ++a) corner_[a].resize(static_cast<std::size_t>(n_z));
    for (auto& g : gradient_) g.resize(static_cast<std::size_t>(n_z));
    volume_.resize(static_cast<std::size_t>(n_z));
    std::vector<real> block_volume(static_cast<std::size_t>(n_b), 0.0);
    for (index_t z = 0; z < n_z; ++z) {
      const auto zs = static_cast<std::size_t>(z);
      const auto& c = mesh.zones[zs];
      std::array<vec3, 4> x;
      for (std::size_t a = 0; a < 4; ++a) {
        corner_[a][zs] = c[a];
        require<geometry_error>(c[a] >= 0 && c[a] < n_gp && mesh.gridpoint_block[static_cast<std::size_t>(c[a])] ==
                                                                 mesh.zone_block[zs],
                                "deformable blocks: corner ", a, " of zone ", z, " (block ", mesh.zone_block[zs],
                                ") is gridpoint ", c[a], ", which is not a gridpoint of that block");
        x[a] = mesh.gridpoints[static_cast<std::size_t>(c[a])];
      }
      const tet_shape shape = linear_tet(x, z, zone_block_[zs]);
      const real volume = shape.volume;
      volume_[zs] = volume;
      for (std::size_t k = 0; k < 12; ++k) gradient_[k][zs] = shape.gradient[k];
      block_volume[static_cast<std::size_t>(zone_block_[zs])] += volume;
    }

    // Runs of consecutive zones of one block and the zone tasks (runs_of).
    zone_runs runs = runs_of(zone_block_, n_b);
    run_offsets_ = std::move(runs.run_offsets);
    run_block_ = std::move(runs.run_block);
    task_run_offsets_ = std::move(runs.task_run_offsets);
    task_runs_ = std::move(runs.task_runs);
    task_block_ = std::move(runs.task_block);
    for (index_t i = 0; i < n_gp; ++i) {
      const index_t b = gridpoint_block_[static_cast<std::size_t>(i)];
      require<geometry_error>(b >= 0 && b < n_b && i >= block_gridpoint_offsets_[static_cast<std::size_t>(b)] &&
                                  i < block_gridpoint_offsets_[static_cast<std::size_t>(b) + 1],
                              "deformable blocks: gridpoint ", i, " of block ", b,
                              " lies outside that block's gridpoint range (block_mesh numbers gridpoints block by block)");
    }

    // Block-average gradient weights w_i and the gridpoint -> zone-corner incidence (CSR, each
    // gridpoint's corners in increasing zone order).
    block_gradient_.setZero(n_gp, 3);
    for (index_t z = 0; z < n_z; ++z) {
      const std::array<real, 12> g = gradients(z);
      const real v = volume_[static_cast<std::size_t>(z)];
      const real vb = block_volume[static_cast<std::size_t>(zone_block_[static_cast<std::size_t>(z)])];
      for (int a = 0; a < 4; ++a)
        for (int k = 0; k < 3; ++k) block_gradient_(corner(z, a), k) += v * g[static_cast<std::size_t>(3 * a + k)] / vb;
    }
    auto corners = [&](auto&& emit) {
      for (index_t z = 0; z < n_z; ++z)
        for (int a = 0; a < 4; ++a)
          emit(corner(z, a), [&](index_t slot) { corner_slots_[static_cast<std::size_t>(slot)] = 3 * a * n_z + z; });
    };
    corner_offsets_ = csr_offsets(n_gp, corners);
    corner_slots_.resize(static_cast<std::size_t>(4 * n_z));
    csr_fill(corner_offsets_, corners);
  }
};

}  // namespace tessera::blocks::detail

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/zone_layout.ipp"
#endif
