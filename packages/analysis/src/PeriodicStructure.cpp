#include "cms/analysis/PeriodicStructure.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>
#include <array>
#include <sstream>

#include <Teuchos_LAPACK.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>

#include "cms/analysis/MultiBladeCoordinates.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/ParameterReading.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/fem/RigidPlacement.hpp"

namespace cms::analysis {

namespace {
/// x to 3 significant digits: std::to_string's six fixed decimals printed
/// a 1.4e-12 tolerance as 0.000000 (found by a review).
std::string shortNumber(double x) {
  std::ostringstream os;
  os << std::setprecision(3) << x;
  return os.str();
}

const double kEps = std::numeric_limits<double>::epsilon();

/// X^T A Y.
DenseMatrix congruence(const DenseMatrix& X, const DenseMatrix& A, const DenseMatrix& Y) {
  DenseMatrix AY(A.numRows(), Y.numCols()), out(X.numCols(), Y.numCols());
  gemm(false, false, 1.0, A, Y, 0.0, AY);
  gemm(true, false, 1.0, X, AY, 0.0, out);
  return out;
}

DenseMatrix sum(const DenseMatrix& A, const DenseMatrix& B) {
  if (B.numRows() == 0) return A;
  DenseMatrix C(A);
  C += B;
  return C;
}

/// The rotation by psi about the unit axis a, and its psi-derivatives:
/// dR/dpsi = [a x] R, d2R/dpsi2 = [a x]^2 R.
std::array<std::array<double, 3>, 3> turn(const fem::Vec3& a, double psi, int r) {
  auto R = fem::Rotation::about(a, psi).R;
  const double S[3][3] = {{0, -a[2], a[1]}, {a[2], 0, -a[0]}, {-a[1], a[0], 0}};
  for (int k = 0; k < r; ++k) {
    std::array<std::array<double, 3>, 3> SR{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int l = 0; l < 3; ++l) SR[i][j] += S[i][l] * R[l][j];
    R = SR;
  }
  return R;
}

double relativeDifference(const DenseMatrix& A, const DenseMatrix& B) {
  DenseMatrix D(A);
  D -= B;
  return frobeniusNorm(D) / std::max(frobeniusNorm(A), std::numeric_limits<double>::min());
}

/// The stability of each mode of an undamped (Hamiltonian) fixed-frame
/// system judged on the mode's own scale: s_m = sqrt(|q|^T |K| |q| / q^H M q)
/// + |q|^T |G| |q| / q^H M q. The eigen layer judges dggev's modes on the
/// system's scale, which a finite-element model's stiff modes (1e4 rad/s)
/// inflate until a flutter of 10% growth at 0.6 rad/s reads "neutral". A
/// Krein collision is a double eigenvalue: rounding splits it by at most
/// 10 sqrt(max(eta, eps)) s_m (theory §16.8), so a growth above that is a
/// flutter; below it the mode is stable to rounding.
void classifyOnOwnScales(const eigen::GyroscopicSystem& sys, std::vector<eigen::GyroscopicMode>& modes) {
  const int n = sys.size();
  for (auto& m : modes) {
    double qMq = 0, qKq = 0, qGq = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double a = std::abs(m.q[static_cast<std::size_t>(i)]) * std::abs(m.q[static_cast<std::size_t>(j)]);
        qKq += a * std::abs(sys.K(i, j));
        qGq += a * std::abs(sys.G(i, j));
        qMq += (std::conj(m.q[static_cast<std::size_t>(i)]) * sys.M(i, j) * m.q[static_cast<std::size_t>(j)]).real();
      }
    const double scale = std::sqrt(qKq / qMq) + qGq / qMq;
    const double radius = 10.0 * std::sqrt(std::max(m.residual, kEps)) * scale;
    m.scale = scale;
    if (std::abs(m.lambda) <= radius) m.stability = eigen::Stability::RigidBody;
    else if (m.growthRate > radius) m.stability = m.omega > radius ? eigen::Stability::Flutter : eigen::Stability::Divergence;
    else m.stability = eigen::Stability::Stable;
    eigen::zeroRigidDamping(m);
  }
}

}  // namespace

