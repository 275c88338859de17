// The 3D frame element: rigid-body modes, one-element cantilever closed
// forms (Euler-Bernoulli and Timoshenko), the classic consistent mass and
// geometric stiffness, Przemieniecki's shear-beam matrices for an oblique
// element, rotating- and stationary-frame spin terms on rigid motions, the
// convergence of a cantilever's first frequency, and clear input errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "ExpectError.hpp"
#include "cms/core/Error.hpp"
#include "cms/fem/FrameElement.hpp"

extern "C" {
void dsyev_(const char* jobz, const char* uplo, const int* n, double* a, const int* lda, double* w,
            double* work, const int* lwork, int* info);
void dsygv_(const int* itype, const char* jobz, const char* uplo, const int* n, double* a,
            const int* lda, double* b, const int* ldb, double* w, double* work, const int* lwork,
            int* info);
void dgesv_(const int* n, const int* nrhs, double* a, const int* lda, int* ipiv, double* b,
            const int* ldb, int* info);
}

using namespace cms::fem;

using cms::fixtures::expectInputError;

namespace {

using Vector = std::vector<double>;

using cms::fem::cross;  // cms/fem/Vec3.hpp
using cms::fem::dot;
using cms::fem::unit;
using cms::fem::axpy;

/// Steel, and a 40 x 70 mm rectangle (y across 40 mm, z across 70 mm).
IsotropicMaterial steel() { return {210e9, 0.3, 7850.0}; }
BeamSection rectangle(const Vec3& orientation) {
  const double b = 0.04, h = 0.07;
  BeamSection s;
  s.A = b * h;
  s.Iy = b * h * h * h / 12.0;
  s.Iz = h * b * b * b / 12.0;
  s.J = 0.229 * h * b * b * b;  // Saint-Venant constant of a 1.75:1 rectangle
  s.orientation = orientation;
  return s;
}

/// An element in no special direction, off the origin.
FrameElement obliqueElement(BeamTheory theory, double L = 0.5) {
  FrameElement e;
  e.x1 = {0.3, -0.2, 0.5};
  e.x2 = axpy(L, unit({1.0, 2.0, -0.5}), e.x1);
  e.material = steel();
  e.section = rectangle({0.2, 0.1, 1.0});
  e.theory = theory;
  return e;
}

/// Local axes as the header defines them, computed here independently.
struct Axes {
  Vec3 e1, e2, e3;
  double L;
};
Axes axesOf(const FrameElement& e) {
  Axes a;
  const Vec3 d = axpy(-1.0, e.x1, e.x2);
  a.L = std::sqrt(dot(d, d));
  a.e1 = unit(d);
  a.e2 = unit(axpy(-dot(e.section.orientation, a.e1), a.e1, e.section.orientation));
  a.e3 = cross(a.e1, a.e2);
  return a;
}

double maxAbs(const ElementMatrix& a) {
  double m = 0.0;
  for (double v : a.a) m = std::max(m, std::abs(v));
  return m;
}
double form(const ElementMatrix& a, const Vector& x, const Vector& y) {
  double s = 0.0;
  for (int i = 0; i < a.n; ++i)
    for (int j = 0; j < a.n; ++j) s += x[i] * a(i, j) * y[j];
  return s;
}
double dotv(const Vector& a, const Vector& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}
Vector multiply(const ElementMatrix& a, const Vector& x) {
  Vector y(a.n, 0.0);
  for (int i = 0; i < a.n; ++i)
    for (int j = 0; j < a.n; ++j) y[i] += a(i, j) * x[j];
  return y;
}

Vector symmetricEigenvalues(const ElementMatrix& m) {
  int n = m.n, lwork = 64 * m.n, info = 0;
  Vector a = m.a, w(n), work(lwork);
  dsyev_("N", "U", &n, a.data(), &n, w.data(), work.data(), &lwork, &info);
  EXPECT_EQ(info, 0);
  return w;
}

/// Rigid translation a: the same displacement at both nodes, no rotation.
Vector rigidTranslation(const Vec3& a) {
  Vector d(12, 0.0);
  for (int i = 0; i < 3; ++i) d[i] = d[6 + i] = a[i];
  return d;
}
/// Small rigid rotation c about the point p: u = c x (x - p), theta = c.
Vector rigidRotation(const FrameElement& e, const Vec3& c, const Vec3& p) {
  Vector d(12, 0.0);
  const Vec3 u1 = cross(c, axpy(-1.0, p, e.x1)), u2 = cross(c, axpy(-1.0, p, e.x2));
  for (int i = 0; i < 3; ++i) {
    d[i] = u1[i], d[6 + i] = u2[i];
    d[3 + i] = d[9 + i] = c[i];
  }
  return d;
}

Vec3 midpoint(const FrameElement& e) { return axpy(0.5, axpy(-1.0, e.x1, e.x2), e.x1); }

/// A 12x12 local matrix from an axial and a torsional 2x2 pattern and the
/// 4x4 matrices of the two bending planes on (v1, rz1, v2, rz2) and
/// (w1, -ry1, w2, -ry2), then T^T K T to global axes.
using Plane = std::array<std::array<double, 4>, 4>;
ElementMatrix assembleLocal(const Axes& ax, double axial, double torsion, const Plane& xy,
                            const Plane& xz, bool consistentPair) {
  ElementMatrix k(12);
  const double off = consistentPair ? 0.5 : -1.0;  // mass [2 1; 1 2] or stiffness [1 -1; -1 1]
  const double scale = consistentPair ? 2.0 : 1.0;
  for (auto [i, j, c] : {std::tuple{0, 6, axial}, std::tuple{3, 9, torsion}}) {
    k(i, i) = k(j, j) = scale * c;
    k(i, j) = k(j, i) = off * scale * c;
  }
  const int pxy[4] = {1, 5, 7, 11}, pxz[4] = {2, 4, 8, 10};
  const double sxz[4] = {1.0, -1.0, 1.0, -1.0};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      k(pxy[i], pxy[j]) = xy[i][j];
      k(pxz[i], pxz[j]) = sxz[i] * sxz[j] * xz[i][j];
    }
  const Vec3 r[3] = {ax.e1, ax.e2, ax.e3};  // local = R global
  ElementMatrix g(12);
  for (int a = 0; a < 12; a += 3)
    for (int b = 0; b < 12; b += 3)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          for (int p = 0; p < 3; ++p)
            for (int q = 0; q < 3; ++q) g(a + i, b + j) += r[p][i] * k(a + p, b + q) * r[q][j];
  return g;
}

