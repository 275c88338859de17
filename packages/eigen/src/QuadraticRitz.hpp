// Internal to the eigen package: gyroscopic modes from the converged
// vectors of the spectral transform (SparseEigenproblem.hpp for the roles),
// by a Rayleigh-Ritz projection of the quadratic problem onto the halves of
// those vectors, solved by the dense solver, each mode expanded and its
// residual recomputed from the full M, G, K (doc/theory.md, "Sparse path").
#pragma once

#include <vector>

#include "cms/core/TpetraTypes.hpp"
#include "cms/eigen/GyroscopicModes.hpp"
#include "cms/eigen/SparseGyroscopicSystem.hpp"

namespace cms::eigen::detail {

/// Every Ritz mode of span{q, v halves of `vectors`}, ordered by preference
/// of the transform (largest |1 / (lambda^2 - shift)| first), each with this
/// rank's rows of q (M-normalised, phase fixed by its largest entry),
/// backward error, energies, scale, growth uncertainty (those of
/// `refinement` refined where undecided), and classified (classifyModes).
/// Collective.
/// Which of them the solver returns (its first nModes within residualTol):
/// an undecided growth rate among them is refined by two-sided inverse
/// iteration on the full model (theory §13.3).
/// A damped (or circulatory) system's returned mode whose first-order
/// eigenvalue error exceeds frequencyTol |lambda| is refined too (theory §5,
/// "Stiff rows"): 0 refines every one, infinity none.
struct RitzRefinement {
  int nModes = 0;
  double residualTol = 1e-8;
  double frequencyTol = 1e-5;
};

std::vector<GyroscopicMode> quadraticRitzModes(const SparseGyroscopicSystem& sys, const MultiVector& vectors,
                                               double shift, double rigidTol, double instabTol,
                                               const RitzRefinement& refinement);

}  // namespace cms::eigen::detail
