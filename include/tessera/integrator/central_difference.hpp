#pragma once
// integrator::central_difference<Damping> — explicit central differences with velocities at
// half steps (study eq. 1), for every degree of freedom independently:
//     v(t + dt/2) = v(t - dt/2) + (F(t) - F_d) dt / m         (free component)
//     v(t + dt/2) = v_prescribed                               (prescribed component)
//     u(t + dt)   = u(t) + v(t + dt/2) dt
// The reaction of a prescribed component is the force the support must add so that the update
// gives the prescribed velocity: R = m (v_p - v(t - dt/2)) / dt - F(t) (N, acting on the node),
// which makes the kinetic-energy balance of the scheme exact:
//     1/2 m (v+^2 - v-^2) = (F + R - F_d) v_mid dt,   v_mid = (v- + v+)/2.
// Energy increments accumulated every step (trapezoidal in the velocity): boundary work
// R v_mid dt at prescribed components and damping dissipation F_d v_mid dt at free ones.
//
// Loops run over components (column-major SoA), in fixed chunks; per-chunk partial energies are
// added in chunk order, so the result is bit-identical for any thread count. No allocation.
// Thread safety: advance writes only to the node_set passed to it.

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>

#include "../core/nodes.hpp"
#include "../core/parallel.hpp"
#include "../core/types.hpp"
#include "concepts.hpp"
#include "damping.hpp"

namespace tessera::integrator {

/// Explicit central differences with damping D (local_damping or no_damping): velocities at half steps, displacements at full steps
template <Damping D = local_damping>
class central_difference {
 public:
  using damping_type = D;  ///< the damping policy
  D damping{};  ///< the damping in force

  central_difference() = default;
  explicit central_difference(const D& d) : damping(d) { damping.validate(); }  ///< Refuses (invalid_input) a damping constant out of range

  [[nodiscard]] real stiffness_amplification() const noexcept { return damping.stiffness_amplification(); }  ///< 1 + gamma with local damping, 1 without
  /// The damping in force (D::describe(), e.g. "local damping gamma = 0.8 (...)"), which the
  /// solver's run results and the drivers' summaries name.
  [[nodiscard]] std::string describe_damping() const {
    if constexpr (requires { damping.describe(); })
      return damping.describe();
    else
      return D::enabled ? "a user damping policy (no describe())" : "no damping (a user policy)";
  }

  /// Updates one scalar degree of freedom; returns v(t + dt/2). `constraint` is a
  /// dof_constraint value, `reaction` receives R for prescribed components.
  [[nodiscard]] real advance_dof(real force, real mass, real v_old, std::uint8_t constraint, real v_prescribed,
                                 real dt, real& reaction, step_work& work) const noexcept {
    if (constraint == static_cast<std::uint8_t>(dof_constraint::prescribed)) {
      reaction = mass * (v_prescribed - v_old) / dt - force;
      work.boundary += reaction * 0.5 * (v_old + v_prescribed) * dt;
      return v_prescribed;
    }
    if constexpr (D::enabled) {
      const real fd = damping.force(force, v_old);
      const real v_new = v_old + (force - fd) * dt / mass;
      work.damping += fd * 0.5 * (v_old + v_new) * dt;
      return v_new;
    } else {
      return v_old + force * dt / mass;
    }
  }

