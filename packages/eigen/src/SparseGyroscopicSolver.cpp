#include "cms/eigen/SparseGyroscopicSolver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <sstream>

#include <AnasaziBasicEigenproblem.hpp>
#include <AnasaziBlockDavidsonSolMgr.hpp>
#include <AnasaziBlockKrylovSchurSolMgr.hpp>
#include <AnasaziLOBPCGSolMgr.hpp>
#include <AnasaziTpetraAdapter.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include "ArpackEigensolver.hpp"
#include "SpectralTransform.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/HashRandom.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/SturmCount.hpp"

namespace cms::eigen {

using cplx = std::complex<double>;
using MVT = Anasazi::MultiVecTraits<double, MultiVector>;

namespace {

const double kTwoPi = 2.0 * M_PI;

/// A deterministic start block, the same for any rank count.
Teuchos::RCP<MultiVector> startBlock(const Teuchos::RCP<const Map>& map, int cols) {
  auto X = Teuchos::rcp(new MultiVector(map, cols));
  auto v = X->getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (size_t i = 0; i < map->getNodeNumElements(); ++i)
    for (int j = 0; j < cols; ++j) v(i, j) = hashSigned(map->getGlobalElement(i), 5u + j);
  return X;
}

/// Orthonormal basis of span(B) by the eigen-decomposition of its Gram matrix,
/// dropping directions below `relTol` (SVQB with truncation): the converged
/// vectors of a double eigenvalue may be (nearly) dependent once halved.
Teuchos::RCP<MultiVector> orthonormalBasis(const MultiVector& B, double relTol) {
  const int k = static_cast<int>(B.getNumVectors());
  DenseMatrix Gm(k, k);
  MVT::MvTransMv(1.0, B, B, Gm);
  std::vector<double> w(k), work(std::max(1, 4 * k));
  int info = 0;
  Teuchos::LAPACK<int, double>().SYEV('V', 'U', k, Gm.values(), k, w.data(), work.data(),
                                      static_cast<int>(work.size()), &info);
  TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError, "orthonormalBasis: dsyev info " << info);
  const double wmax = k > 0 ? w[k - 1] : 0.0;
  std::vector<int> keep;
  for (int j = k - 1; j >= 0; --j)
    if (w[j] > relTol * wmax) keep.push_back(j);
  DenseMatrix T(k, static_cast<int>(keep.size()));
  for (std::size_t c = 0; c < keep.size(); ++c)
    for (int i = 0; i < k; ++i) T(i, c) = Gm(i, keep[c]) / std::sqrt(w[keep[c]]);
  auto Q = Teuchos::rcp(new MultiVector(B.getMap(), std::max<size_t>(keep.size(), 1)));
  if (!keep.empty()) MVT::MvTimesMatAddMv(1.0, B, T, 0.0, *Q);
  return Q;
}

// |A|: the entrywise absolute value, same graph (GyroscopicMode::scale).
Teuchos::RCP<CrsMatrix> absoluteValues(const CrsMatrix& A) {
  auto B = Teuchos::rcp(new CrsMatrix(A, Teuchos::Copy));
  B->resumeFill();
  typename CrsMatrix::nonconst_local_inds_host_view_type cols("cols", A.getNodeMaxNumRowEntries());
  typename CrsMatrix::nonconst_values_host_view_type vals("vals", A.getNodeMaxNumRowEntries());
  for (LocalOrdinal r = 0; r < static_cast<LocalOrdinal>(A.getNodeNumRows()); ++r) {
    size_t count = 0;
    A.getLocalRowCopy(r, cols, vals, count);
    for (size_t e = 0; e < count; ++e) vals(e) = std::abs(vals(e));
    B->replaceLocalValues(r, static_cast<LocalOrdinal>(count), vals.data(), cols.data());
  }
  B->fillComplete(A.getDomainMap(), A.getRangeMap());
  return B;
}

DenseMatrix projectOnto(const CrsMatrix& A, const MultiVector& Q) {
  MultiVector AQ(Q.getMap(), Q.getNumVectors());
  A.apply(Q, AQ);
  DenseMatrix R(static_cast<int>(Q.getNumVectors()), static_cast<int>(Q.getNumVectors()));
  MVT::MvTransMv(1.0, Q, AQ, R);
  return R;
}

struct Config {
  std::string method, eigensolver, linearSolver;
  int nModes, blockSize, numBlocks, maxRestarts, verbosity;
  double tol, shift, residualTol, rigidTol, instabTol;
};

}  // namespace

