// Damping through the stack (theory §13.1): dampers and Rayleigh damping
// assembled by fem, carried by the substructure, projected by the
// synthesis (T_s^T D_s T_s) and solved on the general paths; modal damping
// of a reduced substructure. At 1 and 2 ranks (the MPI main min-reduces).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <Teuchos_DefaultComm.hpp>

#include <Teuchos_LAPACK.hpp>

#include "BeamModels.hpp"
#include "DenseOf.hpp"
#include "HubBoomStructure.hpp"
#include "cms/core/Error.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "StructureModels.hpp"
#include "cms/analysis/TruthComparison.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

using namespace cms;
using namespace cms::synthesis;

namespace {
auto world() { return Teuchos::DefaultComm<int>::getComm(); }
const double eps = std::numeric_limits<double>::epsilon();

/// A clamped aluminium cantilever (1 m, 20 frame elements) as the structure's C.
StructureDescription cantilever(const fem::StructuralDamping& damping, const std::string& basis, int vectors) {
  fem::BeamSection sec{0.01, 1e-5, 1e-5, 2e-5};
  auto model = fixtures::frameModel(fixtures::lineMesh(1.0, 20), {7e10, 0.3, 2700.0}, sec);
  fem::FixedSet clamp;
  clamp.name = "clamp";
  clamp.nodeSet = "root";
  clamp.all = true;
  model.fixed.push_back(clamp);
  model.damping = damping;
  SubstructureSpec C;
  C.name = "beam";
  C.kind = SubstructureKind::Central;
  C.model = std::make_shared<fem::FiniteElementModel>(model);
  C.reduction.set("Basis", basis);
  if (vectors > 0) C.reduction.set("Vectors", vectors);
  StructureDescription d;
  d.substructures.push_back(C);
  return d;
}

StructureModes solveWith(const SynthesizedStructure& s, const std::string& solver, int modes) {
  Teuchos::ParameterList p;
  p.set("Solver", solver);
  p.set("Number of Modes", modes);
  return s.solve({}, p);
}

/// The frequency scale the dense path's absolute accuracy is relative to:
/// dggev is normwise backward stable on the time-scaled pencil, so a mode's
/// eigenvalue is good to about 10 N eps s (N = 2n) in absolute terms.
double denseScale(const SynthesizedStructure& s) {
  const auto sys = s.system({});
  return eigen::frequencyScale(sys.M->getFrobeniusNorm(), sys.D->getFrobeniusNorm(), sys.K->getFrobeniusNorm());
}
}  // namespace

TEST(DampedStructure, RayleighDampedBeamHasAlphaOver2wPlusBetaWOver2) {
  // D = alpha M + beta K is diagonal in the undamped modes: each mode is a
  // damped single DOF of frequency w_j = |lambda_j| and ratio
  // zeta_j = alpha / (2 w_j) + beta w_j / 2.
  const double alpha = 20.0, beta = 2e-5;
  const auto a = AssembledStructure::assemble(cantilever({alpha, beta, 0.0}, "Full", 0), world());
  const auto s = SynthesizedStructure::synthesize(a);
  ASSERT_FALSE(s.damping().is_null());
  const auto dense = solveWith(s, "Dense", 6);
  EXPECT_NE(dense.result.reason.find("damped"), std::string::npos) << dense.result.reason;
  const double n = static_cast<double>(s.size()), scale = denseScale(s);
  ASSERT_EQ(dense.result.modes.size(), 6u);
  for (const auto& m : dense.result.modes) {
    const double w = std::abs(m.lambda), zeta = alpha / (2 * w) + beta * w / 2;
    // zeta = -Re/|lambda|: its error is the eigenvalue's, 10 N eps s, over |lambda|.
    EXPECT_NEAR(m.dampingRatio, zeta, 10.0 * 2 * n * eps * scale / w) << "w = " << w;
    EXPECT_EQ(m.stability, eigen::Stability::Stable);
  }
  // The sparse non-Hermitian path agrees to its Residual Tolerance (1e-8).
  const auto sparse = solveWith(s, "Sparse", 6);
  ASSERT_EQ(sparse.result.status, eigen::SolveStatus::Converged) << sparse.result.reason;
  ASSERT_EQ(sparse.result.modes.size(), dense.result.modes.size());
  for (std::size_t k = 0; k < dense.result.modes.size(); ++k)
    EXPECT_LT(std::abs(sparse.result.modes[k].lambda - dense.result.modes[k].lambda),
              1e-8 * std::abs(dense.result.modes[k].lambda)) << "mode " << k;
}

