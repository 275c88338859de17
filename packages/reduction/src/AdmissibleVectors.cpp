#include "cms/reduction/AdmissibleVectors.hpp"

#include <cmath>
#include <limits>

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "HeldStiffness.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/HeldDofs.hpp"

namespace cms::reduction {

namespace {

using fem::Component;

/// The load patterns as columns of F, with a label each.
void loadPatterns(const substructure::Substructure& s, const SubstructureBoundary& b,
                  const std::vector<std::string>& patterns, Teuchos::RCP<MultiVector>& F,
                  std::vector<std::string>& labels) {
  const auto& t = s.dofs();
  const auto map = s.map();
  const auto nodeOf = t.rowNodes();
  const std::size_t nloc = map->getNodeNumElements();
  std::vector<std::vector<double>> cols;  // local values per column
  auto newColumn = [&](const std::string& label) -> std::vector<double>& {
    labels.push_back(label);
    cols.emplace_back(nloc, 0.0);
    return cols.back();
  };
  auto mass = [&](const std::vector<double>& r) {  // M r, as local values
    MultiVector x(map, 1), y(map, 1);
    auto xv = x.getDataNonConst(0);
    std::copy(r.begin(), r.end(), xv.begin());
    s.M()->apply(x, y);
    auto yv = y.getData(0);
    return std::vector<double>(yv.begin(), yv.end());
  };
  const char* axisName[3] = {"x", "y", "z"};
  for (const std::string& p : patterns) {
    if (p == "interfaces") {
      for (std::size_t c = 0; c < b.interfaceLoads.size(); ++c)
        for (std::size_t k = 0; k < b.interfaceLoads[c].size(); ++k) {
          auto& col = newColumn("static: interface " + std::to_string(c + 1) + " load " + std::to_string(k + 1));
          for (auto [g, v] : b.interfaceLoads[c][k]) {
            const auto l = map->getLocalElement(g);
            if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) col[l] += v;
          }
        }
    } else if (p == "uniform") {
      for (int d = 0; d < 3; ++d) {
        std::vector<double> r(nloc, 0.0);
        for (std::size_t l = 0; l < nloc; ++l)
          if (static_cast<int>(t.components[map->getGlobalElement(l)]) == d) r[l] = 1.0;
        newColumn(std::string("static: uniform ") + axisName[d]) = mass(r);
      }
    } else if (p == "centrifugal") {
      if (s.KT1().is_null() || !s.spin()) continue;  // not rotating: no such load
      const auto& spin = s.spin()->spin;
      MultiVector x(map, 1), y(map, 1);
      auto xv = x.getDataNonConst(0);
      for (std::size_t l = 0; l < nloc; ++l) {
        const long long g = map->getGlobalElement(l);
        const int c = static_cast<int>(t.components[g]);
        if (c < 3) xv[l] = t.coordinates[3 * nodeOf[g] + c] - spin.origin[c];
      }
      s.KT1()->apply(x, y);
      auto yv = y.getData(0);
      newColumn("static: centrifugal").assign(yv.begin(), yv.end());
    } else if (p == "tip") {
      // The node farthest from the held nodes' centroid (or from the
      // centroid of all nodes when nothing is held).
      double c[3] = {0, 0, 0};
      std::size_t count = 0;
      if (!b.held.empty()) {
        for (GlobalOrdinal g : b.held) {
          for (int d = 0; d < 3; ++d) c[d] += t.coordinates[3 * nodeOf[g] + d];
          ++count;
        }
      } else {
        for (std::size_t n = 0; n < t.nodes(); ++n)
          for (int d = 0; d < 3; ++d) c[d] += t.coordinates[3 * n + d];
        count = t.nodes();
      }
      for (double& v : c) v /= static_cast<double>(std::max<std::size_t>(count, 1));
      std::size_t far = 0;
      double best = -1.0;
      for (std::size_t n = 0; n < t.nodes(); ++n) {
        double d2 = 0;
        for (int d = 0; d < 3; ++d) d2 += std::pow(t.coordinates[3 * n + d] - c[d], 2);
        if (d2 > best) best = d2, far = n;
      }
      for (int d = 0; d < 3; ++d) {
        auto& col = newColumn("static: tip " + std::string(axisName[d]) + " at node " +
                              std::to_string(t.nodeIds[far]));
        const long long g = t.row(static_cast<std::int64_t>(far), static_cast<Component>(d));
        const auto l = g < 0 ? Teuchos::OrdinalTraits<LocalOrdinal>::invalid() : map->getLocalElement(g);
        if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) col[l] = 1.0;
      }
    } else {
      throw InputError(s.name() + ": \"Reduction\" -> \"Load Patterns\": unknown pattern \"" + p +
                       "\" (valid: interfaces, uniform, centrifugal, tip)");
    }
  }
  F = Teuchos::rcp(new MultiVector(map, std::max<std::size_t>(cols.size(), 1)));
  for (std::size_t j = 0; j < cols.size(); ++j) {
    auto v = F->getDataNonConst(j);
    std::copy(cols[j].begin(), cols[j].end(), v.begin());
  }
  if (cols.empty()) F = Teuchos::null;
}

}  // namespace

