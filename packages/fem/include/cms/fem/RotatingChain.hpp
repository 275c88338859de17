// A lumped test structure with a closed description: a chain of point masses,
// each with two in-plane DOFs (x, y), joined by springs, optionally grounded,
// spinning at Omega either in a rotating frame (Coriolis 2 m Omega, spin
// softening m Omega^2) or as a rotor in the stationary frame (polar-inertia
// coupling between the planes, no softening). Every entry is a formula of the
// node index (pseudo-random properties seeded by node), so the same structure
// is built distributed on any number of ranks and dense, independently: the
// sparse solvers' tests and benchmarks compare against the dense solver on it.
#pragma once

#include "cms/core/DenseMatrix.hpp"
#include "cms/core/TpetraTypes.hpp"

namespace Teuchos { template <class T> class Comm; }

namespace cms::fem {

struct RotatingChain {
  long long nodes = 50;
  double spin = 0.0;          ///< rad/s
  bool grounded = true;       ///< false: a free chain (K singular at zero spin)
  bool rotatingFrame = true;  ///< false: stationary-frame rotor coupling
  unsigned seed = 1;

  long long dofs() const { return 2 * nodes; }

  struct Dense { DenseMatrix M, G, K; };
  struct Distributed { Teuchos::RCP<const CrsMatrix> M, G, K; };

  Dense dense() const;
  /// Whole nodes per rank, contiguous ids; collective.
  Distributed distributed(const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const;
};

}  // namespace cms::fem
