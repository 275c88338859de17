// A copy made by "Copies: N" from its prototype's matrices, turned node by
// node, instead of assembled and prestressed again (doc/theory.md §15.2).
#include "cms/substructure/Substructure.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsGraph.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

namespace cms::substructure {

namespace {

using fem::Component;
using Graph = Tpetra::CrsGraph<>;
using Values = CrsMatrix::local_matrix_device_type::values_type;

/// A rotation entry that is zero but for the rounding of the turn (16 eps,
/// as fem::rotationVariantItem allows): it may not carry a fixed
/// component's value into a free one.
bool negligible(double r) { return std::abs(r) <= 16.0 * std::numeric_limits<double>::epsilon(); }

/// The node triple (translations or rotations) a row belongs to: its rows
/// (-1 where the component is fixed) and the row's place in it.
int triple(const DofTable& t, const std::vector<std::int64_t>& rowNode, GlobalOrdinal g, long long rows[3]) {
  const int c = static_cast<int>(t.components[static_cast<std::size_t>(g)]);
  const int base = c < 3 ? 0 : 3;
  for (int e = 0; e < 3; ++e) rows[e] = t.row(rowNode[static_cast<std::size_t>(g)], static_cast<Component>(base + e));
  return c - base;
}

/// Q A Q^T for matrices on one graph: the turned pattern once, then each
/// matrix's values on it (so the copy's matrices share one graph, as an
/// assembled model's do, and K2 = KS1 - KT1 stays on it: Substructure
/// finishConstruction). Local work only: each node's rows are on one rank
/// (the assembly distributes whole nodes), and a row's turned columns are
/// its node neighbours' other components, already in A's column map.
class TurnedPattern {
public:
  TurnedPattern(const CrsMatrix& A, const DofTable& t, const std::vector<std::int64_t>& rowNode,
                const fem::Rotation& turn)
      : R_(turn.R), rowMap_(A.getRowMap()), colMap_(A.getColMap()), domainMap_(A.getDomainMap()),
        rangeMap_(A.getRangeMap()), graph_(A.getCrsGraph().get()) {
    // 1. Each local column's triple as local columns (the columns an entry
    // turns into: weight R_df from its place f to d), and its place in it.
    localTriples(*colMap_, t, rowNode, true, partner_, slot_, "a column's node is not whole in the column map");
    // 2. Each local row's source rows (the rows it reads: weight R_ce from
    // e to its place c), local.
    if (why_.empty()) localTriples(*rowMap_, t, rowNode, false, source_, rowSlot_, "a node's rows are on two ranks");
  }

  /// 3. The turned pattern: every column some source entry reaches.
  /// Collective (the graph's import), once every rank's why() is empty.
  void build(const CrsMatrix& A) {
    const std::size_t nrows = rowMap_->getNodeNumElements(), ncols = colMap_->getNodeNumElements();
    const auto local = A.getLocalMatrixHost();
    const auto& ptr = local.graph.row_map;
    const auto& ind = local.graph.entries;
    Teuchos::ArrayRCP<std::size_t> rptr(nrows + 1, 0);
    std::vector<LocalOrdinal> rind;
    rind.reserve(static_cast<std::size_t>(A.getNodeNumEntries()));
    std::vector<char> seen(ncols, 0);
    std::vector<LocalOrdinal> row;
    for (std::size_t lr = 0; lr < nrows; ++lr) {
      for (int e = 0; e < 3; ++e) {
        const LocalOrdinal s = source_[lr][static_cast<std::size_t>(e)];
        if (s < 0 || R_[rowSlot_[lr]][e] == 0.0) continue;
        for (auto k = ptr(s); k < ptr(s + 1); ++k) {
          const auto lc = static_cast<std::size_t>(ind(k));
          for (int d = 0; d < 3; ++d) {
            const LocalOrdinal to = partner_[lc][static_cast<std::size_t>(d)];
            if (to < 0 || R_[d][slot_[lc]] == 0.0 || seen[static_cast<std::size_t>(to)]) continue;
            seen[static_cast<std::size_t>(to)] = 1;
            row.push_back(to);
          }
        }
      }
      std::sort(row.begin(), row.end());
      for (LocalOrdinal c : row) seen[static_cast<std::size_t>(c)] = 0;
      rind.insert(rind.end(), row.begin(), row.end());
      rptr[lr + 1] = rind.size();
      row.clear();
    }
    Teuchos::ArrayRCP<LocalOrdinal> cols(rind.size());
    std::copy(rind.begin(), rind.end(), cols.begin());
    auto g = Teuchos::rcp(new Graph(rowMap_, colMap_, rptr, cols));
    g->expertStaticFillComplete(domainMap_, rangeMap_);
    turned_ = g;
  }

