#pragma once
// tessera::solver_external_steps<Solver>: a base of tessera::solver (CRTP; its members are the
// solver's) for a driver that runs the pieces of solver::step itself, as a run split over MPI
// ranks does (distributed::stepper for deformable blocks, distributed::rigid_stepper for rigid
// blocks on detected contacts). Such a driver zeroes and gathers the forces of the gridpoints it
// owns, integrates them, and closes the step here; the solver keeps the time step, the time and
// the work books. What solver::step also does and such a driver does not: the step checker (it
// runs its own checks) and the initial energy (it books its rank's share, book_initial_energy).
//
// A rigid-block step by pieces, in solver::step's order:
//   s.begin_rigid_step();                    // the stable step's checks, as step() starts
//   ... zero forces, s.contacts_for_step().update(gridpoints, s.dt()) ...
//   const real kick = s.time_step_after_contacts();  // dt chosen again after a contact rebuild
//   ... s.blocks().advance_blocks(s.integrator(), gridpoints, s.dt(), work, kick, own) ...
//   s.close_external_step(work, 0, gravity_work);

#include "../core/types.hpp"
#include "../integrator/concepts.hpp"

namespace tessera {

/// The step run by pieces from outside (a run split over MPI ranks), a base of solver<...> (file comment)
template <class Solver>
class solver_external_steps {
 public:
  /// The contact set, to run its step pieces (prepare_step, update_faces, update, add_force) directly.
  [[nodiscard]] auto& contacts_for_step() { return self().contacts_; }
  /// The integrator, whose advance_dof integrates one component as advance does.
  [[nodiscard]] const auto& integrator() const { return static_cast<const Solver&>(*this).integrator_; }

  /// Rigid blocks, before a step's pieces: what solver::step checks first (solver/time_step.hpp).
  /// Before the first step the time step is chosen from the supports as they stand (refusing an
  /// options.dt above it); later, a block the step left out must still be fully prescribed.
  /// Throws invalid_input as solver::step does.
  void begin_rigid_step() {
    Solver& s = self();
    static_assert(Solver::blocks_type::is_rigid, "begin_rigid_step: rigid blocks only");
    if (s.step_ == 0)
      s.choose_time_step(true);
    else
      s.blocks_.check_step_bound(s.gridpoints_);
  }
  /// Rigid blocks on a contact set that rebuilds, after its update in a step's pieces: when it
  /// rebuilt and dt is automatic, dt is chosen again from the contacts now present, as
  /// solver::step does. Returns the step of this step's velocity update (s): (dt before + dt
  /// after) / 2, which is dt to the bit when dt did not change.
  [[nodiscard]] real time_step_after_contacts() {
    Solver& s = self();
    if constexpr (Solver::rebuilds_choose_dt)
      if (s.contacts_.rebuild_count() != s.bound_rebuilds_) {
        const real before = s.dt_;
        s.bound_after_rebuild();
        return 0.5 * (before + s.dt_);
      }
    return s.dt_;
  }

  /// Sets the energy balance's initial energy (J), which solver::step takes from the kinetic and
  /// stored energy before the first step; a driver of pieces books its own (a split run: its
  /// rank's share), before its first step. A checkpoint keeps it.
  void book_initial_energy(real e) { self().initial_energy_ = e; }

  /// Closes a step whose pieces a driver ran: books its integration's, applied forces' and
  /// gravity's work (J), advances step and time. No step checker (such a driver runs its own).
  void close_external_step(const integrator::step_work& work, real applied_work = 0, real gravity_work = 0) {
    Solver& s = self();
    s.boundary_work_ += work.boundary;
    s.damping_dissipated_ += work.damping;
    s.applied_work_ += applied_work;
    s.gravity_work_ += gravity_work;
    s.note_peak_work();
    ++s.step_;
    s.time_ += s.dt_;
  }

 private:
  [[nodiscard]] Solver& self() { return static_cast<Solver&>(*this); }
};

}  // namespace tessera
