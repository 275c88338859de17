// cms: run a scene — a structure of substructures with rotating parts — by
// component-mode synthesis (doc/user-guide.md, "The cms driver").
//
//   cms modes [SCENE]     the structure's lowest modes at the scene's speeds:
//                         frequencies (Hz, rad/s), stability, residuals, the
//                         share of each substructure in each mode, and each
//                         substructure's own frequency estimates (the
//                         paper's truncation guide)
//   cms campbell [SCENE]  a speed sweep of the reduced model (every spin rate
//                         scaled from 0 to --max-factor times its nominal
//                         value, no re-projection): modes tracked across
//                         speeds by MAC (not by sorting, so crossings and
//                         veerings stay right), critical speeds where a
//                         tracked frequency meets an engine order of the
//                         first spin rate, and the speed ranges where any
//                         mode is unstable
//   cms truncate [SCENE]  a convergence study: starting from --start vectors
//                         per substructure, add --step vectors at a time to
//                         the substructure whose addition lowers the
//                         estimated error (no truth solve; --truth prints
//                         the true error beside it) most per coordinate, until
//                         the lowest "Number of Modes" are within
//                         --accuracy; each step checks the inclusion
//                         principle; ends with the suggested counts
//   cms compare [SCENE]   the same structure reduced by every strategy
//                         (Guyan; Admissible, Modes, Craig-Bampton at several
//                         vector counts) against its truth model: reduced
//                         DOFs, times, peak memory, max and mean frequency
//                         error, worst MAC — the table to choose a strategy from
//
// Without SCENE the built-in spacecraft (drivers/scenes/spacecraft.yaml) runs.
// Results go to --output (default ./cms-results, or the scene's "Output"
// directory): <name>.json and CSV tables, written to a temporary name and
// renamed, and only when the run succeeded: any other exit code writes no
// file (drivers/DriverBoundary.hpp, the one table of outcomes). With --plot, the CSV
// tables of campbell, compare and truncate are also drawn as PNG by
// drivers/plot_results.py (Debian's python3-matplotlib).
//
// Exit codes (drivers::outcome): 0 success, 2 bad input (scene, options),
// 3 numerical breakdown (status NUMERICAL ISSUE), 4 a solve did not converge
// (NOT CONVERGED) or truncate's accuracy was not reached, 5 internal error.
//
// Sample runs:
//   cms modes
//   cms modes drivers/scenes/spacecraft.yaml --output=/tmp/sc
//   mpiexec -n 2 cms compare --counts=2,4,8
//   cms campbell --steps=41 --max-factor=3 --orders=1,2
//   cms truncate --accuracy=1e-4
//   cms modes drivers/bench/rotor/rotor.yaml --mesh-parameters=h=0.01

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <complex>
#include <limits>
#include <tuple>

#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Vector.hpp>

#include <Teuchos_CommandLineProcessor.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Teuchos_GlobalMPISession.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include <map>

#include <Teuchos_CommHelpers.hpp>

#include "DriverBoundary.hpp"
#include "PeakMemory.hpp"
#include "cms/analysis/ModeShapeFiles.hpp"
#include "cms/analysis/TruthComparison.hpp"
#include "cms/analysis/Enrichment.hpp"
#include "cms/analysis/ZeroFrequencies.hpp"
#include "cms/core/Error.hpp"
#include "cms/reduction/RitzBasis.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace {

using namespace cms;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// A file written under a temporary name and renamed on commit(), so that a
/// failed run leaves nothing half-written (rank 0 only).
class AtomicFile {
public:
  explicit AtomicFile(std::filesystem::path path) : path_(std::move(path)), tmp_(path_.string() + ".tmp") {
    out_.open(tmp_);
    CMS_INPUT_CHECK(!out_, path_.string() << ": cannot write");
    out_ << std::setprecision(12);
  }
  std::ofstream& stream() { return out_; }
  void commit() {
    out_.close();
    std::filesystem::rename(tmp_, path_);
  }
  ~AtomicFile() {
    if (out_.is_open()) {
      out_.close();
      std::filesystem::remove(tmp_);
    }
  }

private:
  std::filesystem::path path_;
  std::string tmp_;
  std::ofstream out_;
};

/// --plot: drivers/plot_results.py with Debian's python3-matplotlib, when present.
bool plotRequested = false;
bool vtuRequested = false;
bool truthRequested = false;  ///< modes, truncate: also solve the truth (--truth)
bool countRequested = false;  ///< modes: the truth's Sturm count at the highest frequency (--check-count)
void plot(const std::string& kind, const std::filesystem::path& csv) {
  if (!plotRequested) return;
  const auto png = std::filesystem::path(csv).replace_extension(".png");
  const std::string cmd = std::string(CMS_PYTHON) + " '" + CMS_SCRIPT_DIR + "/plot_results.py' " + kind + " '" +
                          csv.string() + "' '" + png.string() + "'";
  if (std::system(cmd.c_str()) == 0)
    std::cout << "plotted " << png.string() << '\n';
  else
    std::cout << "no plot: " << cmd << " failed (plots need Debian's python3-matplotlib: "
              << "apt-get install python3-matplotlib)\n";
}

std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    if (c == '\n') { o += "\\n"; continue; }
    o += c;
  }
  return o + "\"";
}

std::vector<double> scaledSpeeds(const synthesis::AssembledStructure& a, double factor) {
  auto s = a.nominalSpeeds();
  for (double& v : s) v *= factor;
  return s;
}

/// Whirl of a spinning substructure k in mode m: the orbit of its
/// transverse motion (translations of an elastic rotor's nodes; a rigid
/// rotor's tilts) turning with the spin (forward) or against it (backward);
/// "-" when the orbit is flat, or the motion is mostly axial or torsional.
std::string whirl(const synthesis::AssembledStructure& a, const std::vector<Teuchos::RCP<MultiVector>>& u,
                  std::size_t k, const eigen::GyroscopicMode& mode) {
  const auto& spec = a.substructure(k);
  if (!spec.spin) return "";
  fem::Vec3 n = spec.spin->axis;
  const double nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (double& v : n) v /= nn;
  // e1, e2 transverse with e1 x e2 = n.
  fem::Vec3 e1 = std::abs(n[0]) < 0.9 ? fem::Vec3{1, 0, 0} : fem::Vec3{0, 1, 0};
  const double d = e1[0] * n[0] + e1[1] * n[1] + e1[2] * n[2];
  for (int i = 0; i < 3; ++i) e1[i] -= d * n[i];
  const double n1 = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (double& v : e1) v /= n1;
  const fem::Vec3 e2{n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]};
  const auto map = u[k]->getMap();
  const auto* sub = a.assembled(k);
  const auto nodeOf = sub ? sub->dofs().rowNodes() : std::vector<std::int64_t>();
  // Per node (or the rotor's centre): the complex 3-vector of the chosen components.
  std::map<long long, std::array<std::complex<double>, 3>> v;
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
    const auto g = map->getGlobalElement(static_cast<LocalOrdinal>(l));
    int c = static_cast<int>(g);
    long long node = 0;
    if (sub) {
      c = static_cast<int>(sub->dofs().components[g]);
      if (c > 2) continue;
      node = nodeOf[g];
    } else {
      if (c < 3) continue;
      c -= 3;
    }
    v[node][c] = {u[k]->getData(0)[l], u[k]->getData(1)[l]};
  }
  double local[3] = {0, 0, 0}, global[3] = {0, 0, 0};
  for (const auto& [node, x] : v) {
    local[2] += std::norm(x[0]) + std::norm(x[1]) + std::norm(x[2]);
    const std::complex<double> a1 = x[0] * e1[0] + x[1] * e1[1] + x[2] * e1[2];
    const std::complex<double> a2 = x[0] * e2[0] + x[1] * e2[1] + x[2] * e2[2];
    // x(t) = Re(a e^{lambda t}), lambda = i w: the orbit in (e1, e2) turns
    // positively (about n) when Im(a1 conj(a2)) > 0 (analysis::whirlOf's rule).
    local[0] += std::imag(a1 * std::conj(a2)) * (mode.lambda.imag() >= 0 ? 1.0 : -1.0);
    local[1] += std::norm(a1) + std::norm(a2);
  }
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, 3, local, global);
  // No whirl: a mode moving mostly along the axis or twisting about it
  // (transverse share < 10%), or a flat orbit (circularity < 1%).
  if (!(global[1] > 0.1 * global[2]) || std::abs(2 * global[0]) < 1e-2 * global[1]) return "-";
  const bool withSpin = (global[0] > 0) == (spec.spin->rate >= 0);
  return withSpin ? "FW" : "BW";
}

