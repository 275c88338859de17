#include "cms/analysis/TruthComparison.hpp"

#include <limits>

#include <algorithm>
#include <cmath>
#include <complex>
#include <tuple>

#include <Teuchos_Array.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/MatrixSum.hpp"
#include "cms/core/SparseInertia.hpp"
#include "cms/eigen/SturmCount.hpp"
#include <Tpetra_CrsMatrix.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

namespace cms::analysis {

namespace {

using cplx = std::complex<double>;
using Shape = std::vector<Teuchos::RCP<MultiVector>>;  // per substructure, (re, im)

/// x = G^-1 b for a small Hermitian positive definite G (Gaussian elimination
/// with partial pivoting).
std::vector<cplx> solveSmall(std::vector<std::vector<cplx>> G, std::vector<cplx> b) {
  const std::size_t n = b.size();
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t p = c;
    for (std::size_t r = c + 1; r < n; ++r)
      if (std::abs(G[r][c]) > std::abs(G[p][c])) p = r;
    std::swap(G[c], G[p]);
    std::swap(b[c], b[p]);
    if (std::abs(G[c][c]) == 0.0) continue;
    for (std::size_t r = c + 1; r < n; ++r) {
      const cplx f = G[r][c] / G[c][c];
      for (std::size_t k = c; k < n; ++k) G[r][k] -= f * G[c][k];
      b[r] -= f * b[c];
    }
  }
  std::vector<cplx> x(n);
  for (std::size_t i = n; i-- > 0;) {
    cplx s = b[i];
    for (std::size_t k = i + 1; k < n; ++k) s -= G[i][k] * x[k];
    x[i] = std::abs(G[i][i]) > 0.0 ? s / G[i][i] : 0.0;
  }
  return x;
}

}  // namespace

std::vector<double> frequencies(const synthesis::StructureModes& modes) {
  std::vector<double> w;
  for (const auto& m : modes.result.modes) w.push_back(m.omega);
  return w;
}

void requireComparableTruth(const synthesis::SynthesizedStructure& truth) {
  const auto& omitted = truth.modalDampingOmitted();
  if (omitted.empty()) return;
  std::string names;
  for (const auto& n : omitted) names += (names.empty() ? "'" : ", '") + n + "'";
  throw InputError("the truth model (every basis Full) has no modal coordinates for the Modal Damping Ratio of " +
                   names + " (doc/theory.md section 13.1), so it would be a less damped structure and every "
                   "difference a false error: compare with Rayleigh Alpha / Beta instead, or read the error "
                   "estimates, which need no truth (section 11.8)");
}

Teuchos::ParameterList truthSolveParameters(const Teuchos::ParameterList& solve, int truthSize) {
  Teuchos::ParameterList p = solve;
  const int n = p.isParameter("Number of Modes") ? p.get<int>("Number of Modes") : 0;
  if (n > 0) p.set("Number of Modes", std::min(truthSize, n + std::max(2, (n + 3) / 4)));
  return p;
}

