// Assembly of the substructures of a structure and their interfaces
// (doc/theory.md §11.1-§11.4): frames and spin parameters from the tree,
// attachment maps H_s (parent DOFs -> attachment frame motion), the held
// DOFs of each child, the centrifugal prestress leaves first with each
// child's root reaction passed to its parent, and the rigid rotors' matrices.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include <Teuchos_Comm.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include "PartData.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/HeldDofs.hpp"
#include "cms/core/PeakMemory.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/fem/LumpedElements.hpp"

namespace cms::synthesis {

using fem::Component;
using fem::Vec3;

std::vector<double> AssembledStructure::Part::attachmentRow(const fem::Vec3& x, std::int64_t node, int component) const {
  if (!boolean()) {
    const auto r = detail::rigidRow({x[0] - point[0], x[1] - point[1], x[2] - point[2]}, component);
    return std::vector<double>(r.begin(), r.end());
  }
  std::vector<double> row(booleanDofs.size(), 0.0);
  for (std::size_t k = 0; k < booleanDofs.size(); ++k)
    if (booleanDofs[k].first == node && static_cast<int>(booleanDofs[k].second) == component) row[k] = 1.0;
  return row;
}

namespace {

using fem::cross;  // the vector algebra: cms/fem/Vec3.hpp
using fem::norm;
using fem::sub;
using fem::unit;

Vec3 nodePosition(const mesh::Mesh& mesh, std::int64_t n) {
  return {mesh.coordinates[3 * n], mesh.coordinates[3 * n + 1], mesh.coordinates[3 * n + 2]};
}

/// Node indices of a named set of a model's mesh, with the error naming both.
std::vector<std::int64_t> nodeSet(const SubstructureSpec& s, const std::string& set, const char* role) {
  const mesh::Mesh& mesh = *s.model->mesh;
  const bool known = mesh.hasGroup(set);  // a deck's names in any case, as Mesh compares them
  CMS_INPUT_CHECK(!known, "substructure '" << s.name << "': " << role << " node set '" << set
                                           << "' is not a physical group of " << mesh.source);
  auto nodes = mesh.nodeSet(set);
  CMS_INPUT_CHECK(nodes.empty(), "substructure '" << s.name << "': " << role << " node set '" << set << "' is empty");
  // A hinge's second node keeps only its hinge rotation as a row (theory
  // §17): its translations are the first node's, which the attachment maps
  // (built from the rows) would miss. Refused rather than clamped silently.
  for (const fem::HingeSet& h : s.model->hinges)
    for (std::int64_t b : mesh.nodeSet(h.toNodeSet))
      CMS_INPUT_CHECK(std::find(nodes.begin(), nodes.end(), b) != nodes.end(),
                      "substructure '" << s.name << "': " << role << " node set '" << set << "' holds node "
                                       << mesh.nodeTags[b] << ", the second node of hinge '" << h.name
                                       << "', which follows the hinge; use its first node set '" << h.nodeSet
                                       << "' instead");
  return nodes;
}

Vec3 centroid(const mesh::Mesh& mesh, const std::vector<std::int64_t>& nodes) {
  Vec3 c{0, 0, 0};
  for (auto n : nodes)
    for (int d = 0; d < 3; ++d) c[d] += mesh.coordinates[3 * n + d];
  for (double& v : c) v /= static_cast<double>(nodes.size());
  return c;
}

/// The bounding box (lo, hi) of `nodes` of `mesh` (every node when empty).
std::pair<Vec3, Vec3> boundingBox(const mesh::Mesh& mesh, const std::vector<std::int64_t>& nodes = {}) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  const auto take = [&](std::int64_t n) {
    for (int d = 0; d < 3; ++d)
      lo[d] = std::min(lo[d], mesh.coordinates[3 * n + d]), hi[d] = std::max(hi[d], mesh.coordinates[3 * n + d]);
  };
  if (nodes.empty())
    for (std::size_t n = 0; n < mesh.nodeCount(); ++n) take(static_cast<std::int64_t>(n));
  for (auto n : nodes) take(n);
  return {lo, hi};
}

/// Whether nodal DOFs (component c of a node at r from a point, c < 3 a
/// translation, else a rotation) fix every rigid motion (t, theta) about
/// that point: the rank test of N = sum x x^T over their rows x, about the
/// translations' centroid, in the parameters (t, L theta), L the RMS
/// radius of the translations' nodes about it.
/// A translation's row is then that of [I, -[r / L]x] and a rotation's
/// (weighed by L: the motion it makes at that radius) a unit row. N mixes
/// translations (~n) with rotations (~n L^2) otherwise, and a 10 um face was
/// refused as collinear in SI units (found by a review); scaled, the test
/// is the set's shape, not its size.
bool fixRigidMotion(const std::vector<std::pair<Vec3, int>>& dofs) {
  // About the translations' centroid: the rank does not depend on the point
  // (a change of point is an invertible map of (t, theta)), but the scaling
  // does, and a small face far from P read collinear from there (a review).
  Vec3 centre{0, 0, 0};
  int translations = 0;
  for (const auto& [r, c] : dofs)
    if (c < 3) {
      for (int d = 0; d < 3; ++d) centre[d] += r[d];
      ++translations;
    }
  if (translations > 0)
    for (double& x : centre) x /= translations;
  double L2 = 0.0;
  for (const auto& [r, c] : dofs)
    if (c < 3) L2 += std::pow(r[0] - centre[0], 2) + std::pow(r[1] - centre[1], 2) + std::pow(r[2] - centre[2], 2);
  const double L = translations > 0 ? std::sqrt(L2 / translations) : 0.0;
  double N[36] = {0};
  for (const auto& [r0, c] : dofs) {
    const Vec3 r = sub(r0, centre);
    const Vec3 s = L > 0.0 ? Vec3{r[0] / L, r[1] / L, r[2] / L} : r;
    const auto x = detail::rigidRow(s, c);
    for (int a = 0; a < 6; ++a)
      for (int b = 0; b < 6; ++b) N[a + 6 * b] += x[a] * x[b];
  }
  double w[6], work[64];
  int info = 0;
  Teuchos::LAPACK<int, double> lapack;
  lapack.SYEV('N', 'U', 6, N, 6, w, work, 64, &info);
  return info == 0 && w[0] > 1e-10 * w[5];
}

/// Whether a model is held by supports of its own: fixed DOFs, or a
/// grounded spring with some stiffness (a spring between its own nodes, or
/// a damper alone, holds nothing; found by a review).
bool heldByItsOwnSupports(const fem::FiniteElementModel& m) {
  if (!m.fixed.empty()) return true;
  for (const fem::SpringSet& s : m.springs)
    if (s.toNodeSet.empty() && std::any_of(s.stiffness.begin(), s.stiffness.end(), [](double k) { return k > 0.0; }))
      return true;
  return false;
}

/// H for a Node attachment (u_P = u_n + theta_n x (P - x_n), theta_P = theta_n)
/// or a RigidFit (least-squares rigid motion of the set's translations).
std::vector<std::vector<detail::NodalCoefficient>> attachmentMap(const SubstructureSpec& child,
                                                                const SubstructureSpec& parent, Vec3& point) {
  const mesh::Mesh& mesh = *parent.model->mesh;
  const auto nodes = nodeSet(parent, child.attachment.parentNodes, ("attachment of '" + child.name + "':").c_str());
  std::vector<std::vector<detail::NodalCoefficient>> H(6);
  if (child.attachment.point) {
    // A point given by the user may sit off the parent's nodes (a rotor's
    // centre, an offset bracket) but not off the parent itself: within its
    // bounding box grown by 10% of its diagonal.
    const auto [lo, hi] = boundingBox(mesh);
    const double margin = 0.1 * norm(sub(hi, lo));
    const Vec3& p = *child.attachment.point;
    for (int d = 0; d < 3; ++d)
      CMS_INPUT_CHECK(p[d] < lo[d] - margin || p[d] > hi[d] + margin,
                      "substructure '" << child.name << "': attachment point (" << p[0] << ", " << p[1] << ", " << p[2]
                                       << ") is not on its parent '" << parent.name << "' (which spans (" << lo[0]
                                       << ", " << lo[1] << ", " << lo[2] << ") to (" << hi[0] << ", " << hi[1] << ", "
                                       << hi[2] << "))");
  }
  if (child.attachment.type == Attachment::Type::Node) {
    CMS_INPUT_CHECK(nodes.size() != 1, "substructure '" << child.name << "': Node attachment set '"
                                                        << child.attachment.parentNodes << "' of '" << parent.name
                                                        << "' has " << nodes.size() << " nodes, not one "
                                                        << "(use RigidFit for a set)");
    const auto n = nodes.front();
    point = child.attachment.point.value_or(nodePosition(mesh, n));
    const Vec3 r = sub(point, nodePosition(mesh, n));
    for (int c = 0; c < 6; ++c) {
      const auto x = detail::rigidRow(r, c);  // u_P,c in terms of the node's (u, theta)
      for (int k = 0; k < 6; ++k)
        if (x[k] != 0.0) H[c].push_back({n, static_cast<Component>(k), x[k]});
    }
    return H;
  }
  point = child.attachment.point.value_or(centroid(mesh, nodes));
  // a = N^-1 sum_i A_i^T u_i, A_i = [I, -[r_i]x] (the rows of rigidRow).
  double N[36] = {0};
  for (auto n : nodes) {
    const Vec3 r = sub(nodePosition(mesh, n), point);
    for (int c = 0; c < 3; ++c) {
      const auto x = detail::rigidRow(r, c);
      for (int a = 0; a < 6; ++a)
        for (int b = 0; b < 6; ++b) N[a + 6 * b] += x[a] * x[b];
    }
  }
  std::vector<std::pair<Vec3, int>> translations;
  for (auto n : nodes)
    for (int c = 0; c < 3; ++c) translations.push_back({sub(nodePosition(mesh, n), point), c});
  CMS_INPUT_CHECK(!fixRigidMotion(translations),
                  "substructure '" << child.name << "': the RigidFit nodes '" << child.attachment.parentNodes << "' of '"
                                   << parent.name << "' (" << nodes.size()
                                   << " nodes) cannot fix a rigid motion: they are collinear or coincident");
  // Inverse of N by Cholesky.
  double work[64];
  int info = 0;
  Teuchos::LAPACK<int, double> lapack;
  int ipiv[6];
  double Ninv[36];
  std::copy(N, N + 36, Ninv);
  lapack.GETRF(6, 6, Ninv, 6, ipiv, &info);
  lapack.GETRI(6, Ninv, 6, ipiv, work, 64, &info);
  for (auto n : nodes) {
    const Vec3 r = sub(nodePosition(mesh, n), point);
    for (int c = 0; c < 3; ++c) {
      const auto x = detail::rigidRow(r, c);
      for (int a = 0; a < 6; ++a) {
        double v = 0;
        for (int b = 0; b < 6; ++b) v += Ninv[a + 6 * b] * x[b];
        if (v != 0.0) H[a].push_back({n, static_cast<Component>(c), v});
      }
    }
  }
  return H;
}

/// A Boolean (primal) interface: every node of the child's set is matched to
/// the parent node at the same position; a_k are the parent's DOFs there.
std::vector<std::vector<detail::NodalCoefficient>> booleanMap(
    const SubstructureSpec& child, const SubstructureSpec& parent, Vec3& point,
    std::vector<std::pair<std::int64_t, Component>>& childDofs) {
  const mesh::Mesh& pm = *parent.model->mesh;
  const mesh::Mesh& cm = *child.model->mesh;
  const auto pn = nodeSet(parent, child.attachment.parentNodes, ("interface of '" + child.name + "':").c_str());
  const auto cn = nodeSet(child, child.attachment.childNodes, "interface");
  double extent = 0;
  for (auto n : pn)
    for (int d = 0; d < 3; ++d) extent = std::max(extent, std::abs(pm.coordinates[3 * n + d]));
  const double tol = 1e-9 * std::max(1.0, extent);
  std::vector<std::vector<detail::NodalCoefficient>> H;
  for (auto c : cn) {
    const Vec3 x = nodePosition(cm, c);
    std::int64_t match = -1;
    for (auto n : pn)
      if (norm(sub(nodePosition(pm, n), x)) <= tol) match = n;
    CMS_INPUT_CHECK(match < 0, "substructure '" << child.name << "': Boolean interface node " << cm.nodeTags[c]
                                                << " at (" << x[0] << ", " << x[1] << ", " << x[2]
                                                << ") has no node of '" << parent.name << "' set '"
                                                << child.attachment.parentNodes
                                                << "' at the same position (the meshes must be compatible)");
    for (int k = 0; k < 6; ++k) {
      H.push_back({{match, static_cast<Component>(k), 1.0}});
      childDofs.push_back({c, static_cast<Component>(k)});
    }
  }
  point = centroid(cm, cn);
  return H;
}

/// Six statically determinate translation DOFs of a free body's reference
/// set (greedy: each adds a rigid motion the previous ones do not fix).
std::vector<detail::NodalCoefficient> referenceDofs(const mesh::Mesh& mesh, const std::vector<std::int64_t>& nodes,
                                                    const Vec3& point, const std::string& who) {
  std::vector<std::array<double, 6>> kept;
  std::vector<detail::NodalCoefficient> out;
  double scale = 0;
  for (auto n : nodes) scale = std::max(scale, norm(sub(nodePosition(mesh, n), point)));
  for (auto n : nodes)
    for (int c = 0; c < 3 && out.size() < 6; ++c) {
      auto x = detail::rigidRow(sub(nodePosition(mesh, n), point), c);
      for (int pass = 0; pass < 2; ++pass)
        for (const auto& q : kept) {
          double d = 0;
          for (int k = 0; k < 6; ++k) d += q[k] * x[k];
          for (int k = 0; k < 6; ++k) x[k] -= d * q[k];
        }
      double nx = 0;
      for (double v : x) nx += v * v;
      nx = std::sqrt(nx);
      if (nx < 1e-6 * std::max(1.0, scale)) continue;
      for (double& v : x) v /= nx;
      kept.push_back(x);
      out.push_back({n, static_cast<Component>(c), 1.0});
    }
  CMS_INPUT_CHECK(out.size() < 6, who << ": the free reference nodes cannot fix a rigid motion (collinear or "
                                         "coincident); give one node with rotations or three non-collinear nodes");
  return out;
}

using Part = AssembledStructure::Part;
using Parts = std::vector<std::shared_ptr<Part>>;

std::string who(const Part& p) { return "substructure '" + p.spec.name + "' (" + toString(p.spec.kind) + ")"; }

// 1. Tree order (pre-order from C): parents before children, so frames
// and attachment maps can be worked out in one pass; each part knows its
// parent's and children's indices.
Parts orderParts(const StructureDescription& d) {
  const int nsub = static_cast<int>(d.substructures.size());
  std::vector<std::vector<int>> children(nsub);
  int root = -1;
  for (int i = 0; i < nsub; ++i) {
    if (d.substructures[i].kind == SubstructureKind::Central) root = i;
    else children[d.find(d.substructures[i].parent)].push_back(i);
  }
  std::vector<int> order, partOf(nsub, -1);
  std::function<void(int)> visit = [&](int i) {
    partOf[i] = static_cast<int>(order.size());
    order.push_back(i);
    for (int c : children[i]) visit(c);
  };
  visit(root);
  Parts parts;
  for (int i : order) {
    auto p = std::make_shared<Part>();
    p->spec = d.substructures[i];
    p->parent = p->spec.parent.empty() ? -1 : partOf[d.find(p->spec.parent)];
    for (int c : children[i]) p->children.push_back(partOf[c]);
    parts.push_back(p);
  }
  return parts;
}

/// A rotor (A) spins in its own frame (Rotating: its attachment must be
/// immovable; about its parent frame's axis if that spins), in its parent's
/// (Stationary: axisymmetric, parent frame not spinning), or, stationary
/// inside a spinning frame, as a compound spin (theory §11.5).
void setRotorFrame(Part& p, const Part* parent, const Frame& inherited) {
  const Vec3 a = unit(p.spec.spin->axis);
  // A compound rotor's frame is its parent's spinning one (kind Rotating),
  // so the checks below did not see that this rotor would spin with it: it
  // got the compound rotor's rate in no term (refused, as for E and R).
  CMS_INPUT_CHECK(parent && parent->compound, who(p) << ": a rotor on the spinning rotor '" << parent->spec.name
                                                     << "' has periodic coefficients (not supported)");
  if (p.spec.spin->frame == fem::SpinDefinition::Frame::Stationary) {
    // The stationary form, alone or compound (on a spinning parent), is a
    // rotor spinning about its own axis (theory §9.4): every node on the
    // line through the attachment point along the spin axis. Each element
    // was checked parallel to the axis, never on it: a shaft 0.3 m off it
    // ran as if centred (an eccentric mass orbiting, periodic
    // coefficients; found by a review, and for a compound rotor by a
    // review of that fix).
    if (p.spec.model && p.spec.model->mesh) {
      const auto& mesh = *p.spec.model->mesh;
      double extent = 0.0, worst = 0.0;
      std::size_t at = 0;
      for (std::size_t n = 0; n < mesh.nodeCount(); ++n) {
        const Vec3 r = sub({mesh.coordinates[3 * n], mesh.coordinates[3 * n + 1], mesh.coordinates[3 * n + 2]}, p.point);
        extent = std::max(extent, norm(r));
        const double off = norm(cross(r, a));
        if (off > worst) worst = off, at = n;
      }
      CMS_INPUT_CHECK(worst > 1e-6 * extent,
                      who(p) << ": Frame: Stationary needs a rotor on its spin axis (the line through its attachment "
                             << "point along the axis), and node " << mesh.nodeTags[at] << " is " << worst
                             << " off it; a rotor off its axis orbits it, with periodic coefficients. Use Frame: "
                             << "Rotating");
    }
  }
  if (p.spec.spin->frame == fem::SpinDefinition::Frame::Stationary && inherited.spinning) {
    // Compound spin (theory §11.5): the parent frame's terms as for an
    // E, plus the rotor's own spin (G1 per omega) and the cross
    // stiffness per Omega omega, from a second, stationary assembly.
    CMS_INPUT_CHECK(inherited.kind == fem::SpinDefinition::Frame::Stationary,
                    who(p) << ": a stationary-frame rotor on the stationary-frame rotor '" << parent->spec.name
                           << "' (not supported)");
    p.frame = inherited;
    p.compound = true;
  } else if (p.spec.spin->frame == fem::SpinDefinition::Frame::Stationary) {
    p.frame.spinning = true;
    p.frame.kind = fem::SpinDefinition::Frame::Stationary;
    p.frame.axis = a;
    p.frame.origin = p.point;
    p.frame.coefficients = {{p.speedParam, 1.0}};
    p.frame.stressStiffening = false;
  } else {
    CMS_INPUT_CHECK(inherited.spinning && inherited.kind == fem::SpinDefinition::Frame::Stationary,
                    who(p) << ": a rotating-frame rotor on the stationary-frame rotor '" << parent->spec.name
                           << "' (not supported)");
    p.frame.spinning = true;
    p.frame.axis = a;
    p.frame.origin = p.point;
    p.frame.coefficients = inherited.coefficients;
    p.frame.stressStiffening = p.spec.spin->stressStiffening;
    if (inherited.spinning) {
      // Absolute spin (a . e) Omega_parent + omega about one fixed line: a
      // steady frame only if the two axes are one line, a = +-e.
      const double scale = std::max(1.0, norm(sub(p.point, inherited.origin)));
      CMS_INPUT_CHECK(norm(cross(a, inherited.axis)) > 1e-9 ||
                          norm(cross(sub(p.point, inherited.origin), inherited.axis)) > 1e-9 * scale,
                      who(p) << ": its spin axis is not the axis of its spinning parent's frame ('"
                             << parent->spec.name << "'): the coefficients would be periodic");
      // The parent's rates are about e, the rotor's frame about a: they count
      // with the sign of a . e. A counter-rotating rotor (a = -e) turns at
      // s_A - s_parent about a; adding them gave s_A + s_parent, the wrong
      // Coriolis sign and cross stiffness (theory §11.1).
      if (fem::dot(a, inherited.axis) < 0.0)
        for (auto& c : p.frame.coefficients) c.second = -c.second;
    }
    p.frame.coefficients.push_back({p.speedParam, 1.0});
  }
}

/// A child's attachment nodes are held to the attachment's rigid motion
/// wherever they lie: a gap between them and the parent's attachment is a
/// massless rigid link (an offset, by design: a solid child on a rigid
/// link, a shaft off its support's axis), which a misplaced mesh makes
/// without a word (a tip 1 m off its blade's end gave 2.48 Hz for 3.97;
/// found by a review). Noted, naming the largest gap, where it exceeds 1e-3
/// of the larger model's size from the parent's attachment nodes' box and
/// from the attachment point; "" otherwise.
std::string attachmentGapNote(const SubstructureSpec& child, const SubstructureSpec& parent, const Vec3& point) {
  if (child.kind == SubstructureKind::Rigid || !child.model || !child.model->mesh) return "";
  const mesh::Mesh& pm = *parent.model->mesh;
  const mesh::Mesh& cm = *child.model->mesh;
  const auto extent = [](const mesh::Mesh& m) {
    const auto [lo, hi] = boundingBox(m);
    return norm(sub(hi, lo));
  };
  const double tol = 1e-3 * std::max(extent(pm), extent(cm));
  const auto [lo, hi] =
      boundingBox(pm, nodeSet(parent, child.attachment.parentNodes, ("attachment of '" + child.name + "':").c_str()));
  double worst = 0.0;
  std::int64_t at = -1;
  for (auto n : nodeSet(child, child.attachment.childNodes, "attachment")) {
    const Vec3 x = nodePosition(cm, n);
    double box = 0.0;
    for (int d = 0; d < 3; ++d) {
      const double out = std::max({lo[d] - x[d], x[d] - hi[d], 0.0});
      box += out * out;
    }
    const double gap = std::min(std::sqrt(box), norm(sub(x, point)));
    if (gap > worst) worst = gap, at = n;
  }
  if (!(worst > tol)) return "";
  std::ostringstream os;
  os << child.name << ": its attachment node " << cm.nodeTags[static_cast<std::size_t>(at)] << " lies " << worst
     << " from " << parent.name << "'s attachment nodes '" << child.attachment.parentNodes
     << "': it hangs on a massless rigid link of that length (intended for an offset; a misplaced mesh otherwise)";
  return os.str();
}

// 2. Frames and spin parameters (§11.1) of one part, its parent's already
// set: its attachment point and map H, its own speed parameter, and its
// frame. C's spin is the frame of C and of every E below it; an A spins
// in its own frame or its parent's (setRotorFrame); an R spins relative to
// its parent's frame. Combinations with periodic coefficients are refused.
void setFrame(Part& p, const Part* parent, std::vector<SpeedParameter>& speeds) {
  if (p.spec.kind != SubstructureKind::Central) {
    // Attachment point and map (the parent's model exists: R has no children).
    if (p.spec.attachment.type == Attachment::Type::Boolean)
      p.H = booleanMap(p.spec, parent->spec, p.point, p.booleanDofs);
    else {
      p.H = attachmentMap(p.spec, parent->spec, p.point);
      p.gapNote = attachmentGapNote(p.spec, parent->spec, p.point);
    }
  }
  if (p.spec.spin) {
    p.speedParam = static_cast<int>(speeds.size());
    speeds.push_back({p.spec.name, p.spec.spin->rate});
  }
  const Frame inherited = parent ? parent->frame : Frame();
  switch (p.spec.kind) {
    case SubstructureKind::Central:
      if (p.spec.spin) {
        p.frame.spinning = true;
        p.frame.axis = unit(p.spec.spin->axis);
        p.frame.origin = p.spec.spin->origin;
        p.frame.coefficients = {{p.speedParam, 1.0}};
        p.frame.stressStiffening = p.spec.spin->stressStiffening;
      }
      break;
    case SubstructureKind::Elastic:
      CMS_INPUT_CHECK(parent->compound, who(p) << ": attached to the spinning rotor '" << parent->spec.name
                                               << "', it would spin with it: its coefficients are periodic "
                                                  "(not supported)");
      CMS_INPUT_CHECK(inherited.spinning && inherited.kind == fem::SpinDefinition::Frame::Stationary,
                      who(p) << ": attached to the stationary-frame rotor '" << parent->spec.name
                             << "', it would spin with it: its coefficients are periodic (not supported)");
      p.frame = inherited;
      break;
    case SubstructureKind::Rigid:
      CMS_INPUT_CHECK(parent->compound, who(p) << ": a rotor on the spinning rotor '" << parent->spec.name
                                               << "' has periodic coefficients (not supported)");
      CMS_INPUT_CHECK(inherited.spinning && inherited.kind == fem::SpinDefinition::Frame::Stationary,
                      who(p) << ": a rotor on the stationary-frame rotor '" << parent->spec.name
                             << "' has periodic coefficients (not supported)");
      p.frame = inherited;  // the wheel's transport frame
      break;
    case SubstructureKind::Rotating:
      setRotorFrame(p, parent, inherited);
      break;
  }
}

// 3. Held DOFs (attachment of an elastic child; a free C's reference, whose
// point is the node or the set's centroid) as nodal DOFs, before assembly:
// the prestress solves hold them.
void setHeldDofs(Part& p, const std::string& freeReference) {
  if (p.spec.kind == SubstructureKind::Rigid) return;
  const mesh::Mesh& mesh = *p.spec.model->mesh;
  if (p.spec.kind == SubstructureKind::Central) {
    if (freeReference.empty()) return;
    const auto nodes = nodeSet(p.spec, freeReference, "free reference");
    p.point = nodes.size() == 1 ? nodePosition(mesh, nodes.front()) : centroid(mesh, nodes);
    p.floating = true;
    if (nodes.size() == 1) {
      for (int c = 0; c < 6; ++c) p.heldDofs.push_back({nodes.front(), static_cast<Component>(c), 1.0});
    } else {
      p.heldDofs = referenceDofs(mesh, nodes, p.point, who(p));
    }
    return;
  }
  const auto nodes = nodeSet(p.spec, p.spec.attachment.childNodes, "attachment");
  for (auto n : nodes)
    for (int c = 0; c < 6; ++c) p.heldDofs.push_back({n, static_cast<Component>(c), 1.0});
  // Held only where its DOFs cannot fix a rigid motion (a solid's nodes on a
  // line, or one: translations only), a child turns freely about them. Said
  // here, before the assembly, naming the set: a Full basis called it
  // "ill-conditioned" and a reduced one "not positive definite", exit 3,
  // and a spinning one failed its prestress solve (found by a review). Not
  // where its own supports or grounded springs may hold it. A node carries
  // rotations exactly when a frame element uses it (the assembly's DOF
  // layout).
  if (heldByItsOwnSupports(*p.spec.model)) return;
  std::set<std::int64_t> frameNodes;
  for (const fem::ElementSet& es : p.spec.model->elementSets)
    if (es.kind == fem::ElementSet::Kind::Frame && mesh.hasGroup(es.group))
      for (const mesh::CellBlock& b : mesh.group(es.group).blocks) frameNodes.insert(b.nodes.begin(), b.nodes.end());
  std::vector<std::pair<Vec3, int>> held;
  bool rotations = false;
  for (auto n : nodes) {
    const bool frame = frameNodes.count(n) > 0;
    for (int c = 0; c < (frame ? 6 : 3); ++c) held.push_back({sub(nodePosition(mesh, n), p.point), c});
    rotations = rotations || frame;
  }
  CMS_INPUT_CHECK(!fixRigidMotion(held),
                  who(p) << ": its attachment nodes '" << p.spec.attachment.childNodes << "' (" << nodes.size()
                         << (nodes.size() == 1 ? " node" : " nodes") << (rotations ? "" : ", translations only")
                         << ") cannot hold it: "
                         << (nodes.size() == 1 ? "it would turn freely about the node"
                                               : "they lie on a line, and it would turn freely about it")
                         << "; attach it by nodes not on one line (a face), or by nodes with rotations");
}

/// The largest RigidFit node set whose link stiffness is formed: it couples
/// every pair of the set's translations (rank 3, dense over the set), 128
/// nodes being 1.5e5 entries; beyond, the assembly says it is not formed.
constexpr std::size_t kRigidFitLinkNodes = 128;

/// A RigidFit's link (theory §11.4): the rotation fitted to the parent's
/// set translations (H's rotation rows) and the set's centroid c, about
/// which a rigid turn of the set moves the child's points, so that a force
/// at x works on the link's second-order displacement theta x (theta x
/// (x - c)) / 2. Not formed (false) for another attachment or a set above
/// kRigidFitLinkNodes. `link` gets the rotation rows, `centre` c.
bool rigidFitLink(const Part& p, const Part& parent, fem::PrestressConditions::OffsetLoad& link, Vec3& centre) {
  if (p.spec.attachment.type != Attachment::Type::RigidFit || p.H.size() < 6) return false;
  const auto nodes = nodeSet(parent.spec, p.spec.attachment.parentNodes, "attachment");
  if (nodes.empty() || nodes.size() > kRigidFitLinkNodes) return false;
  link.node = nodes.front();
  for (int i = 0; i < 3; ++i) {
    link.rotation[static_cast<std::size_t>(i)].clear();
    for (const auto& h : p.H[static_cast<std::size_t>(3 + i)])
      link.rotation[static_cast<std::size_t>(i)].push_back({h.node, h.component, h.coefficient});
  }
  centre = centroid(*parent.spec.model->mesh, nodes);
  return true;
}

/// A force carried to the parent's node through a Node attachment's rigid
/// offset (a rigid rotor at its Point off the node) adds the link's
/// geometric stiffness to the parent's prestress: without it a 2 kg wheel
/// 0.04 m off a spinning hub's tip gave 4.124 Hz where the same wheel on a
/// stiff stub gives 4.313 (found by a review). An elastic child's forces go
/// node by node (passReactionToParent). RigidFit and Boolean: none here.
void addOffsetLoad(const Part& p, Part& parent, const Vec3& force) {
  fem::PrestressConditions::OffsetLoad link;
  Vec3 centre;
  if (norm(force) > 0.0 && rigidFitLink(p, parent, link, centre)) {  // a rotor on a RigidFit: its arm from the centroid
    link.arm = sub(p.point, centre);
    link.force = force;
    if (norm(link.arm) > 0.0) parent.childOffsetLoads.push_back(std::move(link));
    return;
  }
  if (p.spec.attachment.type != Attachment::Type::Node || p.H.empty() || p.H[0].empty()) return;
  const std::int64_t node = p.H[0].front().node;
  const Vec3 arm = sub(p.point, nodePosition(*parent.spec.model->mesh, node));
  if (norm(arm) == 0.0 || norm(force) == 0.0) return;
  parent.childOffsetLoads.push_back({node, force, arm});
}

// 4. A rigid rotor's matrices: M on a = (u_P, theta), the parent frame's
// transport terms (a point mass with inertia J, theory §9.3) and the
// wheel's own gyroscopic and frame-coupling terms (§11.5); its centrifugal
// force goes to the parent's prestress loads.
void buildRigidRotor(Part& p, Part& parent) {
  const Vec3 a = unit(p.spec.spin->axis);
  const auto& r = p.spec.rotor;
  fem::PointMass pm;
  pm.m = r.mass;
  pm.x = p.point;
  double J[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) J[i][j] = r.transverseInertia * ((i == j) - a[i] * a[j]) + r.axialInertia * a[i] * a[j];
  pm.inertia = {J[0][0], J[1][1], J[2][2], J[0][1], J[1][2], J[0][2]};
  // With a free spin angle phi: omega_z = w + phi' + a'.(Omega e + w_rel)
  // adds Ia phi'^2 / 2 + Ia phi' a.theta' (mass) and Ia Omega phi' (a x e).theta
  // (gyroscopic, per unit frame speed) to the Lagrangian (theory §11.5).
  const int n = r.spinCoordinate ? 7 : 6;
  auto grow = [n](const fem::ElementMatrix& E) {
    fem::ElementMatrix F(n);
    for (int i = 0; i < E.n; ++i)
      for (int j = 0; j < E.n; ++j) F(i, j) = E(i, j);
    return F;
  };
  p.rotor.M = grow(fem::pointMassMatrix(pm, 6));
  if (r.spinCoordinate) {
    p.rotor.M(6, 6) = r.axialInertia;
    for (int i = 0; i < 3; ++i) p.rotor.M(6, 3 + i) = p.rotor.M(3 + i, 6) = r.axialInertia * a[i];
  }
  const fem::ElementMatrix Gw = grow(fem::pointMassStationaryGyroscopic(pm, a));
  p.rotor.G.push_back({p.speedParam, Gw});
  if (!p.frame.spinning) return;
  const fem::SpinMatrices sm = fem::pointMassSpinMatrices(pm, fem::Spin{p.frame.axis, p.frame.origin}, 6);
  for (auto [i, ci] : p.frame.coefficients) {
    fem::ElementMatrix G = grow(sm.G1);
    for (double& v : G.a) v *= ci;
    if (r.spinCoordinate) {
      // L has phi' c.theta with c = Ia (a x e): F(theta, phi) = c, G = F^T - F.
      const Vec3 c = cross(a, p.frame.axis);
      for (int x = 0; x < 3; ++x) {
        G(6, 3 + x) += ci * r.axialInertia * c[x];
        G(3 + x, 6) -= ci * r.axialInertia * c[x];
      }
    }
    p.rotor.G.push_back({i, G});
    for (auto [j, cj] : p.frame.coefficients) {
      if (j < i) continue;
      fem::ElementMatrix K = grow(sm.KT1);
      for (double& v : K.a) v *= -(i == j ? ci * cj : 2.0 * ci * cj);
      p.rotor.K.push_back({i, j, K});
    }
    // theta-theta coupling of the wheel's momentum h = Ia w with the
    // frame's rotation: -Ia (sym(e a^T) - (e.a) I) per unit Omega w.
    const Vec3& e = p.frame.axis;
    const double ea = e[0] * a[0] + e[1] * a[1] + e[2] * a[2];
    fem::ElementMatrix K(n);
    for (int x = 0; x < 3; ++x)
      for (int y = 0; y < 3; ++y)
        K(3 + x, 3 + y) = -ci * r.axialInertia * (0.5 * (e[x] * a[y] + a[x] * e[y]) - (x == y ? ea : 0.0));
    p.rotor.K.push_back({std::min(i, p.speedParam), std::max(i, p.speedParam), K});
  }
  // Its centrifugal force on the parent's prestress, through H^T.
  p.rotor.f1.assign(sm.f1.begin(), sm.f1.end());
  p.rotor.f1.resize(n, 0.0);
  if (parent.frame.kind == fem::SpinDefinition::Frame::Rotating && parent.frame.stressStiffening) {
    for (std::size_t k = 0; k < 6; ++k)
      for (const auto& h : p.H[k]) parent.childLoads.push_back({h.node, h.component, h.coefficient * sm.f1[k]});
    addOffsetLoad(p, parent, {sm.f1[0], sm.f1[1], sm.f1[2]});
  }
}

// 5. One elastic part assembled: its model gets its frame's spin; its
// prestress holds its attachment and carries its children's reactions
// (§11.4), which is why parts are assembled leaves first. A compound rotor
// is assembled a second time in its own stationary frame. Collective.
void assemblePart(Part& p, const Teuchos::RCP<const Teuchos::Comm<int>>& comm, bool keepFactor) {
  fem::FiniteElementModel model = *p.spec.model;
  model.name = p.spec.name;
  if (p.frame.spinning)
    model.spin = fem::SpinDefinition{fem::Spin{p.frame.axis, p.frame.origin}, p.frame.kind,
                                     p.frame.stressStiffening};
  fem::PrestressConditions pc;
  if (p.frame.spinning && p.frame.kind == fem::SpinDefinition::Frame::Rotating && p.frame.stressStiffening) {
    for (const auto& h : p.heldDofs) pc.held.push_back({h.node, h.component, 0.0});
    pc.loads = p.childLoads;
    pc.offsetLoads = p.childOffsetLoads;
  }
  p.sub = substructure::Substructure::fromFiniteElementModel(model, comm, pc,
                                                             keepFactor ? &p.stiffnessFactor : nullptr);
  if (p.compound) {
    fem::FiniteElementModel own = *p.spec.model;
    own.name = p.spec.name;
    fem::SpinDefinition sd;
    sd.spin = fem::Spin{unit(p.spec.spin->axis), p.point};
    sd.frame = fem::SpinDefinition::Frame::Stationary;
    sd.stressStiffening = false;
    sd.frameAxis = p.frame.axis;
    own.spin = sd;
    p.stationary = substructure::Substructure::fromFiniteElementModel(own, comm);
  }
}

/// The order of step 5: leaves first (the reverse of tree order, parents
/// first), except that a copy waits for its prototype and comes right
/// after it, still before its parent (the prototype and its copies share
/// a parent, or have parents that are copies of one another, placed the
/// same way).
std::vector<std::size_t> assemblyOrder(const AssembledStructure& out) {
  const std::size_t n = out.numSubstructures();
  std::vector<std::size_t> order;
  std::vector<char> done(n, 0);
  std::map<std::size_t, std::vector<std::size_t>> waiting;
  for (std::size_t i = n; i-- > 0;) {
    const std::size_t q = out.prototypeOf(i);
    if (q != i && !done[q]) {
      waiting[q].push_back(i);
      continue;
    }
    order.push_back(i);
    done[i] = 1;
    for (std::size_t c : waiting[i]) order.push_back(c), done[c] = 1;
    waiting.erase(i);
  }
  return order;
}

/// Each node's loads or holds as its two triples (translations, rotations).
using NodalTriples = std::map<std::int64_t, std::array<double, 6>>;

/// The copy `p` made from its prototype `q`'s matrices turned
/// (Substructure::turned), when the copy is the prototype turned: the
/// models withCopies made for both, neither a compound part, the same held
/// DOFs (a set the turn maps onto itself) and the children's loads the
/// prototype's turned, to 64 eps of the sum of their magnitudes (the
/// children are copies whose reactions were turned, then carried through
/// the attachment's rigid rows and summed: each load's rounding is a few
/// eps of the magnitudes it was summed from, at most that sum). False with
/// the reason otherwise. Collective.
bool turnCopy(Part& p, const Part& q, std::string& why) {
  const auto& c = p.spec.copy;
  const auto& cq = q.spec.copy;
  if (!c || !cq || !p.spec.model || p.spec.model != c->model || q.spec.model != cq->model) {
    why = "its model or the prototype's is not the one Copies made";
    return false;
  }
  if (!q.sub || p.compound || q.compound) {
    why = q.sub ? "a rotor in the stationary form inside a spinning frame" : "the prototype has no matrices";
    return false;
  }
  const auto turn = turnFromPrototype(*c, *cq);
  const double eps = std::numeric_limits<double>::epsilon();
  // Held DOFs: the same (node, component) set, closed under the turn.
  std::set<std::pair<std::int64_t, int>> held, heldq;
  for (const auto& h : p.heldDofs) held.insert({h.node, static_cast<int>(h.component)});
  for (const auto& h : q.heldDofs) heldq.insert({h.node, static_cast<int>(h.component)});
  bool closed = held == heldq;
  for (const auto& [node, comp] : held) {
    const int base = comp < 3 ? 0 : 3;
    for (int d = 0; d < 3 && closed; ++d)
      closed = held.count({node, base + d}) || std::abs(turn.R[d][comp - base]) <= 16 * eps;
  }
  if (!closed) {
    why = "its held DOFs are not the prototype's turned";
    return false;
  }
  auto triples = [](const std::vector<fem::PrestressConditions::NodalValue>& loads) {
    NodalTriples t;
    for (const auto& l : loads) t[l.node][static_cast<std::size_t>(l.component)] += l.value;
    return t;
  };
  const NodalTriples mine = triples(p.childLoads), theirs = triples(q.childLoads);
  double total = 0.0, off = 0.0;  // sum of |load|: bounds the terms each load was summed from
  for (const auto& l : q.childLoads) total += std::abs(l.value);
  for (const auto& [node, v] : mine)
    if (!theirs.count(node))
      for (double x : v) off = std::max(off, std::abs(x));
  for (const auto& [node, v] : theirs) {
    const auto it = mine.find(node);
    for (int base : {0, 3})
      for (int d = 0; d < 3; ++d) {
        double turned = 0.0;
        for (int e = 0; e < 3; ++e) turned += turn.R[d][e] * v[static_cast<std::size_t>(base + e)];
        const double have = it == mine.end() ? 0.0 : it->second[static_cast<std::size_t>(base + d)];
        off = std::max(off, std::abs(have - turned));
      }
  }
  if (off > 64 * eps * total) {
    why = "its children's prestress loads are not the prototype's turned";
    return false;
  }
  std::optional<fem::SpinDefinition> spin = p.spec.model->spin;
  if (p.frame.spinning)
    spin = fem::SpinDefinition{fem::Spin{p.frame.axis, p.frame.origin}, p.frame.kind, p.frame.stressStiffening};
  fem::FiniteElementModel model = *p.spec.model;
  model.name = p.spec.name;
  auto s = substructure::Substructure::turned(*q.sub, model, spin, turn, c->origin, why);
  if (!s) return false;
  p.sub = std::move(*s);
  p.matricesTurned = true;
  return true;
}

/// A prestressed part's reaction, as generalised forces on its attachment
/// coordinates a (F_a = -X^T r), passed to its parent through H^T when both
/// spin in the same frame (an A on an immovable attachment: the support
/// takes it).
void passReactionToParent(const Part& p, Part& parent) {
  if (parent.frame.coefficients != p.frame.coefficients) return;
  std::vector<double> Fa(p.H.size(), 0.0);
  const mesh::Mesh& mesh = *p.spec.model->mesh;
  for (const auto& r : p.sub->prestressReactions()) {
    const auto x = p.attachmentRow(nodePosition(mesh, r.node), r.node, static_cast<int>(r.component));
    for (std::size_t k = 0; k < Fa.size(); ++k) Fa[k] -= x[k] * r.value;
  }
  for (std::size_t k = 0; k < Fa.size(); ++k)
    if (Fa[k] != 0.0)  // a Boolean interface's rotations at solid nodes carry nothing
      for (const auto& h : p.H[k]) parent.childLoads.push_back({h.node, h.component, h.coefficient * Fa[k]});
  // The rigid link's geometric stiffness (theory §11.4), each reaction's
  // force on its own arm from the parent's node, x_i - x_n: the link runs
  // to the child's nodes, not only to P. The total force on P - x_n alone
  // lost the part from P to the child's nodes: a blade whose root node sat
  // 0.1 m off the hub's tip, without a Point, was 2.9% low at 30 rad/s
  // against the same blade on a stiff stub (found by a review). Only the
  // forces: a moment carried rigidly does no second-order work here.
  // A RigidFit: the same with the rotation fitted to the parent's set and
  // the arms from the set's centroid (a 2 kg arm 0.1 m off a spinning bar's
  // tip face was 0.08-0.34% low against a stiff stub; found by a review).
  fem::PrestressConditions::OffsetLoad fitted;
  Vec3 centre;
  const bool fit = rigidFitLink(p, parent, fitted, centre);
  if (!fit && (p.spec.attachment.type != Attachment::Type::Node || p.H.empty() || p.H[0].empty())) return;
  const std::int64_t n = fit ? fitted.node : p.H[0].front().node;
  const Vec3 xn = fit ? centre : nodePosition(*parent.spec.model->mesh, n);
  std::map<std::int64_t, Vec3> forces;
  for (const auto& r : p.sub->prestressReactions())
    if (static_cast<int>(r.component) < 3) forces[r.node][static_cast<int>(r.component)] -= r.value;
  for (const auto& [node, f] : forces) {
    const Vec3 arm = sub(nodePosition(mesh, node), xn);
    if (!(norm(arm) > 0.0 && norm(f) > 0.0)) continue;
    fem::PrestressConditions::OffsetLoad load = fit ? fitted : fem::PrestressConditions::OffsetLoad{};
    load.node = n, load.force = f, load.arm = arm;
    parent.childOffsetLoads.push_back(std::move(load));
  }
}

/// A RigidFit over more than kRigidFitLinkNodes nodes: the link's
/// second-order term (theory §11.4, rigidFitLink) is not formed, and where
/// the child's attachment nodes sit off the set (an offset, a Point) its
/// frequencies come out slightly low (0.08-0.34% for a 2 kg arm 0.1 m off a
/// bar's tip at 30 rad/s, against a stiff stub, when no RigidFit formed
/// it). Said: the note, or "".
std::string rigidFitLinkNote(const Part& p, const Part& parent) {
  // (The parent is assembled after its children: its frame, not its matrices, says it is prestressed.)
  const bool parentPrestressed = parent.frame.spinning && parent.frame.kind == fem::SpinDefinition::Frame::Rotating &&
                                 parent.frame.stressStiffening;
  if (p.spec.attachment.type != Attachment::Type::RigidFit || !parentPrestressed ||
      parent.frame.coefficients != p.frame.coefficients)
    return "";
  const auto parentNodes = nodeSet(parent.spec, p.spec.attachment.parentNodes, "attachment");
  const auto childNodes = nodeSet(p.spec, p.spec.attachment.childNodes, "attachment");
  if (parentNodes.size() <= kRigidFitLinkNodes || childNodes.empty()) return "";
  const auto& pm = *parent.spec.model->mesh;
  const Vec3 c = centroid(pm, parentNodes);
  const Vec3 x = centroid(*p.spec.model->mesh, childNodes);
  const auto [lo, hi] = boundingBox(pm);
  const double link = norm(sub(x, c));
  if (!(link > 1e-3 * norm(sub(hi, lo)))) return "";
  std::ostringstream os;
  os << p.spec.name << ": spinning on a RigidFit " << link << " from the centroid of " << parent.spec.name
     << "'s nodes '" << p.spec.attachment.parentNodes
     << "': the link's geometric stiffness is not formed for a RigidFit over more than " << kRigidFitLinkNodes
     << " nodes (it would couple every pair of them; theory §11.4), so its frequencies are slightly low (0.1-0.3% "
        "for a 0.1 m link in a review's case); attach it by fewer nodes, or model the offset as a stiff member and "
        "attach by Node";
  return os.str();
}

/// A free structure spins steadily only about a principal axis through its
/// centre of mass: otherwise its centrifugal loads do not balance and the
/// reference carries a reaction (theory §11.4). There is then no steady
/// state to linearise about: refuse rather than answer.
void checkFreeSpinBalances(const Part& c) {
  double reaction = 0.0, load = c.sub->f1()->getVector(0)->norm2();
  for (const auto& r : c.sub->prestressReactions()) reaction = std::max(reaction, std::abs(r.value));
  for (const auto& l : c.childLoads) load += std::abs(l.value);
  CMS_INPUT_CHECK(reaction > 1e-6 * load,
                  who(c) << ": the free structure's centrifugal loads do not balance (reaction " << reaction
                         << " at the reference, loads " << load << ", per (rad/s)^2): the spin axis is not a "
                            "principal axis through the centre of mass, so there is no steady spin to "
                            "linearise about");
}

// 6a. Held nodal DOFs as sorted rows of the part's own layout; a free
// reference must give the six of a rigid motion.
void resolveHeldRows(Part& p, const std::string& freeReference) {
  const auto& t = p.sub->dofs();
  for (const auto& h : p.heldDofs) {
    const long long r = t.row(h.node, h.component);
    if (r >= 0) p.held.push_back(static_cast<GlobalOrdinal>(r));
  }
  std::sort(p.held.begin(), p.held.end());
  p.held.erase(std::unique(p.held.begin(), p.held.end()), p.held.end());
  if (p.floating)
    CMS_INPUT_CHECK(p.held.size() != 6,
                    who(p) << ": the free reference '" << freeReference << "' gives " << p.held.size()
                           << " DOFs, not the six of a rigid motion (one node needs rotations)");
}

// 6b. The attachment map H as rows of the parent's layout, and the checks
// only the layouts allow: a Node attachment needs the parent node's
// rotations, a Boolean interface a parent DOF for each child DOF, and a
// rotor spinning in its own frame an immovable attachment.
void resolveAttachmentRows(Part& p, const Part& parent) {
  const auto& t = parent.sub->dofs();
  bool rotations = false;
  p.Hrows.assign(p.H.size(), {});
  for (std::size_t k = 0; k < p.H.size(); ++k)
    for (const auto& h : p.H[k]) {
      const long long r = t.row(h.node, h.component);
      if (h.component >= Component::RX && r >= 0) rotations = true;
      if (r >= 0) p.Hrows[k].push_back({static_cast<GlobalOrdinal>(r), h.coefficient});
    }
  if (p.spec.attachment.type == Attachment::Type::Node) {
    const auto n = p.H[3].empty() ? -1 : p.H[3].front().node;
    bool anyRow = false;
    for (const auto& h : p.Hrows) anyRow = anyRow || !h.empty();
    CMS_INPUT_CHECK(anyRow && !rotations && n >= 0 && t.row(n, Component::RX) < 0 && t.row(n, Component::RY) < 0 &&
                        t.row(n, Component::RZ) < 0 && t.row(n, Component::UX) >= 0,
                    who(p) << ": the parent node in '" << p.spec.attachment.parentNodes << "' of '"
                           << parent.spec.name << "' has no rotational DOFs; a solid needs a RigidFit attachment");
  }
  if (p.boolean()) {
    // Each child DOF needs a parent DOF: a component the parent's node does
    // not carry (a frame child on a solid parent) would be clamped silently.
    const auto& ct = p.sub->dofs();
    for (std::size_t k = 0; k < p.booleanDofs.size(); ++k) {
      const auto [cnode, comp] = p.booleanDofs[k];
      const auto pnode = p.H[k].front().node;
      const bool parentHasNode = t.offsets[pnode + 1] > t.offsets[pnode];
      CMS_INPUT_CHECK(ct.row(cnode, comp) >= 0 && t.row(pnode, comp) < 0 && parentHasNode &&
                          comp >= Component::RX && t.row(pnode, Component::RX) < 0 &&
                          t.row(pnode, Component::RY) < 0 && t.row(pnode, Component::RZ) < 0,
                      who(p) << ": Boolean interface node " << ct.nodeIds[cnode] << " has rotations, the node of '"
                             << parent.spec.name << "' it meets has none (use a Node or RigidFit attachment)");
    }
  }
  if (p.spec.kind == SubstructureKind::Rotating && !p.compound &&
      p.frame.kind == fem::SpinDefinition::Frame::Rotating) {
    bool moves = false;
    for (const auto& h : p.Hrows) moves = moves || !h.empty();
    // A rotor turning in its own frame on a moving attachment (a hub on an
    // airframe): its coefficients are periodic in the hub azimuth, which
    // the multi-blade transform or Floquet analysis handles (theory §16.8).
    // Its own attachment coordinates b stand between it and the parent.
    CMS_INPUT_CHECK(moves && (parent.frame.spinning || p.boolean()),
                    who(p) << ": spins in its own frame relative to '" << parent.spec.name
                           << "', whose attachment moves" << (p.boolean() ? " through a Boolean interface" : "")
                           << (parent.frame.spinning ? " in a spinning frame" : "")
                           << ": not supported. Supported: an immovable attachment, a Node or RigidFit attachment to "
                              "a parent that does not spin (a hub on an airframe: theory §16.8), or \"Frame: "
                              "Stationary\" for an axisymmetric rotor");
    p.movingHub = moves;
  }
}

// 7. A Boolean interface deforms, so holding it in the child's prestress
// solve is not exact (K Psi != 0): solve the coupled static problem of one
// frame family (the parts spinning with these coefficients) on the truth
// model and give each of its substructures its own part of u1, reassembled
// (theory §11.4). Returns how many were reassembled. Collective.
int solveFamilyPrestress(const AssembledStructure& out, const std::vector<std::pair<int, double>>& family) {
  const Parts& parts = out.parts();
  const auto comm = out.comm();
  const auto truth = SynthesizedStructure::synthesize(out, true);
  const auto& T = truth.transforms();
  auto K = truth.system(std::vector<double>(out.speeds().size(), 0.0)).K;
  if (out.freeFloating()) K = holdDofsScaled(*K, {0, 1, 2, 3, 4, 5});
  MultiVector f(truth.coordinateMap(), 1);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const Part& q = *parts[k];
    if (q.frame.coefficients != family) continue;
    if (q.prestressed()) {
      T[k]->apply(*q.sub->f1(), f, Teuchos::TRANS, 1.0, 1.0);
    } else if (q.spec.kind == SubstructureKind::Rigid && !q.rotor.f1.empty()) {
      MultiVector fr(T[k]->getRangeMap(), 1);
      for (std::size_t l = 0; l < fr.getLocalLength(); ++l)
        fr.replaceLocalValue(l, 0, q.rotor.f1[T[k]->getRangeMap()->getGlobalElement(static_cast<LocalOrdinal>(l))]);
      T[k]->apply(fr, f, Teuchos::TRANS, 1.0, 1.0);
    }
  }
  if (out.freeFloating()) zeroHeldRows(f, {0, 1, 2, 3, 4, 5});
  SparseDirectSolver solver(K, "CHOLMOD");
  if (solver.factor() != SparseDirectSolver::Outcome::Factored)
    throw NumericalError("structure: the coupled centrifugal prestress needs a positive definite stiffness "
                         "(CHOLMOD: " + solver.failure() + ")");
  MultiVector q1(truth.coordinateMap(), 1);
  solver.solve(f, q1);
  int count = 0;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    Part& q = *parts[k];
    if (!q.prestressed() || q.frame.coefficients != family) continue;
    const auto map = T[k]->getRangeMap();
    MultiVector u(map, 1);
    T[k]->apply(q1, u);
    const auto n = static_cast<GlobalOrdinal>(q.sub->dofs().rows());
    auto rep = Teuchos::rcp(new Map(n, 0, comm, Tpetra::LocallyReplicated));
    MultiVector ur(rep, 1);
    ur.doImport(u, Tpetra::Import<>(map, rep), Tpetra::INSERT);
    fem::FiniteElementModel model = *q.spec.model;
    model.name = q.spec.name;
    model.spin = fem::SpinDefinition{fem::Spin{q.frame.axis, q.frame.origin}, q.frame.kind, true};
    fem::PrestressConditions pc;
    auto v = ur.getData(0);
    pc.displacement.assign(v.begin(), v.end());
    pc.offsetLoads = q.childOffsetLoads;
    q.sub = substructure::Substructure::fromFiniteElementModel(model, comm, pc);
    q.stiffnessFactor.reset();  // a new K object: the reduction factors it itself
    q.matricesTurned = false;   // assembled here, a turned copy too
    q.prestressSolvedGlobally = true;
    ++count;
  }
  return count;
}

}  // namespace

