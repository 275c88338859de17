// The dense gyroscopic solver: agreement with an independent nonsymmetric
// solution, residuals, normalisation, repeated frequencies, fallbacks, and
// clear errors on bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "RandomSystems.hpp"
#include "cms/core/Error.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"

using namespace cms;
using namespace cms::eigen;

namespace {
GyroscopicResult solveWith(const GyroscopicSystem& s, const std::string& method, int nModes = -1,
                           const std::string& reduction = "Skew Tridiagonal") {
  Teuchos::ParameterList p;
  p.set("Method", method);
  p.set("Number of Modes", nModes);
  p.set("Reduction", reduction);
  return DenseGyroscopicSolver(p).solve(s);
}
}  // namespace

const double kEps = std::numeric_limits<double>::epsilon();

// Meirovitch's symmetric form and the general pencil both reproduce the
// eigenvalues of the companion matrix (dgeev, independent code). Tolerance
// 1e-10 relative: these systems have cond(M), cond(K) <= ~10 and ||G|| ~ 1, so
// every eigenvalue is computed to ~1e-14; 1e-10 leaves room for n = 200.

TEST(DenseGyroscopic, MeirovitchAndGeneralMatchCompanionEigenvalues) {
  std::mt19937 rng(12345);
  for (int n : {5, 8, 13, 30, 64, 200}) {
    const GyroscopicSystem s = fixtures::randomGyroscopic(n, rng);
    const std::vector<double> ref = fixtures::companionFrequencies(s);
    ASSERT_EQ(static_cast<int>(ref.size()), n);
    const GyroscopicResult sym = solveWith(s, "Meirovitch");
    const GyroscopicResult gen = solveWith(s, "General");
    ASSERT_EQ(static_cast<int>(sym.modes.size()), n);
    ASSERT_EQ(static_cast<int>(gen.modes.size()), n);
    for (int k = 0; k < n; ++k) {
      EXPECT_NEAR(sym.modes[k].omega, ref[k], 1e-10 * ref[k]) << "n=" << n << " k=" << k;
      EXPECT_NEAR(gen.modes[k].omega, ref[k], 1e-10 * ref[k]) << "n=" << n << " k=" << k;
      EXPECT_EQ(sym.modes[k].stability, Stability::Stable);
      EXPECT_EQ(gen.modes[k].stability, Stability::Stable);
      EXPECT_LT(std::abs(gen.modes[k].growthRate), 1e-9 * ref[k]);
    }
    // maxResidual is the largest normwise backward error (relative to
    // ||K|| + |lambda| ||G|| + |lambda|^2 ||M||, doc/theory.md §4): a
    // backward-stable solve gives a small multiple of n eps; 100 n eps
    // leaves two decades for the constant.
    EXPECT_LT(sym.maxResidual(), 100 * n * kEps) << "n=" << n;
    EXPECT_LT(gen.maxResidual(), 100 * n * kEps) << "n=" << n;
  }
}

