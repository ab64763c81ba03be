#pragma once
// How sharp the solver's stable step is: lambda_max(M^-1 K) of a scene, estimated with the
// solver's own force kernels, against the Gershgorin bound the time step is chosen from
// (integrator/timestep.hpp).
//
// The solver picks dt = safety x dt_cr, dt_cr = min_i 2 sqrt(m_i / (a k_i)) = 2 / sqrt(a lambda_G),
// lambda_G = max_i k_i / m_i >= lambda_max(M^-1 K) (Gershgorin row sums; a = the damping's stiffness
// amplification). The exact limit of the undamped linear scheme is 2 / sqrt(a lambda_max). The ratio
// lambda_G / lambda_max says what a sharper bound could give: at the same masses a step
// sqrt(lambda_G / lambda_max) times larger, or at the same step less added mass.
//
// Method: Lanczos on the symmetric form A = M^-1/2 K M^-1/2 over the free degrees of freedom
// (a Krylov refinement of power iteration: the same operator products, but its largest Ritz value
// converges much faster where the top of the spectrum is dense, as it is in a zoned mesh), with
// full reorthogonalization. Each product K v is a directional derivative of the internal force,
// by central differences (f(u - h v) - f(u + h v)) / (2 h), each force evaluated on COPIES of the
// solver's gridpoints, blocks, contact set and reinforcement: the solver is not changed. The
// contacts see the probe displacement as their increment of one step (velocity h v / dt), so they
// respond with the stiffness of their present state (elastic at the start of a run). The largest
// Ritz value is a lower bound on lambda_max (a Rayleigh quotient); its residual ||A y - theta y||
// bounds the distance from theta to the nearest eigenvalue.
//
// What K holds: zones, contact springs, bar axial and bond springs, i.e. what add_stiffness_bounds
// of blocks, contacts and bars bound. Forces applied from outside the model (a contact::rigid_platen
// registered with register_applied_forces) are not in K; their springs are in lambda_G.
// Deformable blocks only (rigid blocks' degrees of freedom are the bodies', not the gridpoints').
//
// Cost: 2 force evaluations (each with a copy of the model's state) per iteration, and memory for
// `iterations` vectors of the free degrees of freedom (8 bytes each). Not thread-safe on one
// solver with a concurrent step(); the solver may be shared between concurrent estimates (const).
// A template on the solver type: nothing here needs solver/solver.hpp, so including it costs little.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "../core/errors.hpp"
#include "../core/nodes.hpp"
#include "../core/types.hpp"

