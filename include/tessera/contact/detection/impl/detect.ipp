// The definitions of the larger functions that contact/detection/detect.hpp declares (their documentation is
// there): included at the end of that header, or compiled once into tessera::instances under
// TESSERA_SEPARATE_COMPILATION (core/separate_compilation.hpp).
#pragma once

#include <algorithm>
#include <array>
#include <limits>

#include "../detect.hpp"

namespace tessera::contact::detection {

TESSERA_INLINE void detect(std::span<const geometry::convex_polyhedron> blocks, std::span<const polyhedron_edges> edges,
                           std::span<const aabb> boxes, const detection_options& options, detection_result& out,
                           detection_workspace& w, detection_share share, std::span<const std::uint8_t> only,
                           std::span<const block_pair> skip) {
  require(edges.size() == blocks.size() && boxes.size() == blocks.size() &&
              (only.empty() || only.size() == blocks.size()),
          "detect: ", blocks.size(), " blocks, ", edges.size(), " edge lists, ", boxes.size(), " boxes and ",
          only.size(), " marks: give one of each per block (marks: or none)");
  require(skip.empty() || !only.empty(), "detect: ", skip.size(), " skipped pairs in a pass without marks");
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
  // The merges below in `parts` chunks of the candidates, one a thread (2+ threads, >= 256
  // candidates and kept axes): chunk c holds candidates [part(c), part(c + 1)) and the kept axes from the first
  // not before its first candidate (kept_from), so it merges as the one thread would from there;
  // each chunk counts what it writes, then writes it from the counts of the chunks before it.
  const std::size_t n_cand = w.candidates.size();
  const std::size_t parts = std::clamp<std::size_t>((n_cand + w.axis_pairs.size()) / 256, 1,
                                                     std::min<std::size_t>(std::max<std::size_t>(n_cand, 1), static_cast<std::size_t>(std::min(max_threads(), 64))));
  const auto part = [&](std::size_t c) { return n_cand * c / parts; };
  std::array<std::size_t, 65> kept_from{}, skip_from{}, before{};
  for (std::size_t c = 1; c < parts; ++c) {
    const block_pair& x = w.candidates[part(c)];
    kept_from[c] = static_cast<std::size_t>(std::lower_bound(w.axis_pairs.begin(), w.axis_pairs.end(), x) - w.axis_pairs.begin());
    skip_from[c] = static_cast<std::size_t>(std::lower_bound(skip.begin(), skip.end(), x) - skip.begin());
  }
  kept_from[parts] = w.axis_pairs.size();
  const auto each_part = [&](auto&& f) {
    parallel_for(static_cast<std::int64_t>(parts), [&](std::int64_t c) { f(static_cast<std::size_t>(c)); }, 1);
  };
  const auto sum_before = [&] {  // (before[c + 1]: chunk c's count -> the counts of chunks 0..c)
    for (std::size_t c = 0; c < parts; ++c) before[c + 1] += before[c];
    return before[parts];
  };
  // reuse_axes: each candidate's kept axis (both lists increasing: one merge a chunk).
  if (options.reuse_axes) {
    w.hints.assign(n_cand, axis_hint{});
    each_part([&](std::size_t c) {
      std::size_t k = kept_from[c];
      for (std::size_t i = part(c); i < part(c + 1); ++i) {
        while (k < w.axis_pairs.size() && w.axis_pairs[k] < w.candidates[i]) ++k;
        if (k < w.axis_pairs.size() && w.axis_pairs[k] == w.candidates[i]) w.hints[i] = w.axes[k];
      }
    });
  }
  // The blocks' face planes, once per pass (the pairs read them, rather than each candidate
  // pair computing both blocks' normals again).
  w.face_first.assign(1, 0);
  for (const geometry::convex_polyhedron& p : blocks) w.face_first.push_back(w.face_first.back() + p.face_count());
  w.faces.resize(static_cast<std::size_t>(w.face_first.back()));
  parallel_for_dynamic(static_cast<std::int64_t>(blocks.size()), [&](std::int64_t k) {  // (the marked blocks cluster)
    const auto b = static_cast<std::size_t>(k);
    if (w.needs_faces[b] == 0) return;
    for (index_t f = 0; f < blocks[b].face_count(); ++f)
      w.faces[static_cast<std::size_t>(w.face_first[b] + f)] = blocks[b].face_plane(f);
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
    std::array<std::size_t, 64> skips{};
    const auto merge_part = [&](std::size_t c, bool write) {
      std::size_t k = kept_from[c], s = skip_from[c], to = write ? before[c] : 0;
      const auto emit = [&](const block_pair& p, axis_hint h) {
        if (write) {
          w.next_pairs[to] = p;
          w.next_axes[to] = h;
        }
        ++to;
      };
      const auto keep_old_until = [&](const block_pair* before_pair) {
        for (; k < kept_from[c + 1] && (before_pair == nullptr || w.axis_pairs[k] < *before_pair); ++k)
          if (skipped(s, w.axis_pairs[k]) || !marked(w.axis_pairs[k])) emit(w.axis_pairs[k], w.axes[k]);
      };
      for (std::size_t i = part(c); i < part(c + 1); ++i) {
        keep_old_until(&w.candidates[i]);
        const axis_hint h = i >= first && i < last ? axis_hint::of(w.planes[i]) : w.hints[i];
        if (!write && i >= first && i < last) skips[c] += w.skipped[i];
        if (h.names_axis()) emit(w.candidates[i], h);
      }
      keep_old_until(nullptr);
      if (!write) before[c + 1] = to;
    };
    before.fill(0);
    each_part([&](std::size_t c) { merge_part(c, false); });
    const std::size_t kept = sum_before();
    w.next_pairs.resize(kept);
    w.next_axes.resize(kept);
    each_part([&](std::size_t c) { merge_part(c, true); });
    for (std::size_t c = 0; c < parts; ++c) w.axis_skips += skips[c];
    w.axis_pairs.swap(w.next_pairs);
    w.axes.swap(w.next_axes);
  }
  out.candidates = n;
  out.evaluated = last - first;
  out.clear_pairs();
  // The touching pairs of this part and their corners, in candidate order: each chunk of
  // [first, last) counts its pairs and corners, then writes them from the chunks' before it.
  const auto range = [&](std::size_t c) { return first + (last - first) * c / parts; };
  std::array<std::size_t, 65> corners_before{};
  const auto gather_part = [&](std::size_t c, bool write) {
    std::size_t to = write ? before[c] : 0, corner = write ? corners_before[c] : 0;
    for (std::size_t i = range(c); i < range(c + 1); ++i) {
      const contact_patch& p = w.patches[i];
      if (p.type == patch_type::none) continue;
      if (write) {
        out.pairs[to] = w.candidates[i];
        out.planes[to] = w.planes[i];
        out.type[to] = p.type;
        const auto from = static_cast<std::ptrdiff_t>(corner);
        std::copy(p.points.begin(), p.points.end(), out.point.begin() + from);
        std::copy(p.gap.begin(), p.gap.end(), out.gap.begin() + from);
        std::copy(p.area.begin(), p.area.end(), out.area.begin() + from);
        std::copy(p.label.begin(), p.label.end(), out.label.begin() + from);
        out.first_corner[to + 1] = static_cast<index_t>(corner + p.points.size());
      }
      ++to;
      corner += p.points.size();
    }
    if (!write) {
      before[c + 1] = to;
      corners_before[c + 1] = corner;
    }
  };
  before.fill(0);
  each_part([&](std::size_t c) { gather_part(c, false); });
  for (std::size_t c = 0; c < parts; ++c) corners_before[c + 1] += corners_before[c];
  const std::size_t touching = sum_before(), corners = corners_before[parts];
  out.pairs.resize(touching);
  out.planes.resize(touching);
  out.type.resize(touching);
  out.first_corner.resize(touching + 1);
  out.point.resize(corners);
  out.gap.resize(corners);
  out.area.resize(corners);
  out.label.resize(corners);
  each_part([&](std::size_t c) { gather_part(c, true); });
}

}  // namespace tessera::contact::detection
