// Whirl: whether a mode's orbit turns with the spin (forward), against it
// (backward), not at all (neutral), or cannot be told (unresolved). The one
// rule of the project (doc/theory.md §12.2), used by `cms modes`, `cms
// campbell` and the `campbell` driver.
//
// A mode x(t) = Re(a e^{i omega t}) of a spinning part is sampled at points
// (nodes of an elastic rotor, the tilts of a rigid one, coordinate pairs of a
// dense model): at each, its complex amplitudes a1, a2 along two transverse
// directions e1, e2 (e1 x e2 = n, the spin axis) and a3 along n. Three
// Hermitian forms measure the motion of any combination z of the modes of a
// cluster (z^H F z):
//
//   circulation  C_ij = sum (conj(a2_i) a1_j - conj(a1_i) a2_j) / (2 i)
//                (C_ii = sum Im(a1 conj(a2)): the orbit's mean angular
//                 momentum about n, per unit omega)
//   transverse   P_ij = sum conj(a1_i) a1_j + conj(a2_i) a2_j
//   total        N_ij = P_ij + sum conj(a3_i) a3_j
//
// Modes whose frequencies agree to "Cluster Tolerance" are one cluster: in a
// (nearly) degenerate cluster every combination is as much a mode as the
// solver's basis vectors, which are arbitrary (they differ between rank
// counts). The cluster is classified as a whole, from the eigenvalues of the
// pencils (2C, N) (circularity, in [-1, 1]) and (P, N) (transverse share, in
// [0, 1]), which no change of the cluster's basis alters:
//   neutral     the part takes no part in the cluster (its motion below
//               "Participation" of its largest in these modes: rounding), or
//               no combination has a transverse share above "Transverse
//               Share" (axial or torsional motion), or no circularity beyond
//               "Circularity" times that share (flat orbits); zero-frequency
//               modes (no orbit)
//   forward     some combination circulates with the spin, none against it
//   backward    some against, none with
//   unresolved  both senses in one cluster (a double frequency at rest, or a
//               forward and a backward mode that coincide), or the part does
//               not spin at this speed: the sense is not a property of the
//               modes the solver returned
#pragma once

#include <complex>
#include <string>
#include <utility>
#include <vector>

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include "cms/core/TpetraTypes.hpp"
#include "cms/eigen/GyroscopicModes.hpp"

namespace Teuchos { template <class T> class Comm; }
namespace cms::synthesis { class AssembledStructure; class SynthesizedStructure; struct StructureModes; }

namespace cms::analysis {

enum class Whirl { Forward, Backward, Neutral, Unresolved };
/// "FW", "BW", "-", "unresolved".
const char* toString(Whirl w);

/// One mode's motion as the whirl rule sees it: this rank's sample points,
/// the amplitudes along e1, e2 (transverse, e1 x e2 = n) and n. A mode
/// reported with omega < 0 is conjugated first (its orbit turns the other way).
struct Orbit {
  std::vector<std::complex<double>> a1, a2, a3;
};

/// Orbit of a dense mode from coordinate pairs (v, w): e1 = v, e2 = w, no axial part.
Orbit orbitOfPairs(const eigen::GyroscopicMode& mode, const std::vector<std::pair<int, int>>& pairs);

/// Orbit of substructure k in a mode expanded by SynthesizedStructure::expand
/// (u[k]: its rows, real and imaginary part): an elastic part's node
/// translations, a rigid rotor's rotations, about its spin axis.
Orbit orbitOfSubstructure(const synthesis::AssembledStructure& structure, const std::vector<Teuchos::RCP<MultiVector>>& u,
                          std::size_t k, const eigen::GyroscopicMode& mode);

class WhirlClassification {
public:
  /// "Cluster Tolerance" (1e-3): relative frequency difference within which
  ///   modes are one cluster; above the splitting rounding gives a defective
  ///   cluster (measured 6e-5 across rank counts, theory §11.6).
  /// "Transverse Share" (0.1): below it a motion is axial/torsional: neutral.
  /// "Circularity" (1e-2): below it, times the transverse share, an orbit is flat.
  /// "Participation" (1e-6): a mode (cluster) in which the part moves less
  ///   than this fraction (amplitude) of its largest motion over the modes
  ///   classified together is neutral: the part takes no part, its orbit is
  ///   rounding (which differs between rank counts).
  static Teuchos::RCP<const Teuchos::ParameterList> getValidParameters();
  explicit WhirlClassification(const Teuchos::ParameterList& params = Teuchos::ParameterList());

  /// Index lists of the clusters of `modes` (ascending frequency; chained:
  /// neighbours within the tolerance). Zero-frequency modes are singletons.
  std::vector<std::vector<int>> clusters(const std::vector<eigen::GyroscopicMode>& modes) const;

  /// Whirl of every mode; orbits[i] belongs to modes[i] (same sample points
  /// for all). `spinSign`: +1 spin about +n, -1 about -n, 0 not spinning
  /// (every oscillating mode unresolved). Collective over `comm` (null: one
  /// process) when the orbits are distributed.
  /// `forwardShare`, when given, gets per mode its orbit's forward part
  /// (1 + c) / 2 for c the most forward circularity of its cluster (with the
  /// spin): 1 a forward circle, 0 a backward one, between for an ellipse
  /// (anisotropy); 0 for a neutral or zero-frequency mode.
  std::vector<Whirl> classify(const std::vector<eigen::GyroscopicMode>& modes, const std::vector<Orbit>& orbits,
                              double spinSign, const Teuchos::Comm<int>* comm = nullptr,
                              std::vector<double>* forwardShare = nullptr) const;

  /// Whirl of substructure k (a spinning A or R) in every mode of `modes`,
  /// relative to its spin. Collective.
  std::vector<Whirl> classify(const synthesis::AssembledStructure& structure,
                              const synthesis::SynthesizedStructure& reduced, const synthesis::StructureModes& modes,
                              std::size_t k, double spinRate, std::vector<double>* forwardShare = nullptr) const;

private:
  double clusterTolerance_, transverseShare_, circularity_, participation_;
  Whirl classifyCluster(const std::vector<int>& members, const std::vector<Orbit>& orbits, double largest,
                        const Teuchos::Comm<int>* comm, std::pair<double, double>* circularities = nullptr) const;
};

}  // namespace cms::analysis