  bool built() const { return !turned_.is_null(); }
  /// Why this rank's rows could not be turned locally (empty: they can).
  const std::string& why() const { return why_; }
  bool serves(const CrsMatrix& A) const { return A.getCrsGraph().get() == graph_; }

  /// Q A Q^T on the turned pattern: (Q A Q^T)_(i c, k d) =
  /// sum_(e, f) R_ce A_(i e, k f) R_df.
  Teuchos::RCP<const CrsMatrix> apply(const CrsMatrix& A) const {
    const auto local = A.getLocalMatrixHost();
    const auto& ptr = local.graph.row_map;
    const auto& ind = local.graph.entries;
    const auto& val = local.values;
    const auto out = turned_->getLocalGraphHost();
    const std::size_t nrows = rowMap_->getNodeNumElements();
    Values values("turned", out.entries.extent(0));
    std::vector<double> acc(colMap_->getNodeNumElements(), 0.0);
    for (std::size_t lr = 0; lr < nrows; ++lr) {
      const int c = rowSlot_[lr];
      for (int e = 0; e < 3; ++e) {
        const LocalOrdinal s = source_[lr][static_cast<std::size_t>(e)];
        const double w = s < 0 ? 0.0 : R_[c][e];
        if (w == 0.0) continue;
        for (auto k = ptr(s); k < ptr(s + 1); ++k) {
          const auto lc = static_cast<std::size_t>(ind(k));
          const double wa = w * val(k);
          const auto& to = partner_[lc];
          const auto f = static_cast<std::size_t>(slot_[lc]);
          for (int d = 0; d < 3; ++d)
            if (to[static_cast<std::size_t>(d)] >= 0) acc[static_cast<std::size_t>(to[static_cast<std::size_t>(d)])] += wa * R_[d][f];
        }
      }
      for (auto k = out.row_map(lr); k < out.row_map(lr + 1); ++k) {
        auto& a = acc[static_cast<std::size_t>(out.entries(k))];
        values(k) = a;
        a = 0.0;
      }
    }
    auto T = Teuchos::rcp(new CrsMatrix(turned_, values));
    T->fillComplete(domainMap_, rangeMap_);
    return T;
  }

private:
  /// For each local index of `map`: the local indices of its node triple
  /// (-1 where the component is fixed) and its place in the triple. The
  /// turn may not carry a value between a fixed and a free component:
  /// R_(other, place) for columns (into the other), R_(place, other) for rows
  /// (from it). `split`: the reason when a triple is not whole in `map`.
  void localTriples(const Map& map, const DofTable& t, const std::vector<std::int64_t>& rowNode, bool columns,
                    std::vector<std::array<LocalOrdinal, 3>>& local, std::vector<std::int8_t>& place,
                    const char* split) {
    const std::size_t n = map.getNodeNumElements();
    local.assign(n, {-1, -1, -1});
    place.assign(n, 0);
    for (std::size_t l = 0; l < n && why_.empty(); ++l) {
      long long rows[3];
      const int p = triple(t, rowNode, map.getGlobalElement(static_cast<LocalOrdinal>(l)), rows);
      place[l] = static_cast<std::int8_t>(p);
      for (int o = 0; o < 3; ++o) {
        if (rows[o] < 0) {
          if (!negligible(columns ? R_[o][p] : R_[p][o]))
            why_ = columns ? "the turn carries a free component into a fixed one"
                           : "the turn carries a fixed component into a free one";
          continue;
        }
        const auto g = map.getLocalElement(static_cast<GlobalOrdinal>(rows[o]));
        if (g == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) why_ = split;
        local[l][static_cast<std::size_t>(o)] = g;
      }
    }
  }

