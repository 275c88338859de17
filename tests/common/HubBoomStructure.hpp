// The validation structure of doc/theory.md §11.7: a hub (C, a stiff frame
// beam along x from -h to h) carrying two flexible booms (E, frame beams
// from +-h to +-(h + L)), the whole spinning about z through the hub centre.
// Also the same structure as one monolithic frame model (one mesh, the booms'
// roots merged with the hub's ends), for the truth-versus-monolithic check,
// and a dense copy of a distributed matrix for small reference solves.
#pragma once

#include <memory>
#include <string>

#include <Teuchos_Comm.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "BeamModels.hpp"
#include "DenseOf.hpp"
#include "StructureModels.hpp"
#include "cms/core/DenseMatrix.hpp"
#include "cms/core/TpetraTypes.hpp"
#include "cms/synthesis/Structure.hpp"

namespace cms::fixtures {

struct HubBoom {
  double h = 0.5, L = 3.0;
  int hubElements = 4, boomElements = 8;
  fem::IsotropicMaterial hubMaterial{2.0e11, 0.3, 7800.0}, boomMaterial{7.0e10, 0.33, 2700.0};
  fem::BeamSection hubSection{4e-3, 2e-6, 2e-6, 4e-6};
  fem::BeamSection boomSection{2e-4, 3e-9, 6e-9, 5e-9};
  double Omega = 2.0;  ///< rad/s (the first boom frequency is about 4 rad/s)
  double tipMass = 0.0;  ///< kg, a point mass at each boom tip (0: none)

  /// A frame model of a segment mesh, local z along global z.
  fem::FiniteElementModel frame(std::shared_ptr<const mesh::Mesh> mesh, const fem::IsotropicMaterial& mat,
                                fem::BeamSection sec, const std::string& name) const {
    sec.orientation = {0.0, 0.0, 1.0};
    auto m = frameModel(std::move(mesh), mat, sec);
    m.name = name;
    return m;
  }

  /// free: hub free-floating about its centre node; else clamped there.
  synthesis::StructureDescription structure(bool free, const std::string& basis, int vectors) const {
    using namespace synthesis;
    StructureDescription d;
    SubstructureSpec C;
    C.name = "hub";
    C.kind = SubstructureKind::Central;
    auto hub = frame(segmentMesh({-h, 0, 0}, {h, 0, 0}, hubElements), hubMaterial, hubSection, "hub");
    if (!free) hub.fixed.push_back({"centre", "mid", {}, true});
    C.model = std::make_shared<fem::FiniteElementModel>(hub);
    C.spin = SpinRate{{0, 0, 1}, {0, 0, 0}, Omega};
    C.reduction.set("Basis", basis);
    C.reduction.set("Vectors", std::min(vectors, 6));
    d.substructures.push_back(C);
    for (int side : {+1, -1}) {
      SubstructureSpec E;
      E.name = side > 0 ? "boom+" : "boom-";
      E.kind = SubstructureKind::Elastic;
      E.parent = "hub";
      E.attachment.type = Attachment::Type::Node;
      E.attachment.parentNodes = side > 0 ? "end" : "start";
      E.attachment.childNodes = "start";
      E.model = std::make_shared<fem::FiniteElementModel>(
          frame(segmentMesh({side * h, 0, 0}, {side * (h + L), 0, 0}, boomElements, 100), boomMaterial, boomSection,
                E.name));
      if (tipMass > 0) {
        auto withTip = *E.model;
        withTip.pointMasses.push_back({"tip mass", "end", tipMass, {}});
        E.model = std::make_shared<fem::FiniteElementModel>(withTip);
      }
      E.reduction.set("Basis", basis);
      E.reduction.set("Vectors", vectors);
      d.substructures.push_back(E);
    }
    if (free) d.freeReference = "mid";
    return d;
  }

