// Isoparametric 3D solid elements with three translational DOFs per node:
// 4- and 10-node tetrahedra and 8-node hexahedra, in Gmsh's node order.
// Stiffness, consistent mass, rotating-frame terms per unit speed and the
// geometric stiffness of the stress caused by a displacement (doc/theory.md
// §9, §10). Integration is exact for the polynomial degree of each integrand
// on straight-sided elements (tetrahedra: collapsed Gauss products).
#pragma once

#include "cms/fem/ElementMatrix.hpp"

namespace cms::fem {

enum class SolidType { Tet4, Tet10, Hex8 };

int solidNodeCount(SolidType type);

struct SolidElement {
  SolidType type = SolidType::Tet4;
  const double* xyz = nullptr;  ///< node coordinates, 3 per node, Gmsh order
  IsotropicMaterial material;
};

/// All throw cms::NumericalError when the Jacobian determinant is not
/// positive at an integration point (an inverted or degenerate element); the
/// assembler adds the element tag to the message.
ElementMatrix solidStiffness(const SolidElement& e);
ElementMatrix solidMass(const SolidElement& e);
double solidVolume(const SolidElement& e);

/// Rotating-frame terms per unit speed: G1 = 2 ∫ rho N^T [n]x N dV,
/// KT1 = ∫ rho N^T [n]x^T [n]x N dV, f1 = ∫ rho N^T r_perp dV with
/// r_perp = (I - n n^T)(x - origin).
SpinMatrices solidSpinMatrices(const SolidElement& e, const Spin& spin);

/// Geometric stiffness of the linear-elastic stress sigma = D B ue at each
/// integration point: K_ab = ∫ (grad N_a^T sigma grad N_b) dV * I_3.
ElementMatrix solidGeometricStiffness(const SolidElement& e, const double* ue);

/// Volume-averaged stress of ue, Voigt order xx yy zz yz xz xy.
std::array<double, 6> solidMeanStress(const SolidElement& e, const double* ue);

}  // namespace cms::fem
