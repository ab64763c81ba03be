#pragma once
// The increments of implicit::quasi_static (quasi_static.hpp): how each is iterated to
// equilibrium, its options and its results, and the line search on the energy.
//
// Increment (solve_increment). The prescribed components move; then, from the states committed at
// the last equilibrium, secant iterations
//     1. each sub-contact's state = Law::update(committed state, relative displacement since
//        the last equilibrium, its normal): one law step from the committed state, so a
//        monotonic branch is followed in closed form (the softening envelope at the total opening);
//     2. the out-of-balance force r = f(u) on the free components; converged when max |r| <=
//        force_tolerance (N);
//     3. K_sec on the free components, of the last equilibrium's states in the first iteration of
//        an increment and of the states of step 1 after it (with a floor of stiffness_floor x k
//        on sub-contacts whose secant is zero, so a block freed by cracks keeps K non-singular; the
//        floor shapes the iteration only, not the equilibrium it converges to), factorised when
//        a secant changed since the last factorisation (elastic branch: once), then
//        K_sec du = r, u += omega du, omega = 1 in the first iteration and Aitken's factor after it
//        (increment_options::aitken; it speeds the linear convergence of the secant iteration on a
//        softening branch several-fold). With refactor_each_iteration = false the factor of the
//        first iteration serves the whole increment (more iterations, no factorisation).
// On convergence the states are committed; otherwise the model returns to its last equilibrium
// (displacements and states) and reports the residual, so the caller can retry with a smaller
// increment. The secant iteration converges at a rate set by how far the secant is from the
// tangent; it fails when the load path snaps back (a softening branch steeper than the
// unloading of the rest of the model), which displacement control cannot follow, and where the
// path branches (several cracks that could open, one of which unloads the others): the iterates
// then hop between cracking patterns (increment_result::reversals).
//
// Path following (solve_controlled_increment). Past the peak the load path of a softening model
// can snap back: the prescribed displacement must decrease while the cracks open on. The
// increment is then controlled by the opening of the cracks, not by the supports: the prescribed
// displacements are lambda x velocity (lambda the pseudo-time, s), lambda an extra unknown, and
// the extra equation
//     sum_{i in S} A_i sigma_i n_i . (d_i - d_i^0) = Delta_tau   (J),
// S the sub-contacts softening in tension at the last equilibrium, or intact within 1e-3 of their
// tensile strength (so the control can start at the peak of a face that has not softened yet),
// with sigma_i > 0 their committed normal stress, d_i^0 their relative displacement there: the work of the committed crack
// tractions on the opening increment, to first order the energy the increment dissipates in the
// cracks (a softening sub-contact advancing on its envelope dissipates sigma dw; one closing
// returns its elastic energy), a linear form of u in the spirit of the dissipation-based
// arc-length of Gutierrez (2004) and Verhoosel, Remmers and Gutierrez (2009) and of the
// crack-opening control with the pattern weighted by the crack stresses. Each iteration is the
// bordered solve with the factor of the increment's first iteration,
//     a = K_sec^-1 r,   b = -K_sec^-1 K_fp v   (b once per factorisation the mode uses),
//     du_f = a + dlambda b,   dlambda from the constraint (linear: met exactly after every iteration),
// K_fp v the coupling of the free components to a unit motion of the prescribed ones. Because the
// constraint fixes the crack openings' projection, a single localising crack is driven in closed
// form by its law, so the iteration follows a snap-back (dlambda < 0) that displacement control
// cannot. No Aitken or line search in this mode. What no scalar control removes: where the
// tangent of the modes the constraint leaves free is negative (several softening cracks of
// which one can localise and unload the others, a bifurcation), the secant iteration, whose
// factor is positive definite, moves away from that equilibrium or hops between cracking
// patterns; on the 100-block prism this happens at the peak (benchmarks/implicit_prism
// --path-following). control_fraction restricts the control set to the sub-contacts that opened
// most in the last increment; unload_outside_control factorises the softening sub-contacts
// outside it with their unloading stiffnesses k_n, k_s, the tangent of the branch on which they
// unload while the controlled crack opens: with both (0.5, true) the prism's solve passes that
// peak, along a snap-back of the top displacement (76.22 -> 75.56 um), and stops at 77.9 um.
//

#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "../../core/errors.hpp"
#include "../../core/types.hpp"