Teuchos::RCP<const Teuchos::ParameterList> SparseGyroscopicSolver::getValidParameters() {
  static Teuchos::RCP<const Teuchos::ParameterList> valid = [] {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Sparse Gyroscopic Solver"));
    Teuchos::setStringToIntegralParameter<int>(
        "Method", "Auto",
        "Symmetric: Meirovitch's I*-self-adjoint form (K must be positive definite); General: "
        "non-Hermitian iteration valid for any K; Auto: Symmetric if CHOLMOD finds K > 0",
        Teuchos::tuple<std::string>("Auto", "Symmetric", "General"), pl.get());
    Teuchos::setStringToIntegralParameter<int>(
        "Eigensolver", "Block Krylov-Schur",
        "Iterative eigensolver: Anasazi's Block Krylov-Schur (any path), Block Davidson or "
        "LOBPCG (symmetric path, Shift >= 0), or PARPACK (pdsaupd / pdnaupd)",
        Teuchos::tuple<std::string>("Block Krylov-Schur", "Block Davidson", "LOBPCG", "ARPACK"),
        pl.get());
    Teuchos::setStringToIntegralParameter<int>(
        "Linear Solver", "KLU2",
        "Sparse direct solver for shifted Q(mu) = mu^2 M + mu G + K, which is nonsymmetric, so an "
        "LU (KLU2; Tacho is Cholesky-only and is not offered); K alone is "
        "factored by CHOLMOD when it is positive definite",
        Teuchos::tuple<std::string>("KLU2"), pl.get());
    pl->set("Number of Modes", 10, "How many modes (one per +/- frequency pair) to return");
    pl->set("Shift", 0.0,
            "s in (H^2 - s)^-1: 0 targets the lowest frequencies; s > 0 the lowest too but "
            "regularises a singular K (free bodies); s < 0 targets frequencies near sqrt(-s) rad/s");
    pl->set("Block Size", 2, "Block size (>= 2: every eigenvalue of the transform is double)");
    pl->set("Number of Blocks", 0, "Krylov/Davidson subspace blocks; 0 picks max(3 nev / bs, 10)");
    pl->set("Maximum Restarts", 300, "Restarts (Anasazi) or iterations (ARPACK) before giving up");
    pl->set("Convergence Tolerance", 1e-10, "Relative residual tolerance of the iteration");
    pl->set("Residual Tolerance", 1e-8,
            "A returned mode whose backward error ||Q(lambda) q|| / ((||K|| + |lambda| ||G|| + "
            "|lambda|^2 ||M||) ||q||) exceeds this makes the status NotConverged");
    pl->set("Rigid Body Tolerance", 1e-6, "As for the dense solver");
    pl->set("Instability Tolerance", 1e-7, "As for the dense solver");
    pl->set("Verbosity", 0, "0 silent, 1 summary, 2 iteration details (Anasazi's output on rank 0)");
    return pl;
  }();
  return valid;
}

SparseGyroscopicSolver::SparseGyroscopicSolver(const Teuchos::ParameterList& params)
    : params_(params) {
  try {
    params_.validateParametersAndSetDefaults(*getValidParameters());
  } catch (const std::exception& e) {
    throw InputError(std::string("SparseGyroscopicSolver: invalid parameter: ") + e.what());
  }
  const int k = params_.get<int>("Number of Modes"), bs = params_.get<int>("Block Size");
  CMS_INPUT_CHECK(k < 1, "SparseGyroscopicSolver: \"Number of Modes\" = " << k << " must be >= 1");
  CMS_INPUT_CHECK(bs < 2, "SparseGyroscopicSolver: \"Block Size\" = "
                              << bs << " must be >= 2: every eigenvalue is double");
  CMS_INPUT_CHECK(!(params_.get<double>("Convergence Tolerance") > 0.0),
                  "SparseGyroscopicSolver: \"Convergence Tolerance\" must be positive");
  CMS_INPUT_CHECK(!std::isfinite(params_.get<double>("Shift")),
                  "SparseGyroscopicSolver: \"Shift\" must be finite");
}

