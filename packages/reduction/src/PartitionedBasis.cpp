// The Partitioned basis (doc/theory.md §18): one level of automatic
// substructuring inside a large substructure. Steps, in order:
//   1. the node graph of K, gathered to rank 0, partitioned by Scotch; the
//      nodes on the cut edges (and the children's interface nodes) form the
//      separator B, the rest the parts' interiors;
//   2. each part's rows imported whole to the rank that owns it (parts dealt
//      round-robin), the separator's to rank 0;
//   3. per part, on its rank alone: K_pp factored (CHOLMOD), the static
//      extension X_p = -K_pp^-1 K_pB, its contributions to the interface's
//      Schur complement S and mass M^, and the fixed-interface modes below
//      the cut-off (counted by a Sturm sequence, found by ARPACK's
//      shift-invert Lanczos with the same factor, or LAPACK when small);
//   4. on rank 0: S and M^ assembled, their modes below the cut-off (the
//      characteristic constraint modes);
//   5. the columns [Phi_p; X Psi] laid out on the substructure's map and
//      M-orthonormalised in order like every Ritz basis.
#include "cms/reduction/PartitionedBasis.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <numeric>
#include <tuple>
#include <sstream>

#include <arpack/arpack.h>
#include <mpi.h>
#include <scotch.h>

#include <Teuchos_BLAS.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_MultiVector.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

#include "LoadPatterns.hpp"
#include "SymmetricEigen.hpp"
#include "cms/core/MatrixSum.hpp"
#include "cms/core/MpiComm.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/Redistribution.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/core/SparseInertia.hpp"

namespace cms::reduction {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// A serial symmetric matrix by rows (both triangles), columns sorted.
struct Csr {
  int n = 0;
  std::vector<int> ptr{0}, col;
  std::vector<double> val;
  void endRow() { ptr.push_back(static_cast<int>(col.size())); }
};

/// Triplets summed into a Csr of order n (duplicates added).
Csr fromTriplets(int n, std::vector<std::pair<long long, double>>& t) {
  std::sort(t.begin(), t.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Csr A;
  A.n = n;
  std::size_t k = 0;
  for (int i = 0; i < n; ++i) {
    while (k < t.size() && t[k].first / n == i) {
      const long long key = t[k].first;
      double v = 0.0;
      for (; k < t.size() && t[k].first == key; ++k) v += t[k].second;
      A.col.push_back(static_cast<int>(key % n));
      A.val.push_back(v);
    }
    A.endRow();
  }
  return A;
}

Teuchos::RCP<CrsMatrix> toTpetra(const Csr& A, const Teuchos::RCP<const Teuchos::Comm<int>>& self) {
  auto map = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(A.n), 0, self));
  std::vector<std::size_t> counts(A.n);
  for (int i = 0; i < A.n; ++i) counts[i] = static_cast<std::size_t>(A.ptr[i + 1] - A.ptr[i]);
  auto T = Teuchos::rcp(new CrsMatrix(map, Teuchos::ArrayView<const std::size_t>(counts)));
  std::vector<GlobalOrdinal> cols;
  for (int i = 0; i < A.n; ++i) {
    cols.assign(A.col.begin() + A.ptr[i], A.col.begin() + A.ptr[i + 1]);
    T->insertGlobalValues(i, Teuchos::ArrayView<const GlobalOrdinal>(cols),
                          Teuchos::ArrayView<const double>(A.val.data() + A.ptr[i], A.ptr[i + 1] - A.ptr[i]));
  }
  T->fillComplete();
  return T;
}

/// Modes of K x = lambda M x below lambda_cut, M-orthonormal, column-major
/// n x m. `factor` is K's factorisation (ARPACK's shift-invert at 0).
struct Modes {
  int m = 0;
  std::vector<double> lambda, vectors;
  std::string method;
};

