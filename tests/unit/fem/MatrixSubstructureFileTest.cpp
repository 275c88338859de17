// The Matrix Market sidecar reader and writer (fem/MatrixSubstructureFile.hpp):
// a round trip, comments and optional records, and every malformed record
// named by its line.
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
#include <unistd.h>
#include <vector>

#include "ExpectError.hpp"
#include "TempFiles.hpp"
#include "cms/core/Error.hpp"
#include "cms/fem/MatrixSubstructureFile.hpp"

namespace fs = std::filesystem;
using namespace cms::fixtures;
using cms::fem::Component;

namespace {

cms::fem::MatrixSubstructureFile sample() {
  cms::fem::MatrixSubstructureFile f;
  f.matrices = {{"K", "blade_K.mtx"}, {"M", "blade_M.mtx"}, {"G1", "sub/blade_G1.mtx"}};
  f.hasSpinAxis = true;
  f.spinAxis = {0, 0, 1};
  f.spinOrigin = {-0.1, 1.0 / 3.0, 0};
  f.nodeIds = {12, 13, -7};
  f.coordinates = {0.0, 0.5, 1.0, 0.1, 0.6, 1.0, 1e-300, -2.5e10, 0.7};
  f.components = {{Component::UX, Component::UY, Component::UZ},
                  {Component::UX, Component::UY, Component::UZ, Component::RX, Component::RY, Component::RZ},
                  {Component::RZ, Component::UX}};
  f.nodeSets = {{"root", {12, 13}}, {"tip", {-7}}};
  return f;
}

TEST(Sidecar, RoundTrip) {
  TempDir dir("cms_sidecar_test");
  const auto f = sample();
  const std::string path = (dir.path() / "blade.cms").string();
  cms::fem::writeMatrixSubstructureFile(f, path);
  const auto g = cms::fem::readMatrixSubstructureFile(path);
  EXPECT_EQ(g.path, path);
  EXPECT_EQ(g.units, "SI");
  ASSERT_EQ(g.matrices.size(), 3u);
  EXPECT_EQ(g.matrices.at("K"), (dir.path() / "blade_K.mtx").string());
  EXPECT_EQ(g.matrices.at("G1"), (dir.path() / "sub/blade_G1.mtx").string());
  EXPECT_TRUE(g.hasSpinAxis);
  EXPECT_EQ(g.spinAxis, f.spinAxis);
  EXPECT_EQ(g.spinOrigin, f.spinOrigin);  // exact: written with 17 digits
  EXPECT_EQ(g.nodeIds, f.nodeIds);
  EXPECT_EQ(g.coordinates, f.coordinates);
  EXPECT_EQ(g.components, f.components);
  EXPECT_EQ(g.nodeSets, f.nodeSets);
  EXPECT_EQ(g.dofCount(), 11);
  EXPECT_EQ(g.rowOffsets(), (std::vector<long long>{0, 3, 9, 11}));
  EXPECT_STREQ(cms::fem::componentName(Component::RY), "ry");
}

TEST(Sidecar, CommentsAbsolutePathsAndOptionalRecords) {
  TempDir dir("cms_sidecar_test");
  const std::string p = dir.write("s.cms",
                                  "# header comment\n\n   cms-substructure 1   # trailing comment\n"
                                  "matrix K /abs/K.mtx\r\nmatrix M M.mtx\nset ends 5\nnode 5 0 0 0 uz\n");
  const auto f = cms::fem::readMatrixSubstructureFile(p);
  EXPECT_EQ(f.matrices.at("K"), "/abs/K.mtx");
  EXPECT_EQ(f.matrices.at("M"), (dir.path() / "M.mtx").string());
  EXPECT_FALSE(f.hasSpinAxis);
  EXPECT_EQ(f.units, "SI");
  EXPECT_EQ(f.nodeSets.at("ends"), std::vector<long long>{5});
  EXPECT_EQ(f.dofCount(), 1);
}

TEST(Sidecar, MalformedRecordsNameTheLine) {
  TempDir dir("cms_sidecar_test");
  const std::string head = "cms-substructure 1\nmatrix K K.mtx\nmatrix M M.mtx\n";  // lines 1-3
  const std::string node = "node 12 0 0 0 ux uy uz\n";                                 // line 4
  struct Case {
    std::string text, line, what;
  };
  const Case cases[] = {
      {"substructure 1\n", ":1:", "expected 'cms-substructure 1'"},
      {"# c\ncms-substructure 2\n", ":2:", "version 2 is not supported"},
      {"cms-substructure one\n", ":1:", "version 'one' is not an integer"},
      {"cms-substructure 1 x\n", ":1:", "unexpected 'x'"},
      {head + node + "cms-substructure 1\n", ":5:", "second 'cms-substructure'"},
      {head + node + "nodes 13 0 0 0 ux\n", ":5:", "unknown record 'nodes'"},
      {head + "matrix X X.mtx\n" + node, ":4:", "unknown matrix name 'X'"},
      {head + "matrix K K2.mtx\n" + node, ":4:", "matrix K is given twice (first on line 2)"},
      {head + "matrix G1\n" + node, ":4:", "truncated 'matrix' record"},
      {head + "matrix G1 a b\n" + node, ":4:", "unexpected 'b'"},
      {head + "units SI extra\n" + node, ":4:", "unexpected 'extra'"},
      {head + "units imperial\n" + node, ":4:", "units 'imperial'"},
      {head + "spin-axis 0 0\n" + node, ":4:", "truncated 'spin-axis'"},
      {head + "spin-axis 0 0 0\n" + node, ":4:", "zero vector"},
      {head + "spin-axis 0 0 nan\n" + node, ":4:", "'nan' is not a finite number"},
      {head + "spin-origin 1e999 0 0\n" + node, ":4:", "'1e999' is not a finite number"},
      {head + node + "node 12 1 0 0 ux\n", ":5:", "node 12 is given twice (first on line 4)"},
      {head + "node 12 0 0 0 ux uy ux\n", ":4:", "component ux of node 12 is given twice"},
      {head + "node 12 0 0 0 ux uw\n", ":4:", "unknown component 'uw'"},
      {head + "node 12 0 0\n", ":4:", "truncated 'node' record"},
      {head + "node 12 0 inf 0 ux\n", ":4:", "'inf' is not a finite number"},
      {head + "node 12 0 1.0.0 0 ux\n", ":4:", "'1.0.0' is not a number"},
      {head + "node 12x 0 0 0 ux\n", ":4:", "node id '12x' is not an integer"},
      {head + "node 99999999999999999999 0 0 0 ux\n", ":4:", "out of range"},
      {head + node + "set root 12 13\n", ":5:", "set root names node 13, which has no 'node' record"},
      {head + "set root 12 12\n" + node, ":4:", "set root names node 12 twice"},
      {head + node + "set root\n", ":5:", "set root names no nodes"},
      {head + node + "set root 12\nset root 12\n", ":6:", "set root is given twice"},
      {head + node + "set root 1e3\n", ":5:", "node id '1e3' is not an integer"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const std::string p = dir.write("bad.cms", c.text);
    expectInputErrorWith([&] { cms::fem::readMatrixSubstructureFile(p); }, {p + c.line, c.what});
  }
}

TEST(Sidecar, MissingPieces) {
  TempDir dir("cms_sidecar_test");
  const std::string node = "node 12 0 0 0 ux\n";
  struct Case {
    std::string text, what;
  };
  const Case cases[] = {
      {"", "empty file"},
      {"# only a comment\n", "empty file"},
      {"cms-substructure 1\nmatrix K K.mtx\nmatrix M M.mtx\n", "no 'node' records"},
      {"cms-substructure 1\nmatrix M M.mtx\n" + node, "no stiffness matrix"},
      {"cms-substructure 1\nmatrix K K.mtx\n" + node, "no mass matrix"},
  };
  for (const Case& c : cases) {
    const std::string p = dir.write("bad.cms", c.text);
    expectInputErrorWith([&] { cms::fem::readMatrixSubstructureFile(p); }, {p + ": ", c.what});
  }
  const std::string missing = (dir.path() / "missing.cms").string();
  expectInputErrorWith([&] { cms::fem::readMatrixSubstructureFile(missing); }, {missing, "cannot open"});
}

TEST(Sidecar, WriterRejectsWhatCannotBeReadBack) {
  TempDir dir("cms_sidecar_test");
  const std::string p = (dir.path() / "w.cms").string();
  auto f = sample();
  f.matrices["K"] = "my matrix.mtx";
  expectInputErrorWith([&] { cms::fem::writeMatrixSubstructureFile(f, p); }, {p, "whitespace"});
  f = sample();
  f.nodeSets["a b"] = {12};
  expectInputErrorWith([&] { cms::fem::writeMatrixSubstructureFile(f, p); }, {p, "set name"});
  f = sample();
  f.coordinates[4] = std::nan("");
  expectInputErrorWith([&] { cms::fem::writeMatrixSubstructureFile(f, p); }, {p, "non-finite"});
  f = sample();
  f.matrices["X"] = "x.mtx";
  expectInputErrorWith([&] { cms::fem::writeMatrixSubstructureFile(f, p); }, {p, "unknown matrix name 'X'"});
  const std::string nowhere = (dir.path() / "no/such/dir/w.cms").string();
  expectInputErrorWith([&] { cms::fem::writeMatrixSubstructureFile(sample(), nowhere); }, {nowhere, "cannot open"});
}

}  // namespace
