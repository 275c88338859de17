#include "cms/synthesis/Structure.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <sstream>

#include "cms/core/Error.hpp"
#include "cms/fem/RigidPlacement.hpp"

namespace cms::synthesis {

const char* toString(SubstructureKind k) {
  switch (k) {
    case SubstructureKind::Central: return "C";
    case SubstructureKind::Rigid: return "R";
    case SubstructureKind::Elastic: return "E";
    default: return "A";
  }
}

int StructureDescription::find(const std::string& name) const {
  for (std::size_t i = 0; i < substructures.size(); ++i)
    if (substructures[i].name == name) return static_cast<int>(i);
  return -1;
}

void StructureDescription::validate() const {
  CMS_INPUT_CHECK(substructures.empty(), "structure: no substructures");
  int central = -1;
  std::set<std::string> names;
  for (std::size_t i = 0; i < substructures.size(); ++i) {
    const auto& s = substructures[i];
    const std::string who = "substructure '" + s.name + "' (" + toString(s.kind) + ")";
    CMS_INPUT_CHECK(s.name.empty(), "structure: substructure " << i + 1 << " has no name");
    CMS_INPUT_CHECK(s.copies < 1 || !std::isfinite(s.copyPhase),
                    who << ": \"Copies\" must be at least 1 and its phase finite (got " << s.copies << ", "
                        << s.copyPhase << ")");
    CMS_INPUT_CHECK(!s.copyParentNodes.empty() && s.copies == 1,
                    who << ": \"Copy Parent Nodes\" without \"Copies\" (more than one)");
    // Read only where there are copies to turn: a phase on a single part
    // turned nothing and was accepted (found by a review).
    CMS_INPUT_CHECK(s.copyPhase != 0.0 && s.copies == 1,
                    who << ": \"Copy Phase\" without \"Copies\" (more than one) turns nothing; to turn one "
                           "substructure, give its model a \"Placement\"");
    // A Boolean interface's point is the centroid of its shared nodes (its
    // frame's origin): a given Point was ignored (the frequencies those
    // of none), and a Point off the parent accepted (found by a review).
    CMS_INPUT_CHECK(s.attachment.point && s.attachment.type == Attachment::Type::Boolean,
                    who << ": \"Attachment/Point\" with a Boolean attachment: its point is the centroid of the "
                           "shared nodes; remove Point, or attach by Node or RigidFit");
    CMS_INPUT_CHECK(s.copies > 1 && s.kind == SubstructureKind::Central,
                    who << ": the central substructure cannot be copied (\"Copies\" places copies about the parent's "
                           "spin axis)");
    CMS_INPUT_CHECK(!names.insert(s.name).second, "structure: two substructures are named '" << s.name << "'");
    if (s.kind == SubstructureKind::Central) {
      CMS_INPUT_CHECK(central >= 0, who << ": a second central substructure (the first is '"
                                        << substructures[central].name << "')");
      central = static_cast<int>(i);
      CMS_INPUT_CHECK(!s.parent.empty(), who << ": the central substructure has no parent (got '" << s.parent << "')");
    } else {
      CMS_INPUT_CHECK(s.parent.empty(), who << ": needs a parent");
      CMS_INPUT_CHECK(find(s.parent) < 0, who << ": parent '" << s.parent << "' is not a substructure of the structure");
      CMS_INPUT_CHECK(substructures[find(s.parent)].kind == SubstructureKind::Rigid,
                      who << ": parent '" << s.parent << "' is a rigid rotor (R), which carries no children");
      CMS_INPUT_CHECK(s.attachment.parentNodes.empty(),
                      who << ": \"Attachment\" needs the parent's node set (\"Parent Nodes\")");
    }
    if (s.kind == SubstructureKind::Rigid) {
      CMS_INPUT_CHECK(!(s.rotor.mass > 0.0) || !std::isfinite(s.rotor.mass),
                      who << ": rotor mass " << s.rotor.mass << " must be positive and finite");
      CMS_INPUT_CHECK(!(s.rotor.transverseInertia > 0.0) || !(s.rotor.axialInertia > 0.0) ||
                          !std::isfinite(s.rotor.transverseInertia) || !std::isfinite(s.rotor.axialInertia),
                      who << ": rotor inertias (transverse " << s.rotor.transverseInertia << ", axial "
                          << s.rotor.axialInertia << ") must be positive and finite");
      CMS_INPUT_CHECK(s.rotor.axialInertia > 2.0 * s.rotor.transverseInertia * (1 + 1e-12),
                      who << ": axial inertia " << s.rotor.axialInertia << " exceeds twice the transverse inertia "
                          << s.rotor.transverseInertia << " (no rigid body has such inertias)");
      CMS_INPUT_CHECK(!s.spin, who << ": a rigid rotor needs \"Spin\" (axis and rate)");
      CMS_INPUT_CHECK(s.attachment.type == Attachment::Type::Boolean,
                      who << ": a rigid rotor attaches at a point (Node or RigidFit), not by a Boolean interface");
    } else {
      CMS_INPUT_CHECK(!s.model, who << ": needs a finite element model");
      CMS_INPUT_CHECK(s.model->spin.has_value(),
                      who << ": its model sets \"Spin\"; the structure sets each substructure's spin from its kind "
                             "and parent, so give the spin on the substructure instead");
      if (s.kind != SubstructureKind::Central)
        CMS_INPUT_CHECK(s.attachment.childNodes.empty(),
                        who << ": \"Attachment\" needs its own node set moving with the attachment (\"Nodes\")");
    }
    if (s.kind == SubstructureKind::Elastic)
      CMS_INPUT_CHECK(s.spin.has_value(), who << ": an E substructure does not rotate relative to its parent; "
                                                 "use kind A for a spinning one");
    if (s.kind == SubstructureKind::Rotating) CMS_INPUT_CHECK(!s.spin, who << ": an A substructure needs \"Spin\"");
    if (s.spin) {
      const auto& a = s.spin->axis;
      const double n = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
      CMS_INPUT_CHECK(!(n > 0.0) || !std::isfinite(n), who << ": spin axis must be a nonzero finite vector");
      CMS_INPUT_CHECK(!std::isfinite(s.spin->rate), who << ": spin rate must be finite");
    }
  }
  CMS_INPUT_CHECK(central < 0, "structure: no central substructure (kind C)");
  CMS_INPUT_CHECK(!freeReference.empty() && !substructures[central].model->fixed.empty(),
                  "substructure '" << substructures[central].name
                                   << "' (C) is free-floating but its model fixes DOFs (\""
                                   << substructures[central].model->fixed.front().name << "\")");
  // Nothing in a free-floating structure may hold it to the ground: the
  // synthesis makes K exactly zero on the six rigid-body coordinates (theory
  // §11.6), so a support or a grounded spring on any part lost its hold on
  // the rigid motion and its coupling to the elastic ones, with six zeros
  // still reported as the free body's rigid modes (found by a review).
  if (!freeReference.empty())
    for (const auto& s : substructures) {
      if (!s.model) continue;
      CMS_INPUT_CHECK(!s.model->fixed.empty(), "substructure '" << s.name << "' of a free-floating structure (Free "
                                                "Reference) fixes DOFs (\"" << s.model->fixed.front().name
                                                << "\"): a free structure has no ground; without Free Reference its "
                                                   "supports hold it");
      for (const auto& k : s.model->springs)
        CMS_INPUT_CHECK(k.toNodeSet.empty() &&
                            std::any_of(k.stiffness.begin(), k.stiffness.end(), [](double v) { return v != 0.0; }),
                        "substructure '" << s.name << "' of a free-floating structure (Free Reference) has the "
                                         "grounded spring \"" << k.name << "\": a free structure has no ground; "
                                         "without Free Reference the springs hold it");
    }
  // Every chain must reach C (no cycles).
  for (const auto& s : substructures) {
    std::set<std::string> seen;
    const SubstructureSpec* p = &s;
    while (!p->parent.empty()) {
      CMS_INPUT_CHECK(!seen.insert(p->name).second, "structure: the parents of '" << s.name << "' form a cycle");
      p = &substructures[find(p->parent)];
    }
  }
}

namespace {

/// The axis a child of `parent` is patterned about, and a point of it: C's
/// spin axis through its Origin, an A's spin axis through its attachment
/// point (the given Point, or the centroid of its parent's attachment
/// nodes, as AssembledStructure places it).
std::pair<fem::Vec3, fem::Vec3> patternAxis(const StructureDescription& d, const SubstructureSpec& parent,
                                            const SubstructureSpec& copied) {
  CMS_INPUT_CHECK(!parent.spin, "substructure '" << copied.name << "': \"Copies: " << copied.copies
                                                 << "\" places the copies about the parent's spin axis, and its parent '"
                                                 << parent.name << "' does not spin");
  if (parent.kind == SubstructureKind::Central) return {fem::unit(parent.spin->axis), parent.spin->origin};
  if (parent.attachment.point) return {fem::unit(parent.spin->axis), *parent.attachment.point};
  const auto& grand = d.substructures[d.find(parent.parent)];
  const auto nodes = grand.model->mesh->nodeSet(parent.attachment.parentNodes);
  CMS_INPUT_CHECK(nodes.empty(), "substructure '" << parent.name << "': attachment node set '"
                                                  << parent.attachment.parentNodes << "' of '" << grand.name
                                                  << "' is empty");
  fem::Vec3 c{0, 0, 0};
  for (auto n : nodes)
    for (int k = 0; k < 3; ++k) c[k] += grand.model->mesh->coordinates[3 * n + k] / static_cast<double>(nodes.size());
  return {fem::unit(parent.spin->axis), c};
}

/// The parent's nodes where the nodes of its set `set` turn to, added to the
/// parent's mesh as the node set `name` (the parent's model is copied).
/// The diagonal of the mesh's bounding box.
double meshSize(const mesh::Mesh& mesh) {
  fem::Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (std::size_t n = 0; n < mesh.nodeCount(); ++n)
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], mesh.coordinates[3 * n + k]), hi[k] = std::max(hi[k], mesh.coordinates[3 * n + k]);
  return fem::norm(fem::sub(hi, lo));
}

