#pragma once
// The stable time step and the mass scaling of blocks::rigid (rigid.hpp's file comment derives
// the bound: dt_cr = min_b min(2 sqrt(m / (2 a k_t)), 2 sqrt(I1 / (2 a k_r))) from the gridpoints'
// stiffness bounds, fully prescribed blocks left out while a free block has a stiffness): the
// bounds of one block, the minimum over the blocks, the blocks left out, and the common factor
// that brings a block's m and I up to a target step. Not a public interface.
//
// Cost: O(gridpoints) per call, no allocation. Thread safety: pure functions but for
// scale_rigid_masses, which writes the records it is given.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>

#include "../../core/separate_compilation.hpp"
#include "../../core/errors.hpp"
#include "../../core/nodes.hpp"
#include "../../core/types.hpp"
#include "../../integrator/timestep.hpp"
#include "rigid_body.hpp"

namespace tessera::blocks::detail {

/// k_t = sum_i k_i (N/m) and k_r = sum_i k_i |r_i|^2 (N m) over the gridpoints of block `bd`.
[[nodiscard]] inline std::array<real, 2> rigid_stiffness_bounds(const node_set& gridpoints, const soa3& body_position,
                                                          const rigid_body& bd) {
  real k_t = 0, k_r = 0;
  for (index_t i = bd.first; i < bd.end; ++i) {
    k_t += gridpoints.stiffness[i];
    k_r += gridpoints.stiffness[i] * body_position.row(i).squaredNorm();
  }
  return {k_t, k_r};
}

/// True when every translation component of block `bd` is prescribed on some gridpoint of it
/// (rigid::fully_prescribed), as the gridpoints' constraints stand.
[[nodiscard]] inline bool rigid_fully_prescribed(const node_set& gridpoints, const rigid_body& bd) {
  constexpr auto prescribed = static_cast<std::uint8_t>(dof_constraint::prescribed);
  bool held[3] = {false, false, false};
  for (index_t i = bd.first; i < bd.end; ++i)
    for (int c = 0; c < 3; ++c) held[c] = held[c] || gridpoints.constraint(i, c) == prescribed;
  return held[0] && held[1] && held[2];
}

/// min over blocks (all, or only those not fully prescribed) of both bounds (s; rigid::
/// critical_time_step), reported at the block's first gridpoint with m and k_eq (N/m).
[[nodiscard]] TESSERA_INLINE integrator::critical_step rigid_step_bound(std::span<const rigid_body> bodies,
                                                                 const node_set& gridpoints, const soa3& body_position,
                                                                 real amplification, bool skip_prescribed);

/// Throws invalid_input for block b, left out of the step in use and no longer fully
/// prescribed, naming its free translation components.
[[noreturn]] inline void throw_rigid_unbounded(const node_set& gridpoints, index_t b, const rigid_body& bd) {
  std::string freed;
  for (int c = 0; c < 3; ++c) {
    bool held = false;
    for (index_t i = bd.first; i < bd.end; ++i)
      held = held || gridpoints.constraint(i, c) == static_cast<std::uint8_t>(dof_constraint::prescribed);
    if (!held) freed += "xyz"[c];
  }
  throw invalid_input(tessera::detail::concat(
      "rigid blocks: block ", b, " was fully prescribed when the time step was chosen, so the step does not bound it, "
      "and its translation component(s) ", freed, " are free now; call solver::compute_time_step() after freeing it "
      "(the step may drop), or keep it prescribed"));
}

/// Multiplies m and I of every block in `bodies` whose bound is below target_dt (s) by the
/// smallest common factor that makes safety x its bound reach it (rigid::scale_masses, which
/// checks the arguments and shares the new masses among the gridpoints).
TESSERA_INLINE integrator::mass_scaling_report scale_rigid_masses(std::span<rigid_body> bodies, const node_set& gridpoints,
                                                                  const soa3& body_position, real target_dt, real safety,
                                                                  real amplification);

}  // namespace tessera::blocks::detail

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/rigid_step_bound.ipp"
#endif
