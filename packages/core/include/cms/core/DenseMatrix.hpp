// Dense real matrices for reduced models: Teuchos::SerialDenseMatrix (column
// major, LAPACK-compatible) and the structural checks every solver applies to
// its input before trusting it.
#pragma once

#include <string>

#include <Teuchos_SerialDenseMatrix.hpp>

namespace cms {

using DenseMatrix = Teuchos::SerialDenseMatrix<int, double>;

/// Frobenius norm.
double frobeniusNorm(const DenseMatrix& A);

/// max |A - A^T| / max(||A||_F, tiny): 0 for an exactly symmetric matrix.
double symmetryDefect(const DenseMatrix& A);

/// max |A + A^T| / max(||A||_F, tiny): 0 for an exactly skew-symmetric matrix.
double skewDefect(const DenseMatrix& A);

/// Throws cms::InputError naming `name` and the first offending entry if A
/// has a NaN or an Inf.
void requireFinite(const DenseMatrix& A, const std::string& name);

/// Lower Cholesky factor of a symmetric A in place (upper triangle zeroed).
/// Returns 0 on success, or the LAPACK pivot index k > 0 at which A failed to
/// be positive definite. Also fails (returns n+1) when the smallest pivot
/// squared falls below `relPivotTol` times the largest, which flags a matrix
/// that is positive definite only by rounding.
int choleskyLower(DenseMatrix& A, double relPivotTol = 0.0);

/// What showPositiveDefinite found (theory §13.3, "The energy bound").
struct DefinitenessCheck {
  bool shown = false;  ///< A is positive definite, shown from its Cholesky factor
  /// The smallest eigenvalue's lower estimate over Cholesky's backward error
  /// (> 1: shown); 0 where the factorisation failed.
  double margin = 0.0;
  std::string why;     ///< where not shown: the failed pivot or the margin
};

/// Whether a symmetric A is positive definite, shown from a floating-point
/// Cholesky factor rather than assumed from its success. A is scaled to unit
/// diagonal by powers of two (exact), H = S A S; the computed factor obeys
/// L L^T = H + E with |E| <= gamma_{m+1} |L| |L|^T (Higham, Accuracy and
/// Stability of Numerical Algorithms, Thm 10.3; m the most nonzeros in a row
/// of L: an exact zero adds no rounding), so H, and A with it, is positive
/// definite where lambda_min(L L^T) > gamma_{m+1} || |L| |L|^T ||_inf (Weyl;
/// the inf-norm of a symmetric nonnegative matrix bounds its 2-norm).
/// lambda_min(L L^T) >= 1 / ||(L L^T)^-1||_1, whose estimate (LAPACK dpocon,
/// a lower estimate, rarely below a third) is taken ten times larger. A
/// diagonal entry that is not positive, or a failed pivot, is not shown.
DefinitenessCheck showPositiveDefinite(const DenseMatrix& A);

/// C = alpha * op(A) * op(B) (+ beta C), thin wrapper of Teuchos::BLAS GEMM.
void gemm(bool transA, bool transB, double alpha, const DenseMatrix& A, const DenseMatrix& B,
          double beta, DenseMatrix& C);

}  // namespace cms
