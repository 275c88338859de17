// The Abaqus/CalculiX .inp reader (packages/mesh/src/InpReader.cpp): every
// keyword it reads, GENERATE, includes, sets of sets, the node order of each
// element type (mid-edge nodes where the project's order puts them, positive
// element volume), Gmsh's own Abaqus export read back as the Gmsh mesh it
// came from, and every malformed deck refused with file:line and what.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

#include "cms/core/Error.hpp"
#include "cms/fem/SolidElement.hpp"
#include "cms/mesh/InpReader.hpp"
#include "cms/mesh/Mesh.hpp"

#ifndef CMS_TEST_DATA_DIR
#define CMS_TEST_DATA_DIR "tests/data"
#endif

namespace fs = std::filesystem;
using cms::mesh::CellType;
using cms::mesh::Mesh;
using cms::mesh::readInp;

namespace {

const std::string kMeshes = std::string(CMS_TEST_DATA_DIR) + "/meshes/";
constexpr double kEps = std::numeric_limits<double>::epsilon();

class TempDir {
public:
  TempDir() {
    std::string t = (fs::temp_directory_path() / "cms_inp_test_XXXXXX").string();
    if (!mkdtemp(t.data())) throw std::runtime_error("mkdtemp failed");
    path_ = t;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = path_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }

private:
  fs::path path_;
};

/// fn throws cms::InputError whose message holds every one of parts.
void expectInputError(const std::function<void()>& fn, std::initializer_list<std::string> parts) {
  try {
    fn();
    ADD_FAILURE() << "no cms::InputError (expected one mentioning \"" << *parts.begin() << "\")";
  } catch (const cms::InputError& e) {
    const std::string what = e.what();
    for (const std::string& p : parts)
      EXPECT_NE(what.find(p), std::string::npos) << "message \"" << what << "\" lacks \"" << p << "\"";
  }
}

/// Index of the node with that deck id.
std::int64_t node(const Mesh& m, std::size_t id) {
  const auto it = std::lower_bound(m.nodeTags.begin(), m.nodeTags.end(), id);
  if (it == m.nodeTags.end() || *it != id) throw std::runtime_error("no node " + std::to_string(id));
  return it - m.nodeTags.begin();
}

std::vector<std::size_t> ids(const Mesh& m, const std::vector<std::int64_t>& indices) {
  std::vector<std::size_t> out;
  for (auto i : indices) out.push_back(m.nodeTags[static_cast<std::size_t>(i)]);
  return out;
}

bool noted(const Mesh& m, const std::string& part) {
  return std::any_of(m.notes.begin(), m.notes.end(), [&](const std::string& n) { return n.find(part) != std::string::npos; });
}

// A unit cube of C3D8 split in two along x, lower case keywords, comments,
// sparse ids, a material and a step to skip.
const char* kTwoBricks = R"(** two bricks
*heading
  two bricks, x in [0, 2]
*Node, nset=ALLN
 10, 0., 0., 0.
 20, 1., 0., 0.
 30, 1., 1., 0.
 40, 0., 1., 0.
 50, 0., 0., 1.
 60, 1., 0., 1.
 70, 1., 1., 1.
 80, 0., 1., 1.
 90, 2., 0., 0.
 100, 2., 1., 0.
 110, 2., 0., 1.
 120, 2., 1., 1.5D-0
*element, type=c3d8, elset=Left
 7, 10, 20, 30, 40, 50, 60, 70, 80
*ELEMENT, TYPE=C3D8R, ELSET=right
 9, 20, 90, 100, 30, 60, 110, 120, 70
*ELSET, ELSET=both
 left, RIGHT
*NSET, NSET=root
 10, 40, 50,
 80
*NSET, NSET=Ends, GENERATE
 10, 40, 30
 90, 120, 10
*NSET, NSET=ends
 root
*NSET, NSET=rightNodes, ELSET=right
*MATERIAL, NAME=steel
*ELASTIC
 2.1e11, 0.3
*STEP
*FREQUENCY
 10
*END STEP
)";

}  // namespace