namespace tessera::implicit {

/// Settings of one increment.
struct increment_options {
  real force_tolerance = 0;     ///< converged when the largest free out-of-balance component <= this (N), > 0
  int max_iterations = 50;      ///< secant iterations (linear solves) before giving up, >= 1
  real stiffness_floor = 1e-6;  ///< a zero secant is replaced by this x k_n (k_s) in K only, in [0, 1)
  bool aitken = true;           ///< relax the secant steps by Aitken's factor (file comment)
  /// step length by a line search on the energy instead (search_along, below; Aitken is then off)
  bool line_search = false;
  /// false: K_sec of the last equilibrium factorised once per increment, its iterations reuse
  /// the factor (on the 100-block prism to its peak 45 factorisations and 3.6 s against 3585 and
  /// 84 s); true: K_sec of the latest states factorised in every iteration
  bool refactor_each_iteration = false;
  /// solve_controlled_increment: the control set keeps only the sub-contacts whose opening in the
  /// last converged increment was at least this fraction of the largest one (the localising
  /// crack), in [0, 1]; 0 keeps every softening one
  real control_fraction = 0;
  /// solve_controlled_increment: softening sub-contacts outside the control set enter K with
  /// their elastic (unloading) stiffnesses k_n, k_s instead of their secants, so the iteration
  /// expects them to unload while the controlled crack opens
  bool unload_outside_control = false;
};

/// What one increment did.
struct increment_result {
  bool converged = false;  ///< the residual fell below the tolerance within the iterations allowed
  int iterations = 0;          ///< linear solves
  real max_residual = 0;       ///< largest free out-of-balance component at the end (N)
  index_t softening = 0;       ///< sub-contacts softening in tension (or broken) after the increment
  index_t broken = 0;          ///< sub-contacts broken in tension after the increment
  index_t slipped = 0;         ///< sub-contacts that have slipped after the increment
  /// Sub-contacts whose tensile strength the last iterate lowers (advancing along the envelope),
  /// and how many of them changed between advancing and not in the last iteration: a count that
  /// stays high while the residual stalls marks an iteration that hops between cracking patterns
  /// (a bifurcation of the equilibrium path), which secant iterations cannot settle.
  index_t advancing = 0;
  index_t reversals = 0;  ///< of advancing, those that changed between advancing and not in the last iteration
};

/// Work done so far, for the comparison with the explicit solver.
struct solve_counts {
  std::int64_t increments = 0;         ///< load increments advanced
  std::int64_t iterations = 0;         ///< secant iterations over all increments
  std::int64_t force_evaluations = 0;  ///< evaluations of the internal forces
  std::int64_t analyses = 0;           ///< symbolic analyses of the stiffness pattern
  std::int64_t factorizations = 0;     ///< numeric factorisations
  std::int64_t solves = 0;             ///< triangular solves
  double assembly_s = 0;               ///< wall-clock seconds assembling the stiffness
  double factorization_s = 0;          ///< wall-clock seconds factorising
  double solve_s = 0;                  ///< wall-clock seconds in the solves
  double force_s = 0;                  ///< wall-clock seconds evaluating forces
  [[nodiscard]] double total_s() const { return assembly_s + factorization_s + solve_s + force_s; }  ///< Wall-clock seconds in all four (s)
};

/// Refuses bad increment options, naming the value (invalid_input), before anything changes.
inline void require_valid_increment_options(const increment_options& o) {
  require_positive(o.force_tolerance, "quasi_static: force tolerance (N)");
  require(o.max_iterations >= 1, "quasi_static: max_iterations = ", o.max_iterations, " must be >= 1");
  require(o.stiffness_floor >= 0 && o.stiffness_floor < 1, "quasi_static: stiffness floor = ", o.stiffness_floor,
          " must lie in [0, 1)");
}

/// The step length alpha along a descent direction where the energy stops falling: a root of the
/// directional derivative g(alpha) = -f(u + alpha step) . step (f = -grad of the energy, zone and
/// contact work), by regula falsi (Illinois) on [0, 1] when g(1) > 0, else alpha = 1 extended by
/// doublings up to 8 while g stays negative; at most 8 evaluations of `slope` (which moves the
/// model to u + alpha step and returns g there; the last call is at the returned alpha). g0 =
/// g(0) < 0 (K_sec positive definite: g(0) = -f . K^-1 f). A descent step of the secant direction
/// lets the iterates settle on a branch of lower energy where plain steps hop between cracking
/// patterns.
template <class Slope>
[[nodiscard]] real energy_line_search(real g0, Slope&& slope) {
  real a = 0, ga = g0, b = 1, gb = slope(real(1));
  int evaluations = 1;
  while (gb < 0 && b < 8 && evaluations < 8) {
    a = b, ga = gb;
    b *= 2;
    gb = slope(b);
    ++evaluations;
  }
  if (gb < 0) return b;  // still descending at the largest step: keep it
  real alpha = b;
  int side = 0;
  while (evaluations < 8 && std::abs(gb) > 0.5 * std::abs(g0)) {
    alpha = (a * gb - b * ga) / (gb - ga);
    const real g = slope(alpha);
    ++evaluations;
    if (g > 0) {
      b = alpha, gb = g;
      if (side == -1) ga *= 0.5;
      side = -1;
    } else {
      a = alpha, ga = g;
      if (side == 1) gb *= 0.5;
      side = 1;
    }
    if (std::abs(g) <= 0.5 * std::abs(g0)) break;
  }
  return alpha;
}

/// u += alpha step with alpha where the energy stops falling along the step (energy_line_search),
/// `evaluate()` refreshing `force` (N, the model's f(u)) at each trial u; the plain step when it is
/// not a descent direction (round-off at convergence), the forces then not evaluated.
template <class Evaluate>
void search_along(Eigen::VectorXd& u, const Eigen::VectorXd& force, const Eigen::VectorXd& step, Evaluate&& evaluate) {
  const Eigen::VectorXd base = u;
  const real g0 = -force.dot(step);
  if (!(g0 < 0)) {
    u = base + step;
    return;
  }
  const real alpha = energy_line_search(g0, [&](real a) {
    u = base + a * step;
    evaluate();
    return -force.dot(step);
  });
  u = base + alpha * step;
}

}  // namespace tessera::implicit
