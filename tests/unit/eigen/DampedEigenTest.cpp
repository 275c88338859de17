// The damped problem (lambda^2 M + lambda (G + D) + K + N) q = 0 (theory §13)
// against closed forms: a single DOF (under- and overdamped), two DOFs with
// proportional damping, a gyroscopic rotor on damped isotropic bearings
// (forward and backward whirl), and the Jeffcott rotor with internal
// (rotating) damping, unstable above Omega_th = w_n (1 + c_e / c_i).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cfloat>
#include <complex>
#include <limits>
#include <random>
#include <vector>

#include "cms/core/Error.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/EnergyBound.hpp"

using namespace cms;
using namespace cms::eigen;
using cplx = std::complex<double>;

namespace {

const double eps = std::numeric_limits<double>::epsilon();

DenseMatrix diag(std::vector<double> d) {
  DenseMatrix A(static_cast<int>(d.size()), static_cast<int>(d.size()));
  for (std::size_t i = 0; i < d.size(); ++i) A(i, i) = d[i];
  return A;
}

/// [[0, a], [-a, 0]]: the skew coupling of two transverse DOFs.
DenseMatrix skew2(double a) {
  DenseMatrix A(2, 2);
  A(0, 1) = a;
  A(1, 0) = -a;
  return A;
}

/// Roots of a lambda^2 + b lambda + c = 0 (complex coefficients).
std::vector<cplx> quadraticRoots(cplx a, cplx b, cplx c) {
  const cplx d = std::sqrt(b * b - 4.0 * a * c);
  return {(-b + d) / (2.0 * a), (-b - d) / (2.0 * a)};
}

/// The underdamped pair of a mode of frequency w and damping ratio z.
cplx dampedRoot(double w, double z) { return cplx(-z * w, w * std::sqrt(1.0 - z * z)); }

/// A backward-stable solve of the 2n pencil (dggev) moves a simple,
/// well-separated eigenvalue by about its condition times N eps times the
/// pencil's scale (|lambda| after the time scaling); for these small systems
/// the condition is O(1), and 10 N eps |lambda| is the bound asserted.
double tolOf(cplx lambda, int n) { return 10.0 * 2 * n * eps * std::max(std::abs(lambda), 1.0); }

/// Each expected root (Im >= 0) is found among the returned eigenvalues.
void expectRoots(const GyroscopicResult& r, const std::vector<cplx>& expected, int n) {
  ASSERT_EQ(r.modes.size(), expected.size());
  for (cplx e : expected) {
    double best = std::numeric_limits<double>::max();
    for (const auto& m : r.modes) best = std::min(best, std::abs(m.lambda - e));
    EXPECT_LE(best, tolOf(e, n)) << "expected " << e;
  }
}

GyroscopicResult solveAll(const GyroscopicSystem& s) { return DenseGyroscopicSolver().solve(s); }

}  // namespace

TEST(DampedEigen, SingleDofMatchesClosedForm) {
  const double m = 2.0, k = 50.0, w = std::sqrt(k / m), zeta = 0.05;
  GyroscopicSystem s{diag({m}), diag({0.0}), diag({k}), diag({2.0 * zeta * std::sqrt(k * m)})};
  const auto r = solveAll(s);
  EXPECT_NE(r.solver.find("dggev"), std::string::npos) << r.solver;
  EXPECT_NE(r.reason.find("damped"), std::string::npos) << r.reason;
  expectRoots(r, {dampedRoot(w, zeta)}, 1);
  const auto& mode = r.modes.at(0);
  // zeta and delta are derived from lambda: their error is lambda's relative one.
  EXPECT_NEAR(mode.dampingRatio, zeta, tolOf(w, 1) / w);
  EXPECT_NEAR(mode.logDecrement, 2.0 * M_PI * zeta / std::sqrt(1.0 - zeta * zeta), 2.0 * M_PI * tolOf(w, 1) / w);
  EXPECT_EQ(mode.stability, Stability::Stable);
  EXPECT_NEAR(r.leastDampingRatio(), zeta, tolOf(w, 1) / w);
  EXPECT_LE(mode.residual, 10.0 * eps);
}

