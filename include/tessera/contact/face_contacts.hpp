#pragma once
// contact::face_contacts<Law>: the bonded sub-contacts of a conforming tessellation of blocks,
// their kinematics and the per-step contact force kernel (DESIGN.md §3 "Contact",
// docs/architecture.md). A contact::ContactSet (contact/concepts.hpp): the solver drives it
// through prepare_step / run_task / add_force and knows nothing else of it.
//
// Materials. The set is built from a contact::material_table<Law::params>: a face between blocks
// of materials a and b (geometry::block_mesh::block_material) uses the entry of the pair {a, b};
// a never-bonded pair's sub-contacts start in Law::unbonded_state. The parameters are resolved
// per face when the set is built (face blocks never mix two entries), so the step loop reads one
// parameter struct per face block, as with a single material.
//
// Creation (detail/face_pairs.hpp): one sub-contact per pair of coincident face gridpoints of
// every shared face, its tributary area; block A is the lower cell id; the sub-contacts of a face
// are contiguous, faces in tessellation::shared_faces order ("face s" = shared face s). The face
// blocks of the kernel and the reference frames: detail/face_layout.hpp.
//
// Contact frame (detail/face_pairs.hpp, face_corners): one unit normal per shared face per step,
// A -> B, the normalised vector area of the polygon through the midpoints of its corner pairs.
//
// Kinematics (contact/kinematics.hpp, which derives it): called in step 3 of the time step
// (displacements at t, velocities at t - dt/2), per sub-contact
//     du = (v_b - v_a) dt - (n_prev x n) x (u_b - u_a),   du_n = du . n,   du_s = du - du_n n,
// the tilt term keeping a rigidly turned open contact free of spurious slip (test "rigid
// rotation": sigma_n drifts 2e-4 over 1.2 rad in 4000 steps, 33 % without it). Law::update then
// advances the state and the force on node B is f_b = -area (sigma_n n + tau), f_a = -f_b: tension
// pulls B back toward A and tau, along the slip of B relative to A, resists it.
//
// Storage (structure of arrays behind index handles): per sub-contact node_a, node_b, face, area,
// the law state and f_i = area (sigma_n n + tau), the force on node A of the last step (node B
// gets -f_i), one array per component; per face its sub-contact range, corners and the current
// and previous normals. The gather of gridpoint g sums sign x f_i over its CSR slots
// (detail::build_gather) in increasing sub-contact order.
//
// Kernel. Faces go in face blocks, runs of consecutive faces with at least block_subcontacts
// sub-contacts and one material-pair entry. By default the states are an array of Law::state and
// the face loop runs Law::update per sub-contact. For a law with a pack path that asks for it
// (law::ElasticPackLaw, law::with_elastic_packs; `packed` below) the state is stored as columns
// from the law's declaration (detail::state_columns) and a face block runs three loops: (1) frames
// and per sub-contact du_n, du_s, n into per-step columns; (2) Law::update_elastic over
// lanes::pack's, committing the lanes whose damage flags the step leaves unchanged; (3)
// Law::update for the declined lanes (peak, breaking, first slip, cap: detail::advance_states).
// Both are the law's one step<> function, so every sub-contact gets the bits Law::update gives
// it, whatever its lane (test_contacts "[pack]"); on the RC tie the packs take all but 8 in a
// million sub-contact-steps. Frame and kinematics use kinematics::triple (scalars in registers).
//
// Threading and determinism. update() runs two parallel loops (core/parallel.hpp), over face
// blocks and over contact gridpoints (gather); each writes only what its index owns and the gather
// sums in a fixed order, so results are bit-identical for any thread count; nothing is allocated.
// update() is also offered in pieces (prepare_step, run_task, add_force) for a solver that runs the
// face blocks beside the zone kernel in one parallel region (solver.hpp), to the same bits.
// Concurrent const access is safe; update() must not run concurrently with anything else.
//
// Cost: memory ~ (70 + sizeof(Law::state)) bytes per sub-contact, plus 64 for the per-step
// columns with packs; update() O(sub-contacts); construction O(sub-contacts + gridpoints).
// Measured costs per sub-contact-step: docs/performance.md.

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/tessellation.hpp"
#include "../law/concepts.hpp"
#include "concepts.hpp"
#include "detail/face_layout.hpp"
#include "detail/face_pairs.hpp"
#include "detail/packed_states.hpp"
#include "detail/slot_gather.hpp"
#include "detail/subcontact_energies.hpp"
#include "kinematics.hpp"
#include "stiffness_bound.hpp"
#include "material_table.hpp"

