// A structure as the paper builds it (seed, "Kinematical considerations"): a
// central substructure C with a tree of appended substructures, each of one
// of the paper's kinds, attached to its parent at a point whose frame it
// follows, and spinning steadily (doc/theory.md §11).
//
//   C  central: clamped by its own supports, or free-floating with six
//      rigid-body coordinates (w_OC, theta_C) about a reference
//   R  rigid rotor, axisymmetric (a momentum wheel): mass, transverse and
//      axial inertia, spinning about its axis relative to its parent
//   E  elastic, not rotating relative to its parent (panel, boom, blade of a
//      rotor whose hub spins)
//   A  elastic, rotating relative to its parent (rotor, spinning antenna)
//
// Meshes are in one set of axes: the structure's, at rest (the paper's
// L_GR = I: every child frame is parallel to C's when undeformed).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/fem/FiniteElementModel.hpp"

namespace cms::synthesis {

enum class SubstructureKind { Central, Rigid, Elastic, Rotating };
const char* toString(SubstructureKind k);  ///< "C", "R", "E", "A"

/// How a child's frame follows its parent (doc/theory.md §11.2).
struct Attachment {
  enum class Type {
    /// One parent node with rotational DOFs (a frame node): the attachment
    /// frame translates with u_n + theta_n x (P - x_n) and turns with
    /// theta_n (the paper's curl term at R, eq. (2), for a beam node).
    Node,
    /// A set of parent nodes whose translations are fitted by a rigid motion
    /// in the least-squares sense (RBE3-like: the parent is not stiffened).
    RigidFit,
    /// Compatible meshes: every node of the child's set coincides with a node
    /// of the parent's set and shares its DOFs (primal assembly). The child's
    /// interface motion is extended inside it by static constraint modes
    /// (Craig-Bampton) unless its basis is Full.
    Boolean
  };
  Type type = Type::Node;
  std::string parentNodes;  ///< node set of the parent (Node: exactly one node)
  /// Node set of an elastic child moving rigidly with the attachment frame
  /// (RBE2-like; for a frame node, its six DOFs), or sharing the parent's
  /// DOFs (Boolean). Unused for R.
  std::string childNodes;
  /// The attachment point P (the rotor's centre for R). Default: the parent
  /// node (Node) or the centroid of the parent nodes (RigidFit).
  std::optional<fem::Vec3> point;
};

/// An axisymmetric rigid rotor about its spin axis (R).
struct RigidRotor {
  double mass = 0.0;
  double transverseInertia = 0.0;  ///< about axes through P normal to the spin axis
  double axialInertia = 0.0;       ///< about the spin axis (h = axialInertia * spin rate)
  /// false: a motor holds the relative spin rate (the angle is prescribed);
  /// true: the wheel turns freely on its bearing and its spin angle theta_R
  /// is a coordinate of q (the paper's q; a zero frequency of its own).
  bool spinCoordinate = false;
};

/// A steady spin. For C: the rotation of the structure's frame (axis through
/// `origin`). For A and R: the spin relative to the parent about `axis`
/// through the attachment point.
struct SpinRate {
  fem::Vec3 axis{0.0, 0.0, 1.0};
  fem::Vec3 origin{0.0, 0.0, 0.0};  ///< C only
  double rate = 0.0;                ///< nominal rad/s (a sweep scales it)
  /// A only: Rotating (the child's own spinning frame; its attachment must be
  /// immovable) or Stationary (axisymmetric rotor in the parent's frame).
  fem::SpinDefinition::Frame frame = fem::SpinDefinition::Frame::Rotating;
  bool stressStiffening = true;  ///< centrifugal prestress in rotating frames
};

/// Where a copy made by "Copies: N" sits (doc/theory.md §15): the prototype
/// (its first copy) turned by `angle` about `axis` through `origin`, the
/// spin axis of the copied substructure's parent.
struct CopyPlacement {
  std::string prototype;  ///< name of copy 1 of the same item (itself for copy 1)
  std::string group;      ///< the name as written ("blade" for "blade[3]")
  int index = 0;          ///< 0 .. count-1
  int count = 1;
  double angle = 0.0;     ///< rad, phase + 2 pi index / count
  fem::Vec3 axis{0, 0, 1}, origin{0, 0, 0};
  /// The model withCopies made (the prototype's turned): while the copy's
  /// model is still this one, the assembly turns the prototype's matrices
  /// instead of assembling the copy's (theory §15.2).
  std::shared_ptr<const fem::FiniteElementModel> model;
};

struct SubstructureSpec {
  std::string name;
  SubstructureKind kind = SubstructureKind::Elastic;
  std::string parent;  ///< empty for C
  Attachment attachment;
  /// Elastic kinds (C, E, A): the meshed model, in structure axes. Its own
  /// "Spin" must be unset: the structure sets it from the tree.
  std::shared_ptr<const fem::FiniteElementModel> model;
  RigidRotor rotor;             ///< R only
  std::optional<SpinRate> spin;  ///< C (frame), A and R (relative); none: not spinning
  /// "Reduction" parameters (reduction::validParameters()).
  Teuchos::ParameterList reduction = Teuchos::ParameterList("Reduction");
  /// "Copies: N": N identical copies in an azimuthal pattern about the
  /// parent's spin axis, the first at `copyPhase` (rad) from the item as
  /// written; its descendants are copied with it. Expanded by
  /// StructureDescription::withCopies.
  int copies = 1;
  double copyPhase = 0.0;
  /// The parent's node set of each copy ("Attachment/Copy Parent Nodes"),
  /// for a parent whose mesh has no node where the written set turns to (an
  /// unstructured hub); empty: found by turning.
  std::vector<std::string> copyParentNodes;
  /// Set on the items withCopies makes: which copy this is.
  std::optional<CopyPlacement> copy;
};

struct StructureDescription {
  std::vector<SubstructureSpec> substructures;
  /// C free-floating: its reference is this node set of C (one node with
  /// rotations, or three or more non-collinear nodes, of which six
  /// statically determinate DOFs are chosen). Empty: C is clamped by the
  /// supports of its model.
  std::string freeReference;

  /// Checks the tree (exactly one C, parents exist, no cycle, kinds and
  /// attachments consistent, rotors with positive inertia) and throws
  /// cms::InputError naming the substructure and what is wrong.
  void validate() const;
  /// Index of the named substructure, or -1.
  int find(const std::string& name) const;
  /// The description with every "Copies: N" item (and its descendants)
  /// replaced by N items named "<name>[1]" .. "<name>[N]", turned about the
  /// parent's spin axis (C: its Spin axis through its Origin; A, R: their
  /// spin axis through their attachment point), each attached to the
  /// parent's nodes found where the written attachment nodes turn to (a node
  /// set "<set>@<copy>" added to the parent's mesh). Throws cms::InputError
  /// naming the item: parent not spinning, no parent node at a turned
  /// position, a per-component item (support, spring, damper) the turn does
  /// not map onto itself. Identity when nothing is copied.
  StructureDescription withCopies() const;
};

}  // namespace cms::synthesis
