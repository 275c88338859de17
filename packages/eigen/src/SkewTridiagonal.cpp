#include "cms/eigen/SkewTridiagonal.hpp"

#include <algorithm>
#include <cmath>

#include <Teuchos_BLAS.hpp>

#include "cms/core/Error.hpp"

namespace cms::eigen {

extern "C" {
void dlarfg_(const int* n, double* alpha, double* x, const int* incx, double* tau);
void dormtr_(const char* side, const char* uplo, const char* trans, const int* m, const int* n, const double* a,
             const int* lda, const double* tau, double* c, const int* ldc, double* work, const int* lwork, int* info,
             std::size_t, std::size_t, std::size_t);
void dbdsqr_(const char* uplo, const int* n, const int* ncvt, const int* nru, const int* ncc, double* d, double* e,
             double* vt, const int* ldvt, double* u, const int* ldu, double* c, const int* ldc, double* work,
             int* info, std::size_t);
void dstein_(const int* n, const double* d, const double* e, const int* m, const double* w, const int* iblock,
             const int* isplit, double* z, const int* ldz, double* work, int* iwork, int* ifail, int* info);
}

SkewTridiagonal skewTridiagonalise(const DenseMatrix& A, int blockSize) {
  const int N = A.numRows();
  CMS_INPUT_CHECK(A.numCols() != N, "skewTridiagonalise: A is " << N << " x " << A.numCols() << ", not square");
  SkewTridiagonal s;
  // Every entry is written below (zero-filling it first was 2% of a
  // sweep's speed).
  s.reflectors.shapeUninitialized(N, N);
  DenseMatrix& R = s.reflectors;
  // Exactly skew from the strictly lower triangle.
  for (int j = 0; j < N; ++j) {
    R(j, j) = 0.0;
    for (int i = j + 1; i < N; ++i) R(i, j) = A(i, j), R(j, i) = -A(i, j);
  }
  s.t.assign(std::max(0, N - 1), 0.0);
  s.tau.assign(std::max(0, N - 1), 0.0);
  if (N < 2) return s;

  Teuchos::BLAS<int, double> blas;
  const int nb = std::max(1, blockSize), ld = R.stride();
  // Within a panel the trailing matrix is A + V W^T - W V^T, V holding the
  // panel's reflectors and W the products p = tau A v (theory §2: H A H =
  // A + v p^T - p v^T for skew A, since v^T A v = 0).
  DenseMatrix V(N, nb), W(N, nb);
  std::vector<double> tmp1(nb), tmp2(nb);
  for (int k0 = 0; k0 < N - 1; k0 += nb) {
    const int jb = std::min(nb, N - 1 - k0);
    V.putScalar(0.0), W.putScalar(0.0);
    for (int j = 0; j < jb; ++j) {
      const int k = k0 + j, m = N - k - 1;
      double* x = &R(k + 1, k);
      if (j > 0) {  // column k of the updated matrix: += V W(k,:)^T - W V(k,:)^T
        blas.GEMV(Teuchos::NO_TRANS, m, j, 1.0, &V(k + 1, 0), N, &W(k, 0), N, 1.0, x, 1);
        blas.GEMV(Teuchos::NO_TRANS, m, j, -1.0, &W(k + 1, 0), N, &V(k, 0), N, 1.0, x, 1);
      }
      double beta = x[0], tk = 0.0;
      const int one = 1;
      dlarfg_(&m, &beta, x + 1, &one, &tk);
      s.t[k] = beta;
      s.tau[k] = tk;
      double* v = &V(k + 1, j);
      v[0] = 1.0;
      for (int i = 1; i < m; ++i) v[i] = x[i];
      double* p = &W(k + 1, j);
      if (tk == 0.0) continue;  // H_k = I: nothing to apply (p stays zero)
      // p = tau (A + V W^T - W V^T) v over rows k+1..N-1.
      blas.GEMV(Teuchos::NO_TRANS, m, m, tk, &R(k + 1, k + 1), ld, v, 1, 0.0, p, 1);
      if (j > 0) {
        blas.GEMV(Teuchos::TRANS, m, j, 1.0, &W(k + 1, 0), N, v, 1, 0.0, tmp1.data(), 1);
        blas.GEMV(Teuchos::TRANS, m, j, 1.0, &V(k + 1, 0), N, v, 1, 0.0, tmp2.data(), 1);
        blas.GEMV(Teuchos::NO_TRANS, m, j, tk, &V(k + 1, 0), N, tmp1.data(), 1, 1.0, p, 1);
        blas.GEMV(Teuchos::NO_TRANS, m, j, -tk, &W(k + 1, 0), N, tmp2.data(), 1, 1.0, p, 1);
      }
    }
    // The trailing matrix past the panel: A += V W^T - W V^T.
    const int r = k0 + jb, mr = N - r;
    if (mr > 0) {
      blas.GEMM(Teuchos::NO_TRANS, Teuchos::TRANS, mr, mr, jb, 1.0, &V(r, 0), N, &W(r, 0), N, 1.0, &R(r, r), ld);
      blas.GEMM(Teuchos::NO_TRANS, Teuchos::TRANS, mr, mr, jb, -1.0, &W(r, 0), N, &V(r, 0), N, 1.0, &R(r, r), ld);
    }
  }
  return s;
}

void SkewTridiagonal::applyQ(DenseMatrix& C) const {
  const int N = size(), nc = C.numCols();
  TEUCHOS_TEST_FOR_EXCEPTION(C.numRows() != N, std::logic_error,
                             "SkewTridiagonal::applyQ: " << C.numRows() << " rows, Q is " << N << " x " << N);
  if (N < 2 || nc == 0) return;
  int info = 0, lwork = -1;
  const int ldc = C.stride();
  double wq = 0.0;
  dormtr_("L", "L", "N", &N, &nc, reflectors.values(), &N, tau.data(), C.values(), &ldc, &wq, &lwork, &info, 1, 1,
          1);
  lwork = std::max(1, static_cast<int>(wq));
  std::vector<double> work(lwork);
  dormtr_("L", "L", "N", &N, &nc, reflectors.values(), &N, tau.data(), C.values(), &ldc, work.data(), &lwork, &info,
          1, 1, 1);
  TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError, "SkewTridiagonal::applyQ: LAPACK dormtr failed, info = " << info);
}

