// Internal to the reduction package: K with a set of DOFs held at zero
// (cms::holdDofs), factored once and solved many times: the static solves
// of admissible vectors and constraint modes and the inverse of the
// fixed-interface eigenproblem. Factored by CHOLMOD gathered to rank 0, or
// by MUMPS across the ranks ("Reduction" -> "Direct Solver", issue 18).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cms/core/HeldDofs.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/reduction/FixedInterfaceModes.hpp"
#include "cms/substructure/Substructure.hpp"

namespace cms::reduction::detail {

/// The "Reduction" -> "Direct Solver" choice ("Auto", "CHOLMOD", "MUMPS")
/// in force on this thread while buildRitzBasis runs: the basis functions
/// (admissibleVectors, craigBamptonBasis, ...) take no solver argument, so
/// that their public headers, which the synthesis layer includes
/// everywhere, stay as they are. "Auto" outside any scope (StaticCorrection,
/// direct calls): MUMPS when the substructure is distributed over several
/// ranks and has at least kDistributedAutoEntriesReduction entries
/// (cms::useDistributedSolver), CHOLMOD otherwise.
class DirectSolverScope {
public:
  explicit DirectSolverScope(std::string choice);
  ~DirectSolverScope();
  DirectSolverScope(const DirectSolverScope&) = delete;
  DirectSolverScope& operator=(const DirectSolverScope&) = delete;
  static const std::string& current();

private:
  std::string previous_;
};

/// A factorisation already made of K with some DOFs held (the prestress
/// solve's: fem::AssembledMatrices::stiffnessFactor), offered to every
/// HeldStiffness built on this thread while the scope lives: one whose
/// substructure's K and held rows are the factor's adopts it instead of
/// factoring again (theory §11.4). Like DirectSolverScope, it keeps the
/// basis functions' signatures as they are.
class OfferedFactorScope {
public:
  explicit OfferedFactorScope(std::shared_ptr<const HeldFactor> factor);
  ~OfferedFactorScope();
  OfferedFactorScope(const OfferedFactorScope&) = delete;
  OfferedFactorScope& operator=(const OfferedFactorScope&) = delete;
  /// Whether a HeldStiffness adopted the offer.
  bool adopted() const;

private:
  std::shared_ptr<const HeldFactor> previous_;
  bool previousAdopted_;
};

/// Whether `f` factored what a HeldStiffness of `s` with `held` (any order,
/// duplicates allowed) under the "Direct Solver" choice `directSolver`
/// would factor: the same K object (nothing changes its values after
/// assembly), the same set of held rows, and CHOLMOD, which that choice
/// would pick here. Collective (the choice may look at the matrix's size).
bool factorFits(const HeldFactor& f, const substructure::Substructure& s, std::vector<GlobalOrdinal> held,
                const std::string& directSolver);

/// Why a substructure's stiffness with its attachment (or reference) DOFs
/// held is not positive definite, as every basis that factors it says so:
/// the rigid motions and hinges it can still have, or a matrix singular to
/// working precision.
std::string notPositiveDefiniteReasons();

class HeldStiffness {
public:
  /// Throws cms::NumericalError naming the substructure when K with `held`
  /// fixed is not positive definite (an unrestrained substructure).
  HeldStiffness(const substructure::Substructure& s, std::vector<GlobalOrdinal> held);
  /// X = K_held^-1 B with B's held rows ignored (set to zero): X is zero there.
  /// The solve checks its residual with the product K_held X; given `KX`
  /// (X's shape), that product is left there: K X on the free rows, since X
  /// vanishes on the held ones (admissibleVectors needs it, one sparse
  /// product fewer per vector).
  void solve(const MultiVector& B, MultiVector& X, MultiVector* KX = nullptr) const;
  const std::vector<GlobalOrdinal>& held() const { return held_; }
  Teuchos::RCP<const CrsMatrix> matrix() const { return K_; }
  /// The SparseDirectSolver method that factored it: "CHOLMOD" or "MUMPS-LDLT".
  const std::string& method() const { return solver_->method(); }
  /// The factorisation's flop count (CHOLMOD's analysis, or MUMPS's).
  double factorFlops() const { return solver_->factorFlops(); }
  /// Whether it adopted an offered factorisation (OfferedFactorScope).
  bool adopted() const { return adopted_; }

private:
  std::vector<GlobalOrdinal> held_;
  std::string name_;
  Teuchos::RCP<const CrsMatrix> K_;
  std::shared_ptr<const SparseDirectSolver> solver_;
  bool adopted_ = false;
};

/// fixedInterfaceModes with an existing factorisation of K with the held
/// rows (Craig-Bampton shares it with its static solves).
RitzBasis fixedInterfaceModes(const substructure::Substructure& s, const HeldStiffness& K, int count,
                              double eigensolverTolerance, double dependenceTolerance,
                              const ModeConstraints& constraints, const SturmCut& cut = {});

}  // namespace cms::reduction::detail