TEST(DampedStructure, ModalDampingGivesEveryReducedModeItsRatio) {
  // A clamped C reduced to its own 8 lowest modes: the modal damping
  // 2 zeta (V^T K V)^(1/2) = diag(2 zeta w_j) gives every mode exactly zeta.
  const double zeta = 0.03;
  const auto a = AssembledStructure::assemble(cantilever({0.0, 0.0, zeta}, "Modes", 8), world());
  const auto s = SynthesizedStructure::synthesize(a);
  const auto r = solveWith(s, "Dense", 8);
  ASSERT_EQ(r.result.modes.size(), 8u);
  const double n = static_cast<double>(s.size()), scale = denseScale(s);
  for (const auto& m : r.result.modes)
    EXPECT_NEAR(m.dampingRatio, zeta, 10.0 * 2 * n * eps * scale / std::abs(m.lambda)) << m.lambda;
  // A Full substructure has no modal coordinates: refused, saying so.
  const auto full = AssembledStructure::assemble(cantilever({0.0, 0.0, zeta}, "Full", 0), world());
  try {
    SynthesizedStructure::synthesize(full);
    FAIL() << "modal damping of a Full substructure was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Rayleigh"), std::string::npos) << e.what();
  }
}

TEST(DampedStructure, GroundedAndTwoNodeDampersAssembleAsDerived) {
  // Two point masses (3 translations each): a at the origin on a grounded
  // spring k_g and damper c_g, b joined to a by a spring k and damper c.
  // Per direction: M = diag(m_a, m_b), K = [[k_g + k, -k], [-k, k]],
  // D = [[c_g + c, -c], [-c, c]]: the synthesised structure (Full) must be
  // this system, and its modes the dense solution of it.
  auto mesh = std::make_shared<mesh::Mesh>();
  mesh->source = "two masses (in code)";
  mesh->nodeTags = {1, 2};
  mesh->coordinates = {0, 0, 0, 1, 0, 0};
  fixtures::addPointGroup(*mesh, "a", {0});
  fixtures::addPointGroup(*mesh, "b", {1});
  const double ma = 2.0, mb = 1.0, kg[3] = {400, 900, 1600}, k = 100, cg = 3.0, c = 0.5;
  fem::FiniteElementModel model;
  model.name = "masses";
  model.mesh = mesh;
  model.pointMasses.push_back({"ma", "a", ma, {}});
  model.pointMasses.push_back({"mb", "b", mb, {}});
  fem::SpringSet ground{"ground", "a", "", {kg[0], kg[1], kg[2], 0, 0, 0}, {}};
  fem::SpringSet joint{"joint", "a", "b", {k, k, k, 0, 0, 0}, {}};
  fem::SpringSet groundDamper{"groundDamper", "a", "", {}, {cg, cg, cg, 0, 0, 0}};
  fem::SpringSet jointDamper{"jointDamper", "a", "b", {}, {c, c, c, 0, 0, 0}};
  model.springs = {ground, joint, groundDamper, jointDamper};
  SubstructureSpec C;
  C.name = "masses";
  C.kind = SubstructureKind::Central;
  C.model = std::make_shared<fem::FiniteElementModel>(model);
  C.reduction.set("Basis", std::string("Full"));
  StructureDescription d;
  d.substructures.push_back(C);
  const auto a = AssembledStructure::assemble(d, world());
  const auto s = SynthesizedStructure::synthesize(a);
  const auto sys = s.denseSystem({});
  ASSERT_EQ(sys.size(), 6);
  ASSERT_EQ(sys.D.numRows(), 6);
  // Rows: node a (ux uy uz), then node b.
  eigen::GyroscopicSystem ref{DenseMatrix(6, 6), DenseMatrix(6, 6), DenseMatrix(6, 6), DenseMatrix(6, 6)};
  for (int i = 0; i < 3; ++i) {
    ref.M(i, i) = ma, ref.M(3 + i, 3 + i) = mb;
    ref.K(i, i) = kg[i] + k, ref.K(3 + i, 3 + i) = k, ref.K(i, 3 + i) = ref.K(3 + i, i) = -k;
    ref.D(i, i) = cg + c, ref.D(3 + i, 3 + i) = c, ref.D(i, 3 + i) = ref.D(3 + i, i) = -c;
  }
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) {
      // Sums of a few exact element entries: equal to their rounding.
      EXPECT_NEAR(sys.D(i, j), ref.D(i, j), 4 * eps * (cg + c)) << i << "," << j;
      EXPECT_NEAR(sys.K(i, j), ref.K(i, j), 4 * eps * (kg[2] + k)) << i << "," << j;
    }
  const auto got = solveWith(s, "Dense", 6).result;
  const auto want = eigen::DenseGyroscopicSolver().solve(ref);
  ASSERT_EQ(got.modes.size(), 6u);
  const double scale = eigen::frequencyScale(ref.M.normFrobenius(), ref.D.normFrobenius(), ref.K.normFrobenius());
  for (std::size_t m = 0; m < 6; ++m) {
    EXPECT_LE(std::abs(got.modes[m].lambda - want.modes[m].lambda), 10.0 * 12 * eps * scale) << m;
    EXPECT_GT(got.modes[m].dampingRatio, 0.0);
  }
}

