#pragma once
// The rebuild pass of detected_contacts (contact/detected_contacts.hpp): one detection pass on the
// blocks' current geometry and the merge of its corners with the sub-contacts so far.
//
// Rebuilds. At construction, after max_rebuild_interval steps and, for deformable blocks, once a
// block vertex has moved tolerance / 2 since the last rebuild, prepare_step runs a full pass
// (grid broad phase with boxes enlarged by the tolerance, common plane and patch of every
// candidate pair): no vertex moves more than tolerance / 2 in between, so no contact is missed.
// Rigid blocks rebuild incrementally in between: detected/incremental.hpp says which blocks and
// pairs a rebuild covers, which it keeps, and why that misses nothing.
//
// Sub-contacts. Each corner of a touching pair's patch is one sub-contact, keyed by (block a, block
// b, corner label): a vertex of A, a vertex of B, or the crossing of an edge of A with an edge of B
// (detection::corner_label). Keys are kept sorted (detected/keys.hpp); at a rebuild the new corners
// are merged with the old ones, so a corner that persists keeps its law state (stresses, slip,
// damage) and a new one starts in Law::unbonded_state with its opening u_n = its geometric gap at t
// (a corner found open by g carries force only once g has closed; after construction a corner born
// overlapped starts at u_n = 0); its first update takes no increment, since the gap already holds
// the motion up to t. A persisting corner whose tributary area changes keeps its dissipated energy
// (the per-area fields rescaled) and, if the area grows, its force (Law::scale_stresses): a rebuild
// can take elastic energy out of the springs, never put it in. What it takes is booked as the
// rebuild exchange (energies()). Tributary areas come from the patch polygon; a segment or point
// patch (a block on its edge or corner) gives each corner the nominal area min over the two blocks
// of S / (3 V) (S the block's surface area, V its vertex count: a third of a vertex's share of the
// surface, a quarter of a face for a cube).
//
// Bonded faces (params::bond_faces): at construction the corners of a face-to-face patch whose
// faces coincide, between a material pair the table declares bonded, start intact (state_type{})
// instead: the faces a tessellation's blocks start on are bonded, and a bonded face that breaks
// keeps its residual state through the rebuilds for as long as its corners persist (the
// hand-over of a broken face to detected contacts: its crack can slide onto new neighbours,
// close and reopen). scale_stresses keeps a grown corner's force in tension too until it softens.
//
// After the merge: each pair's normal features in its blocks' frames, each sub-contact's weights
// in its blocks' frames (detected/frames.hpp) or zones (detected/deformable_fit.hpp), and the
// tasks and gather slots (index_subcontacts, detected/tasks.hpp; also after a checkpoint load).
//
// Cost: docs/performance.md "Contact detection kernels". The only allocations of a run: the
// per-sub-contact, per-pair and gather arrays grow (and keep their capacity; growth_count()).
//
// Definitions of detected_contacts<Law>'s private members (declared in the class); it includes the
// class and the class includes it, so either header can come first.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

#include "../../core/errors.hpp"
#include "../../core/nodes.hpp"
#include "../../core/parallel.hpp"
#include "../../core/types.hpp"
#include "../detection/detect.hpp"
#include "../detected_contacts.hpp"
#include "keys.hpp"
#include "refusals.hpp"

