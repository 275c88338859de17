// Isoparametric 3D solid elements with three translational DOFs per node, in
// Gmsh's node order (cms/mesh/Mesh.hpp): 4- and 10-node tetrahedra, 8-node
// hexahedra (full 2x2x2 integration, or with Wilson-Taylor incompatible modes
// condensed per element), 20-node serendipity hexahedra (3x3x3, or reduced
// 2x2x2 as CalculiX's C3D20R), 15-node wedges, and Lagrange hexahedra of
// order 2, 3 and 4 (27, 64 and 125 nodes, in lexicographic order: the
// reader reorders Gmsh's). Stiffness, consistent mass,
// rotating-frame terms per unit speed and the geometric stiffness of the
// stress caused by a displacement (doc/theory.md §9, §10, §14). Mass rules
// are exact on tetrahedra, right prisms, trilinear Hex8 and parallelepiped
// Hex20 (on tapered wedges and Hex20 only their row sums are, §14.2);
// stiffness rules are exact on straight-sided tetrahedra and wedges and on
// parallelepiped bricks, except where reduced integration is the point
// (Hex20Reduced).
#pragma once

#include "cms/fem/ElementMatrix.hpp"

namespace cms::fem {

/// An element: a cell shape and its formulation. Hex8Incompatible and
/// Hex20Reduced share the nodes of Hex8 and Hex20. Hex27, Hex64 and Hex125
/// are the Lagrange (tensor-product) hexahedra of order k = 2, 3, 4, node
/// (i, j, l) at reference point (-1 + 2i/k, -1 + 2j/k, -1 + 2l/k) numbered
/// i + (k+1) j + (k+1)^2 l, fully integrated ((k+1)^3 Gauss points): the
/// frequency error falls as h^(2k) (theory §14.5), so a slender part needs
/// far fewer DOFs than with quadratic elements.
enum class SolidType { Tet4, Tet10, Hex8, Hex20, Wedge15, Hex8Incompatible, Hex20Reduced, Hex27, Hex64, Hex125 };

/// "Tet4", ..., "Hex8Incompatible", "Hex20Reduced".
const char* solidTypeName(SolidType type);
int solidNodeCount(SolidType type);

struct SolidElement {
  SolidType type = SolidType::Tet4;
  const double* xyz = nullptr;  ///< node coordinates, 3 per node, Gmsh order
  IsotropicMaterial material;
};

/// All throw cms::NumericalError when the Jacobian determinant is not
/// positive at an integration point (an inverted or degenerate element) or
/// negative at a node (a mid-edge node nearer a corner than the quarter
/// point: part of the element inside out, which its Gauss points may not
/// see); the assembler adds the element tag to the message.
ElementMatrix solidStiffness(const SolidElement& e);
ElementMatrix solidMass(const SolidElement& e);
double solidVolume(const SolidElement& e);

/// Hex8Incompatible: the stiffness after static condensation of its nine
/// internal modes, K = Kuu - Kua Kaa^-1 Kau; the internal modes carry no
/// mass, so M, G1, KT1 and f1 are those of Hex8 (theory §14.3).

/// Rotating-frame terms per unit speed: G1 = 2 ∫ rho N^T [n]x N dV,
/// KT1 = ∫ rho N^T [n]x^T [n]x N dV, f1 = ∫ rho N^T r_perp dV with
/// r_perp = (I - n n^T)(x - origin).
SpinMatrices solidSpinMatrices(const SolidElement& e, const Spin& spin);
/// solidMass and solidSpinMatrices from one integration of the scalar mass
/// (each integrates it on its own): the same M, G1, KT1 and f1, bit for
/// bit. Returns M; `out` takes the rest.
ElementMatrix solidMassWithSpin(const SolidElement& e, const Spin& spin, SpinMatrices& out);

/// Geometric stiffness of the linear-elastic stress sigma = D B ue at each
/// integration point of the stiffness rule: K_ab = ∫ (grad N_a^T sigma
/// grad N_b) dV * I_3. Hex8Incompatible: with the displacement gradient of
/// the condensed element (its internal modes follow ue), both in sigma and in
/// the quadratic form (theory §14.3).
ElementMatrix solidGeometricStiffness(const SolidElement& e, const double* ue);

/// Volume-averaged stress of ue, Voigt order xx yy zz yz xz xy (over the
/// stiffness rule's points).
std::array<double, 6> solidMeanStress(const SolidElement& e, const double* ue);

}  // namespace cms::fem
