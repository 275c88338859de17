// A small distributed matrix gathered as a dense one on every rank, for
// reference solves in the tests.
#pragma once

#include <algorithm>
#include <cmath>

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

/// max |A_ij - B_ij| of two matrices of one shape.
inline double maxAbsDifference(const DenseMatrix& A, const DenseMatrix& B) {
  double d = 0.0;
  for (int c = 0; c < A.numCols(); ++c)
    for (int r = 0; r < A.numRows(); ++r) d = std::max(d, std::abs(A(r, c) - B(r, c)));
  return d;
}

}  // namespace cms::fixtures
