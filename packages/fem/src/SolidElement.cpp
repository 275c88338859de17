#include "cms/fem/SolidElement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "cms/core/Error.hpp"

namespace cms::fem {

namespace {

constexpr int kMaxNodes = 125;  // Hex125
constexpr int kMaxGauss = 5;    // points per direction of the largest rule below

/// Gauss-Jacobi rule with n points on [0, 1] for the weight (1 - u)^alpha:
/// the zeros of P_n^(alpha,0) by Newton with deflation from Chebyshev guesses,
/// weights 2^(alpha+1) / ((1 - x²) P_n'(x)²) on [-1, 1] (Karniadakis & Sherwin,
/// Spectral/hp Element Methods for CFD, 2nd ed., App. B; with beta = 0 the
/// Gamma factors cancel). The map to [0, 1] divides that weight by 2^(alpha+1).
void gaussJacobi01(int n, int alpha, double* u, double* w) {
  const double a = alpha;
  auto jacobi = [&](double x, double& p, double& dp) {
    double p0 = 1.0, d0 = 0.0;
    double p1 = 0.5 * (a + (a + 2.0) * x), d1 = 0.5 * (a + 2.0);
    for (int k = 2; k <= n; ++k) {
      const double c1 = 2.0 * k * (k + a) * (2.0 * k + a - 2.0);
      const double c2 = (2.0 * k + a - 1.0) * a * a;
      const double c3 = (2.0 * k + a - 2.0) * (2.0 * k + a - 1.0) * (2.0 * k + a);
      const double c4 = 2.0 * (k + a - 1.0) * (k - 1.0) * (2.0 * k + a);
      const double p2 = ((c2 + c3 * x) * p1 - c4 * p0) / c1;
      const double d2 = ((c2 + c3 * x) * d1 + c3 * p1 - c4 * d0) / c1;
      p0 = p1, d0 = d1, p1 = p2, d1 = d2;
    }
    p = p1, dp = d1;
  };
  double x[kMaxGauss];
  for (int k = 0; k < n; ++k) {
    double r = -std::cos((2.0 * k + 1.0) * M_PI / (2.0 * n));
    if (k > 0) r = 0.5 * (r + x[k - 1]);
    for (int it = 0; it < 100; ++it) {
      double p, dp, deflate = 0.0;
      jacobi(r, p, dp);
      for (int i = 0; i < k; ++i) deflate += 1.0 / (r - x[i]);
      const double delta = -p / (dp - deflate * p);
      r += delta;
      if (std::abs(delta) < 1e-15) break;
    }
    x[k] = r;
    double p, dp;
    jacobi(r, p, dp);
    u[k] = 0.5 * (r + 1.0);
    w[k] = 1.0 / ((1.0 - r * r) * dp * dp);
  }
}

/// The reference cell of each element: a formulation shares its shape's
/// nodes and shape functions.
enum class Shape { Tet4, Tet10, Hex8, Hex20, Wedge15, HexQ2, HexQ3, HexQ4 };
Shape shapeOf(SolidType type) {
  switch (type) {
    case SolidType::Tet4: return Shape::Tet4;
    case SolidType::Tet10: return Shape::Tet10;
    case SolidType::Hex8:
    case SolidType::Hex8Incompatible: return Shape::Hex8;
    case SolidType::Hex20:
    case SolidType::Hex20Reduced: return Shape::Hex20;
    case SolidType::Wedge15: return Shape::Wedge15;
    case SolidType::Hex27: return Shape::HexQ2;
    case SolidType::Hex64: return Shape::HexQ3;
    case SolidType::Hex125: return Shape::HexQ4;
  }
  throw std::logic_error("solid element: unknown SolidType");
}
/// The polynomial order per coordinate of a Lagrange hex; 0 for the others.
int lagrangeOrder(Shape s) { return s == Shape::HexQ2 ? 2 : s == Shape::HexQ3 ? 3 : s == Shape::HexQ4 ? 4 : 0; }
int shapeNodeCount(Shape s) {
  switch (s) {
    case Shape::Tet4: return 4;
    case Shape::Tet10: return 10;
    case Shape::Hex8: return 8;
    case Shape::Hex20: return 20;
    case Shape::Wedge15: return 15;
    case Shape::HexQ2: return 27;
    case Shape::HexQ3: return 64;
    case Shape::HexQ4: return 125;
  }
  throw std::logic_error("solid element: unknown Shape");
}

/// Reference-element shape functions and their derivatives in (xi, eta, zeta),
/// precomputed at the points of one quadrature rule (sized to the shape: a
/// Hex125 rule holds 125 x 125 values, a Hex20 one 27 x 20).
struct Rule {
  int nn = 0, nq = 0;
  double refVolume = 0.0;
  std::vector<double> w;       ///< weight of each point
  std::vector<double> points;  ///< reference coordinates, 3 per point
  std::vector<double> values;  ///< N_a at point q: values[q * nn + a]
  std::vector<double> grads;   ///< grad_ref N_a at point q: grads[3 * (q * nn + a) + i]