  /// Advances every node of `nodes` by one step (see the file comment).
  void advance(node_set& nodes, real dt, step_work& work) const noexcept {
    advance(nodes, dt, work, [](std::int64_t, std::int64_t) {});
  }
  /// The same, calling prepare(begin, end) on each chunk of nodes [begin, end) right before
  /// integrating it (in the same parallel loop), e.g. to gather the chunk's forces while they
  /// are about to be used; prepare must only write the nodes of its chunk.
  template <class Prepare>
  void advance(node_set& nodes, real dt, step_work& work, Prepare&& prepare) const noexcept {
    const std::int64_t n = nodes.size();
    if (n == 0) return;
    constexpr std::int64_t max_chunks = 64;
    const std::int64_t chunk = std::max<std::int64_t>(512, (n + max_chunks - 1) / max_chunks);
    const std::int64_t chunks = (n + chunk - 1) / chunk;
    std::array<step_work, max_chunks> partial{};
    parallel_for(chunks, [&](std::int64_t k) {
      const std::int64_t begin = k * chunk, end = std::min(n, (k + 1) * chunk);
      prepare(begin, end);
      real boundary = 0, damped = 0;
      for (int c = 0; c < 3; ++c) {
        real* v = nodes.velocity.col(c).data();
        real* u = nodes.displacement.col(c).data();
        const real* f = nodes.force.col(c).data();
        real* r = nodes.reaction.col(c).data();
        const real* vp = nodes.prescribed_velocity.col(c).data();
        const std::uint8_t* con = nodes.constraint.col(c).data();
        const real* m = nodes.mass.data();
#if defined(__AVX2__) || defined(__AVX512F__)
        // advance_dof for every component, branch-free so the loop vectorises: both updates
        // are evaluated and the constraint selects one (same operations, so the same velocities
        // and displacements to the bit as advance_dof). The energy sums are reductions over
        // vector lanes: their rounding depends on the vector width of the build, never on the
        // thread count (fixed chunks), and they do not feed back into the motion. (Baseline
        // x86-64 has no cheap byte-to-double mask widening, so GCC keeps this loop scalar there,
        // where the branchy advance_dof below is faster.)
        TESSERA_PRAGMA_SIMD_REDUCTION(boundary, damped)
        for (std::int64_t i = begin; i < end; ++i) {
          const real v_old = v[i], force = f[i], mass = m[i];
          const bool prescribed = con[i] == static_cast<std::uint8_t>(dof_constraint::prescribed);
          const real reaction = mass * (vp[i] - v_old) / dt - force;
          real v_free, fd = 0;
          if constexpr (D::enabled) {
            fd = damping.force(force, v_old);
            v_free = v_old + (force - fd) * dt / mass;
          } else {
            v_free = v_old + force * dt / mass;
          }
          const real v_new = prescribed ? vp[i] : v_free;
          r[i] = prescribed ? reaction : r[i];
          boundary += prescribed ? reaction * 0.5 * (v_old + v_new) * dt : real(0);
          if constexpr (D::enabled) damped += prescribed ? real(0) : fd * 0.5 * (v_old + v_new) * dt;
          v[i] = v_new;
          u[i] += v_new * dt;
        }
#else
        step_work w{boundary, damped};
        for (std::int64_t i = begin; i < end; ++i) {
          v[i] = advance_dof(f[i], m[i], v[i], con[i], vp[i], dt, r[i], w);
          u[i] += v[i] * dt;
        }
        boundary = w.boundary;
        damped = w.damping;
#endif
      }
      partial[static_cast<std::size_t>(k)] = step_work{boundary, damped};
    }, 1);
    for (std::int64_t k = 0; k < chunks; ++k) {
      work.boundary += partial[static_cast<std::size_t>(k)].boundary;
      work.damping += partial[static_cast<std::size_t>(k)].damping;
    }
  }
};

static_assert(Integrator<central_difference<local_damping>>);
static_assert(Integrator<central_difference<no_damping>>);

/// The two schemes by what they are for, so a scene names its choice where it builds its solver
/// (solver<Blocks, Contacts, Reinforcement, integrator::dynamic>):
///   quasi_static  central differences with local damping (solver_options::damping_gamma, 0.8 by
///                 default): the solver's default; settling, stability and quasi-static loading,
///                 where the damping removes the kinetic energy of each oscillation;
///   dynamic       central differences without damping: impacts, sliding, toppling, rocking,
///                 any motion whose time history is the result (local damping slows such a
///                 motion by a force gamma |F| that no physics supplies).
/// Each solver's run result names the damping in force (run_result::damping).
using quasi_static = central_difference<local_damping>;
using dynamic = central_difference<no_damping>;

}  // namespace tessera::integrator
