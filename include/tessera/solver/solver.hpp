#pragma once
// tessera::solver<Blocks, Contacts, Reinforcement, Integrator, Checker> — the composed model of a
// scene: blocks (deformable zones or rigid bodies) on one node_set of gridpoints, a contact set
// (contact::ContactSet: contact::face_contacts<Law> for the bonded faces of a tessellation, or a
// detecting set) that evaluates its contact law per sub-contact, optional embedded reinforcement, boundary
// conditions, the stable time step, energy bookkeeping and a step checker. Each policy is
// checked by its concept, and what a scene does not use is not compiled in (reinforcement::none
// removes every bar call, no_step_checker the checks).
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
// Time step (integrator/timestep.hpp): nodal stiffness bounds from blocks, contacts and bonds,
// then optional mass scaling to options.mass_scaling_dt (or to the step that adds
// options.mass_scaling_ratio times the original mass), then dt = options.dt if given (it must
// not exceed safety x the critical step, else invalid_input naming the limiting node and block),
// else the mass-scaling target, else safety x critical step.
// Rigid blocks: a fully prescribed block does not bound the step (blocks/rigid.hpp), and the
// supports are set after construction, so the step is chosen again, from the supports as they
// stand, by every support call of the solver (fix, prescribe_velocity, fix_block(s),
// prescribe_block_velocity) before the first step, and once more at the first step (which also
// sees constraints written straight into gridpoints()). Then dt stays: it never changes silently
// once the run has started. An options.dt above the limit is refused then (invalid_input from the
// first step, or from checkpoint), not at construction, since fixing a block raises the limit;
// a block that was left out of the bound and is freed during the run is refused before the next
// step (blocks::rigid::check_step_bound; call compute_time_step() to choose a step that bounds it).
// A contact set whose bound covers only the contacts present until its next rebuild
// (contact::detected_contacts with rigid blocks, params::step_bound = present_contacts) changes
// its bound at every rebuild: when dt is automatic (no options.dt, no mass scaling) the solver
// then assembles the nodal bounds again and chooses dt again, in the step whose contact update
// rebuilt, after that update (which used the step that moved the blocks to where they are) and
// before the blocks are integrated with the new dt. The kick of that step is the variable-step
// central difference, v(t + dt'/2) = v(t - dt/2) + a(t) (dt + dt') / 2, then u(t + dt') =
// u(t) + v(t + dt'/2) dt' (blocks::rigid::advance with kick_dt; second order, and the kinetic
// energy change equals the work F.v (dt + dt')/2 the books take); each step is stable for the
// contacts present while it is used. Time and gravity work are booked with the dt of each step,
// boundary work and damping with the kick's; a checkpoint saves dt, so a restart continues with
// the same steps. With a given options.dt or mass scaling the contact set gives the bound of
// every contact that can ever appear (add_whole_surface_stiffness_bounds), so the check of
// options.dt holds for the whole run and dt never changes, as above.
//
// Thread safety: one solver is driven by one thread; its loops are parallel and deterministic
// (bit-identical for any thread count). step() allocates nothing.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <utility>
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
#include "balance.hpp"
#include "boundary.hpp"
#include "energy.hpp"
#include "step_checker.hpp"

