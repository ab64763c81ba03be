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
// Creation. Blocks of a conforming tessellation share faces exactly. For every shared face
// s = (cell_a < cell_b, face_a, face_b) of the tessellation the block_mesh lists the face
// gridpoints of the two sides in the same order (node k of face_a coincides with node k of
// face_b); each such pair is one sub-contact i with
//     node_a(i) = face_nodes(face_a)[k],   node_b(i) = face_nodes(face_b)[k],
//     area(i)   = face_node_area(face_a)[k]   (tributary area, m^2; equal to face_b's),
// so the sub-contact areas of a face sum to the face area. Block A is the lower cell id.
// Sub-contacts of a face are contiguous, faces in tessellation::shared_faces order, and
// "face s" below always means shared face s (not a tessellation face id).
//
// Contact frame. One unit normal per shared face per step, from block A to block B, the
// normalised vector area of the face's polygon drawn through the midpoints of its corner pairs:
//     m_k = (x_a,k + x_b,k) / 2,   S = sum_{k=1}^{K-2} (m_k - m_0) x (m_{k+1} - m_0),   n = S / |S|
// where k runs over the K polygon vertices of the tessellation face (tessellation::face(face_a),
// counter-clockwise seen from A, so S points from A to B) and x = X + u are current positions.
// This is the common plane of the two nearly coincident sides: (S_a - S_b)/2, the difference of
// the Newell vectors of side A and side B, up to terms quadratic in the relative displacement of
// the sides (microns against the face size). The vector area of a closed loop does not depend on
// the surface spanned, so S is exact for a planar face and the mean plane of a warped one; edge
// midpoints and interior face gridpoints of a refined zoning do not enter it. Faces are 4 to 8
// times fewer than sub-contacts, so the frame is computed once per face per step and shared.
//
// Kinematics. The solver calls update() in step 3 of the step, when displacements are at time
// t and velocities at t - dt/2 (docs/architecture.md). The relative displacement increment is
// (contact/kinematics.hpp, shared with any other contact set)
//     du = (v_b - v_a) dt  -  (n_prev x n) x (u_b - u_a)
// The first term is the increment of the last step, t - dt -> t: exactly u(t) - u(t - dt)
// when dt is the (constant) step that produced the current positions. The second removes, to
// first order, the part of that increment due to the rigid tilt of the contact plane from
// the previous frame n_prev to n acting on the current gap g = u_b - u_a (the reference
// positions of a pair coincide to 1e-9 of the model size, so X_b - X_a is dropped): without it
// an open contact (g = u_n n) turned rigidly by dtheta would register a spurious slip
// u_n dtheta, and a slipped one a spurious opening. The law rotates the stored shear stress
// into the new plane (tilt) but not about n, so the twist about n is deliberately left in du:
// for an elastic contact it turns tau with the blocks. Together, a rigid rotation of both blocks
// by any axis and total angle theta in steps dtheta leaves sigma_n and tau (turned with the blocks)
// unchanged up to a relative drift of order theta dtheta (test "rigid rotation": 2e-4 for
// theta = 1.2 rad in 4000 steps; without the correction sigma_n drifts by 33 %).
//     du_n = du . n   (m, + opens),      du_s = du - du_n n   (m, in the contact plane)
// Law::update(params, state, du_n, du_s, n) advances the sub-contact state; the force on node B
// is then (N = Pa m^2)
//     f_b = -area (sigma_n n + tau),     f_a = -f_b,
// so tension (sigma_n > 0, B pulled away from A along n) pulls B back toward A, and tau, which
// has the direction of the slip of B relative to A, resists that slip.
//
// Storage (structure of arrays behind index handles): per sub-contact node_a, node_b, face,
// area, the law state and the force of the last step; per face its sub-contact range, polygon
// corners (the gridpoint pair and the constant reference offset from the first corner, so the
// frame reads displacements only) and the current and previous normals. The force of sub-contact
// i is stored as f_i = area (sigma_n n + tau), the force on node A (node B gets -f_i), one array
// per component written in sub-contact order; the CSR incidence gridpoint -> (sub-contact, sign)
// is built once, listing for each gridpoint that carries sub-contacts its sub-contacts in
// increasing order, and the gather sums sign x f_i over it (exact: sign = +-1). (Writing +-f_i to
// gridpoint-major rows instead cost six stores to scattered cache lines per sub-contact.)
//
// Kernel. Faces go in face blocks, runs of consecutive faces with at least block_subcontacts
// sub-contacts. By default (any law, including the plain cohesive_frictional aliases) the states
// are an array of Law::state and loop (1) below runs Law::update per sub-contact. For a law with
// an elastic pack path (law::ElasticPackLaw: cohesive_frictional) that asks for it
// (law::with_elastic_packs; `packed` below) the state is stored field by field
// (detail::state_columns; state(i) assembles a Law::state by value) and a face block runs three
// loops: (1) per face the frame, then per sub-contact du_n, du_s and n into per-step columns
// (detail::step_columns); (2) Law::update_elastic over lanes::pack's of consecutive sub-contacts
// (core/lanes.hpp), which commits the lanes whose damage flags the step leaves unchanged
// (elastic whatever their damage, advancing along the softening envelope, sliding on the
// residual Coulomb limit); (3) Law::update, from the unchanged state, for the lanes it declined
// (reaching the peak, breaking, a first slip, a compressive cap: detail::advance_states).
// update_elastic and update are one function of the law (step<T, Transitions>), so each sub-contact gets exactly the bits
// Law::update gives it whatever its lane, pack or block (test_contacts "[pack]"). On the RC tie
// the packs take all but 8 in a million sub-contact-steps (55 % when they took only intact
// lanes, which made the tie slower than the default layout; now 12 % faster on one thread), so
// the named solvers (prism_solver, ..., solver.hpp) and the examples' tie use them. The frame
// and the kinematics are written on scalars (kinematics::triple): Eigen's vec3 in 2 + 1 SSE packets went
// through the stack there and stalled on store forwarding once per polygon corner.
//
// Threading and determinism. update() runs two parallel loops (core/parallel.hpp): over face
// blocks (frames, law updates and forces of the block's sub-contacts) and over contact gridpoints
// (gather). Each loop writes only what its index owns and the gather sums in a fixed order, so
// results are bit-identical for any thread count. update() allocates nothing. Concurrent const
// access is safe; update() and add_stiffness_bounds() must not run concurrently with anything
// else on the same object. update() is also offered in pieces (prepare_step, run_task,
// add_force) so that the solver can run the face blocks in one parallel region with the zone
// kernel and gather contact and zone forces in one pass over the gridpoints (solver.hpp); the
// results are the same to the bit.
//
// Cost: memory ~ (70 + sizeof(Law::state)) bytes per sub-contact, plus 64 for the per-step
// columns with packs; update() O(sub-contacts); construction O(sub-contacts + gridpoints). With
// law::study_tie_law on the 100-block prism (benchmarks/bench_contacts.cpp, one core of the shared
// 2-core machine, -march=native): about 26 ns per sub-contact-step by default; with
// law::with_elastic_packs about 17.4 ns with intact-only packs (8 lanes; 296 instructions on
// baseline x86-64 with 2 lanes, 174 for x86-64-v3 with 4), of which roughly frames 3.5,
// kinematics 6, law 4.7 and gather 3.4 (removing one stage at a time); 17.8-18.1 ns since the
// packs also take damaged lanes (17.5-18.2 ns for the intact-only packs in the same rounds).

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <numbers>
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
#include "detail/packed_states.hpp"
#include "kinematics.hpp"
#include "material_table.hpp"

