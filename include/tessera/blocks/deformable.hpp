#pragma once
// blocks::deformable<Zone> — deformable blocks discretised into constant-strain tetrahedral
// zones (the zones of geometry::block_mesh), co-rotational with ONE rotation per block.
//
// Kinematics (decision, see docs/architecture.md "Zone kinematics"):
//  1. Per block b, the volume-averaged deformation gradient
//         F_b = (1/V_b) sum_z V_z F_z = 1 + sum_i u_i (x) w_i,   w_i = (1/V_b) sum_{z, a = i} V_z grad N_a
//     (w_i is non-zero only on the block surface) and its rotation R_b = polar(F_b), by a
//     warm-started Newton iteration (blocks/detail/polar.hpp), a few dozen flops per block, run
//     for lanes::width blocks at a time in lock-step (the iteration is a chain of dependent
//     operations: one block at a time it cost ~130 ns per block, mostly waiting).
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
// Assembly (deterministic, no atomics): the blocks own disjoint, contiguous ranges of gridpoints,
// so the zones of one block form one task: the task computes its zones (runs of consecutive
// zones, each writing its 4 corner forces to its own slot of a corner-force buffer), then sums
// the corners of each of its gridpoints in a fixed CSR order (increasing zone order) while they
// are still in L1. Tasks touch disjoint gridpoints and may run concurrently; results are
// bit-identical for any thread count. No allocation inside accumulate_forces. (The sums used to
// run in a separate pass over all gridpoints after all zones, to the same bits; on the 500-block
// tie that pass read 1.8 MB of corner forces back from L3 every step.)
//
// Lumped mass: rho V_z / 4 per corner. Stable-step stiffness: Gershgorin row sums of |K_z|,
// K_z = V_z B^T C B, summed over the zones of a gridpoint (an upper bound of the row sum of the
// assembled |K|).
//
// Layout: the reference geometry (zones, runs, tasks, gather incidence) is detail::zone_geometry
// (detail/zone_layout.hpp), the arithmetic of a run of zones detail::zone_kernel
// (detail/zone_kernel.hpp); this class adds the materials, the rotations, the gather and the
// read-outs.
// Cost: O(zones) per step, no allocation; measured per zone-step in docs/performance.md.
//
// Thread safety: const members are safe to call concurrently; accumulate_forces is not.

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "../core/csr.hpp"
#include "detail/zone_layout.hpp"
#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/tessellation.hpp"
#include "concepts.hpp"
#include "detail/polar.hpp"
#include "detail/zone_kernel.hpp"

namespace tessera::blocks {

/// Deformable blocks: each block zoned into tetrahedra of the Zone model (file comment); owns the loops over its gridpoints and zones
template <zones::ZoneModel Zone>
class deformable : private detail::zone_geometry {
 public:
  using zone_model = Zone;  ///< the zone model
  using params = typename Zone::params;  ///< the zone material (e.g. E, nu, rho), one per block material
  static constexpr bool is_rigid = false;  ///< not rigid

  deformable() = default;

