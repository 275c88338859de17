// core/Redistribution (doc/architecture.md, "Parallelism"): a distributed
// matrix and multivector gathered whole onto one rank and re-expressed on a
// one-rank communicator, and a multivector scattered back, against the
// distributed originals; a mismatch on the owner raises on every rank (no
// hang), and a map whose ids are not 0 .. n-1 is refused everywhere.
#include <gtest/gtest.h>

#include <stdexcept>

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

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
