// Closed form (a): a point mass m on springs kx, ky in a frame spinning at
// Omega about z (doc/theory.md, "Rotating point mass"):
//   m x'' - 2 m Omega y' + (kx - m Omega^2) x = 0
//   m y'' + 2 m Omega x' + (ky - m Omega^2) y = 0
// lambda^2 solves m^2 s^2 + (m (a + b) + 4 m^2 Omega^2) s + a b = 0 with
// a = kx - m Omega^2, b = ky - m Omega^2. With kx < ky the system diverges for
// sqrt(kx/m) < Omega < sqrt(ky/m) and is gyroscopically stabilised above,
// where K is negative definite.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "cms/analysis/CampbellStudy.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"

using namespace cms;
using namespace cms::eigen;
using cplx = std::complex<double>;

namespace {
const double m = 2.0, kx = 800.0, ky = 1250.0;  // critical speeds 20 and 25 rad/s

analysis::SpeedDependentSystem pointMass() {
  analysis::SpeedDependentSystem s;
  s.M.shape(2, 2), s.G1.shape(2, 2), s.K0.shape(2, 2), s.K2.shape(2, 2);
  s.M(0, 0) = s.M(1, 1) = m;
  s.G1(0, 1) = -2.0 * m, s.G1(1, 0) = 2.0 * m;
  s.K0(0, 0) = kx, s.K0(1, 1) = ky;
  s.K2(0, 0) = s.K2(1, 1) = -m;  // spin softening K_T = m Omega^2 I
  return s;
}

/// The two lambda with Im >= 0 (or Re >= 0 when real), from the closed form.
std::vector<cplx> exactLambdas(double W) {
  const double a = kx - m * W * W, b = ky - m * W * W;
  const double B = m * (a + b) + 4 * m * m * W * W, C = a * b, A = m * m;
  const cplx disc = std::sqrt(cplx(B * B - 4 * A * C));
  std::vector<cplx> out;
  for (cplx s : {(-B + disc) / (2 * A), (-B - disc) / (2 * A)}) {
    cplx l = std::sqrt(s);  // principal root: Re >= 0
    if (std::abs(l.real()) < 1e-12 * std::abs(l)) l = cplx(0.0, std::abs(l.imag()));
    out.push_back(l);
  }
  std::sort(out.begin(), out.end(), [](cplx p, cplx q) { return std::abs(p) < std::abs(q); });
  return out;
}

/// A Campbell study from rest to the nominal rate in `steps` speeds.
Teuchos::ParameterList sweepOf(int steps, bool refine = true, double crossingTol = 1e-6) {
  Teuchos::ParameterList study;
  study.set("Steps", steps);
  study.set("Max Factor", 1.0);
  study.set("Crossing Tolerance", crossingTol);
  study.set("Refine Crossings", refine);
  return study;
}

GyroscopicResult solveAt(double W) {
  return DenseGyroscopicSolver().solve(pointMass().at(W));
}
}  // namespace

// Below, between (a narrow margin either side) and above the critical speeds,
// the solver's lambdas equal the closed form to 1e-9 relative; that bound
// covers dggev's backward error ~1e-16 amplified by the conditioning near
// the critical speeds (margin 1e-3: a double root is 1e-3 away at most).
// A root near zero is absolute-accurate only to rounding of the pencil's
// scale, the frequency sqrt(ky / m) + 2 Omega of its largest root: a floor
// of 16 eps of that scale. The residual is the normwise backward error
// (relative, doc/theory.md §4): ~eps for a backward stable solve.
TEST(RotatingPointMass, MatchesClosedFormAtAllSpeedRegimes) {
  const double eps = std::numeric_limits<double>::epsilon();
  for (double W : {0.0, 5.0, 19.9, 20.02, 22.5, 24.98, 25.1, 40.0, 200.0}) {
    const GyroscopicResult r = solveAt(W);
    ASSERT_EQ(r.modes.size(), 2u);
    const std::vector<cplx> ex = exactLambdas(W);
    const double scale = std::sqrt(ky / m) + 2 * W;
    for (int k = 0; k < 2; ++k)
      EXPECT_LT(std::abs(r.modes[k].lambda - ex[k]), 1e-9 * std::abs(ex[k]) + 16 * eps * scale)
          << "Omega=" << W << " k=" << k << " got " << r.modes[k].lambda << " exact " << ex[k];
    // Normwise backward error of a 2-DOF solve: a small multiple of eps.
    EXPECT_LT(r.maxResidual(), 1000 * eps) << "Omega=" << W;
  }
}

