// Y = alpha A X + beta Y for a Tpetra matrix and a block of vectors, the
// rows shared among this rank's cores. Debian's Trilinos builds Kokkos with
// its Serial backend only, so Tpetra's apply runs on one core: on the
// 54,000-DOF bar the products were 29% of the main thread's time while the
// second core idled (doc/benchmarks.md, "Sparse products on both cores").
#pragma once

#include <limits>
#include <vector>

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

/// Y = |A| |X| (entrywise absolute values): the scale of the rounding of
/// the product A X, whose computed entries lie within (the row's entries)
/// eps (|A||X|)_i of the exact ones (Higham, Accuracy and Stability of
/// Numerical Algorithms, §3.5). Collective (imports |X| to A's columns).
void multiplyAbsolute(const CrsMatrix& A, const MultiVector& X, MultiVector& Y);

/// Entry by entry, what a product A X may differ from exact by, relative to
/// (|A||X|)_i: the product's own (rows of fewer than 1e3 entries here: a
/// 20-node brick couples 81 nodes' 3 DOFs) and the rounding already in A's
/// entries, as far as A annihilates X in exact arithmetic (an elastic
/// stiffness and a rigid motion: its element matrices' sums).
inline constexpr double kProductRounding = 1e3 * std::numeric_limits<double>::epsilon();

/// Per column of AX = A X, whether it is rounding only: every row has
/// |(A X)_ij| <= kProductRounding (|A||X|)_ij, given absAX = |A||X| (rows
/// listed in `ignored`, global, are not looked at). The same on every rank
/// (collective).
std::vector<char> roundingOnly(const MultiVector& AX, const MultiVector& absAX,
                               const std::vector<GlobalOrdinal>& ignored = {});

}  // namespace cms
