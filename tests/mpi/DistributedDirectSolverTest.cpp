// MUMPS factored across the ranks (DistributedDirectSolver, issue 18) on
// matrices whose spectra are known in closed form: the 3-D Dirichlet
// Laplacian on an a x b x c grid, eigenvalues
//   sum over the three axes of 4 sin^2(k pi / (2 (n + 1))), k = 1..n,
// so cond(A) and the inertia of A - sigma I are exact. Solves are checked
// against the normwise bounds of a backward-stable factorisation and against
// CHOLMOD on the same matrix; the inertia against the closed-form count and
// CHOLMOD's L D L^T; a singular matrix is refused by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/DistributedDirectSolver.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/core/SparseInertia.hpp"

using namespace cms;
using Kind = DistributedDirectSolver::Kind;
using Outcome = SparseDirectSolver::Outcome;

namespace {

constexpr int NX = 14, NY = 12, NZ = 11;  // 1848 rows: distinct 1-D spectra, few coincidences
constexpr double kEps = std::numeric_limits<double>::epsilon();

std::vector<double> axis(int n) {
  std::vector<double> v;
  for (int k = 1; k <= n; ++k) v.push_back(4.0 * std::pow(std::sin(k * M_PI / (2.0 * (n + 1))), 2));
  return v;
}

/// Every eigenvalue of the grid Laplacian, ascending.
std::vector<double> spectrum() {
  std::vector<double> all;
  for (double a : axis(NX))
    for (double b : axis(NY))
      for (double c : axis(NZ)) all.push_back(a + b + c);
  std::sort(all.begin(), all.end());
  return all;
}

/// The grid Laplacian minus sigma I, plus gamma times a skew convection
/// term along x (gamma = 0: symmetric). Rows dealt in blocks, or with
/// `gaps` the global id of cell i is 3 i + 7 (a map whose ids do not fill a
/// range: MUMPS needs them renumbered).
Teuchos::RCP<CrsMatrix> laplacian(double sigma, double gamma = 0.0, bool gaps = false,
                                  bool neumann = false, int NX = ::NX, int NY = ::NY, int NZ = ::NZ) {
  const auto comm = Teuchos::DefaultComm<int>::getComm();
  const GlobalOrdinal N = NX * NY * NZ;
  auto id = [&](GlobalOrdinal i) { return gaps ? 3 * i + 7 : i; };
  const int p = comm->getSize(), r = comm->getRank();
  const GlobalOrdinal lo = N * r / p, hi = N * (r + 1) / p;
  Teuchos::Array<GlobalOrdinal> mine;
  for (GlobalOrdinal i = lo; i < hi; ++i) mine.push_back(id(i));
  auto map = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(N), mine(), gaps ? 7 : 0, comm));
  auto A = Teuchos::rcp(new CrsMatrix(map, 7));
  for (GlobalOrdinal i = lo; i < hi; ++i) {
    const int x = i % NX, y = (i / NX) % NY, z = i / (NX * NY);
    Teuchos::Array<GlobalOrdinal> cols;
    Teuchos::Array<double> vals;
    double diag = 6.0 - sigma;
    auto add = [&](bool inside, GlobalOrdinal j, double v) {
      if (inside) {
        cols.push_back(id(j));
        vals.push_back(v);
      } else if (neumann) {
        diag -= 1.0;  // no neighbour: a free face, the constant vector in the null space
      }
    };
    add(x > 0, i - 1, -1.0 - gamma);
    add(x < NX - 1, i + 1, -1.0 + gamma);
    add(y > 0, i - NX, -1.0);
    add(y < NY - 1, i + NX, -1.0);
    add(z > 0, i - NX * NY, -1.0);
    add(z < NZ - 1, i + NX * NY, -1.0);
    cols.push_back(id(i));
    vals.push_back(diag);
    A->insertGlobalValues(id(i), cols(), vals());
  }
  A->fillComplete(map, map);
  return A;
}

struct Errors {
  double backward = 0.0;  ///< max_j ||b - A x|| / (||A||_F ||x||)
  double forward = 0.0;   ///< max_j ||x - x0|| / ||x0||
};

