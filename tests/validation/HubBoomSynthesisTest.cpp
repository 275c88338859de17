// A spinning hub with two flexible booms (doc/theory.md §11.7), through the
// whole synthesis path:
//  (a) hub clamped at its centre, K > 0: the truth equals one monolithic FE
//      model of the same structure to round-off; every basis kind converges
//      to it from above as vectors are added (nested subspaces, Rayleigh-Ritz
//      bounds), and adding one vector to one boom interlaces the frequencies
//      (inclusion principle, seed eqs. (28)-(29));
//  (b) hub free-floating (K indefinite in the spinning frame): the truth
//      equals the monolithic free model; reductions converge, no bound claimed;
//  (c) the same reduced matrices and frequencies on 1 and 2 ranks (each rank
//      also solves alone on MPI_COMM_SELF);
//  (d) the error-versus-DOFs table of the basis kinds, against the copy kept
//      in doc/bench/basis-comparison.csv.
#include <gtest/gtest.h>

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_Vector.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

#include <Teuchos_DefaultComm.hpp>
#include <Teuchos_DefaultSerialComm.hpp>

#include "DenseOf.hpp"
#include "ExpectError.hpp"
#include "HubBoomStructure.hpp"
#include "cms/core/Error.hpp"
#include "cms/analysis/TruthComparison.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/substructure/Substructure.hpp"

using namespace cms;
using namespace cms::synthesis;

namespace {

const fixtures::HubBoom hb;
const int kModes = 8;

Teuchos::RCP<const Teuchos::Comm<int>> world() { return Teuchos::DefaultComm<int>::getComm(); }

StructureModes solve(const SynthesizedStructure& s, int modes = kModes) {
  Teuchos::ParameterList p;
  p.set("Number of Modes", modes);
  return s.solve({hb.Omega}, p);
}

/// The same basis kind and vector count for every substructure.
std::vector<Teuchos::ParameterList> everywhere(const AssembledStructure& a, const std::string& basis, int k) {
  return sameReduction(a, basis, k);
}

const double eps = std::numeric_limits<double>::epsilon();

/// The elastic modes (above 1.5 Omega: past the rigid-body and frame modes
/// of the free structure) of a result, ascending.
std::vector<eigen::GyroscopicMode> elasticModes(const eigen::GyroscopicResult& r, bool free) {
  std::vector<eigen::GyroscopicMode> e;
  for (const auto& m : r.modes)
    if (!free || m.omega > 1.5 * hb.Omega) e.push_back(m);
  return e;
}

/// Their frequencies.
std::vector<double> elastic(const eigen::GyroscopicResult& r, bool free) {
  std::vector<double> w;
  for (const auto& m : elasticModes(r, free)) w.push_back(m.omega);
  return w;
}

/// The first-order condition number of the frequency w of a mass-normalised
/// mode q of (M, G, K) under normwise relative perturbations of the matrices
/// (Tisseur 2000, normalised as the solvers' residual, doc/theory.md §4):
/// kappa = (||K|| + w ||G|| + w^2 ||M||) ||q||^2 / (2 w^2). A solve with
/// backward error eta (the mode's residual) has w to ~ eta kappa.
double frequencyCondition(const DenseMatrix& M, const DenseMatrix& G, const DenseMatrix& K,
                          const eigen::GyroscopicMode& m) {
  const double w = m.omega;
  double q2 = 0;
  for (const auto& v : m.q) q2 += std::norm(v);
  return (frobeniusNorm(K) + w * frobeniusNorm(G) + w * w * frobeniusNorm(M)) * q2 / (2 * w * w);
}

/// |w_a / w_b - 1| for the same mode of the same structure assembled twice
/// (matrices equal up to the rounding of their sums, ~eps of their norms)
/// and solved independently with backward errors eta_a, eta_b: first order,
/// (eta_a + eta_b + eps) kappa, with a factor 4 for the higher-order terms
/// and the two assemblies' rounding.
double agreementBound(double kappa, const eigen::GyroscopicMode& a, const eigen::GyroscopicMode& b) {
  return 4 * (a.residual + b.residual + eps) * kappa;
}

/// The monolithic model solved densely (independent of the synthesis code).
struct Monolithic {
  eigen::GyroscopicSystem system;
  eigen::GyroscopicResult result;
};
Monolithic monolithic(bool free) {
  auto model = hb.monolithic(free);
  fem::PrestressConditions pc;
  if (free) {
    const auto centre = model.mesh->nodeSet("centre").front();
    for (int c = 0; c < 6; ++c) pc.held.push_back({centre, static_cast<fem::Component>(c), 0.0});
  }
  const auto sub = substructure::Substructure::fromFiniteElementModel(model, world(), pc);
  const auto m = sub.atSpeed(hb.Omega);
  eigen::GyroscopicSystem sys{fixtures::denseOf(*m.M), fixtures::denseOf(*m.G), fixtures::denseOf(*m.K)};
  Teuchos::ParameterList p;
  p.set("Number of Modes", 20);
  return {sys, eigen::DenseGyroscopicSolver(p).solve(sys)};
}

}  // namespace