namespace tessera::contact {

/// The bonded faces of a tessellation as contacts (file comment): sub-contacts at the corners of each shared face, which never change partner
template <law::ContactLaw Law>
class face_contacts {
  /// Array subscript of an index handle.
  template <std::integral I>
  [[nodiscard]] static constexpr std::size_t at(I i) noexcept {
    return static_cast<std::size_t>(i);
  }

 public:
  using law_type = Law;  ///< the contact law
  using params_type = typename Law::params;  ///< the law's parameters of one material pair
  /// What the constructor takes: the law's parameters per pair of block materials (a plain
  /// params_type converts to a table with one entry for every pair).
  using params = material_table<params_type>;
  using state_type = typename Law::state;  ///< the law's state per sub-contact
  /// True when Law has an elastic pack path (law::ElasticPackLaw) and asks for it
  /// (law::with_elastic_packs): states are then stored as columns and updated over lanes::pack's
  /// (file comment, "Kernel"). Off for the plain laws (the default layout, Law::update per
  /// sub-contact).
  static constexpr bool packed = law::ElasticPackLaw<Law> && requires { requires Law::use_elastic_packs; };

  /// Row bound of one sub-contact spring per unit area (Pa/m), any orientation (stiffness_bound.hpp).
  [[nodiscard]] static real stiffness_row_bound_per_area(const params_type& p) {
    return contact::stiffness_row_bound_per_area<Law>(p);
  }

  face_contacts() = default;

  /// Builds one sub-contact per face-node pair of every shared face of `tess` (see the file
  /// comment). Validates `p` with Law::validate (invalid_input). Throws geometry_error, naming
  /// the shared face, its cells and tessellation faces, when the mesh does not match the
  /// tessellation, when the two sides of a face have different node counts or a polygon vertex
  /// of the face has no face node (block_mesh::gridpoint_vertex), when
  /// paired gridpoints do not coincide (beyond 1e-9 of the model's bounding-box diagonal) or
  /// belong to the wrong block, or when their tributary areas differ (beyond 1e-9 relative) or
  /// are not > 0. Cost O(sub-contacts + gridpoints).
  /// One law for every material pair.
  face_contacts(const geometry::tessellation& tess, const geometry::block_mesh& mesh, const params_type& p)
      : face_contacts(tess, mesh, params(p)) {}
  /// Law parameters per pair of block materials (geometry::block_mesh::block_material).
  face_contacts(const geometry::tessellation& tess, const geometry::block_mesh& mesh, const params& table) {
    for (const auto& e : table.entries()) Law::validate(e.params);
    const index_t n_gridpoints = mesh.gridpoint_count();
    gridpoint_count_ = n_gridpoints;
    for (const auto& e : table.entries()) {
      law_params_.push_back(e.params);
      bonded_.push_back(e.bonded ? 1 : 0);
      if constexpr (!requires { Law::unbonded_state(e.params); })
        require(e.bonded, "face_contacts: a never-bonded material pair needs a law with an unbonded state "
                          "(Law::unbonded_state); this law has none");
    }

    detail::face_pairs pairs = detail::pair_face_nodes(tess, mesh, table);
    node_a_ = std::move(pairs.node_a);
    node_b_ = std::move(pairs.node_b);
    face_ = std::move(pairs.face);
    area_ = std::move(pairs.area);
    first_subcontact_ = std::move(pairs.first_subcontact);
    face_area_ = std::move(pairs.face_area);
    face_param_ = std::move(pairs.face_param);
    corners_ = std::move(pairs.corners);
    shared_faces_ = tess.shared_faces;
    initial_states();
    // Face blocks and reference frames (detail/face_layout.hpp).
    const auto n_faces = static_cast<index_t>(face_area_.size());
    face_blocks_ = detail::face_blocks_of(n_faces, face_param_, first_subcontact_, block_subcontacts);
    normal_ = detail::reference_normals(corners_, shared_faces_, n_faces, n_gridpoints);
    previous_normal_ = normal_;
    detail::gather_slots gather = detail::build_gather(n_gridpoints, node_a_, node_b_);
    slot_offsets_ = std::move(gather.offsets);
    slot_subcontact_ = std::move(gather.subcontact);
    slot_sign_ = std::move(gather.sign);
    contact_gridpoints_ = std::move(gather.gridpoints);
    for (auto& column : force_) column.assign(node_a_.size(), 0.0);
  }


