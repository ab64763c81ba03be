#pragma once
// contact::detected_contacts<Law>: a ContactSet (contact/concepts.hpp) whose sub-contacts come from
// contact detection (detection/detect.hpp), so blocks that separate, slide and meet new neighbours
// are in contact wherever they touch, not only across the faces they were built with. It serves
// rigid blocks (blocks::rigid) and, with params::deformable_blocks, deformable ones
// (blocks::deformable; "Deformable blocks" below; the solver checks the flag against its block
// model). DESIGN.md section 4, docs/model.md "Detected contacts".
//
// Rebuilds. At construction and whenever a block vertex has moved more than tolerance / 2 since
// the last rebuild (or after max_rebuild_interval steps), prepare_step runs a detection pass on
// the blocks' current geometry: grid broad phase with boxes enlarged by the tolerance, common
// plane and contact patch of every candidate pair (common_plane.hpp). Guarantee: between
// rebuilds no vertex moves more than tolerance / 2, so two blocks whose gap was above the
// tolerance at the last rebuild cannot have closed it: no contact is missed. The check reads
// every block vertex once per step (no velocity bound to guess).
//
// Refusals at construction (issue #40 items 3 and 5): a material pair whose residual friction is
// 0 beside a non-zero phi_0 (or, starting unbonded, whose residual cohesion is 0 beside c_0 > 0),
// since every detected corner starts on the residual limit; and two blocks that overlap by more
// than the tolerance (params::allow_initial_overlap opts in).
//
// Sub-contacts. Each corner of a touching pair's patch is one sub-contact, keyed by (block a,
// block b, corner label): a vertex of A, a vertex of B, or the crossing of an edge of A with an
// edge of B (detection::corner_label). Keys are kept sorted; at a rebuild the new corners are
// merged with the old ones, so a corner that persists keeps its law state (stresses, slip,
// damage) and a new one starts in Law::unbonded_state with its opening u_n = its geometric gap
// at t (a corner found open by g carries force only once g has closed; after construction a
// corner born overlapped starts at u_n = 0); its first update takes no increment, since the gap
// already holds the motion up to t. A persisting corner whose tributary area changes keeps its
// dissipated energy (the per-area fields rescaled) and, if the area grows, its force
// (Law::scale_stresses): a rebuild can take elastic energy out of the springs, never put it in.
// What it takes is booked as the rebuild exchange (energies()). Tributary areas come from the
// patch polygon; a segment or point patch (a block on its edge or corner) gives each corner the
// nominal area min over the two blocks of S / (3 V) (S the block's surface area, V its vertex
// count: a third of a vertex's share of the surface, a quarter of a face for a cube).
//
// Bonded faces (params::bond_faces): at construction the corners of a face-to-face patch whose
// faces coincide, between a material pair the table declares bonded, start intact (state_type{})
// instead: the faces a tessellation's blocks start on are bonded, and a bonded face that breaks
// keeps its residual state through the rebuilds for as long as its corners persist (the
// hand-over of a broken face to detected contacts: its crack can slide onto new neighbours,
// close and reopen). scale_stresses keeps a grown corner's force in tension too until it softens.
//
// Kinematics between rebuilds. A sub-contact is a material point p fixed in each block: its
// affine coordinates w (sum 1) in a frame of four vertex gridpoints of the block, so x(p) =
// sum_k w_k x_k and v(p) = sum_k w_k v_k exactly for a rigid motion (the secant gridpoint
// velocities of blocks::rigid are affine in the body coordinates). The pair's unit normal n turns
// with the feature the plane came from: a face of A (R_a n0), a face of B (-R_b n0), or an edge of
// each (R_a e_a x R_b e_b), R = the block's rotation from its frame. Then, as for face_contacts
// (kinematics.hpp), du = (v_b(p) - v_a(p)) dt - (n_prev x n) x (x_b(p) - x_a(p)), split along n,
// Law::update, and the force area (sigma_n n + tau) on A's side (B gets its opposite), handed to
// the frame gridpoints with the weights w: resultant and moment about any point are exact. Each
// pair sums its sub-contacts' shares per frame gridpoint (eight sums), which the gather reads.
//
// Stable step (rigid blocks). add_stiffness_bounds puts a bound per block on its vertex farthest
// from its centroid (distance r_max), from which blocks::rigid's 6-DOF bound takes k_t = k and
// k_r = k r_max^2. params::step_bound chooses which contacts it covers:
// - present_contacts (default): the sub-contacts that exist until the next rebuild. Each
//   sub-contact i couples its two material points by [K -K; -K K], K = a_i (k_s I + (k_n - k_s)
//   n n^T), whose row sum is at most 2 k_row a_i on either side (stiffness_bound.hpp; k_row of
//   the pair's own table entry, a_i the tributary or nominal area its springs use, so no margin
//   for nominal areas is needed). So the block carries k = sum_i 2 k_row a_i over the
//   sub-contacts of its pairs, times max(1, max_i |rho_i|^2 / r_max^2) (rho_i: centroid to the
//   material point, fixed in the body; a corner of a patch can lie up to the tolerance outside
//   the block), and k_r = k r_max^2 >= sum_i 2 k_row a_i |rho_i|^2 as the proof in
//   blocks/rigid.hpp needs. Why this is stable until the next rebuild: between rebuilds the
//   sub-contact set, its areas, its material points and its pairs' law entries are fixed, and new
//   contacts appear only at rebuilds; every sub-contact's stiffness stays within its row bound for
//   any normal it turns to. The bound changes at every rebuild (recomputed there, and after a
//   checkpoint load, from the sub-contacts' areas and weights), so the solver chooses dt again
//   after each rebuild (solver.hpp, "Time step"). With no sub-contact at all it falls back to:
// - whole_surface: every contact the block could ever carry: k = 4 k_row A, A = min(S, sum of the
//   other blocks' S) bounds its contact area (x 2 for the nominal areas of corner contacts and
//   overlapping patches), k_row the row bound of the stiffest material entry. It holds for any
//   contacts that appear later, so a dt chosen once from it stays stable for the whole run: the
//   solver uses it when dt does not follow the rebuilds (a given solver_options::dt, mass scaling).
//
// Deformable blocks (params::deformable_blocks). Detection reads each block's affine fit: the map
// F = d D^-1 of its frame (four vertex gridpoints) applied to its reference polyhedron, so the
// shapes stay convex with planar faces. A rebuild measures how far every surface gridpoint lies
// from its block's fit (max_deviation()) and refuses a block farther than a quarter of the
// tolerance (geometry_error: raise the tolerance); the trigger then reads every surface gridpoint
// and fires at tolerance / 2 - deviation, so the guarantee above holds for the real surfaces. A
// face-to-face patch puts its sub-contacts at surface gridpoints (block_mesh::face_nodes) rather
// than at its corners, as 3DEC does for zoned blocks: those of A's faces that face the plane and
// lie within tolerance / 2 of the patch, or those of B's, whichever side's tributary areas
// (block_mesh::face_node_area) sum closer to the patch area (a small face on a large one: the
// small face's; the side of the last rebuild while it fits within 5 %), each labelled by its
// gridpoint, their areas scaled to sum to the patch area; a side needs three such gridpoints,
// else the patch keeps its corners. Each material point is the gridpoint itself on its own side
// and, on the other, the surface zone holding it (largest smallest barycentric weight): four
// gridpoints and their weights, fixed between rebuilds, so a point moves with the zone's linear
// field exactly and its force goes to those gridpoints. Corners of segment and point patches are
// located in both blocks' zones the same way. Face normals turn with F^-T, edges with F. Stable step: every
// surface gridpoint g carries 4 k_row (a_g + 2 T_g + 2 a_max), a_g its own tributary area, T_g the
// surface area of the zones around it (where other blocks' points can land), a_max the largest
// tributary or nominal area in the scene.
//
// Checkpoints: checkpoint(Archive&) saves the sub-contacts and pairs with their sizes (the
// tasks and gather slots are derived again on load), the rebuild trigger's state and the books, so a restarted run rebuilds at the same steps
// with the same bits (io/checkpoint.hpp).
//
// Storage and threading: structure of arrays per sub-contact (key, weights, area, state, force),
// per pair (blocks, normal feature, normals now and last step, parameters; rigid blocks: the
// eight frame-gridpoint sums), per gridpoint the gather slots. Only a rebuild allocates (arrays
// grow and keep their capacity; counted in growth_count()); a step between rebuilds allocates
// nothing. Tasks are runs of pairs; a pair sums its sub-contacts in order and the gather sums each
// gridpoint's slots in increasing pair order (deformable blocks: sub-contact order), so results
// are bit-identical for any thread count. Cost of a step and of a rebuild: docs/performance.md
// "Contact detection kernels".

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Dense>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/convex_polyhedron.hpp"
#include "../geometry/tessellation.hpp"
#include "../geometry/tessellation_queries.hpp"
#include "../law/concepts.hpp"
#include "concepts.hpp"
#include "detection/detect.hpp"
#include "face_contacts.hpp"
#include "kinematics.hpp"
#include "material_table.hpp"
#include "stiffness_bound.hpp"

namespace tessera::contact {

/// Which contacts detected_contacts::add_stiffness_bounds covers for rigid blocks (file comment,
/// "Stable step"): those present until the next rebuild, or every contact a block could carry.
enum class step_bound_scope { present_contacts, whole_surface };

template <law::ContactLaw Law>
class detected_contacts {
  template <std::integral I>
  [[nodiscard]] static constexpr std::size_t at(I i) noexcept {
    return static_cast<std::size_t>(i);
  }
  using triple = kinematics::triple;

 public:
  using law_type = Law;
  using params_type = typename Law::params;
  using state_type = typename Law::state;
  static_assert(requires(const params_type& p, state_type s) {
    Law::unbonded_state(p);
    Law::scale_stresses(p, s, real{});
    s.u_n;
  } && detail::has_dissipation_split<state_type>,
                "detected_contacts needs a law with Law::unbonded_state, Law::scale_stresses and state fields u_n "
                "(normal opening, m) and dissipated_tension / _shear / _compression");

