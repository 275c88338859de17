#include "cms/core/SparseDirectSolver.hpp"

#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <sstream>
#include <vector>

#include <Amesos2.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultSerialComm.hpp>
#include <Teuchos_Time.hpp>
#include <Tpetra_ComputeGatherMap.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/DistributedDirectSolver.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/Redistribution.hpp"  // GatheredRows

namespace cms {

namespace {

/// All rows of a map on rank 0, keeping their global ids.
Teuchos::RCP<const Map> rootMapOf(const Teuchos::RCP<const Map>& map) {
  return Tpetra::Details::computeGatherMap(map, Teuchos::null);
}

const double kDefinitenessTolerance = 1e-14;
/// The smallest pivot share L_jj^2 / A_jj of a matrix positive definite
/// beyond rounding: a rigid motion's pivot is rounding, ~eps times a growth
/// of at most ~1e4 (2e-12), 50 times below; a genuine pivot this small is
/// known to eps / 1e-10 = 2e-6 only, so refusing it is honest too.
const double kPivotShareTolerance = 1e-10;

/// min_j L_jj^2 / A_pj,pj over the columns of a supernodal L L^T factor of
/// P A P^T (A's diagonal given in A's numbering); 0 for a simplicial factor,
/// which the callers do not make (CHOLMOD_SUPERNODAL).
double smallestPivotShare(const cholmod_factor& L, const std::vector<double>& diagonal) {
  if (!L.is_super) return 0.0;
  const auto* Lx = static_cast<const double*>(L.x);
  const auto* super = static_cast<const int*>(L.super);
  const auto* pi = static_cast<const int*>(L.pi);
  const auto* px = static_cast<const int*>(L.px);
  const auto* perm = static_cast<const int*>(L.Perm);
  double smallest = std::numeric_limits<double>::infinity();
  for (size_t s = 0; s < L.nsuper; ++s) {
    const int k1 = super[s], k2 = super[s + 1], rows = pi[s + 1] - pi[s];
    for (int j = k1; j < k2; ++j) {  // the diagonal of column j: row j - k1 of the supernode's block
      const double l = Lx[static_cast<size_t>(px[s]) + static_cast<size_t>(j - k1) * (rows + 1)];
      const double a = diagonal[static_cast<size_t>(perm[j])];
      smallest = std::min(smallest, a > 0.0 ? l * l / a : 0.0);
    }
  }
  return smallest;
}

}  // namespace

// CHOLMOD's supernodal factorisation (SuiteSparse 5) opens OpenMP teams of
// CHOLMOD_OMP_NUM_THREADS = 4 threads, a compile-time num_threads clause
// that OMP_NUM_THREADS does not bound: on a 2-core machine 4 threads fork
// and join per supernode (issue 18: 6.5e4 context switches, a fifth of the
// CPU time in the kernel, on a 1.7e4-DOF bar). With dynamic adjustment on
// (omp_set_dynamic), the runtime bounds each team by min(OMP_NUM_THREADS,
// cores) less the load. libgomp comes with CHOLMOD: weak references, so a
// CHOLMOD without OpenMP leaves them null and nothing changes.
extern "C" void omp_set_dynamic(int) __attribute__((weak));
extern "C" int omp_get_dynamic(void) __attribute__((weak));

namespace {
/// omp_set_dynamic(1) for its lifetime, then the caller's setting back.
class DynamicOpenMpTeams {
public:
  DynamicOpenMpTeams() {
    if (omp_set_dynamic && omp_get_dynamic) {
      previous_ = omp_get_dynamic();
      omp_set_dynamic(1);
    }
  }
  ~DynamicOpenMpTeams() {
    if (previous_ >= 0) omp_set_dynamic(previous_);
  }
  DynamicOpenMpTeams(const DynamicOpenMpTeams&) = delete;
  DynamicOpenMpTeams& operator=(const DynamicOpenMpTeams&) = delete;

private:
  int previous_ = -1;
};
}  // namespace

struct SparseDirectSolver::Impl {
  Teuchos::RCP<const CrsMatrix> A;
  // Every method factors the whole matrix on rank 0: rootMap holds all rows
  // there, toRoot moves data between the caller's map and it.
  Teuchos::RCP<const Map> rootMap;
  Teuchos::RCP<const Tpetra::Import<>> toRoot;
  // Amesos2 on rank 0, on a serial communicator: Amesos2 13.2's KLU2 given
  // the distributed matrix itself returned wrong solutions on 2 ranks
  // (forward error ~1e2, tests/unit/core), so it never sees more than one rank.
  Teuchos::RCP<const Map> serialMap;
  Teuchos::RCP<CrsMatrix> serialA;
  Teuchos::RCP<Amesos2::Solver<CrsMatrix, MultiVector>> amesos;
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  bool commonStarted = false;
  double factorNonzeros = 0.0, factorFlops = 0.0;  ///< CHOLMOD's nnz(L) and flop count
  double factorBytes = 0.0;  ///< CHOLMOD's L as allocated (0: not known)
  // "MUMPS" (LU) and "MUMPS-LDLT" (L D L^T, definiteness as CHOLMOD reports
  // it): factored across the ranks, nothing gathered (DistributedDirectSolver).
  std::unique_ptr<DistributedDirectSolver> mumps;

