#include "cms/fem/FrameElement.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "RigidBodySpin.hpp"

namespace cms::fem {

namespace {

using detail::Mat3;
using detail::operator-;
using detail::operator*;

constexpr int kDofs = 12;

/// A 3 x 12 interpolation matrix: field(x) = N(x) ue.
using Shape = std::array<std::array<double, kDofs>, 3>;

/// Local DOFs (u v w rx ry rz per node) of the two bending planes, ordered as
/// the shape functions (displacement 1, rotation 1, displacement 2,
/// rotation 2). In the x-z plane theta_y = -w', so the pair (w, -theta_y)
/// behaves as (v, theta_z): the rotation DOFs enter with a minus sign.
constexpr int kPlaneXY[4] = {1, 5, 7, 11};
constexpr int kPlaneXZ[4] = {2, 4, 8, 10};
constexpr double kSignXZ[4] = {1.0, -1.0, 1.0, -1.0};

/// 5-point Gauss-Legendre rule on [0, 1]: exact to degree 9, enough for every
/// integrand here (at most degree 6: products of two cubics, or a cubic times
/// the linear position).
constexpr double kGaussXi[5] = {0.5 - 0.5 * 0.9061798459386640, 0.5 - 0.5 * 0.5384693101056831, 0.5,
                                0.5 + 0.5 * 0.5384693101056831, 0.5 + 0.5 * 0.9061798459386640};
constexpr double kGaussW[5] = {0.5 * 0.2369268850561891, 0.5 * 0.4786286704993665,
                               0.5 * 0.5688888888888889, 0.5 * 0.4786286704993665,
                               0.5 * 0.2369268850561891};

/// "frame element from (x1) to (x2)", to start a message.
std::string describe(const FrameElement& e) {
  std::ostringstream os;
  os << "frame element from (" << e.x1[0] << ", " << e.x1[1] << ", " << e.x1[2] << ") to ("
     << e.x2[0] << ", " << e.x2[1] << ", " << e.x2[2] << ")";
  return os.str();
}

/// Element axis e1 and length; InputError if the length is zero or not finite.
void axisAndLength(const FrameElement& e, Vec3& e1, double& L) {
  const Vec3 d = e.x2 - e.x1;
  L = detail::norm(d);
  CMS_INPUT_CHECK(
      !(std::isfinite(L) && L > 1e-12 * (detail::norm(e.x1) + detail::norm(e.x2))),
      describe(e) << ": length " << L << " is zero (beside the coordinates) or not finite");
  e1 = (1.0 / L) * d;
}

/// Length and the rotation R (rows e1, e2, e3) taking global to local
/// components.
struct LocalAxes {
  double L = 0.0;
  Mat3 R{};
};

LocalAxes localAxes(const FrameElement& e) {
  LocalAxes a;
  Vec3 e1;
  axisAndLength(e, e1, a.L);
  const Vec3& o = e.section.orientation;
  const Vec3 normal = o - detail::dot(o, e1) * e1;
  const double size = detail::norm(normal);
  CMS_INPUT_CHECK(!orientationAcross(e1, o),
                  describe(e) << ": section orientation (" << o[0] << ", " << o[1] << ", " << o[2]
                              << "): orientation vector parallel to the beam");
  const Vec3 e2 = (1.0 / size) * normal, e3 = detail::cross(e1, e2);
  a.R = {e1[0], e1[1], e1[2], e2[0], e2[1], e2[2], e3[0], e3[1], e3[2]};
  return a;
}

/// Shear parameters phi = 12 E I / (kappa G A L^2) of the x-y plane (Iz,
/// kappa_y) and the x-z plane (Iy, kappa_z); zero for Euler-Bernoulli.
struct ShearParameters {
  double xy = 0.0, xz = 0.0;
};

ShearParameters shearParameters(const FrameElement& e, double L) {
  if (e.theory == BeamTheory::EulerBernoulli) return {};
  const BeamSection& s = e.section;
  const double c = 12.0 * e.material.E / (e.material.shearModulus() * s.A * L * L);
  return {c * s.Iz / s.shearFactorY, c * s.Iy / s.shearFactorZ};
}

/// One bending plane at xi = x / L: displacement v, section rotation theta
/// and dv/dx on (v1, theta1, v2, theta2). These are the interdependent
/// interpolation functions of Friedman & Kosmatka (1993): exact solutions of
/// the homogeneous Timoshenko equations, so one element reproduces the exact
/// cantilever and the closed-form stiffness of Przemieniecki; Hermite cubics
/// and their slopes for phi = 0.
struct PlaneShape {
  double v[4], theta[4], dv[4], dtheta[4];
};

PlaneShape planeShape(double xi, double L, double phi) {
  const double c = 1.0 / (1.0 + phi), x2 = xi * xi, x3 = x2 * xi;
  PlaneShape s;
  s.v[0] = c * (2.0 * x3 - 3.0 * x2 - phi * xi + 1.0 + phi);
  s.v[1] = c * L * (x3 - (2.0 + 0.5 * phi) * x2 + (1.0 + 0.5 * phi) * xi);
  s.v[2] = -c * (2.0 * x3 - 3.0 * x2 - phi * xi);
  s.v[3] = c * L * (x3 - (1.0 - 0.5 * phi) * x2 - 0.5 * phi * xi);
  s.theta[0] = 6.0 * c * (x2 - xi) / L;
  s.theta[1] = c * (3.0 * x2 - (4.0 + phi) * xi + 1.0 + phi);
  s.theta[2] = -s.theta[0];
  s.theta[3] = c * (3.0 * x2 - (2.0 - phi) * xi);
  s.dv[0] = c * (6.0 * x2 - 6.0 * xi - phi) / L;
  s.dv[1] = c * (3.0 * x2 - (4.0 + phi) * xi + 1.0 + 0.5 * phi);
  s.dv[2] = -s.dv[0];
  s.dv[3] = c * (3.0 * x2 - (2.0 - phi) * xi - 0.5 * phi);
  s.dtheta[0] = 6.0 * c * (2.0 * xi - 1.0) / (L * L);
  s.dtheta[1] = c * (6.0 * xi - (4.0 + phi)) / L;
  s.dtheta[2] = -s.dtheta[0];
  s.dtheta[3] = c * (6.0 * xi - (2.0 - phi)) / L;
  return s;
}

/// Local displacement (u, v, w) and rotation (rx, ry, rz) interpolation, and
/// the slopes v' and w', on the local DOFs.
struct LocalShapes {
  Shape u{}, theta{};
  std::array<double, kDofs> dv{}, dw{};
  std::array<double, kDofs> dthetaY{}, dthetaZ{};  ///< theta_y', theta_z'
};

LocalShapes localShapes(double xi, double L, const ShearParameters& phi) {
  LocalShapes s;
  s.u[0][0] = s.theta[0][3] = 1.0 - xi;
  s.u[0][6] = s.theta[0][9] = xi;
  const PlaneShape xy = planeShape(xi, L, phi.xy), xz = planeShape(xi, L, phi.xz);
  for (int k = 0; k < 4; ++k) {
    s.u[1][kPlaneXY[k]] = xy.v[k];
    s.theta[2][kPlaneXY[k]] = xy.theta[k];
    s.dv[kPlaneXY[k]] = xy.dv[k];
    s.u[2][kPlaneXZ[k]] = kSignXZ[k] * xz.v[k];
    s.theta[1][kPlaneXZ[k]] = -kSignXZ[k] * xz.theta[k];
    s.dw[kPlaneXZ[k]] = kSignXZ[k] * xz.dv[k];
    s.dthetaZ[kPlaneXY[k]] = xy.dtheta[k];
    s.dthetaY[kPlaneXZ[k]] = -kSignXZ[k] * xz.dtheta[k];
  }
  return s;
}

/// N_global = R^T N_local T, T = diag(R, R, R, R): global field from global DOFs.
Shape toGlobal(const Shape& n, const Mat3& R) {
  Shape g{};
  for (int b = 0; b < kDofs; b += 3)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double s = 0.0;
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < 3; ++l) s += R[3 * k + i] * n[k][b + l] * R[3 * l + j];
        g[i][b + j] = s;
      }
  return g;
}

