#include "cms/analysis/CampbellStudy.hpp"
#include "cms/analysis/PeriodicStructure.hpp"
#include "cms/core/CsvField.hpp"
#include "cms/core/SparseInertia.hpp"
#include "cms/core/SparseProduct.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <ostream>
#include <sstream>
#include <tuple>

#include <Teuchos_Array.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/Error.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/SturmCount.hpp"

namespace cms::analysis {

// ---------------------------------------------------------------- problems

eigen::GyroscopicSystem SpeedDependentSystem::at(double Omega) const {
  eigen::GyroscopicSystem s;
  s.M = M;
  s.G = G1;
  s.G.scale(Omega);
  s.K = K0;
  s.D = D;
  if (K2.numRows() > 0) {
    CMS_INPUT_CHECK(K2.numRows() != K0.numRows() || K2.numCols() != K0.numCols(),
                    "SpeedDependentSystem: K2 is " << K2.numRows() << "x" << K2.numCols() << " but K0 is "
                                                   << K0.numRows() << "x" << K0.numCols());
    for (int j = 0; j < K0.numCols(); ++j)
      for (int i = 0; i < K0.numRows(); ++i) s.K(i, j) += Omega * Omega * K2(i, j);
  }
  return s;
}


StiffnessCount DenseSweepProblem::stiffnessCount(const std::vector<double>& speeds) const {
  CMS_INPUT_CHECK(speeds.size() != 1 || !std::isfinite(speeds[0]),
                  "DenseSweepProblem: one finite speed expected, got " << speeds.size());
  return denseStiffnessCount(system_.at(speeds[0]).K);
}

DenseSweepProblem::DenseSweepProblem(SpeedDependentSystem system, std::string name, double nominal,
                                     const Teuchos::ParameterList& solverParams)
    : system_(std::move(system)), name_(std::move(name)), nominal_(nominal), solverParams_(solverParams) {
  eigen::DenseGyroscopicSolver check(solverParams_);  // InputError now for bad parameters
  (void)check;
}

synthesis::StructureModes DenseSweepProblem::solve(const std::vector<double>& speeds) const {
  CMS_INPUT_CHECK(speeds.size() != 1 || !std::isfinite(speeds[0]),
                  "DenseSweepProblem: one finite speed expected, got " << speeds.size());
  synthesis::StructureModes m;
  m.result = eigen::DenseGyroscopicSolver(solverParams_).solve(system_.at(speeds[0]));
  m.path = "dense";
  m.speeds = speeds;
  return m;
}

std::vector<std::vector<double>> DenseSweepProblem::mac(const std::vector<eigen::GyroscopicMode>& a,
                                                        const std::vector<eigen::GyroscopicMode>& b) const {
  const int n = system_.M.numRows();
  auto Mx = [&](const std::vector<std::complex<double>>& x) {
    std::vector<std::complex<double>> y(n, 0.0);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) y[i] += system_.M(i, j) * x[j];
    return y;
  };
  auto dot = [&](const std::vector<std::complex<double>>& x, const std::vector<std::complex<double>>& y) {
    std::complex<double> s = 0.0;
    for (int i = 0; i < n; ++i) s += std::conj(x[i]) * y[i];
    return s;
  };
  std::vector<std::vector<std::complex<double>>> Mb;
  std::vector<double> bb;
  for (const auto& m : b) Mb.push_back(Mx(m.q)), bb.push_back(dot(m.q, Mb.back()).real());
  std::vector<std::vector<double>> out(a.size(), std::vector<double>(b.size(), 0.0));
  for (std::size_t t = 0; t < a.size(); ++t) {
    const double aa = dot(a[t].q, Mx(a[t].q)).real();
    for (std::size_t j = 0; j < b.size(); ++j)
      out[t][j] = aa > 0 && bb[j] > 0 ? std::norm(dot(a[t].q, Mb[j])) / (aa * bb[j]) : 0.0;
  }
  return out;
}

std::vector<Whirl> DenseSweepProblem::whirl(const synthesis::StructureModes& modes, const WhirlClassification& rule) const {
  std::vector<double> unused;
  return whirlAndForwardShare(modes, rule, unused);
}

std::vector<Whirl> DenseSweepProblem::whirlAndForwardShare(const synthesis::StructureModes& modes,
                                                           const WhirlClassification& rule,
                                                           std::vector<double>& forwardShare) const {
  std::vector<Orbit> orbits;
  for (const auto& m : modes.result.modes) orbits.push_back(orbitOfPairs(m, system_.whirlPairs));
  forwardShare.assign(orbits.size(), -1.0);
  if (system_.whirlPairs.empty()) return std::vector<Whirl>(orbits.size(), Whirl::Neutral);
  const double s = modes.speeds.empty() ? 0.0 : modes.speeds[0];
  return rule.classify(modes.result.modes, orbits, s > 0 ? 1.0 : s < 0 ? -1.0 : 0.0, nullptr, &forwardShare);
}

namespace {
/// Substructure k's parent's index (-1 for C).
int parentOf(const synthesis::AssembledStructure& structure, int k) {
  const std::string& name = structure.substructure(static_cast<std::size_t>(k)).parent;
  for (std::size_t q = 0; q < structure.numSubstructures(); ++q)
    if (structure.substructure(q).name == name) return static_cast<int>(q);
  return -1;
}
}  // namespace

SynthesizedSweepProblem::SynthesizedSweepProblem(const synthesis::AssembledStructure& structure,
                                                 const synthesis::SynthesizedStructure& reduced,
                                                 const Teuchos::ParameterList& solveParams, const std::string& whirlOf)
    : structure_(structure), reduced_(reduced), solveParams_(solveParams) {
  M_ = reduced_.system(std::vector<double>(reduced_.speeds().size(), 0.0)).M;  // the same at every speed
  // `whirlOf` when it is a spinning A or R, else the first spinning A or R.
  for (const bool named : {true, false})
    for (std::size_t k = 0; k < structure_.numSubstructures() && whirlPart_ < 0; ++k) {
      const auto& s = structure_.substructure(k);
      if (s.kind != synthesis::SubstructureKind::Central && s.spin && (!named || s.name == whirlOf))
        whirlPart_ = static_cast<int>(k);
    }
  // Its spin rate is the speed parameter it declares, or its parent's.
  for (int k = whirlPart_; k >= 0 && whirlSpeed_ < 0;) {
    const auto& name = structure_.substructure(static_cast<std::size_t>(k)).name;
    for (std::size_t p = 0; p < reduced_.speeds().size(); ++p)
      if (reduced_.speeds()[p].name == name) whirlSpeed_ = static_cast<int>(p);
    k = parentOf(structure_, k);
  }
}

std::string SynthesizedSweepProblem::whirlOf() const {
  return whirlPart_ < 0 ? "" : structure_.substructure(static_cast<std::size_t>(whirlPart_)).name;
}

bool SynthesizedSweepProblem::whirlInRotorFrame(int reference) const {
  if (whirlPart_ < 0) return false;
  const auto rotatingA = [](const synthesis::SubstructureSpec& s) {
    return s.kind == synthesis::SubstructureKind::Rotating && s.spin &&
           s.spin->frame == fem::SpinDefinition::Frame::Rotating;
  };
  if (rotatingA(structure_.substructure(static_cast<std::size_t>(whirlPart_)))) return true;
  // An R, an E or a stationary-frame A moves in its parent's frame (an E's
  // parent's in turn). Where that frame spins (a spinning C, a
  // rotating-frame A), the part's unbalance turns in it at the part's own
  // rate: a 1X force of the reference only when the reference is that
  // rate. Before, only an A's own frame was recognised, and a disc on a
  // spinning C shaft, swept by the shaft's rate, had "forward: unbalance
  // excites it" at the 1X crossing of a rotating-frame frequency (found by
  // a review).
  for (int k = whirlPart_;;) {
    const int parent = parentOf(structure_, k);
    if (parent < 0) return false;
    const auto& p = structure_.substructure(static_cast<std::size_t>(parent));
    if ((p.kind == synthesis::SubstructureKind::Central && p.spin) || rotatingA(p)) return whirlSpeed_ != reference;
    if (p.kind == synthesis::SubstructureKind::Central) return false;
    k = parent;
  }
}

synthesis::StructureModes SynthesizedSweepProblem::solve(const std::vector<double>& speeds) const {
  // A rotor on a moving attachment: its fixed-frame modes (theory §16.8).
  if (!reduced_.movingHubs().empty())
    return PeriodicStructure(reduced_, speeds)
        .solve(solveParams_.isParameter("Number of Modes") ? solveParams_.get<int>("Number of Modes") : 10)
        .modes;
  return reduced_.solve(speeds, solveParams_);
}

StiffnessCount SynthesizedSweepProblem::stiffnessCount(const std::vector<double>& speeds) const {
  // A free body's K is singular at every speed (its rigid motions), and
  // spinning, indefinite from the first speed on: not sought.
  StiffnessCount out;
  if (structure_.freeFloating()) {
    out.available = false;
    out.why = "a free body's stiffness is singular at every speed";
    return out;
  }
  if (!reduced_.movingHubs().empty()) {
    out.available = false;
    out.why = "a rotor on a moving hub (periodic, theory 16.8)";
    return out;
  }
  return analysis::stiffnessCount(reduced_, speeds,
                                  solveParams_.isParameter("Dense Limit") ? solveParams_.get<int>("Dense Limit") : 1500);
}

std::vector<synthesis::StructureModes> SynthesizedSweepProblem::solveAll(const std::vector<std::vector<double>>& speeds,
                                                                         int threads) const {
  if (!reduced_.movingHubs().empty()) return SpeedSweepProblem::solveAll(speeds, threads);
  return reduced_.solveMany(speeds, solveParams_, threads);
}

