// Hinges (theory §17): an exact joint between coincident frame nodes, free
// about one axis, eliminated at assembly (u = T u_free). Checks that the
// constraint holds to round-off in every mode, that a hinged rigid link has
// the closed-form spring frequency and a zero-frequency rigid rotation when
// free, that a hinge about an axis along no coordinate axis gives the
// frequencies of the aligned model turned rigidly (spinning, with stress
// stiffening), that the hinge's damper is D = c w w^T on the hinge rotation,
// and the input errors. At 1 and 2 ranks (the MPI main min-reduces).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_Map.hpp>

#include "DenseOf.hpp"
#include "ExpectError.hpp"
#include "HingedBlade.hpp"
#include "cms/core/Error.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/fem/FiniteElementAssembly.hpp"
#include "cms/fem/RigidPlacement.hpp"

using namespace cms;
using fem::Component;

namespace {
auto world() { return Teuchos::DefaultComm<int>::getComm(); }
const double eps = std::numeric_limits<double>::epsilon();

/// M, G, K(Omega) = K + Omega^2 (KS1 - KT1) of an assembled model, dense.
eigen::GyroscopicSystem denseSystem(const fem::AssembledMatrices& a, double Omega) {
  eigen::GyroscopicSystem s;
  s.M = fixtures::denseOf(*a.M);
  s.K = fixtures::denseOf(*a.K);
  const int n = s.M.numRows();
  s.G.shape(n, n);
  if (Omega != 0.0) {
    const DenseMatrix G1 = fixtures::denseOf(*a.G1), KT1 = fixtures::denseOf(*a.KT1);
    const DenseMatrix KS1 = a.KS1.is_null() ? DenseMatrix(n, n) : fixtures::denseOf(*a.KS1);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        s.G(i, j) = Omega * G1(i, j);
        s.K(i, j) += Omega * Omega * (KS1(i, j) - KT1(i, j));
      }
  }
  return s;
}

eigen::GyroscopicResult solveAll(const eigen::GyroscopicSystem& s) {
  Teuchos::ParameterList p;
  p.set("Method", "Meirovitch");  // K > 0 in these tests; omega to eps * omega_max (theory §2)
  return eigen::DenseGyroscopicSolver(p).solve(s);
}

double largestOmega(const eigen::GyroscopicResult& r) {
  double w = 0.0;
  for (const auto& m : r.modes) w = std::max(w, m.omega);
  return w;
}

/// Value of (node, c) in the full (unconstrained) DOF set: its row, or its
/// hinge expression, or 0 for a fixed DOF; `bound` gets sum |coef u_row|,
/// what rounding of the expression is relative to.
std::complex<double> fullValue(const fem::AssembledMatrices& a, const std::vector<std::complex<double>>& q,
                               std::int64_t node, Component c, double& bound) {
  const long long r = a.layout.row(node, c);
  if (r >= 0) {
    bound += std::abs(q[r]);
    return q[r];
  }
  for (const auto& d : a.dependent)
    if (d.node == node && d.component == c) {
      std::complex<double> v = 0.0;
      for (const auto& [row, w] : d.terms) v += w * q[row], bound += std::abs(w * q[row]);
      return v;
    }
  return 0.0;
}
}  // namespace