void addTurnedNodeSet(SubstructureSpec& parent, const std::string& set, const fem::Rotation& turn,
                      const fem::Vec3& origin, const std::string& name, const std::string& who, double degrees) {
  const mesh::Mesh& mesh = *parent.model->mesh;
  CMS_INPUT_CHECK(!mesh.hasGroup(set), who << ": attachment node set '" << set << "' is not a physical group of '"
                                           << parent.name << "' (" << mesh.source << ")");
  // Coincident within 1e-6 of the parent's size: a mesher's rounding of a
  // position it was asked for, far below any element.
  const double tol = 1e-6 * meshSize(mesh);
  mesh::PhysicalGroup group{name, 0, 0, {}};
  for (const auto& g : mesh.groups) group.tag = std::max(group.tag, g.tag + 1);
  mesh::CellBlock points;
  points.type = mesh::CellType::Point1, points.gmshType = 15, points.nodesPerCell = 1;
  for (auto n : mesh.nodeSet(set)) {
    const fem::Vec3 x{mesh.coordinates[3 * n], mesh.coordinates[3 * n + 1], mesh.coordinates[3 * n + 2]};
    const fem::Vec3 target = fem::axpy(1.0, turn.apply(fem::sub(x, origin)), origin);
    std::int64_t found = -1;
    for (std::size_t m = 0; m < mesh.nodeCount() && found < 0; ++m)
      if (fem::norm(fem::sub({mesh.coordinates[3 * m], mesh.coordinates[3 * m + 1], mesh.coordinates[3 * m + 2]},
                             target)) <= tol)
        found = static_cast<std::int64_t>(m);
    CMS_INPUT_CHECK(found < 0, who << ": its parent '" << parent.name << "' has no node at (" << target[0] << ", "
                                   << target[1] << ", " << target[2] << "), where node " << mesh.nodeTags[n]
                                   << " of '" << set << "' turns to by " << degrees
                                   << " degrees about the parent's spin axis (the copy's attachment)");
    points.nodes.push_back(found);
    points.cellTags.push_back(points.cellTags.size() + 1);
  }
  group.blocks.push_back(points);
  auto model = std::make_shared<fem::FiniteElementModel>(*parent.model);
  auto copy = std::make_shared<mesh::Mesh>(mesh);
  copy->groups.push_back(group);
  model->mesh = copy;
  parent.model = model;
}

