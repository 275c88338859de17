// Sparse direct solvers on 1 and 2 ranks: accurate solves, definiteness
// reported by CHOLMOD, singular matrices refused rather than solved wrongly.
#include <gtest/gtest.h>

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_MultiVector.hpp>

#include "RotatingChain.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/SparseDirectSolver.hpp"

using namespace cms;
using Outcome = SparseDirectSolver::Outcome;

namespace {
Teuchos::RCP<const CrsMatrix> chainK(double spin, bool grounded = true) {
  fixtures::ChainSpec s;
  s.nodes = 150;
  s.spin = spin;
  s.support = grounded ? models::RotatingChain::Support::EveryNode : models::RotatingChain::Support::None;
  return fixtures::sparseChain(s, Teuchos::DefaultComm<int>::getComm()).K;
}

/// ||x - x0|| / ||x0|| for A x = A x0.
double forwardError(const CrsMatrix& A, const SparseDirectSolver& solver) {
  const auto map = A.getDomainMap();
  MultiVector x0(map, 3), b(map, 3), x(map, 3);
  x0.randomize();
  A.apply(x0, b);
  solver.solve(b, x);
  x.update(-1.0, x0, 1.0);
  Teuchos::Array<double> e(3), n(3);
  x.norm2(e());
  x0.norm2(n());
  double worst = 0.0;
  for (int j = 0; j < 3; ++j) worst = std::max(worst, e[j] / n[j]);
  return worst;
}
}  // namespace

// cond(K) <= ~1e5 here, so forward errors ~1e-11 at most; 1e-9 is safe.
TEST(SparseDirectSolver, SolvesAccuratelyOnAnyRankCount) {
  const auto spd = chainK(1.0), indefinite = chainK(4.0);
  for (const char* m : {"KLU2", "CHOLMOD"}) {
    SparseDirectSolver s(spd, m);
    ASSERT_EQ(s.factor(), Outcome::Factored) << m << ": " << s.failure();
    EXPECT_LT(forwardError(*spd, s), 1e-9) << m;
  }
  SparseDirectSolver lu(indefinite, "KLU2");
  ASSERT_EQ(lu.factor(), Outcome::Factored) << lu.failure();
  EXPECT_LT(forwardError(*indefinite, lu), 1e-9);
}

// Rows dealt round-robin (non-contiguous ids on each rank, as the eigen
// layer's state map has), solved for a block of right-hand sides: Amesos2
// mis-solved this on 2 ranks until the matrix was renumbered on rank 0.
TEST(SparseDirectSolver, NonContiguousMapWithBlockRightHandSides) {
  const auto K = chainK(4.0);
  const auto comm = K->getComm();
  const GlobalOrdinal N = static_cast<GlobalOrdinal>(K->getGlobalNumRows());
  Teuchos::Array<GlobalOrdinal> mine;
  for (GlobalOrdinal g = N - 1; g >= 0; --g)
    if (g % comm->getSize() == comm->getRank()) mine.push_back(g);
  auto map = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(N), mine(), 0, comm));
  auto Kp = Teuchos::rcp(new CrsMatrix(map, 0));
  Kp->doImport(*K, Tpetra::Import<>(K->getRowMap(), map), Tpetra::INSERT);
  Kp->fillComplete(map, map);
  for (const char* m : {"KLU2"}) {
    SparseDirectSolver s(Kp, m);
    ASSERT_EQ(s.factor(), Outcome::Factored) << s.failure();
    EXPECT_LT(forwardError(*Kp, s), 1e-9) << m;
  }
}

TEST(SparseDirectSolver, CholmodReportsIndefiniteMatrices) {
  SparseDirectSolver s(chainK(4.0), "CHOLMOD");
  EXPECT_EQ(s.factor(), Outcome::NotPositiveDefinite);
  EXPECT_NE(s.failure().find("not positive definite"), std::string::npos);
}

TEST(SparseDirectSolver, SingularMatrixIsRefusedNotSolved) {
  const auto singular = chainK(0.0, /*grounded=*/false);  // two rigid translations
  SparseDirectSolver lu(singular, "KLU2");
  EXPECT_EQ(lu.factor(), Outcome::Singular);
  SparseDirectSolver ch(singular, "CHOLMOD");
  EXPECT_NE(ch.factor(), Outcome::Factored);
}

TEST(SparseDirectSolver, UnknownMethodIsAnInputError) {
  // MUMPS is a method since issue 18 (DistributedDirectSolver); SuperLU is not.
  EXPECT_THROW(SparseDirectSolver(chainK(1.0), "SuperLU"), InputError);
}
