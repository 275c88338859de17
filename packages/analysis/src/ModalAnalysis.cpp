#include "cms/analysis/ModalAnalysis.hpp"

#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <map>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>

#include "cms/analysis/TruthComparison.hpp"
#include "cms/analysis/WhirlClassification.hpp"
#include "cms/analysis/ZeroFrequencies.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/ParameterReading.hpp"
#include "cms/core/Stopwatch.hpp"

namespace cms::analysis {

Teuchos::RCP<const Teuchos::ParameterList> ModalAnalysis::validParameters() {
  auto p = Teuchos::rcp(new Teuchos::ParameterList("Modal Analysis"));
  p->set("Speed Factor", 1.0, "every nominal spin rate is multiplied by this (>= 0)");
  p->set("Target Accuracy", 0.0,
         "> 0: bases enriched until every wanted mode's estimated relative error is below it (theory 11.10)");
  p->set("Truth", false, "also solve the truth model (every basis Full) and report the true error per mode");
  p->set("Check Count", false,
         "count the truth's frequencies below the highest one found (one factorisation of the assembled model)");
  p->set("Periodic Method", "Auto",
         "a rotor on a moving attachment (theory 16.8): Auto, Multi-Blade or Floquet (PeriodicStructure's \"Method\")");
  return p;
}

ModalAnalysis::ModalAnalysis(synthesis::StructureDescription description, Teuchos::ParameterList solve,
                             const Teuchos::ParameterList& options)
    : description_(std::move(description)), solve_(std::move(solve)), options_(options) {
  validateOptions(options_, *validParameters(), "Modal Analysis");
  CMS_INPUT_CHECK(!(options_.get<double>("Speed Factor") >= 0.0),
                  "Modal Analysis: \"Speed Factor\" = " << options_.get<double>("Speed Factor") << " must be >= 0");
  CMS_INPUT_CHECK(!(options_.get<double>("Target Accuracy") >= 0.0),
                  "Modal Analysis: \"Target Accuracy\" = " << options_.get<double>("Target Accuracy")
                                                           << " must be >= 0");
}

ModalResult ModalAnalysis::run(const Teuchos::RCP<const Teuchos::Comm<int>>& comm) const {
  auto say = [&](const std::string& s) {
    if (progress_) progress_(s);
  };
  ModalResult r;
  // 1. Assembly of every substructure (with its prestress, leaves first).
  const Stopwatch t0;
  r.structure = [&] {
    Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewCounter("cms: 1. assembly of the substructures"));
    return synthesis::AssembledStructure::assemble(description_, comm);
  }();
  const auto& structure = *r.structure;
  r.assemblySeconds = t0.seconds();
  r.speeds = structure.nominalSpeeds();
  for (double& v : r.speeds) v *= options_.get<double>("Speed Factor");

  say("assembled " + std::to_string(structure.numSubstructures()) + " substructures");
  // 2. The bases: as given, or enriched to "Target Accuracy" (theory §11.10).
  say("reducing: factorising the stiffness and building the bases of " +
      std::to_string(structure.numSubstructures()) + " substructures");
  const Stopwatch t1;
  std::vector<Teuchos::ParameterList> reductions;
  for (std::size_t k = 0; k < structure.numSubstructures(); ++k) reductions.push_back(structure.substructure(k).reduction);
  r.enrichment.reached = true;
  if (const double target = options_.get<double>("Target Accuracy"); target > 0.0) {
    r.enrichment = enrichToAccuracy(structure, r.speeds, solve_, target, reductions);
    if (!r.enrichment.reached) return r;
  }

