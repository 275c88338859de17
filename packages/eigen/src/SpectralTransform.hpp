// Internal to the eigen package: the operators the iterative eigensolvers see,
// on the state x = [v; q] (v = q') distributed as each rank's v rows followed
// by its q rows (doc/theory.md, "Sparse path").
#pragma once

#include <memory>
#include <string>

#include <Tpetra_Operator.hpp>

#include "cms/core/SparseDirectSolver.hpp"
#include "cms/core/SparseInertia.hpp"
#include "cms/eigen/SparseGyroscopicSystem.hpp"
#include "cms/eigen/SturmCount.hpp"

namespace cms::eigen::detail {

/// The Sturm count of sturmCount(sys, omega) (cms/eigen/SturmCount.hpp),
/// its inertia taken by `method` (cms::inertia).
SparseSturmCount sturmCountBy(const SparseGyroscopicSystem& sys, double omega, InertiaMethod method);

using cms::stateMap;  // the 2n state map (cms/core/SparseInertia.hpp)

/// An operator from the 2n state space to itself: the map every operator
/// below shares.
class StateOperator : public Tpetra::Operator<double> {
public:
  explicit StateOperator(const Map& rowMap) : map_(stateMap(rowMap)) {}
  Teuchos::RCP<const Map> getDomainMap() const override { return map_; }
  Teuchos::RCP<const Map> getRangeMap() const override { return map_; }

protected:
  Teuchos::RCP<const Map> map_;
};

/// R = sign * (H^2 - s)^-1 with H the Hamiltonian matrix of the first-order
/// system; sign = -1 makes it positive definite in the I* inner product when
/// K > 0 and s >= 0.
class SpectralTransform : public StateOperator {
public:
  /// `solverMethod`: SparseDirectSolver method for Q(mu) (K alone when s = 0
  /// may use CHOLMOD; shifted Q(mu) are nonsymmetric and need an LU: KLU2).
  SpectralTransform(const SparseGyroscopicSystem& sys, double s, double sign,
                    const std::string& solverMethod, const std::string& kSolverMethod);

  /// Factor what the shift needs. Returns "" on success, else why not.
  std::string factor();
  /// When K was already factored by CHOLMOD (the definiteness test), reuse it.
  void adoptStiffnessFactor(std::shared_ptr<SparseDirectSolver> kFactor);

  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS,
             double alpha = 1.0, double beta = 0.0) const override;

  int numApplies() const { return applies_; }
  double factorSeconds() const;

private:
  /// Y = (H - mu)^-1 X for real mu, with Q(mu) factored in `Q`.
  void applyRealResolvent(double mu, const SparseDirectSolver& Q, const MultiVector& X,
                          MultiVector& Y) const;
  /// Y = Im((H - i w)^-1 X) / w = (H^2 + w^2)^-1 X, via the real 2n form of Q(i w).
  void applyComplexResolvent(const MultiVector& X, MultiVector& Y) const;

  SparseGyroscopicSystem sys_;
  double s_, sign_;
  std::string method_, kMethod_;
  std::shared_ptr<SparseDirectSolver> qPlus_, qMinus_, qComplex_;
  mutable int applies_ = 0;
};

/// I* = diag(M, K) on [v; q]: Meirovitch's inner product (seed eq. (21)).
class StateInnerProduct : public StateOperator {
public:
  explicit StateInnerProduct(const SparseGyroscopicSystem& sys);
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS,
             double alpha = 1.0, double beta = 0.0) const override;

private:
  SparseGyroscopicSystem sys_;
};

/// I*^-1 = diag(M^-1, K^-1), from factorisations of M and K.
class StateInverseInnerProduct : public StateOperator {
public:
  StateInverseInnerProduct(const SparseGyroscopicSystem& sys,
                           std::shared_ptr<SparseDirectSolver> mFactor,
                           std::shared_ptr<SparseDirectSolver> kFactor);
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS,
             double alpha = 1.0, double beta = 0.0) const override;

private:
  SparseGyroscopicSystem sys_;
  std::shared_ptr<SparseDirectSolver> m_, k_;
};

/// A * B as one operator (Block Davidson and LOBPCG need the symmetric
/// I* (-R) rather than the I*-self-adjoint -R).
class ProductOperator : public Tpetra::Operator<double> {
public:
  ProductOperator(Teuchos::RCP<const Operator> A, Teuchos::RCP<const Operator> B)
      : A_(A), B_(B) {}
  Teuchos::RCP<const Map> getDomainMap() const override { return B_->getDomainMap(); }
  Teuchos::RCP<const Map> getRangeMap() const override { return A_->getRangeMap(); }
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS,
             double alpha = 1.0, double beta = 0.0) const override;

private:
  Teuchos::RCP<const Operator> A_, B_;
};

/// X itself when its columns have constant stride, else a packed copy
/// (eigensolvers pass strided column views; the half views need packing).
Teuchos::RCP<const MultiVector> packed(const MultiVector& X);

/// Views of the v and q halves of a state multivector.
Teuchos::RCP<MultiVector> upperHalf(MultiVector& X, const Teuchos::RCP<const Map>& rowMap);
Teuchos::RCP<MultiVector> lowerHalf(MultiVector& X, const Teuchos::RCP<const Map>& rowMap);
Teuchos::RCP<const MultiVector> upperHalf(const MultiVector& X,
                                          const Teuchos::RCP<const Map>& rowMap);
Teuchos::RCP<const MultiVector> lowerHalf(const MultiVector& X,
                                          const Teuchos::RCP<const Map>& rowMap);

}  // namespace cms::eigen::detail
