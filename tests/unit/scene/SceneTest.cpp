// Scenes (doc/user-guide.md, "Scenes"): every malformed scene is refused
// before any computation with a message naming the file and the key path;
// and the example scenes, run at 1 and 2 ranks, reproduce their checked-in
// frequencies (tests/data/expected/<scene>-modes.csv, regenerate with
// CMS_WRITE_EXPECTED=1): relative 1e-8 for vibrations (well above the
// rounding of a 48-coordinate dense solve, far below any modelling change),
// and rigid-body zeros to the solvers' own zero, 1e-6 of the frequency
// scale (doc/theory.md §3).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>
#include <Teuchos_XMLParameterListCoreHelpers.hpp>
#include <Teuchos_YamlParameterListCoreHelpers.hpp>

#include "ExpectError.hpp"
#include "cms/core/BlasThreads.hpp"
#include "cms/analysis/CampbellStudy.hpp"
#include "cms/analysis/ModalAnalysis.hpp"
#include "cms/analysis/PeriodicStructure.hpp"
#include "cms/analysis/TruncationStudy.hpp"
#include "cms/analysis/TruthComparison.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

using namespace cms;

namespace {

const char* kGood = R"(
Scene:
  Substructures:
    hub:
      Kind: C
      Beam:
        From: [0.0, 0.0, 0.0]
        To: [1.0, 0.0, 0.0]
        Elements: 4
        Young's Modulus: 7.0e10
        Density: 2700.0
        Area: 0.01
        Iy: 1.0e-5
        Iz: 1.0e-5
        Torsion Constant: 2.0e-5
        Clamp: start
    arm:
      Kind: E
      Parent: hub
      Attachment:
        Parent Nodes: end
        Nodes: start
      Beam:
        From: [1.0, 0.0, 0.0]
        To: [2.0, 0.0, 0.0]
        Young's Modulus: 7.0e10
        Density: 2700.0
        Area: 0.001
        Iy: 1.0e-7
        Iz: 1.0e-7
        Torsion Constant: 2.0e-7
      Reduction:
        Basis: Modes
        Vectors: 4
)";

scene::Scene parse(const std::string& yaml) {
  return scene::Scene::fromParameters(*Teuchos::getParametersFromYamlString(yaml), "test.yaml");
}

/// `from` replaced by `to` in `text` (a second edit of an edited scene).
std::string edit2(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

std::string edit(const std::string& from, const std::string& to) {
  std::string s = kGood;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}


/// The scene's lowest `count` frequencies at its nominal speeds, reduced
/// over those of its truth (the same assembly unreduced), with the basis
/// report of its substructure `which`; no ratios when either solve returned
/// another count.
struct AgainstTruth {
  std::vector<double> ratios;
  std::string basis, report;
  long long coordinates = 0;
};
AgainstTruth againstTruth(const scene::Scene& sc, std::size_t count, std::size_t which) {
  const auto a = synthesis::AssembledStructure::assemble(sc.structure, Teuchos::DefaultComm<int>::getComm());
  const auto reduced = synthesis::SynthesizedStructure::synthesize(a);
  const auto truth = synthesis::SynthesizedStructure::synthesize(a, true);
  const auto m = reduced.solve(a.nominalSpeeds(), sc.solve);
  const auto t = truth.solve(a.nominalSpeeds(), sc.solve);
  AgainstTruth out;
  out.basis = reduced.reductions()[which].basis;
  out.report = reduced.reductions()[which].eigensolverReport;
  out.coordinates = reduced.size();
  EXPECT_EQ(m.result.modes.size(), count);
  EXPECT_EQ(t.result.modes.size(), count);
  if (m.result.modes.size() != count || t.result.modes.size() != count) return out;
  for (std::size_t i = 0; i < count; ++i) out.ratios.push_back(m.result.modes[i].omega / t.result.modes[i].omega);
  return out;
}

}  // namespace

TEST(Scene, AGoodSceneBecomesAStructure) {
  const auto sc = parse(kGood);
  ASSERT_EQ(sc.structure.substructures.size(), 2u);
  EXPECT_EQ(sc.structure.substructures[1].parent, "hub");
  EXPECT_EQ(sc.structure.substructures[1].reduction.get<std::string>("Basis"), "Modes");
  const auto a = synthesis::AssembledStructure::assemble(sc.structure, Teuchos::DefaultComm<int>::getComm());
  EXPECT_EQ(a.numSubstructures(), 2u);
}

TEST(Scene, MalformedScenesNameTheKey) {
  using fixtures::expectInputError;
  expectInputError([] { parse(edit("Kind: E", "Kind: X")); }, "test.yaml: Scene/Substructures/arm/Kind = \"X\"");
  expectInputError([] { parse(edit("Parent: hub", "Parent: nobody")); }, "parent 'nobody'");
  expectInputError([] { parse(edit("Young's Modulus: 7.0e10\n        Density: 2700.0\n        Area: 0.01",
                                   "Young's Modulus: seven\n        Density: 2700.0\n        Area: 0.01")); },
                   "Scene/Substructures/hub/Beam/Young's Modulus: must be a number");
  expectInputError([] { parse(edit("Elements: 4", "Elements: 5")); }, "Elements = 5 must be an even integer");
  expectInputError([] { parse(edit("Clamp: start", "Clamp: top")); }, "Clamp = \"top\"");
  expectInputError([] { parse(edit("Basis: Modes", "Basis: Eigen")); }, "Scene/Substructures/arm/Reduction");
  // A Partition under another basis was read and ignored (found by a review).
  expectInputError([] { parse(edit("Basis: Modes", "Basis: Modes\n        Partition: {Parts: 4}")); },
                   "Scene/Substructures/arm/Reduction/Partition: read by Basis: Partitioned only, not by Modes");
  expectInputError([] { parse(edit("Basis: Modes\n        Vectors: 4", "Partition: {Parts: 4}")); },
                   "not by Admissible");
  expectInputError([] { parse(edit("Parent Nodes: end", "Parnt Nodes: end")); }, "unknown key \"Parnt Nodes\"");
  expectInputError([] { parse(edit("Scene:\n", "Scene:\n  Units: imperial\n")); }, "only SI");
  expectInputError([] { parse(edit("      Beam:\n        From: [1.0", "      Rotor:\n        Mass: 1.0\n      Beam:\n        From: [1.0")); },
                   "exactly one of");
  expectInputError([] { parse(edit("From: [0.0, 0.0, 0.0]", "From: [0.0, 0.0]")); }, "has 2 numbers, needs 3");
  // A vertical beam with the default Orientation: the key and "the
  // default" named (the element's message named only its coordinates; a
  // review). Given, it is named without "the default".
  expectInputError([] { parse(edit("To: [1.0, 0.0, 0.0]", "To: [0.0, 0.0, 1.0]")); },
                   "Scene/Substructures/hub/Beam/Orientation = [0, 0, 1] (the default) is parallel to the beam");
  expectInputError([] { parse(edit("To: [1.0, 0.0, 0.0]", "To: [0.0, 2.0, 0.0]\n        Orientation: [0.0, -3.0, 0.0]")); },
                   "Scene/Substructures/hub/Beam/Orientation = [0, -3, 0] is parallel to the beam");
  expectInputError([] { parse(edit("Clamp: start", "Clamp: start\n        Tip Inertia: [1.0, 1.0, 1.0]")); },
                   "Tip Inertia needs a \"Tip Mass\"");
  expectInputError(
      [] {
        synthesis::AssembledStructure::assemble(parse(edit("Parent Nodes: end", "Parent Nodes: ends")).structure,
                                                Teuchos::DefaultComm<int>::getComm());
      },
      "has 2 nodes, not one");
}

// The scene makes its .geo scripts ahead (mesh/ScriptMeshes.hpp): a scene
// refused before a script's mesh is taken must not wait for it. The hub's
// misspelt key is read first; the blade's script runs for minutes.
TEST(Scene, ARefusedSceneStopsTheScriptsItStarted) {
  const std::string yaml = R"(
Scene:
  Substructures:
    hub:
      Kind: C
      Beem: {}
    blade:
      Kind: E
      Parent: hub
      Finite Element Model:
        Mesh: slow_loop.geo
)";
  const auto t0 = std::chrono::steady_clock::now();
  fixtures::expectInputError(
      [&] {
        scene::Scene::fromParameters(*Teuchos::getParametersFromYamlString(yaml),
                                     std::string(CMS_TEST_DATA_DIR) + "/meshes/slow-loop-scene.yaml");
      },
      "unknown key \"Beem\"");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Stopping is a flag looked at every 50 ms and the mesher killed; 10 s is
  // the machine's noise, where the script runs for minutes.
  EXPECT_LT(seconds, 10.0);
}

// Each script a scene names is meshed once: made ahead, over the ranks, and
// taken by its substructure, not meshed again by the model's reader. The
// script counts its own runs (Gmsh's Printf appends to a file beside it):
// four substructures name two distinct requests (one repeated with the same
// Mesh Parameters, its path written three ways), so two runs in all,
// whatever the rank count. Before
// the scene and the model shared FiniteElementModel::meshSource, a path or a
// parameter read differently would have meshed silently twice.
TEST(Scene, EachScriptIsMeshedOnce) {
  const auto comm = Teuchos::DefaultComm<int>::getComm();
  std::string dir;
  if (comm->getRank() == 0) {
    dir = testing::TempDir() + "cms_scene_scripts_" + std::to_string(::getpid());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/counted.geo") << R"(DefineConstant[ n = {4, Name "Parameters/n"} ];
Printf("made") >> "runs.txt";
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Line(1) = {1, 2};
Transfinite Curve{1} = n + 1;
Physical Curve("beam") = {1};
Physical Point("root") = {1};
Physical Point("tip") = {2};
)";
  }
  int length = static_cast<int>(dir.size());
  Teuchos::broadcast(*comm, 0, &length);
  dir.resize(static_cast<std::size_t>(length));
  Teuchos::broadcast(*comm, 0, length, dir.data());
  auto model = [](const std::string& mesh, int n) {
    return "      Finite Element Model:\n        Mesh: " + mesh + "\n        Mesh Parameters: {n: " +
           std::to_string(n) +
           "}\n        Materials: {steel: {Young's Modulus: 2.0e11, Poisson's Ratio: 0.3, Density: 7800.0}}\n"
           "        Element Sets:\n          beam: {Type: Frame, Material: steel, Area: 1.0e-3, Iy: 1.0e-7, "
           "Iz: 1.0e-7, Torsion Constant: 2.0e-7, Orientation: [0, 0, 1]}\n";
  };
  const std::string yaml = "Scene:\n  Substructures:\n    hub:\n      Kind: C\n" + model("counted.geo", 4) +
                           "        Boundary Conditions: {root: {Node Set: root, Fixed: all}}\n"
                           "    arm:\n      Kind: E\n      Parent: hub\n"
                           "      Attachment: {Parent Nodes: tip, Nodes: root}\n" + model("counted.geo", 6) +
                           "    other:\n      Kind: E\n      Parent: hub\n"
                           "      Attachment: {Parent Nodes: tip, Nodes: root}\n" + model(dir + "/counted.geo", 6) +
                           "    again:\n      Kind: E\n      Parent: hub\n"
                           "      Attachment: {Parent Nodes: tip, Nodes: root}\n" + model("./counted.geo", 6);
  const auto scene = scene::Scene::fromParameters(*Teuchos::getParametersFromYamlString(yaml), dir + "/scene.yaml");
  ASSERT_EQ(scene.structure.substructures.size(), 4u);
  EXPECT_EQ(scene.structure.substructures[0].model->mesh->nodeCount(), 5u);
  EXPECT_EQ(scene.structure.substructures[1].model->mesh->nodeCount(), 7u);
  EXPECT_EQ(scene.structure.substructures[2].model->mesh->nodeCount(), 7u);
  EXPECT_EQ(scene.structure.substructures[3].model->mesh->nodeCount(), 7u);
  comm->barrier();  // every rank's meshing done before the count
  if (comm->getRank() == 0) {
    std::ifstream in(dir + "/runs.txt");
    int runs = 0;
    for (std::string line; std::getline(in, line);) runs += line == "made";
    std::filesystem::remove_all(dir);
    // Two requests: {n: 4}, and {n: 6} named three times (relative to the
    // scene, absolute, and as "./counted.geo": the same path once resolved
    // and normalised; three runs before the normalisation).
    EXPECT_EQ(runs, 2) << "runs of the script";
  }
}

// Issue 14 item 9: a repeated key was a Teuchos parser trace whose caret
// pointed at the line after it; now one line naming both.
TEST(Scene, DuplicateKeysNameBothLines) {
  using fixtures::expectInputError;
  const std::string twice = edit("        Area: 0.01\n", "        Area: 0.01\n        Area: 0.02\n");
  expectInputError([&] { scene::Scene::parse(twice, "dup.yaml"); }, "dup.yaml:13: duplicate key 'Area' (first at line 12)");
  // Quoted or not, the same key; a repeated substructure; a repeated top key.
  expectInputError([] { scene::Scene::parse(edit("        Iy: 1.0e-5\n", "        Iy: 1.0e-5\n        'Iy': 2.0e-5\n"), "q.yaml"); },
                   "q.yaml:14: duplicate key 'Iy' (first at line 13)");
  expectInputError([] { scene::Scene::parse(edit("    arm:\n", "    hub:\n"), "s.yaml"); },
                   "s.yaml:17: duplicate key 'hub' (first at line 4)");
  expectInputError([] { scene::Scene::parse(std::string(kGood) + "Scene:\n  Name: x\n", "t.yaml"); },
                   "t.yaml:35: duplicate key 'Scene' (first at line 2)");
  // In a flow mapping, on one line or several, the line scan does not look:
  // the last one won silently (2 vectors for 4), found by a review.
  expectInputError([] { scene::Scene::parse(edit("      Reduction:\n        Basis: Modes\n        Vectors: 4\n",
                                                 "      Reduction: {Basis: Modes, Vectors: 4, Vectors: 2}\n"),
                                            "f.yaml"); },
                   "f.yaml:32:45: duplicate key 'Vectors' (first at line 32)");
  expectInputError([] { scene::Scene::parse(edit("      Reduction:\n        Basis: Modes\n        Vectors: 4\n",
                                                 "      Reduction: {Basis: Modes,\n        Vectors: 4,\n        Vectors: 2}\n"),
                                            "g.yaml"); },
                   "g.yaml:34:9: duplicate key 'Vectors' (first at line 33)");
  // Not duplicates: the same key in sibling mappings, in a comment, in a
  // block scalar, in items of a sequence.
  EXPECT_NO_THROW(scene::Scene::parse(kGood, "good.yaml"));
  EXPECT_NO_THROW(scene::Scene::parse(edit("  Substructures:\n", "  Name: |\n    Kind: a\n    Kind: b\n  Substructures:\n  # Kind: C\n"),
                                      "scalar.yaml"));
  EXPECT_NO_THROW(scene::Scene::parse(
      edit("      Reduction:\n", "      Reduction:\n        Load Patterns: [uniform, tip]\n"), "flow.yaml"));
}

// A second YAML document was ignored silently (found by a review; a scene
// pasted twice is also a repeated top-level key, which the line scan
// names). Refused, naming its line; a lone end marker is no document.
TEST(Scene, ASecondYamlDocumentIsRefused) {
  using fixtures::expectInputError;
  expectInputError([] { scene::Scene::parse(std::string(kGood) + "---\nNotes: {Owner: me}\n", "two.yaml"); },
                   "two.yaml:36:1: a second YAML document");
  EXPECT_NO_THROW(scene::Scene::parse("---\n" + std::string(kGood) + "...\n", "marked.yaml"));
}

// A document whose first token is ',' (a comment that lost its '#') made
// yaml-cpp 0.7 allocate until killed: the scene fuzz test hung on it. It is
// refused with its line before the parser sees it, also after "---", blank
// and comment lines; a ',' further on stays the parser's to judge.
TEST(Scene, ADocumentBeginningWithACommaIsRefusedNotHung) {
  using fixtures::expectInputError;
  expectInputError([] { scene::Scene::parse("# a scene\n, its comment\n" + std::string(kGood), "comma.yaml"); },
                   "comma.yaml:2:1: not a valid scene file (a document cannot begin with ',')");
  expectInputError([] { scene::Scene::parse("\n--- # first\n  , x\n", "marked.yaml"); }, "marked.yaml:3:3:");
  expectInputError([] { scene::Scene::parse(std::string(kGood) + "--- , x\n", "second.yaml"); }, "second.yaml:35:5:");
  expectInputError([] { scene::Scene::parse("Scene:\n  Name: x\n, y\n", "later.yaml"); }, "later.yaml:3:1");
  // The same behind CRLF line ends, a byte-order mark, an anchor or a tag
  // (the first guard missed each, and the parser ran out of memory; found
  // by a review).
  const std::string refused = "a document cannot begin with ','";
  expectInputError([&] { scene::Scene::parse("---\r\n, x\r\n", "crlf.yaml"); }, refused);
  expectInputError([&] { scene::Scene::parse("\xEF\xBB\xBF, x\n", "bom.yaml"); }, refused);
  expectInputError([&] { scene::Scene::parse("Scene: 1\r\n...\r\n, x\r\n", "end.yaml"); }, refused);
  expectInputError([&] { scene::Scene::parse("--- &a\n, x\n", "anchor.yaml"); }, refused);
  expectInputError([&] { scene::Scene::parse("!t , x\n", "tag.yaml"); }, refused);
  // A ',' that begins a line at or left of the document's root node, after
  // an indented root mapping or a root sequence: yaml-cpp 0.7 allocates
  // until killed there too (the long fuzz run, seed 2, cases 33586 and
  // 88744: a comment line broken by "    x: 1" and ", rad)." in the
  // spacecraft scene).
  const std::string atRoot = "a ',' at the start of a line there";
  expectInputError([&] { scene::Scene::parse("# c\n    x: 1\n, rad).\n" + std::string(kGood), "fuzz.yaml"); },
                   "fuzz.yaml:3:1: not a valid scene file (" + atRoot);
  expectInputError([&] { scene::Scene::parse("  x: 1\n\n# c\n, y\n", "indented.yaml"); }, "indented.yaml:4:1:");
  expectInputError([&] { scene::Scene::parse("- a\n- b\n, y\n", "sequence.yaml"); }, "sequence.yaml:3:1:");
  // Where a ',' begins a line validly: inside a flow collection, a plain
  // scalar's continuation, a block scalar's content (indented past the root).
  EXPECT_NO_THROW(scene::Scene::parse(edit("        From: [0.0, 0.0, 0.0]\n", "        From: [0.0\n, 0.0, 0.0]\n"),
                                      "flow.yaml"));
  EXPECT_NO_THROW(scene::Scene::parse(edit("  Substructures:\n", "  Name: a hub\n    , and an arm\n  Substructures:\n"),
                                      "plain.yaml"));
  // A "---" indented in a block scalar is content, not a document marker.
  EXPECT_NO_THROW(scene::Scene::parse(
      edit("  Substructures:\n", "  Name: |\n    Notes\n    ---\n    , with a comma\n  Substructures:\n"), "block.yaml"));
  // A byte-order mark and CRLF line ends on a good scene: read as before.
  std::string crlf;
  for (char c : std::string(kGood)) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  EXPECT_NO_THROW(scene::Scene::parse("\xEF\xBB\xBF---\r\n" + crlf, "bom-crlf.yaml"));
}

// Spin keys the kind does not read were accepted and ignored (found by a
// review): a C's Frame: Stationary (its frame spins with it), an A's or R's Origin
// (they spin about their attachment point), a rigid rotor's or a
// stationary-frame rotor's Stress Stiffening (no prestress is formed in
// either). Each is refused, naming the key and why.
TEST(Scene, SpinKeysAKindDoesNotReadAreRefused) {
  using fixtures::expectInputError;
  const std::string spinning = edit("        Clamp: start\n", "        Clamp: start\n      Spin: {Axis: [0, 0, 1], Rate: 10}\n");
  EXPECT_NO_THROW(scene::Scene::parse(spinning, "ok.yaml"));
  const auto withHubSpin = [&](const std::string& extra) {
    return edit("        Clamp: start\n", "        Clamp: start\n      Spin: {Axis: [0, 0, 1], Rate: 10, " + extra + "}\n");
  };
  expectInputError([&] { scene::Scene::parse(withHubSpin("Frame: Stationary"), "c.yaml"); },
                   "Substructures/hub/Spin/Frame = Stationary");
  EXPECT_NO_THROW(scene::Scene::parse(withHubSpin("Frame: Rotating"), "c1.yaml"));  // what a C does: said
  EXPECT_NO_THROW(scene::Scene::parse(withHubSpin("Origin: [0, 1, 0]"), "c2.yaml"));
  const auto armSpin = [&](const std::string& extra) {
    std::string t = edit("      Kind: E\n", "      Kind: A\n");
    return edit2(t, "        Torsion Constant: 2.0e-7\n",
                 "        Torsion Constant: 2.0e-7\n      Spin: {Axis: [1, 0, 0], Rate: 5" + extra + "}\n");
  };
  EXPECT_NO_THROW(scene::Scene::parse(armSpin(""), "a.yaml"));
  expectInputError([&] { scene::Scene::parse(armSpin(", Origin: [1, 0, 0]"), "a1.yaml"); },
                   "Substructures/arm/Spin/Origin");
  expectInputError([&] { scene::Scene::parse(armSpin(", Frame: Stationary, Stress Stiffening: true"), "a2.yaml"); },
                   "Substructures/arm/Spin/Stress Stiffening");
  EXPECT_NO_THROW(scene::Scene::parse(armSpin(", Frame: Stationary"), "a3.yaml"));
  // A rigid rotor (R) spins about its attachment point and has no stress:
  // its Origin, Frame and Stress Stiffening are read by no one.
  const auto wheelSpin = [&](const std::string& extra) {
    return std::string(kGood) + "    wheel:\n      Kind: R\n      Parent: hub\n      Attachment:\n        Type: Node\n"
                                "        Parent Nodes: end\n      Rotor:\n        Mass: 8.0\n"
                                "        Transverse Inertia: 0.04\n        Axial Inertia: 0.07\n"
                                "      Spin: {Axis: [0, 0, 1], Rate: 600" + extra + "}\n";
  };
  EXPECT_NO_THROW(scene::Scene::parse(wheelSpin(""), "r.yaml"));
  expectInputError([&] { scene::Scene::parse(wheelSpin(", Origin: [1, 0, 0]"), "r1.yaml"); },
                   "Substructures/wheel/Spin/Origin");
  expectInputError([&] { scene::Scene::parse(wheelSpin(", Stress Stiffening: true"), "r2.yaml"); },
                   "Substructures/wheel/Spin/Stress Stiffening");
  expectInputError([&] { scene::Scene::parse(wheelSpin(", Frame: Stationary"), "r3.yaml"); },
                   "Substructures/wheel/Spin/Frame = Stationary");
}

TEST(Scene, ANameIsNotAPath) {
  // "Name: ../escaped" wrote escaped.json beside the output directory, not in
  // it; "nosuchdir/x" failed only after the computation (found by a review).
  using fixtures::expectInputError;
  for (const char* name : {"../escaped", "nosuchdir/x", "a\\b", ".."})
    expectInputError([&] { scene::Scene::parse(edit("Scene:\n", std::string("Scene:\n  Name: '") + name + "'\n"), "n.yaml"); },
                     "n.yaml: Scene/Name = ");
  EXPECT_EQ(scene::Scene::parse(edit("Scene:\n", "Scene:\n  Name: my-run.2\n"), "n.yaml").name, "my-run.2");
}

TEST(Scene, UnreadableFilesAreInputErrors) {
  using fixtures::expectInputError;
  const std::string dir = CMS_TEST_DATA_DIR "/scenes/";
  expectInputError([&] { scene::Scene::read(dir + "no-such-scene.yaml"); }, "cannot open the scene file");
  // The parser's line and column, without its echo, caret and throw trace.
  expectInputError([&] { scene::Scene::read(dir + "malformed.yaml"); }, "malformed.yaml:4:11: not a valid scene file (end of sequence flow not found)");
  expectInputError([&] { scene::Scene::read(dir + "misspelt-key.yaml"); }, "unknown key \"Youngs Modulus\"");
  expectInputError([&] { scene::Scene::read(dir + "missing-mesh.yaml"); }, "no-such-mesh.msh");
}

TEST(Scene, OrdinaryYamlReads) {
  // What most YAML tools write and Teuchos 13.2's own reader refused (issue
  // 17): block sequences (one "- value" per line, indented or not) and a
  // flow mapping over several lines; yaml-cpp reads them into the same list.
  const std::string block = edit("        From: [0.0, 0.0, 0.0]\n", "        From:\n          - 0.0\n          - 0.0\n          - 0.0\n");
  const std::string flush = edit("        From: [0.0, 0.0, 0.0]\n", "        From:\n        - 0.0\n        - 0.0\n        - 0.0\n");
  const auto a = scene::Scene::parse(kGood, "a.yaml"), b = scene::Scene::parse(block, "b.yaml"),
             c = scene::Scene::parse(flush, "c.yaml");
  const auto x = [](const scene::Scene& sc) { return sc.structure.substructures[0].model->mesh->coordinates[0]; };
  EXPECT_EQ(x(b), x(a));
  EXPECT_EQ(x(c), x(a));
  const auto d = scene::Scene::parse(
      edit("      Reduction:\n        Basis: Modes\n        Vectors: 4\n", "      Reduction: {Basis: Modes,\n                  Vectors: 4}\n"),
      "d.yaml");  // a flow mapping over two lines
  const auto& r = d.structure.substructures.back().reduction;
  EXPECT_EQ(r.get<std::string>("Basis"), "Modes");
  EXPECT_EQ(r.get<int>("Vectors"), 4);
}