/// A basis with fewer vectors than its "Vectors" asks (issue 14 item 9): one
/// console line with the substructure, the counts asked and kept, and why
/// (the JSON's "dropped" lists every candidate); empty when nothing is lost.
std::string droppedNote(const synthesis::SubstructureReduction& r, const Teuchos::ParameterList& reduction) {
  if (r.dropped.empty()) return {};
  Teuchos::ParameterList p(reduction);
  p.validateParametersAndSetDefaults(*reduction::validParameters());
  const int asked = p.get<int>("Vectors");
  const bool modes = r.basis == "Craig-Bampton";  // "Vectors" counts its fixed-interface modes
  int kept = 0;
  for (const auto& l : r.labels) kept += !modes || l.rfind("mode ", 0) == 0;
  if (kept >= asked) return {};
  int dependent = 0, massless = 0;
  std::string other;
  for (const auto& d : r.dropped) {
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

/// 1. modes
int runModes(const scene::Scene& sc, const std::filesystem::path& outDir, bool root) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto t0 = Clock::now();
  // A large model: a line as each long phase starts, with its size
  // (issue 14 item 9; a 1e6-element beam once ran minutes in silence).
  const bool large = sc.estimatedDofs > scene::Scene::kLargeDofs;
  auto progress = [&](const std::string& what) {
    if (!root || !large) return;
    std::ostringstream os;
    os << "[" << std::fixed << std::setprecision(2) << since(t0) << " s] " << what;
    std::cout << os.str() << std::endl;
  };
  {
    std::ostringstream os;
    os << std::setprecision(3) << "assembling " << sc.structure.substructures.size() << " substructures: "
       << sc.estimatedDofs << " DOFs, at least " << sc.estimatedBytes / 1e9 << " GB of the "
       << scene::availableMemoryBytes() / 1e9 << " GB available";
    progress(os.str());
  }
  const auto structure = [&] {
    Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewCounter("cms: 1. assembly of the substructures"));
    return synthesis::AssembledStructure::assemble(sc.structure, comm);
  }();
  const double tAssemble = since(t0);
  if (root) std::cout << "[" << std::fixed << std::setprecision(2) << tAssemble << " s] assembled "
                      << structure.numSubstructures() << " substructures\n" << std::defaultfloat;
  progress("reducing: factorising the stiffness and building the bases of " +
           std::to_string(structure.numSubstructures()) + " substructures");
  const auto t1 = Clock::now();
  // The scene's bases, or with "Target Accuracy" the bases enriched until
  // every wanted mode's estimated error is below it (analysis/Enrichment).
  std::vector<Teuchos::ParameterList> reductions;
  for (std::size_t k = 0; k < structure.numSubstructures(); ++k) reductions.push_back(structure.substructure(k).reduction);
  analysis::Enrichment enrichment;
  enrichment.reached = true;
  if (sc.targetAccuracy > 0.0) {
    try {
      enrichment = analysis::enrichToAccuracy(structure, scaledSpeeds(structure, sc.speedFactor), sc.solve,
                                              sc.targetAccuracy, reductions);
    } catch (const InputError& e) {
      throw InputError(sc.path + ": " + e.what());
    }
    if (root)
      for (const auto& n : enrichment.notes) std::cout << "target accuracy " << sc.targetAccuracy << ": " << n << '\n';
    if (!enrichment.reached) {
      if (root)
        std::cerr << "cms: " << drivers::kNotConverged.message << " (exit " << drivers::kNotConverged.code
                  << "): Target Accuracy " << sc.targetAccuracy << " not reached (worst estimate "
                  << enrichment.worstEstimate << "); no files written\n";
      return drivers::kNotConverged.code;
    }
  }
  const auto s = [&] {
    Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewCounter("cms: 2. reduction and synthesis"));
    try {
      return synthesis::SynthesizedStructure::synthesize(structure, reductions);
    } catch (const InputError& e) {  // name the scene file (issue item 9)
      throw InputError(sc.path + ": " + e.what());
    }
  }();
  const double tReduce = since(t1);
  if (root) std::cout << "[" << std::fixed << std::setprecision(2) << tAssemble + tReduce << " s] reduced and coupled: "
                      << s.size() << " coordinates\n" << std::defaultfloat;
  const auto speeds = scaledSpeeds(structure, sc.speedFactor);
  // Massless DOFs kept as coordinates make M singular: named before solving.
  try {
    analysis::checkMass(structure, s);
  } catch (const InputError& e) {
    throw InputError(sc.path + ": " + e.what());
  }
  progress("solving: the lowest " + std::to_string(sc.solve.get<int>("Number of Modes")) + " modes of " +
           std::to_string(s.size()) + " coordinates");
  auto modes = [&] {
    Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewCounter("cms: 3. eigensolution"));
    return s.solve(speeds, sc.solve);
  }();
  // More zero frequencies than rigid-body motions: a critical speed (an
  // answer, flagged "critical"), an unrestrained substructure (exit 2) or an
  // ill-conditioned stiffness (exit 3), told apart before anything is
  // written (analysis/ZeroFrequencies.hpp, theory §4.3).
  try {
    analysis::checkZeroFrequencies(structure, s, modes, sc.solve);
  } catch (const InputError& e) {
    throw InputError(sc.path + ": " + e.what());
  } catch (const NumericalError& e) {
    throw NumericalError(sc.path + ": " + e.what());
  }
  const auto character = s.characterise(modes);
  // Each mode's estimated relative error against the truth, from the
  // residual of the substructures' full equations (theory §11.8; collective).
  const auto estimates = s.errorEstimates(modes);
  // --truth: the true error beside the estimate (the validation of §11.8
  // on the user's own structure; costs the solve a reduction avoids).
  std::vector<double> trueErrors;
  if (truthRequested) {
    const auto truth = synthesis::SynthesizedStructure::synthesize(structure, true);
    const auto truthModes = truth.solve(speeds, sc.solve);
    const int n = static_cast<int>(std::min(modes.result.modes.size(), truthModes.result.modes.size()));
    for (const auto& a : analysis::compareWithTruth(s, modes, truth, truthModes, n).modes)
      trueErrors.push_back(std::abs(a.relativeError));
  }
  auto estimate = [&](std::size_t m) {
    std::ostringstream os;
    os << std::setprecision(2);
    // Past 10% the first-order estimate is a flag, not a number (theory §11.8).
    if (estimates[m] >= 0.1) os << "unresolved";
    else if (estimates[m] >= 0.0) os << estimates[m];
    else os << "-";
    return os.str();
  };
  // Missing-mode detection (theory §11.9): each reduced substructure's own
  // modes below the highest frequency found, by a Sturm count, against
  // those its basis represents (collective).
  double cutoff = 0.0;
  for (const auto& md : modes.result.modes) cutoff = std::max(cutoff, md.omega);
  const auto coverage = s.coverage(cutoff);
  // --check-count: the assembled truth's frequencies below just above the
  // highest reduced one (Ritz frequencies lie above the truth's, so the
  // truth has at least as many): more means modes the reduced model lacks.
  long long truthCount = -2, reducedCount = 0;
  const double countAt = cutoff * (1.0 + 1e-6);
  if (countRequested) {
    truthCount = analysis::truthFrequenciesBelow(structure, speeds, countAt);
    for (const auto& md : modes.result.modes) reducedCount += md.omega < countAt;
  }
  // Whirl of each spinning substructure in each mode (collective).
  std::vector<std::vector<std::string>> whirls(modes.result.modes.size());
  for (std::size_t m = 0; m < modes.result.modes.size(); ++m) {
    const auto u = s.expand(modes, static_cast<int>(m));
    for (std::size_t k = 0; k < structure.numSubstructures(); ++k)
      if (structure.substructure(k).kind != synthesis::SubstructureKind::Central &&
          structure.substructure(k).spin)
        whirls[m].push_back(structure.substructure(k).name + " " + whirl(structure, u, k, modes.result.modes[m]));
  }
  // The run's outcome (drivers/DriverBoundary.hpp): only a success writes files.
  const drivers::Outcome outcome = drivers::outcome(modes.result.status);
  if (!root) {
    if (vtuRequested && outcome.code == ExitSuccess)
      analysis::writeModeShapes(structure, s, modes, outDir.string(), sc.name);  // collective
    return outcome.code;
  }

  std::cout << "[" << std::fixed << std::setprecision(2) << since(t0) << " s] solved (" << modes.path << ")\n\n"
            << std::defaultfloat;
  // Substructures and their truncation guide.
  std::cout << "substructure  kind  DOFs      basis          coords  lowest own frequencies (Hz, attachment held)\n";
  const auto& reps = s.reductions();
  for (const auto& r : reps) {
    std::cout << std::left << std::setw(14) << r.name << std::setw(6) << r.kind << std::setw(10) << r.physicalDofs
              << std::setw(15) << r.basis << std::setw(8) << r.coordinates << std::right;
    for (std::size_t k = 0; k < std::min<std::size_t>(4, r.frequencyEstimates.size()); ++k)
      std::cout << std::setprecision(5) << r.frequencyEstimates[k] / (2 * M_PI) << ' ';
    std::cout << '\n';
  }
  for (std::size_t k = 0; k < reps.size(); ++k)
    if (const auto n = droppedNote(reps[k], structure.substructure(k).reduction); !n.empty()) std::cout << n << '\n';
  for (const auto& n : structure.notes()) std::cout << "note: " << n << '\n';
  std::cout << "coverage below " << std::setprecision(5) << cutoff / (2 * M_PI)
            << " Hz (the highest mode; Sturm count of each substructure with its attachment held):";
  for (const auto& c : coverage)
    if (c.verdict != "Full" && c.verdict != "rigid") std::cout << "\n  " << c.name << ": " << c.verdict;
  if (truthCount >= 0)
    std::cout << "\n  structure: the truth has " << truthCount << " frequencies below " << countAt / (2 * M_PI)
              << " Hz, the reduced model " << reducedCount
              << (truthCount > reducedCount ? ": MODES MISSING (a family the bases lack, or errors that push modes past it)"
                                            : ": none missing");
  else if (truthCount == -1)
    std::cout << "\n  structure: the truth's count was not reliable (a frequency at the cut-off)";
  std::cout << '\n';
  std::cout << "\nspeeds (rad/s):";
  for (std::size_t i = 0; i < speeds.size(); ++i) std::cout << ' ' << structure.speeds()[i].name << " = " << speeds[i];
  std::cout << "\nsolver: " << modes.result.solver
            << (modes.result.reason.empty() ? "" : " (" + drivers::condense(modes.result.reason) + ")")
            << "\n\n mode      Hz          rad/s       growth (1/s)  stability   residual  est.error  largest share, whirl (FW/BW)\n";
  for (std::size_t m = 0; m < modes.result.modes.size(); ++m) {
    const auto& md = modes.result.modes[m];
    std::size_t top = 0;
    for (std::size_t k = 1; k < character[m].kineticShare.size(); ++k)
      if (character[m].kineticShare[k] > character[m].kineticShare[top]) top = k;
    std::cout << std::setw(5) << m + 1 << std::setw(12) << std::setprecision(6) << md.hz << std::setw(12) << md.omega
              << std::setw(14) << std::setprecision(3) << md.growthRate << "  " << std::left << std::setw(11)
              << toString(md.stability) << std::right << std::setw(9) << std::setprecision(2) << md.residual
              << std::setw(11) << estimate(m);
    if (m < trueErrors.size()) std::cout << " (true " << std::setprecision(2) << trueErrors[m] << ")";
    std::cout << "  " << reps[top].name << " " << std::setprecision(3) << character[m].kineticShare[top]
              << (character[m].frameArtefact ? "  (rigid motion seen at the frame rate: not a vibration)" : "");
    for (const auto& w : whirls[m]) std::cout << "  " << w;
    std::cout << '\n';
  }
  if (outcome.code != ExitSuccess) {
    std::cerr << "cms: " << outcome.message << " (status " << toString(modes.result.status) << ", exit " << outcome.code
              << "): " << drivers::condense(modes.result.reason) << "; no files written\n";
    return outcome.code;
  }
  // Files.
  std::filesystem::create_directories(outDir);
  if (sc.csv) {
    AtomicFile f(outDir / (sc.name + "-modes.csv"));
    f.stream() << "mode,hz,rad_per_s,growth_rate,stability,residual,error_estimate,frame_artefact";
    for (const auto& r : reps) f.stream() << ",share_" << r.name;
    f.stream() << '\n';
    for (std::size_t m = 0; m < modes.result.modes.size(); ++m) {
      const auto& md = modes.result.modes[m];
      f.stream() << m + 1 << ',' << md.hz << ',' << md.omega << ',' << md.growthRate << ',' << toString(md.stability)
                 << ',' << md.residual << ',' << (estimates[m] >= 0.0 ? estimates[m] : std::nan(""))
                 << ',' << character[m].frameArtefact;
      for (double v : character[m].kineticShare) f.stream() << ',' << v;
      f.stream() << '\n';
    }
    f.commit();
  }
  if (sc.csv) {  // the missing-mode check per substructure (theory §11.9)
    AtomicFile f(outDir / (sc.name + "-coverage.csv"));
    f.stream() << "substructure,basis,cutoff_hz,sturm_count,represented,coordinates,verdict\n";
    for (const auto& c : coverage)
      f.stream() << c.name << ',' << c.basis << ',' << c.cutoff / (2 * M_PI) << ',' << c.sturmCount << ','
                 << c.represented << ',' << c.coordinates << ",\"" << c.verdict << "\"\n";
    f.commit();
  }
  if (sc.json) {
    AtomicFile f(outDir / (sc.name + ".json"));
    auto& o = f.stream();
    std::ifstream sceneFile(sc.path);
    std::stringstream sceneText;
    sceneText << sceneFile.rdbuf();
    o << "{\n  \"scene\": " << jsonString(sc.path) << ",\n  \"scene_text\": " << jsonString(sceneText.str())
      << ",\n  \"name\": " << jsonString(sc.name)
      << ",\n  \"units\": {\"length\": \"m\", \"mass\": \"kg\", \"time\": \"s\", \"frequency\": \"Hz and rad/s\"}"
      << ",\n  \"version\": \"" << CMS_VERSION << "\",\n  \"ranks\": " << comm->getSize()
      << ",\n  \"timings_s\": {\"assembly\": " << tAssemble << ", \"reduction_and_synthesis\": " << tReduce
      << ", \"solve\": " << modes.seconds << "},\n  \"peak_memory_mib\": " << drivers::peakRssMiB()
      << ",\n  \"speeds\": [";
    for (std::size_t i = 0; i < speeds.size(); ++i)
      o << (i ? ", " : "") << "{\"name\": " << jsonString(structure.speeds()[i].name) << ", \"rad_per_s\": " << speeds[i] << "}";
    o << "],\n  \"notes\": [";
    for (std::size_t i = 0; i < structure.notes().size(); ++i) o << (i ? ", " : "") << jsonString(structure.notes()[i]);
    o << "],\n  \"substructures\": [\n";
    for (std::size_t k = 0; k < reps.size(); ++k) {
      const auto& r = reps[k];
      o << "    {\"name\": " << jsonString(r.name) << ", \"kind\": \"" << r.kind << "\", \"physical_dofs\": " << r.physicalDofs
        << ", \"basis\": " << jsonString(r.basis) << ", \"coordinates\": " << r.coordinates
        << ", \"attachment_dofs\": " << r.attachmentDofs << ", \"basis_seconds\": " << r.seconds
        << ", \"frequency_estimates_hz\": [";
      for (std::size_t j = 0; j < r.frequencyEstimates.size(); ++j)
        o << (j ? ", " : "") << r.frequencyEstimates[j] / (2 * M_PI);
      o << "], \"dropped\": [";
      for (std::size_t j = 0; j < r.dropped.size(); ++j) o << (j ? ", " : "") << jsonString(r.dropped[j]);
      o << "]}" << (k + 1 < reps.size() ? "," : "") << '\n';
    }
    o << "  ],\n  \"coverage\": {\"cutoff_hz\": " << cutoff / (2 * M_PI) << ", \"substructures\": [";
    for (std::size_t k = 0; k < coverage.size(); ++k) {
      const auto& c = coverage[k];
      o << (k ? ", " : "") << "{\"name\": " << jsonString(c.name) << ", \"basis\": " << jsonString(c.basis)
        << ", \"sturm_count\": " << c.sturmCount << ", \"represented\": " << c.represented
        << ", \"coordinates\": " << c.coordinates << ", \"verdict\": " << jsonString(c.verdict) << "}";
    }
    o << "]";
    if (truthCount >= -1) o << ", \"structure_truth_count\": " << truthCount << ", \"structure_reduced_count\": " << reducedCount;
    o << "}";
    o << ",\n  \"solver\": " << jsonString(modes.result.solver) << ",\n  \"path\": " << jsonString(modes.path)
      << ",\n  \"status\": " << jsonString(toString(modes.result.status)) << ",\n  \"reason\": "
      << jsonString(modes.result.reason) << ",\n  \"modes\": [\n";
    for (std::size_t m = 0; m < modes.result.modes.size(); ++m) {
      const auto& md = modes.result.modes[m];
      o << "    {\"hz\": " << md.hz << ", \"rad_per_s\": " << md.omega << ", \"growth_rate\": " << md.growthRate
        << ", \"stability\": " << jsonString(toString(md.stability)) << ", \"residual\": " << md.residual
        << ", \"error_estimate\": ";
      if (estimates[m] >= 0.0) o << estimates[m]; else o << "null";
      if (m < trueErrors.size()) o << ", \"true_error\": " << trueErrors[m];
      o
        << ", \"frame_artefact\": " << (character[m].frameArtefact ? "true" : "false") << ", \"whirl\": [";
      for (std::size_t w = 0; w < whirls[m].size(); ++w) o << (w ? ", " : "") << jsonString(whirls[m][w]);
      o << "], \"kinetic_share\": [";
      for (std::size_t k = 0; k < character[m].kineticShare.size(); ++k)
        o << (k ? ", " : "") << character[m].kineticShare[k];
      o << "]}" << (m + 1 < modes.result.modes.size() ? "," : "") << '\n';
    }
    o << "  ]\n}\n";
    f.commit();
  }
  std::cout << "\nwrote " << (outDir / sc.name).string() << (sc.json ? ".json " : " ")
            << (sc.csv ? "(and -modes.csv, -coverage.csv)" : "")
            << '\n';
  if (vtuRequested) {
    const auto files = analysis::writeModeShapes(structure, s, modes, outDir.string(), sc.name);
    std::cout << "wrote " << files.size() - 1 << " mode shapes for ParaView: " << files.back() << '\n';
  }
  return ExitSuccess;
}

