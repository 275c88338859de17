// core/Redistribution (doc/architecture.md, "Parallelism"): a distributed
// matrix and multivector gathered whole onto one rank and re-expressed on a
// one-rank communicator, and a multivector scattered back, against the
// distributed originals; a mismatch on the owner raises on every rank (no
// hang), and a map whose ids are not 0 .. n-1 is refused everywhere. A
// matrix's rows gathered for a factorisation (gatherRows, GatheredRows) in
// the gather map's order, with every entry where its ids say.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <utility>

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_ComputeGatherMap.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/MpiComm.hpp"
#include "cms/core/Redistribution.hpp"

using namespace cms;

namespace {

auto world() { return Teuchos::DefaultComm<int>::getComm(); }

/// A tridiagonal matrix with distinct entries, rows split over the ranks.
Teuchos::RCP<CrsMatrix> tridiagonal(GlobalOrdinal n) {
  auto map = Teuchos::rcp(new Map(n, 0, world()));
  auto A = Teuchos::rcp(new CrsMatrix(map, 3));
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
    const GlobalOrdinal g = map->getGlobalElement(static_cast<LocalOrdinal>(l));
    for (GlobalOrdinal c = std::max<GlobalOrdinal>(0, g - 1); c <= std::min(n - 1, g + 1); ++c)
      A->insertGlobalValues(g, Teuchos::tuple(c), Teuchos::tuple(1.0 + 10.0 * g + c));
  }
  A->fillComplete();
  return A;
}

}  // namespace

TEST(Redistribution, GatherAndScatterReproduceTheDistributedProduct) {
  const GlobalOrdinal n = 37;
  const auto A = tridiagonal(n);
  const auto self = world()->split(world()->getRank(), 0);
  for (int owner = 0; owner < world()->getSize(); ++owner) {
    MultiVector X(A->getDomainMap(), 2), Y(A->getRangeMap(), 2);
    for (std::size_t l = 0; l < X.getLocalLength(); ++l) {
      const auto g = A->getRowMap()->getGlobalElement(static_cast<LocalOrdinal>(l));
      X.replaceLocalValue(static_cast<LocalOrdinal>(l), 0, 1.0 + g);
      X.replaceLocalValue(static_cast<LocalOrdinal>(l), 1, 2.0 - 0.5 * g);
    }
    A->apply(X, Y);
    const auto As = gatherToRank(*A, owner, self);
    const auto Xs = gatherToRank(X, owner, self);
    const auto Ys = gatherToRank(Y, owner, self);
    EXPECT_EQ(world()->getRank() == owner, !As.is_null());
    Teuchos::RCP<MultiVector> Zs;
    if (!As.is_null()) {
      ASSERT_EQ(As->getGlobalNumRows(), static_cast<std::size_t>(n));
      EXPECT_EQ(As->getGlobalNumEntries(), A->getGlobalNumEntries());
      Zs = Teuchos::rcp(new MultiVector(As->getRangeMap(), 2));
      As->apply(*Xs, *Zs);
      for (int j = 0; j < 2; ++j) {
        const auto z = Zs->getData(j), y = Ys->getData(j);
        for (GlobalOrdinal i = 0; i < n; ++i) EXPECT_EQ(z[i], y[i]) << "row " << i;  // same sums, same order
      }
    }
    // Back onto the distributed map: Y again, entry for entry.
    const auto Yd = scatterFromRank(Zs, owner, 2, A->getRangeMap());
    for (int j = 0; j < 2; ++j) {
      const auto a = Yd->getData(j), b = Y.getData(j);
      for (std::size_t l = 0; l < Y.getLocalLength(); ++l) EXPECT_EQ(a[l], b[l]);
    }
  }
}

TEST(Redistribution, MismatchesRaiseOnEveryRank) {
  const auto A = tridiagonal(12);
  const auto self = world()->split(world()->getRank(), 0);
  const int owner = world()->getSize() - 1;
  Teuchos::RCP<MultiVector> wrong;
  if (world()->getRank() == owner)
    wrong = Teuchos::rcp(new MultiVector(Teuchos::rcp(new Map(12, 12, 0, self)), 1));
  // Three columns announced, one given on the owner: every rank throws.
  EXPECT_THROW(scatterFromRank(wrong, owner, 3, A->getRangeMap()), std::invalid_argument);
  // Ids 5 .. 16 instead of 0 .. 11.
  auto shifted = Teuchos::rcp(new Map(12, 5, world()));
  MultiVector X(shifted, 1);
  EXPECT_THROW(gatherToRank(X, owner, self), std::invalid_argument);
}