TEST(HubBoom, TruthEqualsMonolithicModel) {
  for (bool free : {false, true}) {
    SCOPED_TRACE(free ? "free" : "clamped");
    const auto structure = AssembledStructure::assemble(hb.structure(free, "Full", 0), world());
    const auto truth = SynthesizedStructure::synthesize(structure, true);
    const auto t = solve(truth, 20);
    const auto mono = monolithic(free);
    const auto mt = elasticModes(t.result, free), mm = elasticModes(mono.result, free);
    ASSERT_GE(mt.size(), 6u);
    ASSERT_GE(mm.size(), 6u);
    // Round-off: the same matrices up to the order of summation (and, free,
    // the exact zero of K on the rigid coordinates), each solved backward
    // stably: agreementBound, with kappa ~ 1e9 for the lowest modes of these
    // beams (||K|| is the hub's axial stiffness). Measured: 1e-13 clamped
    // (Meirovitch's SVD), up to 1.2e-8 free (dggev on the 2n pencil; the
    // kernels move it: 1.6e-9 Haswell, 1.2e-8 Nehalem): below 1e-2 of the
    // bound, which is 1e-7 to 2e-6 here.
    const auto d = truth.denseSystem({hb.Omega});
    for (std::size_t r = 0; r < 6; ++r) {
      const double kappa = std::max(frequencyCondition(d.M, d.G, d.K, mt[r]),
                                    frequencyCondition(mono.system.M, mono.system.G, mono.system.K, mm[r]));
      EXPECT_NEAR(mt[r].omega / mm[r].omega, 1.0, agreementBound(kappa, mt[r], mm[r]))
          << "mode " << r << ": kappa " << kappa << ", residuals " << mt[r].residual << ", " << mm[r].residual;
    }
    if (!free) EXPECT_NE(t.result.solver.find("Meirovitch"), std::string::npos) << t.result.solver;
  }
}

TEST(HubBoom, ClampedReductionsConvergeFromAboveAndInterlace) {
  const auto structure = AssembledStructure::assemble(hb.structure(false, "Full", 0), world());
  const auto truth = SynthesizedStructure::synthesize(structure, true);
  const auto t = solve(truth);
  const auto wt = analysis::frequencies(t);
  for (const std::string basis : {"Admissible", "Modes", "Craig-Bampton"}) {
    SCOPED_TRACE(basis);
    std::vector<double> previous;
    for (int k : {3, 5, 8, 12}) {
      const auto s = SynthesizedStructure::synthesize(structure, everywhere(structure, basis, k));
      if (s.size() < kModes) continue;
      const auto m = solve(s);
      const auto w = analysis::frequencies(m);
      EXPECT_NE(m.result.solver.find("Meirovitch"), std::string::npos);
      // Rayleigh-Ritz upper bounds on the truth (K > 0), to rounding:
      // relative, the clamped truth's frequencies being good to ~1e-13
      // (TruthEqualsMonolithicModel), the reduced models' better.
      for (int r = 0; r < kModes; ++r) EXPECT_GE(w[r], wt[r] * (1 - 1e-9)) << "k " << k << " mode " << r;
      // Nested bases: adding vectors never raises a frequency.
      if (!previous.empty())
        for (int r = 0; r < kModes; ++r) EXPECT_LE(w[r], previous[r] * (1 + 1e-9)) << "k " << k << " mode " << r;
      previous = w;
    }
    // Converged: the largest bases reproduce the lowest four to 1e-4.
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(previous[r] / wt[r], 1.0, 1e-4) << basis << " mode " << r;
  }
  // Inclusion principle: one more admissible vector on one boom.
  for (int k = 2; k < 7; ++k) {
    std::vector<double> w[2];
    for (int extra : {0, 1}) {
      std::vector<Teuchos::ParameterList> red;
      for (std::size_t q = 0; q < structure.numSubstructures(); ++q) {
        const SubstructureSpec& sp = structure.substructure(q);
        Teuchos::ParameterList r("Reduction");
        r.set("Basis", std::string("Admissible"));
        r.set("Vectors", sp.name == "boom+" ? k + extra : 4);
        red.push_back(r);
      }
      const auto s = SynthesizedStructure::synthesize(structure, red);
      Teuchos::ParameterList p;
      p.set("Number of Modes", static_cast<int>(s.size()));
      w[extra] = analysis::frequencies(s.solve({hb.Omega}, p));
    }
    const auto violations = analysis::checkInclusion(w[0], w[1]);
    EXPECT_THROW(analysis::checkInclusion(w[0], w[1], 1e-9, 0), InputError);
    for (const auto& v : violations)
      ADD_FAILURE() << "inclusion principle violated (boom+ " << k << " -> " << k + 1 << " vectors): mode "
                    << v.index << ", " << v.inequality << " by " << v.amount;
  }
}

TEST(HubBoom, MoreModesThanCoordinatesAreAllReturnedAndSaidSo) {
  // A request past the reduced model's size was cut to it silently (found
  // by a review): every mode is returned, and the reason says so, alone and
  // in a sweep.
  const auto structure = AssembledStructure::assemble(hb.structure(false, "Admissible", 4), world());
  const auto s = SynthesizedStructure::synthesize(structure, everywhere(structure, "Admissible", 4));
  const long long n = s.size();
  Teuchos::ParameterList p;
  p.set("Number of Modes", static_cast<int>(n + 5));
  const std::string note = "asks for more than the reduced model's " + std::to_string(n) + " coordinates";
  const auto one = s.solve({hb.Omega}, p);
  EXPECT_EQ(static_cast<long long>(one.result.modes.size()), n);
  EXPECT_NE(one.result.reason.find(note), std::string::npos) << one.result.reason;
  for (const auto& m : s.solveMany({{0.0}, {hb.Omega}}, p, 2)) {
    EXPECT_EQ(static_cast<long long>(m.result.modes.size()), n);
    EXPECT_NE(m.result.reason.find(note), std::string::npos) << m.result.reason;
  }
}

