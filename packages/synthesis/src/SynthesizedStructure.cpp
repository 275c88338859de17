// The interface transforms T_s and the projected structure matrices
// (doc/theory.md §11.2-§11.3).
#include "cms/synthesis/SynthesizedStructure.hpp"

#include <algorithm>
#include <limits>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <set>
#include <sstream>
#include <atomic>
#include <memory>
#include <exception>
#include <thread>
#include <tuple>

#include <Teuchos_BLAS.hpp>
#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <TpetraExt_MatrixMatrix.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "CopiedBasis.hpp"
#include "MonolithicSum.hpp"
#include "PartData.hpp"
#include "cms/core/MatrixSum.hpp"
#include "cms/core/BlasThreads.hpp"
#include "cms/core/DistributedDirectSolver.hpp"  // ranksOnNode
#include "cms/core/Error.hpp"
#include "cms/core/HeldDofs.hpp"
#include "cms/core/Redistribution.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/SparseGyroscopicSolver.hpp"
#include "cms/reduction/CraigBamptonBasis.hpp"
#include "cms/reduction/StaticCorrection.hpp"
#include "cms/core/SparseInertia.hpp"
#include "cms/core/HeldDofs.hpp"

namespace cms::synthesis {

namespace detail {
namespace {

/// Numbers and strings from rank `from` to every rank (collective); sizes
/// need not be known elsewhere.
void broadcastFrom(const Teuchos::Comm<int>& comm, int from, std::vector<double>& numbers,
                   std::vector<std::string>& text) {
  std::vector<long long> sizes{static_cast<long long>(numbers.size()), static_cast<long long>(text.size())};
  for (const auto& t : text) sizes.push_back(static_cast<long long>(t.size()));
  long long count = static_cast<long long>(sizes.size());
  Teuchos::broadcast(comm, from, &count);
  sizes.resize(static_cast<std::size_t>(count));
  Teuchos::broadcast(comm, from, static_cast<int>(count), sizes.data());
  numbers.resize(static_cast<std::size_t>(sizes[0]));
  if (sizes[0] > 0) Teuchos::broadcast(comm, from, static_cast<int>(sizes[0]), numbers.data());
  std::string joined;
  if (comm.getRank() == from)
    for (const auto& t : text) joined += t;
  long long total = 0;
  for (long long i = 2; i < count; ++i) total += sizes[i];
  joined.resize(static_cast<std::size_t>(total));
  if (total > 0) Teuchos::broadcast(comm, from, static_cast<int>(total), joined.data());
  text.assign(static_cast<std::size_t>(sizes[1]), std::string());
  std::size_t at = 0;
  for (long long i = 0; i < sizes[1]; ++i) {
    text[i] = joined.substr(at, static_cast<std::size_t>(sizes[2 + i]));
    at += static_cast<std::size_t>(sizes[2 + i]);
  }
}

}  // namespace
}  // namespace detail

namespace {

using Row = std::vector<std::pair<GlobalOrdinal, double>>;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// Modes per block of the error estimates' residuals (residualFlexibilityNorms):
/// 8 columns (real and imaginary parts), each block of vectors of the
/// largest substructure and of its factor's solve workspace ~10 such
/// columns wide; wide enough for the solves' BLAS-3 kernels, and each block
/// is one pass over the factor.
constexpr int kResidualBlockModes = 4;

/// The requested rows of a distributed matrix, on every rank (collective).
std::map<GlobalOrdinal, Row> gatherRows(const CrsMatrix& T, const std::set<GlobalOrdinal>& rows) {
  const auto& comm = *T.getRowMap()->getComm();
  const auto& colMap = *T.getColMap();
  std::vector<double> mine;  // row, count, (col, value)...: ids stay exact below 2^53
  for (GlobalOrdinal g : rows) {
    const LocalOrdinal l = T.getRowMap()->getLocalElement(g);
    if (l == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) continue;
    const std::size_t n = T.getNumEntriesInLocalRow(l);
    Teuchos::Array<LocalOrdinal> c(n);
    Teuchos::Array<double> v(n);
    std::size_t got = 0;
    T.getLocalRowCopy(l, c(), v(), got);
    mine.push_back(static_cast<double>(g));
    mine.push_back(static_cast<double>(got));
    for (std::size_t k = 0; k < got; ++k) {
      mine.push_back(static_cast<double>(colMap.getGlobalElement(c[k])));
      mine.push_back(v[k]);
    }
  }
  const int p = comm.getSize(), r = comm.getRank();
  std::vector<long long> counts(p, 0), all(p, 0);
  counts[r] = static_cast<long long>(mine.size());
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, p, counts.data(), all.data());
  const long long total = std::accumulate(all.begin(), all.end(), 0LL);
  std::vector<double> buf(total, 0.0), sum(total, 0.0);
  const long long off = std::accumulate(all.begin(), all.begin() + r, 0LL);
  std::copy(mine.begin(), mine.end(), buf.begin() + off);
  if (total > 0) Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, static_cast<int>(total), buf.data(), sum.data());
  std::map<GlobalOrdinal, Row> out;
  for (long long i = 0; i < total;) {
    const auto g = static_cast<GlobalOrdinal>(sum[i]);
    const auto n = static_cast<long long>(sum[i + 1]);
    Row& row = out[g];
    for (long long k = 0; k < n; ++k)
      row.push_back({static_cast<GlobalOrdinal>(sum[i + 2 + 2 * k]), sum[i + 3 + 2 * k]});
    i += 2 + 2 * n;
  }
  return out;
}

/// A fill-complete matrix from explicit rows (global row -> entries) on
/// `rowMap`, with the given domain and range maps.
Teuchos::RCP<CrsMatrix> fromRows(const Teuchos::RCP<const Map>& rowMap, const std::vector<Row>& rows,
                                 const Teuchos::RCP<const Map>& domain, const Teuchos::RCP<const Map>& range) {
  Teuchos::Array<std::size_t> counts(rows.size());
  for (std::size_t l = 0; l < rows.size(); ++l) counts[l] = rows[l].size();
  auto A = Teuchos::rcp(new CrsMatrix(rowMap, counts()));
  for (std::size_t l = 0; l < rows.size(); ++l) {
    if (rows[l].empty()) continue;
    Teuchos::Array<GlobalOrdinal> c(rows[l].size());
    Teuchos::Array<double> v(rows[l].size());
    for (std::size_t k = 0; k < rows[l].size(); ++k) c[k] = rows[l][k].first, v[k] = rows[l][k].second;
    A->insertGlobalValues(rowMap->getGlobalElement(static_cast<LocalOrdinal>(l)), c(), v());
  }
  A->fillComplete(domain, range);
  return A;
}

/// sum of coefficient * row, merged by column.
Row combine(const std::vector<std::pair<double, const Row*>>& terms) {
  std::map<GlobalOrdinal, double> acc;
  for (auto [c, r] : terms)
    for (auto [g, v] : *r) acc[g] += c * v;
  Row out;
  for (auto [g, v] : acc)
    if (v != 0.0) out.push_back({g, v});
  return out;
}

/// D^T S D for n x n column-major D and S.
std::vector<double> congruence(const std::vector<double>& D, const std::vector<double>& S) {
  const int n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(S.size()))));
  std::vector<double> W(S.size()), out(S.size());
  Teuchos::BLAS<int, double> blas;
  if (n == 0) return out;
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, n, n, n, 1.0, S.data(), n, D.data(), n, 0.0, W.data(), n);
  blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, n, n, n, 1.0, D.data(), n, W.data(), n, 0.0, out.data(), n);
  return out;
}

/// T^T A T for every matrix A of one substructure, with u_s = T q
/// (collective). A reduced substructure's T has few nonzero columns (its own
/// coordinates and those of its parent's that reach its attachment), each
/// full length: as sparse matrices the products cost a sparse-sparse
/// multiply with k entries per row, O(n k^2) hash operations, which took 92%
/// of a 1000-coordinate synthesis (perf, doc/benchmarks.md). Reduced
/// substructures are therefore projected through the factors T = B C below
/// (a sparse-times-dense product, one GEMM with a reduction over ranks, and
/// small dense products); T of Full bases (the truth: near identity) and of
/// rigid rotors (six rows) keep Tpetra's sparse products.
class Projection {
public:
  explicit Projection(const CrsMatrix& T) : T_(&T), coords_(T.getDomainMap()) {}

  /// T = B C with B (n x b, on T's row map) and C (b rows over the
  /// coordinates, given sparse): for a reduced substructure B = [X_s | V_s]
  /// (rigid or constraint-mode columns, then the basis) and C = [H_s T_p;
  /// I], so that T^T A T = C^T (B^T A B) C needs A times b = 6 + k columns
  /// instead of every coordinate reaching the substructure.
  Projection(Teuchos::RCP<const Map> coords, Teuchos::RCP<const MultiVector> B, std::vector<Row> C)
      : coords_(std::move(coords)), B_(std::move(B)), C_(std::move(C)) {
    small_ = Teuchos::rcp(new Map(B_->getNumVectors(), 0, coords_->getComm(), Tpetra::LocallyReplicated));
    std::set<GlobalOrdinal> cs;
    for (const auto& row : C_)
      for (auto [g, v] : row) cs.insert(g);
    cols_.assign(cs.begin(), cs.end());
  }

  /// T^T A T for the substructure's matrix `a`: applied (a turned copy's
  /// without being formed, theory §15.2) when T = B C; a Full basis's
  /// sparse product needs the matrix itself.
  Teuchos::RCP<const CrsMatrix> operator()(const substructure::Substructure& s, substructure::Matrix a) const {
    return B_.is_null() ? sparse(*s.matrix(a)) : factored(s, a, 0);
  }
  /// The same for a matrix of its own (a compound rotor's KX1).
  Teuchos::RCP<const CrsMatrix> operator()(const CrsMatrix& A) const {
    return B_.is_null() ? sparse(A) : factored([&](const MultiVector& X, MultiVector& Y) { A.apply(X, Y); },
                                               A.getRangeMap(), 0);
  }

  /// The elastic stiffness, where B's first `rigid` columns are rigid
  /// motions X of the substructure (a point attachment) that K annihilates
  /// (nothing grounds the substructure: the caller passes rigid = 0 for one
  /// held by supports of its own, SynthesizedStructure::carriedRigidly).
  /// What is computed for K X is then rounding, eps |K||X|, which for a
  /// part 1e12 times stiffer than its parent outweighs the parent's
  /// stiffness (a Guyan arm on a post gave 4.5 Hz for 7.27): those columns
  /// are made exactly zero (theory §11.2).
  Teuchos::RCP<const CrsMatrix> stiffness(const substructure::Substructure& s, int rigid) const {
    return B_.is_null() ? sparse(*s.K()) : factored(s, substructure::Matrix::K, rigid);
  }

  /// B^T A B (nb x nb, column-major, on every rank) for the substructure's
  /// matrix `a`, the first `rigid` columns treated as in stiffness().
  std::vector<double> small(const substructure::Substructure& s, substructure::Matrix a, int rigid) const {
    return small([&](const MultiVector& X, MultiVector& Y) { s.apply(a, X, Y); }, s.map(), rigid);
  }
  /// C^T S C over the coordinates, for S = B^T A B.
  Teuchos::RCP<const CrsMatrix> expand(const std::vector<double>& Sd) const {
    const int nb = static_cast<int>(B_->getNumVectors()), nc = static_cast<int>(cols_.size());
    std::vector<double> Cd(static_cast<std::size_t>(nb) * nc, 0.0);
    for (int i = 0; i < nb; ++i)
      for (auto [g, v] : C_[i]) {
        const auto c = std::lower_bound(cols_.begin(), cols_.end(), g) - cols_.begin();
        Cd[i + static_cast<std::size_t>(c) * nb] += v;
      }
    // P = C^T (S C), column-major.
    std::vector<double> W(static_cast<std::size_t>(nb) * nc), P(static_cast<std::size_t>(nc) * nc);
    Teuchos::BLAS<int, double> blas;
    if (nb > 0 && nc > 0) {
      blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nb, nc, nb, 1.0, Sd.data(), nb, Cd.data(), nb, 0.0, W.data(), nb);
      blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, nc, nc, nb, 1.0, Cd.data(), nb, W.data(), nb, 0.0, P.data(), nc);
    }
    const auto& coords = coords_;
    std::vector<Row> rows(coords->getNodeNumElements());
    for (int i = 0; i < nc; ++i) {
      const auto l = coords->getLocalElement(cols_[i]);
      if (l == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) continue;
      for (int j = 0; j < nc; ++j) {
        const double v = P[i + static_cast<std::size_t>(j) * nc];
        if (v != 0.0) rows[l].push_back({cols_[j], v});
      }
    }
    return fromRows(coords, rows, coords, coords);
  }

private:
  Teuchos::RCP<const CrsMatrix> factored(const substructure::Substructure& s, substructure::Matrix a, int rigid) const {
    return expand(small(s, a, rigid));
  }
  template <class Apply>
  Teuchos::RCP<const CrsMatrix> factored(const Apply& apply, const Teuchos::RCP<const Map>& range, int rigid) const {
    return expand(small(apply, range, rigid));
  }
  template <class Apply>
  std::vector<double> small(const Apply& apply, const Teuchos::RCP<const Map>& range, int rigid) const {
    const int nb = static_cast<int>(B_->getNumVectors());
    MultiVector AB(range, nb), S(small_, nb);
    apply(*B_, AB);
    for (int a = 0; a < std::min(rigid, nb); ++a) AB.getVectorNonConst(a)->putScalar(0.0);
    S.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, *B_, AB, 0.0);
    if (rigid > 0) {
      // B_a^T K B_j = (K B_a)^T B_j: the row of a zeroed column is zero too.
      for (int a = 0; a < std::min(rigid, nb); ++a) {
        bool zero = true;
        for (double v : S.getData(a)) zero = zero && v == 0.0;
        if (zero)
          for (int j = 0; j < nb; ++j) S.replaceLocalValue(static_cast<LocalOrdinal>(a), j, 0.0);
      }
    }
    std::vector<double> Sd(static_cast<std::size_t>(nb) * nb);
    for (int j = 0; j < nb; ++j) {
      const auto c = S.getData(j);
      for (int i = 0; i < nb; ++i) Sd[i + static_cast<std::size_t>(j) * nb] = c[i];
    }
    return Sd;
  }

  Teuchos::RCP<const CrsMatrix> sparse(const CrsMatrix& A) const {
    CrsMatrix AT(A.getRowMap(), 0);
    Tpetra::MatrixMatrix::Multiply(A, false, *T_, false, AT);
    auto P = Teuchos::rcp(new CrsMatrix(coords_, 0));
    Tpetra::MatrixMatrix::Multiply(*T_, true, AT, false, *P);
    return P;
  }
  const CrsMatrix* T_ = nullptr;  ///< formed (no B)
  Teuchos::RCP<const Map> coords_;
  Teuchos::RCP<const MultiVector> B_;
  std::vector<Row> C_;
  std::vector<GlobalOrdinal> cols_;  ///< the coordinates C reaches
  Teuchos::RCP<const Map> small_;
};

Teuchos::RCP<const CrsMatrix> addScaled(const Teuchos::RCP<const CrsMatrix>& acc, double c,
                                        const Teuchos::RCP<const CrsMatrix>& P) {
  if (acc.is_null()) {
    if (c == 1.0) return P;
    return Tpetra::MatrixMatrix::add(c, false, *P, 0.0, false, *P);
  }
  return Tpetra::MatrixMatrix::add(1.0, false, *acc, c, false, *P);
}

Teuchos::RCP<const CrsMatrix> zeroMatrix(const Teuchos::RCP<const Map>& map) {
  auto Z = Teuchos::rcp(new CrsMatrix(map, 0));
  Z->fillComplete(map, map);
  return Z;
}

