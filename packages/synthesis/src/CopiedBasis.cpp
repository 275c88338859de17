#include "CopiedBasis.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include <Teuchos_LAPACK.hpp>
#include <Teuchos_SerialDenseMatrix.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/SparseProduct.hpp"

namespace cms::synthesis::detail {

namespace {

/// V^T A V on every rank, and the bound of its rounding: the products sum
/// over the rows n, so |fl - exact| <= gamma_n |V|^T |A| |V|, whose
/// Frobenius norm is at most n eps ||A||_F ||V||_F^2 (Higham, §3.5).
struct Projection {
  Teuchos::SerialDenseMatrix<int, double> P;
  double rounding = 0.0;
};

Projection project(const CrsMatrix& A, const MultiVector& V) {
  const auto n = static_cast<int>(V.getNumVectors());
  MultiVector AV(A.getRangeMap(), n);
  multiply(A, V, AV);
  auto local = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(n), 0, V.getMap()->getComm(),
                                    Tpetra::LocallyReplicated));
  MultiVector S(local, n);
  S.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, V, AV, 0.0);
  Projection out;
  out.P.shape(n, n);
  for (int j = 0; j < n; ++j) {
    const auto col = S.getData(j);
    for (int i = 0; i < n; ++i) out.P(i, j) = col[i];
  }
  std::vector<double> norms(n);
  V.norm2(Teuchos::ArrayView<double>(norms));
  double v2 = 0;
  for (double x : norms) v2 += x * x;
  out.rounding = static_cast<double>(V.getGlobalLength()) * std::numeric_limits<double>::epsilon() *
                 A.getFrobeniusNorm() * v2;
  return out;
}

}  // namespace

std::optional<reduction::RitzBasis> turnedBasis(const substructure::Substructure& prototype,
                                                const reduction::RitzBasis& basis,
                                                const substructure::Substructure& copy, const fem::Rotation& turn,
                                                bool operatorsTurned, std::string& why) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto& dp = prototype.dofs();
  const auto& dc = copy.dofs();
  if (dp.offsets != dc.offsets || dp.components != dc.components) {
    why = "its DOFs are not the prototype's (node by node)";
    return std::nullopt;
  }
  if (basis.full) {
    why = "the prototype's basis is Full";
    return std::nullopt;
  }
  // An empty basis (Guyan on a leaf, Vectors 0, a cut-off below every
  // mode) turns into an empty basis: it was taken for Full, and each copy
  // reduced on its own with a false FINDING (found by a review).
  if (basis.vectors.is_null()) {
    reduction::RitzBasis out = basis;
    out.flexibility.reset();
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }
  const auto& Vp = *basis.vectors;
  const int ncols = static_cast<int>(Vp.getNumVectors());
  auto Vc = turnedRows(Vp, dc, copy.map(), turn);
  // The check: the copy's reduced matrices are the prototype's; for turned
  // matrices, K and M turned on a random vector (the caller's) stand for it.
  auto turnedCopy = [&] {
    reduction::RitzBasis out = basis;
    out.vectors = Vc;
    out.flexibility.reset();  // the prototype's factor, not the copy's (shared turned, §15.2)
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  };
  if (operatorsTurned) return turnedCopy();
  struct Pair {
    const char* name;
    Teuchos::RCP<const CrsMatrix> p, c;
  };
  for (const Pair& m : {Pair{"M", prototype.M(), copy.M()}, Pair{"K", prototype.K(), copy.K()},
                        Pair{"G1", prototype.G1(), copy.G1()}, Pair{"KS1 - KT1", prototype.K2(), copy.K2()}}) {
    if (m.p.is_null() != m.c.is_null()) {
      why = std::string("it has ") + (m.c.is_null() ? "no " : "") + m.name + " where the prototype has " +
            (m.p.is_null() ? "none" : "one");
      return std::nullopt;
    }
    if (m.p.is_null()) continue;
    const auto a = project(*m.p, Vp), b = project(*m.c, *Vc);
    double diff = 0, scale = 0;
    for (int j = 0; j < ncols; ++j)
      for (int i = 0; i < ncols; ++i) {
        diff += std::pow(a.P(i, j) - b.P(i, j), 2);
        scale += std::pow(a.P(i, j), 2);
      }
    diff = std::sqrt(diff);
    if (diff > a.rounding + b.rounding) {
      std::ostringstream os;
      os.precision(3);
      os << "its reduced " << m.name << " differs from the prototype's by " << diff / std::max(std::sqrt(scale), 1e-300)
         << " (relative; rounding allows " << (a.rounding + b.rounding) / std::max(std::sqrt(scale), 1e-300)
         << "): the copy is not the prototype turned (a load, support or spin not symmetric about the pattern axis)";
      why = os.str();
      return std::nullopt;
    }
  }
  return turnedCopy();
}

bool operatorsAreTurned(const substructure::Substructure& prototype, const substructure::Substructure& copy,
                        const fem::Rotation& turn) {
  const auto& table = prototype.dofs();
  if (table.offsets != copy.dofs().offsets || table.components != copy.dofs().components) return false;
  MultiVector x(prototype.map(), 1);
  x.randomize();
  const auto Qx = turnedRows(x, table, copy.map(), turn);
  for (const auto& [Ap, Ac] : {std::make_pair(prototype.K(), copy.K()), std::make_pair(prototype.M(), copy.M())}) {
    MultiVector yp(prototype.map(), 1), yc(copy.map(), 1);
    Ap->apply(x, yp);
    Ac->apply(*Qx, yc);
    yc.update(-1.0, *turnedRows(yp, table, copy.map(), turn), 1.0);
    Teuchos::Array<double> diff(1), size(1);
    yc.norm2(diff());
    x.norm2(size());
    const double rounding = 4.0 * static_cast<double>(x.getGlobalLength()) * std::numeric_limits<double>::epsilon() *
                            Ap->getFrobeniusNorm() * size[0];
    if (!(diff[0] <= rounding)) return false;
  }
  return true;
}