  /// Recomputes the contact frames from the current positions of `gridpoints` and makes them
  /// the previous frames as well. Construction uses the reference positions; call this before
  /// the first update() when the run starts from non-zero displacements (e.g. a restart).
  void initialize_frames(const node_set& gridpoints) {
    require(gridpoints.size() == gridpoint_count_, "face_contacts::initialize_frames: node_set has ",
            gridpoints.size(), " gridpoints, expected ", gridpoint_count_);
    const real* u[3] = {gridpoints.displacement.col(0).data(), gridpoints.displacement.col(1).data(),
                        gridpoints.displacement.col(2).data()};
    for (index_t s = 0; s < face_count(); ++s) {
      const triple area = corners_.area_vector(s, u);
      const vec3 d(area.x, area.y, area.z);
      if (d.squaredNorm() > 0) normal_.row(s) = d.normalized().transpose();
    }
    previous_normal_ = normal_;
  }

  /// Step 3 of the time step (docs/architecture.md): updates the contact frames from the
  /// current positions, advances every sub-contact's law state by the relative displacement
  /// increment of the last step, and ADDS the contact forces to gridpoints.force (N). Expects
  /// displacements at t, velocities at t - dt/2 and dt (s) the step that produced the current
  /// positions. `gridpoints` must be the node_set of the block_mesh the set was built from.
  void update(node_set& gridpoints, real dt) noexcept {
    assert(gridpoints.size() == gridpoint_count_);
    // 1+2. Per face (one parallel loop, so the face's gridpoints are still in L1 for its
    // sub-contacts): the frame, then the law update and force on node B of each sub-contact.
    prepare_step(gridpoints, dt);
    parallel_for(task_count(), [&](std::int64_t b) { run_task(static_cast<index_t>(b), gridpoints, dt); }, 2);
    // 3. Gather onto gridpoints: contiguous sums over each gridpoint's slots, in fixed order.
    parallel_for(static_cast<std::int64_t>(contact_gridpoints_.size()),
                 [&](std::int64_t j) { add_force(contact_gridpoints_[at(j)], gridpoints); });
  }

  // ---- update() in pieces, for a solver that fuses the loops of its step (solver.hpp) ----
  // update(gp, dt) == prepare_step(gp, dt); run_task(b, gp, dt) for every face block b (or
  // update_face(s, gp, dt) for every face s; in any order or concurrently); then add_force(g, gp)
  // for every gridpoint g (concurrently for distinct g). Same results to the bit.

  /// Makes the current frames the previous ones; once per step, before the tasks (the set never
  /// allocates: its sub-contacts are fixed when it is built).
  void prepare_step(const node_set& /*gridpoints*/, real /*dt*/) noexcept { normal_.swap(previous_normal_); }