  const double* p(int q) const { return &points[3 * static_cast<std::size_t>(q)]; }
  const double* N(int q) const { return &values[static_cast<std::size_t>(q) * nn]; }
  const double (*dN(int q) const)[3] {
    return reinterpret_cast<const double(*)[3]>(&grads[3 * static_cast<std::size_t>(q) * nn]);
  }
};

/// Tet: reference vertices (0,0,0) (1,0,0) (0,1,0) (0,0,1), barycentrics
/// L = (1 - xi - eta - zeta, xi, eta, zeta). Tet10 edge nodes 4..9 sit on the
/// vertex pairs below: Gmsh's order, checked against gmsh's own second-order
/// meshes by tests/unit/fem/SolidElementTest.cpp.
constexpr int kTet10Edge[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
/// Hex: [-1, 1]³, bottom face zeta = -1 counter-clockwise seen from above, top face over it.
constexpr int kHexCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                  {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
/// Hex20 mid-edge nodes 8..19 on these corner pairs (Gmsh's order, Mesh.hpp).
constexpr int kHex20Edge[12][2] = {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3},
                                   {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}};
/// Wedge: triangle (xi, eta) with L = (1 - xi - eta, xi, eta) times zeta in
/// [-1, 1]; corners 0-2 at zeta = -1, 3-5 above them. Mid-edge nodes 6..14
/// on these corner pairs (Gmsh's order).
constexpr int kWedge15Edge[9][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 4},
                                    {2, 5}, {3, 4}, {3, 5}, {4, 5}};

/// Lagrange hexahedron of order k: nodes on the (k+1)^3 equispaced grid of
/// [-1, 1]^3 in lexicographic order, a = i + (k+1) j + (k+1)^2 l for the
/// node at (-1 + 2i/k, -1 + 2j/k, -1 + 2l/k) (the reader puts Gmsh's order
/// into this one, cms/mesh/Mesh.hpp); N_a = l_i(xi) l_j(eta) l_l(zeta) with
/// l_i the 1D Lagrange polynomials on those points.
void lagrangeHexShape(int k, const double* p, double* N, double (*dN)[3]) {
  double l[3][kMaxGauss], dl[3][kMaxGauss];  // k + 1 <= kMaxGauss
  for (int d = 0; d < 3; ++d)
    for (int i = 0; i <= k; ++i) {
      const double ti = -1.0 + 2.0 * i / k;
      double v = 1.0, dv = 0.0;
      for (int m = 0; m <= k; ++m) {
        if (m == i) continue;
        const double tm = -1.0 + 2.0 * m / k, f = (p[d] - tm) / (ti - tm);
        dv = dv * f + v / (ti - tm);  // product rule, one factor at a time
        v *= f;
      }
      l[d][i] = v, dl[d][i] = dv;
    }
  int a = 0;
  for (int c = 0; c <= k; ++c)
    for (int b = 0; b <= k; ++b)
      for (int i = 0; i <= k; ++i, ++a) {
        N[a] = l[0][i] * l[1][b] * l[2][c];
        dN[a][0] = dl[0][i] * l[1][b] * l[2][c];
        dN[a][1] = l[0][i] * dl[1][b] * l[2][c];
        dN[a][2] = l[0][i] * l[1][b] * dl[2][c];
      }
}

void shape(Shape type, const double* p, double* N, double (*dN)[3]) {
  if (const int k = lagrangeOrder(type)) return lagrangeHexShape(k, p, N, dN);
  if (type == Shape::Hex8) {
    for (int a = 0; a < 8; ++a) {
      const int* s = kHexCorner[a];
      const double f0 = 1.0 + s[0] * p[0], f1 = 1.0 + s[1] * p[1], f2 = 1.0 + s[2] * p[2];
      N[a] = 0.125 * f0 * f1 * f2;
      dN[a][0] = 0.125 * s[0] * f1 * f2;
      dN[a][1] = 0.125 * f0 * s[1] * f2;
      dN[a][2] = 0.125 * f0 * f1 * s[2];
    }
    return;
  }
  if (type == Shape::Hex20) {
    // Serendipity (Zienkiewicz & Taylor, vol. 1, §8.7): corners
    // N = (1/8) f0 f1 f2 (s.p - 2) with f_i = 1 + s_i p_i; a mid-edge node
    // with s_d = 0: N = (1/4) (1 - p_d²) f_j f_k.
    for (int a = 0; a < 8; ++a) {
      const int* s = kHexCorner[a];
      const double f[3] = {1.0 + s[0] * p[0], 1.0 + s[1] * p[1], 1.0 + s[2] * p[2]};
      const double S = s[0] * p[0] + s[1] * p[1] + s[2] * p[2] - 2.0;
      N[a] = 0.125 * f[0] * f[1] * f[2] * S;
      for (int i = 0; i < 3; ++i) {
        const double others = f[(i + 1) % 3] * f[(i + 2) % 3];
        dN[a][i] = 0.125 * s[i] * others * (S + f[i]);
      }
    }
    for (int e = 0; e < 12; ++e) {
      const int* s0 = kHexCorner[kHex20Edge[e][0]];
      const int* s1 = kHexCorner[kHex20Edge[e][1]];
      int d = 0;
      while (s0[d] == s1[d]) ++d;  // the edge runs along coordinate d
      const int j = (d + 1) % 3, k = (d + 2) % 3;
      const double g = 1.0 - p[d] * p[d], fj = 1.0 + s0[j] * p[j], fk = 1.0 + s0[k] * p[k];
      N[8 + e] = 0.25 * g * fj * fk;
      dN[8 + e][d] = -0.5 * p[d] * fj * fk;
      dN[8 + e][j] = 0.25 * g * s0[j] * fk;
      dN[8 + e][k] = 0.25 * g * fj * s0[k];
    }
    return;
  }
  if (type == Shape::Wedge15) {
    // Corners: N = (1/2) L (1 + z_a zeta)(2 L + z_a zeta - 2); triangle edges
    // at level z: 2 L_i L_j (1 + z zeta); vertical edges: L_i (1 - zeta²).
    const double L[3] = {1.0 - p[0] - p[1], p[0], p[1]};
    const double dL[3][2] = {{-1, -1}, {1, 0}, {0, 1}};
    const double zeta = p[2];
    for (int a = 0; a < 6; ++a) {
      const int i = a % 3;
      const double z = a < 3 ? -1.0 : 1.0;
      const double f = 1.0 + z * zeta, S = 2.0 * L[i] + z * zeta - 2.0;
      N[a] = 0.5 * L[i] * f * S;
      const double dNdL = 0.5 * f * (S + 2.0 * L[i]);
      dN[a][0] = dNdL * dL[i][0];
      dN[a][1] = dNdL * dL[i][1];
      dN[a][2] = 0.5 * L[i] * z * (S + f);
    }
    for (int e = 0; e < 9; ++e) {
      const int a = kWedge15Edge[e][0], b = kWedge15Edge[e][1];
      const int i = a % 3, j = b % 3;
      if ((a < 3) == (b < 3)) {  // in a triangle face
        const double z = a < 3 ? -1.0 : 1.0, f = 1.0 + z * zeta;
        N[6 + e] = 2.0 * L[i] * L[j] * f;
        for (int m = 0; m < 2; ++m) dN[6 + e][m] = 2.0 * f * (L[j] * dL[i][m] + L[i] * dL[j][m]);
        dN[6 + e][2] = 2.0 * L[i] * L[j] * z;
      } else {  // vertical, i == j
        const double g = 1.0 - zeta * zeta;
        N[6 + e] = L[i] * g;
        dN[6 + e][0] = dL[i][0] * g;
        dN[6 + e][1] = dL[i][1] * g;
        dN[6 + e][2] = -2.0 * zeta * L[i];
      }
    }
    return;
  }
  const double L[4] = {1.0 - p[0] - p[1] - p[2], p[0], p[1], p[2]};
  const double dL[4][3] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  if (type == Shape::Tet4) {
    for (int a = 0; a < 4; ++a) {
      N[a] = L[a];
      std::copy(dL[a], dL[a] + 3, dN[a]);
    }
    return;
  }
  for (int a = 0; a < 4; ++a) {
    N[a] = L[a] * (2.0 * L[a] - 1.0);
    for (int j = 0; j < 3; ++j) dN[a][j] = (4.0 * L[a] - 1.0) * dL[a][j];
  }
  for (int e = 0; e < 6; ++e) {
    const int i = kTet10Edge[e][0], k = kTet10Edge[e][1];
    N[4 + e] = 4.0 * L[i] * L[k];
    for (int j = 0; j < 3; ++j) dN[4 + e][j] = 4.0 * (L[k] * dL[i][j] + L[i] * dL[k][j]);
  }
}

/// n points per direction. Hex: Gauss-Legendre product, exact to degree 2n-1
/// in each coordinate. Tet: a conical product rule (Stroud, Approximate
/// Calculation of Multiple Integrals, 1971) in the collapsed coordinates of
/// Karniadakis & Sherwin (op. cit.):
/// zeta = u1, eta = u2 (1 - u1), xi = u3 (1 - u1)(1 - u2), whose Jacobian
/// (1 - u1)² (1 - u2) is absorbed by Gauss-Jacobi weights: a monomial of total
/// degree p becomes degree <= p in each u, so the rule is exact to total
/// degree 2n-1. Wedge: the same collapse on the triangle (eta = u1,
/// xi = u2 (1 - u1), Jacobian 1 - u1) times Gauss-Legendre in zeta: exact to
/// total degree 2n-1 in (xi, eta) and degree 2n-1 in zeta.
Rule makeRule(Shape type, int n) {
  Rule r;
  r.nn = shapeNodeCount(type);
  r.nq = n * n * n;
  r.w.resize(r.nq);
  r.points.resize(3 * static_cast<std::size_t>(r.nq));
  r.values.resize(static_cast<std::size_t>(r.nq) * r.nn);
  r.grads.resize(3 * static_cast<std::size_t>(r.nq) * r.nn);
  const bool hex = type == Shape::Hex8 || type == Shape::Hex20 || lagrangeOrder(type) > 0;
  const bool wedge = type == Shape::Wedge15;
  double u[3][kMaxGauss], w[3][kMaxGauss];
  for (int d = 0; d < 3; ++d)
    gaussJacobi01(n, hex ? 0 : wedge ? (d == 0 ? 1 : 0) : 2 - d, u[d], w[d]);
  r.refVolume = hex ? 8.0 : wedge ? 1.0 : 1.0 / 6.0;
  int q = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k, ++q) {
        double* p = &r.points[3 * static_cast<std::size_t>(q)];
        if (hex) {
          p[0] = 2.0 * u[0][i] - 1.0, p[1] = 2.0 * u[1][j] - 1.0, p[2] = 2.0 * u[2][k] - 1.0;
          r.w[q] = 8.0 * w[0][i] * w[1][j] * w[2][k];
        } else if (wedge) {
          p[1] = u[0][i];
          p[0] = u[1][j] * (1.0 - u[0][i]);
          p[2] = 2.0 * u[2][k] - 1.0;
          r.w[q] = 2.0 * w[0][i] * w[1][j] * w[2][k];
        } else {
          p[2] = u[0][i];
          p[1] = u[1][j] * (1.0 - u[0][i]);
          p[0] = u[2][k] * (1.0 - u[0][i]) * (1.0 - u[1][j]);
          r.w[q] = w[0][i] * w[1][j] * w[2][k];
        }
        shape(type, p, &r.values[static_cast<std::size_t>(q) * r.nn],
              reinterpret_cast<double(*)[3]>(&r.grads[3 * static_cast<std::size_t>(q) * r.nn]));
      }
  return r;
}

/// The shape's nodes as points (weights unused): det J there, not only at
/// the integration points, tells an element that maps part of itself
/// inside out (a mid-edge node nearer a corner than the quarter point).
Rule makeNodeRule(Shape type) {
  Rule r;
  r.nn = shapeNodeCount(type);
  r.nq = r.nn;
  r.w.assign(r.nq, 0.0);
  r.points.resize(3 * static_cast<std::size_t>(r.nq));
  r.values.resize(static_cast<std::size_t>(r.nq) * r.nn);
  r.grads.resize(3 * static_cast<std::size_t>(r.nq) * r.nn);
  std::vector<std::array<double, 3>> at;
  const auto mid = [&](int a, int b) {
    at.push_back({0.5 * (at[a][0] + at[b][0]), 0.5 * (at[a][1] + at[b][1]), 0.5 * (at[a][2] + at[b][2])});
  };
  if (const int k = lagrangeOrder(type)) {
    for (int c = 0; c <= k; ++c)
      for (int b = 0; b <= k; ++b)
        for (int i = 0; i <= k; ++i) at.push_back({-1.0 + 2.0 * i / k, -1.0 + 2.0 * b / k, -1.0 + 2.0 * c / k});
  } else if (type == Shape::Hex8 || type == Shape::Hex20) {
    for (const auto& c : kHexCorner) at.push_back({double(c[0]), double(c[1]), double(c[2])});
    if (type == Shape::Hex20)
      for (const auto& e : kHex20Edge) mid(e[0], e[1]);
  } else if (type == Shape::Wedge15) {
    const double tri[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    for (int a = 0; a < 6; ++a) at.push_back({tri[a % 3][0], tri[a % 3][1], a < 3 ? -1.0 : 1.0});
    for (const auto& e : kWedge15Edge) mid(e[0], e[1]);
  } else {
    at = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    if (type == Shape::Tet10)
      for (const auto& e : kTet10Edge) mid(e[0], e[1]);
  }
  for (int q = 0; q < r.nq; ++q) {
    double* p = &r.points[3 * static_cast<std::size_t>(q)];
    std::copy(at[q].begin(), at[q].end(), p);
    shape(type, p, &r.values[static_cast<std::size_t>(q) * r.nn],
          reinterpret_cast<double(*)[3]>(&r.grads[3 * static_cast<std::size_t>(q) * r.nn]));
  }
  return r;
}

const Rule& nodeRuleFor(Shape s) {
  static const std::array<Rule, 8> rules = {makeNodeRule(Shape::Tet4),   makeNodeRule(Shape::Tet10),
                                            makeNodeRule(Shape::Hex8),   makeNodeRule(Shape::Hex20),
                                            makeNodeRule(Shape::Wedge15), makeNodeRule(Shape::HexQ2),
                                            makeNodeRule(Shape::HexQ3),  makeNodeRule(Shape::HexQ4)};
  return rules[static_cast<std::size_t>(s)];
}

/// Stiffness rules integrate B^T D B exactly on straight-sided tetrahedra
/// and wedges (degree 0 for Tet4, 2 for Tet10, 4 for Wedge15) and
/// parallelepipeds (Hex8: degree 2 per coordinate, Hex20: 4, with 3x3x3);
/// they also integrate det J exactly on any Tet10 and trilinear hex, hence the
/// volume, and (adj J) grad_ref N, so constant-stress patch tests pass on
/// curved and distorted elements. Hex20Reduced (2x2x2) under-integrates on
/// purpose: that is C3D20R. Mass rules integrate N_a N_b det J exactly on
/// straight-sided tetrahedra (degree 2, 4), right-prism wedges (det J
/// constant in zeta; a tapered one has degree 6 in zeta), any trilinear
/// Hex8 (quartic per coordinate) and a parallelepiped Hex20 (quartic), and
/// with it the centrifugal load N_a x det J; row sums, hence the total
/// mass, are exact on every straight-sided element (theory §14.2). A Lagrange hex of order k takes
/// k + 1 points per direction for both (Hex27 3, Hex64 4, Hex125 5): N_a N_b
/// has degree 2k per coordinate, so the mass is exact on parallelepipeds, and
/// B^T D B degree 2k there too (d/deta of a degree-k polynomial in xi is
/// still degree k in xi): the stiffness is integrated exactly, with no point
/// to spare (no spurious zero-energy modes, tested on distorted cells).
enum class Use { Stiffness, Mass };

const Rule& ruleFor(SolidType type, Use use) {
  struct Rules {
    Rule tet4K = makeRule(Shape::Tet4, 1), tet4M = makeRule(Shape::Tet4, 2);
    Rule tet10K = makeRule(Shape::Tet10, 2), tet10M = makeRule(Shape::Tet10, 3);
    Rule hex2 = makeRule(Shape::Hex8, 2), hex3 = makeRule(Shape::Hex8, 3);
    Rule hex20x2 = makeRule(Shape::Hex20, 2), hex20x3 = makeRule(Shape::Hex20, 3);
    Rule wedge3 = makeRule(Shape::Wedge15, 3);
  };
  static const Rules rules;
  // The Lagrange bricks' rules (up to 125 x 125 values, 0.5 MB for Hex125)
  // are made the first time such a brick is, not for every run.
  static const auto lagrange = [](Shape s) -> const Rule& {
    if (s == Shape::HexQ2) {
      static const Rule q2 = makeRule(Shape::HexQ2, 3);
      return q2;
    }
    if (s == Shape::HexQ3) {
      static const Rule q3 = makeRule(Shape::HexQ3, 4);
      return q3;
    }
    static const Rule q4 = makeRule(Shape::HexQ4, 5);
    return q4;
  };
  const bool k = use == Use::Stiffness;
  switch (type) {
    case SolidType::Tet4: return k ? rules.tet4K : rules.tet4M;
    case SolidType::Tet10: return k ? rules.tet10K : rules.tet10M;
    case SolidType::Hex8:
    case SolidType::Hex8Incompatible: return k ? rules.hex2 : rules.hex3;
    case SolidType::Hex20: return rules.hex20x3;
    case SolidType::Hex20Reduced: return k ? rules.hex20x2 : rules.hex20x3;
    case SolidType::Wedge15: return rules.wedge3;
    case SolidType::Hex27:
    case SolidType::Hex64:
    case SolidType::Hex125: return lagrange(shapeOf(type));
  }
  throw std::logic_error("solid element: unknown SolidType");
}

/// Integration over one element: checks the input once, then yields the
/// weight times det J and, on request, the physical shape-function gradients
/// at each point.
class Integrator {
public:
  Integrator(const SolidElement& e, Use use) : r_(ruleFor(e.type, use)), x_(e.xyz) {
    CMS_INPUT_CHECK(x_ == nullptr, "solid element: node coordinates are missing (xyz is null)");
    // det J * refVolume is the volume the element would have with this
    // Jacobian throughout: below 1e-14 of its bounding box cubed it is flat
    // to rounding, and its gradients would be noise.
    double lo[3] = {x_[0], x_[1], x_[2]}, hi[3] = {x_[0], x_[1], x_[2]};
    for (int a = 1; a < r_.nn; ++a)
      for (int i = 0; i < 3; ++i)
        lo[i] = std::min(lo[i], x_[3 * a + i]), hi[i] = std::max(hi[i], x_[3 * a + i]);
    const double h = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    minDet_ = 1e-14 * h * h * h / r_.refVolume;
    // det J at the nodes too: a mid-edge node nearer a corner than the
    // quarter point inverts the corner's region while every Gauss point
    // keeps det J > 0 (a bar's frequency 19% high, found by a review). Zero
    // there is allowed (the quarter-point element, a collapsed corner).
    const Rule& nodes = nodeRuleFor(shapeOf(e.type));
    for (int q = 0; q < nodes.nq; ++q) {
      const double det = determinant(nodes.dN(q));
      if (!(det >= -minDet_))
        throw NumericalError("solid element: Jacobian determinant < 0 at node " + std::to_string(q) +
                             " (a mid-edge node nearer a corner than the quarter point, or an inverted corner: the "
                             "element maps part of itself inside out; a coarse curved mesh: refine it there, or let "
                             "Gmsh optimise the high-order mesh, Mesh.HighOrderOptimize)");
    }
  }

  const Rule& rule() const { return r_; }

  /// Weight * det J at point q; fills g[a] = grad N_a when g is not null,
  /// and the cofactor matrix C = det J * J^-T (C[i][j]) and det J when C is
  /// not null.
  double point(int q, double (*g)[3], double (*Cout)[3] = nullptr, double* detOut = nullptr) const {
    // Columns c_j = dx/dxi_j. The cofactor matrix C = det J * J^{-T} has
    // columns c1 x c2, c2 x c0, c0 x c1, and grad N = C grad_ref N / det J.
    double c[3][3] = {};
    for (int a = 0; a < r_.nn; ++a) {  // unrolled by hand: -O2 keeps c in registers
      const double* x = x_ + 3 * a;
      const double* d = r_.dN(q)[a];
      c[0][0] += x[0] * d[0], c[0][1] += x[1] * d[0], c[0][2] += x[2] * d[0];
      c[1][0] += x[0] * d[1], c[1][1] += x[1] * d[1], c[1][2] += x[2] * d[1];
      c[2][0] += x[0] * d[2], c[2][1] += x[1] * d[2], c[2][2] += x[2] * d[2];
    }
    double C[3][3];
    for (int j = 0; j < 3; ++j) {
      const double* u = c[(j + 1) % 3];
      const double* v = c[(j + 2) % 3];
      C[0][j] = u[1] * v[2] - u[2] * v[1];
      C[1][j] = u[2] * v[0] - u[0] * v[2];
      C[2][j] = u[0] * v[1] - u[1] * v[0];
    }
    const double det = c[0][0] * C[0][0] + c[0][1] * C[1][0] + c[0][2] * C[2][0];
    if (!(det > minDet_))  // also catches NaN coordinates
      throw NumericalError(
          "solid element: Jacobian determinant <= 0 at an integration point (inverted or "
          "degenerate element)");
    if (Cout) {
      for (int i = 0; i < 3; ++i) std::copy(C[i], C[i] + 3, Cout[i]);
      *detOut = det;
    }
    if (g) {
      const double inv = 1.0 / det;
      for (int a = 0; a < r_.nn; ++a) {
        const double* d = r_.dN(q)[a];
        for (int i = 0; i < 3; ++i)
          g[a][i] = inv * (C[i][0] * d[0] + C[i][1] * d[1] + C[i][2] * d[2]);
      }
    }
    return r_.w[q] * det;
  }

  /// det J at a point with reference gradients dN.
  double determinant(const double (*dN)[3]) const {
    double c[3][3] = {};
    for (int a = 0; a < r_.nn; ++a) {
      const double* x = x_ + 3 * a;
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) c[j][i] += x[i] * dN[a][j];
    }
    return c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1]) - c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0]) +
           c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
  }

  /// Physical coordinates of point q.
  void position(int q, double* x) const {
    x[0] = x[1] = x[2] = 0.0;
    for (int a = 0; a < r_.nn; ++a)
      for (int i = 0; i < 3; ++i) x[i] += r_.N(q)[a] * x_[3 * a + i];
  }

