// The drivers' error boundary: cms::reportErrors and the table of outcomes
// (cms/core/ProgramBoundary.hpp, shared with the examples), and what a solve
// status means for a driver's exit code.
#pragma once

#include "cms/core/ProgramBoundary.hpp"
#include "cms/eigen/GyroscopicModes.hpp"

namespace cms::drivers {

using cms::condense;
using cms::Outcome;
using cms::reportErrors;

/// eigen::SolveStatus -> outcome: Converged 0, NotConverged 4, NumericalIssue 3.
inline Outcome outcome(eigen::SolveStatus s) {
  switch (s) {
    case eigen::SolveStatus::Converged: return kSuccess;
    case eigen::SolveStatus::NotConverged: return kNotConverged;
    case eigen::SolveStatus::NumericalIssue: return kBreakdown;
  }
  return kInternal;
}

}  // namespace cms::drivers