/// Solve A x = A x0 for three random x0 through `solve`.
template <class Solve>
Errors errorsOf(const CrsMatrix& A, Solve solve, MultiVector* keep = nullptr) {
  const auto map = A.getRowMap();
  MultiVector x0(map, 3), b(map, 3), x(map, 3), r(map, 3);
  x0.randomize();
  A.apply(x0, b);
  solve(b, x);
  A.apply(x, r);
  r.update(1.0, b, -1.0);
  Teuchos::Array<double> rn(3), xn(3), en(3), x0n(3);
  r.norm2(rn());
  x.norm2(xn());
  if (keep) *keep = MultiVector(x, Teuchos::Copy);
  x.update(-1.0, x0, 1.0);
  x.norm2(en());
  x0.norm2(x0n());
  Errors e;
  const double nA = A.getFrobeniusNorm();
  for (int j = 0; j < 3; ++j) {
    e.backward = std::max(e.backward, rn[j] / (nA * xn[j]));
    e.forward = std::max(e.forward, en[j] / x0n[j]);
  }
  return e;
}

}  // namespace

// A backward-stable factorisation of order n solves with a normwise backward
// error ||b - A x|| / (||A|| ||x||) of at most ~n eps (Higham, Thm 9.4 with
// a modest growth factor) and so a forward error of at most ~n eps cond(A).
// Both are asserted at exactly n eps and n eps cond: a wrong or unpivoted-
// unstable solve misses them by orders of magnitude (the singular case below
// gives forward errors of order 1), a correct one is ~1e3 below them.
TEST(DistributedDirectSolver, SolvesWithinBackwardStableBoundsAndAgreesWithCholmod) {
  const auto ev = spectrum();
  const double n = static_cast<double>(ev.size()), cond = ev.back() / ev.front();
  for (bool gaps : {false, true}) {
    const auto A = laplacian(0.0, 0.0, gaps);
    for (Kind kind : {Kind::PositiveDefinite, Kind::Symmetric, Kind::General}) {
      DistributedDirectSolver mumps(A, kind, "the grid Laplacian");
      ASSERT_NO_THROW(mumps.factor());
      EXPECT_EQ(mumps.nullPivots(), 0);
      MultiVector xm(A->getRowMap(), 3);
      const auto em = errorsOf(*A, [&](const MultiVector& b, MultiVector& x) { mumps.solve(b, x); }, &xm);
      EXPECT_LT(em.backward, n * kEps) << "kind " << int(kind) << (gaps ? ", gapped ids" : "");
      EXPECT_LT(em.forward, n * kEps * cond) << "kind " << int(kind);
    }
    // The same system through SparseDirectSolver: MUMPS-LDLT and CHOLMOD
    // both within the bound of x0, so within twice it of each other.
    SparseDirectSolver chol(A, "CHOLMOD"), ldlt(A, "MUMPS-LDLT"), lu(A, "MUMPS");
    ASSERT_EQ(chol.factor(), Outcome::Factored) << chol.failure();
    ASSERT_EQ(ldlt.factor(), Outcome::Factored) << ldlt.failure();
    ASSERT_EQ(lu.factor(), Outcome::Factored) << lu.failure();
    MultiVector b(A->getRowMap(), 2), xc(A->getRowMap(), 2), xl(A->getRowMap(), 2), xu(A->getRowMap(), 2);
    b.randomize();
    chol.solve(b, xc);
    ldlt.solve(b, xl);
    lu.solve(b, xu);
    Teuchos::Array<double> d(2), c(2);
    xc.norm2(c());
    xl.update(-1.0, xc, 1.0);
    xl.norm2(d());
    for (int j = 0; j < 2; ++j) EXPECT_LT(d[j] / c[j], 2.0 * n * kEps * cond) << "MUMPS-LDLT vs CHOLMOD";
    xu.update(-1.0, xc, 1.0);
    xu.norm2(d());
    for (int j = 0; j < 2; ++j) EXPECT_LT(d[j] / c[j], 2.0 * n * kEps * cond) << "MUMPS LU vs CHOLMOD";
    EXPECT_GT(ldlt.factorNonzeros(), 0.0);
    // The kept-factor budget's bytes: CHOLMOD's supernodal L as allocated,
    // at least its entries' 8 bytes (relaxed supernodes store zeros too) and
    // its index arrays; it counted nnz(L) alone before (found by a review).
    EXPECT_GT(chol.factorBytes(), 8.0 * chol.factorNonzeros());
    EXPECT_LT(chol.factorBytes(), 4.0 * 8.0 * chol.factorNonzeros());
  }
}

