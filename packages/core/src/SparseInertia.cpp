#include "cms/core/SparseInertia.hpp"

#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>

#include "cms/core/DistributedDirectSolver.hpp"  // distributedInertia
#include "cms/core/Error.hpp"
#include "cms/core/PeakMemory.hpp"  // availableMemoryBytes
#include "cms/core/Redistribution.hpp"  // GatheredRows

namespace cms {

namespace {

/// The upper triangle of a symmetric matrix by columns (CSC), filled a
/// column at a time: begin(j), then add(i, v) for its entries i <= j.
class UpperColumns {
public:
  UpperColumns(std::size_t n, std::size_t nnzBound) : p_(n + 1, 0) {
    i_.reserve(nnzBound);
    x_.reserve(nnzBound);
  }
  void begin(std::size_t j) { p_[j] = static_cast<int>(i_.size()); }
  void add(int i, double v) {
    i_.push_back(i);
    x_.push_back(v);
  }
  void finish() { p_.back() = static_cast<int>(i_.size()); }
  std::size_t n() const { return p_.size() - 1; }
  const std::vector<int>& p() const { return p_; }
  const std::vector<int>& i() const { return i_; }
  const std::vector<double>& x() const { return x_; }

private:
  std::vector<int> p_, i_;
  std::vector<double> x_;
};

/// CHOLMOD's LDL^T of the symmetric matrix whose upper triangle is given by
/// columns and the inertia of its D; rank 0 only. With `flopLimit` > 0, a
/// factorisation CHOLMOD's analysis predicts above that many flops is not
/// done: `tooCostly` is set and nothing else.
SparseInertia ldltInertia(const UpperColumns& upper, double flopLimit, bool& tooCostly) {
  tooCostly = false;
  SparseInertia out;
  out.method = "CHOLMOD simplicial L D L^T";
  const std::size_t n = upper.n();
  const std::size_t nnz = upper.i().size();
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  // L D L^T of an indefinite matrix: simplicial (supernodal is always
  // L L^T and stops at the first non-positive pivot), left as L D L^T
  // (final_ll = 0), D never modified (dbound = 0), no early stop.
  common.supernodal = CHOLMOD_SIMPLICIAL;
  common.final_ll = 0;
  common.dbound = 0.0;
  common.quick_return_if_not_posdef = 0;
  // One ordering, AMD: CHOLMOD's default tries METIS too when AMD's fill is
  // high, which for a large 3-D model costs seconds before Auto hands the
  // count to MUMPS (which orders by METIS itself).
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_AMD;
  // CHOLMOD reads the columns where they are (a copy was 43 of the 217 MiB
  // the 54,000-DOF bar's count held at its peak); never freed by CHOLMOD.
  cholmod_sparse view{};
  view.nrow = view.ncol = n;
  view.nzmax = nnz;
  view.p = const_cast<int*>(upper.p().data());
  view.i = const_cast<int*>(upper.i().data());
  view.x = const_cast<double*>(upper.x().data());
  view.stype = 1;  // the upper triangle
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 0;
  view.packed = 1;
  cholmod_sparse* S = &view;
  std::vector<double> diag(n, 0.0);
  for (std::size_t j = 0; j < n; ++j)
    for (int k = upper.p()[j]; k < upper.p()[j + 1]; ++k)
      if (static_cast<std::size_t>(upper.i()[k]) == j) diag[j] += upper.x()[k];
  cholmod_factor* L = cholmod_analyze(S, &common);
  if (L && flopLimit > 0.0 && common.fl > flopLimit) {
    tooCostly = true;
    cholmod_free_factor(&L, &common);
    cholmod_finish(&common);
    return out;
  }
  if (L) cholmod_factorize(S, L, &common);
  if (!L || common.status < CHOLMOD_OK || L->is_ll || L->is_super) {
    out.failure = "CHOLMOD's L D L^T failed (status " + std::to_string(common.status) + ")";
  } else {
    const auto* Lp = static_cast<const int*>(L->p);
    const auto* Lx = static_cast<const double*>(L->x);
    const auto* perm = static_cast<const int*>(L->Perm);
    double amax = 0.0;
    for (double a : diag) amax = std::max(amax, std::abs(a));
    for (std::size_t j = 0; j < n; ++j) {
      const double d = Lx[Lp[j]];  // the diagonal of a simplicial L D L^T holds D
      if (!std::isfinite(d) || std::abs(d) <= kTinyPivot * amax) {
        ++out.tinyPivots;
        continue;
      }
      (d < 0.0 ? out.negative : out.positive) += 1;
      out.maxPivotRatio = std::max(out.maxPivotRatio, std::abs(diag[perm ? perm[j] : j]) / std::abs(d));
    }
    // CHOLMOD records an exactly zero pivot in L->minor.
    if (L->minor < L->n && out.tinyPivots == 0) out.tinyPivots = 1;
  }
  if (L) cholmod_free_factor(&L, &common);
  cholmod_finish(&common);
  return out;
}

/// Rank 0's result on every rank.
SparseInertia broadcast(const Teuchos::Comm<int>& comm, SparseInertia r) {
  long long counts[3] = {r.negative, r.positive, r.tinyPivots};
  Teuchos::broadcast(comm, 0, 3, counts);
  r.negative = counts[0], r.positive = counts[1], r.tinyPivots = counts[2];
  Teuchos::broadcast(comm, 0, &r.maxPivotRatio);
  int len = static_cast<int>(r.failure.size());
  Teuchos::broadcast(comm, 0, &len);
  r.failure.resize(len);
  if (len > 0) Teuchos::broadcast(comm, 0, len, &r.failure[0]);
  r.method = "CHOLMOD simplicial L D L^T";
  return r;
}

void checkSquare(const CrsMatrix& A, const char* what) {
  CMS_INPUT_CHECK(!A.isFillComplete() || !A.getRowMap()->isSameAs(*A.getRangeMap()) ||
                      !A.getRowMap()->isSameAs(*A.getDomainMap()),
                  "inertia: " << what << " must be fill-complete with equal row, range and domain maps");
}

/// Whether rank 0 found the simplicial count too costly (Auto), on every rank.
bool agreeTooCostly(const Teuchos::Comm<int>& comm, bool tooCostly) {
  int flag = tooCostly ? 1 : 0;
  Teuchos::broadcast(comm, 0, &flag);
  return flag != 0;
}

double flopLimitOf(InertiaMethod method) {
  return method == InertiaMethod::Auto ? kSimplicialInertiaFlops : 0.0;
}

}  // namespace

Teuchos::RCP<const Map> stateMap(const Map& rowMap) {
  const GlobalOrdinal N = static_cast<GlobalOrdinal>(rowMap.getGlobalNumElements());
  const auto mine = rowMap.getNodeElementList();
  Teuchos::Array<GlobalOrdinal> gids(2 * mine.size());
  for (std::size_t i = 0; i < static_cast<std::size_t>(mine.size()); ++i) {
    gids[i] = mine[i];
    gids[mine.size() + i] = mine[i] + N;
  }
  return Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(2 * N), gids(),
                              rowMap.getIndexBase(), rowMap.getComm()));
}

