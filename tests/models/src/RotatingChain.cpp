#include "cms/models/RotatingChain.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>

#include "cms/core/HashRandom.hpp"

namespace cms::models {

namespace {
double nodeRandom(unsigned seed, long long node, int which) {
  return hashUnit(static_cast<std::uint64_t>(node), 8u * seed + which);
}

using Sink = std::function<void(long long, long long, double, double, double)>;

/// add(row, col, m, g, k) for every nonzero of the rows of nodes [first, last).
void entries(const RotatingChain& s, const Sink& add, long long first, long long last) {
  const double W = s.spin;
  for (long long i = first; i < last; ++i) {
    const double m = 1.0 + nodeRandom(s.seed, i, 0);
    const long long x = 2 * i, y = 2 * i + 1;
    double kxx = 0.0, kyy = 0.0;
    const bool grounded = s.support == RotatingChain::Support::EveryNode ||
                          (s.support == RotatingChain::Support::Ends && (i == 0 || i == s.nodes - 1));
    if (grounded)
      kxx += 10.0 * (1 + nodeRandom(s.seed, i, 1)), kyy += 25.0 * (1 + nodeRandom(s.seed, i, 2));
    for (long long j : {i - 1, i + 1}) {  // springs to neighbours, x and y stiffness differ
      if (j < 0 || j >= s.nodes) continue;
      const long long a = std::min(i, j);
      const double kx = 400.0 * (1 + nodeRandom(s.seed, a, 3)),
                   ky = 900.0 * (1 + nodeRandom(s.seed, a, 4));
      kxx += kx, kyy += ky;
      add(x, 2 * j, 0.0, 0.0, -kx);
      add(y, 2 * j + 1, 0.0, 0.0, -ky);
    }
    double gxy;
    if (s.rotatingFrame) {  // doc/theory.md, "Rotating point mass"
      gxy = -2.0 * m * W;
      kxx -= m * W * W, kyy -= m * W * W;
    } else {
      gxy = 0.3 * m * W;
    }
    add(x, x, m, 0.0, kxx);
    add(y, y, m, 0.0, kyy);
    add(x, y, 0.0, gxy, 0.0);
    add(y, x, 0.0, -gxy, 0.0);
  }
}
}  // namespace

double RotatingChain::subcriticalSpin(double fraction) const {
  // Lowest stiffness eigenvalue of a chain held at its ends is about
  // k_min (pi / (nodes + 1))^2 with k_min = 400 the softest spring; the heaviest
  // mass is 2, so m Omega^2 stays below it for Omega = fraction * sqrt(k_min / 2) pi / (nodes + 1).
  return fraction * std::sqrt(400.0 / 2.0) * M_PI / static_cast<double>(nodes + 1);
}

RotatingChain::Dense RotatingChain::dense() const {
  const int n = static_cast<int>(dofs());
  Dense d{DenseMatrix(n, n), DenseMatrix(n, n), DenseMatrix(n, n)};
  entries(
      *this,
      [&](long long r, long long c, double m, double g, double k) {
        d.M(r, c) += m, d.G(r, c) += g, d.K(r, c) += k;
      },
      0, nodes);
  return d;
}

RotatingChain::Distributed RotatingChain::distributed(
    const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const {
  const int p = comm->getSize(), r = comm->getRank();
  const long long first = nodes * r / p, last = nodes * (r + 1) / p;
  auto map = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(dofs()),
                                  static_cast<size_t>(2 * (last - first)), 0, comm));
  auto M = Teuchos::rcp(new CrsMatrix(map, 1)), G = Teuchos::rcp(new CrsMatrix(map, 2)),
       K = Teuchos::rcp(new CrsMatrix(map, 3));
  entries(
      *this,
      [&](long long row, long long col, double m, double g, double k) {
        const auto c = Teuchos::tuple<GlobalOrdinal>(col);
        if (m != 0.0) M->insertGlobalValues(row, c, Teuchos::tuple(m));
        if (g != 0.0) G->insertGlobalValues(row, c, Teuchos::tuple(g));
        if (k != 0.0 || row == col) K->insertGlobalValues(row, c, Teuchos::tuple(k));
      },
      first, last);
  // A zero diagonal keeps every row of G present when the spin is zero.
  for (long long row = 2 * first; row < 2 * last; ++row)
    G->insertGlobalValues(row, Teuchos::tuple<GlobalOrdinal>(row), Teuchos::tuple(0.0));
  M->fillComplete(), G->fillComplete(), K->fillComplete();
  return {M, G, K};
}

}  // namespace cms::models