// Unsymmetric: A = L + gamma S with S skew, so x^T A x = x^T L x and
// sigma_min(A) >= lambda_min(L), ||A||_2 <= lambda_max(L) + 2 gamma: the
// bound cond(A) <= (lambda_max + 2 gamma) / lambda_min is rigorous.
TEST(DistributedDirectSolver, UnsymmetricWithinBoundsAndAgreesWithKlu2) {
  const auto ev = spectrum();
  const double n = static_cast<double>(ev.size()), gamma = 0.4;
  const double cond = (ev.back() + 2.0 * gamma) / ev.front();
  const auto A = laplacian(0.0, gamma);
  DistributedDirectSolver mumps(A, Kind::General, "the convected Laplacian");
  ASSERT_NO_THROW(mumps.factor());
  const auto em = errorsOf(*A, [&](const MultiVector& b, MultiVector& x) { mumps.solve(b, x); });
  EXPECT_LT(em.backward, n * kEps);
  EXPECT_LT(em.forward, n * kEps * cond);
  SparseDirectSolver klu(A, "KLU2");
  ASSERT_EQ(klu.factor(), Outcome::Factored);
  const auto ek = errorsOf(*A, [&](const MultiVector& b, MultiVector& x) { klu.solve(b, x); });
  EXPECT_LT(ek.forward, n * kEps * cond);  // the reference path meets the same bound
}

// Sylvester: the negative pivots of L D L^T of A - sigma I are the
// eigenvalues below sigma, counted exactly from the closed form, and equal to
// CHOLMOD's L D L^T count (cms::inertia, the Sturm count of the sparse path).
// sigma midway between consecutive distinct eigenvalues: the smallest
// |lambda - sigma| is then half a gap (>= 1e-4 here), far above rounding.
TEST(DistributedDirectSolver, InertiaEqualsTheClosedFormAndCholmodCount) {
  const auto ev = spectrum();
  for (std::size_t k : {std::size_t(0), std::size_t(7), ev.size() / 3, ev.size() / 2, ev.size() - 2}) {
    std::size_t j = k;
    while (ev[j + 1] - ev[j] < 1e-3) ++j;  // a real gap
    const double sigma = 0.5 * (ev[j] + ev[j + 1]);
    const long long below = static_cast<long long>(j + 1);
    const auto A = laplacian(sigma);
    DistributedDirectSolver f(A, Kind::Symmetric, "A - sigma I");
    ASSERT_NO_THROW(f.factor());
    EXPECT_EQ(f.negativePivots(), below) << "sigma " << sigma;
    const auto m = distributedInertia(*A);
    const auto c = inertia(*A);
    ASSERT_TRUE(m.reliable()) << m.failure;
    ASSERT_TRUE(c.reliable()) << c.failure;
    EXPECT_EQ(m.negative, below);
    EXPECT_EQ(m.positive, static_cast<long long>(ev.size()) - below);
    EXPECT_EQ(c.negative, m.negative);
  }
  // Indefinite: refused by the definiteness test as CHOLMOD refuses it.
  SparseDirectSolver ldlt(laplacian(ev[40] + 1e-2), "MUMPS-LDLT");
  EXPECT_EQ(ldlt.factor(), Outcome::NotPositiveDefinite);
  EXPECT_NE(ldlt.failure().find("negative pivots"), std::string::npos) << ldlt.failure();
}

// The Neumann Laplacian is singular (constant null vector): refused with the
// matrix's name and the null-pivot count, on every rank alike, and a shifted
// matrix exactly at an eigenvalue is counted as a tiny pivot, not a sign.
TEST(DistributedDirectSolver, SingularMatrixIsANumericalErrorNamingIt) {
  const auto A = laplacian(0.0, 0.0, false, /*neumann*/ true);
  for (Kind kind : {Kind::General, Kind::Symmetric}) {
    DistributedDirectSolver f(A, kind, "K of the floating block");
    try {
      f.factor();
      ADD_FAILURE() << "a singular matrix was factored without complaint";
    } catch (const NumericalError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("K of the floating block"), std::string::npos) << what;
      EXPECT_NE(what.find("singular"), std::string::npos) << what;
    }
    EXPECT_GE(f.nullPivots(), 1);
  }
  SparseDirectSolver lu(A, "MUMPS");
  EXPECT_EQ(lu.factor(), Outcome::Singular);
  EXPECT_NE(lu.failure().find("zero to rounding"), std::string::npos) << lu.failure();
  SparseDirectSolver ldlt(A, "MUMPS-LDLT");
  EXPECT_EQ(ldlt.factor(), Outcome::NotPositiveDefinite);
  const auto in = distributedInertia(*A);
  EXPECT_FALSE(in.reliable());
  EXPECT_GE(in.tinyPivots, 1);
}

