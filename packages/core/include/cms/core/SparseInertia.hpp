// The inertia (how many negative and positive eigenvalues) of a distributed
// real symmetric matrix, or of a Hermitian matrix A + iB given by its real
// symmetric part A and skew part B, from one sparse LDL^T factorisation
// without pivoting (Sylvester's law of inertia): the Sturm-sequence check of
// Nastran and ANSYS. Used by the eigen layer to count the eigenfrequencies
// below a frequency (doc/theory.md §5, "Sturm count on the sparse path").
//
// CHOLMOD's simplicial L D L^T (fill-reducing symmetric permutation P, no
// numerical pivoting): P A P^T = L D L^T, so the signs of D are those of A's
// eigenvalues. The matrix is gathered to rank 0, as SparseDirectSolver does;
// every call is collective and returns the same result on every rank.
#pragma once

#include <string>

#include "cms/core/TpetraTypes.hpp"

namespace cms {

struct SparseInertia {
  /// Eigenvalues below and above zero (of A, or of A + iB counted once each).
  long long negative = 0, positive = 0;
  /// Pivots zero to rounding (|d_j| <= kTinyPivot max_k |a_kk|, or CHOLMOD's
  /// zero pivot): the matrix is singular to working precision where it was
  /// taken, and the counts are not to be trusted. Shift and count again.
  long long tinyPivots = 0;
  /// max_j |a_jj| / |d_j| over the nonzero pivots, with a_jj the diagonal
  /// entry eliminated at step j (Nastran's MAXRATIO diagnostic): large when
  /// the matrix is nearly singular or elimination without pivoting grew.
  double maxPivotRatio = 0.0;
  /// Non-empty when no count could be made (CHOLMOD failed, or the real
  /// embedding of A + iB had an odd number of negative pivots, which exact
  /// arithmetic excludes), saying why.
  std::string failure;

  /// A count that can be used: factored, no pivot zero to rounding.
  bool reliable() const { return failure.empty() && tinyPivots == 0; }
};

/// |d_j| at or below this times the largest |a_kk| is a zero pivot to rounding
/// (about 5e3 eps: the pivot a cut within ~1e-12 of an eigenvalue leaves).
inline constexpr double kTinyPivot = 1e-12;

/// The inertia of the symmetric A (fill-complete; square, same row, range and
/// domain maps). Collective.
SparseInertia inertia(const CrsMatrix& A);

/// The inertia of the Hermitian H = A + iB (A symmetric, B skew, on the same
/// maps) through its real symmetric embedding [[A, -B], [B, A]] of order 2n,
/// whose eigenvalues are H's, each twice: the returned counts are halved.
/// Collective.
SparseInertia inertia(const CrsMatrix& A, const CrsMatrix& B);

}  // namespace cms
