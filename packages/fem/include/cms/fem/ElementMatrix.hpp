// Dense element-level quantities shared by every element: material and
// section data, a small square matrix, and the spin of a rotating frame.
// Element DOFs are ordered node by node; a node carries (ux, uy, uz) for
// solids and (ux, uy, uz, rx, ry, rz) for frames and lumped items with
// inertia. All quantities are in global axes.
#pragma once

#include <array>
#include <vector>

#include "cms/fem/Vec3.hpp"

namespace cms::fem {

/// Isotropic linear elastic material. Checked by validate(): E > 0, rho > 0,
/// -1 < nu < 0.5 (finite), with cms::InputError naming `what` (the material's
/// name in the model) and the offending value.
struct IsotropicMaterial {
  double E = 0.0, nu = 0.0, rho = 0.0;
  double shearModulus() const { return E / (2.0 * (1.0 + nu)); }
  void validate(const char* what) const;
};

/// Beam cross-section in the element's local axes: x along the beam from
/// node 1 to node 2, y = the component of `orientation` normal to x, z = x × y.
/// Iy = ∫ z² dA (bending in the x-z plane), Iz = ∫ y² dA (bending in x-y),
/// J = torsion constant (J = Iy + Iz only for circular sections). Shear factors
/// k_y, k_z (Timoshenko's kappa, 5/6 rectangle, 0.9 solid circle) are used by
/// the Timoshenko theory only. Rotary inertia per unit length is
/// rho diag(Iy + Iz, Iy, Iz) in local axes when rotaryInertia is set, and
/// rho diag(Iy + Iz, 0, 0) otherwise (the twist always keeps its inertia).
struct BeamSection {
  double A = 0.0, Iy = 0.0, Iz = 0.0, J = 0.0;
  double shearFactorY = 5.0 / 6.0, shearFactorZ = 5.0 / 6.0;
  Vec3 orientation{0.0, 0.0, 1.0};
  bool rotaryInertia = true;
  void validate(const char* what) const;  ///< all positive and finite, orientation nonzero
};

enum class BeamTheory { EulerBernoulli, Timoshenko };

/// Square dense matrix, row-major: (i, j) = a[i * n + j].
struct ElementMatrix {
  int n = 0;
  std::vector<double> a;
  ElementMatrix() = default;
  explicit ElementMatrix(int size) : n(size), a(static_cast<std::size_t>(size) * size, 0.0) {}
  double& operator()(int i, int j) { return a[static_cast<std::size_t>(i) * n + j]; }
  double operator()(int i, int j) const { return a[static_cast<std::size_t>(i) * n + j]; }
};

/// The rotating frame: constant angular velocity Omega * axis about the point
/// origin. axis is a unit vector (callers normalise it).
struct Spin {
  Vec3 axis{0.0, 0.0, 1.0};
  Vec3 origin{0.0, 0.0, 0.0};
};

/// An element's rotating-frame terms per unit spin speed (doc/theory.md §9):
///   G1  gyroscopic (Coriolis) matrix, skew:      G  = Omega   G1
///   KT1 spin-softening matrix, symmetric:        K gets -Omega^2 KT1
///   f1  centrifugal load on the undeformed body: f  = Omega^2 f1
struct SpinMatrices {
  ElementMatrix G1, KT1;
  std::vector<double> f1;
};

/// A rotor's material damping seen from the stationary frame (doc/theory.md
/// §13.1): the damping force acts on the velocity relative to the material,
/// which turns at Omega about `axis`, so -D_r q' becomes -D_r (q' - Omega A q)
/// with A = [axis x] on every node's translations and rotations. The
/// circulatory matrix per unit Omega is N1 = -D_r A; returned as its skew part
/// -(D_r A + A D_r) / 2, which is -D_r A exactly when D_r commutes with turns
/// about the axis (an axisymmetric rotor on it, the only one the stationary
/// frame admits). `nodeDofs`: 3 (translations) or 6 per node.
ElementMatrix stationaryRotatingDamping(const ElementMatrix& Dr, const Vec3& axis, int nodeDofs);

}  // namespace cms::fem