std::vector<std::string> SynthesizedSweepProblem::dominant(const synthesis::StructureModes& modes) const {
  // Parts whose shares agree with the largest to three digits are named
  // together: identical parts in a symmetric mode ("boom+ & boom-"), where
  // which of them is largest is rounding.
  const double sameShare = 1e-3;
  std::vector<std::string> names;
  for (const auto& c : reduced_.characterise(modes)) {
    const double top = c.kineticShare.empty() ? 0.0 : *std::max_element(c.kineticShare.begin(), c.kineticShare.end());
    std::string name;
    for (std::size_t k = 0; k < c.kineticShare.size(); ++k)
      if (c.kineticShare[k] >= (1.0 - sameShare) * top)
        name += (name.empty() ? "" : " & ") + structure_.substructure(k).name;
    names.push_back(name);
  }
  return names;
}

std::vector<std::vector<double>> SynthesizedSweepProblem::mac(const std::vector<eigen::GyroscopicMode>& a,
                                                              const std::vector<eigen::GyroscopicMode>& b) const {
  return macMatrix(*M_, reduced_.size(), a, b);
}

std::vector<Whirl> SynthesizedSweepProblem::whirl(const synthesis::StructureModes& modes,
                                                  const WhirlClassification& rule) const {
  std::vector<double> unused;
  return whirlAndForwardShare(modes, rule, unused);
}

std::vector<Whirl> SynthesizedSweepProblem::whirlAndForwardShare(const synthesis::StructureModes& modes,
                                                                 const WhirlClassification& rule,
                                                                 std::vector<double>& forwardShare) const {
  forwardShare.assign(modes.result.modes.size(), -1.0);
  // No whirl label for the fixed-frame modes of a periodic rotor: their
  // shapes are a snapshot at azimuth 0, not an orbit in the rotor's frame.
  if (whirlPart_ < 0 || !reduced_.movingHubs().empty())
    return std::vector<Whirl>(modes.result.modes.size(), Whirl::Neutral);
  const double rate = whirlSpeed_ >= 0 && whirlSpeed_ < static_cast<int>(modes.speeds.size())
                          ? modes.speeds[static_cast<std::size_t>(whirlSpeed_)]
                          : structure_.substructure(static_cast<std::size_t>(whirlPart_)).spin->rate;
  return rule.classify(structure_, reduced_, modes, static_cast<std::size_t>(whirlPart_), rate, &forwardShare);
}

std::vector<std::vector<double>> macMatrix(const CrsMatrix& M, long long n, const std::vector<eigen::GyroscopicMode>& a,
                                           const std::vector<eigen::GyroscopicMode>& b) {
  const auto map = M.getRowMap();
  const std::size_t nloc = map->getNodeNumElements(), P = a.size(), C = b.size();
  auto pack = [&](const std::vector<eigen::GyroscopicMode>& modes) {
    MultiVector X(map, std::max<std::size_t>(2 * modes.size(), 1));
    for (std::size_t j = 0; j < modes.size(); ++j) {
      const bool replicated = static_cast<long long>(modes[j].q.size()) == n;
      auto re = X.getDataNonConst(2 * j), im = X.getDataNonConst(2 * j + 1);
      for (std::size_t l = 0; l < nloc; ++l) {
        const std::size_t i =
            replicated ? static_cast<std::size_t>(map->getGlobalElement(static_cast<LocalOrdinal>(l))) : l;
        re[l] = modes[j].q[i].real(), im[l] = modes[j].q[i].imag();
      }
    }
    return X;
  };
  const MultiVector Xa = pack(a), Xb = pack(b);
  MultiVector MXa(map, Xa.getNumVectors()), MXb(map, Xb.getNumVectors());
  multiply(M, Xa, MXa);
  multiply(M, Xb, MXb);
  // Local sums: per pair (re, im) of a^H M b, then a^H M a, then b^H M b; one reduction.
  std::vector<double> local(2 * P * C + P + C, 0.0), global(local.size(), 0.0);
  for (std::size_t t = 0; t < P; ++t) {
    const auto ar = Xa.getData(2 * t), ai = Xa.getData(2 * t + 1);
    const auto Mar = MXa.getData(2 * t), Mai = MXa.getData(2 * t + 1);
    for (std::size_t l = 0; l < nloc; ++l) local[2 * P * C + t] += ar[l] * Mar[l] + ai[l] * Mai[l];
    for (std::size_t j = 0; j < C; ++j) {
      const auto Mbr = MXb.getData(2 * j), Mbi = MXb.getData(2 * j + 1);
      double re = 0, im = 0;
      // a^H M b = (ar.M br + ai.M bi) + i (ar.M bi - ai.M br)
      for (std::size_t l = 0; l < nloc; ++l) re += ar[l] * Mbr[l] + ai[l] * Mbi[l], im += ar[l] * Mbi[l] - ai[l] * Mbr[l];
      local[2 * (t * C + j)] = re, local[2 * (t * C + j) + 1] = im;
    }
  }
  for (std::size_t j = 0; j < C; ++j) {
    const auto br = Xb.getData(2 * j), bi = Xb.getData(2 * j + 1);
    const auto Mbr = MXb.getData(2 * j), Mbi = MXb.getData(2 * j + 1);
    for (std::size_t l = 0; l < nloc; ++l) local[2 * P * C + P + j] += br[l] * Mbr[l] + bi[l] * Mbi[l];
  }
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
  std::vector<std::vector<double>> mac(P, std::vector<double>(C, 0.0));
  for (std::size_t t = 0; t < P; ++t)
    for (std::size_t j = 0; j < C; ++j) {
      const double aa = global[2 * P * C + t], bb = global[2 * P * C + P + j];
      const double re = global[2 * (t * C + j)], im = global[2 * (t * C + j) + 1];
      mac[t][j] = aa > 0 && bb > 0 ? (re * re + im * im) / (aa * bb) : 0.0;
    }
  return mac;
}

// ---------------------------------------------------------------- the study

Teuchos::RCP<const Teuchos::ParameterList> CampbellStudy::getValidParameters() {
  static Teuchos::RCP<Teuchos::ParameterList> p;
  if (p.is_null()) {
    using Teuchos::rcp;
    p = rcp(new Teuchos::ParameterList("Campbell"));
    p->set("Steps", 21, "speeds in the sweep, from factor 0 to Max Factor (>= 2)",
           rcp(new Teuchos::EnhancedNumberValidator<int>(2, 100000)));
    p->set("Max Factor", 2.0, "top speed as a multiple of the nominal rates (> 0)",
           rcp(new Teuchos::EnhancedNumberValidator<double>(1e-300, 1e300)));
    p->set("Speed Factor", 1.0, "the nominal rates are multiplied by this first (a scene's Speed Factor)");
    p->set("Speed Parameter", std::string(),
           "the one speed parameter swept (others held at nominal); empty: all swept together, the first the reference");
    p->set("Engine Orders", Teuchos::Array<double>(1, 1.0), "engine orders: lines omega = order * reference rate");
    p->set("Refine Crossings", true, "bisect each engine-order crossing (one solve per halving)");
    p->set("Crossing Tolerance", 1e-6, "relative width of the speed bracket that ends a bisection",
           rcp(new Teuchos::EnhancedNumberValidator<double>(1e-14, 1.0)));
    p->set("Frame Rate Tolerance", 1e-3,
           "relative difference within which a track's frequency equals a spin rate (frame-rate rigid motion), "
           "added to the mode's split radius (the rounding the solver reports for it)",
           rcp(new Teuchos::EnhancedNumberValidator<double>(0.0, 1.0)));
    p->set("Track MAC Floor", 0.1,
           "a track goes on to the next speed's mode only when their MAC (with the span of that mode's repeated "
           "cluster) is at least this; below it the track is lost there (its mode left the requested set) and the "
           "unmatched mode starts a track of its own (it entered the set), so that no track joins two modes",
           rcp(new Teuchos::EnhancedNumberValidator<double>(0.0, 1.0)));
    p->set("Whirl", *WhirlClassification::getValidParameters(), "the whirl rule's parameters");
    p->set("Threads", 0, "threads for the sweep's solves on each rank (0: the cores left to it)",
           rcp(new Teuchos::EnhancedNumberValidator<int>(0, 1024)));
  }
  return p;
}

CampbellStudy::CampbellStudy(const Teuchos::ParameterList& params) : params_(params) {
  try {
    params_.validateParametersAndSetDefaults(*getValidParameters());
  } catch (const std::exception& e) {
    throw InputError(std::string("CampbellStudy: ") + e.what());
  }
  for (double o : params_.get<Teuchos::Array<double>>("Engine Orders"))
    CMS_INPUT_CHECK(!(o > 0.0) || !std::isfinite(o), "CampbellStudy: \"Engine Orders\": " << o << " is not positive");
  CMS_INPUT_CHECK(!std::isfinite(params_.get<double>("Speed Factor")),
                  "CampbellStudy: \"Speed Factor\" = " << params_.get<double>("Speed Factor") << " is not finite");
}

namespace {

bool unstable(eigen::Stability s) { return s == eigen::Stability::Divergence || s == eigen::Stability::Flutter; }
bool zeroFrequency(eigen::Stability s) { return s == eigen::Stability::RigidBody || s == eigen::Stability::Critical; }

/// The worse of two statuses: a breakdown before a non-convergence.
void worsen(CampbellResult& r, const eigen::GyroscopicResult& g) {
  if (g.status == eigen::SolveStatus::Converged) return;
  if (r.status == eigen::SolveStatus::Converged || g.status == eigen::SolveStatus::NumericalIssue)
    r.status = g.status, r.reason = g.reason;
}

}  // namespace

