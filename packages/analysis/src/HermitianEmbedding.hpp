// A Hermitian k x k matrix as the real symmetric 2k x 2k one LAPACK's
// dsyev takes, and that eigensolve: shared by the whirl rule's pencils
// (WhirlClassification.cpp) and the truth comparison's subspace MAC
// (TruthComparison.cpp). Internal to the analysis package.
#pragma once

#include <algorithm>
#include <complex>
#include <string>
#include <vector>

#include <Teuchos_LAPACK.hpp>

#include "cms/core/Error.hpp"

namespace cms::analysis::detail {

/// The real symmetric 2k x 2k embedding [[Re H, -Im H], [Im H, Re H]] of a
/// Hermitian k x k H (column-major): z^H H z = [x; y]^T S [x; y] for
/// z = x + i y, and each eigenvalue of H appears twice. Column-major.
inline std::vector<double> hermitianEmbedding(const std::vector<std::complex<double>>& H, int k) {
  const int n = 2 * k;
  std::vector<double> S(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      const auto h = H[i + k * j];
      S[i + n * j] = h.real(), S[(i + k) + n * (j + k)] = h.real();
      S[(i + k) + n * j] = h.imag(), S[i + n * (j + k)] = -h.imag();
    }
  return S;
}

/// Eigenvalues (ascending) and, in `A` on return, eigenvectors (columns) of
/// the symmetric n x n matrix A (column-major), by dsyev. A NumericalError
/// naming `who` when LAPACK fails.
inline std::vector<double> symmetricEigen(std::vector<double>& A, int n, const char* who) {
  std::vector<double> w(n);
  if (n == 0) return w;
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  double query = 0.0;
  lapack.SYEV('V', 'U', n, A.data(), n, w.data(), &query, -1, &info);
  std::vector<double> work(std::max(1, static_cast<int>(query)));
  lapack.SYEV('V', 'U', n, A.data(), n, w.data(), work.data(), static_cast<int>(work.size()), &info);
  if (info != 0) throw NumericalError(std::string(who) + ": LAPACK dsyev failed (info " + std::to_string(info) + ")");
  return w;
}

}  // namespace cms::analysis::detail
