// The Gmsh reader (through Gmsh's SDK, behind a scan of .msh files): the
// test meshes, the four MSH flavours agreeing, and every rejected input
// named in the message. (The Matrix Market sidecar: tests/unit/fem.)
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <dlfcn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <tuple>
#include <vector>

#include "ExpectError.hpp"
#include "GmshTypes.hpp"
#include "TempFiles.hpp"
#include "cms/core/Error.hpp"
#include "cms/mesh/Mesh.hpp"

namespace fs = std::filesystem;
using namespace cms::fixtures;
using cms::mesh::CellType;
using cms::mesh::Mesh;

namespace {

const std::string kMeshes = std::string(CMS_TEST_DATA_DIR) + "/meshes/";

const cms::mesh::CellBlock& onlyBlock(const Mesh& m, const std::string& group) {
  const auto& g = m.group(group);
  EXPECT_EQ(g.blocks.size(), 1u) << group;
  return g.blocks.at(0);
}

/// Node indices in range, one block per type, sizes consistent.
void expectWellFormed(const Mesh& m) {
  ASSERT_EQ(m.coordinates.size(), 3 * m.nodeCount());
  EXPECT_TRUE(std::is_sorted(m.nodeTags.begin(), m.nodeTags.end()));
  for (const auto& g : m.groups)
    for (const auto& b : g.blocks) {
      EXPECT_EQ(b.nodes.size(), b.size() * static_cast<std::size_t>(b.nodesPerCell));
      if (b.type != CellType::Other) {
        EXPECT_EQ(b.nodesPerCell, cms::mesh::cellNodeCount(b.type));
      }
      for (std::int64_t n : b.nodes) {
        EXPECT_GE(n, 0);
        EXPECT_LT(n, static_cast<std::int64_t>(m.nodeCount()));
      }
    }
}

/// The same groups in the same order, each with the same blocks, cells
/// and node indices.
void expectSameGroups(const Mesh& m, const Mesh& ref) {
  ASSERT_EQ(m.groups.size(), ref.groups.size());
  for (std::size_t g = 0; g < m.groups.size(); ++g) {
    const auto &a = m.groups[g], &b = ref.groups[g];
    SCOPED_TRACE(b.name);
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.dim, b.dim);
    EXPECT_EQ(a.tag, b.tag);
    ASSERT_EQ(a.blocks.size(), b.blocks.size());
    for (std::size_t k = 0; k < a.blocks.size(); ++k) {
      EXPECT_EQ(a.blocks[k].type, b.blocks[k].type);
      EXPECT_EQ(a.blocks[k].gmshType, b.blocks[k].gmshType);
      EXPECT_EQ(a.blocks[k].nodesPerCell, b.blocks[k].nodesPerCell);
      EXPECT_EQ(a.blocks[k].cellTags, b.blocks[k].cellTags);
      EXPECT_EQ(a.blocks[k].nodes, b.blocks[k].nodes);
    }
  }
}

// ---------------------------------------------------------------------------
// The test meshes.
// ---------------------------------------------------------------------------

TEST(MeshReader, BarHexGeo) {
  const Mesh m = cms::mesh::readGmsh(kMeshes + "bar_hex.geo");
  expectWellFormed(m);
  EXPECT_EQ(m.source, kMeshes + "bar_hex.geo");
  EXPECT_EQ(m.nodeCount(), 21u * 3 * 3);  // nx = 20, ns = 2
  const auto& blade = onlyBlock(m, "blade");
  EXPECT_EQ(blade.type, CellType::Hex8);
  EXPECT_EQ(blade.gmshType, 5);
  EXPECT_EQ(blade.size(), 20u * 2 * 2);
  EXPECT_EQ(m.group("blade").dim, 3);
  for (const char* face : {"root", "tip"}) {
    EXPECT_EQ(onlyBlock(m, face).type, CellType::Quad4);
    EXPECT_EQ(onlyBlock(m, face).size(), 4u);
    EXPECT_EQ(m.group(face).dim, 2);
  }
  const auto root = m.nodeSet("root"), tip = m.nodeSet("tip");
  EXPECT_EQ(root.size(), 9u);
  EXPECT_EQ(tip.size(), 9u);
  for (auto n : root) EXPECT_EQ(m.x(n)[0], 0.0);
  // Gmsh computes the nodes from the geometry (L = 1, a = 0.02): to
  // rounding of the coordinate extent L (measured: exact), 4 eps L.
  const double tol = 4 * std::numeric_limits<double>::epsilon() * 1.0;
  for (auto n : tip) EXPECT_NEAR(m.x(n)[0], 1.0, tol);
  for (std::size_t i = 0; i < m.nodeCount(); ++i) {
    EXPECT_LE(std::abs(m.x(i)[1]), 0.01 + tol);
    EXPECT_LE(std::abs(m.x(i)[2]), 0.01 + tol);
  }
  EXPECT_EQ(m.nodeSet("blade").size(), m.nodeCount());
}

TEST(MeshReader, BarTet10Geo) {
  const Mesh m = cms::mesh::readGmsh(kMeshes + "bar_tet10.geo");
  expectWellFormed(m);
  const auto& blade = onlyBlock(m, "blade");
  EXPECT_EQ(blade.type, CellType::Tet10);
  EXPECT_EQ(blade.nodesPerCell, 10);
  EXPECT_GT(blade.size(), 50u);
  EXPECT_LT(m.nodeCount(), 5000u);
  EXPECT_EQ(onlyBlock(m, "root").type, CellType::Tri6);
  EXPECT_EQ(onlyBlock(m, "tip").type, CellType::Tri6);
  for (auto n : m.nodeSet("root")) EXPECT_EQ(m.x(n)[0], 0.0);
  // Tip nodes on the plane x = L = 1, to rounding of the extent L (measured:
  // exact): 4 eps L.
  for (auto n : m.nodeSet("tip")) EXPECT_NEAR(m.x(n)[0], 1.0, 4 * std::numeric_limits<double>::epsilon() * 1.0);
  // Mid-side nodes make a face's node count 2 * corners + edges: more than 4.
  EXPECT_GT(m.nodeSet("root").size(), 4u);
}