/// T^T K T, T = diag(R, R, R, R).
ElementMatrix toGlobal(const ElementMatrix& k, const Mat3& R) {
  ElementMatrix g(kDofs);
  for (int a = 0; a < kDofs; a += 3)
    for (int b = 0; b < kDofs; b += 3)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double s = 0.0;
          for (int p = 0; p < 3; ++p)
            for (int q = 0; q < 3; ++q) s += R[3 * p + i] * k(a + p, b + q) * R[3 * q + j];
          g(a + i, b + j) = s;
        }
  return g;
}

/// K += w A^T B C.
void addProduct(ElementMatrix& K, double w, const Shape& A, const Mat3& B, const Shape& C) {
  Shape BC{};
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < kDofs; ++j)
      BC[k][j] = B[3 * k] * C[0][j] + B[3 * k + 1] * C[1][j] + B[3 * k + 2] * C[2][j];
  for (int i = 0; i < kDofs; ++i)
    for (int j = 0; j < kDofs; ++j)
      K(i, j) += w * (A[0][i] * BC[0][j] + A[1][i] * BC[1][j] + A[2][i] * BC[2][j]);
}

/// f += w A^T b.
void addProduct(std::vector<double>& f, double w, const Shape& A, const Vec3& b) {
  for (int i = 0; i < kDofs; ++i) f[i] += w * (A[0][i] * b[0] + A[1][i] * b[1] + A[2][i] * b[2]);
}