/// A 6 x 6 element matrix as a CrsMatrix on `map` (all rows on rank 0).
Teuchos::RCP<const CrsMatrix> smallMatrix(const Teuchos::RCP<const Map>& map, const fem::ElementMatrix& E) {
  std::vector<Row> rows(map->getNodeNumElements());
  for (std::size_t l = 0; l < rows.size(); ++l) {
    const auto i = map->getGlobalElement(static_cast<LocalOrdinal>(l));
    for (int j = 0; j < E.n; ++j)
      if (E(static_cast<int>(i), j) != 0.0) rows[l].push_back({j, E(static_cast<int>(i), j)});
  }
  return fromRows(map, rows, map, map);
}

DenseMatrix toDense(const CrsMatrix& A) {
  const auto n = static_cast<int>(A.getGlobalNumRows());
  std::vector<double> mine(static_cast<std::size_t>(n) * n, 0.0), all(mine.size(), 0.0);
  const auto& rowMap = *A.getRowMap();
  const auto& colMap = *A.getColMap();
  Teuchos::Array<LocalOrdinal> c;
  Teuchos::Array<double> v;
  for (LocalOrdinal l = 0; l < static_cast<LocalOrdinal>(rowMap.getNodeNumElements()); ++l) {
    const std::size_t k = A.getNumEntriesInLocalRow(l);
    c.resize(k), v.resize(k);
    std::size_t got = 0;
    A.getLocalRowCopy(l, c(), v(), got);
    const auto i = rowMap.getGlobalElement(l);
    for (std::size_t e = 0; e < got; ++e) mine[i + static_cast<std::size_t>(n) * colMap.getGlobalElement(c[e])] += v[e];
  }
  Teuchos::reduceAll(*rowMap.getComm(), Teuchos::REDUCE_SUM, static_cast<int>(mine.size()), mine.data(), all.data());
  DenseMatrix D(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) D(i, j) = all[i + static_cast<std::size_t>(n) * j];
  return D;
}

}  // namespace

std::vector<Teuchos::ParameterList> sameReduction(const AssembledStructure& structure, const std::string& basis,
                                                  int vectors) {
  std::vector<Teuchos::ParameterList> red;
  for (std::size_t q = 0; q < structure.numSubstructures(); ++q) {
    Teuchos::ParameterList r("Reduction");
    r.set("Basis", basis);
    if (basis == "Partitioned") {  // its size follows a cut-off: the count is that cut-off in Hz (theory §18)
      r.set("Cutoff Frequency", static_cast<double>(vectors));
      red.push_back(r);
      continue;
    }
    // Never more than the substructure's free DOFs (a small hub beside a
    // large blade): the same count elsewhere.
    long long count = vectors;
    if (const auto* sub = structure.assembled(q))
      count = std::min<long long>(count, sub->dofs().rows() - static_cast<long long>(structure.parts()[q]->held.size()));
    r.set("Vectors", static_cast<int>(std::max<long long>(count, 0)));
    red.push_back(r);
  }
  return red;
}

long long SynthesizedStructure::size() const { return static_cast<long long>(map_->getGlobalNumElements()); }

SynthesizedStructure SynthesizedStructure::synthesize(const AssembledStructure& structure, bool truth) {
  std::vector<Teuchos::ParameterList> reductions;
  for (const auto& p : structure.parts()) {
    Teuchos::ParameterList r = p->spec.reduction;
    if (truth) r.set("Basis", std::string("Full"));
    reductions.push_back(r);
  }
  return synthesize(structure, reductions);
}

namespace {
// What a substructure's basis holds: its attachment, and per child the rows
// the child attaches to with their generalised forces (§11.3).
reduction::SubstructureBoundary substructureBoundary(const std::vector<std::shared_ptr<AssembledStructure::Part>>& parts,
                                                     std::size_t k) {
  const auto& p = *parts[k];
  reduction::SubstructureBoundary b;
  b.held = p.held;
  // A child held by supports of its own besides its attachment (a Boolean
  // child's constraint modes are static shapes with its supports already).
  if (p.ownSupports && p.parent >= 0 && !p.boolean()) b.supportedAttachment = p.point;
  for (int c : p.children) {
    std::set<GlobalOrdinal> rows;
    const auto& Hc = parts[c]->Hrows;
    std::vector<std::vector<std::pair<GlobalOrdinal, double>>> loads(Hc.size());
    for (std::size_t a = 0; a < Hc.size(); ++a)
      for (auto [g, v] : Hc[a]) rows.insert(g), loads[a].push_back({g, v});
    b.interfaces.emplace_back(rows.begin(), rows.end());
    b.interfaceLoads.push_back(loads);
  }
  return b;
}
}  // namespace

namespace {
/// Modal damping of a reduced substructure (theory §13.1): with its basis V
/// M-orthonormal, the Caughey damping 2 zeta (V^T K V)^(1/2) of its own
/// coordinates eta (rows offset .. offset + k of q), which is diag(2 zeta
/// w_j) when V holds the fixed-interface modes (w_j their frequencies) and
/// gives every mode of the substructure's reduced model, at rest and held
/// at its attachment, the ratio zeta. K is the stiffness at rest; the
/// coupling with the attachment coordinates gets no damping (an
/// approximation, like modal damping itself). `block` gets D_eta (k x k,
/// column-major, on every rank) for the error estimates' lift of its force
/// (theory §11.8). Collective.
Teuchos::RCP<const CrsMatrix> modalDamping(const substructure::Substructure& sub, const reduction::RitzBasis& basis,
                                           GlobalOrdinal offset, double zeta, const Teuchos::RCP<const Map>& qMap,
                                           std::vector<double>& block) {
  const int k = basis.size();
  DenseMatrix Kr(k, k);
  if (k > 0) {
    MultiVector KV(sub.map(), static_cast<std::size_t>(k));
    sub.apply(substructure::Matrix::K, *basis.vectors, KV);
    std::vector<double> local(static_cast<std::size_t>(k) * k, 0.0), global(local.size(), 0.0);
    const auto V = basis.vectors->getLocalViewHost(Tpetra::Access::ReadOnly);
    const auto W = KV.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i)
        for (std::size_t l = 0; l < V.extent(0); ++l) local[static_cast<std::size_t>(j) * k + i] += V(l, i) * W(l, j);
    Teuchos::reduceAll(*sub.map()->getComm(), Teuchos::REDUCE_SUM, k * k, local.data(), global.data());
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) Kr(i, j) = 0.5 * (global[static_cast<std::size_t>(j) * k + i] + global[static_cast<std::size_t>(i) * k + j]);
  }
  // (V^T K V)^(1/2) by its eigen-decomposition (symmetric, >= 0 to rounding).
  std::vector<double> w(std::max(k, 1)), work(std::max(1, 4 * k));
  int info = 0;
  if (k > 0)
    Teuchos::LAPACK<int, double>().SYEV('V', 'U', k, Kr.values(), Kr.stride(), w.data(), work.data(),
                                        static_cast<int>(work.size()), &info);
  TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError,
                             "synthesis: modal damping of '" << sub.name() << "': LAPACK dsyev info " << info);
  block.assign(static_cast<std::size_t>(k) * k, 0.0);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      double d = 0.0;
      for (int e = 0; e < k; ++e) d += Kr(i, e) * std::sqrt(std::max(w[e], 0.0)) * Kr(j, e);
      block[i + static_cast<std::size_t>(j) * k] = 2.0 * zeta * d;
    }
  std::vector<Row> rows(qMap->getNodeNumElements());
  for (std::size_t l = 0; l < rows.size(); ++l) {
    const GlobalOrdinal g = qMap->getGlobalElement(static_cast<LocalOrdinal>(l));
    if (g < offset || g >= offset + k) continue;
    const int i = static_cast<int>(g - offset);
    for (int j = 0; j < k; ++j)
      if (const double d = block[i + static_cast<std::size_t>(j) * k]; d != 0.0) rows[l].push_back({offset + j, d});
  }
  return fromRows(qMap, rows, qMap, qMap);
}
}  // namespace

/// The projected matrices of synthesize as they accumulate, part by part.
struct SynthesizedStructure::Sums {
  /// The parts some copy takes its basis from, and their B^T A B (with the
  /// rigid rows stiffness() zeroed) for the copies' congruences (§15.2).
  std::set<std::size_t> prototypes;
  struct Small {
    std::vector<double> S;
    int rigidZeroed = 0;
  };
  std::map<std::pair<std::size_t, substructure::Matrix>, Small> ofPrototype;
  Teuchos::RCP<const CrsMatrix> M, K0;
  Teuchos::RCP<const CrsMatrix> D;  ///< damping (null until a damped part is met)
  std::vector<Teuchos::RCP<const CrsMatrix>> G;  ///< per speed parameter
  std::vector<Teuchos::RCP<const CrsMatrix>> N;  ///< circulatory, per speed parameter (theory §13.1)
  std::map<std::pair<int, int>, Teuchos::RCP<const CrsMatrix>> K2;
  /// The same sums' Full substructures, assembled monolithically
  /// (MonolithicSum.hpp): added to the above in finishMatrices.
  detail::MonolithicSum fullM, fullK0, fullD;
  std::vector<detail::MonolithicSum> fullG, fullN;
  std::map<std::pair<int, int>, detail::MonolithicSum> fullK2;
};

/// What depends on a substructure's matrices and held rows but not on its
/// basis: built once (on first use, collectively) and shared by copies of
/// the synthesis and by later syntheses of the same assembled structure
/// (synthesize's `previous`), so that neither the error estimates of every
/// mode, nor a second call, nor an enrichment step factorises again.
struct SynthesizedStructure::Factorisations {
  explicit Factorisations(std::size_t n)
      : flexibility(n), flexibilityFlops(n, 0.0), constraintModes(n), heldK(n), heldM(n),
        turnedImage(n, -1) {}
  /// K_a,s with its attachment held, factored (the estimates' flexibility, §11.8).
  std::vector<std::shared_ptr<const reduction::StaticCorrection>> flexibility;
  /// Its factorisation's flops, kept when it is released: the coverage's
  /// count of K_a - w^2 M_a (the same pattern) forecasts its own with it.
  std::vector<double> flexibilityFlops;
  /// A Boolean child's static constraint modes (reduced bases only).
  std::vector<Teuchos::RCP<MultiVector>> constraintModes;
  /// K_a, M_a with the attachment held, and the coverage Sturm counts made
  /// with them, per (part, cut-off).
  std::vector<Teuchos::RCP<const CrsMatrix>> heldK, heldM;
  std::map<std::pair<std::size_t, double>, SparseInertia> counts;
  /// A copy's K and M are its prototype's turned (1), not (0), not yet known (-1).
  std::vector<int> turnedImage;
};

SynthesizedStructure SynthesizedStructure::synthesize(const AssembledStructure& structure,
                                                      const std::vector<Teuchos::ParameterList>& reductions,
                                                      ReductionSchedule schedule, const SynthesizedStructure* previous) {
  const auto t0 = Clock::now();
  const auto& parts = structure.parts();
  CMS_INPUT_CHECK(reductions.size() != parts.size(), "synthesis: " << reductions.size() << " reduction lists for "
                                                                   << parts.size() << " substructures");
  SynthesizedStructure out;
  out.structure_ = std::make_shared<AssembledStructure>(structure);
  // Only a synthesis of the same assembled parts has anything to give.
  if (previous != nullptr && previous->structure_->parts() != parts) previous = nullptr;
  out.factorisations_ = previous != nullptr ? previous->factorisations_ : std::make_shared<Factorisations>(parts.size());
  // 1. Bases (each substructure independently: §11.3).
  out.buildBases(reductions, schedule, previous);
  out.basesSeconds_ = since(t0);
  // 2. Coordinates q.
  const auto offset = out.layoutCoordinates();
  out.offsets_.assign(offset.begin(), offset.end());
  // 3. Interface transforms and projections, parents first (a child's
  // attachment motion reads its parent's transform).
  Sums sums;
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (structure.prototypeOf(k) != k) sums.prototypes.insert(structure.prototypeOf(k));
  sums.G.resize(structure.speeds().size());
  sums.fullG.assign(structure.speeds().size(), detail::MonolithicSum(-1.0));
  sums.N.resize(structure.speeds().size());
  sums.fullN.assign(structure.speeds().size(), detail::MonolithicSum(-1.0));
  out.T_.resize(parts.size());
  out.B_.resize(parts.size());
  out.C_.resize(parts.size());
  out.rotations_.assign(parts.size(), {});
  out.modalDamping_.assign(parts.size(), {});
  for (std::size_t k = 0; k < parts.size(); ++k) {
    bool moves = false;
    const auto A = out.attachmentMotion(k, moves);
    if (parts[k]->sub) out.projectSubstructure(k, A, moves, offset[k], sums);
    else out.projectRigidRotor(k, A, offset[k], sums);
  }
  // 4. The structure's matrices, exactly symmetric.
  out.finishMatrices(sums);
  out.seconds_ = since(t0);
  return out;
}

namespace {
using detail::asksBasis;

/// Whether copy k's K and M are its prototype's turned (detail::
/// operatorsAreTurned), asked once per assembled structure: `known` caches
/// it (1 yes, 0 no, -1 not yet). Collective the first time.
bool operatorsTurned(const AssembledStructure& structure, std::size_t k, std::vector<int>& known) {
  if (known[k] < 0) {
    const auto& parts = structure.parts();
    const std::size_t q = structure.prototypeOf(k);
    // A copy applying its prototype's matrices turned has them by construction.
    if (!parts[k]->sub->matricesFormed()) return (known[k] = 1) == 1;
    known[k] = detail::operatorsAreTurned(*parts[q]->sub, *parts[k]->sub,
                                          turnFromPrototype(*parts[k]->spec.copy, *parts[q]->spec.copy))
                   ? 1
                   : 0;
  }
  return known[k] == 1;
}
}  // namespace

