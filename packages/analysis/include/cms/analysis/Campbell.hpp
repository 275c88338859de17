// Campbell diagram: the frequencies and stability of a rotating system over a
// range of spin speeds, from matrices stored per unit speed so that a sweep
// needs no reassembly (doc/theory.md, "Speed dependence"):
//   M q'' + Omega G1 q' + (K0 + Omega^2 K2) q = 0,
// with K2 = K_sigma1 - K_T1 (stress stiffening minus spin softening) in a
// rotating frame, or K2 = 0 for an axisymmetric rotor in the stationary frame.
#pragma once

#include <iosfwd>
#include <utility>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "cms/eigen/GyroscopicModes.hpp"
#include "cms/eigen/GyroscopicSystem.hpp"

namespace cms::analysis {

struct SpeedDependentSystem {
  DenseMatrix M, G1, K0, K2;  ///< K2 may be empty (0 x 0) for none
  /// Optional (v, w) coordinate pairs of two transverse directions whose
  /// orbit tells forward (with the spin) from backward whirl.
  std::vector<std::pair<int, int>> whirlPairs;

  eigen::GyroscopicSystem at(double Omega) const;
};

enum class Whirl { Forward, Backward, Undefined };
const char* toString(Whirl w);

/// Whirl sense of a mode from sum Im(q_v conj(q_w)) over the pairs: positive is
/// an orbit turning the same way as a spin about +x (doc/theory.md).
Whirl whirlOf(const eigen::GyroscopicMode& mode, const std::vector<std::pair<int, int>>& pairs);

struct CampbellPoint {
  double speed = 0.0;  ///< rad/s
  std::vector<eigen::GyroscopicMode> modes;
  std::vector<Whirl> whirl;
  std::string solver;
  double maxResidual = 0.0;
};

struct CriticalSpeed {
  double speed = 0.0;      ///< rad/s where a frequency curve meets engineOrder * Omega
  int modeIndex = 0;       ///< index in frequency order (0 = lowest)
  Whirl whirl = Whirl::Undefined;
};

struct CampbellDiagram {
  std::vector<CampbellPoint> points;
  /// Speeds at which the sorted frequency curves cross engineOrder * Omega
  /// (linear interpolation between sweep speeds).
  std::vector<CriticalSpeed> criticalSpeeds(double engineOrder = 1.0) const;
  /// [start, end] speed intervals where some mode is unstable.
  std::vector<std::pair<double, double>> instabilityRanges() const;
  /// The table an engineer reads: speed, each mode's frequency (Hz), whirl, stability.
  void print(std::ostream& os, int numModes) const;
};

/// Solve at each speed with eigen::DenseGyroscopicSolver configured by
/// `solverParams` (its valid parameters).
CampbellDiagram campbell(const SpeedDependentSystem& system, const std::vector<double>& speeds,
                         const Teuchos::ParameterList& solverParams);

}  // namespace cms::analysis
