// A small distributed matrix gathered as a dense one on every rank, for
// reference solves in the tests.
#pragma once

#include <Teuchos_RCP.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/DenseMatrix.hpp"
#include "cms/core/TpetraTypes.hpp"

namespace cms::fixtures {

/// A distributed matrix as a dense one on every rank (small matrices only).
inline DenseMatrix denseOf(const CrsMatrix& A) {
  const auto n = static_cast<int>(A.getGlobalNumRows());
  const auto map = A.getRowMap();
  MultiVector E(A.getDomainMap(), n), AE(A.getRangeMap(), n);
  for (std::size_t l = 0; l < A.getDomainMap()->getNodeNumElements(); ++l)
    E.replaceLocalValue(l, A.getDomainMap()->getGlobalElement(static_cast<LocalOrdinal>(l)), 1.0);
  A.apply(E, AE);
  auto rep = Teuchos::rcp(new Map(static_cast<GlobalOrdinal>(n), 0, map->getComm(), Tpetra::LocallyReplicated));
  MultiVector R(rep, n);
  R.doImport(AE, Tpetra::Import<>(A.getRangeMap(), rep), Tpetra::INSERT);
  DenseMatrix D(n, n);
  for (int j = 0; j < n; ++j) {
    auto c = R.getData(j);
    for (int i = 0; i < n; ++i) D(i, j) = c[i];
  }
  return D;
}

}  // namespace cms::fixtures
