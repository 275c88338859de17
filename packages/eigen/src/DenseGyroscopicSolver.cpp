#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/EnergyBound.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>

#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>

#include "cms/core/Error.hpp"
#include "cms/eigen/SkewTridiagonal.hpp"
#include "cms/eigen/SturmCount.hpp"

namespace cms::eigen {

using cplx = std::complex<double>;

namespace {

const double kTwoPi = 2.0 * M_PI;

/// X <- L^-1 X (left) or X <- X L^-T (right), L lower triangular.
void lowerSolveLeft(const DenseMatrix& L, DenseMatrix& X) {
  Teuchos::BLAS<int, double>().TRSM(Teuchos::LEFT_SIDE, Teuchos::LOWER_TRI, Teuchos::NO_TRANS,
                                    Teuchos::NON_UNIT_DIAG, X.numRows(), X.numCols(), 1.0,
                                    L.values(), L.stride(), X.values(), X.stride());
}
void lowerTransSolveRight(const DenseMatrix& L, DenseMatrix& X) {
  Teuchos::BLAS<int, double>().TRSM(Teuchos::RIGHT_SIDE, Teuchos::LOWER_TRI, Teuchos::TRANS,
                                    Teuchos::NON_UNIT_DIAG, X.numRows(), X.numCols(), 1.0,
                                    L.values(), L.stride(), X.values(), X.stride());
}
/// x <- L^-T x for one column x (length n) stored contiguously.
void lowerTransSolveVector(const DenseMatrix& L, double* x) {
  Teuchos::BLAS<int, double>().TRSM(Teuchos::LEFT_SIDE, Teuchos::LOWER_TRI, Teuchos::TRANS,
                                    Teuchos::NON_UNIT_DIAG, L.numRows(), 1, 1.0, L.values(),
                                    L.stride(), x, L.numRows());
}

int requestedCount(const Teuchos::ParameterList& p, int n) {
  const int k = p.get<int>("Number of Modes");
  CMS_INPUT_CHECK(k == 0 || k < -1, "DenseGyroscopicSolver: \"Number of Modes\" = "
                                        << k << " must be positive, or -1 for all " << n);
  CMS_INPUT_CHECK(k > n, "DenseGyroscopicSolver: \"Number of Modes\" = "
                             << k << " but the system has only " << n
                             << " DOFs, hence " << n << " modes");
  return k == -1 ? n : k;
}

extern "C" void dgesvdx_(const char* jobu, const char* jobvt, const char* range, const int* m,
                         const int* n, double* a, const int* lda, const double* vl,
                         const double* vu, const int* il, const int* iu, int* ns, double* s,
                         double* u, const int* ldu, double* vt, const int* ldvt, double* work,
                         const int* lwork, int* iwork, int* info, std::size_t, std::size_t,
                         std::size_t);

/// Singular values of the square A, descending, with their right singular
/// vectors as rows of VT.
struct Triplets {
  std::vector<double> s;
  DenseMatrix VT;
  bool all = false;  ///< the whole spectrum, not only the smallest values
};

/// The `count` smallest singular triplets of the square A by LAPACK dgesvdx
/// (one bidiagonalisation, then only the wanted vectors).
Triplets singularTriplets(const DenseMatrix& A, int count) {
  const int N = A.numRows();
  DenseMatrix Ac(A);
  const int il = N - count + 1, iu = N, ldu = 1;
  const double vl = 0.0, vu = 0.0;
  int ns = 0, info = 0, lwork = -1;
  Triplets t;
  t.s.assign(N, 0.0);
  t.VT.shape(count, N);
  t.all = count == N;
  double u = 0.0, wq = 0.0;
  std::vector<int> iwork(12 * N);
  dgesvdx_("N", "V", "I", &N, &N, Ac.values(), &N, &vl, &vu, &il, &iu, &ns, t.s.data(), &u, &ldu,
           t.VT.values(), &count, &wq, &lwork, iwork.data(), &info, 1, 1, 1);
  lwork = static_cast<int>(wq);
  std::vector<double> work(std::max(1, lwork));
  dgesvdx_("N", "V", "I", &N, &N, Ac.values(), &N, &vl, &vu, &il, &iu, &ns, t.s.data(), &u, &ldu,
           t.VT.values(), &count, work.data(), &lwork, iwork.data(), &info, 1, 1, 1);
  TEUCHOS_TEST_FOR_EXCEPTION(info != 0 || ns != count, NumericalError,
                             "DenseGyroscopicSolver: LAPACK dgesvdx failed, info = "
                                 << info << ", " << ns << " of " << count << " values");
  t.s.resize(count);
  return t;
}

/// Every singular triplet of A by LAPACK dgesvd (QR iteration on the whole
/// bidiagonal): the fallback when a Sturm count shows the selected set missed values.
Triplets allSingularTriplets(const DenseMatrix& A) {
  const int N = A.numRows();
  DenseMatrix Ac(A);
  Triplets t;
  t.s.assign(N, 0.0);
  t.VT.shape(N, N);
  t.all = true;
  double u = 0.0, wq = 0.0;
  int info = 0;
  std::vector<double> rwork(5 * N);
  Teuchos::LAPACK<int, double> lapack;
  lapack.GESVD('N', 'A', N, N, Ac.values(), N, t.s.data(), &u, 1, t.VT.values(), N, &wq, -1,
               rwork.data(), &info);
  const int lwork = std::max(1, static_cast<int>(wq));
  std::vector<double> work(lwork);
  lapack.GESVD('N', 'A', N, N, Ac.values(), N, t.s.data(), &u, 1, t.VT.values(), N, work.data(),
               lwork, rwork.data(), &info);
  TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError,
                             "DenseGyroscopicSolver: LAPACK dgesvd failed, info = " << info);
  return t;
}

extern "C" {
void dgebrd_(const int* m, const int* n, double* a, const int* lda, double* d, double* e, double* tauq,
             double* taup, double* work, const int* lwork, int* info);
void dbdsqr_(const char* uplo, const int* n, const int* ncvt, const int* nru, const int* ncc, double* d,
             double* e, double* vt, const int* ldvt, double* u, const int* ldu, double* c, const int* ldc,
             double* work, int* info, std::size_t);
void dormbr_(const char* vect, const char* side, const char* trans, const int* m, const int* n, const int* k,
             const double* a, const int* lda, const double* tau, double* c, const int* ldc, double* work,
             const int* lwork, int* info, std::size_t, std::size_t, std::size_t);
}

/// A = Q B P^T (LAPACK dgebrd: B upper bidiagonal, the reflectors of Q and
/// P kept in `reflectors`) and every singular value of B, descending (dbdsqr
/// without vectors: the dqds algorithm, O(N^2), to high relative accuracy;
/// none if it did not converge).
struct Bidiagonal {
  DenseMatrix reflectors;
  std::vector<double> d, e, tauq, taup;
  std::vector<double> s;  ///< all N singular values, descending
};

Bidiagonal bidiagonalise(const DenseMatrix& A) {
  const int N = A.numRows();
  Bidiagonal b;
  b.reflectors = DenseMatrix(Teuchos::Copy, A);
  b.d.assign(N, 0.0), b.e.assign(std::max(1, N - 1), 0.0), b.tauq.assign(N, 0.0), b.taup.assign(N, 0.0);
  int info = 0, lwork = -1;
  double wq = 0.0;
  dgebrd_(&N, &N, b.reflectors.values(), &N, b.d.data(), b.e.data(), b.tauq.data(), b.taup.data(), &wq, &lwork,
          &info);
  lwork = std::max(1, static_cast<int>(wq));
  std::vector<double> work(lwork);
  dgebrd_(&N, &N, b.reflectors.values(), &N, b.d.data(), b.e.data(), b.tauq.data(), b.taup.data(), work.data(),
          &lwork, &info);
  TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError, "DenseGyroscopicSolver: LAPACK dgebrd failed, info = " << info);
  b.s = b.d;
  std::vector<double> e(b.e), w(4 * N);
  const int zero = 0, one = 1;
  double dummy = 0.0;
  dbdsqr_("U", &N, &zero, &zero, &zero, b.s.data(), e.data(), &dummy, &one, &dummy, &one, &dummy, &one, w.data(),
          &info, 1);
  if (info != 0) b.s.clear();  // dqds did not converge: the caller falls back to dgesvdx
  return b;
}

/// The `count` smallest singular triplets of A from its bidiagonal form:
/// the values from b.s, the right vectors by inverse iteration for just
/// those values on B's Golub-Kahan tridiagonal (LAPACK dstein; the
/// tridiagonal of zero diagonal and off-diagonal d1, e1, d2, e2, ... has
/// eigenvector (v1, u1, v2, u2, ...) / sqrt 2 for +sigma, B v = sigma u),
/// mapped to A's by P (dormbr). This is dgesvdx's own method less its
/// bisection, which, selecting values by index, took longer than the
/// bidiagonalisation (doc/theory.md §2). False when dstein does not converge.
bool tripletsFromBidiagonal(const Bidiagonal& b, int count, Triplets& t) {
  const int N = static_cast<int>(b.d.size()), T = 2 * N;
  std::vector<double> off(T - 1, 0.0);
  for (int i = 0; i < N; ++i) {
    off[2 * i] = b.d[i];
    if (i + 1 < N) off[2 * i + 1] = b.e[i];
  }
  // The wanted values ascending.
  std::vector<double> w(count), Z;
  for (int k = 0; k < count; ++k) w[k] = b.s[N - 1 - k];
  if (!zeroDiagonalTridiagonalVectors(off, w, Z)) return false;
  int info = 0;
  // v = sqrt 2 (z_1, z_3, ...), normalised; then P v.
  DenseMatrix V(N, count);
  for (int k = 0; k < count; ++k) {
    double nv = 0.0;
    for (int i = 0; i < N; ++i) nv += Z[static_cast<std::size_t>(k) * T + 2 * i] * Z[static_cast<std::size_t>(k) * T + 2 * i];
    nv = std::sqrt(nv);
    if (!(nv > 0.0)) return false;
    for (int i = 0; i < N; ++i) V(i, k) = Z[static_cast<std::size_t>(k) * T + 2 * i] / nv;
  }
  int lwork = -1;
  double wq = 0.0;
  dormbr_("P", "L", "N", &N, &count, &N, b.reflectors.values(), &N, b.taup.data(), V.values(), &N, &wq, &lwork,
          &info, 1, 1, 1);
  lwork = std::max(1, static_cast<int>(wq));
  std::vector<double> mwork(lwork);
  dormbr_("P", "L", "N", &N, &count, &N, b.reflectors.values(), &N, b.taup.data(), V.values(), &N, mwork.data(),
          &lwork, &info, 1, 1, 1);
  TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError, "DenseGyroscopicSolver: LAPACK dormbr failed, info = " << info);
  // As dgesvdx returns them: values descending, right vectors as rows.
  t.s.resize(count);
  t.VT.shape(count, N);
  t.all = count == N;
  for (int k = 0; k < count; ++k) {
    const int j = count - 1 - k;  // descending
    t.s[k] = w[j];
    for (int i = 0; i < N; ++i) t.VT(k, i) = V(i, j);
  }
  return true;
}

/// The smallest singular triplets of A, at least 2 nModes of them, widened
/// until the cluster holding the (2 nModes)-th smallest value is complete (a
/// larger returned value lies beyond the cluster tolerance from it). Every
/// value is known after the bidiagonalisation, so the widening costs no
/// recomputation; dgesvdx is the fallback if inverse iteration fails.
Triplets smallestTriplets(const DenseMatrix& A, int nModes, double clusterTol) {
  const int N = A.numRows();
  const Bidiagonal b = bidiagonalise(A);
  int want = std::min(N, 2 * nModes + 4);
  Triplets t;
  if (!b.s.empty()) {
    while (want < N && b.s[N - want] - b.s[N - 2 * nModes] <= clusterTol) want = std::min(N, 2 * want);
    if (tripletsFromBidiagonal(b, want, t)) return t;
    want = std::min(N, 2 * nModes + 4);
  }
  while (true) {
    t = singularTriplets(A, want);       // s descending, s.size() == want
    const int edge = want - 2 * nModes;  // index of the (2 nModes)-th smallest
    if (want == N || t.s[0] - t.s[edge] > clusterTol) return t;
    want = std::min(N, 2 * want);
  }
}

/// The smallest singular triplets of the skew A from its skew tridiagonal
/// form (doc/theory.md §2, "Skew tridiagonal form"): every frequency once,
/// from the n x n bidiagonal; at least nModes + 2 of them, widened until the
/// cluster holding the nModes-th is complete; each returned as the two right
/// singular vectors (y, z) of its invariant plane, so the set reads as the
/// bidiagonal path's (every value twice). False if dqds or inverse iteration
/// did not converge: the caller then bidiagonalises A as a general matrix.
bool skewTriplets(const DenseMatrix& A, int nModes, double clusterTol, Triplets& t) {
  const int N = A.numRows();
  const SkewTridiagonal st = skewTridiagonalise(A);
  const std::vector<double> s = skewFrequencies(st);  // descending
  const int n = static_cast<int>(s.size());
  if (n == 0 || 2 * n != N) return false;
  int want = std::min(n, nModes + 2);
  while (want < n && s[n - want] - s[n - nModes] <= clusterTol) want = std::min(n, 2 * want);
  std::vector<double> w(want);
  for (int k = 0; k < want; ++k) w[k] = s[n - 1 - k];  // ascending
  DenseMatrix Y;
  if (!skewInvariantPlanes(st, w, Y)) return false;
  t.s.resize(2 * want);
  t.VT.shape(2 * want, N);
  t.all = want == n;
  for (int k = 0; k < want; ++k) {
    const int j = want - 1 - k;  // descending, as dgesvdx returns them
    t.s[2 * k] = t.s[2 * k + 1] = w[j];
    for (int i = 0; i < N; ++i) t.VT(2 * k, i) = Y(i, 2 * j), t.VT(2 * k + 1, i) = Y(i, 2 * j + 1);
  }
  return true;
}

/// Whether the returned values hold every eigenfrequency up to the first gap
/// past the nModes-th: the Sturm count of the system (doc/theory.md, "Sturm
/// count") at the middle of that gap must equal the number of returned
/// frequencies below it (each a pair of singular values). Returns "" when it
/// does (or when the whole spectrum was returned), else what disagreed.
std::string sturmDisagreement(const GyroscopicSystem& sys, const Triplets& t, int nModes,
                              double clusterTol, std::string& confirmation) {
  const int ns = static_cast<int>(t.s.size()), edge = ns - 2 * nModes;
  int j = edge - 1;  // the smallest returned value beyond the edge's cluster
  while (j >= 0 && t.s[j] - t.s[edge] <= clusterTol) --j;
  if (j < 0) {
    confirmation = "the whole spectrum computed";
    return t.all ? "" : "no gap after the requested modes among the returned values";
  }
  const double tau = 0.5 * (t.s[j] + t.s[j + 1]);
  const int below = ns - 1 - j, counted = sturmCount(sys, tau);
  std::ostringstream os;
  if (below % 2 == 0 && counted == below / 2) {
    os << "Sturm count at " << tau << " rad/s confirms the " << counted << " lowest";
    confirmation = os.str();
    return "";
  }
  os << "the Sturm count finds " << counted << " frequencies below " << tau << " rad/s, the "
     << "returned singular values " << below / 2.0;
  return os.str();
}

