// Which reduction to choose (doc/user-guide.md, "cms compare"): the same
// structure reduced by every strategy — Guyan, and Admissible, Modes and
// Craig-Bampton bases at several vector counts per substructure — each
// against the truth model (every basis Full): reduced size, times, peak
// memory, frequency errors (true and estimated, theory §11.8) and the
// subspace MAC of the vibration modes. A strategy whose solve fails is a
// finding of the comparison (its status and reason), not a row.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/analysis/TruthComparison.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace cms::analysis {

struct StrategyRow {
  std::string basis;
  int vectors = 0;        ///< per substructure (0 for Guyan)
  long long dofs = 0;     ///< reduced coordinates
  /// Wall seconds of the synthesis (bases, interface transforms and
  /// projections), of which `basesSeconds` the bases
  /// (SynthesizedStructure::basesSeconds), and of the solve.
  double reduceSeconds = 0.0, basesSeconds = 0.0, solveSeconds = 0.0;
  double peakMiB = 0.0;   ///< this rank's peak resident memory so far (cms::peakRssMiB)
  bool compared = true;   ///< false without a truth: `accuracy` is empty
  TruthComparison accuracy;
  double estimate = 0.0;  ///< largest estimated relative error of the compared modes ("Error Estimates")
  /// Wall seconds of those estimates (SynthesizedStructure::errorEstimates:
  /// the flexibilities' factorisations not kept from the prestress solves,
  /// the residuals and their solves); 0 without "Error Estimates".
  double estimateSeconds = 0.0;
  std::vector<int> perSubstructure;  ///< coordinates of each substructure
  /// The substructures whose basis adopted the prestress solve's
  /// factorisation (SubstructureReduction::adoptedPrestressFactor).
  std::vector<std::string> adopted;
  std::string path;       ///< the solve path (synthesis::StructureModes::path)
  std::vector<double> hz;  ///< the frequencies solved, ascending (Hz)
};

/// A strategy that did not give a row: skipped (too few coordinates or
/// modes, bad input such as more Craig-Bampton modes than DOFs) or failed
/// (its solve did not converge or broke down, or a NumericalError ended it:
/// `status` says which).
struct StrategyOutcome {
  std::string basis;
  int vectors = 0;
  bool failed = false;
  eigen::SolveStatus status = eigen::SolveStatus::Converged;
  std::string why;
  long long dofs = 0;  ///< reduced coordinates, when the synthesis got that far
};

struct ComparisonResult {
  long long truthSize = 0;
  double truthSeconds = 0.0;
  synthesis::StructureModes truthModes;  ///< its status decides whether anything was compared
  std::vector<StrategyRow> rows;
  std::vector<StrategyOutcome> others;   ///< skipped and failed strategies, in order
};

/// A truth the caller synthesised and solved itself (bench_rotor times and
/// factors it apart); `model` null: no truth, the rows carry no accuracy.
struct SolvedTruth {
  const synthesis::SynthesizedStructure* model = nullptr;
  const synthesis::StructureModes* modes = nullptr;  ///< at least "Number of Modes" of them
  double seconds = 0.0;
};

/// What a caller sees of the run as it goes: `onStart` before each
/// strategy's synthesis (bench_rotor opens a peak-memory window there),
/// `onResult` with its row or its outcome (one of the two is null). Both
/// are called on every rank, in the same order, so they may communicate.
struct StrategyHooks {
  std::function<void(const std::string& basis, int vectors)> onStart;
  std::function<void(const StrategyRow*, const StrategyOutcome*)> onResult;
};

class StrategyComparison {
public:
  /// "Counts" (Teuchos::Array<int>, {2, 4, 8}): vectors per substructure;
  /// "Strategies" (Teuchos::Array<std::string>, Guyan, Admissible, Modes,
  /// Craig-Bampton); "Speed Factor" (double, 1); "Error Estimates" (bool,
  /// true: each row's largest estimated error, theory §11.8).
  static Teuchos::RCP<const Teuchos::ParameterList> validParameters();

  StrategyComparison(const synthesis::AssembledStructure& structure, Teuchos::ParameterList solve,
                     const Teuchos::ParameterList& options);

  /// The truth first (when it fails, nothing else runs: result.truthModes
  /// says why), then every strategy; `onResult` sees each row or outcome as
  /// it comes. Collective.
  ComparisonResult run(const std::function<void(const StrategyRow*, const StrategyOutcome*)>& onResult = {}) const;

  /// Every strategy against a truth already solved (or none); the result's
  /// truthModes stay empty (the caller holds them). Collective.
  ComparisonResult run(const SolvedTruth& truth, const StrategyHooks& hooks) const;

private:
  std::vector<double> scaledSpeeds() const;  ///< the nominal speeds times "Speed Factor"

  const synthesis::AssembledStructure& structure_;
  Teuchos::ParameterList solve_, options_;
};

}  // namespace cms::analysis
