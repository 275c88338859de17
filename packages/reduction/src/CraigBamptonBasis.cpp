#include "cms/reduction/CraigBamptonBasis.hpp"

#include <algorithm>
#include <set>

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "HeldStiffness.hpp"
#include "cms/core/SparseProduct.hpp"
#include "cms/core/HeldDofs.hpp"
#include "cms/reduction/FixedInterfaceModes.hpp"

namespace cms::reduction {

namespace {

/// psi = e_g + K_held^-1 (-K e_g): the held solve zeroes every held row of
/// the correction, so psi is 1 at g and 0 at the other held rows.
Teuchos::RCP<MultiVector> constraintModes(const substructure::Substructure& s, const detail::HeldStiffness& K,
                                          const std::vector<GlobalOrdinal>& unitRows) {
  const auto map = s.map();
  const int nb = static_cast<int>(unitRows.size());
  MultiVector E(map, nb), KE(map, nb);
  auto Psi = Teuchos::rcp(new MultiVector(map, nb));
  for (int j = 0; j < nb; ++j) {
    if (unitRows[j] < 0) continue;
    const auto l = map->getLocalElement(unitRows[j]);
    if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) E.replaceLocalValue(l, j, 1.0);
  }
  multiply(*s.K(), E, KE);
  KE.scale(-1.0);
  K.solve(KE, *Psi);
  Psi->update(1.0, E, 1.0);
  return Psi;
}

}  // namespace

Teuchos::RCP<MultiVector> constraintModes(const substructure::Substructure& s, const std::vector<GlobalOrdinal>& held,
                                          const std::vector<GlobalOrdinal>& unitRows) {
  return constraintModes(s, detail::HeldStiffness(s, held), unitRows);
}

namespace {
// A child attached through a single node or a Boolean interface moves
// with as many of these rows as it has attachment coordinates: each row is
// an interface coordinate and gets a unit constraint mode. A distributing
// (RigidFit, RBE3-like) interface has many rows but only the 6 fitted
// coordinates a = H u: its constraint modes are the minimum-energy shapes
// with H u = e_i, whose span is K^-1 H^T (doc/theory.md §11.3), i.e. the
// static shapes under the child's 6 attachment loads, not one per row.
std::set<GlobalOrdinal> pointInterfaceRows(const SubstructureBoundary& boundary, std::vector<std::size_t>* distributing) {
  std::set<GlobalOrdinal> interface;
  for (std::size_t c = 0; c < boundary.interfaces.size(); ++c) {
    const auto& rows = boundary.interfaces[c];
    const std::size_t patterns = c < boundary.interfaceLoads.size() ? boundary.interfaceLoads[c].size() : rows.size();
    if (patterns < rows.size()) {
      if (distributing) distributing->push_back(c);
    } else {
      interface.insert(rows.begin(), rows.end());
    }
  }
  for (GlobalOrdinal g : boundary.held) interface.erase(g);
  return interface;
}
}  // namespace

std::vector<GlobalOrdinal> craigBamptonHeldRows(const SubstructureBoundary& boundary) {
  const auto interface = pointInterfaceRows(boundary, nullptr);
  std::set<GlobalOrdinal> all(boundary.held.begin(), boundary.held.end());
  all.insert(interface.begin(), interface.end());
  return {all.begin(), all.end()};
}

RitzBasis craigBamptonBasis(const substructure::Substructure& s, const SubstructureBoundary& boundary, int modes,
                            double eigTol, double depTol, const SturmCut& cut) {
  std::vector<std::size_t> distributing;
  const std::set<GlobalOrdinal> interface = pointInterfaceRows(boundary, &distributing);
  std::vector<GlobalOrdinal> heldAll(boundary.held);
  heldAll.insert(heldAll.end(), interface.begin(), interface.end());

  RitzBasis basis;
  basis.kind = modes == 0 ? "Guyan" : "Craig-Bampton";
  // One factorisation of K with the attachment and the point interfaces
  // held serves the constraint modes of both kinds and the modes.
  std::sort(heldAll.begin(), heldAll.end());
  const detail::HeldStiffness K(s, heldAll);
  if (!interface.empty()) {
    std::vector<GlobalOrdinal> unit(interface.begin(), interface.end());
    std::vector<std::string> labels;
    for (GlobalOrdinal g : unit) labels.push_back("constraint mode of row " + std::to_string(g));
    const auto Psi = constraintModes(s, K, unit);
    const int nb = static_cast<int>(unit.size());
    appendOrthonormal(*s.M(), *Psi, labels, depTol, nb, basis);
  }
  ModeConstraints constraints;
  if (!distributing.empty()) {
    const auto map = s.map();
    int nf = 0;
    for (std::size_t c : distributing) nf += static_cast<int>(boundary.interfaceLoads[c].size());
    auto F = Teuchos::rcp(new MultiVector(map, nf));
    auto X = Teuchos::rcp(new MultiVector(map, nf));
    std::vector<std::string> labels;
    int j = 0;
    for (std::size_t c : distributing)
      for (std::size_t k = 0; k < boundary.interfaceLoads[c].size(); ++k, ++j) {
        labels.push_back("constraint mode of interface " + std::to_string(c + 1) + " coordinate " +
                         std::to_string(k + 1));
        for (auto [g, v] : boundary.interfaceLoads[c][k]) {
          const auto l = map->getLocalElement(g);
          if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) F->sumIntoLocalValue(l, j, v);
        }
      }
    zeroHeldRows(*F, heldAll);
    K.solve(*F, *X);
    appendOrthonormal(*s.M(), *X, labels, depTol, basis.size() + nf, basis);
    // The modes of the fixed interface satisfy H u = 0 (theory §11.3).
    constraints = {F, X};
  }
  if (modes > 0) {
    RitzBasis phi = detail::fixedInterfaceModes(s, K, modes, eigTol, depTol, constraints, cut);
    appendOrthonormal(*s.M(), *phi.vectors, phi.labels, depTol, basis.size() + phi.size(), basis);
    basis.eigensolverReport = phi.eigensolverReport;
    basis.dropped.insert(basis.dropped.end(), phi.dropped.begin(), phi.dropped.end());
  }
  return basis;
}

}  // namespace cms::reduction
