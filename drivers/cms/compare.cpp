// cms compare: the same structure reduced by every strategy against its
// truth model — the table to choose a reduction from (doc/user-guide.md,
// "cms compare").
//
// Guyan, and Admissible, Modes and Craig-Bampton bases at --counts vectors
// per substructure: reduced DOFs, reduction and solve times, peak memory,
// the largest true and estimated relative frequency errors (doc/theory.md
// §11.8), the mean error, and the smallest subspace MAC of the vibration
// modes (rigid and frame-rate modes excluded). A strategy that fails is
// named, the table is written as <name>-compare-partial.csv, and the exit
// code is the worst outcome.
//
// Sample runs:
//   cms compare
//   cms compare drivers/scenes/rotor-chain.yaml --counts=2,4,8,16 --plot
//   mpiexec -n 2 cms compare --counts=4,8
#include <iomanip>
#include <iostream>

#include <Teuchos_Array.hpp>

#include "../DriverBoundary.hpp"
#include "Command.hpp"
#include "cms/analysis/StrategyComparison.hpp"
#include "cms/io/OutputFiles.hpp"

namespace cms::drivers {


int compare(int argc, char* argv[]) {
  // 1. Options and scene.
  Options options("compare",
                  "Every reduction strategy (Guyan; Admissible, Modes, Craig-Bampton at --counts vectors) against\n"
                  "the truth model: sizes, times, memory, true and estimated errors, subspace MAC.");
  std::string counts = "2,4,8";
  options.add("counts", &counts, "vectors per substructure, comma-separated");
  options.plotOption();
  SceneRun run;
  if (const auto exit = run.start(options, argc, argv)) return *exit;
  const auto& sc = run.scene;

  // 2. The comparison (analysis::StrategyComparison), one line per strategy as it comes.
  const auto structure = run.assemble();
  Teuchos::ParameterList study;
  study.set("Counts", Teuchos::Array<int>(positiveIntegers(counts, "--counts")));
  study.set("Speed Factor", sc.speedFactor);
  Outcome worst = kSuccess;  // breakdown (3) outranks not converged (4)
  const auto c = run.namingScene([&] { return analysis::StrategyComparison(structure, sc.solve, study).run(
      [&](const analysis::StrategyRow* row, const analysis::StrategyOutcome* other) {
        if (other && other->failed) {
          const auto o = outcome(other->status);
          if (worst.code == ExitSuccess || o.code == ExitNumericalError) worst = o;
        }
        if (!run.root) return;
        if (row)
          std::cout << "[" << row->basis << " " << row->vectors << "] " << row->dofs << " DOFs, max error "
                    << analysis::trueErrorText(row->accuracy.maxRelativeError, row->accuracy.missingModes, row->accuracy.unmatchedModes) << '\n';
        else if (other->failed)
          std::cout << "FAILED " << other->basis << " with " << other->vectors << " vectors: "
                    << outcome(other->status).message << " (" << toString(other->status) << "): " << condense(other->why)
                    << '\n';
        else
          std::cout << "skipped " << other->basis << " with " << other->vectors << " vectors: " << other->why << '\n';
      });
  });
  // Without a converged truth there is nothing to compare with: its outcome is the run's.
  if (const auto o = outcome(c.truthModes.result.status); o.code != ExitSuccess) {
    if (run.root)
      std::cerr << "cms: " << o.message << ": the truth model (" << c.truthSize << " coordinates) "
                << toString(c.truthModes.result.status) << ": " << condense(c.truthModes.result.reason)
                << "; no files written\n";
    return o.code;
  }
  const int nModes = sc.solve.get<int>("Number of Modes");
  if (c.rows.empty()) {
    if (worst.code == ExitSuccess) worst = kBreakdown;  // nothing could be compared
    if (run.root)
      std::cerr << "cms: " << worst.message << ": no strategy gave " << nModes << " modes to compare; no files written\n";
    return worst.code;
  }

  // 3. The table, then the CSV.
  if (!run.root) return worst.code;
  std::cout << "\ntruth: " << c.truthSize << " coordinates, " << c.truthSeconds << " s (" << c.truthModes.path
            << ")\nlowest " << nModes << " modes compared, each with the truth mode of its shape (MISSING n: n truth modes the\n"
            << "reduced model lacks; UNMATCHED n: n reduced modes of no computed truth shape)\n\n"
            << "strategy        vectors  DOFs    reduce s  solve s   peak MiB  max rel err  max est err  mean rel err  worst MAC\n";
  for (const auto& r : c.rows)
    std::cout << std::left << std::setw(16) << r.basis << std::right << std::setw(7) << r.vectors << std::setw(7)
              << r.dofs << std::setw(10) << std::setprecision(3) << r.reduceSeconds << std::setw(10) << r.solveSeconds
              << std::setw(10) << std::setprecision(4) << r.peakMiB << std::setw(13) << analysis::trueErrorText(r.accuracy.maxRelativeError, r.accuracy.missingModes, r.accuracy.unmatchedModes)
              << std::setw(13) << r.estimate << std::setw(14) << r.accuracy.meanRelativeError << std::setw(11)
              << r.accuracy.worstMac << '\n';
  if (!sc.csv) {  // Output/CSV false (read by cms modes alone before; a review)
    std::cout << "\nno table written (the scene's Output/CSV is false)\n";
    if (worst.code != ExitSuccess) std::cerr << "cms: " << worst.message << ": some strategies failed (FAILED above)\n";
    return worst.code;
  }
  const std::string csv = sc.name + (worst.code == ExitSuccess ? "-compare.csv" : "-compare-partial.csv");
  io::OutputFiles f;
  auto& out = f.open(run.outDir / csv);
  out << "strategy,vectors_per_substructure,reduced_dofs,reduce_s,solve_s,peak_mib,max_rel_error,"
         "max_estimated_rel_error,mean_rel_error,worst_mac,missing_modes,unmatched_modes,truth_dofs,truth_s";
  for (std::size_t q = 0; q < structure.numSubstructures(); ++q)
    out << ",dofs_" << io::csvField(structure.substructure(q).name);
  out << '\n';
  for (const auto& r : c.rows) {
    out << r.basis << ',' << r.vectors << ',' << r.dofs << ',' << r.reduceSeconds << ',' << r.solveSeconds << ','
        << r.peakMiB << ',' << r.accuracy.maxRelativeError << ',' << r.estimate << ','
        << r.accuracy.meanRelativeError << ',' << r.accuracy.worstMac << ',' << r.accuracy.missingModes << ','
        << r.accuracy.unmatchedModes << ',' << c.truthSize << ',' << c.truthSeconds;
    for (int d : r.perSubstructure) out << ',' << d;
    out << '\n';
  }
  f.commit();
  std::cout << "\nwrote " << (run.outDir / csv).string() << '\n';
  if (worst.code != ExitSuccess) {
    std::cerr << "cms: " << worst.message << ": some strategies failed (FAILED above); the others are in " << csv << '\n';
    return worst.code;
  }
  plot(options, "compare", run.outDir / csv);
  return ExitSuccess;
}

}  // namespace cms::drivers
