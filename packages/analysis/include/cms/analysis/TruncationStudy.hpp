// How many vectors each substructure needs (doc/user-guide.md, "cms
// truncate"; doc/theory.md §11.7-11.8): starting from "Start" vectors per
// reducible substructure, a greedy search adds "Step" vectors at a time to
// the substructure whose addition lowers the largest estimated error of
// the lowest "Number of Modes" most per added coordinate, until that error
// is below "Accuracy" — judged by the error estimates of §11.8, without the
// truth ("Truth" also solves it and records the true error beside them).
// Every step checks the inclusion principle between the nested models
// (seed eqs. (28)-(29)) where K > 0, above a round-off threshold derived
// from the solves' residuals (inclusionTolerances); a violation is a
// finding, reported, never loosened away.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/analysis/TruthComparison.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace cms::analysis {

struct TruncationStep {
  int step = 0;
  std::string changed;             ///< the substructure that got the vectors ("(start)" first; "name (stall)":
                                   ///< chosen by the worst mode's energy, no single addition lowered the estimate)
  long long dofs = 0;              ///< reduced coordinates
  double estimate = 0.0;           ///< largest estimated relative error of the wanted modes
  double trueError = 0.0;          ///< largest true relative error ("Truth"), else NaN
  std::vector<InclusionViolation> findings;  ///< against the previous step
  std::vector<int> vectors;        ///< per substructure ("Vectors" of the reducible ones, 0 others)
  /// The inclusion principle was checked against the previous step (K > 0
  /// and the dense Meirovitch solve in both); false for the first step and
  /// where it could not be, so that no findings is not read as none found.
  bool inclusionChecked = false;
  /// Truth modes the model lacks and its modes of no computed truth shape
  /// (compareWithTruth, "Truth"; -1 without): where either is above 0,
  /// trueError covers only the modes paired.
  int trueMissing = -1, trueUnmatched = -1;
};

struct TruncationResult {
  std::vector<TruncationStep> steps;
  bool reached = false;
  bool definite = false;            ///< K > 0 and the dense Meirovitch solve in every model compared (the inclusion principle checked at every step)
  long long truthSize = 0;          ///< coordinates of the truth ("Truth"), else 0
  std::vector<bool> reducible;      ///< per substructure: its count was searched
};

class TruncationStudy {
public:
  /// "Start" (int, 2), "Step" (int, 2), "Accuracy" (double, 1e-3),
  /// "Truth" (bool, false), "Max Steps" (int, 200), "Speed Factor" (double, 1).
  static Teuchos::RCP<const Teuchos::ParameterList> validParameters();

  TruncationStudy(const synthesis::AssembledStructure& structure, Teuchos::ParameterList solve,
                  const Teuchos::ParameterList& options);

  /// Runs the search; `onStep` (if set) sees each step as it is taken,
  /// with the result so far (truthSize, definite). Collective.
  TruncationResult run(
      const std::function<void(const TruncationStep&, const TruncationResult&)>& onStep = {}) const;

private:
  const synthesis::AssembledStructure& structure_;
  Teuchos::ParameterList solve_, options_;
};

}  // namespace cms::analysis
