// The sparse distributed solvers (Anasazi Block Krylov-Schur, Block
// Davidson, LOBPCG, PARPACK) against the dense solver on the same structure
// built independently, on every path (symmetric, general, shifted for a free
// body, targeted), and against themselves on one rank inside a 2-rank run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultComm.hpp>

#include "RotatingChain.hpp"
#include "cms/core/Error.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/SparseGyroscopicSolver.hpp"

using namespace cms;
using namespace cms::eigen;
using fixtures::ChainSpec;

namespace {
auto world() { return Teuchos::DefaultComm<int>::getComm(); }

GyroscopicResult sparseSolve(const SparseGyroscopicSystem& s, const std::string& eigensolver,
                             int nModes, double shift = 0.0, const std::string& method = "Auto") {
  Teuchos::ParameterList p;
  p.set("Eigensolver", eigensolver);
  p.set("Number of Modes", nModes);
  p.set("Shift", shift);
  p.set("Method", method);
  return SparseGyroscopicSolver(p).solve(s);
}

/// Dense reference modes ordered as the sparse solver orders its selection:
/// nearest lambda^2 = s first, then by |lambda|.
std::vector<GyroscopicMode> denseReference(const ChainSpec& spec, int nModes, double shift = 0.0) {
  auto modes = DenseGyroscopicSolver().solve(fixtures::denseChain(spec)).modes;
  std::stable_sort(modes.begin(), modes.end(), [&](const GyroscopicMode& a, const GyroscopicMode& b) {
    return std::abs(a.lambda * a.lambda - shift) < std::abs(b.lambda * b.lambda - shift);
  });
  modes.resize(nModes);
  std::stable_sort(modes.begin(), modes.end(), [](const GyroscopicMode& a, const GyroscopicMode& b) {
    return std::abs(a.lambda) < std::abs(b.lambda);
  });
  return modes;
}

// 1e-8 relative, as the issue states: the iteration stops at 1e-10 on the
// transformed problem and the Rayleigh-Ritz extraction is then accurate to
// the square of the vector error for eigenvalues. Relative to each
// eigenvalue, the small ones included: the shift-invert transform resolves
// those nearest the shift best (measured 4e-13 relative at |lambda| = 0.045).
// The residual is the normwise backward error (relative, doc/theory.md §4):
// the solver's Residual Tolerance is 1e-8.
void expectSameModes(const GyroscopicResult& r, const std::vector<GyroscopicMode>& ref,
                     double tol = 1e-8) {
  std::ostringstream got;
  for (const auto& m : r.modes) got << " " << m.lambda << " (residual " << m.residual << ")";
  ASSERT_EQ(r.status, SolveStatus::Converged) << r.solver << " / " << r.reason << "; modes:" << got.str();
  ASSERT_EQ(r.modes.size(), ref.size()) << r.solver;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    EXPECT_LT(std::abs(r.modes[k].lambda - ref[k].lambda), tol * std::abs(ref[k].lambda))
        << r.solver << " mode " << k << ": " << r.modes[k].lambda << " vs " << ref[k].lambda;
    EXPECT_EQ(r.modes[k].stability, ref[k].stability) << r.solver << " mode " << k;
    EXPECT_LT(r.modes[k].residual, 1e-9) << r.solver << " mode " << k;
  }
}
}  // namespace

TEST(SparseGyroscopic, SymmetricPathAllEigensolversMatchDense) {
  ChainSpec spec;
  spec.nodes = 200;  // n = 400
  spec.spin = 1.5;   // K stays positive definite
  const auto sys = fixtures::sparseChain(spec, world());
  const auto ref = denseReference(spec, 6);
  for (const char* es : {"Block Krylov-Schur", "ARPACK"}) {
    const GyroscopicResult r = sparseSolve(sys, es, 6);
    EXPECT_NE(r.reason.find("Meirovitch"), std::string::npos) << es << ": " << r.reason;
    expectSameModes(r, ref);
  }
  // LOBPCG and Block Davidson are selectable but unreliable on these spectra
  // (doc/benchmarks.md: LOBPCG's basis can break down, Davidson stagnates).
  // Whatever they return must be right, and a shortfall must show in the
  // status and the reason — never a silent wrong number.
  for (const char* es : {"LOBPCG", "Block Davidson"}) {
    const GyroscopicResult d = sparseSolve(sys, es, 6);
    if (d.status == SolveStatus::Converged) {
      expectSameModes(d, ref);
    } else {
      EXPECT_TRUE(d.reason.find("did not converge") != std::string::npos ||
                  d.reason.find("broke down") != std::string::npos ||
                  d.reason.find("exceed the Residual Tolerance") != std::string::npos ||
                  d.reason.find("could be extracted") != std::string::npos)
          << es << ": " << d.reason;
      for (const auto& m : d.modes) {
        double best = std::numeric_limits<double>::max();
        for (const auto& r : ref) best = std::min(best, std::abs(m.lambda - r.lambda) / std::abs(r.lambda));
        if (m.residual < 1e-9) EXPECT_LT(best, 1e-8) << es;
      }
    }
  }
}

