// Holding DOFs at zero without renumbering: a copy of a matrix whose held
// rows and columns are zero except the diagonal. With diagonal 1 for K and 0
// for M, a solve or an eigenproblem on the copies is the problem with those
// DOFs fixed, and its solutions are exactly zero there (the prestress solve of
// a child held at its attachment, fixed-interface vectors; doc/theory.md §11).
#pragma once

#include <memory>
#include <vector>

#include "cms/core/TpetraTypes.hpp"

namespace cms {

/// Collective. `rows` are global rows of A's row map (the same list on every
/// rank, any order, duplicates allowed). A must be fill-complete.
Teuchos::RCP<CrsMatrix> holdDofs(const CrsMatrix& A, const std::vector<GlobalOrdinal>& rows, double diagonal);

/// The same for a stiffness to be factored: each held row keeps A's own
/// diagonal entry (or, where that is not positive, the largest diagonal
/// magnitude of A), so holding DOFs does not ruin the pivot ratio that
/// tells a definite matrix from one definite only by rounding (a unit
/// diagonal beside entries of 1e16 would).
Teuchos::RCP<CrsMatrix> holdDofsScaled(const CrsMatrix& A, const std::vector<GlobalOrdinal>& rows);

class SparseDirectSolver;

/// A factorisation of holdDofsScaled(*base, held) (or of *base itself when
/// `held` is empty), kept by the layer that made it for a later one that
/// needs the same matrix factored: the centrifugal prestress solve's K with
/// a child's attachment held is the reduction's held stiffness (theory
/// §10.2, §11.4), so the reduction need not factor it again (issue 18).
/// A user checks `base` (the same matrix object, whose values nobody
/// changes after assembly) and `held` (sorted, unique) before relying on it.
struct HeldFactor {
  std::shared_ptr<const SparseDirectSolver> solver;
  Teuchos::RCP<const CrsMatrix> matrix;  ///< what `solver` factored
  Teuchos::RCP<const CrsMatrix> base;    ///< the matrix before holding
  std::vector<GlobalOrdinal> held;       ///< sorted, unique
  /// Bytes it holds: the factor's entries (8 bytes each; none counted when
  /// the solver does not report them) and `matrix` when it is a copy; the
  /// same on every rank.
  double bytes = 0.0;
};

/// Zero the held rows of every column of X (owned rows only).
void zeroHeldRows(MultiVector& X, const std::vector<GlobalOrdinal>& rows);

}  // namespace cms
