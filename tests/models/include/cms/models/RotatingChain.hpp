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

namespace cms::models {

struct RotatingChain {
  /// Where the chain is grounded by springs: at every node (a low spectrum
  /// densely clustered near the grounding frequency: a hard case for Krylov
  /// methods), at its two end nodes only (string-like, well-separated low
  /// modes, omega_k ~ k), or nowhere (a free chain: K singular at zero spin).
  enum class Support { EveryNode, Ends, None };

  long long nodes = 50;
  double spin = 0.0;          ///< rad/s
  Support support = Support::EveryNode;
  bool rotatingFrame = true;  ///< false: stationary-frame rotor coupling
  unsigned seed = 1;

  long long dofs() const { return 2 * nodes; }
  /// For Support::Ends: a spin at which K stays positive definite, a fraction
  /// of the chain's lowest frequency (spin softening below every stiffness).
  double subcriticalSpin(double fraction = 0.5) const;

  struct Dense { DenseMatrix M, G, K; };
  struct Distributed { Teuchos::RCP<const CrsMatrix> M, G, K; };

  Dense dense() const;
  /// Whole nodes per rank, contiguous ids; collective.
  Distributed distributed(const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const;
};

}  // namespace cms::models
