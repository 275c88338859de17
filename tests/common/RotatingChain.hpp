// Test adapters from models::RotatingChain to the eigen layer's systems.
#pragma once

#include "cms/eigen/GyroscopicSystem.hpp"
#include "cms/eigen/SparseGyroscopicSystem.hpp"
#include "cms/models/RotatingChain.hpp"

namespace cms::fixtures {

using ChainSpec = models::RotatingChain;

inline eigen::GyroscopicSystem denseChain(const ChainSpec& s) {
  auto d = s.dense();
  return {d.M, d.G, d.K};
}

inline eigen::SparseGyroscopicSystem sparseChain(const ChainSpec& s,
                                                 const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  auto d = s.distributed(comm);
  return {d.M, d.G, d.K};
}

}  // namespace cms::fixtures