private:
  const Rule& r_;
  const double* x_;
  double minDet_ = 0.0;
};

/// Gradients at the stiffness rule's points of an element's "gradient
/// nodes": its nodes, then for Hex8Incompatible three internal modes
/// P_k = 1 - xi_k², k = 0..2, whose coefficients (one per displacement
/// component, like a node's) are condensed out. Their gradients follow
/// Taylor, Beresford & Wilson (IJNME 10, 1976): grad P_k = J0^-T grad_ref P_k
/// det J0 / det J with J0 the Jacobian at the centre, so that ∫ grad P_k dV
/// = 0 on any element and constant strain stays exact (the patch test).
/// In cofactor form, grad P_k = -2 xi_k C0[:, k] / det J.
class Gradients {
public:
  explicit Gradients(const SolidElement& e)
      : in_(e, Use::Stiffness), incompatible_(e.type == SolidType::Hex8Incompatible) {
    if (!incompatible_) return;
    // The centre Jacobian's cofactors, from the Hex8 derivatives at 0.
    double c[3][3] = {};
    for (int a = 0; a < 8; ++a)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) c[j][i] += 0.125 * kHexCorner[a][j] * e.xyz[3 * a + i];
    for (int j = 0; j < 3; ++j) {
      const double* u = c[(j + 1) % 3];
      const double* v = c[(j + 2) % 3];
      C0_[0][j] = u[1] * v[2] - u[2] * v[1];
      C0_[1][j] = u[2] * v[0] - u[0] * v[2];
      C0_[2][j] = u[0] * v[1] - u[1] * v[0];
    }
  }
  const Rule& rule() const { return in_.rule(); }
  int nodes() const { return in_.rule().nn; }
  /// Gradient nodes: nodes() plus the internal modes.
  int total() const { return nodes() + (incompatible_ ? 3 : 0); }
  bool incompatible() const { return incompatible_; }

  /// Weight * det J at point q, and g[a] for a < total().
  double point(int q, double (*g)[3]) const {
    if (!incompatible_) return in_.point(q, g);
    double C[3][3], det = 0.0;
    const double s = in_.point(q, g, C, &det);
    const double* p = in_.rule().p(q);
    for (int k = 0; k < 3; ++k) {
      const double f = -2.0 * p[k] / det;
      for (int i = 0; i < 3; ++i) g[8 + k][i] = f * C0_[i][k];
    }
    return s;
  }