  Outcome factorMumps(const std::string& method, std::string& failure) {
    const bool ldlt = method == "MUMPS-LDLT";
    mumps = std::make_unique<DistributedDirectSolver>(
        A, ldlt ? DistributedDirectSolver::Kind::Symmetric : DistributedDirectSolver::Kind::General,
        "a matrix of " + std::to_string(A->getGlobalNumRows()) + " rows",
        // Null only below CHOLMOD's definiteness test (pivot ratio 1e-14),
        // so that both methods call the same matrices singular.
        kDefinitenessTolerance);
    try {
      mumps->factor(/*allowNullPivots*/ true);  // told apart below
    } catch (const NumericalError& e) {
      failure = std::string(method + ": ") + e.what();
      mumps.reset();
      return Outcome::Singular;
    }
    factorNonzeros = mumps->factorEntries();
    factorFlops = mumps->factorFlops();
    if (ldlt && mumps->negativePivots() > 0) {
      failure = "MUMPS-LDLT: not positive definite (" + std::to_string(mumps->negativePivots()) +
                " negative pivots of " + std::to_string(mumps->rows()) + ")";
      return Outcome::NotPositiveDefinite;
    }
    if (mumps->nullPivots() > 0) {
      // The same verdict as CHOLMOD's pivot-ratio test: definite (or
      // nonsingular) only to rounding.
      failure = method + ": " + std::to_string(mumps->nullPivots()) + " pivots of " +
                std::to_string(mumps->rows()) + " zero to rounding (singular to working precision)";
      return ldlt ? Outcome::NotPositiveDefinite : Outcome::Singular;
    }
    return Outcome::Factored;
  }

  ~Impl() {
    if (factor) cholmod_free_factor(&factor, &common);
    if (commonStarted) cholmod_finish(&common);
  }

  /// A's rows on rank 0 in rootMap's order (GatheredRows: on one rank A's
  /// own arrays), and the maps the solves move right-hand sides by.
  GatheredRows gather() {
    rootMap = rootMapOf(A->getRowMap());
    toRoot = Teuchos::rcp(new Tpetra::Import<>(A->getRowMap(), rootMap));
    return GatheredRows(A, 0);
  }

  Outcome factorAmesos(const std::string& method, std::string& failure) {
    const auto comm = A->getComm();
    const GatheredRows rootA = gather();
    int ok = 1;
    if (comm->getRank() == 0) {
      try {
        auto self = Teuchos::rcp(new Teuchos::SerialComm<int>());
        const size_t n = rootMap->getNodeNumElements();
        // Contiguous ids 0..n-1 (the gathered position): Amesos2 assumes
        // contiguous global ids ("IsContiguous") and mis-solves blocks of
        // right-hand sides otherwise.
        serialMap = Teuchos::rcp(new Map(n, 0, self));
        size_t longest = 0;
        for (size_t i = 0; i < n; ++i) longest = std::max(longest, rootA.length(i));
        serialA = Teuchos::rcp(new CrsMatrix(serialMap, longest));
        Teuchos::Array<GlobalOrdinal> gc;
        Teuchos::Array<double> v;
        for (size_t i = 0; i < n; ++i) {
          gc.clear(), v.clear();
          rootA.forEach(i, [&](int c, double x) { gc.push_back(c), v.push_back(x); });
          serialA->insertGlobalValues(static_cast<GlobalOrdinal>(i), gc(), v());
        }
        serialA->fillComplete(serialMap, serialMap);
        amesos = Amesos2::create<CrsMatrix, MultiVector>(method, serialA);
        amesos->symbolicFactorization();
        amesos->numericFactorization();
      } catch (const std::exception& e) {
        ok = 0;
        failure = method + ": " + e.what();
      }
    }
    Teuchos::broadcast(*comm, 0, &ok);
    return ok ? Outcome::Factored : Outcome::Singular;
  }

