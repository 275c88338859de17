// The description of one meshed substructure, everything its matrices need:
// the mesh, which physical groups are element sets (solid or frame, with
// material and section), lumped items (point masses, springs), fixed DOFs by
// node set, and the spin of its frame. Built in code or from a Teuchos
// ParameterList (a scene's "Finite Element Model" sublist, doc/user-guide.md)
// validated against validParameters(), as Anasazi and Belos solver managers do.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/fem/ElementMatrix.hpp"
#include "cms/fem/MatrixSubstructureFile.hpp"
#include "cms/fem/SolidElement.hpp"
#include "cms/mesh/Mesh.hpp"

namespace cms::fem {

// The mesh types a model holds, also under the names they had while the
// readers lived in fem (before packages/mesh, issue 17), for callers not
// yet moved to cms::mesh.
using mesh::CellType;
using mesh::Mesh;

struct ElementSet {
  enum class Kind { Solid, Frame };
  std::string group;     ///< physical group of the mesh
  Kind kind = Kind::Solid;
  std::string material;  ///< key into FiniteElementModel::materials
  BeamSection section;   ///< Frame only
  BeamTheory theory = BeamTheory::EulerBernoulli;
  /// Solid only: the element of the cell shapes that have a choice ("Hex8":
  /// Full or Incompatible, "Hex20": Full or Reduced). Unset: the mesh block's
  /// element name decides (an .inp deck's C3D8I or C3D8R: Incompatible,
  /// C3D20R: Reduced), else Full.
  std::optional<SolidType> hex8, hex20;
};

/// The element that an element set's cells of block b get (Solid sets):
/// Tet4, Tet10, Wedge15 as they are, Hex8 and Hex20 by the set's choice
/// (ElementSet::hex8, hex20). Throws cms::InputError for any other cell type.
SolidType solidTypeOf(const ElementSet& set, const mesh::CellBlock& b);

struct PointMassSet {
  std::string name, nodeSet;  ///< one point mass at every node of the set
  double mass = 0.0;
  std::array<double, 6> inertia{};  ///< Jxx Jyy Jzz Jxy Jyz Jxz about the node
};

/// Springs and viscous dampers (a scene's "Springs" and "Dampers"): one item
/// at each node of the set, grounded or to the coincident node of another
/// set, with a stiffness, a damping coefficient, or both (a bearing).
struct SpringSet {
  std::string name, nodeSet;
  std::string toNodeSet;  ///< empty: grounded; else nodes paired by coincident coordinates
  std::array<double, 6> stiffness{};
  /// Viscous damping cx cy cz crx cry crz (N s/m, N m s/rad), into D (theory §13.1).
  std::array<double, 6> damping{};
};

/// A blade hinge (a scene's "Hinges", theory §17): a zero-length joint
/// between the coincident nodes of two node sets of frame nodes, rigid in
/// the translations and in the two rotations normal to `axis`, free in the
/// rotation about it, with an optional rotational spring and viscous damper
/// about the axis. An exact constraint, not a penalty: the assembly
/// eliminates the second node's dependent DOFs (u = T u_free), keeping of
/// that node only its rotation about the coordinate axis closest to `axis`.
struct HingeSet {
  std::string name;
  std::string nodeSet;    ///< the first (master) nodes: they keep all their DOFs
  std::string toNodeSet;  ///< the second nodes, paired by coincident coordinates; one DOF each remains
  Vec3 axis{0.0, 0.0, 1.0};  ///< the hinge axis, normalised by the reader (any direction)
  double stiffness = 0.0;    ///< rotational spring about the axis (N m/rad)
  double damping = 0.0;      ///< viscous damper about the axis (N m s/rad), into D
};

/// One "Hinges" entry (keys Node Set, To Node Set, Axis, Stiffness, Damping),
/// validated; `path` names it in messages (cms::InputError). Also used by
/// the scene's built-in Beam, whose hinges name stations instead of sets.
HingeSet hingeFromParameters(const std::string& name, const Teuchos::ParameterList& p, const std::string& path);

/// Damping of the whole substructure (a scene's "Structural Damping"):
/// Rayleigh D = alpha M + beta K (K at rest), and a modal damping ratio that
/// the synthesis applies in a reduced substructure's own coordinates
/// (theory §13.1; refused for a Full basis).
struct StructuralDamping {
  double alpha = 0.0;       ///< mass-proportional (1/s)
  double beta = 0.0;        ///< stiffness-proportional (s)
  double modalRatio = 0.0;  ///< zeta of every mode of the substructure's reduced model
  bool any() const { return alpha != 0.0 || beta != 0.0 || modalRatio != 0.0; }
};

struct FixedSet {
  std::string name, nodeSet;
  std::vector<Component> components;  ///< all six for "all" (absent ones skipped)
  bool all = false;
};

/// The steady spin of the substructure's frame (doc/theory.md §9).
struct SpinDefinition {
  enum class Frame {
    Rotating,   ///< displacements in the spinning frame: G1, KT1, f1, KS1
    Stationary  ///< axisymmetric rotor about its own axis: polar-inertia G1 only
  };
  Spin spin;    ///< unit axis and origin
  Frame frame = Frame::Rotating;
  bool stressStiffening = true;  ///< Rotating only: assemble KS1 from the centrifugal prestress
  /// Stationary only: the axis of a spinning frame that carries the rotor;
  /// then KX1, the tilt stiffness per unit Omega_frame * omega, is assembled
  /// too (theory §11.5).
  std::optional<Vec3> frameAxis;
};

struct FiniteElementModel {
  std::string name = "substructure";
  std::shared_ptr<const mesh::Mesh> mesh;
  std::map<std::string, IsotropicMaterial> materials;
  std::vector<ElementSet> elementSets;
  std::vector<PointMassSet> pointMasses;
  std::vector<SpringSet> springs;  ///< springs, and the dampers (stiffness 0)
  std::vector<HingeSet> hinges;    ///< exact hinge constraints (theory §17)
  std::vector<FixedSet> fixed;
  StructuralDamping damping;
  std::optional<SpinDefinition> spin;  ///< none: a non-rotating substructure

  /// Every key with its type, default and a one-line description.
  static Teuchos::RCP<const Teuchos::ParameterList> validParameters();
  /// Reads and validates `params` (unknown keys, wrong types, bad values:
  /// cms::InputError naming the key path) and the mesh it names ("Mesh",
  /// resolved against baseDir when relative).
  /// `readMesh` reads it (mesh::readMesh when empty): the scene passes the
  /// meshes it made ahead (mesh/ScriptMeshes.hpp).
  using MeshReader = std::function<mesh::Mesh(const std::string& path, const std::map<std::string, double>& parameters)>;
  /// The mesh file `params` names ("Mesh", resolved against baseDir when
  /// relative) and its "Mesh Parameters", as fromParameters reads them (the
  /// same cms::InputError for a bad one): the scene asks for its scripts
  /// ahead with these, so that each is taken, not meshed again.
  struct MeshSource {
    std::string file;
    std::map<std::string, double> parameters;
  };
  static MeshSource meshSource(const Teuchos::ParameterList& params, const std::string& baseDir);
  static FiniteElementModel fromParameters(const Teuchos::ParameterList& params,
                                           const std::string& baseDir = ".", const MeshReader& readMesh = {});
  /// Checks the model against its mesh: element sets name existing groups of
  /// supported cell types (Solid: Tet4, Tet10, Hex8, Hex20, Wedge15; Frame: Line2), materials
  /// exist and are valid, node sets exist. Throws cms::InputError.
  void validate() const;
};

}  // namespace cms::fem
