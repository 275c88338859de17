// The least-squares fit by which a copy's rigid motions are read as its
// prototype's mixed (synthesis/src/CopiedBasis.hpp, rigidMotionFit; theory
// §15.2), on distributed vectors: an exact mixture is accepted and its M6
// recovered; one off by more than rounding is refused, which is the path
// that sends such a copy to be projected on its own. The assembly vouches
// for every copy's mesh, so no scene reaches the refusal: it is tested here
// directly.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include "CopiedBasis.hpp"

using namespace cms;
using namespace cms::synthesis;

namespace {

const double kEps = std::numeric_limits<double>::epsilon();

struct Fixture {
  Teuchos::RCP<const Map> map;
  Teuchos::RCP<MultiVector> Xq;
  std::vector<double> M6;  // na x na, column-major
  int na = 6;
  explicit Fixture(long long rows) {
    const auto comm = Teuchos::DefaultComm<int>::getComm();
    map = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(rows), 0, comm));
    Xq = Teuchos::rcp(new MultiVector(map, na));
    std::mt19937 rng(77 + comm->getRank());  // each rank its own rows
    std::normal_distribution<double> d;
    for (int j = 0; j < na; ++j) {
      auto x = Xq->getDataNonConst(j);
      for (std::size_t i = 0; i < x.size(); ++i) x[i] = d(rng);
    }
    std::mt19937 same(5);  // M6 the same on every rank
    M6.resize(static_cast<std::size_t>(na) * na);
    for (auto& m : M6) m = d(same);
  }
  /// Y = Xq M6 + delta ||Xq M6||_F / ||E||_F E, E random.
  Teuchos::RCP<MultiVector> mixed(double delta) const {
    auto small = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(na), 0, map->getComm(), Tpetra::LocallyReplicated));
    MultiVector m6(small, na);
    for (int j = 0; j < na; ++j)
      for (int i = 0; i < na; ++i) m6.replaceLocalValue(i, j, M6[i + static_cast<std::size_t>(j) * na]);
    auto Y = Teuchos::rcp(new MultiVector(map, na));
    Y->multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, *Xq, m6, 0.0);
    if (delta == 0.0) return Y;
    MultiVector E(map, na);
    E.randomize();
    std::vector<double> ny(na), ne(na);
    Y->norm2(Teuchos::ArrayView<double>(ny));
    E.norm2(Teuchos::ArrayView<double>(ne));
    double y2 = 0, e2 = 0;
    for (int j = 0; j < na; ++j) y2 += ny[j] * ny[j], e2 += ne[j] * ne[j];
    Y->update(delta * std::sqrt(y2 / e2), E, 1.0);
    return Y;
  }
};

}  // namespace

// An exact mixture: accepted, and M6 recovered to the fit's rounding,
// ~eps cond(Xq)^2 (normal equations; Gaussian columns of 1e4 rows have
// cond ~1.1): 1e3 eps bounds it with room.
TEST(CopyRotationFit, AnExactMixtureIsAcceptedAndRecovered) {
  const Fixture f(10000);
  auto Y = f.mixed(0.0);
  const auto M6 = detail::rigidMotionFit(*f.Xq, *Y);
  ASSERT_TRUE(M6.has_value());
  double err = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < f.M6.size(); ++i) err += std::pow((*M6)[i] - f.M6[i], 2), norm += f.M6[i] * f.M6[i];
  EXPECT_LT(std::sqrt(err), 1e3 * kEps * std::sqrt(norm));
}

// Off by 1e-10 of its norm (far above the 1e3 eps acceptance, far below
// anything a frequency would show): refused, not fitted. At 1e-14 (within
// the rounding the acceptance allows) still accepted.
TEST(CopyRotationFit, AMotionThatIsNotTheMixtureIsRefused) {
  const Fixture f(10000);
  auto off = f.mixed(1e-10);
  EXPECT_FALSE(detail::rigidMotionFit(*f.Xq, *off).has_value());
  auto rounding = f.mixed(1e-14);
  EXPECT_TRUE(detail::rigidMotionFit(*f.Xq, *rounding).has_value());
}

// Dependent prototype columns (a rigid motion repeated): the normal
// equations are not positive definite, or the fit does not reproduce Y;
// either way no M6.
TEST(CopyRotationFit, DependentPrototypeColumnsGiveNoFit) {
  const Fixture f(1000);
  auto Xq = Teuchos::rcp(new MultiVector(*f.Xq, Teuchos::Copy));
  Xq->getVectorNonConst(5)->update(1.0, *Xq->getVector(0), 0.0);  // column 5 = column 0
  auto Y = f.mixed(0.0);
  Y->getVectorNonConst(5)->randomize();  // a motion outside the span of the dependent Xq
  EXPECT_FALSE(detail::rigidMotionFit(*Xq, *Y).has_value());
}