Plane scaled(double c, const Plane& p) {
  Plane s;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) s[i][j] = c * p[i][j];
  return s;
}
Plane add(const Plane& a, const Plane& b) {
  Plane s;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) s[i][j] = a[i][j] + b[i][j];
  return s;
}

/// Przemieniecki's shear-beam matrices (Theory of Matrix Structural Analysis,
/// 1968) for one plane with shear parameter phi: stiffness, translational
/// mass (times rho A L) and rotary mass (times rho I / L); for phi = 0 the
/// classic Hermite matrices (156, 22L, ... / 420 and 36, 3L, ... / 30).
Plane przemienieckiStiffness(double EI, double L, double ph) {
  const double c = EI / ((1.0 + ph) * L * L * L);
  return scaled(c, Plane{{{12.0, 6.0 * L, -12.0, 6.0 * L},
                          {6.0 * L, (4.0 + ph) * L * L, -6.0 * L, (2.0 - ph) * L * L},
                          {-12.0, -6.0 * L, 12.0, -6.0 * L},
                          {6.0 * L, (2.0 - ph) * L * L, -6.0 * L, (4.0 + ph) * L * L}}});
}
Plane przemienieckiTranslationalMass(double L, double p) {
  const double a = 13.0 / 35.0 + 7.0 * p / 10.0 + p * p / 3.0,
               b = (11.0 / 210.0 + 11.0 * p / 120.0 + p * p / 24.0) * L,
               c = 9.0 / 70.0 + 3.0 * p / 10.0 + p * p / 6.0,
               d = (13.0 / 420.0 + 3.0 * p / 40.0 + p * p / 24.0) * L,
               e = (1.0 / 105.0 + p / 60.0 + p * p / 120.0) * L * L,
               f = (1.0 / 140.0 + p / 60.0 + p * p / 120.0) * L * L;
  return scaled(1.0 / ((1.0 + p) * (1.0 + p)),
                Plane{{{a, b, c, -d}, {b, e, d, -f}, {c, d, a, -b}, {-d, -f, -b, e}}});
}
Plane przemienieckiRotaryMass(double L, double p) {
  const double a = 6.0 / 5.0, b = (1.0 / 10.0 - p / 2.0) * L,
               e = (2.0 / 15.0 + p / 6.0 + p * p / 3.0) * L * L,
               f = (-1.0 / 30.0 - p / 6.0 + p * p / 6.0) * L * L;
  return scaled(1.0 / ((1.0 + p) * (1.0 + p)),
                Plane{{{a, b, -a, b}, {b, e, -b, f}, {-a, -b, a, -b}, {b, f, -b, e}}});
}
/// ∫ v'^T v' dx in closed form for the interdependent shape functions; for
/// phi = 0 the classic (36, 3L, -36, 3L; 3L, 4L², -3L, -L²; ...) / (30 L).
Plane slopeProduct(double L, double p) {
  const double a = 6.0 * (5.0 * p * p + 10.0 * p + 6.0), b = 3.0 * L,
               e = L * L * (5.0 * p * p + 10.0 * p + 8.0) / 2.0,
               f = -L * L * (5.0 * p * p + 10.0 * p + 2.0) / 2.0;
  return scaled(1.0 / (30.0 * L * (1.0 + p) * (1.0 + p)),
                Plane{{{a, b, -a, b}, {b, e, -b, f}, {-a, -b, a, -b}, {b, f, -b, e}}});
}

struct Phi {
  double xy, xz;
};
Phi shearParameters(const FrameElement& e) {
  if (e.theory == BeamTheory::EulerBernoulli) return {0.0, 0.0};
  const double L = axesOf(e).L, GA = e.material.shearModulus() * e.section.A;
  return {12.0 * e.material.E * e.section.Iz / (e.section.shearFactorY * GA * L * L),
          12.0 * e.material.E * e.section.Iy / (e.section.shearFactorZ * GA * L * L)};
}

void expectMatrixNear(const ElementMatrix& a, const ElementMatrix& b, double relTol) {
  ASSERT_EQ(a.n, b.n);
  const double tol = relTol * std::max(maxAbs(a), maxAbs(b));
  for (int i = 0; i < a.n; ++i)
    for (int j = 0; j < a.n; ++j)
      EXPECT_NEAR(a(i, j), b(i, j), tol) << "(" << i << ", " << j << ")";
}

/// Tip displacements of a cantilever clamped at node 1 under the tip load f
/// (6 values at node 2): solve the 6x6 block of K.
Vector tipDisplacement(const ElementMatrix& k, const Vector& f) {
  int n = 6, nrhs = 1, info = 0, ipiv[6];
  Vector a(36), b = f;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) a[j * 6 + i] = k(6 + i, 6 + j);  // column-major
  dgesv_(&n, &nrhs, a.data(), &n, ipiv, b.data(), &n, &info);
  EXPECT_EQ(info, 0);
  return b;
}

}  // namespace

// K is symmetric and its null space is exactly the six rigid-body motions:
// K d = 0 for three translations and three rotations, and K has six zero and
// six positive eigenvalues. Tolerances: rounding in T^T K T is ~1e-16 of the
// largest entry (EA/L here), so 1e-10 of it is a zero; the smallest genuine
// eigenvalue (torsion, GJ/L) is ~1e-4 of the largest, far above.
TEST(FrameStiffness, SymmetricWithExactlySixRigidBodyModesInAnyOrientation) {
  for (BeamTheory theory : {BeamTheory::EulerBernoulli, BeamTheory::Timoshenko}) {
    const FrameElement e = obliqueElement(theory);
    const ElementMatrix k = frameStiffness(e);
    const double kmax = maxAbs(k);
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) EXPECT_NEAR(k(i, j), k(j, i), 1e-14 * kmax);
    const Vec3 basis[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const Vec3& a : basis)
      for (const Vector& d : {rigidTranslation(a), rigidRotation(e, a, {1.0, -2.0, 0.7})})
        for (double r : multiply(k, d)) EXPECT_NEAR(r, 0.0, 1e-10 * kmax * 3.0);
    const Vector ev = symmetricEigenvalues(k);
    const double emax = ev.back();
    for (int i = 0; i < 6; ++i) EXPECT_LT(std::abs(ev[i]), 1e-10 * emax) << "eigenvalue " << i;
    for (int i = 6; i < 12; ++i) EXPECT_GT(ev[i], 1e-6 * emax) << "eigenvalue " << i;
  }
}

