// analysis::WhirlClassification: a degenerate cluster is classified as a
// whole, so the labels do not depend on which basis of the cluster the
// solver returned (which differs between rank counts), while a per-vector
// rule would.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>

#include "cms/analysis/CampbellStudy.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"

using namespace cms;
using analysis::Whirl;
using cplx = std::complex<double>;

namespace {

/// Two identical, uncoupled point masses on isotropic springs in a frame
/// spinning at Omega about z (theory §7): each frequency w0 -/+ Omega is
/// double (identical parts), and at rest all four are w0.
analysis::SpeedDependentSystem twoMasses() {
  const double m = 2.0, k = 800.0;
  analysis::SpeedDependentSystem s;
  s.M.shape(4, 4), s.G1.shape(4, 4), s.K0.shape(4, 4), s.K2.shape(4, 4);
  for (int b = 0; b < 2; ++b) {
    const int x = 2 * b, y = 2 * b + 1;
    s.M(x, x) = s.M(y, y) = m;
    s.G1(x, y) = -2.0 * m, s.G1(y, x) = 2.0 * m;
    s.K0(x, x) = s.K0(y, y) = k;
    s.K2(x, x) = s.K2(y, y) = -m;
    s.whirlPairs.push_back({x, y});
  }
  return s;
}

std::vector<Whirl> classify(const std::vector<eigen::GyroscopicMode>& modes, const analysis::SpeedDependentSystem& s,
                            double spin) {
  std::vector<analysis::Orbit> orbits;
  for (const auto& m : modes) orbits.push_back(analysis::orbitOfPairs(m, s.whirlPairs));
  return analysis::WhirlClassification().classify(modes, orbits, spin);
}

/// The cluster's modes replaced by q'_j = sum_i q_i U_ij for the unitary
/// U = [[c, -conj(s)], [s, conj(c)]] (|c|^2 + |s|^2 = 1) on members (a, b).
std::vector<eigen::GyroscopicMode> rotated(std::vector<eigen::GyroscopicMode> modes, int a, int b, cplx c, cplx s) {
  const auto qa = modes[a].q, qb = modes[b].q;
  for (std::size_t i = 0; i < qa.size(); ++i) {
    modes[a].q[i] = c * qa[i] + s * qb[i];
    modes[b].q[i] = -std::conj(s) * qa[i] + std::conj(c) * qb[i];
  }
  return modes;
}

}  // namespace

TEST(WhirlClassification, DegenerateClusterInvariantUnderARotationOfItsBasis) {
  const auto sys = twoMasses();
  const double Omega = 3.0;
  const auto r = eigen::DenseGyroscopicSolver().solve(sys.at(Omega));
  ASSERT_EQ(r.modes.size(), 4u);
  const analysis::WhirlClassification rule;
  const auto clusters = rule.clusters(r.modes);
  ASSERT_EQ(clusters.size(), 2u);  // {w0 - Omega} x 2, {w0 + Omega} x 2
  const auto base = classify(r.modes, sys, 1.0);
  // In the spinning frame the slow pair turns with the spin, the fast against.
  for (int i : clusters[0]) EXPECT_EQ(base[i], Whirl::Forward);
  for (int i : clusters[1]) EXPECT_EQ(base[i], Whirl::Backward);
  for (const auto& [c, s] : {std::pair<cplx, cplx>{std::sqrt(0.5), cplx(0, std::sqrt(0.5))},
                             {cplx(0.6, 0.0), cplx(0.0, 0.8)}, {cplx(0.36, 0.48), cplx(0.8, 0.0)}}) {
    auto q = rotated(r.modes, clusters[0][0], clusters[0][1], c, s);
    q = rotated(q, clusters[1][0], clusters[1][1], c, s);
    EXPECT_EQ(classify(q, sys, 1.0), base);
  }
}