/// Meirovitch's symmetric form, seed eqs. (20)-(24), solved by the SVD of the
/// skew factor A = L^-1 G* L^-T (doc/theory.md, "Dense path"). `note` gets
/// how the set was confirmed, and says when the request cut a cluster.
std::vector<GyroscopicMode> meirovitchModes(const GyroscopicSystem& sys, const DenseMatrix& Lm,
                                            const DenseMatrix& Lk, int nModes, bool skew, std::string& note,
                                            bool& complete) {
  const int n = sys.size(), N = 2 * n;
  // With L = diag(Lm, Lk):  A = [[Lm^-1 G Lm^-T, Lm^-1 Lk], [-(Lm^-1 Lk)^T, 0]].
  DenseMatrix A11(sys.G);
  lowerSolveLeft(Lm, A11);
  lowerTransSolveRight(Lm, A11);
  DenseMatrix A12(Lk);
  lowerSolveLeft(Lm, A12);
  DenseMatrix A(N, N);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      A(i, j) = 0.5 * (A11(i, j) - A11(j, i));  // exactly skew despite rounding
      A(i, n + j) = A12(i, j);
      A(n + j, i) = -A12(i, j);
    }

  // The smallest singular triplets of A: omega_r are the singular values,
  // each (nearly) double. They are selected from every value of the
  // bidiagonal form; dgesvdx, which selected them by index (and is now the
  // fallback), returned wrong sets on clusters of repeated frequencies (a
  // member of a repeated pair missing, a higher value in its place): a Sturm
  // count, independent of any eigensolver, checks the set, and the full SVD
  // replaces it if wrong.
  const double clusterTol = 1e-10 * frobeniusNorm(A);
  // The skew tridiagonal form (half the bidiagonalisation's matrix-vector
  // work, each frequency once); the general bidiagonalisation on request, or
  // should dqds or inverse iteration fail on it.
  Triplets t;
  std::string reduction = "skew tridiagonal form";
  if (!skew || !skewTriplets(A, nModes, clusterTol, t)) {
    if (skew) reduction = "bidiagonal form (the skew tridiagonal form's dqds or inverse iteration failed)";
    else reduction = "bidiagonal form";
    t = smallestTriplets(A, nModes, clusterTol);
  }
  const SetConfirmation checked = confirmLowestSet(
      [&](std::string& confirmation) { return sturmDisagreement(sys, t, nModes, clusterTol, confirmation); },
      "the selected set", [&] {
        t = allSingularTriplets(A);
        return std::string("recomputed by the full SVD (dgesvd)");
      });
  complete = checked.complete;
  note = "values from the " + reduction + "; " + checked.note;
  const std::vector<double>& s = t.s;
  const DenseMatrix& VT = t.VT;
  const int ns = static_cast<int>(s.size());

  // Walk the singular values from the smallest up, in clusters of (near-)equal
  // values. A cluster of 2m values spans m complex modes: pick them by a
  // Gram-Schmidt that keeps {c, J c} pairs, J = V^T A V / sigma being the
  // complex structure of the cluster (J^2 = -I). This separates the repeated
  // frequencies of symmetric rotors instead of returning one mode twice.
  std::vector<GyroscopicMode> modes;
  Teuchos::BLAS<int, double> blas;
  // Every returned right singular vector as a column, and W = A V for all of
  // them in one product (per cluster, 22 thin products took a tenth of a
  // sweep's solve).
  DenseMatrix Vall(N, ns), Wall;
  for (int k = 0; k < ns; ++k)
    for (int i = 0; i < N; ++i) Vall(i, k) = VT(k, i);  // rows of V^T
  gemm(false, false, 1.0, A, Vall, 0.0, Wall);
  int hi = ns;  // clusters are [lo, hi) in descending-s index
  while (hi > 0 && static_cast<int>(modes.size()) < nModes) {
    int lo = hi - 1;
    while (lo > 0 && s[lo - 1] - s[hi - 1] <= clusterTol) --lo;
    if ((hi - lo) % 2 == 1 && lo > 0) --lo;  // rounding split a pair across the tolerance
    const int c = hi - lo, m = c / 2;
    double sigma = 0.0;
    for (int k = lo; k < hi; ++k) sigma += s[k] / c;
    // V (N x c): right singular vectors of the cluster; W = A V.
    const DenseMatrix V(Teuchos::View, Vall, N, c, 0, lo), W(Teuchos::View, Wall, N, c, 0, lo);
    DenseMatrix J(c, c);
    gemm(true, false, 1.0 / std::max(sigma, std::numeric_limits<double>::min()), V, W, 0.0, J);
    std::vector<std::vector<double>> basis;  // orthonormal, closed under J
    for (int e = 0; e < c && static_cast<int>(basis.size()) < 2 * m; ++e) {
      std::vector<double> w(c, 0.0);
      w[e] = 1.0;
      for (const auto& b : basis) {
        const double d = b[e];
        for (int i = 0; i < c; ++i) w[i] -= d * b[i];
      }
      double nw = std::sqrt(std::inner_product(w.begin(), w.end(), w.begin(), 0.0));
      if (nw < 0.5) continue;
      for (double& x : w) x /= nw;
      std::vector<double> Jw(c, 0.0);
      for (int j = 0; j < c; ++j)
        for (int i = 0; i < c; ++i) Jw[i] += J(i, j) * w[j];
      for (const auto& b : basis) {  // J is orthogonal only to rounding
        const double d = std::inner_product(b.begin(), b.end(), Jw.begin(), 0.0);
        for (int i = 0; i < c; ++i) Jw[i] -= d * b[i];
      }
      const double nJ = std::sqrt(std::inner_product(Jw.begin(), Jw.end(), Jw.begin(), 0.0));
      for (double& x : Jw) x /= nJ;
      basis.push_back(w);
      basis.push_back(Jw);
      // y' = V w, z' = A y' / omega with omega = ||A y'|| (Rayleigh quotient, seed eq. (25)).
      std::vector<double> yp(N, 0.0), zp(N, 0.0);
      for (int k = 0; k < c; ++k) {
        blas.AXPY(N, w[k], &V(0, k), 1, yp.data(), 1);
        blas.AXPY(N, w[k], &W(0, k), 1, zp.data(), 1);
      }
      const double omega = blas.NRM2(N, zp.data(), 1);
      for (double& x : zp) x /= omega;
      // The state is x = [q'; q], so q is the lower half of y = L^-T y',
      // z = L^-T z' (the solves for all modes at once, below).
      GyroscopicMode mode;
      mode.lambda = cplx(0.0, omega);
      mode.q.resize(n);
      for (int i = 0; i < n; ++i) mode.q[i] = cplx(yp[n + i], zp[n + i]);
      modes.push_back(std::move(mode));
    }
    hi = lo;
  }
  // Each cluster whole, then the lowest nModes by frequency: a cluster is
  // values within clusterTol = 1e-10 ||A||_F, which for a stiff model (a
  // stub of E = 7e14 beside aluminium beams: ||A||_F ~ 2e11, clusterTol 21
  // rad/s) holds distinct frequencies too (34.57 and 43.05 rad/s), whose
  // modes came in the singular vectors' order: the list was out of order,
  // and asked for one mode the solve returned 43.05, not the lowest (found
  // by a review). A mode's frequency is its vector's ||A y'||, exact for
  // each of them.
  std::stable_sort(modes.begin(), modes.end(),
                   [](const GyroscopicMode& a, const GyroscopicMode& b) { return a.lambda.imag() < b.lambda.imag(); });
  if (static_cast<int>(modes.size()) > nModes) {
    const double kept = modes[nModes - 1].lambda.imag(), next = modes[nModes].lambda.imag();
    if (next - kept <= clusterTol) {
      std::ostringstream os;
      os << "; the request cuts a cluster: mode " << nModes + 1 << " (" << next / kTwoPi << " Hz) lies within "
         << clusterTol / kTwoPi << " Hz of mode " << nModes << " (" << kept / kTwoPi
         << " Hz), the lowest " << nModes << " returned (ask for more to have the whole cluster)";
      note += os.str();
    }
    modes.resize(nModes);
  }
  // q = L_K^-T (y'_q + i z'_q) for every mode, one triangular solve.
  const int k = static_cast<int>(modes.size());
  DenseMatrix Q(n, 2 * k);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < n; ++i) Q(i, 2 * j) = modes[j].q[i].real(), Q(i, 2 * j + 1) = modes[j].q[i].imag();
  blas.TRSM(Teuchos::LEFT_SIDE, Teuchos::LOWER_TRI, Teuchos::TRANS, Teuchos::NON_UNIT_DIAG, n, 2 * k, 1.0,
            Lk.values(), Lk.stride(), Q.values(), Q.stride());
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < n; ++i) modes[j].q[i] = cplx(Q(i, 2 * j), Q(i, 2 * j + 1));
  return modes;
}

/// dggev's QZ returned beta = 0 exactly: an infinite eigenvalue, which a
/// positive definite M does not have (it happened at a mass ratio of 1e6,
/// with OpenBLAS's Nehalem kernels, on 2 ranks' sums).
class InfiniteEigenvalue : public NumericalError {
public:
  using NumericalError::NumericalError;
};

/// dggev's QZ iteration did not converge (info > 0). It happened at the
/// edge of a ground-resonance band (theory §16.4), where two eigenvalues
/// coalesce into a defective pair, after the pencil's scale moved by one
/// rounding: a critical speed, an answer the general path must give.
class QzFailure : public NumericalError {
public:
  using NumericalError::NumericalError;
};

/// The 2n first-order pencil A x = lambda B x with x = [q; q'],
/// A = [[0, I], [-(K + N), -(G + D)]], B = [[I, 0], [0, M]], solved by LAPACK
/// dggev after scaling time so that M, G, K have comparable norms
/// (doc/theory.md, "General"; the damped pencil, §13). With `standard`, M
/// must be I and B is then the identity: LAPACK dgeev (Hessenberg QR, shifts
/// of its own) solves A x = lambda x instead, the last resort when dggev's QZ
/// failed on the pencil in both coordinates. `unreturned` receives the
/// eigenvalues (Im >= 0) past the nModes returned, for the stability
/// verdict's mirror test (classifyModes). `rigidBodyTol`: of the scaled
/// |lambda| (frequency scale 1), as classifyModes takes it.
/// The modes of the unrestrained coordinates (GyroscopicSystem::unrestrained)
/// solved on their own scale by solveUnrestrained, for generalModes to put
/// in place of the whole solve's values there (theory §4.3).
struct UnrestrainedModes {
  std::vector<GyroscopicMode> modes;  ///< one of each conjugate pair, as generalModes returns; q on all n rows
  int count = 0;                      ///< the block's eigenvalues, both halves: 2k
  double largest = 0.0;               ///< the largest |lambda| among them, 1/s
  std::string note;                   ///< what was done, or why not (then `modes` is empty)
};

std::vector<GyroscopicMode> generalModes(const GyroscopicSystem& sys, int nModes, double scale, double rigidBodyTol,
                                         std::vector<cplx>& unreturned, bool standard = false,
                                         UnrestrainedModes* block = nullptr, bool spares = false) {
  const int n = sys.size(), N = 2 * n;
  const bool hasD = sys.D.numRows() == n, hasN = sys.N.numRows() == n;
  const bool damped = sys.damped();
  const double mu = std::max(frobeniusNorm(sys.M), std::numeric_limits<double>::min());
  DenseMatrix A(N, N), B(N, N);
  for (int i = 0; i < n; ++i) {
    A(i, n + i) = 1.0;
    B(i, i) = 1.0;
  }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      A(n + i, j) = -(sys.K(i, j) + (hasN ? sys.N(i, j) : 0.0)) / (mu * scale * scale);
      A(n + i, n + j) = -(sys.G(i, j) + (hasD ? sys.D(i, j) : 0.0)) / (mu * scale);
      B(n + i, n + j) = sys.M(i, j) / mu;
    }
  std::vector<double> ar(N), ai(N), be(N);
  DenseMatrix VR(N, N);
  double vl = 0.0, wq = 0.0;
  int info = 0, lwork = -1;
  Teuchos::LAPACK<int, double> lapack;
  if (standard) {
    // B = diag(I, M / mu) with M = I: A itself, scaled back by mu.
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) A(n + i, j) *= mu, A(n + i, n + j) *= mu;
    lapack.GEEV('N', 'V', N, A.values(), N, ar.data(), ai.data(), &vl, 1, VR.values(), N, &wq, lwork, nullptr, &info);
    lwork = static_cast<int>(wq);
    std::vector<double> work(std::max(1, lwork));
    lapack.GEEV('N', 'V', N, A.values(), N, ar.data(), ai.data(), &vl, 1, VR.values(), N, work.data(), lwork, nullptr,
                &info);
    TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError,
                               "DenseGyroscopicSolver: LAPACK dgeev failed, info = " << info
                                   << " (its QR iteration did not converge), after dggev's QZ failed on the pencil "
                                      "in the given coordinates and in those with M = I");
    std::fill(be.begin(), be.end(), 1.0);
  } else {
    lapack.GGEV('N', 'V', N, A.values(), N, B.values(), N, ar.data(), ai.data(), be.data(), &vl, 1,
                VR.values(), N, &wq, lwork, &info);
    lwork = static_cast<int>(wq);
    std::vector<double> work(std::max(1, lwork));
    lapack.GGEV('N', 'V', N, A.values(), N, B.values(), N, ar.data(), ai.data(), be.data(), &vl, 1,
                VR.values(), N, work.data(), lwork, &info);
    TEUCHOS_TEST_FOR_EXCEPTION(info < 0, std::logic_error,
                               "DenseGyroscopicSolver: LAPACK dggev rejected argument " << -info);
    if (info > 0)
      throw QzFailure("DenseGyroscopicSolver: LAPACK dggev's QZ iteration failed, info = " + std::to_string(info));
  }

  // One eigenvalue of each conjugate pair is kept (the modes of lambda and
  // conj(lambda) are conjugate): those with Im > 0, and of the (near-)real
  // ones, which pair as +/- sigma, the upper half by Re. A damped system's
  // spectrum has no +/- symmetry: every real eigenvalue is a mode of its
  // own (an overdamped DOF gives two, both decaying), and of a complex pair
  // only the member with Im > 0 is kept even when Im is within rounding of 0.
  struct Cand { cplx lambda; std::vector<cplx> q; double blockScale = 0.0, blockError = 0.0; };
  std::vector<Cand> upper, real;
  const double imagTol = 1e-9;  // relative to the scaled frequency 1
  // The unrestrained block's modes, solved on their own scale, take the
  // place of the 2k values of least |lambda| here, where this solve left
  // them to its normwise rounding (theory §4.3), when those 2k are
  // separated from the rest by a factor of 10 (and from the block's own
  // values): otherwise the block is not what the least values are.
  std::vector<char> replaced(N, 0);
  if (block && !block->modes.empty()) {
    std::vector<std::pair<double, int>> size(N);
    for (int j = 0; j < N; ++j)
      size[j] = {be[j] == 0.0 ? std::numeric_limits<double>::infinity() : std::hypot(ar[j], ai[j]) / std::abs(be[j]), j};
    std::sort(size.begin(), size.end());
    const int p = block->count;
    const double inner = p > 0 ? size[p - 1].first : 0.0, outer = p < N ? size[p].first : 0.0;
    std::ostringstream note;
    note << std::setprecision(3);
    if (p < N && outer >= 10.0 * std::max(inner, block->largest / scale)) {
      for (int i = 0; i < p; ++i) replaced[size[i].second] = 1;
      note << "; the " << p << " eigenvalues of least |lambda| solved again on the " << p / 2
           << " coordinates the stiffness at rest does not reach (Schur complement, theory §4.3)";
    } else {
      block->modes.clear();
      note << "; the " << p / 2 << " coordinates the stiffness at rest does not reach were not solved apart: their "
           << p << " eigenvalues are not separated from the rest by 10x (|lambda| " << inner * scale << " and "
           << outer * scale << " 1/s about the cut, the block's largest " << block->largest << ")";
    }
    block->note = note.str();
  }
  for (int j = 0; j < N; ++j) {
    if (replaced[j]) {
      if (ai[j] != 0.0) ++j;  // its conjugate, of the same |lambda|, is replaced too
      continue;
    }
    if (be[j] == 0.0) throw InfiniteEigenvalue("DenseGyroscopicSolver: dggev returned an infinite eigenvalue (beta = 0)");
    cplx lam(ar[j] / be[j], ai[j] / be[j]);
    std::vector<cplx> q(n);
    if (ai[j] != 0.0) {  // complex pair stored in columns j, j+1
      for (int i = 0; i < n; ++i) q[i] = cplx(VR(i, j), VR(i, j + 1));
      cplx lam2 = std::conj(lam);
      std::vector<cplx> q2(n);
      for (int i = 0; i < n; ++i) q2[i] = std::conj(q[i]);
      for (auto& [l, v] : {std::make_pair(lam, q), std::make_pair(lam2, q2)}) {
        if (damped && l.imag() < 0) continue;
        if (std::abs(l.imag()) <= imagTol * std::max(1.0, std::abs(l))) real.push_back({l, v});
        else if (l.imag() > 0) upper.push_back({l, v});
      }
      ++j;
    } else {
      for (int i = 0; i < n; ++i) q[i] = VR(i, j);
      real.push_back({lam, q});
    }
  }
  std::sort(real.begin(), real.end(),
            [](const Cand& a, const Cand& b) { return a.lambda.real() > b.lambda.real(); });
  // A rigid motion D does not damp is a double, defective zero of the damped
  // pencil too (theory §13.2): dggev returns two eigenvectors of one shape,
  // split by rounding into two real zeros or a pair +/- i delta, and with
  // several rigid motions the cluster's vectors are ill-conditioned mixes
  // of them. So the zeros are not told apart one by one (a threshold on
  // each vector's remainder kept 8 of 6 rigid motions and dropped one of 3;
  // found by a review): their number is K's, the count r of eigenvalues of
  // (K + N symmetric part, M) within the rigid tolerance, and the r rigid
  // modes are the r dominant directions of the span of every zero's shape
  // (an M-orthonormal basis: the null space of K). A rigid motion D damps is
  // one zero and one decaying root, the root kept as any real eigenvalue.
  // The undamped path halves the +/- pairs instead.
  if (damped) {
    std::vector<Cand> zeros;
    for (std::vector<Cand>* list : {&real, &upper}) {
      std::vector<Cand> rest;
      for (Cand& c : *list) (std::abs(c.lambda) <= rigidBodyTol ? zeros : rest).push_back(std::move(c));
      *list = std::move(rest);
    }
    int r = static_cast<int>(zeros.size());
    if (zeros.size() > 1) {
      // r: (K_sym / s^2) x = mu M x, mu = omega^2 in the scaled time.
      DenseMatrix Ks(n, n), Mc(sys.M);
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          Ks(i, j) = (0.5 * (sys.K(i, j) + sys.K(j, i)) +
                      (hasN ? 0.5 * (sys.N(i, j) + sys.N(j, i)) : 0.0)) / (scale * scale);
      std::vector<double> mu(n), work(std::max(1, 3 * n));
      int info = 0;
      lapack.SYGV(1, 'N', 'U', n, Ks.values(), n, Mc.values(), n, mu.data(), work.data(), static_cast<int>(work.size()),
                  &info);
      if (info == 0) {
        int count = 0;
        for (double m : mu) count += std::abs(m) <= rigidBodyTol * rigidBodyTol;
        r = std::min(r, count);
      }
    }
    if (r > 0 && r < static_cast<int>(zeros.size())) {
      // The span of the zeros' shapes (real and imaginary parts) in M's inner
      // product: its r largest directions, M-orthonormal.
      const int z = static_cast<int>(zeros.size());
      DenseMatrix Z(n, 2 * z), MZ, G;
      for (int j = 0; j < z; ++j)
        for (int i = 0; i < n; ++i) Z(i, j) = zeros[j].q[i].real(), Z(i, z + j) = zeros[j].q[i].imag();
      gemm(false, false, 1.0, sys.M, Z, 0.0, MZ);
      gemm(true, false, 1.0, Z, MZ, 0.0, G);
      std::vector<double> w(2 * z), work(std::max(1, 6 * z));
      int info = 0;
      lapack.SYEV('V', 'U', 2 * z, G.values(), 2 * z, w.data(), work.data(), static_cast<int>(work.size()), &info);
      if (info == 0 && w[2 * z - 1] > 0.0) {
        std::vector<Cand> rigid;
        for (int k = 0; k < r; ++k) {
          const int col = 2 * z - 1 - k;  // dsyev's eigenvalues ascend
          Cand c{cplx(0.0, 0.0), std::vector<cplx>(n)};
          const double norm = std::sqrt(std::max(w[col], 0.0));
          if (!(norm > 0.0)) break;
          for (int i = 0; i < n; ++i) {
            double v = 0.0;
            for (int m = 0; m < 2 * z; ++m) v += Z(i, m) * G(m, col);
            c.q[i] = v / norm;
          }
          rigid.push_back(std::move(c));
        }
        zeros = std::move(rigid);
      }
    }
    for (Cand& c : zeros) real.push_back(std::move(c));
    std::sort(real.begin(), real.end(),
              [](const Cand& a, const Cand& b) { return a.lambda.real() > b.lambda.real(); });
  }
  const std::size_t keepReal = damped ? real.size() : (real.size() + 1) / 2;
  for (std::size_t k = 0; k < keepReal; ++k) {
    real[k].lambda = cplx(real[k].lambda.real(), 0.0);
    upper.push_back(real[k]);
  }
  if (block)
    for (const auto& m : block->modes) upper.push_back({m.lambda / scale, m.q, m.blockScale, m.blockError});
  std::sort(upper.begin(), upper.end(), [](const Cand& a, const Cand& b) {
    return std::abs(a.lambda) < std::abs(b.lambda);
  });
  // Flutter of a conservative system is a quadruple: a + ib and -a + ib
  // have the same |lambda|, so the count can cut between them, and rounding
  // picks the survivor. The growing member is returned (a decaying one alone
  // would leave the system "stable"), and the rest go to `unreturned`, where
  // the verdict finds its mirror (found by a review: a growing member
  // without its returned mirror was called stable).
  const int kept = std::min(nModes, static_cast<int>(upper.size()));
  // A damped system's real pair +/- sigma (a divergence D does not reach,
  // a free body's about its intermediate axis) has |lambda| equal to
  // rounding: the count cut between them kept the decaying one and the
  // verdict read stable (found by a review). A growing value beyond the
  // cut within 1e-8 of the last kept |lambda| takes the place of a
  // decaying one there.
  if (damped && kept > 0)
    for (std::size_t j = kept; j < upper.size(); ++j) {
      if (!(upper[j].lambda.real() > 0.0) ||
          std::abs(upper[j].lambda) > (1.0 + 1e-8) * std::abs(upper[static_cast<std::size_t>(kept - 1)].lambda))
        continue;
      for (int k = kept - 1; k >= 0; --k)
        if (upper[static_cast<std::size_t>(k)].lambda.real() < 0.0 &&
            std::abs(upper[j].lambda) <= (1.0 + 1e-8) * std::abs(upper[static_cast<std::size_t>(k)].lambda)) {
          std::swap(upper[static_cast<std::size_t>(k)], upper[j]);
          break;
        }
    }
  if (!damped)
    for (int k = 0; k < kept; ++k) {
      if (!(upper[k].lambda.real() < 0.0)) continue;
      for (std::size_t j = kept; j < upper.size(); ++j)
        if (std::abs(upper[j].lambda + std::conj(upper[k].lambda)) <= 0.5 * std::abs(upper[k].lambda.real())) {
          std::swap(upper[k], upper[j]);
          break;
        }
    }
  // With `spares`, a damped system's modes past the count, one for each
  // real value within it: a conjugate pair rounding split onto the real
  // axis is two real values for one mode, and where the refinement finds
  // the second half to be the pair already held it is dropped
  // (undoRepeatedRefinements); a spare then takes its place, and the rest
  // go back to `unreturned` (completeModes).
  std::size_t returned = static_cast<std::size_t>(kept);
  if (spares && damped)
    for (int k = 0; k < kept; ++k)
      if (returned < upper.size() && upper[k].lambda.imag() == 0.0 && std::abs(upper[k].lambda) > rigidBodyTol &&
          upper[k].blockScale == 0.0)
        ++returned;
  std::vector<GyroscopicMode> modes;
  for (std::size_t k = 0; k < returned; ++k) {
    GyroscopicMode m;
    m.lambda = upper[k].lambda * scale;
    m.q = std::move(upper[k].q);
    m.blockScale = upper[k].blockScale;
    m.blockError = upper[k].blockError;
    modes.push_back(std::move(m));
  }
  unreturned.clear();
  for (std::size_t j = returned; j < upper.size(); ++j) unreturned.push_back(upper[j].lambda * scale);
  return modes;
}

