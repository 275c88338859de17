// The rotating blade as a 3D solid (10-node tetrahedra, blade_tet10.geo)
// against the same blade as Timoshenko frame elements, both assembled and
// solved by this framework: flapwise frequencies at rest and spinning, where
// the solid's stress stiffening comes from the full 3D stress field of the
// centrifugal prestress (theory §10) and the beam's from its axial force.
#include <gtest/gtest.h>

#include <cmath>

#include <Teuchos_DefaultComm.hpp>

#include "BeamModels.hpp"
#include "SubstructureModes.hpp"

using namespace cms;
using fem::Component;
using substructure::Substructure;

namespace {

auto world() { return Teuchos::DefaultComm<int>::getComm(); }

constexpr double L = 1.0, chord = 0.04, thick = 0.02;  // blade_tet10.geo defaults
const fem::IsotropicMaterial steel{2.1e11, 0.3, 7800.0};

fem::SpinDefinition spinAboutZ() {
  fem::SpinDefinition s;
  s.spin.axis = {0.0, 0.0, 1.0};
  return s;
}

Substructure solidBlade() {
  fem::FiniteElementModel m;
  m.name = "solid blade";
  m.mesh = std::make_shared<mesh::Mesh>(mesh::readGmsh(std::string(CMS_TEST_DATA_DIR) + "/meshes/blade_tet10.geo"));
  m.materials["steel"] = steel;
  m.elementSets.push_back({"blade", fem::ElementSet::Kind::Solid, "steel", {}, {}});
  m.fixed.push_back({"root", "root", {}, true});
  m.spin = spinAboutZ();
  return Substructure::fromFiniteElementModel(m, world());
}

Substructure beamBlade() {
  fem::BeamSection sec;
  sec.A = chord * thick;
  sec.Iy = chord * thick * thick * thick / 12.0;  // flapwise: about the chord axis
  sec.Iz = thick * chord * chord * chord / 12.0;
  sec.J = 0.229 * chord * thick * thick * thick;  // rectangle 2:1 (Roark)
  sec.orientation = {0.0, 1.0, 0.0};
  auto m = fixtures::frameModel(fixtures::lineMesh(L, 60), steel, sec, fem::BeamTheory::Timoshenko);
  m.fixed.push_back({"root", "root", {}, true});
  m.spin = spinAboutZ();
  return Substructure::fromFiniteElementModel(m, world());
}

std::vector<double> flapwise(const Substructure& s, double Omega, int count) {
  const auto r = fixtures::solveAtSpeed(s, Omega, 8);
  EXPECT_EQ(r.status, eigen::SolveStatus::Converged) << r.reason;
  std::vector<double> w;
  for (const auto& m : r.modes)
    if (fixtures::translationShare(s, m, Component::UZ) > 0.9 && static_cast<int>(w.size()) < count)
      w.push_back(m.omega);
  return w;
}

}  // namespace

// Expected solid-versus-beam difference for this slender bar (L/t = 50):
// the Timoshenko beam already carries shear and rotary inertia, so what
// remains is the solid's own 3D physics, which makes it slightly stiffer
// (the clamped root also restrains the Poisson contraction that beam theory
// leaves free; a section of chord 2t bends a little like a plate, whose
// stiffness E/(1 - nu^2) exceeds E), plus the discretisation of the coarse
// tet10 mesh (h = t, one element through the thickness), which is stiff
// from above. Measured (2026-11-22): +0.28%, +0.30% (T = 0) and +0.14%,
// +0.24% (T = 6) for flap modes 1, 2 at h = t; +0.22%, +0.23%, +0.11%,
// +0.19% at h = t/2, so about 0.2% is the 3D effect and the rest the mesh.
// The bound is 0.5% and one-sided in spirit: a solid softer than the beam by
// more than the 0.05% the beam model itself is accurate to would be a bug.
TEST(SolidBlade, FlapwiseFrequenciesAgreeWithTheBeamModel) {
  const auto solid = solidBlade();
  const auto beam = beamBlade();
  const double EI = steel.E * chord * thick * thick * thick / 12.0, rhoA = steel.rho * chord * thick;
  const double unit = std::sqrt(EI / (rhoA * L * L * L * L));  // Omega of T = 1
  for (double T : {0.0, 6.0}) {
    const auto ws = flapwise(solid, T * unit, 2), wb = flapwise(beam, T * unit, 2);
    ASSERT_EQ(ws.size(), 2u) << "T = " << T;
    ASSERT_EQ(wb.size(), 2u) << "T = " << T;
    for (int k = 0; k < 2; ++k) {
      if (world()->getRank() == 0) std::printf("T = %g flap %d: solid %.6f beam %.6f (omega-bar), difference %.3f%%\n", T, k + 1,
                  ws[k] / unit, wb[k] / unit, 100.0 * (ws[k] - wb[k]) / wb[k]);
      EXPECT_LT(ws[k], 1.005 * wb[k]) << "T = " << T << ", flap mode " << k + 1;
      EXPECT_GT(ws[k], 0.9995 * wb[k]) << "T = " << T << ", flap mode " << k + 1;
    }
  }
}