TEST(DampedEigen, OverdampedDofGivesTwoDecayingRealModes) {
  const double m = 1.0, k = 4.0, w = 2.0, zeta = 2.0;
  GyroscopicSystem s{diag({m}), diag({0.0}), diag({k}), diag({2.0 * zeta * w * m})};
  const auto r = solveAll(s);
  const double root = std::sqrt(zeta * zeta - 1.0);
  expectRoots(r, {cplx(-w * (zeta - root), 0.0), cplx(-w * (zeta + root), 0.0)}, 1);
  for (const auto& mode : r.modes) {
    EXPECT_EQ(mode.lambda.imag(), 0.0);
    EXPECT_NEAR(mode.dampingRatio, 1.0, 10 * eps);
    EXPECT_TRUE(std::isinf(mode.logDecrement));
    EXPECT_EQ(mode.stability, Stability::Stable);
  }
}

TEST(DampedEigen, TwoDofProportionalDampingMatchesModalClosedForm) {
  // M = diag(m1, m2), K a grounded two-spring chain, D = alpha M + beta K:
  // the undamped modes diagonalise D, so each mode is a damped single DOF
  // with zeta_j = alpha / (2 w_j) + beta w_j / 2.
  const double m1 = 1.0, m2 = 2.0, k1 = 300.0, k2 = 100.0, alpha = 0.4, beta = 2e-3;
  DenseMatrix M = diag({m1, m2}), K(2, 2);
  K(0, 0) = k1 + k2, K(0, 1) = K(1, 0) = -k2, K(1, 1) = k2;
  DenseMatrix D(2, 2);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) D(i, j) = alpha * M(i, j) + beta * K(i, j);
  // det(K - w^2 M) = m1 m2 w^4 - (m1 k2 + m2 (k1 + k2)) w^2 + k1 k2 = 0.
  const double a = m1 * m2, b = m1 * k2 + m2 * (k1 + k2), c = k1 * k2;
  const double disc = std::sqrt(b * b - 4 * a * c);
  const double w1 = std::sqrt((b - disc) / (2 * a)), w2 = std::sqrt((b + disc) / (2 * a));
  const double z1 = alpha / (2 * w1) + beta * w1 / 2, z2 = alpha / (2 * w2) + beta * w2 / 2;
  const auto r = solveAll({M, DenseMatrix(2, 2), K, D});
  expectRoots(r, {dampedRoot(w1, z1), dampedRoot(w2, z2)}, 2);
  EXPECT_NEAR(r.modes.at(0).dampingRatio, z1, tolOf(w2, 2) / w1);
  EXPECT_NEAR(r.modes.at(1).dampingRatio, z2, tolOf(w2, 2) / w2);
  EXPECT_NEAR(r.leastDampingRatio(), std::min(z1, z2), tolOf(w2, 2) / w1);
}