// In every mode of a blade on a spring hinge about a skew axis, the pair's
// translations and the two rotations normal to the axis are equal: the
// expansion u = T u_free is exact to the rounding of its own few terms
// (4 eps of the sum of their magnitudes), and the hinge rotation itself is
// far above that (the joint does move).
TEST(Hinge, ConstraintIsExactInEveryMode) {
  fixtures::HingedBladeSpec b;
  b.hingeAxis = fem::unit({0.3, -0.5, 0.8});
  b.stiffness = 2000.0;
  b.spinning = true;
  const auto model = fixtures::hingedBlade(b);
  const auto a = fem::assemble(model, world());
  const std::int64_t hub = b.hubElements, root = b.hubElements + 1;
  ASSERT_EQ(a.dependent.size(), 5u);  // all but the kept rotation of the second node
  ASSERT_EQ(a.layout.componentCount(root), 1);
  const auto r = solveAll(denseSystem(a, 20.0));
  ASSERT_EQ(static_cast<int>(r.modes.size()), a.M->getGlobalNumRows());
  const fem::Vec3 n = fem::unit(b.hingeAxis);
  double largestHingeRotation = 0.0;
  for (const auto& m : r.modes) {
    double bound = 0.0;
    std::array<std::complex<double>, 6> ua, ub;
    for (int c = 0; c < 6; ++c) {
      ua[c] = fullValue(a, m.q, hub, static_cast<Component>(c), bound);
      ub[c] = fullValue(a, m.q, root, static_cast<Component>(c), bound);
    }
    for (int c = 0; c < 3; ++c) EXPECT_LE(std::abs(ub[c] - ua[c]), 4 * eps * bound) << "omega " << m.omega;
    std::complex<double> phi = 0.0;
    for (int c = 0; c < 3; ++c) phi += n[c] * (ub[3 + c] - ua[3 + c]);
    for (int c = 0; c < 3; ++c)
      EXPECT_LE(std::abs(ub[3 + c] - ua[3 + c] - n[c] * phi), 4 * eps * bound) << "omega " << m.omega;
    largestHingeRotation = std::max(largestHingeRotation, std::abs(phi) / std::max(bound, 1e-300));
  }
  EXPECT_GT(largestHingeRotation, 0.1);
}

// A stiff link on a hinge with a spring k (at rest): the rigid link turns
// about the hinge at nu^2 = k / I, I = rho A L^3 / 3 about the hinge. The
// link's flexibility lowers nu by 1.2e7 / (2 E) = 1.1e-8 (measured at
// E = 7e10, 7e12, 5.3e13: the 1/E law), and the rounding of K (entries of
// EI / h^3 that cancel in the rigid rotation) moves it by up to 1e-7 here
// (measured over E = 2e14 .. 5.3e15, growing with E; theory §17.3): 2e-7
// bounds the two (measured: -5.4e-8). The inverse first-order form and
// Meirovitch's solver agreed to every printed digit over that scan: the
// matrices, not the solver, set the floor. Without the spring the same
// rotation is a zero-frequency
// mode: K v = 0 to round-off of ||K|| ||v||, and v^T M v = I exactly (the
// consistent mass is exact for the linear field of a rigid rotation).
TEST(Hinge, SpringHingedRigidLinkHasSqrtKOverI) {
  fixtures::HingedBladeSpec b;
  b.stiffness = 2000.0;
  const auto a = fem::assemble(fixtures::hingedBlade(b), world());
  const auto s = denseSystem(a, 0.0);
  const auto w = fixtures::lowestFrequencies(s.M, s.G, s.K, 2);
  const double nu = std::sqrt(b.stiffness / b.inertia());
  EXPECT_NEAR(w[0] / nu - 1.0, 0.0, 2e-7) << w[0] << " vs " << nu;
  EXPECT_GT(w[1], 100 * nu);  // every other mode is elastic, far above

  b.stiffness = 0.0;
  const auto f = fem::assemble(fixtures::hingedBlade(b), world());
  const DenseMatrix K = fixtures::denseOf(*f.K), M = fixtures::denseOf(*f.M);
  std::vector<double> v(K.numRows(), 0.0);
  const auto& mesh = *fixtures::hingedBlade(b).mesh;
  for (std::int64_t node = b.hubElements + 1; node < static_cast<std::int64_t>(mesh.nodeCount()); ++node) {
    const double x = mesh.x(node)[0] - b.e;  // a unit rotation about z through the hinge: u_y = x, theta_z = 1
    if (long long row = f.layout.row(node, Component::UY); row >= 0) v[row] = x;
    v[f.layout.row(node, Component::RZ)] = 1.0;
  }
  double Kv = 0.0, vv = 0.0, vMv = 0.0;
  for (int i = 0; i < K.numRows(); ++i) {
    double s = 0.0, sm = 0.0;
    for (int j = 0; j < K.numRows(); ++j) s += K(i, j) * v[j], sm += M(i, j) * v[j];
    Kv += s * s, vv += v[i] * v[i], vMv += v[i] * sm;
  }
  // ||K v|| against rounding of ||K|| ||v|| (K entries of EI/h^3 ~ 1e13 cancel).
  EXPECT_LE(std::sqrt(Kv), 100 * eps * frobeniusNorm(K) * std::sqrt(vv));
  EXPECT_NEAR(vMv / b.inertia(), 1.0, 100 * eps);
}