  void solveAmesos(const MultiVector& B, MultiVector& X) const {
    const size_t nv = B.getNumVectors();
    MultiVector rootB(rootMap, nv), rootX(rootMap, nv);
    rootB.doImport(B, *toRoot, Tpetra::INSERT);
    onRootCollectively("an Amesos2 solve", [&] {
      const size_t n = serialMap->getNodeNumElements();
      MultiVector sb(serialMap, nv), sx(serialMap, nv);
      {
        auto from = rootB.getLocalViewHost(Tpetra::Access::ReadOnly);
        auto to = sb.getLocalViewHost(Tpetra::Access::OverwriteAll);
        for (size_t j = 0; j < nv; ++j)
          for (size_t i = 0; i < n; ++i) to(i, j) = from(i, j);
      }
      amesos->solve(Teuchos::ptrFromRef(sx), Teuchos::ptrFromRef(sb));
      auto from = sx.getLocalViewHost(Tpetra::Access::ReadOnly);
      auto to = rootX.getLocalViewHost(Tpetra::Access::OverwriteAll);
      for (size_t j = 0; j < nv; ++j)
        for (size_t i = 0; i < n; ++i) to(i, j) = from(i, j);
    });
    X.doExport(rootX, *toRoot, Tpetra::INSERT);
  }

  /// Runs rank 0's part `work` of a collective step and makes its failure
  /// (an exception, or CHOLMOD's allocations returning null) every rank's:
  /// a NumericalError naming `what` on all of them, where the other ranks
  /// waited in the next collective before (found by a review).
  template <class Work>
  void onRootCollectively(const char* what, Work&& work) const {
    const auto comm = A->getComm();
    std::string failure;
    if (comm->getRank() == 0) {
      try {
        work();
      } catch (const std::bad_alloc&) {
        failure = "out of memory";
      } catch (const std::exception& e) {
        failure = e.what();
      }
    }
    int len = static_cast<int>(failure.size());
    Teuchos::broadcast(*comm, 0, &len);
    if (len == 0) return;
    failure.resize(static_cast<std::size_t>(len));
    Teuchos::broadcast(*comm, 0, len, failure.data());
    throw NumericalError(std::string("SparseDirectSolver: ") + what + " on rank 0 failed: " + failure);
  }