TEST(InpReader, ReadsNodesElementsAndSets) {
  TempDir dir;
  const std::string path = dir.write("bricks.inp", kTwoBricks);
  const Mesh m = readInp(path);
  EXPECT_EQ(m.source, path);
  ASSERT_EQ(m.nodeCount(), 12u);
  EXPECT_TRUE(std::is_sorted(m.nodeTags.begin(), m.nodeTags.end()));
  EXPECT_EQ(m.nodeTags.front(), 10u);
  EXPECT_EQ(m.nodeTags.back(), 120u);
  EXPECT_EQ(m.x(node(m, 70))[0], 1.0);
  EXPECT_EQ(m.x(node(m, 120))[2], 1.5);  // Fortran's D exponent

  // Element sets: names as first written, found case-insensitively in the
  // deck; the deck's type name kept for the model.
  const auto& left = m.group("Left");
  EXPECT_EQ(left.dim, 3);
  ASSERT_EQ(left.blocks.size(), 1u);
  EXPECT_EQ(left.blocks[0].type, CellType::Hex8);
  EXPECT_EQ(left.blocks[0].elementName, "C3D8");
  EXPECT_EQ(left.blocks[0].cellTags, std::vector<std::size_t>{7});
  EXPECT_EQ(m.group("right").blocks[0].elementName, "C3D8R");
  const auto& both = m.group("both");
  ASSERT_EQ(both.blocks.size(), 2u);  // one block per deck type
  EXPECT_EQ(both.blocks[0].size() + both.blocks[1].size(), 2u);

  // Node sets: a trailing comma continues the list, GENERATE takes the
  // defined ids of its range (10, 40; 90, 100, 110, 120), a set named
  // again adds to itself (root), *NSET ELSET= takes an element set's nodes.
  EXPECT_EQ(m.group("root").dim, 0);
  EXPECT_EQ(ids(m, m.nodeSet("root")), (std::vector<std::size_t>{10, 40, 50, 80}));
  EXPECT_EQ(ids(m, m.nodeSet("Ends")), (std::vector<std::size_t>{10, 40, 50, 80, 90, 100, 110, 120}));
  EXPECT_EQ(ids(m, m.nodeSet("rightNodes")), (std::vector<std::size_t>{20, 30, 60, 70, 90, 100, 110, 120}));
  EXPECT_EQ(m.nodeSet("ALLN").size(), 12u);

  // The rest of the deck is skipped with a note.
  EXPECT_TRUE(noted(m, "*MATERIAL (" + path + ":32)"));
  EXPECT_TRUE(noted(m, "*STEP"));
  EXPECT_FALSE(noted(m, "HEADING"));
  // GENERATE 10, 40, 30 names ids 10 and 40, both defined: no note; 90, 120,
  // 10 names 90, 100, 110, 120, all defined.
  EXPECT_FALSE(noted(m, "not defined"));
}

TEST(InpReader, GenerateTakesTheDefinedIdsOfItsRange) {
  TempDir dir;
  const std::string deck = std::string(kTwoBricks) + "*NSET, NSET=odd, GENERATE\n 10, 130, 20\n";
  const Mesh m = readInp(dir.write("g.inp", deck));
  // 10, 30, 50, 70, 90, 110, 130: 130 is not a node.
  EXPECT_EQ(ids(m, m.nodeSet("odd")), (std::vector<std::size_t>{10, 30, 50, 70, 90, 110}));
  EXPECT_TRUE(noted(m, "1 of its 7 ids are not defined nodes"));
  // An element set by GENERATE.
  const Mesh e = readInp(dir.write("e.inp", std::string(kTwoBricks) + "*ELSET, ELSET=all, GENERATE\n1, 100\n"));
  EXPECT_EQ(e.group("all").blocks.size(), 2u);
}

