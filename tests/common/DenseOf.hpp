// A small distributed matrix gathered as a dense one on every rank, for
// reference solves in the tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Teuchos_LAPACK.hpp>
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

/// kappa_2 of the symmetric K with the rows and columns `held` removed
/// (dense: small matrices only); NaN when that is not positive definite.
inline double heldConditionNumber(const CrsMatrix& K, const std::vector<GlobalOrdinal>& held) {
  const DenseMatrix D = denseOf(K);
  std::vector<int> keep;
  for (int i = 0; i < D.numRows(); ++i)
    if (std::find(held.begin(), held.end(), i) == held.end()) keep.push_back(i);
  const int m = static_cast<int>(keep.size());
  DenseMatrix Kf(m, m);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) Kf(i, j) = D(keep[i], keep[j]);
  std::vector<double> w(static_cast<std::size_t>(m)), work(static_cast<std::size_t>(3 * m));
  int info = 0;
  Teuchos::LAPACK<int, double>().SYEV('N', 'U', m, Kf.values(), m, w.data(), work.data(), 3 * m, &info);
  if (info != 0 || m == 0 || !(w.front() > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return w.back() / w.front();
}

}  // namespace cms::fixtures