  Outcome factorCholmod(std::string& failure) {
    const auto comm = A->getComm();
    const GatheredRows rootA = gather();
    int status = 0;  // 0 factored, 1 not positive definite, 2 other failure
    onRootCollectively("the CHOLMOD factorisation", [&] {
      // A second factor() (new values) starts afresh: the former factor
      // and workspace are freed, not dropped.
      if (factor) cholmod_free_factor(&factor, &common);
      if (commonStarted) cholmod_finish(&common), commonStarted = false;
      cholmod_start(&common);
      commonStarted = true;
      common.print = 0;  // failures are reported through Outcome and failure()
      const size_t n = rootA.size();
      std::vector<double> diagonal(n, 0.0);
      // CSR of a symmetric matrix is its CSC; keep the upper triangle (stype 1).
      cholmod_sparse* S = cholmod_allocate_sparse(n, n, rootA.entries(), /*sorted*/ 0, /*packed*/ 1, /*stype*/ 1,
                                                  CHOLMOD_REAL, &common);
      if (!S) throw NumericalError("CHOLMOD could not allocate the matrix (status " + std::to_string(common.status) + ")");
      auto* Sp = static_cast<int*>(S->p);
      auto* Si = static_cast<int*>(S->i);
      auto* Sx = static_cast<double*>(S->x);
      size_t k = 0;
      for (size_t j = 0; j < n; ++j) {
        Sp[j] = static_cast<int>(k);
        rootA.forEachUpper(j, [&](int i, double v) {
          Si[k] = i, Sx[k] = v, ++k;
          if (static_cast<size_t>(i) == j) diagonal[j] = v;
        });
      }
      Sp[n] = static_cast<int>(k);
      common.quick_return_if_not_posdef = 1;
      // Supernodal is always L L^T, which fails on the first non-positive pivot;
      // CHOLMOD's simplicial default is L D L^T, which succeeds on indefinite
      // matrices and would hide exactly what we need to know.
      common.supernodal = CHOLMOD_SUPERNODAL;
      factor = cholmod_analyze(S, &common);
      if (factor) {
        const DynamicOpenMpTeams teams;
        cholmod_factorize(S, factor, &common);
      }
      cholmod_free_sparse(&S, &common);
      if (!factor || common.status < CHOLMOD_OK) status = 2;
      else if (common.status == CHOLMOD_NOT_POSDEF || factor->minor < factor->n) status = 1;
      if (status == 1)
        failure = "CHOLMOD: not positive definite at column " + std::to_string(factor->minor) +
                  " of " + std::to_string(n);
      // A singular positive semi-definite matrix (a free body's K) can factor
      // with a rounding-sized positive pivot. CHOLMOD's estimate (min/max
      // diag L)^2 falls below the dense solver's "Definiteness Tolerance"
      // then, but also for a healthy matrix whose diagonal spans many orders
      // (the hub-boom model with a hub 1e6 times stiffer: 7.8e-15, after a
      // change of ordering, though every pivot kept 1.5e-3 of its diagonal
      // or more). So a matrix is definite only to rounding when both that
      // estimate and the smallest pivot relative to its own diagonal,
      // L_jj^2 / A_jj (what elimination left of it; a rigid motion's pivot
      // is rounding, ~eps times a growth of at most ~1e4), are below their
      // tolerances (theory §4.3).
      if (status == 0) {
        const double rc = cholmod_rcond(factor, &common);
        if (!(rc >= kDefinitenessTolerance)) {
          const double kept = smallestPivotShare(*factor, diagonal);
          if (!(kept >= kPivotShareTolerance)) {
            status = 1;
            std::ostringstream os;
            os << "CHOLMOD: positive definite only to rounding (pivot ratio estimate " << rc
               << ", the smallest pivot " << kept << " of its diagonal)";
            failure = os.str();
          }
        }
      }
      if (status == 2) failure = "CHOLMOD failed, status " + std::to_string(common.status);
      factorNonzeros = common.lnz;
      factorFlops = common.fl;
      if (factor && factor->is_super)
        factorBytes = 8.0 * static_cast<double>(factor->xsize) + 4.0 * static_cast<double>(factor->ssize) +
                      4.0 * (4.0 * static_cast<double>(factor->nsuper) + 3.0 * static_cast<double>(factor->n));
    });
    Teuchos::broadcast(*comm, 0, &status);
    Teuchos::broadcast(*comm, 0, &factorNonzeros);
    Teuchos::broadcast(*comm, 0, &factorBytes);
    Teuchos::broadcast(*comm, 0, &factorFlops);
    return status == 0 ? Outcome::Factored
                       : (status == 1 ? Outcome::NotPositiveDefinite : Outcome::Singular);
  }

