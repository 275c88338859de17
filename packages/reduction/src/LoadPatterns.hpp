// Internal to the reduction package: the static load patterns of admissible
// vectors (doc/theory.md §11.3), shared by the Admissible and Partitioned
// bases.
#pragma once

#include <string>
#include <vector>

#include "cms/reduction/RitzBasis.hpp"

namespace cms::reduction::detail {

/// The load patterns ("interfaces", "uniform", "rotation", "centrifugal",
/// "tip") as columns of F on the substructure's map, with a label each; F
/// is null when no pattern applies. Collective. Throws InputError naming an
/// unknown pattern.
void loadPatterns(const substructure::Substructure& s, const SubstructureBoundary& b,
                  const std::vector<std::string>& patterns, Teuchos::RCP<MultiVector>& F,
                  std::vector<std::string>& labels);

}  // namespace cms::reduction::detail
