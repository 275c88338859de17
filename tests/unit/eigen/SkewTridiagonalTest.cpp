// The skew tridiagonal reduction of the dense Meirovitch path (doc/theory.md
// §2, "Skew tridiagonal form"): Q^T A Q = T by an orthogonal Q, the
// frequencies against LAPACK's SVD of A (independent code) and against
// values built in, and the invariant planes by their residuals.
//
// Tolerances: a Householder reduction is backward stable, Q T Q^T = A + E
// with ||E||_F <= c N eps ||A||_F and Q orthogonal to c N eps (Higham,
// Accuracy and Stability, §19.3); by Weyl's theorem each singular value then
// moves by at most ||E||_2 <= ||E||_F. The bound 10 N eps ||A||_F leaves a
// decade for c; measured c: at most 0.21 for the similarity and 0.9 for
// orthogonality (N = 7 to 256, OpenBLAS Haswell and Nehalem kernels).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>

#include "RandomSystems.hpp"
#include "cms/core/Error.hpp"
#include "cms/eigen/SkewTridiagonal.hpp"

using namespace cms;
using namespace cms::eigen;

namespace {

const double kEps = std::numeric_limits<double>::epsilon();

DenseMatrix product(const DenseMatrix& A, const DenseMatrix& B, bool transA = false) {
  DenseMatrix C(transA ? A.numCols() : A.numRows(), B.numCols());
  C.multiply(transA ? Teuchos::TRANS : Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, A, B, 0.0);
  return C;
}

DenseMatrix skewTridiagonalMatrix(const SkewTridiagonal& s) {
  const int N = s.size();
  DenseMatrix T(N, N);
  for (int k = 0; k + 1 < N; ++k) T(k + 1, k) = s.t[k], T(k, k + 1) = -s.t[k];
  return T;
}

/// Singular values of A, descending (LAPACK dgesvd, no vectors).
std::vector<double> singularValues(const DenseMatrix& A) {
  const int N = A.numRows();
  DenseMatrix B(A);
  std::vector<double> s(N), rwork(5 * N);
  double dummy = 0.0, wq = 0.0;
  int info = 0;
  Teuchos::LAPACK<int, double> lapack;
  lapack.GESVD('N', 'N', N, N, B.values(), N, s.data(), &dummy, 1, &dummy, 1, &wq, -1, rwork.data(), &info);
  std::vector<double> work(static_cast<std::size_t>(wq));
  lapack.GESVD('N', 'N', N, N, B.values(), N, s.data(), &dummy, 1, &dummy, 1, work.data(),
               static_cast<int>(work.size()), rwork.data(), &info);
  EXPECT_EQ(info, 0);
  return s;
}

/// A random orthogonal N x N matrix (Q of the QR of a Gaussian matrix).
DenseMatrix randomOrthogonal(int N, std::mt19937& rng) {
  DenseMatrix X = fixtures::randomMatrix(N, N, rng);
  std::vector<double> tau(N), work(64 * N);
  int info = 0;
  Teuchos::LAPACK<int, double> lapack;
  lapack.GEQRF(N, N, X.values(), N, tau.data(), work.data(), static_cast<int>(work.size()), &info);
  lapack.ORGQR(N, N, N, X.values(), N, tau.data(), work.data(), static_cast<int>(work.size()), &info);
  return X;
}

/// A = Q0 diag(sigma_k [[0, 1], [-1, 0]]) Q0^T: frequencies known by construction.
DenseMatrix skewWithFrequencies(const std::vector<double>& sigma, std::mt19937& rng) {
  const int N = 2 * static_cast<int>(sigma.size());
  DenseMatrix D(N, N);
  for (std::size_t k = 0; k < sigma.size(); ++k) D(2 * k, 2 * k + 1) = sigma[k], D(2 * k + 1, 2 * k) = -sigma[k];
  const DenseMatrix Q0 = randomOrthogonal(N, rng);
  const DenseMatrix QD = product(Q0, D);
  DenseMatrix A(N, N);
  A.multiply(Teuchos::NO_TRANS, Teuchos::TRANS, 1.0, QD, Q0, 0.0);
  for (int j = 0; j < N; ++j)  // exactly skew
    for (int i = j; i < N; ++i) A(j, i) = i == j ? 0.0 : -A(i, j);
  return A;
}

}  // namespace