  std::array<std::array<double, 3>, 3> R_;
  Teuchos::RCP<const Map> rowMap_, colMap_, domainMap_, rangeMap_;
  const void* graph_;
  std::vector<std::array<LocalOrdinal, 3>> partner_, source_;
  std::vector<std::int8_t> slot_, rowSlot_;
  Teuchos::RCP<const Graph> turned_;
  std::string why_;
};

/// Each job's matrix A (null: none) as Q A Q^T on the turned pattern of
/// its graph, one pattern per graph the matrices share, into *out; with no
/// `out` only whether it can be (patterns checked, not built). Returns why
/// not (empty: done), the same on every rank. Collective.
std::string turnOnPatterns(
    const std::vector<std::pair<Teuchos::RCP<const CrsMatrix>, Teuchos::RCP<const CrsMatrix>*>>& jobs,
    const DofTable& tp, const fem::Rotation& turn, const Teuchos::Comm<int>& comm) {
  const auto rowNode = tp.rowNodes();
  std::vector<std::unique_ptr<TurnedPattern>> patterns;
  for (const auto& [A, out] : jobs) {
    if (A.is_null()) continue;  // the same on every rank
    TurnedPattern* p = nullptr;
    for (const auto& q : patterns)
      if (q->serves(*A)) p = q.get();
    if (p == nullptr) {
      auto q = std::make_unique<TurnedPattern>(*A, tp, rowNode, turn);
      // One verdict on every rank before the collective build.
      int bad = q->why().empty() ? 0 : 1, anyBad = 0;
      Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, bad, Teuchos::outArg(anyBad));
      if (anyBad) return q->why().empty() ? "another rank's rows could not be turned" : q->why();
      patterns.push_back(std::move(q));
      p = patterns.back().get();
    }
    if (out == nullptr) continue;
    if (!p->built()) p->build(*A);
    *out = p->apply(*A);
  }
  return "";
}

}  // namespace

Teuchos::RCP<MultiVector> turnedRows(const MultiVector& X, const DofTable& table, const Teuchos::RCP<const Map>& toMap,
                                     const fem::Rotation& turn) {
  const int ncols = static_cast<int>(X.getNumVectors());
  const auto rowNode = table.rowNodes();
  // 1. The rows of X each local row of the result reads: its node's
  // translations (or rotations), which the turn mixes.
  std::vector<GlobalOrdinal> need;
  const auto nlocal = toMap->getNodeNumElements();
  for (std::size_t lr = 0; lr < nlocal; ++lr) {
    long long r[3];
    triple(table, rowNode, toMap->getGlobalElement(static_cast<LocalOrdinal>(lr)), r);
    for (long long v : r)
      if (v >= 0) need.push_back(static_cast<GlobalOrdinal>(v));
  }
  std::sort(need.begin(), need.end());
  need.erase(std::unique(need.begin(), need.end()), need.end());
  auto needMap = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                      Teuchos::ArrayView<const GlobalOrdinal>(need), 0, toMap->getComm()));
  MultiVector Xn(needMap, ncols);
  Xn.doImport(X, Tpetra::Import<>(X.getMap(), needMap), Tpetra::INSERT);
  // 2. (Q x)_(node, c) = sum_e R[c][e] x_(node, e), a fixed component (no
  // row) being zero.
  auto out = Teuchos::rcp(new MultiVector(toMap, ncols));
  for (int j = 0; j < ncols; ++j) {
    const auto src = Xn.getData(j);
    auto dst = out->getDataNonConst(j);
    for (std::size_t lr = 0; lr < nlocal; ++lr) {
      long long r[3];
      const int c = triple(table, rowNode, toMap->getGlobalElement(static_cast<LocalOrdinal>(lr)), r);
      double v = 0;
      for (int e = 0; e < 3; ++e)
        if (r[e] >= 0) v += turn.R[c][e] * src[needMap->getLocalElement(static_cast<GlobalOrdinal>(r[e]))];
      dst[lr] = v;
    }
  }
  return out;
}