Teuchos::RCP<const Teuchos::ParameterList> PeriodicStructure::validParameters() {
  auto p = Teuchos::rcp(new Teuchos::ParameterList("Periodic Structure"));
  p->set("Method", "Auto",
         "Auto (multi-blade when constant to rounding, else Floquet), Multi-Blade or Floquet (theory 16.8)",
         Teuchos::rcp(new Teuchos::StringValidator(Teuchos::tuple<std::string>("Auto", "Multi-Blade", "Floquet"))));
  p->set("Check With Floquet", false, "on the multi-blade path, also run Floquet and report the difference");
  p->sublist("Floquet").setParameters(*FloquetAnalysis::getValidParameters());
  return p;
}

PeriodicStructure::PeriodicStructure(const synthesis::SynthesizedStructure& structure, std::vector<double> speeds)
    : structure_(structure), speeds_(std::move(speeds)) {
  const auto& hubs = structure.movingHubs();
  CMS_INPUT_CHECK(hubs.size() != 1, "periodic structure: " << hubs.size()
                                                           << " rotors on moving attachments (exactly one is supported)");
  hub_ = hubs.front();
  CMS_INPUT_CHECK(hub_.speedParameter < 0 || hub_.speedParameter >= static_cast<int>(speeds_.size()),
                  "periodic structure: no speed for the hub");
  omega_ = speeds_[hub_.speedParameter];
  system_ = structure.denseSystem(speeds_);
  ne_ = system_.size();
  n_ = ne_ - 6;
  // The blades: the copies of one item below the hub, in copy order, each
  // with its copied descendants (theory §15.1); N >= 3 for the transform.
  const auto& a = structure.reductions();
  const auto& offsets = structure.coordinateOffsets();
  std::map<std::string, std::vector<std::vector<std::size_t>>> groups;  // item -> copy -> parts
  std::size_t nparts = a.size();
  std::vector<bool> belowHub(nparts, false);
  // Parts are in pre-order: a part is below the hub when its parent is (or is the hub).
  std::vector<int> parentOf(nparts, -1);
  {
    std::map<std::string, std::size_t> index;
    for (std::size_t k = 0; k < nparts; ++k) index[a[k].name] = k;
    for (std::size_t k = 0; k < nparts; ++k) {
      const auto& spec = structure.assembled().substructure(k);
      if (!spec.parent.empty()) parentOf[k] = static_cast<int>(index.at(spec.parent));
    }
  }
  for (std::size_t k = 0; k < nparts; ++k)
    belowHub[k] = k == hub_.part || (parentOf[k] >= 0 && belowHub[static_cast<std::size_t>(parentOf[k])]);
  std::string item;
  for (std::size_t k = 0; k < nparts; ++k) {
    const auto& spec = structure.assembled().substructure(k);
    if (!belowHub[k] || k == hub_.part || !spec.copy) continue;
    // The copy's top item: the first copied ancestor-or-self below the hub.
    std::size_t top = k;
    while (parentOf[top] >= 0 && structure.assembled().substructure(static_cast<std::size_t>(parentOf[top])).copy)
      top = static_cast<std::size_t>(parentOf[top]);
    const auto& c = *structure.assembled().substructure(top).copy;
    auto& g = groups[c.group];
    if (g.empty()) g.resize(static_cast<std::size_t>(c.count));
    g[static_cast<std::size_t>(c.index)].push_back(k);
  }
  std::vector<bool> inBlade(static_cast<std::size_t>(ne_), false);
  std::vector<int> bladeCoords;
  // Full copies: a coordinate's node and component, to turn each blade's
  // rows into its own axes (local_).
  std::vector<std::array<long long, 3>> fullRow(static_cast<std::size_t>(ne_), {-1, -1, -1});  // part, node, comp
  if (groups.size() == 1 && groups.begin()->second.size() >= 3) {
    const auto& g = groups.begin()->second;
    for (std::size_t j = 0; j < g.size(); ++j) {
      int count = 0;
      for (std::size_t k : g[j]) {
        const auto* sub = structure.assembled().assembled(k);
        std::vector<long long> free;
        if (a[k].basis == "Full" && sub) {
          const auto held = structure.assembled().heldRows(k);
          for (long long row = 0; row < sub->dofs().rows(); ++row)
            if (!std::binary_search(held.begin(), held.end(), row)) free.push_back(row);
        }
        const auto nodeOf = sub ? sub->dofs().rowNodes() : std::vector<std::int64_t>();
        for (int i = 0; i < a[k].coordinates; ++i) {
          bladeCoords.push_back(static_cast<int>(offsets[k]) + i);
          inBlade[static_cast<std::size_t>(offsets[k] + i)] = true;
          if (!free.empty())
            fullRow[static_cast<std::size_t>(offsets[k] + i)] = {
                static_cast<long long>(k), nodeOf[static_cast<std::size_t>(free[i])],
                static_cast<long long>(sub->dofs().components[static_cast<std::size_t>(free[i])])};
        }
        count += a[k].coordinates;
      }
      if (j == 0) perBlade_ = count;
      CMS_INPUT_CHECK(count != perBlade_, "periodic structure: blade copy " << j + 1 << " has " << count
                                                                            << " coordinates, the first " << perBlade_);
    }
    blades_ = perBlade_ > 0 ? static_cast<int>(g.size()) : 0;
  }
  // (It said "no copied blades below the hub" of two copied blades: found
  // by a review.)
  if (groups.empty()) noBlades_ = "no copied blades below the hub";
  else if (groups.size() > 1) noBlades_ = std::to_string(groups.size()) + " copied families below the hub (the transform takes one)";
  else if (groups.begin()->second.size() < 3)
    noBlades_ = std::to_string(groups.begin()->second.size()) + " copied blades below the hub (the transform needs 3 or more)";
  else if (blades_ == 0) noBlades_ = "copied blades with no coordinates of their own";
  // Fixed coordinates first (everything but b and the blades), then the blades.
  for (int i = 0; i < ne_; ++i)
    if (!(i >= hub_.offset && i < hub_.offset + 6) && (blades_ == 0 || !inBlade[static_cast<std::size_t>(i)]))
      order_.push_back(i);
  if (blades_ > 0) order_.insert(order_.end(), bladeCoords.begin(), bladeCoords.end());
  CMS_INPUT_CHECK(static_cast<int>(order_.size()) != n_, "periodic structure: coordinate bookkeeping failed");
  // A Full hub's own coordinates are its nodes' components in the rotating
  // axes: written as fixed-axis components, u_rot = R^T u_fixed node by
  // node (a time-dependent change like b's), an axisymmetric hub has
  // constant coefficients (theory §16.8). Reduced hubs keep their Ritz
  // coordinates (rotating: periodic, Floquet).
  if (a[hub_.part].basis == "Full") {
    const auto* sub = structure.assembled().assembled(hub_.part);
    const auto held = structure.assembled().heldRows(hub_.part);
    std::vector<long long> free;
    for (long long row = 0; row < sub->dofs().rows(); ++row)
      if (!std::binary_search(held.begin(), held.end(), row)) free.push_back(row);
    const auto nodeOf = sub->dofs().rowNodes();
    std::vector<int> position(static_cast<std::size_t>(ne_), -1);
    for (int i = 0; i < n_; ++i) position[static_cast<std::size_t>(order_[i])] = i;
    std::map<std::pair<long long, int>, int> where;  // (node, component) -> permuted index
    for (int i = 0; i < a[hub_.part].coordinates; ++i) {
      const auto row = static_cast<std::size_t>(free[static_cast<std::size_t>(i)]);
      const int c = static_cast<int>(sub->dofs().components[row]);
      const int p = position[static_cast<std::size_t>(offsets[hub_.part] + i)];
      hubRows_.push_back({p, static_cast<int>(nodeOf[row]), c});
      where[{nodeOf[row], c}] = p;
    }
    for (auto& h : hubRows_) {
      const int base = h[2] < 3 ? 0 : 3;
      for (int e = 0; e < 3; ++e) {
        const auto it = where.find({h[1], base + e});
        hubPartner_.push_back(it == where.end() ? -1 : it->second);
      }
    }
  }
  // q = L xi: a Full copy's rows are its nodes' components in the structure's
  // axes; turned back by the copy's angle they are the first copy's, so the
  // blades' coordinates transform alike (what the multi-blade transform needs).
  local_.shape(n_, n_);
  std::map<std::array<long long, 3>, int> where;  // (part, node, comp) -> permuted index
  for (int i = 0; i < n_; ++i) {
    const auto& f = fullRow[static_cast<std::size_t>(order_[i])];
    if (f[0] >= 0) where[f] = i;
  }
  for (int i = 0; i < n_; ++i) {
    const auto& f = fullRow[static_cast<std::size_t>(order_[i])];
    if (f[0] < 0) {
      local_(i, i) = 1.0;
      continue;
    }
    const auto& spec = structure.assembled().substructure(static_cast<std::size_t>(f[0]));
    double first = spec.copy->angle - 2.0 * M_PI * spec.copy->index / spec.copy->count;
    const auto R = fem::Rotation::about(spec.copy->axis, spec.copy->angle - first).R;
    const int c = static_cast<int>(f[2]), base = c < 3 ? 0 : 3;
    for (int e = 0; e < 3; ++e) {
      const auto it = where.find({f[0], f[1], base + e});
      if (it != where.end()) local_(i, it->second) = R[c - base][e];
    }
  }
}

