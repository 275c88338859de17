#include "cms/reduction/AdmissibleVectors.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "HeldStiffness.hpp"
#include "LoadPatterns.hpp"
#include "cms/reduction/StaticCorrection.hpp"
#include "cms/core/SparseProduct.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/HeldDofs.hpp"
#include "cms/fem/Vec3.hpp"

namespace cms::reduction {

namespace {

using fem::Component;

/// Where the substructure is supported: the centroid of the nodes of its
/// attachment's held DOFs; or else of the nodes that boundary conditions fix
/// (those with no free component, or else those with fewer free components
/// than the most any node has: a C substructure clamped by its own
/// supports); or else of all nodes (a free body).
std::array<double, 3> supportCentroid(const substructure::Substructure& s, const SubstructureBoundary& b) {
  const auto& t = s.dofs();
  std::vector<char> supported(t.nodes(), 0);
  if (!b.held.empty()) {
    const auto nodeOf = t.rowNodes();
    for (GlobalOrdinal g : b.held) supported[nodeOf[g]] = 1;
  } else {
    auto freeCount = [&](std::size_t n) { return t.offsets[n + 1] - t.offsets[n]; };
    long long most = 0;
    for (std::size_t n = 0; n < t.nodes(); ++n) most = std::max(most, freeCount(n));
    for (std::size_t n = 0; n < t.nodes(); ++n) supported[n] = freeCount(n) == 0;
    if (std::find(supported.begin(), supported.end(), 1) == supported.end())
      for (std::size_t n = 0; n < t.nodes(); ++n) supported[n] = freeCount(n) < most;
  }
  const bool any = std::find(supported.begin(), supported.end(), 1) != supported.end();
  std::array<double, 3> c{0.0, 0.0, 0.0};
  double count = 0.0;
  for (std::size_t n = 0; n < t.nodes(); ++n)
    if (!any || supported[n]) {
      for (int d = 0; d < 3; ++d) c[d] += t.coordinates[3 * n + d];
      count += 1.0;
    }
  for (double& v : c) v /= std::max(count, 1.0);
  return c;
}

}  // namespace

namespace detail {

void ownSupportLoads(const substructure::Substructure& s, const SubstructureBoundary& b,
                     Teuchos::RCP<MultiVector>& F, std::vector<std::string>& labels) {
  F = Teuchos::null;
  if (!b.supportedAttachment) return;
  const auto& t = s.dofs();
  const auto map = s.map();
  const auto nodeOf = t.rowNodes();
  const std::size_t nloc = map->getNodeNumElements();
  const auto& P = *b.supportedAttachment;
  MultiVector X(map, 6), R(map, 6);
  for (std::size_t l = 0; l < nloc; ++l) {
    const long long g = map->getGlobalElement(static_cast<LocalOrdinal>(l));
    const auto nd = nodeOf[g];
    const auto x = fem::rigidRow({t.coordinates[3 * nd] - P[0], t.coordinates[3 * nd + 1] - P[1],
                                  t.coordinates[3 * nd + 2] - P[2]},
                                 static_cast<int>(t.components[g]));
    for (int a = 0; a < 6; ++a) X.replaceLocalValue(static_cast<LocalOrdinal>(l), a, x[a]);
  }
  multiply(*s.K(), X, R);
  // K X vanishes for a free elastic body up to rounding, entry by entry
  // within kProductRounding (|K||X|)_i: a column within it everywhere off
  // the held rows is no resistance of the supports. (A bound over the
  // whole column, 1e3 eps ||K||_F ||X||, grew with the mesh: a 1000-element
  // boom's tip spring of 2e5 N/m, stiffer than the boom's own 1.9e5 N/m,
  // fell below it; a review.)
  MultiVector bound(map, 6);
  multiplyAbsolute(*s.K(), X, bound);
  const auto rounding = roundingOnly(R, bound, b.held);
  // The loads are the entries above that rounding: the rest is noise, which
  // K_h^-1 would spread over the body (at 1000 elements the turn's
  // correction then differed from the translation's by 4e-8 of it, above the
  // Dependence Tolerance, and was kept as a column of noise).
  {
    auto r = R.getLocalViewHost(Tpetra::Access::ReadWrite);
    const auto e = bound.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (std::size_t l = 0; l < nloc; ++l)
      for (int a = 0; a < 6; ++a)
        if (std::abs(r(l, a)) <= kProductRounding * e(l, a)) r(l, a) = 0.0;
  }
  for (GlobalOrdinal g : b.held) {
    const auto l = map->getLocalElement(g);
    if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid())
      for (int a = 0; a < 6; ++a) R.replaceLocalValue(l, a, 0.0);
  }
  const char* coordinate[6] = {"ux", "uy", "uz", "rx", "ry", "rz"};
  std::vector<int> resisted;
  for (int a = 0; a < 6; ++a)
    if (!rounding[a]) resisted.push_back(a);
  if (resisted.empty()) return;
  F = Teuchos::rcp(new MultiVector(map, resisted.size()));
  for (std::size_t j = 0; j < resisted.size(); ++j) {
    F->getVectorNonConst(j)->update(1.0, *R.getVector(resisted[j]), 0.0);
    labels.push_back(std::string(kOwnSupportsColumn) + coordinate[resisted[j]]);
  }
}

void loadPatterns(const substructure::Substructure& s, const SubstructureBoundary& b,
                  const std::vector<std::string>& patterns, Teuchos::RCP<MultiVector>& F,
                  std::vector<std::string>& labels) {
  const auto& t = s.dofs();
  const auto map = s.map();
  const auto nodeOf = t.rowNodes();
  const std::size_t nloc = map->getNodeNumElements();
  std::vector<std::vector<double>> cols;  // local values per column
  // The static correction of a child held by its own supports first,
  // whatever the list: without it the attachment's rigid motion is no
  // constraint mode, and the basis converges slowly (theory §11.2).
  {
    Teuchos::RCP<MultiVector> R;
    ownSupportLoads(s, b, R, labels);
    for (std::size_t j = 0; !R.is_null() && j < R->getNumVectors(); ++j) {
      auto v = R->getData(j);
      cols.emplace_back(v.begin(), v.end());
    }
  }
  auto newColumn = [&](const std::string& label) -> std::vector<double>& {
    labels.push_back(label);
    cols.emplace_back(nloc, 0.0);
    return cols.back();
  };
  auto mass = [&](const std::vector<double>& r) {  // M r, as local values
    MultiVector x(map, 1), y(map, 1);
    auto xv = x.getDataNonConst(0);
    std::copy(r.begin(), r.end(), xv.begin());
    multiply(*s.M(), x, y);
    auto yv = y.getData(0);
    return std::vector<double>(yv.begin(), yv.end());
  };
  const char* axisName[3] = {"x", "y", "z"};
  const std::array<double, 3> support = supportCentroid(s, b);
  // "interfaces" first wherever the list names it: step 1 below keeps the
  // leading interface columns whole (the attachment modes that carry the
  // coupling); listed after "uniform" they competed with the others by
  // Rayleigh quotient and could be left out (found by a review).
  std::vector<std::string> ordered;
  for (const std::string& p : patterns)
    if (p == "interfaces") ordered.push_back(p);
  for (const std::string& p : patterns)
    if (p != "interfaces") ordered.push_back(p);
  for (const std::string& p : ordered) {
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
      multiply(*s.KT1(), x, y);
      auto yv = y.getData(0);
      newColumn("static: centrifugal").assign(yv.begin(), yv.end());
    } else if (p == "rotation") {
      // Inertia loads of a unit angular acceleration about x, y, z through
      // the supports' centroid: M (e_d x (x - c)) on translations, M e_d on
      // rotations. They bring torsion and the bending that a rotation of
      // the supports excites, which uniform loads miss.
      for (int d = 0; d < 3; ++d) {
        std::vector<double> r(nloc, 0.0);
        for (std::size_t l = 0; l < nloc; ++l) {
          const long long g = map->getGlobalElement(l);
          const int c = static_cast<int>(t.components[g]);
          if (c >= 3) {
            r[l] = c - 3 == d ? 1.0 : 0.0;
          } else {
            // (e_d x x)_c for x relative to the supports
            const int a = (d + 1) % 3, b = (d + 2) % 3;
            const double xa = t.coordinates[3 * nodeOf[g] + a] - support[a];
            const double xb = t.coordinates[3 * nodeOf[g] + b] - support[b];
            r[l] = c == a ? -xb : (c == b ? xa : 0.0);
          }
        }
        newColumn(std::string("static: rotation about ") + axisName[d]) = mass(r);
      }
    } else if (p == "tip") {
      // Unit forces at the free node farthest from the supports: the
      // attachment's held DOFs, or the DOFs fixed by boundary conditions.
      std::size_t far = 0;
      double best = -1.0;
      for (std::size_t n = 0; n < t.nodes(); ++n) {
        if (t.row(static_cast<std::int64_t>(n), Component::UX) < 0) continue;  // a fixed node
        double d2 = 0;
        for (int d = 0; d < 3; ++d) d2 += std::pow(t.coordinates[3 * n + d] - support[d], 2);
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
                       "\" (valid: interfaces, uniform, rotation, centrifugal, tip)");
    }
  }
  F = Teuchos::rcp(new MultiVector(map, std::max<std::size_t>(cols.size(), 1)));
  for (std::size_t j = 0; j < cols.size(); ++j) {
    auto v = F->getDataNonConst(j);
    std::copy(cols[j].begin(), cols[j].end(), v.begin());
  }
  if (cols.empty()) F = Teuchos::null;
}

}  // namespace detail

