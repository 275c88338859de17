// Sparse direct solvers on 1 and 2 ranks: accurate solves, definiteness
// reported by CHOLMOD, singular matrices refused rather than solved wrongly.
#include <gtest/gtest.h>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

#include <malloc.h>

#include <cmath>
#include <map>
#include <string>

#include "RotatingChain.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/HeldDofs.hpp"
#include "cms/core/MatrixSum.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/core/SparseInertia.hpp"
#include "cms/core/SparseProduct.hpp"

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

// Solves with the transpose from the same factors (inverse iteration's left
// vectors, theory §13.3): the real form [[K, -B], [B, K]] with B = 0.3 K is
// not symmetric, and A^T x = A^T x0 must give x0 back by MUMPS as A x = A x0
// does (1e-9: cond <= ~1e5 as above), where a plain solve of the same
// right-hand side does not (0.57 here); CHOLMOD's symmetric K is its own
// transpose. KLU2 is refused: Amesos2 13.2's "Transpose" control gave
// forward errors of 2.4 and 3.4 (tried, not used).
TEST(SparseDirectSolver, SolvesWithTheTransposeFromTheSameFactors) {
  const auto K = chainK(1.0);
  auto B = matrixSum(0.3, *K, 0.0, *K);
  const auto map2 = stateMap(*K->getRowMap());
  const Teuchos::RCP<const CrsMatrix> A = realEmbedding(*K, *B, map2);
  for (const char* m : {"MUMPS", "CHOLMOD"}) {
    const bool symmetric = std::string(m) == "CHOLMOD";
    const auto& matrix = symmetric ? K : A;
    SparseDirectSolver s(matrix, m);
    ASSERT_EQ(s.factor(), Outcome::Factored) << m << ": " << s.failure();
    const auto map = matrix->getDomainMap();
    MultiVector x0(map, 2), b(map, 2), x(map, 2), plain(map, 2);
    x0.randomize();
    matrix->apply(x0, b, Teuchos::TRANS);
    s.solveTransposed(b, x);
    s.solve(b, plain);
    x.update(-1.0, x0, 1.0);
    plain.update(-1.0, x0, 1.0);
    Teuchos::Array<double> e(2), p(2), n(2);
    x.norm2(e()), plain.norm2(p()), x0.norm2(n());
    for (int j = 0; j < 2; ++j) {
      EXPECT_LT(e[j] / n[j], 1e-9) << m;
      if (!symmetric) EXPECT_GT(p[j] / n[j], 1e-3) << m << ": the plain solve should differ";
    }
  }
  SparseDirectSolver klu(A, "KLU2");
  ASSERT_EQ(klu.factor(), Outcome::Factored) << klu.failure();
  MultiVector b(A->getDomainMap(), 1), x(A->getDomainMap(), 1);
  b.putScalar(1.0);
  EXPECT_THROW(klu.solveTransposed(b, x), std::logic_error);
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

TEST(SparseDirectSolver, ScaledDiagonalIsNotRoundingDefinite) {
  // D K D with K the grounded chain (positive definite, cond <= ~1e5) and D
  // powers of 2 from 1 to 2^-40 (exact scaling): CHOLMOD's pivot ratio
  // estimate (min/max diag L)^2 is ~2^-80 ~ 1e-24, far below its 1e-14, yet
  // every pivot keeps what it kept in K. Refused as "definite only to
  // rounding" before; factored now, and the solve's residual is that of a
  // backward-stable solve.
  const auto K = chainK(1.0);
  auto d = Teuchos::rcp(new Vector(K->getRowMap()));
  {
    auto v = d->getDataNonConst();
    for (std::size_t l = 0; l < v.size(); ++l)
      v[l] = std::ldexp(1.0, -static_cast<int>(K->getRowMap()->getGlobalElement(l) % 41));
  }
  auto DKD = Teuchos::rcp(new CrsMatrix(*K, Teuchos::Copy));
  DKD->leftScale(*d);
  DKD->rightScale(*d);
  SparseDirectSolver s(DKD, "CHOLMOD");
  ASSERT_EQ(s.factor(), Outcome::Factored) << s.failure();
  MultiVector x0(DKD->getDomainMap(), 1), b(DKD->getRangeMap(), 1), x(DKD->getDomainMap(), 1), r(b);
  x0.randomize();
  DKD->apply(x0, b);
  s.solve(b, x);
  DKD->apply(x, r);
  r.update(-1.0, b, 1.0);
  // Backward stable: ||A x - b|| <= c n eps ||A|| ||x||, c n = 1e3 for 150
  // nodes' banded factor.
  Teuchos::Array<double> rn(1), xn(1);
  r.norm2(rn());
  x.norm2(xn());
  EXPECT_LT(rn[0], 1e3 * 2.2e-16 * DKD->getFrobeniusNorm() * xn[0]);
  // The free chain is still refused: its rigid motion's pivot is rounding.
  SparseDirectSolver free(chainK(0.0, /*grounded=*/false), "CHOLMOD");
  EXPECT_NE(free.factor(), Outcome::Factored);
}

// Positive definite but ill-conditioned (cond ~1e12: the free chain held
// by springs 1e-12 of its stiffest diagonal): definite for CHOLMOD's test
// (pivot ratio above 1e-14) and so for MUMPS-LDLT's, whose pivots are the
// same test. MUMPS-LDLT also ran the LU codes' singularity probe (forward
// error below 1e-6, i.e. cond below ~5e9) and called this matrix singular,
// so a sparse solve on MUMPS took the general path and lost its Sturm
// check, where CHOLMOD's did not (found by a review).
TEST(SparseDirectSolver, IllConditionedDefiniteMatrixIsDefiniteForBothLdlts) {
  const auto K = chainK(0.0, /*grounded=*/false);
  double kmax = 0.0;
  {
    Vector d(K->getRowMap());
    K->getLocalDiagCopy(d);
    const double local = d.normInf();
    Teuchos::reduceAll(*K->getComm(), Teuchos::REDUCE_MAX, local, Teuchos::outArg(kmax));
  }
  auto I = Teuchos::rcp(new CrsMatrix(K->getRowMap(), 1));
  for (std::size_t l = 0; l < K->getRowMap()->getNodeNumElements(); ++l) {
    const GlobalOrdinal g = K->getRowMap()->getGlobalElement(l);
    I->insertGlobalValues(g, Teuchos::tuple(g), Teuchos::tuple(1.0));
  }
  I->fillComplete(K->getDomainMap(), K->getRangeMap());
  const Teuchos::RCP<const CrsMatrix> A = matrixSum(1.0, *K, 1e-12 * kmax, *I);
  for (const char* m : {"CHOLMOD", "MUMPS-LDLT"}) {
    SparseDirectSolver s(A, m);
    EXPECT_EQ(s.factor(), Outcome::Factored) << m << ": " << s.failure();
  }
}

// factor() again (a caller refactoring after a change of values) frees the
// former factor: each call used to analyse into a fresh cholmod_factor and
// drop the last one (found by a review). The heap in use (glibc's
// mallinfo2: what malloc has handed out and not had back, mmapped blocks
// included) is measured after one factorisation and after ten more: with
// the leak it grows by ten factors, each about factorBytes(); without it by
// what a call keeps in the end (nothing more than the first call kept).
// Half a factor bounds that, leaving room for allocator bookkeeping; the
// chain is long enough (3000 nodes) that a factor is far above that noise.
// And a refactorisation reports its own outcome: the values changed from an
// indefinite K (spin 4) to a definite one (spin 1) on the same graph, the
// second factor() succeeds with no failure text left from the first.
TEST(SparseDirectSolver, RefactoringFreesTheFormerFactorAndReportsItsOwnOutcome) {
  const auto comm = Teuchos::DefaultComm<int>::getComm();
  fixtures::ChainSpec spec;
  spec.nodes = 3000;
  spec.support = models::RotatingChain::Support::EveryNode;
  spec.spin = 4.0;
  const auto indefinite = fixtures::sparseChain(spec, comm).K;
  spec.spin = 1.0;
  const auto definite = fixtures::sparseChain(spec, comm).K;
  auto K = Teuchos::rcp(new CrsMatrix(*indefinite, Teuchos::Copy));
  SparseDirectSolver s(K, "CHOLMOD");
  ASSERT_EQ(s.factor(), Outcome::NotPositiveDefinite);
  ASSERT_FALSE(s.failure().empty());
  // The definite values on the same rows and columns.
  K->resumeFill();
  {
    Teuchos::Array<GlobalOrdinal> cols;
    Teuchos::Array<double> vals;
    for (std::size_t l = 0; l < K->getRowMap()->getNodeNumElements(); ++l) {
      const GlobalOrdinal g = K->getRowMap()->getGlobalElement(l);
      const std::size_t n = definite->getNumEntriesInGlobalRow(g);
      cols.resize(n), vals.resize(n);
      std::size_t got = 0;
      definite->getGlobalRowCopy(g, cols(), vals(), got);
      ASSERT_EQ(static_cast<std::size_t>(K->replaceGlobalValues(g, cols(0, got), vals(0, got))), got)
          << "the two chains' graphs differ at row " << g;
    }
  }
  K->fillComplete(K->getDomainMap(), K->getRangeMap());
  ASSERT_EQ(s.factor(), Outcome::Factored) << s.failure();
  EXPECT_TRUE(s.failure().empty()) << s.failure();
  EXPECT_LT(forwardError(*K, s), 1e-9);
  const auto inUse = [] {
    const struct mallinfo2 m = mallinfo2();
    return static_cast<double>(m.uordblks) + static_cast<double>(m.hblkhd);
  };
  const double before = inUse();
  for (int k = 0; k < 10; ++k) ASSERT_EQ(s.factor(), Outcome::Factored) << s.failure();
  const double grown = inUse() - before;
  if (comm->getRank() == 0) {
    ASSERT_GT(s.factorBytes(), 0.0);
    EXPECT_LT(grown, 0.5 * s.factorBytes()) << "ten refactorisations kept " << grown / s.factorBytes()
                                           << " factors' bytes";
  }
}

TEST(SparseDirectSolver, UnknownMethodIsAnInputError) {
  // MUMPS is a method since issue 18 (DistributedDirectSolver); SuperLU is not.
  EXPECT_THROW(SparseDirectSolver(chainK(1.0), "SuperLU"), InputError);
}

// holdDofsScaled on a stiffness that stores no diagonal in a held row (a
// Matrix Market K may leave a zero out): the held row must still get its
// diagonal, or the copy is singular where the held problem is not. K is the
// grounded chain with row r's diagonal left out of the graph; held at r the
// problem is the chain with that DOF fixed, positive definite. The held row
// takes the largest diagonal (no own value), as the header says; the row on
// one rank only makes the other ranks build alike (2 ranks).
TEST(HeldDofs, AHeldRowWithoutAStoredDiagonalGetsOne) {
  const auto K = chainK(1.0);
  const GlobalOrdinal r = static_cast<GlobalOrdinal>(K->getGlobalNumRows() / 3);
  auto noDiagonal = Teuchos::rcp(new CrsMatrix(K->getRowMap(), K->getNodeMaxNumRowEntries()));
  double largest = 0.0;
  {
    Teuchos::Array<GlobalOrdinal> cols;
    Teuchos::Array<double> vals;
    double mine = 0.0;
    for (std::size_t l = 0; l < K->getRowMap()->getNodeNumElements(); ++l) {
      const GlobalOrdinal g = K->getRowMap()->getGlobalElement(l);
      const std::size_t n = K->getNumEntriesInGlobalRow(g);
      cols.resize(n), vals.resize(n);
      std::size_t got = 0;
      K->getGlobalRowCopy(g, cols(), vals(), got);
      Teuchos::Array<GlobalOrdinal> c;
      Teuchos::Array<double> v;
      for (std::size_t k = 0; k < got; ++k) {
        if (cols[k] == g) mine = std::max(mine, std::abs(vals[k]));
        if (g == r && cols[k] == g) continue;
        c.push_back(cols[k]), v.push_back(vals[k]);
      }
      noDiagonal->insertGlobalValues(g, c(), v());
    }
    noDiagonal->fillComplete(K->getDomainMap(), K->getRangeMap());
    Teuchos::reduceAll(*K->getComm(), Teuchos::REDUCE_MAX, mine, Teuchos::outArg(largest));
  }
  const auto held = holdDofsScaled(*noDiagonal, {r});
  SparseDirectSolver s(held, "CHOLMOD");
  EXPECT_EQ(s.factor(), Outcome::Factored) << s.failure();
  EXPECT_LT(forwardError(*held, s), 1e-9);
  const LocalOrdinal lr = held->getRowMap()->getLocalElement(r);
  if (lr != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) {
    const std::size_t n = held->getNumEntriesInGlobalRow(r);
    Teuchos::Array<GlobalOrdinal> cols(n);
    Teuchos::Array<double> vals(n);
    std::size_t got = 0;
    held->getGlobalRowCopy(r, cols(), vals(), got);
    for (std::size_t k = 0; k < got; ++k) EXPECT_EQ(vals[k], cols[k] == r ? largest : 0.0) << "column " << cols[k];
  }
  // The mass's held rows stay zero (diagonal 0): nothing is inserted then.
  const auto zero = holdDofs(*noDiagonal, {r}, 0.0);
  EXPECT_EQ(zero->getGlobalNumEntries(), noDiagonal->getGlobalNumEntries());
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

// cms::multiply against Tpetra's apply: Y = alpha A X + beta Y on a chain
// large enough for threads (nnz x columns above multiply's threshold), with
// 7 columns (a block of four and a remainder). On one rank it runs its own kernel on 1, 2 and 3 threads: the
// same bits on all three (each row summed in an order fixed by the row),
// and against Tpetra per column within 2 m eps (|alpha| ||A||_inf ||x||_inf
// + |beta| ||y0||_inf), m the most entries in a row: both sums run over the
// same m terms, each rounding at most m times. On two ranks A has an
// importer and multiply is Tpetra's apply itself: the same bits.
namespace {
/// What rounding may do to column j of alpha A x + beta y: both sums run
/// over the same m terms of a row, each rounding at most m times, so
/// 2 m eps (|alpha| ||A||_inf ||x||_inf + |beta| ||y||_inf), with
/// ||A||_inf <= sqrt(m) ||A||_F.
double productBound(const CrsMatrix& A, double alpha, double xInf, double beta, double yInf) {
  const double m = static_cast<double>(A.getGlobalMaxNumRowEntries()), eps = std::numeric_limits<double>::epsilon();
  return 2 * m * eps * (std::abs(alpha) * std::sqrt(m) * A.getFrobeniusNorm() * xInf + std::abs(beta) * yInf);
}
}  // namespace

TEST(SparseProduct, ThreadedRowsAgreeWithTpetraApply) {
  const auto comm = Teuchos::DefaultComm<int>::getComm();
  fixtures::ChainSpec spec;
  spec.nodes = 60000;  // 360,000 entries: x 7 columns above multiply's threshold of 2e6
  spec.spin = 3.0;
  const auto K = fixtures::sparseChain(spec, comm).K;
  const auto map = K->getDomainMap();
  const int nv = 7;
  MultiVector X(map, nv), Y0(map, nv);
  X.randomize();
  Y0.randomize();
  const double alpha = 0.7, beta = -1.3;
  MultiVector want(Y0, Teuchos::Copy);
  K->apply(X, want, Teuchos::NO_TRANS, alpha, beta);
  const bool threaded = multiplyThreads(*K, X, Y0, 2) > 1;
  EXPECT_EQ(threaded, comm->getSize() == 1) << "threads only without communication";
  EXPECT_EQ(multiplyThreads(*K, X, Y0, 1), comm->getSize() == 1 ? 1 : 0) << "the own kernel on one thread";
  Teuchos::Array<double> xn(nv), yn(nv), dn(nv);
  X.normInf(xn());
  Y0.normInf(yn());
  std::vector<MultiVector> got;
  for (int threads : {1, 2, 3}) {
    got.emplace_back(Y0, Teuchos::Copy);
    multiply(*K, X, got.back(), alpha, beta, threads);
    MultiVector d(got.back(), Teuchos::Copy);
    d.update(-1.0, want, 1.0);
    d.normInf(dn());
    for (int j = 0; j < nv; ++j) {
      const double bound = productBound(*K, alpha, xn[j], beta, yn[j]);
      if (threaded) EXPECT_LE(dn[j], bound) << threads << " threads, column " << j;
      else EXPECT_EQ(dn[j], 0.0) << "Tpetra's apply itself, column " << j;
    }
  }
  for (int k : {1, 2}) {
    got[k].update(-1.0, got[0], 1.0);
    got[k].normInf(dn());
    for (int j = 0; j < nv; ++j) EXPECT_EQ(dn[j], 0.0) << k + 1 << " threads and 1 differ in column " << j;
  }
}

// beta = 0 overwrites Y (NaN included), as Tpetra's apply, within
// productBound of it. X and Y the same vectors (in place) go through
// Tpetra's apply, which copies X first: its bits. Two overlapping views of
// one block, which Tpetra 13.2's apply mis-computes (it wrote columns of X
// before reading them), are multiplied from a copy of X: within
// productBound of the product of an untouched copy.
TEST(SparseProduct, OverwritesNaNAndCopiesOverlappingViews) {
  const auto comm = Teuchos::DefaultComm<int>::getComm();
  fixtures::ChainSpec spec;
  spec.nodes = 60000;
  const auto K = fixtures::sparseChain(spec, comm).K;
  const auto map = K->getDomainMap();
  MultiVector X(map, 7), Y(map, 7);
  X.randomize();
  Y.putScalar(std::numeric_limits<double>::quiet_NaN());
  ASSERT_EQ(multiplyThreads(*K, X, Y, 2) > 1, comm->getSize() == 1);
  multiply(*K, X, Y, 1.0, 0.0, 2);
  MultiVector want(map, 7);
  K->apply(X, want);
  Teuchos::Array<double> n(7), xn(7);
  X.normInf(xn());
  Y.update(-1.0, want, 1.0);
  Y.normInf(n());
  for (int j = 0; j < 7; ++j) {
    EXPECT_TRUE(std::isfinite(n[j])) << "column " << j;
    EXPECT_LE(n[j], productBound(*K, 1.0, xn[j], 0.0, 0.0)) << "column " << j;
  }
  // In place: Z = A Z.
  MultiVector Z(X, Teuchos::Copy);
  EXPECT_EQ(multiplyThreads(*K, Z, Z, 2), 0);
  multiply(*K, Z, Z, 1.0, 0.0, 2);
  Z.update(-1.0, want, 1.0);
  Z.normInf(n());
  for (int j = 0; j < 7; ++j) EXPECT_EQ(n[j], 0.0) << "in place, column " << j;
  // Two views of one 8-column block, columns 0-6 and 1-7: distinct
  // objects, overlapping memory (multiplyThreads cannot see it; multiply
  // compares the spans).
  MultiVector W(map, 8);
  W.randomize();
  const MultiVector W0(W, Teuchos::Copy);
  const auto Xv = W.subView(Teuchos::Range1D(0, 6));
  const auto Yv = W.subViewNonConst(Teuchos::Range1D(1, 7));
  EXPECT_EQ(multiplyThreads(*K, *Xv, *Yv, 2) > 1, comm->getSize() == 1);
  multiply(*K, *Xv, *Yv, 1.0, 0.0, 2);
  MultiVector wantV(map, 7);
  K->apply(*W0.subView(Teuchos::Range1D(0, 6)), wantV);
  Teuchos::Array<double> wn(7);
  W0.subView(Teuchos::Range1D(0, 6))->normInf(wn());
  wantV.update(-1.0, *Yv, 1.0);
  wantV.normInf(n());
  for (int j = 0; j < 7; ++j) EXPECT_LE(n[j], productBound(*K, 1.0, wn[j], 0.0, 0.0)) << "overlapping views, column " << j;
}