double PeriodicStructure::period() const { return 2.0 * M_PI / std::abs(omega_); }

DenseMatrix PeriodicStructure::embedding(double psi, int r) const {
  // Z: q_e = Z q, identity on every coordinate but b; b = R6^T A q (§16.8).
  DenseMatrix Z(ne_, n_);
  std::vector<int> position(static_cast<std::size_t>(ne_), -1);
  for (int i = 0; i < n_; ++i) position[static_cast<std::size_t>(order_[i])] = i;
  if (r == 0)
    for (int i = 0; i < n_; ++i) Z(order_[i], i) = 1.0;
  const auto R = turn(hub_.axis, psi, r);  // d^r R / dpsi^r; b rows take its transpose
  for (int blk = 0; blk < 2; ++blk)        // translations, rotations
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double rt = R[j][i];  // (R^T)_ij
        if (rt == 0.0) continue;
        for (auto [g, v] : hub_.parentMotion[static_cast<std::size_t>(3 * blk + j)]) {
          const int col = position[static_cast<std::size_t>(g)];
          if (col >= 0) Z(static_cast<int>(hub_.offset) + 3 * blk + i, col) += rt * v;
        }
      }
  // A Full hub's rows: u_rot(node, c) = sum_e (R^T)_ce u_fixed(node, e).
  for (std::size_t h = 0; h < hubRows_.size(); ++h) {
    const int p = hubRows_[h][0], c = hubRows_[h][2] % 3, row = order_[p];
    for (int j = 0; j < n_; ++j) Z(row, j) = 0.0;
    for (int e = 0; e < 3; ++e)
      if (const int col = hubPartner_[3 * h + static_cast<std::size_t>(e)]; col >= 0) Z(row, col) = R[e][c];
  }
  return Z;
}

