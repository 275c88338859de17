// Moving a distributed object whole onto one rank and back, for work that
// runs on a communicator of that rank alone: the concurrent reduction of
// substructures (one substructure per rank, doc/architecture.md
// "Parallelism"). The rows' global ids must be 0 .. n-1.
#pragma once

#include "cms/core/TpetraTypes.hpp"

namespace Teuchos { template <class T> class Comm; }

namespace cms {

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