namespace {

/// One run of the iteration for `nModes` modes, and what the Sturm check of
/// its set needs: every accurate frequency it found (ascending; the returned
/// ones are the lowest of them) and whether the check applies.
struct Attempt {
  GyroscopicResult result;
  std::vector<double> known;
  bool checkable = false;  ///< symmetric path (K > 0), lowest frequencies targeted (s >= 0)
};

Attempt solveAttempt(const Teuchos::ParameterList& params, const SparseGyroscopicSystem& sys, int nModes) {
  Config c{params.get<std::string>("Method"), params.get<std::string>("Eigensolver"),
           params.get<std::string>("Linear Solver"), nModes,
           params.get<int>("Block Size"), params.get<int>("Number of Blocks"),
           params.get<int>("Maximum Restarts"), params.get<int>("Verbosity"),
           params.get<double>("Convergence Tolerance"), params.get<double>("Shift"),
           params.get<double>("Residual Tolerance"), params.get<double>("Rigid Body Tolerance"),
           params.get<double>("Instability Tolerance")};
  Attempt attempt;
  GyroscopicResult& result = attempt.result;
  const GlobalOrdinal N = sys.globalSize();
  CMS_INPUT_CHECK(c.nModes > N, "SparseGyroscopicSolver: \"Number of Modes\" = "
                                    << c.nModes << " but the system has only " << N
                                    << " DOFs, hence " << N << " modes");
  const auto rowMap = sys.M->getRowMap();
  const auto comm = rowMap->getComm();

  // 1. Which form: Meirovitch's needs K > 0, which CHOLMOD tells (and its
  //    factor is the K-solve of the unshifted transform).
  result.numRequested = c.nModes;
  bool symmetric = c.method == "Symmetric";
  std::shared_ptr<SparseDirectSolver> kFactor;
  if (c.method != "General") {
    kFactor = std::make_shared<SparseDirectSolver>(sys.K, "CHOLMOD");
    const auto out = kFactor->factor();
    const bool posdef = out == SparseDirectSolver::Outcome::Factored;
    CMS_INPUT_CHECK(c.method == "Symmetric" && !posdef,
                    "SparseGyroscopicSolver: Method \"Symmetric\" needs K > 0 (I* = diag(M,K) > 0, "
                    "seed eq. (23)), but " << kFactor->failure() << "; use \"Auto\" or \"General\"");
    symmetric = posdef;
    result.reason = posdef ? "K positive definite (CHOLMOD): Meirovitch's symmetric form, seed eq. (24)"
                           : "K is not positive definite (" + kFactor->failure() +
                                 "): general non-Hermitian iteration";
    if (!posdef) kFactor.reset();
  } else {
    result.reason = "requested";
  }
  CMS_INPUT_CHECK(!symmetric && (c.eigensolver == "Block Davidson" || c.eigensolver == "LOBPCG"),
                  "SparseGyroscopicSolver: \"" << c.eigensolver
                      << "\" needs the symmetric path (K > 0); " << result.reason);
  CMS_INPUT_CHECK(c.shift < 0.0 && (c.eigensolver == "Block Davidson" || c.eigensolver == "LOBPCG"),
                  "SparseGyroscopicSolver: \"" << c.eigensolver
                      << "\" needs a definite transform: \"Shift\" >= 0");

  // 2. The spectral transform, factored once.
  const double sign = symmetric ? -1.0 : 1.0;  // -R is I*-positive when K > 0, s >= 0
  auto R = Teuchos::rcp(new detail::SpectralTransform(sys, c.shift, sign, c.linearSolver, "KLU2"));
  if (kFactor && c.shift == 0.0) R->adoptStiffnessFactor(kFactor);
  const std::string why = R->factor();
  if (!why.empty()) {
    result.status = SolveStatus::NumericalIssue;
    result.solver = "none";
    result.reason += "; " + why;
    return attempt;
  }
  const auto state = R->getDomainMap();
  auto Istar = Teuchos::rcp(new detail::StateInnerProduct(sys));

  // 3. Iterate. Each mode is a double eigenvalue of R: ask for 2 per mode.
  const int nev = static_cast<int>(std::min<GlobalOrdinal>(2 * c.nModes, 2 * N - 1));
  // The automatic subspace never exceeds the state dimension 2N (Anasazi
  // refuses a basis longer than the vectors); a problem too small for any
  // Krylov subspace is reported, not attempted: the dense solver is the
  // right tool there.
  const int maxBlocks = static_cast<int>(std::min<GlobalOrdinal>(2 * N / c.blockSize, 1 << 20));
  const int numBlocks =
      c.numBlocks > 0 ? c.numBlocks : std::min(std::max(3 * nev / c.blockSize + 1, 10), maxBlocks);
  if (c.eigensolver != "ARPACK" && numBlocks * c.blockSize < nev + c.blockSize) {
    result.status = SolveStatus::NumericalIssue;
    result.solver = "none";
    result.reason += "; " + std::to_string(N) + " DOFs leave no room for a Krylov subspace of " +
                     std::to_string(numBlocks) + " blocks of " + std::to_string(c.blockSize) + " for " +
                     std::to_string(c.nModes) + " modes: use DenseGyroscopicSolver for a model this small";
    return attempt;
  }
  Teuchos::RCP<MultiVector> ritz;
  int converged = 0;
  std::string solverName;
  if (c.eigensolver == "ARPACK") {
    const int ncv = static_cast<int>(std::min<GlobalOrdinal>(2 * N, std::max(2 * nev + 1, nev + 20)));
    auto out = detail::arpackSolve(*R, symmetric ? Istar.get() : nullptr, symmetric, nev, ncv,
                                   c.tol, c.maxRestarts);
    solverName = symmetric ? "PARPACK pdsaupd (mode 3, B = I*)" : "PARPACK pdnaupd";
    result.iterations = out.iterations;
    if (out.info < 0 || out.vectors.is_null()) {
      result.status = SolveStatus::NumericalIssue;
      result.solver = solverName;
      result.reason += "; ARPACK: " + out.message;
      return attempt;
    }
    if (!out.message.empty()) result.reason += "; ARPACK: " + out.message;
    ritz = out.vectors;
    converged = out.numConverged;
  } else {
    using Problem = Anasazi::BasicEigenproblem<double, MultiVector, Operator>;
    Teuchos::RCP<Problem> problem;
    const bool krylovSchur = c.eigensolver == "Block Krylov-Schur";
    if (krylovSchur)
      problem = Teuchos::rcp(new Problem(R, symmetric ? Teuchos::RCP<Operator>(Istar) : Teuchos::null,
                                         startBlock(state, c.blockSize)));
    else {
      // Davidson / LOBPCG: the symmetric pencil (I* (-R_s), I*), largest
      // eigenvalues 1/(omega^2 + s), preconditioned by I*^-1 so that a
      // preconditioned residual is a step of the Krylov space of -R_s. (The
      // un-inverted pencil (K* + s I*, I*) with its exact preconditioner was
      // measured unusable: its residual cannot fall below eps ||K*|| / omega_1^2.)
      auto mFactor = std::make_shared<SparseDirectSolver>(sys.M, "CHOLMOD");
      CMS_INPUT_CHECK(mFactor->factor() != SparseDirectSolver::Outcome::Factored,
                      "SparseGyroscopicSolver: M is not positive definite ("
                          << mFactor->failure() << ")");
      if (!kFactor) {
        kFactor = std::make_shared<SparseDirectSolver>(sys.K, "CHOLMOD");
        kFactor->factor();
      }
      auto Iinv = Teuchos::rcp(new detail::StateInverseInnerProduct(sys, mFactor, kFactor));
      problem = Teuchos::rcp(new Problem(Teuchos::rcp(new detail::ProductOperator(Istar, R)), Istar,
                                         startBlock(state, c.blockSize)));
      problem->setPrec(Iinv);
    }
    problem->setHermitian(symmetric);
    problem->setNEV(nev);
    TEUCHOS_TEST_FOR_EXCEPTION(!problem->setProblem(), std::logic_error,
                               "Anasazi rejected the eigenproblem set-up");
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
    std::string breakdown;
    try {
      if (krylovSchur) {
        pl.set("Num Blocks", numBlocks);
        Anasazi::BlockKrylovSchurSolMgr<double, MultiVector, Operator> mgr(problem, pl);
        ret = mgr.solve();
        result.iterations = mgr.getNumIters();
      } else if (c.eigensolver == "Block Davidson") {
        pl.set("Num Blocks", numBlocks);
        pl.set("Use Locking", true);
        pl.set("Max Locked", nev);
        Anasazi::BlockDavidsonSolMgr<double, MultiVector, Operator> mgr(problem, pl);
        ret = mgr.solve();
        result.iterations = mgr.getNumIters();
      } else {
        pl.set("Maximum Iterations", 10 * c.maxRestarts);
        pl.set("Use Locking", true);
        pl.set("Max Locked", nev);
        Anasazi::LOBPCGSolMgr<double, MultiVector, Operator> mgr(problem, pl);
        ret = mgr.solve();
        result.iterations = mgr.getNumIters();
      }
    } catch (const std::exception& e) {
      breakdown = e.what();
    }
    if (!breakdown.empty()) {
      result.status = SolveStatus::NumericalIssue;
      result.solver = "Anasazi " + c.eigensolver;
      result.reason += "; Anasazi broke down: " + breakdown.substr(0, 300);
      result.numOperatorApplies = R->numApplies();
      return attempt;
    }
    solverName = "Anasazi " + c.eigensolver + (symmetric ? " (Hermitian, I* inner product)" : " (non-Hermitian)");
    const auto& sol = problem->getSolution();
    converged = sol.numVecs;
    if (ret != Anasazi::Converged) result.reason += "; Anasazi did not converge all requested vectors";
    if (sol.numVecs > 0) ritz = sol.Evecs;
  }
  result.solver = solverName + ", " + (c.shift == 0.0 ? std::string("unshifted")
                                                      : "shift s = " + std::to_string(c.shift)) +
                  ", Q(mu) by " + (kFactor && c.shift == 0.0 ? "CHOLMOD" : c.linearSolver);
  result.numOperatorApplies = R->numApplies();
  if (ritz.is_null() || converged == 0) {
    result.status = SolveStatus::NotConverged;
    return attempt;
  }

  // 4. Quadratic Rayleigh-Ritz on the halves of the converged vectors.
  // Both halves of each converged state vector: for an exact eigenvector
  // v = lambda q adds nothing, but for a partly converged one (a double
  // eigenvalue of R near the edge of the wanted set) it enriches the subspace.
  const size_t nr = ritz->getNumVectors(), nloc0 = rowMap->getNodeNumElements();
  MultiVector halves(rowMap, 2 * nr);
  {
    const auto src = ritz->getLocalViewHost(Tpetra::Access::ReadOnly);
    auto dst = halves.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (size_t j = 0; j < nr; ++j)
      for (size_t i = 0; i < nloc0; ++i) {
        dst(i, j) = src(nloc0 + i, j);  // q
        dst(i, nr + j) = src(i, j);     // v
      }
  }
  // The threshold is on the Gram matrix's eigenvalues, the squares of the
  // singular values: 1e-20 keeps directions down to 1e-10 of the largest
  // (1e-12 kept only those above 1e-6, and dropped the correction that
  // separates a near-double pair, leaving its modes at residuals ~1e-7). The
  // small directions come out of SVQB with errors ~eps/sigma, so a second
  // pass orthonormalises the result again (SVQB twice, as CGS twice).
  const auto Q = orthonormalBasis(*orthonormalBasis(halves, 1e-20), 1e-20);
  GyroscopicSystem reduced{projectOnto(*sys.M, *Q), projectOnto(*sys.G, *Q), projectOnto(*sys.K, *Q)};
  Teuchos::ParameterList dense;
  dense.set("Rigid Body Tolerance", c.rigidTol);
  dense.set("Instability Tolerance", c.instabTol);
  // The projections of the (validated) symmetric M, K and skew G are so in
  // exact arithmetic; their rounding, eps ||A|| ||q_i|| ||q_j||, exceeded the
  // dense solver's 1e-10 structure check on a 2.4e4-DOF model (synthesis
  // truth, issue 4). Hand over the exactly symmetric parts.
  GyroscopicResult ritzModes = DenseGyroscopicSolver(dense).solve(reduced.symmetrised());
  // Keep those the transform favours: largest |1 / (lambda^2 - s)|.
  auto& rm = ritzModes.modes;
  std::stable_sort(rm.begin(), rm.end(), [&](const GyroscopicMode& a, const GyroscopicMode& b) {
    return std::abs(a.lambda * a.lambda - c.shift) < std::abs(b.lambda * b.lambda - c.shift);
  });
  // Every candidate gets its full-model residual: a projection can also
  // produce spurious Ritz values (large residual) near the target, and those
  // must lose to genuine modes, not be selected for being close.
  const int k = static_cast<int>(rm.size());

  // 5. Full modes q = Q q_r and their residuals from M, G, K.
  const int kk = std::max(k, 1);
  DenseMatrix Yr(static_cast<int>(Q->getNumVectors()), kk), Yi(static_cast<int>(Q->getNumVectors()), kk);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < Yr.numRows(); ++i) {
      Yr(i, j) = rm[j].q[i].real();
      Yi(i, j) = rm[j].q[i].imag();
    }
  MultiVector Qr(rowMap, kk), Qi(rowMap, kk);
  MVT::MvTimesMatAddMv(1.0, *Q, Yr, 0.0, Qr);
  MVT::MvTimesMatAddMv(1.0, *Q, Yi, 0.0, Qi);
  MultiVector MQr(rowMap, kk), MQi(rowMap, kk), GQr(rowMap, kk), GQi(rowMap, kk), KQr(rowMap, kk),
      KQi(rowMap, kk);
  sys.M->apply(Qr, MQr), sys.M->apply(Qi, MQi);
  sys.G->apply(Qr, GQr), sys.G->apply(Qi, GQi);
  sys.K->apply(Qr, KQr), sys.K->apply(Qi, KQi);
  // |K| |q| and |G| |q| for the modes' own scales (GyroscopicMode::scale).
  MultiVector Qa(rowMap, kk), KQa(rowMap, kk), GQa(rowMap, kk);
  {
    auto a = Qa.getLocalViewHost(Tpetra::Access::OverwriteAll);
    auto r = Qr.getLocalViewHost(Tpetra::Access::ReadOnly), i = Qi.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (size_t l = 0; l < rowMap->getNodeNumElements(); ++l)
      for (int j = 0; j < kk; ++j) a(l, j) = std::hypot(r(l, j), i(l, j));
  }
  absoluteValues(*sys.K)->apply(Qa, KQa);
  absoluteValues(*sys.G)->apply(Qa, GQa);
  const double nM = sys.M->getFrobeniusNorm(), nG = sys.G->getFrobeniusNorm(), nK = sys.K->getFrobeniusNorm();
  const double scale = frequencyScale(nM, nG, nK);
  const size_t nloc = rowMap->getNodeNumElements();
  auto qr = Qr.getLocalViewHost(Tpetra::Access::ReadOnly), qi = Qi.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto mr = MQr.getLocalViewHost(Tpetra::Access::ReadOnly), mi = MQi.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto gr = GQr.getLocalViewHost(Tpetra::Access::ReadOnly), gi = GQi.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto kr = KQr.getLocalViewHost(Tpetra::Access::ReadOnly), ki = KQi.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto ka = KQa.getLocalViewHost(Tpetra::Access::ReadOnly), ga = GQa.getLocalViewHost(Tpetra::Access::ReadOnly);
  const int nprocs = comm->getSize();
  for (int j = 0; j < k; ++j) {
    GyroscopicMode& m = rm[j];
    const cplx l = m.lambda, l2 = l * l;
    double local[6] = {0, 0, 0, 0, 0, 0};  // qMq, qKq, qq, rr, |q||K||q|, |q||G||q|
    double big = -1.0;
    cplx bigVal = 0.0;
    for (size_t i = 0; i < nloc; ++i) {
      const cplx q(qr(i, j), qi(i, j)), Mq(mr(i, j), mi(i, j)), Gq(gr(i, j), gi(i, j)), Kq(kr(i, j), ki(i, j));
      local[0] += std::real(std::conj(q) * Mq);
      local[1] += std::real(std::conj(q) * Kq);
      local[2] += std::norm(q);
      local[3] += std::norm(l2 * Mq + l * Gq + Kq);
      local[4] += std::abs(q) * ka(i, j), local[5] += std::abs(q) * ga(i, j);
      if (std::abs(q) > big) big = std::abs(q), bigVal = q;
    }
    double global[6];
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 6, local, global);
    // The largest entry over all ranks fixes the phase (lowest rank wins ties).
    std::vector<double> bigs(3 * nprocs), mine = {big, bigVal.real(), bigVal.imag()};
    Teuchos::gatherAll(*comm, 3, mine.data(), 3 * nprocs, bigs.data());
    int owner = 0;
    for (int p = 1; p < nprocs; ++p)
      if (bigs[3 * p] > bigs[3 * owner]) owner = p;
    const cplx top(bigs[3 * owner + 1], bigs[3 * owner + 2]);
    const cplx phase = std::abs(top) > 0 ? std::conj(top) / std::abs(top) : 1.0;
    const double s = global[0] > 0 ? 1.0 / std::sqrt(global[0]) : 1.0;
    m.q.resize(nloc);
    for (size_t i = 0; i < nloc; ++i) m.q[i] = cplx(qr(i, j), qi(i, j)) * phase * s;
    const double denom = (nK + std::abs(l) * nG + std::norm(l) * nM) * std::sqrt(global[2]);
    m.residual = denom > 0 ? std::sqrt(global[3]) / denom : std::sqrt(global[3]);
    m.kineticEnergy = 0.5 * std::norm(l);
    m.strainEnergy = 0.5 * global[1] * s * s;
    m.growthRate = l.real();
    m.omega = std::abs(l.imag());
    m.hz = m.omega / kTwoPi;
    m.scale = global[0] > 0 ? std::sqrt(global[4] / global[0]) + global[5] / global[0] : 0.0;
  }
  classifyModes(rm, scale, c.rigidTol, c.instabTol);
  // Accurate candidates first (in order of preference), then the first nModes.
  std::stable_partition(rm.begin(), rm.end(),
                        [&](const GyroscopicMode& m) { return m.residual <= c.residualTol; });
  // Every accurate frequency, for the Sturm check: the returned ones and the
  // further ones beyond them that locate the gap after the last cluster.
  for (const auto& m : rm)
    if (m.residual <= c.residualTol) attempt.known.push_back(m.omega);
  std::sort(attempt.known.begin(), attempt.known.end());
  attempt.checkable = symmetric && c.shift >= 0.0;
  if (static_cast<int>(rm.size()) > c.nModes) rm.resize(c.nModes);
  std::stable_sort(rm.begin(), rm.end(), [](const GyroscopicMode& a, const GyroscopicMode& b) {
    return std::abs(a.lambda) < std::abs(b.lambda);
  });
  result.modes = std::move(rm);
  const int kept = static_cast<int>(result.modes.size());
  const bool allAccurate = std::all_of(result.modes.begin(), result.modes.end(),
                                       [&](const GyroscopicMode& m) { return m.residual <= c.residualTol; });
  result.status = (kept == c.nModes && allAccurate) ? SolveStatus::Converged : SolveStatus::NotConverged;
  // The reason always says why a status is not Converged.
  if (kept < c.nModes)
    result.reason += "; only " + std::to_string(kept) + " of " + std::to_string(c.nModes) +
                     " modes could be extracted from the converged vectors";
  if (!allAccurate) {
    int bad = 0;
    for (const auto& m : result.modes) bad += m.residual > c.residualTol;
    std::ostringstream os;
    os << "; " << bad << " of " << kept << " modes exceed the Residual Tolerance " << c.residualTol
       << " (worst " << result.maxResidual() << ")";
    result.reason += os.str();
  }
  return attempt;
}

