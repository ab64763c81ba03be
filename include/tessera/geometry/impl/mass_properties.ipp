// The definitions of the larger functions that geometry/mass_properties.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../mass_properties.hpp"

namespace tessera::geometry {

[[nodiscard]] TESSERA_INLINE vec3 polygon_centroid(std::span<const vec3> vertices, std::span<const index_t> loop) {
  const std::size_t n = loop.size();
  if (n == 0) return vec3::Zero();
  const std::size_t k0 = fan_apex(loop);
  const vec3& a = vertices[static_cast<std::size_t>(loop[k0])];
  const vec3 area = polygon_area_vector(vertices, loop);
  const real area2 = area.squaredNorm();
  vec3 mean = vec3::Zero();
  for (index_t v : loop) mean += vertices[static_cast<std::size_t>(v)];
  mean /= static_cast<real>(n);
  if (!(area2 > 0)) return mean;  // degenerate (collinear) loop: vertex average
  vec3 first = vec3::Zero();
  for (std::size_t t = 1; t + 1 < n; ++t) {
    const vec3& b = vertices[static_cast<std::size_t>(loop[(k0 + t) % n])];
    const vec3& c = vertices[static_cast<std::size_t>(loop[(k0 + t + 1) % n])];
    // signed triangle area measured along the polygon normal: handles any planar loop
    const real w = real(0.5) * (b - a).cross(c - a).dot(area) / std::sqrt(area2);
    first += w * (a + b + c) / 3;
  }
  return first / area.norm();
}

[[nodiscard]] TESSERA_INLINE mass_properties polyhedron_mass_properties(std::span<const vec3> vertices,
                                                                        std::span<const index_t> face_offsets,
                                                                        std::span<const index_t> face_vertices) {
  mass_properties mp;
  if (face_offsets.size() < 2) return mp;
  const vec3 r = detail::reference_point(vertices, face_offsets, face_vertices);
  real six_v = 0;
  vec3 first = vec3::Zero();  // 24 * first moment
  mat3 second = mat3::Zero(); // 120 * second moment
  detail::for_each_fan_tetrahedron(vertices, face_offsets, face_vertices, r,
                                   [&](const vec3& a, const vec3& b, const vec3& c) {
                                     const real w = a.dot(b.cross(c));  // 6 V_t
                                     const vec3 s = a + b + c;
                                     six_v += w;
                                     first += w * s;
                                     second += w * (a * a.transpose() + b * b.transpose() + c * c.transpose() +
                                                    s * s.transpose());
                                   });
  mp.volume = six_v / 6;
  if (!(std::abs(six_v) > 0)) {
    mp.centroid = r;
    return mp;
  }
  const vec3 c_rel = first / (4 * six_v);                 // (int x dV) / V = (sum w s / 24) / (sum w / 6)
  mp.centroid = r + c_rel;
  mp.second_moment = second / 120 - mp.volume * c_rel * c_rel.transpose();  // parallel-axis shift
  return mp;
}

}  // namespace tessera::geometry
