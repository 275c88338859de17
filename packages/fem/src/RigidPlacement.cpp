#include "cms/fem/RigidPlacement.hpp"

#include <cmath>
#include <limits>

namespace cms::fem {

Rotation Rotation::about(const Vec3& axis, double radians) {
  const Vec3 a = unit(axis);
  const double c = std::cos(radians), s = std::sin(radians);
  Rotation r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.R[i][j] = c * (i == j) + (1 - c) * a[i] * a[j];
  r.R[0][1] -= s * a[2], r.R[0][2] += s * a[1], r.R[1][0] += s * a[2];
  r.R[1][2] -= s * a[0], r.R[2][0] -= s * a[1], r.R[2][1] += s * a[0];
  return r;
}

Vec3 Rotation::apply(const Vec3& x) const {
  return {R[0][0] * x[0] + R[0][1] * x[1] + R[0][2] * x[2], R[1][0] * x[0] + R[1][1] * x[1] + R[1][2] * x[2],
          R[2][0] * x[0] + R[2][1] * x[1] + R[2][2] * x[2]};
}

namespace {

using Tensor = std::array<std::array<double, 3>, 3>;

Tensor rotated(const Rotation& r, const Tensor& a) {
  Tensor out{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) out[i][j] += r.R[i][k] * a[k][l] * r.R[j][l];
  return out;
}

/// Whether R D R^T = D for D = diag(d): to 16 eps |D|, the rounding of the
/// rotation's own entries (cos 90 degrees is 6e-17, not 0).
bool invariant(const Rotation& r, const std::array<double, 3>& d) {
  const Tensor D{{{d[0], 0, 0}, {0, d[1], 0}, {0, 0, d[2]}}};
  const Tensor RD = rotated(r, D);
  double scale = 0, diff = 0;
  for (int i = 0; i < 3; ++i) {
    scale = std::max(scale, std::abs(d[i]));
    for (int j = 0; j < 3; ++j) diff = std::max(diff, std::abs(RD[i][j] - D[i][j]));
  }
  return diff <= 16 * std::numeric_limits<double>::epsilon() * scale;
}

}  // namespace

std::array<double, 6> Rotation::applyToTensor(const std::array<double, 6>& a) const {
  const Tensor A{{{a[0], a[3], a[5]}, {a[3], a[1], a[4]}, {a[5], a[4], a[2]}}};
  const Tensor B = rotated(*this, A);
  return {B[0][0], B[1][1], B[2][2], B[0][1], B[1][2], B[0][2]};
}

std::shared_ptr<FiniteElementModel> placedModel(const FiniteElementModel& model, const Rotation& rotation,
                                                const Vec3& pivot, const Vec3& translation) {
  auto out = std::make_shared<FiniteElementModel>(model);
  auto mesh = std::make_shared<mesh::Mesh>(*model.mesh);
  for (std::size_t n = 0; n < mesh->nodeCount(); ++n) {
    const Vec3 x = rotation.apply(sub({mesh->coordinates[3 * n], mesh->coordinates[3 * n + 1],
                                       mesh->coordinates[3 * n + 2]}, pivot));
    for (int d = 0; d < 3; ++d) mesh->coordinates[3 * n + d] = x[d] + pivot[d] + translation[d];
  }
  out->mesh = mesh;
  for (auto& es : out->elementSets) es.section.orientation = rotation.apply(es.section.orientation);
  for (auto& pm : out->pointMasses) pm.inertia = rotation.applyToTensor(pm.inertia);
  for (auto& h : out->hinges) h.axis = rotation.apply(h.axis);  // a hinge turns with its nodes (theory §17)
  return out;
}

std::string rotationVariantItem(const FiniteElementModel& model, const Rotation& rotation) {
  auto variant = [&](const std::array<double, 6>& d) {
    return !invariant(rotation, {d[0], d[1], d[2]}) || !invariant(rotation, {d[3], d[4], d[5]});
  };
  for (const auto& s : model.springs) {
    if (variant(s.stiffness)) return "spring '" + s.name + "'";
    if (variant(s.damping)) return "damper '" + s.name + "'";
  }
  for (const auto& f : model.fixed) {
    if (f.all) continue;
    std::array<double, 6> fixedComponents{};
    for (Component c : f.components) fixedComponents[static_cast<int>(c)] = 1.0;
    if (variant(fixedComponents)) return "fixed set '" + f.name + "'";
  }
  return {};
}

}  // namespace cms::fem