Teuchos::RCP<CrsMatrix> realEmbedding(const CrsMatrix& A, const CrsMatrix& B, const Teuchos::RCP<const Map>& map2) {
  const auto rowMap = A.getRowMap();
  const GlobalOrdinal N = static_cast<GlobalOrdinal>(rowMap->getGlobalNumElements());
  const size_t nloc = rowMap->getNodeNumElements();
  // Exactly the entries each row needs (row g and row g + N both hold A's
  // and B's row): a bound by the longest row allocated 2n times that
  // (measured: 5.8 GB for the 1e5-row embedding of the 5e4-DOF rotor's Sturm
  // count, whose MUMPS factor took 0.58 GB).
  Teuchos::Array<size_t> perRow(2 * nloc);
  for (size_t i = 0; i < nloc; ++i)
    perRow[i] = perRow[nloc + i] = A.getNumEntriesInLocalRow(i) + B.getNumEntriesInLocalRow(i);
  auto C = Teuchos::rcp(new CrsMatrix(map2, perRow()));
  for (size_t i = 0; i < nloc; ++i) {
    const GlobalOrdinal g = rowMap->getGlobalElement(static_cast<LocalOrdinal>(i));
    for (int which = 0; which < 2; ++which) {
      const CrsMatrix& X = which == 0 ? A : B;
      CrsMatrix::local_inds_host_view_type cols;
      CrsMatrix::values_host_view_type vals;
      X.getLocalRowView(static_cast<LocalOrdinal>(i), cols, vals);
      const auto colMap = X.getColMap();
      Teuchos::Array<GlobalOrdinal> gc(cols.extent(0));
      Teuchos::Array<double> v(cols.extent(0)), mv(cols.extent(0));
      for (size_t e = 0; e < cols.extent(0); ++e) {
        gc[e] = colMap->getGlobalElement(cols(e));
        v[e] = vals(e);
        mv[e] = -vals(e);
      }
      Teuchos::Array<GlobalOrdinal> gcN(gc);
      for (auto& c : gcN) c += N;
      if (which == 0) {  // A on both diagonal blocks
        C->insertGlobalValues(g, gc(), v());
        C->insertGlobalValues(g + N, gcN(), v());
      } else {  // -B upper right, B lower left
        C->insertGlobalValues(g, gcN(), mv());
        C->insertGlobalValues(g + N, gc(), v());
      }
    }
  }
  C->fillComplete(map2, map2);
  return C;
}