TEST(MeshReader, BeamLineGeo) {
  const Mesh m = cms::mesh::readGmsh(kMeshes + "beam_line.geo");
  expectWellFormed(m);
  EXPECT_EQ(m.nodeCount(), 11u);
  const auto& beam = onlyBlock(m, "beam");
  EXPECT_EQ(beam.type, CellType::Line2);
  EXPECT_EQ(beam.size(), 10u);
  EXPECT_EQ(m.group("beam").dim, 1);
  EXPECT_EQ(m.group("root").dim, 0);
  EXPECT_EQ(onlyBlock(m, "root").type, CellType::Point1);
  const auto root = m.nodeSet("root"), tip = m.nodeSet("tip");
  ASSERT_EQ(root.size(), 1u);
  ASSERT_EQ(tip.size(), 1u);
  EXPECT_EQ(m.x(root[0])[0], 0.0);
  EXPECT_EQ(m.x(tip[0])[0], 1.0);
  for (std::size_t i = 0; i < m.nodeCount(); ++i) {
    EXPECT_EQ(m.x(i)[1], 0.0);
    EXPECT_EQ(m.x(i)[2], 0.0);
  }
}

TEST(MeshReader, FourMshFormatsAgree) {
  const char* files[] = {"bar_hex_small_v22_ascii.msh", "bar_hex_small_v22_binary.msh",
                         "bar_hex_small_v41_ascii.msh", "bar_hex_small_v41_binary.msh"};
  const Mesh ref = cms::mesh::readGmsh(kMeshes + files[0]);
  expectWellFormed(ref);
  EXPECT_EQ(ref.nodeCount(), 7u * 3 * 3);  // nx = 6, ns = 2
  EXPECT_EQ(onlyBlock(ref, "blade").size(), 6u * 2 * 2);
  for (auto n : ref.nodeSet("root")) EXPECT_EQ(ref.x(n)[0], 0.0);
  for (const char* f : files) {
    SCOPED_TRACE(f);
    const Mesh m = cms::mesh::readGmsh(kMeshes + f);
    expectWellFormed(m);
    EXPECT_EQ(m.nodeTags, ref.nodeTags);
    ASSERT_EQ(m.coordinates.size(), ref.coordinates.size());
    // ASCII files hold 16 significant digits, binary ones all 17: the same
    // parsed data up to rounding x to 16 digits (5e-16 |x|) and reading it
    // back (eps / 2): relative to each coordinate (measured: 3.3e-16 |x|).
    for (std::size_t i = 0; i < m.coordinates.size(); ++i)
      EXPECT_NEAR(m.coordinates[i], ref.coordinates[i],
                  (5e-16 + std::numeric_limits<double>::epsilon()) * std::abs(ref.coordinates[i]));
    expectSameGroups(m, ref);
  }
}

TEST(MeshReader, ScriptsDoNotInheritEachOthersSettings) {
  TempDir dir("cms_mesh_test");
  // The same parameter name with another default: Gmsh keeps ONELAB
  // parameters across sessions unless they are cleared.
  std::string coarse = slurp(kMeshes + "bar_hex.geo");
  coarse = replaced(coarse, "nx = {20,", "nx = {5,");
  EXPECT_EQ(cms::mesh::readGmsh(kMeshes + "bar_hex.geo").nodeCount(), 21u * 9);
  EXPECT_EQ(cms::mesh::readGmsh(dir.write("coarse.geo", coarse)).nodeCount(), 6u * 9);
  // Mesh.ElementOrder = 2 in bar_tet10.geo must not carry over.
  EXPECT_EQ(onlyBlock(cms::mesh::readGmsh(kMeshes + "bar_tet10.geo"), "blade").type, CellType::Tet10);
  const std::string linear = dir.write(
      "linear.geo", replaced(slurp(kMeshes + "bar_tet10.geo"), "Mesh.ElementOrder = 2;", ""));
  EXPECT_EQ(onlyBlock(cms::mesh::readGmsh(linear), "blade").type, CellType::Tet4);
}

// A mesh parameter the script does not name was ignored: "Mesh Parameters:
// {hh: 0.01}" meshed at the script's default size, silently (found by a
// review). Refused, listing the names the script (and what it includes)
// gives as "Parameters/<name>"; a parameter named in an included file is
// one.
TEST(MeshReader, AMeshParameterTheScriptDoesNotNameIsRefused) {
  TempDir dir("cms_mesh_test");
  const std::string geo = kMeshes + "bar_hex.geo";
  EXPECT_EQ(cms::mesh::readGmsh(geo, {{"nx", 5}}).nodeCount(), 6u * 9);
  expectInputErrorWith([&] { cms::mesh::readGmsh(geo, {{"nxx", 5}}); },
                       {geo, "mesh parameter \"nxx\"", "\"Parameters/nx\""});
  const std::string inner = dir.write("inner.geo", slurp(geo));
  const std::string outer = dir.write("outer.geo", "Include \"inner.geo\";\n");
  EXPECT_EQ(cms::mesh::readGmsh(outer, {{"nx", 5}}).nodeCount(), 6u * 9);
  expectInputErrorWith([&] { cms::mesh::readGmsh(outer, {{"nxx", 5}}); }, {outer, "mesh parameter \"nxx\""});
  (void)inner;
}

TEST(MeshReader, CellNamesAndCounts) {
  EXPECT_STREQ(cms::mesh::cellTypeName(CellType::Tet10), "Tet10");
  EXPECT_STREQ(cms::mesh::cellTypeName(CellType::Other), "Other");
  EXPECT_EQ(cms::mesh::cellNodeCount(CellType::Hex8), 8);
  EXPECT_EQ(cms::mesh::cellNodeCount(CellType::Point1), 1);
  EXPECT_EQ(cms::mesh::cellNodeCount(CellType::Other), 0);
}