TEST(SparseGyroscopic, GeneralPathFindsDivergenceLikeDense) {
  ChainSpec spec;
  spec.nodes = 150;
  spec.spin = 4.0;  // softening m Omega^2 = up to 32 > grounding: K indefinite, some divergence
  const auto sys = fixtures::sparseChain(spec, world());
  const auto ref = denseReference(spec, 6);
  bool refUnstable = false;
  for (const auto& m : ref) refUnstable |= m.stability == Stability::Divergence || m.stability == Stability::Flutter;
  EXPECT_TRUE(refUnstable) << "the test case should contain an instability";
  for (const char* es : {"Block Krylov-Schur", "ARPACK"}) {
    const GyroscopicResult r = sparseSolve(sys, es, 6);
    EXPECT_NE(r.reason.find("not positive definite"), std::string::npos) << es << ": " << r.reason;
    expectSameModes(r, ref);
    EXPECT_FALSE(r.isStable());
  }
}

TEST(SparseGyroscopic, PositiveShiftHandlesFreeBodyWithRigidModes) {
  ChainSpec spec;
  spec.nodes = 120;
  spec.support = ChainSpec::Support::None;  // K singular: two rigid translations
  spec.rotatingFrame = false;
  spec.spin = 3.0;
  const auto sys = fixtures::sparseChain(spec, world());
  // Unshifted, K cannot be factored: a clear status, not a wrong number.
  const GyroscopicResult bad = sparseSolve(sys, "Block Krylov-Schur", 5, 0.0, "General");
  EXPECT_EQ(bad.status, SolveStatus::NumericalIssue);
  EXPECT_NE(bad.reason.find("Shift"), std::string::npos) << bad.reason;
  const auto ref = denseReference(spec, 5, 4.0);
  int rigid = 0;
  for (const auto& m : ref) rigid += m.stability == Stability::RigidBody;
  EXPECT_GE(rigid, 1);
  for (const char* es : {"Block Krylov-Schur", "ARPACK"}) {
    const GyroscopicResult r = sparseSolve(sys, es, 5, 4.0);
    ASSERT_EQ(r.modes.size(), 5u) << es << ": " << r.solver << " / " << r.reason;
    for (std::size_t k = 0; k < ref.size(); ++k) {
      if (ref[k].stability == Stability::RigidBody) {
        EXPECT_EQ(r.modes[k].stability, Stability::RigidBody) << es << " mode " << k;
      } else {
        EXPECT_NEAR(r.modes[k].omega, ref[k].omega, 1e-8 * ref[k].omega) << es << " mode " << k;
      }
    }
  }
}

TEST(SparseGyroscopic, NegativeShiftTargetsFrequenciesNearTarget) {
  ChainSpec spec;
  spec.nodes = 200;
  spec.spin = 1.0;
  const auto sys = fixtures::sparseChain(spec, world());
  const double target = 30.0;  // rad/s, inside the spectrum
  const auto ref = denseReference(spec, 4, -target * target);
  for (const char* es : {"Block Krylov-Schur", "ARPACK"}) {
    const GyroscopicResult r = sparseSolve(sys, es, 4, -target * target);
    expectSameModes(r, ref);
    for (const auto& m : r.modes) EXPECT_GT(m.omega, 10.0) << "target missed";
  }
}

// The same problem on all ranks and on rank 0 alone gives the same frequencies.
TEST(SparseGyroscopic, SameFrequenciesOnOneRankAndAll) {
  ChainSpec spec;
  spec.nodes = 300;
  spec.spin = 2.0;
  const auto comm = world();
  const auto self = comm->split(comm->getRank() == 0 ? 0 : 1, 0);
  for (const char* es : {"Block Krylov-Schur", "ARPACK"}) {
    const GyroscopicResult all = sparseSolve(fixtures::sparseChain(spec, comm), es, 6);
    std::vector<double> w(6, 0.0);
    if (comm->getRank() == 0) {
      const GyroscopicResult one = sparseSolve(fixtures::sparseChain(spec, self), es, 6);
      for (int k = 0; k < 6; ++k) w[k] = one.modes.at(k).omega;
    }
    Teuchos::broadcast(*comm, 0, 6, w.data());
    for (int k = 0; k < 6; ++k)
      EXPECT_NEAR(all.modes[k].omega, w[k], 1e-10 * w[k]) << es << " mode " << k << " on "
                                                          << comm->getSize() << " ranks";
  }
}

