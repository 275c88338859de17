// Reading and checking a FiniteElementModel (doc/user-guide.md, "Finite
// element substructures"). The parameter list is checked key by key against
// validParameters() before anything is computed, so a misspelt key or a value
// of the wrong type is reported with its full path. Numbers may be given as
// integers or reals (YAML writes 7850, not 7850.0).
#include "cms/fem/FiniteElementModel.hpp"
#include "cms/fem/LumpedItemParameters.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include <Teuchos_Array.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/ParameterReading.hpp"
#include "cms/fem/LumpedElements.hpp"

namespace cms::fem {

namespace {

using Teuchos::ParameterList;

using cms::checkKeys;
using cms::namesOf;
using cms::getBool;
using cms::getNumber;
using cms::getNumbers;
using cms::getString;

Vec3 toVec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

ParameterList materialParameters() {
  ParameterList p("Material");
  p.set("Young's Modulus", 0.0, "E (Pa), > 0");
  p.set("Poisson's Ratio", 0.0, "nu, in (-1, 0.5)");
  p.set("Density", 0.0, "rho (kg/m^3), > 0");
  return p;
}

ParameterList elementSetParameters() {
  ParameterList p("Element Set");
  p.set("Type", "Solid", "Solid (Tet4, Tet10, Hex8, Hex20, Wedge15 cells) or Frame (2-node line cells)");
  p.set("Material", "", "a name under Materials");
  p.set("Hex8", "Full", "Solid: Full (2x2x2 Gauss, locks in bending) or Incompatible (Wilson-Taylor modes, "
                        "condensed); default Full, or Incompatible for an .inp deck's C3D8I/C3D8R");
  p.set("Hex20", "Full", "Solid: Full (3x3x3 Gauss, C3D20) or Reduced (2x2x2, C3D20R); default Full, "
                         "or Reduced for an .inp deck's C3D20R");
  p.set("Theory", "Euler-Bernoulli", "Frame: Euler-Bernoulli or Timoshenko");
  p.set("Area", 0.0, "Frame: cross-section area A (m^2)");
  p.set("Iy", 0.0, "Frame: second moment about local y, int z^2 dA (m^4)");
  p.set("Iz", 0.0, "Frame: second moment about local z, int y^2 dA (m^4)");
  p.set("Torsion Constant", 0.0, "Frame: J (m^4)");
  p.set("Shear Factor Y", 5.0 / 6.0, "Frame, Timoshenko: kappa for shear along local y");
  p.set("Shear Factor Z", 5.0 / 6.0, "Frame, Timoshenko: kappa for shear along local z");
  p.set("Orientation", Teuchos::Array<double>(Teuchos::tuple<double>(0.0, 0.0, 1.0)), "Frame: a vector in the local x-y plane");
  p.set("Rotary Inertia", true, "Frame: include the section's rotary inertia");
  return p;
}

ParameterList pointMassParameters() {
  ParameterList p("Point Mass");
  p.set("Node Set", "", "physical group whose nodes each carry this mass");
  p.set("Mass", 0.0, "m (kg)");
  p.set("Inertia", Teuchos::Array<double>(6, 0.0), "Jxx Jyy Jzz Jxy Jyz Jxz about the node (kg m^2)");
  return p;
}

ParameterList springParameters() {
  ParameterList p("Spring");
  p.set("Node Set", "", "physical group: one spring at each node");
  p.set("To Node Set", "", "empty: grounded; else the other ends (coincident nodes)");
  p.set("Stiffness", Teuchos::Array<double>(6, 0.0), "kx ky kz krx kry krz (N/m, N m/rad)");
  p.set("Damping", Teuchos::Array<double>(6, 0.0), "cx cy cz crx cry crz (N s/m, N m s/rad): a viscous damper beside the spring");
  return p;
}

ParameterList damperParameters() {
  ParameterList p("Damper");
  p.set("Node Set", "", "physical group: one damper at each node");
  p.set("To Node Set", "", "empty: grounded; else the other ends (coincident nodes)");
  p.set("Damping", Teuchos::Array<double>(6, 0.0), "cx cy cz crx cry crz (N s/m, N m s/rad)");
  return p;
}

ParameterList hingeParameters() {
  ParameterList p("Hinge");
  p.set("Node Set", "", "physical group of frame nodes on one side (they keep all their DOFs)");
  p.set("To Node Set", "", "the other side: nodes coincident with those of \"Node Set\", paired by position");
  p.set("Axis", Teuchos::Array<double>(Teuchos::tuple<double>(0.0, 0.0, 1.0)),
        "the hinge axis (any nonzero direction): free rotation about it, rigid otherwise");
  p.set("Stiffness", 0.0, "rotational spring about the axis (N m/rad)");
  p.set("Damping", 0.0, "viscous damper about the axis (N m s/rad)");
  return p;
}

ParameterList structuralDampingParameters() {
  ParameterList p("Structural Damping");
  p.set("Rayleigh Alpha", 0.0, "D += alpha M (1/s): zeta = alpha / (2 w) per mode");
  p.set("Rayleigh Beta", 0.0, "D += beta K, K at rest (s): zeta = beta w / 2 per mode");
  p.set("Modal Damping Ratio", 0.0, "zeta of every mode of the reduced substructure (2 zeta w_j in its own "
                                    "coordinates; an approximation, refused for a Full basis)");
  return p;
}

ParameterList fixedParameters() {
  ParameterList p("Boundary Condition");
  p.set("Node Set", "", "physical group whose nodes are fixed");
  p.set("Fixed", "all", "\"all\" or components among ux uy uz rx ry rz, space-separated");
  return p;
}

ParameterList spinParameters() {
  ParameterList p("Spin");
  p.set("Axis", Teuchos::Array<double>(Teuchos::tuple<double>(0.0, 0.0, 1.0)), "spin axis (normalised)");
  p.set("Origin", Teuchos::Array<double>(Teuchos::tuple<double>(0.0, 0.0, 0.0)), "a point on the spin axis (m)");
  p.set("Frame", "Rotating", "Rotating (displacements in the spinning frame) or Stationary "
                             "(axisymmetric rotor about its own axis, Nelson-McVaugh)");
  p.set("Stress Stiffening", true, "Rotating: assemble the centrifugal geometric stiffness");
  return p;
}

/// Entries of a "name -> list of fixed keys" sublist, each checked.
template <class Fn>
void forEachEntry(const ParameterList& p, const std::string& key, const std::string& path,
                  const ParameterList& valid, Fn fn) {
  if (!p.isSublist(key)) return;
  const ParameterList& list = p.sublist(key);
  for (auto it = list.begin(); it != list.end(); ++it) {
    const std::string& name = list.name(it);
    const std::string sub = path + "/" + key + "/" + name;
    CMS_INPUT_CHECK(!list.isSublist(name), sub << ": must be a list of keys (" << namesOf(valid) << ")");
    checkKeys(list.sublist(name), valid, sub);
    fn(name, list.sublist(name), sub);
  }
}

}  // namespace

HingeSet hingeFromParameters(const std::string& name, const ParameterList& p, const std::string& path) {
  checkKeys(p, hingeParameters(), path);
  HingeSet h;
  h.name = name;
  h.nodeSet = getString(p, "Node Set", path);
  h.toNodeSet = getString(p, "To Node Set", path);
  CMS_INPUT_CHECK(h.nodeSet == h.toNodeSet,
                  path << ": \"Node Set\" and \"To Node Set\" are both '" << h.nodeSet
                       << "'; a hinge joins two sets of coincident nodes (duplicate the nodes in the mesh)");
  const auto a = getNumbers(p, "Axis", path, 3, std::vector<double>{0.0, 0.0, 1.0});
  const double norm = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  CMS_INPUT_CHECK(!(norm > 0.0) || !std::isfinite(norm), path << "/Axis = [" << a[0] << ", " << a[1] << ", " << a[2]
                                                                << "] must be a finite nonzero vector");
  for (int d = 0; d < 3; ++d) h.axis[d] = a[d] / norm;
  h.stiffness = getNumber(p, "Stiffness", path, 0.0);
  h.damping = getNumber(p, "Damping", path, 0.0);
  CMS_INPUT_CHECK(!(h.stiffness >= 0.0) || !std::isfinite(h.stiffness),
                  path << "/Stiffness = " << h.stiffness << " must be finite and >= 0 (N m/rad)");
  CMS_INPUT_CHECK(!(h.damping >= 0.0) || !std::isfinite(h.damping),
                  path << "/Damping = " << h.damping << " must be finite and >= 0 (N m s/rad)");
  return h;
}

Teuchos::RCP<const ParameterList> FiniteElementModel::validParameters() {
  auto p = Teuchos::rcp(new ParameterList("Finite Element Model"));
  p->set("Name", "substructure", "used in messages and output");
  p->set("Mesh", "", "Gmsh .msh (2.2 or 4.1, ASCII or binary), .geo, or Abaqus/CalculiX .inp; relative to the scene");
  p->sublist("Mesh Parameters", false, "name -> number: ONELAB parameters \"Parameters/<name>\" of a .geo script (DefineConstant)");
  p->sublist("Materials", false, "name -> material").sublist("<name>") = materialParameters();
  p->sublist("Element Sets", false, "physical group -> element set").sublist("<group>") = elementSetParameters();
  p->sublist("Point Masses", false, "name -> point mass").sublist("<name>") = pointMassParameters();
  p->sublist("Springs", false, "name -> spring").sublist("<name>") = springParameters();
  p->sublist("Dampers", false, "name -> viscous damper").sublist("<name>") = damperParameters();
  p->sublist("Hinges", false, "name -> hinge (exact joint free about one axis)").sublist("<name>") =
      hingeParameters();
  p->sublist("Structural Damping", false, "Rayleigh and modal damping of the whole substructure") =
      structuralDampingParameters();
  p->sublist("Boundary Conditions", false, "name -> fixed node set").sublist("<name>") = fixedParameters();
  p->sublist("Spin", false, "the frame's steady spin (omit for none)") = spinParameters();
  return p;
}

ParameterList lumpedItemKeys() {
  const auto all = FiniteElementModel::validParameters();
  ParameterList p("Lumped Items");
  for (const char* key : {"Point Masses", "Springs", "Dampers", "Hinges", "Structural Damping", "Boundary Conditions"})
    p.sublist(key) = all->sublist(key);
  return p;
}

void readLumpedItems(const ParameterList& params, const std::string& path, FiniteElementModel& m) {
  forEachEntry(params, "Point Masses", path, pointMassParameters(), [&](const std::string& name,
                                                                        const ParameterList& p,
                                                                        const std::string& sub) {
    PointMassSet s;
    s.name = name;
    s.nodeSet = getString(p, "Node Set", sub);
    s.mass = getNumber(p, "Mass", sub);
    const auto J = getNumbers(p, "Inertia", sub, 6, std::vector<double>(6, 0.0));
    std::copy(J.begin(), J.end(), s.inertia.begin());
    PointMass check;
    check.m = s.mass;
    check.inertia = s.inertia;
    check.validate(sub.c_str());
    m.pointMasses.push_back(s);
  });
  forEachEntry(params, "Springs", path, springParameters(), [&](const std::string& name, const ParameterList& p,
                                                                const std::string& sub) {
    SpringSet s;
    s.name = name;
    s.nodeSet = getString(p, "Node Set", sub);
    s.toNodeSet = getString(p, "To Node Set", sub, std::string());
    const auto k = getNumbers(p, "Stiffness", sub, 6, std::nullopt);
    const auto c = getNumbers(p, "Damping", sub, 6, std::vector<double>(6, 0.0));
    for (std::size_t i = 0; i < 6; ++i) {
      CMS_INPUT_CHECK(k[i] < 0.0, sub << "/Stiffness: entry " << i + 1 << " = " << k[i] << " must be >= 0");
      CMS_INPUT_CHECK(!(c[i] >= 0.0), sub << "/Damping: entry " << i + 1 << " = " << c[i] << " must be >= 0");
      s.stiffness[i] = k[i];
      s.damping[i] = c[i];
    }
    m.springs.push_back(s);
  });
  forEachEntry(params, "Dampers", path, damperParameters(), [&](const std::string& name, const ParameterList& p,
                                                                const std::string& sub) {
    SpringSet s;  // a damper is a spring item with no stiffness
    s.name = name;
    s.nodeSet = getString(p, "Node Set", sub);
    s.toNodeSet = getString(p, "To Node Set", sub, std::string());
    const auto c = getNumbers(p, "Damping", sub, 6, std::nullopt);
    for (std::size_t i = 0; i < 6; ++i) {
      CMS_INPUT_CHECK(!(c[i] >= 0.0), sub << "/Damping: entry " << i + 1 << " = " << c[i] << " must be >= 0");
      s.damping[i] = c[i];
    }
    m.springs.push_back(s);
  });
  forEachEntry(params, "Hinges", path, hingeParameters(), [&](const std::string& name, const ParameterList& p,
                                                              const std::string& sub) {
    m.hinges.push_back(hingeFromParameters(name, p, sub));
  });
  if (params.isSublist("Structural Damping")) {
    const std::string sub = path + "/Structural Damping";
    const ParameterList& p = params.sublist("Structural Damping");
    checkKeys(p, structuralDampingParameters(), sub);
    const std::pair<double*, const char*> keys[] = {{&m.damping.alpha, "Rayleigh Alpha"},
                                                   {&m.damping.beta, "Rayleigh Beta"},
                                                   {&m.damping.modalRatio, "Modal Damping Ratio"}};
    for (const auto& [value, key] : keys) {
      *value = getNumber(p, key, sub, 0.0);
      CMS_INPUT_CHECK(!(*value >= 0.0) || !std::isfinite(*value),
                      sub << "/" << key << " = " << *value << " must be finite and >= 0");
    }
    CMS_INPUT_CHECK(m.damping.modalRatio >= 1.0, sub << "/Modal Damping Ratio = " << m.damping.modalRatio
                                                     << " must be below 1 (critical damping)");
  }
  forEachEntry(params, "Boundary Conditions", path, fixedParameters(), [&](const std::string& name,
                                                                           const ParameterList& p,
                                                                           const std::string& sub) {
    FixedSet f;
    f.name = name;
    f.nodeSet = getString(p, "Node Set", sub);
    std::istringstream is(getString(p, "Fixed", sub, std::string("all")));
    std::string word;
    while (is >> word) {
      if (word == "all") { f.all = true; continue; }
      Component c;
      CMS_INPUT_CHECK(!parseComponent(word, c), sub << "/Fixed: unknown component \"" << word
                                  << "\"; use \"all\" or ux uy uz rx ry rz");
      f.components.push_back(c);
    }
    CMS_INPUT_CHECK(!f.all && f.components.empty(), sub << "/Fixed: names no component");
    m.fixed.push_back(f);
  });
}

namespace {
/// The key path of a "Finite Element Model" list in messages: Teuchos names
/// sublists "Parent->Child"; messages use "Parent/Child".
std::string keyPath(const ParameterList& params) {
  std::string path = params.name();
  if (path.empty() || path == "ANONYMOUS") path = "Finite Element Model";
  for (std::size_t at; (at = path.find("->")) != std::string::npos;) path.replace(at, 2, "/");
  return path;
}
}  // namespace

FiniteElementModel::MeshSource FiniteElementModel::meshSource(const ParameterList& params,
                                                              const std::string& baseDir) {
  const std::string path = keyPath(params);
  std::filesystem::path mesh = getString(params, "Mesh", path);
  CMS_INPUT_CHECK(mesh.empty(), path << "/Mesh: must name a mesh file");
  if (mesh.is_relative()) mesh = std::filesystem::path(baseDir) / mesh;
  // "a.geo", "./a.geo" and "sub/../a.geo" are one script, made once
  // (mesh/ScriptMeshes.hpp compares paths as given); lexically, so links
  // are left as named.
  mesh = mesh.lexically_normal();
  MeshSource out{mesh.string(), {}};
  if (params.isSublist("Mesh Parameters")) {
    const auto& mp = params.sublist("Mesh Parameters");
    for (auto it = mp.begin(); it != mp.end(); ++it) {
      const std::string& name = mp.name(it);
      out.parameters[name] = getNumber(mp, name, path + "/Mesh Parameters");
    }
    CMS_INPUT_CHECK(!out.parameters.empty() && mesh.extension() != ".geo",
                    path << "/Mesh Parameters: apply to a .geo script only, not " << mesh.filename().string());
  }
  return out;
}

FiniteElementModel FiniteElementModel::fromParameters(const ParameterList& params, const std::string& baseDir,
                                                      const MeshReader& readMesh) {
  const std::string path = keyPath(params);
  ParameterList top = *validParameters();
  checkKeys(params, top, path);

  FiniteElementModel m;
  m.name = getString(params, "Name", path, std::string("substructure"));
  forEachEntry(params, "Materials", path, materialParameters(), [&](const std::string& name, const ParameterList& p,
                                                                    const std::string& sub) {
    IsotropicMaterial mat;
    mat.E = getNumber(p, "Young's Modulus", sub);
    mat.nu = getNumber(p, "Poisson's Ratio", sub);
    mat.rho = getNumber(p, "Density", sub);
    mat.validate(sub.c_str());
    m.materials[name] = mat;
  });
  forEachEntry(params, "Element Sets", path, elementSetParameters(), [&](const std::string& name,
                                                                         const ParameterList& p,
                                                                         const std::string& sub) {
    ElementSet s;
    s.group = name;
    const std::string type = getString(p, "Type", sub);
    CMS_INPUT_CHECK(type != "Solid" && type != "Frame",
                    sub << "/Type = \"" << type << "\" must be \"Solid\" or \"Frame\"");
    s.kind = type == "Frame" ? ElementSet::Kind::Frame : ElementSet::Kind::Solid;
    s.material = getString(p, "Material", sub);
    if (s.kind == ElementSet::Kind::Frame) {
      const std::string theory = getString(p, "Theory", sub, std::string("Euler-Bernoulli"));
      CMS_INPUT_CHECK(theory != "Euler-Bernoulli" && theory != "Timoshenko",
                      sub << "/Theory = \"" << theory << "\" must be \"Euler-Bernoulli\" or \"Timoshenko\"");
      s.theory = theory == "Timoshenko" ? BeamTheory::Timoshenko : BeamTheory::EulerBernoulli;
      s.section.A = getNumber(p, "Area", sub);
      s.section.Iy = getNumber(p, "Iy", sub);
      s.section.Iz = getNumber(p, "Iz", sub);
      s.section.J = getNumber(p, "Torsion Constant", sub);
      s.section.shearFactorY = getNumber(p, "Shear Factor Y", sub, 5.0 / 6.0);
      s.section.shearFactorZ = getNumber(p, "Shear Factor Z", sub, 5.0 / 6.0);
      s.section.orientation = toVec3(getNumbers(p, "Orientation", sub, 3, std::vector<double>{0, 0, 1}));
      s.section.rotaryInertia = getBool(p, "Rotary Inertia", sub, true);
      s.section.validate(sub.c_str());
      for (const char* k : {"Hex8", "Hex20"})
        CMS_INPUT_CHECK(p.isParameter(k), sub << "/" << k << ": applies to Solid element sets only");
    } else {
      for (const char* k : {"Theory", "Area", "Iy", "Iz", "Torsion Constant", "Shear Factor Y", "Shear Factor Z",
                            "Orientation", "Rotary Inertia"})
        CMS_INPUT_CHECK(p.isParameter(k), sub << "/" << k << ": applies to Frame element sets only");
      if (p.isParameter("Hex8")) {
        const std::string f = getString(p, "Hex8", sub);
        CMS_INPUT_CHECK(f != "Full" && f != "Incompatible",
                        sub << "/Hex8 = \"" << f << "\" must be \"Full\" or \"Incompatible\"");
        s.hex8 = f == "Full" ? SolidType::Hex8 : SolidType::Hex8Incompatible;
      }
      if (p.isParameter("Hex20")) {
        const std::string f = getString(p, "Hex20", sub);
        CMS_INPUT_CHECK(f != "Full" && f != "Reduced",
                        sub << "/Hex20 = \"" << f << "\" must be \"Full\" or \"Reduced\"");
        s.hex20 = f == "Full" ? SolidType::Hex20 : SolidType::Hex20Reduced;
      }
    }
    m.elementSets.push_back(s);
  });
  readLumpedItems(params, path, m);
  if (params.isSublist("Spin")) {
    const ParameterList& p = params.sublist("Spin");
    const std::string sub = path + "/Spin";
    checkKeys(p, spinParameters(), sub);
    SpinDefinition s;
    auto axis = getNumbers(p, "Axis", sub, 3, std::nullopt);
    const double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    CMS_INPUT_CHECK(norm == 0.0, sub << "/Axis: must be a nonzero vector");
    s.spin.axis = {axis[0] / norm, axis[1] / norm, axis[2] / norm};
    s.spin.origin = toVec3(getNumbers(p, "Origin", sub, 3, std::vector<double>{0, 0, 0}));
    const std::string frame = getString(p, "Frame", sub, std::string("Rotating"));
    CMS_INPUT_CHECK(frame != "Rotating" && frame != "Stationary",
                    sub << "/Frame = \"" << frame << "\" must be \"Rotating\" or \"Stationary\"");
    s.frame = frame == "Rotating" ? SpinDefinition::Frame::Rotating : SpinDefinition::Frame::Stationary;
    s.stressStiffening = getBool(p, "Stress Stiffening", sub, true);
    CMS_INPUT_CHECK(s.frame == SpinDefinition::Frame::Stationary && p.isParameter("Stress Stiffening") &&
                        s.stressStiffening,
                    sub << "/Stress Stiffening: applies to the Rotating frame only");
    if (s.frame == SpinDefinition::Frame::Stationary) s.stressStiffening = false;
    m.spin = s;
  }

  const MeshSource source = meshSource(params, baseDir);
  m.mesh = std::make_shared<mesh::Mesh>(readMesh ? readMesh(source.file, source.parameters)
                                                 : mesh::readMesh(source.file, source.parameters));
  m.validate();
  return m;
}

SolidType solidTypeOf(const ElementSet& set, const mesh::CellBlock& b) {
  std::string deck = b.elementName;
  for (char& c : deck) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  switch (b.type) {
    case mesh::CellType::Tet4: return SolidType::Tet4;
    case mesh::CellType::Tet10: return SolidType::Tet10;
    case mesh::CellType::Wedge15: return SolidType::Wedge15;
    case mesh::CellType::Hex27: return SolidType::Hex27;
    case mesh::CellType::Hex64: return SolidType::Hex64;
    case mesh::CellType::Hex125: return SolidType::Hex125;
    case mesh::CellType::Hex8:
      if (set.hex8) return *set.hex8;
      // C3D8R has no one-point brick here; the incompatible-mode brick is the
      // non-locking element closest to what its user meant.
      return deck == "C3D8I" || deck == "C3D8R" ? SolidType::Hex8Incompatible : SolidType::Hex8;
    case mesh::CellType::Hex20:
      if (set.hex20) return *set.hex20;
      return deck == "C3D20R" ? SolidType::Hex20Reduced : SolidType::Hex20;
    default: break;
  }
  CMS_INPUT_CHECK(true, "element set '" << set.group << "': cells of type " << mesh::cellTypeName(b.type)
                                        << " (Gmsh type " << b.gmshType << ") are not solid elements");
  throw std::logic_error("unreachable");
}

void FiniteElementModel::validate() const {
  CMS_INPUT_CHECK(!mesh, name << ": no mesh");
  // A lumped model (point masses on springs) needs no elements.
  CMS_INPUT_CHECK(elementSets.empty() && pointMasses.empty(),
                  name << ": no element sets and no point masses; name at least one physical group of "
                       << mesh->source << " under \"Element Sets\"");
  std::set<std::string> seen;
  for (const ElementSet& s : elementSets) {
    const std::string what = name + ": element set '" + s.group + "'";
    CMS_INPUT_CHECK(!seen.insert(s.group).second, what << " is listed twice");
    const mesh::PhysicalGroup& g = mesh->group(s.group);
    auto mat = materials.find(s.material);
    CMS_INPUT_CHECK(mat == materials.end(), what << ": unknown material '" << s.material << "'");
    mat->second.validate(("material '" + s.material + "'").c_str());
    if (s.kind == ElementSet::Kind::Frame) s.section.validate(what.c_str());
    for (const mesh::CellBlock& b : g.blocks) {
      const bool ok = s.kind == ElementSet::Kind::Frame
                          ? b.type == mesh::CellType::Line2
                          : (b.type == mesh::CellType::Tet4 || b.type == mesh::CellType::Tet10 ||
                             b.type == mesh::CellType::Hex8 || b.type == mesh::CellType::Hex20 ||
                             b.type == mesh::CellType::Wedge15 || b.type == mesh::CellType::Hex27 ||
                             b.type == mesh::CellType::Hex64 || b.type == mesh::CellType::Hex125);
      CMS_INPUT_CHECK(!ok, what << " (" << mesh->source << ", physical group of dimension " << g.dim
                                << "): cells of type " << mesh::cellTypeName(b.type) << " (Gmsh type " << b.gmshType
                                << ", e.g. element " << (b.cellTags.empty() ? 0 : b.cellTags[0])
                                << ") are not supported by "
                                << (s.kind == ElementSet::Kind::Frame ? "Frame sets (2-node lines only)"
                                                                      : "Solid sets (Tet4, Tet10, Hex8, Hex20, Wedge15, Hex27, Hex64, Hex125)"));
    }
  }
  // An element in two listed sets would be assembled twice (decks list
  // EALL beside a part's own set as a matter of course): refused, naming
  // one such element and its two sets. By element tag, which a Gmsh mesh
  // and a deck both keep unique.
  {
    std::vector<std::pair<std::size_t, std::size_t>> tagSet;  // (tag, set index)
    for (std::size_t s = 0; s < elementSets.size(); ++s)
      for (const mesh::CellBlock& b : mesh->group(elementSets[s].group).blocks)
        for (std::size_t t : b.cellTags) tagSet.emplace_back(t, s);
    std::sort(tagSet.begin(), tagSet.end());
    for (std::size_t i = 1; i < tagSet.size(); ++i)
      CMS_INPUT_CHECK(tagSet[i].first == tagSet[i - 1].first,
                      name << ": element " << tagSet[i].first << " is in element sets '"
                           << elementSets[tagSet[i - 1].second].group << "' and '" << elementSets[tagSet[i].second].group
                           << "' of " << mesh->source
                           << ": it would be assembled twice; list sets that share no element (a deck's EALL, or its "
                              "parts' own sets, not both)");
  }
  // A frame element far shorter than a neighbour (two nodes a deck places
  // almost together) is stiffer by the cube of the ratio, and the solve
  // loses that many digits: at 2e-4 a circular beam's double frequencies
  // split by 8e-5, residuals 1e-17, and below 1e-5 the clamped beam read
  // "unrestrained" (found by a review). Refused below 1e-3 (a stiffness
  // ratio of 1e9), naming both elements' lengths.
  {
    struct Line { std::size_t tag; std::int64_t a, b; double length; };
    std::vector<Line> lines;
    std::vector<double> longest(mesh->nodeCount(), 0.0);  // node -> longest frame element there
    for (const ElementSet& s : elementSets) {
      if (s.kind != ElementSet::Kind::Frame) continue;
      for (const mesh::CellBlock& b : mesh->group(s.group).blocks)
        for (std::size_t c = 0; c < b.size(); ++c) {
          const std::int64_t a = b.nodes[2 * c], e = b.nodes[2 * c + 1];
          double d2 = 0.0;
          for (int k = 0; k < 3; ++k) d2 += std::pow(mesh->x(e)[k] - mesh->x(a)[k], 2);
          const double length = std::sqrt(d2);
          lines.push_back({c < b.cellTags.size() ? b.cellTags[c] : c, a, e, length});
          for (std::int64_t n : {a, e})
            longest[static_cast<std::size_t>(n)] = std::max(longest[static_cast<std::size_t>(n)], length);
        }
    }
    for (const Line& l : lines) {
      const double neighbour = std::max(longest[static_cast<std::size_t>(l.a)], longest[static_cast<std::size_t>(l.b)]);
      CMS_INPUT_CHECK(l.length > 0.0 && l.length < 1e-3 * neighbour,
                      name << ": frame element " << l.tag << " of " << mesh->source << " is " << l.length
                           << " long beside a neighbour " << neighbour << " long (ratio " << l.length / neighbour
                           << "): its stiffness, ~1/L^3, would be " << std::pow(neighbour / l.length, 3)
                           << " times theirs and the solve would lose as many digits; merge its two nodes, or move "
                              "them together and join them by a Spring or a Hinge (both join coincident nodes), or "
                              "make a short offset a rigid link (an attachment Point off the node)");
    }
  }
  for (const PointMassSet& p : pointMasses) mesh->group(p.nodeSet);
  for (const SpringSet& s : springs) {
    mesh->group(s.nodeSet);
    if (!s.toNodeSet.empty()) mesh->group(s.toNodeSet);
  }
  for (const FixedSet& f : fixed) mesh->group(f.nodeSet);
  for (const HingeSet& h : hinges) {
    const std::string what = name + ": hinge '" + h.name + "'";
    for (const std::string* set : {&h.nodeSet, &h.toNodeSet}) {
      CMS_INPUT_CHECK(!mesh->hasGroup(*set), what << ": no node set '" << *set << "' in " << mesh->source);
    }
    const double n2 = h.axis[0] * h.axis[0] + h.axis[1] * h.axis[1] + h.axis[2] * h.axis[2];
    CMS_INPUT_CHECK(!(std::abs(n2 - 1.0) <= 1e-12), what << ": the axis must be a unit vector");
    CMS_INPUT_CHECK(!(h.stiffness >= 0.0) || !(h.damping >= 0.0),
                    what << ": stiffness and damping must be >= 0");
  }
  if (spin) {
    const Vec3& a = spin->spin.axis;
    CMS_INPUT_CHECK(std::abs(a[0] * a[0] + a[1] * a[1] + a[2] * a[2] - 1.0) > 1e-12,
                    name << ": spin axis must be a unit vector");
    if (spin->frame == SpinDefinition::Frame::Stationary)
      for (const ElementSet& s : elementSets) {
        CMS_INPUT_CHECK(s.kind == ElementSet::Kind::Solid,
                        name << ": element set '" << s.group
                             << "' is solid; the stationary-frame (Nelson-McVaugh) form is for beam and "
                                "point-mass rotors spinning about their own axis. Use Frame: Rotating");
        // Constant coefficients in the stationary frame need a section that
        // looks the same at every angle of rotation (theory §9.4).
        CMS_INPUT_CHECK(std::abs(s.section.Iy - s.section.Iz) > 1e-8 * (s.section.Iy + s.section.Iz),
                        name << ": element set '" << s.group << "' has Iy = " << s.section.Iy << " != Iz = "
                             << s.section.Iz << "; the stationary frame needs an axisymmetric rotor "
                                "(Iy = Iz). Use Frame: Rotating");
      }
    // A hinge about any other axis than the spin's is not axisymmetric
    // either: its stiffness and damping turn with the rotor, which constant
    // stationary-frame coefficients cannot hold (theory §9.4), and its
    // damper would need a circulatory term of its own (§13.1). (A review
    // found one about y on a rotor spinning about x accepted.)
    if (spin->frame == SpinDefinition::Frame::Stationary)
      for (const HingeSet& h : hinges) {
        CMS_INPUT_CHECK(!(norm(cross(h.axis, a)) <= 1e-8),
                        name << ": hinge '" << h.name << "' turns about (" << h.axis[0] << ", " << h.axis[1] << ", "
                             << h.axis[2] << "), not the spin axis (" << a[0] << ", " << a[1] << ", " << a[2]
                             << "); the stationary frame needs an axisymmetric rotor, so a hinge there must turn "
                                "about the spin axis. Use Frame: Rotating");
      }
  }
}

}  // namespace cms::fem