private:
  Integrator in_;
  bool incompatible_;
  double C0_[3][3] = {};
};

struct Lame {
  double lambda, mu;
};
Lame lame(const IsotropicMaterial& m) {
  return {m.E * m.nu / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu)), m.shearModulus()};
}

/// Stress tensor of ue at a point with physical gradients g of nn gradient
/// nodes: sigma = lambda tr(eps) I + 2 mu eps, eps = sym(grad u).
void stressAt(const Lame& L, int nn, const double (*g)[3], const double* ue, double S[3][3]) {
  double H[3][3] = {};
  for (int a = 0; a < nn; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) H[i][j] += ue[3 * a + i] * g[a][j];
  const double tr = H[0][0] + H[1][1] + H[2][2];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      S[i][j] = L.mu * (H[i][j] + H[j][i]) + (i == j ? L.lambda * tr : 0.0);
}

/// Stiffness of all gradient nodes (3 * total() rows).
ElementMatrix gradientStiffness(const Gradients& in, const Lame& L) {
  const Rule& r = in.rule();
  const int nn = in.total(), n = 3 * nn;
  ElementMatrix K(n);
  double* P = K.a.data();
  double g[kMaxNodes][3];
  // For isotropic D, B_a^T D B_b = lambda g_a g_b^T + mu (g_b g_a^T + (g_a . g_b) I)
  // only recombines the 3x3 blocks of P = ∫ g g^T dV (g the n-vector of all
  // gradient components). So accumulate P, a contiguous rank-1 update per
  // point on the upper block triangle, and recombine once at the end.
  for (int q = 0; q < r.nq; ++q) {
    const double s = in.point(q, g);
    const double* gf = &g[0][0];
    for (int i = 0; i < n; ++i) {
      const double v = s * gf[i];
      double* row = P + static_cast<std::size_t>(i) * n;
      for (int j = i - i % 3; j < n; ++j) row[j] += v * gf[j];
    }
  }
  for (int a = 0; a < nn; ++a)
    for (int b = a; b < nn; ++b) {
      double B[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) B[i][j] = K(3 * a + i, 3 * b + j);
      const double trace = B[0][0] + B[1][1] + B[2][2];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const double v = L.lambda * B[i][j] + L.mu * (B[j][i] + (i == j ? trace : 0.0));
          K(3 * a + i, 3 * b + j) = v;
          K(3 * b + j, 3 * a + i) = v;
        }
    }
  return K;
}

