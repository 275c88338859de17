// Gyroscopic modes from the converged vectors of the spectral transform
// (QuadraticRitz.hpp).
#include "QuadraticRitz.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <AnasaziTpetraAdapter.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/MatrixSum.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/core/SparseInertia.hpp"  // realEmbedding, stateMap
#include "cms/core/SparseProduct.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"

namespace cms::eigen::detail {

using cplx = std::complex<double>;
using MVT = Anasazi::MultiVecTraits<double, MultiVector>;

namespace {

const double kTwoPi = 2.0 * M_PI;

/// Orthonormal basis of span(B) by the eigen-decomposition of its Gram matrix,
/// dropping directions below `relTol` (SVQB with truncation): the converged
/// vectors of a double eigenvalue may be (nearly) dependent once halved.
Teuchos::RCP<MultiVector> orthonormalBasis(const MultiVector& B, double relTol) {
  const int k = static_cast<int>(B.getNumVectors());
  DenseMatrix Gm(k, k);
  MVT::MvTransMv(1.0, B, B, Gm);
  std::vector<double> w(k), work(std::max(1, 4 * k));
  int info = 0;
  Teuchos::LAPACK<int, double>().SYEV('V', 'U', k, Gm.values(), k, w.data(), work.data(),
                                      static_cast<int>(work.size()), &info);
  TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError, "orthonormalBasis: dsyev info " << info);
  const double wmax = k > 0 ? w[k - 1] : 0.0;
  std::vector<int> keep;
  for (int j = k - 1; j >= 0; --j)
    if (w[j] > relTol * wmax) keep.push_back(j);
  DenseMatrix T(k, static_cast<int>(keep.size()));
  for (std::size_t c = 0; c < keep.size(); ++c)
    for (int i = 0; i < k; ++i) T(i, c) = Gm(i, keep[c]) / std::sqrt(w[keep[c]]);
  auto Q = Teuchos::rcp(new MultiVector(B.getMap(), std::max<size_t>(keep.size(), 1)));
  if (!keep.empty()) MVT::MvTimesMatAddMv(1.0, B, T, 0.0, *Q);
  return Q;
}

DenseMatrix projectOnto(const CrsMatrix& A, const MultiVector& Q) {
  MultiVector AQ(Q.getMap(), Q.getNumVectors());
  multiply(A, Q, AQ);
  DenseMatrix R(static_cast<int>(Q.getNumVectors()), static_cast<int>(Q.getNumVectors()));
  MVT::MvTransMv(1.0, Q, AQ, R);
  return R;
}

/// An orthonormal basis of both halves of the converged state vectors: for
/// an exact eigenvector v = lambda q adds nothing, but for a partly
/// converged one (a double eigenvalue of R near the edge of the wanted set)
/// it enriches the subspace.
Teuchos::RCP<MultiVector> ritzSubspace(const MultiVector& ritz, const Teuchos::RCP<const Map>& rowMap) {
  const size_t nr = ritz.getNumVectors(), nloc0 = rowMap->getNodeNumElements();
  MultiVector halves(rowMap, 2 * nr);
  {
    const auto src = ritz.getLocalViewHost(Tpetra::Access::ReadOnly);
    auto dst = halves.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (size_t j = 0; j < nr; ++j)
      for (size_t i = 0; i < nloc0; ++i) {
        dst(i, j) = src(nloc0 + i, j);  // q
        dst(i, nr + j) = src(i, j);     // v
      }
  }
  // Each column at unit norm first: v ~ omega q, so in seconds a mode at
  // 1e4 rad/s has its q-half 1e-4 of its v-half, and the cut below, relative
  // to the largest column, would judge the q-halves' directions against the
  // v-halves' (found by a review). Scaling columns leaves the span alone.
  {
    std::vector<double> norms(2 * nr);
    halves.norm2(Teuchos::ArrayView<double>(norms));
    for (size_t j = 0; j < 2 * nr; ++j)
      if (norms[j] > 0.0) halves.getVectorNonConst(j)->scale(1.0 / norms[j]);
  }
  // The threshold is on the Gram matrix's eigenvalues, the squares of the
  // singular values: 1e-20 keeps directions down to 1e-10 of the largest
  // (1e-12 kept only those above 1e-6, and dropped the correction that
  // separates a near-double pair, leaving its modes at residuals ~1e-7). The
  // small directions come out of SVQB with errors ~eps/sigma, so a second
  // pass orthonormalises the result again (SVQB twice, as CGS twice).
  auto basis = orthonormalBasis(*orthonormalBasis(halves, 1e-20), 1e-20);
  // More columns than the model has coordinates (a small reduced model,
  // 2 nr > n): the cut keeps a rounding direction (a Gram eigenvalue of
  // ~1e-16, above 1e-20) that is no direction at all, and the projected M
  // was singular: 23 columns for 22 coordinates, refused as "M is not
  // positive definite" (a review). The subspace is then the whole space:
  // its exact basis, the identity.
  const auto n = static_cast<size_t>(rowMap->getGlobalNumElements());
  if (basis->getNumVectors() >= n) {
    auto identity = Teuchos::rcp(new MultiVector(rowMap, n));
    size_t offset = 0;
    Teuchos::scan(*rowMap->getComm(), Teuchos::REDUCE_SUM, nloc0, Teuchos::outArg(offset));
    offset -= nloc0;  // the rows on the ranks before this one
    auto v = identity->getLocalViewHost(Tpetra::Access::ReadWrite);  // keeps the zeros
    for (size_t i = 0; i < nloc0; ++i) v(i, offset + i) = 1.0;
    return identity;
  }
  return basis;
}

/// Each Ritz mode's full vector q = Q q_r: this rank's rows into m.q (not
/// yet normalised; measureRitzModes does that). A bound the projected
/// solve's own refinement left (refinedError) is of the projected pencil,
/// no bound on the full model's eigenvalue: cleared, or measureRitzModes
/// took it for the full model's growth uncertainty (a review).
void expandModes(const MultiVector& Q, std::vector<GyroscopicMode>& rm) {
  for (auto& m : rm) m.refinedError = 0.0;
  const int k = static_cast<int>(rm.size());
  const int kk = std::max(k, 1);
  DenseMatrix Yr(static_cast<int>(Q.getNumVectors()), kk), Yi(static_cast<int>(Q.getNumVectors()), kk);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < Yr.numRows(); ++i) {
      Yr(i, j) = rm[j].q[i].real();
      Yi(i, j) = rm[j].q[i].imag();
    }
  MultiVector Qr(Q.getMap(), kk), Qi(Q.getMap(), kk);
  MVT::MvTimesMatAddMv(1.0, Q, Yr, 0.0, Qr);
  MVT::MvTimesMatAddMv(1.0, Q, Yi, 0.0, Qi);
  const size_t nloc = Q.getMap()->getNodeNumElements();
  auto qr = Qr.getLocalViewHost(Tpetra::Access::ReadOnly), qi = Qi.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (int j = 0; j < k; ++j) {
    rm[j].q.resize(nloc);
    for (size_t i = 0; i < nloc; ++i) rm[j].q[i] = cplx(qr(i, j), qi(i, j));
  }
}