// The lowest modes alone (the sweep's and every reduced solve's request):
// the values come from all singular values of the skew tridiagonal form's
// n x n bidiagonal, or of A's general bidiagonal form (dqds), the vectors by
// inverse iteration for just those values (doc/theory.md §2); both reductions.
// Two decoupled identical copies of a random system beside a third make
// every frequency of the copies exactly double and the bidiagonal split
// between the blocks. Against the companion eigenvalues (dgeev, independent
// code): both solves are backward stable, so each frequency is within
// ~n eps s kappa of the exact one, s the frequency scale (§4) and kappa its
// condition, <= ~10 here (cond(M), cond(K) <= ~10, ||G|| ~ 1): the bound
// 1e3 n eps s leaves a decade over kappa for the constants (measured: 0.13
// n eps s at most, AVX-512 and Nehalem kernels). The two members of each repeated frequency are
// independent modes; backward errors 100 n eps.
TEST(DenseGyroscopic, TheLowestModesAloneMatchTheCompanionEigenvalues) {
  std::mt19937 rng(2026);
  const int h = 30, n = 3 * h;
  const GyroscopicSystem a = fixtures::randomGyroscopic(h, rng), b = fixtures::randomGyroscopic(h, rng);
  GyroscopicSystem s{DenseMatrix(n, n), DenseMatrix(n, n), DenseMatrix(n, n)};
  for (int blk = 0; blk < 3; ++blk) {
    const GyroscopicSystem& part = blk < 2 ? a : b;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < h; ++i) {
        s.M(blk * h + i, blk * h + j) = part.M(i, j);
        s.G(blk * h + i, blk * h + j) = part.G(i, j);
        s.K(blk * h + i, blk * h + j) = part.K(i, j);
      }
  }
  const std::vector<double> ref = fixtures::companionFrequencies(s);
  const double tol = 1e3 * n * kEps * frequencyScale(s.M.normFrobenius(), s.G.normFrobenius(), s.K.normFrobenius());
  for (const std::string reduction : {"Skew Tridiagonal", "Bidiagonal"}) {
    for (int nModes : {1, 7, 20, 45}) {
      const GyroscopicResult r = solveWith(s, "Meirovitch", nModes, reduction);
      ASSERT_EQ(static_cast<int>(r.modes.size()), nModes);
      EXPECT_EQ(r.status, SolveStatus::Converged) << r.reason;
      EXPECT_NE(r.reason.find(reduction == "Bidiagonal" ? "bidiagonal form" : "skew tridiagonal form"),
                std::string::npos) << r.reason;
      for (int k = 0; k < nModes; ++k)
        EXPECT_NEAR(r.modes[k].omega, ref[k], tol) << reduction << ", nModes " << nModes << " k=" << k;
      for (int k = 0; k + 1 < nModes; ++k) {
        if (std::abs(r.modes[k].omega - r.modes[k + 1].omega) > tol) continue;  // not a repeated pair
        std::complex<double> ip = 0;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) ip += std::conj(r.modes[k].q[i]) * s.M(i, j) * r.modes[k + 1].q[j];
        EXPECT_LT(std::abs(ip), 0.99) << "repeated modes " << k << " and " << k + 1 << " coincide";
      }
      EXPECT_LT(r.maxResidual(), 100 * n * kEps) << "nModes " << nModes;
    }
  }
}

TEST(DenseGyroscopic, AutoPicksMeirovitchForPositiveDefiniteK) {
  std::mt19937 rng(7);
  const GyroscopicResult r = solveWith(fixtures::randomGyroscopic(10, rng), "Auto");
  EXPECT_NE(r.solver.find("Meirovitch"), std::string::npos) << r.solver;
  EXPECT_EQ(r.status, SolveStatus::Converged);
}

// Modes are mass-normalised (q^H M q = 1), so the kinetic energy is omega^2/2,
// and the energy balance of seed eq. (19) holds: omega^2 - omega q^H(iG)q - q^H K q = 0.
TEST(DenseGyroscopic, ModesAreMassNormalisedAndBalanceEnergy) {
  std::mt19937 rng(99);
  const GyroscopicSystem s = fixtures::randomGyroscopic(12, rng, 3.0);
  for (const char* method : {"Meirovitch", "General"}) {
    const GyroscopicResult r = solveWith(s, method);
    for (const auto& m : r.modes) {
      std::complex<double> qMq = 0, qGq = 0;
      for (int i = 0; i < s.size(); ++i)
        for (int j = 0; j < s.size(); ++j) {
          qMq += std::conj(m.q[i]) * s.M(i, j) * m.q[j];
          qGq += std::conj(m.q[i]) * s.G(i, j) * m.q[j];
        }
      // q^H M q against the normalisation 1 (dimensionless): a sum of n^2
      // products of O(1) entries, 1e-12 ~ 30 n^2 eps.
      EXPECT_NEAR(qMq.real(), 1.0, 1e-12) << method;
      EXPECT_NEAR(m.kineticEnergy, 0.5 * m.omega * m.omega, 1e-12 * m.omega * m.omega);
      // -omega^2 + i omega (q^H G q) + q^H K q = 0 with q^H G q = i g: -w^2 - w g + qKq = 0.
      const double g = std::imag(qGq);
      EXPECT_NEAR(-m.omega * m.omega - m.omega * g + 2.0 * m.strainEnergy, 0.0,
                  1e-10 * m.omega * m.omega)
          << method;
    }
  }
}

