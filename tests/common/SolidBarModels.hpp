// A solid bar meshed in code, every element family of fem/SolidElement.hpp
// on the same structured grid: the mesh with its groups, and the element set
// that picks the formulation as a scene does. Shared by the element
// convergence test and the Partitioned basis test.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "BeamModels.hpp"
#include "SolidTestMeshes.hpp"
#include "cms/fem/FiniteElementModel.hpp"
#include "cms/mesh/Mesh.hpp"

namespace cms::fixtures {

inline mesh::CellType cellTypeOf(fem::SolidType t, int* gmshType) {
  switch (t) {
    case fem::SolidType::Tet4: *gmshType = 4; return mesh::CellType::Tet4;
    case fem::SolidType::Tet10: *gmshType = 11; return mesh::CellType::Tet10;
    case fem::SolidType::Hex8:
    case fem::SolidType::Hex8Incompatible: *gmshType = 5; return mesh::CellType::Hex8;
    case fem::SolidType::Hex20:
    case fem::SolidType::Hex20Reduced: *gmshType = 17; return mesh::CellType::Hex20;
    case fem::SolidType::Wedge15: *gmshType = 18; return mesh::CellType::Wedge15;
    case fem::SolidType::Hex27: *gmshType = 12; return mesh::CellType::Hex27;
    case fem::SolidType::Hex64: *gmshType = 92; return mesh::CellType::Hex64;
    case fem::SolidType::Hex125: *gmshType = 93; return mesh::CellType::Hex125;
  }
  return mesh::CellType::Other;
}

/// A bar [0, L] x [-b/2, b/2] x [-c/2, c/2] of `type`, nx x ny x nz cells of
/// the hex grid; groups "bar" (the cells), "ends" (x = 0 and x = L), "root"
/// (x = 0), "mid" (x = L / 2, nx even).
inline std::shared_ptr<mesh::Mesh> barMesh(fem::SolidType type, double L, double b, double c, int nx, int ny, int nz) {
  const fixtures::TestMesh m =
      fixtures::fromHexGrid(fixtures::hexGrid(nx, ny, nz, L, b, c, 0.0, -b / 2, -c / 2), type);
  auto mesh = std::make_shared<mesh::Mesh>();
  mesh->source = std::string("bar of ") + fem::solidTypeName(type) + " (in code)";
  std::vector<std::int64_t> ends, root, mid;
  for (int a = 0; a < m.nodes(); ++a) {
    mesh->nodeTags.push_back(static_cast<std::size_t>(a + 1));
    for (int i = 0; i < 3; ++i) mesh->coordinates.push_back(m.xyz[3 * a + i]);
    const double x = m.xyz[3 * a];
    if (x == 0.0 || x == L) ends.push_back(a);
    if (x == 0.0) root.push_back(a);
    if (std::abs(x - L / 2) < 1e-12 * L) mid.push_back(a);
  }
  mesh::PhysicalGroup bar{"bar", 3, 1, {}};
  mesh::CellBlock block;
  block.type = cellTypeOf(type, &block.gmshType);
  block.nodesPerCell = fem::solidNodeCount(type);
  for (std::size_t e = 0; e < m.cells.size(); ++e) {
    block.nodes.insert(block.nodes.end(), m.cells[e].begin(), m.cells[e].end());
    block.cellTags.push_back(e + 1);
  }
  bar.blocks.push_back(block);
  mesh->groups.push_back(bar);
  fixtures::addPointGroup(*mesh, "ends", ends);
  fixtures::addPointGroup(*mesh, "root", root);
  fixtures::addPointGroup(*mesh, "mid", mid);
  return mesh;
}

/// The element set of `type`: its cell shape with the formulation chosen the
/// way a scene chooses it (ElementSet::hex8 / hex20).
inline fem::ElementSet elementSet(fem::SolidType type, const std::string& material) {
  fem::ElementSet s;
  s.group = "bar";
  s.material = material;
  if (type == fem::SolidType::Hex8 || type == fem::SolidType::Hex8Incompatible) s.hex8 = type;
  if (type == fem::SolidType::Hex20 || type == fem::SolidType::Hex20Reduced) s.hex20 = type;
  return s;
}

}  // namespace cms::fixtures
