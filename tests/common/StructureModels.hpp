// Solid meshes and models built in code for the synthesis validations: a
// Hex8 box (a rigid-ish body when stiff, or half of a split bar). Frame
// segments are in BeamModels.hpp.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "BeamModels.hpp"
#include "cms/fem/FiniteElementModel.hpp"
#include "cms/mesh/Mesh.hpp"

namespace cms::fixtures {

/// [-a/2, a/2] x [-b/2, b/2] x [-c/2, c/2] (moved to `centre`) in
/// nx x ny x nz Hex8 cells (even counts): groups "solid", "center" (the
/// centre node), "reference" (the centre and its neighbours along +x and +y:
/// three non-collinear nodes), "corner" (the node at +a/2, +b/2, +c/2), and
/// the end faces "xmin" and "xmax".
inline std::shared_ptr<mesh::Mesh> boxMesh(double a, double b, double c, std::array<int, 3> n,
                                          const std::array<double, 3>& centre = {0.0, 0.0, 0.0}) {
  auto mesh = std::make_shared<mesh::Mesh>();
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
  mesh::PhysicalGroup solid{"solid", 3, 1, {}};
  mesh::CellBlock hex;
  hex.type = mesh::CellType::Hex8;
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

inline std::shared_ptr<mesh::Mesh> boxMesh(double a, double b, double c, int n,
                                          const std::array<double, 3>& centre = {0.0, 0.0, 0.0}) {
  return boxMesh(a, b, c, {n, n, n}, centre);
}

inline fem::FiniteElementModel solidModel(std::shared_ptr<const mesh::Mesh> mesh, const fem::IsotropicMaterial& mat) {
  fem::ElementSet set;
  set.group = "solid";
  set.kind = fem::ElementSet::Kind::Solid;
  return oneSetModel("solid", std::move(mesh), mat, std::move(set));
}

}  // namespace cms::fixtures