TEST(SceneRegression, ExampleScenesReproduceTheirFrequencies) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  for (const std::string name :
       {"spacecraft", "rotating-blade", "shaft-on-support", "rotor-chain", "solid-blade", "helicopter-hover"}) {
    SCOPED_TRACE(name);
    const auto sc = scene::Scene::read(std::string(CMS_SCENE_DIR) + "/" + name + ".yaml");
    const auto a = synthesis::AssembledStructure::assemble(sc.structure, comm);
    const auto s = synthesis::SynthesizedStructure::synthesize(a);
    auto speeds = a.nominalSpeeds();
    for (double& v : speeds) v *= sc.speedFactor;
    // A rotor on a moving attachment has its fixed-frame modes (theory §16.8).
    const auto m = s.movingHubs().empty()
                       ? s.solve(speeds, sc.solve)
                       : analysis::PeriodicStructure(s, speeds).solve(sc.solve.get<int>("Number of Modes")).modes;
    ASSERT_EQ(m.result.status, eigen::SolveStatus::Converged) << m.result.reason;
    const std::string expected = CMS_TEST_DATA_DIR "/expected/" + name + "-modes.csv";
    if (std::getenv("CMS_WRITE_EXPECTED") && comm->getRank() == 0) {
      std::ofstream out(expected);
      out << std::setprecision(15) << "mode,rad_per_s\n";
      for (std::size_t i = 0; i < m.result.modes.size(); ++i) out << i + 1 << ',' << m.result.modes[i].omega << '\n';
    }
    // A spinning free structure's rigid motions (zero, and at the frame rate
    // Omega) are defective (Jordan) double eigenvalues, computed to
    // sqrt(eps kappa) Omega, kappa ~ (omega_max / Omega)^2 ~ 1e7 for the
    // spacecraft: up to 1e-4 Omega apart between rank counts, so 2e-4 Omega
    // for those (theory §11.6).
    double frame = 0.0;
    for (std::size_t k = 0; k < a.numSubstructures(); ++k)
      if (a.substructure(k).kind == synthesis::SubstructureKind::Central && a.substructure(k).spin)
        frame = std::abs(a.substructure(k).spin->rate * sc.speedFactor);
    std::ifstream in(expected);
    ASSERT_TRUE(in) << expected;
    std::string line;
    std::getline(in, line);
    std::vector<double> listed;
    while (std::getline(in, line)) listed.push_back(std::stod(line.substr(line.find(',') + 1)));
    ASSERT_FALSE(listed.empty()) << expected;
    // The scene's frequency scale: its highest listed frequency. A zero
    // below 1e-6 of it is a rigid-body zero, which the solvers compute (and
    // call zero) to 1e-6 of the frequency scale (Rigid Body Tolerance).
    const double scale = *std::max_element(listed.begin(), listed.end());
    std::size_t i = 0;
    for (const double w : listed) {
      ASSERT_LT(i, m.result.modes.size());
      const double got = m.result.modes[i].omega;
      const bool defective = sc.structure.freeReference.size() && frame > 0 &&
                             (w < 1e-3 * frame || std::abs(w - frame) < 1e-3 * frame);
      if (defective) EXPECT_NEAR(got, w, 2e-4 * frame) << "mode " << i + 1;
      else if (w <= 1e-6 * scale) EXPECT_NEAR(got, w, 1e-6 * scale) << "mode " << i + 1;
      else EXPECT_NEAR(got / w, 1.0, 1e-8) << "mode " << i + 1;
      ++i;
    }
    EXPECT_EQ(i, m.result.modes.size());
  }
}

// The free spacecraft on the sparse path: its rigid motions (six zeros at
// rest; at speed the zero pair about the spin axis) are rigid, as the dense
// path calls them, not DIVERGENCE. The sparse path judged each Ritz value
// against its own mode's scale s_q = sqrt(|q|^T|K||q| / q^H M q) + ...,
// which a rigid coordinate (K zero, G zero along the spin) makes rounding,
// while the projected pencil's dggev computes those zeros only to its
// normwise accuracy (growth 8e-9 .. 5e-6 1/s read as divergence, exit 0;
// found by a review; theory §4.3). Each mode's verdict must be the dense
// path's; the rigid ones' |lambda| is below 1e-6 of the frequency scale
// either way.
TEST(SceneRegression, TheFreeSpacecraftsVerdictsOnTheSparsePathAreTheDensePaths) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto sc = scene::Scene::read(std::string(CMS_SCENE_DIR) + "/spacecraft.yaml");
  const auto a = synthesis::AssembledStructure::assemble(sc.structure, comm);
  const auto s = synthesis::SynthesizedStructure::synthesize(a);
  for (const double factor : {0.0, 1.0}) {
    SCOPED_TRACE("speed factor " + std::to_string(factor));
    auto speeds = a.nominalSpeeds();
    for (double& v : speeds) v *= factor;
    Teuchos::ParameterList dense = sc.solve, sparse = sc.solve;
    dense.set("Solver", "Dense");
    sparse.set("Solver", "Sparse");
    const auto d = s.solve(speeds, dense), p = s.solve(speeds, sparse);
    ASSERT_EQ(d.result.status, eigen::SolveStatus::Converged) << d.result.reason;
    ASSERT_EQ(p.result.status, eigen::SolveStatus::Converged) << p.result.reason;
    ASSERT_EQ(p.result.modes.size(), d.result.modes.size());
    int rigid = 0;
    for (std::size_t i = 0; i < d.result.modes.size(); ++i) {
      const auto& dm = d.result.modes[i];
      const auto& pm = p.result.modes[i];
      EXPECT_EQ(eigen::toString(pm.stability), std::string(eigen::toString(dm.stability)))
          << "mode " << i + 1 << ": dense lambda " << dm.lambda << ", sparse " << pm.lambda;
      rigid += dm.stability == eigen::Stability::RigidBody;
    }
    EXPECT_GE(rigid, factor == 0.0 ? 6 : 2) << "the rigid motions the test is about";
  }
}

// compareWithTruth pairs each reduced mode with the truth mode of its shape,
// not the truth mode of the same index (found by a review: on the rotor
// chain with every basis Craig-Bampton 3 the reduced model lacks the truth's
// 141.6 Hz mode, so its 155.2 Hz mode, 3.4% above the truth's 150.1 Hz of
// the same shape, was reported 9.6% off against 141.6, and nothing said a
// mode was missing; on the free shaft at its critical speed with Modes 2,
// two modes' order swaps and the worst error read 33% for 52%). Checked
// here against the test's own pairing: each reduced shape's best individual
// MAC (unweighted, over every truth mode computed) where that is clear
// (>= 0.8, the next below 0.5), and the truth modes in the reduced range
// that are no reduced mode's best counted missing.
namespace {
using Shape = std::vector<Teuchos::RCP<MultiVector>>;
double macOf(const Shape& u, const Shape& v) {
  std::complex<double> uv = 0.0;
  double uu = 0.0, vv = 0.0;
  for (std::size_t k = 0; k < u.size(); ++k) {
    const auto ur = u[k]->getVector(0), ui = u[k]->getVector(1), vr = v[k]->getVector(0), vi = v[k]->getVector(1);
    uv += std::complex<double>(ur->dot(*vr) + ui->dot(*vi), ur->dot(*vi) - ui->dot(*vr));
    uu += ur->dot(*ur) + ui->dot(*ui);
    vv += vr->dot(*vr) + vi->dot(*vi);
  }
  return std::norm(uv) / (uu * vv);
}
}  // namespace

TEST(SceneRegression, TruthComparisonPairsModesByShape) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  struct Case {
    const char* scene;
    const char* basis;
    int vectors;
    int lacking;  // truth modes in range the reduced model lacks
    int edge;     // a count whose last mode has the next truth mode's shape (0: none)
  };
  for (const Case c :
       {Case{"rotor-chain-target", "Craig-Bampton", 3, 1, 0}, Case{"free-shaft-critical", "Modes", 2, 0, 8}}) {
    SCOPED_TRACE(c.scene);
    auto sc = scene::Scene::read(std::string(CMS_TEST_DATA_DIR) + "/scenes/" + c.scene + ".yaml");
    for (auto& spec : sc.structure.substructures) {
      spec.reduction = Teuchos::ParameterList("Reduction");
      spec.reduction.set("Basis", c.basis);
      spec.reduction.set("Vectors", c.vectors);
    }
    const auto a = synthesis::AssembledStructure::assemble(sc.structure, comm);
    const auto s = synthesis::SynthesizedStructure::synthesize(a);
    const auto truth = synthesis::SynthesizedStructure::synthesize(a, true);
    auto speeds = a.nominalSpeeds();
    for (double& v : speeds) v *= sc.speedFactor;
    const int n = sc.solve.get<int>("Number of Modes");
    Teuchos::ParameterList wide = sc.solve;
    wide.set("Number of Modes", 2 * n);
    const auto rm = analysis::solveForComparison(s, speeds, sc.solve), tm = truth.solve(speeds, wide);
    ASSERT_EQ(rm.result.status, eigen::SolveStatus::Converged) << rm.result.reason;
    ASSERT_EQ(tm.result.status, eigen::SolveStatus::Converged) << tm.result.reason;
    const auto cmp = analysis::compareWithTruth(s, rm, truth, tm, n);
    const int T = static_cast<int>(tm.result.modes.size());
    std::vector<Shape> truthShapes;
    for (int t = 0; t < T; ++t) truthShapes.push_back(truth.expand(tm, t));
    std::vector<int> bestOf(static_cast<std::size_t>(n), -1);
    double top = 0.0;
    int checked = 0;
    for (int m = 0; m < n; ++m) {
      top = std::max(top, rm.result.modes[m].omega);
      const Shape u = s.expand(rm, m);
      std::vector<double> mac(static_cast<std::size_t>(T));
      for (int t = 0; t < T; ++t) mac[t] = macOf(u, truthShapes[t]);
      const int best = static_cast<int>(std::max_element(mac.begin(), mac.end()) - mac.begin());
      double next = 0.0;
      for (int t = 0; t < T; ++t)
        if (t != best) next = std::max(next, mac[t]);
      if (rm.result.modes[m].omega < 1e-3 * tm.result.modes[T - 1].omega || mac[best] < 0.8 || next >= 0.5) continue;
      bestOf[m] = best;
      ++checked;
      EXPECT_EQ(cmp.modes[m].truthOmega, tm.result.modes[best].omega)
          << "reduced mode " << m + 1 << " (" << rm.result.modes[m].omega << " rad/s) has the shape of truth mode "
          << best + 1 << " (MAC " << mac[best] << ")";
      EXPECT_NEAR(cmp.modes[m].relativeError,
                  (rm.result.modes[m].omega - tm.result.modes[best].omega) / tm.result.modes[best].omega, 1e-12);
    }
    EXPECT_GE(checked, 3) << "too few clear shapes for the test to mean anything";
    int unclaimed = 0;
    for (int t = 0; t < T; ++t)
      if (tm.result.modes[t].omega <= top && std::find(bestOf.begin(), bestOf.end(), t) == bestOf.end()) ++unclaimed;
    EXPECT_EQ(cmp.missingModes, c.lacking);
    EXPECT_LE(cmp.missingModes, unclaimed);
    EXPECT_EQ(cmp.unmatchedModes, 0);
    // Two modes in the other order at the edge of the compared range (the
    // free shaft's 8th reduced mode has the 9th truth mode's shape, its 9th
    // the 8th's): compared up to the 8th, the 8th truth mode is the 9th
    // reduced mode's, not a missing one (a review).
    if (c.edge > 0) {
      const auto edge = analysis::compareWithTruth(s, rm, truth, tm, c.edge);
      ASSERT_GE(bestOf[c.edge - 1], 0) << "the edge mode's shape is not clear";
      EXPECT_EQ(bestOf[c.edge - 1], c.edge) << "the test's premise: the edge mode has the next truth mode's shape";
      EXPECT_EQ(edge.modes[c.edge - 1].truthOmega, tm.result.modes[c.edge].omega);
      EXPECT_EQ(edge.missingModes, 0);
    }
  }
}

// The truncation search says at which steps it checked the inclusion
// principle: on the sparse path (whose frequencies carry its eigensolver's
// error, which the check's round-off term does not know) none, so its zero
// findings are not a clean result; on the dense path every step after the
// first (found by a review: the table and CSV showed 0 for steps never
// checked).
TEST(SceneRegression, TruncationSaysWhichStepsTheInclusionPrincipleChecked) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto sc = scene::Scene::read(std::string(CMS_TEST_DATA_DIR) + "/scenes/boom-at-rest.yaml");
  const auto a = synthesis::AssembledStructure::assemble(sc.structure, comm);
  Teuchos::ParameterList study;
  study.set("Start", 1);
  study.set("Step", 1);
  study.set("Accuracy", 1e-4);
  for (const char* solver : {"Dense", "Sparse"}) {
    SCOPED_TRACE(solver);
    Teuchos::ParameterList solve = sc.solve;
    solve.set("Solver", solver);
    const auto r = analysis::TruncationStudy(a, solve, study).run();
    ASSERT_GE(r.steps.size(), 3u);
    EXPECT_FALSE(r.steps.front().inclusionChecked) << "the first step has nothing to compare with";
    for (std::size_t i = 1; i < r.steps.size(); ++i) {
      EXPECT_EQ(r.steps[i].inclusionChecked, std::string(solver) == "Dense") << "step " << i;
      EXPECT_TRUE(r.steps[i].findings.empty()) << "step " << i;
    }
  }
}

// The Campbell study's zero-frequency critical speed of the disc on a
// spinning C shaft (the shaft's first bending passing through zero in its
// own frame, theory §12.1) by the dense count and by the sparse inertia
// ("Dense Limit" below the model's size), on 1 and 2 ranks: the same speed
// to the bisection's tolerance (1e-6 of the speed, the default, doubled).
TEST(SceneRegression, ZeroFrequencyCriticalSpeedByTheDenseAndTheSparseCount) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto sc = scene::Scene::read(std::string(CMS_TEST_DATA_DIR) + "/scenes/disc-on-spinning-shaft.yaml");
  const auto a = synthesis::AssembledStructure::assemble(sc.structure, comm);
  const auto s = synthesis::SynthesizedStructure::synthesize(a);
  Teuchos::ParameterList study;
  study.set("Steps", 11);
  std::vector<double> found;
  for (const int limit : {100000, 4}) {
    SCOPED_TRACE("Dense Limit " + std::to_string(limit));
    Teuchos::ParameterList solve = sc.solve;
    solve.set("Dense Limit", limit);
    const auto r = analysis::CampbellStudy(study).run(analysis::SynthesizedSweepProblem(a, s, solve));
    ASSERT_TRUE(r.zeroCountsTaken) << r.zeroCountsNote;
    ASSERT_EQ(r.zeroFrequencySpeeds.size(), 1u) << r.zeroCountsNote;
    found.push_back(r.zeroFrequencySpeeds[0]);
  }
  EXPECT_GT(found[0], 170.0);
  EXPECT_LT(found[0], 185.0);
  EXPECT_NEAR(found[1], found[0], 2e-6 * found[0]);
}

// Issue 18: a sweep's dense solves run on threads (SynthesizedStructure::
// solveMany, one Teuchos-free LAPACK solve per thread on the gathered M, G_i,
// K_ij), and must give what one solve after another gives, bit for bit: the
// same computation on the same matrices. The spacecraft (free: the general
// dggev path, with rigid and frame-rate clusters) and the shaft on a support
// (clamped: Meirovitch's SVD with its Sturm check), 11 speeds each from 0 to
// twice nominal, on 3 threads per rank.
TEST(SceneRegression, ThreadedSweepSolvesEqualOneAfterAnother) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  for (const std::string name : {"spacecraft", "shaft-on-support"}) {
    SCOPED_TRACE(name);
    const auto sc = scene::Scene::read(std::string(CMS_SCENE_DIR) + "/" + name + ".yaml");
    const auto a = synthesis::AssembledStructure::assemble(sc.structure, comm);
    const auto s = synthesis::SynthesizedStructure::synthesize(a);
    std::vector<std::vector<double>> speeds;
    for (int k = 0; k <= 10; ++k) {
      auto v = a.nominalSpeeds();
      for (double& x : v) x *= 0.2 * k;
      speeds.push_back(v);
    }
    const auto threaded = s.solveMany(speeds, sc.solve, 3);
    ASSERT_EQ(threaded.size(), speeds.size());
    for (std::size_t k = 0; k < speeds.size(); ++k) {
      const auto one = s.solve(speeds[k], sc.solve);
      const auto& many = threaded[k];
      EXPECT_EQ(many.speeds, speeds[k]);
      EXPECT_EQ(many.path, one.path);
      EXPECT_EQ(many.result.status, one.result.status) << many.result.reason;
      EXPECT_EQ(many.result.solver, one.result.solver);
      ASSERT_EQ(many.result.modes.size(), one.result.modes.size()) << "speed " << k;
      for (std::size_t m = 0; m < one.result.modes.size(); ++m) {
        EXPECT_EQ(many.result.modes[m].lambda, one.result.modes[m].lambda) << "speed " << k << " mode " << m;
        EXPECT_EQ(many.result.modes[m].q, one.result.modes[m].q) << "speed " << k << " mode " << m;
        EXPECT_EQ(many.result.modes[m].residual, one.result.modes[m].residual) << "speed " << k << " mode " << m;
        EXPECT_EQ(many.result.modes[m].stability, one.result.modes[m].stability) << "speed " << k << " mode " << m;
      }
    }
  }
}

TEST(SceneRegression, RotatingBladeSceneMatchesWrightTable) {
  // The example scene is the validated blade (theory §10.1): flapwise
  // 7.3604, 26.8091, 66.6840 rad/s at T = 6 (modes 1, 3 and 5 here; the
  // others are lead-lag), to the mesh issue's 5e-4.
  const auto sc = scene::Scene::read(std::string(CMS_SCENE_DIR) + "/rotating-blade.yaml");
  const auto a = synthesis::AssembledStructure::assemble(sc.structure, Teuchos::DefaultComm<int>::getComm());
  const auto m = synthesis::SynthesizedStructure::synthesize(a).solve(a.nominalSpeeds(), sc.solve);
  ASSERT_GE(m.result.modes.size(), 5u);
  EXPECT_NEAR(m.result.modes[0].omega / 7.3604, 1.0, 5e-4);
  EXPECT_NEAR(m.result.modes[2].omega / 26.8091, 1.0, 5e-4);
  EXPECT_NEAR(m.result.modes[4].omega / 66.6840, 1.0, 5e-4);
}

TEST(SceneRegression, PartitionedBladeConvergesToItsTruth) {
  // The Wright blade, spinning, reduced by the Partitioned basis (theory
  // §18) in 4 parts with the cut-off given as an integer: its lowest six
  // modes against the truth of the same scene. Rayleigh-Ritz with the
  // centrifugal and inertia static shapes solved exactly through the
  // partition: measured 6.9e-7 worst at the cut-off 120 Hz (4.1e-6 at 60
  // Hz, the order-2 convergence of theory §18.3); bounded at 2e-6.
  const auto sc = scene::Scene::read(std::string(CMS_TEST_DATA_DIR) + "/scenes/partitioned-rotating-blade.yaml");
  const auto r = againstTruth(sc, 6, 1);
  ASSERT_EQ(r.ratios.size(), 6u);
  EXPECT_EQ(r.basis, "Partitioned");
  EXPECT_NE(r.report.find("into 4 parts"), std::string::npos) << r.report;
  double worst = 0;
  for (int i = 0; i < 6; ++i) {
    worst = std::max(worst, r.ratios[i] - 1.0);
    EXPECT_GE(r.ratios[i], 1.0 - 1e-9) << "mode " << i;
    EXPECT_NEAR(r.ratios[i], 1.0, 2e-6) << "mode " << i;
  }
  if (Teuchos::DefaultComm<int>::getComm()->getRank() == 0)
    std::printf("Partitioned blade: worst error %.2e, %lld coordinates; %s\n", worst, r.coordinates, r.report.c_str());
}

// The benchmark rotor with its solid hub Partitioned and a polynomial
// interface (theory §18.4; drivers/bench/rotor/rotor-partitioned-hub.yaml):
// the three blades are attached to faces of the hub, which join its
// separator as pieces of their own, so the blades' attachment motions reach
// the hub through the polynomials (degree 2). Against the truth of the same
// mesh (h = 30 mm, 14,730 DOFs): every frequency from above (inclusion
// principle; the reduced values carry the rounding of a Rayleigh-Ritz
// projection, eps lambda_max / lambda_i, far below 1e-9 here), and the
// lowest 20 within 1e-3 (measured 8.4e-6).
TEST(Scene, ThePartitionedHubsPolynomialInterfaceCarriesTheBlades) {
  const auto sc = scene::Scene::read(std::string(CMS_SCENE_DIR) + "/../bench/rotor/rotor-partitioned-hub.yaml",
                                     {{"h", 0.03}});
  const auto r = againstTruth(sc, 20, 0);
  ASSERT_EQ(r.ratios.size(), 20u);
  EXPECT_EQ(r.basis, "Partitioned");
  EXPECT_NE(r.report.find("polynomials of degree <= 2"), std::string::npos) << r.report;
  EXPECT_NE(r.report.find("by block conjugate gradients"), std::string::npos) << r.report;
  double worst = 0;
  for (int i = 0; i < 20; ++i) {
    worst = std::max(worst, r.ratios[i] - 1.0);
    EXPECT_GE(r.ratios[i], 1.0 - 1e-9) << "mode " << i;
    EXPECT_LT(r.ratios[i], 1.0 + 1e-3) << "mode " << i;
  }
  if (Teuchos::DefaultComm<int>::getComm()->getRank() == 0)
    std::printf("Partitioned hub, polynomial interface: worst error %.2e; %s\n", worst, r.report.c_str());
}

TEST(Scene, XmlScenesReadLikeYaml) {
  // Trilinos' other input-deck format comes for free: the same list written
  // as XML (by extension .xml) gives the same structure.
  auto p = Teuchos::getParametersFromYamlString(kGood);
  const std::string xml = testing::TempDir() + "scene_" + std::to_string(Teuchos::DefaultComm<int>::getComm()->getRank()) + ".xml";
  Teuchos::writeParameterListToXmlFile(*p, xml);
  const auto a = scene::Scene::read(xml), b = parse(kGood);
  ASSERT_EQ(a.structure.substructures.size(), b.structure.substructures.size());
  for (std::size_t i = 0; i < a.structure.substructures.size(); ++i) {
    EXPECT_EQ(a.structure.substructures[i].name, b.structure.substructures[i].name);
    EXPECT_EQ(a.structure.substructures[i].model->mesh->nodeCount(), b.structure.substructures[i].model->mesh->nodeCount());
  }
}

