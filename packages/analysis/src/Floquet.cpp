#include "cms/analysis/Floquet.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include <Teuchos_LAPACK.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <Teuchos_Time.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/ParameterReading.hpp"

namespace cms::analysis {

eigen::GyroscopicSystem gyroscopicSystem(const SecondOrderMatrices& m) {
  const int n = m.M.numRows();
  eigen::GyroscopicSystem s;
  s.M = m.M;
  s.G.shape(n, n), s.D.shape(n, n), s.K.shape(n, n), s.N.shape(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      s.G(i, j) = 0.5 * (m.D(i, j) - m.D(j, i));
      s.D(i, j) = 0.5 * (m.D(i, j) + m.D(j, i));
      s.K(i, j) = 0.5 * (m.K(i, j) + m.K(j, i));
      s.N(i, j) = 0.5 * (m.K(i, j) - m.K(j, i));
    }
  return s.symmetrised();
}


namespace {

using cplx = std::complex<double>;
constexpr int kStages = 4;  // Gauss-Legendre, order 2 s = 8
constexpr int kOrder = 2 * kStages;
const double kEps = std::numeric_limits<double>::epsilon();

/// The s = 4 Gauss-Legendre Butcher tableau: nodes c_i the roots of the
/// shifted Legendre polynomial P_4(2c - 1), weights b and matrix a from the
/// simplifying conditions B(4) and C(4) (sum_j b_j c_j^(k-1) = 1/k,
/// sum_j a_ij c_j^(k-1) = c_i^k / k, k = 1..4): collocation at the nodes, so
/// the method is the unique order-8 collocation method (Hairer, Norsett &
/// Wanner I, §II.7). Solved once from the 4 x 4 Vandermonde system instead of
/// typing 20 constants.
struct GaussLegendre4 {
  std::array<double, kStages> c{}, b{};
  std::array<std::array<double, kStages>, kStages> a{};
  GaussLegendre4() {
    const double r = 2.0 / 7.0 * std::sqrt(6.0 / 5.0);
    const double inner = 0.5 * std::sqrt(3.0 / 7.0 - r), outer = 0.5 * std::sqrt(3.0 / 7.0 + r);
    c = {0.5 - outer, 0.5 - inner, 0.5 + inner, 0.5 + outer};
    // V x = rhs with V_kj = c_j^(k-1); 5 right-hand sides: b, then the rows of a.
    DenseMatrix V(kStages, kStages), rhs(kStages, kStages + 1);
    for (int k = 0; k < kStages; ++k)
      for (int j = 0; j < kStages; ++j) V(k, j) = std::pow(c[j], k);
    for (int k = 0; k < kStages; ++k) {
      rhs(k, 0) = 1.0 / (k + 1);
      for (int i = 0; i < kStages; ++i) rhs(k, i + 1) = std::pow(c[i], k + 1) / (k + 1);
    }
    std::array<int, kStages> piv{};
    int info = 0;
    Teuchos::LAPACK<int, double>().GESV(kStages, kStages + 1, V.values(), kStages, piv.data(), rhs.values(),
                                         kStages, &info);
    TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError, "FloquetAnalysis: Gauss-Legendre tableau, dgesv info = " << info);
    for (int j = 0; j < kStages; ++j) {
      b[j] = rhs(j, 0);
      for (int i = 0; i < kStages; ++i) a[i][j] = rhs(j, i + 1);
    }
  }
};

const GaussLegendre4& tableau() {
  static const GaussLegendre4 t;
  return t;
}

DenseMatrix evaluateA(const PeriodicSystem& sys, double t) {
  DenseMatrix A = sys.stateMatrix(t);
  TEUCHOS_TEST_FOR_EXCEPTION(A.numRows() != sys.dimension || A.numCols() != sys.dimension, InputError,
                             "FloquetAnalysis: A(t = " << t << ") is " << A.numRows() << " x " << A.numCols()
                                                       << ", the system's dimension is " << sys.dimension);
  for (int j = 0; j < A.numCols(); ++j)
    for (int i = 0; i < A.numRows(); ++i)
      TEUCHOS_TEST_FOR_EXCEPTION(!std::isfinite(A(i, j)), NumericalError,
                                 "FloquetAnalysis: A(t = " << t << ") has a non-finite entry at (" << i << ", " << j
                                                           << ")");
  return A;
}

/// What one integration run leaves behind.
struct Run {
  DenseMatrix phi;        ///< Phi(T)
  double traceIntegral;   ///< int_0^T tr A dt by the same quadrature (order 8)
  std::vector<DenseMatrix> samples;  ///< C(t_j) Phi(t_j), t_j = j T / steps, j < steps (when requested)
};

/// Phi(T) by `steps` Gauss-Legendre steps. Each step solves the linear stage
/// equations K_i = A(t + c_i h) (X + h sum_j a_ij K_j) for all n columns of X
/// at once: one LU of the (s n) x (s n) matrix I - h (a_ij A_i).
Run integrate(const PeriodicSystem& sys, int steps, bool sample) {
  const auto& gl = tableau();
  const int n = sys.dimension, sn = kStages * n;
  const double h = sys.period / steps;
  Teuchos::LAPACK<int, double> lapack;
  Run run;
  run.phi.shape(n, n);
  for (int i = 0; i < n; ++i) run.phi(i, i) = 1.0;
  run.traceIntegral = 0.0;
  DenseMatrix L(sn, sn), R(sn, n);
  std::vector<int> piv(sn);
  std::array<DenseMatrix, kStages> Ai;
  for (int step = 0; step < steps; ++step) {
    const double t = step * h;
    if (sample) {
      DenseMatrix y = run.phi;
      if (sys.observation) {
        const DenseMatrix C = sys.observation(t);
        TEUCHOS_TEST_FOR_EXCEPTION(C.numCols() != n, InputError,
                                   "FloquetAnalysis: the observation C(t = " << t << ") has " << C.numCols()
                                                                             << " columns, the state " << n);
        y.shape(C.numRows(), n);
        gemm(false, false, 1.0, C, run.phi, 0.0, y);
      }
      run.samples.push_back(std::move(y));
    }
    for (int i = 0; i < kStages; ++i) {
      Ai[i] = evaluateA(sys, t + gl.c[i] * h);
      double tr = 0.0;
      for (int k = 0; k < n; ++k) tr += Ai[i](k, k);
      run.traceIntegral += h * gl.b[i] * tr;
    }
    L.putScalar(0.0);
    for (int i = 0; i < kStages; ++i) {
      for (int j = 0; j < kStages; ++j)
        for (int c = 0; c < n; ++c)
          for (int r = 0; r < n; ++r) L(i * n + r, j * n + c) = -h * gl.a[i][j] * Ai[i](r, c);
      for (int r = 0; r < n; ++r) L(i * n + r, i * n + r) += 1.0;
      DenseMatrix rhs(Teuchos::View, R, n, n, i * n, 0);
      gemm(false, false, 1.0, Ai[i], run.phi, 0.0, rhs);
    }
    int info = 0;
    lapack.GESV(sn, n, L.values(), L.stride(), piv.data(), R.values(), R.stride(), &info);
    TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError,
                               "FloquetAnalysis: the Gauss-Legendre stage equations are singular at t = "
                                   << t << " (step " << h << "; dgesv info = " << info
                                   << "): take more steps per period");
    for (int i = 0; i < kStages; ++i)
      for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) run.phi(r, c) += h * gl.b[i] * R(i * n + r, c);
  }
  return run;
}