/// Static condensation of the last na rows of a symmetric A (nu + na rows):
/// X = -A_aa^-1 A_au (na x nu, row-major) by Cholesky, so that the condensed
/// matrix is T^T A T with T = [I; X]. Throws cms::NumericalError when A_aa
/// is not positive definite (a degenerate element).
std::vector<double> condensation(const ElementMatrix& A, int nu) {
  const int na = A.n - nu;
  std::vector<double> Lf(static_cast<std::size_t>(na) * na, 0.0), X(static_cast<std::size_t>(na) * nu);
  for (int j = 0; j < na; ++j) {
    double d = A(nu + j, nu + j);
    for (int k = 0; k < j; ++k) d -= Lf[j * na + k] * Lf[j * na + k];
    if (!(d > 1e-12 * A(nu + j, nu + j)))
      throw NumericalError("solid element: the incompatible modes' stiffness is not positive definite "
                           "(degenerate element)");
    Lf[j * na + j] = std::sqrt(d);
    for (int i = j + 1; i < na; ++i) {
      double v = A(nu + i, nu + j);
      for (int k = 0; k < j; ++k) v -= Lf[i * na + k] * Lf[j * na + k];
      Lf[i * na + j] = v / Lf[j * na + j];
    }
  }
  for (int c = 0; c < nu; ++c) {  // solve L L^T x = -A_a,c
    double y[kMaxNodes];
    for (int i = 0; i < na; ++i) {
      double v = -A(nu + i, c);
      for (int k = 0; k < i; ++k) v -= Lf[i * na + k] * y[k];
      y[i] = v / Lf[i * na + i];
    }
    for (int i = na - 1; i >= 0; --i) {
      double v = y[i];
      for (int k = i + 1; k < na; ++k) v -= Lf[k * na + i] * y[k];
      y[i] = v / Lf[i * na + i];
    }
    for (int i = 0; i < na; ++i) X[static_cast<std::size_t>(i) * nu + c] = y[i];
  }
  return X;
}

