#include "MonolithicSum.hpp"

#include <algorithm>

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Export.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>

namespace cms::synthesis::detail {

namespace {

/// T's rows for every column of A (A's column map, local order), flat.
struct RowsOnColumns {
  std::vector<std::size_t> ptr;
  std::vector<GlobalOrdinal> coord;
  std::vector<double> coeff;
};

RowsOnColumns rowsOnColumns(const CrsMatrix& T, const Map& columns) {
  const auto target = Teuchos::rcpFromRef(columns);
  CrsMatrix Tc(target, 0);
  Tc.doImport(T, Tpetra::Import<>(T.getRowMap(), target), Tpetra::INSERT);
  RowsOnColumns out;
  const std::size_t n = columns.getNodeNumElements();
  out.ptr.assign(n + 1, 0);
  Teuchos::Array<GlobalOrdinal> c;
  Teuchos::Array<double> v;
  for (std::size_t l = 0; l < n; ++l) {
    const GlobalOrdinal g = columns.getGlobalElement(static_cast<LocalOrdinal>(l));
    const std::size_t k = Tc.getNumEntriesInGlobalRow(g);
    const std::size_t have = k == Teuchos::OrdinalTraits<std::size_t>::invalid() ? 0 : k;
    c.resize(have), v.resize(have);
    std::size_t got = 0;
    if (have > 0) Tc.getGlobalRowCopy(g, c(), v(), got);
    for (std::size_t e = 0; e < got; ++e)
      if (v[e] != 0.0) out.coord.push_back(c[e]), out.coeff.push_back(v[e]);
    out.ptr[l + 1] = out.coord.size();
  }
  return out;
}

/// Gustavson's sparse accumulator over the coordinates 0 .. n-1.
class Accumulator {
public:
  explicit Accumulator(std::size_t n) : w_(n, 0.0), seen_(n, 0) {}
  void add(GlobalOrdinal q, double v) {
    const auto i = static_cast<std::size_t>(q);
    if (!seen_[i]) seen_[i] = 1, touched_.push_back(q);
    w_[i] += v;
  }
  /// The touched coordinates (sorted if asked) and their sums; then cleared by clear().
  std::vector<GlobalOrdinal>& touched(bool sorted) {
    if (sorted) std::sort(touched_.begin(), touched_.end());
    return touched_;
  }
  double operator[](GlobalOrdinal q) const { return w_[static_cast<std::size_t>(q)]; }
  void clear() {
    for (GlobalOrdinal q : touched_) w_[static_cast<std::size_t>(q)] = 0.0, seen_[static_cast<std::size_t>(q)] = 0;
    touched_.clear();
  }

private:
  std::vector<double> w_;
  std::vector<char> seen_;
  std::vector<GlobalOrdinal> touched_;
};

}  // namespace

void MonolithicSum::add(const CrsMatrix& T, const CrsMatrix& A, double c, GlobalOrdinal n,
                        const std::vector<Row>& motion) {
  const auto& colMap = *A.getColMap();
  const auto& rowMap = *A.getRowMap();
  const RowsOnColumns t = rowsOnColumns(T, colMap);
  const std::size_t nloc = rowMap.getNodeNumElements();
  Accumulator acc(T.getDomainMap()->getGlobalNumElements());
  // 1. X = A T, row by row of A: X_i = sum_j a_ij T_j.
  const auto local = A.getLocalMatrixHost();
  const auto& aptr = local.graph.row_map;
  const auto& aind = local.graph.entries;
  const auto& aval = local.values;
  std::vector<std::size_t> xptr(nloc + 1, 0);
  std::vector<GlobalOrdinal> xcol;
  std::vector<double> xval;
  xcol.reserve(A.getNodeNumEntries());
  xval.reserve(A.getNodeNumEntries());
  for (std::size_t l = 0; l < nloc; ++l) {
    for (auto e = aptr(l); e < aptr(l + 1); ++e) {
      const auto lc = static_cast<std::size_t>(aind(e));
      const double a = aval(e);
      for (std::size_t k = t.ptr[lc]; k < t.ptr[lc + 1]; ++k) acc.add(t.coord[k], a * t.coeff[k]);
    }
    for (GlobalOrdinal q : acc.touched(false)) xcol.push_back(q), xval.push_back(acc[q]);
    xptr[l + 1] = xcol.size();
    acc.clear();
  }
  // 2. T^T X by rows of T^T: each coordinate p gathers t_ip X_i over the rows
  // i whose T reaches it (T's transpose, this rank's rows), so every entry
  // of the result is summed once, and the rows come out in order. (Scattering
  // T_i^T X_i row by row of X instead made n_held n_face^2 separate entries
  // for a RigidFit face, 4e8 on the 5e4-DOF rotor.)
  struct Reach {
    GlobalOrdinal p;
    std::size_t i;
    double t;
  };
  std::vector<Reach> reach;
  reach.reserve(nloc);
  for (std::size_t l = 0; l < nloc; ++l) {
    const auto li = static_cast<std::size_t>(colMap.getLocalElement(rowMap.getGlobalElement(static_cast<LocalOrdinal>(l))));
    for (std::size_t k = t.ptr[li]; k < t.ptr[li + 1]; ++k) reach.push_back({t.coord[k], l, t.coeff[k]});
  }
  std::stable_sort(reach.begin(), reach.end(), [](const Reach& a, const Reach& b) { return a.p < b.p; });
  const std::size_t start = entries_.size();
  // About the upper half of X's entries: grown geometrically it would be
  // copied a dozen times, the page faults of issue 18.
  entries_.reserve(start + xcol.size() / 2 + nloc);
  for (std::size_t r = 0; r < reach.size();) {
    const GlobalOrdinal p = reach[r].p;
    for (; r < reach.size() && reach[r].p == p; ++r)
      for (std::size_t e = xptr[reach[r].i]; e < xptr[reach[r].i + 1]; ++e) acc.add(xcol[e], reach[r].t * xval[e]);
    // The upper triangle (a skew matrix's diagonal is 0); matrix() sorts
    // each row once, over every add.
    for (GlobalOrdinal q : acc.touched(false)) {
      const double v = c * acc[q];
      if (v != 0.0 && (p < q || (p == q && sign_ > 0.0))) entries_.push_back({p, q, v});
    }
    acc.clear();
  }
  if (!motion.empty()) expandMotion(start, n, motion);
  added_ = true;
}

void MonolithicSum::expandMotion(std::size_t start, GlobalOrdinal n, const std::vector<Row>& motion) {
  // The coordinates the motion reaches, and H (row v: motion[v] over them).
  std::vector<GlobalOrdinal> reach;
  for (const auto& row : motion)
    for (const auto& [q, h] : row) reach.push_back(q);
  std::sort(reach.begin(), reach.end());
  reach.erase(std::unique(reach.begin(), reach.end()), reach.end());
  const std::size_t nv = motion.size(), m = reach.size();
  std::vector<double> H(nv * m, 0.0);
  for (std::size_t v = 0; v < nv; ++v)
    for (const auto& [q, h] : motion[v])
      H[v * m + static_cast<std::size_t>(std::lower_bound(reach.begin(), reach.end(), q) - reach.begin())] += h;
  // The block's entries with a virtual column: (p, v) with p real, or (v, w)
  // both virtual (virtual ids are the largest, so never (v, p)); they come
  // by row. In the full product (p, v) = x and (v, p) = sign x, so with
  // v = H_v q, row p's r = sum_v x_v H_v adds r_c to (p, c) and sign r_c to
  // (c, p): in the upper triangle, (p, c) if p < c, (c, p) times sign if
  // p > c, and both on the diagonal if p = c. One pass over a row's (at
  // most six) virtual entries, then one entry per reached coordinate.
  std::vector<double> B(nv * nv, 0.0), r(m);
  std::vector<Entry> expanded;
  std::size_t kept = start;
  for (std::size_t e = start; e < entries_.size();) {
    const Entry x = entries_[e];
    if (x.col < n) {
      entries_[kept++] = x;
      ++e;
      continue;
    }
    if (x.row >= n) {
      B[static_cast<std::size_t>(x.row - n) * nv + static_cast<std::size_t>(x.col - n)] += x.value;
      ++e;
      continue;
    }
    std::fill(r.begin(), r.end(), 0.0);
    for (; e < entries_.size() && entries_[e].row == x.row && entries_[e].col >= n; ++e) {
      const double* h = &H[static_cast<std::size_t>(entries_[e].col - n) * m];
      for (std::size_t j = 0; j < m; ++j) r[j] += entries_[e].value * h[j];
    }
    for (std::size_t j = 0; j < m; ++j) {
      if (r[j] == 0.0) continue;
      const GlobalOrdinal q = reach[j];
      if (x.row < q) expanded.push_back({x.row, q, r[j]});
      else if (x.row > q) expanded.push_back({q, x.row, sign_ * r[j]});
      else if (sign_ > 0.0) expanded.push_back({q, q, 2.0 * r[j]});
    }
  }
  entries_.resize(kept);
  entries_.insert(entries_.end(), expanded.begin(), expanded.end());
  // D = H^T B H with B made whole (B_wv = sign B_vw): its upper triangle.
  bool any = false;
  for (double b : B) any = any || b != 0.0;
  if (!any || m == 0) return;
  std::vector<double> full(nv * nv, 0.0);
  for (std::size_t v = 0; v < nv; ++v)
    for (std::size_t w = v; w < nv; ++w) {
      full[v * nv + w] += B[v * nv + w];
      if (w != v) full[w * nv + v] += sign_ * B[v * nv + w];
    }
  std::vector<double> W(nv * m, 0.0);  // B H
  for (std::size_t v = 0; v < nv; ++v)
    for (std::size_t w = 0; w < nv; ++w) {
      const double b = full[v * nv + w];
      if (b == 0.0) continue;
      for (std::size_t j = 0; j < m; ++j) W[v * m + j] += b * H[w * m + j];
    }
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i; j < m; ++j) {
      if (j == i && sign_ < 0.0) continue;
      double d = 0.0;
      for (std::size_t v = 0; v < nv; ++v) d += H[v * m + i] * W[v * m + j];
      if (d != 0.0) entries_.push_back({reach[i], reach[j], d});
    }
}