CampbellResult CampbellStudy::run(const SpeedSweepProblem& problem) const {
  const int steps = params_.get<int>("Steps");
  const double maxFactor = params_.get<double>("Max Factor"), speedFactor = params_.get<double>("Speed Factor");
  const std::string swept = params_.get<std::string>("Speed Parameter");
  // Each order once ("1,1.0" listed every crossing twice; a review).
  auto orders = params_.get<Teuchos::Array<double>>("Engine Orders");
  std::sort(orders.begin(), orders.end());
  orders.erase(std::unique(orders.begin(), orders.end()), orders.end());
  const bool refine = params_.get<bool>("Refine Crossings");
  const double crossingTol = params_.get<double>("Crossing Tolerance"), frameTol = params_.get<double>("Frame Rate Tolerance");
  const WhirlClassification rule(params_.sublist("Whirl"));
  const double clusterTol = params_.sublist("Whirl").get<double>("Cluster Tolerance");
  const double macFloor = params_.get<double>("Track MAC Floor");

  CampbellResult r;
  r.parameters = problem.parameters();
  r.whirlOf = problem.whirlOf();
  r.orders.assign(orders.begin(), orders.end());
  CMS_INPUT_CHECK(r.parameters.empty(), "CampbellStudy: nothing spins: no speed parameter to sweep");
  r.scaled.assign(r.parameters.size(), swept.empty());
  if (!swept.empty()) {
    std::string names;
    for (std::size_t p = 0; p < r.parameters.size(); ++p) {
      names += (p ? ", " : "") + r.parameters[p].name;
      if (r.parameters[p].name == swept) r.reference = static_cast<int>(p), r.scaled[p] = true;
    }
    CMS_INPUT_CHECK(!r.scaled[r.reference], "CampbellStudy: \"Speed Parameter\" = \"" << swept
                                                << "\" is not a speed parameter (those of this structure: " << names << ")");
  }
  r.whirlInRotorFrame = problem.whirlInRotorFrame(r.reference);
  const double refNominal = r.parameters[r.reference].nominal * speedFactor;
  CMS_INPUT_CHECK(refNominal == 0.0, "CampbellStudy: the nominal rate of \"" << r.parameters[r.reference].name
                                                                          << "\" is 0: nothing to sweep");
  auto speedsAt = [&](double f) {
    std::vector<double> s;
    for (std::size_t p = 0; p < r.parameters.size(); ++p)
      s.push_back(r.parameters[p].nominal * speedFactor * (r.scaled[p] ? f : 1.0));
    return s;
  };
  auto refAt = [&](double f) { return refNominal * f; };

  // Crossings found on the way (merged and filtered at the end); for an
  // unrefined one, the grid step and mode its dominant part is named from.
  std::vector<EngineOrderCrossing> found;
  std::map<std::size_t, std::pair<std::size_t, int>> dominantAt;
  std::vector<eigen::GyroscopicMode> last;  // each track's mode at the previous speed
  // A frequency at a spin rate: within the tolerance, or within what
  // rounding can do to the eigenvalue (its split radius): a free body's
  // frame-rate modes are a split defective cluster, ~1e-4 rad/s wide
  // whatever the rate, so at low rates a relative test alone passed or
  // failed by the BLAS kernel's rounding.
  const auto atRate = [&](double omega, double split, double rate) {
    return std::abs(omega - rate) <= frameTol * rate + split;
  };
  // Equals a spin rate at every step so far where it was found: a step
  // where the track was lost says nothing either way (before, one such
  // step made a frame-rate track's crossings critical speeds).
  auto rateLike = [&](const CampbellTrack& tr) {
    for (std::size_t p = 0; p < r.parameters.size(); ++p) {
      double top = 0.0;  // over the speeds tracked so far (the grid is solved ahead)
      for (std::size_t k = 0; k < tr.omega.size() && k < r.speeds.size(); ++k)
        if (!tr.lost[k]) top = std::max(top, std::abs(r.speeds[k][p]));
      if (top == 0.0) continue;
      bool all = true;
      for (std::size_t k = 0; k < tr.omega.size() && all; ++k) {
        if (tr.lost[k]) continue;
        const double rate = std::abs(r.speeds[k][p]), split = tr.splitRadius[k];
        all = rate > 0.0 ? atRate(tr.omega[k], split, rate)
                         : zeroFrequency(tr.stability[k]) || tr.omega[k] <= frameTol * top + split;
      }
      if (all) return static_cast<int>(p);
    }
    return -1;
  };

  // The grid's solves first (independent: on threads where the problem
  // can), then the tracking in speed order.
  for (int k = 0; k < steps; ++k) {
    r.factors.push_back(maxFactor * k / (steps - 1));
    r.speeds.push_back(speedsAt(r.factors.back()));
  }
  const auto grid = problem.solveAll(r.speeds, params_.get<int>("Threads"));
  // K(Omega)'s count of negative eigenvalues at each grid speed (a
  // factorisation each): where it changes over a step a frequency passes
  // through zero inside it. Taken before the tracking, which follows such a
  // mode through the step, and bisected after it (zero-frequency critical
  // speeds, below).
  const double step = r.factors.size() > 1 ? std::abs(r.factors[1] - r.factors[0]) : 1.0;
  std::vector<StiffnessCount> counts(r.factors.size());
  std::vector<double> countAt(r.factors.begin(), r.factors.end());  // where counts[k] was taken
  {
    const StiffnessCount first = problem.stiffnessCount(speedsAt(r.factors[0]));
    r.zeroCountsTaken = first.available;
    if (!r.zeroCountsTaken) r.zeroCountsNote = first.why;  // the model gives none
    for (std::size_t k = 0; k < r.factors.size() && r.zeroCountsTaken; ++k) {
      counts[k] = k == 0 ? first : problem.stiffnessCount(speedsAt(r.factors[k]));
      if (counts[k].negative < 0) {
        countAt[k] = r.factors[k] + crossingTol * step;
        counts[k] = problem.stiffnessCount(speedsAt(countAt[k]));
      }
      if (counts[k].negative < 0)
        r.zeroCountsNote = counts[k].why + " (at " + std::to_string(refAt(r.factors[k])) + " rad/s; the steps beside "
                           "it not searched)";
    }
  }
  std::vector<std::pair<int, int>> unstableSteps;  // each range's first and last grid step
  for (int k = 0; k < steps; ++k) {
    const double f = r.factors[k];
    const auto& sol = grid[static_cast<std::size_t>(k)];
    worsen(r, sol.result);
    r.solver = sol.result.solver;
    r.maxResidual = std::max(r.maxResidual, sol.result.maxResidual());
    const auto& modes = sol.result.modes;
    std::vector<double> forward;
    const auto whirl = problem.whirlAndForwardShare(sol, rule, forward);
    bool anyUnstable = false, anyUndecided = false;
    for (const auto& m : modes) anyUnstable = anyUnstable || unstable(m.stability), anyUndecided = anyUndecided || m.undecided;
    if (anyUndecided) {
      if (k > 0 && !r.undecidedRanges.empty() && r.undecidedRanges.back().second == refAt(r.factors[k - 1]))
        r.undecidedRanges.back().second = refAt(f);
      else
        r.undecidedRanges.push_back({refAt(f), refAt(f)});
    }
    if (anyUnstable) {
      if (k > 0 && !r.unstableRanges.empty() && r.unstableRanges.back().second == refAt(r.factors[k - 1])) {
        r.unstableRanges.back().second = refAt(f);
        unstableSteps.back().second = k;
        r.unstableOpen.back().second = k + 1 == steps;
      } else {
        r.unstableRanges.push_back({refAt(f), refAt(f)});
        unstableSteps.push_back({k, k});
        r.unstableOpen.push_back({k == 0, k + 1 == steps});
      }
    }
    if (k == 0) {
      for (std::size_t j = 0; j < modes.size(); ++j) {
        r.tracks.push_back({{modes[j].omega}, {modes[j].stability}, {whirl[j]}, {forward[j]}, {false},
                            {modes[j].dampingRatio}, {modes[j].splitRadius}});
        last.push_back(modes[j]);
      }
      continue;
    }
    // Match by decreasing MAC with each track's previous mode.
    const auto mac = problem.mac(last, modes);
    std::vector<std::tuple<double, int, int>> pairs;
    for (std::size_t t = 0; t < last.size(); ++t)
      for (std::size_t j = 0; j < modes.size(); ++j) pairs.push_back({mac[t][j], static_cast<int>(t), static_cast<int>(j)});
    std::stable_sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return std::get<0>(a) > std::get<0>(b); });
    std::vector<int> match(last.size(), -1);
    std::vector<bool> used(modes.size(), false);
    // A match below the floor joins two modes: when the set is the N lowest,
    // the top mode leaves it and another enters, and the greedy pairing had
    // nothing else left to give the leaving track (MAC ~ 0). A repeated
    // mode's shapes are any basis of its cluster: the MAC with the
    // cluster's span counts. Its cluster: the modes within the cluster
    // tolerance plus both split radii (what rounding can do to each: a free
    // body's frame-rate triple), and every zero frequency together (rigid
    // motions, any basis of the rigid space).
    const auto together = [&](const eigen::GyroscopicMode& a, const eigen::GyroscopicMode& b) {
      if (zeroFrequency(a.stability) && zeroFrequency(b.stability)) return true;
      return std::abs(a.omega - b.omega) <= clusterTol * std::max(a.omega, b.omega) + a.splitRadius + b.splitRadius;
    };
    const auto spanMac = [&](std::size_t t, int j) {
      double sum = 0.0;
      for (std::size_t i = 0; i < modes.size(); ++i)
        if (together(modes[i], modes[static_cast<std::size_t>(j)])) sum += mac[t][i];
      return std::min(1.0, sum);
    };
    // Zero frequencies and frame-rate modes (a rigid motion seen at a spin
    // rate) are matched as before, whatever their MAC: their shapes are any
    // basis of a rigid space that rounding splits, differently at every
    // speed (the spacecraft's zeros number two or three; a member of its
    // bus's frame-rate triple came back orthogonal to the whole triple one
    // step later), and their crossings are no critical speeds.
    const auto rigidLike = [&](const eigen::GyroscopicMode& m, std::size_t step) {
      if (zeroFrequency(m.stability)) return true;
      for (const double rate : r.speeds[step])
        if (rate != 0.0 && atRate(m.omega, m.splitRadius, std::abs(rate))) return true;
      return false;
    };
    // A vibration mode that becomes a zero frequency is matched by shape,
    // like any mode (one at its critical speed is the same branch by MAC):
    // a zero that took any mode let a track jump, silently, from a mode
    // that left the set to an unrelated zero (an axial mode hidden at a
    // critical speed by the in-plane pair's two zeros was followed by an
    // in-plane track from there; found by a review). From a zero to a
    // vibration mode any MAC is still taken: a mode through zero frequency
    // comes back conjugated, its shape no longer comparable (the free
    // shaft past its critical speed).
    const auto accept = [&](int t, int j) {
      const auto& a = last[static_cast<std::size_t>(t)];
      const auto& b = modes[static_cast<std::size_t>(j)];
      const bool becomesZero = !zeroFrequency(a.stability) && zeroFrequency(b.stability);
      if (becomesZero && !rigidLike(a, static_cast<std::size_t>(k - 1)))
        return spanMac(static_cast<std::size_t>(t), j) >= macFloor;
      return rigidLike(a, static_cast<std::size_t>(k - 1)) || rigidLike(b, static_cast<std::size_t>(k)) ||
             spanMac(static_cast<std::size_t>(t), j) >= macFloor;
    };
    // Two or more tracks whose modes were one degenerate cluster (rigid
    // zeros: any basis of the rigid space; an undamped symmetric rotor's
    // repeated pair at rest, equal to 1e-8: any basis of the pair; at a speed, modes that
    // equal are more often two branches crossing on the grid, which MAC
    // follows) go on, in track order, to the modes mostly in the cluster's span
    // (summed MAC >= 1/2) in ascending |lambda|. By MAC alone, which track
    // took which member depended on the basis rounding chose at both speeds,
    // and so on the rank count: a free body's six zeros at rest (exactly the
    // rigid coordinates since they are solved apart, theory §4.3) unfold into
    // two zeros, the frame-rate triple and the nutation; a free shaft's
    // bending pair at rest into its forward and backward branches, tracks 7
    // and 8 swapped between 1 and 2 ranks (found by a review). A critical
    // speed's zero is a vibration mode passing through zero, which MAC
    // follows, and distinct modes merely within the whirl's cluster
    // tolerance (a crossing on a grid speed) keep their MAC too; so does a
    // split defective cluster (a free body's frame-rate triple, whose
    // members can come back orthogonal to the triple's span one step later:
    // rigidLike below takes them whatever their MAC).
    bool atRest = true;
    for (const double rate : r.speeds[static_cast<std::size_t>(k - 1)]) atRest = atRest && rate == 0.0;
    const auto degenerate = [&](const eigen::GyroscopicMode& a, const eigen::GyroscopicMode& b) {
      if (a.stability == eigen::Stability::RigidBody || b.stability == eigen::Stability::RigidBody)
        return a.stability == b.stability;
      if (zeroFrequency(a.stability) || zeroFrequency(b.stability) || !atRest) return false;
      // Undamped (Re lambda within 1e-8 of |lambda|) and equal in lambda, not
      // only in omega: a damped pair's rounding split (6e-9 to 1.6e-7 on a
      // damped rotor) would turn the rule on or off with the rank count, and
      // a damped and an undamped mode of one omega are different branches
      // (both found by a review); MAC follows those, as before.
      const double size = std::max(std::abs(a.lambda), std::abs(b.lambda));
      return std::abs(a.lambda.real()) <= 1e-8 * size && std::abs(b.lambda.real()) <= 1e-8 * size &&
             std::abs(a.lambda - b.lambda) <= 1e-8 * size;
    };
    std::vector<char> grouped(last.size(), 0);
    for (std::size_t t0 = 0; t0 < last.size(); ++t0) {
      if (grouped[t0]) continue;
      std::vector<int> group{static_cast<int>(t0)};
      for (std::size_t t = t0 + 1; t < last.size(); ++t)
        if (!grouped[t] && degenerate(last[t0], last[t])) group.push_back(static_cast<int>(t));
      if (group.size() < 2) continue;
      for (int t : group) grouped[static_cast<std::size_t>(t)] = 1;
      std::size_t next = 0;
      for (std::size_t j = 0; j < modes.size() && next < group.size(); ++j) {
        if (used[j]) continue;
        double sum = 0.0;
        for (int t : group) sum += mac[static_cast<std::size_t>(t)][j];
        if (sum < 0.5) continue;
        const auto t = static_cast<std::size_t>(group[next++]);
        match[t] = static_cast<int>(j), used[j] = true;
        r.tracks[t].minMac = std::min(r.tracks[t].minMac, std::min(1.0, sum));
      }
    }
    // Pairs whose MACs tie (within 1e-3) go by the frequency's continuity,
    // the least relative change first: two modes can share one shape, and
    // the MAC cannot tell them apart. Past its critical speed an isotropic
    // rotor's lower whirl, |omega_0 - Omega|, comes back conjugated, its
    // orbit turning as the upper whirl's, and both modes had MAC 1 with the
    // upper track: it took the lower mode, a 1X "critical speed" was read
    // on the jump, and the lower track was lost (an open finding). The
    // change is from the track's frequency extrapolated from its last two
    // steps (the grid is uniform), |2 omega_{k-1} - omega_{k-2}| (a branch
    // through zero comes back reflected): from its last value alone, a step
    // h past omega_0 made the wrong pair the nearer, |2 omega_0 - h| against
    // h, and the tracks swapped at every step, inventing a 1X crossing each
    // time (a review). From the last value where the track has one step.
    const auto change = [&](int t, int j) {
      const auto& om = r.tracks[static_cast<std::size_t>(t)].omega;
      const auto& lost = r.tracks[static_cast<std::size_t>(t)].lost;
      double a = last[static_cast<std::size_t>(t)].omega;
      const auto ks = static_cast<std::size_t>(k);
      if (ks >= 2 && om.size() >= ks && !lost[ks - 1] && !lost[ks - 2]) a = std::abs(2.0 * om[ks - 1] - om[ks - 2]);
      const double b = modes[static_cast<std::size_t>(j)].omega;
      return a + b > 0.0 ? std::abs(a - b) / (a + b) : 0.0;
    };
    constexpr double macTie = 1e-3;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const auto [v, t, j] = pairs[i];
      if (match[t] >= 0 || used[j] || !accept(t, j)) continue;
      std::size_t best = i;
      for (std::size_t q = i + 1; q < pairs.size() && std::get<0>(pairs[q]) >= v - macTie; ++q) {
        const auto [v2, t2, j2] = pairs[q];
        if (match[t2] < 0 && !used[j2] && change(t2, j2) < change(std::get<1>(pairs[best]), std::get<2>(pairs[best])) &&
            accept(t2, j2))
          best = q;
      }
      const auto [vb, tb, jb] = pairs[best];
      match[tb] = jb, used[jb] = true, r.tracks[tb].minMac = std::min(r.tracks[tb].minMac, vb);
      if (best != i) --i;  // pair i is still open: looked at again
    }
    // A vibration mode through zero frequency inside the step comes back
    // conjugated (a pair is listed by its member with Im >= 0): its shape is
    // the conjugate of its continuation, whose MAC with the track's last
    // mode is low, and the track was lost there, the mode entering as a new
    // one (the shaft on its 1e18 support past its critical speed, once the
    // zero refinement showed it nonzero at 78.02 rad/s: before, a grid
    // speed in the window that read "critical" carried it, as a zero takes
    // any MAC). Where the count of K(Omega)'s negative eigenvalues changes
    // over the step, tracks left unmatched take unused modes by the MAC of
    // their conjugates (the floor as above, the largest first), at most as
    // many as the count changed.
    // Only a mode near enough to zero at both speeds: through zero within
    // the step, omega_{k-1} + omega_k is the frequency's change over it,
    // at most 4 times the largest rate's (a whirl's image moves by up to
    // 1 + Jp / Jd <= 3 times the rate). Past the zero the forward whirl has
    // the backward whirl's sense and nearly its shape, the pass above can
    // give the backward track either, and without this the forward track
    // took the backward mode (MAC ~1), and a 1X crossing was invented
    // between them, at one rank and not at two (a review: a 20-element
    // shaft, a small disc, 15 of 56 step counts).
    if (r.zeroCountsTaken && counts[k - 1].negative >= 0 && counts[k].negative >= 0 &&
        counts[k].negative != counts[k - 1].negative) {
      double rateStep = 0.0;
      for (std::size_t p = 0; p < r.parameters.size(); ++p)
        rateStep = std::max(rateStep, std::abs(r.speeds[static_cast<std::size_t>(k)][p] -
                                               r.speeds[static_cast<std::size_t>(k - 1)][p]));
      std::vector<eigen::GyroscopicMode> conjugated(modes);
      for (auto& m : conjugated)
        for (auto& c : m.q) c = std::conj(c);
      const auto conjugateMac = problem.mac(last, conjugated);
      std::vector<std::tuple<double, int, int>> through;
      for (std::size_t t = 0; t < last.size(); ++t)
        for (std::size_t j = 0; j < modes.size(); ++j)
          if (match[t] < 0 && !used[j] && !zeroFrequency(last[t].stability) && !zeroFrequency(modes[j].stability) &&
              conjugateMac[t][j] >= macFloor && last[t].omega + modes[j].omega <= 4.0 * rateStep)
            through.push_back({conjugateMac[t][j], static_cast<int>(t), static_cast<int>(j)});
      std::stable_sort(through.begin(), through.end(),
                       [](const auto& a, const auto& b) { return std::get<0>(a) > std::get<0>(b); });
      long long left = std::llabs(counts[k].negative - counts[k - 1].negative);
      for (const auto& [v, t, j] : through)
        if (left > 0 && match[t] < 0 && !used[j])
          match[t] = j, used[j] = true, r.tracks[t].minMac = std::min(r.tracks[t].minMac, v), --left;
    }
    for (std::size_t t = 0; t < r.tracks.size(); ++t) {
      auto& tr = r.tracks[t];
      const int j = match[t];
      const double w0 = tr.omega.back();
      const bool ok0 = !tr.lost.back() && !zeroFrequency(tr.stability.back());
      // Following a swept rate up to f_{k-1} (a frame-rate member): a sign
      // change from there is rounding about the line, or the track leaving
      // it for another mode (a frame-rate member dropping out of the set),
      // never a critical speed.
      const int followed = rateLike(tr);
      const bool wasOnLine = followed >= 0 && r.scaled[static_cast<std::size_t>(followed)];
      tr.omega.push_back(j < 0 ? std::nan("") : modes[j].omega);
      tr.stability.push_back(j < 0 ? eigen::Stability::Stable : modes[j].stability);
      tr.whirl.push_back(j < 0 ? Whirl::Neutral : whirl[j]);
      tr.forwardShare.push_back(j < 0 ? -1.0 : forward[j]);
      tr.lost.push_back(j < 0);
      tr.dampingRatio.push_back(j < 0 ? std::nan("") : modes[j].dampingRatio);
      tr.splitRadius.push_back(j < 0 ? 0.0 : modes[j].splitRadius);
      if (j < 0) continue;
      // Engine-order crossings in (f_{k-1}, f_k]: a sign change of omega -
      // order * Omega_ref, bisected. Frame-rate tracks too (their crossings
      // are set aside at the end, at an accurate speed all the same), but
      // not one that follows a swept rate: it lies on an engine-order line,
      // and its sign changes are rounding.
      const int follows = rateLike(tr);
      const bool onLine = (follows >= 0 && r.scaled[static_cast<std::size_t>(follows)]) || wasOnLine;
      for (double order : orders) {
        const double f0 = r.factors[k - 1];
        // An engine order n excites n |Omega|: a rate turning against its
        // axis (negative) has the same lines (before, none was crossed).
        double lo = f0, hi = f, gLo = w0 - order * std::abs(refAt(lo)), gHi = modes[j].omega - order * std::abs(refAt(hi));
        // g_hi exactly 0 is a crossing at f_k, from either side (g_lo = 0
        // was the previous interval's). A zero frequency at f_k ends the
        // interval only where the track took it for being rigid-like (any
        // MAC): where it is the same branch by shape (a mode at its critical
        // speed on the grid, its frequency falling to zero), the crossing
        // below it is there to find (it was skipped, a critical speed
        // missed; found by a review).
        const bool zeroAbove =
            zeroFrequency(modes[j].stability) && spanMac(t, j) < macFloor;
        if (!ok0 || zeroAbove || gLo == 0.0 || (gHi != 0.0 && (gLo > 0) == (gHi > 0))) continue;
        // Found where its track follows a swept rate's line: counted with
        // the frame-rate tracks' crossings, even if the track leaves the
        // line later (a frame-rate member dropping out of a 7-mode set: its
        // rounding crossings before were listed as critical speeds,
        // different at each rank count; found by a review).
        if (onLine) {
          ++r.frameRateOnLine;
          continue;
        }
        EngineOrderCrossing c;
        c.order = order;
        c.tracks = {static_cast<int>(t)};
        c.whirl = std::abs(gLo) < std::abs(gHi) ? tr.whirl[k - 1] : tr.whirl[k];
        c.forwardShare = std::abs(gLo) < std::abs(gHi) ? tr.forwardShare[k - 1] : tr.forwardShare[k];
        // The last bisection's solve, nearest the crossing (none: f_k's).
        synthesis::StructureModes at;
        int atIndex = -1;
        bool jump = false;
        if (refine) {
          const double dg0 = std::abs(gLo - gHi);
          // Bisection, following the track's mode at the lower end by MAC
          // into each half.
          const auto bisect = [&]() {
            eigen::GyroscopicMode followed = last[t];
            for (int it = 0; it < 200 && hi - lo > crossingTol * hi; ++it) {
              const double mid = 0.5 * (lo + hi);
              auto m = problem.solve(speedsAt(mid));
              if (m.result.status != eigen::SolveStatus::Converged || m.result.modes.empty()) break;
              const auto row = problem.mac({followed}, m.result.modes).front();
              int best = static_cast<int>(std::max_element(row.begin(), row.end()) - row.begin());
              if (row[static_cast<std::size_t>(best)] < macFloor) break;  // the mode left the set in between
              // Followed from a repeated mode (a symmetric rotor's pair at
              // rest: any combination of the two, MAC ~0.5 with each branch
              // once the speed splits them), the lower end does not say
              // which branch is the track's: the upper end's mode, the
              // track's by the grid's matching, does. Without it the
              // bisection followed the other branch, closed on a "jump"
              // and lost the crossing (found by a review).
              {
                const double top = row[static_cast<std::size_t>(best)];
                int rivals = 0;
                for (const double v : row) rivals += v >= 0.8 * top;
                if (rivals > 1) {
                  const auto upper = problem.mac({modes[static_cast<std::size_t>(j)]}, m.result.modes).front();
                  for (std::size_t i = 0; i < row.size(); ++i)
                    if (row[i] >= 0.8 * top && upper[i] > upper[static_cast<std::size_t>(best)]) best = static_cast<int>(i);
                }
              }
              const double g = m.result.modes[best].omega - order * std::abs(refAt(mid));
              if ((g > 0) == (gLo > 0)) lo = mid, gLo = g, followed = m.result.modes[best];
              else hi = mid, gHi = g;
              at = std::move(m), atIndex = best;
            }
            // On one branch omega - n Omega is continuous: closed to the
            // tolerance, its two ends differ by the slope times a bracket
            // of crossingTol, a millionth of the grid's difference. Ends
            // that still differ by 1% of it are two branches: the track
            // took another mode at the grid speed (a mode through zero
            // frequency is returned as its conjugate), and the bracket
            // closed on that speed, where it was reported as a refined
            // critical speed (the helicopter at 5 rad/s, found by a review).
            return hi - lo <= crossingTol * hi && std::abs(gLo - gHi) > 0.01 * dg0;
          };
          // Only the lower end's branch is followed. Following the upper
          // end's down as well was tried: on the helicopter (11 steps, the
          // regressing lag taken at 5 rad/s and crossing 1X at 2.37) it
          // never found that crossing (the mode through zero frequency is
          // conjugated below it, and the MAC then took another branch;
          // found by a review), so it is not kept: a jump is said instead.
          jump = bisect();
          // Refined only when the bracket closed: a bisection that stopped
          // early (the mode left the set, a solve failed) is interpolated,
          // as theory §12.1 says (it was called refined after one step).
          if (atIndex >= 0 && !jump) {
            std::vector<double> share;
            c.whirl = problem.whirlAndForwardShare(at, rule, share)[atIndex];
            c.forwardShare = share[static_cast<std::size_t>(atIndex)];
            c.refined = hi - lo <= crossingTol * hi;
          }
        }
        // The part that dominates it: at the bisection's last solve now; at
        // the grid's f_k once the crossing is known to be reported (below):
        // most unrefined ones are a frame-rate track's rounding about a line,
        // counted and dropped, and each name costs a characterise.
        c.factor = lo + gLo / (gLo - gHi) * (hi - lo);
        c.speed = refAt(c.factor);
        c.omega = order * std::abs(c.speed);
        if (jump) {
          r.branchJumps.push_back({static_cast<int>(t), order, refAt(r.factors[k - 1]), refAt(f)});
          continue;
        }
        if (atIndex >= 0) c.dominant = {problem.dominant(at)[atIndex]};
        else dominantAt.emplace(found.size(), std::make_pair(static_cast<std::size_t>(k), j));
        found.push_back(c);
      }
      last[t] = modes[j];
    }
    // The modes no track took entered the set here: a track each, lost before.
    for (std::size_t j = 0; j < modes.size(); ++j) {
      if (used[j]) continue;
      CampbellTrack tr;
      tr.omega.assign(static_cast<std::size_t>(k), std::nan(""));
      tr.stability.assign(static_cast<std::size_t>(k), eigen::Stability::Stable);
      tr.whirl.assign(static_cast<std::size_t>(k), Whirl::Neutral);
      tr.forwardShare.assign(static_cast<std::size_t>(k), -1.0);
      tr.lost.assign(static_cast<std::size_t>(k), true);
      tr.dampingRatio.assign(static_cast<std::size_t>(k), std::nan(""));
      tr.splitRadius.assign(static_cast<std::size_t>(k), 0.0);
      tr.omega.push_back(modes[j].omega);
      tr.stability.push_back(modes[j].stability);
      tr.whirl.push_back(whirl[j]);
      tr.forwardShare.push_back(forward[j]);
      tr.lost.push_back(false);
      tr.dampingRatio.push_back(modes[j].dampingRatio);
      tr.splitRadius.push_back(modes[j].splitRadius);
      tr.firstStep = k;
      r.tracks.push_back(std::move(tr));
      last.push_back(modes[j]);
    }
  }

  // The edges of each unstable range, bisected between the grid's last
  // stable and first unstable speeds like a crossing (theory §12.1): the
  // grid alone puts them up to a step inside the band. A band narrower than
  // a step between two stable speeds is not seen.
  if (refine) {
    // A speed whose growth is undecided is not shown unstable, and the
    // edge is bisected to where instability is shown; the undecided speeds
    // the bisection met are listed with the grid's (before, only the grid's
    // were: an onset below the edge, within the uncertainty, went unsaid).
    std::vector<double> edgeUndecided;                        // this edge's, reference speeds
    std::vector<std::pair<double, double>> metUndecided;      // per edge, lowest to highest
    const auto unstableAt = [&](double f, bool& ok) {
      const auto m = problem.solve(speedsAt(f));
      ok = m.result.status == eigen::SolveStatus::Converged && !m.result.modes.empty();
      bool u = false, undecided = false;
      for (const auto& mode : m.result.modes) u = u || unstable(mode.stability), undecided = undecided || mode.undecided;
      if (ok && undecided) edgeUndecided.push_back(refAt(f));
      return u;
    };
    // From rest (a free body diverging about its intermediate axis at any
    // speed above zero) a width relative to the bracket's speeds never
    // closed, and 200 solves took the edge to 6e-62 rad/s (found by a
    // review): a bracket whose stable end is at rest closes at the Crossing
    // Tolerance times the sweep's largest factor instead.
    const auto edge = [&](double stable, double unstableF) {
      const auto width = [&] {
        return stable == 0.0 ? crossingTol * std::abs(maxFactor)
                             : crossingTol * std::max(std::abs(stable), std::abs(unstableF));
      };
      edgeUndecided.clear();
      for (int it = 0; it < 200 && std::abs(unstableF - stable) > width(); ++it) {
        const double mid = 0.5 * (stable + unstableF);
        bool ok = false;
        const bool u = unstableAt(mid, ok);
        if (!ok) break;
        (u ? unstableF : stable) = mid;
      }
      // This edge's undecided speeds as one range, from the lowest to the
      // highest (a stable speed between them does not decide the others).
      if (!edgeUndecided.empty()) {
        const auto [lo, hi] = std::minmax_element(edgeUndecided.begin(), edgeUndecided.end());
        metUndecided.push_back({*lo, *hi});
      }
      return refAt(0.5 * (stable + unstableF));
    };
    for (std::size_t i = 0; i < unstableSteps.size(); ++i) {
      const auto [first, lastStep] = unstableSteps[i];
      if (first > 0) r.unstableRanges[i].first = edge(r.factors[static_cast<std::size_t>(first - 1)], r.factors[static_cast<std::size_t>(first)]);
      if (lastStep + 1 < steps)
        r.unstableRanges[i].second = edge(r.factors[static_cast<std::size_t>(lastStep + 1)], r.factors[static_cast<std::size_t>(lastStep)]);
    }
    r.unstableEdgesRefined = true;
    if (!metUndecided.empty()) {
      // Merged with the grid's runs where they overlap, as intervals
      // [low, high] whatever the speeds' sign, then written back in the
      // sweep's direction as the grid's runs are (a negative nominal rate
      // runs from high to low; a review found the two orders mixed).
      const bool ascending = refAt(r.factors.back()) >= refAt(r.factors.front());
      std::vector<std::pair<double, double>> u;
      for (const auto& [a, b] : r.undecidedRanges) u.push_back({std::min(a, b), std::max(a, b)});
      u.insert(u.end(), metUndecided.begin(), metUndecided.end());
      std::sort(u.begin(), u.end());
      std::vector<std::pair<double, double>> merged;
      for (const auto& range : u)
        if (!merged.empty() && range.first <= merged.back().second)
          merged.back().second = std::max(merged.back().second, range.second);
        else
          merged.push_back(range);
      if (!ascending) {
        std::reverse(merged.begin(), merged.end());
        for (auto& [a, b] : merged) std::swap(a, b);
      }
      r.undecidedRanges = merged;
    }
  }

  // Speeds where a frequency passes through zero (theory §12.1): K(Omega)
  // singular, where the count of its negative eigenvalues changes. The
  // tracks cannot show it (a mode through zero comes back conjugated, its
  // shape no longer comparable, and the grid rarely falls on it): a disc on
  // a spinning shaft, swept in the shaft's frame, had its unbalance critical
  // speed nowhere in the output (found by a review). Each change between
  // grid speeds is bisected on the count; an interval whose count changes
  // by more than one is split until each change stands alone. Two changes
  // that cancel within one step are not seen.
  //    The count is bisected whether or not "Refine Crossings" is set (a
  //    factorisation a step, no eigensolve), so that two changes in one
  //    step are two speeds. A change that closes on speed 0 is dropped: K
  //    singular at rest is a mechanism or a rigid motion that spin softens,
  //    not a critical speed.
  //    A count refused at a grid speed (the sparse inertia met a pivot zero
  //    to rounding: a critical speed on the grid, or a mechanism at rest)
  //    is taken again a crossing tolerance of a step above it, and that
  //    speed is the bracket's end; refused there too, the brackets beside
  //    it are not searched, and the note says where.
  //    Between two zeros the count is known too; where it is odd, det K <
  //    0 and the characteristic polynomial det(lambda^2 M + lambda (G + D)
  //    + K), positive for large real lambda (M > 0), has a real root
  //    lambda > 0: divergence whatever G and D. Such a band is listed
  //    unstable, its edges the two zeros: inside one step no grid speed
  //    shows it (found by a review), and at a grid speed inside it the
  //    dense solve can take the real root for a zero (an anisotropic shaft
  //    in its own frame, growth 0.37-0.67 1/s on a scale of 7e7 rad/s,
  //    "critical"). Not where a circulatory N acts (the polynomial at 0 is
  //    then det(K + N)), nor across a failed count, nor from a zero that
  //    closed on rest (a mechanism's count there is its rounding's).
  struct CountEdge {
    double at;           // factor
    long long below, above;
    bool refined;        // bisected to the tolerance (not a failed count's middle, nor closed on rest)
  };
  std::vector<std::pair<double, double>> countBands;  // factors
  {
    std::vector<CountEdge> edges;  // this step's, in speed order
    bool circulatory = false;
    const std::function<void(double, long long, double, long long)> search = [&](double lo, long long cLo, double hi,
                                                                              long long cHi) {
      if (cLo == cHi) return;
      const double width = crossingTol * std::max({std::abs(lo), std::abs(hi), step});
      const auto record = [&](double f, bool refined) {
        // A bracket that closed on rest: K singular at rest (a mechanism,
        // a rigid motion that spin softens) is no critical speed.
        const bool rest = lo == r.factors[0] && r.factors[0] == 0.0 && hi <= crossingTol * step;
        edges.push_back({f, cLo, cHi, refined && !rest});
        if (rest) return;
        r.zeroFrequencySpeeds.push_back(refAt(f));
        r.zeroFrequencyRefined.push_back(refined);
      };
      if (hi - lo <= width) return record(0.5 * (lo + hi), true);
      const double mid = 0.5 * (lo + hi);
      const auto cMid = problem.stiffnessCount(speedsAt(mid));
      circulatory = circulatory || cMid.circulatory;
      if (cMid.negative < 0) {  // said, and the middle of what is known
        r.zeroCountsNote = cMid.why + " (at " + std::to_string(refAt(mid)) + " rad/s, inside a bracket)";
        return record(mid, false);
      }
      search(lo, cLo, mid, cMid.negative);
      search(mid, cMid.negative, hi, cHi);
    };
    std::optional<double> oddFrom;  // the zero past which the count is odd, while known
    if (r.zeroCountsTaken)
      for (std::size_t k = 1; k < r.factors.size(); ++k) {
        if (counts[k - 1].negative < 0 || counts[k].negative < 0) {
          oddFrom.reset();
          continue;
        }
        edges.clear();
        circulatory = counts[k - 1].circulatory || counts[k].circulatory;
        search(countAt[k - 1], counts[k - 1].negative, countAt[k], counts[k].negative);
        if (circulatory) {
          oddFrom.reset();
          continue;
        }
        for (const auto& e : edges) {
          if (oddFrom && e.refined) countBands.push_back({*oddFrom, e.at});
          oddFrom.reset();
          if (e.refined && e.above % 2 != 0) oddFrom = e.at;
        }
      }
  }
  r.unstableByCount.assign(r.unstableRanges.size(), false);
  r.unstableCountBands.assign(r.unstableRanges.size(), {});
  r.unstableEdgesBisected.assign(r.unstableRanges.size(), {r.unstableEdgesRefined, r.unstableEdgesRefined});
  if (const double ref1 = refAt(1.0) - refAt(0.0); !countBands.empty() && ref1 != 0.0) {
    // Into the grid's ranges, in the sweep's order (of the factor), one
    // range where they meet, each edge bisected or not as the band it came
    // from (a grid range's unrefined edge beyond a count band stays the
    // grid's; a review found "its lower edge bisected" on a grid speed). A
    // grid range's factors from its reference speeds (refAt is linear in
    // the factor).
    struct Band {
      double lo, hi;  // factors
      std::pair<double, double> range;
      std::pair<bool, bool> open, bisected;
      bool byCount;
    };
    std::vector<Band> bands;
    for (std::size_t i = 0; i < r.unstableRanges.size(); ++i) {
      const double a = (r.unstableRanges[i].first - refAt(0.0)) / ref1;
      const double b = (r.unstableRanges[i].second - refAt(0.0)) / ref1;
      bands.push_back({std::min(a, b), std::max(a, b), r.unstableRanges[i], r.unstableOpen[i],
                       r.unstableEdgesBisected[i], false});
    }
    for (const auto& [lo, hi] : countBands)
      bands.push_back({lo, hi, {refAt(lo), refAt(hi)}, {false, false}, {true, true}, true});
    std::stable_sort(bands.begin(), bands.end(), [](const Band& x, const Band& y) { return x.lo < y.lo; });
    r.unstableRanges.clear(), r.unstableOpen.clear(), r.unstableByCount.clear();
    r.unstableCountBands.clear(), r.unstableEdgesBisected.clear();
    double reach = 0.0;  // the last range's upper factor
    for (const auto& b : bands) {
      if (r.unstableRanges.empty() || b.lo > reach) {
        r.unstableRanges.push_back(b.range), r.unstableOpen.push_back(b.open), r.unstableByCount.push_back(false);
        r.unstableCountBands.emplace_back(), r.unstableEdgesBisected.push_back(b.bisected);
        reach = b.hi;
      } else if (b.hi > reach) {
        r.unstableRanges.back().second = b.range.second, r.unstableOpen.back().second = b.open.second;
        r.unstableEdgesBisected.back().second = b.bisected.second;
        reach = b.hi;
      }
      if (b.byCount) r.unstableByCount.back() = true, r.unstableCountBands.back().push_back(b.range);
    }
  }

  // Frame-rate tracks (equal to a spin rate over the whole sweep) and their crossings set aside.
  for (auto& tr : r.tracks) tr.frameRateOf = rateLike(tr), tr.frameRate = tr.frameRateOf >= 0;
  // A frame-rate track's jumps are rounding about a rate, like its crossings.
  r.branchJumps.erase(std::remove_if(r.branchJumps.begin(), r.branchJumps.end(),
                                     [&](const auto& b) { return r.tracks[static_cast<std::size_t>(b.track)].frameRate; }),
                      r.branchJumps.end());
  std::vector<EngineOrderCrossing> kept;
  std::map<std::size_t, std::vector<std::string>> namesAt;  // per grid step, computed once
  for (std::size_t i = 0; i < found.size(); ++i) {
    auto& c = found[i];
    const auto& tr = r.tracks[c.tracks.front()];
    const bool onLine = tr.frameRate && r.scaled[static_cast<std::size_t>(tr.frameRateOf)];
    if (onLine) {
      ++r.frameRateOnLine;
      continue;
    }
    const auto pending = dominantAt.find(i);
    if (pending != dominantAt.end()) {
      const auto [k, j] = pending->second;
      auto names = namesAt.find(k);
      if (names == namesAt.end()) names = namesAt.emplace(k, problem.dominant(grid[k])).first;
      c.dominant = {names->second[static_cast<std::size_t>(j)]};
    }
    (tr.frameRate ? r.frameRateCrossings : kept).push_back(c);
  }
  // Identical parts (or a repeated mode): the same order, whirl and speed to
  // the cluster tolerance: one entry naming every track.
  // By |speed|: the sweep's order, for a rate turning against its axis too.
  const auto byOrderThenSpeed = [](const auto& a, const auto& b) {
    return a.order != b.order ? a.order < b.order : std::abs(a.speed) < std::abs(b.speed);
  };
  std::stable_sort(kept.begin(), kept.end(), byOrderThenSpeed);
  std::stable_sort(r.frameRateCrossings.begin(), r.frameRateCrossings.end(), byOrderThenSpeed);
  // Every entry of the same order within the tolerance below is a
  // candidate, not only the last: one of another whirl may lie between
  // two identical parts' crossings.
  for (const auto& c : kept) {
    bool merged = false;
    for (auto p = r.crossings.rbegin(); p != r.crossings.rend(); ++p) {
      if (p->order != c.order || std::abs(c.speed) - std::abs(p->speed) > clusterTol * std::abs(c.speed)) break;
      if (p->whirl == c.whirl && std::abs(p->speed - c.speed) <= clusterTol * std::abs(c.speed)) {
        p->tracks.push_back(c.tracks.front());
        p->dominant.push_back(c.dominant.front());
        merged = true;
        break;
      }
    }
    if (!merged) r.crossings.push_back(c);
  }
  return r;
}