RitzBasis admissibleVectors(const substructure::Substructure& s, const SubstructureBoundary& boundary,
                            const std::vector<std::string>& patterns, int count, double tol) {
  RitzBasis basis;
  basis.kind = "Admissible";
  if (count == 0) return basis;
  Teuchos::RCP<MultiVector> F;
  std::vector<std::string> labels;
  loadPatterns(s, boundary, patterns, F, labels);
  CMS_INPUT_CHECK(F.is_null(), s.name() << ": \"Reduction\" -> \"Load Patterns\" gives no load on this "
                                        "substructure (no children, not spinning?): add \"uniform\" or \"tip\"");
  detail::HeldStiffness K(s, boundary.held);
  MultiVector X(F->getMap(), F->getNumVectors());
  K.solve(*F, X);
  appendOrthonormal(*s.M(), X, labels, tol, count, basis);
  // Load-dependent Ritz continuation: the Krylov space of K^-1 M from the
  // static block, one block of the newest columns at a time.
  int block = 1;
  std::size_t lastStart = 0;
  while (basis.size() < count) {
    const std::size_t have = static_cast<std::size_t>(basis.size());
    if (have == lastStart && block > 1) break;
    if (have == 0) break;
    Teuchos::Range1D newest(block == 1 ? 0 : lastStart, have - 1);
    auto B = basis.vectors->subView(newest);
    MultiVector MB(B->getMap(), B->getNumVectors()), Y(B->getMap(), B->getNumVectors());
    s.M()->apply(*B, MB);
    K.solve(MB, Y);
    std::vector<std::string> l(Y.getNumVectors());
    for (std::size_t j = 0; j < l.size(); ++j)
      l[j] = "Krylov " + std::to_string(block) + ": K^-1 M (" + basis.labels[newest.lbound() + j] + ")";
    lastStart = have;
    appendOrthonormal(*s.M(), Y, l, tol, count, basis);
    ++block;
    if (static_cast<std::size_t>(basis.size()) == have) {
      basis.dropped.push_back("Krylov sequence stopped growing at " + std::to_string(have) +
                              " vectors (invariant subspace)");
      break;
    }
  }
  return basis;
}