// Invariance: the same spinning blade (lag hinge with a spring, stress
// stiffening, Coriolis) turned rigidly by 0.7 rad about (1, 2, 3), so that
// neither the hinge nor the spin axis is along a coordinate axis, has the
// frequencies of the aligned one. The dense solve gives omega to about
// eps omega_max (Meirovitch's SVD, theory §2): 1e3 eps omega_max bounds the
// difference of two such solves of differently rounded matrices (measured:
// ~2e-12 of omega_max). Also for the flap hinge (axis along y).
TEST(Hinge, GeneralAxisGivesTheFrequenciesOfTheAlignedModelTurned) {
  for (const fem::Vec3 axis : {fem::Vec3{0, 0, 1}, fem::Vec3{0, 1, 0}}) {
    fixtures::HingedBladeSpec b;
    b.E = 7e10;  // flexible: the elastic modes matter here too
    b.hingeAxis = axis;
    b.stiffness = 500.0;
    b.spinning = true;
    const auto aligned = solveAll(denseSystem(fem::assemble(fixtures::hingedBlade(b), world()), 20.0));
    b.rotation = fixtures::rotationAbout({1, 2, 3}, 0.7);
    const auto turned = solveAll(denseSystem(fem::assemble(fixtures::hingedBlade(b), world()), 20.0));
    ASSERT_EQ(aligned.modes.size(), turned.modes.size());
    const double tol = 1e3 * eps * largestOmega(aligned);
    for (std::size_t i = 0; i < aligned.modes.size(); ++i)
      EXPECT_NEAR(turned.modes[i].omega, aligned.modes[i].omega, tol) << "mode " << i << " axis " << axis[1];
  }
}

// The damper about the axis: D = c w w^T with w the hinge rotation
// phi = (theta_b,k - theta_a,k) / n_k in the rows (theory §17.1), so the
// rigid rotation about the hinge v (phi = 1) has v^T D v = c exactly and the
// hub's own rotations (phi = 0) none.
TEST(Hinge, DamperActsOnTheHingeRotationOnly) {
  fixtures::HingedBladeSpec b;
  b.damping = 50.0;
  b.hingeAxis = fem::unit({0.2, 0.1, 1.0});
  const auto a = fem::assemble(fixtures::hingedBlade(b), world());
  ASSERT_FALSE(a.D.is_null());
  const DenseMatrix D = fixtures::denseOf(*a.D);
  const fem::Vec3 n = fem::unit(b.hingeAxis);
  int k = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(n[d]) > std::abs(n[k])) k = d;
  const long long kept = a.layout.row(b.hubElements + 1, static_cast<Component>(3 + k));
  ASSERT_GE(kept, 0);
  // phi = 1 with the hub still: only the kept row moves, by n_k.
  EXPECT_NEAR(D(kept, kept) * n[k] * n[k], b.damping, 10 * eps * b.damping);
  // The hub node turning with the blade (theta = n everywhere): phi = 0.
  std::vector<double> v(D.numRows(), 0.0);
  for (int c = 0; c < 3; ++c) v[a.layout.row(b.hubElements, static_cast<Component>(3 + c))] = n[c];
  v[kept] = n[k];
  double vDv = 0.0;
  for (int i = 0; i < D.numRows(); ++i)
    for (int j = 0; j < D.numRows(); ++j) vDv += v[i] * D(i, j) * v[j];
  EXPECT_LE(std::abs(vDv), 10 * eps * b.damping);
}

