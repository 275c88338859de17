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
//      characteristic constraint modes); on every separator DOF, or (with
//      Interface: Polynomial) projected on low-degree polynomials over
//      each piece of the separator, made on rank 0
//      before step 3;
//   5. the columns [Phi_p; X Psi] laid out on the substructure's map and
//      M-orthonormalised in order like every Ritz basis.
#include "cms/reduction/PartitionedBasis.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <tuple>
#include <sstream>

#include <arpack/arpack.h>
#include <mpi.h>
#include <scotch.h>

#include <Teuchos_BLAS.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_MultiVector.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

#include "HeldStiffness.hpp"
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
  // One run of implicitly restarted Lanczos from a fixed start (the modes
  // must not depend on which rank, after which other parts, ARPACK's own
  // random sequence is drawn); `phase` varies the start, `ncv` the space.
  auto lanczos = [&](double phase, int ncv, std::vector<double>& d, std::vector<double>& z) {
    const int lworkl = ncv * (ncv + 8);
    std::vector<double> resid(n), v(static_cast<std::size_t>(n) * ncv), workd(3 * static_cast<std::size_t>(n)),
        workl(lworkl);
    for (int i = 0; i < n; ++i) resid[i] = 1.0 + 0.5 * std::sin(phase * i);
    a_int iparam[11] = {}, ipntr[14] = {};
    iparam[0] = 1;
    iparam[2] = 500;
    iparam[6] = 3;
    a_int ido = 0, info = 1;
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
    d.assign(nev, 0.0);
    z.assign(static_cast<std::size_t>(n) * nev, 0.0);
    a_int einfo = 0;
    dseupd_c(1, "A", select.data(), d.data(), z.data(), n, 0.0, "G", n, "LM", nev, tolerance, resid.data(), ncv,
             v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, &einfo);
    if (einfo != 0) throw NumericalError(what + ": ARPACK (dseupd) failed (info " + std::to_string(einfo) + ")");
    return static_cast<int>(std::count_if(d.begin(), d.end(), [&](double l) { return l < lambdaCut; }));
  };
  // The Sturm count says nev values lie below the cut; single-vector
  // Lanczos can converge one member of a repeated pair (a square section's
  // bending) and the next value above the cut in place of the other, so
  // the values are checked against the cut (a review found them unchecked):
  // once more from another start in twice the space, then an error.
  std::vector<double> d, z;
  const int ncv = std::min(n, std::max(2 * nev + 1, nev + 20));
  int below = lanczos(0.37, ncv, d, z);
  if (below < nev) below = lanczos(0.71, std::min(n, 2 * ncv), d, z);
  if (below < nev)
    throw NumericalError(what + ": ARPACK found " + std::to_string(below) + " of the " + std::to_string(nev) +
                         " modes below the cut-off (Sturm count) twice: a repeated frequency's second member "
                         "missed");
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

/// Orthonormalises the m columns of W (rows x m, column-major) in order, by
/// modified Gram-Schmidt twice; a column with no more than `drop` of its
/// norm left is dependent on those before it and removed. Returns how many
/// are kept: the first columns of W on return.
int orthonormalColumns(std::vector<double>& W, int rows, int m, double drop) {
  Teuchos::BLAS<int, double> blas;
  const auto column = [&](int j) { return &W[static_cast<std::size_t>(j) * rows]; };
  int kept = 0;
  for (int j = 0; j < m; ++j) {
    double* w = column(j);
    const double before = blas.NRM2(rows, w, 1);
    for (int pass = 0; pass < 2; ++pass)
      for (int i = 0; i < kept; ++i) blas.AXPY(rows, -blas.DOT(rows, column(i), 1, w, 1), column(i), 1, w, 1);
    const double after = blas.NRM2(rows, w, 1);
    if (!(after > drop * before)) continue;
    blas.SCAL(rows, 1.0 / after, w, 1);
    if (kept != j) std::copy_n(w, rows, column(kept));
    ++kept;
  }
  return kept;
}

/// What one part contributes (kept on the rank that owns it).
struct PartWork {
  int part = -1;
  std::vector<GlobalOrdinal> rows;   ///< interior rows, ascending
  std::vector<int> boundary;         ///< separator indices (0 .. nB-1) it touches, ascending
  std::vector<int> coords;           ///< its interface coordinates (0 .. nI-1), ascending: X's columns
  std::vector<double> X;             ///< n_p x coords, column-major: the static extension
  Modes modes;
  Teuchos::RCP<CrsMatrix> Mpp;       ///< the part's interior mass
  std::shared_ptr<SparseDirectSolver> factor;  ///< K_pp, kept for the residual vectors and the separator's static solve
  std::vector<std::tuple<int, int, double>> MpB;  ///< mass coupling to the separator (i, separator index)
  std::vector<std::tuple<int, int, double>> KpB;  ///< stiffness coupling, kept for the separator's static solve
  std::vector<double> Yf;            ///< n_p x n_f: K_pp^-1 f_p for the static load patterns
  double seconds = 0.0;
};

/// The separator's values of the static shapes, S u_B = g (nB x k), for an
/// interface whose Schur complement S is never formed: block conjugate
/// gradients preconditioned by balancing (Mandel's balancing domain
/// decomposition: the coarse problem on the interface polynomials Phi,
/// S_c = Phi^T S Phi, and the separator's own stiffness K_BB as the fine
/// solve; doc/theory.md §18.4). Collective: rank 0 runs the iteration and
/// holds g, Phi, S Phi, S_c's factor (the interface problem's) and K_BB;
/// every rank applies its parts' share of S = K_BB - sum_p K_Bp K_pp^-1
/// K_pB. Returns u_B on every rank; throws NumericalError on every rank
/// when a column does not reach `tolerance` (relative residual) within the
/// iteration limit.
struct SeparatorSolve {
  std::vector<double> u;  ///< nB x k
  int iterations = 0;
  double residual = 0.0;  ///< the largest final relative residual
};

