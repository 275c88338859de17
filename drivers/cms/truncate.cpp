// cms truncate: how many vectors each substructure needs for the lowest
// "Number of Modes" to reach --accuracy, judged by the error estimates
// (doc/theory.md §11.8) without the truth (doc/user-guide.md, "cms truncate").
//
// A greedy search (analysis::TruncationStudy): from --start vectors per
// reducible substructure, --step more at a time to the substructure whose
// addition lowers the largest estimated error most per coordinate; each
// step checks the inclusion principle between the nested models (K > 0).
// Ends with the suggested counts; --truth prints the true error beside the
// estimate.
//
// Sample runs:
//   cms truncate --accuracy=1e-4
//   cms truncate drivers/scenes/rotor-chain.yaml --accuracy=1e-6 --truth --plot
#include <iomanip>
#include <iostream>
#include <sstream>


#include "../DriverBoundary.hpp"
#include "Command.hpp"
#include "cms/analysis/TruncationStudy.hpp"
#include "cms/analysis/TruthComparison.hpp"
#include "cms/io/OutputFiles.hpp"

namespace cms::drivers {

int truncate(int argc, char* argv[]) {
  // 1. Options and scene.
  Options options("truncate",
                  "Vectors added where they lower the estimated error most, until the lowest \"Number of Modes\"\n"
                  "are within --accuracy (no truth solve); ends with the suggested vector counts.");
  int start = 2, step = 2;
  double accuracy = 1e-3;
  bool truth = false;
  options.add("start", &start, "vectors per substructure to start from");
  options.add("step", &step, "vectors added per step");
  options.add("accuracy", &accuracy, "target largest relative error of the lowest modes (estimated)");
  options.flag("truth", &truth, "also solve the truth model and print the true error beside each estimate");
  options.plotOption();
  SceneRun run;
  if (const auto exit = run.start(options, argc, argv)) return *exit;
  const auto& sc = run.scene;
  CMS_INPUT_CHECK(start < 0 || step < 1, "--start must be >= 0 and --step >= 1");
  CMS_INPUT_CHECK(!(accuracy > 0), "--accuracy = " << accuracy << " must be positive");

  // 2. The search, one line per step as it is taken.
  const auto structure = run.assemble();
  Teuchos::ParameterList study;
  study.set("Start", start);
  study.set("Step", step);
  study.set("Accuracy", accuracy);
  study.set("Truth", truth);
  study.set("Speed Factor", sc.speedFactor);
  const analysis::TruncationStudy search(structure, sc.solve, study);
  std::ostringstream table;
  table << "step,changed,dofs,max_rel_error,max_true_rel_error,true_missing_modes,true_unmatched_modes,"
           "inclusion_violations,inclusion_checked";
  for (std::size_t q = 0; q < structure.numSubstructures(); ++q)
    table << ",vectors_" << io::csvField(structure.substructure(q).name);
  table << '\n' << std::setprecision(12);
  int findings = 0, checkedSteps = 0;
  const auto r = run.namingScene([&] { return search.run([&](const analysis::TruncationStep& s, const analysis::TruncationResult& sofar) {
    if (run.root && s.step == 0)
      std::cout << (truth ? "truth: " + std::to_string(sofar.truthSize) + " coordinates; " : "no truth solve; ")
                << "target: the lowest " << sc.solve.get<int>("Number of Modes") << " within " << accuracy
                << ", by their error estimates\n\nstep  added to      DOFs  max est err  max true err  incl.\n";
    findings += static_cast<int>(s.findings.size());
    checkedSteps += s.inclusionChecked;
    // Unchecked steps show no count ("-", an empty CSV field), not 0.
    const std::string violations = s.inclusionChecked ? std::to_string(s.findings.size()) : std::string();
    const auto count = [](int n) { return n >= 0 ? std::to_string(n) : std::string(); };  // empty without truth
    table << s.step << ',' << io::csvField(s.changed) << ',' << s.dofs << ',' << s.estimate << ',' << s.trueError << ','
          << count(s.trueMissing) << ',' << count(s.trueUnmatched) << ',' << violations << ','
          << (s.inclusionChecked ? 1 : 0);
    for (int v : s.vectors) table << ',' << v;
    table << '\n';
    if (!run.root) return;
    std::cout << std::setw(4) << s.step << "  " << std::left << std::setw(12) << s.changed << std::right << std::setw(7)
              << s.dofs << std::setw(13) << std::setprecision(4) << s.estimate << std::setw(13) << analysis::trueErrorText(s.trueError, s.trueMissing, s.trueUnmatched)
              << std::setw(6) << (s.inclusionChecked ? violations : std::string("-")) << '\n';
    for (const auto& x : s.findings)
      std::cout << "  finding: inclusion principle violated at mode " << x.index + 1 << " (" << x.inequality << ", by "
                << x.amount << ", above the solves' round-off) when adding to " << s.changed << '\n';
  }); });

  // 3. The verdict and the suggested counts; the table only when reached.
  const auto& last = r.steps.back();
  if (!run.root) return r.reached ? ExitSuccess : kNotConverged.code;
  std::cout << "\n" << (r.reached ? "reached " : "NOT reached: ") << "max estimated relative error " << last.estimate
            << " with " << last.dofs << " coordinates";
  if (truth) std::cout << " (true error " << analysis::trueErrorText(last.trueError, last.trueMissing, last.trueUnmatched) << ", truth " << r.truthSize << " coordinates)";
  const int comparable = static_cast<int>(r.steps.size()) - 1;  // every step after the first
  if (checkedSteps < comparable)
    std::cout << "\n(the inclusion principle was checked at " << checkedSteps << " of " << comparable
              << " steps, \"-\" above: it needs K > 0 and the dense Meirovitch solve in both models compared)";
  std::cout << "\nsuggested vectors:";
  for (std::size_t q = 0; q < structure.numSubstructures(); ++q)
    if (r.reducible[q]) std::cout << ' ' << structure.substructure(q).name << " = " << last.vectors[q];
  std::cout << "\ninclusion-principle violations: " << findings;
  if (checkedSteps < comparable) std::cout << " in the " << checkedSteps << " steps checked";
  std::cout << '\n';
  if (!r.reached) {
    std::cerr << "cms: " << kNotConverged.message << " (exit " << kNotConverged.code
              << "): --accuracy not reached; no files written\n";
    return kNotConverged.code;
  }
  if (!sc.csv) {  // Output/CSV false (read by cms modes alone before; a review)
    std::cout << "no table written (the scene's Output/CSV is false)\n";
    return ExitSuccess;
  }
  const auto csv = run.outDir / (sc.name + "-truncate.csv");
  io::OutputFiles f;
  f.open(csv) << table.str();
  f.commit();
  std::cout << "wrote " << csv.string() << '\n';
  plot(options, "truncate", csv);
  return ExitSuccess;
}

}  // namespace cms::drivers
