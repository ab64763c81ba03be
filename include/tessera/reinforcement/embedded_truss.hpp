#pragma once
// embedded_truss<Bond>: steel bars as chains of 2-node truss elements embedded in the tetrahedral
// zones of the blocks, bonded to them by a bond law (DESIGN.md §3 "Reinforcement", study Sec. 2.2,
// eq. 7-10). Satisfies the Reinforcement concept; the solver integrates nodes() like gridpoints.
//
// Model and the decisions this implementation makes:
// - Bars: straight, N equal elements (bar.hpp); 3-DOF nodes; lumped steel mass rho_s A L_el / 2 at
//   each element end. Elements cross block faces and cracks freely (they only see their nodes).
// - Axial law (truss.hpp): K_axial = E_s A / L_el (eq. 8), elastic-perfectly plastic at
//   +-f_y A, no rupture; the element axis is the current chord direction.
// - Embedding (embedding.hpp): each node of a bonded bar has one host zone and barycentric weights
//   w_i (eq. 10); u_host = sum w_i u_i over the zone's 4 gridpoints.
// - Bond, per node n with reference unit tangent a (mean of the adjacent elements' reference
//   directions): relative displacement d = u_n - u_host, slip s = d . a, axial bond force
//   F_a = Bond law (eq. 7) with stiffness K_bond,n and strength F_max,n.
//   * Stiffness (eq. 9), coulomb_bond::params::basis = per_node (the default):
//     K_bond,n = (xi / 2) sum over the adjacent elements of K_axial, i.e.
//     xi K_axial on an interior node and xi K_axial / 2 on an end node. With basis =
//     per_unit_length, xi K_axial is a modulus per metre of bar and each adjacent element adds
//     (xi / 2) K_axial L_el (bond.hpp explains why the study's tie needs this reading). This is a bond modulus per
//     unit length k_b = xi E_s A / L_el^2 lumped over each node's tributary length, so a bar's bond
//     stiffness does not depend on where it is cut, and the discrete pull-out response converges
//     to the shear-lag solution (tested).
//   * Strength: F_max,n = (c_bond + sigma_conf tan(phi_bond) pi d) L_trib,n, L_trib,n = half the
//     adjacent elements' lengths; sigma_conf = max(0, -(tr sigma - a.sigma.a) / 2) is the mean
//     compressive stress of the host zone in the plane normal to the bar (Pa, compression +), 0
//     when no zone stress is given (rigid blocks).
//   * Transverse to the bar: a stiff elastic tie, d_t = d - s a resisted by K_bond,n d_t with no
//     limit (the node follows its host, softened only by the tie's finite stiffness, which keeps
//     the stable time step set by the same K_bond).
//   * The tangent a is frozen in the reference configuration: a small-rotation assumption for the
//     bond (the axial law itself uses the current chord).
//   * Force on the node f_n = -(F_a a + K_bond d_t); the host gridpoints receive -w_i f_n, so the
//     bond exchanges no net force.
// - Unbonded bars (bar::bonded = false) have no host and no bond springs (bare-bar reference).
//
// Cost and threading: accumulate_forces is a serial loop over elements then nodes in a fixed order
// (bars have O(100) nodes), allocation-free and deterministic. A solver that gathers gridpoint
// forces in parallel calls its two halves instead: compute_forces (serial), then add_host_forces
// over gridpoint ranges (concurrently for disjoint ranges), with the same result to the bit.
// Not thread-safe for concurrent calls of the other members on one object.

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <utility>
#include <vector>

#include "../core/csr.hpp"
#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "bar.hpp"
#include "bond.hpp"
#include "concepts.hpp"
#include "detail/format.hpp"
#include "embedding.hpp"
#include "truss.hpp"

namespace tessera::reinforcement {

/// Steel bars embedded in the blocks as trusses, bonded to their host zones by Bond (file comment); build refuses bad parameters, no bars, or a bar node outside all zones, naming it
template <BondLaw Bond>
class embedded_truss {
 public:
  using bond_type = Bond;  ///< the bond law
  using bond_state = typename Bond::state;  ///< the bond state per bar node