SecondOrderMatrices PeriodicStructure::individual(double psi) const {
  // Lagrange's equations under the time-dependent constraint q_e = Z q
  // (theory §16.8): with Z' = dZ/dt = omega Z_psi,
  //   M = Z^T M_e Z,  C = Z^T C_e Z + 2 omega Z^T M_e Z_psi,
  //   K = Z^T K_e Z + omega Z^T C_e Z_psi + omega^2 Z^T M_e Z_psipsi,  C_e = G_e + D_e.
  auto times = [this](const DenseMatrix& A) {
    DenseMatrix B(A.numRows(), local_.numCols());
    gemm(false, false, 1.0, A, local_, 0.0, B);
    return B;
  };
  const DenseMatrix Z = times(embedding(psi, 0)), Z1 = times(embedding(psi, 1)), Z2 = times(embedding(psi, 2));
  const DenseMatrix Ce = sum(system_.G, system_.D);
  DenseMatrix Ke = sum(system_.K, system_.N);
  SecondOrderMatrices s;
  s.M = congruence(Z, system_.M, Z);
  s.D = congruence(Z, Ce, Z);
  DenseMatrix t = congruence(Z, system_.M, Z1);
  t.scale(2.0 * omega_);
  s.D += t;
  s.K = congruence(Z, Ke, Z);
  t = congruence(Z, Ce, Z1);
  t.scale(omega_);
  s.K += t;
  t = congruence(Z, system_.M, Z2);
  t.scale(omega_ * omega_);
  s.K += t;
  return s;
}