// One oblique element clamped at node 1 reproduces the cantilever exactly:
// tip deflection P L^3 / (3 E I) (+ P L / (kappa G A) for Timoshenko, exact
// with the interdependent shape functions) and tip rotation P L^2 / (2 E I)
// in both planes, with theta_z = +v' and theta_y = -w'; axial P L / (E A);
// twist T L / (G J). Tolerance 1e-9 relative: a 6x6 solve with condition
// number ~1e5 loses at most ~1e-11.
TEST(FrameStiffness, OneElementCantileverMatchesClosedFormsInBothPlanes) {
  const double P = 1000.0, T = 50.0;
  for (BeamTheory theory : {BeamTheory::EulerBernoulli, BeamTheory::Timoshenko}) {
    const FrameElement e = obliqueElement(theory);
    const Axes ax = axesOf(e);
    const double L = ax.L, E = e.material.E, G = e.material.shearModulus();
    const BeamSection& s = e.section;
    const bool shear = theory == BeamTheory::Timoshenko;
    const ElementMatrix k = frameStiffness(e);
    const auto load = [](const Vec3& force, const Vec3& moment) {
      return Vector{force[0], force[1], force[2], moment[0], moment[1], moment[2]};
    };
    const auto translation = [](const Vector& u, const Vec3& dir) {
      return u[0] * dir[0] + u[1] * dir[1] + u[2] * dir[2];
    };
    const auto rotation = [](const Vector& u, const Vec3& dir) {
      return u[3] * dir[0] + u[4] * dir[1] + u[5] * dir[2];
    };
    const auto rel = [](double a, double b) { return std::abs(a - b) / std::abs(b); };
    // x-y plane: load along e2, bending about e3 (Iz, kappa_y).
    Vector u = tipDisplacement(k, load({P * ax.e2[0], P * ax.e2[1], P * ax.e2[2]}, {}));
    const double vxy =
        P * L * L * L / (3.0 * E * s.Iz) + (shear ? P * L / (s.shearFactorY * G * s.A) : 0.0);
    EXPECT_LT(rel(translation(u, ax.e2), vxy), 1e-9);
    EXPECT_LT(rel(rotation(u, ax.e3), P * L * L / (2.0 * E * s.Iz)), 1e-9);
    EXPECT_NEAR(translation(u, ax.e3), 0.0, 1e-9 * vxy);
    // x-z plane: load along e3, bending about e2 (Iy, kappa_z), theta_y = -w'.
    u = tipDisplacement(k, load({P * ax.e3[0], P * ax.e3[1], P * ax.e3[2]}, {}));
    const double wxz =
        P * L * L * L / (3.0 * E * s.Iy) + (shear ? P * L / (s.shearFactorZ * G * s.A) : 0.0);
    EXPECT_LT(rel(translation(u, ax.e3), wxz), 1e-9);
    EXPECT_LT(rel(rotation(u, ax.e2), -P * L * L / (2.0 * E * s.Iy)), 1e-9);
    EXPECT_NEAR(translation(u, ax.e2), 0.0, 1e-9 * wxz);
    // Axial and torsion.
    u = tipDisplacement(k, load({P * ax.e1[0], P * ax.e1[1], P * ax.e1[2]}, {}));
    EXPECT_LT(rel(translation(u, ax.e1), P * L / (E * s.A)), 1e-9);
    u = tipDisplacement(k, load({}, {T * ax.e1[0], T * ax.e1[1], T * ax.e1[2]}));
    EXPECT_LT(rel(rotation(u, ax.e1), T * L / (G * s.J)), 1e-9);
  }
}

// The stiffness is Przemieniecki's closed form, rotated by T^T K T with axes
// computed here; for Timoshenko this checks phi_y (Iz, kappa_y) and phi_z
// (Iy, kappa_z) go to the right planes (the shear factors differ on purpose).
// Tolerance 1e-13 of the largest entry: both sides are a few flops each.
TEST(FrameStiffness, EqualsPrzemienieckiClosedFormRotated) {
  for (BeamTheory theory : {BeamTheory::EulerBernoulli, BeamTheory::Timoshenko}) {
    FrameElement e = obliqueElement(theory, 0.3);
    e.section.shearFactorY = 0.7, e.section.shearFactorZ = 0.9;
    const Axes ax = axesOf(e);
    const Phi phi = shearParameters(e);
    const double E = e.material.E;
    const ElementMatrix ref =
        assembleLocal(ax, E * e.section.A / ax.L, e.material.shearModulus() * e.section.J / ax.L,
                      przemienieckiStiffness(E * e.section.Iz, ax.L, phi.xy),
                      przemienieckiStiffness(E * e.section.Iy, ax.L, phi.xz), false);
    expectMatrixNear(frameStiffness(e), ref, 1e-13);
  }
}

/// The oblique element in both theories, with and without rotary inertia:
/// every variant the mass matrix has.
std::vector<FrameElement> massVariants() {
  std::vector<FrameElement> out;
  for (BeamTheory theory : {BeamTheory::EulerBernoulli, BeamTheory::Timoshenko})
    for (bool rotary : {false, true}) {
      out.push_back(obliqueElement(theory));
      out.back().section.rotaryInertia = rotary;
    }
  return out;
}

// A rigid translation carries the whole mass: d_a^T M d_b = rho A L a.b for
// unit translations, in both theories, with and without rotary inertia.
// 5-point Gauss is exact for these degree-6 integrands, so only rounding is
// left: a 12 x 12 quadratic form sums 144 products, kForm = 144 eps relative
// to the mass it carries (x 4 for the quadrature's own sums).
const double kForm = 4 * 144 * std::numeric_limits<double>::epsilon();
TEST(FrameMass, RigidTranslationCarriesTheTotalMass) {
  for (const FrameElement& e : massVariants()) {
    const ElementMatrix m = frameMass(e);
    const double total = e.material.rho * e.section.A * axesOf(e).L;
    const Vec3 a{0.6, -0.8, 0.0}, b{0.3, 0.4, 1.2};
    EXPECT_NEAR(form(m, rigidTranslation(a), rigidTranslation(a)), total, kForm * total);
    EXPECT_NEAR(form(m, rigidTranslation(a), rigidTranslation(b)), total * dot(a, b),
                kForm * total);
  }
}

