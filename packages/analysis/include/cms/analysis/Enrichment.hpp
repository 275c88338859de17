// Reduction driven by an accuracy (issue #9): the reduced substructures'
// bases are enriched until every wanted mode's estimated relative frequency
// error (SynthesizedStructure::errorEstimates, doc/theory.md §11.8) is below
// a target, with no truth solve. Each step adds vectors (a quarter more, at
// least 2; or a cut-off frequency 1.5 times higher) to the reducible
// substructure carrying the largest kinetic-energy share of the worst
// estimated mode.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/synthesis/SynthesizedStructure.hpp"

namespace cms::analysis {

struct Enrichment {
  bool reached = false;
  double worstEstimate = 0.0;
  std::vector<std::string> notes;  ///< one line per step and the outcome
  /// When reached: the synthesis with the enriched bases (pass it as
  /// synthesize's `previous` to reuse its bases and factorisations).
  std::shared_ptr<const synthesis::SynthesizedStructure> synthesis;
};

/// `reductions` (one "Reduction" list per substructure, tree order) is
/// updated in place. Collective.
Enrichment enrichToAccuracy(const synthesis::AssembledStructure& structure, const std::vector<double>& speeds,
                            const Teuchos::ParameterList& solveParams, double target,
                            std::vector<Teuchos::ParameterList>& reductions);

}  // namespace cms::analysis
