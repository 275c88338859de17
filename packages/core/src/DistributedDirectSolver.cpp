#include "cms/core/DistributedDirectSolver.hpp"

#include <cholmod.h>
#include <dmumps_c.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <type_traits>
#include <vector>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_Time.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/MpiComm.hpp"
#include "cms/core/PeakMemory.hpp"

namespace cms {

namespace {

// ICNTL(k), INFOG(k), ... are 1-based in MUMPS's documentation.
inline MUMPS_INT& icntl(DMUMPS_STRUC_C& id, int k) { return id.icntl[k - 1]; }
inline double& cntl(DMUMPS_STRUC_C& id, int k) { return id.cntl[k - 1]; }
inline MUMPS_INT infog(const DMUMPS_STRUC_C& id, int k) { return id.infog[k - 1]; }
inline MUMPS_INT info(const DMUMPS_STRUC_C& id, int k) { return id.info[k - 1]; }

/// MUMPS reports large counts negative, in millions (INFOG(29), INFO(2) ...).
double countOf(MUMPS_INT v) { return v >= 0 ? double(v) : -1e6 * double(v); }

bool isWorkspaceShortfall(int code) {
  return code == -8 || code == -9 || code == -14 || code == -17 || code == -20;
}

/// METIS's nested-dissection ordering (through CHOLMOD's cholmod_metis) of
/// the symmetric pattern whose upper-triangle entries (1-based, any rank's
/// share) are (irn, jcn), as MUMPS's PERM_IN: the host gets perm[i - 1] =
/// the position of variable i in the pivot order, 1-based; the other ranks
/// an empty vector. Empty on the host too if CHOLMOD failed (MUMPS then
/// orders by itself). Collective.
std::vector<MUMPS_INT> nestedDissection(const Teuchos::Comm<int>& comm, MUMPS_INT n,
                                        const std::vector<MUMPS_INT>& irn, const std::vector<MUMPS_INT>& jcn) {
  const MPI_Comm c = rawMpiComm(comm);
  static_assert(std::is_same<MUMPS_INT, int>::value, "MUMPS_INT gathered as int");
  std::vector<MUMPS_INT> I, J, perm;
  try {
    I = gatherOnRank(irn, 0, c, "the nested dissection's pattern entries");
    J = gatherOnRank(jcn, 0, c, "the nested dissection's pattern entries");
  } catch (const std::length_error&) {  // refused on every rank: MUMPS orders by itself
    return perm;
  }
  const long long total = static_cast<long long>(I.size());
  if (comm.getRank() != 0) return perm;
  // The pattern by columns, upper triangle (stype 1), duplicates allowed.
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  cholmod_sparse* A = cholmod_allocate_sparse(n, n, total, /*sorted*/ 0, /*packed*/ 1, /*stype*/ 1,
                                              CHOLMOD_PATTERN, &common);
  if (A) {
    auto* Ap = static_cast<int*>(A->p);
    auto* Ai = static_cast<int*>(A->i);
    std::fill(Ap, Ap + n + 1, 0);
    for (long long e = 0; e < total; ++e) ++Ap[std::max(I[e], J[e])];  // column: the larger index (1-based)
    for (MUMPS_INT j = 0; j < n; ++j) Ap[j + 1] += Ap[j];
    std::vector<int> next(Ap, Ap + n);
    for (long long e = 0; e < total; ++e) Ai[next[std::max(I[e], J[e]) - 1]++] = std::min(I[e], J[e]) - 1;
    std::vector<int> order(n);
    if (cholmod_metis(A, nullptr, 0, /*postorder*/ 1, order.data(), &common) && common.status == CHOLMOD_OK) {
      perm.assign(n, 0);
      for (MUMPS_INT k = 0; k < n; ++k) perm[order[k]] = k + 1;
    }
    cholmod_free_sparse(&A, &common);
  }
  cholmod_finish(&common);
  return perm;
}

}  // namespace

std::string DistributedDirectSolver::errorMeaning(int e, long long i2) {
  const std::string n2 = std::to_string(i2);
  switch (e) {
    case -1: return "an error occurred on MPI process " + n2;
    case -2: return "NNZ (entries) out of range: " + n2;
    case -3: return "MUMPS called with an invalid JOB";
    case -4: return "error in the user-given permutation (PERM_IN) at " + n2;
    case -5: return "not enough memory for the real workspace of the analysis (" + n2 + ")";
    case -6: return "the matrix is structurally singular (structural rank " + n2 + ")";
    case -7: return "not enough memory for the integer workspace of the analysis (" + n2 + ")";
    case -8: return "the integer workarray IS is too small for the factorisation (ICNTL(14))";
    case -9: return "the real workarray S is too small for the factorisation (ICNTL(14))";
    case -10: return "the matrix is numerically singular (" + n2 + " pivots eliminated)";
    case -11: return "the real workarray S is too small for the solution";
    case -12: return "the real workarray S is too small for iterative refinement";
    case -13: return "an allocation failed (" + n2 + " entries; negative: millions)";
    case -14: return "the integer workarray IS is too small for the solution";
    case -15: return "the integer workarray IS is too small for iterative refinement or error analysis";
    case -16: return "N is out of range: " + n2;
    case -17: return "the internal send buffer is too small (ICNTL(14))";
    case -19: return "the memory limit ICNTL(23) is too small";
    case -20: return "the internal reception buffer is too small (ICNTL(14))";
    case -21: return "PAR = 0 is not allowed on one process";
    case -22: return "an array given to MUMPS is missing or too small (" + n2 + ")";
    case -23: return "MPI was not initialised";
    case -25: return "BLACS/ScaLAPACK failed on the root node";
    case -26: return "LRHS is out of range: " + n2;
    case -29: return "LSOL_loc is smaller than INFO(23): " + n2;
    case -32: return "incompatible NRHS: " + n2;
    case -38: return "parallel analysis requested without PT-Scotch or ParMETIS";
    case -40: return "SYM = 1 (positive definite) was declared but a negative or null pivot was met; use SYM = 2";
    case -44: return "the solve phase was called without a successful factorisation";
    case -53: return "the structure of the matrix changed between analysis and factorisation";
    default: return "MUMPS error " + std::to_string(e) + " (INFOG(2) = " + n2 + "); see the MUMPS 5.5 user guide §8";
  }
}

struct DistributedDirectSolver::Impl {
  Teuchos::RCP<const CrsMatrix> A;
  Kind kind = Kind::General;
  double nullTolerance = kTinyPivot;
  DMUMPS_STRUC_C id{};
  bool started = false;
  // MUMPS's 1-based index of each owned row (the caller's local order) and
  // of each column of A's column map.
  std::vector<MUMPS_INT> rowIndex, colIndex;
  // The skew part of a Hermitian A + iB whose real embedding
  // [[A, -B], [B, A]] is factored (null: A itself), on A's row map, and
  // MUMPS's index of each column of B's column map.
  Teuchos::RCP<const CrsMatrix> B;
  std::vector<MUMPS_INT> colIndexB;
  // idMap: the same rows, in the same local order, with global id = MUMPS
  // index - 1: the space the distributed solution is imported into.
  Teuchos::RCP<const Map> idMap;
  // The distributed solution's layout (ISOL_loc, fixed after factorisation)
  // and its import to idMap, built at the first solve.
  mutable Teuchos::RCP<const Map> solMap;
  mutable Teuchos::RCP<const Tpetra::Import<>> fromSol;
  std::vector<MUMPS_INT> irn, jcn;
  std::vector<double> values;