// Rigid rotations about the midpoint: about the beam axis only the rotary
// polar inertia rho (Iy + Iz) L moves (kept without rotary inertia too: it is
// the twist's only mass); about e2 (e3) the translational
// rho A L^3 / 12 plus rho Iy L (rho Iz L). The interdependent shape functions
// represent rigid rotation exactly, so this holds for Timoshenko too.
// Exact quadrature: rounding only, kForm relative to the inertia carried.
TEST(FrameMass, RigidRotationsCarryTheBeamInertia) {
  for (const FrameElement& e : massVariants()) {
    const Axes ax = axesOf(e);
    const ElementMatrix m = frameMass(e);
    const double rho = e.material.rho, L = ax.L, r = e.section.rotaryInertia ? 1.0 : 0.0;
    const double rhoA = rho * e.section.A, Iy = e.section.Iy, Iz = e.section.Iz;
    const Vec3 mid = midpoint(e);
    const double axial = form(m, rigidRotation(e, ax.e1, mid), rigidRotation(e, ax.e1, mid));
    const double aboutY = form(m, rigidRotation(e, ax.e2, mid), rigidRotation(e, ax.e2, mid));
    const double aboutZ = form(m, rigidRotation(e, ax.e3, mid), rigidRotation(e, ax.e3, mid));
    const double tilt = rhoA * L * L * L / 12.0;
    EXPECT_NEAR(axial, rho * (Iy + Iz) * L, kForm * rho * (Iy + Iz) * L);
    EXPECT_NEAR(aboutY, tilt + r * rho * Iy * L, kForm * (tilt + r * rho * Iy * L));
    EXPECT_NEAR(aboutZ, tilt + r * rho * Iz * L, kForm * (tilt + r * rho * Iz * L));
  }
}

// Euler-Bernoulli without rotary inertia on an element along x: the classic
// consistent mass, rho A L / 420 (156, 22L, 54, -13L; ...) in each plane
// (sign-flipped rotation coupling in x-z) and rho A L / 6 (2, 1; 1, 2)
// axially; the twist keeps only its polar inertia, rho (Iy + Iz) L / 6 (2, 1;
// 1, 2). Tolerance 1e-13: exact.
TEST(FrameMass, EulerBernoulliEqualsClassicConsistentMass) {
  FrameElement e;
  e.x1 = {1.0, 2.0, 3.0};
  e.x2 = {1.8, 2.0, 3.0};
  e.material = steel();
  e.section = rectangle({0.0, 1.0, 0.0});
  e.section.rotaryInertia = false;
  const double L = 0.8, rhoAL = e.material.rho * e.section.A * L;
  const Plane classic{{{156.0, 22.0 * L, 54.0, -13.0 * L},
                       {22.0 * L, 4.0 * L * L, 13.0 * L, -3.0 * L * L},
                       {54.0, 13.0 * L, 156.0, -22.0 * L},
                       {-13.0 * L, -3.0 * L * L, -22.0 * L, 4.0 * L * L}}};
  const Plane bending = scaled(rhoAL / 420.0, classic);
  const double twist = e.material.rho * (e.section.Iy + e.section.Iz) * L / 6.0;
  const ElementMatrix ref = assembleLocal(axesOf(e), rhoAL / 6.0, twist, bending, bending, true);
  expectMatrixNear(frameMass(e), ref, 1e-13);
}

// Timoshenko with rotary inertia on an oblique element: Przemieniecki's
// shear-beam mass (translational rho A L and rotary rho I / L parts, each a
// quadratic in phi over (1 + phi)^2) and rho (Iy + Iz) L / 6 (2, 1; 1, 2) on
// the twist, rotated with axes computed here. Tolerance 1e-12: exact.
TEST(FrameMass, TimoshenkoEqualsPrzemienieckiShearBeamMassRotated) {
  FrameElement e = obliqueElement(BeamTheory::Timoshenko, 0.25);  // thick: phi ~ 0.1
  e.section.shearFactorY = 0.7, e.section.shearFactorZ = 0.9;
  const Axes ax = axesOf(e);
  const Phi phi = shearParameters(e);
  ASSERT_GT(phi.xy, 0.03);
  const double rho = e.material.rho, L = ax.L, rhoAL = rho * e.section.A * L;
  const Plane xy = add(scaled(rhoAL, przemienieckiTranslationalMass(L, phi.xy)),
                       scaled(rho * e.section.Iz / L, przemienieckiRotaryMass(L, phi.xy)));
  const Plane xz = add(scaled(rhoAL, przemienieckiTranslationalMass(L, phi.xz)),
                       scaled(rho * e.section.Iy / L, przemienieckiRotaryMass(L, phi.xz)));
  const ElementMatrix ref =
      assembleLocal(ax, rhoAL / 6.0, rho * (e.section.Iy + e.section.Iz) * L / 6.0, xy, xz, true);
  expectMatrixNear(frameMass(e), ref, 1e-12);
}

// The geometric stiffness of an axial force N is the classic
// N / (30 L) (36, 3L, -36, 3L; 3L, 4L², -3L, -L²; ...) in each plane for
// Euler-Bernoulli, its shear-corrected closed form for Timoshenko, plus
// N (Iy + Iz) / (A L) on the twist; rotated. Tolerance 1e-12: exact.
TEST(FrameGeometricStiffness, EqualsClassicMatrixAndItsShearForm) {
  const double N = -2.5e4;  // compression
  for (BeamTheory theory : {BeamTheory::EulerBernoulli, BeamTheory::Timoshenko}) {
    const FrameElement e = obliqueElement(theory, 0.3);
    const Axes ax = axesOf(e);
    const Phi phi = shearParameters(e);
    const double L = ax.L, torsion = N * (e.section.Iy + e.section.Iz) / (e.section.A * L);
    const ElementMatrix ref = assembleLocal(ax, 0.0, torsion, scaled(N, slopeProduct(L, phi.xy)),
                                            scaled(N, slopeProduct(L, phi.xz)), false);
    expectMatrixNear(frameGeometricStiffness(e, N), ref, 1e-12);
  }
  // For phi = 0 the closed form above is the classic one: spot-check entries.
  const Plane classic = slopeProduct(2.0, 0.0);
  EXPECT_DOUBLE_EQ(classic[0][0], 36.0 / 60.0);
  EXPECT_DOUBLE_EQ(classic[1][3], -4.0 / 60.0);
  EXPECT_DOUBLE_EQ(classic[1][1], 16.0 / 60.0);
}