namespace tessera::contact {

namespace detail {
/// A law state that reports its dissipated energy (J/m^2) per mechanism.
template <class S>
concept has_dissipation_split = requires(const S& s) {
  { s.dissipated_tension } -> std::convertible_to<real>;
  { s.dissipated_shear } -> std::convertible_to<real>;
  { s.dissipated_compression } -> std::convertible_to<real>;
};

}  // namespace detail

template <law::ContactLaw Law>
class face_contacts {
  /// Array subscript of an index handle.
  template <std::integral I>
  [[nodiscard]] static constexpr std::size_t at(I i) noexcept {
    return static_cast<std::size_t>(i);
  }

 public:
  using law_type = Law;
  using params_type = typename Law::params;
  /// What the constructor takes: the law's parameters per pair of block materials (a plain
  /// params_type converts to a table with one entry for every pair).
  using params = material_table<params_type>;
  using state_type = typename Law::state;
  /// True when Law has an elastic pack path (law::ElasticPackLaw) and asks for it
  /// (law::with_elastic_packs): states are then stored as columns and updated over lanes::pack's
  /// (file comment, "Kernel"). Off for the plain laws (the default layout, Law::update per
  /// sub-contact).
  static constexpr bool packed = law::ElasticPackLaw<Law> && requires { requires Law::use_elastic_packs; };