  void call(int job) {
    id.job = job;
    dmumps_c(&id);
  }

  ~Impl() {
    if (started) call(-2);
  }

  /// MUMPS indices: gid - min + 1 when the row map's ids fill [min, max]
  /// exactly (every map in this code), else a contiguous renumbering in
  /// rank order with the columns' numbers imported from their owners.
  void number() {
    const auto rowMap = A->getRowMap();
    const auto colMap = A->getColMap();
    const auto comm = rowMap->getComm();
    const long long N = static_cast<long long>(rowMap->getGlobalNumElements());
    const long long lo = rowMap->getMinAllGlobalIndex(), hi = rowMap->getMaxAllGlobalIndex();
    const size_t nloc = rowMap->getNodeNumElements();
    rowIndex.resize(nloc);
    colIndex.resize(colMap->getNodeNumElements());
    if (!B.is_null()) colIndexB.resize(B->getColMap()->getNodeNumElements());
    Teuchos::Array<GlobalOrdinal> ids(nloc);
    if (hi - lo + 1 == N) {
      for (size_t i = 0; i < nloc; ++i) rowIndex[i] = static_cast<MUMPS_INT>(rowMap->getGlobalElement(i) - lo + 1);
      for (size_t c = 0; c < colIndex.size(); ++c)
        colIndex[c] = static_cast<MUMPS_INT>(colMap->getGlobalElement(c) - lo + 1);
      for (size_t c = 0; c < colIndexB.size(); ++c)
        colIndexB[c] = static_cast<MUMPS_INT>(B->getColMap()->getGlobalElement(c) - lo + 1);
    } else {
      long long offset = 0, mine = static_cast<long long>(nloc);
      Teuchos::scan(*comm, Teuchos::REDUCE_SUM, mine, Teuchos::outArg(offset));
      offset -= mine;
      Vector own(rowMap), cols(colMap);
      {
        auto v = own.getLocalViewHost(Tpetra::Access::OverwriteAll);
        for (size_t i = 0; i < nloc; ++i) {
          rowIndex[i] = static_cast<MUMPS_INT>(offset + static_cast<long long>(i) + 1);
          v(i, 0) = rowIndex[i];
        }
      }
      cols.doImport(own, Tpetra::Import<>(rowMap, colMap), Tpetra::INSERT);
      auto c = cols.getLocalViewHost(Tpetra::Access::ReadOnly);
      for (size_t k = 0; k < colIndex.size(); ++k) colIndex[k] = static_cast<MUMPS_INT>(std::lround(c(k, 0)));
      if (!B.is_null()) {
        Vector colsB(B->getColMap());
        colsB.doImport(own, Tpetra::Import<>(rowMap, B->getColMap()), Tpetra::INSERT);
        auto cb = colsB.getLocalViewHost(Tpetra::Access::ReadOnly);
        for (size_t k = 0; k < colIndexB.size(); ++k) colIndexB[k] = static_cast<MUMPS_INT>(std::lround(cb(k, 0)));
      }
    }
    for (size_t i = 0; i < nloc; ++i) ids[i] = rowIndex[i] - 1;
    idMap = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(N), ids(), 0, comm));
  }

  /// The owned rows' entries on or above the diagonal (MUMPS's numbering).
  size_t upperEntries() const {
    CrsMatrix::local_inds_host_view_type cols;
    CrsMatrix::values_host_view_type vals;
    size_t count = 0;
    for (size_t i = 0; i < rowIndex.size(); ++i) {
      A->getLocalRowView(static_cast<LocalOrdinal>(i), cols, vals);
      for (size_t e = 0; e < cols.extent(0); ++e) count += colIndex[cols(e)] >= rowIndex[i];
    }
    return count;
  }

  /// The upper triangle of the real embedding E = [[A, -B], [B, A]] of
  /// order 2N (B^T = -B makes E symmetric): A's row r gives E's rows r and
  /// N + r; their upper entries are A's upper entries at (r, c) and
  /// (N + r, N + c), and -B's row at (r, N + c). (B's row at (N + r, c)
  /// lies below the diagonal.) Straight from A and B: no 2N-row matrix.
  void embeddingTriplets() {
    const size_t nloc = A->getRowMap()->getNodeNumElements();
    const MUMPS_INT N = static_cast<MUMPS_INT>(A->getGlobalNumRows());
    CrsMatrix::local_inds_host_view_type cols;
    CrsMatrix::values_host_view_type vals;
    const size_t count = 2 * upperEntries() + B->getNodeNumEntries();
    irn.clear(), jcn.clear(), values.clear();
    irn.reserve(count), jcn.reserve(count), values.reserve(count);
    auto add = [&](MUMPS_INT r, MUMPS_INT c, double v) {
      irn.push_back(r);
      jcn.push_back(c);
      values.push_back(v);
    };
    for (size_t i = 0; i < nloc; ++i) {
      const MUMPS_INT r = rowIndex[i];
      A->getLocalRowView(static_cast<LocalOrdinal>(i), cols, vals);
      for (size_t e = 0; e < cols.extent(0); ++e) {
        const MUMPS_INT c = colIndex[cols(e)];
        if (c < r) continue;
        add(r, c, vals(e));
        add(N + r, N + c, vals(e));
      }
      B->getLocalRowView(static_cast<LocalOrdinal>(i), cols, vals);
      for (size_t e = 0; e < cols.extent(0); ++e) add(r, N + colIndexB[cols(e)], -vals(e));
    }
  }

  /// The owned rows as coordinate triplets (upper triangle for SYM != 0).
  void triplets() {
    if (!B.is_null()) return embeddingTriplets();
    const size_t nloc = A->getRowMap()->getNodeNumElements();
    irn.clear();
    jcn.clear();
    values.clear();
    CrsMatrix::local_inds_host_view_type cols;
    CrsMatrix::values_host_view_type vals;
    // Exactly the entries handed over (the upper triangle of a symmetric
    // matrix is half of them): the triplets live through the factorisation.
    const size_t count = kind == Kind::General ? A->getNodeNumEntries() : upperEntries();
    irn.reserve(count);
    jcn.reserve(count);
    values.reserve(count);
    for (size_t i = 0; i < nloc; ++i) {
      A->getLocalRowView(static_cast<LocalOrdinal>(i), cols, vals);
      const MUMPS_INT r = rowIndex[i];
      for (size_t e = 0; e < cols.extent(0); ++e) {
        const MUMPS_INT c = colIndex[cols(e)];
        if (kind != Kind::General && c < r) continue;
        irn.push_back(r);
        jcn.push_back(c);
        values.push_back(vals(e));
      }
    }
  }
};