TEST(RotatingPointMass, StabilityRegimesAreClassified) {
  // Below the first critical speed: K > 0, Meirovitch's form, stable.
  GyroscopicResult r = solveAt(10.0);
  EXPECT_NE(r.solver.find("Meirovitch"), std::string::npos);
  EXPECT_TRUE(r.isStable());
  // Between the critical speeds: one divergent mode (real positive lambda).
  r = solveAt(22.5);
  EXPECT_NE(r.solver.find("general"), std::string::npos) << r.solver;
  EXPECT_FALSE(r.isStable());
  int div = 0;
  for (const auto& mm : r.modes) div += mm.stability == Stability::Divergence;
  EXPECT_EQ(div, 1);
  // Above: K negative definite, yet stable (gyroscopic stabilisation).
  r = solveAt(40.0);
  EXPECT_NE(r.reason.find("not positive definite"), std::string::npos) << r.reason;
  EXPECT_TRUE(r.isStable());
  for (const auto& mm : r.modes) EXPECT_EQ(mm.stability, Stability::Stable);
  // At a critical speed exactly, the stiffness has a null direction and one
  // root is zero: reported as a zero-frequency (rigid) mode, not as a number.
  r = solveAt(20.0);
  EXPECT_EQ(r.modes[0].stability, Stability::RigidBody);
}

TEST(RotatingPointMass, CampbellFindsTheDivergenceRange) {
  // Frame rate 0 to 30 rad/s in 300 steps of 0.1 rad/s.
  Teuchos::ParameterList study;
  study.set("Steps", 301);
  study.set("Max Factor", 1.0);
  study.set("Refine Crossings", false);
  const auto d = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(pointMass(), "frame", 30.0));
  const auto& ranges = d.unstableRanges;
  ASSERT_EQ(ranges.size(), 1u);
  EXPECT_FALSE(d.unstableEdgesRefined);
  // Sweep step 0.1: the first/last unstable sample lies within one step inside
  // (20, 25); exactly at 20 and 25 the zero root is neutral. Without
  // "Refine Crossings" the grid's range ends there; the stiffness count,
  // bisected either way, proves the band divergent between its zeros
  // (theory §12.1, "A band between two speeds"), and the range is the
  // count's: 20 and 25 to the Crossing Tolerance (1e-6 of the speed,
  // doubled: the bracket's middle, and a rounding of the count's pivot).
  ASSERT_EQ(d.unstableByCount.size(), 1u);
  EXPECT_TRUE(d.unstableByCount[0]);
  EXPECT_NEAR(ranges[0].first, 20.0, 2e-6 * 20.0);
  EXPECT_NEAR(ranges[0].second, 25.0, 2e-6 * 25.0);
}

TEST(RotatingPointMass, CampbellBisectsTheDivergenceRangesEdges) {
  // Steps of 3 rad/s (0, 3, ..., 30): the grid's unstable speeds are 21 and
  // 24, up to a step inside the band (20, 25). Bisected, each edge lies in
  // a bracket narrower than "Crossing Tolerance" 1e-9 of the speed, and it
  // is its middle: within 1e-9 of 20 and 25 (0.5e-9 for the half bracket,
  // doubled for the solver's verdict a rounding away from the edge, where
  // the zero root is neutral).
  Teuchos::ParameterList study;
  study.set("Steps", 11);
  study.set("Max Factor", 1.0);
  study.set("Crossing Tolerance", 1e-9);
  const auto d = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(pointMass(), "frame", 30.0));
  ASSERT_EQ(d.unstableRanges.size(), 1u);
  EXPECT_TRUE(d.unstableEdgesRefined);
  EXPECT_NEAR(d.unstableRanges[0].first, 20.0, 1e-9 * 20.0);
  EXPECT_NEAR(d.unstableRanges[0].second, 25.0, 1e-9 * 25.0);
}

