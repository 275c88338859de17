#include "cms/reduction/CraigBamptonBasis.hpp"

#include <set>

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "HeldStiffness.hpp"
#include "cms/reduction/FixedInterfaceModes.hpp"

namespace cms::reduction {

Teuchos::RCP<MultiVector> constraintModes(const substructure::Substructure& s, const std::vector<GlobalOrdinal>& held,
                                          const std::vector<GlobalOrdinal>& unitRows) {
  // psi = e_g + K_held^-1 (-K e_g): the held solve zeroes every held row of
  // the correction, so psi is 1 at g and 0 at the other held rows.
  const auto map = s.map();
  const int nb = static_cast<int>(unitRows.size());
  MultiVector E(map, nb), KE(map, nb);
  auto Psi = Teuchos::rcp(new MultiVector(map, nb));
  for (int j = 0; j < nb; ++j) {
    if (unitRows[j] < 0) continue;
    const auto l = map->getLocalElement(unitRows[j]);
    if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) E.replaceLocalValue(l, j, 1.0);
  }
  s.K()->apply(E, KE);
  KE.scale(-1.0);
  detail::HeldStiffness K(s, held);
  K.solve(KE, *Psi);
  Psi->update(1.0, E, 1.0);
  return Psi;
}

RitzBasis craigBamptonBasis(const substructure::Substructure& s, const SubstructureBoundary& boundary, int modes,
                            double eigTol, double depTol) {
  std::set<GlobalOrdinal> interface;
  for (const auto& rows : boundary.interfaces) interface.insert(rows.begin(), rows.end());
  for (GlobalOrdinal g : boundary.held) interface.erase(g);
  std::vector<GlobalOrdinal> heldAll(boundary.held);
  heldAll.insert(heldAll.end(), interface.begin(), interface.end());

  RitzBasis basis;
  basis.kind = modes == 0 ? "Guyan" : "Craig-Bampton";
  if (!interface.empty()) {
    std::vector<GlobalOrdinal> unit(interface.begin(), interface.end());
    std::vector<std::string> labels;
    for (GlobalOrdinal g : unit) labels.push_back("constraint mode of row " + std::to_string(g));
    const auto Psi = constraintModes(s, heldAll, unit);
    const int nb = static_cast<int>(unit.size());
    appendOrthonormal(*s.M(), *Psi, labels, depTol, nb, basis);
  }
  if (modes > 0) {
    RitzBasis phi = fixedInterfaceModes(s, heldAll, modes, eigTol, depTol);
    appendOrthonormal(*s.M(), *phi.vectors, phi.labels, depTol, basis.size() + phi.size(), basis);
    basis.eigensolverReport = phi.eigensolverReport;
    basis.dropped.insert(basis.dropped.end(), phi.dropped.begin(), phi.dropped.end());
  }
  return basis;
}

}  // namespace cms::reduction