const SubstructureSpec& AssembledStructure::substructure(std::size_t k) const { return parts_.at(k)->spec; }

std::vector<long long> AssembledStructure::heldRows(std::size_t k) const {
  const auto& held = parts_.at(k)->held;
  return {held.begin(), held.end()};
}

std::size_t AssembledStructure::prototypeOf(std::size_t k) const {
  const auto& copy = parts_.at(k)->spec.copy;
  if (!copy) return k;
  for (std::size_t i = 0; i < parts_.size(); ++i)
    if (parts_[i]->spec.name == copy->prototype) return i;
  return k;
}

fem::Vec3 AssembledStructure::attachmentPoint(std::size_t k) const { return parts_.at(k)->point; }

const substructure::Substructure* AssembledStructure::assembled(std::size_t k) const {
  return parts_.at(k)->sub ? &*parts_.at(k)->sub : nullptr;
}

std::string AssembledStructure::steadySpinDefect(const std::vector<double>& speeds) const {
  if (relativeMomenta_.empty()) return "";
  const Part& c = *parts_.front();
  // Each rotor's momentum h_i = omega_i J_i a_i turns with its frame, at
  // that frame's rate W_i about e (C's, or an A's that spins about the same
  // axis with it: found by a review): the torque sum W_i e x h_i must
  // vanish. The rotors' own sizes give the scale of a cancellation (a
  // counter-spinning pair) that is exact but for rounding.
  Vec3 torque{0, 0, 0}, across{0, 0, 0};
  double scale = 0.0, momentum = 0.0;
  for (const auto& r : relativeMomenta_) {
    const double w = speeds.at(static_cast<std::size_t>(r.speedParameter));
    double W = 0.0;
    for (auto [i, ci] : r.frame) W += ci * speeds.at(static_cast<std::size_t>(i));
    const Vec3 h{w * r.perUnitRate[0], w * r.perUnitRate[1], w * r.perUnitRate[2]};
    const Vec3 t = cross(r.frameAxis, h), e = cross(c.frame.axis, h);
    for (int k = 0; k < 3; ++k) torque[k] += W * t[k], across[k] += e[k];
    scale += std::abs(W) * std::abs(w) * norm(r.perUnitRate);
  }
  momentum = norm(across);
  if (!(norm(torque) > 1e-9 * scale)) return "";
  std::ostringstream os;
  os << "the rotors spinning relative to the free-floating '" << c.spec.name << "' carry angular momentum "
     << momentum << " N m s across its spin axis: keeping it turning with their frames needs a steady torque "
     << norm(torque) << " N m, which nothing applies to a free body, so there is no steady spin to "
     << "linearise about at these speeds; align the rotors' axes with the spin axis (or let their momenta cancel), "
     << "or clamp the structure";
  return os.str();
}

