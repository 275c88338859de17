// Craig-Bampton (Craig & Bampton 1968): fixed-interface normal modes (the
// substructure's attachment and its children's interfaces all fixed) plus the
// static constraint modes of the children's interface coordinates: for a
// Node or Boolean interface one per interface row, psi_g = e_g - K_ii^-1
// K_ig; for a distributing (RigidFit) interface, whose coordinates are the
// six fitted motions a = H u, the static shapes K^-1 H^T, with the modes
// computed under H u = 0 (doc/theory.md §11.3). With no modes it is Guyan's
// static condensation onto the interface. The attachment to the parent needs
// no constraint modes here: its motion is the interface transform's rigid
// part (doc/theory.md §11.2).
#pragma once

#include "cms/reduction/FixedInterfaceModes.hpp"
#include "cms/reduction/RitzBasis.hpp"

namespace cms::reduction {

/// Static constraint modes with every row of `held` fixed: column k is 1 at
/// unitRows[k] (which must be held), 0 at the other held rows, and the static
/// response K_ii^-1 (-K_ik) elsewhere; a column with unitRows[k] < 0 is zero.
/// Collective.
Teuchos::RCP<MultiVector> constraintModes(const substructure::Substructure& s, const std::vector<GlobalOrdinal>& held,
                                          const std::vector<GlobalOrdinal>& unitRows);

/// Constraint modes first (one per interface row), then `modes` eigenvectors.
/// The rows a Craig-Bampton (or Guyan) basis holds in its modes and
/// factors K with: the attachment and every point or Boolean interface row
/// (a distributing interface is represented by its 6 static load shapes
/// instead), sorted and unique.
std::vector<GlobalOrdinal> craigBamptonHeldRows(const SubstructureBoundary& boundary);
/// H^T of the distributing interfaces (their load shapes, `held` rows
/// zeroed), reduced to an orthonormal basis of its range when dependent
/// (eigenvalues of F^T F above 1e-10 of the largest): its column count is
/// the number of independent constraints H u = 0. `labels` names each.
Teuchos::RCP<MultiVector> distributingConstraints(const substructure::Substructure& s,
                                                  const SubstructureBoundary& boundary,
                                                  const std::vector<GlobalOrdinal>& held,
                                                  std::vector<std::string>& labels);

/// `cut`: the cut-off's Sturm count, which the fixed-interface modes are
/// checked against (FixedInterfaceModes.hpp).
RitzBasis craigBamptonBasis(const substructure::Substructure& s, const SubstructureBoundary& boundary, int modes,
                            double eigensolverTolerance, double dependenceTolerance, const SturmCut& cut = {});

}  // namespace cms::reduction