  /// Number of tasks: the face blocks, runs of consecutive faces with about block_subcontacts
  /// sub-contacts and one material-pair entry.
  [[nodiscard]] index_t task_count() const { return static_cast<index_t>(face_blocks_.size()) - 1; }
  /// update_faces over face block b.
  void run_task(index_t b, const node_set& gridpoints, real dt) noexcept {
    update_faces(face_blocks_[at(b)], face_blocks_[at(b) + 1], gridpoints, dt);
  }
  /// update_faces over face s alone.
  void update_face(index_t s, const node_set& gridpoints, real dt) noexcept { update_faces(s, s + 1, gridpoints, dt); }

  /// Frames of faces [first_face, last_face) from the current positions (a degenerate face keeps
  /// its previous frame), then law update and force rows of each of their sub-contacts. Writes
  /// only those faces' data.
  void update_faces(index_t first_face, index_t last_face, const node_set& gridpoints, real dt) noexcept {
    const real* u[3] = {gridpoints.displacement.col(0).data(), gridpoints.displacement.col(1).data(),
                        gridpoints.displacement.col(2).data()};
    const real* v[3] = {gridpoints.velocity.col(0).data(), gridpoints.velocity.col(1).data(),
                        gridpoints.velocity.col(2).data()};
    for (index_t s = first_face; s < last_face; ++s) {
      const params_type& p = face_params(s);
      const triple d = corners_.area_vector(s, u);
      const triple n_prev{previous_normal_(s, 0), previous_normal_(s, 1), previous_normal_(s, 2)};
      const real length2 = kinematics::dot(d, d);
      triple n = n_prev;
      if (length2 > 0) {
        const real length = std::sqrt(length2);
        n = {d.x / length, d.y / length, d.z / length};
      }
      normal_(s, 0) = n.x;
      normal_(s, 1) = n.y;
      normal_(s, 2) = n.z;
      const triple tilt = kinematics::tilt(n_prev, n);  // rotation vector n_prev -> n (first order)
      for (std::size_t i = at(first_subcontact_[at(s)]); i < at(first_subcontact_[at(s) + 1]); ++i) {
        const index_t a = node_a_[i], b = node_b_[i];
        const triple gap{u[0][b] - u[0][a], u[1][b] - u[1][a], u[2][b] - u[2][a]};
        const triple dv{v[0][b] - v[0][a], v[1][b] - v[1][a], v[2][b] - v[2][a]};
        const auto [du_n, du_s] = kinematics::split(kinematics::relative_increment(dv, gap, tilt, dt), n);
        if constexpr (packed) {
          // Law::update's arguments, for the pack loop below.
          step_.du_n[i] = du_n;
          step_.ds0[i] = du_s.x;
          step_.ds1[i] = du_s.y;
          step_.ds2[i] = du_s.z;
          step_.n0[i] = n.x;
          step_.n1[i] = n.y;
          step_.n2[i] = n.z;
        } else {
          state_type& st = state_[i];
          const vec3 normal(n.x, n.y, n.z);
          Law::update(p, st, du_n, vec3(du_s.x, du_s.y, du_s.z), normal);
          const vec3 traction = st.sigma_n * normal + vec3(st.tau);
          for (int c = 0; c < 3; ++c) force_[at(c)][i] = area_[i] * traction[c];
        }
      }
    }
    if constexpr (packed) {
      // One pack pass per run of faces with the same parameters (one run within a face block).
      real* const force[3] = {force_[0].data(), force_[1].data(), force_[2].data()};
      for (index_t run = first_face; run < last_face;) {
        index_t run_end = run + 1;
        while (run_end < last_face && face_param_[at(run_end)] == face_param_[at(run)]) ++run_end;
        detail::advance_states<Law>(face_params(run), state_, step_, area_.data(), at(first_subcontact_[at(run)]),
                                    at(first_subcontact_[at(run_end)]), force);
        run = run_end;
      }
    }
  }

