#include "cms/analysis/Campbell.hpp"

#include <cmath>
#include <iomanip>
#include <ostream>

#include "cms/core/Error.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"

namespace cms::analysis {

eigen::GyroscopicSystem SpeedDependentSystem::at(double Omega) const {
  eigen::GyroscopicSystem s;
  s.M = M;
  s.G = G1;
  s.G.scale(Omega);
  s.K = K0;
  if (K2.numRows() > 0) {
    CMS_INPUT_CHECK(K2.numRows() != K0.numRows() || K2.numCols() != K0.numCols(),
                    "SpeedDependentSystem: K2 is " << K2.numRows() << "x" << K2.numCols()
                                                   << " but K0 is " << K0.numRows() << "x"
                                                   << K0.numCols());
    for (int j = 0; j < K0.numCols(); ++j)
      for (int i = 0; i < K0.numRows(); ++i) s.K(i, j) += Omega * Omega * K2(i, j);
  }
  return s;
}

const char* toString(Whirl w) {
  switch (w) {
    case Whirl::Forward: return "FW";
    case Whirl::Backward: return "BW";
    case Whirl::Undefined: return "--";
  }
  return "?";
}

Whirl whirlOf(const eigen::GyroscopicMode& mode, const std::vector<std::pair<int, int>>& pairs) {
  double s = 0.0, scale = 0.0;
  for (const auto& [v, w] : pairs) {
    s += std::imag(mode.q[v] * std::conj(mode.q[w]));
    scale += std::norm(mode.q[v]) + std::norm(mode.q[w]);
  }
  // A planar (non-whirling) orbit has s = 0; require a clear circulation.
  if (pairs.empty() || std::abs(s) <= 1e-6 * scale) return Whirl::Undefined;
  // Orbit (v, w) = Re((q_v, q_w) e^{i omega t}) turns positively about +x when
  // Im(q_v conj(q_w)) > 0 for omega > 0.
  return s > 0 ? Whirl::Forward : Whirl::Backward;
}

CampbellDiagram campbell(const SpeedDependentSystem& system, const std::vector<double>& speeds,
                         const Teuchos::ParameterList& solverParams) {
  eigen::DenseGyroscopicSolver solver(solverParams);
  CampbellDiagram d;
  for (double Omega : speeds) {
    CMS_INPUT_CHECK(!std::isfinite(Omega), "campbell: speed " << Omega << " is not finite");
    eigen::GyroscopicResult r = solver.solve(system.at(Omega));
    CampbellPoint p;
    p.speed = Omega;
    p.solver = r.solver;
    p.maxResidual = r.maxResidual();
    // Without spin the whirl sense of a repeated root is an arbitrary choice of basis.
    for (const auto& m : r.modes)
      p.whirl.push_back(Omega == 0.0 ? Whirl::Undefined : whirlOf(m, system.whirlPairs));
    p.modes = std::move(r.modes);
    d.points.push_back(std::move(p));
  }
  return d;
}

std::vector<CriticalSpeed> CampbellDiagram::criticalSpeeds(double engineOrder) const {
  std::vector<CriticalSpeed> out;
  for (std::size_t s = 1; s < points.size(); ++s) {
    const auto &a = points[s - 1], &b = points[s];
    const std::size_t nm = std::min(a.modes.size(), b.modes.size());
    for (std::size_t k = 0; k < nm; ++k) {
      const double fa = a.modes[k].omega - engineOrder * a.speed;
      const double fb = b.modes[k].omega - engineOrder * b.speed;
      if (fa == 0.0 || (fa < 0.0) != (fb < 0.0)) {
        if (fa == fb) continue;
        const double t = fa / (fa - fb);
        out.push_back({a.speed + t * (b.speed - a.speed), static_cast<int>(k),
                       t < 0.5 ? a.whirl[k] : b.whirl[k]});
      }
    }
  }
  return out;
}

std::vector<std::pair<double, double>> CampbellDiagram::instabilityRanges() const {
  std::vector<std::pair<double, double>> ranges;
  bool open = false;
  for (const auto& p : points) {
    bool unstable = false;
    for (const auto& m : p.modes)
      unstable |= m.stability == eigen::Stability::Divergence ||
                  m.stability == eigen::Stability::Flutter;
    if (unstable && !open) ranges.push_back({p.speed, p.speed}), open = true;
    if (unstable) ranges.back().second = p.speed;
    if (!unstable) open = false;
  }
  return ranges;
}

void CampbellDiagram::print(std::ostream& os, int numModes) const {
  const auto flags = os.flags();
  os << std::setw(9) << "rpm";
  for (int k = 0; k < numModes; ++k) os << std::setw(11) << ("f" + std::to_string(k + 1) + " Hz") << "   ";
  os << "  max resid  stability\n";
  for (const auto& p : points) {
    os << std::fixed << std::setprecision(0) << std::setw(9) << p.speed * 60.0 / (2.0 * M_PI);
    bool stable = true;
    for (int k = 0; k < numModes; ++k) {
      if (k < static_cast<int>(p.modes.size())) {
        const auto& m = p.modes[k];
        os << std::setprecision(3) << std::setw(11) << m.hz << " " << toString(p.whirl[k]);
        stable &= m.stability == eigen::Stability::Stable ||
                  m.stability == eigen::Stability::RigidBody || m.stability == eigen::Stability::Neutral ||
                  m.stability == eigen::Stability::Critical;
      } else {
        os << std::setw(14) << "";
      }
    }
    os << std::scientific << std::setprecision(1) << std::setw(11) << p.maxResidual << "  "
       << (stable ? "stable" : "UNSTABLE") << "\n";
    os.flags(flags);
  }
  os.flags(flags);
}

}  // namespace cms::analysis
