// Sparse direct solvers on 1 and 2 ranks: accurate solves, definiteness
// reported by CHOLMOD, singular matrices refused rather than solved wrongly.
#include <gtest/gtest.h>

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_MultiVector.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

#include <map>

#include "RotatingChain.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/MatrixSum.hpp"
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

// matrixSum: on a shared graph, a A + b B costs values only (no graph of its
// own) and its entries are MatrixMatrix::add's to the bit (each a x + b y,
// one rounding of each product and one of the sum, either way).
TEST(MatrixSum, OnASharedGraphTheSameEntriesAsMatrixMatrixAdd) {
  const auto K = chainK(3.0);
  // B on K's graph with other values: K's entries times 0.37 plus 1.1.
  auto B = Teuchos::rcp(new CrsMatrix(K->getCrsGraph()));
  CrsMatrix::local_inds_host_view_type cols;
  CrsMatrix::values_host_view_type vals;
  for (LocalOrdinal r = 0; r < static_cast<LocalOrdinal>(K->getNodeNumRows()); ++r) {
    K->getLocalRowView(r, cols, vals);
    std::vector<double> v(vals.extent(0));
    for (std::size_t e = 0; e < v.size(); ++e) v[e] = 0.37 * vals(e) + 1.1;
    B->replaceLocalValues(r, cols, CrsMatrix::values_host_view_type(v.data(), v.size()));
  }
  B->fillComplete(K->getDomainMap(), K->getRangeMap());
  const double a = 1.0, b = -1234.567;
  const auto shared = matrixSum(a, *K, b, *B);
  EXPECT_EQ(shared->getCrsGraph().get(), K->getCrsGraph().get()) << "a graph of its own";
  const auto added = Tpetra::MatrixMatrix::add(a, false, *K, b, false, *B);
  // B on a graph of its own: matrixSum falls back to MatrixMatrix::add.
  const auto Bcopy = Tpetra::MatrixMatrix::add(1.0, false, *B, 0.0, false, *B);  // B's values, a new graph
  const auto fallback = matrixSum(a, *K, b, *Bcopy);
  EXPECT_NE(fallback->getCrsGraph().get(), K->getCrsGraph().get());
  auto entries = [](const CrsMatrix& A, GlobalOrdinal row) {
    const std::size_t n = A.getNumEntriesInGlobalRow(row);
    CrsMatrix::nonconst_global_inds_host_view_type c("c", n);
    CrsMatrix::nonconst_values_host_view_type v("v", n);
    std::size_t got = 0;
    A.getGlobalRowCopy(row, c, v, got);
    std::map<GlobalOrdinal, double> m;
    for (std::size_t e = 0; e < got; ++e) m[c(e)] += v(e);
    return m;
  };
  const auto map = K->getRowMap();
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
    const GlobalOrdinal g = map->getGlobalElement(static_cast<LocalOrdinal>(l));
    const auto want = entries(*added, g);
    EXPECT_EQ(entries(*shared, g), want) << "row " << g;
    EXPECT_EQ(entries(*fallback, g), want) << "row " << g;
  }
}
