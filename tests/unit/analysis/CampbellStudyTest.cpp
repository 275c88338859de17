// analysis::CampbellStudy on small systems whose frequencies are closed
// form: tracking keeps a mode's identity through a crossing and follows the
// branch through a veering; engine-order crossings (critical speeds) are
// where the closed form puts them, bisected or interpolated to a bound that
// the sweep resolution justifies; tracks at a spin rate (rigid motions seen
// from a spinning frame) give no critical speeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <Teuchos_Array.hpp>

#include "ExpectError.hpp"
#include "cms/analysis/CampbellStudy.hpp"

using namespace cms;

namespace {

/// M = I, G = 0, K(Omega) = [[k1, e], [e, k2 + c Omega^2]]: omega_1 = sqrt(k1)
/// stays, omega_2 = sqrt(k2 + c Omega^2) rises through it at
/// Omega = sqrt((k1 - k2) / c) (e = 0: a crossing), or veers away (e != 0).
analysis::SpeedDependentSystem twoDof(double k1, double k2, double c, double e) {
  analysis::SpeedDependentSystem s;
  s.M.shape(2, 2), s.G1.shape(2, 2), s.K0.shape(2, 2), s.K2.shape(2, 2);
  s.M(0, 0) = s.M(1, 1) = 1.0;
  s.K0(0, 0) = k1, s.K0(1, 1) = k2, s.K0(0, 1) = s.K0(1, 0) = e;
  s.K2(1, 1) = c;
  return s;
}

/// Closed-form eigenvalues of the symmetric 2 x 2 K at Omega: (lower, upper) omega.
std::pair<double, double> exact(double k1, double k2, double c, double e, double Omega) {
  const double a = k1, b = k2 + c * Omega * Omega;
  const double mid = 0.5 * (a + b), rad = std::sqrt(0.25 * (a - b) * (a - b) + e * e);
  return {std::sqrt(mid - rad), std::sqrt(mid + rad)};
}

Teuchos::ParameterList sweep(int steps, double maxFactor, std::vector<double> orders = {1.0}, bool refine = true) {
  Teuchos::ParameterList p;
  p.set("Steps", steps);
  p.set("Max Factor", maxFactor);
  p.set("Engine Orders", Teuchos::Array<double>(orders));
  p.set("Refine Crossings", refine);
  return p;
}

/// MAC of modes whose shapes q are unit vectors of an orthonormal basis:
/// |a^H b|^2 over the components both have.
std::vector<std::vector<double>> coordinateMac(const std::vector<eigen::GyroscopicMode>& a,
                                               const std::vector<eigen::GyroscopicMode>& b) {
  std::vector<std::vector<double>> m(a.size(), std::vector<double>(b.size()));
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j) {
      std::complex<double> d = 0.0;
      for (std::size_t k = 0; k < std::min(a[i].q.size(), b[j].q.size()); ++k) d += std::conj(a[i].q[k]) * b[j].q[k];
      m[i][j] = std::norm(d);
    }
  return m;
}

/// Two spin rates, "bus" (swept) and "wheel" (held at 10 rad/s), and two
/// modes in closed form: one whose frequency is the wheel's rate within
/// a(bus)^2 (a rigid motion of the wheel seen at its rate, slightly bent by
/// the bus's speed: a frame-rate track that crosses 1X of the bus where
/// bus = wheel (1 + a bus^2)), and a stiff mode of the bus at 50 rad/s. Each
/// mode is dominated by the part it moves.
class TwoRateProblem : public analysis::SpeedSweepProblem {
public:
  static constexpr double kWheel = 10.0, kBend = 1e-6, kStiff = 50.0;
  std::vector<synthesis::SpeedParameter> parameters() const override { return {{"bus", 1.0}, {"wheel", kWheel}}; }
  synthesis::StructureModes solve(const std::vector<double>& speeds) const override {
    synthesis::StructureModes out;
    out.speeds = speeds;
    const double wheel = speeds[1] * (1.0 + kBend * speeds[0] * speeds[0]);
    for (const double w : {wheel, kStiff}) {
      eigen::GyroscopicMode m;
      m.omega = w, m.hz = w / (2 * M_PI), m.lambda = {0.0, w};
      m.q = {w == kStiff ? 0.0 : 1.0, w == kStiff ? 1.0 : 0.0};
      out.result.modes.push_back(m);
    }
    return out;
  }
  std::vector<std::vector<double>> mac(const std::vector<eigen::GyroscopicMode>& a,
                                       const std::vector<eigen::GyroscopicMode>& b) const override {
    return coordinateMac(a, b);
  }
  std::vector<analysis::Whirl> whirl(const synthesis::StructureModes& modes,
                                     const analysis::WhirlClassification&) const override {
    return std::vector<analysis::Whirl>(modes.result.modes.size(), analysis::Whirl::Neutral);
  }
  std::string whirlOf() const override { return ""; }
  std::vector<std::string> dominant(const synthesis::StructureModes& modes) const override {
    std::vector<std::string> names;
    for (const auto& m : modes.result.modes) names.push_back(std::abs(m.q[0]) > 0.5 ? "wheel" : "bus");
    return names;
  }
};

// The frequencies are eigenvalues of symmetric 2 x 2 problems: computed to
// a few eps times the largest (Weyl), 100 eps of margin for the gyroscopic
// formulation the solver uses.
const double kRound = 100 * DBL_EPSILON;

}  // namespace