  /// Validates the material, precomputes zone gradients and volumes, and sizes `gridpoints`
  /// (reference positions from the mesh, lumped masses, zero state). Throws invalid_input for a
  /// bad material and geometry_error for a zone of non-positive volume (naming zone and block).
  /// One material for every block.
  void build(const geometry::tessellation& tess, const geometry::block_mesh& mesh, const params& p,
             node_set& gridpoints) {
    build(tess, mesh, std::span<const params>(&p, 1), gridpoints);
  }
  /// The same with one material per material id: block b takes materials[mesh.material(b)]
  /// (geometry::block_mesh::block_material). Throws invalid_input for a bad material or a block
  /// whose id has no entry.
  void build(const geometry::tessellation& /*tess*/, const geometry::block_mesh& mesh,
             std::span<const params> materials, node_set& gridpoints) {
    require(!materials.empty(), "deformable blocks: no block material given");
    materials_.assign(materials.begin(), materials.end());
    constants_.clear();
    for (const params& p : materials_) {
      Zone::validate(p);
      constants_.push_back(Zone::prepare(p));
    }
    const index_t n_gp = mesh.gridpoint_count();
    const index_t n_z = mesh.zone_count();
    const index_t n_b = mesh.block_count();
    require<geometry_error>(n_gp > 0 && n_z > 0, "deformable blocks: block_mesh has ", n_gp, " gridpoints and ",
                            n_z, " zones; zone the blocks first (geometry::zone_blocks)");
    gridpoints.resize(n_gp);
    for (index_t i = 0; i < n_gp; ++i) gridpoints.reference.row(i) = mesh.gridpoints[static_cast<std::size_t>(i)];

    block_material_.resize(static_cast<std::size_t>(n_b));
    for (index_t b = 0; b < n_b; ++b) {
      const int m = mesh.material(b);
      require(m >= 0 && static_cast<std::size_t>(m) < materials_.size(), "deformable blocks: block ", b,
              " has material id ", m, ", but ", materials_.size(), " block material(s) were given");
      block_material_[static_cast<std::size_t>(b)] = m;
    }
    build_geometry(mesh);  // zones, runs, tasks, block gradients, corner incidence (zone_layout.hpp)
    // Lumped masses rho V_z / 4 per corner, in zone order.
    for (index_t z = 0; z < n_z; ++z) {
      const real rho = Zone::density(material_of_block(zone_block_[at(z)]));
      for (int a = 0; a < 4; ++a) gridpoints.mass[corner(z, a)] += rho * volume_[at(z)] / 4;
    }
    for (index_t i = 0; i < n_gp; ++i)
      require<geometry_error>(gridpoints.mass[i] > 0, "deformable blocks: gridpoint ", i, " of block ",
                              gridpoint_block_[static_cast<std::size_t>(i)],
                              " belongs to no zone (zero mass); every gridpoint must be a zone corner");
    rotation_.assign(static_cast<std::size_t>(n_b), mat3::Identity());
    corner_force_.setZero(n_z, 12);
    local_stress_.setZero(n_z, 6);
    watch_slot_.assign(static_cast<std::size_t>(n_z), invalid_index);
    watch_offsets_.assign(static_cast<std::size_t>(n_b) + 1, 0);
    watch_zones_.clear();
    watched_stress_.resize(0, 6);
  }

  /// Zones whose global stress every step keeps ready (the bars' host zones, set by the solver):
  /// each zone task forms them right after its zones' stresses (add_zone_forces), in parallel,
  /// so zone_stress_rows().row(z) of a watched zone is a read. Other zones' global stress is
  /// formed when asked. Throws invalid_input for a zone outside [0, zone_count()).
  void watch_zone_stress(const std::vector<index_t>& zones) {
    std::vector<index_t> slot(static_cast<std::size_t>(zone_count()), invalid_index);
    for (const index_t z : zones) {
      require<invalid_input>(z >= 0 && z < zone_count(), "deformable blocks: watched zone ", z, " is not a zone (",
                             zone_count(), " zones)");
      slot[at(z)] = 0;  // watched; its slot is set below
    }
    // The watched zones by block, in increasing zone order within a block (core/csr.hpp).
    auto watched = [&](auto&& emit) {
      for (index_t z = 0; z < zone_count(); ++z)
        if (slot[at(z)] != invalid_index) emit(zone_block_[at(z)], [&, z](index_t w) { watch_zones_[at(w)] = z; });
    };
    watch_offsets_ = csr_offsets(block_count(), watched);
    watch_zones_.resize(static_cast<std::size_t>(watch_offsets_.back()));
    csr_fill(watch_offsets_, watched);
    for (index_t w = 0; w < static_cast<index_t>(watch_zones_.size()); ++w) slot[at(watch_zones_[at(w)])] = w;
    watch_slot_ = std::move(slot);
    watched_stress_.resize(static_cast<index_t>(watch_zones_.size()), 6);
    form_watched_stress(0, static_cast<index_t>(watch_zones_.size()));
  }

