#include "cms/fem/ElementMatrix.hpp"

#include <cmath>
#include <utility>

#include "cms/core/Error.hpp"

namespace cms::fem {

// `what` names the object in full (e.g. "material 'steel'" or a parameter-list
// path); keys are given as the model's input keys followed by the field name.

namespace {
void checkPositive(double value, const char* what, const char* key) {
  CMS_INPUT_CHECK(!(std::isfinite(value) && value > 0.0),
                  what << ": " << key << " = " << value << " must be positive and finite");
}
}  // namespace

void IsotropicMaterial::validate(const char* what) const {
  checkPositive(E, what, "Young's Modulus E");
  CMS_INPUT_CHECK(!(std::isfinite(nu) && nu > -1.0 && nu < 0.5),
                  what << ": Poisson's Ratio nu = " << nu << " must be in (-1, 0.5)");
  checkPositive(rho, what, "Density rho");
}

void BeamSection::validate(const char* what) const {
  const std::pair<double, const char*> v[] = {{A, "Area A"},
                                              {Iy, "Iy"},
                                              {Iz, "Iz"},
                                              {J, "Torsion Constant J"},
                                              {shearFactorY, "Shear Factor Y"},
                                              {shearFactorZ, "Shear Factor Z"}};
  for (const auto& [value, key] : v) checkPositive(value, what, key);
  const double size = std::sqrt(orientation[0] * orientation[0] + orientation[1] * orientation[1] +
                                orientation[2] * orientation[2]);
  CMS_INPUT_CHECK(!(std::isfinite(size) && size > 0.0),
                  what << ": Orientation (" << orientation[0] << ", " << orientation[1] << ", "
                       << orientation[2] << ") must be nonzero and finite");
}

ElementMatrix stationaryRotatingDamping(const ElementMatrix& Dr, const Vec3& axis, int nodeDofs) {
  const int n = Dr.n;
  CMS_INPUT_CHECK((nodeDofs != 3 && nodeDofs != 6) || n % nodeDofs != 0,
                  "stationaryRotatingDamping: " << n << " DOFs are not whole nodes of " << nodeDofs);
  // A = [a x] on each triple: (a x v)_i = sum_j A_ij v_j.
  const double A3[3][3] = {{0.0, -axis[2], axis[1]}, {axis[2], 0.0, -axis[0]}, {-axis[1], axis[0], 0.0}};
  auto A = [&](int i, int j) { return i / 3 == j / 3 ? A3[i % 3][j % 3] : 0.0; };
  // The upper triangle, mirrored: exactly skew whatever D_r's rounding.
  ElementMatrix N(n);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      // (D_r A)_ij and (A D_r)_ij: A is block diagonal in triples.
      double DA = 0.0, AD = 0.0;
      const int bj = 3 * (j / 3), bi = 3 * (i / 3);
      for (int k = bj; k < bj + 3; ++k) DA += Dr(i, k) * A(k, j);
      for (int k = bi; k < bi + 3; ++k) AD += A(i, k) * Dr(k, j);
      N(i, j) = -0.5 * (DA + AD);
      N(j, i) = -N(i, j);
    }
  return N;
}

}  // namespace cms::fem