// ---------------------------------------------------------------- output

namespace {
const char* stabilityText(const CampbellTrack& tr, std::size_t k) {
  return tr.lost[k] ? "lost" : eigen::toString(tr.stability[k]);
}
bool flagged(const CampbellTrack& tr, std::size_t k) {
  return tr.lost[k] || unstable(tr.stability[k]);
}
std::string orderText(double o) {
  std::ostringstream os;
  os << o << "X";
  return os.str();
}
/// "track 3 (blade)" or "tracks 3,4 (blade1, blade2)".
std::string tracksText(const EngineOrderCrossing& c) {
  std::ostringstream os;
  os << "track" << (c.tracks.size() > 1 ? "s" : "");
  for (std::size_t i = 0; i < c.tracks.size(); ++i) os << (i ? "," : " ") << c.tracks[i] + 1;
  os << " (";
  for (std::size_t i = 0; i < c.dominant.size(); ++i) os << (i ? ", " : "") << c.dominant[i];
  os << ")";
  return os.str();
}
/// Whether unbalance excites the crossing: a 1X forward whirl seen from a
/// stationary (or the parent's) frame. Seen from the rotor's own frame the
/// rotor's unbalance is a static load: a crossing there is excited by n per
/// rev of something stationary (a blade's Campbell diagram), and forward and
/// backward are the senses in that frame (theory §12.2).
/// A backward whirl's orbit on anisotropic supports is an ellipse, whose
/// forward part unbalance excites (theory §12.2): above kEllipticalShare of
/// the orbit (a circle's is 0 to rounding; the overhung disc on a shaft of
/// two bending stiffnesses, axis ratio 0.15, had 0.35), it is excited (it
/// was said not to be, beside an unbounded response; found by a review).
constexpr double kEllipticalShare = 1e-2;
bool ellipticalBackward(const EngineOrderCrossing& c) {
  return c.whirl == Whirl::Backward && c.forwardShare > kEllipticalShare;
}
/// A repeated mode holding a forward and a backward whirl (a Jeffcott disc
/// at mid-span: no gyroscopic split) has a forward motion among its
/// combinations, which unbalance excites (it read "whirl unresolved", no
/// more; found by a review).
bool unresolvedWithForward(const EngineOrderCrossing& c) {
  return c.whirl == Whirl::Unresolved && c.forwardShare > kEllipticalShare;
}
bool unbalanceExcites(const EngineOrderCrossing& c, bool rotorFrame) {
  return !rotorFrame && c.order == 1.0 &&
         (c.whirl == Whirl::Forward || ellipticalBackward(c) || unresolvedWithForward(c));
}

std::string unbalanceNote(const EngineOrderCrossing& c, bool rotorFrame) {
  if (rotorFrame && (c.whirl == Whirl::Forward || c.whirl == Whirl::Backward)) {
    // A stationary force at nu, seen from a frame turning at Omega, is a
    // forward force at nu - Omega and a backward one at nu + Omega: a whirl
    // at n Omega in that frame is excited by a stationary force at (n + 1)
    // Omega (forward) or (n - 1) Omega (backward), not at n Omega (theory
    // §12.2; found by a review).
    const bool forward = c.whirl == Whirl::Forward;
    const double stationary = forward ? c.order + 1.0 : std::abs(c.order - 1.0);
    std::ostringstream os;
    os << (forward ? "forward" : "backward") << " in a spinning frame (the rotor's unbalance is no 1X force there; ";
    if (stationary == 0.0) os << "a static stationary load, gravity or a side load, excites it";
    else os << "a stationary force at " << orderText(stationary) << " excites it";
    os << " where that frame turns at the reference rate)";
    return os.str();
  }
  if (c.whirl == Whirl::Forward)
    return unbalanceExcites(c, rotorFrame) ? "forward: unbalance excites it" : "forward";
  if (c.whirl == Whirl::Backward && c.order == 1.0 && !rotorFrame && ellipticalBackward(c)) {
    std::ostringstream os;
    os << "backward, elliptical: unbalance excites its forward part (" << std::setprecision(2) << c.forwardShare
       << " of the orbit: anisotropy)";
    return os.str();
  }
  if (c.whirl == Whirl::Backward)
    return c.order == 1.0 ? (c.forwardShare < 0.0
                                 ? "backward: unbalance excites it only through anisotropy (an elliptical orbit) or a "
                                   "backward force"
                                 : "backward, circular: unbalance does not excite it (it would need anisotropy or a "
                                   "backward force)")
                          : "backward";
  if (c.order == 1.0 && !rotorFrame && unresolvedWithForward(c))
    return "forward and backward together (a repeated mode): unbalance excites the forward one";
  return c.whirl == Whirl::Neutral ? "no whirl" : "whirl unresolved";
}
}  // namespace