TEST(CampbellStudy, TrackKeepsItsIdentityThroughACrossing) {
  const double k1 = 4.0, k2 = 1.0, c = 1.0;  // cross at Omega = sqrt(3)
  const auto r = analysis::CampbellStudy(sweep(31, 1.0)).run(
      analysis::DenseSweepProblem(twoDof(k1, k2, c, 0.0), "spin", 3.0));
  ASSERT_EQ(r.tracks.size(), 2u);
  // Track 1 starts lowest (omega_2(0) = 1) and keeps rising past track 2
  // (omega_1 = 2): sorting by frequency would swap them at the crossing.
  for (std::size_t k = 0; k < r.factors.size(); ++k) {
    const double W = r.speeds[k][0], rising = std::sqrt(k2 + c * W * W);
    EXPECT_NEAR(r.tracks[0].omega[k], rising, kRound * 4.0) << "Omega " << W;
    EXPECT_NEAR(r.tracks[1].omega[k], std::sqrt(k1), kRound * 4.0) << "Omega " << W;
  }
  // Where the tracks cross, by linear interpolation of their difference
  // g = omega_2 - omega_1 between sweep speeds: the error is at most
  // h^2 max|g''| / (8 min|g'|) with h = 0.1, |g''| <= 1, |g'| >= 0.8 on the
  // bracket (1.7, 1.8).
  double crossing = std::nan("");
  for (std::size_t k = 1; k < r.factors.size(); ++k) {
    const double g0 = r.tracks[0].omega[k - 1] - r.tracks[1].omega[k - 1];
    const double g1 = r.tracks[0].omega[k] - r.tracks[1].omega[k];
    if (g0 < 0 && g1 >= 0) crossing = r.speeds[k - 1][0] + g0 / (g0 - g1) * (r.speeds[k][0] - r.speeds[k - 1][0]);
  }
  EXPECT_NEAR(crossing, std::sqrt((k1 - k2) / c), 0.1 * 0.1 / (8 * 0.8));
  // Uncoupled: each mode is a unit vector throughout, so its MAC with the
  // previous one is 1 up to the rounding of two 2-term products: kRound.
  EXPECT_GT(r.tracks[0].minMac, 1.0 - kRound);
}

TEST(CampbellStudy, TrackFollowsItsBranchThroughAVeering) {
  // Coupled (e = 0.05): the branches come within 2e of each other in omega^2
  // near Omega = sqrt(3) and turn away; the eigenvectors rotate by 90
  // degrees over |a - b| ~ e, at most 1 / (4 e) * d(a - b)/dOmega = 17 rad
  // per rad/s. Steps of 0.005 rad/s turn them at most 5 degrees per step, so
  // the MAC with the same branch stays above cos^2(5 deg) and the track does
  // not jump to the other branch.
  const double k1 = 4.0, k2 = 1.0, c = 1.0, e = 0.05;
  const auto r = analysis::CampbellStudy(sweep(601, 1.0)).run(
      analysis::DenseSweepProblem(twoDof(k1, k2, c, e), "spin", 3.0));
  ASSERT_EQ(r.tracks.size(), 2u);
  for (std::size_t k = 0; k < r.factors.size(); ++k) {
    const auto [lo, hi] = exact(k1, k2, c, e, r.speeds[k][0]);
    EXPECT_NEAR(r.tracks[0].omega[k], lo, kRound * 4.0) << "Omega " << r.speeds[k][0];
    EXPECT_NEAR(r.tracks[1].omega[k], hi, kRound * 4.0) << "Omega " << r.speeds[k][0];
  }
  const double c5 = std::cos(5.0 * M_PI / 180.0);
  EXPECT_GT(r.tracks[0].minMac, c5 * c5 - 0.01);
  EXPECT_GT(r.tracks[1].minMac, c5 * c5 - 0.01);
}

TEST(CampbellStudy, EngineOrderCriticalSpeedsMatchTheClosedForm) {
  // Track 1: omega = sqrt(1 + Omega^2) meets 2 Omega at 1/sqrt(3), never 1X;
  // track 2: omega = 2 meets 1X at 2 and 2X at 1.
  const double tol = 1e-9;
  auto params = sweep(31, 1.0, {1.0, 2.0});
  params.set("Crossing Tolerance", tol);
  const analysis::DenseSweepProblem problem(twoDof(4.0, 1.0, 1.0, 0.0), "spin", 3.0);
  const auto r = analysis::CampbellStudy(params).run(problem);
  ASSERT_EQ(r.crossings.size(), 3u);
  struct Expected { double order, speed; int track; };
  const Expected want[] = {{1.0, 2.0, 1}, {2.0, 1.0 / std::sqrt(3.0), 0}, {2.0, 1.0, 1}};
  for (int i = 0; i < 3; ++i) {
    const auto& c = r.crossings[i];
    EXPECT_EQ(c.order, want[i].order);
    ASSERT_EQ(c.tracks.size(), 1u);
    EXPECT_EQ(c.tracks[0], want[i].track);
    EXPECT_TRUE(c.refined);
    // Bisection stops with a bracket narrower than tol times its top; the
    // crossing is interpolated inside it.
    EXPECT_NEAR(c.speed, want[i].speed, tol * 3.0 + kRound * 4.0) << "crossing " << i;
    EXPECT_NEAR(c.omega, c.order * c.speed, kRound * 8.0);
  }
  // Without bisection: linear interpolation of g = omega - n Omega between
  // sweep speeds, h = 0.1. Track 2's g is linear (exact to rounding); track
  // 1's has |g''| <= 1 and |g'| >= 1.29, so the error is below h^2 / (8 * 1.29).
  const auto coarse = analysis::CampbellStudy(sweep(31, 1.0, {1.0, 2.0}, false)).run(problem);
  ASSERT_EQ(coarse.crossings.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(coarse.crossings[i].refined);
    EXPECT_NEAR(coarse.crossings[i].speed, want[i].speed, want[i].track == 0 ? 0.01 / (8 * 1.29) : kRound * 40.0);
  }
}