// Q^T A Q = T with Q orthogonal, for even and odd sizes and panel widths
// from the unblocked (1) to a single panel (N).
TEST(SkewTridiagonal, IsAnOrthogonalSimilarity) {
  std::mt19937 rng(11);
  for (int N : {1, 2, 3, 7, 64, 129, 256}) {
    const DenseMatrix A = fixtures::randomSkew(N, 1.0, rng);
    const double nA = std::max(A.normFrobenius(), std::numeric_limits<double>::min());
    for (int nb : {1, 5, 32, N}) {
      const SkewTridiagonal s = skewTridiagonalise(A, nb);
      ASSERT_EQ(static_cast<int>(s.t.size()), std::max(0, N - 1));
      DenseMatrix Q(N, N);
      for (int i = 0; i < N; ++i) Q(i, i) = 1.0;
      s.applyQ(Q);
      DenseMatrix QtQ = product(Q, Q, true);
      for (int i = 0; i < N; ++i) QtQ(i, i) -= 1.0;
      EXPECT_LT(QtQ.normFrobenius(), 10 * N * kEps) << "N = " << N << ", block " << nb;
      DenseMatrix QtAQ = product(product(Q, A, true), Q);
      QtAQ -= skewTridiagonalMatrix(s);
      EXPECT_LT(QtAQ.normFrobenius(), 10 * N * kEps * nA) << "N = " << N << ", block " << nb;
    }
  }
}

// The frequencies are A's singular values, each once (dgesvd returns each
// twice, and a zero for odd N).
TEST(SkewTridiagonal, FrequenciesAreTheSingularValuesOfA) {
  std::mt19937 rng(12);
  for (int N : {2, 5, 40, 255, 256}) {
    const DenseMatrix A = fixtures::randomSkew(N, 1.0, rng);
    const std::vector<double> ref = singularValues(A), f = skewFrequencies(skewTridiagonalise(A));
    ASSERT_EQ(static_cast<int>(f.size()), N / 2);
    const double tol = 10 * N * kEps * A.normFrobenius();
    for (int k = 0; k < N / 2; ++k) {
      EXPECT_NEAR(f[k], ref[2 * k], tol) << "N = " << N << " k = " << k;
      EXPECT_NEAR(f[k], ref[2 * k + 1], tol) << "N = " << N << " k = " << k;
    }
    if (N % 2 == 1) EXPECT_LT(ref[N - 1], tol);
  }
}

// Built-in frequencies, repeated ones included (a symmetric rotor's pairs,
// a triple) and a spread of 1e6: each returned to its absolute bound, and
// every plane (y, z) with A y = -sigma z, A z = sigma y, all planes
// orthonormal together, so a repeated frequency has as many independent
// planes as its multiplicity.
TEST(SkewTridiagonal, InvariantPlanesOfRepeatedAndSpreadFrequencies) {
  std::mt19937 rng(13);
  const std::vector<double> sigma{1e-3, 1e-3, 0.5, 1.0, 1.0, 1.0, 2.0, 7.5, 7.5, 1e3, 3e2, 42.0, 0.25, 9.0};
  const int n = static_cast<int>(sigma.size()), N = 2 * n;
  const DenseMatrix A = skewWithFrequencies(sigma, rng);
  const double tol = 10 * N * kEps * A.normFrobenius();
  const SkewTridiagonal s = skewTridiagonalise(A, 4);  // several panels
  const std::vector<double> f = skewFrequencies(s);
  std::vector<double> ref(sigma);
  std::sort(ref.rbegin(), ref.rend());
  ASSERT_EQ(static_cast<int>(f.size()), n);
  for (int k = 0; k < n; ++k) EXPECT_NEAR(f[k], ref[k], tol) << "k = " << k;
  // The 9 smallest, ascending (a request cut after the triple and the 7.5 pair).
  const int count = 9;
  std::vector<double> w(count);
  for (int k = 0; k < count; ++k) w[k] = f[n - 1 - k];
  DenseMatrix Y;
  ASSERT_TRUE(skewInvariantPlanes(s, w, Y));
  ASSERT_EQ(Y.numCols(), 2 * count);
  const DenseMatrix AY = product(A, Y);
  for (int c = 0; c < count; ++c) {
    double ry = 0.0, rz = 0.0;
    for (int i = 0; i < N; ++i) {
      ry += std::pow(AY(i, 2 * c) + w[c] * Y(i, 2 * c + 1), 2);
      rz += std::pow(AY(i, 2 * c + 1) - w[c] * Y(i, 2 * c), 2);
    }
    EXPECT_LT(std::sqrt(ry), tol) << "plane " << c << " (sigma " << w[c] << ")";
    EXPECT_LT(std::sqrt(rz), tol) << "plane " << c << " (sigma " << w[c] << ")";
  }
  // Orthonormal: within a cluster dstein orthogonalises; across separated
  // values orthogonality follows from the residuals over the gaps (>= 0.249
  // here, against residuals ~N eps ||A||): 1e3 N eps bounds both.
  DenseMatrix YtY = product(Y, Y, true);
  for (int i = 0; i < 2 * count; ++i) YtY(i, i) -= 1.0;
  EXPECT_LT(YtY.normFrobenius(), 1e3 * N * kEps * A.normFrobenius());
}

TEST(SkewTridiagonal, RefusesANonSquareMatrix) {
  EXPECT_THROW(skewTridiagonalise(DenseMatrix(4, 3)), InputError);
}
