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

}  // namespace cms::fem
