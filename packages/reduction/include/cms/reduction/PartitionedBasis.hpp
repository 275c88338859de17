// A large substructure reduced by substructuring it once more, automatically
// (doc/theory.md §18): its nodes are partitioned by Scotch into parts, the
// nodes on the cuts form the separator B, and
//
//   u_I^p = X_p u_B + Phi_p eta_p,   X_p = -K_pp^-1 K_pB   (static extension)
//   u_B   = Psi xi
//
// where Phi_p are part p's fixed-interface modes (B held) below the cut-off
// and Psi the modes of the interface's own problem (S, M^) below it: S the
// Schur complement K_BB - sum_p K_Bp K_pp^-1 K_pB, M^ the mass of the
// static extensions (Craig & Chang's characteristic constraint modes; the
// first level of Bennighof & Lehoucq's AMLS). With a polynomial interface
// (on request, or past a separator size), u_B = Phi_B xi with Phi_B
// low-degree polynomials over the separator, and S, M^ are formed on their
// span only (§18.4). Each part is factored and
// solved on its own, the parts spread over the ranks, so nothing of the
// size of the whole substructure is ever factored. The basis is a Ritz
// basis like the others: M-orthonormalised in order, zero on the held rows;
// the synthesis projects the substructure's full matrices on it.
#pragma once

#include <string>
#include <vector>

#include "cms/reduction/RitzBasis.hpp"

namespace cms::reduction {

struct PartitionOptions {
  int parts = 0;                 ///< > 0: this many parts; 0: from maxDofs
  long long maxDofs = 20000;     ///< parts of at most about this many free DOFs (parts = 0)
  double cutoffHz = 0.0;         ///< part modes kept below this (Hz), > 0
  /// Interface modes kept below this multiple of cutoffHz: the interface's
  /// statically condensed (S, M^) is stiffer than the structure it stands
  /// for, so its modes need a higher cut-off than the parts' (§18.3).
  double interfaceCutoffFactor = 2.0;
  /// The interface problem's coordinates. Exact: every separator DOF (the
  /// exact Schur complement: per part n_B_p solves and n_p n_B_p^2 flops).
  /// Polynomial: per connected piece of the separator (children's
  /// attachment faces included) and per component, the monomials of degree
  /// <= interfaceDegree in its coordinates: the interface problem projected
  /// on their span (Rayleigh-Ritz, from above; §18.4), per part as many
  /// solves as coordinates. Auto: Exact up to exactInterfaceLimit separator
  /// DOFs, Polynomial beyond.
  enum class Interface { Auto, Exact, Polynomial };
  Interface interface = Interface::Auto;
  long long exactInterfaceLimit = 2000;
  int interfaceDegree = 3;
  /// Polynomial: the static shapes' separator values solve S u_B = g by
  /// block conjugate gradients (balancing preconditioner, §18.4) to this
  /// relative residual, within this many iterations (else NumericalError).
  double staticTolerance = 1e-12;
  int staticIterations = 500;
  /// Per interface mode, the interiors' static response (separator held)
  /// to its inertia load: one load-dependent Ritz step (§18.2).
  bool residualVectors = true;
  /// Static shapes under these load patterns (the Admissible basis's,
  /// RitzBasis.hpp), solved exactly through the partition: K_pp^-1 f_p and
  /// the Schur complement's factor on the separator (§18.2).
  std::vector<std::string> loadPatterns{"interfaces", "uniform", "rotation", "centrifugal"};
  double eigensolverTolerance = 1e-10;
  double dependenceTolerance = 1e-8;
};

/// Collective over the substructure's communicator. The children's
/// interface rows join the separator (their motion is an interface
/// coordinate, as in Craig-Bampton). The partition is made on rank 0 from
/// the whole graph of K's nonzero entries (not its stored pattern, which
/// depends on how K was assembled), so the basis does not depend on the
/// rank count beyond rounding. Throws NumericalError naming the part when
/// its stiffness with the separator held is not positive definite, when an
/// eigensolve fails, or when the polynomial interface's static solve does
/// not converge (on every rank); InputError for options out of range.
RitzBasis partitionedBasis(const substructure::Substructure& s, const SubstructureBoundary& boundary,
                           const PartitionOptions& options);

}  // namespace cms::reduction