TEST(WhirlClassification, ClusterWithBothSensesIsUnresolvedInEveryBasis) {
  // At rest each mass's x and y motions have the same frequency: one cluster
  // of four holding forward and backward circular orbits alike. Its label
  // must not depend on the basis; a per-vector rule's does, as the second
  // half shows (so the basis change below is not a no-op).
  const auto sys = twoMasses();
  const auto r = eigen::DenseGyroscopicSolver().solve(sys.at(0.0));
  ASSERT_EQ(r.modes.size(), 4u);
  const analysis::WhirlClassification rule;
  ASSERT_EQ(rule.clusters(r.modes).size(), 1u);
  const auto base = classify(r.modes, sys, 1.0);  // as if spinning: the test is of the cluster rule
  for (auto w : base) EXPECT_EQ(w, Whirl::Unresolved);
  // A basis whose first two vectors are mass 1's x and y motions, then
  // rotated to circular orbits.
  std::vector<eigen::GyroscopicMode> planar(2, r.modes[0]);
  planar[0].q = {1.0, 0.0, 0.0, 0.0};
  planar[1].q = {0.0, 1.0, 0.0, 0.0};
  const auto circular = rotated(planar, 0, 1, std::sqrt(0.5), cplx(0, std::sqrt(0.5)));
  auto single = [&](const eigen::GyroscopicMode& m) { return classify({m}, sys, 1.0).front(); };
  EXPECT_EQ(single(planar[0]), Whirl::Neutral);
  EXPECT_NE(single(circular[0]), single(circular[1]));  // one forward, one backward
  EXPECT_NE(single(circular[0]), Whirl::Neutral);
  // As one cluster, planar or circular, the pair is unresolved.
  EXPECT_EQ(classify(planar, sys, 1.0), std::vector<Whirl>(2, Whirl::Unresolved));
  EXPECT_EQ(classify(circular, sys, 1.0), std::vector<Whirl>(2, Whirl::Unresolved));
}

TEST(WhirlClassification, SpinAgainstTheAxisSwapsTheSenseAndNoSpinHasNone) {
  const auto sys = twoMasses();
  const auto r = eigen::DenseGyroscopicSolver().solve(sys.at(3.0));
  const auto plus = classify(r.modes, sys, 1.0), minus = classify(r.modes, sys, -1.0), none = classify(r.modes, sys, 0.0);
  for (std::size_t i = 0; i < r.modes.size(); ++i) {
    EXPECT_EQ(minus[i], plus[i] == Whirl::Forward ? Whirl::Backward : Whirl::Forward);
    EXPECT_EQ(none[i], Whirl::Unresolved);
  }
}

// The forward part of an orbit, (1 + c) / 2 with c its circularity with the
// spin, which tells a backward whirl unbalance excites (an ellipse from
// anisotropy) from one it does not (a circle): for a1 = 1, a2 = i r (a
// backward ellipse of axis ratio r about +n), c = -2 r / (1 + r^2), so the
// share is (1 - r)^2 / (2 (1 + r^2)): 0 for the circle, 0.353 at r = 0.15,
// 1/2 for a line (neutral: 0). Mirrored for a negative spin. A share is
// at most 1, the pencils' eigenvalues of 2 x 2 Hermitian forms of norm
// about 1 round to a few eps of it: 4096 eps (9e-13) is their bound with
// room for any BLAS kernel.
TEST(WhirlClassification, TheForwardShareOfAnEllipticalBackwardOrbit) {
  const analysis::WhirlClassification rule;
  const double tol = 4096.0 * std::numeric_limits<double>::epsilon();
  for (double r : {1.0, 0.15, 0.5}) {
    eigen::GyroscopicMode m;
    m.omega = 10.0, m.hz = 10.0 / (2 * M_PI), m.lambda = cplx(0.0, 10.0);
    analysis::Orbit o;
    o.a1 = {cplx(1.0, 0.0)}, o.a2 = {cplx(0.0, r)}, o.a3 = {cplx(0.0, 0.0)};
    std::vector<double> share;
    const auto w = rule.classify({m}, {o}, 1.0, nullptr, &share);
    ASSERT_EQ(share.size(), 1u);
    EXPECT_EQ(w[0], Whirl::Backward) << r;
    EXPECT_NEAR(share[0], (1 - r) * (1 - r) / (2 * (1 + r * r)), tol) << r;
    // Spun the other way the same orbit turns with the spin: forward, its
    // share the complement.
    const auto back = rule.classify({m}, {o}, -1.0, nullptr, &share);
    EXPECT_EQ(back[0], Whirl::Forward) << r;
    EXPECT_NEAR(share[0], 1.0 - (1 - r) * (1 - r) / (2 * (1 + r * r)), tol) << r;
  }
}