// N = EA (u2 - u1).e1 / L: a stretch delta gives EA delta / L; rigid
// translations and small rigid rotations give none. Tolerances: rounding of
// a few flops (1e-12 relative), and for the rigid motions relative to the
// force their displacements would give as a stretch, EA / L max |d_i|: the
// difference u2 - u1 cancels to rounding of the displacements, 8 eps.
TEST(FrameAxialForce, StretchGivesEAOverLAndRigidMotionsNothing) {
  const FrameElement e = obliqueElement(BeamTheory::EulerBernoulli);
  const Axes ax = axesOf(e);
  const double delta = 1e-4, EA = e.material.E * e.section.A;
  Vector d(12, 0.0);
  for (int i = 0; i < 3; ++i) d[6 + i] = delta * ax.e1[i];
  EXPECT_NEAR(frameAxialForce(e, d.data()), EA * delta / ax.L, 1e-12 * EA * delta / ax.L);
  const auto stretchScale = [&](const Vector& u) {
    double m = 0.0;
    for (double v : u) m = std::max(m, std::abs(v));
    return EA / ax.L * m;
  };
  const double eps = std::numeric_limits<double>::epsilon();
  const Vector t = rigidTranslation({1e-3, 2e-3, -1e-3}), r = rigidRotation(e, {1e-4, -2e-4, 3e-4}, {0, 0, 0});
  EXPECT_NEAR(frameAxialForce(e, t.data()), 0.0, 8 * eps * stretchScale(t));
  EXPECT_NEAR(frameAxialForce(e, r.data()), 0.0, 8 * eps * stretchScale(r));
}

// G1 is skew and KT1 symmetric (to rounding, 1e-14 of the largest entry) for
// an oblique element, an oblique axis and a nonzero origin.
TEST(FrameSpin, GyroscopicIsSkewAndSofteningSymmetric) {
  const Spin spin{unit({0.3, -1.0, 0.4}), {0.5, 0.2, -0.1}};
  for (BeamTheory theory : {BeamTheory::EulerBernoulli, BeamTheory::Timoshenko}) {
    const SpinMatrices s = frameSpinMatrices(obliqueElement(theory), spin);
    ASSERT_EQ(s.G1.n, 12);
    ASSERT_EQ(s.KT1.n, 12);
    ASSERT_EQ(s.f1.size(), 12u);
    const double g = maxAbs(s.G1), k = maxAbs(s.KT1);
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) {
        EXPECT_NEAR(s.G1(i, j), -s.G1(j, i), 1e-14 * g);
        EXPECT_NEAR(s.KT1(i, j), s.KT1(j, i), 1e-14 * k);
      }
  }
}

// On rigid translations only the translational terms act, and the element
// behaves as its total mass m = rho A L at its midpoint:
// a^T KT1 a = m |n x a|^2, a^T G1 b = 2 m a.(n x b), f1.a = m r_perp(mid).a.
// Exact quadrature: rounding only, kForm relative to the inertia carried.
TEST(FrameSpin, RigidTranslationsSeeTheTotalMassAtTheMidpoint) {
  const Spin spin{unit({0.3, -1.0, 0.4}), {0.5, 0.2, -0.1}};
  const Vec3& n = spin.axis;
  for (BeamTheory theory : {BeamTheory::EulerBernoulli, BeamTheory::Timoshenko}) {
    const FrameElement e = obliqueElement(theory);
    const SpinMatrices s = frameSpinMatrices(e, spin);
    const double m = e.material.rho * e.section.A * axesOf(e).L;
    const Vec3 r = axpy(-1.0, spin.origin, midpoint(e));
    const Vec3 rPerp = axpy(-dot(r, n), n, r);
    const Vec3 basis[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const Vec3& a : basis) {
      const Vector da = rigidTranslation(a);
      const Vec3 na = cross(n, a);
      EXPECT_NEAR(form(s.KT1, da, da), m * dot(na, na), 1e-12 * m);
      EXPECT_NEAR(dotv(s.f1, da), m * dot(rPerp, a), 1e-12 * m);
      for (const Vec3& b : basis)
        EXPECT_NEAR(form(s.G1, da, rigidTranslation(b)), 2.0 * m * dot(a, cross(n, b)), 1e-12 * m);
    }
  }
}

// A beam spinning about its own axis (n = e1, origin on the axis), tilted
// rigidly about e2 or e3 through its midpoint, behaves as the rigid body it
// is, with inertia about the midpoint Jxx = rho (Iy + Iz) L,
// Jyy = rho Iy L + m L^2 / 12, Jzz = rho Iz L + m L^2 / 12 (local axes):
// the rigid-body formulas give softening Jzz - Jxx = m L^2/12 - rho Iy L for
// the tilt about e2, Jyy - Jxx for e3, Coriolis coupling Jyy + Jzz - Jxx
// between them, no centrifugal load (everything is on the axis), and the
// spin about the own axis (a rigid rotation about e1) is neutral. Tolerance
// 1e-12 relative: exact quadrature.
TEST(FrameSpin, RigidTiltsOfABeamSpinningAboutItsAxisMatchRigidBodyInertia) {
  for (BeamTheory theory : {BeamTheory::EulerBernoulli, BeamTheory::Timoshenko})
    for (double sense : {1.0, -1.0}) {
      const FrameElement e = obliqueElement(theory);
      const Axes ax = axesOf(e);
      const Spin spin{{sense * ax.e1[0], sense * ax.e1[1], sense * ax.e1[2]},
                      axpy(-0.7, ax.e1, e.x1)};
      const SpinMatrices s = frameSpinMatrices(e, spin);
      const double rho = e.material.rho, L = ax.L, m = rho * e.section.A * L;
      const double Jxx = rho * (e.section.Iy + e.section.Iz) * L,
                   Jyy = rho * e.section.Iy * L + m * L * L / 12.0,
                   Jzz = rho * e.section.Iz * L + m * L * L / 12.0;
      const Vec3 mid = midpoint(e);
      const Vector ty = rigidRotation(e, ax.e2, mid), tz = rigidRotation(e, ax.e3, mid),
                   tx = rigidRotation(e, ax.e1, mid);
      const double scale = m * L * L;
      EXPECT_NEAR(form(s.KT1, ty, ty), Jzz - Jxx, 1e-12 * scale);
      EXPECT_NEAR(form(s.KT1, tz, tz), Jyy - Jxx, 1e-12 * scale);
      EXPECT_NEAR(form(s.KT1, ty, tz), 0.0, 1e-12 * scale);
      EXPECT_NEAR(form(s.KT1, tx, tx), 0.0, 1e-12 * scale);
      // G = J[n]x + [n]x J - [Jn]x: the (e3, e2) entry is sense (Jyy + Jzz - Jxx).
      EXPECT_NEAR(form(s.G1, tz, ty), sense * (Jyy + Jzz - Jxx), 1e-12 * scale);
      EXPECT_NEAR(form(s.G1, ty, tz), -sense * (Jyy + Jzz - Jxx), 1e-12 * scale);
      for (double f : s.f1) EXPECT_NEAR(f, 0.0, 1e-12 * m * L);
    }
}

