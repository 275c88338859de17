// Admissible vectors (the seed's method and the default basis) on a
// substructure clamped by its own supports, with nothing held by an
// attachment (issue #8 item 3): the "tip" loads once landed on the clamped
// root (the farthest node from the centroid of all nodes) and were dropped,
// and the Krylov blocks spent a third of the vectors on axial stretching, so
// 4, 8, 16 vectors gave worst errors of 344, 15, 0.14 over a cantilever's
// lowest 4 frequencies. Reference: the exact lowest eigenvalues of the same
// discretisation (the Modes basis: Anasazi/LAPACK on the full substructure),
// so the errors measured are those of the reduction alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Teuchos_DefaultComm.hpp>

#include "BeamModels.hpp"
#include "cms/reduction/RitzBasis.hpp"

using namespace cms;
using namespace cms::reduction;

namespace {

auto world() { return Teuchos::DefaultComm<int>::getComm(); }

/// A steel cantilever, 1 m, 40 elements, clamped at "root" by its own
/// boundary condition (a C substructure), unequal bending stiffnesses so the
/// lowest modes are distinct.
substructure::Substructure clampedBeam() {
  fem::IsotropicMaterial steel{2e11, 0.3, 7800};
  auto sec = fixtures::beamSection(1e-3, 1e-7, 3e-7, 2e-7, {0.0, 1.0, 0.0});
  auto model = fixtures::frameModel(fixtures::lineMesh(1.0, 40), steel, sec);
  fem::FixedSet root;
  root.name = "clamped root";
  root.nodeSet = "root";
  root.all = true;
  model.fixed.push_back(root);
  return substructure::Substructure::fromFiniteElementModel(model, world());
}

Teuchos::ParameterList params(const std::string& basis, int vectors) {
  Teuchos::ParameterList p("Reduction");
  p.set("Basis", basis);
  p.set("Vectors", vectors);
  return p;
}

/// Worst relative error of the lowest `count` Rayleigh-Ritz frequencies.
double worstError(const std::vector<double>& w, const std::vector<double>& exact, int count) {
  double worst = 0.0;
  for (int r = 0; r < count; ++r) worst = std::max(worst, (w[r] - exact[r]) / exact[r]);
  return worst;
}

}  // namespace

// Worst error over the lowest 4 frequencies with 4, 8, 16 admissible vectors
// (Rayleigh-Ritz values, never below the exact ones: checked). Measured
// 8.2e-3, 8.1e-6, 1.7e-11 (before the fix 12.3, 2.4e-2, 8e-12): Krylov
// (Lanczos-like) vectors converge geometrically in the spectral gaps, so the
// error must fall at least a hundredfold from 4 to 8 vectors. Bounds: 8
// vectors within 1e-4 (twice the mode count: what an engineer would use), 16
// within 1e-8 (the round-off of a Rayleigh quotient is eps cond(K) ~ 1e-16 x
// 1e8, so 1e-8 is the tightest level safely above it).
TEST(AdmissibleVectors, ConvergeOnABeamClampedByItsOwnSupports) {
  const auto s = clampedBeam();
  SubstructureBoundary none;  // clamped by its boundary condition, nothing held
  const std::vector<double> exact = estimateFrequencies(s, buildRitzBasis(s, none, params("Modes", 6)));
  std::vector<double> err;
  for (int k : {4, 8, 16}) {
    const RitzBasis b = buildRitzBasis(s, none, params("Admissible", k));
    ASSERT_EQ(b.size(), k);
    const std::vector<double> w = estimateFrequencies(s, b);
    // Rayleigh-Ritz values bound the exact ones from above; relative 1e-10 is
    // the reference's own accuracy (its Eigensolver Tolerance).
    for (int r = 0; r < 4; ++r) EXPECT_GE(w[r], exact[r] * (1 - 1e-10)) << "k " << k << " mode " << r;
    err.push_back(worstError(w, exact, 4));
    if (world()->getRank() == 0) std::printf("Admissible %2d: worst error over 4 modes %.2e\n", k, err.back());
  }
  EXPECT_LT(err[1], 1e-4);
  EXPECT_LT(err[2], 1e-8);
  EXPECT_LT(err[1], 1e-2 * err[0]);
}

// The same cantilever, lowest 6 frequencies (flap 1, lead-lag 1, flap 2,
// lead-lag 2, flap 3, torsion 1), 16 vectors (issue 14 item 3,
// doc/benchmarks.md "Admissible vectors against Craig-Bampton per
// coordinate"). When the continuations K^-1 M x were taken first-in-first-out,
// the continuations of stiff shapes (axial stretching, entered once the queue's
// front was stiffer still) took columns in turn with the refinements of the
// soft families: the same beam on a clamped hub gave 1.4e-7 at 16 vectors (and
// a clamped plate stalled at 4.8e-3 from 12 to 16). Taking the softest
// candidate of all gives 1.7e-9 there; bound 1e-8 (the round-off level, above).
TEST(AdmissibleVectors, SoftestCandidateFirstAcrossFamilies) {
  const auto s = clampedBeam();
  SubstructureBoundary none;
  const std::vector<double> exact = estimateFrequencies(s, buildRitzBasis(s, none, params("Modes", 8)));
  const RitzBasis b = buildRitzBasis(s, none, params("Admissible", 16));
  ASSERT_EQ(b.size(), 16);
  const double err = worstError(estimateFrequencies(s, b), exact, 6);
  if (world()->getRank() == 0) std::printf("Admissible 16: worst error over 6 modes %.2e\n", err);
  EXPECT_LT(err, 1e-8);
}
