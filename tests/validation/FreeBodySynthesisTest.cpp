// A free-floating body spinning at Omega about a principal axis (doc/theory.md
// §7 and §11.6), as the central substructure C of a structure:
//  - a stiff Hex8 box, truth model (every DOF) with centrifugal stress
//    stiffening;
//  - the same box reduced to its six rigid-body coordinates only
//    (Admissible basis with no vectors): the rigid body.
// Closed forms (linearised Euler equations seen in the spinning frame):
//   nutation  omega_n = Omega sqrt((I3 - I1)(I3 - I2) / (I1 I2))  (major and minor axis)
//   divergence rate   Omega sqrt((I3 - I1)(I2 - I3) / (I1 I2))    (intermediate axis)
// plus, seen from the spinning frame, three inertially fixed rigid motions at
// exactly Omega (the two transverse translations and the tilt of the spin
// axis: kinematic artefacts, flagged as such) and zero frequencies (axial
// translation, rotation about the axis).
// Dual spin: the same body carrying a momentum wheel (R) with axial momentum
// h = Ia w on the spin axis: omega_n^2 = ((I3 - I1) Omega + h)((I3 - I2) Omega + h) / (I1 I2)
// with I1, I2, I3 the whole body's (wheel included).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include <Teuchos_DefaultComm.hpp>

#include "HubBoomStructure.hpp"
#include "StructureModels.hpp"
#include "cms/core/Error.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

using namespace cms;
using namespace cms::synthesis;

namespace {

const double a = 1.0, b = 0.6, c = 0.3, rho = 7800.0, Omega = 10.0;
const double mass = rho * a * b * c;
const double Ix = mass * (b * b + c * c) / 12, Iy = mass * (a * a + c * c) / 12, Iz = mass * (a * a + b * b) / 12;

StructureDescription freeBox(const fem::Vec3& axis, const std::string& basis, double E = 2e11) {
  auto model = std::make_shared<fem::FiniteElementModel>(fixtures::solidModel(fixtures::boxMesh(a, b, c, 2),
                                                                              {E, 0.3, rho}));
  SubstructureSpec C;
  C.name = "box";
  C.kind = SubstructureKind::Central;
  C.model = model;
  C.spin = SpinRate{axis, {0, 0, 0}, Omega};
  C.reduction.set("Basis", basis);
  C.reduction.set("Vectors", 0);
  StructureDescription d;
  d.substructures.push_back(C);
  d.freeReference = "reference";
  return d;
}

StructureModes solveAll(const SynthesizedStructure& s) {
  Teuchos::ParameterList p;
  p.set("Number of Modes", static_cast<int>(std::min<long long>(s.size(), 12)));
  return s.solve(s.speeds().empty() ? std::vector<double>{} : std::vector<double>{Omega}, p);
}

/// I1, I2 are the transverse moments, I3 the spin-axis moment.
struct Axes {
  fem::Vec3 axis;
  double I1, I2, I3;
};

}  // namespace

class FreeBody : public ::testing::TestWithParam<int> {};

