#pragma once
// The out-of-line members of tessera::solver (solver/solver.hpp declares them and documents what
// they do; solver.hpp includes this file at its end): the constructor, set_gravity, step, the
// kinetic energy, the out-of-balance and the energy books. Defined outside the class, and not
// `inline`, on purpose: for the solver types that tessera::instances declares `extern template`
// (tessera/instances.hpp), a translation unit that includes instances.hpp then instantiates none
// of them, nor what they call (the block model's and contact set's step members, the contact
// law, the time step), and takes the compiled copy from the library. GCC instantiates an inline
// member of an extern template all the same at -O2, to inline it; members defined in the class are
// inline, and so cost every scene their instantiation and optimisation
// (docs/studies/compile_time.md). Any other solver type instantiates them in the user's file as
// before.

#include <chrono>
#include <cstdint>
#include <span>

#include "../solver.hpp"

namespace tessera {

template <blocks::BlockModel Blocks, contact::ContactSet Contacts, reinforcement::Reinforcement Reinforcement,
          integrator::Integrator Integrator, class Checker>
solver<Blocks, Contacts, Reinforcement, Integrator, Checker>::solver(const geometry::tessellation& tess,
                                                                    const geometry::block_mesh& mesh,
                                                                    const block_materials& materials,
                                                                    const typename Contacts::params& contact_params,
                                                                    const typename Reinforcement::params& reinforcement_params,
                                                                    const solver_options& options)
    : options_(options) {
  detail::require_valid_options(options, Blocks::is_rigid);
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

template <blocks::BlockModel Blocks, contact::ContactSet Contacts, reinforcement::Reinforcement Reinforcement,
          integrator::Integrator Integrator, class Checker>
real solver<Blocks, Contacts, Reinforcement, Integrator, Checker>::kinetic_energy() const {
  real e = blocks_.kinetic_energy(gridpoints_);
  if constexpr (Reinforcement::enabled) e += detail::bar_kinetic_energy(reinforcement_.nodes());
  return e;
}

template <blocks::BlockModel Blocks, contact::ContactSet Contacts, reinforcement::Reinforcement Reinforcement,
          integrator::Integrator Integrator, class Checker>
void solver<Blocks, Contacts, Reinforcement, Integrator, Checker>::set_gravity(const vec3& g) {
  require(g.allFinite(), "solver: gravity (", g.transpose(), ") m/s^2 is not finite");
  gravity_ = g;
  if constexpr (Blocks::is_rigid) {
    blocks_.set_gravity(g);
  } else {
    gravity_force_.resize(gridpoints_.size(), 3);
    for (index_t i = 0; i < gridpoints_.size(); ++i) gravity_force_.row(i) = weight_mass_[i] * g.transpose();
  }
}

template <blocks::BlockModel Blocks, contact::ContactSet Contacts, reinforcement::Reinforcement Reinforcement,
          integrator::Integrator Integrator, class Checker>
void solver<Blocks, Contacts, Reinforcement, Integrator, Checker>::step() {
  thread_governor_step();  // this step's thread count, while a governor runs (core/thread_governor.hpp)
  using clock = std::chrono::steady_clock;
  const auto since = [](clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); };
  if constexpr (Blocks::is_rigid) {
    // The step from the supports as they stand now (solver/time_step.hpp), refusing an options.dt
    // above it; later, a block the step left out must still be held. Both before anything changes.
    if (step_ == 0)
      choose_time_step(true);
    else
      blocks_.check_step_bound(gridpoints_);
  }
  if (step_ == 0) { detail::refuse_first_step_traps(*this); initial_energy_ = stored_and_kinetic(); }
  [[maybe_unused]] real kick_dt = dt_;  // the velocity update's step (solver/time_step.hpp)
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
    // chosen again before the integration (solver/time_step.hpp).
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

template <blocks::BlockModel Blocks, contact::ContactSet Contacts, reinforcement::Reinforcement Reinforcement,
          integrator::Integrator Integrator, class Checker>
out_of_balance solver<Blocks, Contacts, Reinforcement, Integrator, Checker>::unbalanced_force() const {
  return detail::unbalanced_force(blocks_, gridpoints_, reinforcement_);
}

template <blocks::BlockModel Blocks, contact::ContactSet Contacts, reinforcement::Reinforcement Reinforcement,
          integrator::Integrator Integrator, class Checker>
energy_balance solver<Blocks, Contacts, Reinforcement, Integrator, Checker>::energies() const {
  energy_balance e;
  e.initial = step_ == 0 ? stored_and_kinetic() : initial_energy_;
  e.boundary_work = boundary_work_;
  e.gravity_work = gravity_work_;
  // The last step's share is booked with the forces written since, if any (applied_forces).
  e.applied_work = applied_work_ + (applied_active_ ? applied_work_of_last_step() : 0);
  e.damping_dissipated = damping_dissipated_;
  e.peak_work = std::max(peak_work_, std::abs(e.boundary_work) + std::abs(e.gravity_work) + std::abs(e.applied_work));
  detail::add_state_energies(e, blocks_, gridpoints_, contacts_, reinforcement_);
  return e;
}

}  // namespace tessera
