// analysis::FloquetAnalysis and analysis::MultiBladeTransform on systems with
// closed-form answers (doc/theory.md §16):
//  - a constant system seen from a rotating frame, x = R(Omega t) z, z' = B z:
//    its monodromy is exactly exp(B T) (R(T) = I), so the Gauss-Legendre
//    integrator's error and order are measured, not assumed;
//  - the same system's frequencies by the principal-branch rule, in the
//    fixed frame (observation R^T: beta) and in the rotating one (beta +/- Omega,
//    whichever circular component of the mode is larger);
//  - the multi-blade transform: T T^-1 = I, psi-derivatives against
//    differences, the ground-resonance rotor's periodic matrices turned into
//    constant ones equal to the hand derivation of theory §16.4;
//  - the quartic discriminant against the product of its roots' differences.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <complex>

#include "ExpectError.hpp"
#include "cms/analysis/Floquet.hpp"
#include "cms/analysis/MultiBladeCoordinates.hpp"
#include "cms/models/GroundResonance.hpp"

using namespace cms;

namespace {

/// z' = B z with B = [[a, b], [c, d]] (complex eigenvalues alpha +/- i beta),
/// seen as x = R(Omega t) z: x' = (Omega J + R B R^T) x, J = [[0, -1], [1, 0]].
struct RotatedConstantSystem {
  double a = -0.1, b = 2.0, c = -1.5, d = 0.05, Omega = 1.0;
  double alpha() const { return 0.5 * (a + d); }
  double beta() const { return std::sqrt(-b * c - 0.25 * (a - d) * (a - d)); }
  double period() const { return 2.0 * M_PI / Omega; }
  static DenseMatrix rotation(double th) {
    DenseMatrix R(2, 2);
    R(0, 0) = R(1, 1) = std::cos(th);
    R(1, 0) = std::sin(th);
    R(0, 1) = -std::sin(th);
    return R;
  }
  analysis::PeriodicSystem system(bool fixedFrameObservation) const {
    analysis::PeriodicSystem s;
    s.period = period();
    s.dimension = 2;
    s.stateMatrix = [this](double t) {
      DenseMatrix B(2, 2), RB(2, 2), A(2, 2);
      B(0, 0) = a, B(0, 1) = b, B(1, 0) = c, B(1, 1) = d;
      const DenseMatrix R = rotation(Omega * t);
      gemm(false, false, 1.0, R, B, 0.0, RB);
      gemm(false, true, 1.0, RB, R, 0.0, A);
      A(0, 1) -= Omega;
      A(1, 0) += Omega;
      return A;
    };
    if (fixedFrameObservation) {
      s.observation = [this](double t) {
        DenseMatrix Rt = rotation(-Omega * t);  // z = R^T x
        return Rt;
      };
    }
    return s;
  }
  /// exp(B T) = e^(alpha T) (cos(beta T) I + sin(beta T) / beta (B - alpha I)).
  DenseMatrix exactMonodromy() const {
    const double T = period(), al = alpha(), be = beta(), g = std::exp(al * T);
    const double co = std::cos(be * T), si = std::sin(be * T) / be;
    DenseMatrix E(2, 2);
    E(0, 0) = g * (co + si * (a - al));
    E(0, 1) = g * si * b;
    E(1, 0) = g * si * c;
    E(1, 1) = g * (co + si * (d - al));
    return E;
  }
};

double relativeError(const DenseMatrix& X, const DenseMatrix& ref) {
  DenseMatrix D = X;
  D -= ref;
  return frobeniusNorm(D) / frobeniusNorm(ref);
}

}  // namespace

TEST(Floquet, GaussLegendreMonodromyConvergesAtOrderEight) {
  const RotatedConstantSystem rc;
  const DenseMatrix exact = rc.exactMonodromy();
  const auto sys = rc.system(false);
  // Errors at 8 .. 128 steps; the observed order log2(e_n / e_2n) must be 8
  // (to +/- 0.5: the next term of the error expansion) while e_2n is above
  // the rounding floor, 1e3 eps (a few hundred steps of n eps ||Phi|| each).
  std::vector<int> steps{8, 16, 32, 64, 128};
  std::vector<double> err;
  for (int n : steps) err.push_back(relativeError(analysis::FloquetAnalysis::monodromy(sys, n), exact));
  int pairs = 0;
  for (std::size_t i = 0; i + 1 < err.size(); ++i) {
    std::printf("steps %4d: error %.3e, next %.3e\n", steps[i], err[i], err[i + 1]);
    if (err[i + 1] < 1e3 * DBL_EPSILON) continue;
    const double order = std::log2(err[i] / err[i + 1]);
    EXPECT_NEAR(order, 8.0, 0.5) << "steps " << steps[i] << " -> " << steps[i + 1];
    ++pairs;
  }
  EXPECT_GE(pairs, 2) << "too few step pairs above the rounding floor to measure the order";
  // Liouville: det exp(B T) = exp((a + d) T), checked by the result.
  Teuchos::ParameterList p;
  p.set("Steps Per Period", 32);
  p.set("Maximum Steps Per Period", 32);
  p.set("Tolerance", 1e-15);
  const auto r = analysis::FloquetAnalysis(p).analyse(sys);
  EXPECT_FALSE(r.converged);  // 32 steps cannot reach 1e-15: a status, not an exception
  EXPECT_EQ(r.steps, 32);
  // The Richardson estimate is the error of the 32-step run to within a factor
  // 2 in the asymptotic regime (e_16 / e_32 ~ 2^8 above).
  const double actual = relativeError(r.monodromy, exact);
  EXPECT_GT(r.monodromyError, 0.5 * actual);
  EXPECT_LT(r.monodromyError, 2.0 * actual);
  EXPECT_LT(r.liouvilleDefect, 10.0 * actual + 1e3 * DBL_EPSILON);
}