/// A "Copy Parent Nodes" set given for a copy must lie where the written
/// attachment set turns to: its centroid at the turned centroid, within a
/// tenth of the written set's extent (a face meshed differently on each
/// side) or 1e-6 of the parent's size (one node). A list in the wrong order
/// or naming another face was accepted, and a Node or RigidFit attachment
/// then held the copy to it through a long rigid link (found by a review:
/// blade[3] of the helicopter hung on the hub's other end).
void checkNamedParentNodes(const SubstructureSpec& parent, const std::string& written, const std::string& named,
                           const fem::Rotation& turn, const fem::Vec3& origin, const std::string& who,
                           double degrees) {
  if (!parent.model || !parent.model->mesh) return;
  const mesh::Mesh& mesh = *parent.model->mesh;
  for (const std::string& set : {written, named})
    CMS_INPUT_CHECK(!mesh.hasGroup(set), who << ": attachment node set '" << set << "' is not a physical group of '"
                                             << parent.name << "' (" << mesh.source << ")");
  auto centroid = [&](const std::string& set, double& extent) {
    fem::Vec3 c{0, 0, 0}, lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    const auto nodes = mesh.nodeSet(set);
    for (auto n : nodes)
      for (int k = 0; k < 3; ++k) {
        const double x = mesh.coordinates[3 * n + k];
        c[k] += x / static_cast<double>(nodes.size()), lo[k] = std::min(lo[k], x), hi[k] = std::max(hi[k], x);
      }
    extent = nodes.empty() ? 0.0 : fem::norm(fem::sub(hi, lo));
    return c;
  };
  double extent = 0.0, unused = 0.0;
  const double size = meshSize(mesh);
  const fem::Vec3 target = fem::axpy(1.0, turn.apply(fem::sub(centroid(written, extent), origin)), origin);
  const fem::Vec3 at = centroid(named, unused);
  const double off = fem::norm(fem::sub(at, target));
  CMS_INPUT_CHECK(off > std::max(0.1 * extent, 1e-6 * size),
                  who << ": \"Copy Parent Nodes\" gives it '" << named << "', centred at (" << at[0] << ", " << at[1]
                      << ", " << at[2] << "), " << off << " from (" << target[0] << ", " << target[1] << ", "
                      << target[2] << "), where '" << written << "' turns to by " << degrees
                      << " degrees about the parent's spin axis: list one set per copy, in the copies' order");
}

}  // namespace