namespace {

/// a_i^H b_j for every pair (rows: a, columns: b), one reduce over the ranks.
std::vector<std::vector<cplx>> innerProducts(const std::vector<Shape>& a, const std::vector<Shape>& b) {
  const std::size_t na = a.size(), nb = b.size();
  std::vector<double> local(2 * na * nb, 0.0), global(2 * na * nb, 0.0);
  Teuchos::RCP<const Teuchos::Comm<int>> comm;
  if (na > 0 && nb > 0) {
    for (std::size_t k = 0; k < a[0].size(); ++k) {
      if (a[0][k].is_null()) continue;
      comm = a[0][k]->getMap()->getComm();
      std::vector<decltype(a[0][k]->getLocalViewHost(Tpetra::Access::ReadOnly))> va, vb;
      for (const auto& s : a) va.push_back(s[k]->getLocalViewHost(Tpetra::Access::ReadOnly));
      for (const auto& s : b) vb.push_back(s[k]->getLocalViewHost(Tpetra::Access::ReadOnly));
      const std::size_t rows = a[0][k]->getLocalLength();
      for (std::size_t i = 0; i < na; ++i)
        for (std::size_t j = 0; j < nb; ++j) {
          double re = 0.0, im = 0.0;
          for (std::size_t r = 0; r < rows; ++r) {
            const double ar = va[i](r, 0), ai = va[i](r, 1), br = vb[j](r, 0), bi = vb[j](r, 1);
            re += ar * br + ai * bi;
            im += ar * bi - ai * br;
          }
          local[2 * (i * nb + j)] += re;
          local[2 * (i * nb + j) + 1] += im;
        }
    }
  }
  if (!comm.is_null() && !local.empty())
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
  else
    global = local;
  std::vector<std::vector<cplx>> out(na, std::vector<cplx>(nb));
  for (std::size_t i = 0; i < na; ++i)
    for (std::size_t j = 0; j < nb; ++j) out[i][j] = cplx(global[2 * (i * nb + j)], global[2 * (i * nb + j) + 1]);
  return out;
}

/// How much of u lies in the span of the truth modes `cluster`: b^H G^-1 b
/// / u^H u (P: truth-by-reduced inner products, G: the truth's Gram matrix).
double subspaceMac(const std::vector<std::vector<cplx>>& P, const std::vector<std::vector<cplx>>& G, double uu,
                   std::size_t m, const std::vector<int>& cluster) {
  if (!(uu > 0.0) || cluster.empty()) return 0.0;
  std::vector<std::vector<cplx>> Gc(cluster.size(), std::vector<cplx>(cluster.size()));
  std::vector<cplx> b(cluster.size());
  for (std::size_t i = 0; i < cluster.size(); ++i) {
    b[i] = P[cluster[i]][m];
    for (std::size_t j = 0; j < cluster.size(); ++j) Gc[i][j] = G[cluster[i]][cluster[j]];
  }
  const auto x = solveSmall(Gc, b);
  cplx proj = 0.0;
  for (std::size_t i = 0; i < cluster.size(); ++i) proj += std::conj(b[i]) * x[i];
  return std::clamp(proj.real() / uu, 0.0, 1.0);
}

}  // namespace

