// The definitions of the larger functions that io/neper.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include "../neper.hpp"

namespace tessera::io {

[[nodiscard]] TESSERA_INLINE geometry::tessellation read_neper_tess(std::istream& in, const std::string& name) {
  detail::tess_tokens tok(in, name);
  constexpr long long max_count = 100'000'000;
  if (tok.done() || tok.peek() != "***tess") tok.fail("the file must start with ***tess");
  tok.next("***tess");

  index_t cell_count = -1;
  std::vector<vec3> seeds;
  std::vector<real> weights;
  std::vector<vec3> vertices;
  std::vector<std::pair<index_t, index_t>> edges;
  std::vector<std::vector<index_t>> faces;
  std::vector<int> face_line;
  std::vector<std::vector<index_t>> polyhedra;  // unsigned 0-based face ids
  bool have_vertex = false, have_face = false, have_polyhedron = false, ended = false;
  std::vector<std::string> sections_read;  // each **section at most once, so counts stay consistent

  while (!tok.done() && !ended) {
    const int marker_line = tok.line();
    const std::string marker = tok.next("a section");
    tok.set_section(marker);
    if (marker.rfind("**", 0) == 0) {
      if (std::find(sections_read.begin(), sections_read.end(), marker) != sections_read.end())
        tok.fail_at(marker_line, "section " + marker + " appears twice");
      sections_read.push_back(marker);
    }
    if (marker == "***end") {
      ended = true;
    } else if (marker == "**format") {
      const std::string version = tok.next("format version");
      if (version.rfind("3.", 0) != 0) tok.fail_at(marker_line, "format version '" + version + "' is not supported (3.x expected)");
    } else if (marker == "**general") {
      const long long dim = tok.integer("dimension");
      if (dim != 3) tok.fail_at(marker_line, tessera::detail::concat("dimension ", dim, " is not supported (3 expected)"));
      tok.skip_to_marker();  // tessellation type
    } else if (marker == "**cell") {
      cell_count = tok.count("number of cells", 1, max_count);
      while (!tok.done() && tok.at_marker() && tok.peek().rfind("**", 0) != 0) {
        const std::string sub = tok.next("a subsection");
        tok.set_section("**cell " + sub);
        if (sub == "*seed") {
          if (!seeds.empty()) tok.fail("subsection *seed appears twice");
          for (index_t c = 0; c < cell_count; ++c) {
            const int l = tok.line();
            if (tok.integer("seed id") != c + 1) tok.fail_at(l, tessera::detail::concat("seed id must be ", c + 1));
            vec3 p;
            for (int a = 0; a < 3; ++a) p[a] = tok.number("seed coordinate");
            seeds.push_back(p);
            weights.push_back(tok.number("seed weight"));
          }
        }
        tok.skip_to_marker();  // *id, *ori, *crysym, ... are not used
      }
    } else if (marker == "**vertex") {
      const index_t n = tok.count("number of vertices", 4, max_count);
      for (index_t v = 0; v < n; ++v) {
        const int l = tok.line();
        if (tok.integer("vertex id") != v + 1)
          tok.fail_at(l, tessera::detail::concat("vertex id must be ", v + 1, " (consecutive from 1)"));
        vec3 p;
        for (int a = 0; a < 3; ++a) p[a] = tok.number("vertex coordinate");
        vertices.push_back(p);
        tok.skip_line();  // state
      }
      have_vertex = true;
    } else if (marker == "**edge") {
      const index_t n = tok.count("number of edges", 0, max_count);
      for (index_t e = 0; e < n; ++e) {
        const int l = tok.line();
        if (tok.integer("edge id") != e + 1) tok.fail_at(l, tessera::detail::concat("edge id must be ", e + 1));
        const index_t a = tok.count("edge vertex", 1, static_cast<long long>(vertices.size()));
        const index_t b = tok.count("edge vertex", 1, static_cast<long long>(vertices.size()));
        edges.emplace_back(a - 1, b - 1);
        tok.skip_line();
      }
    } else if (marker == "**face") {
      if (!have_vertex) tok.fail_at(marker_line, "**face before **vertex");
      const index_t n = tok.count("number of faces", 4, max_count);
      for (index_t f = 0; f < n; ++f) {
        const int l = tok.line();
        if (tok.integer("face id") != f + 1) tok.fail_at(l, tessera::detail::concat("face id must be ", f + 1));
        const index_t nver = tok.count("number of face vertices", 3, 100000);
        std::vector<index_t> loop;
        for (index_t k = 0; k < nver; ++k) loop.push_back(tok.count("face vertex id", 1, static_cast<long long>(vertices.size())) - 1);
        const index_t nedge = tok.count("number of face edges", 3, 100000);
        for (index_t k = 0; k < nedge; ++k) {
          const int le = tok.line();
          const long long e = tok.integer("face edge id");
          const auto ne = static_cast<long long>(edges.size());
          if (e == 0 || e < -ne || e > ne)  // not llabs: llabs(LLONG_MIN) overflows
            tok.fail_at(le, tessera::detail::concat("face edge id ", e, " out of range [1, ", edges.size(), "]"));
        }
        for (int k = 0; k < 4; ++k) (void)tok.number("face equation coefficient");
        tok.skip_line();  // state, point type and point coordinates
        faces.push_back(std::move(loop));
        face_line.push_back(l);
      }
      have_face = true;
    } else if (marker == "**polyhedron") {
      if (!have_face) tok.fail_at(marker_line, "**polyhedron before **face");
      const index_t n = tok.count("number of polyhedra", 1, max_count);
      for (index_t p = 0; p < n; ++p) {
        const int l = tok.line();
        if (tok.integer("polyhedron id") != p + 1) tok.fail_at(l, tessera::detail::concat("polyhedron id must be ", p + 1));
        const index_t nface = tok.count("number of polyhedron faces", 4, 100000);
        std::vector<index_t> list;
        for (index_t k = 0; k < nface; ++k) {
          const int lf = tok.line();
          const long long f = tok.integer("polyhedron face id");
          const auto nf = static_cast<long long>(faces.size());
          if (f == 0 || f < -nf || f > nf)  // not llabs: llabs(LLONG_MIN) overflows
            tok.fail_at(lf, tessera::detail::concat("polyhedron ", p + 1, ": face id ", f, " out of range [1, ", faces.size(), "]"));
          list.push_back(static_cast<index_t>((f < 0 ? -f : f) - 1));
        }
        polyhedra.push_back(std::move(list));
      }
      have_polyhedron = true;
    } else if (marker == "**domain") {
      while (!tok.done() && tok.at_marker() && tok.peek().rfind("**", 0) != 0) {
        const std::string sub = tok.next("a subsection");
        tok.set_section("**domain " + sub);
        if (sub == "*general") {
          const int l = tok.line();
          const std::string type = tok.next("domain type");
          if (type != "cube") tok.fail_at(l, "domain type '" + type + "' is not a box ('cube' expected)");
        }
        tok.skip_to_marker();
      }
    } else if (marker.front() == '*') {
      tok.skip_to_marker();  // sections tessera does not use (e.g. **periodicity, **scale)
    } else {
      tok.fail_at(marker_line, "expected a section marker (**name), got '" + marker + "'");
    }
  }
  tok.set_section("");
  if (!ended) tok.fail("missing ***end (truncated file?)");
  if (!have_vertex || !have_face || !have_polyhedron) tok.fail("**vertex, **face and **polyhedron sections are required");
  if (cell_count >= 0 && cell_count != static_cast<index_t>(polyhedra.size()))
    tok.fail(tessera::detail::concat("**cell declares ", cell_count, " cells but **polyhedron lists ", polyhedra.size()));

  geometry::tessellation t;
  for (const vec3& v : vertices) t.domain.expand(v);
  const vec3 size = t.domain.size();
  if (!((size.array() > 0).all()))
    tok.fail(tessera::detail::concat("the vertices span a degenerate box of size (", size.x(), ", ", size.y(), ", ", size.z(), ")"));
  const real tol = 1e-9 * size.maxCoeff();

  // Which polyhedra use each face.
  std::vector<std::vector<index_t>> users(faces.size());
  for (std::size_t p = 0; p < polyhedra.size(); ++p)
    for (index_t f : polyhedra[p]) users[static_cast<std::size_t>(f)].push_back(static_cast<index_t>(p));
  std::vector<int> boundary_side(faces.size(), -1);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& u = users[f];
    if (u.size() > 2 || (u.size() == 2 && u[0] == u[1]))
      tok.fail_at(face_line[f], tessera::detail::concat("face ", f + 1, " is used ", u.size(), " times by polyhedra (at most twice, by two different ones)"));
    if (u.size() != 1) continue;
    for (int s = 0; s < 6 && boundary_side[f] < 0; ++s) {
      const int axis = s / 2;
      const real x = (s % 2) ? t.domain.hi[axis] : t.domain.lo[axis];
      bool on = true;
      for (index_t v : faces[f]) on = on && std::abs(vertices[static_cast<std::size_t>(v)][axis] - x) <= tol;
      if (on) boundary_side[f] = s;
    }
    if (boundary_side[f] < 0)
      tok.fail_at(face_line[f], tessera::detail::concat("face ", f + 1, " belongs to one polyhedron only but does not lie on a side of the domain box"));
    const int axis = boundary_side[f] / 2;
    const real x = (boundary_side[f] % 2) ? t.domain.hi[axis] : t.domain.lo[axis];
    for (index_t v : faces[f]) vertices[static_cast<std::size_t>(v)][axis] = x;
  }
  t.vertices = vertices;
  t.seeds = seeds;
  if (std::any_of(weights.begin(), weights.end(), [](real w) { return w != 0; })) t.weights = weights;

