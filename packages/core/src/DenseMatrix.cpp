#include "cms/core/DenseMatrix.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>

#include "cms/core/Error.hpp"

namespace cms {

double frobeniusNorm(const DenseMatrix& A) { return A.normFrobenius(); }

namespace {
double structureDefect(const DenseMatrix& A, double sign) {
  const int n = A.numRows();
  double worst = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) worst = std::max(worst, std::abs(A(i, j) + sign * A(j, i)));
  return worst / std::max(A.normFrobenius(), std::numeric_limits<double>::min());
}
}  // namespace

double symmetryDefect(const DenseMatrix& A) { return structureDefect(A, -1.0); }
double skewDefect(const DenseMatrix& A) { return structureDefect(A, +1.0); }

void requireFinite(const DenseMatrix& A, const std::string& name) {
  for (int j = 0; j < A.numCols(); ++j)
    for (int i = 0; i < A.numRows(); ++i)
      CMS_INPUT_CHECK(!std::isfinite(A(i, j)),
                      name << "(" << i << "," << j << ") = " << A(i, j) << " is not finite");
}

int choleskyLower(DenseMatrix& A, double relPivotTol) {
  const int n = A.numRows();
  int info = 0;
  Teuchos::LAPACK<int, double>().POTRF('L', n, A.values(), A.stride(), &info);
  if (info != 0) return info;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < j; ++i) A(i, j) = 0.0;
  if (relPivotTol > 0.0 && n > 0) {
    double lo = std::numeric_limits<double>::max(), hi = 0.0;
    for (int i = 0; i < n; ++i) {
      lo = std::min(lo, A(i, i) * A(i, i));
      hi = std::max(hi, A(i, i) * A(i, i));
    }
    if (lo < relPivotTol * hi) return n + 1;
  }
  return 0;
}

void gemm(bool transA, bool transB, double alpha, const DenseMatrix& A, const DenseMatrix& B,
          double beta, DenseMatrix& C) {
  const int m = transA ? A.numCols() : A.numRows();
  const int k = transA ? A.numRows() : A.numCols();
  const int n = transB ? B.numRows() : B.numCols();
  if (C.numRows() != m || C.numCols() != n) {
    C.shape(m, n);
    beta = 0.0;
  }
  Teuchos::BLAS<int, double>().GEMM(transA ? Teuchos::TRANS : Teuchos::NO_TRANS,
                                    transB ? Teuchos::TRANS : Teuchos::NO_TRANS, m, n, k, alpha,
                                    A.values(), A.stride(), B.values(), B.stride(), beta,
                                    C.values(), C.stride());
}

}  // namespace cms
