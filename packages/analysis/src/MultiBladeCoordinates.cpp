#include "cms/analysis/MultiBladeCoordinates.hpp"

#include <cmath>

#include "cms/core/Error.hpp"

namespace cms::analysis {

MultiBladeTransform::MultiBladeTransform(int blades, int dofsPerBlade) : N_(blades), nb_(dofsPerBlade) {
  CMS_INPUT_CHECK(blades < 3, "MultiBladeTransform: " << blades
                                                      << " blades; multi-blade coordinates need N >= 3 (with two "
                                                         "blades there is no cyclic pair and the system stays "
                                                         "periodic: use FloquetAnalysis)");
  CMS_INPUT_CHECK(dofsPerBlade < 1,
                  "MultiBladeTransform: " << dofsPerBlade << " coordinates per blade, at least 1 needed");
}

std::vector<std::string> MultiBladeTransform::names() const {
  std::vector<std::string> out{"0"};
  for (int n = 1; n <= (N_ - 1) / 2; ++n) {
    out.push_back(std::to_string(n) + "c");
    out.push_back(std::to_string(n) + "s");
  }
  if (N_ % 2 == 0) out.push_back("d");
  return out;
}

double MultiBladeTransform::basis(int m, int k, double psi, int r) const {
  if (m == 0) return r == 0 ? 1.0 : 0.0;
  if (N_ % 2 == 0 && m == N_ - 1) return r == 0 ? (k % 2 == 0 ? 1.0 : -1.0) : 0.0;  // (-1)^k: no psi
  const int n = (m + 1) / 2;                      // m = 2n - 1: cos, m = 2n: sin
  const double psik = psi + 2.0 * M_PI * k / N_;
  const double phase = n * psik + r * M_PI / 2.0;  // d^r/dpsi^r of cos (sin) x = n^r cos (sin)(x + r pi/2)
  return std::pow(double(n), r) * (m % 2 == 1 ? std::cos(phase) : std::sin(phase));
}

DenseMatrix MultiBladeTransform::matrix(double psi, int derivative) const {
  CMS_INPUT_CHECK(derivative < 0 || derivative > 2,
                  "MultiBladeTransform::matrix: derivative order " << derivative << ", expected 0, 1 or 2");
  DenseMatrix T(size(), size());
  for (int k = 0; k < N_; ++k)
    for (int m = 0; m < N_; ++m) {
      const double v = basis(m, k, psi, derivative);
      for (int j = 0; j < nb_; ++j) T(k * nb_ + j, m * nb_ + j) = v;
    }
  return T;
}

DenseMatrix MultiBladeTransform::inverse(double psi) const {
  DenseMatrix Ti(size(), size());
  for (int m = 0; m < N_; ++m) {
    const bool single = m == 0 || (N_ % 2 == 0 && m == N_ - 1);  // sum f_m^2 = N, else N / 2
    const double w = (single ? 1.0 : 2.0) / N_;
    for (int k = 0; k < N_; ++k) {
      const double v = w * basis(m, k, psi, 0);
      for (int j = 0; j < nb_; ++j) Ti(m * nb_ + j, k * nb_ + j) = v;
    }
  }
  return Ti;
}

namespace {
DenseMatrix blockDiagonal(int fixedDofs, const DenseMatrix& T) {
  const int n = fixedDofs + T.numRows();
  DenseMatrix B(n, n);
  for (int i = 0; i < fixedDofs; ++i) B(i, i) = 1.0;
  for (int j = 0; j < T.numCols(); ++j)
    for (int i = 0; i < T.numRows(); ++i) B(fixedDofs + i, fixedDofs + j) = T(i, j);
  return B;
}
/// B^T X B for square X.
DenseMatrix congruence(const DenseMatrix& B, const DenseMatrix& XB) {
  DenseMatrix out(B.numCols(), XB.numCols());
  gemm(true, false, 1.0, B, XB, 0.0, out);
  return out;
}
}  // namespace

SecondOrderMatrices MultiBladeTransform::toMultiBlade(const SecondOrderMatrices& q, double psi, double Omega,
                                                      int fixedDofs) const {
  const int n = fixedDofs + size();
  CMS_INPUT_CHECK(fixedDofs < 0, "MultiBladeTransform::toMultiBlade: fixedDofs = " << fixedDofs << " < 0");
  for (const DenseMatrix* X : {&q.M, &q.D, &q.K})
    CMS_INPUT_CHECK(X->numRows() != n || X->numCols() != n,
                    "MultiBladeTransform::toMultiBlade: a matrix is " << X->numRows() << " x " << X->numCols()
                                                                      << ", expected " << n << " x " << n << " ("
                                                                      << fixedDofs << " fixed + " << N_ << " blades x "
                                                                      << nb_ << ")");
  const DenseMatrix B = blockDiagonal(fixedDofs, matrix(psi, 0));
  DenseMatrix B1 = blockDiagonal(0, matrix(psi, 1)), B2 = blockDiagonal(0, matrix(psi, 2));
  {  // the fixed coordinates do not move with psi: zero blocks
    DenseMatrix b1(n, n), b2(n, n);
    for (int j = 0; j < size(); ++j)
      for (int i = 0; i < size(); ++i) {
        b1(fixedDofs + i, fixedDofs + j) = B1(i, j);
        b2(fixedDofs + i, fixedDofs + j) = B2(i, j);
      }
    B1 = b1;
    B2 = b2;
  }
  SecondOrderMatrices z;
  DenseMatrix X(n, n);
  gemm(false, false, 1.0, q.M, B, 0.0, X);  // M B
  z.M = congruence(B, X);
  gemm(false, false, 1.0, q.D, B, 0.0, X);  // D B + 2 Omega M B_psi
  gemm(false, false, 2.0 * Omega, q.M, B1, 1.0, X);
  z.D = congruence(B, X);
  gemm(false, false, 1.0, q.K, B, 0.0, X);  // K B + Omega D B_psi + Omega^2 M B_psipsi
  gemm(false, false, Omega, q.D, B1, 1.0, X);
  gemm(false, false, Omega * Omega, q.M, B2, 1.0, X);
  z.K = congruence(B, X);
  return z;
}

DenseMatrix MultiBladeTransform::observation(double psi, int fixedDofs) const {
  CMS_INPUT_CHECK(fixedDofs < 0, "MultiBladeTransform::observation: fixedDofs = " << fixedDofs << " < 0");
  return blockDiagonal(fixedDofs, inverse(psi));
}

}  // namespace cms::analysis