extern "C" {
void zgetrf_(const int* m, const int* n, std::complex<double>* a, const int* lda, int* ipiv, int* info);
void zgetrs_(const char* trans, const int* n, const int* nrhs, const std::complex<double>* a, const int* lda,
             const int* ipiv, std::complex<double>* b, const int* ldb, int* info, std::size_t);
void zggev_(const char* jobvl, const char* jobvr, const int* n, std::complex<double>* a, const int* lda,
            std::complex<double>* b, const int* ldb, std::complex<double>* alpha, std::complex<double>* beta,
            std::complex<double>* vl, const int* ldvl, std::complex<double>* vr, const int* ldvr,
            std::complex<double>* work, const int* lwork, double* rwork, int* info, std::size_t, std::size_t);
}

/// The modes of the coordinates r on which the stiffness at rest vanishes
/// (theory §4.3). With e the others, eliminating q_e from the rows e of
/// Q(lambda) q = 0, Q = lambda^2 M + lambda C + A (C = G + D, A = K + N),
/// leaves S(lambda) q_r = 0 with the Schur complement
///   S(lambda) = Q_rr - Q_re Q_ee(lambda)^-1 Q_er = sum_j S_j lambda^j,
///   q_e = -sum_j lambda^j X_j q_r,
///   X_j = A_ee^-1 (B_j - C_ee X_{j-1} - M_ee X_{j-2}),  B = (A_er, C_er, M_er, 0, ...),
///   S_j = (A_rr, C_rr, M_rr, 0, ...)_j - A_re X_j - C_re X_{j-1} - M_re X_{j-2},
/// a series converging for |lambda| below the least eigenvalue of Q_ee. A_rr,
/// A_re hold the speed's terms only (Omega^2 K_T, the prestress), so every
/// S_j is on the block's scale, not the elastic one: its eigenvalues are
/// resolved to that scale. The quadratic S_0 + lambda S_1 + lambda^2 S_2 (a
/// gyroscopic system of k coordinates, Hamiltonian like the whole) is solved
/// by generalModes, which says which modes are returned; each nonzero one
/// takes the nearest eigenvalue of the whole series (its companion pencil),
/// each zero the null space of S_0, and q_e is summed to rounding.
UnrestrainedModes solveUnrestrained(const GyroscopicSystem& sys, double rigidBodyTol) {
  UnrestrainedModes out;
  const int n = sys.size(), k = static_cast<int>(sys.unrestrained.size()), m = n - k;
  if (k == 0 || m == 0) return out;
  const double eps = std::numeric_limits<double>::epsilon();
  const bool hasD = sys.D.numRows() == n, hasN = sys.N.numRows() == n;
  const std::vector<int>& r = sys.unrestrained;
  std::vector<int> e;
  for (int i = 0, next = 0; i < n; ++i)
    if (next < k && r[next] == i) ++next;
    else e.push_back(i);
  // The coefficients of lambda^0, lambda^1, lambda^2: A = K + N, C = G + D, M.
  const auto coefficient = [&](int d, int i, int j) {
    return d == 0 ? sys.K(i, j) + (hasN ? sys.N(i, j) : 0.0)
                  : d == 1 ? sys.G(i, j) + (hasD ? sys.D(i, j) : 0.0) : sys.M(i, j);
  };
  DenseMatrix Aee[3], Aer[3], Are[3], Arr[3];
  for (int d = 0; d < 3; ++d) {
    Aee[d].shape(m, m), Aer[d].shape(m, k), Are[d].shape(k, m), Arr[d].shape(k, k);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) Aee[d](i, j) = coefficient(d, e[i], e[j]);
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < m; ++i) Aer[d](i, j) = coefficient(d, e[i], r[j]), Are[d](j, i) = coefficient(d, r[j], e[i]);
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) Arr[d](i, j) = coefficient(d, r[i], r[j]);
  }
  Teuchos::LAPACK<int, double> lapack;
  DenseMatrix F(Aee[0]);
  std::vector<int> piv(m);
  int info = 0;
  double norm1 = 0.0;
  for (int j = 0; j < m; ++j) {
    double c = 0.0;
    for (int i = 0; i < m; ++i) c += std::abs(Aee[0](i, j));
    norm1 = std::max(norm1, c);
  }
  lapack.GETRF(m, m, F.values(), m, piv.data(), &info);
  double rcond = 0.0;
  if (info == 0) {
    std::vector<double> work(4 * m);
    std::vector<int> iwork(m);
    lapack.GECON('1', m, F.values(), m, norm1, &rcond, work.data(), iwork.data(), &info);
  }
  if (info != 0 || !(rcond > 100.0 * eps)) {
    std::ostringstream why;
    why << std::setprecision(3) << "; the " << k << " coordinates the stiffness at rest does not reach were not solved "
        << "apart: K on the other " << m << " is singular to rounding (reciprocal condition " << rcond << ")";
    out.note = why.str();
    return out;
  }
  // What the block's matrices are worth: X_j = A_ee^-1 (...) carries eps
  // cond(A_ee), and so does the prestress in A_rr, which a static solve
  // with the same stiffness made (its rigid-rotation balance, theory
  // §11.6). A coned spinner's booms 1e3 times stiffer (cond 4e9) split the
  // double zero of its turn about the axis by 6e-6 of the block's scale:
  // within 10 sqrt(eps cond), and no instability (the zeros, below).
  std::vector<DenseMatrix> X, S;
  const auto term = [&](int j) {  // X_j and S_j from those before
    DenseMatrix B(m, k), Sj(k, k);
    if (j <= 2) B.assign(Aer[j]), Sj.assign(Arr[j]);
    if (j >= 1) gemm(false, false, -1.0, Aee[1], X[j - 1], 1.0, B);
    if (j >= 2) gemm(false, false, -1.0, Aee[2], X[j - 2], 1.0, B);
    int inf = 0;
    lapack.GETRS('N', m, k, F.values(), m, piv.data(), B.values(), m, &inf);
    gemm(false, false, -1.0, Are[0], B, 1.0, Sj);
    if (j >= 1) gemm(false, false, -1.0, Are[1], X[j - 1], 1.0, Sj);
    if (j >= 2) gemm(false, false, -1.0, Are[2], X[j - 2], 1.0, Sj);
    X.push_back(std::move(B));
    S.push_back(std::move(Sj));
  };
  for (int j = 0; j < 3; ++j) term(j);
  // The quadratic: symmetric and skew parts as a gyroscopic system (the
  // other parts, D's and N's, only where the whole system has them; in an
  // undamped one they are rounding).
  GyroscopicSystem q;
  q.M.shape(k, k), q.G.shape(k, k), q.K.shape(k, k);
  if (hasD) q.D.shape(k, k);
  if (hasN) q.N.shape(k, k);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      q.M(i, j) = 0.5 * (S[2](i, j) + S[2](j, i));
      q.G(i, j) = 0.5 * (S[1](i, j) - S[1](j, i));
      q.K(i, j) = 0.5 * (S[0](i, j) + S[0](j, i));
      if (hasD) q.D(i, j) = 0.5 * (S[1](i, j) + S[1](j, i));
      if (hasN) q.N(i, j) = 0.5 * (S[0](i, j) - S[0](j, i));
    }
  // A damping term that does no work on these coordinates (Rayleigh's beta
  // K, zero on a rigid motion as K is) leaves them only its rounding: S_1 is
  // then that rounding, and on its scale (1e-10 for a damped free beam at
  // rest) the rounding of the zeros read DIVERGENCE (found by a review).
  // That rounding is the synthesis' projection's (T^T D T, sums over a
  // substructure's DOFs weighted by rigid motions' lever arms), not eps
  // ||D||: the spacecraft at rest with beta on its booms kept 90 eps ||D||
  // there, above the 10 eps this took for zero, and read two rigid motions
  // a second time, one as DIVERGENCE at 1.7e-15 1/s on its block scale of
  // 3e-15 (a review). Below 1e3 eps of the whole system's ||G|| + ||D||
  // (ten times that) it is zero: a genuine damping of these coordinates so
  // small is below what their matrices hold.
  {
    const double roundingOfC = 1e3 * eps * (frobeniusNorm(sys.G) + (hasD ? frobeniusNorm(sys.D) : 0.0));
    if (frobeniusNorm(q.G) + (hasD ? frobeniusNorm(q.D) : 0.0) <= roundingOfC) {
      q.G.putScalar(0.0);
      if (hasD) q.D.putScalar(0.0);
      S[1].putScalar(0.0);
    }
  }
  DenseMatrix L(q.M);
  if (choleskyLower(L) != 0) {
    out.note = "; the " + std::to_string(k) + " coordinates the stiffness at rest does not reach were not solved "
               "apart: their Schur complement's mass is not positive definite";
    return out;
  }
  const double blockScale = frequencyScale(frobeniusNorm(q.M), frobeniusNorm(q.G) + (hasD ? frobeniusNorm(q.D) : 0.0),
                                           frobeniusNorm(q.K) + (hasN ? frobeniusNorm(q.N) : 0.0));
  // S_0 = S_1 = 0 (a free body at rest): every eigenvalue is exactly zero,
  // and any scale resolves them; 1 keeps the arithmetic finite.
  const double useScale = blockScale > 0.0 ? blockScale : 1.0;
  std::vector<cplx> beyond;
  std::vector<GyroscopicMode> modes;
  try {
    modes = generalModes(q, 2 * k, useScale, rigidBodyTol, beyond);
  } catch (const NumericalError& err) {
    out.note = "; the " + std::to_string(k) + " coordinates the stiffness at rest does not reach were not solved "
               "apart: " + err.what();
    return out;
  }
  // The zeros: a mode of the quadratic within 10 sqrt(blockError) s_b of
  // zero (what the block's accuracy, eps cond(A_ee), can split a double
  // zero by) whose energy S_0 does not see beyond that accuracy:
  // |y^H S_0 y| <= 10 blockError s_b^2 |y^H S_2 y|. A simple small real pair
  // +/- sigma has sigma^2 / s_b^2 there, a split zero at most blockError: a
  // free body whose two inertias differ by 4e-6, diverging at 0.00233 1/s,
  // is no zero at 64 elements (eps cond 3e-8; with the radius alone it read
  // "rigid", found by a review), but at 128 (eps cond 5e-7) the block's
  // accuracy cannot tell it from one. Their shapes:
  // an M-orthonormal basis of the null space of S_0 (the eigenvectors of
  // (S_0, S_2) of least |mu|, as many as there are zeros, at most k). The
  // pencil's own vectors at a Jordan block are the block's one eigenvector
  // twice, and halving the +/- pairs kept both copies: a free body at rest
  // (S_0 = S_1 = 0) returned two of its six rigid motions twice and lost
  // the axial translation and the turn about the axis.
  const double blockError = std::max(eps / rcond, eps);
  const double zeroBelow = std::max(rigidBodyTol, 10.0 * std::sqrt(blockError)) * useScale;
  std::vector<char> isZero(modes.size(), 0);
  {
    std::vector<GyroscopicMode*> zeros;
    for (std::size_t i = 0; i < modes.size(); ++i) {
      auto& md = modes[i];
      if (!(std::abs(md.lambda) <= zeroBelow) || static_cast<int>(zeros.size()) >= k) continue;
      cplx yKy = 0.0, yMy = 0.0;
      for (int c = 0; c < k; ++c)
        for (int r2 = 0; r2 < k; ++r2)
          yKy += std::conj(md.q[r2]) * q.K(r2, c) * md.q[c], yMy += std::conj(md.q[r2]) * q.M(r2, c) * md.q[c];
      if (std::abs(yKy) <= 10.0 * blockError * useScale * useScale * std::abs(yMy)) zeros.push_back(&md), isZero[i] = 1;
    }
    if (!zeros.empty()) {
      DenseMatrix Ks(q.K), Ms(q.M);
      std::vector<double> w(k), work(std::max(1, 3 * k));
      int inf = 0;
      lapack.SYGV(1, 'V', 'U', k, Ks.values(), k, Ms.values(), k, w.data(), work.data(), static_cast<int>(work.size()),
                  &inf);
      if (inf == 0) {
        std::vector<int> least(k);
        std::iota(least.begin(), least.end(), 0);
        std::stable_sort(least.begin(), least.end(), [&](int a, int b) { return std::abs(w[a]) < std::abs(w[b]); });
        for (std::size_t z = 0; z < zeros.size(); ++z)
          for (int i = 0; i < k; ++i) zeros[z]->q[i] = Ks(i, least[z]);
      }
    }
  }
  for (const auto& md : modes) out.largest = std::max(out.largest, std::abs(md.lambda));
  for (cplx l : beyond) out.largest = std::max(out.largest, std::abs(l));
  // The series to rounding at the largest eigenvalue: ||X_j|| mu^j against
  // the sum so far, two terms in a row below eps of it. Within 24 terms it
  // gets there when mu is below a fifth of the series' radius (the least
  // eigenvalue of Q_ee); one that does not has an eigenvalue of Q_ee near
  // the block's, which the whole solve's 10x separation test below would
  // refuse anyway, after a companion pencil of 6 k x 6 k or more (the
  // spacecraft's 101-speed sweep took 1.2 s for 0.25 s with 60 terms).
  const double mu = out.largest;
  double sum = 0.0;
  for (int j = 0; j < 3; ++j) sum += frobeniusNorm(X[j]) * std::pow(mu, j);
  int quiet = 0;
  for (int j = 3; j < 24 && quiet < 2; ++j) {
    term(j);
    const double t = frobeniusNorm(X[j]) * std::pow(mu, j);
    sum += t;
    quiet = t <= eps * sum ? quiet + 1 : 0;
    if (!std::isfinite(t)) break;
  }
  if (quiet < 2) {
    std::ostringstream why;
    why << std::setprecision(3) << "; the " << k << " coordinates the stiffness at rest does not reach were not solved "
        << "apart: the other coordinates' response does not converge at |lambda| = " << mu
        << " 1/s (their own frequencies are not far enough above)";
    out.note = why.str();
    return out;
  }
  // The whole series' eigenvalues: its companion pencil (A, B) of size d k,
  // z = [y; mu y; ...; mu^(d-1) y], in mu = lambda / s_b with the
  // coefficients over the largest ||S_j|| s_b^j. The quadratic alone is off
  // by the series' tail, ~(lambda / omega_e)^2 relative, which a defective
  // eigenvalue (a free body's frame-rate triple) turns into a split of its
  // square or cube root: 1.2e-4 Omega for the beam below, a false flutter.
  const int terms = static_cast<int>(S.size()), d = terms - 1, N = d * k;
  double nu = 0.0;
  for (int j = 0; j < terms; ++j) nu = std::max(nu, frobeniusNorm(S[j]) * std::pow(useScale, j));
  DenseMatrix A(N, N), B(N, N);
  for (int i = 0; i < (d - 1) * k; ++i) A(i, k + i) = 1.0, B(i, i) = 1.0;
  for (int j = 0; j < terms; ++j) {
    const double c = std::pow(useScale, j) / nu;
    for (int col = 0; col < k; ++col)
      for (int row = 0; row < k; ++row) {
        if (j < d) A((d - 1) * k + row, j * k + col) = -S[j](row, col) * c;
        else B((d - 1) * k + row, (d - 1) * k + col) = S[j](row, col) * c;
      }
  }
  std::vector<double> ar(N), ai(N), be(N);
  DenseMatrix Z(N, N);
  double vl = 0.0, wq = 0.0;
  int lwork = -1;
  lapack.GGEV('N', 'V', N, A.values(), N, B.values(), N, ar.data(), ai.data(), be.data(), &vl, 1, Z.values(), N, &wq,
              lwork, &info);
  lwork = static_cast<int>(wq);
  std::vector<double> work(std::max(1, lwork));
  lapack.GGEV('N', 'V', N, A.values(), N, B.values(), N, ar.data(), ai.data(), be.data(), &vl, 1, Z.values(), N,
              work.data(), lwork, &info);
  std::vector<std::pair<double, int>> order;
  for (int j = 0; info == 0 && j < N; ++j)
    order.push_back({be[j] == 0.0 ? std::numeric_limits<double>::infinity() : std::hypot(ar[j], ai[j]) / std::abs(be[j]), j});
  std::sort(order.begin(), order.end());
  // Its 2k least are the block's, when the next is 10 times further out
  // (the rest approximate the other coordinates' own eigenvalues).
  if (info != 0 || N <= 2 * k || !(order[2 * k].first >= 10.0 * order[2 * k - 1].first)) {
    std::ostringstream why;
    why << std::setprecision(3) << "; the " << k << " coordinates the stiffness at rest does not reach were not solved "
        << "apart: " << (info != 0 ? "dggev failed on their series' companion pencil"
                                   : "their series has other eigenvalues near theirs");
    out.note = why.str();
    return out;
  }
  struct Root { cplx lambda; std::vector<cplx> y; bool used = false; };
  std::vector<Root> roots;
  for (int i = 0; i < 2 * k; ++i) {
    const int j = order[i].second;
    // A complex pair is stored in columns (j, j + 1) for Im > 0, its
    // conjugate's index being j + 1 with the same columns.
    const bool second = ai[j] < 0.0 && j > 0 && ai[j - 1] > 0.0;
    const int c = second ? j - 1 : j;
    Root root{cplx(ar[j], ai[j]) / be[j] * useScale, std::vector<cplx>(k)};
    for (int row = 0; row < k; ++row)
      root.y[row] = ai[j] == 0.0 ? cplx(Z(row, c), 0.0)
                                 : cplx(Z(row, c), second ? -Z(row, c + 1) : Z(row, c + 1));
    roots.push_back(std::move(root));
  }
  // Each of the quadratic's modes (one of each conjugate pair, its zeros
  // told apart by generalModes) takes the nearest of the series' roots; a
  // zero (within the Jordan split of the block's accuracy, above) keeps
  // the quadratic's value and its null-space shape: the tail vanishes at
  // lambda = 0.
  for (std::size_t i = 0; i < modes.size(); ++i) {
    auto& md = modes[i];
    cplx l = md.lambda;
    std::vector<cplx> y = md.q;
    if (!isZero[i]) {
      Root* best = nullptr;
      for (auto& root : roots)
        if (!root.used && (!best || std::abs(root.lambda - l) < std::abs(best->lambda - l))) best = &root;
      if (best) best->used = true, l = best->lambda, y = best->y;
    }
    // Every coordinate: q_r = y, q_e = -sum_j l^j X_j y.
    std::vector<cplx> full(n, 0.0);
    for (int i = 0; i < k; ++i) full[r[i]] = y[i];
    cplx p = 1.0;
    for (int j = 0; j < terms; ++j, p *= l)
      for (int c = 0; c < k; ++c) {
        const cplx f = p * y[c];
        for (int i = 0; i < m; ++i) full[e[i]] -= f * X[j](i, c);
      }
    md.lambda = l;
    md.q = std::move(full);
    md.blockScale = useScale;
    // Only a zero carries the block's accuracy into its verdict: a simple
    // eigenvalue moves by it to first order, not by its square root.
    md.blockError = isZero[i] ? blockError : 0.0;
  }
  out.modes = std::move(modes);
  out.count = 2 * k;
  return out;
}

}  // namespace

