#include "cms/core/MatrixSum.hpp"

#include <vector>

#include <TpetraExt_MatrixMatrix.hpp>

namespace cms {

Teuchos::RCP<CrsMatrix> matrixSum(double a, const CrsMatrix& A, double b, const CrsMatrix& B) {
  if (!A.isFillComplete() || !B.isFillComplete() || A.getCrsGraph().get() != B.getCrsGraph().get())
    return Tpetra::MatrixMatrix::add(a, false, A, b, false, B);
  auto S = Teuchos::rcp(new CrsMatrix(A.getCrsGraph()));
  CrsMatrix::local_inds_host_view_type cols, colsB;
  CrsMatrix::values_host_view_type x, y;
  std::vector<double> v;
  for (LocalOrdinal r = 0; r < static_cast<LocalOrdinal>(A.getNodeNumRows()); ++r) {
    A.getLocalRowView(r, cols, x);
    B.getLocalRowView(r, colsB, y);  // the same graph: the same columns in the same order
    v.resize(x.extent(0));
    for (std::size_t e = 0; e < v.size(); ++e) v[e] = a * x(e) + b * y(e);
    S->replaceLocalValues(r, cols, CrsMatrix::values_host_view_type(v.data(), v.size()));
  }
  S->fillComplete(A.getDomainMap(), A.getRangeMap());
  return S;
}

}  // namespace cms