/// Step 1 of synthesize: every substructure's basis and its report, reused
/// from `previous` where its "Reduction" list is unchanged; the others on
/// the schedule.
void SynthesizedStructure::buildBases(const std::vector<Teuchos::ParameterList>& requested, ReductionSchedule schedule,
                                      const SynthesizedStructure* previous) {
  const auto& parts = structure_->parts();
  const auto comm = structure_->comm();
  const int rank = comm->getRank(), nranks = comm->getSize();
  bases_.assign(parts.size(), reduction::RitzBasis());
  reports_.assign(parts.size(), SubstructureReduction());
  // The copies of a "Copies: N" item are truncated alike: each takes its
  // prototype's list, and (below) its basis turned (theory §15).
  std::vector<Teuchos::ParameterList> own(requested);
  std::vector<bool> turned(parts.size(), false);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const std::size_t p = structure_->prototypeOf(k);
    own[k] = requested[p];
    turned[k] = p != k && parts[k]->sub && !asksBasis(own[k], "Full");
    // A copy applying its prototype's matrices turned (theory §15.2) whose
    // basis is not turned here, or whose Boolean interface's constraint
    // modes factor its K, has them formed, for good (collective).
    if (parts[k]->sub && !parts[k]->sub->matricesFormed() && (!turned[k] || parts[k]->boolean()))
      parts[k]->sub = parts[k]->sub->formed();
  }
  const std::vector<Teuchos::ParameterList>& reductions = own;
  reductionLists_ = own;
  std::vector<bool> reused(parts.size(), false);
  if (previous != nullptr)
    for (std::size_t k = 0; k < parts.size(); ++k)
      if (parts[k]->sub && Teuchos::haveSameValuesSorted(previous->reductionLists_[k], reductions[k])) {
        bases_[k] = previous->bases_[k];
        reports_[k] = previous->reports_[k];
        reports_[k].adoptedPrestressFactor = false;  // nothing factored or adopted by this synthesis
        reports_[k].estimatesAdoptedPrestressFactor = false;
        reused[k] = true;
      }
  auto boundaryOf = [&](std::size_t k) { return substructureBoundary(parts, k); };
  auto report = [&](std::size_t k) {
    const auto& p = *parts[k];
    SubstructureReduction& rep = reports_[k];
    rep.basis = bases_[k].kind;
    rep.physicalDofs = p.sub->dofs().rows();
    rep.attachmentDofs = static_cast<int>(p.held.size());
    rep.labels = bases_[k].labels;
    rep.dropped = bases_[k].dropped;
    rep.eigensolverReport = bases_[k].eigensolverReport;
    rep.seconds = bases_[k].seconds;
    rep.adoptedPrestressFactor = bases_[k].adoptedFactor;
    rep.basisBytes = bases_[k].vectors.is_null()
                         ? 0.0
                         : 8.0 * static_cast<double>(bases_[k].vectors->getGlobalLength()) *
                               static_cast<double>(bases_[k].vectors->getNumVectors());
  };
  // The schedule: which rank reduces each substructure whole (-1: all ranks
  // together). Largest first onto the least-loaded rank, the cost taken as
  // n^1.5 (between the n^2 flops of a 3D factorisation and the n of the
  // solves); the same on every rank.
  std::vector<int> owner(parts.size(), -1);
  if (schedule == ReductionSchedule::Concurrent && nranks > 1) {
    // A substructure that adopts its kept prestress factorisation stays on
    // its distributed matrix, the one factored (theory §11.4): its basis is
    // then solves with a factor made already, where gathered it would factor
    // again on one rank (and so would its error estimates). The same
    // decision on every rank: the factors kept are.
    auto adopts = [&](std::size_t k) {
      if (!parts[k]->stiffnessFactor) return false;
      auto boundary = boundaryOf(k);
      boundary.stiffnessFactor = parts[k]->stiffnessFactor;
      return reduction::adoptsStiffnessFactor(*parts[k]->sub, boundary, reductions[k]);
    };
    std::vector<std::pair<double, std::size_t>> work;
    for (std::size_t k = 0; k < parts.size(); ++k)
      if (parts[k]->sub && !reused[k] && !turned[k] && !adopts(k) && !asksBasis(reductions[k], "Full") &&
          !asksBasis(reductions[k], "Partitioned"))  // spreads its own parts over the ranks
        work.push_back({std::pow(static_cast<double>(parts[k]->sub->dofs().rows()), 1.5), k});
    std::sort(work.begin(), work.end(), [](const auto& a, const auto& b) {
      return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    std::vector<double> load(nranks, 0.0);
    if (work.size() > 1)
      for (const auto& [cost, k] : work) {
        const int r = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
        owner[k] = r;
        load[r] += cost;
      }
  }
  const bool concurrent = std::any_of(owner.begin(), owner.end(), [](int o) { return o >= 0; });
  // The prestress solves' factorisations kept for the reductions (theory
  // §11.4). K with the attachment held is also the error estimates'
  // flexibility (§11.8): a factor of it serves them, whatever the basis
  // holds (a Craig-Bampton hub holds its point interfaces too, and factors
  // another matrix), instead of the estimates factoring K again. Then one
  // reduced here, on its own distributed matrix, adopts its own; the rest
  // (gathered onto one rank, turned, reused) let go of theirs now.
  for (std::size_t k = 0; k < parts.size(); ++k) {
    auto& kept = parts[k]->stiffnessFactor;
    // (A Full basis has no estimate: nothing to serve.)
    if (kept && !asksBasis(reductions[k], "Full") && !reused[k] && !turned[k] && !factorisations_->flexibility[k]) {
      reduction::SubstructureBoundary own;
      own.held = parts[k]->held;  // as flexibility(k) holds it
      if (auto f = reduction::StaticCorrection::adopting(*parts[k]->sub, own, kept)) {
        factorisations_->flexibility[k] = std::move(f);
        reports_[k].estimatesAdoptedPrestressFactor = true;
      }
    }
    if (reused[k] || turned[k] || owner[k] >= 0) kept.reset();
  }
  if (concurrent) {
    const auto self = comm->split(rank, 0);
    // a. Every such substructure gathered onto its rank (collective).
    std::vector<std::optional<substructure::Substructure>> local(parts.size());
    for (std::size_t k = 0; k < parts.size(); ++k)
      if (owner[k] >= 0) {
        auto g = parts[k]->sub->gatheredTo(owner[k], self);
        if (owner[k] == rank) local[k] = std::move(g);
      }
    // b. Each rank reduces its own, with no communication between ranks.
    // A failure is kept and raised on every rank in c., in tree order.
    std::vector<int> failure(parts.size(), 0);  // 1 input, 2 numerical, 3 other
    std::vector<std::string> message(parts.size());
    std::vector<std::vector<double>> estimates(parts.size());
    for (std::size_t k = 0; k < parts.size(); ++k) {
      if (owner[k] != rank) continue;
      try {
        bases_[k] = reduction::buildRitzBasis(*local[k], boundaryOf(k), reductions[k]);
        bases_[k].flexibility.reset();  // on this rank's gathered copy: not the distributed matrix
        if (!bases_[k].full && bases_[k].size() > 0) estimates[k] = reduction::estimateFrequencies(*local[k], bases_[k]);
      } catch (const InputError& e) {
        failure[k] = 1, message[k] = e.what();
      } catch (const NumericalError& e) {
        failure[k] = 2, message[k] = e.what();
      } catch (const std::exception& e) {
        failure[k] = 3, message[k] = e.what();
      }
      local[k].reset();
    }
    // c. What each rank found, to every rank; the bases onto the
    // substructures' own distributed maps.
    for (std::size_t k = 0; k < parts.size(); ++k) {
      if (owner[k] < 0) continue;
      auto& b = bases_[k];
      std::vector<std::string> text{b.kind, b.eigensolverReport, message[k]};
      text.insert(text.end(), b.labels.begin(), b.labels.end());
      text.insert(text.end(), b.dropped.begin(), b.dropped.end());
      std::vector<double> numbers{static_cast<double>(failure[k]), b.full ? 1.0 : 0.0, b.seconds,
                                  static_cast<double>(b.size()), static_cast<double>(b.labels.size()),
                                  static_cast<double>(b.dropped.size())};
      numbers.insert(numbers.end(), estimates[k].begin(), estimates[k].end());
      detail::broadcastFrom(*comm, owner[k], numbers, text);
      failure[k] = static_cast<int>(numbers[0]);
      if (failure[k] == 1) throw InputError(text[2]);
      if (failure[k] == 2) throw NumericalError(text[2]);
      if (failure[k] == 3) throw std::runtime_error(text[2]);
      const int ncols = static_cast<int>(numbers[3]);
      const auto nl = static_cast<std::size_t>(numbers[4]), nd = static_cast<std::size_t>(numbers[5]);
      auto V = scatterFromRank(b.vectors, owner[k], ncols, parts[k]->sub->map());
      b.kind = text[0];
      b.eigensolverReport = text[1];
      b.labels.assign(text.begin() + 3, text.begin() + 3 + static_cast<long>(nl));
      b.dropped.assign(text.begin() + 3 + static_cast<long>(nl), text.begin() + 3 + static_cast<long>(nl + nd));
      b.full = numbers[1] != 0.0;
      b.seconds = numbers[2];
      b.vectors = ncols > 0 ? V : Teuchos::null;
      reports_[k].frequencyEstimates.assign(numbers.begin() + 6, numbers.end());
    }
  }
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const auto& p = *parts[k];
    SubstructureReduction& rep = reports_[k];
    rep.name = p.spec.name;
    rep.kind = toString(p.spec.kind);
    if (!p.sub) {
      rep.basis = "rigid";
      rep.physicalDofs = 6;
      continue;
    }
    if (reused[k]) continue;
    if (turned[k]) {
      // Its prototype, earlier in tree order, has its basis by now.
      const std::size_t q = structure_->prototypeOf(k);
      const auto turn = turnFromPrototype(*p.spec.copy, *parts[q]->spec.copy);
      std::string why;
      // A copy the assembly turned: K and M checked on a random vector (the
      // same check the error estimates' shared factorisations ask, cached).
      const bool operators = p.matricesTurned && operatorsTurned(*structure_, k, factorisations_->turnedImage);
      if (auto b = detail::turnedBasis(*parts[q]->sub, bases_[q], *p.sub, turn, operators, why)) {
        bases_[k] = std::move(*b);
        report(k);
        rep.turnedFrom = parts[q]->spec.name;
        rep.adoptedPrestressFactor = false;  // its prototype's flag came with the basis: it factored nothing
        rep.frequencyEstimates = reports_[q].frequencyEstimates;  // the same reduced K and M
        continue;
      }
      rep.notTurned = why;
      if (!p.sub->matricesFormed()) parts[k]->sub = p.sub->formed();  // reduced on its own (collective)
    }
    if (owner[k] < 0) {
      auto boundary = boundaryOf(k);
      boundary.stiffnessFactor = std::move(parts[k]->stiffnessFactor);  // the basis keeps it if it adopts it
      parts[k]->stiffnessFactor.reset();
      // One it will not adopt is freed before it factors its own.
      if (!reduction::adoptsStiffnessFactor(*p.sub, boundary, reductions[k])) boundary.stiffnessFactor.reset();
      bases_[k] = reduction::buildRitzBasis(*p.sub, boundary, reductions[k]);
      if (!bases_[k].full && bases_[k].size() > 0)
        rep.frequencyEstimates = reduction::estimateFrequencies(*p.sub, bases_[k]);
    }
    report(k);
  }
}

/// Step 2 of synthesize: q = [w_OC, theta_C (free C)], then each part's own
/// coordinates in tree order; returns where each part's begin.
std::vector<GlobalOrdinal> SynthesizedStructure::layoutCoordinates() {
  const auto& parts = structure_->parts();
  std::vector<GlobalOrdinal> offset(parts.size(), 0);
  GlobalOrdinal n = structure_->freeFloating() ? 6 : 0;
  hubs_.clear();
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const auto& p = *parts[k];
    if (p.movingHub) {  // its attachment coordinates b first (theory §16.8)
      MovingHub hub;
      hub.part = k;
      hub.offset = n;
      hub.speedParameter = p.speedParam;
      hub.axis = fem::unit(p.spec.spin->axis);
      hubs_.push_back(hub);
      n += 6;
    }
    offset[k] = n;
    int own = p.spec.kind == SubstructureKind::Rigid && p.spec.rotor.spinCoordinate ? 1 : 0;
    if (p.sub) own = bases_[k].full ? static_cast<int>(p.sub->dofs().rows() - p.held.size()) : bases_[k].size();
    reports_[k].coordinates = own;
    n += own;
  }
  CMS_INPUT_CHECK(n == 0, "synthesis: the structure has no coordinates (every basis is empty)");
  map_ = Teuchos::rcp(new Map(n, 0, structure_->comm()));
  return offset;
}

/// Step 3a: part k's attachment coordinates a_k = H_k T_parent q as rows over
/// q (rows of T_parent gathered to every rank; a free C's a is its six
/// rigid-body coordinates); `moves` says whether any is nonzero.
std::vector<SynthesizedStructure::SparseRow> SynthesizedStructure::attachmentMotion(std::size_t k, bool& moves) {
  const auto& p = *structure_->parts()[k];
  std::vector<Row> A(p.floating ? 6 : p.Hrows.size());
  moves = false;
  if (p.floating) {
    for (int a = 0; a < 6; ++a) A[a] = {{a, 1.0}};
    moves = true;
  } else if (p.parent >= 0) {
    std::set<GlobalOrdinal> need;
    for (const auto& h : p.Hrows)
      for (auto [g, v] : h) need.insert(g);
    const auto Tp = transformRows(p.parent, need);
    for (std::size_t a = 0; a < A.size(); ++a) {
      std::vector<std::pair<double, const Row*>> terms;
      for (auto [g, v] : p.Hrows[a]) {
        auto it = Tp.find(g);
        if (it != Tp.end()) terms.push_back({v, &it->second});
      }
      A[a] = combine(terms);
      moves = moves || !A[a].empty();
    }
  }
  if (p.movingHub) {  // the parent's motion kept apart; the rotor moves with its own b (§16.8)
    auto hub = std::find_if(hubs_.begin(), hubs_.end(), [&](const MovingHub& h) { return h.part == k; });
    for (const auto& row : A) {
      hub->parentMotion.emplace_back();
      for (auto [g, v] : row) {
        CMS_INPUT_CHECK(std::any_of(hubs_.begin(), hubs_.end(), [&](const MovingHub& h) {
                          return g >= h.offset && g < h.offset + 6;
                        }),
                        "synthesis: the rotor '" << p.spec.name
                                                 << "' on a moving attachment hangs on another such rotor "
                                                    "(nested periodic rotors are not supported)");
        hub->parentMotion.back().push_back({static_cast<long long>(g), v});
      }
    }
    for (int a = 0; a < 6; ++a) A[a] = {{static_cast<GlobalOrdinal>(hub->offset + a), 1.0}};
    moves = true;
  }
  return A;
}

/// Step 3b for a rigid rotor: its DOFs are a itself, and its spin angle if
/// free; its 6 x 6 (7 x 7) matrices projected sparsely.
void SynthesizedStructure::projectRigidRotor(std::size_t k, const std::vector<SparseRow>& A, GlobalOrdinal offset,
                                             Sums& sums) {
  const auto& p = *structure_->parts()[k];
  const auto comm = structure_->comm();
  const int nr = p.rotor.M.n;
  auto rmap = Teuchos::rcp(new Map(nr, comm->getRank() == 0 ? nr : 0, 0, comm));
  std::vector<Row> rows(rmap->getNodeNumElements());
  for (std::size_t l = 0; l < rows.size(); ++l) {
    const auto g = rmap->getGlobalElement(static_cast<LocalOrdinal>(l));
    rows[l] = g < 6 ? A[g] : Row{{offset, 1.0}};
  }
  T_[k] = fromRows(rmap, rows, map_, rmap);
  const Projection project(*T_[k]);
  sums.M = addScaled(sums.M, 1.0, project(*smallMatrix(rmap, p.rotor.M)));
  for (const auto& [i, Gi] : p.rotor.G) sums.G[i] = addScaled(sums.G[i], 1.0, project(*smallMatrix(rmap, Gi)));
  for (const auto& [i, j, Kij] : p.rotor.K)
    sums.K2[{i, j}] = addScaled(sums.K2[{i, j}], 1.0, project(*smallMatrix(rmap, Kij)));
}