double frobenius(const DenseMatrix& A) { return frobeniusNorm(A); }

double differenceNorm(const DenseMatrix& A, const DenseMatrix& B) {
  double s = 0.0;
  for (int j = 0; j < A.numCols(); ++j)
    for (int i = 0; i < A.numRows(); ++i) s += (A(i, j) - B(i, j)) * (A(i, j) - B(i, j));
  return std::sqrt(s);
}

double norm(const std::vector<cplx>& v) {
  double s = 0.0;
  for (const cplx& z : v) s += std::norm(z);
  return std::sqrt(s);
}

/// In-place discrete Fourier transform a_k = sum_j a_j e^(-2 pi i k j / S):
/// radix-2 FFT when S is a power of two (the steps are a power of two times
/// "Steps Per Period"), the direct sum otherwise.
void dft(std::vector<cplx>& a) {
  const int S = static_cast<int>(a.size());
  if (S > 1 && (S & (S - 1)) == 0) {
    for (int i = 1, j = 0; i < S; ++i) {  // bit reversal
      int bit = S >> 1;
      for (; j & bit; bit >>= 1) j ^= bit;
      j ^= bit;
      if (i < j) std::swap(a[i], a[j]);
    }
    for (int len = 2; len <= S; len <<= 1) {
      const cplx w = std::polar(1.0, -2.0 * M_PI / len);
      for (int i = 0; i < S; i += len) {
        cplx wk = 1.0;
        for (int k = 0; k < len / 2; ++k, wk *= w) {
          const cplx u = a[i + k], v = a[i + k + len / 2] * wk;
          a[i + k] = u + v;
          a[i + k + len / 2] = u - v;
        }
      }
    }
    return;
  }
  std::vector<cplx> out(S), twiddle(S);
  for (int j = 0; j < S; ++j) twiddle[j] = std::polar(1.0, -2.0 * M_PI * j / S);
  for (int k = 0; k < S; ++k)
    for (int j = 0; j < S; ++j) out[k] += a[j] * twiddle[(static_cast<long>(k) * j) % S];
  a = std::move(out);
}

