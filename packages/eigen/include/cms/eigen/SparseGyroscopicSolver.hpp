// Sparse distributed gyroscopic eigensolver for full models (1e5-1e6 DOFs).
//
// Every method iterates on the same real spectral transformation of the
// Hamiltonian matrix H of the first-order system (doc/theory.md, "Sparse path"):
//     R_s = (H^2 - s)^-1,   eigenvalues 1 / (lambda^2 - s),
// applied through sparse factorisations of Q(mu) = mu^2 M + mu G + K only
// (never forming K* or I*^-1):
//   s = 0           two solves with K per application (K factored once);
//   s = tau^2 > 0   solves with Q(-tau), Q(tau): nonsingular for a free body
//                   (singular K), the "K + sigma M" style shift;
//   s = -w_t^2 < 0  one complex solve with Q(i w_t): frequencies near w_t.
// When K > 0 (detected by a CHOLMOD Cholesky), -R_s = (K* + s I*)^-1 I* is
// self-adjoint in the I* = diag(M, K) inner product: Meirovitch's symmetric
// form (seed eqs. (21)-(24)) without forming it, solved by Anasazi (Block
// Krylov-Schur, Block Davidson or LOBPCG, block size >= 2 because every
// eigenvalue is double) or PARPACK dsaupd. Otherwise the general path runs
// Anasazi's non-Hermitian Block Krylov-Schur or PARPACK dnaupd on R_s.
// Either way the modes are extracted by a Rayleigh-Ritz projection of the
// quadratic problem onto the converged vectors, solved by the dense solver,
// and every mode's residual is recomputed from M, G, K. When K > 0 and the
// lowest frequencies are wanted (Shift >= 0), the returned set is checked by
// a Sturm count (checkLowestModes, doc/theory.md §5).
#pragma once

#include <functional>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/eigen/GyroscopicModes.hpp"
#include "cms/eigen/GyroscopicSolverManager.hpp"
#include "cms/eigen/SparseGyroscopicSystem.hpp"
#include "cms/eigen/SturmCount.hpp"

namespace cms::eigen {

/// The distributed manager (GyroscopicSolverManager.hpp). Beyond the
/// validation: "Number of Modes" >= 1 and "Block Size" >= 2 (cms::InputError).
class SparseGyroscopicSolver : public GyroscopicSolverManager<SparseGyroscopicSystem> {
public:
  static Teuchos::RCP<const Teuchos::ParameterList> getValidParameters();
  explicit SparseGyroscopicSolver(const Teuchos::ParameterList& params = Teuchos::ParameterList());
  /// Collective. Modes carry this rank's rows of q. On the symmetric path with
  /// Shift >= 0 a converged set is checked by checkLowestModes.
  GyroscopicResult solve(const SparseGyroscopicSystem& system) const override;
};

/// The sparse path's completeness check, factored out of solve() so that a
/// wrong set can be injected in tests. `result` holds the returned modes
/// (sorted by frequency, result.numRequested of them wanted); `known` every
/// accurate frequency the iteration found, ascending (the returned ones
/// first). The Sturm count (`countBelow`, by default sturmCount(system, w))
/// at a cut past the cluster of the highest returned frequency must equal
/// the number known below it. If not, `resolve(asked, known)` runs the
/// iteration once more for `asked` = requested + shortfall + margin modes
/// (filling `known` anew) and its lowest numRequested modes are checked
/// again; a set that still disagrees comes back as NumericalIssue with the
/// counts and the frequency in its reason. A set that agrees gets the
/// confirmation appended to its reason, and, when the request cuts a
/// cluster, which modes share it. Collective.
GyroscopicResult checkLowestModes(
    const SparseGyroscopicSystem& system, GyroscopicResult result, const std::vector<double>& known,
    const std::function<GyroscopicResult(int asked, std::vector<double>& known)>& resolve,
    const std::function<SparseSturmCount(double)>& countBelow = nullptr, double residualTol = 1e-8);

}  // namespace cms::eigen