namespace {

/// A symmetric matrix whose rows are dealt out cyclically (row k on rank
/// k mod P), with ids offset by `base` and either a hole every 7th id
/// (stride 1) or `stride` apart: neither a slab nor 0 .. n-1, so that the
/// gathered order and the positions are the map's and not the ids'; stride
/// 100 spreads the ids beyond GatheredRows's table (its sorted search).
/// With `lastOnly` every row is the last rank's instead (the others,
/// rank 0 among them, hold none). Entry (i, j) = 1 + i + j + i j / 100 at
/// the ids of a pentadiagonal pattern.
Teuchos::RCP<CrsMatrix> dealtOut(int n, GlobalOrdinal base, GlobalOrdinal stride, bool lastOnly = false) {
  const int P = world()->getSize(), me = world()->getRank();
  const auto id = [&](int k) { return stride == 1 ? base + k + k / 6 : base + stride * k; };
  const auto ownerOf = [&](int k) { return lastOnly ? P - 1 : k % P; };
  Teuchos::Array<GlobalOrdinal> mine;
  for (int k = 0; k < n; ++k)
    if (ownerOf(k) == me) mine.push_back(id(k));
  auto map = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), mine(), 0, world()));
  auto A = Teuchos::rcp(new CrsMatrix(map, 5));
  for (int k = 0; k < n; ++k) {
    if (ownerOf(k) != me) continue;
    for (int c = std::max(0, k - 2); c <= std::min(n - 1, k + 2); ++c) {
      const double i = static_cast<double>(id(k)), j = static_cast<double>(id(c));
      A->insertGlobalValues(id(k), Teuchos::tuple(id(c)), Teuchos::tuple(1.0 + i + j + i * j / 100.0));
    }
  }
  A->fillComplete();
  return A;
}

}  // namespace

// gatherRows and GatheredRows (what every gathered factorisation reads):
// the rows in computeGatherMap's order with their ids, every entry with its
// column's id (gatherRows) or its row's position there (GatheredRows), on
// rank 0 and, for gatherRows, on the last rank; nothing elsewhere. Also
// when the rows are all another rank's.
TEST(Redistribution, GatheredRowsFollowTheGatherMapsOrder) {
  for (const auto& [stride, lastOnly] : {std::pair<GlobalOrdinal, bool>{1, false}, {100, false}, {1, true}}) {
    SCOPED_TRACE("ids " + std::to_string(stride) + " apart" + (lastOnly ? ", every row on the last rank" : ""));
    const int n = 41;
    const auto A = dealtOut(n, 1000, stride, lastOnly);
    const auto order = Tpetra::Details::computeGatherMap(A->getRowMap(), Teuchos::null);
    const auto ids = order->getNodeElementList();  // rank 0: every id in the gathered order
    const auto value = [](GlobalOrdinal i, GlobalOrdinal j) {
      const double x = static_cast<double>(i), y = static_cast<double>(j);
      return 1.0 + x + y + x * y / 100.0;
    };
    for (int owner : {0, world()->getSize() - 1}) {
      const RowsOnRank g = gatherRows(*A, owner);
      if (world()->getRank() != owner) {
        EXPECT_EQ(g.size(), 0u);
        continue;
      }
      ASSERT_EQ(g.size(), static_cast<std::size_t>(n));
      ASSERT_EQ(g.offsets.size(), static_cast<std::size_t>(n) + 1);
      EXPECT_EQ(g.offsets.back(), A->getGlobalNumEntries());
      std::set<GlobalOrdinal> seen;
      for (std::size_t r = 0; r < g.size(); ++r) {
        if (owner == 0) EXPECT_EQ(g.rows[r], ids[r]) << "row " << r;  // computeGatherMap's order
        seen.insert(g.rows[r]);
        for (std::size_t e = g.offsets[r]; e < g.offsets[r + 1]; ++e)
          EXPECT_EQ(g.values[e], value(g.rows[r], g.columns[e]))
              << "row id " << g.rows[r] << ", column id " << g.columns[e];
      }
      EXPECT_EQ(seen.size(), static_cast<std::size_t>(n));
    }
    const GatheredRows rows(A, 0);
    if (world()->getRank() != 0) {
      EXPECT_EQ(rows.size(), 0u);
      continue;
    }
    ASSERT_EQ(rows.size(), static_cast<std::size_t>(n));
    EXPECT_EQ(rows.entries(), A->getGlobalNumEntries());
    for (std::size_t r = 0; r < rows.size(); ++r) {
      int count = 0;
      rows.forEach(r, [&](int position, double v) {
        ASSERT_GE(position, 0);
        ASSERT_LT(position, n);
        EXPECT_EQ(v, value(ids[r], ids[position])) << "row " << r << ", position " << position;
        ++count;
      });
      EXPECT_GE(count, 3);  // the pentadiagonal pattern: 3 to 5 a row
      EXPECT_LE(count, 5);
      // forEachUpper: exactly those at positions <= r (a column's upper
      // triangle, what CHOLMOD and the Sturm count take).
      int upper = 0, below = 0;
      rows.forEach(r, [&](int position, double) { (static_cast<std::size_t>(position) <= r ? upper : below)++; });
      int visited = 0;
      rows.forEachUpper(r, [&](int position, double v) {
        EXPECT_LE(static_cast<std::size_t>(position), r);
        EXPECT_EQ(v, value(ids[r], ids[position]));
        ++visited;
      });
      EXPECT_EQ(visited, upper);
      EXPECT_EQ(visited + below, count);
    }
  }
}

