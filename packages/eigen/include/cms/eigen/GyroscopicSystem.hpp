// A dense gyroscopic system M q'' + (G + D) q' + (K + N) q = 0 (seed eq. (19)
// with damping, theory §13): M symmetric positive definite, G skew-symmetric
// (G = F^T - F), K symmetric (K = K_V - K_T, possibly indefinite or
// singular); optionally a viscous damping matrix D (symmetric, >= 0 for a
// passive structure) and a circulatory matrix N (skew: rotating internal
// damping seen from a stationary frame). Either makes the system
// non-conservative: only the general first-order path applies.
#pragma once

#include <vector>

#include "cms/core/DenseMatrix.hpp"

namespace cms::eigen {

struct GyroscopicSystem {
  DenseMatrix M, G, K;
  /// Viscous damping (symmetric); 0 x 0 (the default) for none.
  DenseMatrix D;
  /// Circulatory stiffness (skew-symmetric), e.g. Omega c_i J of a rotor's
  /// internal damping in stationary coordinates; 0 x 0 for none.
  DenseMatrix N;
  /// Coordinates on which the stiffness at rest vanishes exactly, rows and
  /// columns (a free structure's six rigid-body coordinates, theory §11.6),
  /// ascending; empty for none. Their modes live on a scale of their own
  /// (the spin rate), which a solve of the whole system resolves only to
  /// its own normwise scale, so the general path solves them again through
  /// the Schur complement of the other coordinates (theory §4.3).
  std::vector<int> unrestrained;
  /// Optional, entrywise >= 0: the magnitudes of the parts K was summed
  /// from, |K_0| + sum |s_i s_j| |K_ij| (K(Omega) = K_0 + Omega^2 (K_S1 -
  /// K_T1)), where each part was assembled entry by entry (no products of
  /// reduced bases, whose entries cancel). K's entries then carry rounding
  /// of a few eps of these, not of |K|: at a critical speed K_0 and
  /// Omega^2 K_T1 cancel. The dense solver bounds what rounding can do to a
  /// mode near zero with it (theory §4.3, "A zero shown nonzero"). 0 x 0:
  /// not known (the zero tests stay on the system's scale).
  DenseMatrix KMagnitude;

  int size() const { return M.numRows(); }
  /// D or N present and not all zero: the spectrum is no longer Hamiltonian.
  bool damped() const;

  /// Throws cms::InputError naming the matrix and the defect when the sizes
  /// disagree, a matrix is not square or empty, an entry is NaN/Inf, or M, K
  /// (and D when present) are not symmetric / G (and N) not skew-symmetric to `relTol` (relative to the
  /// size s^2||M|| + s||G|| + ||K|| of the quadratic at the frequency scale s). Positive definiteness of M is checked by the
  /// solver, which needs its Cholesky factor anyway. `unrestrained` must
  /// ascend strictly within [0, n).
  void validate(double relTol = 1e-10) const;

  /// The exactly symmetric (M, K, D) and skew (G, N) parts: solvers work on these,
  /// so rounding asymmetry in the input cannot leak into the results.
  GyroscopicSystem symmetrised() const;
};

}  // namespace cms::eigen