DistributedDirectSolver::DistributedDirectSolver(Teuchos::RCP<const CrsMatrix> A, Kind kind, std::string name,
                                                 double nullPivotTolerance)
    : impl_(new Impl), name_(std::move(name)) {
  CMS_INPUT_CHECK(A.is_null() || !A->isFillComplete(),
                  "DistributedDirectSolver (" << name_ << "): the matrix must exist and be fill-complete");
  CMS_INPUT_CHECK(A->getGlobalNumRows() != A->getGlobalNumCols() ||
                      !A->getRowMap()->isSameAs(*A->getDomainMap()) ||
                      !A->getRowMap()->isSameAs(*A->getRangeMap()),
                  "DistributedDirectSolver (" << name_ << "): the matrix must be square with its row, domain and "
                                                 "range maps the same");
  CMS_INPUT_CHECK(A->getGlobalNumRows() > static_cast<Tpetra::global_size_t>(std::numeric_limits<MUMPS_INT>::max()),
                  "DistributedDirectSolver (" << name_ << "): " << A->getGlobalNumRows()
                                              << " rows exceed MUMPS's 32-bit indices (libmumps64-dev has 64-bit ones)");
  CMS_INPUT_CHECK(!(nullPivotTolerance >= 0.0), "DistributedDirectSolver (" << name_ << "): the null-pivot tolerance "
                                                                              << nullPivotTolerance << " must be >= 0");
  impl_->A = A;
  impl_->kind = kind;
  if (nullPivotTolerance > 0.0) impl_->nullTolerance = nullPivotTolerance;
  n_ = static_cast<long long>(A->getGlobalNumRows());
}

