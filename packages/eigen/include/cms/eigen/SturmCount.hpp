// How many eigenfrequencies of a gyroscopic system lie below a frequency,
// counted from the inertia of one Hermitian factorisation rather than from
// any eigensolver (doc/theory.md, "Sturm count of a gyroscopic system").
#pragma once

#include <complex>
#include <vector>

#include <functional>
#include <string>
#include <vector>

#include "cms/eigen/GyroscopicSystem.hpp"
#include "cms/eigen/SparseGyroscopicSystem.hpp"

namespace cms::eigen {

/// The number of negative eigenvalues of the dense Hermitian n x n matrix
/// whose lower triangle `lower` holds (column-major; overwritten by its
/// Bunch-Kaufman factor, LAPACK zhetrf): Sylvester's law on D's 1x1 pivots
/// and 2x2 blocks' eigenvalues, each counted negative only below -tiny.
/// Throws NumericalError if zhetrf fails or a pivot is not finite. Shared
/// by sturmCount and (symmetricNegatives) the Campbell study's stiffness
/// count.
int hermitianNegatives(std::vector<std::complex<double>>& lower, int n, double tiny = 0.0);
/// The same for a real symmetric matrix (LAPACK dsytrf: a quarter of the
/// complex factorisation's flops); `within`, if given, receives how many of
/// D's eigenvalues lie within tiny of zero (counted neither way).
int symmetricNegatives(std::vector<double>& lower, int n, double tiny = 0.0, int* within = nullptr);

/// The number of eigenfrequencies omega_j < omega (counted with multiplicity,
/// one per +/- pair) of M q'' + G q' + K q = 0 with M > 0 and K > 0: the number
/// of negative eigenvalues of the Hermitian Q(omega) = K - omega^2 M + i omega G.
/// Each eigencurve of Q starts positive (Q(0) = K > 0), ends negative and has
/// exactly one zero on (0, inf), so the inertia counts the crossings below
/// omega. Reliable while omega is farther from every eigenfrequency than
/// rounding (eps times the conditioning of Q) can move it. LAPACK zhetrf
/// (Bunch-Kaufman), n^3/3 complex operations. Throws NumericalError if the
/// factorisation fails; InputError if omega is not positive and finite.
int sturmCount(const GyroscopicSystem& sys, double omega);

/// A count on the sparse path, with where it was taken.
struct SparseSturmCount {
  long long count = 0;  ///< eigenfrequencies below `omega`
  double omega = 0.0;   ///< where the count was taken (the request, or shifted off a tiny pivot)
  bool reliable = false;
  std::string note;     ///< a shift, or why the count is unreliable
};

/// The same count for a distributed system (doc/theory.md §5, "Sturm count on
/// the sparse path"): the inertia of Q(omega) = A + iB, A = K - omega^2 M,
/// B = omega G, through its real embedding [[A, -B], [B, A]] (or of A alone
/// when G = 0), by CHOLMOD's simplicial L D L^T without pivoting or, when
/// CHOLMOD's analysis predicts that costly, MUMPS's multifrontal one
/// (cms::inertia, InertiaMethod::Auto). A pivot
/// zero to rounding (omega on an eigenfrequency) moves omega by a relative
/// +1e-8, then -1e-8; if both fail too, the count is returned unreliable.
/// Collective; the same result on every rank. Valid for M > 0, K > 0.
SparseSturmCount sturmCount(const SparseGyroscopicSystem& sys, double omega);

/// The check of a returned set of frequencies against a Sturm count.
struct LowestSetCheck {
  enum class Verdict { Confirmed, Disagrees, Unreliable, NotChecked };
  Verdict verdict = Verdict::NotChecked;
  double cut = 0.0;           ///< where the count was taken (rad/s)
  long long known = 0;        ///< known frequencies below the cut (the returned set's whole last cluster)
  long long counted = 0;      ///< the Sturm count there
  std::string message;        ///< the confirmation, or what disagreed / why not checked
  std::string clusterNote;    ///< non-empty when the N lowest cut a cluster: which modes, how many to ask for
};

/// Checks that the lowest `nModes` of `omegas` (ascending, every accurately
/// known frequency: the returned ones first, then any further ones the
/// solver found) are the nModes lowest of the system. The set is extended to
/// the whole cluster of the nModes-th (values within relClusterTol of it),
/// and `countBelow` is asked at a cut just above that cluster (10
/// relClusterTol above its top, or the middle of the gap to the next known
/// value if nearer); it must find exactly as many frequencies as are known
/// below.
LowestSetCheck checkLowestSet(const std::vector<double>& omegas, int nModes, double relClusterTol,
                              const std::function<SparseSturmCount(double)>& countBelow);

/// What a solver concluded about its set of frequencies.
struct SetConfirmation {
  bool complete = false;  ///< confirmed (or not checkable); false: still wrong after a recomputation
  std::string note;       ///< for GyroscopicResult::reason
};

/// The policy both paths follow. `check` returns "" when the set agrees with
/// the count (setting `confirmation`), else what disagreed; then `recompute`
/// replaces the set once (returning how, for the note) and the set is
/// checked again. A set that still disagrees is not complete: the caller
/// reports NumericalIssue, never a converged answer.
SetConfirmation confirmLowestSet(const std::function<std::string(std::string& confirmation)>& check,
                                 const std::string& firstSet, const std::function<std::string()>& recompute);

}  // namespace cms::eigen
