#include "cms/core/HeldDofs.hpp"

#include <unordered_set>

#include <Teuchos_Array.hpp>
#include <Teuchos_CommHelpers.hpp>
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
  if (held.empty()) return Teuchos::rcp(new CrsMatrix(A, Teuchos::Copy));
  // A held row whose diagonal A does not store (a Matrix Market K may leave
  // out a zero) has no place for its value in A's graph: copied, the row
  // would be all zero and the held matrix singular. Then the matrix is
  // built anew with room for the diagonal, on every rank alike (the column
  // map is made collectively).
  const auto& rowMap = *A.getRowMap();
  int missing = 0;
  {
    Teuchos::Array<GlobalOrdinal> cols;
    Teuchos::Array<double> vals;
    for (LocalOrdinal lr = 0; lr < static_cast<LocalOrdinal>(rowMap.getNodeNumElements()); ++lr) {
      const GlobalOrdinal gr = rowMap.getGlobalElement(lr);
      if (!held.count(gr)) continue;
      const std::size_t n = A.getNumEntriesInGlobalRow(gr);
      cols.resize(n), vals.resize(n);
      std::size_t got = 0;
      A.getGlobalRowCopy(gr, cols(), vals(), got);
      if (std::find(cols.begin(), cols.begin() + static_cast<std::ptrdiff_t>(got), gr) ==
              cols.begin() + static_cast<std::ptrdiff_t>(got) &&
          diagonal(0.0) != 0.0)
        missing = 1;
    }
    int anywhere = 0;
    Teuchos::reduceAll(*A.getComm(), Teuchos::REDUCE_MAX, missing, Teuchos::outArg(anywhere));
    missing = anywhere;
  }
  if (missing) {
    auto B = Teuchos::rcp(new CrsMatrix(A.getRowMap(), A.getNodeMaxNumRowEntries() + 1));
    Teuchos::Array<GlobalOrdinal> cols;
    Teuchos::Array<double> vals;
    for (LocalOrdinal lr = 0; lr < static_cast<LocalOrdinal>(rowMap.getNodeNumElements()); ++lr) {
      const GlobalOrdinal gr = rowMap.getGlobalElement(lr);
      const bool rowHeld = held.count(gr) > 0;
      const std::size_t n = A.getNumEntriesInGlobalRow(gr);
      cols.resize(n), vals.resize(n);
      std::size_t got = 0;
      A.getGlobalRowCopy(gr, cols(), vals(), got);
      cols.resize(got), vals.resize(got);
      bool hasDiagonal = false;
      for (std::size_t k = 0; k < got; ++k) {
        hasDiagonal = hasDiagonal || cols[k] == gr;
        if (rowHeld || held.count(cols[k])) vals[k] = (rowHeld && cols[k] == gr) ? diagonal(vals[k]) : 0.0;
      }
      if (rowHeld && !hasDiagonal) cols.push_back(gr), vals.push_back(diagonal(0.0));
      if (!cols.empty()) B->insertGlobalValues(gr, cols(), vals());
    }
    B->fillComplete(A.getDomainMap(), A.getRangeMap());
    return B;
  }
  auto B = Teuchos::rcp(new CrsMatrix(A, Teuchos::Copy));
  B->resumeFill();
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
