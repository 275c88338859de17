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
  double reduceSeconds = 0.0, solveSeconds = 0.0, peakMiB = 0.0;
  TruthComparison accuracy;
  double estimate = 0.0;  ///< largest estimated relative error of the compared modes
  std::vector<int> perSubstructure;  ///< coordinates of each substructure
};

/// A strategy that did not give a row: skipped (too few coordinates or
/// modes, bad input such as more Craig-Bampton modes than DOFs) or failed
/// (its solve did not converge or broke down: `status` says which).
struct StrategyOutcome {
  std::string basis;
  int vectors = 0;
  bool failed = false;
  eigen::SolveStatus status = eigen::SolveStatus::Converged;
  std::string why;
};

struct ComparisonResult {
  long long truthSize = 0;
  double truthSeconds = 0.0;
  synthesis::StructureModes truthModes;  ///< its status decides whether anything was compared
  std::vector<StrategyRow> rows;
  std::vector<StrategyOutcome> others;   ///< skipped and failed strategies, in order
};

class StrategyComparison {
public:
  /// "Counts" (Teuchos::Array<int>, {2, 4, 8}): vectors per substructure;
  /// "Strategies" (Teuchos::Array<std::string>, Guyan, Admissible, Modes,
  /// Craig-Bampton); "Speed Factor" (double, 1).
  static Teuchos::RCP<const Teuchos::ParameterList> validParameters();

  StrategyComparison(const synthesis::AssembledStructure& structure, Teuchos::ParameterList solve,
                     const Teuchos::ParameterList& options);

  /// The truth first (when it fails, nothing else runs: result.truthModes
  /// says why), then every strategy; `onRow` sees each row or outcome as
  /// it comes. Collective.
  ComparisonResult run(const std::function<void(const StrategyRow*, const StrategyOutcome*)>& onResult = {}) const;

private:
  const synthesis::AssembledStructure& structure_;
  Teuchos::ParameterList solve_, options_;
};

}  // namespace cms::analysis
