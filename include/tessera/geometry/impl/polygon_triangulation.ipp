// The definitions of the larger functions that geometry/polygon_triangulation.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../polygon_triangulation.hpp"

namespace tessera::geometry {

TESSERA_INLINE real min_angle_triangulation(std::span<const vec3> vertices, std::span<const index_t> loop,
                                            std::vector<std::array<index_t, 3>>& out, triangulation_workspace& ws) {
  const int n = static_cast<int>(loop.size());
  const auto at = [](auto i) { return static_cast<std::size_t>(i); };
  // ---- canonical sequence: smallest id first, towards its smaller neighbour ----
  int start = 0;
  for (int k = 1; k < n; ++k)
    if (loop[at(k)] < loop[at(start)]) start = k;
  const bool forward = loop[at((start + 1) % n)] < loop[at((start + n - 1) % n)];
  ws.sequence.resize(at(n));
  ws.points.resize(at(n));
  for (int k = 0; k < n; ++k) {
    const int pos = forward ? (start + k) % n : (start + n - k) % n;
    ws.sequence[at(k)] = loop[at(pos)];
    ws.points[at(k)] = vertices[at(loop[at(pos)])];
  }
  const auto emit = [&](int i, int k, int j) {
    const index_t a = ws.sequence[at(i)], b = ws.sequence[at(k)], c = ws.sequence[at(j)];
    out.push_back(forward ? std::array<index_t, 3>{a, b, c} : std::array<index_t, 3>{a, c, b});
  };
  if (n == 3) {
    emit(0, 1, 2);
    return min_corner_angle(ws.points[0], ws.points[1], ws.points[2]);
  }
  // Newell normal of the canonical sequence (same bits for both twins).
  vec3 normal = vec3::Zero();
  for (int k = 0; k < n; ++k) normal += ws.points[at(k)].cross(ws.points[at((k + 1) % n)]);

  const auto cell = [n](int i, int j) { return static_cast<std::size_t>(i * n + j); };
  ws.score.assign(at(n * n), std::numeric_limits<real>::infinity());
  ws.split.assign(at(n * n), -1);
  for (int gap = 2; gap < n; ++gap)
    for (int i = 0; i + gap < n; ++i) {
      const int j = i + gap;
      real best = -std::numeric_limits<real>::infinity();
      int best_k = i + 1;
      for (int k = i + 1; k < j; ++k) {
        const vec3& a = ws.points[at(i)];
        const vec3& b = ws.points[at(k)];
        const vec3& c = ws.points[at(j)];
        const real angle = (b - a).cross(c - a).dot(normal) > 0 ? min_corner_angle(a, b, c) : real(-1);
        const real s = std::min({ws.score[cell(i, k)], ws.score[cell(k, j)], angle});
        if (s > best) { best = s; best_k = k; }
      }
      ws.score[cell(i, j)] = best;
      ws.split[cell(i, j)] = best_k;
    }
  const real result = ws.score[cell(0, n - 1)];
  if (!(result > 0)) {
    for (int k = 1; k + 1 < n; ++k) emit(0, k, k + 1);
    return result;
  }
  ws.stack.clear();
  ws.stack.push_back({0, n - 1});
  while (!ws.stack.empty()) {
    const auto [i, j] = ws.stack.back();
    ws.stack.pop_back();
    if (j - i < 2) continue;
    const int k = ws.split[cell(i, j)];
    emit(i, k, j);
    ws.stack.push_back({k, j});
    ws.stack.push_back({i, k});
  }
  return result;
}

}  // namespace tessera::geometry
