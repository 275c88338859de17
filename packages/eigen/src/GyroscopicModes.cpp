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

}  // namespace cms::eigen
