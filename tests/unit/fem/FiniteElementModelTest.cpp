// A Finite Element Model read from YAML (Teuchos' parameter-list format):
// every key reaches the model, relative mesh paths resolve against the
// scene's folder, and every malformed entry is refused with its key path.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include <Teuchos_YamlParameterListCoreHelpers.hpp>

#include "cms/core/Error.hpp"
#include "cms/fem/FiniteElementModel.hpp"

#ifndef CMS_TEST_DATA_DIR
#define CMS_TEST_DATA_DIR "tests/data"
#endif

using namespace cms;
using namespace cms::fem;

namespace {

const std::string kBlade = R"(
Finite Element Model:
  Name: blade
  Mesh: meshes/blade_tet10.geo
  Materials:
    steel: {Young's Modulus: 2.1e11, Poisson's Ratio: 0.3, Density: 7850}
  Element Sets:
    blade: {Type: Solid, Material: steel}
  Point Masses:
    tip mass: {Node Set: tip, Mass: 2}
  Springs:
    root spring: {Node Set: root, Stiffness: [0, 0, 1000, 0, 0, 0]}
  Boundary Conditions:
    clamp: {Node Set: root, Fixed: ux uy}
  Spin:
    Axis: [0, 0, 2]
    Origin: [-0.1, 0, 0]
    Frame: Rotating
    Stress Stiffening: false
)";

FiniteElementModel read(const std::string& yaml) {
  // Teuchos names the returned list after the document's single top-level key.
  auto p = Teuchos::getParametersFromYamlString(yaml);
  return FiniteElementModel::fromParameters(*p, CMS_TEST_DATA_DIR);
}

/// The YAML of kBlade with one line replaced.
std::string edit(const std::string& from, const std::string& to) {
  std::string s = kBlade;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

void expectRefused(const std::string& yaml, const std::string& needle) {
  try {
    read(yaml);
    ADD_FAILURE() << "accepted; expected an error mentioning \"" << needle << "\"";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a cms::InputError: " << e.what();
  }
}

}  // namespace

TEST(FiniteElementModelYaml, EveryKeyReachesTheModel) {
  const FiniteElementModel m = read(kBlade);
  EXPECT_EQ(m.name, "blade");
  ASSERT_TRUE(m.mesh);
  EXPECT_TRUE(m.mesh->hasGroup("blade"));
  EXPECT_DOUBLE_EQ(m.materials.at("steel").rho, 7850.0);  // an integer in YAML
  ASSERT_EQ(m.elementSets.size(), 1u);
  EXPECT_EQ(m.elementSets[0].kind, ElementSet::Kind::Solid);
  ASSERT_EQ(m.pointMasses.size(), 1u);
  EXPECT_EQ(m.pointMasses[0].nodeSet, "tip");
  ASSERT_EQ(m.springs.size(), 1u);
  EXPECT_DOUBLE_EQ(m.springs[0].stiffness[2], 1000.0);
  ASSERT_EQ(m.fixed.size(), 1u);
  EXPECT_EQ(m.fixed[0].components, (std::vector<Component>{Component::UX, Component::UY}));
  ASSERT_TRUE(m.spin.has_value());
  EXPECT_DOUBLE_EQ(m.spin->spin.axis[2], 1.0);  // normalised
  EXPECT_DOUBLE_EQ(m.spin->spin.origin[0], -0.1);
  EXPECT_FALSE(m.spin->stressStiffening);
}

TEST(FiniteElementModelYaml, FrameSetsReadTheirSection) {
  const std::string yaml = R"(
Finite Element Model:
  Mesh: meshes/beam_line.geo
  Materials:
    al: {Young's Modulus: 7e10, Poisson's Ratio: 0.33, Density: 2700}
  Element Sets:
    beam:
      Type: Frame
      Material: al
      Theory: Timoshenko
      Area: 1e-4
      Iy: 1e-9
      Iz: 2e-9
      Torsion Constant: 3e-9
      Shear Factor Y: 0.9
      Orientation: [0, 1, 0]
      Rotary Inertia: false
  Boundary Conditions:
    root: {Node Set: root}
)";
  const FiniteElementModel m = read(yaml);
  const ElementSet& s = m.elementSets.at(0);
  EXPECT_EQ(s.theory, BeamTheory::Timoshenko);
  EXPECT_DOUBLE_EQ(s.section.Iz, 2e-9);
  EXPECT_DOUBLE_EQ(s.section.shearFactorY, 0.9);
  EXPECT_DOUBLE_EQ(s.section.shearFactorZ, 5.0 / 6.0);
  EXPECT_DOUBLE_EQ(s.section.orientation[1], 1.0);
  EXPECT_FALSE(s.section.rotaryInertia);
  EXPECT_TRUE(m.fixed.at(0).all);
}

