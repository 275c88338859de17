#include "cms/analysis/TruncationStudy.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "cms/core/Error.hpp"
#include "cms/core/ParameterReading.hpp"

namespace cms::analysis {

Teuchos::RCP<const Teuchos::ParameterList> TruncationStudy::validParameters() {
  auto p = Teuchos::rcp(new Teuchos::ParameterList("Truncation Study"));
  p->set("Start", 2, "vectors per reducible substructure to start from (>= 0)");
  p->set("Step", 2, "vectors added per step (>= 1)");
  p->set("Accuracy", 1e-3, "target: largest estimated relative frequency error of the wanted modes (> 0)");
  p->set("Truth", false, "also solve the truth model and record the true error beside each estimate");
  p->set("Max Steps", 200, "steps before the search gives up (>= 1)");
  p->set("Speed Factor", 1.0, "every nominal spin rate is multiplied by this (>= 0)");
  return p;
}

TruncationStudy::TruncationStudy(const synthesis::AssembledStructure& structure, Teuchos::ParameterList solve,
                                 const Teuchos::ParameterList& options)
    : structure_(structure), solve_(std::move(solve)), options_(options) {
  validateOptions(options_, *validParameters(), "Truncation Study");
  CMS_INPUT_CHECK(options_.get<int>("Start") < 0 || options_.get<int>("Step") < 1,
                  "Truncation Study: \"Start\" must be >= 0 and \"Step\" >= 1 (--start, --step)");
  CMS_INPUT_CHECK(!(options_.get<double>("Accuracy") > 0),
                  "Truncation Study: \"Accuracy\" = " << options_.get<double>("Accuracy") << " must be positive");
  CMS_INPUT_CHECK(options_.get<int>("Max Steps") < 1, "Truncation Study: \"Max Steps\" must be >= 1");
}

TruncationResult TruncationStudy::run(
    const std::function<void(const TruncationStep&, const TruncationResult&)>& onStep) const {
  const auto& structure = structure_;
  auto speeds = structure.nominalSpeeds();
  for (double& v : speeds) v *= options_.get<double>("Speed Factor");
  const int nModes = solve_.get<int>("Number of Modes");
  const int start = options_.get<int>("Start"), step = options_.get<int>("Step");
  const double accuracy = options_.get<double>("Accuracy");
  TruncationResult result;

  // 1. The truth, only when asked: the cost a reduction exists to avoid.
  std::optional<synthesis::SynthesizedStructure> truth;
  synthesis::StructureModes truthModes;
  if (options_.get<bool>("Truth")) {
    truth = synthesis::SynthesizedStructure::synthesize(structure, true);
    requireComparableTruth(*truth);  // before its solve
    truthModes = solveForComparison(*truth, speeds, solve_);
    TEUCHOS_TEST_FOR_EXCEPTION(truthModes.result.status != eigen::SolveStatus::Converged, NumericalError,
                               "the truth model (every basis Full) did not converge ("
                                   << eigen::toString(truthModes.result.status) << ": " << truthModes.result.reason
                                   << "): no true errors to give");
    CMS_INPUT_CHECK(static_cast<int>(truthModes.result.modes.size()) < nModes,
                    "the truth model gave " << truthModes.result.modes.size() << " modes of " << nModes);
    result.truthSize = truth->size();
  }

  // 2. The reducible substructures (Admissible, Polynomial, Modes,
  // Craig-Bampton bases) start from "Start" vectors.
  const std::size_t ns = structure.numSubstructures();
  std::vector<Teuchos::ParameterList> red(ns);
  std::vector<int> count(ns, 0);
  std::vector<long long> limit(ns, 0);
  result.reducible.assign(ns, false);
  for (std::size_t q = 0; q < ns; ++q) {
    red[q] = structure.substructure(q).reduction;
    red[q].setName("Reduction");
    const std::string basis = red[q].get<std::string>("Basis", "Admissible");
    result.reducible[q] = structure.assembled(q) && basis != "Full" && basis != "Guyan" &&
                           basis != "Partitioned";  // its size follows the cut-off, not "Vectors"
    if (result.reducible[q]) {
      limit[q] = structure.assembled(q)->dofs().rows() - 6;
      count[q] = static_cast<int>(std::min<long long>(start, limit[q]));
      red[q].set("Vectors", count[q]);
    }
  }
  // Copies follow their prototype (theory §15.2): it alone is grown, and its
  // count stands for theirs.
  auto prototype = [&](std::size_t q) { return structure.prototypeOf(q); };
  for (std::size_t q = 0; q < ns; ++q) result.reducible[q] = result.reducible[q] && prototype(q) == q;

  // 3. One model: its largest estimated error over the wanted modes (theory §11.8).
  struct Model {
    double estimate = std::numeric_limits<double>::infinity();
    double trueError = std::numeric_limits<double>::quiet_NaN();
    long long dofs = 0;
    synthesis::StructureModes modes;
    int worst = -1;  ///< the wanted mode with the largest estimate
    std::vector<double> worstShares;  ///< each substructure's share of that estimate
    /// Kept so that a trial reuses the other substructures' bases and every
    /// factorisation (synthesize's `previous`), and for the energy shares.
    std::shared_ptr<const synthesis::SynthesizedStructure> synthesis;
    /// K > 0 and solved by the dense Meirovitch path, whose round-off the
    /// inclusion check allows for. The sparse path's factorisation shows K
    /// > 0 too, but its frequencies carry its eigensolver's error (1e-13
    /// relative measured on the rotor chain), which the check's round-off
    /// term does not know: there it is not checked, and the driver says so.
    bool definite = false;
    int trueMissing = -1, trueUnmatched = -1;  ///< compareWithTruth's counts ("Truth")
  };
  auto evaluate = [&](const std::vector<Teuchos::ParameterList>& r, const Model* from) {
    Model model;
    model.synthesis = std::make_shared<const synthesis::SynthesizedStructure>(synthesis::SynthesizedStructure::synthesize(
        structure, r, synthesis::ReductionSchedule::Concurrent, from ? from->synthesis.get() : nullptr));
    const auto& s = *model.synthesis;
    model.dofs = s.size();
    if (model.dofs < nModes) return model;
    model.modes = s.solve(speeds, solve_);
    // A solve that did not converge has no estimate (infinite: never
    // "reached"): its modes' residual estimates would read as accuracy
    // (a review found the status unread).
    if (static_cast<int>(model.modes.result.modes.size()) < nModes ||
        model.modes.result.status != eigen::SolveStatus::Converged)
      return model;
    if (truth) {
      // Paired by shape with a few modes more on each side (solveForComparison);
      // a mode the reduced model lacks or one of no truth shape is counted,
      // not folded into the largest error.
      const auto c = compareWithTruth(s, solveForComparison(s, speeds, solve_), *truth, truthModes, nModes);
      model.trueError = c.maxRelativeError;
      model.trueMissing = c.missingModes;
      model.trueUnmatched = c.unmatchedModes;
    }
    std::vector<std::vector<double>> shares;
    const auto e = s.errorEstimates(model.modes, &shares);
    model.estimate = 0.0;
    for (int j = 0; j < nModes; ++j)  // -1 (zero frequency): none
      if (e[j] > model.estimate || model.worst < 0) model.estimate = std::max(model.estimate, e[j]), model.worst = j;
    if (model.worst >= 0) model.worstShares = shares.at(static_cast<std::size_t>(model.worst));
    model.definite = model.modes.result.solver.find("Meirovitch") != std::string::npos;
    return model;
  };
  auto record = [&](const std::string& changed, const Model& m, std::vector<InclusionViolation> findings,
                    bool checked) {
    result.steps.push_back({static_cast<int>(result.steps.size()), changed, m.dofs, m.estimate, m.trueError,
                            std::move(findings), count, checked, m.trueMissing, m.trueUnmatched});
    if (onStep) onStep(result.steps.back(), result);
  };
  Model current = evaluate(red, nullptr);
  result.definite = current.definite;  // and every model compared after it (below)
  record("(start)", current, {}, false);

  // 4. Greedy: the addition that lowers the estimate most per added coordinate.
  for (int k = 1; current.estimate > accuracy && k <= options_.get<int>("Max Steps"); ++k) {
    int best = -1;
    double bestGain = -1;
    std::vector<std::optional<Model>> trials(ns);
    for (std::size_t q = 0; q < ns; ++q) {
      if (!result.reducible[q] || count[q] + step > limit[q]) continue;
      auto trial = red;
      trial[q].set("Vectors", count[q] + step);
      Model m;
      try {
        m = evaluate(trial, &current);
      } catch (const InputError&) {
        continue;  // e.g. more Craig-Bampton modes than the substructure has
      }
      if (m.dofs <= current.dofs) continue;  // no new coordinate (the substructure is complete)
      const double gain = (std::min(current.estimate, 1e300) - m.estimate) / std::max<long long>(1, m.dofs - current.dofs);
      if (best < 0 || gain > bestGain) best = static_cast<int>(q), bestGain = gain;
      trials[q] = std::move(m);
    }
    if (best < 0) break;
    // "Lowers" means beyond the estimate's rounding: the estimates come from
    // backward-stable solves, and their last digits follow the BLAS kernel
    // and the eigensolver's order of operations. A "gain" of 1e-12 there
    // chose the greedy path (shaft-on-support to 1e-6: 59 coordinates with
    // AVX-512 kernels, 61 with Nehalem's, 77 after the dense solver's
    // vectors came by inverse iteration instead of dgesvdx).
    const double rounding = 1e-8;
    const auto lowers = [&](const Model& m) { return m.estimate < current.estimate * (1.0 - rounding); };
    std::string changed = structure.substructure(best).name;
    int added = step;
    std::optional<Model> chosen = std::move(trials[best]);
    if (!lowers(*chosen)) {
      // A stall: no single addition lowers the estimate. A bending pair
      // needs two vectors: each substructure is tried with two additions at
      // once, and the best gain per coordinate taken (theory §11.10).
      int pair = -1;
      double pairGain = 0.0;
      for (std::size_t q = 0; q < ns; ++q) {
        if (!trials[q] || count[q] + 2 * step > limit[q]) continue;
        auto trial = red;
        trial[q].set("Vectors", count[q] + 2 * step);
        Model m;
        try {
          m = evaluate(trial, &current);
        } catch (const InputError&) {
          continue;
        }
        if (m.dofs <= current.dofs || !lowers(m)) continue;
        const double gain = (std::min(current.estimate, 1e300) - m.estimate) / static_cast<double>(m.dofs - current.dofs);
        if (pair < 0 || gain > pairGain) pair = static_cast<int>(q), pairGain = gain, chosen = std::move(m);
      }
      if (pair >= 0) {
        best = pair, added = 2 * step;
        changed = structure.substructure(best).name + " (pair)";
      } else if (!current.worstShares.empty()) {
        // Not even two: grow the one whose truncation makes most of the
        // worst mode's estimate (its term of sum_s r_s^H K_s^-1 r_s, §11.8).
        std::vector<double> share(ns, 0.0);  // a prototype's share is its copies' together
        for (std::size_t q = 0; q < ns; ++q) share[prototype(q)] += current.worstShares.at(q);
        int largest = -1;
        for (std::size_t q = 0; q < ns; ++q)
          if (trials[q] && (largest < 0 || share[q] > share[largest])) largest = static_cast<int>(q);
        if (largest >= 0) {
          if (largest != best) chosen = std::move(trials[largest]);  // trials[best] is in `chosen` already
          best = largest;
          changed = structure.substructure(best).name + " (stall)";
        }
      }
    }
    Model bestModel = std::move(*chosen);
    // 5. Inclusion principle between the nested models (K > 0 only), above
    // the round-off of the two solves.
    std::vector<InclusionViolation> findings;
    // Both models' own definiteness (before: the flag of whichever trial was
    // evaluated last, and only the dense path's, found by a review).
    const bool checkable = current.definite && bestModel.definite;
    result.definite = result.definite && checkable;
    const bool checked = checkable && !current.modes.result.modes.empty();
    if (checked)
      findings = checkInclusion(current.modes, bestModel.modes, static_cast<int>(bestModel.dofs - current.dofs));
    count[best] += added;
    red[best].set("Vectors", count[best]);
    for (std::size_t q = 0; q < ns; ++q)
      if (prototype(q) == static_cast<std::size_t>(best) && q != static_cast<std::size_t>(best)) {
        count[q] = count[best];
        red[q] = red[best];
      }
    current = std::move(bestModel);
    record(changed, current, std::move(findings), checked);
  }
  result.reached = current.estimate <= accuracy;
  return result;
}

}  // namespace cms::analysis