namespace tessera {

/// Time spent in each phase of the step since the solver was built (s). zones and contacts are
/// summed over threads (on one thread their wall time; on several the thread time, so
/// zones / (zone count x steps) is the per-core cost of a zone-step), the others are wall time:
/// bars (their axial and bond forces), integration (gather of the contact and bar host forces
/// and the integrator; on the unfused path the integrator alone), recorders (the observers of run
/// and run_until). A few clock reads per step and thread (about 0.1 us).
struct phase_times {
  double zones = 0;
  double contacts = 0;
  double bars = 0;
  double integration = 0;
  double recorders = 0;
};

/// What solver::run_until did: the steps it took, why it stopped and whether max_steps ran out
/// first. Converts to the step count, so `std::int64_t n = s.run_until(...)` still reads it.
struct run_result {
  std::int64_t steps = 0;      ///< steps taken by this call
  std::string reason;          ///< the stop condition's reason() (e.g. "t - t0 = 0.5 s >= 0.5 s"), or "max_steps = N reached"
  bool hit_max_steps = false;  ///< true when max_steps ran out before the condition held
  operator std::int64_t() const { return steps; }  // NOLINT(google-explicit-constructor): old callers read the count
};

/// Run-time options of a solver (SI).
struct solver_options {
  real safety = integrator::default_safety;  ///< dt = safety x min_i 2 sqrt(m_i / k_i), in (0, 1]
  real dt = 0;                 ///< user time step (s); 0 = automatic. Above the stable limit -> invalid_input
  real mass_scaling_dt = 0;    ///< > 0: raise nodal masses so this step (s) is stable, and use it
  /// > 0 (instead of mass_scaling_dt): scale masses to the step at which the added mass is this
  /// multiple of the original mass (integrator::step_for_added_mass; deformable blocks). Resolved
  /// into mass_scaling_dt when the solver is built (options().mass_scaling_dt then holds the step).
  real mass_scaling_ratio = 0;
  real damping_gamma = 0.8;    ///< local damping constant (ignored by no_damping)
  int threads = 0;             ///< OpenMP threads; 0 = leave the current setting
  index_t check_interval = 100;  ///< steps between step-checker passes
};

template <blocks::BlockModel Blocks, contact::ContactSet Contacts, reinforcement::Reinforcement Reinforcement = reinforcement::none,
          integrator::Integrator Integrator = integrator::central_difference<integrator::local_damping>,
          class Checker = checks::default_step_checker>
class solver {
 public:
  using blocks_type = Blocks;
  using contact_set_type = Contacts;
  using law_type = typename Contacts::law_type;
  using reinforcement_type = Reinforcement;
  using integrator_type = Integrator;
  using checker_type = Checker;

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
    std::vector<typename Blocks::params> list;
  };
  /// The same with one block material per material id.
  solver(const geometry::tessellation& tess, const geometry::block_mesh& mesh, const block_materials& materials,
         const typename Contacts::params& contact_params, const typename Reinforcement::params& reinforcement_params = {},
         const solver_options& options = {})
      : options_(options) {
    require(options.safety > 0 && options.safety <= 1, "solver: safety factor = ", options.safety,
            " must lie in (0, 1]");
    require_non_negative(options.dt, "solver: user time step dt (s)");
    require_non_negative(options.mass_scaling_dt, "solver: mass-scaling target time step (s)");
    require(std::isfinite(options.mass_scaling_ratio) && options.mass_scaling_ratio >= 0,
            "solver: mass-scaling added-mass ratio = ", options.mass_scaling_ratio, " must be finite and >= 0");
    require(options.mass_scaling_ratio == 0 || options.mass_scaling_dt == 0,
            "solver: give a mass-scaling time step (", options.mass_scaling_dt, " s) or an added-mass ratio (",
            options.mass_scaling_ratio, "), not both");
    require(options.mass_scaling_ratio == 0 || !Blocks::is_rigid,
            "solver: an added-mass ratio (", options.mass_scaling_ratio,
            ") is for deformable blocks; give rigid blocks a mass-scaling time step");
    require(options.check_interval >= 1, "solver: check_interval = ", options.check_interval, " must be >= 1");
    if (options.threads > 0) set_threads(options.threads);
    if constexpr (requires(typename Integrator::damping_type d) { d.gamma; }) {
      typename Integrator::damping_type d;
      d.gamma = options.damping_gamma;
      d.validate();
      integrator_ = Integrator(d);
    }
    checker_.interval = options.check_interval;

    blocks_.build(tess, mesh, std::span<const typename Blocks::params>(materials.list), gridpoints_);
    if constexpr (!Blocks::is_rigid) weight_mass_ = gridpoints_.mass;  // before any mass scaling
    gridpoint_block_ = mesh.gridpoint_block;
    block_gridpoint_offsets_ = mesh.block_gridpoint_offsets;
    contacts_ = contact_set_type(tess, mesh, contact_params);
    // A contact set that places its points by block kind (contact::detected_contacts) must be
    // told which kind it serves.
    if constexpr (requires { contacts_.deformable_blocks(); })
      require(contacts_.deformable_blocks() == !Blocks::is_rigid, "solver: the contact set's deformable_blocks = ",
              contacts_.deformable_blocks(), " does not match the block model (", Blocks::is_rigid ? "rigid" : "deformable",
              "); set contact params deformable_blocks = ", !Blocks::is_rigid);
    if constexpr (Reinforcement::enabled) {
      reinforcement_.build(reinforcement_params, mesh, gridpoints_);
      // The zones whose stress the bars read every step get it formed inside the zone tasks.
      if constexpr (requires { blocks_.watch_zone_stress(reinforcement_.host_zones()); })
        blocks_.watch_zone_stress(reinforcement_.host_zones());
    }
    if constexpr (Blocks::is_rigid)
      compute_time_step_refusing(false);  // the supports come later: options.dt is checked at the first step
    else
      compute_time_step();
  }

  // ---- boundary conditions on the gridpoints (bar nodes: use bc:: on bar_nodes()) ----
  /// Gridpoints on the plane X[axis] = value (reference configuration, tolerance tol m).
  [[nodiscard]] bc::node_group gridpoints_on_plane(int axis, real value, real tol) const {
    return bc::nodes_on_plane(gridpoints_, axis, value, tol);
  }
  /// Fixes components c of the gridpoints of g (bc::fix); rigid blocks: chooses the step again
  /// before the first step (file comment).
  void fix(const bc::node_group& g, bc::components c = bc::components::xyz) {
    bc::fix(gridpoints_, g, c);
    supports_changed();
  }
  /// Prescribes velocity v (m/s) on components c of the gridpoints of g (bc::prescribe_velocity);
  /// rigid blocks: chooses the step again before the first step (file comment).
  void prescribe_velocity(const bc::node_group& g, const vec3& v, bc::components c = bc::components::xyz) {
    bc::prescribe_velocity(gridpoints_, g, v, c);
    supports_changed();
  }

  // ---- supports, velocities and selections by block (rigid and deformable blocks) ----
  // A block is held through its gridpoints, so the reactions land where recorders::reaction_sum
  // reads them: on rigid blocks a prescribed component on any gridpoint prescribes the block's
  // translation component and holds its rotation (blocks/rigid.hpp), and the block's reaction is
  // shared among the gridpoints that prescribe it; on deformable blocks every gridpoint is held.
  // Every function below refuses a bad block id or a non-finite value before changing anything.