// A symmetric rotor: two identical bending planes and no gyroscopic coupling
// give every frequency twice. Both modes of each double root must come back,
// independent (not the same mode twice), with small residuals.
TEST(DenseGyroscopic, RepeatedFrequenciesOfSymmetricRotorAreSeparated) {
  std::mt19937 rng(3);
  const int h = 6, n = 2 * h;
  const DenseMatrix Mh = fixtures::randomSpd(h, 0.5, rng), Kh = fixtures::randomSpd(h, 1.0, rng);
  GyroscopicSystem s{DenseMatrix(n, n), DenseMatrix(n, n), DenseMatrix(n, n)};
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < h; ++i) {
      s.M(i, j) = s.M(h + i, h + j) = Mh(i, j);
      s.K(i, j) = s.K(h + i, h + j) = Kh(i, j);
    }
  const GyroscopicResult r = solveWith(s, "Meirovitch");
  ASSERT_EQ(static_cast<int>(r.modes.size()), n);
  for (int k = 0; k < n; k += 2) {
    EXPECT_NEAR(r.modes[k].omega, r.modes[k + 1].omega, 1e-12 * r.modes[k].omega);
    // Independence: |<q1, q2>_M| < 1 for unit M-norm modes (1 would mean the same mode).
    std::complex<double> ip = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) ip += std::conj(r.modes[k].q[i]) * s.M(i, j) * r.modes[k + 1].q[j];
    EXPECT_LT(std::abs(ip), 0.99) << "modes " << k << " and " << k + 1 << " coincide";
  }
  // Normwise backward error (relative): a small multiple of n eps for a
  // backward-stable solve; 100 n eps leaves two decades for the constant.
  EXPECT_LT(r.maxResidual(), 100 * static_cast<double>(s.size()) * kEps);
}

// K indefinite: the symmetric form is invalid; Auto must say so and fall back.
TEST(DenseGyroscopic, IndefiniteStiffnessFallsBackToGeneralAndSaysWhy) {
  std::mt19937 rng(5);
  GyroscopicSystem s = fixtures::randomGyroscopic(8, rng);
  s.K(0, 0) = -50.0;
  const GyroscopicResult r = solveWith(s, "Auto");
  EXPECT_NE(r.solver.find("general"), std::string::npos) << r.solver;
  EXPECT_NE(r.reason.find("not positive definite"), std::string::npos) << r.reason;
  const std::vector<std::complex<double>> ref = fixtures::companionEigenvalues(s);
  // Each returned lambda is an eigenvalue of the companion matrix: relative
  // to |lambda|, and for the small ones to the pencil's frequency scale
  // sqrt(||K|| / ||M||) (dggev's errors are relative to the pencil's norm).
  const double scale = std::sqrt(frobeniusNorm(s.K) / frobeniusNorm(s.M));
  for (const auto& m : r.modes) {
    double best = std::numeric_limits<double>::max();
    for (auto l : ref) best = std::min(best, std::abs(l - m.lambda));
    EXPECT_LT(best, 1e-9 * std::max(scale, std::abs(m.lambda)));
  }
  // Normwise backward error (relative): a small multiple of n eps for a
  // backward-stable solve; 100 n eps leaves two decades for the constant.
  EXPECT_LT(r.maxResidual(), 100 * static_cast<double>(s.size()) * kEps);
  // A strongly negative K_00 with weak gyroscopic coupling diverges.
  EXPECT_FALSE(r.isStable());
}

TEST(DenseGyroscopic, ForcedMeirovitchWithIndefiniteKIsAnError) {
  std::mt19937 rng(5);
  GyroscopicSystem s = fixtures::randomGyroscopic(4, rng);
  s.K(1, 1) = -10.0;
  EXPECT_THROW(solveWith(s, "Meirovitch"), InputError);
}

