#include "ArpackEigensolver.hpp"

#include <arpack/parpack.h>
#include <mpi.h>

#include <algorithm>
#include <random>
#include <vector>

#include <Tpetra_MultiVector.hpp>

#include "cms/core/HashRandom.hpp"
#include "cms/core/MpiComm.hpp"

namespace cms::eigen::detail {

namespace {

/// y = A x on raw local arrays, through Tpetra vectors on the operator's map.
void applyRaw(const Operator& A, const double* x, double* y) {
  const auto map = A.getDomainMap();
  const size_t n = map->getNodeNumElements();
  MultiVector X(map, 1), Y(map, 1);
  {
    auto xv = X.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (size_t i = 0; i < n; ++i) xv(i, 0) = x[i];
  }
  A.apply(X, Y);
  auto yv = Y.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (size_t i = 0; i < n; ++i) y[i] = yv(i, 0);
}

std::string infoMessage(int info, bool saupd) {
  switch (info) {
    case 0: return "";
    case 1: return "maximum number of iterations taken";
    case 3: return "no shifts could be applied during an implicit restart: increase NCV";
    case -9999: return "could not build an Arnoldi factorisation";
    default:
      return std::string(saupd ? "pdsaupd" : "pdnaupd") + " info = " + std::to_string(info);
  }
}

}  // namespace

ArpackOutcome arpackSolve(const Operator& op, const Operator* inner, bool symmetric, int nev,
                          int ncv, double tol, int maxIterations) {
  const auto map = op.getDomainMap();
  const auto comm = map->getComm();
  const MPI_Fint fcomm = MPI_Comm_c2f(rawMpiComm(*comm));
  const int n = static_cast<int>(map->getNodeNumElements());
  const bool generalised = symmetric && inner != nullptr;
  const char* bmat = generalised ? "G" : "I";
  const char* which = "LM";

  // A deterministic start vector, the same for any rank count (seeded by global id).
  std::vector<double> resid(std::max(n, 1));
  for (int i = 0; i < n; ++i) resid[i] = hashSigned(map->getGlobalElement(i), 17u);
  const int ldv = std::max(n, 1);
  std::vector<double> v(static_cast<size_t>(ldv) * ncv), workd(3 * ldv);
  const int lworkl = symmetric ? ncv * (ncv + 8) : 3 * ncv * ncv + 6 * ncv;
  std::vector<double> workl(lworkl);
  int iparam[11] = {0}, ipntr[14] = {0};
  iparam[0] = 1;  // exact shifts
  iparam[2] = maxIterations;
  iparam[6] = generalised ? 3 : 1;
  int ido = 0, info = 1;  // info = 1: use resid as the start vector

  ArpackOutcome out;
  std::vector<double> tmp(n);
  while (true) {
    if (symmetric)
      pdsaupd_c(fcomm, &ido, bmat, n, which, nev, tol, resid.data(), ncv, v.data(), ldv, iparam,
                ipntr, workd.data(), workl.data(), lworkl, &info);
    else
      pdnaupd_c(fcomm, &ido, bmat, n, which, nev, tol, resid.data(), ncv, v.data(), ldv, iparam,
                ipntr, workd.data(), workl.data(), lworkl, &info);
    double* x = workd.data() + ipntr[0] - 1;
    double* y = workd.data() + ipntr[1] - 1;
    if (ido == -1 || ido == 1) {
      applyRaw(op, x, y);  // mode 3: OP = (K* + s I*)^-1 I* already includes B
    } else if (ido == 2) {
      applyRaw(*inner, x, y);
    } else {
      break;
    }
  }
  out.iterations = iparam[2];
  out.info = info;
  out.message = infoMessage(info, symmetric);
  if (info < 0) return out;

  // Ritz vectors.
  const int nconv = iparam[4];
  std::vector<int> select(ncv, 1);
  std::vector<double> z(static_cast<size_t>(ldv) * (nev + 1));
  int infoE = 0;
  if (symmetric) {
    std::vector<double> d(nev);
    pdseupd_c(fcomm, 1, "A", select.data(), d.data(), z.data(), ldv, 0.0, bmat, n, which, nev,
              tol, resid.data(), ncv, v.data(), ldv, iparam, ipntr, workd.data(), workl.data(),
              lworkl, &infoE);
  } else {
    std::vector<double> dr(nev + 1), di(nev + 1), workev(3 * ncv);
    pdneupd_c(fcomm, 1, "A", select.data(), dr.data(), di.data(), z.data(), ldv, 0.0, 0.0,
              workev.data(), bmat, n, which, nev, tol, resid.data(), ncv, v.data(), ldv, iparam,
              ipntr, workd.data(), workl.data(), lworkl, &infoE);
  }
  if (infoE != 0) {
    out.info = infoE;
    out.message = std::string(symmetric ? "pdseupd" : "pdneupd") + " info = " + std::to_string(infoE);
    return out;
  }
  // For pdneupd, a complex pair occupies two columns (real, imaginary part):
  // both are wanted as basis vectors, so take every converged column.
  const int cols = std::min(nconv + (symmetric ? 0 : 1), symmetric ? nev : nev + 1);
  out.numConverged = nconv;
  out.vectors = Teuchos::rcp(new MultiVector(map, std::max(cols, 1)));
  auto zv = out.vectors->getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < n; ++i) zv(i, j) = z[static_cast<size_t>(j) * ldv + i];
  return out;
}

}  // namespace cms::eigen::detail