TEST(MeshReader, OtherCellTypesAreKeptWithTheirGmshType) {
  TempDir dir("cms_mesh_test");
  const std::string geo = dir.write("prism.geo",
                                    "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {0, 1, 0};\n"
                                    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};\n"
                                    "Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};\n"
                                    "Transfinite Curve{1, 2, 3} = 2; Transfinite Surface{1};\n"
                                    "v[] = Extrude {0, 0, 1} { Surface{1}; Layers{1}; Recombine; };\n"
                                    "Physical Volume(\"wedge\") = {v[1]};\n");
  const Mesh m = cms::mesh::readGmsh(geo);
  const auto& b = onlyBlock(m, "wedge");
  EXPECT_EQ(b.type, CellType::Other);
  EXPECT_EQ(b.gmshType, 6);  // 6-node prism
  EXPECT_EQ(b.nodesPerCell, 6);
  EXPECT_EQ(b.size(), 1u);
}

// Lagrange hexahedra of order 2, 3, 4 (Gmsh 12, 92, 93): the reader puts
// Gmsh's node order (corners, edges, faces, interior) into lexicographic
// order of the reference grid (Mesh.hpp), which SolidElement.cpp's shape
// functions assume. On a transfinite mesh of a parallelepiped every cell is
// affine, so node (i, j, l) must sit at c000 + (i/k) e1 + (j/k) e2 + (l/k)
// e3 with e1, e2, e3 the edges from the cell's first corner to the nodes
// (k,0,0), (0,k,0), (0,0,k), and (e1 x e2) . e3 > 0 (positively oriented, as
// Gmsh's hexahedra are). A node out of place is off by at least 1/(2k) of a
// cell edge (0.06 of the mesh's extent here). Gmsh places the extruded
// and transfinite nodes through its geometry, not by one interpolation:
// measured up to 3.4e-12 off the affine position, 1.7e-12 of the extent
// (1.5e4 eps; the same from both readers, which read Gmsh's coordinates
// as written, so no BLAS or CPU enters). Bound: 1e-10 of the extent (the
// bounding box's largest side, from the mesh), 30x the measured value and
// 6e8 below a misplaced node.
TEST(MeshReader, LagrangeHexahedraArriveInLexicographicOrder) {
  TempDir dir("cms_mesh_test");
  for (const auto& [order, type, gmshType] : {std::tuple{2, CellType::Hex27, 12}, std::tuple{3, CellType::Hex64, 92},
                                               std::tuple{4, CellType::Hex125, 93}}) {
    SCOPED_TRACE(order);
    const std::string geo = dir.write(
        "lagrange" + std::to_string(order) + ".geo",
        "Point(1) = {0, 0, 0}; Point(2) = {1, 0.2, 0.1}; Point(3) = {1.3, 1.2, 0.3}; Point(4) = {0.3, 1, 0.2};\n"
        "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
        "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
        "Transfinite Curve{1, 2, 3, 4} = 3; Transfinite Surface{1}; Recombine Surface{1};\n"
        "v[] = Extrude {0.1, 0.25, 1.2} { Surface{1}; Layers{2}; Recombine; };\n"
        "Physical Volume(\"solid\") = {v[1]}; Physical Surface(\"base\") = {1};\n"
        "Mesh.ElementOrder = " + std::to_string(order) + "; Mesh.SecondOrderIncomplete = 0;\n");
    const Mesh m = cms::mesh::readGmsh(geo);
    expectWellFormed(m);
    const auto& b = onlyBlock(m, "solid");
    ASSERT_EQ(b.type, type);
    EXPECT_EQ(b.gmshType, gmshType);
    ASSERT_EQ(b.nodesPerCell, (order + 1) * (order + 1) * (order + 1));
    ASSERT_EQ(b.size(), 8u);
    const int k = order, n1 = k + 1;
    double extent = 0.0;
    for (int d = 0; d < 3; ++d) {
      double lo = m.coordinates[d], hi = lo;
      for (std::size_t a = 0; a < m.nodeCount(); ++a)
        lo = std::min(lo, m.coordinates[3 * a + d]), hi = std::max(hi, m.coordinates[3 * a + d]);
      extent = std::max(extent, hi - lo);
    }
    ASSERT_GT(extent, 1.0);
    for (std::size_t c = 0; c < b.size(); ++c) {
      const std::int64_t* cell = &b.nodes[c * b.nodesPerCell];
      const double* x0 = m.x(cell[0]);
      double e[3][3];
      const int ends[3] = {k, k * n1, k * n1 * n1};
      for (int d = 0; d < 3; ++d)
        for (int i = 0; i < 3; ++i) e[d][i] = m.x(cell[ends[d]])[i] - x0[i];
      const double triple = (e[0][1] * e[1][2] - e[0][2] * e[1][1]) * e[2][0] +
                            (e[0][2] * e[1][0] - e[0][0] * e[1][2]) * e[2][1] +
                            (e[0][0] * e[1][1] - e[0][1] * e[1][0]) * e[2][2];
      EXPECT_GT(triple, 0.0) << "cell " << b.cellTags[c];
      for (int l = 0; l <= k; ++l)
        for (int j = 0; j <= k; ++j)
          for (int i = 0; i <= k; ++i) {
            const double* x = m.x(cell[i + n1 * (j + n1 * l)]);
            for (int d = 0; d < 3; ++d)
              ASSERT_NEAR(x[d], x0[d] + (i * e[0][d] + j * e[1][d] + l * e[2][d]) / k, 1e-10 * extent)
                  << "cell " << b.cellTags[c] << " node (" << i << ", " << j << ", " << l << ")";
          }
    }
    // The base's cubic and quartic quadrangles (Gmsh 36, 37) pass the .msh
    // scan and make a node set like any other cells.
    EXPECT_EQ(m.group("base").blocks.at(0).nodesPerCell, n1 * n1);
  }
}