TEST(HubBoom, AFreeStructureHeldToTheGroundIsRefused) {
  // The synthesis makes K exactly zero on a free structure's six rigid-body
  // coordinates (theory §11.6): a grounded spring or a support on any part
  // lost its hold there and its coupling to the elastic coordinates, and the
  // six zeros still read as the free body's rigid modes. Refused, naming the
  // part and the item; before, both were accepted (found by a review).
  // The free structure with one item added to a boom's model.
  const auto freeWith = [](std::size_t boom, const std::function<void(fem::FiniteElementModel&)>& add) {
    auto d = hb.structure(true, "Full", 0);
    auto model = *d.substructures[boom].model;
    add(model);
    d.substructures[boom].model = std::make_shared<fem::FiniteElementModel>(model);
    return d;
  };
  const auto spring = [](const char* name, std::array<double, 6> stiffness, std::array<double, 6> damping) {
    fem::SpringSet k;
    k.name = name, k.nodeSet = "end", k.stiffness = stiffness, k.damping = damping;
    return k;
  };
  fixtures::expectInputError(
      [&] {
        AssembledStructure::assemble(freeWith(1, [&](auto& m) { m.springs.push_back(spring("suspension", {10, 10, 10, 0, 0, 0}, {})); }),
                                     world());
      },
      "'boom+' of a free-floating structure (Free Reference) has the grounded spring \"suspension\"");
  fixtures::expectInputError(
      [&] { AssembledStructure::assemble(freeWith(2, [](auto& m) { m.fixed.push_back({"tip", "end", {}, true}); }), world()); },
      "'boom-' of a free-floating structure (Free Reference) fixes DOFs (\"tip\")");
  // A grounded damper holds nothing still: accepted.
  EXPECT_NO_THROW(AssembledStructure::assemble(
      freeWith(1, [&](auto& m) { m.springs.push_back(spring("dashpot", {}, {1, 1, 1, 0, 0, 0})); }), world()));
}

TEST(HubBoom, FreeReductionsConvergeToTruth) {
  const auto structure = AssembledStructure::assemble(hb.structure(true, "Full", 0), world());
  const auto truth = SynthesizedStructure::synthesize(structure, true);
  const auto wt = elastic(solve(truth, 20).result, true);
  for (const std::string basis : {"Admissible", "Modes", "Craig-Bampton"}) {
    SCOPED_TRACE(basis);
    double first = -1, last = -1;
    for (int k : {4, 12}) {
      const auto s = SynthesizedStructure::synthesize(structure, everywhere(structure, basis, k));
      const auto w = elastic(solve(s, 20).result, true);
      ASSERT_GE(w.size(), 4u);
      double err = 0;
      for (int r = 0; r < 4; ++r) err = std::max(err, std::abs(w[r] / wt[r] - 1));
      (first < 0 ? first : last) = err;
    }
    EXPECT_LT(last, first) << "no convergence";
    EXPECT_LT(last, 1e-3);
  }
}

TEST(HubBoom, SameOnEveryRankCount) {
  // Each rank also builds the structure alone; the distributed reduced
  // matrices and frequencies must agree with the serial ones.
  auto self = Teuchos::rcp(new Teuchos::SerialComm<int>());
  std::vector<double> w[2];
  DenseMatrix K[2], M[2];
  int i = 0;
  for (auto comm : {world(), Teuchos::RCP<const Teuchos::Comm<int>>(self)}) {
    const auto structure = AssembledStructure::assemble(hb.structure(false, "Admissible", 6), comm);
    const auto s = SynthesizedStructure::synthesize(structure);
    const auto d = s.denseSystem({hb.Omega});
    K[i] = d.K, M[i] = d.M;
    w[i] = analysis::frequencies(solve(s));
    ++i;
  }
  ASSERT_EQ(K[0].numRows(), K[1].numRows());
  // Matrices: projections summed in a different order (1e-12 of the norm;
  // measured 4e-16 on 2 ranks, natively and with OPENBLAS_CORETYPE=Nehalem
  // set by hand); frequencies: 1e-10 relative (issue 6's target; measured
  // 1e-13). Regression bounds relative to what they bound.
  double dk = 0, dm = 0;
  for (int c = 0; c < K[0].numCols(); ++c)
    for (int r = 0; r < K[0].numRows(); ++r) {
      dk = std::max(dk, std::abs(K[0](r, c) - K[1](r, c)));
      dm = std::max(dm, std::abs(M[0](r, c) - M[1](r, c)));
    }
  EXPECT_LE(dk, 1e-12 * frobeniusNorm(K[1]));
  EXPECT_LE(dm, 1e-12 * frobeniusNorm(M[1]));
  for (std::size_t r = 0; r < w[0].size(); ++r) EXPECT_NEAR(w[0][r] / w[1][r], 1.0, 1e-10);
}

