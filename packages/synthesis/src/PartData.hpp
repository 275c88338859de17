// Internal to the synthesis package: one substructure of an assembled
// structure with its frame, attachment and interface data (theory §11).
#pragma once

#include <array>
#include <string>
#include <cstdint>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/fem/FiniteElementAssembly.hpp"
#include "cms/substructure/Substructure.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace cms::synthesis {

/// Q's rotation (theory §15.2): copy `c` relative to its prototype `p`, both
/// placed about the same axis.
inline fem::Rotation turnFromPrototype(const CopyPlacement& c, const CopyPlacement& p) {
  return fem::Rotation::about(c.axis, c.angle - p.angle);
}

namespace detail {

/// A coefficient on a (mesh node index, component) DOF: H before the
/// parent's layout is known.
struct NodalCoefficient {
  std::int64_t node = 0;
  fem::Component component = fem::Component::UX;
  double coefficient = 0.0;
};

/// Row of the rigid motion about P (fem/Vec3.hpp; the reduction's static
/// correction of a child held by its own supports makes the same field).
using fem::rigidRow;

/// Whether a "Reduction" list asks for the basis `kind` ("Basis" given as a
/// string; an unset or mistyped one is the default's or refused later).
inline bool asksBasis(const Teuchos::ParameterList& reduction, const char* kind) {
  return reduction.isParameter("Basis") && reduction.isType<std::string>("Basis") &&
         reduction.get<std::string>("Basis") == kind;
}

}  // namespace detail

/// The frame a substructure's matrices refer to, and its absolute speed as
/// a combination sum_i c_i s_i of the speed parameters.
struct Frame {
  bool spinning = false;
  fem::SpinDefinition::Frame kind = fem::SpinDefinition::Frame::Rotating;
  fem::Vec3 axis{0, 0, 1}, origin{0, 0, 0};
  std::vector<std::pair<int, double>> coefficients;
  bool stressStiffening = true;
};

struct AssembledStructure::Part {
  SubstructureSpec spec;
  int parent = -1;  ///< index in parts(), -1 for C
  std::vector<int> children;
  std::optional<substructure::Substructure> sub;  ///< C, E, A
  /// A copy whose matrices are its prototype's turned by the assembly
  /// (Substructure::turned, theory §15.2), not assembled on its own.
  bool matricesTurned = false;
  /// An axisymmetric A in the stationary form spinning inside a spinning
  /// parent frame ("compound"): `sub` carries the parent frame's terms (like
  /// an E), `stationary` its own spin's G1 and the cross stiffness KX1.
  bool compound = false;
  std::optional<substructure::Substructure> stationary;
  Frame frame;
  int speedParam = -1;  ///< its own spin parameter (C, A, R), or -1
  fem::Vec3 point{0, 0, 0};  ///< attachment point P (free C: reference point)
  std::string gapNote;       ///< its attachment nodes' rigid link to P, where long (AssembledStructure notes)
  /// Its model holds it by supports or grounded springs of its own (fixed
  /// DOFs, or a grounded spring with stiffness): a rigid motion of it
  /// strains it, K X != 0. A child's attachment motion then needs the
  /// static correction in its basis (reduction::SubstructureBoundary::
  /// supportedAttachment), and its projected stiffness keeps K X
  /// (SynthesizedStructure::carriedRigidly; theory §11.2).
  bool ownSupports = false;
  bool floating = false;     ///< free C: a = the six rigid-body coordinates
  /// A rotor spinning in its own frame on an attachment that moves (a hub on
  /// an airframe): a = six coordinates b of its own, the attachment motion in
  /// the rotor's axes, tied to the parent's by b = R(psi)^T a_parent at hub
  /// azimuth psi (theory §16.8; SynthesizedStructure::movingHubs).
  bool movingHub = false;
  /// a_k = sum H[k] over the parent's DOFs, nodal and then as parent rows
  /// (6 rows for a point attachment, one per shared DOF for Boolean).
  std::vector<std::vector<detail::NodalCoefficient>> H;
  std::vector<std::vector<std::pair<GlobalOrdinal, double>>> Hrows;
  /// Boolean attachment: the child's (node, component) that a_k is.
  std::vector<std::pair<std::int64_t, fem::Component>> booleanDofs;
  bool boolean() const { return !booleanDofs.empty(); }
  /// Row of X (u_child = X a + ...) for the child's DOF (node at x, component):
  /// the rigid motion of a point at x - P, or the Boolean injection.
  std::vector<double> attachmentRow(const fem::Vec3& x, std::int64_t node, int component) const;
  /// Held DOFs (attachment or reference), nodal and as rows (sorted).
  std::vector<detail::NodalCoefficient> heldDofs;
  std::vector<GlobalOrdinal> held;
  bool prestressSolvedGlobally = false;  ///< step 7 of assemble (Boolean interfaces)
  /// Its prestress solve's factorisation of K with `held` held, kept for
  /// its reduction (SynthesizedStructure::buildBases takes it and frees it
  /// after the part's basis; null if none or not kept: theory §11.4).
  std::shared_ptr<const HeldFactor> stiffnessFactor;
  /// Prestress loads per unit Omega^2 from its children (their reactions).
  std::vector<fem::PrestressConditions::NodalValue> childLoads;
  /// Those of them applied through a rigid offset (a Node attachment with a
  /// Point off the node): the link's geometric stiffness (theory §11.4).
  std::vector<fem::PrestressConditions::OffsetLoad> childOffsetLoads;
  /// R only: 6 x 6 matrices on a = (u_P, theta_P), 7 x 7 with the spin
  /// angle last when it is a coordinate.
  struct Rotor {
    fem::ElementMatrix M;
    std::vector<std::pair<int, fem::ElementMatrix>> G;           ///< per speed parameter
    std::vector<std::tuple<int, int, fem::ElementMatrix>> K;     ///< K_ij, i <= j
    std::vector<double> f1;  ///< centrifugal load on a per unit frame speed^2 (spinning frame)
  } rotor;
  bool prestressed() const {
    return sub && frame.spinning && frame.kind == fem::SpinDefinition::Frame::Rotating && frame.stressStiffening;
  }
};

}  // namespace cms::synthesis
