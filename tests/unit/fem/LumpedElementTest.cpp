// Lumped items: the point mass (mass matrix, rotating-frame terms checked
// against Euler's equations of a spinning disc, stationary-frame gyroscopic
// term, validation) and grounded and two-node springs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "ExpectError.hpp"
#include "cms/core/Error.hpp"
#include "cms/fem/LumpedElements.hpp"

using namespace cms::fem;

using cms::fixtures::expectInputError;

namespace {

const double eps = std::numeric_limits<double>::epsilon();

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 crossMatrix(const Vec3& a) {
  return Mat3{{{0.0, -a[2], a[1]}, {a[2], 0.0, -a[0]}, {-a[1], a[0], 0.0}}};
}
/// Rotation by angle t about the unit axis a (Rodrigues).
Mat3 rotation(const Vec3& a, double t) {
  const Mat3 K = crossMatrix(a);
  Mat3 R{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double k2 = 0.0;
      for (int k = 0; k < 3; ++k) k2 += K[i][k] * K[k][j];
      R[i][j] = (i == j ? 1.0 : 0.0) + std::sin(t) * K[i][j] + (1.0 - std::cos(t)) * k2;
    }
  return R;
}
/// Q A Q^T.
Mat3 similar(const Mat3& Q, const Mat3& A) {
  Mat3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) r[i][j] += Q[i][k] * A[k][l] * Q[j][l];
  return r;
}
Vec3 times(const Mat3& Q, const Vec3& v) {
  return {Q[0][0] * v[0] + Q[0][1] * v[1] + Q[0][2] * v[2],
          Q[1][0] * v[0] + Q[1][1] * v[1] + Q[1][2] * v[2],
          Q[2][0] * v[0] + Q[2][1] * v[1] + Q[2][2] * v[2]};
}
std::array<double, 6> packed(const Mat3& J) {
  return {J[0][0], J[1][1], J[2][2], J[0][1], J[1][2], J[0][2]};
}
Mat3 block(const ElementMatrix& m, int offset) {
  Mat3 b;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b[i][j] = m(offset + i, offset + j);
  return b;
}
void expectNear(const Mat3& a, const Mat3& b, double tol, const char* what) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(a[i][j], b[i][j], tol) << what << " (" << i << ", " << j << ")";
}

/// A disc-like body: polar moment Ip about its axis, Id about diameters.
PointMass disc(double m, double Ip, double Id) {
  PointMass p;
  p.m = m;
  p.inertia = {Ip, Id, Id, 0.0, 0.0, 0.0};
  p.x = {0.4, -1.0, 2.0};
  return p;
}

}  // namespace

// M = diag(m I, J) with J unpacked symmetrically (xx yy zz xy yz xz); with
// three DOFs only m I, and then a nonzero J is an error, as is any other size.
TEST(PointMass, MatrixIsMassAndInertiaTensor) {
  PointMass p;
  p.m = 3.0;
  p.inertia = {2.0, 3.0, 4.0, 0.1, 0.2, 0.3};
  const ElementMatrix M = pointMassMatrix(p, 6);
  ASSERT_EQ(M.n, 6);
  const Mat3 J{{{2.0, 0.1, 0.3}, {0.1, 3.0, 0.2}, {0.3, 0.2, 4.0}}};
  expectNear(block(M, 3), J, 0.0, "J");
  expectNear(block(M, 0), Mat3{{{3.0, 0, 0}, {0, 3.0, 0}, {0, 0, 3.0}}}, 0.0, "m I");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_EQ(M(i, 3 + j), 0.0);
  expectInputError([&] { pointMassMatrix(p, 3); }, "dofs = 3");
  expectInputError([&] { pointMassMatrix(p, 5); }, "dofs = 5");
  p.inertia = {};
  const ElementMatrix M3 = pointMassMatrix(p, 3);
  ASSERT_EQ(M3.n, 3);
  expectNear(block(M3, 0), Mat3{{{3.0, 0, 0}, {0, 3.0, 0}, {0, 0, 3.0}}}, 0.0, "m I");
}

