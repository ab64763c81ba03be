#pragma once
// tessera::solver<Blocks, Contacts, Reinforcement, Integrator, Checker> — the composed model of a
// scene: blocks (deformable zones or rigid bodies) on one node_set of gridpoints, a contact set
// (contact::ContactSet: face_contacts<Law> for a tessellation's bonded faces, or a detecting set),
// optional embedded reinforcement, boundary conditions, the stable time step, energy books and a
// step checker. Each policy is checked by its concept; what a scene does not use is not compiled.
//
// One step (docs/architecture.md, study eq. 1):
//   1. zero gridpoint and bar-node forces (gridpoints start from their weights under gravity and
//      the applied forces, e.g. of a contact::rigid_platen; rigid blocks add their weight at the
//      centroid in step 5)
//   2. blocks: zone forces from the current displacements            -> gridpoints.force
//   3. contacts: law update from du = (v_b - v_a) dt, forces           -> gridpoints.force
//   4. reinforcement: axial + bond forces (zone stress = confinement)  -> bar nodes, gridpoints
//      (steps 2-4 fused into two parallel loops where the policies allow: docs/architecture.md)
//   5-6. blocks.advance: (rigid: reduce to block force/moment) central differences with damping,
//      prescribed components and reactions; then bar nodes
//   7. energy increments, time, step checker every `interval` steps
// Velocities live at half steps; displacements at full steps.
//
// The solver's other jobs, each in its own header: the time step, how it is chosen and chosen
// again (by the supports of rigid blocks before the first step, after a contact rebuild when dt
// is automatic), in time_step.hpp; options, run_result and phase_times in options.hpp; the energy
// books and the out-of-balance in detail/energy_books.hpp. Bases of the solver (CRTP), whose
// members are the solver's: supports, velocities and selections by block (supports.hpp), forces
// applied from outside the model (applied_forces.hpp), run and run_until (run.hpp), a step run by
// pieces from outside (external_step.hpp: a run split over MPI ranks).
//
// Thread safety: one solver, one driving thread; its loops are parallel and bit-identical for
// any thread count. step() allocates nothing.

#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

#include "../blocks/concepts.hpp"
#include "../contact/concepts.hpp"
#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/parallel.hpp"
#include "../core/thread_governor.hpp"
#include "../core/types.hpp"
#include "../geometry/block_mesh.hpp"
#include "../geometry/tessellation.hpp"
#include "../integrator/central_difference.hpp"
#include "../integrator/concepts.hpp"
#include "../integrator/damping.hpp"
#include "../integrator/timestep.hpp"
#include "../reinforcement/concepts.hpp"
#include "../reinforcement/none.hpp"
#include "applied_forces.hpp"
#include "balance.hpp"
#include "boundary.hpp"
#include "detail/energy_books.hpp"
#include "detail/first_step_checks.hpp"
#include "energy.hpp"
#include "external_step.hpp"
#include "options.hpp"
#include "run.hpp"
#include "step_checker.hpp"
#include "supports.hpp"
#include "time_step.hpp"