TruthComparison compareWithTruth(const synthesis::SynthesizedStructure& reduced,
                                 const synthesis::StructureModes& rm,
                                 const synthesis::SynthesizedStructure& truth,
                                 const synthesis::StructureModes& tm, int count) {
  requireComparableTruth(truth);
  CMS_INPUT_CHECK(count < 1 || static_cast<int>(rm.result.modes.size()) < count ||
                      static_cast<int>(tm.result.modes.size()) < count,
                  "compareWithTruth: " << count << " modes asked; the reduced model has " << rm.result.modes.size()
                                       << " and the truth " << tm.result.modes.size());
  const auto& rmodes = rm.result.modes;
  const auto& tmodes = tm.result.modes;
  const int T = static_cast<int>(tmodes.size());
  double scale = 0.0;
  for (int m = 0; m < count; ++m) scale = std::max(scale, tmodes[m].omega);
  scale = std::max(scale, 1e-300);
  const auto isRigid = [&](double w) { return w < 1e-6 * scale; };

  // 1. Every shape of both, and their inner products in three reduces.
  std::vector<Shape> truthShapes(T), reducedShapes(count);
  for (int t = 0; t < T; ++t) truthShapes[t] = truth.expand(tm, t);
  for (int m = 0; m < count; ++m) reducedShapes[m] = reduced.expand(rm, m);
  const auto P = innerProducts(truthShapes, reducedShapes);  // t^H u
  const auto G = innerProducts(truthShapes, truthShapes);
  const auto U = innerProducts(reducedShapes, reducedShapes);

  // 2. The truth's clusters: its rigid-body zeros together (their computed
  //    shapes are any combination of the rigid motions), and modes whose
  //    frequencies follow within 1e-3 (a repeated pair of a symmetric rotor,
  //    a spinning free body's defective frame-rate pair): what a reduced
  //    shape is compared against as a whole.
  std::vector<std::vector<int>> clusters;
  std::vector<int> clusterOf(T, -1);
  for (int t = 0; t < T; ++t) {
    const double w = tmodes[t].omega;
    bool joins = false;
    if (!clusters.empty()) {
      const double last = tmodes[clusters.back().back()].omega;
      joins = isRigid(w) ? isRigid(last) : (!isRigid(last) && w - last <= 1e-3 * w);
    }
    if (!joins) clusters.emplace_back();
    clusters.back().push_back(t);
    clusterOf[t] = static_cast<int>(clusters.size()) - 1;
  }

  // 3. Pairing by shape: each reduced mode to the cluster holding most of
  //    it (subspace MAC), best pairs first, a cluster taking as many reduced
  //    modes as it has members; within a cluster, to the member of largest
  //    MAC left. A reduced mode no cluster holds half of (MAC < 0.5 with
  //    each one left) is unmatched: the truth mode of its shape is not
  //    among those computed, or its shape is not converged; its error is
  //    then against the nearest truth frequency, which it does not take.
  std::vector<std::tuple<double, double, int, int>> candidates;  // (-mac, |dw|, m, cluster)
  for (int m = 0; m < count; ++m)
    for (int c = 0; c < static_cast<int>(clusters.size()); ++c) {
      const double mac = subspaceMac(P, G, U[m][m].real(), static_cast<std::size_t>(m), clusters[c]);
      if (mac >= 0.5)
        candidates.emplace_back(-mac, std::abs(rmodes[m].omega - tmodes[clusters[c].front()].omega), m, c);
    }
  std::sort(candidates.begin(), candidates.end());
  std::vector<int> partner(count, -1), room(clusters.size());
  for (std::size_t c = 0; c < clusters.size(); ++c) room[c] = static_cast<int>(clusters[c].size());
  std::vector<bool> taken(T, false);
  for (const auto& [negMac, dw, m, c] : candidates) {
    if (partner[m] >= 0 || room[c] == 0) continue;
    int best = -1;
    double bestMac = -1.0;
    for (int t : clusters[c]) {
      if (taken[t]) continue;
      const double gtt = G[t][t].real(), uu = U[m][m].real();
      const double mac = gtt > 0.0 && uu > 0.0 ? std::norm(P[t][m]) / (gtt * uu) : 0.0;
      if (mac > bestMac) best = t, bestMac = mac;
    }
    partner[m] = best;
    taken[best] = true;
    --room[c];
  }

  TruthComparison out;
  double sum = 0.0;
  const auto character = reduced.characterise(rm);  // frame-rate modes (collective)
  std::vector<double> error(count);
  std::vector<int> against(count);  // the partner, or for an unmatched mode the nearest truth frequency
  for (int m = 0; m < count; ++m) {
    int t = partner[m];
    if (t < 0) {
      t = 0;
      for (int j = 1; j < T; ++j)
        if (std::abs(tmodes[j].omega - rmodes[m].omega) < std::abs(tmodes[t].omega - rmodes[m].omega)) t = j;
    }
    against[m] = t;
    const double wt = tmodes[t].omega;
    error[m] = (rmodes[m].omega - wt) / (isRigid(wt) ? scale : wt);
  }
  for (int m = 0; m < count; ++m) {
    ModeAccuracy a;
    a.index = m;
    a.omega = rmodes[m].omega;
    a.unmatched = partner[m] < 0;
    a.truthIndex = partner[m];
    a.truthOmega = tmodes[against[m]].omega;
    a.rigid = isRigid(a.truthOmega);
    a.frameRate = m < static_cast<int>(character.size()) && character[m].frameArtefact;
    a.relativeError = error[m];
    // The MAC reported: against the truth modes (numerically) of the same
    // frequency as the partner, the subspace a reduced mode cannot be told
    // apart within at its own accuracy. Rigid-body zeros form one cluster;
    // otherwise the truth modes within max(1e-6, twice this mode's or a
    // neighbour's error, at most 10%) of the partner (close pairs or
    // triples of symmetric structures split differently in each model).
    double spread = std::abs(error[m]);
    if (m > 0) spread = std::max(spread, std::abs(error[m - 1]));
    if (m + 1 < count) spread = std::max(spread, std::abs(error[m + 1]));
    const double window = std::min(0.1, std::max(1e-6, 2.0 * spread)) * a.truthOmega;
    std::vector<int> cluster;
    for (int t = 0; t < T; ++t) {
      const double wt = tmodes[t].omega;
      if (a.rigid ? isRigid(wt) : std::abs(wt - a.truthOmega) <= window) cluster.push_back(t);
    }
    a.mac = subspaceMac(P, G, U[m][m].real(), static_cast<std::size_t>(m), cluster);
    out.maxRelativeError = std::max(out.maxRelativeError, std::abs(a.relativeError));
    if (!a.rigid && !a.frameRate) out.worstMac = std::min(out.worstMac, a.mac);
    out.unmatchedModes += a.unmatched;
    sum += std::abs(a.relativeError);
    out.modes.push_back(a);
  }
  // 4. The truth's modes that no reduced mode took, in clusters below the
  //    highest one a reduced mode took: modes the reduced model lacks. Not
  //    in that cluster (a repeated pair the mode count cuts) nor above it
  //    (the partners of reduced modes above the `count` compared: Ritz
  //    values lie above the truth's, so truth modes just below the highest
  //    reduced frequency may be theirs).
  int highest = -1;
  for (int m = 0; m < count; ++m)
    if (partner[m] >= 0) highest = std::max(highest, clusterOf[partner[m]]);
  for (int t = 0; t < T; ++t) out.missingModes += !taken[t] && clusterOf[t] < highest;
  out.meanRelativeError = sum / count;
  return out;
}