  /// What the constructor takes.
  struct params {
    /// Law parameters per pair of block materials. A detected sub-contact starts unbonded
    /// (Law::unbonded_state: no tension, residual cohesion c_res and friction phi_res) unless
    /// bond_faces says otherwise. The constructor refuses a pair whose phi_res is 0 while phi_0 > 0,
    /// and one that starts unbonded with c_res = 0 while c_0 > 0 (values that would be silently
    /// unused); law::dry_joint and law::bonded_joint (law/joints.hpp) fill them all.
    material_table<params_type> law{};
    /// Contact tolerance (m, > 0): pairs whose gap is at most this touch, and vertices within it
    /// of a block's supporting plane form the patch. Typically 1e-3 to 1e-2 of a block's size.
    real tolerance = 0;
    /// A rebuild at least every this many steps (>= 1), besides the motion trigger.
    index_t max_rebuild_interval = 1000;
    /// true: at construction, the corners of every face-to-face patch whose faces coincide (each
    /// corner's |gap| <= bond_gap_fraction x tolerance) between a material pair the table
    /// declares bonded start intact (state_type{}: the law's tensile strength and cohesion), as
    /// face_contacts bonds a tessellation's faces. Such a bonded face, once broken, keeps its
    /// residual state through every rebuild, so the crack can open, slide onto new neighbours,
    /// close and reopen. Corners born later start unbonded. false: every corner starts unbonded.
    bool bond_faces = false;
    /// true for blocks::deformable (the solver checks that it matches its block model): a
    /// sub-contact's material point is located in a surface zone of each block (its four
    /// gridpoints, barycentric weights), a face-to-face patch puts its sub-contacts at the surface
    /// gridpoints of the side whose tributary areas fit the patch, detection reads each block's
    /// affine fit and the stable step a bound per surface gridpoint (file comment, "Deformable
    /// blocks"). false: rigid blocks (blocks::rigid), one frame per block.
    bool deformable_blocks = false;
    /// false (default): at construction, two blocks that overlap by more than the tolerance
    /// (penetration depth -g of their common plane > tolerance, common_plane.hpp) are refused
    /// (invalid_input naming both blocks, the depth and the tolerance): such an overlap is a
    /// placement error, and its springs would push the blocks apart with energy no force supplied.
    /// An overlap within the tolerance (a block placed at its static overlap W/(k_n A), faces
    /// that coincide up to round-off) is accepted. true: any initial overlap is accepted, its
    /// springs loaded from the start (the run's initial energy), for scenes that mean it.
    bool allow_initial_overlap = false;
    /// Rigid blocks: the stable step from the sub-contacts present until the next rebuild
    /// (present_contacts; the solver chooses dt again after each rebuild) or from every contact a
    /// block could carry (whole_surface; a dt that holds for the whole run). File comment,
    /// "Stable step". Deformable blocks keep their per-gridpoint bound either way.
    step_bound_scope step_bound = step_bound_scope::present_contacts;

    params() = default;
    params(material_table<params_type> table, real tol, index_t interval = 1000, bool bond = false,
           bool deformable = false)
        : law(std::move(table)), tolerance(tol), max_rebuild_interval(interval), bond_faces(bond),
          deformable_blocks(deformable) {}
  };
  /// A corner found at construction is bonded (params::bond_faces) when its gap is within this
  /// fraction of the tolerance: the two faces coincide, as the faces of a tessellation split into
  /// separate blocks do (geometry::separate_blocks), up to round-off.
  static constexpr real bond_gap_fraction = 1e-3;

  detected_contacts() = default;

  /// Reads the blocks of `tess` (cell b = block b) and their vertex gridpoints in `mesh`, picks each
  /// block's frame and runs the first detection pass on the reference geometry. Throws
  /// invalid_input for bad parameters, geometry_error when a cell vertex has no gridpoint or a
  /// block is flat.
  detected_contacts(const geometry::tessellation& tess, const geometry::block_mesh& mesh, const params& p)
      : options_(p) {
    require(std::isfinite(p.tolerance) && p.tolerance > 0, "detected_contacts: contact tolerance = ", p.tolerance,
            " m must be finite and > 0");
    require(p.max_rebuild_interval >= 1, "detected_contacts: max_rebuild_interval = ", p.max_rebuild_interval,
            " steps must be >= 1");
    for (const auto& e : p.law.entries()) {
      Law::validate(e.params);
      law_params_.push_back(e.params);
    }
    table_ = p.law;
    const index_t n_b = mesh.block_count();
    require<geometry_error>(tess.cell_count() == n_b, "detected_contacts: the tessellation has ", tess.cell_count(),
                            " cells but the block_mesh ", n_b, " blocks");
    refuse_unused_strengths(mesh);
    gridpoint_count_ = mesh.gridpoint_count();
    reference_.resize(gridpoint_count_, 3);
    for (index_t g = 0; g < gridpoint_count_; ++g) reference_.row(g) = mesh.gridpoints[at(g)].transpose();
    material_.resize(at(n_b));
    blocks_.resize(at(n_b));
    motion_.resize(at(n_b));
    moved_.resize(at(n_b));
    shapes_.resize(at(n_b));
    edges_.resize(at(n_b));
    real row_max = 0;
    for (const params_type& q : law_params_) {
      entry_row_bound_.push_back(stiffness_row_bound_per_area<Law>(q));
      row_max = std::max(row_max, entry_row_bound_.back());
    }
    for (index_t b = 0; b < n_b; ++b) {
      material_[at(b)] = mesh.material(b);
      build_block(tess, mesh, b);
    }
    // A block's contacts cover at most its own surface and at most the others' surfaces.
    real all_surfaces = 0;
    for (const block_data& bd : blocks_) all_surfaces += bd.surface;
    for (block_data& bd : blocks_) bd.stiffness_bound = 4 * row_max * std::min(bd.surface, all_surfaces - bd.surface);
    if (options_.deformable_blocks) {
      build_surfaces(tess, mesh, row_max);
    } else {
      watch_gridpoints_ = vertex_gridpoints_;
      for (block_data& bd : blocks_) {
        bd.watch_begin = bd.vertex_begin;
        bd.watch_end = bd.vertex_end;
      }
    }
    current_ = shapes_;
    boxes_.resize(at(n_b));
    present_bound_.resize(at(n_b));
    present_reach2_.resize(at(n_b));
    rebuild(nullptr);
  }

  // ---- the time step (ContactSet) ----

  /// Rebuilds when a vertex has moved more than tolerance / 2 since the last rebuild or the
  /// interval is reached (the only call that allocates), then takes each block's motion for
  /// the step.
  void prepare_step(const node_set& gridpoints, real /*dt*/) {
    ++steps_since_rebuild_;
    const real* u[3] = {gridpoints.displacement.col(0).data(), gridpoints.displacement.col(1).data(),
                        gridpoints.displacement.col(2).data()};
    // Per block, in one parallel loop: its affine motion this step (the pairs read it, rather
    // than gathering the four frame gridpoints of both blocks at every corner) and how far its
    // watched gridpoints moved since the last rebuild (a rebuild leaves the motion as it is).
    parallel_for(
        static_cast<std::int64_t>(blocks_.size()),
        [&](std::int64_t b) {
          const block_data& bd = blocks_[at(b)];
          motion_[at(b)] = motion_of(bd, gridpoints);
          real m2 = 0;
          for (index_t k = bd.watch_begin; k < bd.watch_end; ++k) {
            const auto g = at(watch_gridpoints_[at(k)]);
            const real dx = u[0][g] - rebuild_u_(k, 0), dy = u[1][g] - rebuild_u_(k, 1), dz = u[2][g] - rebuild_u_(k, 2);
            m2 = std::max(m2, (dx * dx + dy * dy) + dz * dz);
          }
          moved_[at(b)] = m2;
        },
        64);
    const real moved2 = moved_.empty() ? real(0) : *std::max_element(moved_.begin(), moved_.end());
    // Deformable blocks: detection read each block's affine fit, within max_deviation_ of its
    // surface gridpoints, so the trigger keeps that much of the half tolerance in reserve.
    const real half = 0.5 * options_.tolerance - max_deviation_;
    if (moved2 > half * half || steps_since_rebuild_ >= options_.max_rebuild_interval) rebuild(&gridpoints);
  }
  [[nodiscard]] index_t task_count() const { return static_cast<index_t>(pair_tasks_.size()) - 1; }
  /// Kinematics, law update and force of the sub-contacts of the pairs of task t (the blocks'
  /// motion was read from the gridpoints in prepare_step).
  void run_task(index_t t, const node_set& gridpoints, real dt) noexcept {
    // In runs of up to normal_batch pairs: first every pair's normals, then the sub-contacts.
    // (Each normal is a chain of dependent operations through a square root and divisions;
    // computed ahead, the chains of several pairs overlap instead of each holding up its own
    // pair's sub-contacts.)
    std::array<std::array<triple, 3>, normal_batch> normals, tilts;
    for (index_t k0 = pair_tasks_[at(t)]; k0 < pair_tasks_[at(t) + 1]; k0 += normal_batch) {
      const index_t k1 = std::min<index_t>(k0 + normal_batch, pair_tasks_[at(t) + 1]);
      for (index_t k = k0; k < k1; ++k) turn_normals(at(k), normals[at(k - k0)], tilts[at(k - k0)]);
      for (index_t k = k0; k < k1; ++k)
        if (options_.deformable_blocks)
          update_pair_zoned(k, dt, gridpoints, normals[at(k - k0)], tilts[at(k - k0)]);
        else
          update_pair(k, dt, normals[at(k - k0)], tilts[at(k - k0)]);
    }
  }
  /// Adds the contact force on gridpoint g (N) to gridpoints.force, summed over its slots in
  /// increasing order: rigid blocks, the pairs' frame-gridpoint sums (pair_force_, in pair
  /// order); deformable blocks, the weighted sub-contact forces (in sub-contact order).
  void add_force(index_t g, node_set& gridpoints) const noexcept {
    const index_t begin = slot_offsets_[at(g)], end = slot_offsets_[at(g) + 1];
    if (begin == end) return;
    real fx = 0, fy = 0, fz = 0;
    if (!options_.deformable_blocks) {
      for (index_t e = begin; e < end; ++e) {
        const real* f = pair_force_.data() + slot_source_[at(e)];
        fx += f[0];
        fy += f[1];
        fz += f[2];
      }
    } else {
      for (index_t e = begin; e < end; ++e) {
        const auto i = at(slot_source_[at(e)]);
        const real w = slot_weight_[at(e)];
        fx += w * force_[0][i];
        fy += w * force_[1][i];
        fz += w * force_[2][i];
      }
    }
    gridpoints.force(g, 0) += fx;
    gridpoints.force(g, 1) += fy;
    gridpoints.force(g, 2) += fz;
  }
  /// prepare_step, every task, the gather (the unfused path, which blocks::rigid takes).
  void update(node_set& gridpoints, real dt) {
    prepare_step(gridpoints, dt);
    // Tasks of >= task_subcontacts sub-contacts (some 30 000 instructions each): serial below
    // 2 x serial_tasks tasks, where a fork/join per step costs more than it saves on a shared
    // machine (a 21-block stack of 80 sub-contacts on 2 threads at load 8: 729 -> 26 us a
    // step). Same bits either way: a task writes only its own sub-contacts.
    parallel_for(task_count(), [&](std::int64_t t) { run_task(static_cast<index_t>(t), gridpoints, dt); }, serial_tasks);
    parallel_for(static_cast<std::int64_t>(contact_gridpoints_.size()),
                 [&](std::int64_t j) { add_force(contact_gridpoints_[at(j)], gridpoints); });
  }
  /// Adds the contacts' stiffness bounds (N/m) to gridpoints.stiffness, as params::step_bound
  /// says (file comment, "Stable step"): rigid blocks, per block on its farthest vertex, from the
  /// sub-contacts present (valid until the next rebuild) or from its whole surface (valid for the
  /// whole run; also when no sub-contact exists); deformable blocks, per surface gridpoint. Throws
  /// invalid_input for a node_set of another model.
  void add_stiffness_bounds(node_set& gridpoints) const { add_bounds(gridpoints, options_.step_bound); }
  /// The same with step_bound_scope::whole_surface, whatever params::step_bound says: the bound
  /// for a dt chosen once for the whole run (the solver's given dt or mass scaling).
  void add_whole_surface_stiffness_bounds(node_set& gridpoints) const {
    add_bounds(gridpoints, step_bound_scope::whole_surface);
  }
  /// params::step_bound.
  [[nodiscard]] step_bound_scope step_bound() const { return options_.step_bound; }
  /// params::deformable_blocks.
  [[nodiscard]] bool deformable_blocks() const { return options_.deformable_blocks; }
  /// Deformable blocks: the largest distance (m) of a surface gridpoint from its block's affine
  /// fit at the last rebuild (the geometry detection read); 0 for rigid blocks.
  [[nodiscard]] real max_deviation() const { return max_deviation_; }

