// cms modes: the structure's lowest modes at the scene's speeds, each with
// its accuracy (doc/user-guide.md, "cms modes").
//
// For every mode: frequency (Hz, rad/s), growth rate, stability and damping ratio (§13), the
// residual of the reduced equations, the estimated relative error against
// the truth model without solving it (doc/theory.md §11.8), the
// substructure carrying most of its kinetic energy and the whirl of each
// spinning part. For every substructure: its basis, its own frequencies
// (the paper's truncation guide) and whether its basis can miss modes below
// the highest frequency found (a Sturm count, §11.9).
//
// Sample runs:
//   cms modes
//   cms modes drivers/scenes/rotor-chain.yaml --truth --check-count
//   mpiexec -n 2 cms modes drivers/scenes/spacecraft.yaml --vtu --output=/tmp/sc
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <Teuchos_DefaultComm.hpp>

#include "../DriverBoundary.hpp"
#include "cms/core/PeakMemory.hpp"
#include "Command.hpp"
#include "cms/analysis/ModalAnalysis.hpp"
#include "cms/analysis/TruthComparison.hpp"
#include "cms/io/ModeShapeFiles.hpp"
#include "cms/io/ModesReport.hpp"
#include "cms/reduction/RitzBasis.hpp"

namespace cms::drivers {

namespace {

/// A basis whose size is not what its "Vectors" asks: one line naming the
/// substructure, the counts asked and kept, and why (the JSON's "dropped"
/// lists every candidate); empty when it is. Under a cut-off the count is
/// the cut-off's, not "Vectors" (whose default 6 was reported as asked;
/// found by a review): nothing to compare with.
std::string droppedNote(const synthesis::SubstructureReduction& r, const Teuchos::ParameterList& reduction) {
  Teuchos::ParameterList p(reduction);
  p.validateParametersAndSetDefaults(*reduction::validParameters());
  const bool cutoff = p.get<double>("Cutoff Frequency") > 0.0;
  const int asked = p.get<int>("Vectors");
  const bool modes = r.basis == "Craig-Bampton";  // "Vectors" counts its fixed-interface modes
  // The static corrections of a child's own supports come beyond "Vectors"
  // (theory §11.2), and those repeating another's loads are dropped as
  // dependent by design: neither is what "Vectors" asked (a Guyan boom read
  // "6 vectors asked, 2 kept"; a review).
  auto correction = [](const std::string& s) { return s.rfind(reduction::kOwnSupportsColumn, 0) == 0; };
  int kept = 0, shapesLeft = 0;
  for (const auto& l : r.labels) kept += !correction(l) && (!modes || l.rfind("mode ", 0) == 0);
  for (const auto& d : r.dropped) shapesLeft += d.find(reduction::kAttachmentShapeLeftOut) != std::string::npos;
  // Admissible: fewer vectors than its children's attachment shapes hold the
  // later children rigidly (theory §11.3), whether Vectors or a cut-off's
  // count set them (found by a review).
  if (shapesLeft > 0) {
    std::ostringstream os;
    os << "note: " << r.name << ": Admissible basis: its " << kept << " vectors"
       << (cutoff ? " (the cut-off's count)" : "") << " keep " << kept << " of the " << kept + shapesLeft
       << " static shapes under its children's interface loads: " << shapesLeft
       << " left out, the later children's attachments held rigidly to the basis; "
       << (cutoff ? "raise the cut-off, or replace it by Vectors >= " : "ask Vectors >= ") << kept + shapesLeft
       << " (theory §11.3)";
    return os.str();
  }
  const bool onlyCorrections = std::all_of(r.dropped.begin(), r.dropped.end(), correction);
  if (cutoff || onlyCorrections || kept >= asked || r.basis == "Guyan") return {};  // (Guyan reads no "Vectors")
  int dependent = 0, massless = 0;
  std::string other;
  for (const auto& d : r.dropped) {
    if (correction(d)) continue;
    if (d.find("zero M-norm") != std::string::npos) ++massless;
    else if (d.find("after projection") != std::string::npos) ++dependent;
    else other += "; " + d;
  }
  std::ostringstream os;
  os << "note: " << r.name << ": " << r.basis << " basis: " << asked << (modes ? " modes" : " vectors") << " asked, "
     << kept << " kept: ";
  if (dependent) os << dependent << " candidate(s) linearly dependent on those kept (dropped at \"Dependence Tolerance\" "
                    << p.get<double>("Dependence Tolerance") << ")";
  if (massless) os << (dependent ? ", " : "") << massless << " with no mass on the free DOFs";
  os << other << " (the list: \"dropped\" in the JSON)";
  return os.str();
}

/// Past 10% the first-order estimate is a flag, not a number (theory §11.8).
std::string estimateText(double e) {
  std::ostringstream os;
  os << std::setprecision(2);
  if (e >= 0.1) os << "unresolved";
  else if (e >= 0.0) os << e;
  else os << "-";
  return os.str();
}

/// The rigorous bound where the structure is SPD (theory §11.8): "KT" for
/// Kato-Temple, "KB" for Krylov-Bogoliubov; "-" when there is none.
std::string boundText(const synthesis::ModeAccuracy& a) {
  std::ostringstream os;
  os << std::setprecision(2);
  if (a.bound < 0.0) os << "-";
  else if (a.bound >= 0.1) os << ">0.1";
  else os << a.bound << (a.boundKind == "Kato-Temple" ? " KT" : " KB");
  return os.str();
}

void printSubstructures(const analysis::ModalResult& r) {
  const auto& structure = *r.structure;
  const auto& reps = r.reduced->reductions();
  std::cout << "substructure  kind  DOFs      basis          coords  lowest own frequencies (Hz, attachment held)\n";
  for (const auto& s : reps) {
    std::cout << std::left << std::setw(14) << s.name << std::setw(6) << s.kind << std::setw(10) << s.physicalDofs
              << std::setw(15) << s.basis << std::setw(8) << s.coordinates << std::right;
    for (std::size_t k = 0; k < std::min<std::size_t>(4, s.frequencyEstimates.size()); ++k)
      std::cout << std::setprecision(5) << s.frequencyEstimates[k] / (2 * M_PI) << ' ';
    std::cout << '\n';
  }
  for (std::size_t k = 0; k < reps.size(); ++k)
    if (const auto n = droppedNote(reps[k], structure.substructure(k).reduction); !n.empty()) std::cout << n << '\n';
  for (const auto& s : reps)  // how a Partitioned basis was made, and where its time went (theory §18)
    if (s.basis == "Partitioned" && s.turnedFrom.empty())
      std::cout << s.name << ": " << s.eigensolverReport << " (" << std::setprecision(3) << s.seconds << " s)\n";
  for (const auto& s : reps) {  // copies (theory §15.2)
    if (!s.turnedFrom.empty())
      std::cout << s.name << ": basis of " << s.turnedFrom << " turned (" << std::setprecision(2) << s.seconds
                << " s, " << s.basisBytes / 1e6 << " MB of vectors; no factorisation or eigensolve of its own)\n";
    if (!s.notTurned.empty()) std::cout << "FINDING: " << s.name << " reduced on its own: " << s.notTurned << '\n';
  }
  for (const auto& n : structure.notes()) std::cout << "note: " << n << '\n';
  // Missing-mode detection (theory §11.9).
  std::cout << "coverage below " << std::setprecision(5) << r.cutoff / (2 * M_PI)
            << " Hz (the highest mode; Sturm count of each substructure with its attachment held):";
  for (const auto& c : r.coverage)
    if (c.verdict != "Full" && c.verdict != "rigid") std::cout << "\n  " << c.name << ": " << c.verdict;
  if (r.truthCount >= 0)
    std::cout << "\n  structure: the truth has " << r.truthCount << " frequencies below " << r.countAt / (2 * M_PI)
              << " Hz, the reduced model " << r.reducedCount
              << (r.truthCount > r.reducedCount
                      ? ": MODES MISSING (a family the bases lack, or errors that push modes past it)"
                      : ": none missing")
              << (r.countBand > 0.0 ? " (reduced frequencies counted up to " +
                                          [&] {
                                            std::ostringstream b;
                                            b << std::setprecision(2) << r.countBand;
                                            return b.str();
                                          }() + " above it, the highest mode's estimated error: theory §11.9)"
                                    : std::string());
  else if (const std::string why = analysis::truthCountNote(r.truthCount); !why.empty())
    std::cout << "\n  structure: " << why << (r.truthCount == -1 ? "" : " (theory §11.9)");
  if (r.truthMissing > 0)
    std::cout << "\n  structure: the truth has " << r.truthMissing
              << " mode(s) in the reduced modes' range that none of them pairs with: MODES MISSING";
  if (r.truthUnmatched > 0)
    std::cout << "\n  structure: " << r.truthUnmatched
              << " reduced mode(s) have the shape of no truth mode computed (their true error not given)";
  if (r.truthMissing == 0 && r.truthUnmatched <= 0)
    std::cout << "\n  structure: every truth mode in the reduced modes' range paired with one (one to one)";
  std::cout << '\n';
}

void printModes(const analysis::ModalResult& r) {
  const auto& structure = *r.structure;
  const auto& reps = r.reduced->reductions();
  const auto& result = r.modes.result;
  std::cout << "\nspeeds (rad/s):";
  for (std::size_t i = 0; i < r.speeds.size(); ++i) std::cout << ' ' << structure.speeds()[i].name << " = " << r.speeds[i];
  std::cout << "\nsolver: " << result.solver << (result.reason.empty() ? "" : " (" + condense(result.reason) + ")")
            << "\n\n mode      Hz          rad/s       growth (1/s)  stability       zeta  residual  est.error       bound  "
               "largest share, whirl (FW/BW)\n";
  for (std::size_t m = 0; m < result.modes.size(); ++m) {
    const auto& md = result.modes[m];
    const auto& share = r.character[m].kineticShare;
    const std::size_t top = std::max_element(share.begin(), share.end()) - share.begin();
    std::cout << std::setw(5) << m + 1 << std::setw(12) << std::setprecision(6) << md.hz << std::setw(12) << md.omega
              << std::setw(14) << std::setprecision(3) << md.growthRate << "  " << std::left << std::setw(11)
              << toString(md.stability) << std::right << std::setw(11) << std::setprecision(3) << md.dampingRatio
              << std::setw(10) << std::setprecision(2) << md.residual
              << std::setw(11) << estimateText(r.estimates[m]) << std::setw(12) << boundText(r.accuracy[m]);
    if (m < r.trueErrors.size()) {
      if (std::isfinite(r.trueErrors[m])) std::cout << " (true " << std::setprecision(2) << r.trueErrors[m] << ")";
      else std::cout << " (true: no truth mode of this shape computed)";
    }
    std::cout << "  " << reps[top].name << " " << std::setprecision(3) << share[top]
              << (r.character[m].frameArtefact ? "  (rigid motion seen at the frame rate: not a vibration)" : "");
    for (const auto& w : r.whirls[m]) std::cout << "  " << w;
    for (const auto& c : r.character[m].cyclic) {  // its share when the harmonics mix (an asymmetric parent)
      std::cout << "  " << c.group << ": " << c.label();
      if (c.share[c.dominant] < 0.99) std::cout << " (" << std::setprecision(2) << c.share[c.dominant] << ")";
    }
    std::cout << '\n';
  }
  // The stability margin of a damped structure (theory §13.3). The verdict
  // is the modes' classification (growth beyond what rounding can make),
  // not the sign of the least ratio: an undamped mode of a damped structure
  // (a hinge's flap mode beside a lag damper) has zeta = +-1e-15.
  const long undecided = std::count_if(result.modes.begin(), result.modes.end(),
                                       [](const eigen::GyroscopicMode& m) { return m.undecided; });
  if (!r.reduced->damping().is_null())
    std::cout << "least damping ratio: " << std::setprecision(4) << result.leastDampingRatio()
              << (!result.isStable() ? " (UNSTABLE: a mode grows" +
                                           (undecided > 0 ? "; UNDECIDED: " + std::to_string(undecided) +
                                                                " more have a growth rate whose sign is within its uncertainty, marked neutral)"
                                                          : std::string(")"))
                  : undecided > 0      ? " (UNDECIDED: " + std::to_string(undecided) +
                                        " mode(s) have a growth rate whose sign is within its uncertainty, marked neutral)"
                  : result.leastDampingRatio() < 0.0
                      ? std::string(result.energyBound.shown ? " (rounding: every mode stable, by the energy bound)"
                                                             : " (rounding: every mode stable)")
                      : std::string())
              << '\n';
  // What decides a growth rate within its uncertainty (theory §13.3).
  if (!r.reduced->damping().is_null() && !result.energyBound.note.empty())
    std::cout << "energy bound: " << result.energyBound.note << '\n';
}

}  // namespace

int modes(int argc, char* argv[]) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  // 1. Options and scene.
  Options options("modes",
                  "The structure's lowest modes at the scene's speeds, each with its residual and estimated error\n"
                  "against the truth model (doc/theory.md 11.8), and each substructure's missing-mode check (11.9).");
  bool vtu = false, truth = false, checkCount = false;
  options.flag("vtu", &vtu, "mode shapes for ParaView (.vtu per mode, .pvd)");
  options.flag("truth", &truth, "also solve the truth model and print the true error beside each estimate");
  options.flag("check-count", &checkCount,
               "count the truth's frequencies below the highest one (one factorisation of the assembled model)");
  std::string periodic = "Auto";
  options.add("periodic", &periodic,
              "a rotor on a moving attachment (theory 16.8): Auto, Multi-Blade or Floquet (e.g. to check the "
              "multi-blade answer)");
  SceneRun run;
  if (const auto exit = run.start(options, argc, argv)) return *exit;
  const auto& sc = run.scene;
  const bool root = run.root;

