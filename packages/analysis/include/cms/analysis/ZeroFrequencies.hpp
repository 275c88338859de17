// What a zero frequency means (doc/theory.md §4.3). A structure has as many
// zero frequencies as rigid-body motions: six when C floats, one per
// free-turning wheel. More zeros than that have four causes that need four
// different answers, and a tool that calls them all "K is singular" sends
// its user the wrong way:
//   - a critical speed: K(Omega) is singular at this speed but not at rest.
//     That is an answer (the edge of a divergence band), reported with
//     Stability::Critical, never refused; inside the band, where K(Omega)'s
//     count of negative eigenvalues is odd (det K < 0), the zero is a real
//     root lambda > 0 the zero tests could not tell from zero, reported
//     with Stability::Divergence (theory §4.3);
//   - an unrestrained substructure: zero at rest too, and the mode moves some
//     substructure rigidly. Bad input (exit 2), naming it and its free motion;
//   - an ill-conditioned stiffness: zero at rest too, but the mode deforms a
//     substructure (a stiff part 1e8 times stiffer than the soft one it
//     loads puts the soft part's frequencies below what rounding of the
//     assembled K can resolve). Numerical breakdown (exit 3) with the
//     condition estimate and what to do;
//   - a singular mass: DOFs without mass kept as coordinates (a Full basis):
//     bad input naming the substructure, node and component (checkMass).
#pragma once

#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/core/DenseMatrix.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace cms::analysis {

/// The inertia of a stiffness K(speeds) (SpeedSweepProblem::stiffnessCount).
struct StiffnessCount {
  long long negative = -1;  ///< negative eigenvalues; -1: not counted
  bool available = true;    ///< false: the model gives no count at any speed
  std::string why;          ///< why not counted
  /// A circulatory stiffness N acts at these speeds: the count's parity
  /// then proves nothing (an odd count proves divergence only where the
  /// characteristic polynomial at 0 is det K, theory §12.1).
  bool circulatory = false;
  /// Scaled by the magnitudes of K's parts (GyroscopicSystem::KMagnitude),
  /// so that a pivot zero to their rounding is refused even where K's own
  /// diagonal has cancelled; false: by K's own diagonal.
  bool againstParts = false;
  /// Pivots within rounding of zero (the dense count: counted neither
  /// way; the sparse count refuses them, `negative` -1).
  long long tinyPivots = 0;
};

/// K's negative eigenvalues by a dense Bunch-Kaufman L D L^T of S K S (S =
/// |diag K|^-1/2, or diag(R)^-1/2 with the magnitudes R of K's parts where
/// given, n x n); a pivot within 1e-13 of its scaled row is not counted
/// (`negative` -1 with `why`).
StiffnessCount denseStiffnessCount(const DenseMatrix& K, const DenseMatrix* R = nullptr);

/// The same for the synthesised K(speeds): dense up to `denseLimit`
/// coordinates, else the sparse inertia (cms::inertia, no pivoting: a
/// pivot zero to rounding refuses the count). Not for a free body (its K
/// is singular at every speed): the caller's to exclude. Collective.
StiffnessCount stiffnessCount(const synthesis::SynthesizedStructure& reduced, const std::vector<double>& speeds,
                              int denseLimit);

/// How many zero frequencies the structure has by construction: six if C
/// floats, plus one per rigid rotor whose spin angle is a coordinate.
int rigidBodyMotions(const synthesis::AssembledStructure& structure);

struct ZeroFrequencyReport {
  int expected = 0;  ///< rigidBodyMotions()
  int zeros = 0;     ///< modes found rigid (before relabelling)
  int critical = 0;  ///< of these, relabelled Stability::Critical
  /// Of these, relabelled Stability::Divergence: inside a divergence band,
  /// where K(Omega)'s count of negative eigenvalues is odd (det K < 0: a
  /// real root lambda > 0) and the root was below the zero tests' reach.
  int divergent = 0;
};

/// Checks the zero frequencies of `modes` (solved at modes.speeds with
/// `solveParams`) against the structure's rigid-body motions and acts as
/// the header says: relabels critical-speed zeros, or throws cms::InputError
/// (unrestrained; the message starts with "unrestrained") or
/// cms::NumericalError (ill-conditioned, with the condition estimate).
/// Collective: may solve once more at rest and expand modes.
ZeroFrequencyReport checkZeroFrequencies(const synthesis::AssembledStructure& structure,
                                         const synthesis::SynthesizedStructure& reduced,
                                         synthesis::StructureModes& modes,
                                         const Teuchos::ParameterList& solveParams);

/// Refuses (cms::InputError naming the substructure, node and component) a
/// substructure kept with a Full basis that has a free DOF without mass: its
/// M diagonal below 1e3 eps of the substructure's mass (translations) or of
/// mass x size^2 (rotations). Such a DOF makes the structure's M singular;
/// a reduced basis condenses it statically and is the remedy. Collective.
void checkMass(const synthesis::AssembledStructure& structure, const synthesis::SynthesizedStructure& reduced);

}  // namespace cms::analysis
