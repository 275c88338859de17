// One substructure as the synthesis layer sees it: distributed matrices per
// unit spin speed on one row map, and the table saying which node and
// component each row is (for attachments, interface DOFs and output). Built
// from a meshed FiniteElementModel (assembled in parallel) or from
// pre-assembled Matrix Market files with a sidecar (fem/MatrixSubstructureFile.hpp),
// and written back out in the same form.
//
//   K(Omega) = K + Omega^2 (KS1 - KT1),   G(Omega) = Omega G1      (theory §9)
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cms/core/TpetraTypes.hpp"
#include "cms/fem/FiniteElementAssembly.hpp"
#include "cms/fem/FiniteElementModel.hpp"
#include "cms/fem/RigidPlacement.hpp"

namespace Teuchos { template <class T> class Comm; }

namespace cms::substructure {

/// Which node and component each global row is; identical on every rank.
struct DofTable {
  std::vector<long long> nodeIds;            ///< mesh node tag / sidecar node id
  std::vector<double> coordinates;           ///< 3 per node
  std::vector<long long> offsets;            ///< rows of node i: offsets[i] .. offsets[i+1]-1
  std::vector<fem::Component> components;    ///< component of each row
  std::map<std::string, std::vector<std::int64_t>> nodeSets;  ///< name -> node indices

  long long rows() const { return offsets.empty() ? 0 : offsets.back(); }
  std::size_t nodes() const { return nodeIds.size(); }
  /// Row of (node, c), or -1 when the node has no such (free) component.
  long long row(std::int64_t node, fem::Component c) const;
  /// The node index of every row (the inverse of `offsets`).
  std::vector<std::int64_t> rowNodes() const;
};

struct GyroscopicMatrices {
  Teuchos::RCP<const CrsMatrix> M, G, K;
};

/// A substructure's matrices by name (theory §9): K2 = KS1 - KT1; N1 the
/// circulatory matrix per unit speed of a stationary-frame rotor's material
/// damping (theory §13.1).
enum class Matrix { M, K, G1, KT1, KS1, K2, D, N1 };
const char* toString(Matrix a);

class Substructure {
public:
  /// Assembles the model (collective); see fem::assemble for errors. The
  /// prestress conditions hold a child's attachment and add its children's
  /// reactions during the centrifugal prestress solve (theory §10.2).
  /// Given `stiffnessFactor`, the prestress solve's factorisation of K (with
  /// the held DOFs held) is handed over there for the reduction to reuse
  /// (null when there was none); otherwise it is freed here.
  static Substructure fromFiniteElementModel(const fem::FiniteElementModel& model,
                                             const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                             const fem::PrestressConditions& prestress = {},
                                             std::shared_ptr<const HeldFactor>* stiffnessFactor = nullptr);
  /// A copy made by "Copies: N" from its prototype, without assembling or
  /// solving anything (doc/theory.md §15.2): every matrix Q A Q^T, applied
  /// as such without being formed (matricesFormed() is false: apply(),
  /// frobeniusNorm(), or formed() for the matrices themselves), the
  /// centrifugal load and the prestress reactions Q f, Q turning each node's
  /// translations and rotations by `turn` (the copy's placement relative to
  /// the prototype's, about an axis through `origin`); the DOF table with
  /// the copy `model`'s coordinates and node tags, `spin` the copy's.
  /// Exact when the copy is the prototype turned about an axis its loads
  /// and supports respect, which the caller vouches for (the copy's model
  /// is the one StructureDescription::withCopies made). Returns nullopt
  /// with the reason in `why` (the caller then assembles the copy) when
  /// the copy's mesh or spin is not the prototype's turned, the prototype
  /// has a stationary rotor's tilt stiffness, or a node's rows are not
  /// whole on one rank. Collective; the same verdict on every rank.
  static std::optional<Substructure> turned(const Substructure& prototype, const fem::FiniteElementModel& model,
                                            const std::optional<fem::SpinDefinition>& spin,
                                            const fem::Rotation& turn, const fem::Vec3& origin, std::string& why);
  /// Reads a sidecar and its Matrix Market files (collective). Throws
  /// cms::InputError naming the file: unreadable or malformed matrix,
  /// dimensions that differ from the sidecar's DOF count, M or K missing,
  /// per-unit-speed matrices without a spin axis.
  static Substructure fromMatrixMarket(const std::string& sidecarPath,
                                       const Teuchos::RCP<const Teuchos::Comm<int>>& comm);
  /// Writes <directory>/<stem>.cms and <stem>_<matrix>.mtx for every matrix
  /// present (collective; rank 0 writes), stem = fileStem(), all or none:
  /// each to a temporary renamed when all are written. Throws
  /// cms::InputError if the directory cannot be written, or for a damped
  /// substructure (D or a modal ratio: the format has no record for them,
  /// and they were dropped without a word).
  void writeMatrixMarket(const std::string& directory) const;
  /// The name with every character but letters, digits, '-', '_' and '.'
  /// replaced by '_' (a file name without spaces, as the sidecar requires).
  std::string fileStem() const;