std::vector<InclusionViolation> checkInclusion(const std::vector<double>& coarse, const std::vector<double>& fine,
                                               double relTol, int added) {
  CMS_INPUT_CHECK(added < 1, "checkInclusion: " << added << " added coordinates; must be >= 1");
  std::vector<InclusionViolation> v;
  const std::size_t k = static_cast<std::size_t>(added);
  for (std::size_t r = 0; r < coarse.size() && r < fine.size(); ++r) {
    const double tol = relTol * std::max(std::abs(coarse[r]), 1e-300);
    if (fine[r] > coarse[r] + tol)
      v.push_back({static_cast<int>(r), "fine[r] <= coarse[r]", (fine[r] - coarse[r]) / coarse[r]});
    if (r + k < fine.size() && coarse[r] > fine[r + k] + tol)
      v.push_back({static_cast<int>(r), "coarse[r] <= fine[r+" + std::to_string(k) + "]",
                   (coarse[r] - fine[r + k]) / coarse[r]});
  }
  return v;
}

std::vector<InclusionViolation> checkInclusion(const synthesis::StructureModes& coarse,
                                               const synthesis::StructureModes& fine, int added) {
  CMS_INPUT_CHECK(added < 1, "checkInclusion: " << added << " added coordinates; must be >= 1");
  const auto& c = coarse.result.modes;
  const auto& f = fine.result.modes;
  // What the solve's residual can do to this mode's frequency, relative.
  auto roundOff = [](const eigen::GyroscopicMode& m) {
    const double w = std::max(m.omega, std::numeric_limits<double>::min());
    const double kappa = m.scale > w ? (m.scale / w) * (m.scale / w) : 1.0;
    return kappa * std::max(10.0 * m.residual, 100.0 * std::numeric_limits<double>::epsilon());
  };
  std::vector<InclusionViolation> v;
  const std::size_t k = static_cast<std::size_t>(added);
  for (std::size_t r = 0; r < c.size() && r < f.size(); ++r) {
    const double scale = std::max(std::abs(c[r].omega), std::numeric_limits<double>::min());
    if (f[r].omega > c[r].omega + (roundOff(c[r]) + roundOff(f[r])) * scale)
      v.push_back({static_cast<int>(r), "fine[r] <= coarse[r]", (f[r].omega - c[r].omega) / scale});
    if (r + k < f.size() && c[r].omega > f[r + k].omega + (roundOff(c[r]) + roundOff(f[r + k])) * scale)
      v.push_back({static_cast<int>(r), "coarse[r] <= fine[r+" + std::to_string(k) + "]",
                   (c[r].omega - f[r + k].omega) / scale});
  }
  return v;
}