// Isotropic springs: in the rotating frame omega = |sqrt(k/m) -/+ Omega|.
TEST(RotatingPointMass, IsotropicSpringsGiveShiftedFrequencies) {
  auto s = pointMass();
  s.K0(1, 1) = kx;
  const double w0 = std::sqrt(kx / m);
  for (double W : {3.0, 12.0, 35.0}) {
    const GyroscopicResult r = DenseGyroscopicSolver().solve(s.at(W));
    std::vector<double> ex = {std::abs(w0 - W), w0 + W};
    std::sort(ex.begin(), ex.end());
    for (int k = 0; k < 2; ++k) EXPECT_NEAR(r.modes[k].omega, ex[k], 1e-10 * ex[k]) << W;
    EXPECT_TRUE(r.isStable());
  }
}

// A critical speed on the sweep's grid (20 rad/s, of steps 0, 10, 20, 30):
// the lower mode is zero there, and the 1X crossing of that mode below it
// (between 10 and 20) was skipped with the whole interval, a critical speed
// silently missed (found by a review; 6 steps found it). It must be found,
// refined, where a fine sweep (31 steps) puts it, to the bisection's
// tolerance (1e-9 of the speed, doubled for the two runs).
TEST(RotatingPointMass, ACrossingBelowACriticalSpeedOnTheGridIsFound) {
  const auto crossings = [](int steps) {
    Teuchos::ParameterList study;
    study.set("Steps", steps);
    study.set("Max Factor", 1.0);
    study.set("Crossing Tolerance", 1e-9);
    return analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(pointMass(), "frame", 30.0)).crossings;
  };
  const auto fine = crossings(31);
  ASSERT_EQ(fine.size(), 1u) << "the premise: one 1X crossing, of the lower mode below 20 rad/s";
  EXPECT_GT(fine[0].speed, 10.0);
  EXPECT_LT(fine[0].speed, 20.0);
  const auto coarse = crossings(4);
  ASSERT_EQ(coarse.size(), 1u) << "the crossing between 10 and the critical speed 20 on the grid";
  EXPECT_TRUE(coarse[0].refined);
  EXPECT_NEAR(coarse[0].speed, fine[0].speed, 2e-9 * fine[0].speed);
}

// An unstable range that reaches the end of the sweep has no upper edge in
// it: swept to 22.5 rad/s, the divergence band (20, 25) is unstable from 20
// to the sweep's end and beyond, which the description must say, not
// "edges bisected" as if 22.5 were where it stabilises (found by a review).
TEST(RotatingPointMass, AnUnstableRangeOpenAtTheSweepsEndSaysSo) {
  Teuchos::ParameterList study;
  study.set("Steps", 10);
  study.set("Max Factor", 1.0);
  const auto d = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(pointMass(), "frame", 22.5));
  ASSERT_EQ(d.unstableRanges.size(), 1u);
  ASSERT_EQ(d.unstableOpen.size(), 1u);
  EXPECT_FALSE(d.unstableOpen[0].first);
  EXPECT_TRUE(d.unstableOpen[0].second);
  EXPECT_NEAR(d.unstableRanges[0].first, 20.0, 1e-6 * 20.0);
  EXPECT_EQ(d.unstableRanges[0].second, 22.5);
  std::ostringstream os;
  d.printCrossings(os);
  EXPECT_NE(os.str().find("unstable from 20 to 22.5 rad/s of 'frame' and beyond (still unstable at the sweep's end"),
            std::string::npos)
      << os.str();
}

