// Example 3: your own study on top of the library's solve.
//
// The question: at what spin speed does a spinning shaft's lowest
// forward-whirl frequency meet the spin speed itself? There an unbalance,
// which turns with the shaft and so excites forward whirl only, drives the
// rotor at resonance: the synchronous (1X) forward critical speed. The
// library has a Campbell study; this example writes the question directly,
// the way a user writes one the library does not have:
//   - reduce the structure once: the synthesised matrices are stored per
//     speed parameter, M, G(s) = sum s_i G_i, K(s) = K_0 + sum s_i s_j K_ij
//     (theory §8, §11.2), so each speed costs one small eigensolution and no
//     re-projection;
//   - sweep one speed parameter with the others held at their nominal
//     values, and at each speed pick the lowest mode in which the spinning
//     substructure whirls forward (analysis::substructureWhirl: the sense of
//     the orbit of its transverse motion against the spin);
//   - find where that frequency minus the speed changes sign, and refine the
//     crossing by bisection, each probe one more solve.
//
// The structure is drivers/scenes/shaft-on-support.yaml (installed in
// <prefix>/share/cms/scenes, CMS_EXAMPLE_SCENES): a steel shaft with a disc
// (A, stationary-frame form, theory §9.4) cantilevered from a flexible,
// non-spinning support beam (C).
//
// Sample runs:
//   ex3_custom_study
//   ex3_custom_study --steps=31 --max-speed=400
//   ex3_custom_study --scene=<prefix>/share/cms/scenes/spacecraft.yaml --speed=wheel --max-speed=1200
//   mpiexec -n 2 ex3_custom_study
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <vector>


#include "cms/analysis/ModalAnalysis.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/Program.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace {

/// The lowest forward-whirl mode of substructure `k` at one speed.
struct Probe {
  double speed = 0.0;                 ///< rad/s
  std::optional<double> forward;      ///< its frequency, rad/s (none: none found, or at rest)
  std::optional<double> backward;     ///< the lowest backward-whirl frequency, for the table
  bool stable = true;
};

}  // namespace