  // ---- sub-contacts ----
  [[nodiscard]] index_t size() const { return static_cast<index_t>(key_label_.size()); }
  [[nodiscard]] index_t subcontact_count() const { return size(); }
  [[nodiscard]] index_t pair_count() const { return static_cast<index_t>(pair_a_.size()); }
  [[nodiscard]] const state_type& state(index_t i) const { return state_[at(i)]; }
  [[nodiscard]] real area(index_t i) const { return area_[at(i)]; }
  [[nodiscard]] index_t pair_of(index_t i) const { return pair_[at(i)]; }
  /// Unit normal of sub-contact i, A -> B: that of the face its vertex is pushed by (a face of A
  /// for a vertex of B and the other way round, when the faces are parallel), else the pair's.
  [[nodiscard]] vec3 normal(index_t i) const { return normal_[corner_normal_[at(i)]].row(pair_[at(i)]).transpose(); }
  /// Force on block B's side in the last update (N); A's side received its opposite.
  [[nodiscard]] vec3 force(index_t i) const { return -vec3(force_[0][at(i)], force_[1][at(i)], force_[2][at(i)]); }
  [[nodiscard]] index_t block_a(index_t i) const { return pair_a_[at(pair_[at(i)])]; }
  [[nodiscard]] index_t block_b(index_t i) const { return pair_b_[at(pair_[at(i)])]; }
  /// First gridpoint of sub-contact i's material point on block A / B (its frame's for rigid
  /// blocks, its zone's or its own gridpoint for deformable ones; the force goes to all four).
  [[nodiscard]] index_t node_a(index_t i) const {
    return options_.deformable_blocks ? node_[0][at(i)] : blocks_[at(block_a(i))].frame[0];
  }
  [[nodiscard]] index_t node_b(index_t i) const {
    return options_.deformable_blocks ? node_[4][at(i)] : blocks_[at(block_b(i))].frame[0];
  }
  /// corner_label of sub-contact i (detection/common_plane.hpp).
  [[nodiscard]] std::uint64_t label(index_t i) const { return key_label_[at(i)]; }
  [[nodiscard]] const params_type& subcontact_params(index_t i) const { return law_params_[at(pair_param_[at(pair_[at(i)])])]; }
  /// Current position (m) of the material point of sub-contact i on block A / B.
  [[nodiscard]] vec3 position_a(index_t i, const node_set& gp) const { return point(i, true, gp); }
  [[nodiscard]] vec3 position_b(index_t i, const node_set& gp) const { return point(i, false, gp); }

  // ---- rebuild statistics ----
  /// Detection passes so far, the construction's included (the solver chooses dt again when it
  /// changes, file comment "Stable step").
  [[nodiscard]] index_t rebuild_count() const { return rebuilds_; }
  /// Rebuilds at which a per-sub-contact or per-pair array had to grow (allocate).
  [[nodiscard]] index_t growth_count() const { return growths_; }
  [[nodiscard]] index_t peak_subcontacts() const { return peak_subcontacts_; }
  /// Wall time spent in rebuilds so far, the construction's included (s; for reports, never
  /// for results).
  [[nodiscard]] double rebuild_seconds() const { return rebuild_seconds_; }
  /// Candidate pairs of the last pass.
  [[nodiscard]] std::size_t candidate_count() const { return result_.candidates; }
  /// Sub-contacts of the last rebuild that kept the state of an earlier one.
  [[nodiscard]] index_t kept_last_rebuild() const { return kept_last_; }
  [[nodiscard]] real tolerance() const { return options_.tolerance; }
  /// Sub-contacts that started bonded at construction (params::bond_faces; 0 without).
  [[nodiscard]] index_t bonded_at_start() const { return bonded_at_start_; }

  /// Energies of the current sub-contacts plus what those that ended at rebuilds dissipated (J),
  /// and the rebuild exchange: the change of the springs' elastic energy at each rebuild after
  /// the first (new corners that start overlapped, tributary areas that change, corners dropped
  /// while loaded). That change is no work of any force; the solver's energy balance books it
  /// beside the supplied energy so error_rel measures the integration, and reports it.
  [[nodiscard]] contact_energies energies() const {
    contact_energies e = retired_;
    for (index_t i = 0; i < size(); ++i) {
      const contact_energies c = energies_of(at(i));
      e.stored += c.stored;
      e.dissipated += c.dissipated;
      e.dissipated_tension += c.dissipated_tension;
      e.dissipated_shear += c.dissipated_shear;
      e.dissipated_compression += c.dissipated_compression;
    }
    return e;
  }
  /// The part of energies() held by sub-contacts that ended at rebuilds, and the rebuild exchange (J).
  [[nodiscard]] const contact_energies& retired_energies() const { return retired_; }

  /// Saves or loads everything a rebuild and a step read (io/checkpoint.hpp): the sub-contacts
  /// (keys, pairs, areas, affine weights, law states field by field, forces, fresh flags), the
  /// pairs (blocks, parameters, normal features, normals now; the tasks and gather slots are
  /// derived from them again on load), the vertex displacements of the last rebuild and the
  /// steps since it, the energies of the sub-contacts that ended and the rebuild statistics. Their sizes change during a run, so the file gives
  /// them (ar.count) and a load resizes; the model's own (block count, tolerance, rebuild
  /// interval) must match. So a restart rebuilds at the same steps and is bit-identical.
  template <class Archive>
  void checkpoint(Archive& ar) {
    static_assert(law::DeclaresStateFields<Law>, "checkpoints need a law that declares state_fields");
    ar.same("detected/blocks", static_cast<std::int64_t>(blocks_.size()));
    ar.same("detected/gridpoints", static_cast<std::int64_t>(gridpoint_count_));
    ar.same("detected/tolerance", options_.tolerance);
    ar.same("detected/max_rebuild_interval", static_cast<std::int64_t>(options_.max_rebuild_interval));
    std::int64_t n_pairs = pair_count(), n = size();
    ar.count("detected/pairs", n_pairs);
    ar.count("detected/subcontacts", n);
    // Variable-size arrays: the dry pass checks the records against the file's sizes on scratch
    // arrays; the copy pass resizes the model's.
    const auto sized = [&](const std::string& name, auto& v, std::int64_t count) {
      using V = std::remove_reference_t<decltype(v)>;
      constexpr bool rows = std::is_same_v<V, soa3>;  // n x 3 matrices: count rows
      const auto pass = [&](V& x) {
        if constexpr (rows) {
          x.resize(static_cast<index_t>(count), 3);
          ar.matrix(name, x);
        } else {
          x.resize(static_cast<std::size_t>(count));
          ar.array(name, x);
        }
      };
      if (ar.saving() || ar.loading()) {
        pass(v);
      } else {
        V dry;
        pass(dry);
      }
    };
    // per pair
    sized("detected/pair/a", pair_a_, n_pairs);
    sized("detected/pair/b", pair_b_, n_pairs);
    sized("detected/pair/param", pair_param_, n_pairs);
    sized("detected/pair/first", pair_first_, n_pairs + 1);
    sized("detected/pair/feature", feature_, n_pairs);
    sized("detected/pair/feature_a", feature_a_, n_pairs);
    sized("detected/pair/feature_b", feature_b_, n_pairs);
    sized("detected/pair/side_a", side_a_, n_pairs);
    sized("detected/pair/side_b", side_b_, n_pairs);
    for (int j = 0; j < 3; ++j) sized("detected/pair/normal/" + std::to_string(j), normal_[at(j)], n_pairs);
    // per sub-contact
    sized("detected/subcontact/pair", pair_, n);
    sized("detected/subcontact/label", key_label_, n);
    sized("detected/subcontact/normal", corner_normal_, n);
    sized("detected/subcontact/area", area_, n);
    sized("detected/subcontact/fresh", fresh_, n);
    for (int k = 0; k < 8; ++k) sized("detected/subcontact/weight/" + std::to_string(k), weight_[at(k)], n);
    for (int c = 0; c < 3; ++c) sized(std::string("detected/subcontact/force_a/") + "xyz"[c], force_[at(c)], n);
    if (options_.deformable_blocks) {
      for (int k = 0; k < 8; ++k) sized("detected/subcontact/gridpoint/" + std::to_string(k), node_[at(k)], n);
      ar.scalar("detected/max_deviation", max_deviation_);
    }
    if (ar.loading()) state_.resize(static_cast<std::size_t>(n));
    law::checkpoint_states<Law>(
        ar, "detected/state/", static_cast<std::size_t>(n), [&](std::size_t i) { return state_[i]; },
        [&](std::size_t i, const state_type& st) { state_[i] = st; });
    // rebuild trigger, books, statistics
    ar.matrix("detected/rebuild_displacement", rebuild_u_);
    ar.scalar("detected/steps_since_rebuild", steps_since_rebuild_);
    ar.scalar("detected/retired/stored", retired_.stored);
    ar.scalar("detected/retired/dissipated", retired_.dissipated);
    ar.scalar("detected/retired/dissipated_tension", retired_.dissipated_tension);
    ar.scalar("detected/retired/dissipated_shear", retired_.dissipated_shear);
    ar.scalar("detected/retired/dissipated_compression", retired_.dissipated_compression);
    ar.scalar("detected/retired/rebuild_exchange", retired_.rebuild_exchange);
    ar.scalar("detected/rebuilds", rebuilds_);
    ar.scalar("detected/growths", growths_);
    ar.scalar("detected/peak_subcontacts", peak_subcontacts_);
    ar.scalar("detected/kept_last_rebuild", kept_last_);
    // Tasks and gather slots follow from the pairs and weights.
    if (ar.loading()) index_subcontacts();
  }

 private:
  void add_bounds(node_set& gridpoints, step_bound_scope scope) const {
    require(gridpoints.size() == gridpoint_count_ && gridpoints.stiffness.size() == gridpoint_count_,
            "detected_contacts::add_stiffness_bounds: node_set has ", gridpoints.size(), " gridpoints, expected ",
            gridpoint_count_);
    if (options_.deformable_blocks) {
      for (index_t g = 0; g < gridpoint_count_; ++g) gridpoints.stiffness[g] += gridpoint_bound_[at(g)];
      return;
    }
    const bool present = scope == step_bound_scope::present_contacts && size() > 0;
    for (std::size_t b = 0; b < blocks_.size(); ++b)
      gridpoints.stiffness[blocks_[b].farthest] += present ? present_bound_[b] : blocks_[b].stiffness_bound;
  }

