#pragma once
// blocks::deformable<Zone> — deformable blocks discretised into constant-strain tetrahedral
// zones (the zones of geometry::block_mesh), co-rotational with ONE rotation per block.
//
// Kinematics (decision, see docs/architecture.md "Zone kinematics"):
//  1. Per block b, the volume-averaged deformation gradient
//         F_b = (1/V_b) sum_z V_z F_z = 1 + sum_i u_i (x) w_i,   w_i = (1/V_b) sum_{z, a = i} V_z grad N_a
//     (w_i is non-zero only on the block surface) and its rotation R_b = polar(F_b), by a
//     warm-started Newton iteration (blocks/detail/polar.hpp), a few dozen flops per block.
//  2. Per zone, the displacement gradient H_z = sum_a u_a (x) grad N_a (constant strain), the
//     small strain in the rotated frame of its block
//         eps = sym(R_b^T (1 + H_z)) - 1,
//     the stress sigma' = Zone::stress(eps) in that frame, and the corner forces (study eq. 2,
//     f_a = -int_V B_a^T sigma dV for a constant-strain tetrahedron)
//         f_a = -V_z R_b sigma' grad N_a.
//     The zone stress stored for output/confinement is the global Cauchy stress R_b sigma' R_b^T.
// A block moved rigidly (x = Q X + c) has F_z = F_b = Q, R_b = Q and eps = 0 to round-off: no
// spurious stress for any rotation. The per-block rotation keeps the zone kernel a fixed
// sequence of small dense products (no per-zone polar decomposition); the price is that zones of
// one block bending strongly relative to each other see part of their relative rotation as
// strain, which is irrelevant for the semi-rigid blocks (E_block = 10 E) of the reference study.
//
// Gather (deterministic, no atomics): each zone writes its 4 corner forces to its own slot of a
// corner-force buffer; each gridpoint then sums its zone corners in a fixed CSR order. Results
// are bit-identical for any thread count. No allocation inside accumulate_forces.
//
// Lumped mass: rho V_z / 4 per corner. Stable-step stiffness: Gershgorin row sums of |K_z|,
// K_z = V_z B^T C B, summed over the zones of a gridpoint (an upper bound of the row sum of the
// assembled |K|).
//
// Thread safety: const members are safe to call concurrently; accumulate_forces is not.

#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/tessellation.hpp"
#include "concepts.hpp"
#include "detail/polar.hpp"

namespace tessera::blocks {

template <zones::ZoneModel Zone>
class deformable {
 public:
  using zone_model = Zone;
  using params = typename Zone::params;
  static constexpr bool is_rigid = false;

  deformable() = default;