// A matrix with a column that is no row (ids 0 .. n-1 as rows, a coupling
// to id n beyond them) is refused by GatheredRows on every rank, the owner
// and the others alike, instead of leaving the others waiting in their next
// collective.
TEST(Redistribution, GatheredRowsRefuseAColumnThatIsNoRowOnEveryRank) {
  const GlobalOrdinal n = 9;
  auto rows = Teuchos::rcp(new Map(n, 0, world()));
  auto columns = Teuchos::rcp(new Map(n + 1, 0, world()));
  auto A = Teuchos::rcp(new CrsMatrix(rows, 2));
  for (std::size_t l = 0; l < rows->getNodeNumElements(); ++l) {
    const GlobalOrdinal g = rows->getGlobalElement(static_cast<LocalOrdinal>(l));
    A->insertGlobalValues(g, Teuchos::tuple(g, g + 1), Teuchos::tuple(2.0, -1.0));  // row n - 1 reaches id n
  }
  A->fillComplete(columns, rows);
  EXPECT_THROW(GatheredRows(A, 0), std::invalid_argument);
  EXPECT_THROW(GatheredRows(A, world()->getSize() - 1), std::invalid_argument);
}

// gatherOnRank (MpiComm.hpp), which gatherRows, MUMPS's ordering and the
// partitioned basis's interface call: every rank's entries in rank order on
// the owner; past its limit (MPI's int counts, here lowered so that a test
// reaches the refusal without 2^31 entries) a std::length_error naming the
// array on every rank, the owner's total agreed on before any rank decides.
TEST(Redistribution, GatherOnRankConcatenatesInRankOrderAndRefusesPastItsLimitOnEveryRank) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const int owner = size - 1;
  std::vector<long long> mine(static_cast<std::size_t>(rank + 2));  // rank r holds r + 2 entries
  for (std::size_t k = 0; k < mine.size(); ++k) mine[k] = 1000LL * rank + static_cast<long long>(k);
  long long total = 0;
  std::vector<long long> expected;
  for (int r = 0; r < size; ++r)
    for (int k = 0; k < r + 2; ++k) expected.push_back(1000LL * r + k), ++total;
  const auto all = gatherOnRank(mine, owner, MPI_COMM_WORLD, "test entries", total);
  if (rank == owner) EXPECT_EQ(all, expected);
  else EXPECT_TRUE(all.empty());

  bool refused = false;
  try {
    gatherOnRank(mine, owner, MPI_COMM_WORLD, "test entries", total - 1);
  } catch (const std::length_error& e) {
    refused = true;
    EXPECT_NE(std::string(e.what()).find("test entries: " + std::to_string(total)), std::string::npos) << e.what();
  }
  EXPECT_TRUE(refused) << "rank " << rank;
  // Still in step: a collective after the refusal completes on every rank.
  int one = 1, sum = 0;
  MPI_Allreduce(&one, &sum, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(sum, size);
}
