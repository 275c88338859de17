// cms::frobeniusNorm and the structure defects: the unrolled sum of squares
// against a reference summed in long double, and its scaled fallback where
// the squares would overflow or underflow.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

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

}  // namespace