/// M-weighted MAC of every pair (previous mode t, current mode j) of the
/// same coordinates: |a^H M b|^2 / (a^H M a  b^H M b), with two
/// applications of M and one reduction per call (q replicated on every rank
/// by the dense path, or this rank's rows by the sparse path). Collective.
std::vector<std::vector<double>> macMatrix(const synthesis::SynthesizedStructure& s, const CrsMatrix& M,
                                           const std::vector<eigen::GyroscopicMode>& prev,
                                           const std::vector<eigen::GyroscopicMode>& cur) {
  const auto map = M.getRowMap();
  const std::size_t nloc = map->getNodeNumElements(), P = prev.size(), C = cur.size();
  auto pack = [&](const std::vector<eigen::GyroscopicMode>& modes) {
    MultiVector X(map, std::max<std::size_t>(2 * modes.size(), 1));
    for (std::size_t j = 0; j < modes.size(); ++j) {
      const bool replicated = static_cast<long long>(modes[j].q.size()) == s.size();
      auto re = X.getDataNonConst(2 * j), im = X.getDataNonConst(2 * j + 1);
      for (std::size_t l = 0; l < nloc; ++l) {
        const std::size_t i = replicated ? static_cast<std::size_t>(map->getGlobalElement(static_cast<LocalOrdinal>(l))) : l;
        re[l] = modes[j].q[i].real(), im[l] = modes[j].q[i].imag();
      }
    }
    return X;
  };
  const MultiVector Xp = pack(prev), Xc = pack(cur);
  MultiVector MXp(map, Xp.getNumVectors()), MXc(map, Xc.getNumVectors());
  M.apply(Xp, MXp);
  M.apply(Xc, MXc);
  // Local sums: per pair (re, im) of a^H M b, then a^H M a per previous, b^H M b per current.
  std::vector<double> local(2 * P * C + P + C, 0.0), global(local.size(), 0.0);
  auto col = [](const MultiVector& X, std::size_t j) { return X.getData(j); };
  for (std::size_t t = 0; t < P; ++t) {
    const auto ar = col(Xp, 2 * t), ai = col(Xp, 2 * t + 1), Mar = col(MXp, 2 * t), Mai = col(MXp, 2 * t + 1);
    for (std::size_t l = 0; l < nloc; ++l) local[2 * P * C + t] += ar[l] * Mar[l] + ai[l] * Mai[l];
    for (std::size_t j = 0; j < C; ++j) {
      const auto Mbr = col(MXc, 2 * j), Mbi = col(MXc, 2 * j + 1);
      double re = 0, im = 0;
      // a^H M b = (ar.M br + ai.M bi) + i (ar.M bi - ai.M br)
      for (std::size_t l = 0; l < nloc; ++l) re += ar[l] * Mbr[l] + ai[l] * Mbi[l], im += ar[l] * Mbi[l] - ai[l] * Mbr[l];
      local[2 * (t * C + j)] = re, local[2 * (t * C + j) + 1] = im;
    }
  }
  for (std::size_t j = 0; j < C; ++j) {
    const auto br = col(Xc, 2 * j), bi = col(Xc, 2 * j + 1), Mbr = col(MXc, 2 * j), Mbi = col(MXc, 2 * j + 1);
    for (std::size_t l = 0; l < nloc; ++l) local[2 * P * C + P + j] += br[l] * Mbr[l] + bi[l] * Mbi[l];
  }
  Teuchos::reduceAll(*map->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
  std::vector<std::vector<double>> mac(P, std::vector<double>(C, 0.0));
  for (std::size_t t = 0; t < P; ++t)
    for (std::size_t j = 0; j < C; ++j) {
      const double aa = global[2 * P * C + t], bb = global[2 * P * C + P + j];
      const double n2 = global[2 * (t * C + j)] * global[2 * (t * C + j)] +
                        global[2 * (t * C + j) + 1] * global[2 * (t * C + j) + 1];
      mac[t][j] = aa > 0 && bb > 0 ? n2 / (aa * bb) : 0.0;
    }
  return mac;
}

/// 3. campbell
int runCampbell(const scene::Scene& sc, const std::filesystem::path& outDir, int steps, double maxFactor,
                const std::vector<int>& orders, bool root) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  CMS_INPUT_CHECK(steps < 2, "--steps = " << steps << " must be at least 2");
  CMS_INPUT_CHECK(!(maxFactor > 0), "--max-factor = " << maxFactor << " must be positive");
  const auto structure = synthesis::AssembledStructure::assemble(sc.structure, comm);
  CMS_INPUT_CHECK(structure.speeds().empty(), sc.path << ": nothing spins in this scene: no Campbell diagram");
  const auto s = synthesis::SynthesizedStructure::synthesize(structure);
  const auto nominal = structure.nominalSpeeds();
  const auto M = s.system(std::vector<double>(nominal.size(), 0.0)).M;  // the same at every speed
  const auto t0 = Clock::now();
  // Tracks: frequency (Hz) and stability of one mode followed across speeds.
  struct Track {
    std::vector<double> hz;
    std::vector<std::string> stability, whirl;
    eigen::GyroscopicMode last;
  };
  // Whirl is reported for the first spinning A or R (its orbit about its axis).
  int spinning = -1;
  for (std::size_t k = 0; k < structure.numSubstructures() && spinning < 0; ++k)
    if (structure.substructure(k).kind != synthesis::SubstructureKind::Central && structure.substructure(k).spin)
      spinning = static_cast<int>(k);
  std::vector<Track> tracks;
  std::vector<double> factors;
  drivers::Outcome worst = drivers::kSuccess;  // breakdown (3) outranks not converged (4)
  std::string worstReason;
  std::vector<std::pair<double, double>> unstable;  // factor ranges
  for (int k = 0; k < steps; ++k) {
    const double f = maxFactor * k / (steps - 1);
    factors.push_back(f);
    std::vector<double> speeds(nominal);
    for (double& v : speeds) v *= f * sc.speedFactor;
    const auto m = s.solve(speeds, sc.solve);
    {
      const auto o = drivers::outcome(m.result.status);
      if (o.code != ExitSuccess && (worst.code == ExitSuccess || o.code == ExitNumericalError))
        worst = o, worstReason = drivers::condense(m.result.reason);
    }
    bool anyUnstable = false;
    for (const auto& md : m.result.modes)
      anyUnstable = anyUnstable || md.stability == eigen::Stability::Flutter ||
                    md.stability == eigen::Stability::Divergence;
    if (anyUnstable) {
      if (!unstable.empty() && unstable.back().second == factors[k > 0 ? k - 1 : 0] && k > 0) unstable.back().second = f;
      else unstable.push_back({f, f});
    }
    const auto& modes = m.result.modes;
    std::vector<std::string> wl(modes.size(), "");
    if (spinning >= 0)
      for (std::size_t j = 0; j < modes.size(); ++j)
        wl[j] = whirl(structure, s.expand(m, static_cast<int>(j)), static_cast<std::size_t>(spinning), modes[j]);
    if (tracks.empty()) {
      for (std::size_t j = 0; j < modes.size(); ++j)
        tracks.push_back({{modes[j].hz}, {toString(modes[j].stability)}, {wl[j]}, modes[j]});
      continue;
    }
    // Greedy assignment by decreasing MAC.
    std::vector<eigen::GyroscopicMode> last;
    for (const auto& tr : tracks) last.push_back(tr.last);
    const auto mac = macMatrix(s, *M, last, modes);
    std::vector<std::tuple<double, int, int>> pairs;
    for (std::size_t t = 0; t < tracks.size(); ++t)
      for (std::size_t j = 0; j < modes.size(); ++j)
        pairs.push_back({mac[t][j], static_cast<int>(t), static_cast<int>(j)});
    std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return std::get<0>(a) > std::get<0>(b); });
    std::vector<bool> trackDone(tracks.size(), false), modeDone(modes.size(), false);
    for (const auto& [mac, t, j] : pairs) {
      if (trackDone[t] || modeDone[j]) continue;
      trackDone[t] = modeDone[j] = true;
      tracks[t].hz.push_back(modes[j].hz);
      tracks[t].stability.push_back(toString(modes[j].stability));
      tracks[t].whirl.push_back(wl[j]);
      tracks[t].last = modes[j];
    }
    for (std::size_t t = 0; t < tracks.size(); ++t)
      if (!trackDone[t])
        tracks[t].hz.push_back(std::nan("")), tracks[t].stability.push_back("lost"), tracks[t].whirl.push_back("");
  }
  if (!root) return worst.code;
  const double ref = nominal.front() * sc.speedFactor;  // engine orders of the first spin rate
  std::cout << "[" << std::setprecision(3) << since(t0) << " s] " << steps << " speeds, " << s.size()
            << " coordinates, no re-projection\n\nfactor";
  for (std::size_t i = 0; i < nominal.size(); ++i) std::cout << "  " << structure.speeds()[i].name << "(rad/s)";
  for (std::size_t t = 0; t < tracks.size(); ++t) std::cout << "  track" << t + 1 << "(Hz)";
  std::cout << '\n';
  for (int k = 0; k < steps; ++k) {
    std::cout << std::setw(6) << std::setprecision(3) << factors[k];
    for (double v : nominal) std::cout << std::setw(14) << std::setprecision(5) << v * factors[k] * sc.speedFactor;
    for (const auto& tr : tracks)
      std::cout << std::setw(13) << std::setprecision(6) << tr.hz[k]
                << (tr.stability[k] == "stable" || tr.stability[k] == "rigid" || tr.stability[k] == "neutral" ? " " : "*");
    std::cout << '\n';
  }
  std::cout << "(* unstable or lost)\n\ncritical speeds of '" << structure.speeds().front().name << "' (rad/s):\n";
  for (int order : orders)
    for (std::size_t t = 0; t < tracks.size(); ++t)
      for (int k = 1; k < steps; ++k) {
        const double w0 = ref * factors[k - 1] * order, w1 = ref * factors[k] * order;
        const double a = tracks[t].hz[k - 1] * 2 * M_PI - w0, b = tracks[t].hz[k] * 2 * M_PI - w1;
        if (std::isfinite(a) && std::isfinite(b) && a * b < 0 && tracks[t].hz[k] > 0) {
          const double x = a / (a - b), speed = ref * (factors[k - 1] + x * (factors[k] - factors[k - 1]));
          std::cout << "  " << order << "X crosses track " << t + 1 << " at " << speed << " rad/s ("
                    << speed * 60 / (2 * M_PI) << " rpm)\n";
        }
      }
  for (const auto& [a, b] : unstable)
    std::cout << "unstable from factor " << a << " to " << b << " (" << ref * a << " to " << ref * b << " rad/s)\n";
  if (worst.code != ExitSuccess) {
    std::cerr << "cms: " << worst.message << " (exit " << worst.code << "): " << worstReason << "; no files written\n";
    return worst.code;
  }
  std::filesystem::create_directories(outDir);
  AtomicFile f(outDir / (sc.name + "-campbell.csv"));
  f.stream() << "factor";
  for (const auto& p : structure.speeds()) f.stream() << "," << p.name << "_rad_per_s";
  for (std::size_t t = 0; t < tracks.size(); ++t)
    f.stream() << ",track" << t + 1 << "_hz,track" << t + 1 << "_stability,track" << t + 1 << "_whirl";
  f.stream() << '\n';
  for (int k = 0; k < steps; ++k) {
    f.stream() << factors[k];
    for (double v : nominal) f.stream() << ',' << v * factors[k] * sc.speedFactor;
    for (const auto& tr : tracks) f.stream() << ',' << tr.hz[k] << ',' << tr.stability[k] << ',' << tr.whirl[k];
    f.stream() << '\n';
  }
  f.commit();
  std::cout << "\nwrote " << (outDir / (sc.name + "-campbell.csv")).string() << '\n';
  plot("campbell", outDir / (sc.name + "-campbell.csv"));
  return ExitSuccess;
}