TEST(FiniteElementModelYaml, MalformedEntriesNameTheirKeyPath) {
  expectRefused(edit("  Name: blade", "  Nmae: blade"), "unknown key \"Nmae\"");
  expectRefused(edit("Type: Solid", "Type: Shell"), "Element Sets/blade/Type = \"Shell\"");
  expectRefused(edit("Density: 7850", "Density: -1"), "steel");
  expectRefused(edit("Density: 7850", "Density: heavy"), "Density: must be a number");
  expectRefused(edit("Material: steel}", "Material: titanium}"), "unknown material 'titanium'");
  expectRefused(edit("Element Sets:\n    blade:", "Element Sets:\n    blades:"), "blades");
  expectRefused(edit("Fixed: ux uy", "Fixed: ux uw"), "unknown component \"uw\"");
  expectRefused(edit("Axis: [0, 0, 2]", "Axis: [0, 0, 0]"), "Spin/Axis: must be a nonzero vector");
  expectRefused(edit("Axis: [0, 0, 2]", "Axis: [0, 2]"), "Spin/Axis: has 2 numbers, needs 3");
  expectRefused(edit("Frame: Rotating", "Frame: Inertial"), "Spin/Frame = \"Inertial\"");
  expectRefused(edit("Stiffness: [0, 0, 1000, 0, 0, 0]", "Stiffness: [0, 0, -1000, 0, 0, 0]"),
                "Stiffness: entry 3");
  expectRefused(edit("Mesh: meshes/blade_tet10.geo", "Mesh: meshes/missing.msh"), "missing.msh");
  expectRefused(edit("blade: {Type: Solid, Material: steel}", "blade: {Type: Solid, Material: steel, Area: 1}"),
                "applies to Frame element sets only");
  expectRefused(edit("    Stress Stiffening: false", "    Stress Stiffening: 3"), "must be true or false");
}

// The element of each hex shape that has a choice: the set's key ("Hex8:
// Incompatible", "Hex20: Reduced"), else the deck's element name of the
// block (C3D8I, C3D8R, C3D20R, any case), else full integration. Values are
// checked; the keys belong to Solid sets only.
TEST(FiniteElementModelYaml, SolidSetsChooseTheirHexElements) {
  const FiniteElementModel m = read(edit("blade: {Type: Solid, Material: steel}",
                                         "blade: {Type: Solid, Material: steel, Hex8: Incompatible, Hex20: Reduced}"));
  const ElementSet& s = m.elementSets.at(0);
  ASSERT_TRUE(s.hex8 && s.hex20);
  EXPECT_EQ(*s.hex8, SolidType::Hex8Incompatible);
  EXPECT_EQ(*s.hex20, SolidType::Hex20Reduced);
  mesh::CellBlock hex8, hex20, wedge, tri;
  hex8.type = mesh::CellType::Hex8, hex20.type = mesh::CellType::Hex20, wedge.type = mesh::CellType::Wedge15;
  tri.type = mesh::CellType::Tri6;
  EXPECT_EQ(solidTypeOf(s, hex8), SolidType::Hex8Incompatible);
  EXPECT_EQ(solidTypeOf(s, hex20), SolidType::Hex20Reduced);
  EXPECT_EQ(solidTypeOf(s, wedge), SolidType::Wedge15);
  ElementSet plain;
  plain.group = "blade";
  EXPECT_EQ(solidTypeOf(plain, hex8), SolidType::Hex8);
  EXPECT_EQ(solidTypeOf(plain, hex20), SolidType::Hex20);
  hex8.elementName = "c3d8i", hex20.elementName = "C3D20R";
  EXPECT_EQ(solidTypeOf(plain, hex8), SolidType::Hex8Incompatible);
  EXPECT_EQ(solidTypeOf(plain, hex20), SolidType::Hex20Reduced);
  hex8.elementName = "C3D8R";
  EXPECT_EQ(solidTypeOf(plain, hex8), SolidType::Hex8Incompatible);
  plain.hex8 = SolidType::Hex8;  // the key wins over the deck
  EXPECT_EQ(solidTypeOf(plain, hex8), SolidType::Hex8);
  EXPECT_THROW(solidTypeOf(plain, tri), InputError);

  expectRefused(edit("blade: {Type: Solid, Material: steel}", "blade: {Type: Solid, Material: steel, Hex8: Reduced}"),
                "Element Sets/blade/Hex8 = \"Reduced\" must be \"Full\" or \"Incompatible\"");
  expectRefused(edit("blade: {Type: Solid, Material: steel}", "blade: {Type: Solid, Material: steel, Hex20: Incompatible}"),
                "Element Sets/blade/Hex20 = \"Incompatible\" must be \"Full\" or \"Reduced\"");
  expectRefused(edit("blade: {Type: Solid, Material: steel}", "blade: {Type: Solid, Material: steel, Hex20: 2}"),
                "Hex20");
}