double PeriodicStructure::highestFrequency() const {
  // sqrt of the largest eigenvalue of (sym K(0), M(0)) in magnitude, by the
  // symmetric-definite LAPACK solver on the Cholesky-reduced form: an upper
  // bound of the periodic system's fast time scale within the Omega terms.
  const auto s = individual(0.0);
  const int n = n_;
  DenseMatrix A(n, n), B(s.M);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = 0.5 * (s.K(i, j) + s.K(j, i));
  std::vector<double> w(static_cast<std::size_t>(n));
  int info = 0, lwork = -1;
  double query = 0;
  Teuchos::LAPACK<int, double> lapack;
  lapack.SYGV(1, 'N', 'U', n, A.values(), n, B.values(), n, w.data(), &query, lwork, &info);
  lwork = static_cast<int>(query);
  std::vector<double> work(static_cast<std::size_t>(std::max(1, lwork)));
  lapack.SYGV(1, 'N', 'U', n, A.values(), n, B.values(), n, w.data(), work.data(), lwork, &info);
  if (info != 0)
    throw NumericalError("periodic structure: the mass matrix at azimuth 0 is not positive definite (LAPACK dsygv info " +
                         std::to_string(info) + ")");
  double top = 0.0;
  for (double v : w) top = std::max(top, std::abs(v));
  return std::sqrt(top) + std::abs(omega_);
}

std::vector<std::complex<double>> PeriodicStructure::toExtended(const std::vector<std::complex<double>>& q) const {
  DenseMatrix Z(ne_, n_);
  gemm(false, false, 1.0, embedding(0.0, 0), local_, 0.0, Z);
  std::vector<std::complex<double>> qe(static_cast<std::size_t>(ne_), 0.0);
  for (int i = 0; i < ne_; ++i)
    for (int j = 0; j < n_; ++j)
      if (Z(i, j) != 0.0) qe[static_cast<std::size_t>(i)] += Z(i, j) * q[static_cast<std::size_t>(j)];
  std::complex<double> mass = 0.0;
  for (int i = 0; i < ne_; ++i)
    for (int j = 0; j < ne_; ++j) mass += std::conj(qe[i]) * system_.M(i, j) * qe[j];
  const double scale = mass.real() > 0 ? 1.0 / std::sqrt(mass.real()) : 1.0;
  for (auto& v : qe) v *= scale;
  return qe;
}

