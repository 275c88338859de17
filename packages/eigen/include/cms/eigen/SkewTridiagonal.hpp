// Orthogonal reduction of a real skew-symmetric matrix to skew tridiagonal
// form, Q^T A Q = T, and the frequencies T holds (doc/theory.md §2, "Skew
// tridiagonal form"). LAPACK has no skew reduction: dgebrd, which the dense
// Meirovitch path used, bidiagonalises A as a general matrix (twice the
// level-2 work) and returns every frequency twice.
#pragma once

#include <vector>

#include "cms/core/DenseMatrix.hpp"

namespace cms::eigen {

/// Q^T A Q = T, T skew tridiagonal: T(k+1, k) = t[k] = -T(k, k+1).
/// Q = H_0 H_1 ... H_{N-2}, H_k = I - tau[k] v_k v_k^T, v_k zero above row
/// k + 1, one at row k + 1 and the rest below the subdiagonal of column k of
/// `reflectors`: LAPACK dsytrd's lower storage, so dormtr applies Q.
struct SkewTridiagonal {
  DenseMatrix reflectors;
  std::vector<double> t;    ///< the N - 1 subdiagonal entries of T
  std::vector<double> tau;  ///< the N - 1 reflector scalars

  int size() const { return reflectors.numRows(); }
  /// C <- Q C (C has N rows; LAPACK dormtr).
  void applyQ(DenseMatrix& C) const;
};

/// Householder reduction of the N x N skew-symmetric A (both triangles
/// stored; only the strictly lower one is read, the upper taken as its
/// negative), blocked: a panel of `blockSize` reflectors is accumulated as
/// A <- A + V W^T - W V^T (the skew analogue of LAPACK dlatrd; v^T A v = 0
/// for skew A removes dlatrd's correction term), applied to the trailing
/// matrix by one matrix product. About (4/3) N^3 operations, a third of them
/// matrix-vector. Throws cms::InputError if A is not square.
SkewTridiagonal skewTridiagonalise(const DenseMatrix& A, int blockSize = 32);

/// The eigenvalues of T are +/- i sigma_j (and 0 if N is odd): sigma_j are
/// the singular values of the upper bidiagonal B with diagonal t[0], t[2],
/// t[4], ... and superdiagonal t[1], t[3], ... (T is, after the odd-even
/// permutation, [[0, B], [-B^T, 0]]). All floor(N/2) of them, descending,
/// by dqds (LAPACK dbdsqr without vectors: to high relative accuracy);
/// empty if dqds did not converge.
std::vector<double> skewFrequencies(const SkewTridiagonal& T);

/// Eigenvectors of the symmetric tridiagonal with zero diagonal and
/// off-diagonal `off` (its order is off.size() + 1) for the given
/// eigenvalues, ascending, by inverse iteration (LAPACK dstein): column c of
/// Z (column-major, order x values.size()) for values[c]. Such a matrix is
/// the Golub-Kahan form of a bidiagonal, so this is how both the skew
/// tridiagonal and the general bidiagonal path find their vectors. False if
/// inverse iteration did not converge.
bool zeroDiagonalTridiagonalVectors(const std::vector<double>& off, const std::vector<double>& values,
                                    std::vector<double>& Z);

/// For the given sigma (each a value of skewFrequencies, ascending), a
/// real orthonormal pair (y, z) per value spanning A's invariant plane,
/// A y = -sigma z, A z = sigma y: columns 2j and 2j + 1 of Y. From the
/// eigenvectors of the symmetric tridiagonal with zero diagonal and
/// off-diagonal t (LAPACK dstein: +sigma is one of its eigenvalues; T =
/// i D^-1 Ts D with D = diag(1, i, i^2, ...)), mapped by Q. Values closer
/// than dstein's orthogonalisation tolerance get orthogonal pairs, so a
/// repeated frequency gives as many planes as its multiplicity. False if
/// inverse iteration did not converge.
bool skewInvariantPlanes(const SkewTridiagonal& T, const std::vector<double>& sigma, DenseMatrix& Y);

}  // namespace cms::eigen
