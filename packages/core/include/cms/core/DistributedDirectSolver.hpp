// A sparse direct factorisation done across the ranks of a distributed
// Tpetra::CrsMatrix by MUMPS (Debian's libmumps-dev, called directly through
// its C interface; issue 18), instead of gathering the matrix to rank 0 as
// SparseDirectSolver's CHOLMOD and KLU2 do.
//
//   input    distributed assembled (ICNTL(18) = 3): each rank hands MUMPS the
//            rows it owns, straight from the CrsMatrix (upper triangle only
//            for the symmetric kinds); nothing is gathered.
//   ordering sequential analysis on the host (ICNTL(28) = 1, ICNTL(7) = 7,
//            MUMPS's automatic choice): Debian's parallel libmumps-dev has
//            PORD, AMD, AMF and QAMD but neither PT-Scotch nor ParMETIS
//            (those are libmumps-ptscotch-dev, not linked here). The
//            analysis is symbolic; the factorisation is distributed.
//   solve    distributed right-hand side (ICNTL(20) = 10: each rank gives
//            its own rows) and distributed solution (ICNTL(21) = 1), moved to
//            the caller's map by one Tpetra::Import; no rank holds all of B
//            or X.
//   inertia  for the symmetric kinds, the number of negative pivots of
//            L D L^T (INFOG(12)), which by Sylvester's law is the number of
//            negative eigenvalues (Sturm counts), and the null pivots
//            (INFOG(28), null-pivot detection ICNTL(24) = 1 at a threshold).
//   errors   INFOG(1) < 0 becomes cms::NumericalError naming the matrix,
//            MUMPS's code, INFOG(2) and the meaning of the code. Workspace
//            shortfalls (-8, -9, -14, -17, -20) are retried with twice the
//            relaxation (ICNTL(14)) up to four times first.
//
// Every call is collective over the matrix's communicator. The matrix must be
// square and fill-complete with its row, domain and range maps the same.
// Tpetra and MUMPS headers stay in the .cpp.
#pragma once

#include <memory>
#include <string>

#include <Teuchos_Comm.hpp>

#include "cms/core/SparseInertia.hpp"
#include "cms/core/TpetraTypes.hpp"

namespace cms {

class DistributedDirectSolver {
public:
  enum class Kind {
    General,            ///< SYM = 0: LU with partial threshold pivoting, any nonsingular matrix
    Symmetric,          ///< SYM = 2: L D L^T with 1x1/2x2 pivots, symmetric indefinite; inertia
    PositiveDefinite    ///< SYM = 1: L D L^T without pivoting, symmetric positive definite only
  };

  /// `name` is how errors refer to the matrix ("K of blade", "Q(tau)").
  /// `nullPivotTolerance` > 0: a pivot is null (counted in nullPivots(),
  /// replaced by MUMPS) when MUMPS finds its row's norm at or below this
  /// times the norm of the matrix as MUMPS scaled it (CNTL(3)); 0 (the
  /// default): kTinyPivot, the "zero to rounding" of cms::inertia. Throws
  /// cms::InputError for a matrix that is not square, not fill-complete, or
  /// has different row and domain/range maps.
  DistributedDirectSolver(Teuchos::RCP<const CrsMatrix> A, Kind kind, std::string name,
                          double nullPivotTolerance = 0.0);
  /// The real symmetric embedding [[A, -B], [B, A]] (order 2N) of the
  /// Hermitian A + iB (A symmetric, B skew, both on A's row map), whose
  /// inertia counts A + iB's eigenvalues twice (SparseInertia.hpp): MUMPS
  /// is given its upper triangle straight from A's and B's rows, no 2N-row
  /// matrix is built, and the factorisation counts pivots only (solve()
  /// refused). Kind::Symmetric. Throws cms::InputError for a B that is not
  /// fill-complete on A's row map.
  DistributedDirectSolver(Teuchos::RCP<const CrsMatrix> A, Teuchos::RCP<const CrsMatrix> B, std::string name);
  ~DistributedDirectSolver();
  DistributedDirectSolver(const DistributedDirectSolver&) = delete;
  DistributedDirectSolver& operator=(const DistributedDirectSolver&) = delete;

