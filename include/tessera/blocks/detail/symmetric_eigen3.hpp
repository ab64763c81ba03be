#pragma once
// Eigenvalues and eigenvectors of a symmetric 3x3 matrix by cyclic Jacobi rotations, for the
// principal moments and axes of a rigid block's inertia tensor (blocks::rigid::build).
//
// Why not Eigen::SelfAdjointEigenSolver<mat3>: rigid::build is an ordinary (non-template) inline
// function, so GCC 12 at -O2 instantiated and compiled Eigen's tridiagonalisation + implicit QR in
// every translation unit including blocks/rigid.hpp, called or not (about 4 s of CPU each, issue
// #40 item 9, notes/h6_compile.md "rigid eigen solver"). A 3x3 Jacobi sweep is a few dozen
// scalar operations and costs nothing to compile.
//
// Method: cyclic sweeps over the pairs (0,1), (0,2), (1,2); each rotation zeroes a(p,q) with the
// smaller of the two angles (Rutishauser's formulas, t = tan(angle), |angle| <= pi/4). An
// off-diagonal entry is negligible, and set to zero without a rotation, once
// |a(p,q)| <= eps sqrt(|a(p,p) a(q,q)|) (Demmel and Veselic's criterion: the eigenvalues of a
// positive definite matrix then keep their relative accuracy) or it is below the smallest normal
// number over eps. Convergence is quadratic: 3-6 sweeps from any symmetric start; the loop stops at
// the first sweep that leaves every off-diagonal entry zero (at most 50 sweeps, never reached).
// Then the eigenvalues are sorted ascending (ties keep Jacobi's order), each of the first two
// eigenvectors is signed so that its entry of largest magnitude (the first such entry on a tie) is
// positive, and the third is flipped if needed so that det[e1 e2 e3] = +1. Only fixed operations in
// a fixed order: the same input gives the same bits on every run and thread.

#include <cmath>
#include <limits>
#include <utility>

#include "../../core/separate_compilation.hpp"
#include "../../core/types.hpp"

namespace tessera::blocks::detail {

/// Eigen decomposition a = vectors diag(values) vectors^T of a symmetric 3x3 matrix.
struct symmetric_eigen3 {
  vec3 values = vec3::Zero();             ///< eigenvalues, ascending (units of the matrix)
  mat3 vectors = mat3::Identity();        ///< unit eigenvectors as columns, orthonormal, det = +1
  int sweeps = 0;                         ///< Jacobi sweeps made (diagnostics)
};

/// Cyclic Jacobi eigen solver for a symmetric 3x3 matrix (only the lower triangle of a is read,
/// as Eigen's SelfAdjointEigenSolver does). See the file comment for conventions.
TESSERA_INLINE symmetric_eigen3 symmetric_eigen_3x3(const mat3& a_in) noexcept;

}  // namespace tessera::blocks::detail

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/symmetric_eigen3.ipp"
#endif
