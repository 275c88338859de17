#include "cms/reduction/FixedInterfaceModes.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <sstream>

#include <AnasaziBasicEigenproblem.hpp>
#include <AnasaziBlockKrylovSchurSolMgr.hpp>
#include <AnasaziTpetraAdapter.hpp>
#include <Teuchos_BLAS.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Operator.hpp>

#include "HeldStiffness.hpp"
#include "SymmetricEigen.hpp"
#include "cms/core/SparseProduct.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/PeakMemory.hpp"
#include "cms/core/HashRandom.hpp"
#include "cms/core/HeldDofs.hpp"

namespace cms::reduction {

namespace {

/// Y = K_held^-1 M_held X: self-adjoint in the M_held inner product, its
/// eigenvalues 1 / omega^2 (and 0 on the held DOFs).
///
/// With constraints H u = 0 (F = H^T, Y = K^-1 F, S = F^T Y = H K^-1 H^T):
/// Z M X with Z = K^-1 - Y S^-1 Y^T, the inverse of K on {H u = 0} (from
/// K u = lambda M u + H^T mu, H u = 0); still M-self-adjoint, its range
/// inside H u = 0, so every eigenvector of a nonzero eigenvalue satisfies
/// the constraints.
class ShiftInvert : public Tpetra::Operator<double> {
public:
  ShiftInvert(const detail::HeldStiffness& K, Teuchos::RCP<const CrsMatrix> M, const ModeConstraints& c = {})
      : K_(K), M_(std::move(M)), Y_(c.Y) {
    if (Y_.is_null()) return;
    const int m = static_cast<int>(Y_->getNumVectors());
    small_ = Teuchos::rcp(new Map(m, 0, M_->getRangeMap()->getComm(), Tpetra::LocallyReplicated));
    MultiVector S(small_, m);
    S.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, *c.F, *Y_, 0.0);
    Sinv_.assign(static_cast<std::size_t>(m) * m, 0.0);
    for (int j = 0; j < m; ++j) {
      const auto col = S.getData(j);
      for (int i = 0; i < m; ++i) Sinv_[i + static_cast<std::size_t>(j) * m] = col[i];
    }
    // S is symmetric positive definite (H has full rank: RigidFit refuses
    // degenerate fits): its Cholesky factor, for S^-1 below.
    Teuchos::LAPACK<int, double> lapack;
    int info = 0;
    lapack.POTRF('L', m, Sinv_.data(), m, &info);
    TEUCHOS_TEST_FOR_EXCEPTION(info != 0, std::runtime_error,
                               "fixed-interface modes: the constraints' Schur complement H K^-1 H^T is not "
                               "positive definite (dependent constraints), LAPACK info "
                                   << info);
  }
  Teuchos::RCP<const Map> getDomainMap() const override { return M_->getDomainMap(); }
  Teuchos::RCP<const Map> getRangeMap() const override { return M_->getRangeMap(); }
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp = Teuchos::NO_TRANS, double alpha = 1.0,
             double beta = 0.0) const override {
    MultiVector MX(X.getMap(), X.getNumVectors()), Z(X.getMap(), X.getNumVectors());
    multiply(*M_, X, MX);
    K_.solve(MX, Z);
    if (!Y_.is_null()) {
      const int m = static_cast<int>(Y_->getNumVectors()), nv = static_cast<int>(X.getNumVectors());
      MultiVector R(small_, nv);
      R.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, *Y_, MX, 0.0);  // Y^T M X = H K^-1 M X
      std::vector<double> r(static_cast<std::size_t>(m) * nv);
      for (int j = 0; j < nv; ++j) {
        const auto col = R.getData(j);
        for (int i = 0; i < m; ++i) r[i + static_cast<std::size_t>(j) * m] = col[i];
      }
      Teuchos::LAPACK<int, double> lapack;
      int info = 0;
      lapack.POTRS('L', m, nv, Sinv_.data(), m, r.data(), m, &info);
      for (int j = 0; j < nv; ++j) {
        auto col = R.getDataNonConst(j);
        for (int i = 0; i < m; ++i) col[i] = r[i + static_cast<std::size_t>(j) * m];
      }
      Z.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, -1.0, *Y_, R, 1.0);
    }
    Y.update(alpha, Z, beta);
  }

