#include "cms/core/Redistribution.hpp"

#include <algorithm>
#include <climits>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include <mpi.h>

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/MpiComm.hpp"

namespace cms {

namespace {

/// All of 0 .. n-1 on `owner`, nothing elsewhere (world communicator).
/// Throws std::invalid_argument (on every rank: the extremes are global)
/// unless the map's ids are 0 .. n-1, each on one rank.
void checkZeroToN(const Map& like) {
  const auto n = like.getGlobalNumElements();
  if (n > 0 && (!like.isOneToOne() || like.getMinAllGlobalIndex() != 0 ||
                like.getMaxAllGlobalIndex() != static_cast<GlobalOrdinal>(n) - 1))
    throw std::invalid_argument("gatherToRank: the row ids are not 0 .. n-1");
}

Teuchos::RCP<const Map> concentrated(const Map& like, int owner) {
  checkZeroToN(like);
  const auto n = like.getGlobalNumElements();
  const auto comm = like.getComm();
  return Teuchos::rcp(new Map(n, comm->getRank() == owner ? n : 0, 0, comm));
}

const char* const notSquare = "GatheredRows: a column that is no row (the matrix is not square in its ids)";

static_assert(std::is_same<GlobalOrdinal, long long>::value, "gatherRows sends global ids as MPI_LONG_LONG");

}  // namespace

RowsOnRank gatherRows(const CrsMatrix& A, int owner) {
  const auto& comm = *A.getComm();
  const bool isOwner = comm.getRank() == owner;
  const auto rowMap = A.getRowMap(), colMap = A.getColMap();
  const std::size_t nLocal = A.getNodeNumRows();
  // This rank's rows in global ids.
  RowsOnRank local;
  local.rows.resize(nLocal);
  std::vector<int> lengths(nLocal);
  local.columns.reserve(A.getNodeNumEntries());
  local.values.reserve(A.getNodeNumEntries());
  const auto columnIds = colMap->getNodeElementList();
  CrsMatrix::local_inds_host_view_type cols;
  CrsMatrix::values_host_view_type vals;
  for (std::size_t i = 0; i < nLocal; ++i) {
    A.getLocalRowView(static_cast<LocalOrdinal>(i), cols, vals);
    local.rows[i] = rowMap->getGlobalElement(static_cast<LocalOrdinal>(i));
    lengths[i] = static_cast<int>(cols.extent(0));
    for (std::size_t e = 0; e < cols.extent(0); ++e)
      local.columns.push_back(columnIds[cols(e)]), local.values.push_back(vals(e));
  }
  RowsOnRank out;
  if (comm.getSize() == 1) {
    out = std::move(local);
  } else {
    const MPI_Comm c = rawMpiComm(comm);
    out.rows = gatherOnRank(local.rows, owner, c, "gatherRows' rows");
    lengths = gatherOnRank(lengths, owner, c, "gatherRows' rows");
    out.columns = gatherOnRank(local.columns, owner, c, "gatherRows' entries");
    out.values = gatherOnRank(local.values, owner, c, "gatherRows' entries");
  }
  if (!isOwner) return RowsOnRank{};
  out.offsets.assign(out.rows.size() + 1, 0);
  for (std::size_t r = 0; r < out.rows.size(); ++r)
    out.offsets[r + 1] = out.offsets[r] + static_cast<std::size_t>(lengths[r]);
  return out;
}

GatheredRows::GatheredRows(const Teuchos::RCP<const CrsMatrix>& A, int owner) {
  const auto& comm = *A->getComm();
  const auto rowMap = A->getRowMap();
  if (comm.getSize() == 1) {  // A's own arrays; columns renumbered through the row map
    A_ = A;
    n_ = A->getNodeNumRows();
    const auto local = A->getLocalMatrixHost();
    static_assert(sizeof(local.graph.row_map(0)) == sizeof(std::size_t), "a local matrix's row offsets are size_t");
    static_assert(sizeof(local.graph.entries(0)) == sizeof(int), "a local matrix's column indices are int");
    ptr_ = reinterpret_cast<const std::size_t*>(local.graph.row_map.data());
    col_ = reinterpret_cast<const int*>(local.graph.entries.data());
    val_ = local.values.data();
    const auto colMap = A->getColMap();
    position_.resize(colMap->getNodeNumElements());
    for (std::size_t c = 0; c < position_.size(); ++c) {
      const auto l = rowMap->getLocalElement(colMap->getGlobalElement(static_cast<LocalOrdinal>(c)));
      if (l == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) throw std::invalid_argument(notSquare);
      position_[c] = static_cast<int>(l);
    }
    return;
  }
  RowsOnRank g = gatherRows(*A, owner);
  // The owner's verdict on the columns, to every rank: a refusal on the
  // owner alone would leave the others waiting in their next collective.
  int square = 1;
  if (comm.getRank() == owner) square = positionColumns(g) ? 1 : 0;
  Teuchos::broadcast(comm, owner, Teuchos::outArg(square));
  if (!square) throw std::invalid_argument(notSquare);
}

bool GatheredRows::positionColumns(RowsOnRank& g) {
  n_ = g.size();  // at most INT_MAX: gatherRows refused more on every rank
  // Global id -> position: a table over the ids' span when it is at most a
  // few times the rows (the layouts' ids are 0 .. n-1), else a sorted search.
  GlobalOrdinal lo = 0, hi = -1;
  if (n_ > 0) {
    const auto [a, b] = std::minmax_element(g.rows.begin(), g.rows.end());
    lo = *a, hi = *b;
  }
  std::vector<int> table;
  std::vector<std::pair<GlobalOrdinal, int>> sorted;
  const bool dense = n_ > 0 && static_cast<double>(hi - lo) < 4.0 * static_cast<double>(n_) + 1024.0;
  if (dense) {
    table.assign(static_cast<std::size_t>(hi - lo + 1), -1);
    for (std::size_t r = 0; r < n_; ++r) table[static_cast<std::size_t>(g.rows[r] - lo)] = static_cast<int>(r);
  } else {
    sorted.reserve(n_);
    for (std::size_t r = 0; r < n_; ++r) sorted.emplace_back(g.rows[r], static_cast<int>(r));
    std::sort(sorted.begin(), sorted.end());
  }
  const auto positionOf = [&](GlobalOrdinal id) {
    if (dense) return id < lo || id > hi ? -1 : table[static_cast<std::size_t>(id - lo)];
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(id, INT_MIN));
    return it != sorted.end() && it->first == id ? it->second : -1;
  };
  ownCol_.resize(g.columns.size());
  for (std::size_t e = 0; e < g.columns.size(); ++e) {
    ownCol_[e] = positionOf(g.columns[e]);
    if (ownCol_[e] < 0) {
      n_ = 0;
      return false;
    }
  }
  std::vector<GlobalOrdinal>().swap(g.columns);
  ownPtr_ = std::move(g.offsets);
  ownVal_ = std::move(g.values);
  ptr_ = ownPtr_.data();
  col_ = ownCol_.data();
  val_ = ownVal_.data();
  return true;
}