/// Principal-branch rule (theory §16.3): the harmonic k of largest energy in
/// the periodic part p(t_j) = C(t_j) Phi(t_j) v e^(-rho t_j) sampled at
/// t_j = j T / S, by the DFT over |k| < S / 2 (Nyquist excluded). Ties go to
/// the smaller |k| (then the positive k).
void harmonicRule(const std::vector<DenseMatrix>& samples, double T, FloquetMultiplier& m) {
  const int S = static_cast<int>(samples.size());
  const int p = samples.front().numRows(), n = samples.front().numCols();
  std::vector<double> energy(S, 0.0);
  std::vector<cplx> y(S);
  for (int r = 0; r < p; ++r) {
    for (int j = 0; j < S; ++j) {
      cplx s = 0.0;
      for (int c = 0; c < n; ++c) s += samples[j](r, c) * m.eigenvector[c];
      y[j] = s * std::exp(-m.exponent * (j * T / S));
    }
    dft(y);
    for (int k = 0; k < S; ++k) energy[k] += std::norm(y[k] / double(S));
  }
  const int kmax = (S - 1) / 2;
  double total = 0.0, best = -1.0;
  int bestK = 0;
  for (int a = 0; a <= kmax; ++a)
    for (int k : {a, -a}) {
      if (a == 0 && k < 0) continue;
      const double e = energy[(k + S) % S];
      total += e;
      if (e > best * (1.0 + 1e3 * kEps)) {  // strictly larger beyond rounding: ties keep the smaller |k|
        best = e;
        bestK = k;
      }
    }
  m.harmonic = bestK;
  m.harmonicShare = total > 0.0 ? best / total : 0.0;
  m.frequency = m.exponent.imag() + bestK * 2.0 * M_PI / T;
}

}  // namespace

const char* toString(FloquetStability s) {
  switch (s) {
    case FloquetStability::Stable: return "stable";
    case FloquetStability::Marginal: return "marginal";
    case FloquetStability::Unstable: return "unstable";
  }
  return "?";
}

double FloquetResult::maxResidual() const {
  double r = 0.0;
  for (const auto& m : multipliers) r = std::max(r, m.residual);
  return r;
}