  /// The fill-reducing ordering of the (sequential) analysis: MUMPS's
  /// automatic choice (ICNTL(7) = 7: PORD, the only nested dissection
  /// Debian's MUMPS has), or METIS's nested dissection computed by CHOLMOD
  /// (cholmod_metis) on the host and given to MUMPS (ICNTL(7) = 1,
  /// PERM_IN). distributedInertia takes METIS: on the real 2n embedding of
  /// the 5e4-DOF rotor's Sturm count (doc/benchmarks.md, "Sturm counts")
  /// PORD's analysis alone was a third of a 13 s count, and the minimum
  /// degree orderings (AMD: 8.6 s) give a chain an elimination tree as deep
  /// as the chain, which overflowed MUMPS's stack on two ranks at 1e5 rows.
  /// Before factor().
  enum class Ordering { Automatic, NestedDissection };
  void setOrdering(Ordering o) { ordering_ = o; }

  /// Count pivots only (a Sturm count, a definiteness test): MUMPS discards
  /// each front's factor as soon as it is eliminated (ICNTL(31) = 1), so the
  /// factorisation needs only its working memory, MUMPS's out-of-core
  /// estimate INFO(17) (a third of the in-core INFO(15) on the rotor's K),
  /// and the memory guard holds that estimate against the budget. solve()
  /// is then refused. Before factor(). With `releaseMatrix`, factor() lets
  /// go of the matrices once MUMPS's triplets are made: a count given the
  /// only reference to its matrix (distributedInertia(RCP)) frees it before
  /// the factorisation's own peak, and cannot factor a second time.
  void setPivotsOnly(bool only, bool releaseMatrix = false) {
    pivotsOnly_ = only;
    releaseMatrix_ = only && releaseMatrix;
  }

  /// Analysis and numeric factorisation. Throws cms::NumericalError (the
  /// matrix's name, MUMPS's INFOG(1), INFOG(2) and meaning) if MUMPS fails,
  /// and, unless `allowNullPivots`, when MUMPS found null pivots (the matrix
  /// is singular to working precision; the counts are set either way, for a
  /// caller that counts inertia or tells "not positive definite" apart).
  void factor(bool allowNullPivots = false);
  /// X = A^-1 B (B and X on A's row map; any number of columns).
  void solve(const MultiVector& B, MultiVector& X) const { solve(B, X, false); }
  /// X = A^-T B when `transposed` (MUMPS's ICNTL(9) != 1), from the same
  /// factors: for inverse iteration's left vectors (the real form of
  /// Q(sigma)^H is that of Q(sigma) transposed).
  void solve(const MultiVector& B, MultiVector& X, bool transposed) const;

  /// Symmetric kinds: negative pivots of L D L^T, i.e. negative eigenvalues
  /// (INFOG(12)); General: 0.
  long long negativePivots() const { return negative_; }
  /// Pivots MUMPS found null at the threshold (INFOG(28)).
  long long nullPivots() const { return null_; }
  long long rows() const { return n_; }

  /// Seconds of factor() in all, and of its (sequential) analysis phase.
  double factorSeconds() const { return factorSeconds_; }
  double analysisSeconds() const { return analysisSeconds_; }
  /// The ordering the analysis used (INFOG(7): 0 AMD, 1 given (METIS here), 2 AMF, 4 PORD, 6 QAMD, ...).
  int ordering() const { return orderingUsed_; }
  /// Entries of the factors (INFOG(29)) and flops of the elimination (RINFOG(3)).
  double factorEntries() const { return factorEntries_; }
  double factorFlops() const { return factorFlops_; }
  /// MUMPS's own memory in the factorisation, MB: the largest rank's
  /// (INFOG(21)) and the sum over ranks (INFOG(22)).
  double factorMemoryMaxMB() const { return memoryMaxMB_; }
  double factorMemoryTotalMB() const { return memoryTotalMB_; }
  const std::string& name() const { return name_; }