  const std::string& name() const { return name_; }
  Teuchos::RCP<const Map> map() const { return map_; }
  const DofTable& dofs() const { return dofs_; }
  /// The matrices themselves. A turned copy whose matrices are not formed
  /// (matricesFormed() false) has none to hand out: these throw
  /// std::logic_error there (apply() and frobeniusNorm() serve it).
  Teuchos::RCP<const CrsMatrix> M() const { return matrix(Matrix::M); }
  Teuchos::RCP<const CrsMatrix> K() const { return matrix(Matrix::K); }
  Teuchos::RCP<const CrsMatrix> G1() const { return matrix(Matrix::G1); }
  Teuchos::RCP<const CrsMatrix> KT1() const { return matrix(Matrix::KT1); }
  Teuchos::RCP<const CrsMatrix> KS1() const { return matrix(Matrix::KS1); }
  /// The matrix held for `a` (null: none), as the accessors above.
  Teuchos::RCP<const CrsMatrix> matrix(Matrix a) const;
  /// Whether it has matrix `a` (K2: KS1 or KT1; D: any damping).
  bool has(Matrix a) const;
  /// Y = alpha A X + beta Y for its matrix A (collective). A turned copy
  /// whose matrices are not formed applies Q A_p Q^T, its prototype's A_p
  /// between the turns of the rows (theory §15.2): the copy's matrices are
  /// never held. A missing matrix (has(a) false) is an error.
  void apply(Matrix a, const MultiVector& X, MultiVector& Y, double alpha = 1.0, double beta = 0.0) const;
  /// ||A||_F: a turned copy's is its prototype's (Q is orthogonal node by
  /// node; the same to rounding).
  double frobeniusNorm(Matrix a) const;
  /// False for a copy made by turned(), whose matrices are its
  /// prototype's turned and applied, not formed (theory §15.2).
  bool matricesFormed() const { return !prototype_; }
  /// This substructure with its matrices formed: a turned copy's Q A_p Q^T
  /// on the turned pattern (collective; its memory is a prototype's);
  /// otherwise a copy of this one (the matrices shared).
  Substructure formed() const;
  /// Stationary rotor in a spinning frame: tilt stiffness per unit
  /// Omega_frame * omega (fem::AssembledMatrices::KX1; null otherwise).
  Teuchos::RCP<const CrsMatrix> KX1() const { return KX1_; }
  /// Centrifugal load per unit Omega^2 (rotating frame; null otherwise).
  Teuchos::RCP<const MultiVector> f1() const { return f1_; }
  /// KS1 - KT1, the Omega^2 part of K(Omega) (null without either).
  Teuchos::RCP<const CrsMatrix> K2() const { return matrix(Matrix::K2); }
  /// Viscous damping, independent of speed: the model's dampers plus the
  /// Rayleigh part alpha M + beta K (K at rest; a stationary-frame rotor's
  /// beta on K_R, its frames and hinges only); null when there is none
  /// (theory §13.1). Not read from or written to Matrix Market files.
  Teuchos::RCP<const CrsMatrix> D() const { return matrix(Matrix::D); }
  /// A stationary-frame rotor with Rayleigh beta: its material damping
  /// beta K_R (frames and hinges) turns with it and adds the circulatory
  /// N = Omega N1 (skew; theory §13.1, fem::AssembledMatrices::N1); null
  /// otherwise.
  Teuchos::RCP<const CrsMatrix> N1() const { return matrix(Matrix::N1); }
  /// The model's modal damping ratio, applied by the synthesis in the
  /// reduced substructure's coordinates (0: none).
  double modalDampingRatio() const { return modalDampingRatio_; }
  /// The spin the per-unit-speed matrices refer to (none: not rotating).
  const std::optional<fem::SpinDefinition>& spin() const { return spin_; }
  /// The mass moving with a unit rigid translation along x of the rows,
  /// u^T M u: the total mass of an unsupported substructure; supports take
  /// away what sits on their fixed DOFs.
  double mass() const { return mass_; }
  /// The prestress holds' reactions per unit Omega^2 (fem::AssembledMatrices::reactions1).
  const std::vector<fem::PrestressConditions::NodalValue>& prestressReactions() const { return reactions1_; }

