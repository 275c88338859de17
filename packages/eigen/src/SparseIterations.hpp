// Internal to the eigen package: the iterations of the sparse gyroscopic
// solve, one per method (SparseEigenproblem.hpp for the roles). Each runs on
// the problem's factored spectral transform and returns its converged
// vectors, or why it could not; none decides a status or extracts modes.
// Apart from SparseGyroscopicSolver.cpp so that Anasazi's solver-manager
// templates are compiled in one translation unit of their own.
#pragma once

#include <string>

#include "SparseEigenproblem.hpp"
#include "cms/core/TpetraTypes.hpp"

namespace cms::eigen::detail {

/// The iteration's own settings (the solver's "Eigensolver", "Block Size",
/// ... parameters, validated by SparseGyroscopicSolver).
struct IterationSettings {
  std::string eigensolver;  ///< "Block Krylov-Schur", "Block Davidson", "LOBPCG" or "ARPACK"
  int blockSize = 2, maxRestarts = 300, verbosity = 0;
  double tol = 1e-10;
  /// SparseDirectSolver method for the symmetric positive definite M and K
  /// that Block Davidson and LOBPCG precondition with: "CHOLMOD" (gathered)
  /// or "MUMPS-LDLT" (across the ranks; "Direct Solver").
  std::string symmetricMethod = "CHOLMOD";
};

struct IterationOutcome {
  Teuchos::RCP<MultiVector> vectors;  ///< converged vectors of the transform (null if none)
  int converged = 0;
  int iterations = 0;
  std::string solver;   ///< what ran, e.g. "Anasazi LOBPCG (Hermitian, I* inner product)"
  std::string failure;  ///< non-empty: a breakdown (NumericalIssue), said in the reason
  std::string note;     ///< said in the reason (not all converged, ARPACK's message)
};

/// Anasazi's Block Krylov-Schur (I* inner product on the symmetric path,
/// non-Hermitian otherwise), or Block Davidson / LOBPCG on the symmetric
/// pencil (I* (-R_s), I*) preconditioned by I*^-1. `nev` eigenvalues of the
/// transform (two per mode), `numBlocks` blocks of the subspace. Collective.
IterationOutcome iterateAnasazi(SparseEigenproblem& problem, const IterationSettings& settings, int nev,
                                int numBlocks);

/// PARPACK: pdsaupd in mode 3 with B = I* on the symmetric path, pdnaupd
/// otherwise. Collective.
IterationOutcome iterateArpack(const SparseEigenproblem& problem, const IterationSettings& settings, int nev);

}  // namespace cms::eigen::detail