/// Full modes (this rank's rows in m.q), M-normalised with the phase of
/// their largest entry over all ranks, and their residuals, energies,
/// scales, eigenvalue errors and growth uncertainties from M, G, K (and D,
/// N): run on the expanded Ritz modes, and again on refined ones.
void measureRitzModes(const SparseGyroscopicSystem& sys, std::vector<GyroscopicMode>& rm, double instabilityTol,
                      bool conservative) {
  const auto rowMap = sys.M->getRowMap();
  const auto comm = rowMap->getComm();
  const int k = static_cast<int>(rm.size());
  const int kk = std::max(k, 1);
  MultiVector Qr(rowMap, kk), Qi(rowMap, kk);
  {
    auto r = Qr.getLocalViewHost(Tpetra::Access::OverwriteAll), i = Qi.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (int j = 0; j < k; ++j)
      for (size_t l = 0; l < rowMap->getNodeNumElements(); ++l) r(l, j) = rm[j].q[l].real(), i(l, j) = rm[j].q[l].imag();
  }
  MultiVector MQr(rowMap, kk), MQi(rowMap, kk), GQr(rowMap, kk), GQi(rowMap, kk), KQr(rowMap, kk),
      KQi(rowMap, kk);
  multiply(*sys.M, Qr, MQr), multiply(*sys.M, Qi, MQi);
  multiply(*sys.G, Qr, GQr), multiply(*sys.G, Qi, GQi);
  if (!sys.D.is_null()) {  // G q stands for (G + D) q in the residual below
    multiply(*sys.D, Qr, GQr, 1.0, 1.0);
    multiply(*sys.D, Qi, GQi, 1.0, 1.0);
  }
  multiply(*sys.K, Qr, KQr), multiply(*sys.K, Qi, KQi);
  if (!sys.N.is_null()) {  // K q stands for (K + N) q
    multiply(*sys.N, Qr, KQr, 1.0, 1.0);
    multiply(*sys.N, Qi, KQi, 1.0, 1.0);
  }
  // |K| |q| and |G| |q| for the modes' own scales (GyroscopicMode::scale).
  MultiVector Qa(rowMap, kk), KQa(rowMap, kk), GQa(rowMap, kk), MQa(rowMap, kk);
  {
    auto a = Qa.getLocalViewHost(Tpetra::Access::OverwriteAll);
    auto r = Qr.getLocalViewHost(Tpetra::Access::ReadOnly), i = Qi.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (size_t l = 0; l < rowMap->getNodeNumElements(); ++l)
      for (int j = 0; j < kk; ++j) a(l, j) = std::hypot(r(l, j), i(l, j));
  }
  // (cms::multiplyAbsolute: no |A| copies of the matrices at every solve.)
  {
    MultiVector part(rowMap, kk);
    multiplyAbsolute(*sys.K, Qa, KQa);
    if (!sys.N.is_null()) multiplyAbsolute(*sys.N, Qa, part), KQa.update(1.0, part, 1.0);
    multiplyAbsolute(*sys.G, Qa, GQa);
    if (!sys.D.is_null()) multiplyAbsolute(*sys.D, Qa, part), GQa.update(1.0, part, 1.0);
  }
  multiplyAbsolute(*sys.M, Qa, MQa);  // for the componentwise backward error (growthTolerance)
  const double nM = sys.M->getFrobeniusNorm(),
               nK = sys.K->getFrobeniusNorm() + (sys.N.is_null() ? 0.0 : sys.N->getFrobeniusNorm()),
               nG = sys.G->getFrobeniusNorm() + (sys.D.is_null() ? 0.0 : sys.D->getFrobeniusNorm());
  const size_t nloc = rowMap->getNodeNumElements();
  auto qr = Qr.getLocalViewHost(Tpetra::Access::ReadOnly), qi = Qi.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto mr = MQr.getLocalViewHost(Tpetra::Access::ReadOnly), mi = MQi.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto gr = GQr.getLocalViewHost(Tpetra::Access::ReadOnly), gi = GQi.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto kr = KQr.getLocalViewHost(Tpetra::Access::ReadOnly), ki = KQi.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto ka = KQa.getLocalViewHost(Tpetra::Access::ReadOnly), ga = GQa.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto ma = MQa.getLocalViewHost(Tpetra::Access::ReadOnly);
  const int nprocs = comm->getSize();
  for (int j = 0; j < k; ++j) {
    GyroscopicMode& m = rm[j];
    const cplx l = m.lambda, l2 = l * l;
    // qMq, qKq, qq, rr, |q||K||q|, |q||G||q|, q^H G q (re, im), || |K||q| + |l||G||q| + |l|^2|M||q| ||^2
    double local[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    double big = -1.0;
    cplx bigVal = 0.0;
    for (size_t i = 0; i < nloc; ++i) {
      const cplx q(qr(i, j), qi(i, j)), Mq(mr(i, j), mi(i, j)), Gq(gr(i, j), gi(i, j)), Kq(kr(i, j), ki(i, j));
      local[0] += std::real(std::conj(q) * Mq);
      local[1] += std::real(std::conj(q) * Kq);
      local[2] += std::norm(q);
      local[3] += std::norm(l2 * Mq + l * Gq + Kq);
      local[4] += std::abs(q) * ka(i, j), local[5] += std::abs(q) * ga(i, j);
      const cplx qGq = std::conj(q) * Gq;
      local[6] += qGq.real(), local[7] += qGq.imag();
      local[8] += std::pow(ka(i, j) + std::abs(l) * ga(i, j) + std::norm(l) * ma(i, j), 2);
      if (std::abs(q) > big) big = std::abs(q), bigVal = q;
    }
    double global[9];
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 9, local, global);
    // The largest entry over all ranks fixes the phase (lowest rank wins ties).
    std::vector<double> bigs(3 * nprocs), mine = {big, bigVal.real(), bigVal.imag()};
    Teuchos::gatherAll(*comm, 3, mine.data(), 3 * nprocs, bigs.data());
    int owner = 0;
    for (int p = 1; p < nprocs; ++p)
      if (bigs[3 * p] > bigs[3 * owner]) owner = p;
    const cplx top(bigs[3 * owner + 1], bigs[3 * owner + 2]);
    const cplx phase = std::abs(top) > 0 ? std::conj(top) / std::abs(top) : 1.0;
    const double s = global[0] > 0 ? 1.0 / std::sqrt(global[0]) : 1.0;
    m.q.resize(nloc);
    for (size_t i = 0; i < nloc; ++i) m.q[i] = cplx(qr(i, j), qi(i, j)) * phase * s;
    const double denom = (nK + std::abs(l) * nG + std::norm(l) * nM) * std::sqrt(global[2]);
    m.residual = denom > 0 ? std::sqrt(global[3]) / denom : std::sqrt(global[3]);
    m.kineticEnergy = 0.5 * std::norm(l);
    m.strainEnergy = 0.5 * global[1] * s * s;
    m.growthRate = l.real();
    m.omega = std::abs(l.imag());
    m.hz = m.omega / kTwoPi;
    setDamping(m);
    m.scale = global[0] > 0 ? std::sqrt(global[4] / global[0]) + global[5] / global[0] : 0.0;
    // The eigenvalue's first-order error and the growth rate's uncertainty
    // from the full model's residual (GyroscopicMode::eigenvalueError,
    // growthTolerance; theory §13.3), replacing the projected solve's,
    // which measured the projection only (a Ritz value's error is here).
    const double derivative = std::abs(2.0 * l * global[0] + cplx(global[6], global[7]));
    m.eigenvalueError = derivative > 0.0 ? std::sqrt(global[3]) * std::sqrt(global[2]) / derivative
                                         : std::numeric_limits<double>::infinity();
    const double etaQ = global[8] > 0.0 ? std::sqrt(global[3] / global[8]) : 1.0;
    std::vector<cplx> others;
    for (int o = 0; o < k; ++o)
      if (o != j) others.push_back(rm[o].lambda);
    const double bound = m.refinedError > 0.0 ? m.refinedError
                                              : 10.0 * std::min(m.eigenvalueError, std::max(m.scale, std::abs(l)));
    m.growthTolerance = growthUncertainty(l, bound, etaQ, instabilityTol, others, conservative);
  }
}