namespace tessera {

/// The composed model of a scene (file comment): blocks, a contact set, reinforcement, an integrator and a step checker, each a policy checked by its concept
template <blocks::BlockModel Blocks, contact::ContactSet Contacts, reinforcement::Reinforcement Reinforcement = reinforcement::none,
          integrator::Integrator Integrator = integrator::central_difference<integrator::local_damping>,
          class Checker = checks::default_step_checker>
class solver : public solver_supports<solver<Blocks, Contacts, Reinforcement, Integrator, Checker>>,
               public solver_applied_forces<solver<Blocks, Contacts, Reinforcement, Integrator, Checker>>,
               public solver_runs<solver<Blocks, Contacts, Reinforcement, Integrator, Checker>>,
               public solver_external_steps<solver<Blocks, Contacts, Reinforcement, Integrator, Checker>> {
  // The supports, the applied forces and the runs reach the state through the solver.
  friend class solver_supports<solver>;
  friend class solver_applied_forces<solver>;
  friend class solver_runs<solver>;
  friend class solver_external_steps<solver>;

 public:
  using blocks_type = Blocks;  ///< the block model
  using contact_set_type = Contacts;  ///< the contact set
  using law_type = typename Contacts::law_type;  ///< the contact law
  using reinforcement_type = Reinforcement;  ///< the reinforcement (reinforcement::none without bars)
  using integrator_type = Integrator;  ///< the integrator with its damping
  using checker_type = Checker;  ///< the step checker

  /// Builds the model: blocks (validating their material), the contact set (validating the law
  /// parameters of every material pair: `contact_params` is Contacts::params, for face_contacts a
  /// contact::material_table, which a plain law params struct converts to),
  /// reinforcement, nodal stiffness bounds, mass scaling and the time step. Throws
  /// invalid_input / geometry_error naming the offending entity.
  solver(const geometry::tessellation& tess, const geometry::block_mesh& mesh, const typename Blocks::params& block_params,
         const typename Contacts::params& contact_params, const typename Reinforcement::params& reinforcement_params = {},
         const solver_options& options = {})
      : solver(tess, mesh, block_materials{{block_params}}, contact_params, reinforcement_params, options) {}

  /// Block parameters per material id (geometry::block_mesh::block_material): block b takes
  /// list[mesh.material(b)]. An aggregate, so `{2400}` never converts to it by accident.
  struct block_materials {
    std::vector<typename Blocks::params> list;  ///< one params per material id
  };
  /// The same with one block material per material id.
  solver(const geometry::tessellation& tess, const geometry::block_mesh& mesh, const block_materials& materials,
         const typename Contacts::params& contact_params, const typename Reinforcement::params& reinforcement_params = {},
         const solver_options& options = {});

  /// Kinetic energy of blocks and bar nodes (J, half-step velocities, scaled masses), as in
  /// energies().kinetic, without evaluating the contact energies.
  [[nodiscard]] real kinetic_energy() const;

  /// Acceleration of gravity g (m/s^2, world; e.g. (0, 0, -9.81)), a body force on every block:
  /// the lumped weights m0_i g on the gridpoints of deformable blocks, each rigid block's weight at
  /// its centroid (blocks::rigid::set_gravity); m0 the masses before mass scaling. Its work enters
  /// the energy balance (energy_balance::gravity_work). Throws invalid_input for a non-finite g.
  void set_gravity(const vec3& g);
  [[nodiscard]] const vec3& gravity() const { return gravity_; }  ///< Acceleration of gravity (m/s^2), zero until set_gravity
  /// Deformable blocks: each gridpoint's weight m0_i g (N), where each step's forces start; empty without gravity.
  [[nodiscard]] const soa3& gravity_forces() const { return gravity_force_; }

  /// Advances the model by one time step (see the file comment). One function on purpose (about
  /// 85 lines): the step order of docs/architecture.md, with its fused parallel region, in one place.
  void step();

  // ---- accessors ----
  [[nodiscard]] node_set& gridpoints() { return gridpoints_; }  ///< The gridpoints: positions, velocities, forces, constraints, reactions
  [[nodiscard]] const node_set& gridpoints() const { return gridpoints_; }  ///< The gridpoints
  [[nodiscard]] node_set& bar_nodes() { return reinforcement_.nodes(); }  ///< The bar nodes (empty without reinforcement)
  [[nodiscard]] const node_set& bar_nodes() const { return reinforcement_.nodes(); }  ///< The bar nodes
  [[nodiscard]] const contact_set_type& contacts() const { return contacts_; }  ///< The contact set
  [[nodiscard]] const Blocks& blocks() const { return blocks_; }  ///< The block model
  /// The block model, e.g. for initial conditions (blocks::rigid::set_velocity).
  [[nodiscard]] Blocks& blocks() { return blocks_; }
  [[nodiscard]] const Reinforcement& reinforcement() const { return reinforcement_; }  ///< The reinforcement
  [[nodiscard]] Reinforcement& reinforcement() { return reinforcement_; }  ///< The reinforcement
  [[nodiscard]] index_t gridpoint_block(index_t i) const { return gridpoint_block_[static_cast<std::size_t>(i)]; }  ///< The block of gridpoint i (no bounds check)
  [[nodiscard]] real time() const { return time_; }  ///< Simulated time since the solver was built (s)
  [[nodiscard]] real dt() const { return dt_; }  ///< The step the next step() takes (s)
  [[nodiscard]] std::int64_t step_count() const { return step_; }  ///< Steps taken since the solver was built
  /// Critical step min 2 sqrt(m/(a k)) (after mass scaling; a = damping's stiffness amplification)
  /// and its limiting node.
  [[nodiscard]] const integrator::critical_step& critical_step() const { return critical_; }
  [[nodiscard]] const integrator::mass_scaling_report& mass_scaling() const { return scaling_; }  ///< What mass scaling did (empty without it)
  /// Factor a on the nodal stiffness in the stable step (1 + gamma with local damping, else 1).
  [[nodiscard]] real stiffness_amplification() const { return integrator_.stiffness_amplification(); }
  [[nodiscard]] const solver_options& options() const { return options_; }  ///< The options the solver was built with (mass_scaling_ratio resolved into mass_scaling_dt)
  /// Time spent in each phase of the steps so far (see phase_times).
  [[nodiscard]] const phase_times& phases() const { return phases_; }

  /// Unbalanced force of the last step over free components (solver/balance.hpp): of the
  /// gridpoints (deformable blocks) or of the blocks' translations (rigid blocks: the block force
  /// with the weight, moments left out), then of the bar nodes (max_node counts on from the
  /// gridpoints or blocks). O(nodes); the same for any thread count.
  [[nodiscard]] out_of_balance unbalanced_force() const;

  /// All energy terms now (J); O(zones + sub-contacts + nodes).
  [[nodiscard]] energy_balance energies() const;

  /// Saves or loads the solver's evolving state through a checkpoint archive (io/checkpoint.hpp:
  /// io::save_checkpoint, io::load_checkpoint): step, time and the energy accounts, then the
  /// gridpoints, blocks, contacts and reinforcement, each by its own checkpoint(), and the forces
  /// applied from outside (a platen's) where there are any. The time step must be the one the
  /// solver was built with (a model built with other options is refused).
  /// Phase timings are not state and restart from zero.
  template <class Archive>
  void checkpoint(Archive& ar) {
    static_assert(requires { blocks_.checkpoint(ar); }, "this block model has no checkpoint(Archive&)");
    static_assert(requires { contacts_.checkpoint(ar); }, "this contact set has no checkpoint(Archive&)");
    static_assert(requires { reinforcement_.checkpoint(ar); }, "this reinforcement has no checkpoint(Archive&)");
    if constexpr (Blocks::is_rigid)
      if (step_ == 0) choose_time_step(true);  // the step the first step would take (solver/time_step.hpp)
    // A dt that follows the contact rebuilds (solver/time_step.hpp) is state: saved and loaded. Any
    // other is the model's own and must match.
    if (rebuilds_choose_dt && dt_follows_rebuilds())
      ar.scalar("solver/dt", dt_);
    else
      ar.same("solver/dt", dt_);
    ar.scalar("solver/step", step_);
    ar.scalar("solver/time", time_);
    ar.scalar("solver/boundary_work", boundary_work_);
    ar.scalar("solver/damping_dissipated", damping_dissipated_);
    ar.scalar("solver/gravity_work", gravity_work_);
    ar.scalar("solver/applied_work", applied_work_);
    ar.scalar("solver/initial_energy", initial_energy_);
    // Forces applied from outside the model (rigid platens, applied_forces.hpp): those written for
    // the next step and those the last step applied, whose work is booked at the next step. Only
    // where the model has applied gridpoints, so a file of a model without them keeps its records.
    if (!applied_nodes_.empty()) {
      ar.same("solver/applied_gridpoints", static_cast<std::int64_t>(applied_nodes_.size()));
      ar.matrix("solver/applied_force", applied_force_);
      ar.matrix("solver/applied_previous", applied_previous_);
      ar.scalar("solver/applied_active", applied_active_);
    }
    gridpoints_.checkpoint(ar, "gridpoints");
    blocks_.checkpoint(ar);
    contacts_.checkpoint(ar);
    reinforcement_.checkpoint(ar);
    // The loaded dt is the one chosen at the file's last rebuild.
    if constexpr (requires { contacts_.rebuild_count(); })
      if (ar.loading()) bound_rebuilds_ = contacts_.rebuild_count();
  }

  /// Recomputes nodal stiffness bounds, mass scaling and dt (after changing options or masses;
  /// rigid blocks: after freeing a block that was fully prescribed when dt was chosen). Throws
  /// invalid_input for an options.dt above the stable limit.
  void compute_time_step() { compute_time_step_refusing(true); }

 private:
  /// Rigid blocks on a contact set that rebuilds: dt is chosen again after each rebuild when
  /// automatic (solver/time_step.hpp).
  static constexpr bool rebuilds_choose_dt = Blocks::is_rigid && requires(const contact_set_type& c) {
    c.rebuild_count();
  };

  /// compute_time_step; with refuse_user_dt false an options.dt above the limit is kept for now
  /// (rigid blocks at construction: the supports that raise the limit come later).
  void compute_time_step_refusing(bool refuse_user_dt) {
    assemble_stiffness_bounds();
    detail::scale_masses_to_target(blocks_, gridpoints_, reinforcement_, integrator_.stiffness_amplification(), options_,
                                   scaling_, scaled_);
    choose_time_step(refuse_user_dt);
  }
  [[nodiscard]] bool dt_follows_rebuilds() const { return detail::dt_follows_rebuilds(options_); }
  /// The nodal stiffness bounds (solver/time_step.hpp), and the rebuild they hold for.
  void assemble_stiffness_bounds() {
    detail::assemble_stiffness_bounds(gridpoints_, blocks_, contacts_, reinforcement_, applied_stiffness_,
                                      dt_follows_rebuilds());
    if constexpr (requires { contacts_.rebuild_count(); }) bound_rebuilds_ = contacts_.rebuild_count();
  }
  /// After a contact rebuild inside step(): with an automatic dt, the bounds of the contacts now
  /// present and dt from them (O(gridpoints); allocates only when more blocks are fully
  /// prescribed than at the last choice, blocks::rigid::record_step_bound).
  void bound_after_rebuild() {
    if constexpr (requires { contacts_.rebuild_count(); }) bound_rebuilds_ = contacts_.rebuild_count();
    if (!dt_follows_rebuilds()) return;
    assemble_stiffness_bounds();
    choose_time_step(true);
  }
  /// critical_ and dt_ from the bounds and masses in place (solver/time_step.hpp).
  void choose_time_step(bool refuse_user_dt) {
    detail::choose_time_step(blocks_, gridpoints_, reinforcement_, integrator_.stiffness_amplification(), options_,
                             gridpoint_block_, refuse_user_dt, critical_, dt_);
  }
  /// After a support call (solver/supports.hpp): rigid blocks choose the step again while no step
  /// was taken (a block fixed now may no longer bound it); an options.dt above the limit is
  /// refused at the first step.
  void supports_changed() {
    if constexpr (Blocks::is_rigid)
      if (step_ == 0) choose_time_step(false);
  }

  /// Step 7: energy increments, time, step checker.
  /// The zone stresses the bars read for their confinement: the block model's rows where it
  /// offers them (deformable: the bars' host zones are formed by the zone tasks), else its
  /// zone_stress().
  [[nodiscard]] decltype(auto) stress_for_bars() const {
    if constexpr (requires { blocks_.zone_stress_rows(); })
      return blocks_.zone_stress_rows();
    else
      return (blocks_.zone_stress());
  }

  void finish_step(const integrator::step_work& work) {
    boundary_work_ += work.boundary;
    damping_dissipated_ += work.damping;
    if (gravity_ != vec3::Zero()) {
      // Weight x half-step velocity x dt: the exact work of a constant force over the step.
      if constexpr (Blocks::is_rigid) {
        gravity_work_ += blocks_.gravity_power(gridpoints_) * dt_;
      } else {
        gravity_work_ += detail::gravity_work_of_step(gravity_force_, gridpoints_, dt_);
      }
    }
    note_peak_work();
    ++step_;
    time_ += dt_;
    if constexpr (Checker::enabled)
      if (step_ % checker_.interval == 0) checker_.check(*this);
  }

  /// energy_balance::peak_work: the largest sum of the works' magnitudes after any step (J).
  void note_peak_work() {
    peak_work_ = std::max(peak_work_, std::abs(boundary_work_) + std::abs(gravity_work_) + std::abs(applied_work_));
  }
  /// The work of the last step's applied forces (solver/applied_forces.hpp), F(t) those now written.
  [[nodiscard]] real applied_work_of_last_step() const {
    return detail::applied_work_of_step(applied_nodes_, applied_previous_, applied_force_, gridpoints_, dt_);
  }
  [[nodiscard]] real stored_and_kinetic() const {
    return detail::stored_and_kinetic(blocks_, gridpoints_, contacts_, reinforcement_);
  }

  solver_options options_;
  Blocks blocks_;
  node_set gridpoints_;
  std::vector<index_t> gridpoint_block_;
  std::vector<index_t> block_gridpoint_offsets_;  ///< CSR of the mesh: gridpoints of block b
  contact_set_type contacts_;
  Reinforcement reinforcement_;
  Integrator integrator_{};
  Checker checker_{};
  real dt_ = 0;
  index_t bound_rebuilds_ = 0;  ///< the contact set's rebuild count when the bounds were assembled
  real time_ = 0;
  std::int64_t step_ = 0;
  real boundary_work_ = 0;
  real damping_dissipated_ = 0;
  real gravity_work_ = 0;
  real peak_work_ = 0;  ///< energy_balance::peak_work (J), not checkpointed
  real initial_energy_ = 0;
  vec3 gravity_ = vec3::Zero();
  soa3 gravity_force_;               ///< m0_i g per gridpoint (N), deformable blocks
  std::vector<index_t> applied_nodes_;   ///< gridpoints with applied forces, increasing
  bool applied_active_ = false;        ///< the last step applied them (its work is pending)
  soa3 applied_force_;                 ///< forces from outside the model per gridpoint (N)
  soa3 applied_previous_;              ///< those the last step applied, per applied_nodes_ entry
  Eigen::VectorXd applied_stiffness_;  ///< their springs' stiffness per gridpoint (N/m)
  real applied_work_ = 0;
  Eigen::VectorXd weight_mass_;      ///< gridpoint masses before mass scaling (kg), deformable blocks
  integrator::critical_step critical_;
  phase_times phases_;
  integrator::mass_scaling_report scaling_;
  bool scaled_ = false;  ///< masses scaled once (scaling_ holds that pass)
};

}  // namespace tessera

// The members declared above and defined out of the class (not inline: tessera::instances).
#include "detail/solver_members.hpp"