// A divergence band that no grid speed falls in (speeds 0, 15, 30 about the
// band (20, 25)): every grid speed is stable, and the sweep said so, though
// the count of K's negative eigenvalues, already taken and bisected for the
// zero-frequency speeds 20 and 25, is 1 between them: det K < 0 there, so
// det(lambda^2 M + lambda G + K) has a real positive root, whatever G and
// the damping (theory §12.1, "A band between two speeds"). The band must be
// listed unstable, its edges the bisected zeros (to the Crossing Tolerance
// 1e-9 of the speed, doubled: the bracket's middle within half its width,
// and the count's zero pivot a rounding away), with or without "Refine
// Crossings" (the count is bisected either way). Before, no range was
// listed (found by a review).
TEST(RotatingPointMass, ADivergenceBandBetweenTwoSweepSpeedsIsListed) {
  for (const bool refine : {true, false}) {
    auto study = sweepOf(3, refine, 1e-9);
    const auto d = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(pointMass(), "frame", 30.0));
    ASSERT_EQ(d.zeroFrequencySpeeds.size(), 2u) << "the premise: both zeros found by the count";
    ASSERT_EQ(d.unstableRanges.size(), 1u) << "refine " << refine;
    EXPECT_NEAR(d.unstableRanges[0].first, 20.0, 2e-9 * 20.0);
    EXPECT_NEAR(d.unstableRanges[0].second, 25.0, 2e-9 * 25.0);
    ASSERT_EQ(d.unstableOpen.size(), 1u);
    EXPECT_FALSE(d.unstableOpen[0].first);
    EXPECT_FALSE(d.unstableOpen[0].second);
    std::ostringstream os;
    d.printCrossings(os);
    EXPECT_NE(os.str().find("odd number of negative eigenvalues"), std::string::npos) << os.str();
    // The same band seen at a grid speed (22.5 of 0, 7.5, ..., 30) gives
    // the same edges: the two ways agree.
    study.set("Steps", 5);
    const auto g = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(pointMass(), "frame", 30.0));
    ASSERT_EQ(g.unstableRanges.size(), 1u);
    if (refine) {
      EXPECT_NEAR(g.unstableRanges[0].first, d.unstableRanges[0].first, 2e-9 * 20.0);
      EXPECT_NEAR(g.unstableRanges[0].second, d.unstableRanges[0].second, 2e-9 * 25.0);
    }
  }
  // No false alarm: isotropic springs pass both frequencies through zero
  // at one speed (20 rad/s; the count goes 0 to 2 there), and the mass is
  // gyroscopically stable on either side: no range.
  auto iso = pointMass();
  iso.K0(1, 1) = kx;
  const auto study = sweepOf(3, true, 1e-9);
  const auto d = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(iso, "frame", 30.0));
  ASSERT_EQ(d.zeroFrequencySpeeds.size(), 1u);
  EXPECT_NEAR(d.zeroFrequencySpeeds[0], 20.0, 2e-9 * 20.0);
  EXPECT_TRUE(d.unstableRanges.empty());
  // Where a circulatory N acts the parity proves nothing (p(0) = det(K +
  // N)): the same counts, said to come with N, list no band.
  class WithCirculation : public analysis::DenseSweepProblem {
  public:
    using analysis::DenseSweepProblem::DenseSweepProblem;
    analysis::StiffnessCount stiffnessCount(const std::vector<double>& speeds) const override {
      auto c = analysis::DenseSweepProblem::stiffnessCount(speeds);
      c.circulatory = true;
      return c;
    }
  };
  const auto n = analysis::CampbellStudy(study).run(WithCirculation(pointMass(), "frame", 30.0));
  EXPECT_EQ(n.zeroFrequencySpeeds.size(), 2u);
  EXPECT_TRUE(n.unstableRanges.empty());
}