SpeedAxis speedAxis(const std::string& text, const std::string& option) {
  if (text == "hz") return SpeedAxis::Hz;
  if (text == "rpm") return SpeedAxis::Rpm;
  if (text == "per-rev") return SpeedAxis::PerRev;
  throw InputError(option + " = \"" + text + "\": expected hz, rpm or per-rev");
}

const char* toString(SpeedAxis a) {
  switch (a) {
    case SpeedAxis::Hz: return "hz";
    case SpeedAxis::Rpm: return "rpm";
    case SpeedAxis::PerRev: return "per-rev";
  }
  return "?";
}

void CampbellResult::printTable(std::ostream& os, SpeedAxis axis) const {
  const auto flags = os.flags();
  const auto prec = os.precision();
  const auto& ref = parameters[reference].name;
  const bool hz = axis == SpeedAxis::Hz;
  os << std::setw(8) << "factor" << std::setw(16) << (ref + (hz ? "(rev/s)" : "(rpm)"));
  for (const auto& p : parameters) os << std::setw(16) << (p.name + "(rad/s)");
  for (std::size_t t = 0; t < tracks.size(); ++t)
    os << std::setw(14) << ("track" + std::to_string(t + 1) + (axis == SpeedAxis::PerRev ? "(/rev)" : "(Hz)"))
       << std::setw(11) << "whirl";
  os << '\n';
  for (std::size_t k = 0; k < factors.size(); ++k) {
    const double Omega = speeds[k][reference];
    os << std::defaultfloat << std::setw(8) << std::setprecision(4) << factors[k] << std::setw(16)
       << std::setprecision(6) << Omega / (2 * M_PI) * (hz ? 1.0 : 60.0);
    for (double v : speeds[k]) os << std::setw(16) << std::setprecision(6) << v;
    for (const auto& tr : tracks) {
      const double y = axis == SpeedAxis::PerRev ? tr.omega[k] / std::abs(Omega) : tr.omega[k] / (2 * M_PI);
      // Per rev at rest is no number (inf or nan printed before): "-".
      if (axis == SpeedAxis::PerRev && Omega == 0.0 && !std::isnan(tr.omega[k])) os << std::setw(13) << "-";
      else os << std::setw(13) << std::setprecision(6) << y;
      os << (flagged(tr, k) ? '*' : ' ') << std::setw(11) << toString(tr.whirl[k]);
    }
    os << '\n';
  }
  os << "(* unstable or lost; whirl of " << (whirlOf.empty() ? "nothing (no spinning A or R)" : whirlOf)
     << ": FW with its spin, BW against, - none, unresolved: a cluster holding both senses, or no spin)\n";
  os.flags(flags);
  os.precision(prec);
}