// An order given twice ("1,1.0") is swept once: each crossing was listed
// twice, its tracks "2,2" (found by a review). And the per-rev axis at
// rest, where frequency over speed is no number, prints "-", not inf/nan.
TEST(CampbellStudy, AnOrderGivenTwiceIsSweptOnceAndPerRevAtRestIsNoNumber) {
  const analysis::DenseSweepProblem problem(twoDof(4.0, 1.0, 1.0, 0.0), "spin", 3.0);
  const auto once = analysis::CampbellStudy(sweep(31, 1.0, {1.0, 2.0})).run(problem);
  const auto twice = analysis::CampbellStudy(sweep(31, 1.0, {2.0, 1.0, 1.0, 2.0})).run(problem);
  ASSERT_EQ(twice.crossings.size(), once.crossings.size());
  EXPECT_EQ(twice.orders, once.orders);
  for (std::size_t i = 0; i < once.crossings.size(); ++i) {
    EXPECT_EQ(twice.crossings[i].order, once.crossings[i].order);
    EXPECT_EQ(twice.crossings[i].tracks, once.crossings[i].tracks);
  }
  std::ostringstream table;
  once.printTable(table, analysis::SpeedAxis::PerRev);
  EXPECT_EQ(table.str().find("inf"), std::string::npos) << table.str();
  EXPECT_EQ(table.str().find("nan"), std::string::npos) << table.str();
}

TEST(CampbellStudy, ASpinAgainstItsAxisHasTheSameCriticalSpeeds) {
  // A negative rate turns the other way about the same axis: K(Omega)
  // depends on Omega^2 and the frequencies do not change, and an engine
  // order n excites n |Omega|. The crossings are the positive rate's at the
  // negative speeds. Before: n Omega < 0 lay below every frequency and no
  // crossing was found ("none in the sweep").
  auto params = sweep(31, 1.0, {1.0, 2.0});
  params.set("Crossing Tolerance", 1e-9);
  const auto forward = analysis::CampbellStudy(params).run(
      analysis::DenseSweepProblem(twoDof(4.0, 1.0, 1.0, 0.0), "spin", 3.0));
  const auto against = analysis::CampbellStudy(params).run(
      analysis::DenseSweepProblem(twoDof(4.0, 1.0, 1.0, 0.0), "spin", -3.0));
  ASSERT_EQ(forward.crossings.size(), 3u);
  ASSERT_EQ(against.crossings.size(), forward.crossings.size());
  for (std::size_t i = 0; i < forward.crossings.size(); ++i) {
    const auto &a = against.crossings[i], &f = forward.crossings[i];
    EXPECT_EQ(a.order, f.order);
    EXPECT_EQ(a.tracks, f.tracks);
    // The same bisection on mirrored speeds: to its tolerance, 1e-9.
    EXPECT_NEAR(a.speed, -f.speed, 3e-9 * std::abs(f.speed)) << "crossing " << i;
    EXPECT_NEAR(a.omega, f.omega, 3e-9 * f.omega) << "crossing " << i;
    EXPECT_GT(a.omega, 0.0);
  }
}

TEST(CampbellStudy, AModeLeavingTheRequestedSetEndsItsTrack) {
  // Three uncoupled modes, the two lowest requested: a = 1 stays, b =
  // sqrt(2 + 4 Omega^2) rises past c = 2.5 at Omega = sqrt(4.25) / 2 =
  // 1.031, and from there the set is {a, c}. Track 2 (b) must end there and
  // c start a track of its own; before, track 2 went on as c (a jump from
  // 2.45 to 2.5 read as one mode) and c's 1X crossing at 2.5 rad/s was
  // credited to b.
  analysis::SpeedDependentSystem s;
  s.M.shape(3, 3), s.G1.shape(3, 3), s.K0.shape(3, 3), s.K2.shape(3, 3);
  for (int i = 0; i < 3; ++i) s.M(i, i) = 1.0;
  s.K0(0, 0) = 1.0, s.K0(1, 1) = 2.0, s.K0(2, 2) = 6.25;
  s.K2(1, 1) = 4.0;
  Teuchos::ParameterList solver;
  solver.set("Number of Modes", 2);
  auto params = sweep(31, 1.0, {1.0});
  params.set("Crossing Tolerance", 1e-9);
  const auto r = analysis::CampbellStudy(params).run(analysis::DenseSweepProblem(s, "spin", 3.0, solver));
  ASSERT_EQ(r.tracks.size(), 3u);
  const int enters = 11;  // Omega = 1.1, the first grid speed past 1.031
  for (std::size_t k = 0; k < r.factors.size(); ++k) {
    const double W = r.speeds[k][0];
    EXPECT_NEAR(r.tracks[0].omega[k], 1.0, kRound * 4.0);
    if (static_cast<int>(k) < enters) {
      EXPECT_NEAR(r.tracks[1].omega[k], std::sqrt(2.0 + 4.0 * W * W), kRound * 20.0) << "Omega " << W;
      EXPECT_TRUE(r.tracks[2].lost[k] && std::isnan(r.tracks[2].omega[k])) << "Omega " << W;
    } else {
      EXPECT_TRUE(r.tracks[1].lost[k] && std::isnan(r.tracks[1].omega[k])) << "Omega " << W;
      EXPECT_NEAR(r.tracks[2].omega[k], 2.5, kRound * 20.0) << "Omega " << W;
    }
  }
  EXPECT_EQ(r.tracks[2].firstStep, enters);
  // 1X: a at 1 rad/s, c at 2.5 (b = sqrt(2 + 4 Omega^2) > Omega never meets it).
  ASSERT_EQ(r.crossings.size(), 2u);
  EXPECT_EQ(r.crossings[0].tracks, std::vector<int>{0});
  EXPECT_NEAR(r.crossings[0].speed, 1.0, 3e-9);
  EXPECT_EQ(r.crossings[1].tracks, std::vector<int>{2});
  EXPECT_NEAR(r.crossings[1].speed, 2.5, 3e-9 * 2.5);
  EXPECT_TRUE(r.crossings[1].refined);
  std::ostringstream os;
  r.printCrossings(os);
  EXPECT_NE(os.str().find("track3 entered the requested modes at 1.1 rad/s"), std::string::npos) << os.str();
  EXPECT_NE(os.str().find("track2 left the requested modes at 1.1 rad/s"), std::string::npos) << os.str();
}