DistributedDirectSolver::DistributedDirectSolver(Teuchos::RCP<const CrsMatrix> A, Teuchos::RCP<const CrsMatrix> B,
                                                 std::string name)
    : DistributedDirectSolver(A, Kind::Symmetric, std::move(name)) {
  CMS_INPUT_CHECK(B.is_null() || !B->isFillComplete() || !B->getRowMap()->isSameAs(*A->getRowMap()),
                  "DistributedDirectSolver (" << name_ << "): the skew part must be fill-complete on A's row map");
  CMS_INPUT_CHECK(2 * A->getGlobalNumRows() > static_cast<Tpetra::global_size_t>(std::numeric_limits<MUMPS_INT>::max()),
                  "DistributedDirectSolver (" << name_ << "): the embedding's " << 2 * A->getGlobalNumRows()
                                              << " rows exceed MUMPS's 32-bit indices");
  impl_->B = B;
  n_ = 2 * static_cast<long long>(A->getGlobalNumRows());
  pivotsOnly_ = true;  // no 2N-row map to solve on: counts only
}

DistributedDirectSolver::~DistributedDirectSolver() = default;

/// After the analysis, and before each retry with more workspace: the
/// factorisation's memory MUMPS estimates for this rank (INFO(15) in core,
/// INFO(17) when only the pivots are counted; MB, times
/// `growth` for the workspace added since) against what this rank may use
/// (its share of the memory available on its node), on every rank. A
/// factorisation that cannot fit is refused with a NumericalError naming
/// both figures, instead of the machine's out-of-memory killer ending the
/// run.
void DistributedDirectSolver::refuseWhatCannotFit(Impl& m, const Teuchos::Comm<int>& comm, double growth) const {
  const int onNode = ranksOnNode(comm);
  // INFO(15): the analysis's estimate of this rank's memory for an in-core
  // factorisation, in MUMPS's megabytes (1e6 bytes). INFO(17), the
  // out-of-core estimate (a third of it on the rotor), holds only when the
  // factors are not kept (ICNTL(31) = 1, MUMPS 5.5 guide): read for a
  // factorisation that keeps them, it let a 5.7e5-DOF count through that
  // then could not fit.
  const int estimate = pivotsOnly_ ? 17 : 15;
  const double needMB = growth * countOf(info(m.id, estimate)), availableMB = availableMemoryBytes() / 1e6 / onNode;
  double worst[2] = {needMB > 0.9 * availableMB ? needMB : 0.0, availableMB};
  double all[2] = {0.0, 0.0};
  MPI_Allreduce(worst, all, 1, MPI_DOUBLE, MPI_MAX, rawMpiComm(comm));
  if (all[0] == 0.0) return;
  std::ostringstream os;
  os << name_ << ": the factorisation of " << n_ << " rows needs about " << std::fixed << std::setprecision(0)
     << all[0] << " MB on one rank (MUMPS's "
     << (pivotsOnly_ ? "estimate with its factors discarded, INFO(17)" : "in-core estimate, INFO(15)") << (growth > 1.0 ? ", with the workspace its delayed pivots asked for" : "") << "), more than the 90% of the " << availableMB
     << " MB its rank may use (available memory shared by the node's ranks); run on more nodes or a coarser model";
  m.call(-2);
  m.started = false;
  throw NumericalError(os.str());
}