/// Frequencies within this relative distance are one cluster for the Sturm
/// check: above the spread rounding and the Residual Tolerance (1e-8) leave
/// between the members of a repeated frequency, below any separation a
/// model's distinct modes have in practice; the count is taken at least half
/// this far from every known frequency, which keeps its +-1e-8 retry in the gap.
const double kClusterRelTol = 1e-6;

/// Status for `modes` as the returned set of a request for `nModes`.
SolveStatus statusOf(const std::vector<GyroscopicMode>& modes, int nModes, double residualTol) {
  const bool accurate = std::all_of(modes.begin(), modes.end(),
                                    [&](const GyroscopicMode& m) { return m.residual <= residualTol; });
  return static_cast<int>(modes.size()) == nModes && accurate ? SolveStatus::Converged : SolveStatus::NotConverged;
}

}  // namespace

GyroscopicResult SparseGyroscopicSolver::solve(const SparseGyroscopicSystem& sys) const {
  sys.validate();
  const int nModes = params_.get<int>("Number of Modes");
  Attempt a = solveAttempt(params_, sys, nModes);
  // The set is checked by a Sturm count when the count applies (K > 0, the
  // lowest frequencies wanted) and the iteration claims success; a failure
  // is already reported by its status.
  if (!a.checkable || a.result.status != SolveStatus::Converged) return a.result;
  return checkLowestModes(sys, std::move(a.result), a.known, [&](int asked, std::vector<double>& known) {
    Attempt b = solveAttempt(params_, sys, asked);
    known = b.known;
    return b.result;
  }, nullptr, params_.get<double>("Residual Tolerance"));
}

