// libFuzzer target: arbitrary bytes as a Neper .tess file.
//
// Acceptable outcomes: a tessellation whose index structure is consistent (every id in range,
// CSR offsets monotone, twins mutual, seeds/weights empty or one per cell), or a tessera::error
// with a non-empty message. Anything else (a sanitizer report, another exception type, a hang)
// is a finding. A tessellation that is read successfully is also fed to geometry::check(), which
// must not crash on it whatever the geometry is.

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include <tessera/core/errors.hpp>
#include <tessera/geometry/tessellation_queries.hpp>
#include <tessera/io/neper.hpp>

#include "fuzz_support.hpp"

namespace {

using tessera::index_t;
using tessera::detail::concat;
using tessera::fuzz::finding;

void require_structure(const tessera::geometry::tessellation& t) {
  const index_t nc = t.cell_count(), nf = t.face_count(), nv = t.vertex_count();
  if (nc < 1) finding(concat("reader returned ", nc, " cells"));
  if (t.face_offsets.empty() || t.face_offsets.front() != 0 ||
      t.face_offsets.back() != static_cast<index_t>(t.face_vertices.size()))
    finding("face_offsets do not span face_vertices");
  for (index_t f = 0; f < nf; ++f)
    if (t.face_offsets[static_cast<std::size_t>(f) + 1] - t.face_offsets[static_cast<std::size_t>(f)] < 3)
      finding(concat("face ", f, " has fewer than 3 vertices"));
  for (index_t v : t.face_vertices)
    if (v < 0 || v >= nv) finding(concat("face vertex id ", v, " out of [0, ", nv, ")"));
  if (t.cell_face_offsets.front() != 0 || t.cell_face_offsets.back() != nf) finding("cell_face_offsets do not span faces");
  for (index_t c = 0; c < nc; ++c)
    if (t.end_face(c) < t.first_face(c) + 4) finding(concat("cell ", c, " has fewer than 4 faces"));
  if (t.face_cell.size() != static_cast<std::size_t>(nf) || t.face_neighbor.size() != static_cast<std::size_t>(nf) ||
      t.face_twin.size() != static_cast<std::size_t>(nf))
    finding("per-face arrays differ in size from the face count");
  for (index_t c = 0; c < nc; ++c)
    for (index_t f = t.first_face(c); f < t.end_face(c); ++f)
      if (t.face_cell[static_cast<std::size_t>(f)] != c) finding(concat("face ", f, " listed by cell ", c, " but owned by another"));
  for (index_t f = 0; f < nf; ++f) {
    const index_t n = t.face_neighbor[static_cast<std::size_t>(f)], g = t.face_twin[static_cast<std::size_t>(f)];
    if (n >= nc || (n < 0 && tessera::geometry::boundary_side(n) > 5)) finding(concat("face ", f, " neighbour ", n));
    if (n < 0 && g != tessera::invalid_index) finding(concat("boundary face ", f, " has a twin"));
    if (n >= 0 && (g < 0 || g >= nf || t.face_twin[static_cast<std::size_t>(g)] != f ||
                   t.face_cell[static_cast<std::size_t>(g)] != n))
      finding(concat("interior face ", f, " has no mutual twin"));
  }
  for (const auto& s : t.shared_faces)
    if (s.cell_a >= s.cell_b || s.face_a < 0 || s.face_a >= nf || s.face_b < 0 || s.face_b >= nf)
      finding("inconsistent shared_faces entry");
  if (!t.seeds.empty() && t.seeds.size() != static_cast<std::size_t>(nc))
    finding(concat(t.seeds.size(), " seeds for ", nc, " cells"));
  if (!t.weights.empty() && t.weights.size() != static_cast<std::size_t>(nc))
    finding(concat(t.weights.size(), " weights for ", nc, " cells"));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const tessera::geometry::tessellation t = tessera::io::read_neper_tess(in, "fuzz.tess");
    require_structure(t);
    (void)tessera::geometry::check(t);
  } catch (const tessera::error& e) {
    if (std::string(e.what()).empty()) finding("tessera::error with an empty message");
  }
  // Any other exception propagates out of this function: libFuzzer reports it as a crash.
  return 0;
}