  /// The steel, the bond law's parameters and the bars (polylines, m)
  struct params {
    reinforcement::steel steel;     ///< bar material and diameter (shared by all bars)
    typename Bond::params bond;     ///< bond law parameters
    std::vector<bar> bars;          ///< bar geometry and discretisation
    /// Which nodes of bonded bars look for a host in this mesh: empty = all of them (a node
    /// outside every zone is refused); otherwise one flag per bar node, in discretisation order,
    /// and only flagged nodes are hosted (each must find a zone), the rest left without a host or
    /// bond here. For a rank's local model, whose mesh holds part of the concrete: its bar nodes'
    /// bonds are evaluated by their own ranks (distributed::local_model::bar_params sets it).
    std::vector<char> hosted_nodes{};
  };
  static constexpr bool enabled = true;  ///< bars present

  /// Validates p, discretises the bars, locates the host zone of every node of a bonded bar among
  /// mesh.zones (reference positions mesh.gridpoints) and sets masses. `gridpoints` must be the
  /// node_set of the mesh's gridpoints (same ids). Throws invalid_input naming the bad parameter,
  /// or the bar, node index and coordinates of a node outside all zones.
  void build(const params& p, const geometry::block_mesh& mesh, const node_set& gridpoints) {
    p.steel.validate();
    Bond::validate(p.bond);
    require(!p.bars.empty(), "embedded_truss: no bars given");
    params_ = p;
    const bar_discretisation d = discretise_bars(p.bars);
    const index_t n_nodes = d.node_count();
    const index_t n_elements = d.element_count();
    const real area = p.steel.area();
    const real rigidity = p.steel.axial_rigidity();
    yield_force_ = p.steel.yield_force();

    bar_node_offsets_ = d.bar_node_offsets;
    bar_element_offsets_ = d.bar_element_offsets;
    element_node_a_ = d.element_node_a;
    element_node_b_ = d.element_node_b;
    element_length_ = d.element_length;
    reference_chord_.resize(n_elements, 3);
    axial_stiffness_.resize(static_cast<std::size_t>(n_elements));
    elements_.assign(static_cast<std::size_t>(n_elements), truss_element::state{});

    nodes_.resize(n_nodes);
    for (index_t n = 0; n < n_nodes; ++n) nodes_.reference.row(n) = d.nodes[static_cast<std::size_t>(n)].transpose();
    node_bar_ = d.node_bar;
    tangent_.setZero(n_nodes, 3);
    tributary_length_.assign(static_cast<std::size_t>(n_nodes), 0.0);
    bond_stiffness_.assign(static_cast<std::size_t>(n_nodes), 0.0);
    const real xi = Bond::stiffness_ratio(p.bond);
    const bool per_unit_length = Bond::stiffness_per_unit_length(p.bond);
    for (index_t e = 0; e < n_elements; ++e) {
      const index_t a = element_node_a_[static_cast<std::size_t>(e)], b = element_node_b_[static_cast<std::size_t>(e)];
      const real length = element_length_[static_cast<std::size_t>(e)];
      const vec3 chord = d.nodes[static_cast<std::size_t>(b)] - d.nodes[static_cast<std::size_t>(a)];
      reference_chord_.row(e) = chord.transpose();
      const real k_axial = rigidity / length;  // eq. 8
      axial_stiffness_[static_cast<std::size_t>(e)] = k_axial;
      const real half_mass = 0.5 * p.steel.density * area * length;
      for (index_t n : {a, b}) {
        nodes_.mass(n) += half_mass;
        tangent_.row(n) += chord.transpose() / length;
        tributary_length_[static_cast<std::size_t>(n)] += 0.5 * length;
        // eq. 9: half of each adjacent element's xi K_axial (per node), or of its modulus per unit
        // length xi K_axial times its length (per unit length); see bond.hpp
        bond_stiffness_[static_cast<std::size_t>(n)] += 0.5 * xi * k_axial * (per_unit_length ? length : 1.0);
      }
    }
    for (index_t n = 0; n < n_nodes; ++n) tangent_.row(n).normalize();

    locate_hosts(p, mesh, gridpoints, d);  // host zones of bonded nodes, and their gridpoint slots
    transverse_gap_.assign(static_cast<std::size_t>(n_nodes), 0.0);
    confining_stress_.assign(static_cast<std::size_t>(n_nodes), 0.0);
  }

  [[nodiscard]] node_set& nodes() { return nodes_; }  ///< The bar nodes
  [[nodiscard]] const node_set& nodes() const { return nodes_; }  ///< The bar nodes