Mat3 diagonal(double a, double b, double c) { return {a, 0.0, 0.0, 0.0, b, 0.0, 0.0, 0.0, c}; }

/// Rotary inertia per unit length in local axes. Without rotary inertia (the
/// Euler-Bernoulli idealisation) the bending rotations lose theirs, but the
/// twist keeps its polar inertia: it is the only mass torsion has, and a
/// massless twist would make M singular.
Mat3 localRotaryInertia(const FrameElement& e) {
  const double rho = e.material.rho;
  if (!e.section.rotaryInertia) return diagonal(rho * (e.section.Iy + e.section.Iz), 0.0, 0.0);
  return diagonal(rho * (e.section.Iy + e.section.Iz), rho * e.section.Iy, rho * e.section.Iz);
}

}  // namespace

double FrameElement::length() const { return detail::norm(x2 - x1); }

bool orientationAcross(const Vec3& e1, const Vec3& o) {
  const double size = detail::norm(o - detail::dot(o, e1) * e1);
  return size >= 1e-8 * detail::norm(o) && size > 0.0;
}

ElementMatrix frameStiffness(const FrameElement& e) {
  const LocalAxes ax = localAxes(e);
  const double L = ax.L, E = e.material.E;
  const BeamSection& s = e.section;
  const ShearParameters phi = shearParameters(e, L);
  ElementMatrix k(kDofs);
  const auto addPair = [&](int i, int j, double c) {
    k(i, i) += c, k(j, j) += c, k(i, j) -= c, k(j, i) -= c;
  };
  addPair(0, 6, E * s.A / L);
  addPair(3, 9, e.material.shearModulus() * s.J / L);
  // Przemieniecki's closed-form shear-deformable beam stiffness (Theory of
  // Matrix Structural Analysis, 1968): the strain energy of the shape
  // functions above.
  const auto addPlane = [&](const int* dof, const double* sign, double EI, double ph) {
    const double c = EI / ((1.0 + ph) * L * L * L);
    const double kp[4][4] = {{12.0, 6.0 * L, -12.0, 6.0 * L},
                             {6.0 * L, (4.0 + ph) * L * L, -6.0 * L, (2.0 - ph) * L * L},
                             {-12.0, -6.0 * L, 12.0, -6.0 * L},
                             {6.0 * L, (2.0 - ph) * L * L, -6.0 * L, (4.0 + ph) * L * L}};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) k(dof[i], dof[j]) += c * sign[i] * sign[j] * kp[i][j];
  };
  constexpr double kSignXY[4] = {1.0, 1.0, 1.0, 1.0};
  addPlane(kPlaneXY, kSignXY, E * s.Iz, phi.xy);
  addPlane(kPlaneXZ, kSignXZ, E * s.Iy, phi.xz);
  return toGlobal(k, ax.R);
}