PeriodicModes PeriodicStructure::solve(int numModes, const Teuchos::ParameterList& options) const {
  Teuchos::ParameterList opts(options);
  validateOptions(opts, *validParameters(), "Periodic Structure");
  const std::string method = opts.get<std::string>("Method");
  PeriodicModes out;
  out.blades = blades_;
  const int fixed = n_ - blades_ * perBlade_;
  // 1. The multi-blade transform and its constancy (theory §16.8).
  std::optional<MultiBladeTransform> mbc;
  if (blades_ >= 3) mbc.emplace(blades_, perBlade_);
  SecondOrderMatrices constant;
  if (mbc) {
    // Blade k of the transform is copy k, at psi + 2 pi k / N from the first.
    constant = mbc->toMultiBlade(individual(0.0), 0.0, omega_, fixed);
    double defect = 0.0;
    for (double f : {0.31, 0.57, 0.83}) {
      const double psi = f * 2.0 * M_PI / blades_;
      const auto other = mbc->toMultiBlade(individual(psi), psi, omega_, fixed);
      defect = std::max({defect, relativeDifference(other.M, constant.M), relativeDifference(other.D, constant.D),
                         relativeDifference(other.K, constant.K)});
    }
    out.constancyDefect = defect;
    // The products Z^T A Z, B^T A B of n x n matrices round at about
    // n eps relative to their norms, twice; a periodic part above that is
    // physics (a flexible hub, dissimilar blades, an anisotropic rotor).
    out.constancyTolerance = 100.0 * n_ * kEps;
  }
  // At rest the constraint b = A q is constant: the system is ordinary.
  const bool atRest = omega_ == 0.0;
  const bool constantForm = atRest || (mbc && out.constancyDefect <= out.constancyTolerance);
  if (atRest) constant = individual(0.0);
  CMS_INPUT_CHECK(method == "Multi-Blade" && !constantForm,
                  "periodic structure: \"Method: Multi-Blade\" needs N >= 3 identical blades (Copies) on a rigid "
                  "hub; "
                      << (mbc ? "the transformed matrices vary by " + shortNumber(out.constancyDefect) +
                                    " over the azimuth (rounding allows " + shortNumber(out.constancyTolerance) + ")"
                              : "there are " + noBlades_));
  const bool useMultiBlade = constantForm && (method != "Floquet" || atRest);
  auto& result = out.modes.result;
  out.modes.speeds = speeds_;
  if (useMultiBlade) {
    std::ostringstream why;
    if (atRest) {
      out.method = "at rest";
      why << "the hub does not turn: constant coefficients";
    } else {
      out.method = "multi-blade";
      why << blades_ << " identical blades: the multi-blade transform is constant to " << out.constancyDefect
          << " (rounding allows " << out.constancyTolerance << "); eigenvalues in the fixed frame";
    }
    out.reason = why.str();
    eigen::GyroscopicSystem sys = gyroscopicSystem(constant);
    const int n = n_;
    // A damping or circulatory part at the rounding of the products (an
    // undamped rotor: B^T K B is symmetric in exact arithmetic) is dropped,
    // so that the conservative paths, accurate for stiff models, apply; a
    // QZ of the first-order form would lose eps (omega_max / omega)^2 on the
    // low modes (theory §16.8).
    const double roundingD = out.constancyTolerance * (frobeniusNorm(constant.D) + 1e-300),
                 roundingK = out.constancyTolerance * frobeniusNorm(constant.K);
    if (frobeniusNorm(sys.D) <= std::max(roundingD, 100.0 * n * kEps * frobeniusNorm(constant.D))) sys.D.shape(0, 0);
    if (frobeniusNorm(sys.N) <= std::max(roundingK, 100.0 * n * kEps * frobeniusNorm(constant.K))) sys.N.shape(0, 0);
    Teuchos::ParameterList dense;
    dense.set("Number of Modes", numModes);
    result = eigen::DenseGyroscopicSolver(dense).solve(sys.symmetrised());
    if (!sys.damped()) classifyOnOwnScales(sys.symmetrised(), result.modes);
    // The shapes at psi = 0: individual q = B(0) z, then q_e.
    const DenseMatrix T = mbc && !atRest ? mbc->matrix(0.0, 0) : DenseMatrix();
    for (auto& m : result.modes) {
      std::vector<std::complex<double>> q(m.q);
      for (int i = 0; i < T.numRows(); ++i) {
        std::complex<double> v = 0.0;
        for (int j = 0; j < blades_ * perBlade_; ++j) v += T(i, j) * m.q[static_cast<std::size_t>(fixed + j)];
        q[static_cast<std::size_t>(fixed + i)] = v;
      }
      m.q = toExtended(q);
    }
    result.reason = out.reason + (result.reason.empty() ? "" : "; " + result.reason);
  }
  // 2. Floquet: the answer when the transform is not constant, or the check.
  if (!atRest && (!useMultiBlade || opts.get<bool>("Check With Floquet"))) {
    const auto system = PeriodicSystem::secondOrder(
        period(), n_, [this](double t) { return individual(omega_ * t); },
        [this, mbc, fixed](double t) {
          if (mbc) return mbc->observation(omega_ * t, fixed);
          DenseMatrix C(fixed, n_);  // the fixed coordinates as they are
          for (int i = 0; i < fixed; ++i) C(i, i) = 1.0;
          return C;
        });
    // The integrator must resolve the model's highest frequency w_max over
    // the period: steps of w_max h <= 1/2 to start. A model that needs more
    // than "Maximum Steps Per Period" is refused (reduce its bases) rather
    // than integrated for hours.
    Teuchos::ParameterList fo = opts.sublist("Floquet");
    fo.validateParametersAndSetDefaults(*FloquetAnalysis::getValidParameters());
    const double wmax = highestFrequency();
    const int maxSteps = fo.get<int>("Maximum Steps Per Period");
    int steps = fo.get<int>("Steps Per Period");
    while (steps < maxSteps && wmax * period() / steps > 0.5) steps *= 2;
    CMS_INPUT_CHECK(wmax * period() / steps > 0.5,
                    "periodic structure: Floquet needs about " << static_cast<long long>(2 * wmax * period())
                        << " steps per revolution to resolve the model's highest frequency (" << wmax
                        << " rad/s), above \"Maximum Steps Per Period\" = " << maxSteps
                        << ": reduce the substructures' bases (fewer vectors) or, with N >= 3 identical blades on a "
                           "rigid hub, use the multi-blade path");
    fo.set("Steps Per Period", steps);
    FloquetAnalysis floquet(fo);
    if (progress_) floquet.setProgress(progress_);
    out.floquet = floquet.analyse(system);
    const auto& fl = out.floquet;
    if (!useMultiBlade) {
      out.method = "Floquet";
      std::ostringstream why;
      if (method == "Floquet") why << "Floquet asked (the multi-blade transform " << (mbc ? "applies" : "does not") << ")";
      else if (mbc) why << "the multi-blade transform varies by " << out.constancyDefect << " over the azimuth";
      else why << noBlades_;
      why << ": monodromy over one revolution, " << fl.steps
          << " Gauss-Legendre steps, error " << fl.monodromyError
          << (fl.converged ? "" : fl.stalled ? " (NOT CONVERGED: the error stopped falling, rounding above the tolerance)"
                                             : " (NOT CONVERGED)");
      out.reason = why.str();
      result.solver = "Floquet (" + fl.integrator + ")";
      result.reason = out.reason;
      result.status = fl.converged ? eigen::SolveStatus::Converged : eigen::SolveStatus::NotConverged;
      // One member of each conjugate pair: frequency >= 0, ascending.
      std::vector<const FloquetMultiplier*> chosen;
      for (const auto& m : fl.multipliers)
        if (m.frequency > 0.0 || (m.frequency == 0.0 && m.multiplier.imag() >= 0.0)) chosen.push_back(&m);
      std::sort(chosen.begin(), chosen.end(),
                [](const FloquetMultiplier* x, const FloquetMultiplier* y) { return x->frequency < y->frequency; });
      // The numModes lowest, and every unstable one past them: the monodromy
      // has them all, and a growing mode beyond the count was dropped with
      // the verdict (one mode asked of a rotor in ground resonance read
      // "stable", exit 0; found by a review).
      for (int i = 0; i < static_cast<int>(chosen.size()); ++i) {
        const auto& f = *chosen[static_cast<std::size_t>(i)];
        eigen::GyroscopicMode m;
        m.lambda = f.fixedFrameExponent();
        m.omega = std::abs(f.frequency);
        m.hz = m.omega / (2 * M_PI);
        m.growthRate = f.growthRate;
        const double mag = std::abs(m.lambda);
        m.dampingRatio = mag > 0 ? -f.growthRate / mag : 0.0;
        m.logDecrement = m.omega > 0 ? -2 * M_PI * f.growthRate / m.omega : 0.0;
        // A multiplier at 1 within its own error is a rigid motion (the
        // multi-blade path says "rigid"; this one said "stable", with a
        // damping ratio of -1 or +1 on the split pair; found by a review).
        m.stability = mag <= f.growthRateError ? eigen::Stability::RigidBody
                      : f.growthRate > f.growthRateError
                          ? (m.omega > 0 ? eigen::Stability::Flutter : eigen::Stability::Divergence)
                          : eigen::Stability::Stable;
        if (i >= numModes && m.stability != eigen::Stability::Flutter && m.stability != eigen::Stability::Divergence)
          continue;
        eigen::zeroRigidDamping(m);
        m.residual = f.residual;
        m.q = toExtended(std::vector<std::complex<double>>(f.eigenvector.begin(), f.eigenvector.begin() + n_));
        result.modes.push_back(m);
      }
      result.numRequested = numModes;
    } else {
      // The check: each multi-blade eigenvalue against the nearest Floquet exponent.
      double worst = 0.0;
      for (const auto& m : result.modes) {
        double best = std::numeric_limits<double>::infinity();
        for (const auto& f : fl.multipliers) best = std::min(best, std::abs(f.fixedFrameExponent() - m.lambda));
        worst = std::max(worst, best);
      }
      out.floquetDifference = worst / std::abs(omega_);
    }
  }
  out.modes.path = out.method + ": " + out.reason;
  return out;
}

}  // namespace cms::analysis