TEST(Scene, PlacementMovesAMeshRigidly) {
  // The solid blade meshed along +x, placed along +y at (0, 0.5, 0): every
  // node moves by the rotation (90 degrees about z) and the translation, so
  // the frequencies, which do not depend on where the blade is, stay.
  const std::string dir = std::string(CMS_SCENE_DIR);
  std::ifstream in(dir + "/solid-blade.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const auto at = yaml.find("      Finite Element Model:");
  ASSERT_NE(at, std::string::npos);
  yaml.insert(at, "      Placement:\n        Axis: [0.0, 0.0, 1.0]\n        Angle: 90.0\n        Translation: [0.0, 0.5, 0.0]\n");
  const auto moved = scene::Scene::parse(yaml, dir + "/moved.yaml");
  const auto original = scene::Scene::read(dir + "/solid-blade.yaml");
  const auto& m0 = *original.structure.substructures[1].model->mesh;
  const auto& m1 = *moved.structure.substructures[1].model->mesh;
  ASSERT_EQ(m0.nodeCount(), m1.nodeCount());
  // To rounding of x -> R x + t, relative to the coordinates' extent (with
  // the translation): a 3-term product sum, cos(90 deg) ~ 6e-17 instead of
  // 0, and the addition of t, each within an eps of the extent: 8 eps.
  double extent = 0.5;
  for (double x : m0.coordinates) extent = std::max(extent, std::abs(x) + 0.5);
  const double tol = 8 * std::numeric_limits<double>::epsilon() * extent;
  for (std::size_t n = 0; n < m0.nodeCount(); n += 97) {
    EXPECT_NEAR(m1.coordinates[3 * n], -m0.coordinates[3 * n + 1], tol);
    EXPECT_NEAR(m1.coordinates[3 * n + 1], m0.coordinates[3 * n] + 0.5, tol);
    EXPECT_NEAR(m1.coordinates[3 * n + 2], m0.coordinates[3 * n + 2], tol);
  }
  fixtures::expectInputError([&] { scene::Scene::parse(edit("      Beam:\n        From: [1.0", "      Placement:\n        Angle: 10.0\n      Beam:\n        From: [1.0"), "p.yaml"); },
                             "only a \"Finite Element Model\" is placed");
  // A spring's components act along the structure's axes, and Placement
  // turns the mesh under it: one along y, left as written, then acted along
  // the placed blade's -x, a different structure with no message (found by
  // a review: a frame beam turned about its axis went from 12.67 to 20.19
  // Hz). As with Copies, only a spring the rotation maps onto itself is
  // placed; another is refused naming it.
  const auto withSpring = [&](const std::string& stiffness) {
    std::string t = yaml;
    const auto es = t.find("            Material: steel\n");
    EXPECT_NE(es, std::string::npos);
    return t.insert(es + std::string("            Material: steel\n").size(),
                    "        Springs:\n          side: {Node Set: tip, Stiffness: " + stiffness + "}\n");
  };
  fixtures::expectInputError([&] { scene::Scene::parse(withSpring("[0, 2.0e4, 0, 0, 0, 0]"), dir + "/s.yaml"); },
                             "Placement: the substructure's spring 'side' acts along the structure's axes");
  EXPECT_NO_THROW(scene::Scene::parse(withSpring("[2.0e4, 2.0e4, 1.0e4, 0, 0, 0]"), dir + "/s2.yaml"));
}

// The coverage verdict where a substructure's Ritz value lies just above the
// cut-off while its exact mode lies just below: the partitioned Wright blade
// at rest, whose 10th Ritz value is 2.2e-6 above its mode. With the cut-off
// 1e-7 below that value, the Sturm count finds 10 modes and the basis 9
// values: "can miss 1 mode" without a band; with a band of 1e-6 (the cut-off
// known to that), the 10th value is that mode approximated from above; with
// 1e-9 it is not within it. Through `cms modes` (ModalAnalysis, 10 modes,
// the band 4x the highest mode's estimate) the verdict said "can miss 1
// mode" for this blade on one BLAS and "complete" on another, by where the
// cut-off's rounding fell (a false alarm, found by a review); now never.
TEST(SceneRegression, ACoverageValueJustAboveTheCutoffIsNoMissingMode) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  auto sc = scene::Scene::read(std::string(CMS_TEST_DATA_DIR) + "/scenes/partitioned-rotating-blade.yaml");
  sc.solve.set("Number of Modes", 10);
  const auto a = synthesis::AssembledStructure::assemble(sc.structure, comm);
  const auto s = synthesis::SynthesizedStructure::synthesize(a);
  std::size_t k = 0;
  while (k < s.reductions().size() && s.reductions()[k].name != "blade") ++k;
  ASSERT_LT(k, s.reductions().size());
  std::vector<double> ritz = s.reductions()[k].frequencyEstimates;
  std::sort(ritz.begin(), ritz.end());
  ASSERT_GE(ritz.size(), 11u);
  const double cut = ritz[9] * (1.0 - 1e-7);
  const auto verdict = [&](double band) {
    for (const auto& c : s.coverage(cut, band))
      if (c.name == "blade") return c;
    return synthesis::SubstructureCoverage();
  };
  const auto none = verdict(0.0), wide = verdict(1e-6), narrow = verdict(1e-9);
  EXPECT_EQ(none.sturmCount, 10) << none.verdict;
  EXPECT_EQ(none.represented, 9) << none.verdict;
  EXPECT_NE(none.verdict.find("can miss 1 mode"), std::string::npos) << none.verdict;
  EXPECT_EQ(wide.withinBand, 1) << wide.verdict;
  EXPECT_NE(wide.verdict.find("complete to the cut-off's accuracy"), std::string::npos) << wide.verdict;
  EXPECT_NE(narrow.verdict.find("can miss 1 mode"), std::string::npos) << narrow.verdict;

  Teuchos::ParameterList options;
  options.set("Speed Factor", 0.0);
  const auto r = analysis::ModalAnalysis(sc.structure, sc.solve, options).run(comm);
  for (const auto& c : r.coverage) {
    EXPECT_EQ(c.verdict.find("can miss"), std::string::npos) << c.name << ": " << c.verdict;
    if (c.sturmCount >= 0) EXPECT_EQ(c.represented + c.withinBand, c.sturmCount) << c.name << ": " << c.verdict;
  }
}

// A clamped bar of C3D20R bricks one element across: the reduced brick's
// zero-energy (hourglass) modes communicate along the column, and the model
// has seven zero frequencies at rest. Spinning without stress stiffening,
// the softening turned each into a real root: seven DIVERGENCE modes (growth
// 70.7 1/s), exit 0, where the bar is stable (found by a review). At speed,
// unstable modes now send the structure to the at-rest check too, and both
// refuse it naming the hourglass modes (at rest it said "clamp it" of a
// clamped bar).
TEST(SceneRegression, AReducedHex20ColumnsHourglassModesAreNamed) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::string scene = std::string(R"(Scene:
  Name: c3d20r-column
  Substructures:
    bar:
      Kind: C
      Finite Element Model:
        Mesh: )") + CMS_TEST_DATA_DIR + R"(/meshes/bar_c3d20r_one_across.inp
        Materials:
          steel: {Young's Modulus: 2.1e11, Poisson's Ratio: 0.3, Density: 7850.0}
        Element Sets:
          bar: {Type: Solid, Material: steel}
        Boundary Conditions:
          root: {Node Set: root, Fixed: all}
      Spin: {Axis: [0, 0, 1], Origin: [-0.1, 0, 0], Stress Stiffening: false, Rate: 100}
      Reduction: {Basis: Full}
  Analysis:
    Number of Modes: 8
    Solver: Dense
)";
  const auto sc = scene::Scene::parse(scene, "c3d20r-column.yaml");
  for (const double factor : {1.0, 0.0}) {
    SCOPED_TRACE(factor);
    Teuchos::ParameterList options;
    options.set("Speed Factor", factor);
    fixtures::expectInputError([&] { analysis::ModalAnalysis(sc.structure, sc.solve, options).run(comm); },
                               "zero-energy (hourglass) modes of its reduced-integration Hex20 elements");
  }
  // The same column with Hex20: Full: a stable bar.
  std::string full = scene;
  const std::string set = "bar: {Type: Solid, Material: steel}";
  full.replace(full.find(set), set.size(), "bar: {Type: Solid, Material: steel, Hex20: Full}");
  Teuchos::ParameterList options;
  const auto r = analysis::ModalAnalysis(scene::Scene::parse(full, "full.yaml").structure, sc.solve, options).run(comm);
  ASSERT_FALSE(r.modes.result.modes.empty());
  EXPECT_TRUE(r.modes.result.isStable());
}

// The two-blade helicopter of helicopter-two-blades.yaml without its gear and
// lag dampers, at 23 rad/s: in ground resonance (Floquet, the two-blade rotor
// is not isotropic). One mode asked: the lowest is stable, and the growing
// one lies above it. The Floquet analysis had every multiplier and dropped
// the growing one with the count: "stable", exit 0 (found by a review). Now
// every unstable mode is listed past the asked ones.
TEST(SceneRegression, AnInstabilityBeyondTheAskedModesIsListed) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  std::ifstream in(std::string(CMS_TEST_DATA_DIR) + "/scenes/helicopter-two-blades.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"            Damping: [12000.0, 12000.0, 0.0, 0.0, 0.0, 0.0]\n", ""},
           {"            Damping: 1200.0\n", ""},
           {"        Rate: 40.0", "        Rate: 23.0"},
           {"    Number of Modes: 10", "    Number of Modes: 1"}}) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  const auto sc = scene::Scene::parse(text, std::string(CMS_TEST_DATA_DIR) + "/scenes/h2-undamped.yaml");
  const auto r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm);
  const auto& modes = r.modes.result.modes;
  ASSERT_GE(modes.size(), 2u) << r.modes.result.solver;
  EXPECT_FALSE(r.modes.result.isStable());
  EXPECT_NE(modes[0].stability, eigen::Stability::Flutter);
  bool growing = false;
  for (std::size_t i = 1; i < modes.size(); ++i) growing = growing || modes[i].stability == eigen::Stability::Flutter;
  EXPECT_TRUE(growing);
  // The coverage's cut-off is the highest asked mode, not an unstable one
  // listed past the count (it was: the count check then ran to a frequency
  // no mode was asked for).
  EXPECT_EQ(r.cutoff, modes[0].omega);
}

// A child's attachment nodes off its parent's attachment: the rotor chain's
// tip moved 1 m beyond the blade's end hung on a 1 m massless rigid link,
// and the first frequency fell from 3.97 to 2.48 Hz without a word (found
// by a review). Offsets are rigid links by design (a solid child on a
// rigid link, a shaft off its support's axis), so this is a note, naming
// the node and the gap; a gap within 1e-3 of the model's size is none.
TEST(Scene, AChildsAttachmentNodesOffItsParentAreNoted) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  std::ifstream in(std::string(CMS_SCENE_DIR) + "/rotor-chain.yaml");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto moved = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    const std::string was = "        From: [2.3, 0.0, 0.0]\n        To: [2.5, 0.0, 0.0]\n";
    const auto at = t.find(was);
    EXPECT_NE(at, std::string::npos);
    return t.replace(at, was.size(), "        From: " + from + "\n        To: " + to + "\n");
  };
  const auto notes = [&](const std::string& scene, const std::string& path = "gap.yaml") {
    std::string all;
    const auto a = synthesis::AssembledStructure::assemble(scene::Scene::parse(scene, path).structure, comm);
    for (const auto& n : a.notes()) all += n + "\n";
    return all;
  };
  const std::string gap = notes(moved("[3.3, 0.0, 0.0]", "[3.5, 0.0, 0.0]"));
  EXPECT_NE(gap.find("tip: its attachment node 1 lies 1 from blade's attachment nodes 'end': it hangs on a massless "
                     "rigid link"),
            std::string::npos)
      << gap;
  EXPECT_EQ(notes(moved("[2.3000001, 0.0, 0.0]", "[2.5, 0.0, 0.0]")).find("rigid link"), std::string::npos);
  EXPECT_EQ(notes(text).find("rigid link"), std::string::npos);

  // A RigidFit attachment the same (only a Node attachment was tested): an
  // arm fitted to a solid hub's tip face (x = 0.2), moved 1 m beyond it.
  std::ifstream fitIn(std::string(CMS_TEST_DATA_DIR) + "/scenes/craig-bampton-cutoff-rigidfit.yaml");
  const std::string fit((std::istreambuf_iterator<char>(fitIn)), std::istreambuf_iterator<char>());
  const std::string arm = "        From: [0.2, 0.0, 0.0]\n        To: [1.2, 0.0, 0.0]\n";
  ASSERT_NE(fit.find(arm), std::string::npos);
  std::string far = fit;
  far.replace(far.find(arm), arm.size(), "        From: [1.2, 0.0, 0.0]\n        To: [2.2, 0.0, 0.0]\n");
  const std::string fitPath = std::string(CMS_TEST_DATA_DIR) + "/scenes/craig-bampton-cutoff-rigidfit.yaml";
  const std::string fitGap = notes(far, fitPath);
  EXPECT_NE(fitGap.find("arm: its attachment node 1 lies 1 from hub's attachment nodes 'tip': it hangs on a massless "
                        "rigid link"),
            std::string::npos)
      << fitGap;
  EXPECT_EQ(notes(fit, fitPath).find("rigid link"), std::string::npos);
}

// Two arms fitted (RigidFit) to one face of a Craig-Bampton hub: the second
// arm's constraints are the first's, so the hub's fixed-interface problem is
// the one-arm problem. Its 12 constraints, 6 independent, were taken as 12:
// six random directions were removed with them, the hub's Ritz estimates
// moved (1193.83 Hz -> 1194.15, symmetric pairs split) and 6 coordinates
// were lost; on the sparse path an "internal error" (found by a review).
// Now the constraints are reduced to their range first.
TEST(SceneRegression, TwoChildrenFittedToOneFaceConstrainTheHubOnce) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::string path = std::string(CMS_TEST_DATA_DIR) + "/scenes/craig-bampton-cutoff-rigidfit.yaml";
  std::ifstream in(path);
  const std::string one((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string two = one;
  const auto arm = two.find("    arm:\n"), end = two.find("  Analysis:");
  ASSERT_NE(arm, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  std::string second = two.substr(arm, end - arm);
  second.replace(0, 8, "    arm2:");
  two.insert(end, second);
  std::vector<double> hz[2];
  long long coordinates[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const auto a = synthesis::AssembledStructure::assemble(scene::Scene::parse(k ? two : one, path).structure, comm);
    const auto s = synthesis::SynthesizedStructure::synthesize(a);
    ASSERT_EQ(s.reductions().front().name, "hub");
    hz[k] = s.reductions().front().frequencyEstimates;
    coordinates[k] = s.reductions().front().coordinates;
    std::sort(hz[k].begin(), hz[k].end());
  }
  EXPECT_EQ(coordinates[1], coordinates[0]);
  ASSERT_EQ(hz[1].size(), hz[0].size());
  // The same Rayleigh-Ritz problem: its values to rounding, eps lambda_max /
  // lambda_i of a projection (1e-8 here is far above it, and far below the
  // 2.7e-4 of the dependent constraints).
  for (std::size_t i = 0; i < std::min<std::size_t>(hz[0].size(), 12); ++i)
    EXPECT_NEAR(hz[1][i] / hz[0][i], 1.0, 1e-8) << "hub value " << i;
}

// A shaft of unequal bending stiffness (unstable between its two critical
// speeds) carrying a blade on a free lag hinge, at 240 rad/s: the
// divergence is the answer. When every unstable structure was checked at
// rest, the free hinge's zero there refused it as "ill-conditioned" (exit
// 3; found by a review of that change): only structures holding reduced
// Hex20 cells are so checked now.
TEST(SceneRegression, AFreeHingeOnAnUnstableShaftIsAnswered) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto sc = scene::Scene::parse(R"(Scene:
  Substructures:
    shaft:
      Kind: C
      Spin:
        Axis: [0.0, 0.0, 1.0]
        Origin: [0.0, 0.0, 0.0]
        Rate: 240.0
      Beam:
        From: [0.0, 0.0, 0.0]
        To: [0.0, 0.0, 1.0]
        Elements: 10
        Young's Modulus: 2.0e11
        Density: 7800.0
        Area: 1.2566e-3
        Iy: 1.0e-7
        Iz: 4.0e-7
        Torsion Constant: 2.5e-7
        Orientation: [1.0, 0.0, 0.0]
        Clamp: start
      Reduction:
        Basis: Full
    blade:
      Kind: E
      Parent: shaft
      Attachment:
        Type: Node
        Parent Nodes: end
        Nodes: start
      Beam:
        From: [0.0, 0.0, 1.0]
        To: [0.5, 0.0, 1.0]
        Elements: 8
        Young's Modulus: 7.0e10
        Density: 100.0
        Area: 1.0e-4
        Iy: 1.0e-9
        Iz: 1.0e-9
        Torsion Constant: 2.0e-9
        Orientation: [0.0, 1.0, 0.0]
        Hinges:
          lag:
            Station: 0.25
            Axis: [0.0, 0.0, 1.0]
            Stiffness: 0.0
      Reduction:
        Basis: Full
  Analysis:
    Number of Modes: 6
)", "hinge.yaml");
  const auto r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm);
  ASSERT_FALSE(r.modes.result.modes.empty());
  EXPECT_EQ(r.modes.result.modes.front().stability, eigen::Stability::Divergence);
}

// Three findings of a review on the shaft on its support (22 reduced
// coordinates), each failed before:
// - seven modes by the sparse solver: a Krylov-Schur subspace of 2N
//   vectors broke Anasazi down ("Orthogonalization constraints not
//   feasible"); now solved, the same as the dense solve to the sparse
//   tolerance;
// - twenty modes leave no room for a subspace: with the truth and the count
//   asked, "bad input" (exit 2) from the comparison of no modes; now the
//   solve's own NUMERICAL ISSUE, nothing compared;
// - at rest, six modes, the count cutting a near-repeated pair (truth 51.6310
//   and 51.6311 Hz; the reduced pair 1.1e-5 and 3.8e-5 above): the second
//   reduced member lay above the count's point and read "MODES MISSING"
//   beside "every truth mode paired"; a reduced frequency within the highest
//   mode's estimated error above the point now counts.
TEST(SceneRegression, ASmallSparseSolveAndACountCuttingAPair) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::string path = std::string(CMS_SCENE_DIR) + "/shaft-on-support.yaml";
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto with = [&](const std::string& analysis) {
    std::string t = text;
    const std::string was = "    Number of Modes: 8\n";
    const auto at = t.find(was);
    EXPECT_NE(at, std::string::npos);
    return scene::Scene::parse(t.replace(at, was.size(), analysis), path);
  };
  Teuchos::ParameterList options;
  options.set("Truth", true);
  options.set("Check Count", true);
  {
    const auto sparse = with("    Number of Modes: 7\n    Solver: Sparse\n");
    const auto dense = with("    Number of Modes: 7\n    Solver: Dense\n");
    const auto rs = analysis::ModalAnalysis(sparse.structure, sparse.solve, Teuchos::ParameterList()).run(comm);
    const auto rd = analysis::ModalAnalysis(dense.structure, dense.solve, Teuchos::ParameterList()).run(comm);
    ASSERT_EQ(rs.modes.result.status, eigen::SolveStatus::Converged) << rs.modes.result.reason;
    ASSERT_EQ(rs.modes.result.modes.size(), 7u);
    ASSERT_EQ(rd.modes.result.modes.size(), 7u);
    // The sparse solve's residual tolerance (1e-10 by default) bounds each
    // frequency's relative error by about its square root for a simple
    // mode; 1e-6 leaves room for the pair.
    for (std::size_t i = 0; i < 7; ++i)
      EXPECT_NEAR(rs.modes.result.modes[i].omega, rd.modes.result.modes[i].omega, 1e-6 * rd.modes.result.modes[i].omega);
  }
  {
    const auto small = with("    Number of Modes: 20\n    Solver: Sparse\n");
    const auto r = analysis::ModalAnalysis(small.structure, small.solve, options).run(comm);
    EXPECT_EQ(r.modes.result.status, eigen::SolveStatus::NumericalIssue);
    EXPECT_NE(r.modes.result.reason.find("no room for a Krylov subspace"), std::string::npos) << r.modes.result.reason;
    EXPECT_TRUE(r.trueErrors.empty());
  }
  {
    std::string t = text;
    const auto swap = [&t](const std::string& from, const std::string& to) {
      const auto at = t.find(from);
      ASSERT_NE(at, std::string::npos) << from;
      t.replace(at, from.size(), to);
    };
    swap("        Iy: 8.0e-7", "        Iy: 5.0e-7");  // the support symmetric: pairs
    swap("    Number of Modes: 8\n", "    Number of Modes: 6\n    Solver: Dense\n    Speed Factor: 0.0\n");
    const auto pair = scene::Scene::parse(t, path);
    Teuchos::ParameterList atRest(options);
    atRest.set("Speed Factor", pair.speedFactor);
    const auto r = analysis::ModalAnalysis(pair.structure, pair.solve, atRest).run(comm);
    ASSERT_EQ(r.modes.result.modes.size(), 6u);
    EXPECT_EQ(r.truthMissing, 0);
    EXPECT_EQ(r.truthCount, 7);
    EXPECT_EQ(r.reducedCount, r.truthCount) << "count band " << r.countBand;
    EXPECT_GT(r.countBand, 0.0);
    EXPECT_LE(r.countBand, 1e-3);
  }
}

// A solid bar held by a line of its nodes (translations only) to a frame
// hub turns freely about that line. Refused before assembly, naming the
// set; and where the up-front test stands aside (the bar has springs of its
// own, here along the line, which do not restrain the turn), the at-rest
// check calls it "unrestrained", naming the bar. Both were "ill-conditioned"
// (exit 3) with the Full basis, blaming the clamped hub, whose share of the
// mode is rounding (3e-24) and whose strain relative to its own motion is
// its conditioning (7.4e-5); found by a review.
TEST(SceneRegression, ASolidChildOnALineOfNodesTurnsFreely) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::string path = std::string(CMS_TEST_DATA_DIR) + "/scenes/solid-child-on-a-line.yaml";
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto run = [&](const std::string& t) {
    const auto sc = scene::Scene::parse(t, path);
    analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm);
  };
  fixtures::expectInputError([&] { run(text); },
                             "substructure 'bar' (E): its attachment nodes 'rootline' (5 nodes, translations only) "
                             "cannot hold it: they lie on a line");
  std::string sprung = text;
  const std::string sets = "        Element Sets:\n          blade: {Type: Solid, Material: steel}\n";
  const auto at = sprung.find(sets);
  ASSERT_NE(at, std::string::npos);
  sprung.insert(at + sets.size(), "        Springs:\n          along: {Node Set: rootline, Stiffness: [0, 1.0e3, 0, 0, 0, 0]}\n");
  fixtures::expectInputError([&] { run(sprung); }, "substructure 'bar' moves freely");
  // Spinning about z, stress-stiffened, the same bar would be a blade on a
  // flap hinge through the spin axis, held by the centrifugal stiffness; but
  // the prestress solve needs K with the attachment held positive definite,
  // so it is refused as at rest, by the plainer message (a review asked).
  std::string spinning = text;
  const std::string kind = "    bar:\n      Kind: E\n";
  const auto k = spinning.find(kind);
  ASSERT_NE(k, std::string::npos);
  spinning.replace(k, kind.size(), "    bar:\n      Kind: A\n      Spin: {Axis: [0.0, 0.0, 1.0], Rate: 10.0}\n");
  fixtures::expectInputError([&] { run(spinning); }, "its attachment nodes 'rootline' (5 nodes, translations only)");
}

// A hub of three spokes carrying three blades (Copies), reviewed: (1) its
// Admissible basis of "Vectors: 6" kept the first blade's six attachment
// shapes and none of the others', so two blades hung on a rigid hub, and
// the structure's 16.12 Hz triple came out 16.12, 43.64, 43.64, silently:
// the twelve shapes left out are now listed in `dropped` (cms modes says
// "ask Vectors >= 18"), and with 18 the frequencies are the Full hub's to
// the Admissible basis' accuracy; (2) a prototype blade reduced to nothing
// (Guyan, a leaf) was taken for a Full basis and each copy reduced on its
// own with a FINDING: its empty basis now turns.
TEST(SceneRegression, AttachmentShapesLeftOutAreListedAndEmptyBasesTurn) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::string deck = testing::TempDir() + "cms_spokes_" + std::to_string(::getpid()) + "_" +
                           std::to_string(comm->getRank()) + ".inp";
  std::ofstream(deck) << "*NODE\n1, 0, 0, 0\n2, 0.2, 0.0, 0.0\n3, -0.1, 0.17320508075688776, 0.0\n"
                         "4, -0.1, -0.17320508075688767, 0.0\n*ELEMENT, TYPE=B31, ELSET=spokes\n1, 1, 2\n2, 1, 3\n"
                         "3, 1, 4\n*NSET, NSET=centre\n1\n*NSET, NSET=pt0\n2\n";
  const auto scene = [&](const std::string& hub, const std::string& blade) {
    return R"(
Scene:
  Substructures:
    hub:
      Kind: C
      Spin: {Axis: [0, 0, 1], Origin: [0, 0, 0], Rate: 0}
      Finite Element Model:
        Mesh: )" + deck + R"(
        Materials: {st: {Young's Modulus: 2.0e11, Poisson's Ratio: 0.3, Density: 7800.0}}
        Element Sets: {spokes: {Type: Frame, Material: st, Area: 0.001, Iy: 1.0e-7, Iz: 1.0e-7, Torsion Constant: 2.0e-7, Orientation: [0, 0, 1]}}
        Boundary Conditions: {c: {Node Set: centre, Fixed: all}}
      Reduction: )" + hub + R"(
    blade:
      Kind: E
      Parent: hub
      Copies: 3
      Attachment: {Type: Node, Parent Nodes: pt0, Nodes: start}
      Beam: {From: [0.2, 0, 0], To: [1.2, 0, 0], Elements: 10, Young's Modulus: 7.0e10, Density: 2700.0, Area: 0.004, Iy: 2.0e-6, Iz: 5.0e-6, Torsion Constant: 4.0e-6, Orientation: [0, 0, 1], Tip Mass: 3.0}
      Reduction: )" + blade + R"(
  Analysis: {Number of Modes: 6}
)";
  };
  const auto hz = [&](const std::string& text, std::vector<synthesis::SubstructureReduction>* reps = nullptr) {
    const auto sc = scene::Scene::parse(text, deck);
    const auto r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm);
    if (reps) *reps = r.reduced->reductions();
    std::vector<double> out;
    for (const auto& m : r.modes.result.modes) out.push_back(m.hz);
    return out;
  };
  const auto full = hz(scene("{Basis: Full}", "{Basis: Full}"));
  std::vector<synthesis::SubstructureReduction> reps;
  hz(scene("{Basis: Admissible, Vectors: 6}", "{Basis: Full}"), &reps);
  int left = 0;
  for (const auto& d : reps.at(0).dropped) left += d.find("not kept: the basis' 6 vectors are fewer than the 18") != std::string::npos;
  EXPECT_EQ(left, 12);
  const auto admissible = hz(scene("{Basis: Admissible, Vectors: 18}", "{Basis: Full}"), &reps);
  ASSERT_EQ(full.size(), 6u);
  ASSERT_EQ(admissible.size(), 6u);
  // The three blades' lowest triple and the next: the hub's static shapes
  // under every blade's interface loads hold them to the Admissible
  // basis' error, measured 1e-7 here; 1e-4 leaves room and is far below the
  // 1.7x of a blade clamped.
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(admissible[i], full[i], 1e-4 * full[i]) << "mode " << i + 1;
  int interface = 0;
  for (const auto& l : reps.at(0).labels) interface += l.rfind("static: interface", 0) == 0;
  EXPECT_EQ(interface, 18);
  // The Guyan blade (no vectors: a leaf) turns for its copies.
  hz(scene("{Basis: Full}", "{Basis: Guyan}"), &reps);
  for (const auto& rep : reps) EXPECT_TRUE(rep.notTurned.empty()) << rep.name << ": " << rep.notTurned;
  std::remove(deck.c_str());
}

