#pragma once
// implicit::quasi_static<Zone, Law, Bars>: the static equilibrium of a model of deformable blocks,
// bonded face contacts and optionally steel bars (Bars = reinforcement::embedded_truss<Bond>,
// bars.hpp; no_bars by default), advanced in increments of prescribed displacement and solved with
// a sparse Cholesky factorisation (sparse_factor.hpp: Eigen's SimplicialLDLT, or CHOLMOD's
// supernodal LL^T where built with it) of the secant stiffness (stiffness.hpp), instead of
// stepping the equations of motion (issue #43, candidate 3).
//
// Model. Small displacements: the zones are linear elastic about the reference state (K_z of
// stiffness.hpp, the linearisation of the co-rotated zone kernel), the sub-contacts keep the
// normals they had when the model was made, and their stresses come from the contact law itself,
// Law::update, so the law's envelope, limits and flags are the explicit solver's. The forces on
// the gridpoints (N) are
//     f(u) = -K_zones u + sum_i f_i(state_i),   f_i on b = -A_i (sigma_n n + tau), on a the opposite,
// plus the bars' element and bond forces on their nodes and host gridpoints (bars.hpp), and equilibrium is f = 0 on every free component; a prescribed component's reaction (N, the force
// the support exerts on the gridpoint) is -f there.
//
// Supports. Read from the node_set's constraint flags and prescribed velocities when the model is
// made (solver/boundary.hpp, supports.hpp): an increment of duration dt (s of pseudo-time) moves
// each prescribed component by its prescribed velocity x dt (m); a fixed component stays at zero.
//
// Increments: displacement control (solve_increment) and crack-opening control
// (solve_controlled_increment), their iterations, options and results: increment.hpp.
//
// Counts and times (counts()): increments, iterations, force evaluations, factorisations (with
// symbolic analyses), solves, and wall-clock seconds in assembly, factorisation, solves and force
// evaluations.
//
// Cost: memory of the factor (fill-in of a 3D mesh); per iteration O(zones + sub-contacts) for the
// forces and one triangular solve pair; a factorisation where secants changed. Not thread-safe.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "../../core/errors.hpp"
#include "../../core/nodes.hpp"
#include "../../core/types.hpp"
#include "../boundary.hpp"
#include "bars.hpp"
#include "increment.hpp"
#include "sparse_factor.hpp"
#include "stiffness.hpp"

namespace tessera::implicit {

/// Static equilibrium of deformable blocks, bonded faces and optionally bars under increments of prescribed displacement (file comment); refuses (invalid_input) a model it cannot solve, naming it
template <zones::ZoneModel Zone, SecantLaw Law, class Bars = no_bars>
class quasi_static {
 public:
  using state_type = typename Law::state;  ///< the contact law's state per sub-contact