// A free body (K = 0 on three translations) has rigid-body modes; they are
// classified, and the elastic modes are still right.
TEST(DenseGyroscopic, FreeBodyRigidModesAreClassified) {
  std::mt19937 rng(11);
  const int n = 6;
  GyroscopicSystem s = fixtures::randomGyroscopic(n, rng, 0.0);
  // K = B^T diag(0,0,0,k..) B: three zero-energy directions.
  DenseMatrix B = fixtures::randomMatrix(n, n, rng), D(n, n), DB, K;
  for (int i = 3; i < n; ++i) D(i, i) = 1.0 + i;
  gemm(false, false, 1.0, D, B, 0.0, DB);
  gemm(true, false, 1.0, B, DB, 0.0, K);
  s.K = K;
  const GyroscopicResult r = solveWith(s, "Auto");
  int rigid = 0;
  for (const auto& m : r.modes) rigid += m.stability == Stability::RigidBody;
  EXPECT_EQ(rigid, 3);
  EXPECT_TRUE(r.isStable());
  const std::vector<double> ref = fixtures::companionFrequencies(s);
  std::vector<double> elastic;
  for (const auto& m : r.modes)
    if (m.stability == Stability::Stable) elastic.push_back(m.omega);
  ASSERT_EQ(elastic.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(elastic[k], ref[ref.size() - 3 + k], 1e-9 * elastic[k]);
}

// Stiffness/mass ratios of 1e6 and more across DOFs: still right.
TEST(DenseGyroscopic, WideSpreadOfScalesStaysAccurate) {
  std::mt19937 rng(21);
  const int n = 10;
  GyroscopicSystem s = fixtures::randomGyroscopic(n, rng);
  for (int i = 0; i < n / 2; ++i) {  // scale half the DOFs: K by 1e6, M by 1e-3
    for (int j = 0; j < n; ++j) {
      s.K(i, j) *= 1e3, s.K(j, i) *= 1e3;
      s.M(i, j) *= 3e-2, s.M(j, i) *= 3e-2;
      s.G(i, j) *= 1e-1, s.G(j, i) *= 1e-1;
    }
  }
  const std::vector<double> ref = fixtures::companionFrequencies(s);
  for (const char* method : {"Meirovitch", "General"}) {
    const GyroscopicResult r = solveWith(s, method);
    // The spread of frequencies is ~1e4; the lowest carry relative errors up to
    // eps * omega_max / omega_min ~ 1e-12; 1e-9 is the bound we promise.
    for (int k = 0; k < n; ++k) EXPECT_NEAR(r.modes[k].omega, ref[k], 1e-9 * ref[k]) << method;
  }
}

TEST(DenseGyroscopic, NumberOfModesReturnsTheLowest) {
  std::mt19937 rng(8);
  const GyroscopicSystem s = fixtures::randomGyroscopic(20, rng);
  const std::vector<double> ref = fixtures::companionFrequencies(s);
  for (const char* method : {"Meirovitch", "General"}) {
    const GyroscopicResult r = solveWith(s, method, 4);
    ASSERT_EQ(r.modes.size(), 4u);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(r.modes[k].omega, ref[k], 1e-10 * ref[k]);
  }
}

// ---- Bad input: a clear error, never a crash or a number --------------------

namespace {
std::string errorOf(const GyroscopicSystem& s, Teuchos::ParameterList p = {}) {
  try {
    DenseGyroscopicSolver(p).solve(s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(DenseGyroscopicInput, RejectsMalformedSystems) {
  std::mt19937 rng(1);
  const GyroscopicSystem good = fixtures::randomGyroscopic(4, rng);

  GyroscopicSystem s = good;
  s.K.shape(3, 4);
  EXPECT_NE(errorOf(s).find("K is 3x4, not square"), std::string::npos) << errorOf(s);

  s = good;
  s.G.shape(5, 5);
  EXPECT_NE(errorOf(s).find("G is 5x5 but M is 4x4"), std::string::npos) << errorOf(s);

  s = good;
  s.M(0, 0) = -1.0;
  EXPECT_NE(errorOf(s).find("M is not positive definite"), std::string::npos) << errorOf(s);

  s = good;
  s.G(0, 1) += 1.0;
  EXPECT_NE(errorOf(s).find("G is not skew-symmetric"), std::string::npos) << errorOf(s);

  s = good;
  s.K(1, 2) += 1.0;
  EXPECT_NE(errorOf(s).find("K is not symmetric"), std::string::npos) << errorOf(s);

  s = good;
  s.K(2, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(errorOf(s).find("K(2,2) = nan is not finite"), std::string::npos) << errorOf(s);

  s = good;
  s.M(3, 1) = s.M(1, 3) = std::numeric_limits<double>::infinity();
  EXPECT_NE(errorOf(s).find("is not finite"), std::string::npos) << errorOf(s);

  EXPECT_NE(errorOf(GyroscopicSystem{}).find("empty"), std::string::npos);

  Teuchos::ParameterList p;
  p.set("Number of Modes", 5);
  EXPECT_NE(errorOf(good, p).find("only 4 DOFs"), std::string::npos) << errorOf(good, p);
}

TEST(DenseGyroscopicInput, RejectsUnknownParametersAndBadValues) {
  Teuchos::ParameterList p;
  p.set("Numbr of Modes", 3);
  EXPECT_THROW(DenseGyroscopicSolver{p}, InputError);
  Teuchos::ParameterList q;
  q.set("Method", "Lanczos");
  EXPECT_THROW(DenseGyroscopicSolver{q}, InputError);
  Teuchos::ParameterList r;
  r.set("Number of Modes", 2.5);
  EXPECT_THROW(DenseGyroscopicSolver{r}, InputError);
}

// The general path in the coordinates congruent to M = I (q = L^-T p,
// M = L L^T) is what the solver falls back to when dggev returns an
// infinite eigenvalue for a positive definite M: seen only with OpenBLAS's
// Nehalem kernels (a hub with 1e6 tip masses on 2 ranks), so without this
// request the fallback would be tested on no other CPU. On undamped and
// damped systems with cond(M) ~ 1e3 both coordinates give the same
// eigenvalues and shapes: the congruence adds a backward error of ~eps
// cond(M) to dggev's n eps, so eigenvalues agree to 100 n eps cond(M)
// relative to the frequency scale (these Hamiltonian and lightly damped
// spectra are well conditioned), and every mapped-back mode has a backward
// error in the given coordinates below 100 n eps cond(M). The same holds
// for Hessenberg QR (dgeev) in those coordinates: the last resort when QZ
// fails in both, which no CPU here reaches unrequested.
TEST(DenseGyroscopic, MassCongruentCoordinatesGiveTheSameModes) {
  std::mt19937 rng(2718);
  for (int n : {6, 17, 40})
    for (bool damped : {false, true}) {
      GyroscopicSystem s{fixtures::randomSpd(n, 0.004, rng), fixtures::randomSkew(n, 1.0, rng),
                         fixtures::randomSpd(n, 1.0, rng)};
      if (damped) {
        s.D = fixtures::randomSpd(n, 0.5, rng);
        s.D.scale(0.05);  // Teuchos::SerialDenseMatrix::scale
      }
      // cond(M) from its eigenvalues.
      DenseMatrix Mc(s.M);
      std::vector<double> ev(n), work(3 * n);
      int info = 0;
      Teuchos::LAPACK<int, double>().SYEV('N', 'L', n, Mc.values(), n, ev.data(), work.data(), 3 * n, &info);
      ASSERT_EQ(info, 0);
      const double condM = ev.back() / ev.front();
      ASSERT_GT(condM, 100.0) << "M must be far from the identity";
      Teuchos::ParameterList given, congruent, qr;
      given.set("Method", "General");
      congruent.set("Method", "General");
      congruent.set("General Coordinates", "Mass Congruent");
      qr.set("Method", "General");
      qr.set("General Eigensolver", "Hessenberg QR");
      const GyroscopicResult a = DenseGyroscopicSolver(given).solve(s);
      const std::string where = "n=" + std::to_string(n) + (damped ? " damped" : "");
      EXPECT_EQ(a.solver.find("congruent"), std::string::npos) << a.solver;
      const double scale = frequencyScale(s.M.normFrobenius(), s.G.normFrobenius() + s.D.normFrobenius(),
                                          s.K.normFrobenius());
      const double tol = 100 * n * kEps * condM;
      for (const auto* p : {&congruent, &qr}) {
        const GyroscopicResult b = DenseGyroscopicSolver(*p).solve(s);
        EXPECT_NE(b.solver.find("congruent to M = I"), std::string::npos) << b.solver;
        EXPECT_NE(b.solver.find(p == &qr ? "dgeev" : "dggev"), std::string::npos) << b.solver;
        ASSERT_EQ(a.modes.size(), b.modes.size()) << where << ", " << b.solver;
        for (std::size_t k = 0; k < a.modes.size(); ++k) {
          EXPECT_LT(std::abs(a.modes[k].lambda - b.modes[k].lambda), tol * scale)
              << where << " mode " << k << ", " << b.solver;
          EXPECT_EQ(a.modes[k].stability, b.modes[k].stability) << where << " mode " << k << ", " << b.solver;
        }
        EXPECT_LT(b.maxResidual(), tol) << where << ", " << b.solver;
      }
    }
}