namespace {
/// Before the multifrontal count of an n-row matrix whose upper triangle
/// has `upperEntries` entries (known on rank 0): a count with an empty
/// `failure` if it may fit, else one that says why not, on every rank. The
/// solver's own guard (DistributedDirectSolver: MUMPS's estimate INFO(17),
/// the count keeping no factor) comes only after MUMPS's triplets, METIS's
/// ordering and MUMPS's analysis are built on rank 0, which for the
/// 5.7e5-DOF rotor's truth took the 24 GiB machine from 13 GiB (the truth's
/// own factor and vectors) to its out-of-memory killer. So first an
/// estimate of that preparation's peak: kPreparationBytes an upper entry,
/// measured at METIS's ordering on the 16,800-DOF bar's truth count
/// (heaptrack, 2.63e6 upper entries of the embedding: MUMPS's triplets 16
/// bytes, CHOLMOD's symmetric copy for METIS 12, METIS's own graphs 23,
/// the rest 7; 58 in all).
constexpr double kPreparationBytes = 60.0;
SparseInertia multifrontalCannotFit(const Teuchos::Comm<int>& comm, Tpetra::global_size_t n, double upperEntries) {
  const int onNode = ranksOnNode(comm);
  double figures[2] = {kPreparationBytes * upperEntries, availableMemoryBytes() / onNode};
  Teuchos::broadcast(comm, 0, 2, figures);
  SparseInertia refused;
  refused.method = "MUMPS multifrontal L D L^T";
  if (!(figures[0] > 0.9 * figures[1])) return refused;
  std::ostringstream os;
  os << std::setprecision(3) << "the multifrontal L D L^T of the " << n
     << "-row matrix was not started: rank 0 would need about " << figures[0] / 1e9
     << " GB to prepare it (MUMPS's triplets and METIS's ordering), more than 90% of the "
     << figures[1] / 1e9 << " GB it may use (CMS_MEMORY_LIMIT or the node's available memory)";
  refused.failure = os.str();
  return refused;
}

/// The multifrontal count `run()` if its preparation fits
/// (multifrontalCannotFit), else the refusal; the same on every rank.
template <class Run>
SparseInertia multifrontalIfItFits(const Teuchos::Comm<int>& comm, Tpetra::global_size_t n, double upperEntries,
                                   Run&& run) {
  SparseInertia refused = multifrontalCannotFit(comm, n, upperEntries);
  return refused.failure.empty() ? run() : refused;
}
}  // namespace

SparseInertia inertia(const CrsMatrix& A, InertiaMethod method) {
  return inertia(Teuchos::rcpFromRef(A), method);  // not owned: nothing is freed
}

SparseInertia inertia(Teuchos::RCP<const CrsMatrix> owned, InertiaMethod method) {
  return inertia(std::move(owned), method, 0.0);
}