void CampbellResult::printCrossings(std::ostream& os) const {
  const auto flags = os.flags();
  const auto prec = os.precision();
  const auto& ref = parameters[reference].name;
  os << "engine-order crossings (critical speeds) of '" << ref << "' (";
  for (std::size_t i = 0; i < orders.size(); ++i) os << (i ? ", " : "") << orderText(orders[i]);
  os << "; whirl of " << (whirlOf.empty() ? "-" : whirlOf) << "):\n";
  if (crossings.empty()) os << "  none in the sweep\n";
  for (const auto& c : crossings) {
    os << "  " << std::setw(5) << orderText(c.order) << std::setw(11) << toString(c.whirl) << std::fixed
       << std::setprecision(4) << std::setw(14) << c.speed << " rad/s" << std::setw(14) << c.speed * 30.0 / M_PI
       << " rpm" << std::setw(12) << c.omega / (2 * M_PI) << " Hz   " << unbalanceNote(c, whirlInRotorFrame) << "   "
       << tracksText(c);
    if (c.tracks.size() > 1) os << " (identical parts or a repeated mode: listed once)";
    if (!c.refined) os << " (linear between sweep speeds)";
    os << '\n';
    os.flags(flags);
  }
  // Zero frequencies (K(Omega) singular): a static mode of the swept frame.
  if (!zeroFrequencySpeeds.empty()) {
    os << "zero-frequency critical speeds of '" << ref
       << "' (a frequency passes through zero: K(Omega) singular; a static load of the swept frame excites it, "
          "such as the unbalance of a part turning with that frame):\n";
    for (std::size_t i = 0; i < zeroFrequencySpeeds.size(); ++i) {
      const double w = zeroFrequencySpeeds[i];
      os << "  " << std::setw(5) << "0X" << std::fixed << std::setprecision(4) << std::setw(25) << w << " rad/s"
         << std::setw(14) << w * 30.0 / M_PI << " rpm"
         << (i < zeroFrequencyRefined.size() && !zeroFrequencyRefined[i] ? " (not bisected: a count failed)" : "")
         << '\n';
      os.flags(flags);
    }
  }
  if (!zeroCountsNote.empty())
    os << "zero-frequency critical speeds: " << (zeroCountsTaken ? "a count failed: " : "not sought: ")
       << zeroCountsNote << '\n';
  std::vector<int> frame;
  for (std::size_t t = 0; t < tracks.size(); ++t)
    if (tracks[t].frameRate) frame.push_back(static_cast<int>(t));
  if (!frame.empty()) {
    os << "frame-rate tracks (a rigid motion seen at a spin rate, no vibration; their "
       << frameRateCrossings.size() + frameRateOnLine << " crossing(s) are not critical speeds";
    if (frameRateOnLine > 0)
      os << ", " << frameRateOnLine << " of them rounding about an engine-order line they follow";
    os << "):";
    for (int t : frame) os << " track" << t + 1 << " (" << parameters[tracks[t].frameRateOf].name << ")";
    os << '\n';
    for (const auto& c : frameRateCrossings) {
      os << "  " << std::setw(5) << orderText(c.order) << std::fixed << std::setprecision(4) << std::setw(14) << c.speed
         << " rad/s" << std::setw(14) << c.speed * 30.0 / M_PI << " rpm   frame rate, not a critical speed   "
         << tracksText(c) << (c.refined ? "" : " (linear between sweep speeds)") << '\n';
      os.flags(flags);
    }
  }
  // Modes that entered or left the requested set mid-sweep (theory §12.3):
  // a crossing of an entering mode below its first speed is not checked.
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    const auto& tr = tracks[t];
    const auto at = [&](std::size_t k) { return speeds[k][static_cast<std::size_t>(reference)]; };
    if (tr.firstStep > 0)
      os << "track" << t + 1 << " entered the requested modes at " << at(static_cast<std::size_t>(tr.firstStep))
         << " rad/s of '" << ref << "' (from above; its crossings below " << at(static_cast<std::size_t>(tr.firstStep))
         << " rad/s are not checked)\n";
    for (std::size_t k = static_cast<std::size_t>(tr.firstStep) + 1; k < tr.lost.size(); ++k) {
      if (!tr.lost[k] || tr.lost[k - 1]) continue;
      std::size_t back = k;
      while (back < tr.lost.size() && tr.lost[back]) ++back;
      os << "track" << t + 1 << " left the requested modes at " << at(k) << " rad/s of '" << ref << "'";
      if (back < tr.lost.size())  // its mode came back by shape: its crossings in between are not checked
        os << " and came back at " << at(back) << " rad/s (* in the table between; its crossings there not checked)\n";
      else
        os << " (lost from there: * in the table)\n";
    }
  }
  for (const auto& b : branchJumps)
    os << "track" << b.track + 1 << " jumps between two branches from " << b.from << " to " << b.to << " rad/s of '"
       << ref << "' (" << orderText(b.order) << " changes sign by the jump, not by a crossing: no critical speed "
       << "read there, and a crossing of either branch in between may be missed; a finer sweep follows them)\n";
  for (std::size_t i = 0; i < unstableRanges.size(); ++i) {
    const auto [a, b] = unstableRanges[i];
    const auto [fromStart, toEnd] = i < unstableOpen.size() ? unstableOpen[i] : std::make_pair(false, false);
    // An end of the sweep is no edge of the range: it goes on beyond it.
    // The stretches the stiffness count proves divergent are said apart
    // (the rest of a merged range may be a damped or gyroscopic
    // instability with an even count; a review).
    os << "unstable from " << a << " to " << b << " rad/s of '" << ref << "'" << (toEnd ? " and beyond" : "") << " (";
    if (i < unstableCountBands.size() && !unstableCountBands[i].empty()) {
      os << "divergence ";
      for (std::size_t c = 0; c < unstableCountBands[i].size(); ++c)
        os << (c > 0 ? " and " : "") << "from " << unstableCountBands[i][c].first << " to "
           << unstableCountBands[i][c].second;
      os << ": K(Omega) has an odd number of negative eigenvalues between two zero-frequency speeds, so det K < 0 "
            "and a real root lambda > 0, whether or not a sweep speed shows it; ";
    }
    os << (fromStart ? "unstable from the sweep's first speed; " : "") << (toEnd ? "still unstable at the sweep's end; " : "");
    const auto [lowBisected, highBisected] =
        i < unstableEdgesBisected.size() ? unstableEdgesBisected[i] : std::make_pair(unstableEdgesRefined, unstableEdgesRefined);
    const char* grid = "the sweep's unstable speed: up to a step outside";
    if (fromStart && toEnd) os << "no edge in the sweep)";
    else if (fromStart) os << "its upper edge " << (highBisected ? "bisected" : grid) << ")";
    else if (toEnd) os << "its lower edge " << (lowBisected ? "bisected" : grid) << ")";
    else if (lowBisected == highBisected) os << "edges " << (lowBisected ? "bisected)" : "the sweep's unstable speeds: up to a step outside)");
    else os << "lower edge " << (lowBisected ? "bisected" : grid) << ", upper edge " << (highBisected ? "bisected" : grid) << ")";
    os << '\n';
  }
  // A damped mode's growth its uncertainty does not decide (theory §13.3):
  // neither the unstable ranges above nor "stable".
  for (const auto& [a, b] : undecidedRanges) {
    os << "UNDECIDED " << (a == b ? "at " : "from ") << a;
    if (a != b) os << " to " << b;
    os << " rad/s of '" << ref
       << "' (the sweep's speeds, \"neutral\" in the CSV, and the speeds the bisection of an unstable edge met; "
          "a growth rate within its uncertainty of the Instability Tolerance: neither shown stable nor unstable "
          "there)\n";
  }
  os.flags(flags);
  os.precision(prec);
}

