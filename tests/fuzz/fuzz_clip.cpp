// libFuzzer target: a box clipped repeatedly by adversarial planes (convex_polyhedron::clip).
//
// Input layout (byte_reader, zeros past the end):
//   byte 0     length scale 10^(b % 7 - 3)
//   bytes 1-3  box edge lengths (1 + b / 32) x scale
//   then up to 48 cuts, each an opcode byte and operands:
//     0  normal from three i16, offset through the centroid shifted by (u16 / 65535 - 1/2) extent
//     1  normal from three i16, plane exactly through vertex j
//     2  plane through vertices j and k (normal: three i16 made orthogonal to the edge)
//     3  plane through vertices j, k and l (often a face plane or a diagonal of a face)
//     4  normal with components in {-1, 0, 1}, offset on the quarter lattice of the box
//     5  normal from three i16, shaving 10^-(5..15) extent off the farthest vertex
//     6  normal from three i16, offset beyond every vertex (must leave the polyhedron unchanged)
//     7  the flipped plane of the previous cut (keeps only a sliver or nothing)
//
// After every cut the polyhedron must be empty or: closed and manifold (each directed edge once,
// its reverse once; Euler characteristic 2), free of duplicate vertices (when no edge of the cut polyhedron
// was shorter than 1e-9 extent), every face a loop of at
// least 3 distinct vertices, convex (no vertex more than 1e-9 extent outside a face plane, plus
// the resolution of the vertices: the plane tolerances of earlier cuts, see require_valid),
// inside every cut made so far (within the documented maximal widening of the plane tolerance,
// 1e-6 of the extent), with a volume that is positive and no larger than before the cut, both up
// to the rounding of the coordinates and of the volume sum (see require_valid).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <tessera/core/errors.hpp>
#include <tessera/geometry/convex_polyhedron.hpp>

#include "fuzz_support.hpp"