std::optional<Substructure> Substructure::turned(const Substructure& prototype, const fem::FiniteElementModel& model,
                                                 const std::optional<fem::SpinDefinition>& spin,
                                                 const fem::Rotation& turn, const fem::Vec3& origin,
                                                 std::string& why) {
  const DofTable& tp = prototype.dofs_;
  const mesh::Mesh& mesh = *model.mesh;
  const double eps = std::numeric_limits<double>::epsilon();
  auto turnedPoint = [&](const fem::Vec3& x) { return fem::axpy(1.0, turn.apply(fem::sub(x, origin)), origin); };
  // 1. What the turn can stand for: a copy mesh that is the prototype's
  // turned node by node, the same spin turned, matrices without the
  // stationary rotor's tilt term (not turned here) or a compound part.
  // Otherwise the caller assembles the copy, and the turned basis' check
  // (§15.2) judges it.
  if (prototype.map_.is_null() || prototype.M_.is_null() || prototype.K_.is_null()) {
    why = "the prototype has no matrices here";
  } else if (!prototype.KX1_.is_null()) {
    why = "its tilt stiffness (a stationary rotor in a spinning frame) is not turned";
  } else if (mesh.nodeCount() != tp.nodes()) {
    why = "its mesh has another node count";
  } else if (spin.has_value() != prototype.spin_.has_value()) {
    why = "it spins where the prototype does not, or the other way round";
  }
  // The structure's size here: the largest distance of a prototype node
  // from the origin or from the turn's axis point (the placement's scale).
  double size = fem::norm(origin);
  for (std::size_t n = 0; n < tp.nodes(); ++n) {
    const fem::Vec3 xp{tp.coordinates[3 * n], tp.coordinates[3 * n + 1], tp.coordinates[3 * n + 2]};
    size = std::max({size, fem::norm(xp), fem::norm(fem::sub(xp, origin))});
  }
  if (why.empty() && spin) {
    const auto& a = *prototype.spin_;
    size = std::max({size, fem::norm(a.spin.origin), fem::norm(spin->spin.origin)});
    if (spin->frame != a.frame || spin->stressStiffening != a.stressStiffening ||
        spin->frameAxis.has_value() != a.frameAxis.has_value() ||
        fem::norm(fem::sub(spin->spin.axis, turn.apply(a.spin.axis))) > 64 * eps ||
        fem::norm(fem::sub(spin->spin.origin, turnedPoint(a.spin.origin))) > 64 * eps * size ||
        (a.frameAxis && fem::norm(fem::sub(*spin->frameAxis, turn.apply(*a.frameAxis))) > 64 * eps))
      why = "its spin is not the prototype's turned";
  }
  if (why.empty()) {
    // The mesh: each node the prototype's turned, to the rounding of the
    // turn against the structure's size (as the copies' placement, §15.1).
    double off = 0.0;
    for (std::size_t n = 0; n < tp.nodes(); ++n) {
      const fem::Vec3 xp{tp.coordinates[3 * n], tp.coordinates[3 * n + 1], tp.coordinates[3 * n + 2]};
      const fem::Vec3 xc{mesh.coordinates[3 * n], mesh.coordinates[3 * n + 1], mesh.coordinates[3 * n + 2]};
      off = std::max(off, fem::norm(fem::sub(xc, turnedPoint(xp))));
    }
    if (off > 64 * eps * size) why = "its mesh is not the prototype's turned";
  }
  // 2. The matrices: not formed (the copy applies its prototype's, turned:
  // apply()), but whether they could be, on the turned pattern of each
  // graph they share (formed() relies on it), asked now.
  if (!why.empty()) return std::nullopt;
  const auto comm = prototype.map_->getComm();
  Substructure s;
  auto proto = std::make_shared<Prototype>();
  proto->M = prototype.M_, proto->K = prototype.K_, proto->G1 = prototype.G1_, proto->KT1 = prototype.KT1_;
  proto->KS1 = prototype.KS1_, proto->K2 = prototype.K2_, proto->D = prototype.D_, proto->N1 = prototype.N1_;
  proto->turn = turn;
  why = turnOnPatterns({{proto->M, nullptr}, {proto->K, nullptr}, {proto->G1, nullptr}, {proto->KT1, nullptr},
                        {proto->KS1, nullptr}, {proto->D, nullptr}, {proto->N1, nullptr}},
                       tp, turn, *comm);
  if (!why.empty()) return std::nullopt;  // the same on every rank (step 1 is, and the patterns' verdicts)
  // The local plan of the turns (Substructure::apply), where it serves.
  {
    const Map& map = *prototype.map_;
    const auto rowNode = tp.rowNodes();
    bool local = true;
    for (const auto& A : {proto->M, proto->K, proto->G1, proto->KT1, proto->KS1, proto->K2, proto->D, proto->N1})
      local = local && (A.is_null() || (A->getDomainMap()->isSameAs(map) && A->getRangeMap()->isSameAs(map)));
    const std::size_t n = map.getNodeNumElements();
    proto->triples.resize(local ? n : 0);
    proto->places.resize(local ? n : 0);
    for (std::size_t l = 0; l < n && local; ++l) {
      long long r[3];
      proto->places[l] = static_cast<std::int8_t>(triple(tp, rowNode, map.getGlobalElement(static_cast<LocalOrdinal>(l)), r));
      for (int e = 0; e < 3; ++e) {
        const LocalOrdinal at = r[e] < 0 ? -1 : map.getLocalElement(static_cast<GlobalOrdinal>(r[e]));
        if (r[e] >= 0 && at == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) local = false;
        proto->triples[l][static_cast<std::size_t>(e)] = at;
      }
    }
    // The same path on every rank: apply() is collective (the other one
    // imports).
    int mine = local ? 1 : 0, all = 0;
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_MIN, mine, Teuchos::outArg(all));
    if (all == 0) proto->triples.clear(), proto->places.clear();
  }
  s.prototype_ = std::move(proto);
  // 3. The rest: the load and reactions per unit Omega^2 turned, the DOF
  // table with the copy's own coordinates and names.
  s.name_ = model.name;
  s.map_ = prototype.map_;
  s.spin_ = spin;
  s.modalDampingRatio_ = prototype.modalDampingRatio_;
  if (!prototype.f1_.is_null()) s.f1_ = turnedRows(*prototype.f1_, tp, prototype.map_, turn);
  std::map<std::pair<std::int64_t, int>, double> reaction;
  for (const auto& r : prototype.reactions1_) reaction[{r.node, static_cast<int>(r.component)}] = 0.0;
  for (const auto& r : prototype.reactions1_) {
    const int c = static_cast<int>(r.component), base = c < 3 ? 0 : 3;
    for (int d = 0; d < 3; ++d) {
      const auto key = std::make_pair(r.node, base + d);
      const double v = turn.R[d][c - base] * r.value;
      if (reaction.count(key)) reaction[key] += v;
      else if (!negligible(turn.R[d][c - base])) {
        why = "its prestress reactions turn onto components the prototype holds none on";
        return std::nullopt;
      }
    }
  }
  for (const auto& r : prototype.reactions1_)
    s.reactions1_.push_back({r.node, r.component, reaction[{r.node, static_cast<int>(r.component)}]});
  s.dofs_ = tp;
  s.dofs_.nodeIds.assign(mesh.nodeTags.begin(), mesh.nodeTags.end());
  s.dofs_.coordinates = mesh.coordinates;
  s.finishConstruction();
  return s;
}

Substructure Substructure::formed() const {
  if (!prototype_) return *this;
  Substructure s = *this;
  s.prototype_.reset();
  const auto& p = *prototype_;
  const std::string why = turnOnPatterns({{p.M, &s.M_}, {p.K, &s.K_}, {p.G1, &s.G1_}, {p.KT1, &s.KT1_},
                                          {p.KS1, &s.KS1_}, {p.D, &s.D_}, {p.N1, &s.N1_}},
                                         dofs_, p.turn, *map_->getComm());
  // turned() asked the same patterns: they could be built then.
  if (!why.empty()) throw std::logic_error("Substructure::formed: '" + name_ + "': " + why);
  s.finishConstruction();
  return s;
}

}  // namespace cms::substructure