// Centrifugal load of an element inclined to the axis on a rigid rotation c
// about its midpoint: the translational work ∫ rho A (c x s).r_perp ds
// (= rho A L^3/12 (s_hat.n) c.(n x s_hat), s along the element) plus the
// rotary torque L c.((J n) x n) with J = rho (Iy+Iz) e1e1^T + rho Iy e2e2^T +
// rho Iz e3e3^T; without rotary inertia (Euler-Bernoulli) the section is a
// point of the axis for the bending rotations' spin terms, so only the
// torque's twist component e1 (e1 . torque) remains, the full section's
// propeller moment (the polar inertia kept in M for torsion once gave a
// torque on the bending rotations: issue #8 item 2).
// Tolerance 1e-12 of rho A L^3, the size of the translational term.
TEST(FrameSpin, CentrifugalLoadOnRigidRotationsIncludesTheRotaryTorque) {
  const Spin spin{unit({0.3, -1.0, 0.4}), {0.5, 0.2, -0.1}};
  const Vec3& n = spin.axis;
  for (bool rotary : {false, true}) {
    FrameElement e = obliqueElement(BeamTheory::Timoshenko);
    e.section.rotaryInertia = rotary;
    const Axes ax = axesOf(e);
    const SpinMatrices s = frameSpinMatrices(e, spin);
    const double rho = e.material.rho, L = ax.L, rhoA = rho * e.section.A;
    const double Ip = rho * (e.section.Iy + e.section.Iz), Jy = rho * e.section.Iy,
                 Jz = rho * e.section.Iz;
    const Vec3 Jn = axpy(Jy * dot(ax.e2, n), ax.e2,
                         axpy(Jz * dot(ax.e3, n), ax.e3,
                              {Ip * dot(ax.e1, n) * ax.e1[0], Ip * dot(ax.e1, n) * ax.e1[1],
                               Ip * dot(ax.e1, n) * ax.e1[2]}));
    const Vec3 torque = cross(Jn, n);
    const Vec3 basis[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const Vec3& c : basis) {
      const double translational =
          rhoA * L * L * L / 12.0 * dot(ax.e1, n) * dot(c, cross(n, ax.e1));
      const double expected =
          translational + (rotary ? L * dot(c, torque) : L * dot(c, ax.e1) * dot(ax.e1, torque));
      EXPECT_NEAR(dotv(s.f1, rigidRotation(e, c, midpoint(e))), expected, 1e-12 * rhoA * L * L * L);
    }
  }
}

// The propeller moment: a section spinning about an axis n across the beam
// resists twist by the difference of its inertias. Twisting by theta about
// e1 changes the spin energy (Omega^2 / 2) n.J(theta) n; for n = e3 its
// second derivative is rho (Iy - Iz) per unit length, the twist-twist entry
// of K_T (K = K_V - K_T: stiffening when Iz > Iy, a blade spinning flat).
// With rotary inertia off it was dropped with the bending rotations' terms
// (a blade's first torsion frequency 2.6% low; found by a review); it is
// the same with it on and off, and so is the twist's part of a general
// spin axis. The quadrature is exact; what is left is rounding in sums of
// terms of the size of the section's inertia rho max(Iy, Iz) L (the polar
// one at most 2x that), turned through the element's axes (a 12 x 12
// congruence): 1e-12 of it, about 5e3 eps, bounds that rounding with room,
// relative to the size of what it bounds; it held on OpenBLAS's SkylakeX,
// Nehalem and Haswell kernels.
TEST(FrameSpin, TheTwistKeepsThePropellerMomentWithoutRotaryInertia) {
  for (BeamTheory theory : {BeamTheory::EulerBernoulli, BeamTheory::Timoshenko}) {
    FrameElement e = obliqueElement(theory);
    const Axes ax = axesOf(e);
    const double rho = e.material.rho, L = ax.L, scale = rho * std::max(e.section.Iy, e.section.Iz) * L;
    const Vector tx = rigidRotation(e, ax.e1, midpoint(e));
    double twist[2] = {0.0, 0.0};
    for (bool rotary : {false, true}) {
      e.section.rotaryInertia = rotary;
      const SpinMatrices s = frameSpinMatrices(e, Spin{ax.e3, e.x1});
      EXPECT_NEAR(form(s.KT1, tx, tx), rho * L * (e.section.Iy - e.section.Iz), 1e-12 * scale) << "rotary " << rotary;
      twist[rotary] = form(frameSpinMatrices(e, Spin{unit({0.3, -1.0, 0.4}), {0.5, 0.2, -0.1}}).KT1, tx, tx);
    }
    EXPECT_NEAR(twist[0], twist[1], 1e-12 * scale);
  }
}

// Nelson & McVaugh's stationary-frame gyroscopic matrix on an element along
// x spinning about +x: rho Ip ∫ theta'^T ... couples the planes through the
// Hermite slopes, G(v_a, w_b) = rho Ip P_ab s_b and G(w_a, v_b) = -s_a
// rho Ip P_ab, P = (36, 3L, ...) / (30 L), s = (1, -1, 1, -1) (theta_y = -w'):
// the sign of doc/theory.md §7 (M a'' + Omega Gp b' + K a = 0 for v), for which
// backward whirl lies below forward. Skew; a rigid tilt pair of the oblique
// element gives -rho Ip L e3.(n x e2); no rotary inertia gives zero; an axis
// not along the element is rejected. Tolerance 1e-12: exact quadrature.
TEST(FrameStationaryGyroscopic, NelsonMcVaughMatrixForAShaftSpinningAboutItsAxis) {
  FrameElement e;
  e.x1 = {0.0, 0.0, 0.0};
  e.x2 = {0.6, 0.0, 0.0};
  e.material = steel();
  e.section = rectangle({0.0, 1.0, 0.0});
  const double L = 0.6, rhoIp = e.material.rho * (e.section.Iy + e.section.Iz);
  const ElementMatrix g = frameStationaryGyroscopic(e, {1.0, 0.0, 0.0});
  const Plane P = slopeProduct(L, 0.0);
  const int v[4] = {1, 5, 7, 11}, w[4] = {2, 4, 8, 10};
  const double s[4] = {1.0, -1.0, 1.0, -1.0};
  const double tol = 1e-12 * maxAbs(g);
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      EXPECT_NEAR(g(v[a], w[b]), rhoIp * P[a][b] * s[b], tol);
      EXPECT_NEAR(g(w[a], v[b]), -s[a] * rhoIp * P[a][b], tol);
      EXPECT_NEAR(g(v[a], v[b]), 0.0, tol);
      EXPECT_NEAR(g(w[a], w[b]), 0.0, tol);
    }
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 12; ++j) EXPECT_NEAR(g(i, j), -g(j, i), tol);
    for (int j : {0, 3, 6, 9}) EXPECT_NEAR(g(i, j), 0.0, tol);  // no axial, no twist
  }

  for (BeamTheory theory : {BeamTheory::EulerBernoulli, BeamTheory::Timoshenko})
    for (double sense : {1.0, -1.0}) {
      FrameElement o = obliqueElement(theory);
      const Axes ax = axesOf(o);
      const Vec3 n{sense * ax.e1[0], sense * ax.e1[1], sense * ax.e1[2]};
      const ElementMatrix go = frameStationaryGyroscopic(o, n);
      const Vec3 mid = midpoint(o);
      const double oIp = o.material.rho * (o.section.Iy + o.section.Iz);
      EXPECT_NEAR(form(go, rigidRotation(o, ax.e3, mid), rigidRotation(o, ax.e2, mid)),
                  -oIp * ax.L * dot(ax.e3, cross(n, ax.e2)), 1e-12 * oIp * ax.L);
      o.section.rotaryInertia = false;
      EXPECT_EQ(maxAbs(frameStationaryGyroscopic(o, n)), 0.0);
    }
  expectInputError([&] { frameStationaryGyroscopic(e, {1.0, 1e-6, 0.0}); }, "not parallel");
}

