// Y = alpha A X + beta Y for a Tpetra matrix and a block of vectors, the
// rows shared among this rank's cores. Debian's Trilinos builds Kokkos with
// its Serial backend only, so Tpetra's apply runs on one core: on the
// 54,000-DOF bar the products were 29% of the main thread's time while the
// second core idled (doc/benchmarks.md, "Sparse products on both cores").
#pragma once

#include "cms/core/TpetraTypes.hpp"

namespace cms {

/// Y = alpha A X + beta Y (beta = 0 overwrites Y, NaN included, as Tpetra's
/// apply). When A needs no communication (no import or export: one rank,
/// or rows and columns owned alike) and X and Y have constant stride, by
/// cms's own kernel, which loads each entry of A once per four columns
/// (with it on one thread instead of Tpetra 13.2's serial apply, a run on
/// the bar of Lagrange bricks went from 1.74 to 1.55 s, doc/benchmarks.md
/// "Elements of higher order against CalculiX"), on `threads` threads (0:
/// blasThreads(), this rank's share of the cores, BlasThreads.hpp) when the
/// product is large enough to pay for
/// them, else on one. Otherwise Tpetra's apply. X and Y the same vectors go
/// to Tpetra's apply, which copies X; distinct views whose memory overlaps
/// are multiplied from a copy of X (Tpetra 13.2's apply got them wrong).
/// Each row's sum runs in the order of its stored entries whatever the
/// thread count, so every count gives the same bits.
void multiply(const CrsMatrix& A, const MultiVector& X, MultiVector& Y, double alpha = 1.0, double beta = 0.0,
              int threads = 0);

/// The threads multiply() would run its own kernel on for A X with
/// `threads` asked (0: blasThreads()); 0 means Tpetra's apply.
int multiplyThreads(const CrsMatrix& A, const MultiVector& X, const MultiVector& Y, int threads = 0);

}  // namespace cms
