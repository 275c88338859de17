// The one 3-vector of the project and its algebra (issue #11: four sets of
// Vec3 helpers had grown in fem, synthesis, analysis and the tests). A point,
// a direction or an axis in global axes (m, or unitless for directions).
#pragma once

#include <array>
#include <cmath>

namespace cms::fem {

using Vec3 = std::array<double, 3>;

inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
/// a - b
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
/// s a + b
inline Vec3 axpy(double s, const Vec3& a, const Vec3& b) {
  return {s * a[0] + b[0], s * a[1] + b[1], s * a[2] + b[2]};
}
/// a / |a| (a != 0: the callers check their axes when reading them).
inline Vec3 unit(const Vec3& a) {
  const double n = norm(a);
  return {a[0] / n, a[1] / n, a[2] / n};
}
/// Two unit vectors normal to the axis n, with e1 x e2 = n / |n|: e1 from the
/// coordinate axis least aligned with n (well conditioned for any n).
inline std::array<Vec3, 2> transverseBasis(const Vec3& axis) {
  const Vec3 n = unit(axis);
  int least = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(n[d]) < std::abs(n[least])) least = d;
  Vec3 e{0.0, 0.0, 0.0};
  e[least] = 1.0;
  const Vec3 e1 = unit(axpy(-dot(e, n), n, e));
  return {e1, cross(n, e1)};
}

/// Row `component` (0..5: ux uy uz rx ry rz) of the rigid motion
/// u = u_P + theta x r, theta = theta_P, of a point at r from P, as
/// coefficients of a = (u_P, theta_P): [I, -[r]x; 0, I] (theory §11.2).
inline std::array<double, 6> rigidRow(const Vec3& r, int component) {
  std::array<double, 6> x{};
  switch (component) {
    case 0: x[0] = 1, x[4] = r[2], x[5] = -r[1]; break;
    case 1: x[1] = 1, x[5] = r[0], x[3] = -r[2]; break;
    case 2: x[2] = 1, x[3] = r[1], x[4] = -r[0]; break;
    default: x[component] = 1; break;
  }
  return x;
}

}  // namespace cms::fem
