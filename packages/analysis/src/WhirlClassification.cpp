#include "cms/analysis/WhirlClassification.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/ParameterReading.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"
#include "HermitianEmbedding.hpp"

namespace cms::analysis {

const char* toString(Whirl w) {
  switch (w) {
    case Whirl::Forward: return "FW";
    case Whirl::Backward: return "BW";
    case Whirl::Neutral: return "-";
    case Whirl::Unresolved: return "unresolved";
  }
  return "?";
}

namespace {

/// A mode reported at -omega is the conjugate motion.
std::complex<double> oriented(std::complex<double> a, const eigen::GyroscopicMode& mode) {
  return mode.lambda.imag() < 0 ? std::conj(a) : a;
}

bool zeroFrequency(const eigen::GyroscopicMode& m) {
  return m.stability == eigen::Stability::RigidBody || m.stability == eigen::Stability::Critical || m.omega == 0.0;
}

/// Eigenvalues of the pencil (S, N) on the range of N: N = V D V^T, W = V_r
/// D_r^{-1/2} (the eigenvalues of N above 1e-12 of the largest), the
/// eigenvalues of W^T S W. Invariant under any change of basis.
std::vector<double> pencilEigenvalues(const std::vector<double>& S, const std::vector<double>& Nv,
                                      const std::vector<double>& d, int n) {
  const double dmax = d.empty() ? 0.0 : d.back();
  std::vector<int> keep;
  for (int j = 0; j < n; ++j)
    if (d[j] > 1e-12 * dmax && d[j] > 0.0) keep.push_back(j);
  const int r = static_cast<int>(keep.size());
  std::vector<double> W(n * r);
  for (int c = 0; c < r; ++c)
    for (int i = 0; i < n; ++i) W[i + n * c] = Nv[i + n * keep[c]] / std::sqrt(d[keep[c]]);
  std::vector<double> SW(n * r, 0.0), T(r * r, 0.0);
  for (int c = 0; c < r; ++c)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) SW[i + n * c] += S[i + n * j] * W[j + n * c];
  for (int b = 0; b < r; ++b)
    for (int a = 0; a < r; ++a)
      for (int i = 0; i < n; ++i) T[a + r * b] += W[i + n * a] * SW[i + n * b];
  for (int b = 0; b < r; ++b)  // symmetrise the rounding
    for (int a = 0; a < b; ++a) T[a + r * b] = T[b + r * a] = 0.5 * (T[a + r * b] + T[b + r * a]);
  return detail::symmetricEigen(T, r, "WhirlClassification");
}

}  // namespace

Orbit orbitOfPairs(const eigen::GyroscopicMode& mode, const std::vector<std::pair<int, int>>& pairs) {
  Orbit o;
  const int n = static_cast<int>(mode.q.size());
  for (const auto& [v, w] : pairs) {
    CMS_INPUT_CHECK(v < 0 || w < 0 || v >= n || w >= n,
                    "orbitOfPairs: pair (" << v << ", " << w << ") outside the mode's " << n << " coordinates");
    o.a1.push_back(oriented(mode.q[v], mode));
    o.a2.push_back(oriented(mode.q[w], mode));
    o.a3.push_back(0.0);
  }
  return o;
}

Orbit orbitOfSubstructure(const synthesis::AssembledStructure& a, const std::vector<Teuchos::RCP<MultiVector>>& u,
                          std::size_t k, const eigen::GyroscopicMode& mode) {
  const auto& spec = a.substructure(k);
  CMS_INPUT_CHECK(!spec.spin, "orbitOfSubstructure: " << spec.name << " does not spin");
  // e1, e2 transverse with e1 x e2 = n, the unit spin axis (the orbit's
  // sense, Im(a1 conj(a2)), does not depend on which such pair).
  const fem::Vec3 n = fem::unit(spec.spin->axis);
  const auto [e1, e2] = fem::transverseBasis(n);
  const auto map = u[k]->getMap();
  const auto* sub = a.assembled(k);
  const auto nodeOf = sub ? sub->dofs().rowNodes() : std::vector<std::int64_t>();
  // Per node the complex 3-vector of the translations (elastic part); a
  // rigid rotor is sampled twice: its centre's translations, and its
  // rotations times its radius of gyration sqrt(I_t / m) (the motion they
  // make there, with the same kinetic-energy weight). Its rotations alone
  // made a Jeffcott disc, which translates without tilting, "no whirl" at
  // its unbalance critical speed (found by a review). The spin angle, row
  // 6, is no orbit. A node's rows live on one rank (fem::assemble).
  std::map<long long, std::array<std::complex<double>, 3>> v;
  const auto re = u[k]->getData(0), im = u[k]->getData(1);
  const double gyration = spec.rotor.mass > 0.0 ? std::sqrt(spec.rotor.transverseInertia / spec.rotor.mass) : 1.0;
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
    const auto g = map->getGlobalElement(static_cast<LocalOrdinal>(l));
    int c = static_cast<int>(g);
    long long node = 0;
    double weight = 1.0;
    if (sub) {
      c = static_cast<int>(sub->dofs().components[g]);
      node = nodeOf[g];
    } else if (c >= 3) {
      c -= 3, node = 1, weight = gyration;
    }
    if (c < 0 || c > 2) continue;
    v[node][c] = weight * oriented({re[l], im[l]}, mode);
  }
  Orbit o;
  for (const auto& [node, x] : v) {
    o.a1.push_back(x[0] * e1[0] + x[1] * e1[1] + x[2] * e1[2]);
    o.a2.push_back(x[0] * e2[0] + x[1] * e2[1] + x[2] * e2[2]);
    o.a3.push_back(x[0] * n[0] + x[1] * n[1] + x[2] * n[2]);
  }
  return o;
}