  /// Gershgorin bounds (N/m) on the rows of the stiffness matrix, per node, with the 3x3 blocks
  /// measured by their spectral norm (block Gershgorin, valid for the symmetric elastic stiffness):
  /// - an element between a and b has blocks +-K_axial a a^T, norm K_axial: 2 K_axial on each end;
  /// - an elastic bond (axial spring + transverse tie = K_bond I between u_n and sum w_i u_i) has
  ///   blocks K_bond I (n,n), -w_i K_bond I (n,i), w_i w_j K_bond I (i,j), giving
  ///   K_bond (1 + sum|w|) on the bar node (= 2 K_bond) and K_bond |w_i| (1 + sum|w|) on gridpoint i.
  /// Sets nodes().stiffness; adds to gridpoints.stiffness.
  void add_stiffness_bounds(node_set& gridpoints) {
    nodes_.stiffness.setZero(nodes_.size());
    for (std::size_t e = 0; e < axial_stiffness_.size(); ++e) {
      nodes_.stiffness(element_node_a_[e]) += 2.0 * axial_stiffness_[e];
      nodes_.stiffness(element_node_b_[e]) += 2.0 * axial_stiffness_[e];
    }
    for (index_t n : bonded_nodes_) {
      const host_point& h = hosts_[static_cast<std::size_t>(n)];
      real abs_sum = 0.0;
      for (real w : h.weights) abs_sum += std::abs(w);
      const real k = bond_stiffness_[static_cast<std::size_t>(n)];
      nodes_.stiffness(n) += k * (1.0 + abs_sum);
      for (int i = 0; i < 4; ++i) gridpoints.stiffness(h.gridpoints[static_cast<std::size_t>(i)]) += k * std::abs(h.weights[static_cast<std::size_t>(i)]) * (1.0 + abs_sum);
    }
  }

  /// Step 4 of the step order: adds the axial forces to the bar nodes and the bond forces to the
  /// bar nodes and their host gridpoints (N), from the current displacements; advances the plastic
  /// histories. zone_stress: one Voigt row (xx, yy, zz, yz, zx, xy; Pa, tension +) per zone of the
  /// mesh given to build(), or empty (no confinement): a zone_stress_matrix, or anything with
  /// rows() and row(z) (blocks::deformable::stress_rows).
  template <class ZoneStress = zone_stress_matrix>
  void accumulate_forces(node_set& gridpoints, const ZoneStress& zone_stress) noexcept {
    compute_forces(gridpoints, zone_stress);
    add_host_forces(0, gridpoints.size(), gridpoints);
  }

  // ---- accumulate_forces() in two pieces, for a solver that gathers and integrates the
  // gridpoints in one loop (solver.hpp): compute_forces(gp, stress); then add_host_forces(b, e,
  // gp) over ranges covering all gridpoints (concurrently for disjoint ranges). Same bits. ----

  /// Axial and bond forces on the bar nodes (added to nodes().force), plastic and bond
  /// histories advanced; the bond force on each node's host point is kept for add_host_forces.
  /// Reads gridpoints' displacements only.
  template <class ZoneStress = zone_stress_matrix>
  void compute_forces(const node_set& gridpoints, const ZoneStress& zone_stress) noexcept {
    for (std::size_t e = 0; e < elements_.size(); ++e) add_element_force(e);
    const real perimeter = params_.steel.perimeter();
    for (index_t n : bonded_nodes_) add_bond_force(n, gridpoints, zone_stress, perimeter);
  }
  /// compute_forces over the listed elements (ids, increasing) and the bond springs of the listed
  /// bonded nodes (bonded(n)) only: a rank's part in a run split over MPI ranks
  /// (distributed::stepper). A node all of whose elements are listed takes compute_forces' bits;
  /// the others' forces and histories are left as they were.
  template <class ZoneStress = zone_stress_matrix>
  void compute_forces_of(std::span<const index_t> elements, std::span<const index_t> bonded_nodes,
                         const node_set& gridpoints, const ZoneStress& zone_stress) noexcept {
    for (const index_t e : elements) add_element_force(static_cast<std::size_t>(e));
    const real perimeter = params_.steel.perimeter();
    for (const index_t n : bonded_nodes) add_bond_force(n, gridpoints, zone_stress, perimeter);
  }