TEST(FiniteElementModelYaml, MeshParametersSetTheGeoScriptsConstants) {
  // "Mesh Parameters" reach the script's DefineConstant (ONELAB
  // "Parameters/<name>"): halving h gives a finer mesh; an unset one keeps
  // the script's default; the next read without them is back to the default
  // (no parameter leaks from one read into the next).
  const auto coarse = read(kBlade);
  const auto fine = read(edit("  Mesh: meshes/blade_tet10.geo",
                              "  Mesh: meshes/blade_tet10.geo\n  Mesh Parameters: {h: 0.01}"));
  const auto same = read(edit("  Mesh: meshes/blade_tet10.geo",
                              "  Mesh: meshes/blade_tet10.geo\n  Mesh Parameters: {h: 0.02}"));
  const auto again = read(kBlade);
  EXPECT_GT(fine.mesh->nodeCount(), 4 * coarse.mesh->nodeCount());
  EXPECT_EQ(same.mesh->nodeCount(), coarse.mesh->nodeCount());
  EXPECT_EQ(again.mesh->nodeCount(), coarse.mesh->nodeCount());
  expectRefused(edit("  Mesh: meshes/blade_tet10.geo",
                     "  Mesh: meshes/blade_tet10.geo\n  Mesh Parameters: {h: fine}"),
                "Mesh Parameters/h: must be a number");
  expectRefused(edit("  Mesh: meshes/blade_tet10.geo",
                     "  Mesh: meshes/bar_hex_small_v41_ascii.msh\n  Mesh Parameters: {h: 0.01}"),
                "apply to a .geo script only");
}

TEST(FiniteElementModelYaml, AnElementInTwoListedSetsIsRefused) {
  // A deck's element sets overlap as a matter of course (EALL beside a
  // part's own set). Listing two that share elements assembled those
  // elements twice: a bar's first frequency fell from 110.5 Hz to 80.4 Hz
  // without a word (found by a review). The model now refuses it, naming
  // an element and both sets.
  const std::string dir = ::testing::TempDir();
  const std::string deck = dir + "/cms_overlap.inp";
  std::ofstream(deck) << R"(*NODE
 1, 0., 0., 0.
 2, 1., 0., 0.
 3, 1., 1., 0.
 4, 0., 1., 0.
 5, 0., 0., 1.
 6, 1., 0., 1.
 7, 1., 1., 1.
 8, 0., 1., 1.
 9, 2., 0., 0.
 10, 2., 1., 0.
 11, 2., 0., 1.
 12, 2., 1., 1.
*ELEMENT, TYPE=C3D8, ELSET=EALL
 1, 1, 2, 3, 4, 5, 6, 7, 8
 2, 2, 9, 10, 3, 6, 11, 12, 7
*ELSET, ELSET=TIP
 2
*ELSET, ELSET=ROOTSIDE
 1
*NSET, NSET=ROOT
 1, 4, 5, 8
)";
  const std::string yaml = R"(
Finite Element Model:
  Name: bar
  Mesh: )" + deck + R"(
  Materials:
    steel: {Young's Modulus: 2.1e11, Poisson's Ratio: 0.3, Density: 7850}
  Element Sets:
    EALL: {Type: Solid, Material: steel}
    TIP: {Type: Solid, Material: steel}
  Boundary Conditions:
    clamp: {Node Set: ROOT}
)";
  expectRefused(yaml, "element 2 is in element sets 'EALL' and 'TIP'");
  // Disjoint sets are a model, as before.
  std::string disjoint = yaml;
  disjoint.replace(disjoint.find("EALL: {"), 4, "ROOTSIDE");
  EXPECT_NO_THROW(read(disjoint));
  std::remove(deck.c_str());
}

TEST(FiniteElementModelYaml, AFrameElementFarShorterThanItsNeighbourIsRefused) {
  // Two nodes of a B31 deck 1e-4 apart between 0.5 m elements: the short
  // element is 1e11 times stiffer, and a circular beam's double frequencies
  // split by 8.4e-5 with residuals of 1e-17; at gaps of 1e-5 and less the
  // clamped beam read "unrestrained" (found by a review). Refused below a
  // length ratio of 1e-3; at 2e-3 a model.
  const std::string dir = ::testing::TempDir();
  const auto deckWithGap = [&](const std::string& x3) {
    const std::string deck = dir + "/cms_short_" + x3 + ".inp";
    std::ofstream(deck) << "*NODE, NSET=ALL\n1, 0.0, 0.0, 0.0\n2, 0.5, 0.0, 0.0\n3, " << x3
                        << ", 0.0, 0.0\n4, 1.0, 0.0, 0.0\n*NSET, NSET=ROOT\n1\n"
                           "*ELEMENT, TYPE=B31, ELSET=BEAM\n1, 1, 2\n2, 2, 3\n3, 3, 4\n";
    return R"(
Finite Element Model:
  Name: short
  Mesh: )" + deck + R"(
  Materials:
    al: {Young's Modulus: 7.0e10, Poisson's Ratio: 0.3, Density: 2700}
  Element Sets:
    BEAM: {Type: Frame, Material: al, Area: 1.0e-3, Iy: 1.0e-7, Iz: 1.0e-7, Torsion Constant: 2.0e-7, Orientation: [0, 1, 0]}
  Boundary Conditions:
    root: {Node Set: ROOT}
)";
  };
  expectRefused(deckWithGap("0.5001"), "frame element 2 of ");
  expectRefused(deckWithGap("0.5001"), "merge its two nodes, or move them together and join them by a Spring");
  EXPECT_NO_THROW(read(deckWithGap("0.501")));
}
