// libFuzzer target: Voronoi and Laguerre tessellations of adversarial generator sets.
//
// Input layout (byte_reader, zeros past the end):
//   byte 0   flags: bit 0 Laguerre; bits 1-3 coordinate lattice (none, 1, 2, 3, 4, 5, 8, 16
//            divisions of the box: coplanar, cocircular and cospherical sets); bits 4-6 length
//            scale 10^(k - 3), k = 0..6; bit 7 box shifted off the origin
//   byte 1   number of generators N = 3 + byte % 62 (3..64)
//   bytes 2-4  box edge lengths (1 + b / 32) x scale (anisotropic boxes)
//   (bit 7)  3 bytes of box offset
//   per generator: an opcode byte, a byte j selecting an earlier generator, and the operands:
//     0-2  a point from three u16 (on the lattice when one is selected; 0 and 65535 are the sides)
//     3    generator j plus 10^-(9..13) L along one of 13 directions (nearly coincident pair)
//     4    an exact copy of generator j (coincident: invalid_input expected)
//     5    on a box side, edge or corner: per axis a byte (lo, hi, interior) and, for interior, a u16
//     6    on the sphere of radius 0.4 min(size) around the box centre, along one of 26
//          lattice directions or 12 icosahedron vertices (cospherical sets)
//     7    generator j with one coordinate replaced (collinear/coplanar with j)
//   Laguerre: a weight scale byte (0, 1e-12, 1e-6, 1e-3, 1e-2, 0.1, 0.5, 2) x L^2, then one byte
//   per generator, w_i = scale (b - 128) / 128.
//
// Acceptable outcomes: a tessellation that passes geometry::check() (volume error < 1e-9 of the
// box, every interior face matched by its reversed twin, every cell closed), whose vertices lie
// within the weld resolution of the planes that define their faces and whose cells are convex
// up to what that resolution allows (require_convex); for Voronoi also each surviving cell
// containing its generator; or tessera::invalid_input
// / geometry_error with a non-empty message. With TESSERA_FUZZ_STRICT_GEOMETRY=1 in the
// environment a geometry_error for generators that passed validation is a finding too.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

#include <tessera/core/errors.hpp>
#include <tessera/geometry/tessellation_queries.hpp>
#include <tessera/geometry/voronoi.hpp>

#include "fuzz_support.hpp"