void DistributedDirectSolver::factor(bool allowNullPivots) {
  Teuchos::Time timer("factor", true);
  Impl& m = *impl_;
  TEUCHOS_TEST_FOR_EXCEPTION(m.A.is_null(), std::logic_error,
                             name_ << ": factor() again after the count released its matrix");
  const auto comm = m.A->getComm();
  if (m.started) {  // a second factor() starts afresh
    m.call(-2);
    m.started = false;
  }
  m.number();
  m.triplets();
  if (releaseMatrix_) m.A = m.B = Teuchos::null;  // the triplets hold the values from here
  DMUMPS_STRUC_C& id = m.id;
  id = DMUMPS_STRUC_C{};
  id.par = 1;  // the host works too
  id.sym = m.kind == Kind::General ? 0 : (m.kind == Kind::PositiveDefinite ? 1 : 2);
  id.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(rawMpiComm(*comm)));
  m.call(-1);
  m.started = true;
  auto check = [&](const char* phase) {
    const int e = infog(id, 1);
    if (e >= 0) return;
    throw NumericalError(name_ + ": MUMPS " + phase + " failed with INFOG(1) = " + std::to_string(e) +
                         ", INFOG(2) = " + std::to_string(infog(id, 2)) + ": " +
                         errorMeaning(e, infog(id, 2)) + " (" + std::to_string(n_) + " rows)");
  };
  check("initialisation");
  icntl(id, 1) = -1;  // no error, diagnostic, global or statistics output: errors come back as exceptions
  icntl(id, 2) = -1;
  icntl(id, 3) = -1;
  icntl(id, 4) = 0;
  icntl(id, 5) = 0;   // assembled matrix
  icntl(id, 18) = 3;  // distributed by the user: each rank its own rows
  icntl(id, 28) = 1;  // sequential analysis (no PT-Scotch/ParMETIS in libmumps-dev)
  icntl(id, 7) = 7;   // ordering: MUMPS's automatic choice (PORD on the rotor's K; measured against AMD, AMF, QAMD:
                      // the fewest factor entries, within the noise in time), unless METIS's is given (below)
  icntl(id, 20) = 10; // distributed right-hand side
  icntl(id, 21) = 1;  // distributed solution
  icntl(id, 24) = 1;  // null-pivot detection: counted in INFOG(28), never silently divided by
  cntl(id, 3) = m.nullTolerance;  // null if |pivot row| <= CNTL(3) ||A_pre||
  // ScaLAPACK's factorisation of the root front reports no inertia (MUMPS
  // guide, ICNTL(13)): the root by MUMPS's own kernels, so that INFOG(12)
  // counts every negative pivot (the price: the root front is not split
  // over the ranks).
  if (m.kind != Kind::General) icntl(id, 13) = 1;
  // Counting only: each front's factor is dropped once eliminated, so the
  // factorisation holds its working fronts, not the factors (ICNTL(31) = 1;
  // INFOG(12), (28), (29) are still returned).
  icntl(id, 31) = pivotsOnly_ ? 1 : 0;
  id.n = static_cast<MUMPS_INT>(n_);
  id.nnz_loc = static_cast<MUMPS_INT8>(m.irn.size());
  id.irn_loc = m.irn.data();
  id.jcn_loc = m.jcn.data();
  id.a_loc = m.values.data();
  std::vector<MUMPS_INT> perm;
  if (ordering_ == Ordering::NestedDissection && m.kind != Kind::General) {
    perm = nestedDissection(*comm, id.n, m.irn, m.jcn);
    int given = comm->getRank() == 0 ? !perm.empty() : 0;
    MPI_Bcast(&given, 1, MPI_INT, 0, rawMpiComm(*comm));
    if (given) {
      icntl(id, 7) = 1;  // the ordering in PERM_IN (host)
      id.perm_in = perm.empty() ? nullptr : perm.data();
    }
  }
  m.call(1);
  id.perm_in = nullptr;
  check("analysis");
  analysisSeconds_ = timer.totalElapsedTime(true);
  refuseWhatCannotFit(m, *comm, 1.0);
  orderingUsed_ = infog(id, 7);
  // An indefinite L D L^T can delay pivots beyond the analysis's workspace
  // (INFOG(1) = -8/-9): the factorisation is retried with the relaxation
  // ICNTL(14) doubled, the memory estimate grown by the same ratio and
  // checked against the budget again before each retry (unchecked, the
  // retries of a 5.7e5-DOF Sturm count ran a 24 GiB machine out of memory).
  double growth = 1.0;
  for (int attempt = 0;; ++attempt) {
    m.call(2);
    if (!(isWorkspaceShortfall(infog(id, 1)) && attempt < 4)) break;
    const MUMPS_INT before = icntl(id, 14);
    icntl(id, 14) = 2 * std::max<MUMPS_INT>(before, 20);
    growth *= (100.0 + icntl(id, 14)) / (100.0 + std::max<MUMPS_INT>(before, 0));
    refuseWhatCannotFit(m, *comm, growth);
  }
  check("factorisation");
  negative_ = m.kind == Kind::General ? 0 : countOf(infog(id, 12));
  null_ = countOf(infog(id, 28));
  factorEntries_ = countOf(infog(id, 29));
  factorFlops_ = id.rinfog[2];
  memoryMaxMB_ = infog(id, 21);
  memoryTotalMB_ = infog(id, 22);
  // The factors are MUMPS's own now; the triplets are not needed to solve.
  std::vector<MUMPS_INT>().swap(m.irn);
  std::vector<MUMPS_INT>().swap(m.jcn);
  std::vector<double>().swap(m.values);
  id.irn_loc = id.jcn_loc = nullptr;
  id.a_loc = nullptr;
  m.solMap = Teuchos::null;
  m.fromSol = Teuchos::null;
  factorSeconds_ = timer.stop();
  if (null_ > 0 && !allowNullPivots) {
    std::ostringstream os;
    os << name_ << ": singular to working precision: MUMPS found " << null_ << " null pivots of " << n_
       << " (a pivot row's norm at or below " << m.nullTolerance
       << " times the matrix's; null-pivot detection, ICNTL(24))";
    throw NumericalError(os.str());
  }
}

