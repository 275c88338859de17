#include "cms/eigen/GyroscopicSystem.hpp"

#include <algorithm>
#include <cmath>

#include "cms/core/Error.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"

namespace cms::eigen {

bool GyroscopicSystem::damped() const {
  return (D.numRows() > 0 && frobeniusNorm(D) > 0.0) || (N.numRows() > 0 && frobeniusNorm(N) > 0.0);
}

void GyroscopicSystem::validate(double relTol) const {
  const int n = M.numRows();
  CMS_INPUT_CHECK(n == 0, "GyroscopicSystem: M is empty (0 DOFs)");
  const std::pair<const DenseMatrix*, const char*> mats[] = {{&M, "M"}, {&G, "G"}, {&K, "K"}};
  for (const auto& [A, name] : mats) {
    CMS_INPUT_CHECK(A->numRows() != A->numCols(), "GyroscopicSystem: " << name << " is "
                                                      << A->numRows() << "x" << A->numCols()
                                                      << ", not square");
    CMS_INPUT_CHECK(A->numRows() != n, "GyroscopicSystem: " << name << " is " << A->numRows()
                                           << "x" << A->numCols() << " but M is " << n << "x"
                                           << n);
    requireFinite(*A, std::string("GyroscopicSystem: ") + name);
  }
  // The optional damping (D) and circulatory (N) matrices: empty, or n x n.
  const std::pair<const DenseMatrix*, const char*> optional[] = {{&D, "D"}, {&N, "N"}};
  for (const auto& [A, name] : optional) {
    if (A->numRows() == 0 && A->numCols() == 0) continue;
    CMS_INPUT_CHECK(A->numRows() != n || A->numCols() != n,
                    "GyroscopicSystem: " << name << " is " << A->numRows() << "x" << A->numCols()
                                         << " but M is " << n << "x" << n
                                         << " (leave it 0x0 for none)");
    requireFinite(*A, std::string("GyroscopicSystem: ") + name);
  }
  if (KMagnitude.numRows() != 0 || KMagnitude.numCols() != 0) {
    CMS_INPUT_CHECK(KMagnitude.numRows() != n || KMagnitude.numCols() != n,
                    "GyroscopicSystem: KMagnitude is " << KMagnitude.numRows() << "x" << KMagnitude.numCols()
                                                       << " but M is " << n << "x" << n << " (leave it 0x0 for none)");
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        CMS_INPUT_CHECK(!(KMagnitude(i, j) >= std::abs(K(i, j)) * (1.0 - 1e-12)) || !std::isfinite(KMagnitude(i, j)),
                        "GyroscopicSystem: KMagnitude(" << i << ", " << j << ") = " << KMagnitude(i, j)
                                                        << " is not a finite magnitude of K's parts (|K(i, j)| = "
                                                        << std::abs(K(i, j)) << ")");
  }
  for (std::size_t i = 0; i < unrestrained.size(); ++i)
    CMS_INPUT_CHECK(unrestrained[i] < 0 || unrestrained[i] >= n || (i > 0 && unrestrained[i] <= unrestrained[i - 1]),
                    "GyroscopicSystem: unrestrained coordinate " << unrestrained[i] << " (entry " << i
                        << ") is out of [0, " << n << ") or not ascending");
  // Defects are measured against the size of each term of the quadratic at the
  // frequency scale s (lambda^2 M, lambda G, K at |lambda| = s), so a G or K
  // that is zero up to rounding (a Ritz projection onto rigid-body vectors) is
  // not mistaken for a structural error.
  const double nM = frobeniusNorm(M), nG = frobeniusNorm(G), nK = frobeniusNorm(K);
  const double s = frequencyScale(nM, nG, nK);
  const double sys = s * s * nM + s * nG + nK;
  const double dM = symmetryDefect(M) * nM * s * s / sys;
  const double dG = skewDefect(G) * nG * s / sys;
  const double dK = symmetryDefect(K) * nK / sys;
  CMS_INPUT_CHECK(dM > relTol, "GyroscopicSystem: M is not symmetric: max|M - M^T| s^2 / "
                               "(s^2||M|| + s||G|| + ||K||) = "
                                   << dM << " > " << relTol);
  CMS_INPUT_CHECK(dG > relTol, "GyroscopicSystem: G is not skew-symmetric: max|G + G^T| s / "
                               "(s^2||M|| + s||G|| + ||K||) = "
                                   << dG << " > " << relTol
                                   << " (damping belongs in a separate matrix, not in G)");
  CMS_INPUT_CHECK(dK > relTol, "GyroscopicSystem: K is not symmetric: max|K - K^T| / "
                               "(s^2||M|| + s||G|| + ||K||) = "
                                   << dK << " > " << relTol);
  if (D.numRows() > 0) {
    const double nD = frobeniusNorm(D);
    const double dD = symmetryDefect(D) * nD * s / (sys + s * nD);
    CMS_INPUT_CHECK(dD > relTol, "GyroscopicSystem: the damping matrix D is not symmetric: "
                                 "max|D - D^T| s / (s^2||M|| + s||G|| + s||D|| + ||K||) = "
                                     << dD << " > " << relTol
                                     << " (a skew part is gyroscopic: it belongs in G)");
  }
  if (N.numRows() > 0) {
    const double nN = frobeniusNorm(N);
    const double dN = skewDefect(N) * nN / (sys + nN);
    CMS_INPUT_CHECK(dN > relTol, "GyroscopicSystem: the circulatory matrix N is not skew-symmetric: "
                                 "max|N + N^T| / (s^2||M|| + s||G|| + ||K|| + ||N||) = "
                                     << dN << " > " << relTol
                                     << " (a symmetric part is stiffness: it belongs in K)");
  }
}

GyroscopicSystem GyroscopicSystem::symmetrised() const {
  GyroscopicSystem s{M, G, K, D, N, unrestrained, KMagnitude};
  const int n = size();
  const bool hasD = D.numRows() == n && n > 0, hasN = N.numRows() == n && n > 0;
  const bool hasR = KMagnitude.numRows() == n && n > 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < j; ++i) {
      s.M(i, j) = s.M(j, i) = 0.5 * (M(i, j) + M(j, i));
      if (hasR) s.KMagnitude(i, j) = s.KMagnitude(j, i) = std::max(KMagnitude(i, j), KMagnitude(j, i));
      s.K(i, j) = s.K(j, i) = 0.5 * (K(i, j) + K(j, i));
      s.G(i, j) = 0.5 * (G(i, j) - G(j, i));
      s.G(j, i) = -s.G(i, j);
      if (hasD) s.D(i, j) = s.D(j, i) = 0.5 * (D(i, j) + D(j, i));
      if (hasN) {
        s.N(i, j) = 0.5 * (N(i, j) - N(j, i));
        s.N(j, i) = -s.N(i, j);
      }
    }
  for (int i = 0; i < n; ++i) {
    s.G(i, i) = 0.0;
    if (hasN) s.N(i, i) = 0.0;
  }
  return s;
}

}  // namespace cms::eigen