std::vector<double> skewFrequencies(const SkewTridiagonal& T) {
  // For odd N, B is (n + 1) x n; a zero last column makes it square (its
  // Golub-Kahan tridiagonal gains a decoupled zero) and adds one zero value.
  const int N = T.size(), n = (N + 1) / 2;
  if (N < 2) return {};
  std::vector<double> t(T.t);
  t.resize(2 * n, 0.0);
  std::vector<double> d(n), e(std::max(1, n - 1), 0.0), work(4 * n);
  for (int i = 0; i < n; ++i) d[i] = t[2 * i];
  for (int i = 0; i + 1 < n; ++i) e[i] = t[2 * i + 1];
  int info = 0;
  const int zero = 0, one = 1;
  double dummy = 0.0;
  dbdsqr_("U", &n, &zero, &zero, &zero, d.data(), e.data(), &dummy, &one, &dummy, &one, &dummy, &one, work.data(),
          &info, 1);
  if (info != 0) return {};
  d.resize(N / 2);  // dbdsqr sorts descending: for odd N the zero is last
  return d;
}

bool zeroDiagonalTridiagonalVectors(const std::vector<double>& off, const std::vector<double>& values,
                                    std::vector<double>& Z) {
  const int N = static_cast<int>(off.size()) + 1, count = static_cast<int>(values.size());
  Z.assign(static_cast<std::size_t>(N) * count, 0.0);
  if (count == 0) return true;
  // One block (dstein wants its values ascending within it).
  std::vector<double> diag(N, 0.0), e(off);
  e.resize(N, 0.0);
  std::vector<int> iblock(count, 1), isplit(1, N), iwork(N), ifail(count);
  std::vector<double> work(5 * N);
  int info = 0;
  dstein_(&N, diag.data(), e.data(), &count, values.data(), iblock.data(), isplit.data(), Z.data(), &N, work.data(),
          iwork.data(), ifail.data(), &info);
  return info == 0;
}

bool skewInvariantPlanes(const SkewTridiagonal& T, const std::vector<double>& sigma, DenseMatrix& Y) {
  const int N = T.size(), count = static_cast<int>(sigma.size());
  Y.shape(N, 2 * count);
  if (count == 0) return true;
  // Eigenvectors of Ts: zero diagonal, off-diagonal t.
  std::vector<double> Z;
  if (!zeroDiagonalTridiagonalVectors(T.t, sigma, Z)) return false;
  // w = D^-1 z, D^-1 = diag(1, -i, -1, i, ...): y = Re w on the even rows,
  // z = Im w on the odd rows, each of norm 1/sqrt 2; normalised.
  for (int c = 0; c < count; ++c) {
    const double* z = &Z[static_cast<std::size_t>(c) * N];
    double ny = 0.0, nz = 0.0;
    for (int k = 0; k < N; ++k) {
      const double sign = (k / 2) % 2 == 0 ? 1.0 : -1.0;  // (-1)^(k/2) for even k, -(-1)^((k-1)/2) for odd
      if (k % 2 == 0)
        Y(k, 2 * c) = sign * z[k], ny += z[k] * z[k];
      else
        Y(k, 2 * c + 1) = -sign * z[k], nz += z[k] * z[k];
    }
    if (!(ny > 0.0) || !(nz > 0.0)) return false;
    ny = 1.0 / std::sqrt(ny), nz = 1.0 / std::sqrt(nz);
    for (int k = 0; k < N; ++k) Y(k, 2 * c) *= ny, Y(k, 2 * c + 1) *= nz;
  }
  T.applyQ(Y);
  return true;
}

}  // namespace cms::eigen