namespace tessera::contact {

/// One detection pass on the current geometry and the merge of the sub-contacts (file comment);
/// `full` false (rigid blocks during a run): of the blocks that moved only (detected/incremental.hpp).
template <law::ContactLaw Law>
inline void detected_contacts<Law>::rebuild(const node_set* gp, bool full) {
  const auto started = std::chrono::steady_clock::now();
  ++rebuilds_;
  steps_since_rebuild_ = 0;
  const std::size_t capacity_before = storage_capacity();
  const auto n_b = static_cast<index_t>(blocks_.size());
  // The blocks detected again: all at a full pass, else those that moved past redetect_fraction
  // x the tolerance since they were last detected (moved_, prepare_step's).
  const bool incremental = gp != nullptr && !full && !options_.deformable_blocks;
  const real redetect = detail::redetect_fraction * options_.tolerance;
  redetect_.assign(at(n_b), 1);
  if (incremental)
    for (std::size_t b = 0; b < at(n_b); ++b) redetect_[b] = moved_[b] > redetect * redetect ? 1 : 0;
  redetected_ += std::count(redetect_.begin(), redetect_.end(), 1);
  const auto changed = [&](index_t a, index_t b) { return redetect_[at(a)] != 0 || redetect_[at(b)] != 0; };
  detail::pair_poses& pp = poses_;
  // An incremental rebuild places the blocks detected again, and the others only if the pass
  // reads them (place_block); their boxes are bounds (detail::grown_box), so the pass finds the
  // same contacts to the bit (detected/incremental.hpp, "Placement").
  const auto pose_of = [&](std::size_t b, mat3& map, vec3& translation) {
    map = rotation(blocks_[b], gp);
    translation = position(blocks_[b].frame[0], gp) - map * shapes_[b].vertex(0);
  };
  detail::place_blocks(pp, shapes_, current_, boxes_, pose_of,
                       incremental ? std::span<const std::uint8_t>(redetect_) : std::span<const std::uint8_t>(),
                       [&](std::size_t b) { return detail::grown_box(detected_box_[b], moved_[b], options_.tolerance); });
  const auto place_block = [&](std::size_t b) {  // (passed to the pass on incremental rebuilds only)
    if (redetect_[b] == 0) current_[b].assign_transformed(shapes_[b], pp.block_rot[b], pp.block_shift[b]);
  };
  if (options_.deformable_blocks) check_affine_fit(gp);  // detected/deformable_fit.hpp
  // The blocks detected again start their motion from here.
  rebuild_u_.conservativeResize(static_cast<index_t>(watch_gridpoints_.size()), 3);
  for (index_t b = 0; b < n_b; ++b) {
    if (redetect_[at(b)] == 0) continue;
    for (index_t k = blocks_[at(b)].watch_begin; k < blocks_[at(b)].watch_end; ++k)
      for (int c = 0; c < 3; ++c) rebuild_u_(k, c) = gp != nullptr ? gp->displacement(watch_gridpoints_[at(k)], c) : 0.0;
    if (!options_.deformable_blocks) detected_box_[at(b)] = box_at_detection(at(b));
  }
  // An old pair whose blocks moved together keeps its columns; the pass leaves it out (incremental.hpp).
  const std::size_t n_old_pairs = pair_a_.size();
  pp.keep.assign(n_old_pairs, 0);
  pp.skip.clear();
  if (incremental) {
    if (pp.center.size() != at(n_b)) detail::reference_spheres(shapes_, pp.center, pp.radius);
    parallel_for(static_cast<std::int64_t>(n_old_pairs), [&](std::int64_t i) {  // (each old pair its own mark)
      const auto k = at(i);
      const bool ra = redetect_[at(pair_a_[k])] != 0, rb = redetect_[at(pair_b_[k])] != 0;  // (m_o: one block detected again)
      const real allowed = ra && rb ? redetect : redetect - std::sqrt(moved_[at(ra ? pair_b_[k] : pair_a_[k])]);
      pp.keep[k] = (ra || rb) && pp.drift(k, pair_a_[k], pair_b_[k], 2 * options_.tolerance) <= allowed;  // (reach: the tolerance and the motion to come)
    });
    for (std::size_t k = 0; k < n_old_pairs; ++k)
      if (pp.keep[k] != 0) pp.skip.push_back({pair_a_[k], pair_b_[k]});
    pp.kept_as_one += static_cast<std::int64_t>(pp.skip.size());
  }
  const auto redo = [&](std::size_t ko) { return changed(pair_a_[ko], pair_b_[ko]) && pp.keep[ko] == 0; };
  // The springs' energy before and after, over the pairs detected again (the others keep theirs
  // to the bit; the construction's pass sets the initial energy).
  real stored_before = 0;
  if (gp != nullptr)
    for (std::size_t k = 0; k < n_old_pairs; ++k)
      if (redo(k))
        for (auto i = at(pair_first_[k]); i < at(pair_first_[k + 1]); ++i)
          if (counted(i)) stored_before += energies_of(i).stored;
  // (Rigid blocks' face planes: the reference faces carried by the poses, detection::placed_faces.)
  detection::detect(current_, edges_, boxes_, {options_.tolerance, options_.tolerance, true}, result_, workspace_, share_,
                    incremental ? std::span<const std::uint8_t>(redetect_) : std::span<const std::uint8_t>(), pp.skip,
                    options_.deformable_blocks ? detection::placed_faces{} : detail::placed_faces_of(shapes_, pp),
                    incremental ? std::function<void(std::size_t)>(std::ref(place_block)) : std::function<void(std::size_t)>());  // (by reference: no allocation)
  narrow_pairs_ += static_cast<std::int64_t>(result_.evaluated);
  for (std::size_t b = 0; b < at(n_b); ++b)  // (placed: detected again, or read by the pass)
    placed_ += redetect_[b] != 0 || (incremental && workspace_.needs_faces[b] != 0) ? 1 : 0;
  if (share_.parts > 1) gather_(result_);  // the other parts, from the ranks that evaluated them
  if (gp == nullptr && !options_.allow_initial_overlap) detail::refuse_initial_overlaps(workspace_, options_.tolerance);

  // New pairs and their corners, sorted by label within a pair: the pass's pairs (increasing)
  // and, merged in (a, b) order, the old pairs of two blocks not detected again or kept as one, kept whole.
  // new_label_, new_area_, new_point_ and new_gap_ hold the pass's corners only (pair k's from
  // new_found_first_[k]); a kept pair's sub-contacts are a run of the old columns (kept_runs_).
  const std::size_t n_found = result_.pairs.size();
  new_pair_a_.clear();
  new_pair_b_.clear();
  new_label_.clear();
  new_area_.clear();
  new_point_.clear();
  new_gap_.clear();
  new_source_.clear();
  new_found_first_.clear();
  new_pair_first_.assign(1, 0);
  kept_runs_.clear();
  untouched_last_ = 0;
  std::size_t ko = 0, n_kept = 0;
  for (std::size_t k = 0; k < n_found || ko < n_old_pairs;) {
    // Old pairs with a block detected again (but those kept as one) make way for the pass's.
    while (ko < n_old_pairs && redo(ko)) ++ko;
    const bool take_old = ko < n_old_pairs && (k == n_found || pair_a_[ko] < result_.pairs[k].a ||
                                               (pair_a_[ko] == result_.pairs[k].a && pair_b_[ko] < result_.pairs[k].b));
    if (take_old) {
      // It and its sub-contacts: runs of the old pair and sub-contact columns, copied whole below.
      const auto o0 = at(pair_first_[ko]), o1 = at(pair_first_[ko + 1]), i0 = n_kept + new_label_.size();
      if (detail::continues_run(kept_runs_, o0, i0, ko, new_pair_a_.size())) {
        kept_runs_.back().count += o1 - o0;
        ++kept_runs_.back().pairs;
      } else {
        kept_runs_.push_back({o0, i0, o1 - o0, ko, new_pair_a_.size(), 1});
      }
      n_kept += o1 - o0;
      new_pair_a_.push_back(pair_a_[ko]);
      new_pair_b_.push_back(pair_b_[ko]);
      new_pair_first_.push_back(static_cast<index_t>(n_kept + new_label_.size()));
      new_found_first_.push_back(0);  // (none: its columns are copied)
      new_source_.push_back(-1 - static_cast<std::ptrdiff_t>(ko));
      ++untouched_last_;
      ++ko;
      continue;
    }
    if (k == n_found) break;
    new_source_.push_back(static_cast<std::ptrdiff_t>(k));
    new_found_first_.push_back(static_cast<index_t>(new_label_.size()));
    const auto first = at(result_.first_corner[k]), last = at(result_.first_corner[k + 1]);
    // Deformable blocks: a face-to-face patch's sub-contacts at surface gridpoints.
    if (options_.deformable_blocks && result_.type[k] == detection::patch_type::polygon && collect_nodes(k, gp)) {
      for (const node_contact& c : node_scratch_) {
        new_label_.push_back(c.label);
        new_area_.push_back(c.area);
        new_point_.push_back(position(c.gridpoint, gp));
        new_gap_.push_back(c.gap);
      }
      new_pair_a_.push_back(result_.pairs[k].a);
      new_pair_b_.push_back(result_.pairs[k].b);
      new_pair_first_.push_back(static_cast<index_t>(n_kept + new_label_.size()));
      ++k;
      continue;
    }
    order_.clear();
    for (std::size_t j = first; j < last; ++j) order_.push_back(j);
    std::sort(order_.begin(), order_.end(), [&](std::size_t x, std::size_t y) {
      return result_.label[x] < result_.label[y] || (result_.label[x] == result_.label[y] && x < y);
    });
    const bool polygon = result_.type[k] == detection::patch_type::polygon;
    const real nominal =
        std::min(blocks_[at(result_.pairs[k].a)].nominal_area, blocks_[at(result_.pairs[k].b)].nominal_area);
    const auto pair_begin = new_label_.size();
    for (std::size_t j : order_) {
      // A sliver polygon's corner keeps a floor of 1e-6 of the nominal area, so that areas stay
      // > 0 and the ratios of a rebuild (below) stay finite.
      const real a = polygon ? std::max(result_.area[j], 1e-6 * nominal) : nominal;
      // A label met twice (a corner within round-off of another) keeps its first point and
      // takes the other's area.
      if (new_label_.size() > pair_begin && new_label_.back() == result_.label[j]) {
        if (polygon) new_area_.back() += a;
        continue;
      }
      new_label_.push_back(result_.label[j]);
      new_area_.push_back(a);
      new_point_.push_back(result_.point[j]);
      new_gap_.push_back(result_.gap[j]);
    }
    new_pair_a_.push_back(result_.pairs[k].a);
    new_pair_b_.push_back(result_.pairs[k].b);
    new_pair_first_.push_back(static_cast<index_t>(n_kept + new_label_.size()));
    ++k;
  }
  const std::size_t n_pairs = new_pair_a_.size();
  const std::size_t n = n_kept + new_label_.size();
  // The pass's corner of new sub-contact i of pass pair k.
  const auto found = [&](std::size_t k, std::size_t i) { return at(new_found_first_[k]) + (i - at(new_pair_first_[k])); };

  // Merge the states: old and new keys are both sorted by (a, b, label). A kept pair's
  // sub-contacts keep theirs to the bit; a pass pair's corner looks for its label among the
  // sub-contacts of the old pair of the same blocks (if any). Each pair writes its own
  // sub-contacts and marks the old ones it finds, each once (a pair's labels are distinct): the
  // pairs in parallel (at construction in order, which counts the bonded corners).
  new_state_.resize(n);
  new_fresh_.assign(n, 0);
  kept_old_.assign(key_label_.size(), 0);
  // A kept pair's run of a column, and the runs of the state columns (in parallel: each writes its own).
  const auto copy_run = [](const kept_run& run, const auto& from, auto& to) {
    std::copy_n(from.begin() + static_cast<std::ptrdiff_t>(run.from), run.count, to.begin() + static_cast<std::ptrdiff_t>(run.to));
  };
  parallel_for_dynamic(static_cast<std::int64_t>(kept_runs_.size()), [&](std::int64_t r) {
    copy_run(kept_runs_[at(r)], state_, new_state_);
    copy_run(kept_runs_[at(r)], fresh_, new_fresh_);
  }, 4);
  const auto merge_pair = [&](std::size_t k) {
    index_t bonded_here = 0;
    const index_t a = new_pair_a_[k], b = new_pair_b_[k];
    const std::ptrdiff_t source = new_source_[k];
    if (source < 0) return bonded_here;  // (kept: copied above)
    const auto j = at(source);
    const params_type& p = law_params_[table_.entry_index(material_[at(a)], material_[at(b)])];
    const std::size_t old_pair = detail::find_old_pair(a, b, pair_a_, pair_b_);
    const bool had = old_pair < n_old_pairs;
    std::size_t old = had ? at(pair_first_[old_pair]) : 0;
    const std::size_t old_end = had ? at(pair_first_[old_pair + 1]) : 0;
    for (auto i = at(new_pair_first_[k]); i < at(new_pair_first_[k + 1]); ++i) {
      const std::size_t f = found(k, i);
      if (detail::seek_old_label(old, old_end, new_label_[f], key_label_)) {
        new_state_[i] = state_[old];
        // A tributary area that grows keeps the corner's force (stresses scaled down), one that
        // shrinks keeps its stresses: either way the spring's energy can only drop, so a
        // rebuild never feeds energy into the scene.
        // The energy it dissipated (per area in the state) stays what it was.
        if (const real a_old = area_[old]; new_area_[f] != a_old) {
          state_type& st = new_state_[i];
          const real r = a_old / new_area_[f];
          if (r < 1) Law::scale_stresses(p, st, r);
          st.dissipated_tension *= r;
          st.dissipated_shear *= r;
          st.dissipated_compression *= r;
        }
        kept_old_[old] = 1;
      } else {
        // params::bond_faces: at construction, the coinciding faces of a bonded material pair.
        const bool bonded = gp == nullptr && options_.bond_faces &&
                            result_.type[j] == detection::patch_type::polygon &&
                            table_.get(material_[at(a)], material_[at(b)]).bonded &&
                            std::abs(new_gap_[f]) <= bond_gap_fraction * options_.tolerance;
        state_type s = bonded ? state_type{} : Law::unbonded_state(p);
        if (bonded) ++bonded_here;
        // At construction a corner takes its gap (a scene may start in contact, e.g. at its
        // static overlap: that energy is the run's initial energy). Later a corner that is
        // born overlapped (a new crossing of two edges inside a loaded patch) starts at zero
        // opening: its overlap is the neighbours' share, and a spring born compressed would
        // inject energy that no force supplied.
        s.u_n = gp == nullptr ? new_gap_[f] : std::max<real>(new_gap_[f], 0);
        // A zero increment sets the stresses of that opening (compression if it overlaps), so
        // the energy it holds is in the books from the start.
        // (The law books that energy as work done on the contact; it was not: undo its entry.)
        const state_type unbonded = s;
        Law::update(p, s, 0, vec3::Zero(), result_.planes[j].normal);
        s.dissipated_tension = unbonded.dissipated_tension;
        s.dissipated_shear = unbonded.dissipated_shear;
        s.dissipated_compression = unbonded.dissipated_compression;
        new_state_[i] = s;
        new_fresh_[i] = 1;
      }
    }
    return bonded_here;
  };
  if (gp == nullptr)
    for (std::size_t k = 0; k < n_pairs; ++k) bonded_at_start_ += merge_pair(k);
  else
    parallel_for_dynamic(static_cast<std::int64_t>(n_pairs), [&](std::int64_t k) { (void)merge_pair(at(k)); }, 64);
  kept_last_ = static_cast<index_t>(n_kept + static_cast<std::size_t>(std::count(kept_old_.begin(), kept_old_.end(), 1)));
  // Sub-contacts that end keep what they dissipated in the books; what they still stored leaves
  // the springs through the rebuild exchange. (They are among the old pairs detected again.)
  for (std::size_t ok = 0; ok < n_old_pairs; ++ok) {
    if (!redo(ok)) continue;
    for (auto o = at(pair_first_[ok]); o < at(pair_first_[ok + 1]); ++o) {
      if (kept_old_[o] != 0 || !counted(o)) continue;
      const contact_energies e = energies_of(o);
      retired_.dissipated += e.dissipated;
      retired_.dissipated_tension += e.dissipated_tension;
      retired_.dissipated_shear += e.dissipated_shear;
      retired_.dissipated_compression += e.dissipated_compression;
    }
  }
  state_.swap(new_state_);
  fresh_.swap(new_fresh_);
  // The pair and sub-contact columns: the old ones go to prev_, the kept pairs' are copied from
  // there in runs, then each pass pair fills its own slot and sub-contacts (the pairs in parallel).
  std::swap(key_label_, prev_.label);
  std::swap(area_, prev_.area);
  std::swap(pair_param_, prev_.param);
  std::swap(feature_, prev_.feature);
  std::swap(feature_a_, prev_.feature_a);
  std::swap(feature_b_, prev_.feature_b);
  std::swap(side_a_, prev_.side_a);
  std::swap(side_b_, prev_.side_b);
  std::swap(pair_stiffness_, prev_.stiffness);
  std::swap(pair_reach2_, prev_.reach2);
  for (int j = 0; j < 3; ++j) normal_[at(j)].swap(prev_.normal[at(j)]);
  pp.rot.swap(pp.prev_rot);
  pp.shift.swap(pp.prev_shift);
  std::swap(corner_normal_, prev_.corner_normal);
  for (int s = 0; s < 8; ++s) weight_[at(s)].swap(prev_.weight[at(s)]);
  for (int c = 0; c < 3; ++c) force_[at(c)].swap(prev_.force[at(c)]);
  pp.rot.resize(n_pairs);
  pp.shift.resize(n_pairs);
  pair_a_.swap(new_pair_a_);  // (the new_ scratch is cleared at the next rebuild)
  pair_b_.swap(new_pair_b_);
  pair_param_.resize(n_pairs);
  feature_.resize(n_pairs);
  feature_a_.resize(n_pairs);
  feature_b_.resize(n_pairs);
  side_a_.resize(n_pairs);
  side_b_.resize(n_pairs);
  pair_stiffness_.resize(n_pairs);
  pair_reach2_.resize(n_pairs);
  for (soa3& m : normal_) m.resize(static_cast<index_t>(n_pairs), 3);
  key_label_.resize(n);
  area_.resize(n);
  pair_.resize(n);
  corner_normal_.resize(n);
  for (auto& w : weight_) w.resize(n);
  for (auto& f : force_) f.resize(n);  // (a pass pair's: zero, below)
  // The kept pairs' columns (blocks: swapped in above; parameters, features, poses, normals) and
  // their sub-contacts' (keys, areas, weights, forces, pairs): the runs in parallel.
  parallel_for_dynamic(static_cast<std::int64_t>(kept_runs_.size()), [&](std::int64_t r) {
    const kept_run& run = kept_runs_[at(r)];
    const auto copy = [&](const auto& from, auto& to) { copy_run(run, from, to); };
    copy(prev_.label, key_label_);
    copy(prev_.area, area_);
    copy(prev_.corner_normal, corner_normal_);
    for (int s = 0; s < 8; ++s) copy(prev_.weight[at(s)], weight_[at(s)]);
    for (int c = 0; c < 3; ++c) copy(prev_.force[at(c)], force_[at(c)]);
    const kept_run pairs{run.pair_from, run.pair_to, run.pairs};
    const auto copy_pairs = [&](const auto& from, auto& to) { copy_run(pairs, from, to); };
    copy_pairs(prev_.param, pair_param_);
    copy_pairs(prev_.feature, feature_);
    copy_pairs(prev_.feature_a, feature_a_);
    copy_pairs(prev_.feature_b, feature_b_);
    copy_pairs(prev_.side_a, side_a_);
    copy_pairs(prev_.side_b, side_b_);
    copy_pairs(prev_.stiffness, pair_stiffness_);  // (rigid blocks: bounded at the last rebuild)
    copy_pairs(prev_.reach2, pair_reach2_);
    copy_pairs(pp.prev_rot, pp.rot);
    copy_pairs(pp.prev_shift, pp.shift);
    const auto rows = static_cast<index_t>(run.pairs);
    for (int j = 0; j < 3; ++j)
      normal_[at(j)].middleRows(static_cast<index_t>(run.pair_to), rows) =
          prev_.normal[at(j)].middleRows(static_cast<index_t>(run.pair_from), rows);
    for (std::size_t k = run.pair_to; k < run.pair_to + run.pairs && !options_.deformable_blocks; ++k)
      std::fill(pair_.begin() + new_pair_first_[k], pair_.begin() + new_pair_first_[k + 1], static_cast<index_t>(k));
  }, 4);
  // Per pass pair: parameters, normal feature, normals; its sub-contacts: keys, areas, normals,
  // zero forces, weights.
  parallel_for_dynamic(static_cast<std::int64_t>(n_pairs), [&](std::int64_t kk) {
    const auto k = at(kk);
    if (new_source_[k] < 0) return;  // (kept: copied above)
    const index_t a = pair_a_[k], b = pair_b_[k];
    if (!options_.deformable_blocks)
      std::fill(pair_.begin() + new_pair_first_[k], pair_.begin() + new_pair_first_[k + 1], static_cast<index_t>(k));
    for (auto i = at(new_pair_first_[k]); i < at(new_pair_first_[k + 1]); ++i) {
      key_label_[i] = new_label_[found(k, i)];
      area_[i] = new_area_[found(k, i)];
    }
    pair_param_[k] = static_cast<index_t>(table_.entry_index(material_[at(a)], material_[at(b)]));
    pp.relative(a, b, pp.rot[k], pp.shift[k]);
    const detection::contact_plane& plane = result_.planes[at(new_source_[k])];
    // The feature in each block's reference frame: n = R_a fa (face of A), -R_b fb (face of B),
    // or +-(R_a ea x R_b eb) (edges), so that n equals the plane's normal now.
    const mat3 ra = rotation(blocks_[at(a)], gp), rb = rotation(blocks_[at(b)], gp);
    const vec3 n = plane.normal;
    if (plane.source == detection::plane_source::edge_edge) {
      const auto& ea = edges_[at(a)].list[at(plane.feature_a)];
      const auto& eb = edges_[at(b)].list[at(plane.feature_b)];
      const vec3 da = shapes_[at(a)].vertex(ea.v) - shapes_[at(a)].vertex(ea.u);
      const vec3 db = shapes_[at(b)].vertex(eb.v) - shapes_[at(b)].vertex(eb.u);
      const real sign = (ra * da).cross(rb * db).dot(n) >= 0 ? 1.0 : -1.0;
      feature_[k] = feature_kind::edges;
      feature_a_[k] = sign * da;
      feature_b_[k] = db;
    } else if (plane.source == detection::plane_source::face_b) {
      feature_[k] = feature_kind::face_b;
      feature_b_[k] = -(rb.transpose() * n);  // R is a rotation (rigid blocks): R^-1 = R^T
      feature_a_[k] = vec3::Zero();
    } else {
      feature_[k] = feature_kind::face_a;
      feature_a_[k] = ra.transpose() * n;
      feature_b_[k] = vec3::Zero();
    }
    // Faces of A and B parallel to the plane (within parallel_cos): a vertex of B is pushed by
    // A's face, whose normal turns with A, and a vertex of A by B's face.
    side_a_[k] = side_b_[k] = vec3::Zero();
    real best_a = parallel_cos, best_b = parallel_cos;
    // (The face normals of this pass's planes: workspace_.faces_of, face_normal to the bit.)
    const auto faces_a = workspace_.faces_of(at(a)), faces_b = workspace_.faces_of(at(b));
    for (const geometry::plane& fa : faces_a)
      if (const vec3& m = fa.normal; m.dot(n) > best_a) {
        best_a = m.dot(n);
        side_a_[k] = ra.transpose() * m;
      }
    for (const geometry::plane& fb : faces_b)
      if (const vec3& m = fb.normal; -m.dot(n) > best_b) {
        best_b = -m.dot(n);
        side_b_[k] = rb.transpose() * m;
      }
    // Face normals map through R (rigid) or F^-T (deformable: n0 = F^T n above).
    const mat3 na = options_.deformable_blocks ? mat3(ra.inverse().transpose()) : ra;
    const mat3 nb = options_.deformable_blocks ? mat3(rb.inverse().transpose()) : rb;
    for (int j = 0; j < 3; ++j) {
      const vec3 nj = j == 0 || normal_is_plane(k, j) ? n : j == 1 ? vec3(na * side_a_[k]) : vec3(-(nb * side_b_[k]));
      normal_[at(j)].row(static_cast<index_t>(k)) = nj.transpose();
    }
    for (auto& f : force_) std::fill(f.begin() + new_pair_first_[k], f.begin() + new_pair_first_[k + 1], 0.0);
    for (auto i = at(new_pair_first_[k]); i < at(new_pair_first_[k + 1]); ++i) {
      // A gridpoint sub-contact (deformable blocks) is pushed like a vertex of its side.
      const std::uint64_t label = key_label_[i];
      const bool node = detail::is_node_label(label), node_b = node && detail::node_label_side_b(label);
      const auto kind = detection::corner_label::kind_of(label);
      const bool of_b = node ? node_b : kind == detection::corner_label::kind::vertex_b;
      const bool of_a = node ? !node_b : kind == detection::corner_label::kind::vertex_a;
      corner_normal_[i] = of_b && side_a_[k].squaredNorm() > 0 ? 1 : of_a && side_b_[k].squaredNorm() > 0 ? 2 : 0;
    }
    if (options_.deformable_blocks) return;  // (zoned weights: below, in order)
    const mat3 inv_a = frame_inverse(blocks_[at(a)], gp), inv_b = frame_inverse(blocks_[at(b)], gp);
    const vec3 xa = position(blocks_[at(a)].frame[0], gp), xb = position(blocks_[at(b)].frame[0], gp);
    for (auto i = at(new_pair_first_[k]); i < at(new_pair_first_[k + 1]); ++i) {
      const vec3 la = inv_a * (new_point_[found(k, i)] - xa), lb = inv_b * (new_point_[found(k, i)] - xb);
      weight_[0][i] = 1 - la.sum();
      weight_[4][i] = 1 - lb.sum();
      for (int c = 0; c < 3; ++c) {
        weight_[at(1 + c)][i] = la[c];
        weight_[at(5 + c)][i] = lb[c];
      }
    }
  }, 32);
  if (options_.deformable_blocks) {
    for (auto& v : node_) v.resize(n);
    for (std::size_t k = 0; k < n_pairs; ++k)
      for (auto i = at(new_pair_first_[k]); i < at(new_pair_first_[k + 1]); ++i) {
        pair_[i] = static_cast<index_t>(k);
        place_zoned(i, pair_a_[k], pair_b_[k], gp);  // (every pair is the pass's: new_point_[i] is its)
      }
  }
  pair_first_.swap(new_pair_first_);
  index_subcontacts(true);

  peak_subcontacts_ = std::max(peak_subcontacts_, static_cast<index_t>(n));
  if (storage_capacity() > capacity_before) ++growths_;
  if (gp != nullptr) {
    real stored_after = 0;
    for (std::size_t k = 0; k < n_pairs; ++k)
      if (new_source_[k] >= 0)  // (the pass's pairs)
        for (auto i = at(pair_first_[k]); i < at(pair_first_[k + 1]); ++i)
          if (counted(i)) stored_after += energies_of(i).stored;
    retired_.rebuild_exchange += stored_after - stored_before;
  }
  rebuild_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

}  // namespace tessera::contact
