// Internal to the eigen package: PARPACK (ARPACK's MPI version) by reverse
// communication on a Tpetra operator, returning the Ritz vectors for the
// quadratic Rayleigh-Ritz extraction (doc/theory.md, "ARPACK path").
#pragma once

#include <string>

#include <Tpetra_Operator.hpp>

#include "cms/core/TpetraTypes.hpp"

namespace cms::eigen::detail {

struct ArpackOutcome {
  Teuchos::RCP<MultiVector> vectors;  ///< converged Ritz vectors (real and imaginary parts)
  int numConverged = 0;
  int iterations = 0;
  int info = 0;         ///< ARPACK's info from the last call (0 = normal)
  std::string message;  ///< ARPACK's meaning of a non-zero info
};

/// symmetric: pdsaupd in mode 3 with B = `inner` (OP is B-self-adjoint);
/// otherwise pdnaupd in mode 1. `which` is "LM" for the spectral transform.
ArpackOutcome arpackSolve(const Operator& op, const Operator* inner, bool symmetric, int nev,
                          int ncv, double tol, int maxIterations);

}  // namespace cms::eigen::detail