/// Step 3b for an elastic part: u_s = X_s a_s + V_s eta_s (or its Full
/// form), T_s, and T_s^T A T_s of each of its matrices added to the sums.
void SynthesizedStructure::projectSubstructure(std::size_t k, const std::vector<SparseRow>& A, bool hasA,
                                               GlobalOrdinal offset, Sums& sums) {
  const auto& p = *structure_->parts()[k];
  const auto& sub = *p.sub;
  const auto& t = sub.dofs();
  const auto smap = sub.map();
  const auto nodeOf = t.rowNodes();
  const std::size_t nloc = smap->getNodeNumElements();
  std::vector<Row> rows(nloc);
  const auto& basis = bases_[k];
  std::vector<Teuchos::ArrayRCP<const double>> cols;
  if (!basis.full)
    for (int j = 0; j < basis.size(); ++j) cols.push_back(basis.vectors->getData(j));
  // A Boolean interface's motion enters the child through its static
  // constraint modes (reduced) or by injection on the shared rows (Full).
  std::vector<Teuchos::ArrayRCP<const double>> psi;
  std::map<GlobalOrdinal, int> injected;
  if (p.boolean()) {
    std::vector<GlobalOrdinal> unit;
    for (auto [node, comp] : p.booleanDofs) unit.push_back(static_cast<GlobalOrdinal>(t.row(node, comp)));
    if (basis.full) {
      for (std::size_t a = 0; a < unit.size(); ++a)
        if (unit[a] >= 0) injected[unit[a]] = static_cast<int>(a);
    } else {
      auto& Psi = factorisations_->constraintModes[k];  // independent of the basis: made once
      if (Psi.is_null()) Psi = reduction::constraintModes(sub, p.held, unit);
      for (std::size_t a = 0; a < unit.size(); ++a) psi.push_back(Psi->getData(a));
    }
  }
  // A Full basis on a substructure with a distributing (RigidFit)
  // attachment takes the absolute displacements of its free rows as
  // coordinates, and only the held rows follow the parent: the same space
  // as rigid motion plus relative displacement, so the same model, but T
  // stays as sparse as the mesh, where the rigid part on every row would
  // couple each DOF to every parent DOF of the fit (a dense n_s x n_face
  // block: 10^9 entries at 5e5 DOFs). Elsewhere the relative (floating
  // frame) form is kept: it is better conditioned when the parent is much
  // stiffer (at a stiffness ratio of 1e6 the absolute form lost two more
  // digits in the truth's lowest frequency, theory §11.2). Never for a free
  // structure, whose first six coordinates must stay a rigid motion of the
  // whole (K0 is made exactly zero there, below).
  std::set<GlobalOrdinal> parentRows;
  for (const auto& h : p.Hrows)
    for (auto [g, v] : h) parentRows.insert(g);
  const bool absolute = basis.full && !p.boolean() && !structure_->freeFloating() && parentRows.size() > 6;
  // The factors T = B C of a reduced substructure (Projection).
  const int na = !basis.full && hasA ? static_cast<int>(A.size()) : 0;
  Teuchos::RCP<MultiVector> B;
  std::vector<Row> C;
  std::vector<Teuchos::ArrayRCP<double>> bcol;
  if (!basis.full && na + basis.size() > 0) {
    B = Teuchos::rcp(new MultiVector(smap, static_cast<std::size_t>(na + basis.size())));
    for (int j = 0; j < na + basis.size(); ++j) bcol.push_back(B->getDataNonConst(j));
    for (int a = 0; a < na; ++a) C.push_back(A[a]);
    for (int j = 0; j < basis.size(); ++j) C.push_back(Row{{offset + static_cast<GlobalOrdinal>(j), 1.0}});
  }
  // For the monolithic sum of a Full basis (MonolithicSum.hpp): the same
  // rows with its attachment motion a = A q kept as six virtual
  // coordinates n + a, expanded through A after the product. A RigidFit's
  // held rows are rank 6 (X_h A); written out, each carries every face
  // coordinate of the parent, and the face block T_h^T K_hh T_h costs
  // n_held n_face^2 instead of 36 n_face^2.
  const bool virtualMotion = basis.full && hasA && !p.boolean();
  const GlobalOrdinal nq = static_cast<GlobalOrdinal>(map_->getGlobalNumElements());
  std::vector<Row> rowsV(virtualMotion ? nloc : 0);
  for (std::size_t l = 0; l < nloc; ++l) {
    const auto g = smap->getGlobalElement(static_cast<LocalOrdinal>(l));
    std::vector<std::pair<double, const Row*>> terms;
    Row own, virt;
    if (hasA && p.boolean()) {
      if (basis.full) {
        const auto it = injected.find(g);
        if (it != injected.end() && !A[it->second].empty()) terms.push_back({1.0, &A[it->second]});
      } else {
        for (std::size_t a = 0; a < psi.size(); ++a) {
          if (psi[a][l] != 0.0 && !A[a].empty()) terms.push_back({psi[a][l], &A[a]});
          if (na > 0) bcol[a][l] = psi[a][l];
        }
      }
    } else if (hasA && (!absolute || std::binary_search(p.held.begin(), p.held.end(), g))) {
      const auto nd = nodeOf[g];
      const fem::Vec3 r{t.coordinates[3 * nd] - p.point[0], t.coordinates[3 * nd + 1] - p.point[1],
                        t.coordinates[3 * nd + 2] - p.point[2]};
      const auto x = detail::rigidRow(r, static_cast<int>(t.components[g]));
      for (int a = 0; a < 6; ++a) {
        if (x[a] != 0.0 && !A[a].empty()) terms.push_back({x[a], &A[a]});
        if (x[a] != 0.0 && !A[a].empty() && virtualMotion) virt.push_back({nq + a, x[a]});
        if (na > 0) bcol[a][l] = x[a];
      }
    }
    const bool isHeld = std::binary_search(p.held.begin(), p.held.end(), g);
    if (basis.full) {
      if (!isHeld) {
        const auto before = std::lower_bound(p.held.begin(), p.held.end(), g) - p.held.begin();
        own.push_back({offset + g - before, 1.0});
      }
    } else if (!isHeld) {
      for (std::size_t j = 0; j < cols.size(); ++j) {
        if (cols[j][l] != 0.0) own.push_back({offset + static_cast<GlobalOrdinal>(j), cols[j][l]});
        bcol[na + j][l] = cols[j][l];
      }
    }
    if (virtualMotion) {
      rowsV[l] = own;
      rowsV[l].insert(rowsV[l].end(), virt.begin(), virt.end());
    }
    if (B.is_null()) {
      terms.push_back({1.0, &own});
      rows[l] = combine(terms);
    }
  }
  // A reduced part's T = B C stays factored (transforms()): not formed.
  if (B.is_null()) T_[k] = fromRows(smap, rows, map_, smap);
  else B_[k] = B, C_[k] = C;
  Teuchos::RCP<const CrsMatrix> Tv = T_[k];
  std::vector<Row> motion;  // the virtual coordinates' rows over q
  if (virtualMotion) {
    auto wide = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(nq + 6), 0, map_->getComm()));
    Tv = fromRows(smap, rowsV, wide, smap);
    motion.assign(A.begin(), A.end());
  }
  bcol.clear();  // release the host views before B is read
  // c T^T A T added to a sum: a Full basis's by the monolithic assembly
  // (MonolithicSum.hpp), a reduced one's through its factors T = B C.
  const Projection project = B.is_null() ? Projection(*T_[k]) : Projection(map_, B, C);
  const bool full = basis.full;
  using substructure::Matrix;
  // A turned copy's B^T A B from its prototype's (theory §15.2), when
  // Q^T B_c = B_p D: no product with its matrices at all.
  const auto D = B.is_null() ? std::nullopt : copyRotation(k, *B, na, hasA && !p.boolean());
  if (D) rotations_[k] = *D;  // for its error estimates (residualFlexibilityNorms)
  const int rigid = hasA && !p.boolean() ? na : 0;
  reports_[k].projectedFromPrototype = D.has_value();  // until one matrix is projected itself
  const auto reduced = [&](Matrix a) -> Teuchos::RCP<const CrsMatrix> {
    const int r = a == Matrix::K && rigid > 0 && carriedRigidly(k) ? rigid : 0;
    const std::size_t q = structure_->prototypeOf(k);
    if (D) {
      const auto it = sums.ofPrototype.find({q, a});
      // (K: only when the prototype's rigid rows were all zeroed, as the
      // copy's then are: a mix of kept and zeroed ones would not turn.)
      if (it != sums.ofPrototype.end() && (r == 0 || it->second.rigidZeroed == r))
        return project.expand(congruence(*D, it->second.S));
    }
    reports_[k].projectedFromPrototype = false;
    auto S = project.small(sub, a, r);
    if (sums.prototypes.count(k)) {
      int zeroed = 0;  // the rigid rows stiffness() made zero
      const int nb = static_cast<int>(B->getNumVectors());
      for (int i = 0; i < r; ++i) {
        bool zero = true;
        for (int j = 0; j < nb; ++j) zero = zero && S[i + static_cast<std::size_t>(j) * nb] == 0.0;
        zeroed += zero;
      }
      sums.ofPrototype[{k, a}] = {S, zeroed};
    }
    return project.expand(S);
  };
  const auto addTo = [&](Teuchos::RCP<const CrsMatrix>& sum, detail::MonolithicSum& fullSum, Matrix a, double c) {
    if (full) fullSum.add(*Tv, *sub.matrix(a), c, nq, motion);
    else sum = addScaled(sum, c, B.is_null() ? project(sub, a) : reduced(a));
  };
  addTo(sums.M, sums.fullM, Matrix::M, 1.0);
  if (full) sums.fullK0.add(*Tv, *sub.K(), 1.0, nq, motion);
  else if (B.is_null()) sums.K0 = addScaled(sums.K0, 1.0, project.stiffness(sub, rigid));
  else sums.K0 = addScaled(sums.K0, 1.0, reduced(Matrix::K));
  // Damping (theory §13.1): the dampers' and Rayleigh D_s projected like
  // M; a modal ratio in the substructure's own coordinates.
  if (sub.has(Matrix::D)) addTo(sums.D, sums.fullD, Matrix::D, 1.0);
  if (sub.modalDampingRatio() > 0.0) {
    // Full by its own Reduction: refused. Full because every basis is (the
    // truth, a Full comparison): left out and said (modalDampingOmitted),
    // for the comparisons to refuse and the prestress solve to ignore.
    const bool ownFull = detail::asksBasis(p.spec.reduction, "Full");
    CMS_INPUT_CHECK(basis.full && ownFull,
                    "synthesis: substructure '" << sub.name() << "': a Modal Damping Ratio needs a reduced basis (its "
                                                << "modes' coordinates); a Full substructure has none: give it Rayleigh "
                                                << "Alpha / Beta");
    if (basis.full) modalDampingOmitted_.push_back(sub.name());
    else sums.D = addScaled(sums.D, 1.0, modalDamping(sub, basis, offset, sub.modalDampingRatio(), map_, modalDamping_[k]));
  }
  const auto K2Sum = [&](std::pair<int, int> ij) -> detail::MonolithicSum& { return sums.fullK2[ij]; };
  if (p.compound) {
    // Its own spin inside the spinning parent frame (theory §11.5).
    const auto& st = *p.stationary;
    if (full) sums.fullG[p.speedParam].add(*Tv, *st.G1(), 1.0, nq, motion);
    else sums.G[p.speedParam] = addScaled(sums.G[p.speedParam], 1.0, project(st, Matrix::G1));
    // Its material damping turns at its own rate relative to the frame.
    if (st.has(Matrix::N1)) {
      if (full) sums.fullN[p.speedParam].add(*Tv, *st.N1(), 1.0, nq, motion);
      else sums.N[p.speedParam] = addScaled(sums.N[p.speedParam], 1.0, project(st, Matrix::N1));
    }
    if (!st.KX1().is_null()) {
      const auto PX = full ? Teuchos::null : project(*st.KX1());
      for (auto [i, ci] : p.frame.coefficients) {
        const std::pair<int, int> ij{std::min(i, p.speedParam), std::max(i, p.speedParam)};
        if (full) K2Sum(ij).add(*Tv, *st.KX1(), ci, nq, motion);
        else sums.K2[ij] = addScaled(sums.K2[ij], ci, PX);
      }
    }
  }
  if (p.frame.spinning) {
    const bool hasG = sub.has(Matrix::G1), hasK2 = sub.has(Matrix::K2), hasN = sub.has(Matrix::N1);
    Teuchos::RCP<const CrsMatrix> PG, PK, PN;
    if (!full && hasG) PG = B.is_null() ? project(sub, Matrix::G1) : reduced(Matrix::G1);
    if (!full && hasK2) PK = B.is_null() ? project(sub, Matrix::K2) : reduced(Matrix::K2);
    if (!full && hasN) PN = B.is_null() ? project(sub, Matrix::N1) : reduced(Matrix::N1);
    for (auto [i, ci] : p.frame.coefficients) {
      if (hasG) {
        if (full) sums.fullG[i].add(*Tv, *sub.G1(), ci, nq, motion);
        else sums.G[i] = addScaled(sums.G[i], ci, PG);
      }
      // A stationary-frame rotor's material damping (theory §13.1): N =
      // Omega N1, projected like G.
      if (hasN) {
        if (full) sums.fullN[i].add(*Tv, *sub.N1(), ci, nq, motion);
        else sums.N[i] = addScaled(sums.N[i], ci, PN);
      }
      if (!hasK2) continue;
      for (auto [j, cj] : p.frame.coefficients) {
        if (j < i) continue;
        const double cij = i == j ? ci * cj : 2.0 * ci * cj;
        if (full) K2Sum({i, j}).add(*Tv, *sub.K2(), cij, nq, motion);
        else sums.K2[{i, j}] = addScaled(sums.K2[{i, j}], cij, PK);
      }
    }
  }
}


/// For copy k whose basis is its prototype's turned and whose matrices are
/// its prototype's applied turned (theory §15.2): D with Q^T B_k = B_q D,
/// so that B_k^T A_k B_k = D^T (B_q^T A_q B_q) D. D = blockdiag(M6, I): the
/// basis columns turn back exactly, and the attachment's rigid motions X_k
/// (about the copy's own point, which a parent face not symmetric about the
/// axis places off the prototype's turned) are X_q M6, a 6 x 6 change of
/// axes and reference point, found by least squares and accepted when
/// ||Q^T X_k - X_q M6||_F <= 1e3 eps ||X_k||_F (rounding of the turn and of
/// the copy's turned coordinates, which the assembly holds to 64 eps of the
/// structure's size). nullopt otherwise (the caller projects). Collective.
std::optional<std::vector<double>> SynthesizedStructure::copyRotation(std::size_t k, const MultiVector& B, int na,
                                                                      bool rigidColumns) const {
  const auto& parts = structure_->parts();
  const std::size_t q = structure_->prototypeOf(k);
  const auto& p = *parts[k];
  if (q == k || reports_[k].turnedFrom.empty() || p.sub->matricesFormed() || B_[q].is_null() || !p.spec.copy ||
      !parts[q]->spec.copy)
    return std::nullopt;
  const auto& Bq = *B_[q];
  const int nb = static_cast<int>(B.getNumVectors());
  if (static_cast<int>(Bq.getNumVectors()) != nb || (na > 0 && !rigidColumns) || na > nb) return std::nullopt;
  std::vector<double> D(static_cast<std::size_t>(nb) * nb, 0.0);
  for (int j = na; j < nb; ++j) D[j + static_cast<std::size_t>(j) * nb] = 1.0;
  if (na == 0) return D;
  const auto turn = turnFromPrototype(*p.spec.copy, *parts[q]->spec.copy);
  fem::Rotation back;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) back.R[i][j] = turn.R[j][i];
  const auto Xk = B.subCopy(Teuchos::Range1D(0, na - 1));
  const auto Xq = Bq.subCopy(Teuchos::Range1D(0, na - 1));
  const auto Y = substructure::turnedRows(*Xk, p.sub->dofs(), p.sub->map(), back);
  const auto M6 = detail::rigidMotionFit(*Xq, *Y);
  if (!M6) return std::nullopt;
  for (int j = 0; j < na; ++j)
    for (int i = 0; i < na; ++i) D[i + static_cast<std::size_t>(j) * nb] = (*M6)[i + static_cast<std::size_t>(j) * na];
  return D;
}