std::vector<CyclicContent> cyclicContent(const std::vector<std::shared_ptr<AssembledStructure::Part>>& parts,
                                         const std::vector<Teuchos::RCP<MultiVector>>& u) {
  // The copies of each item, by copy index.
  std::map<std::string, std::vector<std::size_t>> groups;
  std::vector<std::string> order;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const auto& c = parts[k]->spec.copy;
    if (!c) continue;
    auto& g = groups[c->group];
    if (g.empty()) order.push_back(c->group), g.assign(static_cast<std::size_t>(c->count), parts.size());
    g[static_cast<std::size_t>(c->index)] = k;
  }
  std::vector<CyclicContent> out;
  for (const auto& name : order) {
    const auto& g = groups[name];
    const auto& proto = *parts[g[0]];
    bool comparable = proto.sub.has_value();
    for (std::size_t k : g)
      comparable = comparable && k < parts.size() && parts[k]->sub &&
                   parts[k]->sub->dofs().offsets == proto.sub->dofs().offsets &&
                   parts[k]->sub->dofs().components == proto.sub->dofs().components;
    if (!comparable) continue;
    const int N = static_cast<int>(g.size());
    // Each copy's motion in the prototype's axes (turned back).
    std::vector<Teuchos::RCP<MultiVector>> back;
    for (std::size_t k : g) {
      const auto& c = *parts[k]->spec.copy;
      const auto turn = fem::Rotation::about(c.axis, proto.spec.copy->angle - c.angle);
      back.push_back(turnedRows(*u[k], proto.sub->dofs(), proto.sub->map(), turn));
    }
    CyclicContent content;
    content.group = name;
    content.copies = N;
    content.share.assign(static_cast<std::size_t>(N / 2 + 1), 0.0);
    const auto map = proto.sub->map();
    for (int h = 0; h < N; ++h) {
      // c_h = sum_j (a_j + i b_j)(cos phi - i sin phi), phi = 2 pi j h / N.
      MultiVector C(map, 2), MC(map, 2);
      for (int j = 0; j < N; ++j) {
        const double phi = 2.0 * M_PI * j * h / N, cs = std::cos(phi), sn = std::sin(phi);
        auto a = back[j]->getVector(0), b = back[j]->getVector(1);
        C.getVectorNonConst(0)->update(cs, *a, sn, *b, 1.0);
        C.getVectorNonConst(1)->update(cs, *b, -sn, *a, 1.0);
      }
      multiply(*proto.sub->M(), C, MC);
      Teuchos::Array<double> d(2);
      C.dot(MC, d());
      content.share[static_cast<std::size_t>(std::min(h, N - h))] += (d[0] + d[1]) / N;
    }
    double total = 0;
    for (double v : content.share) total += v;
    for (double& v : content.share) v = total > 0 ? v / total : 0.0;
    content.dominant = static_cast<int>(std::max_element(content.share.begin(), content.share.end()) -
                                        content.share.begin());
    out.push_back(content);
  }
  return out;
}

std::optional<std::vector<double>> rigidMotionFit(const MultiVector& Xq, MultiVector& Y) {
  const int na = static_cast<int>(Xq.getNumVectors());
  if (na == 0 || static_cast<int>(Y.getNumVectors()) != na) return std::nullopt;
  auto small =
      Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(na), 0, Xq.getMap()->getComm(), Tpetra::LocallyReplicated));
  MultiVector G(small, na), H(small, na);
  G.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, Xq, Xq, 0.0);
  H.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, Xq, Y, 0.0);
  std::vector<double> g(static_cast<std::size_t>(na) * na), h(g.size());
  for (int j = 0; j < na; ++j) {
    const auto gj = G.getData(j), hj = H.getData(j);
    for (int i = 0; i < na; ++i) g[i + static_cast<std::size_t>(j) * na] = gj[i], h[i + static_cast<std::size_t>(j) * na] = hj[i];
  }
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  lapack.POTRF('L', na, g.data(), na, &info);
  if (info != 0) return std::nullopt;
  lapack.POTRS('L', na, na, g.data(), na, h.data(), na, &info);
  if (info != 0) return std::nullopt;
  MultiVector M6(small, na);
  for (int j = 0; j < na; ++j)
    for (int i = 0; i < na; ++i) M6.replaceLocalValue(i, j, h[i + static_cast<std::size_t>(j) * na]);
  std::vector<double> before(na), after(na);
  Y.norm2(Teuchos::ArrayView<double>(before));
  Y.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, -1.0, Xq, M6, 1.0);
  Y.norm2(Teuchos::ArrayView<double>(after));
  double b2 = 0.0, a2 = 0.0;
  for (int j = 0; j < na; ++j) b2 += before[j] * before[j], a2 += after[j] * after[j];
  if (!(std::sqrt(a2) <= 1e3 * std::numeric_limits<double>::epsilon() * std::sqrt(b2))) return std::nullopt;
  return h;
}

}  // namespace cms::synthesis::detail

namespace cms::synthesis {

std::string CyclicContent::label() const {
  if (dominant == 0) return "collective";
  if (2 * dominant == copies) return "differential";
  return "cyclic " + std::to_string(dominant);
}

}  // namespace cms::synthesis
