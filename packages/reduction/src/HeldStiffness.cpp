#include "HeldStiffness.hpp"

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/HeldDofs.hpp"

namespace cms::reduction::detail {

HeldStiffness::HeldStiffness(const substructure::Substructure& s, std::vector<GlobalOrdinal> held)
    : held_(std::move(held)) {
  K_ = holdDofsScaled(*s.K(), held_);
  solver_ = std::make_unique<SparseDirectSolver>(K_, "CHOLMOD");
  if (solver_->factor() != SparseDirectSolver::Outcome::Factored)
    throw NumericalError(s.name() + ": the stiffness with the attachment (or reference) DOFs held is not "
                         "positive definite, so the substructure can still move as a rigid body: check its "
                         "supports and attachment (CHOLMOD: " + solver_->failure() + ")");
}

void HeldStiffness::solve(const MultiVector& B, MultiVector& X) const {
  MultiVector b(B, Teuchos::Copy);
  zeroHeldRows(b, held_);
  solver_->solve(b, X);
  zeroHeldRows(X, held_);  // exact zeros, not rounding-sized values
}

}  // namespace cms::reduction::detail
