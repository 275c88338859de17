#include "cms/analysis/TruthComparison.hpp"

#include <limits>

#include <algorithm>
#include <cmath>
#include <complex>
#include <iomanip>
#include <sstream>
#include <tuple>

#include <Teuchos_Array.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/MatrixSum.hpp"
#include "cms/core/SparseInertia.hpp"
#include "cms/eigen/SturmCount.hpp"
#include "HermitianEmbedding.hpp"
#include <Tpetra_CrsMatrix.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

namespace cms::analysis {

namespace {

using cplx = std::complex<double>;
using Shape = std::vector<Teuchos::RCP<MultiVector>>;  // per substructure, (re, im)

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

std::string trueErrorText(double maxRelativeError, int missingModes, int unmatchedModes) {
  std::ostringstream os;
  os << std::setprecision(4);
  if (missingModes > 0) os << "MISSING " << missingModes;
  else if (unmatchedModes > 0) os << "UNMATCHED " << unmatchedModes;
  else os << maxRelativeError;
  return os.str();
}

Teuchos::ParameterList comparedSolveParameters(const Teuchos::ParameterList& solve, long long size) {
  Teuchos::ParameterList p = solve;
  const int n = p.isParameter("Number of Modes") ? p.get<int>("Number of Modes") : 0;
  if (n > 0)
    p.set("Number of Modes", static_cast<int>(std::min<long long>(size, n + std::max(2, (n + 3) / 4))));
  return p;
}

synthesis::StructureModes solveForComparison(const synthesis::SynthesizedStructure& model,
                                             const std::vector<double>& speeds, const Teuchos::ParameterList& solve) {
  const auto wider = comparedSolveParameters(solve, model.size());
  auto modes = model.solve(speeds, wider);
  if (modes.result.status != eigen::SolveStatus::Converged &&
      wider.get<int>("Number of Modes") != solve.get<int>("Number of Modes"))
    modes = model.solve(speeds, solve);
  return modes;
}

namespace {

/// Collective: a^H b summed over every substructure's rows and the ranks
/// (each shape: per substructure, columns re and im).
std::vector<cplx> reduceInner(const std::vector<cplx>& local, const Teuchos::Comm<int>& comm) {
  std::vector<double> in(2 * local.size()), out(2 * local.size());
  for (std::size_t i = 0; i < local.size(); ++i) in[2 * i] = local[i].real(), in[2 * i + 1] = local[i].imag();
  if (!in.empty()) Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, static_cast<int>(in.size()), in.data(), out.data());
  std::vector<cplx> r(local.size());
  for (std::size_t i = 0; i < local.size(); ++i) r[i] = cplx(out[2 * i], out[2 * i + 1]);
  return r;
}

/// This rank's part of a_i^H b for every a_i (no communication).
std::vector<cplx> localInner(const std::vector<Shape>& a, const Shape& b) {
  std::vector<cplx> out(a.size(), 0.0);
  for (std::size_t k = 0; k < b.size(); ++k) {
    const auto vb = b[k]->getLocalViewHost(Tpetra::Access::ReadOnly);
    const std::size_t rows = b[k]->getLocalLength();
    for (std::size_t i = 0; i < a.size(); ++i) {
      const auto va = a[i][k]->getLocalViewHost(Tpetra::Access::ReadOnly);
      double re = 0.0, im = 0.0;
      for (std::size_t r = 0; r < rows; ++r) {
        const double ar = va(r, 0), ai = va(r, 1), br = vb(r, 0), bi = vb(r, 1);
        re += ar * br + ai * bi;
        im += ar * bi - ai * br;
      }
      out[i] += cplx(re, im);
    }
  }
  return out;
}

/// How much of u lies in the span of the truth modes `set`: b^H G^+ b /
/// u^H u with b = T^H u and G = T^H T over the set. G by its eigenvalues,
/// those below 1e-10 of the largest dropped: computed shapes of a
/// defective or repeated pair can be nearly parallel, where an inverse
/// would turn rounding into any number in [0, 1].
double subspaceMac(const std::vector<std::vector<cplx>>& P, const std::vector<std::vector<cplx>>& G, double uu,
                   std::size_t m, const std::vector<int>& set) {
  // The Hermitian G as its real symmetric embedding (each eigenvalue
  // twice), b as [Re b; Im b]: b^H G^+ b unchanged.
  const int k = static_cast<int>(set.size()), n = 2 * k;
  if (!(uu > 0.0) || k == 0) return 0.0;
  std::vector<std::complex<double>> Gs(static_cast<std::size_t>(k) * k);
  std::vector<double> b(n);
  for (int j = 0; j < k; ++j) {
    b[j] = P[set[j]][m].real(), b[j + k] = P[set[j]][m].imag();
    for (int i = 0; i < k; ++i) Gs[i + k * j] = G[set[i]][set[j]];
  }
  std::vector<double> A = detail::hermitianEmbedding(Gs, k);
  const std::vector<double> w = detail::symmetricEigen(A, n, "compareWithTruth");
  const double top = w[n - 1];
  double proj = 0.0;
  for (int j = 0; j < n; ++j) {
    if (!(w[j] > 1e-10 * top)) continue;
    double vb = 0.0;
    for (int i = 0; i < n; ++i) vb += A[i + j * n] * b[i];
    proj += vb * vb / w[j];
  }
  return std::clamp(proj / uu, 0.0, 1.0);
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
  const int T = static_cast<int>(tmodes.size()), R = static_cast<int>(rmodes.size());
  double scale = 0.0;
  for (int m = 0; m < count; ++m) scale = std::max(scale, tmodes[m].omega);
  scale = std::max(scale, 1e-300);
  // A truth mode is a rigid-body zero by its solve's verdict (a full
  // model's dggev leaves its zeros at ~sqrt(eps) of its own scale, which
  // can exceed 1e-6 of the compared range) or by a frequency below 1e-6 of
  // the compared range (the errors' convention: absolute over that scale).
  std::vector<bool> rigid(T);
  for (int t = 0; t < T; ++t)
    rigid[t] = tmodes[t].stability == eigen::Stability::RigidBody || tmodes[t].omega < 1e-6 * scale;

  // 1. The truth's shapes and their Gram matrix; each reduced shape (one at
  //    a time: a large truth's shapes are memory enough) against them.
  std::vector<Shape> truthShapes(T);
  for (int t = 0; t < T; ++t) truthShapes[t] = truth.expand(tm, t);
  const auto comm = truthShapes.empty() || truthShapes[0].empty() ? Teuchos::DefaultComm<int>::getComm()
                                                                    : truthShapes[0][0]->getMap()->getComm();
  std::vector<std::vector<cplx>> G(T);
  for (int t = 0; t < T; ++t) G[t] = reduceInner(localInner(truthShapes, truthShapes[t]), *comm);  // G[i][t]
  std::vector<std::vector<cplx>> P(T, std::vector<cplx>(R));  // t^H u_m
  std::vector<double> uu(R);
  for (int m = 0; m < R; ++m) {
    const Shape u = reduced.expand(rm, m);
    auto local = localInner(truthShapes, u);
    local.push_back(localInner({u}, u)[0]);
    const auto inner = reduceInner(local, *comm);
    for (int t = 0; t < T; ++t) P[t][m] = inner[t];
    uu[m] = inner[T].real();
  }
  // G was filled column by column: G[t] holds (truth_i^H truth_t)_i.
  for (int i = 0; i < T; ++i)
    for (int j = i + 1; j < T; ++j) std::swap(G[i][j], G[j][i]);

  // 2. The truth's clusters, in ascending frequency (the solvers order by
  //    |lambda|, which damping or a real eigenvalue puts out of frequency
  //    order): its rigid-body zeros together (their computed shapes are any
  //    combination of the rigid motions), then eigenvalues that follow
  //    within 1e-3 of each other (a repeated pair of a symmetric rotor, a
  //    spinning free body's defective frame-rate pair): what a reduced
  //    shape is compared against as a whole.
  std::vector<int> order;
  for (int t = 0; t < T; ++t)
    if (!rigid[t]) order.push_back(t);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return tmodes[a].omega != tmodes[b].omega ? tmodes[a].omega < tmodes[b].omega
                                              : std::abs(tmodes[a].lambda) < std::abs(tmodes[b].lambda);
  });
  std::vector<std::vector<int>> clusters;
  std::vector<int> clusterOf(T, -1);
  for (int t = 0; t < T; ++t)
    if (rigid[t]) {
      if (clusters.empty()) clusters.emplace_back();
      clusters.back().push_back(t);
    }
  bool first = true;
  for (int t : order) {
    const auto l = tmodes[t].lambda;
    const bool joins = !first && [&] {
      const auto last = tmodes[clusters.back().back()].lambda;
      return std::abs(l - last) <= 1e-3 * std::max(std::abs(l), std::abs(last));
    }();
    if (!joins) clusters.emplace_back();
    clusters.back().push_back(t);
    first = false;
  }
  for (std::size_t c = 0; c < clusters.size(); ++c)
    for (int t : clusters[c]) clusterOf[t] = static_cast<int>(c);