namespace {
// A free beam with a core's point inertia, spun about y (its intermediate
// axis with the default inertia): the scene of the free-body tests below.
std::string freeEulerBeam(double rate, int elements, const std::string& inertia, const std::string& damping,
                          int count) {
  return R"(
Scene:
  Free Reference: mid
  Substructures:
    body:
      Kind: C
      Spin: {Axis: [0, 1, 0], Origin: [0, 0, 0], Rate: )" + std::to_string(rate) + R"(}
      Beam: {From: [-0.5, 0, 0], To: [0.5, 0, 0], Elements: )" + std::to_string(elements) + R"(, Young's Modulus: 7.0e10, Density: 2700.0, Area: 0.02, Iy: 1.0e-4, Iz: 1.0e-4, Torsion Constant: 2.0e-4, Orientation: [0, 0, 1], Point Masses: {core: {Node Set: mid, Mass: 100.0, Inertia: [)" + inertia + R"(, 0, 0, 0]}})" + damping + R"(}
      Reduction: {Basis: Full}
  Analysis: {Number of Modes: )" + std::to_string(count) + R"(}
)";
}
}  // namespace

// Stability verdicts judged on the whole model's frequency scale grew with
// the mesh (its stiffest element, and Rayleigh's beta omega_max^2): a
// Jeffcott rotor with internal damping above its critical speed (78.3 rad/s)
// grew at 0.241 1/s (the closed form (beta w^2 / 2)(Omega / w - 1): 0.242)
// and read "stable" at 40 elements (found by a review). Now each mode's
// growth is judged on its own residual's error bound, refined where only
// the general solve's normwise residual leaves it undecided: the same
// verdict at 4, 40 and 80 elements, growth rates agreeing across the meshes
// to 1% (the beam's flexibility between them), and stable below the
// critical speed. A free body spun about its intermediate axis diverges at
// 0.777 Omega (Euler): the same at 4 and 64 elements.
TEST(SceneRegression, InternalDampingInstabilityDoesNotDependOnTheMesh) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto jeffcott = [](int elements, double rate) {
    return R"(
Scene:
  Substructures:
    shaft:
      Kind: C
      Spin: {Axis: [1, 0, 0], Origin: [0, 0, 0], Rate: )" + std::to_string(rate) + R"(}
      Beam: {From: [0, 0, 0], To: [1, 0, 0], Elements: )" + std::to_string(elements) + R"(, Young's Modulus: 2.0e11, Density: 7800.0, Area: 1.2566e-3, Iy: 1.2566e-7, Iz: 1.2566e-7, Torsion Constant: 2.5133e-7, Tip Mass: 10.0, Tip Inertia: [0.02, 0.01, 0.01], Clamp: start, Structural Damping: {Rayleigh Beta: 1.0e-4}}
      Reduction: {Basis: Full}
  Analysis: {Number of Modes: 4}
)";
  };
  const auto euler = [](int elements) { return freeEulerBeam(1.0, elements, "10.0, 20.0, 40.0", "", 8); };
  const auto modes = [&](const std::string& scene) {
    const auto sc = parse(scene);
    return analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm).modes.result.modes;
  };
  struct Growth {
    int unstable = 0;
    double rate = 0.0, error = 0.0;  // the fastest growth, and its eigenvalue's error bound
  };
  auto growing = [](const std::vector<eigen::GyroscopicMode>& ms) {
    Growth g;
    for (const auto& m : ms)
      if (m.stability == eigen::Stability::Flutter || m.stability == eigen::Stability::Divergence) {
        ++g.unstable;
        if (m.growthRate > g.rate) g.rate = m.growthRate, g.error = m.eigenvalueError;
      }
    return g;
  };
  const auto coarse = growing(modes(jeffcott(4, 140.0)));
  EXPECT_GE(coarse.unstable, 1);
  // 80 elements: the general solve's residual alone (without refinement)
  // put the growth within its uncertainty there (found by a review).
  for (int elements : {40, 80}) {
    const auto fine = growing(modes(jeffcott(elements, 140.0)));
    EXPECT_GE(fine.unstable, 1) << elements << " elements";
    EXPECT_NEAR(fine.rate, coarse.rate, 1e-2 * coarse.rate) << elements << " elements";
    EXPECT_NEAR(fine.rate, 0.242, 2e-2 * 0.242) << elements << " elements";  // the Jeffcott closed form
  }
  EXPECT_EQ(growing(modes(jeffcott(40, 60.0))).unstable, 0);  // below the critical speed
  // Euler: Omega sqrt((Iyy - Ixx)(Izz - Iyy) / (Ixx Izz)) with the beam's
  // inertia added to the core's: Ixx 10.54, Iyy 24.77, Izz 44.77 (the
  // beam's first bending, ~8e3 rad/s, changes it by ~1e-8), within 1e-3.
  // At 64 elements the whole solve, normwise on the system's scale, read
  // it "rigid" (found by a review); the block the elastic stiffness does
  // not reach is now solved on its own scale (theory §4.3).
  const double rate = std::sqrt((24.77 - 10.54) * (44.77 - 24.77) / (10.54 * 44.77));
  for (int elements : {4, 64}) {
    const auto ms = modes(euler(elements));
    const auto g = growing(ms);
    EXPECT_EQ(g.unstable, 1) << elements << " elements";
    EXPECT_NEAR(g.rate, rate, 1e-3 * rate) << elements << " elements";
    // The rest of the rigid block: two zeros (the translation along the
    // axis, the turn about it) and three rigid motions seen at the frame
    // rate, 1 rad/s, to the 1e-4 that flags them as artefacts (theory
    // §11.6); at 64 elements the whole solve gave them at 1.0102 (neutral)
    // and 0.974 to 1.026 at 128, split by sqrt(eps) s.
    int zeros = 0, frameRate = 0;
    for (const auto& m : ms) {
      zeros += m.stability == eigen::Stability::RigidBody;
      frameRate += m.stability != eigen::Stability::RigidBody && std::abs(m.omega - 1.0) <= 1e-4;
    }
    EXPECT_EQ(zeros, 2) << elements << " elements";
    EXPECT_EQ(frameRate, 3) << elements << " elements";
  }
  // At rest the six zeros are the six rigid motions, each once: their rigid
  // coordinates (the first six rows) are independent, the least of them
  // after Gram-Schmidt above 1e-3 of its length (an M_rr-orthonormal basis
  // is as independent as M_rr's condition, 4 here, allows). The pencil's own
  // vectors at a Jordan block repeat the block's one shape, and two rigid
  // motions came back twice, the axial translation and the turn about the
  // axis lost (found by the Campbell rank test).
  const std::string rest = freeEulerBeam(0.0, 64, "10.0, 20.0, 40.0", "", 8);
  std::vector<std::vector<std::complex<double>>> basis;
  double least = 1.0;
  for (const auto& m : modes(rest)) {
    if (m.stability != eigen::Stability::RigidBody) continue;
    std::vector<std::complex<double>> v(m.q.begin(), m.q.begin() + 6);
    const auto norm = [](const std::vector<std::complex<double>>& x) {
      double s = 0.0;
      for (const auto& c : x) s += std::norm(c);
      return std::sqrt(s);
    };
    const double length = norm(v);
    for (const auto& b : basis) {
      std::complex<double> dot = 0.0;
      for (int i = 0; i < 6; ++i) dot += std::conj(b[i]) * v[i];
      for (int i = 0; i < 6; ++i) v[i] -= dot * b[i];
    }
    const double left = norm(v);
    least = std::min(least, length > 0.0 ? left / length : 0.0);
    for (auto& c : v) c /= left;
    basis.push_back(v);
  }
  EXPECT_EQ(basis.size(), 6u);
  EXPECT_GT(least, 1e-3);
}

// The free beam's block solved apart (theory §4.3), against what a review
// found in its first version, each reproduced by the reviewer's run:
//  - its rounding radius, eps cond(K_ee) under a square root, was applied
//    to every mode of the block: Rayleigh alpha's flutter of the frame-rate
//    motion (growth 0.00223 1/s, -alpha/2 + sqrt(alpha Omega / 2)) read
//    "stable" at 64 elements, and a divergence of 0.00233 1/s (two inertias
//    4e-6 apart) "rigid";
//  - at rest with Rayleigh beta, whose D is rounding on the rigid rows, the
//    zeros' rounding read DIVERGENCE on the block's rounding scale;
//  - three modes asked of the damped beam kept -0.777 and dropped +0.777,
//    equal to rounding in |lambda|, and the verdict read stable.
TEST(SceneRegression, AFreeBodysSmallInstabilitiesAreNotTakenForZeros) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto& beam = freeEulerBeam;
  const auto modes = [&](const std::string& scene) {
    const auto sc = parse(scene);
    return analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm).modes.result.modes;
  };
  // The growth rates within 1e-3: each closed form's own approximation
  // (the beam's flexibility, ~1e-8, and alpha's first order in alpha / Omega).
  const auto growing = [](const std::vector<eigen::GyroscopicMode>& ms, eigen::Stability kind, double rate) {
    int n = 0;
    for (const auto& m : ms) n += m.stability == kind && std::abs(m.growthRate - rate) <= 1e-3 * rate;
    return n;
  };
  const double alpha = 1e-5, flutter = -alpha / 2 + std::sqrt(alpha / 2);
  for (int elements : {16, 64}) {
    const auto ms = modes(beam(1.0, elements, "10.0, 20.0, 40.0", ", Structural Damping: {Rayleigh Alpha: 1.0e-5}", 10));
    EXPECT_EQ(growing(ms, eigen::Stability::Flutter, flutter), 1) << elements << " elements";
  }
  // Inertias (with the beam's) 10.54, 24.77, 24.77 + 1e-4: Euler's rate
  // sqrt((24.77 - 10.54) 1e-4 / (10.54 (24.77 + 1e-4))) = 0.00233.
  const double slow = std::sqrt((24.77 - 10.54) * 1e-4 / (10.54 * 24.7701));
  EXPECT_EQ(growing(modes(beam(1.0, 64, "10.0, 20.0, 20.0001", "", 8)), eigen::Stability::Divergence, slow), 1);
  for (const auto& m : modes(beam(0.0, 4, "10.0, 20.0, 40.0", ", Structural Damping: {Rayleigh Beta: 1.0e-5}", 8)))
    EXPECT_FALSE(m.stability == eigen::Stability::Divergence || m.stability == eigen::Stability::Flutter)
        << "at rest: growth " << m.growthRate;
  // The built-in spacecraft at rest with Rayleigh beta on its booms: its
  // beta K leaves the rigid rows 90 eps ||D|| of the synthesis' rounding,
  // which the block took for damping, and two of its six rigid motions came
  // back a second time, one as DIVERGENCE at 1.7e-15 1/s (a review). Six
  // rigid modes, each once, and nothing grows.
  {
    std::ifstream in(std::string(CMS_SCENE_DIR) + "/spacecraft.yaml");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string tip = "        Tip Mass: 5.0\n";
    ASSERT_NE(text.find(tip), std::string::npos);
    for (std::size_t at = text.find(tip); at != std::string::npos; at = text.find(tip, at + 1))
      text.insert(at + tip.size(), "        Structural Damping: {Rayleigh Beta: 1.0e-3}\n");
    const auto sc = parse(text);
    Teuchos::ParameterList atRest;
    atRest.set("Speed Factor", 0.0);
    const auto ms = analysis::ModalAnalysis(sc.structure, sc.solve, atRest).run(comm).modes.result.modes;
    EXPECT_EQ(std::count_if(ms.begin(), ms.end(),
                            [](const eigen::GyroscopicMode& m) { return m.stability == eigen::Stability::RigidBody; }),
              6);
    for (const auto& m : ms)
      EXPECT_FALSE(m.stability == eigen::Stability::Divergence || m.stability == eigen::Stability::Flutter)
          << "spacecraft at rest: growth " << m.growthRate;
  }
  const double euler = std::sqrt((24.77 - 10.54) * (44.77 - 24.77) / (10.54 * 44.77));
  EXPECT_EQ(growing(modes(beam(1.0, 64, "10.0, 20.0, 40.0", ", Structural Damping: {Rayleigh Beta: 1.0e-5}", 3)),
                    eigen::Stability::Divergence, euler),
            1);
}

// A reduced hub carrying a child by a Boolean interface: the child's forces
// on the shared rows were not passed to the hub's residual, which then held
// the whole interface force, and every estimate read "unresolved" (true
// errors 1e-8 to 3e-5); Target Accuracy 1e-3 grew the hub to every DOF and
// failed (found by a review). Checked against the same structure's Full
// model: each estimate within the factor 3 of the true error that the
// estimates' validation asserts (theory §11.8), where the true error is
// above 1e-9 (below that the two solves' rounding, eps (scale/omega)^2,
// competes), for the child Full and reduced; and the target reached.
TEST(SceneRegression, AReducedParentOfABooleanChildEstimatesItsErrors) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto text = [](const std::string& hub, const std::string& mid, const std::string& analysis) {
    return R"(
Scene:
  Substructures:
    hub:
      Kind: C
      Beam: {From: [0, 0, 0], To: [0.6, 0, 0], Elements: 6, Young's Modulus: 7.0e10, Density: 2700.0, Area: 1.0e-3, Iy: 2.0e-8, Iz: 2.0e-7, Torsion Constant: 5.0e-8, Orientation: [0, 1, 0], Clamp: start}
      Reduction: )" + hub + R"(
    mid:
      Kind: E
      Parent: hub
      Attachment: {Type: Boolean, Parent Nodes: end, Nodes: start}
      Beam: {From: [0.6, 0, 0], To: [1.4, 0, 0], Elements: 8, Young's Modulus: 7.0e10, Density: 2700.0, Area: 1.0e-3, Iy: 2.0e-8, Iz: 2.0e-7, Torsion Constant: 5.0e-8, Orientation: [0, 1, 0]}
      Reduction: )" + mid + R"(
  Analysis: )" + analysis + R"(
)";
  };
  const auto run = [&](const std::string& scene, const Teuchos::ParameterList& options = Teuchos::ParameterList()) {
    const auto sc = parse(scene);
    return analysis::ModalAnalysis(sc.structure, sc.solve, options).run(comm);
  };
  const auto truth = run(text("{Basis: Full}", "{Basis: Full}", "{Number of Modes: 6}"));
  ASSERT_EQ(truth.modes.result.modes.size(), 6u);
  for (const std::string mid : {"{Basis: Full}", "{Basis: Craig-Bampton, Vectors: 6}"}) {
    const auto r = run(text("{Basis: Craig-Bampton, Vectors: 6}", mid, "{Number of Modes: 4}"));
    ASSERT_EQ(r.modes.result.modes.size(), 4u);
    ASSERT_EQ(r.estimates.size(), 4u);
    int compared = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      const double w = r.modes.result.modes[i].omega, t = truth.modes.result.modes[i].omega;
      const double trueError = (w - t) / t;
      if (trueError < 1e-9) continue;
      ++compared;
      EXPECT_GT(r.estimates[i], trueError / 3.0) << mid << " mode " << i + 1;
      EXPECT_LT(r.estimates[i], trueError * 3.0) << mid << " mode " << i + 1;
    }
    EXPECT_GE(compared, 2) << mid;
  }
  Teuchos::ParameterList target;
  target.set("Target Accuracy", 1e-3);
  const auto enriched = run(text("{Basis: Craig-Bampton, Vectors: 6}", "{Basis: Full}", "{Number of Modes: 4}"), target);
  EXPECT_TRUE(enriched.enrichment.reached);
}

namespace {
/// An aluminium hub spinning at 30 rad/s, clamped at its root, and the
/// Beam line of a blade from 1.1 to 2.2 m with a 1 kg tip mass: the
/// offset-link and stiff-stub tests' structure.
const char* const kSpinningHubAndBlade[2] = {R"(    hub:
      Kind: C
      Beam: {From: [0, 0, 0], To: [1, 0, 0], Elements: 10, Young's Modulus: 7.0e10, Density: 2700.0, Area: 1.0e-3, Iy: 2.0e-8, Iz: 2.0e-7, Torsion Constant: 5.0e-8, Orientation: [0, 1, 0], Clamp: start}
      Spin: {Axis: [0, 0, 1], Rate: 30.0}
      Reduction: {Basis: Full}
)", R"(      Beam: {From: [1.1, 0, 0], To: [2.2, 0, 0], Elements: 10, Young's Modulus: 7.0e10, Density: 2700.0, Area: 1.0e-3, Iy: 2.0e-8, Iz: 2.0e-7, Torsion Constant: 5.0e-8, Orientation: [0, 1, 0], Tip Mass: 1.0})"};
}  // namespace

// A blade whose root node sits 0.1 m off the spinning hub's tip node,
// attached without a Point: it hangs on a rigid link to the tip, and the
// link's geometric stiffness was formed only for a Point's offset, so the
// blade was 2.9%, 1.9% and 1.2% low against the same blade with the Point
// at its root or on a stiff massless stub (found by a review). The gap and
// the Point are one model (the same rigid link, the same loads): they
// agree to the rounding of two assemblies, 1e-9 of the frequency (eps times
// the stiffness spread, below 1e6 here). A RigidFit on a solid's face with
// its child off the face is still without the term (theory §11.4): noted.
TEST(SceneRegression, AChildsNodeOffItsParentsNodeIsStiffenedAsOnALink) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto text = [](const std::string& attachment) {
    return R"(
Scene:
  Substructures:
)" + std::string(kSpinningHubAndBlade[0]) + R"(    blade:
      Kind: E
      Parent: hub
      Attachment: )" + attachment + "\n" + kSpinningHubAndBlade[1] + R"(
      Reduction: {Basis: Full}
  Analysis: {Number of Modes: 6}
)";
  };
  const auto hz = [&](const std::string& scene) {
    const auto sc = parse(scene);
    const auto r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm);
    std::vector<double> out;
    for (const auto& m : r.modes.result.modes) out.push_back(m.hz);
    return out;
  };
  const auto gap = hz(text("{Type: Node, Parent Nodes: end, Nodes: start}"));
  const auto point = hz(text("{Type: Node, Parent Nodes: end, Nodes: start, Point: [1.1, 0, 0]}"));
  ASSERT_EQ(gap.size(), 6u);
  ASSERT_EQ(point.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(gap[i], point[i], 1e-9 * point[i]) << "mode " << i + 1;

  // A RigidFit: the link runs from the centroid of the parent's set, turned
  // by the rotation fitted to it. Against the same arm on a stiff stub
  // (E 7e15) RigidFit-attached at that centroid and carrying the arm by
  // Node: the stub's flexibility and mass move the frequencies by less than
  // 1e-5 between E = 7e13 and 7e15 (measured), so 2e-5. Without the term the
  // RigidFit was 3.8e-5 to 4.8e-4 low (it was only noted at assembly).
  const auto hub = [](const std::string& ns) {
    return R"(
Scene:
  Substructures:
    hub:
      Kind: C
      Finite Element Model:
        Mesh: ../meshes/bar_hex.geo
        Mesh Parameters: {L: 1.0, a: 0.03, nx: 4, ns: )" + ns + R"(}
        Materials: {steel: {Young's Modulus: 2.0e11, Poisson's Ratio: 0.3, Density: 7800.0}}
        Element Sets: {blade: {Type: Solid, Material: steel}}
        Boundary Conditions: {root: {Node Set: root, Fixed: all}}
      Spin: {Axis: [0, 0, 1], Rate: 30.0}
      Reduction: {Basis: Full}
)";
  };
  // The arm from P to its tip; the stub from the tip face's centroid to P.
  const auto arm = [](const std::string& from, const std::string& to) {
    return R"(      Beam: {From: [)" + from + "], To: [" + to +
           R"(], Elements: 4, Young's Modulus: 7.0e10, Density: 2700.0, Area: 1.0e-3, Iy: 2.0e-8, Iz: 2.0e-7, Torsion Constant: 5.0e-8, Orientation: [0, 1, 0], Tip Mass: 2.0}
      Reduction: {Basis: Full}
  Analysis: {Number of Modes: 4}
)";
  };
  const auto rigidFit = [&](const std::string& ns, const std::string& from = "1.1, 0, 0",
                            const std::string& to = "2.1, 0, 0") {
    return hub(ns) + R"(    arm:
      Kind: E
      Parent: hub
      Attachment: {Type: RigidFit, Parent Nodes: tip, Nodes: start, Point: [)" + from + R"(]}
)" + arm(from, to);
  };
  const auto stubTo = [&](const std::string& from) {
    return hub("1") + R"(    stub:
      Kind: E
      Parent: hub
      Attachment: {Type: RigidFit, Parent Nodes: tip, Nodes: start}
      Beam: {From: [1.0, 0, 0], To: [)" + from + R"(], Elements: 2, Young's Modulus: 7.0e15, Density: 1.0e-3, Area: 1.0e-3, Iy: 2.0e-6, Iz: 2.0e-6, Torsion Constant: 4.0e-6, Orientation: [0, 0, 1]}
      Reduction: {Basis: Full}
)";
  };
  const auto stub = [&](const std::string& from, const std::string& to) {
    return stubTo(from) + R"(    arm:
      Kind: E
      Parent: stub
      Attachment: {Type: Node, Parent Nodes: end, Nodes: start}
)" + arm(from, to);
  };
  const std::string path = std::string(CMS_TEST_DATA_DIR) + "/scenes/rigid-fit-link.yaml";  // for the mesh's path
  const auto hzAt = [&](const std::string& scene) {
    const auto sc = scene::Scene::parse(scene, path);
    const auto r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm);
    std::vector<double> out;
    for (const auto& m : r.modes.result.modes) out.push_back(m.hz);
    return out;
  };
  // Along the radius through the centroid, and off it diagonally (the
  // arms' cross terms; there the child's moment about the centroid meets
  // the fitted rotation's own second-order part, which neither model forms,
  // theory §11.4).
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"1.1, 0, 0", "2.1, 0, 0"},
                                 std::pair<std::string, std::string>{"1.1, 0.1, 0.05", "1.6, 0.6, 0.05"}}) {
    const auto fitted = hzAt(rigidFit("1", from, to)), stubbed = hzAt(stub(from, to));
    ASSERT_EQ(fitted.size(), 4u);
    ASSERT_EQ(stubbed.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i)
      EXPECT_NEAR(fitted[i], stubbed[i], 2e-5 * stubbed[i]) << "mode " << i + 1 << ", arm from " << from;
  }
  // A rigid rotor at the Point, the same way.
  const std::string wheel = R"(      Rotor: {Mass: 20.0, Transverse Inertia: 0.05, Axial Inertia: 0.1}
      Spin: {Axis: [0, 1, 0], Rate: 0.0}
  Analysis: {Number of Modes: 4}
)";
  const auto wheelFitted = hzAt(hub("1") + R"(    wheel:
      Kind: R
      Parent: hub
      Attachment: {Type: RigidFit, Parent Nodes: tip, Point: [1.1, 0, 0]}
)" + wheel);
  const auto wheelStubbed = hzAt(stubTo("1.1, 0, 0") + R"(    wheel:
      Kind: R
      Parent: stub
      Attachment: {Type: Node, Parent Nodes: end}
)" + wheel);
  ASSERT_EQ(wheelFitted.size(), 4u);
  ASSERT_EQ(wheelStubbed.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_NEAR(wheelFitted[i], wheelStubbed[i], 2e-5 * wheelStubbed[i]) << "wheel, mode " << i + 1;
  // A set of more than 128 nodes (a tip face 11 elements across: 144) is
  // not coupled densely: the term is not formed there, and the assembly
  // says so.
  auto notesOf = [&](const std::string& ns) {
    int said = 0;
    const auto assembled = synthesis::AssembledStructure::assemble(scene::Scene::parse(rigidFit(ns), path).structure, comm);
    for (const auto& n : assembled.notes()) said += n.find("arm: spinning on a RigidFit") != std::string::npos;
    return said;
  };
  EXPECT_EQ(notesOf("1"), 0);
  EXPECT_EQ(notesOf("11"), 1);
}