/// Step 4 of synthesize: the accumulated matrices made exactly symmetric
/// (G skew), a free structure's rigid-body stiffness made exactly zero.
void SynthesizedStructure::finishMatrices(Sums& sums) {
  // T^T (A T) is symmetric (G skew) in exact arithmetic, but rounding
  // leaves eps ||A|| ||t_i|| ||t_j|| in entry (i, j), which for smooth
  // vectors on a fine mesh is far above eps |t_i^T A t_j| (found at 1e4 DOFs
  // per substructure: 6e-10, past the dense solver's structure check). Keep
  // the exactly symmetric (skew) part, as the mathematics says.
  auto symmetric = [](const Teuchos::RCP<const CrsMatrix>& A, double sign) -> Teuchos::RCP<const CrsMatrix> {
    if (A.is_null()) return A;
    return Tpetra::MatrixMatrix::add(0.5, false, *A, 0.5 * sign, true, *A);
  };
  // The Full substructures' monolithic sum is exactly symmetric (skew) on
  // one rank by construction (its lower triangle mirrors its upper); the
  // export that adds the ranks' shares may round an entry and its mirror
  // differently, so on several ranks, as for any sum with reduced parts,
  // the symmetric part is taken.
  const auto comm = map_->getComm();
  const bool oneRank = comm->getSize() == 1;
  auto total = [&](const Teuchos::RCP<const CrsMatrix>& sum, detail::MonolithicSum& full,
                   double sign) -> Teuchos::RCP<const CrsMatrix> {
    const Teuchos::RCP<const CrsMatrix> F = full.empty(*comm) ? Teuchos::null : full.matrix(map_);
    if (sum.is_null()) return F.is_null() || oneRank ? F : symmetric(F, sign);
    if (F.is_null()) return symmetric(sum, sign);
    return symmetric(Tpetra::MatrixMatrix::add(1.0, false, *sum, 1.0, false, *F), sign);
  };
  // Before the sums below fold the reduced parts in: K is entrywise where
  // none of its parts is a projection (an element-assembled entry's
  // rounding is a few eps of its own magnitude; a projection's, of
  // B^T |K| B, which its cancellation can leave far above |B^T K B|).
  kEntrywise_ = sums.K0.is_null() && std::all_of(sums.K2.begin(), sums.K2.end(), [](const auto& t) {
                  return t.second.is_null();
                });
  M_ = total(sums.M, sums.fullM, 1.0);
  const auto K0 = total(sums.K0, sums.fullK0, 1.0);
  for (std::size_t i = 0; i < sums.G.size(); ++i) sums.G[i] = total(sums.G[i], sums.fullG[i], -1.0);
  for (std::size_t i = 0; i < sums.N.size(); ++i) sums.N[i] = total(sums.N[i], sums.fullN[i], -1.0);
  for (auto& [ij, F] : sums.fullK2) sums.K2[ij];  // every key, in the same order on every rank
  for (auto& [ij, Kij] : sums.K2) Kij = total(Kij, sums.fullK2[ij], 1.0);
  K0_ = K0.is_null() ? zeroMatrix(map_) : K0;
  if (structure_->freeFloating()) {
    // The elastic stiffness does no work on the rigid-body coordinates of a
    // free structure (K X = 0): made exact, because its rounding,
    // eps ||K||, would otherwise split the defective (Jordan) rigid-body
    // eigenvalues of a spinning free body by sqrt(eps ||K|| / ||K_T||)
    // (doc/theory.md §11.6).
    K0_ = holdDofs(*K0_, {0, 1, 2, 3, 4, 5}, 0.0);
  }
  G_ = sums.G;
  N_ = sums.N;
  D_ = total(sums.D, sums.fullD, 1.0);
  for (auto& [ij, Kij] : sums.K2) K2_.push_back({ij.first, ij.second, Kij});
}

eigen::SparseGyroscopicSystem SynthesizedStructure::system(const std::vector<double>& s) const {
  CMS_INPUT_CHECK(s.size() != structure_->speeds().size(),
                  "synthesis: " << s.size() << " speeds given, the structure has " << structure_->speeds().size());
  if (const auto why = structure_->steadySpinDefect(s); !why.empty()) throw InputError(why);
  eigen::SparseGyroscopicSystem sys;
  sys.M = M_;
  Teuchos::RCP<const CrsMatrix> G, K = K0_, N;
  for (std::size_t i = 0; i < G_.size(); ++i)
    if (!G_[i].is_null() && s[i] != 0.0) G = addScaled(G, s[i], G_[i]);
  for (std::size_t i = 0; i < N_.size(); ++i)
    if (!N_[i].is_null() && s[i] != 0.0) N = addScaled(N, s[i], N_[i]);
  for (const auto& t : K2_) {
    const double c = s[t.i] * s[t.j];
    if (c != 0.0) K = addScaled(K, c, t.K);
  }
  sys.G = G.is_null() ? zeroMatrix(map_) : G;
  sys.K = K;
  sys.D = D_;
  sys.N = N;
  return sys;
}

/// The structure's matrices gathered to every rank once, per speed piece.
struct SynthesizedStructure::DensePieces {
  DenseMatrix M, K0, D;
  /// Rows (and columns) of K0 that are exactly zero: a free structure's
  /// rigid-body coordinates (made so above), a free-turning rotor's angle.
  std::vector<int> unrestrained;
  std::vector<DenseMatrix> G;  ///< per speed parameter (0 x 0: none)
  std::vector<DenseMatrix> N;  ///< circulatory, per speed parameter (0 x 0: none)
  std::vector<std::tuple<int, int, DenseMatrix>> K2;
};

eigen::GyroscopicSystem SynthesizedStructure::denseSystem(const std::vector<double>& s) const {
  CMS_INPUT_CHECK(s.size() != structure_->speeds().size(),
                  "synthesis: " << s.size() << " speeds given, the structure has " << structure_->speeds().size());
  if (const auto why = structure_->steadySpinDefect(s); !why.empty()) throw InputError(why);
  auto& pieces = const_cast<std::shared_ptr<DensePieces>&>(dense_);
  if (!pieces) {  // collective: every rank calls solve at the same speeds
    auto d = std::make_shared<DensePieces>();
    d->M = toDense(*M_);
    d->K0 = toDense(*K0_);
    for (int i = 0; i < d->K0.numRows(); ++i) {
      bool zero = true;
      for (int j = 0; j < d->K0.numCols() && zero; ++j) zero = d->K0(i, j) == 0.0 && d->K0(j, i) == 0.0;
      if (zero) d->unrestrained.push_back(i);
    }
    if (!D_.is_null()) d->D = toDense(*D_);
    for (const auto& Gi : G_) d->G.push_back(Gi.is_null() ? DenseMatrix() : toDense(*Gi));
    for (const auto& Ni : N_) d->N.push_back(Ni.is_null() ? DenseMatrix() : toDense(*Ni));
    for (const auto& t : K2_) d->K2.emplace_back(t.i, t.j, toDense(*t.K));
    pieces = d;
  }
  // G(s) = sum_i s_i G_i, K(s) = K0 + sum s_i s_j K_ij, entry by entry in
  // the order system() adds them.
  const DensePieces& d = *pieces;
  const int n = d.M.numRows();
  eigen::GyroscopicSystem out;
  out.M = d.M;
  out.G = DenseMatrix(n, n);
  out.K = d.K0;
  for (std::size_t i = 0; i < d.G.size(); ++i)
    if (d.G[i].numRows() == n && s[i] != 0.0)
      for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) out.G(r, c) += s[i] * d.G[i](r, c);
  // With the magnitudes of the parts summed, what K's rounding is relative
  // to (GyroscopicSystem::KMagnitude; theory §4.3, "A zero shown nonzero").
  if (kEntrywise_) {
    out.KMagnitude = DenseMatrix(n, n);
    for (int col = 0; col < n; ++col)
      for (int r = 0; r < n; ++r) out.KMagnitude(r, col) = std::abs(d.K0(r, col));
  }
  for (const auto& [i, j, Kij] : d.K2) {
    const double c = s[static_cast<std::size_t>(i)] * s[static_cast<std::size_t>(j)];
    if (c == 0.0) continue;
    for (int col = 0; col < n; ++col)
      for (int r = 0; r < n; ++r) out.K(r, col) += c * Kij(r, col);
    if (kEntrywise_)
      for (int col = 0; col < n; ++col)
        for (int r = 0; r < n; ++r) out.KMagnitude(r, col) += std::abs(c * Kij(r, col));
  }
  if (d.D.numRows() == n) out.D = d.D;
  for (std::size_t i = 0; i < d.N.size(); ++i) {
    if (d.N[i].numRows() != n || s[i] == 0.0) continue;
    if (out.N.numRows() != n) out.N = DenseMatrix(n, n);
    for (int c = 0; c < n; ++c)
      for (int r = 0; r < n; ++r) out.N(r, c) += s[i] * d.N[i](r, c);
  }
  out.unrestrained = d.unrestrained;  // solved apart by the general path (theory §4.3)
  return out;
}

Teuchos::RCP<const Teuchos::ParameterList> SynthesizedStructure::validSolveParameters() {
  static Teuchos::RCP<const Teuchos::ParameterList> valid = [] {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Solve"));
    Teuchos::setStringToIntegralParameter<int>(
        "Solver", "Auto", "Auto (Dense up to \"Dense Limit\" coordinates, else Sparse), Dense or Sparse",
        Teuchos::tuple<std::string>("Auto", "Dense", "Sparse"), pl.get());
    pl->set("Dense Limit", 1500, "Largest n solved by the dense LAPACK path under Auto");
    pl->set("Number of Modes", 10, "Lowest modes to return");
    pl->sublist("Dense Solver").disableRecursiveValidation();
    pl->sublist("Sparse Solver").disableRecursiveValidation();
    return pl;
  }();
  return valid;
}

namespace {
/// The request cut to the model's size is said, not silent (found by a review).
std::string fewerCoordinatesNote(long long requested, long long n) {
  return "; \"Number of Modes\" = " + std::to_string(requested) + " asks for more than the reduced model's " +
         std::to_string(n) + " coordinates: all " + std::to_string(n) + " returned";
}
}  // namespace

StructureModes SynthesizedStructure::solve(const std::vector<double>& s, const Teuchos::ParameterList& params) const {
  const auto t0 = Clock::now();
  CMS_INPUT_CHECK(!hubs_.empty(), "synthesis: the rotor '" << structure_->parts()[hubs_.front().part]->spec.name
                                      << "' spins on a moving attachment: the structure's coefficients are periodic "
                                         "in its azimuth (theory §16.8); its modes come from "
                                         "analysis::PeriodicStructure (cms modes), not from this solve");
  Teuchos::ParameterList p(params);
  try {
    p.validateParametersAndSetDefaults(*validSolveParameters());
  } catch (const std::exception& e) {
    throw InputError(std::string("synthesis solve parameters: ") + e.what());
  }
  const std::string solver = p.get<std::string>("Solver");
  const int limit = p.get<int>("Dense Limit");
  const int nev = p.get<int>("Number of Modes");
  CMS_INPUT_CHECK(nev < 1, "synthesis solve parameters: \"Number of Modes\" = " << nev << " must be >= 1");
  StructureModes out;
  out.speeds = s;
  const long long n = size();
  const bool dense = solver == "Dense" || (solver == "Auto" && n <= limit);
  std::ostringstream why;
  if (dense) {
    why << "dense (n = " << n << (solver == "Dense" ? ", requested)" : " <= Dense Limit)");
    Teuchos::ParameterList dp = p.sublist("Dense Solver");
    dp.set("Number of Modes", static_cast<int>(std::min<long long>(nev, n)));
    out.result = eigen::DenseGyroscopicSolver(dp).solve(denseSystem(s));
    if (nev > n) out.result.reason += fewerCoordinatesNote(nev, n);
  } else {
    why << "sparse (n = " << n << (solver == "Sparse" ? ", requested)" : " > Dense Limit)");
    Teuchos::ParameterList sp = p.sublist("Sparse Solver");
    sp.set("Number of Modes", nev);
    const auto sys = system(s);
    if (structure_->freeFloating() && !sp.isParameter("Shift")) {
      // K of a free structure is singular: shift the transform by s = tau^2
      // > 0 (theory §5), tau = 1e-3 sqrt(||K|| / ||M||), which regularises
      // Q(+-tau) without changing which modes come first (the lowest |lambda|).
      const double tau = 1e-3 * std::sqrt(sys.K->getFrobeniusNorm() / sys.M->getFrobeniusNorm());
      sp.set("Shift", tau * tau);
      why << ", free structure: automatic Shift " << tau * tau;
    }
    out.result = eigen::SparseGyroscopicSolver(sp).solve(sys);
  }
  out.path = why.str();
  out.seconds = since(t0);
  return out;
}

std::vector<StructureModes> SynthesizedStructure::solveMany(const std::vector<std::vector<double>>& speeds,
                                                            const Teuchos::ParameterList& params, int threads) const {
  std::vector<StructureModes> out(speeds.size());
  Teuchos::ParameterList p(params);
  try {
    p.validateParametersAndSetDefaults(*validSolveParameters());
  } catch (const std::exception& e) {
    throw InputError(std::string("synthesis solve parameters: ") + e.what());
  }
  const std::string solver = p.get<std::string>("Solver");
  const long long n = size();
  const bool dense = solver == "Dense" || (solver == "Auto" && n <= p.get<int>("Dense Limit"));
  if (threads <= 0)  // the ranks sharing this node, not the communicator's size (collective)
    threads = coresPerRank(ranksOnNode(*structure_->comm()));  // within this rank's CPU binding
  threads = std::min<int>(threads, static_cast<int>(speeds.size()));
  if (!dense || !hubs_.empty() || threads <= 1) {
    for (std::size_t k = 0; k < speeds.size(); ++k) out[k] = solve(speeds[k], params);
    return out;
  }
  // Everything Teuchos is done here, before any thread starts (its RCPs
  // count references without atomics in Debian's build): the collective
  // gathers of denseSystem and one solver, with its own parameters, per
  // thread. A thread only combines the gathered pieces and runs LAPACK.
  const int nev = p.get<int>("Number of Modes");
  CMS_INPUT_CHECK(nev < 1, "synthesis solve parameters: \"Number of Modes\" = " << nev << " must be >= 1");
  Teuchos::ParameterList dp = p.sublist("Dense Solver");
  dp.set("Number of Modes", static_cast<int>(std::min<long long>(nev, n)));
  std::vector<std::unique_ptr<eigen::DenseGyroscopicSolver>> solvers;
  for (int w = 0; w < threads; ++w) solvers.push_back(std::make_unique<eigen::DenseGyroscopicSolver>(dp));
  for (auto& s : speeds)
    CMS_INPUT_CHECK(s.size() != structure_->speeds().size(), "synthesis: " << s.size() << " speeds given, the structure has "
                                                                           << structure_->speeds().size());
  denseSystem(speeds.front());
  std::ostringstream why;
  why << "dense (n = " << n << (solver == "Dense" ? ", requested)" : " <= Dense Limit)");
  const std::string path = why.str();
  // Each worker's LAPACK calls run on the worker alone: OpenBLAS's own pool
  // under these threads spun for 63% of the CPU (cms/core/BlasThreads.hpp).
  const BlasThreadScope oneEach(1);
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> failed(static_cast<std::size_t>(threads));
  auto work = [&](int w) {
    try {
      for (std::size_t k = next++; k < speeds.size(); k = next++) {
        const auto t0 = Clock::now();
        out[k].speeds = speeds[k];
        out[k].result = solvers[static_cast<std::size_t>(w)]->solve(denseSystem(speeds[k]));
        if (nev > n) out[k].result.reason += fewerCoordinatesNote(nev, n);
        out[k].path = path;
        out[k].seconds = since(t0);
      }
    } catch (...) {
      failed[static_cast<std::size_t>(w)] = std::current_exception();
      next = speeds.size();
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < threads; ++w) pool.emplace_back(work, w);
  work(0);
  for (auto& t : pool) t.join();
  for (const auto& e : failed)
    if (e) std::rethrow_exception(e);
  return out;
}

std::vector<Teuchos::RCP<MultiVector>> SynthesizedStructure::expand(const StructureModes& modes, int m) const {
  return expandParts(modes, m, {});
}

std::vector<double> SynthesizedStructure::factorCoordinates(std::size_t k, const StructureModes& modes, int m0,
                                                            int bm) const {
  // y = C q per column (real, imaginary per mode), each rank summing over its
  // coordinates, then over the ranks.
  const auto& C = C_[k];
  const int nb = static_cast<int>(C.size()), nc = 2 * bm;
  std::vector<double> local(static_cast<std::size_t>(nb) * nc, 0.0), y(local.size(), 0.0);
  for (int m = 0; m < bm; ++m) {
    const auto& q = modes.result.modes.at(m0 + m).q;
    const bool replicated = static_cast<long long>(q.size()) == size();
    for (int j = 0; j < nb; ++j)
      for (auto [g, v] : C[j]) {
        const auto l = map_->getLocalElement(g);
        if (l == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) continue;
        const auto& x = q.at(replicated ? static_cast<std::size_t>(g) : static_cast<std::size_t>(l));
        local[j + static_cast<std::size_t>(2 * m) * nb] += v * x.real();
        local[j + static_cast<std::size_t>(2 * m + 1) * nb] += v * x.imag();
      }
  }
  if (!local.empty())
    Teuchos::reduceAll(*map_->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), y.data());
  return y;
}