/// 4. truncate
int runTruncate(const scene::Scene& sc, const std::filesystem::path& outDir, int start, int step, double accuracy,
                bool useTruth, bool root) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  CMS_INPUT_CHECK(start < 0 || step < 1, "--start must be >= 0 and --step >= 1");
  CMS_INPUT_CHECK(!(accuracy > 0), "--accuracy = " << accuracy << " must be positive");
  const auto structure = synthesis::AssembledStructure::assemble(sc.structure, comm);
  const auto speeds = scaledSpeeds(structure, sc.speedFactor);
  const int nModes = sc.solve.get<int>("Number of Modes");
  // The accuracy is judged from each mode's error estimate (theory §11.8),
  // without the truth; --truth also solves the truth and prints the true
  // error beside it (the cost a reduction exists to avoid).
  std::optional<synthesis::SynthesizedStructure> truth;
  synthesis::StructureModes truthModes;
  if (useTruth) {
    truth = synthesis::SynthesizedStructure::synthesize(structure, true);
    truthModes = truth->solve(speeds, sc.solve);
    CMS_INPUT_CHECK(static_cast<int>(truthModes.result.modes.size()) < nModes,
                    "the truth model gave " << truthModes.result.modes.size() << " modes of " << nModes);
  }
  double trueError = std::numeric_limits<double>::quiet_NaN();
  bool definite = false;  // K > 0 (the Meirovitch path ran): the inclusion principle applies
  // The substructures whose count can change: those with an Admissible,
  // Polynomial, Modes or Craig-Bampton basis.
  const std::size_t ns = structure.numSubstructures();
  std::vector<Teuchos::ParameterList> red(ns);
  std::vector<int> count(ns, 0);
  std::vector<bool> tunable(ns, false);
  std::vector<long long> limit(ns, 0);
  for (std::size_t q = 0; q < ns; ++q) {
    red[q] = structure.substructure(q).reduction;
    red[q].setName("Reduction");
    const std::string basis = red[q].get<std::string>("Basis", "Admissible");
    tunable[q] = structure.assembled(q) && basis != "Full" && basis != "Guyan";
    if (tunable[q]) {
      limit[q] = structure.assembled(q)->dofs().rows() - 6;
      count[q] = static_cast<int>(std::min<long long>(start, limit[q]));
      red[q].set("Vectors", count[q]);
    }
  }
  auto evaluate = [&](const std::vector<Teuchos::ParameterList>& r, long long& dofs, std::vector<double>& w) {
    const auto s = synthesis::SynthesizedStructure::synthesize(structure, r);
    dofs = s.size();
    if (dofs < nModes) return std::numeric_limits<double>::infinity();
    const auto m = s.solve(speeds, sc.solve);
    if (static_cast<int>(m.result.modes.size()) < nModes) return std::numeric_limits<double>::infinity();
    w = analysis::frequencies(m);
    if (truth) trueError = analysis::compareWithTruth(s, m, *truth, truthModes, nModes).maxRelativeError;
    double worst = 0.0;
    const auto e = s.errorEstimates(m);
    for (int j = 0; j < nModes; ++j) worst = std::max(worst, e[j]);  // -1 (zero frequency): no error
    definite = m.result.solver.find("Meirovitch") != std::string::npos;
    return worst;
  };
  long long dofs = 0;
  std::vector<double> w;
  double error = evaluate(red, dofs, w);
  std::ostringstream table;
  table << "step,changed,dofs,max_rel_error,max_true_rel_error,inclusion_violations";
  for (std::size_t q = 0; q < ns; ++q) table << ",vectors_" << structure.substructure(q).name;
  table << '\n';
  auto row = [&](int k, const std::string& changed, int violations) {
    table << k << ',' << changed << ',' << dofs << ',' << error << ',' << trueError << ',' << violations;
    for (std::size_t q = 0; q < ns; ++q) table << ',' << count[q];
    table << '\n';
    if (root)
      std::cout << std::setw(4) << k << "  " << std::left << std::setw(12) << changed << std::right << std::setw(7)
                << dofs << std::setw(13) << std::setprecision(4) << error << std::setw(13) << trueError
                << std::setw(6) << violations << '\n';
  };
  if (root)
    std::cout << (truth ? "truth: " + std::to_string(truth->size()) + " coordinates; " : std::string("no truth solve; "))
              << "target: the lowest " << nModes << " within " << accuracy << ", by their error estimates"
              << (definite ? "" : " (K not positive definite: no inclusion bound, not checked)")
              << "\n\nstep  added to      DOFs  max est err  max true err  incl.\n";
  row(0, "(start)", 0);
  int totalViolations = 0;
  for (int k = 1; error > accuracy && k <= 200; ++k) {
    int best = -1;
    double bestGain = -1, bestError = error, bestTrue = trueError;
    long long bestDofs = dofs;
    std::vector<double> bestW;
    for (std::size_t q = 0; q < ns; ++q) {
      if (!tunable[q] || count[q] + step > limit[q]) continue;
      auto trial = red;
      trial[q].set("Vectors", count[q] + step);
      long long d = 0;
      std::vector<double> tw;
      double e = std::numeric_limits<double>::infinity();
      try {
        e = evaluate(trial, d, tw);
      } catch (const InputError&) {
        continue;
      }
      if (d <= dofs) continue;  // no new coordinate (the substructure is complete): nothing to gain
      const double gain = (std::min(error, 1e300) - e) / std::max<long long>(1, d - dofs);
      if (best < 0 || gain > bestGain)
        best = static_cast<int>(q), bestGain = gain, bestError = e, bestDofs = d, bestW = tw, bestTrue = trueError;
    }
    if (best < 0) break;
    // Inclusion principle between the nested models (K > 0 only).
    int violations = 0;
    if (definite && !w.empty()) {
      const auto v = analysis::checkInclusion(w, bestW, 1e-9, static_cast<int>(bestDofs - dofs));
      violations = static_cast<int>(v.size());
      for (const auto& x : v)
        if (root)
          std::cout << "  finding: inclusion principle violated at mode " << x.index + 1 << " (" << x.inequality
                    << ", by " << x.amount << ") when adding to " << structure.substructure(best).name << '\n';
    }
    totalViolations += violations;
    count[best] += step;
    red[best].set("Vectors", count[best]);
    error = bestError, dofs = bestDofs, w = bestW;
    if (truth) trueError = bestTrue;
    row(k, structure.substructure(best).name, violations);
  }
  if (!root) return error <= accuracy ? ExitSuccess : drivers::kNotConverged.code;
  std::cout << "\n" << (error <= accuracy ? "reached " : "NOT reached: ") << "max estimated relative error " << error
            << " with " << dofs << " coordinates"
            << [&] {
                 std::ostringstream os;
                 if (truth) os << " (true error " << trueError << ", truth " << truth->size() << " coordinates)";
                 return os.str();
               }()
            << "\nsuggested vectors:";
  for (std::size_t q = 0; q < ns; ++q)
    if (tunable[q]) std::cout << ' ' << structure.substructure(q).name << " = " << count[q];
  std::cout << "\ninclusion-principle violations: " << totalViolations << '\n';
  if (error > accuracy) {
    std::cerr << "cms: " << drivers::kNotConverged.message << " (exit " << drivers::kNotConverged.code
              << "): --accuracy not reached; no files written\n";
    return drivers::kNotConverged.code;
  }
  std::filesystem::create_directories(outDir);
  AtomicFile f(outDir / (sc.name + "-truncate.csv"));
  f.stream() << table.str();
  f.commit();
  std::cout << "wrote " << (outDir / (sc.name + "-truncate.csv")).string() << '\n';
  plot("truncate", outDir / (sc.name + "-truncate.csv"));
  return error <= accuracy ? ExitSuccess : ExitNotConverged;
}