TEST(HubBoom, ConcurrentAndDistributedSchedulesAgree) {
  // The same assembled structure reduced with each substructure whole on
  // one rank (concurrently) and with each distributed over every rank: the
  // same bases up to the order of sums (the same CHOLMOD factor, gathered:
  // the orthonormalisation's and projections' sums differ), so the same
  // reduced matrices and frequencies. Measured on 2 ranks, natively and
  // with OPENBLAS_CORETYPE=Nehalem set by hand: 1e-18 of the norms, 2e-14
  // in the frequencies. The bounds, 1e-12 of the norms (~4500 eps) and
  // 1e-10 relative (issue 6's target), are regression bounds relative to
  // what they bound, not derived from a condition estimate (eps times the
  // held stiffness's 2.2e7 would be looser). On one rank both
  // schedules are the same code path. The first synthesis after the assembly
  // takes the prestress factorisations kept for the booms, which adopt
  // them and so stay distributed (theory §11.4); a later one finds none
  // kept and gathers every reduced substructure: both are compared.
  const auto structure = AssembledStructure::assemble(hb.structure(false, "Craig-Bampton", 6), world());
  const auto red = everywhere(structure, "Craig-Bampton", 6);
  const auto adopting = SynthesizedStructure::synthesize(structure, red, ReductionSchedule::Concurrent);
  const auto a = SynthesizedStructure::synthesize(structure, red, ReductionSchedule::Concurrent);
  const auto b = SynthesizedStructure::synthesize(structure, red, ReductionSchedule::Distributed);
  int adopted = 0;
  for (std::size_t k = 0; k < adopting.reductions().size(); ++k) {
    adopted += adopting.reductions()[k].adoptedPrestressFactor;
    EXPECT_FALSE(a.reductions()[k].adoptedPrestressFactor) << k << ": the factors were taken by the first synthesis";
  }
  EXPECT_GE(adopted, 2) << "the booms adopt their prestress factorisations";
  for (const SynthesizedStructure* x : {&a, &adopting}) {
    ASSERT_EQ(x->size(), b.size());
    const auto da = x->denseSystem({hb.Omega}), db = b.denseSystem({hb.Omega});
    EXPECT_LE(fixtures::maxAbsDifference(da.K, db.K), 1e-12 * frobeniusNorm(db.K));
    EXPECT_LE(fixtures::maxAbsDifference(da.M, db.M), 1e-12 * frobeniusNorm(db.M));
    const auto wa = analysis::frequencies(solve(*x)), wb = analysis::frequencies(solve(b));
    for (std::size_t r = 0; r < wa.size(); ++r) EXPECT_NEAR(wa[r] / wb[r], 1.0, 1e-10) << "mode " << r;
    // What each rank found reaches every rank: labels and the truncation guide.
    for (std::size_t k = 0; k < x->reductions().size(); ++k) {
      EXPECT_EQ(x->reductions()[k].labels, b.reductions()[k].labels) << k;
      ASSERT_EQ(x->reductions()[k].frequencyEstimates.size(), b.reductions()[k].frequencyEstimates.size()) << k;
      for (std::size_t j = 0; j < x->reductions()[k].frequencyEstimates.size(); ++j)
        EXPECT_NEAR(x->reductions()[k].frequencyEstimates[j] / b.reductions()[k].frequencyEstimates[j], 1.0, 1e-10);
    }
  }
}

TEST(HubBoom, ConcurrentReductionFailureReachesEveryRank) {
  // A substructure that cannot be reduced (more vectors than free DOFs) on
  // whichever rank owns it: every rank throws the same error, naming it,
  // instead of waiting for a rank that gave up (a hang).
  const auto structure = AssembledStructure::assemble(hb.structure(false, "Admissible", 6), world());
  for (std::size_t bad = 0; bad < structure.numSubstructures(); ++bad) {
    auto red = everywhere(structure, "Admissible", 6);
    red[bad].set("Vectors", 100000);
    try {
      SynthesizedStructure::synthesize(structure, red, ReductionSchedule::Concurrent);
      ADD_FAILURE() << "no error for substructure " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(structure.substructure(bad).name), std::string::npos) << e.what();
    }
  }
}

