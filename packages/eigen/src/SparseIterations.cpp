// The iterations of the sparse gyroscopic solve, one per method
// (SparseIterations.hpp).
#include "SparseIterations.hpp"

#include <memory>

#include <AnasaziBasicEigenproblem.hpp>
#include <AnasaziBlockDavidsonSolMgr.hpp>
#include <AnasaziBlockKrylovSchurSolMgr.hpp>
#include <AnasaziLOBPCGSolMgr.hpp>
#include <AnasaziTpetraAdapter.hpp>
#include <Tpetra_MultiVector.hpp>

#include "ArpackEigensolver.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/HashRandom.hpp"

namespace cms::eigen::detail {

namespace {

/// A deterministic start block, the same for any rank count.
Teuchos::RCP<MultiVector> startBlock(const Teuchos::RCP<const Map>& map, int cols) {
  auto X = Teuchos::rcp(new MultiVector(map, cols));
  auto v = X->getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (size_t i = 0; i < map->getNodeNumElements(); ++i)
    for (int j = 0; j < cols; ++j) v(i, j) = hashSigned(map->getGlobalElement(i), 5u + j);
  return X;
}

using Problem = Anasazi::BasicEigenproblem<double, MultiVector, Operator>;

/// The Anasazi eigenproblem of the method: R_s itself for Krylov-Schur (in
/// the I* inner product on the symmetric path); for Davidson / LOBPCG the
/// symmetric pencil (I* (-R_s), I*), largest eigenvalues 1/(omega^2 + s),
/// preconditioned by I*^-1 so that a preconditioned residual is a step of
/// the Krylov space of -R_s. (The un-inverted pencil (K* + s I*, I*) with
/// its exact preconditioner was measured unusable: its residual cannot fall
/// below eps ||K*|| / omega_1^2.)
Teuchos::RCP<Problem> anasaziProblem(SparseEigenproblem& p, const IterationSettings& c, int nev) {
  const auto& sys = *p.system;
  const auto state = p.transform->getDomainMap();
  Teuchos::RCP<Problem> problem;
  if (c.eigensolver == "Block Krylov-Schur") {
    problem = Teuchos::rcp(new Problem(p.transform,
                                       p.symmetric ? Teuchos::RCP<Operator>(p.innerProduct) : Teuchos::null,
                                       startBlock(state, c.blockSize)));
  } else {
    auto mFactor = std::make_shared<SparseDirectSolver>(sys.M, c.symmetricMethod);
    CMS_INPUT_CHECK(mFactor->factor() != SparseDirectSolver::Outcome::Factored,
                    "SparseGyroscopicSolver: M is not positive definite (" << mFactor->failure() << ")");
    if (!p.kFactor) {
      p.kFactor = std::make_shared<SparseDirectSolver>(sys.K, c.symmetricMethod);
      p.kFactor->factor();
    }
    auto Iinv = Teuchos::rcp(new StateInverseInnerProduct(sys, mFactor, p.kFactor));
    problem = Teuchos::rcp(new Problem(Teuchos::rcp(new ProductOperator(p.innerProduct, p.transform)),
                                       p.innerProduct, startBlock(state, c.blockSize)));
    problem->setPrec(Iinv);
  }
  problem->setHermitian(p.symmetric);
  problem->setNEV(nev);
  TEUCHOS_TEST_FOR_EXCEPTION(!problem->setProblem(), std::logic_error, "Anasazi rejected the eigenproblem set-up");
  return problem;
}

}  // namespace

IterationOutcome iterateAnasazi(SparseEigenproblem& p, const IterationSettings& c, int nev, int numBlocks) {
  IterationOutcome out;
  const auto problem = anasaziProblem(p, c, nev);
  const bool krylovSchur = c.eigensolver == "Block Krylov-Schur";
  Teuchos::ParameterList pl;
  pl.set("Which", std::string("LM"));
  if (!krylovSchur) pl.set("Orthogonalization", std::string("DGKS"));  // SVQB looped (2 ranks)
  pl.set("Block Size", c.blockSize);
  pl.set("Convergence Tolerance", c.tol);
  pl.set("Maximum Restarts", c.maxRestarts);
  pl.set("Verbosity", c.verbosity >= 2 ? Anasazi::Errors + Anasazi::Warnings + Anasazi::IterationDetails +
                                             Anasazi::FinalSummary
                                       : (c.verbosity == 1 ? Anasazi::Errors + Anasazi::Warnings +
                                                                 Anasazi::FinalSummary
                                                           : Anasazi::Errors));
  Anasazi::ReturnType ret = Anasazi::Unconverged;
  // A breakdown inside Anasazi (LOBPCG's Cholesky of a dependent basis, a
  // Davidson restart on an empty block) is an outcome, not a crash.
  try {
    if (krylovSchur) {
      pl.set("Num Blocks", numBlocks);
      Anasazi::BlockKrylovSchurSolMgr<double, MultiVector, Operator> mgr(problem, pl);
      ret = mgr.solve();
      out.iterations = mgr.getNumIters();
    } else if (c.eigensolver == "Block Davidson") {
      pl.set("Num Blocks", numBlocks);
      pl.set("Use Locking", true);
      pl.set("Max Locked", nev);
      Anasazi::BlockDavidsonSolMgr<double, MultiVector, Operator> mgr(problem, pl);
      ret = mgr.solve();
      out.iterations = mgr.getNumIters();
    } else {
      pl.set("Maximum Iterations", 10 * c.maxRestarts);
      pl.set("Use Locking", true);
      pl.set("Max Locked", nev);
      Anasazi::LOBPCGSolMgr<double, MultiVector, Operator> mgr(problem, pl);
      ret = mgr.solve();
      out.iterations = mgr.getNumIters();
    }
  } catch (const std::exception& e) {
    out.solver = "Anasazi " + c.eigensolver;
    out.failure = std::string("Anasazi broke down: ") + std::string(e.what()).substr(0, 300);
    return out;
  }
  out.solver = "Anasazi " + c.eigensolver + (p.symmetric ? " (Hermitian, I* inner product)" : " (non-Hermitian)");
  const auto& sol = problem->getSolution();
  out.converged = sol.numVecs;
  if (ret != Anasazi::Converged) out.note = "Anasazi did not converge all requested vectors";
  if (sol.numVecs > 0) out.vectors = sol.Evecs;
  return out;
}

IterationOutcome iterateArpack(const SparseEigenproblem& p, const IterationSettings& c, int nev) {
  IterationOutcome out;
  const GlobalOrdinal N = p.system->globalSize();
  const int ncv = static_cast<int>(std::min<GlobalOrdinal>(2 * N, std::max(2 * nev + 1, nev + 20)));
  auto a = arpackSolve(*p.transform, p.symmetric ? p.innerProduct.get() : nullptr, p.symmetric, nev, ncv, c.tol,
                       c.maxRestarts);
  out.solver = p.symmetric ? "PARPACK pdsaupd (mode 3, B = I*)" : "PARPACK pdnaupd";
  out.iterations = a.iterations;
  if (a.info < 0 || a.vectors.is_null()) {
    out.failure = "ARPACK: " + a.message;
    return out;
  }
  if (!a.message.empty()) out.note = "ARPACK: " + a.message;
  out.vectors = a.vectors;
  out.converged = a.numConverged;
  return out;
}

}  // namespace cms::eigen::detail
