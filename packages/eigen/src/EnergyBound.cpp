#include "cms/eigen/EnergyBound.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "cms/core/DenseMatrix.hpp"

namespace cms::eigen {

EnergyBound energyBound(const GyroscopicSystem& sys, double d) {
  EnergyBound b;
  const int n = sys.size();
  // A circulatory N does work, -q'^T N q, of either sign: no bound.
  if (sys.N.numRows() == n && n > 0 && frobeniusNorm(sys.N) > 0.0) {
    b.note = "not shown: N != 0 (circulatory forces can feed the motion energy)";
    return b;
  }
  if (!(d >= 0.0) || !std::isfinite(d)) {
    b.note = "not shown: no bound asked for";
    return b;
  }
  // M > 0 carries the argument (E >= q'^T M q' / 2); the solver's own
  // Cholesky of M succeeding is not a proof.
  const DefinitenessCheck mass = showPositiveDefinite(sys.M);
  if (!mass.shown) {
    b.note = "not shown: M > 0 not shown (" + mass.why + ")";
    return b;
  }
  const DefinitenessCheck k = showPositiveDefinite(sys.K);
  if (!k.shown) {
    b.note = "not shown: K > 0 not shown (" + k.why + ")";
    return b;
  }
  // D + d M as formed, and what forming it rounded: each entry a product
  // and a sum, |error| <= 2 u (d |m_ij| + |d_ij|) to first order (2.01 u).
  DenseMatrix A(n, n), F(n, n);
  const double u = std::numeric_limits<double>::epsilon() / 2.0;
  const bool hasD = sys.D.numRows() == n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double dm = d * sys.M(i, j), dd = hasD ? sys.D(i, j) : 0.0;
      A(i, j) = dm + dd;
      F(i, j) = 2.01 * u * (std::abs(dm) + std::abs(dd));
    }
  const DefinitenessCheck damping = showPositiveDefinite(A, &F);
  std::ostringstream os;
  os.precision(3);
  if (!damping.shown) {
    os << "not shown: D + d M > 0 not shown at d = " << d << " 1/s (" << damping.why << ")";
    b.note = os.str();
    return b;
  }
  b.shown = true;
  b.growth = d;
  os << "no mode grows faster than " << d << " 1/s: N = 0, and M > 0, K > 0 and D + d M > 0 proven from "
     << "Cholesky factors of their shifts by Cholesky's a-priori error (" << mass.shift << ", " << k.shift << ", "
     << damping.shift << " on the unit diagonal)";
  b.note = os.str();
  return b;
}

std::vector<int> applyEnergyBound(std::vector<GyroscopicMode>& modes, const EnergyBound& bound,
                                  double instabilityTol) {
  std::vector<int> contradicted;
  if (!bound.shown) return contradicted;
  for (int j = 0; j < static_cast<int>(modes.size()); ++j) {
    auto& m = modes[j];
    if (m.stability == Stability::RigidBody || m.stability == Stability::Critical) continue;
    const bool unstable = m.stability == Stability::Divergence || m.stability == Stability::Flutter;
    if (unstable && m.lambda.real() - m.growthTolerance > bound.growth) {
      contradicted.push_back(j);
      continue;
    }
    if (bound.growth <= instabilityTol * std::abs(m.lambda)) {
      m.stability = Stability::Stable;
      m.undecided = false;
    }
  }
  return contradicted;
}

}  // namespace cms::eigen
