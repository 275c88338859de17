#include "cms/scene/Scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include <mpi.h>
#include <sys/resource.h>

#include <Teuchos_XMLParameterListCoreHelpers.hpp>

#include "YamlScene.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/PeakMemory.hpp"
#include "cms/core/ParameterReading.hpp"
#include "cms/fem/FrameElement.hpp"
#include "cms/fem/LumpedItemParameters.hpp"
#include "cms/fem/RigidPlacement.hpp"
#include "cms/mesh/ScriptMeshes.hpp"
#include "cms/reduction/RitzBasis.hpp"

namespace cms::scene {

namespace {

using Teuchos::ParameterList;
using synthesis::Attachment;
using synthesis::SubstructureKind;
using synthesis::SubstructureSpec;

ParameterList sceneKeys() {
  ParameterList p("Scene");
  p.set("Name", "", "a name for the outputs (default: the file's stem)");
  p.set("Units", "SI", "SI only: m, kg, s, N, rad; frequencies are reported in Hz and rad/s");
  p.sublist("Substructures").disableRecursiveValidation();
  p.set("Free Reference", "", "the central substructure's node set it floats about (empty: clamped)");
  ParameterList& a = p.sublist("Analysis");
  a.set("Number of Modes", 10, "lowest modes to compute");
  a.set("Solver", "Auto", "Auto, Dense or Sparse");
  a.set("Dense Limit", 1500, "largest number of coordinates solved densely under Auto");
  a.set("Direct Solver", "Auto",
        "who factors on the sparse path (the truth, large reduced models): CHOLMOD, gathered to rank 0; MUMPS, "
        "across the ranks; Auto: MUMPS on more than one rank for matrices of 2e6 entries or more");
  a.set("Frequency Tolerance", 1e-5,
        "a damped structure: a mode whose first-order eigenvalue error exceeds this times |lambda| is refined "
        "by two-sided inverse iteration on the full model (sparse path) or on the reduced Q(lambda) (dense "
        "path, a cluster as one block), one factorisation each (doc/theory.md §5, \"Stiff rows\")");
  a.set("Speed Factor", 1.0, "multiplies every nominal spin rate");
  a.set("Target Accuracy", 0.0,
        "> 0: cms modes enriches the reduced substructures until every one of the Number of Modes has an "
        "estimated relative frequency error below it (doc/theory.md §11.8); 0: the scene's bases as written");
  ParameterList& o = p.sublist("Output");
  o.set("Directory", "", "where results go (relative to the scene); empty: the command line's choice");
  o.set("JSON", true, "write <name>.json");
  o.set("CSV", true, "write <name>-modes.csv (and the other tables)");
  return p;
}

ParameterList substructureKeys() {
  ParameterList p("Substructure");
  p.set("Kind", "", "C (central), E (elastic), A (elastic, spinning relative to its parent), R (rigid rotor)");
  p.set("Parent", "", "the substructure it is attached to (not for C)");
  ParameterList& at = p.sublist("Attachment");
  at.set("Type", "Node", "Node, RigidFit or Boolean");
  at.set("Parent Nodes", "", "node set of the parent");
  at.set("Nodes", "", "its own node set moving with the attachment (not for R)");
  at.set("Point", Teuchos::Array<double>(3, 0.0), "attachment point (default: the parent node or set centroid)");
  at.set("Copy Parent Nodes", Teuchos::Array<std::string>(),
         "with Copies: N, the parent's node set of each copy (default: the parent's nodes where the written "
         "ones turn to)");
  ParameterList& beam = p.sublist("Beam");
  beam.set("From", Teuchos::Array<double>(3, 0.0), "first end (node set \"start\")");
  beam.set("To", Teuchos::Array<double>(3, 0.0), "second end (node set \"end\"; \"mid\" the middle node)");
  beam.set("Elements", 8, "number of frame elements (even)");
  beam.set("Young's Modulus", 0.0, "E (Pa)");
  beam.set("Poisson's Ratio", 0.3, "nu");
  beam.set("Density", 0.0, "rho (kg/m^3)");
  beam.set("Area", 0.0, "A (m^2)");
  beam.set("Iy", 0.0, "second moment about local y (m^4)");
  beam.set("Iz", 0.0, "second moment about local z (m^4)");
  beam.set("Torsion Constant", 0.0, "J (m^4)");
  beam.set("Orientation", Teuchos::Array<double>(Teuchos::tuple<double>(0.0, 0.0, 1.0)),
           "a vector in the local x-y plane");
  beam.set("Clamp", "", "node set clamped (start, end, mid or ends; empty: none)");
  beam.set("Tip Mass", 0.0, "point mass at \"end\" (kg)");
  beam.sublist("Hinges", false, "name -> hinge at a station (theory §17): Station, Axis, Stiffness, Damping")
      .disableRecursiveValidation();
  // The lumped items of a Finite Element Model, on the beam's node sets
  // (start, end, mid, ends): landing gear, a fuselage's mass, supports.
  for (const char* key : {"Point Masses", "Springs", "Dampers", "Structural Damping", "Boundary Conditions"})
    beam.sublist(key, false, "as in a Finite Element Model, on the beam's node sets").disableRecursiveValidation();
  beam.set("Tip Inertia", Teuchos::Array<double>(3, 0.0),
           "principal moments Jxx Jyy Jzz of the tip mass about \"end\" (kg m^2; a disc)");
  p.sublist("Finite Element Model").disableRecursiveValidation();
  ParameterList& place = p.sublist("Placement");
  place.set("Axis", Teuchos::Array<double>(Teuchos::tuple<double>(0.0, 0.0, 1.0)), "rotation axis");
  place.set("Angle", 0.0, "rotation angle about the axis through the origin (degrees), applied first");
  place.set("Translation", Teuchos::Array<double>(3, 0.0), "then this translation (m)");
  ParameterList& rotor = p.sublist("Rotor");
  rotor.set("Mass", 0.0, "kg");
  rotor.set("Transverse Inertia", 0.0, "kg m^2");
  rotor.set("Axial Inertia", 0.0, "kg m^2");
  rotor.set("Free", false, "true: turns freely (its angle a coordinate); false: a motor holds its rate");
  ParameterList& spin = p.sublist("Spin");
  spin.set("Axis", Teuchos::Array<double>(Teuchos::tuple<double>(0.0, 0.0, 1.0)), "spin axis");
  spin.set("Origin", Teuchos::Array<double>(3, 0.0), "C: a point of the axis (A, R: the attachment point)");
  spin.set("Rate", 0.0, "nominal rate (rad/s)");
  spin.set("Frame", "Rotating", "A: Rotating (own frame) or Stationary (axisymmetric, parent's frame)");
  spin.set("Stress Stiffening", true, "centrifugal prestress in rotating frames");
  p.sublist("Reduction").disableRecursiveValidation();
  p.set("Copies", 1,
        "N identical copies in an azimuthal pattern about the parent's spin axis, sharing one reduction "
        "(named <name>[1] .. <name>[N]; doc/theory.md §15)");
  p.set("Copy Phase", 0.0, "angle of the first copy from the substructure as written (degrees)");
  return p;
}

fem::Vec3 vec3(const ParameterList& p, const std::string& key, const std::string& path,
               std::optional<std::vector<double>> fallback = std::nullopt) {
  const auto v = getNumbers(p, key, path, 3, fallback);
  return {v[0], v[1], v[2]};
}

/// A Beam's "Hinges" (theory §17): each at a station (m from "From") on an
/// interior node, which is split in two coincident nodes, the one toward
/// "From" keeping the elements before it (node set "<name>_inboard", the
/// hinge's first node) and a new one the elements after it
/// ("<name>_outboard", the second). Axis, Stiffness and Damping as in a
/// Finite Element Model's Hinges.
void addBeamHinges(const ParameterList& b, const std::string& path, int elements, double length,
                   mesh::Mesh& mesh, fem::FiniteElementModel& model) {
  if (!b.isSublist("Hinges")) return;
  const ParameterList& list = b.sublist("Hinges");
  std::vector<int> split;  // the interior node of each hinge
  for (auto it = list.begin(); it != list.end(); ++it) {
    const std::string name = list.name(it), hp = path + "/Hinges/" + name;
    CMS_INPUT_CHECK(!list.isSublist(name), hp << ": must be a list of keys (Station, Axis, Stiffness, Damping)");
    ParameterList h = list.sublist(name);
    CMS_INPUT_CHECK(h.isParameter("Node Set") || h.isParameter("To Node Set"),
                    hp << ": a Beam's hinge is placed by \"Station\", not by node sets (those are for a "
                          "\"Finite Element Model\")");
    CMS_INPUT_CHECK(!h.isParameter("Station"), hp << ": missing \"Station\" (m from \"From\", at a node)");
    const double station = getNumber(h, "Station", hp);
    const double spacing = length / elements, at = station / spacing;
    const long long node = std::llround(at);
    CMS_INPUT_CHECK(!(station > 0.0 && station < length) || std::abs(at - node) > 1e-9 * elements || node <= 0 ||
                        node >= elements,
                    hp << "/Station = " << station << " must be at an interior node of the beam: the nodes are every "
                       << spacing << " m (length " << length << ", Elements = " << elements << "), e.g. "
                       << spacing * std::clamp<long long>(node, 1, elements - 1));
    CMS_INPUT_CHECK(std::find(split.begin(), split.end(), static_cast<int>(node)) != split.end(),
                    hp << "/Station = " << station << ": another hinge is at that node; hinges in series need an "
                          "element between them");
    split.push_back(static_cast<int>(node));
    h.remove("Station");
    h.set("Node Set", name + "_inboard");
    h.set("To Node Set", name + "_outboard");
    model.hinges.push_back(fem::hingeFromParameters(name, h, hp));
    // The new node, coincident, takes over the element after the station.
    const auto twin = static_cast<std::int64_t>(mesh.nodeCount());
    mesh.nodeTags.push_back(mesh.nodeTags.size() + 1);
    for (int d = 0; d < 3; ++d) mesh.coordinates.push_back(mesh.coordinates[3 * node + d]);
    mesh::CellBlock& lines = mesh.groups.front().blocks.front();
    lines.nodes[2 * node] = twin;  // element `node` runs from node to node + 1
    for (auto [set, v] : {std::pair{name + "_inboard", static_cast<std::int64_t>(node)}, std::pair{name + "_outboard", twin}}) {
      CMS_INPUT_CHECK(mesh.hasGroup(set), hp << ": node set '" << set << "' exists already (two hinges named alike?)");
      mesh::PhysicalGroup pg{set, 0, static_cast<int>(mesh.groups.size()) + 1, {}};
      mesh::CellBlock blk;
      blk.type = mesh::CellType::Point1, blk.gmshType = 15, blk.nodesPerCell = 1;
      blk.nodes.push_back(v);
      blk.cellTags.push_back(static_cast<std::size_t>(3 * elements + 10 + v));
      pg.blocks.push_back(blk);
      mesh.groups.push_back(pg);
    }
  }
}

/// A straight frame beam from the "Beam" keys: the mesh of a segment with
/// node sets start, end, mid, ends, and its frame model.
std::shared_ptr<fem::FiniteElementModel> beamModel(const ParameterList& b, const std::string& name,
                                                   const std::string& path) {
  checkKeys(b, substructureKeys().sublist("Beam"), path);
  const fem::Vec3 p0 = vec3(b, "From", path), p1 = vec3(b, "To", path);
  const double n = getNumber(b, "Elements", path, 8.0);
  CMS_INPUT_CHECK(n < 2 || n > 1e6 || std::floor(n) != n || static_cast<long long>(n) % 2,
                  path << "/Elements = " << n << " must be an even integer from 2 to 1e6");
  const int elements = static_cast<int>(n);
  const double length = std::sqrt(std::pow(p1[0] - p0[0], 2) + std::pow(p1[1] - p0[1], 2) + std::pow(p1[2] - p0[2], 2));
  CMS_INPUT_CHECK(!(length > 0), path << ": \"From\" and \"To\" coincide");
  auto mesh = std::make_shared<mesh::Mesh>();
  mesh->source = path;
  for (int i = 0; i <= elements; ++i) {
    mesh->nodeTags.push_back(static_cast<std::size_t>(i + 1));
    for (int d = 0; d < 3; ++d) mesh->coordinates.push_back(p0[d] + (p1[d] - p0[d]) * i / elements);
  }
  mesh::PhysicalGroup beam{"beam", 1, 1, {}};
  mesh::CellBlock lines;
  lines.type = mesh::CellType::Line2, lines.gmshType = 1, lines.nodesPerCell = 2;
  for (int e = 0; e < elements; ++e) {
    lines.nodes.insert(lines.nodes.end(), {e, e + 1});
    lines.cellTags.push_back(static_cast<std::size_t>(e + 1));
  }
  beam.blocks.push_back(lines);
  mesh->groups.push_back(beam);
  auto points = [&](const std::string& g, std::vector<std::int64_t> nodes) {
    mesh::PhysicalGroup pg{g, 0, static_cast<int>(mesh->groups.size()) + 1, {}};
    mesh::CellBlock blk;
    blk.type = mesh::CellType::Point1, blk.gmshType = 15, blk.nodesPerCell = 1;
    for (auto v : nodes) blk.nodes.push_back(v), blk.cellTags.push_back(static_cast<std::size_t>(elements + 2 + v));
    pg.blocks.push_back(blk);
    mesh->groups.push_back(pg);
  };
  points("start", {0});
  points("end", {elements});
  points("mid", {elements / 2});
  points("ends", {0, elements});
  auto m = std::make_shared<fem::FiniteElementModel>();
  m->name = name;
  m->mesh = mesh;
  fem::IsotropicMaterial mat{getNumber(b, "Young's Modulus", path), getNumber(b, "Poisson's Ratio", path, 0.3),
                             getNumber(b, "Density", path)};
  mat.validate(path.c_str());
  m->materials["beam"] = mat;
  fem::ElementSet set;
  set.group = "beam";
  set.kind = fem::ElementSet::Kind::Frame;
  set.material = "beam";
  set.section.A = getNumber(b, "Area", path);
  set.section.Iy = getNumber(b, "Iy", path);
  set.section.Iz = getNumber(b, "Iz", path);
  set.section.J = getNumber(b, "Torsion Constant", path);
  set.section.orientation = vec3(b, "Orientation", path, std::vector<double>{0, 0, 1});
  {
    // Checked here to name the key (and the default a user never wrote): the
    // element's own check named only its coordinates (a review).
    const fem::Vec3& o = set.section.orientation;
    const fem::Vec3 axis{(p1[0] - p0[0]) / length, (p1[1] - p0[1]) / length, (p1[2] - p0[2]) / length};
    CMS_INPUT_CHECK(!fem::orientationAcross(axis, o),
                    path << "/Orientation = [" << o[0] << ", " << o[1] << ", " << o[2] << "]"
                         << (b.isParameter("Orientation") ? "" : " (the default)")
                         << " is parallel to the beam from \"From\" to \"To\": give an Orientation across it (a "
                            "vector in the local x-y plane)");
  }
  set.section.validate(path.c_str());
  m->elementSets.push_back(set);
  const std::string clamp = getString(b, "Clamp", path, std::string());
  if (!clamp.empty()) {
    CMS_INPUT_CHECK(clamp != "start" && clamp != "end" && clamp != "mid" && clamp != "ends",
                    path << "/Clamp = \"" << clamp << "\": must be start, end, mid or ends");
    m->fixed.push_back({"clamp", clamp, {}, true});
  }
  const double tip = getNumber(b, "Tip Mass", path, 0.0);
  CMS_INPUT_CHECK(tip < 0, path << "/Tip Mass = " << tip << " must be >= 0");
  const auto J = getNumbers(b, "Tip Inertia", path, 3, std::vector<double>{0, 0, 0});
  for (double v : J) CMS_INPUT_CHECK(v < 0, path << "/Tip Inertia: " << v << " must be >= 0");
  CMS_INPUT_CHECK(tip == 0 && (J[0] > 0 || J[1] > 0 || J[2] > 0), path << "/Tip Inertia needs a \"Tip Mass\"");
  if (tip > 0) m->pointMasses.push_back({"tip mass", "end", tip, {J[0], J[1], J[2], 0, 0, 0}});

  addBeamHinges(b, path, elements, length, *mesh, *m);
  ParameterList lumped(b);  // its Hinges are placed by station (addBeamHinges), not by node sets
  if (lumped.isSublist("Hinges")) lumped.remove("Hinges");
  fem::readLumpedItems(lumped, path, *m);
  try {
    m->validate();  // the lumped items' node sets
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  return m;
}

SubstructureSpec substructure(const ParameterList& p, const std::string& name, const std::string& path,
                              const std::string& baseDir, const fem::FiniteElementModel::MeshReader& readMesh) {
  checkKeys(p, substructureKeys(), path);
  SubstructureSpec s;
  s.name = name;
  const std::string kind = getString(p, "Kind", path);
  if (kind == "C") s.kind = SubstructureKind::Central;
  else if (kind == "E") s.kind = SubstructureKind::Elastic;
  else if (kind == "A") s.kind = SubstructureKind::Rotating;
  else if (kind == "R") s.kind = SubstructureKind::Rigid;
  else CMS_INPUT_CHECK(true, path << "/Kind = \"" << kind << "\": must be C, E, A or R");
  s.parent = getString(p, "Parent", path, std::string());
  if (p.isSublist("Attachment")) {
    const auto& a = p.sublist("Attachment");
    const std::string ap = path + "/Attachment";
    checkKeys(a, substructureKeys().sublist("Attachment"), ap);
    const std::string type = getString(a, "Type", ap, std::string("Node"));
    if (type == "Node") s.attachment.type = Attachment::Type::Node;
    else if (type == "RigidFit") s.attachment.type = Attachment::Type::RigidFit;
    else if (type == "Boolean") s.attachment.type = Attachment::Type::Boolean;
    else CMS_INPUT_CHECK(true, ap << "/Type = \"" << type << "\": must be Node, RigidFit or Boolean");
    s.attachment.parentNodes = getString(a, "Parent Nodes", ap);
    s.attachment.childNodes = getString(a, "Nodes", ap, std::string());
    if (a.isParameter("Point")) s.attachment.point = vec3(a, "Point", ap);
    if (a.isParameter("Copy Parent Nodes")) {
      CMS_INPUT_CHECK(!a.isType<Teuchos::Array<std::string>>("Copy Parent Nodes"),
                      ap << "/Copy Parent Nodes must be a list of node set names, e.g. [side0, side2, side4]");
      for (const auto& n : a.get<Teuchos::Array<std::string>>("Copy Parent Nodes")) s.copyParentNodes.push_back(n);
    }
  }
  const int sources = p.isSublist("Beam") + p.isSublist("Finite Element Model") + p.isSublist("Rotor");
  CMS_INPUT_CHECK(sources != 1, path << ": give exactly one of \"Beam\", \"Finite Element Model\" and \"Rotor\"");
  if (p.isSublist("Beam")) s.model = beamModel(p.sublist("Beam"), name, path + "/Beam");
  if (p.isSublist("Finite Element Model")) {
    try {
      auto m = fem::FiniteElementModel::fromParameters(p.sublist("Finite Element Model"), baseDir, readMesh);
      m.name = name;
      s.model = std::make_shared<fem::FiniteElementModel>(m);
    } catch (const InputError& e) {
      throw InputError(path + "/Finite Element Model: " + e.what());
    }
  }
  CMS_INPUT_CHECK(p.isSublist("Placement") && !p.isSublist("Finite Element Model"),
                  path << "/Placement: only a \"Finite Element Model\" is placed (a Beam is given by its ends)");
  if (p.isSublist("Placement")) {
    // A mesh made in its own axes, moved rigidly into the structure's:
    // x' = R x + t, R the rotation by Angle about Axis (Rodrigues); frame
    // section orientations turn with it.
    const auto& pl = p.sublist("Placement");
    const std::string pp = path + "/Placement";
    checkKeys(pl, substructureKeys().sublist("Placement"), pp);
    const fem::Vec3 a = vec3(pl, "Axis", pp, std::vector<double>{0, 0, 1});
    CMS_INPUT_CHECK(!(fem::norm(a) > 0), pp << "/Axis must be a nonzero vector");
    const double th = getNumber(pl, "Angle", pp, 0.0) * M_PI / 180.0;
    // Fixed components, springs and dampers are written per component of
    // the structure's axes; the mesh under them turns. One the rotation
    // does not map onto itself would act along other directions of the
    // placed body than of the mesh it was written for: refused, as for
    // Copies (a review found such a spring left as written, silently).
    const std::string variant = fem::rotationVariantItem(*s.model, fem::Rotation::about(a, th));
    CMS_INPUT_CHECK(!variant.empty(),
                    pp << ": the substructure's " << variant << " acts along the structure's axes, and turned by "
                       << th * 180 / M_PI << " degrees with its mesh it would act along others: give it the same "
                       << "values in every direction the rotation turns, or mesh the substructure in the "
                       << "structure's axes without Placement");
    s.model = fem::placedModel(*s.model, fem::Rotation::about(a, th), {0, 0, 0},
                               vec3(pl, "Translation", pp, std::vector<double>{0, 0, 0}));
  }
  if (p.isSublist("Rotor")) {
    const auto& r = p.sublist("Rotor");
    const std::string rp = path + "/Rotor";
    checkKeys(r, substructureKeys().sublist("Rotor"), rp);
    s.rotor = {getNumber(r, "Mass", rp), getNumber(r, "Transverse Inertia", rp), getNumber(r, "Axial Inertia", rp),
               getBool(r, "Free", rp, false)};
  }
  if (p.isSublist("Spin")) {
    const auto& sp = p.sublist("Spin");
    const std::string spp = path + "/Spin";
    checkKeys(sp, substructureKeys().sublist("Spin"), spp);
    synthesis::SpinRate rate;
    rate.axis = vec3(sp, "Axis", spp, std::vector<double>{0, 0, 1});
    rate.origin = vec3(sp, "Origin", spp, std::vector<double>{0, 0, 0});
    rate.rate = getNumber(sp, "Rate", spp);
    const std::string frame = getString(sp, "Frame", spp, std::string("Rotating"));
    CMS_INPUT_CHECK(frame != "Rotating" && frame != "Stationary",
                    spp << "/Frame = \"" << frame << "\": must be Rotating or Stationary");
    rate.frame = frame == "Rotating" ? fem::SpinDefinition::Frame::Rotating : fem::SpinDefinition::Frame::Stationary;
    rate.stressStiffening = getBool(sp, "Stress Stiffening", spp, true);
    // Keys the kind does not read were accepted and ignored (found by a
    // review): refused, each with what the kind does instead.
    CMS_INPUT_CHECK(sp.isParameter("Origin") && s.kind != SubstructureKind::Central,
                    spp << "/Origin: an " << kind << " substructure spins about its attachment point; only the "
                                                      "central substructure (C) takes a spin origin");
    CMS_INPUT_CHECK(rate.frame == fem::SpinDefinition::Frame::Stationary && s.kind != SubstructureKind::Rotating,
                    spp << "/Frame = Stationary: only an A substructure chooses its frame; "
                        << (s.kind == SubstructureKind::Central ? "the central substructure's frame spins with it"
                                                                : "a rigid rotor has none")
                        << " (Rotating, the default, says so)");
    CMS_INPUT_CHECK(sp.isParameter("Stress Stiffening") &&
                        (s.kind == SubstructureKind::Rigid || rate.frame == fem::SpinDefinition::Frame::Stationary),
                    spp << "/Stress Stiffening: no centrifugal prestress is formed "
                        << (s.kind == SubstructureKind::Rigid ? "for a rigid rotor" : "in a stationary frame"));
    s.spin = rate;
  }
  const double copies = getNumber(p, "Copies", path, 1.0);
  CMS_INPUT_CHECK(copies < 1 || copies > 1000 || std::floor(copies) != copies,
                  path << "/Copies = " << copies << " must be an integer from 1 to 1000");
  s.copies = static_cast<int>(copies);
  s.copyPhase = getNumber(p, "Copy Phase", path, 0.0) * M_PI / 180.0;
  CMS_INPUT_CHECK(!std::isfinite(s.copyPhase), path << "/Copy Phase must be finite (degrees)");
  CMS_INPUT_CHECK(s.copies > 1 && s.kind == SubstructureKind::Central,
                  path << "/Copies: the central substructure (C) cannot be copied; copies are placed about "
                          "their parent's spin axis");
  if (p.isSublist("Reduction")) {
    s.reduction = p.sublist("Reduction");
    promoteIntegers(s.reduction, *reduction::validParameters());
    try {
      Teuchos::ParameterList check(s.reduction);
      check.validateParametersAndSetDefaults(*reduction::validParameters());
    } catch (const std::exception& e) {
      throw InputError(path + "/Reduction: " + e.what());
    }
    // A Partition under another basis would be read and ignored.
    const std::string basis =
        s.reduction.isParameter("Basis") ? s.reduction.get<std::string>("Basis") : std::string("Admissible");
    CMS_INPUT_CHECK(s.reduction.isSublist("Partition") && basis != "Partitioned",
                    path << "/Reduction/Partition: read by Basis: Partitioned only, not by " << basis
                         << " (remove it, or set Basis: Partitioned)");
  }
  return s;
}

/// The .geo scripts the substructures' "Finite Element Model"s name, with
/// their "Mesh Parameters", as FiniteElementModel::fromParameters will ask
/// for them (FiniteElementModel::meshSource): the scene makes them ahead,
/// side by side (mesh/ScriptMeshes.hpp). Anything malformed is left out, for
/// that reader to report in its place.
std::vector<mesh::ScriptRequest> scriptRequests(const ParameterList& subs, const std::string& baseDir) {
  std::vector<mesh::ScriptRequest> out;
  for (auto it = subs.begin(); it != subs.end(); ++it) {
    const std::string& name = subs.name(it);
    if (!subs.isSublist(name) || !subs.sublist(name).isSublist("Finite Element Model")) continue;
    try {
      auto source = fem::FiniteElementModel::meshSource(subs.sublist(name).sublist("Finite Element Model"), baseDir);
      if (std::filesystem::path(source.file).extension() == ".geo")
        out.push_back({std::move(source.file), std::move(source.parameters)});
    } catch (const InputError&) {
    }
  }
  return out;
}

/// MPI_COMM_WORLD while MPI runs (every rank reads the scene), else none.
MPI_Comm sceneComm() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  return initialized && !finalized ? MPI_COMM_WORLD : MPI_COMM_NULL;
}

}  // namespace

Scene Scene::fromParameters(const ParameterList& p, const std::string& path) {
  const std::string top = path + ": Scene";
  checkKeys(p, sceneKeys(), top);
  Scene scene;
  scene.path = path;
  scene.name = getString(p, "Name", top, std::filesystem::path(path).stem().string());
  if (scene.name.empty()) scene.name = std::filesystem::path(path).stem().string();
  // The outputs are <output directory>/<Name>.json and the like: a name with
  // a path in it wrote outside that directory ("../x"), or failed only after
  // the whole computation ("nosuchdir/x").
  CMS_INPUT_CHECK(scene.name.find_first_of("/\\") != std::string::npos || scene.name == "." || scene.name == "..",
                  top << "/Name = \"" << scene.name
                      << "\": a name for the output files, not a path (no / or \\; --output chooses the directory)");
  scene.units = getString(p, "Units", top, std::string("SI"));
  CMS_INPUT_CHECK(scene.units != "SI", top << "/Units = \"" << scene.units << "\": only SI is supported");
  const std::string baseDir = std::filesystem::path(path).parent_path().string();
  CMS_INPUT_CHECK(!p.isSublist("Substructures"), top << ": missing \"Substructures\"");
  const auto& subs = p.sublist("Substructures");
  // The scripts meshed ahead, each once over the ranks and side by side
  // (Gmsh runs in a child process per script); the substructures below take
  // them in their turn. Those not taken are stopped when this returns.
  const std::string dir = baseDir.empty() ? "." : baseDir;
  mesh::ScriptMeshes ahead(scriptRequests(subs, dir), sceneComm());
  const fem::FiniteElementModel::MeshReader readMesh = [&](const std::string& file,
                                                           const std::map<std::string, double>& parameters) {
    auto m = ahead.take(file, parameters);
    return m ? std::move(*m) : mesh::readMesh(file, parameters);
  };
  for (auto it = subs.begin(); it != subs.end(); ++it) {
    const std::string name = subs.name(it);
    CMS_INPUT_CHECK(!subs.isSublist(name), top << "/Substructures/" << name << ": must be a list of keys");
    scene.structure.substructures.push_back(
        substructure(subs.sublist(name), name, top + "/Substructures/" + name, dir, readMesh));
  }
  scene.structure.freeReference = getString(p, "Free Reference", top, std::string());
  if (p.isSublist("Analysis")) {
    const auto& a = p.sublist("Analysis");
    const std::string ap = top + "/Analysis";
    checkKeys(a, sceneKeys().sublist("Analysis"), ap);
    const double modes = getNumber(a, "Number of Modes", ap, 10.0);
    CMS_INPUT_CHECK(modes < 1 || std::floor(modes) != modes || modes > 1e5,
                    ap << "/Number of Modes = " << modes << " must be an integer from 1 to 1e5");
    scene.solve.set("Number of Modes", static_cast<int>(modes));
    const std::string solver = getString(a, "Solver", ap, std::string("Auto"));
    CMS_INPUT_CHECK(solver != "Auto" && solver != "Dense" && solver != "Sparse",
                    ap << "/Solver = \"" << solver << "\": must be Auto, Dense or Sparse");
    scene.solve.set("Solver", solver);
    const double denseLimit = getNumber(a, "Dense Limit", ap, 1500.0);
    CMS_INPUT_CHECK(!(denseLimit >= 1) || std::floor(denseLimit) != denseLimit || denseLimit > 1e9,
                    ap << "/Dense Limit = " << denseLimit << " must be an integer from 1 to 1e9");
    scene.solve.set("Dense Limit", static_cast<int>(denseLimit));
    const std::string direct = getString(a, "Direct Solver", ap, std::string("Auto"));
    CMS_INPUT_CHECK(direct != "Auto" && direct != "CHOLMOD" && direct != "MUMPS",
                    ap << "/Direct Solver = \"" << direct << "\": must be Auto, CHOLMOD or MUMPS");
    scene.solve.sublist("Sparse Solver").set("Direct Solver", direct);
    const double frequencyTol = getNumber(a, "Frequency Tolerance", ap, 1e-5);
    CMS_INPUT_CHECK(!(frequencyTol >= 0.0) || !std::isfinite(frequencyTol),
                    ap << "/Frequency Tolerance = " << frequencyTol
                       << " must be finite and >= 0 (a relative eigenvalue error; 0 refines every damped mode)");
    scene.solve.sublist("Sparse Solver").set("Frequency Tolerance", frequencyTol);
    scene.solve.sublist("Dense Solver").set("Frequency Tolerance", frequencyTol);
    scene.targetAccuracy = getNumber(a, "Target Accuracy", ap, 0.0);
    CMS_INPUT_CHECK(!std::isfinite(scene.targetAccuracy) || scene.targetAccuracy < 0 || scene.targetAccuracy >= 0.1,
                    ap << "/Target Accuracy = " << scene.targetAccuracy
                       << " must be >= 0 and below 0.1 (a relative frequency error; 0: off)");
    scene.speedFactor = getNumber(a, "Speed Factor", ap, 1.0);
    CMS_INPUT_CHECK(!std::isfinite(scene.speedFactor) || scene.speedFactor < 0,
                    ap << "/Speed Factor = " << scene.speedFactor
                       << " must be finite and >= 0 (it multiplies every nominal spin rate; 0 = at rest)");
  } else {
    scene.solve.set("Number of Modes", 10);
  }
  if (p.isSublist("Output")) {
    const auto& o = p.sublist("Output");
    const std::string op = top + "/Output";
    checkKeys(o, sceneKeys().sublist("Output"), op);
    const std::string dir = getString(o, "Directory", op, std::string());
    if (!dir.empty())
      scene.outputDirectory = std::filesystem::path(dir).is_absolute()
                                  ? dir
                                  : (std::filesystem::path(baseDir.empty() ? "." : baseDir) / dir).string();
    scene.json = getBool(o, "JSON", op, true);
    scene.csv = getBool(o, "CSV", op, true);
  }
  try {
    scene.structure.validate();
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  // The size before anything is assembled, and a model that cannot fit
  // refused at once (not after minutes of assembly, or by the OOM killer).
  std::string largest;
  long long largestDofs = -1;
  for (const auto& s : scene.structure.substructures) {
    if (!s.model || !s.model->mesh) continue;
    bool frame = false;
    for (const auto& es : s.model->elementSets) frame |= es.kind == fem::ElementSet::Kind::Frame;
    const long long dofs = static_cast<long long>(s.model->mesh->nodeCount()) * (frame ? 6 : 3);
    scene.estimatedDofs += dofs * s.copies;  // a copied descendant is counted once: a lower bound
    if (dofs > largestDofs) {
      largestDofs = dofs;
      const auto& fe = p.sublist("Substructures").sublist(s.name);
      largest = top + "/Substructures/" + s.name +
                (fe.isSublist("Beam") ? "/Beam/Elements = " + std::to_string(s.model->mesh->nodeCount() - 1)
                                      : "/Finite Element Model/Mesh (" + s.model->mesh->source + ")");
    }
  }
  scene.estimatedBytes = Scene::kBytesPerDof * static_cast<double>(scene.estimatedDofs);
  // The least over the ranks, so that every rank (all read the scene)
  // decides alike; no MPI: this process alone.
  double available = availableMemoryBytes();
  if (sceneComm() != MPI_COMM_NULL) MPI_Allreduce(MPI_IN_PLACE, &available, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  CMS_INPUT_CHECK(scene.estimatedBytes > available,
                  largest << ": " << largestDofs << " DOFs (" << scene.estimatedDofs
                          << " in the model), which need at least " << std::setprecision(3) << scene.estimatedBytes / 1e9
                          << " GB, more than the " << available / 1e9
                          << " GB available (MemAvailable, ulimit -v, cgroup memory.max): make it coarser");
  return scene;
}

double availableMemoryBytes() { return cms::availableMemoryBytes(); }

Scene Scene::read(const std::string& path) { return read(path, {}); }

namespace {

/// A key of a block mapping written on line `line`: its text without quotes
/// and its indentation, or nothing for a line that is not "key:" or
/// "key: value" (a sequence item's "- " counts as indentation).
struct KeyLine {
  std::string key, value;
  std::size_t indent = 0;
  bool sequenceItem = false;
};

std::optional<KeyLine> keyLine(const std::string& line) {
  KeyLine k;
  std::size_t i = 0;
  while (i < line.size() && line[i] == ' ') ++i;
  if (i + 1 < line.size() && line[i] == '-' && line[i + 1] == ' ') {
    k.sequenceItem = true;
    for (i += 2; i < line.size() && line[i] == ' ';) ++i;
  }
  k.indent = i;
  if (i >= line.size() || line[i] == '#') return std::nullopt;
  std::size_t end;  // one past the key
  if (line[i] == '"' || line[i] == '\'') {
    const char q = line[i];
    end = i + 1;
    for (; end < line.size(); ++end) {
      if (q == '"' && line[end] == '\\') ++end;
      else if (line[end] == q) {
        if (q == '\'' && end + 1 < line.size() && line[end + 1] == '\'') ++end;  // '' inside '...'
        else break;
      }
    }
    if (end >= line.size()) return std::nullopt;
    k.key = line.substr(i + 1, end - i - 1);
    ++end;
    while (end < line.size() && line[end] == ' ') ++end;
    if (end >= line.size() || line[end] != ':') return std::nullopt;
  } else {
    if (std::string("[{&*!|>%@`?,").find(line[i]) != std::string::npos) return std::nullopt;
    end = i;
    while (end < line.size() && !(line[end] == ':' && (end + 1 == line.size() || line[end + 1] == ' ')) &&
           !(line[end] == '#' && line[end - 1] == ' '))
      ++end;
    if (end >= line.size() || line[end] != ':') return std::nullopt;
    k.key = line.substr(i, end - i);
    while (!k.key.empty() && k.key.back() == ' ') k.key.pop_back();
  }
  std::size_t v = end + 1;
  while (v < line.size() && line[v] == ' ') ++v;
  k.value = v < line.size() && line[v] != '#' ? line.substr(v) : std::string();
  return k;
}

/// Teuchos' YAML reader refuses a repeated key with a trace whose line is
/// that of the next token. A scan of the block mappings first names both
/// lines: "file:line: duplicate key 'X' (first at line N)". Flow mappings,
/// block scalars and anything else the scan does not follow are left to
/// the parser.
void checkDuplicateKeys(const std::string& text, const std::string& path) {
  struct Level {
    std::size_t indent;
    std::map<std::string, std::size_t> keys;  // key -> line
  };
  std::vector<Level> open;
  std::optional<std::size_t> blockScalar;  // indentation of the key that opened one
  int flowDepth = 0;                       // inside a flow collection spread over lines
  std::istringstream in(text);
  std::size_t number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t first = line.find_first_not_of(' ');
    if (first == std::string::npos || line[first] == '#') continue;
    if (line[first] == '\t') return;  // tabs: the parser's to report
    if (blockScalar) {
      if (first > *blockScalar) continue;
      blockScalar.reset();
    }
    if (flowDepth > 0) {
      for (char c : line) flowDepth += (c == '[' || c == '{') - (c == ']' || c == '}');
      if (flowDepth < 0) return;
      continue;
    }
    if (line.compare(first, 3, "---") == 0 || line.compare(first, 3, "...") == 0) {
      open.clear();
      continue;
    }
    const auto k = keyLine(line);
    if (!k) {
      if (line.compare(first, 2, "- ") == 0 || line.compare(first, 2, "-") == 0)
        while (!open.empty() && open.back().indent > first) open.pop_back();
      continue;
    }
    while (!open.empty() && open.back().indent > k->indent) open.pop_back();
    if (k->sequenceItem && !open.empty() && open.back().indent == k->indent) open.pop_back();  // a new item
    if (open.empty() || open.back().indent < k->indent) open.push_back({k->indent, {}});
    auto [at, fresh] = open.back().keys.emplace(k->key, number);
    CMS_INPUT_CHECK(!fresh, path << ":" << number << ": duplicate key '" << k->key << "' (first at line " << at->second
                                 << ")");
    const std::string& v = k->value;
    if (!v.empty() && (v[0] == '|' || v[0] == '>')) blockScalar = k->indent;
    if (!v.empty() && (v[0] == '[' || v[0] == '{')) {
      bool quoted = false;
      for (char c : v) {
        if (c == '"') quoted = !quoted;
        if (!quoted) flowDepth += (c == '[' || c == '{') - (c == ']' || c == '}');
      }
      if (flowDepth < 0) return;
    }
  }
}

/// The YAML text of a scene as a ParameterList named "Scene".
Teuchos::RCP<ParameterList> yamlScene(const std::string& text, const std::string& path) {
  checkDuplicateKeys(text, path);
  // yaml-cpp, a complete YAML parser (issue 17: Teuchos' rejected block
  // sequences and multi-line flow mappings); its messages name line and column.
  auto p = detail::parseYaml(text, path);
  CMS_INPUT_CHECK(p->name() != "Scene", path << ": the top-level key must be \"Scene\" (got \"" << p->name() << "\")");
  return p;
}

/// Sets "Mesh Parameters" on every substructure meshed from a .geo script.
void setMeshParameters(ParameterList& scene, const std::map<std::string, double>& values) {
  if (values.empty() || !scene.isSublist("Substructures")) return;
  auto& subs = scene.sublist("Substructures");
  for (auto it = subs.begin(); it != subs.end(); ++it) {
    if (!subs.isSublist(subs.name(it))) continue;
    auto& s = subs.sublist(subs.name(it));
    if (!s.isSublist("Finite Element Model")) continue;
    auto& fe = s.sublist("Finite Element Model");
    if (!fe.isType<std::string>("Mesh") || std::filesystem::path(fe.get<std::string>("Mesh")).extension() != ".geo")
      continue;
    // A "Mesh Parameters" that is not a list is left for the reader to
    // report, with its key path.
    if (fe.isParameter("Mesh Parameters") && !fe.isSublist("Mesh Parameters")) continue;
    for (const auto& [name, value] : values) fe.sublist("Mesh Parameters").set(name, value);
  }
}

}  // namespace

Scene Scene::read(const std::string& path, const std::map<std::string, double>& meshParameters) {
  std::ifstream in(path);
  CMS_INPUT_CHECK(!in, path << ": cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  if (std::filesystem::path(path).extension() == ".xml") {
    Teuchos::RCP<ParameterList> p;
    try {
      p = Teuchos::getParametersFromXmlString(text.str());
    } catch (const std::exception& e) {
      std::string what = e.what();
      throw InputError(path + ": not a valid scene file (" + what.substr(0, 600) + ")");
    }
    // Teuchos' XML reader does not keep the root list's name: accept
    // <ParameterList name="Scene"> as the root or as its only sublist.
    ParameterList& root = p->isSublist("Scene") && p->numParams() == 1 ? p->sublist("Scene") : *p;
    setMeshParameters(root, meshParameters);
    Scene s = fromParameters(root, path);
    s.text = text.str();
    return s;
  }
  auto p = yamlScene(text.str(), path);
  setMeshParameters(*p, meshParameters);
  Scene s = fromParameters(*p, path);
  s.text = text.str();
  return s;
}

Scene Scene::parse(const std::string& text, const std::string& path) {
  Scene s = fromParameters(*yamlScene(text, path), path);
  s.text = text;
  return s;
}

}  // namespace cms::scene