  /// The model of `blocks` (built from `mesh`) and `contacts`, with the supports and the current
  /// displacements of `gridpoints` (the solver's node_set; displacements must be zero: the zones
  /// are linear about the reference state). Copies the contact states as the committed ones.
  /// `kind` is the sparse factorisation of K_sec (sparse_factor.hpp). Throws invalid_input for a
  /// mesh that is not the blocks', a node_set of another size or with non-zero displacements, no
  /// free component, or factorization::supernodal in a build without CHOLMOD.
  quasi_static(const geometry::block_mesh& mesh, const blocks::deformable<Zone>& blocks,
               const contact::face_contacts<Law>& contacts, const node_set& gridpoints,
               factorization kind = default_factorization())
    requires std::same_as<Bars, no_bars>
      : quasi_static(mesh, blocks, contacts, gridpoints, no_bars{}, kind) {}
  /// The same with steel bars (reinforcement::embedded_truss, bars.hpp), their nodes' supports and
  /// prescribed velocities from bars.nodes(); also throws for displaced bar nodes or a bond law with
  /// a friction angle.
  quasi_static(const geometry::block_mesh& mesh, const blocks::deformable<Zone>& blocks,
               const contact::face_contacts<Law>& contacts, const node_set& gridpoints, const Bars& bars,
               factorization kind = default_factorization())
      : contacts_(&contacts), bars_(bars, 3 * gridpoints.size()), factor_(kind) {
    const index_t n_gp = mesh.gridpoint_count();
    require(gridpoints.size() == n_gp, "quasi_static: node_set has ", gridpoints.size(), " gridpoints, the mesh ", n_gp);
    require(gridpoints.displacement.cwiseAbs().maxCoeff() == 0, "quasi_static: the gridpoints are displaced by up to ",
            gridpoints.displacement.cwiseAbs().maxCoeff(), " m; the model starts from the reference state");
    const auto timer = clock::now();
    std::vector<triplet> t;
    add_zone_stiffness(mesh, blocks, t);
    append_node_dofs(gridpoints, free_index_, free_dofs_, velocity_);
    if constexpr (!std::same_as<Bars, no_bars>) append_node_dofs(bars.nodes(), free_index_, free_dofs_, velocity_);
    const auto n_dofs = static_cast<index_t>(free_index_.size());
    zones_.resize(n_dofs, n_dofs);
    zones_.setFromTriplets(t.begin(), t.end());
    require(!free_dofs_.empty(), "quasi_static: every component of the ", n_gp, " gridpoints is prescribed");
    // The zones' part of K on the free components, once.
    std::vector<triplet> free_t;
    const auto n_free = static_cast<index_t>(free_dofs_.size());
    zones_coupling_.setZero(n_free);  // K_fp v of the zones (N/s)
    for (const triplet& e : t) {
      const index_t r = free_index_[static_cast<std::size_t>(e.row())], c = free_index_[static_cast<std::size_t>(e.col())];
      if (r >= 0 && c >= 0)
        free_t.emplace_back(r, c, e.value());
      else if (r >= 0)
        zones_coupling_[r] += e.value() * velocity_[e.col()];
    }
    zones_free_.resize(n_free, n_free);
    zones_free_.setFromTriplets(free_t.begin(), free_t.end());
    const auto n_c = static_cast<std::size_t>(contacts.size());
    normals_.resize(n_c);
    committed_.resize(n_c);
    committed_gap_.assign(n_c, vec3::Zero());
    last_opening_.assign(n_c, 0);
    in_control_.assign(n_c, 0);
    for (index_t i = 0; i < contacts.size(); ++i) {
      normals_[static_cast<std::size_t>(i)] = contacts.normal(i);
      committed_[static_cast<std::size_t>(i)] = state_type(contacts.state(i));
    }
    trial_ = committed_;
    advancing_.assign(n_c, 0);
    u_.setZero(n_dofs);
    committed_u_ = u_;
    force_.setZero(n_dofs);
    counts_.assembly_s += seconds_since(timer);
    evaluate_forces();
  }