/// 2. compare
int runCompare(const scene::Scene& sc, const std::filesystem::path& outDir, const std::vector<int>& counts, bool root) {
  auto comm = Teuchos::DefaultComm<int>::getComm();
  const auto structure = synthesis::AssembledStructure::assemble(sc.structure, comm);
  const auto speeds = scaledSpeeds(structure, sc.speedFactor);
  const int nModes = sc.solve.get<int>("Number of Modes");
  auto tt = Clock::now();
  const auto truth = synthesis::SynthesizedStructure::synthesize(structure, true);
  const auto truthModes = truth.solve(speeds, sc.solve);
  const double truthSeconds = since(tt);
  // Without a converged truth there is nothing to compare with: the truth's
  // outcome is the run's, and nothing is written.
  if (const auto o = drivers::outcome(truthModes.result.status); o.code != ExitSuccess) {
    if (root)
      std::cerr << "cms: " << o.message << ": the truth model (" << truth.size() << " coordinates) "
                << toString(truthModes.result.status) << ": " << drivers::condense(truthModes.result.reason)
                << "; no files written\n";
    return o.code;
  }
  CMS_INPUT_CHECK(static_cast<int>(truthModes.result.modes.size()) < nModes,
                  "the truth model gave " << truthModes.result.modes.size() << " modes of " << nModes);
  struct Row {
    std::string basis;
    int vectors;
    long long dofs;
    double reduce, solve, memory;
    analysis::TruthComparison c;
    double estimate;  ///< the largest estimated error of the compared modes (theory §11.8)
    std::vector<int> perSubstructure;  ///< coordinates of each substructure
  };
  std::vector<Row> rows;
  // A strategy whose solve did not converge or broke down is a failure of
  // the run, not a row: it is named, the table is written as
  // <name>-compare-partial.csv, and the exit code is the worst outcome (3
  // before 4), as for campbell (doc/user-guide.md, "Exit codes").
  drivers::Outcome worst = drivers::kSuccess;
  for (const std::string basis : {"Guyan", "Admissible", "Modes", "Craig-Bampton"}) {
    for (int k : basis == "Guyan" ? std::vector<int>{0} : counts) {
      const auto red = synthesis::sameReduction(structure, basis, k);
      const auto t1 = Clock::now();
      const std::size_t before = rows.size();
      try {
        const auto s = synthesis::SynthesizedStructure::synthesize(structure, red);
        const double tr = since(t1);
        if (s.size() < nModes) {
          if (root) std::cout << "skipped " << basis << " with " << k << " vectors: " << s.size()
                              << " coordinates, fewer than the " << nModes << " modes compared\n";
          continue;
        }
        const auto m = s.solve(speeds, sc.solve);
        if (const auto o = drivers::outcome(m.result.status); o.code != ExitSuccess) {
          if (root) std::cout << "FAILED " << basis << " with " << k << " vectors: " << o.message << " ("
                              << toString(m.result.status) << "): " << drivers::condense(m.result.reason) << '\n';
          if (worst.code == ExitSuccess || o.code == ExitNumericalError) worst = o;
          continue;
        }
        if (static_cast<int>(m.result.modes.size()) < nModes) {
          if (root) std::cout << "skipped " << basis << " with " << k << " vectors: the solve gave "
                              << m.result.modes.size() << " modes (" << m.result.reason << ")\n";
          continue;
        }
        std::vector<int> per;
        for (const auto& r : s.reductions()) per.push_back(r.coordinates);
        const auto estimates = s.errorEstimates(m);
        double worstEstimate = 0.0;
        for (int j = 0; j < nModes && j < static_cast<int>(estimates.size()); ++j)
          worstEstimate = std::max(worstEstimate, estimates[j]);
        rows.push_back({basis, k, s.size(), tr, m.seconds, drivers::peakRssMiB(),
                        analysis::compareWithTruth(s, m, truth, truthModes, nModes), worstEstimate, per});
      } catch (const InputError& e) {
        if (root) std::cout << "skipped " << basis << " with " << k << " vectors: " << e.what() << '\n';
      }
      if (root && rows.size() > before)
        std::cout << "[" << basis << " " << k << "] " << rows.back().dofs << " DOFs, max error "
                  << rows.back().c.maxRelativeError << '\n';
    }
  }
  if (rows.empty() && worst.code == ExitSuccess) worst = drivers::kBreakdown;  // nothing could be compared
  if (!root) return worst.code;
  if (rows.empty()) {
    std::cerr << "cms: " << worst.message << ": no strategy gave " << nModes << " modes to compare; no files written\n";
    return worst.code;
  }
  std::cout << "\ntruth: " << truth.size() << " coordinates, " << truthSeconds << " s (" << truthModes.path
            << ")\nlowest " << nModes << " modes compared\n\n"
            << "strategy        vectors  DOFs    reduce s  solve s   peak MiB  max rel err  max est err  mean rel err  worst MAC\n";
  for (const auto& r : rows)
    std::cout << std::left << std::setw(16) << r.basis << std::right << std::setw(7) << r.vectors << std::setw(7)
              << r.dofs << std::setw(10) << std::setprecision(3) << r.reduce << std::setw(10) << r.solve
              << std::setw(10) << std::setprecision(4) << r.memory << std::setw(13) << r.c.maxRelativeError
              << std::setw(13) << r.estimate << std::setw(14) << r.c.meanRelativeError << std::setw(11) << r.c.worstMac << '\n';
  std::filesystem::create_directories(outDir);
  const std::string csv = sc.name + (worst.code == ExitSuccess ? "-compare.csv" : "-compare-partial.csv");
  AtomicFile f(outDir / csv);
  f.stream() << "strategy,vectors_per_substructure,reduced_dofs,reduce_s,solve_s,peak_mib,max_rel_error,max_estimated_rel_error,mean_rel_error,"
                "worst_mac,truth_dofs,truth_s";
  for (std::size_t q = 0; q < structure.numSubstructures(); ++q)
    f.stream() << ",dofs_" << structure.substructure(q).name;
  f.stream() << '\n';
  for (const auto& r : rows) {
    f.stream() << r.basis << ',' << r.vectors << ',' << r.dofs << ',' << r.reduce << ',' << r.solve << ',' << r.memory
               << ',' << r.c.maxRelativeError << ',' << r.estimate << ',' << r.c.meanRelativeError << ',' << r.c.worstMac << ','
               << truth.size() << ',' << truthSeconds;
    for (int d : r.perSubstructure) f.stream() << ',' << d;
    f.stream() << '\n';
  }
  f.commit();
  std::cout << "\nwrote " << (outDir / csv).string() << '\n';
  if (worst.code != ExitSuccess) {
    std::cerr << "cms: " << worst.message << ": some strategies failed (FAILED above); the others are in " << csv
              << '\n';
    return worst.code;
  }
  plot("compare", outDir / csv);
  return ExitSuccess;
}

}  // namespace