Teuchos::RCP<const Teuchos::ParameterList> WhirlClassification::getValidParameters() {
  static Teuchos::RCP<Teuchos::ParameterList> p;
  if (p.is_null()) {
    p = Teuchos::rcp(new Teuchos::ParameterList("Whirl"));
    auto unit = [](double lo) {
      return Teuchos::rcp(new Teuchos::EnhancedNumberValidator<double>(lo, 1.0));
    };
    p->set("Cluster Tolerance", 1e-3,
           "relative frequency difference within which modes form one cluster, classified as a whole", unit(0.0));
    p->set("Transverse Share", 0.1, "a motion with less transverse share (of the part's motion) is neutral", unit(0.0));
    p->set("Circularity", 1e-2, "an orbit with less circularity (times its transverse share) is flat: neutral",
           unit(0.0));
    p->set("Participation", 1e-6,
           "a mode whose motion of the part is below this fraction of the part's largest (amplitude) is neutral",
           unit(0.0));
  }
  return p;
}

WhirlClassification::WhirlClassification(const Teuchos::ParameterList& params) {
  Teuchos::ParameterList p(params);
  validateOptions(p, *getValidParameters(), "WhirlClassification");
  clusterTolerance_ = p.get<double>("Cluster Tolerance");
  transverseShare_ = p.get<double>("Transverse Share");
  circularity_ = p.get<double>("Circularity");
  participation_ = p.get<double>("Participation");
}

std::vector<std::vector<int>> WhirlClassification::clusters(const std::vector<eigen::GyroscopicMode>& modes) const {
  std::vector<int> order(modes.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return modes[a].omega < modes[b].omega; });
  std::vector<std::vector<int>> out;
  for (int i : order) {
    const bool join = !out.empty() && !zeroFrequency(modes[i]) && !zeroFrequency(modes[out.back().back()]) &&
                      modes[i].omega - modes[out.back().back()].omega <= clusterTolerance_ * modes[i].omega;
    if (join) out.back().push_back(i);
    else out.push_back({i});
  }
  return out;
}

Whirl WhirlClassification::classifyCluster(const std::vector<int>& members, const std::vector<Orbit>& orbits,
                                           double largest, const Teuchos::Comm<int>* comm, std::pair<double, double>* circularities) const {
  const int k = static_cast<int>(members.size());
  // The three k x k Hermitian forms, summed over this rank's points, then
  // over ranks (one reduction: real and imaginary parts of C, P, N).
  std::vector<double> local(6 * k * k, 0.0), global(local.size(), 0.0);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      const Orbit &a = orbits[members[i]], &b = orbits[members[j]];
      std::complex<double> c = 0.0, p = 0.0, t = 0.0;
      for (std::size_t s = 0; s < a.a1.size(); ++s) {
        c += (std::conj(a.a2[s]) * b.a1[s] - std::conj(a.a1[s]) * b.a2[s]) / std::complex<double>(0.0, 2.0);
        p += std::conj(a.a1[s]) * b.a1[s] + std::conj(a.a2[s]) * b.a2[s];
        t += std::conj(a.a3[s]) * b.a3[s];
      }
      const int e = 6 * (i + k * j);
      local[e] = c.real(), local[e + 1] = c.imag(), local[e + 2] = p.real(), local[e + 3] = p.imag();
      local[e + 4] = p.real() + t.real(), local[e + 5] = p.imag() + t.imag();
    }
  if (comm) Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
  else global = local;
  std::vector<std::complex<double>> C(k * k), P(k * k), N(k * k);
  for (int e = 0; e < k * k; ++e) {
    C[e] = {2.0 * global[6 * e], 2.0 * global[6 * e + 1]};  // 2C: circularity in [-1, 1] against N
    P[e] = {global[6 * e + 2], global[6 * e + 3]};
    N[e] = {global[6 * e + 4], global[6 * e + 5]};
  }
  const int n = 2 * k;
  std::vector<double> Nv = detail::hermitianEmbedding(N, k);
  const std::vector<double> d = detail::symmetricEigen(Nv, n, "WhirlClassification");
  // The part does not take part: its orbit would be rounding.
  if (!(d.back() > participation_ * participation_ * largest)) return Whirl::Neutral;
  const auto share = pencilEigenvalues(detail::hermitianEmbedding(P, k), Nv, d, n);
  const auto circ = pencilEigenvalues(detail::hermitianEmbedding(C, k), Nv, d, n);
  const double maxShare = share.empty() ? 0.0 : share.back();
  if (!(maxShare > transverseShare_)) return Whirl::Neutral;
  const double tau = circularity_ * maxShare;
  // The least and the most forward circularity, per unit transverse motion.
  if (circularities && !circ.empty())
    *circularities = {circ.front() / std::max(maxShare, 1e-300), circ.back() / std::max(maxShare, 1e-300)};
  const bool forward = !circ.empty() && circ.back() > tau, backward = !circ.empty() && circ.front() < -tau;
  if (forward && backward) return Whirl::Unresolved;
  if (forward) return Whirl::Forward;
  if (backward) return Whirl::Backward;
  return Whirl::Neutral;
}