TEST(HubBoom, BasisComparisonTableMatchesDoc) {
  // Error against DOFs for each basis kind on the clamped structure: the
  // table in doc/bench/basis-comparison.csv is this output (regenerate with
  // CMS_WRITE_TABLE=path). The ordering of the kinds is recorded there as a
  // finding; here only the numbers are checked to stay true.
  const auto structure = AssembledStructure::assemble(hb.structure(false, "Full", 0), world());
  const auto truth = SynthesizedStructure::synthesize(structure, true);
  const auto t = solve(truth);
  EXPECT_THROW(analysis::compareWithTruth(truth, t, truth, t, kModes + 1), InputError);
  std::ostringstream table;
  table << "basis,vectors_per_substructure,reduced_dofs,max_rel_error_lowest6,mean_rel_error_lowest6,worst_mac\n";
  std::map<std::string, std::vector<double>> computed;
  for (const std::string basis : {"Guyan", "Admissible", "Modes", "Craig-Bampton"}) {
    for (int k : basis == "Guyan" ? std::vector<int>{0} : std::vector<int>{2, 4, 6, 8, 12}) {
      const auto s = SynthesizedStructure::synthesize(structure, everywhere(structure, basis, k));
      if (s.size() < 6) continue;
      const auto m = solve(s, static_cast<int>(std::min<long long>(s.size(), kModes)));
      const auto c = analysis::compareWithTruth(s, m, truth, t, 6);
      table << basis << ',' << k << ',' << s.size() << ',' << std::setprecision(4) << c.maxRelativeError << ','
            << c.meanRelativeError << ',' << std::setprecision(6) << c.worstMac << '\n';
      computed[basis + "," + std::to_string(k)] = {double(s.size()), c.maxRelativeError, c.worstMac};
    }
  }
  if (const char* path = std::getenv("CMS_WRITE_TABLE")) std::ofstream(path) << table.str();
  std::ifstream in(std::string(CMS_SOURCE_DIR) + "/doc/bench/basis-comparison.csv");
  ASSERT_TRUE(in) << "doc/bench/basis-comparison.csv missing; this run gives:\n" << table.str();
  std::string line;
  std::getline(in, line);
  int rows = 0;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string basis, k, n, maxErr, meanErr, mac;
    std::getline(ls, basis, ','), std::getline(ls, k, ','), std::getline(ls, n, ',');
    std::getline(ls, maxErr, ','), std::getline(ls, meanErr, ','), std::getline(ls, mac, ',');
    const auto it = computed.find(basis + "," + k);
    ASSERT_NE(it, computed.end()) << "doc row not computed: " << line;
    EXPECT_EQ(std::stod(n), it->second[0]) << line;
    // The file keeps 4 significant digits (1e-3 of the value, relative);
    // the errors are themselves relative, and below 1e-9 they are the
    // models' rounding (the truth's own error, TruthEqualsMonolithicModel).
    // The MAC is in [0, 1] and kept to 6 digits: 1e-5.
    const double e = std::stod(maxErr);
    EXPECT_NEAR(it->second[1], e, std::max(1e-3 * e, 1e-9)) << line;
    EXPECT_NEAR(it->second[2], std::stod(mac), 1e-5) << line;
    ++rows;
  }
  EXPECT_EQ(rows, static_cast<int>(computed.size())) << "this run gives:\n" << table.str();
}

TEST(HubBoom, SparseAnasaziPathAgreesWithDensePath) {
  // The reduced and the truth systems through Anasazi (Tpetra matrices, the
  // path of large reduced systems) and through LAPACK. The sparse solver
  // promises a backward error (its residual eta <= 1e-8); the frequency it
  // implies differs by at most ~ eta kappa with the first-order condition
  // number kappa = (||K|| + w ||G|| + w^2 ||M||) ||q||^2 / (2 w^2) of the
  // mass-normalised mode q (||q||^2 >> 1 for the truth's low modes): the
  // bound asserted, agreementBound (both solvers' residuals and the
  // rounding of the matrices, with a factor 4).
  const auto structure = AssembledStructure::assemble(hb.structure(false, "Admissible", 8), world());
  for (bool truth : {false, true}) {
    SCOPED_TRACE(truth ? "truth" : "reduced");
    const auto s = SynthesizedStructure::synthesize(structure, truth);
    StructureModes m[2];
    int i = 0;
    for (const std::string path : {"Dense", "Sparse"}) {
      Teuchos::ParameterList p;
      p.set("Solver", path);
      p.set("Number of Modes", 6);
      m[i] = s.solve({hb.Omega}, p);
      EXPECT_NE(m[i].path.find(path == "Dense" ? "dense" : "sparse"), std::string::npos) << m[i].path;
      EXPECT_EQ(m[i].result.status, eigen::SolveStatus::Converged) << m[i].result.reason;
      ++i;
    }
    const auto d = s.denseSystem({hb.Omega});
    ASSERT_EQ(m[0].result.modes.size(), m[1].result.modes.size());
    for (std::size_t r = 0; r < m[0].result.modes.size(); ++r) {
      const auto &dm = m[0].result.modes[r], &sm = m[1].result.modes[r];
      const double kappa = frequencyCondition(d.M, d.G, d.K, dm);
      EXPECT_LE(std::abs(sm.omega / dm.omega - 1.0), agreementBound(kappa, dm, sm))
          << "mode " << r << " residual " << sm.residual << " kappa " << kappa;
    }
  }
}

TEST(HubBoom, FreeStructureOnTheSparsePathGetsAShift) {
  // K is singular for a free structure: the sparse path shifts its
  // transform automatically (and says so); its elastic frequencies match
  // the dense path's within the solver's residual bound (1e-6 here).
  const auto structure = AssembledStructure::assemble(hb.structure(true, "Full", 0), world());
  const auto s = SynthesizedStructure::synthesize(structure, true);
  std::vector<double> w[2];
  int i = 0;
  for (const std::string path : {"Dense", "Sparse"}) {
    Teuchos::ParameterList p;
    p.set("Solver", path);
    p.set("Number of Modes", 16);
    const auto m = s.solve({hb.Omega}, p);
    EXPECT_EQ(m.result.status, eigen::SolveStatus::Converged) << m.path << ": " << m.result.reason;
    if (path == "Sparse") EXPECT_NE(m.path.find("automatic Shift"), std::string::npos) << m.path;
    w[i++] = elastic(m.result, true);
  }
  ASSERT_GE(w[1].size(), 4u);
  for (int r = 0; r < 4; ++r) EXPECT_NEAR(w[1][r] / w[0][r], 1.0, 1e-6) << "mode " << r;
}