  // Per-cell faces, oriented outward from the cell's vertex centroid.
  std::vector<index_t> stored(faces.size() * 2, invalid_index);  // (face, user slot) -> tessellation face
  for (std::size_t p = 0; p < polyhedra.size(); ++p) {
    vec3 centre = vec3::Zero();
    std::size_t count = 0;
    for (index_t f : polyhedra[p])
      for (index_t v : faces[static_cast<std::size_t>(f)]) { centre += t.vertices[static_cast<std::size_t>(v)]; ++count; }
    centre /= static_cast<real>(count);
    for (index_t f : polyhedra[p]) {
      const auto& loop = faces[static_cast<std::size_t>(f)];
      const vec3 area = geometry::polygon_area_vector(t.vertices, loop);
      const vec3 fc = geometry::polygon_centroid(t.vertices, loop);
      const real outward = area.dot(fc - centre);
      if (!(std::abs(outward) > 0))
        tok.fail_at(face_line[static_cast<std::size_t>(f)], tessera::detail::concat("face ", f + 1, " of polyhedron ", p + 1, " is degenerate (zero area or through the cell centre)"));
      const std::size_t start = t.face_vertices.size();
      t.face_vertices.insert(t.face_vertices.end(), loop.begin(), loop.end());
      if (outward < 0) std::reverse(t.face_vertices.begin() + static_cast<std::ptrdiff_t>(start), t.face_vertices.end());
      t.face_offsets.push_back(static_cast<index_t>(t.face_vertices.size()));
      t.face_cell.push_back(static_cast<index_t>(p));
      const auto& u = users[static_cast<std::size_t>(f)];
      const std::size_t slot = (u[0] == static_cast<index_t>(p)) ? 0 : 1;
      t.face_neighbor.push_back(u.size() == 2 ? u[1 - slot] : geometry::boundary_tag(boundary_side[static_cast<std::size_t>(f)]));
      stored[2 * static_cast<std::size_t>(f) + slot] = t.face_count() - 1;
    }
    t.cell_face_offsets.push_back(static_cast<index_t>(t.face_cell.size()));
  }
  t.face_twin.assign(t.face_cell.size(), invalid_index);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (users[f].size() != 2) continue;
    index_t a = stored[2 * f], b = stored[2 * f + 1];
    if (t.face_cell[static_cast<std::size_t>(a)] > t.face_cell[static_cast<std::size_t>(b)]) std::swap(a, b);
    t.face_twin[static_cast<std::size_t>(a)] = b;
    t.face_twin[static_cast<std::size_t>(b)] = a;
    t.shared_faces.push_back({t.face_cell[static_cast<std::size_t>(a)], a, t.face_cell[static_cast<std::size_t>(b)], b});
  }
  std::sort(t.shared_faces.begin(), t.shared_faces.end(),
            [](const auto& x, const auto& y) { return x.face_a < y.face_a; });
  return t;
}

}  // namespace tessera::io
