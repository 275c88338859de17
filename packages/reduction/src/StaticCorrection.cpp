#include "cms/reduction/StaticCorrection.hpp"

#include <algorithm>
#include <stdexcept>

#include <Teuchos_TestForException.hpp>

#include "HeldStiffness.hpp"

namespace cms::reduction {

namespace {
/// The attachment and the children's interface rows, sorted, unique.
std::vector<GlobalOrdinal> heldRows(const SubstructureBoundary& boundary) {
  std::vector<GlobalOrdinal> held(boundary.held);
  for (const auto& rows : boundary.interfaces) held.insert(held.end(), rows.begin(), rows.end());
  std::sort(held.begin(), held.end());
  held.erase(std::unique(held.begin(), held.end()), held.end());
  return held;
}
}  // namespace

StaticCorrection::StaticCorrection(const substructure::Substructure& s, const SubstructureBoundary& boundary)
    : K_(std::make_unique<detail::HeldStiffness>(s, heldRows(boundary))) {}

std::shared_ptr<const StaticCorrection> StaticCorrection::adopting(const substructure::Substructure& s,
                                                                   const SubstructureBoundary& boundary,
                                                                   const std::shared_ptr<const HeldFactor>& factor) {
  auto held = heldRows(boundary);
  // "Auto": the choice a StaticCorrection made outside any reduction makes.
  if (!factor || !detail::factorFits(*factor, s, held, "Auto")) return nullptr;
  const detail::DirectSolverScope automatic("Auto");
  const detail::OfferedFactorScope offered(factor);
  auto K = std::make_unique<detail::HeldStiffness>(s, std::move(held));
  // HeldStiffness asks factorFits with the same choice: it adopts.
  TEUCHOS_TEST_FOR_EXCEPTION(!offered.adopted(), std::logic_error,
                             s.name() << ": a factor that fits was not adopted (factored again)");
  return std::make_shared<const StaticCorrection>(std::move(K));
}

StaticCorrection::StaticCorrection(std::unique_ptr<detail::HeldStiffness> factored) : K_(std::move(factored)) {}

StaticCorrection::~StaticCorrection() = default;

void StaticCorrection::solve(const MultiVector& R, MultiVector& X) const { K_->solve(R, X); }

double StaticCorrection::factorFlops() const { return K_->factorFlops(); }

}  // namespace cms::reduction
