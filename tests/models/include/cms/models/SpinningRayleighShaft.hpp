// A uniform, simply supported, spinning Rayleigh shaft (translational and
// rotary inertia, bending stiffness, polar-inertia gyroscopic coupling) in the
// stationary frame, discretised by the Rayleigh-Ritz method with admissible
// functions that are NOT its eigenfunctions: phi_j(xi) = xi (1 - xi)
// P_{j-1}(2 xi - 1), xi = x / L, which satisfy only the geometric boundary
// conditions v = w = 0 at both ends (seed eq. (10); doc/theory.md, "Spinning
// Rayleigh shaft"). The sets are nested in j, so the inclusion principle
// (seed eqs. (26)-(29)) orders the frequencies of successive truncations.
//
// Coordinates q = [a_1..a_n, b_1..b_n] with v = sum phi_j a_j (bending in the
// x-y plane) and w = sum phi_j b_j (x-z plane); spin Omega about +x.
#pragma once

#include <complex>
#include <utility>
#include <vector>

#include "cms/core/DenseMatrix.hpp"

namespace cms::models {

struct ShaftProperties {
  double length = 1.0;         ///< L (m)
  double radius = 0.02;        ///< solid circular section (m)
  double youngsModulus = 2.1e11;  ///< E (Pa)
  double density = 7800.0;     ///< rho (kg/m^3)
  bool rotaryInertia = true;   ///< false: Euler-Bernoulli (no rotary inertia, no gyroscopic)

  /// Throws cms::InputError naming the property when it is not positive/finite.
  void validate() const;
};

class SpinningRayleighShaft {
public:
  /// `numFunctions` admissible functions per bending plane (n >= 1).
  SpinningRayleighShaft(const ShaftProperties& props, int numFunctions);

  int size() const { return 2 * n_; }
  const DenseMatrix& massMatrix() const { return M_; }
  /// G per unit spin speed: G(Omega) = Omega * G1 (skew).
  const DenseMatrix& gyroscopicPerUnitSpeed() const { return G1_; }
  const DenseMatrix& stiffnessMatrix() const { return K_; }
  /// (v, w) coordinate index pairs, used to tell forward from backward whirl.
  std::vector<std::pair<int, int>> whirlPairs() const;

  /// Closed form for the k-th bending mode (k >= 1): forward and backward
  /// whirl frequencies (rad/s) at spin Omega, roots of
  /// (rhoA + rhoI kk^2) w^2 -/+ 2 rhoI Omega kk^2 w - EI kk^4 = 0, kk = k pi / L.
  static std::pair<double, double> exactWhirl(const ShaftProperties& props, int k, double Omega);
  /// The same mode with Rayleigh damping alpha M + beta K (theory §13.1,
  /// §13.4): beta K is the material's and turns with it, alpha M damps the
  /// absolute velocity. In z = v + i w the damping force is
  /// -alpha m z' - beta kap (z' - i Omega z), so
  ///   m z'' + (alpha m + beta kap - i g Omega) z' + (kap - i beta kap Omega) z = 0,
  /// m = rhoA + rhoI kk^2, g = 2 rhoI kk^2, kap = EI kk^4. Returns its two
  /// roots lambda (z = e^(lambda t)): the forward whirl (Im > 0) and the
  /// backward one (Im < 0; a real solver reports its conjugate).
  static std::pair<std::complex<double>, std::complex<double>> exactDampedWhirl(const ShaftProperties& props, int k,
                                                                                double Omega, double alpha,
                                                                                double beta);

private:
  int n_;
  DenseMatrix M_, G1_, K_;
};

}  // namespace cms::models