  /// One increment under crack-opening control (file comment, path following): the prescribed
  /// components move by dlambda x velocity with dlambda found with the displacements, so that the
  /// committed crack tractions do the work `crack_work` (J, > 0) on the opening increment of the
  /// softening sub-contacts. Throws invalid_input for bad options, a crack_work that is not
  /// positive and finite, or no sub-contact softening in tension (or at its tensile strength) at
  /// the last equilibrium (use solve_increment there), before anything changes. On failure the model
  /// returns to its last equilibrium.
  increment_result solve_controlled_increment(real crack_work, const increment_options& o) {
    require(std::isfinite(crack_work) && crack_work > 0, "quasi_static: crack work per increment = ", crack_work,
            " J must be finite and > 0");
    require_valid_increment_options(o);
    require(o.control_fraction >= 0 && o.control_fraction <= 1, "quasi_static: control fraction = ",
            o.control_fraction, " must lie in [0, 1]");
    // The constraint's weights on all dofs: A sigma n on b, -A sigma n on a.
    Eigen::VectorXd weight = Eigen::VectorXd::Zero(u_.size());
    index_t controlling = 0;
    std::fill(in_control_.begin(), in_control_.end(), char(0));
    real widest = 0;
    for (const real w : last_opening_) widest = std::max(widest, w);
    for (index_t i = 0; i < contacts_->size(); ++i) {
      const state_type& st = committed_[static_cast<std::size_t>(i)];
      const law::contact_status f = Law::status(st);
      const auto& p = contacts_->subcontact_params(i);
      const bool at_strength = st.sigma_n >= (1 - strength_fraction) * Law::tensile_strength(p, st);
      if (!(law::has(f, law::contact_status::softening) || at_strength) ||
          law::has(f, law::contact_status::broken_tension) || !(st.sigma_n > 0) ||
          (o.control_fraction > 0 && !(last_opening_[static_cast<std::size_t>(i)] >= o.control_fraction * widest)))
        continue;
      const vec3 w = contacts_->area(i) * st.sigma_n * normals_[static_cast<std::size_t>(i)];
      weight.segment<3>(3 * contacts_->node_b(i)) += w;
      weight.segment<3>(3 * contacts_->node_a(i)) -= w;
      ++controlling;
      in_control_[static_cast<std::size_t>(i)] = 1;
    }
    require(controlling > 0, "quasi_static: no sub-contact softens in tension or stands at its tensile strength at the ",
            "last equilibrium; the crack-opening control needs one (advance with solve_increment)");
    ++counts_.increments;
    increment_result r;
    evaluations_in_increment_ = 0;
    const real weight_v = weight.dot(velocity_);  // d(constraint)/d(lambda) through the prescribed components
    Eigen::VectorXd weight_free(static_cast<index_t>(free_dofs_.size()));
    for (std::size_t k = 0; k < free_dofs_.size(); ++k) weight_free[static_cast<index_t>(k)] = weight[free_dofs_[k]];
    evaluate_forces();
    controlled_ = true;
    for (;;) {
      if (r.iterations > 0 && increment_done(r, o)) break;
      const Eigen::VectorXd a = secant_step(r.iterations, o);
      const auto timer = clock::now();
      if (unit_response_stale_) {
        // The free components' response to a unit rate of the prescribed ones: one
        // back-substitution per factorisation that a controlled increment uses.
        bool solved = false;
        unit_response_ = -factor_.solve(coupling_, &solved);
        require(solved && unit_response_.allFinite(), "quasi_static: the solve for the load factor's response failed");
        unit_response_stale_ = false;
        ++counts_.solves;
      }
      // constraint: weight . (u + a + dlambda (b, v) - u_0) = crack_work
      const real reached = weight.dot(u_ - committed_u_) + weight_free.dot(a);
      const real per_lambda = weight_free.dot(unit_response_) + weight_v;
      require(std::isfinite(per_lambda) && per_lambda != 0, "quasi_static: the crack-opening control does not depend on ",
              "the load factor (", per_lambda, " J/s)");
      const real dlambda = (crack_work - reached) / per_lambda;
      for (std::size_t k = 0; k < free_dofs_.size(); ++k)
        u_[free_dofs_[k]] += a[static_cast<index_t>(k)] + dlambda * unit_response_[static_cast<index_t>(k)];
      u_ += dlambda * velocity_;
      time_ += dlambda;
      counts_.solve_s += seconds_since(timer);
      ++r.iterations;
      evaluate_forces();
    }
    controlled_ = false;
    finish_increment(r);
    return r;
  }

