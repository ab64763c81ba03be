#pragma once
// The closed form of a bar bonded in a held host and pulled at its last node (test_relaxation,
// test_stability "[implicit]"): with the host held, bar node n hangs on its bond spring k_b(n) to
// the ground and on its trusses k_a to its neighbours, so the free nodes 0 .. last - 1 solve the
// chain K u = f with u_last = pull, and the pull-out force is k_b(last) pull + k_a (pull - u_{last-1}).
#include <Eigen/Dense>

#include "tessera/core/types.hpp"

namespace tessera::test {

struct bar_chain_solution {
  Eigen::VectorXd u;   ///< axial displacements of nodes 0 .. last - 1 (m)
  real pull_out = 0;   ///< force on the pulled node (N)
};

/// `truss`: anything with bond_stiffness(n) and axial_stiffness(e) (N/m), element e between nodes
/// e and e + 1 (one bar); `last` the pulled node, moved by `pull` (m).
template <class Truss>
[[nodiscard]] bar_chain_solution pulled_bar_chain(const Truss& truss, index_t last, real pull) {
  Eigen::MatrixXd chain = Eigen::MatrixXd::Zero(last, last);
  Eigen::VectorXd load = Eigen::VectorXd::Zero(last);
  for (index_t n = 0; n < last; ++n) {
    chain(n, n) += truss.bond_stiffness(n) + truss.axial_stiffness(n);
    if (n > 0) chain(n, n) += truss.axial_stiffness(n - 1), chain(n, n - 1) = chain(n - 1, n) = -truss.axial_stiffness(n - 1);
  }
  load(last - 1) = truss.axial_stiffness(last - 1) * pull;
  bar_chain_solution s;
  s.u = chain.ldlt().solve(load);
  s.pull_out = truss.bond_stiffness(last) * pull + truss.axial_stiffness(last - 1) * (pull - s.u(last - 1));
  return s;
}

}  // namespace tessera::test
