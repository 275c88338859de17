#include "cms/fem/LumpedElements.hpp"

#include <algorithm>
#include <cmath>

#include "RigidBodySpin.hpp"

namespace cms::fem {

namespace {

using detail::Mat3;

constexpr const char* kInertiaKeys[6] = {"Jxx", "Jyy", "Jzz", "Jxy", "Jyz", "Jxz"};
constexpr const char* kSpringKeys[6] = {"kx", "ky", "kz", "krx", "kry", "krz"};

Mat3 inertiaTensor(const PointMass& p) {
  const auto& j = p.inertia;
  return {j[0], j[3], j[5], j[3], j[1], j[4], j[5], j[4], j[2]};
}

/// Eigenvalues of a symmetric 3x3 matrix by cyclic Jacobi rotations.
std::array<double, 3> symmetricEigenvalues(Mat3 a) {
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[1] * a[1] + a[2] * a[2] + a[5] * a[5];
    const double diag = a[0] * a[0] + a[4] * a[4] + a[8] * a[8];
    if (off <= 1e-32 * diag || off == 0.0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        const double apq = a[3 * p + q];
        if (apq == 0.0) continue;
        const double theta = (a[3 * q + q] - a[3 * p + p]) / (2.0 * apq);
        const double t =
            (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {  // A <- A G
          const double akp = a[3 * k + p], akq = a[3 * k + q];
          a[3 * k + p] = c * akp - s * akq;
          a[3 * k + q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // A <- G^T A
          const double apk = a[3 * p + k], aqk = a[3 * q + k];
          a[3 * p + k] = c * apk - s * aqk;
          a[3 * q + k] = s * apk + c * aqk;
        }
      }
  }
  return {a[0], a[4], a[8]};
}

void checkDofs(int dofs, const char* what) {
  CMS_INPUT_CHECK(dofs != 3 && dofs != 6, what << ": dofs = " << dofs << " must be 3 or 6");
}

void checkPointMassDofs(const PointMass& p, int dofs) {
  checkDofs(dofs, "point mass");
  CMS_INPUT_CHECK(dofs == 3 && p.hasInertia(),
                  "point mass at (" << p.x[0] << ", " << p.x[1] << ", " << p.x[2]
                                    << "): a nonzero inertia tensor needs rotational DOFs, "
                                       "but the node has dofs = 3");
}

void checkSprings(const std::array<double, 6>& k, int dofs, const char* what) {
  checkDofs(dofs, what);
  for (int i = 0; i < 6; ++i)
    CMS_INPUT_CHECK(!(std::isfinite(k[i]) && k[i] >= 0.0),
                    what << ": Stiffness " << kSpringKeys[i] << " = " << k[i]
                         << " must be non-negative and finite");
  for (int i = 3; i < 6 && dofs == 3; ++i)
    CMS_INPUT_CHECK(k[i] != 0.0, what << ": Stiffness " << kSpringKeys[i] << " = " << k[i]
                                      << " needs rotational DOFs, but the node has dofs = 3");
}

}  // namespace

void PointMass::validate(const char* what) const {
  CMS_INPUT_CHECK(!(std::isfinite(m) && m >= 0.0),
                  what << ": Mass m = " << m << " must be non-negative and finite");
  for (int i = 0; i < 6; ++i)
    CMS_INPUT_CHECK(!std::isfinite(inertia[i]), what << ": Inertia " << kInertiaKeys[i] << " = "
                                                     << inertia[i] << " must be finite");
  const std::array<double, 3> ev = symmetricEigenvalues(inertiaTensor(*this));
  const double largest = std::max({std::abs(ev[0]), std::abs(ev[1]), std::abs(ev[2])});
  const double smallest = std::min({ev[0], ev[1], ev[2]});
  CMS_INPUT_CHECK(smallest < -1e-12 * largest,
                  what << ": Inertia (Jxx Jyy Jzz Jxy Jyz Jxz = " << inertia[0] << " " << inertia[1]
                       << " " << inertia[2] << " " << inertia[3] << " " << inertia[4] << " "
                       << inertia[5] << ") must be positive semidefinite; it has the eigenvalue "
                       << smallest);
  CMS_INPUT_CHECK(m == 0.0 && !hasInertia(),
                  what << ": Mass m = 0 and a zero Inertia; the mass must be positive or "
                          "the inertia nonzero");
}

bool PointMass::hasInertia() const {
  return std::any_of(inertia.begin(), inertia.end(), [](double j) { return j != 0.0; });
}

ElementMatrix pointMassMatrix(const PointMass& p, int dofs) {
  checkPointMassDofs(p, dofs);
  ElementMatrix M(dofs);
  for (int i = 0; i < 3; ++i) M(i, i) = p.m;
  if (dofs == 6) {
    const Mat3 J = inertiaTensor(p);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) M(3 + i, 3 + j) = J[3 * i + j];
  }
  return M;
}

SpinMatrices pointMassSpinMatrices(const PointMass& p, const Spin& spin, int dofs) {
  checkPointMassDofs(p, dofs);
  const Vec3 n = detail::unitAxis(spin.axis, "point mass");
  const Mat3 N = detail::crossMatrix(n), NtN = detail::mul(detail::transpose(N), N);
  const Vec3 r = detail::perpendicularToAxis(p.x, Spin{n, spin.origin});
  SpinMatrices s{ElementMatrix(dofs), ElementMatrix(dofs), std::vector<double>(dofs, 0.0)};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      s.G1(i, j) = 2.0 * p.m * N[3 * i + j];
      s.KT1(i, j) = p.m * NtN[3 * i + j];
    }
    s.f1[i] = p.m * r[i];
  }
  if (dofs == 6) {
    const detail::RigidBodySpin rb = detail::rigidBodySpin(inertiaTensor(p), n);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        s.G1(3 + i, 3 + j) = rb.G[3 * i + j];
        s.KT1(3 + i, 3 + j) = rb.KT[3 * i + j];
      }
      s.f1[3 + i] = rb.f[i];
    }
  }
  return s;
}

