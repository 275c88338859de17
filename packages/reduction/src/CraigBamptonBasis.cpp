#include "cms/reduction/CraigBamptonBasis.hpp"

#include <set>

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "HeldStiffness.hpp"
#include "cms/reduction/FixedInterfaceModes.hpp"

namespace cms::reduction {

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
    // psi = e_g + K_held^-1 (-K e_g): the held solve zeroes every interface
    // row of the correction, so psi is 1 at g and 0 at the other interface
    // and attachment rows.
    const auto map = s.map();
    const int nb = static_cast<int>(interface.size());
    MultiVector E(map, nb), KE(map, nb), Psi(map, nb);
    std::vector<std::string> labels;
    int j = 0;
    for (GlobalOrdinal g : interface) {
      const auto l = map->getLocalElement(g);
      if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) E.replaceLocalValue(l, j, 1.0);
      labels.push_back("constraint mode of row " + std::to_string(g));
      ++j;
    }
    s.K()->apply(E, KE);
    KE.scale(-1.0);
    detail::HeldStiffness K(s, heldAll);
    K.solve(KE, Psi);
    Psi.update(1.0, E, 1.0);
    appendOrthonormal(*s.M(), Psi, labels, depTol, nb, basis);
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
