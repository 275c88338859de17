// Example 1: the modes of a spinning spacecraft by component-mode synthesis.
//
// Computes the lowest whirl frequencies of the default scene of `cms`, a
// free-floating bus spinning at 1 rad/s that carries two flexible booms, a
// momentum wheel and an antenna spinning on a flexible mast, and prints
// every mode with the two numbers that say how far to trust it: its
// residual (how well it solves the reduced equations) and its estimated
// error against the full finite-element model (how well the reduced
// equations stand for the structure), both computed without solving the
// full model.
//
// The structure is written here in code, as the same parameter list a YAML
// scene becomes (drivers/scenes/spacecraft.yaml), and read through the scene
// API, so it is checked key by key exactly like a file; --scene reads a file
// instead. The phases that `cms modes` runs in one call
// (analysis::ModalAnalysis) are spelled out one by one.
//
// Build: in the cms build tree (build/examples/ex1_spacecraft), or against an
// installed cms (examples/CMakeLists.txt: find_package(cms), cms::cms).
// Sample runs:
//   ex1_spacecraft
//   ex1_spacecraft --modes=16 --vectors=12 --wheel-speed=300
//   ex1_spacecraft --scene=<prefix>/share/cms/scenes/rotor-chain.yaml
//   mpiexec -n 2 ex1_spacecraft
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <Teuchos_Array.hpp>
#include <Teuchos_ParameterList.hpp>

#include "cms/analysis/ZeroFrequencies.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/Program.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace {

using Teuchos::ParameterList;

Teuchos::Array<double> xyz(double x, double y, double z) {
  Teuchos::Array<double> a;
  a.push_back(x), a.push_back(y), a.push_back(z);
  return a;
}

/// A straight aluminium frame beam from `from` to `to` (the scene's "Beam"
/// keys: the scene layer meshes it and names its node sets start, mid, end).
ParameterList beam(Teuchos::Array<double> from, Teuchos::Array<double> to, int elements, double area, double iy,
                   double iz, double torsion) {
  ParameterList b("Beam");
  b.set("From", from), b.set("To", to), b.set("Elements", elements);
  b.set("Young's Modulus", 7.0e10), b.set("Density", 2700.0);
  b.set("Area", area), b.set("Iy", iy), b.set("Iz", iz), b.set("Torsion Constant", torsion);
  return b;
}

ParameterList reduction(const std::string& basis, int vectors) {
  ParameterList r("Reduction");
  r.set("Basis", basis), r.set("Vectors", vectors);
  return r;
}

/// A child attached at one parent node (its attachment frame follows that
/// node's translation and rotation, theory §11.2); `nodes`: the child's
/// node set that moves rigidly with it.
ParameterList attachment(const std::string& parentNodes, const std::string& nodes) {
  ParameterList a("Attachment");
  a.set("Type", std::string("Node")), a.set("Parent Nodes", parentNodes);
  if (!nodes.empty()) a.set("Nodes", nodes);
  return a;
}

