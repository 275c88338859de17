// Gyroscopic modes from the converged vectors of the spectral transform
// (QuadraticRitz.hpp).
#include "QuadraticRitz.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <AnasaziTpetraAdapter.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/Error.hpp"
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
  return orthonormalBasis(*orthonormalBasis(halves, 1e-20), 1e-20);
}

/// Full modes q = Q q_r, M-normalised with the phase of their largest entry
/// over all ranks, and their residuals, energies and scales from M, G, K.
void expandModes(const SparseGyroscopicSystem& sys, const MultiVector& Q, std::vector<GyroscopicMode>& rm,
                 double instabilityTol, bool conservative) {
  const auto rowMap = sys.M->getRowMap();
  const auto comm = rowMap->getComm();
  const int k = static_cast<int>(rm.size());
  const int kk = std::max(k, 1);
  DenseMatrix Yr(static_cast<int>(Q.getNumVectors()), kk), Yi(static_cast<int>(Q.getNumVectors()), kk);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < Yr.numRows(); ++i) {
      Yr(i, j) = rm[j].q[i].real();
      Yi(i, j) = rm[j].q[i].imag();
    }
  MultiVector Qr(rowMap, kk), Qi(rowMap, kk);
  MVT::MvTimesMatAddMv(1.0, Q, Yr, 0.0, Qr);
  MVT::MvTimesMatAddMv(1.0, Q, Yi, 0.0, Qi);
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
    m.growthTolerance = growthUncertainty(l, std::min(m.eigenvalueError, std::max(m.scale, std::abs(l))), etaQ,
                                          instabilityTol, others, conservative);
  }
}

}  // namespace

std::vector<GyroscopicMode> quadraticRitzModes(const SparseGyroscopicSystem& sys, const MultiVector& vectors,
                                               double shift, double rigidTol, double instabTol) {
  const auto Q = ritzSubspace(vectors, sys.M->getRowMap());
  GyroscopicSystem reduced{projectOnto(*sys.M, *Q), projectOnto(*sys.G, *Q), projectOnto(*sys.K, *Q)};
  if (!sys.D.is_null()) reduced.D = projectOnto(*sys.D, *Q);
  if (!sys.N.is_null()) reduced.N = projectOnto(*sys.N, *Q);
  Teuchos::ParameterList dense;
  dense.set("Rigid Body Tolerance", rigidTol);
  dense.set("Instability Tolerance", instabTol);
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
  const bool damped = (!sys.D.is_null() && sys.D->getFrobeniusNorm() > 0.0) ||
                      (!sys.N.is_null() && sys.N->getFrobeniusNorm() > 0.0);
  expandModes(sys, *Q, rm, instabTol, !damped);
  // Which scale judges a Ritz value (theory §4.3): its mode's own s_q (set
  // by expandModes) only where the projected pencil was solved
  // componentwise, by the Meirovitch path; dggev resolves the projection
  // only normwise, to the projected pencil's scale, which a rigid mode's
  // s_q (K and G zero on it: rounding) would undercut, its zero read as
  // DIVERGENCE. Then every mode is judged on that projected scale, as the
  // dense path judges its dggev modes on the system's.
  if (ritzModes.solver.rfind("dense Meirovitch", 0) != 0) {
    const double projected = frequencyScale(
        frobeniusNorm(reduced.M), frobeniusNorm(reduced.G) + (reduced.D.numRows() ? frobeniusNorm(reduced.D) : 0.0),
        frobeniusNorm(reduced.K) + (reduced.N.numRows() ? frobeniusNorm(reduced.N) : 0.0));
    for (auto& m : rm) m.scale = projected;
  }
  const double scale = frequencyScale(sys.M->getFrobeniusNorm(),
                                      sys.G->getFrobeniusNorm() + (sys.D.is_null() ? 0.0 : sys.D->getFrobeniusNorm()),
                                      sys.K->getFrobeniusNorm() + (sys.N.is_null() ? 0.0 : sys.N->getFrobeniusNorm()));
  classifyModes(rm, scale, rigidTol, instabTol, !damped);
  return std::move(rm);
}

}  // namespace cms::eigen::detail