  /// Validates the material, precomputes zone gradients and volumes, and sizes `gridpoints`
  /// (reference positions from the mesh, lumped masses, zero state). Throws invalid_input for a
  /// bad material and geometry_error for a zone of non-positive volume (naming zone and block).
  void build(const geometry::tessellation& /*tess*/, const geometry::block_mesh& mesh, const params& p,
             node_set& gridpoints) {
    Zone::validate(p);
    params_ = p;
    const index n_gp = mesh.gridpoint_count();
    const index n_z = mesh.zone_count();
    const index n_b = mesh.block_count();
    require<geometry_error>(n_gp > 0 && n_z > 0, "deformable blocks: block_mesh has ", n_gp, " gridpoints and ",
                            n_z, " zones; zone the blocks first (geometry::zone_blocks)");
    gridpoints.resize(n_gp);
    for (index i = 0; i < n_gp; ++i) gridpoints.reference.row(i) = mesh.gridpoints[static_cast<std::size_t>(i)];

    corners_ = mesh.zones;
    zone_block_ = mesh.zone_block;
    gridpoint_block_ = mesh.gridpoint_block;
    block_gridpoint_offsets_ = mesh.block_gridpoint_offsets;
    zone_geometry_.resize(static_cast<std::size_t>(n_z));
    std::vector<real> block_volume(static_cast<std::size_t>(n_b), 0.0);
    const real rho = Zone::density(p);
    for (index z = 0; z < n_z; ++z) {
      const auto& c = corners_[static_cast<std::size_t>(z)];
      std::array<vec3, 4> x;
      for (int a = 0; a < 4; ++a) x[static_cast<std::size_t>(a)] = mesh.gridpoints[static_cast<std::size_t>(c[static_cast<std::size_t>(a)])];
      // Shape-function gradients of a linear tetrahedron: with J = [x1-x0, x2-x0, x3-x0],
      // grad N_{1,2,3} are the rows of J^-1 and grad N_0 = -(sum of the others).
      mat3 j;
      j.col(0) = x[1] - x[0];
      j.col(1) = x[2] - x[0];
      j.col(2) = x[3] - x[0];
      const real det = j.determinant();
      const real volume = det / 6;
      const real scale = std::cbrt(std::abs(j.col(0).dot(j.col(0)) * j.col(1).dot(j.col(1)) * j.col(2).dot(j.col(2))));
      require<geometry_error>(det > 1e-12 * std::pow(scale, 1.5), "deformable blocks: zone ", z, " of block ",
                              zone_block_[static_cast<std::size_t>(z)], " has volume ", volume,
                              " m^3; expected a positively oriented tetrahedron of non-zero volume");
      const mat3 j_inv = j.inverse();
      zone_geometry& g = zone_geometry_[static_cast<std::size_t>(z)];
      g.volume = volume;
      for (int a = 1; a < 4; ++a)
        for (int k = 0; k < 3; ++k) g.grad[static_cast<std::size_t>(3 * a + k)] = j_inv(a - 1, k);
      for (int k = 0; k < 3; ++k)
        g.grad[static_cast<std::size_t>(k)] = -(g.grad[static_cast<std::size_t>(3 + k)] + g.grad[static_cast<std::size_t>(6 + k)] +
                                               g.grad[static_cast<std::size_t>(9 + k)]);
      for (int a = 0; a < 4; ++a) gridpoints.mass[c[static_cast<std::size_t>(a)]] += rho * volume / 4;
      block_volume[static_cast<std::size_t>(zone_block_[static_cast<std::size_t>(z)])] += volume;
    }
    for (index i = 0; i < n_gp; ++i)
      require<geometry_error>(gridpoints.mass[i] > 0, "deformable blocks: gridpoint ", i, " of block ",
                              gridpoint_block_[static_cast<std::size_t>(i)],
                              " belongs to no zone (zero mass); every gridpoint must be a zone corner");

    // Block-average gradient weights w_i and the gridpoint -> zone-corner incidence (CSR).
    block_gradient_.setZero(n_gp, 3);
    corner_offsets_.assign(static_cast<std::size_t>(n_gp) + 1, 0);
    for (index z = 0; z < n_z; ++z)
      for (index id : corners_[static_cast<std::size_t>(z)]) ++corner_offsets_[static_cast<std::size_t>(id) + 1];
    for (index i = 0; i < n_gp; ++i) corner_offsets_[static_cast<std::size_t>(i) + 1] += corner_offsets_[static_cast<std::size_t>(i)];
    corner_slots_.resize(static_cast<std::size_t>(4 * n_z));
    std::vector<index> fill(corner_offsets_.begin(), corner_offsets_.end() - 1);
    for (index z = 0; z < n_z; ++z) {
      const zone_geometry& g = zone_geometry_[static_cast<std::size_t>(z)];
      const real vb = block_volume[static_cast<std::size_t>(zone_block_[static_cast<std::size_t>(z)])];
      for (int a = 0; a < 4; ++a) {
        const index id = corners_[static_cast<std::size_t>(z)][static_cast<std::size_t>(a)];
        corner_slots_[static_cast<std::size_t>(fill[static_cast<std::size_t>(id)]++)] = 4 * z + a;
        for (int k = 0; k < 3; ++k) block_gradient_(id, k) += g.volume * g.grad[static_cast<std::size_t>(3 * a + k)] / vb;
      }
    }
    rotation_.assign(static_cast<std::size_t>(n_b), mat3::Identity());
    corner_force_.setZero(12, n_z);
    zone_stress_.setZero(n_z, 6);
  }