/// One mode, omega = Omega^2 - 2 Omega + 2 exactly: it meets 1X at 1 (from
/// above) and at 2 (from below).
class ParabolaProblem : public analysis::SpeedSweepProblem {
public:
  std::vector<synthesis::SpeedParameter> parameters() const override { return {{"spin", 2.0}}; }
  synthesis::StructureModes solve(const std::vector<double>& speeds) const override {
    synthesis::StructureModes out;
    out.speeds = speeds;
    eigen::GyroscopicMode m;
    const double W = speeds[0];
    m.omega = W * W - 2.0 * W + 2.0, m.hz = m.omega / (2 * M_PI), m.lambda = {0.0, m.omega};
    m.q = {1.0};
    out.result.modes.push_back(m);
    return out;
  }
  std::vector<std::vector<double>> mac(const std::vector<eigen::GyroscopicMode>& a,
                                       const std::vector<eigen::GyroscopicMode>& b) const override {
    return std::vector<std::vector<double>>(a.size(), std::vector<double>(b.size(), 1.0));
  }
  std::vector<analysis::Whirl> whirl(const synthesis::StructureModes& modes,
                                     const analysis::WhirlClassification&) const override {
    return std::vector<analysis::Whirl>(modes.result.modes.size(), analysis::Whirl::Neutral);
  }
  std::string whirlOf() const override { return ""; }
  std::vector<std::string> dominant(const synthesis::StructureModes& modes) const override {
    return std::vector<std::string>(modes.result.modes.size(), "rotor");
  }
};

TEST(CampbellStudy, ACrossingOnASweepSpeedFromBelowIsFound) {
  // Speeds 0, 2/3, 4/3 and 2 (exactly): g = omega - Omega = (Omega - 1)
  // (Omega - 2) is 2, 4/9, -2/9 and exactly 0 at the last. Both crossings,
  // with and without bisection; before, the one reached from below exactly
  // at a sweep speed was dropped (g_hi = 0 counted as no sign change).
  for (const bool refine : {true, false}) {
    auto params = sweep(4, 1.0, {1.0}, refine);
    params.set("Crossing Tolerance", 1e-9);
    const auto r = analysis::CampbellStudy(params).run(ParabolaProblem());
    ASSERT_EQ(r.crossings.size(), 2u) << (refine ? "bisected" : "interpolated");
    // Bisected: within the tolerance. Interpolated, the first: g is a
    // parabola, |g''| = 2, |g'| >= 1/3 on (2/3, 4/3): error <= h^2 / (4 / 3).
    EXPECT_NEAR(r.crossings[0].speed, 1.0, refine ? 2e-9 : (4.0 / 9.0) * 0.75);
    EXPECT_NEAR(r.crossings[1].speed, 2.0, refine ? 2e-9 : 4.0 * DBL_EPSILON);
  }
}

/// ParabolaProblem whose mode whirls forward, seen from a stationary frame
/// or from the rotor's own.
class WhirlingParabola : public ParabolaProblem {
public:
  explicit WhirlingParabola(bool rotorFrame) : rotorFrame_(rotorFrame) {}
  std::vector<analysis::Whirl> whirl(const synthesis::StructureModes& modes,
                                     const analysis::WhirlClassification&) const override {
    return std::vector<analysis::Whirl>(modes.result.modes.size(), analysis::Whirl::Forward);
  }
  std::string whirlOf() const override { return "rotor"; }
  bool whirlInRotorFrame(int) const override { return rotorFrame_; }

private:
  bool rotorFrame_;
};

TEST(CampbellStudy, UnbalanceExcitesNoCrossingSeenFromTheRotorsOwnFrame) {
  // A 1X forward crossing: unbalance excites it when forward is seen from a
  // stationary frame. Seen from the rotor's own frame (an A with Frame:
  // Rotating) the rotor's unbalance is a static load; the note said
  // "unbalance excites it" there too (found by a review).
  for (const bool rotorFrame : {false, true}) {
    const auto r = analysis::CampbellStudy(sweep(4, 1.0, {1.0})).run(WhirlingParabola(rotorFrame));
    ASSERT_EQ(r.crossings.size(), 2u);
    EXPECT_EQ(r.whirlInRotorFrame, rotorFrame);
    std::ostringstream text, csv;
    r.printCrossings(text);
    r.writeCrossingsCsv(csv);
    EXPECT_EQ(text.str().find("unbalance excites it") != std::string::npos, !rotorFrame) << text.str();
    EXPECT_EQ(text.str().find("forward in a spinning frame") != std::string::npos, rotorFrame) << text.str();
    // A 1X forward whirl in the rotor's frame is 2X in the stationary one:
    // a stationary force at 2X excites it, not at 1X (found by a review).
    EXPECT_EQ(text.str().find("a stationary force at 2X excites it") != std::string::npos, rotorFrame) << text.str();
    EXPECT_EQ(csv.str().find(",forward,yes,") != std::string::npos || csv.str().find(",FW,yes,") != std::string::npos,
              !rotorFrame)
        << csv.str();
  }
}