TEST(Hinge, BadInputIsAnInputErrorNamingTheHinge) {
  auto assembleWith = [](const std::function<void(fem::FiniteElementModel&)>& change) {
    auto m = fixtures::hingedBlade(fixtures::HingedBladeSpec());
    change(m);
    fem::assemble(m, world());
  };
  fixtures::expectInputError([&] { assembleWith([](auto& m) { m.hinges[0].toNodeSet = "nowhere"; }); },
                             "hinge 'hinge': no node set 'nowhere'");
  fixtures::expectInputError([&] { assembleWith([](auto& m) { m.hinges[0].toNodeSet = "tip"; }); },
                             "has no coincident node in set 'tip'");
  fixtures::expectInputError([&] { assembleWith([](auto& m) { m.hinges[0].toNodeSet = "hub_tip"; }); },
                             "is in both 'hub_tip' and 'hub_tip'");
  fixtures::expectInputError(
      [&] {
        assembleWith([](auto& m) {
          fem::FixedSet f;
          f.name = "root";
          f.nodeSet = "blade_root";
          f.all = true;
          m.fixed.push_back(f);
        });
      },
      "has a boundary condition; fix the hinge's first node set 'hub_tip'");
  // Nodes without rotations: two coincident nodes carrying only point masses.
  fixtures::expectInputError(
      [&] {
        assembleWith([](auto& m) {
          auto mesh = std::make_shared<mesh::Mesh>(*m.mesh);
          for (int i = 0; i < 2; ++i) {
            mesh->nodeTags.push_back(100 + i);
            mesh->coordinates.insert(mesh->coordinates.end(), {0.0, 3.0, 0.0});
          }
          const auto n = static_cast<std::int64_t>(mesh->nodeCount());
          fixtures::addPointGroup(*mesh, "p", {n - 2});
          fixtures::addPointGroup(*mesh, "q", {n - 1});
          m.mesh = mesh;
          m.pointMasses.push_back({"p", "p", 1.0, {}});
          m.pointMasses.push_back({"q", "q", 1.0, {}});
          m.hinges[0].nodeSet = "p";
          m.hinges[0].toNodeSet = "q";
        });
      },
      "node 100 of set 'p' has no rotations");
  Teuchos::ParameterList p;
  p.set("Node Set", std::string("a"));
  p.set("To Node Set", std::string("b"));
  p.set("Axis", Teuchos::Array<double>(3, 0.0));
  fixtures::expectInputError([&] { fem::hingeFromParameters("lag", p, "scene.yaml: Hinges/lag"); },
                             "scene.yaml: Hinges/lag/Axis = [0, 0, 0] must be a finite nonzero vector");
  p.set("Axis", Teuchos::Array<double>(Teuchos::tuple(0.0, 0.0, 2.0)));
  p.set("Stiffness", -1.0);
  fixtures::expectInputError([&] { fem::hingeFromParameters("lag", p, "scene.yaml: Hinges/lag"); },
                             "scene.yaml: Hinges/lag/Stiffness = -1 must be finite and >= 0");
  p.set("Stiffness", 1.0);
  p.set("Axle", 1.0);
  fixtures::expectInputError([&] { fem::hingeFromParameters("lag", p, "scene.yaml: Hinges/lag"); }, "Axle");
}

// A free hinge (no spring) is a mechanism: the prestress solve holds it
// with a spring that must carry nothing. A radial blade is balanced (the
// centrifugal loads pass through the hinge): assembled, its hinge rotation
// stiffness at speed is then Omega^2 e S alone (the offset-hinge validation
// checks its frequency). With the spin axis moved off the hub's line
// (origin at y = 0.3) the centrifugal loads turn the blade about its lag
// hinge: no steady state at the undeformed position, an input error naming
// the hinge.
TEST(Hinge, FreeHingeNeedsBalancedCentrifugalLoads) {
  fixtures::HingedBladeSpec b;
  b.spinning = true;
  EXPECT_NO_THROW(fem::assemble(fixtures::hingedBlade(b), world()));
  auto m = fixtures::hingedBlade(b);
  m.spin->spin.origin = {0.0, 0.3, 0.0};
  fixtures::expectInputError([&] { fem::assemble(m, world()); },
                             "hinge 'hinge' is free (no Stiffness) but the centrifugal loads have a moment");
}