// A boom held by a spring at its tip besides its attachment: the
// attachment's rigid motion X strains it (K X != 0), so X is no constraint
// mode, and before every reduced basis added the static correction
// K_h^-1 K X (theory §11.2) Craig-Bampton 8 was 59% off (found by a
// review; only noted at assembly then). Against the same structure's Full
// model, each basis kind: Rayleigh-Ritz, so from above, and converging at
// Craig-Bampton's rate.
TEST(SceneRegression, AChildHeldBySpringsOfItsOwnTakesTheirStaticCorrection) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto text = [](const std::string& basis, const std::string& elements = "12", const std::string& spring = "1e7",
                       const std::string& hub = "{Basis: Full}") {
    return R"(
Scene:
  Substructures:
    hub:
      Kind: C
      Beam: {From: [0, 0, 0], To: [1, 0, 0], Elements: 8, Young's Modulus: 7.0e10, Density: 2700.0, Area: 0.01, Iy: 1.0e-5, Iz: 2.0e-5, Torsion Constant: 2.0e-5, Orientation: [0, 0, 1], Clamp: start}
      Reduction: )" + hub + R"(
    boom:
      Kind: E
      Parent: hub
      Attachment: {Parent Nodes: end, Nodes: root}
      Finite Element Model:
        Mesh: ../meshes/beam_line.geo
        Mesh Parameters: {n: )" + elements + R"(, L: 1.5}
        Materials: {al: {Young's Modulus: 7.0e10, Poisson's Ratio: 0.3, Density: 2700.0}}
        Element Sets: {beam: {Type: Frame, Material: al, Area: 0.004, Iy: 2.0e-6, Iz: 3.0e-6, Torsion Constant: 4.0e-6, Orientation: [0, 0, 1]}}
        )" + (spring == "fixed" ? "Boundary Conditions: {prop: {Node Set: tip, Fixed: uy uz}}"
                                : "Springs: {prop: {Node Set: tip, Stiffness: [0, " + spring + ", " + spring + ", 0, 0, 0]}}") + R"(
      Placement: {Axis: [0, 0, 1], Angle: 0.0, Translation: [1, 0, 0]}
      Reduction: )" + basis + R"(
  Analysis: {Number of Modes: 8}
)";
  };
  const std::string path = std::string(CMS_TEST_DATA_DIR) + "/scenes/propped-boom.yaml";  // for the mesh's path
  const auto hz = [&](const std::string& basis, std::vector<std::string>* labels = nullptr,
                      const std::string& elements = "12", const std::string& spring = "1e7",
                      const std::string& hub = "{Basis: Full}") {
    const auto sc = scene::Scene::parse(text(basis, elements, spring, hub), path);
    const auto r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm);
    if (labels) *labels = r.reduced->reductions().at(1).labels;
    std::vector<double> out;
    for (const auto& m : r.modes.result.modes) out.push_back(m.hz);
    return out;
  };
  const auto full = hz("{Basis: Full}");
  ASSERT_EQ(full.size(), 8u);
  // The tip spring resists the rigid motions that move the tip across the
  // boom: uy, uz, and the turns ry, rz about the root, whose loads are the
  // same tip forces (dependent: dropped); not ux or rx.
  const std::vector<std::string> resisted{"uy", "uz"};
  auto corrections = [&](const std::vector<std::string>& labels) {
    std::vector<std::string> got;
    for (const auto& l : labels)
      if (l.rfind(reduction::kOwnSupportsColumn, 0) == 0) got.push_back(l.substr(std::string(reduction::kOwnSupportsColumn).size()));
    return got;
  };
  // An upper bound up to the dense solves' rounding: eps times the spread
  // of the eigenvalues (below 1e7 for these 20 beam elements) is < 1e-8.
  auto error = [&](const std::vector<double>& f, std::size_t i) {
    EXPECT_GE(f[i], full[i] * (1.0 - 1e-8)) << "mode " << i + 1 << " below the Full model's";
    return (f[i] - full[i]) / full[i];
  };
  std::vector<std::string> labels;
  const auto cb8 = hz("{Basis: Craig-Bampton, Vectors: 8}", &labels);
  EXPECT_EQ(corrections(labels), resisted);
  // No longer a limitation to note at assembly.
  const auto assembled =
      synthesis::AssembledStructure::assemble(scene::Scene::parse(text("{Basis: Craig-Bampton, Vectors: 8}"), path).structure, comm);
  for (const auto& n : assembled.notes()) EXPECT_EQ(n.find("held by supports or springs"), std::string::npos) << n;
  const auto cb16 = hz("{Basis: Craig-Bampton, Vectors: 16}");
  // Craig-Bampton 8 against 16 fixed-interface modes: errors 1.8e-6 ..
  // 2.9e-4 and 4.6e-7 .. 3.0e-5 measured over the first six (before the
  // correction 59% on the first); 1e-3 bounds the first, and doubling the
  // modes must gain at least 5x on the modes the boom's bending governs
  // (error above 1e-5: gains of 7x to 23x measured; the hub's fifth, 1.8e-6,
  // gains 4x).
  for (std::size_t i = 0; i < 6; ++i) {
    const double e8 = error(cb8, i), e16 = error(cb16, i);
    EXPECT_LT(e8, 1e-3) << "mode " << i + 1;
    if (e8 > 1e-5) EXPECT_LT(e16, e8 / 5.0) << "mode " << i + 1 << ": " << e8 << " then " << e16;
  }
  // The other kinds: Modes as Craig-Bampton here (the boom has no
  // children), Admissible counts the corrections among its Vectors, Guyan
  // is the corrections alone, a Partitioned boom has them among its parts'
  // static shapes. Bounds: 1e-3 for those measured within 3e-4, 1e-1 for
  // Guyan (6.6% on the first: static shapes only).
  const auto modes8 = hz("{Basis: Modes, Vectors: 8}", &labels);
  EXPECT_EQ(corrections(labels), resisted);
  const auto adm16 = hz("{Basis: Admissible, Vectors: 16}", &labels);
  EXPECT_EQ(corrections(labels), resisted);
  EXPECT_EQ(labels.size(), 16u + resisted.size());  // beyond "Vectors", as the other bases add them
  const auto guyan = hz("{Basis: Guyan}", &labels);
  EXPECT_EQ(corrections(labels), resisted);
  const auto parts = hz("{Basis: Partitioned, Partition: {Parts: 2}, Cutoff Frequency: 600}", &labels);
  EXPECT_EQ(corrections(labels), resisted);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_LT(error(modes8, i), 1e-3) << "mode " << i + 1;
    EXPECT_LT(error(adm16, i), 1e-3) << "mode " << i + 1;
    EXPECT_LT(error(parts, i), 1e-3) << "mode " << i + 1;
  }
  EXPECT_LT(error(guyan, 0), 1e-1);
  // A fine mesh and a soft spring: 1000 elements and 2e5 N/m across, about
  // the boom's own tip stiffness 3 E Iy / L^3 = 1.9e5 N/m. The rule that
  // told the supports' K X from rounding was a bound over the whole column,
  // 1e3 eps ||K||_F ||X||, which grows with the mesh (here ~4e5 N/m): the
  // spring read as rounding, its hold on the attachment was zeroed in the
  // projection and no correction was added, and Craig-Bampton 8 gave 21.3
  // Hz, below the Full model's 33.6, converging to that wrong value (a
  // review). Now entry by entry: from above, within 1e-3 as above.
  const auto fineFull = hz("{Basis: Full}", nullptr, "1000", "2e5");
  const auto fineCb = hz("{Basis: Craig-Bampton, Vectors: 8}", &labels, "1000", "2e5");
  EXPECT_EQ(corrections(labels), resisted);
  ASSERT_EQ(fineFull.size(), 8u);
  ASSERT_EQ(fineCb.size(), 8u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_GE(fineCb[i], fineFull[i] * (1.0 - 1e-8)) << "mode " << i + 1;
    EXPECT_LT((fineCb[i] - fineFull[i]) / fineFull[i], 1e-3) << "mode " << i + 1;
  }
  // Supports instead of the spring (the tip held across), and the hub
  // reduced too, so that on two ranks each substructure is reduced whole on
  // a rank of its own (the boom's correction made on its gathered copy).
  const auto heldFull = hz("{Basis: Full}", nullptr, "12", "fixed");
  const auto heldCb = hz("{Basis: Craig-Bampton, Vectors: 8}", &labels, "12", "fixed", "{Basis: Craig-Bampton, Vectors: 8}");
  EXPECT_EQ(corrections(labels), resisted);
  ASSERT_EQ(heldFull.size(), 8u);
  ASSERT_EQ(heldCb.size(), 8u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_GE(heldCb[i], heldFull[i] * (1.0 - 1e-8)) << "mode " << i + 1;
    EXPECT_LT((heldCb[i] - heldFull[i]) / heldFull[i], 1e-3) << "mode " << i + 1;
  }
}

// A stiff massless stub (E = 7e14 beside aluminium beams) makes the dense
// path's skew factor large (||A||_F ~ 2e11), and its cluster tolerance,
// 1e-10 ||A||_F = 21 rad/s, joined distinct frequencies (34.57 and 43.05
// rad/s; 295.2 and 309.0) into clusters whose modes came in the singular
// vectors' order: listed out of order, and asked for one mode the solve
// returned 43.05 rad/s, not the lowest (found by a review). Now ascending,
// and one mode is the lowest of six, on both reductions of the skew factor.
TEST(SceneRegression, AStiffStubsModesComeInOrderAndTheLowestFirst) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto sc = parse(R"(
Scene:
  Substructures:
)" + std::string(kSpinningHubAndBlade[0]) + R"(
    stub:
      Kind: E
      Parent: hub
      Attachment: {Type: Node, Parent Nodes: end, Nodes: start}
      Beam: {From: [1.0, 0, 0], To: [1.1, 0, 0], Elements: 2, Young's Modulus: 7.0e14, Density: 1.0e-3, Area: 1.0e-2, Iy: 2.0e-4, Iz: 2.0e-4, Torsion Constant: 4.0e-4, Orientation: [0, 1, 0]}
      Reduction: {Basis: Full}
    blade:
      Kind: E
      Parent: stub
      Attachment: {Type: Node, Parent Nodes: end, Nodes: start}
)" + kSpinningHubAndBlade[1] + R"(
      Reduction: {Basis: Full}
)");
  const auto st = synthesis::AssembledStructure::assemble(sc.structure, comm);
  const auto s = synthesis::SynthesizedStructure::synthesize(st, true);
  const std::vector<double> speeds(st.speeds().size(), 30.0);
  for (const std::string reduction : {"Skew Tridiagonal", "Bidiagonal"}) {
    auto solve = [&](int modes) {
      Teuchos::ParameterList p;
      p.set("Number of Modes", modes);
      p.set("Solver", std::string("Dense"));
      p.sublist("Dense Solver").set("Reduction", reduction);
      std::vector<double> hz;
      for (const auto& m : s.solve(speeds, p).result.modes) hz.push_back(m.hz);
      return hz;
    };
    const auto six = solve(6), one = solve(1);
    ASSERT_EQ(six.size(), 6u) << reduction;
    ASSERT_EQ(one.size(), 1u) << reduction;
    for (std::size_t i = 1; i < six.size(); ++i) EXPECT_LT(six[i - 1], six[i]) << reduction << " mode " << i + 1;
    // The same mode from two solves: a frequency ||A y'|| from a vector
    // whose error couples it to the stub's values of order ||A|| moves by
    // about (eps ||A||_F / omega)^2 ~ 1e-12 of it; 1e-9 leaves room for
    // other BLAS kernels, far below the 24% between the two lowest.
    EXPECT_NEAR(one[0], six[0], 1e-9 * six[0]) << reduction;
  }
}

namespace {
/// The overhung Jeffcott-like shaft of stationary-rotor-damped.yaml (8
/// elements, 10 kg tip disc), clamped at x = 0, Rayleigh beta of its own
/// material, spinning at `rate` about x. `stationary`: an A rotor in the
/// stationary frame on a support held at both ends (so the shaft is clamped
/// exactly as the C below; the support's middle node moves on its own);
/// otherwise the C shaft in its own
/// spinning frame. `beta` 0: undamped. `reduction`: the shaft's basis.
/// `supportRate`: the support spins too, coaxially (a compound rotor: the
/// shaft's coordinates in the support's frame, its own spin relative to it).
/// `extraBeam`: more keys of the shaft's Beam.
std::string overhungShaft(bool stationary, double rate, double beta, const std::string& reduction = "{Basis: Full}",
                          const std::string& solver = "Auto", int count = 6, double supportRate = 0.0,
                          const std::string& extraBeam = "") {
  const std::string beam = "Beam: {From: [0, 0, 0], To: [1, 0, 0], Elements: 8, Young's Modulus: 2.0e11, "
                           "Density: 7800.0, Area: 1.2566e-3, Iy: 1.2566e-7, Iz: 1.2566e-7, Torsion Constant: "
                           "2.5133e-7, Tip Mass: 10.0, Tip Inertia: [0.02, 0.01, 0.01]" +
                           std::string(stationary ? "" : ", Clamp: start") +
                           (beta > 0.0 ? ", Structural Damping: {Rayleigh Beta: " + std::to_string(beta) + "}" : "") +
                           (extraBeam.empty() ? "" : ", " + extraBeam) + "}";
  const std::string spin = "Spin: {Axis: [1, 0, 0], Rate: " + std::to_string(rate) +
                           (stationary ? ", Frame: Stationary}" : "}");
  std::string s = "Scene:\n  Substructures:\n";
  if (stationary)
    s += "    support:\n      Kind: C\n      Beam: {From: [-0.1, 0, 0], To: [0, 0, 0], Elements: 2, Young's Modulus: "
         "2.0e11, Density: 7800.0, Area: 2.0e-3, Iy: 8.0e-7, Iz: 8.0e-7, Torsion Constant: 1.6e-6, Clamp: ends}\n"
         "      Reduction: {Basis: Full}\n" +
         (supportRate != 0.0 ? "      Spin: {Axis: [1, 0, 0], Rate: " + std::to_string(supportRate) + "}\n" : "");
  s += "    shaft:\n      Kind: " + std::string(stationary ? "A\n      Parent: support\n      Attachment: {Parent "
                                                               "Nodes: end, Nodes: start}\n"
                                                             : "C\n") +
       "      " + spin + "\n      " + beam + "\n      Reduction: " + reduction + "\n";
  s += "  Analysis: {Number of Modes: " + std::to_string(count) + ", Solver: " + solver + "}\n";
  return s;
}

/// The modes of a scene's modal analysis.
std::vector<eigen::GyroscopicMode> rotorModes(const std::string& scene,
                                              const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  const auto sc = parse(scene);
  return analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm).modes.result.modes;
}

/// A shaft of `elements` Full beam elements spinning at `rate` in the
/// stationary frame on a 2-element clamped support (Full) of Young's modulus
/// `supportE` with bearing dampers (200 N s/m) at its end, or with
/// `supportDamping` appended to its Beam map instead; `material` is
/// appended to the shaft's Beam map (e.g. its Structural Damping).
std::string dampedSupportRotor(double supportE, int elements, double rate, const std::string& material,
                               const std::string& solver,
                               const std::string& supportDamping =
                                   ", Dampers: {bearing: {Node Set: end, Damping: [0, 200.0, 200.0, 0, 0, 0]}}") {
  std::ostringstream s;
  s << "Scene:\n  Substructures:\n    support:\n      Kind: C\n"
    << "      Beam: {From: [-0.1, 0, 0], To: [0, 0, 0], Elements: 2, Young's Modulus: " << supportE
    << ", Density: 7800.0, Area: 2.0e-3, Iy: 8.0e-7, Iz: 8.0e-7, Torsion Constant: 1.6e-6, Clamp: start"
    << supportDamping << "}\n"
    << "      Reduction: {Basis: Full}\n"
    << "    shaft:\n      Kind: A\n      Parent: support\n      Attachment: {Parent Nodes: end, Nodes: start}\n"
    << "      Spin: {Axis: [1, 0, 0], Rate: " << rate << ", Frame: Stationary}\n"
    << "      Beam: {From: [0, 0, 0], To: [1, 0, 0], Elements: " << elements
    << ", Young's Modulus: 2.0e11, Density: 7800.0, Area: 1.2566e-3, Iy: 1.2566e-7, Iz: 1.2566e-7, Torsion "
       "Constant: 2.5133e-7, Tip Mass: 10.0, Tip Inertia: [0.02, 0.01, 0.01]"
    << material << "}\n"
    << "      Reduction: {Basis: Full}\n"
    << "  Analysis: {Number of Modes: 10, Solver: " << solver << "}\n";
  return s.str();
}

/// The eigenvalues of the undamped modes `undamped` with D = alpha M added
/// (theory §13.4): lambda = -alpha/2 + i sqrt(omega^2 - alpha^2/4), each.
std::vector<std::complex<double>> massDamped(const std::vector<eigen::GyroscopicMode>& undamped, double alpha) {
  std::vector<std::complex<double>> exact;
  for (const auto& m : undamped) exact.emplace_back(-alpha / 2.0, std::sqrt(m.omega * m.omega - alpha * alpha / 4.0));
  return exact;
}

/// How many of `ms` flutter.
long flutters(const std::vector<eigen::GyroscopicMode>& ms) {
  return std::count_if(ms.begin(), ms.end(),
                       [](const eigen::GyroscopicMode& m) { return m.stability == eigen::Stability::Flutter; });
}
}  // namespace

// A rotor modelled in the stationary frame with Rayleigh damping of its own
// material: the damping turns with the rotor, and in these coordinates adds
// the circulatory N = Omega N1 (theory §13.1). Before it was formed the
// damping was applied as a stationary one: at 140 rad/s the forward whirl
// read damped at -0.31 1/s where the same shaft in its own spinning frame
// grows at 0.241 1/s (a review).
// - The two frames describe one motion (lambda_stationary = lambda_rotating
//   +- i Omega for an axisymmetric rotor's whirl, the same lambda along and
//   about its axis): each of the six lowest modes has
//   its twin, to 1e-9 of |lambda| (the two dense solves' rounding, eps times
//   the pencils' conditioning, measured 4e-12) and the same growth rate to
//   1e-7 of |lambda| (measured 7e-13).
// - The instability begins exactly at the forward critical speed, where the
//   undamped forward whirl's frequency equals the spin (theory §13.4; no
//   stationary damping): found by a secant on the undamped model, flutter
//   absent 1e-4 to 1e-3 below it and present as far above (growth
//   -/+3.05e-5 1/s at 1e-4, 3.9e-7 of |lambda|, above the Instability
//   Tolerance's 1e-7).
// - A compound rotor (the shaft stationary in its spinning support's frame)
//   likewise, its N at its own rate relative to the support.
// - The projected N (a Craig-Bampton shaft) and the sparse path's K + N.
TEST(SceneRegression, AStationaryFrameRotorsMaterialDampingTurnsWithIt) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto modes = [&](const std::string& scene) { return rotorModes(scene, comm); };
  const double rate = 140.0, beta = 1e-4;
  const auto fixed = modes(overhungShaft(true, rate, beta));
  // (More modes in the spinning frame: the stationary sixth, 2377 rad/s
  // backward, is its eighth, at 2517.)
  const auto spinning = modes(overhungShaft(false, rate, beta, "{Basis: Full}", "Auto", 10));
  ASSERT_EQ(fixed.size(), 6u);
  // Each of `ms`, seen from a frame turning `shift` slower, among
  // `spinning`: the worst relative distance and growth-rate difference.
  const auto twins = [&](const std::vector<eigen::GyroscopicMode>& ms, double shift) {
    double worst = 0.0, worstGrowth = 0.0;
    for (const auto& m : ms) {
      double best = 1e300, growth = 0.0;
      for (const auto& r : spinning)
        for (double s : {-shift, 0.0, shift}) {  // 0: along the axis and about it, no whirl
          const std::complex<double> twin = m.lambda + std::complex<double>(0.0, s);
          for (const auto& t : {twin, std::conj(twin)}) {
            const double d = std::abs(r.lambda - t);
            if (d < best) best = d, growth = std::abs(r.growthRate - m.growthRate);
          }
        }
      worst = std::max(worst, best / std::abs(m.lambda));
      worstGrowth = std::max(worstGrowth, growth / std::abs(m.lambda));
    }
    return std::make_pair(worst, worstGrowth);
  };
  const auto [worst, worstGrowth] = twins(fixed, rate);
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worstGrowth, 1e-7);
  EXPECT_EQ(flutters(fixed), 1);
  EXPECT_EQ(flutters(spinning), 1);
  // Compound: the support spinning at 40 rad/s and the shaft at 100 relative
  // to it; its material turns at 100 in the support's frame (N = 100 N1),
  // 140 absolute: the same motion seen from a frame 100 slower than its own.
  const auto compound = modes(overhungShaft(true, rate - 40.0, beta, "{Basis: Full}", "Auto", 6, 40.0));
  const auto [worstC, worstGrowthC] = twins(compound, rate - 40.0);
  EXPECT_LT(worstC, 1e-9);
  EXPECT_LT(worstGrowthC, 1e-7);
  EXPECT_EQ(flutters(compound), 1);
  double growth = 0.0;
  for (const auto& m : fixed)
    if (m.stability == eigen::Stability::Flutter) growth = m.growthRate;
  EXPECT_NEAR(growth, 0.241, 1e-3);  // the massless Jeffcott's closed form, theory §13.4: 0.242

  // The forward critical speed of the undamped rotor: omega_FW(Omega) = Omega.
  const auto forwardMinusSpin = [&](double Omega) {
    const auto ms = modes(overhungShaft(true, Omega, 0.0));
    return std::max(ms[0].omega, ms[1].omega) - Omega;  // the first pair: forward above backward
  };
  double a = 70.0, b = 90.0, fa = forwardMinusSpin(a), fb = forwardMinusSpin(b);
  for (int it = 0; it < 8 && std::abs(b - a) > 1e-10 * b; ++it) {
    const double c = b - fb * (b - a) / (fb - fa);
    a = b, fa = fb, b = c, fb = forwardMinusSpin(b);
  }
  const double critical = b;
  EXPECT_NEAR(critical, 78.29, 0.01);  // the Campbell's 1X forward crossing, 78.2927 rad/s
  // Both sides at four offsets, dense and sparse. Within 1.6e-4 of the
  // threshold the growth, 4.8e-5 1/s (6e-7 of |lambda|, six times the
  // Instability Tolerance), read "stable" at some speeds and FLUTTER at
  // others: the growth's uncertainty took 10 sqrt(eta) |lambda| of a split
  // near-defective pair, 5.7e-5 from a backward error eta of 5e-15, for an
  // eigenvalue 0.29 rad/s from any other (the Campbell's unstable range
  // began at 78.31 or 78.32 by rank count).
  for (double offset : {1e-3, 3e-4, 1.6e-4, 1.56e-4, 1e-4})
    for (const char* solver : {"Dense", "Sparse"}) {
      EXPECT_EQ(flutters(modes(overhungShaft(true, critical * (1.0 - offset), beta, "{Basis: Full}", solver))), 0)
          << offset << " below, " << solver;
      EXPECT_EQ(flutters(modes(overhungShaft(true, critical * (1.0 + offset), beta, "{Basis: Full}", solver))), 1)
          << offset << " above, " << solver;
    }

  // Reduced: the shaft by Craig-Bampton (N projected like G), four vectors:
  // the growth to 1e-4 (measured 3e-6), and each of the first two modes'
  // error estimate within a factor 3 of its true error against the Full
  // model (2.6e-6 and 3.0e-6 measured; the estimate's residual without N
  // said 1e-4, theory §11.8). Sparse: the same system to 1e-8 of |lambda|
  // (its Residual Tolerance; measured 3e-12).
  {
    const auto sc = parse(overhungShaft(true, rate, beta, "{Basis: Craig-Bampton, Vectors: 4}"));
    const auto run = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm);
    const auto& reduced = run.modes.result.modes;
    ASSERT_EQ(flutters(reduced), 1);
    for (const auto& m : reduced)
      if (m.stability == eigen::Stability::Flutter) EXPECT_NEAR(m.growthRate, growth, 1e-4 * growth);
    for (int j = 0; j < 2; ++j) {
      const double error = std::abs(reduced[j].lambda - fixed[j].lambda) / std::abs(fixed[j].lambda);
      ASSERT_GT(run.estimates.size(), static_cast<std::size_t>(j));
      EXPECT_GT(run.estimates[j], error / 3.0) << "mode " << j;
      EXPECT_LT(run.estimates[j], 3.0 * error) << "mode " << j;
    }
  }
  const auto sparse = modes(overhungShaft(true, rate, beta, "{Basis: Full}", "Sparse"));
  ASSERT_EQ(sparse.size(), fixed.size());
  for (std::size_t j = 0; j < fixed.size(); ++j)
    EXPECT_LT(std::abs(sparse[j].lambda - fixed[j].lambda), 1e-8 * std::abs(fixed[j].lambda)) << "mode " << j;
  EXPECT_EQ(flutters(sparse), 1);
}