TEST(HubBoom, SolidChildOnARigidLinkKeepsSixRigidBodyModes) {
  // A free beam hub carrying a Hex8 block whose "reference" nodes move
  // rigidly with the hub's end node (RBE2-like): at rest the structure has
  // exactly six zero frequencies, truth and reduced, and its mass is the sum.
  auto d = hb.structure(true, "Admissible", 6);
  d.substructures.pop_back();
  auto& boom = d.substructures.back();
  boom.name = "block";
  boom.model = std::make_shared<fem::FiniteElementModel>(
      fixtures::solidModel(fixtures::boxMesh(0.4, 0.3, 0.2, 2, {hb.h + 0.2, 0, 0}), {7e10, 0.33, 2700}));
  boom.attachment.childNodes = "reference";
  d.substructures[0].spin.reset();
  for (bool truth : {false, true}) {
    SCOPED_TRACE(truth ? "truth" : "reduced");
    const auto a = AssembledStructure::assemble(d, world());
    const auto s = SynthesizedStructure::synthesize(a, truth);
    Teuchos::ParameterList p;
    p.set("Number of Modes", 8);
    const auto m = s.solve({}, p);
    int rigid = 0;
    for (const auto& mode : m.result.modes) rigid += mode.stability == eigen::Stability::RigidBody;
    EXPECT_EQ(rigid, 6);
    EXPECT_GT(m.result.modes[6].omega, 1.0);
    const auto M = s.denseSystem({}).M;
    const double mass = 7800 * hb.hubSection.A * 2 * hb.h + 2700 * 0.4 * 0.3 * 0.2;
    // Relative: a sum of the elements' masses projected on the rigid
    // coordinates, a few eps per element (12 here): 1e-12 ~ 4500 eps.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(M(c, c) / mass, 1.0, 1e-12);
  }
}

TEST(BooleanInterface, SplitBarEqualsOneMeshAndCraigBamptonConverges) {
  // A spinning steel bar of Hex8 cells, clamped at x = 0, as two boxes
  // sharing the face x = a (compatible meshes, primal assembly) and as one
  // mesh. With and without stress stiffening the truth equals the one-mesh
  // model to round-off (agreementBound, kappa 2e3 to 6e5, ~1e-9; measured
  // below 5e-3 of it): with it, the
  // prestress of boxes joined by a Boolean interface is one static problem
  // (theory §11.4; holding the face instead was 5e-5 off).
  const double a = 1.0, b = 0.2, c = 0.1, W = 30.0;
  const fem::IsotropicMaterial steel{2e11, 0.3, 7800};
  bool stiffening = false;
  auto d = [&](const std::string& basis, int k) {
    auto s = fixtures::booleanSplitBar(a, b, c, {2, 2, 2}, W, stiffening);
    s.substructures[0].reduction.set("Basis", basis);
    // The root has 27 DOFs off its clamp and its interface: all its
    // fixed-interface modes (asking more is an input error, issue 14 item 9).
    s.substructures[0].reduction.set("Vectors", basis == "Craig-Bampton" ? std::min(k, 27) : k);
    s.substructures[1].reduction.set("Basis", basis);
    s.substructures[1].reduction.set("Vectors", k);
    return s;
  };
  auto solveAt = [&](const SynthesizedStructure& s, int n) {
    Teuchos::ParameterList p;
    p.set("Number of Modes", n);
    return analysis::frequencies(s.solve({W}, p));
  };
  std::vector<double> wt;
  for (bool on : {true, false}) {
    SCOPED_TRACE(on ? "stress stiffening" : "no stress stiffening");
    stiffening = on;
    auto mono = fixtures::solidModel(fixtures::boxMesh(2 * a, b, c, {4, 2, 2}, {a, 0, 0}), steel);
    mono.fixed.push_back({"clamp", "xmin", {}, true});
    mono.spin = fem::SpinDefinition{fem::Spin{{0, 0, 1}, {0, 0, 0}}, fem::SpinDefinition::Frame::Rotating, on};
    const auto ms = substructure::Substructure::fromFiniteElementModel(mono, world());
    const auto mm = ms.atSpeed(W);
    Teuchos::ParameterList dp;
    dp.set("Number of Modes", 8);
    const eigen::GyroscopicSystem one{fixtures::denseOf(*mm.M), fixtures::denseOf(*mm.G), fixtures::denseOf(*mm.K)};
    const auto ref = eigen::DenseGyroscopicSolver(dp).solve(one);
    const auto structure = AssembledStructure::assemble(d("Full", 0), world());
    EXPECT_EQ(structure.notes().size(), on ? 1u : 0u);
    const auto truth = SynthesizedStructure::synthesize(structure, true);
    const auto t = truth.solve({W}, dp);
    const auto td = truth.denseSystem({W});
    wt = analysis::frequencies(t);
    for (int r = 0; r < 8; ++r) {
      const auto &tm = t.result.modes[r], &rm = ref.modes[r];
      const double kappa = std::max(frequencyCondition(td.M, td.G, td.K, tm), frequencyCondition(one.M, one.G, one.K, rm));
      EXPECT_NEAR(tm.omega / rm.omega, 1.0, agreementBound(kappa, tm, rm)) << "mode " << r << ": kappa " << kappa;
    }
  }
  for (const std::string basis : {"Craig-Bampton", "Admissible"}) {
    SCOPED_TRACE(basis);
    std::vector<double> previous;
    for (int k : {4, 16, 40}) {
      const auto st = AssembledStructure::assemble(d(basis, k), world());
      const auto w = solveAt(SynthesizedStructure::synthesize(st), 6);
      for (int r = 0; r < 6; ++r) EXPECT_GE(w[r], wt[r] * (1 - 1e-9)) << "k " << k << " mode " << r;
      if (!previous.empty())
        for (int r = 0; r < 6; ++r) EXPECT_LE(w[r], previous[r] * (1 + 1e-9)) << "k " << k << " mode " << r;
      previous = w;
    }
    // 40 of the 54 free DOFs of each box: both kinds close in (the first
    // 27 admissible vectors of the root are its interface loads).
    EXPECT_NEAR(previous[0] / wt[0], 1.0, 1e-6);
  }
}