int main(int argc, char* argv[]) {
  using namespace cms;
  return runProgram("ex3_custom_study", argc, argv, [&](const CommPtr& comm, bool root) -> int {
    // 1. Options, printed back so that the output records how it was made.
    int steps = 17, bisections = 30;
    double maxSpeed = 0.0;
    std::string scenePath, speedName;
    ProgramOptions options("ex3_custom_study",
                           "The 1X forward critical speed by a user's own sweep (examples/ex3_custom_study.cpp).");
    options.add("steps", &steps, "speeds of the coarse sweep, from 0 to --max-speed");
    options.add("max-speed", &maxSpeed, "top of the sweep, rad/s (default: twice the nominal rate)");
    options.add("speed", &speedName, "the substructure whose spin is swept (default: the first that spins)");
    options.add("bisections", &bisections, "bisection steps refining the crossing");
    options.add("scene", &scenePath, "read this YAML scene instead of the shaft on its support");
    if (const auto exit = options.parse(argc, argv, *comm)) return *exit;
    CMS_INPUT_CHECK(steps < 2, "--steps = " << steps << " must be at least 2");
    CMS_INPUT_CHECK(bisections < 0, "--bisections = " << bisections << " must be >= 0");

    // 2. Read, assemble and reduce once (theory §11.1-§11.4).
    const scene::Scene sc =
        scene::Scene::read(scenePath.empty() ? CMS_EXAMPLE_SCENES "/shaft-on-support.yaml" : scenePath);
    const auto structure = synthesis::AssembledStructure::assemble(sc.structure, comm);
    const auto reduced = synthesis::SynthesizedStructure::synthesize(structure);

    // 3. Which speed parameter to sweep, and which substructure declares it
    //    (its whirl is the one tracked).
    const auto& parameters = structure.speeds();
    CMS_INPUT_CHECK(parameters.empty(), sc.path << ": nothing spins, there is no speed to sweep");
    std::size_t p = 0;
    if (!speedName.empty()) {
      while (p < parameters.size() && parameters[p].name != speedName) ++p;
      CMS_INPUT_CHECK(p == parameters.size(), "--speed = \"" << speedName << "\": no substructure of that name spins");
    }
    std::size_t k = 0;
    while (structure.substructure(k).name != parameters[p].name) ++k;
    if (!(maxSpeed > 0)) maxSpeed = 2.0 * std::abs(parameters[p].nominal);
    CMS_INPUT_CHECK(!(maxSpeed > 0), "--max-speed must be positive");
    if (root)
      std::cout << "ex3_custom_study: sweeping the spin of " << parameters[p].name << " from 0 to " << maxSpeed
                << " rad/s in " << steps << " steps (" << reduced.size() << " coordinates)\n";

    // 4. One probe: solve at this speed (the others nominal), then the whirl
    //    of substructure k in each mode, lowest first. Collective: every
    //    rank runs the same probes in the same order.
    //    At rest no orbit has a sense (whirl needs spin): the probe at 0
    //    solves but classifies nothing.
    auto probe = [&](double speed) {
      Probe pr;
      pr.speed = speed;
      auto speeds = structure.nominalSpeeds();
      speeds[p] = speed;
      const auto modes = reduced.solve(speeds, sc.solve);
      pr.stable = modes.result.isStable();
      if (speed == 0.0) return pr;
      for (std::size_t m = 0; m < modes.result.modes.size() && !(pr.forward && pr.backward); ++m) {
        const auto& mode = modes.result.modes[m];
        if (mode.stability != eigen::Stability::Stable) continue;  // zero frequencies have no whirl
        const auto whirl = analysis::substructureWhirl(structure, reduced.expand(modes, static_cast<int>(m)), k, mode);
        if (whirl == "FW" && !pr.forward) pr.forward = mode.omega;
        if (whirl == "BW" && !pr.backward) pr.backward = mode.omega;
      }
      return pr;
    };

    // 5. The coarse sweep: a table, and the first interval in which
    //    g(speed) = forward frequency - speed changes sign. At rest g > 0
    //    whatever the forward branch starts from (a frequency is positive);
    //    where no forward mode was found g is unknown.
    auto g = [](const Probe& pr) -> std::optional<double> {
      if (pr.speed == 0.0) return std::numeric_limits<double>::infinity();
      if (!pr.forward) return std::nullopt;
      return *pr.forward - pr.speed;
    };
    if (root) std::printf("\n%12s %16s %16s %8s\n", "speed rad/s", "lowest FW rad/s", "lowest BW rad/s", "stable");
    std::optional<std::pair<Probe, Probe>> bracket;
    std::optional<Probe> previous;
    for (int i = 0; i < steps; ++i) {
      const Probe pr = probe(maxSpeed * i / (steps - 1));
      if (root) {
        auto text = [](const std::optional<double>& v) {
          char b[32] = "-";
          if (v) std::snprintf(b, sizeof b, "%.6g", *v);
          return std::string(b);
        };
        std::printf("%12.6g %16s %16s %8s\n", pr.speed, text(pr.forward).c_str(), text(pr.backward).c_str(),
                    pr.stable ? "yes" : "NO");
      }
      if (const auto gi = g(pr)) {
        if (previous && !bracket && *g(*previous) > 0 && *gi <= 0) bracket = std::make_pair(*previous, pr);
        previous = pr;
      }
    }

    // 6. Refine by bisection on g, which changes sign in the bracket. A
    //    probe that finds no forward mode (the orbit turns flat) ends the
    //    refinement where it is.
    if (!bracket) {
      if (root) std::printf("\nno 1X forward crossing below %g rad/s\n", maxSpeed);
      return ExitSuccess;
    }
    Probe lo = bracket->first, hi = bracket->second;
    for (int i = 0; i < bisections; ++i) {
      const Probe mid = probe(0.5 * (lo.speed + hi.speed));
      const auto gm = g(mid);
      if (!gm) break;
      (*gm > 0 ? lo : hi) = mid;
    }
    // Linear interpolation of g inside the final bracket (its midpoint if
    // the bracket still starts at rest, where g has no finite value).
    const double glo = *g(lo), ghi = *g(hi);
    const double critical = std::isfinite(glo) ? lo.speed + (hi.speed - lo.speed) * glo / (glo - ghi)
                                               : 0.5 * (lo.speed + hi.speed);
    if (root)
      std::printf("\n1X forward critical speed of %s: %.8g rad/s = %.6g rpm (bracket width %.2e rad/s)\n",
                  parameters[p].name.c_str(), critical, critical * 60.0 / (2.0 * M_PI), hi.speed - lo.speed);
    return ExitSuccess;
  });
}
