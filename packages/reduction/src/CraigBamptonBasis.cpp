#include "cms/reduction/CraigBamptonBasis.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <Teuchos_LAPACK.hpp>

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "HeldStiffness.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/TpetraTypes.hpp"
#include "cms/core/SparseProduct.hpp"
#include "cms/core/HeldDofs.hpp"
#include "cms/reduction/FixedInterfaceModes.hpp"

namespace cms::reduction {

namespace {
/// The columns of F (n x m, distributed) scaled to unit norm, and, when
/// they are dependent, their first `rank` columns replaced by an
/// orthonormal basis of their range: F V_k Lambda_k^-1/2 with (Lambda, V)
/// the eigenpairs of the Gram matrix F^T F above 1e-10 of its largest.
/// Returns the rank. Scaling a column leaves its constraint H u = 0 as it was.
int compressToRange(MultiVector& F, int m) {
  if (m == 0) return 0;
  // Columns to unit norm first: a small face's rotations beside a large
  // face's translations differ in norm by its size ratio, and the rank
  // test must not take one for the other's rounding (found by a review).
  // A column of zeros (every row held) counts as dependent.
  {
    Teuchos::Array<double> norms(m);
    F.norm2(norms());
    double top = 0.0;
    for (double v : norms) top = std::max(top, v);
    Teuchos::Array<double> scale(m);
    for (int k = 0; k < m; ++k) scale[k] = norms[k] > 1e-14 * top && norms[k] > 0.0 ? 1.0 / norms[k] : 0.0;
    F.scale(scale());
  }
  auto small = Teuchos::rcp(new Map(m, 0, F.getMap()->getComm(), Tpetra::LocallyReplicated));
  MultiVector G(small, m);
  G.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, F, F, 0.0);
  std::vector<double> A(static_cast<std::size_t>(m) * m), w(m), work(static_cast<std::size_t>(64) * m);
  for (int j = 0; j < m; ++j) {
    const auto c = G.getData(j);
    for (int i = 0; i < m; ++i) A[i + static_cast<std::size_t>(j) * m] = c[i];
  }
  int info = 0;
  Teuchos::LAPACK<int, double>().SYEV('V', 'L', m, A.data(), m, w.data(), work.data(), static_cast<int>(work.size()),
                                      &info);
  TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError,
                             "Craig-Bampton: the distributing constraints' Gram matrix: LAPACK dsyev info " << info);
  const double top = w[m - 1];
  int rank = 0;
  for (int k = 0; k < m; ++k) rank += w[k] > 1e-10 * top && top > 0.0;
  TEUCHOS_TEST_FOR_EXCEPTION(rank == 0, InputError,
                             "Craig-Bampton: every distributing interface's rows are held (no constraint left)");
  if (rank == m) return m;
  // Columns of the kept eigenvectors (the largest rank of them), scaled.
  MultiVector C(small, rank);
  for (int k = 0; k < rank; ++k) {
    const int e = m - 1 - k;
    const double sc = 1.0 / std::sqrt(w[e]);
    auto col = C.getDataNonConst(k);
    for (int i = 0; i < m; ++i) col[i] = A[i + static_cast<std::size_t>(e) * m] * sc;
  }
  MultiVector Fk(F.getMap(), rank);
  Fk.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, F, C, 0.0);
  for (int k = 0; k < rank; ++k) F.getVectorNonConst(k)->assign(*Fk.getVector(k));
  return rank;
}
}  // namespace

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

Teuchos::RCP<MultiVector> distributingConstraints(const substructure::Substructure& s,
                                                  const SubstructureBoundary& boundary,
                                                  const std::vector<GlobalOrdinal>& held,
                                                  std::vector<std::string>& labels) {
  std::vector<std::size_t> distributing;
  pointInterfaceRows(boundary, &distributing);
  const auto map = s.map();
  int nf = 0;
  for (std::size_t c : distributing) nf += static_cast<int>(boundary.interfaceLoads[c].size());
  auto F = Teuchos::rcp(new MultiVector(map, nf));
  labels.clear();
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
  zeroHeldRows(*F, held);
  // Dependent constraints (two children fitted to one face, a grandchild's
  // face on its parent's held rows) made H rank deficient: the fixed-
  // interface problem then dropped random directions (symmetric pairs
  // split, results by rounding) or stopped on an "internal error" (found
  // by a review). F is replaced by an orthonormal basis of its range.
  if (const int rank = compressToRange(*F, nf); rank < nf) {
    F = F->subCopy(Teuchos::Range1D(0, rank - 1));
    labels.clear();
    for (int k = 0; k < rank; ++k)
      labels.push_back("constraint mode of the distributing interfaces, independent combination " +
                       std::to_string(k + 1) + " of " + std::to_string(rank) + " (" + std::to_string(nf) +
                       " constraints)");
  }
  return F;
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
    std::vector<std::string> labels;
    auto F = distributingConstraints(s, boundary, heldAll, labels);
    const int nf = static_cast<int>(F->getNumVectors());
    auto X = Teuchos::rcp(new MultiVector(s.map(), nf));
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