TEST(InpReader, IncludesAreReadInPlaceFromTheDecksFolder) {
  TempDir dir;
  // The nodes' data lines in one file two folders down, which includes a
  // sibling with the last node by its name from the deck's folder, as
  // CalculiX reads it (from the folder it runs in); the elements and a set
  // in another.
  dir.write("parts/nodes/a.inp", "** nodes\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n*INCLUDE, INPUT=parts/nodes/b.inp\n");
  dir.write("parts/nodes/b.inp", "4, 0, 0, 1\n");
  dir.write("parts/tet.inp", "*ELEMENT, TYPE=C3D4, ELSET=tet\n5, 1, 2, 3, 4\n*NSET, NSET=base\n1, 2, 3\n");
  const std::string top = dir.write("deck.inp",
                                    "*NODE\n*INCLUDE, INPUT=parts/nodes/a.inp\n*include,input=\"parts/tet.inp\"\n");
  const Mesh m = readInp(top);
  EXPECT_EQ(m.nodeCount(), 4u);
  EXPECT_EQ(m.x(node(m, 4))[2], 1.0);
  EXPECT_EQ(m.group("tet").blocks.at(0).type, CellType::Tet4);
  EXPECT_EQ(m.nodeSet("base").size(), 3u);
  EXPECT_FALSE(noted(m, "INPUT="));

  // A nested include named relative to its own file (the reader's earlier
  // rule; before, "parts/nodes/b.inp" above was looked for in
  // parts/nodes/parts/nodes/ and not found): read where only that file
  // exists, with a note.
  dir.write("near/a.inp", "1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n*INCLUDE, INPUT=b.inp\n");
  dir.write("near/b.inp", "4, 0, 0, 1\n");
  const Mesh near = readInp(dir.write("near.inp", "*NODE, NSET=all\n*INCLUDE, INPUT=near/a.inp\n"));
  EXPECT_EQ(near.nodeCount(), 4u);
  EXPECT_TRUE(noted(near, "INPUT=b.inp is not in the deck's folder")) << "no note of the include's folder";
  // Where both exist, the deck's folder's (CalculiX's), with a note naming the other.
  dir.write("b.inp", "4, 0, 0, 2\n");
  const Mesh both = readInp(dir.write("both.inp", "*NODE, NSET=all\n*INCLUDE, INPUT=near/a.inp\n"));
  EXPECT_EQ(both.x(node(both, 4))[2], 2.0);
  EXPECT_TRUE(noted(both, "read from the deck's folder, as CalculiX does")) << "no note of the other file";

  // An error inside an included file names it, its line, and where it was included from.
  dir.write("bad/x.inp", "1, 0, 0, 0\n2, 0, zero, 0\n");
  const std::string bad = dir.write("bad.inp", "*NODE\n*INCLUDE, INPUT=bad/x.inp\n");
  expectInputError([&] { readInp(bad); }, {"bad/x.inp:2: coordinate y of node 2 \"zero\" is not a number",
                                            "is included from " + bad + ":2"});
  // Not found, and cycles: direct, and through another file.
  const std::string missing = dir.write("missing.inp", "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=nowhere.inp\n");
  expectInputError([&] { readInp(missing); }, {missing + ":3: cannot read", "nowhere.inp: it does not exist"});
  const std::string self = dir.write("self.inp", "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=self.inp\n");
  expectInputError([&] { readInp(self); }, {self + ":3: including", "again makes a cycle"});
  dir.write("loop/b.inp", "*INCLUDE, INPUT=../a.inp\n");
  const std::string a = dir.write("a.inp", "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=loop/b.inp\n");
  expectInputError([&] { readInp(a); }, {"b.inp:1: including", "again makes a cycle", "is included from " + a + ":3"});
  // A keyword line ending in ',' at the end of an included file: its
  // continuation is not the including file's next line (read as more
  // parameters before; found by a review).
  dir.write("cont/k.inp", "*NSET, NSET=base,\n");
  const std::string cont = dir.write("cont.inp", std::string(kTwoBricks) + "*INCLUDE, INPUT=cont/k.inp\n*ELSET, ELSET=e\n1\n");
  expectInputError([&] { readInp(cont); }, {"k.inp:1: the keyword line ends with ','", "is included from " + cont});
  // INPUT= on a data keyword: its data lines from that file.
  dir.write("n.txt", "1, 0, 0, 0\n2, 1, 0, 0\n");
  const Mesh n = readInp(dir.write("input.inp", "*NODE, INPUT=n.txt, NSET=two\n"));
  EXPECT_EQ(n.nodeSet("two").size(), 2u);
}

TEST(InpReader, ContinuationLinesAndSetsSharingANameWithAnElementSet) {
  TempDir dir;
  // A C3D20 whose 20 nodes run over two lines (CalculiX's layout), a
  // keyword line continued, and an *NSET and an *ELSET named alike: the
  // element set is the group, the node set what nodeSet() gives.
  std::string deck = "*NODE\n";
  const double corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int i = 0; i < 8; ++i)
    deck += std::to_string(i + 1) + ", " + std::to_string(corner[i][0]) + ", " + std::to_string(corner[i][1]) + ", " +
            std::to_string(corner[i][2]) + "\n";
  const int edge[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (int e = 0; e < 12; ++e)
    deck += std::to_string(9 + e) + ", " + std::to_string(0.5 * (corner[edge[e][0]][0] + corner[edge[e][1]][0])) + ", " +
            std::to_string(0.5 * (corner[edge[e][0]][1] + corner[edge[e][1]][1])) + ", " +
            std::to_string(0.5 * (corner[edge[e][0]][2] + corner[edge[e][1]][2])) + "\n";
  deck += "*ELEMENT, TYPE=C3D20,\n ELSET=brick\n1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,\n16, 17, 18, 19, 20\n";
  deck += "*NSET, NSET=brick\n1, 2\n";
  const Mesh m = readInp(dir.write("c3d20.inp", deck));
  const auto& g = m.group("brick");
  EXPECT_EQ(g.dim, 3);
  ASSERT_EQ(g.blocks.at(0).type, CellType::Hex20);
  EXPECT_EQ(g.blocks[0].size(), 1u);
  EXPECT_EQ(ids(m, m.nodeSet("brick")), (std::vector<std::size_t>{1, 2}));

  // The same element without the first line's trailing comma, and over
  // three lines: CalculiX reads on while an element lacks nodes (refused
  // before: "element 1 has 15 nodes"). Coordinates in Fortran's form
  // without an exponent letter (1.0+00, 5.0-01), as CalculiX reads them.
  std::string bare = deck;
  bare.replace(bare.find("15,\n16"), 6, "15\n16");
  std::string three = deck;
  three.replace(three.find("15,\n16"), 6, "15\n16");
  three.replace(three.find("\n1, 1, 2, 3"), 11, "\n1, 1\n2, 3");
  for (const std::string& d : {bare, three}) {
    const Mesh b = readInp(dir.write("bare.inp", d));
    ASSERT_EQ(b.group("brick").blocks.at(0).size(), 1u);
    EXPECT_EQ(b.group("brick").blocks[0].nodes, g.blocks[0].nodes);
  }
  const Mesh fortran = readInp(dir.write("fortran.inp", "*NODE, NSET=n\n1, 1.0+00, 5.0-01, -2.5+1\n2, 1.-3, 0, 0\n"));
  EXPECT_EQ(fortran.x(node(fortran, 1))[0], 1.0);
  EXPECT_EQ(fortran.x(node(fortran, 1))[1], 0.5);
  EXPECT_EQ(fortran.x(node(fortran, 1))[2], -25.0);
  EXPECT_EQ(fortran.x(node(fortran, 2))[0], 1e-3);
}