std::vector<double> AssembledStructure::nominalSpeeds() const {
  std::vector<double> s;
  for (const auto& p : speeds_) s.push_back(p.nominal);
  return s;
}

std::vector<std::pair<std::string, long long>> AssembledStructure::substructureDofs() const {
  std::vector<std::pair<std::string, long long>> out;
  for (const auto& p : parts_) out.emplace_back(p->spec.name, p->sub ? p->sub->dofs().rows() : 6);
  return out;
}

/// The angular momentum per unit relative spin rate, J a (a vector in the
/// structure's axes), of every part that spins relative to its frame: a
/// rigid rotor's axial inertia along its axis, a stationary-frame elastic
/// rotor's X^T M X a about its attachment point (X the rigid rotations'
/// fields). For the steady-spin check of a free structure
/// (AssembledStructure::steadySpinDefect). Collective.
std::vector<AssembledStructure::RelativeMomentum> relativeMomenta(const Parts& parts) {
  std::vector<AssembledStructure::RelativeMomentum> out;
  for (const auto& p : parts) {
    if (!p->spec.spin || !(p->spec.kind == SubstructureKind::Rigid || p->compound)) continue;
    const Vec3 a = unit(p->spec.spin->axis);
    if (p->spec.kind == SubstructureKind::Rigid) {
      const double J = p->spec.rotor.axialInertia;
      out.push_back({p->speedParam, {J * a[0], J * a[1], J * a[2]}, p->frame.coefficients, p->frame.axis});
      continue;
    }
    const auto& sub = *p->sub;
    const auto& t = sub.dofs();
    const auto map = sub.map();
    const auto nodeOf = t.rowNodes();
    MultiVector X(map, 3), v(map, 1), Mv(map, 1);
    for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
      const auto g = map->getGlobalElement(static_cast<LocalOrdinal>(l));
      const auto nd = nodeOf[g];
      const auto x = detail::rigidRow({t.coordinates[3 * nd] - p->point[0], t.coordinates[3 * nd + 1] - p->point[1],
                                       t.coordinates[3 * nd + 2] - p->point[2]},
                                      static_cast<int>(t.components[g]));
      double va = 0.0;
      for (int k = 0; k < 3; ++k) X.replaceLocalValue(l, k, x[3 + k]), va += x[3 + k] * a[k];
      v.replaceLocalValue(l, 0, va);
    }
    sub.apply(substructure::Matrix::M, v, Mv);
    Vec3 h{0, 0, 0};
    for (int k = 0; k < 3; ++k) h[k] = X.getVector(k)->dot(*Mv.getVector(0));
    out.push_back({p->speedParam, h, p->frame.coefficients, p->frame.axis});
  }
  return out;
}