ElementMatrix pointMassStationaryGyroscopic(const PointMass& p, const Vec3& axis) {
  const Vec3 n = detail::unitAxis(axis, "point mass");
  const Mat3 J = inertiaTensor(p);
  // In the stationary frame the spin enters only through the polar moment Ip
  // of a body symmetric about the axis (Nelson & McVaugh 1976): such a body
  // has J = Id I + (Ip - Id) n n^T, and then nothing else depends on its spin
  // angle.
  const double Ip = detail::dot(n, detail::mul(J, n)), Id = 0.5 * (J[0] + J[4] + J[8] - Ip);
  double deviation = 0.0, size = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double sym = (i == j ? Id : 0.0) + (Ip - Id) * n[i] * n[j];
      deviation += std::pow(J[3 * i + j] - sym, 2);
      size += std::pow(J[3 * i + j], 2);
    }
  CMS_INPUT_CHECK(!(std::sqrt(deviation) <= 1e-8 * std::sqrt(size)),
                  "point mass at ("
                      << p.x[0] << ", " << p.x[1] << ", " << p.x[2]
                      << "): inertia tensor (Jxx Jyy Jzz Jxy Jyz Jxz = " << p.inertia[0] << " "
                      << p.inertia[1] << " " << p.inertia[2] << " " << p.inertia[3] << " "
                      << p.inertia[4] << " " << p.inertia[5]
                      << ") is not axisymmetric about the spin axis (" << n[0] << ", " << n[1]
                      << ", " << n[2] << "), as the stationary frame requires");
  ElementMatrix g(6);
  const Mat3 N = detail::crossMatrix(n);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) g(3 + i, 3 + j) = Ip * N[3 * j + i];
  return g;
}

ElementMatrix groundedSpringMatrix(const std::array<double, 6>& k, int dofs) {
  checkSprings(k, dofs, "grounded spring");
  ElementMatrix K(dofs);
  for (int i = 0; i < dofs; ++i) K(i, i) = k[i];
  return K;
}

ElementMatrix twoNodeSpringMatrix(const std::array<double, 6>& k, int dofs) {
  checkSprings(k, dofs, "two-node spring");
  ElementMatrix K(2 * dofs);
  for (int i = 0; i < dofs; ++i) {
    K(i, i) = K(dofs + i, dofs + i) = k[i];
    K(i, dofs + i) = K(dofs + i, i) = -k[i];
  }
  return K;
}

ElementMatrix pointMassStationaryTiltStiffness(const PointMass& p, const Vec3& axis, const Vec3& frameAxis) {
  pointMassStationaryGyroscopic(p, axis);  // the axisymmetry check
  const Vec3 n = detail::unitAxis(axis, "point mass"), f = detail::unitAxis(frameAxis, "point mass");
  const Mat3 J = inertiaTensor(p);
  const double Ip = detail::dot(n, detail::mul(J, n)), fn = detail::dot(f, n);
  ElementMatrix k(6);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) k(3 + i, 3 + j) = -Ip * (0.5 * (f[i] * n[j] + n[i] * f[j]) - (i == j ? fn : 0.0));
  return k;
}

}  // namespace cms::fem