/// Q(sigma) = A + i B in the real form [[A, -B], [B, A]] on the 2n map
/// (cms::realEmbedding), `C` = G + D and `Kt` = K + N. Its transpose
/// [[A^T, B^T], [-B^T, A^T]] is the real form of Q(sigma)^H = A^T - i B^T:
/// the left vector's solve is the transposed solve with the same factors.
Teuchos::RCP<CrsMatrix> complexPencil(const CrsMatrix& M, const CrsMatrix& C, const CrsMatrix& Kt, cplx sigma,
                                      const Teuchos::RCP<const Map>& map2) {
  const cplx s2 = sigma * sigma;
  const auto A = matrixSum(1.0, *matrixSum(s2.real(), M, sigma.real(), C), 1.0, Kt);
  const auto B = matrixSum(s2.imag(), M, sigma.imag(), C);
  return realEmbedding(*A, *B, map2);
}

/// The Ritz modes among `which` whose growth rate is undecided (positive,
/// above instabilityTol |lambda|, within its uncertainty, whose first-order
/// bound ten times ||r|| ||q|| / |q^H Q' q| the stiff rows' residual
/// inflates), refined by two-sided inverse iteration on the full model as
/// the dense path refines its own (DenseGyroscopicSolver.cpp,
/// refineUndecided; theory §13.3; which: undecidedGrowth, `zeroBelow` the
/// rigid test's |lambda|): Q(sigma) at the Ritz value sigma factored once
/// in its real 2n form by MUMPS (LU across the ranks; the left vector by
/// its transposed solve, which KLU2 here gets wrong), three steps, lambda the root of y^H Q(mu) x = 0 nearest, and its
/// bound twoSidedBound in refinedError. Without it a support of E = 2e16, or
/// 250 shaft elements, read a 0.241 1/s flutter "stable" (depending on the
/// mode count; a review). Also refined, whatever its growth: a mode whose
/// first-order error exceeds frequencyTol |lambda| (uncertainFrequency; the
/// caller passes infinity for a conservative system), a member of a double
/// pair included. Not refined for its growth: a value within 1e-3 |lambda| of
/// another (a split cluster's member). Not refined: one solved apart, or one whose
/// factorisation fails (it keeps its first-order uncertainty), and one whose
/// refined bound is no smaller than the uncertainty it had (the refinement
/// did not help: the value and shape are kept). `rigidTol` and `scale` give
/// each mode's zero, rigidTol min(its scale, scale), as classifyModes
/// judges it: the full model's scale alone left a mode above the projected
/// scale's zero unrefined and then Neutral without a refinement (a review).
/// Collective. Returns whether any mode changed.
bool refineRitzModes(const SparseGyroscopicSystem& sys, std::vector<GyroscopicMode>& rm, const std::vector<int>& which,
                     double instabilityTol, double rigidTol, double scale, double frequencyTol) {
  const auto rowMap = sys.M->getRowMap();
  const size_t nloc = rowMap->getNodeNumElements();
  const double n = static_cast<double>(rowMap->getGlobalNumElements());
  std::vector<int> chosen;
  for (int j : which) {
    const double s = rm[j].scale > 0.0 ? std::min(rm[j].scale, scale) : scale;
    if (undecidedGrowth(rm[j], rm, instabilityTol, rigidTol * s) ||
        uncertainFrequency(rm[j], frequencyTol, rigidTol * s))
      chosen.push_back(j);
  }
  if (chosen.empty()) return false;
  // C = G + D, Kt = K + N, and C's transpose D - G (for Q'(sigma)^H).
  using Matrix = Teuchos::RCP<const CrsMatrix>;
  const Matrix C = sys.D.is_null() ? sys.G : (Matrix)matrixSum(1.0, *sys.G, 1.0, *sys.D);
  const Matrix CT = sys.D.is_null() ? matrixSum(-1.0, *sys.G, 0.0, *sys.G) : matrixSum(-1.0, *sys.G, 1.0, *sys.D);
  const Matrix Kt = sys.N.is_null() ? sys.K : (Matrix)matrixSum(1.0, *sys.K, 1.0, *sys.N);
  const auto map2 = stateMap(*rowMap);
  bool any = false;
  for (int j : chosen) {
    GyroscopicMode& m = rm[j];
    cplx sigma = m.lambda;
    // One factorisation; an exactly singular one (sigma an eigenvalue to
    // the last bit) is moved by 1e-10 |sigma|, as the dense path does.
    std::unique_ptr<SparseDirectSolver> F;
    for (int attempt = 0; attempt < 2; ++attempt) {
      if (attempt == 1) sigma += 1e-10 * std::abs(m.lambda);
      F = std::make_unique<SparseDirectSolver>(complexPencil(*sys.M, *C, *Kt, sigma, map2), "MUMPS");
      F->acceptNearlySingular();
      if (F->factor() == SparseDirectSolver::Outcome::Factored) break;
      F.reset();
    }
    if (!F) continue;
    // x and y as [Re; Im] on the 2n map; both start from the Ritz vector.
    MultiVector x(map2, 1), y(map2, 1), rhs(map2, 1);
    {
      auto v = x.getLocalViewHost(Tpetra::Access::OverwriteAll);
      for (size_t i = 0; i < nloc; ++i) v(i, 0) = m.q[i].real(), v(nloc + i, 0) = m.q[i].imag();
    }
    // Q'(sigma) v = (2 sigma M + C) v in real form, into `out`.
    MultiVector Mr(rowMap, 1), Mi(rowMap, 1), Cr(rowMap, 1), Ci(rowMap, 1);
    const auto derivative = [&](const CrsMatrix& Cm, cplx s, const MultiVector& v, MultiVector& out) {
      const auto vr = v.offsetView(rowMap, 0), vi = v.offsetView(rowMap, nloc);
      multiply(*sys.M, *vr, Mr), multiply(*sys.M, *vi, Mi);
      multiply(Cm, *vr, Cr), multiply(Cm, *vi, Ci);
      auto outR = out.offsetViewNonConst(rowMap, 0), outI = out.offsetViewNonConst(rowMap, nloc);
      outR->update(2.0 * s.real(), Mr, -2.0 * s.imag(), Mi, 0.0), outR->update(1.0, Cr, 1.0);
      outI->update(2.0 * s.real(), Mi, 2.0 * s.imag(), Mr, 0.0), outI->update(1.0, Ci, 1.0);
    };
    y.assign(x);
    // y^H A x, sum_i m_i |y_i| (|A| |x|)_i (m_i: row i's entries) and
    // |y|^T |A x| for A = Kt, C, M, as twoSidedBound takes them.
    MultiVector ar(rowMap, 1), ai(rowMap, 1), xa(rowMap, 1), ya(rowMap, 1), Ax(rowMap, 1);
    const auto forms = [&](const CrsMatrix& A, cplx& value, double& absolute, double& product) {
      const auto xr = x.offsetView(rowMap, 0), xi = x.offsetView(rowMap, nloc);
      const auto yr = y.offsetView(rowMap, 0), yi = y.offsetView(rowMap, nloc);
      multiply(A, *xr, ar), multiply(A, *xi, ai);
      multiplyAbsolute(A, xa, Ax);
      double local[6] = {0, 0, 0, 0, 0, 0}, global[6];
      {
        auto r = ar.getLocalViewHost(Tpetra::Access::ReadOnly), i = ai.getLocalViewHost(Tpetra::Access::ReadOnly);
        auto yv = y.getLocalViewHost(Tpetra::Access::ReadOnly), w = ya.getLocalViewHost(Tpetra::Access::ReadOnly);
        auto p = Ax.getLocalViewHost(Tpetra::Access::ReadOnly);
        for (size_t e = 0; e < nloc; ++e) {
          const double y0 = yv(e, 0), y1 = yv(nloc + e, 0);
          local[0] += y0 * r(e, 0), local[1] += y1 * i(e, 0), local[2] += y0 * i(e, 0), local[3] += y1 * r(e, 0);
          const double entries = static_cast<double>(A.getNumEntriesInLocalRow(static_cast<LocalOrdinal>(e)));
          local[4] += entries * w(e, 0) * p(e, 0), local[5] += w(e, 0) * std::hypot(r(e, 0), i(e, 0));
        }
      }
      Teuchos::reduceAll(*rowMap->getComm(), Teuchos::REDUCE_SUM, 6, local, global);
      value = cplx(global[0] + global[1], global[2] - global[3]);
      absolute = global[4], product = global[5];
    };
    TwoSidedEstimate e{m.lambda};
    cplx a = 0.0, b = 0.0, c = 0.0;
    FunctionalRounding rounding;
    rounding.n = n;
    // The step whose bound is least is kept: within a double eigenvalue x
    // and y turn in the pair's plane from step to step, their pairing
    // y^H Q' x with them, and the value moves by more than its floor after a
    // step that had converged to it (the lowest pair of an isotropic shaft on
    // a stiff damped support: 1.96e-5 rad/s at the first step, 0.024 after
    // the third with OPENBLAS_CORETYPE=Nehalem; theory §5, "Stiff rows").
    // Eight steps (the dense path too): a pair whose Ritz value was
    // 1.9e-3 off reached its floor (2e-5 rad/s) at the fifth, after a step
    // whose floor was 700 times that (2 ranks, Nehalem). A step costs two solves with the
    // factors, a small part of the factorisation.
    // sum_i |y_i| |(Q(mu) x)_i|: the residual where the left vector weighs it.
    MultiVector Rr(rowMap, 1), Ri(rowMap, 1);
    const auto weightedResidual = [&](cplx mu) {
      const auto xr = x.offsetView(rowMap, 0), xi = x.offsetView(rowMap, nloc);
      const cplx mu2 = mu * mu;
      Rr.putScalar(0.0), Ri.putScalar(0.0);
      for (auto [A, w] : {std::pair<const CrsMatrix*, cplx>{Kt.get(), 1.0}, {C.get(), mu}, {sys.M.get(), mu2}}) {
        multiply(*A, *xr, ar), multiply(*A, *xi, ai);
        Rr.update(w.real(), ar, -w.imag(), ai, 1.0);
        Ri.update(w.imag(), ar, w.real(), ai, 1.0);
      }
      double local = 0.0, global = 0.0;
      auto r = Rr.getLocalViewHost(Tpetra::Access::ReadOnly), i = Ri.getLocalViewHost(Tpetra::Access::ReadOnly);
      auto w = ya.getLocalViewHost(Tpetra::Access::ReadOnly);
      for (size_t e = 0; e < nloc; ++e) local += w(e, 0) * std::hypot(r(e, 0), i(e, 0));
      Teuchos::reduceAll(*rowMap->getComm(), Teuchos::REDUCE_SUM, 1, &local, &global);
      return global;
    };
    RefinementGate gate(m.lambda);
    MultiVector bestX(map2, 1);
    for (int step = 0; step < 8; ++step) {
      derivative(*C, sigma, x, rhs);
      F->solve(rhs, x);
      derivative(*CT, std::conj(sigma), y, rhs);
      F->solveTransposed(rhs, y);
      Teuchos::Array<double> nx(1), ny(1);
      x.norm2(nx()), y.norm2(ny());
      if (!(nx[0] > 0.0) || !(ny[0] > 0.0) || !std::isfinite(nx[0]) || !std::isfinite(ny[0])) break;
      x.scale(1.0 / nx[0]), y.scale(1.0 / ny[0]);
      {
        auto v = xa.getLocalViewHost(Tpetra::Access::OverwriteAll), w = ya.getLocalViewHost(Tpetra::Access::OverwriteAll);
        auto xv = x.getLocalViewHost(Tpetra::Access::ReadOnly), yv = y.getLocalViewHost(Tpetra::Access::ReadOnly);
        for (size_t i = 0; i < nloc; ++i)
          v(i, 0) = std::hypot(xv(i, 0), xv(nloc + i, 0)), w(i, 0) = std::hypot(yv(i, 0), yv(nloc + i, 0));
      }
      forms(*Kt, c, rounding.absolute[0], rounding.product[0]);
      forms(*C, b, rounding.absolute[1], rounding.product[1]);
      forms(*sys.M, a, rounding.absolute[2], rounding.product[2]);
      if (!e.step(a, b, c)) break;
      // Which step stands, and with what bound: RefinementGate (the stall
      // of a close pair refined from a shift between its members).
      const double bound = twoSidedBound(e.lambda, e.change, e.changeBefore, a, b, rounding);
      const double measure = weightedResidual(e.lambda) / std::abs(2.0 * e.lambda * a + b);
      if (gate.offer(step, e, bound, measure)) bestX.assign(x);
    }
    // Kept only where it decides more than the Ritz value's own uncertainty
    // did (the refinement helped; the same on every rank: both come from
    // global sums).
    if (!(gate.best < m.growthTolerance)) continue;
    {
      auto xv = bestX.getLocalViewHost(Tpetra::Access::ReadOnly);
      for (size_t i = 0; i < nloc; ++i) m.q[i] = cplx(xv(i, 0), xv(nloc + i, 0));
    }
    m.lambda = gate.bestLambda, m.refinedError = gate.best;
    any = true;
  }
  return any;
}

}  // namespace

