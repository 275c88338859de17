#include "cms/core/SparseProduct.hpp"

#include <algorithm>
#include <cmath>
#include <system_error>
#include <thread>
#include <type_traits>
#include <vector>

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Export.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/core/BlasThreads.hpp"

namespace cms {

namespace {
/// Below this many multiply-adds (entries x columns) a second thread's start
/// (~30 us) is not worth it: one thread runs the kernel.
constexpr double kMinimumWork = 2e6;

/// Rows [r0, r1) of Y = alpha A X + beta Y, columns four at a time so that
/// each entry of A is loaded once per four columns. Each sum runs in an
/// order fixed by the row alone (its entries in order; a lone column's in
/// four interleaved parts).
void rows(const std::size_t* rowPtr, const LocalOrdinal* col, const double* val, const double* x, std::size_t ldx,
          double* y, std::size_t ldy, int nv, double alpha, double beta, std::size_t r0, std::size_t r1) {
  int j = 0;
  for (; j + 3 < nv; j += 4) {
    const double *x0 = x + j * ldx, *x1 = x0 + ldx, *x2 = x1 + ldx, *x3 = x2 + ldx;
    double *y0 = y + j * ldy, *y1 = y0 + ldy, *y2 = y1 + ldy, *y3 = y2 + ldy;
    for (std::size_t r = r0; r < r1; ++r) {
      double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
      for (std::size_t k = rowPtr[r]; k < rowPtr[r + 1]; ++k) {
        const double a = val[k];
        const std::size_t c = static_cast<std::size_t>(col[k]);
        s0 += a * x0[c], s1 += a * x1[c], s2 += a * x2[c], s3 += a * x3[c];
      }
      if (beta == 0.0) {
        y0[r] = alpha * s0, y1[r] = alpha * s1, y2[r] = alpha * s2, y3[r] = alpha * s3;
      } else {
        y0[r] = alpha * s0 + beta * y0[r], y1[r] = alpha * s1 + beta * y1[r];
        y2[r] = alpha * s2 + beta * y2[r], y3[r] = alpha * s3 + beta * y3[r];
      }
    }
  }
  // A column alone: one running sum would make every multiply-add wait for
  // the one before (a row of a Hex64 mesh has ~600 entries), so four sums
  // take every fourth entry and are added pairwise at the end: a fixed
  // order, whatever the thread count.
  for (; j < nv; ++j) {
    const double* xj = x + j * ldx;
    double* yj = y + j * ldy;
    for (std::size_t r = r0; r < r1; ++r) {
      double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
      std::size_t k = rowPtr[r];
      const std::size_t e = rowPtr[r + 1];
      for (; k + 3 < e; k += 4) {
        s0 += val[k] * xj[static_cast<std::size_t>(col[k])];
        s1 += val[k + 1] * xj[static_cast<std::size_t>(col[k + 1])];
        s2 += val[k + 2] * xj[static_cast<std::size_t>(col[k + 2])];
        s3 += val[k + 3] * xj[static_cast<std::size_t>(col[k + 3])];
      }
      for (; k < e; ++k) s0 += val[k] * xj[static_cast<std::size_t>(col[k])];
      const double s = (s0 + s1) + (s2 + s3);
      yj[r] = beta == 0.0 ? alpha * s : alpha * s + beta * yj[r];
    }
  }
}
}  // namespace

int multiplyThreads(const CrsMatrix& A, const MultiVector& X, const MultiVector& Y, int threads) {
  if (threads <= 0) threads = blasThreads();
  if (!A.isFillComplete() || &X == &Y || !X.isConstantStride() || !Y.isConstantStride()) return 0;
  const auto graph = A.getCrsGraph();
  if (!graph->getImporter().is_null() || !graph->getExporter().is_null()) return 0;
  if (X.getNumVectors() != Y.getNumVectors() || X.getLocalLength() != A.getColMap()->getNodeNumElements() ||
      Y.getLocalLength() != A.getRowMap()->getNodeNumElements())
    return 0;
  const double work = static_cast<double>(A.getNodeNumEntries()) * static_cast<double>(X.getNumVectors());
  if (threads <= 1 || work < kMinimumWork) return 1;
  return std::min<int>(threads, static_cast<int>(std::max<std::size_t>(1, A.getNodeNumRows() / 64)));
}

void multiply(const CrsMatrix& A, const MultiVector& X, MultiVector& Y, double alpha, double beta, int asked) {
  if (&X != &Y) {
    // Two views of one block whose memory overlaps: Tpetra's apply (13.2)
    // copies X only when X and Y are the same vectors, and on columns 0-6
    // and 1-7 of one block it overwrote columns of X before reading them
    // (SparseProduct.OverwritesNaNAndCopiesOverlappingViews). X is copied.
    bool overlap = false;
    {
      const auto xv = X.getLocalViewHost(Tpetra::Access::ReadOnly);
      const auto yv = Y.getLocalViewHost(Tpetra::Access::ReadOnly);
      const double *x0 = xv.data(), *x1 = x0 + xv.span(), *y0 = yv.data(), *y1 = y0 + yv.span();
      overlap = x0 < y1 && y0 < x1;
    }
    if (overlap) {
      const MultiVector copy(X, Teuchos::Copy);
      multiply(A, copy, Y, alpha, beta, asked);
      return;
    }
  }
  const int threads = multiplyThreads(A, X, Y, asked);
  if (threads <= 0) {  // also X and Y the same vectors, which Tpetra's apply copies itself
    A.apply(X, Y, Teuchos::NO_TRANS, alpha, beta);
    return;
  }
  // Without an importer the column map is the domain map and X's local
  // rows are the columns' local indices (Tpetra's own fast path).
  const auto local = A.getLocalMatrixHost();
  const auto rowMap = local.graph.row_map;
  const auto entries = local.graph.entries;
  const auto values = local.values;
  const std::size_t n = A.getNodeNumRows();
  // The local matrix's own row offsets, read in place (copied per call
  // before: an O(n) pass for nothing).
  static_assert(std::is_same_v<std::remove_const_t<std::remove_pointer_t<decltype(rowMap.data())>>, std::size_t>,
                "Tpetra's row offsets are size_t");
  const std::size_t* rowPtr = rowMap.data();
  const auto xv = X.getLocalViewHost(Tpetra::Access::ReadOnly);
  const auto yv = beta == 0.0 ? Y.getLocalViewHost(Tpetra::Access::OverwriteAll)
                              : Y.getLocalViewHost(Tpetra::Access::ReadWrite);
  const int nv = static_cast<int>(X.getNumVectors());
  const std::size_t ldx = xv.stride(1), ldy = yv.stride(1);
  const double* x = xv.data();
  double* y = yv.data();
  const LocalOrdinal* col = entries.data();
  const double* val = values.data();
  // Rows split so that each thread has about the same number of entries.
  std::vector<std::size_t> split(static_cast<std::size_t>(threads) + 1, n);
  split[0] = 0;
  const std::size_t nnz = rowPtr[n];
  for (int t = 1; t < threads; ++t) {
    const std::size_t target = nnz / static_cast<std::size_t>(threads) * static_cast<std::size_t>(t);
    split[static_cast<std::size_t>(t)] =
        static_cast<std::size_t>(std::lower_bound(rowPtr, rowPtr + n + 1, target) - rowPtr);
  }
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) {
    const std::size_t r0 = split[static_cast<std::size_t>(t)], r1 = std::max(r0, split[static_cast<std::size_t>(t) + 1]);
    try {
      pool.emplace_back(rows, rowPtr, col, val, x, ldx, y, ldy, nv, alpha, beta, r0, r1);
    } catch (const std::system_error&) {  // no thread to be had: these rows here
      rows(rowPtr, col, val, x, ldx, y, ldy, nv, alpha, beta, r0, r1);
    }
  }
  rows(rowPtr, col, val, x, ldx, y, ldy, nv, alpha, beta, 0, split[1]);
  for (auto& th : pool) th.join();
}