// MSH 4.1 files are read without Gmsh (MshReader.cpp); CMS_MSH_READER=gmsh
// sends them to Gmsh's SDK as before. Both must give the same Mesh, bit for
// bit: nodes, coordinates, groups in order, each group's blocks, cells and
// node indices (the Lagrange bricks' reorder included: the native reader's
// table of Gmsh's node order against Gmsh's own reference coordinates). On
// the test meshes in ASCII and binary, the .geo scripts (meshed to MSH 4.1
// by the mesher), and the Lagrange bricks of order 2, 3 and 4 (one cell
// distorted, so that no two nodes share a position by symmetry).
TEST(MeshReader, NativeAndGmshReadersAgree) {
  TempDir dir("cms_mesh_test");
  std::vector<std::string> files = {kMeshes + "bar_hex_small_v41_ascii.msh", kMeshes + "bar_hex_small_v41_binary.msh",
                                    kMeshes + "bar_hex.geo", kMeshes + "bar_tet10.geo", kMeshes + "beam_line.geo"};
  for (int order : {2, 3, 4})
    files.push_back(dir.write(
        "lagrange" + std::to_string(order) + ".geo",
        "Point(1) = {0, 0, 0}; Point(2) = {1, 0.2, 0.1}; Point(3) = {1.4, 1.1, 0.3}; Point(4) = {0.3, 1, 0.2};\n"
        "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
        "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
        "Transfinite Curve{1, 2, 3, 4} = 2; Transfinite Surface{1}; Recombine Surface{1};\n"
        "v[] = Extrude {0.1, 0.25, 1.2} { Surface{1}; Layers{2}; Recombine; };\n"
        "Physical Volume(\"solid\") = {v[1]}; Physical Surface(\"base\") = {1}; Physical Surface(7) = {v[0]};\n"
        "Mesh.ElementOrder = " + std::to_string(order) + "; Mesh.SecondOrderIncomplete = 0;\n"));
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    ASSERT_EQ(::unsetenv("CMS_MSH_READER"), 0);
    const Mesh native = cms::mesh::readGmsh(file);
    ASSERT_EQ(::setenv("CMS_MSH_READER", "gmsh", 1), 0);
    const Mesh gmsh = cms::mesh::readGmsh(file);
    ASSERT_EQ(::unsetenv("CMS_MSH_READER"), 0);
    EXPECT_EQ(native.source, gmsh.source);
    EXPECT_EQ(native.nodeTags, gmsh.nodeTags);
    EXPECT_EQ(native.coordinates, gmsh.coordinates);
    expectSameGroups(native, gmsh);
  }
  ::setenv("CMS_MSH_READER", "neither", 1);
  expectInputErrorWith([&] { cms::mesh::readGmsh(files[0]); }, {"CMS_MSH_READER", "\"neither\"", "\"cms\" or \"gmsh\""});
  ::unsetenv("CMS_MSH_READER");
}

// ---------------------------------------------------------------------------
// Rejected meshes: each message names the file and the line, node or group.
// ---------------------------------------------------------------------------

// Two points and a curve: nodes 1 (x = 0), 2 (x = 1), 3 (x = 0.5); a point
// element at node 1, two line elements.
const std::string kLine41 = R"($MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
0 2 "root"
1 1 "beam"
$EndPhysicalNames
$Entities
2 1 0 0
1 0 0 0 1 2
2 1 0 0 0
1 0 0 0 1 0 0 1 1 2 1 -2
$EndEntities
$Nodes
3 3 1 3
0 1 0 1
1
0 0 0
0 2 0 1
2
1 0 0
1 1 0 1
3
0.5 0 0
$EndNodes
$Elements
2 3 1 3
0 1 15 1
1 1
1 1 1 2
2 1 3
3 3 2
$EndElements
)";

TEST(MeshReaderErrors, HandWrittenMeshReads) {
  TempDir dir("cms_mesh_test");
  const Mesh m = cms::mesh::readGmsh(dir.write("line.msh", kLine41));
  expectWellFormed(m);
  EXPECT_EQ(m.nodeCount(), 3u);
  EXPECT_EQ(m.nodeSet("beam").size(), 3u);
  ASSERT_EQ(m.nodeSet("root").size(), 1u);
  EXPECT_EQ(m.x(m.nodeSet("root")[0])[0], 0.0);
}

TEST(MeshReaderErrors, WindowsLineEndingsRead) {
  TempDir dir("cms_mesh_test");
  std::string crlf;
  for (char c : kLine41) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  const Mesh m = cms::mesh::readGmsh(dir.write("crlf.msh", crlf));
  EXPECT_EQ(m.nodeCount(), 3u);
  EXPECT_EQ(m.nodeSet("beam").size(), 3u);
}

TEST(MeshReaderErrors, MissingAndUnrecognisedFiles) {
  TempDir dir("cms_mesh_test");
  const std::string missing = (dir.path() / "nope.msh").string();
  expectInputErrorWith([&] { cms::mesh::readGmsh(missing); }, {missing, "cannot open"});
  const std::string junk = dir.write("junk.msh", "Point(1) = {0, 0, 0};\n");
  expectInputErrorWith([&] { cms::mesh::readGmsh(junk); }, {junk, "not a Gmsh mesh"});
  const std::string version = dir.write("v3.msh", replaced(kLine41, "4.1 0 8", "3.0 0 8"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(version); }, {version + ":2:", "version 3.0"});
  const std::string script = dir.write("broken.geo", "Point(1) = {0, 0, 0};\nLine(1) = {1, ;\n");
  expectInputErrorWith([&] { cms::mesh::readGmsh(script); }, {script + ": ", "rror"});
}

