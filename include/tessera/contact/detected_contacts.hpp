#pragma once
// contact::detected_contacts<Law>: a ContactSet (contact/concepts.hpp) whose sub-contacts come from
// contact detection (detection/detect.hpp), so blocks that separate, slide and meet new neighbours
// are in contact wherever they touch, not only across the faces they were built with. It serves
// rigid blocks (blocks::rigid) and, with params::deformable_blocks, deformable ones
// (blocks::deformable, detected/deformable_fit.hpp; the solver checks the flag against its block
// model). DESIGN.md section 4, docs/model.md "Detected contacts".
//
// Rooms (contact/detected/), each with the part of this description that its code implements:
//   rebuild.hpp         "Rebuilds": the detection pass (no contact is missed), the merge of the
//                       sub-contacts that keeps a persisting corner's state, bonded faces
//                       (params::bond_faces), tasks and gather slots
//   incremental.hpp     rigid blocks: a rebuild detects again only the blocks that moved
//   keys.hpp            the sub-contacts' keys (a, b, corner label) and their merge, sorted
//   frames.hpp          a block's frame of four vertex gridpoints, sub-contact weights in it, its motion
//   step.hpp            "Kinematics between rebuilds": the pairs' normals, each sub-contact's
//                       relative motion, law update and force
//   step_bound.hpp      "Stable step": the time step's stiffness bounds (params::step_bound)
//   deformable_fit.hpp  "Deformable blocks": surfaces, the affine fit detection reads, sub-contacts
//                       at surface gridpoints
//   refusals.hpp        what the constructor refuses (unused residual strengths, initial overlaps)
//   checkpoint.hpp      "Checkpoints": a restart rebuilds at the same steps with the same bits
//   params.hpp          what the constructor takes
//   subset.hpp          a rank's part in a run split over MPI ranks (set_own_blocks), the energies
//   tasks.hpp           the tasks, the gather slots (rigid blocks: per block) and the gather
//
// Storage and threading: structure of arrays per sub-contact (key, weights, area, state, force),
// per pair (blocks, normal feature, normals now and last step, parameters; rigid blocks: the eight
// frame-gridpoint sums), the gather slots per block (rigid) or per gridpoint (deformable). Only a
// rebuild allocates (arrays grow and keep their capacity; counted in growth_count()); a step
// between rebuilds allocates nothing. Tasks are runs of pairs; a pair sums its sub-contacts in
// order and the gather sums each gridpoint's slots in increasing pair order (deformable blocks:
// sub-contact order), so results are bit-identical for any thread count. Cost of a step and of a
// rebuild: docs/performance.md "Contact detection kernels".

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/convex_polyhedron.hpp"
#include "../geometry/tessellation.hpp"
#include "../law/concepts.hpp"
#include "concepts.hpp"
#include "detected/frames.hpp"
#include "detected/incremental.hpp"
#include "detected/keys.hpp"
#include "detected/params.hpp"
#include "detected/refusals.hpp"
#include "detection/detect.hpp"
#include "face_contacts.hpp"
#include "kinematics.hpp"
#include "material_table.hpp"
#include "stiffness_bound.hpp"

namespace tessera::contact {

/// Contacts found between blocks and renewed as they move (file comment): sub-contacts at the corners of each pair's patch, keyed by corner so their law state survives rebuilds
template <law::ContactLaw Law>
class detected_contacts {
  template <std::integral I>
  [[nodiscard]] static constexpr std::size_t at(I i) noexcept {
    return static_cast<std::size_t>(i);
  }
  using triple = kinematics::triple;
  using block_data = detail::detected_block;    // detected/frames.hpp
  using block_motion = detail::block_motion;    // detected/frames.hpp
  using node_contact = detail::node_contact;    // detected/keys.hpp

