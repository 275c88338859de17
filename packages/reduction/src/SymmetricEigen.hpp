// Internal to the reduction package: the small dense symmetric-definite
// eigenproblem A x = lambda B x (column-major n x n, replicated), with the
// rounding asymmetry of projected matrices removed first.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include <Teuchos_LAPACK.hpp>

namespace cms::reduction::detail {

/// Ascending eigenvalues in w; with `vectors`, A holds the B-orthonormal
/// eigenvectors on return. Returns LAPACK dsygv's info (0: success).
inline int symmetricEigen(std::vector<double>& A, std::vector<double>& B, int n, bool vectors,
                          std::vector<double>& w) {
  // (Indices in size_t: i + j n overflows an int past n = 46,341, a
  // Partitioned part of many modes below its cut-off.)
  const std::size_t N = static_cast<std::size_t>(n);
  for (std::size_t j = 0; j < N; ++j)
    for (std::size_t i = 0; i < j; ++i) {
      A[i + j * N] = A[j + i * N] = 0.5 * (A[i + j * N] + A[j + i * N]);
      B[i + j * N] = B[j + i * N] = 0.5 * (B[i + j * N] + B[j + i * N]);
    }
  Teuchos::LAPACK<int, double> lapack;
  w.assign(n, 0.0);
  std::vector<double> work(std::max(1, 3 * n));
  int info = 0;
  lapack.SYGV(1, vectors ? 'V' : 'N', 'U', n, A.data(), n, B.data(), n, w.data(), work.data(),
              static_cast<int>(work.size()), &info);
  return info;
}

}  // namespace cms::reduction::detail
