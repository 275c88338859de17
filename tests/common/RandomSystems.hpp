// Seeded random gyroscopic systems for property tests. Header-only: test code.
#pragma once

#include <algorithm>
#include <complex>
#include <random>
#include <vector>

#include <Teuchos_LAPACK.hpp>

#include "cms/core/DenseMatrix.hpp"
#include "cms/eigen/GyroscopicSystem.hpp"

namespace cms::fixtures {

inline DenseMatrix randomMatrix(int m, int n, std::mt19937& rng) {
  std::normal_distribution<double> d(0.0, 1.0);
  DenseMatrix A(m, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < m; ++i) A(i, j) = d(rng);
  return A;
}

/// B B^T / n + shift I: symmetric positive definite, condition ~ (4 + shift)/shift.
inline DenseMatrix randomSpd(int n, double shift, std::mt19937& rng) {
  DenseMatrix B = randomMatrix(n, n, rng), A;
  gemm(false, true, 1.0 / n, B, B, 0.0, A);
  for (int i = 0; i < n; ++i) A(i, i) += shift;
  return A;
}

inline DenseMatrix randomSkew(int n, double scale, std::mt19937& rng) {
  DenseMatrix B = randomMatrix(n, n, rng), G(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) G(i, j) = scale * (B(i, j) - B(j, i)) / std::sqrt(double(n));
  return G;
}

inline eigen::GyroscopicSystem randomGyroscopic(int n, std::mt19937& rng, double gyro = 1.0) {
  return {randomSpd(n, 0.5, rng), randomSkew(n, gyro, rng), randomSpd(n, 1.0, rng)};
}

/// V^T A V.
inline DenseMatrix project(const DenseMatrix& A, const DenseMatrix& V) {
  DenseMatrix AV, VtAV;
  gemm(false, false, 1.0, A, V, 0.0, AV);
  gemm(true, false, 1.0, V, AV, 0.0, VtAV);
  return VtAV;
}

inline eigen::GyroscopicSystem project(const eigen::GyroscopicSystem& s, const DenseMatrix& V) {
  return {project(s.M, V), project(s.G, V), project(s.K, V)};
}

/// An independent reference: eigenvalues of the companion matrix
/// [[0, I], [-M^-1 K, -M^-1 G]] by LAPACK dgeev (M^-1 by dgesv), i.e. a plain
/// nonsymmetric solution that shares no code with the solvers under test.
inline std::vector<std::complex<double>> companionEigenvalues(const eigen::GyroscopicSystem& s) {
  const int n = s.size(), N = 2 * n;
  DenseMatrix Mc(s.M), R(n, 2 * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) R(i, j) = s.K(i, j), R(i, n + j) = s.G(i, j);
  std::vector<int> piv(n);
  int info = 0;
  Teuchos::LAPACK<int, double> lapack;
  lapack.GESV(n, 2 * n, Mc.values(), n, piv.data(), R.values(), n, &info);
  DenseMatrix H(N, N);
  for (int i = 0; i < n; ++i) H(i, n + i) = 1.0;
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < n; ++i) H(n + i, j) = -R(i, j);
  std::vector<double> wr(N), wi(N), work(8 * N);
  double dummy = 0.0;
  lapack.GEEV('N', 'N', N, H.values(), N, wr.data(), wi.data(), &dummy, 1, &dummy, 1, work.data(),
              static_cast<int>(work.size()), nullptr, &info);
  std::vector<std::complex<double>> ev;
  for (int i = 0; i < N; ++i) ev.emplace_back(wr[i], wi[i]);
  return ev;
}

/// Positive imaginary parts of the companion eigenvalues, ascending: the
/// frequencies of a stable system.
inline std::vector<double> companionFrequencies(const eigen::GyroscopicSystem& s) {
  std::vector<double> w;
  for (auto l : companionEigenvalues(s))
    if (l.imag() > 0) w.push_back(l.imag());
  std::sort(w.begin(), w.end());
  return w;
}

}  // namespace cms::fixtures