std::vector<Teuchos::RCP<MultiVector>> SynthesizedStructure::expandParts(const StructureModes& modes, int m,
                                                                         const std::vector<bool>& skip) const {
  const auto& q = modes.result.modes.at(m).q;
  const std::size_t nloc = map_->getNodeNumElements();
  const bool replicated = static_cast<long long>(q.size()) == size();
  MultiVector x(map_, 2);
  for (std::size_t l = 0; l < nloc; ++l) {
    const std::size_t i = replicated ? static_cast<std::size_t>(map_->getGlobalElement(static_cast<LocalOrdinal>(l))) : l;
    x.replaceLocalValue(l, 0, q.at(i).real());
    x.replaceLocalValue(l, 1, q.at(i).imag());
  }
  std::vector<Teuchos::RCP<MultiVector>> out;
  for (std::size_t k = 0; k < T_.size(); ++k) {
    if (k < skip.size() && skip[k]) {
      out.push_back(Teuchos::null);
      continue;
    }
    if (!T_[k].is_null()) {
      auto u = Teuchos::rcp(new MultiVector(T_[k]->getRangeMap(), 2));
      T_[k]->apply(x, *u);
      out.push_back(u);
      continue;
    }
    // u = B (C q).
    const int nb = static_cast<int>(C_[k].size());
    const auto y = factorCoordinates(k, modes, m, 1);
    auto small = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(nb), 0, map_->getComm(), Tpetra::LocallyReplicated));
    MultiVector Y(small, 2);
    for (int j = 0; j < nb; ++j) Y.replaceLocalValue(j, 0, y[j]), Y.replaceLocalValue(j, 1, y[nb + j]);
    auto u = Teuchos::rcp(new MultiVector(B_[k]->getMap(), 2));
    u->multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, *B_[k], Y, 0.0);
    out.push_back(u);
  }
  return out;
}

std::map<GlobalOrdinal, SynthesizedStructure::SparseRow> SynthesizedStructure::transformRows(
    std::size_t k, const std::set<GlobalOrdinal>& rows) const {
  if (!T_[k].is_null()) return gatherRows(*T_[k], rows);
  // T's rows of B C: B's rows gathered (each rank holds some), times C.
  const auto& B = *B_[k];
  const auto& C = C_[k];
  const int nb = static_cast<int>(B.getNumVectors());
  const std::vector<GlobalOrdinal> ids(rows.begin(), rows.end());
  const int n = static_cast<int>(ids.size());
  std::vector<double> local(static_cast<std::size_t>(n) * nb, 0.0), all(local.size(), 0.0);
  std::vector<Teuchos::ArrayRCP<const double>> col(nb);
  for (int j = 0; j < nb; ++j) col[j] = B.getData(j);
  for (int i = 0; i < n; ++i) {
    const auto l = B.getMap()->getLocalElement(ids[i]);
    if (l == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) continue;
    for (int j = 0; j < nb; ++j) local[static_cast<std::size_t>(i) * nb + j] = col[j][l];
  }
  col.clear();
  if (!local.empty())
    Teuchos::reduceAll(*B.getMap()->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), all.data());
  std::map<GlobalOrdinal, SparseRow> out;
  for (int i = 0; i < n; ++i) {
    std::vector<std::pair<double, const Row*>> terms;
    for (int j = 0; j < nb; ++j) {
      const double b = all[static_cast<std::size_t>(i) * nb + j];
      if (b != 0.0 && !C[j].empty()) terms.push_back({b, &C[j]});
    }
    out[ids[i]] = combine(terms);
  }
  return out;
}

std::vector<ModeCharacter> SynthesizedStructure::characterise(const StructureModes& modes) const {
  const auto& parts = structure_->parts();
  double frameRate = 0.0;
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (parts[k]->spec.kind == SubstructureKind::Central && parts[k]->speedParam >= 0)
      frameRate = std::abs(modes.speeds.at(parts[k]->speedParam));
  // Rigid-coordinate block of M (free C), on every rank.
  std::set<GlobalOrdinal> rigidRows;
  if (structure_->freeFloating())
    for (GlobalOrdinal g = 0; g < 6; ++g) rigidRows.insert(g);
  const auto Mrr = gatherRows(*M_, rigidRows);
  // ||K_s||_F once per substructure, not per mode (a collective reduction).
  std::vector<double> normK(parts.size(), 0.0);
  for (std::size_t k = 0; k < parts.size(); ++k)
    if (parts[k]->sub) normK[k] = parts[k]->sub->frobeniusNorm(substructure::Matrix::K);
  // The modes a block at a time (as the error estimates): each part's M and
  // K applied to the block's motions at once, one pass over a matrix per
  // four columns, not two passes per mode.
  std::vector<ModeCharacter> out;
  const int nm = static_cast<int>(modes.result.modes.size());
  for (int m0 = 0; m0 < nm; m0 += kResidualBlockModes) {
    const std::size_t bm = static_cast<std::size_t>(std::min(kResidualBlockModes, nm - m0)), nc = 2 * bm;
    std::vector<std::vector<Teuchos::RCP<MultiVector>>> block(bm);
    for (std::size_t b = 0; b < bm; ++b) block[b] = expand(modes, m0 + static_cast<int>(b));
    // Per part and mode: u^H M u, and |u^H K u| / (||K||_F u^H u).
    std::vector<std::vector<double>> kinetic(bm, std::vector<double>(parts.size(), 0.0)), strain = kinetic;
    for (std::size_t k = 0; k < parts.size(); ++k) {
      const auto map = block[0][k]->getMap();
      MultiVector U(map, nc), AU(map, nc);
      for (std::size_t b = 0; b < bm; ++b)
        for (std::size_t c = 0; c < 2; ++c) U.getVectorNonConst(2 * b + c)->update(1.0, *block[b][k]->getVector(c), 0.0);
      Teuchos::Array<double> d(nc), uu(nc);
      if (parts[k]->sub) parts[k]->sub->apply(substructure::Matrix::M, U, AU);
      else smallMatrix(map, parts[k]->rotor.M)->apply(U, AU);
      U.dot(AU, d());
      for (std::size_t b = 0; b < bm; ++b) kinetic[b][k] = d[2 * b] + d[2 * b + 1];
      if (!parts[k]->sub) continue;
      parts[k]->sub->apply(substructure::Matrix::K, U, AU);
      U.dot(AU, d());
      U.dot(U, uu());
      for (std::size_t b = 0; b < bm; ++b) {
        const double size = uu[2 * b] + uu[2 * b + 1];
        strain[b][k] = normK[k] > 0.0 && size > 0.0 ? std::abs(d[2 * b] + d[2 * b + 1]) / (normK[k] * size) : 0.0;
      }
    }
    for (std::size_t b = 0; b < bm; ++b) {
      const auto& mode = modes.result.modes[static_cast<std::size_t>(m0) + b];
      const auto& u = block[b];
      ModeCharacter c;
      c.kineticShare = kinetic[b];
      c.relativeStrain = strain[b];
      double total = 0.0;
      for (double v : c.kineticShare) total += v;
      for (double& v : c.kineticShare) v = total > 0.0 ? v / total : 0.0;
      c.cyclic = detail::cyclicContent(parts, u);  // §15.3
      if (structure_->freeFloating()) {
        // a = q_r^H M_rr q_r and the elastic part e = q_e^H M_ee q_e =
        // q^H M q - 2 Re(q_r^H (M q)_r) + a: both non-negative, unlike the
        // cross terms, so a / (a + e) is a share.
        MultiVector x(map_, 2), Mx(map_, 2);
        const bool replicated = static_cast<long long>(mode.q.size()) == size();
        for (std::size_t l = 0; l < map_->getNodeNumElements(); ++l) {
          const std::size_t i = replicated ? static_cast<std::size_t>(map_->getGlobalElement(static_cast<LocalOrdinal>(l))) : l;
          x.replaceLocalValue(l, 0, mode.q[i].real());
          x.replaceLocalValue(l, 1, mode.q[i].imag());
        }
        M_->apply(x, Mx);
        double local[24] = {0}, global[24] = {0};
        for (GlobalOrdinal g = 0; g < 6; ++g) {
          const auto l = map_->getLocalElement(g);
          if (l == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) continue;
          local[4 * g] = x.getData(0)[l], local[4 * g + 1] = x.getData(1)[l];
          local[4 * g + 2] = Mx.getData(0)[l], local[4 * g + 3] = Mx.getData(1)[l];
        }
        Teuchos::reduceAll(*map_->getComm(), Teuchos::REDUCE_SUM, 24, local, global);
        Teuchos::Array<double> qMq(2);
        x.dot(Mx, qMq());
        std::complex<double> qr[6], aa = 0.0, rMq = 0.0;
        for (int g = 0; g < 6; ++g) {
          qr[g] = {global[4 * g], global[4 * g + 1]};
          rMq += std::conj(qr[g]) * std::complex<double>(global[4 * g + 2], global[4 * g + 3]);
        }
        for (const auto& [i, row] : Mrr)
          for (auto [j, v] : row)
            if (j < 6) aa += std::conj(qr[i]) * v * qr[j];
        const double rigid = aa.real(), elastic = std::max(0.0, qMq[0] + qMq[1] - 2.0 * rMq.real() + rigid);
        c.rigidShare = rigid + elastic > 0.0 ? rigid / (rigid + elastic) : 0.0;
        c.frameArtefact = frameRate > 0.0 && c.rigidShare > 0.99 &&
                          std::abs(mode.omega - frameRate) <= 1e-4 * frameRate;
      }
      out.push_back(c);
    }
  }
  return out;
}

const reduction::StaticCorrection& SynthesizedStructure::flexibility(std::size_t k) const {
  auto& f = factorisations_->flexibility[k];
  if (!f) f = bases_[k].flexibility;  // the reduction's own factor of the same matrix
  if (!f) {
    reduction::SubstructureBoundary own;
    own.held = structure_->parts()[k]->held;  // its attachment only: the interfaces move with f
    f = std::make_shared<const reduction::StaticCorrection>(*structure_->parts()[k]->sub, own);
  }
  return *f;
}

double SynthesizedStructure::flexibilityFlops(std::size_t k) const {
  const auto& f = *factorisations_;
  const auto& held = f.flexibility[k] ? f.flexibility[k] : bases_[k].flexibility;
  return held ? held->factorFlops() : f.flexibilityFlops[k];  // the same on every rank (broadcast by the solver)
}

void SynthesizedStructure::releaseFlexibilities() {
  auto& f = *factorisations_;
  for (std::size_t k = 0; k < f.flexibility.size(); ++k) f.flexibilityFlops[k] = flexibilityFlops(k);
  for (auto& g : f.flexibility) g.reset();
  for (auto& b : bases_) b.flexibility.reset();
}

std::vector<double> SynthesizedStructure::copyResidualNorms(std::size_t k, const StructureModes& modes, int m0, int bm,
                                                            const std::vector<double>& D,
                                                            const std::vector<substructure::Matrix>& terms,
                                                            double frame, const std::vector<double>& W,
                                                            const std::vector<double>& XP,
                                                            std::vector<double>* toParent) const {
  using substructure::Matrix;
  const int nb = static_cast<int>(C_[k].size()), nc = 2 * bm, nt = static_cast<int>(terms.size()), w = nt * nb;
  const int na = static_cast<int>(XP.size()) / std::max(w, 1);
  const auto y = factorCoordinates(k, modes, m0, bm);
  Teuchos::BLAS<int, double> blas;
  std::vector<double> z(y.size()), Z(static_cast<std::size_t>(w) * nc, 0.0), WZ(Z.size()), out(nc, 0.0);
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, nb, nc, nb, 1.0, D.data(), nb, y.data(), nb, 0.0, z.data(), nb);
  // Z: each term's coefficient c_t(lambda) times z, as the residual's
  // accumulation does (Re r = Re c A a - Im c A b, Im r = Im c A a + Re c A b).
  for (int t = 0; t < nt; ++t)
    for (int m = 0; m < bm; ++m) {
      const std::complex<double> l = modes.result.modes[m0 + m].lambda;
      std::complex<double> c = 1.0;
      switch (terms[static_cast<std::size_t>(t)]) {
        case Matrix::M: c = l * l; break;
        case Matrix::D: c = l; break;
        case Matrix::G1: c = frame * l; break;
        case Matrix::K2: c = frame * frame; break;
        default: break;
      }
      for (int i = 0; i < nb; ++i) {
        const double a = z[i + static_cast<std::size_t>(2 * m) * nb], b = z[i + static_cast<std::size_t>(2 * m + 1) * nb];
        Z[t * nb + i + static_cast<std::size_t>(2 * m) * w] = c.real() * a - c.imag() * b;
        Z[t * nb + i + static_cast<std::size_t>(2 * m + 1) * w] = c.imag() * a + c.real() * b;
      }
    }
  blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, w, nc, w, 1.0, W.data(), w, Z.data(), w, 0.0, WZ.data(), w);
  for (int col = 0; col < nc; ++col)
    for (int i = 0; i < w; ++i) out[col] += Z[i + static_cast<std::size_t>(col) * w] * WZ[i + static_cast<std::size_t>(col) * w];
  if (toParent && na > 0) {
    // X_c^T r_c = M6^T (X_p^T P) Z, M6 the top-left na x na of D.
    std::vector<double> XPZ(static_cast<std::size_t>(na) * nc), M6(static_cast<std::size_t>(na) * na), g(XPZ.size());
    blas.GEMM(Teuchos::NO_TRANS, Teuchos::NO_TRANS, na, nc, w, 1.0, XP.data(), na, Z.data(), w, 0.0, XPZ.data(), na);
    for (int j = 0; j < na; ++j)
      for (int i = 0; i < na; ++i) M6[i + static_cast<std::size_t>(j) * na] = D[i + static_cast<std::size_t>(j) * nb];
    blas.GEMM(Teuchos::TRANS, Teuchos::NO_TRANS, na, nc, na, 1.0, M6.data(), na, XPZ.data(), na, 0.0, g.data(), na);
    toParent->assign(static_cast<std::size_t>(6) * nc, 0.0);
    for (int a = 0; a < std::min(na, 6); ++a)
      for (int col = 0; col < nc; ++col) (*toParent)[static_cast<std::size_t>(a) * nc + col] = g[a + static_cast<std::size_t>(col) * na];
  }
  return out;
}

