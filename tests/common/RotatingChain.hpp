// A test structure with a closed description: a chain of point masses, each
// with two in-plane DOFs (x, y), joined by springs, optionally grounded, and
// spinning at Omega either in a rotating frame (Coriolis 2 m Omega, softening
// m Omega^2) or as a rotor in the stationary frame (polar-inertia coupling,
// no softening). Every entry is a formula of the node index, so the same
// system is built distributed (any rank count) and dense, independently.
#pragma once

#include <cmath>
#include <functional>
#include <random>

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>

#include "cms/eigen/GyroscopicSystem.hpp"
#include "cms/eigen/SparseGyroscopicSystem.hpp"

namespace cms::fixtures {

struct ChainSpec {
  long long nodes = 50;
  double spin = 0.0;
  bool grounded = true;       ///< false: a free chain (K singular at zero spin)
  bool rotatingFrame = true;  ///< false: stationary-frame rotor coupling
  unsigned seed = 1;
};

inline double nodeRandom(unsigned seed, long long node, int which) {
  std::mt19937 rng(static_cast<unsigned>(node) * 2654435761u + 7919u * which + 104729u * seed);
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng);
}

/// Calls add(row, col, m, g, k) for every nonzero of M, G, K.
inline void chainEntries(const ChainSpec& s,
                         const std::function<void(long long, long long, double, double, double)>& add,
                         long long firstNode, long long lastNode) {
  const double W = s.spin;
  for (long long i = firstNode; i < lastNode; ++i) {
    const double m = 1.0 + nodeRandom(s.seed, i, 0);
    const long long x = 2 * i, y = 2 * i + 1;
    double kxx = 0.0, kyy = 0.0;
    if (s.grounded) kxx += 10.0 * (1 + nodeRandom(s.seed, i, 1)), kyy += 25.0 * (1 + nodeRandom(s.seed, i, 2));
    // Springs to neighbours (x and y stiffness differ).
    for (long long j : {i - 1, i + 1}) {
      if (j < 0 || j >= s.nodes) continue;
      const long long a = std::min(i, j);
      const double kx = 400.0 * (1 + nodeRandom(s.seed, a, 3)), ky = 900.0 * (1 + nodeRandom(s.seed, a, 4));
      kxx += kx, kyy += ky;
      add(x, 2 * j, 0.0, 0.0, -kx);
      add(y, 2 * j + 1, 0.0, 0.0, -ky);
    }
    double gxy;
    if (s.rotatingFrame) {
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

inline eigen::GyroscopicSystem denseChain(const ChainSpec& s) {
  const int n = static_cast<int>(2 * s.nodes);
  eigen::GyroscopicSystem d{DenseMatrix(n, n), DenseMatrix(n, n), DenseMatrix(n, n)};
  chainEntries(
      s,
      [&](long long r, long long c, double m, double g, double k) {
        d.M(r, c) += m, d.G(r, c) += g, d.K(r, c) += k;
      },
      0, s.nodes);
  return d;
}

inline eigen::SparseGyroscopicSystem sparseChain(const ChainSpec& s,
                                                 const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  // Whole nodes per rank, contiguous.
  const int p = comm->getSize(), r = comm->getRank();
  const long long first = s.nodes * r / p, last = s.nodes * (r + 1) / p;
  auto map = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(2 * s.nodes),
                                  static_cast<size_t>(2 * (last - first)), 0, comm));
  auto M = Teuchos::rcp(new CrsMatrix(map, 4)), G = Teuchos::rcp(new CrsMatrix(map, 4)),
       K = Teuchos::rcp(new CrsMatrix(map, 4));
  chainEntries(
      s,
      [&](long long row, long long col, double m, double g, double k) {
        const GlobalOrdinal c = col;
        if (m != 0.0) M->insertGlobalValues(row, Teuchos::tuple(c), Teuchos::tuple(m));
        if (g != 0.0) G->insertGlobalValues(row, Teuchos::tuple(c), Teuchos::tuple(g));
        K->insertGlobalValues(row, Teuchos::tuple(c), Teuchos::tuple(k));
      },
      first, last);
  // A G with no entries still needs a (zero) diagonal to exist in every row.
  for (long long row = 2 * first; row < 2 * last; ++row)
    G->insertGlobalValues(row, Teuchos::tuple<GlobalOrdinal>(row), Teuchos::tuple(0.0));
  M->fillComplete(), G->fillComplete(), K->fillComplete();
  return {M, G, K};
}

}  // namespace cms::fixtures