SparseInertia inertia(Teuchos::RCP<const CrsMatrix> owned, InertiaMethod method, double patternFlops) {
  const CrsMatrix& A = *owned;
  checkSquare(A, "A");
  if (method == InertiaMethod::Multifrontal) return distributedInertia(std::move(owned));
  if (method == InertiaMethod::Auto && patternFlops > kSimplicialInertiaFlops) {
    // The upper triangle's entries, for the memory guard: the diagonal and
    // half of the rest (symmetric), counted without gathering anything.
    const double n = static_cast<double>(A.getGlobalNumRows());
    const double upperEntries = 0.5 * (static_cast<double>(A.getGlobalNumEntries()) + n);
    return multifrontalIfItFits(*A.getComm(), A.getGlobalNumRows(), upperEntries,
                                [&] { return distributedInertia(std::move(owned)); });
  }
  SparseInertia r;
  bool tooCostly = false;
  double upperEntries = 0.0;
  {  // the gathered copy released before the multifrontal path
    const GatheredRows a(Teuchos::rcpFromRef(A), 0);
    if (A.getComm()->getRank() == 0) {
      // Symmetric: row j is column j; keep its upper part (i <= j).
      UpperColumns cols(a.size(), a.entries() / 2 + a.size());
      for (std::size_t j = 0; j < a.size(); ++j) {
        cols.begin(j);
        a.forEachUpper(j, [&](int i, double v) { cols.add(i, v); });
      }
      cols.finish();
      upperEntries = static_cast<double>(cols.i().size());
      r = ldltInertia(cols, flopLimitOf(method), tooCostly);
    }
  }
  if (agreeTooCostly(*A.getComm(), tooCostly)) {
    return multifrontalIfItFits(*A.getComm(), A.getGlobalNumRows(), upperEntries,
                                [&] { return distributedInertia(std::move(owned)); });
  }
  return broadcast(*A.getComm(), r);
}

namespace {
/// Halved counts of the real embedding; an odd count is a failure.
SparseInertia halved(SparseInertia r, const char* who) {
  if (r.failure.empty() && r.tinyPivots == 0 && (r.negative % 2 != 0 || r.positive % 2 != 0))
    r.failure = std::string("the real embedding of A + iB has ") + std::to_string(r.negative) + " negative pivots (" +
                who + "), an odd number (each eigenvalue of A + iB is one of the embedding's twice): the "
                "factorisation is not to be trusted";
  r.negative /= 2, r.positive /= 2, r.tinyPivots = (r.tinyPivots + 1) / 2;
  return r;
}
}  // namespace

SparseInertia inertia(const CrsMatrix& A, const CrsMatrix& B, InertiaMethod method) {
  checkSquare(A, "A");
  checkSquare(B, "B");
  CMS_INPUT_CHECK(!A.getRowMap()->isSameAs(*B.getRowMap()), "inertia: A and B must share their row map");
  const auto multifrontal = [&] {
    return halved(distributedInertia(A, B), "MUMPS");  // from A's and B's rows: no 2n-row matrix
  };
  if (method == InertiaMethod::Multifrontal) return multifrontal();
  SparseInertia r;
  bool tooCostly = false;
  double upperEntries = 0.0;
  {  // the gathered copies released before the multifrontal path
  const GatheredRows a(Teuchos::rcpFromRef(A), 0), b(Teuchos::rcpFromRef(B), 0);
  if (A.getComm()->getRank() == 0) {
    // Upper triangle of E = [[A, -B], [B, A]] by columns. Column j < n: A's
    // (i, j), i <= j. Column n + j: the block -B, whose column j is row j of
    // B (B^T = -B), then A's (i, j), i <= j, at rows n + i.
    const std::size_t n = a.size();
    UpperColumns cols(2 * n, a.entries() + b.entries() + 2 * n);
    for (std::size_t j = 0; j < n; ++j) {
      cols.begin(j);
      a.forEachUpper(j, [&](int i, double v) { cols.add(i, v); });
    }
    for (std::size_t j = 0; j < n; ++j) {
      cols.begin(n + j);
      a.forEachUpper(j, [&](int i, double v) { cols.add(static_cast<int>(n) + i, v); });
      b.forEach(j, [&](int i, double v) { cols.add(i, v); });
    }
    cols.finish();
    upperEntries = static_cast<double>(cols.i().size());
    r = ldltInertia(cols, flopLimitOf(method), tooCostly);
    if (!tooCostly) r = halved(r, "CHOLMOD");
  }
  }
  if (agreeTooCostly(*A.getComm(), tooCostly)) {
    return multifrontalIfItFits(*A.getComm(), 2 * A.getGlobalNumRows(), upperEntries, multifrontal);
  }
  return broadcast(*A.getComm(), r);
}

}  // namespace cms
