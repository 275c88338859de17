// The modal analysis of a structure at its speeds, as `cms modes` runs it
// (doc/user-guide.md, "cms modes"), in the Anasazi style: a problem (the
// structure, its speeds and the solve parameters), a study with validated
// options, and a result that holds everything the run found, with its
// accuracy: each mode's residual, error estimate (theory §11.8), the
// missing-mode coverage of each substructure (§11.9) and, on request, the
// true error against the truth model and the truth's Sturm count.
//
// The phases, in the order they run (ModalAnalysis::run):
//   1. assemble the substructures (synthesis::AssembledStructure);
//   2. with "Target Accuracy", enrich the bases until every wanted mode's
//      estimate meets it (analysis::enrichToAccuracy, §11.10);
//   3. reduce and couple (synthesis::SynthesizedStructure), refuse massless
//      DOFs kept as coordinates (checkMass);
//   4. solve (the eigen layer picks the formulation), then tell apart what
//      each zero frequency means (checkZeroFrequencies, §4.3);
//   5. judge the accuracy: share of each substructure, error estimates,
//      coverage, optionally the truth (--truth) and its count (--check-count);
//   6. whirl of each spinning substructure in each mode.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/analysis/Enrichment.hpp"
#include "cms/analysis/PeriodicStructure.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace cms::analysis {

/// What one run of ModalAnalysis found (rank 0 holds the whole of it; the
/// other ranks hold the same numbers, the expansions are collective).
struct ModalResult {
  std::optional<synthesis::AssembledStructure> structure;
  std::optional<synthesis::SynthesizedStructure> reduced;
  std::vector<double> speeds;  ///< rad/s, one per speed parameter
  synthesis::StructureModes modes;
  std::vector<synthesis::ModeCharacter> character;
  std::vector<double> estimates;   ///< relative frequency error per mode (theory §11.8); < 0: none
  /// Per mode the estimate with, where the structure is SPD (at rest,
  /// clamped), its rigorous bound (synthesis::ModeAccuracy, theory §11.8).
  std::vector<synthesis::ModeAccuracy> accuracy;
  /// |relative error| against the truth mode of each mode's shape ("Truth"
  /// only); NaN where no computed truth mode has its shape.
  std::vector<double> trueErrors;
  /// Truth modes within the reduced modes' range that none of them pairs
  /// with (by shape, compareWithTruth; by eigenvalue on the periodic path;
  /// -1: not compared).
  int truthMissing = -1;
  /// Reduced modes of no computed truth mode's shape (compareWithTruth; -1:
  /// not compared).
  int truthUnmatched = -1;
  std::vector<synthesis::SubstructureCoverage> coverage;  ///< at `cutoff` (theory §11.9)
  double cutoff = 0.0;             ///< rad/s: the highest frequency found
  long long truthCount = -2;       ///< truth frequencies below countAt; -1 unreliable, -2 not asked, -3 damped, -4 K(Omega) indefinite (not countable: truthFrequenciesBelow)
  long long reducedCount = 0;      ///< reduced frequencies below countAt (1 + countBand)
  double countAt = 0.0;            ///< rad/s
  /// Relative band above countAt where a reduced frequency still counts:
  /// the partner, from above, of a truth mode just below (the coverage's
  /// band, theory §11.9).
  double countBand = 0.0;
  std::vector<std::vector<std::string>> whirls;  ///< per mode: "<substructure> FW|BW|-"
  Enrichment enrichment;           ///< "Target Accuracy": the steps and whether it was reached
  double assemblySeconds = 0.0, reductionSeconds = 0.0;
  double accuracySeconds = 0.0;    ///< error estimates, bounds and coverage (step 5, without the truth)
  double estimateSeconds = 0.0;    ///< of which the estimates and bounds
  /// A rotor on a moving attachment (theory §16.8): how its fixed-frame
  /// modes were found (multi-blade or Floquet). Its modes have no error
  /// estimates (the residual test of §11.8 is for constant coefficients)
  /// and no whirl labels (their motion is the fixed frame's).
  std::optional<PeriodicModes> periodic;
};

class ModalAnalysis {
public:
  /// "Speed Factor" (double, 1): every nominal spin rate times it;
  /// "Target Accuracy" (double, 0 = the scene's bases as given);
  /// "Truth" (bool, false): also solve the truth model, true error per mode;
  /// "Check Count" (bool, false): the truth's Sturm count at the highest
  /// frequency found (one factorisation of the assembled model).
  static Teuchos::RCP<const Teuchos::ParameterList> validParameters();

  /// `solve` is the "Solve" list of synthesis::SynthesizedStructure::solve;
  /// `options` is validated against validParameters() (cms::InputError
  /// naming the key otherwise).
  ModalAnalysis(synthesis::StructureDescription description, Teuchos::ParameterList solve,
                const Teuchos::ParameterList& options);

  /// A line as each long phase starts (large models: nobody waits in silence).
  void setProgress(std::function<void(const std::string&)> progress) { progress_ = std::move(progress); }

  /// Runs phases 1-6. Throws cms::InputError / NumericalError for what
  /// checkMass and checkZeroFrequencies refuse; a solve that did not
  /// converge is a status in result.modes, not an exception. When "Target
  /// Accuracy" is not reached the result holds no modes and
  /// result.enrichment.reached is false. Collective.
  ModalResult run(const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const;

private:
  /// Steps 4-6 for a rotor on a moving attachment (theory §16.8).
  ModalResult& runPeriodic(ModalResult& r) const;
  synthesis::StructureDescription description_;
  Teuchos::ParameterList solve_, options_;
  std::function<void(const std::string&)> progress_;
};

/// Whirl of spinning substructure k in mode `mode` alone, from its expanded
/// shape u (synthesis::SynthesizedStructure::expand), by the one rule
/// (analysis::WhirlClassification, theory §12.2) applied to this mode as a
/// cluster of one: "FW" when the orbit of its transverse motion turns with
/// the spin, "BW" against it, "-" when the orbit is flat or the motion
/// mostly axial or torsional, "" when k does not spin. For the modes of a
/// solve use WhirlClassification::classify, which classifies a degenerate
/// cluster whole (the same at every rank count). Collective.
std::string substructureWhirl(const synthesis::AssembledStructure& structure,
                              const std::vector<Teuchos::RCP<MultiVector>>& u, std::size_t k,
                              const eigen::GyroscopicMode& mode);

}  // namespace cms::analysis
