#include "cms/analysis/StrategyComparison.hpp"

#include <chrono>

#include <Teuchos_Array.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/ParameterReading.hpp"
#include "cms/core/PeakMemory.hpp"

namespace cms::analysis {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

Teuchos::RCP<const Teuchos::ParameterList> StrategyComparison::validParameters() {
  auto p = Teuchos::rcp(new Teuchos::ParameterList("Strategy Comparison"));
  p->set("Counts", Teuchos::Array<int>(std::vector<int>{2, 4, 8}), "vectors per substructure for each basis but Guyan (each >= 1)");
  p->set("Strategies", Teuchos::Array<std::string>(std::vector<std::string>{"Guyan", "Admissible", "Modes", "Craig-Bampton"}),
         "the bases compared (reduction::validParameters' \"Basis\" values)");
  p->set("Speed Factor", 1.0, "every nominal spin rate is multiplied by this (>= 0)");
  return p;
}

StrategyComparison::StrategyComparison(const synthesis::AssembledStructure& structure, Teuchos::ParameterList solve,
                                       const Teuchos::ParameterList& options)
    : structure_(structure), solve_(std::move(solve)), options_(options) {
  checkKeys(options_, *validParameters(), "Strategy Comparison");
  try {
    options_.validateParametersAndSetDefaults(*validParameters());
  } catch (const std::exception& e) {
    throw InputError(std::string("Strategy Comparison: ") + e.what());
  }
  for (int k : options_.get<Teuchos::Array<int>>("Counts"))
    CMS_INPUT_CHECK(k < 1, "Strategy Comparison: \"Counts\" has " << k << "; each must be >= 1 (--counts)");
}

ComparisonResult StrategyComparison::run(
    const std::function<void(const StrategyRow*, const StrategyOutcome*)>& onResult) const {
  auto speeds = structure_.nominalSpeeds();
  for (double& v : speeds) v *= options_.get<double>("Speed Factor");
  const int nModes = solve_.get<int>("Number of Modes");
  ComparisonResult out;
  auto other = [&](StrategyOutcome o) {
    out.others.push_back(std::move(o));
    if (onResult) onResult(nullptr, &out.others.back());
  };

  // 1. The truth: without a converged truth there is nothing to compare with.
  const auto t0 = Clock::now();
  const auto truth = synthesis::SynthesizedStructure::synthesize(structure_, true);
  out.truthModes = truth.solve(speeds, solve_);
  out.truthSeconds = since(t0);
  out.truthSize = truth.size();
  if (out.truthModes.result.status != eigen::SolveStatus::Converged) return out;
  CMS_INPUT_CHECK(static_cast<int>(out.truthModes.result.modes.size()) < nModes,
                  "the truth model gave " << out.truthModes.result.modes.size() << " modes of " << nModes);

  // 2. Every strategy at every count: reduce, solve, compare.
  for (const std::string& basis : options_.get<Teuchos::Array<std::string>>("Strategies")) {
    for (int k : basis == "Guyan" ? Teuchos::Array<int>(1, 0) : options_.get<Teuchos::Array<int>>("Counts")) {
      try {
        const auto t1 = Clock::now();
        const auto s = synthesis::SynthesizedStructure::synthesize(structure_, synthesis::sameReduction(structure_, basis, k));
        const double reduceSeconds = since(t1);
        if (s.size() < nModes) {
          other({basis, k, false, {}, std::to_string(s.size()) + " coordinates, fewer than the " +
                                          std::to_string(nModes) + " modes compared"});
          continue;
        }
        const auto m = s.solve(speeds, solve_);
        if (m.result.status != eigen::SolveStatus::Converged) {
          other({basis, k, true, m.result.status, m.result.reason});
          continue;
        }
        if (static_cast<int>(m.result.modes.size()) < nModes) {
          other({basis, k, false, {}, "the solve gave " + std::to_string(m.result.modes.size()) + " modes (" +
                                          m.result.reason + ")"});
          continue;
        }
        StrategyRow row{basis, k, s.size(), reduceSeconds, m.seconds, peakRssMiB(),
                        compareWithTruth(s, m, truth, out.truthModes, nModes), 0.0, {}};
        for (const auto& r : s.reductions()) row.perSubstructure.push_back(r.coordinates);
        const auto estimates = s.errorEstimates(m);
        for (int j = 0; j < nModes && j < static_cast<int>(estimates.size()); ++j)
          row.estimate = std::max(row.estimate, estimates[j]);
        out.rows.push_back(std::move(row));
        if (onResult) onResult(&out.rows.back(), nullptr);
      } catch (const InputError& e) {
        other({basis, k, false, {}, e.what()});
      }
    }
  }
  return out;
}

}  // namespace cms::analysis