void DistributedDirectSolver::solve(const MultiVector& B, MultiVector& X, bool transposed) const {
  Impl& m = *impl_;
  CMS_INPUT_CHECK(!m.started || m.idMap.is_null(), "DistributedDirectSolver (" << name_ << "): solve before factor");
  CMS_INPUT_CHECK(!m.B.is_null(), "DistributedDirectSolver (" << name_
                                     << "): a real embedding of A + iB is factored for its inertia only; "
                                        "it has no 2N-row map to solve on");
  CMS_INPUT_CHECK(pivotsOnly_, "DistributedDirectSolver (" << name_
                                    << "): solve after a factorisation that counted pivots only (its factors were "
                                       "discarded, setPivotsOnly)");
  DMUMPS_STRUC_C& id = m.id;
  const size_t nv = B.getNumVectors();
  const size_t nloc = m.rowIndex.size();
  // Each rank's own rows of B, column-major (B may be strided).
  std::vector<double> rhs(std::max<size_t>(1, nloc * nv));
  {
    auto b = B.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (size_t j = 0; j < nv; ++j)
      for (size_t i = 0; i < nloc; ++i) rhs[i + j * nloc] = b(i, j);
  }
  const size_t nsol = static_cast<size_t>(std::max<MUMPS_INT>(info(id, 23), 0));
  std::vector<double> sol(std::max<size_t>(1, nsol * nv));
  std::vector<MUMPS_INT> isol(std::max<size_t>(1, nsol));
  id.nrhs = static_cast<MUMPS_INT>(nv);
  id.nloc_rhs = static_cast<MUMPS_INT>(nloc);
  id.lrhs_loc = static_cast<MUMPS_INT>(std::max<size_t>(1, nloc));
  id.irhs_loc = const_cast<MUMPS_INT*>(m.rowIndex.data());
  id.rhs_loc = rhs.data();
  id.lsol_loc = static_cast<MUMPS_INT>(std::max<size_t>(1, nsol));
  id.sol_loc = sol.data();
  id.isol_loc = isol.data();
  icntl(id, 9) = transposed ? 0 : 1;  // 1: A X = B; otherwise A^T X = B
  m.call(3);
  icntl(id, 9) = 1;
  const int e = infog(id, 1);
  id.rhs_loc = id.sol_loc = nullptr;
  id.irhs_loc = id.isol_loc = nullptr;
  if (e < 0)
    throw NumericalError(name_ + ": MUMPS solve failed with INFOG(1) = " + std::to_string(e) + ": " +
                         errorMeaning(e, infog(id, 2)));
  if (m.solMap.is_null()) {
    Teuchos::Array<GlobalOrdinal> ids(nsol);
    for (size_t k = 0; k < nsol; ++k) ids[k] = isol[k] - 1;
    m.solMap = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(n_), ids(), 0, m.idMap->getComm()));
    m.fromSol = Teuchos::rcp(new Tpetra::Import<>(m.solMap, m.idMap));
  }
  MultiVector S(m.solMap, nv), Xid(m.idMap, nv);
  {
    auto s = S.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (size_t j = 0; j < nv; ++j)
      for (size_t k = 0; k < nsol; ++k) s(k, j) = sol[k + j * nsol];
  }
  Xid.doImport(S, *m.fromSol, Tpetra::INSERT);
  auto from = Xid.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto to = X.getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (size_t j = 0; j < nv; ++j)
    for (size_t i = 0; i < nloc; ++i) to(i, j) = from(i, j);
}