TEST(CampbellStudy, CrossingsOfIdenticalPartsAreListedOnce) {
  // Two identical, uncoupled copies of the 2-DOF system: every frequency is
  // double, and each engine-order crossing is met by two tracks at the same
  // speed: one entry naming both, at the closed-form speed.
  const auto one = twoDof(4.0, 1.0, 1.0, 0.0);
  analysis::SpeedDependentSystem two;
  two.M.shape(4, 4), two.G1.shape(4, 4), two.K0.shape(4, 4), two.K2.shape(4, 4);
  for (int b = 0; b < 2; ++b)
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        two.M(2 * b + i, 2 * b + j) = one.M(i, j);
        two.K0(2 * b + i, 2 * b + j) = one.K0(i, j);
        two.K2(2 * b + i, 2 * b + j) = one.K2(i, j);
      }
  const auto r = analysis::CampbellStudy(sweep(31, 1.0, {1.0, 2.0})).run(analysis::DenseSweepProblem(two, "spin", 3.0));
  ASSERT_EQ(r.tracks.size(), 4u);
  const double want[] = {2.0, 1.0 / std::sqrt(3.0), 1.0};
  ASSERT_EQ(r.crossings.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(r.crossings[i].tracks.size(), 2u) << "crossing " << i;
    EXPECT_EQ(r.crossings[i].dominant.size(), 2u) << "crossing " << i << ": one dominant part per track";
    EXPECT_NEAR(r.crossings[i].speed, want[i], 1e-6 * 3.0 + kRound * 4.0) << "crossing " << i;
  }
}

TEST(CampbellStudy, FrameRateTracksGiveNoCriticalSpeeds) {
  // Two point masses in a frame spinning at Omega about z (theory §7): one
  // free (k = 0: its translations, fixed in inertial space, are seen at
  // exactly Omega, a defective double root that rounding splits by
  // sqrt(eps)), one on isotropic springs (omega = w0 -/+ Omega). The 1X line
  // lies on the free mass's tracks at every speed (rounding puts them on
  // either side of it); the elastic slow track crosses 1X where w0 - Omega =
  // Omega and 2X where w0 - Omega = 2 Omega.
  const double m = 2.0, k = 800.0, w0 = std::sqrt(k / m);  // 20 rad/s
  analysis::SpeedDependentSystem s;
  s.M.shape(4, 4), s.G1.shape(4, 4), s.K0.shape(4, 4), s.K2.shape(4, 4);
  for (int b = 0; b < 2; ++b) {
    s.M(2 * b, 2 * b) = s.M(2 * b + 1, 2 * b + 1) = m;
    s.G1(2 * b, 2 * b + 1) = -2.0 * m, s.G1(2 * b + 1, 2 * b) = 2.0 * m;
    s.K2(2 * b, 2 * b) = s.K2(2 * b + 1, 2 * b + 1) = -m;
    s.whirlPairs.push_back({2 * b, 2 * b + 1});
  }
  s.K0(2, 2) = s.K0(3, 3) = k;
  const double tol = 1e-6;  // "Crossing Tolerance", the default
  const auto r = analysis::CampbellStudy(sweep(31, 1.0, {1.0, 2.0})).run(analysis::DenseSweepProblem(s, "frame", 15.0));
  int frame = 0;
  for (const auto& tr : r.tracks) {
    if (!tr.frameRate) continue;
    ++frame;
    EXPECT_EQ(tr.frameRateOf, 0);
    EXPECT_LT(std::abs(tr.omega.back() - 15.0), 1e-3 * 15.0);
  }
  EXPECT_EQ(frame, 2);  // the free mass's two translations, nothing elastic
  ASSERT_EQ(r.crossings.size(), 2u) << "a frame-rate track was listed as a critical speed";
  // K = diag(-m Omega^2 (twice), k - m Omega^2 (twice)): singular at rest
  // (the free mass) and negative from the first speed on, which is no
  // critical speed (a review found one "at 0.0000 rad/s"); the elastic
  // mass's zero frequency at sqrt(k / m) (here above the sweep or in it)
  // is the only one.
  for (const double w : r.zeroFrequencySpeeds)
    EXPECT_NEAR(w, std::sqrt(k / m), 2e-6 * std::sqrt(k / m)) << "a zero-frequency speed that is not sqrt(k/m)";
  EXPECT_EQ(r.zeroFrequencySpeeds.size(), std::sqrt(k / m) < 15.0 ? 1u : 0u);
  // Its tracks follow the swept rate, on the 1X line: rounding, not listed.
  EXPECT_TRUE(r.frameRateCrossings.empty());
  EXPECT_EQ(r.crossings[0].order, 1.0);
  EXPECT_NEAR(r.crossings[0].speed, w0 / 2, tol * w0 + kRound * 40.0);
  EXPECT_EQ(r.crossings[1].order, 2.0);
  EXPECT_NEAR(r.crossings[1].speed, w0 / 3, tol * w0 + kRound * 40.0);
  // In the frame the slow mode's orbit turns with the spin (at 1X it
  // coincides with the free mass's backward-turning translations: that
  // cluster is unresolved, so only the 2X whirl is asserted).
  EXPECT_EQ(r.crossings[1].whirl, analysis::Whirl::Forward);
}

