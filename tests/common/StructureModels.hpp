// Meshes and models built in code for the synthesis validations: a Hex8 box
// (a rigid-ish body when stiff) and straight frame segments with named end
// and middle nodes (hubs and booms).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "cms/fem/FiniteElementModel.hpp"
#include "cms/fem/Mesh.hpp"

namespace cms::fixtures {

inline void addPointGroup(fem::Mesh& mesh, const std::string& name, const std::vector<std::int64_t>& nodes) {
  fem::PhysicalGroup g{name, 0, static_cast<int>(mesh.groups.size()) + 1, {}};
  fem::CellBlock b;
  b.type = fem::CellType::Point1;
  b.gmshType = 15;
  b.nodesPerCell = 1;
  for (auto n : nodes) {
    b.nodes.push_back(n);
    b.cellTags.push_back(100000 + static_cast<std::size_t>(n));
  }
  g.blocks.push_back(b);
  mesh.groups.push_back(g);
}

/// [-a/2, a/2] x [-b/2, b/2] x [-c/2, c/2] (moved to `centre`) in
/// nx x ny x nz Hex8 cells (even counts): groups "solid", "center" (the
/// centre node), "reference" (the centre and its neighbours along +x and +y:
/// three non-collinear nodes), "corner" (the node at +a/2, +b/2, +c/2), and
/// the end faces "xmin" and "xmax".
inline std::shared_ptr<fem::Mesh> boxMesh(double a, double b, double c, std::array<int, 3> n,
                                          const std::array<double, 3>& centre = {0.0, 0.0, 0.0}) {
  auto mesh = std::make_shared<fem::Mesh>();
  mesh->source = "box mesh (in code)";
  const auto [nx, ny, nz] = n;
  auto id = [&](int i, int j, int k) { return static_cast<std::int64_t>(i + (nx + 1) * (j + (ny + 1) * k)); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        mesh->nodeTags.push_back(static_cast<std::size_t>(id(i, j, k) + 1));
        mesh->coordinates.insert(mesh->coordinates.end(),
                                 {centre[0] + a * (double(i) / nx - 0.5), centre[1] + b * (double(j) / ny - 0.5),
                                  centre[2] + c * (double(k) / nz - 0.5)});
      }
  fem::PhysicalGroup solid{"solid", 3, 1, {}};
  fem::CellBlock hex;
  hex.type = fem::CellType::Hex8;
  hex.gmshType = 5;
  hex.nodesPerCell = 8;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        hex.nodes.insert(hex.nodes.end(), {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                                           id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1),
                                           id(i, j + 1, k + 1)});
        hex.cellTags.push_back(hex.cellTags.size() + 1);
      }
  solid.blocks.push_back(hex);
  mesh->groups.push_back(solid);
  const int hx = nx / 2, hy = ny / 2, hz = nz / 2;
  addPointGroup(*mesh, "center", {id(hx, hy, hz)});
  addPointGroup(*mesh, "reference", {id(hx, hy, hz), id(hx + 1, hy, hz), id(hx, hy + 1, hz)});
  addPointGroup(*mesh, "corner", {id(nx, ny, nz)});
  std::vector<std::int64_t> xmin, xmax;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j) xmin.push_back(id(0, j, k)), xmax.push_back(id(nx, j, k));
  addPointGroup(*mesh, "xmin", xmin);
  addPointGroup(*mesh, "xmax", xmax);
  return mesh;
}

inline std::shared_ptr<fem::Mesh> boxMesh(double a, double b, double c, int n,
                                          const std::array<double, 3>& centre = {0.0, 0.0, 0.0}) {
  return boxMesh(a, b, c, {n, n, n}, centre);
}

inline fem::FiniteElementModel solidModel(std::shared_ptr<const fem::Mesh> mesh, const fem::IsotropicMaterial& mat) {
  fem::FiniteElementModel m;
  m.name = "solid";
  m.mesh = std::move(mesh);
  m.materials["material"] = mat;
  fem::ElementSet set;
  set.group = "solid";
  set.kind = fem::ElementSet::Kind::Solid;
  set.material = "material";
  m.elementSets.push_back(set);
  return m;
}

/// Frame elements along a straight segment from p0 to p1 (`elements` even):
/// groups "beam", "start", "end", "mid" and "ends".
inline std::shared_ptr<fem::Mesh> segmentMesh(const std::array<double, 3>& p0, const std::array<double, 3>& p1,
                                              int elements, std::size_t firstTag = 1) {
  auto mesh = std::make_shared<fem::Mesh>();
  mesh->source = "segment mesh (in code)";
  for (int i = 0; i <= elements; ++i) {
    const double t = double(i) / elements;
    mesh->nodeTags.push_back(firstTag + static_cast<std::size_t>(i));
    for (int d = 0; d < 3; ++d) mesh->coordinates.push_back(p0[d] + t * (p1[d] - p0[d]));
  }
  fem::PhysicalGroup beam{"beam", 1, 1, {}};
  fem::CellBlock lines;
  lines.type = fem::CellType::Line2;
  lines.gmshType = 1;
  lines.nodesPerCell = 2;
  for (int e = 0; e < elements; ++e) {
    lines.nodes.insert(lines.nodes.end(), {e, e + 1});
    lines.cellTags.push_back(static_cast<std::size_t>(e + 1));
  }
  beam.blocks.push_back(lines);
  mesh->groups.push_back(beam);
  addPointGroup(*mesh, "start", {0});
  addPointGroup(*mesh, "end", {elements});
  addPointGroup(*mesh, "mid", {elements / 2});
  addPointGroup(*mesh, "ends", {0, elements});
  return mesh;
}

}  // namespace cms::fixtures
