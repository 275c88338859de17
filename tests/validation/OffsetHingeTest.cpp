// The offset-hinge frequencies of a rotor blade (theory §17.3) from the
// finite-element blade: a hub arm from the spin axis to x = e and a stiff
// blade beyond it on a hinge, spinning in its own frame (Coriolis, spin
// softening and centrifugal stress stiffening). A rigid blade of moment of
// inertia I and first moment S about the hinge has
//   lag  (hinge axis parallel to the spin axis): nu^2 = k / I + Omega^2 e S / I,
//   flap (hinge axis normal to the blade and the spin axis):
//        nu^2 = k / I + Omega^2 (1 + e S / I),
// and the FE model reproduces them exactly for a rigid blade (the geometric
// stiffness of the blade's tension integrates to Omega^2 (I + e S) on the
// rigid rotation, the softening to -Omega^2 I in the plane of rotation and to
// nothing out of it). Then the same blade as a child E of a spinning hub C
// through a scene (a Beam with a hinge station), reduced by admissible
// vectors against the truth. At 1 and 2 ranks.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <limits>
#include <sstream>

#include <Teuchos_DefaultComm.hpp>

#include "DenseOf.hpp"
#include "HingedBlade.hpp"
#include "cms/analysis/ModalAnalysis.hpp"
#include "cms/fem/FiniteElementAssembly.hpp"
#include "cms/io/ModeShapeFiles.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

using namespace cms;

namespace {
auto world() { return Teuchos::DefaultComm<int>::getComm(); }

/// The lowest frequency of the FE blade spinning at Omega.
double lowestAtSpeed(const fem::AssembledMatrices& a, double Omega) {
  const DenseMatrix M = fixtures::denseOf(*a.M), G1 = fixtures::denseOf(*a.G1), K0 = fixtures::denseOf(*a.K);
  const DenseMatrix KT1 = fixtures::denseOf(*a.KT1), KS1 = fixtures::denseOf(*a.KS1);
  const int n = M.numRows();
  DenseMatrix G(n, n), K(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      G(i, j) = Omega * G1(i, j);
      K(i, j) = K0(i, j) + Omega * Omega * (KS1(i, j) - KT1(i, j));
    }
  return fixtures::lowestFrequencies(M, G, K, 1)[0];
}
}  // namespace

// nu^2 = k / I + Omega^2 e S / I at Omega = 10, 20, 30, 40 rad/s (nu from 4.4
// to 15.6 rad/s) to 1e-6 relative. What separates the FE blade from the rigid
// one (theory §17.3): its flexibility, which lowers nu by 7e6 / E (Omega = 10)
// to 4.5e7 / E (Omega = 40) relative (measured at E = 5.3e10 .. 5.3e13, where
// it dominates and follows 1/E to three digits; 0.7 to 3 times
// (nu / omega_b)^2 with the pinned-free bending omega_b = 1.4e5 rad/s at
// E = 5.3e15), so at most 8.5e-9 here, below 1e-7 (the Coriolis coupling to
// the blade's axial stretch, of order (2 Omega / omega_axial)^2 <= 1.2e-8 with
// omega_axial = 7.2e5 rad/s, is part of it); and the rounding of K's stiff entries, which
// cancel on the rigid rotation: measured up to 6.6e-8 (it does not follow
// 1/E). Measured errors: printed.
TEST(OffsetHinge, LagFrequencyIsSqrtOfKPlusOmegaSquaredESOverI) {
  fixtures::HingedBladeSpec b;
  b.E = 5.3e15;
  b.stiffness = 2000.0;
  b.spinning = true;
  const auto a = fem::assemble(fixtures::hingedBlade(b), world());
  const double I = b.inertia(), S = b.firstMoment();
  for (double Omega : {10.0, 20.0, 30.0, 40.0}) {
    const double nu = std::sqrt(b.stiffness / I + Omega * Omega * b.e * S / I);
    const double fe = lowestAtSpeed(a, Omega);
    if (world()->getRank() == 0)
      std::cout << "lag: Omega " << Omega << " nu " << nu << " FE " << fe << " relative error " << fe / nu - 1
                << "\n";
    EXPECT_NEAR(fe / nu, 1.0, 1e-6) << "Omega = " << Omega;
  }
}