// A free body's frame-rate modes are a split defective cluster: the solver
// returns them spread about the spin rate by rounding, ~1e-4 rad/s on the
// spacecraft whatever the rate, and says how far (GyroscopicMode::
// splitRadius). Judged by the relative "Frame Rate Tolerance" alone, those
// tracks passed or failed at the lowest rates by the BLAS kernel's rounding
// (AVX-512 kernels: 91 of the spacecraft's backward 1X crossings reported
// as critical speeds, and a 7 s sweep instead of 0.5 s). Here a track at
// Omega +/- 1e-3 rad/s (above 1e-3 Omega below Omega = 1) with a reported
// split radius of 2e-3 rad/s is a frame-rate track and none of its
// crossings is a critical speed; without the radius it is not.
TEST(CampbellStudy, AFrameRateTrackIsJudgedWithinItsSplitRadius) {
  class SplitFrameProblem : public TwoRateProblem {
  public:
    explicit SplitFrameProblem(double radius) : radius_(radius) {}
    std::vector<synthesis::SpeedParameter> parameters() const override { return {{"bus", 1.0}}; }
    synthesis::StructureModes solve(const std::vector<double>& speeds) const override {
      synthesis::StructureModes out;
      out.speeds = speeds;
      // The rounding's side alternates with the speed: the track crosses 1X.
      const double side = std::fmod(std::floor(speeds[0] * 10.0 + 0.5), 2.0) == 0.0 ? 1.0 : -1.0;  // steps of 0.1
      for (const double w : {speeds[0] + side * 1e-3, kStiff}) {
        eigen::GyroscopicMode m;
        m.omega = w, m.hz = w / (2 * M_PI), m.lambda = {0.0, w};
        m.q = {w == kStiff ? 0.0 : 1.0, w == kStiff ? 1.0 : 0.0};
        m.splitRadius = w == kStiff ? 0.0 : radius_;
        out.result.modes.push_back(m);
      }
      return out;
    }

  private:
    double radius_;
  };
  const auto withRadius = analysis::CampbellStudy(sweep(21, 2.0)).run(SplitFrameProblem(2e-3));
  ASSERT_EQ(withRadius.tracks.size(), 2u);
  EXPECT_TRUE(withRadius.tracks[0].frameRate);
  EXPECT_TRUE(withRadius.crossings.empty()) << withRadius.crossings.size() << " frame-rate crossings listed";
  const auto without = analysis::CampbellStudy(sweep(21, 2.0)).run(SplitFrameProblem(0.0));
  EXPECT_FALSE(without.tracks[0].frameRate);
  // Its sign changes are a jump of the rounding's side, which bisection
  // sees as such (omega - Omega does not close on either side): said as
  // jumps between branches, not listed as critical speeds.
  EXPECT_TRUE(without.crossings.empty());
  EXPECT_FALSE(without.branchJumps.empty());
  EXPECT_TRUE(withRadius.branchJumps.empty());
}

TEST(CampbellStudy, RefusesBadParameters) {
  const analysis::DenseSweepProblem problem(twoDof(4.0, 1.0, 1.0, 0.0), "spin", 3.0);
  Teuchos::ParameterList p;
  p.set("Speed Parameter", std::string("wheel"));
  fixtures::expectInputError([&] { analysis::CampbellStudy(p).run(problem); }, "spin");
  Teuchos::ParameterList q;
  q.set("Steps", 1);
  fixtures::expectInputError([&] { analysis::CampbellStudy{q}; }, "Steps");
  Teuchos::ParameterList u;
  u.set("Stepz", 3);
  fixtures::expectInputError([&] { analysis::CampbellStudy{u}; }, "Stepz");
  Teuchos::ParameterList o;
  o.set("Engine Orders", Teuchos::Array<double>(1, -1.0));
  fixtures::expectInputError([&] { analysis::CampbellStudy{o}; }, "Engine Orders");
  fixtures::expectInputError([&] { analysis::speedAxis("rad"); }, "hz, rpm or per-rev");
}

TEST(CampbellStudy, FrameRateCrossingsAreBisectedAndListedApart) {
  // The wheel's frame-rate track meets 1X of the bus between sweep speeds
  // 10 and 11 (bus 0..20 by 1): g = wheel (1 + a bus^2) - bus has g'' =
  // 2 a wheel = 2e-5 and |g'| ~ 1, so interpolating between sweep speeds is
  // off by up to h^2 g'' / 8 = 2.5e-6; bisected to "Crossing Tolerance" =
  // 1e-12 it is within 1e-12 of its bracket's top, and the crossing stays
  // out of the critical speeds.
  const double a = TwoRateProblem::kBend, w = TwoRateProblem::kWheel;
  const double exactSpeed = (1.0 - std::sqrt(1.0 - 4.0 * a * w * w)) / (2.0 * a * w);
  auto params = sweep(21, 20.0, {1.0});
  params.set("Speed Parameter", std::string("bus"));
  params.set("Crossing Tolerance", 1e-12);
  const auto r = analysis::CampbellStudy(params).run(TwoRateProblem());
  ASSERT_EQ(r.tracks.size(), 2u);
  EXPECT_TRUE(r.tracks[0].frameRate);
  EXPECT_EQ(r.tracks[0].frameRateOf, 1);
  EXPECT_TRUE(r.crossings.empty()) << "a frame-rate track was listed as a critical speed";
  ASSERT_EQ(r.frameRateCrossings.size(), 1u);
  EXPECT_EQ(r.frameRateOnLine, 0);
  const auto& c = r.frameRateCrossings[0];
  EXPECT_TRUE(c.refined);
  // The bracket's width (1e-12 of its top) and the rounding of g near 10.
  EXPECT_NEAR(c.speed, exactSpeed, 1e-12 * 11.0 + kRound * 40.0);
  ASSERT_EQ(c.dominant.size(), 1u);
  EXPECT_EQ(c.dominant[0], "wheel");
}