  /// Rigid blocks: per block, the bound of its present sub-contacts on its farthest vertex (file
  /// comment, "Stable step"), from the pairs' law entries, the areas and the weights (so a
  /// checkpoint load gets the same bits as the rebuild). Allocates nothing.
  void bound_present_contacts() {
    std::fill(present_bound_.begin(), present_bound_.end(), 0.0);
    std::fill(present_reach2_.begin(), present_reach2_.end(), 0.0);
    for (std::size_t k = 0; k < pair_a_.size(); ++k) {
      const real per_area = 2 * entry_row_bound_[at(pair_param_[k])];
      const std::array<index_t, 2> ab{pair_a_[k], pair_b_[k]};
      for (int side = 0; side < 2; ++side) {
        const block_data& bd = blocks_[at(ab[at(side)])];
        // The material point in the block's reference frame: X0 + D (w1, w2, w3), rigid motion
        // keeps its distance from the centroid.
        const mat3 d = frame_matrix(bd, nullptr);
        const vec3 x0 = reference_.row(bd.frame[0]).transpose();
        real k_sum = 0, reach2 = 0;
        for (auto i = at(pair_first_[k]); i < at(pair_first_[k + 1]); ++i) {
          k_sum += per_area * area_[i];
          const int w = 4 * side;
          const vec3 local(weight_[at(w + 1)][i], weight_[at(w + 2)][i], weight_[at(w + 3)][i]);
          reach2 = std::max(reach2, (x0 + d * local - bd.centroid).squaredNorm());
        }
        present_bound_[at(ab[at(side)])] += k_sum;
        present_reach2_[at(ab[at(side)])] = std::max(present_reach2_[at(ab[at(side)])], reach2);
      }
    }
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
      const real far2 = (reference_.row(blocks_[b].farthest).transpose() - blocks_[b].centroid).squaredNorm();
      if (present_reach2_[b] > far2) present_bound_[b] *= present_reach2_[b] / far2;
    }
  }

  struct block_data {
    std::array<index_t, 4> frame{};  ///< vertex gridpoints spanning the block
    mat3 reference_inverse = mat3::Identity();  ///< [X1-X0 X2-X0 X3-X0]^-1
    index_t vertex_begin = 0, vertex_end = 0;     ///< into vertex_gridpoints_ (local vertex order)
    index_t farthest = 0;                         ///< vertex gridpoint farthest from the centroid
    real stiffness_bound = 0;                   ///< N/m, on `farthest`
    real nominal_area = 0;                      ///< S / (3 V), m^2
    real surface = 0;                           ///< S, m^2
    vec3 centroid = vec3::Zero();               ///< reference centroid (m)
    index_t watch_begin = 0, watch_end = 0;  ///< its watched gridpoints (rigid: vertices; deformable: surface)
    // deformable blocks only
    index_t zone_begin = 0, zone_end = 0;    ///< its surface zones, into surface_zones_
    index_t face_begin = 0;                  ///< its first tessellation face (local face f = face_begin + f)
  };

  /// A gridpoint sub-contact of a deformable patch (collect_nodes).
  struct node_contact {
    std::uint64_t label = 0;
    index_t gridpoint = 0;
    real area = 0, gap = 0;
  };
  /// Label of a gridpoint sub-contact: kind 3 (beside corner_label's 0-2), bit 61 the side (B),
  /// the gridpoint below; and its three readers.
  [[nodiscard]] static constexpr std::uint64_t node_label(index_t g, bool side_b) noexcept {
    return (std::uint64_t{3} << 62) | (side_b ? std::uint64_t{1} << 61 : 0) | static_cast<std::uint64_t>(g);
  }
  [[nodiscard]] static constexpr bool is_node_label(std::uint64_t label) noexcept { return (label >> 62) == 3; }
  [[nodiscard]] static constexpr bool node_label_side_b(std::uint64_t label) noexcept { return ((label >> 61) & 1U) != 0; }
  [[nodiscard]] static constexpr index_t node_label_gridpoint(std::uint64_t label) noexcept {
    return static_cast<index_t>(label & ((std::uint64_t{1} << 61) - 1));
  }

  /// Deformable blocks: surface gridpoints, surface zones and the per-gridpoint stiffness bounds
  /// (file comment, "Deformable blocks").
  void build_surfaces(const geometry::tessellation& tess, const geometry::block_mesh& mesh, real row_max) {
    const index_t n_faces = static_cast<index_t>(mesh.face_node_offsets.size()) - 1;
    require<geometry_error>(n_faces == static_cast<index_t>(tess.face_cell.size()) &&
                                mesh.face_node_area.size() == mesh.face_nodes.size() &&
                                static_cast<index_t>(mesh.face_triangle_offsets.size()) == n_faces + 1,
                            "detected_contacts: the block_mesh has surface nodes for ", n_faces, " faces, the tessellation ",
                            tess.face_cell.size(), " (zone the blocks with geometry::zone_blocks)");
    face_node_offsets_ = mesh.face_node_offsets;
    face_nodes_ = mesh.face_nodes;
    face_node_area_ = mesh.face_node_area;
    zones_ = mesh.zones;
    std::vector<real> own(at(gridpoint_count_), 0.0), around(at(gridpoint_count_), 0.0);
    std::vector<std::uint8_t> on_surface(at(gridpoint_count_), 0);
    real a_max = 0;
    for (real a : face_node_area_) a_max = std::max(a_max, a);
    for (const block_data& bd : blocks_) a_max = std::max(a_max, bd.nominal_area);
    std::vector<index_t> nodes;
    std::vector<real> zone_area;
    for (index_t b = 0; b < static_cast<index_t>(blocks_.size()); ++b) {
      block_data& bd = blocks_[at(b)];
      bd.face_begin = tess.first_face(b);
      nodes.clear();
      for (index_t f = tess.first_face(b); f < tess.end_face(b); ++f)
        for (index_t e = face_node_offsets_[at(f)]; e < face_node_offsets_[at(f) + 1]; ++e) {
          nodes.push_back(face_nodes_[at(e)]);
          own[at(face_nodes_[at(e)])] += face_node_area_[at(e)];
        }
      std::sort(nodes.begin(), nodes.end());
      nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
      bd.watch_begin = static_cast<index_t>(watch_gridpoints_.size());
      watch_gridpoints_.insert(watch_gridpoints_.end(), nodes.begin(), nodes.end());
      bd.watch_end = static_cast<index_t>(watch_gridpoints_.size());
      // The zone of each surface triangle (the one holding its three gridpoints) and the area of
      // the surface it carries.
      const index_t z0 = mesh.block_zone_offsets[at(b)], z1 = mesh.block_zone_offsets[at(b) + 1];
      zone_area.assign(at(z1 - z0), 0.0);
      for (index_t f = tess.first_face(b); f < tess.end_face(b); ++f)
        for (index_t t = mesh.face_triangle_offsets[at(f)]; t < mesh.face_triangle_offsets[at(f) + 1]; ++t) {
          const auto& tri = mesh.face_triangles[at(t)];
          index_t found = invalid_index;
          for (index_t z = z0; z < z1 && found == invalid_index; ++z) {
            const auto& zn = zones_[at(z)];
            const auto has = [&](index_t g) { return std::find(zn.begin(), zn.end(), g) != zn.end(); };
            if (has(tri[0]) && has(tri[1]) && has(tri[2])) found = z;
          }
          require<geometry_error>(found != invalid_index, "detected_contacts: surface triangle ", t, " of block ", b,
                                  " belongs to none of its zones");
          const vec3 x0 = reference_.row(tri[0]).transpose();
          zone_area[at(found - z0)] += 0.5 * (vec3(reference_.row(tri[1]).transpose()) - x0)
                                                 .cross(vec3(reference_.row(tri[2]).transpose()) - x0)
                                                 .norm();
        }
      bd.zone_begin = static_cast<index_t>(surface_zones_.size());
      for (index_t z = z0; z < z1; ++z)
        if (zone_area[at(z - z0)] > 0) {
          surface_zones_.push_back(z);
          for (index_t g : zones_[at(z)]) {
            around[at(g)] += zone_area[at(z - z0)];
            on_surface[at(g)] = 1;
          }
        }
      bd.zone_end = static_cast<index_t>(surface_zones_.size());
      require<geometry_error>(bd.zone_end > bd.zone_begin, "detected_contacts: block ", b, " has no surface zones");
    }
    // Gridpoint g carries its own gridpoint sub-contacts (area own) and the material points that
    // land in its surface zones (at most the surface they carry, plus the largest tributary area
    // of a gridpoint or corner straddling their edge, on either side): 4 k_row x that area.
    gridpoint_bound_.assign(at(gridpoint_count_), 0.0);
    for (index_t g = 0; g < gridpoint_count_; ++g)
      if (on_surface[at(g)] != 0) gridpoint_bound_[at(g)] = 4 * row_max * (own[at(g)] + 2 * around[at(g)] + 2 * a_max);
  }

  /// Deformable blocks: the surface zone of block b holding x (the largest smallest barycentric
  /// weight, so a point just outside the surface takes the zone below it) and x's weights in it.
  void locate(index_t b, const vec3& x, const node_set* gp, std::array<index_t, 4>& nodes, std::array<real, 4>& w) const {
    const block_data& bd = blocks_[at(b)];
    real best = -std::numeric_limits<real>::infinity();
    for (index_t s = bd.zone_begin; s < bd.zone_end; ++s) {
      const auto& zn = zones_[at(surface_zones_[at(s)])];
      const vec3 x0 = position(zn[0], gp);
      mat3 d;
      d << position(zn[1], gp) - x0, position(zn[2], gp) - x0, position(zn[3], gp) - x0;
      const vec3 l = d.inverse() * (x - x0);
      const real smallest = std::min({1 - l.sum(), l.x(), l.y(), l.z()});
      if (smallest > best) {
        best = smallest;
        nodes = zn;
        w = {1 - l.sum(), l.x(), l.y(), l.z()};
      }
    }
  }

  /// Deformable blocks: the gridpoints and weights of sub-contact i of pair (a, b): a gridpoint
  /// sub-contact is its own gridpoint on its side and located in the other block's zones; a corner
  /// is located in both.
  void place_zoned(std::size_t i, index_t a, index_t b, const node_set* gp) {
    std::array<index_t, 4> na{}, nb{};
    std::array<real, 4> wa{}, wb{};
    const std::uint64_t label = key_label_[i];
    const bool node = is_node_label(label);
    const bool node_side_b = node && node_label_side_b(label);
    const auto own = [&](std::array<index_t, 4>& nodes, std::array<real, 4>& w) {
      nodes = {node_label_gridpoint(label), invalid_index, invalid_index, invalid_index};
      w = {1, 0, 0, 0};
    };
    if (node && !node_side_b)
      own(na, wa);
    else
      locate(a, new_point_[i], gp, na, wa);
    if (node && node_side_b)
      own(nb, wb);
    else
      locate(b, new_point_[i], gp, nb, wb);
    for (int k = 0; k < 4; ++k) {
      node_[at(k)][i] = na[at(k)];
      node_[at(4 + k)][i] = nb[at(k)];
      weight_[at(k)][i] = wa[at(k)];
      weight_[at(4 + k)][i] = wb[at(k)];
    }
  }

  /// The side whose gridpoints pair (a, b) used at the last rebuild: 0 A, 1 B, -1 corners or no
  /// such pair (reads the old pairs, before the rebuild replaces them).
  [[nodiscard]] int previous_node_side(index_t a, index_t b) const {
    const auto n_old = static_cast<std::ptrdiff_t>(pair_a_.size());
    std::ptrdiff_t lo = 0, hi = n_old;
    while (lo < hi) {  // first old pair >= (a, b)
      const std::ptrdiff_t mid = (lo + hi) / 2;
      const auto m = static_cast<std::size_t>(mid);
      if (pair_a_[m] < a || (pair_a_[m] == a && pair_b_[m] < b))
        lo = mid + 1;
      else
        hi = mid;
    }
    const auto k = static_cast<std::size_t>(lo);
    if (lo == n_old || pair_a_[k] != a || pair_b_[k] != b || pair_first_[k + 1] == pair_first_[k]) return -1;
    const std::uint64_t label = key_label_[at(pair_first_[k])];
    if (!is_node_label(label)) return -1;
    return node_label_side_b(label) ? 1 : 0;
  }