  /// Subtracts from gridpoints.force(g) the host share w_i f_n of every bond force whose host
  /// zone has g as corner i, for the gridpoints g in [begin, end), each gridpoint's shares in
  /// the order of the bonded nodes (that of accumulate_forces).
  void add_host_forces(index_t begin, index_t end, node_set& gridpoints) const noexcept {
    if (host_offsets_.empty()) return;
    for (index_t k = host_offsets_[static_cast<std::size_t>(begin)]; k < host_offsets_[static_cast<std::size_t>(end)]; ++k) {
      const auto ks = static_cast<std::size_t>(k);
      const index_t g = host_slot_gridpoint_[ks], n = host_slot_node_[ks];
      const real w = host_slot_weight_[ks];
      for (int c = 0; c < 3; ++c) gridpoints.force(g, c) -= w * host_load_(n, c);
    }
  }

  /// Mean compressive stress in the plane normal to the unit axis a (Pa, compression +, >= 0):
  /// max(0, -(tr sigma - a.sigma.a) / 2), sigma a Voigt row (xx, yy, zz, yz, zx, xy; tension +).
  template <class Row>
  [[nodiscard]] static real confining_stress(const Row& s, const vec3& a) noexcept {
    const real trace = s(0) + s(1) + s(2);
    const real axial = a.x() * a.x() * s(0) + a.y() * a.y() * s(1) + a.z() * a.z() * s(2) +
                       2.0 * (a.y() * a.z() * s(3) + a.z() * a.x() * s(4) + a.x() * a.y() * s(5));
    return std::max(0.0, -0.5 * (trace - axial));
  }

  // ---- energies (J), fixed-order sums ----
  /// Elastic energy of the bars N^2 / (2 K_axial) and of the bond springs (axial + transverse tie).
  [[nodiscard]] real stored_energy() const {
    real e = 0.0;
    for (std::size_t i = 0; i < elements_.size(); ++i) e += truss_element::stored_energy(elements_[i], axial_stiffness_[i]);
    for (index_t n : bonded_nodes_) {
      const auto ni = static_cast<std::size_t>(n);
      const real k = bond_stiffness_[ni];
      e += Bond::stored_energy(bonds_[ni], k) + 0.5 * k * transverse_gap_[ni] * transverse_gap_[ni];
    }
    return e;
  }
  [[nodiscard]] real dissipated_axial() const {  ///< plastic work of the bars (J)
    real e = 0.0;
    for (const auto& s : elements_) e += s.dissipated;
    return e;
  }
  [[nodiscard]] real dissipated_bond() const {  ///< work of bond slip (J)
    real e = 0.0;
    for (index_t n : bonded_nodes_) e += Bond::dissipated_energy(bonds_[static_cast<std::size_t>(n)]);
    return e;
  }
  [[nodiscard]] real dissipated_energy() const { return dissipated_axial() + dissipated_bond(); }  ///< Axial plus bond dissipation (J)
  /// The parts of stored_energy() and dissipated_energy() held by `elements` (element ids) and
  /// by the bond springs of `nodes` (bar node ids; unbonded nodes add nothing), summed in the
  /// lists' order (J): a rank's share in a split run (distributed::stepper::summed_energies).
  /// Throws invalid_input for an id out of range.
  [[nodiscard]] std::array<real, 2> stored_and_dissipated_of(std::span<const index_t> elements,
                                                             std::span<const index_t> nodes) const {
    std::array<real, 2> e{0.0, 0.0};
    for (const index_t i : elements) {
      require(i >= 0 && i < element_count(), "embedded_truss: element ", i, " is out of range [0, ", element_count(), ")");
      e[0] += truss_element::stored_energy(elements_[static_cast<std::size_t>(i)], axial_stiffness_[static_cast<std::size_t>(i)]);
      e[1] += elements_[static_cast<std::size_t>(i)].dissipated;
    }
    for (const index_t n : nodes) {
      require(n >= 0 && n < node_count(), "embedded_truss: bar node ", n, " is out of range [0, ", node_count(), ")");
      if (!bonded(n)) continue;
      const auto ni = static_cast<std::size_t>(n);
      const real k = bond_stiffness_[ni];
      e[0] += Bond::stored_energy(bonds_[ni], k) + 0.5 * k * transverse_gap_[ni] * transverse_gap_[ni];
      e[1] += Bond::dissipated_energy(bonds_[ni]);
    }
    return e;
  }

