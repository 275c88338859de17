#include "cms/core/HeldDofs.hpp"

#include <unordered_set>

#include <Teuchos_Array.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include <algorithm>

namespace cms {

namespace {

/// diagonal(row): the value a held row gets.
template <class Diagonal>
Teuchos::RCP<CrsMatrix> hold(const CrsMatrix& A, const std::vector<GlobalOrdinal>& rows, Diagonal diagonal) {
  const std::unordered_set<GlobalOrdinal> held(rows.begin(), rows.end());
  auto B = Teuchos::rcp(new CrsMatrix(A, Teuchos::Copy));
  if (held.empty()) return B;
  B->resumeFill();
  const auto& rowMap = *B->getRowMap();
  const auto& colMap = *B->getColMap();
  Teuchos::Array<LocalOrdinal> cols;
  Teuchos::Array<double> vals;
  for (LocalOrdinal lr = 0; lr < static_cast<LocalOrdinal>(rowMap.getNodeNumElements()); ++lr) {
    const GlobalOrdinal gr = rowMap.getGlobalElement(lr);
    const bool rowHeld = held.count(gr) > 0;
    const std::size_t n = B->getNumEntriesInLocalRow(lr);
    cols.resize(n);
    vals.resize(n);
    std::size_t got = 0;
    B->getLocalRowCopy(lr, cols(), vals(), got);
    bool changed = false;
    for (std::size_t k = 0; k < got; ++k) {
      const GlobalOrdinal gc = colMap.getGlobalElement(cols[k]);
      if (rowHeld || held.count(gc)) {
        vals[k] = (rowHeld && gc == gr) ? diagonal(vals[k]) : 0.0;
        changed = true;
      }
    }
    if (changed) B->replaceLocalValues(lr, cols(0, got), vals(0, got));
  }
  B->fillComplete(A.getDomainMap(), A.getRangeMap());
  return B;
}

}  // namespace

Teuchos::RCP<CrsMatrix> holdDofs(const CrsMatrix& A, const std::vector<GlobalOrdinal>& rows, double diagonal) {
  return hold(A, rows, [diagonal](double) { return diagonal; });
}

Teuchos::RCP<CrsMatrix> holdDofsScaled(const CrsMatrix& A, const std::vector<GlobalOrdinal>& rows) {
  Vector d(A.getRowMap());
  A.getLocalDiagCopy(d);
  const double largest = std::max(d.normInf(), 1e-300);
  return hold(A, rows, [largest](double own) { return own > 0.0 ? own : largest; });
}

void zeroHeldRows(MultiVector& X, const std::vector<GlobalOrdinal>& rows) {
  const auto& map = *X.getMap();
  for (GlobalOrdinal g : rows) {
    const LocalOrdinal l = map.getLocalElement(g);
    if (l == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) continue;
    for (std::size_t j = 0; j < X.getNumVectors(); ++j) X.replaceLocalValue(l, j, 0.0);
  }
}

}  // namespace cms