StructureDescription StructureDescription::withCopies() const {
  auto copied = [](const SubstructureSpec& s) { return s.copies > 1; };
  validate();  // every assembly's description (AssembledStructure::assemble calls this first)
  if (std::none_of(substructures.begin(), substructures.end(), copied)) return *this;
  StructureDescription out = *this;
  // A copied item inside another's subtree is refused (its copies would need
  // two indices); then the copied items expand one at a time.
  for (const auto& s : substructures) {
    if (!copied(s)) continue;
    for (const SubstructureSpec* a = &s; !a->parent.empty();) {
      a = &substructures[find(a->parent)];
      CMS_INPUT_CHECK(copied(*a), "substructure '" << s.name << "' (Copies: " << s.copies << ") is inside '" << a->name
                                                  << "' (Copies: " << a->copies
                                                  << "): copies inside a copied subtree are not supported");
    }
  }
  for (;;) {
    auto it = std::find_if(out.substructures.begin(), out.substructures.end(), copied);
    if (it == out.substructures.end()) break;
    const SubstructureSpec top = *it;
    const std::string who = "substructure '" + top.name + "' (Copies: " + std::to_string(top.copies) + ")";
    CMS_INPUT_CHECK(top.copies > 1000, who << ": at most 1000 copies");
    // The subtree, in the description's order.
    std::vector<std::size_t> subtree;
    std::function<bool(const SubstructureSpec&)> inside = [&](const SubstructureSpec& s) {
      if (s.name == top.name) return true;
      return !s.parent.empty() && inside(out.substructures[out.find(s.parent)]);
    };
    for (std::size_t i = 0; i < out.substructures.size(); ++i)
      if (inside(out.substructures[i])) subtree.push_back(i);
    const auto topIndex = static_cast<std::size_t>(it - out.substructures.begin());
    CMS_INPUT_CHECK(!top.copyParentNodes.empty() && static_cast<int>(top.copyParentNodes.size()) != top.copies,
                    who << ": \"Copy Parent Nodes\" names " << top.copyParentNodes.size() << " node sets for "
                        << top.copies << " copies");
    const int parentIndex = out.find(top.parent);
    const auto [axis, origin] = patternAxis(out, out.substructures[parentIndex], top);
    std::vector<SubstructureSpec> made;
    for (int j = 0; j < top.copies; ++j) {
      const double angle = top.copyPhase + 2.0 * M_PI * j / top.copies;
      const auto turn = fem::Rotation::about(axis, angle);
      const std::string suffix = "[" + std::to_string(j + 1) + "]";
      for (std::size_t i : subtree) {
        const SubstructureSpec& x = out.substructures[i];
        SubstructureSpec c = x;
        c.name = x.name + suffix;
        c.copies = 1;
        c.copyPhase = 0.0;
        c.copy = CopyPlacement{x.name + "[1]", x.name, j, top.copies, angle, axis, origin};
        if (&x != &*it) c.parent = x.parent + suffix;
        const std::string cwho = "substructure '" + c.name + "' (copy " + std::to_string(j + 1) + " of '" + x.name + "')";
        if (x.model) {
          const std::string variant = fem::rotationVariantItem(*x.model, turn);
          CMS_INPUT_CHECK(!variant.empty(),
                          cwho << ": its " << variant << " acts along the structure's axes, and turned by "
                               << angle * 180 / M_PI << " degrees about the spin axis it would act along others: give "
                               << "it the same values in every direction normal to the spin axis, or do not copy it");
          c.model = fem::placedModel(*x.model, turn, origin);
          c.copy->model = c.model;
        }
        if (c.spin) {
          c.spin->axis = turn.apply(x.spin->axis);
          c.spin->origin = fem::axpy(1.0, turn.apply(fem::sub(x.spin->origin, origin)), origin);
        }
        if (c.attachment.point) c.attachment.point = fem::axpy(1.0, turn.apply(fem::sub(*x.attachment.point, origin)), origin);
        if (&x == &*it && !top.copyParentNodes.empty()) {
          c.attachment.parentNodes = top.copyParentNodes[static_cast<std::size_t>(j)];
          c.copyParentNodes.clear();
          checkNamedParentNodes(out.substructures[parentIndex], x.attachment.parentNodes, c.attachment.parentNodes, turn,
                                origin, cwho, angle * 180 / M_PI);
        } else if (&x == &*it && angle != 0.0) {
          c.attachment.parentNodes = x.attachment.parentNodes + "@" + c.name;
          addTurnedNodeSet(out.substructures[parentIndex], x.attachment.parentNodes, turn, origin,
                           c.attachment.parentNodes, cwho, angle * 180 / M_PI);
        }
        made.push_back(std::move(c));
      }
    }
    // Replace the subtree by its copies, where the copied item was.
    const auto at = topIndex - static_cast<std::size_t>(std::count_if(subtree.begin(), subtree.end(),
                                                                       [&](std::size_t i) { return i < topIndex; }));
    for (auto i = subtree.rbegin(); i != subtree.rend(); ++i)
      out.substructures.erase(out.substructures.begin() + static_cast<long>(*i));
    out.substructures.insert(out.substructures.begin() + static_cast<long>(at), made.begin(), made.end());
  }
  out.validate();
  return out;
}

}  // namespace cms::synthesis