  // ---- topology ----
  [[nodiscard]] const params& parameters() const { return params_; }  ///< The parameters given
  [[nodiscard]] index_t bar_count() const { return static_cast<index_t>(bar_node_offsets_.size()) - 1; }  ///< Number of bars
  [[nodiscard]] index_t node_count() const { return nodes_.size(); }  ///< Number of bar nodes
  [[nodiscard]] index_t element_count() const { return static_cast<index_t>(elements_.size()); }  ///< Number of truss elements
  /// Node ids of bar b: [first, last) (the first is the bar's start).
  [[nodiscard]] std::pair<index_t, index_t> bar_nodes(index_t b) const {
    return {bar_node_offsets_[static_cast<std::size_t>(b)], bar_node_offsets_[static_cast<std::size_t>(b) + 1]};
  }
  /// Element ids of bar b: [first, last).
  [[nodiscard]] std::pair<index_t, index_t> bar_elements(index_t b) const {
    return {bar_element_offsets_[static_cast<std::size_t>(b)], bar_element_offsets_[static_cast<std::size_t>(b) + 1]};
  }
  [[nodiscard]] index_t node_bar(index_t n) const { return node_bar_[static_cast<std::size_t>(n)]; }  ///< Bar of node n
  [[nodiscard]] index_t element_node_a(index_t e) const { return element_node_a_[static_cast<std::size_t>(e)]; }  ///< First node of element e
  [[nodiscard]] index_t element_node_b(index_t e) const { return element_node_b_[static_cast<std::size_t>(e)]; }  ///< Second node of element e
  [[nodiscard]] real element_length(index_t e) const { return element_length_[static_cast<std::size_t>(e)]; }  ///< reference (m)
  [[nodiscard]] real axial_stiffness(index_t e) const { return axial_stiffness_[static_cast<std::size_t>(e)]; }  ///< N/m
  [[nodiscard]] real yield_force() const { return yield_force_; }                                              ///< N
  /// Host of node n (zone = invalid_index on an unbonded bar).
  [[nodiscard]] const host_point& host(index_t n) const { return hosts_[static_cast<std::size_t>(n)]; }
  [[nodiscard]] bool bonded(index_t n) const { return hosts_[static_cast<std::size_t>(n)].zone != invalid_index; }  ///< True when node n has a host zone
  /// The host zone of every bonded node, in node order: the zones whose stress the bars read.
  [[nodiscard]] std::vector<index_t> host_zones() const {
    std::vector<index_t> zones;
    for (const index_t n : bonded_nodes_) zones.push_back(hosts_[static_cast<std::size_t>(n)].zone);
    return zones;
  }
  [[nodiscard]] vec3 tangent(index_t n) const { return tangent_.row(n).transpose(); }  ///< reference unit axis
  [[nodiscard]] real tributary_length(index_t n) const { return tributary_length_[static_cast<std::size_t>(n)]; }  ///< m
  [[nodiscard]] real bond_stiffness(index_t n) const { return bond_stiffness_[static_cast<std::size_t>(n)]; }  ///< N/m

  /// Saves or loads the bar nodes, the element states (truss_element::checkpoint_fields), the bond
  /// states (Bond::checkpoint_fields) and the last transverse gaps and confining stresses
  /// (io/checkpoint.hpp).
  template <class Archive>
  void checkpoint(Archive& ar) {
    nodes_.checkpoint(ar, "bars/nodes");
    truss_element::checkpoint_fields(ar, "bars/element/", elements_);
    Bond::checkpoint_fields(ar, "bars/bond/", bonds_);
    ar.array("bars/transverse_gap", transverse_gap_);
    ar.array("bars/confining_stress", confining_stress_);
  }

