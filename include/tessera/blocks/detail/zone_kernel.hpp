#pragma once
// The arithmetic of the constant-strain zones of blocks::deformable (its file comment gives the
// kinematics): zone_kernel, per run of consecutive zones of one block, the co-rotated small strain,
// the zone model's stress and the corner forces, over structure-of-arrays zone data
// (zone_geometry, zone_layout.hpp); rotate_stress, P = R sigma', which the kernel's forces and the
// on-demand global stress (deformable::global_stress) share, so both are the same bits.
// No allocation; a run writes only its own zones' entries.

#include <algorithm>
#include <cstddef>

#include <Eigen/Core>

#include "../../core/parallel.hpp"
#include "../../core/types.hpp"
#include "../concepts.hpp"
#include "zone_layout.hpp"

namespace tessera::blocks::detail {

/// sigma' = Zone::stress(eps) on plain arrays (Voigt, Pa). A zone model that provides
/// Zone::stress(constants, const real (&)[6], real (&)[6]) keeps the zone loop free of Eigen
/// temporaries, which GCC cannot vectorise across zones (linear_elastic_tet does); otherwise
/// the voigt6 form of the ZoneModel concept is used.
template <class Zone>
[[gnu::always_inline]] inline void zone_model_stress(const typename Zone::constants& p, const real (&eps)[6],
                                                     real (&sigma)[6]) noexcept {
  if constexpr (requires { Zone::stress(p, eps, sigma); }) {
    Zone::stress(p, eps, sigma);
  } else {
    const voigt6 s = Zone::stress(p, voigt6(Eigen::Map<const voigt6>(eps)));
    for (int k = 0; k < 6; ++k) sigma[k] = s[k];
  }
}

/// P = R sigma' (row i: global component, column k: block frame; r = R row by row, s = sigma'
/// in Voigt order xx yy zz yz zx xy), for the zone kernel's corner forces and for
/// global_stress: one set of expressions, so the global stress formed on demand is the one the
/// kernel's forces used, to the bit.
[[gnu::always_inline]] inline void rotate_stress(const real (&r)[9], const real (&s)[6], real (&p)[9]) noexcept {
  for (int i = 0; i < 3; ++i) {
    p[3 * i + 0] = r[3 * i] * s[0] + r[3 * i + 1] * s[5] + r[3 * i + 2] * s[4];
    p[3 * i + 1] = r[3 * i] * s[5] + r[3 * i + 1] * s[1] + r[3 * i + 2] * s[3];
    p[3 * i + 2] = r[3 * i] * s[4] + r[3 * i + 1] * s[3] + r[3 * i + 2] * s[2];
  }
}

/// Zones per pack of the zone kernel's vector loop (see zone_kernel): two 8-wide vectors with
/// AVX-512, 0 (plain loop) otherwise.
#if defined(__AVX512F__)
inline constexpr index_t zone_pack = 16;
#else
inline constexpr index_t zone_pack = 0;
#endif

/// Zone forces and stresses of the zones of run r of `geo` (consecutive zones of one block b, of
/// rotation `rot` = R_b; u: the gridpoints' displacement columns), written to `corner_force`
/// (column 3 a + i of zone z at corner_force[(3 a + i) n_z + z], N) and `local_stress` (Voigt
/// component k of sigma' at local_stress[k n_z + z], Pa), n_z the zone count. Per zone, with g_a = grad N_a (g_0 = -(g_1 + g_2 + g_3)):
///     H = sum_{a=0..3} u_a (x) g_a,   M = R^T H,
///     eps = sym(M) + sym(R^T) - 1 (Voigt, engineering shears; sym(R^T) - 1 once per run),
///     sigma' = Zone::stress(eps) (kept),   P = R sigma'   (Sigma = P R^T: global_stress),
///     f_a = -V P g_a (a = 1..3),   f_0 = -(f_1 + f_2 + f_3).
/// Scalar straight-line code over structure-of-arrays zone data, so the loop over the zones
/// of a run vectorises (omp simd; the results of a zone do not depend on which thread or
/// vector lane computes it, since runs are never split).
/// One function on purpose (about 110 lines): the per-zone body is one straight-line block
/// the compiler vectorises across the zones of the run; helpers taking the zone's arrays would
/// hide that from it.
template <class Zone>
void zone_kernel(const typename Zone::constants& p, const mat3& rot, const zone_geometry& geo, const real* const u[3],
                 std::size_t r, real* const corner_force, real* const local_stress) noexcept {
  const real r00 = rot(0, 0), r01 = rot(0, 1), r02 = rot(0, 2);
  const real r10 = rot(1, 0), r11 = rot(1, 1), r12 = rot(1, 2);
  const real r20 = rot(2, 0), r21 = rot(2, 1), r22 = rot(2, 2);
  // sym(R^T) - 1 in Voigt form (engineering shears).
  const real q0 = r00 - 1, q1 = r11 - 1, q2 = r22 - 1, q3 = r12 + r21, q4 = r20 + r02, q5 = r01 + r10;
  const real rm[9] = {r00, r01, r02, r10, r11, r12, r20, r21, r22};
  const real* const ux = u[0];
  const real* const uy = u[1];
  const real* const uz = u[2];
  const index_t* const c0 = geo.corner_[0].data();
  const index_t* const c1 = geo.corner_[1].data();
  const index_t* const c2 = geo.corner_[2].data();
  const index_t* const c3 = geo.corner_[3].data();
  const real* const g[12] = {geo.gradient_[0].data(), geo.gradient_[1].data(), geo.gradient_[2].data(),
                             geo.gradient_[3].data(), geo.gradient_[4].data(), geo.gradient_[5].data(),
                             geo.gradient_[6].data(), geo.gradient_[7].data(), geo.gradient_[8].data(),
                             geo.gradient_[9].data(), geo.gradient_[10].data(), geo.gradient_[11].data()};
  const real* const vol = geo.volume_.data();
  const auto n_z = static_cast<std::ptrdiff_t>(geo.volume_.size());
  real* const f = corner_force;  // column 3 a + i: component i of corner a, over zones
  real* const sig = local_stress;  // column k: Voigt component k of sigma', over zones
  const auto zone = [&](index_t z) __attribute__((always_inline)) {
    const index_t i0 = c0[z], i1 = c1[z], i2 = c2[z], i3 = c3[z];
    const real u0x = ux[i0], u0y = uy[i0], u0z = uz[i0];
    const real u1x = ux[i1], u1y = uy[i1], u1z = uz[i1];
    const real u2x = ux[i2], u2y = uy[i2], u2z = uz[i2];
    const real u3x = ux[i3], u3y = uy[i3], u3z = uz[i3];
    const real g0x = g[0][z], g0y = g[1][z], g0z = g[2][z];
    const real g1x = g[3][z], g1y = g[4][z], g1z = g[5][z];
    const real g2x = g[6][z], g2y = g[7][z], g2z = g[8][z];
    const real g3x = g[9][z], g3y = g[10][z], g3z = g[11][z];
    // Displacement gradient H (row i, column k) = sum_a u_a[i] grad N_a[k].
    const real hxx = u0x * g0x + u1x * g1x + u2x * g2x + u3x * g3x;
    const real hxy = u0x * g0y + u1x * g1y + u2x * g2y + u3x * g3y;
    const real hxz = u0x * g0z + u1x * g1z + u2x * g2z + u3x * g3z;
    const real hyx = u0y * g0x + u1y * g1x + u2y * g2x + u3y * g3x;
    const real hyy = u0y * g0y + u1y * g1y + u2y * g2y + u3y * g3y;
    const real hyz = u0y * g0z + u1y * g1z + u2y * g2z + u3y * g3z;
    const real hzx = u0z * g0x + u1z * g1x + u2z * g2x + u3z * g3x;
    const real hzy = u0z * g0y + u1z * g1y + u2z * g2y + u3z * g3y;
    const real hzz = u0z * g0z + u1z * g1z + u2z * g2z + u3z * g3z;
    // M = R^T H (row i: local, column k: reference), M_ik = sum_j R_ji H_jk.
    const real mxx = r00 * hxx + r10 * hyx + r20 * hzx, mxy = r00 * hxy + r10 * hyy + r20 * hzy,
               mxz = r00 * hxz + r10 * hyz + r20 * hzz;
    const real myx = r01 * hxx + r11 * hyx + r21 * hzx, myy = r01 * hxy + r11 * hyy + r21 * hzy,
               myz = r01 * hxz + r11 * hyz + r21 * hzz;
    const real mzx = r02 * hxx + r12 * hyx + r22 * hzx, mzy = r02 * hxy + r12 * hyy + r22 * hzy,
               mzz = r02 * hxz + r12 * hyz + r22 * hzz;
    // eps = sym(M) + sym(R^T) - 1 (Voigt, engineering shears).
    const real eps[6] = {q0 + mxx, q1 + myy, q2 + mzz, q3 + (myz + mzy), q4 + (mzx + mxz), q5 + (mxy + myx)};
    real s[6];
    zone_model_stress<Zone>(p, eps, s);
    real pm[9];
    rotate_stress(rm, s, pm);  // P = R sigma'
    const real p00 = pm[0], p01 = pm[1], p02 = pm[2], p10 = pm[3], p11 = pm[4], p12 = pm[5], p20 = pm[6],
               p21 = pm[7], p22 = pm[8];
    // The block-frame stress is kept; the global Sigma = P R^T is formed by the zone task for
    // the watched zones and on demand for the others (global_stress): most zones never need
    // it, and forming it in every zone cost 7.5 % of the zone update (docs/performance.md).
    for (int k = 0; k < 6; ++k) sig[k * n_z + z] = s[k];
    // Corner forces f_a = -V P g_a, f_0 = -(f_1 + f_2 + f_3).
    const real mv = -vol[z];
    const real m00 = mv * p00, m01 = mv * p01, m02 = mv * p02;
    const real m10 = mv * p10, m11 = mv * p11, m12 = mv * p12;
    const real m20 = mv * p20, m21 = mv * p21, m22 = mv * p22;
    const real f1x = m00 * g1x + m01 * g1y + m02 * g1z, f1y = m10 * g1x + m11 * g1y + m12 * g1z,
               f1z = m20 * g1x + m21 * g1y + m22 * g1z;
    const real f2x = m00 * g2x + m01 * g2y + m02 * g2z, f2y = m10 * g2x + m11 * g2y + m12 * g2z,
               f2z = m20 * g2x + m21 * g2y + m22 * g2z;
    const real f3x = m00 * g3x + m01 * g3y + m02 * g3z, f3y = m10 * g3x + m11 * g3y + m12 * g3z,
               f3z = m20 * g3x + m21 * g3y + m22 * g3z;
    f[0 * n_z + z] = -(f1x + f2x + f3x);
    f[1 * n_z + z] = -(f1y + f2y + f3y);
    f[2 * n_z + z] = -(f1z + f2z + f3z);
    f[3 * n_z + z] = f1x;
    f[4 * n_z + z] = f1y;
    f[5 * n_z + z] = f1z;
    f[6 * n_z + z] = f2x;
    f[7 * n_z + z] = f2y;
    f[8 * n_z + z] = f2z;
    f[9 * n_z + z] = f3x;
    f[10 * n_z + z] = f3y;
    f[11 * n_z + z] = f3z;
  };
  // With 512-bit vectors the zones of the run go in packs of zone_pack, the last pack shifted
  // back to end at `last` (it recomputes a few zones of the previous pack, writing the same
  // values), so every zone goes through the vector loop: runs are ~30 zones, and GCC's scalar
  // remainder loop would take a fifth of them (-3 ns per zone on the bench preset's AVX-512).
  // With 2- or 4-wide vectors the remainder is small and the overlap would cost more than it
  // saves, so the plain loop is kept. Each zone's arithmetic is the same in any lane, so the
  // results do not depend on the packing.
  const index_t first = geo.run_offsets_[r], last = geo.run_offsets_[r + 1];
  if (zone_pack == 0 || last - first < zone_pack) {
TESSERA_PRAGMA_SIMD
    for (index_t z = first; z < last; ++z) zone(z);
    return;
  }
  for (index_t start = first;; start += zone_pack) {
    const index_t pack_first = std::min(start, last - zone_pack);
TESSERA_PRAGMA_SIMD
    for (index_t k = 0; k < zone_pack; ++k) zone(pack_first + k);
    if (pack_first == last - zone_pack) break;
  }
}

}  // namespace tessera::blocks::detail