  /// Adds the contact forces of the last update_face calls on gridpoint g to gridpoints.force
  /// (a contiguous sum over g's slots in fixed order; nothing for a gridpoint without sub-contacts).
  void add_force(index_t g, node_set& gridpoints) const noexcept {
    // Weights +-1, so +-f exactly: the sum is that of the forces on g in increasing sub-contact order.
    detail::add_weighted_slot_forces(g, slot_offsets_, slot_subcontact_, slot_sign_, force_, gridpoints);
  }

  /// Adds to gridpoints.stiffness (N/m) the Gershgorin row bound of every sub-contact spring:
  /// the pair (node_a, node_b) is coupled by [K -K; -K K] with K = area (k_s I + (k_n - k_s) n n^T),
  /// whose absolute row sum is 2 x that of K, bounded for any orientation of n by
  /// 2 area stiffness_row_bound_per_area(params). Throws invalid_input if the node_set does not
  /// have the set's gridpoint count.
  void add_stiffness_bounds(node_set& gridpoints) const {
    require(gridpoints.size() == gridpoint_count_ && gridpoints.stiffness.size() == gridpoint_count_,
            "face_contacts::add_stiffness_bounds: node_set has ", gridpoints.size(), " gridpoints and ",
            gridpoints.stiffness.size(), " stiffness entries, expected ", gridpoint_count_);
    for (std::size_t i = 0; i < node_a_.size(); ++i) {
      const real per_area = 2.0 * stiffness_row_bound_per_area(face_params(face_[i]));
      gridpoints.stiffness[node_a_[i]] += per_area * area_[i];
      gridpoints.stiffness[node_b_[i]] += per_area * area_[i];
    }
  }

  // ---- sub-contacts ----
  [[nodiscard]] index_t size() const { return static_cast<index_t>(node_a_.size()); }  ///< Number of sub-contacts
  [[nodiscard]] index_t subcontact_count() const { return size(); }  ///< Number of sub-contacts (as size())
  /// Gridpoint of block A (lower cell id) / block B of sub-contact i.
  [[nodiscard]] index_t node_a(index_t i) const { return node_a_[at(i)]; }
  [[nodiscard]] index_t node_b(index_t i) const { return node_b_[at(i)]; }  ///< Gridpoint of sub-contact i on block B
  [[nodiscard]] index_t block_a(index_t i) const { return shared_faces_[at(face(i))].cell_a; }  ///< Block A of sub-contact i
  [[nodiscard]] index_t block_b(index_t i) const { return shared_faces_[at(face(i))].cell_b; }  ///< Block B of sub-contact i
  /// Shared face (index into tessellation::shared_faces) of sub-contact i.
  [[nodiscard]] index_t face(index_t i) const { return face_[at(i)]; }
  /// Tributary area (m^2).
  [[nodiscard]] real area(index_t i) const { return area_[at(i)]; }
  /// Current unit normal, from block A to block B (that of its face).
  [[nodiscard]] vec3 normal(index_t i) const { return face_normal(face(i)); }
  /// Current position (m): midpoint of the two gridpoints.
  [[nodiscard]] vec3 position(index_t i, const node_set& gridpoints) const {
    return 0.5 * (gridpoints.position(node_a(i)) + gridpoints.position(node_b(i)));
  }
  /// Law state of sub-contact i: a const reference, or a value assembled from the columns when
  /// `packed` (bind it as `const auto&` either way).
  [[nodiscard]] decltype(auto) state(index_t i) const {
    if constexpr (packed)
      return state_.get(at(i));
    else
      return static_cast<const state_type&>(state_[at(i)]);
  }
  /// Law parameters of sub-contact i (those of its face's material pair).
  [[nodiscard]] const params_type& subcontact_params(index_t i) const { return face_params(face(i)); }
  /// Law parameters of shared face s.
  [[nodiscard]] const params_type& face_params(index_t s) const { return law_params_[at(face_param_[at(s)])]; }
  /// True when the sub-contacts of face s started bonded (false: a never-bonded material pair).
  [[nodiscard]] bool face_bonded(index_t s) const { return bonded_[at(face_param_[at(s)])] != 0; }
  /// Contact force on node_b in the last update (N); node_a received its opposite.
  [[nodiscard]] vec3 force(index_t i) const { return -vec3(force_[0][at(i)], force_[1][at(i)], force_[2][at(i)]); }

