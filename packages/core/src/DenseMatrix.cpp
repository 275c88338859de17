#include "cms/core/DenseMatrix.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>

#include "cms/core/Error.hpp"

namespace cms {

double frobeniusNorm(const DenseMatrix& A) {
  // Four independent sums of squares, column by column: Teuchos'
  // normFrobenius chains one sum through an abs per entry, and a dense
  // solve of n = 128 called it a dozen times, 6% of a sweep's speed
  // (doc/benchmarks.md, "A speed's bookkeeping trimmed").
  const int m = A.numRows(), n = A.numCols(), ld = A.stride();
  const double* a = A.values();
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  for (int j = 0; j < n; ++j) {
    const double* c = a + static_cast<std::size_t>(j) * ld;
    int i = 0;
    for (; i + 3 < m; i += 4) s0 += c[i] * c[i], s1 += c[i + 1] * c[i + 1], s2 += c[i + 2] * c[i + 2], s3 += c[i + 3] * c[i + 3];
    for (; i < m; ++i) s0 += c[i] * c[i];
  }
  const double sum = (s0 + s1) + (s2 + s3);
  // Squares overflow past 1e154 and underflow below 1e-154: then the scaled
  // sum (LAPACK dlassq's idea), which also carries NaN and Inf through.
  if (std::isfinite(sum) && sum >= std::numeric_limits<double>::min() / std::numeric_limits<double>::epsilon())
    return std::sqrt(sum);
  double scale = 0.0, ssq = 1.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i) {
      const double x = std::abs(a[i + static_cast<std::size_t>(j) * ld]);
      if (x == 0.0) continue;
      if (!(x <= scale)) {  // also true for NaN, which then propagates
        ssq = 1.0 + ssq * (scale / x) * (scale / x);
        scale = x;
      } else {
        ssq += (x / scale) * (x / scale);
      }
    }
  return scale * std::sqrt(ssq);
}

namespace {
double structureDefect(const DenseMatrix& A, double sign) {
  // |a_ij + sign a_ji| is the same for (i, j) and (j, i): the lower triangle
  // and the diagonal suffice.
  const int n = A.numRows();
  double worst = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = j; i < n; ++i) worst = std::max(worst, std::abs(A(i, j) + sign * A(j, i)));
  return worst / std::max(frobeniusNorm(A), std::numeric_limits<double>::min());
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

DefinitenessCheck showPositiveDefinite(const DenseMatrix& A, const DenseMatrix* entryError) {
  const int n = A.numRows();
  DefinitenessCheck c;
  if (n == 0) {
    c.why = "empty matrix";
    return c;
  }
  // Unit diagonal (within [1/4, 2)) by powers of two: every scaled entry
  // is exact, and the proof is blind to the units of the coordinates (a
  // rotation's stiffness beside a translation's).
  std::vector<double> s(n);
  for (int i = 0; i < n; ++i) {
    if (!(A(i, i) > 0.0)) {
      std::ostringstream os;
      os << "diagonal entry " << i << " is " << A(i, i);
      c.why = os.str();
      return c;
    }
    int e = 0;
    std::frexp(A(i, i), &e);
    s[i] = std::ldexp(1.0, -e / 2);
  }
  // tr(H) >= tr(H - c I) (below; its rounding is within the 1% there), and
  // ||S F S||_inf, rounded up by 1%.
  double trace = 0.0;
  for (int i = 0; i < n; ++i) trace += A(i, i) * s[i] * s[i];
  double entries = 0.0;
  if (entryError) {
    for (int i = 0; i < n; ++i) {
      double row = 0.0;
      for (int j = 0; j < n; ++j) row += std::abs((*entryError)(i, j)) * s[i] * s[j];
      entries = std::max(entries, row);
    }
    entries *= 1.01;
  }
  const double u = std::numeric_limits<double>::epsilon() / 2.0;
  // Cholesky of H - shift I (choleskyLower: the upper triangle zeroed); the
  // most nonzeros in a row of its factor (0 where it failed, `pivot` then
  // the failed column).
  int pivot = 0;
  const auto factorShifted = [&](double shift) {
    DenseMatrix L(n, n);
    for (int j = 0; j < n; ++j)
      for (int i = j; i < n; ++i) L(i, j) = A(i, j) * s[i] * s[j] - (i == j ? shift : 0.0);
    pivot = choleskyLower(L);
    if (pivot != 0) return 0;
    int m = 0;
    for (int i = 0; i < n; ++i) {
      int row = 0;
      for (int j = 0; j <= i; ++j) row += L(i, j) != 0.0;
      m = std::max(m, row);
    }
    return m;
  };
  const auto shiftFor = [&](int m) {
    const double k = m + 1.0, gamma = k * u / (1.0 - k * u);
    return 1.01 * (gamma / (1.0 - gamma) * trace + entries) + 4.0 * u;
  };
  int m = factorShifted(0.0);
  if (m == 0) {
    c.why = "Cholesky pivot " + std::to_string(pivot) + " of " + std::to_string(n) + " is not positive";
    return c;
  }
  c.factored = true;
  // The shifted factor's own row count decides its gamma_k: refactor if its
  // fill differs (an exact zero of one factor need not be one of the other).
  for (int attempt = 0; attempt < 3; ++attempt) {
    c.shift = shiftFor(m);
    const int mShifted = factorShifted(c.shift);
    if (mShifted == 0) break;
    if (mShifted <= m) {
      c.shown = true;
      return c;
    }
    m = mShifted;
  }
  std::ostringstream os;
  os << "scaled to unit diagonal and shifted by " << c.shift << " (Cholesky's a-priori error, Rump's test), ";
  if (pivot > 0)
    os << "its factorisation fails at pivot " << pivot << ": its least eigenvalue is within rounding of zero, or below";
  else
    os << "its factor's fill kept growing past the shift's assumption";
  c.why = os.str();
  return c;
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