TEST(HubBoom, StiffnessRatioOfAMillion) {
  // Extremes: the hub 1e6 times stiffer (E = 2e17; its bending stiffness
  // ~2e9 times the booms'). Reference: the rigid-hub limit, one boom clamped
  // at radius h and spinning (the hub's compliance moves it by ~1e-9), each
  // of its frequencies a pair of the structure's.
  // Finding (doc/theory.md §11.7): the full models, truth and monolithic
  // alike, are limited by rounding, eps kappa with kappa = (w_max / w_1)^2 ~
  // 3e13 (a pessimistic 6e-3); measured 2.4e-6 on 1 rank and 1.1e-5 on 2
  // (the rounding, hence the error, depends on the rank count), and their
  // pairs split by as much; 1.2e-4 on 2 ranks with OpenBLAS's Nehalem
  // kernels. Asserted to that bound, eps kappa, kappa from max K_ii / M_ii
  // (a lower bound of w_max^2) over the truth's w_1^2. Craig-Bampton with few hub vectors is better conditioned: its pairs
  // are equal, it bounds the rigid-hub limit from above, and converges to it.
  fixtures::HubBoom stiff = hb;
  stiff.hubMaterial.E *= 1e6;
  const auto structure = AssembledStructure::assemble(stiff.structure(false, "Full", 0), world());
  const auto wt = analysis::frequencies(solve(SynthesizedStructure::synthesize(structure, true), 6));
  Teuchos::ParameterList p;
  p.set("Number of Modes", 6);
  const auto dense = [&](const substructure::Substructure& sub) {
    const auto m = sub.atSpeed(stiff.Omega);
    return eigen::DenseGyroscopicSolver(p).solve(
        {fixtures::denseOf(*m.M), fixtures::denseOf(*m.G), fixtures::denseOf(*m.K)});
  };
  const auto mono = dense(substructure::Substructure::fromFiniteElementModel(stiff.monolithic(false), world()));
  auto boom = *stiff.structure(false, "Full", 0).substructures[1].model;
  boom.fixed.push_back({"root", "start", {}, true});
  boom.spin = fem::SpinDefinition{fem::Spin{{0, 0, 1}, {0, 0, 0}}, fem::SpinDefinition::Frame::Rotating, true};
  const auto alone = dense(substructure::Substructure::fromFiniteElementModel(boom, world()));
  double lambdaMax = 0.0;
  {
    const auto whole = substructure::Substructure::fromFiniteElementModel(stiff.monolithic(false), world());
    Vector dK(whole.K()->getRowMap()), dM(whole.M()->getRowMap());
    whole.K()->getLocalDiagCopy(dK);
    whole.M()->getLocalDiagCopy(dM);
    const auto k = dK.getData(), m = dM.getData();
    double mine = 0.0;
    for (std::size_t l = 0; l < k.size(); ++l)
      if (m[l] > 0) mine = std::max(mine, k[l] / m[l]);
    Teuchos::reduceAll(*world(), Teuchos::REDUCE_MAX, mine, Teuchos::outArg(lambdaMax));
  }
  const double rounding = std::numeric_limits<double>::epsilon() * lambdaMax / (wt[0] * wt[0]);
  ASSERT_LT(rounding, 1e-2) << "kappa " << lambdaMax / (wt[0] * wt[0]);  // still a meaningful check
  for (int r = 0; r < 6; ++r) {
    const double ref = alone.modes[r / 2].omega;
    EXPECT_NEAR(wt[r] / ref, 1.0, rounding) << "truth mode " << r;
    EXPECT_NEAR(mono.modes[r].omega / ref, 1.0, rounding) << "monolithic mode " << r;
  }
  std::vector<double> previous;
  for (int k : {4, 8}) {
    const auto s = SynthesizedStructure::synthesize(structure, everywhere(structure, "Craig-Bampton", k));
    const auto w = analysis::frequencies(solve(s, 6));
    for (int r = 0; r < 6; ++r) {
      const double ref = alone.modes[r / 2].omega;
      EXPECT_GE(w[r], ref * (1 - 1e-9)) << "k " << k << " mode " << r;
      if (r % 2) EXPECT_NEAR(w[r] / w[r - 1], 1.0, 1e-9) << "pair " << r;
      if (!previous.empty()) EXPECT_LE(w[r], previous[r] * (1 + 1e-9));
    }
    previous = w;
  }
  for (int r = 0; r < 6; ++r) EXPECT_NEAR(previous[r] / alone.modes[r / 2].omega, 1.0, 2e-6);
}