Modes modesBelow(const CrsMatrix& K, const CrsMatrix& M, const Csr& Kc, const Csr& Mc, double lambdaCut,
                 const SparseDirectSolver& factor, double tolerance, const std::string& what) {
  Modes out;
  const int n = Kc.n;
  // How many: the inertia of K - lambda_cut M (Sylvester), one LDL^T.
  Teuchos::RCP<const CrsMatrix> A = matrixSum(1.0, K, -lambdaCut, M);
  const auto count = inertia(std::move(A));  // handed over: freed once the count holds its values
  if (!count.reliable())
    throw NumericalError(what + ": the Sturm count at the cut-off failed (" +
                         (count.failure.empty() ? std::string("a pivot zero to rounding: the cut-off is one of its "
                                                              "frequencies; move it")
                                                : count.failure) +
                         ")");
  const int nev = static_cast<int>(count.negative);
  if (nev == 0) return out;
  if (n <= 600 || 3 * nev > n) {  // small: LAPACK on the dense pencil
    std::vector<double> Kd(static_cast<std::size_t>(n) * n, 0.0), Md(Kd.size(), 0.0), w;
    for (int i = 0; i < n; ++i) {
      for (int e = Kc.ptr[i]; e < Kc.ptr[i + 1]; ++e) Kd[i + static_cast<std::size_t>(Kc.col[e]) * n] = Kc.val[e];
      for (int e = Mc.ptr[i]; e < Mc.ptr[i + 1]; ++e) Md[i + static_cast<std::size_t>(Mc.col[e]) * n] = Mc.val[e];
    }
    const int info = detail::symmetricEigen(Kd, Md, n, true, w);
    if (info != 0) throw NumericalError(what + ": LAPACK dsygv failed (info " + std::to_string(info) + ")");
    out.m = nev;
    out.lambda.assign(w.begin(), w.begin() + nev);
    out.vectors.assign(Kd.begin(), Kd.begin() + static_cast<std::size_t>(n) * nev);
    out.method = "LAPACK";
    return out;
  }
  // ARPACK, mode 3: OP = K^-1 M in the M inner product, largest |1/lambda|.
  const int ncv = std::min(n, std::max(2 * nev + 1, nev + 20));
  const int lworkl = ncv * (ncv + 8);
  std::vector<double> resid(n), v(static_cast<std::size_t>(n) * ncv), workd(3 * static_cast<std::size_t>(n)),
      workl(lworkl);
  // A fixed start: the modes must not depend on which rank (and after which
  // other parts) ARPACK's own random sequence is drawn.
  for (int i = 0; i < n; ++i) resid[i] = 1.0 + 0.5 * std::sin(0.37 * i);
  a_int iparam[11] = {}, ipntr[14] = {};
  iparam[0] = 1;
  iparam[2] = 500;
  iparam[6] = 3;
  a_int ido = 0, info = 1;
  const auto map = K.getRowMap();
  Vector x(map), y(map), Mx(map);
  auto apply = [&](const double* in, double* to, bool solve, bool mass) {
    {
      auto d = x.getDataNonConst();
      std::copy(in, in + n, d.begin());
    }
    if (mass) {
      M.apply(x, Mx);
      if (!solve) {
        auto d = Mx.getData();
        std::copy(d.begin(), d.end(), to);
        return;
      }
      factor.solve(Mx, y);
    } else {
      factor.solve(x, y);
    }
    auto d = y.getData();
    std::copy(d.begin(), d.end(), to);
  };
  for (;;) {
    dsaupd_c(&ido, "G", n, "LM", nev, tolerance, resid.data(), ncv, v.data(), n, iparam, ipntr, workd.data(),
             workl.data(), lworkl, &info);
    double* in = workd.data() + ipntr[0] - 1;
    double* to = workd.data() + ipntr[1] - 1;
    if (ido == -1) apply(in, to, true, true);
    else if (ido == 1) apply(workd.data() + ipntr[2] - 1, to, true, false);
    else if (ido == 2) apply(in, to, false, true);
    else break;
  }
  if (info < 0 || iparam[4] < nev)
    throw NumericalError(what + ": ARPACK (dsaupd) converged " + std::to_string(iparam[4]) + " of the " +
                         std::to_string(nev) + " modes below the cut-off (info " + std::to_string(info) + ")");
  std::vector<a_int> select(ncv);
  std::vector<double> d(nev), z(static_cast<std::size_t>(n) * nev);
  a_int einfo = 0;
  dseupd_c(1, "A", select.data(), d.data(), z.data(), n, 0.0, "G", n, "LM", nev, tolerance, resid.data(), ncv,
           v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, &einfo);
  if (einfo != 0) throw NumericalError(what + ": ARPACK (dseupd) failed (info " + std::to_string(einfo) + ")");
  out.m = nev;
  out.lambda = d;
  out.vectors = std::move(z);
  out.method = "ARPACK";
  return out;
}

/// Raises on every rank when any rank failed (the message of the lowest
/// failing rank), so that a part's failure cannot leave the others waiting.
void agreeOnFailure(const Teuchos::Comm<int>& comm, const std::string& failure) {
  const int mine = failure.empty() ? comm.getSize() : comm.getRank();
  int first = 0;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MIN, mine, Teuchos::outArg(first));
  if (first == comm.getSize()) return;
  int length = comm.getRank() == first ? static_cast<int>(failure.size()) : 0;
  Teuchos::broadcast(comm, first, &length);
  std::string message(length, ' ');
  if (comm.getRank() == first) message = failure;
  if (length > 0) Teuchos::broadcast(comm, first, length, message.data());
  throw NumericalError(message);
}