double frequencyScale(double normM, double normG, double normK) {
  const double tiny = std::numeric_limits<double>::min();
  const double s = std::sqrt(normK / std::max(normM, tiny)) + normG / std::max(normM, tiny);
  return s > 0.0 ? s : 1.0;
}

double growthUncertainty(cplx lambda, double errorBound, double etaQ, double instabilityTol,
                         const std::vector<cplx>& others, bool conservative) {
  const double eps = std::numeric_limits<double>::epsilon();
  const double size = std::abs(lambda), split = 10.0 * std::sqrt(std::max(etaQ, eps)) * size;
  const double radius = 10.0 * split;
  // lambda's own conjugate (a real pair split off the axis) and, conservative,
  // its mirror -conj(lambda) (a flutter pair at its onset).
  bool near = 2.0 * std::abs(lambda.imag()) <= radius || (conservative && 2.0 * std::abs(lambda.real()) <= radius);
  for (cplx o : others) {
    if (near) break;
    for (cplx v : {o, std::conj(o)}) {
      near = near || std::abs(v - lambda) <= radius;
      if (conservative) near = near || std::abs(-v - lambda) <= radius;
    }
  }
  return std::max({errorBound, near ? split : 0.0, instabilityTol * size});
}

namespace {
/// undecidedGrowth for a growth rate of sign `sign` (+1: growing; -1:
/// decaying, undecidedDecay).
bool undecidedSign(const GyroscopicMode& m, const std::vector<GyroscopicMode>& modes, double instabilityTol,
                   double zeroBelow, double sign) {
  const double growth = sign * m.lambda.real(), size = std::abs(m.lambda);
  if (!(growth > instabilityTol * size) || !(growth <= m.growthTolerance) ||
      size <= zeroBelow || m.blockScale > 0.0)
    return false;
  for (const auto& o : modes)
    if (&o != &m && (std::abs(o.lambda - m.lambda) <= 1e-3 * size ||
                     std::abs(o.lambda - std::conj(m.lambda)) <= 1e-3 * size ||
                     std::abs(o.lambda + std::conj(m.lambda)) <= 1e-3 * size))
      return false;
  return true;
}

/// A decaying growth rate whose sign its uncertainty does not decide (as
/// undecidedGrowth, the sign turned): on a circulatory system (N != 0,
/// which no energy bound makes stable) the dense path refines it too, and
/// one left unrefined reads Neutral (theory §13.3).
bool undecidedDecay(const GyroscopicMode& m, const std::vector<GyroscopicMode>& modes, double instabilityTol,
                    double zeroBelow) {
  return undecidedSign(m, modes, instabilityTol, zeroBelow, -1.0);
}
}  // namespace

bool undecidedGrowth(const GyroscopicMode& m, const std::vector<GyroscopicMode>& modes, double instabilityTol,
                     double zeroBelow) {
  return undecidedSign(m, modes, instabilityTol, zeroBelow, 1.0);
}

bool uncertainFrequency(const GyroscopicMode& m, double frequencyTol, double zeroBelow) {
  const double size = std::abs(m.lambda);
  return size > zeroBelow && m.blockScale == 0.0 && !(m.eigenvalueError <= frequencyTol * size);
}

std::string accuracyNote(const std::vector<GyroscopicMode>& modes, double frequencyTol, const std::string& where) {
  int refined = 0, unshown = 0, worstMode = 0;
  double worstRefined = 0.0, worstUnshown = 0.0;
  for (std::size_t j = 0; j < modes.size(); ++j) {
    const GyroscopicMode& m = modes[j];
    const double size = std::abs(m.lambda);
    if (m.stability == Stability::RigidBody || m.blockScale > 0.0 || !(size > 0.0)) continue;
    const double error = m.reportedError() / size;
    if (m.refinedError > 0.0) ++refined, worstRefined = std::max(worstRefined, error);
    if (!(error <= frequencyTol)) {
      ++unshown;
      if (!(error <= worstUnshown)) worstUnshown = error, worstMode = static_cast<int>(j) + 1;
    }
  }
  std::ostringstream os;
  os.precision(2);
  if (refined > 0)
    os << "; " << refined << " mode(s) refined" << where << " by two-sided inverse iteration, each eigenvalue "
       << "within " << worstRefined << " of |lambda| (bound)";
  // Tolerance 0 asks for every mode refined, not for zero error: the
  // refined ones' bounds are said above.
  if (unshown > 0 && frequencyTol > 0.0)
    os << "; " << unshown << " mode(s) not shown within the Frequency Tolerance " << frequencyTol
       << " (worst: mode " << worstMode << ", " << worstUnshown << " of |lambda|)";
  return os.str();
}

cplx twoSidedRoot(cplx a, cplx b, cplx c, cplx near) {
  if (a == 0.0) return b == 0.0 ? cplx(std::nan(""), std::nan("")) : -c / b;
  // q = -(b + sign sqrt(b^2 - 4ac)) / 2 with the sign that adds magnitudes;
  // the roots are q / a and c / q.
  cplx root = std::sqrt(b * b - 4.0 * a * c);
  if (std::real(std::conj(b) * root) < 0.0) root = -root;
  const cplx q = -0.5 * (b + root);
  const cplx mu1 = q / a, mu2 = q != 0.0 ? c / q : mu1;
  return std::abs(mu1 - near) <= std::abs(mu2 - near) ? mu1 : mu2;
}

double twoSidedBound(cplx lambda, double change, double changeBefore, cplx a, cplx b, const FunctionalRounding& f) {
  const double eps = std::numeric_limits<double>::epsilon(), size = std::abs(lambda);
  const double weight[3] = {1.0, size, size * size};
  double sum = 0.0;
  for (int t = 0; t < 3; ++t) sum += weight[t] * (f.absolute[t] + f.n * f.product[t]);
  const double derivative = std::abs(2.0 * lambda * a + b);
  const double floor = derivative > 0.0 ? 2.0 * eps * sum / derivative : std::numeric_limits<double>::infinity();
  if (!(change > floor)) return floor;  // converged to what rounding leaves
  // Not yet: the error after geometric contraction by the last ratio r,
  // change r / (1 - r); none if the changes do not shrink.
  const double r = changeBefore > 0.0 ? change / changeBefore : std::numeric_limits<double>::infinity();
  return r < 1.0 ? std::max(floor, change * r / (1.0 - r)) : std::numeric_limits<double>::infinity();
}

bool TwoSidedEstimate::step(cplx a, cplx b, cplx c) { return step(a, b, c, lambda); }

bool TwoSidedEstimate::step(cplx a, cplx b, cplx c, cplx near) {
  const cplx next = twoSidedRoot(a, b, c, near);
  changeBefore = change, change = std::abs(next - lambda), lambda = next;
  return std::isfinite(lambda.real()) && std::isfinite(lambda.imag());
}

bool RefinementGate::offer(int step, const TwoSidedEstimate& e, double bound, double measure) {
  // The stall this gate is for: the stiff-support shaft spinning at 0.5
  // rad/s, its pair split by 1.9e-3 rad/s, its mean 78.146892 claimed within
  // the floor 8.3e-5 (a review), where the measure read 9.4e-4; on converged
  // steps the measure reads 0.05 of the floor. The drift: a pair's mean
  // moving 1.6e-6 rad/s a step, its measure below the floor too
  // (OPENBLAS_CORETYPE=Nehalem, one BLAS thread). Converged pairs 1e-5 to
  // 1e-4 |lambda| apart keep a leftover of the other member, damped 0.19-0.35
  // a step: their measure halves (a second review).
  const bool contracting = measure <= 0.5 * previousMeasure_;
  previousMeasure_ = measure;
  const double ratio = e.changeBefore > 0.0 ? e.change / e.changeBefore : 0.0;
  const bool drifting = step >= 2 && ratio >= 0.8 && ratio <= 1.25 && std::abs(e.lambda - twoBack_) > 1.5 * e.change;
  twoBack_ = oneBack_, oneBack_ = e.lambda;
  const double stands = drifting || step < 2 ? std::numeric_limits<double>::infinity()
                        : measure <= bound   ? bound
                        : contracting        ? measure
                                             : std::numeric_limits<double>::infinity();
  if (!(stands < best)) return false;
  best = stands, bestLambda = e.lambda;
  return true;
}

Stability classify(cplx lambda, double scale, double rigidBodyTol, double instabilityTol) {
  if (std::abs(lambda) <= rigidBodyTol * scale) return Stability::RigidBody;
  if (lambda.real() > instabilityTol * scale)
    return std::abs(lambda.imag()) <= instabilityTol * scale ? Stability::Divergence
                                                              : Stability::Flutter;
  return Stability::Stable;
}

void zeroRigidDamping(GyroscopicMode& m) {
  // A rigid motion's lambda is zero to rounding: -Re/|lambda| of that
  // rounding printed zeta = -1 or +1 (theory §13.3: 0 for lambda = 0).
  if (m.stability == Stability::RigidBody) m.dampingRatio = m.logDecrement = 0.0;
}

void setDamping(GyroscopicMode& m) {
  const double a = std::abs(m.lambda), re = m.lambda.real(), im = std::abs(m.lambda.imag());
  m.dampingRatio = a > 0.0 ? -re / a : 0.0;
  if (re == 0.0) m.logDecrement = 0.0;
  else if (im > 0.0) m.logDecrement = -2.0 * M_PI * re / im;
  else m.logDecrement = re < 0.0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
}

namespace {
/// m's split cluster: m and every other returned mode within r of m (or of a
/// mirror of m) whose shape is nearly parallel to m's (|q_m^H q_o|^2 >= 0.9
/// |q_m|^2 |q_o|^2: the values of one split defective eigenvalue all
/// approximate its single eigenvector), each eigenvalue taken with Im >= 0.
std::vector<std::complex<double>> splitCluster(const std::vector<GyroscopicMode>& modes, const GyroscopicMode& m,
                                               double r) {
  auto upper = [](std::complex<double> l) { return l.imag() < 0.0 ? std::conj(l) : l; };
  std::vector<std::complex<double>> members{upper(m.lambda)};
  for (const auto& o : modes) {
    if (&o == &m || o.q.size() != m.q.size()) continue;
    const double d = std::min({std::abs(o.lambda - m.lambda), std::abs(o.lambda + std::conj(m.lambda)),
                               std::abs(o.lambda - std::conj(m.lambda)), std::abs(o.lambda + m.lambda)});
    if (d > r) continue;
    std::complex<double> dot = 0.0;
    double mm = 0.0, oo = 0.0;
    for (std::size_t i = 0; i < m.q.size(); ++i)
      dot += std::conj(m.q[i]) * o.q[i], mm += std::norm(m.q[i]), oo += std::norm(o.q[i]);
    if (std::norm(dot) >= 0.9 * mm * oo) members.push_back(upper(o.lambda));
  }
  return members;
}

/// Is a split cluster centred within twice its spread of zero?
bool centredAtZero(const std::vector<std::complex<double>>& members) {
  std::complex<double> centre = 0.0;
  for (auto l : members) centre += l;
  centre /= static_cast<double>(members.size());
  double spread = 0.0;
  for (auto a : members)
    for (auto b : members) spread = std::max(spread, std::abs(a - b));
  return std::abs(centre) <= 2.0 * spread;
}
}  // namespace

void classifyModes(std::vector<GyroscopicMode>& modes, double scale, double rigidBodyTol,
                   double instabilityTol, bool conservative, bool completeShapes,
                   const std::vector<std::complex<double>>& unreturned) {
  if (!conservative) {
    // A damped (or circulatory) system: no Hamiltonian mirrors, so no
    // rounding argument keeps an eigenvalue on the axis. The verdict is the
    // sign of the growth rate beyond the instability tolerance (theory §13.3).
    for (auto& m : modes) {
      const double s = m.blockScale > 0.0 ? m.blockScale : m.scale > 0.0 ? std::min(m.scale, scale) : scale;
      // A mode solved apart: a zero its block's accuracy splits (a rigid
      // motion D does not damp is a double zero) by up to 10 sqrt(blockError)
      // of the block's scale is a zero, and a growth rate within that is
      // none (theory §4.3).
      const double split = m.blockScale > 0.0 && m.blockError > 0.0 ? 10.0 * std::sqrt(m.blockError) * s : 0.0;
      m.stability = std::abs(m.lambda) <= split
                        ? Stability::RigidBody
                        : classify(m.lambda, s, m.shownNonzero ? 0.0 : rigidBodyTol, instabilityTol);
      m.growthTolerance = std::max(m.growthTolerance, split);
      // A growth rate against the mode's own uncertainty where it was made
      // (completeDenseModes, measureRitzModes): beyond it, an instability;
      // positive, above the Instability Tolerance but within it, for a mode
      // the refinement takes (undecidedGrowth: it could not decide it),
      // Neutral, not "stable" (a stiff rotor's 0.241 1/s flutter read stable
      // within an uncertainty inflated by its stiff rows; theory §13.3). A
      // split cluster's member, not refined, stays "stable" as before (made
      // Neutral, a stable damped free body's frame-rate triple, rounding
      // growth 9e-6 on the sparse path, read UNDECIDED; a review). (Not for a
      // zero: see the conservative branch.)
      if (m.growthTolerance > 0.0 && m.stability != Stability::RigidBody)
        m.stability = m.lambda.real() > m.growthTolerance
                          ? (std::abs(m.lambda.imag()) <= m.growthTolerance ? Stability::Divergence : Stability::Flutter)
                      : undecidedGrowth(m, modes, instabilityTol, rigidBodyTol * s) ? Stability::Neutral
                                                                                      : Stability::Stable;
      m.undecided = m.stability == Stability::Neutral;
      zeroRigidDamping(m);
    }
    return;
  }
  const double eps = std::numeric_limits<double>::epsilon();
  // The spectrum of a conservative gyroscopic system is Hamiltonian: with
  // lambda, also -lambda, conj(lambda), -conj(lambda) (theory §4).
  std::vector<cplx> spectrum;
  for (const auto& m : modes)
    for (cplx l : {m.lambda, -m.lambda, std::conj(m.lambda), -std::conj(m.lambda)}) {
      bool known = false;
      for (cplx k : spectrum) known = known || std::abs(k - l) <= 4 * eps * std::max(scale, std::abs(l));
      if (!known) spectrum.push_back(l);
    }
  const double systemScale = scale;
  // A structure-preserving solve (the Meirovitch path: K > 0, every
  // eigenvalue exactly imaginary and semisimple) has no defective cluster
  // to split: only the first-order radius applies. Without this, the low
  // modes of a soft blade on a stiff hub (below 10 eps^(1/4) s) were taken
  // for a split defective zero and called rigid.
  const bool structured = std::all_of(modes.begin(), modes.end(), [](const GyroscopicMode& m) { return m.lambda.real() == 0.0; });
  for (auto& m : modes) {
    // A mode solved apart (the unrestrained block, theory §4.3) is judged on
    // that block's scale, to which it was resolved.
    const double scale = m.blockScale > 0.0 ? m.blockScale
                         : m.scale > 0.0    ? std::min(m.scale, systemScale)
                                            : systemScale;
    // A mode solved apart: its block's matrices hold to blockError, which
    // the residual against them does not see.
    const double eta = std::max({m.residual, eps, m.blockError});
    double radius = 0.0;  // the splitting rounding can cause around this eigenvalue
    int radiusOrder = 1;  // the multiplicity k that radius assumes
    // A defective eigenvalue of multiplicity k splits into k computed values,
    // up to 2k with their mirrors; more within r_k means r_k reaches other
    // eigenvalues, not a cluster of one. Except for k <= 2: r_2 = 10
    // sqrt(eta) s (1.5e-7 s) is closer than a normwise solver tells two
    // eigenvalues apart, and a defective pair can coalesce with simple
    // eigenvalues there (a free body's frame-rate triple: a pair and a simple
    // one at i Omega, five values with mirrors): up to 8 values (multiplicity
    // 4, the loop's cap) are one cluster. For k >= 3 the radius (6e-5 s,
    // 1.2e-3 s) reaches distinct eigenvalues, and the count must be k's own.
    for (int k = 1; k <= (structured ? 1 : 4); ++k) {
      const double r = 10.0 * std::pow(eta, 1.0 / k) * scale;
      const int most = k <= 2 ? 8 : 2 * k;
      int near = 0;
      for (cplx l : spectrum) near += std::abs(l - m.lambda) <= r;
      // The k >= 3 values of a split defective eigenvalue approximate one
      // eigenvector: their computed shapes are nearly parallel. Distinct
      // modes that merely fall within r_k of each other (a free body's
      // frame-rate triple at Omega and a stable mode at 1.5 Omega, with a
      // wheel's gyroscopic scale making r_4 ~ 1 rad/s) have independent
      // shapes and are not one split cluster: without this, which of them
      // were taken for a split zero (and called rigid) depended on how
      // rounding placed the mirrors, i.e. on the rank count (issue #11).
      if (near >= k && near <= most && (k <= 2 || !completeShapes || splitCluster(modes, m, r).size() > 1))
        radius = r, radiusOrder = k;
    }
    // Rigid through the radius only for a cluster that can be centred at
    // zero: a split defective eigenvalue of order k >= 3 spreads its values
    // around its centre, so a cluster whose centre lies further from zero
    // than its spread (a free body's frame-rate triple at i Omega, split by
    // 1e-4 Omega) is a cluster at that centre, not a split zero.
    const bool zeroCentred = radiusOrder <= 2 || !completeShapes || centredAtZero(splitCluster(modes, m, radius));
    m.splitRadius = radius;
    // A growing mode of a conservative system has a partner -conj(lambda)
    // (a real one, +/- sigma, is kept as +sigma alone). An eigenvalue near
    // the imaginary axis without one is simple and isolated, and Hamiltonian
    // symmetry keeps such an eigenvalue on the axis under any structured
    // perturbation: its growth rate is the unstructured solver's rounding.
    bool partner = std::abs(m.lambda.imag()) <= radius + instabilityTol * scale;
    // A defective eigenvalue of multiplicity k is split by about
    // eta^(1/k) s into k returned values, a semisimple one (the repeated
    // pair of a symmetric rotor) by eta s only: another returned value
    // further than 100 eta s but within 10 sqrt(eta) s (or two within
    // 10 eta^(1/3) s) is a split defective eigenvalue, whose growth rates (of
    // either sign, or none if the split happened along the axis) are
    // rounding. Its verdict is neutral whatever direction the split took,
    // which the summation order (the rank count) decides (issue #8 item 6).
    // Only for values off the axis: a structure-preserving solver (the
    // Meirovitch path, K > 0) returns exactly imaginary, semisimple ones.
    int near2 = 0, near3 = 0;  // other off-axis values within the k = 2 and k = 3 splittings
    std::vector<cplx> within3;  // those within the k = 3 splitting
    for (cplx o : unreturned) partner = partner || std::abs(o + std::conj(m.lambda)) <= 0.5 * std::abs(m.lambda.real());
    for (const auto& o : modes) {
      if (&o == &m) continue;
      partner = partner || std::abs(o.lambda + std::conj(m.lambda)) <= 0.5 * std::abs(m.lambda.real());
      const double d = std::abs(o.lambda - m.lambda);
      if (d <= 100.0 * eta * scale || std::abs(o.lambda.real()) + std::abs(m.lambda.real()) == 0.0) continue;
      near2 += d <= 10.0 * std::sqrt(eta) * scale;
      near3 += d <= 10.0 * std::cbrt(eta) * scale;
      if (d <= 10.0 * std::cbrt(eta) * scale) within3.push_back(o.lambda);
    }
    // Two within the k = 3 splitting count only where this value is one of
    // them, not an outsider: the k values of a split defective eigenvalue
    // lie about its centre at distances of one size, so one whose nearest
    // of them is more than 10 times their own spread away is a distinct
    // eigenvalue near the cluster. A free shaft's bending mode at 906.43
    // rad/s, 2.2 rad/s from the frame-rate triple at 908.6 (spread 3e-4),
    // lay inside 10 eta^(1/3) s at two ranks (2.43, eta 4.2e-16) and outside
    // it at one (2.11, eta 2.8e-16), and read neutral at one rank count only
    // (an AMD EPYC; the Campbell rank test,
    // free_shaft_campbell_same_tracks_at_1_and_2_ranks). (Tried first:
    // asking for a nearly parallel shape, as the radius above does; at two
    // ranks a frame-rate member's computed shape was parallel to the bending
    // mode's at other speeds, and the flip moved there.)
    double nearest3 = std::numeric_limits<double>::infinity(), spread3 = 0.0;
    for (std::size_t a = 0; a < within3.size(); ++a) {
      nearest3 = std::min(nearest3, std::abs(within3[a] - m.lambda));
      for (std::size_t b = a + 1; b < within3.size(); ++b) spread3 = std::max(spread3, std::abs(within3[a] - within3[b]));
    }
    const bool split = near2 >= 1 || (near3 >= 2 && nearest3 <= 10.0 * spread3);
    Stability s = classify(m.lambda, scale, m.shownNonzero ? 0.0 : rigidBodyTol, instabilityTol);
    // (Zeros stay judged on the system's scale, except those of the block
    // solved apart on its own (theory §4.3). Taking a value whose growth
    // exceeded ten times its first-order error bound for no zero made a
    // free body's defective rigid zero, computed at 4e-8 with a residual
    // of 1e-16, a DIVERGENCE on two ranks: that bound fails at a Jordan
    // block.)
    if (std::abs(m.lambda) <= radius && zeroCentred && !m.shownNonzero) s = Stability::RigidBody;
    else if (!partner && (s == Stability::Divergence || s == Stability::Flutter || m.lambda.real() > 0.0))
      s = Stability::Stable;
    else if ((s == Stability::Divergence || s == Stability::Flutter) && m.lambda.real() <= radius)
      s = Stability::Neutral;
    // A growth rate of either sign above plain rounding (10 eta s, the
    // first-order error of a simple eigenvalue) but inside the cluster
    // radius, with a partner, cannot be decided either way: neutral, not
    // "stable". A simple, isolated eigenvalue of either sign of growth is
    // stable (Hamiltonian symmetry, above).
    else if (s == Stability::Stable && partner && std::abs(m.lambda.real()) > 10.0 * eta * scale &&
             std::abs(m.lambda.real()) <= radius)
      s = Stability::Neutral;
    if (s == Stability::Stable && split) s = Stability::Neutral;
    // A growth rate beyond the mode's own uncertainty (its residual's
    // first-order error, a near-defective split on its own scale) is an
    // instability whatever the system's scale: a Krein collision's split
    // pair has q^H Q' q -> 0 there, and its bound no such certainty.
    // (Not for a zero of a block solved apart: its radius above is what the
    // block's accuracy can do to it.)
    if (s != Stability::RigidBody && m.blockError == 0.0 && m.growthTolerance > 0.0 &&
        m.lambda.real() > m.growthTolerance)
      s = std::abs(m.lambda.imag()) <= m.growthTolerance ? Stability::Divergence : Stability::Flutter;
    m.stability = s;
    m.undecided = false;
    zeroRigidDamping(m);
  }
}

