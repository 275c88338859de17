// Private to cms_fem: 3x3 algebra and the per-unit-speed spin terms of a rigid
// body, shared by the frame element (per unit length, integrated along the
// beam) and the point mass.
#pragma once

#include <array>
#include <cmath>

#include "cms/core/Error.hpp"
#include "cms/fem/ElementMatrix.hpp"

namespace cms::fem::detail {

/// Row-major 3x3: (i, j) = m[3 i + j].
using Mat3 = std::array<double, 9>;

using fem::cross;  // the vector algebra: cms/fem/Vec3.hpp
using fem::dot;
using fem::norm;
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return sub(a, b); }
inline Vec3 operator*(double s, const Vec3& a) { return axpy(s, a, {0.0, 0.0, 0.0}); }

/// [a]x, the matrix of v -> a x v.
inline Mat3 crossMatrix(const Vec3& a) {
  return {0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0};
}

inline Mat3 mul(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
  return c;
}
inline Mat3 transpose(const Mat3& a) {
  return {a[0], a[3], a[6], a[1], a[4], a[7], a[2], a[5], a[8]};
}
inline Vec3 mul(const Mat3& a, const Vec3& v) {
  return {a[0] * v[0] + a[1] * v[1] + a[2] * v[2], a[3] * v[0] + a[4] * v[1] + a[5] * v[2],
          a[6] * v[0] + a[7] * v[1] + a[8] * v[2]};
}

/// r_perp = (I - n n^T)(x - origin): the position relative to the spin axis.
inline Vec3 perpendicularToAxis(const Vec3& x, const Spin& spin) {
  const Vec3 r = x - spin.origin;
  return r - dot(r, spin.axis) * spin.axis;
}

/// The unit vector along a user's axis; InputError if it is zero or not finite.
inline Vec3 unitAxis(const Vec3& axis, const char* what) {
  const double a = norm(axis);
  CMS_INPUT_CHECK(!(std::isfinite(a) && a > 0.0), what << ": spin axis (" << axis[0] << ", "
                                                       << axis[1] << ", " << axis[2]
                                                       << ") must be nonzero and finite");
  return (1.0 / a) * axis;
}

/// Spin terms of a rigid body with inertia J (symmetric, global axes) about a
/// point, linearised in its small rotation theta in a frame spinning at
/// Omega n: Euler's equations give J theta'' + Omega G theta' - Omega^2 KT
/// theta = Omega^2 f with the matrices below (for J = diag(Ip, Id, Id),
/// n = e_x: KT = (Id - Ip) I and G = (2 Id - Ip)[e_x]x on the tilts);
/// doc/theory.md §9.3 derives them.
struct RigidBodySpin {
  Mat3 G, KT;
  Vec3 f;
};

inline RigidBodySpin rigidBodySpin(const Mat3& J, const Vec3& n) {
  const Mat3 N = crossMatrix(n);
  const Vec3 Jn = mul(J, n);
  const Mat3 JN = mul(J, N), NJ = mul(N, J), NJN = mul(transpose(N), JN), C = crossMatrix(Jn);
  const double nJn = dot(n, Jn);
  RigidBodySpin s{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int ij = 3 * i + j;
      s.G[ij] = JN[ij] + NJ[ij] - C[ij];
      s.KT[ij] = NJN[ij] + 0.5 * (Jn[i] * n[j] + n[i] * Jn[j]) - (i == j ? nJn : 0.0);
    }
  s.f = cross(Jn, n);
  return s;
}

}  // namespace cms::fem::detail