TEST(CampbellStudy, CrossingsNameTheDominantPartOfEachTrack) {
  // DenseSweepProblem is one part: its name at every crossing. Identical
  // parts merged into one crossing keep one name per track.
  const analysis::DenseSweepProblem one(twoDof(4.0, 1.0, 1.0, 0.0), "spin", 3.0);
  const auto r = analysis::CampbellStudy(sweep(31, 1.0, {1.0, 2.0})).run(one);
  ASSERT_EQ(r.crossings.size(), 3u);
  for (const auto& c : r.crossings) EXPECT_EQ(c.dominant, std::vector<std::string>{"spin"});
  std::ostringstream csv, console;
  r.writeCrossingsCsv(csv);
  r.printCrossings(console);
  EXPECT_NE(csv.str().find(",refined,dominant,forward_share\n"), std::string::npos) << csv.str();
  EXPECT_NE(csv.str().find(",track2,yes,spin,"), std::string::npos) << csv.str();
  EXPECT_NE(console.str().find("track 2 (spin)"), std::string::npos) << console.str();
}

/// Three modes of one frequency, omega = Omega^2 - 2 Omega + 2: tracks 1
/// and 3 whirl forward (identical parts), track 2 backward (another part at
/// the same frequency). Each meets 1X at 1 and at 2.
class TwoForwardOneBackward : public ParabolaProblem {
public:
  synthesis::StructureModes solve(const std::vector<double>& speeds) const override {
    auto out = ParabolaProblem::solve(speeds);
    const auto m = out.result.modes.front();
    out.result.modes.assign(3, m);
    for (std::size_t k = 0; k < 3; ++k) out.result.modes[k].q = {k == 0 ? 1.0 : 0.0, k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0};
    return out;
  }
  std::vector<std::vector<double>> mac(const std::vector<eigen::GyroscopicMode>& a,
                                       const std::vector<eigen::GyroscopicMode>& b) const override {
    return coordinateMac(a, b);
  }
  std::vector<analysis::Whirl> whirl(const synthesis::StructureModes& modes,
                                     const analysis::WhirlClassification&) const override {
    std::vector<analysis::Whirl> w;
    for (const auto& m : modes.result.modes) w.push_back(m.q[1] == 1.0 ? analysis::Whirl::Backward : analysis::Whirl::Forward);
    return w;
  }
  std::string whirlOf() const override { return "rotor"; }
};

TEST(CampbellStudy, IdenticalCrossingsAreMergedPastOneOfAnotherWhirl) {
  // At each speed the forward crossings of tracks 1 and 3 are one entry
  // and the backward one of track 2 another: two entries a speed, four in
  // all. Before, a crossing was compared with the last entry only: the
  // backward one between them kept track 3 apart (six entries; found by a
  // review).
  auto params = sweep(4, 1.0, {1.0});
  params.set("Crossing Tolerance", 1e-9);
  const auto r = analysis::CampbellStudy(params).run(TwoForwardOneBackward());
  ASSERT_EQ(r.tracks.size(), 3u);
  ASSERT_EQ(r.crossings.size(), 4u);
  for (const auto& c : r.crossings) {
    const bool forward = c.whirl == analysis::Whirl::Forward;
    const std::vector<int> want = forward ? std::vector<int>{0, 2} : std::vector<int>{1};
    EXPECT_EQ(c.tracks, want) << "at " << c.speed;
    EXPECT_EQ(c.dominant.size(), c.tracks.size());
    EXPECT_NEAR(c.speed, c.speed < 1.5 ? 1.0 : 2.0, 2e-9 * 2.0);
  }
}

TEST(CampbellStudy, AFrameRateTrackMissingAtOneSpeedStaysAFrameRateTrack) {
  // TwoRateProblem whose wheel mode is missing from the solve at bus = 5
  // (as a mode leaving the requested set for one speed does): its track is
  // lost there and found again, and is still the wheel's rate wherever it
  // was found. Its crossing of 1X near bus = 10 is no critical speed.
  class Gap : public TwoRateProblem {
  public:
    synthesis::StructureModes solve(const std::vector<double>& speeds) const override {
      auto out = TwoRateProblem::solve(speeds);
      if (speeds[0] == 5.0) out.result.modes.erase(out.result.modes.begin());
      return out;
    }
  };
  auto params = sweep(21, 20.0, {1.0});
  params.set("Speed Parameter", std::string("bus"));
  const auto r = analysis::CampbellStudy(params).run(Gap());
  ASSERT_FALSE(r.tracks.empty());
  EXPECT_TRUE(r.tracks[0].lost[5]);
  EXPECT_TRUE(r.tracks[0].frameRate);
  EXPECT_TRUE(r.crossings.empty()) << "a frame-rate track was listed as a critical speed";
  EXPECT_EQ(r.frameRateCrossings.size(), 1u);
}

