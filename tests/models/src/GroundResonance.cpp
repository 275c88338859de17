#include "cms/models/GroundResonance.hpp"

#include <cmath>

#include "cms/core/Error.hpp"

namespace cms::models {

void GroundResonanceRotor::validate() const {
  CMS_INPUT_CHECK(blades < 2, "GroundResonanceRotor: " << blades << " blades, at least 2 needed");
  auto positive = [](double v, const char* name) {
    CMS_INPUT_CHECK(!(std::isfinite(v) && v > 0.0), "GroundResonanceRotor: " << name << " = " << v
                                                                              << " must be positive and finite");
  };
  auto nonNegative = [](double v, const char* name) {
    CMS_INPUT_CHECK(!(std::isfinite(v) && v >= 0.0), "GroundResonanceRotor: " << name << " = " << v
                                                                               << " must be >= 0 and finite");
  };
  positive(hubMass, "hub mass M");
  positive(bladeMass, "blade mass m");
  positive(firstMoment, "first moment S");
  positive(inertia, "inertia I");
  positive(kx, "kx");
  positive(ky, "ky");
  nonNegative(hingeOffset, "hinge offset e");
  nonNegative(lagStiffness, "lag stiffness");
  nonNegative(lagDamping, "lag damping");
  nonNegative(cx, "cx");
  nonNegative(cy, "cy");
  nonNegative(Omega, "Omega");
  CMS_INPUT_CHECK(bladeMass * inertia <= firstMoment * firstMoment,
                  "GroundResonanceRotor: m I = " << bladeMass * inertia << " must exceed S^2 = "
                                                  << firstMoment * firstMoment << " (Cauchy-Schwarz for a real blade)");
}

double GroundResonanceRotor::lagFrequencySquared() const {
  return lagStiffness / inertia + Omega * Omega * hingeOffset * firstMoment / inertia;
}

GroundResonanceRotor::Matrices GroundResonanceRotor::individualBlade(double t) const {
  validate();
  const int n = size();
  Matrices out{DenseMatrix(n, n), DenseMatrix(n, n), DenseMatrix(n, n)};
  const double Mt = totalMass(), S = firstMoment, W = Omega;
  out.M(0, 0) = out.M(1, 1) = Mt;
  out.D(0, 0) = cx;
  out.D(1, 1) = cy;
  out.K(0, 0) = kx;
  out.K(1, 1) = ky;
  for (int k = 0; k < blades; ++k) {
    const double psi = W * t + 2.0 * M_PI * k / blades, s = std::sin(psi), c = std::cos(psi);
    const int b = 2 + k;
    // S d^2/dt^2 (-zeta sin psi) = S (-sin psi zeta'' - 2 Omega cos psi zeta' + Omega^2 sin psi zeta)
    out.M(0, b) = out.M(b, 0) = -S * s;
    out.D(0, b) = -2.0 * W * S * c;
    out.K(0, b) = W * W * S * s;
    // S d^2/dt^2 (zeta cos psi) = S (cos psi zeta'' - 2 Omega sin psi zeta' - Omega^2 cos psi zeta)
    out.M(1, b) = out.M(b, 1) = S * c;
    out.D(1, b) = -2.0 * W * S * s;
    out.K(1, b) = -W * W * S * c;
    out.M(b, b) = inertia;
    out.D(b, b) = lagDamping;
    out.K(b, b) = inertia * lagFrequencySquared();
  }
  return out;
}

GroundResonanceRotor::Matrices GroundResonanceRotor::multiBlade() const {
  validate();
  CMS_INPUT_CHECK(blades < 3, "GroundResonanceRotor::multiBlade: " << blades
                                                                   << " blades; the constant-coefficient form needs N >= 3");
  Matrices out{DenseMatrix(4, 4), DenseMatrix(4, 4), DenseMatrix(4, 4)};
  const double Mt = totalMass(), h = 0.5 * blades, S = firstMoment, I = inertia, W = Omega, c = lagDamping;
  // z = [x, y, zeta_1c, zeta_1s]; rows c, s are the cyclic lag equations times N / 2.
  out.M(0, 0) = out.M(1, 1) = Mt;
  out.M(0, 3) = out.M(3, 0) = -h * S;
  out.M(1, 2) = out.M(2, 1) = h * S;
  out.M(2, 2) = out.M(3, 3) = h * I;
  out.D(0, 0) = cx;
  out.D(1, 1) = cy;
  out.D(2, 2) = out.D(3, 3) = h * c;
  out.D(2, 3) = 2.0 * h * I * W;  // Coriolis: I (2 Omega zeta_1s') in the cosine equation
  out.D(3, 2) = -2.0 * h * I * W;
  out.K(0, 0) = kx;
  out.K(1, 1) = ky;
  out.K(2, 2) = out.K(3, 3) = h * I * (lagFrequencySquared() - W * W);
  out.K(2, 3) = h * c * W;  // the lag damper sees zeta_1c' + Omega zeta_1s
  out.K(3, 2) = -h * c * W;
  return out;
}

std::array<double, 5> GroundResonanceRotor::characteristicQuartic() const {
  validate();
  CMS_INPUT_CHECK(kx != ky, "GroundResonanceRotor::characteristicQuartic: the hub is anisotropic (kx = "
                                << kx << ", ky = " << ky << "); the closed form is for kx = ky");
  const double Mt = totalMass(), k = kx, I = inertia, W = Omega, nu2 = lagFrequencySquared();
  // (k - Mt w^2) (-I w^2 + 2 I Omega w + I (nu^2 - Omega^2)) - (N S^2 / 2) w^4
  return {Mt * I - 0.5 * blades * firstMoment * firstMoment, -2.0 * Mt * I * W, -k * I - Mt * I * (nu2 - W * W),
          2.0 * k * I * W, k * I * (nu2 - W * W)};
}

double GroundResonanceRotor::centreSpeed() const {
  validate();
  const double wh2 = kx / totalMass(), wh = std::sqrt(wh2), eps = hingeOffset * firstMoment / inertia,
               nu02 = lagStiffness / inertia;
  CMS_INPUT_CHECK(eps >= 1.0, "GroundResonanceRotor::centreSpeed: e S / I = " << eps
                                                                               << " >= 1: the regressing lag never meets the hub");
  // (Omega - wh)^2 = nu0^2 + eps Omega^2  ->  (1 - eps) Omega^2 - 2 wh Omega + wh^2 - nu0^2 = 0, the root above wh
  const double disc = eps * wh2 + (1.0 - eps) * nu02;
  return (wh + std::sqrt(disc)) / (1.0 - eps);
}

double GroundResonanceRotor::deutschCriticalProduct() const {
  GroundResonanceRotor at = *this;
  at.Omega = centreSpeed();
  const double wh = std::sqrt(kx / totalMass()), nu = std::sqrt(at.lagFrequencySquared());
  return 0.5 * blades * firstMoment * firstMoment * wh * wh * wh / nu;
}

double quarticDiscriminant(const std::array<double, 5>& q) {
  const double a = q[0], b = q[1], c = q[2], d = q[3], e = q[4];
  return 256 * a * a * a * e * e * e - 192 * a * a * b * d * e * e - 128 * a * a * c * c * e * e +
         144 * a * a * c * d * d * e - 27 * a * a * d * d * d * d + 144 * a * b * b * c * e * e -
         6 * a * b * b * d * d * e - 80 * a * b * c * c * d * e + 18 * a * b * c * d * d * d +
         16 * a * c * c * c * c * e - 4 * a * c * c * c * d * d - 27 * b * b * b * b * e * e +
         18 * b * b * b * c * d * e - 4 * b * b * b * d * d * d - 4 * b * b * c * c * c * e + b * b * c * c * d * d;
}

}  // namespace cms::models