  /// Step 2: computes block rotations, zone strains and stresses from the current displacements
  /// and adds the zone forces (N) to gridpoints.force.
  void accumulate_forces(node_set& gridpoints) noexcept {
    update_rotations(gridpoints);
    const typename Zone::constants p = Zone::prepare(params_);
    const real* const u[3] = {gridpoints.displacement.col(0).data(), gridpoints.displacement.col(1).data(),
                              gridpoints.displacement.col(2).data()};
    parallel_for(zone_count(), [&](std::int64_t z) { zone_kernel(p, u, static_cast<index>(z)); });
    const index n_gp = gridpoints.size();
    parallel_for(n_gp, [&](std::int64_t ii) {
      const index i = static_cast<index>(ii);
      real f0 = 0, f1 = 0, f2 = 0;
      for (index s = corner_offsets_[static_cast<std::size_t>(i)]; s < corner_offsets_[static_cast<std::size_t>(i) + 1]; ++s) {
        const index slot = corner_slots_[static_cast<std::size_t>(s)];
        const real* f = corner_force_.data() + 3 * static_cast<std::ptrdiff_t>(slot);
        f0 += f[0];
        f1 += f[1];
        f2 += f[2];
      }
      gridpoints.force(i, 0) += f0;
      gridpoints.force(i, 1) += f1;
      gridpoints.force(i, 2) += f2;
    });
  }

  /// Adds to gridpoints.stiffness (N/m) the largest Gershgorin row sum sum_j |K_ij| over the
  /// three rows of each gridpoint, K = sum_z V_z B_z^T C B_z in the reference frame. All zones of
  /// a gridpoint belong to one block and share its rotation R_b, so the co-rotated stiffness is
  /// Q K Q^T with Q = blockdiag(R_b): a similarity transform that commutes with the nodal lumped
  /// mass matrix, hence lambda_max(M^-1 K) is rotation-invariant and the reference-frame bound
  /// holds in any rotated state.
  void add_stiffness_bounds(node_set& gridpoints) const {
    const Eigen::Matrix<real, 6, 6> c = Zone::elasticity_matrix(params_);
    for (index z = 0; z < zone_count(); ++z) {
      const zone_geometry& g = zone_geometry_[static_cast<std::size_t>(z)];
      Eigen::Matrix<real, 6, 12> b = Eigen::Matrix<real, 6, 12>::Zero();
      for (int a = 0; a < 4; ++a) {
        const real gx = g.grad[static_cast<std::size_t>(3 * a)], gy = g.grad[static_cast<std::size_t>(3 * a + 1)],
                   gz = g.grad[static_cast<std::size_t>(3 * a + 2)];
        b(0, 3 * a) = gx;
        b(1, 3 * a + 1) = gy;
        b(2, 3 * a + 2) = gz;
        b(3, 3 * a + 1) = gz;
        b(3, 3 * a + 2) = gy;
        b(4, 3 * a) = gz;
        b(4, 3 * a + 2) = gx;
        b(5, 3 * a) = gy;
        b(5, 3 * a + 1) = gx;
      }
      const Eigen::Matrix<real, 12, 12> k = g.volume * b.transpose() * c * b;
      for (int a = 0; a < 4; ++a) {
        real row_max = 0;
        for (int r = 0; r < 3; ++r) row_max = std::max(row_max, k.row(3 * a + r).cwiseAbs().sum());
        gridpoints.stiffness[corners_[static_cast<std::size_t>(z)][static_cast<std::size_t>(a)]] += row_max;
      }
    }
  }

  /// Steps 5-6 for deformable blocks: the gridpoints are the degrees of freedom.
  template <class Integrator, class Work>
  void advance(const Integrator& integ, node_set& gridpoints, real dt, Work& work) noexcept {
    integ.advance(gridpoints, dt, work);
  }

  /// Global Cauchy stress of every zone at the last accumulate_forces (Pa, Voigt, tension +).
  [[nodiscard]] const zone_stress_matrix& zone_stress() const { return zone_stress_; }

  /// Elastic energy stored in the zones, sum_z V_z W(eps_z) (J), with block rotations of the
  /// CURRENT displacements (the cached ones lag one step behind after the integrator has moved
  /// the gridpoints). Allocates; not for the time step.
  [[nodiscard]] real stored_energy(const node_set& gridpoints) const {
    std::vector<mat3> rotations = rotation_;
    for (index b = 0; b < block_count(); ++b)
      rotations[static_cast<std::size_t>(b)] = block_rotation(gridpoints, b, rotation_[static_cast<std::size_t>(b)]);
    return deterministic_sum(zone_count(), [&](std::int64_t z) {
      const index zi = static_cast<index>(z);
      const mat3 m = rotated_gradient(gridpoints, zi, rotations[static_cast<std::size_t>(zone_block_[static_cast<std::size_t>(zi)])]);
      voigt6 e;
      e << m(0, 0), m(1, 1), m(2, 2), m(1, 2) + m(2, 1), m(2, 0) + m(0, 2), m(0, 1) + m(1, 0);
      return zone_geometry_[static_cast<std::size_t>(zi)].volume * Zone::strain_energy_density(params_, e);
    });
  }
  /// Kinetic energy sum_i 1/2 m_i |v_i|^2 (J), v at the half step.
  [[nodiscard]] real kinetic_energy(const node_set& gridpoints) const {
    return deterministic_sum(gridpoints.size(), [&](std::int64_t i) {
      return 0.5 * gridpoints.mass[i] * gridpoints.velocity.row(i).squaredNorm();
    });
  }