Teuchos::RCP<CrsMatrix> gatherToRank(const CrsMatrix& A, int owner,
                                     const Teuchos::RCP<const Teuchos::Comm<int>>& self) {
  checkZeroToN(*A.getRowMap());
  const auto n = A.getRowMap()->getGlobalNumElements();
  const RowsOnRank g = gatherRows(A, owner);
  if (A.getComm()->getRank() != owner) return Teuchos::null;
  // Row i of the one-rank matrix is global id i; its columns are sorted by
  // id, which is their local index on a column map of 0 .. n-1 (a square
  // matrix's columns are among its rows' ids).
  using LocalMatrix = CrsMatrix::local_matrix_device_type;
  typename LocalMatrix::row_map_type::non_const_type ptr("rows", n + 1);
  typename LocalMatrix::index_type::non_const_type ind("columns", g.columns.size());
  typename LocalMatrix::values_type::non_const_type val("values", g.values.size());
  std::vector<std::size_t> at(n, 0);
  for (std::size_t r = 0; r < g.size(); ++r) at[static_cast<std::size_t>(g.rows[r])] = r;
  std::vector<std::pair<GlobalOrdinal, double>> row;
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ptr(i) = k;
    const std::size_t r = at[i];
    row.clear();
    for (std::size_t e = g.offsets[r]; e < g.offsets[r + 1]; ++e) row.emplace_back(g.columns[e], g.values[e]);
    std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [cId, v] : row) ind(k) = static_cast<LocalOrdinal>(cId), val(k) = v, ++k;
  }
  ptr(n) = k;
  auto rows = Teuchos::rcp(new Map(n, n, 0, self));
  LocalMatrix local("gathered", static_cast<LocalOrdinal>(n), static_cast<LocalOrdinal>(n), k, val, ptr, ind);
  return Teuchos::rcp(new CrsMatrix(local, rows, rows, rows, rows));
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
