// Coleman & Feingold's ground resonance model (doc/theory.md §16.4): N rigid
// blades on offset lag hinges on a hub that translates in the plane of the
// rotor on springs and dampers. Built in code, for the Floquet and
// multi-blade tests (not installed).
//
// Hub: mass M (without the blades) at (x, y) in the fixed frame, springs kx,
// ky and dampers cx, cy to ground. Blade k (k = 0..N-1) at azimuth
// psi_k = Omega t + 2 pi k / N, hinged at radius e from the hub centre, lag
// angle zeta_k positive in the sense of rotation (a lead); mass m, first
// moment S and inertia I about its hinge, lag spring k_zeta and damper
// c_zeta at the hinge. Linearised equations (theory §16.4):
//
//   (M + N m) x'' + cx x' + kx x + S sum_k d^2/dt^2 (-zeta_k sin psi_k) = 0
//   (M + N m) y'' + cy y' + ky y + S sum_k d^2/dt^2 ( zeta_k cos psi_k) = 0
//   I zeta_k'' + c_zeta zeta_k' + (k_zeta + e S Omega^2) zeta_k + S (-x'' sin psi_k + y'' cos psi_k) = 0
//
// q = [x, y, zeta_0, ..., zeta_{N-1}].
#pragma once

#include <array>

#include "cms/core/DenseMatrix.hpp"

namespace cms::models {

struct GroundResonanceRotor {
  int blades = 4;          ///< N
  double hubMass = 1.0;    ///< M, without the blades (kg)
  double bladeMass = 0.1;  ///< m (kg)
  double firstMoment = 0.05;  ///< S = int r dm about the hinge (kg m)
  double inertia = 0.04;   ///< I = int r^2 dm about the hinge (kg m^2)
  double hingeOffset = 0.1;   ///< e (m)
  double lagStiffness = 0.0;  ///< k_zeta (N m / rad)
  double lagDamping = 0.0;    ///< c_zeta (N m s / rad)
  double kx = 1.0, ky = 1.0;  ///< hub springs (N/m)
  double cx = 0.0, cy = 0.0;  ///< hub dampers (N s/m)
  double Omega = 1.0;         ///< rotor speed (rad/s)

  /// Throws cms::InputError naming the property out of range (N >= 2,
  /// masses, inertias, springs > 0, dampers >= 0, m I > S^2).
  void validate() const;
  /// M + N m: the mass that translates with the hub.
  double totalMass() const { return hubMass + blades * bladeMass; }
  /// nu^2 = k_zeta / I + Omega^2 e S / I: the lag frequency in the rotating frame.
  double lagFrequencySquared() const;
  int size() const { return 2 + blades; }

  /// M(t), D(t), K(t) of the individual-blade (periodic) equations above.
  struct Matrices { DenseMatrix M, D, K; };
  Matrices individualBlade(double t) const;

  /// The constant-coefficient multi-blade form for N >= 3 on an isotropic
  /// hub, written out by hand (theory §16.4): z = [x, y, zeta_1c, zeta_1s],
  /// the cyclic lag equations scaled by N/2 (premultiplied by T^T, as
  /// MultiBladeTransform does). D carries the Coriolis (skew) and damping
  /// parts, K the circulatory part c_zeta Omega of the lag damper.
  Matrices multiBlade() const;

  /// Undamped, isotropic hub (k = kx = ky): the characteristic polynomial of
  /// the 4-DOF multi-blade system in complex form, s = i omega (theory §16.4):
  ///   P(omega) = (k - M_t omega^2) I (nu^2 - (omega - Omega)^2) - (N S^2 / 2) omega^4,
  /// coefficients [a4, a3, a2, a1, a0] of omega^4 .. omega^0. Its 4 roots
  /// omega (real: neutral whirl; complex pairs: the instability) and their
  /// negatives' conjugates are the 8 eigenvalues i omega of the real system.
  std::array<double, 5> characteristicQuartic() const;

  /// Speed at the centre of the resonance band: where the regressing lag
  /// frequency Omega - nu(Omega) equals the hub frequency sqrt(k / M_t)
  /// (isotropic hub). InputError if there is none (e S >= I and no root).
  double centreSpeed() const;
  /// Deutsch's boundary at the centre speed (theory §16.5):
  /// c_hub c_zeta = (N S^2 / 2) omega_h^3 / nu, omega_h = sqrt(k / M_t),
  /// nu = Omega_c - omega_h. Above: stable there; below: unstable.
  double deutschCriticalProduct() const;
};

/// Discriminant of a4 w^4 + a3 w^3 + a2 w^2 + a1 w + a0 (the classical
/// expression in the coefficients): a4^6 prod_{i<j} (r_i - r_j)^2. > 0: four
/// real roots or two complex pairs; < 0: two real and one complex pair; 0: a
/// double root.
double quarticDiscriminant(const std::array<double, 5>& a);

}  // namespace cms::models
