// Internal to the eigen package: the sparse gyroscopic solve split as
// Anasazi splits it (doc/architecture.md, "eigen"):
//   - the eigenproblem (this struct): the system, the spectral shift, how
//     many modes, and the form chosen for it (symmetric when K > 0), with
//     the spectral transform and inner product that form iterates on;
//   - the iterations, one per method (SparseIterations.hpp: Anasazi's Block
//     Krylov-Schur, Block Davidson, LOBPCG; PARPACK), which only return
//     converged vectors of the transform;
//   - the extraction of gyroscopic modes from those vectors
//     (QuadraticRitz.hpp: Rayleigh-Ritz of the quadratic problem, residuals
//     from the user's M, G, K);
//   - the manager, SparseGyroscopicSolver::solve: decides the form and says
//     why, picks the iteration, sets the status, and re-solves once when the
//     Sturm count disagrees with the returned set (checkLowestModes).
#pragma once

#include <memory>
#include <string>

#include "SpectralTransform.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/eigen/SparseGyroscopicSystem.hpp"

namespace cms::eigen::detail {

struct SparseEigenproblem {
  const SparseGyroscopicSystem* system = nullptr;
  double shift = 0.0;  ///< s of R_s = (H^2 - s)^-1
  int nModes = 0;      ///< modes wanted (each a double eigenvalue of R_s)
  /// Meirovitch's form: K > 0, so -R_s is self-adjoint in the I* inner
  /// product; otherwise the general non-Hermitian iteration.
  bool symmetric = false;
  std::shared_ptr<SparseDirectSolver> kFactor;     ///< CHOLMOD's factor of K when K > 0
  Teuchos::RCP<SpectralTransform> transform;       ///< R_s (times -1 on the symmetric path), factored
  Teuchos::RCP<StateInnerProduct> innerProduct;    ///< I* = diag(M, K)
};

}  // namespace cms::eigen::detail
