// cms::frobeniusNorm and the structure defects: the unrolled sum of squares
// against a reference summed in long double, and its scaled fallback where
// the squares would overflow or underflow.
#include <cfloat>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <Teuchos_LAPACK.hpp>

#include "cms/core/DenseMatrix.hpp"

namespace {

using cms::DenseMatrix;

/// ||A||_F summed in long double (64-bit mantissa on x86), entries scaled by
/// 2^-e first so that no square leaves the double range of the test.
double referenceNorm(const DenseMatrix& A, int e) {
  long double s = 0.0L;
  for (int j = 0; j < A.numCols(); ++j)
    for (int i = 0; i < A.numRows(); ++i) {
      const long double x = std::ldexp(static_cast<long double>(A(i, j)), -e);
      s += x * x;
    }
  return static_cast<double>(std::ldexp(std::sqrt(s), e));
}

DenseMatrix randomMatrix(int m, int n, double scale, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  DenseMatrix A(m, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i) A(i, j) = scale * u(gen);
  return A;
}

// A sum of N squares is exact to about N eps relative (each addition
// rounds once); the bound is stated at 2 N eps of the norm, which the
// unrolled four-way sum meets as a plain loop does.
TEST(FrobeniusNorm, AgreesWithALongDoubleSumAtEveryShapeAndScale) {
  const double eps = std::numeric_limits<double>::epsilon();
  const int shapes[][2] = {{1, 1}, {3, 1}, {1, 7}, {5, 5}, {7, 3}, {128, 128}, {257, 13}};
  const double scales[] = {1.0, 1e-3, 1e150, 1e200, 1e300, 1e-150, 1e-200, 1e-310};
  unsigned seed = 1;
  for (const auto& sh : shapes)
    for (double scale : scales) {
      const DenseMatrix A = randomMatrix(sh[0], sh[1], scale, seed++);
      const int e = std::ilogb(scale);
      const double ref = referenceNorm(A, e), got = cms::frobeniusNorm(A);
      ASSERT_TRUE(std::isfinite(got)) << sh[0] << " x " << sh[1] << " at scale " << scale;
      EXPECT_LE(std::abs(got - ref), 2.0 * sh[0] * sh[1] * eps * ref)
          << sh[0] << " x " << sh[1] << " at scale " << scale << ": " << got << " against " << ref;
    }
}

TEST(FrobeniusNorm, ZeroNaNAndInfinity) {
  DenseMatrix A(4, 3);
  EXPECT_EQ(cms::frobeniusNorm(A), 0.0);
  EXPECT_EQ(cms::frobeniusNorm(DenseMatrix()), 0.0);
  A(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(cms::frobeniusNorm(A)));
  A(2, 1) = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(cms::frobeniusNorm(A), std::numeric_limits<double>::infinity());
  A(0, 0) = 1e300;  // finite entries after an infinite one
  EXPECT_EQ(cms::frobeniusNorm(A), std::numeric_limits<double>::infinity());
}

// A view (stride larger than its rows) reads only its own entries.
TEST(FrobeniusNorm, AViewReadsOnlyItsColumnsRows) {
  DenseMatrix A(6, 4);
  A.putScalar(1e10);
  DenseMatrix V(Teuchos::View, A, 3, 2, 1, 1);
  V.putScalar(2.0);
  EXPECT_DOUBLE_EQ(cms::frobeniusNorm(V), std::sqrt(6.0 * 4.0));
}

// The defects read the lower triangle only; an asymmetry above the
// diagonal is the same pair, so it must still be found.
TEST(StructureDefect, FindsAnAsymmetryOnEitherSideOfTheDiagonal) {
  DenseMatrix S = randomMatrix(9, 9, 1.0, 7), K(9, 9);
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 9; ++i) K(i, j) = S(i, j) - S(j, i);  // exactly skew
  DenseMatrix M(K);
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 9; ++i) M(i, j) = S(i, j) + S(j, i);  // exactly symmetric
  EXPECT_EQ(cms::symmetryDefect(M), 0.0);
  EXPECT_EQ(cms::skewDefect(K), 0.0);
  M(2, 6) += 0.25;  // above the diagonal
  EXPECT_DOUBLE_EQ(cms::symmetryDefect(M), 0.25 / cms::frobeniusNorm(M));
  K(6, 2) += 0.5;  // below
  EXPECT_DOUBLE_EQ(cms::skewDefect(K), 0.5 / cms::frobeniusNorm(K));
  K(6, 2) -= 0.5;
  K(4, 4) = 0.125;  // a skew matrix's diagonal is zero: 2 |k_ii|
  EXPECT_DOUBLE_EQ(cms::skewDefect(K), 0.25 / cms::frobeniusNorm(K));
}