TEST(DampedStructure, ErrorEstimatesIncludeTheDamping) {
  // A reduced Rayleigh-damped cantilever (zeta 0.05 to 0.3 over the modes)
  // against its truth: each mode's estimate of |lambda - lambda_truth| /
  // |lambda| (its residual with lambda D u, theory §11.8) within a factor 3
  // of the true error, as for the undamped structures (ErrorEstimate tests).
  const double alpha = 8.0, beta = 1e-4;
  const auto truth = SynthesizedStructure::synthesize(AssembledStructure::assemble(cantilever({alpha, beta, 0.0}, "Full", 0), world()));
  const auto exact = solveWith(truth, "Dense", 6);
  int checked = 0;
  for (int vectors : {3, 5}) {
    const auto s = SynthesizedStructure::synthesize(
        AssembledStructure::assemble(cantilever({alpha, beta, 0.0}, "Admissible", vectors), world()));
    const auto m = solveWith(s, "Dense", 4);
    const auto e = s.errorEstimates(m);
    for (std::size_t j = 0; j < m.result.modes.size(); ++j) {
      const auto l = m.result.modes[j].lambda, t = exact.result.modes[j].lambda;
      const double err = std::abs(l - t) / std::abs(t);
      // Below 1e-9 the truth's own rounding; past 10% the estimate is a flag.
      if (err <= 1e-9 || e[j] >= 0.1) continue;
      ++checked;
      EXPECT_LE(e[j], 3.0 * err) << vectors << " vectors, mode " << j + 1 << ", zeta " << m.result.modes[j].dampingRatio;
      EXPECT_GE(e[j], err / 3.0) << vectors << " vectors, mode " << j + 1 << ", zeta " << m.result.modes[j].dampingRatio;
    }
  }
  EXPECT_GE(checked, 3);
}

namespace {
/// Mode m = e_j of `s`, expanded: each substructure's physical displacement.
std::vector<Teuchos::RCP<MultiVector>> unitExpansion(const SynthesizedStructure& s, long long j) {
  StructureModes u;
  u.result.modes.resize(1);
  u.result.modes[0].q.assign(static_cast<std::size_t>(s.size()), 0.0);
  u.result.modes[0].q[static_cast<std::size_t>(j)] = 1.0;
  return s.expand(u, 0);
}

/// Column c of a replicated copy of a distributed vector.
std::vector<double> gathered(const MultiVector& x, int c) {
  const auto map = x.getMap();
  std::vector<double> local(map->getGlobalNumElements(), 0.0), all(local.size(), 0.0);
  const auto d = x.getData(c);
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l)
    local[static_cast<std::size_t>(map->getGlobalElement(static_cast<LocalOrdinal>(l)))] = d[l];
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), all.data());
  return all;
}
}  // namespace