  /// Number of blocks.
  [[nodiscard]] index_t block_count() const { return blocks_.block_count(); }
  /// All gridpoints of block b (node group named "block b"). Throws invalid_input for a bad id.
  [[nodiscard]] bc::node_group gridpoints_of_block(index_t b) const {
    require_block(b, "gridpoints_of_block");
    bc::node_group g{{}, detail::concat("block ", b)};
    for (index_t i = block_first(b); i < block_end(b); ++i) g.nodes.push_back(i);
    return g;
  }
  /// All gridpoints of the listed blocks (increasing; a block listed twice counts once). Throws
  /// invalid_input for an empty list or a bad id.
  [[nodiscard]] bc::node_group gridpoints_of_blocks(const std::vector<index_t>& list) const {
    require(!list.empty(), "solver: gridpoints_of_blocks got an empty block list");
    for (index_t b : list) require_block(b, "gridpoints_of_blocks");
    std::vector<index_t> sorted = list;
    std::sort(sorted.begin(), sorted.end());
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    bc::node_group g{{}, detail::concat(sorted.size(), " blocks (", sorted.front(), " ... ", sorted.back(), ")")};
    for (index_t b : sorted)
      for (index_t i = block_first(b); i < block_end(b); ++i) g.nodes.push_back(i);
    return g;
  }
  /// Blocks whose REFERENCE geometry reaches the plane X[axis] = value (m) within tol (m): the
  /// extent [min, max] of the block's gridpoints along axis meets [value - tol, value + tol] (a
  /// face, edge or vertex on the plane, or the block cut by it). Increasing ids. Throws
  /// invalid_input for a bad axis, a non-finite value, a negative tol or an empty selection.
  [[nodiscard]] std::vector<index_t> blocks_on_plane(int axis, real value, real tol) const {
    require_plane(axis, value, tol, "blocks_on_plane");
    std::vector<index_t> out;
    for (index_t b = 0; b < block_count(); ++b) {
      const auto [lo, hi] = block_extent(b, axis);
      if (lo - tol <= value && value <= hi + tol) out.push_back(b);
    }
    require(!out.empty(), "solver: blocks_on_plane selects no block: none of the ", block_count(),
            " blocks reaches the plane ", "xyz"[axis], " = ", value, " m (tol ", tol, " m)");
    return out;
  }
  /// Blocks whose REFERENCE geometry lies wholly at X[axis] <= value + tol (m). Increasing ids.
  /// Throws invalid_input for a bad axis, a non-finite value, a negative tol or an empty selection.
  [[nodiscard]] std::vector<index_t> blocks_below(int axis, real value, real tol = 0) const {
    require_plane(axis, value, tol, "blocks_below");
    std::vector<index_t> out;
    for (index_t b = 0; b < block_count(); ++b)
      if (block_extent(b, axis).second <= value + tol) out.push_back(b);
    require(!out.empty(), "solver: blocks_below selects no block: none of the ", block_count(), " blocks lies below ",
            "xyz"[axis], " = ", value, " m (tol ", tol, " m)");
    return out;
  }

  /// Holds block b: zero velocity in all three components on every gridpoint of the block (rigid:
  /// translations and rotations held; deformable: every gridpoint fixed). The support's force on
  /// the block is recorders::reaction_sum(gridpoints(), gridpoints_of_block(b)) (N). Throws
  /// invalid_input for a bad id or a component already prescribed with another velocity.
  void fix_block(index_t b) {
    require_block(b, "fix_block");  // named here, not as the prescribe_block_velocity it calls
    prescribe_block_velocity(b, vec3::Zero(), bc::components::xyz);
  }
  /// fix_block for each listed block, all or none (validated first).
  void fix_blocks(const std::vector<index_t>& list) {
    bc::fix(gridpoints_, gridpoints_of_blocks(list));
    supports_changed();
  }
  /// Prescribes the translation velocity v (m/s, world) on components c of block b, on every
  /// gridpoint of it: a rigid block translates at v in those components and its rotations are held
  /// (free components stay free); a deformable block's gridpoints all move at v in them. Throws
  /// invalid_input for a bad id, a non-finite v, or a component already prescribed otherwise.
  void prescribe_block_velocity(index_t b, const vec3& v, bc::components c = bc::components::xyz) {
    require_block(b, "prescribe_block_velocity");
    require(v.allFinite(), "solver: prescribe_block_velocity: velocity (", v.transpose(), ") m/s of block ", b,
            " is not finite");
    bc::prescribe_velocity(gridpoints_, gridpoints_of_block(b), v, c);
    supports_changed();
  }
  /// Initial condition: gives block b the rigid velocity field v + omega x (x - c) (v in m/s at
  /// the centroid c, omega in rad/s, world; x the current positions), as the half-step velocities
  /// of the next step. Rigid blocks: blocks::rigid::set_velocity. Deformable blocks: every gridpoint
  /// of the block, c the mass-weighted mean of their current positions (unscaled masses).
  /// Prescribed components are overwritten by their prescription at the next step. Throws
  /// invalid_input for a bad id or a non-finite vector.
  void set_block_velocity(index_t b, const vec3& v, const vec3& omega = vec3::Zero()) {
    require_block(b, "set_block_velocity");
    require(v.allFinite() && omega.allFinite(), "solver: set_block_velocity: velocity (", v.transpose(),
            ") m/s or angular velocity (", omega.transpose(), ") rad/s of block ", b, " is not finite");
    if constexpr (Blocks::is_rigid) {
      blocks_.set_velocity(b, v, omega, gridpoints_);
    } else {
      vec3 c = vec3::Zero();
      real m = 0;
      for (index_t i = block_first(b); i < block_end(b); ++i) {
        c += weight_mass_[i] * current_position(i);
        m += weight_mass_[i];
      }
      c /= m;
      for (index_t i = block_first(b); i < block_end(b); ++i)
        gridpoints_.velocity.row(i) = (v + omega.cross(current_position(i) - c)).transpose();
    }
  }
  /// Displacement of block b (m): rigid, its centroid's u_c; deformable, the mass-weighted mean of
  /// its gridpoints' displacements (unscaled masses, so mass scaling does not move it).
  [[nodiscard]] vec3 block_displacement(index_t b) const {
    require_block(b, "block_displacement");
    if constexpr (Blocks::is_rigid)
      return blocks_.displacement(b);
    else
      return block_mean(b, gridpoints_.displacement);
  }
  /// Velocity of block b (m/s, half step): rigid, its centroid's v; deformable, the mass-weighted
  /// mean of its gridpoints' velocities (momentum over mass, unscaled masses).
  [[nodiscard]] vec3 block_velocity(index_t b) const {
    require_block(b, "block_velocity");
    if constexpr (Blocks::is_rigid)
      return blocks_.velocity(b);
    else
      return block_mean(b, gridpoints_.velocity);
  }
  /// Kinetic energy of blocks and bar nodes (J, half-step velocities, scaled masses), as in
  /// energies().kinetic, without evaluating the contact energies.
  [[nodiscard]] real kinetic_energy() const {
    real e = blocks_.kinetic_energy(gridpoints_);
    if constexpr (Reinforcement::enabled) {
      const node_set& bars = reinforcement_.nodes();
      e += deterministic_sum(bars.size(), [&](std::int64_t i) {
        return 0.5 * bars.mass[i] * bars.velocity.row(i).squaredNorm();
      });
    }
    return e;
  }

