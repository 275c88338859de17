#include "cms/core/Redistribution.hpp"

#include <stdexcept>

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

namespace cms {

namespace {

/// All of 0 .. n-1 on `owner`, nothing elsewhere (world communicator).
Teuchos::RCP<const Map> concentrated(const Map& like, int owner) {
  const auto n = like.getGlobalNumElements();
  if (n > 0 && (!like.isOneToOne() || like.getMinAllGlobalIndex() != 0 ||
                like.getMaxAllGlobalIndex() != static_cast<GlobalOrdinal>(n) - 1))
    throw std::invalid_argument("gatherToRank: the row ids are not 0 .. n-1");
  const auto comm = like.getComm();
  return Teuchos::rcp(new Map(n, comm->getRank() == owner ? n : 0, 0, comm));
}

}  // namespace

Teuchos::RCP<CrsMatrix> gatherToRank(const CrsMatrix& A, int owner,
                                     const Teuchos::RCP<const Teuchos::Comm<int>>& self) {
  const auto cmap = concentrated(*A.getRowMap(), owner);
  Tpetra::Import<> imp(A.getRowMap(), cmap);
  CrsMatrix Ac(cmap, 0);
  Ac.doImport(A, imp, Tpetra::INSERT);
  Ac.fillComplete(cmap, cmap);
  if (cmap->getComm()->getRank() != owner) return Teuchos::null;
  // The local arrays are already those of a one-rank matrix: the same
  // contiguous row map and column ids, re-expressed on `self`.
  const auto n = cmap->getGlobalNumElements();
  auto rows = Teuchos::rcp(new Map(n, n, 0, self));
  auto cols = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                   Ac.getColMap()->getNodeElementList(), 0, self));
  return Teuchos::rcp(new CrsMatrix(Ac.getLocalMatrixDevice(), rows, cols, rows, rows));
}

Teuchos::RCP<MultiVector> gatherToRank(const MultiVector& X, int owner,
                                       const Teuchos::RCP<const Teuchos::Comm<int>>& self) {
  const auto cmap = concentrated(*X.getMap(), owner);
  Tpetra::Import<> imp(X.getMap(), cmap);
  MultiVector Xc(cmap, X.getNumVectors());
  Xc.doImport(X, imp, Tpetra::INSERT);
  if (cmap->getComm()->getRank() != owner) return Teuchos::null;
  const auto n = cmap->getGlobalNumElements();
  auto out = Teuchos::rcp(new MultiVector(Teuchos::rcp(new Map(n, n, 0, self)), X.getNumVectors()));
  for (std::size_t j = 0; j < X.getNumVectors(); ++j) {
    auto from = Xc.getData(j);
    auto to = out->getDataNonConst(j);
    std::copy(from.begin(), from.end(), to.begin());
  }
  return out;
}

Teuchos::RCP<MultiVector> scatterFromRank(const Teuchos::RCP<const MultiVector>& X, int owner, int numVectors,
                                          const Teuchos::RCP<const Map>& target) {
  const auto cmap = concentrated(*target, owner);
  MultiVector Xc(cmap, static_cast<std::size_t>(std::max(numVectors, 1)));
  // Checked on the owner and agreed by every rank before the collective
  // import, so that a mismatch raises everywhere instead of hanging.
  int bad = target->getComm()->getRank() == owner && numVectors > 0 &&
            (X.is_null() || static_cast<int>(X->getNumVectors()) != numVectors ||
             X->getLocalLength() != cmap->getNodeNumElements());
  Teuchos::broadcast(*target->getComm(), owner, &bad);
  if (bad) throw std::invalid_argument("scatterFromRank: the owner's multivector does not match");
  if (target->getComm()->getRank() == owner && numVectors > 0) {
    for (int j = 0; j < numVectors; ++j) {
      auto from = X->getData(j);
      auto to = Xc.getDataNonConst(j);
      std::copy(from.begin(), from.end(), to.begin());
    }
  }
  Tpetra::Import<> imp(cmap, target);
  auto out = Teuchos::rcp(new MultiVector(target, static_cast<std::size_t>(std::max(numVectors, 1))));
  out->doImport(Xc, imp, Tpetra::INSERT);
  return out;
}

}  // namespace cms