// showPositiveDefinite (theory §13.3, "Proving definiteness") must never show
// an indefinite matrix positive definite, and should show one whose smallest
// eigenvalue stands clear of Cholesky's a-priori error.
//
// Exactly known spectra first: the free spring chain's stiffness (integer
// entries, rows summing to zero: singular exactly, its null vector 1) shifted
// by +-2^-k on the diagonal (exact in binary), so its least eigenvalue is
// +-2^-k exactly. Its factor has two nonzeros per row (gamma_3), so the
// shift is c = 1.01 gamma_3 tr(H) + 4 u ~ 7.5e-15 (the diagonal 2 scaled to
// 1/2, the ends' 1 kept: tr(H) ~ 21): +2^-k, at least 2^-k / 4 scaled, is
// shown down to k = 40 (2.3e-13 > 7.5e-15); -2^-k is never shown.
TEST(PositiveDefiniteness, IsShownOnlyWhereItHolds) {
  const int n = 40;
  const auto chain = [&](double shift) {
    DenseMatrix K(n, n);
    for (int i = 0; i < n; ++i) {
      K(i, i) = (i == 0 || i == n - 1 ? 1.0 : 2.0) + shift;
      if (i + 1 < n) K(i, i + 1) = K(i + 1, i) = -1.0;
    }
    return K;
  };
  EXPECT_FALSE(cms::showPositiveDefinite(chain(0.0)).shown) << "singular exactly";
  for (int k = 2; k <= 50; k += 2) {  // 2 - 2^-50 is a double; 2 - 2^-54 would round to 2
    const double d = std::ldexp(1.0, -k);
    const auto minus = cms::showPositiveDefinite(chain(-d));
    EXPECT_FALSE(minus.shown) << "least eigenvalue -2^-" << k << ", shift " << minus.shift;
    EXPECT_FALSE(minus.why.empty());
    if (k <= 40) {
      const auto plus = cms::showPositiveDefinite(chain(d));
      EXPECT_TRUE(plus.shown) << "least eigenvalue 2^-" << k << ": " << plus.why;
      EXPECT_GT(plus.shift, 0.0);
      // The shift the proof needs at most: tr(H) < 2n by the scaling.
      const double u = DBL_EPSILON / 2, g = 3 * u / (1 - 3 * u);
      EXPECT_LE(plus.shift, 1.01 * g / (1 - g) * 2.0 * n + 4 * u);
    }
  }
  // Units: the same chain with its coordinates scaled by 10^-8 .. 10^8
  // (a rotation beside a translation) is as definite; the powers-of-two
  // scaling to unit diagonal makes the check blind to them.
  DenseMatrix S = chain(std::ldexp(1.0, -20));
  std::vector<double> u(n);
  for (int i = 0; i < n; ++i) u[i] = std::pow(10.0, -8.0 + 16.0 * i / (n - 1));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) S(i, j) *= u[i] * u[j];
  EXPECT_TRUE(cms::showPositiveDefinite(S).shown);
  // An empty matrix proves nothing.
  const auto empty = cms::showPositiveDefinite(DenseMatrix());
  EXPECT_FALSE(empty.shown);
  EXPECT_EQ(empty.why, "empty matrix");
  // A diagonal entry that is not positive is named.
  DenseMatrix Z = chain(1.0);
  Z(7, 7) = 0.0;
  const auto z = cms::showPositiveDefinite(Z);
  EXPECT_FALSE(z.shown);
  EXPECT_NE(z.why.find("diagonal entry 7"), std::string::npos) << z.why;
}

// The entries' own error counts: diag(1, 2^-43) is positive definite as
// stored, but with its second entry known only to within 2^-42 (as if
// rounded when formed) the exact matrix may be diag(1, -2^-43), and it is not
// shown; within 2^-60 it is.
TEST(PositiveDefiniteness, CountsTheEntriesOwnError) {
  DenseMatrix A(2, 2), F(2, 2);
  A(0, 0) = 1.0, A(1, 1) = std::ldexp(1.0, -43);
  EXPECT_TRUE(cms::showPositiveDefinite(A).shown);
  F(1, 1) = std::ldexp(1.0, -42);
  EXPECT_FALSE(cms::showPositiveDefinite(A, &F).shown);
  F(1, 1) = std::ldexp(1.0, -60);
  EXPECT_TRUE(cms::showPositiveDefinite(A, &F).shown);
}

