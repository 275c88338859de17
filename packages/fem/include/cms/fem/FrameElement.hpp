// Two-node 3D frame element (12 DOFs: ux uy uz rx ry rz at each node):
// axial, torsion and bending in two planes, Euler-Bernoulli or Timoshenko
// (shear-deformable, interdependent interpolation: the shape functions of
// Friedman & Kosmatka 1993, which reduce to Hermite cubics when the shear
// parameter phi = 12 E I / (kappa G A L^2) is zero), consistent mass with
// rotary inertia. Rotating-frame and stationary-frame spin terms and the
// geometric stiffness of an axial force (doc/theory.md §9, §10).
#pragma once

#include "cms/fem/ElementMatrix.hpp"

namespace cms::fem {

struct FrameElement {
  Vec3 x1{}, x2{};
  IsotropicMaterial material;
  BeamSection section;
  BeamTheory theory = BeamTheory::EulerBernoulli;

  double length() const;
};

/// Whether a section orientation vector `o` lies across the unit axis `e1`
/// (its part normal to e1 at least 1e-8 of |o|): the rule every frame
/// element's local axes are made by, and the scene's Beam checks with it.
bool orientationAcross(const Vec3& e1, const Vec3& o);

/// Throws cms::InputError when the length is zero (relative to |x1| + |x2|)
/// or the orientation vector is parallel to the axis.
ElementMatrix frameStiffness(const FrameElement& e);
ElementMatrix frameMass(const FrameElement& e);

/// Axial force (tension positive) of the element displacement ue (12 values,
/// global axes): N = EA (u2 - u1) . x_local / L.
double frameAxialForce(const FrameElement& e, const double* ue);

/// An axial force (tension positive) varying along an element as a quadratic
/// in xi = x / L, given by its values at the start, the middle and the end.
/// A constant force N is {N, N, N}. The centrifugal prestress of a spinning
/// element is quadratic: its distributed axial load is linear in x.
struct FrameAxialForce {
  double start = 0.0, middle = 0.0, end = 0.0;

  /// N(xi), quadratic Lagrange interpolation of the three values.
  double at(double xi) const;
  /// (1/L) ∫ N dx (Simpson's rule, exact for a quadratic).
  double mean() const;
};

/// Axial force along a spinning element whose displacement per unit Omega^2
/// is ue (12 values, global axes, the prestress K u1 = f1 of theory §10). The
/// element's own centrifugal load rho A r_perp(x) has the axial component
/// q(x) = rho A r_perp(x) . e1, linear in x; the element's equilibrium
/// (end forces K_e ue - f_e, exact whenever the nodal displacements are) gives
///   N(0) = Nbar + ∫ (1 - xi) q dx,   N(x) = N(0) - ∫_0^x q ds,
/// with Nbar = EA (u2 - u1) . e1 / L = frameAxialForce(e, ue), the mean of N.
FrameAxialForce frameCentrifugalAxialForce(const FrameElement& e, const double* ue, const Spin& spin);

/// The stress resultants of a spinning element's centrifugal prestress that
/// its geometric stiffness needs: the axial force N and the shear forces
/// Vy, Vz along the local y and z axes (the force the part beyond x exerts
/// on the part before it), each quadratic in xi (theory §10).
/// One transverse direction d (the local y or z axis) of the prestress: the
/// shear force V(x) = V(0) - ∫_0^x q ds under the linear load q, and the
/// first moment of the axial stress about that axis, S(x) = ∫ sigma_xx d dA
/// (S' = V by the element's moment equilibrium; the bending moment is
/// M_z = -S_y, M_y = S_z).
struct FrameTransverseResultants {
  double shearStart = 0.0, momentStart = 0.0, loadStart = 0.0, loadEnd = 0.0;
  double shear(double xi, double L) const;
  double moment(double xi, double L) const;
};

struct FramePrestress {
  FrameAxialForce N;
  FrameTransverseResultants y, z;
  /// The torque T = ∫ (y tau_xz - z tau_xy) dA (no distributed torque:
  /// constant along the element).
  double torque = 0.0;
};

/// N as frameCentrifugalAxialForce; V and S from the same equilibrium: the
/// end forces and moments F = K_e ue - f_e at the start (V(0) = -F_d,
/// S_y(0) = F_theta_z, S_z(0) = -F_theta_y in local axes), q = rho A r_perp
/// . e2 (or e3), linear in x. A beam across the radius (a coned or swept
/// blade) carries a transverse centrifugal load, hence shear and bending.
FramePrestress frameCentrifugalPrestress(const FrameElement& e, const double* ue, const Spin& spin);

/// Geometric (stress) stiffness of an axial force N(x): bending
/// ∫ N(x) v'^T v' dx in both planes with the element's own translational shape
/// functions (Gauss points exact for a quadratic N times the products of two
/// slopes), and the torsional term mean(N) (Iy + Iz) / (A L) (the twist is
/// linear, its slope constant).
ElementMatrix frameGeometricStiffness(const FrameElement& e, const FrameAxialForce& axialForce);
/// The same for a constant axial force N.
ElementMatrix frameGeometricStiffness(const FrameElement& e, double axialForce);
/// The same with the transverse resultants' terms, from the second-order
/// work (1/2) ∫ sigma_ij u_k,i u_k,j dV with the beam's kinematics
/// (v = v0 - z theta_x, w = w0 + y theta_x, u = u0 - y theta_z + z theta_y):
/// the shear stresses give ∫ [Vy (w' theta_x - u' theta_z) + Vz (u' theta_y -
/// v' theta_x)] dx, the bending stresses ∫ (S_y w' - S_z v') theta_x' dx, and
/// the torque (the shear stresses' first moments) ∫ (T/2) (theta_y' theta_z -
/// theta_z' theta_y) dx.
/// Without them a rigid rotation of a beam under transverse prestress was
/// not balanced (theory §11.6): a free coned spinner diverged about its axis.
ElementMatrix frameGeometricStiffness(const FrameElement& e, const FramePrestress& prestress);

/// Rotating-frame terms per unit speed: translational (rho A) from the
/// displacement shape functions, rotary (rho J_section) from the rotation
/// shape functions with the rigid-body formulas of theory §9.3; f1 includes
/// the centrifugal force rho A Omega^2 r_perp (r from spin.origin) and the
/// rotary torque (J n) x n.
SpinMatrices frameSpinMatrices(const FrameElement& e, const Spin& spin);

/// Stationary-frame gyroscopic matrix per unit speed of a beam spinning about
/// its own axis (Nelson & McVaugh 1976): only the polar rotary inertia,
/// rho (Iy + Iz) [n]x^T on the rotations, no softening. Throws
/// cms::InputError if axis is not parallel to the element (to 1e-8).
ElementMatrix frameStationaryGyroscopic(const FrameElement& e, const Vec3& axis);
/// A stationary-frame rotor inside a frame spinning about `frameAxis`: the
/// tilt stiffness of its sections' spin momentum per unit Omega_frame *
/// omega, -rho Ip (sym(e n^T) - (e.n) I) interpolated like the gyroscopic
/// matrix (theory §11.5; rho Ip (I - n n^T) for a coaxial rotor).
ElementMatrix frameStationaryTiltStiffness(const FrameElement& e, const Vec3& axis, const Vec3& frameAxis);

}  // namespace cms::fem