  // 3. Reduction and coupling; massless coordinates refused before solving.
  r.reduced = [&] {
    Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewCounter("cms: 2. reduction and synthesis"));
    // After enrichment its last synthesis already has these bases.
    return synthesis::SynthesizedStructure::synthesize(structure, reductions, synthesis::ReductionSchedule::Concurrent,
                                                       r.enrichment.synthesis.get());
  }();
  const auto& s = *r.reduced;
  r.reductionSeconds = t1.seconds();
  checkMass(structure, s);

  // 4. The solve, then what each zero frequency means (theory §4.3): a
  // critical speed is an answer, an unrestrained or ill-conditioned model is not.
  say("solving: the lowest " + std::to_string(solve_.get<int>("Number of Modes")) + " modes of " +
      std::to_string(s.size()) + " coordinates");
  if (!s.movingHubs().empty()) {
    runPeriodic(r);
    return r;
  }
  r.modes = [&] {
    Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewCounter("cms: 3. eigensolution"));
    return s.solve(r.speeds, solve_);
  }();
  // A solve that returned no mode (an eigensolver's breakdown) is the
  // answer: the steps below would compare nothing with the truth and count
  // below frequency 0, and said "bad input" (exit 2) in place of the
  // breakdown (found by a review).
  if (r.modes.result.modes.empty()) return r;
  checkZeroFrequencies(structure, s, r.modes, solve_);

  // 5. Accuracy, without the truth (theory §11.8, §11.9), and with it on request.
  r.character = s.characterise(r.modes);
  const Stopwatch t5;
  {
    Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewCounter("cms: 4. error estimates, bounds and coverage"));
    r.accuracy = s.accuracy(r.modes);
    for (const auto& a : r.accuracy) r.estimates.push_back(a.estimate);
    r.estimateSeconds = t5.seconds();
    // The cut-off is the highest mode, known to its estimated error: a
    // substructure's Ritz value above it by less is its mode below it,
    // approximated from above (4x: the estimate is not a bound).
    double band = 0.0;
    for (std::size_t i = 0; i < r.modes.result.modes.size(); ++i) {
      const double w = r.modes.result.modes[i].omega;
      if (w < r.cutoff) continue;
      r.cutoff = w;
      // Capped at 1e-3: a coarse model's top estimate (1e-2 and more) would
      // open a window wide enough to take an unrelated value for a missing
      // mode (found by a review).
      band = i < r.estimates.size() && r.estimates[i] > 0.0 && std::isfinite(r.estimates[i])
                 ? std::min(4.0 * r.estimates[i], 1e-3)
                 : 0.0;
    }
    // The estimates' factors are not needed again: freed before the counts'
    // factorisations, they no longer add to the run's peak memory.
    r.reduced->releaseFlexibilities();
    r.coverage = s.coverage(r.cutoff, band);
    r.countBand = band;
  }
  r.accuracySeconds = t5.seconds();
  // The truth, synthesised once for both "Truth" and "Check Count".
  std::optional<synthesis::SynthesizedStructure> truthModel;
  if (options_.get<bool>("Truth") || options_.get<bool>("Check Count"))
    truthModel = synthesis::SynthesizedStructure::synthesize(structure, true);
  if (options_.get<bool>("Truth")) {
    const auto& truth = *truthModel;
    requireComparableTruth(truth);  // before its solve
    // Both solved for a few modes more than asked: the partners of reduced
    // modes above a mode the bases lack, and of modes in the other order at
    // the edge of the range (solveForComparison). The reduced model's first
    // modes are r.modes again (its dense solve returns the lowest; a sparse
    // one the same to its tolerance).
    const auto truthModes = solveForComparison(truth, r.speeds, solve_);
    TEUCHOS_TEST_FOR_EXCEPTION(truthModes.result.status != eigen::SolveStatus::Converged, NumericalError,
                               "the truth model (every basis Full) did not converge ("
                                   << eigen::toString(truthModes.result.status) << ": " << truthModes.result.reason
                                   << "): no true errors to give");
    const auto wider = solveForComparison(s, r.speeds, solve_);
    const int n = static_cast<int>(
        std::min({r.modes.result.modes.size(), wider.result.modes.size(), truthModes.result.modes.size()}));
    const auto compared = compareWithTruth(s, wider, truth, truthModes, n);
    // An unmatched mode (no computed truth mode of its shape) has no true
    // error to give: NaN, printed and written as such.
    for (const auto& a : compared.modes)
      r.trueErrors.push_back(a.unmatched ? std::numeric_limits<double>::quiet_NaN() : std::abs(a.relativeError));
    r.truthMissing = compared.missingModes;
    r.truthUnmatched = compared.unmatchedModes;
  }
  // Ritz frequencies lie above the truth's: the truth has at least as many
  // below just above the highest reduced one; more means modes missing.
  r.countAt = r.cutoff * (1.0 + 1e-6);
  if (options_.get<bool>("Check Count")) {
    r.truthCount = truthFrequenciesBelow(*truthModel, r.speeds, r.countAt);  // -3 damped, -4 K indefinite: not counted
    // A reduced frequency within the band above countAt is the partner, from
    // above, of a truth mode just below it: a near-repeated pair cut by the
    // count had its second reduced member 3e-5 above it and read "MODES
    // MISSING" beside "every truth mode paired" (a review).
    const double reducedAt = r.countAt * (1.0 + r.countBand);
    for (const auto& md : r.modes.result.modes) r.reducedCount += md.omega < reducedAt;
    // Fewer returned than the truth counts may be modes the reduced model
    // has and was not asked for: "Number of Modes" cutting a repeated
    // frequency returns one member and the truth counts both (a cantilever
    // of square section, basis Full, was "MODES MISSING" against itself;
    // found by a review). The reduced model then answers for itself, asked
    // for as many more as the truth counts.
    const long long asked =
        std::min<long long>(s.size(), static_cast<long long>(r.modes.result.modes.size()) + r.truthCount - r.reducedCount);
    if (r.truthCount > r.reducedCount && asked > static_cast<long long>(r.modes.result.modes.size())) {
      Teuchos::ParameterList more(solve_);
      more.set("Number of Modes", static_cast<int>(asked));
      const auto wider = s.solve(r.speeds, more);
      long long below = 0;
      for (const auto& md : wider.result.modes) below += md.omega < reducedAt;
      // Only a converged solve answers (one that did not could hide a
      // missing mode; a review).
      if (wider.result.status == eigen::SolveStatus::Converged) r.reducedCount = std::max(r.reducedCount, below);
    }
  }

  // 6. Whirl of each spinning substructure in each mode, degenerate
  //    clusters classified whole (analysis::WhirlClassification, theory §12.2).
  r.whirls.resize(r.modes.result.modes.size());
  const WhirlClassification whirlRule;
  for (std::size_t k = 0; k < structure.numSubstructures(); ++k) {
    const auto& spec = structure.substructure(k);
    if (spec.kind == synthesis::SubstructureKind::Central || !spec.spin) continue;
    const auto w = whirlRule.classify(structure, s, r.modes, k, spec.spin->rate * options_.get<double>("Speed Factor"));
    for (std::size_t m = 0; m < w.size(); ++m) r.whirls[m].push_back(spec.name + " " + toString(w[m]));
  }
  return r;
}