TEST(HubBoom, MassRatioOfAMillion) {
  // Extremes: a point mass 1e6 times a boom's mass (1.6e6 kg) at each boom
  // tip. The truth equals the monolithic model to round-off, and the
  // reductions bound it from above and converge. (At 0.02 rad/s, above the
  // tip masses' first frequency, K is indefinite and admissible vectors were
  // still 20% off at 12 vectors: no bound holds there.)
  fixtures::HubBoom heavy = hb;
  heavy.tipMass = 1e6 * 2700 * hb.boomSection.A * hb.L;
  heavy.Omega = 1e-3;  // below the tip masses' first frequency, ~3.8e-3 rad/s: K > 0
  const auto structure = AssembledStructure::assemble(heavy.structure(false, "Full", 0), world());
  Teuchos::ParameterList p;
  p.set("Number of Modes", 6);
  const auto wt = analysis::frequencies(SynthesizedStructure::synthesize(structure, true).solve({heavy.Omega}, p));
  const auto sub = substructure::Substructure::fromFiniteElementModel(heavy.monolithic(false), world());
  const auto m = sub.atSpeed(heavy.Omega);
  const auto mono = eigen::DenseGyroscopicSolver(p).solve(
      {fixtures::denseOf(*m.M), fixtures::denseOf(*m.G), fixtures::denseOf(*m.K)});
  // Relative, to round-off of two Meirovitch solves of the same matrices:
  // measured 2e-12 (Haswell) to 4e-11 (Nehalem). The normwise
  // agreementBound is not informative here (~1e-4: these masses inflate
  // ||M|| and the residuals to 3e-14); 1e-8 leaves a factor 250 and still
  // sees any difference of model.
  for (int r = 0; r < 6; ++r) EXPECT_NEAR(wt[r] / mono.modes[r].omega, 1.0, 1e-8) << "mode " << r;
  for (const std::string basis : {"Admissible", "Craig-Bampton"}) {
    std::vector<double> previous;
    for (int k : {4, 8, 12}) {
      const auto w = analysis::frequencies(
          SynthesizedStructure::synthesize(structure, everywhere(structure, basis, k)).solve({heavy.Omega}, p));
      // Upper bounds up to the truth's own rounding: eps (w_max / w_1)^2 ~
      // 1e-5 at worst with these masses; measured 2e-7.
      for (int r = 0; r < 6; ++r)
        EXPECT_GE(w[r], wt[r] * (1 - 1e-6)) << basis << " k " << k << " mode " << r << " rel " << w[r] / wt[r] - 1;
      if (!previous.empty())
        for (int r = 0; r < 6; ++r) EXPECT_LE(w[r], previous[r] * (1 + 1e-6)) << basis << " k " << k;  // the same floor
      previous = w;
    }
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(previous[r] / wt[r], 1.0, 1e-4) << basis << " mode " << r;
  }
}

TEST(HubBoom, FineMeshTruthOnTheSparsePath) {
  // 2000 elements per boom (2.4e4 truth coordinates, past the dense limit):
  // the projections' rounding, eps ||A|| ||t_i|| ||t_j||, exceeded the
  // dense solver's 1e-10 symmetry check inside both the synthesis and the
  // sparse solver's Rayleigh-Ritz extraction until both kept the exactly
  // symmetric parts. Truth (Anasazi) and 20 admissible vectors agree.
  fixtures::HubBoom fine = hb;
  fine.boomElements = 2000;
  const auto structure = AssembledStructure::assemble(fine.structure(false, "Admissible", 20), world());
  const auto truth = SynthesizedStructure::synthesize(structure, true);
  const auto reduced = SynthesizedStructure::synthesize(structure);
  Teuchos::ParameterList p;
  p.set("Number of Modes", 4);
  const auto t = truth.solve({fine.Omega}, p), r = reduced.solve({fine.Omega}, p);
  EXPECT_NE(t.path.find("sparse"), std::string::npos) << t.path;
  ASSERT_EQ(t.result.status, eigen::SolveStatus::Converged) << t.result.reason;
  ASSERT_EQ(r.result.status, eigen::SolveStatus::Converged) << r.result.reason;
  // Finding: with 1.5 mm frame elements on 3 m booms the full model's
  // conditioning, ~(L/h)^4 ~ 1e13, leaves its frequencies uncertain at
  // ~1e-4 although its residuals are ~1e-18 (normwise, dominated by the
  // short elements' stiffness): the reduced model even falls 1e-4 below it,
  // which no exact truth would allow. Agreement is asserted to 1e-3 only.
  for (int m = 0; m < 4; ++m)
    EXPECT_NEAR(r.result.modes[m].omega / t.result.modes[m].omega, 1.0, 1e-3) << "mode " << m;
}