  /// Deformable blocks, polygon patch of pair k: the surface gridpoints on A's faces that face the
  /// plane (within parallel_cos) and lie inside the patch, and those on B's; keeps in
  /// node_scratch_, sorted by label, the side whose tributary areas (block_mesh::face_node_area)
  /// fit the patch area (below), each with its area scaled and its gap to the other block. false
  /// (the patch keeps its corners) when the side has fewer than three.
  bool collect_nodes(std::size_t k, const node_set* gp) {
    const vec3 n = result_.planes[k].normal;
    const vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
    const auto first = at(result_.first_corner[k]), last = at(result_.first_corner[k + 1]);
    using point2 = Eigen::Matrix<real, 2, 1>;
    polygon_.clear();
    point2 centre = point2::Zero();
    for (std::size_t j = first; j < last; ++j) {
      polygon_.emplace_back(t1.dot(result_.point[j]), t2.dot(result_.point[j]));
      centre += polygon_.back();
    }
    centre /= static_cast<real>(polygon_.size());
    std::sort(polygon_.begin(), polygon_.end(), [&](const point2& p, const point2& q) {
      return std::atan2(p.y() - centre.y(), p.x() - centre.x()) < std::atan2(q.y() - centre.y(), q.x() - centre.x());
    });
    real extent = 0;
    for (const point2& p : polygon_) extent = std::max(extent, (p - centre).norm());
    // A gridpoint counts when it lies within half the tolerance of the patch: the patch comes
    // from the affine fits, from which a face's own gridpoints (its edge ones among them) may
    // stand off by max_deviation_.
    const real eps = std::max(1e-6 * extent, 0.5 * options_.tolerance);
    const auto inside = [&](const point2& q) {
      for (std::size_t e = 0; e < polygon_.size(); ++e) {
        const point2& p0 = polygon_[e];
        const point2& p1 = polygon_[(e + 1) % polygon_.size()];
        const real cross = (p1.x() - p0.x()) * (q.y() - p0.y()) - (p1.y() - p0.y()) * (q.x() - p0.x());
        if (cross < -eps * (p1 - p0).norm()) return false;  // farther than eps outside edge e
      }
      return true;
    };
    const index_t a = result_.pairs[k].a, b = result_.pairs[k].b;
    std::array<std::vector<node_contact>*, 2> found{&node_scratch_, &node_other_};
    for (int side = 0; side < 2; ++side) {
      std::vector<node_contact>& out = *found[at(side)];
      out.clear();
      const index_t self = side == 0 ? a : b, other = side == 0 ? b : a;
      const real sign = side == 0 ? 1.0 : -1.0;
      // The other block's extreme along -sign n: its face that the patch lies on.
      const real support = side == 0 ? detection::detail::support_min(current_[at(other)], n)
                                     : detection::detail::support_max(current_[at(other)], n);
      const auto faces = workspace_.faces_of(at(self));  // this pass's face planes
      for (index_t f = 0; f < static_cast<index_t>(faces.size()); ++f) {
        if (sign * faces[at(f)].normal.dot(n) <= parallel_cos) continue;
        const index_t tf = blocks_[at(self)].face_begin + f;
        for (index_t e = face_node_offsets_[at(tf)]; e < face_node_offsets_[at(tf) + 1]; ++e) {
          const index_t g = face_nodes_[at(e)];
          const vec3 x = position(g, gp);
          if (!inside(point2(t1.dot(x), t2.dot(x)))) continue;
          out.push_back({node_label(g, side == 1), g, face_node_area_[at(e)], sign * (support - n.dot(x))});
        }
      }
    }
    // The side whose gridpoints' tributary areas cover the patch best: the face that lies inside
    // the other (a small block on a large one) has areas summing to the patch's, while the large
    // face's gridpoints on the patch edge carry areas reaching beyond it. A side needs three
    // gridpoints; on a tie, A. Its areas are then scaled to sum to the patch's area.
    real patch_area = 0;
    for (std::size_t e = 0; e < polygon_.size(); ++e) {
      const point2& p0 = polygon_[e];
      const point2& p1 = polygon_[(e + 1) % polygon_.size()];
      patch_area += 0.5 * (p0.x() * p1.y() - p1.x() * p0.y());
    }
    const auto misfit = [&](const std::vector<node_contact>& side) {
      if (side.size() < 3) return std::numeric_limits<real>::infinity();
      real sum = 0;
      for (const node_contact& c : side) sum += c.area;
      return std::abs(sum - patch_area);
    };
    // Keep the side the pair used at the last rebuild while it still fits within 5 % of the patch
    // area of the other: on coinciding faces both sides fit to round-off, and a flip would drop
    // every sub-contact's state (a bonded face would come back unbonded). Else the better fit,
    // A unless B is better by more than round-off.
    const real fit_a = misfit(node_scratch_), fit_b = misfit(node_other_), slack = 0.05 * patch_area;
    const int previous = previous_node_side(a, b);
    const bool use_b = previous == 1 && std::isfinite(fit_b)   ? fit_b <= fit_a + slack
                       : previous == 0 && std::isfinite(fit_a) ? fit_a > fit_b + slack
                                                               : fit_b < fit_a - 1e-9 * patch_area;
    if (use_b) node_scratch_.swap(node_other_);
    if (node_scratch_.size() < 3 || !(patch_area > 0)) return false;
    real covered = 0;
    for (const node_contact& c : node_scratch_) covered += c.area;
    for (node_contact& c : node_scratch_) c.area *= patch_area / covered;
    std::sort(node_scratch_.begin(), node_scratch_.end(),
              [](const node_contact& x, const node_contact& y) { return x.label < y.label; });
    // A gridpoint on two faces that both face the plane cannot occur (convex, parallel_cos), but
    // keep labels unique whatever the input.
    node_scratch_.erase(std::unique(node_scratch_.begin(), node_scratch_.end(),
                                    [](const node_contact& x, const node_contact& y) { return x.label == y.label; }),
                        node_scratch_.end());
    return true;
  }

  /// Energies of sub-contact i (J).
  [[nodiscard]] contact_energies energies_of(std::size_t i) const {
    contact_energies e;
    const state_type& st = state_[i];
    const real a = area_[i];
    e.stored = a * Law::stored_energy(law_params_[at(pair_param_[at(pair_[i])])], st);
    e.dissipated = a * Law::dissipated_energy(st);
    if constexpr (detail::has_dissipation_split<state_type>) {
      e.dissipated_tension = a * st.dissipated_tension;
      e.dissipated_shear = a * st.dissipated_shear;
      e.dissipated_compression = a * st.dissipated_compression;
    }
    return e;
  }

  [[nodiscard]] vec3 position(index_t g, const node_set* gp) const {
    vec3 x = reference_.row(g).transpose();
    if (gp != nullptr) x += gp->displacement.row(g).transpose();
    return x;
  }
  [[nodiscard]] vec3 point(index_t i, bool side_a, const node_set& gp) const {
    const block_data& b = blocks_[at(side_a ? block_a(i) : block_b(i))];
    vec3 x = vec3::Zero();
    for (int k = 0; k < 4; ++k) {
      const int slot = side_a ? k : 4 + k;
      const index_t g = options_.deformable_blocks ? node_[at(slot)][at(i)] : b.frame[at(k)];
      if (g != invalid_index) x += weight_[at(slot)][at(i)] * position(g, &gp);
    }
    return x;
  }

  /// Vertex gridpoints, shape, edges, frame and bounds of block b.
  void build_block(const geometry::tessellation& tess, const geometry::block_mesh& mesh, index_t b) {
    // The tessellation vertex -> gridpoint map of this block.
    std::vector<std::pair<index_t, index_t>> vertex_gp;
    for (index_t g = mesh.block_gridpoint_offsets[at(b)]; g < mesh.block_gridpoint_offsets[at(b) + 1]; ++g)
      if (const index_t v = mesh.gridpoint_vertex[at(g)]; v != invalid_index) vertex_gp.emplace_back(v, g);
    std::sort(vertex_gp.begin(), vertex_gp.end());
    block_data& bd = blocks_[at(b)];
    bd.vertex_begin = static_cast<index_t>(vertex_gridpoints_.size());
    // Local vertices in order of first use, as geometry::cell_polyhedron numbers them.
    std::vector<index_t> local;
    for (index_t f = tess.first_face(b); f < tess.end_face(b); ++f)
      for (index_t v : tess.face(f))
        if (std::find(local.begin(), local.end(), v) == local.end()) {
          local.push_back(v);
          const auto it = std::lower_bound(vertex_gp.begin(), vertex_gp.end(), std::pair<index_t, index_t>{v, index_t{-1}});
          require<geometry_error>(it != vertex_gp.end() && it->first == v, "detected_contacts: vertex ", v,
                                  " of block ", b, " has no gridpoint in the block_mesh");
          vertex_gridpoints_.push_back(it->second);
        }
    bd.vertex_end = static_cast<index_t>(vertex_gridpoints_.size());
    shapes_[at(b)] = geometry::cell_polyhedron(tess, b);
    edges_[at(b)] = detection::edges_of(shapes_[at(b)]);
    const geometry::convex_polyhedron& s = shapes_[at(b)];
    // Frame: the first vertex, the farthest from it, the farthest from their line, the farthest
    // from their plane.
    const auto gp = [&](index_t k) { return vertex_gridpoints_[at(bd.vertex_begin + k)]; };
    const index_t nv = bd.vertex_end - bd.vertex_begin;
    const auto arg_max = [&](auto&& score) {
      index_t best = 0;
      for (index_t k = 1; k < nv; ++k)
        if (score(s.vertex(k)) > score(s.vertex(best))) best = k;
      return best;
    };
    const vec3 x0 = s.vertex(0);
    const index_t k1 = arg_max([&](const vec3& x) { return (x - x0).squaredNorm(); });
    const vec3 d1 = (s.vertex(k1) - x0).normalized();
    const index_t k2 = arg_max([&](const vec3& x) { return (x - x0 - d1 * d1.dot(x - x0)).squaredNorm(); });
    const vec3 n12 = d1.cross(s.vertex(k2) - x0).normalized();
    const index_t k3 = arg_max([&](const vec3& x) { return std::abs(n12.dot(x - x0)); });
    bd.frame = {gp(0), gp(k1), gp(k2), gp(k3)};
    mat3 d;
    d << s.vertex(k1) - x0, s.vertex(k2) - x0, s.vertex(k3) - x0;
    require<geometry_error>(std::abs(d.determinant()) > 1e-12 * std::pow(s.extent(), 3), "detected_contacts: block ", b,
                            " is flat (its vertices span no volume)");
    bd.reference_inverse = d.inverse();
    // Bounds.
    const vec3 c = s.centroid();
    real surface = 0;
    for (index_t f = 0; f < s.face_count(); ++f) surface += s.face_area(f);
    bd.farthest = gp(arg_max([&](const vec3& x) { return (x - c).squaredNorm(); }));
    bd.centroid = c;
    bd.surface = surface;
    bd.nominal_area = surface / (3 * static_cast<real>(nv));
  }