private:
  const detail::HeldStiffness& K_;
  Teuchos::RCP<const CrsMatrix> M_;
  Teuchos::RCP<const MultiVector> Y_;
  Teuchos::RCP<const Map> small_;
  std::vector<double> Sinv_;  ///< Cholesky factor of S = F^T Y
};

/// The number of modes to keep so that a repeated eigenvalue (a symmetric
/// section, an axisymmetric rotor) is never cut: with `count` of the
/// ascending eigenvalues lambda kept, add those equal to the last to 1e-8.
/// Otherwise the basis would hold an arbitrary vector of the eigenspace,
/// which changes with rounding (and the rank count).
int completeCluster(const std::vector<double>& lambda, int count, int available) {
  while (count > 0 && count < available &&
         std::abs(lambda[count] - lambda[count - 1]) <= 1e-8 * std::abs(lambda[count - 1]))
    ++count;
  return count;
}

/// Dense path for small substructures: gather K and M on the free rows to
/// every rank and call LAPACK dsygv; returns the lowest `count` vectors.
Teuchos::RCP<MultiVector> denseModes(const substructure::Substructure& s, const std::vector<GlobalOrdinal>& held,
                                     int& count, std::vector<double>& omega, const ModeConstraints& constraints) {
  const auto map = s.map();
  const long long n = s.dofs().rows();
  const std::set<GlobalOrdinal> heldSet(held.begin(), held.end());
  std::vector<GlobalOrdinal> freeRows;
  for (long long g = 0; g < n; ++g)
    if (!heldSet.count(g)) freeRows.push_back(g);
  const int nf = static_cast<int>(freeRows.size());
  MultiVector E(map, nf), KE(map, nf), ME(map, nf);
  for (int j = 0; j < nf; ++j) {
    const auto l = map->getLocalElement(freeRows[j]);
    if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) E.replaceLocalValue(l, j, 1.0);
  }
  multiply(*s.K(), E, KE);
  multiply(*s.M(), E, ME);
  auto rep = Teuchos::rcp(new Map(static_cast<GlobalOrdinal>(n), 0, map->getComm(), Tpetra::LocallyReplicated));
  Tpetra::Import<> imp(map, rep);
  MultiVector Kr(rep, nf), Mr(rep, nf);
  Kr.doImport(KE, imp, Tpetra::INSERT);
  Mr.doImport(ME, imp, Tpetra::INSERT);
  std::vector<double> A(static_cast<std::size_t>(nf) * nf), B(A.size());
  for (int j = 0; j < nf; ++j) {
    auto kc = Kr.getData(j), mc = Mr.getData(j);
    for (int i = 0; i < nf; ++i) A[i + j * nf] = kc[freeRows[i]], B[i + j * nf] = mc[freeRows[i]];
  }
  // Constraints H u = 0: the problem on the null space N of H (free rows),
  // from the full QR of H^T = F: N = the last nf - m columns of Q.
  int nr = nf;
  std::vector<double> N;
  if (!constraints.F.is_null()) {
    const int m = static_cast<int>(constraints.F->getNumVectors());
    MultiVector Fr(rep, m);
    Fr.doImport(*constraints.F, imp, Tpetra::INSERT);
    std::vector<double> Q(static_cast<std::size_t>(nf) * nf, 0.0), tau(std::max(1, m));
    for (int j = 0; j < m; ++j) {
      auto c = Fr.getData(j);
      for (int i = 0; i < nf; ++i) Q[i + static_cast<std::size_t>(j) * nf] = c[freeRows[i]];
    }
    Teuchos::LAPACK<int, double> lapack;
    std::vector<double> work(static_cast<std::size_t>(std::max(1, nf)) * 64);
    int info = 0;
    lapack.GEQRF(nf, m, Q.data(), nf, tau.data(), work.data(), static_cast<int>(work.size()), &info);
    lapack.ORGQR(nf, nf, m, Q.data(), nf, tau.data(), work.data(), static_cast<int>(work.size()), &info);
    nr = nf - m;
    N.assign(Q.begin() + static_cast<long>(m) * nf, Q.end());
    // A <- N^T A N, B <- N^T B N.
    Teuchos::BLAS<int, double> blas;
    std::vector<double> T(static_cast<std::size_t>(nf) * nr), Ar(static_cast<std::size_t>(nr) * nr),
        Br(Ar.size());
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nf, nr, nf, 1.0, A.data(), nf, N.data(), nf, 0.0, T.data(), nf);
    blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, nr, nr, nf, 1.0, N.data(), nf, T.data(), nf, 0.0, Ar.data(), nr);
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nf, nr, nf, 1.0, B.data(), nf, N.data(), nf, 0.0, T.data(), nf);
    blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, nr, nr, nf, 1.0, N.data(), nf, T.data(), nf, 0.0, Br.data(), nr);
    A.swap(Ar);
    B.swap(Br);
  }
  std::vector<double> w;
  const int info = detail::symmetricEigen(A, B, nr, true, w);
  if (info != 0)
    throw NumericalError(s.name() + ": fixed-interface eigenproblem failed (LAPACK dsygv info " +
                         std::to_string(info) + "; K or M not definite on the free DOFs)");
  count = completeCluster(w, count, nr);
  if (!N.empty()) {  // back to the free rows: x = N y
    std::vector<double> X(static_cast<std::size_t>(nf) * count);
    Teuchos::BLAS<int, double> blas;
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nf, count, nr, 1.0, N.data(), nf, A.data(), nr, 0.0, X.data(),
              nf);
    A.swap(X);
  }
  auto V = Teuchos::rcp(new MultiVector(map, count));
  omega.resize(count);
  for (int j = 0; j < count; ++j) {
    omega[j] = std::sqrt(std::max(0.0, w[j]));
    for (int i = 0; i < nf; ++i) {
      const auto l = map->getLocalElement(freeRows[i]);
      if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) V->replaceLocalValue(l, j, A[i + j * nf]);
    }
  }
  return V;
}

}  // namespace

