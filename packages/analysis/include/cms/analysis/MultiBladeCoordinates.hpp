// Multi-blade (Coleman) coordinates for a rotor of N >= 3 identical blades
// (doc/theory.md §16.2). Blade k (k = 0..N-1) sits at azimuth
// psi_k = psi + 2 pi k / N, psi = Omega t + psi_0 the azimuth of blade 0.
// Each blade has the same nb coordinates (a rigid blade's lag angle; an
// elastic blade's Ritz coordinates, which transform identically because the
// copies share one basis). The blades' coordinates beta_k (nb each) are
//
//   beta_k = b_0 + sum_{n=1}^{L} (b_nc cos n psi_k + b_ns sin n psi_k) + b_d (-1)^k,
//
// L = (N - 1) / 2 (integer division), b_d only for even N: N nb multi-blade
// coordinates b = [b_0, b_1c, b_1s, ..., b_Lc, b_Ls, (b_d)] (each nb long),
// in that order: collective, cyclic, differential (reactionless). Inverse:
// b_0 = (1/N) sum beta_k, b_nc = (2/N) sum beta_k cos n psi_k,
// b_ns = (2/N) sum beta_k sin n psi_k, b_d = (1/N) sum beta_k (-1)^k.
//
// With q = [fixed coordinates (f); beta_0; ...; beta_{N-1}] = B(psi) z,
// B = blkdiag(I_f, T(psi) (x) I_nb), the time derivatives carry the Omega
// terms: q' = B z' + Omega B_psi z, q'' = B z'' + 2 Omega B_psi z' + Omega^2 B_psipsi z
// (constant Omega). Premultiplying M q'' + D q' + K q = 0 by B^T gives
//
//   M~ = B^T M B,  D~ = B^T (D B + 2 Omega M B_psi),  K~ = B^T (K B + Omega D B_psi + Omega^2 M B_psipsi),
//
// constant in time for an isotropic rotor of N >= 3 identical blades
// (symmetric M stays symmetric; the Omega terms give the skew Coriolis and
// circulatory parts). For N = 2 (or a dissimilar blade, an anisotropic
// support) the result still depends on psi: use FloquetAnalysis.
#pragma once

#include <string>
#include <vector>

#include "cms/analysis/Floquet.hpp"
#include "cms/core/DenseMatrix.hpp"

namespace cms::analysis {

class MultiBladeTransform {
public:
  /// N >= 3 blades (InputError otherwise: two blades have no cyclic pair, a
  /// two-bladed rotor stays periodic), nb >= 1 coordinates per blade.
  explicit MultiBladeTransform(int blades, int dofsPerBlade = 1);

  int blades() const { return N_; }
  int dofsPerBlade() const { return nb_; }
  int size() const { return N_ * nb_; }
  /// "0", "1c", "1s", ..., "Lc", "Ls", and "d" for even N: the multi-blade
  /// coordinates in order (each stands for nb coordinates).
  std::vector<std::string> names() const;

  /// d^r T / dpsi^r (r = 0, 1, 2): beta = T(psi) b, (N nb) x (N nb); row
  /// k nb + j is blade k's coordinate j, column m nb + j multi-blade coordinate m's.
  DenseMatrix matrix(double psi, int derivative = 0) const;
  /// T(psi)^-1 = W T(psi)^T, W = diag(1/N, 2/N, ..., 2/N, (1/N)).
  DenseMatrix inverse(double psi) const;

  /// The system M q'' + D q' + K q = 0 on q = [f fixed coordinates; the
  /// blades'] at azimuth psi, in z = [fixed; b] premultiplied by B^T (above).
  /// Constant in psi exactly when the rotor is isotropic.
  SecondOrderMatrices toMultiBlade(const SecondOrderMatrices& individual, double psi, double Omega,
                                   int fixedDofs) const;

  /// blkdiag(I_f, T(psi)^-1): the fixed-frame quantities [fixed; b] of q, the
  /// observation under which Floquet's harmonic rule gives fixed-frame
  /// frequencies (PeriodicSystem::observation).
  DenseMatrix observation(double psi, int fixedDofs) const;

private:
  int N_, nb_;
  /// value of multi-blade function m at blade k, psi-derivative r
  double basis(int m, int k, double psi, int r) const;
};

}  // namespace cms::analysis