  /// Moves the prescribed components by prescribed velocity x duration (m; duration in s of
  /// pseudo-time, >= 0) and iterates to equilibrium (file comment). Throws invalid_input for bad
  /// options or a negative or non-finite duration, before anything changes.
  increment_result solve_increment(real duration, const increment_options& o) {
    require(std::isfinite(duration) && duration >= 0, "quasi_static: increment duration = ", duration,
            " s must be finite and >= 0");
    require_valid_increment_options(o);
    ++counts_.increments;
    u_ += duration * velocity_;
    time_ += duration;
    increment_result r;
    evaluations_in_increment_ = 0;
    real omega = 1;  // relaxation of the secant step (Aitken)
    Eigen::VectorXd previous_du;
    for (;;) {
      evaluate_forces();
      if (increment_done(r, o)) break;
      const Eigen::VectorXd du = secant_step(r.iterations, o);
      const auto timer = clock::now();
      // Aitken's relaxation of the fixed-point step du = G(u) - u (Irons and Tuck; Kuttler and
      // Wall 2008): omega_k = -omega_{k-1} du_{k-1}.(du_k - du_{k-1}) / |du_k - du_{k-1}|^2.
      if (r.iterations > 0 && o.aitken && !o.line_search) {
        const Eigen::VectorXd change = du - previous_du;
        const real change2 = change.squaredNorm();
        if (change2 > 0) omega = -omega * previous_du.dot(change) / change2;
      }
      previous_du = du;
      counts_.solve_s += seconds_since(timer);
      Eigen::VectorXd step = Eigen::VectorXd::Zero(u_.size());  // on the free dofs
      for (std::size_t k = 0; k < free_dofs_.size(); ++k) step[free_dofs_[k]] = omega * du[static_cast<index_t>(k)];
      if (o.line_search)
        search_along(u_, force_, step, [&] { evaluate_forces(); });
      else
        u_ += step;
      ++r.iterations;
    }
    finish_increment(r);
    return r;
  }

  // ---- read-outs ----
  /// Pseudo-time lambda (s) at the last equilibrium: the prescribed components are displaced by
  /// lambda x their prescribed velocity.
  [[nodiscard]] real prescribed_time() const { return time_; }
  /// Energy dissipated in the sub-contacts (J) at the last equilibrium: sum of area x the law's
  /// dissipated_tension (tension) and of area x its other dissipation fields (shear, compression).
  [[nodiscard]] real dissipated_tension() const { return dissipated(&state_type::dissipated_tension); }
  [[nodiscard]] real dissipated_shear() const { return dissipated(&state_type::dissipated_shear); }  ///< Energy dissipated in shear by the sub-contacts (J)
  /// Displacement (m) of gridpoint i, component c, at the last equilibrium.
  [[nodiscard]] real displacement(index_t i, int c) const { return u_[3 * i + c]; }
  /// All displacements (m), dof 3 i + c.
  [[nodiscard]] const Eigen::VectorXd& displacements() const { return u_; }
  /// Sum of the support reactions (N) over the gridpoints of `group` at the last equilibrium:
  /// -f on their prescribed components (f: zone, contact and bond forces), 0 on their free ones.
  [[nodiscard]] vec3 reaction_sum(const bc::node_group& group) const { return reaction_over(group, 0); }
  /// The same over the bar nodes of `group` (ids of Bars::nodes()), and a bar node's displacement (m).
  [[nodiscard]] vec3 bar_reaction_sum(const bc::node_group& group) const { return reaction_over(group, bars_.dof(0)); }
  [[nodiscard]] real bar_node_displacement(index_t n, int c) const { return u_[bars_.dof(n) + c]; }  ///< Displacement component c (0 x, 1 y, 2 z) of bar node n (m)
  /// The bars' part at the last equilibrium: axial_force(e), bond_force(n) (N; bars.hpp).
  [[nodiscard]] const bar_part<Bars>& bars() const { return bars_; }
  /// Mean displacement (m) of the gridpoints of `group`.
  [[nodiscard]] vec3 mean_displacement(const bc::node_group& group) const {
    vec3 sum = vec3::Zero();
    for (const index_t i : group.nodes) sum += u_.segment<3>(3 * i);
    return sum / static_cast<real>(group.size());
  }
  /// Committed law state of sub-contact i.
  [[nodiscard]] const state_type& state(index_t i) const { return committed_[static_cast<std::size_t>(i)]; }
  /// Relative displacement u_b - u_a (m) of sub-contact i.
  [[nodiscard]] vec3 gap(index_t i) const {
    return u_.segment<3>(3 * contacts_->node_b(i)) - u_.segment<3>(3 * contacts_->node_a(i));
  }
  /// The zones' stiffness (N/m) over all dofs, no supports.
  [[nodiscard]] const sparse_matrix& zone_stiffness() const { return zones_; }
  [[nodiscard]] index_t free_dof_count() const { return static_cast<index_t>(free_dofs_.size()); }  ///< Number of free degrees of freedom solved for
  /// The sparse factorisation of K_sec this model uses.
  [[nodiscard]] factorization factorization_kind() const noexcept { return factor_.kind(); }
  /// Non-zeros of the last Cholesky factor (L), 0 before the first factorisation.
  [[nodiscard]] std::int64_t factor_nonzeros() const { return factor_nonzeros_; }
  [[nodiscard]] const solve_counts& counts() const { return counts_; }  ///< Work done so far (increments, iterations, factorisations, times)