/// T^T A T with T = [I; X] (A symmetric, nu + na rows): A_uu + A_ua X +
/// X^T A_au + X^T A_aa X, symmetrised against rounding.
ElementMatrix condensed(const ElementMatrix& A, int nu, const std::vector<double>& X) {
  const int na = A.n - nu;
  std::vector<double> AX(static_cast<std::size_t>(A.n) * nu, 0.0);  // A [I; X], A.n x nu
  for (int i = 0; i < A.n; ++i)
    for (int c = 0; c < nu; ++c) {
      double v = A(i, c);
      for (int k = 0; k < na; ++k) v += A(i, nu + k) * X[static_cast<std::size_t>(k) * nu + c];
      AX[static_cast<std::size_t>(i) * nu + c] = v;
    }
  ElementMatrix K(nu);
  for (int r = 0; r < nu; ++r)
    for (int c = r; c < nu; ++c) {
      double v = AX[static_cast<std::size_t>(r) * nu + c];
      for (int k = 0; k < na; ++k) v += X[static_cast<std::size_t>(k) * nu + r] * AX[static_cast<std::size_t>(nu + k) * nu + c];
      K(r, c) = v;
    }
  for (int r = 0; r < nu; ++r)
    for (int c = 0; c < r; ++c) K(r, c) = K(c, r);
  return K;
}