// Past its critical speed an isotropic mass's lower mode, |omega_0 -
// Omega|, comes back conjugated: its circular orbit then turns the way the
// upper mode's does, and both modes have one shape (MAC 1 with the upper
// track's last, 0 with the lower's). The MAC alone cannot tell them
// apart; the tracks must follow the frequencies' continuity: the upper
// track is omega_0 + Omega at every speed and the lower |omega_0 - Omega|
// (each to 1e-9 of omega_0 + Omega: the eigenvalues of a 2-DOF dense
// solve). The upper track took |omega_0 - Omega| past 20 rad/s, the lower
// was lost and a 1X crossing read on the jump (an open finding of an
// earlier review; theory §12.1, "Ties").
TEST(RotatingPointMass, IsotropicTracksKeepTheirBranchesPastTheCriticalSpeed) {
  auto iso = pointMass();
  iso.K0(1, 1) = kx;
  const double w0 = std::sqrt(kx / m);  // 20 rad/s
  // To 45 rad/s in steps below omega_0, and to 100 in 6 steps (h = 20 =
  // omega_0) and 5 (h = 25 > omega_0): with the change from the last value
  // alone the tracks swapped at every step past h = omega_0 (a review).
  for (const auto& [steps, top] : std::vector<std::pair<int, double>>{{7, 45.0}, {11, 45.0}, {16, 45.0}, {31, 45.0},
                                                                       {6, 100.0}, {5, 100.0}, {4, 120.0}}) {
    SCOPED_TRACE(std::to_string(steps) + " steps to " + std::to_string(top));
    const auto d = analysis::CampbellStudy(sweepOf(steps, false)).run(analysis::DenseSweepProblem(iso, "frame", top));
    ASSERT_EQ(d.tracks.size(), 2u);
    for (const auto& tr : d.tracks) {
      const bool upper = tr.omega.back() > top;  // omega_0 + top at the sweep's end, the lower top - omega_0
      for (std::size_t k = 0; k < tr.omega.size(); ++k) {
        const double W = d.speeds[k][0];
        if (tr.lost[k]) continue;
        EXPECT_NEAR(tr.omega[k], upper ? w0 + W : std::abs(w0 - W), 1e-9 * (w0 + W))
            << (upper ? "upper" : "lower") << " track at " << W << " rad/s";
      }
    }
    // One 1X crossing, the lower whirl's at omega_0 / 2 = 10 rad/s (linear
    // between sweep speeds: exact where the branch is linear over its step,
    // its zero at 20 not inside that step; else inside the step); the swap
    // read a second on the jump (18.75 rad/s at 7 steps).
    ASSERT_EQ(d.crossings.size(), 1u) << d.crossings.back().speed;
    const double h = top / (steps - 1);
    if (h <= w0)
      EXPECT_NEAR(d.crossings[0].speed, 10.0, 1e-9 * 10.0);
    else
      EXPECT_TRUE(d.crossings[0].speed > 0.0 && d.crossings[0].speed < h) << d.crossings[0].speed;
  }
}

// A track keeps its mode's identity through a critical speed that hides
// it: a mass on isotropic springs (k = 100, m = 1: the in-plane pair at
// 10 -/+ Omega in the rotating frame) with internal damping (c = 1 in x,
// y) and an axial spring (k = 1e4: 100 rad/s, independent of speed), the
// three lowest modes asked. At Omega = 10 the in-plane pair has two zero
// frequencies and the axial mode drops out of the three; a zero frequency
// took any mode, so the axial track followed an in-plane zero and an
// in-plane track took the axial mode when it came back, with no word
// (found by a review). Every track must be the axial mode (100 rad/s)
// wherever it is not lost, or never.
TEST(RotatingPointMass, ATrackKeepsItsModeThroughACriticalSpeedThatHidesIt) {
  analysis::SpeedDependentSystem s;
  s.M.shape(3, 3), s.G1.shape(3, 3), s.K0.shape(3, 3), s.K2.shape(3, 3), s.D.shape(3, 3);
  s.M(0, 0) = s.M(1, 1) = s.M(2, 2) = 1.0;
  s.G1(0, 1) = -2.0, s.G1(1, 0) = 2.0;
  s.K0(0, 0) = s.K0(1, 1) = 100.0, s.K0(2, 2) = 1e4;
  s.K2(0, 0) = s.K2(1, 1) = -1.0;
  s.D(0, 0) = s.D(1, 1) = 1.0;
  Teuchos::ParameterList solver;
  solver.set("Number of Modes", 3);
  Teuchos::ParameterList study;
  study.set("Steps", 11);
  study.set("Max Factor", 2.0);
  const auto d = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(s, "mass", 10.0, solver));
  int axial = 0;
  for (std::size_t t = 0; t < d.tracks.size(); ++t) {
    const auto& tr = d.tracks[t];
    int isAxial = 0, other = 0;
    for (std::size_t k = 0; k < tr.omega.size(); ++k) {
      if (tr.lost[k]) continue;
      (std::abs(tr.omega[k] - 100.0) < 1e-6 * 100.0 ? isAxial : other)++;
    }
    EXPECT_TRUE(isAxial == 0 || other == 0) << "track " << t + 1 << " is the axial mode at " << isAxial
                                            << " speeds and another mode at " << other;
    axial += isAxial > 0;
  }
  EXPECT_EQ(axial, 1) << "one track for the axial mode";
  // Lost at the critical speed only, and said so.
  std::ostringstream os;
  d.printCrossings(os);
  EXPECT_NE(os.str().find("left the requested modes at 10 rad/s of 'mass' and came back at 12 rad/s"),
            std::string::npos)
      << os.str();
}