 private:
  using clock = std::chrono::steady_clock;
  [[nodiscard]] static double seconds_since(clock::time_point t) {
    return std::chrono::duration<double>(clock::now() - t).count();
  }

  [[nodiscard]] vec3 reaction_over(const bc::node_group& group, index_t first_dof) const {
    vec3 sum = vec3::Zero();
    for (const index_t i : group.nodes)
      for (int c = 0; c < 3; ++c) {
        const index_t dof = first_dof + 3 * i + c;
        if (free_index_[static_cast<std::size_t>(dof)] < 0) sum[c] -= force_[dof];
      }
    return sum;
  }

  [[nodiscard]] real dissipated(real state_type::*field) const {
    real sum = 0;
    for (index_t i = 0; i < contacts_->size(); ++i) sum += contacts_->area(i) * committed_[static_cast<std::size_t>(i)].*field;
    return sum;
  }

  /// Commits a converged increment or returns to the last equilibrium; counts into r.
  void finish_increment(increment_result& r) {
    counts_.iterations += r.iterations;
    if (r.converged) {
      committed_ = trial_;
      bars_.commit();
      committed_u_ = u_;
      committed_time_ = time_;
      for (index_t i = 0; i < contacts_->size(); ++i) {
        const auto k = static_cast<std::size_t>(i);
        last_opening_[k] = (gap(i) - committed_gap_[k]).dot(normals_[k]);
        committed_gap_[k] = gap(i);
      }
    } else {
      u_ = committed_u_;
      time_ = committed_time_;
      evaluate_forces();
    }
    for (const state_type& s : committed_) {
      const law::contact_status f = Law::status(s);
      r.softening += law::has(f, law::contact_status::softening) || law::has(f, law::contact_status::broken_tension);
      r.broken += law::has(f, law::contact_status::broken_tension);
      r.slipped += law::has(f, law::contact_status::slipped);
    }
    r.advancing = advancing_count_;
    r.reversals = reversal_count_;
  }

  /// K_sec^-1 r on the free components (step 3): the first iteration of an increment factorises
  /// the secants of the last equilibrium (the trial states of step 1 see the prescribed jump
  /// alone, on the supported gridpoints), later ones those of the latest states when asked.
  Eigen::VectorXd secant_step(int iteration, const increment_options& o) {
    if (iteration == 0)
      factorize_secant(o.stiffness_floor, committed_, committed_gap_, controlled_ && o.unload_outside_control);
    else if (o.refactor_each_iteration)
      factorize_secant(o.stiffness_floor, trial_, current_gaps(), controlled_ && o.unload_outside_control);
    const auto timer = clock::now();
    Eigen::VectorXd rhs(static_cast<index_t>(free_dofs_.size()));
    for (std::size_t k = 0; k < free_dofs_.size(); ++k) rhs[static_cast<index_t>(k)] = force_[free_dofs_[k]];
    bool solved = false;
    Eigen::VectorXd du = factor_.solve(rhs, &solved);
    require(solved && du.allFinite(), "quasi_static: the linear solve failed (",
            "K_sec singular or not positive definite) in iteration ", iteration + 1);
    ++counts_.solves;
    counts_.solve_s += seconds_since(timer);
    return du;
  }