  /// What MUMPS's error code INFOG(1) < 0 means (MUMPS 5.5 user guide §8).
  static std::string errorMeaning(int infog1, long long infog2);

private:
  struct Impl;
  void refuseWhatCannotFit(Impl& m, const Teuchos::Comm<int>& comm, double growth) const;
  std::unique_ptr<Impl> impl_;
  std::string name_;
  long long n_ = 0, negative_ = 0, null_ = 0;
  double factorSeconds_ = 0.0, analysisSeconds_ = 0.0, factorEntries_ = 0.0, factorFlops_ = 0.0;
  Ordering ordering_ = Ordering::Automatic;
  bool pivotsOnly_ = false;
  bool releaseMatrix_ = false;
  int orderingUsed_ = -1;  ///< INFOG(7) after factor()
  double memoryMaxMB_ = 0.0, memoryTotalMB_ = 0.0;
};

/// How many ranks of `comm` share this rank's node (its memory). Collective.
int ranksOnNode(const Teuchos::Comm<int>& comm);

/// The inertia of the symmetric A from MUMPS's distributed L D L^T (SYM = 2):
/// the same contract as cms::inertia (SparseInertia.hpp), pivots zero to
/// rounding counted in tinyPivots by MUMPS's null-pivot detection at
/// kTinyPivot max |a_jj|; maxPivotRatio is not available from MUMPS (0).
/// A MUMPS failure is returned in `failure`, not thrown. Collective.
SparseInertia distributedInertia(const CrsMatrix& A);
/// The same taking A over: a caller passing its only reference (a K - w^2 M
/// formed for the count) has it freed once MUMPS's triplets are made, before
/// the factorisation's working memory (the count was `cms modes`'s peak on
/// the bar of doc/benchmarks.md).
SparseInertia distributedInertia(Teuchos::RCP<const CrsMatrix> A);
/// The same for the real embedding [[A, -B], [B, A]] of the Hermitian
/// A + iB, its triplets built straight from A and B (no 2N-row matrix):
/// counts of the embedding, each eigenvalue of A + iB twice (the caller
/// halves them). Collective.
SparseInertia distributedInertia(const CrsMatrix& A, const CrsMatrix& B);

/// The "Direct Solver" choice for a factorisation of A: "CHOLMOD" (the
/// gathered SparseDirectSolver methods), "MUMPS", or "Auto": MUMPS when A is
/// distributed over more than one rank and has at least
/// kDistributedAutoEntries stored entries, else CHOLMOD. Entries rather
/// than rows: a factorisation's cost follows the graph's dimension, and a
/// 1-D chain of 1e5 rows (6e5 entries) factors in milliseconds gathered but
/// solves latency-bound across ranks (MUMPS's distributed triangular
/// solves: the 1e5-DOF chain's eigensolve test took 300 s on 2 ranks by
/// MUMPS, the whole test file 109 s on one by CHOLMOD), while a 3-D solid
/// reaches 2e6 entries at ~2e4 DOFs. `autoEntries` replaces that size for a
/// caller whose measurements say otherwise (the reduction's held stiffness:
/// kDistributedAutoEntriesReduction). Returns true for MUMPS. Throws
/// cms::InputError for any other choice.
inline constexpr long long kDistributedAutoEntries = 2000000;
/// Auto's size for a substructure's held stiffness: its many short solves
/// (Krylov sequences, constraint modes, shift-invert) pay MUMPS's
/// distributed triangular solves and its sequential analysis, and measured
/// slower than the gathered CHOLMOD at 1.3e5 DOFs on 2 ranks (Admissible 32:
/// 10.5 s against 5.9 s; Craig-Bampton 12: 21.6 s against 20.9 s,
/// doc/benchmarks.md); above 3e7 entries (~2.5e5 solid DOFs, a factor of
/// several GB on rank 0) memory decides for MUMPS.
inline constexpr long long kDistributedAutoEntriesReduction = 30000000;
bool useDistributedSolver(const std::string& choice, const CrsMatrix& A,
                          long long autoEntries = kDistributedAutoEntries);


}  // namespace cms
