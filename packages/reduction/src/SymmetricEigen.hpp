// Internal to the reduction package: the small dense symmetric-definite
// eigenproblem A x = lambda B x (column-major n x n, replicated), with the
// rounding asymmetry of projected matrices removed first.
#pragma once

#include <algorithm>
#include <vector>

#include <Teuchos_LAPACK.hpp>

namespace cms::reduction::detail {

/// Ascending eigenvalues in w; with `vectors`, A holds the B-orthonormal
/// eigenvectors on return. Returns LAPACK dsygv's info (0: success).
inline int symmetricEigen(std::vector<double>& A, std::vector<double>& B, int n, bool vectors,
                          std::vector<double>& w) {
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < j; ++i) {
      A[i + j * n] = A[j + i * n] = 0.5 * (A[i + j * n] + A[j + i * n]);
      B[i + j * n] = B[j + i * n] = 0.5 * (B[i + j * n] + B[j + i * n]);
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
