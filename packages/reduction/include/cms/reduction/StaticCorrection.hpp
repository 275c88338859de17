// The static correction of a substructure: x = K_b^-1 r, K_b its stiffness
// with the rows its caller holds (every caller holds its attachment only,
// as theory §11.8 has it; with the children's interface rows held too it is
// the fixed-interface flexibility Craig-Bampton's constraint modes leave
// out). Applied to the residual of a reduced mode's full equations it gives
// the mode's error estimate (doc/theory.md §11.8). One CHOLMOD factorisation
// of the substructure (never of the assembled structure), then one solve per
// block of residuals. Collective.
#pragma once

#include <memory>

#include "cms/core/TpetraTypes.hpp"
#include "cms/reduction/RitzBasis.hpp"

namespace cms::substructure {
class Substructure;
}

namespace cms::reduction {
namespace detail {
class HeldStiffness;
}

class StaticCorrection {
public:
  /// Throws cms::NumericalError naming the substructure if K with the
  /// boundary held is not positive definite.
  StaticCorrection(const substructure::Substructure& s, const SubstructureBoundary& boundary);
  /// One already factored (a basis's own: RitzBasis::flexibility).
  explicit StaticCorrection(std::unique_ptr<detail::HeldStiffness> factored);
  /// The flexibility of `s` with `boundary` held made from `factor`, a
  /// factorisation already made (the prestress solve's, kept: theory §11.4)
  /// when it factored this very matrix (the same K, the same held rows, a
  /// method the "Auto" choice would pick); null otherwise. Nothing is
  /// factored either way. Collective.
  static std::shared_ptr<const StaticCorrection> adopting(const substructure::Substructure& s,
                                                          const SubstructureBoundary& boundary,
                                                          const std::shared_ptr<const HeldFactor>& factor);
  ~StaticCorrection();
  StaticCorrection(const StaticCorrection&) = delete;
  StaticCorrection& operator=(const StaticCorrection&) = delete;
  /// X = K_b^-1 R with R's held and interface rows ignored; X is zero there.
  void solve(const MultiVector& R, MultiVector& X) const;
  /// The flops its factorisation took (CHOLMOD's count with its chosen
  /// ordering, or MUMPS's): a forecast for another factorisation of the
  /// same pattern (SynthesizedStructure::coverage's Sturm count).
  double factorFlops() const;

private:
  std::unique_ptr<detail::HeldStiffness> K_;
};

}  // namespace cms::reduction
