// Built only where the installed package has tessera::cholmod: the supernodal factorisation of the
// implicit solve, found through find_package(tessera COMPONENTS cholmod), solves a small SPD system
// (a chain of three unit springs fixed at one end) to round-off.
#include <cmath>
#include <cstdio>

#include <tessera/solver/implicit/sparse_factor.hpp>

int main() {
  namespace im = tessera::implicit;
  static_assert(im::supernodal_available(), "tessera::cholmod must define TESSERA_HAVE_CHOLMOD");
  im::sparse_factor f(im::factorization::supernodal);
  Eigen::SparseMatrix<double> k(3, 3);  // springs 0-1, 1-2, 2-3 with dof 0's end fixed
  k.insert(0, 0) = 2;
  k.insert(1, 0) = -1;
  k.insert(0, 1) = -1;
  k.insert(1, 1) = 2;
  k.insert(2, 1) = -1;
  k.insert(1, 2) = -1;
  k.insert(2, 2) = 1;
  f.analyze(k);
  bool solved = false;
  const Eigen::VectorXd x = f.factorize(k) ? f.solve(Eigen::Vector3d(0, 0, 1), &solved) : Eigen::VectorXd();
  // A unit pull at the free end stretches each spring by 1: x = (1, 2, 3).
  const bool ok = solved && x.size() == 3 && (x - Eigen::Vector3d(1, 2, 3)).norm() < 1e-12;
  std::printf("supernodal factor: x = (%g, %g, %g), %s\n", x.size() == 3 ? x[0] : 0.0, x.size() == 3 ? x[1] : 0.0,
              x.size() == 3 ? x[2] : 0.0, ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