namespace tessera::analysis {

/// Settings of estimate_max_frequency_squared.
struct spectral_options {
  int iterations = 200;      ///< most Lanczos steps (operator products), >= 1
  real tolerance = 1e-8;     ///< stop when ||A y - theta y|| / theta falls below this (> 0, < 1)
  /// ... but not before this many steps: a Ritz pair can converge to a large eigenvalue of one
  /// sliver zone before a larger one elsewhere has entered the Krylov space (>= 1)
  int min_iterations = 30;
  real probe = 1e-9;         ///< largest nodal probe displacement h max|v_i| (m) of the difference quotient
  std::uint64_t seed = 1;    ///< seed of the random start vector (the estimate is deterministic for a seed)
};

/// lambda_max(M^-1 K) as Lanczos found it.
struct spectral_estimate {
  real lambda_max = 0;  ///< largest Ritz value of M^-1 K (1/s^2), a lower bound on the true one
  real residual = 0;    ///< ||A y - theta y|| / theta of its Ritz pair (relative, A = M^-1/2 K M^-1/2)
  int iterations = 0;   ///< operator products used
  index_t dofs = 0;     ///< free degrees of freedom the operator acts on
  [[nodiscard]] bool converged(real tolerance) const { return residual <= tolerance; }  ///< True when the residual is at most tolerance
};

/// lambda_max of M^-1 K over n degrees of freedom of masses dof_mass (kg, each > 0), with
/// stiffness_times(v, out) writing out = K v (N for v in m; K symmetric). Lanczos with full
/// reorthogonalization from a random start (file comment). Throws invalid_input, before any
/// product, for an empty mass vector, a non-finite or non-positive mass (naming the degree of
/// freedom) or bad options, and for a non-finite product (naming the Lanczos step).
template <class StiffnessTimes>
[[nodiscard]] spectral_estimate estimate_max_frequency_squared(const Eigen::VectorXd& dof_mass,
                                                              StiffnessTimes&& stiffness_times,
                                                              const spectral_options& o = {}) {
  const index_t n = dof_mass.size();
  require(n > 0, "spectral bound: no free degree of freedom to estimate lambda_max over");
  require(o.iterations >= 1, "spectral bound: iterations = ", o.iterations, " must be >= 1");
  require(o.min_iterations >= 1, "spectral bound: min_iterations = ", o.min_iterations, " must be >= 1");
  require(std::isfinite(o.tolerance) && o.tolerance > 0 && o.tolerance < 1, "spectral bound: tolerance = ", o.tolerance,
          " must lie in (0, 1)");
  for (index_t i = 0; i < n; ++i)
    require(std::isfinite(dof_mass[i]) && dof_mass[i] > 0, "spectral bound: degree of freedom ", i, " has mass ",
            dof_mass[i], " kg; expected finite and > 0");
  const Eigen::VectorXd inv_sqrt_m = dof_mass.cwiseSqrt().cwiseInverse();
  const int max_steps = static_cast<int>(std::min<index_t>(o.iterations, n));

  std::vector<Eigen::VectorXd> q;  // Lanczos vectors (orthonormal in the plain inner product)
  q.reserve(static_cast<std::size_t>(max_steps) + 1);
  std::vector<real> alpha, beta;  // diagonal and off-diagonal of T
  {
    std::mt19937_64 rng(o.seed);
    std::uniform_real_distribution<real> u(-1, 1);
    Eigen::VectorXd start(n);
    for (index_t i = 0; i < n; ++i) start[i] = u(rng);
    q.push_back(start.normalized());
  }
  Eigen::VectorXd kv(n), z(n);
  spectral_estimate out;
  out.dofs = n;
  for (int j = 0; j < max_steps; ++j) {
    // z = A q_j = M^-1/2 K M^-1/2 q_j
    const Eigen::VectorXd v = inv_sqrt_m.cwiseProduct(q[static_cast<std::size_t>(j)]);
    kv.setZero();
    stiffness_times(v, kv);
    require(kv.allFinite(), "spectral bound: the stiffness product of Lanczos step ", j, " is not finite");
    z = inv_sqrt_m.cwiseProduct(kv);
    alpha.push_back(q[static_cast<std::size_t>(j)].dot(z));
    // Full reorthogonalization, twice ("twice is enough"): keeps T's spectrum free of ghost copies.
    for (int pass = 0; pass < 2; ++pass)
      for (const Eigen::VectorXd& qi : q) z -= qi.dot(z) * qi;
    const real b = z.norm();
    out.iterations = j + 1;
    // Ritz values of T_j (tridiagonal, symmetric): the largest and its residual b |s_last|.
    const auto k = static_cast<index_t>(alpha.size());
    Eigen::VectorXd diag = Eigen::Map<const Eigen::VectorXd>(alpha.data(), k);
    Eigen::VectorXd sub = k > 1 ? Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(beta.data(), k - 1))
                                : Eigen::VectorXd(0);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> tri;
    tri.computeFromTridiagonal(diag, sub, Eigen::ComputeEigenvectors);
    const index_t top = k - 1;  // eigenvalues in increasing order
    out.lambda_max = tri.eigenvalues()[top];
    const real scale = std::max(std::abs(out.lambda_max), std::numeric_limits<real>::min());
    out.residual = b * std::abs(tri.eigenvectors()(k - 1, top)) / scale;
    // An invariant subspace (b ~ 0 against the operator's size) makes the Ritz values exact.
    if ((out.residual <= o.tolerance && j + 1 >= o.min_iterations) || b <= 1e-14 * scale) break;
    beta.push_back(b);
    q.push_back(z / b);
  }
  return out;
}

/// Result of estimate_max_frequency_squared on a solver: the estimate beside the solver's own bound.
struct stable_step_sharpness {
  spectral_estimate estimate;  ///< lambda_max(M^-1 K) (1/s^2), undamped, scaled masses as they stand
  real gershgorin = 0;         ///< lambda_G = 4 / (a dt_cr^2) = max_i k_i / m_i of the solver's step (1/s^2)
  real amplification = 1;      ///< a, the damping's stiffness amplification in the step
  /// lambda_G / lambda_max (>= 1 when the bound holds): how much the Gershgorin bound overstates.
  [[nodiscard]] real ratio() const { return gershgorin / estimate.lambda_max; }
  /// The solver's critical step 2 / sqrt(a lambda_G) (s), before the safety factor.
  [[nodiscard]] real gershgorin_step() const { return 2 / std::sqrt(amplification * gershgorin); }
  /// The critical step of the estimate, 2 / sqrt(a lambda_max) (s), before the safety factor.
  [[nodiscard]] real spectral_step() const { return 2 / std::sqrt(amplification * estimate.lambda_max); }
};