  // 2. The analysis (analysis::ModalAnalysis: assemble, reduce, solve, judge).
  Teuchos::ParameterList study;
  study.set("Speed Factor", sc.speedFactor);
  study.set("Target Accuracy", sc.targetAccuracy);
  study.set("Truth", truth);
  study.set("Check Count", checkCount);
  study.set("Periodic Method", periodic);
  analysis::ModalAnalysis modal(sc.structure, sc.solve, study);
  // Nobody waits minutes in silence: a large scene's every stage, and any
  // scene's Floquet doubling (a periodic rotor's runs grow with its bases,
  // not its DOFs), are said as they end.
  const bool large = sc.estimatedDofs > scene::Scene::kLargeDofs;
  if (root && large)
    std::cout << stamp(seconds()) << std::setprecision(3) << "assembling " << sc.structure.substructures.size()
              << " substructures: " << sc.estimatedDofs << " DOFs, at least " << sc.estimatedBytes / 1e9 << " GB of the "
              << scene::availableMemoryBytes() / 1e9 << " GB available" << std::endl;
  if (root)
    modal.setProgress([&, large](const std::string& what) {
      if (large || what.find("Floquet: ") != std::string::npos) std::cout << stamp(seconds()) << what << std::endl;
    });
  const auto r = run.namingScene([&] { return modal.run(Teuchos::DefaultComm<int>::getComm()); });
  if (root)
    for (const auto& n : r.enrichment.notes) std::cout << "target accuracy " << sc.targetAccuracy << ": " << n << '\n';
  if (!r.enrichment.reached) {
    if (root)
      std::cerr << "cms: " << kNotConverged.message << " (exit " << kNotConverged.code << "): Target Accuracy "
                << sc.targetAccuracy << " not reached (worst estimate " << r.enrichment.worstEstimate
                << "); no files written\n";
    return kNotConverged.code;
  }