RitzBasis polynomialVectors(const substructure::Substructure& s, const SubstructureBoundary& boundary, int count,
                            double tol) {
  RitzBasis basis;
  basis.kind = "Polynomial";
  if (count == 0) return basis;
  CMS_INPUT_CHECK(boundary.held.empty(),
                  s.name() << ": \"Basis: Polynomial\" needs an attachment (or a free body's reference) to "
                              "start from; a substructure clamped by its own supports should use Admissible");
  const auto& t = s.dofs();
  const auto nodeOf = t.rowNodes();
  auto x = [&](std::int64_t n, int d) { return t.coordinates[3 * n + d]; };
  double o[3] = {0, 0, 0};
  for (GlobalOrdinal g : boundary.held)
    for (int d = 0; d < 3; ++d) o[d] += x(nodeOf[g], d) / static_cast<double>(boundary.held.size());
  double axis[3] = {0, 0, 0}, L = 0;
  for (std::size_t n = 0; n < t.nodes(); ++n) {
    double r[3], r2 = 0;
    for (int d = 0; d < 3; ++d) r[d] = x(static_cast<std::int64_t>(n), d) - o[d], r2 += r[d] * r[d];
    if (std::sqrt(r2) > L) {
      L = std::sqrt(r2);
      for (int d = 0; d < 3; ++d) axis[d] = r[d];
    }
  }
  CMS_INPUT_CHECK(!(L > 0), s.name() << ": \"Basis: Polynomial\": every node is at the attachment");
  for (double& v : axis) v /= L;
  // Two transverse directions: t1 normal to the axis and to the coordinate
  // axis least aligned with it, t2 = axis x t1.
  int least = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(axis[d]) < std::abs(axis[least])) least = d;
  double e[3] = {0, 0, 0};
  e[least] = 1;
  auto crossp = [](const double* a, const double* b, double* c) {
    c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
  };
  double t1[3], t2[3], n1[3], n2[3];
  crossp(axis, e, t1);
  const double nt = std::sqrt(t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]);
  for (double& v : t1) v /= nt;
  crossp(axis, t1, t2);
  crossp(axis, t1, n1);  // rotation of a bending along t1: slope about axis x t1
  crossp(axis, t2, n2);
  const auto map = s.map();
  const std::size_t nloc = map->getNodeNumElements();
  const int degrees = (count + 3) / 4 + 1;
  MultiVector C(map, 4 * degrees);
  std::vector<std::string> labels;
  for (int k = 1; k <= degrees; ++k) {
    labels.push_back("polynomial: bending s^" + std::to_string(k + 1) + " (1)");
    labels.push_back("polynomial: bending s^" + std::to_string(k + 1) + " (2)");
    labels.push_back("polynomial: axial s^" + std::to_string(k));
    labels.push_back("polynomial: torsion s^" + std::to_string(k));
  }
  for (std::size_t l = 0; l < nloc; ++l) {
    const auto g = map->getGlobalElement(static_cast<LocalOrdinal>(l));
    const auto n = nodeOf[g];
    const int c = static_cast<int>(t.components[g]);
    double r[3], sAxis = 0;
    for (int d = 0; d < 3; ++d) r[d] = x(n, d) - o[d], sAxis += r[d] * axis[d];
    const double sv = sAxis / L;
    double rp[3], tw[3];  // the part of r normal to the axis, and axis x rp
    for (int d = 0; d < 3; ++d) rp[d] = r[d] - sAxis * axis[d];
    crossp(axis, rp, tw);
    for (int k = 1; k <= degrees; ++k) {
      const int j = 4 * (k - 1);
      const double p = std::pow(sv, k), dp = (k + 1) * std::pow(sv, k) / L;  // s^k, d(s^(k+1))/dx
      if (c < 3) {
        C.replaceLocalValue(l, j, std::pow(sv, k + 1) * t1[c]);
        C.replaceLocalValue(l, j + 1, std::pow(sv, k + 1) * t2[c]);
        C.replaceLocalValue(l, j + 2, p * axis[c]);
        C.replaceLocalValue(l, j + 3, p * tw[c]);
      } else {
        C.replaceLocalValue(l, j, dp * n1[c - 3]);
        C.replaceLocalValue(l, j + 1, dp * n2[c - 3]);
        C.replaceLocalValue(l, j + 3, p * axis[c - 3]);
      }
    }
  }
  zeroHeldRows(C, boundary.held);
  appendOrthonormal(*s.M(), C, labels, tol, count, basis);
  return basis;
}

}  // namespace cms::reduction
