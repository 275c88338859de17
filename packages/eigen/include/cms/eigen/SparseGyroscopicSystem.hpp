// A distributed gyroscopic system M q'' + G q' + K q = 0 (seed eq. (19)) of a
// full ("truth") model: three fill-complete Tpetra::CrsMatrix on one row map,
// and optionally a viscous damping matrix D: M q'' + (G + D) q' + K q = 0.
#pragma once

#include "cms/core/TpetraTypes.hpp"

namespace cms::eigen {

struct SparseGyroscopicSystem {
  Teuchos::RCP<const CrsMatrix> M, G, K;
  /// Viscous damping (symmetric, on M's maps); null for none. With D the
  /// solver takes the general (non-Hermitian) path.
  Teuchos::RCP<const CrsMatrix> D;
  /// Circulatory stiffness (skew, on M's maps; theory §13.1): a
  /// stationary-frame rotor's material damping turning with it. Null for
  /// none; with N the solver takes the general path on K + N.
  Teuchos::RCP<const CrsMatrix> N;

  /// Throws cms::InputError (on every rank) naming the matrix and the defect
  /// when a matrix is missing or not fill-complete, the row/domain/range maps
  /// differ, an entry is NaN/Inf, diag(M) has a non-positive entry, or M, K
  /// (and D) are not symmetric / G (and N) not skew: tested with random probe vectors x, y as
  /// |x^T A y -/+ y^T A x| <= relTol ||A||_F ||x|| ||y||, which catches any
  /// structural defect with probability one at O(nnz) cost.
  void validate(double relTol = 1e-10) const;

  GlobalOrdinal globalSize() const;
  /// Whether D or N is present and not zero (||.||_F > 0): the system is
  /// not conservative and the general path (and its refinement) applies.
  /// Collective.
  bool damped() const;
};

}  // namespace cms::eigen
