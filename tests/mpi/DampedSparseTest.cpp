// The damped sparse path (theory §13.2): a Rayleigh-damped spinning chain
// solved by the non-Hermitian iteration on Q(mu) = mu^2 M + mu (G + D) + K
// against the dense dggev solution of the same structure built
// independently; at 1 and 2 ranks (the MPI main min-reduces the verdict).
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include <Teuchos_DefaultComm.hpp>
#include <TpetraExt_MatrixMatrix.hpp>
#include <Tpetra_CrsMatrix.hpp>

#include "RotatingChain.hpp"
#include "cms/core/Error.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/SparseGyroscopicSolver.hpp"

using namespace cms;
using namespace cms::eigen;
using fixtures::ChainSpec;

namespace {
auto world() { return Teuchos::DefaultComm<int>::getComm(); }

const double kAlpha = 0.05, kBeta = 2e-3;  // zeta_j = alpha / (2 w_j) + beta w_j / 2 for G = 0

ChainSpec dampedSpec() {
  ChainSpec spec;
  spec.nodes = 120;  // n = 240
  spec.spin = 1.5;   // K > 0: undamped, the symmetric path would run
  return spec;
}
}  // namespace

TEST(DampedSparse, RayleighDampedChainMatchesDense) {
  const ChainSpec spec = dampedSpec();
  auto dense = fixtures::denseChain(spec);
  dense.D = dense.M;
  dense.D.scale(kAlpha);
  for (int j = 0; j < dense.K.numCols(); ++j)
    for (int i = 0; i < dense.K.numRows(); ++i) dense.D(i, j) += kBeta * dense.K(i, j);
  auto ref = DenseGyroscopicSolver().solve(dense).modes;
  ASSERT_GE(ref.size(), 6u);
  ref.resize(6);  // ascending |lambda|, as the sparse set is sorted

  auto sys = fixtures::sparseChain(spec, world());
  sys.D = Tpetra::MatrixMatrix::add(kAlpha, false, *sys.M, kBeta, false, *sys.K);
  for (const char* es : {"Block Krylov-Schur", "ARPACK"}) {
    Teuchos::ParameterList p;
    p.set("Eigensolver", es);
    p.set("Number of Modes", 6);
    const GyroscopicResult r = SparseGyroscopicSolver(p).solve(sys);
    std::ostringstream got;
    for (const auto& m : r.modes) got << " " << m.lambda << " (residual " << m.residual << ")";
    ASSERT_EQ(r.status, SolveStatus::Converged) << es << ": " << r.solver << " / " << r.reason << got.str();
    EXPECT_NE(r.reason.find("damped"), std::string::npos) << r.reason;
    ASSERT_EQ(r.modes.size(), ref.size());
    for (std::size_t k = 0; k < ref.size(); ++k) {
      // 1e-8 relative: the Residual Tolerance of the sparse set (as in
      // SparseGyroscopicSolverTest); the dense reference is ~n eps.
      EXPECT_LT(std::abs(r.modes[k].lambda - ref[k].lambda), 1e-8 * std::abs(ref[k].lambda))
          << es << " mode " << k << ": " << r.modes[k].lambda << " vs " << ref[k].lambda;
      EXPECT_NEAR(r.modes[k].dampingRatio, ref[k].dampingRatio, 1e-8) << es << " mode " << k;
      EXPECT_GT(r.modes[k].dampingRatio, 0.0);
      EXPECT_EQ(r.modes[k].stability, Stability::Stable);
    }
  }
  Teuchos::ParameterList symmetric;
  symmetric.set("Method", "Symmetric");
  EXPECT_THROW(SparseGyroscopicSolver(symmetric).solve(sys), InputError);
}