/// The spacecraft of drivers/scenes/spacecraft.yaml, as a "Scene" list.
ParameterList spacecraft(int vectors, double wheelSpeed) {
  ParameterList s("Scene");
  s.set("Name", std::string("spacecraft"));
  // The bus floats: its six rigid-body coordinates are taken at its middle
  // node (theory §11.6); its frame spins at 1 rad/s about z (§11.1).
  s.set("Free Reference", std::string("mid"));
  ParameterList& subs = s.sublist("Substructures");

  ParameterList& bus = subs.sublist("bus");
  bus.set("Kind", std::string("C"));
  bus.sublist("Spin").set("Axis", xyz(0, 0, 1)).set("Origin", xyz(0, 0, 0)).set("Rate", 1.0);
  bus.set("Beam", beam(xyz(-0.5, 0, 0), xyz(0.5, 0, 0), 4, 0.02, 1e-4, 1e-4, 2e-4));
  bus.set("Reduction", reduction("Craig-Bampton", 4));

  // Two booms (E: turning with the bus, so centrifugally stiffened, §11.4),
  // reduced by admissible vectors: static shapes under the loads the
  // attachment and the spin apply, then Krylov continuations (§11.3).
  for (const std::string side : {"+", "-"}) {
    ParameterList& boom = subs.sublist("boom" + side);
    const double x = side == "+" ? 1.0 : -1.0;
    boom.set("Kind", std::string("E")), boom.set("Parent", std::string("bus"));
    boom.set("Attachment", attachment(side == "+" ? "end" : "start", "start"));
    ParameterList b = beam(xyz(0.5 * x, 0, 0), xyz(5.5 * x, 0, 0), 10, 3e-4, 2e-8, 3e-8, 4e-8);
    b.set("Tip Mass", 5.0);
    boom.set("Beam", b);
    boom.set("Reduction", reduction("Admissible", vectors));
  }

  // The momentum wheel (R): a rigid rotor at the bus centre, its angular
  // momentum entering the bus's gyroscopic matrix (§11.5).
  ParameterList& wheel = subs.sublist("wheel");
  wheel.set("Kind", std::string("R")), wheel.set("Parent", std::string("bus"));
  wheel.set("Attachment", attachment("mid", ""));
  wheel.sublist("Rotor").set("Mass", 8.0).set("Transverse Inertia", 0.04).set("Axial Inertia", 0.07);
  wheel.sublist("Spin").set("Axis", xyz(0, 0, 1)).set("Rate", wheelSpeed);

  // The antenna (A): an axisymmetric mast and dish spinning at 10 rad/s
  // relative to the bus, in the stationary (Nelson-McVaugh) form (§9.4).
  ParameterList& antenna = subs.sublist("antenna");
  antenna.set("Kind", std::string("A")), antenna.set("Parent", std::string("bus"));
  antenna.set("Attachment", attachment("mid", "start"));
  ParameterList mast = beam(xyz(0, 0, 0), xyz(0, 0, 2), 8, 4e-4, 5e-8, 5e-8, 1e-7);
  mast.set("Orientation", xyz(1, 0, 0)), mast.set("Tip Mass", 3.0), mast.set("Tip Inertia", xyz(0.3, 0.3, 0.5));
  antenna.set("Beam", mast);
  antenna.sublist("Spin").set("Axis", xyz(0, 0, 1)).set("Rate", 10.0).set("Frame", std::string("Stationary"));
  antenna.set("Reduction", reduction("Admissible", vectors));
  return s;
}

}  // namespace

