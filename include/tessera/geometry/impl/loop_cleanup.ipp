// The definitions of the larger functions that geometry/loop_cleanup.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../loop_cleanup.hpp"

namespace tessera::geometry {

TESSERA_INLINE void clean_loop(std::vector<index_t>& loop) {
  bool changed = true;
  while (changed && !loop.empty()) {
    changed = false;
    std::size_t w = 0;
    for (std::size_t r = 0; r < loop.size(); ++r) {
      const index_t v = loop[r];
      if (w > 0 && loop[w - 1] == v) { changed = true; continue; }
      if (w > 1 && loop[w - 2] == v) { --w; changed = true; continue; }
      loop[w++] = v;
    }
    loop.resize(w);
    // wrap-around: last == first, or spike across the seam
    if (loop.size() > 1 && loop.back() == loop.front()) { loop.pop_back(); changed = true; }
    else if (loop.size() > 2 && loop[loop.size() - 2] == loop.front()) { loop.pop_back(); changed = true; }
    else if (loop.size() > 2 && loop.back() == loop[1]) { loop.erase(loop.begin()); changed = true; }
    if (loop.size() < 3) { loop.clear(); return; }
  }
}

TESSERA_INLINE void match_twins(tessellation& t) {
  t.face_twin.assign(t.face_cell.size(), invalid_index);
  for (index_t f = 0; f < t.face_count(); ++f) {
    const index_t c = t.face_cell[static_cast<std::size_t>(f)], n = t.face_neighbor[static_cast<std::size_t>(f)];
    if (n < 0 || c > n) continue;
    index_t g = invalid_index;
    for (index_t h = t.first_face(n); h < t.end_face(n); ++h)
      if (t.face_neighbor[static_cast<std::size_t>(h)] == c) { g = h; break; }
    require<geometry_error>(g != invalid_index, "tessellation cleanup: face ", f, " of cell ", c,
                            " has no twin in neighbour cell ", n, " (area ",
                            polygon_area_vector(t.vertices, t.face(f)).norm(), " m^2); increase cleanup_tolerance");
    const auto a = t.face(f), b = t.face(g);
    bool reversed = a.size() == b.size();
    if (reversed) {
      const std::size_t m = a.size();
      const auto start = std::find(b.begin(), b.end(), a[0]);
      reversed = start != b.end();
      if (reversed) {
        const std::size_t s = static_cast<std::size_t>(start - b.begin());
        for (std::size_t k = 0; k < m && reversed; ++k) reversed = a[k] == b[(s + m - k) % m];
      }
    }
    require<geometry_error>(reversed, "tessellation cleanup: face ", f, " of cell ", c, " (", a.size(),
                            " vertices) and its twin ", g, " of cell ", n, " (", b.size(),
                            " vertices) are not the same loop reversed; increase cleanup_tolerance");
    t.face_twin[static_cast<std::size_t>(f)] = g;
    t.face_twin[static_cast<std::size_t>(g)] = f;
    t.shared_faces.push_back({c, f, n, g});
  }
  for (index_t f = 0; f < t.face_count(); ++f)
    require<geometry_error>(t.face_neighbor[static_cast<std::size_t>(f)] < 0 || t.face_twin[static_cast<std::size_t>(f)] >= 0,
                            "tessellation cleanup: face ", f, " of cell ", t.face_cell[static_cast<std::size_t>(f)],
                            " toward cell ", t.face_neighbor[static_cast<std::size_t>(f)], " has no twin");
}

}  // namespace tessera::geometry