  void solveCholmod(const MultiVector& B, MultiVector& X) const {
    const size_t nv = B.getNumVectors();
    MultiVector rootB(rootMap, nv), rootX(rootMap, nv);
    rootB.doImport(B, *toRoot, Tpetra::INSERT);
    onRootCollectively("a CHOLMOD solve", [&] {
      auto& c = const_cast<cholmod_common&>(common);
      const size_t n = rootMap->getNodeNumElements();
      auto b = rootB.getLocalViewHost(Tpetra::Access::ReadOnly);
      cholmod_dense* rhs = cholmod_allocate_dense(n, nv, n, CHOLMOD_REAL, &c);
      if (!rhs) throw NumericalError("CHOLMOD could not allocate the right-hand sides (status " + std::to_string(c.status) + ")");
      auto* r = static_cast<double*>(rhs->x);
      for (size_t j = 0; j < nv; ++j)
        for (size_t i = 0; i < n; ++i) r[i + j * n] = b(i, j);
      cholmod_dense* sol = cholmod_solve(CHOLMOD_A, factor, rhs, &c);
      if (!sol) {
        cholmod_free_dense(&rhs, &c);
        throw NumericalError("CHOLMOD's solve failed (status " + std::to_string(c.status) + ")");
      }
      auto x = rootX.getLocalViewHost(Tpetra::Access::OverwriteAll);
      const auto* s = static_cast<const double*>(sol->x);
      for (size_t j = 0; j < nv; ++j)
        for (size_t i = 0; i < n; ++i) x(i, j) = s[i + j * n];
      cholmod_free_dense(&rhs, &c);
      cholmod_free_dense(&sol, &c);
    });
    X.doExport(rootX, *toRoot, Tpetra::INSERT);
  }
};

bool SparseDirectSolver::isKnownMethod(const std::string& m) {
  return m == "KLU2" || m == "Tacho" || m == "CHOLMOD" || m == "MUMPS" || m == "MUMPS-LDLT";
}

SparseDirectSolver::SparseDirectSolver(Teuchos::RCP<const CrsMatrix> A, const std::string& method)
    : impl_(new Impl), method_(method) {
  CMS_INPUT_CHECK(!isKnownMethod(method), "SparseDirectSolver: unknown method \""
                                              << method
                                              << "\"; valid: KLU2, Tacho, CHOLMOD, MUMPS, MUMPS-LDLT");
  CMS_INPUT_CHECK(A.is_null() || !A->isFillComplete(),
                  "SparseDirectSolver: the matrix must exist and be fill-complete");
  impl_->A = A;
}

SparseDirectSolver::~SparseDirectSolver() = default;

SparseDirectSolver::Outcome SparseDirectSolver::factor() {
  Teuchos::Time timer("factor", true);
  Outcome out = Outcome::Factored;
  // A refactorisation reports its own outcome, not the last one's.
  failure_.clear();
  impl_->factorNonzeros = impl_->factorFlops = impl_->factorBytes = 0.0;
  if (method_ == "CHOLMOD") {
    out = impl_->factorCholmod(failure_);
  } else {
    out = method_.rfind("MUMPS", 0) == 0 ? impl_->factorMumps(method_, failure_)
                                         : impl_->factorAmesos(method_, failure_);
    // LU codes factor a singular matrix without complaint and then return
    // Inf/NaN or a huge null-space component: solve a probe A x = A x0. A
    // backward-stable solve has a small residual even then, so judge the
    // forward error, which is ~cond(A) eps: above 1e-6 (cond >~ 1e10) the
    // matrix is singular for every purpose of this code. Not MUMPS-LDLT:
    // its pivots are CHOLMOD's definiteness test (factorMumps), which takes
    // a definite matrix of cond 1e12 as definite; the probe called it
    // singular, and the same matrix took another path on MUMPS than on
    // CHOLMOD (found by a review).
    // (Not for inverse iteration: acceptNearlySingular.)
    if (out == Outcome::Factored && method_ != "MUMPS-LDLT" && probe_) {
      const auto map = impl_->A->getDomainMap();
      MultiVector x0(map, 1), b(map, 1), x(map, 1);
      x0.randomize();
      impl_->A->apply(x0, b);
      solve(b, x);
      Teuchos::Array<double> nx0(1), ne(1);
      x0.norm2(nx0());
      x.update(-1.0, x0, 1.0);
      x.norm2(ne());
      const double ferr = ne[0] / nx0[0];
      if (!std::isfinite(ferr) || !(ferr < 1e-6)) {
        out = Outcome::Singular;
        failure_ = method_ + ": the matrix is singular to working precision (probe forward "
                             "error " + std::to_string(ferr) + ")";
      }
    }
  }
  // Rank 0 factored; every rank must report the same words.
  {
    const auto comm = impl_->A->getComm();
    int len = static_cast<int>(failure_.size());
    Teuchos::broadcast(*comm, 0, &len);
    failure_.resize(len);
    if (len > 0) Teuchos::broadcast(*comm, 0, len, &failure_[0]);
  }
  factorSeconds_ = timer.stop();
  factorNonzeros_ = impl_->factorNonzeros;
  factorFlops_ = impl_->factorFlops;
  factorBytes_ = impl_->factorBytes;
  return out;
}

void SparseDirectSolver::solve(const MultiVector& B, MultiVector& X) const {
  if (method_ == "CHOLMOD") {
    impl_->solveCholmod(B, X);
    return;
  }
  if (impl_->mumps) {
    impl_->mumps->solve(B, X);
    return;
  }
  TEUCHOS_TEST_FOR_EXCEPTION(impl_->toRoot.is_null(), std::logic_error,
                             "SparseDirectSolver::solve before a successful factor()");
  impl_->solveAmesos(B, X);
}

void SparseDirectSolver::solveTransposed(const MultiVector& B, MultiVector& X) const {
  // Amesos2 13.2's KLU2 with its "Transpose" (or "Trans") control returned
  // wrong solutions here (forward error ~3, a different one at each build;
  // tests/mpi/SparseDirectSolverTest.cpp): refused, not used.
  TEUCHOS_TEST_FOR_EXCEPTION(method_ == "KLU2", std::logic_error,
                             "SparseDirectSolver::solveTransposed: not with KLU2 (Amesos2 13.2's transposed solve is "
                             "wrong); factor with MUMPS");
  if (impl_->mumps && method_ == "MUMPS") {
    impl_->mumps->solve(B, X, /*transposed=*/true);
    return;
  }
  solve(B, X);  // CHOLMOD, Tacho, MUMPS-LDLT: symmetric factorisations
}

}  // namespace cms