namespace {
/// Each mode's residual, energies, scales, eigenvalue error and growth
/// uncertainty from (lambda, q), q normalised to q^H M q = 1 (the body of
/// completeDenseModes, run again on refined modes). Returns the system's
/// frequency scale.
double measureModes(const GyroscopicSystem& sys, std::vector<GyroscopicMode>& modes, double instabilityTol,
                    bool ownScales, const std::vector<cplx>& unreturned) {
  const int n = sys.size(), k = static_cast<int>(modes.size());
  if (k == 0) return 1.0;
  // A damped system's residual is that of lambda^2 M + lambda (G + D) + K + N:
  // G and K below stand for G + D and K + N, their norms for the sums of
  // the parts' norms.
  const bool damped = sys.damped();
  const bool hasD = sys.D.numRows() == n, hasN = sys.N.numRows() == n;
  DenseMatrix Ge(sys.G), Ke(sys.K);
  if (hasD) Ge += sys.D;
  if (hasN) Ke += sys.N;
  const double nM = frobeniusNorm(sys.M),
               nG = frobeniusNorm(sys.G) + (hasD ? frobeniusNorm(sys.D) : 0.0),
               nK = frobeniusNorm(sys.K) + (hasN ? frobeniusNorm(sys.N) : 0.0);
  const double scale = frequencyScale(nM, nG, nK);
  // Products with the real and imaginary parts of all modes at once (BLAS-3):
  // Q = [Re q_1 .. Re q_k, Im q_1 .. Im q_k].
  DenseMatrix Q(n, 2 * k);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < n; ++i) {
      Q(i, j) = modes[j].q[i].real();
      Q(i, k + j) = modes[j].q[i].imag();
    }
  DenseMatrix MQ, GQ, KQ;
  gemm(false, false, 1.0, sys.M, Q, 0.0, MQ);
  gemm(false, false, 1.0, Ge, Q, 0.0, GQ);
  gemm(false, false, 1.0, Ke, Q, 0.0, KQ);
  // |K| |q| and |G| |q| for the modes' own scales (GyroscopicMode::scale).
  // |q_i| as sqrt(norm): std::abs's hypot guards against squares
  // overflowing, which needs entries beyond 1e154 that no computed shape
  // has, and took 4% of a sweep's speed.
  DenseMatrix absK(n, n), absG(n, n), Qa(n, k), KQa, GQa, MQa;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) absK(i, j) = std::abs(Ke(i, j)), absG(i, j) = std::abs(Ge(i, j));
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < n; ++i) Qa(i, j) = std::sqrt(std::norm(modes[j].q[i]));
  gemm(false, false, 1.0, absK, Qa, 0.0, KQa);
  gemm(false, false, 1.0, absG, Qa, 0.0, GQa);
  // The growth rates' own uncertainties (GyroscopicMode::growthTolerance)
  // where a growth rate is computed at all: the general path's, or a
  // damped one's (the Meirovitch path's eigenvalues are exactly imaginary).
  const bool growth = damped || !ownScales;
  if (growth) {  // |M| |q| for the componentwise backward error below
    DenseMatrix absM(n, n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) absM(i, j) = std::abs(sys.M(i, j));
    gemm(false, false, 1.0, absM, Qa, 0.0, MQa);
  }
  for (int j = 0; j < k; ++j) {
    GyroscopicMode& m = modes[j];
    const cplx l = m.lambda, l2 = l * l;
    double qMq = 0.0, qKq = 0.0, qq = 0.0, rr = 0.0, ss = 0.0;
    cplx qGq = 0.0;
    std::size_t imax = 0;
    for (int i = 0; i < n; ++i) {
      const cplx q = m.q[i];
      const cplx Mq(MQ(i, j), MQ(i, k + j)), Gq(GQ(i, j), GQ(i, k + j)), Kq(KQ(i, j), KQ(i, k + j));
      qMq += std::real(std::conj(q) * Mq);
      qKq += std::real(std::conj(q) * Kq);  // with N: its Hermitian part only (N skew adds i Im)
      qGq += std::conj(q) * Gq;
      qq += std::norm(q);
      rr += std::norm(l2 * Mq + l * Gq + Kq);
      if (growth) ss += std::pow(KQa(i, j) + std::abs(l) * GQa(i, j) + std::norm(l) * MQa(i, j), 2);
      if (Qa(i, j) > Qa(imax, j)) imax = i;
    }
    const double denom = (nK + std::abs(l) * nG + std::norm(l) * nM) * std::sqrt(qq);
    m.residual = denom > 0.0 ? std::sqrt(rr) / denom : std::sqrt(rr);
    // Normalise q^H M q = 1 with the largest entry real positive.
    const cplx phase = std::abs(m.q[imax]) > 0 ? std::conj(m.q[imax]) / std::abs(m.q[imax]) : 1.0;
    const double s = qMq > 0.0 ? 1.0 / std::sqrt(qMq) : 1.0;
    for (auto& q : m.q) q *= phase * s;
    m.kineticEnergy = 0.5 * std::norm(l);
    m.strainEnergy = 0.5 * qKq * s * s;
    m.growthRate = l.real();
    m.omega = std::abs(l.imag());
    m.hz = m.omega / kTwoPi;
    setDamping(m);
    double aKa = 0.0, aGa = 0.0;
    for (int i = 0; i < n; ++i) aKa += Qa(i, j) * KQa(i, j), aGa += Qa(i, j) * GQa(i, j);
    const double own = qMq > 0.0 ? std::sqrt(aKa / qMq) + aGa / qMq : 0.0;
    m.scale = ownScales ? own : 0.0;
    const double derivative = std::abs(2.0 * l * qMq + qGq);
    m.eigenvalueError = derivative > 0.0 ? std::sqrt(rr) * std::sqrt(qq) / derivative
                                         : std::numeric_limits<double>::infinity();
    if (growth && own > 0.0) {
      // The growth rate's uncertainty from this mode's own residual, not
      // from the system's scale: that scale holds ||D|| / ||M||, Rayleigh's
      // beta omega_max^2, and the stiffest element's frequency, both growing
      // with the mesh, and dggev's modes were judged on it: a Jeffcott
      // rotor's internal-damping instability (growth 0.241 1/s, the closed
      // form's 0.242) read "stable", and the speed where instability starts
      // moved from 79 to 147 rad/s between 4 and 40 elements against 78.3
      // (found by a review); a free body's intermediate-axis divergence the
      // same (below). First-order
      // perturbation: the eigenvalue of a computed pair lies within about
      // ||r|| ||q|| / |q^H Q'(lambda) q| (ten times that, for the left
      // vector's departure from the right), a near-defective pair is split
      // by about 10 sqrt(eta_q) |lambda| (eta_q its componentwise backward
      // error: relative perturbations of the coefficients at lambda), and
      // below instabilityTol |lambda| a growth rate is the tolerance's own
      // (theory §13.3; growthUncertainty). (Its componentwise scale s_q is
      // no measure here: a beam's |q|^T |K| |q| cancels nothing and grows
      // with the mesh too.)
      const double etaQ = ss > 0.0 ? std::sqrt(rr / ss) : 1.0;
      std::vector<cplx> others(unreturned);
      for (int o = 0; o < k; ++o)
        if (o != j) others.push_back(modes[o].lambda);
      const double bound = m.refinedError > 0.0 ? m.refinedError : 10.0 * std::min(m.eigenvalueError, own);
      m.growthTolerance = growthUncertainty(l, bound, etaQ, instabilityTol, others, !damped);
    }
  }
  return scale;
}

/// The projected two-sided problem of a cluster of p eigenvalues
/// (refineModes): w^H (mu^2 A2 + mu A1 + A0) z = 0 with A_k = Y^H (M, G + D,
/// K + N) X, p x p, column-major, solved by LAPACK zggev on its 2p companion
/// pencil [[0, I], [-A0, -A1]] v = mu [[I, 0], [0, A2]] v: a right vector's
/// top half is z, a left vector's bottom half w (u^H L(mu) = 0 gives
/// u_2^H (mu^2 A2 + mu A1 + A0) = 0). Returns false where zggev fails or
/// meets an infinite eigenvalue.
bool projectedQuadratic(int p, const std::vector<cplx>& A0, const std::vector<cplx>& A1, const std::vector<cplx>& A2,
                        std::vector<cplx>& mu, std::vector<cplx>& Z, std::vector<cplx>& W) {
  const int P = 2 * p;
  std::vector<cplx> L(static_cast<std::size_t>(P) * P, 0.0), B(L), VL(L), VR(L), alpha(P), beta(P);
  for (int i = 0; i < p; ++i) L[i + static_cast<std::size_t>(p + i) * P] = 1.0, B[i + static_cast<std::size_t>(i) * P] = 1.0;
  for (int j = 0; j < p; ++j)
    for (int i = 0; i < p; ++i) {
      const std::size_t ij = i + static_cast<std::size_t>(j) * p;
      L[(p + i) + static_cast<std::size_t>(j) * P] = -A0[ij];
      L[(p + i) + static_cast<std::size_t>(p + j) * P] = -A1[ij];
      B[(p + i) + static_cast<std::size_t>(p + j) * P] = A2[ij];
    }
  std::vector<double> rwork(8 * P);
  cplx wq;
  int info = 0, lwork = -1;
  zggev_("V", "V", &P, L.data(), &P, B.data(), &P, alpha.data(), beta.data(), VL.data(), &P, VR.data(), &P, &wq, &lwork,
         rwork.data(), &info, 1, 1);
  lwork = std::max(1, static_cast<int>(wq.real()));
  std::vector<cplx> work(lwork);
  zggev_("V", "V", &P, L.data(), &P, B.data(), &P, alpha.data(), beta.data(), VL.data(), &P, VR.data(), &P, work.data(),
         &lwork, rwork.data(), &info, 1, 1);
  if (info != 0) return false;
  mu.assign(P, 0.0), Z.assign(static_cast<std::size_t>(p) * P, 0.0), W.assign(static_cast<std::size_t>(p) * P, 0.0);
  for (int k = 0; k < P; ++k) {
    if (beta[k] == 0.0) return false;
    mu[k] = alpha[k] / beta[k];
    for (int i = 0; i < p; ++i) {
      Z[i + static_cast<std::size_t>(k) * p] = VR[i + static_cast<std::size_t>(k) * P];
      W[i + static_cast<std::size_t>(k) * p] = VL[(p + i) + static_cast<std::size_t>(k) * P];
    }
  }
  return true;
}

/// Removes from the n entries of v their parts along the orthonormal
/// `basis` (modified Gram-Schmidt, twice); returns v's squared norm before
/// and after (orthonormalise, undoRepeatedRefinements).
std::pair<double, double> projectOut(cplx* v, int n, const std::vector<const cplx*>& basis) {
  double norm = 0.0, rest = 0.0;
  for (int i = 0; i < n; ++i) norm += std::norm(v[i]);
  for (int pass = 0; pass < 2; ++pass)
    for (const cplx* b : basis) {
      cplx d = 0.0;
      for (int i = 0; i < n; ++i) d += std::conj(b[i]) * v[i];
      for (int i = 0; i < n; ++i) v[i] -= d * b[i];
    }
  for (int i = 0; i < n; ++i) rest += std::norm(v[i]);
  return {norm, rest};
}

/// Orthonormalises the p columns of the n x p `X` (modified Gram-Schmidt,
/// twice). Returns false where a column is lost (its norm after projection
/// below 1e-12 of its own: the block has collapsed onto fewer directions).
bool orthonormalise(int n, int p, std::vector<cplx>& X) {
  std::vector<const cplx*> before;
  for (int j = 0; j < p; ++j) {
    cplx* x = X.data() + static_cast<std::size_t>(j) * n;
    const auto [norm, rest] = projectOut(x, n, before);
    if (!(rest > 1e-24 * norm) || !std::isfinite(rest)) return false;
    const double s = 1.0 / std::sqrt(rest);
    for (int i = 0; i < n; ++i) x[i] *= s;
    before.push_back(x);
  }
  return true;
}

/// The span of shapes kept (undoRepeatedRefinements, repeatsAShapeHeld):
/// an orthonormal basis grown by projectOut.
struct ShapeSpan {
  std::vector<std::vector<cplx>> basis;
  /// v's squared norm, and that of its part orthogonal to the span (v is
  /// left holding that part).
  std::pair<double, double> project(std::vector<cplx>& v) const {
    std::vector<const cplx*> b;
    for (const auto& u : basis) b.push_back(u.data());
    return projectOut(v.data(), static_cast<int>(v.size()), b);
  }
  /// Adds q's direction where its orthogonal part exceeds `minRest` of its
  /// squared norm; returns whether it did.
  bool add(std::vector<cplx> q, double minRest) {
    const auto [norm, rest] = project(q);
    if (!(rest > minRest * norm)) return false;
    for (auto& c : q) c /= std::sqrt(rest);
    basis.push_back(std::move(q));
    return true;
  }
  /// Whether q lies within the span: its orthogonal part at most 0.09 of its
  /// squared norm (0.3 of its norm, an angle of 17 degrees).
  bool holds(std::vector<cplx> q) const {
    const auto [norm, rest] = project(q);
    return !(rest > 0.09 * norm);
  }
};

/// A refined mode given back the value and shape the solve returned, and
/// with them its first-order error (refinedError 0).
void restoreSolved(GyroscopicMode& m, const GyroscopicMode& solved) {
  m.lambda = solved.lambda, m.q = solved.q, m.refinedError = 0.0;
}

/// Whether a mode is a candidate for refineModes, and what it needs: its
/// growth undecided (undecidedGrowth; with `decays`, a circulatory N,
/// undecidedDecay too), or its frequency not shown within `frequencyTol`
/// |lambda| by its first-order error (uncertainFrequency).
bool needsRefinement(const GyroscopicMode& m, const std::vector<GyroscopicMode>& modes, double instabilityTol,
                     double zeroBelow, bool decays, double frequencyTol) {
  return undecidedGrowth(m, modes, instabilityTol, zeroBelow) ||
         (decays && undecidedDecay(m, modes, instabilityTol, zeroBelow)) ||
         uncertainFrequency(m, frequencyTol, zeroBelow);
}