TEST(DampedStructure, ModalDampingEstimatesAgainstTheTruthItDefines) {
  // A clamped hub (Full) carrying a boom reduced to Admissible vectors with a
  // modal damping ratio, at rest and spinning. Its damping D_eta lives in the
  // boom's own coordinates eta; the truth it stands for damps the same
  // relative motion V eta by M V (V^T M V)^-1 D_eta (V^T M V)^-1 V^T M
  // (theory §11.8), whose projection is D_eta. That truth is built here from
  // its definition (the Full model's matrices plus this block on the boom's
  // coordinates) and solved densely; each reduced mode's estimate must lie
  // within the factor 3 of the other estimate tests of its true error. The
  // estimates read the modal damping force as residual before (a floor of
  // 5e-3 at zeta = 0.05 where the true errors are far smaller).
  const double zeta = 0.05;
  fixtures::HubBoom hb;
  auto d = hb.structure(false, "Admissible", 4);
  d.substructures.pop_back();  // one boom: no near-repeated pairs to pair by index
  d.substructures[0].reduction.set("Basis", std::string("Full"));
  auto boom = *d.substructures[1].model;
  boom.damping = {0.0, 0.0, zeta};
  d.substructures[1].model = std::make_shared<fem::FiniteElementModel>(boom);
  int checked = 0;
  for (int vectors : {4, 6}) {
    d.substructures[1].reduction.set("Vectors", vectors);
    const auto a = AssembledStructure::assemble(d, world());
    const auto s = SynthesizedStructure::synthesize(a);
    const auto t = SynthesizedStructure::synthesize(a, true);
    ASSERT_EQ(t.modalDampingOmitted(), std::vector<std::string>{"boom+"});
    // V: the boom's columns of the reduced model, on its physical rows
    // (the hub's coordinates zero, so its attachment does not move).
    const long long off = s.coordinateOffsets()[1], k = s.reductions()[1].coordinates;
    ASSERT_EQ(k, vectors);
    std::vector<std::vector<double>> V;
    for (long long j = 0; j < k; ++j) V.push_back(gathered(*unitExpansion(s, off + j)[1], 0));
    // The truth's boom coordinates: e_j moves one boom row alone.
    std::vector<std::pair<long long, std::size_t>> own;  // (truth coordinate, boom row)
    for (long long j = 0; j < t.size(); ++j) {
      const auto u = unitExpansion(t, j);
      const auto hub = gathered(*u[0], 0), b = gathered(*u[1], 0);
      bool hubMoves = false;
      for (double x : hub) hubMoves = hubMoves || x != 0.0;
      std::vector<std::size_t> rows;
      for (std::size_t r = 0; r < b.size(); ++r)
        if (b[r] != 0.0) rows.push_back(r);
      if (!hubMoves && rows.size() == 1 && b[rows[0]] == 1.0) own.push_back({j, rows[0]});
    }
    ASSERT_EQ(own.size(), static_cast<std::size_t>(6 * hb.boomElements));  // every boom DOF off its attachment
    for (double speed : {0.0, hb.Omega}) {
      SCOPED_TRACE(std::to_string(vectors) + " vectors, Omega = " + std::to_string(speed));
      const std::vector<double> speeds{speed};
      auto truth = t.denseSystem(speeds);
      const auto red = s.denseSystem(speeds);
      const int n = truth.size(), no = static_cast<int>(own.size()), kk = static_cast<int>(k);
      // Vt = V on the truth's boom coordinates; MV = M_ff Vt; G = Vt^T M_ff Vt.
      DenseMatrix Vt(no, kk), MV(no, kk), G(kk, kk), De(kk, kk);
      for (int i = 0; i < no; ++i)
        for (int c = 0; c < kk; ++c) Vt(i, c) = V[c][own[i].second];
      for (int i = 0; i < no; ++i)
        for (int c = 0; c < kk; ++c)
          for (int l = 0; l < no; ++l) MV(i, c) += truth.M(own[i].first, own[l].first) * Vt(l, c);
      for (int i = 0; i < kk; ++i)
        for (int c = 0; c < kk; ++c) {
          for (int l = 0; l < no; ++l) G(i, c) += Vt(l, i) * MV(l, c);
          De(i, c) = red.D(off + i, off + c);
        }
      // P = MV G^-1, then D_t = P D_eta P^T on the boom's coordinates.
      DenseMatrix Ginv(G);
      Teuchos::LAPACK<int, double> lapack;
      int info = 0;
      std::vector<int> piv(kk);
      std::vector<double> work(64 * kk);
      lapack.GETRF(kk, kk, Ginv.values(), Ginv.stride(), piv.data(), &info);
      ASSERT_EQ(info, 0);
      lapack.GETRI(kk, Ginv.values(), Ginv.stride(), piv.data(), work.data(), static_cast<int>(work.size()), &info);
      ASSERT_EQ(info, 0);
      DenseMatrix P(no, kk), PD(no, kk);
      P.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, MV, Ginv, 0.0);
      PD.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, P, De, 0.0);
      truth.D = DenseMatrix(n, n);
      for (int i = 0; i < no; ++i)
        for (int j = 0; j < no; ++j) {
          double v = 0.0;
          for (int c = 0; c < kk; ++c) v += PD(i, c) * P(j, c);
          truth.D(own[i].first, own[j].first) = v;
        }
      Teuchos::ParameterList tp;
      tp.set("Number of Modes", 6);
      const auto exact = eigen::DenseGyroscopicSolver(tp).solve(truth);
      Teuchos::ParameterList p;
      p.set("Solver", std::string("Dense"));
      p.set("Number of Modes", 4);
      const auto m = s.solve(speeds, p);
      const auto e = s.errorEstimates(m);
      for (std::size_t j = 0; j < m.result.modes.size(); ++j) {
        const auto l = m.result.modes[j].lambda, tl = exact.modes[j].lambda;
        const double err = std::abs(l - tl) / std::abs(tl);
        EXPECT_NEAR(m.result.modes[j].dampingRatio, zeta, 0.02) << "mode " << j + 1;  // the boom's modes
        // Below 1e-9 the truth's own rounding; past 10% the estimate is a flag.
        if (err <= 1e-9 || e[j] >= 0.1) continue;
        ++checked;
        EXPECT_LE(e[j], 3.0 * err) << "mode " << j + 1 << ": true error " << err;
        EXPECT_GE(e[j], err / 3.0) << "mode " << j + 1 << ": true error " << err;
      }
    }
  }
  EXPECT_GE(checked, 8);
}