// A rotor's material damping seen from the stationary frame (theory §13.1):
// N1 = -D_r A, A = [n x] on each node's translations and rotations.
// - The Jeffcott sign of theory §13.4: D_r = c I on one node, spin about z,
//   gives N1 = c [[0, 1], [-1, 0]] on (x, y) and nothing along the axis.
// - An axisymmetric shaft element (Iy = Iz) along an oblique axis: its
//   Rayleigh D_r = alpha M + beta K commutes with A (to 1e-12 of ||D_r||:
//   the element matrices' rounding in oblique axes), so the returned skew
//   part is -D_r A itself; exactly skew (its upper triangle mirrored).
TEST(StationaryRotatingDamping, IsMinusDrAWithTheJeffcottSign) {
  ElementMatrix c(3);
  for (int i = 0; i < 3; ++i) c(i, i) = 2.5;
  const ElementMatrix j = stationaryRotatingDamping(c, {0.0, 0.0, 1.0}, 3);
  EXPECT_EQ(j(0, 1), 2.5);
  EXPECT_EQ(j(1, 0), -2.5);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(j(i, i), 0.0);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(j(2, i), 0.0);
    EXPECT_EQ(j(i, 2), 0.0);
  }

  FrameElement o = obliqueElement(BeamTheory::Timoshenko);
  o.section.Iz = o.section.Iy;
  o.section.J = 2.0 * o.section.Iy;
  const Axes ax = axesOf(o);
  const ElementMatrix M = frameMass(o), K = frameStiffness(o);
  ElementMatrix Dr(12);
  for (std::size_t q = 0; q < Dr.a.size(); ++q) Dr.a[q] = 0.7 * M.a[q] + 3e-5 * K.a[q];
  const ElementMatrix N = stationaryRotatingDamping(Dr, ax.e1, 6);
  const double A3[3][3] = {{0.0, -ax.e1[2], ax.e1[1]}, {ax.e1[2], 0.0, -ax.e1[0]}, {-ax.e1[1], ax.e1[0], 0.0}};
  double worst = 0.0;
  for (int r = 0; r < 12; ++r)
    for (int col = 0; col < 12; ++col) {
      EXPECT_EQ(N(r, col), -N(col, r));
      double DA = 0.0;
      for (int k = 3 * (col / 3); k < 3 * (col / 3) + 3; ++k) DA += Dr(r, k) * A3[k % 3][col % 3];
      worst = std::max(worst, std::abs(N(r, col) + DA));
    }
  EXPECT_LT(worst, 1e-12 * maxAbs(Dr));
  EXPECT_GT(maxAbs(N), 1e-3 * maxAbs(Dr));  // not trivially zero
}

namespace {
/// Dense K and M of a straight cantilever of nElem equal elements from the
/// origin along dir, clamped at node 0, without the DOFs listed in drop (per
/// node: 0..5). Eigenvalues of K x = lambda M x, ascending, by dsygv.
Vector cantileverEigenvalues(FrameElement proto, const Vec3& dir, double length, int nElem,
                             const std::vector<int>& drop) {
  const int nodes = nElem + 1, full = 6 * nodes;
  std::vector<double> K(full * full, 0.0), M(full * full, 0.0);
  for (int k = 0; k < nElem; ++k) {
    proto.x1 = {dir[0] * length * k / nElem, dir[1] * length * k / nElem,
                dir[2] * length * k / nElem};
    proto.x2 = {dir[0] * length * (k + 1) / nElem, dir[1] * length * (k + 1) / nElem,
                dir[2] * length * (k + 1) / nElem};
    const ElementMatrix ke = frameStiffness(proto), me = frameMass(proto);
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) {
        K[(6 * k + i) * full + 6 * k + j] += ke(i, j);
        M[(6 * k + i) * full + 6 * k + j] += me(i, j);
      }
  }
  std::vector<int> keep;
  for (int node = 1; node < nodes; ++node)
    for (int c = 0; c < 6; ++c)
      if (std::find(drop.begin(), drop.end(), c) == drop.end()) keep.push_back(6 * node + c);
  int n = static_cast<int>(keep.size()), itype = 1, lwork = 64 * n, info = 0;
  Vector a(n * n), b(n * n), w(n), work(lwork);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      a[j * n + i] = K[keep[i] * full + keep[j]];
      b[j * n + i] = M[keep[i] * full + keep[j]];
    }
  dsygv_(&itype, "N", "U", &n, a.data(), &n, b.data(), &n, w.data(), work.data(), &lwork, &info);
  EXPECT_EQ(info, 0);
  return w;
}
}  // namespace

// Twenty Euler-Bernoulli elements along x, without rotary inertia (so the
// twist DOFs carry no mass and are left out: they are uncoupled from bending
// and axial motion of a straight beam): the first bending frequency in each
// plane converges to (1.87510407)^2 sqrt(E I / (rho A L^4)). Tolerance 1e-5
// relative: the Hermite element's frequency error is O(h^4), 5e-8 here;
// 1.87510407 itself is given to 9 digits.
TEST(FrameEigen, CantileverFirstBendingFrequencyConverges) {
  FrameElement e;
  e.material = steel();
  e.section = rectangle({0.0, 1.0, 0.0});
  e.section.rotaryInertia = false;
  const double L = 2.0, beta = 1.87510407;
  const Vector lambda = cantileverEigenvalues(e, {1.0, 0.0, 0.0}, L, 20, {3});
  const double rhoAL4 = e.material.rho * e.section.A * std::pow(L, 4);
  const double weak = beta * beta * std::sqrt(e.material.E * e.section.Iz / rhoAL4);
  const double strong = beta * beta * std::sqrt(e.material.E * e.section.Iy / rhoAL4);
  EXPECT_NEAR(std::sqrt(lambda[0]), weak, 1e-5 * weak);
  EXPECT_NEAR(std::sqrt(lambda[1]), strong, 1e-5 * strong);
}