  /// Block b's frame now, [x1-x0 x2-x0 x3-x0] (reference positions when gp is null).
  [[nodiscard]] mat3 frame_matrix(const block_data& b, const node_set* gp) const {
    const vec3 x0 = position(b.frame[0], gp);
    mat3 d;
    d << position(b.frame[1], gp) - x0, position(b.frame[2], gp) - x0, position(b.frame[3], gp) - x0;
    return d;
  }
  /// Rotation of block b from its reference frame D: d D^-1.
  [[nodiscard]] mat3 rotation(const block_data& b, const node_set* gp) const {
    return frame_matrix(b, gp) * b.reference_inverse;
  }
  /// d^-1 of block b's frame now: a point's local coordinates are d^-1 (x - x0).
  [[nodiscard]] mat3 frame_inverse(const block_data& b, const node_set* gp) const { return frame_matrix(b, gp).inverse(); }

  /// A block's frame now: x(p) = x0 + d l, v(p) = v0 + dv l for the local coordinates l of a
  /// point (its weights 1..3), and the rotation d D^-1 from the reference frame D.
  /// For a deformable block `rotation` is the affine fit's gradient F = d D^-1 and normal_map
  /// F^-T (a face normal in the reference frame maps to F^-T n0, normalised); for a rigid one
  /// both are its rotation.
  struct block_motion {
    vec3 x0 = vec3::Zero(), v0 = vec3::Zero();
    mat3 d = mat3::Identity(), dv = mat3::Zero(), rotation = mat3::Identity(), normal_map = mat3::Identity();
  };
  [[nodiscard]] block_motion motion_of(const block_data& b, const node_set& gp) const {
    block_motion m;
    m.x0 = position(b.frame[0], &gp);
    m.d = frame_matrix(b, &gp);
    m.v0 = gp.velocity.row(b.frame[0]).transpose();
    for (int k = 1; k < 4; ++k) m.dv.col(k - 1) = gp.velocity.row(b.frame[at(k)]).transpose() - m.v0;
    m.rotation = m.d * b.reference_inverse;
    m.normal_map = options_.deformable_blocks ? mat3(m.rotation.inverse().transpose()) : m.rotation;
    return m;
  }

  /// The trap of a detected set (issue #40 item 3): its corners start unbonded, on the residual
  /// Coulomb limit c_res + sigma_c tan(phi_res), so a residual value left at 0 beside a non-zero
  /// initial one silently gives joints weaker than the user wrote. Refused, per material pair in
  /// use (the blocks' material ids), when the law has those fields:
  ///   phi_res = 0 while phi_0 > 0: always (new corners, and broken bonds, slide on phi_res);
  ///   c_res = 0 while c_0 > 0: when the pair starts unbonded (bond_faces off, or never_bonded),
  ///     since then c_0 is never used.
  /// Frictionless joints are phi_0 = phi_res = 0; law::dry_joint fills both angles.
  void refuse_unused_strengths(const geometry::block_mesh& mesh) const {
    if constexpr (requires(const params_type& q) {
                    q.shear.phi_0.radians();
                    q.shear.phi_res.radians();
                    real(q.shear.c_0);
                    real(q.shear.c_res);
                  }) {
      std::vector<int> ids;
      for (index_t b = 0; b < mesh.block_count(); ++b) ids.push_back(mesh.material(b));
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      for (std::size_t i = 0; i < ids.size(); ++i)
        for (std::size_t j = i; j < ids.size(); ++j) {
          const auto& e = table_.get(ids[i], ids[j]);
          const auto& sh = e.params.shear;
          require(!(sh.phi_res.radians() == 0 && sh.phi_0.radians() > 0), "detected_contacts: material pair (",
                  ids[i], ", ", ids[j], ") has residual friction phi_res = 0 deg while phi_0 = ", sh.phi_0.degrees(),
                  " deg: detected contacts start unbonded and slide at phi_res (so do broken bonds), which makes "
                  "these joints frictionless. Set shear.phi_res (e.g. = phi_0), or build the params with "
                  "law::dry_joint(k_n, k_s, phi); for frictionless joints write phi_0 = phi_res = 0");
          const bool starts_bonded = options_.bond_faces && e.bonded;
          require(starts_bonded || !(sh.c_res == 0 && sh.c_0 > 0), "detected_contacts: material pair (", ids[i],
                  ", ", ids[j], ") has residual cohesion c_res = 0 Pa while c_0 = ", sh.c_0,
                  " Pa, and its contacts start unbonded (",
                  options_.bond_faces ? "the table declares the pair never_bonded" : "bond_faces is false",
                  "), on the residual cohesion c_res: c_0 would never be used. Set shear.c_res, or "
                  "c_0 = 0 for a cohesionless joint (law::dry_joint), or bond_faces = true for faces that start "
                  "bonded (law::bonded_joint)");
        }
    }
  }

  /// params::allow_initial_overlap is false: refuses, after the construction's detection pass,
  /// a candidate pair whose penetration depth -g (the common plane's gap, exact for overlapping
  /// convex blocks: common_plane.hpp) exceeds the tolerance. Names the deepest such pair.
  void refuse_initial_overlaps() const {
    const auto& planes = workspace_.planes;
    const auto& pairs = workspace_.candidates;
    std::size_t deepest = planes.size();
    for (std::size_t k = 0; k < planes.size(); ++k)
      if (-planes[k].gap > options_.tolerance && (deepest == planes.size() || planes[k].gap < planes[deepest].gap))
        deepest = k;
    if (deepest == planes.size()) return;
    throw invalid_input(tessera::detail::concat(
        "detected_contacts: blocks ", pairs[deepest].a, " and ", pairs[deepest].b, " overlap by ", -planes[deepest].gap,
        " m at the start, more than the contact tolerance ", options_.tolerance,
        " m (a placement error: the overlap's springs would push them apart with energy no force supplied); move "
        "them apart, or set params::allow_initial_overlap = true if the overlap is meant"));
  }