/// lambda_max(M^-1 K) of a solver's scene (deformable blocks) with its present masses and contact
/// states, by Lanczos on its own force kernels (file comment), beside the Gershgorin bound of its
/// step (solver.critical_step()). Leaves the solver unchanged. Throws invalid_input for bad options
/// (spectral_options), a non-positive probe, or a scene with no free degree of freedom.
template <class Solver>
[[nodiscard]] stable_step_sharpness estimate_max_frequency_squared(const Solver& s, const spectral_options& o = {}) {
  static_assert(!Solver::blocks_type::is_rigid,
                "estimate_max_frequency_squared: rigid blocks move as bodies; the gridpoint operator is for deformable blocks");
  constexpr bool bars = Solver::reinforcement_type::enabled;
  require(std::isfinite(o.probe) && o.probe > 0, "spectral bound: probe displacement = ", o.probe,
          " m must be finite and > 0");
  const node_set& gp = s.gridpoints();
  const index_t n_gp = gp.size();
  index_t n_bar = 0;
  if constexpr (bars) n_bar = s.bar_nodes().size();
  // Free degrees of freedom: node (gridpoints, then bar nodes) and component.
  const auto node_of = [&](index_t i) -> const node_set& {
    if constexpr (bars)
      if (i >= n_gp) return s.bar_nodes();
    return gp;
  };
  std::vector<index_t> dof;  // 3 node + c
  for (index_t i = 0; i < n_gp + n_bar; ++i) {
    const node_set& ns = node_of(i);
    const index_t local = i < n_gp ? i : i - n_gp;
    for (int c = 0; c < 3; ++c)
      if (ns.constraint(local, c) == static_cast<std::uint8_t>(dof_constraint::free)) dof.push_back(3 * i + c);
  }
  Eigen::VectorXd mass(static_cast<index_t>(dof.size()));
  for (std::size_t d = 0; d < dof.size(); ++d) {
    const index_t i = dof[d] / 3;
    mass[static_cast<index_t>(d)] = node_of(i).mass[i < n_gp ? i : i - n_gp];
  }
  const real dt = s.dt();
  // Internal force at u + h v (v over the free dofs), on copies of the model's state; the
  // contact sees h v as this step's increment.
  const auto force_at = [&](const Eigen::VectorXd& v, real h, Eigen::VectorXd& f) {
    node_set probe_gp = gp;
    node_set probe_bars;
    if constexpr (bars) probe_bars = s.bar_nodes();
    for (std::size_t d = 0; d < dof.size(); ++d) {
      const index_t i = dof[d] / 3;
      const int c = static_cast<int>(dof[d] % 3);
      const real du = h * v[static_cast<index_t>(d)];
      if (i < n_gp) {
        probe_gp.displacement(i, c) += du;
        probe_gp.velocity(i, c) = du / dt;
      } else {
        probe_bars.displacement(i - n_gp, c) += du;
        probe_bars.velocity(i - n_gp, c) = du / dt;
      }
    }
    probe_gp.force.setZero();
    auto blocks = s.blocks();
    blocks.accumulate_forces(probe_gp);
    auto contacts = s.contacts();
    contacts.update(probe_gp, dt);
    if constexpr (bars) {
      auto reinforcement = s.reinforcement();
      reinforcement.nodes() = probe_bars;
      reinforcement.nodes().force.setZero();
      reinforcement.accumulate_forces(probe_gp, blocks.zone_stress());
      probe_bars = reinforcement.nodes();
    }
    for (std::size_t d = 0; d < dof.size(); ++d) {
      const index_t i = dof[d] / 3;
      const int c = static_cast<int>(dof[d] % 3);
      f[static_cast<index_t>(d)] = i < n_gp ? probe_gp.force(i, c) : probe_bars.force(i - n_gp, c);
    }
  };
  Eigen::VectorXd f_plus(mass.size()), f_minus(mass.size());
  const auto stiffness_times = [&](const Eigen::VectorXd& v, Eigen::VectorXd& kv) {
    const real h = o.probe / v.cwiseAbs().maxCoeff();
    force_at(v, h, f_plus);
    force_at(v, -h, f_minus);
    kv = (f_minus - f_plus) / (2 * h);  // K v = -df/du v
  };
  stable_step_sharpness out;
  out.estimate = estimate_max_frequency_squared(mass, stiffness_times, o);
  out.amplification = s.stiffness_amplification();
  const real dt_cr = s.critical_step().dt;
  out.gershgorin = 4 / (out.amplification * dt_cr * dt_cr);
  return out;
}

}  // namespace tessera::analysis