// Where a frequency passes through zero, K(Omega) = diag(kx - m Omega^2,
// ky - m Omega^2) is singular: at 20 and 25 rad/s exactly (the critical
// speeds of this frame). The tracks cannot show it (the grid rarely falls
// on it, and past it the mode comes back conjugated), and no crossing list
// had it: a disc on a spinning shaft had its unbalance critical speed
// nowhere in the output (found by a review). Bisected on the count of K's
// negative eigenvalues, to "Crossing Tolerance" 1e-9 of the speed (doubled:
// the count at the bracket's middle).
TEST(RotatingPointMass, ZeroFrequencyCriticalSpeedsAreFoundByTheStiffnessCount) {
  Teuchos::ParameterList study;
  study.set("Steps", 4);  // 0, 10, 20, 30: the first one on the grid
  study.set("Max Factor", 1.0);
  study.set("Crossing Tolerance", 1e-9);
  const auto d = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(pointMass(), "frame", 30.0));
  ASSERT_TRUE(d.zeroCountsTaken);
  ASSERT_EQ(d.zeroFrequencySpeeds.size(), 2u);
  EXPECT_NEAR(d.zeroFrequencySpeeds[0], 20.0, 2e-9 * 20.0);
  EXPECT_NEAR(d.zeroFrequencySpeeds[1], 25.0, 2e-9 * 25.0);
  std::ostringstream csv;
  d.writeCrossingsCsv(csv);
  EXPECT_NE(csv.str().find("\n0,25"), std::string::npos) << csv.str();
}

// A crossing bisected from a repeated pair: on isotropic springs (k = 800,
// m = 2: 20 -/+ Omega in the rotating frame) the pair is double at rest, and
// its lower branch meets 1.25X at 20 / 2.25 = 8.889 rad/s. With the grid 0,
// 10 the bisection starts from the double mode, any combination of the two
// branches (MAC ~0.5 with each once the speed splits them): it followed the
// upper branch, which never crosses, and reported a jump instead of the
// crossing (found by a review). Bisected to 1e-9, doubled for the two ends.
TEST(RotatingPointMass, ACrossingBisectedFromARepeatedPairFollowsItsOwnBranch) {
  auto s = pointMass();
  s.K0(1, 1) = kx;
  Teuchos::ParameterList study;
  study.set("Steps", 2);
  study.set("Max Factor", 1.0);
  study.set("Crossing Tolerance", 1e-9);
  study.set("Engine Orders", Teuchos::Array<double>(1, 1.25));
  const auto d = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(s, "frame", 10.0));
  EXPECT_TRUE(d.branchJumps.empty()) << d.branchJumps.size() << " jump(s) reported";
  ASSERT_EQ(d.crossings.size(), 1u);
  EXPECT_TRUE(d.crossings[0].refined);
  EXPECT_NEAR(d.crossings[0].speed, 20.0 / 2.25, 2e-9 * 20.0 / 2.25);
}

