#pragma once
// How a solver chooses its time step (integrator/timestep.hpp): nodal stiffness bounds from
// blocks, contacts and bonds, then optional mass scaling to options.mass_scaling_dt (or to the
// step that adds options.mass_scaling_ratio times the original mass), then dt = options.dt if given
// (it must not exceed safety x the critical step, else invalid_input naming the limiting node and
// block), else the mass-scaling target, else safety x critical step.
//
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
// The functions below are the solver's three stages of that choice, each taking the parts of the
// solver it reads and writes (solver/solver.hpp calls them; not a public interface). Cost:
// O(gridpoints + bar nodes) per call (the added-mass ratio: a bisection of such passes, once), no
// allocation but in blocks::rigid::record_step_bound (only when more blocks are fully prescribed
// than at the last choice). Thread safety: as the solver (one thread).

#include <algorithm>
#include <cmath>
#include <vector>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../integrator/timestep.hpp"
#include "options.hpp"

namespace tessera::detail {

/// True when dt is automatic (no options.dt, no mass scaling), so it may change at a contact
/// rebuild (file comment).
[[nodiscard]] inline bool dt_follows_rebuilds(const solver_options& options) {
  return options.dt == 0 && options.mass_scaling_dt == 0 && options.mass_scaling_ratio == 0;
}

/// Writes gridpoints.stiffness: the nodal stiffness bounds (N/m) of blocks, contacts, bonds and
/// applied forces (applied_stiffness, one per gridpoint, or empty). A contact set whose bound holds
/// only until its next rebuild gives the bound of every contact it could carry when dt does not
/// follow the rebuilds (file comment).
template <class Blocks, class Contacts, class Reinforcement>
void assemble_stiffness_bounds(node_set& gridpoints, Blocks& blocks, Contacts& contacts, Reinforcement& reinforcement,
                               const Eigen::VectorXd& applied_stiffness, bool follows_rebuilds) {
  gridpoints.stiffness.setZero();
  blocks.add_stiffness_bounds(gridpoints);
  if constexpr (requires { contacts.add_whole_surface_stiffness_bounds(gridpoints); }) {
    if (follows_rebuilds)
      contacts.add_stiffness_bounds(gridpoints);
    else
      contacts.add_whole_surface_stiffness_bounds(gridpoints);
  } else {
    contacts.add_stiffness_bounds(gridpoints);
  }
  if constexpr (Reinforcement::enabled) reinforcement.add_stiffness_bounds(gridpoints);
  if (applied_stiffness.size() == gridpoints.size()) gridpoints.stiffness += applied_stiffness;
}

/// Mass scaling to the target of `options` on the stiffness bounds in place, if one is set: an
/// added-mass ratio is resolved once into options.mass_scaling_dt (on the unscaled masses; later
/// calls keep the step it gave), then the gridpoints' (rigid blocks: the bodies') and bar nodes'
/// masses are raised so that step is stable. `scaling` reports the added mass over all passes
/// (`scaled`: a first pass was made). amplification: the damping's factor on the stiffness.
template <class Blocks, class Reinforcement>
void scale_masses_to_target(Blocks& blocks, node_set& gridpoints, Reinforcement& reinforcement, real amplification,
                            solver_options& options, integrator::mass_scaling_report& scaling, bool& scaled) {
  if (options.mass_scaling_ratio > 0) {
    // Resolved once, on the unscaled masses; later calls keep the step it gave.
    real unscaled = integrator::critical_time_step(gridpoints, amplification).dt;
    if constexpr (Reinforcement::enabled)
      unscaled = std::min(unscaled, integrator::critical_time_step(reinforcement.nodes(), amplification).dt);
    options.mass_scaling_dt = integrator::step_for_added_mass(
        options.mass_scaling_ratio, options.safety * unscaled, [&](real dt) {
          integrator::mass_scaling_report r =
              integrator::preview_mass_scaling(gridpoints, dt, options.safety, amplification);
          if constexpr (Reinforcement::enabled)
            r += integrator::preview_mass_scaling(reinforcement.nodes(), dt, options.safety, amplification);
          return r.added_mass / r.original_mass;
        });
    options.mass_scaling_ratio = 0;
  }
  if (options.mass_scaling_dt > 0) {
    // Rigid blocks scale their bodies' mass and inertia (blocks/rigid.hpp), not the gridpoints.
    integrator::mass_scaling_report pass;
    if constexpr (Blocks::is_rigid)
      pass = blocks.scale_masses(gridpoints, options.mass_scaling_dt, options.safety, amplification);
    else
      pass = integrator::scale_masses(gridpoints, options.mass_scaling_dt, options.safety, amplification);
    if constexpr (Reinforcement::enabled)
      pass += integrator::scale_masses(reinforcement.nodes(), options.mass_scaling_dt, options.safety, amplification);
    // A later call (new stiffness: register_applied_forces) scales masses already scaled: the
    // report keeps the first pass's original mass and adds what this one adds.
    if (scaled) {
      scaling.added_mass += pass.added_mass;
      scaling.scaled_nodes = std::max(scaling.scaled_nodes, pass.scaled_nodes);
    } else {
      scaling = pass;
      scaled = true;
    }
  }
}

/// The critical step from the nodal stiffness bounds and masses in place (-> critical), and dt
/// from it (-> dt, s; file comment); rigid blocks leave fully prescribed blocks out
/// (blocks::rigid::critical_time_step) and remember which (record_step_bound). gridpoint_block
/// names the limiting gridpoint's block in the refusal. refuse_user_dt: throw invalid_input for
/// an options.dt above the limit (else it is kept for now: rigid blocks before their supports).
template <class Blocks, class Reinforcement>
void choose_time_step(Blocks& blocks, const node_set& gridpoints, Reinforcement& reinforcement, real amplification,
                      const solver_options& options, const std::vector<index_t>& gridpoint_block, bool refuse_user_dt,
                      integrator::critical_step& critical, real& dt) {
  if constexpr (Blocks::is_rigid) {
    critical = blocks.critical_time_step(gridpoints, amplification);  // 6-DOF bound per block
    blocks.record_step_bound(gridpoints);
  } else {
    critical = integrator::critical_time_step(gridpoints, amplification);
  }
  bool limited_by_bar = false;
  if constexpr (Reinforcement::enabled) {
    const auto bars = integrator::critical_time_step(reinforcement.nodes(), amplification);
    if (bars.dt < critical.dt) {
      critical = bars;
      limited_by_bar = true;
    }
  }
  require(std::isfinite(critical.dt), "solver: no node has a positive stiffness bound; cannot choose a time step");
  const real stable = options.safety * critical.dt;
  if (options.dt > 0) {
    require(!refuse_user_dt || options.dt <= stable * (1 + 1e-12), "solver: time step dt = ", options.dt,
            " s exceeds the stable limit ", stable, " s (safety ", options.safety, " x 2 sqrt(m/(a k)), a = ",
            amplification, ") set by ",
            limited_by_bar ? detail::concat("bar node ", critical.node)
                           : detail::concat("gridpoint ", critical.node, " of block ",
                                            gridpoint_block[static_cast<std::size_t>(critical.node)]),
            " (m = ", critical.mass, " kg, k = ", critical.stiffness, " N/m); lower dt or use mass scaling");
    dt = options.dt;
  } else if (options.mass_scaling_dt > 0) {
    // The masses were scaled so that mass_scaling_dt is stable; recomputed from them, the limit
    // can come back an ulp below it (with fused multiply-adds), which is rounding, not a limit.
    dt = stable >= options.mass_scaling_dt * (1 - 1e-12) ? options.mass_scaling_dt : stable;
  } else {
    dt = stable;
  }
}

}  // namespace tessera::detail
