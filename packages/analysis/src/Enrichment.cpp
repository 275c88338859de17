#include "cms/analysis/Enrichment.hpp"

#include <algorithm>
#include <memory>
#include <optional>
#include <sstream>

#include "cms/core/Error.hpp"
#include "cms/substructure/Substructure.hpp"

namespace cms::analysis {

Enrichment enrichToAccuracy(const synthesis::AssembledStructure& structure, const std::vector<double>& speeds,
                            const Teuchos::ParameterList& solveParams, double target,
                            std::vector<Teuchos::ParameterList>& reductions) {
  const int nModes = solveParams.get<int>("Number of Modes");
  const std::size_t ns = structure.numSubstructures();
  std::vector<bool> tunable(ns, false);
  for (std::size_t k = 0; k < ns; ++k) {
    const std::string basis = reductions[k].get<std::string>("Basis", "Admissible");
    // Copies follow their prototype (theory §15.2): it alone is grown.
    tunable[k] = structure.assembled(k) && basis != "Full" && basis != "Guyan" && basis != "Partitioned" &&
                structure.prototypeOf(k) == k;
  }
  auto mirrorCopies = [&] {
    for (std::size_t k = 0; k < ns; ++k)
      if (structure.prototypeOf(k) != k) reductions[k] = reductions[structure.prototypeOf(k)];
  };
  mirrorCopies();
  Enrichment out;
  // Grows substructure k; false when it cannot grow any more.
  auto grow = [&](std::size_t k) {
    auto& r = reductions[k];
    const double cutoff = r.get<double>("Cutoff Frequency", 0.0);
    const long long limit = structure.assembled(k)->dofs().rows() - 6;
    if (cutoff > 0.0) {
      r.set("Cutoff Frequency", 1.5 * cutoff);
      return true;
    }
    const int v = r.get<int>("Vectors", 6);
    if (v >= limit) return false;
    r.set("Vectors", static_cast<int>(std::min<long long>(limit, v + std::max(2, v / 4))));
    return true;
  };
  // Each step rebuilds only the substructure it grew: the others keep their
  // bases, and every substructure its factorisations (synthesize's previous).
  std::optional<synthesis::SynthesizedStructure> previous;
  for (int step = 0; step < 60; ++step) {
    previous = synthesis::SynthesizedStructure::synthesize(structure, reductions,
                                                           synthesis::ReductionSchedule::Concurrent,
                                                           previous ? &*previous : nullptr);
    const auto& s = *previous;
    bool grown = false;
    if (s.size() < nModes) {
      for (std::size_t k = 0; k < ns; ++k)
        if (tunable[k]) grown = grow(k) || grown;
      if (!grown) break;
      continue;
    }
    const auto m = s.solve(speeds, solveParams);
    std::vector<std::vector<double>> shares;  // of each estimate, per substructure
    const auto e = s.errorEstimates(m, &shares);
    int worst = -1;
    for (int j = 0; j < nModes && j < static_cast<int>(e.size()); ++j)
      if (worst < 0 || e[j] > e[worst]) worst = j;
    out.worstEstimate = worst >= 0 ? std::max(0.0, e[worst]) : 0.0;
    std::ostringstream os;
    os.precision(3);
    os << "step " << step << ": " << s.size() << " coordinates, worst estimated error " << out.worstEstimate;
    if (worst >= 0) os << " (mode " << worst + 1 << ")";
    // Only a converged solve reaches the target (its status was unread: a
    // solve that had not converged could end the enrichment; a review).
    if (m.result.status != eigen::SolveStatus::Converged) os << " (the solve did not converge: " << m.result.reason << ")";
    if (out.worstEstimate <= target && static_cast<int>(m.result.modes.size()) >= nModes &&
        m.result.status == eigen::SolveStatus::Converged) {
      out.reached = true;
      out.synthesis = std::make_shared<const synthesis::SynthesizedStructure>(s);
      os << ": target " << target << " reached";
      out.notes.push_back(os.str());
      break;
    }
    // The reducible substructure with the largest share of the worst mode's
    // estimate (its term r_s^H K_s^-1 r_s, theory §11.8: where that mode's
    // error comes from); if it is complete, the next one. By the worst
    // mode's kinetic energy instead, rotor-chain to 1e-6 grew the blade five
    // times without gain while the tip's truncation made the error.
    std::vector<double> share(ns, 0.0);  // a prototype's share is its copies' together
    for (std::size_t k = 0; k < ns; ++k) share[structure.prototypeOf(k)] += shares.at(static_cast<std::size_t>(worst)).at(k);
    std::vector<std::pair<double, std::size_t>> order;
    for (std::size_t k = 0; k < ns; ++k)
      if (tunable[k]) order.push_back({-share[k], k});
    std::sort(order.begin(), order.end());
    for (const auto& [share, k] : order)
      if (grow(k)) {
        os << "; enriched " << structure.substructure(k).name;
        grown = true;
        break;
      }
    out.notes.push_back(os.str());
    if (!grown) break;
    mirrorCopies();
  }
  std::ostringstream os;
  os << (out.reached ? "reached" : "NOT reached") << "; bases:";
  for (std::size_t k = 0; k < ns; ++k)
    if (tunable[k]) {
      auto& r = reductions[k];
      os << ' ' << structure.substructure(k).name << " = ";
      if (r.get<double>("Cutoff Frequency", 0.0) > 0.0) os << "cut-off " << r.get<double>("Cutoff Frequency") << " Hz";
      else os << r.get<int>("Vectors", 6) << " vectors";
    }
  out.notes.push_back(os.str());
  return out;
}

}  // namespace cms::analysis
