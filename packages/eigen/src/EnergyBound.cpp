#include "cms/eigen/EnergyBound.hpp"

#include <cmath>
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
  const DefinitenessCheck k = showPositiveDefinite(sys.K);
  if (!k.shown) {
    b.note = "not shown: K > 0 not shown (" + k.why + ")";
    return b;
  }
  DenseMatrix A(sys.M);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) A(i, j) = d * sys.M(i, j) + (sys.D.numRows() == n ? sys.D(i, j) : 0.0);
  const DefinitenessCheck damping = showPositiveDefinite(A);
  std::ostringstream os;
  os.precision(3);
  if (!damping.shown) {
    os << "not shown: D + d M > 0 not shown at d = " << d << " 1/s (" << damping.why << ")";
    b.note = os.str();
    return b;
  }
  b.shown = true;
  b.growth = d;
  os << "no mode grows faster than " << d << " 1/s: N = 0, K > 0 and D + d M > 0 shown from their Cholesky "
     << "factors (margins " << k.margin << ", " << damping.margin << ")";
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