// Translation in a frame spinning about n through O: G1 = 2 m [n]x (the
// Coriolis force; for n = e_z it is 2 m [[0, -1], [1, 0]] on (x, y) as in
// doc/theory.md §7), KT1 = m [n]x^T [n]x = m (I - n n^T), f1 = m r_perp.
// Tolerances: a few flops per entry on a unit axis, so 4 eps of the entries'
// scale, m for G1 and KT1 and m |r| for f1 (the position's rounding as well).
TEST(PointMass, SpinTranslationIsCoriolisSofteningAndCentrifugalForce) {
  const PointMass p = disc(2.5, 0.0, 0.0);
  const Vec3 n = unit({1.0, -2.0, 0.5}), O{0.1, 0.2, -0.3};
  const SpinMatrices s = pointMassSpinMatrices(p, Spin{n, O}, 3);
  ASSERT_EQ(s.G1.n, 3);
  const Mat3 N = crossMatrix(n);
  Mat3 G, KT;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      G[i][j] = 2.0 * p.m * N[i][j];
      KT[i][j] = p.m * ((i == j ? 1.0 : 0.0) - n[i] * n[j]);
    }
  expectNear(block(s.G1, 0), G, 4 * eps * p.m, "G1");
  expectNear(block(s.KT1, 0), KT, 4 * eps * p.m, "KT1");
  const Vec3 r{p.x[0] - O[0], p.x[1] - O[1], p.x[2] - O[2]};
  const double along = r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
  const double rNorm = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(s.f1[i], p.m * (r[i] - along * n[i]), 16 * eps * p.m * rNorm);

  const SpinMatrices z = pointMassSpinMatrices(p, Spin{{0.0, 0.0, 1.0}, {}}, 3);
  EXPECT_EQ(z.G1(0, 1), -2.0 * p.m);
  EXPECT_EQ(z.G1(1, 0), 2.0 * p.m);
}

// Euler's equations of a body J = diag(Ip, Id, Id) spinning about its
// symmetry axis n = e_x, linearised in the tilts (theta_y, theta_z):
// KT1 = (Id - Ip) I and G1 = (2 Id - Ip) [[0, -1], [1, 0]] on the tilts,
// nothing on the spin angle theta_x, and no torque (n is principal).
// Tolerance 4 eps of the inertia Ip (the largest entry): the inputs are
// exact binary fractions and n = e_x, so only the sums of products round.
TEST(PointMass, SpinRotationOfASymmetricBodyMatchesEulerEquations) {
  const double Ip = 3.0, Id = 1.25;
  const SpinMatrices s = pointMassSpinMatrices(disc(2.0, Ip, Id), Spin{{1.0, 0.0, 0.0}, {}}, 6);
  ASSERT_EQ(s.G1.n, 6);
  expectNear(block(s.KT1, 3), Mat3{{{0.0, 0.0, 0.0}, {0.0, Id - Ip, 0.0}, {0.0, 0.0, Id - Ip}}},
             4 * eps * Ip, "KT1");
  expectNear(block(s.G1, 3),
             Mat3{{{0.0, 0.0, 0.0}, {0.0, 0.0, -(2.0 * Id - Ip)}, {0.0, 2.0 * Id - Ip, 0.0}}},
             4 * eps * Ip, "G1");
  for (int i = 3; i < 6; ++i) EXPECT_NEAR(s.f1[i], 0.0, 4 * eps * Ip);
  for (int i = 0; i < 3; ++i)
    for (int j = 3; j < 6; ++j) {
      EXPECT_EQ(s.G1(i, j), 0.0);
      EXPECT_EQ(s.KT1(i, j), 0.0);
    }
}

// Physics of the formulas above: a free spinning disc's tilt motion in the
// stationary frame is a fixed axis (frequency 0) and nutation at
// (Ip / Id) Omega; seen from the frame spinning with it, these are
// Omega and (Ip / Id - 1) Omega. Both solve the rotating-frame tilt equations
// Id theta'' + Omega G1 theta' - Omega^2 KT1 theta = 0, i.e.
// det(-w^2 Id - Omega^2 k + i w Omega g [[0, -1], [1, 0]]) =
// (w^2 Id + Omega^2 k)^2 - (w Omega g)^2 = 0 with k = KT1, g = G1 entries.
// The stationary-frame term (Ip [n]x^T, no softening) gives w = (Ip/Id) Omega
// directly. Tolerance 1e-12 relative: cancellation in the determinant.
TEST(PointMass, TiltFrequenciesOfASpinningDiscAreFixedAxisAndNutation) {
  const double Ip = 0.5, Id = 0.26, Omega = 7.0;  // a thin disc: Ip ~ 2 Id
  const PointMass p = disc(1.0, Ip, Id);
  const SpinMatrices s = pointMassSpinMatrices(p, Spin{{1.0, 0.0, 0.0}, {}}, 6);
  const double k = -s.KT1(4, 4), g = s.G1(5, 4);  // K gets -Omega^2 KT1
  const auto det = [&](double w, double kk, double gg) {
    const double a = -w * w * Id + Omega * Omega * kk, b = w * Omega * gg;
    return a * a - b * b;
  };
  const double scale = std::pow(Omega * Omega * Ip, 2);
  EXPECT_NEAR(det(Omega, k, g), 0.0, 1e-12 * scale);
  EXPECT_NEAR(det((Ip / Id - 1.0) * Omega, k, g), 0.0, 1e-12 * scale);
  const ElementMatrix gs = pointMassStationaryGyroscopic(p, {1.0, 0.0, 0.0});
  EXPECT_NEAR(det((Ip / Id) * Omega, 0.0, gs(5, 4)), 0.0, 1e-12 * scale);
  EXPECT_NEAR(det(0.0, 0.0, gs(5, 4)), 0.0, 1e-12 * scale);
}