std::vector<double> SynthesizedStructure::residualFlexibilityNorms(const StructureModes& modes,
                                                                   std::vector<std::vector<double>>* byPart) const {
  const auto& parts = structure_->parts();
  const int nm = static_cast<int>(modes.result.modes.size());
  std::vector<double> correction(nm, 0.0);  // sum over substructures of Re(f^H K_a^-1 f)
  if (byPart) byPart->assign(static_cast<std::size_t>(nm), std::vector<double>(parts.size(), 0.0));
  // The modes a block at a time, and per substructure three blocks of
  // vectors (the motion U, the residual R, one product or solution T): the
  // residuals of every mode at once, with a block for each of M U, G U, K U,
  // a temporary and the solution, were the error estimates' peak memory,
  // 8 x 2 nm vectors of the largest substructure (doc/benchmarks.md, "The
  // bar's memory"). The factor is read once per block in the solves.
  //
  // A turned copy with no children, whose reduced matrices came from its
  // prototype's (copyRotation: Q^T B_c = B_p D), has its residual in the
  // prototype's axes r_p = Q^T r_c = sum_t c_t(lambda) A_t B_p (D y), y = C q
  // its factors' coordinates, t over M, D, G1, K, K2 with c_t = lambda^2,
  // lambda, Omega lambda, 1, Omega^2. So r^T K^-1 r = Z^T W Z with W = P^T
  // K_p^-1 P, P = [A_t B_p]_t, and X_c^T r_c = M6^T (X_p^T P) Z (theory
  // §15.2): W made once from the prototype serves every copy, which then
  // costs small dense products instead of sparse ones and solves.
  struct Gram {
    std::vector<substructure::Matrix> terms;
    int nb = 0, na = 0;
    std::vector<double> W, XP;  ///< (nt nb)^2 and na x (nt nb), column-major
  };
  std::map<std::size_t, Gram> gram;  // by prototype
  std::vector<bool> useGram(parts.size(), false);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const auto& p = *parts[k];
    const std::size_t q = structure_->prototypeOf(k);
    // (projectedFromPrototype: its D was found, rotations_[k].)
    // (A modally damped copy takes the general path below, which lifts its
    // modal damping force: the Gram terms hold only the substructure's own
    // matrices.)
    if (q == k || !p.sub || !reports_[k].projectedFromPrototype || !p.children.empty() || p.compound ||
        p.boolean() || parts[q]->compound || !sharesPrototypeFactorisations(k) || !modalDamping_[k].empty() ||
        (parts[q]->sub && parts[q]->sub->has(substructure::Matrix::N1)))
      continue;
    const int nb = static_cast<int>(B_[k]->getNumVectors()), na = nb - bases_[k].size();
    useGram[k] = true;
    if (gram.count(q)) continue;
    Gram g;
    g.nb = nb, g.na = na;
    const auto& proto = *parts[q]->sub;
    using substructure::Matrix;
    for (Matrix a : {Matrix::M, Matrix::D, Matrix::G1, Matrix::K, Matrix::K2})
      if (proto.has(a)) g.terms.push_back(a);
    const int nt = static_cast<int>(g.terms.size()), w = nt * nb;
    MultiVector P(proto.map(), static_cast<std::size_t>(w)), KP(proto.map(), static_cast<std::size_t>(w));
    for (int t = 0; t < nt; ++t) {
      auto Pt = P.subViewNonConst(Teuchos::Range1D(t * nb, (t + 1) * nb - 1));
      proto.apply(g.terms[static_cast<std::size_t>(t)], *B_[q], *Pt);
    }
    flexibility(q).solve(P, KP);
    auto small = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(w), 0, proto.map()->getComm(), Tpetra::LocallyReplicated));
    MultiVector Wm(small, static_cast<std::size_t>(w));
    Wm.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, P, KP, 0.0);
    g.W.resize(static_cast<std::size_t>(w) * w);
    for (int j = 0; j < w; ++j) {
      const auto c = Wm.getData(j);
      for (int i = 0; i < w; ++i) g.W[i + static_cast<std::size_t>(j) * w] = c[i];
    }
    if (na > 0) {
      auto rigid = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(na), 0, proto.map()->getComm(), Tpetra::LocallyReplicated));
      MultiVector XPm(rigid, static_cast<std::size_t>(w));
      XPm.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, *B_[q]->subView(Teuchos::Range1D(0, na - 1)), P, 0.0);
      g.XP.resize(static_cast<std::size_t>(na) * w);
      for (int j = 0; j < w; ++j) {
        const auto c = XPm.getData(j);
        for (int i = 0; i < na; ++i) g.XP[i + static_cast<std::size_t>(j) * na] = c[i];
      }
    }
    gram[q] = std::move(g);
  }
  // A modal damping ratio damps a reduced substructure's own coordinates
  // eta only (theory §13.1): D_eta has no physical matrix, so its force
  // would be read as residual (a floor of about zeta under every estimate,
  // found by a review). The truth it is compared with damps the same
  // relative motion v = V eta (V: the basis columns of B, zero on the held
  // rows) by the physical M V (V^T M V)^-1 D_eta (V^T M V)^-1 V^T M, whose
  // projection is D_eta, with no force on the attachment coordinates a
  // (§11.8): on a mode its force on the free rows is M V (V^T M V)^-1 D_eta
  // eta. (Lifted through all of B = [X V] instead, to give X^T F = 0 on the
  // physical rows, the force gained a rigid part M X alpha that no basis
  // vector represents: the floor fell only from 5e-3 to 3e-3.) Per such
  // part, the Cholesky factor of V^T M V (collective).
  std::map<std::size_t, DenseMatrix> liftGram;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (modalDamping_[k].empty() || useGram[k]) continue;
    const int ne = bases_[k].size(), na = static_cast<int>(B_[k]->getNumVectors()) - ne;
    const auto V = B_[k]->subView(Teuchos::Range1D(na, na + ne - 1));
    MultiVector MV(V->getMap(), static_cast<std::size_t>(ne));
    parts[k]->sub->apply(substructure::Matrix::M, *V, MV);
    auto small = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(ne), 0, V->getMap()->getComm(), Tpetra::LocallyReplicated));
    MultiVector Gm(small, static_cast<std::size_t>(ne));
    Gm.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, *V, MV, 0.0);
    DenseMatrix G(ne, ne);
    for (int j = 0; j < ne; ++j) {
      const auto c = Gm.getData(j);
      for (int i = 0; i < ne; ++i) G(i, j) = c[i];
    }
    int info = 0;
    Teuchos::LAPACK<int, double>().POTRF('L', ne, G.values(), G.stride(), &info);
    TEUCHOS_TEST_FOR_EXCEPTION(info != 0, NumericalError,
                               "synthesis: error estimates of '" << parts[k]->spec.name << "': the Gram matrix V^T M V of "
                               "its basis vectors is not positive definite (LAPACK dpotrf info " << info << "), so its modal "
                               "damping force cannot be lifted to its physical rows");
    liftGram.emplace(k, std::move(G));
  }
  for (int m0 = 0; m0 < nm; m0 += kResidualBlockModes) {
    const int bm = std::min(kResidualBlockModes, nm - m0), nc = 2 * bm;  // real, imaginary per mode
    // The expanded modes of the block, per substructure (collective).
    std::vector<std::vector<Teuchos::RCP<MultiVector>>> u(bm);
    for (int m = 0; m < bm; ++m) u[m] = expandParts(modes, m0 + m, useGram);  // (not the Gram copies')
    // Per part, the generalised forces of its residual on its 6 attachment
    // coordinates (X^T r), which act on its parent's rows through H^T.
    std::vector<std::vector<double>> toParent(parts.size());
    // Children before parents (parts are in pre-order).
    for (std::size_t kk = parts.size(); kk-- > 0;) {
      const std::size_t k = kk;
      const auto& p = *parts[k];
      if (useGram[k]) {
        const auto& g = gram.at(structure_->prototypeOf(k));
        double frame = 0.0;
        for (auto [i, ci] : p.frame.coefficients) frame += ci * modes.speeds.at(i);
        const auto d = copyResidualNorms(k, modes, m0, bm, rotations_[k], g.terms, frame, g.W, g.XP,
                                         p.parent >= 0 ? &toParent[k] : nullptr);
        for (int m = 0; m < bm; ++m) correction[m0 + m] += d[2 * m] + d[2 * m + 1];
        if (byPart)
          for (int m = 0; m < bm; ++m) (*byPart)[static_cast<std::size_t>(m0 + m)][k] = d[2 * m] + d[2 * m + 1];
        continue;
      }
      const auto rmap = u[0][k]->getMap();
      MultiVector U(rmap, nc), R(rmap, nc), T(rmap, nc);
      for (int m = 0; m < bm; ++m) {
        for (int c = 0; c < 2; ++c) U.getVectorNonConst(2 * m + c)->update(1.0, *u[m][k]->getVector(c), 0.0);
        u[m][k] = Teuchos::null;  // held in U from here
      }
      // r = (lambda^2 M + lambda G + K) u, real and imaginary parts, for
      // u = a + i b and lambda = sigma + i omega, accumulated term by term
      // from T = M U, then G U, then K U.
      auto accumulate = [&](auto coefficient, bool first) {
        for (int m = 0; m < bm; ++m) {
          const std::complex<double> f = coefficient(modes.result.modes[m0 + m].lambda);
          auto Ta = T.getVector(2 * m), Tb = T.getVector(2 * m + 1);
          auto Ra = R.getVectorNonConst(2 * m), Rb = R.getVectorNonConst(2 * m + 1);
          Ra->update(f.real(), *Ta, -f.imag(), *Tb, first ? 0.0 : 1.0);
          Rb->update(f.imag(), *Ta, f.real(), *Tb, first ? 0.0 : 1.0);
        }
      };
      auto squared = [](std::complex<double> l) { return l * l; };
      auto linear = [](std::complex<double> l) { return l; };
      auto one = [](std::complex<double>) { return std::complex<double>(1.0, 0.0); };
      if (p.sub) {
        // The substructure's matrices at these speeds (as projected in
        // synthesize): G_s = Omega_s G1 (+ its own spin's G1 for a compound
        // rotor), K_s = K + Omega_s^2 K2 (+ Omega_s omega KX1).
        // (A turned copy's applied as Q A_p Q^T, theory §15.2.)
        using substructure::Matrix;
        const auto& sub = *p.sub;
        double frame = 0.0;
        for (auto [i, ci] : p.frame.coefficients) frame += ci * modes.speeds.at(i);
        sub.apply(Matrix::M, U, T);
        accumulate(squared, true);
        // Its viscous damping D_s (dampers, Rayleigh: theory §13.1) acts with
        // lambda like G: r = (lambda^2 M + lambda (G + D) + K) u.
        double beta = 0.0;  // T holds nothing yet
        if (sub.has(Matrix::D)) sub.apply(Matrix::D, U, T), beta = 1.0;
        if (p.frame.spinning && frame != 0.0 && sub.has(Matrix::G1))
          sub.apply(Matrix::G1, U, T, frame, beta), beta = 1.0;
        if (p.compound) p.stationary->G1()->apply(U, T, Teuchos::NO_TRANS, modes.speeds.at(p.speedParam), beta), beta = 1.0;
        if (beta != 0.0) accumulate(linear, false);
        sub.apply(Matrix::K, U, T);
        if (p.frame.spinning && frame != 0.0 && sub.has(Matrix::K2)) sub.apply(Matrix::K2, U, T, frame * frame, 1.0);
        if (p.compound && !p.stationary->KX1().is_null())
          p.stationary->KX1()->apply(U, T, Teuchos::NO_TRANS, modes.speeds.at(p.speedParam) * frame, 1.0);
        // A stationary-frame rotor's circulatory N_s = Omega N1 (theory §13.1).
        if (p.frame.spinning && frame != 0.0 && sub.has(Matrix::N1)) sub.apply(Matrix::N1, U, T, frame, 1.0);
        if (p.compound && p.stationary->has(Matrix::N1))
          p.stationary->N1()->apply(U, T, Teuchos::NO_TRANS, modes.speeds.at(p.speedParam), 1.0);
        accumulate(one, false);
      } else {  // a rigid rotor: its equations on a (§11.5)
        smallMatrix(rmap, p.rotor.M)->apply(U, T);
        accumulate(squared, true);
        double beta = 0.0;
        for (const auto& [i, Gi] : p.rotor.G)
          smallMatrix(rmap, Gi)->apply(U, T, Teuchos::NO_TRANS, modes.speeds.at(i), beta), beta = 1.0;
        if (beta != 0.0) accumulate(linear, false);
        beta = 0.0;
        for (const auto& [i, j, Kij] : p.rotor.K)
          smallMatrix(rmap, Kij)->apply(U, T, Teuchos::NO_TRANS, modes.speeds.at(i) * modes.speeds.at(j), beta),
              beta = 1.0;
        if (beta != 0.0) accumulate(one, false);
      }
      // The children's forces on this substructure's rows, f = r + sum H^T g:
      // the truth's equations on these rows in the floating-frame coordinates.
      for (int c : p.children) {
        if (toParent[c].empty()) continue;
        for (std::size_t a = 0; a < parts[c]->Hrows.size() && (a + 1) * nc <= toParent[c].size(); ++a)
          for (auto [g, v] : parts[c]->Hrows[a]) {
            const auto l = rmap->getLocalElement(g);
            if (l == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) continue;
            for (int col = 0; col < nc; ++col) R.sumIntoLocalValue(l, col, v * toParent[c][a * nc + col]);
          }
      }
      // Its generalised forces on its attachment: g_a = sum_rows X(row, a) f(row).
      if (p.parent >= 0 && !p.boolean()) {
        std::vector<double> local(6 * nc, 0.0), global(6 * nc, 0.0);
        const auto nodeOf = p.sub ? p.sub->dofs().rowNodes() : std::vector<std::int64_t>{};
        std::vector<Teuchos::ArrayRCP<const double>> Rc(nc);  // views taken once: not per row
        for (int col = 0; col < nc; ++col) Rc[col] = R.getData(col);
        for (std::size_t l = 0; l < rmap->getNodeNumElements(); ++l) {
          const auto g = rmap->getGlobalElement(static_cast<LocalOrdinal>(l));
          std::array<double, 6> x{};
          if (p.sub) {
            const auto& t = p.sub->dofs();
            const auto nd = nodeOf[g];
            x = detail::rigidRow({t.coordinates[3 * nd] - p.point[0], t.coordinates[3 * nd + 1] - p.point[1],
                                  t.coordinates[3 * nd + 2] - p.point[2]},
                                 static_cast<int>(t.components[g]));
          } else if (g < 6) {
            x[g] = 1.0;
          }
          for (int a = 0; a < 6; ++a)
            if (x[a] != 0.0)
              for (int col = 0; col < nc; ++col) local[a * nc + col] += x[a] * Rc[col][l];
        }
        Rc.clear();
        Teuchos::reduceAll(*rmap->getComm(), Teuchos::REDUCE_SUM, 6 * nc, local.data(), global.data());
        toParent[k] = global;
      } else if (p.parent >= 0) {
        // A Boolean child's forces on the rows it shares, g_a = X_a^T r with
        // X its transform's interface columns: the constraint modes Psi of a
        // reduced basis (B's first columns), the injection of a Full one (its
        // own row of shared DOF a). Without them a reduced parent's residual
        // held the whole interface force and every estimate read
        // "unresolved" (true errors 1e-8 to 3e-5; Target Accuracy then grew
        // the parent to every DOF and failed; found by a review).
        const std::size_t na = p.Hrows.size();
        std::vector<double> local(na * nc, 0.0), global(na * nc, 0.0);
        if (!B_[k].is_null()) {
          auto small = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(na), 0, rmap->getComm(),
                                            Tpetra::LocallyReplicated));
          MultiVector XR(small, static_cast<std::size_t>(nc));
          XR.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0,
                      *B_[k]->subView(Teuchos::Range1D(0, static_cast<int>(na) - 1)), R, 0.0);
          for (int col = 0; col < nc; ++col) {
            const auto v = XR.getData(col);
            for (std::size_t a = 0; a < na; ++a) global[a * nc + col] = v[a];
          }
        } else {
          const auto& t = p.sub->dofs();
          for (std::size_t a = 0; a < na && a < p.booleanDofs.size(); ++a) {
            const long long row = t.row(p.booleanDofs[a].first, p.booleanDofs[a].second);
            const auto l = row < 0 ? Teuchos::OrdinalTraits<LocalOrdinal>::invalid() : rmap->getLocalElement(row);
            if (l == Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) continue;
            for (int col = 0; col < nc; ++col) local[a * nc + col] = R.getData(col)[l];
          }
          Teuchos::reduceAll(*rmap->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(na) * nc, local.data(),
                             global.data());
        }
        toParent[k] = global;
      }
      // A Full basis satisfies its own equations (with its children's forces)
      // to the solver's accuracy; a rigid rotor has no deformation.
      if (!p.sub || reports_[k].basis == "Full") continue;
      if (const auto lift = liftGram.find(k); lift != liftGram.end()) {
        // Its modal damping force lambda M V (V^T M V)^-1 D_eta eta (above),
        // eta = C q's own rows. After toParent: it does no work on the
        // attachment, which the flexibility holds.
        const auto& B = *B_[k];
        const int nb = static_cast<int>(B.getNumVectors()), ne = bases_[k].size(), na = nb - ne;
        const auto& De = modalDamping_[k];
        const auto y = factorCoordinates(k, modes, m0, bm);
        DenseMatrix z(ne, nc);
        for (int col = 0; col < nc; ++col)
          for (int j = 0; j < ne; ++j) {
            const double yj = y[na + j + static_cast<std::size_t>(col) * nb];
            for (int i = 0; i < ne; ++i) z(i, col) += De[i + static_cast<std::size_t>(j) * ne] * yj;
          }
        int info = 0;
        Teuchos::LAPACK<int, double>().POTRS('L', ne, nc, lift->second.values(), lift->second.stride(), z.values(),
                                             z.stride(), &info);
        auto small = Teuchos::rcp(new Map(static_cast<Tpetra::global_size_t>(ne), 0, rmap->getComm(), Tpetra::LocallyReplicated));
        MultiVector W(small, static_cast<std::size_t>(nc)), F(rmap, static_cast<std::size_t>(nc));
        for (int col = 0; col < nc; ++col)
          for (int i = 0; i < ne; ++i) W.replaceLocalValue(i, col, z(i, col));
        F.multiply(Teuchos::NO_TRANS, Teuchos::NO_TRANS, 1.0, *B.subView(Teuchos::Range1D(na, nb - 1)), W, 0.0);
        p.sub->apply(substructure::Matrix::M, F, T);
        accumulate(linear, false);
      }
      Teuchos::Array<double> d(nc);
      if (sharesPrototypeFactorisations(k)) {
        // r^T K_c^-1 r = (Q^T r)^T K_p^-1 (Q^T r): the prototype's factor (§15.2).
        const std::size_t q = structure_->prototypeOf(k);
        const auto& proto = *parts[q]->sub;
        const auto back = detail::turnedRows(R, proto.dofs(), proto.map(),
                                             fem::Rotation::about(p.spec.copy->axis,
                                                                  parts[q]->spec.copy->angle - p.spec.copy->angle));
        MultiVector X(proto.map(), nc);
        flexibility(q).solve(*back, X);
        back->dot(X, d());
      } else {
        flexibility(k).solve(R, T);  // zero on the held rows; factored once per substructure
        R.dot(T, d());
      }
      for (int m = 0; m < bm; ++m) correction[m0 + m] += d[2 * m] + d[2 * m + 1];
      if (byPart)
        for (int m = 0; m < bm; ++m) (*byPart)[static_cast<std::size_t>(m0 + m)][k] = d[2 * m] + d[2 * m + 1];
    }
  }
  return correction;
}