  /// Acceleration of gravity g (m/s^2, world; e.g. (0, 0, -9.81)), a body force on every block:
  /// the lumped weights m0_i g on the gridpoints of deformable blocks, each rigid block's weight at
  /// its centroid (blocks::rigid::set_gravity); m0 the masses before mass scaling. Its work enters
  /// the energy balance (energy_balance::gravity_work). Throws invalid_input for a non-finite g.
  void set_gravity(const vec3& g) {
    require(g.allFinite(), "solver: gravity (", g.transpose(), ") m/s^2 is not finite");
    gravity_ = g;
    if constexpr (Blocks::is_rigid) {
      blocks_.set_gravity(g);
    } else {
      gravity_force_.resize(gridpoints_.size(), 3);
      for (index_t i = 0; i < gridpoints_.size(); ++i) gravity_force_.row(i) = weight_mass_[i] * g.transpose();
    }
  }
  [[nodiscard]] const vec3& gravity() const { return gravity_; }

  /// Registers gridpoints that take forces from outside the model (deformable blocks; a
  /// contact::rigid_platen, a point load), with the stiffness k[j] (N/m, >= 0; 0 for a plain
  /// load) of whatever applies them, which joins the gridpoint's bound: the time step is
  /// recomputed (compute_time_step; with mass scaling the masses are raised where the spring
  /// needs it). Throws invalid_input for an unknown gridpoint or a bad k.
  void register_applied_forces(std::span<const index_t> nodes, std::span<const real> k) {
    static_assert(!Blocks::is_rigid, "register_applied_forces: rigid blocks take loads on their bodies");
    require(nodes.size() == k.size(), "solver: register_applied_forces got ", nodes.size(), " gridpoints and ",
            k.size(), " stiffnesses");
    if (applied_active_) applied_work_ += applied_work_of_last_step();  // booked before the list changes
    applied_active_ = false;
    if (applied_stiffness_.size() != gridpoints_.size()) applied_stiffness_.setZero(gridpoints_.size());
    if (applied_force_.rows() != gridpoints_.size()) applied_force_.setZero(gridpoints_.size(), 3);
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      require(nodes[j] >= 0 && nodes[j] < gridpoints_.size(), "solver: applied force on gridpoint ", nodes[j],
              ", not one of the ", gridpoints_.size());
      require(std::isfinite(k[j]) && k[j] >= 0, "solver: applied-force stiffness ", k[j], " N/m on gridpoint ",
              nodes[j], " must be finite and >= 0");
      applied_stiffness_[nodes[j]] += k[j];
      applied_nodes_.push_back(nodes[j]);
    }
    std::sort(applied_nodes_.begin(), applied_nodes_.end());
    applied_nodes_.erase(std::unique(applied_nodes_.begin(), applied_nodes_.end()), applied_nodes_.end());
    applied_previous_.setZero(static_cast<index_t>(applied_nodes_.size()), 3);
    for (std::size_t j = 0; j < applied_nodes_.size(); ++j)
      applied_previous_.row(static_cast<index_t>(j)) = applied_force_.row(applied_nodes_[j]);
    compute_time_step();
  }
  /// Forces from outside the model (N), one row per gridpoint, of which the rows registered by
  /// register_applied_forces are read (the others stay unread): each step starts from them (with
  /// the weights), so a caller that computes them from the state, such as a
  /// contact::rigid_platen, writes them between steps. Their work enters the energy balance as
  /// energy_balance::applied_work, booked by the trapezoidal rule, (F(t) + F(t + dt)) / 2 x the
  /// step's displacement, which is exact for a linear spring (a one-sided rule gains 1/2 k du^2
  /// per step: 1.7 % of a platen's work on a column that springs back, test "rigid platen").
  [[nodiscard]] soa3& applied_forces() { return applied_force_; }
  [[nodiscard]] const std::vector<index_t>& applied_nodes() const { return applied_nodes_; }

  /// Advances the model by one time step (see the file comment). One function on purpose (about
  /// 85 lines): the step order of docs/architecture.md, with its fused parallel region, in one place.
  void step() {
    thread_governor_step();  // this step's thread count, while a governor runs (core/thread_governor.hpp)
    using clock = std::chrono::steady_clock;
    const auto since = [](clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); };
    if constexpr (Blocks::is_rigid) {
      // The step from the supports as they stand now (file comment), refusing an options.dt
      // above it; later, a block the step left out must still be held. Both before anything changes.
      if (step_ == 0)
        choose_time_step(true);
      else
        blocks_.check_step_bound(gridpoints_);
    }
    if (step_ == 0) initial_energy_ = stored_and_kinetic();
    [[maybe_unused]] real kick_dt = dt_;  // the velocity update's step (file comment, "Time step")
    if (!Blocks::is_rigid && gravity_ != vec3::Zero())
      gridpoints_.force = gravity_force_;
    else
      gridpoints_.force.setZero();
    if (!applied_nodes_.empty()) {
      // Book the last step's applied work now that its closing forces are known, then apply them.
      if (applied_active_) applied_work_ += applied_work_of_last_step();
      applied_active_ = true;
      for (std::size_t j = 0; j < applied_nodes_.size(); ++j) {
        const index_t g = applied_nodes_[j];
        gridpoints_.force.row(g) += applied_force_.row(g);
        applied_previous_.row(static_cast<index_t>(j)) = applied_force_.row(g);
      }
    }
    if constexpr (Reinforcement::enabled) reinforcement_.nodes().force.setZero();
    if constexpr (requires(Blocks& b, index_t i) {
                    b.zone_task_count();
                    b.add_zone_forces_of_tasks(i, i, gridpoints_);
                  }) {
      // Steps 2-3 fused (same results to the bit as accumulate_forces + update): the zone tasks
      // (which add their corner forces to their own block's gridpoints) and the contact faces
      // (which store their forces per sub-contact) are independent, so they share one parallel
      // region, in which each thread first computes the rotations of its own zone tasks' blocks,
      // and one pass over the gridpoints then gathers the contact forces. Two
      // fork/joins per step instead of five; on a busy machine each one can cost a scheduler
      // time slice.
      const auto prepare = clock::now();
      contacts_.prepare_step(gridpoints_, dt_);
      phases_.contacts += since(prepare);
      range_pair_times region;
      parallel_range_pair(
          blocks_.zone_task_count(),
          [&](std::int64_t t0, std::int64_t t1) {
            blocks_.add_zone_forces_of_tasks(static_cast<index_t>(t0), static_cast<index_t>(t1), gridpoints_);
          },
          contacts_.task_count(),
          [&](std::int64_t t) { contacts_.run_task(static_cast<index_t>(t), gridpoints_, dt_); }, 16, &region);
      phases_.zones += region.first;
      phases_.contacts += region.second;
      // An integrator that can gather each chunk of gridpoints inside its own loop.
      const auto no_prepare = [](std::int64_t, std::int64_t) {};
      constexpr bool fused_integrator =
          requires(integrator::step_work& w) { integrator_.advance(gridpoints_, dt_, w, no_prepare); };
      // Bars that can hand their host forces to that gather (embedded_truss): bar-side forces
      // first (they read displacements and this step's zone stresses), host shares in the gather.
      // (Without a fused integrator the bars keep accumulate_forces below.)
      constexpr bool split_bars = fused_integrator && Reinforcement::enabled && requires(Reinforcement& rf, index_t i) {
        rf.compute_forces(gridpoints_, stress_for_bars());
        rf.add_host_forces(i, i, gridpoints_);
      };
      if constexpr (split_bars) {
        const auto bars = clock::now();
        reinforcement_.compute_forces(gridpoints_, stress_for_bars());
        phases_.bars += since(bars);
      }
      const auto gather = [&](std::int64_t begin, std::int64_t end) {
        // Per gridpoint: zone forces (already added), then contact forces, then bar host shares
        // (the order of the unfused step).
        for (std::int64_t i = begin; i < end; ++i) contacts_.add_force(static_cast<index_t>(i), gridpoints_);
        if constexpr (split_bars)
          reinforcement_.add_host_forces(static_cast<index_t>(begin), static_cast<index_t>(end), gridpoints_);
      };
      if constexpr (fused_integrator && (!Reinforcement::enabled || split_bars)) {
        // The integrator gathers each chunk of gridpoints right before integrating it (one
        // parallel loop for gather and update); the bar nodes, whose forces are complete, follow.
        const auto integration = clock::now();
        integrator::step_work work;
        integrator_.advance(gridpoints_, dt_, work, gather);
        if constexpr (Reinforcement::enabled) integrator_.advance(reinforcement_.nodes(), dt_, work);
        phases_.integration += since(integration);
        finish_step(work);
        return;
      } else {
        const auto gathering = clock::now();
        parallel_for(gridpoints_.size(), [&](std::int64_t i) { gather(i, i + 1); });
        phases_.integration += since(gathering);
      }
    } else {
      const auto zones = clock::now();
      blocks_.accumulate_forces(gridpoints_);
      const auto contacts = clock::now();
      phases_.zones += std::chrono::duration<double>(contacts - zones).count();
      contacts_.update(gridpoints_, dt_);
      phases_.contacts += since(contacts);
      // (Rigid blocks take this unfused path.) A rebuild changed the contact set's bound: dt
      // chosen again before the integration (file comment, "Time step").
      if constexpr (rebuilds_choose_dt)
        if (contacts_.rebuild_count() != bound_rebuilds_) {
          const real before = dt_;
          bound_after_rebuild();
          kick_dt = 0.5 * (before + dt_);  // = dt_ to the bit when dt did not change
        }
    }
    if constexpr (Reinforcement::enabled) {
      const auto bars = clock::now();
      reinforcement_.accumulate_forces(gridpoints_, stress_for_bars());
      phases_.bars += since(bars);
    }
    const auto integration = clock::now();
    integrator::step_work work;
    if constexpr (rebuilds_choose_dt)
      blocks_.advance(integrator_, gridpoints_, dt_, work, kick_dt);
    else
      blocks_.advance(integrator_, gridpoints_, dt_, work);
    if constexpr (Reinforcement::enabled) integrator_.advance(reinforcement_.nodes(), dt_, work);
    phases_.integration += since(integration);
    finish_step(work);
  }

  /// Runs n_steps steps, calling observer(*this) after each (wrap with recorders::every).
  template <class... Observers>
  void run(std::int64_t n_steps, Observers&&... observers) {
    for (std::int64_t k = 0; k < n_steps; ++k) {
      step();
      observe(observers...);
    }
  }
  /// Steps until stop(*this) is true or max_steps (>= 0) were taken, calling observer(*this)
  /// after each step. stop is evaluated before every step, the first time before any step; a
  /// condition of solver/stop_conditions.hpp (stop::after_time(1.0) || stop::when_beyond(...)) is
  /// first restarted (stop.start(*this), where the predicate has it), so it counts from this call.
  /// Returns the steps taken, the reason (stop.reason() where the predicate has it) and whether
  /// max_steps ran out first; converts to the step count. Throws invalid_input for max_steps < 0.
  template <class Predicate, class... Observers>
  run_result run_until(Predicate&& stop, std::int64_t max_steps, Observers&&... observers) {
    require(max_steps >= 0, "solver: run_until max_steps = ", max_steps, " must be >= 0");
    if constexpr (requires { stop.start(std::as_const(*this)); }) stop.start(std::as_const(*this));
    run_result result;
    bool stopped = false;
    while (!(stopped = stop(std::as_const(*this))) && result.steps < max_steps) {
      step();
      ++result.steps;
      observe(observers...);
    }
    result.hit_max_steps = !stopped;
    if (!stopped)
      result.reason = detail::concat("max_steps = ", max_steps, " reached");
    else if constexpr (requires { stop.reason(); })
      result.reason = stop.reason();
    else
      result.reason = "the stop predicate returned true";
    return result;
  }

  // ---- accessors ----
  [[nodiscard]] node_set& gridpoints() { return gridpoints_; }
  [[nodiscard]] const node_set& gridpoints() const { return gridpoints_; }
  [[nodiscard]] node_set& bar_nodes() { return reinforcement_.nodes(); }
  [[nodiscard]] const node_set& bar_nodes() const { return reinforcement_.nodes(); }
  [[nodiscard]] const contact_set_type& contacts() const { return contacts_; }
  [[nodiscard]] const Blocks& blocks() const { return blocks_; }
  /// The block model, e.g. for initial conditions (blocks::rigid::set_velocity).
  [[nodiscard]] Blocks& blocks() { return blocks_; }
  [[nodiscard]] const Reinforcement& reinforcement() const { return reinforcement_; }
  [[nodiscard]] Reinforcement& reinforcement() { return reinforcement_; }
  [[nodiscard]] index_t gridpoint_block(index_t i) const { return gridpoint_block_[static_cast<std::size_t>(i)]; }
  [[nodiscard]] real time() const { return time_; }
  [[nodiscard]] real dt() const { return dt_; }
  [[nodiscard]] std::int64_t step_count() const { return step_; }
  /// Critical step min 2 sqrt(m/(a k)) (after mass scaling; a = damping's stiffness amplification)
  /// and its limiting node.
  [[nodiscard]] const integrator::critical_step& critical_step() const { return critical_; }
  [[nodiscard]] const integrator::mass_scaling_report& mass_scaling() const { return scaling_; }
  /// Factor a on the nodal stiffness in the stable step (1 + gamma with local damping, else 1).
  [[nodiscard]] real stiffness_amplification() const { return integrator_.stiffness_amplification(); }
  [[nodiscard]] const solver_options& options() const { return options_; }
  /// Time spent in each phase of the steps so far (see phase_times).
  [[nodiscard]] const phase_times& phases() const { return phases_; }

  /// Unbalanced force of the last step over free components (solver/balance.hpp): of the
  /// gridpoints (deformable blocks) or of the blocks' translations (rigid blocks: the block force
  /// with the weight, moments left out), then of the bar nodes (max_node counts on from the
  /// gridpoints or blocks). O(nodes); the same for any thread count.
  [[nodiscard]] out_of_balance unbalanced_force() const {
    out_of_balance b;
    if constexpr (Blocks::is_rigid) {
      for (index_t k = 0; k < blocks_.block_count(); ++k)
        b.add_free(k, [&](int c) { return !blocks_.translation_prescribed(k, c); },
                   [&](int c) { return blocks_.force(k)[c]; });
    } else {
      for (index_t i = 0; i < gridpoints_.size(); ++i) b.add(gridpoints_, i);
    }
    if constexpr (Reinforcement::enabled) {
      const index_t offset = Blocks::is_rigid ? blocks_.block_count() : gridpoints_.size();
      const node_set& bars = reinforcement_.nodes();
      for (index_t i = 0; i < bars.size(); ++i) b.add(bars, i, offset + i);
    }
    return b;
  }

  /// All energy terms now (J); O(zones + sub-contacts + nodes).
  [[nodiscard]] energy_balance energies() const {
    energy_balance e;
    e.initial = step_ == 0 ? stored_and_kinetic() : initial_energy_;
    e.boundary_work = boundary_work_;
    e.gravity_work = gravity_work_;
    // The last step's share is booked with the forces written since, if any (applied_forces).
    e.applied_work = applied_work_ + (applied_active_ ? applied_work_of_last_step() : 0);
    e.damping_dissipated = damping_dissipated_;
    e.kinetic = blocks_.kinetic_energy(gridpoints_);
    e.block_elastic = blocks_.stored_energy(gridpoints_);
    const auto c = contacts_.energies();
    e.contact_stored = c.stored;
    e.contact_dissipated = c.dissipated;
    e.contact_dissipated_tension = c.dissipated_tension;
    e.contact_rebuild_exchange = c.rebuild_exchange;
    if constexpr (Reinforcement::enabled) {
      const node_set& bars = reinforcement_.nodes();
      e.kinetic += deterministic_sum(bars.size(), [&](std::int64_t i) {
        return 0.5 * bars.mass[i] * bars.velocity.row(i).squaredNorm();
      });
      e.reinforcement_stored = reinforcement_.stored_energy();
      e.reinforcement_dissipated = reinforcement_.dissipated_energy();
    }
    return e;
  }

  /// Saves or loads the solver's evolving state through a checkpoint archive (io/checkpoint.hpp:
  /// io::save_checkpoint, io::load_checkpoint): step, time and the energy accounts, then the
  /// gridpoints, blocks, contacts and reinforcement, each by its own checkpoint(). The time step
  /// must be the one the solver was built with (a model built with other options is refused).
  /// Phase timings are not state and restart from zero.
  template <class Archive>
  void checkpoint(Archive& ar) {
    static_assert(requires { blocks_.checkpoint(ar); }, "this block model has no checkpoint(Archive&)");
    static_assert(requires { contacts_.checkpoint(ar); }, "this contact set has no checkpoint(Archive&)");
    static_assert(requires { reinforcement_.checkpoint(ar); }, "this reinforcement has no checkpoint(Archive&)");
    if constexpr (Blocks::is_rigid)
      if (step_ == 0) choose_time_step(true);  // the step the first step would take (file comment)
    // A dt that follows the contact rebuilds (file comment) is state: saved and loaded. Any
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
  /// automatic (file comment, "Time step").
  static constexpr bool rebuilds_choose_dt = Blocks::is_rigid && requires(const contact_set_type& c) {
    c.rebuild_count();
  };

  /// compute_time_step; with refuse_user_dt false an options.dt above the limit is kept for now
  /// (rigid blocks at construction: the supports that raise the limit come later).
  void compute_time_step_refusing(bool refuse_user_dt) {
    assemble_stiffness_bounds();
    const real amplification = integrator_.stiffness_amplification();
    if (options_.mass_scaling_ratio > 0) {
      // Resolved once, on the unscaled masses; later calls keep the step it gave.
      real unscaled = integrator::critical_time_step(gridpoints_, amplification).dt;
      if constexpr (Reinforcement::enabled)
        unscaled = std::min(unscaled, integrator::critical_time_step(reinforcement_.nodes(), amplification).dt);
      options_.mass_scaling_dt = integrator::step_for_added_mass(
          options_.mass_scaling_ratio, options_.safety * unscaled, [&](real dt) {
            integrator::mass_scaling_report r =
                integrator::preview_mass_scaling(gridpoints_, dt, options_.safety, amplification);
            if constexpr (Reinforcement::enabled)
              r += integrator::preview_mass_scaling(reinforcement_.nodes(), dt, options_.safety, amplification);
            return r.added_mass / r.original_mass;
          });
      options_.mass_scaling_ratio = 0;
    }
    if (options_.mass_scaling_dt > 0) {
      // Rigid blocks scale their bodies' mass and inertia (blocks/rigid.hpp), not the gridpoints.
      integrator::mass_scaling_report pass;
      if constexpr (Blocks::is_rigid)
        pass = blocks_.scale_masses(gridpoints_, options_.mass_scaling_dt, options_.safety, amplification);
      else
        pass = integrator::scale_masses(gridpoints_, options_.mass_scaling_dt, options_.safety, amplification);
      if constexpr (Reinforcement::enabled)
        pass += integrator::scale_masses(reinforcement_.nodes(), options_.mass_scaling_dt, options_.safety, amplification);
      // A later call (new stiffness: register_applied_forces) scales masses already scaled: the
      // report keeps the first pass's original mass and adds what this one adds.
      if (scaled_) {
        scaling_.added_mass += pass.added_mass;
        scaling_.scaled_nodes = std::max(scaling_.scaled_nodes, pass.scaled_nodes);
      } else {
        scaling_ = pass;
        scaled_ = true;
      }
    }
    choose_time_step(refuse_user_dt);
  }

  /// True when dt is automatic (no options.dt, no mass scaling), so it may change at a contact
  /// rebuild (file comment, "Time step").
  [[nodiscard]] bool dt_follows_rebuilds() const {
    return options_.dt == 0 && options_.mass_scaling_dt == 0 && options_.mass_scaling_ratio == 0;
  }

  /// The nodal stiffness bounds of blocks, contacts, bonds and applied forces. A contact set whose
  /// bound holds only until its next rebuild gives the bound of every contact it could carry
  /// when dt does not follow the rebuilds (file comment).
  void assemble_stiffness_bounds() {
    gridpoints_.stiffness.setZero();
    blocks_.add_stiffness_bounds(gridpoints_);
    if constexpr (requires { contacts_.add_whole_surface_stiffness_bounds(gridpoints_); }) {
      if (dt_follows_rebuilds())
        contacts_.add_stiffness_bounds(gridpoints_);
      else
        contacts_.add_whole_surface_stiffness_bounds(gridpoints_);
    } else {
      contacts_.add_stiffness_bounds(gridpoints_);
    }
    if constexpr (requires { contacts_.rebuild_count(); }) bound_rebuilds_ = contacts_.rebuild_count();
    if constexpr (Reinforcement::enabled) reinforcement_.add_stiffness_bounds(gridpoints_);
    if (applied_stiffness_.size() == gridpoints_.size()) gridpoints_.stiffness += applied_stiffness_;
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

  /// The critical step from the nodal stiffness bounds and masses in place, and dt from it (file
  /// comment); rigid blocks leave fully prescribed blocks out (blocks::rigid::critical_time_step).
  /// O(gridpoints). refuse_user_dt: throw invalid_input for an options.dt above the limit.
  void choose_time_step(bool refuse_user_dt) {
    const real amplification = integrator_.stiffness_amplification();
    if constexpr (Blocks::is_rigid) {
      critical_ = blocks_.critical_time_step(gridpoints_, amplification);  // 6-DOF bound per block
      blocks_.record_step_bound(gridpoints_);
    } else {
      critical_ = integrator::critical_time_step(gridpoints_, amplification);
    }
    bool limited_by_bar = false;
    if constexpr (Reinforcement::enabled) {
      const auto bars = integrator::critical_time_step(reinforcement_.nodes(), amplification);
      if (bars.dt < critical_.dt) {
        critical_ = bars;
        limited_by_bar = true;
      }
    }
    require(std::isfinite(critical_.dt), "solver: no node has a positive stiffness bound; cannot choose a time step");
    const real stable = options_.safety * critical_.dt;
    if (options_.dt > 0) {
      require(!refuse_user_dt || options_.dt <= stable * (1 + 1e-12), "solver: time step dt = ", options_.dt,
              " s exceeds the stable limit ", stable, " s (safety ", options_.safety, " x 2 sqrt(m/(a k)), a = ",
              amplification, ") set by ",
              limited_by_bar ? detail::concat("bar node ", critical_.node)
                             : detail::concat("gridpoint ", critical_.node, " of block ", gridpoint_block(critical_.node)),
              " (m = ", critical_.mass, " kg, k = ", critical_.stiffness, " N/m); lower dt or use mass scaling");
      dt_ = options_.dt;
    } else if (options_.mass_scaling_dt > 0) {
      // The masses were scaled so that mass_scaling_dt is stable; recomputed from them, the limit
      // can come back an ulp below it (with fused multiply-adds), which is rounding, not a limit.
      dt_ = stable >= options_.mass_scaling_dt * (1 - 1e-12) ? options_.mass_scaling_dt : stable;
    } else {
      dt_ = stable;
    }
  }

  /// After a support call: rigid blocks choose the step again while no step was taken (a block
  /// fixed now may no longer bound it); an options.dt above the limit is refused at the first step.
  void supports_changed() {
    if constexpr (Blocks::is_rigid)
      if (step_ == 0) choose_time_step(false);
  }

  // ---- blocks' gridpoints (block b owns gridpoints [block_first(b), block_end(b)), mesh CSR) ----
  void require_block(index_t b, const char* what) const {
    require(b >= 0 && b < block_count(), "solver: ", what, ": block ", b, " does not exist (", block_count(), " blocks)");
  }
  [[nodiscard]] index_t block_first(index_t b) const { return block_gridpoint_offsets_[static_cast<std::size_t>(b)]; }
  [[nodiscard]] index_t block_end(index_t b) const { return block_gridpoint_offsets_[static_cast<std::size_t>(b) + 1]; }
  static void require_plane(int axis, real value, real tol, const char* what) {
    require(axis >= 0 && axis < 3, "solver: ", what, ": axis = ", axis, " must be 0 (x), 1 (y) or 2 (z)");
    require(std::isfinite(value), "solver: ", what, ": plane position ", value, " m is not finite");
    require(std::isfinite(tol) && tol >= 0, "solver: ", what, ": tolerance ", tol, " m must be finite and >= 0");
  }
  /// Smallest and largest reference coordinate along axis of block b's gridpoints (m).
  [[nodiscard]] std::pair<real, real> block_extent(index_t b, int axis) const {
    real lo = std::numeric_limits<real>::infinity(), hi = -lo;
    for (index_t i = block_first(b); i < block_end(b); ++i) {
      lo = std::min(lo, gridpoints_.reference(i, axis));
      hi = std::max(hi, gridpoints_.reference(i, axis));
    }
    return {lo, hi};
  }
  [[nodiscard]] vec3 current_position(index_t i) const {
    return (gridpoints_.reference.row(i) + gridpoints_.displacement.row(i)).transpose();
  }
  /// Mass-weighted mean (unscaled masses) of rows of `field` over block b's gridpoints (deformable).
  [[nodiscard]] vec3 block_mean(index_t b, const soa3& field) const {
    vec3 sum = vec3::Zero();
    real m = 0;
    for (index_t i = block_first(b); i < block_end(b); ++i) {
      sum += weight_mass_[i] * field.row(i).transpose();
      m += weight_mass_[i];
    }
    return sum / m;
  }

  template <class... Observers>
  void observe(Observers&... observers) {
    if constexpr (sizeof...(Observers) > 0) {
      const auto start = std::chrono::steady_clock::now();
      (observers(std::as_const(*this)), ...);
      phases_.recorders += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
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
        gravity_work_ += deterministic_sum(gridpoints_.size(), [&](std::int64_t i) {
                           return (gravity_force_(i, 0) * gridpoints_.velocity(i, 0) +
                                   gravity_force_(i, 1) * gridpoints_.velocity(i, 1)) +
                                  gravity_force_(i, 2) * gridpoints_.velocity(i, 2);
                         }) * dt_;
      }
    }
    ++step_;
    time_ += dt_;
    if constexpr (Checker::enabled)
      if (step_ % checker_.interval == 0) checker_.check(*this);
  }

  /// (F(t - dt) + F(t)) / 2 . v(t - dt/2) dt summed over the applied-force gridpoints: the work of
  /// the last step, F(t - dt) the forces it applied, F(t) the forces now written.
  [[nodiscard]] real applied_work_of_last_step() const {
    real w = 0;
    for (std::size_t j = 0; j < applied_nodes_.size(); ++j) {
      const index_t g = applied_nodes_[j];
      for (int c = 0; c < 3; ++c)
        w += 0.5 * (applied_previous_(static_cast<index_t>(j), c) + applied_force_(g, c)) * gridpoints_.velocity(g, c);
    }
    return w * dt_;
  }

  [[nodiscard]] real stored_and_kinetic() const {
    real e = blocks_.kinetic_energy(gridpoints_) + blocks_.stored_energy(gridpoints_) + contacts_.energies().stored;
    if constexpr (Reinforcement::enabled) {
      const node_set& bars = reinforcement_.nodes();
      for (index_t i = 0; i < bars.size(); ++i) e += 0.5 * bars.mass[i] * bars.velocity.row(i).squaredNorm();
      e += reinforcement_.stored_energy();
    }
    return e;
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
