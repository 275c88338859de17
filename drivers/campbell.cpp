// campbell: Campbell diagram of a spinning shaft, the project's default job.
//
// Computes the whirl frequencies of a simply supported, spinning Rayleigh
// shaft over a speed sweep, with the dense gyroscopic eigensolver on a
// Rayleigh-Ritz model built from admissible functions (not eigenfunctions),
// and prints:
//   1. the Campbell table: speed, frequency and whirl sense (FW/BW) of the
//      lowest modes, the largest residual of the solve, stability;
//   2. the synchronous (1X) critical speeds, each beside its closed form;
//   3. the accuracy of every frequency at the top speed against the closed form.
// Exit code 0 when every solve converged and every check was run, 4 when a
// solve did not converge, 2 on bad options.
//
// Sample runs:
//   campbell
//   campbell --functions=4 --max-rpm=80000 --steps=17
//   campbell --radius=0.08 --length=0.6 --modes=4
//
// (The full substructure-synthesis scene replaces this default in a later
// release; see doc/user-guide.md.)

#include <cmath>
#include <iomanip>
#include <iostream>
#include <vector>

#include <Teuchos_CommandLineProcessor.hpp>

#include "cms/analysis/Campbell.hpp"
#include "cms/core/Error.hpp"
#include "cms/fem/SpinningRayleighShaft.hpp"

int main(int argc, char* argv[]) {
  using namespace cms;
  try {
    // 1. Options, printed back so every output records how it was produced.
    fem::ShaftProperties shaft;
    shaft.length = 0.5;
    shaft.radius = 0.05;
    int functions = 8, modes = 3, steps = 13;
    double maxRpm = 60000.0;
    Teuchos::CommandLineProcessor clp(false, true);
    clp.setDocString("Campbell diagram of a spinning simply supported Rayleigh shaft.");
    clp.setOption("length", &shaft.length, "shaft length (m)");
    clp.setOption("radius", &shaft.radius, "shaft radius (m)");
    clp.setOption("E", &shaft.youngsModulus, "Young's modulus (Pa)");
    clp.setOption("rho", &shaft.density, "density (kg/m^3)");
    clp.setOption("functions", &functions, "admissible functions per bending plane");
    clp.setOption("modes", &modes, "number of modes in the table");
    clp.setOption("max-rpm", &maxRpm, "top speed of the sweep (rev/min)");
    clp.setOption("steps", &steps, "number of speeds in the sweep (>= 2)");
    if (clp.parse(argc, argv) != Teuchos::CommandLineProcessor::PARSE_SUCCESSFUL)
      return ExitInputError;
    CMS_INPUT_CHECK(steps < 2, "--steps = " << steps << " must be at least 2");
    CMS_INPUT_CHECK(!(maxRpm > 0.0), "--max-rpm = " << maxRpm << " must be positive");
    CMS_INPUT_CHECK(modes < 1 || modes > 2 * functions,
                    "--modes = " << modes << " must be in [1, 2*functions = " << 2 * functions << "]");
    std::cout << "campbell: shaft L = " << shaft.length << " m, r = " << shaft.radius
              << " m, E = " << shaft.youngsModulus << " Pa, rho = " << shaft.density
              << " kg/m^3; " << functions << " admissible functions per plane; " << steps
              << " speeds to " << maxRpm << " rpm\n\n";

    // 2. The Ritz model, stored per unit speed (M, G1, K) so the sweep never reassembles.
    fem::SpinningRayleighShaft model(shaft, functions);
    analysis::SpeedDependentSystem sys{model.massMatrix(), model.gyroscopicPerUnitSpeed(),
                                       model.stiffnessMatrix(), DenseMatrix(),
                                       model.whirlPairs()};

    // 3. Sweep.
    std::vector<double> speeds;
    const double maxOmega = maxRpm * 2.0 * M_PI / 60.0;
    for (int s = 0; s < steps; ++s) speeds.push_back(maxOmega * s / (steps - 1));
    Teuchos::ParameterList solverParams;
    solverParams.set("Number of Modes", modes);
    const analysis::CampbellDiagram diagram = analysis::campbell(sys, speeds, solverParams);
    std::cout << "Campbell table (solver: " << diagram.points.front().solver << ")\n";
    diagram.print(std::cout, modes);

    // 4. Synchronous critical speeds against the closed form (doc/theory.md).
    std::cout << "\n1X critical speeds (rpm), computed vs closed form:\n";
    const double A = M_PI * shaft.radius * shaft.radius, I = M_PI * std::pow(shaft.radius, 4) / 4;
    const double rhoA = shaft.density * A, rhoI = shaft.density * I, EI = shaft.youngsModulus * I;
    for (const auto& c : diagram.criticalSpeeds(1.0)) {
      const int k = c.modeIndex / 2 + 1;  // modes come in BW/FW pairs per bending order
      const double kk = k * M_PI / shaft.length;
      const double denom = c.whirl == analysis::Whirl::Forward ? rhoA - rhoI * kk * kk
                                                               : rhoA + 3.0 * rhoI * kk * kk;
      const double exact = std::sqrt(EI * std::pow(kk, 4) / denom);
      std::cout << "  mode " << c.modeIndex + 1 << " (" << analysis::toString(c.whirl)
                << ", bending order " << k << "): " << std::fixed << std::setprecision(0)
                << c.speed * 30.0 / M_PI << "  vs  " << exact * 30.0 / M_PI << std::scientific
                << std::setprecision(2) << "   (rel. diff " << std::abs(c.speed - exact) / exact
                << ", includes the sweep's linear interpolation)\n";
    }

    // 5. Accuracy at the top speed: every Ritz frequency bounds its exact value from above.
    const auto& top = diagram.points.back();
    std::cout << "\nAt " << std::fixed << std::setprecision(0) << maxRpm
              << " rpm, Ritz vs closed form:\n";
    bool allConverged = true;
    for (int m = 0; m < static_cast<int>(top.modes.size()); ++m) {
      const int k = m / 2 + 1;
      const auto [fw, bw] = fem::SpinningRayleighShaft::exactWhirl(shaft, k, top.speed);
      const double exact = top.whirl[m] == analysis::Whirl::Forward ? fw : bw;
      std::cout << "  mode " << m + 1 << " " << analysis::toString(top.whirl[m]) << std::fixed
                << std::setprecision(4) << "  " << top.modes[m].hz << " Hz  exact "
                << exact / (2 * M_PI) << " Hz  rel. error " << std::scientific
                << std::setprecision(2) << (top.modes[m].omega - exact) / exact << "  residual "
                << top.modes[m].residual << "\n";
      allConverged &= top.modes[m].residual < 1e-8;
    }
    return allConverged ? ExitSuccess : ExitNotConverged;
  } catch (const cms::InputError& e) {
    std::cerr << "campbell: input error: " << e.what() << "\n";
    return ExitInputError;
  } catch (const cms::NumericalError& e) {
    std::cerr << "campbell: numerical failure: " << e.what() << "\n";
    return ExitNumericalError;
  } catch (const std::exception& e) {
    std::cerr << "campbell: internal error: " << e.what() << "\n";
    return ExitInternalError;
  }
}