  /// Small strain of zone z in the rotated frame of its block at the last accumulate_forces
  /// (Voigt, engineering shears).
  [[nodiscard]] voigt6 zone_strain(const node_set& gridpoints, index z) const {
    const mat3 m = rotated_gradient(gridpoints, z, rotation_[static_cast<std::size_t>(zone_block_[static_cast<std::size_t>(z)])]);
    voigt6 e;
    e << m(0, 0), m(1, 1), m(2, 2), m(1, 2) + m(2, 1), m(2, 0) + m(0, 2), m(0, 1) + m(1, 0);
    return e;
  }

  [[nodiscard]] index block_count() const { return static_cast<index>(rotation_.size()); }
  [[nodiscard]] index zone_count() const { return static_cast<index>(corners_.size()); }
  [[nodiscard]] real zone_volume(index z) const { return zone_geometry_[static_cast<std::size_t>(z)].volume; }
  /// Rotation R_b of block b at the last accumulate_forces.
  [[nodiscard]] const mat3& rotation(index b) const { return rotation_[static_cast<std::size_t>(b)]; }
  [[nodiscard]] index gridpoint_block(index i) const { return gridpoint_block_[static_cast<std::size_t>(i)]; }
  [[nodiscard]] const params& material() const { return params_; }

 private:
  /// Reference shape-function gradients (1/m) of the 4 corners, corner-major, and volume (m^3):
  /// the 13 numbers the zone kernel reads, contiguous per zone.
  struct zone_geometry {
    std::array<real, 12> grad{};
    real volume = 0;
  };

  /// R_b = polar(F_b), F_b = 1 + sum_i u_i (x) w_i over the gridpoints of block b, warm-started
  /// from `previous`.
  [[nodiscard]] mat3 block_rotation(const node_set& gp, index b, const mat3& previous) const noexcept {
    mat3 f = mat3::Identity();
    const auto bs = static_cast<std::size_t>(b);
    for (index i = block_gridpoint_offsets_[bs]; i < block_gridpoint_offsets_[bs + 1]; ++i)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) f(r, c) += gp.displacement(i, r) * block_gradient_(i, c);
    return detail::polar_rotation(f, previous);
  }

  void update_rotations(const node_set& gp) noexcept {
    parallel_for(block_count(), [&](std::int64_t bb) {
      const auto b = static_cast<std::size_t>(bb);
      rotation_[b] = block_rotation(gp, static_cast<index>(bb), rotation_[b]);
    }, 16);
  }

  /// R_b^T (1 + H_z) - 1 of zone z (its symmetric part is the co-rotated small strain).
  [[nodiscard]] mat3 rotated_gradient(const node_set& gp, index z, const mat3& r) const noexcept {
    const zone_geometry& g = zone_geometry_[static_cast<std::size_t>(z)];
    const auto& c = corners_[static_cast<std::size_t>(z)];
    mat3 h = mat3::Zero();  // displacement gradient H = sum_a u_a (x) grad N_a
    for (int a = 0; a < 4; ++a) {
      const index id = c[static_cast<std::size_t>(a)];
      const real u0 = gp.displacement(id, 0), u1 = gp.displacement(id, 1), u2 = gp.displacement(id, 2);
      const real* gr = g.grad.data() + 3 * a;
      for (int k = 0; k < 3; ++k) {
        h(0, k) += u0 * gr[k];
        h(1, k) += u1 * gr[k];
        h(2, k) += u2 * gr[k];
      }
    }
    // R^T (1 + H) - 1 = (R^T - 1) + R^T H, grouped so a small strain is not cancelled against 1.
    mat3 m = r.transpose() * h;
    m += r.transpose();
    m.diagonal().array() -= 1.0;
    return m;
  }

