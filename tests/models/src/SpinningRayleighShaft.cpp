#include "cms/models/SpinningRayleighShaft.hpp"

#include <cmath>

#include "cms/core/Error.hpp"

namespace cms::models {

namespace {

/// Gauss-Legendre nodes and weights on [-1, 1] by Newton on P_n.
void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.resize(n);
  w.resize(n);
  for (int i = 0; i < n; ++i) {
    double t = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * t * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      const double pn = n == 1 ? t : p1, pm = n == 1 ? 1.0 : p0;
      dp = n * (t * pn - pm) / (t * t - 1.0);
      const double dt = pn / dp;
      t -= dt;
      if (std::abs(dt) < 1e-15) break;
    }
    x[i] = t;
    w[i] = 2.0 / ((1.0 - t * t) * dp * dp);
  }
}

/// phi_j, phi_j', phi_j'' (derivatives in xi) for j = 1..n at xi.
void admissible(int n, double xi, std::vector<double>& f, std::vector<double>& d1,
                std::vector<double>& d2) {
  const double t = 2.0 * xi - 1.0;
  std::vector<double> P(n + 1), dP(n + 1), ddP(n + 1);  // in t
  P[0] = 1.0, dP[0] = 0.0, ddP[0] = 0.0;
  if (n >= 1) P[1] = t, dP[1] = 1.0, ddP[1] = 0.0;
  for (int k = 1; k < n; ++k) {
    P[k + 1] = ((2 * k + 1) * t * P[k] - k * P[k - 1]) / (k + 1);
    dP[k + 1] = ((2 * k + 1) * (P[k] + t * dP[k]) - k * dP[k - 1]) / (k + 1);
    ddP[k + 1] = ((2 * k + 1) * (2.0 * dP[k] + t * ddP[k]) - k * ddP[k - 1]) / (k + 1);
  }
  const double g = xi * (1.0 - xi), g1 = 1.0 - 2.0 * xi, g2 = -2.0;
  f.resize(n), d1.resize(n), d2.resize(n);
  for (int j = 0; j < n; ++j) {
    f[j] = g * P[j];
    d1[j] = g1 * P[j] + g * 2.0 * dP[j];
    d2[j] = g2 * P[j] + 2.0 * g1 * 2.0 * dP[j] + g * 4.0 * ddP[j];
  }
}

}  // namespace

void ShaftProperties::validate() const {
  const std::pair<double, const char*> v[] = {{length, "length"},
                                              {radius, "radius"},
                                              {youngsModulus, "youngsModulus"},
                                              {density, "density"}};
  for (const auto& [value, name] : v)
    CMS_INPUT_CHECK(!(std::isfinite(value) && value > 0.0),
                    "ShaftProperties: " << name << " = " << value << " must be positive");
}

SpinningRayleighShaft::SpinningRayleighShaft(const ShaftProperties& p, int numFunctions)
    : n_(numFunctions) {
  p.validate();
  CMS_INPUT_CHECK(numFunctions < 1 || numFunctions > 60,
                  "SpinningRayleighShaft: numFunctions = " << numFunctions
                                                           << " must be in [1, 60]");
  const double L = p.length, A = M_PI * p.radius * p.radius,
               I = M_PI * std::pow(p.radius, 4) / 4.0;
  const double rhoA = p.density * A, rhoI = p.rotaryInertia ? p.density * I : 0.0,
               EI = p.youngsModulus * I;
  // Exact for the polynomial integrands (degree <= 2n+2 in xi).
  std::vector<double> gx, gw;
  gaussLegendre(n_ + 3, gx, gw);
  DenseMatrix Mt(n_, n_), Mr(n_, n_), Kb(n_, n_);
  std::vector<double> f, d1, d2;
  for (std::size_t g = 0; g < gx.size(); ++g) {
    const double xi = 0.5 * (gx[g] + 1.0), wq = 0.5 * gw[g] * L;  // dx = L dxi
    admissible(n_, xi, f, d1, d2);
    for (int j = 0; j < n_; ++j)
      for (int i = 0; i < n_; ++i) {
        Mt(i, j) += wq * f[i] * f[j];
        Mr(i, j) += wq * d1[i] * d1[j] / (L * L);            // (d/dx)^2
        Kb(i, j) += wq * d2[i] * d2[j] / (L * L * L * L);    // (d2/dx2)^2
      }
  }
  const int N = 2 * n_;
  M_.shape(N, N), G1_.shape(N, N), K_.shape(N, N);
  for (int j = 0; j < n_; ++j)
    for (int i = 0; i < n_; ++i) {
      const double m = rhoA * Mt(i, j) + rhoI * Mr(i, j);
      M_(i, j) = M_(n_ + i, n_ + j) = m;
      K_(i, j) = K_(n_ + i, n_ + j) = EI * Kb(i, j);
      // Polar inertia rho Ip = 2 rho I couples the planes (doc/theory.md):
      // M a'' + Omega Gp b' + K a = 0,  M b'' - Omega Gp a' + K b = 0.
      const double gp = 2.0 * rhoI * Mr(i, j);
      G1_(i, n_ + j) = gp;
      G1_(n_ + i, j) = -gp;
    }
}

std::vector<std::pair<int, int>> SpinningRayleighShaft::whirlPairs() const {
  std::vector<std::pair<int, int>> p;
  for (int j = 0; j < n_; ++j) p.emplace_back(j, n_ + j);
  return p;
}

std::pair<double, double> SpinningRayleighShaft::exactWhirl(const ShaftProperties& p, int k,
                                                            double Omega) {
  const double A = M_PI * p.radius * p.radius, I = M_PI * std::pow(p.radius, 4) / 4.0;
  const double rhoA = p.density * A, rhoI = p.rotaryInertia ? p.density * I : 0.0,
               EI = p.youngsModulus * I;
  const double kk = k * M_PI / p.length;
  const double m = rhoA + rhoI * kk * kk, gp = 2.0 * rhoI * kk * kk * Omega,
               kap = EI * std::pow(kk, 4);
  const double root = std::sqrt(gp * gp + 4.0 * m * kap);
  return {(gp + root) / (2.0 * m), (-gp + root) / (2.0 * m)};  // forward, backward
}

std::pair<std::complex<double>, std::complex<double>> SpinningRayleighShaft::exactDampedWhirl(
    const ShaftProperties& p, int k, double Omega, double alpha, double beta) {
  const double A = M_PI * p.radius * p.radius, I = M_PI * std::pow(p.radius, 4) / 4.0;
  const double rhoA = p.density * A, rhoI = p.rotaryInertia ? p.density * I : 0.0,
               EI = p.youngsModulus * I;
  const double kk = k * M_PI / p.length;
  const double m = rhoA + rhoI * kk * kk, g = 2.0 * rhoI * kk * kk, kap = EI * std::pow(kk, 4);
  using C = std::complex<double>;
  const C b(alpha * m + beta * kap, -g * Omega), k0(kap, -beta * kap * Omega);
  const C root = std::sqrt(b * b - 4.0 * m * k0);
  const C l1 = (-b + root) / (2.0 * m), l2 = (-b - root) / (2.0 * m);
  return l1.imag() > l2.imag() ? std::make_pair(l1, l2) : std::make_pair(l2, l1);
}

}  // namespace cms::models