TEST(DistributedDirectSolver, AutoChoosesMumpsOnlyWhenDistributedAndLarge) {
  const auto A = laplacian(0.0);
  EXPECT_TRUE(useDistributedSolver("MUMPS", *A));
  EXPECT_FALSE(useDistributedSolver("CHOLMOD", *A));
  EXPECT_FALSE(useDistributedSolver("Auto", *A));  // 12,000 entries: below kDistributedAutoEntries
  EXPECT_THROW(useDistributedSolver("SuperLU", *A), InputError);
  // At a threshold of one entry, Auto is MUMPS exactly when the matrix is
  // spread over more than one rank.
  EXPECT_EQ(useDistributedSolver("Auto", *A, 1), A->getComm()->getSize() > 1);
}

// Issue 18: a factorisation that cannot fit is refused before it starts,
// naming the matrix and MUMPS's estimate, instead of the out-of-memory
// killer ending the run; a Sturm count refused so comes back unreliable
// with that reason (the sparse path then says its set is not confirmed).
// The budget is CMS_MEMORY_LIMIT (a documented setting for shared
// machines), here 1 MB: below any factorisation's estimate.
namespace {
/// What factor() refused with ("" if it factored).
std::string refusalOf(DistributedDirectSolver& f) {
  try {
    f.factor();
  } catch (const NumericalError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(DistributedDirectSolver, AFactorisationThatCannotFitIsRefusedByName) {
  const auto A = laplacian(0.0);
  setenv("CMS_MEMORY_LIMIT", "1e6", 1);
  DistributedDirectSolver f(A, Kind::Symmetric, "K of the big block");
  const std::string what = refusalOf(f);
  const auto count = distributedInertia(*A);
  unsetenv("CMS_MEMORY_LIMIT");
  EXPECT_NE(what.find("K of the big block"), std::string::npos) << what;
  EXPECT_NE(what.find("needs about"), std::string::npos) << what;
  EXPECT_FALSE(count.reliable());
  EXPECT_NE(count.failure.find("needs about"), std::string::npos) << count.failure;
  // A count keeps no factor: refused on the estimate for that, INFO(17).
  EXPECT_NE(count.failure.find("INFO(17)"), std::string::npos) << count.failure;
  // Within the budget again: the same matrix factors.
  DistributedDirectSolver g(A, Kind::Symmetric, "K of the big block");
  EXPECT_NO_THROW(g.factor());
}

// The budget is held against the in-core estimate, not the out-of-core one
// (INFO(17), a third of the in-core figure on the rotor, let a 5.7e5-DOF
// Sturm count through that the machine's out-of-memory killer then ended):
// with a budget whose 90% share is 95% of what the same factorisation was
// measured to use (INFOG(21), the busiest rank), it is refused.
TEST(DistributedDirectSolver, TheBudgetHoldsAgainstTheInCoreEstimate) {
  const auto A = laplacian(0.0);
  DistributedDirectSolver measured(A, Kind::Symmetric, "K measured");
  measured.factor();
  const double usedMB = measured.factorMemoryMaxMB();
  ASSERT_GT(usedMB, 0.0);
  const int ranksOnNode = A->getComm()->getSize();  // the tests run on one node
  const double budget = usedMB * 1e6 * ranksOnNode * 0.95 / 0.9;
  setenv("CMS_MEMORY_LIMIT", std::to_string(budget).c_str(), 1);
  DistributedDirectSolver f(A, Kind::Symmetric, "K at 95% of its need");
  const std::string what = refusalOf(f);
  unsetenv("CMS_MEMORY_LIMIT");
  EXPECT_NE(what.find("K at 95% of its need"), std::string::npos) << "measured " << usedMB << " MB; " << what;
  EXPECT_NE(what.find("INFO(15)"), std::string::npos) << what;
}

// A Sturm count needs the signs of the pivots, not the factors: counting
// only (setPivotsOnly), MUMPS discards each front's factor as it goes
// (ICNTL(31) = 1) and works in its out-of-core memory. Measured on the
// 54,000-DOF bar, the count's MUMPS factorisation was the run's peak (344 of
// 1,040 MiB, most of it a factor nobody solved with). The count agrees with
// the factorisation that keeps its factors, exactly (integers), and the
// memory MUMPS reports using drops by at least half the factor's 8-byte
// reals (the other half left to MUMPS's differently sized work buffers);
// solving with a count-only factorisation is refused by name.
TEST(DistributedDirectSolver, ACountDiscardsTheFactorsAndKeepsOnlyItsWorkingMemory) {
  const auto A = laplacian(0.3, 0.0, false, false, 24, 24, 24);  // 13,824 rows; 0.3 cuts the spectrum
  DistributedDirectSolver kept(A, Kind::Symmetric, "A kept");
  ASSERT_NO_THROW(kept.factor());
  DistributedDirectSolver counted(A, Kind::Symmetric, "A counted");
  counted.setPivotsOnly(true);
  ASSERT_NO_THROW(counted.factor());
  EXPECT_GT(kept.negativePivots(), 0);
  EXPECT_EQ(counted.negativePivots(), kept.negativePivots());
  EXPECT_EQ(counted.nullPivots(), kept.nullPivots());
  const double factorMB = 8.0 * kept.factorEntries() / 1e6;
  ASSERT_GT(factorMB, 10.0) << "the grid must be large enough for the factor to dominate MUMPS's memory";
  EXPECT_LT(counted.factorMemoryTotalMB(), kept.factorMemoryTotalMB() - 0.5 * factorMB)
      << "factor " << factorMB << " MB";
  MultiVector b(A->getRowMap(), 1), x(A->getRowMap(), 1);
  b.putScalar(1.0);
  try {
    counted.solve(b, x);
    ADD_FAILURE() << "solved with discarded factors";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("A counted"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("discarded"), std::string::npos) << e.what();
  }
  // distributedInertia (the Sturm count's multifrontal path) counts only.
  const auto c = distributedInertia(*A);
  ASSERT_TRUE(c.reliable()) << c.failure;
  EXPECT_EQ(c.negative, kept.negativePivots());
}

// A count given the only reference to its matrix frees it once MUMPS's
// triplets hold the values, before the factorisation (the peak of `cms modes`
// on the bar was the coverage count with its K - w^2 M alive beside them).
TEST(DistributedDirectSolver, ACountTakingItsMatrixOverFreesItBeforeFactoring) {
  Teuchos::RCP<const CrsMatrix> A = laplacian(0.3, 0.0, false, false, 12, 12, 12);
  const auto reference = distributedInertia(*A);
  ASSERT_TRUE(reference.reliable()) << reference.failure;
  const auto weak = A.create_weak();
  DistributedDirectSolver counted(A, Kind::Symmetric, "A handed over");
  A = Teuchos::null;  // the solver holds the only strong reference
  counted.setPivotsOnly(true, /*releaseMatrix*/ true);
  ASSERT_NO_THROW(counted.factor());
  EXPECT_FALSE(weak.is_valid_ptr()) << "the matrix outlived its triplets";
  EXPECT_EQ(counted.negativePivots(), reference.negative);
  EXPECT_THROW(counted.factor(), std::logic_error) << "factored again without its matrix";
  // inertia(RCP) and distributedInertia(RCP) count the same as by reference.
  Teuchos::RCP<const CrsMatrix> B = laplacian(0.3, 0.0, false, false, 12, 12, 12);
  const auto weakB = B.create_weak();
  const auto c = inertia(std::move(B), InertiaMethod::Multifrontal);
  ASSERT_TRUE(c.reliable()) << c.failure;
  EXPECT_EQ(c.negative, reference.negative);
  EXPECT_EQ(c.positive, reference.positive);
  EXPECT_FALSE(weakB.is_valid_ptr());
}

namespace {
/// gamma times the skew convection along x of the grid: B(i, i + 1) =
/// gamma, B(i + 1, i) = -gamma.
/// With `gaps`, cell i has the global id 3 i + 7, as laplacian(..., gaps).
Teuchos::RCP<CrsMatrix> skewAlongX(const CrsMatrix& like, double gamma, bool gaps = false) {
  const auto map = like.getRowMap();
  auto B = Teuchos::rcp(new CrsMatrix(map, 2));
  auto id = [&](GlobalOrdinal i) { return gaps ? 3 * i + 7 : i; };
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
    const GlobalOrdinal g = map->getGlobalElement(static_cast<LocalOrdinal>(l)), i = gaps ? (g - 7) / 3 : g;
    Teuchos::Array<GlobalOrdinal> cols;
    Teuchos::Array<double> vals;
    if (i % NX > 0) cols.push_back(id(i - 1)), vals.push_back(-gamma);
    if (i % NX < NX - 1) cols.push_back(id(i + 1)), vals.push_back(gamma);
    if (!cols.empty()) B->insertGlobalValues(g, cols(), vals());
  }
  B->fillComplete(map, map);
  return B;
}
}  // namespace

// A Sturm count of a Hermitian H = A + iB by MUMPS is the inertia of its real
// embedding [[A, -B], [B, A]], now given to MUMPS straight from A's and B's
// rows (no 2N-row matrix: on the 5.7e5-DOF rotor the embedding's preparation
// alone did not fit beside the truth). Closed form: along x, H is the
// Hermitian Toeplitz tridiagonal with off-diagonal -1 + i gamma, eigenvalues
// 2 - 2 sqrt(1 + gamma^2) cos(k pi / (NX + 1)); y and z as the Laplacian.
// The embedding counts each eigenvalue twice; the count equals the closed
// form's and that of the embedding built as a matrix (integers: exact).
TEST(DistributedDirectSolver, TheEmbeddingOfAHermitianMatrixIsCountedFromItsParts) {
  const double gamma = 0.7;
  std::vector<double> ev;
  for (int k = 1; k <= NX; ++k) {
    const double x = 2.0 - 2.0 * std::sqrt(1.0 + gamma * gamma) * std::cos(k * M_PI / (NX + 1));
    for (double b : axis(NY))
      for (double c : axis(NZ)) ev.push_back(x + b + c);
  }
  std::sort(ev.begin(), ev.end());
  for (std::size_t k : {std::size_t(0), std::size_t(9), ev.size() / 4, ev.size() / 2}) {
    std::size_t j = k;
    while (ev[j + 1] - ev[j] < 1e-3) ++j;
    const double sigma = 0.5 * (ev[j] + ev[j + 1]);
    const auto A = laplacian(sigma);
    const auto B = skewAlongX(*A, gamma);
    const SparseInertia parts = distributedInertia(*A, *B);
    ASSERT_TRUE(parts.reliable()) << parts.failure;
    EXPECT_EQ(parts.negative, 2 * static_cast<long long>(j + 1)) << "sigma " << sigma;
    EXPECT_EQ(parts.positive, 2 * static_cast<long long>(ev.size() - j - 1)) << "sigma " << sigma;
    const SparseInertia whole = distributedInertia(*realEmbedding(*A, *B, stateMap(*A->getRowMap())));
    EXPECT_EQ(whole.negative, parts.negative);
    // And through cms::inertia's multifrontal path, halved.
    EXPECT_EQ(inertia(*A, *B, InertiaMethod::Multifrontal).negative, static_cast<long long>(j + 1));
    // Ids that do not fill a range: MUMPS's numbering of B's columns too.
    const auto Ag = laplacian(sigma, 0.0, /*gaps*/ true);
    const SparseInertia gapped = distributedInertia(*Ag, *skewAlongX(*Ag, gamma, true));
    EXPECT_EQ(gapped.negative, parts.negative) << "sigma " << sigma;
  }
  // A skew part on another map is refused by name.
  {
    const auto A = laplacian(0.0), Ag = laplacian(0.0, 0.0, /*gaps*/ true);
    EXPECT_THROW(DistributedDirectSolver(A, skewAlongX(*Ag, gamma, true), "H"), InputError);
  }
  // Solving with it is refused (there is no 2N-row map to solve on).
  const auto A = laplacian(0.0);
  DistributedDirectSolver f(A, skewAlongX(*A, gamma), "H");
  f.factor();
  MultiVector b(A->getRowMap(), 1), x(A->getRowMap(), 1);
  EXPECT_THROW(f.solve(b, x), InputError);
}