namespace {
/// ParabolaProblem whose mode is damped, its growth rate undecided
/// (GyroscopicMode::undecided, Neutral) from `from` to `to` (below `onset`),
/// Flutter from `onset` up, and a conservative system's Neutral (a split
/// defective cluster, not undecided) everywhere else below `to`.
class UndecidedParabola : public ParabolaProblem {
public:
  UndecidedParabola(double from, double to, double onset = std::numeric_limits<double>::infinity())
      : from_(from), to_(to), onset_(onset) {}
  synthesis::StructureModes solve(const std::vector<double>& speeds) const override {
    auto out = ParabolaProblem::solve(speeds);
    auto& m = out.result.modes[0];
    const double W = speeds[0];
    m.undecided = W >= from_ && W <= to_ && W < onset_;
    m.stability = W >= onset_ ? eigen::Stability::Flutter
                  : W <= to_  ? eigen::Stability::Neutral
                              : eigen::Stability::Stable;
    return out;
  }

private:
  double from_, to_, onset_;
};
}  // namespace

// A damped mode whose growth rate its uncertainty leaves undecided (theory
// §13.3) is neither stable nor unstable: the Campbell lists the speeds
// where one is, apart from the unstable ranges, and a conservative
// system's Neutral (a split defective cluster, theory §4) is not among them.
// Before, the unstable ranges counted Divergence and Flutter only and the
// sweep said nothing of an undecided mode but "neutral" in its CSV.
TEST(CampbellStudy, SpeedsWhereAGrowthRateIsUndecidedAreListed) {
  // Speeds 0, 0.4, ..., 2.0: undecided at 0.8 and 1.2, Neutral (not
  // undecided) at 0 and 0.4.
  const auto r = analysis::CampbellStudy(sweep(6, 1.0)).run(UndecidedParabola(0.7, 1.3));
  ASSERT_EQ(r.undecidedRanges.size(), 1u);
  EXPECT_NEAR(r.undecidedRanges[0].first, 0.8, 4 * DBL_EPSILON);
  EXPECT_NEAR(r.undecidedRanges[0].second, 1.2, 4 * DBL_EPSILON);
  EXPECT_TRUE(r.unstableRanges.empty());
  std::ostringstream os;
  r.printCrossings(os);
  EXPECT_NE(os.str().find("UNDECIDED from 0.8"), std::string::npos) << os.str();
  const auto none = analysis::CampbellStudy(sweep(6, 1.0)).run(UndecidedParabola(5.0, 6.0));
  EXPECT_TRUE(none.undecidedRanges.empty());
}

// The bisection of an unstable range's edge (theory §12.1) goes to where
// instability is shown; a speed it meets whose growth is undecided (theory
// §13.3) is not shown unstable, but the onset may lie there, within the
// growth's uncertainty: those speeds are listed as UNDECIDED too. Before,
// only the grid's were, and here none is (grid 0, 0.4, ..., 2.0; undecided
// from 0.9 to 1.0, unstable from 1.0): the sweep said "unstable from 1"
// and nothing of 0.9 to 1.
TEST(CampbellStudy, UndecidedSpeedsTheEdgesBisectionMeetsAreListed) {
  const auto r = analysis::CampbellStudy(sweep(6, 1.0)).run(UndecidedParabola(0.9, 1.0, 1.0));
  ASSERT_EQ(r.unstableRanges.size(), 1u);
  EXPECT_TRUE(r.unstableEdgesRefined);
  // The edge to the bisection's width, 1e-6 of the bracket's speeds.
  EXPECT_NEAR(r.unstableRanges[0].first, 1.0, 2e-6);
  ASSERT_EQ(r.undecidedRanges.size(), 1u);
  // The bisection's mids: 1.0 (unstable), 0.9 (undecided), 0.95, ...: the
  // lowest undecided mid is 0.9 itself, the highest within the width of 1.
  EXPECT_NEAR(r.undecidedRanges[0].first, 0.9, 4 * DBL_EPSILON);
  EXPECT_LT(r.undecidedRanges[0].second, 1.0);
  EXPECT_GT(r.undecidedRanges[0].second, 1.0 - 2e-6);
  std::ostringstream os;
  r.printCrossings(os);
  EXPECT_NE(os.str().find("UNDECIDED from 0.9"), std::string::npos) << os.str();
  // The same at negative speeds (Speed Factor -1: the sweep runs from 0
  // down to -2): the bisection's range is written in the sweep's direction,
  // as the unstable range is, from -0.9 down to just above -1 (a review
  // found "from -78.5 to -78.49" beside "unstable from -78.51 to -161").
  class Mirrored : public UndecidedParabola {
  public:
    Mirrored() : UndecidedParabola(0.9, 1.0, 1.0) {}
    synthesis::StructureModes solve(const std::vector<double>& speeds) const override {
      std::vector<double> flipped(speeds);
      for (double& w : flipped) w = -w;
      auto out = UndecidedParabola::solve(flipped);
      out.speeds = speeds;
      return out;
    }
  };
  auto params = sweep(6, 1.0);
  params.set("Speed Factor", -1.0);
  const auto n = analysis::CampbellStudy(params).run(Mirrored());
  ASSERT_EQ(n.unstableRanges.size(), 1u);
  EXPECT_NEAR(n.unstableRanges[0].first, -1.0, 2e-6);
  ASSERT_EQ(n.undecidedRanges.size(), 1u);
  EXPECT_NEAR(n.undecidedRanges[0].first, -0.9, 4 * DBL_EPSILON);
  EXPECT_GT(n.undecidedRanges[0].second, -1.0);
  EXPECT_LT(n.undecidedRanges[0].second, -1.0 + 2e-6);
}
