// a A + b B for two fill-complete sparse matrices, on A's own graph when B
// shares it (an assembled substructure's M, K, G1, KT1 and KS1 share one:
// packages/fem), so that the sum costs its values only, not a graph of its
// own (a third of a matrix's memory: MatrixMatrix::add makes one). The
// values are a x + b y entry by entry, as MatrixMatrix::add computes them.
#pragma once

#include "cms/core/TpetraTypes.hpp"

namespace cms {

/// a A + b B (collective when the graphs differ: Tpetra::MatrixMatrix::add).
Teuchos::RCP<CrsMatrix> matrixSum(double a, const CrsMatrix& A, double b, const CrsMatrix& B);

}  // namespace cms
