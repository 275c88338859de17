#include "cms/eigen/SturmCount.hpp"

#include <cmath>
#include <complex>
#include <sstream>
#include <vector>

#include <Tpetra_CrsMatrix.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

#include "SpectralTransform.hpp"
#include "cms/core/MatrixSum.hpp"
#include "cms/core/DistributedDirectSolver.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/SparseInertia.hpp"

extern "C" void zhetrf_(const char* uplo, const int* n, std::complex<double>* a, const int* lda,
                        int* ipiv, std::complex<double>* work, const int* lwork, int* info,
                        std::size_t);
extern "C" void dsytrf_(const char* uplo, const int* n, double* a, const int* lda, int* ipiv, double* work,
                        const int* lwork, int* info, std::size_t);

namespace cms::eigen {

int sturmCount(const GyroscopicSystem& sys, double omega) {
  CMS_INPUT_CHECK(!(std::isfinite(omega) && omega > 0.0),
                  "sturmCount: frequency " << omega << " must be positive and finite");
  const int n = sys.size();
  // Q(omega) = K - omega^2 M + i omega G: Hermitian because G is skew. Only
  // the lower triangle is read.
  std::vector<std::complex<double>> Q(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = j; i < n; ++i)
      Q[static_cast<std::size_t>(j) * n + i] = {sys.K(i, j) - omega * omega * sys.M(i, j), omega * sys.G(i, j)};
  // An exactly zero 1x1 pivot (zhetrf's info > 0) is omega at an
  // eigenfrequency to working precision: the count is that of the nonzero
  // pivots.
  return hermitianNegatives(Q, n);
}

namespace {
/// Inertia of D from a Bunch-Kaufman factor (Sylvester): 1x1 pivots by
/// sign; a 2x2 block [a b; conj(b) c] by its two eigenvalues (a + c)/2 -/+
/// sqrt((a - c)^2 / 4 + |b|^2); each negative only below -tiny.
template <class Scalar>
int negativePivots(const std::vector<Scalar>& F, const std::vector<int>& ipiv, int n, double tiny, int* within = nullptr) {
  const auto d = [&](int i, int j) { return F[static_cast<std::size_t>(j) * n + i]; };
  int negative = 0, small = 0;
  for (int k = 0; k < n;) {
    TEUCHOS_TEST_FOR_EXCEPTION(!std::isfinite(std::real(d(k, k))), NumericalError,
                               "Bunch-Kaufman L D L^T: pivot " << k << " is not finite");
    if (ipiv[k] > 0 || k + 1 == n) {
      negative += std::real(d(k, k)) < -tiny;
      small += std::abs(std::real(d(k, k))) <= tiny;
      k += 1;
    } else {
      const double a = std::real(d(k, k)), c = std::real(d(k + 1, k + 1));
      const double r = std::sqrt(0.25 * (a - c) * (a - c) + std::norm(d(k + 1, k)));
      negative += (0.5 * (a + c) - r < -tiny) + (0.5 * (a + c) + r < -tiny);
      small += (std::abs(0.5 * (a + c) - r) <= tiny) + (std::abs(0.5 * (a + c) + r) <= tiny);
      k += 2;
    }
  }
  if (within) *within = small;
  return negative;
}
}  // namespace

int hermitianNegatives(std::vector<std::complex<double>>& Q, int n, double tiny) {
  if (n == 0) return 0;
  std::vector<int> ipiv(n);
  int info = 0, lwork = -1;
  std::complex<double> wq;
  zhetrf_("L", &n, Q.data(), &n, ipiv.data(), &wq, &lwork, &info, 1);
  lwork = std::max(1, static_cast<int>(wq.real()));
  std::vector<std::complex<double>> work(lwork);
  zhetrf_("L", &n, Q.data(), &n, ipiv.data(), work.data(), &lwork, &info, 1);
  TEUCHOS_TEST_FOR_EXCEPTION(info < 0, NumericalError, "LAPACK zhetrf failed, info = " << info);
  return negativePivots(Q, ipiv, n, tiny);
}

int symmetricNegatives(std::vector<double>& A, int n, double tiny, int* within) {
  if (within) *within = 0;
  if (n == 0) return 0;
  std::vector<int> ipiv(n);
  int info = 0, lwork = -1;
  double wq = 0.0;
  dsytrf_("L", &n, A.data(), &n, ipiv.data(), &wq, &lwork, &info, 1);
  lwork = std::max(1, static_cast<int>(wq));
  std::vector<double> work(lwork);
  dsytrf_("L", &n, A.data(), &n, ipiv.data(), work.data(), &lwork, &info, 1);
  TEUCHOS_TEST_FOR_EXCEPTION(info < 0, NumericalError, "LAPACK dsytrf failed, info = " << info);
  return negativePivots(A, ipiv, n, tiny, within);
}

SparseSturmCount sturmCount(const SparseGyroscopicSystem& sys, double omega) {
  return detail::sturmCountBy(sys, omega, InertiaMethod::Auto);
}

SparseSturmCount detail::sturmCountBy(const SparseGyroscopicSystem& sys, double omega, InertiaMethod method) {
  CMS_INPUT_CHECK(!(std::isfinite(omega) && omega > 0.0),
                  "sturmCount: frequency " << omega << " must be positive and finite");
  const bool gyroscopic = sys.G->getFrobeniusNorm() > 0.0;
  SparseSturmCount out;
  std::ostringstream note;
  // The request, then off a zero pivot by a relative 1e-8 each way: a cut
  // placed in a gap of the returned spectrum stays in it (the gaps the
  // solver cuts in are at least its cluster tolerance 1e-6 wide).
  for (const double factor : {1.0, 1.0 + 1e-8, 1.0 - 1e-8}) {
    const double w = omega * factor;
    Teuchos::RCP<const CrsMatrix> A = matrixSum(1.0, *sys.K, -w * w, *sys.M);
    SparseInertia in;
    if (gyroscopic) {
      const auto B = Tpetra::MatrixMatrix::add(w, false, *sys.G, 0.0, false, *sys.G);
      in = inertia(*A, *B, method);
    } else {
      in = inertia(std::move(A), method);  // handed over: freed once the count holds its values
    }
    out.omega = w;
    out.count = in.negative;
    out.reliable = in.reliable();
    if (out.reliable) break;
    note << (note.tellp() > 0 ? "; " : "") << "at " << w << " rad/s "
         << (in.failure.empty() ? std::to_string(in.tinyPivots) + " pivot(s) zero to rounding"
                                : in.failure);
  }
  out.note = note.str();
  if (out.reliable && !out.note.empty()) out.note += ", counted at " + std::to_string(out.omega) + " rad/s instead";
  return out;
}

LowestSetCheck checkLowestSet(const std::vector<double>& omegas, int nModes, double relClusterTol,
                              const std::function<SparseSturmCount(double)>& countBelow) {
  LowestSetCheck c;
  const int n = static_cast<int>(omegas.size());
  if (nModes < 1 || n < nModes) {
    c.message = "no Sturm check: " + std::to_string(n) + " of " + std::to_string(nModes) + " frequencies known";
    return c;
  }
  const double top = omegas[nModes - 1], tol = relClusterTol * top;
  int lo = nModes - 1, hi = nModes;  // the cluster of the nModes-th: [lo, hi)
  // Grown member to member: measured from the nModes-th alone, a value just
  // past the tolerance could sit a rounding above the cluster's last member,
  // and the cut between them within rounding of both (theory §5).
  while (lo > 0 && omegas[lo] - omegas[lo - 1] <= tol) --lo;
  while (hi < n && omegas[hi] - omegas[hi - 1] <= tol) ++hi;
  // Just above the cluster: 10 cluster tolerances above its top, or the
  // middle of the gap to the next known value if that is nearer. A cut
  // farther out (the middle of a wide gap, as on the dense path, which
  // always knows the next value) would count modes the solver was never
  // asked for: on a dense spectrum (a 1e5-node chain) two of them lay within
  // 0.5 % above the 4th mode and failed a correct set.
  const double clusterTop = omegas[hi - 1];
  double cut = clusterTop * (1.0 + 10.0 * relClusterTol);
  if (hi < n) cut = std::min(cut, 0.5 * (clusterTop + omegas[hi]));
  if (!(cut > 0.0)) {  // every requested frequency is zero: nothing lies below a positive cut
    c.message = "no Sturm check: the requested frequencies are zero";
    return c;
  }
  if (hi > nModes) {
    std::ostringstream os;
    os << "the request cuts a cluster: modes " << lo + 1 << " to " << hi << " share " << top / (2.0 * M_PI)
       << " Hz, of which " << nModes - lo << " returned (ask for " << hi << " to have the whole cluster)";
    c.clusterNote = os.str();
  }
  const SparseSturmCount s = countBelow(cut);
  c.cut = s.omega;
  c.known = hi;
  c.counted = s.count;
  std::ostringstream os;
  if (!s.reliable) {
    c.verdict = LowestSetCheck::Verdict::Unreliable;
    os << "the set is not confirmed: no reliable Sturm count near " << cut << " rad/s (" << s.note << ")";
  } else if (s.count == hi) {
    c.verdict = LowestSetCheck::Verdict::Confirmed;
    os << "Sturm count at " << s.omega << " rad/s confirms the " << hi << " lowest";
    if (!s.note.empty()) os << " (" << s.note << ")";
  } else {
    c.verdict = LowestSetCheck::Verdict::Disagrees;
    os << "the Sturm count finds " << s.count << " frequencies below " << s.omega << " rad/s, the solver " << hi;
  }
  c.message = os.str();
  return c;
}

SetConfirmation confirmLowestSet(const std::function<std::string(std::string& confirmation)>& check,
                                 const std::string& firstSet, const std::function<std::string()>& recompute) {
  SetConfirmation c;
  std::string confirmation, why = check(confirmation);
  if (!why.empty()) {
    c.note = firstSet + " failed the check (" + why + "); " + recompute();
    why = check(confirmation);
  }
  c.complete = why.empty();
  c.note += (c.note.empty() ? "" : "; ") + (c.complete ? confirmation : "and still " + why);
  return c;
}

}  // namespace cms::eigen
