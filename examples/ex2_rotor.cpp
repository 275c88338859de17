// Example 2: a rotor reduced two ways, each compared with the truth.
//
// A spinning hub carries a flexible blade with a stiff tip and a tip mass
// (drivers/scenes/rotor-chain.yaml: the hub's frame spins at 20 rad/s, each
// child's centrifugal pull stiffens its parent). The example reduces every
// substructure with the same number of vectors by two strategies (by
// default the paper's admissible vectors and Craig-Bampton modes), solves
// the full finite-element model of the same structure (the truth: every
// basis Full), and prints per mode the frequency error and the modal
// assurance criterion (MAC) of each strategy against the truth, beside the
// error each strategy estimated without the truth. That is the trade the
// framework exists to measure: coordinates and seconds against accuracy.
//
// The scene is drivers/scenes/rotor-chain.yaml, installed with the library
// in <prefix>/share/cms/scenes (find_package(cms) sets cms_DATA_DIR;
// examples/CMakeLists.txt passes the folder as CMS_EXAMPLE_SCENES), read and
// checked exactly as `cms` reads it; its "Reduction" lists are replaced in
// step 5, one strategy at a time. --scene reads another file.
//
// Sample runs:
//   ex2_rotor
//   ex2_rotor --vectors=4 --modes=6
//   ex2_rotor --first=Modes --second=Guyan
//   ex2_rotor --scene=<prefix>/share/cms/scenes/shaft-on-support.yaml
//   mpiexec -n 2 ex2_rotor
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>


#include "cms/analysis/TruthComparison.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/Program.hpp"
#include "cms/core/Stopwatch.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace {

/// One strategy's reduced model, its modes and what they cost.
struct Strategy {
  std::string basis;
  cms::synthesis::SynthesizedStructure reduced;
  cms::synthesis::StructureModes modes;
  std::vector<double> estimates;
  double seconds = 0.0;
};

}  // namespace

