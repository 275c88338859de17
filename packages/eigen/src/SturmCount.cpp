#include "cms/eigen/SturmCount.hpp"

#include <cmath>
#include <complex>
#include <vector>

#include "cms/core/Error.hpp"

extern "C" void zhetrf_(const char* uplo, const int* n, std::complex<double>* a, const int* lda,
                        int* ipiv, std::complex<double>* work, const int* lwork, int* info,
                        std::size_t);

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
  std::vector<int> ipiv(n);
  int info = 0, lwork = -1;
  std::complex<double> wq;
  zhetrf_("L", &n, Q.data(), &n, ipiv.data(), &wq, &lwork, &info, 1);
  lwork = std::max(1, static_cast<int>(wq.real()));
  std::vector<std::complex<double>> work(lwork);
  zhetrf_("L", &n, Q.data(), &n, ipiv.data(), work.data(), &lwork, &info, 1);
  TEUCHOS_TEST_FOR_EXCEPTION(info < 0, NumericalError, "sturmCount: LAPACK zhetrf failed, info = " << info);
  // info > 0 is an exactly zero 1x1 pivot: omega is an eigenfrequency to
  // working precision, and the count is taken as that of the nonzero pivots.
  // Inertia of D (Sylvester): 1x1 pivots by sign; a 2x2 block [a b; conj(b) c]
  // has one eigenvalue of each sign when a c - |b|^2 < 0, else both of a's sign.
  int negative = 0;
  for (int k = 0; k < n;) {
    const auto d = [&](int i, int j) { return Q[static_cast<std::size_t>(j) * n + i]; };
    if (ipiv[k] > 0) {
      negative += d(k, k).real() < 0.0;
      k += 1;
    } else {
      const double a = d(k, k).real(), c = d(k + 1, k + 1).real(), b2 = std::norm(d(k + 1, k));
      const double det = a * c - b2;
      negative += det < 0.0 ? 1 : (a < 0.0 ? 2 : 0);
      k += 2;
    }
  }
  return negative;
}

}  // namespace cms::eigen