// ---------------------------------------------------------------------------
// Node order: each element type written in Abaqus's order must come out in
// the project's (Gmsh's) order: every mid-edge node at the middle of the
// corners the project's element puts it between, and a positive volume.
// ---------------------------------------------------------------------------

namespace {

struct OrderCase {
  const char* type;
  std::vector<std::array<double, 3>> corners;
  std::vector<std::array<int, 2>> abaqusEdges;   ///< deck's mid-edge nodes, 0-based corners (Abaqus manual)
  std::vector<std::array<int, 2>> projectEdges;  ///< the project's (Mesh.hpp, SolidElement.cpp)
};

/// The deck of one element in Abaqus order, node ids 100 + 7 k (sparse).
std::string oneElement(const OrderCase& c) {
  std::string deck = "*NODE\n";
  std::vector<std::array<double, 3>> x = c.corners;
  for (const auto& e : c.abaqusEdges) {
    std::array<double, 3> mid{};
    for (int d = 0; d < 3; ++d) mid[d] = 0.5 * (x[e[0]][d] + x[e[1]][d]);
    x.push_back(mid);
  }
  char line[200];
  for (std::size_t k = 0; k < x.size(); ++k) {
    std::snprintf(line, sizeof line, "%zu, %.17g, %.17g, %.17g\n", 100 + 7 * k, x[k][0], x[k][1], x[k][2]);
    deck += line;
  }
  // The element id and 15 nodes on the first line, the rest continued
  // (CalculiX's layout of a C3D20).
  deck += std::string("*ELEMENT, TYPE=") + c.type + ", ELSET=e\n1";
  for (std::size_t k = 0; k < x.size(); ++k) deck += (k == 15 ? ",\n" : ", ") + std::to_string(100 + 7 * k);
  return deck + "\n";
}

const std::vector<OrderCase>& orderCases() {
  static const std::vector<OrderCase> cases = {
      {"C3D10",
       {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}, {0, 0, 4}},
       {{{0, 1}}, {{1, 2}}, {{2, 0}}, {{0, 3}}, {{1, 3}}, {{2, 3}}},
       {{{0, 1}}, {{1, 2}}, {{0, 2}}, {{0, 3}}, {{2, 3}}, {{1, 3}}}},
      {"C3D20",
       {{0, 0, 0}, {2, 0, 0}, {2, 3, 0}, {0, 3, 0}, {0, 0, 4}, {2, 0, 4}, {2, 3, 4}, {0, 3, 4}},
       {{{0, 1}}, {{1, 2}}, {{2, 3}}, {{3, 0}}, {{4, 5}}, {{5, 6}}, {{6, 7}}, {{7, 4}}, {{0, 4}}, {{1, 5}}, {{2, 6}}, {{3, 7}}},
       {{{0, 1}}, {{0, 3}}, {{0, 4}}, {{1, 2}}, {{1, 5}}, {{2, 3}}, {{2, 6}}, {{3, 7}}, {{4, 5}}, {{4, 7}}, {{5, 6}}, {{6, 7}}}},
      {"C3D15",
       {{0, 0, 0}, {2, 0, 0}, {0, 3, 0}, {0, 0, 4}, {2, 0, 4}, {0, 3, 4}},
       {{{0, 1}}, {{1, 2}}, {{2, 0}}, {{3, 4}}, {{4, 5}}, {{5, 3}}, {{0, 3}}, {{1, 4}}, {{2, 5}}},
       {{{0, 1}}, {{0, 2}}, {{0, 3}}, {{1, 2}}, {{1, 4}}, {{2, 5}}, {{3, 4}}, {{3, 5}}, {{4, 5}}}},
  };
  return cases;
}

}  // namespace