  /// max over unit normals n of the absolute row sum of (k_s I + (k_n - k_s) n n^T), per unit
  /// area (Pa/m). Row i: |k_s + (k_n - k_s) n_i^2| + sum_{j != i} |k_n - k_s| |n_i n_j|
  /// <= k_s + |k_n - k_s| |n_i| ||n||_1, and max over unit n of |n_i| ||n||_1 = (1 + sqrt 3) / 2
  /// (n_i = cos a, the other two sin a / sqrt 2: cos^2 a + sqrt 2 sin a cos a peaks at
  /// 1/2 + sqrt(3)/2). The bound is attained, and holds for every orientation the contact may
  /// rotate to, so a rotation never invalidates the time step computed from it.
  [[nodiscard]] static real stiffness_row_bound_per_area(const params_type& p) {
    const real k_n = Law::normal_stiffness(p);
    const real k_s = Law::shear_stiffness(p);
    return k_s + std::abs(k_n - k_s) * (1.0 + std::numbers::sqrt3) / 2.0;
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
    const index n_faces = tess.face_count();
    const index n_gridpoints = mesh.gridpoint_count();
    require<geometry_error>(static_cast<index>(mesh.face_node_offsets.size()) == n_faces + 1,
                            "face_contacts: block_mesh has face nodes for ", mesh.face_node_offsets.size() - 1,
                            " faces, expected one entry per tessellation face (", n_faces, ")");
    require<geometry_error>(static_cast<index>(mesh.gridpoint_vertex.size()) == n_gridpoints,
                            "face_contacts: block_mesh has ", mesh.gridpoint_vertex.size(),
                            " gridpoint_vertex entries, expected one per gridpoint (", n_gridpoints, ")");
    require<geometry_error>(mesh.face_node_area.size() == mesh.face_nodes.size(), "face_contacts: block_mesh has ",
                            mesh.face_node_area.size(), " face node areas for ", mesh.face_nodes.size(), " face nodes");
    require<geometry_error>(mesh.block_material.empty() || static_cast<index>(mesh.block_material.size()) == mesh.block_count(),
                            "face_contacts: block_mesh has ", mesh.block_material.size(), " block materials for ",
                            mesh.block_count(), " blocks (give one id per block, or none for all 0)");
    gridpoint_count_ = n_gridpoints;
    for (const auto& e : table.entries()) {
      law_params_.push_back(e.params);
      bonded_.push_back(e.bonded ? 1 : 0);
      if constexpr (!requires { Law::unbonded_state(e.params); })
        require(e.bonded, "face_contacts: a never-bonded material pair needs a law with an unbonded state "
                          "(Law::unbonded_state); this law has none");
    }

    aabb box;
    for (const vec3& x : mesh.gridpoints) box.expand(x);
    const real tolerance = 1e-9 * (mesh.gridpoints.empty() ? 1.0 : box.size().norm());

    const auto face_count = static_cast<index>(tess.shared_faces.size());
    first_subcontact_.assign(1, 0);
    first_corner_.assign(1, 0);
    first_subcontact_.reserve(at(face_count) + 1);
    first_corner_.reserve(at(face_count) + 1);
    shared_faces_ = tess.shared_faces;
    face_area_.reserve(at(face_count));
    for (index s = 0; s < face_count; ++s) {
      const auto& sf = tess.shared_faces[at(s)];
      // Throws geometry_error naming the face; the message is only built on failure.
      const auto check = [&](bool ok, const auto&... message) {
        if (!ok)
          throw geometry_error(tessera::detail::concat("face_contacts: shared face ", s, " (cells ", sf.cell_a,
                                                       " and ", sf.cell_b, ", tessellation faces ", sf.face_a, " and ",
                                                       sf.face_b, "): ", message...));
      };
      check(sf.face_a >= 0 && sf.face_a < n_faces && sf.face_b >= 0 && sf.face_b < n_faces && sf.cell_a >= 0 &&
                sf.cell_a < sf.cell_b && sf.cell_b < tess.cell_count(),
            "face or cell id out of range or cells not in increasing order (", tess.cell_count(), " cells, ", n_faces,
            " faces)");
      if (static_cast<index>(tess.face_cell.size()) == n_faces)
        check(tess.face_cell[at(sf.face_a)] == sf.cell_a && tess.face_cell[at(sf.face_b)] == sf.cell_b,
              "faces belong to cells ", tess.face_cell[at(sf.face_a)], " and ", tess.face_cell[at(sf.face_b)]);
      const index na0 = mesh.face_node_offsets[at(sf.face_a)];
      const index nb0 = mesh.face_node_offsets[at(sf.face_b)];
      const index n_nodes = mesh.face_node_offsets[at(sf.face_a) + 1] - na0;
      const index n_nodes_b = mesh.face_node_offsets[at(sf.face_b) + 1] - nb0;
      check(n_nodes == n_nodes_b && n_nodes >= 3, "the sides have ", n_nodes, " and ", n_nodes_b,
            " face nodes, expected the same number (>= 3)");
      real face_area = 0;
      for (index k = 0; k < n_nodes; ++k) {
        const index a = mesh.face_nodes[at(na0 + k)];
        const index b = mesh.face_nodes[at(nb0 + k)];
        check(a >= 0 && a < n_gridpoints && b >= 0 && b < n_gridpoints, "face node ", k, " refers to gridpoints ", a,
              " and ", b, ", expected ids in [0, ", n_gridpoints, ")");
        if (static_cast<index>(mesh.gridpoint_block.size()) == n_gridpoints)
          check(mesh.gridpoint_block[at(a)] == sf.cell_a && mesh.gridpoint_block[at(b)] == sf.cell_b, "face node ", k,
                ": gridpoints ", a, " and ", b, " belong to blocks ", mesh.gridpoint_block[at(a)], " and ",
                mesh.gridpoint_block[at(b)]);
        const vec3& xa = mesh.gridpoints[at(a)];
        const vec3& xb = mesh.gridpoints[at(b)];
        const real gap = (xb - xa).norm();
        check(gap <= tolerance, "face node ", k, ": gridpoint ", a, " at (", xa.x(), ", ", xa.y(), ", ", xa.z(),
              ") and gridpoint ", b, " at (", xb.x(), ", ", xb.y(), ", ", xb.z(), ") are ", gap,
              " m apart, expected coincident (tolerance ", tolerance,
              " m); the twin faces list their nodes in different orders");
        const real area_a = mesh.face_node_area[at(na0 + k)];
        const real area_b = mesh.face_node_area[at(nb0 + k)];
        check(area_a > 0 && std::isfinite(area_a) && std::abs(area_a - area_b) <= 1e-9 * std::max(area_a, area_b),
              "face node ", k, ": tributary areas ", area_a, " and ", area_b, " m^2, expected equal and > 0");
        node_a_.push_back(a);
        node_b_.push_back(b);
        face_.push_back(s);
        area_.push_back(area_a);
        face_area += area_a;
      }
      first_subcontact_.push_back(static_cast<index>(node_a_.size()));
      face_area_.push_back(face_area);
      face_param_.push_back(static_cast<index>(table.entry_index(mesh.material(sf.cell_a), mesh.material(sf.cell_b))));

      // Polygon corners: the face node of each tessellation vertex of face_a, in loop order.
      const auto loop = tess.face(sf.face_a);
      check(loop.size() >= 3, "the polygon has ", loop.size(), " vertices, expected >= 3");
      for (const index vertex : loop) {
        index corner = invalid_index;
        for (index k = 0; k < n_nodes && corner == invalid_index; ++k)
          if (mesh.gridpoint_vertex[at(mesh.face_nodes[at(na0 + k)])] == vertex &&
              mesh.gridpoint_vertex[at(mesh.face_nodes[at(nb0 + k)])] == vertex)
            corner = first_subcontact_[at(s)] + k;
        check(corner != invalid_index, "tessellation vertex ", vertex,
              " has no face node copying it on both sides (block_mesh::gridpoint_vertex)");
        corner_a_.push_back(node_a_[at(corner)]);
        corner_b_.push_back(node_b_[at(corner)]);
      }
      first_corner_.push_back(static_cast<index>(corner_a_.size()));
      // Reference offsets of the corners from the first one (side A), constant.
      const vec3& x0 = mesh.gridpoints[at(corner_a_[at(first_corner_[at(s)])])];
      for (index k = first_corner_[at(s)]; k < first_corner_[at(s) + 1]; ++k)
        for (int c = 0; c < 3; ++c) corner_offset_[at(c)].push_back(mesh.gridpoints[at(corner_a_[at(k)])][c] - x0[c]);
    }

    const std::size_t n = node_a_.size();
    if constexpr (packed) {
      state_.resize(n);
      step_.resize(n);
    } else {
      state_.assign(n, state_type{});
    }
    // Initial states: virgin, or unbonded for a never-bonded pair.
    for (index s = 0; s < face_count; ++s) {
      const params_type& p = face_params(s);
      state_type initial{};
      if constexpr (requires { Law::unbonded_state(p); })
        if (bonded_[at(face_param_[at(s)])] == 0) initial = Law::unbonded_state(p);
      for (index i = first_subcontact_[at(s)]; i < first_subcontact_[at(s) + 1]; ++i) {
        if constexpr (packed)
          state_.reset(at(i), initial, p);
        else
          state_[at(i)] = initial;
      }
    }
    // Face blocks: runs of consecutive faces with at least block_subcontacts sub-contacts (the
    // last one may have fewer) and one material-pair entry, the unit of the parallel face loop.
    face_blocks_.assign(1, 0);
    for (index s = 0; s < face_count; ++s)
      if (s + 1 == face_count || face_param_[at(s) + 1] != face_param_[at(s)] ||
          first_subcontact_[at(s) + 1] - first_subcontact_[at(face_blocks_.back())] >= block_subcontacts)
        face_blocks_.push_back(s + 1);

    // Reference frames; a face whose two sides cancel has no plane.
    normal_.setZero(face_count, 3);
    {
      const soa3 u = soa3::Zero(n_gridpoints, 3);
      const real* up[3] = {u.col(0).data(), u.col(1).data(), u.col(2).data()};
      for (index s = 0; s < face_count; ++s) {
        const triple area = face_area_vector(s, up);
        const vec3 d(area.x, area.y, area.z);
        require<geometry_error>(d.norm() > 0, "face_contacts: shared face ", s, " (cells ",
                                shared_faces_[at(s)].cell_a, " and ", shared_faces_[at(s)].cell_b,
                                "): zero vector area, the face polygon has no plane (degenerate face)");
        normal_.row(s) = d.normalized().transpose();
      }
    }
    previous_normal_ = normal_;

    // Gather incidence: for each gridpoint carrying sub-contacts, in increasing id, one slot per
    // incident sub-contact in increasing sub-contact order: the sub-contact and the sign of its
    // force_ on that gridpoint (+1 on node A, -1 on node B).
    std::vector<index> count(at(n_gridpoints), 0);
    for (std::size_t i = 0; i < n; ++i) {
      ++count[at(node_a_[i])];
      ++count[at(node_b_[i])];
    }
    std::vector<index> next_slot(at(n_gridpoints), invalid_index);
    slot_offsets_.assign(at(n_gridpoints) + 1, 0);
    for (index g = 0; g < n_gridpoints; ++g) {
      slot_offsets_[at(g) + 1] = slot_offsets_[at(g)] + count[at(g)];
      if (count[at(g)] == 0) continue;
      next_slot[at(g)] = slot_offsets_[at(g)];
      contact_gridpoints_.push_back(g);
    }
    slot_subcontact_.resize(2 * n);
    slot_sign_.resize(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const index sb = next_slot[at(node_b_[i])]++, sa = next_slot[at(node_a_[i])]++;
      slot_subcontact_[at(sb)] = static_cast<index>(i);
      slot_sign_[at(sb)] = -1;
      slot_subcontact_[at(sa)] = static_cast<index>(i);
      slot_sign_[at(sa)] = 1;
    }
    for (auto& column : force_) column.assign(n, 0.0);
  }

