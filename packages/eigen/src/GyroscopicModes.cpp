#include "cms/eigen/GyroscopicModes.hpp"

#include <algorithm>

namespace cms::eigen {

const char* toString(Stability s) {
  switch (s) {
    case Stability::Stable: return "stable";
    case Stability::RigidBody: return "rigid";
    case Stability::Divergence: return "DIVERGENCE";
    case Stability::Flutter: return "FLUTTER";
    case Stability::Neutral: return "neutral";
    case Stability::Critical: return "critical";
  }
  return "?";
}

const char* toString(SolveStatus s) {
  switch (s) {
    case SolveStatus::Converged: return "converged";
    case SolveStatus::NotConverged: return "NOT CONVERGED";
    case SolveStatus::NumericalIssue: return "NUMERICAL ISSUE";
  }
  return "?";
}

double GyroscopicResult::maxResidual() const {
  double r = 0.0;
  for (const auto& m : modes) r = std::max(r, m.residual);
  return r;
}

bool GyroscopicResult::isStable() const {
  return std::none_of(modes.begin(), modes.end(), [](const GyroscopicMode& m) {
    return m.stability == Stability::Divergence || m.stability == Stability::Flutter;
  });
}

double GyroscopicResult::leastDampingRatio() const {
  double z = 0.0;
  bool any = false;
  for (const auto& m : modes) {
    if (m.stability == Stability::RigidBody || m.stability == Stability::Critical) continue;
    z = any ? std::min(z, m.dampingRatio) : m.dampingRatio;
    any = true;
  }
  return z;
}

}  // namespace cms::eigen
