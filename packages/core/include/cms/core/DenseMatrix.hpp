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

/// What showPositiveDefinite found (theory §13.3, "Proving definiteness").
struct DefinitenessCheck {
  bool shown = false;     ///< A is positive definite, proven from a Cholesky factor
  bool factored = false;  ///< the Cholesky factorisation of A (scaled) itself ran to the end
  /// c: the shift H - c I that was factored, H = A scaled to unit diagonal
  /// (0 where it was not reached).
  double shift = 0.0;
  std::string why;        ///< where not shown: the failed pivot or the shift
};

/// Whether a symmetric A is positive definite, proven from a floating-point
/// Cholesky factor rather than assumed from its success (Rump, "Verification
/// of positive definiteness", BIT 46, 2006, with the factor's sparsity). A is
/// scaled to unit diagonal (within [1/4, 2)) by powers of two, exactly: H = S A S.
/// Where Cholesky of B = fl(H - c I) succeeds, R^T R = B + E with
/// ||E||_2 <= gamma_k / (1 - gamma_k) tr(B) (Higham, Accuracy and Stability
/// of Numerical Algorithms, Thm 10.3; k = 1 + the most nonzeros in a row of
/// R, since an exact zero adds no rounding; || |R^T| |R| ||_2 <= ||R||_F^2 =
/// tr(R^T R)), so H >= (c - ||E|| - u) I > 0 for
///   c > gamma_k / (1 - gamma_k) tr(H) + u + ||S F S||_inf,
/// F the entries' own error bound `entryError` (>= |A_exact - A|
/// componentwise, e.g. the rounding of a sum that formed A; null for none).
/// No estimate enters. A diagonal entry that is not positive, or a failed
/// pivot, is not shown; nor is a matrix whose least eigenvalue (scaled) is
/// below ~c: ~tr(H) k u, ~n k u.
DefinitenessCheck showPositiveDefinite(const DenseMatrix& A, const DenseMatrix* entryError = nullptr);

/// C = alpha * op(A) * op(B) (+ beta C), thin wrapper of Teuchos::BLAS GEMM.
void gemm(bool transA, bool transB, double alpha, const DenseMatrix& A, const DenseMatrix& B,
          double beta, DenseMatrix& C);

}  // namespace cms
