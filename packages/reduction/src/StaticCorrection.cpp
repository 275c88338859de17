#include "cms/reduction/StaticCorrection.hpp"

#include <algorithm>

#include "HeldStiffness.hpp"

namespace cms::reduction {

StaticCorrection::StaticCorrection(const substructure::Substructure& s, const SubstructureBoundary& boundary) {
  std::vector<GlobalOrdinal> held(boundary.held);
  for (const auto& rows : boundary.interfaces) held.insert(held.end(), rows.begin(), rows.end());
  std::sort(held.begin(), held.end());
  held.erase(std::unique(held.begin(), held.end()), held.end());
  K_ = std::make_unique<detail::HeldStiffness>(s, std::move(held));
}

StaticCorrection::StaticCorrection(std::unique_ptr<detail::HeldStiffness> factored) : K_(std::move(factored)) {}

StaticCorrection::~StaticCorrection() = default;

void StaticCorrection::solve(const MultiVector& R, MultiVector& X) const { K_->solve(R, X); }

}  // namespace cms::reduction
