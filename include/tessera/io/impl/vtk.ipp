// The definitions of the larger functions that io/vtk.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../vtk.hpp"

namespace tessera::io::vtk {

TESSERA_INLINE void write_blocks_vtu(const std::filesystem::path& path, const geometry::tessellation& tess,
                                     format fmt) {
  unstructured_grid grid;
  grid.set_points(tess.vertices);
  std::vector<std::int32_t> block_id;
  std::vector<double> volume;
  std::vector<std::vector<index_t>> faces;
  for (index_t c = 0; c < tess.cell_count(); ++c) {
    faces.clear();
    double volume6 = 0.0;
    for (index_t f = tess.first_face(c); f < tess.end_face(c); ++f) {
      const auto loop = tess.face(f);
      faces.emplace_back(loop.begin(), loop.end());
      // V = (1/6) sum over fan triangles of x0 . (x1 x x2) for outward-oriented faces.
      const vec3& x0 = tess.vertices[static_cast<std::size_t>(loop[0])];
      for (std::size_t i = 1; i + 1 < loop.size(); ++i)
        volume6 += x0.dot(tess.vertices[static_cast<std::size_t>(loop[i])].cross(tess.vertices[static_cast<std::size_t>(loop[i + 1])]));
    }
    grid.add_polyhedron(faces);
    block_id.push_back(c);
    volume.push_back(volume6 / 6.0);
  }
  grid.cell_data.add_scalar("block", std::span<const std::int32_t>(block_id));
  grid.cell_data.add_scalar("volume", std::span<const double>(volume));
  grid.write(path, fmt);
}

}  // namespace tessera::io::vtk
