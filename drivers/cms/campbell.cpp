// cms campbell: the Campbell diagram of a scene's reduced model
// (doc/user-guide.md, "cms campbell"; the method: doc/theory.md §12).
//
// The spin rates are swept from 0 to --max-factor times their nominal
// values, all together or only --speed's with the others held; the reduced
// matrices are polynomials in the rates, so nothing is re-projected. The
// library's Campbell study (analysis::CampbellStudy) follows each mode by
// its mass-weighted MAC (crossings and veerings keep their identities),
// finds where a track meets an engine order (--orders) of the swept rate,
// bisected to 1e-6, tells forward from backward whirl (the one rule,
// analysis::WhirlClassification: unbalance excites forward whirl), lists
// the crossings of identical parts once, sets aside the frame-rate tracks
// (rigid motions seen at a spin rate) and lists the unstable speed ranges.
// Writes <name>-campbell.csv and <name>-campbell-crossings.csv; --plot
// draws them (drivers/plot_results.py) in the units of --axis.
//
// Sample runs:
//   cms campbell
//   cms campbell --steps=41 --max-factor=3 --orders=1,2 --axis=hz --plot
//   cms campbell drivers/scenes/shaft-on-support.yaml --orders=1 --axis=per-rev --plot
//   cms campbell --speed=wheel --max-factor=1.5 --orders=1
//   mpiexec -n 2 cms campbell --steps=11
#include <chrono>
#include <iostream>
#include <sstream>

#include <Teuchos_Array.hpp>

#include "../DriverBoundary.hpp"
#include "Command.hpp"
#include "cms/analysis/CampbellStudy.hpp"
#include "cms/io/OutputFiles.hpp"

namespace cms::drivers {

int campbell(int argc, char* argv[]) {
  // 1. Options and scene.
  Options options("campbell",
                  "The Campbell diagram of the reduced model: the spin rates swept from 0 to --max-factor times\n"
                  "their nominal values (or only --speed's), modes tracked by MAC, engine-order critical speeds\n"
                  "(forward and backward whirl told apart), frame-rate tracks set aside, unstable ranges.");
  int steps = 21;
  double maxFactor = 2.0;
  std::string ordersText = "1", speed, axisText = "rpm";
  bool refine = true;
  options.add("steps", &steps, "number of speeds (>= 2)");
  options.add("max-factor", &maxFactor, "top speed as a multiple of the nominal rates");
  options.add("orders", &ordersText, "engine orders of the swept rate, comma-separated (e.g. 1,2 or 0.5,1)");
  options.add("speed", &speed, "sweep only this substructure's spin rate, the others held (empty: all rates together)");
  options.add("axis", &axisText, "units: hz (rev/s, Hz), rpm (rpm, Hz) or per-rev (rpm, frequency per rev)");
  options.flag("refine", &refine, "bisect each crossing to 1e-6 of its speed (else linear between speeds)");
  options.plotOption();
  SceneRun run;
  if (const auto exit = run.start(options, argc, argv)) return *exit;
  const auto& sc = run.scene;
  CMS_INPUT_CHECK(steps < 2, "--steps = " << steps << " must be at least 2");
  CMS_INPUT_CHECK(!(maxFactor > 0), "--max-factor = " << maxFactor << " must be positive");
  const Teuchos::Array<double> orders(positiveNumbers(ordersText, "--orders"));
  const auto axis = analysis::speedAxis(axisText);

  // 2. Assemble and reduce once; every speed parameter is a polynomial variable.
  const auto structure = run.assemble();
  CMS_INPUT_CHECK(structure.speeds().empty(), sc.path << ": nothing spins in this scene: no Campbell diagram");
  if (!speed.empty()) {
    std::string names;
    bool known = false;
    for (const auto& p : structure.speeds()) names += (names.empty() ? "" : ", ") + p.name, known |= p.name == speed;
    CMS_INPUT_CHECK(!known, "--speed = " << speed << ": not a spinning substructure of " << sc.path
                                         << " (its speed parameters: " << names << ")");
  }
  const auto reduced = run.namingScene([&] { return synthesis::SynthesizedStructure::synthesize(structure); });

  // 3. The study: sweep, track, cross, classify (collective).
  Teuchos::ParameterList study;
  study.set("Steps", steps);
  study.set("Max Factor", maxFactor);
  study.set("Speed Factor", sc.speedFactor);
  study.set("Speed Parameter", speed);
  study.set("Engine Orders", orders);
  study.set("Refine Crossings", refine);
  const analysis::SynthesizedSweepProblem problem(structure, reduced, sc.solve, speed);
  const auto t0 = std::chrono::steady_clock::now();
  const analysis::CampbellResult r = run.namingScene([&] { return analysis::CampbellStudy(study).run(problem); });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!run.root) return outcome(r.status).code;

  // 4. What an engineer reads: the tracks, then the critical speeds.
  std::cout << stamp(seconds) << steps << " speeds, " << reduced.size() << " coordinates, no re-projection; "
            << (speed.empty() ? "every rate scaled together" : "only " + speed + "'s rate swept, the others held")
            << "\n\n";
  r.printTable(std::cout, axis);
  std::cout << '\n';
  r.printCrossings(std::cout);
  if (const auto o = outcome(r.status); o.code != ExitSuccess) {
    std::cerr << "cms: " << o.message << " (exit " << o.code << "): " << condense(r.reason) << "; no files written\n";
    return o.code;
  }

  // 5. The tables, written whole or not at all, and the plot (none with
  //    Output/CSV false, which was read by cms modes alone; a review).
  if (!sc.csv) {
    std::cout << "\nno tables written (the scene's Output/CSV is false)\n";
    return ExitSuccess;
  }
  const auto csv = run.outDir / (sc.name + "-campbell.csv");
  const auto crossings = run.outDir / (sc.name + "-campbell-crossings.csv");
  io::OutputFiles files;  // both or neither
  r.writeCsv(files.open(csv));
  r.writeCrossingsCsv(files.open(crossings));
  files.commit();
  std::cout << "\nwrote " << csv.string() << " and " << crossings.filename().string() << '\n';
  plot(options, "campbell", csv, {"--orders=" + ordersText, "--axis=" + axisText});
  return ExitSuccess;
}

}  // namespace cms::drivers