std::vector<GyroscopicMode> quadraticRitzModes(const SparseGyroscopicSystem& sys, const MultiVector& vectors,
                                               double shift, double rigidTol, double instabTol,
                                               const RitzRefinement& refinement) {
  const auto Q = ritzSubspace(vectors, sys.M->getRowMap());
  GyroscopicSystem reduced{projectOnto(*sys.M, *Q), projectOnto(*sys.G, *Q), projectOnto(*sys.K, *Q)};
  if (!sys.D.is_null()) reduced.D = projectOnto(*sys.D, *Q);
  if (!sys.N.is_null()) reduced.N = projectOnto(*sys.N, *Q);
  Teuchos::ParameterList dense;
  dense.set("Rigid Body Tolerance", rigidTol);
  // The projection's K holds its own rounding, which the dense solver's
  // proof that sym(K + N) > 0 (no zero eigenvalue, theory §4.3) takes as
  // exact: a free body's rigid direction, K's rounding there, could be
  // "proven" stiff. Proven with that rounding (gamma |Q|^T |K + N| |Q|) it
  // failed where it was wanted, the bound coupling stiff and soft Ritz
  // vectors (the shaft on a support of E = 1e18 clamped at both ends; not
  // adopted). Not proven here, then.
  dense.set("Stiffness Proof", false);
  // Its decays are not refined here: the Ritz values are refined on the full
  // model below. Refined here too, the stiff-support shaft's pair at 0.5
  // rad/s (OPENBLAS_CORETYPE=Nehalem) came back from the full model's
  // refinement as one member twice
  // (`SceneRegression.TwoSolvesOfAStiffSpinningRotorAgreeWithinTheirReportedErrors`).
  dense.set("Refine Decays", false);
  // Nor its frequencies, for the same reason: the Ritz values whose
  // first-order error exceeds the Frequency Tolerance are refined on the
  // full model (refineRitzModes).
  dense.set("Frequency Tolerance", std::numeric_limits<double>::infinity());
  dense.set("Instability Tolerance", instabTol);
  // The projected pencil's energy bound is not the full model's: its
  // verdicts are made again below, on the full model's residuals.
  dense.set("Energy Bound", false);
  // The projections of the (validated) symmetric M, K and skew G are so in
  // exact arithmetic; their rounding, eps ||A|| ||q_i|| ||q_j||, exceeded the
  // dense solver's 1e-10 structure check on a 2.4e4-DOF model (synthesis
  // truth, issue 4). Hand over the exactly symmetric parts.
  GyroscopicResult ritzModes = DenseGyroscopicSolver(dense).solve(reduced.symmetrised());
  // Keep those the transform favours: largest |1 / (lambda^2 - s)|.
  auto& rm = ritzModes.modes;
  std::stable_sort(rm.begin(), rm.end(), [&](const GyroscopicMode& a, const GyroscopicMode& b) {
    return std::abs(a.lambda * a.lambda - shift) < std::abs(b.lambda * b.lambda - shift);
  });
  // Every candidate gets its full-model residual: a projection can also
  // produce spurious Ritz values (large residual) near the target, and those
  // must lose to genuine modes, not be selected for being close.
  // Damped: D != 0, or a circulatory N (not Hamiltonian either).
  const bool damped = sys.damped();
  expandModes(*Q, rm);
  measureRitzModes(sys, rm, instabTol, !damped);
  // Which scale judges a Ritz value (theory §4.3): its mode's own s_q (set
  // by expandModes) only where the projected pencil was solved
  // componentwise, by the Meirovitch path; dggev resolves the projection
  // only normwise, to the projected pencil's scale, which a rigid mode's
  // s_q (K and G zero on it: rounding) would undercut, its zero read as
  // DIVERGENCE. Then every mode is judged on that projected scale, as the
  // dense path judges its dggev modes on the system's.
  const bool projectedScale = ritzModes.solver.rfind("dense Meirovitch", 0) != 0;
  const double projected =
      frequencyScale(frobeniusNorm(reduced.M),
                     frobeniusNorm(reduced.G) + (reduced.D.numRows() ? frobeniusNorm(reduced.D) : 0.0),
                     frobeniusNorm(reduced.K) + (reduced.N.numRows() ? frobeniusNorm(reduced.N) : 0.0));
  if (projectedScale)
    for (auto& m : rm) m.scale = projected;
  // Undecided growth rates among the modes the solver will return (the
  // first nModes of those within the Residual Tolerance, in this order: the
  // selection of SparseGyroscopicSolver), refined on the full model, then
  // measured again (theory §13.3).
  std::vector<int> returned;
  for (int j = 0; j < static_cast<int>(rm.size()) && static_cast<int>(returned.size()) < refinement.nModes; ++j)
    if (rm[j].residual <= refinement.residualTol) returned.push_back(j);
  const double scale = frequencyScale(sys.M->getFrobeniusNorm(),
                                      sys.G->getFrobeniusNorm() + (sys.D.is_null() ? 0.0 : sys.D->getFrobeniusNorm()),
                                      sys.K->getFrobeniusNorm() + (sys.N.is_null() ? 0.0 : sys.N->getFrobeniusNorm()));
  if (refineRitzModes(sys, rm, returned, instabTol, rigidTol, scale,
                      damped ? refinement.frequencyTol : std::numeric_limits<double>::infinity())) {
    measureRitzModes(sys, rm, instabTol, !damped);
    if (projectedScale)
      for (auto& m : rm) m.scale = projected;
  }
  classifyModes(rm, scale, rigidTol, instabTol, !damped);
  // A returned damped mode left with its first-order error only (not
  // refined, or no step of its refinement kept), that error above the
  // Frequency Tolerance, and whose growth rate, beyond the Instability
  // Tolerance of zero, has a sign that error does not decide is undecided,
  // a split cluster's member too: classifyModes keeps such a member
  // "stable", and a stiff spinning support's flutter, +8.5e-4 1/s, read
  // "stable" as a pair of members at +0.0026 and -0.0087 within 9e3 and
  // 1.3e4 1/s (1 rank; a review; theory §13.3). A refined mode is not
  // (a negative growth within a refined bound reads stable, as before: on
  // fine meshes the bound's rounding floor, 2.3e-2 1/s at 400 elements,
  // exceeds light damping that every solve agrees on, and the first version
  // read UNDECIDED there, and on D = alpha M, a second review). A growth
  // within the Instability Tolerance is zero, as classify takes it: a free
  // body's frame-rate triple, split by rounding (-1.4e-9 1/s at 1 rad/s),
  // stays stable.
  if (damped)
    for (int j : returned) {
      GyroscopicMode& m = rm[j];
      const double size = std::abs(m.lambda), growth = m.lambda.real();
      const double s = m.scale > 0.0 ? std::min(m.scale, scale) : scale;
      if (m.stability == Stability::Stable && m.refinedError == 0.0 &&
          uncertainFrequency(m, refinement.frequencyTol, rigidTol * s) && std::abs(growth) > instabTol * size &&
          growth + m.growthTolerance > instabTol * size)
        m.stability = Stability::Neutral, m.undecided = true;
    }
  return std::move(rm);
}

}  // namespace cms::eigen::detail
