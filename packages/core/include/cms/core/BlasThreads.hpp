// The BLAS library's own threads. Debian's BLAS alternative is usually
// OpenBLAS, which runs each call on a pool of its own threads (one per core
// by default) whose idle workers spin in sched_yield. Where cms runs threads
// or ranks of its own that each call the BLAS, the two pools oversubscribe
// the cores: measured on the 1.5e4-DOF rotor's 101-speed sweep (two sweep
// threads, each one dense solve of n = 66 at a time), 63% of the CPU went to
// OpenBLAS's dispatch and spinning, and the sweep took 1.8 s instead of
// 0.7 s (doc/benchmarks.md, "The BLAS's own threads"). The control is
// resolved at run time (openblas_set_num_threads): with a BLAS that has no
// threads of its own (the reference BLAS, OpenBLAS's serial build) every
// call here is a no-op.
#pragma once

namespace Teuchos {
template <class Ordinal>
class Comm;
}

namespace cms {

/// Threads the BLAS runs one call on; 1 for a BLAS without threads of its own.
int blasThreads();

/// Sets the BLAS's threads (n >= 1); false when the BLAS has no such control.
bool setBlasThreads(int n);

/// For this object's lifetime the BLAS runs on `n` threads, its previous
/// setting restored after: around a pool of cms's own threads that each call
/// the BLAS (SynthesizedStructure::solveMany's dense solves).
class BlasThreadScope {
public:
  explicit BlasThreadScope(int n);
  ~BlasThreadScope();
  BlasThreadScope(const BlasThreadScope&) = delete;
  BlasThreadScope& operator=(const BlasThreadScope&) = delete;

private:
  int previous_;
};

/// The cores this process may run on: the count of its CPU affinity mask
/// (Linux), else the hardware threads. A launcher binds ranks: Open MPI's
/// mpiexec puts a lone rank on one core by default, where a BLAS of two
/// threads ran both on that core (doc/benchmarks.md, "A lone rank under
/// mpiexec").
int usableCores();

/// This rank's share of its node: the hardware threads over the ranks on the
/// node, at most usableCores(), at least 1.
int coresPerRank(int ranksOnThisNode);

/// Gives the BLAS this rank's share of its node's cores (coresPerRank of
/// ranksOnNode, DistributedDirectSolver.hpp) unless the environment already chose
/// (OPENBLAS_NUM_THREADS, GOTO_NUM_THREADS or OMP_NUM_THREADS set: left as
/// they are). Two ranks on two cores each had two OpenBLAS threads before.
/// Collective over `comm`. Returns the BLAS's threads afterwards.
int shareCoresWithBlas(const Teuchos::Comm<int>& comm);

}  // namespace cms