// The rotating-frame terms are frame-independent: rotating the body (J ->
// Q J Q^T), the axis (n -> Q n) and the position together rotates the
// matrices (X -> Q X Q^T) and loads (f -> Q f). G1 is skew, KT1 symmetric.
// For J with a product of inertia the torque (J n) x n appears: for n = e_z,
// ((Jxz, Jyz, Jzz) x e_z) = (Jyz, -Jxz, 0). Tolerances relative to the
// size of what is compared: the inertia's (largest entry Jzz = 4) for the
// torque, the matrix blocks' for G1 and KT1 and the loads' for f1; 64 eps:
// three rotations (Q J Q^T, Q X Q^T, each a sum of 9 products of 3 terms)
// round on both sides.
TEST(PointMass, SpinTermsRotateWithTheBodyAndIncludeTheTorque) {
  PointMass p;
  p.m = 1.5;
  p.inertia = {2.0, 3.0, 4.0, 0.1, -0.2, 0.3};
  p.x = {0.5, 0.7, -0.2};
  const Spin spin{{0.0, 0.0, 1.0}, {0.1, 0.0, 0.0}};
  const SpinMatrices s = pointMassSpinMatrices(p, spin, 6);
  const double Jzz = p.inertia[2];  // the largest entry of the inertia tensor
  EXPECT_NEAR(s.f1[3], p.inertia[4], 4 * eps * Jzz);
  EXPECT_NEAR(s.f1[4], -p.inertia[5], 4 * eps * Jzz);
  EXPECT_NEAR(s.f1[5], 0.0, 4 * eps * Jzz);

  const Mat3 Q = rotation(unit({0.3, 1.0, -0.4}), 0.9);
  const Mat3 J = block(pointMassMatrix(p, 6), 3);
  PointMass q = p;
  q.inertia = packed(similar(Q, J));
  q.x = times(Q, p.x);
  const SpinMatrices r =
      pointMassSpinMatrices(q, Spin{times(Q, spin.axis), times(Q, spin.origin)}, 6);
  const auto largest = [](const ElementMatrix& a) {
    double x = 0.0;
    for (double v : a.a) x = std::max(x, std::abs(v));
    return x;
  };
  const double g = largest(s.G1), k = largest(s.KT1);
  double f = 0.0;
  for (double v : s.f1) f = std::max(f, std::abs(v));
  for (int offset : {0, 3}) {
    expectNear(block(r.G1, offset), similar(Q, block(s.G1, offset)), 64 * eps * g, "G1");
    expectNear(block(r.KT1, offset), similar(Q, block(s.KT1, offset)), 64 * eps * k, "KT1");
    const Vec3 fq = times(Q, {s.f1[offset], s.f1[offset + 1], s.f1[offset + 2]});
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.f1[offset + i], fq[i], 64 * eps * f);
  }
  // Skew and symmetric to the rounding of one rotated entry.
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      EXPECT_NEAR(r.G1(i, j), -r.G1(j, i), 64 * eps * g);
      EXPECT_NEAR(r.KT1(i, j), r.KT1(j, i), 64 * eps * k);
    }
}

// Stationary frame (Nelson & McVaugh 1976): (n^T J n) [n]x^T on the rotations
// of a body axisymmetric about an oblique axis n, zero elsewhere; zero for a
// body without inertia; an inertia that is not axisymmetric about n is an
// error. Tolerance 64 eps of Ip (the entries' size): rounding of the
// rotation that builds J (Q J Q^T) and of n^T J n.
TEST(PointMass, StationaryGyroscopicIsPolarInertiaAboutAnAxisymmetricAxis) {
  const double Ip = 0.8, Id = 0.45;
  const Mat3 Q = rotation(unit({-0.2, 0.5, 1.0}), 1.3);
  const Vec3 n = times(Q, {1.0, 0.0, 0.0});
  PointMass p = disc(3.0, Ip, Id);
  p.inertia = packed(similar(Q, Mat3{{{Ip, 0, 0}, {0, Id, 0}, {0, 0, Id}}}));
  const ElementMatrix g = pointMassStationaryGyroscopic(p, n);
  ASSERT_EQ(g.n, 6);
  const Mat3 N = crossMatrix(n);
  Mat3 expected;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) expected[i][j] = Ip * N[j][i];
  expectNear(block(g, 3), expected, 64 * eps * Ip, "G");
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      if (i < 3 || j < 3) {
        EXPECT_EQ(g(i, j), 0.0);
      }

  const ElementMatrix none = pointMassStationaryGyroscopic(disc(1.0, 0.0, 0.0), n);
  for (double v : none.a) EXPECT_EQ(v, 0.0);

  PointMass lopsided = disc(1.0, Ip, Id);
  lopsided.inertia[2] = 0.5;  // Jzz != Jyy
  expectInputError(
      [&] {
        pointMassStationaryGyroscopic(lopsided, {1.0, 0.0, 0.0});
      },
      "not axisymmetric");
  expectInputError(
      [&] {
        pointMassStationaryGyroscopic(disc(1.0, Ip, Id), {0.0, 1.0, 0.0});
      },
      "not axisymmetric");
}

