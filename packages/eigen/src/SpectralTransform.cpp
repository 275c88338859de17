#include "SpectralTransform.hpp"

#include <cmath>

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>
#include <TpetraExt_MatrixMatrix.hpp>

#include "cms/core/MatrixSum.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/SparseInertia.hpp"  // realEmbedding, stateMap

namespace cms::eigen::detail {

Teuchos::RCP<const MultiVector> packed(const MultiVector& X) {
  return X.isConstantStride() ? Teuchos::rcpFromRef(X)
                              : Teuchos::RCP<const MultiVector>(new MultiVector(X, Teuchos::Copy));
}

Teuchos::RCP<MultiVector> upperHalf(MultiVector& X, const Teuchos::RCP<const Map>& rowMap) {
  return X.offsetViewNonConst(rowMap, 0);
}
Teuchos::RCP<MultiVector> lowerHalf(MultiVector& X, const Teuchos::RCP<const Map>& rowMap) {
  return X.offsetViewNonConst(rowMap, rowMap->getNodeNumElements());
}
Teuchos::RCP<const MultiVector> upperHalf(const MultiVector& X,
                                          const Teuchos::RCP<const Map>& rowMap) {
  return X.offsetView(rowMap, 0);
}
Teuchos::RCP<const MultiVector> lowerHalf(const MultiVector& X,
                                          const Teuchos::RCP<const Map>& rowMap) {
  return X.offsetView(rowMap, rowMap->getNodeNumElements());
}

namespace {
/// alpha A + beta B + gamma C on the pattern union (all on one row map).
Teuchos::RCP<CrsMatrix> combine(double a, const CrsMatrix& A, double b, const CrsMatrix& B,
                                double c, const CrsMatrix& C) {
  auto AB = Tpetra::MatrixMatrix::add(a, false, A, b, false, B);
  return Tpetra::MatrixMatrix::add(1.0, false, *AB, c, false, C);
}
}  // namespace

SpectralTransform::SpectralTransform(const SparseGyroscopicSystem& sys, double s, double sign,
                                     const std::string& method, const std::string& kMethod)
    : StateOperator(*sys.M->getRowMap()), sys_(sys), s_(s), sign_(sign), method_(method),
      kMethod_(kMethod) {}

void SpectralTransform::adoptStiffnessFactor(std::shared_ptr<SparseDirectSolver> k) {
  qPlus_ = qMinus_ = std::move(k);
}

std::string SpectralTransform::factor() {
  auto run = [](std::shared_ptr<SparseDirectSolver>& f, Teuchos::RCP<const CrsMatrix> A,
                const std::string& method, const std::string& what) -> std::string {
    f = std::make_shared<SparseDirectSolver>(A, method);
    const auto out = f->factor();
    if (out == SparseDirectSolver::Outcome::Factored) return "";
    return what + " could not be factored (" + f->failure() + ")";
  };
  if (s_ == 0.0) {
    if (qPlus_) return "";
    const std::string why = run(qPlus_, sys_.K, kMethod_, "K");
    qMinus_ = qPlus_;
    return why.empty() ? why
                       // (Not only singular: the LU probe refuses a cond
                       // >~ 1e10, which a beam of 600 elements reaches; "a
                       // free body?" alone misled there, and a scene has no
                       // "Shift" to set: a review.)
                       : why + ": K is singular or too ill-conditioned to invert unshifted (cond >~ 1e10: a free "
                               "body or mechanism, or a mesh far finer than the model's precision needs; the sparse "
                               "solver's parameter list takes a positive \"Shift\")";
  }
  if (s_ > 0.0) {
    const double tau = std::sqrt(s_);
    std::string why = run(qPlus_, combine(1.0, *sys_.K, tau, *sys_.G, tau * tau, *sys_.M),
                          method_, "Q(tau) = K + tau G + tau^2 M");
    if (why.empty())
      why = run(qMinus_, combine(1.0, *sys_.K, -tau, *sys_.G, tau * tau, *sys_.M), method_,
                "Q(-tau) = K - tau G + tau^2 M");
    return why;
  }
  const double w = std::sqrt(-s_);
  auto A = matrixSum(1.0, *sys_.K, -w * w, *sys_.M);
  CrsMatrix B(*sys_.G, Teuchos::Copy);
  B.resumeFill();
  B.scale(w);
  B.fillComplete(sys_.G->getDomainMap(), sys_.G->getRangeMap());
  return run(qComplex_, realEmbedding(*A, B, map_), method_,
             "Q(i w) = K - w^2 M + i w G (real 2n form)");
}

double SpectralTransform::factorSeconds() const {
  double t = 0.0;
  if (qPlus_) t += qPlus_->factorSeconds();
  if (qMinus_ && qMinus_ != qPlus_) t += qMinus_->factorSeconds();
  if (qComplex_) t += qComplex_->factorSeconds();
  return t;
}

void SpectralTransform::applyRealResolvent(double mu, const SparseDirectSolver& Q,
                                           const MultiVector& X, MultiVector& Y) const {
  // (H - mu)^-1 [c; d]:  Q(mu) q = -(M (c + mu d) + G d),  v = d + mu q.
  const auto rowMap = sys_.M->getRowMap();
  const auto c = upperHalf(X, rowMap), d = lowerHalf(X, rowMap);
  auto v = upperHalf(Y, rowMap), q = lowerHalf(Y, rowMap);
  MultiVector t(*c, Teuchos::Copy), r(rowMap, X.getNumVectors());
  t.update(mu, *d, 1.0);         // c + mu d
  sys_.M->apply(t, r);           // M (c + mu d)
  sys_.G->apply(*d, r, Teuchos::NO_TRANS, -1.0, -1.0);  // -(M(c + mu d) + G d)
  Q.solve(r, *q);
  v->update(1.0, *d, mu, *q, 0.0);
}

void SpectralTransform::applyComplexResolvent(const MultiVector& X, MultiVector& Y) const {
  // z = (H - i w)^-1 [c; d]:  Q(i w) q = -(M c + G d) - i w M d,  v = d + i w q;
  // (H^2 + w^2)^-1 x = Im(z) / w = [Re q; Im q / w].
  const double w = std::sqrt(-s_);
  const auto rowMap = sys_.M->getRowMap();
  const auto c = upperHalf(X, rowMap), d = lowerHalf(X, rowMap);
  MultiVector rhs(map_, X.getNumVectors()), z(map_, X.getNumVectors());
  auto rre = upperHalf(rhs, rowMap), rim = lowerHalf(rhs, rowMap);
  sys_.M->apply(*c, *rre, Teuchos::NO_TRANS, -1.0, 0.0);
  sys_.G->apply(*d, *rre, Teuchos::NO_TRANS, -1.0, 1.0);
  sys_.M->apply(*d, *rim, Teuchos::NO_TRANS, -w, 0.0);
  qComplex_->solve(rhs, z);
  auto yv = upperHalf(Y, rowMap), yq = lowerHalf(Y, rowMap);
  yv->update(1.0, *upperHalf(z, rowMap), 0.0);
  yq->update(1.0 / w, *lowerHalf(z, rowMap), 0.0);
}

void SpectralTransform::apply(const MultiVector& Xin, MultiVector& Y, Teuchos::ETransp,
                              double alpha, double beta) const {
  ++applies_;
  const Teuchos::RCP<const MultiVector> Xc = packed(Xin);
  const MultiVector& X = *Xc;
  MultiVector out(map_, X.getNumVectors());
  if (s_ < 0.0) {
    applyComplexResolvent(X, out);
  } else {
    // (H^2 - tau^2)^-1 = (H - tau)^-1 (H + tau)^-1.
    const double tau = std::sqrt(s_);
    MultiVector mid(map_, X.getNumVectors());
    applyRealResolvent(-tau, *qMinus_, X, mid);
    applyRealResolvent(tau, *qPlus_, mid, out);
  }
  Y.update(alpha * sign_, out, beta);
}

StateInnerProduct::StateInnerProduct(const SparseGyroscopicSystem& sys)
    : StateOperator(*sys.M->getRowMap()), sys_(sys) {}

void StateInnerProduct::apply(const MultiVector& Xin, MultiVector& Y, Teuchos::ETransp,
                              double alpha, double beta) const {
  const auto rowMap = sys_.M->getRowMap();
  const Teuchos::RCP<const MultiVector> Xc = packed(Xin);
  MultiVector out(map_, Xin.getNumVectors());
  sys_.M->apply(*upperHalf(*Xc, rowMap), *upperHalf(out, rowMap));
  sys_.K->apply(*lowerHalf(*Xc, rowMap), *lowerHalf(out, rowMap));
  Y.update(alpha, out, beta);
}

StateInverseInnerProduct::StateInverseInnerProduct(const SparseGyroscopicSystem& sys,
                                                   std::shared_ptr<SparseDirectSolver> m,
                                                   std::shared_ptr<SparseDirectSolver> k)
    : StateOperator(*sys.M->getRowMap()), sys_(sys), m_(std::move(m)), k_(std::move(k)) {}

void StateInverseInnerProduct::apply(const MultiVector& Xin, MultiVector& Y, Teuchos::ETransp,
                                     double alpha, double beta) const {
  const auto rowMap = sys_.M->getRowMap();
  const Teuchos::RCP<const MultiVector> Xc = packed(Xin);
  MultiVector out(map_, Xin.getNumVectors());
  m_->solve(*upperHalf(*Xc, rowMap), *upperHalf(out, rowMap));
  k_->solve(*lowerHalf(*Xc, rowMap), *lowerHalf(out, rowMap));
  Y.update(alpha, out, beta);
}

void ProductOperator::apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp, double alpha,
                            double beta) const {
  MultiVector t(B_->getRangeMap(), X.getNumVectors());
  B_->apply(X, t);
  A_->apply(t, Y, Teuchos::NO_TRANS, alpha, beta);
}

}  // namespace cms::eigen::detail