// n = 2000, the top of the range where the dense path is the reference: the
// end-supported chain (string-like spectrum), K > 0, lowest 6 modes.
TEST(SparseGyroscopic, AgreeWithDenseAtTwoThousandDofs) {
  ChainSpec spec;
  spec.nodes = 1000;
  spec.support = ChainSpec::Support::Ends;
  spec.spin = spec.subcriticalSpin(0.5);
  Teuchos::ParameterList dp;
  dp.set("Number of Modes", 6);
  const auto ref = DenseGyroscopicSolver(dp).solve(fixtures::denseChain(spec)).modes;
  const auto sys = fixtures::sparseChain(spec, world());
  for (const char* es : {"Block Krylov-Schur", "ARPACK"}) expectSameModes(sparseSolve(sys, es, 6), ref);
}

// n = 1e5: Anasazi and ARPACK agree with each other.
TEST(SparseGyroscopic, AnasaziAndArpackAgreeAtHundredThousandDofs) {
  ChainSpec spec;
  spec.nodes = 50000;
  spec.spin = 1.0;
  const auto sys = fixtures::sparseChain(spec, world());
  const GyroscopicResult a = sparseSolve(sys, "Block Krylov-Schur", 4);
  const GyroscopicResult b = sparseSolve(sys, "ARPACK", 4);
  ASSERT_EQ(a.status, SolveStatus::Converged) << a.reason;
  ASSERT_EQ(b.status, SolveStatus::Converged) << b.reason;
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(a.modes[k].omega, b.modes[k].omega, 1e-8 * a.modes[k].omega);
}

// ---- Bad input -----------------------------------------------------------------

TEST(SparseGyroscopicInput, RejectsMalformedSystemsAndParameters) {
  ChainSpec spec;
  spec.nodes = 20;
  const auto sys = fixtures::sparseChain(spec, world());
  auto message = [](const SparseGyroscopicSystem& s, Teuchos::ParameterList p = {}) -> std::string {
    try {
      SparseGyroscopicSolver(p).solve(s);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  ChainSpec spinning = spec;
  spinning.spin = 1.0;  // G nonzero
  const auto sysG = fixtures::sparseChain(spinning, world());
  SparseGyroscopicSystem s = sysG;
  s.G = sysG.K;  // symmetric, not skew
  EXPECT_NE(message(s).find("G is not skew-symmetric"), std::string::npos) << message(s);
  s = sysG;
  s.K = sysG.G;
  EXPECT_NE(message(s).find("K is not symmetric"), std::string::npos) << message(s);
  // A circulatory N must be skew, and the symmetric method cannot take it.
  s = sysG;
  s.N = sysG.K;
  EXPECT_NE(message(s).find("N is not skew-symmetric"), std::string::npos) << message(s);
  s = sysG;
  s.N = sysG.G;
  {
    Teuchos::ParameterList symmetric;
    symmetric.set("Method", "Symmetric");
    EXPECT_NE(message(s, symmetric).find("D or N is given"), std::string::npos) << message(s, symmetric);
  }
  ChainSpec other = spec;
  other.nodes = 21;
  s = sys;
  s.K = fixtures::sparseChain(other, world()).K;
  EXPECT_NE(message(s).find("does not share M's row"), std::string::npos) << message(s);
  s = sys;
  s.M = Teuchos::null;
  EXPECT_NE(message(s).find("M is missing"), std::string::npos);
  Teuchos::ParameterList p;
  p.set("Number of Modes", 41);
  EXPECT_NE(message(sys, p).find("only 40 DOFs"), std::string::npos) << message(sys, p);
  Teuchos::ParameterList q;
  q.set("Eigensolver", "Lanczos");
  EXPECT_THROW(SparseGyroscopicSolver{q}, InputError);
  Teuchos::ParameterList t;  // shifted Q(mu) are nonsymmetric: no Cholesky-only solver
  t.set("Linear Solver", "Tacho");
  EXPECT_THROW(SparseGyroscopicSolver{t}, InputError);
  Teuchos::ParameterList b;
  b.set("Block Size", 1);
  EXPECT_THROW(SparseGyroscopicSolver{b}, InputError);
  for (double f : {-1e-5, std::nan("")}) {
    Teuchos::ParameterList ft;
    ft.set("Frequency Tolerance", f);
    EXPECT_THROW(SparseGyroscopicSolver{ft}, InputError) << f;
  }
  // LOBPCG needs the symmetric path; a spinning chain beyond critical has K indefinite.
  ChainSpec fast = spec;
  fast.spin = 5.0;
  Teuchos::ParameterList l;
  l.set("Eigensolver", "LOBPCG");
  l.set("Number of Modes", 3);
  const std::string lobpcg = message(fixtures::sparseChain(fast, world()), l);
  EXPECT_NE(lobpcg.find("needs the symmetric path"), std::string::npos) << lobpcg;
}
