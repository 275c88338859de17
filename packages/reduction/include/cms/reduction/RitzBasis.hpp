// A Ritz basis of one substructure (seed eq. (10), u = Phi eta): columns over
// its DOFs that vanish on its held DOFs (its attachment to the parent, or a
// free body's reference: the geometric boundary conditions of admissible
// vectors), M-orthonormalised in order, so that the first k columns of a
// longer basis span the k-column basis and the inclusion principle applies
// (doc/theory.md §11.3).
//
// Kinds ("Basis" of the "Reduction" parameters, validated against
// validParameters()):
//   Admissible      static deflections under load patterns, continued by
//                   load-dependent Ritz (Krylov) vectors K^-1 M x (Wilson):
//                   the paper's proposal, no eigenproblem solved
//   Polynomial      polynomial admissible functions along the substructure's
//                   axis, evaluated at the nodes (beam-like substructures)
//   Modes           the lowest eigenvectors with the held DOFs fixed and the
//                   children's attachments free (the "common practice")
//   Craig-Bampton   eigenvectors with the children's attachments fixed too,
//                   plus the static constraint modes of those interface DOFs
//   Guyan           the constraint modes only (static condensation)
//   Full            every non-held DOF: no truncation (the truth model)
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/core/TpetraTypes.hpp"
#include "cms/substructure/Substructure.hpp"

namespace cms::reduction {

class StaticCorrection;

/// Where a substructure meets the rest of the structure, as global rows of
/// its map (identical on every rank).
struct SubstructureBoundary {
  /// Held at zero in every basis vector: the attachment to the parent
  /// (its motion is the interface transform's rigid part) or a free
  /// body's statically determinate reference.
  std::vector<GlobalOrdinal> held;
  /// The rows its children attach to, per child: Craig-Bampton fixes them in
  /// its modes and adds their constraint modes.
  std::vector<std::vector<GlobalOrdinal>> interfaces;
  /// Per child, the generalised forces of its 6 attachment coordinates on
  /// these DOFs (the transpose of the interface transform): the
  /// "interfaces" load pattern of admissible vectors (attachment modes).
  std::vector<std::vector<std::vector<std::pair<GlobalOrdinal, double>>>> interfaceLoads;
  /// A factorisation of K with some rows held that another layer already
  /// made (the prestress solve's), which the basis adopts instead of
  /// factoring K again when its held rows are the same (theory §11.4);
  /// null: none.
  std::shared_ptr<const HeldFactor> stiffnessFactor;
  /// Set for a child held by supports or grounded springs of its own
  /// besides its attachment, which its caller moves rigidly about this
  /// point P: that rigid motion X strains it (K X != 0), so its constraint
  /// modes are X - K_h^-1 K X and every reduced basis adds the static
  /// correction K_h^-1 K X, a column per coordinate the supports resist
  /// (theory §11.2). Unset otherwise (K X = 0: nothing to add).
  std::optional<std::array<double, 3>> supportedAttachment;
};

/// The label prefix of those correction columns ("static: own supports
/// under the attachment's ux", ...).
inline constexpr const char* kOwnSupportsColumn = "static: own supports under the attachment's ";

/// The phrase a `dropped` entry carries when an Admissible basis left out
/// one of its children's attachment shapes (fewer vectors than shapes);
/// what cms modes counts them by.
inline constexpr const char* kAttachmentShapeLeftOut = "attachment shapes of the children";

struct RitzBasis {
  std::string kind;                   ///< as in the parameters
  bool full = false;                  ///< identity on every non-held row; `vectors` is null
  Teuchos::RCP<MultiVector> vectors;  ///< M-orthonormal columns, zero on held rows
  std::vector<std::string> labels;    ///< where each column came from
  /// Candidates dropped as (numerically) dependent on the previous columns,
  /// with their relative norm after projection: reported, never hidden.
  std::vector<std::string> dropped;
  double seconds = 0.0;
  /// Its held stiffness is the boundary's stiffnessFactor, adopted instead
  /// of factored (a cut-off's Sturm count, if any, is still its own).
  bool adoptedFactor = false;
  /// Anasazi's outcome for eigenvector bases ("" otherwise).
  std::string eigensolverReport;
  /// K with the attachment held, factored while the basis was built
  /// (admissible vectors), for the error estimates' flexibility (theory
  /// §11.8) instead of a second factorisation; null otherwise.
  std::shared_ptr<const StaticCorrection> flexibility;
  /// V^T K V and V^T M V (size() x size(), column-major) when the
  /// construction had K V and M V at hand (admissible vectors keep both for
  /// every column): estimateFrequencies then multiplies nothing. Empty
  /// otherwise.
  std::vector<double> projectedK, projectedM;

  int size() const;  ///< columns (full: the non-held DOF count)
};

/// Whether buildRitzBasis with these parameters would adopt
/// boundary.stiffnessFactor (theory §11.4): a basis that factors K with
/// the same rows held (Admissible, Modes, and Craig-Bampton or Guyan
/// without point interfaces), by CHOLMOD, and counts no cut-off first. The
/// caller frees the factor otherwise, before the basis factors its own.
/// False for parameters buildRitzBasis would refuse. Collective.
bool adoptsStiffnessFactor(const substructure::Substructure& s, const SubstructureBoundary& boundary,
                           const Teuchos::ParameterList& params);

/// "Reduction" parameters: Basis, Vectors, Load Patterns, Dependence Tolerance.
Teuchos::RCP<const Teuchos::ParameterList> validParameters();

/// Builds the basis the parameters ask for (collective). Throws
/// cms::InputError naming the key for bad parameters, and when more vectors
/// are asked than the substructure has free DOFs; cms::NumericalError when
/// K with the held DOFs fixed is not positive definite (the substructure
/// is not restrained by its supports and attachment).
RitzBasis buildRitzBasis(const substructure::Substructure& s, const SubstructureBoundary& boundary,
                         const Teuchos::ParameterList& params);

/// Appends the candidate columns to `basis` one by one, each M-orthogonalised
/// against those kept (classical Gram-Schmidt, twice), and keeps it only if
/// its M-norm after projection exceeds `tolerance` times its norm before;
/// stops at `maxColumns`. The order of the candidates is kept, so the span
/// of the first k columns never changes when more are added.
void appendOrthonormal(const CrsMatrix& M, const MultiVector& candidates, const std::vector<std::string>& labels,
                       double tolerance, int maxColumns, RitzBasis& basis);

/// Rayleigh-Ritz estimates of the substructure's lowest natural frequencies
/// (rad/s) at rest, with its held DOFs fixed, from its own basis (the paper's
/// truncation guide): eigenvalues of V^T K V against V^T M V = I.
std::vector<double> estimateFrequencies(const substructure::Substructure& s, const RitzBasis& basis);

}  // namespace cms::reduction