  /// Step 2: computes block rotations, zone strains and stresses from the current displacements
  /// and adds the zone forces (N) to gridpoints.force.
  void accumulate_forces(node_set& gridpoints) noexcept {
    begin_zone_forces(gridpoints);
    parallel_for(zone_task_count(), [&](std::int64_t t) { add_zone_forces(static_cast<index_t>(t), gridpoints); }, 4);
  }

  // ---- accumulate_forces() in pieces, for a solver that fuses the loops of its step ----
  // accumulate_forces(gp) == begin_zone_forces(gp); then add_zone_forces(t, gp) for every task t,
  // in any order or concurrently (same results to the bit).

  /// Number of zone tasks: one per block with zones (the gridpoints of a task are its block's).
  [[nodiscard]] index_t zone_task_count() const { return static_cast<index_t>(task_run_offsets_.size()) - 1; }
  /// Block rotations (all blocks, the polar iterations in lock-step over lanes; see
  /// update_rotations).
  void begin_zone_forces(const node_set& gridpoints) noexcept { update_rotations(gridpoints); }
  /// begin_zone_forces(gp) restricted to the blocks of tasks [t0, t1), then add_zone_forces(t, gp)
  /// for t in [t0, t1): a thread can run its own share of the tasks without waiting for the other
  /// blocks' rotations (each block's rotation is the same bits however the blocks are packed).
  void add_zone_forces_of_tasks(index_t t0, index_t t1, node_set& gridpoints) noexcept {
    if (t0 >= t1) return;
    update_rotations(gridpoints, task_block_[at(t0)], task_block_[at(t1 - 1)] + 1);
    for (index_t t = t0; t < t1; ++t) add_zone_forces(t, gridpoints);
  }
  /// Zone stresses of the zones of task t (one block b), then the corner forces of each gridpoint
  /// of b summed (in increasing zone order) and added to gridpoints.force. Touches no gridpoint of
  /// another task.
  void add_zone_forces(index_t t, node_set& gridpoints) noexcept {
    const real* const u[3] = {gridpoints.displacement.col(0).data(), gridpoints.displacement.col(1).data(),
                              gridpoints.displacement.col(2).data()};
    const auto b = at(task_block_[at(t)]);
    const typename Zone::constants& constants = constants_[at(block_material_[b])];
    for (index_t k = task_run_offsets_[at(t)]; k < task_run_offsets_[at(t) + 1]; ++k)
      detail::zone_kernel<Zone>(constants, rotation_[at(run_block_[at(task_runs_[at(k)])])], *this, u,
                                at(task_runs_[at(k)]), corner_force_.data(), local_stress_.data());
    form_watched_stress(watch_offsets_[b], watch_offsets_[b + 1]);  // this block's watched zones
    const real* const f = corner_force_.data();
    const std::ptrdiff_t n_z = zone_count();
    real* const force[3] = {gridpoints.force.col(0).data(), gridpoints.force.col(1).data(),
                            gridpoints.force.col(2).data()};
    for (index_t i = block_gridpoint_offsets_[b]; i < block_gridpoint_offsets_[b + 1]; ++i) {
      real f0 = 0, f1 = 0, f2 = 0;
      for (index_t s = corner_offsets_[at(i)]; s < corner_offsets_[at(i) + 1]; ++s) {
        const real* fs = f + corner_slots_[at(s)];
        f0 += fs[0];
        f1 += fs[n_z];
        f2 += fs[2 * n_z];
      }
      force[0][at(i)] += f0;
      force[1][at(i)] += f1;
      force[2][at(i)] += f2;
    }
  }

