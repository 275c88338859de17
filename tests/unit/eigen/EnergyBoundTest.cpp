// The energy bound on a damped system's growth rates (theory §13.3, "The
// energy bound"): with N = 0 and K > 0, E = (q'^T M q' + q^T K q) / 2 obeys
// dE/dt = -q'^T D q', so where D + d M >= 0 no eigenvalue has Re lambda > d.
// Against closed forms: a negatively damped DOF, whose growth c / (2 m) the
// bound must cover and whose bound exists only for d > c / m; a gyroscopic
// rotor on damped bearings (shown: every mode decided stable); the Jeffcott
// rotor's circulatory N and a free body's singular K (not shown, said why).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <vector>

#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/EnergyBound.hpp"

using namespace cms;
using namespace cms::eigen;
using cplx = std::complex<double>;

namespace {

DenseMatrix diag(std::vector<double> d) {
  DenseMatrix A(static_cast<int>(d.size()), static_cast<int>(d.size()));
  for (std::size_t i = 0; i < d.size(); ++i) A(i, i) = d[i];
  return A;
}

DenseMatrix skew2(double a) {
  DenseMatrix A(2, 2);
  A(0, 1) = a;
  A(1, 0) = -a;
  return A;
}

GyroscopicResult solveAll(const GyroscopicSystem& s) {
  Teuchos::ParameterList p;
  p.set("Number of Modes", -1);
  return DenseGyroscopicSolver(p).solve(s);
}

}  // namespace

// m x'' - c x' + k x = 0 (negative damping c > 0: a self-excited DOF):
// lambda = c / (2 m) +/- i sqrt(k / m - (c / 2m)^2). D + d M = d m - c is
// positive exactly for d > c / m, and the bound d must then cover the
// growth c / (2 m). The solver's own bound (d = 1e-7 |lambda|) is not shown:
// the mode's FLUTTER stands.
TEST(EnergyBound, CoversANegativelyDampedDofAndIsRefusedBelowItsDamping) {
  const double m = 2.0, k = 8.0, c = 0.4;
  const GyroscopicSystem s{diag({m}), DenseMatrix(1, 1), diag({k}), diag({-c})};
  const EnergyBound below = energyBound(s, 0.99 * c / m), above = energyBound(s, 1.01 * c / m);
  EXPECT_FALSE(below.shown) << below.note;
  EXPECT_NE(below.note.find("D + d M"), std::string::npos) << below.note;
  ASSERT_TRUE(above.shown) << above.note;
  const auto r = solveAll(s);
  ASSERT_EQ(r.modes.size(), 1u);
  // The closed form, to 1e-12 |lambda| (a 2-state dggev: eps times a
  // condition of order one).
  EXPECT_NEAR(r.modes[0].growthRate, c / (2 * m), 1e-12 * std::abs(r.modes[0].lambda));
  EXPECT_LE(r.modes[0].growthRate, above.growth);
  EXPECT_FALSE(r.energyBound.shown) << r.energyBound.note;
  EXPECT_EQ(r.modes[0].stability, Stability::Flutter);
  EXPECT_EQ(r.status, SolveStatus::Converged);
}

// A disc on damped isotropic bearings (Jt lambda^2 -/+ i Omega Jp lambda +
// c lambda + k = 0; DampedEigen checks the roots): passive, so the bound is
// shown at the solver's d = Instability Tolerance (1e-7) times the least
// |lambda|, and every mode is Stable and decided.
TEST(EnergyBound, DecidesAPassiveRotor) {
  const double Jt = 0.5, Jp = 0.8, k = 2.0e3, c = 3.0, Omega = 40.0;
  const auto r = solveAll({diag({Jt, Jt}), skew2(Omega * Jp), diag({k, k}), diag({c, c})});
  ASSERT_TRUE(r.energyBound.shown) << r.energyBound.note;
  double least = std::numeric_limits<double>::infinity();
  for (const auto& m : r.modes) least = std::min(least, std::abs(m.lambda));
  EXPECT_DOUBLE_EQ(r.energyBound.growth, 1e-7 * least);
  for (const auto& m : r.modes) {
    EXPECT_EQ(m.stability, Stability::Stable) << m.lambda;
    EXPECT_FALSE(m.undecided);
    EXPECT_LE(m.growthRate, r.energyBound.growth);
  }
}

// Where the theorem does not hold, the bound is not shown and says why: the
// Jeffcott rotor's internal damping (a circulatory N, which feeds energy in
// above Omega_th), and a free body (K singular: a rigid motion).
TEST(EnergyBound, IsNotShownForACirculatoryOrAFreeSystem) {
  const double m = 2.0, k = 8.0e3, ce = 4.0, ci = 6.0;
  GyroscopicSystem jeffcott{diag({m, m}), DenseMatrix(2, 2), diag({k, k}), diag({ce + ci, ce + ci})};
  jeffcott.N = skew2(100.0 * ci);
  const auto rj = solveAll(jeffcott);
  EXPECT_FALSE(rj.energyBound.shown);
  EXPECT_NE(rj.energyBound.note.find("N != 0"), std::string::npos) << rj.energyBound.note;
  GyroscopicSystem free{diag({m, m}), DenseMatrix(2, 2), diag({k, 0.0}), diag({ce, ce})};
  const auto rf = solveAll(free);
  EXPECT_FALSE(rf.energyBound.shown);
  EXPECT_NE(rf.energyBound.note.find("K > 0 not shown"), std::string::npos) << rf.energyBound.note;
}

// The verdicts against a shown bound (d = 1e-6 1/s here): a growth within
// its uncertainty (Neutral, undecided) is Stable; a mode whose |lambda| is
// too small for the bound to decide (d > 1e-7 |lambda|) keeps its verdict;
// an instability beyond its uncertainty and past the bound contradicts it,
// is returned, and keeps its verdict (the solve is wrong there, said so);
// a rigid mode is left alone.
TEST(EnergyBound, DecidesUndecidedModesAndReturnsContradictions) {
  const auto mode = [](cplx lambda, double tolerance, Stability s) {
    GyroscopicMode m;
    m.lambda = lambda;
    m.growthTolerance = tolerance;
    m.stability = s;
    m.undecided = s == Stability::Neutral;
    return m;
  };
  std::vector<GyroscopicMode> modes{mode({2e-3, 78.4}, 1.0, Stability::Neutral),
                                    mode({2e-3, 1.0}, 1.0, Stability::Neutral),
                                    mode({0.241, 78.4}, 0.1, Stability::Flutter),
                                    mode({1e-9, 0.0}, 0.0, Stability::RigidBody)};
  EnergyBound b{true, 1e-6, "test"};
  const auto wrong = applyEnergyBound(modes, b, 1e-7);
  EXPECT_EQ(modes[0].stability, Stability::Stable);
  EXPECT_FALSE(modes[0].undecided);
  EXPECT_EQ(modes[1].stability, Stability::Neutral);  // 1e-7 |lambda| = 1e-7 < d
  EXPECT_TRUE(modes[1].undecided);
  EXPECT_EQ(modes[2].stability, Stability::Flutter);
  EXPECT_EQ(modes[3].stability, Stability::RigidBody);
  ASSERT_EQ(wrong.size(), 1u);
  EXPECT_EQ(wrong[0], 2);
  // Not shown: nothing changes.
  std::vector<GyroscopicMode> again{mode({2e-3, 78.4}, 1.0, Stability::Neutral)};
  EXPECT_TRUE(applyEnergyBound(again, EnergyBound{}, 1e-7).empty());
  EXPECT_EQ(again[0].stability, Stability::Neutral);
}
