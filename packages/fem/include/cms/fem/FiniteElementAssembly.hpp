// Parallel assembly of a FiniteElementModel into distributed Tpetra matrices
// (doc/theory.md §9-§10, doc/architecture.md "Assembly"): every rank holds the
// mesh, computes the element matrices of its own block of elements into an
// overlapping CSR matrix, and one Tpetra Export (ADD) sums the shared rows
// into the owned rows. Nothing is gathered onto one rank except the
// factorisation of the prestress solve (cms::SparseDirectSolver's design).
#pragma once

#include <array>

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "cms/core/HeldDofs.hpp"
#include "cms/core/TpetraTypes.hpp"
#include "cms/fem/FiniteElementModel.hpp"

namespace Teuchos { template <class T> class Comm; }

namespace cms::fem {

/// Which global row each (node, component) is: nodes in mesh order, their
/// free components in the order ux uy uz rx ry rz. Identical on every rank
/// and for every rank count.
struct DofLayout {
  std::vector<std::uint8_t> present;  ///< bit c: node carries component c
  std::vector<std::uint8_t> fixed;    ///< bit c: component c is fixed (no row)
  /// bit c: component c of a hinge's second node, eliminated by the hinge
  /// (theory §17): no row, it follows the first node and the hinge rotation.
  /// Empty: none.
  std::vector<std::uint8_t> slaved;
  std::vector<long long> first;       ///< row of the node's first free component
  long long size = 0;                 ///< number of free DOFs

  int componentCount(std::int64_t node) const;  ///< free components of the node
  /// Row of (node, c), or -1 if absent or fixed.
  long long row(std::int64_t node, Component c) const;
};

/// Extra conditions of the centrifugal prestress solve K u1 = f1 (theory
/// §10.2), set by the synthesis layer for a substructure that is part of a
/// structure: DOFs held only during that static solve (a child's attachment,
/// a free body's statically determinate reference) and loads per unit
/// Omega^2 that its children pass on to it (their root reactions). The
/// matrices keep every DOF.
struct PrestressConditions {
  struct NodalValue {
    std::int64_t node = 0;  ///< mesh node index (mesh order, not the tag)
    Component component = Component::UX;
    double value = 0.0;     ///< load per unit Omega^2 (unused for a held DOF)
  };
  std::vector<NodalValue> held;   ///< components the node does not carry are ignored
  std::vector<NodalValue> loads;
  /// A force applied at node + arm through a rigid link (a child or rotor
  /// attached at a Point off the node), per unit Omega^2; its force and
  /// moment arm x force are among `loads`. The link's geometric stiffness
  /// on the node's rotations, (F . r) I - (F r^T + r F^T) / 2 (the force's
  /// work on the arm's second-order displacement theta x (theta x r) / 2),
  /// is added to KS1 (theory §11.4). Nodes without rotations are skipped.
  struct OffsetLoad {
    std::int64_t node = 0;
    Vec3 force{0, 0, 0}, arm{0, 0, 0};
    /// When not empty, the link turns with a rotation fitted to a node
    /// set's translations (a RigidFit attachment) instead of the node's
    /// rotations: theta_i = sum of value x DOF over rotation[i], and the
    /// stiffness is (F . r) I - (F r^T + r F^T) / 2 on those (theory §11.4).
    std::array<std::vector<NodalValue>, 3> rotation;
  };
  std::vector<OffsetLoad> offsetLoads;
  /// When not empty: u1 itself, one value per free DOF in layout order (the
  /// structure solved the coupled static problem); no solve, no reactions.
  std::vector<double> displacement;
  /// Keep the solve's factorisation in AssembledMatrices::stiffnessFactor
  /// for the reduction (otherwise it is freed as soon as u1 is known).
  bool keepFactor = false;
  bool empty() const { return held.empty() && loads.empty() && displacement.empty(); }
};

/// The assembled matrices of one substructure, all on `map` (rows owned by
/// the ranks of a coordinate-slab partition of the nodes; not contiguous). Per unit spin speed (null when the model has
/// no spin, or the term does not apply):
///   K(Omega) = K + Omega^2 (KS1 - KT1),  G(Omega) = Omega G1,  f(Omega) = Omega^2 f1.
struct AssembledMatrices {
  DofLayout layout;
  Teuchos::RCP<const Map> map;
  Teuchos::RCP<const CrsMatrix> M, K, G1, KT1, KS1;
  /// Viscous damping of the model's dampers (SpringSet::damping); null
  /// when none has any. Rayleigh damping is added by the substructure.
  Teuchos::RCP<const CrsMatrix> D;
  /// Stationary frame with Rayleigh beta (StructuralDamping::beta): the
  /// circulatory matrix per unit Omega of the rotor's material damping beta
  /// K_R turning with it, N = Omega N1, skew, and K_R, the stiffness of the
  /// items that turn with it (frames and hinges; not its springs, which are
  /// its bearings and supports), for that damping (theory §13.1); null
  /// otherwise.
  Teuchos::RCP<const CrsMatrix> N1, KR;
  /// Stationary frame with SpinDefinition::frameAxis: the tilt stiffness per
  /// unit Omega_frame * omega (null otherwise).
  Teuchos::RCP<const CrsMatrix> KX1;
  /// The DOFs that hinges eliminated (theory §17), each as a combination of
  /// free rows: u(node, component) = sum coefficient * u[row]. Identical on
  /// every rank; empty without hinges. Expands a solution to every DOF.
  struct DependentDof {
    std::int64_t node = 0;  ///< mesh node index (a hinge's second node)
    Component component = Component::UX;
    std::vector<std::pair<long long, double>> terms;  ///< (row, coefficient)
  };
  std::vector<DependentDof> dependent;
  Teuchos::RCP<const MultiVector> f1;  ///< centrifugal load per Omega^2
  Teuchos::RCP<const MultiVector> u1;  ///< static response K u1 = f1 (prestress)
  /// The prestress solve's factorisation of K with the held DOFs of the
  /// PrestressConditions held (null without a prestress solve, or when free
  /// hinges made it a different matrix), for the reduction to reuse.
  std::shared_ptr<const HeldFactor> stiffnessFactor;
  /// Per held DOF of the PrestressConditions (same order; DOFs the model
  /// already fixes are skipped): the force the hold exerts on the
  /// substructure per unit Omega^2, r = K u1 - f1 - loads. Identical on every rank.
  std::vector<PrestressConditions::NodalValue> reactions1;
  long long elementCount = 0;
  double assemblySeconds = 0.0, prestressSeconds = 0.0;
  /// assemblySeconds split into phases (this rank): DOF layout, pattern and
  /// maps; element matrices and scattering; export to the owned rows.
  double setupSeconds = 0.0, elementSeconds = 0.0, exportSeconds = 0.0;
  /// This rank's share: items (elements and lumped items) assembled here,
  /// and ghost rows (rows owned elsewhere that its elements touch).
  long long localItems = 0, ghostRows = 0;
};

/// Collective. Throws cms::InputError for a model inconsistent with its mesh
/// (naming the set, node or element tag; also a held or loaded DOF the node
/// does not have) and cms::NumericalError for an inverted element or an
/// unconstrained prestress problem.
AssembledMatrices assemble(const FiniteElementModel& model,
                           const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                           const PrestressConditions& prestress = PrestressConditions());

}  // namespace cms::fem
