// Solve a substructure's gyroscopic eigenproblem at one spin speed with the
// sparse solver, and tell modes apart by the direction they move in: the
// share of a mode's translational amplitude along one component, reduced
// over ranks (mode shapes are distributed).
#pragma once

#include <array>
#include <complex>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Tpetra_Map.hpp>

#include "cms/eigen/SparseGyroscopicSolver.hpp"
#include "cms/substructure/Substructure.hpp"

namespace cms::fixtures {

inline eigen::GyroscopicResult solveAtSpeed(const substructure::Substructure& s, double omega, int modes) {
  const auto m = s.atSpeed(omega);
  Teuchos::ParameterList p;
  p.set("Number of Modes", modes);
  return eigen::SparseGyroscopicSolver(p).solve(eigen::SparseGyroscopicSystem{m.M, m.G, m.K});
}

/// sum |q_c|^2 / sum |q_ux|^2 + |q_uy|^2 + |q_uz|^2 over the whole structure.
inline double translationShare(const substructure::Substructure& s, const eigen::GyroscopicMode& mode,
                               fem::Component c) {
  const auto& map = *s.map();
  std::array<double, 2> local{0.0, 0.0}, global{0.0, 0.0};
  for (std::size_t i = 0; i < mode.q.size(); ++i) {
    const auto comp = s.dofs().components[map.getGlobalElement(static_cast<LocalOrdinal>(i))];
    if (static_cast<int>(comp) > 2) continue;
    const double a = std::norm(mode.q[i]);
    local[1] += a;
    if (comp == c) local[0] += a;
  }
  Teuchos::reduceAll(*map.getComm(), Teuchos::REDUCE_SUM, 2, local.data(), global.data());
  return global[1] > 0.0 ? global[0] / global[1] : 0.0;
}

}  // namespace cms::fixtures