// Without the hinge's own spring the lag frequency is purely centrifugal,
// nu = Omega sqrt(e S / I), and at e = 0 the blade has no lag stiffness: the
// hinge on the spin axis gives a zero-frequency mode (here tested through
// the stiffness of the rigid rotation being Omega^2 e S: e = 0.5 and 1.0).
TEST(OffsetHinge, FreeLagHingeFrequencyIsProportionalToSpeed) {
  for (double e : {0.5, 1.0}) {
    fixtures::HingedBladeSpec b;
    b.E = 5.3e15;
    b.e = e;
    b.spinning = true;
    const auto a = fem::assemble(fixtures::hingedBlade(b), world());
    for (double Omega : {10.0, 30.0}) {
      const double nu = Omega * std::sqrt(e * b.firstMoment() / b.inertia());
      EXPECT_NEAR(lowestAtSpeed(a, Omega) / nu, 1.0, 1e-6) << "e = " << e << ", Omega = " << Omega;
    }
  }
}

// Flap hinge (axis y, normal to the blade and to the spin axis z):
// nu^2 = k / I + Omega^2 (1 + e S / I), the Southwell form of a hinged
// rigid blade (no spin softening out of the plane of rotation). Same bounds
// as the lag case.
TEST(OffsetHinge, FlapFrequencyIsSqrtOfKOverIPlusOmegaSquaredOnePlusESOverI) {
  fixtures::HingedBladeSpec b;
  b.E = 5.3e15;
  b.stiffness = 2000.0;
  b.hingeAxis = {0, 1, 0};
  b.spinning = true;
  const auto a = fem::assemble(fixtures::hingedBlade(b), world());
  const double I = b.inertia(), S = b.firstMoment();
  for (double Omega : {10.0, 20.0, 30.0}) {
    const double nu = std::sqrt(b.stiffness / I + Omega * Omega * (1.0 + b.e * S / I));
    const double fe = lowestAtSpeed(a, Omega);
    if (world()->getRank() == 0)
      std::cout << "flap: Omega " << Omega << " nu " << nu << " FE " << fe << " relative error " << fe / nu - 1
                << "\n";
    EXPECT_NEAR(fe / nu, 1.0, 1e-6) << "Omega = " << Omega;
  }
}

namespace {
/// A spinning hub arm (C, clamped on the axis, 0 to 0.5 m) carrying a blade
/// (E, 0.5 to 6 m) with a lag hinge at a station (m from its root), through
/// the scene reader.
std::string hingedRotorScene(const std::string& basis, int vectors, double E, int elements, double station) {
  std::ostringstream os;
  os << "Scene:\n"
        "  Name: hinged-rotor\n"
        "  Substructures:\n"
        "    hub:\n"
        "      Kind: C\n"
        "      Beam:\n"
        "        From: [0, 0, 0]\n"
        "        To: [0.5, 0, 0]\n"
        "        Elements: 2\n"
        "        Young's Modulus: 5.3e15\n"
        "        Density: 1000\n"
        "        Area: 0.01\n"
        "        Iy: 1.0e-2\n"
        "        Iz: 1.0e-2\n"
        "        Torsion Constant: 2.0e-2\n"
        "        Clamp: start\n"
        "      Spin: {Axis: [0, 0, 1], Rate: 20.0}\n"
        "      Reduction: {Basis: Full}\n"
        "    blade:\n"
        "      Kind: E\n"
        "      Parent: hub\n"
        "      Attachment: {Parent Nodes: end, Nodes: start}\n"
        "      Beam:\n"
        "        From: [0.5, 0, 0]\n"
        "        To: [6.0, 0, 0]\n"
        "        Elements: " << elements << "\n"
        "        Young's Modulus: " << E << "\n"
        "        Density: 1000\n"
        "        Area: 0.01\n"
        "        Iy: 1.0e-4\n"
        "        Iz: 1.0e-4\n"
        "        Torsion Constant: 2.0e-4\n"
        "        Hinges:\n"
        "          lag: {Station: " << station << ", Axis: [0, 0, 1], Stiffness: 2000.0}\n"
        "      Reduction: {Basis: " << basis;
  if (vectors > 0) os << ", Vectors: " << vectors;
  os << "}\n";
  return os.str();
}

double lowestOf(const synthesis::SynthesizedStructure& s, double Omega) {
  const auto sys = s.denseSystem({Omega});
  return fixtures::lowestFrequencies(sys.M, sys.G, sys.K, 1)[0];
}
}  // namespace