TEST(InpReader, QuadraticElementsComeOutInTheProjectsNodeOrder) {
  TempDir dir;
  for (const OrderCase& c : orderCases()) {
    SCOPED_TRACE(c.type);
    const Mesh m = readInp(dir.write(std::string(c.type) + ".inp", oneElement(c)));
    const auto& b = m.group("e").blocks.at(0);
    const std::size_t nc = c.corners.size();
    ASSERT_EQ(b.nodes.size(), nc + c.projectEdges.size());
    for (std::size_t k = 0; k < nc; ++k)
      for (int d = 0; d < 3; ++d) EXPECT_EQ(m.x(b.nodes[k])[d], c.corners[k][d]) << "corner " << k;
    // Coordinates up to 4 in exact binary halves: the midpoints are exact.
    for (std::size_t e = 0; e < c.projectEdges.size(); ++e)
      for (int d = 0; d < 3; ++d)
        EXPECT_EQ(m.x(b.nodes[nc + e])[d],
                  0.5 * (c.corners[c.projectEdges[e][0]][d] + c.corners[c.projectEdges[e][1]][d]))
            << "mid-edge node " << nc + e;
  }
}

TEST(InpReader, ElementsHaveTheirVolumeWithAPositiveJacobian) {
  // Through the element library: an element whose nodes were misordered
  // has a Jacobian that changes sign (solidStiffness throws) or a wrong
  // volume. Volumes are sums of a few products of exact coordinates: to
  // 16 eps of the volume.
  TempDir dir;
  const OrderCase& tet = orderCases()[0];
  const Mesh m = readInp(dir.write("tet.inp", oneElement(tet)));
  std::vector<double> xyz;
  for (auto n : m.group("e").blocks.at(0).nodes) xyz.insert(xyz.end(), m.x(n), m.x(n) + 3);
  cms::fem::SolidElement e{cms::fem::SolidType::Tet10, xyz.data(), {2.1e11, 0.3, 7850}};
  EXPECT_NEAR(cms::fem::solidVolume(e), 4.0, 16 * kEps * 4.0);
  EXPECT_NO_THROW(cms::fem::solidStiffness(e));
  // The same element read without conversion (Abaqus order taken as the
  // project's) is wrong: the test can fail.
  std::vector<double> raw;
  const auto& deckOrder = m.group("e").blocks.at(0).nodes;
  for (int k : {0, 1, 2, 3, 4, 5, 6, 7, 9, 8}) raw.insert(raw.end(), m.x(deckOrder[k]), m.x(deckOrder[k]) + 3);
  cms::fem::SolidElement wrong{cms::fem::SolidType::Tet10, raw.data(), {2.1e11, 0.3, 7850}};
  bool misread = false;
  try {
    misread = std::abs(cms::fem::solidVolume(wrong) - 4.0) > 1e-6;
    cms::fem::solidStiffness(wrong);
  } catch (const cms::NumericalError&) {
    misread = true;
  }
  EXPECT_TRUE(misread);

  const Mesh bricks = readInp(dir.write("bricks.inp", kTwoBricks));
  for (const char* set : {"Left", "right"}) {
    const auto& b = bricks.group(set).blocks.at(0);
    std::vector<double> x;
    for (auto n : b.nodes) x.insert(x.end(), bricks.x(n), bricks.x(n) + 3);
    cms::fem::SolidElement h{cms::fem::SolidType::Hex8, x.data(), {2.1e11, 0.3, 7850}};
    // Left: the unit cube; right: a unit cube with its corner (2, 1, 1) raised
    // by 0.5, det J = 1 + 0.5 xi eta on the unit reference cube: 1 + 0.5 / 4.
    EXPECT_NEAR(cms::fem::solidVolume(h), std::string(set) == "Left" ? 1.0 : 1.125, 16 * kEps) << set;
    EXPECT_NO_THROW(cms::fem::solidStiffness(h));
  }
}

