// The inertia (how many negative and positive eigenvalues) of a distributed
// real symmetric matrix, or of a Hermitian matrix A + iB given by its real
// symmetric part A and skew part B, from one sparse LDL^T factorisation
// without pivoting (Sylvester's law of inertia): the Sturm-sequence check of
// Nastran and ANSYS. Used by the eigen layer to count the eigenfrequencies
// below a frequency (doc/theory.md §5, "Sturm count on the sparse path").
//
// Two factorisations give the count:
//   Simplicial     CHOLMOD's simplicial L D L^T (fill-reducing symmetric
//                  permutation P, no numerical pivoting): P A P^T = L D L^T,
//                  so the signs of D are those of A's eigenvalues. Gathered to
//                  rank 0, as SparseDirectSolver does. Column by column, no
//                  dense kernels: milliseconds for a chain, minutes for a 3-D
//                  solid (46 s for the 1e5-row embedding of the 5e4-DOF rotor).
//   Multifrontal   MUMPS's L D L^T with 1x1/2x2 pivots, METIS-ordered, across
//                  the ranks (cms::distributedInertia): dense kernels on the
//                  fronts (8-10 s for the same count), but a fixed cost per
//                  front that makes a chain of 1e5 rows take a minute.
//   Auto           CHOLMOD's symbolic analysis predicts the simplicial flops
//                  (or the caller's forecast from a factorisation of the
//                  same pattern); above kSimplicialInertiaFlops the count
//                  goes to MUMPS.
// Every call is collective and returns the same result on every rank.
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
  /// Which factorisation counted: "CHOLMOD simplicial L D L^T" or "MUMPS
  /// multifrontal L D L^T".
  std::string method;

  /// A count that can be used: factored, no pivot zero to rounding.
  bool reliable() const { return failure.empty() && tinyPivots == 0; }
};

/// |d_j| at or below this times the largest |a_kk| is a zero pivot to rounding
/// (about 5e3 eps: the pivot a cut within ~1e-12 of an eigenvalue leaves).
inline constexpr double kTinyPivot = 1e-12;

enum class InertiaMethod { Auto, Simplicial, Multifrontal };

/// Auto's limit: a simplicial L D L^T CHOLMOD's analysis predicts above this
/// many flops goes to MUMPS instead (about a second of CHOLMOD's column
/// kernels; MUMPS's own start-up is a few hundredths).
inline constexpr double kSimplicialInertiaFlops = 3e8;

/// The inertia of the symmetric A (fill-complete; square, same row, range and
/// domain maps). Collective.
SparseInertia inertia(const CrsMatrix& A, InertiaMethod method = InertiaMethod::Auto);
/// The same taking A over: given the only reference (a K - w^2 M formed for
/// the count), A is freed as soon as the count has its own copy of the
/// values (MUMPS's triplets, distributedInertia), before the factorisation.
SparseInertia inertia(Teuchos::RCP<const CrsMatrix> A, InertiaMethod method = InertiaMethod::Auto);
/// The same, given `patternFlops`: the flops of a factorisation the caller
/// made of a matrix with A's pattern (CHOLMOD's count with its best
/// ordering, e.g. K's when A = K - w^2 M). Auto above kSimplicialInertiaFlops
/// then goes to MUMPS without CHOLMOD's analysis (its ordering cost 3% of the
/// 9,702-DOF Hex64 bar only to refuse); at or below, or 0, as above. The
/// memory guard before MUMPS applies either way.
SparseInertia inertia(Teuchos::RCP<const CrsMatrix> A, InertiaMethod method, double patternFlops);

/// The inertia of the Hermitian H = A + iB (A symmetric, B skew, on the same
/// maps) through its real symmetric embedding [[A, -B], [B, A]] of order 2n,
/// whose eigenvalues are H's, each twice: the returned counts are halved
/// (an odd count, impossible in exact arithmetic, is a failure). Collective.
SparseInertia inertia(const CrsMatrix& A, const CrsMatrix& B, InertiaMethod method = InertiaMethod::Auto);

/// Map of a 2n state or embedding: global ids g and g + N for each row g
/// this rank owns, the first n rows first.
Teuchos::RCP<const Map> stateMap(const Map& rowMap);

/// The real form [[A, -B], [B, A]] of the complex matrix A + iB on `map2`
/// (stateMap of A's row map): a complex shift's Q(i w), and the real
/// embedding of a Hermitian Q(omega) whose inertia is a Sturm count.
Teuchos::RCP<CrsMatrix> realEmbedding(const CrsMatrix& A, const CrsMatrix& B, const Teuchos::RCP<const Map>& map2);

}  // namespace cms
