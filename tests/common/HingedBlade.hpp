// A blade on a hinge (theory §17), built in code: a hub arm of frame
// elements from the spin axis (node set "axis", clamped) to the hinge at
// x = e ("hub_tip"), and a blade from the hinge to x = e + L whose first node
// ("blade_root") is a second node at the same place, joined to "hub_tip" by
// a hinge; "tip" is the blade's last node. Laid out along x with the spin
// about z through the origin, then turned rigidly by `rotation` (points,
// section orientations, hinge and spin axes) for the invariance tests.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>

#include <algorithm>
#include <complex>
#include <vector>

#include <Teuchos_LAPACK.hpp>

#include "BeamModels.hpp"
#include "cms/core/DenseMatrix.hpp"
#include "cms/core/Error.hpp"
#include "cms/fem/FiniteElementModel.hpp"

namespace cms::fixtures {

using Rotation = std::array<std::array<double, 3>, 3>;

inline Rotation identityRotation() { return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; }

/// The rotation by `angle` (rad) about the unit vector `a` (Rodrigues).
inline Rotation rotationAbout(fem::Vec3 a, double angle) {
  a = fem::unit(a);
  const double c = std::cos(angle), s = std::sin(angle);
  Rotation R{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R[i][j] = c * (i == j) + (1 - c) * a[i] * a[j];
  R[0][1] -= s * a[2], R[0][2] += s * a[1], R[1][0] += s * a[2];
  R[1][2] -= s * a[0], R[2][0] -= s * a[1], R[2][1] += s * a[0];
  return R;
}

inline fem::Vec3 rotate(const Rotation& R, const fem::Vec3& x) {
  fem::Vec3 y{0, 0, 0};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) y[i] += R[i][j] * x[j];
  return y;
}

struct HingedBladeSpec {
  double e = 0.5;          ///< hinge offset from the spin axis (m)
  double L = 5.0;          ///< blade length beyond the hinge (m)
  int hubElements = 2, bladeElements = 2;  ///< a rigid rotation is exact with any count (theory §17.3)
  double density = 1000.0, area = 0.01;  ///< rho A = 10 kg/m
  /// "Rigid": the blade's bending far above the hinge frequencies. Its
  /// flexibility lowers nu^2 = k / I by about 1.2e7 / E relative (measured,
  /// k = 2000), while the rounding of K's stiff entries, which cancel in the
  /// rigid rotation, perturbs it by about 2e-23 E k_ref / k: at 5.3e14 both
  /// are near their balance, 2e-8 each (theory §17.3).
  double E = 5.3e14;
  double I2 = 1e-4;        ///< Iy = Iz of the blade's section (m^4)
  double hubI2 = 1e-2;     ///< Iy = Iz of the hub arm's: 100 times stiffer, it carries the blade
  fem::Vec3 hingeAxis{0, 0, 1};  ///< in the unrotated axes: z = lag, y = flap
  double stiffness = 0.0, damping = 0.0;  ///< of the hinge
  bool spinning = false;   ///< spin about z (rotated with the model) in its own frame, stress stiffening on
  Rotation rotation = identityRotation();