// A tolerance below rounding (1e-20) cannot be met: the doubling stops when
// the estimate, already below sqrt(eps) (the order-8 regime, where a
// doubling divides it by ~256), no longer halves, and says so, rather than
// doubling to "Maximum Steps Per Period" for nothing (on a large model,
// minutes with no word: found by a review). Each integration is reported
// through the progress callback. The answer kept is the stalled run's, at
// the rounding floor (1e3 eps, as above).
TEST(Floquet, DoublingStopsWhereTheErrorStopsFallingAndReportsEachRun) {
  const RotatedConstantSystem rc;
  Teuchos::ParameterList p;
  p.set("Steps Per Period", 8);
  p.set("Maximum Steps Per Period", 1 << 16);
  p.set("Tolerance", 1e-20);
  analysis::FloquetAnalysis floquet(p);
  std::vector<std::string> lines;
  floquet.setProgress([&](const std::string& s) { lines.push_back(s); });
  const auto r = floquet.analyse(rc.system(false));
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(r.stalled);
  for (const auto& l : lines) std::printf("%s\n", l.c_str());
  EXPECT_LE(r.steps, 512) << "doubled on below the rounding floor";
  const double actual = relativeError(r.monodromy, rc.exactMonodromy());
  EXPECT_LT(actual, 1e3 * DBL_EPSILON);
  // At the floor the reported error is the two runs' raw difference, which
  // bounds the kept run's (the order-8 estimate, a 255th of it, did not).
  EXPECT_GE(r.monodromyError, actual);
  std::printf("kept run: error %.3g, reported %.3g\n", actual, r.monodromyError);
  // One line for each doubling after the first pair of runs, naming the steps.
  ASSERT_GE(lines.size(), 2u);
  EXPECT_NE(lines.front().find(std::to_string(p.get<int>("Steps Per Period")) + " steps"), std::string::npos)
      << lines.front();
  EXPECT_NE(lines.back().find("stopped falling"), std::string::npos) << lines.back();
  EXPECT_NE(lines.back().find("the " + std::to_string(r.steps) + "-step run is kept"), std::string::npos)
      << lines.back();
}

TEST(Floquet, ExponentsAndFixedFrameFrequenciesOfARotatedConstantSystem) {
  const RotatedConstantSystem rc;
  Teuchos::ParameterList p;
  p.set("Tolerance", 1e-13);
  const auto r = analysis::FloquetAnalysis(p).analyse(rc.system(true));
  ASSERT_TRUE(r.converged) << r.monodromyError;
  EXPECT_EQ(r.steps & (r.steps - 1), 0);  // 64 doubled: a power of two, the FFT
  ASSERT_EQ(r.multipliers.size(), 2u);
  // Growth rate alpha; the error estimate bounds the actual error.
  for (const auto& m : r.multipliers) {
    // The estimate, or the rounding of the exponent itself (64 eps |rho|) when it is smaller.
    EXPECT_NEAR(m.growthRate, rc.alpha(), std::max(m.growthRateError, 64 * DBL_EPSILON * std::abs(m.exponent)))
        << m.growthRateError;
    EXPECT_LT(m.residual, 1e2 * DBL_EPSILON);
    // beta = 1.73 lies outside the principal strip |Im rho| <= Omega / 2: the
    // harmonic rule must move it by k = +/-2 to the fixed-frame frequency.
    EXPECT_EQ(std::abs(m.harmonic), 2);
    EXPECT_NEAR(std::abs(m.frequency), rc.beta(), 1e-10 * rc.beta());
    EXPECT_GT(m.harmonicShare, 1.0 - 1e-10);  // z(t) e^(-rho t) is constant: all in one harmonic
  }
  EXPECT_EQ(r.stability, analysis::FloquetStability::Stable);  // alpha < 0
  EXPECT_NEAR(r.largestGrowthRate, rc.alpha(), 1e-12);
}