ElementMatrix frameMass(const FrameElement& e) {
  const LocalAxes ax = localAxes(e);
  const ShearParameters phi = shearParameters(e, ax.L);
  const double rhoA = e.material.rho * e.section.A;
  const Mat3 translational = diagonal(rhoA, rhoA, rhoA), rotary = localRotaryInertia(e);
  ElementMatrix m(kDofs);
  for (int g = 0; g < 5; ++g) {
    const LocalShapes n = localShapes(kGaussXi[g], ax.L, phi);
    const double w = kGaussW[g] * ax.L;
    addProduct(m, w, n.u, translational, n.u);
    addProduct(m, w, n.theta, rotary, n.theta);
  }
  return toGlobal(m, ax.R);
}

double frameAxialForce(const FrameElement& e, const double* ue) {
  Vec3 e1;
  double L = 0.0;
  axisAndLength(e, e1, L);
  const Vec3 du{ue[6] - ue[0], ue[7] - ue[1], ue[8] - ue[2]};
  return e.material.E * e.section.A / L * detail::dot(du, e1);
}

double FrameAxialForce::at(double xi) const {
  return start * (1.0 - xi) * (1.0 - 2.0 * xi) + 4.0 * middle * xi * (1.0 - xi) + end * xi * (2.0 * xi - 1.0);
}

double FrameAxialForce::mean() const { return (start + 4.0 * middle + end) / 6.0; }

FrameAxialForce frameCentrifugalAxialForce(const FrameElement& e, const double* ue, const Spin& spin) {
  Vec3 e1;
  double L = 0.0;
  axisAndLength(e, e1, L);
  const Vec3 n = detail::unitAxis(spin.axis, "frame element");
  const Spin unitSpin{n, spin.origin};
  // Axial load per unit length and unit Omega^2 at the two ends; linear in
  // between, as r_perp is.
  const double rhoA = e.material.rho * e.section.A;
  const double q1 = rhoA * detail::dot(detail::perpendicularToAxis(e.x1, unitSpin), e1);
  const double q2 = rhoA * detail::dot(detail::perpendicularToAxis(e.x2, unitSpin), e1);
  // N(xi) = N(0) - L (q1 xi + (q2 - q1) xi^2 / 2), N(0) = Nbar + L (q1/3 + q2/6).
  const double Nbar = frameAxialForce(e, ue);
  const double N0 = Nbar + L * (q1 / 3.0 + q2 / 6.0);
  const auto N = [&](double xi) { return N0 - L * (q1 * xi + 0.5 * (q2 - q1) * xi * xi); };
  return {N0, N(0.5), N(1.0)};
}

double FrameTransverseResultants::shear(double xi, double L) const {
  return shearStart - L * (loadStart * xi + 0.5 * (loadEnd - loadStart) * xi * xi);
}

double FrameTransverseResultants::moment(double xi, double L) const {
  // S' = V: S(0) + ∫_0^x V ds.
  return momentStart +
         L * (shearStart * xi - L * (loadStart * xi * xi / 2.0 + (loadEnd - loadStart) * xi * xi * xi / 6.0));
}

FramePrestress frameCentrifugalPrestress(const FrameElement& e, const double* ue, const Spin& spin) {
  FramePrestress p;
  p.N = frameCentrifugalAxialForce(e, ue, spin);
  const LocalAxes ax = localAxes(e);
  const Vec3 n = detail::unitAxis(spin.axis, "frame element");
  const Spin unitSpin{n, spin.origin};
  // The element's start force and moment per unit Omega^2: F = K_e ue - f_e,
  // f_e its own centrifugal load (exact whenever the nodal displacements are).
  const ElementMatrix K = frameStiffness(e);
  const SpinMatrices sm = frameSpinMatrices(e, unitSpin);
  std::array<double, 6> F{};
  for (int i = 0; i < 6; ++i) {
    double f = -sm.f1[i];
    for (int j = 0; j < kDofs; ++j) f += K(i, j) * ue[j];
    F[i] = f;
  }
  const auto local = [&](int row, int offset) {
    return ax.R[3 * row] * F[offset] + ax.R[3 * row + 1] * F[offset + 1] + ax.R[3 * row + 2] * F[offset + 2];
  };
  const double rhoA = e.material.rho * e.section.A;
  const auto transverse = [&](int row, double momentStart) {
    const Vec3 d{ax.R[3 * row], ax.R[3 * row + 1], ax.R[3 * row + 2]};
    FrameTransverseResultants t;
    t.shearStart = -local(row, 0);
    t.momentStart = momentStart;
    t.loadStart = rhoA * detail::dot(detail::perpendicularToAxis(e.x1, unitSpin), d);
    t.loadEnd = rhoA * detail::dot(detail::perpendicularToAxis(e.x2, unitSpin), d);
    return t;
  };
  // The moment the part beyond the start exerts, -F_theta, is (T, S_z, -S_y).
  p.y = transverse(1, local(2, 3));
  p.z = transverse(2, -local(1, 3));
  p.torque = -local(0, 3);
  return p;
}