  double rhoA() const { return density * area; }
  /// The blade's moment of inertia about the hinge and its first moment
  /// (Euler-Bernoulli sections without rotary inertia: the line's mass only).
  double inertia() const { return rhoA() * L * L * L / 3.0; }
  double firstMoment() const { return rhoA() * L * L / 2.0; }
};

inline std::shared_ptr<mesh::Mesh> hingedBladeMesh(const HingedBladeSpec& b) {
  auto mesh = std::make_shared<mesh::Mesh>();
  mesh->source = "hinged blade (in code)";
  auto node = [&](double x) {
    const auto p = rotate(b.rotation, {x, 0.0, 0.0});
    mesh->nodeTags.push_back(mesh->nodeTags.size() + 1);
    mesh->coordinates.insert(mesh->coordinates.end(), p.begin(), p.end());
    return static_cast<std::int64_t>(mesh->nodeTags.size() - 1);
  };
  auto line = [&](const std::string& name, int tag, std::int64_t first, int count) {
    mesh::PhysicalGroup g{name, 1, tag, {}};
    mesh::CellBlock lines;
    lines.type = mesh::CellType::Line2;
    lines.gmshType = 1;
    lines.nodesPerCell = 2;
    for (int e = 0; e < count; ++e) {
      lines.nodes.insert(lines.nodes.end(), {first + e, first + e + 1});
      lines.cellTags.push_back(static_cast<std::size_t>(tag * 1000 + e));
    }
    g.blocks.push_back(lines);
    mesh->groups.push_back(g);
  };
  for (int i = 0; i <= b.hubElements; ++i) node(b.e * i / b.hubElements);
  const std::int64_t root = static_cast<std::int64_t>(mesh->nodeTags.size());
  for (int i = 0; i <= b.bladeElements; ++i) node(b.e + b.L * i / b.bladeElements);
  line("hub", 1, 0, b.hubElements);
  line("blade", 2, root, b.bladeElements);
  addPointGroup(*mesh, "axis", {0});
  addPointGroup(*mesh, "hub_tip", {b.hubElements});
  addPointGroup(*mesh, "blade_root", {root});
  addPointGroup(*mesh, "tip", {root + b.bladeElements});
  return mesh;
}

inline fem::FiniteElementModel hingedBlade(const HingedBladeSpec& b) {
  fem::FiniteElementModel m;
  m.name = "hinged blade";
  m.mesh = hingedBladeMesh(b);
  m.materials["stiff"] = {b.E, 0.3, b.density};
  for (const char* g : {"hub", "blade"}) {
    fem::ElementSet set;
    set.group = g;
    set.kind = fem::ElementSet::Kind::Frame;
    set.material = "stiff";
    const double I2 = std::string(g) == "hub" ? b.hubI2 : b.I2;
    set.section = beamSection(b.area, I2, I2, 2 * I2, rotate(b.rotation, {0, 0, 1}));
    set.section.rotaryInertia = false;
    m.elementSets.push_back(set);
  }
  fem::FixedSet clamp;
  clamp.name = "clamp";
  clamp.nodeSet = "axis";
  clamp.all = true;
  m.fixed.push_back(clamp);
  fem::HingeSet h;
  h.name = "hinge";
  h.nodeSet = "hub_tip";
  h.toNodeSet = "blade_root";
  h.axis = fem::unit(rotate(b.rotation, b.hingeAxis));
  h.stiffness = b.stiffness;
  h.damping = b.damping;
  m.hinges.push_back(h);
  if (b.spinning) {
    fem::SpinDefinition s;
    s.spin.axis = rotate(b.rotation, {0, 0, 1});
    s.spin.origin = {0, 0, 0};
    s.frame = fem::SpinDefinition::Frame::Rotating;
    s.stressStiffening = true;
    m.spin = s;
  }
  return m;
}

/// The `count` lowest frequencies |lambda| of M q'' + G q' + K q = 0 (K > 0)
/// by the inverse of its first-order form: mu = 1/lambda are the eigenvalues
/// of C = [[-K^-1 G, -K^-1 M], [I, 0]] (LAPACK dgeev), the lowest
/// frequencies being the largest |mu|. Unlike a solve on K's own scale (whose
/// error is eps omega_max, or worse through K's Cholesky factor), the soft
/// modes of a stiff model (a rigid blade on a hinge) keep the accuracy that
/// the rounding of K itself allows them: what a backward-stable solve with K
/// perturbs, v^T dK v / v^T K v for the soft mode v.
inline std::vector<double> lowestFrequencies(const DenseMatrix& M, const DenseMatrix& G, const DenseMatrix& K,
                                             int count) {
  const int n = K.numRows(), n2 = 2 * n;
  Teuchos::LAPACK<int, double> lapack;
  std::vector<double> L(K.values(), K.values() + static_cast<std::size_t>(n) * n);
  int info = 0;
  lapack.POTRF('L', n, L.data(), n, &info);
  if (info != 0) throw NumericalError("lowestFrequencies: K is not positive definite (POTRF info " + std::to_string(info) + ")");
  std::vector<double> KG(G.values(), G.values() + static_cast<std::size_t>(n) * n);
  std::vector<double> KM(M.values(), M.values() + static_cast<std::size_t>(n) * n);
  lapack.POTRS('L', n, n, L.data(), n, KG.data(), n, &info);
  lapack.POTRS('L', n, n, L.data(), n, KM.data(), n, &info);
  std::vector<double> C(static_cast<std::size_t>(n2) * n2, 0.0);  // column-major
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      C[static_cast<std::size_t>(j) * n2 + i] = -KG[static_cast<std::size_t>(j) * n + i];
      C[static_cast<std::size_t>(j + n) * n2 + i] = -KM[static_cast<std::size_t>(j) * n + i];
    }
  for (int i = 0; i < n; ++i) C[static_cast<std::size_t>(i) * n2 + n + i] = 1.0;
  std::vector<double> wr(n2), wi(n2), work(8 * n2);
  double dummy = 0.0;
  lapack.GEEV('N', 'N', n2, C.data(), n2, wr.data(), wi.data(), &dummy, 1, &dummy, 1, work.data(),
              static_cast<int>(work.size()), nullptr, &info);
  if (info != 0) throw NumericalError("lowestFrequencies: dgeev info " + std::to_string(info));
  std::vector<double> omega;
  for (int i = 0; i < n2; ++i) {
    const double mu = std::abs(std::complex<double>(wr[i], wi[i]));
    if (mu > 0.0) omega.push_back(1.0 / mu);
  }
  std::sort(omega.begin(), omega.end());
  // Each frequency comes twice (lambda and its conjugate): keep one of each.
  std::vector<double> out;
  for (std::size_t i = 0; i + 1 < omega.size() && static_cast<int>(out.size()) < count; i += 2) out.push_back(omega[i]);
  return out;
}

}  // namespace cms::fixtures