TEST(InpReader, GmshsOwnAbaqusExportIsTheGmshMesh) {
  // tests/data/meshes/bar_tet10_short.inp is Gmsh's Abaqus export of
  // bar_tet10_short.msh, its node ids renumbered (reversed, sparse) and its
  // nodes in an included file: every element has the same nodes, in the same
  // order, as the .msh read by Gmsh's SDK; the node sets are the same.
  const Mesh inp = readInp(kMeshes + "bar_tet10_short.inp");
  const Mesh msh = cms::mesh::readGmsh(kMeshes + "bar_tet10_short.msh");
  ASSERT_EQ(inp.nodeCount(), msh.nodeCount());
  auto renumbered = [](std::size_t id) { return 3 * (1000 - id) + 7; };
  const auto& a = inp.group("blade").blocks.at(0);
  const auto& b = msh.group("blade").blocks.at(0);
  ASSERT_EQ(a.type, CellType::Tet10);
  ASSERT_EQ(a.size(), b.size());
  std::map<std::size_t, std::size_t> cellOf;
  for (std::size_t e = 0; e < b.size(); ++e) cellOf[b.cellTags[e]] = e;
  for (std::size_t e = 0; e < a.size(); ++e) {
    ASSERT_TRUE(cellOf.count(a.cellTags[e])) << "element " << a.cellTags[e];
    const std::size_t f = cellOf[a.cellTags[e]];
    for (int k = 0; k < 10; ++k) {
      const std::size_t want = renumbered(msh.nodeTags[static_cast<std::size_t>(b.nodes[10 * f + k])]);
      ASSERT_EQ(inp.nodeTags[static_cast<std::size_t>(a.nodes[10 * e + k])], want)
          << "element " << a.cellTags[e] << " node " << k;
    }
  }
  for (const char* set : {"root", "tip"}) {
    std::vector<std::size_t> want;
    for (auto n : msh.nodeSet(set)) want.push_back(renumbered(msh.nodeTags[static_cast<std::size_t>(n)]));
    std::sort(want.begin(), want.end());
    EXPECT_EQ(ids(inp, inp.nodeSet(set)), want) << set;
  }
  // The same coordinates: the .msh's are rounded to the 14 digits Gmsh's
  // Abaqus export writes (make_bar_inp.py), so both hold the same decimals.
  for (std::size_t i = 0; i < msh.nodeCount(); ++i)
    for (int d = 0; d < 3; ++d)
      EXPECT_EQ(inp.x(node(inp, renumbered(msh.nodeTags[i])))[d], msh.x(static_cast<std::int64_t>(i))[d]);
}

TEST(InpReader, GmshsOwnC3D20ExportIsTheGmshMesh) {
  // The same for 20-node bricks (bar_hex20_small.inp: Gmsh's export of
  // bar_hex20_small.msh, ids unchanged, elements over two lines each).
  const Mesh inp = readInp(kMeshes + "bar_hex20_small.inp");
  const Mesh msh = cms::mesh::readGmsh(kMeshes + "bar_hex20_small.msh");
  ASSERT_EQ(inp.nodeTags, msh.nodeTags);
  const auto& a = inp.group("blade").blocks.at(0);
  const auto& b = msh.group("blade").blocks.at(0);
  ASSERT_EQ(a.type, CellType::Hex20);
  ASSERT_EQ(b.type, CellType::Hex20);
  EXPECT_EQ(a.elementName, "C3D20");
  EXPECT_EQ(a.cellTags, b.cellTags);
  EXPECT_EQ(a.nodes, b.nodes);
  EXPECT_EQ(inp.nodeSet("root"), msh.nodeSet("root"));
}

TEST(InpReader, BeamsAreLinesOfAFrameSet) {
  TempDir dir;
  const Mesh m = readInp(dir.write("beam.inp", "*NODE\n1, 0, 0, 0\n2, 0.5, 0, 0\n3, 1, 0, 0\n"
                                               "*ELEMENT, TYPE=B31, ELSET=beam\n1, 1, 2\n2, 2, 3\n*NSET, NSET=end\n3\n"));
  const auto& g = m.group("beam");
  EXPECT_EQ(g.dim, 1);
  EXPECT_EQ(g.blocks.at(0).type, CellType::Line2);
  EXPECT_EQ(g.blocks[0].size(), 2u);
}

TEST(InpReader, ReadMeshDispatchesByExtension) {
  TempDir dir;
  const std::string upper = dir.write("BEAM.INP", "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*ELEMENT, TYPE=B31, ELSET=b\n1, 1, 2\n");
  EXPECT_EQ(cms::mesh::readMesh(upper).group("b").blocks.at(0).type, CellType::Line2);
  expectInputError([&] { cms::mesh::readMesh(upper, {{"h", 0.1}}); }, {upper, "apply to a .geo script only"});
  EXPECT_EQ(cms::mesh::readMesh(kMeshes + "bar_tet10_short.msh").group("blade").blocks.at(0).type, CellType::Tet10);
}

