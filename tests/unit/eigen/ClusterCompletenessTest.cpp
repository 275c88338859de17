// The dense path returns exactly the N lowest frequencies, whole clusters
// included, at every N (issue #8 item 1): LAPACK dgesvdx, which selects
// singular values by index, returned a wrong set on repeated frequencies (one
// member of a pair missing, a higher mode in its place, status "converged").
// The reference is independent of the solver under test: the companion
// matrix's eigenvalues (dgeev) and a Sturm count (the inertia of
// K - w^2 M + i w G, zhetrf), itself checked against the companion spectrum.
#include <gtest/gtest.h>

#include <algorithm>
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

GyroscopicResult solveDense(const GyroscopicSystem& s, int nModes, const std::string& reduction = "Skew Tridiagonal") {
  Teuchos::ParameterList p;
  p.set("Method", "Meirovitch");
  p.set("Number of Modes", nModes);
  p.set("Reduction", reduction);
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
    for (const std::string reduction : {"Skew Tridiagonal", "Bidiagonal"}) {
      for (int N = 1; N <= s.size(); ++N) {
        const GyroscopicResult r = solveDense(s, N, reduction);
        EXPECT_EQ(r.status, SolveStatus::Converged) << reduction << ", system " << c << " N = " << N << ": " << r.reason;
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

// The policy both paths follow when the count disagrees (confirmLowestSet):
// recompute once, check again; a set that still disagrees is not complete,
// which DenseGyroscopicSolver turns into NumericalIssue (the branch the
// dense solver reaches only if dgesvd itself returned a wrong set) and the
// sparse solver too (SparseSturmCountTest).
TEST(LowestSetPolicy, StillDisagreeingAfterTheRecomputationIsNotComplete) {
  int recomputed = 0;
  const SetConfirmation still = confirmLowestSet(
      [](std::string&) { return std::string("the Sturm count finds 4 frequencies below 9 rad/s, the solver 3"); },
      "dgesvdx's set", [&] { ++recomputed; return std::string("recomputed by the full SVD (dgesvd)"); });
  EXPECT_EQ(recomputed, 1);
  EXPECT_FALSE(still.complete);
  EXPECT_NE(still.note.find("dgesvdx's set failed the check (the Sturm count finds 4"), std::string::npos) << still.note;
  EXPECT_NE(still.note.find("recomputed by the full SVD"), std::string::npos) << still.note;
  EXPECT_NE(still.note.find("and still the Sturm count finds 4"), std::string::npos) << still.note;

  int checks = 0;
  const SetConfirmation fixed = confirmLowestSet(
      [&](std::string& confirmation) {
        if (checks++ == 0) return std::string("the Sturm count finds 4 frequencies below 9 rad/s, the solver 3");
        confirmation = "Sturm count at 9 rad/s confirms the 4 lowest";
        return std::string();
      },
      "dgesvdx's set", [] { return std::string("recomputed by the full SVD (dgesvd)"); });
  EXPECT_TRUE(fixed.complete);
  EXPECT_NE(fixed.note.find("recomputed by the full SVD (dgesvd); Sturm count at 9 rad/s confirms"), std::string::npos)
      << fixed.note;

  const SetConfirmation first = confirmLowestSet(
      [](std::string& confirmation) { confirmation = "Sturm count at 1 rad/s confirms the 1 lowest"; return std::string(); },
      "dgesvdx's set", [&] { ++recomputed; return std::string(); });
  EXPECT_TRUE(first.complete);
  EXPECT_EQ(first.note, "Sturm count at 1 rad/s confirms the 1 lowest");
  EXPECT_EQ(recomputed, 1);  // not called when the first set agrees
}

// Where checkLowestSet cuts and what it expects, with an injected count: just
// past the whole cluster of the N-th frequency (members within 1e-6
// relative), 1e-5 relative above it, or in the middle of the gap to the next
// known value when that is nearer.
TEST(LowestSetPolicy, CutsJustPastTheWholeClusterOfTheLastReturnedFrequency) {
  const std::vector<double> w{1.0, 1.0, 2.0, 2.0 * (1 + 1e-9), 3.0, 3.0 * (1 + 4e-6)};
  double at = 0.0;
  // An exact count of `values` below omega, remembering where it was taken.
  const auto countOf = [&](const std::vector<double>& values) {
    return [&at, &values](double omega) {
      at = omega;
      SparseSturmCount c;
      c.omega = omega, c.reliable = true;
      c.count = std::count_if(values.begin(), values.end(), [&](double x) { return x < omega; });
      return c;
    };
  };
  const auto truth = countOf(w);
  // N = 3 cuts the pair at 2: the cut is 1e-5 above its top, four expected, a note.
  LowestSetCheck c = checkLowestSet(w, 3, 1e-6, truth);
  EXPECT_EQ(c.verdict, LowestSetCheck::Verdict::Confirmed) << c.message;
  // The cut is a product of three rounded factors: within a few ulps of it.
  EXPECT_NEAR(at, 2.0 * (1 + 1e-9) * (1 + 1e-5), 8 * std::numeric_limits<double>::epsilon() * 2.0);
  EXPECT_EQ(c.known, 4);
  EXPECT_NE(c.clusterNote.find("modes 3 to 4"), std::string::npos) << c.clusterNote;
  EXPECT_NE(c.clusterNote.find("ask for 4"), std::string::npos) << c.clusterNote;
  // N = 5: the next known value (4e-6 above) is nearer than 1e-5: mid-gap.
  c = checkLowestSet(w, 5, 1e-6, truth);
  EXPECT_EQ(c.verdict, LowestSetCheck::Verdict::Confirmed) << c.message;
  EXPECT_NEAR(at, 3.0 * (1 + 2e-6), 8 * std::numeric_limits<double>::epsilon() * 3.0);
  EXPECT_TRUE(c.clusterNote.empty());
  // A pair member missing from what the solver knew: disagreement, named.
  const std::vector<double> missing{1.0, 2.0, 2.0, 3.0};
  c = checkLowestSet(missing, 2, 1e-6, truth);
  EXPECT_EQ(c.verdict, LowestSetCheck::Verdict::Disagrees);
  EXPECT_EQ(c.known, 3);
  EXPECT_EQ(c.counted, 2 + 2);  // both 1s and both 2s lie below the cut just above 2
  EXPECT_NE(c.message.find("the Sturm count finds 4 frequencies below 2.00002 rad/s, the solver 3"), std::string::npos)
      << c.message;
  // A chain: 2 (1 + 0.99999e-6) is within the tolerance of 2 and 2 (1 +
  // 1.00001e-6) within it of that one, though not of 2. The cluster is the
  // chain, and the cut at least half a tolerance from every known value;
  // grown from 2 alone, it ended before the last and cut 1e-11 from both
  // (found by a review).
  const std::vector<double> chain{1.0, 2.0, 2.0 * (1 + 0.99999e-6), 2.0 * (1 + 1.00001e-6), 3.0};
  c = checkLowestSet(chain, 2, 1e-6, countOf(chain));
  EXPECT_EQ(c.known, 4);
  EXPECT_EQ(c.verdict, LowestSetCheck::Verdict::Confirmed) << c.message;
  for (double x : chain) EXPECT_GE(std::abs(at - x), 0.5e-6 * x) << "the cut " << at << " near " << x;
  // An unreliable count confirms nothing and says so.
  c = checkLowestSet(w, 1, 1e-6, [](double omega) { SparseSturmCount s; s.omega = omega; s.note = "pivots"; return s; });
  EXPECT_EQ(c.verdict, LowestSetCheck::Verdict::Unreliable);
  EXPECT_NE(c.message.find("not confirmed"), std::string::npos) << c.message;
}
