// The energy bound on a damped system's growth rates (theory §13.3, "The
// energy bound"): with M > 0, no circulatory term (N = 0) and K > 0, the
// energy E = (q'^T M q' + q^T K q) / 2 of a free motion obeys
//   dE/dt = -q'^T D q'                    (G skew does no work)
// so where D + d M >= 0, dE/dt <= d q'^T M q' <= 2 d E, and no eigenvalue
// has Re lambda > d (Kelvin-Tait-Chetaev for d = 0). It decides what the
// computed growth rates cannot: a mode whose growth lies within its own
// uncertainty (which grows with K's condition on fine or stiff meshes) is
// stable where d is below the Instability Tolerance's share of it.
#pragma once

#include <vector>

#include "cms/eigen/GyroscopicModes.hpp"
#include "cms/eigen/GyroscopicSystem.hpp"

namespace cms::eigen {

/// The bound d for `sys` (symmetric M, K, D; skew G, N: the system the
/// solver solves, GyroscopicSystem::symmetrised), shown where N is absent or
/// zero and M, K and D + d M are proven positive definite
/// (cms::showPositiveDefinite: Cholesky of each shifted by Cholesky's
/// a-priori error, so rounding cannot make the proof; D + d M with the
/// rounding of its forming). The note says what was proven, or which
/// condition failed.
EnergyBound energyBound(const GyroscopicSystem& sys, double d);

/// Each mode's verdict against a shown bound: a mode that is not RigidBody
/// is Stable (not undecided) where the bound is within instabilityTol
/// |lambda|, whatever its computed growth's uncertainty. A mode the solve
/// called unstable (Divergence, Flutter) whose growth less its uncertainty
/// exceeds the bound contradicts it: the solve is wrong there; its verdict
/// stays and its index is returned (the solver reports a numerical issue).
std::vector<int> applyEnergyBound(std::vector<GyroscopicMode>& modes, const EnergyBound& bound,
                                  double instabilityTol);

}  // namespace cms::eigen