// The hinged blade through the normal scene path: a Beam with a hinge
// station as a child E of a spinning C, assembled, reduced and synthesised
// with no change to those layers. With a stiff blade (two elements, the
// hinge between them) the truth (every basis Full) reproduces the
// offset-hinge formula to 1e-6 (the bounds of the fem-level test; the hub
// arm as stiff, so that its axial stretch under the Coriolis load,
// (2 Omega / omega_axial)^2, stays below 1e-8). An aluminium-like blade
// (E = 7e10, 22 elements, the hinge at 0.5 m) is the truth that admissible
// vectors converge to: the reduced lag frequency is never below it and its
// error never grows with the vectors (nested bases: the inclusion
// principle), from 4e-4 at 4 vectors (about the Coriolis coupling to the
// blade's axial stretch, (2 Omega / omega_axial)^2 = 2.8e-4, which a basis
// of static and Krylov shapes at rest captures slowly) to 9.1e-7 at 64
// (measured; 2e-6 asserted).
TEST(OffsetHinge, HingedBladeThroughASceneConvergesToItsTruth) {
  const auto comm = world();
  {
    // Two stiff elements of 2.75 m, the hinge between them: e = 3.25, L = 2.75.
    const auto scene = scene::Scene::parse(hingedRotorScene("Full", 0, 5.3e15, 2, 2.75), "hinged-rotor.yaml");
    const auto truth = synthesis::SynthesizedStructure::synthesize(
        synthesis::AssembledStructure::assemble(scene.structure, comm), true);
    // The Beam's sections keep their rotary inertia: rho Iy per unit length
    // about the lag axis (local y is z here) adds rho Iy L to I.
    const double rhoA = 10.0, e = 3.25, L = 2.75, S = rhoA * L * L / 2;
    const double I = rhoA * L * L * L / 3 + 1000.0 * 1.0e-4 * L;
    for (double Omega : {10.0, 20.0}) {
      const double nu = std::sqrt(2000.0 / I + Omega * Omega * e * S / I), fe = lowestOf(truth, Omega);
      if (comm->getRank() == 0)
        std::cout << "scene truth: Omega " << Omega << " nu " << nu << " relative error " << fe / nu - 1 << "\n";
      EXPECT_NEAR(fe / nu, 1.0, 1e-6) << "Omega = " << Omega;
    }
  }
  const auto truthScene = scene::Scene::parse(hingedRotorScene("Full", 0, 7e10, 22, 0.5), "hinged-rotor.yaml");
  const auto assembled = synthesis::AssembledStructure::assemble(truthScene.structure, comm);
  const double truth = lowestOf(synthesis::SynthesizedStructure::synthesize(assembled, true), 20.0);
  double previous = 1.0;
  for (int vectors : {4, 8, 16, 32, 64}) {
    const auto scene = scene::Scene::parse(hingedRotorScene("Admissible", vectors, 7e10, 22, 0.5), "hinged-rotor.yaml");
    const auto s = synthesis::SynthesizedStructure::synthesize(synthesis::AssembledStructure::assemble(scene.structure, comm));
    const double error = lowestOf(s, 20.0) / truth - 1.0;
    if (comm->getRank() == 0) std::cout << "Admissible " << vectors << ": lag relative error " << error << "\n";
    EXPECT_GE(error, -1e-12) << vectors;  // a Ritz value is never below the truth's
    EXPECT_LE(error, previous + 1e-12) << vectors;
    previous = error;
  }
  EXPECT_LT(previous, 2e-6);
}