SeparatorSolve separatorSolve(const Teuchos::Comm<int>& comm, const std::vector<PartWork>& work, int nB, int k,
                              const std::vector<double>& g, const std::vector<double>& Phi, int nI,
                              const std::vector<double>& SPhi, const SparseDirectSolver* coarseFactor,
                              const Teuchos::RCP<const Map>& coarseMap,
                              const SparseDirectSolver* KBBfactor, const CrsMatrix* KBB, double tolerance,
                              int maxIterations, const std::string& what) {
  const int rank = comm.getRank();
  const auto at = [nB](int b, int j) { return b + static_cast<std::size_t>(j) * nB; };
  // This rank's share of S V (V: nB x m, the same on every rank). A rank
  // whose solve fails adds NaN, which rank 0's iteration then meets, and
  // keeps its own message, which every rank then throws (below).
  std::string partFailure;
  auto share = [&](const std::vector<double>& V, int m) {
    std::vector<double> mine(V.size(), 0.0);
    try {
      for (const auto& w : work) {
        const auto map = w.Mpp->getRowMap();
        const int n = static_cast<int>(map->getNodeNumElements());
        std::vector<double> f(static_cast<std::size_t>(n) * m, 0.0), z(f.size());
        for (const auto& [i, b, v] : w.KpB)
          for (int j = 0; j < m; ++j) f[i + static_cast<std::size_t>(j) * n] -= v * V[at(b, j)];
        const MultiVector F(map, Teuchos::ArrayView<const double>(f), n, m);
        MultiVector Z(map, m);
        w.factor->solve(F, Z);
        Z.get1dCopy(Teuchos::ArrayView<double>(z), n);
        for (const auto& [i, b, v] : w.KpB)
          for (int j = 0; j < m; ++j) mine[at(b, j)] += v * z[i + static_cast<std::size_t>(j) * n];
      }
      if (rank == 0) {
        const MultiVector Vm(KBB->getRowMap(), Teuchos::ArrayView<const double>(V), nB, m);
        MultiVector KV(KBB->getRowMap(), m);
        KBB->apply(Vm, KV);
        for (int j = 0; j < m; ++j) {
          const auto d = KV.getData(j);
          for (int b = 0; b < nB; ++b) mine[at(b, j)] += d[b];
        }
      }
    } catch (const std::exception& e) {
      if (partFailure.empty())
        partFailure = what + ": a part's solve failed on rank " + std::to_string(rank) + ": " + e.what();
      std::fill(mine.begin(), mine.end(), std::numeric_limits<double>::quiet_NaN());
    }
    return mine;
  };
  // S V on every rank, V sent by rank 0 (m columns, m already sent).
  auto collective = [&](std::vector<double>& V, int m) {
    V.resize(static_cast<std::size_t>(nB) * m);
    Teuchos::broadcast(comm, 0, static_cast<int>(V.size()), V.data());
    const std::vector<double> mine = share(V, m);
    std::vector<double> all(mine.size(), 0.0);
    Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, static_cast<int>(mine.size()), mine.data(), all.data());
    return all;
  };
  SeparatorSolve out;
  out.u.assign(static_cast<std::size_t>(nB) * k, 0.0);
  std::string failure;
  if (rank != 0) {
    for (;;) {
      int m = 0;
      Teuchos::broadcast(comm, 0, &m);
      if (m == 0) break;
      std::vector<double> V;
      collective(V, m);
    }
  } else {
    try {
      Teuchos::BLAS<int, double> blas;
      Teuchos::LAPACK<int, double> lapack;
      auto applyS = [&](std::vector<double> V, int m) {
        Teuchos::broadcast(comm, 0, &m);
        return collective(V, m);
      };
      // y (nI x m) <- S_c^-1 y, by the interface problem's factor.
      auto coarse = [&](std::vector<double>& y, int m) {
        const MultiVector Y(coarseMap, Teuchos::ArrayView<const double>(y), nI, m);
        MultiVector Z(coarseMap, m);
        coarseFactor->solve(Y, Z);
        Z.get1dCopy(Teuchos::ArrayView<double>(y), nI);
      };
      // The balancing preconditioner on R (nB x m):
      //   c1 = S_c^-1 Phi^T R,  W = K_BB^-1 (R - S Phi c1),  c2 = S_c^-1 (S Phi)^T W,
      //   Z = W + Phi (c1 - c2).
      auto precondition = [&](const std::vector<double>& R, int m) {
        std::vector<double> c1(static_cast<std::size_t>(nI) * m), c2(c1.size()), T(R);
        blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, nI, m, nB, 1.0, Phi.data(), nB, R.data(), nB, 0.0, c1.data(), nI);
        coarse(c1, m);
        blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nB, m, nI, -1.0, SPhi.data(), nB, c1.data(), nI, 1.0, T.data(), nB);
        const MultiVector Tm(KBB->getRowMap(), Teuchos::ArrayView<const double>(T), nB, m);
        MultiVector Wm(KBB->getRowMap(), m);
        KBBfactor->solve(Tm, Wm);
        std::vector<double> W(T.size());
        Wm.get1dCopy(Teuchos::ArrayView<double>(W), nB);
        blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, nI, m, nB, 1.0, SPhi.data(), nB, W.data(), nB, 0.0, c2.data(), nI);
        coarse(c2, m);
        for (std::size_t e = 0; e < c1.size(); ++e) c1[e] -= c2[e];
        blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nB, m, nI, 1.0, Phi.data(), nB, c1.data(), nI, 1.0, W.data(), nB);
        return W;
      };
      auto dot = [&](const std::vector<double>& a, int ja, const std::vector<double>& b, int jb) {
        return blas.DOT(nB, &a[at(0, ja)], 1, &b[at(0, jb)], 1);
      };
      // The block of some of a block's columns.
      auto pick = [&](const std::vector<double>& A, const std::vector<int>& cols) {
        std::vector<double> out(static_cast<std::size_t>(nB) * cols.size());
        for (std::size_t c = 0; c < cols.size(); ++c) std::copy_n(&A[at(0, cols[c])], nB, &out[at(0, static_cast<int>(c))]);
        return out;
      };
      // Block conjugate gradients, breakdown-free (Ji & Li, 2017): the
      // columns share one Krylov space, each step's directions P
      // orthonormalised with dependent ones dropped. Converged columns stay
      // in the block: deflating them lost the space they had built (the test
      // bar's three loads at degree 0 took 111 steps so, 37 without, and 52
      // one column at a time; the benchmark hub's 25 take 24 and 30 steps at
      // h = 15 and 9 mm where one at a time took 50 and 60). The columns
      // are scaled to unit norm first (the loads' scales differ by orders),
      // so a residual's norm is its relative residual.
      std::vector<double> gs(g), gNorm(k, 0.0);
      for (int j = 0; j < k; ++j) {
        gNorm[j] = std::sqrt(dot(g, j, g, j));
        if (gNorm[j] > 0) blas.SCAL(nB, 1.0 / gNorm[j], &gs[at(0, j)], 1);
      }
      // The coarse start x = Phi S_c^-1 Phi^T g leaves Phi^T r = 0.
      std::vector<double> c(static_cast<std::size_t>(nI) * k);
      blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, nI, k, nB, 1.0, Phi.data(), nB, gs.data(), nB, 0.0, c.data(), nI);
      coarse(c, k);
      std::vector<double>& x = out.u;
      blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nB, k, nI, 1.0, Phi.data(), nB, c.data(), nI, 0.0, x.data(), nB);
      std::vector<double> r = applyS(x, k);
      for (std::size_t e = 0; e < r.size(); ++e) r[e] = gs[e] - r[e];
      std::vector<double> rNorm(k);
      std::vector<int> active;
      auto measure = [&] {
        active.clear();
        for (int j = 0; j < k; ++j) {
          rNorm[j] = gNorm[j] > 0 ? std::sqrt(dot(r, j, r, j)) : 0.0;
          if (!std::isfinite(rNorm[j]))
            throw NumericalError(what + ": the separator's static solve met a non-finite residual (a part's solve failed)");
          if (rNorm[j] > tolerance) active.push_back(j);
        }
      };
      // An orthonormal basis of W's columns (nB x m); a column with less
      // than 1e-10 of its norm left is dependent on the others and dropped.
      auto orth = [&](std::vector<double> W, int m, int& kept) {
        kept = orthonormalColumns(W, nB, m, 1e-10);
        W.resize(static_cast<std::size_t>(nB) * kept);
        return W;
      };
      measure();
      int s = 0;
      std::vector<double> P;
      std::vector<int> live;  // every column but a zero load's
      for (int j = 0; j < k; ++j)
        if (gNorm[j] > 0) live.push_back(j);
      const int m = static_cast<int>(live.size());
      if (!active.empty()) P = orth(precondition(pick(r, live), m), m, s);
      while (!active.empty()) {
        if (out.iterations == maxIterations || s == 0) {
          double worst = 0.0;
          for (int j : active) worst = std::max(worst, rNorm[j]);
          std::ostringstream os;
          os << what << ": the static shapes' separator values (block conjugate gradients on the Schur complement) "
             << (s == 0 ? "stagnated (no independent direction left)" : "did not converge") << " at " << worst
             << " relative residual after " << out.iterations << " iterations, not " << tolerance
             << " (Partition/Static Solve Tolerance, Static Solve Iterations): raise Partition/Interface Degree "
                "or the iterations, or use Interface: Exact";
          throw NumericalError(os.str());
        }
        ++out.iterations;
        const std::vector<double> Q = applyS(P, s);
        // G = P^T S P (s x s, positive definite: P's columns independent).
        std::vector<double> G(static_cast<std::size_t>(s) * s), alpha(static_cast<std::size_t>(s) * k);
        blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, s, s, nB, 1.0, P.data(), nB, Q.data(), nB, 0.0, G.data(), s);
        int info = 0;
        lapack.POTRF('L', s, G.data(), s, &info);
        if (info != 0)
          throw NumericalError(what + ": the block conjugate gradients' P^T S P is not positive definite (LAPACK "
                                      "dpotrf, info " + std::to_string(info) + ")");
        blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, s, k, nB, 1.0, P.data(), nB, r.data(), nB, 0.0, alpha.data(), s);
        lapack.POTRS('L', s, k, G.data(), s, alpha.data(), s, &info);
        blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nB, k, s, 1.0, P.data(), nB, alpha.data(), s, 1.0, x.data(), nB);
        blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nB, k, s, -1.0, Q.data(), nB, alpha.data(), s, 1.0, r.data(), nB);
        measure();
        if (active.empty()) break;
        std::vector<double> W = precondition(pick(r, live), m), beta(static_cast<std::size_t>(s) * m);
        // beta = -G^-1 Q^T Z; P <- orth(Z + P beta).
        blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, s, m, nB, -1.0, Q.data(), nB, W.data(), nB, 0.0, beta.data(), s);
        lapack.POTRS('L', s, m, G.data(), s, beta.data(), s, &info);
        blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nB, m, s, 1.0, P.data(), nB, beta.data(), s, 1.0, W.data(), nB);
        P = orth(std::move(W), m, s);
      }
      for (int j = 0; j < k; ++j) {
        out.residual = std::max(out.residual, rNorm[j]);
        blas.SCAL(nB, gNorm[j], &x[at(0, j)], 1);
      }
    } catch (const std::exception& e) {
      failure = e.what();
    }
    int stop = 0;
    Teuchos::broadcast(comm, 0, &stop);
  }
  agreeOnFailure(comm, partFailure);  // the cause, before rank 0's "non-finite residual"
  agreeOnFailure(comm, failure);
  Teuchos::broadcast(comm, 0, static_cast<int>(out.u.size()), out.u.data());
  Teuchos::broadcast(comm, 0, &out.iterations);
  Teuchos::broadcast(comm, 0, &out.residual);
  return out;
}

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
  CMS_INPUT_CHECK(!(options.staticTolerance > 0.0 && options.staticTolerance < 1.0),
                  where << "/Partition/Static Solve Tolerance = " << options.staticTolerance << " must be in (0, 1)");
  CMS_INPUT_CHECK(options.staticIterations < 1,
                  where << "/Partition/Static Solve Iterations = " << options.staticIterations << " must be >= 1");
  CMS_INPUT_CHECK(options.exactInterfaceLimit < 0, where << "/Partition/Exact Interface Limit = "
                                                          << options.exactInterfaceLimit << " must be >= 0");
  CMS_INPUT_CHECK(options.interface != PartitionOptions::Interface::Exact && options.interfaceDegree < 0,
                  where << "/Partition/Interface Degree = " << options.interfaceDegree
                        << " must be >= 0 (the polynomials' highest degree)");
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
          // Entries stored as zero are no coupling: a matrix read from a file
          // may store some, and the assembly once stored spurious ones that
          // depended on the rank count (theory §18.1), and so did the partition.
          if (b != a && vals(e) != 0.0) {  // both arcs: Scotch needs a symmetric graph, whatever K's stored pattern
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
  const auto self = comm->split(rank, 0);

  // 2b. The interface's coordinates (§18.4). Exact: every separator DOF, so
  // the interface problem is the whole Schur complement. Polynomial: per
  // connected piece of the separator (a cut, or the face a child is
  // attached to) and per component (UX .. RZ), the monomials of degree
  // <= d in the piece's centred, scaled coordinates: the piece's rigid
  // motions (d >= 1, so a child's rigid attachment coordinates too),
  // stretching, bending and warping of its surface. The interface problem
  // is projected on their span (Rayleigh-Ritz, so from above). Phi (nB x
  // nI, column-major) maps interface coordinates to separator values;
  // built on rank 0, which holds the separator's rows, sent to every rank.
  // Auto: the exact interface costs n_B^2 memory and n_p n_B^2 flops per
  // part; the benchmark hub's 2,535 separator DOFs took 15 s and 1.8 GB so,
  // 2.3 s and 0.5 GB with polynomials of degree 2, at the same frequencies
  // to 2.4e-9 (doc/benchmarks.md).
  const bool reduced = nB > 0 && (options.interface == PartitionOptions::Interface::Polynomial ||
                                  (options.interface == PartitionOptions::Interface::Auto &&
                                   nB > options.exactInterfaceLimit));
  int nI = nB;
  std::vector<double> Phi;
  std::string shapesNote;
  const auto tShapes = Clock::now();
  if (reduced) {
    int pieces = 0;
    if (rank == 0) {
      // The separator's pieces: its nodes joined by K's nonzero entries (union-find).
      std::vector<std::int64_t> root(nodes);
      std::iota(root.begin(), root.end(), 0);
      const auto find = [&](std::int64_t a) {
        while (root[a] != a) a = root[a] = root[root[a]];
        return a;
      };
      {
        CrsMatrix::local_inds_host_view_type cols;
        CrsMatrix::values_host_view_type vals;
        const auto colMap = K->getColMap();
        for (int b = 0; b < nB; ++b) {
          K->getLocalRowView(layout->getLocalElement(separatorRows[b]), cols, vals);
          for (std::size_t e = 0; e < cols.extent(0); ++e) {
            const GlobalOrdinal g = colMap->getGlobalElement(cols(e));
            if (rowClass[g] == -1 && vals(e) != 0.0)  // a stored zero joins nothing (as in the partition)
              root[find(rowNode[separatorRows[b]])] = find(rowNode[g]);
          }
        }
      }
      // Groups: (piece, component) -> its separator indices.
      std::map<std::pair<std::int64_t, int>, std::vector<int>> groups;
      for (int b = 0; b < nB; ++b)
        groups[{find(rowNode[separatorRows[b]]), static_cast<int>(dofs.components[separatorRows[b]])}].push_back(b);
      std::vector<std::array<int, 3>> powers;  // every monomial of degree <= d
      for (int total = 0; total <= options.interfaceDegree; ++total)
        for (int a = total; a >= 0; --a)
          for (int b = total - a; b >= 0; --b) powers.push_back({a, b, total - a - b});
      std::vector<std::vector<double>> columns;  // each nB long
      for (const auto& [key, members] : groups) {
        // Centred on the piece's nodes in this group, scaled to unit radius:
        // monomials stay O(1), so their dependence is judged by rounding.
        double centre[3] = {0, 0, 0}, radius = 0;
        auto at = [&](int b, int i) { return dofs.coordinates[3 * rowNode[separatorRows[b]] + i]; };
        for (int b : members)
          for (int i = 0; i < 3; ++i) centre[i] += at(b, i) / members.size();
        for (int b : members) {
          double r2 = 0;
          for (int i = 0; i < 3; ++i) r2 += std::pow(at(b, i) - centre[i], 2);
          radius = std::max(radius, std::sqrt(r2));
        }
        if (!(radius > 0)) radius = 1;
        // The group's monomials on its rows, orthonormalised (other groups'
        // have disjoint supports), dependent ones dropped; then on the
        // separator's rows.
        const int rowsOf = static_cast<int>(members.size()), count = static_cast<int>(powers.size());
        std::vector<double> block(static_cast<std::size_t>(rowsOf) * count);
        for (int k = 0; k < count; ++k)
          for (int r = 0; r < rowsOf; ++r) {
            double x = 1;
            for (int i = 0; i < 3; ++i) x *= std::pow((at(members[r], i) - centre[i]) / radius, powers[k][i]);
            block[r + static_cast<std::size_t>(k) * rowsOf] = x;
          }
        const int kept = orthonormalColumns(block, rowsOf, count, options.dependenceTolerance);
        for (int k = 0; k < kept; ++k) {
          std::vector<double> v(nB, 0.0);
          for (int r = 0; r < rowsOf; ++r) v[members[r]] = block[r + static_cast<std::size_t>(k) * rowsOf];
          columns.push_back(std::move(v));
        }
      }
      nI = static_cast<int>(columns.size());
      Phi.resize(static_cast<std::size_t>(nB) * nI);
      for (int k = 0; k < nI; ++k) std::copy(columns[k].begin(), columns[k].end(), Phi.begin() + static_cast<std::size_t>(k) * nB);
      std::set<std::int64_t> distinct;
      for (const auto& [key, members] : groups) distinct.insert(key.first);
      pieces = static_cast<int>(distinct.size());
    }
    Teuchos::broadcast(*comm, 0, &nI);
    Teuchos::broadcast(*comm, 0, &pieces);
    std::ostringstream os;
    os << "interface reduced to " << nI << " coordinates (polynomials of degree <= " << options.interfaceDegree << " on "
       << pieces << " separator piece" << (pieces == 1 ? "" : "s") << ")";
    shapesNote = os.str();
    Phi.resize(static_cast<std::size_t>(nB) * nI);
    if (!Phi.empty()) Teuchos::broadcast(*comm, 0, static_cast<int>(Phi.size()), Phi.data());
  }
  const double shapesSeconds = since(tShapes);
  std::vector<double> cB(static_cast<std::size_t>(nB) * nf, 0.0);  // sum_p K_Bp K_pp^-1 f_p, this rank's parts
  // Polynomial: S Phi = K_BB Phi + sum_p K_Bp X_p (this rank's share), the
  // separator's static solve's coarse space (§18.4).
  std::vector<double> SPhi(reduced ? static_cast<std::size_t>(nB) * nI : 0, 0.0);
  Teuchos::RCP<CrsMatrix> KBB;  // Polynomial, rank 0: the separator's own stiffness

  // 3. The parts, each on its rank alone.
  const auto tParts = Clock::now();
  std::vector<PartWork> work;
  std::vector<std::pair<long long, double>> Sk, Sm;  // this rank's contributions to S and M^ (i * nI + j)
  Teuchos::BLAS<int, double> blas;
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
            } else if (c >= 0 && vals(e) != 0.0) {  // a stored zero couples nothing (the partition skips it too)
              throw NumericalError(what + ": couples to part " + std::to_string(c) +
                                   " across the separator (a stiffness entry zero where the mass's is not, "
                                   "or an internal error of the partition)");
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
                             factor.failure() + "): K_pp is a principal block of the substructure's held "
                             "stiffness, so that is not positive definite either (fewer parts would not help): " +
                             detail::notPositiveDefiniteReasons());
      for (const auto& [i, b, v] : KpB) w.boundary.push_back(b);
      for (const auto& [i, b, v] : MpB) w.boundary.push_back(b);
      std::sort(w.boundary.begin(), w.boundary.end());
      w.boundary.erase(std::unique(w.boundary.begin(), w.boundary.end()), w.boundary.end());
      const int nb = static_cast<int>(w.boundary.size());
      auto local = [&](int b) {
        return static_cast<int>(std::lower_bound(w.boundary.begin(), w.boundary.end(), b) - w.boundary.begin());
      };
      // The part's interface coordinates: exact, the separator DOFs it
      // touches; reduced, all nI, through Phi_p (its touched rows of Phi,
      // row-major nb x nI).
      if (nb > 0) {
        if (reduced) w.coords.resize(nI), std::iota(w.coords.begin(), w.coords.end(), 0);
        else w.coords = w.boundary;
      }
      const int c = static_cast<int>(w.coords.size());
      std::vector<double> PhiRows;
      if (reduced && nb > 0) {
        PhiRows.resize(static_cast<std::size_t>(nb) * nI);
        for (int bl = 0; bl < nb; ++bl)
          for (int k = 0; k < nI; ++k) PhiRows[k + static_cast<std::size_t>(bl) * nI] = Phi[w.boundary[bl] + static_cast<std::size_t>(k) * nB];
      }
      // sign A_pB Phi_p added to `out` (dense n x c, column-major) from the
      // coupling triplets; exact: Phi_p = I, one entry per triplet.
      auto addCoupled = [&](const std::vector<std::tuple<int, int, double>>& t, double sign, std::vector<double>& out) {
        if (!reduced) {
          for (const auto& [i, b, v] : t) out[i + static_cast<std::size_t>(local(b)) * n] += sign * v;
          return;
        }
        std::vector<double> rowMajor(static_cast<std::size_t>(n) * c, 0.0);
        for (const auto& [i, b, v] : t) {
          double* to = &rowMajor[static_cast<std::size_t>(i) * c];
          const double* from = &PhiRows[static_cast<std::size_t>(local(b)) * nI];
          for (int k = 0; k < c; ++k) to[k] += sign * v * from[k];
        }
        for (int i = 0; i < n; ++i)
          for (int k = 0; k < c; ++k) out[i + static_cast<std::size_t>(k) * n] += rowMajor[k + static_cast<std::size_t>(i) * c];
      };
      if (c > 0) {
        // The static extension X_p = -K_pp^-1 K_pB Phi_p; its contributions
        // S_p = Phi_p^T K_Bp X_p (= -Phi_p^T K_Bp K_pp^-1 K_pB Phi_p) and
        // M^_p = X^T (M_pp X + M_pB Phi_p) + Phi_p^T M_Bp X (exact: Phi_p = I).
        MultiVector X(Kt->getRowMap(), c), MX(Kt->getRowMap(), c);
        {
          std::vector<double> Fd(static_cast<std::size_t>(n) * c, 0.0);
          addCoupled(KpB, -1.0, Fd);
          const MultiVector Fm(Kt->getRowMap(), Teuchos::ArrayView<const double>(Fd), n, c);
          factor.solve(Fm, X);
        }
        Mt->apply(X, MX);
        w.X.resize(static_cast<std::size_t>(n) * c);
        std::vector<double> MXd(w.X.size());
        X.get1dCopy(Teuchos::ArrayView<double>(w.X), n);
        MX.get1dCopy(Teuchos::ArrayView<double>(MXd), n);
        std::vector<double> Gd;  // reduced: G = M_pB Phi_p
        if (reduced) {
          Gd.assign(w.X.size(), 0.0);
          addCoupled(MpB, 1.0, Gd);
          for (std::size_t e = 0; e < MXd.size(); ++e) MXd[e] += Gd[e];
        } else {
          addCoupled(MpB, 1.0, MXd);
        }
        std::vector<double> S(reduced ? 0 : static_cast<std::size_t>(c) * c, 0.0), Mh(static_cast<std::size_t>(c) * c, 0.0);
        blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, c, c, n, 1.0, w.X.data(), n, MXd.data(), n, 0.0, Mh.data(), c);
        if (!reduced) {  // Phi_p = I: the sparse coupling times X (c = nb may be thousands)
          for (const auto& [i, b, v] : KpB) {
            const int bl = local(b);
            for (int j = 0; j < nb; ++j) S[bl + static_cast<std::size_t>(j) * nb] += v * w.X[i + static_cast<std::size_t>(j) * n];
          }
          for (const auto& [i, b, v] : MpB) {
            const int bl = local(b);
            for (int j = 0; j < nb; ++j) Mh[bl + static_cast<std::size_t>(j) * nb] += v * w.X[i + static_cast<std::size_t>(j) * n];
          }
        } else {
          // Phi_p^T M_Bp X = G^T X. S's share goes into S Phi = K_BB Phi +
          // sum_p K_Bp X_p (rows of this part's separator DOFs), from which
          // rank 0 takes S_c = Phi^T (S Phi) once every share is in.
          blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, c, c, n, 1.0, Gd.data(), n, w.X.data(), n, 1.0, Mh.data(), c);
          for (const auto& [i, b, v] : KpB)
            for (int k = 0; k < nI; ++k) SPhi[b + static_cast<std::size_t>(k) * nB] += v * w.X[i + static_cast<std::size_t>(k) * n];
          w.KpB = KpB;
        }
        for (int j = 0; j < c; ++j)
          for (int i = 0; i < c; ++i) {
            const long long key = static_cast<long long>(w.coords[i]) * nI + w.coords[j];
            if (!reduced) Sk.emplace_back(key, S[i + static_cast<std::size_t>(j) * c]);
            Sm.emplace_back(key, Mh[i + static_cast<std::size_t>(j) * c]);
          }
      }
      w.modes = modesBelow(*Kt, *Mt, Kc, Mc, lambdaCut, factor, options.eigensolverTolerance, what);
      if (nf > 0) {  // the loads' particular part, separator held, and its reaction K_Bp K_pp^-1 f_p
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
    if (rank == 0) {  // the separator's own block: K_BB, M_BB; reduced, K_BB Phi into S Phi and Phi^T M_BB Phi
      auto addSeparatorBlock = [&](const CrsMatrix& A, std::vector<std::pair<long long, double>>& into) {
        CrsMatrix::local_inds_host_view_type cols;
        CrsMatrix::values_host_view_type vals;
        const auto colMap = A.getColMap();
        Csr block;  // A_BB (Polynomial)
        block.n = nB;
        std::vector<std::pair<int, double>> row;
        for (int i = 0; i < nB; ++i) {
          A.getLocalRowView(layout->getLocalElement(separatorRows[i]), cols, vals);
          row.clear();
          for (std::size_t e = 0; e < cols.extent(0); ++e) {
            const GlobalOrdinal g = colMap->getGlobalElement(cols(e));
            if (rowClass[g] != -1) continue;
            if (!reduced) into.emplace_back(static_cast<long long>(i) * nB + separatorIndex[g], vals(e));
            else row.emplace_back(separatorIndex[g], vals(e));
          }
          std::sort(row.begin(), row.end());
          for (const auto& [j, v] : row) block.col.push_back(j), block.val.push_back(v);
          block.endRow();
        }
        if (!reduced) return Teuchos::RCP<CrsMatrix>();
        const bool stiffness = &into == &Sk;
        std::vector<double> AP(static_cast<std::size_t>(nB) * nI, 0.0);  // A_BB Phi, column-major
        for (int i = 0; i < nB; ++i)
          for (int e = block.ptr[i]; e < block.ptr[i + 1]; ++e)
            for (int k = 0; k < nI; ++k)
              AP[i + static_cast<std::size_t>(k) * nB] += block.val[e] * Phi[block.col[e] + static_cast<std::size_t>(k) * nB];
        if (stiffness) {  // into S Phi; K_BB itself kept for the static solve's fine solves
          for (std::size_t e = 0; e < AP.size(); ++e) SPhi[e] += AP[e];
          return toTpetra(block, self);
        }
        std::vector<double> P(static_cast<std::size_t>(nI) * nI);
        blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, nI, nI, nB, 1.0, Phi.data(), nB, AP.data(), nB, 0.0, P.data(), nI);
        for (int j = 0; j < nI; ++j)
          for (int i = 0; i < nI; ++i) into.emplace_back(static_cast<long long>(i) * nI + j, P[i + static_cast<std::size_t>(j) * nI]);
        return Teuchos::RCP<CrsMatrix>();
      };
      KBB = addSeparatorBlock(*K, Sk);
      addSeparatorBlock(*M, Sm);
    }
  } catch (const std::exception& e) {
    failure = e.what();
  }
  agreeOnFailure(*comm, failure);
  if (reduced) {
    std::vector<double> all(SPhi.size(), 0.0);
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(SPhi.size()), SPhi.data(), all.data());
    SPhi.swap(all);
  }
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
  // The static shapes on the separator: u_B = S^-1 g, g = f_B - sum_p K_Bp K_pp^-1 f_p
  // (exact: by the Schur complement's factor; Polynomial: by block
  // conjugate gradients, below). g on rank 0.
  std::vector<double> g(cB.size(), 0.0);
  if (!cB.empty())
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(cB.size()), cB.data(), g.data());
  if (rank == 0)
    for (int k = 0; k < nf; ++k) {
      const auto from = F.getData(k);
      for (int b = 0; b < nB; ++b) {
        double& e = g[b + static_cast<std::size_t>(k) * nB];
        e = from[layout->getLocalElement(separatorRows[b])] - e;
      }
    }
  std::vector<double> uB(g.size(), 0.0);
  // Rank 0: the interface problem's stiffness factored, kept (reduced) for
  // the static solve's coarse solves with S_c.
  std::unique_ptr<SparseDirectSolver> interfaceFactor;
  Teuchos::RCP<const Map> interfaceMap;
  Modes interface;
  if (rank == 0 && nI > 0 && failure.empty()) {
    try {
      Csr S;
      if (!reduced) {
        S = fromTriplets(nI, Sk);
      } else {  // S_c = Phi^T (S Phi), symmetrised against rounding
        std::vector<double> P(static_cast<std::size_t>(nI) * nI);
        blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, nI, nI, nB, 1.0, Phi.data(), nB, SPhi.data(), nB, 0.0, P.data(), nI);
        S.n = nI;
        for (int i = 0; i < nI; ++i) {
          for (int j = 0; j < nI; ++j) {
            S.col.push_back(j);
            S.val.push_back(0.5 * (P[i + static_cast<std::size_t>(j) * nI] + P[j + static_cast<std::size_t>(i) * nI]));
          }
          S.endRow();
        }
      }
      const Csr Mh = fromTriplets(nI, Sm);
      std::vector<std::pair<long long, double>>().swap(Sk);
      std::vector<std::pair<long long, double>>().swap(Sm);
      const auto St = toTpetra(S, self), Mt = toTpetra(Mh, self);
      interfaceFactor = std::make_unique<SparseDirectSolver>(St, "CHOLMOD");
      interfaceMap = St->getRowMap();
      SparseDirectSolver& factor = *interfaceFactor;
      if (factor.factor() != SparseDirectSolver::Outcome::Factored)
        // With every part's K_pp positive definite, K (its held DOFs held) is
        // exactly when S is (Haynsworth's inertia additivity), and S_c =
        // Phi^T S Phi is when S is: so K is not, for the reasons any basis
        // gives (a free substructure: S holds its rigid motions).
        throw NumericalError(s.name() + ": the interface's Schur complement (" + std::to_string(nI) +
                             (reduced ? " interface coordinates" : " separator DOFs") + ") is not positive definite (" +
                             factor.failure() + "), so neither is the stiffness with the attachment (or reference) "
                             "DOFs held: " + detail::notPositiveDefiniteReasons());
      interface = modesBelow(*St, *Mt, S, Mh, lambdaCut * std::pow(options.interfaceCutoffFactor, 2), factor,
                             options.eigensolverTolerance,
                             s.name() + ": interface (" + std::to_string(nI) + (reduced ? " coordinates)" : " separator DOFs)"));
      if (nf > 0 && !reduced) {
        const MultiVector gm(St->getRowMap(), Teuchos::ArrayView<const double>(g), nB, nf);
        MultiVector u(St->getRowMap(), nf);
        factor.solve(gm, u);
        u.get1dCopy(Teuchos::ArrayView<double>(uB), nB);
      }
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  agreeOnFailure(*comm, failure);
  Teuchos::broadcast(*comm, 0, &interface.m);
  interface.vectors.resize(static_cast<std::size_t>(nI) * interface.m);
  if (!interface.vectors.empty())
    Teuchos::broadcast(*comm, 0, static_cast<int>(interface.vectors.size()), interface.vectors.data());
  std::string staticNote;
  if (nf > 0 && reduced) {
    std::unique_ptr<SparseDirectSolver> KBBfactor;
    if (rank == 0 && failure.empty()) {
      KBBfactor = std::make_unique<SparseDirectSolver>(KBB, "CHOLMOD");
      if (KBBfactor->factor() != SparseDirectSolver::Outcome::Factored)
        failure = s.name() + ": the separator's own stiffness K_BB is not positive definite (" + KBBfactor->failure() +
                  "), so neither is the stiffness with the attachment (or reference) DOFs held, of which it is a "
                  "principal block: " + detail::notPositiveDefiniteReasons();
    }
    agreeOnFailure(*comm, failure);
    const SeparatorSolve solved =
        separatorSolve(*comm, work, nB, nf, g, Phi, nI, SPhi, interfaceFactor.get(), interfaceMap, KBBfactor.get(), KBB.get(),
                       options.staticTolerance, options.staticIterations, s.name() + ": static shapes");
    uB = solved.u;
    std::ostringstream os;
    os << "static shapes' separator values by block conjugate gradients in " << solved.iterations
       << " iterations (relative residual " << solved.residual << ")";
    staticNote = os.str();
  } else if (nf > 0) {
    Teuchos::broadcast(*comm, 0, static_cast<int>(uB.size()), uB.data());
  }
  // The interface modes on the separator's DOFs: Phi times their coordinates.
  std::vector<double> PsiSep = interface.vectors;
  if (reduced && interface.m > 0) {
    PsiSep.assign(static_cast<std::size_t>(nB) * interface.m, 0.0);
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nB, interface.m, nI, 1.0, Phi.data(), nB, interface.vectors.data(),
              nI, 0.0, PsiSep.data(), nB);
  }
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
      const int n = static_cast<int>(w.rows.size()), c = static_cast<int>(w.coords.size());
      // Interface coordinates (nI x k) restricted to the part's (c x k).
      auto partCoords = [&](const std::vector<double>& all, int k) {
        std::vector<double> out(static_cast<std::size_t>(c) * k);
        for (int j = 0; j < k; ++j)
          for (int l = 0; l < c; ++l) out[l + static_cast<std::size_t>(j) * c] = all[w.coords[l] + static_cast<std::size_t>(j) * nI];
        return out;
      };
      if (nf > 0) {  // u_p = K_pp^-1 (f_p - K_pB u_B): exact, X_p u_B; Polynomial, one more solve (u_B is not in Phi's span)
        std::vector<double> u(w.Yf);
        if (c > 0 && !reduced) {
          const std::vector<double> uc = partCoords(uB, nf);
          blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, nf, c, 1.0, w.X.data(), n, uc.data(), c, 1.0, u.data(), n);
        } else if (c > 0) {
          const auto map = w.Mpp->getRowMap();
          std::vector<double> fb(static_cast<std::size_t>(n) * nf, 0.0), zb(fb.size());
          for (const auto& [i, b, v] : w.KpB)
            for (int k = 0; k < nf; ++k) fb[i + static_cast<std::size_t>(k) * n] -= v * uB[b + static_cast<std::size_t>(k) * nB];
          const MultiVector Fb(map, Teuchos::ArrayView<const double>(fb), n, nf);
          MultiVector Zb(map, nf);
          w.factor->solve(Fb, Zb);
          Zb.get1dCopy(Teuchos::ArrayView<double>(zb), n);
          for (std::size_t e = 0; e < u.size(); ++e) u[e] += zb[e];
        }
        for (int k = 0; k < nf; ++k)
          for (int i = 0; i < n; ++i)
            C.replaceLocalValue(layout->getLocalElement(w.rows[i]), k, u[i + static_cast<std::size_t>(k) * n]);
      }
      for (int k = 0; k < w.modes.m; ++k)
        for (int i = 0; i < n; ++i)
          C.replaceLocalValue(layout->getLocalElement(w.rows[i]), offset[w.part] + k,
                              w.modes.vectors[i + static_cast<std::size_t>(k) * n]);
      if (interface.m > 0 && c > 0) {
        const std::vector<double> Psic = partCoords(interface.vectors, interface.m);
        std::vector<double> Y(static_cast<std::size_t>(n) * interface.m);
        blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, interface.m, c, 1.0, w.X.data(), n, Psic.data(), c, 0.0,
                  Y.data(), n);
        for (int k = 0; k < interface.m; ++k)
          for (int i = 0; i < n; ++i)
            C.replaceLocalValue(layout->getLocalElement(w.rows[i]), offset[parts] + k, Y[i + static_cast<std::size_t>(k) * n]);
        if (residuals > 0) {
          // The interiors' static response, separator held, to the inertia
          // load of each interface mode's extension: -K_pp^-1 (M_pp Y +
          // M_pB Psi_B) up to sign, one load-dependent Ritz step (§18.2).
          const auto map = w.Mpp->getRowMap();
          MultiVector Ym(map, interface.m), Fr(map, interface.m), Z(map, interface.m);
          for (int k = 0; k < interface.m; ++k)
            for (int i = 0; i < n; ++i) Ym.replaceLocalValue(i, k, Y[i + static_cast<std::size_t>(k) * n]);
          w.Mpp->apply(Ym, Fr);
          for (const auto& [i, b, v] : w.MpB)
            for (int k = 0; k < interface.m; ++k) Fr.sumIntoLocalValue(i, k, v * PsiSep[b + static_cast<std::size_t>(k) * nB]);
          w.factor->solve(Fr, Z);
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
                              PsiSep[b + static_cast<std::size_t>(k) * nB]);
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
  // Which eigensolvers found the part modes (LAPACK below 600 DOFs, else
  // ARPACK; none where no part has a mode below the cut-off: the Sturm
  // count said so, and "LAPACK" was printed for a solve never made).
  int used[2] = {0, 0}, any[2] = {0, 0};
  for (const auto& w : work) used[0] |= w.modes.method == "LAPACK", used[1] |= w.modes.method == "ARPACK";
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, 2, used, any);
  const std::string solvers = any[0] && any[1] ? "LAPACK and ARPACK"
                              : any[1]         ? "ARPACK"
                              : any[0]         ? "LAPACK"
                                               : "none below the cut-off by the Sturm count, no eigensolve";
  double slowest = 0.0, local = 0.0;
  for (const auto& w : work) local = std::max(local, w.seconds);
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, local, Teuchos::outArg(slowest));
  std::ostringstream os;
  os << "partitioned by Scotch into " << parts << " parts of " << smallest << "-" << largest << " interior DOFs, "
     << nB << " separator DOFs; " << nf << " static shapes, " << offset[parts] - nf << " part modes ("
     << solvers << ") below " << options.cutoffHz << " Hz, "
     << interface.m << " interface modes below " << options.interfaceCutoffFactor * options.cutoffHz << " Hz" << (residuals > 0 ? " and their residual vectors" : "") << "; partition " << partitionSeconds << " s, parts " << partsSeconds
     << " s (slowest part " << slowest << " s), interface " << interfaceSeconds << " s";
  if (reduced) os << "; " << shapesNote << " in " << shapesSeconds << " s" << (staticNote.empty() ? "" : "; ") << staticNote;
  // Which interface, and why when Auto chose.
  if (options.interface == PartitionOptions::Interface::Auto && nB > 0)
    os << "; " << (reduced ? "polynomial" : "exact") << " interface: " << nB << " separator DOFs "
       << (reduced ? ">" : "<=") << " Partition/Exact Interface Limit " << options.exactInterfaceLimit;
  basis.eigensolverReport = os.str();
  basis.seconds = since(t0);
  return basis;
}

}  // namespace cms::reduction