  /// Adds to gridpoints.stiffness (N/m) the largest Gershgorin row sum sum_j |K_ij| over the
  /// three rows of each gridpoint, K = sum_z V_z B_z^T C B_z in the reference frame. All zones of
  /// a gridpoint belong to one block and share its rotation R_b, so the co-rotated stiffness is
  /// Q K Q^T with Q = blockdiag(R_b): a similarity transform that commutes with the nodal lumped
  /// mass matrix, hence lambda_max(M^-1 K) is rotation-invariant and the reference-frame bound
  /// holds in any rotated state.
  void add_stiffness_bounds(node_set& gridpoints) const {
    std::vector<Eigen::Matrix<real, 6, 6>> elasticity;
    for (const params& p : materials_) elasticity.push_back(Zone::elasticity_matrix(p));
    for (index_t z = 0; z < zone_count(); ++z) {
      const Eigen::Matrix<real, 6, 6>& c = elasticity[at(block_material_[at(zone_block_[at(z)])])];
      const std::array<real, 12> g = gradients(z);
      Eigen::Matrix<real, 6, 12> b = Eigen::Matrix<real, 6, 12>::Zero();
      for (int a = 0; a < 4; ++a) {
        const real gx = g[at(3 * a)], gy = g[at(3 * a + 1)], gz = g[at(3 * a + 2)];
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
      const Eigen::Matrix<real, 12, 12> k = volume_[at(z)] * b.transpose() * c * b;
      for (int a = 0; a < 4; ++a) {
        real row_max = 0;
        for (int r = 0; r < 3; ++r) row_max = std::max(row_max, k.row(3 * a + r).cwiseAbs().sum());
        gridpoints.stiffness[corner(z, a)] += row_max;
      }
    }
  }

  /// Steps 5-6 for deformable blocks: the gridpoints are the degrees of freedom.
  template <class Integrator, class Work>
  void advance(const Integrator& integ, node_set& gridpoints, real dt, Work& work) noexcept {
    integ.advance(gridpoints, dt, work);
  }

  /// Global Cauchy stress of zone z at the last accumulate_forces (Pa, Voigt xx yy zz yz zx xy,
  /// tension +): R_b sigma' R_b^T from the block-frame stress sigma' the zone kernel keeps,
  /// written with the expressions the kernel used when it stored the global stress itself (the
  /// same bits).
  [[nodiscard]] Eigen::Matrix<real, 1, 6> global_stress(index_t z) const noexcept {
    const mat3& rot = rotation_[at(zone_block_[at(z)])];
    const real r00 = rot(0, 0), r01 = rot(0, 1), r02 = rot(0, 2);
    const real r10 = rot(1, 0), r11 = rot(1, 1), r12 = rot(1, 2);
    const real r20 = rot(2, 0), r21 = rot(2, 1), r22 = rot(2, 2);
    const real rm[9] = {r00, r01, r02, r10, r11, r12, r20, r21, r22};
    const real s[6] = {local_stress_(z, 0), local_stress_(z, 1), local_stress_(z, 2),
                       local_stress_(z, 3), local_stress_(z, 4), local_stress_(z, 5)};
    real pm[9];
    detail::rotate_stress(rm, s, pm);  // P = R sigma', as in the kernel; then Sigma = P R^T
    const real p00 = pm[0], p01 = pm[1], p02 = pm[2], p10 = pm[3], p11 = pm[4], p12 = pm[5], p20 = pm[6],
               p21 = pm[7], p22 = pm[8];
    Eigen::Matrix<real, 1, 6> sigma;
    sigma << p00 * r00 + p01 * r01 + p02 * r02, p10 * r10 + p11 * r11 + p12 * r12,
        p20 * r20 + p21 * r21 + p22 * r22, p10 * r20 + p11 * r21 + p12 * r22, p20 * r00 + p21 * r01 + p22 * r02,
        p00 * r10 + p01 * r11 + p02 * r12;
    return sigma;
  }
  /// Global Cauchy stress of every zone at the last accumulate_forces (Pa, Voigt, tension +), one
  /// row per zone, assembled on each call (a value: O(zones) per call, so take it once rather
  /// than once per zone).
  [[nodiscard]] zone_stress_matrix zone_stress() const {
    zone_stress_matrix sigma(zone_count(), 6);
    for (index_t z = 0; z < zone_count(); ++z) sigma.row(z) = global_stress(z);
    return sigma;
  }
  /// The zone stresses as rows (rows(), row(z)), what the bars read each step for their host
  /// zones' confinement: a watched zone's row is the one its zone task formed, any other is
  /// formed on the call. Valid until the next step.
  struct stress_rows {
    const deformable* model = nullptr;  ///< the block model read
    [[nodiscard]] index_t rows() const noexcept { return model->zone_count(); }  ///< Number of zones
    [[nodiscard]] Eigen::Matrix<real, 1, 6> row(index_t z) const noexcept {  ///< Stress of zone z, Voigt order xx yy zz yz xz xy (Pa)
      const index_t w = model->watch_slot_[at(z)];
      return w != invalid_index ? Eigen::Matrix<real, 1, 6>(model->watched_stress_.row(w)) : model->global_stress(z);
    }
  };
  [[nodiscard]] stress_rows zone_stress_rows() const noexcept { return stress_rows{this}; }  ///< The zone stresses as rows

  /// Saves or loads the block rotations (the warm start of the next polar decomposition, so they
  /// are state: a restart without them would differ in the last bits) and the zones' block-frame
  /// stresses (io/checkpoint.hpp).
  template <class Archive>
  void checkpoint(Archive& ar) {
    ar.array("blocks/deformable/rotation", rotation_);
    ar.matrix("blocks/deformable/local_stress", local_stress_);
    if (ar.loading()) form_watched_stress(0, static_cast<index_t>(watch_zones_.size()));  // from what was loaded
  }

  /// Elastic energy stored in the zones, sum_z V_z W(eps_z) (J), with block rotations of the
  /// CURRENT displacements (the cached ones lag one step behind after the integrator has moved
  /// the gridpoints). Allocates; not for the time step.
  [[nodiscard]] real stored_energy(const node_set& gridpoints) const {
    std::vector<mat3> rotations = rotation_;
    for (index_t b = 0; b < block_count(); ++b)
      rotations[static_cast<std::size_t>(b)] = block_rotation(gridpoints, b, rotation_[static_cast<std::size_t>(b)]);
    return deterministic_sum(zone_count(), [&](std::int64_t z) {
      const index_t zi = static_cast<index_t>(z);
      const mat3 m = rotated_gradient(gridpoints, zi, rotations[static_cast<std::size_t>(zone_block_[static_cast<std::size_t>(zi)])]);
      voigt6 e;
      e << m(0, 0), m(1, 1), m(2, 2), m(1, 2) + m(2, 1), m(2, 0) + m(0, 2), m(0, 1) + m(1, 0);
      return volume_[at(zi)] * Zone::strain_energy_density(material_of_block(zone_block_[at(zi)]), e);
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
  [[nodiscard]] voigt6 zone_strain(const node_set& gridpoints, index_t z) const {
    const mat3 m = rotated_gradient(gridpoints, z, rotation_[static_cast<std::size_t>(zone_block_[static_cast<std::size_t>(z)])]);
    voigt6 e;
    e << m(0, 0), m(1, 1), m(2, 2), m(1, 2) + m(2, 1), m(2, 0) + m(0, 2), m(0, 1) + m(1, 0);
    return e;
  }

  [[nodiscard]] index_t block_count() const { return static_cast<index_t>(rotation_.size()); }  ///< Number of blocks
  [[nodiscard]] index_t zone_count() const { return static_cast<index_t>(volume_.size()); }  ///< Number of zones
  [[nodiscard]] real zone_volume(index_t z) const { return volume_[at(z)]; }  ///< Reference volume of zone z (m^3)
  /// Rotation R_b of block b at the last accumulate_forces.
  [[nodiscard]] const mat3& rotation(index_t b) const { return rotation_[static_cast<std::size_t>(b)]; }
  /// R_b = polar(F_b) of block b for the gridpoints' displacements now (warm-started from
  /// rotation(b)): the rotation the next accumulate_forces will use.
  [[nodiscard]] mat3 current_rotation(const node_set& gp, index_t b) const noexcept {
    return block_rotation(gp, b, rotation(b));
  }
  [[nodiscard]] index_t gridpoint_block(index_t i) const { return gridpoint_block_[static_cast<std::size_t>(i)]; }  ///< The block of gridpoint i
  /// Material of block b.
  [[nodiscard]] const params& material_of_block(index_t b) const { return materials_[at(block_material_[at(b)])]; }

 private:
  /// R_b = polar(F_b), F_b = 1 + sum_i u_i (x) w_i over the gridpoints of block b, warm-started
  /// from `previous`.
  [[nodiscard]] mat3 block_rotation(const node_set& gp, index_t b, const mat3& previous) const noexcept {
    return detail::polar_rotation(block_deformation_gradient(gp, b), previous);
  }
  /// F_b = 1 + sum_i u_i (x) w_i over the gridpoints of block b.
  [[nodiscard]] mat3 block_deformation_gradient(const node_set& gp, index_t b) const noexcept {
    mat3 f = mat3::Identity();
    const auto bs = static_cast<std::size_t>(b);
    for (index_t i = block_gridpoint_offsets_[bs]; i < block_gridpoint_offsets_[bs + 1]; ++i)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) f(r, c) += gp.displacement(i, r) * block_gradient_(i, c);
    return f;
  }

  /// R_b of every block: F_b block by block, the polar iterations of lanes::width blocks in
  /// lock-step (detail::polar_rotations; the same bits as block_rotation), over packs of blocks.
  void update_rotations(const node_set& gp) noexcept {
    constexpr index_t w = lanes::width;
    const index_t n_b = block_count();
    parallel_for((n_b + w - 1) / w, [&](std::int64_t pk) {
      const index_t first = static_cast<index_t>(pk) * w;
      update_rotations(gp, first, std::min<index_t>(first + w, n_b));
    }, 2);
  }
  /// R_b of blocks [b0, b1), serially, in packs of lanes::width from b0.
  void update_rotations(const node_set& gp, index_t b0, index_t b1) noexcept {
    constexpr index_t w = lanes::width;
    for (index_t first = b0; first < b1; first += w) {
      const int n = static_cast<int>(std::min<index_t>(w, b1 - first));
      mat3 f[w];
      for (int k = 0; k < n; ++k) f[k] = block_deformation_gradient(gp, first + k);
      detail::polar_rotations(f, rotation_.data() + first, n);
    }
  }

  /// R_b^T (1 + H_z) - 1 of zone z (its symmetric part is the co-rotated small strain).
  [[nodiscard]] mat3 rotated_gradient(const node_set& gp, index_t z, const mat3& r) const noexcept {
    const std::array<real, 12> g = gradients(z);
    mat3 h = mat3::Zero();  // displacement gradient H = sum_a u_a (x) grad N_a
    for (int a = 0; a < 4; ++a) {
      const index_t id = corner(z, a);
      const real u0 = gp.displacement(id, 0), u1 = gp.displacement(id, 1), u2 = gp.displacement(id, 2);
      const real* gr = g.data() + 3 * a;
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

  /// Global stress of the watched zones watch_zones_[w], w in [w0, w1), into watched_stress_ row w.
  void form_watched_stress(index_t w0, index_t w1) noexcept {
    for (index_t w = w0; w < w1; ++w) watched_stress_.row(w) = global_stress(watch_zones_[at(w)]);
  }

  std::vector<params> materials_;                   ///< per material id
  std::vector<typename Zone::constants> constants_;  ///< Zone::prepare of each material
  std::vector<int> block_material_;                 ///< material id of each block
  std::vector<mat3> rotation_;                      ///< R_b, warm start of the next polar decomposition
  Eigen::Matrix<real, Eigen::Dynamic, 12> corner_force_;  ///< row z: the 4 corner forces of zone z (N), column 3 a + i
  zone_stress_matrix local_stress_;                 ///< block-frame Cauchy stress sigma' per zone (Pa, Voigt)
  std::vector<index_t> watch_offsets_;                ///< per block: its watched zones in watch_zones_
  std::vector<index_t> watch_zones_;                  ///< watched zones, block by block
  std::vector<index_t> watch_slot_;                   ///< per zone: its place in watch_zones_, or invalid_index
  zone_stress_matrix watched_stress_;               ///< row w: global stress of zone watch_zones_[w] (Pa)
};

}  // namespace tessera::blocks
