// A dense gyroscopic system M q'' + G q' + K q = 0 (seed eq. (19)):
// M symmetric positive definite, G skew-symmetric (G = F^T - F),
// K symmetric (K = K_V - K_T, possibly indefinite or singular).
#pragma once

#include "cms/core/DenseMatrix.hpp"

namespace cms::eigen {

struct GyroscopicSystem {
  DenseMatrix M, G, K;

  int size() const { return M.numRows(); }

  /// Throws cms::InputError naming the matrix and the defect when the sizes
  /// disagree, a matrix is not square or empty, an entry is NaN/Inf, or M, K
  /// are not symmetric / G not skew-symmetric to `relTol` (relative to the
  /// size s^2||M|| + s||G|| + ||K|| of the quadratic at the frequency scale s). Positive definiteness of M is checked by the
  /// solver, which needs its Cholesky factor anyway.
  void validate(double relTol = 1e-10) const;

  /// The exactly symmetric (M, K) and skew (G) parts: solvers work on these,
  /// so rounding asymmetry in the input cannot leak into the results.
  GyroscopicSystem symmetrised() const;
};

}  // namespace cms::eigen