void CampbellResult::writeCsv(std::ostream& os) const {
  const auto prec = os.precision();
  os << std::setprecision(12) << "factor";
  std::vector<std::size_t> order{static_cast<std::size_t>(reference)};
  for (std::size_t p = 0; p < parameters.size(); ++p)
    if (static_cast<int>(p) != reference) order.push_back(p);
  for (auto p : order) os << ',' << csvField(parameters[p].name + "_rad_per_s");
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    const auto n = "track" + std::to_string(t + 1);
    os << ',' << n << "_hz," << n << "_stability," << n << "_damping_ratio," << n << "_whirl," << n << "_frame_rate";
  }
  os << '\n';
  for (std::size_t k = 0; k < factors.size(); ++k) {
    os << factors[k];
    for (auto p : order) os << ',' << speeds[k][p];
    for (const auto& tr : tracks)
      os << ',' << tr.omega[k] / (2 * M_PI) << ',' << stabilityText(tr, k) << ',' << tr.dampingRatio[k] << ','
         << toString(tr.whirl[k]) << ','
         << (tr.frameRate ? "yes" : "no");
    os << '\n';
  }
  os.precision(prec);
}

void CampbellResult::writeCrossingsCsv(std::ostream& os) const {
  const auto prec = os.precision();
  os << std::setprecision(12)
     << "order,speed_rad_per_s,speed_rpm,frequency_hz,whirl,unbalance,tracks,refined,dominant,forward_share\n";
  for (const auto& c : crossings) {
    os << c.order << ',' << c.speed << ',' << c.speed * 30.0 / M_PI << ',' << c.omega / (2 * M_PI) << ','
       << toString(c.whirl) << ',' << (unbalanceExcites(c, whirlInRotorFrame) ? "yes" : "no") << ',';
    for (std::size_t i = 0; i < c.tracks.size(); ++i) os << (i ? ";" : "") << "track" << c.tracks[i] + 1;
    os << ',' << (c.refined ? "yes" : "no") << ',';
    std::string dominant;
    for (std::size_t i = 0; i < c.dominant.size(); ++i) dominant += (i ? ";" : "") + c.dominant[i];
    os << csvField(dominant) << ',';
    if (c.forwardShare >= 0.0) os << c.forwardShare;  // empty: not known
    os << '\n';
  }
  // Zero-frequency critical speeds: order 0, no track (theory §12.1).
  // unbalance "frame": a static load of the swept frame excites it (the
  // unbalance of a part turning with that frame; theory §12.1).
  for (std::size_t i = 0; i < zeroFrequencySpeeds.size(); ++i) {
    const double w = zeroFrequencySpeeds[i];
    const bool refinedHere = i >= zeroFrequencyRefined.size() || zeroFrequencyRefined[i];
    os << 0 << ',' << w << ',' << w * 30.0 / M_PI << ',' << 0 << ',' << toString(Whirl::Neutral) << ",frame,,"
       << (refinedHere ? "yes" : "no") << ",,\n";
  }
  os.precision(prec);
}

}  // namespace cms::analysis