ModalResult& ModalAnalysis::runPeriodic(ModalResult& r) const {
  // A rotor on a moving attachment (theory §16.8): the fixed-frame modes by
  // the multi-blade transform or Floquet; the shapes are the motion at hub
  // azimuth 0, so the energy shares and cyclic labels hold.
  const auto& s = *r.reduced;
  const int nModes = solve_.get<int>("Number of Modes");
  auto say = [&](const std::string& line) {
    if (progress_) progress_(line);
  };
  {
    Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewCounter("cms: 3. eigensolution"));
    Teuchos::ParameterList method;
    method.set("Method", options_.get<std::string>("Periodic Method"));
    PeriodicStructure periodic(s, r.speeds);
    periodic.setProgress(say);
    r.periodic = periodic.solve(nModes, method);
  }
  r.modes = r.periodic->modes;
  r.character = s.characterise(r.modes);
  r.accuracy.assign(r.modes.result.modes.size(), synthesis::ModeAccuracy());
  r.estimates.assign(r.modes.result.modes.size(), -1.0);
  // The cut-off is the highest of the asked modes: the unstable ones listed
  // past the count (PeriodicStructure) are not a range the basis claims.
  const auto& listed = r.modes.result.modes;
  const std::size_t asked = r.modes.result.numRequested > 0
                                ? std::min(listed.size(), static_cast<std::size_t>(r.modes.result.numRequested))
                                : listed.size();
  for (std::size_t i = 0; i < asked; ++i) r.cutoff = std::max(r.cutoff, listed[i].omega);
  const Stopwatch t5;
  r.coverage = s.coverage(r.cutoff);
  r.accuracySeconds = t5.seconds();
  if (options_.get<bool>("Truth")) {
    // The same periodic analysis of the truth (every basis Full), with more
    // modes than asked; the eigenvalues paired one to one, nearest first
    // (pairEigenvalues), and the truth's left unpaired in the reduced range
    // counted as missing.
    const auto truth = synthesis::SynthesizedStructure::synthesize(*r.structure, true);
    requireComparableTruth(truth);
    Teuchos::ParameterList method;
    method.set("Method", options_.get<std::string>("Periodic Method"));
    PeriodicStructure truthPeriodic(truth, r.speeds);
    truthPeriodic.setProgress([&](const std::string& line) { say("truth: " + line); });
    const auto t = truthPeriodic.solve(2 * nModes, method);
    std::vector<std::complex<double>> reducedLambda, truthLambda;
    for (const auto& md : r.modes.result.modes) reducedLambda.push_back(md.lambda);
    for (const auto& tm : t.modes.result.modes) truthLambda.push_back(tm.lambda);
    const auto paired = pairEigenvalues(reducedLambda, truthLambda);
    r.trueErrors = paired.relativeErrors;
    r.truthMissing = paired.missing;
  }
  CMS_INPUT_CHECK(options_.get<bool>("Check Count"),
                  "Modal Analysis: \"Check Count\" (a Sturm count of the truth) needs constant coefficients; this "
                  "structure's rotor spins on a moving attachment (theory §16.8)");
  r.whirls.assign(r.modes.result.modes.size(), {});
  return r;
}

std::string substructureWhirl(const synthesis::AssembledStructure& a, const std::vector<Teuchos::RCP<MultiVector>>& u,
                              std::size_t k, const eigen::GyroscopicMode& mode) {
  const auto& spec = a.substructure(k);
  if (!spec.spin) return "";
  const double sign = spec.spin->rate > 0 ? 1.0 : spec.spin->rate < 0 ? -1.0 : 0.0;
  return toString(WhirlClassification().classify({mode}, {orbitOfSubstructure(a, u, k, mode)}, sign, a.comm().get())[0]);
}

}  // namespace cms::analysis
