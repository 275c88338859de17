#include "HeldStiffness.hpp"

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/SparseProduct.hpp"
#include "cms/core/DistributedDirectSolver.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/HeldDofs.hpp"

#include <algorithm>
#include <string>

#include <Teuchos_Array.hpp>

namespace cms::reduction::detail {

namespace {
thread_local std::string currentDirectSolver = "Auto";
thread_local std::shared_ptr<const HeldFactor> offeredFactor;
thread_local bool offerAdopted = false;
}  // namespace

DirectSolverScope::DirectSolverScope(std::string choice) : previous_(currentDirectSolver) {
  currentDirectSolver = std::move(choice);
}
DirectSolverScope::~DirectSolverScope() { currentDirectSolver = previous_; }
const std::string& DirectSolverScope::current() { return currentDirectSolver; }

OfferedFactorScope::OfferedFactorScope(std::shared_ptr<const HeldFactor> factor)
    : previous_(std::move(offeredFactor)), previousAdopted_(offerAdopted) {
  offeredFactor = std::move(factor);
  offerAdopted = false;
}
OfferedFactorScope::~OfferedFactorScope() {
  offeredFactor = std::move(previous_);
  offerAdopted = previousAdopted_;
}
bool OfferedFactorScope::adopted() const { return offerAdopted; }

bool factorFits(const HeldFactor& f, const substructure::Substructure& s, std::vector<GlobalOrdinal> held,
                const std::string& directSolver) {
  std::sort(held.begin(), held.end());
  held.erase(std::unique(held.begin(), held.end()), held.end());
  return f.base.get() == s.K().get() && f.held == held && f.solver->method() == "CHOLMOD" &&
         !useDistributedSolver(directSolver, *f.matrix, kDistributedAutoEntriesReduction);
}

HeldStiffness::HeldStiffness(const substructure::Substructure& s, std::vector<GlobalOrdinal> held)
    : held_(std::move(held)), name_(s.name()) {
  // The prestress solve factored this very matrix: adopt it.
  const auto& offer = offeredFactor;
  if (offer && factorFits(*offer, s, held_, DirectSolverScope::current())) {
    K_ = offer->matrix;
    solver_ = offer->solver;
    adopted_ = offerAdopted = true;
    return;
  }
  // Nothing held (a substructure clamped by its own supports): K itself,
  // not a copy (issue 18: one n x n matrix fewer, kept with the factor).
  K_ = held_.empty() ? s.K() : Teuchos::RCP<const CrsMatrix>(holdDofsScaled(*s.K(), held_));
  const bool mumps = useDistributedSolver(DirectSolverScope::current(), *K_, kDistributedAutoEntriesReduction);
  auto solver = std::make_shared<SparseDirectSolver>(K_, mumps ? "MUMPS-LDLT" : "CHOLMOD");
  solver_ = solver;
  if (solver->factor() != SparseDirectSolver::Outcome::Factored)
    throw NumericalError(s.name() + ": the stiffness with the attachment (or reference) DOFs held is not "
                         "positive definite: " + notPositiveDefiniteReasons() + " (" + solver_->failure() + ")");
}

std::string notPositiveDefiniteReasons() {
  return "the substructure can still move as a rigid body (check its supports and attachment) or about a hinge "
         "without Stiffness (a reduced basis needs a hinge spring; Basis: Full does not), or it is singular to "
         "working precision (elements much shorter than their section, stiffness ratios past 1e12)";
}

void HeldStiffness::solve(const MultiVector& B, MultiVector& X, MultiVector* KX) const {
  MultiVector b(B, Teuchos::Copy);
  zeroHeldRows(b, held_);
  solver_->solve(b, X);
  zeroHeldRows(X, held_);  // exact zeros, not rounding-sized values
  // A Cholesky solve is backward stable, so ||K x - b|| / ||b|| is small
  // unless K is ill-conditioned. Any vector vanishing on the held rows is
  // admissible, so an inaccurate one still gives Rayleigh-Ritz bounds; but
  // past 1% of the load the vector is mostly rounding (K singular to
  // working precision: frame elements far shorter than their section,
  // stiffness ratios past 1e12) and the frequencies built from such vectors
  // were wrong with a converged status. Refuse instead (theory §11.7).
  MultiVector r(b.getMap(), b.getNumVectors());
  multiply(*K_, X, r);
  if (KX != nullptr) KX->assign(r);
  r.update(-1.0, b, 1.0);
  Teuchos::Array<double> rn(b.getNumVectors()), bn(b.getNumVectors());
  r.norm2(rn());
  b.norm2(bn());
  for (std::size_t j = 0; j < b.getNumVectors(); ++j)
    if (rn[j] > 1e-2 * bn[j])
      throw NumericalError(name_ + ": the stiffness with the attachment held is singular to working precision "
                           "(a static solve's residual is " + std::to_string(rn[j] / bn[j]) +
                           " of its load): refine less, or check for elements much shorter than their section");
}

}  // namespace cms::reduction::detail