  /// Zone forces and stress of zone z (scalar code: the 3x3 products are written out so the
  /// compiler keeps everything in registers; `p` is a local copy of the material prepared once per
  /// loop).
  [[gnu::always_inline]] inline void zone_kernel(const typename Zone::constants& p, const real* const u[3], index z) noexcept {
    const zone_geometry& g = zone_geometry_[static_cast<std::size_t>(z)];
    const auto& c = corners_[static_cast<std::size_t>(z)];
    const mat3& r = rotation_[static_cast<std::size_t>(zone_block_[static_cast<std::size_t>(z)])];
    // Displacement gradient H (row i, column k) = sum_a u_a[i] grad N_a[k].
    real h[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int a = 0; a < 4; ++a) {
      const index id = c[static_cast<std::size_t>(a)];
      const real* gr = g.grad.data() + 3 * a;
      for (int i = 0; i < 3; ++i) {
        const real ui = u[i][id];
        h[3 * i + 0] += ui * gr[0];
        h[3 * i + 1] += ui * gr[1];
        h[3 * i + 2] += ui * gr[2];
      }
    }
    // M = R^T (1 + H) - 1 = (R^T - 1) + R^T H.
    real m[9];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        m[3 * i + k] = (r(k, i) - (i == k ? 1.0 : 0.0)) + r(0, i) * h[k] + r(1, i) * h[3 + k] + r(2, i) * h[6 + k];
    voigt6 eps;
    eps[0] = m[0];
    eps[1] = m[4];
    eps[2] = m[8];
    eps[3] = m[5] + m[7];
    eps[4] = m[6] + m[2];
    eps[5] = m[1] + m[3];
    const voigt6 s = Zone::stress(p, eps);
    const real sig[9] = {s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2]};
    // P = R sigma' (global first index, local second).
    real pr[9];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) pr[3 * i + k] = r(i, 0) * sig[k] + r(i, 1) * sig[3 + k] + r(i, 2) * sig[6 + k];
    // f_a = -V P grad N_a.
    const real minus_v = -g.volume;
    real* out = corner_force_.data() + 12 * static_cast<std::ptrdiff_t>(z);
    for (int a = 0; a < 4; ++a) {
      const real* gr = g.grad.data() + 3 * a;
      for (int i = 0; i < 3; ++i)
        out[3 * a + i] = minus_v * (pr[3 * i] * gr[0] + pr[3 * i + 1] * gr[1] + pr[3 * i + 2] * gr[2]);
    }
    // Global Cauchy stress R sigma' R^T (six entries).
    const auto entry = [&](int i, int j) { return pr[3 * i] * r(j, 0) + pr[3 * i + 1] * r(j, 1) + pr[3 * i + 2] * r(j, 2); };
    zone_stress_(z, 0) = entry(0, 0);
    zone_stress_(z, 1) = entry(1, 1);
    zone_stress_(z, 2) = entry(2, 2);
    zone_stress_(z, 3) = entry(1, 2);
    zone_stress_(z, 4) = entry(2, 0);
    zone_stress_(z, 5) = entry(0, 1);
  }

  params params_{};
  std::vector<std::array<index, 4>> corners_;       ///< zone corner gridpoints
  std::vector<index> zone_block_;                   ///< owning block of each zone
  std::vector<index> gridpoint_block_;              ///< owning block of each gridpoint
  std::vector<index> block_gridpoint_offsets_;      ///< CSR: gridpoints of block b
  std::vector<zone_geometry> zone_geometry_;        ///< per zone: reference gradients and volume
  soa3 block_gradient_;                             ///< w_i (1/m): F_b = 1 + sum_i u_i (x) w_i
  std::vector<mat3> rotation_;                      ///< R_b, warm start of the next polar decomposition
  std::vector<index> corner_offsets_;               ///< CSR: gridpoint -> zone-corner slots
  std::vector<index> corner_slots_;                 ///< slot = 4 z + a
  Eigen::Matrix<real, 12, Eigen::Dynamic> corner_force_;  ///< per zone: the 4 corner forces (N)
  zone_stress_matrix zone_stress_;                  ///< global Cauchy stress per zone (Pa)
};

}  // namespace tessera::blocks