/// Whether mode j's shape lies within the span of the shapes of the other
/// modes whose values are within its reported error and theirs (the part
/// orthogonal to them below 0.3 of its norm, as undoRepeatedRefinements):
/// a refinement that found an eigenvalue the list holds already. A rod arm
/// 1e16 times stiffer than its post: dggev's values 562 and 1528 (real,
/// taken for zeros) refined onto the rigid-arm pair at 45.6672 that it
/// listed, which was printed four times (completeModes' zero shown nonzero).
bool repeatsAShapeHeld(const std::vector<GyroscopicMode>& modes, std::size_t j) {
  const GyroscopicMode& m = modes[j];
  ShapeSpan span;
  for (std::size_t o = 0; o < modes.size(); ++o)
    if (o != j && modes[o].q.size() == m.q.size() &&
        std::abs(modes[o].lambda - m.lambda) <= m.reportedError() + modes[o].reportedError())
      span.add(modes[o].q, 1e-24);
  return !span.basis.empty() && span.holds(m.q);
}

/// A shape's componentwise frequency scale, rad/s: sqrt(|q|^T |K + N| |q| /
/// q^H M q) + |q|^T |G + D| |q| / q^H M q, what rounding of the entries the
/// shape loads can do to its eigenvalue (GyroscopicMode::scale; completeModes'
/// zero shown nonzero).
double componentScale(const GyroscopicSystem& sys, const std::vector<cplx>& q) {
  const int n = sys.size();
  const bool hasD = sys.D.numRows() == n, hasN = sys.N.numRows() == n;
  double aK = 0.0, aC = 0.0, qMq = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double a = std::abs(q[i]) * std::abs(q[j]);
      aK += std::abs(sys.K(i, j) + (hasN ? sys.N(i, j) : 0.0)) * a;
      aC += std::abs(sys.G(i, j) + (hasD ? sys.D(i, j) : 0.0)) * a;
      qMq += std::real(std::conj(q[i]) * sys.M(i, j) * q[j]);
    }
  return qMq > 0.0 ? std::sqrt(aK / qMq) + aC / qMq : std::numeric_limits<double>::infinity();
}

/// How far rounding of the matrices' entries can move the refined value
/// lambda (right vector x, left y) of the computed system, to first order:
/// a perturbation dQ moves it by y^H dQ(lambda) x / y^H Q'(lambda) x, and
/// with |dK| <= kappa eps sys.KMagnitude (the magnitudes of K's parts,
/// which hold its cancellation at a critical speed) and the other matrices'
/// entries rounded to kappa eps of their own magnitudes, at most
///   kappa eps |y|^T (R + |N| + |lambda| (|G| + |D|) + |lambda|^2 |M|) |x| / |y^H Q'(lambda) x|.
/// kappa = 64: an assembled entry is a sum of element contributions of
/// some ten operations each (10 eps of its magnitude), the sum of K's parts
/// adds two, and near a double root (a critical speed's Jordan block) the
/// first-order move understates by two the perturbation that reaches zero;
/// the rest is margin. Infinite where sys.KMagnitude is not given or Q'
/// vanishes (completeModes' zero shown nonzero; theory §4.3).
double roundingReach(const GyroscopicSystem& sys, cplx lambda, const std::vector<cplx>& x,
                     const std::vector<cplx>& y) {
  const int n = sys.size();
  if (sys.KMagnitude.numRows() != n || static_cast<int>(x.size()) != n || static_cast<int>(y.size()) != n)
    return std::numeric_limits<double>::infinity();
  const bool hasD = sys.D.numRows() == n, hasN = sys.N.numRows() == n;
  const double l = std::abs(lambda);
  double reach = 0.0;
  cplx slope = 0.0;  // y^H Q'(lambda) x, Q'(lambda) = 2 lambda M + G + D
  for (int j = 0; j < n; ++j) {
    const double ax = std::abs(x[j]);
    for (int i = 0; i < n; ++i) {
      const double c = hasD ? sys.D(i, j) : 0.0;
      reach += std::abs(y[i]) * ax *
               (sys.KMagnitude(i, j) + (hasN ? std::abs(sys.N(i, j)) : 0.0) +
                l * (std::abs(sys.G(i, j)) + std::abs(c)) + l * l * std::abs(sys.M(i, j)));
      slope += std::conj(y[i]) * (2.0 * lambda * sys.M(i, j) + sys.G(i, j) + c) * x[j];
    }
  }
  constexpr double kappa = 64.0;
  const double move = kappa * std::numeric_limits<double>::epsilon() * reach;
  return std::abs(slope) > 0.0 ? move / std::abs(slope) : std::numeric_limits<double>::infinity();
}

/// One cluster of refineModes, `members` (indices into `modes`), refined as
/// one block. Returns whether any member changed. With `left` and one
/// member, the left vector of the value kept (y^H Q(lambda) = 0; empty
/// where dggev's value stands).
bool refineCluster(const GyroscopicSystem& sys, std::vector<GyroscopicMode>& modes, const std::vector<int>& members,
                   std::vector<cplx>* left = nullptr) {
  const int n = sys.size(), p = static_cast<int>(members.size());
  const std::size_t N = static_cast<std::size_t>(n);
  const bool hasD = sys.D.numRows() == n, hasN = sys.N.numRows() == n;
  const auto C = [&](int i, int j) { return sys.G(i, j) + (hasD ? sys.D(i, j) : 0.0); };
  const auto Kt = [&](int i, int j) { return sys.K(i, j) + (hasN ? sys.N(i, j) : 0.0); };
  double size = 0.0;
  cplx centre = 0.0;
  for (int j : members) size = std::max(size, std::abs(modes[j].lambda)), centre += modes[j].lambda / double(p);
  // Q(sigma), factored at sigma. An exactly singular one (sigma an
  // eigenvalue to the last bit) is moved by 1e-10 |sigma|: inverse
  // iteration needs only a near-singular matrix.
  std::vector<cplx> A(N * N);
  std::vector<int> piv(n);
  cplx sigma;
  int info = 1;
  const auto factor = [&](cplx at) {
    sigma = at, info = 1;
    for (int attempt = 0; attempt < 2 && info > 0; ++attempt) {
      if (attempt == 1) sigma += 1e-10 * size;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) A[i + j * N] = sigma * sigma * sys.M(i, j) + sigma * C(i, j) + Kt(i, j);
      zgetrf_(&n, &n, A.data(), &n, piv.data(), &info);
    }
    return info == 0;
  };
  if (!factor(centre)) return false;
  // X (right) and Y (left), n x p, from the modes' shapes.
  std::vector<cplx> X(N * p), Y, RX(N * p), RY(N * p), KX, CX, MX;
  for (int t = 0; t < p; ++t) std::copy(modes[members[t]].q.begin(), modes[members[t]].q.end(), X.begin() + t * N);
  Y = X;
  std::vector<TwoSidedEstimate> e(p);
  for (int t = 0; t < p; ++t) e[t].lambda = modes[members[t]].lambda;
  struct Kept {
    double best = std::numeric_limits<double>::infinity();
    cplx lambda;
    std::vector<cplx> x, y;
  };
  std::vector<Kept> kept(p);
  std::vector<std::vector<cplx>> bestX(p), bestY(p);
  std::vector<cplx> x(n), y(n), Kx(n), Cx(n), Mx(n);
  // Eight steps, the least standing bound kept (RefinementGate): with
  // three and the last kept, the stiff-support shaft spinning at 0.5 rad/s
  // (its pair split by 1.9e-3 rad/s) came out at 78.146850 with a bound of
  // 8.4e-5, 8.6e-4 from either member (two BLAS threads), the stall the
  // sparse refinement had (theory §5, "Stiff rows").
  std::vector<std::vector<cplx>> lastX(p);
  for (int shift = 0; shift < (p == 1 ? 2 : 1); ++shift) {
    if (shift == 1) {
      // Again, factored at the values reached, where a member has no
      // standing step and they have moved from the shift (a shift 0.44
      // rad/s from a pair split by 0.02 converged by 0.96 a step: the
      // same shaft at 5.6 rad/s, 50 elements, refined one by one).
      if (std::all_of(kept.begin(), kept.end(), [](const Kept& s) { return std::isfinite(s.best); })) break;
      cplx reached = 0.0;
      double change = 0.0;
      for (const auto& s : e) reached += s.lambda / double(p), change = std::max(change, s.change);
      if (!(std::abs(reached - sigma) > change) || !factor(reached)) break;
    }
    std::vector<RefinementGate> gate;
    for (const auto& s : e) gate.emplace_back(s.lambda);
    bool ok = true;
    for (int step = 0; step < 8 && ok; ++step) {
      // X <- Q(sigma)^-1 Q'(sigma) X and Y <- Q(sigma)^-H Q'(sigma)^H Y,
      // Q'(sigma) = 2 sigma M + G + D (its transpose has D - G),
      // orthonormalised.
      std::fill(RX.begin(), RX.end(), 0.0), std::fill(RY.begin(), RY.end(), 0.0);
      for (int t = 0; t < p; ++t)
        for (int j = 0; j < n; ++j) {
          const cplx xj = X[j + t * N], yj = Y[j + t * N];
          for (int i = 0; i < n; ++i) {
            RX[i + t * N] += (2.0 * sigma * sys.M(i, j) + C(i, j)) * xj;
            RY[i + t * N] += (2.0 * std::conj(sigma) * sys.M(i, j) + C(j, i)) * yj;
          }
        }
      zgetrs_("N", &n, &p, A.data(), &n, piv.data(), RX.data(), &n, &info, 1);
      if (info == 0) zgetrs_("C", &n, &p, A.data(), &n, piv.data(), RY.data(), &n, &info, 1);
      if (info != 0 || !orthonormalise(n, p, RX) || !orthonormalise(n, p, RY)) break;
      X.swap(RX), Y.swap(RY);
      // Each member's vectors: for p = 1 the block's; else the projected
      // problem's, each member taking the Ritz value nearest its own.
      std::vector<cplx> mu, Z, W;
      std::vector<int> pick(p, -1);
      if (p > 1) {
        KX.assign(N * p, 0.0), CX.assign(N * p, 0.0), MX.assign(N * p, 0.0);
        for (int t = 0; t < p; ++t)
          for (int j = 0; j < n; ++j) {
            const cplx xj = X[j + t * N];
            for (int i = 0; i < n; ++i)
              KX[i + t * N] += Kt(i, j) * xj, CX[i + t * N] += C(i, j) * xj, MX[i + t * N] += sys.M(i, j) * xj;
          }
        std::vector<cplx> A0(p * p, 0.0), A1(A0), A2(A0);
        for (int s = 0; s < p; ++s)
          for (int r = 0; r < p; ++r)
            for (int i = 0; i < n; ++i) {
              const cplx yr = std::conj(Y[i + r * N]);
              A0[r + s * p] += yr * KX[i + s * N], A1[r + s * p] += yr * CX[i + s * N], A2[r + s * p] += yr * MX[i + s * N];
            }
        if (!projectedQuadratic(p, A0, A1, A2, mu, Z, W)) break;
        std::vector<char> used(mu.size(), 0);
        for (int round = 0; round < p; ++round) {  // greedy: the nearest (member, value) pair first
          int bt = -1, bk = -1;
          double bd = std::numeric_limits<double>::infinity();
          for (int t = 0; t < p; ++t)
            for (int kk = 0; kk < 2 * p && pick[t] < 0; ++kk)
              if (!used[kk] && std::abs(mu[kk] - e[t].lambda) < bd) bd = std::abs(mu[kk] - e[t].lambda), bt = t, bk = kk;
          if (bt < 0) break;
          pick[bt] = bk, used[bk] = 1;
        }
      }
      for (int t = 0; t < p && ok; ++t) {
        if (p == 1) {
          std::copy(X.begin(), X.begin() + n, x.begin()), std::copy(Y.begin(), Y.begin() + n, y.begin());
        } else {
          if (pick[t] < 0) { ok = false; break; }
          double nx = 0.0, ny = 0.0;
          for (int i = 0; i < n; ++i) {
            x[i] = y[i] = 0.0;
            for (int s = 0; s < p; ++s)
              x[i] += X[i + s * N] * Z[s + pick[t] * p], y[i] += Y[i + s * N] * W[s + pick[t] * p];
            nx += std::norm(x[i]), ny += std::norm(y[i]);
          }
          if (!(nx > 0.0) || !(ny > 0.0) || !std::isfinite(nx) || !std::isfinite(ny)) { ok = false; break; }
          for (int i = 0; i < n; ++i) x[i] /= std::sqrt(nx), y[i] /= std::sqrt(ny);
        }
        cplx a = 0.0, b = 0.0, c = 0.0;
        FunctionalRounding rounding;
        rounding.n = n;
        for (int i = 0; i < n; ++i) {
          Kx[i] = Cx[i] = Mx[i] = 0.0;
          double aK = 0.0, aC = 0.0, aM = 0.0;
          int nK = 0, nC = 0, nM = 0;  // the row's nonzeros: a zero entry adds no rounding
          for (int j = 0; j < n; ++j) {
            const double k = Kt(i, j), g = C(i, j), mm = sys.M(i, j), ax = std::abs(x[j]);
            Kx[i] += k * x[j], Cx[i] += g * x[j], Mx[i] += mm * x[j];
            aK += std::abs(k) * ax, aC += std::abs(g) * ax, aM += std::abs(mm) * ax;
            nK += k != 0.0, nC += g != 0.0, nM += mm != 0.0;
          }
          const cplx yi = std::conj(y[i]);
          const double ay = std::abs(y[i]);
          c += yi * Kx[i], b += yi * Cx[i], a += yi * Mx[i];
          rounding.absolute[0] += nK * ay * aK, rounding.absolute[1] += nC * ay * aC, rounding.absolute[2] += nM * ay * aM;
          rounding.product[0] += ay * std::abs(Kx[i]), rounding.product[1] += ay * std::abs(Cx[i]),
              rounding.product[2] += ay * std::abs(Mx[i]);
        }
        // The root of y^H Q(mu) x = 0: for a member of a block, the Ritz
        // value it took (a root of its functional by construction).
        ok = p == 1 ? e[t].step(a, b, c) : e[t].step(a, b, c, mu[pick[t]]);
        if (!ok) break;
        // sum_i |y_i| |(Q(lambda) x)_i| / |y^H Q'(lambda) x| at the new lambda.
        double weighted = 0.0;
        for (int i = 0; i < n; ++i)
          weighted += std::abs(y[i]) * std::abs(Kx[i] + e[t].lambda * (Cx[i] + e[t].lambda * Mx[i]));
        const double bound = twoSidedBound(e[t].lambda, e[t].change, e[t].changeBefore, a, b, rounding);
        lastX[t] = x;
        if (gate[t].offer(step, e[t], bound, weighted / std::abs(2.0 * e[t].lambda * a + b))) bestX[t] = x, bestY[t] = y;
      }
    }
    for (int t = 0; t < p; ++t)
      if (gate[t].best < kept[t].best) kept[t] = {gate[t].best, gate[t].bestLambda, bestX[t], bestY[t]};
  }
  // A block member no step of which stands is finished alone, from its
  // Ritz value and vector, with Q factored there: the block separates the
  // members (its Ritz values converge at once), but its Ritz vectors, sums
  // of the block's columns, leave a weighted residual a little above the
  // functional's bound (the stiff-support shaft's pair at 182 rad/s: 6.1e-6
  // against 5.6e-6, step after step, where one vector refined alone reads
  // 1.2e-7), so RefinementGate let none stand and the pair stayed with
  // dggev's first-order error (its flutter UNDECIDED). From the Ritz value,
  // 1e-9 from the member and 0.7 from the other, the vector converges alone.
  bool any = false;
  if (p > 1)
    for (int t = 0; t < p; ++t) {
      if (std::isfinite(kept[t].best)) continue;
      GyroscopicMode& m = modes[members[t]];
      const cplx lambda = m.lambda;
      std::vector<cplx> q = m.q;
      // From where the block stopped; or, where the block broke down before
      // a step (a column lost: overdamped partners of D = alpha M share one
      // shape, a review), from dggev's value and shape.
      if (!lastX[t].empty()) m.lambda = e[t].lambda, m.q = lastX[t];
      if (refineCluster(sys, modes, {members[t]})) any = true;
      else m.lambda = lambda, m.q = std::move(q);
    }
  // Kept only where it decides more than the computed value's own
  // uncertainty did (its growth's, or its first-order error): else the
  // refinement did not help, and dggev's value and shape stay (a review
  // found refined values kept that were worse).
  for (int t = 0; t < p; ++t) {
    GyroscopicMode& m = modes[members[t]];
    if (!std::isfinite(kept[t].best)) continue;  // finished alone above, or left as it was
    if (!(kept[t].best < std::max(m.growthTolerance, m.eigenvalueError))) continue;
    m.lambda = kept[t].lambda, m.q = kept[t].x, m.refinedError = kept[t].best;
    if (left && p == 1) *left = kept[t].y;
    // A mode is the member of its conjugate pair with Im >= 0 (generalModes):
    // a real value refined into a complex one can land on either member.
    if (m.lambda.imag() < 0.0) {
      m.lambda = std::conj(m.lambda);
      for (auto& c : m.q) c = std::conj(c);
      if (left && p == 1)
        for (auto& c : *left) c = std::conj(c);
    }
    any = true;
  }
  return any;
}
/// Refinements that found an eigenvalue another refined mode holds, undone
/// (refineModes): near critical damping (one shaft on a support of E = 1e18,
/// D = 156.2 M) dggev returned one member of a double pair at -78.1 + 2.708 i
/// and the other split onto the real axis, -61.97 and -94.23 (first-order
/// errors 8.3: too far apart to be one cluster); refined alone, both real
/// values converged to -78.1 + 2.708 i, and the pair was printed three
/// times, each with a "refined bound" of 3.2e-5, one true mode pushed off
/// the list (a review). Values are not enough (a double pair's members are
/// equal: a guard on values alone broke the isotropic shaft's true pairs),
/// but shapes are: the refined modes whose values lie within each other's
/// bounds are taken by refinement unit (`unit`: a block, or a mode refined
/// alone), the unit that moved least first, and a mode whose shape lies
/// within the span of the units before (the part orthogonal to them below
/// 0.3 of its norm, an angle of 17 degrees) repeats an eigenvector already
/// held: it gets back dggev's value and shape, and with them its
/// first-order error (the reason counts it as not shown). Within one block
/// the values are the projected problem's, multiplicities included, and
/// stand (its Ritz vectors of a multiple value can be nearly parallel:
/// compared mode by mode, four shafts' sixfold value was undone).
///
/// A real value dggev returned that refined into a complex one already held
/// (`converted` below) is half of a conjugate pair rounding split onto the
/// real axis, and the pair is one mode (the member with Im > 0): undone,
/// the half stayed in the list at -61.97, no eigenvalue, "not shown", and
/// pushed the tenth mode off. It is refined again alone, from dggev's value
/// and shape, and where that lands on a value and shape any mode of the list
/// holds (repeatsAShapeHeld) it is dropped: returns the indices to drop
/// (theory §5, "A pair split onto the real axis"). Elsewhere (a genuine real
/// eigenvalue a block carried onto its neighbour stays off every held value
/// from its own), and always without `dropHalves` (the sparse path's
/// projection, which is not refined again), it keeps dggev's value and
/// first-order error.
std::vector<int> undoRepeatedRefinements(const GyroscopicSystem& sys, std::vector<GyroscopicMode>& modes,
                                         const std::vector<GyroscopicMode>& before, const std::vector<int>& unit,
                                         bool dropHalves) {
  std::vector<int> dropped;
  const int k = static_cast<int>(modes.size());
  std::vector<int> refined;
  for (int j = 0; j < k; ++j)
    if (modes[j].refinedError > 0.0) refined.push_back(j);
  const auto moved = [&](int j) { return std::abs(modes[j].lambda - before[j].lambda); };
  std::vector<char> seen(k, 0);
  for (int j : refined) {
    if (seen[j]) continue;
    std::vector<int> group;  // within each other's bounds, transitively
    group.push_back(j), seen[j] = 1;
    for (std::size_t g = 0; g < group.size(); ++g)
      for (int o : refined)
        if (!seen[o] && std::abs(modes[o].lambda - modes[group[g]].lambda) <=
                            modes[o].refinedError + modes[group[g]].refinedError)
          group.push_back(o), seen[o] = 1;
    // A real value dggev returned that refined into a complex one is half
    // of a conjugate pair rounding split onto the real axis: the other half
    // can refine into the same mode, in its block too (at two ranks both
    // members of the shaft's double pair were split, four real values in
    // one block, and refined into four copies). Such modes are compared
    // last, one by one, against every shape kept.
    // Complex where its bound shows it: a real root refined with Im 1e-11
    // within its bound is no conversion (an overdamped shaft's all-real
    // spectrum had values "dropped" as halves of pairs it has not; a review).
    const auto converted = [&](int m) {
      return before[m].lambda.imag() == 0.0 && std::abs(modes[m].lambda.imag()) > modes[m].refinedError;
    };
    std::vector<int> last;
    for (int m : group)
      if (converted(m)) last.push_back(m);
    std::sort(last.begin(), last.end(), [&](int a, int b) { return moved(a) < moved(b); });
    // The group's refinement units (a block, or a mode refined alone), the
    // one whose members moved least first.
    std::vector<int> units;
    for (int m : group)
      if (!converted(m) && std::find(units.begin(), units.end(), unit[m]) == units.end()) units.push_back(unit[m]);
    if (units.size() < 2 && last.empty()) continue;
    const auto least = [&](int u) {
      double d = std::numeric_limits<double>::infinity();
      for (int m : group)
        if (unit[m] == u) d = std::min(d, moved(m));
      return d;
    };
    std::sort(units.begin(), units.end(), [&](int a, int b) { return least(a) < least(b); });
    ShapeSpan kept;  // of the shapes kept
    for (int u : units) {
      std::vector<std::vector<cplx>> own;
      for (int m : group) {
        if (unit[m] != u || converted(m)) continue;
        if (!kept.basis.empty() && kept.holds(modes[m].q)) {
          restoreSolved(modes[m], before[m]);
          continue;
        }
        own.push_back(modes[m].q);
      }
      // The unit's own shapes join the basis where independent (a block's
      // Ritz vectors of a multiple value can be nearly parallel: zggev's
      // eigenvectors of a repeated eigenvalue; its values are the projected
      // problem's, with their multiplicity, and stand).
      for (auto& v : own) kept.add(std::move(v), 0.09);
    }
    for (int m : last) {
      if (kept.add(modes[m].q, 0.09)) continue;
      restoreSolved(modes[m], before[m]);
      // Without `dropHalves` (the sparse path's projection) it stays so.
      if (!dropHalves || !refineCluster(sys, modes, {m})) continue;  // no step stood: dggev's value, first order
      // Onto any value the list holds (not only this group's: two planes
      // of unequal omega between their critical dampings, the half came
      // back on the other plane's genuine real root, held in another group,
      // and was printed twice; a review): the pair's other half.
      if (repeatsAShapeHeld(modes, static_cast<std::size_t>(m))) {
        dropped.push_back(m);
        continue;
      }
      // Else dggev's value stays, with its first-order error: complex
      // again on a value nobody holds, near a nearly defective pair (a
      // spinning shaft near critical damping), such values came with bounds
      // of 0.07-0.1 that the truth, 0.26 away, broke, and a real one with
      // 0.146 where the truth was 0.355 away (a review).
      restoreSolved(modes[m], before[m]);
    }
  }
  std::sort(dropped.begin(), dropped.end());
  return dropped;
}