/// The displacement of every gradient node: ue, then for Hex8Incompatible
/// the condensed internal modes X ue.
std::vector<double> gradientNodeValues(const Gradients& in, const Lame& L, const double* ue,
                                       std::vector<double>* X = nullptr) {
  const int nu = 3 * in.nodes();
  std::vector<double> v(ue, ue + nu);
  if (!in.incompatible()) return v;
  std::vector<double> x = condensation(gradientStiffness(in, L), nu);
  const int na = 3 * (in.total() - in.nodes());
  for (int i = 0; i < na; ++i) {
    double s = 0.0;
    for (int c = 0; c < nu; ++c) s += x[static_cast<std::size_t>(i) * nu + c] * ue[c];
    v.push_back(s);
  }
  if (X) *X = std::move(x);
  return v;
}

/// A symmetric nn x nn matrix of node pairs, row-major (m[a * nn + b]).
using NodeMatrix = std::vector<double>;

/// Scalar consistent-mass kernel m_ab = ∫ rho N_a N_b dV (upper triangle
/// filled) and, when f is not null, f_a = ∫ rho N_a r_perp dV.
NodeMatrix scalarMass(const SolidElement& e, const Spin* spin, double* f) {
  const Integrator in(e, Use::Mass);
  const Rule& r = in.rule();
  const double rho = e.material.rho;
  const int nn = r.nn;
  NodeMatrix m(static_cast<std::size_t>(nn) * nn, 0.0);
  if (f) std::fill(f, f + 3 * r.nn, 0.0);
  for (int q = 0; q < r.nq; ++q) {
    const double rs = rho * in.point(q, nullptr);
    const double* N = r.N(q);
    for (int a = 0; a < nn; ++a) {
      double* row = &m[static_cast<std::size_t>(a) * nn];
      const double ra = rs * N[a];
      for (int b = a; b < nn; ++b) row[b] += ra * N[b];
    }
    if (f) {
      double x[3];
      in.position(q, x);
      const Vec3& n = spin->axis;
      double d[3];
      for (int i = 0; i < 3; ++i) d[i] = x[i] - spin->origin[i];
      const double along = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
      for (int i = 0; i < 3; ++i) d[i] -= along * n[i];
      for (int a = 0; a < r.nn; ++a)
        for (int i = 0; i < 3; ++i) f[3 * a + i] += rs * N[a] * d[i];
    }
  }
  return m;
}

/// Block matrix with blocks k_ab * B, k symmetric with its upper triangle
/// given. A skew B gives a skew matrix.
ElementMatrix expand(int nn, NodeMatrix& k, const double B[3][3]) {
  for (int a = 0; a < nn; ++a)
    for (int b = 0; b < a; ++b) k[static_cast<std::size_t>(a) * nn + b] = k[static_cast<std::size_t>(b) * nn + a];
  ElementMatrix M(3 * nn);
  double* row = M.a.data();
  for (int a = 0; a < nn; ++a) {
    const double* ka = &k[static_cast<std::size_t>(a) * nn];
    for (int i = 0; i < 3; ++i, row += M.n)
      for (int b = 0; b < nn; ++b)
        for (int j = 0; j < 3; ++j) row[3 * b + j] = ka[b] * B[i][j];
  }
  return M;
}

}  // namespace