// The phases in the order they happen (theory §11.1-§11.5); each is a
// function above with the why.
AssembledStructure AssembledStructure::assemble(const StructureDescription& description,
                                                const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  const auto t0 = std::chrono::steady_clock::now();
  const StructureDescription d = description.withCopies();  // 0. "Copies: N" made (theory §15)
  AssembledStructure out;
  out.comm_ = comm;
  out.free_ = !d.freeReference.empty();
  out.parts_ = orderParts(d);  // 1.
  auto& parts = out.parts_;

  for (auto& p : parts) {  // 2. parents first
    setFrame(*p, p->parent >= 0 ? parts[p->parent].get() : nullptr, out.speeds_);
    if (!p->gapNote.empty()) out.notes_.push_back(p->gapNote);
    // Held by supports or springs of its own: a rigid motion X strains it
    // (K X != 0); a child's basis adds the static correction -K_h^-1 K X
    // (theory §11.2).
    p->ownSupports = p->spec.kind != SubstructureKind::Rigid && p->spec.model && heldByItsOwnSupports(*p->spec.model);
    // A stationary-frame rotor's material damping turns with it and adds a
    // circulatory term (theory §13.1), formed from Rayleigh beta; a modal
    // ratio lives in its reduced coordinates and gets none, so its
    // instability above the critical speed would be missed (a Craig-Bampton
    // shaft read stable at zeta 0.01 where the same rotor in its own
    // spinning frame grows at 0.616 1/s; found by a review). Refused.
    CMS_INPUT_CHECK(p->spec.spin && p->spec.spin->frame == fem::SpinDefinition::Frame::Stationary &&
                        p->spec.model && p->spec.model->damping.modalRatio > 0.0,
                    who(*p) << ": Modal Damping Ratio on a rotor in the stationary frame: its material damping "
                               "turns with it and adds a circulatory term, which is formed for Rayleigh Beta but not "
                               "for a modal ratio (theory §13.1); give Structural Damping a Rayleigh Beta (and the "
                               "bearings their Damping)");
  }
  // A free body spinning in its frame is held only by the centrifugal
  // prestress: the spin softening of its rigid rotations is balanced by the
  // geometric stiffness of the stress it causes (theory §10, §11.6).
  // Without it they read as divergence at the spin rate: the spacecraft
  // with its bus's stiffening off diverged at 0.999 rad/s (found by a
  // review). Refused: the answer would be a false instability. (A free
  // hinge is the same mechanism, but whether something else holds it, a
  // spring across it or at the tip, needs the stiffness's rank: not
  // refused, theory §10.)
  for (const auto& p : parts) {
    const bool softOnly = p->frame.spinning && p->frame.kind == fem::SpinDefinition::Frame::Rotating &&
                          !p->frame.stressStiffening && p->spec.kind != SubstructureKind::Rigid;
    if (!softOnly) continue;
    CMS_INPUT_CHECK(out.free_ && p->spec.kind == SubstructureKind::Central,
                    who(*p) << ": \"Stress Stiffening: false\" on a free-floating structure spinning in its frame: "
                               "its rigid rotations' spin softening is balanced only by the centrifugal prestress, "
                               "and without it they would read as divergence at the spin rate; remove the key "
                               "(stiffening is on by default)");
  }
  for (auto& p : parts) setHeldDofs(*p, d.freeReference);  // 3.
  for (auto& p : parts)                                     // 4.
    if (p->spec.kind == SubstructureKind::Rigid) buildRigidRotor(*p, *parts[p->parent]);

  // 5. Leaves first. Each prestress solve's factorisation of K is kept for
  // the part's reduction, which factors the same matrix (theory §11.4),
  // while the kept ones total at most a quarter of the memory available
  // now: they wait for the reductions, which run root first. A copy that
  // its prototype's basis will be turned into is not reduced: none kept.
  // A copy comes right after its prototype (still before its parent) and
  // turns the prototype's matrices, load and reactions instead of being
  // assembled and prestressed again (theory §15.2).
  const double ownBudget = availableMemoryBytes() / 4.0;
  double budget = 0.0, keptBytes = 0.0;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MIN, 1, &ownBudget, &budget);  // one decision on every rank
  std::map<std::size_t, std::set<std::size_t>> turnedCopies;  // prototype -> copies turned
  for (std::size_t i : assemblyOrder(out)) {
    Part& p = *parts[i];
    if (p.spec.kind == SubstructureKind::Rigid) continue;
    const std::size_t q = out.prototypeOf(i);
    std::string why;
    if (q == i) {
      assemblePart(p, comm, true);
    } else if (turnCopy(p, *parts[q], why)) {
      turnedCopies[q].insert(i);
    } else {
      assemblePart(p, comm, false);
      out.notes_.push_back(p.spec.name + ": assembled on its own, not turned from " + parts[q]->spec.name + " (" +
                           why + ")");
    }
    if (p.stiffnessFactor) {  // bytes: the same on every rank
      if (keptBytes + p.stiffnessFactor->bytes > budget) p.stiffnessFactor.reset();
      else keptBytes += p.stiffnessFactor->bytes;
    }
    if (p.parent >= 0 && p.prestressed()) {
      passReactionToParent(p, *parts[p.parent]);
      const std::string link = rigidFitLinkNote(p, *parts[p.parent]);
      if (!link.empty()) out.notes_.push_back(link);
    }
  }
  if (out.free_ && parts.front()->prestressed()) checkFreeSpinBalances(*parts.front());
  if (out.free_ && parts.front()->frame.spinning) out.relativeMomenta_ = relativeMomenta(parts);

  for (auto& p : parts) {  // 6. nodal DOFs to rows, now that every layout is known
    if (p->sub) resolveHeldRows(*p, d.freeReference);
    if (p->parent >= 0) resolveAttachmentRows(*p, *parts[p->parent]);
  }

  for (const auto& pb : parts) {  // 7. each frame family with a Boolean interface, once
    if (!pb->boolean() || !pb->prestressed()) continue;
    const auto family = pb->frame.coefficients;
    bool done = false;
    for (const auto& q : parts) done = done || (q->prestressSolvedGlobally && q->frame.coefficients == family);
    if (done) continue;
    const int count = solveFamilyPrestress(out, family);
    out.notes_.push_back("centrifugal prestress of " + std::to_string(count) + " substructures joined by Boolean "
                         "interfaces solved as one static problem (they were assembled twice)");
  }
  for (const auto& [q, copies] : turnedCopies) {  // those a Boolean family's solve did not reassemble
    std::string list;
    for (std::size_t k : copies)
      if (parts[k]->matricesTurned) list += (list.empty() ? "" : ", ") + parts[k]->spec.name;
    if (list.empty()) continue;
    out.notes_.push_back(list + ": the matrices" + (parts[q]->prestressed() ? " and centrifugal prestress" : "") +
                         " of " + parts[q]->spec.name + " turned (no assembly" +
                         (parts[q]->prestressed() ? " or prestress solve" : "") + " of their own)");
  }
  out.seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace cms::synthesis
