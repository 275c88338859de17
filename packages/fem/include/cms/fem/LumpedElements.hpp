// Lumped items at a node: a rigid point mass with an inertia tensor (discs,
// wheels, hubs) and springs (bearings, joints), grounded or between two nodes.
#pragma once

#include "cms/fem/ElementMatrix.hpp"

namespace cms::fem {

/// Mass m and inertia tensor J about the node (global axes, symmetric:
/// xx yy zz xy yz xz). DOFs: 3 if J == 0 and the node has no rotations, else 6.
struct PointMass {
  double m = 0.0;
  std::array<double, 6> inertia{};  ///< Jxx Jyy Jzz Jxy Jyz Jxz
  Vec3 x{};                         ///< node position
  /// m > 0 (or m == 0 with J != 0), J symmetric positive semidefinite, finite.
  void validate(const char* what) const;
  bool hasInertia() const;
};

/// M = diag(m I, J) (size 3 or 6 = dofs).
ElementMatrix pointMassMatrix(const PointMass& p, int dofs);
/// Rotating frame, per unit speed: translation G1 = 2m[n]x, KT1 = m[n]x^T[n]x,
/// f1 = m r_perp; rotation: the rigid-body formulas of theory §9.3.
SpinMatrices pointMassSpinMatrices(const PointMass& p, const Spin& spin, int dofs);
/// Stationary frame, per unit speed: (n^T J n) [n]x^T on the rotations. Throws
/// cms::InputError unless J is axisymmetric about the axis (J n = Ip n and
/// equal transverse moments, to 1e-8 relative).
ElementMatrix pointMassStationaryGyroscopic(const PointMass& p, const Vec3& axis);
/// Inside a frame spinning about `frameAxis`: -Ip (sym(e n^T) - (e.n) I) on
/// the rotations per unit Omega_frame * omega (theory §11.5).
ElementMatrix pointMassStationaryTiltStiffness(const PointMass& p, const Vec3& axis, const Vec3& frameAxis);

/// Spring stiffnesses per component (kx ky kz krx kry krz, each >= 0).
/// Grounded: diag(k) (size dofs). Two-node: [[k, -k], [-k, k]] (size 2 dofs).
ElementMatrix groundedSpringMatrix(const std::array<double, 6>& k, int dofs);
ElementMatrix twoNodeSpringMatrix(const std::array<double, 6>& k, int dofs);

}  // namespace cms::fem