/// Modes left uncertain by the general solve, refined by two-sided inverse
/// iteration on Q(lambda) = lambda^2 M + lambda (G + D) + K + N with the
/// user's matrices (theory §5, "Stiff rows"; §13.3). dggev is normwise
/// accurate: its residual grows with the stiffest element and with
/// Rayleigh's beta omega_max^2. At 80 elements a Jeffcott rotor's
/// internal-damping growth, 0.241 1/s, read stable, and at 112 a free
/// body's intermediate-axis divergence read rigid (a review); a shaft on a
/// support of E = 1e18 clamped at both ends came out with its lowest pair
/// (78.1456, 78.1475) at 77.944 and 78.882 and no error said but the
/// first-order 12 rad/s in the JSON. Candidates: needsRefinement. The left
/// vector y (Q(lambda)^H y = 0) with the right one x gives the eigenvalue as
/// the root of y^H Q(mu) x = 0, whose error is the product of the two
/// vectors' errors, and a bound (twoSidedBound) that the stiff rows'
/// residual does not reach: with x alone the bound ||r|| ||q|| / |q^H Q' q|
/// grew with the mesh, and at 300 elements the 0.229 1/s flutter read
/// stable again (a review; theory §13.3).
///
/// A cluster is refined as one: candidates and the returned modes within
/// the sum of their first-order errors of them (not zeros, not modes solved
/// apart), however many (past 64, in blocks of 64 neighbours). Refined
/// one by one from dggev's values, a pair split by 1.9e-3 rad/s with
/// values 0.2-0.7 away converged by 0.96-0.99 a step to the pair's mean, or
/// both to one member. Its p vectors X (right) and Y
/// (left) are iterated as blocks, orthonormalised, and the projected
/// problem y^H Q(mu) x = 0 on them (projectedQuadratic; for p = 1 the
/// two-sided root itself) gives every member: the block converges by the
/// distance to the cluster over that to the next eigenvalue outside it,
/// whatever the members' split. One complex LU of Q(sigma) at the cluster's
/// mean (n^3 / 3; its conjugate-transpose solve gives Y), eight steps, the
/// least bound RefinementGate lets stand kept per member. A block member
/// no step of which stands is finished alone from its Ritz value and
/// vector (one more LU there); a single mode no step of which stands, where
/// its value has moved from the shift, gets one more LU at that value and
/// eight more steps (a single shift 0.44 rad/s from a pair split by 0.02
/// had converged by 0.96 a step). Sets refinedError. Returns whether any
/// changed. Conservative systems (frequencyTol infinite): one by one.
/// With `dropHalves`, the second half of a conjugate pair split onto the
/// real axis (undoRepeatedRefinements) leaves the list, counted in
/// `dropped`; without, it keeps dggev's value and first-order error.
bool refineModes(const GyroscopicSystem& sys, std::vector<GyroscopicMode>& modes, double instabilityTol,
                 double zeroBelow, bool decays, double frequencyTol, bool dropHalves, int& dropped) {
  const int k = static_cast<int>(modes.size());
  // The clusters: each candidate with the modes within the sum of their
  // first-order errors, transitively (union-find over the pairs: O(k^2),
  // where growing each cluster by rescans was O(k^3), 2.7e10 at "Number of
  // Modes: -1" on n = 1500).
  const std::size_t n = static_cast<std::size_t>(sys.size());
  const auto eligible = [&](const GyroscopicMode& m) {
    return std::abs(m.lambda) > zeroBelow && m.blockScale == 0.0 && m.q.size() == n;
  };
  const auto reach = [](const GyroscopicMode& m) { return std::isfinite(m.eigenvalueError) ? m.eigenvalueError : 0.0; };
  const std::vector<GyroscopicMode> before(modes);  // dggev's, for undoRepeatedRefinements
  std::vector<int> unit(k, -1);                     // each refined mode's block
  int units = 0;
  std::vector<char> candidate(k);
  for (int j = 0; j < k; ++j)  // a mode without its whole shape is not refined
    candidate[j] = eligible(modes[j]) && needsRefinement(modes[j], modes, instabilityTol, zeroBelow, decays, frequencyTol);
  std::vector<int> root(k);
  std::iota(root.begin(), root.end(), 0);
  const auto find = [&](int j) {
    while (root[j] != j) j = root[j] = root[root[j]];
    return j;
  };
  // A conservative system (frequencyTol infinite) refines its undecided
  // growths one by one, as before clusters: a free shaft's frame-rate
  // triple, a defective cluster rounding splits, projected as one block
  // came out with a growth at two ranks and none at one (the Campbell rank
  // test, tests/CMakeLists.txt free_shaft_campbell_same_tracks).
  if (std::isfinite(frequencyTol))
    for (int a = 0; a < k; ++a)
      for (int b = a + 1; b < k; ++b)
        if (eligible(modes[a]) && eligible(modes[b]) &&
            std::abs(modes[a].lambda - modes[b].lambda) <= reach(modes[a]) + reach(modes[b]))
          root[find(a)] = find(b);
  std::vector<char> wanted(k, 0);  // a cluster holding a candidate
  for (int j = 0; j < k; ++j)
    if (candidate[j]) wanted[find(j)] = 1;
  bool any = false;
  std::vector<char> done(k, 0);
  for (int j = 0; j < k; ++j) {
    const int c = find(j);
    if (!wanted[c] || done[c]) continue;
    done[c] = 1;
    std::vector<int> members;  // ascending |lambda|, as the modes are
    for (int i = j; i < k; ++i)
      if (find(i) == c) members.push_back(i);
    // Refined as one block, however many: refined one by one, a cluster of
    // eight (four identical shafts on one support, D = 0.3 M: a double and
    // a sixfold value 1.7e-6 rad/s apart, dggev's values 1 rad/s off) came
    // back with the double three times and a sixfold member lost, each with
    // a "refined bound" of 7.5e-8 (a review). Past 64 members, in blocks of
    // 64 neighbours (the projected problem's 2p zggev and the block's n^2 p
    // products stay small beside the LU).
    std::vector<std::vector<int>> blocks;
    for (std::size_t i = 0; i < members.size(); i += 64)
      blocks.emplace_back(members.begin() + i, members.begin() + std::min(members.size(), i + 64));
    for (const auto& block : blocks) {
      for (int m : block) unit[m] = units;
      ++units;
      any = refineCluster(sys, modes, block) || any;
    }
  }
  if (any) {
    const std::vector<int> halves = undoRepeatedRefinements(sys, modes, before, unit, dropHalves);
    for (auto h = halves.rbegin(); h != halves.rend(); ++h) modes.erase(modes.begin() + *h), ++dropped;
  }
  return any;
}
}  // namespace

namespace {
/// completeDenseModes; `refineDecays`: a circulatory system's decaying
/// growths within their uncertainty are refined (below; false for the
/// sparse path's projection, whose Ritz values that path refines on the
/// full model by its own rules). `wanted` >= 0 (the dense solve, whose
/// generalModes returned spares past the count): a split pair's second
/// half is dropped (refineModes; counted in `dropped`), and the modes past
/// `wanted` go to `unreturned`; -1 (the projection): every mode stays.
void completeModes(const GyroscopicSystem& sys, std::vector<GyroscopicMode>& modes, double rigidBodyTol,
                   double instabilityTol, bool ownScales, std::vector<std::complex<double>>& unreturned,
                   bool refineDecays, double frequencyTol, int wanted, int& dropped) {
  if (modes.empty()) return;
  const bool damped = sys.damped();
  // A circulatory N (a rotor's material damping seen from the stationary
  // frame) can make a mode flutter, and no energy bound proves otherwise: a
  // decaying growth within its uncertainty is refined too, and one left
  // unrefined is undecided. The stiff-support shaft spinning at 140 rad/s
  // (50 elements, beta 1e-6, two BLAS threads) read its forward whirl
  // "stable" at -0.0020 1/s within 27 (dggev's first order), where it
  // flutters at +0.0024 (a review; refined, 5.6e-6; theory §13.3).
  const bool circulatory = refineDecays && sys.N.numRows() == sys.size() && frobeniusNorm(sys.N) > 0.0;
  double scale = measureModes(sys, modes, instabilityTol, ownScales, unreturned);
  // A conservative system's frequencies are not refined (its growths are,
  // as undecided): as on the sparse path, the Frequency Tolerance is a
  // damped system's.
  const bool refined = !ownScales && refineModes(sys, modes, instabilityTol, rigidBodyTol * scale, circulatory,
                                                 damped ? frequencyTol : std::numeric_limits<double>::infinity(),
                                                 wanted >= 0, dropped);
  if (refined)
    // In the solve's order again (ascending |lambda|, as generalModes
    // returns them): a refined pair can exchange its members (the shaft's
    // 4593.24 and 4593.54 came back in each other's places).
    std::stable_sort(modes.begin(), modes.end(),
                     [](const GyroscopicMode& a, const GyroscopicMode& b) { return std::abs(a.lambda) < std::abs(b.lambda); });
  // The spares past the count, where no half was dropped, are values past
  // the returned ones again.
  const bool cut = wanted >= 0 && static_cast<int>(modes.size()) > wanted;
  if (cut) {
    for (std::size_t j = static_cast<std::size_t>(wanted); j < modes.size(); ++j) unreturned.push_back(modes[j].lambda);
    modes.resize(static_cast<std::size_t>(wanted));
  }
  if (refined || cut) scale = measureModes(sys, modes, instabilityTol, ownScales, unreturned);
  const auto judge = [&] {
    classifyModes(modes, scale, rigidBodyTol, instabilityTol, !damped, /*completeShapes=*/true, unreturned);
    // A mode whose |lambda| lies within its own first-order error of zero
    // cannot be told from a rigid-body motion, whatever the system's scale
    // says (theory §4.3): a solid bar on a line of nodes, its free turn
    // restrained only by a synthesised K's rounding, came out of dggev at
    // 0.0109 rad/s within 0.15 (one BLAS thread on an AMD EPYC; at two it was
    // below the Rigid Body Tolerance) and was printed as a vibration where the
    // run is refused as "unrestrained". Not where the stiffness was proven
    // nonsingular (rigidBodyTol = 0), nor on the Meirovitch path (each mode on
    // its own scale), nor for a refined mode (its bound is not first order).
    // Nor with gyroscopic terms: near a critical speed q^H Q'(lambda) q =
    // 2 lambda q^H M q + q^H G q tends to zero and the first-order error
    // overstates: a spinning support's mode at 4.6986 rad/s, 83 rad/s, has a
    // first-order error about |lambda| (below: shown nonzero by refinement).
    if (!ownScales && rigidBodyTol > 0.0 && !(frobeniusNorm(sys.G) > 0.0))
      for (auto& m : modes)
        if ((m.stability == Stability::Stable || m.stability == Stability::Neutral) && m.blockScale == 0.0 &&
            m.refinedError == 0.0 && std::abs(m.lambda) <= m.eigenvalueError) {
          m.stability = Stability::RigidBody, m.undecided = false;
          zeroRigidDamping(m);
        }
  };
  judge();
  // A zero by the system's scale, or by the radius a split defective zero
  // could take, only: refined alone (two-sided inverse iteration with the
  // user's matrices), it is shown nonzero where it oscillates, |Im lambda|
  // above ten times its bound, its shape repeats none held, and |lambda|
  // exceeds ten times what rounding of the entries can move it
  // (roundingReach) where K's parts are known (sys.KMagnitude, assembled
  // entry by entry: their magnitudes hold K(Omega)'s cancellation at a
  // critical speed), else sqrt(eps) s (below) and the Rigid Body Tolerance
  // of its own componentwise scale (a free turn held by K's rounding alone
  // stays a zero). Never a real value: at a critical speed itself the
  // computed K(Omega) has cancelled (a point mass exactly at its critical
  // speed read DIVERGENCE at 2.1e-8 1/s within a "bound" of 3.8e-23; a
  // review), and with the parts' bound a mechanism still read DIVERGENCE
  // where K_S1 carries the prestress solve's rounding, which R does not
  // hold (a blade on a lag hinge on the axis, its inner element 1e8 times
  // softer axially: 0.0225 1/s at 100 rad/s), or where only the mesh keeps
  // a zero from zero (the same blade coned: 0.00282, 0.00142 1/s at 4 and
  // 8 elements; a review). A shaft spinning with its support of E = 1e18 at 83 rad/s,
  // past its critical speed, has its forward whirl at 4.6986 rad/s in the
  // spinning frame, below 1e-6 of the system's scale (7e7 rad/s, the
  // support's) and within 10 sqrt(eta) s: it was labelled critical, and
  // with the shaft's material damping printed at 0 rad/s where it flutters
  // (a review); on the scales alone a window of 0.3-0.6 rad/s about the
  // critical speed still read so, with the parts' bound 0.04 (theory §4.3,
  // "A zero shown nonzero"). The dense solve only
  // (`wanted` >= 0; not the sparse path's projection), not a mode solved
  // apart (its block's scale is its own). One complex LU of n per such mode.
  if (!ownScales && rigidBodyTol > 0.0 && wanted >= 0 && sys.unrestrained.empty()) {
    const std::size_t n = static_cast<std::size_t>(sys.size());
    // A double zero (a critical speed's Jordan block) split by a normwise
    // perturbation eps of K moves by sqrt(eps) s: below that, a value the
    // refinement "shows" may be the computed K(Omega)'s rounding.
    const double floor = std::sqrt(std::numeric_limits<double>::epsilon()) * scale;
    bool shown = false;
    const bool parts = sys.KMagnitude.numRows() == static_cast<int>(n);
    for (std::size_t j = 0; j < modes.size(); ++j) {
      GyroscopicMode& m = modes[j];
      if (m.stability != Stability::RigidBody || m.blockScale != 0.0 || m.refinedError != 0.0 ||
          !(std::abs(m.lambda) > 0.0) || m.q.size() != n)
        continue;
      const GyroscopicMode was = m;
      std::vector<cplx> left;
      if (!refineCluster(sys, modes, {static_cast<int>(j)}, &left)) {
        m = was;
        continue;
      }
      const double reach = parts ? roundingReach(sys, m.lambda, m.q, left) : 0.0;
      const bool nonzero =
          std::abs(m.lambda.imag()) > 10.0 * m.refinedError &&
          (parts ? std::abs(m.lambda) > 10.0 * reach
                 : std::abs(m.lambda) > floor && std::abs(m.lambda) > rigidBodyTol * componentScale(sys, m.q));
      // Ten times the reach: a point mass 1e-14 below its critical speed,
      // shown beyond its reach once (0.7 |lambda|), printed 9.2339e-7 rad/s
      // within a refined bound of 2.6e-21 where the exact is 9.2582e-7 (a
      // review): the bound, as every mode's, takes the computed matrices as
      // exact, and a mode shown nonzero is one their rounding moves by at
      // most a tenth of itself (the reach is a worst case: the shaft's 0.307
      // rad/s at 78.6 rad/s, reach 1.35e-5, agrees with the stationary
      // frame's model to 6e-10).
      if (nonzero && !repeatsAShapeHeld(modes, j))
        m.shownNonzero = shown = true;
      else
        m = was;
    }
    if (shown) {
      std::stable_sort(modes.begin(), modes.end(), [](const GyroscopicMode& a, const GyroscopicMode& b) {
        return std::abs(a.lambda) < std::abs(b.lambda);
      });
      scale = measureModes(sys, modes, instabilityTol, ownScales, unreturned);
      judge();
    }
  }
  if (circulatory && !ownScales)
    for (auto& m : modes) {
      const double s = m.scale > 0.0 ? std::min(m.scale, scale) : scale;
      if (m.stability == Stability::Stable && m.refinedError == 0.0 &&
          undecidedDecay(m, modes, instabilityTol, rigidBodyTol * s))
        m.stability = Stability::Neutral, m.undecided = true;
    }
}
}  // namespace

