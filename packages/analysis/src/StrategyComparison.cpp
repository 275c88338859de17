#include "cms/analysis/StrategyComparison.hpp"

#include <Teuchos_Array.hpp>

#include "cms/core/Error.hpp"
#include "cms/core/ParameterReading.hpp"
#include "cms/core/PeakMemory.hpp"
#include "cms/core/Stopwatch.hpp"

namespace cms::analysis {

Teuchos::RCP<const Teuchos::ParameterList> StrategyComparison::validParameters() {
  auto p = Teuchos::rcp(new Teuchos::ParameterList("Strategy Comparison"));
  p->set("Counts", Teuchos::Array<int>(std::vector<int>{2, 4, 8}), "vectors per substructure for each basis but Guyan (each >= 1); for Partitioned, its cut-off in Hz");
  p->set("Strategies", Teuchos::Array<std::string>(std::vector<std::string>{"Guyan", "Admissible", "Modes", "Craig-Bampton"}),
         "the bases compared (reduction::validParameters' \"Basis\" values)");
  p->set("Speed Factor", 1.0, "every nominal spin rate is multiplied by this (>= 0)");
  p->set("Error Estimates", true, "each row's largest estimated error (theory §11.8; costs a factorisation per substructure)");
  return p;
}

StrategyComparison::StrategyComparison(const synthesis::AssembledStructure& structure, Teuchos::ParameterList solve,
                                       const Teuchos::ParameterList& options)
    : structure_(structure), solve_(std::move(solve)), options_(options) {
  validateOptions(options_, *validParameters(), "Strategy Comparison");
  for (int k : options_.get<Teuchos::Array<int>>("Counts"))
    CMS_INPUT_CHECK(k < 1, "Strategy Comparison: \"Counts\" has " << k << "; each must be >= 1 (--counts)");
}

std::vector<double> StrategyComparison::scaledSpeeds() const {
  auto speeds = structure_.nominalSpeeds();
  for (double& v : speeds) v *= options_.get<double>("Speed Factor");
  return speeds;
}

ComparisonResult StrategyComparison::run(
    const std::function<void(const StrategyRow*, const StrategyOutcome*)>& onResult) const {
  const auto speeds = scaledSpeeds();
  const int nModes = solve_.get<int>("Number of Modes");

  // 1. The truth: without a converged truth there is nothing to compare with.
  const Stopwatch t0;
  const auto model = synthesis::SynthesizedStructure::synthesize(structure_, true);
  requireComparableTruth(model);  // before its solve
  auto truthModes = solveForComparison(model, speeds, solve_);
  const double truthSeconds = t0.seconds();
  ComparisonResult out;
  if (truthModes.result.status == eigen::SolveStatus::Converged) {
    CMS_INPUT_CHECK(static_cast<int>(truthModes.result.modes.size()) < nModes,
                    "the truth model gave " << truthModes.result.modes.size() << " modes of " << nModes);
    out = run({&model, &truthModes, truthSeconds}, {{}, onResult});
  }
  out.truthSize = model.size();
  out.truthSeconds = truthSeconds;
  out.truthModes = std::move(truthModes);
  return out;
}

ComparisonResult StrategyComparison::run(const SolvedTruth& truth, const StrategyHooks& hooks) const {
  const auto speeds = scaledSpeeds();
  const int nModes = solve_.get<int>("Number of Modes");
  ComparisonResult out;
  out.truthSize = truth.model ? truth.model->size() : 0;
  out.truthSeconds = truth.seconds;
  auto other = [&](StrategyOutcome o) {
    out.others.push_back(std::move(o));
    if (hooks.onResult) hooks.onResult(nullptr, &out.others.back());
  };

  // 2. Every strategy at every count: reduce, solve, compare.
  for (const std::string& basis : options_.get<Teuchos::Array<std::string>>("Strategies")) {
    for (int k : basis == "Guyan" ? Teuchos::Array<int>(1, 0) : options_.get<Teuchos::Array<int>>("Counts")) {
      if (hooks.onStart) hooks.onStart(basis, k);
      long long dofs = 0;
      try {
        const Stopwatch t1;
        const auto s = synthesis::SynthesizedStructure::synthesize(structure_, synthesis::sameReduction(structure_, basis, k));
        const double reduceSeconds = t1.seconds();
        dofs = s.size();
        // A strategy made Full here drops a Modal Damping Ratio (no modal
        // coordinates): a less damped structure, not a row to compare.
        if (!s.modalDampingOmitted().empty()) {
          other({basis, k, false, {}, "a Full basis has no modal coordinates for the Modal Damping Ratio of '" +
                                          s.modalDampingOmitted().front() + "': not comparable", dofs});
          continue;
        }
        if (s.size() < nModes) {
          other({basis, k, false, {}, std::to_string(s.size()) + " coordinates, fewer than the " +
                                          std::to_string(nModes) + " modes compared", dofs});
          continue;
        }
        // Where the truth has modes beyond those compared, the reduced model
        // gets as many more (compareWithTruth pairs them all; bench_rotor's
        // truth, timed as a user's full solve, has none).
        const bool wider = truth.model && static_cast<int>(truth.modes->result.modes.size()) > nModes;
        const auto m = wider ? solveForComparison(s, speeds, solve_) : s.solve(speeds, solve_);
        if (m.result.status != eigen::SolveStatus::Converged) {
          other({basis, k, true, m.result.status, m.result.reason, dofs});
          continue;
        }
        if (static_cast<int>(m.result.modes.size()) < nModes) {
          other({basis, k, false, {}, "the solve gave " + std::to_string(m.result.modes.size()) + " modes (" +
                                          m.result.reason + ")", dofs});
          continue;
        }
        StrategyRow row;
        row.basis = basis;
        row.vectors = k;
        row.dofs = s.size();
        row.reduceSeconds = reduceSeconds;
        row.basesSeconds = s.basesSeconds();
        row.solveSeconds = m.seconds;
        row.peakMiB = peakRssMiB();
        row.compared = truth.model != nullptr;
        if (row.compared) row.accuracy = compareWithTruth(s, m, *truth.model, *truth.modes, nModes);
        for (const auto& r : s.reductions()) {
          row.perSubstructure.push_back(r.coordinates);
          if (r.adoptedPrestressFactor) row.adopted.push_back(r.name);
        }
        row.path = m.path;
        for (int j = 0; j < nModes; ++j) row.hz.push_back(m.result.modes[j].hz);
        if (options_.get<bool>("Error Estimates")) {
          // The compared modes' estimates only: the ones beyond serve the
          // pairing, and would be time the row does not need.
          const Stopwatch te;
          auto compared = m;
          if (static_cast<int>(compared.result.modes.size()) > nModes) compared.result.modes.resize(nModes);
          const auto estimates = s.errorEstimates(compared);
          row.estimateSeconds = te.seconds();
          for (int j = 0; j < nModes && j < static_cast<int>(estimates.size()); ++j)
            row.estimate = std::max(row.estimate, estimates[j]);
        }
        out.rows.push_back(std::move(row));
        if (hooks.onResult) hooks.onResult(&out.rows.back(), nullptr);
      } catch (const InputError& e) {
        other({basis, k, false, {}, e.what(), dofs});
      } catch (const NumericalError& e) {
        other({basis, k, true, eigen::SolveStatus::NumericalIssue, e.what(), dofs});
      }
    }
  }
  return out;
}

}  // namespace cms::analysis