  /// One detection pass on the current geometry and the merge of the sub-contacts (file comment).
  void rebuild(const node_set* gp) {
    const auto started = std::chrono::steady_clock::now();
    // The springs' energy before and after (the construction's pass sets the initial energy).
    const real stored_before = gp != nullptr ? stored_energy() : 0.0;
    ++rebuilds_;
    steps_since_rebuild_ = 0;
    const std::size_t capacity_before = storage_capacity();
    const auto n_b = static_cast<index_t>(blocks_.size());
    real deviation = 0;
    for (index_t b = 0; b < n_b; ++b) {
      const block_data& bd = blocks_[at(b)];
      const mat3 map = rotation(bd, gp);
      const vec3 translation = position(bd.frame[0], gp) - map * shapes_[at(b)].vertex(0);
      current_[at(b)] = shapes_[at(b)].transformed(map, translation);
      boxes_[at(b)] = current_[at(b)].bounds();
      // A deformable block is detected by its affine fit (the frame's map of its reference
      // shape): how far its surface gridpoints are from it.
      if (options_.deformable_blocks)
        for (index_t w = bd.watch_begin; w < bd.watch_end; ++w) {
          const index_t g = watch_gridpoints_[at(w)];
          const vec3 fit = map * reference_.row(g).transpose() + translation;
          deviation = std::max(deviation, (position(g, gp) - fit).norm());
        }
    }
    if (options_.deformable_blocks) {
      require<geometry_error>(deviation <= max_deviation_fraction * options_.tolerance,
                              "detected_contacts: a deformable block's surface lies ", deviation,
                              " m from its affine fit, more than ", max_deviation_fraction,
                              " x the contact tolerance (", options_.tolerance,
                              " m); detection reads the fit, so raise the tolerance (or stiffen the blocks)");
      max_deviation_ = deviation;
    }
    rebuild_u_.resize(static_cast<index_t>(watch_gridpoints_.size()), 3);
    for (std::size_t k = 0; k < watch_gridpoints_.size(); ++k)
      for (int c = 0; c < 3; ++c)
        rebuild_u_(static_cast<index_t>(k), c) = gp != nullptr ? gp->displacement(watch_gridpoints_[k], c) : 0.0;
    detection::detect(current_, edges_, boxes_, {options_.tolerance, options_.tolerance}, result_, workspace_);
    if (gp == nullptr && !options_.allow_initial_overlap) refuse_initial_overlaps();

    // New pairs and their corners, sorted by label within a pair (pairs come increasing).
    const std::size_t n_pairs = result_.pairs.size();
    new_pair_a_.clear();
    new_pair_b_.clear();
    new_label_.clear();
    new_area_.clear();
    new_point_.clear();
    new_gap_.clear();
    new_pair_first_.assign(1, 0);
    for (std::size_t k = 0; k < n_pairs; ++k) {
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
        new_pair_first_.push_back(static_cast<index_t>(new_label_.size()));
        continue;
      }
      order_.clear();
      for (std::size_t j = first; j < last; ++j) order_.push_back(j);
      std::sort(order_.begin(), order_.end(), [&](std::size_t x, std::size_t y) {
        return result_.label[x] < result_.label[y] || (result_.label[x] == result_.label[y] && x < y);
      });
      const bool polygon = result_.type[k] == detection::patch_type::polygon;
      const real nominal = std::min(blocks_[at(result_.pairs[k].a)].nominal_area, blocks_[at(result_.pairs[k].b)].nominal_area);
      for (std::size_t j : order_) {
        // A sliver polygon's corner keeps a floor of 1e-6 of the nominal area, so that areas stay
        // > 0 and the ratios of a rebuild (below) stay finite.
        const real a = polygon ? std::max(result_.area[j], 1e-6 * nominal) : nominal;
        // A label met twice (a corner within round-off of another) keeps its first point and
        // takes the other's area.
        if (new_label_.size() > at(new_pair_first_.back()) && new_label_.back() == result_.label[j]) {
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
      new_pair_first_.push_back(static_cast<index_t>(new_label_.size()));
    }
    const std::size_t n = new_label_.size();

    // Merge the states: old and new keys are both sorted by (a, b, label).
    new_state_.resize(n);
    new_fresh_.assign(n, 0);
    kept_last_ = 0;
    kept_old_.assign(key_label_.size(), 0);
    std::size_t old = 0;
    const std::size_t n_old = key_label_.size();
    for (std::size_t k = 0; k < n_pairs; ++k) {
      const index_t a = new_pair_a_[k], b = new_pair_b_[k];
      const params_type& p = law_params_[table_.entry_index(material_[at(a)], material_[at(b)])];
      for (auto i = at(new_pair_first_[k]); i < at(new_pair_first_[k + 1]); ++i) {
        const auto before = [&](std::size_t o) {
          const index_t oa = pair_a_[at(pair_[o])], ob = pair_b_[at(pair_[o])];
          return oa < a || (oa == a && (ob < b || (ob == b && key_label_[o] < new_label_[i])));
        };
        while (old < n_old && before(old)) ++old;
        if (old < n_old && pair_a_[at(pair_[old])] == a && pair_b_[at(pair_[old])] == b && key_label_[old] == new_label_[i]) {
          new_state_[i] = state_[old];
          // A tributary area that grows keeps the corner's force (stresses scaled down), one that
          // shrinks keeps its stresses: either way the spring's energy can only drop, so a
          // rebuild never feeds energy into the scene.
          // The energy it dissipated (per area in the state) stays what it was.
          if (const real a_old = area_[old]; new_area_[i] != a_old) {
            state_type& st = new_state_[i];
            const real r = a_old / new_area_[i];
            if (r < 1) Law::scale_stresses(p, st, r);
            st.dissipated_tension *= r;
            st.dissipated_shear *= r;
            st.dissipated_compression *= r;
          }
          kept_old_[old] = 1;
          ++kept_last_;
        } else {
          // params::bond_faces: at construction, the coinciding faces of a bonded material pair.
          const bool bonded = gp == nullptr && options_.bond_faces &&
                              result_.type[k] == detection::patch_type::polygon &&
                              table_.get(material_[at(a)], material_[at(b)]).bonded &&
                              std::abs(new_gap_[i]) <= bond_gap_fraction * options_.tolerance;
          state_type s = bonded ? state_type{} : Law::unbonded_state(p);
          if (bonded) ++bonded_at_start_;
          // At construction a corner takes its gap (a scene may start in contact, e.g. at its
          // static overlap: that energy is the run's initial energy). Later a corner that is
          // born overlapped (a new crossing of two edges inside a loaded patch) starts at zero
          // opening: its overlap is the neighbours' share, and a spring born compressed would
          // inject energy that no force supplied.
          s.u_n = gp == nullptr ? new_gap_[i] : std::max<real>(new_gap_[i], 0);
          // A zero increment sets the stresses of that opening (compression if it overlaps), so
          // the energy it holds is in the books from the start.
          // (The law books that energy as work done on the contact; it was not: undo its entry.)
          const state_type unbonded = s;
          Law::update(p, s, 0, vec3::Zero(), result_.planes[k].normal);
          s.dissipated_tension = unbonded.dissipated_tension;
          s.dissipated_shear = unbonded.dissipated_shear;
          s.dissipated_compression = unbonded.dissipated_compression;
          new_state_[i] = s;
          new_fresh_[i] = 1;
        }
      }
    }
    // Sub-contacts that end keep what they dissipated in the books; what they still stored leaves
    // the springs through the rebuild exchange.
    for (std::size_t o = 0; o < n_old; ++o) {
      if (kept_old_[o] != 0) continue;
      const contact_energies e = energies_of(o);
      retired_.dissipated += e.dissipated;
      retired_.dissipated_tension += e.dissipated_tension;
      retired_.dissipated_shear += e.dissipated_shear;
      retired_.dissipated_compression += e.dissipated_compression;
    }
    state_.swap(new_state_);
    fresh_.swap(new_fresh_);

    // Per pair: blocks, parameters, normal feature, normals.
    pair_a_.assign(new_pair_a_.begin(), new_pair_a_.end());
    pair_b_.assign(new_pair_b_.begin(), new_pair_b_.end());
    pair_param_.resize(n_pairs);
    feature_.resize(n_pairs);
    feature_a_.resize(n_pairs);
    feature_b_.resize(n_pairs);
    side_a_.resize(n_pairs);
    side_b_.resize(n_pairs);
    for (soa3& m : normal_) m.resize(static_cast<index_t>(n_pairs), 3);
    for (std::size_t k = 0; k < n_pairs; ++k) {
      const index_t a = pair_a_[k], b = pair_b_[k];
      pair_param_[k] = static_cast<index_t>(table_.entry_index(material_[at(a)], material_[at(b)]));
      const detection::contact_plane& plane = result_.planes[k];
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
    }

    // Per sub-contact: pair, area, weights.
    pair_.resize(n);
    key_label_.assign(new_label_.begin(), new_label_.end());
    corner_normal_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto k = at(std::upper_bound(new_pair_first_.begin(), new_pair_first_.end(), static_cast<index_t>(i)) -
                        new_pair_first_.begin() - 1);
      // A gridpoint sub-contact (deformable blocks) is pushed like a vertex of its side.
      const std::uint64_t label = key_label_[i];
      const bool node = is_node_label(label), node_b = node && node_label_side_b(label);
      const auto kind = detection::corner_label::kind_of(label);
      const bool of_b = node ? node_b : kind == detection::corner_label::kind::vertex_b;
      const bool of_a = node ? !node_b : kind == detection::corner_label::kind::vertex_a;
      corner_normal_[i] = of_b && side_a_[k].squaredNorm() > 0 ? 1 : of_a && side_b_[k].squaredNorm() > 0 ? 2 : 0;
    }
    area_.resize(n);
    for (auto& w : weight_) w.resize(n);
    for (auto& f : force_) f.assign(n, 0.0);
    if (options_.deformable_blocks) {
      for (auto& v : node_) v.resize(n);
      for (std::size_t k = 0; k < n_pairs; ++k)
        for (auto i = at(new_pair_first_[k]); i < at(new_pair_first_[k + 1]); ++i) {
          pair_[i] = static_cast<index_t>(k);
          area_[i] = new_area_[i];
          place_zoned(i, pair_a_[k], pair_b_[k], gp);
        }
    } else {
      for (std::size_t k = 0; k < n_pairs; ++k) {
        const index_t a = pair_a_[k], b = pair_b_[k];
        const mat3 inv_a = frame_inverse(blocks_[at(a)], gp), inv_b = frame_inverse(blocks_[at(b)], gp);
        const vec3 xa = position(blocks_[at(a)].frame[0], gp), xb = position(blocks_[at(b)].frame[0], gp);
        for (auto i = at(new_pair_first_[k]); i < at(new_pair_first_[k + 1]); ++i) {
          pair_[i] = static_cast<index_t>(k);
          area_[i] = new_area_[i];
          const vec3 la = inv_a * (new_point_[i] - xa), lb = inv_b * (new_point_[i] - xb);
          weight_[0][i] = 1 - la.sum();
          weight_[4][i] = 1 - lb.sum();
          for (int c = 0; c < 3; ++c) {
            weight_[at(1 + c)][i] = la[c];
            weight_[at(5 + c)][i] = lb[c];
          }
        }
      }
    }
    pair_first_.assign(new_pair_first_.begin(), new_pair_first_.end());
    index_subcontacts();

    peak_subcontacts_ = std::max(peak_subcontacts_, static_cast<index_t>(n));
    if (storage_capacity() > capacity_before) ++growths_;
    if (gp != nullptr) retired_.rebuild_exchange += stored_energy() - stored_before;
    rebuild_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  }

  /// Tasks (runs of pairs with at least task_subcontacts sub-contacts) and gather slots, from the
  /// pairs' first sub-contacts and the sub-contacts' pairs and weights: after a rebuild or a load.
  void index_subcontacts() {
    const std::size_t n_pairs = pair_a_.size(), n = pair_.size();
    pair_tasks_.assign(1, 0);
    for (std::size_t k = 0; k < n_pairs; ++k)
      if (k + 1 == n_pairs || pair_first_[k + 1] - pair_first_[at(pair_tasks_.back())] >= task_subcontacts)
        pair_tasks_.push_back(static_cast<index_t>(k + 1));

    // Gather slots, by a counting sort over slot (item, s), s = 0-7 (A's four, then B's four), so
    // that each gridpoint's slots come in increasing item order. Rigid blocks: the items are the
    // pairs, slot s the offset of the pair's sum for its block's frame gridpoint s % 4 in
    // pair_force_. Deformable blocks: the items are the sub-contacts, slot s gridpoint node_[s]
    // (none: invalid_index) with its weight (A's +w, B's -w: force_ holds the force on A).
    const bool rigid = !options_.deformable_blocks;
    const std::size_t items = rigid ? n_pairs : n;
    const auto slot_gridpoint = [&](std::size_t item, int s) {
      return rigid ? blocks_[at(s < 4 ? pair_a_[item] : pair_b_[item])].frame[at(s % 4)] : node_[at(s)][item];
    };
    slot_offsets_.assign(at(gridpoint_count_) + 1, 0);
    for (std::size_t item = 0; item < items; ++item)
      for (int s = 0; s < 8; ++s)
        if (const index_t g = slot_gridpoint(item, s); g != invalid_index) ++slot_offsets_[at(g) + 1];
    for (std::size_t g = 0; g < at(gridpoint_count_); ++g) slot_offsets_[g + 1] += slot_offsets_[g];
    slot_source_.resize(at(slot_offsets_.back()));
    slot_weight_.resize(rigid ? 0 : at(slot_offsets_.back()));
    fill_.assign(slot_offsets_.begin(), slot_offsets_.end() - 1);
    for (std::size_t item = 0; item < items; ++item)
      for (int s = 0; s < 8; ++s) {
        const index_t g = slot_gridpoint(item, s);
        if (g == invalid_index) continue;
        const auto e = at(fill_[at(g)]++);
        if (rigid) {
          slot_source_[e] = static_cast<index_t>(24 * item + 3 * at(s));
        } else {
          slot_source_[e] = static_cast<index_t>(item);
          slot_weight_[e] = s < 4 ? weight_[at(s)][item] : -weight_[at(s)][item];
        }
      }
    if (rigid) {
      pair_force_.assign(24 * n_pairs, 0.0);
      bound_present_contacts();
    }
    contact_gridpoints_.clear();
    for (index_t g = 0; g < gridpoint_count_; ++g)
      if (slot_offsets_[at(g) + 1] > slot_offsets_[at(g)]) contact_gridpoints_.push_back(g);
  }

  /// Capacity of the arrays a rebuild grows with the sub-contacts, pairs and gather slots (the
  /// growth count compares it before and after).
  [[nodiscard]] std::size_t storage_capacity() const noexcept {
    return key_label_.capacity() + pair_a_.capacity() + slot_source_.capacity() + pair_force_.capacity();
  }

  /// Elastic energy of the current sub-contacts (J), summed in sub-contact order.
  [[nodiscard]] real stored_energy() const {
    real e = 0;
    for (index_t i = 0; i < size(); ++i) e += energies_of(at(i)).stored;
    return e;
  }

  /// Normal j of pair k now (0 the plane's feature, 1 A's parallel face, 2 B's), from the
  /// blocks' motions: face normals through normal_map, edges through rotation.
  [[nodiscard]] triple pair_normal(std::size_t k, int j, const block_motion& ma, const block_motion& mb) const {
    vec3 n;
    if (j == 1 && side_a_[k].squaredNorm() > 0) {
      n = ma.normal_map * side_a_[k];
    } else if (j == 2 && side_b_[k].squaredNorm() > 0) {
      n = -(mb.normal_map * side_b_[k]);
    } else {
      switch (feature_[k]) {
        case feature_kind::face_a: n = ma.normal_map * feature_a_[k]; break;
        case feature_kind::face_b: n = -(mb.normal_map * feature_b_[k]); break;
        default: n = (ma.rotation * feature_a_[k]).cross(mb.rotation * feature_b_[k]);
      }
    }
    const real len = n.norm();
    const auto row = static_cast<index_t>(k);
    if (!(len > 0)) return {normal_[at(j)](row, 0), normal_[at(j)](row, 1), normal_[at(j)](row, 2)};
    return {n.x() / len, n.y() / len, n.z() / len};
  }