// What does not turn with a stationary-frame rotor (theory §13.1; each found
// by a review of the first version):
// - A bearing: a spring in the rotor's model. Rayleigh beta on the whole K
//   made beta k_b stationary damping of the bearing, external damping that
//   moved the onset of instability from the forward critical speed to
//   Omega (1 + c_e / c_i), about twice it (220 against 110.5 rad/s). Now
//   beta is the material's, on its frames and hinges: the onset is the
//   critical speed again, to the 1e-3 bracket of the test above.
// - Rayleigh alpha: alpha M damps absolute velocity, not the strain rate.
//   Turning with the rotor it pushed on rigid motion: a stiff shaft on a
//   soft support at 60 rad/s, above its rigid forward whirl (28.7 rad/s),
//   fluttered at 0.106 1/s, where beta alone, the material's, gives 1e-7.
//   Now stationary: every mode decays.
// - A modal damping ratio on such a rotor: refused (it would need its own
//   circulatory term; a Craig-Bampton shaft read stable at zeta 0.01 where
//   it grows in its own spinning frame).
TEST(SceneRegression, AStationaryFrameRotorsBearingsAndAlphaDoNotTurnWithIt) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto modes = [&](const std::string& scene) { return rotorModes(scene, comm); };
  const std::string bearing = "Springs: {brg: {Node Set: end, Stiffness: [0, 7.5e4, 7.5e4, 0, 0, 0]}}";
  const auto forwardMinusSpin = [&](double Omega) {
    const auto ms = modes(overhungShaft(true, Omega, 0.0, "{Basis: Full}", "Auto", 6, 0.0, bearing));
    return std::max(ms[0].omega, ms[1].omega) - Omega;
  };
  double a = 100.0, b = 120.0, fa = forwardMinusSpin(a), fb = forwardMinusSpin(b);
  for (int it = 0; it < 8 && std::abs(b - a) > 1e-10 * b; ++it) {
    const double c = b - fb * (b - a) / (fb - fa);
    a = b, fa = fb, b = c, fb = forwardMinusSpin(b);
  }
  const double critical = b;
  EXPECT_NEAR(critical, 110.5, 0.1);
  for (double side : {-1.0, 1.0})
    EXPECT_EQ(flutters(modes(overhungShaft(true, critical * (1.0 + side * 1e-3), 1e-4, "{Basis: Full}", "Auto", 6,
                                           0.0, bearing))),
              side > 0.0 ? 1 : 0)
        << (side > 0.0 ? "above" : "below") << " the critical speed " << critical;

  const std::string soft = R"(
Scene:
  Substructures:
    support:
      Kind: C
      Beam: {From: [-0.5, 0, 0], To: [0, 0, 0], Elements: 4, Young's Modulus: 2.0e9, Density: 7800.0, Area: 2.0e-3, Iy: 8.0e-7, Iz: 8.0e-7, Torsion Constant: 1.6e-6, Clamp: start}
      Reduction: {Basis: Full}
    shaft:
      Kind: A
      Parent: support
      Attachment: {Parent Nodes: end, Nodes: start}
      Spin: {Axis: [1, 0, 0], Rate: 60, Frame: Stationary}
      Beam: {From: [0, 0, 0], To: [0.3, 0, 0], Elements: 4, Young's Modulus: 2.0e13, Density: 7800.0, Area: 1.2566e-3, Iy: 1.2566e-7, Iz: 1.2566e-7, Torsion Constant: 2.5133e-7, Tip Mass: 10.0, Tip Inertia: [0.02, 0.01, 0.01], Structural Damping: {Rayleigh Alpha: 0.2}}
      Reduction: {Basis: Full}
  Analysis: {Number of Modes: 4}
)";
  const auto alpha = modes(soft);
  EXPECT_EQ(flutters(alpha), 0);
  for (const auto& m : alpha) EXPECT_LT(m.growthRate, 0.0) << m.omega << " rad/s";

  fixtures::expectInputError(
      [&] {
        synthesis::AssembledStructure::assemble(
            parse(overhungShaft(true, 140.0, 0.0, "{Basis: Craig-Bampton, Vectors: 6}", "Auto", 6, 0.0,
                                "Structural Damping: {Modal Damping Ratio: 0.01}"))
                .structure,
            comm);
      },
      "Modal Damping Ratio on a rotor in the stationary frame");
  // A hinge about another axis than the spin's is not axisymmetric: refused
  // as Iy != Iz is (a review found one about y accepted); about the spin
  // axis it is.
  const auto hinged = [&](const std::string& axis) {
    return parse(overhungShaft(true, 140.0, 1e-4, "{Basis: Full}", "Auto", 6, 0.0,
                               "Hinges: {c: {Station: 0.5, Axis: " + axis + ", Stiffness: 1.0e5, Damping: 5.0}}"))
        .structure;
  };
  fixtures::expectInputError([&] { synthesis::AssembledStructure::assemble(hinged("[0, 1, 0]"), comm); },
                             "hinge 'c' turns about (0, 1, 0), not the spin axis");
  EXPECT_NO_THROW(synthesis::AssembledStructure::assemble(hinged("[1, 0, 0]"), comm));
}


// A real flutter on a stiff or finely meshed rotor is not read "stable" (a
// review, 2026-12-01; theory §13.3). The growth rate's uncertainty came from
// ten times the residual's first-order error with q^H for the left vector:
// a support of E = 2e16 (its stiffness 1e18 beside the shaft's 1e6) or 250
// shaft elements make ||r|| the stiff rows' rounding, and the 0.241 1/s
// internal-damping flutter above the critical speed read "stable" on the
// sparse path, depending on how many modes were asked for (FLUTTER at 2,
// stable at 3 to 10), and at 250 and 300 elements. Each case must read
// FLUTTER at the growth of the closed form (0.242 at 8 elements, theory
// §13.4; 0.229 at the finer mesh, where dense and sparse agree to 1e-3 at
// 40 to 150 elements), to 1e-3 of it (the meshes' own difference is 5%).
// The growth is now refined with its left vector (theory §13.3). The dense
// path at 300 elements (n = 1808, 6.5 minutes) was checked by hand: FLUTTER
// at 0.229.
TEST(SceneRegression, AStiffOrFineRotorsFlutterIsNotReadStable) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto scene = [](double supportE, int elements, int count, const std::string& solver) {
    std::ostringstream s;
    s << "Scene:\n  Substructures:\n    support:\n      Kind: C\n"
      << "      Beam: {From: [-0.1, 0, 0], To: [0, 0, 0], Elements: 2, Young's Modulus: " << supportE
      << ", Density: 7800.0, Area: 2.0e-3, Iy: 8.0e-7, Iz: 8.0e-7, Torsion Constant: 1.6e-6, Clamp: start}\n"
      << "      Reduction: {Basis: Craig-Bampton, Vectors: 2}\n"
      << "    shaft:\n      Kind: A\n      Parent: support\n      Attachment: {Parent Nodes: end, Nodes: start}\n"
      << "      Spin: {Axis: [1, 0, 0], Rate: 140.0, Frame: Stationary}\n"
      << "      Beam: {From: [0, 0, 0], To: [1, 0, 0], Elements: " << elements
      << ", Young's Modulus: 2.0e11, Density: 7800.0, Area: 1.2566e-3, Iy: 1.2566e-7, Iz: 1.2566e-7, Torsion "
         "Constant: 2.5133e-7, Tip Mass: 10.0, Tip Inertia: [0.02, 0.01, 0.01], Structural Damping: {Rayleigh Beta: "
         "1.0e-4}}\n"
      << "      Reduction: {Basis: Full}\n"
      << "  Analysis: {Number of Modes: " << count << ", Solver: " << solver << "}\n";
    return s.str();
  };
  // How many cases the refinement decided (GyroscopicMode::refinedError):
  // which ones need it depends on the Ritz values' rounding (the BLAS
  // threads of the environment: under ctest the MUMPS and 250-element cases
  // were decided by their first-order bound, by hand refined), so the
  // count, not each case, must show it at work.
  int refinedCases = 0;
  const auto check = [&](const std::string& text, double growth, const std::string& what) {
    const auto ms = rotorModes(text, comm);
    EXPECT_EQ(flutters(ms), 1) << what;
    for (const auto& m : ms)
      if (m.growthRate > 0.0) {
        EXPECT_EQ(m.stability, eigen::Stability::Flutter) << what << ": " << m.growthRate << " 1/s";
        EXPECT_NEAR(m.growthRate, growth, 1e-3 * growth) << what;
        refinedCases += m.refinedError > 0.0;
      }
  };
  for (int count : {2, 3, 4, 6, 10})
    for (const char* solver : {"Sparse", "Dense"})
      check(scene(2.0e16, 8, count, solver), 0.2407,
            std::string("E = 2e16, ") + solver + ", " + std::to_string(count) + " modes");
  // The transform's factorisations by MUMPS (distributed at 2 ranks) as by
  // KLU2 (the refinement's is MUMPS's either way).
  check(scene(2.0e16, 8, 4, "Sparse, Direct Solver: MUMPS"), 0.2407, "E = 2e16, MUMPS");
  for (int elements : {250, 300}) check(scene(2.0e11, elements, 4, "Sparse"), 0.2294, std::to_string(elements) + " elements");
  // A mode whose first-order error exceeds |lambda| itself was not refined
  // (a split zero's is of its own size; but zeros are told apart by the
  // rigid tolerance already): on a support of E = 1e18 with bearing
  // dampers, 100 shaft elements at beta 1e-5 and 120.75 rad/s, the forward
  // whirl's growth 0.0147 1/s within 1172 read "stable" on the sparse path,
  // against FLUTTER at 0.016559 on the dense path (a review, 2026-12-01).
  // Refined, the sparse path gives 0.0165587 within 8.4e-5 (the dense
  // 0.0165587, checked by hand: 5 s at n = 612).
  check(dampedSupportRotor(1e18, 100, 120.75, ", Structural Damping: {Rayleigh Beta: 1.0e-5}", "Sparse"),
        0.0165587, "E = 1e18 with bearing dampers, 100 elements, an error above |lambda|");
  EXPECT_GE(refinedCases, 3) << "the refinement decided too few cases (of 14: 7 by hand, 6 under ctest, 1 rank, before the 14th)";
  // Undecided is only what the refinement takes (undecidedGrowth): a stable
  // damped free body spinning about its major axis has a frame-rate triple,
  // a split cluster it does not refine, whose rounding growth on the sparse
  // path, 9e-6 1/s, read UNDECIDED in the first version (a review). Stable,
  // nothing neutral, nothing growing.
  const std::string freeBody = R"(
Scene:
  Free Reference: mid
  Substructures:
    body:
      Kind: C
      Spin: {Axis: [0, 0, 1], Origin: [0, 0, 0], Rate: 1.0}
      Beam: {From: [-0.5, 0, 0], To: [0.5, 0, 0], Elements: 16, Young's Modulus: 7.0e10, Density: 2700.0, Area: 0.02, Iy: 1.0e-4, Iz: 1.0e-4, Torsion Constant: 2.0e-4, Orientation: [0, 0, 1], Structural Damping: {Rayleigh Beta: 1.0e-4}, Point Masses: {core: {Node Set: mid, Mass: 100.0, Inertia: [10.0, 20.0, 40.0, 0, 0, 0]}}}
      Reduction: {Basis: Full}
  Analysis: {Number of Modes: 8, Solver: Sparse}
)";
  for (const auto& m : rotorModes(freeBody, comm))
    EXPECT_TRUE(m.stability == eigen::Stability::Stable || m.stability == eigen::Stability::RigidBody)
        << "free body: " << eigen::toString(m.stability) << " at " << m.lambda;
}

// A passive rotor (stationary-frame shaft, bearing dampers on its support,
// no material damping: N = 0) on a support of E = 2e16: its growth rates'
// uncertainties, inflated by K's condition, exceed the growth rates
// themselves (-5.7e-5 1/s within 0.056 at 78 rad/s), so "stable" was the
// sign of a number rounding could have flipped (theory §13.3). The energy
// bound decides it: M > 0, K > 0 and D + d M > 0 are proven from Cholesky
// factors of their shifts (theory §13.3) at d = 1e-7 |lambda_1| (the Instability Tolerance's share), so no
// mode grows faster than d, and every mode is Stable, none undecided. The
// same rotor with material damping turning with it (Rayleigh beta: a
// circulatory N, which can feed energy in) has no bound, and says why.
// Solved with a Frequency Tolerance of 1 (no mode refined for its
// frequency): refined to the default 1e-5, every growth is decided by its
// own bound, and the energy bound would have nothing left to decide.
TEST(SceneRegression, APassiveRotorsGrowthWithinItsUncertaintyIsDecidedByTheEnergyBound) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto scene = [](const std::string& material) {
    return dampedSupportRotor(2.0e16, 8, 140.0, material, "Dense");
  };
  const auto solve = [&](const std::string& text) {
    auto sc = parse(text);
    sc.solve.sublist("Dense Solver").set("Frequency Tolerance", 1.0);
    return analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm).modes.result;
  };
  const auto passive = solve(scene(""));
  ASSERT_TRUE(passive.energyBound.shown) << passive.energyBound.note;
  int within = 0;
  double least = std::numeric_limits<double>::infinity();
  for (const auto& m : passive.modes) {
    within += std::abs(m.growthRate) < m.growthTolerance && std::abs(m.growthRate) > passive.energyBound.growth;
    least = std::min(least, std::abs(m.lambda));
    EXPECT_EQ(m.stability, eigen::Stability::Stable) << m.lambda;
    EXPECT_FALSE(m.undecided) << m.lambda;
  }
  EXPECT_GE(within, 1) << "no growth rate within its uncertainty: the bound decided nothing here";
  EXPECT_DOUBLE_EQ(passive.energyBound.growth, 1e-7 * least);
  EXPECT_EQ(passive.status, eigen::SolveStatus::Converged);
  const auto material = solve(scene(", Structural Damping: {Rayleigh Beta: 1.0e-5}"));
  EXPECT_FALSE(material.energyBound.shown);
  EXPECT_NE(material.energyBound.note.find("N != 0"), std::string::npos) << material.energyBound.note;
}

// A breakdown of Anasazi's Block Krylov-Schur is retried by ARPACK on the
// same factored transform. The damped stiff-support shaft at rest (E =
// 1e18, bearing dampers, 100 elements, beta 1e-5; its bending frequencies
// double: isotropic) broke down in the Schur form's reordering ("TREXC
// returned info 1") at 1 rank on this machine, and `cms modes` exited 3
// with no output (a review, 2026-12-01). Now it solves, and returns the
// dense path's modes (checked by hand, 5 s at n = 612). Its frequencies
// erred by up to 4e-4 with normwise residuals of 1e-14 (the lowest double
// pair, 78.1773 against 78.14697, 2 ranks; 6.7e-4 with
// OPENBLAS_CORETYPE=Nehalem), until the modes whose error the residual did
// not show were refined (theory §5, "Stiff rows"). Whether Anasazi breaks
// down depends on its rounding; where it does, the reason says ARPACK took
// over.
TEST(SceneRegression, AKrylovSchurBreakdownIsSolvedAgainByArpack) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::string material = ", Structural Damping: {Rayleigh Beta: 1.0e-5}";
  const auto sc = parse(dampedSupportRotor(1e18, 100, 0.0, material, "Sparse"));
  analysis::ModalResult r;
  ASSERT_NO_THROW(r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm));
  const auto& res = r.modes.result;
  EXPECT_EQ(res.status, eigen::SolveStatus::Converged) << res.reason;
  ASSERT_EQ(res.modes.size(), 10u);
  const double dense[] = {78.14697, 78.14698, 804.64778, 804.64779, 967.39855,
                          2412.92477, 2412.9252, 4323.60565, 4592.17641, 4592.17649};
  // Each within its reported eigenvalue error of the dense path's frequency
  // plus 1e-6 of it, the dense path's own error here (5e-7 against
  // two-sided inverse iteration: theory §5, "Stiff rows"), and the isotropic
  // shaft's pairs double within their members' errors.
  const auto error = [](const eigen::GyroscopicMode& m) { return m.reportedError(); };
  for (int j = 0; j < 10; ++j)
    EXPECT_LE(std::abs(res.modes[j].omega - dense[j]), error(res.modes[j]) + 1e-6 * dense[j]) << "mode " << j;
  for (int j : {0, 2, 5, 8})
    EXPECT_LE(std::abs(res.modes[j].lambda - res.modes[j + 1].lambda),
              error(res.modes[j]) + error(res.modes[j + 1]))
        << "pair " << j;
  if (res.reason.find("broke down") != std::string::npos)
    EXPECT_NE(res.reason.find("solved again by ARPACK"), std::string::npos) << res.reason;
}

// A support of E = 1e18 (K ~ 1e17) under a steel shaft (rows ~ 1e10), both
// with mass-proportional damping D = alpha M (theory §5, "Stiff rows"): each
// mode is an undamped one, lambda = -alpha/2 + i sqrt(omega^2 - alpha^2/4),
// omega from the undamped model's symmetric path (the closed form of §13.4).
// The damped sparse path's normwise residuals of 1e-13 vouched for nothing
// here: its lowest mode was 4.5e-6 off (3.5e-4 rad/s), and no error was said.
// Each mode whose first-order error exceeds the Frequency Tolerance is now
// refined on the full model (most of them here); each must lie within its
// error (the refined bound, else the first-order estimate) of the closed
// form, plus 1e-8 |lambda| for the reference omega's own error (the
// symmetric sparse and the dense Meirovitch paths agree to 2e-9 on this
// support), and that error must be within the Frequency Tolerance (1e-5).
// At 1 and 2 ranks (test_scene_np2).
TEST(SceneRegression, AStiffSupportsDampedFrequenciesAreRefined) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const double alpha = 0.5;
  const std::string damping = ", Structural Damping: {Rayleigh Alpha: 0.5}";
  const auto undamped = rotorModes(dampedSupportRotor(1e18, 100, 0.0, "", "Sparse", ""), comm);
  const auto sc = parse(dampedSupportRotor(1e18, 100, 0.0, damping, "Sparse", damping));
  analysis::ModalResult r;
  ASSERT_NO_THROW(r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm));
  const auto& res = r.modes.result;
  EXPECT_EQ(res.status, eigen::SolveStatus::Converged) << res.reason;
  EXPECT_NE(res.reason.find("refined on the full model"), std::string::npos) << res.reason;
  EXPECT_EQ(res.reason.find("not shown within the Frequency Tolerance"), std::string::npos) << res.reason;
  ASSERT_EQ(res.modes.size(), 10u);
  ASSERT_EQ(undamped.size(), 10u);
  const auto closedForm = massDamped(undamped, alpha);
  for (int j = 0; j < 10; ++j) {
    const std::complex<double> exact = closedForm[j];
    const auto& m = res.modes[j];
    const double error = m.reportedError();
    EXPECT_LE(error, 1e-5 * std::abs(exact)) << "mode " << j << (m.refinedError > 0.0 ? " (refined)" : "");
    EXPECT_LE(std::abs(m.lambda - exact), error + 1e-8 * std::abs(exact))
        << "mode " << j << ": " << m.lambda << " against " << exact;
  }
  // The reason's other clause: asked for 1e-12, below the refinement's
  // rounding floor (~1e-9 |lambda| here), the modes whose reported error
  // exceeds it are counted as not shown.
  auto tight = parse(dampedSupportRotor(1e18, 100, 0.0, damping, "Sparse", damping));
  tight.solve.sublist("Sparse Solver").set("Frequency Tolerance", 1e-12);
  analysis::ModalResult t;
  ASSERT_NO_THROW(t = analysis::ModalAnalysis(tight.structure, tight.solve, Teuchos::ParameterList()).run(comm));
  const long unshown = std::count_if(t.modes.result.modes.begin(), t.modes.result.modes.end(),
                                     [](const eigen::GyroscopicMode& m) {
                                       return !(m.reportedError() <= 1e-12 * std::abs(m.lambda));
                                     });
  EXPECT_GT(unshown, 0);
  EXPECT_NE(t.modes.result.reason.find(std::to_string(unshown) + " mode(s) not shown within the Frequency Tolerance 1e-12"),
            std::string::npos)
      << t.modes.result.reason;
}

// A support of E = 1e18 under a 1.2 m steel shaft, both with D = alpha M,
// at rest, on the dense path (the default for its 612 coordinates): the
// system's scale s = sqrt(||K|| / ||M||), the support's stiffness over the
// shaft's mass, is 6.5e7 rad/s, and the shaft's lowest pair (58.37 rad/s)
// lies below the Rigid Body Tolerance's 1e-6 s. It was taken for two rigid
// motions and the run refused as "unrestrained ... shaft moves freely" (exit
// 2); so was the 1 m shaft on that support clamped at both ends (s = 1.1e8).
// sym(K + N) is now proven positive definite (theory §4.3, "A stiffness
// shown nonsingular"): no eigenvalue is zero, and each mode must be the
// closed form lambda = -alpha/2 + i sqrt(omega^2 - alpha^2/4), omega from
// the undamped model's Meirovitch path (componentwise accurate: its own
// scale), within the mode's reported error, plus 1e-8 |lambda| for the
// reference. (That error is first order, as the dense path reports it: its
// normwise dggev leaves the clamped support's pair 0.66 rad/s off, within
// an error of 5.6.)
TEST(SceneRegression, AShaftOnASupportAMillionTimesStifferIsNotTakenForAFreeBody) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const double alpha = 0.5;
  const std::string damping = ", Structural Damping: {Rayleigh Alpha: 0.5}";
  for (const auto& [length, clamp] : {std::pair<std::string, std::string>{"1.2", "start"}, {"1", "ends"}}) {
    const auto scene = [&](const std::string& material, const std::string& support) {
      std::string s = dampedSupportRotor(1e18, 100, 0.0, material, "Dense", support);
      s.replace(s.find("To: [1, 0, 0]"), 13, "To: [" + length + ", 0, 0]");
      s.replace(s.find("Clamp: start"), 12, "Clamp: " + clamp);
      return s;
    };
    const auto undamped = rotorModes(scene("", ""), comm);
    const auto sc = parse(scene(damping, damping));
    analysis::ModalResult r;
    ASSERT_NO_THROW(r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm))
        << length << " m shaft, support clamped at " << clamp;
    const auto& res = r.modes.result;
    EXPECT_NE(res.reason.find("are vibrations, not rigid-body modes"), std::string::npos) << res.reason;
    ASSERT_EQ(undamped.size(), 10u);
    const auto closedForm = massDamped(undamped, alpha);
    ASSERT_EQ(res.modes.size(), closedForm.size());
    for (std::size_t j = 0; j < closedForm.size(); ++j) {
      const auto& m = res.modes[j];
      const std::complex<double> exact = closedForm[j];
      EXPECT_EQ(m.stability, eigen::Stability::Stable) << clamp << ", mode " << j << ": " << m.lambda;
      EXPECT_LE(std::abs(m.lambda - exact), m.eigenvalueError + 1e-8 * std::abs(exact))
          << clamp << ", mode " << j << ": " << m.lambda << " against " << exact;
    }
  }
}

// The dense path's frequencies on stiff rows (theory §5, "Stiff rows"): the
// 1 m shaft on the support of E = 1e18 clamped at both ends (the shaft, on
// a clamped node, is a plain cantilever beside the support's one stiff
// node), D = alpha M, spinning at 0.5 rad/s, on the dense path (the
// default for its 606 coordinates). dggev left the lowest pair (78.1456,
// 78.1475) at 77.944 and 78.882, the torsion mode (967.41) at 972.03: 1e-2
// and 5e-3 of |lambda| wrong, each with a first-order error of 12 to 110
// rad/s that only the JSON carried, and neither table nor reason said so.
// The dense path now refines a mode whose first-order error exceeds the
// Frequency Tolerance (as the sparse path does) and refines a cluster (the
// pair, within each other's uncertainty) as one. The reference: the same
// scene with a support of E = 2e11 (no stiff rows: the shaft's modes are
// the same), refined on the sparse path to a Frequency Tolerance of 1e-9.
// Each mode, in order, must lie within the sum of the two reported errors
// of its reference, and its own reported error within the default
// Frequency Tolerance, 1e-5 |lambda|, or the reason must count it as not
// shown.
TEST(SceneRegression, ADenseFrequencyOnAStiffSupportIsShownWithinTheFrequencyTolerance) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::string damping = ", Structural Damping: {Rayleigh Alpha: 0.5}";
  const auto scene = [&](double supportE, const std::string& solver) {
    std::string s = dampedSupportRotor(supportE, 100, 0.5, damping, solver, damping);
    s.replace(s.find("Clamp: start"), 12, "Clamp: ends");
    return s;
  };
  auto ref = parse(scene(2e11, "Sparse"));
  ref.solve.sublist("Sparse Solver").set("Frequency Tolerance", 1e-9);
  const auto reference = analysis::ModalAnalysis(ref.structure, ref.solve, Teuchos::ParameterList()).run(comm).modes.result;
  const auto sc = parse(scene(1e18, "Dense"));
  analysis::ModalResult r;
  ASSERT_NO_THROW(r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm));
  const auto& res = r.modes.result;
  EXPECT_EQ(res.status, eigen::SolveStatus::Converged) << res.reason;
  ASSERT_EQ(res.modes.size(), 10u);
  ASSERT_EQ(reference.modes.size(), 10u);
  int unshown = 0;
  for (int j = 0; j < 10; ++j) {
    const auto& m = res.modes[j];
    const auto& e = reference.modes[j];
    EXPECT_LE(std::abs(m.lambda - e.lambda), m.reportedError() + e.reportedError())
        << "mode " << j << ": " << m.lambda << " (error " << m.reportedError()
        << (m.refinedError > 0.0 ? ", refined" : ", first order") << ") against " << e.lambda << " (error "
        << e.reportedError() << ")";
    unshown += !(m.reportedError() <= 1e-5 * std::abs(m.lambda));
  }
  if (unshown > 0)
    EXPECT_NE(res.reason.find(std::to_string(unshown) + " mode(s) not shown within the Frequency Tolerance"),
              std::string::npos)
        << res.reason;
  // Here every mode is shown: the refinement converges from dggev's values.
  EXPECT_EQ(unshown, 0) << res.reason;
}