  /// An intact sub-contact within this fraction of its tensile strength joins the control set.
  static constexpr real strength_fraction = 1e-3;

  /// Trial states from the committed ones (step 1) and f(u) into force_.
  void evaluate_forces() {
    const auto timer = clock::now();
    force_.noalias() = -(zones_ * u_);
    advancing_count_ = 0;
    reversal_count_ = 0;
    for (index_t i = 0; i < contacts_->size(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      const vec3& n = normals_[k];
      const vec3 step = gap(i) - committed_gap_[k];
      const real du_n = step.dot(n);
      const auto& p = contacts_->subcontact_params(i);
      state_type s = committed_[k];
      Law::update(p, s, du_n, vec3(step - du_n * n), n);
      trial_[k] = s;
      const char advancing = Law::tensile_strength(p, s) < Law::tensile_strength(p, committed_[k]) ? 1 : 0;
      advancing_count_ += advancing;
      if (evaluations_in_increment_ > 0 && advancing != advancing_[k]) ++reversal_count_;
      advancing_[k] = advancing;
      const vec3 f = contacts_->area(i) * (s.sigma_n * n + vec3(s.tau));  // force on node a
      force_.segment<3>(3 * contacts_->node_a(i)) += f;
      force_.segment<3>(3 * contacts_->node_b(i)) -= f;
    }
    bars_.evaluate(u_, force_);
    ++counts_.force_evaluations;
    ++evaluations_in_increment_;
    counts_.force_s += seconds_since(timer);
  }

  /// The increment's end test, the one both kinds of increment use: records the largest free
  /// out-of-balance component of the last force evaluation in r; true when it is within the
  /// tolerance (r.converged) or the iterations are spent.
  [[nodiscard]] bool increment_done(increment_result& r, const increment_options& o) const {
    r.max_residual = max_free_residual();
    r.converged = r.max_residual <= o.force_tolerance;
    return r.converged || r.iterations == o.max_iterations;
  }

  [[nodiscard]] real max_free_residual() const {
    real m = 0;
    for (const index_t dof : free_dofs_) m = std::max(m, std::abs(force_[dof]));
    return m;
  }

  /// u_b - u_a of every sub-contact now (m).
  [[nodiscard]] std::vector<vec3> current_gaps() const {
    std::vector<vec3> g(static_cast<std::size_t>(contacts_->size()));
    for (index_t i = 0; i < contacts_->size(); ++i) g[static_cast<std::size_t>(i)] = gap(i);
    return g;
  }

  /// K_sec of `states` with relative displacements `gaps` on the free components, factorised
  /// unless the secants are those of the last factorisation (step 3).
  void factorize_secant(real floor, const std::vector<state_type>& states, const std::vector<vec3>& gaps,
                        bool unloading = false) {
    const auto timer = clock::now();
    const auto n_c = static_cast<std::size_t>(contacts_->size());
    std::vector<secant_stiffness> secants(n_c);
    for (index_t i = 0; i < contacts_->size(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      const auto& p = contacts_->subcontact_params(i);
      const vec3& d = gaps[k];
      const vec3 slip = d - d.dot(normals_[k]) * normals_[k];
      secant_stiffness s = subcontact_secant<Law>(p, states[k], slip.norm());
      if (unloading && !in_control_[k] && law::has(Law::status(states[k]), law::contact_status::softening))
        s = {Law::normal_stiffness(p), Law::shear_stiffness(p)};
      s.normal = std::max(s.normal, floor * Law::normal_stiffness(p));
      s.shear = std::max(s.shear, floor * Law::shear_stiffness(p));
      secants[k] = s;
    }
    std::vector<real> bar_secants = bars_.secants(&states == &trial_, floor);  // the bars' states of the same pass
    if (factored_ && secants == factored_secants_ && bar_secants == factored_bar_secants_) {
      counts_.assembly_s += seconds_since(timer);
      return;
    }
    std::vector<triplet> all, free_t;
    add_contact_stiffness(*contacts_, normals_, secants, all);
    bars_.add_stiffness(bar_secants, all);
    free_t.reserve(all.size());
    coupling_ = zones_coupling_;
    for (const triplet& e : all) {
      const index_t r = free_index_[static_cast<std::size_t>(e.row())], c = free_index_[static_cast<std::size_t>(e.col())];
      if (r >= 0 && c >= 0)
        free_t.emplace_back(r, c, e.value());
      else if (r >= 0)
        coupling_[r] += e.value() * velocity_[e.col()];
    }
    const auto n_free = static_cast<index_t>(free_dofs_.size());
    sparse_matrix k(n_free, n_free);
    k.setFromTriplets(free_t.begin(), free_t.end());
    k += zones_free_;
    counts_.assembly_s += seconds_since(timer);
    const auto factor_timer = clock::now();
    if (!factored_ || k.nonZeros() != pattern_nonzeros_) {
      factor_.analyze(k);
      pattern_nonzeros_ = k.nonZeros();
      ++counts_.analyses;
    }
    const bool factored = factor_.factorize(k);
    require(factored, "quasi_static: the factorisation of K_sec failed (", k.rows(),
            " free dofs); a part of the model is free to move (no support, every contact broken)?");
    factor_nonzeros_ = factor_.nonzeros();
    factored_ = true;
    factored_secants_ = std::move(secants);
    factored_bar_secants_ = std::move(bar_secants);
    ++counts_.factorizations;
    counts_.factorization_s += seconds_since(factor_timer);
    unit_response_stale_ = true;
  }

  const contact::face_contacts<Law>* contacts_ = nullptr;
  bar_part<Bars> bars_;
  sparse_matrix zones_;       ///< K of the zones, all dofs (N/m)
  sparse_matrix zones_free_;  ///< ... on the free dofs
  std::vector<index_t> free_index_;  ///< per dof: its index among the free dofs, -1 if prescribed
  std::vector<index_t> free_dofs_;   ///< the free dofs, increasing
  Eigen::VectorXd velocity_;         ///< per dof: prescribed velocity (m/s), 0 on free dofs
  std::vector<vec3> normals_;        ///< per sub-contact: unit normal A -> B, fixed
  std::vector<state_type> committed_, trial_;
  std::vector<vec3> committed_gap_;  ///< per sub-contact: u_b - u_a at the last equilibrium (m)
  std::vector<char> in_control_;     ///< per sub-contact: in the control set of the present controlled increment
  bool controlled_ = false;          ///< a controlled increment is under way
  std::vector<real> last_opening_;   ///< per sub-contact: normal opening in the last converged increment (m)
  std::vector<char> advancing_;      ///< per sub-contact: the last iterate lowers its tensile strength
  index_t advancing_count_ = 0, reversal_count_ = 0;
  int evaluations_in_increment_ = 0;
  Eigen::VectorXd u_, committed_u_;  ///< displacements (m), dof 3 i + c
  real time_ = 0, committed_time_ = 0;  ///< pseudo-time lambda (s): prescribed displacement / velocity
  Eigen::VectorXd zones_coupling_, coupling_;  ///< K_fp v on the free dofs: zones, zones + factorised contacts (N/s)
  Eigen::VectorXd unit_response_;    ///< -K_sec^-1 K_fp v on the free dofs (m/s)
  bool unit_response_stale_ = true;  ///< unit_response_ is not that of the present factor
  Eigen::VectorXd force_;            ///< f(u) of the last evaluation (N)
  sparse_factor factor_;
  std::vector<secant_stiffness> factored_secants_;
  std::vector<real> factored_bar_secants_;
  bool factored_ = false;
  index_t pattern_nonzeros_ = 0;
  std::int64_t factor_nonzeros_ = 0;
  solve_counts counts_;
};

}  // namespace tessera::implicit