TEST(DampedEigen, GyroscopicRotorOnDampedIsotropicBearings) {
  // Tilt of a rigid disc (transverse inertia Jt, polar Jp, spin Omega) on
  // isotropic bearings (stiffness k, damping c): in the complex tilt
  // theta = a + i b, Jt lambda^2 -/+ i Omega Jp lambda + c lambda + k = 0,
  // forward and backward whirl with their own decay rates.
  const double Jt = 0.5, Jp = 0.8, k = 2.0e3, c = 3.0, Omega = 40.0;
  GyroscopicSystem s{diag({Jt, Jt}), skew2(Omega * Jp), diag({k, k}), diag({c, c})};
  const auto r = solveAll(s);
  std::vector<cplx> expected;
  for (double sign : {1.0, -1.0})
    for (cplx root : quadraticRoots(Jt, cplx(c, sign * Omega * Jp), k))
      if (root.imag() > 0) expected.push_back(root);
  ASSERT_EQ(expected.size(), 2u);
  expectRoots(r, expected, 2);
  // The whirls decay at different rates (Re lambda), but with the same
  // damping ratio: the roots lambda_f and conj(lambda_b) of one quadratic
  // have the real product k / Jt, so their arguments are opposite and
  // zeta = -cos(arg lambda) is shared.
  const double w = std::abs(r.modes[1].lambda);
  EXPECT_GT(std::abs(r.modes[0].lambda.real() - r.modes[1].lambda.real()), 1e-3 * c / Jt);
  EXPECT_NEAR(r.modes[0].dampingRatio, r.modes[1].dampingRatio, 2 * tolOf(w, 2) / std::abs(r.modes[0].lambda));
  EXPECT_GT(r.leastDampingRatio(), 0.0);
}

TEST(DampedEigen, ExternalDampingOfALavalRotorGivesEqualWhirlDecay) {
  // Stationary (external) damping only: m z'' + c_e z' + k z = 0 in both
  // whirl directions, lambda = -zeta w +/- i w sqrt(1 - zeta^2), double.
  const double m = 3.0, k = 1.2e4, ce = 12.0, w = std::sqrt(k / m), zeta = ce / (2 * std::sqrt(k * m));
  const auto r = solveAll({diag({m, m}), DenseMatrix(2, 2), diag({k, k}), diag({ce, ce})});
  expectRoots(r, {dampedRoot(w, zeta), dampedRoot(w, zeta)}, 2);
  for (const auto& mode : r.modes) EXPECT_NEAR(mode.dampingRatio, zeta, tolOf(w, 2) / w);
}

namespace {
/// The Jeffcott (Laval) rotor with external damping c_e and internal
/// (rotating) damping c_i, in stationary coordinates: the internal damping
/// acts on the velocity relative to the spinning shaft, which adds the
/// circulatory force Omega c_i J q (N = Omega c_i [[0, 1], [-1, 0]]);
/// in z = x + i y: m z'' + (c_e + c_i) z' + k z - i Omega c_i z = 0.
GyroscopicSystem jeffcott(double m, double k, double ce, double ci, double Omega) {
  GyroscopicSystem s{diag({m, m}), DenseMatrix(2, 2), diag({k, k}), diag({ce + ci, ce + ci})};
  s.N = skew2(Omega * ci);
  return s;
}
}  // namespace

TEST(DampedEigen, JeffcottRotorWithInternalDampingWhirlsAsClosedForm) {
  const double m = 2.0, k = 8.0e3, ce = 4.0, ci = 6.0, Omega = 90.0;
  const auto r = solveAll(jeffcott(m, k, ce, ci, Omega));
  std::vector<cplx> expected;
  for (double sign : {1.0, -1.0})
    for (cplx root : quadraticRoots(m, ce + ci, cplx(k, -sign * Omega * ci)))
      if (root.imag() > 0) expected.push_back(root);
  expectRoots(r, expected, 2);
}