TEST(MeshReaderErrors, EmptyMesh) {
  TempDir dir("cms_mesh_test");
  const std::string msh = dir.write("empty.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
  expectInputErrorWith([&] { cms::mesh::readGmsh(msh); }, {msh, "empty mesh"});
  const std::string geo = dir.write("empty.geo", "// nothing here\n");
  expectInputErrorWith([&] { cms::mesh::readGmsh(geo); }, {geo, "empty mesh"});
}

TEST(MeshReaderErrors, NoPhysicalGroups) {
  TempDir dir("cms_mesh_test");
  const std::string geo = dir.write("bare.geo", "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Line(1) = {1, 2};\n");
  expectInputErrorWith([&] { cms::mesh::readGmsh(geo); }, {geo, "no physical groups"});
}

TEST(MeshReaderErrors, PhysicalGroupWithoutCells) {
  TempDir dir("cms_mesh_test");
  // Group "root" keeps its point entity, but the point element is gone.
  const std::string msh =
      dir.write("nocells.msh", replaced(replaced(kLine41, "0 1 15 1\n1 1\n", ""), "2 3 1 3\n", "1 2 2 3\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(msh); }, {msh, "\"root\"", "has no cells"});
}

TEST(MeshReaderErrors, NonFiniteCoordinate) {
  TempDir dir("cms_mesh_test");
  for (const char* bad : {"nan", "inf", "-1e999"}) {
    const std::string msh = dir.write("nan.msh", replaced(kLine41, "\n3\n0.5 0 0\n", std::string("\n3\n0.5 ") + bad + " 0\n"));
    expectInputErrorWith([&] { cms::mesh::readGmsh(msh); }, {msh, "node 3", "non-finite coordinate y"});
  }
}

TEST(MeshReaderErrors, CoincidentNodes) {
  TempDir dir("cms_mesh_test");
  const std::string msh = dir.write("dup.msh", replaced(kLine41, "\n3\n0.5 0 0\n", "\n3\n1e-12 0 0\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(msh); }, {msh, "nodes 1 and 3 coincide"});
  // Far apart at the 1e-9 scale: distinct.
  const std::string ok = dir.write("ok.msh", replaced(kLine41, "\n3\n0.5 0 0\n", "\n3\n1e-8 0 0\n"));
  EXPECT_EQ(cms::mesh::readGmsh(ok).nodeCount(), 3u);
}

// A chain of line elements through random points, the corners of the unit
// cube (fixing the size, so the tolerance is 1e-9 * sqrt(3)) and a pair of
// points `gap` apart in a random direction, as MSH 2.2 ASCII.
std::string chainWithPair(std::mt19937& rng, double gap) {
  std::uniform_real_distribution<double> u(0.1, 0.9);
  std::normal_distribution<double> g;
  std::vector<std::array<double, 3>> p = {{0, 0, 0}, {1, 1, 1}};
  for (int i = 0; i < 40; ++i) p.push_back({u(rng), u(rng), u(rng)});
  const std::array<double, 3> a = {u(rng), u(rng), u(rng)};
  std::array<double, 3> d = {g(rng), g(rng), g(rng)};
  const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (double& c : d) c *= gap * 1e-9 * std::sqrt(3.0) / len;
  p.insert(p.begin() + 1 + static_cast<long>(rng() % 40), a);
  p.insert(p.begin() + 1 + static_cast<long>(rng() % 40), {a[0] + d[0], a[1] + d[1], a[2] + d[2]});
  char buf[128];
  std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n1 1 \"chain\"\n$EndPhysicalNames\n";
  s += "$Nodes\n" + std::to_string(p.size()) + "\n";
  for (std::size_t i = 0; i < p.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%zu %.17g %.17g %.17g\n", i + 1, p[i][0], p[i][1], p[i][2]);
    s += buf;
  }
  s += "$EndNodes\n$Elements\n" + std::to_string(p.size() - 1) + "\n";
  for (std::size_t i = 1; i < p.size(); ++i) s += std::to_string(i) + " 1 2 1 1 " + std::to_string(i) + " " + std::to_string(i + 1) + "\n";
  return s + "$EndElements\n";
}

TEST(MeshReaderErrors, CoincidentNodesFoundInEveryDirection) {
  TempDir dir("cms_mesh_test");
  std::mt19937 rng(12345);
  for (int trial = 0; trial < 100; ++trial) {
    SCOPED_TRACE(trial);
    const std::string close = dir.write("close.msh", chainWithPair(rng, 0.9));
    expectInputErrorWith([&] { cms::mesh::readGmsh(close); }, {close, "coincide"});
    const std::string apart = dir.write("apart.msh", chainWithPair(rng, 1.1));
    EXPECT_EQ(cms::mesh::readGmsh(apart).nodeCount(), 44u);
  }
}

TEST(MeshReaderErrors, DuplicatePhysicalNames) {
  TempDir dir("cms_mesh_test");
  const std::string msh =
      dir.write("names.msh", replaced(kLine41, "2\n0 2 \"root\"\n1 1 \"beam\"\n", "3\n0 2 \"root\"\n1 1 \"beam\"\n1 5 \"beam\"\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(msh); }, {msh + ":8:", "\"beam\"", "used twice", "tags 1 and 5"});
  // The same name in two dimensions is two groups.
  const std::string ok = dir.write("ok.msh", replaced(kLine41, "0 2 \"root\"", "0 2 \"beam\""));
  const Mesh m = cms::mesh::readGmsh(ok);
  EXPECT_EQ(m.groups.size(), 2u);
}

// One name on groups of two dimensions above 0 (a Physical Curve and a
// Physical Surface "root"): a node set took the first silently, the
// curve's nodes, and a clamped root face was clamped on its perimeter only
// (found by a review: 16.704 Hz for 16.776). Refused, naming both
// dimensions; a name on a point group and one above it (an .inp deck's
// *NSET and *ELSET) stays two sets: the node set is the point group's.
TEST(MeshReaderErrors, ANameOnGroupsOfTwoDimensionsAboveZeroIsRefused) {
  TempDir dir("cms_mesh_test");
  const Mesh line = cms::mesh::readGmsh(dir.write("line.msh", kLine41));
  Mesh m = line;
  m.source = "two.msh";
  cms::mesh::PhysicalGroup curve = m.group("beam");
  curve.name = "root", curve.dim = 1, curve.tag = 7;
  m.groups.push_back(curve);
  cms::mesh::PhysicalGroup surface = curve;
  surface.dim = 2, surface.tag = 9;
  m.groups.push_back(surface);
  expectInputErrorWith([&] { m.nodeSet("root"); }, {"two.msh", "\"root\"", "dimensions 1 and 2", "tags 7 and 9"});
  expectInputErrorWith([&] { m.group("root"); }, {"two.msh", "\"root\"", "dimensions 1 and 2"});
  m.groups.pop_back();  // the point "root" and the curve "root": two sets
  EXPECT_EQ(m.nodeSet("root"), line.nodeSet("root"));
  EXPECT_EQ(m.group("root").dim, 1);
}

// A group without a name is called "dim:tag"; a group named so explicitly
// collides with it. The structure check cannot see this (the name is made
// later), so each reader refuses it, naming both tags: the curve here is in
// groups 1 (named "1:5") and 5 (unnamed). Both readers, the same message.
TEST(MeshReaderErrors, AGeneratedNameThatCollidesIsRefusedByBothReaders) {
  TempDir dir("cms_mesh_test");
  std::string text = replaced(kLine41, "1 1 \"beam\"", "1 1 \"1:5\"");
  text = replaced(text, "1 0 0 0 1 0 0 1 1 2 1 -2", "1 0 0 0 1 0 0 2 1 5 2 1 -2");
  const std::string msh = dir.write("generated.msh", text);
  for (const char* reader : {"cms", "gmsh"}) {
    setenv("CMS_MSH_READER", reader, 1);
    expectInputErrorWith([&] { cms::mesh::readGmsh(msh); },
                         {msh, "\"1:5\"", "dimension 1", "used by two groups", "tags 1 and 5"});
  }
  unsetenv("CMS_MSH_READER");
  // Named otherwise, the two groups read.
  const std::string ok = dir.write("ok.msh", replaced(text, "1 1 \"1:5\"", "1 1 \"beam\""));
  const Mesh m = cms::mesh::readGmsh(ok);
  EXPECT_EQ(m.groups.size(), 3u);
}

TEST(MeshReaderErrors, UnknownNodeInElement) {
  TempDir dir("cms_mesh_test");
  const std::string msh = dir.write("unknown.msh", replaced(kLine41, "3 3 2\n", "3 3 9\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(msh); }, {msh + ":33:", "element 3", "node 9"});
}

TEST(MeshReaderErrors, DuplicateNodeTag) {
  TempDir dir("cms_mesh_test");
  const std::string msh = dir.write("duptag.msh", replaced(kLine41, "\n3\n0.5 0 0\n", "\n2\n0.5 0 0\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(msh); }, {msh, "node tag 2 appears twice"});
}

TEST(MeshReaderErrors, TruncatedFiles) {
  TempDir dir("cms_mesh_test");
  const std::string ascii = dir.write("cut.msh", kLine41.substr(0, kLine41.find("1 1 0 1\n")));
  expectInputErrorWith([&] { cms::mesh::readGmsh(ascii); }, {ascii + ":23:", "file ends inside $Nodes"});
  for (const char* f : {"bar_hex_small_v41_binary.msh", "bar_hex_small_v22_binary.msh"}) {
    const std::string full = slurp(kMeshes + f);
    const std::string cut = dir.write(std::string("cut_") + f, full.substr(0, full.find("$EndNodes") - 40));
    expectInputErrorWith([&] { cms::mesh::readGmsh(cut); }, {cut + ":", "$Nodes (binary) at byte"});
  }
}

TEST(MeshReaderErrors, HugeCounts) {
  TempDir dir("cms_mesh_test");
  const std::string nodes = dir.write("huge.msh", replaced(kLine41, "3 3 1 3\n", "3 99999999999 1 3\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(nodes); }, {nodes + ":16:", "number of nodes is 99999999999"});
  const std::string names = dir.write("names.msh", replaced(kLine41, "$PhysicalNames\n2\n", "$PhysicalNames\n2147483647\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(names); }, {names + ":5:", "2147483647"});
  const std::string negative = dir.write("neg.msh", replaced(kLine41, "0 1 0 1\n", "0 1 0 -1\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(negative); }, {negative + ":17:", "-1", "out of range"});
  // A 2.2 binary node count beyond the data.
  std::string bin = slurp(kMeshes + "bar_hex_small_v22_binary.msh");
  bin = replaced(bin, "$Nodes\n63\n", "$Nodes\n6300000\n");
  const std::string b = dir.write("huge22.msh", bin);
  expectInputErrorWith([&] { cms::mesh::readGmsh(b); }, {b + ":", "number of nodes is 6300000", "bytes left"});
}

TEST(MeshReaderErrors, UnsupportedSectionsAndTrailingText) {
  TempDir dir("cms_mesh_test");
  const std::string post = dir.write("post.msh", kLine41 + "$NodeData\n1\n\"u\"\n$EndNodeData\n");
  expectInputErrorWith([&] { cms::mesh::readGmsh(post); }, {post + ":35:", "$NodeData", "not supported"});
  const std::string extra = dir.write("extra.msh", replaced(kLine41, "0.5 0 0\n", "0.5 0 0 7\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(extra); }, {extra + ":25:", "unexpected \"7\" after node coordinates"});
  const std::string outside = dir.write("outside.msh", kLine41 + "stray text\n");
  expectInputErrorWith([&] { cms::mesh::readGmsh(outside); }, {outside + ":35:", "outside a section"});
  const std::string tab = dir.write("tab.msh", replaced(kLine41, "0.5 0 0\n", "0.5\t0 0\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(tab); }, {tab + ":25:", "control character 9"});
  const std::string split = dir.write("split.msh", replaced(kLine41, "0.5 0 0\n", "0.5 0\n0\n"));
  expectInputErrorWith([&] { cms::mesh::readGmsh(split); }, {split + ":25:", "line ends before coordinate 3 of node 3"});
  // Comments and other unknown sections are skipped, as Gmsh does.
  const std::string comment = dir.write("comment.msh", kLine41 + "$Comments\nwritten by hand\n$EndComments\n");
  EXPECT_EQ(cms::mesh::readGmsh(comment).nodeCount(), 3u);
}

TEST(MeshReaderErrors, MissingGroupNamesTheAlternatives) {
  const Mesh m = cms::mesh::readGmsh(kMeshes + "beam_line.geo");
  EXPECT_TRUE(m.hasGroup("beam"));
  EXPECT_FALSE(m.hasGroup("hub"));
  expectInputErrorWith([&] { m.group("hub"); }, {"beam_line.geo", "\"hub\"", "\"beam\"", "\"root\"", "\"tip\""});
  expectInputErrorWith([&] { m.nodeSet("hub"); }, {"\"hub\""});
}

// ---------------------------------------------------------------------------
// The .geo mesher helper and the Gmsh reader module, found without a path
// compiled in (Mesh.cpp, libexecFile): $CMS_GEO_MESHER / $CMS_GMSH_READER,
// else <program>/../libexec/cms.
// ---------------------------------------------------------------------------

/// Run only in a copy of this program (GeoMesherLookup.* below): reads a
/// .geo script, and expects the mesher found when CMS_TEST_MESHER is
/// "found", the error naming where it looked when it is "missing", and the
/// error naming the reader module when it is "no reader".
TEST(GeoMesherLookup, DISABLED_InACopyOfThisProgram) {
  const char* expected = std::getenv("CMS_TEST_MESHER");
  ASSERT_NE(expected, nullptr) << "run by GeoMesherLookup.* only";
  const char* tried = std::getenv("CMS_TEST_MESHER_TRIED");
  if (std::string(expected) == "found") {
    EXPECT_EQ(cms::mesh::readGmsh(kMeshes + "bar_hex.geo").nodeCount(), 21u * 9);
  } else if (std::string(expected) == "no reader") {
    // MSH 2.2: read by Gmsh (MSH 4.1 is read without it).
    expectInputErrorWith([&] { cms::mesh::readGmsh(kMeshes + "bar_hex_small_v22_ascii.msh"); },
                         {"cannot find the Gmsh reader module cms-gmsh-reader.so, which reads .msh files",
                          tried ? tried : "?", "set CMS_GMSH_READER"});
  } else {
    expectInputErrorWith([&] { cms::mesh::readGmsh(kMeshes + "bar_hex.geo"); },
                         {"cannot find the .geo mesher cms-geo-mesher", tried ? tried : "?", "set CMS_GEO_MESHER"});
  }
}

/// Runs this program's copy `exe` on the test above with `env` added; true when it passed.
bool copyPasses(const fs::path& exe, const std::string& env) {
  const std::string command = "env -u CMS_GEO_MESHER -u CMS_GMSH_READER " + env + " '" + exe.string() +
                              "' --gtest_also_run_disabled_tests"
                              " --gtest_filter=GeoMesherLookup.DISABLED_InACopyOfThisProgram";
  return std::system(command.c_str()) == 0;
}

TEST(GeoMesherLookup, FoundInLibexecAboveTheProgramNotInTheBuildTree) {
  // A copy of this program in <tmp>/bin: no path of the build may lead it
  // to the helper; <tmp>/libexec/cms/cms-geo-mesher (the installed layout) does.
  TempDir dir("cms_mesher_lookup");
  fs::create_directories(dir.path() / "bin");
  const fs::path exe = dir.path() / "bin" / "test_mesh_readers";
  fs::copy_file(fs::read_symlink("/proc/self/exe"), exe);
  const fs::path libexec = dir.path() / "libexec" / "cms" / "cms-geo-mesher";
  EXPECT_TRUE(copyPasses(exe, "CMS_TEST_MESHER=missing CMS_TEST_MESHER_TRIED='" + libexec.string() + "'"))
      << "a copy of the program outside the build found the build tree's mesher";
  fs::create_directories(libexec.parent_path());
  fs::create_symlink(CMS_TEST_GEO_MESHER, libexec);
  // The mesher alone: an MSH 2.2 file cannot be read without the reader module.
  const fs::path reader = libexec.parent_path() / "cms-gmsh-reader.so";
  EXPECT_TRUE(copyPasses(exe, "CMS_TEST_MESHER='no reader' CMS_TEST_MESHER_TRIED='" + reader.string() + "'"))
      << "a copy of the program outside the build found the build tree's Gmsh reader module";
  fs::create_symlink(CMS_TEST_GMSH_READER, reader);
  EXPECT_TRUE(copyPasses(exe, "CMS_TEST_MESHER=found")) << "the mesher and reader in " << libexec.parent_path()
                                                        << " were not found";
}

/// Whether this process has libgmsh mapped.
bool gmshMapped() {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line))
    if (line.find("libgmsh") != std::string::npos) return true;
  return false;
}

/// Run only in a fresh process (GmshModule.MappedOnlyForAGmshMesh).
TEST(GmshModule, DISABLED_InAFreshProcess) {
  ASSERT_FALSE(gmshMapped()) << "libgmsh is mapped before any mesh was read: linked into the program?";
  EXPECT_GT(cms::mesh::readMesh(kMeshes + "bar_hex20_small.inp").nodeCount(), 0u);
  EXPECT_FALSE(gmshMapped()) << "reading an .inp deck loaded Gmsh";
  const std::size_t nodes = cms::mesh::readGmsh(kMeshes + "bar_hex_small_v41_binary.msh").nodeCount();
  EXPECT_FALSE(gmshMapped()) << "reading an MSH 4.1 file loaded Gmsh";
  EXPECT_EQ(cms::mesh::readGmsh(kMeshes + "bar_hex_small_v22_ascii.msh").nodeCount(), nodes);
  EXPECT_TRUE(gmshMapped()) << "an MSH 2.2 file was read without the Gmsh reader module";
}

TEST(GmshModule, MappedOnlyForAGmshMesh) {
  // A run without a Gmsh mesh never maps libgmsh and OpenCASCADE (~40 MiB
  // resident, doc/benchmarks.md): checked in a fresh copy of this process.
  const std::string command = "'" + fs::read_symlink("/proc/self/exe").string() +
                              "' --gtest_also_run_disabled_tests --gtest_filter=GmshModule.DISABLED_InAFreshProcess";
  EXPECT_EQ(std::system(command.c_str()), 0);
}

/// Run only in a fresh process with CMS_GMSH_READER set
/// (GmshModule.ABadOverrideIsNamed): the module is loaded once per process.
/// CMS_TEST_READER_ERROR is the text the error must hold.
TEST(GmshModule, DISABLED_WithABadOverride) {
  const char* expected = std::getenv("CMS_TEST_READER_ERROR");
  ASSERT_NE(expected, nullptr) << "run by GmshModule.ABadOverrideIsNamed only";
  expectInputErrorWith([&] { cms::mesh::readGmsh(kMeshes + "bar_hex_small_v22_ascii.msh"); }, {expected});
}

TEST(GmshModule, ABadOverrideIsNamed) {
  // Each of Mesh.cpp's refusals of a module: no such file, a file that is no
  // shared library (dlopen fails), a library without the entry point (dlsym).
  auto refused = [](const std::string& reader, const std::string& error) {
    const std::string command = "env CMS_GMSH_READER='" + reader + "' CMS_TEST_READER_ERROR='" + error + "' '" +
                                fs::read_symlink("/proc/self/exe").string() +
                                "' --gtest_also_run_disabled_tests --gtest_filter=GmshModule.DISABLED_WithABadOverride";
    return std::system(command.c_str()) == 0;
  };
  EXPECT_TRUE(refused("/nonexistent/cms-gmsh-reader.so",
                      "CMS_GMSH_READER = /nonexistent/cms-gmsh-reader.so is not a readable file"));
  const std::string notALibrary = kMeshes + "bar_hex_small_v22_ascii.msh";
  EXPECT_TRUE(refused(notALibrary, "cannot load the Gmsh reader module " + notALibrary));
  // A shared library of this machine's that has no cms_gmsh_read_msh: the C library.
  Dl_info libc{};
  ASSERT_NE(dladdr(reinterpret_cast<void*>(&std::malloc), &libc), 0);
  EXPECT_TRUE(refused(libc.dli_fname, "has no cms_gmsh_read_msh"));
}

TEST(GeoMesherLookup, ABadOverrideIsNamed) {
  // In a child: this process's mesher may be running already (started once).
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setenv("CMS_GEO_MESHER", "/nonexistent/cms-geo-mesher", 1);
    try {
      cms::mesh::readGmsh(kMeshes + "bar_hex.geo");
    } catch (const cms::InputError& e) {
      const std::string what = e.what();
      _exit(what.find("CMS_GEO_MESHER = /nonexistent/cms-geo-mesher is not an executable file") != std::string::npos
                ? 0 : 2);
    } catch (...) {
      _exit(3);
    }
    _exit(4);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "2: the message does not name the variable and its value; 3: not an "
                                       "InputError; 4: no error";
}

}  // namespace

// The module reads Gmsh's own description of its Lagrange bricks (types 12,
// 92, 93: getElementProperties) to put their nodes in cms's order. Fed the
// descriptions a Gmsh with another numbering would give, it must refuse
// naming the type, never return a scrambled order: wrong order, node count
// or dimension; a node off the equispaced grid (or not a number); a grid
// point twice. The right description gives a permutation that maps Gmsh's
// corners to cms's (lexicographic: node i + 3 (j + 3 l) for Hex27).
TEST(MeshReader, GmshsLagrangeBrickDescriptionsAreCheckedBeforeUse) {
  using cms::mesh::detail::lexicographicFromReference;
  // Hex27's 27 nodes on [-1, 1]^3, listed in a scrambled order (node g at
  // grid point (7 g) mod 27, a permutation since 7 and 27 are coprime).
  std::vector<double> ref;
  for (int g = 0; g < 27; ++g) {
    const int p = (7 * g) % 27;
    ref.insert(ref.end(), {static_cast<double>(p % 3) - 1.0, static_cast<double>((p / 3) % 3) - 1.0,
                           static_cast<double>(p / 9) - 1.0});
  }
  const auto to = lexicographicFromReference(12, CellType::Hex27, "Hexahedron 27", 3, 2, 27, ref);
  ASSERT_EQ(to.size(), 27u);
  for (int g = 0; g < 27; ++g) EXPECT_EQ(to[g], (7 * g) % 27) << "node " << g;

  auto refused = [&](int order, int count, int dim, const std::vector<double>& r, const std::string& part) {
    expectInputError([&] { lexicographicFromReference(12, CellType::Hex27, "Hexahedron 27", dim, order, count, r); },
                     part);
  };
  refused(3, 27, 3, ref, "element type 12");                   // order
  refused(2, 26, 3, std::vector<double>(ref.begin(), ref.end() - 3), "27-node Lagrange hexahedron");  // count
  refused(2, 27, 2, ref, "element type 12");                   // dimension
  auto off = ref;
  off[3 * 5 + 1] = 0.3;  // between grid points
  refused(2, 27, 3, off, "not on the equispaced grid");
  off = ref;
  off[3 * 5 + 2] = std::numeric_limits<double>::quiet_NaN();
  refused(2, 27, 3, off, "not on the equispaced grid");
  off = ref;
  off[3 * 5 + 0] = 3.0;  // beyond the cube
  refused(2, 27, 3, off, "not on the equispaced grid");
  auto twice = ref;
  std::copy_n(&ref[0], 3, &twice[3 * 5]);  // node 5 at node 0's point
  refused(2, 27, 3, twice, "repeat a grid point");
  // Hex64 and Hex125 take their own orders.
  expectInputError([&] { lexicographicFromReference(92, CellType::Hex64, "Hexahedron 64", 3, 2, 27, ref); },
                   "64-node Lagrange hexahedron");
  expectInputError([&] { lexicographicFromReference(93, CellType::Hex125, "Hexahedron 125", 3, 4, 27, ref); },
                   "125-node Lagrange hexahedron");
}