TEST_P(FreeBody, NutationOrDivergenceMatchesEuler) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const Axes cases[3] = {{{0, 0, 1}, Ix, Iy, Iz},   // major axis
                         {{1, 0, 0}, Iy, Iz, Ix},   // minor axis: K < 0 in the tilts
                         {{0, 1, 0}, Ix, Iz, Iy}};  // intermediate: divergent
  const Axes& ax = cases[GetParam()];
  const double prod = (ax.I3 - ax.I1) * (ax.I3 - ax.I2) / (ax.I1 * ax.I2);
  for (const std::string basis : {"Admissible", "Full"}) {
    SCOPED_TRACE(basis);
    const auto structure = AssembledStructure::assemble(freeBox(ax.axis, basis), comm);
    const auto s = SynthesizedStructure::synthesize(structure);
    if (basis == "Admissible") EXPECT_EQ(s.size(), 6);
    const auto modes = solveAll(s);
    const auto character = s.characterise(modes);
    if (std::getenv("CMS_VERBOSE"))
      for (std::size_t m = 0; m < modes.result.modes.size(); ++m)
        std::cout << basis << " mode " << m << " omega " << modes.result.modes[m].omega << " growth "
                  << modes.result.modes[m].growthRate << " " << toString(modes.result.modes[m].stability)
                  << " rigid share " << character[m].rigidShare << " artefact " << character[m].frameArtefact
                  << " | expected " << Omega * std::sqrt(std::abs(prod)) << " " << modes.result.solver << "\n";
    // Tolerances: the rigid body is exact to rounding of K X = 0 (1e-8);
    // the steel box's flexibility shifts the nutation by O((Omega/w_el)^2)
    // with w_el ~ 5e3 rad/s: 1e-4 covers it with a margin of 25.
    const double tol = basis == "Full" ? 1e-4 : 1e-8;
    int artefacts = 0, zeros = 0;
    bool found = false;
    for (std::size_t m = 0; m < modes.result.modes.size(); ++m) {
      const auto& mode = modes.result.modes[m];
      // Defective (Jordan) double eigenvalues: computed to sqrt(eps kappa),
      // ~1e-5 relative for the steel box (theory §11.6); the split's positive
      // growth rate is "neutral" (theory §4), never unstable.
      if (mode.omega < 2.0 * Omega &&
          (mode.stability == eigen::Stability::Stable || mode.stability == eigen::Stability::Neutral) &&
          std::abs(mode.omega - Omega) < 1e-4 * Omega) {
        ++artefacts;
        EXPECT_TRUE(character[m].frameArtefact) << "mode " << m << " at Omega not flagged";
        continue;
      }
      if (mode.stability == eigen::Stability::RigidBody) {
        ++zeros;
        continue;
      }
      if (prod > 0) {
        if (mode.stability != eigen::Stability::Stable || mode.omega > 3 * Omega) continue;
        EXPECT_NEAR(mode.omega / (Omega * std::sqrt(prod)), 1.0, tol);
        EXPECT_FALSE(character[m].frameArtefact);
        found = true;
      } else if (mode.stability == eigen::Stability::Divergence) {
        EXPECT_NEAR(mode.growthRate / (Omega * std::sqrt(-prod)), 1.0, tol);
        found = true;
      }
    }
    EXPECT_TRUE(found) << "no nutation/divergence mode among " << modes.result.modes.size();
    EXPECT_EQ(artefacts, 3) << "inertially fixed motions seen at Omega";
    EXPECT_EQ(zeros, 2) << "axial translation and rotation about the axis";
  }
}

INSTANTIATE_TEST_SUITE_P(MajorMinorIntermediate, FreeBody, ::testing::Values(0, 1, 2));

TEST(DualSpin, WheelMomentumShiftsNutation) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  // Major-axis spin; the wheel's momentum adds to I3 Omega. w is chosen so
  // the nutation (16.3 rad/s) is well apart from the frame-rate artefacts.
  const double mw = 20.0, It = 0.4, Ia = 0.7, w = 1000.0, h = Ia * w;
  auto d = freeBox({0, 0, 1}, "Admissible");
  SubstructureSpec R;
  R.name = "wheel";
  R.kind = SubstructureKind::Rigid;
  R.parent = "box";
  R.attachment.type = Attachment::Type::RigidFit;
  R.attachment.parentNodes = "reference";
  R.attachment.point = fem::Vec3{0, 0, 0};
  R.rotor = {mw, It, Ia};
  R.spin = SpinRate{{0, 0, 1}, {0, 0, 0}, w};
  d.substructures.push_back(R);
  // The wheel driven by a motor, and turning freely (its spin angle a
  // coordinate: one more zero frequency, the same nutation).
  int zeros[2] = {0, 0};
  for (const std::string basis : {"Admissible", "Full", "Admissible, free wheel"}) {
    SCOPED_TRACE(basis);
    const bool freeWheel = basis.find("free wheel") != std::string::npos;
    d.substructures[0].reduction.set("Basis", freeWheel ? std::string("Admissible") : basis);
    d.substructures[1].rotor.spinCoordinate = freeWheel;
    const auto s = SynthesizedStructure::synthesize(AssembledStructure::assemble(d, comm));
    Teuchos::ParameterList p;
    p.set("Number of Modes", static_cast<int>(std::min<long long>(s.size(), 12)));
    const auto modes = s.solve({Omega, w}, p);
    const double I1 = Ix + It, I2 = Iy + It, I3 = Iz + Ia;
    const double wn = std::sqrt(((I3 - I1) * Omega + h) * ((I3 - I2) * Omega + h) / (I1 * I2));
    const double tol = basis == "Full" ? 1e-4 : 1e-8;
    bool found = false;
    if (basis != "Full")
      for (const auto& mode : modes.result.modes) zeros[freeWheel] += mode.stability == eigen::Stability::RigidBody;
    for (const auto& mode : modes.result.modes)
      if (std::abs(mode.omega / wn - 1.0) < 1e-2) {
        EXPECT_NEAR(mode.omega / wn, 1.0, tol);
        found = true;
      }
    EXPECT_TRUE(found) << "no mode near the dual-spin nutation " << wn;
  }
  EXPECT_EQ(zeros[1], zeros[0] + 1);
}