int main(int argc, char* argv[]) {
  using namespace cms;
  return runProgram("ex1_spacecraft", argc, argv, [&](const CommPtr& comm, bool root) -> int {
    // 1. Options, printed back so that the output records how it was made.
    int modes = 12, vectors = 8;
    double wheelSpeed = 600.0;
    std::string scenePath;
    ProgramOptions options("ex1_spacecraft",
                           "Modes of a spinning spacecraft by component-mode synthesis (examples/ex1_spacecraft.cpp).");
    options.add("modes", &modes, "lowest modes to compute");
    options.add("vectors", &vectors, "admissible vectors per boom and for the mast");
    options.add("wheel-speed", &wheelSpeed, "momentum wheel speed relative to the bus (rad/s)");
    options.add("scene", &scenePath, "read this YAML scene instead of the built-in spacecraft");
    if (const auto exit = options.parse(argc, argv, *comm)) return *exit;
    CMS_INPUT_CHECK(modes < 1, "--modes = " << modes << " must be at least 1");
    CMS_INPUT_CHECK(vectors < 1, "--vectors = " << vectors << " must be at least 1");

    // 2. The structure: a tree of substructures of the paper's kinds C, E, R
    //    and A (theory §11.1), read and checked like a scene file.
    scene::Scene sc = scenePath.empty() ? scene::Scene::fromParameters(spacecraft(vectors, wheelSpeed), "spacecraft")
                                        : scene::Scene::read(scenePath);
    sc.solve.set("Number of Modes", modes);

    // 3. Assemble every substructure's finite-element matrices per unit spin
    //    speed, leaves first, so that each centrifugal prestress sees its
    //    children's reactions (§11.4). One assembly serves every reduction.
    const auto structure = synthesis::AssembledStructure::assemble(sc.structure, comm);

    // 4. Reduce each substructure by its Ritz basis and couple them through
    //    the interface transforms u_s = T_s q (§11.2, §11.3): M, G_i, K_0 and
    //    K_ij of the whole structure, kept per speed parameter.
    const auto reduced = synthesis::SynthesizedStructure::synthesize(structure);
    if (root) {
      std::printf("\n%-10s %-4s %-14s %8s %6s %14s\n", "substruct.", "kind", "basis", "DOFs", "q", "lowest est. Hz");
      for (const auto& r : reduced.reductions())
        std::printf("%-10s %-4s %-14s %8lld %6d %14.4g\n", r.name.c_str(), r.kind.c_str(), r.basis.c_str(),
                    r.physicalDofs, r.coordinates,
                    r.frequencyEstimates.empty() ? 0.0 : r.frequencyEstimates.front() / (2 * M_PI));
      std::printf("%lld coordinates in all\n", reduced.size());
    }

    // 5. Solve M q'' + G q' + K q = 0 at the nominal speeds; the eigen layer
    //    picks Meirovitch's symmetric form when K > 0 (§2) or the general
    //    path (§3) and recomputes every residual from these matrices (§4).
    auto solution = reduced.solve(structure.nominalSpeeds(), sc.solve);
    // A floating structure has six zero frequencies by construction; any
    // other zero is a critical speed, an unrestrained or an ill-conditioned
    // part, each with its own answer (§4.3): relabel or refuse.
    analysis::checkZeroFrequencies(structure, reduced, solution, sc.solve);

    // 6. How far to trust each mode, without the full model: the residual,
    //    the estimated error against the truth from each substructure's own
    //    residual (§11.8), and which substructure carries the mode's kinetic
    //    energy (§11.6; a "frame" mode is a rigid motion fixed in space, seen
    //    from the spinning frame at the frame rate).
    const auto estimates = reduced.errorEstimates(solution);
    const auto character = reduced.characterise(solution);
    const auto& result = solution.result;
    if (root) {
      std::printf("\nsolver: %s (%s)\n", result.solver.c_str(), solution.path.c_str());
      std::printf("%4s %12s %12s %-10s %10s %11s  %s\n", "mode", "Hz", "rad/s", "stability", "residual",
                  "est. error", "dominant");
      for (std::size_t m = 0; m < result.modes.size(); ++m) {
        const auto& md = result.modes[m];
        const auto& share = character[m].kineticShare;
        const auto k = std::max_element(share.begin(), share.end()) - share.begin();
        char estimate[32] = "-";
        if (estimates[m] >= 0) std::snprintf(estimate, sizeof estimate, "%.2e", estimates[m]);
        std::printf("%4zu %12.6g %12.6g %-10s %10.2e %11s  %s%s\n", m + 1, md.hz, md.omega,
                    eigen::toString(md.stability), md.residual, estimate, reduced.reductions()[k].name.c_str(),
                    character[m].frameArtefact ? " (frame)" : "");
      }
      std::printf("status: %s, largest residual %.2e\n", eigen::toString(result.status), result.maxResidual());
    }
    // A residual is a backward error: anything near n eps means the reduced
    // equations are solved to rounding; the error estimate, not the
    // residual, is what more vectors (--vectors) would improve.
    return result.status == eigen::SolveStatus::Converged ? ExitSuccess : ExitNotConverged;
  });
}