  /// Saves or loads the sub-contact states field by field from the law's declaration
  /// (law::checkpoint_states: "contacts/state/<field>"), the face normals now and last step and
  /// the last forces (io/checkpoint.hpp), so a restart is bit-identical.
  template <class Archive>
  void checkpoint(Archive& ar) {
    static_assert(law::DeclaresStateFields<Law>, "checkpoints need a law that declares state_fields");
    const std::size_t n = node_a_.size();
    ar.same("contacts/subcontacts", static_cast<std::int64_t>(n));
    law::checkpoint_states<Law>(
        ar, "contacts/state/", n, [&](std::size_t i) { return state_type(state(static_cast<index_t>(i))); },
        [&](std::size_t i, const state_type& s) {
          if constexpr (packed)
            state_.reset(i, s, subcontact_params(static_cast<index_t>(i)));
          else
            state_[i] = s;
        });
    // The packed columns' current tensile strengths as they are, not re-evaluated: the elastic
    // pack path advances them with u_soft, and a restart must read the same bits.
    if constexpr (packed) ar.array("contacts/tensile_strength", state_.f_t);
    ar.matrix("contacts/normal", normal_);
    ar.matrix("contacts/previous_normal", previous_normal_);
    for (int c = 0; c < 3; ++c) ar.array(std::string("contacts/force_a/") + "xyz"[c], force_[static_cast<std::size_t>(c)]);
  }

  // ---- shared faces ----
  [[nodiscard]] index_t face_count() const { return static_cast<index_t>(face_area_.size()); }  ///< Number of shared faces
  /// The tessellation's record of shared face s (cells and tessellation face ids).
  [[nodiscard]] const geometry::tessellation::shared_face& shared_face(index_t s) const { return shared_faces_[at(s)]; }
  /// Sub-contacts of face s are [first_subcontact(s), first_subcontact(s + 1)).
  [[nodiscard]] index_t first_subcontact(index_t s) const { return first_subcontact_[at(s)]; }
  /// Sum of the sub-contact areas of face s (m^2).
  [[nodiscard]] real face_area(index_t s) const { return face_area_[at(s)]; }
  /// Current unit normal of face s, from block A to block B.
  [[nodiscard]] vec3 face_normal(index_t s) const { return normal_.row(s).transpose(); }
  /// True when every sub-contact of face s is broken in tension: the two blocks are separated
  /// along the whole face (a crack crosses it).
  [[nodiscard]] bool face_fully_broken(index_t s) const {
    for (index_t i = first_subcontact(s); i < first_subcontact(s + 1); ++i)
      if (!law::has(Law::status(state(i)), law::contact_status::broken_tension)) return false;
    return true;
  }
  /// Number of fully broken faces.
  [[nodiscard]] index_t broken_face_count() const {
    index_t count = 0;
    for (index_t s = 0; s < face_count(); ++s) count += face_fully_broken(s) ? 1 : 0;
    return count;
  }