// The stiffness count judges a pivot zero against its own row's stiffness:
// a soft spring (k = 100, m = 1: zero frequency at Omega = 10) beside a
// spring 1e14 times stiffer. Judged against the largest diagonal, the soft
// pivot went negative only well past 10 rad/s (5% late at 1e12, never at
// 1e16; a review). And two zero frequencies in one step are two speeds
// with or without "Refine Crossings" (the count is always bisected).
TEST(RotatingPointMass, ZeroFrequenciesBesideAStiffSpringAndTwoInOneStep) {
  analysis::SpeedDependentSystem s;
  s.M.shape(2, 2), s.G1.shape(2, 2), s.K0.shape(2, 2), s.K2.shape(2, 2);
  s.M(0, 0) = s.M(1, 1) = 1.0;
  s.K0(0, 0) = 100.0, s.K0(1, 1) = 1e16;
  s.K2(0, 0) = -1.0;
  Teuchos::ParameterList study;
  study.set("Steps", 4);
  study.set("Max Factor", 1.0);
  study.set("Crossing Tolerance", 1e-9);
  const auto d = analysis::CampbellStudy(study).run(analysis::DenseSweepProblem(s, "frame", 20.0));
  ASSERT_EQ(d.zeroFrequencySpeeds.size(), 1u);
  EXPECT_NEAR(d.zeroFrequencySpeeds[0], 10.0, 2e-9 * 10.0);

  Teuchos::ParameterList coarse;
  coarse.set("Steps", 2);  // 0 and 30: both zero frequencies, 20 and 25, in one step
  coarse.set("Max Factor", 1.0);
  coarse.set("Refine Crossings", false);
  coarse.set("Crossing Tolerance", 1e-9);
  const auto two = analysis::CampbellStudy(coarse).run(analysis::DenseSweepProblem(pointMass(), "frame", 30.0));
  ASSERT_EQ(two.zeroFrequencySpeeds.size(), 2u);
  EXPECT_NEAR(two.zeroFrequencySpeeds[0], 20.0, 2e-9 * 20.0);
  EXPECT_NEAR(two.zeroFrequencySpeeds[1], 25.0, 2e-9 * 25.0);
}

// A count refused at a grid speed (the sparse inertia's pivot zero to
// rounding where a critical speed falls on the grid) is taken again a
// tolerance of a step above it: the critical speeds at 20 (on the grid
// 0, 10, 20, 30) and 25 are still found. Before, one refusal ended the
// whole search, "not sought" (a review).
TEST(RotatingPointMass, ACountRefusedOnTheGridIsTakenJustAboveIt) {
  class RefusingOnTheGrid : public analysis::DenseSweepProblem {
  public:
    RefusingOnTheGrid() : DenseSweepProblem(pointMass(), "frame", 30.0) {}
    analysis::StiffnessCount stiffnessCount(const std::vector<double>& speeds) const override {
      if (speeds[0] == 20.0) {
        analysis::StiffnessCount refused;
        refused.why = "a pivot zero to rounding (this test's)";
        return refused;
      }
      return DenseSweepProblem::stiffnessCount(speeds);
    }
  };
  Teuchos::ParameterList study;
  study.set("Steps", 4);
  study.set("Max Factor", 1.0);
  study.set("Crossing Tolerance", 1e-9);
  const auto d = analysis::CampbellStudy(study).run(RefusingOnTheGrid());
  EXPECT_TRUE(d.zeroCountsTaken);
  ASSERT_EQ(d.zeroFrequencySpeeds.size(), 2u) << d.zeroCountsNote;
  EXPECT_NEAR(d.zeroFrequencySpeeds[0], 20.0, 2e-8 * 20.0);
  EXPECT_NEAR(d.zeroFrequencySpeeds[1], 25.0, 2e-9 * 25.0);
}