// Four identical shafts on one support of E = 1e18, D = 0.3 M on every
// part, at rest, on the dense path: their lowest bending frequency is a
// double (the whirl pair the support couples) and a sixfold value (the
// decoupled ones) 1.7e-6 rad/s apart, dggev's values ~1 rad/s off both.
// Refined one by one (a cluster past six members was), the double came
// back three times and a sixfold member was lost, each with a "refined
// bound" of 7.5e-8 (a review). Refined as one block of eight, each of the
// two lowest multiplets' 16 modes (asked for all 16: a count cutting a
// multiplet may return any of its members) must
// lie within its reported error, plus 1e-8 |lambda| for the reference, of
// the closed form lambda = -alpha/2 + i sqrt(omega^2 - alpha^2/4) (omega from
// the undamped model's Meirovitch path), in order: so every member is there
// once; and each error within the default Frequency Tolerance, 1e-5.
TEST(SceneRegression, FourIdenticalShaftsKeepEveryMemberOfTheirMultipleFrequencies) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto scene = [](const std::string& damping) {
    std::ostringstream s;
    s << "Scene:\n  Substructures:\n    support:\n      Kind: C\n"
      << "      Beam: {From: [-0.1, 0, 0], To: [0, 0, 0], Elements: 2, Young's Modulus: 1.0e18, Density: 7800.0, "
         "Area: 2.0e-3, Iy: 8.0e-7, Iz: 8.0e-7, Torsion Constant: 1.6e-6, Clamp: start"
      << damping << "}\n      Reduction: {Basis: Full}\n";
    for (int k = 1; k <= 4; ++k)
      s << "    shaft" << k << ":\n      Kind: A\n      Parent: support\n"
        << "      Attachment: {Parent Nodes: end, Nodes: start}\n"
        << "      Spin: {Axis: [1, 0, 0], Rate: 0.0, Frame: Stationary}\n"
        << "      Beam: {From: [0, 0, 0], To: [1, 0, 0], Elements: 20, Young's Modulus: 2.0e11, Density: 7800.0, "
           "Area: 1.2566e-3, Iy: 1.2566e-7, Iz: 1.2566e-7, Torsion Constant: 2.5133e-7, Tip Mass: 10.0, "
           "Tip Inertia: [0.02, 0.01, 0.01]"
        << damping << "}\n      Reduction: {Basis: Full}\n";
    s << "  Analysis: {Number of Modes: 16, Solver: Dense}\n";
    return s.str();
  };
  const auto undamped = rotorModes(scene(""), comm);
  std::vector<eigen::GyroscopicMode> ms;
  ASSERT_NO_THROW(ms = rotorModes(scene(", Structural Damping: {Rayleigh Alpha: 0.3}"), comm));
  ASSERT_EQ(undamped.size(), 16u);
  ASSERT_EQ(ms.size(), 16u);
  const auto closedForm = massDamped(undamped, 0.3);
  for (int j = 0; j < 16; ++j)
    EXPECT_LE(std::abs(ms[j].lambda - closedForm[j]), ms[j].reportedError() + 1e-8 * std::abs(closedForm[j]))
        << "mode " << j << ": " << ms[j].lambda << " (error " << ms[j].reportedError()
        << (ms[j].refinedError > 0.0 ? ", refined" : ", first order") << ") against " << closedForm[j];
  // And each is shown within the default Frequency Tolerance (dggev's own
  // errors are 0.5-1.8 rad/s here: refined, not left).
  for (int j = 0; j < 16; ++j) EXPECT_LE(ms[j].reportedError(), 1e-5 * std::abs(ms[j].lambda)) << "mode " << j;
}

namespace {
/// The near-critical tests' check: ten modes, each within its reported
/// error (plus 1e-8 |lambda| for the closed form's rounding) of the closed
/// form's value in the same place of ascending |lambda|, and each shown
/// within the default Frequency Tolerance, 1e-5 |lambda|.
void expectTheClosedFormInOrder(const eigen::GyroscopicResult& res,
                                const std::vector<std::complex<double>>& closedForm) {
  ASSERT_EQ(res.modes.size(), 10u) << res.reason;
  ASSERT_GE(closedForm.size(), res.modes.size());
  for (std::size_t j = 0; j < res.modes.size(); ++j) {
    const auto& m = res.modes[j];
    EXPECT_LE(std::abs(m.lambda - closedForm[j]), m.reportedError() + 1e-8 * std::abs(closedForm[j]))
        << "mode " << j << ": " << m.lambda << " (error " << m.reportedError()
        << (m.refinedError > 0.0 ? ", refined" : ", first order") << ") against " << closedForm[j];
    EXPECT_LE(m.reportedError(), 1e-5 * std::abs(m.lambda)) << "mode " << j << ": " << res.reason;
  }
}
}  // namespace

// Near critical damping: one shaft (40 elements) on the support of E =
// 1e18, D = 156.2 M on both, at rest, on the dense path. dggev returned one
// member of the lowest double pair at -78.1 + 2.708 i and split the other
// onto the real axis, -61.97 and -94.23 (first-order errors 8.3); refined
// alone, both converged to -78.1 + 2.708 i, and the pair was printed three
// times with "refined bounds" of 3.2e-5, a true mode pushed off the list (a
// review). A refinement that repeats a shape another refined mode holds is
// undone now (undoRepeatedRefinements, theory §5). Undone, the split half
// stayed in the list at -61.97 (its first-order error 8.3, "not shown"), a
// value that is no eigenvalue, and the tenth mode was pushed off: the two
// real values are one conjugate pair, held once (the member with Im > 0),
// and the second half refined onto it again is dropped, the list filled
// from the values past the count (theory §5, "A pair split onto the real
// axis"). Against the closed form lambda = -alpha/2 + i sqrt(omega^2 -
// alpha^2/4), in order: every mode within its reported error (plus 1e-8
// |lambda| for the reference) of the closed form's, so each value is there
// with its multiplicity and no other; each shown within the default
// Frequency Tolerance. (Whether dggev splits a pair, and which, depends
// on the BLAS kernels and the rank count: both members at two ranks.)
TEST(SceneRegression, ANearCriticallyDampedPairIsNotRefinedOntoOneEigenvalueTwice) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const double alpha = 156.2;
  const std::string damping = ", Structural Damping: {Rayleigh Alpha: 156.2}";
  const auto undampedScene = dampedSupportRotor(1e18, 40, 0.0, "", "Dense", "");
  auto more = parse(undampedScene);
  more.solve.set("Number of Modes", 16);
  const auto undamped =
      analysis::ModalAnalysis(more.structure, more.solve, Teuchos::ParameterList()).run(comm).modes.result.modes;
  ASSERT_EQ(undamped.size(), 16u);
  const auto closedForm = massDamped(undamped, alpha);
  const auto sc = parse(dampedSupportRotor(1e18, 40, 0.0, damping, "Dense", damping));
  analysis::ModalResult r;
  ASSERT_NO_THROW(r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm));
  expectTheClosedFormInOrder(r.modes.result, closedForm);
}

// As above with the shaft's planes unequal (Iz = 1.3e-7: omega 78.147 and
// 79.485) and D = alpha M between their critical dampings (157, 158.96): one
// plane's pair is two genuine real roots, the other's a complex pair that
// dggev can split onto the real axis. Refined again alone, the split half
// came back on the first plane's real root, held in another group, and was
// printed twice, the tenth mode lost (at 157 with two ranks, 158.96 with
// one; a review). Against the closed form lambda = -alpha/2 +/- sqrt(alpha^2/4
// - omega^2) (both real roots of an overdamped plane listed, of a complex
// pair the member with Im > 0), in ascending |lambda|: every mode within
// its reported error plus 1e-8 |lambda|, and shown within 1e-5 |lambda|.
TEST(SceneRegression, ASplitHalfRefinedOntoAnotherPlanesRealRootIsDropped) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  // Not spinning: an E shaft (a stationary-frame rotor must be axisymmetric).
  const auto unequal = [](std::string scene) {
    const std::string shaftIz = "Iz: 1.2566e-7, Torsion", kind = "Kind: A";
    scene.replace(scene.find(shaftIz), shaftIz.size(), "Iz: 1.3e-7, Torsion");
    scene.replace(scene.find(kind), kind.size(), "Kind: E");
    const auto spin = scene.find("      Spin:");
    scene.erase(spin, scene.find('\n', spin) + 1 - spin);
    return scene;
  };
  auto more = parse(unequal(dampedSupportRotor(1e18, 40, 0.0, "", "Dense", "")));
  more.solve.set("Number of Modes", 16);
  const auto undamped =
      analysis::ModalAnalysis(more.structure, more.solve, Teuchos::ParameterList()).run(comm).modes.result.modes;
  ASSERT_EQ(undamped.size(), 16u);
  for (double alpha : {157.0, 158.96}) {
    SCOPED_TRACE("alpha " + std::to_string(alpha));
    std::vector<std::complex<double>> closedForm;
    for (const auto& u : undamped) {
      const double disc = alpha * alpha / 4.0 - u.omega * u.omega;
      if (disc < 0.0) closedForm.emplace_back(-alpha / 2.0, std::sqrt(-disc));
      else closedForm.emplace_back(-alpha / 2.0 + std::sqrt(disc), 0.0), closedForm.emplace_back(-alpha / 2.0 - std::sqrt(disc), 0.0);
    }
    std::sort(closedForm.begin(), closedForm.end(),
              [](std::complex<double> a, std::complex<double> b) { return std::abs(a) < std::abs(b); });
    std::ostringstream damping;
    damping << ", Structural Damping: {Rayleigh Alpha: " << alpha << "}";
    const auto sc = parse(unequal(dampedSupportRotor(1e18, 40, 0.0, damping.str(), "Dense", damping.str())));
    analysis::ModalResult r;
    ASSERT_NO_THROW(r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm));
    expectTheClosedFormInOrder(r.modes.result, closedForm);
  }
}

namespace {
/// The shaft of the near-critical tests below (50 Full elements, tip disc)
/// on a 2-element support of E = 1e18, spinning at `rate` about x: in its
/// spinning frame (the support C spins, the shaft E turns with it) or in
/// the stationary frame (the shaft A with Frame: Stationary); `material`
/// is appended to the shaft's Beam map.
std::string shaftOnStiffSupport(double rate, bool spinningFrame, const std::string& material = "") {
  std::ostringstream s;
  s << "Scene:\n  Substructures:\n    support:\n      Kind: C\n"
    << "      Beam: {From: [-0.1, 0, 0], To: [0, 0, 0], Elements: 2, Young's Modulus: 1.0e18, Density: 7800.0, "
       "Area: 2.0e-3, Iy: 8.0e-7, Iz: 8.0e-7, Torsion Constant: 1.6e-6, Clamp: start}\n";
  if (spinningFrame) s << "      Spin: {Axis: [1, 0, 0], Rate: " << rate << ", Stress Stiffening: false}\n";
  s << "      Reduction: {Basis: Full}\n    shaft:\n      Kind: " << (spinningFrame ? "E" : "A")
    << "\n      Parent: support\n      Attachment: {Parent Nodes: end, Nodes: start}\n";
  if (!spinningFrame) s << "      Spin: {Axis: [1, 0, 0], Rate: " << rate << ", Frame: Stationary}\n";
  s << "      Beam: {From: [0, 0, 0], To: [1, 0, 0], Elements: 50, Young's Modulus: 2.0e11, Density: 7800.0, "
       "Area: 1.2566e-3, Iy: 1.2566e-7, Iz: 1.2566e-7, Torsion Constant: 2.5133e-7, Tip Mass: 10.0, "
       "Tip Inertia: [0.02, 0.01, 0.01]"
    << material << "}\n      Reduction: {Basis: Full}\n  Analysis: {Number of Modes: 6, Solver: Dense}\n";
  return s.str();
}

/// The Campbell study of a scene's structure (its Analysis), `steps` speeds
/// from rest to twice the nominal rates, crossings bisected or not.
analysis::CampbellResult campbellOf(const std::string& text, int steps,
                                    const Teuchos::RCP<const Teuchos::Comm<int>>& comm, bool refine = true) {
  const auto sc = parse(text);
  const auto a = synthesis::AssembledStructure::assemble(sc.structure, comm);
  const auto s = synthesis::SynthesizedStructure::synthesize(a);
  Teuchos::ParameterList study;
  study.set("Steps", steps);
  study.set("Refine Crossings", refine);
  return analysis::CampbellStudy(study).run(analysis::SynthesizedSweepProblem(a, s, sc.solve));
}

}  // namespace

// Near a critical speed, seen from the spinning frame: a 2-element support
// of E = 1e18 spins at Omega about x with the shaft (E, turning with it; no
// stress stiffening, none arises for a shaft on its spin axis), past the
// shaft's critical speed (78.3 rad/s forward whirl): its lowest mode, the
// forward whirl seen from the spinning frame, is at |omega_FW - Omega|,
// 4.70 rad/s at 83 and 1.70 at 80. The dense path labelled it "critical"
// (a zero frequency, K(Omega) singular): below 1e-6 of the system's scale
// (7e7 rad/s, the support's) and inside the radius a split defective zero
// can take (10 sqrt(eta) s); with the shaft's material damping (beta 1e-6)
// it printed 0 rad/s, "critical", where the shaft flutters (a review found
// the 4.70 mode labelled critical; theory §4.3, "A zero shown nonzero").
// The reference: the same shaft in the stationary frame (support at rest,
// the shaft A spinning at Omega, Frame: Stationary, its beta as material
// damping with the circulatory term, theory §13.1), whose forward whirl
// lambda_s gives lambda = lambda_s - i Omega in the spinning frame (the
// member with Im >= 0 listed: Re lambda_s + i |Im lambda_s - Omega|); the
// two models share no matrix. Allowed: each mode's reported error, plus
// 1e-9 Omega for the two models' rounding at the scale of the speed.
TEST(SceneRegression, AModeNearACriticalSpeedIsShownNonzeroByItsRefinement) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  // 78.0 and 78.6 rad/s, 0.29 and 0.31 rad/s from the critical speed
  // (78.29): in the window that still read critical where only the
  // system's scale bounded what rounding could do (1e-6 of the mode's own
  // componentwise scale); read with the bound of K's parts
  // (GyroscopicSystem::KMagnitude), as the rest. Damped, the truth flutters
  // at 78.6 (+1.2e-5 1/s), and was printed at 0 rad/s, "critical".
  for (double rate : {78.0, 78.6, 80.0, 83.0})
    for (const std::string material : {"", ", Structural Damping: {Rayleigh Beta: 1.0e-6}"}) {
      SCOPED_TRACE(std::to_string(rate) + " rad/s" + material);
      std::vector<eigen::GyroscopicMode> spinning, stationary;
      ASSERT_NO_THROW(spinning = rotorModes(shaftOnStiffSupport(rate, true, material), comm));
      ASSERT_NO_THROW(stationary = rotorModes(shaftOnStiffSupport(rate, false, material), comm));
      ASSERT_GE(spinning.size(), 1u);
      ASSERT_GE(stationary.size(), 2u);
      // The stationary frame's forward whirl: of its lowest pair, the
      // higher (the tip disc's gyroscopic moment stiffens the forward
      // whirl; the image of the backward one can be the lower: at 78.0
      // rad/s the backward whirl is at 78.0016, its image 0.0016).
      const auto image = [&](const eigen::GyroscopicMode& s) {
        return std::complex<double>(s.lambda.real(), std::abs(s.lambda.imag() - rate));
      };
      const auto& fw = stationary[0].omega > stationary[1].omega ? stationary[0] : stationary[1];
      const auto& m = spinning[0];
      EXPECT_NE(m.stability, eigen::Stability::Critical) << m.lambda;
      EXPECT_NE(m.stability, eigen::Stability::RigidBody) << m.lambda;
      EXPECT_LE(std::abs(m.lambda - image(fw)), m.reportedError() + fw.reportedError() + 1e-9 * rate)
          << m.lambda << " (error " << m.reportedError() << (m.refinedError > 0.0 ? ", refined" : ", first order")
          << ") against " << image(fw) << " (error " << fw.reportedError() << ")";
      // Shown, not only within a first-order error of |lambda| (the
      // default Frequency Tolerance's 1e-5; in the window, 1e-4: the
      // refinement's bound there is its functional's rounding on this
      // system's scale, 3.3e-6 rad/s, 1.1e-5 of 0.29 rad/s).
      EXPECT_LE(m.reportedError(), (rate < 79.0 ? 1e-4 : 1e-5) * std::abs(m.lambda)) << m.lambda;
      // Damped, the forward whirl flutters past its critical speed (the
      // material damping's circulatory term) in either frame. Undamped, the
      // verdict is not compared: the conservative verdict's k = 3 radius,
      // 10 eta^(1/3) s = 4e3 rad/s on this system's scale, holds the whole
      // low spectrum and reads every mode of the spinning frame "neutral",
      // this one as the rest (theory §4, an open finding); it must not be
      // an instability.
      if (material.empty())
        EXPECT_TRUE(m.stability == eigen::Stability::Stable || m.stability == eigen::Stability::Neutral)
            << eigen::toString(m.stability);
      else
        EXPECT_EQ(m.stability, fw.stability) << m.lambda << " against " << fw.lambda;
    }
}

// A Campbell track follows its mode through a critical speed between two
// grid speeds: the shaft of the test above, in its spinning frame, swept
// from 0 to 166 rad/s in 11 steps (its critical speed, 78.29, between 66.4
// and 83). Past it the forward whirl's eigenvalue i (omega_FW - Omega) comes
// back as its conjugate (a pair is listed by its member with Im >= 0), its
// shape conjugated, whose MAC with the mode before is ~0: the track was lost
// at 83 rad/s and the mode entered as a new track ("left the requested
// modes"). Before the zero refinement narrowed the window that reads
// "critical" (theory §4.3), the 101-step sweep had a grid speed in it, and a
// zero takes any MAC; with the window narrowed the track was lost there too
// (theory §12.1). The lowest track must be |omega_FW - Omega| at every
// speed, never lost, omega_FW from the stationary-frame model of the same
// shaft (the test above), within 1e-3 of it (0.078 rad/s): the sweep's
// undamped dense solves keep dggev's values, unrefined, whose first-order
// error on this system's scale (s = 7e7 rad/s) is about eps s^2 / (2
// omega) = 0.014 rad/s at 37.8 rad/s (0.0027 off at 116.2 rad/s with
// OpenBLAS's Nehalem kernels, within 7.8e-5 with Zen's), while every other
// mode of the spinning frame is at least 17 rad/s from this branch above
// rest, so the branch is told apart all the same.
TEST(SceneRegression, ACampbellTrackFollowsItsModeThroughACriticalSpeedBetweenGridSpeeds) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto r = campbellOf(shaftOnStiffSupport(83.0, true), 11, comm);
  ASSERT_EQ(r.zeroFrequencySpeeds.size(), 1u) << r.zeroCountsNote;
  EXPECT_NEAR(r.zeroFrequencySpeeds[0], 78.2927, 1e-4 * 78.29);
  ASSERT_FALSE(r.tracks.empty());
  const auto& low = r.tracks[0];
  for (std::size_t k = 0; k < r.speeds.size(); ++k) {
    const double W = r.speeds[k][0];
    SCOPED_TRACE(std::to_string(W) + " rad/s");
    ASSERT_FALSE(low.lost[k]) << "the lowest track lost";
    if (W == 0.0) continue;  // at rest the pair is double: either whirl
    const auto stationary = rotorModes(shaftOnStiffSupport(W, false), comm);
    ASSERT_GE(stationary.size(), 2u);
    const double fw = std::max(stationary[0].omega, stationary[1].omega);
    EXPECT_NEAR(low.omega[k], std::abs(fw - W), 1e-3 * fw) << "forward whirl " << fw;
  }
}

// No crossing is invented where a track follows its mode through zero: the
// same shaft with 20 elements and a small disc (tip inertia 2e-4, 1e-4),
// swept to 166 rad/s in 40 steps. Past its critical speed (78.22) the
// forward whirl has the backward whirl's sense and nearly its shape, and
// the first form of the track-through-zero rule (theory §12.1) gave the
// forward track the backward mode (MAC ~1): a 1X "critical speed" at 78.70
// rad/s between them, at one rank and not at two (a review; 15 of 56 step
// counts). The only 1X crossing is the forward whirl's image meeting the
// line, Omega = omega_FW - Omega: 39.11 rad/s (the stationary-frame model's
// images agree to 1e-7; the review). Allowed: the bisection's tolerance.
TEST(SceneRegression, ATrackThroughZeroInventsNoCrossing) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  std::string text = shaftOnStiffSupport(83.0, true);
  text.replace(text.find("Elements: 50"), 12, "Elements: 20");
  text.replace(text.find("Tip Inertia: [0.02, 0.01, 0.01]"), 31, "Tip Inertia: [2.0e-4, 1.0e-4, 1.0e-4]");
  const auto r = campbellOf(text, 40, comm);
  ASSERT_EQ(r.zeroFrequencySpeeds.size(), 1u) << r.zeroCountsNote;
  std::vector<double> oneX;
  for (const auto& c : r.crossings)
    if (c.order == 1.0) oneX.push_back(c.speed);
  ASSERT_EQ(oneX.size(), 1u) << (oneX.size() > 1 ? oneX[1] : 0.0);
  EXPECT_NEAR(oneX[0], 39.11, 1e-3 * 39.11);
}

// An anisotropic shaft (Iz = 1.3e-7 against Iy = 1.2566e-7) spinning in its
// own frame diverges between the critical speeds of its two planes, where
// K(Omega) has one negative eigenvalue. Swept 0, 78.9, 157.8 rad/s, the
// grid speed 78.9 lies inside the band, and its dense solve took the
// divergent root (growth 0.67 1/s on a system scale of 7e7 rad/s, the
// support's) for a zero and printed it "critical": the sweep listed no
// unstable range (found while testing the band between sweep speeds). The
// band must be listed, its edges the two zero-frequency speeds, proven by
// the count (theory §12.1, "A band between two speeds"). The edges'
// independent check: K's bending parts in each plane scale with that
// plane's I and spin softening is the same in both, so the upper edge is
// the lower times sqrt(Iz / Iy), up to the rotary inertia the mass matrix
// adds per plane (rho I: a share I / (A L^2) ~ 1e-4 of the plane's inertia,
// 3.4% apart between the planes, ~2e-6 of the speed); allowed 1e-5.
TEST(SceneRegression, ADivergenceBandIsListedWhereASweepSpeedsSolveReadsCritical) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  std::string text = shaftOnStiffSupport(78.9, true);
  text.replace(text.find("Iz: 1.2566e-7"), 13, "Iz: 1.3e-7");
  // Without "Refine Crossings" (the engine-order crossings' bisection,
  // 35 s of solves here): the count is bisected either way.
  const auto r = campbellOf(text, 3, comm, false);
  ASSERT_EQ(r.zeroFrequencySpeeds.size(), 2u) << r.zeroCountsNote;
  ASSERT_EQ(r.unstableRanges.size(), 1u);
  ASSERT_EQ(r.unstableByCount.size(), 1u);
  EXPECT_TRUE(r.unstableByCount[0]);
  EXPECT_EQ(r.unstableRanges[0].first, r.zeroFrequencySpeeds[0]);
  EXPECT_EQ(r.unstableRanges[0].second, r.zeroFrequencySpeeds[1]);
  EXPECT_LT(r.unstableRanges[0].first, 78.9);
  EXPECT_GT(r.unstableRanges[0].second, 78.9);
  EXPECT_NEAR(r.unstableRanges[0].second / r.unstableRanges[0].first, std::sqrt(1.3e-7 / 1.2566e-7), 1e-5);
}