  // 3. Pairing by shape, over every reduced mode given (those above the
  //    `count` compared take their partners too, so that two modes in the
  //    other order at the edge of the range are not read as one missing):
  //    each reduced mode to the cluster holding most of it (subspace MAC at
  //    least 0.5), best pairs first, a cluster taking as many reduced modes
  //    as it has members; within a cluster, to the member of largest single
  //    MAC left.
  std::vector<int> partner(R, -1), room(clusters.size());
  std::vector<bool> taken(T, false);
  for (std::size_t c = 0; c < clusters.size(); ++c) room[c] = static_cast<int>(clusters[c].size());
  const auto singleMac = [&](int t, int m) {
    const double gtt = G[t][t].real();
    return gtt > 0.0 && uu[m] > 0.0 ? std::norm(P[t][m]) / (gtt * uu[m]) : 0.0;
  };
  const auto take = [&](int m, const std::vector<int>& members) {
    int best = -1;
    for (int t : members)
      if (!taken[t] && (best < 0 || singleMac(t, m) > singleMac(best, m))) best = t;
    if (best < 0) return false;
    partner[m] = best;
    taken[best] = true;
    --room[clusterOf[best]];
    return true;
  };
  {
    std::vector<std::tuple<double, double, int, int>> candidates;  // (-mac, |dw|, m, cluster)
    for (int m = 0; m < R; ++m)
      for (int c = 0; c < static_cast<int>(clusters.size()); ++c) {
        const double mac = subspaceMac(P, G, uu[m], static_cast<std::size_t>(m), clusters[c]);
        if (mac >= 0.5)
          candidates.emplace_back(-mac, std::abs(rmodes[m].omega - tmodes[clusters[c].front()].omega), m, c);
      }
    std::sort(candidates.begin(), candidates.end());
    for (const auto& [negMac, dw, m, c] : candidates)
      if (partner[m] < 0 && room[c] > 0) take(m, clusters[c]);
  }
  //    A second pass for the modes left: a close pair split by more than
  //    1e-3, whose shapes the two models mix differently, holds half of
  //    neither member alone; the truth modes within 10% of the reduced
  //    frequency together may hold it. A reduced mode that no such set
  //    holds half of is unmatched: its partner lies above the truth modes
  //    computed, or its shape has not converged; its error is then against
  //    the nearest truth frequency, which it does not take.
  for (int m = 0; m < R; ++m) {
    if (partner[m] >= 0) continue;
    std::vector<int> near;
    for (int t = 0; t < T; ++t)
      if (!rigid[t] && std::abs(tmodes[t].omega - rmodes[m].omega) <= 0.1 * rmodes[m].omega) near.push_back(t);
    if (subspaceMac(P, G, uu[m], static_cast<std::size_t>(m), near) >= 0.5) take(m, near);
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
    error[m] = (rmodes[m].omega - tmodes[t].omega) / (rigid[t] ? scale : tmodes[t].omega);
  }
  for (int m = 0; m < count; ++m) {
    ModeAccuracy a;
    a.index = m;
    a.omega = rmodes[m].omega;
    a.unmatched = partner[m] < 0;
    a.truthIndex = partner[m];
    a.truthOmega = tmodes[against[m]].omega;
    a.rigid = rigid[against[m]];
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
    for (int t = 0; t < T; ++t)
      if (a.rigid ? rigid[t] : (!rigid[t] && std::abs(tmodes[t].omega - a.truthOmega) <= window)) cluster.push_back(t);
    a.mac = subspaceMac(P, G, uu[m], static_cast<std::size_t>(m), cluster);
    out.maxRelativeError = std::max(out.maxRelativeError, std::abs(a.relativeError));
    if (!a.rigid && !a.frameRate) out.worstMac = std::min(out.worstMac, a.mac);
    out.unmatchedModes += a.unmatched;
    sum += std::abs(a.relativeError);
    out.modes.push_back(a);
  }
  // 4. The truth's modes that no reduced mode took, in clusters below the
  //    highest one a compared reduced mode took: modes the reduced model
  //    lacks. Not in that cluster (a repeated pair the mode count cuts), nor
  //    above it; a truth mode an unmatched reduced mode would have taken is
  //    counted here too (that mode is counted unmatched).
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
