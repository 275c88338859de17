// Straight frame models built in code (no mesh file): a line of 2-node frame
// elements along +x with physical groups "beam" (the elements), "root"
// (node at x = 0), "tip" (node at x = L) and "ends" (both). Used by the
// rotating-blade and spinning-shaft validations and the assembly tests.
#pragma once

#include <memory>
#include <string>

#include "cms/fem/FiniteElementModel.hpp"
#include "cms/fem/Mesh.hpp"

namespace cms::fixtures {

inline std::shared_ptr<fem::Mesh> lineMesh(double length, int elements) {
  auto mesh = std::make_shared<fem::Mesh>();
  mesh->source = "line mesh (in code)";
  for (int i = 0; i <= elements; ++i) {
    mesh->nodeTags.push_back(static_cast<std::size_t>(i + 1));
    mesh->coordinates.insert(mesh->coordinates.end(), {length * i / elements, 0.0, 0.0});
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
  auto points = [&](const std::string& name, int tag, std::initializer_list<std::int64_t> nodes) {
    fem::PhysicalGroup g{name, 0, tag, {}};
    fem::CellBlock b;
    b.type = fem::CellType::Point1;
    b.gmshType = 15;
    b.nodesPerCell = 1;
    for (auto n : nodes) {
      b.nodes.push_back(n);
      b.cellTags.push_back(static_cast<std::size_t>(elements + 1 + n));
    }
    g.blocks.push_back(b);
    mesh->groups.push_back(g);
  };
  points("root", 2, {0});
  points("tip", 3, {elements});
  points("ends", 4, {0, elements});
  return mesh;
}

/// A frame model of the line mesh: one material, one section.
inline fem::FiniteElementModel frameModel(std::shared_ptr<const fem::Mesh> mesh, const fem::IsotropicMaterial& mat,
                                          const fem::BeamSection& section,
                                          fem::BeamTheory theory = fem::BeamTheory::EulerBernoulli) {
  fem::FiniteElementModel m;
  m.name = "beam";
  m.mesh = std::move(mesh);
  m.materials["material"] = mat;
  fem::ElementSet set;
  set.group = "beam";
  set.kind = fem::ElementSet::Kind::Frame;
  set.material = "material";
  set.section = section;
  set.theory = theory;
  m.elementSets.push_back(set);
  return m;
}

}  // namespace cms::fixtures
