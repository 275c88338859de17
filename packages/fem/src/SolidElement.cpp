#include "cms/fem/SolidElement.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cms/core/Error.hpp"

namespace cms::fem {

namespace {

constexpr int kMaxNodes = 10;
constexpr int kMaxPoints = 27;
constexpr int kMaxGauss = 3;  // points per direction of the largest rule below

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

/// Reference-element shape functions and their derivatives in (xi, eta, zeta),
/// precomputed at the points of one quadrature rule.
struct Rule {
  int nn = 0, nq = 0;
  double refVolume = 0.0;
  double w[kMaxPoints] = {};
  double N[kMaxPoints][kMaxNodes] = {};
  double dN[kMaxPoints][kMaxNodes][3] = {};
};

/// Tet: reference vertices (0,0,0) (1,0,0) (0,1,0) (0,0,1), barycentrics
/// L = (1 - xi - eta - zeta, xi, eta, zeta). Tet10 edge nodes 4..9 sit on the
/// vertex pairs below: Gmsh's order, checked against gmsh's own second-order
/// meshes by tests/unit/fem/SolidElementTest.cpp.
constexpr int kTet10Edge[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
/// Hex: [-1, 1]³, bottom face zeta = -1 counter-clockwise seen from above, top face over it.
constexpr int kHexCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                  {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

void shape(SolidType type, const double* p, double* N, double (*dN)[3]) {
  if (type == SolidType::Hex8) {
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
  const double L[4] = {1.0 - p[0] - p[1] - p[2], p[0], p[1], p[2]};
  const double dL[4][3] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  if (type == SolidType::Tet4) {
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
/// degree 2n-1.
Rule makeRule(SolidType type, int n) {
  Rule r;
  r.nn = solidNodeCount(type);
  r.nq = n * n * n;
  double u[3][kMaxGauss], w[3][kMaxGauss];
  for (int d = 0; d < 3; ++d) gaussJacobi01(n, type == SolidType::Hex8 ? 0 : 2 - d, u[d], w[d]);
  r.refVolume = type == SolidType::Hex8 ? 8.0 : 1.0 / 6.0;
  int q = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k, ++q) {
        double p[3];
        if (type == SolidType::Hex8) {
          p[0] = 2.0 * u[0][i] - 1.0, p[1] = 2.0 * u[1][j] - 1.0, p[2] = 2.0 * u[2][k] - 1.0;
          r.w[q] = 8.0 * w[0][i] * w[1][j] * w[2][k];
        } else {
          p[2] = u[0][i];
          p[1] = u[1][j] * (1.0 - u[0][i]);
          p[0] = u[2][k] * (1.0 - u[0][i]) * (1.0 - u[1][j]);
          r.w[q] = w[0][i] * w[1][j] * w[2][k];
        }
        shape(type, p, r.N[q], r.dN[q]);
      }
  return r;
}

/// Stiffness rules integrate B^T D B exactly on straight-sided tetrahedra
/// (degree 0 for Tet4, 2 for Tet10) and parallelepipeds; they also integrate
/// det J exactly on any element (constant, cubic for curved Tet10, at most
/// quadratic per coordinate for a trilinear hex), hence the volume, and
/// (adj J) grad_ref N, so constant-stress patch tests pass on curved and
/// distorted elements. Mass rules integrate N_a N_b det J exactly on
/// straight-sided tetrahedra (degree 2, 4) and on any trilinear hex (quartic
/// per coordinate), and with it the centrifugal load N_a x det J.
enum class Use { Stiffness, Mass };

const Rule& ruleFor(SolidType type, Use use) {
  struct Rules {
    Rule tet4K = makeRule(SolidType::Tet4, 1), tet4M = makeRule(SolidType::Tet4, 2);
    Rule tet10K = makeRule(SolidType::Tet10, 2), tet10M = makeRule(SolidType::Tet10, 3);
    Rule hexK = makeRule(SolidType::Hex8, 2), hexM = makeRule(SolidType::Hex8, 3);
  };
  static const Rules rules;
  const bool k = use == Use::Stiffness;
  switch (type) {
    case SolidType::Tet4: return k ? rules.tet4K : rules.tet4M;
    case SolidType::Tet10: return k ? rules.tet10K : rules.tet10M;
    case SolidType::Hex8: return k ? rules.hexK : rules.hexM;
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
  }

  const Rule& rule() const { return r_; }

  /// Weight * det J at point q; fills g[a] = grad N_a when g is not null.
  double point(int q, double (*g)[3]) const {
    // Columns c_j = dx/dxi_j. The cofactor matrix C = det J * J^{-T} has
    // columns c1 x c2, c2 x c0, c0 x c1, and grad N = C grad_ref N / det J.
    double c[3][3] = {};
    for (int a = 0; a < r_.nn; ++a) {  // unrolled by hand: -O2 keeps c in registers
      const double* x = x_ + 3 * a;
      const double* d = r_.dN[q][a];
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
    if (g) {
      const double inv = 1.0 / det;
      for (int a = 0; a < r_.nn; ++a) {
        const double* d = r_.dN[q][a];
        for (int i = 0; i < 3; ++i)
          g[a][i] = inv * (C[i][0] * d[0] + C[i][1] * d[1] + C[i][2] * d[2]);
      }
    }
    return r_.w[q] * det;
  }

  /// Physical coordinates of point q.
  void position(int q, double* x) const {
    x[0] = x[1] = x[2] = 0.0;
    for (int a = 0; a < r_.nn; ++a)
      for (int i = 0; i < 3; ++i) x[i] += r_.N[q][a] * x_[3 * a + i];
  }

private:
  const Rule& r_;
  const double* x_;
  double minDet_ = 0.0;
};

struct Lame {
  double lambda, mu;
};
Lame lame(const IsotropicMaterial& m) {
  return {m.E * m.nu / ((1.0 + m.nu) * (1.0 - 2.0 * m.nu)), m.shearModulus()};
}

/// Stress tensor of ue at a point with physical gradients g:
/// sigma = lambda tr(eps) I + 2 mu eps, eps = sym(grad u).
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

/// Scalar consistent-mass kernel m_ab = ∫ rho N_a N_b dV (upper triangle
/// filled) and, when f is not null, f_a = ∫ rho N_a r_perp dV.
void scalarMass(const SolidElement& e, double m[kMaxNodes][kMaxNodes], const Spin* spin,
                double* f) {
  const Integrator in(e, Use::Mass);
  const Rule& r = in.rule();
  const double rho = e.material.rho;
  for (int a = 0; a < r.nn; ++a) std::fill(m[a], m[a] + r.nn, 0.0);
  if (f) std::fill(f, f + 3 * r.nn, 0.0);
  for (int q = 0; q < r.nq; ++q) {
    const double rs = rho * in.point(q, nullptr);
    const double* N = r.N[q];
    for (int a = 0; a < r.nn; ++a)
      for (int b = a; b < r.nn; ++b) m[a][b] += rs * N[a] * N[b];
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
}

/// Block matrix with blocks k_ab * B, k symmetric with its upper triangle
/// given. A skew B gives a skew matrix.
ElementMatrix expand(int nn, double k[kMaxNodes][kMaxNodes], const double B[3][3]) {
  for (int a = 0; a < nn; ++a)
    for (int b = 0; b < a; ++b) k[a][b] = k[b][a];
  ElementMatrix M(3 * nn);
  double* row = M.a.data();
  for (int a = 0; a < nn; ++a)
    for (int i = 0; i < 3; ++i, row += M.n)
      for (int b = 0; b < nn; ++b)
        for (int j = 0; j < 3; ++j) row[3 * b + j] = k[a][b] * B[i][j];
  return M;
}

}  // namespace

int solidNodeCount(SolidType type) {
  switch (type) {
    case SolidType::Tet4: return 4;
    case SolidType::Tet10: return 10;
    case SolidType::Hex8: return 8;
  }
  throw std::logic_error("solid element: unknown SolidType");
}

ElementMatrix solidStiffness(const SolidElement& e) {
  const Integrator in(e, Use::Stiffness);
  const Rule& r = in.rule();
  const int nn = r.nn, n = 3 * nn;
  const Lame L = lame(e.material);
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

ElementMatrix solidMass(const SolidElement& e) {
  double m[kMaxNodes][kMaxNodes];
  scalarMass(e, m, nullptr, nullptr);
  const double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  return expand(solidNodeCount(e.type), m, I);
}

double solidVolume(const SolidElement& e) {
  const Integrator in(e, Use::Stiffness);
  double v = 0.0;
  for (int q = 0; q < in.rule().nq; ++q) v += in.point(q, nullptr);
  return v;
}

SpinMatrices solidSpinMatrices(const SolidElement& e, const Spin& spin) {
  const int nn = solidNodeCount(e.type);
  double m[kMaxNodes][kMaxNodes];
  SpinMatrices out;
  out.f1.assign(3 * nn, 0.0);
  scalarMass(e, m, &spin, out.f1.data());
  const Vec3& n = spin.axis;
  // G1 blocks 2 m_ab [n]x (skew); KT1 blocks m_ab [n]x^T [n]x = m_ab (I - n n^T).
  const double cross2[3][3] = {{0.0, -2.0 * n[2], 2.0 * n[1]},
                               {2.0 * n[2], 0.0, -2.0 * n[0]},
                               {-2.0 * n[1], 2.0 * n[0], 0.0}};
  double P[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) P[i][j] = (i == j ? 1.0 : 0.0) - n[i] * n[j];
  out.G1 = expand(nn, m, cross2);
  out.KT1 = expand(nn, m, P);
  return out;
}

ElementMatrix solidGeometricStiffness(const SolidElement& e, const double* ue) {
  CMS_INPUT_CHECK(ue == nullptr,
                  "solid element: geometric stiffness needs a displacement (ue is null)");
  const Integrator in(e, Use::Stiffness);
  const Rule& r = in.rule();
  const int nn = r.nn;
  const Lame L = lame(e.material);
  double k[kMaxNodes][kMaxNodes] = {};
  double g[kMaxNodes][3], S[3][3], Sg[kMaxNodes][3];
  for (int q = 0; q < r.nq; ++q) {
    const double s = in.point(q, g);
    stressAt(L, nn, g, ue, S);
    for (int b = 0; b < nn; ++b)
      for (int i = 0; i < 3; ++i)
        Sg[b][i] = s * (S[i][0] * g[b][0] + S[i][1] * g[b][1] + S[i][2] * g[b][2]);
    for (int a = 0; a < nn; ++a)
      for (int b = a; b < nn; ++b)
        k[a][b] += g[a][0] * Sg[b][0] + g[a][1] * Sg[b][1] + g[a][2] * Sg[b][2];
  }
  const double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  return expand(nn, k, I);
}

std::array<double, 6> solidMeanStress(const SolidElement& e, const double* ue) {
  CMS_INPUT_CHECK(ue == nullptr, "solid element: mean stress needs a displacement (ue is null)");
  const Integrator in(e, Use::Stiffness);
  const Rule& r = in.rule();
  const Lame L = lame(e.material);
  double g[kMaxNodes][3], S[3][3], volume = 0.0;
  std::array<double, 6> mean{};
  for (int q = 0; q < r.nq; ++q) {
    const double s = in.point(q, g);
    stressAt(L, r.nn, g, ue, S);
    volume += s;
    const double voigt[6] = {S[0][0], S[1][1], S[2][2], S[1][2], S[0][2], S[0][1]};
    for (int i = 0; i < 6; ++i) mean[i] += s * voigt[i];
  }
  for (double& v : mean) v /= volume;
  return mean;
}

}  // namespace cms::fem