/// What one part contributes (kept on the rank that owns it).
struct PartWork {
  int part = -1;
  std::vector<GlobalOrdinal> rows;   ///< interior rows, ascending
  std::vector<int> boundary;         ///< separator indices (0 .. nB-1) it touches, ascending
  std::vector<double> X;             ///< n_p x n_Bp, column-major: the static extension
  Modes modes;
  Teuchos::RCP<CrsMatrix> Mpp;       ///< the part's interior mass
  std::shared_ptr<SparseDirectSolver> factor;  ///< K_pp, kept for the residual vectors
  std::vector<std::tuple<int, int, double>> MpB;  ///< mass coupling to the separator (i, separator index)
  std::vector<double> Yf;            ///< n_p x n_f: K_pp^-1 f_p for the static load patterns
  double seconds = 0.0;
};

}  // namespace

RitzBasis partitionedBasis(const substructure::Substructure& s, const SubstructureBoundary& boundary,
                           const PartitionOptions& options) {
  const auto t0 = Clock::now();
  const auto comm = s.map()->getComm();
  const int rank = comm->getRank(), ranks = comm->getSize();
  const auto& dofs = s.dofs();
  const long long rows = dofs.rows();
  const auto rowNode = dofs.rowNodes();
  const std::int64_t nodes = static_cast<std::int64_t>(dofs.nodes());
  const std::string where = "Scene/Substructures/" + s.name() + "/Reduction";
  CMS_INPUT_CHECK(!(options.cutoffHz > 0.0) || !std::isfinite(options.cutoffHz),
                  where << "/Cutoff Frequency = " << options.cutoffHz
                        << ": the Partitioned basis keeps every part's and the interface's modes below it; give a "
                           "frequency > 0 (Hz), a few times the highest one wanted");
  CMS_INPUT_CHECK(!(options.interfaceCutoffFactor >= 1.0) || !std::isfinite(options.interfaceCutoffFactor),
                  where << "/Partition/Interface Cutoff Factor = " << options.interfaceCutoffFactor << " must be >= 1");
  CMS_INPUT_CHECK(options.parts < 0, where << "/Partition/Parts = " << options.parts << " must be >= 0");
  CMS_INPUT_CHECK(options.parts == 0 && options.maxDofs < 1,
                  where << "/Partition/Max DOFs = " << options.maxDofs << " must be >= 1");
  const double lambdaCut = std::pow(2.0 * M_PI * options.cutoffHz, 2);

  // Row classes: -2 held, -1 separator, p >= 0 interior of part p.
  std::vector<char> held(rows, 0);
  for (GlobalOrdinal g : boundary.held) held[g] = 1;
  const long long freeRows = rows - std::count(held.begin(), held.end(), 1);
  const int parts = options.parts > 0 ? options.parts
                                      : static_cast<int>(std::max<long long>(1, (freeRows + options.maxDofs - 1) / options.maxDofs));
  CMS_INPUT_CHECK(parts > nodes, where << "/Partition/Parts = " << parts << " but substructure \"" << s.name()
                                       << "\" has only " << nodes << " nodes");

  // 1. The partition, on rank 0 from the whole graph of K (node to node).
  const auto tPartition = Clock::now();
  std::vector<int> nodePart(nodes, 0);
  std::string failure;
  {
    const auto self = comm->split(rank, 0);
    const auto K0 = gatherToRank(*s.K(), 0, self);
    if (rank == 0) {
      std::vector<std::vector<SCOTCH_Num>> adjacent(nodes);
      CrsMatrix::local_inds_host_view_type cols;
      CrsMatrix::values_host_view_type vals;
      const auto colMap = K0->getColMap();
      for (long long r = 0; r < rows; ++r) {
        K0->getLocalRowView(static_cast<LocalOrdinal>(r), cols, vals);
        const auto a = rowNode[r];
        for (std::size_t e = 0; e < cols.extent(0); ++e) {
          const auto b = rowNode[colMap->getGlobalElement(cols(e))];
          if (b != a) {  // both arcs: Scotch needs a symmetric graph, whatever K's stored pattern
            adjacent[a].push_back(static_cast<SCOTCH_Num>(b));
            adjacent[b].push_back(static_cast<SCOTCH_Num>(a));
          }
        }
      }
      std::vector<SCOTCH_Num> vert(nodes + 1, 0), edge;
      for (std::int64_t a = 0; a < nodes; ++a) {
        auto& l = adjacent[a];
        std::sort(l.begin(), l.end());
        l.erase(std::unique(l.begin(), l.end()), l.end());
        edge.insert(edge.end(), l.begin(), l.end());
        vert[a + 1] = static_cast<SCOTCH_Num>(edge.size());
        std::vector<SCOTCH_Num>().swap(l);
      }
      if (parts > 1) {
        // A deterministic context with a fixed seed: the same partition on
        // every call, whatever ran before (the global random state and
        // Scotch's threads made it differ between calls).
        SCOTCH_Context context;
        SCOTCH_Graph graph, bound;
        SCOTCH_Strat strategy;
        std::vector<SCOTCH_Num> partOf(nodes, 0);
        // Every object initialised before anything can fail, and each exited
        // once (exiting one never initialised corrupted the heap).
        int status = SCOTCH_contextInit(&context) | SCOTCH_graphInit(&graph) | SCOTCH_graphInit(&bound) |
                     SCOTCH_stratInit(&strategy);
        // One thread: Scotch's own threads hung in its thread launch (3
        // parts of the benchmark hub), and the partition is a small part of
        // the time.
        if (status == 0) status = SCOTCH_contextThreadSpawn(&context, 1, nullptr);
        if (status == 0) status = SCOTCH_contextOptionSetNum(&context, SCOTCH_OPTIONNUMDETERMINISTIC, 1);
        if (status == 0) status = SCOTCH_contextOptionSetNum(&context, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1);
        if (status == 0) status = SCOTCH_contextRandomClone(&context);
        if (status == 0) SCOTCH_contextRandomSeed(&context, 1);
        if (status == 0)
          status = SCOTCH_graphBuild(&graph, 0, static_cast<SCOTCH_Num>(nodes), vert.data(), nullptr, nullptr,
                                     nullptr, static_cast<SCOTCH_Num>(edge.size()), edge.data(), nullptr);
        if (status == 0 && SCOTCH_graphCheck(&graph) != 0) status = -1;
        if (status == 0) status = SCOTCH_contextBindGraph(&context, &graph, &bound);
        if (status == 0) status = SCOTCH_stratGraphMapBuild(&strategy, SCOTCH_STRATQUALITY, parts, 0.05);
        if (status == 0) status = SCOTCH_graphPart(&bound, parts, &strategy, partOf.data());
        SCOTCH_stratExit(&strategy);
        SCOTCH_graphExit(&bound);
        SCOTCH_graphExit(&graph);
        SCOTCH_contextExit(&context);
        if (status != 0)
          failure = s.name() + ": Scotch could not partition the node graph into " + std::to_string(parts) +
                    " parts (status " + std::to_string(status) + ")";
        std::copy(partOf.begin(), partOf.end(), nodePart.begin());
        // The separator: of every cut edge, the node of the higher part; so
        // no edge joins the interiors of two parts (a vertex separator).
        std::vector<int> separator(nodes, 0);
        for (std::int64_t a = 0; a < nodes; ++a)
          for (SCOTCH_Num e = vert[a]; e < vert[a + 1]; ++e) {
            const auto b = edge[e];
            if (partOf[a] != partOf[b]) separator[partOf[a] > partOf[b] ? a : b] = 1;
          }
        for (std::int64_t a = 0; a < nodes; ++a)
          if (separator[a]) nodePart[a] = -1;
      }
      for (const auto& rowsOfChild : boundary.interfaces)
        for (GlobalOrdinal g : rowsOfChild) nodePart[rowNode[g]] = -1;
    }
  }
  agreeOnFailure(*comm, failure);
  Teuchos::broadcast(*comm, 0, static_cast<int>(nodes), nodePart.data());
  std::vector<int> rowClass(rows);
  std::vector<int> separatorIndex(rows, -1);
  std::vector<GlobalOrdinal> separatorRows;
  for (long long r = 0; r < rows; ++r) {
    rowClass[r] = held[r] ? -2 : nodePart[rowNode[r]];
    if (rowClass[r] == -1) {
      separatorIndex[r] = static_cast<int>(separatorRows.size());
      separatorRows.push_back(r);
    }
  }
  const int nB = static_cast<int>(separatorRows.size());
  const double partitionSeconds = since(tPartition);

  // 2. Each part's rows whole on its rank; the separator's on rank 0.
  auto ownerOf = [&](int p) { return p % ranks; };
  std::vector<std::vector<GlobalOrdinal>> partRows(parts);
  for (long long r = 0; r < rows; ++r)
    if (rowClass[r] >= 0 && ownerOf(rowClass[r]) == rank) partRows[rowClass[r]].push_back(r);
  std::vector<GlobalOrdinal> mine;
  for (int p = 0; p < parts; ++p) mine.insert(mine.end(), partRows[p].begin(), partRows[p].end());
  if (rank == 0) mine.insert(mine.end(), separatorRows.begin(), separatorRows.end());
  const auto layout = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                           Teuchos::ArrayView<const GlobalOrdinal>(mine), 0, comm));
  const Tpetra::Import<> toLayout(s.map(), layout);
  const auto K = Tpetra::importAndFillCompleteCrsMatrix<CrsMatrix>(s.K(), toLayout);
  const auto M = Tpetra::importAndFillCompleteCrsMatrix<CrsMatrix>(s.M(), toLayout);
  // The static load patterns (as the Admissible basis's, §11.3), on the layout.
  Teuchos::RCP<MultiVector> loads;
  std::vector<std::string> loadLabels;
  detail::loadPatterns(s, boundary, options.loadPatterns, loads, loadLabels);
  const int nf = loads.is_null() ? 0 : static_cast<int>(loads->getNumVectors());
  MultiVector F(layout, std::max(nf, 1));
  if (nf > 0) F.doImport(*loads, toLayout, Tpetra::INSERT);
  loads = Teuchos::null;
  std::vector<double> cB(static_cast<std::size_t>(nB) * nf, 0.0);  // sum_p K_Bp K_pp^-1 f_p, this rank's parts

  // 3. The parts, each on its rank alone.
  const auto tParts = Clock::now();
  const auto self = comm->split(rank, 0);
  std::vector<PartWork> work;
  std::vector<std::pair<long long, double>> Sk, Sm;  // this rank's contributions to S and M^ (i * nB + j)
  try {
    for (int p = 0; p < parts; ++p) {
      if (ownerOf(p) != rank || partRows[p].empty()) continue;
      const auto tp = Clock::now();
      PartWork w;
      w.part = p;
      w.rows = partRows[p];
      const int n = static_cast<int>(w.rows.size());
      const std::string what = s.name() + ": part " + std::to_string(p) + " of " + std::to_string(parts) + " (" +
                               std::to_string(n) + " interior DOFs)";
      // The part's rows: interior block (Csr), coupling to the separator (triplets).
      Csr Kc, Mc;
      Kc.n = Mc.n = n;
      std::vector<std::tuple<int, int, double>> KpB, MpB;  // (interior i, separator index, value)
      auto readRows = [&](const CrsMatrix& A, Csr& inner, std::vector<std::tuple<int, int, double>>& coupling) {
        CrsMatrix::local_inds_host_view_type cols;
        CrsMatrix::values_host_view_type vals;
        const auto colMap = A.getColMap();
        std::vector<std::pair<int, double>> row;
        for (int i = 0; i < n; ++i) {
          A.getLocalRowView(layout->getLocalElement(w.rows[i]), cols, vals);
          row.clear();
          for (std::size_t e = 0; e < cols.extent(0); ++e) {
            const GlobalOrdinal g = colMap->getGlobalElement(cols(e));
            const int c = rowClass[g];
            if (c == p) {
              const auto at = std::lower_bound(w.rows.begin(), w.rows.end(), g) - w.rows.begin();
              row.emplace_back(static_cast<int>(at), vals(e));
            } else if (c == -1) {
              coupling.emplace_back(i, separatorIndex[g], vals(e));
            } else if (c >= 0) {
              throw NumericalError(what + ": couples to part " + std::to_string(c) +
                                   " across the separator (internal error of the partition)");
            }
          }
          std::sort(row.begin(), row.end());
          for (const auto& [j, v] : row) {
            inner.col.push_back(j);
            inner.val.push_back(v);
          }
          inner.endRow();
        }
      };
      readRows(*K, Kc, KpB);
      readRows(*M, Mc, MpB);
      const auto Kt = toTpetra(Kc, self), Mt = toTpetra(Mc, self);
      w.factor = std::make_shared<SparseDirectSolver>(Kt, "CHOLMOD");
      SparseDirectSolver& factor = *w.factor;
      w.Mpp = Mt;
      w.MpB = MpB;
      if (factor.factor() != SparseDirectSolver::Outcome::Factored)
        throw NumericalError(what + ": its stiffness with the separator held is not positive definite (" +
                             factor.failure() + "): the part is not restrained by the rest; fewer parts, or "
                             "check the substructure's supports");
      // The static extension X_p = -K_pp^-1 K_pB on the separator rows it touches.
      for (const auto& [i, b, v] : KpB) w.boundary.push_back(b);
      for (const auto& [i, b, v] : MpB) w.boundary.push_back(b);
      std::sort(w.boundary.begin(), w.boundary.end());
      w.boundary.erase(std::unique(w.boundary.begin(), w.boundary.end()), w.boundary.end());
      const int nb = static_cast<int>(w.boundary.size());
      auto local = [&](int b) {
        return static_cast<int>(std::lower_bound(w.boundary.begin(), w.boundary.end(), b) - w.boundary.begin());
      };
      if (nb > 0) {
        MultiVector F(Kt->getRowMap(), nb), X(Kt->getRowMap(), nb), MX(Kt->getRowMap(), nb);
        for (const auto& [i, b, v] : KpB) F.sumIntoLocalValue(i, local(b), -v);
        factor.solve(F, X);
        Mt->apply(X, MX);
        for (const auto& [i, b, v] : MpB) MX.sumIntoLocalValue(i, local(b), v);
        w.X.resize(static_cast<std::size_t>(n) * nb);
        std::vector<double> MXd(w.X.size());
        X.get1dCopy(Teuchos::ArrayView<double>(w.X), n);
        MX.get1dCopy(Teuchos::ArrayView<double>(MXd), n);
        // S_p = K_Bp X_p (= -K_Bp K_pp^-1 K_pB); M^_p = X^T (M_pp X + M_pB) + M_Bp X.
        std::vector<double> S(static_cast<std::size_t>(nb) * nb, 0.0), Mh(S.size(), 0.0);
        for (const auto& [i, b, v] : KpB) {
          const int bl = local(b);
          for (int j = 0; j < nb; ++j) S[bl + static_cast<std::size_t>(j) * nb] += v * w.X[i + static_cast<std::size_t>(j) * n];
        }
        Teuchos::BLAS<int, double>().GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, nb, nb, n, 1.0, w.X.data(), n,
                                          MXd.data(), n, 0.0, Mh.data(), nb);
        for (const auto& [i, b, v] : MpB) {
          const int bl = local(b);
          for (int j = 0; j < nb; ++j) Mh[bl + static_cast<std::size_t>(j) * nb] += v * w.X[i + static_cast<std::size_t>(j) * n];
        }
        for (int j = 0; j < nb; ++j)
          for (int i = 0; i < nb; ++i) {
            const long long key = static_cast<long long>(w.boundary[i]) * nB + w.boundary[j];
            Sk.emplace_back(key, S[i + static_cast<std::size_t>(j) * nb]);
            Sm.emplace_back(key, Mh[i + static_cast<std::size_t>(j) * nb]);
          }
      }
      w.modes = modesBelow(*Kt, *Mt, Kc, Mc, lambdaCut, factor, options.eigensolverTolerance, what);
      if (nf > 0) {  // the loads' particular part, separator held, and its reaction on the separator
        MultiVector Fp(Kt->getRowMap(), nf), Y(Kt->getRowMap(), nf);
        for (int k = 0; k < nf; ++k) {
          const auto from = F.getData(k);
          for (int i = 0; i < n; ++i) Fp.replaceLocalValue(i, k, from[layout->getLocalElement(w.rows[i])]);
        }
        factor.solve(Fp, Y);
        w.Yf.resize(static_cast<std::size_t>(n) * nf);
        Y.get1dCopy(Teuchos::ArrayView<double>(w.Yf), n);
        for (const auto& [i, b, v] : KpB)
          for (int k = 0; k < nf; ++k) cB[b + static_cast<std::size_t>(k) * nB] += v * w.Yf[i + static_cast<std::size_t>(k) * n];
      }
      w.seconds = since(tp);
      work.push_back(std::move(w));
    }
    if (rank == 0) {  // the separator's own block K_BB, M_BB
      auto addSeparatorBlock = [&](const CrsMatrix& A, std::vector<std::pair<long long, double>>& into) {
        CrsMatrix::local_inds_host_view_type cols;
        CrsMatrix::values_host_view_type vals;
        const auto colMap = A.getColMap();
        for (int i = 0; i < nB; ++i) {
          A.getLocalRowView(layout->getLocalElement(separatorRows[i]), cols, vals);
          for (std::size_t e = 0; e < cols.extent(0); ++e) {
            const GlobalOrdinal g = colMap->getGlobalElement(cols(e));
            if (rowClass[g] == -1) into.emplace_back(static_cast<long long>(i) * nB + separatorIndex[g], vals(e));
          }
        }
      };
      addSeparatorBlock(*K, Sk);
      addSeparatorBlock(*M, Sm);
    }
  } catch (const std::exception& e) {
    failure = e.what();
  }
  agreeOnFailure(*comm, failure);
  const double partsSeconds = since(tParts);

  // 4. The interface problem on rank 0: S, M^ gathered and their modes below the cut-off.
  const auto tInterface = Clock::now();
  auto gatherTriplets = [&](std::vector<std::pair<long long, double>>& t) {
    std::vector<long long> keys(t.size());
    std::vector<double> values(t.size());
    for (std::size_t k = 0; k < t.size(); ++k) keys[k] = t[k].first, values[k] = t[k].second;
    t.clear();
    try {
      const auto allKeys = gatherOnRank(keys, 0, rawMpiComm(*comm), "the interface problem's entries");
      const auto allValues = gatherOnRank(values, 0, rawMpiComm(*comm), "the interface problem's entries");
      for (std::size_t k = 0; k < allKeys.size(); ++k) t.emplace_back(allKeys[k], allValues[k]);
    } catch (const std::length_error&) {  // refused on every rank
      if (rank == 0) failure = s.name() + ": the interface problem is too large to gather";
    }
  };
  gatherTriplets(Sk);
  gatherTriplets(Sm);
  std::vector<double> uB(cB.size(), 0.0);  // the static shapes on the separator: S^-1 (f_B - sum_p K_Bp K_pp^-1 f_p)
  if (!cB.empty())
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(cB.size()), cB.data(), uB.data());
  Modes interface;
  if (rank == 0 && nB > 0 && failure.empty()) {
    try {
      const Csr S = fromTriplets(nB, Sk), Mh = fromTriplets(nB, Sm);
      std::vector<std::pair<long long, double>>().swap(Sk);
      std::vector<std::pair<long long, double>>().swap(Sm);
      const auto St = toTpetra(S, self), Mt = toTpetra(Mh, self);
      SparseDirectSolver factor(St, "CHOLMOD");
      if (factor.factor() != SparseDirectSolver::Outcome::Factored)
        throw NumericalError(s.name() + ": the interface's Schur complement (" + std::to_string(nB) +
                             " separator DOFs) is not positive definite (" + factor.failure() + ")");
      interface = modesBelow(*St, *Mt, S, Mh, lambdaCut * std::pow(options.interfaceCutoffFactor, 2), factor,
                             options.eigensolverTolerance, s.name() + ": interface (" + std::to_string(nB) + " separator DOFs)");
      if (nf > 0) {
        MultiVector g(St->getRowMap(), nf), u(St->getRowMap(), nf);
        for (int k = 0; k < nf; ++k) {
          const auto from = F.getData(k);
          for (int b = 0; b < nB; ++b)
            g.replaceLocalValue(b, k, from[layout->getLocalElement(separatorRows[b])] - uB[b + static_cast<std::size_t>(k) * nB]);
        }
        factor.solve(g, u);
        u.get1dCopy(Teuchos::ArrayView<double>(uB), nB);
      }
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  agreeOnFailure(*comm, failure);
  Teuchos::broadcast(*comm, 0, &interface.m);
  interface.vectors.resize(static_cast<std::size_t>(nB) * interface.m);
  if (!interface.vectors.empty())
    Teuchos::broadcast(*comm, 0, static_cast<int>(interface.vectors.size()), interface.vectors.data());
  if (!uB.empty()) Teuchos::broadcast(*comm, 0, static_cast<int>(uB.size()), uB.data());
  const double interfaceSeconds = since(tInterface);

  // 5. The columns on the substructure's map: each part's modes, then the
  // interface modes extended statically into every part.
  std::vector<int> counts(parts, 0), allCounts(parts, 0);
  for (const auto& w : work) counts[w.part] = w.modes.m;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, parts, counts.data(), allCounts.data());
  std::vector<int> offset(parts + 1, nf);  // the static shapes first: they carry the coupling
  for (int p = 0; p < parts; ++p) offset[p + 1] = offset[p] + allCounts[p];
  const int residuals = options.residualVectors ? interface.m : 0;
  const int columns = offset[parts] + interface.m + residuals;
  RitzBasis basis;
  std::vector<std::string> labels(loadLabels);
  for (int p = 0; p < parts; ++p)
    for (int k = 0; k < allCounts[p]; ++k) labels.push_back("part " + std::to_string(p) + " mode " + std::to_string(k + 1));
  for (int k = 0; k < interface.m; ++k) labels.push_back("interface mode " + std::to_string(k + 1));
  for (int k = 0; k < residuals; ++k) labels.push_back("residual of interface mode " + std::to_string(k + 1));
  if (columns > 0) {
    MultiVector C(layout, columns);
    for (const auto& w : work) {
      const int n = static_cast<int>(w.rows.size()), nb = static_cast<int>(w.boundary.size());
      if (nf > 0) {  // u_p = K_pp^-1 f_p + X_p u_B
        std::vector<double> uBp(static_cast<std::size_t>(nb) * nf), u(w.Yf);
        for (int k = 0; k < nf; ++k)
          for (int b = 0; b < nb; ++b) uBp[b + static_cast<std::size_t>(k) * nb] = uB[w.boundary[b] + static_cast<std::size_t>(k) * nB];
        if (nb > 0)
          Teuchos::BLAS<int, double>().GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, nf, nb, 1.0, w.X.data(), n,
                                            uBp.data(), nb, 1.0, u.data(), n);
        for (int k = 0; k < nf; ++k)
          for (int i = 0; i < n; ++i)
            C.replaceLocalValue(layout->getLocalElement(w.rows[i]), k, u[i + static_cast<std::size_t>(k) * n]);
      }
      for (int k = 0; k < w.modes.m; ++k)
        for (int i = 0; i < n; ++i)
          C.replaceLocalValue(layout->getLocalElement(w.rows[i]), offset[w.part] + k,
                              w.modes.vectors[i + static_cast<std::size_t>(k) * n]);
      if (interface.m > 0 && nb > 0) {
        std::vector<double> PsiB(static_cast<std::size_t>(nb) * interface.m), Y(static_cast<std::size_t>(n) * interface.m);
        for (int k = 0; k < interface.m; ++k)
          for (int b = 0; b < nb; ++b) PsiB[b + static_cast<std::size_t>(k) * nb] = interface.vectors[w.boundary[b] + static_cast<std::size_t>(k) * nB];
        Teuchos::BLAS<int, double>().GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, interface.m, nb, 1.0, w.X.data(), n,
                                          PsiB.data(), nb, 0.0, Y.data(), n);
        for (int k = 0; k < interface.m; ++k)
          for (int i = 0; i < n; ++i)
            C.replaceLocalValue(layout->getLocalElement(w.rows[i]), offset[parts] + k, Y[i + static_cast<std::size_t>(k) * n]);
        if (residuals > 0) {
          // The interiors' static response, separator held, to the inertia
          // load of each interface mode's extension: -K_pp^-1 (M_pp Y +
          // M_pB Psi_B) up to sign, one load-dependent Ritz step (§18.2).
          const auto map = w.Mpp->getRowMap();
          MultiVector Ym(map, interface.m), F(map, interface.m), Z(map, interface.m);
          for (int k = 0; k < interface.m; ++k)
            for (int i = 0; i < n; ++i) Ym.replaceLocalValue(i, k, Y[i + static_cast<std::size_t>(k) * n]);
          w.Mpp->apply(Ym, F);
          std::vector<int> at(nB, -1);
          for (int b = 0; b < nb; ++b) at[w.boundary[b]] = b;
          for (const auto& [i, b, v] : w.MpB)
            for (int k = 0; k < interface.m; ++k) F.sumIntoLocalValue(i, k, v * PsiB[at[b] + static_cast<std::size_t>(k) * nb]);
          w.factor->solve(F, Z);
          for (int k = 0; k < interface.m; ++k) {
            const auto z = Z.getData(k);
            for (int i = 0; i < n; ++i)
              C.replaceLocalValue(layout->getLocalElement(w.rows[i]), offset[parts] + interface.m + k, z[i]);
          }
        }
      }
    }
    if (rank == 0) {
      for (int k = 0; k < nf; ++k)
        for (int b = 0; b < nB; ++b)
          C.replaceLocalValue(layout->getLocalElement(separatorRows[b]), k, uB[b + static_cast<std::size_t>(k) * nB]);
      for (int k = 0; k < interface.m; ++k)
        for (int b = 0; b < nB; ++b)
          C.replaceLocalValue(layout->getLocalElement(separatorRows[b]), offset[parts] + k,
                              interface.vectors[b + static_cast<std::size_t>(k) * nB]);
    }
    MultiVector candidates(s.map(), columns);
    candidates.doImport(C, Tpetra::Import<>(layout, s.map()), Tpetra::INSERT);
    appendOrthonormal(*s.M(), candidates, labels, options.dependenceTolerance, INT_MAX, basis);
  }

  // The report: what was made, and where the time went.
  std::vector<long long> partSizes(parts, 0);
  for (long long r = 0; r < rows; ++r)
    if (rowClass[r] >= 0) ++partSizes[rowClass[r]];
  const long long smallest = *std::min_element(partSizes.begin(), partSizes.end());
  const long long largest = *std::max_element(partSizes.begin(), partSizes.end());
  // Which eigensolver found the part modes (LAPACK below 600 DOFs, else ARPACK).
  int usedArpack = 0, anyArpack = 0;
  for (const auto& w : work) usedArpack |= w.modes.method == "ARPACK";
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, usedArpack, Teuchos::outArg(anyArpack));
  double slowest = 0.0, local = 0.0;
  for (const auto& w : work) local = std::max(local, w.seconds);
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, local, Teuchos::outArg(slowest));
  std::ostringstream os;
  os << "partitioned by Scotch into " << parts << " parts of " << smallest << "-" << largest << " interior DOFs, "
     << nB << " separator DOFs; " << nf << " static shapes, " << offset[parts] - nf << " part modes ("
     << (anyArpack ? "ARPACK" : "LAPACK") << ") below " << options.cutoffHz << " Hz, "
     << interface.m << " interface modes below " << options.interfaceCutoffFactor * options.cutoffHz << " Hz" << (residuals > 0 ? " and their residual vectors" : "") << "; partition " << partitionSeconds << " s, parts " << partsSeconds
     << " s (slowest part " << slowest << " s), interface " << interfaceSeconds << " s";
  basis.eigensolverReport = os.str();
  basis.seconds = since(t0);
  return basis;
}

}  // namespace cms::reduction