  /// Recomputes the contact frames from the current positions of `gridpoints` and makes them
  /// the previous frames as well. Construction uses the reference positions; call this before
  /// the first update() when the run starts from non-zero displacements (e.g. a restart).
  void initialize_frames(const node_set& gridpoints) {
    require(gridpoints.size() == gridpoint_count_, "face_contacts::initialize_frames: node_set has ",
            gridpoints.size(), " gridpoints, expected ", gridpoint_count_);
    const real* u[3] = {gridpoints.displacement.col(0).data(), gridpoints.displacement.col(1).data(),
                        gridpoints.displacement.col(2).data()};
    for (index s = 0; s < face_count(); ++s) {
      const triple area = face_area_vector(s, u);
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
    parallel_for(task_count(), [&](std::int64_t b) { run_task(static_cast<index>(b), gridpoints, dt); }, 2);
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
  [[nodiscard]] index task_count() const { return static_cast<index>(face_blocks_.size()) - 1; }
  /// update_faces over face block b.
  void run_task(index b, const node_set& gridpoints, real dt) noexcept {
    update_faces(face_blocks_[at(b)], face_blocks_[at(b) + 1], gridpoints, dt);
  }
  /// update_faces over face s alone.
  void update_face(index s, const node_set& gridpoints, real dt) noexcept { update_faces(s, s + 1, gridpoints, dt); }

  /// Frames of faces [first_face, last_face) from the current positions (a degenerate face keeps
  /// its previous frame), then law update and force rows of each of their sub-contacts. Writes
  /// only those faces' data.
  void update_faces(index first_face, index last_face, const node_set& gridpoints, real dt) noexcept {
    const real* u[3] = {gridpoints.displacement.col(0).data(), gridpoints.displacement.col(1).data(),
                        gridpoints.displacement.col(2).data()};
    const real* v[3] = {gridpoints.velocity.col(0).data(), gridpoints.velocity.col(1).data(),
                        gridpoints.velocity.col(2).data()};
    for (index s = first_face; s < last_face; ++s) {
      const params_type& p = face_params(s);
      const triple d = face_area_vector(s, u);
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
        const index a = node_a_[i], b = node_b_[i];
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
      for (index run = first_face; run < last_face;) {
        index run_end = run + 1;
        while (run_end < last_face && face_param_[at(run_end)] == face_param_[at(run)]) ++run_end;
        detail::advance_states<Law>(face_params(run), state_, step_, area_.data(), at(first_subcontact_[at(run)]),
                                    at(first_subcontact_[at(run_end)]), force);
        run = run_end;
      }
    }
  }

  /// Adds the contact forces of the last update_face calls on gridpoint g to gridpoints.force
  /// (a contiguous sum over g's slots in fixed order; nothing for a gridpoint without sub-contacts).
  void add_force(index g, node_set& gridpoints) const noexcept {
    const index begin = slot_offsets_[at(g)], end = slot_offsets_[at(g) + 1];
    if (begin == end) return;
    const real* f[3] = {force_[0].data(), force_[1].data(), force_[2].data()};
    real fx = 0, fy = 0, fz = 0;
    for (index e = begin; e < end; ++e) {
      // +-f exactly: the sum is that of the forces on g in increasing sub-contact order.
      const auto i = at(slot_subcontact_[at(e)]);
      const real sign = slot_sign_[at(e)];
      fx += sign * f[0][i];
      fy += sign * f[1][i];
      fz += sign * f[2][i];
    }
    gridpoints.force(g, 0) += fx;
    gridpoints.force(g, 1) += fy;
    gridpoints.force(g, 2) += fz;
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
  [[nodiscard]] index size() const { return static_cast<index>(node_a_.size()); }
  [[nodiscard]] index subcontact_count() const { return size(); }
  /// Gridpoint of block A (lower cell id) / block B of sub-contact i.
  [[nodiscard]] index node_a(index i) const { return node_a_[at(i)]; }
  [[nodiscard]] index node_b(index i) const { return node_b_[at(i)]; }
  [[nodiscard]] index block_a(index i) const { return shared_faces_[at(face(i))].cell_a; }
  [[nodiscard]] index block_b(index i) const { return shared_faces_[at(face(i))].cell_b; }
  /// Shared face (index into tessellation::shared_faces) of sub-contact i.
  [[nodiscard]] index face(index i) const { return face_[at(i)]; }
  /// Tributary area (m^2).
  [[nodiscard]] real area(index i) const { return area_[at(i)]; }
  /// Current unit normal, from block A to block B (that of its face).
  [[nodiscard]] vec3 normal(index i) const { return face_normal(face(i)); }
  /// Current position (m): midpoint of the two gridpoints.
  [[nodiscard]] vec3 position(index i, const node_set& gridpoints) const {
    return 0.5 * (gridpoints.position(node_a(i)) + gridpoints.position(node_b(i)));
  }
  /// Law state of sub-contact i: a const reference, or a value assembled from the columns when
  /// `packed` (bind it as `const auto&` either way).
  [[nodiscard]] decltype(auto) state(index i) const {
    if constexpr (packed)
      return state_.get(at(i));
    else
      return static_cast<const state_type&>(state_[at(i)]);
  }
  /// Law parameters of sub-contact i (those of its face's material pair).
  [[nodiscard]] const params_type& subcontact_params(index i) const { return face_params(face(i)); }
  /// Law parameters of shared face s.
  [[nodiscard]] const params_type& face_params(index s) const { return law_params_[at(face_param_[at(s)])]; }
  /// True when the sub-contacts of face s started bonded (false: a never-bonded material pair).
  [[nodiscard]] bool face_bonded(index s) const { return bonded_[at(face_param_[at(s)])] != 0; }
  /// Contact force on node_b in the last update (N); node_a received its opposite.
  [[nodiscard]] vec3 force(index i) const { return -vec3(force_[0][at(i)], force_[1][at(i)], force_[2][at(i)]); }

  // ---- shared faces ----
  [[nodiscard]] index face_count() const { return static_cast<index>(face_area_.size()); }
  /// The tessellation's record of shared face s (cells and tessellation face ids).
  [[nodiscard]] const geometry::tessellation::shared_face& shared_face(index s) const { return shared_faces_[at(s)]; }
  /// Sub-contacts of face s are [first_subcontact(s), first_subcontact(s + 1)).
  [[nodiscard]] index first_subcontact(index s) const { return first_subcontact_[at(s)]; }
  /// Sum of the sub-contact areas of face s (m^2).
  [[nodiscard]] real face_area(index s) const { return face_area_[at(s)]; }
  /// Current unit normal of face s, from block A to block B.
  [[nodiscard]] vec3 face_normal(index s) const { return normal_.row(s).transpose(); }
  /// True when every sub-contact of face s is broken in tension: the two blocks are separated
  /// along the whole face (a crack crosses it).
  [[nodiscard]] bool face_fully_broken(index s) const {
    for (index i = first_subcontact(s); i < first_subcontact(s + 1); ++i)
      if (!law::has(Law::status(state(i)), law::contact_status::broken_tension)) return false;
    return true;
  }
  /// Number of fully broken faces.
  [[nodiscard]] index broken_face_count() const {
    index count = 0;
    for (index s = 0; s < face_count(); ++s) count += face_fully_broken(s) ? 1 : 0;
    return count;
  }

  // ---- totals (fixed summation order, serial: cheap next to update()) ----
  /// All energies in one pass (J). The per-mechanism split reads the law state's
  /// dissipated_tension / dissipated_shear / dissipated_compression fields (J/m^2) and is zero
  /// for a law whose state has no such fields; `dissipated` is always the law's total.
  [[nodiscard]] contact_energies energies() const {
    contact_energies e;
    for (std::size_t i = 0; i < node_a_.size(); ++i) {
      const auto& st = state(static_cast<index>(i));
      const real a = area_[i];
      e.stored += a * Law::stored_energy(face_params(face_[i]), st);
      e.dissipated += a * Law::dissipated_energy(st);
      if constexpr (detail::has_dissipation_split<state_type>) {
        e.dissipated_tension += a * st.dissipated_tension;
        e.dissipated_shear += a * st.dissipated_shear;
        e.dissipated_compression += a * st.dissipated_compression;
      }
    }
    return e;
  }
  [[nodiscard]] real stored_energy() const { return energies().stored; }
  [[nodiscard]] real dissipated_energy() const { return energies().dissipated; }
  [[nodiscard]] real dissipated_tension() const { return energies().dissipated_tension; }
  [[nodiscard]] real dissipated_shear() const { return energies().dissipated_shear; }
  [[nodiscard]] real dissipated_compression() const { return energies().dissipated_compression; }
  /// Total area of the sub-contacts broken in tension (m^2).
  [[nodiscard]] real broken_area() const {
    real total = 0;
    for (index i = 0; i < size(); ++i)
      if (law::has(Law::status(state(i)), law::contact_status::broken_tension)) total += area(i);
    return total;
  }

 private:
  using triple = kinematics::triple;  ///< scalars in registers (kinematics.hpp)

  /// Sub-contacts per face block (at least; fewer in the last block): some whole lanes::pack's per
  /// block, a few dozen blocks on a 100-block model for the two threads.
  static constexpr index block_subcontacts = 64;

  /// Twice the vector area of face s's polygon through the midpoints of its corner pairs (m^2),
  /// sum_k (m_k - m_0) x (m_{k+1} - m_0) (see the file comment), from differences
  /// (X_k - X_0) + ((u_a,k + u_b,k) - (u_a,0 + u_b,0)) / 2 so the displacement is not swamped by
  /// the coordinates; X of side A stands for both sides (coincident to 1e-9 of the model size),
  /// and X_k - X_0 is the stored corner_offset_ (the reference positions of the block_mesh).
  [[nodiscard]] triple face_area_vector(index s, const real* const u[3]) const noexcept {
    const auto first = at(first_corner_[at(s)]);
    const auto count = at(first_corner_[at(s) + 1]) - first;
    const index* ca = corner_a_.data() + first;
    const index* cb = corner_b_.data() + first;
    const real* dX[3] = {corner_offset_[0].data() + first, corner_offset_[1].data() + first,
                         corner_offset_[2].data() + first};
    real origin_u[3];
    for (int c = 0; c < 3; ++c) origin_u[c] = 0.5 * (u[c][ca[0]] + u[c][cb[0]]);
    const auto midpoint_offset = [&](std::size_t k) {
      const index a = ca[k], b = cb[k];
      real d[3];
      for (int c = 0; c < 3; ++c) d[c] = dX[c][k] + (0.5 * (u[c][a] + u[c][b]) - origin_u[c]);
      return triple{d[0], d[1], d[2]};
    };
    triple s_area{0, 0, 0};
    triple previous = midpoint_offset(1);
    for (std::size_t k = 2; k < count; ++k) {
      const triple next = midpoint_offset(k);
      const triple area = kinematics::cross(previous, next);
      s_area = {s_area.x + area.x, s_area.y + area.y, s_area.z + area.z};
      previous = next;
    }
    return s_area;
  }

  /// Law parameters and bonding of each material_table entry (entry 0 the table's default);
  /// face s uses entry face_param_[s].
  std::vector<params_type> law_params_;
  std::vector<char> bonded_;
  std::vector<index> face_param_;
  index gridpoint_count_ = 0;
  // per sub-contact
  std::vector<index> node_a_, node_b_, face_;
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
  std::vector<index> first_subcontact_{0};
  std::vector<index> face_blocks_{0};  ///< faces [face_blocks_[b], face_blocks_[b + 1]) form block b
  // Polygon corners of face s (CCW seen from A), CSR [first_corner_[s], first_corner_[s + 1]):
  // the gridpoints of the corner pair and the reference offset X_a,k - X_a,0 from the face's
  // first corner (per component), so the frame reads only displacements.
  std::vector<index> first_corner_{0}, corner_a_, corner_b_;
  std::array<std::vector<real>, 3> corner_offset_;
  std::vector<real> face_area_;
  soa3 normal_, previous_normal_;  ///< unit normals A->B, now and last step
  // gather incidence (CSR over the gridpoints that carry sub-contacts)
  /// Slots [slot_offsets_[g], slot_offsets_[g + 1]) belong to gridpoint g (empty without
  /// sub-contacts): two per sub-contact, its id and the sign of force_ on g (+1 node A, -1 node B).
  std::vector<index> slot_offsets_{0};
  std::vector<index> slot_subcontact_;
  std::vector<real> slot_sign_;
  std::vector<index> contact_gridpoints_;  ///< gridpoints with a non-empty slot range, increasing
};

}  // namespace tessera::contact
