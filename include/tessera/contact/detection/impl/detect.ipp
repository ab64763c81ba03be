// The definitions of the larger functions that contact/detection/detect.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include <algorithm>
#include <limits>

#include "../detect.hpp"

namespace tessera::contact::detection {

TESSERA_INLINE void detect(std::span<const geometry::convex_polyhedron> blocks, std::span<const polyhedron_edges> edges,
                           std::span<const aabb> boxes, const detection_options& options, detection_result& out,
                           detection_workspace& w, detection_share share, std::span<const std::uint8_t> only,
                           std::span<const block_pair> skip, const placed_faces& placed,
                           const std::function<void(std::size_t)>& prepare) {
  require(edges.size() == blocks.size() && boxes.size() == blocks.size() &&
              (only.empty() || only.size() == blocks.size()),
          "detect: ", blocks.size(), " blocks, ", edges.size(), " edge lists, ", boxes.size(), " boxes and ",
          only.size(), " marks: give one of each per block (marks: or none)");
  require(skip.empty() || !only.empty(), "detect: ", skip.size(), " skipped pairs in a pass without marks");
  require(placed.empty() || (placed.first.size() == blocks.size() + 1 && placed.rotation.size() == blocks.size() &&
                             placed.shift.size() == blocks.size() &&
                             placed.normal.size() == static_cast<std::size_t>(placed.first.back()) &&
                             placed.centroid.size() == placed.normal.size()),
          "detect: placed faces for ", placed.first.size(), " - 1 blocks with ", placed.normal.size(), " normals, ",
          placed.centroid.size(), " centroids, ", placed.rotation.size(), " rotations and ", placed.shift.size(),
          " shifts, for ", blocks.size(), " blocks: give one CSR entry per block, one normal and centroid per face");
  for (std::size_t b = 0; !placed.empty() && b < blocks.size(); ++b)
    require(placed.first[b + 1] - placed.first[b] == blocks[b].face_count(), "detect: block ", b, " has ",
            blocks[b].face_count(), " faces and ", placed.first[b + 1] - placed.first[b], " placed faces");
  require(std::isfinite(options.tolerance) && options.tolerance > 0, "detect: contact tolerance = ", options.tolerance,
          " m must be finite and > 0");
  require(share.parts >= 1 && share.part >= 0 && share.part < share.parts, "detect: part ", share.part, " of ",
          share.parts, " parts: need parts >= 1 and 0 <= part < parts");
  // The grid unless the layout would need too many cells (a few huge boxes): then sort and sweep.
  if (const grid_layout g = layout_grid(boxes, options.margin); g.suits(boxes.size()))
    uniform_grid(boxes, options.margin, g, w.candidates, w.grid, only);  // (the marked blocks' pairs only)
  else
    sweep_and_prune(boxes, options.margin, w.candidates, w.sweep);
  // An incremental pass: the candidates of the marked blocks (kept in order), and the blocks
  // whose face planes they read.
  const auto marked = [&](const block_pair& c) {
    return only.empty() || only[static_cast<std::size_t>(c.a)] != 0 || only[static_cast<std::size_t>(c.b)] != 0;
  };
  // Whether pair c is in `skip`, for pairs asked in increasing order (a cursor over skip, from 0).
  const auto skipped = [&](std::size_t& s, const block_pair& c) {
    while (s < skip.size() && skip[s] < c) ++s;
    return s < skip.size() && skip[s] == c;
  };
  w.needs_faces.assign(blocks.size(), only.empty() ? 1 : 0);
  if (!only.empty()) {
    std::size_t kept = 0, s = 0;
    for (std::size_t i = 0; i < w.candidates.size(); ++i)
      if (const block_pair c = w.candidates[i]; !skipped(s, c) && marked(c)) w.candidates[kept++] = c;
    w.candidates.resize(kept);
    for (const block_pair& c : w.candidates)
      w.needs_faces[static_cast<std::size_t>(c.a)] = w.needs_faces[static_cast<std::size_t>(c.b)] = 1;
  }
  // reuse_axes: each candidate's kept axis (both lists increasing: one merge).
  if (options.reuse_axes) {
    w.hints.assign(w.candidates.size(), axis_hint{});
    std::size_t k = 0;
    for (std::size_t i = 0; i < w.candidates.size(); ++i) {
      while (k < w.axis_pairs.size() && w.axis_pairs[k] < w.candidates[i]) ++k;
      if (k < w.axis_pairs.size() && w.axis_pairs[k] == w.candidates[i]) w.hints[i] = w.axes[k];
    }
  }
  // The blocks' face planes, once per pass (the pairs read them, rather than each candidate
  // pair computing both blocks' normals again).
  w.face_first.assign(1, 0);
  for (const geometry::convex_polyhedron& p : blocks) w.face_first.push_back(w.face_first.back() + p.face_count());
  w.faces.resize(static_cast<std::size_t>(w.face_first.back()));
  parallel_for_dynamic(static_cast<std::int64_t>(blocks.size()), [&](std::int64_t k) {  // (the marked blocks cluster)
    const auto b = static_cast<std::size_t>(k);
    if (w.needs_faces[b] == 0) return;
    if (prepare) prepare(b);
    const auto out_first = static_cast<std::size_t>(w.face_first[b]);
    if (placed.empty()) {
      for (index_t f = 0; f < blocks[b].face_count(); ++f) w.faces[out_first + static_cast<std::size_t>(f)] = blocks[b].face_plane(f);
      return;
    }
    const mat3& r = placed.rotation[b];
    const vec3& t = placed.shift[b];
    const auto first = static_cast<std::size_t>(placed.first[b]), last = static_cast<std::size_t>(placed.first[b + 1]);
    for (std::size_t f = first; f < last; ++f) {
      const vec3 n = (r * placed.normal[f]).normalized();
      w.faces[out_first + (f - first)] = geometry::plane::through(n, r * placed.centroid[f] + t);
    }
  }, 64);
  const std::size_t n = w.candidates.size();
  const auto cut = [&](int p) { return n * static_cast<std::size_t>(p) / static_cast<std::size_t>(share.parts); };
  const std::size_t first = cut(share.part), last = cut(share.part + 1);
  w.planes.resize(n);
  w.patches.resize(n);
  w.skipped.assign(options.reuse_axes ? n : 0, 0);
  // (Pairs cost a kept axis's test or a full search and the costly ones cluster by block: the
  // threads take runs of 16 pairs as they come free.)
  parallel_for_dynamic(static_cast<std::int64_t>(last - first), [&](std::int64_t k) {
    const auto i = first + static_cast<std::size_t>(k);
    const auto a = static_cast<std::size_t>(w.candidates[i].a), b = static_cast<std::size_t>(w.candidates[i].b);
    const auto faces_a = w.faces_of(a), faces_b = w.faces_of(b);
    // A kept axis that still separates the pair by more than the tolerance: not touching.
    // Otherwise its gap (2 ties under the axis's) is the floor of the search (warm start).
    real floor = -std::numeric_limits<real>::infinity();
    if (options.reuse_axes && w.hints[i].names_axis()) {
      w.planes[i] = hinted_plane(blocks[a], edges[a], faces_a, blocks[b], edges[b], faces_b, w.hints[i]);
      if (w.planes[i].gap > options.tolerance) {
        w.patches[i].clear();
        w.skipped[i] = 1;
        return;
      }
      floor = w.planes[i].gap;
    }
    w.planes[i] = common_plane_above(blocks[a], edges[a], faces_a, blocks[b], edges[b], faces_b, floor);
    // (Each slot's patch is written in place, its vectors' capacity kept: none is allocated.)
    if (w.planes[i].gap <= options.tolerance)
      contact_patch_into(blocks[a], blocks[b], w.planes[i], options.tolerance, faces_a, faces_b, w.patches[i]);
    else
      w.patches[i].clear();
  }, 16);
  // The kept axes, merged in pair order: this pass's candidates with this pass's plane's axis
  // (those of another part: the axis they had), and the kept pairs of two unmarked blocks or
  // skipped, which this pass did not look at.
  if (options.reuse_axes) {
    w.next_pairs.clear();
    w.next_axes.clear();
    std::size_t k = 0, s = 0;
    const auto keep_old_until = [&](const block_pair* before) {
      for (; k < w.axis_pairs.size() && (before == nullptr || w.axis_pairs[k] < *before); ++k)
        if (skipped(s, w.axis_pairs[k]) || !marked(w.axis_pairs[k])) {
          w.next_pairs.push_back(w.axis_pairs[k]);
          w.next_axes.push_back(w.axes[k]);
        }
    };
    for (std::size_t i = 0; i < n; ++i) {
      keep_old_until(&w.candidates[i]);
      const axis_hint h = i >= first && i < last ? axis_hint::of(w.planes[i]) : w.hints[i];
      if (i >= first && i < last) w.axis_skips += w.skipped[i];
      if (!h.names_axis()) continue;
      w.next_pairs.push_back(w.candidates[i]);
      w.next_axes.push_back(h);
    }
    keep_old_until(nullptr);
    w.axis_pairs.swap(w.next_pairs);
    w.axes.swap(w.next_axes);
  }
  out.candidates = n;
  out.evaluated = last - first;
  out.clear_pairs();
  for (std::size_t i = first; i < last; ++i) {
    const contact_patch& p = w.patches[i];
    if (p.type == patch_type::none) continue;
    out.pairs.push_back(w.candidates[i]);
    out.planes.push_back(w.planes[i]);
    out.type.push_back(p.type);
    out.point.insert(out.point.end(), p.points.begin(), p.points.end());
    out.gap.insert(out.gap.end(), p.gap.begin(), p.gap.end());
    out.area.insert(out.area.end(), p.area.begin(), p.area.end());
    out.label.insert(out.label.end(), p.label.begin(), p.label.end());
    out.first_corner.push_back(static_cast<index_t>(out.point.size()));
  }
}

}  // namespace tessera::contact::detection