void PeriodicSystem::validate() const {
  CMS_INPUT_CHECK(!(std::isfinite(period) && period > 0.0),
                  "PeriodicSystem: the period T = " << period << " must be positive and finite");
  CMS_INPUT_CHECK(dimension < 1, "PeriodicSystem: the dimension n = " << dimension << " must be at least 1");
  CMS_INPUT_CHECK(!stateMatrix, "PeriodicSystem: no state matrix A(t) given");
}

PeriodicSystem PeriodicSystem::secondOrder(double period, int n, std::function<SecondOrderMatrices(double)> matrices,
                                           std::function<DenseMatrix(double)> observation) {
  CMS_INPUT_CHECK(n < 1, "PeriodicSystem::secondOrder: n = " << n << " must be at least 1");
  CMS_INPUT_CHECK(!matrices, "PeriodicSystem::secondOrder: no matrices M(t), D(t), K(t) given");
  PeriodicSystem sys;
  sys.period = period;
  sys.dimension = 2 * n;
  sys.stateMatrix = [n, matrices](double t) {
    SecondOrderMatrices m = matrices(t);
    auto check = [&](const DenseMatrix& X, const char* name) {
      TEUCHOS_TEST_FOR_EXCEPTION(X.numRows() != n || X.numCols() != n, InputError,
                                 "PeriodicSystem::secondOrder: " << name << "(t = " << t << ") is " << X.numRows()
                                                                 << " x " << X.numCols() << ", expected " << n
                                                                 << " x " << n);
    };
    check(m.M, "M");
    check(m.D, "D");
    check(m.K, "K");
    // [X_K, X_D] = M^-1 [K, D]
    DenseMatrix rhs(n, 2 * n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        rhs(i, j) = m.K(i, j);
        rhs(i, n + j) = m.D(i, j);
      }
    std::vector<int> piv(n);
    int info = 0;
    Teuchos::LAPACK<int, double>().GESV(n, 2 * n, m.M.values(), m.M.stride(), piv.data(), rhs.values(),
                                         rhs.stride(), &info);
    TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError,
                               "PeriodicSystem::secondOrder: M(t = " << t << ") is singular (dgesv info = " << info
                                                                     << ")");
    DenseMatrix A(2 * n, 2 * n);
    for (int i = 0; i < n; ++i) A(i, n + i) = 1.0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        A(n + i, j) = -rhs(i, j);
        A(n + i, n + j) = -rhs(i, n + j);
      }
    return A;
  };
  if (observation) {
    sys.observation = [n, observation](double t) {
      const DenseMatrix Cq = observation(t);
      TEUCHOS_TEST_FOR_EXCEPTION(Cq.numCols() != n, InputError,
                                 "PeriodicSystem::secondOrder: the observation C(t = " << t << ") has "
                                                                                     << Cq.numCols()
                                                                                     << " columns, q has " << n);
      DenseMatrix C(Cq.numRows(), 2 * n);
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < Cq.numRows(); ++i) C(i, j) = Cq(i, j);
      return C;
    };
  }
  return sys;
}

Teuchos::RCP<const Teuchos::ParameterList> FloquetAnalysis::getValidParameters() {
  static Teuchos::RCP<Teuchos::ParameterList> p;
  if (p.is_null()) {
    p = Teuchos::rcp(new Teuchos::ParameterList("Floquet"));
    const auto steps = Teuchos::rcp(new Teuchos::EnhancedNumberValidator<int>(2, 1 << 24));
    p->set("Steps Per Period", 64, "first number of Gauss-Legendre (order 8) steps over one period (even)", steps);
    p->set("Maximum Steps Per Period", 16384, "steps are doubled up to this until the error estimate meets Tolerance",
           steps);
    p->set("Tolerance", 1e-12,
           "relative error of the monodromy matrix to reach, estimated against the run with half the steps",
           Teuchos::rcp(new Teuchos::EnhancedNumberValidator<double>(0.0, 1.0)));
  }
  return p;
}

