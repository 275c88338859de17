#include "cms/synthesis/Structure.hpp"

#include <cmath>
#include <set>

#include "cms/core/Error.hpp"

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

}  // namespace cms::synthesis