// Where Cholesky itself succeeds on an indefinite matrix, the shifted
// factorisation must refuse it. A free spring chain with random stiffnesses k_i in [1, 2]
// (n = 40): K_ii is the double at or just below k_{i-1} + k_i (TwoSum gives
// the sum's rounding exactly), so 1^T K 1 = sum_i (K_ii - k_{i-1} - k_i) < 0
// exactly: K is indefinite, its least eigenvalue ~ -eps. Its factorisation's
// rounding is of the same size, so on some of the 200 chains the last pivot
// comes out positive (asserted, or the test would not test the shift);
// none may be shown.
TEST(PositiveDefiniteness, AnIndefiniteMatrixCholeskyFactorsIsNotShown) {
  const int n = 40;
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> stiffness(1.0, 2.0);
  int factored = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> k(n - 1);
    for (double& x : k) x = stiffness(gen);
    DenseMatrix K(n, n);
    bool below = false;
    for (int i = 0; i < n; ++i) {
      const double a = i > 0 ? k[i - 1] : 0.0, b = i + 1 < n ? k[i] : 0.0;
      double s = a + b;
      const double bb = s - a, err = (a - (s - bb)) + (b - bb);  // TwoSum: a + b = s + err exactly
      if (err < 0.0) s = std::nextafter(s, 0.0);
      below = below || err != 0.0;
      K(i, i) = s;
      if (i + 1 < n) K(i, i + 1) = K(i + 1, i) = -k[i];
    }
    if (!below) K(1, 1) = std::nextafter(K(1, 1), 0.0);
    const auto c = cms::showPositiveDefinite(K);
    EXPECT_FALSE(c.shown) << "trial " << trial << ", shift " << c.shift;
    factored += c.factored;
  }
  EXPECT_GE(factored, 1) << "no chain's Cholesky succeeded: the shift was not tested";
}

// Dense spectra, Q diag(lambda) Q^T with Q orthogonal (Householder QR of a
// random matrix), n = 40, eigenvalues log-spaced from delta to 1: forming A
// moves them by ~n eps ||A|| ~ 1e-14, so the indefinite ones (-delta) are
// tested where delta >= 1e-11 (a thousand times that), and the definite
// ones are shown where delta >= 1e-9: the dense factor's shift is
// 1.01 gamma_41 tr(H) / (1 - gamma_41) + 4 u <~ 3.7e-13 (tr(H) < 2n)
// against a scaled least eigenvalue >= delta / 4.
TEST(PositiveDefiniteness, DenseSpectraAreShownAboveTheBackwardError) {
  const int n = 40;
  DenseMatrix Q = randomMatrix(n, n, 1.0, 11);
  std::vector<double> tau(n), work(64 * n);
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  lapack.GEQRF(n, n, Q.values(), Q.stride(), tau.data(), work.data(), static_cast<int>(work.size()), &info);
  ASSERT_EQ(info, 0);
  lapack.ORGQR(n, n, n, Q.values(), Q.stride(), tau.data(), work.data(), static_cast<int>(work.size()), &info);
  ASSERT_EQ(info, 0);
  const auto spectrum = [&](double least) {
    DenseMatrix A(n, n);
    for (int k = 0; k < n; ++k) {
      const double l = k == 0 ? least : std::pow(10.0, std::log10(std::abs(least)) * (1.0 - double(k) / (n - 1)));
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) A(i, j) += Q(i, k) * l * Q(j, k);
    }
    for (int j = 0; j < n; ++j)  // exactly symmetric
      for (int i = 0; i < j; ++i) A(i, j) = A(j, i);
    return A;
  };
  for (double delta : {1e-2, 1e-5, 1e-8, 1e-11}) {
    const auto minus = cms::showPositiveDefinite(spectrum(-delta));
    EXPECT_FALSE(minus.shown) << "least eigenvalue " << -delta << ", shift " << minus.shift;
  }
  for (double delta : {1e-2, 1e-5, 1e-9}) {
    const auto plus = cms::showPositiveDefinite(spectrum(delta));
    EXPECT_TRUE(plus.shown) << "least eigenvalue " << delta << ": " << plus.why;
  }
}

}  // namespace
