// Fixed-interface modes by Anasazi against the Sturm count (doc/theory.md
// §11.3): a cube clamped on all six faces has cubic symmetry, so frequencies
// of multiplicity three, more than the Block Krylov-Schur block of two.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include <Teuchos_DefaultComm.hpp>

#include "SolidBarModels.hpp"
#include "cms/reduction/RitzBasis.hpp"

using namespace cms;
using namespace cms::reduction;

namespace {

auto world() { return Teuchos::DefaultComm<int>::getComm(); }

/// A steel cube of side 1 m, n x n x n Hex8 elements, every surface node held.
struct ClampedCube {
  substructure::Substructure sub;
  SubstructureBoundary boundary;
};

ClampedCube clampedCube(int n) {
  fem::FiniteElementModel m;
  m.name = "cube";
  m.mesh = fixtures::barMesh(fem::SolidType::Hex8Incompatible, 1.0, 1.0, 1.0, n, n, n);
  m.materials["steel"] = fem::IsotropicMaterial{2.1e11, 0.3, 7850.0};
  m.elementSets.push_back(fixtures::elementSet(fem::SolidType::Hex8Incompatible, "steel"));
  ClampedCube c{substructure::Substructure::fromFiniteElementModel(m, world()), {}};
  const auto& t = c.sub.dofs();
  const auto onSurface = [](double v, double lo, double hi) {
    return std::abs(v - lo) < 1e-9 || std::abs(v - hi) < 1e-9;
  };
  for (std::size_t nd = 0; nd < t.nodes(); ++nd) {
    const double x = t.coordinates[3 * nd], y = t.coordinates[3 * nd + 1], z = t.coordinates[3 * nd + 2];
    if (onSurface(x, 0.0, 1.0) || onSurface(y, -0.5, 0.5) || onSurface(z, -0.5, 0.5))
      for (long long r = t.offsets[nd]; r < t.offsets[nd + 1]; ++r) c.boundary.held.push_back(r);
  }
  return c;
}

}  // namespace

TEST(FixedInterfaceModes, AnasaziKeepsEveryCopyOfATripleFrequencyBelowTheCutoff) {
  // 7 x 7 x 7 elements: 648 free DOFs, above the 400 where Anasazi takes
  // over from LAPACK. The lowest frequencies are triples (3592.6 Hz, then
  // 4077.3 Hz on 8^3): a block of two can converge past a third copy, and
  // the basis must then be refused, not short. With the cut-off between the
  // second and the third triple, the Sturm count finds 6 and the modes must
  // be those 6, to the eigensolver's tolerance against LAPACK's dense solve
  // of the same problem (asked for more than a quarter of the DOFs).
  const auto c = clampedCube(7);
  Teuchos::ParameterList dense("Reduction");
  dense.set("Basis", "Modes");
  dense.set("Vectors", 170);
  const auto db = buildRitzBasis(c.sub, c.boundary, dense);
  ASSERT_NE(db.eigensolverReport.find("LAPACK"), std::string::npos) << db.eigensolverReport;
  const auto exact = estimateFrequencies(c.sub, db);
  // The cut-off halfway between the 6th and 7th frequencies (a gap of
  // about 20%: both triples resolved far above the tolerances).
  ASSERT_NEAR(exact[2] / exact[0], 1.0, 1e-8);
  ASSERT_NEAR(exact[5] / exact[3], 1.0, 1e-8);
  ASSERT_GT(exact[6] / exact[5], 1.05);
  const double cutHz = 0.5 * (exact[5] + exact[6]) / (2 * M_PI);
  for (const char* kind : {"Modes", "Craig-Bampton"}) {
    SCOPED_TRACE(kind);
    Teuchos::ParameterList p("Reduction");
    p.set("Basis", kind);
    p.set("Cutoff Frequency", cutHz);
    const auto b = buildRitzBasis(c.sub, c.boundary, p);
    EXPECT_NE(b.eigensolverReport.find("Anasazi"), std::string::npos) << b.eigensolverReport;
    EXPECT_NE(b.eigensolverReport.find("6 of its modes below it"), std::string::npos) << b.eigensolverReport;
    ASSERT_EQ(b.size(), 6) << b.eigensolverReport;
    const auto f = estimateFrequencies(c.sub, b);
    // Rayleigh-Ritz from exact eigenvectors: relative error of the order
    // of the eigensolver tolerance (1e-10 by default) squared, far below
    // 1e-8; a missed copy would put the next triple's 20% in its place.
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(f[i] / exact[i], 1.0, 1e-8) << "mode " << i;
  }
}