bool MonolithicSum::empty(const Teuchos::Comm<int>& comm) const {
  int mine = added_ ? 1 : 0, any = 0;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, mine, Teuchos::outArg(any));
  return any == 0;
}

Teuchos::RCP<const CrsMatrix> MonolithicSum::matrix(const Teuchos::RCP<const Map>& map) {
  const auto comm = map->getComm();
  const auto n = static_cast<std::size_t>(map->getGlobalNumElements());
  // The upper entries by row (a stable counting sort), then by column within
  // a row, duplicates (a row several substructures reach) summed.
  std::vector<std::size_t> upperPtr(n + 1, 0);
  for (const auto& e : entries_) ++upperPtr[static_cast<std::size_t>(e.row) + 1];
  for (std::size_t i = 0; i < n; ++i) upperPtr[i + 1] += upperPtr[i];
  std::vector<GlobalOrdinal> ucol(entries_.size());
  std::vector<double> uval(entries_.size());
  {
    std::vector<std::size_t> next(upperPtr.begin(), upperPtr.end() - 1);
    for (const auto& e : entries_) {
      const std::size_t k = next[static_cast<std::size_t>(e.row)]++;
      ucol[k] = e.col, uval[k] = e.value;
    }
  }
  std::vector<Entry>().swap(entries_);
  std::vector<std::pair<GlobalOrdinal, double>> row;
  std::size_t kept = 0;
  std::vector<std::size_t> rowStart(n + 1, 0);
  for (std::size_t p = 0; p < n; ++p) {
    const std::size_t b = upperPtr[p], e = upperPtr[p + 1];
    rowStart[p] = kept;
    if (e == b) continue;
    // The row sorted by column in a copy, duplicates summed, then written
    // back at `kept` <= b. (An entry and its mirror are written from the
    // same sum: the symmetry stays exact.)
    row.clear();
    for (std::size_t k = b; k < e; ++k) row.push_back({ucol[k], uval[k]});
    std::sort(row.begin(), row.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    std::size_t w = kept;
    for (const auto& [q, v] : row) {
      if (w > kept && ucol[w - 1] == q) uval[w - 1] += v;
      else ucol[w] = q, uval[w++] = v;
    }
    kept = w;
  }
  rowStart[n] = kept;
  ucol.resize(kept), uval.resize(kept);
  // Rows and columns present, and whether every rank's rows are its own.
  std::vector<char> isRow(n, 0);
  for (std::size_t p = 0; p < n; ++p)
    if (rowStart[p + 1] > rowStart[p]) {
      isRow[p] = 1;
      for (std::size_t k = rowStart[p]; k < rowStart[p + 1]; ++k) isRow[static_cast<std::size_t>(ucol[k])] = 1;
    }
  int allMine = 1, everywhere = 0;
  for (std::size_t p = 0; p < n && allMine; ++p)
    if (isRow[p] && !map->isNodeGlobalElement(static_cast<GlobalOrdinal>(p))) allMine = 0;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MIN, allMine, Teuchos::outArg(everywhere));
  // Rows as built: `map` itself when every rank's rows are its own (one
  // rank), else the rows this rank has entries for, exported with ADD.
  Teuchos::RCP<const Map> built = map;
  std::vector<GlobalOrdinal> present;  // also the column map: every row is a column of its mirror
  for (std::size_t p = 0; p < n; ++p)
    if (isRow[p]) present.push_back(static_cast<GlobalOrdinal>(p));
  if (!everywhere)
    built = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                 Teuchos::ArrayView<const GlobalOrdinal>(present), map->getIndexBase(), comm));
  auto colMap = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                     Teuchos::ArrayView<const GlobalOrdinal>(present), map->getIndexBase(), comm));
  std::vector<LocalOrdinal> localCol(n, 0);
  for (std::size_t k = 0; k < present.size(); ++k) localCol[static_cast<std::size_t>(present[k])] = static_cast<LocalOrdinal>(k);
  // Both triangles: (p, q, v) and its mirror (q, p, sign v). Row r holds its
  // mirrors (columns p < r, in increasing p) and then its own upper entries.
  const std::size_t nrows = built->getNodeNumElements();
  Teuchos::ArrayRCP<std::size_t> ptr(nrows + 1, 0);
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t k = rowStart[p]; k < rowStart[p + 1]; ++k) {
      ++ptr[static_cast<std::size_t>(built->getLocalElement(static_cast<GlobalOrdinal>(p))) + 1];
      if (static_cast<std::size_t>(ucol[k]) != p) ++ptr[static_cast<std::size_t>(built->getLocalElement(ucol[k])) + 1];
    }
  for (std::size_t i = 0; i < nrows; ++i) ptr[i + 1] += ptr[i];
  Teuchos::ArrayRCP<LocalOrdinal> ind(ptr[nrows]);
  Teuchos::ArrayRCP<double> val(ptr[nrows]);
  std::vector<std::size_t> next(ptr.begin(), ptr.begin() + static_cast<std::ptrdiff_t>(nrows));
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t k = rowStart[p]; k < rowStart[p + 1]; ++k) {
      if (static_cast<std::size_t>(ucol[k]) == p) continue;
      const auto r = static_cast<std::size_t>(built->getLocalElement(ucol[k]));
      ind[next[r]] = localCol[p], val[next[r]++] = sign_ * uval[k];
    }
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t k = rowStart[p]; k < rowStart[p + 1]; ++k) {
      const auto r = static_cast<std::size_t>(built->getLocalElement(static_cast<GlobalOrdinal>(p)));
      ind[next[r]] = localCol[static_cast<std::size_t>(ucol[k])], val[next[r]++] = uval[k];
    }
  added_ = false;
  auto A = Teuchos::rcp(new CrsMatrix(built, colMap, ptr, ind, val));
  A->expertStaticFillComplete(map, map);
  if (everywhere) return A;
  return Tpetra::exportAndFillCompleteCrsMatrix<CrsMatrix>(Teuchos::RCP<const CrsMatrix>(A),
                                                           Tpetra::Export<>(built, map), map, map);
}

}  // namespace cms::synthesis::detail