TEST(Floquet, RotatingFrameObservationPicksTheLargerCircularComponent) {
  // x = R(Omega t) w e^(lambda t) = (e^(i Omega t) P+ + e^(-i Omega t) P-) w e^(lambda t),
  // P+- the projections on the circular vectors (1, -/+ i) / sqrt 2: frequency
  // beta + Omega or beta - Omega, whichever of |P+ w|, |P- w| is larger.
  const RotatedConstantSystem rc;
  Teuchos::ParameterList p;
  p.set("Tolerance", 1e-13);
  p.set("Steps Per Period", 48);  // not a power of two: the direct DFT (the other test: the FFT)
  const auto r = analysis::FloquetAnalysis(p).analyse(rc.system(false));
  EXPECT_NE(r.steps & (r.steps - 1), 0);
  for (const auto& m : r.multipliers) {
    // eigenvector of B with eigenvalue alpha + i beta * sign: (b, lambda - a)
    const double s = m.frequency > 0 ? 1.0 : -1.0;
    const std::complex<double> lam(rc.alpha(), s * rc.beta());
    const std::complex<double> w0 = rc.b, w1 = lam - rc.a;
    const std::complex<double> I(0.0, 1.0);
    // R(t) = cos I + sin J, J (1, -i) = i (1, -i): e^(i Omega t) on (1, -i).
    const double plus = std::abs(w0 + I * w1), minus = std::abs(w0 - I * w1);  // components along (1, -i), (1, i)
    const double expected = s * rc.beta() + (plus > minus ? rc.Omega : -rc.Omega);
    EXPECT_NEAR(m.frequency, expected, 1e-10) << "plus " << plus << " minus " << minus;
  }
}

TEST(Floquet, OptionsAndInputAreChecked) {
  Teuchos::ParameterList bad;
  bad.set("Step Per Period", 10);
  fixtures::expectInputErrorWith([&] { analysis::FloquetAnalysis{bad}; }, {"FloquetAnalysis", "Step Per Period"});
  Teuchos::ParameterList odd;
  odd.set("Steps Per Period", 33);
  fixtures::expectInputErrorWith([&] { analysis::FloquetAnalysis{odd}; }, {"Steps Per Period", "even"});
  analysis::PeriodicSystem none;
  none.dimension = 2;
  none.period = -1.0;
  fixtures::expectInputErrorWith([&] { analysis::FloquetAnalysis().analyse(none); }, {"period"});
  // A singular mass at some t: a NumericalError naming the time.
  auto sys = analysis::PeriodicSystem::secondOrder(1.0, 1, [](double t) {
    analysis::SecondOrderMatrices m{DenseMatrix(1, 1), DenseMatrix(1, 1), DenseMatrix(1, 1)};
    m.M(0, 0) = t > 0.5 ? 0.0 : 1.0;
    m.K(0, 0) = 1.0;
    return m;
  });
  try {
    analysis::FloquetAnalysis().analyse(sys);
    ADD_FAILURE() << "no NumericalError for a singular M(t)";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("M(t = "), std::string::npos) << e.what();
  }
}

TEST(MultiBlade, TransformInverseAndDerivatives) {
  for (int N : {3, 4, 5, 6}) {
    const analysis::MultiBladeTransform mbt(N, 2);
    EXPECT_EQ(static_cast<int>(mbt.names().size()), N);
    EXPECT_EQ(mbt.names().back(), N % 2 == 0 ? "d" : std::to_string((N - 1) / 2) + "s");
    const double psi = 0.37, h = 1e-4;
    DenseMatrix P(mbt.size(), mbt.size());
    gemm(false, false, 1.0, mbt.matrix(psi), mbt.inverse(psi), 0.0, P);
    for (int i = 0; i < P.numRows(); ++i) P(i, i) -= 1.0;
    // entries of T are O(1): n eps of an n-term product
    EXPECT_LT(frobeniusNorm(P), 10.0 * mbt.size() * DBL_EPSILON) << "N = " << N;
    // Central differences of T^(r-1): truncation h^2 / 6 max|T^(r+2)| <= h^2 n^(r+2) / 6
    // per entry (n the highest harmonic), rounding eps n^(r-1) / h; Frobenius
    // over the size^2 entries: times size.
    const double nmax = std::max(1, (N - 1) / 2);
    for (int r = 1; r <= 2; ++r) {
      DenseMatrix fd = mbt.matrix(psi + h, r - 1);
      fd -= mbt.matrix(psi - h, r - 1);
      fd.scale(0.5 / h);
      fd -= mbt.matrix(psi, r);
      const double bound = mbt.size() * (h * h * std::pow(nmax, r + 2) / 6.0 + 10.0 * DBL_EPSILON * std::pow(nmax, r - 1) / h);
      EXPECT_LT(frobeniusNorm(fd), bound) << "N = " << N << ", derivative " << r;
    }
  }
  fixtures::expectInputErrorWith([] { analysis::MultiBladeTransform(2); }, {"2 blades", "Floquet"});
}

