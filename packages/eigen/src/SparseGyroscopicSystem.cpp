#include "cms/eigen/SparseGyroscopicSystem.hpp"

#include <cmath>
#include <random>
#include <vector>

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/HashRandom.hpp"

namespace cms::eigen {

bool SparseGyroscopicSystem::damped() const {
  return (!D.is_null() && D->getFrobeniusNorm() > 0.0) || (!N.is_null() && N->getFrobeniusNorm() > 0.0);
}

GlobalOrdinal SparseGyroscopicSystem::globalSize() const {
  return static_cast<GlobalOrdinal>(M->getRowMap()->getGlobalNumElements());
}

namespace {
/// Random vector seeded by global id: the same probe for any rank count.
MultiVector probe(const Teuchos::RCP<const Map>& map, unsigned seed) {
  MultiVector x(map, 1);
  auto v = x.getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (size_t i = 0; i < map->getNodeNumElements(); ++i) v(i, 0) = hashSigned(map->getGlobalElement(i), seed);
  return x;
}
}  // namespace

void SparseGyroscopicSystem::validate(double relTol) const {
  std::vector<std::pair<const Teuchos::RCP<const CrsMatrix>*, const char*>> mats = {
      {&M, "M"}, {&G, "G"}, {&K, "K"}};
  if (!D.is_null()) mats.push_back({&D, "D"});
  if (!N.is_null()) mats.push_back({&N, "N"});
  const auto skew = [](const char* name) { return name[0] == 'G' || name[0] == 'N'; };
  for (const auto& [A, name] : mats) {
    CMS_INPUT_CHECK(A->is_null(), "SparseGyroscopicSystem: " << name << " is missing");
    CMS_INPUT_CHECK(!(*A)->isFillComplete(),
                    "SparseGyroscopicSystem: " << name << " is not fill-complete");
  }
  const auto rowMap = M->getRowMap();
  CMS_INPUT_CHECK(rowMap->getGlobalNumElements() == 0, "SparseGyroscopicSystem: M is empty");
  for (const auto& [A, name] : mats) {
    const auto& a = **A;
    CMS_INPUT_CHECK(!a.getRowMap()->isSameAs(*rowMap) || !a.getDomainMap()->isSameAs(*rowMap) ||
                        !a.getRangeMap()->isSameAs(*rowMap),
                    "SparseGyroscopicSystem: " << name << " ("
                        << a.getRangeMap()->getGlobalNumElements() << "x"
                        << a.getDomainMap()->getGlobalNumElements()
                        << ") does not share M's row, domain and range map ("
                        << rowMap->getGlobalNumElements() << " rows)");
  }
  // NaN/Inf and the diagonal of M, reduced so every rank throws together.
  long long badRow[5] = {-1, -1, -1, -1, -1}, badDiag = -1;
  int m = 0;
  for (const auto& [A, name] : mats) {
    const auto& a = **A;
    for (size_t i = 0; i < a.getNodeNumRows() && badRow[m] < 0; ++i) {
      CrsMatrix::local_inds_host_view_type cols;
      CrsMatrix::values_host_view_type vals;
      a.getLocalRowView(static_cast<LocalOrdinal>(i), cols, vals);
      for (size_t e = 0; e < vals.extent(0); ++e)
        if (!std::isfinite(vals(e))) badRow[m] = a.getRowMap()->getGlobalElement(i);
    }
    ++m;
  }
  {
    Tpetra::Vector<double> d(rowMap);
    M->getLocalDiagCopy(d);
    auto dv = d.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (size_t i = 0; i < rowMap->getNodeNumElements() && badDiag < 0; ++i)
      if (!(dv(i, 0) > 0.0)) badDiag = rowMap->getGlobalElement(i);
  }
  const auto comm = rowMap->getComm();
  // (mats has the same entries on every rank: D and N are null or not on all.)
  long long worst[6], local[6] = {badRow[0], badRow[1], badRow[2], badRow[3], badRow[4], badDiag};
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, 6, local, worst);
  for (std::size_t k = 0; k < mats.size(); ++k)
    CMS_INPUT_CHECK(worst[k] >= 0, "SparseGyroscopicSystem: " << mats[k].second << " has a NaN or Inf in row "
                                                             << worst[k]);
  CMS_INPUT_CHECK(worst[5] >= 0, "SparseGyroscopicSystem: M is not positive definite: diagonal entry "
                                     "of row " << worst[5] << " is not positive");

  // Structure by random probes.
  const MultiVector x = probe(rowMap, 1u), y = probe(rowMap, 2u);
  const double nx = x.getVector(0)->norm2(), ny = y.getVector(0)->norm2();
  for (const auto& [A, name] : mats) {
    const double sign = skew(name) ? -1.0 : 1.0;
    MultiVector Ay(rowMap, 1), Ax(rowMap, 1);
    (*A)->apply(y, Ay);
    (*A)->apply(x, Ax);
    const double xAy = x.getVector(0)->dot(*Ay.getVector(0));
    const double yAx = y.getVector(0)->dot(*Ax.getVector(0));
    const double defect = std::abs(xAy - sign * yAx);
    const double scale = (*A)->getFrobeniusNorm() * nx * ny;
    CMS_INPUT_CHECK(defect > relTol * scale && scale > 0.0,
                    "SparseGyroscopicSystem: " << name << " is not " << (skew(name) ? "skew-symmetric" : "symmetric")
                                               << ": |x^T A y " << (skew(name) ? "+" : "-")
                                               << " y^T A x| / (||A||_F ||x|| ||y||) = "
                                               << defect / scale << " > " << relTol);
  }
}

}  // namespace cms::eigen
