#include "cms/eigen/SparseGyroscopicSolver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <sstream>

#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

#include "QuadraticRitz.hpp"
#include "SparseEigenproblem.hpp"
#include "SparseIterations.hpp"
#include "SpectralTransform.hpp"
#include "cms/core/DistributedDirectSolver.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/SturmCount.hpp"

namespace cms::eigen {

namespace {

struct Config {
  std::string method, eigensolver, linearSolver;
  bool mumps;  ///< "Direct Solver" resolved for this system: every factorisation by MUMPS across the ranks
  int nModes, blockSize, numBlocks, maxRestarts, verbosity;
  double tol, shift, residualTol, rigidTol, instabTol, frequencyTol;
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
    Teuchos::setStringToIntegralParameter<int>(
        "Direct Solver", "Auto",
        "Who factors K (definiteness test), Q(mu) and the Sturm counts' L D L^T: CHOLMOD (with "
        "\"Linear Solver\" for Q(mu)), each gathered to rank 0; MUMPS, distributed across the ranks "
        "(L D L^T for K, LU for Q(mu)); Auto: MUMPS when the system is distributed over more than one "
        "rank and K has at least 2e6 stored entries (a 3-D solid of ~2e4 DOFs), else CHOLMOD, whose "
        "Sturm counts go to MUMPS when its analysis predicts its simplicial L D L^T costly (cms::inertia)",
        Teuchos::tuple<std::string>("Auto", "CHOLMOD", "MUMPS"), pl.get());
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
    pl->set("Frequency Tolerance", 1e-5,
            "A damped system's returned mode whose first-order eigenvalue error ||r|| ||q|| / |q^H (2 lambda M + "
            "G + D) q| exceeds this times |lambda| is refined by two-sided inverse iteration on the full model "
            "(one factorisation of Q(lambda) each), which bounds its error where the iteration converges and a "
            "stiff part's rows inflate the residual (doc/theory.md 5; else it keeps its first-order error); 0 "
            "refines every one. A mode still not shown within it is said in the reason");
    addStabilityTolerances(*pl);
    pl->set("Verbosity", 0, "0 silent, 1 summary, 2 iteration details (Anasazi's output on rank 0)");
    return pl;
  }();
  return valid;
}

SparseGyroscopicSolver::SparseGyroscopicSolver(const Teuchos::ParameterList& params)
    : GyroscopicSolverManager(params, *getValidParameters(), "SparseGyroscopicSolver") {
  const int k = params_.get<int>("Number of Modes"), bs = params_.get<int>("Block Size");
  CMS_INPUT_CHECK(k < 1, "SparseGyroscopicSolver: \"Number of Modes\" = " << k << " must be >= 1");
  CMS_INPUT_CHECK(bs < 2, "SparseGyroscopicSolver: \"Block Size\" = "
                              << bs << " must be >= 2: every eigenvalue is double");
  CMS_INPUT_CHECK(!(params_.get<double>("Convergence Tolerance") > 0.0),
                  "SparseGyroscopicSolver: \"Convergence Tolerance\" must be positive");
  CMS_INPUT_CHECK(!(params_.get<double>("Frequency Tolerance") >= 0.0),
                  "SparseGyroscopicSolver: \"Frequency Tolerance\" must be >= 0");
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

Config configOf(const Teuchos::ParameterList& params, const SparseGyroscopicSystem& sys, int nModes) {
  return Config{params.get<std::string>("Method"), params.get<std::string>("Eigensolver"),
                params.get<std::string>("Linear Solver"),
                useDistributedSolver(params.get<std::string>("Direct Solver"), *sys.K), nModes,
                params.get<int>("Block Size"), params.get<int>("Number of Blocks"),
                params.get<int>("Maximum Restarts"), params.get<int>("Verbosity"),
                params.get<double>("Convergence Tolerance"), params.get<double>("Shift"),
                params.get<double>("Residual Tolerance"), params.get<double>("Rigid Body Tolerance"),
                params.get<double>("Instability Tolerance"), params.get<double>("Frequency Tolerance")};
}

// 1. Which form: Meirovitch's needs K > 0, which CHOLMOD tells (and its
// factor is the K-solve of the unshifted transform). The reason says why;
// the iterations that need the symmetric form are refused without it.
void chooseForm(const Config& c, detail::SparseEigenproblem& p, GyroscopicResult& result, bool damped) {
  p.symmetric = c.method == "Symmetric";
  if (damped) {
    // Damping makes the spectrum non-Hamiltonian: no I*-self-adjoint form.
    CMS_INPUT_CHECK(c.method == "Symmetric",
                    "SparseGyroscopicSolver: Method \"Symmetric\" needs an undamped system (D = 0, N = 0), "
                    "but D or N is given; use \"Auto\" or \"General\"");
    p.symmetric = false;
    result.reason = "damped: D != 0 (or a circulatory N) makes the system non-conservative, Meirovitch's "
                    "symmetric form does not apply: general non-Hermitian iteration on Q(mu) = mu^2 M + mu (G + "
                    "D) + K + N";
  } else if (c.method != "General") {
    p.kFactor = std::make_shared<SparseDirectSolver>(p.system->K, c.mumps ? "MUMPS-LDLT" : "CHOLMOD");
    const auto out = p.kFactor->factor();
    const bool posdef = out == SparseDirectSolver::Outcome::Factored;
    CMS_INPUT_CHECK(c.method == "Symmetric" && !posdef,
                    "SparseGyroscopicSolver: Method \"Symmetric\" needs K > 0 (I* = diag(M,K) > 0, "
                    "seed eq. (23)), but " << p.kFactor->failure() << "; use \"Auto\" or \"General\"");
    p.symmetric = posdef;
    result.reason = posdef ? "K positive definite (" + p.kFactor->method() +
                                 "): Meirovitch's symmetric form, seed eq. (24)"
                           : "K is not positive definite (" + p.kFactor->failure() +
                                 "): general non-Hermitian iteration";
    if (!posdef) p.kFactor.reset();
  } else {
    result.reason = "requested";
  }
  CMS_INPUT_CHECK(!p.symmetric && (c.eigensolver == "Block Davidson" || c.eigensolver == "LOBPCG"),
                  "SparseGyroscopicSolver: \"" << c.eigensolver
                      << "\" needs the symmetric path (K > 0); " << result.reason);
  CMS_INPUT_CHECK(c.shift < 0.0 && (c.eigensolver == "Block Davidson" || c.eigensolver == "LOBPCG"),
                  "SparseGyroscopicSolver: \"" << c.eigensolver
                      << "\" needs a definite transform: \"Shift\" >= 0");
}

// 2. The spectral transform, factored once (reusing K's Cholesky factor
// when unshifted). False, with the status and reason set, if a
// factorisation failed.
bool factorTransform(const Config& c, detail::SparseEigenproblem& p, GyroscopicResult& result) {
  const double sign = p.symmetric ? -1.0 : 1.0;  // -R is I*-positive when K > 0, s >= 0
  p.transform = Teuchos::rcp(new detail::SpectralTransform(*p.system, c.shift, sign,
                                                           c.mumps ? "MUMPS" : c.linearSolver,
                                                           c.mumps ? "MUMPS" : "KLU2"));
  if (p.kFactor && c.shift == 0.0) p.transform->adoptStiffnessFactor(p.kFactor);
  const std::string why = p.transform->factor();
  if (!why.empty()) {
    result.status = SolveStatus::NumericalIssue;
    result.solver = "none";
    result.reason += "; " + why;
    return false;
  }
  p.innerProduct = Teuchos::rcp(new detail::StateInnerProduct(*p.system));
  return true;
}

// 5. The returned set: accurate candidates first, in the transform's order
// of preference, then the first nModes of them sorted by |lambda|; every
// accurate frequency is kept for the Sturm check (the returned ones and the
// further ones that locate the gap after the last cluster). The status and
// the reason say whether all nModes were found accurate, and if not why.
void selectModes(const Config& c, std::vector<GyroscopicMode> rm, Attempt& attempt) {
  GyroscopicResult& result = attempt.result;
  std::stable_partition(rm.begin(), rm.end(),
                        [&](const GyroscopicMode& m) { return m.residual <= c.residualTol; });
  for (const auto& m : rm)
    if (m.residual <= c.residualTol) attempt.known.push_back(m.omega);
  std::sort(attempt.known.begin(), attempt.known.end());
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
}

/// One run for `nModes` modes: the manager's phases in order (the problem
/// and its form, the transform, the iteration, the extraction, the returned
/// set); the caller (SparseGyroscopicSolver::solve) adds the Sturm check.
Attempt solveAttempt(const Teuchos::ParameterList& params, const SparseGyroscopicSystem& sys, int nModes) {
  const Config c = configOf(params, sys, nModes);
  Attempt attempt;
  GyroscopicResult& result = attempt.result;
  const GlobalOrdinal N = sys.globalSize();
  CMS_INPUT_CHECK(c.nModes > N, "SparseGyroscopicSolver: \"Number of Modes\" = "
                                    << c.nModes << " but the system has only " << N
                                    << " DOFs, hence " << N << " modes");
  result.numRequested = c.nModes;
  // The transform sees the damping only through Q(mu) = mu^2 M + mu (G + D)
  // + K, so it iterates on the system with G + D in G's place; the modes
  // are extracted from the system as given (D kept apart).
  // A circulatory N likewise enters as K + N.
  const bool damped = !sys.D.is_null() || !sys.N.is_null();
  SparseGyroscopicSystem effective = sys;
  if (!sys.D.is_null()) {
    effective.G = Tpetra::MatrixMatrix::add(1.0, false, *sys.G, 1.0, false, *sys.D);
    effective.D = Teuchos::null;
  }
  if (!sys.N.is_null()) {
    effective.K = Tpetra::MatrixMatrix::add(1.0, false, *sys.K, 1.0, false, *sys.N);
    effective.N = Teuchos::null;
  }
  detail::SparseEigenproblem problem;
  problem.system = &effective;
  problem.shift = c.shift;
  problem.nModes = c.nModes;
  chooseForm(c, problem, result, damped);              // 1.
  if (!factorTransform(c, problem, result)) return attempt;  // 2.

  // 3. The subspace. Each mode is a double eigenvalue of R: ask for 2 per
  // mode. The automatic subspace never exceeds the state dimension 2N
  // (Anasazi refuses a basis longer than the vectors); a problem too small
  // for any Krylov subspace is reported, not attempted: the dense solver is
  // the right tool there.
  const int nev = static_cast<int>(std::min<GlobalOrdinal>(2 * c.nModes, 2 * N - 1));
  // Block Krylov-Schur keeps numBlocks + 1 blocks: they must fit in 2N
  // with room to spare (2N exactly broke down, "Orthogonalization
  // constraints not feasible", on 22 DOFs asked for 7 modes; a review).
  const int maxBlocks = static_cast<int>(std::min<GlobalOrdinal>((2 * N - 1) / c.blockSize - 1, 1 << 20));
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

  // 4. The iteration the parameters name (SparseIterations.hpp).
  const detail::IterationSettings settings{c.eigensolver, c.blockSize, c.maxRestarts, c.verbosity, c.tol,
                                           c.mumps ? "MUMPS-LDLT" : "CHOLMOD"};
  detail::IterationOutcome it = c.eigensolver == "ARPACK" ? detail::iterateArpack(problem, settings, nev)
                                                           : detail::iterateAnasazi(problem, settings, nev, numBlocks);
  // A breakdown of Anasazi's iteration is retried by ARPACK on the same
  // factored transform: Block Krylov-Schur's Schur reordering (TREXC)
  // refused a swap among the double eigenvalues of a damped isotropic shaft
  // at rest, and the run ended, exit 3, with no output (a review, 2026-12-01).
  if (!it.failure.empty() && c.eigensolver != "ARPACK") {
    detail::IterationSettings arpack = settings;
    arpack.eigensolver = "ARPACK";
    detail::IterationOutcome again = detail::iterateArpack(problem, arpack, nev);
    if (again.failure.empty()) {
      result.reason += "; " + it.failure + ": solved again by ARPACK on the same factored transform";
      it = std::move(again);
    }
  }
  result.iterations = it.iterations;
  if (!it.failure.empty()) {
    result.status = SolveStatus::NumericalIssue;
    result.solver = it.solver;
    result.reason += "; " + it.failure;
    if (c.eigensolver != "ARPACK") result.numOperatorApplies = problem.transform->numApplies();
    return attempt;
  }
  if (!it.note.empty()) result.reason += "; " + it.note;
  result.solver = it.solver + ", " + (c.shift == 0.0 ? std::string("unshifted")
                                                     : "shift s = " + std::to_string(c.shift)) +
                  ", Q(mu) by " + (problem.kFactor && c.shift == 0.0 ? problem.kFactor->method()
                                                                     : (c.mumps ? "MUMPS" : c.linearSolver));
  result.numOperatorApplies = problem.transform->numApplies();
  if (it.vectors.is_null() || it.converged == 0) {
    result.status = SolveStatus::NotConverged;
    return attempt;
  }

  // 5. Modes by the quadratic Rayleigh-Ritz projection (QuadraticRitz.hpp),
  // then the returned set.
  const detail::RitzRefinement refinement{c.nModes, c.residualTol, c.frequencyTol};
  selectModes(c, detail::quadraticRitzModes(sys, *it.vectors, c.shift, c.rigidTol, c.instabTol, refinement),
              attempt);
  // Said where the extraction refines (QuadraticRitz.cpp: D or N not zero).
  if (sys.damped()) result.reason += accuracyNote(result.modes, c.frequencyTol, " on the full model");
  attempt.checkable = problem.symmetric && c.shift >= 0.0;
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
  // The Sturm counts by the same direct solver as the transform.
  // The Sturm counts by MUMPS or CHOLMOD as asked; Auto: by the predicted
  // cost (cms::inertia): CHOLMOD's simplicial L D L^T of the 2n embedding
  // was 80% of the 5e4-DOF rotor's truth solve.
  const std::string direct = params_.get<std::string>("Direct Solver");
  const InertiaMethod counting = useDistributedSolver(direct, *sys.K) ? InertiaMethod::Multifrontal
                                 : direct == "CHOLMOD"                ? InertiaMethod::Simplicial
                                                                      : InertiaMethod::Auto;
  return checkLowestModes(sys, std::move(a.result), a.known, [&](int asked, std::vector<double>& known) {
    Attempt b = solveAttempt(params_, sys, asked);
    known = b.known;
    return b.result;
  }, [&](double w) { return detail::sturmCountBy(sys, w, counting); }, params_.get<double>("Residual Tolerance"));
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