namespace {

using tessera::aabb;
using tessera::index_t;
using tessera::real;
using tessera::vec3;
using tessera::detail::concat;
using tessera::fuzz::byte_reader;
using tessera::fuzz::finding;

struct fuzz_case {
  aabb box;
  std::vector<vec3> seeds;
  std::vector<real> weights;
  bool laguerre = false;
};

vec3 direction(std::uint8_t code) {
  // 26 lattice directions (-1, 0, 1)^3 minus zero, then the 12 icosahedron vertices
  const int k = code % 38;
  if (k < 26) {
    const int m = k < 13 ? k : k + 1;  // skip the centre of the 3x3x3 block
    return vec3(m % 3 - 1, (m / 3) % 3 - 1, m / 9 - 1).normalized();
  }
  const real phi = (1 + std::sqrt(5.0)) / 2;
  const int i = k - 26, s1 = (i & 1) ? -1 : 1, s2 = (i & 2) ? -1 : 1;
  const vec3 v = i < 4 ? vec3(0, s1, s2 * phi) : i < 8 ? vec3(s1, s2 * phi, 0) : vec3(s2 * phi, 0, s1);
  return v.normalized();
}

fuzz_case decode(byte_reader& in) {
  fuzz_case fc;
  const std::uint8_t flags = in.u8();
  fc.laguerre = flags & 1;
  static constexpr std::array<int, 8> lattice{0, 1, 2, 3, 4, 5, 8, 16};
  const int divisions = lattice[(flags >> 1) & 7];
  const real scale = std::pow(10.0, ((flags >> 4) & 7) % 7 - 3);
  const int n = 3 + in.u8() % 62;
  vec3 size;
  for (int a = 0; a < 3; ++a) size[a] = (1 + in.u8() / 32.0) * scale;
  vec3 lo = vec3::Zero();
  if (flags & 0x80)
    for (int a = 0; a < 3; ++a) lo[a] = (in.u8() - 128) / 16.0 * scale;
  fc.box = aabb{lo, lo + size};
  const real spacing = std::cbrt(size.prod() / n);

  auto coordinate = [&](int a) {
    real u = in.unit();
    if (divisions > 0) u = std::round(u * divisions) / divisions;
    return lo[a] + u * size[a];
  };
  auto clamp_to_box = [&](vec3 p) { return p.cwiseMax(fc.box.lo).cwiseMin(fc.box.hi); };
  for (int i = 0; i < n; ++i) {
    const int op = in.u8() % 8;
    const std::uint8_t j_byte = in.u8();
    const std::size_t j = fc.seeds.empty() ? 0 : j_byte % fc.seeds.size();
    vec3 p;
    if (op <= 2 || (fc.seeds.empty() && (op == 3 || op == 4 || op == 7))) {
      for (int a = 0; a < 3; ++a) p[a] = coordinate(a);
    } else if (op == 3) {
      const real gap = std::pow(10.0, -9 - in.u8() % 5) * spacing;
      p = clamp_to_box(fc.seeds[j] + gap * direction(in.u8() % 26));
    } else if (op == 4) {
      p = fc.seeds[j];
    } else if (op == 5) {
      for (int a = 0; a < 3; ++a) {
        const int where = in.u8() % 3;
        p[a] = where == 0 ? fc.box.lo[a] : where == 1 ? fc.box.hi[a] : coordinate(a);
      }
    } else if (op == 6) {
      const vec3 centre = 0.5 * (fc.box.lo + fc.box.hi);
      p = clamp_to_box(centre + 0.4 * size.minCoeff() * direction(in.u8()));
    } else {
      p = fc.seeds[j];
      const int a = in.u8() % 3;
      p[a] = coordinate(a);
    }
    fc.seeds.push_back(p);
  }
  if (fc.laguerre) {
    static constexpr std::array<real, 8> weight_scale{0, 1e-12, 1e-6, 1e-3, 1e-2, 0.1, 0.5, 2};
    const real w = weight_scale[in.u8() % 8] * spacing * spacing;
    for (int i = 0; i < n; ++i) fc.weights.push_back(w * (in.u8() - 128) / 128.0);
  }
  return fc;
}

// Convexity, in place of check()'s nonconvex_cells (a vertex more than 1e-9 of the cell extent
// outside a face plane fitted through the face's vertices). The cleanup (cleanup.hpp) places a
// welded vertex at one of its members, each exactly on its own planes, at most tol = 1e-9 L
// apart in each coordinate (the weld tolerance, L the mean cell size), then snaps it onto a box
// side within tol: so it lies within delta_max = 2 sqrt(3) tol < 4 tol of the defining plane of
// each of its faces (the power plane of the cell and its neighbour, or the box side); a cluster
// spread wider than tol is recomputed by least squares, held to the same bound. That is checked
// first and catches a misplaced vertex; so does the second check, every vertex of a cell inside
// the defining plane of each of its faces within 1e-9 extent + delta_max. The fitted plane of
// a face whose vertices are within delta of the defining planes of their faces is off its own
// by at most delta at the centroid and tilted by at most delta P / A (P perimeter, A area: the
// Newell area vector changes by at most delta P); a vertex x (at most sqrt(3) extent from the
// centroid) that the weld moved by rho_x, measured the same way, is outside it by at most
//     1e-9 extent + 2 delta + rho_x + sqrt(3) extent delta P / A
// (corpus/tessellation/voronoi_weld_moved_vertex: a welded vertex 8.3e-8 m off one of its
// planes is 6.9e-8 m = 1.13e-9 extents outside an accurate face of its cell).
// For cells of well separated generators delta is rounding (1e-13 L) and the bound stays 1e-9 of
// the extent, as strict as check(); it grows only for faces whose vertices the weld moved, and
// most for faces not much larger than tol, whose fitted plane is then undetermined
// (corpus/tessellation/voronoi_weld_scale_face: a generator 7.7e-8 m = 1e-9 L from one of a
// cospherical set gives a 1.5e-7 m face whose welded vertices are 4.9e-8 m off its bisector; its
// fitted plane puts a vertex 15 m away 7.2 m outside, while every vertex is inside every
// defining plane of its cell within 4.9e-8 m).
void require_convex(const fuzz_case& fc, const tessera::geometry::tessellation& t) {
  namespace g = tessera::geometry;
  const real weld = 1e-9 * std::cbrt(fc.box.volume() / static_cast<real>(fc.seeds.size()));
  const real delta_max = 4 * weld;
  auto weight = [&](index_t c) { return t.weights.empty() ? real(0) : t.weights[static_cast<std::size_t>(c)]; };
  std::vector<g::plane> exact;
  std::vector<real> rho;  // per vertex: largest distance from the defining planes of its faces
  for (index_t c = 0; c < t.cell_count(); ++c) {
    const g::convex_polyhedron p = g::cell_polyhedron(t, c);
    const real extent = p.extent();
    exact.clear();
    rho.assign(static_cast<std::size_t>(p.vertex_count()), 0);
    for (index_t f = 0; f < p.face_count(); ++f) {
      const index_t nb = p.face_tag(f);
      if (nb >= 0) {
        exact.push_back(g::power_plane(t.seeds[static_cast<std::size_t>(c)], weight(c), t.seeds[static_cast<std::size_t>(nb)], weight(nb)));
      } else {
        const int side = g::boundary_side(nb), axis = side / 2;
        exact.push_back((side % 2) ? g::plane{vec3::Unit(axis), fc.box.hi[axis]} : g::plane{-vec3::Unit(axis), -fc.box.lo[axis]});
      }
      for (index_t v : p.face(f)) {
        real& r = rho[static_cast<std::size_t>(v)];
        r = std::max(r, std::abs(exact.back().signed_distance(p.vertex(v))));
      }
    }
    for (index_t f = 0; f < p.face_count(); ++f) {
      const g::plane& h = exact[static_cast<std::size_t>(f)];
      const auto loop = p.face(f);
      real delta = 0, perimeter = 0;
      for (std::size_t k = 0; k < loop.size(); ++k) {
        delta = std::max(delta, rho[static_cast<std::size_t>(loop[k])]);
        perimeter += (p.vertex(loop[(k + 1) % loop.size()]) - p.vertex(loop[k])).norm();
      }
      if (delta > delta_max)
        finding(concat("cell ", c, " face ", f, " (neighbour ", p.face_tag(f), "): a vertex ", delta,
                       " m off a defining plane of its faces, > ", delta_max, " m = 4 x the weld tolerance"));
      const g::plane fitted = p.face_plane(f);
      const real tilt = std::sqrt(3.0) * extent * delta * perimeter / p.face_area(f);
      for (index_t v = 0; v < p.vertex_count(); ++v) {
        const real rho_v = rho[static_cast<std::size_t>(v)];
        if (h.signed_distance(p.vertex(v)) > 1e-9 * extent + delta_max)  // well conditioned
          finding(concat("cell ", c, " not convex: a vertex ", h.signed_distance(p.vertex(v)),
                         " m outside the defining plane of face ", f, " (neighbour ", p.face_tag(f), ")"));
        const real tol = 1e-9 * extent + 2 * delta + rho_v + tilt;
        if (fitted.signed_distance(p.vertex(v)) > tol)
          finding(concat("cell ", c, " not convex: a vertex ", fitted.signed_distance(p.vertex(v)) / extent,
                         " extents outside face ", f, " (bound ", tol / extent, ")"));
      }
    }
  }
}

void require_valid(const fuzz_case& fc, const tessera::geometry::tessellation& t) {
  namespace g = tessera::geometry;
  const g::tessellation_report r = g::check(t);
  if (!(r.volume_error_rel < 1e-9)) finding(concat("volume_error_rel = ", r.volume_error_rel, " >= 1e-9"));
  if (r.unmatched_faces != 0) finding(concat(r.unmatched_faces, " unmatched faces"));
  if (r.open_cells != 0) finding(concat(r.open_cells, " open cells"));
  require_convex(fc, t);
  if (t.cell_count() < 1) finding("no cell");
  if (fc.laguerre) return;
  // A Voronoi cell thinner than the weld tolerance (a generator on a box edge with a neighbour
  // 1e-10 away) is dropped by the cleanup (cleanup.hpp, step 3); the survivors keep their
  // generators, in order, and each contains its own.
  if (t.cell_count() > static_cast<index_t>(fc.seeds.size()) || t.seeds.size() != static_cast<std::size_t>(t.cell_count()))
    finding(concat("Voronoi tessellation of ", fc.seeds.size(), " generators has ", t.cell_count(), " cells and ",
                   t.seeds.size(), " seeds"));
  const real tol = 1e-9 * fc.box.size().maxCoeff();
  for (index_t c = 0; c < t.cell_count(); ++c)
    if (!g::cell_polyhedron(t, c).contains(t.seeds[static_cast<std::size_t>(c)], tol))
      finding(concat("Voronoi cell ", c, " does not contain its generator"));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  byte_reader in(data, size);
  const fuzz_case fc = decode(in);
  static const bool strict = [] {
    const char* s = std::getenv("TESSERA_FUZZ_STRICT_GEOMETRY");
    return s && std::string(s) == "1";
  }();
  try {
    const tessera::geometry::tessellation t =
        fc.laguerre ? tessera::geometry::laguerre(fc.box, fc.seeds, fc.weights) : tessera::geometry::voronoi(fc.box, fc.seeds);
    require_valid(fc, t);
  } catch (const tessera::invalid_input& e) {
    if (std::string(e.what()).empty()) finding("invalid_input with an empty message");
  } catch (const tessera::geometry_error& e) {
    if (std::string(e.what()).empty()) finding("geometry_error with an empty message");
    if (strict) finding(concat("geometry_error for validated generators: ", e.what()));
  } catch (const tessera::error& e) {
    finding(concat("unexpected tessera::error type: ", e.what()));
  }
  return 0;
}
