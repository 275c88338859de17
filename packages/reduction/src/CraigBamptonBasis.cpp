#include "cms/reduction/CraigBamptonBasis.hpp"

#include <algorithm>
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
  // A child attached through a single node or a Boolean interface moves
  // with as many of these rows as it has attachment coordinates: each row is
  // an interface coordinate and gets a unit constraint mode. A distributing
  // (RigidFit, RBE3-like) interface has many rows but only the 6 fitted
  // coordinates a = H u: its constraint modes are the minimum-energy shapes
  // with H u = e_i, whose span is K^-1 H^T (doc/theory.md §11.3), i.e. the
  // static shapes under the child's 6 attachment loads, not one per row.
  std::set<GlobalOrdinal> interface;
  std::vector<std::size_t> distributing;
  for (std::size_t c = 0; c < boundary.interfaces.size(); ++c) {
    const auto& rows = boundary.interfaces[c];
    const std::size_t patterns = c < boundary.interfaceLoads.size() ? boundary.interfaceLoads[c].size() : rows.size();
    if (patterns < rows.size()) distributing.push_back(c);
    else interface.insert(rows.begin(), rows.end());
  }
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
  if (!distributing.empty()) {
    const auto map = s.map();
    int nf = 0;
    for (std::size_t c : distributing) nf += static_cast<int>(boundary.interfaceLoads[c].size());
    MultiVector F(map, nf), X(map, nf);
    std::vector<std::string> labels;
    int j = 0;
    for (std::size_t c : distributing)
      for (std::size_t k = 0; k < boundary.interfaceLoads[c].size(); ++k, ++j) {
        labels.push_back("constraint mode of interface " + std::to_string(c + 1) + " coordinate " +
                         std::to_string(k + 1));
        for (auto [g, v] : boundary.interfaceLoads[c][k]) {
          const auto l = map->getLocalElement(g);
          if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) F.sumIntoLocalValue(l, j, v);
        }
      }
    detail::HeldStiffness K(s, heldAll);
    K.solve(F, X);
    appendOrthonormal(*s.M(), X, labels, depTol, basis.size() + nf, basis);
    // The modes hold these rows whole: a stronger constraint than H u = 0
    // (a subspace of it), so the basis stays admissible; theory §11.3.
    for (std::size_t c : distributing)
      for (GlobalOrdinal g : boundary.interfaces[c])
        if (!std::binary_search(boundary.held.begin(), boundary.held.end(), g)) heldAll.push_back(g);
    std::sort(heldAll.begin(), heldAll.end());
    heldAll.erase(std::unique(heldAll.begin(), heldAll.end()), heldAll.end());
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
