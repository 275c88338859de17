// Coleman & Feingold's ground resonance (doc/theory.md §16.4-§16.5), three
// independent ways:
//  - the closed form: the characteristic quartic of the 4-DOF multi-blade
//    system, whose instability edges are the roots of its discriminant
//    (found by bisection on the discriminant's sign, no eigensolver);
//  - the eigenvalues of the constant-coefficient multi-blade system
//    (eigen::DenseGyroscopicSolver on MultiBladeTransform's output);
//  - Floquet on the individual-blade periodic equations.
// With dampers, Deutsch's boundary at the centre of the band (derived in
// §16.5) against the least damping ratio; Floquet against the multi-blade
// eigenvalues (growth rates and fixed-frame frequencies); and a two-bladed
// rotor on an anisotropic support, which has no constant-coefficient form,
// by Floquet against a plain RK4 time integration.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <complex>
#include <functional>

#include <Teuchos_LAPACK.hpp>

#include "cms/analysis/Floquet.hpp"
#include "cms/analysis/MultiBladeCoordinates.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/models/GroundResonance.hpp"

using namespace cms;
using cplx = std::complex<double>;

namespace {

/// An articulated rotor (no lag spring) whose regressing lag meets the hub
/// near Omega = 1 (theory §16.4's example): M_t = 2.4, omega_h = 0.645,
/// nu = 0.378 Omega.
models::GroundResonanceRotor articulated(int N) {
  models::GroundResonanceRotor r;
  r.blades = N;
  r.hubMass = 2.4 - N * 0.1;  // M_t = 2.4 whatever N
  r.bladeMass = 0.1;
  r.firstMoment = 0.05;
  r.inertia = 0.035;
  r.hingeOffset = 0.1;
  r.kx = r.ky = 1.0;
  return r;
}

analysis::SecondOrderMatrices multiBladeOf(const models::GroundResonanceRotor& r) {
  const analysis::MultiBladeTransform mbt(r.blades);
  const auto ib = r.individualBlade(0.0);
  return mbt.toMultiBlade({ib.M, ib.D, ib.K}, 0.0, r.Omega, 2);
}

eigen::GyroscopicResult multiBladeModes(const models::GroundResonanceRotor& r) {
  Teuchos::ParameterList p;
  p.set("Method", "General");
  return eigen::DenseGyroscopicSolver(p).solve(analysis::gyroscopicSystem(multiBladeOf(r)));
}

analysis::FloquetResult floquetOfIndividualBlades(const models::GroundResonanceRotor& r, double tolerance = 1e-12) {
  const int N = r.blades;
  std::function<DenseMatrix(double)> observation;
  if (N >= 3) {  // fixed-frame quantities: x, y and the multi-blade coordinates
    observation = [N, W = r.Omega](double t) { return analysis::MultiBladeTransform(N).observation(W * t, 2); };
  } else {  // two blades: x, y and the blades' lag displacement in the fixed frame, zeta_k (-sin psi_k, cos psi_k)
    observation = [W = r.Omega](double t) {
      DenseMatrix C(6, 4);
      C(0, 0) = C(1, 1) = 1.0;
      for (int k = 0; k < 2; ++k) {
        const double psi = W * t + M_PI * k;
        C(2 + 2 * k, 2 + k) = -std::sin(psi);
        C(3 + 2 * k, 2 + k) = std::cos(psi);
      }
      return C;
    };
  }
  auto sys = analysis::PeriodicSystem::secondOrder(
      2.0 * M_PI / r.Omega, r.size(),
      [r](double t) {
        const auto m = r.individualBlade(t);
        return analysis::SecondOrderMatrices{m.M, m.D, m.K};
      },
      observation);
  Teuchos::ParameterList p;
  p.set("Tolerance", tolerance);
  return analysis::FloquetAnalysis(p).analyse(sys);
}

/// The last point where `unstable` changes between lo (verdict vlo) and hi,
/// by bisection to a relative width `rel`.
double bisectEdge(double lo, double hi, const std::function<bool(double)>& unstable, double rel) {
  const bool vlo = unstable(lo);
  EXPECT_NE(vlo, unstable(hi)) << "no change of verdict in [" << lo << ", " << hi << "]";
  while (hi - lo > rel * hi) {
    const double mid = 0.5 * (lo + hi);
    (unstable(mid) == vlo ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

// Undamped, isotropic: the unstable speed range [Omega_1, Omega_2] from the
// discriminant of the characteristic quartic (§16.4), against the range
// where the multi-blade eigenvalues and the Floquet exponents of the
// individual-blade equations grow. Edges to 1e-6 relative.
TEST(GroundResonance, UndampedUnstableRangeFromTheDiscriminantEigenvaluesAndFloquet) {
  for (int N : {3, 4}) {
    auto rotor = articulated(N);
    auto discriminant = [&](double W) {
      auto r = rotor;
      r.Omega = W;
      return models::quarticDiscriminant(r.characteristicQuartic());
    };
    // 1. Scan for sign changes of the discriminant, then bisect each to the
    //    bracket's rounding (relative 1e-14): the closed-form edges.
    std::vector<std::pair<double, double>> brackets;
    const int scan = 400;
    const double lo = 0.3, hi = 3.0;
    double prev = discriminant(lo);
    for (int i = 1; i <= scan; ++i) {
      const double W0 = lo + (hi - lo) * (i - 1) / scan, W1 = lo + (hi - lo) * i / scan, d = discriminant(W1);
      if ((d < 0) != (prev < 0)) brackets.push_back({W0, W1});
      prev = d;
    }
    ASSERT_EQ(brackets.size(), 2u) << "N = " << N << ": expected one unstable band (two edges)";
    std::vector<double> exact;
    for (auto [a, b] : brackets)
      exact.push_back(bisectEdge(a, b, [&](double W) { return discriminant(W) < 0; }, 1e-14));
    // Between the edges the quartic has a complex pair (discriminant < 0: two real roots, one pair).
    EXPECT_LT(discriminant(0.5 * (exact[0] + exact[1])), 0.0);
    std::printf("N = %d: closed-form unstable range [%.12f, %.12f] rad/s (centre speed %.6f)\n", N, exact[0],
                exact[1], rotor.centreSpeed());
    EXPECT_GT(rotor.centreSpeed(), exact[0]);
    EXPECT_LT(rotor.centreSpeed(), exact[1]);

    // 2. The multi-blade eigenvalues: unstable when some Re lambda exceeds what
    //    rounding can do near the coalescence, where the eigenvalue is
    //    defective and a backward error eps splits it by sqrt(eps) |lambda|:
    //    threshold 10 sqrt(n eps) max|lambda|. The growth near an edge rises
    //    like sqrt(|Omega - Omega_e|), so the threshold moves the edge by
    //    O(threshold^2) ~ 1e-13, far inside 1e-6.
    auto eigenUnstable = [&](double W) {
      auto r = rotor;
      r.Omega = W;
      const auto res = multiBladeModes(r);
      double grow = -1.0, scale = 0.0;
      for (const auto& m : res.modes) grow = std::max(grow, m.growthRate), scale = std::max(scale, std::abs(m.lambda));
      return grow > 10.0 * std::sqrt(r.size() * DBL_EPSILON) * scale;
    };
    // 3. Floquet: the same argument with the monodromy's estimated error
    //    delta: growth above 10 sqrt(max(delta, n eps)) / T.
    auto floquetUnstable = [&](double W) {
      auto r = rotor;
      r.Omega = W;
      const auto f = floquetOfIndividualBlades(r);
      EXPECT_TRUE(f.converged) << f.monodromyError;
      const double T = 2.0 * M_PI / W;
      return f.largestGrowthRate > 10.0 * std::sqrt(std::max(f.monodromyError, 2 * r.size() * DBL_EPSILON)) / T;
    };
    for (int e = 0; e < 2; ++e) {
      const auto [a, b] = brackets[e];
      const double byEigen = bisectEdge(a, b, eigenUnstable, 1e-10);
      const double byFloquet = bisectEdge(a, b, floquetUnstable, 1e-9);
      std::printf("  edge %d: discriminant %.12f, eigenvalues %.12f (rel %.1e), Floquet %.12f (rel %.1e)\n", e,
                  exact[e], byEigen, std::abs(byEigen - exact[e]) / exact[e], byFloquet,
                  std::abs(byFloquet - exact[e]) / exact[e]);
      EXPECT_NEAR(byEigen, exact[e], 1e-6 * exact[e]) << "N = " << N << ", edge " << e;
      EXPECT_NEAR(byFloquet, exact[e], 1e-6 * exact[e]) << "N = " << N << ", edge " << e;
    }
  }
}

// At the band's upper edge the regressing lag and the hub coalesce into a
// defective pair. At 1.3274403076171877 rad/s (7.5e-7 relative above the
// edge, a point the bisection above visits) LAPACK dggev's QZ iteration
// failed on the scaled pencil with OpenBLAS's Haswell kernels (info = 6)
// once the pencil's scale moved by one rounding; the general path threw.
// The solve must return all five modes, and their eigenvalues must be the
// roots of the characteristic quartic (§16.4), found independently from its
// companion matrix, and the collective lag's i nu, which the quartic's
// cyclic coordinates do not hold. Tolerance: 10 sqrt(n eps) max|lambda|, what rounding
// can do to a defective eigenvalue (the argument of the test above).
TEST(GroundResonance, GeneralPathAtTheBandEdgeWhereQzStalled) {
  for (double W : {1.3274403076171877, 0.7759467473, 1.0}) {
    auto r = articulated(3);
    r.Omega = W;
    const auto res = multiBladeModes(r);
    ASSERT_EQ(static_cast<int>(res.modes.size()), r.size()) << "Omega = " << W << ": " << res.reason;
    EXPECT_EQ(res.status, eigen::SolveStatus::Converged) << res.reason;
    // Roots of a4 w^4 + ... + a0 from the companion matrix (LAPACK dgeev on 4 x 4).
    const auto a = r.characteristicQuartic();
    double C[16] = {0.0}, wr[4], wi[4], work[64], dummy = 0.0;
    for (int j = 0; j < 4; ++j) C[0 + 4 * j] = -a[j + 1] / a[0];
    for (int i = 1; i < 4; ++i) C[i + 4 * (i - 1)] = 1.0;
    int info = 0;
    Teuchos::LAPACK<int, double>().GEEV('N', 'N', 4, C, 4, wr, wi, &dummy, 1, &dummy, 1, work, 64, nullptr, &info);
    ASSERT_EQ(info, 0);
    double scale = 0.0;
    for (const auto& m : res.modes) scale = std::max(scale, std::abs(m.lambda));
    const double tol = 10.0 * std::sqrt(r.size() * DBL_EPSILON) * scale;
    for (const auto& m : res.modes) {
      double nearest = std::abs(m.lambda - cplx(0.0, std::sqrt(r.lagFrequencySquared())));
      for (int k = 0; k < 4; ++k) {
        const cplx w(wr[k], wi[k]), I(0.0, 1.0);
        nearest = std::min({nearest, std::abs(m.lambda - I * w), std::abs(m.lambda + I * std::conj(w))});
      }
      EXPECT_LE(nearest, tol) << "Omega = " << W << ": lambda = " << m.lambda << " is no root of the quartic; "
                              << res.reason;
    }
    std::printf("Omega = %.17g: %s\n", W, res.reason.c_str());
  }
}

// Deutsch's boundary (§16.5): at the centre speed, a root sits on the
// imaginary axis exactly when c_hub c_zeta = (N S^2 / 2) omega_h^3 / nu. The
// least damping ratio of the multi-blade system is 0 there, positive 10%
// above, negative 10% below.
TEST(GroundResonance, DeutschCriterionAtTheCentreOfTheBand) {
  auto rotor = articulated(4);
  rotor.Omega = rotor.centreSpeed();
  const double critical = rotor.deutschCriticalProduct();
  const double wh = std::sqrt(rotor.kx / rotor.totalMass()), nu = std::sqrt(rotor.lagFrequencySquared());
  // Split the product so that the hub and lag modes have equal damping ratios
  // c_h / (2 M_t omega_h) = c_zeta / (2 I nu).
  const double ratio = rotor.totalMass() * wh / (rotor.inertia * nu);
  double least[3];
  const double factors[3] = {0.9, 1.0, 1.1};
  for (int i = 0; i < 3; ++i) {
    auto r = rotor;
    const double P = factors[i] * critical;
    r.cx = r.cy = std::sqrt(P * ratio);
    r.lagDamping = std::sqrt(P / ratio);
    const auto res = multiBladeModes(r);
    least[i] = res.leastDampingRatio();
    std::printf("c_h c_zeta = %.2f x critical: least damping ratio %.3e (%s)\n", factors[i], least[i],
                res.solver.c_str());
  }
  EXPECT_LT(least[0], 0.0);  // below the boundary: unstable
  EXPECT_GT(least[2], 0.0);  // above: stable
  // On the boundary the root is simple (the damping splits it from its
  // partner): its real part is exact to n eps times the scale, so the damping
  // ratio to 1e3 n eps (condition of the damped pair well below 1e3), while
  // 10% away it is of order 1e-3: the boundary is where the criterion puts it.
  EXPECT_LT(std::abs(least[1]), 1e3 * 4 * DBL_EPSILON);
  EXPECT_GT(std::min(-least[0], least[2]), 1e6 * std::abs(least[1]));
}

// Floquet on the individual-blade equations (N = 3, 4) against the
// eigenvalues of the multi-blade system: every mode's growth rate and
// fixed-frame frequency (principal-branch rule, observation = multi-blade
// coordinates) to 1e-8 Omega. Cases: undamped below the band (neutral),
// damped inside it (unstable), damped above it.
TEST(GroundResonance, FloquetOfIndividualBladesMatchesMultiBladeEigenvalues) {
  for (int N : {3, 4}) {
    for (double speedFactor : {0.6, 1.0, 1.5}) {
      auto r = articulated(N);
      r.lagStiffness = 0.002;
      r.Omega = speedFactor * r.centreSpeed();
      if (speedFactor != 0.6) {
        r.cx = r.cy = 0.01;
        r.lagDamping = 0.0005;
      }
      const auto modes = multiBladeModes(r);
      const auto f = floquetOfIndividualBlades(r);
      ASSERT_TRUE(f.converged) << f.monodromyError;
      const double tol = 1e-8 * r.Omega;
      double worst = 0.0;
      for (const auto& m : modes.modes) {
        double best = INFINITY;
        const analysis::FloquetMultiplier* match = nullptr;
        for (const auto& fm : f.multipliers) {
          const double d = std::abs(fm.fixedFrameExponent() - m.lambda);
          if (d < best) best = d, match = &fm;
        }
        worst = std::max(worst, best);
        EXPECT_NEAR(match->growthRate, m.lambda.real(), tol) << "N = " << N << ", Omega = " << r.Omega;
        // Floquet's own error estimate bounds the difference (the multi-blade
        // eigenvalue's rounding, n eps |lambda|, added: it is not exact either).
        EXPECT_LE(std::abs(match->growthRate - m.lambda.real()),
                  match->growthRateError + 10.0 * r.size() * DBL_EPSILON * std::abs(m.lambda));
        EXPECT_NEAR(match->frequency, m.lambda.imag(), tol)
            << "N = " << N << ", Omega = " << r.Omega << ": harmonic " << match->harmonic << " share "
            << match->harmonicShare;
      }
      // And conversely: every Floquet exponent with omega >= 0 is a multi-blade eigenvalue.
      for (const auto& fm : f.multipliers) {
        if (fm.frequency < 0.0) continue;
        double best = INFINITY;
        for (const auto& m : modes.modes) best = std::min(best, std::abs(fm.fixedFrameExponent() - m.lambda));
        EXPECT_LT(best, 2 * tol) << "Floquet exponent " << fm.fixedFrameExponent() << " has no multi-blade match";
      }
      std::printf("N = %d, Omega = %.4f: %zu modes, worst |lambda_Floquet - lambda_MBC| = %.2e Omega, "
                  "monodromy error %.1e at %d steps, Liouville defect %.1e, largest growth %.3e (%s)\n",
                  N, r.Omega, modes.modes.size(), worst / r.Omega, f.monodromyError, f.steps, f.liouvilleDefect,
                  f.largestGrowthRate, analysis::toString(f.stability));
      // Liouville: sum ln|mu| against int tr A, both to the integration's
      // error (relative monodromy error times n, the log-determinant's
      // sensitivity to a relative perturbation of each multiplier) plus rounding.
      EXPECT_LT(f.liouvilleDefect, 2 * r.size() * (f.monodromyError + 1e2 * DBL_EPSILON));
      // Inside the band (the centre speed) unstable, outside not: the same verdict both ways.
      // (The undamped case's damping ratios are 0 to rounding: a simple
      // eigenvalue's real part to 100 n eps |lambda|.)
      EXPECT_EQ(f.stability == analysis::FloquetStability::Unstable, speedFactor == 1.0);
      EXPECT_EQ(modes.leastDampingRatio() < -100.0 * r.size() * DBL_EPSILON, speedFactor == 1.0);
    }
  }
}

namespace {

/// One classical RK4 step of x' = A(t) x, A from the individual-blade
/// matrices by its own elimination (LAPACK dgesv on M).
void rk4Step(const models::GroundResonanceRotor& r, double t, double h, std::vector<double>& x) {
  const int n = r.size();
  auto f = [&](double tt, const std::vector<double>& s) {
    const auto m = r.individualBlade(tt);
    std::vector<double> rhs(n);
    for (int i = 0; i < n; ++i) {
      double v = 0.0;
      for (int j = 0; j < n; ++j) v -= m.D(i, j) * s[n + j] + m.K(i, j) * s[j];
      rhs[i] = v;
    }
    DenseMatrix M = m.M;
    std::vector<int> piv(n);
    int info = 0;
    Teuchos::LAPACK<int, double>().GESV(n, 1, M.values(), M.stride(), piv.data(), rhs.data(), n, &info);
    std::vector<double> out(2 * n);
    for (int i = 0; i < n; ++i) out[i] = s[n + i], out[n + i] = rhs[i];
    return out;
  };
  auto axpy = [](const std::vector<double>& a, double c, const std::vector<double>& b) {
    std::vector<double> o(a);
    for (std::size_t i = 0; i < o.size(); ++i) o[i] += c * b[i];
    return o;
  };
  const auto k1 = f(t, x), k2 = f(t + h / 2, axpy(x, h / 2, k1)), k3 = f(t + h / 2, axpy(x, h / 2, k2)),
             k4 = f(t + h, axpy(x, h, k3));
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
}

/// The dominant multiplier by time integration alone: RK4 from several
/// initial states over many periods; after the transient the period samples
/// x_P obey x_{P+2} = a x_{P+1} + b x_P (the dominant pair mu, conj mu: a =
/// 2 Re mu, b = -|mu|^2), fitted by least squares over all states (Prony).
/// Returns mu (Im >= 0) and the fit's relative residual.
std::pair<cplx, double> dominantByTimeIntegration(const models::GroundResonanceRotor& r, int stepsPerPeriod,
                                                  int transient, int samples) {
  const int n = 2 * r.size();
  const double T = 2.0 * M_PI / r.Omega, h = T / stepsPerPeriod;
  double A00 = 0, A01 = 0, A11 = 0, b0 = 0, b1 = 0;
  std::vector<std::vector<std::vector<double>>> runs;
  for (int ic = 0; ic < 3; ++ic) {
    std::vector<double> x(n);
    for (int i = 0; i < n; ++i) x[i] = std::cos(1.3 * i + 2.1 * ic) + (i == ic ? 1.0 : 0.0);
    std::vector<std::vector<double>> seq;
    for (int P = 0; P < transient + samples; ++P) {
      if (P >= transient) seq.push_back(x);
      for (int s = 0; s < stepsPerPeriod; ++s) rk4Step(r, P * T + s * h, h, x);
    }
    runs.push_back(seq);
  }
  for (const auto& seq : runs)
    for (std::size_t P = 0; P + 2 < seq.size(); ++P) {
      double nrm = 0.0;
      for (double v : seq[P + 1]) nrm += v * v;
      const double w = 1.0 / nrm;  // each equation scaled by 1 / ||x_{P+1}||^2: growth removed
      for (int i = 0; i < n; ++i) {
        const double u = seq[P + 1][i], v = seq[P][i], y = seq[P + 2][i];
        A00 += w * u * u, A01 += w * u * v, A11 += w * v * v, b0 += w * u * y, b1 += w * v * y;
      }
    }
  const double det = A00 * A11 - A01 * A01, a = (b0 * A11 - b1 * A01) / det, b = (A00 * b1 - A01 * b0) / det;
  double res = 0.0, tot = 0.0;
  for (const auto& seq : runs)
    for (std::size_t P = 0; P + 2 < seq.size(); ++P)
      for (int i = 0; i < n; ++i) {
        const double e = seq[P + 2][i] - a * seq[P + 1][i] - b * seq[P][i];
        res += e * e, tot += seq[P + 2][i] * seq[P + 2][i];
      }
  // roots of mu^2 - a mu - b = 0
  const cplx disc = std::sqrt(cplx(a * a + 4 * b, 0.0));
  cplx mu1 = 0.5 * (a + disc), mu2 = 0.5 * (a - disc);
  cplx mu = std::abs(mu1) >= std::abs(mu2) ? mu1 : mu2;
  if (mu.imag() < 0) mu = std::conj(mu);
  return {mu, std::sqrt(res / tot)};
}

}  // namespace

// Two blades on an anisotropic support: periodic, no constant-coefficient
// form. Floquet's dominant multiplier against RK4 + Prony (no monodromy
// matrix, no eigensolver). Tolerance 1e-7 relative on mu: it bounds the sum
// of the RK4 error (measured below by halving the step, required < 1e-8)
// and the Prony fit's contamination by the subdominant multipliers
// ((0.69 / 1.045)^45 ~ 7e-9 after the transient; its relative residual
// required < 1e-8); Floquet's own error is ~1e-13 (its estimate).
TEST(GroundResonance, TwoBladesOnAnAnisotropicSupportFloquetAgainstTimeIntegration) {
  auto r = articulated(2);
  r.hubMass = 0.6;  // a light hub: strong coupling, a clearly dominant multiplier
  r.kx = 1.0;
  r.ky = 1.6;
  r.cx = 0.0;
  r.cy = 0.2;
  r.lagDamping = 0.01;
  r.Omega = r.centreSpeed();  // the x hub mode's crossing with the regressing lag
  const auto f = floquetOfIndividualBlades(r);
  ASSERT_TRUE(f.converged) << f.monodromyError;
  const auto& top = f.multipliers.front();
  std::printf("N = 2, kx = %.2f, ky = %.2f, Omega = %.5f: dominant multiplier %.12f%+.12fi (|mu| = %.12f), "
              "growth %.4e 1/s, frequency %.6f rad/s (harmonic %d, share %.3f), %s\n",
              r.kx, r.ky, r.Omega, top.multiplier.real(), top.multiplier.imag(), std::abs(top.multiplier),
              top.growthRate, top.frequency, top.harmonic, top.harmonicShare, analysis::toString(f.stability));
  for (const auto& m : f.multipliers) std::printf("  |mu| = %.6f  rho = %.5f%+.5fi\n", std::abs(m.multiplier), m.exponent.real(), m.exponent.imag());
  ASSERT_EQ(f.stability, analysis::FloquetStability::Unstable) << "the case must be unstable to be dominated";
  const auto [muH, fitH] = dominantByTimeIntegration(r, 1000, 45, 12);
  const auto [muH2, fitH2] = dominantByTimeIntegration(r, 2000, 45, 12);
  const double rkError = std::abs(muH2 - muH) / 15.0 / std::abs(muH2);  // RK4: error(h/2) ~ |diff| / (2^4 - 1)
  std::printf("  RK4 + Prony: %.12f%+.12fi (|mu| = %.12f), step-halving error %.1e, fit residual %.1e\n",
              muH2.real(), muH2.imag(), std::abs(muH2), rkError, fitH2);
  EXPECT_LT(rkError, 1e-8);
  EXPECT_LT(fitH2, 1e-8);
  const cplx muF = top.multiplier.imag() >= 0 ? top.multiplier : std::conj(top.multiplier);
  std::printf("  |mu_Floquet - mu_RK4| / |mu| = %.1e\n", std::abs(muF - muH2) / std::abs(muF));
  EXPECT_NEAR(std::abs(muF), std::abs(muH2), 1e-7 * std::abs(muF));
  EXPECT_LT(std::abs(muF - muH2), 1e-7 * std::abs(muF));
}