TEST(DampedEigen, JeffcottRotorLosesStabilityAtTheInternalDampingThreshold) {
  // At lambda = i w: w = w_n and (c_e + c_i) w_n = Omega c_i, hence
  // Omega_th = w_n (1 + c_e / c_i) (theory §13.4).
  const double m = 2.0, k = 8.0e3, ce = 4.0, ci = 6.0, wn = std::sqrt(k / m);
  const double threshold = wn * (1.0 + ce / ci);
  const auto below = solveAll(jeffcott(m, k, ce, ci, 0.98 * threshold));
  const auto at = solveAll(jeffcott(m, k, ce, ci, threshold));
  const auto above = solveAll(jeffcott(m, k, ce, ci, 1.02 * threshold));
  EXPECT_TRUE(below.isStable());
  EXPECT_GT(below.leastDampingRatio(), 0.0);
  EXPECT_FALSE(above.isStable());
  EXPECT_LT(above.leastDampingRatio(), 0.0);
  const auto unstable = std::find_if(above.modes.begin(), above.modes.end(),
                                     [](const GyroscopicMode& mo) { return mo.stability == Stability::Flutter; });
  ASSERT_NE(unstable, above.modes.end());
  // At the threshold the forward whirl sits on the axis at w_n.
  double onAxis = std::numeric_limits<double>::max();
  for (const auto& mo : at.modes) onAxis = std::min(onAxis, std::abs(mo.lambda - cplx(0.0, wn)));
  EXPECT_LE(onAxis, tolOf(wn, 2));
  EXPECT_NEAR(at.leastDampingRatio(), 0.0, tolOf(wn, 2) / wn);
}

TEST(DampedEigen, ZeroDampingKeepsTheSymmetricPath) {
  // A D that is present but zero changes nothing: Meirovitch, zeta = 0.
  GyroscopicSystem s{diag({1.0, 2.0}), skew2(3.0), diag({10.0, 20.0}), DenseMatrix(2, 2)};
  const auto r = solveAll(s);
  EXPECT_NE(r.solver.find("Meirovitch"), std::string::npos) << r.solver;
  for (const auto& mode : r.modes) {
    EXPECT_EQ(mode.dampingRatio, 0.0);
    EXPECT_EQ(mode.logDecrement, 0.0);
  }
}

TEST(DampedEigen, RefusesMeirovitchWithDampingAndAnUnsymmetricD) {
  GyroscopicSystem s{diag({1.0, 2.0}), DenseMatrix(2, 2), diag({10.0, 20.0}), diag({0.1, 0.1})};
  Teuchos::ParameterList p;
  p.set("Method", "Meirovitch");
  EXPECT_THROW(DenseGyroscopicSolver(p).solve(s), InputError);
  s.D(0, 1) = 0.05;  // D - D^T != 0
  try {
    DenseGyroscopicSolver().solve(s);
    FAIL() << "an unsymmetric D was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("D is not symmetric"), std::string::npos) << e.what();
  }
}

TEST(DampedEigen, AFreeBodysRigidZeroIsListedOnceWhateverTheDamping) {
  // Two masses on a spring, free: one rigid translation, one vibration of
  // w^2 = k (1/m1 + 1/m2). With D = beta K the rigid motion is undamped:
  // lambda = 0 is a double (defective) root of the pencil, one mode, and
  // the vibration's zeta = beta w / 2. With D = alpha M + beta K the rigid
  // motion decays: lambda = 0 and lambda = -alpha, two modes; the
  // vibration's zeta = alpha / (2 w) + beta w / 2. Each rigid
  // zero was listed twice with D = beta K, pushing the vibration out of two
  // asked modes (found by a review).
  const double m1 = 1.0, m2 = 3.0, k = 40.0, alpha = 0.2, beta = 1e-3;
  const double w = std::sqrt(k * (1.0 / m1 + 1.0 / m2));
  DenseMatrix M = diag({m1, m2}), K(2, 2);
  K(0, 0) = K(1, 1) = k, K(0, 1) = K(1, 0) = -k;
  for (double a : {0.0, alpha}) {
    SCOPED_TRACE("alpha = " + std::to_string(a));
    DenseMatrix D(2, 2);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) D(i, j) = a * M(i, j) + beta * K(i, j);
    Teuchos::ParameterList p;
    // Two asked of the undamped rigid motion; every mode (-1: a damped
    // system can have more than n) of the damped one, three.
    p.set("Number of Modes", a == 0.0 ? 2 : -1);
    const auto r = DenseGyroscopicSolver(p).solve({M, DenseMatrix(2, 2), K, D});
    ASSERT_EQ(r.modes.size(), a == 0.0 ? 2u : 3u);
    int zeros = 0;
    for (const auto& mode : r.modes) zeros += mode.stability == Stability::RigidBody;
    EXPECT_EQ(zeros, 1) << "the rigid translation once";
    // The vibration is the last mode either way, zeta = alpha / (2 w) +
    // beta w / 2; the decaying rigid motion (-alpha, real) between.
    const double zeta = a / (2.0 * w) + beta * w / 2.0;
    EXPECT_LE(std::abs(r.modes.back().lambda - dampedRoot(w, zeta)), tolOf(w, 2));
    if (a > 0.0) EXPECT_LE(std::abs(r.modes[1].lambda - cplx(-a, 0.0)), tolOf(w, 2));
  }
}