FloquetAnalysis::FloquetAnalysis(const Teuchos::ParameterList& params) {
  Teuchos::ParameterList p(params);
  validateOptions(p, *getValidParameters(), "FloquetAnalysis");
  steps_ = p.get<int>("Steps Per Period");
  maxSteps_ = p.get<int>("Maximum Steps Per Period");
  tolerance_ = p.get<double>("Tolerance");
  CMS_INPUT_CHECK(steps_ % 2 != 0, "FloquetAnalysis: \"Steps Per Period\" = " << steps_
                                                                             << " must be even (its half is the error run)");
  CMS_INPUT_CHECK(maxSteps_ < steps_, "FloquetAnalysis: \"Maximum Steps Per Period\" = "
                                          << maxSteps_ << " is below \"Steps Per Period\" = " << steps_);
}

DenseMatrix FloquetAnalysis::monodromy(const PeriodicSystem& system, int steps) {
  system.validate();
  CMS_INPUT_CHECK(steps < 1, "FloquetAnalysis::monodromy: steps = " << steps << " must be at least 1");
  return integrate(system, steps, false).phi;
}

FloquetResult FloquetAnalysis::analyse(const PeriodicSystem& system) const {
  system.validate();
  const int n = system.dimension;
  const double T = system.period;
  FloquetResult result;
  result.integrator = "Gauss-Legendre implicit Runge-Kutta, 4 stages (order 8), fixed steps, doubled until the "
                      "half-step estimate meets the tolerance";

  // 1. The monodromy matrix, doubling the steps until the Richardson estimate
  //    ||Phi_n - Phi_{n/2}|| / (2^8 - 1) meets the tolerance (relative).
  //    Where the estimate is already below sqrt(eps), the integration is
  //    in its order-8 regime (a doubling divides the error by ~2^8); an
  //    estimate that then does not even halve is the rounding floor, which
  //    more steps only raise: the doubling stops there (stalled), not at
  //    "Maximum Steps Per Period". Above sqrt(eps) an estimate may stay flat
  //    for a few doublings while the steps come to resolve the fastest
  //    mode, so no stop is made there.
  Teuchos::Time clock("Floquet", true);
  int steps = steps_;
  Run coarse = integrate(system, steps / 2, false);
  Run fine = integrate(system, steps, true);
  double previous = std::numeric_limits<double>::infinity();
  for (;;) {
    const double diff = differenceNorm(fine.phi, coarse.phi);
    result.monodromyError = diff / (std::pow(2.0, kOrder) - 1.0) / std::max(frobenius(fine.phi), 1e-300);
    result.converged = result.monodromyError <= tolerance_;
    result.stalled = !result.converged && previous < std::sqrt(kEps) && result.monodromyError > 0.5 * previous;
    if (progress_) {
      std::ostringstream os;
      os << std::setprecision(3) << "Floquet: " << steps << " steps per period, monodromy error "
         << result.monodromyError << " (tolerance " << tolerance_ << ")";
      if (result.converged) os << ", converged";
      if (result.stalled)
        os << ", stopped falling from " << previous << " (rounding): the " << steps / 2 << "-step run is kept";
      os << ", " << clock.totalElapsedTime(true) << " s";
      progress_(os.str());
    }
    if (result.converged || result.stalled || 2 * steps > maxSteps_) break;
    previous = result.monodromyError;
    steps *= 2;
    coarse = std::move(fine);
    fine = integrate(system, steps, true);
  }
  if (result.stalled) {
    // The coarser run is kept (at the floor the finer one only adds
    // rounding); its error is then rounding, which the order-8 estimate
    // (a difference over 255) understates: the raw difference of the two
    // runs, ||Phi_n - Phi_{n/2}|| / ||Phi_n||, is what it reports.
    result.monodromyError = std::max(previous, result.monodromyError * (std::pow(2.0, kOrder) - 1.0));
    steps /= 2;
    fine = std::move(coarse);
  }
  result.steps = steps;
  result.monodromy = fine.phi;
  const double phiNorm = frobenius(fine.phi);

  // 2. Multipliers with right and left eigenvectors (dgeev).
  DenseMatrix work = fine.phi, VL(n, n), VR(n, n);
  std::vector<double> wr(n), wi(n);
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  double query = 0.0;
  lapack.GEEV('V', 'V', n, work.values(), n, wr.data(), wi.data(), VL.values(), n, VR.values(), n, &query, -1, &info);
  std::vector<double> lwork(std::max(1, static_cast<int>(query)));
  lapack.GEEV('V', 'V', n, work.values(), n, wr.data(), wi.data(), VL.values(), n, VR.values(), n, lwork.data(),
              static_cast<int>(lwork.size()), &info);
  TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError,
                             "FloquetAnalysis: LAPACK dgeev on the monodromy matrix failed, info = " << info);
  auto column = [n](const DenseMatrix& V, const std::vector<double>& wi, int j) {
    std::vector<cplx> v(n);
    if (wi[j] == 0.0) {
      for (int i = 0; i < n; ++i) v[i] = V(i, j);
    } else if (wi[j] > 0.0) {
      for (int i = 0; i < n; ++i) v[i] = cplx(V(i, j), V(i, j + 1));
    } else {
      for (int i = 0; i < n; ++i) v[i] = cplx(V(i, j - 1), -V(i, j));
    }
    return v;
  };
  const double absErr = result.monodromyError * phiNorm + n * kEps * phiNorm;
  for (int j = 0; j < n; ++j) {
    FloquetMultiplier m;
    m.multiplier = cplx(wr[j], wi[j]);
    TEUCHOS_TEST_FOR_EXCEPTION(std::abs(m.multiplier) == 0.0, NumericalError,
                               "FloquetAnalysis: a zero multiplier (the monodromy matrix is singular)");
    m.exponent = std::log(m.multiplier) / T;
    m.growthRate = m.exponent.real();
    std::vector<cplx> v = column(VR, wi, j), u = column(VL, wi, j);
    const double vn = norm(v), un = norm(u);
    for (cplx& z : v) z /= vn;
    for (cplx& z : u) z /= un;
    cplx uv = 0.0;
    for (int i = 0; i < n; ++i) uv += std::conj(u[i]) * v[i];
    m.conditionNumber = std::abs(uv) > 0.0 ? 1.0 / std::abs(uv) : std::numeric_limits<double>::infinity();
    m.growthRateError = m.conditionNumber * absErr / (std::abs(m.multiplier) * T);
    double r = 0.0;
    for (int i = 0; i < n; ++i) {
      cplx s = -m.multiplier * v[i];
      for (int k = 0; k < n; ++k) s += fine.phi(i, k) * v[k];
      r += std::norm(s);
    }
    m.residual = std::sqrt(r) / phiNorm;
    m.eigenvector = std::move(v);
    harmonicRule(fine.samples, T, m);
    result.multipliers.push_back(std::move(m));
  }
  std::stable_sort(result.multipliers.begin(), result.multipliers.end(),
                   [](const FloquetMultiplier& a, const FloquetMultiplier& b) {
                     if (a.growthRate != b.growthRate) return a.growthRate > b.growthRate;
                     return a.frequency > b.frequency;
                   });

  // 3. Stability and the Liouville check det Phi(T) = exp(int tr A).
  result.largestGrowthRate = result.multipliers.front().growthRate;
  result.largestGrowthRateError = result.multipliers.front().growthRateError;
  bool allBelow = true, someAbove = false;
  for (const auto& m : result.multipliers) {
    if (m.growthRate > m.growthRateError) someAbove = true;
    if (m.growthRate >= -m.growthRateError) allBelow = false;
  }
  result.stability = someAbove ? FloquetStability::Unstable
                               : (allBelow ? FloquetStability::Stable : FloquetStability::Marginal);
  double logDet = 0.0;
  for (const auto& m : result.multipliers) logDet += std::log(std::abs(m.multiplier));
  result.liouvilleDefect = std::abs(logDet - fine.traceIntegral) / (std::abs(fine.traceIntegral) + 1.0);
  return result;
}

}  // namespace cms::analysis
