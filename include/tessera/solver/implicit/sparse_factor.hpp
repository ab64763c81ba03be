#pragma once
// implicit::sparse_factor: the sparse Cholesky factorisation of the implicit solve's secant
// stiffness (quasi_static.hpp), one interface over two factorisations:
//
//   factorization::simplicial  Eigen::SimplicialLDLT, AMD ordering, column by column. Always there.
//   factorization::supernodal  CHOLMOD's supernodal LL^T (Eigen::CholmodSupernodalLLT): dense
//                              blocks of columns (supernodes) factorised with the BLAS, its own
//                              choice of ordering (AMD, METIS where its fill is much lower). Only
//                              where tessera was built with TESSERA_CHOLMOD (CMake, on where
//                              Debian's libsuitesparse-dev is found; TESSERA_HAVE_CHOLMOD = 1),
//                              so a target that wants it links tessera::cholmod.
//
// Both solve K x = b to the same tolerance (the secant stiffness is symmetric positive definite
// on the free components of a supported model); their round-off differs, so a run with one does not
// give the other's bits. With Debian's reference BLAS (libblas3, one thread) CHOLMOD is
// deterministic; an alternative BLAS with threads (OpenBLAS) may change the last bits with its
// thread count. Every unit of one program must agree on TESSERA_HAVE_CHOLMOD (the class's layout
// depends on it): link tessera::cholmod to the whole target, as CMake does for its definitions.
//
// Not thread-safe; not copyable (neither factor is).

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#if defined(TESSERA_HAVE_CHOLMOD)
#include <Eigen/CholmodSupport>
#endif

#include "../../core/errors.hpp"
#include "../../core/types.hpp"

namespace tessera::implicit {

enum class factorization {
  simplicial,  ///< Eigen::SimplicialLDLT (always built)
  supernodal,  ///< CHOLMOD's supernodal LL^T (needs TESSERA_CHOLMOD)
};

/// "simplicial" or "supernodal".
[[nodiscard]] inline std::string_view factorization_name(factorization f) noexcept {
  return f == factorization::supernodal ? "supernodal" : "simplicial";
}

/// Whether this build has CHOLMOD's supernodal factorisation (TESSERA_HAVE_CHOLMOD).
[[nodiscard]] constexpr bool supernodal_available() noexcept {
#if defined(TESSERA_HAVE_CHOLMOD)
  return true;
#else
  return false;
#endif
}

/// The factorisation a quasi_static model uses unless told otherwise: the supernodal one where this
/// build has it, else the simplicial one. Measured on the prism's elastic branch
/// (docs/performance.md, "The sparse factorisation"): with Debian's OpenBLAS the supernodal factor
/// is 1.5-4x faster at 100-500 blocks and 14x at 1 000 (2.0 against 28.1 s), with the reference
/// BLAS 1.4-2x from 500 blocks on and even below.
[[nodiscard]] constexpr factorization default_factorization() noexcept {
  return supernodal_available() ? factorization::supernodal : factorization::simplicial;
}

/// The factorisation named `name` ("simplicial" or "supernodal"); throws invalid_input naming it
/// when it is neither, or when it is "supernodal" in a build without CHOLMOD.
[[nodiscard]] inline factorization parse_factorization(std::string_view name) {
  if (name == "simplicial") return factorization::simplicial;
  require(name == "supernodal", "factorization '", std::string(name), "' is not one of simplicial, supernodal");
  require(supernodal_available(), "factorization 'supernodal' needs CHOLMOD, and this build has none: configure with ",
          "-DTESSERA_CHOLMOD=ON where SuiteSparse is installed (Debian: libsuitesparse-dev) and link tessera::cholmod");
  return factorization::supernodal;
}

/// Sparse Cholesky factorisation of the secant stiffness: Eigen's SimplicialLDLT, or CHOLMOD's supernodal LL^T where built in (file comment)
class sparse_factor {
 public:
  using matrix = Eigen::SparseMatrix<real>;  ///< the matrix type factorised (lower triangle used)

  /// A factor of kind `kind`; throws invalid_input for factorization::supernodal in a build
  /// without CHOLMOD.
  explicit sparse_factor(factorization kind = default_factorization()) : kind_(kind) {
    require(kind != factorization::supernodal || supernodal_available(), "sparse_factor: factorization 'supernodal' ",
            "needs CHOLMOD, and this build has none (configure with -DTESSERA_CHOLMOD=ON, Debian: libsuitesparse-dev)");
#if defined(TESSERA_HAVE_CHOLMOD)
    if (kind == factorization::supernodal) {
      supernodal_ = std::make_unique<supernodal_type>();
      supernodal_->cholmod().print = 0;  // a failure is reported by info(), with our own words
    }
#endif
  }
  sparse_factor(const sparse_factor&) = delete;
  sparse_factor& operator=(const sparse_factor&) = delete;

  [[nodiscard]] factorization kind() const noexcept { return kind_; }  ///< The factorisation in use

  /// The ordering and symbolic factorisation of k's pattern (k symmetric, its lower triangle read).
  void analyze(const matrix& k) {
#if defined(TESSERA_HAVE_CHOLMOD)
    if (supernodal_) {
      supernodal_->analyzePattern(k);
      return;
    }
#endif
    simplicial_.analyzePattern(k);
  }

  /// The numeric factorisation of k (the pattern of the last analyze); false when it failed
  /// (k not positive definite, or singular).
  [[nodiscard]] bool factorize(const matrix& k) {
#if defined(TESSERA_HAVE_CHOLMOD)
    if (supernodal_) {
      supernodal_->factorize(k);
      return supernodal_->info() == Eigen::Success;
    }
#endif
    simplicial_.factorize(k);
    return simplicial_.info() == Eigen::Success;
  }

  /// x with K x = b, K the last factorised matrix; false in `ok` is a failed solve.
  [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& b, bool* ok = nullptr) const {
    Eigen::VectorXd x;
    bool good = false;
#if defined(TESSERA_HAVE_CHOLMOD)
    if (supernodal_) {
      x = supernodal_->solve(b);
      good = supernodal_->info() == Eigen::Success;
    } else
#endif
    {
      x = simplicial_.solve(b);
      good = simplicial_.info() == Eigen::Success;
    }
    if (ok != nullptr) *ok = good;
    return x;
  }

  /// Non-zeros of the factor L (for the supernodal factor, CHOLMOD's count of L's entries, without
  /// the zeros its dense supernodes store).
  [[nodiscard]] std::int64_t nonzeros() const {
#if defined(TESSERA_HAVE_CHOLMOD)
    if (supernodal_) return static_cast<std::int64_t>(supernodal_->cholmod().lnz);
#endif
    return static_cast<std::int64_t>(simplicial_.matrixL().nestedExpression().nonZeros());
  }

 private:
  factorization kind_;
  Eigen::SimplicialLDLT<matrix> simplicial_;
#if defined(TESSERA_HAVE_CHOLMOD)
  using supernodal_type = Eigen::CholmodSupernodalLLT<matrix>;
  std::unique_ptr<supernodal_type> supernodal_;
#endif
};

}  // namespace tessera::implicit