TEST(DampedEigen, SeveralRigidMotionsAreListedOnceEach) {
  // r free two-mass systems side by side (r rigid translations, r
  // vibrations w_k^2 = k_k (1/m1 + 1/m2)), mixed by a congruence
  // M' = T^T M T, K' = T^T K T, and D' = beta K': each rigid motion's zero
  // is double and defective, and dggev returns the cluster as ill-
  // conditioned mixes. A threshold on each vector's remainder listed 8, 5,
  // 7, 5 of 6 rigid motions and 2 of 3 over six seeds (found by a review);
  // the count is now K's. Every vibration at w_k with zeta = beta w_k / 2.
  for (unsigned seed = 1; seed <= 6; ++seed)
    for (int r : {3, 6}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + ", rigid motions: " + std::to_string(r));
      std::mt19937 g(seed);
      std::uniform_real_distribution<double> u(0.5, 2.0);
      const int n = 2 * r;
      const double beta = r == 3 ? 1e-3 : 1e-2;
      DenseMatrix M(n, n), K(n, n);
      std::vector<double> w;
      for (int k = 0; k < r; ++k) {
        const double m1 = u(g), m2 = u(g), kk = 40.0 * u(g);
        M(2 * k, 2 * k) = m1, M(2 * k + 1, 2 * k + 1) = m2;
        K(2 * k, 2 * k) = K(2 * k + 1, 2 * k + 1) = kk;
        K(2 * k, 2 * k + 1) = K(2 * k + 1, 2 * k) = -kk;
        w.push_back(std::sqrt(kk * (1.0 / m1 + 1.0 / m2)));
      }
      DenseMatrix T(n, n);  // 2 I plus entries in [-0.75, 0.75]: invertible, condition ~10
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) T(i, j) = u(g) - 1.25 + (i == j ? 2.0 : 0.0);
      const auto congruent = [&](const DenseMatrix& A) {
        DenseMatrix AT, out;
        gemm(false, false, 1.0, A, T, 0.0, AT);
        gemm(true, false, 1.0, T, AT, 0.0, out);
        return out;
      };
      const DenseMatrix Mp = congruent(M), Kp = congruent(K);
      DenseMatrix D(n, n);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) D(i, j) = beta * Kp(i, j);
      const auto result = solveAll({Mp, DenseMatrix(n, n), Kp, D});
      int zeros = 0;
      std::vector<cplx> vibrations;
      for (const auto& mode : result.modes) {
        if (mode.stability == Stability::RigidBody) ++zeros;
        else vibrations.push_back(mode.lambda);
      }
      EXPECT_EQ(zeros, r);
      ASSERT_EQ(vibrations.size(), static_cast<std::size_t>(r));
      // The congruence's condition (~10, squared in M' and K') times the
      // pencil's rounding: 1e3 tolOf.
      for (double wk : w) {
        const cplx e = dampedRoot(wk, beta * wk / 2.0);
        double best = std::numeric_limits<double>::max();
        for (cplx v : vibrations) best = std::min(best, std::abs(v - e));
        EXPECT_LE(best, 1e3 * tolOf(e, n)) << "expected " << e;
      }
    }
}