using detail::loadPatterns;

RitzBasis admissibleVectors(const substructure::Substructure& s, const SubstructureBoundary& boundary,
                            const std::vector<std::string>& patterns, int count, double tol) {
  RitzBasis basis;
  basis.kind = "Admissible";
  if (count == 0 && !boundary.supportedAttachment) return basis;  // (the corrections come beyond "Vectors")
  Teuchos::RCP<MultiVector> F;
  std::vector<std::string> labels;
  loadPatterns(s, boundary, patterns, F, labels);
  CMS_INPUT_CHECK(F.is_null(), s.name() << ": \"Reduction\" -> \"Load Patterns\" gives no load on this "
                                        "substructure (no children, not spinning?): add \"uniform\" or \"tip\"");
  // The factorisation of K with the attachment held: kept with the basis,
  // the error estimates' flexibility is the same matrix (theory §11.8).
  auto factored = std::make_unique<detail::HeldStiffness>(s, boundary.held);
  const detail::HeldStiffness& K = *factored;
  MultiVector X(F->getMap(), F->getNumVectors()), KX(F->getMap(), F->getNumVectors());
  K.solve(*F, X, &KX);

  // 1. The static shapes under the children's interface loads come first:
  //    they carry the coupling (attachment modes). "Vectors" counts them:
  //    fewer than they are keeps the first children's and holds the later
  //    ones' attachments rigidly to the rest of the basis (a hub with three
  //    blades and Vectors 6 gave a 16.12 Hz triple as 16.12, 43.64, 43.64),
  //    which was silent (found by a review): each shape left out is listed
  //    in `dropped`, and cms modes says how many Vectors would keep them.
  //    Before them, for a child held by its own supports, the static
  //    correction of its attachment's rigid motion (theory §11.2), beyond
  //    "Vectors" as the other bases add it (counted among them it crowded
  //    out the children's shapes; a review).
  std::size_t supportColumns = 0;
  while (supportColumns < labels.size() && labels[supportColumns].rfind(kOwnSupportsColumn, 0) == 0) ++supportColumns;
  if (supportColumns > 0)  // every one that is independent: room for all
    appendOrthonormal(*s.M(), *X.subView(Teuchos::Range1D(0, supportColumns - 1)),
                      std::vector<std::string>(labels.begin(), labels.begin() + supportColumns), tol,
                      static_cast<int>(supportColumns), basis);
  const int asked = count;
  count += basis.size();  // the corrections kept, beyond "Vectors"
  std::size_t interfaceColumns = supportColumns;
  while (interfaceColumns < labels.size() && labels[interfaceColumns].rfind("static: interface", 0) == 0)
    ++interfaceColumns;
  if (interfaceColumns > supportColumns) {
    const std::size_t before = static_cast<std::size_t>(basis.size()), droppedBefore = basis.dropped.size();
    appendOrthonormal(*s.M(), *X.subView(Teuchos::Range1D(supportColumns, interfaceColumns - 1)),
                      std::vector<std::string>(labels.begin() + supportColumns, labels.begin() + interfaceColumns), tol,
                      count, basis);
    const std::size_t seen = static_cast<std::size_t>(basis.size()) - before + basis.dropped.size() - droppedBefore;
    for (std::size_t j = supportColumns + seen; j < interfaceColumns; ++j)
      basis.dropped.push_back(labels[j] + " (not kept: the basis' " + std::to_string(asked) + " vectors are fewer than the " +
                              std::to_string(interfaceColumns - supportColumns) + " " + kAttachmentShapeLeftOut + ")");
  }

  // 2. Load-dependent Ritz vectors (Wilson, Yuan & Dickens 1982), in an order
  //    that neither wastes columns nor loses a family (doc/theory.md §11.3):
  //    every column's continuation K^-1 M x becomes a candidate beside the
  //    static shapes still waiting, and the softest candidate (lowest
  //    Rayleigh quotient x^T K x / x^T M x after projection off the basis)
  //    is taken next, static shapes first on ties. The basis thus fills the
  //    spectrum from below across families: a stiff shape (axial stretching
  //    of a beam, a plate's in-plane loads) and the continuations it spawns
  //    wait until the refinements of the soft families reach their
  //    stiffness, instead of taking columns in turn with them (the earlier
  //    first-in-first-out queue of continuations did, and stalled a clamped
  //    plate at 4.8e-3 from 12 to 16 vectors, doc/benchmarks.md), and a
  //    family that no load of the Krylov sequence excites (torsion of a beam
  //    under transverse loads) still enters at its own stiffness. The
  //    sequence does not depend on `count`, so the first k columns of a
  //    longer basis are the k-column basis (nested, for the inclusion
  //    principle).
  const auto map = X.getMap();
  using VectorPtr = Teuchos::RCP<Vector>;
  std::vector<VectorPtr> kept, Mkept, Kkept;  // the columns and their products with M and K
  auto keep = [&](const VectorPtr& x, const VectorPtr& Mx, const VectorPtr& Kx) {
    kept.push_back(x), Mkept.push_back(Mx), Kkept.push_back(Kx);
  };
  for (int j = 0; j < basis.size(); ++j) {
    auto x = Teuchos::rcp(new Vector(*basis.vectors->getVector(j), Teuchos::Copy));
    auto Mx = Teuchos::rcp(new Vector(map)), Kx = Teuchos::rcp(new Vector(map));
    multiply(*s.M(), *x, *Mx), multiply(*s.K(), *x, *Kx);
    keep(x, Mx, Kx);
  }
  // A candidate carries M x and K x, updated with x as it is projected off
  // each new column (one K and one M product per column, not per candidate).
  struct Candidate {
    VectorPtr x, Mx, Kx;
    std::string label;
    double norm0 = 0.0;        ///< M-norm before any projection, in x's current scale
    double quotient = 0.0;     ///< Rayleigh quotient x^T K x / x^T M x after projection
    std::size_t projected = 0; ///< columns it is M-orthogonal to
  };
  // Kv, when the caller has it (a solve's own residual product), is taken
  // as K v: only c.x^T c.Kx is read from it, and c.x vanishes on the held
  // rows, where K_held and K differ.
  auto candidate = [&](const Vector& v, const std::string& label, const Vector* Kv = nullptr) {
    Candidate c{Teuchos::rcp(new Vector(v, Teuchos::Copy)), Teuchos::rcp(new Vector(map)),
                Kv != nullptr ? Teuchos::rcp(new Vector(*Kv, Teuchos::Copy)) : Teuchos::rcp(new Vector(map)), label};
    multiply(*s.M(), *c.x, *c.Mx);
    if (Kv == nullptr) multiply(*s.K(), *c.x, *c.Kx);
    c.norm0 = std::sqrt(std::max(0.0, c.x->dot(*c.Mx)));
    if (!(c.norm0 > 0.0)) basis.dropped.push_back(label + " (zero M-norm: the pattern has no mass on free DOFs)");
    return c;
  };
  // Projects c off the columns it has not met (classical Gram-Schmidt twice)
  // and normalises it; false, with the reason recorded, when the remainder is
  // dependent (M-norm below tol of the original).
  auto project = [&](Candidate& c) {
    for (int pass = 0; pass < 2; ++pass)
      for (std::size_t k = c.projected; k < kept.size(); ++k) {
        const double a = Mkept[k]->dot(*c.x);
        c.x->update(-a, *kept[k], 1.0), c.Mx->update(-a, *Mkept[k], 1.0), c.Kx->update(-a, *Kkept[k], 1.0);
      }
    c.projected = kept.size();
    const double norm = std::sqrt(std::max(0.0, c.x->dot(*c.Mx)));
    if (!(norm > tol * c.norm0)) {
      std::ostringstream os;
      os << c.label << " (relative norm " << norm / c.norm0 << " after projection, tolerance " << tol << ")";
      basis.dropped.push_back(os.str());
      return false;
    }
    c.x->scale(1.0 / norm), c.Mx->scale(1.0 / norm), c.Kx->scale(1.0 / norm);
    c.norm0 /= norm;
    c.quotient = c.x->dot(*c.Kx);
    return true;
  };
  std::vector<Candidate> continuations;  // in the order they were made
  auto enqueueContinuation = [&](std::size_t k, const std::string& of) {
    Vector next(map), Knext(map);
    K.solve(*Mkept[k], next, &Knext);
    Candidate c = candidate(next, "Krylov: K^-1 M (" + of + ")", &Knext);
    if (c.norm0 > 0.0) continuations.push_back(c);
  };
  for (std::size_t k = 0; k < kept.size(); ++k) enqueueContinuation(k, basis.labels[k]);  // interface shapes' first
  // The static shapes wait as they are. One that repeats those before it
  // (its remainder after projection off their span is dependent) is dropped
  // and reported at once; Q, an M-orthonormal basis of that span, serves
  // only this test.
  std::vector<Candidate> waiting;
  std::vector<std::pair<VectorPtr, VectorPtr>> Q;  // q and M q
  for (std::size_t j = interfaceColumns; j < labels.size(); ++j) {
    Candidate c = candidate(*X.getVector(j), labels[j], KX.getVector(j).get());
    if (!(c.norm0 > 0.0)) continue;
    auto r = Teuchos::rcp(new Vector(*c.x, Teuchos::Copy)), Mr = Teuchos::rcp(new Vector(*c.Mx, Teuchos::Copy));
    for (int pass = 0; pass < 2; ++pass)
      for (const auto& [q, Mq] : Q) {
        const double a = Mq->dot(*r);
        r->update(-a, *q, 1.0), Mr->update(-a, *Mq, 1.0);
      }
    const double norm = std::sqrt(std::max(0.0, r->dot(*Mr)));
    if (!(norm > tol * c.norm0)) {
      std::ostringstream os;
      os << c.label << " (relative norm " << norm / c.norm0 << " after projection on the static shapes before it, "
         << "tolerance " << tol << ")";
      basis.dropped.push_back(os.str());
      continue;
    }
    r->scale(1.0 / norm), Mr->scale(1.0 / norm);
    Q.emplace_back(r, Mr);
    if (project(c)) waiting.push_back(c);
  }
  while (static_cast<int>(kept.size()) < count) {
    auto alive = [&](std::vector<Candidate>& cs) {
      std::vector<Candidate> out;
      for (auto& c : cs)
        if (project(c)) out.push_back(c);
      cs.swap(out);
    };
    alive(waiting), alive(continuations);
    if (waiting.empty() && continuations.empty()) break;
    // Every comparison has a relative margin of 1e-8, far above rounding:
    // mirror-image substructures (two identical booms) and different rank
    // counts must make the same choices, or identical parts get different
    // bases and a symmetric structure's repeated frequencies split. Ties keep
    // the patterns' (and the continuations') order and prefer the static
    // shape.
    constexpr double margin = 1e-8;
    auto softest = [&](const std::vector<Candidate>& cs) {
      std::size_t soft = 0;
      for (std::size_t j = 1; j < cs.size(); ++j)
        if (cs[j].quotient < cs[soft].quotient * (1.0 - margin)) soft = j;
      return soft;
    };
    const std::size_t softStatic = softest(waiting), softKrylov = softest(continuations);
    const bool fromStatic =
        !waiting.empty() &&
        (continuations.empty() || waiting[softStatic].quotient <= continuations[softKrylov].quotient * (1.0 + margin));
    auto& from = fromStatic ? waiting : continuations;
    const std::size_t j = fromStatic ? softStatic : softKrylov;
    Candidate pick = from[j];
    from.erase(from.begin() + static_cast<std::ptrdiff_t>(j));
    // The products were updated by recurrence: recompute them, and
    // reorthogonalise once more against every column, so that the columns are
    // M-orthonormal to working precision rather than to the drift.
    for (int pass = 0; pass < 2; ++pass)
      for (std::size_t k = 0; k < kept.size(); ++k) pick.x->update(-Mkept[k]->dot(*pick.x), *kept[k], 1.0);
    multiply(*s.M(), *pick.x, *pick.Mx);
    const double norm = std::sqrt(std::max(0.0, pick.x->dot(*pick.Mx)));
    pick.x->scale(1.0 / norm), pick.Mx->scale(1.0 / norm);
    multiply(*s.K(), *pick.x, *pick.Kx);
    keep(pick.x, pick.Mx, pick.Kx);
    basis.labels.push_back(pick.label);
    enqueueContinuation(kept.size() - 1, "column " + std::to_string(kept.size()));
  }
  if (static_cast<int>(kept.size()) < count && kept.size() > interfaceColumns)
    basis.dropped.push_back("Krylov sequence stopped growing at " + std::to_string(kept.size()) +
                            " vectors (invariant subspace)");
  if (!kept.empty()) {
    auto V = Teuchos::rcp(new MultiVector(map, kept.size()));
    for (std::size_t k = 0; k < kept.size(); ++k) V->getVectorNonConst(k)->assign(*kept[k]);
    basis.vectors = V;
    // V^T K V and V^T M V from the products every column kept (each
    // computed from the column as kept): the Rayleigh-Ritz estimates need
    // no sparse product of their own.
    const std::size_t k = kept.size();
    basis.projectedK.assign(k * k, 0.0), basis.projectedM.assign(k * k, 0.0);
    for (std::size_t i = 0; i < k; ++i)
      for (std::size_t j = 0; j < k; ++j) {
        basis.projectedK[i + j * k] = kept[i]->dot(*Kkept[j]);
        basis.projectedM[i + j * k] = kept[i]->dot(*Mkept[j]);
      }
  }
  basis.flexibility = std::make_shared<const StaticCorrection>(std::move(factored));
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