const char* solidTypeName(SolidType type) {
  switch (type) {
    case SolidType::Tet4: return "Tet4";
    case SolidType::Tet10: return "Tet10";
    case SolidType::Hex8: return "Hex8";
    case SolidType::Hex20: return "Hex20";
    case SolidType::Wedge15: return "Wedge15";
    case SolidType::Hex8Incompatible: return "Hex8Incompatible";
    case SolidType::Hex20Reduced: return "Hex20Reduced";
    case SolidType::Hex27: return "Hex27";
    case SolidType::Hex64: return "Hex64";
    case SolidType::Hex125: return "Hex125";
  }
  throw std::logic_error("solid element: unknown SolidType");
}

int solidNodeCount(SolidType type) { return shapeNodeCount(shapeOf(type)); }

ElementMatrix solidStiffness(const SolidElement& e) {
  const Gradients in(e);
  const ElementMatrix K = gradientStiffness(in, lame(e.material));
  if (!in.incompatible()) return K;
  const int nu = 3 * in.nodes();
  return condensed(K, nu, condensation(K, nu));
}

ElementMatrix solidMass(const SolidElement& e) {
  NodeMatrix m = scalarMass(e, nullptr, nullptr);
  const double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  return expand(solidNodeCount(e.type), m, I);
}

double solidVolume(const SolidElement& e) {
  const Integrator in(e, Use::Mass);  // the mass's volume: M's total mass is rho times it
  double v = 0.0;
  for (int q = 0; q < in.rule().nq; ++q) v += in.point(q, nullptr);
  return v;
}

namespace {
/// G1 and KT1 from the scalar mass m (theory §9.1): blocks 2 m_ab [n]x
/// (skew) and m_ab [n]x^T [n]x = m_ab (I - n n^T).
void spinFromScalarMass(int nn, NodeMatrix& m, const Spin& spin, SpinMatrices& out) {
  const Vec3& n = spin.axis;
  const double cross2[3][3] = {{0.0, -2.0 * n[2], 2.0 * n[1]},
                               {2.0 * n[2], 0.0, -2.0 * n[0]},
                               {-2.0 * n[1], 2.0 * n[0], 0.0}};
  double P[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) P[i][j] = (i == j ? 1.0 : 0.0) - n[i] * n[j];
  out.G1 = expand(nn, m, cross2);
  out.KT1 = expand(nn, m, P);
}
}  // namespace

SpinMatrices solidSpinMatrices(const SolidElement& e, const Spin& spin) {
  const int nn = solidNodeCount(e.type);
  SpinMatrices out;
  out.f1.assign(3 * nn, 0.0);
  NodeMatrix m = scalarMass(e, &spin, out.f1.data());
  spinFromScalarMass(nn, m, spin, out);
  return out;
}

ElementMatrix solidMassWithSpin(const SolidElement& e, const Spin& spin, SpinMatrices& out) {
  const int nn = solidNodeCount(e.type);
  out.f1.assign(3 * nn, 0.0);
  NodeMatrix m = scalarMass(e, &spin, out.f1.data());
  spinFromScalarMass(nn, m, spin, out);
  const double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  return expand(nn, m, I);
}

ElementMatrix solidGeometricStiffness(const SolidElement& e, const double* ue) {
  CMS_INPUT_CHECK(ue == nullptr,
                  "solid element: geometric stiffness needs a displacement (ue is null)");
  const Gradients in(e);
  const Rule& r = in.rule();
  const int nt = in.total();
  const Lame L = lame(e.material);
  std::vector<double> X;
  const std::vector<double> u = gradientNodeValues(in, L, ue, &X);
  NodeMatrix k(static_cast<std::size_t>(nt) * nt, 0.0);
  double g[kMaxNodes][3], S[3][3], Sg[kMaxNodes][3];
  for (int q = 0; q < r.nq; ++q) {
    const double s = in.point(q, g);
    stressAt(L, nt, g, u.data(), S);
    for (int b = 0; b < nt; ++b)
      for (int i = 0; i < 3; ++i)
        Sg[b][i] = s * (S[i][0] * g[b][0] + S[i][1] * g[b][1] + S[i][2] * g[b][2]);
    for (int a = 0; a < nt; ++a) {
      double* row = &k[static_cast<std::size_t>(a) * nt];
      for (int b = a; b < nt; ++b) row[b] += g[a][0] * Sg[b][0] + g[a][1] * Sg[b][1] + g[a][2] * Sg[b][2];
    }
  }
  const double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const ElementMatrix Kg = expand(nt, k, I);
  if (!in.incompatible()) return Kg;
  // The internal modes follow ue (X ue), so the quadratic form is taken on
  // the condensed element's displacement gradient: T^T Kg T.
  return condensed(Kg, 3 * in.nodes(), X);
}

std::array<double, 6> solidMeanStress(const SolidElement& e, const double* ue) {
  CMS_INPUT_CHECK(ue == nullptr, "solid element: mean stress needs a displacement (ue is null)");
  const Gradients in(e);
  const Rule& r = in.rule();
  const Lame L = lame(e.material);
  const std::vector<double> u = gradientNodeValues(in, L, ue);
  double g[kMaxNodes][3], S[3][3], volume = 0.0;
  std::array<double, 6> mean{};
  for (int q = 0; q < r.nq; ++q) {
    const double s = in.point(q, g);
    stressAt(L, in.total(), g, u.data(), S);
    volume += s;
    const double voigt[6] = {S[0][0], S[1][1], S[2][2], S[1][2], S[0][2], S[0][1]};
    for (int i = 0; i < 6; ++i) mean[i] += s * voigt[i];
  }
  for (double& v : mean) v /= volume;
  return mean;
}

}  // namespace cms::fem