ElementMatrix frameGeometricStiffness(const FrameElement& e, const FramePrestress& prestress) {
  ElementMatrix k = frameGeometricStiffness(e, prestress.N);
  const LocalAxes ax = localAxes(e);
  const double L = ax.L;
  const ShearParameters phi = shearParameters(e, L);
  // u' and theta_x' on the axial and twist DOFs (linear interpolation).
  std::array<double, kDofs> du{}, dtx{};
  du[0] = -1.0 / L, du[6] = 1.0 / L;
  dtx[3] = -1.0 / L, dtx[9] = 1.0 / L;
  ElementMatrix ks(kDofs);
  // V quadratic times a slope and a rotation (quadratic each), S cubic times
  // a slope and a constant: degree 6 at most, exact with the 5-point rule.
  for (int g = 0; g < 5; ++g) {
    const double xi = kGaussXi[g];
    const LocalShapes n = localShapes(xi, L, phi);
    const double w = kGaussW[g] * L;
    const double vy = w * prestress.y.shear(xi, L), vz = w * prestress.z.shear(xi, L);
    const double sy = w * prestress.y.moment(xi, L), sz = w * prestress.z.moment(xi, L);
    const double tq = 0.5 * w * prestress.torque;
    const auto& tx = n.theta[0];
    const auto& ty = n.theta[1];
    const auto& tz = n.theta[2];
    for (int i = 0; i < kDofs; ++i)
      for (int j = 0; j < kDofs; ++j)
        ks(i, j) += vy * (n.dw[i] * tx[j] + tx[i] * n.dw[j] - du[i] * tz[j] - tz[i] * du[j]) +
                    vz * (du[i] * ty[j] + ty[i] * du[j] - n.dv[i] * tx[j] - tx[i] * n.dv[j]) +
                    sy * (n.dw[i] * dtx[j] + dtx[i] * n.dw[j]) - sz * (n.dv[i] * dtx[j] + dtx[i] * n.dv[j]) +
                    tq * (n.dthetaY[i] * tz[j] + tz[i] * n.dthetaY[j] - n.dthetaZ[i] * ty[j] - ty[i] * n.dthetaZ[j]);
  }
  // The end moments' terms (semitangential moments): the bending terms
  // above leave, for a rotation theta at an end, (e1 . theta)(e1 . (m x
  // theta)) of the end moment m = (T, S_z, -S_y) unbalanced; along a
  // straight member they cancel at every node, but where members meet at an
  // angle (a coned boom on its hub) a rigid rotation about the spin axis
  // was left with the root moment's a1 (a2 S_y + a3 S_z), a1 = n . e1 (the
  // coned spinner's rotation about its axis came out at 0.34 rad/s instead
  // of 0). In local axes, with e1 x m = (0, S_y, S_z):
  //   -(1/2) [[0, S_y, S_z], [S_y, 0, 0], [S_z, 0, 0]] at the start,
  //   +(1/2) the same at the end.
  const double end[2][2] = {{prestress.y.moment(0.0, L), prestress.z.moment(0.0, L)},
                            {prestress.y.moment(1.0, L), prestress.z.moment(1.0, L)}};
  for (int a = 0; a < 2; ++a) {
    const int r = a == 0 ? 3 : 9;
    const double sign = a == 0 ? -0.5 : 0.5;
    ks(r, r + 1) += sign * end[a][0], ks(r + 1, r) += sign * end[a][0];
    ks(r, r + 2) += sign * end[a][1], ks(r + 2, r) += sign * end[a][1];
  }
  const ElementMatrix kg = toGlobal(ks, ax.R);
  for (int i = 0; i < kDofs; ++i)
    for (int j = 0; j < kDofs; ++j) k(i, j) += kg(i, j);
  return k;
}