void multiplyAbsolute(const CrsMatrix& A, const MultiVector& X, MultiVector& Y) {
  const std::size_t nc = X.getNumVectors();
  MultiVector absX(X.getMap(), nc, false);
  absX.abs(X);
  // A null importer means the column map is the domain map.
  const auto importer = A.getGraph()->getImporter();
  Teuchos::RCP<MultiVector> columns;
  if (!importer.is_null()) {
    columns = Teuchos::rcp(new MultiVector(A.getColMap(), nc, false));
    columns->doImport(absX, *importer, Tpetra::INSERT);
  }
  const MultiVector& xc = importer.is_null() ? absX : *columns;
  const auto exporter = A.getGraph()->getExporter();
  MultiVector rowsOut(A.getRowMap(), nc, false);
  {
    const auto x = xc.getLocalViewHost(Tpetra::Access::ReadOnly);
    auto y = rowsOut.getLocalViewHost(Tpetra::Access::OverwriteAll);
    CrsMatrix::local_inds_host_view_type cols;
    CrsMatrix::values_host_view_type vals;
    const std::size_t nrows = A.getNodeNumRows();
    for (std::size_t l = 0; l < nrows; ++l) {
      A.getLocalRowView(static_cast<LocalOrdinal>(l), cols, vals);
      for (std::size_t j = 0; j < nc; ++j) {
        double sum = 0.0;
        for (std::size_t k = 0; k < cols.extent(0); ++k)
          sum += std::abs(vals(k)) * x(static_cast<std::size_t>(cols(k)), j);
        y(l, j) = sum;
      }
    }
  }
  if (exporter.is_null()) {
    Y.assign(rowsOut);
  } else {
    Y.putScalar(0.0);
    Y.doExport(rowsOut, *exporter, Tpetra::ADD);
  }
}

std::vector<char> roundingOnly(const MultiVector& AX, const MultiVector& absAX,
                               const std::vector<GlobalOrdinal>& ignored) {
  const std::size_t nc = AX.getNumVectors();
  std::vector<int> above(nc, 0), anyAbove(nc, 0);
  const auto map = AX.getMap();
  std::vector<char> skip(map->getNodeNumElements(), 0);
  for (GlobalOrdinal g : ignored) {
    const auto l = map->getLocalElement(g);
    if (l != Teuchos::OrdinalTraits<LocalOrdinal>::invalid()) skip[static_cast<std::size_t>(l)] = 1;
  }
  {
    const auto r = AX.getLocalViewHost(Tpetra::Access::ReadOnly);
    const auto b = absAX.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (std::size_t j = 0; j < nc; ++j)
      for (std::size_t l = 0; l < skip.size() && !above[j]; ++l)
        if (!skip[l] && std::abs(r(l, j)) > kProductRounding * b(l, j)) above[j] = 1;
  }
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_MAX, static_cast<int>(nc), above.data(), anyAbove.data());
  std::vector<char> out(nc);
  for (std::size_t j = 0; j < nc; ++j) out[j] = anyAbove[j] == 0;
  return out;
}

}  // namespace cms
