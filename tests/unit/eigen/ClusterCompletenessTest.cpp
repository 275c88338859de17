// The dense path returns exactly the N lowest frequencies, whole clusters
// included, at every N (issue #8 item 1): LAPACK dgesvdx, which selects
// singular values by index, returned a wrong set on repeated frequencies (one
// member of a pair missing, a higher mode in its place, status "converged").
// The reference is independent of the solver under test: the companion
// matrix's eigenvalues (dgeev) and a Sturm count (the inertia of
// K - w^2 M + i w G, zhetrf), itself checked against the companion spectrum.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "RandomSystems.hpp"
#include "cms/core/Error.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/SturmCount.hpp"

using namespace cms;
using namespace cms::eigen;

namespace {

/// Two identical copies of a system side by side (a symmetric rotor's two
/// bending planes): every frequency exactly twice.
GyroscopicSystem doubled(const GyroscopicSystem& h) {
  const int m = h.size(), n = 2 * m;
  GyroscopicSystem s{DenseMatrix(n, n), DenseMatrix(n, n), DenseMatrix(n, n)};
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      s.M(i, j) = s.M(m + i, m + j) = h.M(i, j);
      s.G(i, j) = s.G(m + i, m + j) = h.G(i, j);
      s.K(i, j) = s.K(m + i, m + j) = h.K(i, j);
    }
  return s;
}

/// A clamped-free chain of n equal masses and springs (stiffness ratio 1e3
/// between its halves): a spread spectrum like a structure's, unlike a
/// random matrix's.
GyroscopicSystem chain(int n) {
  GyroscopicSystem s{DenseMatrix(n, n), DenseMatrix(n, n), DenseMatrix(n, n)};
  for (int i = 0; i < n; ++i) {  // spring i joins mass i - 1 (the ground for i = 0) to mass i
    s.M(i, i) = 1.0;
    const double k = i < n / 2 ? 1e3 : 1.0;
    s.K(i, i) += k;
    if (i > 0) s.K(i - 1, i - 1) += k, s.K(i - 1, i) -= k, s.K(i, i - 1) -= k;
  }
  return s;
}

GyroscopicResult solveDense(const GyroscopicSystem& s, int nModes) {
  Teuchos::ParameterList p;
  p.set("Method", "Meirovitch");
  p.set("Number of Modes", nModes);
  return DenseGyroscopicSolver(p).solve(s);
}

}  // namespace

// Every count from 1 to n on doubled systems (random, and a chain with a
// spread spectrum, with and without gyroscopic coupling): the N returned
// frequencies are the N lowest of the companion spectrum. Tolerance 1e-9
// relative: cond(M), cond(K) of the random systems are ~10 and the chain's
// spectrum spans 1e3, so both solutions carry errors ~1e-13 relative.
TEST(DenseGyroscopic, ReturnsTheLowestAtEveryCountWithRepeatedFrequencies) {
  std::mt19937 rng(2024);
  const std::vector<GyroscopicSystem> halves{fixtures::randomGyroscopic(7, rng, 0.0),
                                             fixtures::randomGyroscopic(7, rng, 1.0), chain(12)};
  for (std::size_t c = 0; c < halves.size(); ++c) {
    const GyroscopicSystem s = doubled(halves[c]);
    // The reference: the half's companion spectrum, each frequency twice.
    std::vector<double> ref;
    for (double w : fixtures::companionFrequencies(halves[c])) ref.insert(ref.end(), {w, w});
    ASSERT_EQ(static_cast<int>(ref.size()), s.size());
    for (int N = 1; N <= s.size(); ++N) {
      const GyroscopicResult r = solveDense(s, N);
      EXPECT_EQ(r.status, SolveStatus::Converged) << "system " << c << " N = " << N << ": " << r.reason;
      ASSERT_EQ(static_cast<int>(r.modes.size()), N) << "system " << c;
      for (int k = 0; k < N; ++k)
        EXPECT_NEAR(r.modes[k].omega, ref[k], 1e-9 * ref[k]) << "system " << c << " N = " << N << " mode " << k;
      // How the set was confirmed: a Sturm count, or the whole spectrum.
      EXPECT_TRUE(r.reason.find("Sturm count") != std::string::npos ||
                  r.reason.find("whole spectrum") != std::string::npos) << r.reason;
      // N odd cuts a pair: the result says so and names the count that keeps it whole.
      if (N % 2 == 1) EXPECT_NE(r.reason.find("cuts a cluster"), std::string::npos) << "N = " << N << ": " << r.reason;
    }
  }
}

// The Sturm count against the companion spectrum at the middle of every gap
// (and below the lowest, above the highest), for gyroscopic systems of
// several sizes and strengths of coupling.
TEST(SturmCount, CountsTheFrequenciesBelowAnyGap) {
  std::mt19937 rng(7);
  for (int n : {3, 10, 40})
    for (double gyro : {0.0, 1.0, 10.0}) {
      const GyroscopicSystem s = fixtures::randomGyroscopic(n, rng, gyro);
      const std::vector<double> w = fixtures::companionFrequencies(s);
      ASSERT_EQ(static_cast<int>(w.size()), n);
      EXPECT_EQ(sturmCount(s, 0.5 * w.front()), 0);
      EXPECT_EQ(sturmCount(s, 2.0 * w.back()), n);
      for (int k = 1; k < n; ++k)
        EXPECT_EQ(sturmCount(s, 0.5 * (w[k - 1] + w[k])), k) << "n " << n << " gyro " << gyro;
    }
  EXPECT_THROW(sturmCount(fixtures::randomGyroscopic(3, rng), -1.0), InputError);
}