ElementMatrix frameGeometricStiffness(const FrameElement& e, double axialForce) {
  return frameGeometricStiffness(e, FrameAxialForce{axialForce, axialForce, axialForce});
}

ElementMatrix frameGeometricStiffness(const FrameElement& e, const FrameAxialForce& axialForce) {
  const LocalAxes ax = localAxes(e);
  const ShearParameters phi = shearParameters(e, ax.L);
  ElementMatrix k(kDofs);
  // N (quadratic) times two slopes (quadratic each): degree 6, integrated
  // exactly by the 5-point rule.
  for (int g = 0; g < 5; ++g) {
    const LocalShapes n = localShapes(kGaussXi[g], ax.L, phi);
    const double w = kGaussW[g] * ax.L * axialForce.at(kGaussXi[g]);
    for (int i = 0; i < kDofs; ++i)
      for (int j = 0; j < kDofs; ++j) k(i, j) += w * (n.dv[i] * n.dv[j] + n.dw[i] * n.dw[j]);
  }
  // Twist tilts a fibre at radius r by r theta_x', and the axial stress N / A
  // works on that tilt: (1/2) N (Iy + Iz) / A theta_x'^2 per unit length;
  // theta_x' is constant on the element, so only the mean of N enters.
  const double t = axialForce.mean() * (e.section.Iy + e.section.Iz) / (e.section.A * ax.L);
  k(3, 3) += t, k(9, 9) += t, k(3, 9) -= t, k(9, 3) -= t;
  return toGlobal(k, ax.R);
}

SpinMatrices frameSpinMatrices(const FrameElement& e, const Spin& spin) {
  const LocalAxes ax = localAxes(e);
  const ShearParameters phi = shearParameters(e, ax.L);
  const Vec3 n = detail::unitAxis(spin.axis, "frame element");
  const Spin unitSpin{n, spin.origin};
  const double rhoA = e.material.rho * e.section.A;
  const Mat3 N = detail::crossMatrix(n), NtN = detail::mul(detail::transpose(N), N);
  Mat3 gyroscopic, softening;
  for (int i = 0; i < 9; ++i) gyroscopic[i] = 2.0 * rhoA * N[i], softening[i] = rhoA * NtN[i];
  // The section's rotary inertia in global axes, J = R^T J_local R, spins as
  // a rigid body at every point of the axis.
  const Mat3 J = detail::mul(detail::transpose(ax.R), detail::mul(localRotaryInertia(e), ax.R));
  const detail::RigidBodySpin rotary = detail::rigidBodySpin(J, n);
  // Without rotary inertia the twist still spins with the whole section:
  // its stiffness rho (Iz - Iy) Omega^2 (the propeller moment) is of the
  // order of torsion's own, not a correction (dropped, a blade's first
  // torsion frequency came out 2.6% low; found by a review). The twist-twist
  // terms of the full section's rigid-body spin (theory §9.3).
  const Mat3 Jfull = detail::mul(detail::transpose(ax.R),
                                 detail::mul(diagonal(e.material.rho * (e.section.Iy + e.section.Iz),
                                                      e.material.rho * e.section.Iy, e.material.rho * e.section.Iz),
                                             ax.R));
  const detail::RigidBodySpin section = detail::rigidBodySpin(Jfull, n);
  SpinMatrices s{ElementMatrix(kDofs), ElementMatrix(kDofs), std::vector<double>(kDofs, 0.0)};
  for (int g = 0; g < 5; ++g) {
    const double xi = kGaussXi[g], w = kGaussW[g] * ax.L;
    const LocalShapes local = localShapes(xi, ax.L, phi);
    const Shape u = toGlobal(local.u, ax.R), theta = toGlobal(local.theta, ax.R);
    const Vec3 x{e.x1[0] + xi * (e.x2[0] - e.x1[0]), e.x1[1] + xi * (e.x2[1] - e.x1[1]),
                 e.x1[2] + xi * (e.x2[2] - e.x1[2])};
    addProduct(s.G1, w, u, gyroscopic, u);
    addProduct(s.KT1, w, u, softening, u);
    addProduct(s.f1, w * rhoA, u, detail::perpendicularToAxis(x, unitSpin));
    // Euler-Bernoulli (rotary inertia off): the section is a point of the
    // axis for the spin terms as well. The polar inertia kept in M so that
    // torsion has mass is of the order of the bending rotary inertia that was
    // dropped, and its spin terms act on the bending rotations (the tilt
    // stiffness (J_zz - J_xx) Omega^2 of theory §9.3): they go with it, or the
    // flapwise frequency would depend on the chordwise Iz.
    if (!e.section.rotaryInertia) {
      // theta's twist alone: e1 (e1 . theta). G's twist-twist term is zero (skew).
      Shape localTwist{};
      localTwist[0] = local.theta[0];
      const Shape twist = toGlobal(localTwist, ax.R);
      addProduct(s.KT1, w, twist, section.KT, twist);
      addProduct(s.f1, w, twist, section.f);
      continue;
    }
    addProduct(s.G1, w, theta, rotary.G, theta);
    addProduct(s.KT1, w, theta, rotary.KT, theta);
    addProduct(s.f1, w, theta, rotary.f);
  }
  return s;
}

