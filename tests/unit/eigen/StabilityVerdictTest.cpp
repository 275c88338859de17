// Stability is decided against what rounding can do to an eigenvalue (issue
// #8 item 6, doc/theory.md "Stability within round-off"): the general
// (dggev) path splits a defective eigenvalue by ~sqrt(eps) of the frequency
// scale, and such a split is neither flutter nor divergence; a real
// instability stays flagged.
#include <gtest/gtest.h>

#include <cmath>

#include "cms/eigen/DenseGyroscopicSolver.hpp"

using namespace cms;
using namespace cms::eigen;

namespace {
GyroscopicResult general(const GyroscopicSystem& s) {
  Teuchos::ParameterList p;
  p.set("Method", "General");
  return DenseGyroscopicSolver(p).solve(s);
}
}  // namespace

// A free point mass in a frame spinning at Omega (M = I, G = 2 Omega J,
// K = -Omega^2 I): lambda = +/- i Omega, each a defective double eigenvalue
// (the rigid translation seen from the spinning frame). dggev returns it
// split; no mode may be called unstable, and a positive growth rate may only
// be "neutral".
TEST(StabilityVerdict, DefectiveFrameRatePairIsNotAnInstability) {
  for (double Omega : {1e-2, 1.0, 316.0, 1e4}) {
    GyroscopicSystem s{DenseMatrix(2, 2), DenseMatrix(2, 2), DenseMatrix(2, 2)};
    s.M(0, 0) = s.M(1, 1) = 1.0;
    s.G(0, 1) = -2.0 * Omega, s.G(1, 0) = 2.0 * Omega;
    s.K(0, 0) = s.K(1, 1) = -Omega * Omega;
    const GyroscopicResult r = general(s);
    ASSERT_EQ(r.modes.size(), 2u);
    for (const auto& m : r.modes) {
      // The frequency itself is right to the defective eigenvalue's
      // sensitivity, sqrt(eps) relative (x 100).
      EXPECT_NEAR(m.omega, Omega, 1e-6 * Omega) << "Omega " << Omega;
      EXPECT_NE(m.stability, Stability::Flutter) << "Omega " << Omega << " growth " << m.growthRate;
      EXPECT_NE(m.stability, Stability::Divergence) << "Omega " << Omega << " growth " << m.growthRate;
      if (m.growthRate > 0 && m.stability != Stability::Stable)
        EXPECT_EQ(m.stability, Stability::Neutral) << "Omega " << Omega;
    }
    EXPECT_TRUE(r.isStable());
  }
}

// A mass on springs kx = 1, ky = 4 (unit mass) in a frame spinning at Omega:
// divergence for 1 < Omega^2 < 4, growth rate from the closed form
// lambda^4 + (kx + ky + 2 Omega^2) lambda^2 + (kx - Omega^2)(ky - Omega^2) = 0.
// Deep in the band (Omega = 1.5: growth 0.52) and near its edge (Omega^2 =
// 1 + 1e-4: growth ~ 5e-3, far above rounding) it stays flagged.
TEST(StabilityVerdict, RealDivergenceStaysFlagged) {
  for (double Omega : {1.5, std::sqrt(1.0 + 1e-4)}) {
    GyroscopicSystem s{DenseMatrix(2, 2), DenseMatrix(2, 2), DenseMatrix(2, 2)};
    s.M(0, 0) = s.M(1, 1) = 1.0;
    s.G(0, 1) = -2.0 * Omega, s.G(1, 0) = 2.0 * Omega;
    s.K(0, 0) = 1.0 - Omega * Omega, s.K(1, 1) = 4.0 - Omega * Omega;
    const double b = 5.0 + 2.0 * Omega * Omega, c = (1.0 - Omega * Omega) * (4.0 - Omega * Omega);
    const double mu = (-b + std::sqrt(b * b - 4.0 * c)) / 2.0;  // lambda^2 > 0
    const GyroscopicResult r = general(s);
    bool found = false;
    for (const auto& m : r.modes)
      if (m.stability == Stability::Divergence) {
        found = true;
        EXPECT_NEAR(m.growthRate, std::sqrt(mu), 1e-8 * std::sqrt(mu)) << "Omega " << Omega;
      }
    EXPECT_TRUE(found) << "Omega " << Omega;
    EXPECT_FALSE(r.isStable());
  }
}