// A placed model (a scene's Placement, the copies of "Copies: N") turns its
// hinge axes with its nodes: the hinged blade and spin turned by
// fem::placedModel has the frequencies of the model built turned (the
// invariance test's reference), to the same 1e3 eps omega_max.
TEST(Hinge, PlacementTurnsTheHingeAxis) {
  fixtures::HingedBladeSpec b;
  b.E = 7e10;
  b.hingeAxis = fem::unit({0.2, 0.1, 1.0});
  b.stiffness = 500.0;
  b.spinning = true;
  const auto aligned = fixtures::hingedBlade(b);
  const fem::Vec3 axis{1, 2, 3};
  b.rotation = fixtures::rotationAbout(axis, 0.7);
  const auto built = solveAll(denseSystem(fem::assemble(fixtures::hingedBlade(b), world()), 20.0));
  auto placed = *fem::placedModel(aligned, fem::Rotation::about(fem::unit(axis), 0.7), {0, 0, 0});
  placed.spin->spin.axis = fixtures::rotate(b.rotation, {0, 0, 1});  // the frame's spin is the structure's
  const auto moved = solveAll(denseSystem(fem::assemble(placed, world()), 20.0));
  ASSERT_EQ(built.modes.size(), moved.modes.size());
  const double tol = 1e3 * eps * largestOmega(built);
  for (std::size_t i = 0; i < built.modes.size(); ++i)
    EXPECT_NEAR(moved.modes[i].omega, built.modes[i].omega, tol) << "mode " << i;
}

// The hinge across a rank boundary: with 4 hub and 4 blade elements the
// coordinate-slab partition puts the first node (x = e, 5th by position) on
// rank 0 and the second (the 6th) on rank 1 at 2 ranks, so the items at the
// second node scatter into rows another rank owns. Every matrix agrees with
// the one-rank assembly (this rank alone) to round-off of its norm: 1e-13
// for the summed element matrices, 1e-10 for KS1, whose prestress solve
// amplifies the summation-order round-off by cond(K) (as in
// Assembly.SameMatricesOnOneRankAndOnAllRanks).
TEST(Hinge, SameMatricesOnOneRankAndOnAllRanksAcrossTheHinge) {
  fixtures::HingedBladeSpec b;
  b.E = 7e10;
  b.hubElements = 4;
  b.bladeElements = 4;
  b.hingeAxis = fem::unit({0.3, -0.5, 0.8});
  b.stiffness = 500.0;
  b.damping = 20.0;
  b.spinning = true;
  const auto model = fixtures::hingedBlade(b);
  const auto dist = fem::assemble(model, world());
  const auto self = world()->split(world()->getRank(), 0);
  const auto serial = fem::assemble(model, self);
  if (world()->getSize() == 2) {
    // The rows of the pair: owned by different ranks.
    const long long ra = dist.layout.row(b.hubElements, Component::UX);
    const long long rb = dist.layout.first[b.hubElements + 1];
    const bool ownsA = dist.map->isNodeGlobalElement(ra), ownsB = dist.map->isNodeGlobalElement(rb);
    EXPECT_NE(ownsA, ownsB) << "the hinge's nodes are on one rank: the test does not cross ranks";
  }
  auto same = [](const CrsMatrix& A, const CrsMatrix& B, const char* name, double rel) {
    const DenseMatrix a = fixtures::denseOf(A), c = fixtures::denseOf(B);
    ASSERT_EQ(a.numRows(), c.numRows()) << name;
    double diff = 0.0;
    for (int i = 0; i < a.numRows(); ++i)
      for (int j = 0; j < a.numRows(); ++j) diff = std::max(diff, std::abs(a(i, j) - c(i, j)));
    EXPECT_LE(diff, rel * frobeniusNorm(c)) << name;
  };
  same(*dist.M, *serial.M, "M", 1e-13);
  same(*dist.K, *serial.K, "K", 1e-13);
  same(*dist.D, *serial.D, "D", 1e-13);
  same(*dist.G1, *serial.G1, "G1", 1e-13);
  same(*dist.KT1, *serial.KT1, "KT1", 1e-13);
  same(*dist.KS1, *serial.KS1, "KS1", 1e-10);
}
