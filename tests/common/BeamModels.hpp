// Straight frame models built in code (no mesh file): lines of 2-node frame
// elements with physical groups "beam" (the elements), "start", "end",
// "mid", "ends" (and for lineMesh along +x, "root" and "tip"). Used by the
// rotating-blade, spinning-shaft and synthesis validations and the assembly
// tests.
#pragma once

#include <memory>
#include <array>
#include <string>
#include <vector>

#include "cms/fem/FiniteElementModel.hpp"
#include "cms/mesh/Mesh.hpp"

namespace cms::fixtures {

inline void addPointGroup(mesh::Mesh& mesh, const std::string& name, const std::vector<std::int64_t>& nodes) {
  mesh::PhysicalGroup g{name, 0, static_cast<int>(mesh.groups.size()) + 1, {}};
  mesh::CellBlock b;
  b.type = mesh::CellType::Point1;
  b.gmshType = 15;
  b.nodesPerCell = 1;
  for (auto n : nodes) {
    b.nodes.push_back(n);
    b.cellTags.push_back(100000 + static_cast<std::size_t>(n));
  }
  g.blocks.push_back(b);
  mesh.groups.push_back(g);
}

/// Frame elements along a straight segment from p0 to p1 (`elements` even):
/// groups "beam", "start", "end", "mid" and "ends".
inline std::shared_ptr<mesh::Mesh> segmentMesh(const std::array<double, 3>& p0, const std::array<double, 3>& p1,
                                              int elements, std::size_t firstTag = 1) {
  auto mesh = std::make_shared<mesh::Mesh>();
  mesh->source = "segment mesh (in code)";
  for (int i = 0; i <= elements; ++i) {
    const double t = double(i) / elements;
    mesh->nodeTags.push_back(firstTag + static_cast<std::size_t>(i));
    for (int d = 0; d < 3; ++d) mesh->coordinates.push_back(p0[d] + t * (p1[d] - p0[d]));
  }
  mesh::PhysicalGroup beam{"beam", 1, 1, {}};
  mesh::CellBlock lines;
  lines.type = mesh::CellType::Line2;
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

/// The segment from the origin to (length, 0, 0), with the groups above
/// plus "root" (x = 0) and "tip" (x = L).
inline std::shared_ptr<mesh::Mesh> lineMesh(double length, int elements) {
  auto mesh = segmentMesh({0.0, 0.0, 0.0}, {length, 0.0, 0.0}, elements);
  mesh->source = "line mesh (in code)";
  addPointGroup(*mesh, "root", {0});
  addPointGroup(*mesh, "tip", {elements});
  return mesh;
}

/// A beam section: area, second moments about local y and z, torsion
/// constant, and the direction of the local y axis.
inline fem::BeamSection beamSection(double A, double Iy, double Iz, double J, const fem::Vec3& orientation) {
  fem::BeamSection s;
  s.A = A, s.Iy = Iy, s.Iz = Iz, s.J = J;
  s.orientation = orientation;
  return s;
}

/// A model named `name` of one element set (`set`, its material filled in)
/// with one material.
inline fem::FiniteElementModel oneSetModel(const std::string& name, std::shared_ptr<const mesh::Mesh> mesh,
                                           const fem::IsotropicMaterial& mat, fem::ElementSet set) {
  fem::FiniteElementModel m;
  m.name = name;
  m.mesh = std::move(mesh);
  m.materials["material"] = mat;
  set.material = "material";
  m.elementSets.push_back(std::move(set));
  return m;
}

/// A frame model of the line mesh: one material, one section.
inline fem::FiniteElementModel frameModel(std::shared_ptr<const mesh::Mesh> mesh, const fem::IsotropicMaterial& mat,
                                          const fem::BeamSection& section,
                                          fem::BeamTheory theory = fem::BeamTheory::EulerBernoulli) {
  fem::ElementSet set;
  set.group = "beam";
  set.kind = fem::ElementSet::Kind::Frame;
  set.section = section;
  set.theory = theory;
  return oneSetModel("beam", std::move(mesh), mat, std::move(set));
}

}  // namespace cms::fixtures