EigenvaluePairing pairEigenvalues(const std::vector<std::complex<double>>& reduced,
                                  const std::vector<std::complex<double>>& truth) {
  // Nearest pairs first, each eigenvalue once: the nearest alone let two
  // reduced modes take one truth mode and hid the one between them that the
  // reduced model lacks (found by a review).
  const auto distance = [](std::complex<double> a, std::complex<double> b) {
    const double d = std::min(std::abs(a - b), std::abs(a - std::conj(b)));
    return std::abs(b) > 0 ? d / std::abs(b) : d;
  };
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < reduced.size(); ++i)
    for (std::size_t j = 0; j < truth.size(); ++j) pairs.emplace_back(distance(reduced[i], truth[j]), i, j);
  std::stable_sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return std::get<0>(a) < std::get<0>(b); });
  EigenvaluePairing out;
  out.relativeErrors.assign(reduced.size(), std::numeric_limits<double>::infinity());
  std::vector<bool> doneReduced(reduced.size(), false), doneTruth(truth.size(), false);
  for (const auto& [d, i, j] : pairs)
    if (!doneReduced[i] && !doneTruth[j]) doneReduced[i] = doneTruth[j] = true, out.relativeErrors[i] = d;
  double top = 0.0;
  for (const auto& l : reduced) top = std::max(top, std::abs(l));
  for (std::size_t j = 0; j < truth.size(); ++j) out.missing += !doneTruth[j] && std::abs(truth[j]) <= top;
  return out;
}

long long truthFrequenciesBelow(const synthesis::AssembledStructure& structure, const std::vector<double>& speeds,
                                double omega) {
  return truthFrequenciesBelow(synthesis::SynthesizedStructure::synthesize(structure, true), speeds, omega);
}

long long truthFrequenciesBelow(const synthesis::SynthesizedStructure& truth, const std::vector<double>& speeds,
                                double omega) {
  // The sparse path's count (eigen::sturmCount): MUMPS's multifrontal
  // L D L^T from a few thousand DOFs, retaken 1e-8 off a zero pivot.
  // The inertia of K - w^2 M + i w G counts undamped frequencies (theory
  // §11.9); a damped mode's lies below its undamped one, so with D the
  // truth could count one short of the reduced model and hide a missing
  // mode (found by a review): not counted.
  const auto sys = truth.system(speeds);
  if (!sys.D.is_null() && sys.D->getFrobeniusNorm() > 0.0) return -3;
  if (!truth.modalDampingOmitted().empty()) return -3;  // damped, though not in this truth
  // The count's premise, K(Omega) >= 0: with it every eigenvalue of Q(w)
  // falls as w rises through a frequency (dQ/dw = -2wM + iG is negative on
  // each mode of a gyroscopically stable structure), so the inertia counts
  // frequencies. A free body in a spinning frame, or a rotor past a
  // divergence speed, has K indefinite: modes of the other sign lower the
  // count as w passes them, and a number would be no count (found by a
  // review; the spacecraft printed "none missing"). Tested as the inertia of
  // K + sigma M, sigma = 1e-4 w^2: rigid modes (K singular, zero
  // frequencies, which the count handles) shift to +sigma. A pivot within
  // the inertia's zero-pivot guard (1e-12 of the largest diagonal, ~5e3
  // eps) is read neither way: with K >= 0 the matrix is positive definite
  // and its L D L^T without pivoting has no growth (as Cholesky), so
  // rounding cannot make a pivot negative beyond the guard; the free
  // hub-boom at rest, its stiff hub's axial stiffness the largest diagonal,
  // puts a rigid mode's pivot inside it for cuts up to ~36 rad/s. A
  // negative stiffness within sigma (an imaginary frequency below 1% of the
  // cut), or whose pivot falls within the guard, is below what this resolves.
  if (std::isfinite(omega) && omega > 0.0) {  // else sturmCount refuses the request
    const auto shifted =
        inertia(Teuchos::RCP<const CrsMatrix>(matrixSum(1.0, *sys.K, 1e-4 * omega * omega, *sys.M)));
    if (!shifted.failure.empty()) return -1;
    if (shifted.negative > 0) return -4;
  }
  const auto count = eigen::sturmCount(sys, omega);
  return count.reliable ? count.count : -1;
}

std::string truthCountNote(long long code) {
  if (code == -1) return "the truth's count was not reliable (pivots zero to rounding: a frequency at the cut-off)";
  if (code == -3) return "not counted: the structure is damped, and the Sturm count counts undamped frequencies";
  if (code == -4)
    return "not counted: K(Omega) is not positive semidefinite (a free body spinning, or past a divergence speed), "
           "where a Sturm count is no count of frequencies";
  return {};
}

}  // namespace cms::analysis