namespace {

using tessera::index_t;
using tessera::real;
using tessera::vec3;
using tessera::detail::concat;
using tessera::fuzz::byte_reader;
using tessera::fuzz::finding;
using tessera::geometry::convex_polyhedron;
using tessera::geometry::plane;

// Reads are sequenced one per statement: the order of evaluation of function arguments is
// unspecified, and an input must decode the same way with every compiler.
vec3 raw_normal(byte_reader& in) {
  vec3 n;
  for (int a = 0; a < 3; ++a) n[a] = in.i16();
  return n;
}

// Rounding bound (m^3) of the signed-tetrahedron sum of p.volume(): about 4 eps |a||b||c| <=
// 4 eps (sqrt(3) L)^3 / 6 per fan triangle (coordinates relative to a reference point inside,
// L the extent); it dominates for slivers and needles, whose volume is << L^3.
real volume_rounding(const convex_polyhedron& p) {
  std::size_t triangles = 0;
  for (index_t f = 0; f < p.face_count(); ++f) triangles += p.face(f).size() - 2;
  const real extent = p.extent();
  return 4 * std::numeric_limits<real>::epsilon() * static_cast<real>(triangles) * 5.2 * extent * extent * extent / 6;
}

void require_valid(const convex_polyhedron& p, const std::vector<plane>& cuts, real extent0, real volume_before,
                   real volume_before_rounding, bool resolved, real resolution) {
  if (p.empty()) {
    if (p.vertex_count() != 0) finding(concat("empty polyhedron keeps ", p.vertex_count(), " vertices"));
    return;
  }
  const index_t nv = p.vertex_count();
  if (p.face_count() < 4) finding(concat("polyhedron with ", p.face_count(), " faces"));
  std::vector<std::pair<index_t, index_t>> edges;
  std::vector<char> used(static_cast<std::size_t>(nv), 0);
  for (index_t f = 0; f < p.face_count(); ++f) {
    const auto loop = p.face(f);
    if (loop.size() < 3) finding(concat("face ", f, " has ", loop.size(), " vertices"));
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const index_t a = loop[k], b = loop[(k + 1) % loop.size()];
      if (a < 0 || a >= nv) finding(concat("face ", f, " vertex id ", a, " out of range"));
      used[static_cast<std::size_t>(a)] = 1;
      edges.emplace_back(a, b);
      for (std::size_t m = k + 1; m < loop.size(); ++m)
        if (loop[m] == a) finding(concat("face ", f, " visits vertex ", a, " twice"));
    }
  }
  for (index_t v = 0; v < nv; ++v)
    if (!used[static_cast<std::size_t>(v)]) finding(concat("vertex ", v, " is used by no face"));
  std::sort(edges.begin(), edges.end());
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (e + 1 < edges.size() && edges[e] == edges[e + 1])
      finding(concat("directed edge ", edges[e].first, "->", edges[e].second, " used twice"));
    if (!std::binary_search(edges.begin(), edges.end(), std::make_pair(edges[e].second, edges[e].first)))
      finding(concat("edge ", edges[e].first, "->", edges[e].second, " has no reverse: the surface is open"));
  }
  if (p.euler_characteristic() != 2) finding(concat("Euler characteristic ", p.euler_characteristic()));
  std::vector<vec3> sorted = p.vertices();
  std::sort(sorted.begin(), sorted.end(),
            [](const vec3& a, const vec3& b) { return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3); });
  // Checked only when the cut polyhedron had no edge shorter than 1e-9 of its extent: nearly
  // parallel edges of a sub-tolerance sliver meet the plane in points that round to the same
  // position, a feature below the kernel's resolution that the tessellation cleanup welds.
  for (std::size_t k = 1; k < sorted.size() && resolved; ++k)
    if (sorted[k] == sorted[k - 1]) finding("two vertices at the same position");
  // Convexity tolerance: 1e-9 of the extent plus the propagated resolution of the vertices.
  // A vertex lies off the planes of its faces by up to delta, which tilts the normal of a face
  // whose smallest height is w by up to delta / w and so moves a vertex at distance `extent` by
  // extent delta / w. delta is an absolute length fixed when the vertex was made, at the scale
  // of the polyhedron of that cut, not of today's: a vertex classified "on" stays where it is,
  // up to the plane tolerance of its cut (1e-12 of the extent then, or 16 eps |x|) off the new
  // face, and an intersection point is rounded to eps |x| of the edge it was computed on. So
  // delta = max(4 eps |x|_max now, `resolution` = the largest plane tolerance of the cuts so
  // far). Measured on the two former open findings: a 1000 m box cut down to 1.5e-6 m (vertices
  // from the 1000 m cuts 1.2e-14 m = 8e-9 extents off their face) and a 528 m polyhedron cut down
  // to 1.4e-3 m (a vertex kept "on" 1e-10 m off plane 11, 7.6e-8 extents now). For a polyhedron
  // not shrunk by its cuts delta stays 1e-12 of the extent, so a face of height >= 1e-3 extent
  // is still held to 2e-9 of the extent: a misplaced vertex or wrong loop (an O(extent) error)
  // is caught.
  const real extent = p.extent();
  real coordinate_max = 0;
  for (const vec3& v : p.vertices()) coordinate_max = std::max(coordinate_max, v.cwiseAbs().maxCoeff());
  const real delta = std::max(4 * std::numeric_limits<real>::epsilon() * coordinate_max, resolution);
  for (index_t f = 0; f < p.face_count(); ++f) {
    const plane h = p.face_plane(f);
    const auto loop = p.face(f);
    real longest_edge = 0;
    for (std::size_t k = 0; k < loop.size(); ++k)
      longest_edge = std::max(longest_edge, (p.vertex(loop[(k + 1) % loop.size()]) - p.vertex(loop[k])).norm());
    const real height = 2 * p.face_area(f) / longest_edge;
    const real tol = 1e-9 * extent + 2 * delta + extent * delta / height;
    for (const vec3& v : p.vertices())
      if (h.signed_distance(v) > tol)
        finding(concat("vertex ", h.signed_distance(v) / extent, " extents outside face ", f, ": not convex"));
  }
  for (std::size_t c = 0; c < cuts.size(); ++c)
    for (const vec3& v : p.vertices())
      if (cuts[c].signed_distance(v) > 1e-6 * extent0)
        finding(concat("vertex ", cuts[c].signed_distance(v) / extent0, " extents outside cut ", c));
  // A cut removes volume. Allowed apparent growth: the rounding of the coordinates (delta x
  // area) plus that of the signed-tetrahedron sums before and after (volume_rounding), each at
  // the scale of its own polyhedron: a cut that leaves a 2.8e-5 m piece of a needle of extent 94 m compares
  // with a volume computed at 94 m (fuzz_clip, corpus/clip/clip_needle_base_volume: -4.0e-14
  // m^3 before, 1.8e-21 after; the former bound took both roundings at today's extent).
  const real volume = p.volume();
  real area = 0;
  for (index_t f = 0; f < p.face_count(); ++f) area += p.face_area(f);
  const real tetrahedron_sum_rounding = volume_rounding(p);
  // "Positive" up to rounding: clip does not resolve features thinner than its plane tolerance
  // (1e-12 extent), so a needle or a sliver below it may keep a volume that rounds to 0 (the
  // tessellation cleanup removes such cells); an inverted (clearly negative) volume is a finding.
  // The vertices are known to delta, which moves the volume by up to delta x area, as above
  // (fuzz_clip, corpus/clip/clip_speck_negative_volume: a needle of extent 94 m cut down to a
  // 3.1e-10 m speck, below the 1e-9 m resolution of the cuts of the 1000 m box, of volume
  // -6.1e-40 m^3; the bound had the tetrahedron-sum rounding, 1.9e-43 m^3, not 2 delta x area,
  // 1.2e-31 m^3).
  if (!(volume > -2 * tetrahedron_sum_rounding - 2 * delta * area))
    finding(concat("non-empty polyhedron of volume ", volume));
  if (volume > volume_before * (1 + 1e-12) + 2 * delta * area + tetrahedron_sum_rounding + volume_before_rounding)
    finding(concat("a cut grew the volume from ", volume_before, " to ", volume));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  byte_reader in(data, size);
  const real scale = std::pow(10.0, in.u8() % 7 - 3);
  vec3 hi;
  for (int a = 0; a < 3; ++a) hi[a] = (1 + in.u8() / 32.0) * scale;
  convex_polyhedron p = convex_polyhedron::box(vec3::Zero(), hi);
  const real extent0 = p.extent();
  std::vector<plane> cuts;
  plane previous = plane::through(vec3::UnitX(), 0.5 * hi);
  real resolution = 0;  // largest plane tolerance of the cuts so far (m), see require_valid
  for (int cut = 0; cut < 48 && !in.exhausted() && !p.empty(); ++cut) {
    const int op = in.u8() % 8;
    const tessera::index_t nv = p.vertex_count();
    const vec3& vj = p.vertex(in.u8() % nv);
    const vec3& vk = p.vertex(in.u8() % nv);
    const vec3& vl = p.vertex(in.u8() % nv);
    const real extent = p.extent();
    vec3 n = raw_normal(in);
    plane h;
    if (op == 0) {
      h = plane::through(n.normalized(), p.centroid());
      h.offset += (in.unit() - 0.5) * extent;
    } else if (op == 1) {
      h = plane::through(n.normalized(), vj);
    } else if (op == 2) {
      const vec3 e = (vk - vj).normalized();
      if ((vk - vj).norm() > 0) n -= n.dot(e) * e;
      h = plane::through(n.normalized(), vj);
    } else if (op == 3) {
      n = (vk - vj).cross(vl - vj);
      h = plane::through(n.normalized(), vj);
    } else if (op == 4) {
      for (int a = 0; a < 3; ++a) n[a] = in.u8() % 3 - 1;
      h = plane::through(n.normalized(), vec3::Zero());
      h.offset = (in.u8() % 9) * 0.25 * n.normalized().cwiseAbs().dot(hi);
    } else if (op == 5) {
      h = plane::through(n.normalized(), vec3::Zero());
      real far = -std::numeric_limits<real>::infinity();
      for (const vec3& v : p.vertices()) far = std::max(far, h.signed_distance(v));
      h.offset += far - std::pow(10.0, -5 - in.u8() % 11) * extent;
    } else if (op == 6) {
      h = plane::through(n.normalized(), p.centroid());
      h.offset += 2 * extent;
    } else {
      h = previous.flipped();
    }
    if (!h.normal.allFinite() || !std::isfinite(h.offset)) continue;  // zero normal: no plane
    const real volume_before = p.volume(), volume_before_rounding = volume_rounding(p);
    real shortest_edge = std::numeric_limits<real>::infinity();
    for (tessera::index_t f = 0; f < p.face_count(); ++f) {
      const auto loop = p.face(f);
      for (std::size_t k = 0; k < loop.size(); ++k)
        shortest_edge = std::min(shortest_edge, (p.vertex(loop[(k + 1) % loop.size()]) - p.vertex(loop[k])).norm());
    }
    const bool resolved = shortest_edge > 1e-9 * extent;
    // clip's default plane tolerance for this cut (convex_polyhedron::clip)
    real coordinate_max = std::abs(h.offset);
    for (const vec3& v : p.vertices()) coordinate_max = std::max(coordinate_max, v.cwiseAbs().maxCoeff());
    resolution = std::max({resolution, tessera::geometry::plane_tolerance_rel * extent,
                           tessera::geometry::plane_rounding_tolerance(coordinate_max)});
    const std::size_t vertices_before = p.vertices().size();
    bool changed = false;
    try {
      changed = p.clip(h, static_cast<tessera::index_t>(cut));
    } catch (const tessera::geometry_error& e) {
      finding(concat("clip of a valid convex polyhedron threw: ", e.what()));
    }
    if (op == 6 && (changed || p.vertices().size() != vertices_before)) finding("a plane beyond every vertex cut something");
    cuts.push_back(h);
    previous = h;
    require_valid(p, cuts, extent0, volume_before, volume_before_rounding, resolved, resolution);
  }
  return 0;
}
