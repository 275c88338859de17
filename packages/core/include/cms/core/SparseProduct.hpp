// Y = alpha A X + beta Y for a Tpetra matrix and a block of vectors, the
// rows shared among this rank's cores. Debian's Trilinos builds Kokkos with
// its Serial backend only, so Tpetra's apply runs on one core: on the
// 54,000-DOF bar the products were 29% of the main thread's time while the
// second core idled (doc/benchmarks.md, "Sparse products on both cores").
#pragma once

#include "cms/core/TpetraTypes.hpp"

namespace cms {

/// Y = alpha A X + beta Y (beta = 0 overwrites Y, NaN included, as Tpetra's
/// apply). On `threads` threads (0: blasThreads(), this rank's share of the
/// cores, BlasThreads.hpp) when A needs no communication (no import or
/// export: one rank, or rows and columns owned alike), X and Y have
/// constant stride, and the product is large enough to pay for the
/// threads; else Tpetra's apply. X and Y the same vectors go to Tpetra's
/// apply, which copies X; distinct views whose memory overlaps are
/// multiplied from a copy of X (Tpetra 13.2's apply got them wrong). Each
/// row's sum runs in the order of its stored entries whatever the thread
/// count, so every count above 1 gives the same bits.
void multiply(const CrsMatrix& A, const MultiVector& X, MultiVector& Y, double alpha = 1.0, double beta = 0.0,
              int threads = 0);

/// The threads multiply() would use for A X with `threads` asked (0:
/// blasThreads()); 1 means Tpetra's apply.
int multiplyThreads(const CrsMatrix& A, const MultiVector& X, const MultiVector& Y, int threads = 0);

}  // namespace cms
