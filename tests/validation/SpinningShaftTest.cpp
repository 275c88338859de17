// Closed form (b): a simply supported spinning Rayleigh shaft. Its Ritz model
// from admissible polynomials (not the sine eigenfunctions) must converge to
// the closed-form forward/backward whirl frequencies from above as functions
// are added (doc/theory.md, "Spinning Rayleigh shaft").
#include <gtest/gtest.h>

#include <cmath>

#include "cms/analysis/Campbell.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/fem/SpinningRayleighShaft.hpp"

using namespace cms;

namespace {
fem::ShaftProperties stubbyShaft() {
  fem::ShaftProperties p;
  p.length = 0.5;
  p.radius = 0.05;  // slender ratio 5: rotary inertia and gyroscopic effects matter
  return p;
}

analysis::SpeedDependentSystem model(const fem::ShaftProperties& p, int n) {
  fem::SpinningRayleighShaft s(p, n);
  return {s.massMatrix(), s.gyroscopicPerUnitSpeed(), s.stiffnessMatrix(), DenseMatrix(),
          s.whirlPairs()};
}

/// Relative errors of the lowest 4 modes (2 bending orders x FW/BW) at Omega.
std::vector<double> errors(const fem::ShaftProperties& p, int n, double Omega,
                           std::vector<analysis::Whirl>* whirl = nullptr) {
  const auto sys = model(p, n);
  Teuchos::ParameterList params;
  params.set("Number of Modes", 4);
  const auto r = eigen::DenseGyroscopicSolver(params).solve(sys.at(Omega));
  std::vector<double> e;
  for (int m = 0; m < 4; ++m) {
    const auto w = analysis::whirlOf(r.modes[m], sys.whirlPairs);
    if (whirl) whirl->push_back(w);
    const auto [fw, bw] = fem::SpinningRayleighShaft::exactWhirl(p, m / 2 + 1, Omega);
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
    EXPECT_EQ(analysis::whirlOf(r.modes[0], sys.whirlPairs), analysis::Whirl::Backward);
    EXPECT_EQ(analysis::whirlOf(r.modes[1], sys.whirlPairs), analysis::Whirl::Forward);
    const double split = r.modes[1].omega - r.modes[0].omega;
    EXPECT_GT(split, lastSplit);
    lastSplit = split;
  }
  // At rest the two planes are identical: a double frequency, no whirl sense.
  const auto r0 = solver.solve(sys.at(0.0));
  EXPECT_NEAR(r0.modes[0].omega, r0.modes[1].omega, 1e-12 * r0.modes[0].omega);
}

TEST(SpinningShaft, CriticalSpeedsMatchClosedForm) {
  const auto p = stubbyShaft();
  std::vector<double> speeds;
  for (int i = 0; i <= 400; ++i) speeds.push_back(25.0 * i);  // to 10000 rad/s
  const auto d = analysis::campbell(model(p, 8), speeds, {});
  const double A = M_PI * p.radius * p.radius, I = M_PI * std::pow(p.radius, 4) / 4;
  const double kk = M_PI / p.length;
  const double bw = std::sqrt(p.youngsModulus * I * std::pow(kk, 4) /
                              (p.density * A + 3 * p.density * I * kk * kk));
  const double fw = std::sqrt(p.youngsModulus * I * std::pow(kk, 4) /
                              (p.density * A - p.density * I * kk * kk));
  const auto crit = d.criticalSpeeds(1.0);
  ASSERT_GE(crit.size(), 2u);
  // Linear interpolation over a 25 rad/s step of curves with curvature
  // ~1e-5 / (rad/s) gives errors below 1e-4 relative.
  EXPECT_NEAR(crit[0].speed, bw, 1e-4 * bw);
  EXPECT_EQ(crit[0].whirl, analysis::Whirl::Backward);
  EXPECT_NEAR(crit[1].speed, fw, 1e-4 * fw);
  EXPECT_EQ(crit[1].whirl, analysis::Whirl::Forward);
}
