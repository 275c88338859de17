// What the gyroscopic solvers share, as Anasazi's solver managers share
// Anasazi::SolverManager: the options, given once as a Teuchos::ParameterList
// and validated when the solver is built against the solver's own
// getValidParameters() (an unknown key or a wrong type throws
// cms::InputError naming the solver and the key), and one solve per system,
// whose every mode carries its residual recomputed from the system's own
// matrices. DenseGyroscopicSolver (reduced models, GyroscopicSystem) and
// SparseGyroscopicSolver (distributed full models, SparseGyroscopicSystem)
// are the two managers; the problem is the system, the iterations are
// theirs (doc/architecture.md, "eigen").
#pragma once

#include <Teuchos_ParameterList.hpp>

#include "cms/core/ParameterReading.hpp"
#include "cms/eigen/GyroscopicModes.hpp"

namespace cms::eigen {

template <class System>
class GyroscopicSolverManager {
public:
  virtual ~GyroscopicSolverManager() = default;
  /// The modes of `system` (collective for a distributed one). Not
  /// converging is a status of the result, not an exception.
  virtual GyroscopicResult solve(const System& system) const = 0;
  /// The options as validated, every default filled in.
  const Teuchos::ParameterList& parameters() const { return params_; }

protected:
  /// `solver` names the class in messages; `valid` is its getValidParameters().
  GyroscopicSolverManager(const Teuchos::ParameterList& params, const Teuchos::ParameterList& valid,
                          const char* solver)
      : params_(params) {
    validateOptions(params_, valid, solver);
  }
  Teuchos::ParameterList params_;
};

/// The stability tolerances every solver classifies its modes with
/// ("Rigid Body Tolerance", "Instability Tolerance": classifyModes), added
/// to a valid list with their defaults and documentation, once for both.
inline void addStabilityTolerances(Teuchos::ParameterList& valid) {
  valid.set("Rigid Body Tolerance", 1e-6,
            "|lambda| below this times the frequency scale sqrt(||K||/||M||)+||G||/||M|| is a "
            "rigid-body (zero-frequency) mode; rigid pairs form Jordan blocks, so their computed "
            "lambda carries an error ~sqrt(eps)");
  valid.set("Instability Tolerance", 1e-7,
            "Re(lambda) above this times the frequency scale is reported as divergence or "
            "flutter; below it the mode is stable (double roots at a critical speed split by "
            "~sqrt(eps))");
}

}  // namespace cms::eigen