  // ---- totals (fixed summation order, serial: cheap next to update()) ----
  /// All energies in one pass (J). The per-mechanism split reads the law state's
  /// dissipated_tension / dissipated_shear / dissipated_compression fields (J/m^2) and is zero
  /// for a law whose state has no such fields; `dissipated` is always the law's total.
  [[nodiscard]] contact_energies energies() const {
    contact_energies e;
    for (std::size_t i = 0; i < node_a_.size(); ++i) {
      const auto& st = state(static_cast<index_t>(i));
      detail::add_subcontact_energies<Law>(e, face_params(face_[i]), st, area_[i]);
    }
    return e;
  }
  [[nodiscard]] real stored_energy() const { return energies().stored; }  ///< Energy stored in the springs (J)
  [[nodiscard]] real dissipated_energy() const { return energies().dissipated; }  ///< Energy dissipated so far (J)
  [[nodiscard]] real dissipated_tension() const { return energies().dissipated_tension; }  ///< Of it, in tension (J)
  [[nodiscard]] real dissipated_shear() const { return energies().dissipated_shear; }  ///< Of it, in shear (J)
  [[nodiscard]] real dissipated_compression() const { return energies().dissipated_compression; }  ///< Of it, in compression (J)
  /// Total area of the sub-contacts broken in tension (m^2).
  [[nodiscard]] real broken_area() const {
    real total = 0;
    for (index_t i = 0; i < size(); ++i)
      if (law::has(Law::status(state(i)), law::contact_status::broken_tension)) total += area(i);
    return total;
  }

 private:
  /// Virgin states, or Law::unbonded_state for the faces of a never-bonded pair.
  void initial_states() {
    const auto face_count = static_cast<index_t>(face_area_.size());
    const std::size_t n = node_a_.size();
    if constexpr (packed) {
      state_.resize(n);
      step_.resize(n);
    } else {
      state_.assign(n, state_type{});
    }
    // Initial states: virgin, or unbonded for a never-bonded pair.
    for (index_t s = 0; s < face_count; ++s) {
      const params_type& p = face_params(s);
      state_type initial{};
      if constexpr (requires { Law::unbonded_state(p); })
        if (bonded_[at(face_param_[at(s)])] == 0) initial = Law::unbonded_state(p);
      for (index_t i = first_subcontact_[at(s)]; i < first_subcontact_[at(s) + 1]; ++i) {
        if constexpr (packed)
          state_.reset(at(i), initial, p);
        else
          state_[at(i)] = initial;
      }
    }
  }

  using triple = kinematics::triple;  ///< scalars in registers (kinematics.hpp)

  /// Sub-contacts per face block (at least; fewer in the last block): some whole lanes::pack's per
  /// block, a few dozen blocks on a 100-block model for the two threads.
  static constexpr index_t block_subcontacts = 64;

  /// Law parameters and bonding of each material_table entry (entry 0 the table's default);
  /// face s uses entry face_param_[s].
  std::vector<params_type> law_params_;
  std::vector<char> bonded_;
  std::vector<index_t> face_param_;
  index_t gridpoint_count_ = 0;
  // per sub-contact
  std::vector<index_t> node_a_, node_b_, face_;
  std::vector<real> area_;
  /// Law states: columns when `packed` (with the per-step columns of Law::update's arguments and
  /// results), else one state_type per sub-contact.
  std::conditional_t<packed, detail::state_columns<Law>, std::vector<state_type>> state_;
  detail::step_columns step_;
  /// Contact force of the last update on node A (N), area (sigma_n n + tau), one array per
  /// component; node B receives its opposite.
  std::array<std::vector<real>, 3> force_;
  // per shared face
  std::vector<geometry::tessellation::shared_face> shared_faces_;
  std::vector<index_t> first_subcontact_{0};
  std::vector<index_t> face_blocks_{0};  ///< faces [face_blocks_[b], face_blocks_[b + 1]) form block b
  detail::face_corners corners_;  ///< polygon corners of each face, for its frame
  std::vector<real> face_area_;
  soa3 normal_, previous_normal_;  ///< unit normals A->B, now and last step
  // gather incidence (CSR over the gridpoints that carry sub-contacts)
  /// Slots [slot_offsets_[g], slot_offsets_[g + 1]) belong to gridpoint g (empty without
  /// sub-contacts): two per sub-contact, its id and the sign of force_ on g (+1 node A, -1 node B).
  std::vector<index_t> slot_offsets_{0};
  std::vector<index_t> slot_subcontact_;
  std::vector<real> slot_sign_;
  std::vector<index_t> contact_gridpoints_;  ///< gridpoints with a non-empty slot range, increasing
};

}  // namespace tessera::contact
