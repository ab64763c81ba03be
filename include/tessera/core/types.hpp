#pragma once
// Basic types shared by every tessera module.
//
// Units: SI throughout (m, kg, s, N, Pa, J). Sign convention: normal stress and normal
// opening are positive in tension; a contact normal points from block A to block B.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>

namespace tessera {

/// Floating-point type of all physical quantities.
using real = double;
/// Index handle of an entity (vertex, face, block, gridpoint, zone, sub-contact, bar node).
/// Entities refer to each other by index, never by pointer, so arrays can be reordered,
/// copied and moved to another memory space without fix-ups. Named index_t, not index, so that
/// `using namespace tessera;` at file scope stays unambiguous beside POSIX index() (<strings.h>,
/// which <cstring> and other standard headers may pull in).
using index_t = std::int32_t;
inline constexpr index_t invalid_index = -1;

using vec3 = Eigen::Matrix<real, 3, 1>;
using mat3 = Eigen::Matrix<real, 3, 3>;

/// Axis-aligned box [lo, hi] (m).
struct aabb {
  vec3 lo = vec3::Constant(std::numeric_limits<real>::infinity());  ///< lower corner (m)
  vec3 hi = vec3::Constant(-std::numeric_limits<real>::infinity());  ///< upper corner (m)
  void expand(const vec3& p) { lo = lo.cwiseMin(p); hi = hi.cwiseMax(p); }  ///< Grows the box to hold p
  [[nodiscard]] vec3 size() const { return hi - lo; }  ///< hi - lo (m)
  [[nodiscard]] real volume() const { const vec3 s = size(); return s.x() * s.y() * s.z(); }  ///< Volume (m^3)
  [[nodiscard]] bool contains(const vec3& p, real tol = 0) const {  ///< True when p lies in the box enlarged by tol (m)
    return (p.array() >= lo.array() - tol).all() && (p.array() <= hi.array() + tol).all();
  }
};

}  // namespace tessera