// Scene input errors of hinges name the file and the key: a station that is
// not an interior node (with the spacing to choose from), node-set keys in a
// Beam's hinge, a zero axis; and an attachment on a hinge's second node set
// (whose translations follow the first node: refused, not clamped).
TEST(OffsetHinge, SceneHingeErrorsNameTheKey) {
  auto errorOf = [](const std::string& text) -> std::string {
    try {
      const auto scene = scene::Scene::parse(text, "hinged-rotor.yaml");
      synthesis::AssembledStructure::assemble(scene.structure, world());
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  auto replaced = [](std::string s, const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  const std::string good = hingedRotorScene("Full", 0, 7e10, 22, 0.5);
  EXPECT_NE(errorOf(replaced(good, "Station: 0.5", "Station: 0.3"))
                .find("hinged-rotor.yaml: Scene/Substructures/blade/Beam/Hinges/lag/Station = 0.3 must be at an "
                      "interior node of the beam: the nodes are every 0.25 m"),
            std::string::npos);
  EXPECT_NE(errorOf(replaced(good, "Station: 0.5", "Station: 5.5")).find("must be at an interior node"),
            std::string::npos);
  EXPECT_NE(errorOf(replaced(good, "Station: 0.5", "Node Set: start")).find("is placed by \"Station\""),
            std::string::npos);
  EXPECT_NE(errorOf(replaced(good, "Axis: [0, 0, 1], Stiffness", "Axis: [0, 0, 0], Stiffness"))
                .find("Scene/Substructures/blade/Beam/Hinges/lag/Axis = [0, 0, 0] must be a finite nonzero vector"),
            std::string::npos);
  EXPECT_NE(errorOf(replaced(good, "Nodes: start}", "Nodes: lag_outboard}"))
                .find("attachment node set 'lag_outboard' holds node 24, the second node of hinge 'lag', which "
                      "follows the hinge; use its first node set 'lag_inboard'"),
            std::string::npos)
      << errorOf(replaced(good, "Nodes: start}", "Nodes: lag_outboard}"));
  EXPECT_EQ(errorOf(good), "no error");
}

namespace {
/// The rows of 3 numbers of the DataArray that follows `marker` in a VTU file.
std::vector<std::array<double, 3>> vtuArray(const std::string& text, const std::string& marker) {
  std::vector<std::array<double, 3>> rows;
  auto at = text.find(marker);
  if (at == std::string::npos) return rows;
  at = text.find('\n', text.find("<DataArray", at)) + 1;
  std::istringstream in(text.substr(at, text.find("</DataArray>", at) - at));
  std::array<double, 3> r;
  while (in >> r[0] >> r[1] >> r[2]) rows.push_back(r);
  return rows;
}
}  // namespace

// Mode-shape files show a hinge's second node moving with the joint: its
// translations are its partner's and, for the lag hinge about z, its
// rotations about x and y too (the row it keeps is its rotation about z).
// The files print 10 digits, so equal to 1e-9 of the mode's largest
// displacement; the partner does move (above 1e-6 of it) in some mode.
TEST(OffsetHinge, ModeShapeFilesShowTheHingeMovingWithTheBlade) {
  const auto comm = world();
  const auto scene = scene::Scene::parse(hingedRotorScene("Full", 0, 7e10, 22, 0.5), "hinged-rotor.yaml");
  const auto assembled = synthesis::AssembledStructure::assemble(scene.structure, comm);
  const auto s = synthesis::SynthesizedStructure::synthesize(assembled, true);
  Teuchos::ParameterList p;
  p.set("Number of Modes", 4);
  const auto modes = s.solve({20.0}, p);
  const auto dir = std::filesystem::temp_directory_path() / ("cms_hinge_vtu_np" + std::to_string(comm->getSize()));
  io::OutputFiles files;
  io::writeModeShapes(files, assembled, s, modes, dir.string(), "hinged");
  files.commit(*comm);
  if (comm->getRank() != 0) return;
  double moved = 0.0;
  for (std::size_t m = 1; m <= modes.result.modes.size(); ++m) {
    std::ifstream f(dir / ("hinged-mode-" + std::to_string(m) + ".vtu"));
    const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const auto points = vtuArray(text, "<Points>"), u = vtuArray(text, "Name=\"displacement_real\""),
               r = vtuArray(text, "Name=\"rotation_real\"");
    ASSERT_EQ(points.size(), u.size());
    ASSERT_EQ(points.size(), r.size());
    std::vector<std::size_t> hinge;
    double largest = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (std::abs(points[i][0] - 1.0) < 1e-12 && std::abs(points[i][1]) < 1e-12) hinge.push_back(i);
      for (double v : u[i]) largest = std::max(largest, std::abs(v));
    }
    ASSERT_EQ(hinge.size(), 2u) << "the hinge's two coincident points";
    const auto a = hinge[0], b = hinge[1];
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(u[b][c], u[a][c], 1e-9 * largest) << "mode " << m << " u" << c;
    for (int c = 0; c < 2; ++c) EXPECT_NEAR(r[b][c], r[a][c], 1e-9 * largest) << "mode " << m << " r" << c;
    for (int c = 0; c < 3; ++c) moved = std::max(moved, std::abs(u[a][c]) / largest);
  }
  EXPECT_GT(moved, 1e-6);
  std::filesystem::remove_all(dir);
}

namespace {
/// The flexible blade of hingedRotorScene (0.5 to 6 m, 22 elements, the
/// hinge at x = 1) as an Abaqus deck with the hinge's node duplicated
/// (node 24 at x = 1 takes over element 3), node sets start, hub_side
/// (node 3) and blade_side (node 24).
std::string bladeDeck() {
  std::ostringstream d;
  d << "*NODE\n";
  for (int i = 1; i <= 23; ++i) d << i << ", " << 0.5 + 0.25 * (i - 1) << ", 0, 0\n";
  d << "24, 1.0, 0, 0\n*ELEMENT, TYPE=B31, ELSET=blade\n";
  for (int e = 1; e <= 22; ++e) d << e << ", " << (e == 3 ? 24 : e) << ", " << e + 1 << "\n";
  d << "*NSET, NSET=start\n1\n*NSET, NSET=hub_side\n3\n*NSET, NSET=blade_side\n24\n*NSET, NSET=tip\n23\n";
  return d.str();
}

/// hingedRotorScene with the blade as a Finite Element Model of bladeDeck()
/// (at `mesh`) whose "Hinges" entry is `hinge`.
std::string deckScene(const std::string& mesh, const std::string& hinge) {
  std::string s = hingedRotorScene("Full", 0, 7e10, 22, 0.5);
  const auto beam = s.find("      Beam:\n        From: [0.5");
  const auto reduction = s.find("      Reduction:", beam);
  return s.replace(beam, reduction - beam,
                   "      Finite Element Model:\n"
                   "        Mesh: " + mesh + "\n"
                   "        Materials:\n"
                   "          m: {Young's Modulus: 7.0e10, Poisson's Ratio: 0.3, Density: 1000}\n"
                   "        Element Sets:\n"
                   "          blade: {Type: Frame, Material: m, Area: 0.01, Iy: 1.0e-4, Iz: 1.0e-4,"
                   " Torsion Constant: 2.0e-4, Orientation: [0, 0, 1]}\n"
                   "        Hinges:\n"
                   "          lag: " + hinge + "\n");
}
}  // namespace

// The same hinged blade written as a Finite Element Model (an .inp deck with
// the hinge's node duplicated, "Hinges" between node sets) is the same
// model as the Beam with a hinge station: its lag frequency agrees to the
// rounding of two differently ordered assemblies (1e-9, far below any
// modelling difference). Its input errors name the scene file and the key
// path: a missing set, a set whose node is not coincident, a zero axis.
TEST(OffsetHinge, FiniteElementModelHingesMatchTheBeamStation) {
  const auto comm = world();
  const auto dir = std::filesystem::temp_directory_path() /
                   ("cms_hinge_deck_np" + std::to_string(comm->getSize()) + "_" + std::to_string(comm->getRank()));
  std::filesystem::create_directories(dir);
  const std::string mesh = (dir / "blade.inp").string();
  std::ofstream(mesh) << bladeDeck();
  const std::string good =
      "{Node Set: hub_side, To Node Set: blade_side, Axis: [0, 0, 1], Stiffness: 2000.0}";
  auto lowestOfScene = [&](const std::string& text) {
    const auto scene = scene::Scene::parse(text, "hinged-rotor.yaml");
    return lowestOf(synthesis::SynthesizedStructure::synthesize(
                        synthesis::AssembledStructure::assemble(scene.structure, comm), true),
                    20.0);
  };
  const double beam = lowestOfScene(hingedRotorScene("Full", 0, 7e10, 22, 0.5));
  EXPECT_NEAR(lowestOfScene(deckScene(mesh, good)) / beam, 1.0, 1e-9);
  auto errorOf = [&](const std::string& hinge) -> std::string {
    try {
      lowestOfScene(deckScene(mesh, hinge));
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  std::string e = errorOf("{Node Set: hub_side, To Node Set: nowhere, Axis: [0, 0, 1]}");
  EXPECT_NE(e.find("hinged-rotor.yaml: Scene/Substructures/blade/Finite Element Model"), std::string::npos) << e;
  EXPECT_NE(e.find("hinge 'lag': no node set 'nowhere'"), std::string::npos) << e;
  e = errorOf("{Node Set: hub_side, To Node Set: tip, Axis: [0, 0, 1]}");
  EXPECT_NE(e.find("hinge 'lag': node 3 of set 'hub_side' has no coincident node in set 'tip'"), std::string::npos)
      << e;
  EXPECT_NE(e.find("blade"), std::string::npos) << e;
  e = errorOf("{Node Set: hub_side, To Node Set: blade_side, Axis: [0, 0, 0]}");
  EXPECT_NE(e.find("Finite Element Model/Hinges/lag/Axis = [0, 0, 0] must be a finite nonzero vector"),
            std::string::npos)
      << e;
  std::filesystem::remove_all(dir);
}

namespace {
/// A rigid blade (rho A = 10 kg/m, L = 5 m; E = 5.3e13: bending at 1.4e4
/// rad/s) on a lag hinge exactly on the spin axis, at the tip of a soft,
/// nearly massless hub arm (one element, x = -0.5 .. 0, clamped at its root;
/// E I = 5.3e4 N m^2 in the plane of rotation, rho A = 1e-5 kg/m), as a
/// Finite Element Model deck, spinning at Omega about z.
std::string hubDeck() {
  std::ostringstream d;
  d << std::setprecision(17) << "*NODE\n1, -0.5, 0, 0\n2, 0, 0, 0\n";
  for (int i = 0; i <= 4; ++i) d << 3 + i << ", " << 5.0 * i / 4 << ", 0, 0\n";
  d << "*ELEMENT, TYPE=B31, ELSET=hub\n1, 1, 2\n*ELEMENT, TYPE=B31, ELSET=blade\n";
  for (int e = 0; e < 4; ++e) d << 2 + e << ", " << 3 + e << ", " << 4 + e << "\n";
  d << "*NSET, NSET=root\n1\n*NSET, NSET=hub_side\n2\n*NSET, NSET=blade_side\n3\n";
  return d.str();
}

std::string hubScene(const std::string& mesh, double Omega) {
  std::ostringstream s;
  s << std::setprecision(17) << "Scene:\n  Substructures:\n    rotor:\n      Kind: C\n      Finite Element Model:\n"
    << "        Mesh: " << mesh << "\n        Materials:\n"
    << "          hub: {Young's Modulus: 5.3e13, Poisson's Ratio: 0.3, Density: 1.0e-3}\n"
    << "          blade: {Young's Modulus: 5.3e13, Poisson's Ratio: 0.3, Density: 1000}\n"
    << "        Element Sets:\n"
    << "          hub: {Type: Frame, Material: hub, Area: 0.01, Iy: 1.0e-9, Iz: 1.0e-9, Torsion Constant: 2.0e-9,"
       " Orientation: [0, 0, 1], Rotary Inertia: false}\n"
    << "          blade: {Type: Frame, Material: blade, Area: 0.01, Iy: 1.0e-4, Iz: 1.0e-4, Torsion Constant: 2.0e-4,"
       " Orientation: [0, 0, 1], Rotary Inertia: false}\n"
    << "        Boundary Conditions:\n          root: {Node Set: root, Fixed: all}\n"
    << "        Hinges:\n          lag: {Node Set: hub_side, To Node Set: blade_side, Axis: [0, 0, 1]}\n"
    << "      Spin: {Axis: [0, 0, 1], Origin: [0, 0, 0], Rate: " << Omega << "}\n"
    << "      Reduction: {Basis: Full}\n  Analysis: {Number of Modes: 4, Solver: Dense}\n";
  return s.str();
}
}  // namespace

// A lag hinge on the spin axis of a flexible hub diverges (theory §17.3,
// "The hinge on the axis"): the blade lagging by zeta pulls the hinge
// sideways with the transverse part Omega^2 S zeta of its tension, and the
// hinge displaced by delta puts the blade off the axis, where the
// centrifugal field turns it further: the potential
//   V = -Omega^2 S zeta delta + (k - Omega^2 M_b) delta^2 / 2
// is indefinite for every k (no term in zeta^2: e = 0). With the kinetic
// energy lambda^2 (I zeta^2 + 2 S zeta delta + M_b delta^2) / 2, the growth
// lambda = sqrt(mu) solves (I M_b - S^2) mu^2 + (I (k - Omega^2 M_b) +
// 2 Omega^2 S^2) mu - Omega^4 S^2 = 0, k the hub's tip stiffness in the
// plane under its tension T = Omega^2 S with its tip free to turn,
// T / (l - tanh(beta l) / beta), beta^2 = T / (E I) (a review read the
// DIVERGENCE as a false alarm; it is this). At 10 and 12 rad/s (0.536 and
// 0.768 1/s); at rest refused, as a mechanism. (Below about 8 rad/s here,
// 22 rad/s of the reviewer's scene, the growth is below 1e-6 of the
// system's scale, a real value the zero tests take, and the run is refused
// as "unrestrained", the free hinge's mechanism at rest: open, theory
// §17.3.) Allowed: each mode's reported error plus 1e-5 of lambda, for what
// the closed form leaves out: the hub as one cubic element under tension
// ((beta l)^4: 3.7e-6 of lambda at 12 rad/s), the blade's flexibility
// ((Omega / 1.4e4)^2 <= 1e-6), the hub's mass (1e-7) and the Coriolis
// coupling to the axial stretch (EA / l = 1e12: below 1e-9).
TEST(OffsetHinge, ALagHingeOnTheAxisOfAFlexibleHubDiverges) {
  const auto comm = world();
  const auto dir = std::filesystem::temp_directory_path() /
                   ("cms_hub_deck_np" + std::to_string(comm->getSize()) + "_" + std::to_string(comm->getRank()));
  std::filesystem::create_directories(dir);
  const std::string mesh = (dir / "hub.inp").string();
  std::ofstream(mesh) << hubDeck();
  const auto modesAt = [&](double Omega) {
    const auto scene = scene::Scene::parse(hubScene(mesh, Omega), "hub.yaml");
    return analysis::ModalAnalysis(scene.structure, scene.solve, Teuchos::ParameterList()).run(comm).modes.result;
  };
  const double rhoA = 10.0, L = 5.0, l = 0.5, EI = 5.3e13 * 1e-9;
  const double I = rhoA * L * L * L / 3, S = rhoA * L * L / 2, Mb = rhoA * L;
  for (double Omega : {10.0, 12.0}) {
    SCOPED_TRACE("Omega " + std::to_string(Omega));
    const double T = Omega * Omega * S, beta = std::sqrt(T / EI);
    const double k = T / (l - std::tanh(beta * l) / beta);
    const double a = I * Mb - S * S, b = I * (k - Omega * Omega * Mb) + 2 * Omega * Omega * S * S,
                 c = -std::pow(Omega, 4) * S * S;
    const double growth = std::sqrt((-b + std::sqrt(b * b - 4 * a * c)) / (2 * a));
    eigen::GyroscopicResult r;
    ASSERT_NO_THROW(r = modesAt(Omega));
    ASSERT_FALSE(r.modes.empty());
    const auto& m = r.modes[0];
    if (comm->getRank() == 0)
      std::cout << "hinge on the axis: Omega " << Omega << " growth " << m.lambda << " closed form " << growth
                << " (error " << m.reportedError() << ")\n";
    EXPECT_EQ(m.stability, eigen::Stability::Divergence) << eigen::toString(m.stability) << " at " << m.lambda;
    EXPECT_LE(std::abs(m.lambda - growth), m.reportedError() + 1e-5 * growth) << m.lambda << " against " << growth;
    for (std::size_t j = 1; j < r.modes.size(); ++j)
      EXPECT_TRUE(r.modes[j].stability == eigen::Stability::Stable || r.modes[j].stability == eigen::Stability::Neutral)
          << j << ": " << eigen::toString(r.modes[j].stability) << " at " << r.modes[j].lambda;
  }
  try {
    modesAt(0.0);
    ADD_FAILURE() << "at rest the free hinge is a mechanism: refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unrestrained"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}