 public:
  using law_type = Law;  ///< the contact law
  using params_type = typename Law::params;  ///< the law's parameters of one material pair
  using state_type = typename Law::state;  ///< the law's state per sub-contact
  static_assert(requires(const params_type& p, state_type s) {
    Law::unbonded_state(p);
    Law::scale_stresses(p, s, real{});
    s.u_n;
  } && detail::has_dissipation_split<state_type>,
                "detected_contacts needs a law with Law::unbonded_state, Law::scale_stresses and state fields u_n "
                "(normal opening, m) and dissipated_tension / _shear / _compression");

  /// What the constructor takes (detected/params.hpp).
  using params = detected_params<params_type>;

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
    detail::refuse_unused_strengths(table_, mesh, options_.bond_faces);
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
      detail::build_block_frame(tess, mesh, b, vertex_gridpoints_, blocks_[at(b)], shapes_[at(b)], edges_[at(b)]);
    }
    detail::refuse_large_tolerance(shapes_, options_.tolerance);  // detected/refusals.hpp
    // A block's contacts cover at most its own surface and at most the others' surfaces.
    real all_surfaces = 0;
    for (const block_data& bd : blocks_) all_surfaces += bd.surface;
    for (block_data& bd : blocks_) bd.stiffness_bound = 4 * row_max * std::min(bd.surface, all_surfaces - bd.surface);
    if (options_.deformable_blocks) {
      build_surfaces(tess, mesh, row_max);
    } else {
      watch_gridpoints_ = vertex_gridpoints_;
      for (block_data& bd : blocks_) detail::watch_vertices(bd, watch_gridpoints_, reference_);  // detected/frames.hpp
      index_frames();  // detected/tasks.hpp
    }
    current_ = shapes_;
    boxes_.resize(at(n_b));
    detected_box_.resize(at(n_b));
    present_bound_.resize(at(n_b));
    present_reach2_.resize(at(n_b));
    moved_bound_.resize(at(n_b));  // the trigger's bound per block (prepare_step)
    rebuild(nullptr);
  }

  // ---- the time step (ContactSet) ----

  /// Rebuilds when a vertex has moved more than the trigger since its block was last detected
  /// (rigid: 0.39 x the tolerance, detected/incremental.hpp; deformable: tolerance / 2) or the
  /// interval is reached (the only call that allocates), then takes each block's motion for
  /// the step.
  void prepare_step(const node_set& gridpoints, real dt);  // detected/step.hpp
  [[nodiscard]] index_t task_count() const { return static_cast<index_t>(pair_tasks_.size()); }  ///< Pair tasks of the step's parallel loop
  /// Kinematics, law update and force of the sub-contacts of the pairs of task t (the blocks'
  /// motion was read from the gridpoints in prepare_step).
  void run_task(index_t t, const node_set& gridpoints, real dt) noexcept {
    // In runs of up to normal_batch pairs: first every pair's normals, then the sub-contacts.
    // (Each normal is a chain of dependent operations through a square root and divisions;
    // computed ahead, the chains of several pairs overlap instead of each holding up its own
    // pair's sub-contacts.)
    std::array<std::array<triple, 3>, normal_batch> normals, tilts;
    for (index_t k0 = pair_tasks_[at(t)]; k0 < task_end_[at(t)]; k0 += normal_batch) {
      const index_t k1 = std::min<index_t>(k0 + normal_batch, task_end_[at(t)]);
      for (index_t k = k0; k < k1; ++k) turn_normals(at(k), normals[at(k - k0)], tilts[at(k - k0)]);
      for (index_t k = k0; k < k1; ++k)
        if (options_.deformable_blocks)
          update_pair_zoned(k, dt, gridpoints, normals[at(k - k0)], tilts[at(k - k0)]);
        else
          update_pair(k, dt, normals[at(k - k0)], tilts[at(k - k0)]);
    }
  }
  /// Adds the contact force on gridpoint g (N) to gridpoints.force, summed over its slots in
  /// increasing order: rigid blocks, the sums of its block's pairs for it (pair_force_, in pair
  /// order; with set_own_blocks, own blocks' gridpoints only); deformable blocks, the weighted
  /// sub-contact forces (in sub-contact order). Defined in detected/tasks.hpp.
  void add_force(index_t g, node_set& gridpoints) const noexcept;
  /// prepare_step, every task, the gather (the unfused path, which blocks::rigid takes).
  void update(node_set& gridpoints, real dt) {
    prepare_step(gridpoints, dt);
    // Tasks of >= task_subcontacts sub-contacts (some 30 000 instructions each): serial below
    // 2 x serial_tasks tasks, where a fork/join per step costs more than it saves on a shared
    // machine (a 21-block stack of 80 sub-contacts on 2 threads at load 8: 729 -> 26 us a
    // step). Same bits either way: a task writes only its own sub-contacts.
    parallel_for(
        task_count(), [&](std::int64_t t) { run_task(static_cast<index_t>(t), gridpoints, dt); }, serial_tasks);
    gather_forces(gridpoints);  // detected/tasks.hpp
  }
  /// Adds the contacts' stiffness bounds (N/m) to gridpoints.stiffness, as params::step_bound
  /// says (detected/step_bound.hpp, "Stable step"): rigid blocks, per block on its farthest vertex, from the
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
  [[nodiscard]] index_t size() const { return static_cast<index_t>(key_label_.size()); }  ///< Number of sub-contacts now
  [[nodiscard]] index_t subcontact_count() const { return size(); }  ///< Number of sub-contacts now (as size())
  [[nodiscard]] index_t pair_count() const { return static_cast<index_t>(pair_a_.size()); }  ///< Number of block pairs in contact now
  /// The blocks (a, b) of pair k, a < b.
  [[nodiscard]] std::array<index_t, 2> pair_blocks(index_t k) const { return {pair_a_[at(k)], pair_b_[at(k)]}; }
  [[nodiscard]] const state_type& state(index_t i) const { return state_[at(i)]; }  ///< Law state of sub-contact i (stresses Pa, relative displacements m)
  [[nodiscard]] real area(index_t i) const { return area_[at(i)]; }  ///< Tributary area of sub-contact i (m^2)
  [[nodiscard]] index_t pair_of(index_t i) const { return pair_[at(i)]; }  ///< The pair of sub-contact i
  /// Unit normal of sub-contact i, A -> B: that of the face its vertex is pushed by (a face of A
  /// for a vertex of B and the other way round, when the faces are parallel), else the pair's.
  [[nodiscard]] vec3 normal(index_t i) const { return normal_[corner_normal_[at(i)]].row(pair_[at(i)]).transpose(); }
  /// Force on block B's side in the last update (N); A's side received its opposite.
  [[nodiscard]] vec3 force(index_t i) const { return -vec3(force_[0][at(i)], force_[1][at(i)], force_[2][at(i)]); }
  [[nodiscard]] index_t block_a(index_t i) const { return pair_a_[at(pair_[at(i)])]; }  ///< Block A of sub-contact i (the lower id)
  [[nodiscard]] index_t block_b(index_t i) const { return pair_b_[at(pair_[at(i)])]; }  ///< Block B of sub-contact i
  /// First gridpoint of sub-contact i's material point on block A / B (its frame's for rigid
  /// blocks, its zone's or its own gridpoint for deformable ones; the force goes to all four).
  [[nodiscard]] index_t node_a(index_t i) const {
    return options_.deformable_blocks ? node_[0][at(i)] : blocks_[at(block_a(i))].frame[0];
  }
  [[nodiscard]] index_t node_b(index_t i) const {  ///< The same on block B
    return options_.deformable_blocks ? node_[4][at(i)] : blocks_[at(block_b(i))].frame[0];
  }
  /// corner_label of sub-contact i (detection/common_plane.hpp).
  [[nodiscard]] std::uint64_t label(index_t i) const { return key_label_[at(i)]; }
  [[nodiscard]] const params_type& subcontact_params(index_t i) const {  ///< The law parameters of sub-contact i's material pair
    return law_params_[at(pair_param_[at(pair_[at(i)])])];
  }
  /// Current position (m) of the material point of sub-contact i on block A / B.
  [[nodiscard]] vec3 position_a(index_t i, const node_set& gp) const { return point(i, true, gp); }
  [[nodiscard]] vec3 position_b(index_t i, const node_set& gp) const { return point(i, false, gp); }  ///< The same on block B

  // ---- rebuild statistics ----
  /// Detection passes so far, the construction's included (the solver chooses dt again when it
  /// changes, detected/step_bound.hpp "Stable step").
  [[nodiscard]] index_t rebuild_count() const { return rebuilds_; }
  /// Rebuilds at which a per-sub-contact or per-pair array had to grow (allocate).
  [[nodiscard]] index_t growth_count() const { return growths_; }
  [[nodiscard]] index_t peak_subcontacts() const { return peak_subcontacts_; }  ///< Largest sub-contact count seen
  /// Wall time spent in rebuilds so far, the construction's included (s; for reports only).
  [[nodiscard]] double rebuild_seconds() const { return rebuild_seconds_; }
  /// Candidate pairs of the last pass, and of them those this rank evaluated (set_detection_split).
  [[nodiscard]] std::size_t candidate_count() const { return result_.candidates; }
  [[nodiscard]] std::size_t evaluated_candidate_count() const { return result_.evaluated; }  ///< Of candidate_count(), those this rank evaluated
  /// Sub-contacts of the last rebuild that kept the state of an earlier one (those of the pairs
  /// it left untouched included).
  [[nodiscard]] index_t kept_last_rebuild() const { return kept_last_; }
  /// Blocks detected again, summed over the rebuilds (a full pass counts every block; the
  /// construction's included), and the pairs the last rebuild left untouched (detected/incremental.hpp).
  [[nodiscard]] std::int64_t redetected_blocks() const { return redetected_; }
  /// Blocks placed (current shape, box) by the rebuilds, summed: those detected again and the others the pass read.
  [[nodiscard]] std::int64_t placed_blocks() const { return placed_; }
  [[nodiscard]] index_t untouched_pairs_last_rebuild() const { return untouched_last_; }  ///< Pairs the last rebuild left untouched
  /// Candidate pairs the rebuilds' narrow phase evaluated, summed (this rank's part), and of them
  /// those their last plane's axis showed apart without the full search (detection_options::reuse_axes).
  [[nodiscard]] std::int64_t narrow_phase_pairs() const { return narrow_pairs_; }
  [[nodiscard]] std::int64_t pairs_apart_by_kept_axis() const { return static_cast<std::int64_t>(workspace_.axis_skips); }  ///< (see narrow_phase_pairs)
  [[nodiscard]] std::int64_t pairs_kept_as_one() const { return poses_.kept_as_one; }  ///< Pairs with a block detected again that the rebuilds kept, their blocks having moved as one (detected/incremental.hpp), summed
  [[nodiscard]] real tolerance() const { return options_.tolerance; }  ///< The contact tolerance (m)
  /// Sub-contacts that started bonded at construction (params::bond_faces; 0 without).
  [[nodiscard]] index_t bonded_at_start() const { return bonded_at_start_; }

  /// Energies of the current sub-contacts plus what those that ended at rebuilds dissipated (J),
  /// and the rebuild exchange: the change of the springs' elastic energy at each rebuild after
  /// the first (new corners that start overlapped, tributary areas that change, corners dropped
  /// while loaded). That change is no work of any force; the solver's energy balance books it
  /// beside the supplied energy so error_rel measures the integration, and reports it.
  /// With set_own_blocks, the sub-contacts this rank counts (its pairs' first block is its own),
  /// here and in the books of the rebuilds. Defined in detected/subset.hpp.
  [[nodiscard]] contact_energies energies() const;
  /// The part of energies() held by sub-contacts that ended at rebuilds, and the rebuild exchange (J).
  [[nodiscard]] const contact_energies& retired_energies() const { return retired_; }

  /// A run split over MPI ranks (distributed::rigid_stepper): this rank evaluates only the pairs
  /// that touch one of `own` (block ids, increasing; every block when empty), gathers forces only
  /// on those blocks' gridpoints, and books (energies()) the sub-contacts of pairs whose first
  /// block is one of them. Rigid blocks only. Defined in detected/subset.hpp.
  void set_own_blocks(std::span<const index_t> own);
  /// Rebuilds evaluate part `part` of `parts` of the candidate pairs, and `gather` turns that
  /// part's result into the whole pass's (detected/subset.hpp). {0, 1, {}}: the whole pass here.
  void set_detection_split(int part, int parts, std::function<void(detection::detection_result&)> gather);
  /// The rebuild trigger of a split run: the watch covers the own blocks only, `largest(m2)` turns
  /// this rank's largest squared motion into the ranks' largest, and `before_rebuild()` runs before
  /// each pass (detected/subset.hpp). Empty functions: the whole watch here.
  void set_motion_vote(std::function<real(real)> largest, std::function<void()> before_rebuild);
  /// The step state of pair k (its normals now; each sub-contact's law state, fresh flag and force):
  /// what a rank that starts to evaluate the pair needs from one that did, when a block changes
  /// rank. write_pair_state appends pair_state_bytes(k) bytes; read_pair_state takes them.
  [[nodiscard]] std::size_t pair_state_bytes(index_t k) const;
  void write_pair_state(index_t k, std::vector<unsigned char>& out) const;  ///< Appends the step state of pair k (pair_state_bytes(k) bytes)
  void read_pair_state(index_t k, const unsigned char* in);  ///< Reads the step state of pair k written by write_pair_state

  /// Saves or loads everything a rebuild and a step read (io/checkpoint.hpp): the sub-contacts
  /// (keys, pairs, areas, affine weights, law states field by field, forces, fresh flags), the
  /// pairs (blocks, parameters, normal features, normals now; the tasks and gather slots are
  /// derived from them again on load), the vertex displacements of the last rebuild and the
  /// steps since it, the energies of the sub-contacts that ended and the rebuild statistics.
  /// Their sizes change during a run, so the file gives them (ar.count) and a load resizes; the
  /// model's own (block count, tolerance, rebuild interval) must match. So a restart rebuilds at
  /// the same steps and is bit-identical. Defined in detected/checkpoint.hpp.
  template <class Archive>
  void checkpoint(Archive& ar);

 private:
  /// Booked here (set_own_blocks): sub-contact i's pair's first block is own, or no subset is set.
  [[nodiscard]] bool counted(std::size_t i) const { return own_block_.empty() || own_block_[at(pair_a_[at(pair_[i])])] != 0; }
  template <class F>
  void visit_pair_state(index_t k, F&& f);  // detected/subset.hpp
  // Defined, each with its doc comment, in the detected/ header named above its group.
  // detected/step_bound.hpp
  void add_bounds(node_set& gridpoints, step_bound_scope scope) const;
  void bound_present_contacts(bool kept_pairs = false);
  // detected/deformable_fit.hpp
  void build_surfaces(const geometry::tessellation& tess, const geometry::block_mesh& mesh, real row_max);
  void locate(index_t b, const vec3& x, const node_set* gp, std::array<index_t, 4>& nodes,
              std::array<real, 4>& w) const;
  void place_zoned(std::size_t i, index_t a, index_t b, const node_set* gp);
  bool collect_nodes(std::size_t k, const node_set* gp);
  void check_affine_fit(const node_set* gp);  ///< max_deviation_ at a rebuild (detected/deformable_fit.hpp)
  // detected/rebuild.hpp
  void rebuild(const node_set* gp, bool full = true);
  [[nodiscard]] real moved2_of(std::size_t b, const node_set& gp) const noexcept;
  // detected/tasks.hpp
  void index_subcontacts(bool kept_pairs = false);
  void index_frames();
  void gather_forces(node_set& gridpoints) const;
  [[nodiscard]] std::size_t storage_capacity() const noexcept;
  [[nodiscard]] real stored_energy() const;
  // detected/step.hpp
  [[nodiscard]] triple pair_normal(std::size_t k, int j, const block_motion& ma, const block_motion& mb) const;
  [[nodiscard]] bool normal_is_plane(std::size_t k, int j) const noexcept;
  void turn_normals(std::size_t k, std::array<triple, 3>& normals, std::array<triple, 3>& tilts) noexcept;
  void update_pair_zoned(index_t pk, real dt, const node_set& gp, const std::array<triple, 3>& normals,
                         const std::array<triple, 3>& tilts) noexcept;
  void update_pair(index_t pk, real dt, const std::array<triple, 3>& normals,
                   const std::array<triple, 3>& tilts) noexcept;
  [[gnu::always_inline]] kinematics::normal_split increment(std::size_t i, const triple& dv, const triple& gap,
                                                            const triple& n, const triple& tilt, real dt) const noexcept;
  [[gnu::always_inline]] triple advance_split(std::size_t i, const params_type& p, const kinematics::normal_split& s,
                                              const triple& n) noexcept;

  // A gridpoint's position and a block's frame now, from reference_ (detected/frames.hpp).
  [[nodiscard]] vec3 position(index_t g, const node_set* gp) const {
    return detail::gridpoint_position(reference_, g, gp);
  }
  [[nodiscard]] mat3 frame_matrix(const block_data& b, const node_set* gp) const { return detail::frame_matrix(reference_, b, gp); }
  [[nodiscard]] mat3 rotation(const block_data& b, const node_set* gp) const { return detail::frame_rotation(reference_, b, gp); }
  [[nodiscard]] mat3 frame_inverse(const block_data& b, const node_set* gp) const { return detail::frame_inverse(reference_, b, gp); }
  /// Block b's vertices' box at its last detection (m), from reference_ and rebuild_u_.
  [[nodiscard]] aabb box_at_detection(std::size_t b) const {
    aabb box;
    for (index_t k = blocks_[b].watch_begin; k < blocks_[b].watch_end; ++k)
      box.expand(reference_.row(watch_gridpoints_[at(k)]).transpose() + rebuild_u_.row(k).transpose());
    return box;
  }

  /// Energies of sub-contact i (J). Defined in detected/subset.hpp.
  [[nodiscard]] contact_energies energies_of(std::size_t i) const;

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

  enum class feature_kind : std::uint8_t { face_a, face_b, edges };
  static constexpr index_t task_subcontacts = 64;
  /// update() runs its tasks serially below 2 x this many (parallel_for's grain).
  static constexpr std::int64_t serial_tasks = 2;
  static constexpr index_t normal_batch = 16;  ///< pairs whose normals run_task computes ahead
  static constexpr std::size_t subcontact_batch = 16;  ///< sub-contacts update_pair takes loop by loop
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
  std::vector<real> moved_;  ///< per block, its watched gridpoints' largest squared move since the rebuild (m^2)
  std::vector<real> moved_bound_;  ///< rigid blocks, per block: a bound on that move (m), prepare_step's
  index_t bound_passed_at_ = -1;   ///< rebuild count when a bound last passed its limit (exact moves till the next)
  std::vector<index_t> vertex_gridpoints_;           ///< per block, its vertex gridpoints (local vertex order)
  std::vector<index_t> watch_gridpoints_;  ///< read by the rebuild trigger (rigid: vertices; deformable: surface)
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
  /// Rigid blocks, per block: the box of its vertices when it was last detected (reference_ +
  /// rebuild_u_, so a restart has it too); with the block's motion since, a box that holds it now.
  std::vector<aabb> detected_box_;
  // rigid blocks: the stable step from the sub-contacts present (bound_present_contacts)
  std::vector<real> present_bound_;   ///< per block, N/m on its farthest vertex
  std::vector<real> present_reach2_;  ///< per block, largest |material point - centroid|^2 (m^2)
  std::vector<real> pair_stiffness_;  ///< per pair: its sub-contacts' stiffness sum (N/m), kept by a kept pair
  std::vector<std::array<real, 2>> pair_reach2_;  ///< per pair: largest reach^2 from A's, B's centroids (m^2)
  soa3 rebuild_u_;                                 ///< vertex displacements at the last rebuild
  index_t steps_since_rebuild_ = 0;
  detection::detection_result result_;
  detection::detection_workspace workspace_;
  detection::detection_share share_;                             ///< set_detection_split
  std::function<void(detection::detection_result&)> gather_;
  std::function<real(real)> largest_motion_;                     ///< set_motion_vote
  std::function<void()> before_rebuild_;
  // per pair
  std::vector<index_t> pair_a_, pair_b_, pair_param_, pair_first_{0};
  std::vector<index_t> pair_tasks_, task_end_;  ///< task t: pairs [pair_tasks_[t], task_end_[t])
  std::vector<std::uint8_t> own_block_;  ///< set_own_blocks (empty: all)
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
  // gather (detected/tasks.hpp): slots per block (rigid; slot_source_ an offset into pair_force_)
  // or per gridpoint (deformable; a sub-contact); the blocks / gridpoints with slots gathered here
  std::vector<index_t> slot_offsets_{0}, slot_source_, contact_blocks_, contact_gridpoints_, fill_;
  std::vector<index_t> frame_of_;  ///< rigid blocks, per gridpoint: 4 b + s, frame gridpoint s of block b (else -1)
  std::vector<real> slot_weight_;  ///< deformable blocks: the weight of the slot's sub-contact
  /// Rigid blocks, per pair: the forces on A's four frame gridpoints (w f) then B's (-w f),
  /// summed over its sub-contacts in order (N; 24 per pair).
  std::vector<real> pair_force_;
  // rebuild scratch
  std::vector<index_t> new_pair_a_, new_pair_b_, new_pair_first_, new_found_first_;
  std::vector<std::uint64_t> new_label_;
  std::vector<std::size_t> order_;
  std::vector<real> new_area_, new_gap_;
  std::vector<vec3> new_point_;
  std::vector<state_type> new_state_;
  std::vector<std::uint8_t> new_fresh_, kept_old_, redetect_;
  std::vector<std::ptrdiff_t> new_source_;  ///< per new pair: its pass pair j >= 0, or -1 - the kept old pair
  /// A run of the kept pairs' sub-contacts: old sub-contacts [from, from + count) are new [to, to + count).
  struct kept_run { std::size_t from = 0, to = 0, count = 0, pair_from = 0, pair_to = 0, pairs = 0; };
  std::vector<kept_run> kept_runs_;  ///< the kept pairs and their sub-contacts, in runs (a rebuild's copies)
  detail::previous_columns<feature_kind> prev_;  ///< the columns a rebuild copies for its kept pairs
  detail::pair_poses poses_;  ///< per pair, its blocks' relative pose at its detection (incremental.hpp)
  contact_energies retired_;                       ///< energies of the sub-contacts that ended
  // statistics
  index_t rebuilds_ = 0, growths_ = 0, peak_subcontacts_ = 0, kept_last_ = 0, bonded_at_start_ = 0, untouched_last_ = 0;
  std::int64_t redetected_ = 0, narrow_pairs_ = 0, placed_ = 0;
  double rebuild_seconds_ = 0;
};

}  // namespace tessera::contact

// The definitions of the members declared above, by job.
#include "detected/checkpoint.hpp"
#include "detected/deformable_fit.hpp"
#include "detected/rebuild.hpp"
#include "detected/step.hpp"
#include "detected/step_bound.hpp"
#include "detected/subset.hpp"
#include "detected/tasks.hpp"