TEST(InpReader, AByteOrderMarkIsSkipped) {
  // Some Windows editors start a UTF-8 file with EF BB BF. It was read as
  // part of the first line ("a data line before any keyword"; in an included
  // data file, node "\xEF\xBB\xBF1" not an integer).
  TempDir dir;
  const std::string bom = "\xEF\xBB\xBF";
  dir.write("nodes.inp", bom + "1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n");
  const Mesh m = readInp(dir.write("deck.inp", bom + "*HEADING\n*NODE, INPUT=nodes.inp\n*ELEMENT, TYPE=C3D4, ELSET=t\n1, 1, 2, 3, 4\n"));
  EXPECT_EQ(m.nodeCount(), 4u);
  EXPECT_EQ(m.group("t").blocks.at(0).size(), 1u);
}

TEST(InpReader, MalformedDecksNameFileLineAndWhat) {
  TempDir dir;
  int n = 0;
  auto refused = [&](const std::string& deck, std::initializer_list<std::string> parts) {
    const std::string path = dir.write("bad" + std::to_string(++n) + ".inp", deck);
    std::vector<std::string> all{path};
    all.insert(all.end(), parts.begin(), parts.end());
    try {
      readInp(path);
      ADD_FAILURE() << "accepted:\n" << deck;
    } catch (const cms::InputError& e) {
      const std::string what = e.what();
      for (const std::string& p : all) EXPECT_NE(what.find(p), std::string::npos) << "\"" << what << "\" lacks \"" << p << "\"";
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an InputError: " << e.what();
    }
  };
  const std::string nodes = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n";
  refused(nodes + "*ELEMENT, TYPE=C3D4, ELSET=t\n1, 1, 2, 3, 9\n", {":7: element 1 refers to node 9, which is not defined"});
  refused(nodes + "*ELEMENT, TYPE=S4R, ELSET=s\n1, 1, 2, 3, 4\n",
          {":6: element type S4R is not supported (supported: C3D4, C3D8, C3D8R, C3D8I, C3D10, C3D20, C3D20R, C3D15, B31)"});
  refused(nodes + "*ELEMENT, ELSET=s\n1, 1, 2, 3, 4\n", {":6: *ELEMENT needs TYPE="});
  refused(nodes + "*ELEMENT, TYPE=C3D4, ELSET=t\n1, 1, 2, 3\n", {":7: element 1 has 3 nodes; C3D4 has 4"});
  refused(nodes + "*ELEMENT, TYPE=C3D4, ELSET=t\n1, 1, 2, 3, 4, 1\n", {":7: element 1 has 5 nodes; C3D4 has 4"});
  // A short line goes on onto the next (CalculiX's rule): a line short by
  // mistake runs into the next element, and the message says so.
  refused(nodes + "*ELEMENT, TYPE=C3D4, ELSET=t\n1, 1, 2, 3\n2, 1, 2, 3, 4\n",
          {":7: element 1 has 8 nodes on 2 lines (a line short of the type's nodes goes on onto the next); C3D4 has 4"});
  refused("*NODE\n1, 0, 0, 1.5+\n", {":2: coordinate z of node 1 \"1.5+\" is not a number"});
  refused("*NODE\n1, 0, 0, 1.5+3+4\n", {":2: coordinate z of node 1 \"1.5+3+4\" is not a number"});
  refused(nodes + "*NODE\n3, 5, 5, 5\n", {":7: node 3 is defined twice (first at", ":4)"});
  refused(nodes + "*ELEMENT, TYPE=C3D4, ELSET=t\n1, 1, 2, 3, 4\n1, 4, 3, 2, 1\n", {":8: element 1 is defined twice"});
  refused("*NODE\n1, 0, 0, 1.2.3\n", {":2: coordinate z of node 1 \"1.2.3\" is not a number"});
  refused("*NODE\n1, 0, 0, 1e999\n", {":2: coordinate z of node 1 1e999 is not finite"});
  refused("*NODE\n1, 0, nan, 0\n", {":2: coordinate y of node 1 \"nan\" is not a number"});
  refused("*NODE\n1x, 0, 0, 0\n", {":2: node \"1x\" is not an integer id"});
  refused("*NODE\n0, 0, 0, 0\n", {":2: node 0 is out of range (ids are 1 to 2147483647)"});
  refused("*NODE\n99999999999, 0, 0, 0\n", {":2: node 99999999999 is out of range"});
  refused("*NODE\n1\n", {":2: node 1 has no coordinates"});
  refused(nodes + "*NSET, NSET=g, GENERATE\n1, 4, 0\n", {":7: *NSET NSET=g, GENERATE: the step is 0; it must be positive"});
  // A keyword line ending in a comma continues onto the next line, which
  // must hold parameters: data or a keyword there was taken as parameters
  // and ignored with a note, so the set lost its members (found by a review:
  // "*NSET, NSET=fix," then "1, 2, 3, 4" then "5, 6" made fix = {5, 6}).
  refused(nodes + "*NSET, NSET=fix,\n1, 2, 3, 4\n",
          {":6: *NSET: \"1\" is not a parameter name", "ends with a comma", "continues onto the next line"});
  refused(nodes + "*ELSET, ELSET=a,\n*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n",
          {":6: *ELSET: \"*ELEMENT\" is not a parameter name"});
  refused(nodes + "*NSET, NSET=g, GENERATE\n4, 1\n", {":7: *NSET NSET=g, GENERATE: the first id 4 is above the last 1"});
  refused(nodes + "*NSET, NSET=g, GENERATE\n10, 20\n", {":7: *NSET NSET=g, GENERATE 10, 20, 1: no node of that range is defined"});
  refused(nodes + "*NSET, NSET=g, GENERATE\n1, 2, 3, 4\n", {":7: *NSET NSET=g, GENERATE: a line is first, last[, step]"});
  refused(nodes + "*NSET, NSET=g\n1, 7\n", {":7: *NSET NSET=g: node 7 is not defined"});
  refused(nodes + "*NSET, NSET=g\n1, later\n*NSET, NSET=later\n2\n",
          {":7: *NSET NSET=g: \"later\" is neither a node id nor a node set defined above"});
  refused(nodes + "*NSET, NSET=g, ELSET=none\n", {":6: *NSET, ELSET=none: no element set of that name is defined above"});
  refused(nodes + "*NSET\n1\n", {":6: *NSET: NSET= names no set"});
  refused("1, 0, 0, 0\n*NODE\n", {":1: a data line before any keyword"});
  refused(nodes + "*NGEN, NSET=x\n1, 4\n", {":6: *NGEN is not supported"});
  // Constraints between nodes change the structure: refused, not skipped
  // with a note (found by a review).
  for (const char* k : {"*TIE, NAME=t\ns1, s2\n", "*EQUATION\n2\n1, 1, 1., 2, 1, -1.\n", "*MPC\nBEAM, 1, 2\n",
                        "*RIGID BODY, NSET=n, REF NODE=1\n", "*COUPLING, REF NODE=1, SURFACE=s\n*KINEMATIC\n",
                        "*SPRING, ELSET=s\n\n1.e4\n"}) {
    const std::string name = std::string(k).substr(1, std::string(k).find_first_of(",\n") - 1);
    refused(nodes + k, {":6: *" + name + " is not supported: it joins or constrains nodes"});
  }
  // A flag no keyword here knows (a set name on the line after a keyword
  // line ending with a comma; a misspelt GENERATE) is refused, not noted.
  refused(nodes + "*ELEMENT, TYPE=C3D4, ELSET=t\n1, 1, 2, 3, 4\n*NSET, NSET=ROOT,\nR2\n",
          {":8: *NSET: \"R2\" is not a parameter of *NSET", "remove the comma"});
  refused(nodes + "*ELEMENT, TYPE=C3D4, ELSET=t\n1, 1, 2, 3, 4\n*NSET, NSET=a, GENERAT\n1, 4, 1\n",
          {":8: *NSET: \"GENERAT\" is not a parameter"});
  refused("*PART, NAME=p\n" + nodes, {":1: *PART is not supported"});
  refused("*NODE, SYSTEM=C\n1, 1, 0, 0\n", {":1: *NODE, SYSTEM=C: only rectangular coordinates"});
  refused("*HEADING\nonly a title\n", {"no nodes"});
  refused(nodes, {"no node or element sets"});
  refused(nodes + "*INCLUDE\n", {":6: *INCLUDE: INPUT= names no file"});
  refused(nodes + "*NSET, NSET=a, NSET=b\n1\n", {":6: *NSET: parameter NSET given twice"});
}

TEST(InpReader, ANodeSetAndAnElementSetSpelledDifferentlyAreOneName) {
  // Abaqus and CalculiX read set names in any case: *NSET, NSET=ROOT and
  // *ELSET, ELSET=Root are one name, and a support on "Root" (or "root")
  // is the node set's. Before, names were compared as spelled: "Root"
  // found the element set only, and the support clamped its 8 nodes
  // instead of the node set's 4 (found by a review).
  TempDir dir;
  std::string deck = kTwoBricks;
  deck += "*ELSET, ELSET=Root\n 7\n";
  deck.replace(deck.find("*NSET, NSET=root"), 16, "*NSET, NSET=ROOT");
  const Mesh m = readInp(dir.write("case.inp", deck));
  for (const char* name : {"Root", "root", "ROOT"}) {
    EXPECT_EQ(ids(m, m.nodeSet(name)), (std::vector<std::size_t>{10, 40, 50, 80})) << name;
    EXPECT_TRUE(m.hasGroup(name)) << name;
    EXPECT_EQ(m.group(name).dim, 3) << name << ": the element set serves Element Sets";
  }
  EXPECT_FALSE(m.hasGroup("Roots"));
}