  /// One frame model of the whole: nodes along x, groups "hub" and "booms"
  /// (element sets) and "centre" (node set).
  fem::FiniteElementModel monolithic(bool free) const {
    auto mesh = std::make_shared<mesh::Mesh>();
    mesh->source = "hub and booms, one mesh (in code)";
    std::vector<double> xs;
    for (int i = 0; i <= boomElements; ++i) xs.push_back(-(h + L) + L * i / boomElements);
    for (int i = 1; i <= hubElements; ++i) xs.push_back(-h + 2 * h * i / hubElements);
    for (int i = 1; i <= boomElements; ++i) xs.push_back(h + L * i / boomElements);
    for (std::size_t i = 0; i < xs.size(); ++i) {
      mesh->nodeTags.push_back(i + 1);
      mesh->coordinates.insert(mesh->coordinates.end(), {xs[i], 0.0, 0.0});
    }
    auto lineGroup = [&](const std::string& name, int tag, const std::vector<int>& elements) {
      mesh::PhysicalGroup g{name, 1, tag, {}};
      mesh::CellBlock b;
      b.type = mesh::CellType::Line2;
      b.gmshType = 1;
      b.nodesPerCell = 2;
      for (int e : elements) {
        b.nodes.insert(b.nodes.end(), {e, e + 1});
        b.cellTags.push_back(static_cast<std::size_t>(e + 1));
      }
      g.blocks.push_back(b);
      mesh->groups.push_back(g);
    };
    std::vector<int> hubEls, boomEls;
    for (int e = 0; e < static_cast<int>(xs.size()) - 1; ++e)
      (e >= boomElements && e < boomElements + hubElements ? hubEls : boomEls).push_back(e);
    lineGroup("hub", 1, hubEls);
    lineGroup("booms", 2, boomEls);
    addPointGroup(*mesh, "centre", {boomElements + hubElements / 2});
    addPointGroup(*mesh, "tips", {0, static_cast<std::int64_t>(xs.size()) - 1});
    fem::FiniteElementModel m;
    m.name = "monolithic";
    m.mesh = mesh;
    m.materials["hub"] = hubMaterial;
    m.materials["boom"] = boomMaterial;
    for (auto [group, mat, sec] : {std::tuple{"hub", "hub", hubSection}, std::tuple{"booms", "boom", boomSection}}) {
      fem::ElementSet set;
      set.group = group;
      set.kind = fem::ElementSet::Kind::Frame;
      set.material = mat;
      set.section = sec;
      set.section.orientation = {0.0, 0.0, 1.0};
      m.elementSets.push_back(set);
    }
    if (!free) m.fixed.push_back({"centre", "centre", {}, true});
    if (tipMass > 0) m.pointMasses.push_back({"tip masses", "tips", tipMass, {}});
    m.spin = fem::SpinDefinition{fem::Spin{{0, 0, 1}, {0, 0, 0}}, fem::SpinDefinition::Frame::Rotating, true};
    return m;
  }
};

/// Two steel boxes a x b x c along x sharing the face x = a (a Boolean
/// interface, compatible meshes of `cells` Hex8 cells each): "root" (C,
/// clamped at x = 0, spinning at W about z, stress stiffening as given) and
/// "tip" (E). The Reduction lists and any damping are the caller's.
inline synthesis::StructureDescription booleanSplitBar(double a, double b, double c, std::array<int, 3> cells,
                                                       double W, bool stiffening) {
  using namespace synthesis;
  const fem::IsotropicMaterial steel{2e11, 0.3, 7800};
  StructureDescription s;
  auto root = solidModel(boxMesh(a, b, c, cells, {a / 2, 0, 0}), steel);
  root.fixed.push_back({"clamp", "xmin", {}, true});
  SubstructureSpec C;
  C.name = "root";
  C.kind = SubstructureKind::Central;
  C.model = std::make_shared<fem::FiniteElementModel>(root);
  C.spin = SpinRate{{0, 0, 1}, {0, 0, 0}, W};
  C.spin->stressStiffening = stiffening;
  s.substructures.push_back(C);
  SubstructureSpec E;
  E.name = "tip";
  E.kind = SubstructureKind::Elastic;
  E.parent = "root";
  E.attachment.type = Attachment::Type::Boolean;
  E.attachment.parentNodes = "xmax";
  E.attachment.childNodes = "xmin";
  E.model = std::make_shared<fem::FiniteElementModel>(solidModel(boxMesh(a, b, c, cells, {1.5 * a, 0, 0}), steel));
  s.substructures.push_back(E);
  return s;
}

}  // namespace cms::fixtures
