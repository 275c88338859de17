// A sparse direct factorisation of a distributed Tpetra::CrsMatrix, factored
// once and solved many times (the inner step of every shift-invert).
//
//   "KLU2"    Amesos2's LU: any nonsingular matrix (nonsymmetric shifted
//             gyroscopic pencils, the real form of complex shifts).
//   "Tacho"   Amesos2's multifrontal factorisation (Trilinos' own); in this
//             build a Cholesky, so symmetric positive definite matrices only
//             (an indefinite one is reported as Outcome::Singular).
//   "CHOLMOD" SuiteSparse's supernodal Cholesky, called directly because
//             Amesos2 here has no CHOLMOD adapter: symmetric positive
//             definite matrices only, and it *reports* when the matrix is not
//             positive definite, which is how the eigen layer decides that
//             Meirovitch's symmetric form applies.
// The distributed matrix and right-hand sides are gathered to rank 0 for the
// factorisation and solves (as Amesos2 does for its serial solvers); results
// are scattered back to the caller's maps. All calls are collective.
#pragma once

#include <memory>
#include <string>

#include "cms/core/TpetraTypes.hpp"

namespace cms {

class SparseDirectSolver {
public:
  enum class Outcome { Factored, NotPositiveDefinite, Singular };

  /// Throws cms::InputError for an unknown method name.
  SparseDirectSolver(Teuchos::RCP<const CrsMatrix> A, const std::string& method);
  ~SparseDirectSolver();
  SparseDirectSolver(const SparseDirectSolver&) = delete;
  SparseDirectSolver& operator=(const SparseDirectSolver&) = delete;

  /// Symbolic and numeric factorisation; the same outcome on every rank.
  Outcome factor();
  /// For inverse iteration, whose shifted matrix is singular to the
  /// eigenvalue's accuracy by design: factor() skips the LU codes' probe
  /// solve that reports a matrix of cond >~ 1e10 as Singular (a breakdown
  /// of the factorisation itself is still reported). Before factor().
  void acceptNearlySingular() { probe_ = false; }
  /// X = A^-1 B. Requires factor() == Factored. B and X on A's range/domain map.
  void solve(const MultiVector& B, MultiVector& X) const;
  /// X = A^-T B from the same factors: MUMPS solves with the transpose
  /// (ICNTL(9)); CHOLMOD, Tacho and MUMPS-LDLT factor symmetric matrices,
  /// whose transpose is themselves; KLU2 is refused (std::logic_error:
  /// Amesos2 13.2's transposed solve returned wrong solutions). For inverse
  /// iteration's left vectors (the real form of Q(sigma)^H is that of
  /// Q(sigma) transposed).
  void solveTransposed(const MultiVector& B, MultiVector& X) const;

  const std::string& method() const { return method_; }
  /// Seconds spent in factor(), for benchmarks and reports.
  double factorSeconds() const { return factorSeconds_; }
  /// CHOLMOD only (0 otherwise): entries of the factor L and the flops of
  /// the numeric factorisation, for benchmarks (memory of L: 8 bytes each).
  double factorNonzeros() const { return factorNonzeros_; }
  double factorFlops() const { return factorFlops_; }
  /// Bytes the factor holds: for CHOLMOD's supernodal L its allocated
  /// values (xsize, with the zeros of relaxed supernodes, which nnz(L) leaves
  /// out) and index arrays; else 8 bytes an entry of factorNonzeros(). The
  /// kept-factor budget counts this (it counted nnz(L) alone; found by a
  /// review).
  double factorBytes() const { return factorBytes_ > 0.0 ? factorBytes_ : 8.0 * factorNonzeros_; }
  /// Human-readable detail of a failed factorisation.
  const std::string& failure() const { return failure_; }

  static bool isKnownMethod(const std::string& method);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string method_, failure_;
  bool probe_ = true;
  double factorSeconds_ = 0.0, factorNonzeros_ = 0.0, factorFlops_ = 0.0, factorBytes_ = 0.0;
};

}  // namespace cms