int ranksOnNode(const Teuchos::Comm<int>& comm) {
  MPI_Comm node;
  MPI_Comm_split_type(rawMpiComm(comm), MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int onNode = 1;
  MPI_Comm_size(node, &onNode);
  MPI_Comm_free(&node);
  return onNode;
}

namespace {
/// The inertia from a count-only factorisation `f` (distributedInertia):
/// METIS's nested dissection, MUMPS's failure returned, not thrown.
SparseInertia countPivots(DistributedDirectSolver& f, bool releaseMatrix = false) {
  SparseInertia out;
  out.method = "MUMPS multifrontal L D L^T";
  f.setOrdering(DistributedDirectSolver::Ordering::NestedDissection);
  f.setPivotsOnly(true, releaseMatrix);  // the signs of the pivots are the count: no factor is kept
  try {
    f.factor(/*allowNullPivots*/ true);
  } catch (const NumericalError& e) {
    out.failure = e.what();
    return out;
  }
  out.negative = f.negativePivots();
  out.tinyPivots = f.nullPivots();
  out.positive = f.rows() - out.negative - out.tinyPivots;
  return out;
}

}  // namespace

SparseInertia distributedInertia(const CrsMatrix& A) {
  DistributedDirectSolver f(Teuchos::rcpFromRef(A), DistributedDirectSolver::Kind::Symmetric, "inertia");
  return countPivots(f);
}

SparseInertia distributedInertia(Teuchos::RCP<const CrsMatrix> A) {
  DistributedDirectSolver f(std::move(A), DistributedDirectSolver::Kind::Symmetric, "inertia");
  return countPivots(f, /*releaseMatrix*/ true);
}

SparseInertia distributedInertia(const CrsMatrix& A, const CrsMatrix& B) {
  DistributedDirectSolver f(Teuchos::rcpFromRef(A), Teuchos::rcpFromRef(B), "inertia of the real embedding");
  return countPivots(f);
}

bool useDistributedSolver(const std::string& choice, const CrsMatrix& A, long long autoEntries) {
  if (choice == "MUMPS") return true;
  if (choice == "CHOLMOD") return false;
  CMS_INPUT_CHECK(choice != "Auto", "\"Direct Solver\" = \"" << choice << "\"; valid: Auto, CHOLMOD, MUMPS");
  return A.getComm()->getSize() > 1 && static_cast<long long>(A.getGlobalNumEntries()) >= autoEntries;
}

}  // namespace cms