void completeDenseModes(const GyroscopicSystem& sys, std::vector<GyroscopicMode>& modes,
                        double rigidBodyTol, double instabilityTol, bool ownScales,
                        const std::vector<std::complex<double>>& unreturned) {
  std::vector<std::complex<double>> beyond(unreturned);
  int dropped = 0;
  completeModes(sys, modes, rigidBodyTol, instabilityTol, ownScales, beyond, true,
                std::numeric_limits<double>::infinity(), -1, dropped);
}

namespace {
/// Whether the symmetric part of sys.K + sys.N is positive definite as the
/// undamped path takes K to be (Cholesky's pivots^2 spread by no more than
/// `definitenessTol`, "Definiteness Tolerance": then that path solves it on
/// its Meirovitch form, each mode on its own scale) and proven so
/// (showPositiveDefinite, the given entries taken exact): then no
/// eigenvalue is zero (Re q^H (K + N) q > 0 for q != 0). Not where sys has
/// coordinates the stiffness at rest does not reach. The proof alone
/// takes a synthesised K's rounding as stiffness: a post's free turn under
/// an arm 2e5 to 1e12 times stiffer was "proven" stiff and printed as a
/// vibration (2.5e-5 to 0.029 rad/s) where it had been refused as
/// "unrestrained" (a review); its pivots spread past the tolerance, as the
/// undamped path finds.
bool stiffnessShownNonsingular(const GyroscopicSystem& sys, double definitenessTol) {
  const int n = sys.size();
  if (n == 0 || !sys.unrestrained.empty()) return false;
  const bool hasN = sys.N.numRows() == n;
  DenseMatrix A(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      A(i, j) = 0.5 * (sys.K(i, j) + sys.K(j, i)) + (hasN ? 0.5 * (sys.N(i, j) + sys.N(j, i)) : 0.0);
  DenseMatrix L(A);
  return choleskyLower(L, definitenessTol) == 0 && showPositiveDefinite(A).shown;
}
}  // namespace

Teuchos::RCP<const Teuchos::ParameterList> DenseGyroscopicSolver::getValidParameters() {
  static Teuchos::RCP<const Teuchos::ParameterList> valid = [] {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Dense Gyroscopic Solver"));
    Teuchos::setStringToIntegralParameter<int>(
        "Method", "Auto",
        "Meirovitch: real symmetric form (K must be positive definite); General: LAPACK dggev "
        "on the first-order pencil; Auto: Meirovitch if K > 0, else General",
        Teuchos::tuple<std::string>("Auto", "Meirovitch", "General"), pl.get());
    pl->set("Number of Modes", -1, "How many of the lowest modes to return; -1 for all n");
    Teuchos::setStringToIntegralParameter<int>(
        "Reduction", "Skew Tridiagonal",
        "the Meirovitch path's reduction of its skew factor A (doc/theory.md §2): Skew Tridiagonal (Householder "
        "similarity, each frequency once from an n x n bidiagonal) or Bidiagonal (LAPACK dgebrd on A as a general "
        "matrix, each frequency twice; also the fallback)",
        Teuchos::tuple<std::string>("Skew Tridiagonal", "Bidiagonal"), pl.get());
    Teuchos::setStringToIntegralParameter<int>(
        "General Coordinates", "Given",
        "the general path's coordinates: Given (the pencil with M; the coordinates congruent to M = I "
        "when dggev returns an infinite eigenvalue or its QZ fails, and for a K positive definite whose pivots "
        "only spread past the Definiteness Tolerance), or Mass Congruent (always M = I by q = L^-T p, M = L L^T)",
        Teuchos::tuple<std::string>("Given", "Mass Congruent"), pl.get());
    Teuchos::setStringToIntegralParameter<int>(
        "General Eigensolver", "QZ",
        "the general path's algorithm: QZ (LAPACK dggev on the pencil; when its iteration fails, again in the "
        "coordinates with M = I, then Hessenberg QR there) or Hessenberg QR (LAPACK dgeev on the standard "
        "problem in the coordinates with M = I; faster, but its rounding can split a defective cluster into a "
        "false instability: doc/benchmarks.md)",
        Teuchos::tuple<std::string>("QZ", "Hessenberg QR"), pl.get());
    pl->set("Structure Tolerance", 1e-10,
            "Tolerance on the symmetry of M, K and skew-symmetry of G, relative to s^2||M||+s||G||+||K|| at the frequency scale s");
    addStabilityTolerances(*pl);
    pl->set("Stiffness Proof", true,
            "a damped system: where the symmetric part of K + N passes the Definiteness Tolerance's Cholesky "
            "test and is proven positive definite (doc/theory.md 4.3), no eigenvalue is zero and none is taken "
            "for a rigid-body mode however far below the Rigid Body Tolerance of the system's scale; false where "
            "the given K carries errors the proof cannot see (a projection's rounding)");
    pl->set("Refine Decays", true,
            "a system with a circulatory N: refine a decaying growth rate within its uncertainty too, and call "
            "one left unrefined undecided (doc/theory.md 13.3); false for the sparse path's projection, whose "
            "Ritz values are refined on the full model");
    pl->set("Frequency Tolerance", 1e-5,
            "a damped system: a mode whose first-order eigenvalue error ||r|| ||q|| / |q^H (2 lambda M + G + D) q| "
            "exceeds this times |lambda| is refined by two-sided inverse iteration on Q(lambda), a cluster within "
            "its members' errors as one block (one complex LU of n each; doc/theory.md 5, \"Stiff rows\"); a mode "
            "still not shown within it is said in the reason (the sparse path's projected solve sets it to infinity: none "
            "refined for its frequency there)");
    pl->set("Energy Bound", true,
            "a damped system: prove N = 0 and M > 0, K > 0, D + d M > 0 (d = Instability Tolerance times the "
            "least |lambda|) from Cholesky factors of their shifts by Cholesky's a-priori error, so that no mode "
            "grows faster than d and a growth within its uncertainty is decided stable (doc/theory.md 13.3); "
            "false skips it");
    pl->set("Definiteness Tolerance", 1e-14,
            "K is treated as not positive definite when its smallest Cholesky pivot squared is "
            "below this times the largest (the symmetric form would lose all accuracy)");
    return pl;
  }();
  return valid;
}

GyroscopicResult DenseGyroscopicSolver::solve(const GyroscopicSystem& input) const {
  input.validate(params_.get<double>("Structure Tolerance"));
  const GyroscopicSystem sys = input.symmetrised();
  const int n = sys.size();
  const int nModes = requestedCount(params_, n);
  std::vector<cplx> unreturned;  // the general path's eigenvalues past the returned ones (classifyModes)
  const std::string method = params_.get<std::string>("Method");
  const double instabTol = params_.get<double>("Instability Tolerance");
  // A damped system whose sym(K + N) is proven positive definite has no
  // zero eigenvalue (Re q^H (K + N) q > 0 for every q != 0): none is a
  // rigid-body mode, however small against the system's scale, which takes
  // its stiffness from the stiffest part and its mass from the heaviest. A
  // 1.2 m shaft on a pedestal of E = 1e18 (s = 6.5e7 rad/s) has its lowest
  // pair at 58.37 rad/s, below 1e-6 s: the pair was taken for two rigid
  // motions and the run refused as "unrestrained" (theory §4.3, "A
  // stiffness shown nonsingular"). Three Cholesky factors of n (the
  // Definiteness Tolerance's and the proof's two), beside the 2n pencil's
  // QZ.
  const bool noZeros =
      sys.damped() && params_.get<bool>("Stiffness Proof") &&
      stiffnessShownNonsingular(sys, params_.get<double>("Definiteness Tolerance"));
  const double rigidTol = noZeros ? 0.0 : params_.get<double>("Rigid Body Tolerance");

  DenseMatrix Lm(sys.M);
  const int infoM = choleskyLower(Lm);
  CMS_INPUT_CHECK(infoM != 0, "DenseGyroscopicSolver: M is not positive definite (Cholesky "
                              "pivot "
                                  << infoM << " of " << n
                                  << " failed): every DOF needs mass or rotary inertia");

  GyroscopicResult result;
  result.numRequested = nModes;
  const double scale = frequencyScale(
      frobeniusNorm(sys.M), frobeniusNorm(sys.G) + (sys.D.numRows() > 0 ? frobeniusNorm(sys.D) : 0.0),
      frobeniusNorm(sys.K) + (sys.N.numRows() > 0 ? frobeniusNorm(sys.N) : 0.0));

  std::string whyNotSymmetric;
  bool spreadOnly = false;  // K positive definite, only its pivots' spread past the tolerance
  DenseMatrix Lk(sys.K);
  if (sys.damped()) {
    // Damping (D) or circulatory (N) terms: the spectrum is no longer
    // Hamiltonian and Meirovitch's real symmetric form does not exist.
    whyNotSymmetric = std::string("damped: ") + (sys.D.numRows() > 0 && frobeniusNorm(sys.D) > 0.0 ? "D != 0" : "N != 0") +
                      " makes the system non-conservative, Meirovitch's symmetric form (seed eq. (24)) "
                      "needs D = N = 0: general first-order pencil";
    CMS_INPUT_CHECK(method == "Meirovitch", "DenseGyroscopicSolver: Method \"Meirovitch\" needs an undamped "
                                            "system, but " << whyNotSymmetric << "; use \"Auto\" or \"General\"");
  } else if (method != "General") {
    const int infoK = choleskyLower(Lk, params_.get<double>("Definiteness Tolerance"));
    spreadOnly = infoK == n + 1;
    if (infoK == n + 1)
      whyNotSymmetric = "K is positive definite only to rounding (smallest Cholesky pivot^2 / "
                        "largest below \"Definiteness Tolerance\")";
    else if (infoK != 0)
      whyNotSymmetric = "K is not positive definite (Cholesky pivot " + std::to_string(infoK) +
                        " of " + std::to_string(n) + " failed)";
    CMS_INPUT_CHECK(method == "Meirovitch" && !whyNotSymmetric.empty(),
                               "DenseGyroscopicSolver: Method \"Meirovitch\" needs K > 0 "
                               "(I* = diag(M,K) > 0, seed eq. (23)), but "
                                   << whyNotSymmetric << "; use \"Auto\" or \"General\"");
  }

  if (method != "General" && whyNotSymmetric.empty()) {
    std::string note;
    bool complete = true;
    result.modes = meirovitchModes(sys, Lm, Lk, nModes, params_.get<std::string>("Reduction") == "Skew Tridiagonal",
                                   note, complete);
    result.solver = "dense Meirovitch (singular values of the skew factor of K*)";
    result.reason = "K and M positive definite: real symmetric form, seed eq. (24); " + note;
    if (!complete) result.status = SolveStatus::NumericalIssue;
  } else {
    // "Number of Modes" = -1 asks for every mode; a damped system can have
    // more than n (each overdamped DOF gives two real eigenvalues).
    const bool every = params_.get<int>("Number of Modes") == -1 && sys.damped();
    result.solver = "dense general (LAPACK dggev, 2n first-order pencil)";
    result.reason = method == "General" && !sys.damped() ? "requested" : whyNotSymmetric;
    // The coordinates the stiffness at rest does not reach, solved apart on
    // their own scale (theory §4.3); generalModes puts their modes in.
    UnrestrainedModes unrestrained = solveUnrestrained(sys, rigidTol);
    UnrestrainedModes* block = sys.unrestrained.empty() ? nullptr : &unrestrained;
    // M = Lm Lm^T > 0 (checked above): the congruent system with M = I,
    // q = Lm^-T p, has B = I in its pencil and no infinite eigenvalue; the
    // same eigenvalues, its shapes mapped back.
    const auto solveCongruent = [&](std::string& how) {
      GyroscopicSystem c = sys;
      const auto congruent = [&](DenseMatrix& X) {
        if (X.numRows() != n) return;
        lowerSolveLeft(Lm, X);
        lowerTransSolveRight(Lm, X);
      };
      c.M.shape(n, n);
      for (int i = 0; i < n; ++i) c.M(i, i) = 1.0;
      congruent(c.G), congruent(c.K), congruent(c.D), congruent(c.N);
      bool qr = params_.get<std::string>("General Eigensolver") == "Hessenberg QR";
      if (!qr) {
        try {
          result.modes = generalModes(c, every ? 2 * n : nModes, scale, rigidTol, unreturned, false, block, !every);
        } catch (const QzFailure& e) {
          qr = true;
          how = std::string("; there too ") + e.what() +
                ": solved by LAPACK dgeev (Hessenberg QR) on the standard problem, B = I";
        }
      }
      if (qr)
        result.modes =
            generalModes(c, every ? 2 * n : nModes, scale, rigidTol, unreturned, /*standard=*/true, block, !every);
      std::vector<double> re(n), im(n);
      for (auto& m : result.modes) {
        if (m.blockScale > 0.0) continue;  // solved apart, in the given coordinates
        for (int i = 0; i < n; ++i) re[i] = m.q[i].real(), im[i] = m.q[i].imag();
        lowerTransSolveVector(Lm, re.data());
        lowerTransSolveVector(Lm, im.data());
        for (int i = 0; i < n; ++i) m.q[i] = cplx(re[i], im[i]);
      }
      result.solver = qr ? "dense general (LAPACK dgeev, 2n first-order standard problem, congruent to M = I)"
                         : "dense general (LAPACK dggev, 2n first-order pencil, congruent to M = I)";
    };
    std::string how;
    const auto also = [&](const std::string& why) {
      result.reason += std::string(result.reason.empty() ? "" : "; ") + why + how;
    };
    if (params_.get<std::string>("General Eigensolver") == "Hessenberg QR") {
      solveCongruent(how);
      also("Hessenberg QR requested, in the coordinates with M = I");
    } else if (params_.get<std::string>("General Coordinates") == "Mass Congruent") {
      solveCongruent(how);
      also("requested in the coordinates with M = I");
    } else if (spreadOnly) {
      // K positive definite, its pivots spread past the Definiteness
      // Tolerance (a stub 1e8 times stiffer than its hub, massless): the
      // pencil in the given coordinates left the low modes to its normwise
      // rounding, and a wheel's 4.31 and 5.36 Hz came out 5.36 and 10.7 Hz
      // with rounding-sized residuals on two of OpenBLAS's kernels (right on
      // a third, where dggev met an infinite eigenvalue and came here). In
      // the coordinates with M = I (B = I) every kernel gives 4.31 and 5.36
      // (found when the suite ran on a new machine; theory §4.3).
      solveCongruent(how);
      also("K spans too many orders for the symmetric form: the pencil in the coordinates with M = I");
    } else {
      try {
        result.modes = generalModes(sys, every ? 2 * n : nModes, scale, rigidTol, unreturned, false, block, !every);
      } catch (const InfiniteEigenvalue&) {
        solveCongruent(how);
        also("dggev returned an infinite eigenvalue on the pencil with M, which is positive definite: "
             "solved again with M = I by the congruence q = L^-T p");
      } catch (const QzFailure& e) {
        // A near-defective pencil (a coalescence at a critical speed): the
        // congruent pencil has other rounding, and B = I.
        solveCongruent(how);
        also(std::string(e.what()) + " on the pencil with M: solved again with M = I by the congruence q = L^-T p");
      }
    }
    if (every) result.numRequested = static_cast<int>(result.modes.size());
    if (block) result.reason += unrestrained.note;
  }
  // Residuals of the user's matrices. The Meirovitch path resolves each
  // eigenvalue to its own componentwise scale (a Cholesky factor of K and
  // an SVD: the low modes come from the largest singular values); dggev's
  // accuracy is normwise, so its modes are judged on the system's scale
  // (theory §4.3).
  int dropped = 0;
  completeModes(input, result.modes, rigidTol, instabTol, result.solver.rfind("dense Meirovitch", 0) == 0, unreturned,
                params_.get<bool>("Refine Decays"), params_.get<double>("Frequency Tolerance"), result.numRequested,
                dropped);
  if (dropped > 0) {
    std::ostringstream note;
    note << "; " << dropped << " real value(s) dggev returned dropped: each refined onto a complex mode the list "
         << "holds already, half of a conjugate pair rounding split onto the real axis (theory §5)";
    result.reason += note.str();
    if (params_.get<int>("Number of Modes") == -1 && sys.damped())
      result.numRequested = static_cast<int>(result.modes.size());  // every mode: the split pair is one
  }
  if (sys.damped()) result.reason += accuracyNote(result.modes, params_.get<double>("Frequency Tolerance"), "");
  if (noZeros) {
    const double below = params_.get<double>("Rigid Body Tolerance") * scale;
    const long small = std::count_if(result.modes.begin(), result.modes.end(), [&](const GyroscopicMode& m) {
      return m.blockScale == 0.0 && std::abs(m.lambda) <= below;
    });
    if (small > 0) {
      std::ostringstream note;
      note << std::setprecision(3) << "; " << small << " mode(s) below the Rigid Body Tolerance of the system's scale ("
           << below << " 1/s) are vibrations, not rigid-body modes: sym(K + N) is positive definite within the "
           << "Definiteness Tolerance and proven so (theory 4.3)";
      result.reason += note.str();
    }
  }
  // A damped system's growth rates against the energy bound (theory §13.3):
  // where N = 0 and M, K, D + d M > 0 are proven, no mode grows faster than
  // d, so a growth within its uncertainty (which grows with K's condition)
  // is decided; d is the Instability Tolerance's share of the least |lambda|.
  if (sys.damped() && params_.get<bool>("Energy Bound")) {
    double least = std::numeric_limits<double>::infinity();
    for (const auto& m : result.modes)
      if (m.stability != Stability::RigidBody) least = std::min(least, std::abs(m.lambda));
    if (std::isfinite(least) && least > 0.0) {
      result.energyBound = energyBound(sys, instabTol * least);
      const std::vector<int> wrong = applyEnergyBound(result.modes, result.energyBound, instabTol);
      if (!wrong.empty()) {
        std::ostringstream os;
        os << "; the energy bound contradicts mode " << wrong.front() + 1 << "'s growth rate "
           << result.modes[wrong.front()].lambda.real() << " 1/s beyond its uncertainty "
           << result.modes[wrong.front()].growthTolerance << " (" << wrong.size()
           << " mode(s)): the solve is wrong there";
        result.reason += os.str();
        result.status = SolveStatus::NumericalIssue;
      }
    }
  }
  if (static_cast<int>(result.modes.size()) != result.numRequested) result.status = SolveStatus::NumericalIssue;
  return result;
}

}  // namespace cms::eigen