TEST(PointMass, ValidateNamesTheItemAndTheKey) {
  EXPECT_NO_THROW(disc(1.0, 0.5, 0.25).validate("point mass 'hub'"));
  EXPECT_NO_THROW(disc(0.0, 0.5, 0.25).validate("point mass 'flywheel'"));  // inertia only
  EXPECT_NO_THROW(disc(2.0, 0.0, 0.0).validate("point mass 'lump'"));       // mass only
  PointMass thin = disc(1.0, 0.0, 0.0);
  thin.inertia = {0.0, 1.0, 1.0, 0.0, 0.0, 0.0};  // semidefinite: a thin rod along x
  EXPECT_NO_THROW(thin.validate("point mass 'rod'"));

  expectInputError([] { disc(-1.0, 0.5, 0.25).validate("point mass 'hub'"); },
                   "point mass 'hub': Mass m = -1");
  expectInputError([] { disc(NAN, 0.5, 0.25).validate("point mass 'hub'"); }, "Mass m = nan");
  expectInputError([] { disc(0.0, 0.0, 0.0).validate("point mass 'hub'"); },
                   "point mass 'hub': Mass m = 0");
  PointMass p = disc(1.0, 0.5, 0.25);
  p.inertia[4] = INFINITY;
  expectInputError([&] { p.validate("point mass 'hub'"); }, "Inertia Jyz = inf");
  p = disc(1.0, 0.5, 0.25);
  p.inertia[3] = 1.0;  // |Jxy| beyond sqrt(Jxx Jyy): an eigenvalue is negative
  expectInputError([&] { p.validate("point mass 'hub'"); }, "positive semidefinite");
  p = disc(1.0, -0.5, 0.25);
  expectInputError([&] { p.validate("point mass 'hub'"); }, "point mass 'hub': Inertia (Jxx");
}

// Springs: diag(k) grounded, [[k, -k], [-k, k]] between two nodes; three DOFs
// use kx ky kz and reject rotational stiffness; negative or non-finite k and
// sizes other than 3 or 6 are errors naming the key.
TEST(Spring, GroundedAndTwoNodeMatrices) {
  const std::array<double, 6> k{1.0, 2.0, 3.0, 4.0, 5.0, 6.0};
  const ElementMatrix g = groundedSpringMatrix(k, 6);
  ASSERT_EQ(g.n, 6);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) EXPECT_EQ(g(i, j), i == j ? k[i] : 0.0);
  const ElementMatrix t = twoNodeSpringMatrix(k, 6);
  ASSERT_EQ(t.n, 12);
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      const double expected = i % 6 != j % 6 ? 0.0 : (i == j ? k[i % 6] : -k[i % 6]);
      EXPECT_EQ(t(i, j), expected) << i << ", " << j;
    }
  const std::array<double, 6> translational{7.0, 8.0, 9.0, 0.0, 0.0, 0.0};
  const ElementMatrix g3 = groundedSpringMatrix(translational, 3);
  ASSERT_EQ(g3.n, 3);
  EXPECT_EQ(g3(2, 2), 9.0);
  const ElementMatrix t3 = twoNodeSpringMatrix(translational, 3);
  ASSERT_EQ(t3.n, 6);
  EXPECT_EQ(t3(1, 4), -8.0);
  EXPECT_EQ(t3(4, 4), 8.0);
}

TEST(Spring, BadStiffnessAndSizesNameTheKey) {
  std::array<double, 6> k{1.0, 2.0, 3.0, 4.0, 5.0, 6.0};
  expectInputError([&] { groundedSpringMatrix(k, 3); }, "krx = 4");
  expectInputError([&] { twoNodeSpringMatrix(k, 3); }, "krx = 4");
  expectInputError([&] { groundedSpringMatrix(k, 4); }, "dofs = 4");
  expectInputError([&] { twoNodeSpringMatrix(k, 12); }, "dofs = 12");
  k[1] = -2.0;
  expectInputError([&] { groundedSpringMatrix(k, 6); }, "Stiffness ky = -2");
  k[1] = 2.0, k[5] = NAN;
  expectInputError([&] { twoNodeSpringMatrix(k, 6); }, "Stiffness krz = nan");
}
