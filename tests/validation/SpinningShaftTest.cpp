// Closed form (b): a simply supported spinning Rayleigh shaft. Its Ritz model
// from admissible polynomials (not the sine eigenfunctions) must converge to
// the closed-form forward/backward whirl frequencies from above as functions
// are added (doc/theory.md, "Spinning Rayleigh shaft").
#include <gtest/gtest.h>

#include <cmath>

#include "cms/analysis/CampbellStudy.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/models/SpinningRayleighShaft.hpp"

using namespace cms;

namespace {
models::ShaftProperties stubbyShaft() {
  models::ShaftProperties p;
  p.length = 0.5;
  p.radius = 0.05;  // slender ratio 5: rotary inertia and gyroscopic effects matter
  return p;
}

analysis::SpeedDependentSystem model(const models::ShaftProperties& p, int n) {
  models::SpinningRayleighShaft s(p, n);
  return {s.massMatrix(), s.gyroscopicPerUnitSpeed(), s.stiffnessMatrix(), DenseMatrix(),
          s.whirlPairs()};
}

/// Whirl of each mode by the project's rule (analysis::WhirlClassification).
std::vector<analysis::Whirl> whirlOf(const eigen::GyroscopicResult& r, const analysis::SpeedDependentSystem& sys,
                                     double Omega) {
  std::vector<analysis::Orbit> orbits;
  for (const auto& m : r.modes) orbits.push_back(analysis::orbitOfPairs(m, sys.whirlPairs));
  return analysis::WhirlClassification().classify(r.modes, orbits, Omega > 0 ? 1.0 : 0.0);
}

/// Relative errors of the lowest 4 modes (2 bending orders x FW/BW) at Omega.
std::vector<double> errors(const models::ShaftProperties& p, int n, double Omega,
                           std::vector<analysis::Whirl>* whirl = nullptr) {
  const auto sys = model(p, n);
  Teuchos::ParameterList params;
  params.set("Number of Modes", 4);
  const auto r = eigen::DenseGyroscopicSolver(params).solve(sys.at(Omega));
  std::vector<double> e;
  const auto whirls = whirlOf(r, sys, Omega);
  for (int m = 0; m < 4; ++m) {
    const auto w = whirls[m];
    if (whirl) whirl->push_back(w);
    const auto [fw, bw] = models::SpinningRayleighShaft::exactWhirl(p, m / 2 + 1, Omega);
    const double exact = w == analysis::Whirl::Forward ? fw : bw;
    e.push_back((r.modes[m].omega - exact) / exact);
  }
  return e;
}
}  // namespace

TEST(SpinningShaft, RitzConvergesToClosedFormFromAbove) {
  const auto p = stubbyShaft();
  for (double Omega : {0.0, 2000.0, 8000.0}) {
    std::vector<double> prev;
    for (int n : {3, 4, 6, 8, 10}) {
      std::vector<analysis::Whirl> whirl;
      const std::vector<double> e = errors(p, n, Omega, &whirl);
      for (int m = 0; m < 4; ++m) {
        // Upper bounds (Rayleigh-Ritz / inclusion principle), to rounding.
        EXPECT_GT(e[m], -1e-11) << "n=" << n << " Omega=" << Omega << " mode " << m;
        if (!prev.empty()) EXPECT_LE(e[m], prev[m] + 1e-11) << "not monotone, n=" << n;
      }
      prev = e;
    }
    // With 10 functions per plane the first two bending orders are exact to
    // 1e-8: the polynomial basis approximates sin(k pi x / L) spectrally.
    for (int m = 0; m < 4; ++m) EXPECT_LT(prev[m], 1e-8) << "Omega=" << Omega << " mode " << m;
  }
}

TEST(SpinningShaft, BackwardBelowForwardAndSplitGrowsWithSpeed) {
  const auto p = stubbyShaft();
  const auto sys = model(p, 8);
  Teuchos::ParameterList params;
  params.set("Number of Modes", 2);
  eigen::DenseGyroscopicSolver solver(params);
  double lastSplit = -1.0;
  for (double Omega : {500.0, 2000.0, 6000.0}) {
    const auto r = solver.solve(sys.at(Omega));
    const auto w = whirlOf(r, sys, Omega);
    EXPECT_EQ(w[0], analysis::Whirl::Backward);
    EXPECT_EQ(w[1], analysis::Whirl::Forward);
    const double split = r.modes[1].omega - r.modes[0].omega;
    EXPECT_GT(split, lastSplit);
    lastSplit = split;
  }
  // At rest the two planes are identical: a double frequency, no whirl sense.
  const auto r0 = solver.solve(sys.at(0.0));
  EXPECT_NEAR(r0.modes[0].omega, r0.modes[1].omega, 1e-12 * r0.modes[0].omega);
  EXPECT_EQ(whirlOf(r0, sys, 0.0)[0], analysis::Whirl::Unresolved);
}

TEST(SpinningShaft, CriticalSpeedsMatchClosedForm) {
  const auto p = stubbyShaft();
  Teuchos::ParameterList study;  // 0 to 10000 rad/s in 250 rad/s steps, crossings bisected
  study.set("Steps", 41);
  study.set("Max Factor", 1.0);
  const double tol = 1e-6;
  study.set("Crossing Tolerance", tol);
  const auto d = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(model(p, 8), "shaft", 10000.0));
  const double A = M_PI * p.radius * p.radius, I = M_PI * std::pow(p.radius, 4) / 4;
  const double kk = M_PI / p.length;
  const double bw = std::sqrt(p.youngsModulus * I * std::pow(kk, 4) /
                              (p.density * A + 3 * p.density * I * kk * kk));
  const double fw = std::sqrt(p.youngsModulus * I * std::pow(kk, 4) /
                              (p.density * A - p.density * I * kk * kk));
  const auto& crit = d.crossings;
  ASSERT_GE(crit.size(), 2u);
  // Bisection ends with a bracket narrower than tol times the speed; the
  // Ritz frequencies are exact to 1e-8 (RitzConvergesToClosedFormFromAbove)
  // and the curves cross the 1X line at a slope of order 1, so the speed is
  // within tol plus 1e-8 of the closed form.
  EXPECT_TRUE(crit[0].refined && crit[1].refined);
  EXPECT_NEAR(crit[0].speed, bw, (tol + 1e-8) * bw);
  EXPECT_EQ(crit[0].whirl, analysis::Whirl::Backward);
  EXPECT_NEAR(crit[1].speed, fw, (tol + 1e-8) * fw);
  EXPECT_EQ(crit[1].whirl, analysis::Whirl::Forward);
}