// A thick cantilever (L / h = 3) along an oblique axis, with rotary inertia
// (so the mass is definite and every DOF is kept): shear flexibility lowers
// the first bending frequency of each plane, by ~2% (bending across the
// 40 mm width) and ~6% (across the 70 mm depth); the test asks for 1%. The
// discretisations have converged: 20 and 40 elements agree to 1e-6 for
// Euler-Bernoulli (error O(h^4)) and 2e-5 for Timoshenko, whose shear strain
// is constant in each element with these shape functions, so that its
// frequencies converge as O(h^2) (measured: 8.6e-6 from 20 to 40 elements).
TEST(FrameEigen, ThickTimoshenkoCantileverIsLowerThanEulerBernoulli) {
  FrameElement e;
  e.material = steel();
  e.section = rectangle({0.0, 0.0, 1.0});
  const Vec3 dir = unit({1.0, 1.0, 0.3});
  const double L = 0.21;  // 3 x the 70 mm depth
  e.theory = BeamTheory::EulerBernoulli;
  const Vector eb = cantileverEigenvalues(e, dir, L, 20, {});
  const Vector eb40 = cantileverEigenvalues(e, dir, L, 40, {});
  e.theory = BeamTheory::Timoshenko;
  const Vector ti = cantileverEigenvalues(e, dir, L, 20, {});
  const Vector ti40 = cantileverEigenvalues(e, dir, L, 40, {});
  EXPECT_NEAR(std::sqrt(eb[0]), std::sqrt(eb40[0]), 1e-6 * std::sqrt(eb40[0]));
  EXPECT_NEAR(std::sqrt(ti[0]), std::sqrt(ti40[0]), 2e-5 * std::sqrt(ti40[0]));
  for (int k = 0; k < 2; ++k) {
    EXPECT_GT(ti[k], 0.0);
    EXPECT_LT(std::sqrt(ti[k]), 0.99 * std::sqrt(eb[k])) << "mode " << k;
  }
}

// Bad material and section values: cms::InputError naming the object (as
// the caller describes it), the input key with the field name, and the value.
TEST(FrameInput, BadMaterialAndSectionValuesNameTheKey) {
  const auto material = [](double E, double nu, double rho) {
    return [=] { IsotropicMaterial{E, nu, rho}.validate("material 'steel'"); };
  };
  expectInputError(material(0.0, 0.3, 7850.0), "material 'steel': Young's Modulus E = 0");
  expectInputError(material(-1.0, 0.3, 7850.0), "Young's Modulus E = -1");
  expectInputError(material(NAN, 0.3, 7850.0), "Young's Modulus E");
  expectInputError(material(210e9, 0.7, 7850.0),
                   "material 'steel': Poisson's Ratio nu = 0.7 must be in (-1, 0.5)");
  expectInputError(material(210e9, -1.0, 7850.0), "Poisson's Ratio nu = -1");
  expectInputError(material(210e9, 0.5, 7850.0), "Poisson's Ratio");
  expectInputError(material(210e9, 0.3, 0.0), "Density rho = 0");
  expectInputError(material(210e9, 0.3, INFINITY), "Density rho = inf");
  EXPECT_NO_THROW(steel().validate("material 'steel'"));

  const BeamSection good = rectangle({0.0, 0.0, 1.0});
  EXPECT_NO_THROW(good.validate("element set 'shaft'"));
  const std::vector<std::pair<std::function<void(BeamSection&)>, std::string>> bad = {
      {[](BeamSection& s) { s.A = 0.0; }, "element set 'shaft': Area A = 0"},
      {[](BeamSection& s) { s.Iy = -1e-6; }, "Iy = -1e-06"},
      {[](BeamSection& s) { s.Iz = NAN; }, "Iz = nan"},
      {[](BeamSection& s) { s.J = 0.0; }, "Torsion Constant J = 0"},
      {[](BeamSection& s) { s.shearFactorY = 0.0; }, "Shear Factor Y = 0"},
      {[](BeamSection& s) { s.shearFactorZ = -0.8; }, "Shear Factor Z = -0.8"},
      {[](BeamSection& s) {
         s.orientation = {0.0, 0.0, 0.0};
       },
       "Orientation (0, 0, 0)"},
      {[](BeamSection& s) {
         s.orientation = {0.0, NAN, 1.0};
       },
       "Orientation (0, nan, 1)"},
  };
  for (const auto& [spoil, key] : bad) {
    BeamSection s = good;
    spoil(s);
    expectInputError([&] { s.validate("element set 'shaft'"); }, key);
  }
}

// A zero-length element (also one shorter than rounding of its coordinates)
// and a section orientation along the element: cms::InputError from every
// routine that needs the local axes.
TEST(FrameInput, ZeroLengthAndParallelOrientationAreRejected) {
  FrameElement e = obliqueElement(BeamTheory::EulerBernoulli);
  e.x2 = e.x1;
  expectInputError([&] { frameStiffness(e); }, "length 0");
  expectInputError([&] { frameMass(e); }, "length 0");
  const double ue[12] = {};
  expectInputError([&] { frameAxialForce(e, ue); }, "length 0");
  e.x1 = e.x2 = {0.0, 0.0, 0.0};
  expectInputError([&] { frameStiffness(e); }, "length 0");
  e.x1 = {1e6, 0.0, 0.0};
  e.x2 = {1e6 + 1e-8, 0.0, 0.0};  // 1e-14 of the coordinates: rounding, not an element
  expectInputError([&] { frameGeometricStiffness(e, 1.0); }, "length");

  e = obliqueElement(BeamTheory::Timoshenko);
  const Axes ax = axesOf(e);
  e.section.orientation = {-2.0 * ax.e1[0], -2.0 * ax.e1[1], -2.0 * ax.e1[2]};
  const std::string msg = "orientation vector parallel to the beam";
  expectInputError([&] { frameStiffness(e); }, msg);
  expectInputError([&] { frameMass(e); }, msg);
  expectInputError([&] { frameGeometricStiffness(e, 1.0); }, msg);
  expectInputError([&] { frameSpinMatrices(e, Spin{}); }, msg);
  expectInputError([&] { frameStationaryGyroscopic(e, ax.e1); }, msg);
}