TEST(DampedStructure, ModalDampingAcrossABooleanInterfaceIsPrestressedAndRefusedAsATruth) {
  // Two spinning boxes joined by a Boolean interface, the tip modally
  // damped: the joined prestress is solved on the truth model (theory
  // §11.4), which has no modal coordinates. The assembly refused the whole
  // structure before ("a Modal Damping Ratio needs a reduced basis"): the
  // truth now leaves the ratio out and says so, and the comparisons with it
  // refuse, naming the substructure.
  auto d = fixtures::booleanSplitBar(1.0, 0.2, 0.1, {2, 1, 1}, 30.0, true);
  d.substructures[0].reduction.set("Basis", std::string("Full"));
  auto tip = *d.substructures[1].model;
  tip.damping = {0.0, 0.0, 0.02};
  d.substructures[1].model = std::make_shared<fem::FiniteElementModel>(tip);
  d.substructures[1].reduction.set("Basis", std::string("Admissible"));
  d.substructures[1].reduction.set("Vectors", 6);
  const auto structure = AssembledStructure::assemble(d, world());
  bool joined = false;  // the prestress solved on the truth model
  for (const auto& n : structure.notes()) joined = joined || n.find("joined by Boolean interfaces") != std::string::npos;
  EXPECT_TRUE(joined);
  const auto s = SynthesizedStructure::synthesize(structure);
  ASSERT_FALSE(s.damping().is_null());
  EXPECT_TRUE(s.modalDampingOmitted().empty());
  const auto t = SynthesizedStructure::synthesize(structure, true);
  EXPECT_EQ(t.modalDampingOmitted(), std::vector<std::string>{"tip"});
  EXPECT_TRUE(t.damping().is_null());
  Teuchos::ParameterList p;
  p.set("Number of Modes", 3);
  const auto m = s.solve({30.0}, p);
  try {
    analysis::compareWithTruth(s, m, t, t.solve({30.0}, p), 3);
    FAIL() << "a truth without the tip's modal damping was compared with";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'tip'"), std::string::npos) << e.what();
  }
  // The count of undamped truth frequencies is not made (code -3: damped).
  EXPECT_EQ(analysis::truthFrequenciesBelow(t, {30.0}, 1e6), -3);
}