RitzBasis fixedInterfaceModes(const substructure::Substructure& s, const std::vector<GlobalOrdinal>& held,
                              int count, double eigTol, double depTol, const ModeConstraints& constraints,
                              const SturmCut& cut) {
  const std::set<GlobalOrdinal> heldSet(held.begin(), held.end());
  const detail::HeldStiffness K(s, std::vector<GlobalOrdinal>(heldSet.begin(), heldSet.end()));
  return detail::fixedInterfaceModes(s, K, count, eigTol, depTol, constraints, cut);
}

RitzBasis detail::fixedInterfaceModes(const substructure::Substructure& s, const detail::HeldStiffness& K, int count,
                                      double eigTol, double depTol, const ModeConstraints& constraints,
                                      const SturmCut& cut) {
  const int requested = count;
  RitzBasis basis;
  basis.kind = "Modes";
  if (count == 0) return basis;
  const std::vector<GlobalOrdinal>& heldRows = K.held();
  const int m = constraints.F.is_null() ? 0 : static_cast<int>(constraints.F->getNumVectors());
  const long long nfree = s.dofs().rows() - static_cast<long long>(heldRows.size()) - m;
  // There are no more modes than DOFs off the held rows and the interface
  // constraints: asking more is an input error (never a silent cap, which
  // once read past the eigenvectors), like Vectors above the free DOFs.
  CMS_INPUT_CHECK(count > nfree, "Scene/Substructures/" << s.name() << "/Reduction/Vectors = " << count
                                     << " but substructure \"" << s.name() << "\" has only " << nfree
                                     << " DOFs free of its attachment and interfaces (its fixed-interface modes: "
                                     << "at most " << nfree << ")");
  Teuchos::RCP<MultiVector> V;
  std::vector<double> omega;
  std::ostringstream report;
  // The Krylov space below (dim vectors, Krylov-Schur keeping one block
  // more) must lie strictly inside the nfree free DOFs: where it does not,
  // the dense solve (a cut-off at 1e12 Hz on 3012 free DOFs ended as
  // "internal error", Anasazi refusing its "Num Blocks"; found by a review),
  // refused where dense's matrices (about four of nfree^2) would not fit in
  // the memory available either.
  const long long nevAsked = std::min<long long>(count + 4, nfree - 1);
  const long long dimAsked =
      std::max<long long>(2LL * count + 20, std::min<long long>(5LL * nevAsked, 2LL * nevAsked + 100));
  const bool krylovFits = dimAsked + 4 < nfree;
  CMS_INPUT_CHECK(!krylovFits && 4.0 * 8.0 * static_cast<double>(nfree) * static_cast<double>(nfree) >
                                     availableMemoryBytes(),
                  "Scene/Substructures/" << s.name() << "/Reduction: " << count << " of the " << nfree
                                         << " fixed-interface modes of \"" << s.name()
                                         << "\" asked: too many for a Krylov space and too large a dense problem; "
                                            "ask fewer (a lower \"Cutoff Frequency\" or \"Vectors\"), or use "
                                            "Basis: Full");
  if (nfree <= 400 || (count > nfree / 4 && nfree <= 3000) || !krylovFits) {
    V = denseModes(s, heldRows, count, omega, constraints);
    report << "LAPACK dsygv on " << nfree << " free DOFs";
  } else {
    const Teuchos::RCP<const CrsMatrix> Mh =  // nothing held: M itself, no copy
        heldRows.empty() ? s.M() : Teuchos::RCP<const CrsMatrix>(holdDofs(*s.M(), heldRows, 0.0));
    auto op = Teuchos::rcp(new ShiftInvert(K, Mh, constraints));
    const int bs = 2;
    // A few more than asked, to see whether the last one is repeated.
    const int nev = static_cast<int>(nevAsked);
    // The Krylov space: five times the wanted count (within 100 vectors of
    // twice it; never less than the 2 count + 20 it was), its Ritz values
    // checked every 5 block steps. With 2 count + 20 the rotor hub's 16
    // modes (clustered pairs of a hexagonal part) took 88-92 block steps,
    // four restarts; with 5 nev, 35 steps and none, 4.2-5.3 s -> 1.8-2.3 s
    // on 35,000 DOFs (doc/benchmarks.md, fifth session of 2026-11-29, "The
    // fixed-interface modes' Krylov space"). The check every 5 steps stops
    // a small part once converged, not when its larger space is full.
    const long long dim = dimAsked;
    const auto solve = [&](int seed, long long space) {
      auto X0 = Teuchos::rcp(new MultiVector(s.map(), bs));
      for (std::size_t l = 0; l < s.map()->getNodeNumElements(); ++l)
        for (int j = 0; j < bs; ++j)
          X0->replaceLocalValue(l, j,
                                hashSigned(static_cast<std::uint64_t>(s.map()->getGlobalElement(l)), seed + j));
      zeroHeldRows(*X0, heldRows);
      using Problem = Anasazi::BasicEigenproblem<double, MultiVector, Operator>;
      auto problem = Teuchos::rcp(new Problem(op, Mh, X0));
      problem->setHermitian(true);
      problem->setNEV(nev);
      TEUCHOS_TEST_FOR_EXCEPTION(!problem->setProblem(), std::logic_error, "Anasazi rejected the problem set-up");
      Teuchos::ParameterList pl;
      pl.set("Which", std::string("LM"));
      pl.set("Block Size", bs);
      // Krylov-Schur keeps Num Blocks + 1 blocks: strictly inside nfree (the
      // sparse gyroscopic solver's 2N exactly broke down; a review).
      pl.set("Num Blocks", static_cast<int>(std::min<long long>((space + bs - 1) / bs, (nfree - 1) / bs - 1)));
      pl.set("Step Size", 5);
      pl.set("Maximum Restarts", 300);
      pl.set("Convergence Tolerance", eigTol);
      pl.set("Verbosity", static_cast<int>(Anasazi::Errors));
      Anasazi::BlockKrylovSchurSolMgr<double, MultiVector, Operator> mgr(problem, pl);
      const auto ret = mgr.solve();
      report.str("");
      report << "Anasazi Block Krylov-Schur (K^-1 M, block " << bs << "): " << problem->getSolution().numVecs
             << " of " << nev << " converged in " << mgr.getNumIters()
             << " block iterations";  // Anasazi counts block steps, not restarts
      if (ret != Anasazi::Converged || problem->getSolution().numVecs < nev)
        throw NumericalError(s.name() + ": fixed-interface modes did not converge (" + report.str() + ")");
      return problem->getSolution();
    };
    // With a cut-off the Sturm count says how many values lie below it. A
    // Krylov method can converge past one copy of a frequency repeated more
    // often than its block (a review: the values were never checked), so
    // a shortfall is solved once more from another start in twice the
    // space, then an error (as the Partitioned basis's ARPACK parts are).
    const auto belowCut = [&](const Anasazi::Eigensolution<double, MultiVector>& sol) {
      // Values of K^-1 M: 1 / omega^2 above 1 / omega_cut^2. One converged
      // to the relative tolerance and within 10 times it of the cut counts
      // as below: the count's side of it is then not resolved, and it is no
      // miss (never a false alarm).
      return static_cast<int>(std::count_if(sol.Evals.begin(), sol.Evals.begin() + sol.numVecs,
                                            [&](const Anasazi::Value<double>& v) {
                                              return v.realpart * cut.omega2 > 1.0 - 10.0 * eigTol;
                                            }));
    };
    auto sol = solve(17, dim);
    if (cut.atLeast >= 0 && belowCut(sol) < cut.atLeast) {
      sol = solve(41, 2 * dim);
      const int found = belowCut(sol);
      if (found < cut.atLeast)
        throw NumericalError(s.name() + ": Anasazi found " + std::to_string(found) + " fixed-interface modes below "
                             "the cut-off where the Sturm count has at least " + std::to_string(cut.atLeast) +
                             ", twice (" + report.str() + "): a repeated frequency's copy missed");
      report << " (second start: the first found fewer modes below the cut-off than the Sturm count)";
    }
    // Lowest frequencies first: largest 1 / omega^2.
    std::vector<int> order(sol.numVecs);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return sol.Evals[a].realpart > sol.Evals[b].realpart; });
    std::vector<double> lambda(sol.numVecs);
    for (int j = 0; j < sol.numVecs; ++j) lambda[j] = 1.0 / std::max(sol.Evals[order[j]].realpart, 1e-300);
    count = completeCluster(lambda, count, sol.numVecs);
    V = Teuchos::rcp(new MultiVector(s.map(), count));
    for (int j = 0; j < count; ++j) {
      V->getVectorNonConst(j)->assign(*sol.Evecs->getVector(order[j]));
      omega.push_back(1.0 / std::sqrt(std::max(sol.Evals[order[j]].realpart, 1e-300)));
    }
  }
  if (count > requested)
    report << "; " << requested << " modes asked, " << count << " kept so as not to split a repeated eigenvalue";
  std::vector<std::string> labels(count);
  for (int j = 0; j < count; ++j) {
    std::ostringstream os;
    os << "mode " << (j + 1) << " (" << omega[j] / (2 * M_PI) << " Hz)";
    labels[j] = os.str();
  }
  appendOrthonormal(*s.M(), *V, labels, depTol, count, basis);
  basis.eigensolverReport = report.str();
  return basis;
}

}  // namespace cms::reduction