int main(int argc, char* argv[]) {
  Teuchos::GlobalMPISession mpi(&argc, &argv, nullptr);
  const bool root = Teuchos::DefaultComm<int>::getComm()->getRank() == 0;
  return drivers::reportErrors("cms", root, [&]() -> int {
    // 1. The subcommand and options.
    std::string command = argc > 1 ? argv[1] : "";
    if (command == "--version") {
      if (root) std::cout << "cms " << CMS_VERSION << '\n';
      return ExitSuccess;
    }
    if (command.empty() || command == "--help" || command == "-h" ||
        (command != "modes" && command != "compare" && command != "campbell" && command != "truncate")) {
      if (root)
        std::cout << "usage: cms modes|compare|campbell|truncate [SCENE] [options]   (cms modes --help for the options)\n"
                     "  modes     the structure's lowest modes at the scene's speeds\n"
                     "  compare   every reduction strategy against the truth model\n"
                     "  campbell  a speed sweep with modes tracked by MAC and critical speeds\n"
                     "  truncate  vectors added where they help most, to a requested accuracy\n"
                     "  SCENE    a YAML scene (default: the built-in spacecraft, "
                  << CMS_SCENE_DIR << "/spacecraft.yaml)\n";
      return command.empty() || command == "--help" || command == "-h" ? ExitSuccess : ExitInputError;
    }
    std::string scenePath = std::string(CMS_SCENE_DIR) + "/spacecraft.yaml";
    int first = 2;
    if (argc > 2 && argv[2][0] != '-') scenePath = argv[first++];
    std::string output, countsText = "2,4,8", ordersText = "1", meshText;
    int steps = 21, start = 2, step = 2;
    double maxFactor = 2.0, accuracy = 1e-3;
    Teuchos::CommandLineProcessor clp(false, true);
    clp.setDocString("cms modes|compare|campbell|truncate [SCENE] [options]: see doc/user-guide.md");
    clp.setOption("output", &output, "results directory (default: the scene's, else ./cms-results)");
    clp.setOption("counts", &countsText, "compare: vectors per substructure, comma-separated");
    clp.setOption("mesh-parameters", &meshText,
                  "name=value,...: \"Mesh Parameters\" of every substructure meshed from a .geo (e.g. h=0.01)");
    clp.setOption("steps", &steps, "campbell: number of speeds (>= 2)");
    clp.setOption("max-factor", &maxFactor, "campbell: top speed as a multiple of the nominal rates");
    clp.setOption("orders", &ordersText, "campbell: engine orders of the first spin rate, comma-separated");
    clp.setOption("plot", "no-plot", &plotRequested, "campbell, compare, truncate: also a PNG (python3-matplotlib)");
    clp.setOption("vtu", "no-vtu", &vtuRequested, "modes: mode shapes for ParaView (.vtu per mode, .pvd)");
    bool timers = false;
    clp.setOption("timers", "no-timers", &timers, "print the Teuchos::TimeMonitor summary at the end");
    clp.setOption("start", &start, "truncate: vectors per substructure to start from");
    clp.setOption("step", &step, "truncate: vectors added per step");
    clp.setOption("accuracy", &accuracy, "truncate: target max relative error of the lowest modes (estimated)");
    clp.setOption("check-count", "no-check-count", &countRequested,
                  "modes: count the truth's frequencies below the highest one (one factorisation of the assembled model)");
    clp.setOption("truth", "no-truth", &truthRequested,
                  "modes, truncate: also solve the truth model and print the true error beside each estimate");
    std::vector<char*> rest{argv[0]};
    for (int i = first; i < argc; ++i) rest.push_back(argv[i]);
    const auto parsed = clp.parse(static_cast<int>(rest.size()), rest.data());
    if (parsed == Teuchos::CommandLineProcessor::PARSE_HELP_PRINTED) return ExitSuccess;
    if (parsed != Teuchos::CommandLineProcessor::PARSE_SUCCESSFUL) return ExitInputError;
    auto integers = [](const std::string& text, const char* option) {
      std::vector<int> out;
      std::istringstream is(text);
      std::string item;
      while (std::getline(is, item, ',')) {
        char* end = nullptr;
        const long v = std::strtol(item.c_str(), &end, 10);
        CMS_INPUT_CHECK(item.empty() || *end != '\0' || v < 1 || v > 100000,
                        option << ": \"" << item << "\" is not a positive integer");
        out.push_back(static_cast<int>(v));
      }
      return out;
    };
    const std::vector<int> counts = integers(countsText, "--counts"), orders = integers(ordersText, "--orders");
    std::map<std::string, double> meshParameters;
    {
      std::istringstream is(meshText);
      std::string item;
      while (std::getline(is, item, ',')) {
        const auto eq = item.find('=');
        char* end = nullptr;
        const double v = eq == std::string::npos ? 0.0 : std::strtod(item.c_str() + eq + 1, &end);
        CMS_INPUT_CHECK(eq == std::string::npos || eq == 0 || end == item.c_str() + eq + 1 || *end != '\0' ||
                            !std::isfinite(v),
                        "--mesh-parameters: \"" << item << "\" is not name=number");
        std::string name = item.substr(0, eq);
        name.erase(0, name.find_first_not_of(" \t"));
        name.erase(name.find_last_not_of(" \t") + 1);
        CMS_INPUT_CHECK(name.empty(), "--mesh-parameters: \"" << item << "\" has no name");
        meshParameters[name] = v;
      }
    }
    // 2. The scene, checked before anything is computed.
    const scene::Scene sc = scene::Scene::read(scenePath, meshParameters);
    if (!meshParameters.empty()) {
      bool used = false;
      for (const auto& s : sc.structure.substructures)
        used = used || (s.model && s.model->mesh && s.model->mesh->source.size() > 4 &&
                        s.model->mesh->source.compare(s.model->mesh->source.size() - 4, 4, ".geo") == 0);
      CMS_INPUT_CHECK(!used, "--mesh-parameters: no substructure of " << scenePath << " is meshed from a .geo script");
    }
    const std::filesystem::path outDir =
        !output.empty() ? output : (!sc.outputDirectory.empty() ? sc.outputDirectory : "cms-results");
    // The output directory must be writable before anything is computed.
    {
      std::error_code ec;
      std::filesystem::create_directories(outDir, ec);
      CMS_INPUT_CHECK(ec || !std::filesystem::is_directory(outDir),
                      outDir.string() << ": cannot create the output directory (" << ec.message() << ")");
    }
    if (root)
      std::cout << "cms " << command << ": scene " << sc.path << " (\"" << sc.name << "\", units " << sc.units
                << ", " << sc.structure.substructures.size() << " substructures, "
                << Teuchos::DefaultComm<int>::getComm()->getSize() << " rank(s))\n";
    // 3. Run.
    int code = ExitSuccess;
    if (command == "campbell") code = runCampbell(sc, outDir, steps, maxFactor, orders, root);
    else if (command == "truncate") code = runTruncate(sc, outDir, start, step, accuracy, truthRequested, root);
    else code = command == "modes" ? runModes(sc, outDir, root) : runCompare(sc, outDir, counts, root);
    if (timers) Teuchos::TimeMonitor::summarize(std::cout);
    return code;
  });
}