  // ---- recorder accessors (state after the last accumulate_forces) ----
  [[nodiscard]] real axial_force(index_t e) const { return elements_[static_cast<std::size_t>(e)].axial_force; }  ///< N, tension +
  [[nodiscard]] real plastic_elongation(index_t e) const { return elements_[static_cast<std::size_t>(e)].plastic_elongation; }  ///< m
  [[nodiscard]] bool yielding(index_t e) const { return elements_[static_cast<std::size_t>(e)].yielding; }  ///< on the plateau now
  [[nodiscard]] bool yielded(index_t e) const { return elements_[static_cast<std::size_t>(e)].has_yielded; }  ///< ever yielded
  [[nodiscard]] const bond_state& bond(index_t n) const { return bonds_[static_cast<std::size_t>(n)]; }  ///< Bond state of node n
  [[nodiscard]] real slip(index_t n) const { return bonds_[static_cast<std::size_t>(n)].slip; }  ///< m, node rel. to host along a
  [[nodiscard]] real bond_force(index_t n) const { return bonds_[static_cast<std::size_t>(n)].force; }  ///< F_a (N)
  [[nodiscard]] bool bond_slipping(index_t n) const { return bonds_[static_cast<std::size_t>(n)].slipping; }  ///< at the limit now
  [[nodiscard]] real transverse_gap(index_t n) const { return transverse_gap_[static_cast<std::size_t>(n)]; }  ///< |d_t| (m)
  [[nodiscard]] real confining_stress(index_t n) const { return confining_stress_[static_cast<std::size_t>(n)]; }  ///< Pa
  [[nodiscard]] vec3 position(index_t n) const { return nodes_.position(n); }  ///< current (m)
  /// Every element's state in element order (axial force N, plastic elongation m, ...): the
  /// storage itself, valid until the next step (the Python module's strided NumPy views).
  [[nodiscard]] std::span<const truss_element::state> element_states() const { return elements_; }
  /// Every bar node's bond state in node order (slip m, bond force N, ...; empty entries on an
  /// unbonded bar): the storage itself, valid until the next step.
  [[nodiscard]] std::span<const bond_state> bond_states() const { return bonds_; }

 private:
  /// Element e's axial force on its two nodes, its plastic history advanced (compute_forces).
  void add_element_force(std::size_t e) noexcept {
    const soa3& u = nodes_.displacement;
    soa3& f = nodes_.force;
    const index_t a = element_node_a_[e], b = element_node_b_[e];
    const vec3 du(u(b, 0) - u(a, 0), u(b, 1) - u(a, 1), u(b, 2) - u(a, 2));
    const vec3 d0 = reference_chord_.row(static_cast<index_t>(e)).transpose();
    const vec3 chord = d0 + du;
    const real length = chord.norm();
    const real elongation = truss_element::elongation(d0, element_length_[e], du, length);
    truss_element::update(elements_[e], elongation, axial_stiffness_[e], yield_force_);
    const vec3 pull = (elements_[e].axial_force / length) * chord;  // tension pulls a towards b
    for (int c = 0; c < 3; ++c) {
      f(a, c) += pull[c];
      f(b, c) -= pull[c];
    }
  }
  /// Bonded node n's bond force on it (and kept for its host), its slip history advanced.
  template <class ZoneStress>
  void add_bond_force(index_t n, const node_set& gridpoints, const ZoneStress& zone_stress, real perimeter) noexcept {
    const soa3& u = nodes_.displacement;
    soa3& f = nodes_.force;
    const auto ni = static_cast<std::size_t>(n);
    const host_point& h = hosts_[ni];
    vec3 u_host = vec3::Zero();  // eq. 10
    for (int i = 0; i < 4; ++i) u_host += h.weights[static_cast<std::size_t>(i)] * gridpoints.displacement.row(h.gridpoints[static_cast<std::size_t>(i)]).transpose();
    const vec3 a = tangent_.row(n).transpose();
    const vec3 d = u.row(n).transpose() - u_host;
    const real slip = d.dot(a);
    real sigma_conf = 0.0;
    if (zone_stress.rows() > 0) sigma_conf = confining_stress(zone_stress.row(h.zone), a);
    confining_stress_[ni] = sigma_conf;
    const real k = bond_stiffness_[ni];
    Bond::update(params_.bond, bonds_[ni], slip, k, Bond::strength(params_.bond, sigma_conf, perimeter, tributary_length_[ni]));
    const vec3 transverse = d - slip * a;
    transverse_gap_[ni] = transverse.norm();
    const vec3 on_node = -(bonds_[ni].force * a + k * transverse);
    for (int c = 0; c < 3; ++c) {
      f(n, c) += on_node[c];
      host_load_(n, c) = on_node[c];
    }
  }