// A divergence band inside a wider unstable range is said apart, and the
// range's edges are bisected or not as the band each came from: two shafts
// on one spinning support, one anisotropic (Iz = 2.5e-7: odd count from
// 78.29 to 110.43 rad/s), one isotropic with material damping (beta 1e-4;
// its pair passes through zero together at 60.07, count 0 to 2, and it is
// unstable from there with an even count). Swept 0 to 160 in steps of 16
// without "Refine Crossings", the grid's range starts at its first
// unstable speed, 64; merged with the count's band it was printed "its
// lower edge bisected" at 64, and the whole range as "divergence: ... an
// odd number of negative eigenvalues" (a review).
TEST(SceneRegression, ADivergenceBandInsideAWiderRangeIsSaidApart) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::string beam = "Young's Modulus: 2.0e11, Density: 7800.0, Area: 1.2566e-3, Iy: 1.2566e-7, ";
  std::ostringstream s;
  s << "Scene:\n  Substructures:\n    support:\n      Kind: C\n"
    << "      Beam: {From: [-0.1, 0, 0], To: [0, 0, 0], Elements: 2, Young's Modulus: 2.0e14, Density: 7800.0, "
       "Area: 2.0e-3, Iy: 8.0e-7, Iz: 8.0e-7, Torsion Constant: 1.6e-6, Clamp: start}\n"
    << "      Spin: {Axis: [1, 0, 0], Rate: 80, Stress Stiffening: false}\n      Reduction: {Basis: Full}\n";
  for (const auto& [name, rest] : std::vector<std::pair<std::string, std::string>>{
           {"shaftA", "Iz: 2.5e-7, Torsion Constant: 2.5133e-7, Tip Mass: 10.0, Tip Inertia: [0.02, 0.01, 0.01]"},
           {"shaftB", "Iz: 1.2566e-7, Torsion Constant: 2.5133e-7, Tip Mass: 18.6, Tip Inertia: [0.02, 0.01, 0.01], "
                      "Structural Damping: {Rayleigh Beta: 1.0e-4}"}})
    s << "    " << name << ":\n      Kind: E\n      Parent: support\n"
      << "      Attachment: {Parent Nodes: end, Nodes: start}\n"
      << "      Beam: {From: [0, 0, 0], To: [1, 0, 0], Elements: 10, " << beam << rest << "}\n"
      << "      Reduction: {Basis: Full}\n";
  s << "  Analysis: {Number of Modes: 8, Solver: Dense}\n";
  const auto r = campbellOf(s.str(), 11, comm, false);
  ASSERT_EQ(r.zeroFrequencySpeeds.size(), 3u) << r.zeroCountsNote;
  ASSERT_EQ(r.unstableRanges.size(), 1u);
  EXPECT_EQ(r.unstableRanges[0].first, 64.0);
  EXPECT_TRUE(r.unstableOpen[0].second);
  EXPECT_FALSE(r.unstableEdgesBisected[0].first);
  ASSERT_EQ(r.unstableCountBands[0].size(), 1u);
  EXPECT_EQ(r.unstableCountBands[0][0].first, r.zeroFrequencySpeeds[1]);
  EXPECT_EQ(r.unstableCountBands[0][0].second, r.zeroFrequencySpeeds[2]);
  std::ostringstream os;
  r.printCrossings(os);
  EXPECT_NE(os.str().find("its lower edge the sweep's unstable speed: up to a step outside"), std::string::npos)
      << os.str();
  EXPECT_NE(os.str().find("divergence from 78.29 to 110.4:"), std::string::npos) << os.str();
}

// Inside a divergence band the root is DIVERGENCE, not "critical": a point
// mass (m = 1 kg) on springs kx = 2, ky = 400 N/m spinning in its own frame
// diverges for sqrt(2) < Omega < 20 rad/s; a stiff axial spring (1e14 N/m)
// puts the system's scale at 1e7 rad/s, and the divergent root (2.536 1/s
// at 3 rad/s, 6.739 at 10) below the zero tests' reach: it was printed
// "critical" with its growth, a zero at a critical speed (found while
// testing the Campbell's divergence bands; theory §4.3, §12.1). K(Omega)'s
// count of negative eigenvalues is 1 there (det K < 0: a real root lambda >
// 0), the structure is restrained at rest, and the root must read
// DIVERGENCE with the closed form's growth (the rotating point mass's
// quartic, tests/validation/RotatingPointMassTest.cpp) within its reported
// error. The critical speed itself (kx = 2 at Omega = sqrt 2, the test
// below) stays critical.
TEST(SceneRegression, ARootInsideADivergenceBandReadsDivergence) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const double m = 1.0, kx = 2.0, ky = 400.0;
  const auto modesAt = [&](double ky2, double rate) {
    std::ostringstream s;
    s << std::setprecision(17) << "Scene:\n  Substructures:\n    mass:\n      Kind: C\n"
      << "      Finite Element Model:\n        Mesh: " << CMS_TEST_DATA_DIR << "/meshes/point_mass.msh\n"
      << "        Point Masses:\n          m: {Node Set: m, Mass: " << m << ", Inertia: [0, 0, 0, 0, 0, 0]}\n"
      << "        Springs:\n          s: {Node Set: m, Stiffness: [" << kx << ", " << ky2 << ", 1.0e14, 0, 0, 0]}\n"
      << "      Spin: {Axis: [0.0, 0.0, 1.0], Origin: [0.0, 0.0, 0.0], Rate: " << rate
      << ", Frame: Rotating}\n      Reduction: {Basis: Full}\n  Analysis: {Number of Modes: 3}\n";
    return rotorModes(s.str(), comm);
  };
  for (double W : {3.0, 10.0}) {
    SCOPED_TRACE(std::to_string(W) + " rad/s");
    std::vector<eigen::GyroscopicMode> ms;
    ASSERT_NO_THROW(ms = modesAt(ky, W));
    ASSERT_FALSE(ms.empty());
    // lambda^2 = s solves m^2 s^2 + (m (a + b) + 4 m^2 W^2) s + a b = 0.
    const double a = kx - m * W * W, b = ky - m * W * W;
    const double B = m * (a + b) + 4 * m * m * W * W, C = a * b;
    const double exact = std::sqrt((-B + std::sqrt(B * B - 4 * m * m * C)) / (2 * m * m));
    int divergent = 0;
    for (const auto& mode : ms) {
      EXPECT_NE(mode.stability, eigen::Stability::Critical) << mode.lambda;
      if (mode.stability != eigen::Stability::Divergence) continue;
      ++divergent;
      // Within the value's own first-order error (dggev's, 5.3e-11 at 3
      // rad/s: the scale 1e7 rad/s times eps over |Q'|), plus 1e-12 of the
      // value for the closed form's own rounding in doubles (the quadratic's
      // root from B^2 - 4 m^2 C, relative error a few eps times B^2 / sqrt of
      // the discriminant, ~1e-14 here): both relative to what they bound.
      EXPECT_LE(std::abs(mode.lambda - exact), mode.reportedError() + 1e-12 * exact)
          << mode.lambda << " (error " << mode.reportedError() << ") against " << exact;
    }
    EXPECT_EQ(divergent, 1);
  }
  // The band's upper edge, Omega = sqrt(ky / m) as the nearest double: the
  // critical speed itself, no divergence. K's kx pivot is clearly negative
  // and the ky pivot zero to rounding, counted neither way: the count was
  // odd, and the edge's zero read DIVERGENCE (a review, at ky = 305, 306,
  // 313, 319). A pivot within rounding now refuses the relabel.
  for (double ky2 : {305.0, 306.0, 313.0, 319.0}) {
    SCOPED_TRACE("ky " + std::to_string(ky2));
    std::vector<eigen::GyroscopicMode> ms;
    ASSERT_NO_THROW(ms = modesAt(ky2, std::sqrt(ky2 / m)));
    for (const auto& mode : ms) EXPECT_NE(mode.stability, eigen::Stability::Divergence) << mode.lambda;
  }
}

// A critical speed itself is an answer, not an instability: a point mass
// on springs kx = 2, ky = 400 N/m (m = 1 kg) spinning in its own frame at
// Omega = sqrt(kx / m), where K(Omega) = diag(kx - m Omega^2, ...) is
// singular (Omega as the nearest double: sqrt(2), sqrt(5) with kx = 5). The
// zero refinement (theory §4.3, "A zero shown nonzero") first refined the
// zero to a real +2.1e-8 within a "bound" of 3.8e-23 and read DIVERGENCE:
// the computed K(Omega)'s entry has cancelled, and its rounding (27% of
// that value against the exact rate) is what no bound of the refinement
// sees (a review). The lowest mode must read critical.
TEST(SceneRegression, APointMassAtItsCriticalSpeedIsCriticalNotDivergent) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  for (double kx : {2.0, 5.0}) {
    SCOPED_TRACE("kx " + std::to_string(kx));
    std::ostringstream s;
    s << std::setprecision(17) << "Scene:\n  Substructures:\n    mass:\n      Kind: C\n"
      << "      Finite Element Model:\n        Mesh: " << CMS_TEST_DATA_DIR << "/meshes/point_mass.msh\n"
      << "        Point Masses:\n          m: {Node Set: m, Mass: 1.0, Inertia: [0, 0, 0, 0, 0, 0]}\n"
      << "        Springs:\n          s: {Node Set: m, Stiffness: [" << kx << ", 400.0, 1.0e4, 0, 0, 0]}\n"
      << "      Spin: {Axis: [0.0, 0.0, 1.0], Origin: [0.0, 0.0, 0.0], Rate: " << std::sqrt(kx)
      << ", Frame: Rotating}\n      Reduction: {Basis: Full}\n  Analysis: {Number of Modes: 6}\n";
    std::vector<eigen::GyroscopicMode> ms;
    ASSERT_NO_THROW(ms = rotorModes(s.str(), comm));
    ASSERT_FALSE(ms.empty());
    EXPECT_EQ(ms[0].stability, eigen::Stability::Critical)
        << eigen::toString(ms[0].stability) << " at " << ms[0].lambda << " (refined bound " << ms[0].refinedError << ")";
    for (const auto& m : ms)
      EXPECT_TRUE(m.stability != eigen::Stability::Divergence && m.stability != eigen::Stability::Flutter)
          << eigen::toString(m.stability) << " at " << m.lambda;
  }
}

// The dense path's refinement stalled as the sparse path's had (theory §5,
// "Stiff rows"; RefinementGate): the stiff-support shaft (bearing dampers,
// beta 1e-5) spinning at 0.5 rad/s, its lowest pair split by 1.9e-3 rad/s,
// came out on the dense path at 78.146850 with a "refined bound" of
// 8.4e-5, 8.6e-4 from either member (78.145990, 78.147852), with the BLAS
// on two threads (on one, dggev's value was not refined: its first-order
// error, 6.3, stood). Solved here with two. The reference: the same shaft
// with the support clamped at its end, where the shaft attaches (the
// support's compliance under the shaft is 3e-11 of the shaft's), a model
// without the stiff rows, on which the dense and the sparse paths agree to
// 1.2e-5 rad/s: allowed 5e-5 beside each mode's reported error.
TEST(SceneRegression, ADenseRefinementThatStallsClaimsNoBound) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::string beta = ", Structural Damping: {Rayleigh Beta: 1.0e-5}";
  std::vector<eigen::GyroscopicMode> stiff;
  {
    BlasThreadScope two(2);
    stiff = rotorModes(dampedSupportRotor(1e18, 100, 0.5, beta, "Dense"), comm);
  }
  std::string clamped = dampedSupportRotor(2e11, 100, 0.5, beta, "Dense");
  clamped.replace(clamped.find("Clamp: start"), 12, "Clamp: end");
  const auto reference = rotorModes(clamped, comm);
  ASSERT_GE(stiff.size(), 2u);
  ASSERT_GE(reference.size(), 2u);
  for (int j = 0; j < 2; ++j) {
    const auto& m = stiff[j];
    const double distance = std::min(std::abs(m.lambda - reference[0].lambda), std::abs(m.lambda - reference[1].lambda));
    EXPECT_LE(distance, m.reportedError() + 5e-5)
        << "mode " << j << ": " << m.lambda << (m.refinedError > 0.0 ? ", refined" : ", first order") << " error "
        << m.reportedError() << ", against " << reference[0].lambda << " and " << reference[1].lambda;
  }
}

// A decaying growth within its uncertainty, on the dense path, of a system
// with a circulatory N (no energy bound): the stiff-support shaft, 50
// elements, beta 1e-6, spinning at 140 rad/s in the stationary frame,
// flutters in its forward whirl at +0.0024066 + 78.407486 i (the sparse
// path, refined within 5.6e-6; the shaft clamped at the support's end, the
// same). With the BLAS on two threads dggev gave -0.0020 within 27 (ten
// times its first-order error), not refined (only positive growths were),
// and read "stable" (a review). Such a decay is refined now, and one left
// unrefined is undecided (theory §13.3). With one and two BLAS threads, the
// flutter must be found, within its reported error of the reference.
//
// And at 182 rad/s (+0.0040447 + 78.485585 i; the sparse path the same,
// within 5.6e-6): there the refinement of the pair as one block (theory §5,
// "The dense path, and clusters") first left both members unrefined (its
// Ritz vectors' weighted residual 6.1e-6 against a bound of 5.6e-6, no step
// standing), and the flutter read UNDECIDED; a member no step of which
// stands is now finished alone from its Ritz value.
TEST(SceneRegression, ADenseDecayWithinItsUncertaintyIsRefinedOnACirculatorySystem) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::vector<std::pair<double, std::complex<double>>> flutters{{140.0, {0.0024066, 78.407486}},
                                                                      {182.0, {0.0040447, 78.485585}}};
  for (const auto& [rate, reference] : flutters)
  for (int threads : {1, 2}) {
    const std::string scene = dampedSupportRotor(1e18, 50, rate, ", Structural Damping: {Rayleigh Beta: 1.0e-6}", "Dense");
    SCOPED_TRACE(std::to_string(rate) + " rad/s");
    std::vector<eigen::GyroscopicMode> ms;
    {
      BlasThreadScope scope(threads);
      ms = rotorModes(scene, comm);
    }
    const auto forward = std::min_element(ms.begin(), ms.end(), [&](const auto& a, const auto& b) {
      return std::abs(a.lambda - reference) < std::abs(b.lambda - reference);
    });
    ASSERT_NE(forward, ms.end());
    EXPECT_EQ(forward->stability, eigen::Stability::Flutter)
        << threads << " BLAS thread(s): " << forward->lambda << " within " << forward->growthTolerance;
    // The reference's own digits: 1e-7 rad/s.
    EXPECT_LE(std::abs(forward->lambda - reference), forward->reportedError() + 1e-6) << threads << " BLAS thread(s)";
  }
  // Below the forward critical speed (78.4 rad/s) material damping cannot
  // destabilise (theory §13.4): at 5.6 rad/s the lowest pair (split by 0.021
  // rad/s) decays at ~0.003 1/s. dggev left the forward whirl at 78.58 (for
  // 78.157) and the refinement from there converged by 0.96 a step: no step
  // stood, and both read UNDECIDED (two BLAS threads). Refactored at the
  // value the steps reached, both read stable.
  const std::string slow = dampedSupportRotor(1e18, 50, 5.6, ", Structural Damping: {Rayleigh Beta: 1.0e-6}", "Dense");
  std::vector<std::vector<eigen::GyroscopicMode>> runs;
  for (int threads : {1, 2}) {
    {
      BlasThreadScope scope(threads);
      runs.push_back(rotorModes(slow, comm));
    }
    ASSERT_GE(runs.back().size(), 2u);
    for (int j = 0; j < 2; ++j) {
      const auto& m = runs.back()[j];
      // Stable. (Where dggev's value landed 0.7 rad/s off, at two ranks and
      // with OPENBLAS_CORETYPE=Nehalem (77.41, 77.45 for 78.137), sixteen
      // steps refining each member alone did not converge, and this allowed
      // UNDECIDED too. The pair refined as one block (theory §5, "The dense
      // path, and clusters") reads stable at 78.1365 and 78.1574 at one and
      // two ranks, one and two BLAS threads, and with Nehalem, by hand.)
      EXPECT_EQ(m.stability, eigen::Stability::Stable)
          << threads << " BLAS thread(s), mode " << j << ": " << m.lambda << " within " << m.growthTolerance;
    }
  }
  // The two solves (their dggev values differ by up to 0.44 rad/s) agree
  // within their reported errors: each of the first's pair near one of the
  // second's.
  for (int j = 0; j < 2; ++j) {
    const auto& m = runs[0][j];
    double closest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 2; ++k)
      closest = std::min(closest, std::abs(m.lambda - runs[1][k].lambda) - m.reportedError() - runs[1][k].reportedError());
    EXPECT_LE(closest, 0.0) << "mode " << j << ": " << m.lambda << " error " << m.reportedError() << " against "
                            << runs[1][0].lambda << ", " << runs[1][1].lambda;
  }
}

// The stiffness proof above takes the given K as exact, and a synthesised
// K's rounding can make a free motion "stiff" as stored: a soft post (E =
// 1e6) on springs along its axis, free to turn about it, under an arm of E
// = 2e11 or 1e18, with D = alpha M, was printed with its free turn as a
// vibration (2.5e-5 and 0.029 rad/s, the latter with a refined bound of
// 9e-14) where it had been refused as "unrestrained" (a review). sym(K + N)
// must now also pass the undamped path's Cholesky test (pivots^2 spread
// within the Definiteness Tolerance), which these fail: refused again.
TEST(SceneRegression, AFreeTurnUnderAStifferArmIsNotProvenStiff) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  for (const std::string armE : {"2.0e11", "1.0e18"}) {
    const std::string scene = R"(
Scene:
  Substructures:
    post:
      Kind: C
      Beam: {From: [0, 0, 0], To: [1, 0, 0], Elements: 4, Young's Modulus: 1.0e6, Density: 2700.0, Area: 0.01, Iy: 1.0e-5, Iz: 1.0e-5, Torsion Constant: 2.0e-5, Springs: {s: {Node Set: end, Stiffness: [0, 1.0e8, 1.0e8, 0, 0, 0]}, t: {Node Set: start, Stiffness: [1.0e8, 1.0e8, 1.0e8, 0, 0, 0]}}, Structural Damping: {Rayleigh Alpha: 0.5}}
      Reduction: {Basis: Full}
    arm:
      Kind: E
      Parent: post
      Attachment: {Type: Node, Parent Nodes: end, Nodes: start}
      Beam: {From: [1, 0, 0], To: [1, 7.03, 3.17], Elements: 6, Young's Modulus: )" + armE + R"(, Density: 2700.0, Area: 0.01, Iy: 1.0e-5, Iz: 1.0e-5, Torsion Constant: 2.0e-5, Orientation: [0.3, 0.1, 1]}
      Reduction: {Basis: Full}
  Analysis: {Number of Modes: 8, Solver: Dense}
)";
    const auto sc = parse(scene);
    SCOPED_TRACE("arm E = " + armE);
    fixtures::expectInputError(
        [&] { analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm); }, "unrestrained");
  }
}

// The same stiff-support shaft (bearing dampers, beta 1e-5) spinning at
// 0.5 rad/s: its lowest pair is split by 1.9e-3 rad/s. Asked for 10 modes,
// the iteration returned both members near 77.7 and 78.1; refined from a
// shift between them, each stalled at a weighted mean, 78.146892, moving by
// less than the rounding floor per step, and that floor, 8.3e-5 rad/s, was
// reported as the bound of a value 9e-4 from either eigenvalue (a review).
// A refined step now stands only where its residual, weighed by the left
// vector, agrees with its bound (theory §5, "Stiff rows"). Checked as two
// solves of one model, for 10 and for 8 modes: each of the first's lowest
// four must lie within the sum of the two reported errors of one of the
// second's (a bound says how far an eigenvalue is, not which one: a value
// between a pair's members is within its bound of the nearer).
TEST(SceneRegression, TwoSolvesOfAStiffSpinningRotorAgreeWithinTheirReportedErrors) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const std::string scene = dampedSupportRotor(1e18, 100, 0.5, ", Structural Damping: {Rayleigh Beta: 1.0e-5}", "Sparse");
  const auto error = [](const eigen::GyroscopicMode& m) { return m.reportedError(); };
  std::vector<std::vector<eigen::GyroscopicMode>> runs;
  for (int count : {10, 8}) {
    auto sc = parse(scene);
    sc.solve.set("Number of Modes", count);
    analysis::ModalResult r;
    ASSERT_NO_THROW(r = analysis::ModalAnalysis(sc.structure, sc.solve, Teuchos::ParameterList()).run(comm));
    ASSERT_EQ(r.modes.result.modes.size(), static_cast<std::size_t>(count)) << r.modes.result.reason;
    runs.push_back(r.modes.result.modes);
  }
  for (int j = 0; j < 4; ++j) {
    const auto& a = runs[0][j];
    const auto nearest = std::min_element(runs[1].begin(), runs[1].end(), [&](const auto& p, const auto& q) {
      return std::abs(a.lambda - p.lambda) - error(p) < std::abs(a.lambda - q.lambda) - error(q);
    });
    EXPECT_LE(std::abs(a.lambda - nearest->lambda), error(a) + error(*nearest))
        << "mode " << j << ": " << a.lambda << " (error " << error(a) << (a.refinedError > 0.0 ? ", refined" : "")
        << ") against " << nearest->lambda << " (error " << error(*nearest)
        << (nearest->refinedError > 0.0 ? ", refined" : "") << ")";
  }
}

// The stiff support (E = 1e18, no dampers) under the shaft with material
// damping beta 1e-6 and a tip of almost no polar inertia, 100 rad/s in the
// stationary frame: its forward whirl flutters at +8.5e-4 + 78.1564 i
// (1 rank at 8, 10 and 12 modes, Nehalem, E = 1e14: a review). On the
// sparse path its lowest pair came out 1e-3 |lambda| apart, a cluster,
// neither refinement converging, and both read "stable" (+0.0026 and
// -0.0087 1/s within 9e3 and 1.3e4 1/s) at 1 rank; at 2 ranks one member
// refined to -0.0059 within 0.0148. A returned mode left with a first-order
// error above the Frequency Tolerance whose growth's sign lies within it is
// now undecided (theory §13.3): the flutter is found or the run says
// UNDECIDED, and no unrefined mode reads stable with an uncertainty that
// reaches zero unless its frequency is shown (its error within 1e-5
// |lambda|). A refined one can (the 2-rank member: an open finding).
TEST(SceneRegression, AnUnresolvedClusterOfAFlutteringRotorIsNotReadStable) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  std::string scene = dampedSupportRotor(1e18, 100, 100.0, ", Structural Damping: {Rayleigh Beta: 1.0e-6}", "Sparse", "");
  const std::string tip = "Tip Inertia: [0.02, 0.01, 0.01]";
  scene.replace(scene.find(tip), tip.size(), "Tip Inertia: [1.0e-6, 0.01, 0.01]");
  std::vector<eigen::GyroscopicMode> ms;
  ASSERT_NO_THROW(ms = rotorModes(scene, comm));
  const long undecided = std::count_if(ms.begin(), ms.end(), [](const eigen::GyroscopicMode& m) { return m.undecided; });
  EXPECT_TRUE(flutters(ms) > 0 || undecided > 0) << "the flutter at +8.5e-4 + 78.1564 i read stable";
  for (std::size_t j = 0; j < ms.size(); ++j) {
    const auto& m = ms[j];
    const double size = std::abs(m.lambda);
    const double error = m.reportedError();
    if (m.stability == eigen::Stability::Stable && m.refinedError == 0.0)
      EXPECT_TRUE(m.growthRate + m.growthTolerance <= 1e-7 * size || error <= 1e-5 * size)
          << "mode " << j << " reads stable: " << m.lambda << " within " << m.growthTolerance << ", error " << error;
  }
}

// A reduced model smaller than twice the Ritz vectors the sparse path
// converges: both halves of the damped state vectors are more columns than
// the model has coordinates, and the subspace kept a rounding direction
// (1e-16 of the Gram matrix's largest eigenvalue, above its 1e-20 cut): 23
// columns for 22 coordinates, the projected M singular, and the run refused
// as bad input "M is not positive definite" (exit 2; a review). The sparse
// path now gives the dense path's modes: frequencies to 1e-9 relative and
// growth rates to 1e-9 |lambda| (both are dense solves of the same 22
// coordinates, the sparse one in another basis: eps times the pencil's
// conditioning).
TEST(SceneRegression, ASmallDampedModelSolvesOnTheSparsePath) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto scene = [](const std::string& solver) {
    return std::string(R"(
Scene:
  Substructures:
    support:
      Kind: C
      Beam: {From: [-1.0, 0, 0], To: [0, 0, 0], Elements: 6, Young's Modulus: 2.0e11, Density: 7800.0, Area: 2.0e-3, Iy: 8.0e-7, Iz: 5.0e-7, Torsion Constant: 1.0e-6, Clamp: start}
      Reduction: {Basis: Craig-Bampton, Vectors: 6}
    shaft:
      Kind: A
      Parent: support
      Attachment: {Parent Nodes: end, Nodes: start}
      Spin: {Axis: [1, 0, 0], Rate: 300.0, Frame: Stationary}
      Beam: {From: [0, 0, 0], To: [2.0, 0, 0], Elements: 10, Young's Modulus: 2.0e11, Density: 7800.0, Area: 1.2566e-3, Iy: 1.2566e-7, Iz: 1.2566e-7, Torsion Constant: 2.5133e-7, Tip Mass: 10.0, Tip Inertia: [0.2, 0.1, 0.1], Structural Damping: {Rayleigh Alpha: 0.01}}
      Reduction: {Basis: Admissible, Vectors: 10}
  Analysis: {Number of Modes: 8, Solver: )") + solver + "}\n";
  };
  const auto dense = rotorModes(scene("Dense"), comm);
  std::vector<eigen::GyroscopicMode> sparse;
  ASSERT_NO_THROW(sparse = rotorModes(scene("Sparse"), comm));
  ASSERT_EQ(sparse.size(), dense.size());
  for (std::size_t j = 0; j < dense.size(); ++j) {
    EXPECT_NEAR(sparse[j].omega, dense[j].omega, 1e-9 * std::abs(dense[j].lambda)) << "mode " << j;
    EXPECT_NEAR(sparse[j].growthRate, dense[j].growthRate, 1e-9 * std::abs(dense[j].lambda)) << "mode " << j;
    EXPECT_EQ(sparse[j].stability, dense[j].stability) << "mode " << j;
  }
}
