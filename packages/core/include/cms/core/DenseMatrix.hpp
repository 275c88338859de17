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

/// C = alpha * op(A) * op(B) (+ beta C), thin wrapper of Teuchos::BLAS GEMM.
void gemm(bool transA, bool transB, double alpha, const DenseMatrix& A, const DenseMatrix& B,
          double beta, DenseMatrix& C);

}  // namespace cms
