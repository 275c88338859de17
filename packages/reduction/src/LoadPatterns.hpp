// Internal to the reduction package: the static load patterns of admissible
// vectors (doc/theory.md §11.3), shared by the Admissible and Partitioned
// bases.
#pragma once

#include <string>
#include <vector>

#include "cms/reduction/RitzBasis.hpp"

namespace cms::reduction::detail {

/// The loads of the static correction of a child held by supports or
/// grounded springs of its own (theory §11.2): R = K X, X the rigid motion
/// about b.supportedAttachment, zero on the held rows, one column per
/// attachment coordinate (ux .. rz) the supports resist, labelled
/// kOwnSupportsColumn + the coordinate. A column at the rounding of the
/// product (the supports do not resist that motion) is left out. F is null
/// when there is none. Collective.
void ownSupportLoads(const substructure::Substructure& s, const SubstructureBoundary& b,
                     Teuchos::RCP<MultiVector>& F, std::vector<std::string>& labels);

/// The load patterns ("interfaces", "uniform", "rotation", "centrifugal",
/// "tip") as columns of F on the substructure's map, with a label each,
/// after the own-support loads (ownSupportLoads) whatever the list; F is
/// null when no pattern applies. Collective. Throws InputError naming an
/// unknown pattern.
void loadPatterns(const substructure::Substructure& s, const SubstructureBoundary& b,
                  const std::vector<std::string>& patterns, Teuchos::RCP<MultiVector>& F,
                  std::vector<std::string>& labels);

}  // namespace cms::reduction::detail