TEST(MultiBlade, GroundResonanceRotorBecomesConstantAndMatchesTheHandDerivation) {
  for (int N : {3, 4, 5}) {
    models::GroundResonanceRotor rotor;
    rotor.blades = N;
    rotor.lagStiffness = 0.02;
    rotor.lagDamping = 0.003;
    rotor.cx = rotor.cy = 0.05;
    rotor.Omega = 1.3;
    const analysis::MultiBladeTransform mbt(N);
    const auto hand = rotor.multiBlade();
    analysis::SecondOrderMatrices first;
    for (double t : {0.0, 0.41, 1.7, 3.3}) {
      const auto ib = rotor.individualBlade(t);
      const auto z = mbt.toMultiBlade({ib.M, ib.D, ib.K}, rotor.Omega * t, rotor.Omega, 2);
      if (t == 0.0) first = z;
      // Constant in time: to rounding of the products (entries O(||M||, Omega ||D||, Omega^2 ||M||)).
      const double scale = frobeniusNorm(z.M) + frobeniusNorm(z.D) + frobeniusNorm(z.K);
      const double tol = 100.0 * (N + 2) * DBL_EPSILON * scale;
      DenseMatrix dM = z.M, dD = z.D, dK = z.K;
      dM -= first.M, dD -= first.D, dK -= first.K;
      EXPECT_LT(frobeniusNorm(dM) + frobeniusNorm(dD) + frobeniusNorm(dK), tol) << "N = " << N << ", t = " << t;
      // The x, y, 1c, 1s rows and columns are the hand-derived 4-DOF system;
      // every other multi-blade coordinate is uncoupled from them.
      const int idx[4] = {0, 1, 3, 4};  // z = [x, y, b_0, b_1c, b_1s, ...]
      for (int i = 0; i < z.M.numRows(); ++i)
        for (int j = 0; j < z.M.numCols(); ++j) {
          int hi = -1, hj = -1;
          for (int a = 0; a < 4; ++a) {
            if (idx[a] == i) hi = a;
            if (idx[a] == j) hj = a;
          }
          const bool inBlock = hi >= 0 && hj >= 0;
          if (!inBlock && (hi >= 0 || hj >= 0)) {  // coupling of the 4 with the rest
            EXPECT_LT(std::abs(z.M(i, j)) + std::abs(z.D(i, j)) + std::abs(z.K(i, j)), tol) << i << "," << j;
          } else if (inBlock) {
            EXPECT_NEAR(z.M(i, j), hand.M(hi, hj), tol) << "M " << i << "," << j;
            EXPECT_NEAR(z.D(i, j), hand.D(hi, hj), tol) << "D " << i << "," << j;
            EXPECT_NEAR(z.K(i, j), hand.K(hi, hj), tol) << "K " << i << "," << j;
          }
        }
    }
  }
}

TEST(MultiBlade, QuarticDiscriminantIsTheProductOfRootDifferences) {
  // a^6 prod (r_i - r_j)^2 for chosen roots, real and complex.
  using C = std::complex<double>;
  const std::vector<std::array<C, 4>> cases{{C(1), C(-2), C(0.5), C(3)}, {C(1, 2), C(1, -2), C(-1), C(4)},
                                            {C(0.3, 1), C(0.3, -1), C(2, 0.5), C(2, -0.5)}};
  for (const auto& r : cases) {
    const double a = 1.7;
    // coefficients of a (w - r0)(w - r1)(w - r2)(w - r3)
    std::array<C, 5> p{C(1), C(0), C(0), C(0), C(0)};
    for (int k = 0; k < 4; ++k) {
      std::array<C, 5> q{};
      for (int i = 0; i <= k; ++i) {
        q[i] += p[i];
        q[i + 1] -= r[k] * p[i];
      }
      p = q;
    }
    std::array<double, 5> coef;
    for (int i = 0; i < 5; ++i) coef[i] = a * p[i].real();
    C prod = std::pow(a, 6);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) prod *= (r[i] - r[j]) * (r[i] - r[j]);
    // 16 terms of degree 6 in coefficients up to ~|a| max|r|^4: rounding relative
    // to the largest term, bounded by the value of the sum of |terms| (< 1e4 |prod| here)
    EXPECT_NEAR(models::quarticDiscriminant(coef), prod.real(), 1e4 * DBL_EPSILON * std::abs(prod));
  }
}