  /// This substructure whole on rank `owner`, its matrices on `self` (a
  /// communicator of that rank alone), for work that runs there while other
  /// ranks reduce other substructures (doc/architecture.md, "Parallelism").
  /// Collective over map()'s communicator; on the other ranks the result has
  /// no matrices. Carries the matrices a reduction reads (M, K, KT1) with
  /// the DOF table, name, spin and mass; not G1, KS1, KX1, f1, D. A turned
  /// copy's are formed first.
  Substructure gatheredTo(int owner, const Teuchos::RCP<const Teuchos::Comm<int>>& self) const;
  /// M, G(Omega), K(Omega) (theory §9); Omega = 0 gives G = 0 and K. New
  /// matrices are formed only when a speed-dependent term is present.
  GyroscopicMatrices atSpeed(double omega) const;

private:
  static double translationMass(const Substructure& s);
  void finishConstruction();  ///< K2_ and mass_ from the matrices
  /// Its own A, or (a turned copy) its prototype's A_p.
  Teuchos::RCP<const CrsMatrix> source(Matrix a) const;

  /// A turned copy's prototype matrices (shared with the prototype: no
  /// memory of their own) and the turn Q (theory §15.2).
  struct Prototype {
    Teuchos::RCP<const CrsMatrix> M, K, G1, KT1, KS1, K2, D, N1;
    fem::Rotation turn;
    /// Each local row's node triple as local rows (-1: a fixed component)
    /// and its place in it, when every triple is local and the matrices'
    /// domain and range are the rows (the assembly distributes whole nodes):
    /// the turns are then local passes; otherwise empty (turnedRows' import).
    std::vector<std::array<LocalOrdinal, 3>> triples;
    std::vector<std::int8_t> places;
  };
  std::shared_ptr<const Prototype> prototype_;

  std::string name_ = "substructure";
  Teuchos::RCP<const Map> map_;
  DofTable dofs_;
  Teuchos::RCP<const CrsMatrix> M_, K_, G1_, KT1_, KS1_;
  Teuchos::RCP<const CrsMatrix> K2_;  ///< KS1 - KT1 (null without either)
  Teuchos::RCP<const CrsMatrix> D_;   ///< viscous damping (null: none)
  Teuchos::RCP<const CrsMatrix> N1_;  ///< circulatory per unit speed (null: none)
  double modalDampingRatio_ = 0.0;
  Teuchos::RCP<const MultiVector> f1_;
  Teuchos::RCP<const CrsMatrix> KX1_;
  std::optional<fem::SpinDefinition> spin_;
  double mass_ = 0.0;
  std::vector<fem::PrestressConditions::NodalValue> reactions1_;
};

/// Q X: the rows of X (a substructure with DOF table `table`) with every
/// node's translations and rotations turned by `turn`, onto `toMap` (the
/// rows of a substructure with the same table: a copy). Collective.
Teuchos::RCP<MultiVector> turnedRows(const MultiVector& X, const DofTable& table, const Teuchos::RCP<const Map>& toMap,
                                     const fem::Rotation& turn);

}  // namespace cms::substructure