  /// Whether normal j (1 or 2) of pair k is the plane's normal to the bit: the pair has no face
  /// parallel to the plane on that side (pair_normal takes the feature's branch), or the
  /// parallel face is the plane's own feature (a face pair: the same body-frame vector through
  /// the same map). The rebuild starts such a normal from the plane's.
  [[nodiscard]] bool normal_is_plane(std::size_t k, int j) const noexcept {
    if (j == 1) return side_a_[k].squaredNorm() == 0 || (feature_[k] == feature_kind::face_a && side_a_[k] == feature_a_[k]);
    return side_b_[k].squaredNorm() == 0 || (feature_[k] == feature_kind::face_b && side_b_[k] == feature_b_[k]);
  }

  /// The pair's three normals now (stored for the next step) and their tilts since the last.
  void turn_normals(std::size_t k, std::array<triple, 3>& normals, std::array<triple, 3>& tilts) noexcept {
    const auto row = static_cast<index_t>(k);
    const block_motion& ma = motion_[at(pair_a_[k])];
    const block_motion& mb = motion_[at(pair_b_[k])];
    for (int j = 0; j < 3; ++j) {
      soa3& m = normal_[at(j)];
      // A normal that is the plane's to the bit (normal_is_plane's) is copied, not computed again.
      if (j > 0 && normal_is_plane(k, j)) {
        m(row, 0) = normals[0].x;
        m(row, 1) = normals[0].y;
        m(row, 2) = normals[0].z;
        normals[at(j)] = normals[0];
        tilts[at(j)] = tilts[0];
        continue;
      }
      const triple n_prev{m(row, 0), m(row, 1), m(row, 2)};
      const triple n = pair_normal(k, j, ma, mb);
      m(row, 0) = n.x;
      m(row, 1) = n.y;
      m(row, 2) = n.z;
      normals[at(j)] = n;
      tilts[at(j)] = kinematics::tilt(n_prev, n);
    }
  }

  /// update_pair for deformable blocks: each material point is its four gridpoints' weighted sum
  /// (a zone's barycentric interpolation, or one surface gridpoint), read from the gridpoints.
  void update_pair_zoned(index_t pk, real dt, const node_set& gp, const std::array<triple, 3>& normals,
                         const std::array<triple, 3>& tilts) noexcept {
    const auto k = at(pk);
    const params_type& p = law_params_[at(pair_param_[k])];
    for (auto i = at(pair_first_[k]); i < at(pair_first_[k + 1]); ++i) {
      real gap[3] = {0, 0, 0}, dv[3] = {0, 0, 0};
      for (int slot = 0; slot < 8; ++slot) {
        const index_t g = node_[at(slot)][i];
        if (g == invalid_index) continue;
        const real w = slot < 4 ? -weight_[at(slot)][i] : weight_[at(slot)][i];
        for (int c = 0; c < 3; ++c) {
          gap[c] += w * (reference_(g, c) + gp.displacement(g, c));
          dv[c] += w * gp.velocity(g, c);
        }
      }
      advance(i, p, {dv[0], dv[1], dv[2]}, {gap[0], gap[1], gap[2]}, normals[corner_normal_[i]],
              tilts[corner_normal_[i]], dt);
    }
  }

  /// The sub-contacts of pair pk (rigid blocks), with the pair's normals and tilts this step.
  void update_pair(index_t pk, real dt, const std::array<triple, 3>& normals, const std::array<triple, 3>& tilts) noexcept {
    const auto k = at(pk);
    const block_motion& ma = motion_[at(pair_a_[k])];
    const block_motion& mb = motion_[at(pair_b_[k])];
    const params_type& p = law_params_[at(pair_param_[k])];
    // The two bodies' points relative to A's frame origin: x_b(p) - x_a(p) and v_b(p) - v_a(p).
    const vec3 dx0 = mb.x0 - ma.x0, dv0 = mb.v0 - ma.v0;
    // The force on each frame gridpoint of the two blocks, summed here over the pair's
    // sub-contacts (the gather then reads 8 sums per pair, not 8 weights per sub-contact).
    real sum[24] = {};
    for (auto i = at(pair_first_[k]); i < at(pair_first_[k + 1]); ++i) {
      const triple& n = normals[corner_normal_[i]];
      const triple& tilt = tilts[corner_normal_[i]];
      const vec3 la(weight_[1][i], weight_[2][i], weight_[3][i]), lb(weight_[5][i], weight_[6][i], weight_[7][i]);
      const vec3 g = dx0 + mb.d * lb - ma.d * la, w = dv0 + mb.dv * lb - ma.dv * la;
      const triple f = advance(i, p, {w.x(), w.y(), w.z()}, {g.x(), g.y(), g.z()}, n, tilt, dt);
      for (int s = 0; s < 8; ++s) {
        const real ws = s < 4 ? weight_[at(s)][i] : -weight_[at(s)][i];
        sum[3 * s] += ws * f.x;
        sum[3 * s + 1] += ws * f.y;
        sum[3 * s + 2] += ws * f.z;
      }
    }
    std::copy(std::begin(sum), std::end(sum), pair_force_.begin() + static_cast<std::ptrdiff_t>(24 * k));
  }

  /// The law step and force of sub-contact i from its relative velocity dv (m/s) and gap (m),
  /// the normal n and the tilt of its plane. A sub-contact created at this step's rebuild
  /// already holds its gap at t: its increment is zero. The law advances a copy of the state
  /// kept in registers, so the traction is not read back from state_[i] right after the law
  /// stored it (perf annotate showed that load stalled on store forwarding: a 32-byte store read
  /// by a 16-byte load at offset 8; the step time did not move measurably, the law's division
  /// took the stall's place).
  /// Returns the force on A's side (N), also stored in force_.
  [[gnu::always_inline]] triple advance(std::size_t i, const params_type& p, const triple& dv, const triple& gap,
                                        const triple& n, const triple& tilt, real dt) noexcept {
    const vec3 normal(n.x, n.y, n.z);
    kinematics::normal_split s{0, {0, 0, 0}};
    if (fresh_[i] == 0) [[likely]]
      s = kinematics::split(kinematics::relative_increment(dv, gap, tilt, dt), n);
    fresh_[i] = 0;
    state_type st = state_[i];
    Law::update(p, st, s.du_n, vec3(s.du_s.x, s.du_s.y, s.du_s.z), normal);
    state_[i] = st;
    const vec3 traction = st.sigma_n * normal + vec3(st.tau);
    const triple f{area_[i] * traction[0], area_[i] * traction[1], area_[i] * traction[2]};
    force_[0][i] = f.x;
    force_[1][i] = f.y;
    force_[2][i] = f.z;
    return f;
  }

  enum class feature_kind : std::uint8_t { face_a, face_b, edges };
  static constexpr index_t task_subcontacts = 64;
  /// update() runs its tasks serially below 2 x this many (parallel_for's grain).
  static constexpr std::int64_t serial_tasks = 2;
  static constexpr index_t normal_batch = 16;  ///< pairs whose normals run_task computes ahead
  /// Deformable blocks: the largest distance of a surface gridpoint from its block's affine fit
  /// that a rebuild accepts, as a fraction of the tolerance (the trigger keeps it in reserve).
  static constexpr real max_deviation_fraction = 0.25;
  /// Faces within about 0.8 deg of the contact plane count as parallel to it.
  static constexpr real parallel_cos = 1 - 1e-4;

  params options_;
  material_table<params_type> table_;
  std::vector<params_type> law_params_;
  std::vector<real> entry_row_bound_;  ///< per table entry, stiffness_row_bound_per_area (Pa/m)
  std::vector<int> material_;
  index_t gridpoint_count_ = 0;
  soa3 reference_;                                 ///< reference gridpoint positions (m)
  std::vector<block_data> blocks_;
  std::vector<block_motion> motion_;  ///< per block, this step (prepare_step)
  std::vector<real> moved_;           ///< per block, its watched gridpoints' largest squared move since the rebuild (m^2)
  std::vector<index_t> vertex_gridpoints_;           ///< per block, its vertex gridpoints (local vertex order)
  std::vector<index_t> watch_gridpoints_;  ///< gridpoints the rebuild trigger reads (rigid: the vertices; deformable: the surface)
  // deformable blocks only
  std::vector<index_t> face_node_offsets_, face_nodes_, surface_zones_;
  std::vector<real> face_node_area_, gridpoint_bound_;
  std::vector<std::array<index_t, 4>> zones_;
  real max_deviation_ = 0;
  std::array<std::vector<index_t>, 8> node_;  ///< per sub-contact, the gridpoints of the weights (invalid_index: none)
  std::vector<node_contact> node_scratch_, node_other_;
  std::vector<Eigen::Matrix<real, 2, 1>> polygon_;
  std::vector<geometry::convex_polyhedron> shapes_, current_;  ///< reference and current geometry
  std::vector<detection::polyhedron_edges> edges_;
  std::vector<aabb> boxes_;
  // rigid blocks: the stable step from the sub-contacts present (bound_present_contacts)
  std::vector<real> present_bound_;   ///< per block, N/m on its farthest vertex
  std::vector<real> present_reach2_;  ///< per block, largest |material point - centroid|^2 (m^2)
  soa3 rebuild_u_;                                 ///< vertex displacements at the last rebuild
  index_t steps_since_rebuild_ = 0;
  detection::detection_result result_;
  detection::detection_workspace workspace_;
  // per pair
  std::vector<index_t> pair_a_, pair_b_, pair_param_, pair_first_{0}, pair_tasks_{0};
  std::vector<feature_kind> feature_;
  std::vector<vec3> feature_a_, feature_b_;
  std::array<soa3, 3> normal_;                     ///< per pair: the plane's, A's parallel face's, B's (now)
  std::vector<vec3> side_a_, side_b_;              ///< A's / B's face parallel to the plane, body frame (0: none)
  std::vector<std::uint8_t> corner_normal_;        ///< which of the pair's normals a sub-contact uses
  // per sub-contact (sorted by (a, b, label))
  std::vector<index_t> pair_;
  std::vector<std::uint64_t> key_label_;
  std::vector<real> area_;
  std::vector<state_type> state_;
  std::vector<std::uint8_t> fresh_;                ///< created at the last rebuild, not yet updated
  std::array<std::vector<real>, 8> weight_;        ///< affine weights, A's frame 0-3, B's 4-7
  std::array<std::vector<real>, 3> force_;         ///< force on A's side (N)
  // gather
  // slot_source_: rigid blocks, an offset into pair_force_; deformable, a sub-contact
  std::vector<index_t> slot_offsets_{0}, slot_source_, contact_gridpoints_, fill_;
  std::vector<real> slot_weight_;  ///< deformable blocks: the weight of the slot's sub-contact
  /// Rigid blocks, per pair: the forces on A's four frame gridpoints (w f) then B's (-w f),
  /// summed over its sub-contacts in order (N; 24 per pair).
  std::vector<real> pair_force_;
  // rebuild scratch
  std::vector<index_t> new_pair_a_, new_pair_b_, new_pair_first_;
  std::vector<std::uint64_t> new_label_;
  std::vector<std::size_t> order_;
  std::vector<real> new_area_, new_gap_;
  std::vector<vec3> new_point_;
  std::vector<state_type> new_state_;
  std::vector<std::uint8_t> new_fresh_, kept_old_;
  contact_energies retired_;                       ///< energies of the sub-contacts that ended
  // statistics
  index_t rebuilds_ = 0, growths_ = 0, peak_subcontacts_ = 0, kept_last_ = 0, bonded_at_start_ = 0;
  double rebuild_seconds_ = 0;
};

}  // namespace tessera::contact