int main(int argc, char* argv[]) {
  using namespace cms;
  return runProgram("ex2_rotor", argc, argv, [&](const CommPtr& comm, bool root) -> int {
    // 1. Options, printed back so that the output records how it was made.
    int vectors = 8, modes = 8;
    std::string first = "Admissible", second = "Craig-Bampton", scenePath;
    ProgramOptions options("ex2_rotor",
                           "A rotor reduced by two strategies, each against the truth (examples/ex2_rotor.cpp).");
    options.add("vectors", &vectors, "vectors per substructure, both strategies (capped at its free DOFs)");
    options.add("modes", &modes, "lowest modes compared");
    options.add("first", &first, "first basis: Admissible, Modes, Craig-Bampton, Guyan, Polynomial");
    options.add("second", &second, "second basis, as --first");
    options.add("scene", &scenePath, "read this YAML scene instead of the rotor chain");
    if (const auto exit = options.parse(argc, argv, *comm)) return *exit;
    CMS_INPUT_CHECK(vectors < 1, "--vectors = " << vectors << " must be at least 1");
    CMS_INPUT_CHECK(modes < 1, "--modes = " << modes << " must be at least 1");

    // 2. The structure, read and checked as a scene (keys, kinds, tree).
    scene::Scene sc = scene::Scene::read(scenePath.empty() ? CMS_EXAMPLE_SCENES "/rotor-chain.yaml" : scenePath);
    sc.solve.set("Number of Modes", modes);

    // 3. One assembly (matrices per unit speed, centrifugal prestress leaves
    //    first, theory §11.4) serves both strategies and the truth: the
    //    reductions differ only in their bases (§11.3).
    const auto structure = synthesis::AssembledStructure::assemble(sc.structure, comm);
    const auto speeds = structure.nominalSpeeds();

    // 4. The truth: every basis Full, i.e. the monolithic model with each
    //    attachment slaved to its parent (§11.2), solved by the same path.
    Stopwatch timer;
    const auto truth = synthesis::SynthesizedStructure::synthesize(structure, /*truth=*/true);
    // A few modes more than compared, on both sides: the modes are paired
    // by shape, and a partner may lie just above the n-th (§11.7).
    const auto truthModes = analysis::solveForComparison(truth, speeds, sc.solve);
    const double truthSeconds = timer.seconds();

    // 5. Each strategy: the same vector count on every substructure
    //    (synthesis::sameReduction), reduced, coupled, solved, and its own
    //    error estimates (§11.8), which need no truth.
    std::vector<Strategy> strategies;
    for (const auto& basis : {first, second}) {
      timer.restart();
      auto reduced = synthesis::SynthesizedStructure::synthesize(structure,
                                                                 synthesis::sameReduction(structure, basis, vectors));
      auto found = analysis::solveForComparison(reduced, speeds, sc.solve);
      auto estimates = reduced.errorEstimates(found);
      strategies.push_back({basis, std::move(reduced), std::move(found), std::move(estimates), timer.seconds()});
    }

    // 6. Against the truth: each reduced mode paired with the truth mode of
    //    its shape, relative error and MAC of the expanded physical shapes
    //    (§11.7). When K > 0 a
    //    reduced (Ritz) frequency lies above the true one (the inclusion
    //    principle, §6), so errors are positive.
    int count = std::min(static_cast<int>(truthModes.result.modes.size()), sc.solve.get<int>("Number of Modes"));
    for (const auto& s : strategies) count = std::min(count, static_cast<int>(s.modes.result.modes.size()));
    std::vector<analysis::TruthComparison> comparisons;
    for (const auto& s : strategies)
      comparisons.push_back(analysis::compareWithTruth(s.reduced, s.modes, truth, truthModes, count));

    if (root) {
      std::printf("\n%-14s %12s %10s %14s %12s\n", "model", "coordinates", "seconds", "max rel. error",
                  "worst MAC");
      std::printf("%-14s %12lld %10.3f %14s %12s\n", "truth (Full)", truth.size(), truthSeconds, "-", "-");
      for (std::size_t i = 0; i < strategies.size(); ++i)
        std::printf("%-14s %12lld %10.3f %14.3e %12.6f\n", strategies[i].basis.c_str(), strategies[i].reduced.size(),
                    strategies[i].seconds, comparisons[i].maxRelativeError, comparisons[i].worstMac);
      std::printf("\n%4s", "mode");
      for (const auto& s : strategies)
        std::printf(" | %-13.13s %10s %10s %10s %8s", s.basis.c_str(), "truth Hz", "error", "estimate", "MAC");
      std::printf("\n");
      for (int m = 0; m < count; ++m) {
        std::printf("%4d", m + 1);
        for (std::size_t i = 0; i < strategies.size(); ++i) {
          const auto& a = comparisons[i].modes[m];
          std::printf(" | %13.6g %10.6g %10.2e %10.2e %8.5f%s", strategies[i].modes.result.modes[m].hz,
                      a.truthOmega / (2.0 * M_PI), a.relativeError, strategies[i].estimates[m], a.mac,
                      a.unmatched ? " (no truth shape)" : "");
        }
        std::printf("\n");
      }
      // Each mode is compared with the truth mode of its shape; truth modes
      // no reduced mode took are modes the reduction lacks (theory §11.9:
      // `cms modes --check-count` finds them without the truth).
      for (std::size_t i = 0; i < strategies.size(); ++i)
        if (comparisons[i].missingModes > 0)
          std::printf("%s: MISSING %d truth mode(s) in its range\n", strategies[i].basis.c_str(),
                      comparisons[i].missingModes);
      std::printf("(estimate: the error predicted without the truth, theory 11.8; < 0: a zero frequency)\n");
    }
    bool converged = truthModes.result.status == eigen::SolveStatus::Converged;
    for (const auto& s : strategies) converged = converged && s.modes.result.status == eigen::SolveStatus::Converged;
    return converged ? ExitSuccess : ExitNotConverged;
  });
}
