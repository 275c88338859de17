// How good a reduced model is: its frequencies and mode shapes against the
// truth model of the same structure (every substructure with a Full basis),
// and the inclusion principle between two nested reductions (seed eqs.
// (28)-(29); doc/theory.md §6 and §11.7). Numbers are reported, never
// adjusted: a violation is a finding.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "cms/synthesis/SynthesizedStructure.hpp"

namespace cms::analysis {

struct ModeAccuracy {
  int index = 0;
  double omega = 0.0, truthOmega = 0.0;  ///< rad/s
  double relativeError = 0.0;            ///< (omega - truth) / truth (absolute / scale for rigid modes)
  /// Modal assurance criterion of the expanded physical shapes, against
  /// the span of the truth modes of the same frequency — within
  /// max(1e-6, 2 |relativeError|), since a repeated or close pair of a
  /// symmetric structure has no unique shape at that accuracy (all
  /// rigid-body zeros together): 1 = same shape.
  double mac = 0.0;
  bool rigid = false;      ///< a zero frequency of the truth (rigid-body motion)
  bool frameRate = false;  ///< rigid motion seen at a spin rate (synthesis::ModeCharacter::frameArtefact)
  /// The truth mode of this mode's shape (index into the truth's modes), -1
  /// when unmatched.
  int truthIndex = -1;
  /// No computed truth mode holds half of this shape (subspace MAC < 0.5):
  /// its partner lies above the truth modes computed, or the shape is not
  /// converged. truthOmega and relativeError are then against the nearest
  /// truth frequency, a pointer rather than this mode's error.
  bool unmatched = false;
};

struct TruthComparison {
  std::vector<ModeAccuracy> modes;
  double maxRelativeError = 0.0, meanRelativeError = 0.0;
  /// Smallest subspace MAC over the vibration modes (rigid and frame-rate
  /// modes excluded: their shapes are any combination of the rigid motions).
  double worstMac = 1.0;
  /// Truth modes that no reduced mode's shape took, below the highest truth
  /// cluster one did take: modes the reduced model lacks.
  int missingModes = 0;
  int unmatchedModes = 0;  ///< reduced modes flagged `unmatched`
};

/// What a table prints for a model's true error (cms compare, cms truncate
/// --truth): "MISSING n" where it lacks truth modes, else "UNMATCHED n"
/// where modes have no computed truth shape, else the largest error of the
/// modes paired (4 digits).
std::string trueErrorText(double maxRelativeError, int missingModes, int unmatchedModes);

/// Throws cms::InputError when `truth` left out a Modal Damping Ratio that
/// the reduced model of the same structure carries (it lives in reduced
/// coordinates only, theory §13.1): its modes would be those of a less
/// damped structure, and every difference a false error. Collective-free.
void requireComparableTruth(const synthesis::SynthesizedStructure& truth);

/// `solve` (the structure's "Solve" parameters) for a model whose modes are
/// to be paired with another's (compareWithTruth): "Number of Modes" n
/// raised to n + max(2, ceil(n/4)), at most `size` (the model's
/// coordinates).
Teuchos::ParameterList comparedSolveParameters(const Teuchos::ParameterList& solve, long long size);

/// `model` solved at `speeds` with comparedSolveParameters(solve), or, where
/// that does not converge (a sparse solve asked for more modes), with
/// `solve` itself: the extra modes serve the pairing, never the verdict.
/// Collective.
synthesis::StructureModes solveForComparison(const synthesis::SynthesizedStructure& model,
                                             const std::vector<double>& speeds, const Teuchos::ParameterList& solve);

/// The lowest `count` reduced modes, each paired with the truth mode of its
/// shape, not of its index (a reduced model lacking a mode, or two modes in
/// the other order, made every later pair wrong and its error a false
/// number, found by a review): each reduced mode goes to the cluster of
/// truth modes (rigid zeros together; eigenvalues within 1e-3) holding
/// most of its shape (subspace MAC of the expanded physical shapes, at
/// least 0.5; else the truth modes within 10% together), best pairs first,
/// one truth mode each; theory §11.7. Both must have at least `count`
/// modes (cms::InputError otherwise); both should have more
/// (comparedSolveParameters): every reduced mode given takes its partner,
/// so that two modes in the other order at the edge of the range are not
/// read as a missing one, and a reduced mode whose partner lies above the
/// truth's `count`-th is still paired. The two structures must come from
/// the same AssembledStructure. Collective.
TruthComparison compareWithTruth(const synthesis::SynthesizedStructure& reduced,
                                 const synthesis::StructureModes& reducedModes,
                                 const synthesis::SynthesizedStructure& truth,
                                 const synthesis::StructureModes& truthModes, int count);

struct InclusionViolation {
  int index = 0;  ///< r (0-based)
  std::string inequality;  ///< which of fine[r] <= coarse[r] <= fine[r+k] failed
  double amount = 0.0;     ///< by how much, relative to coarse[r]
};

/// Checks fine[r] <= coarse[r] (1 + relTol) and coarse[r] <= fine[r+k] (1 + relTol)
/// for every r where both sides were computed (ascending frequencies of the
/// coarse model and of a model whose basis contains it plus k more
/// coordinates; k = 1 is seed eqs. (28)-(29), larger k the same minimax
/// argument applied k times). Meaningful only when K > 0 at that speed (the
/// hyperbolic case, theory §6); the caller decides.
std::vector<InclusionViolation> checkInclusion(const std::vector<double>& coarse, const std::vector<double>& fine,
                                               double relTol = 1e-9, int added = 1);

/// The same check between two solved nested models, each frequency with
/// its own round-off threshold derived from its solve (theory §11.7):
/// a normwise backward error (residual) eta moves a frequency by about
/// kappa eta, kappa = (scale / omega)^2 with the mode's componentwise
/// frequency scale (eigen::GyroscopicMode::scale, >= omega); a pair is a
/// finding only when its difference exceeds the sum of the two thresholds,
/// each at least 10 eta kappa and 100 eps kappa. Meaningful only for K > 0.
std::vector<InclusionViolation> checkInclusion(const synthesis::StructureModes& coarse,
                                               const synthesis::StructureModes& fine, int added);

/// Reduced eigenvalues paired one to one with truth eigenvalues (or their
/// conjugates), nearest pairs first, where no mode order or shape can be
/// compared alike (the periodic structure's fixed-frame modes, theory
/// §16.8). Each reduced eigenvalue gets its partner's relative distance
/// (infinity when the truth has none left); `missing` counts the truth
/// eigenvalues no reduced one took whose |lambda| is at most the largest
/// reduced |lambda|: modes the reduced model lacks in its range.
struct EigenvaluePairing {
  std::vector<double> relativeErrors;
  int missing = 0;
};
EigenvaluePairing pairEigenvalues(const std::vector<std::complex<double>>& reduced,
                                  const std::vector<std::complex<double>>& truth);

/// omega of each mode, ascending (as returned by the solvers).
std::vector<double> frequencies(const synthesis::StructureModes& modes);

/// The truth model's frequencies below omega (rad/s) at `speeds`, counted
/// by a Sturm sequence: the inertia of the Hermitian K - omega^2 M +
/// i omega G of the structure with every basis Full (one sparse LDL^T of
/// the assembled model, eigen::sturmCount; doc/theory.md §11.9). Valid when
/// K >= 0 (a gyroscopically stable structure); a pivot zero to rounding
/// (omega is a frequency) retakes it 1e-8 off omega, and -1 comes back when
/// that fails too; -3 for a damped structure, whose damped frequencies the
/// count of undamped ones does not bound (not counted); -4 when K(Omega) is
/// not positive semidefinite (an eigenvalue of (K, M) below -1e-4 omega^2:
/// a free body spinning, a rotor past divergence), where the inertia is no
/// count of frequencies (not counted). Collective.
long long truthFrequenciesBelow(const synthesis::AssembledStructure& structure, const std::vector<double>& speeds,
                                double omega);
/// The same count on a truth already synthesised (every basis Full).
long long truthFrequenciesBelow(const synthesis::SynthesizedStructure& truth, const std::vector<double>& speeds,
                                double omega);
/// Why truthFrequenciesBelow made no count, for its codes -1, -3 and -4 (the
/// one text the console and the JSON give); empty for a count (>= 0) or -2.
std::string truthCountNote(long long code);

}  // namespace cms::analysis