namespace {

/// The stationary form describes a shaft spinning about its own axis.
Vec3 stationaryAxis(const FrameElement& e, const LocalAxes& ax, const Vec3& axis) {
  const Vec3 n = detail::unitAxis(axis, "frame element");
  const Vec3 e1{ax.R[0], ax.R[1], ax.R[2]};
  CMS_INPUT_CHECK(!(detail::norm(detail::cross(e1, n)) <= 1e-8),
                  describe(e) << ": spin axis (" << n[0] << ", " << n[1] << ", " << n[2]
                              << ") is not parallel to the element; the "
                                 "stationary-frame gyroscopic matrix needs a "
                                 "shaft spinning about its own axis");
  return n;
}

}  // namespace

ElementMatrix frameStationaryGyroscopic(const FrameElement& e, const Vec3& axis) {
  const LocalAxes ax = localAxes(e);
  const Vec3 n = stationaryAxis(e, ax, axis);
  ElementMatrix g(kDofs);
  if (!e.section.rotaryInertia) return g;
  const ShearParameters phi = shearParameters(e, ax.L);
  // Nelson & McVaugh (1976): in the stationary frame only the polar inertia
  // rho Ip of the spinning section couples the two tilts.
  const double rhoIp = e.material.rho * (e.section.Iy + e.section.Iz);
  Mat3 B = detail::transpose(detail::crossMatrix(n));
  for (double& b : B) b *= rhoIp;
  for (int q = 0; q < 5; ++q) {
    const Shape theta = toGlobal(localShapes(kGaussXi[q], ax.L, phi).theta, ax.R);
    addProduct(g, kGaussW[q] * ax.L, theta, B, theta);
  }
  return g;
}

ElementMatrix frameStationaryTiltStiffness(const FrameElement& e, const Vec3& axis, const Vec3& frameAxis) {
  // The same check and interpolation as frameStationaryGyroscopic: the
  // spinning sections' polar inertia, now with the frame rotation's
  // -(sym(e n^T) - (e.n) I) density (theory §11.5), per unit Omega omega.
  const LocalAxes ax = localAxes(e);
  const Vec3 n = stationaryAxis(e, ax, axis), f = detail::unitAxis(frameAxis, "frame element");
  ElementMatrix k(kDofs);
  if (!e.section.rotaryInertia) return k;
  const ShearParameters phi = shearParameters(e, ax.L);
  const double rhoIp = e.material.rho * (e.section.Iy + e.section.Iz), fn = detail::dot(f, n);
  Mat3 B{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) B[3 * i + j] = -rhoIp * (0.5 * (f[i] * n[j] + n[i] * f[j]) - (i == j ? fn : 0.0));
  for (int q = 0; q < 5; ++q) {
    const Shape theta = toGlobal(localShapes(kGaussXi[q], ax.L, phi).theta, ax.R);
    addProduct(k, kGaussW[q] * ax.L, theta, B, theta);
  }
  return k;
}

}  // namespace cms::fem