  // 3. The report, then the files: only a success writes files.
  const Outcome outcome = drivers::outcome(r.modes.result.status);
  if (root) {
    std::cout << stamp(seconds()) << "solved (" << r.modes.path << "): " << r.reduced->size() << " coordinates\n\n";
    printSubstructures(r);
    printModes(r);
  }
  if (outcome.code != ExitSuccess) {
    if (root)
      std::cerr << "cms: " << outcome.message << " (status " << toString(r.modes.result.status) << ", exit "
                << outcome.code << "): " << condense(r.modes.result.reason) << "; no files written\n";
    return outcome.code;
  }
  // 6. The files, all written or none (io::OutputFiles): a failure on the
  //    last leaves not the first behind.
  const auto base = run.outDir / sc.name;
  io::OutputFiles files;
  if (root) {
    if (sc.csv) {
      io::writeModesCsv(files, base.string() + "-modes.csv", r);
      io::writeCoverageCsv(files, base.string() + "-coverage.csv", r);
    }
    if (sc.json) {
      io::writeModesJson(files, base.string() + ".json", r,
                         {sc.path, sc.text, sc.name, sc.units, CMS_VERSION,
                          Teuchos::DefaultComm<int>::getComm()->getSize(), peakRssMiB()});
    }
  }
  std::vector<std::string> shapes;
  if (vtu)  // collective
    shapes = io::writeModeShapes(files, *r.structure, *r.reduced, r.modes, run.outDir.string(), sc.name);
  files.commit(*Teuchos::DefaultComm<int>::getComm());  // collective
  if (root) {
    std::cout << "\nwrote " << base.string() << (sc.json ? ".json " : " ")
              << (sc.csv ? "(and -modes.csv, -coverage.csv)" : "") << '\n';
    if (vtu) std::cout << "wrote " << shapes.size() - 1 << " mode shapes for ParaView: " << shapes.back() << '\n';
  }
  return ExitSuccess;
}

}  // namespace cms::drivers