// The coordinates the stiffness at rest does not reach are solved apart
// through the Schur complement of the others (theory §4.3), which needs K on
// the others to be invertible. Where it is singular (a second mechanism the
// caller did not list) the block is not solved apart, the reason says why,
// and the whole solve stands: here M = I, D = 0.01 I, K = 0 on the listed
// coordinate and [[1, 1], [1, 1]] on the others, whose roots are 0 and -0.01
// (twice: the listed coordinate and the others' mechanism) and the damped
// pair of w^2 = 2. (An error path no test reached.)
TEST(DampedEigen, AnUnrestrainedBlockWhoseOthersAreSingularIsSolvedWhole) {
  GyroscopicSystem sys;
  sys.M = diag({1.0, 1.0, 1.0});
  sys.G = DenseMatrix(3, 3);
  sys.D = diag({0.01, 0.01, 0.01});
  sys.K = DenseMatrix(3, 3);
  for (int i = 1; i < 3; ++i)
    for (int j = 1; j < 3; ++j) sys.K(i, j) = 1.0;
  sys.unrestrained = {0};
  Teuchos::ParameterList p;
  p.set("Number of Modes", -1);  // every mode of the damped system
  const auto r = DenseGyroscopicSolver(p).solve(sys);
  ASSERT_EQ(r.status, SolveStatus::Converged) << r.reason;
  EXPECT_NE(r.reason.find("K on the other 2 is singular to rounding"), std::string::npos) << r.reason;
  const cplx pair = quadraticRoots(1.0, 0.01, 2.0)[0];
  expectRoots(r, {0.0, 0.0, -0.01, -0.01, cplx(pair.real(), std::abs(pair.imag()))}, 3);
}

// The energy bound on a damped system's growth rates (theory §13.3, "The
// energy bound"): with N = 0 and K > 0, E = (q'^T M q' + q^T K q) / 2 obeys
// dE/dt = -q'^T D q', so where D + d M >= 0 no eigenvalue has Re lambda > d.
// Against closed forms: a negatively damped DOF, whose growth c / (2 m) the
// bound must cover and whose bound exists only for d > c / m; a gyroscopic
// rotor on damped bearings (shown: every mode decided stable); the Jeffcott
// rotor's circulatory N and a free body's singular K (not shown, said why).

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
  // The closed form, to 64 eps |lambda|: a 2-state dggev, backward stable,
  // on an eigenvalue of condition ~1 (|lambda|^2 = k / m, the roots apart by
  // 2 |Im lambda| ~ |lambda|). Measured: 0 with the Haswell and Nehalem
  // kernels.
  EXPECT_NEAR(r.modes[0].growthRate, c / (2 * m), 64 * DBL_EPSILON * std::abs(r.modes[0].lambda));
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

// M > 0 carries the argument: with M = -1 (which the solver refuses, but
// energyBound must not rely on that), D = c and K = k > 0 both pass, and
// lambda = (c + sqrt(c^2 + 4k)) / 2 > 0 grows (a review's counterexample).
TEST(EnergyBound, NeedsTheMassShownPositiveDefinite) {
  const GyroscopicSystem s{diag({-1.0}), DenseMatrix(1, 1), diag({4.0}), diag({2.0})};
  const EnergyBound b = energyBound(s, 1.0);
  EXPECT_FALSE(b.shown);
  EXPECT_NE(b.note.find("M > 0 not shown"), std::string::npos) << b.note;
  // No finite d >= 0: nothing is asked, nothing proven.
  const GyroscopicSystem passive{diag({1.0}), DenseMatrix(1, 1), diag({4.0}), diag({2.0})};
  for (double d : {-1.0, std::nan("")}) {
    const EnergyBound none = energyBound(passive, d);
    EXPECT_FALSE(none.shown) << d;
    EXPECT_NE(none.note.find("no bound asked for"), std::string::npos) << none.note;
  }
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