TEST(FreeBody, SpinAboutAnAxisOffTheCentreOfMassIsRefused) {
  // No steady spin exists: the structure says so instead of linearising.
  auto d = freeBox({0, 0, 1}, "Full");
  d.substructures[0].spin->origin = {0.1, 0.0, 0.0};
  try {
    AssembledStructure::assemble(d, Teuchos::DefaultComm<int>::getComm());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("centre of mass"), std::string::npos) << e.what();
  }
  // A tilted axis through the centre of mass is not principal either.
  d = freeBox({0, 0.6, 0.8}, "Full");
  EXPECT_THROW(AssembledStructure::assemble(d, Teuchos::DefaultComm<int>::getComm()), InputError);
}

TEST(DualSpin, ElasticRotorOnASpinningBodyMatchesTheRigidWheel) {
  // Compound spin (theory §11.5): a stiff axisymmetric steel rod (A, the
  // stationary form) spinning at w about z relative to the box, which spins
  // at Omega; against the same rod as a rigid wheel (R) of its mass and
  // inertias, and the dual-spin closed form. The rod's bending frequencies
  // are ~1e4 rad/s: its flexibility shifts the nutation by ~(16/1e4)^2.
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const double r = 0.05, L = 0.2, rhoS = 7800, w = 1000.0;
  const double m = rhoS * M_PI * r * r * L, Ia = m * r * r / 2, It = m * L * L / 12 + m * r * r / 4, h = Ia * w;
  std::vector<double> nutation;
  for (bool elastic : {true, false}) {
    auto d = freeBox({0, 0, 1}, "Admissible");
    SubstructureSpec rotor;
    rotor.name = "rotor";
    rotor.parent = "box";
    rotor.attachment.type = Attachment::Type::RigidFit;
    rotor.attachment.parentNodes = "reference";
    rotor.attachment.point = fem::Vec3{0, 0, 0};
    rotor.spin = SpinRate{{0, 0, 1}, {0, 0, 0}, w, fem::SpinDefinition::Frame::Stationary};
    if (elastic) {
      fixtures::HubBoom hb;
      fem::BeamSection sec{M_PI * r * r, M_PI * std::pow(r, 4) / 4, M_PI * std::pow(r, 4) / 4, M_PI * std::pow(r, 4) / 2};
      auto model = hb.frame(fixtures::segmentMesh({0, 0, -L / 2}, {0, 0, L / 2}, 4, 100), {2e11, 0.3, rhoS}, sec, "rotor");
      model.elementSets[0].section.orientation = {1.0, 0.0, 0.0};
      rotor.kind = SubstructureKind::Rotating;
      rotor.model = std::make_shared<fem::FiniteElementModel>(model);
      rotor.attachment.childNodes = "mid";
      rotor.reduction.set("Basis", std::string("Full"));
    } else {
      rotor.kind = SubstructureKind::Rigid;
      rotor.rotor = {m, It, Ia};
    }
    d.substructures.push_back(rotor);
    const auto s = SynthesizedStructure::synthesize(AssembledStructure::assemble(d, comm));
    Teuchos::ParameterList p;
    p.set("Number of Modes", 12);
    const auto modes = s.solve({Omega, w}, p);
    const double I1 = Ix + It, I2 = Iy + It, I3 = Iz + Ia;
    const double wn = std::sqrt(((I3 - I1) * Omega + h) * ((I3 - I2) * Omega + h) / (I1 * I2));
    bool found = false;
    for (const auto& mode : modes.result.modes)
      if (std::abs(mode.omega / wn - 1.0) < 1e-2) {
        EXPECT_NEAR(mode.omega / wn, 1.0, elastic ? 1e-5 : 1e-8) << (elastic ? "elastic rotor" : "wheel");
        nutation.push_back(mode.omega);
        found = true;
      }
    EXPECT_TRUE(found) << "no mode near the dual-spin nutation " << wn;
  }
}