  /// Host zone of every node of a bonded bar (throws invalid_input for a node outside all zones)
  /// and the host slots grouped by gridpoint (CSR, each gridpoint's in bonded-node order; a
  /// zone's corners are distinct, so a gridpoint appears at most once per node).
  void locate_hosts(const params& p, const geometry::block_mesh& mesh, const node_set& gridpoints,
                    const bar_discretisation& d) {
    const index_t n_nodes = d.node_count();
    hosts_.assign(static_cast<std::size_t>(n_nodes), host_point{});
    bonded_nodes_.clear();
    const bool any_bonded = std::any_of(p.bars.begin(), p.bars.end(), [](const bar& b) { return b.bonded; });
    if (any_bonded) {
      require(gridpoints.size() == mesh.gridpoint_count(), "embedded_truss: the gridpoint node_set has ",
              gridpoints.size(), " nodes but the block mesh has ", mesh.gridpoint_count(), " gridpoints");
      require(mesh.zone_count() > 0, "embedded_truss: bonded bars need a host, but the block mesh has no zones");
      require(p.hosted_nodes.empty() || static_cast<index_t>(p.hosted_nodes.size()) == n_nodes,
              "embedded_truss: hosted_nodes has ", p.hosted_nodes.size(), " flags for the bars' ", n_nodes,
              " nodes (give one per node, or none to host every node of a bonded bar)");
      const zone_locator locator(mesh.gridpoints, mesh.zones);
      for (index_t n = 0; n < n_nodes; ++n) {
        const index_t b = node_bar_[static_cast<std::size_t>(n)];
        if (!p.bars[static_cast<std::size_t>(b)].bonded) continue;
        if (!p.hosted_nodes.empty() && p.hosted_nodes[static_cast<std::size_t>(n)] == 0) continue;
        const vec3 x = d.nodes[static_cast<std::size_t>(n)];
        const std::optional<host_point> host = locator.locate(x);
        require(host.has_value(), "embedded_truss: bar ", b, " node ", n - bar_node_offsets_[static_cast<std::size_t>(b)],
                " at ", detail::point_string(x), " m lies outside every zone of the block mesh (tolerance ",
                zone_locator::tolerance, " relative to the zone size)");
        hosts_[static_cast<std::size_t>(n)] = *host;
        bonded_nodes_.push_back(n);
      }
    }
    bonds_.assign(static_cast<std::size_t>(n_nodes), bond_state{});
    host_load_.setZero(n_nodes, 3);
    host_offsets_.clear();
    host_slot_gridpoint_.clear();
    host_slot_node_.clear();
    host_slot_weight_.clear();
    if (!bonded_nodes_.empty()) {
      auto slots_of = [&](auto&& emit) {
        for (index_t n : bonded_nodes_) {
          const host_point& h = hosts_[static_cast<std::size_t>(n)];
          for (std::size_t i = 0; i < 4; ++i)
            emit(h.gridpoints[i], [&](index_t slot) {
              const auto k = static_cast<std::size_t>(slot);
              host_slot_gridpoint_[k] = h.gridpoints[i];
              host_slot_node_[k] = n;
              host_slot_weight_[k] = h.weights[i];
            });
        }
      };
      host_offsets_ = csr_offsets(static_cast<index_t>(gridpoints.size()), slots_of);
      const std::size_t slots = static_cast<std::size_t>(host_offsets_.back());
      host_slot_gridpoint_.resize(slots);
      host_slot_node_.resize(slots);
      host_slot_weight_.resize(slots);
      csr_fill(host_offsets_, slots_of);
    }
  }

  params params_;
  node_set nodes_;
  real yield_force_ = 0.0;
  std::vector<index_t> bar_node_offsets_{0}, bar_element_offsets_{0}, node_bar_;
  // elements (structure of arrays)
  std::vector<index_t> element_node_a_, element_node_b_;
  std::vector<real> element_length_, axial_stiffness_;
  soa3 reference_chord_;
  std::vector<truss_element::state> elements_;
  // nodes
  soa3 tangent_;
  std::vector<real> tributary_length_, bond_stiffness_, transverse_gap_, confining_stress_;
  std::vector<host_point> hosts_;
  std::vector<index_t> bonded_nodes_;  ///< nodes with a host, ascending
  std::vector<bond_state> bonds_;
  soa3 host_load_;  ///< force on each bonded node from its bond (N); its host gridpoints take -w_i times it
  // host slots (CSR over the gridpoints): slots [host_offsets_[g], host_offsets_[g + 1]) are g's
  std::vector<index_t> host_offsets_;
  std::vector<index_t> host_slot_gridpoint_, host_slot_node_;
  std::vector<real> host_slot_weight_;
};

static_assert(Reinforcement<embedded_truss<coulomb_bond>>,
              "embedded_truss<coulomb_bond> must satisfy the Reinforcement concept");


}  // namespace tessera::reinforcement
