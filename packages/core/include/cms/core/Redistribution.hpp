// Moving a distributed object whole onto one rank and back, for work that
// runs on a communicator of that rank alone: the concurrent reduction of
// substructures (one substructure per rank, doc/architecture.md
// "Parallelism"). The rows' global ids must be 0 .. n-1.
#pragma once

#include <cstddef>
#include <vector>

#include "cms/core/TpetraTypes.hpp"

namespace Teuchos { template <class T> class Comm; }

namespace cms {

/// A distributed matrix's rows on one rank as compressed rows: each rank's
/// rows in rank order, each rank's in its row map's order (the order of
/// Tpetra::Details::computeGatherMap), columns as global ids in the order
/// each row stores them.
struct RowsOnRank {
  std::vector<GlobalOrdinal> rows;     ///< each row's global id
  std::vector<std::size_t> offsets;    ///< row r's entries: [offsets[r], offsets[r + 1])
  std::vector<GlobalOrdinal> columns;  ///< global column ids
  std::vector<double> values;
  std::size_t size() const { return rows.size(); }
};

/// A's rows on rank `owner` (empty elsewhere), moved by one MPI_Gatherv per
/// array. Tpetra's Import into a matrix on the gathered map, the way every
/// gathered factorisation went before, inserts the rows one at a time and
/// then builds a new graph: 0.35-0.8 s for the rotor hub's stiffness (58,281
/// rows) on two ranks, against 0.07-0.2 s this way (doc/benchmarks.md,
/// "Gathered rows"). Collective over A's communicator. Throws
/// std::length_error on every rank when the owner's rows or entries exceed
/// MPI's int counts.
RowsOnRank gatherRows(const CrsMatrix& A, int owner);

/// A square matrix's rows on rank `owner` in the gathered order (as
/// gatherRows), each column numbered by its row's position there, for a
/// factorisation on that rank (CHOLMOD's, the Sturm count's). On one rank
/// A's own arrays are read in place: a copy was a sixth of a factorisation's
/// page faults, and copying the rows into flat arrays 85 of the 217 MiB the
/// 54,000-DOF bar's Sturm count held at its peak (issue 18). Collective;
/// empty (size() 0) on the other ranks. Throws std::invalid_argument on
/// every rank when a column is not among the rows (a matrix that is not
/// square in its ids).
class GatheredRows {
public:
  GatheredRows(const Teuchos::RCP<const CrsMatrix>& A, int owner);
  std::size_t size() const { return n_; }
  std::size_t entries() const { return n_ == 0 ? 0 : ptr_[n_]; }
  /// Stored entries of row j.
  std::size_t length(std::size_t j) const { return ptr_[j + 1] - ptr_[j]; }
  /// f(position, value) for every stored entry of row j.
  template <class F>
  void forEach(std::size_t j, F&& f) const {
    for (std::size_t e = ptr_[j]; e < ptr_[j + 1]; ++e) f(position_.empty() ? col_[e] : position_[col_[e]], val_[e]);
  }
  /// f(position, value) for the entries of row j at positions <= j: of a
  /// symmetric matrix, row j is column j, and these its upper triangle
  /// (CHOLMOD's stype 1 input: the factorisations and the Sturm count).
  template <class F>
  void forEachUpper(std::size_t j, F&& f) const {
    forEach(j, [&](int i, double v) {
      if (static_cast<std::size_t>(i) <= j) f(i, v);
    });
  }

private:
  /// The owner's part: the columns renumbered to row positions; false (and
  /// empty) when one is not a row.
  bool positionColumns(RowsOnRank& g);

  std::size_t n_ = 0;
  const std::size_t* ptr_ = nullptr;
  const int* col_ = nullptr;
  const double* val_ = nullptr;
  std::vector<int> position_;  ///< A's column-map index -> row position (A's own arrays only)
  Teuchos::RCP<const CrsMatrix> A_;  ///< keeps A's arrays (one rank)
  std::vector<std::size_t> ownPtr_;  ///< the gathered rows' arrays (more ranks)
  std::vector<int> ownCol_;
  std::vector<double> ownVal_;
};

/// A's rows gathered onto rank `owner` of A's communicator and re-expressed
/// on `self`, a communicator holding that rank alone (same global ids,
/// contiguous row map). Collective over A's communicator; null on every
/// other rank. Throws std::invalid_argument for ids other than 0 .. n-1.
Teuchos::RCP<CrsMatrix> gatherToRank(const CrsMatrix& A, int owner,
                                     const Teuchos::RCP<const Teuchos::Comm<int>>& self);

/// The same for a multivector.
Teuchos::RCP<MultiVector> gatherToRank(const MultiVector& X, int owner,
                                       const Teuchos::RCP<const Teuchos::Comm<int>>& self);

/// The reverse: X on `self` (given on rank `owner` only, null elsewhere),
/// with `numVectors` columns (the same on every rank), distributed onto
/// `target`, a map of the world communicator over the same ids. Collective
/// over target's communicator.
Teuchos::RCP<MultiVector> scatterFromRank(const Teuchos::RCP<const MultiVector>& X, int owner, int numVectors,
                                          const Teuchos::RCP<const Map>& target);

}  // namespace cms