GyroscopicResult checkLowestModes(const SparseGyroscopicSystem& sys, GyroscopicResult result,
                                  const std::vector<double>& known,
                                  const std::function<GyroscopicResult(int, std::vector<double>&)>& resolve,
                                  const std::function<SparseSturmCount(double)>& countBelow,
                                  double residualTol) {
  const int nModes = result.numRequested;
  const GlobalOrdinal N = sys.globalSize();
  const auto counter = countBelow ? countBelow : [&](double w) { return sturmCount(sys, w); };
  std::vector<double> omegas = known;
  LowestSetCheck last;
  const auto check = [&](std::string& confirmation) -> std::string {
    last = checkLowestSet(omegas, nModes, kClusterRelTol, counter);
    if (last.verdict == LowestSetCheck::Verdict::Disagrees) return last.message;
    confirmation = last.message;
    return "";
  };
  const auto recompute = [&]() -> std::string {
    // The shortfall plus a margin (a quarter more, at least one pair).
    const long long shortfall = std::max<long long>(last.counted - last.known, 0);
    const int asked = static_cast<int>(
        std::min<GlobalOrdinal>(N, nModes + shortfall + std::max(2, nModes / 4)));
    GyroscopicResult again = resolve(asked, omegas);
    // The lowest nModes of the new set (modes are sorted by |lambda|).
    if (static_cast<int>(again.modes.size()) > nModes) again.modes.resize(nModes);
    if (again.status == SolveStatus::Converged || again.status == SolveStatus::NotConverged)
      again.status = statusOf(again.modes, nModes, residualTol);
    again.numRequested = nModes;
    const std::string how = "re-solved asking for " + std::to_string(asked) + " modes (" + again.reason + ")";
    result = std::move(again);
    result.reason.clear();
    return how;
  };
  const std::string before = result.reason;
  const SetConfirmation conf = confirmLowestSet(check, "the iteration's set", recompute);
  result.reason = before + "; " + conf.note;
  if (!conf.complete) result.status = SolveStatus::NumericalIssue;
  else if (!last.clusterNote.empty()) result.reason += "; " + last.clusterNote;
  return result;
}

}  // namespace cms::eigen