std::vector<double> SynthesizedStructure::errorEstimates(const StructureModes& modes,
                                                         std::vector<std::vector<double>>* shares) const {
  std::vector<double> out;
  for (const auto& a : accuracy(modes, shares)) out.push_back(a.estimate);
  return out;
}

std::vector<ModeAccuracy> SynthesizedStructure::accuracy(const StructureModes& modes,
                                                         std::vector<std::vector<double>>* shares) const {
  const int nm = static_cast<int>(modes.result.modes.size());
  const auto correction = residualFlexibilityNorms(modes, shares);
  if (shares)  // each substructure's term over the sum
    for (std::size_t m = 0; m < shares->size(); ++m)
      for (double& x : (*shares)[m]) x = correction[m] > 0.0 ? x / correction[m] : 0.0;
  // d omega = -sum r^H K_b^-1 r / (2 omega q^H M q + g), q^H G q = i g (§11.8).
  std::vector<ModeAccuracy> out(nm);
  const auto sys = system(modes.speeds);
  for (int m = 0; m < nm; ++m) {
    const auto& mode = modes.result.modes[m];
    if (!(mode.omega > 0.0) || mode.stability == eigen::Stability::RigidBody ||
        mode.stability == eigen::Stability::Critical)
      continue;
    MultiVector x(map_, 2), Mx(map_, 2), Gx(map_, 2);
    const bool replicated = static_cast<long long>(mode.q.size()) == size();
    for (std::size_t l = 0; l < map_->getNodeNumElements(); ++l) {
      const std::size_t i = replicated ? static_cast<std::size_t>(map_->getGlobalElement(static_cast<LocalOrdinal>(l))) : l;
      x.replaceLocalValue(l, 0, mode.q[i].real());
      x.replaceLocalValue(l, 1, mode.q[i].imag());
    }
    sys.M->apply(x, Mx);
    sys.G->apply(x, Gx);
    Teuchos::Array<double> mm(2), gg(2);
    x.dot(Mx, mm());
    // g = Im(q^H G q) = a^T G b - b^T G a for q = a + i b; with damping,
    // d = q^H D q = a^T D a + b^T D b, and the first-order change of lambda
    // is -sum r^H K_b^-1 r / (2 lambda q^H M q + i g + d) (theory §11.8; for
    // lambda = i omega and d = 0 the undamped d omega).
    const double aGb = x.getVector(0)->dot(*Gx.getVector(1)), bGa = x.getVector(1)->dot(*Gx.getVector(0));
    double dd = 0.0;
    if (!D_.is_null()) {
      MultiVector Dx(map_, 2);
      D_->apply(x, Dx);
      Teuchos::Array<double> xd(2);
      x.dot(Dx, xd());
      dd = xd[0] + xd[1];
    }
    const std::complex<double> denominator =
        2.0 * mode.lambda * (mm[0] + mm[1]) + std::complex<double>(dd, aGb - bGa);
    out[m].estimate =
        std::abs(denominator) > 0.0 ? std::abs(correction[m] / denominator) / std::abs(mode.lambda) : -1.0;
    // A flexibility is positive definite, so only rounding makes this negative.
    if (mm[0] + mm[1] > 0.0) out[m].residualSquared = std::max(0.0, correction[m]) / (mm[0] + mm[1]);
  }
  if (!boundsUnavailable(modes.speeds).empty()) return out;
  // The symmetric positive definite case (theory §11.8): eps^2 is the
  // truth's own K^-1 norm of the residual of x (x^T M x = 1, theta =
  // omega^2 its Rayleigh quotient in the truth). Krylov-Bogoliubov: some
  // truth lambda has (lambda - theta)^2 <= eps^2 lambda, i.e. sqrt(lambda)
  // within eps/2 of s = sqrt(theta + eps^2/4).
  std::vector<int> order;
  for (int m = 0; m < nm; ++m)
    if (out[m].estimate >= 0.0) order.push_back(m);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return modes.result.modes[a].omega < modes.result.modes[b].omega; });
  auto lowerEnd = [&](int m) {  // the lower end of mode m's Krylov-Bogoliubov interval, in lambda
    const double w = modes.result.modes[m].omega, e2 = out[m].residualSquared;
    const double lo = std::sqrt(w * w + 0.25 * e2) - 0.5 * std::sqrt(e2);
    return lo * lo;
  };
  for (std::size_t i = 0; i < order.size(); ++i) {
    const int m = order[i];
    const double w = modes.result.modes[m].omega, theta = w * w, e2 = out[m].residualSquared, e = std::sqrt(e2);
    const double s = std::sqrt(theta + 0.25 * e2);
    // (s + e/2 - omega) / omega without cancellation: s - omega = (e^2/4) / (s + omega).
    out[m].bound = (0.5 * e + 0.25 * e2 / (s + w)) / w;
    out[m].boundKind = "Krylov-Bogoliubov";
    // Kato-Temple needs the gap b to the truth's next eigenvalue above
    // theta: the lower Krylov-Bogoliubov end of the next distinct Ritz value
    // (a cluster equal to 1e-8, the rounding of a computed repeated
    // eigenvalue, skipped), assuming no truth mode between the two (the
    // coverage check and --check-count test it). None above the highest.
    std::size_t j = i + 1;
    while (j < order.size() && modes.result.modes[order[j]].omega <= w * (1.0 + 1e-8)) ++j;
    if (j == order.size()) continue;
    const double b = lowerEnd(order[j]);
    if (!(b > theta)) continue;
    // With w = x^T M K^-1 M x = (eps^2 + theta) / theta^2 and no truth
    // eigenvalue in (theta, b), sum c_i^2 (lambda_i - a)(lambda_i - b) /
    // lambda_i >= 0 for a the largest truth eigenvalue <= theta gives
    // theta - a <= eps^2 theta b / (eps^2 b + (b - theta) theta).
    const double delta = e2 * theta * b / (e2 * b + (b - theta) * theta);
    const double x = std::min(1.0, delta / theta);
    out[m].bound = x / (1.0 + std::sqrt(1.0 - x));  // 1 - sqrt(1 - x)
    out[m].boundKind = "Kato-Temple";
    out[m].gapFactor = b / (b - theta);
  }
  return out;
}

bool SynthesizedStructure::sharesPrototypeFactorisations(std::size_t k) const {
  return !reports_[k].turnedFrom.empty() && operatorsTurned(*structure_, k, factorisations_->turnedImage);
}

bool SynthesizedStructure::carriedRigidly(std::size_t k) const {
  // K X = 0 exactly for an elastic stiffness and a rigid motion X, unless
  // supports or grounded springs of its own hold the part: known from its
  // model (every substructure of a structure is assembled from one). The
  // rule was K X against a bound over the whole column, 1e3 eps ||K||_F
  // ||X||, which grew with the mesh: a 1000-element boom's tip spring
  // stiffer than the boom itself was taken as rounding, its hold on the
  // attachment zeroed, and Craig-Bampton gave 21.3 Hz below the Full
  // model's 33.6 (a review).
  return !structure_->parts()[k]->ownSupports;
}

std::string SynthesizedStructure::boundsUnavailable(const std::vector<double>& speeds) const {
  for (std::size_t i = 0; i < speeds.size(); ++i)
    if (speeds[i] != 0.0)
      return "spinning (" + structure_->speeds()[i].name + "): G and the speed-dependent stiffness are not in the "
             "substructures' static flexibility, so its residual norm is an estimate, not the truth's";
  if (structure_->freeFloating()) return "free-floating: the truth's stiffness is singular (rigid-body modes)";
  if (!D_.is_null())
    return "damped (doc/theory.md section 13): the bounds hold for the undamped symmetric problem (the estimates include D)";
  const auto& parts = structure_->parts();
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const auto& p = *parts[k];
    if (p.boolean())
      return p.spec.name + " shares DOFs with its parent (Boolean): the truth's stiffness couples them";
    if (!p.sub && p.spec.rotor.spinCoordinate)
      return p.spec.name + "'s spin angle is a coordinate with no stiffness";
    if (p.sub && p.parent >= 0 && !carriedRigidly(k))
      return p.spec.name + " is grounded (its stiffness resists its rigid motion): the truth's stiffness couples it "
             "to its parent";
  }
  return "";
}

std::vector<SubstructureCoverage> SynthesizedStructure::coverage(double omega, double band) const {
  TEUCHOS_TEST_FOR_EXCEPTION(!(band >= 0.0) || !std::isfinite(band), std::logic_error,
                             "SynthesizedStructure::coverage: band " << band << " must be finite and >= 0");
  const auto& parts = structure_->parts();
  std::vector<SubstructureCoverage> out;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const auto& p = *parts[k];
    const auto& rep = reports_[k];
    SubstructureCoverage c;
    c.name = rep.name, c.basis = rep.basis, c.cutoff = omega, c.coordinates = rep.coordinates;
    if (!p.sub) {
      c.verdict = "rigid";
    } else if (rep.basis == "Full") {
      c.verdict = "Full";
    } else {
      // Its own problem with the attachment held, as its Ritz estimates
      // (frequencyEstimates) are computed: K_a - w^2 M_a, the held rows
      // contributing one positive eigenvalue each (K's diagonal, M's zero).
      // Held once per substructure; a count once per cut-off (an inertia is
      // the shift's own: each cut-off needs its own LDL^T).
      // A copy with its prototype's K and M turned has its counts (§15.2).
      const std::size_t src = sharesPrototypeFactorisations(k) ? structure_->prototypeOf(k) : k;
      const auto& ps = *parts[src];
      auto& f = *factorisations_;
      if (f.heldK[src].is_null()) {
        // Nothing held: K and M themselves, not copies kept for the run (issue 18).
        using ConstMatrix = Teuchos::RCP<const CrsMatrix>;
        f.heldK[src] = ps.held.empty() ? ps.sub->K() : ConstMatrix(holdDofsScaled(*ps.sub->K(), ps.held));
        f.heldM[src] = ps.held.empty() ? ps.sub->M() : ConstMatrix(holdDofs(*ps.sub->M(), ps.held, 0.0));
      }
      auto known = f.counts.find({src, omega});
      if (known == f.counts.end()) {
        // K - w^2 M handed over: freed once the count has its values (MUMPS's
        // triplets), before the factorisation (the count was the bar's peak).
        // (A named: a temporary RCP<CrsMatrix> converted in the call would
        // hold it to the end of the statement.)
        Teuchos::RCP<const CrsMatrix> A = matrixSum(1.0, *f.heldK[src], -omega * omega, *f.heldM[src]);
        // The flexibility's factorisation of K_a (the same pattern) forecasts
        // this one's cost: above the simplicial limit the count goes to
        // MUMPS without CHOLMOD's analysis first (SparseInertia.hpp).
        known = f.counts.emplace(std::make_pair(src, omega),
                                 inertia(std::move(A), InertiaMethod::Auto, flexibilityFlops(src))).first;
      }
      const auto& count = known->second;
      for (double w : rep.frequencyEstimates) c.represented += w < omega;
      if (!count.reliable()) {
        c.verdict = "not counted (" + (count.failure.empty() ? std::string("a pivot zero to rounding: the cut-off is "
                                                                           "an eigenvalue") : count.failure) + ")";
      } else {
        c.sturmCount = count.negative;
        std::ostringstream os;
        // Ritz values lie above the modes they approximate (the seed's
        // inclusion principle), so represented <= sturmCount.
        // A mode just below the cut-off whose Ritz value lies just above it,
        // within the cut-off's own uncertainty, is represented from above:
        // the values above omega, lowest first, fill the count within the band.
        const long long short_ = c.sturmCount - c.represented;
        if (short_ > 0 && band > 0.0) {
          std::vector<double> above;
          for (double w : rep.frequencyEstimates)
            if (w >= omega) above.push_back(w);
          std::sort(above.begin(), above.end());
          for (std::size_t i = 0; i < above.size() && static_cast<long long>(i) < short_; ++i)
            if (above[i] <= omega * (1.0 + band)) ++c.withinBand;
            else break;
        }
        if (c.represented >= c.sturmCount) os << "complete";
        else if (c.represented + c.withinBand >= c.sturmCount)
          os << "complete to the cut-off's accuracy (" << c.sturmCount << " below " << omega / (2.0 * M_PI)
             << " Hz, the basis represents " << c.represented << " and has " << c.withinBand
             << " more above it by less than " << std::setprecision(2) << band
             << ", the cut-off's own uncertainty: approximated from above)";
        else
          os << "can miss " << short_ << " mode" << (short_ == 1 ? "" : "s")
             << " below " << omega / (2.0 * M_PI) << " Hz (" << c.sturmCount << " below, the basis represents "
             << c.represented << ")";
        c.verdict = os.str();
      }
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace cms::synthesis