std::vector<Whirl> WhirlClassification::classify(const std::vector<eigen::GyroscopicMode>& modes,
                                                 const std::vector<Orbit>& orbits, double spinSign,
                                                 const Teuchos::Comm<int>* comm, std::vector<double>* forwardShare) const {
  CMS_INPUT_CHECK(orbits.size() != modes.size(),
                  "WhirlClassification: " << orbits.size() << " orbits for " << modes.size() << " modes");
  for (const auto& o : orbits)
    CMS_INPUT_CHECK(o.a1.size() != orbits.front().a1.size() || o.a2.size() != o.a1.size() || o.a3.size() != o.a1.size(),
                    "WhirlClassification: orbits sampled at different points");
  // The part's largest motion in these modes (each M-normalised): the scale
  // below which its motion in a mode is rounding.
  std::vector<double> local(modes.size(), 0.0), motion(modes.size(), 0.0);
  for (std::size_t m = 0; m < modes.size(); ++m)
    for (std::size_t s = 0; s < orbits[m].a1.size(); ++s)
      local[m] += std::norm(orbits[m].a1[s]) + std::norm(orbits[m].a2[s]) + std::norm(orbits[m].a3[s]);
  if (comm && !local.empty())
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), motion.data());
  else
    motion = local;
  const double largest = motion.empty() ? 0.0 : *std::max_element(motion.begin(), motion.end());
  std::vector<Whirl> out(modes.size(), Whirl::Neutral);
  if (forwardShare) forwardShare->assign(modes.size(), 0.0);
  for (const auto& cl : clusters(modes)) {
    if (zeroFrequency(modes[cl.front()])) continue;       // no orbit: neutral
    // The cluster's least and most circularities about n.
    std::pair<double, double> circ{0.0, 0.0};
    Whirl w = classifyCluster(cl, orbits, largest, comm, &circ);  // collective: every rank, every cluster
    if (forwardShare) {
      // With the spin: about n, or about -n for a negative spin (the most
      // forward about -n is minus the least about n).
      const double c = spinSign < 0.0 ? -circ.first : circ.second;
      const double share = w == Whirl::Neutral ? 0.0 : std::clamp(0.5 * (1.0 + c), 0.0, 1.0);
      for (int i : cl) (*forwardShare)[i] = share;
    }
    if (spinSign == 0.0 && w != Whirl::Neutral) w = Whirl::Unresolved;
    if (spinSign < 0.0 && w == Whirl::Forward) w = Whirl::Backward;
    else if (spinSign < 0.0 && w == Whirl::Backward) w = Whirl::Forward;
    for (int i : cl) out[i] = w;
  }
  return out;
}

std::vector<Whirl> WhirlClassification::classify(const synthesis::AssembledStructure& structure,
                                                 const synthesis::SynthesizedStructure& reduced,
                                                 const synthesis::StructureModes& modes, std::size_t k,
                                                 double spinRate, std::vector<double>* forwardShare) const {
  std::vector<Orbit> orbits;
  for (std::size_t m = 0; m < modes.result.modes.size(); ++m)
    orbits.push_back(orbitOfSubstructure(structure, reduced.expand(modes, static_cast<int>(m)), k,
                                         modes.result.modes[m]));
  const double sign = spinRate > 0.0 ? 1.0 : spinRate < 0.0 ? -1.0 : 0.0;
  return classify(modes.result.modes, orbits, sign, structure.comm().get(), forwardShare);
}

}  // namespace cms::analysis
