// bench_rotor: the speed/accuracy trade of component-mode synthesis on a
// rotating assembly of solid meshes, at several mesh sizes (issue #6,
// doc/benchmarks.md "Speed and accuracy at scale").
//
// The structure is drivers/bench/rotor/rotor.yaml: a steel hub (C) clamped
// on its bore and spinning at 200 rad/s, three plate blades (E) tied to it by
// RigidFit attachments, all 10-node tetrahedra meshed by Gmsh from .geo
// scripts with the size h set for each run ("Mesh Parameters"; meshes are
// generated, never committed). After 1. the options, for each h, in one
// process:
//
//   2. assemble the substructures (with the centrifugal prestress);
//   3. the floor: one CHOLMOD factorisation of the full model's stiffness
//      K(Omega) (the truth's coordinates), its time, nnz(L) and flops;
//   4. the truth: the full model solved by the sparse path (Anasazi
//      Block Krylov-Schur on Meirovitch's form) for the lowest --modes;
//   5. every strategy at every vector count: reduction (bases), synthesis
//      (interface transforms and projections), solve; peak memory of that
//      pipeline alone; max and mean relative error over the lowest modes
//      against the truth; and pipeline / truth and pipeline / floor;
//   6. on several ranks, the most accurate model again with every
//      substructure distributed over all ranks instead of whole on one
//      (synthesis::ReductionSchedule), with the frequencies' difference;
//   7. the sweep: --steps speeds from 0 to the nominal speed with the most
//      accurate reduced model (no re-projection), against one speed; and
//      for the truth at sizes up to --truth-sweep-max-dofs.
// One CSV row per measurement (--csv), drawn by
// `plot_results.py rotor CSV PNG` (--plot): error against time, per size.
//
// Run on 1 and 2 ranks to measure the parallel speed-up per phase:
//   bench_rotor --h=0.03,0.015,0.009,0.0052 --csv=rotor-np1.csv
//   mpiexec -n 2 bench_rotor --h=... --csv=rotor-np2.csv
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_CommandLineProcessor.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_Core.hpp>
#include <Tpetra_CrsMatrix.hpp>

#include "DataDirectory.hpp"
#include "DriverBoundary.hpp"
#include "cms/core/PeakMemory.hpp"
#include "cms/analysis/TruthComparison.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"

namespace {

using namespace cms;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream is(text);
  for (std::string w; std::getline(is, w, ',');)
    if (!w.empty()) out.push_back(w);
  return out;
}

/// Peak resident memory since the last reset (largest rank, sum over
/// ranks) and the resident memory at the reset (largest rank), MiB: the
/// window's peak includes what the process already held (the assembled
/// structure, the truth model unless --no-truth --no-floor, and heap glibc
/// kept), `base` says how much.
struct Memory {
  double max = 0, sum = 0, base = 0;
};
double baseline = 0;  ///< VmRSS at the last reset (this rank)
void resetPeak() {
  cms::resetPeakRss();
  baseline = cms::residentMiB();
}
Memory peak(const Teuchos::Comm<int>& comm) {
  double mine = cms::windowPeakRssMiB(), mx = 0, sm = 0, b = 0;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, 1, &mine, &mx);
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, 1, &mine, &sm);
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, 1, &baseline, &b);
  return {mx, sm, b};
}

/// Bytes of a CSR matrix (values, column indices, row offsets) summed over ranks.
double crsBytes(const CrsMatrix& A) {
  return 12.0 * static_cast<double>(A.getGlobalNumEntries()) + 8.0 * static_cast<double>(A.getGlobalNumRows());
}

struct Row {
  double h = 0;
  long long physicalDofs = 0, truthDofs = 0;
  std::string what, strategy;
  int vectors = 0;
  long long reducedDofs = 0;
  double assembly = 0, reduce = 0, synth = 0, solve = 0, pipeline = 0;
  double truth = 0, floor = 0, fullMiB = 0;
  Memory mem;
  double maxError = -1, meanError = -1, worstMac = -1;
  std::string note;
  std::vector<double> hz;  ///< the lowest frequencies (for comparisons across runs)
};

void header(std::ostream& os) {
  os << "h,physical_dofs,truth_dofs,ranks,what,strategy,vectors,reduced_dofs,assembly_s,reduce_s,synthesis_s,solve_s,"
        "pipeline_s,truth_s,floor_s,pipeline_over_truth,pipeline_over_floor,peak_mib_max_rank,peak_mib_sum,"
        "resident_at_start_mib,"
        "full_k_m_factor_mib,max_rel_error,mean_rel_error,worst_mac,note,frequencies_hz\n";
}

void write(std::ostream& os, Row r, int ranks) {
  for (char& c : r.note)
    if (c == ',' || c == '\n') c = ';';
  os << r.h << ',' << r.physicalDofs << ',' << r.truthDofs << ',' << ranks << ',' << r.what << ',' << r.strategy << ','
     << r.vectors << ',' << r.reducedDofs << ',' << r.assembly << ',' << r.reduce << ',' << r.synth << ',' << r.solve
     << ',' << r.pipeline << ',' << r.truth << ',' << r.floor << ','
     << (r.truth > 0 && r.pipeline > 0 ? r.pipeline / r.truth : 0.0) << ','
     << (r.floor > 0 && r.pipeline > 0 ? r.pipeline / r.floor : 0.0) << ',' << r.mem.max << ',' << r.mem.sum << ','
     << r.mem.base << ',' << r.fullMiB << ',' << r.maxError << ',' << r.meanError << ',' << r.worstMac << ',' << r.note << ',';
  const auto old = os.precision(15);
  for (std::size_t i = 0; i < r.hz.size(); ++i) os << (i ? ";" : "") << r.hz[i];
  os.precision(old);
  os << '\n';
}

}  // namespace

int main(int argc, char* argv[]) {
  Tpetra::ScopeGuard scope(&argc, &argv);
  const auto comm = Teuchos::DefaultComm<int>::getComm();
  const bool root = comm->getRank() == 0;
  const int ranks = comm->getSize();
  return drivers::reportErrors("bench_rotor", root, [&]() -> int {
    // 1. Options.
    std::string scenePath;  // default: <prefix>/share/cms/bench/rotor/rotor.yaml
    std::string sizesText = "0.03,0.015", strategiesText = "Admissible,Modes,Craig-Bampton", countsText = "6,12,24";
    std::string csvPath = "bench_rotor.csv";
    int modes = 20, steps = 101;
    double truthSweepMaxDofs = 3e4;
    bool doPlot = false, doTruth = true, doFloor = true;
    Teuchos::CommandLineProcessor clp(false, true);
    clp.setDocString("Speed/accuracy trade of reduction strategies against the truth and one CHOLMOD factorisation.");
    clp.setOption("scene", &scenePath,
                  "scene whose meshed substructures take \"Mesh Parameters/h\" (default: the rotor, "
                  "<prefix>/share/cms/bench/rotor/rotor.yaml)");
    clp.setOption("h", &sizesText, "comma-separated mesh sizes (m), one run each");
    clp.setOption("strategies", &strategiesText, "comma-separated bases: Admissible, Modes, Craig-Bampton, Guyan");
    clp.setOption("counts", &countsText, "comma-separated vectors per substructure");
    clp.setOption("modes", &modes, "lowest modes solved and compared");
    clp.setOption("steps", &steps, "speeds of the sweep (0 for none)");
    clp.setOption("truth-sweep-max-dofs", &truthSweepMaxDofs, "sweep the truth too up to this size");
    clp.setOption("truth", "no-truth", &doTruth, "solve the truth (errors need it)");
    clp.setOption("floor", "no-floor", &doFloor, "factor the full stiffness once (the floor; needs the truth's matrices)");
    clp.setOption("csv", &csvPath, "output CSV file");
    clp.setOption("plot", "no-plot", &doPlot, "also draw CSV -> PNG with plot_results.py");
    if (clp.parse(argc, argv) != Teuchos::CommandLineProcessor::PARSE_SUCCESSFUL) return ExitInputError;
    if (scenePath.empty()) scenePath = drivers::dataFile("bench/rotor/rotor.yaml").string();
    std::vector<double> sizes;
    for (const auto& w : split(sizesText)) {
      char* end = nullptr;
      const double h = std::strtod(w.c_str(), &end);
      CMS_INPUT_CHECK(*end != '\0' || !(h > 0), "--h: \"" << w << "\" is not a positive size");
      sizes.push_back(h);
    }
    std::vector<int> counts;
    for (const auto& w : split(countsText)) {
      char* end = nullptr;
      const long k = std::strtol(w.c_str(), &end, 10);
      CMS_INPUT_CHECK(*end != '\0' || k < 0, "--counts: \"" << w << "\" is not a count");
      counts.push_back(static_cast<int>(k));
    }
    const auto strategies = split(strategiesText);
    CMS_INPUT_CHECK(modes < 1, "--modes = " << modes << " must be at least 1");
    if (root) {
      // Checked before the first (long) run: no partial output.
      std::ofstream probe(csvPath, std::ios::app);
      CMS_INPUT_CHECK(!probe, csvPath << ": cannot be written");
    }

    std::vector<Row> rows;
    auto flush = [&]() {
      if (!root) return;
      std::ofstream csv(csvPath + ".tmp");
      header(csv);
      for (const auto& r : rows) write(csv, r, ranks);
      csv.close();
      std::filesystem::rename(csvPath + ".tmp", csvPath);
    };
    if (root)
      std::cout << "bench_rotor: " << scenePath << ", " << ranks << " rank(s), lowest " << modes << " modes\n";

    for (double h : sizes) {
      // 2. Assembly (meshing timed apart: Gmsh runs when the scene is read).
      resetPeak();
      auto t0 = Clock::now();
      const auto sc = scene::Scene::read(scenePath, {{"h", h}});
      const double meshing = since(t0);
      t0 = Clock::now();
      const auto structure = synthesis::AssembledStructure::assemble(sc.structure, comm);
      const double assembly = since(t0);
      long long physical = 0;
      for (const auto& [name, n] : structure.substructureDofs()) physical += n;
      const auto speeds = structure.nominalSpeeds();
      Teuchos::ParameterList solve = sc.solve;
      solve.set("Number of Modes", modes);
      if (root)
        std::cout << "\nh = " << h << " m: " << physical << " DOFs; meshing " << meshing << " s, assembly "
                  << assembly << " s\n";
      Row base;
      base.h = h;
      base.physicalDofs = physical;
      base.assembly = assembly;
      rows.push_back(base);
      rows.back().what = "assembly";
      rows.back().mem = peak(*comm);
      rows.back().note = "meshing " + std::to_string(meshing) + " s";

      // 3. The floor: one CHOLMOD factorisation of the full stiffness K(Omega).
      // (Skipped with --no-truth --no-floor: then the process never holds a
      // full model, and the strategies' peak memory is the reduced
      // pipeline's own, assembly included.)
      resetPeak();
      t0 = Clock::now();
      std::optional<synthesis::SynthesizedStructure> truthModel;
      if (doTruth || doFloor) truthModel = synthesis::SynthesizedStructure::synthesize(structure, true);
      const double truthSynth = since(t0);
      base.truthDofs = truthModel ? truthModel->size() : 0;
      double floor = 0, fullMiB = 0;
      if (doFloor) {
        const auto& truth = *truthModel;
        const auto sys = truth.system(speeds);
        SparseDirectSolver chol(sys.K, "CHOLMOD");
        const auto outcome = chol.factor();
        floor = chol.factorSeconds();
        fullMiB = (crsBytes(*sys.K) + crsBytes(*sys.M) + 8.0 * chol.factorNonzeros()) / (1024.0 * 1024.0);
        Row r = base;
        r.what = "floor";
        r.strategy = "CHOLMOD";
        r.floor = floor;
        r.fullMiB = fullMiB;
        r.mem = peak(*comm);
        std::ostringstream note;
        note << "nnz(L) " << chol.factorNonzeros() << "; " << chol.factorFlops() << " flop"
             << (outcome == SparseDirectSolver::Outcome::Factored ? "" : "; NOT FACTORED: " + chol.failure());
        r.note = note.str();
        rows.push_back(r);
        if (root)
          std::cout << "floor: CHOLMOD of K(Omega), n = " << truth.size() << ": " << floor << " s, nnz(L) "
                    << chol.factorNonzeros() << ", K + M + L = " << fullMiB << " MiB\n";
      }
      base.floor = floor;
      base.fullMiB = fullMiB;
      if (!doTruth) truthModel.reset();

      // 4. The truth.
      synthesis::StructureModes truthModes;
      double truthSeconds = 0;
      if (doTruth) {
        const auto& truth = *truthModel;
        resetPeak();
        t0 = Clock::now();
        Teuchos::ParameterList ts = solve;
        ts.set("Solver", std::string("Sparse"));
        truthModes = truth.solve(speeds, ts);
        truthSeconds = truthSynth + since(t0);
        Row r = base;
        r.what = "truth";
        r.strategy = "Full";
        r.reducedDofs = truth.size();
        r.synth = truthSynth;
        r.solve = truthModes.seconds;
        r.pipeline = truthSeconds;
        r.truth = truthSeconds;
        r.mem = peak(*comm);
        r.note = truthModes.path + "; " + eigen::toString(truthModes.result.status);
        for (const auto& m : truthModes.result.modes) r.hz.push_back(m.hz);
        rows.push_back(r);
        if (root)
          std::cout << "truth: " << truth.size() << " coordinates, " << truthSeconds << " s (" << truthModes.path
                    << "), peak " << r.mem.max << " MiB\n";
        CMS_INPUT_CHECK(static_cast<int>(truthModes.result.modes.size()) < modes,
                        "the truth gave " << truthModes.result.modes.size() << " modes of " << modes);
      }
      base.truth = truthSeconds;
      flush();

      // 5. Strategies.
      std::vector<Teuchos::ParameterList> best;
      std::string bestStrategy;
      int bestCount = 0;
      std::vector<double> bestHz;  ///< its frequencies and reduction time (concurrent schedule)
      double bestReduce = 0;
      double bestError = 1e300;
      for (const auto& strategy : strategies) {
        for (int k : strategy == "Guyan" ? std::vector<int>{0} : counts) {
          Row r = base;
          r.what = "reduced";
          r.strategy = strategy;
          r.vectors = k;
          resetPeak();
          try {
            const auto red = synthesis::sameReduction(structure, strategy, k);
            t0 = Clock::now();
            const auto s = synthesis::SynthesizedStructure::synthesize(structure, red);
            const double synthWall = since(t0);
            r.reduce = s.basesSeconds();
            r.synth = synthWall - r.reduce;
            r.reducedDofs = s.size();
            if (s.size() < modes) {
              r.note = "fewer coordinates than modes";
            } else {
              const auto m = s.solve(speeds, solve);
              r.solve = m.seconds;
              r.pipeline = synthWall + m.seconds;
              for (const auto& md : m.result.modes) r.hz.push_back(md.hz);
              auto keep = [&] {
                best = red, bestStrategy = strategy, bestCount = k;
                bestHz = r.hz, bestReduce = r.reduce;
              };
              if (!doTruth) keep();  // no errors: the last model stands in
              if (doTruth && static_cast<int>(m.result.modes.size()) >= modes) {
                const auto c = analysis::compareWithTruth(s, m, *truthModel, truthModes, modes);
                r.maxError = c.maxRelativeError;
                r.meanError = c.meanRelativeError;
                r.worstMac = c.worstMac;
                if (r.maxError < bestError) bestError = r.maxError, keep();
              }
              r.note = m.path;
            }
          } catch (const InputError& e) {
            r.note = std::string("skipped: ") + e.what();
          } catch (const NumericalError& e) {
            r.note = std::string("FAILED (numerical): ") + e.what();
          }
          r.mem = peak(*comm);
          rows.push_back(r);
          if (root)
            std::cout << std::left << std::setw(14) << strategy << std::right << std::setw(4) << k << std::setw(7)
                      << r.reducedDofs << " coords  reduce " << std::setprecision(3) << r.reduce << " s, synth "
                      << r.synth << " s, solve " << r.solve << " s; pipeline/truth "
                      << (r.pipeline > 0 && r.truth > 0 ? r.pipeline / r.truth : 0.0) << ", pipeline/floor "
                      << (r.pipeline > 0 && floor > 0 ? r.pipeline / floor : 0.0) << "; max err " << r.maxError << "; peak "
                      << std::setprecision(5) << r.mem.max << " MiB" << (r.note.rfind("skipped", 0) == 0 ? "  " + r.note : "")
                      << '\n';
          flush();
        }
      }

      // A row for the most accurate model synthesised again (wall seconds of
      // the synthesis, bases included, and of the solves).
      auto modelRow = [&](const char* what, const synthesis::SynthesizedStructure& m, double synthWall,
                          double solveSeconds) {
        Row r = base;
        r.what = what;
        r.strategy = bestStrategy;
        r.vectors = bestCount;
        r.reducedDofs = m.size();
        r.reduce = m.basesSeconds();
        r.synth = synthWall - r.reduce;
        r.solve = solveSeconds;
        r.pipeline = synthWall + solveSeconds;
        return r;
      };

      // 6. On several ranks: the most accurate model with each substructure
      // distributed over all ranks instead of whole on one (the schedules'
      // times, and their frequencies' agreement).
      if (ranks > 1 && !best.empty()) {
        resetPeak();
        t0 = Clock::now();
        const auto a = synthesis::SynthesizedStructure::synthesize(structure, best,
                                                                   synthesis::ReductionSchedule::Distributed);
        const double wall = since(t0);
        const auto ma = a.solve(speeds, solve);
        // Against the same model's row above (concurrent schedule).
        double diff = 0;
        for (std::size_t i = 0; i < std::min(ma.result.modes.size(), bestHz.size()); ++i)
          diff = std::max(diff, std::abs(ma.result.modes[i].hz / bestHz[i] - 1.0));
        Row r = modelRow("distributed-schedule", a, wall, ma.seconds);
        std::ostringstream note;
        note << "max rel. frequency difference from the concurrent schedule " << diff << " (concurrent reduce "
             << bestReduce << " s)";
        r.note = note.str();
        r.mem = peak(*comm);
        rows.push_back(r);
        if (root) std::cout << "distributed schedule: reduce " << r.reduce << " s; " << r.note << '\n';
      }

      // 7. The sweep: one model, `steps` speeds, no re-projection.
      if (steps > 0 && !best.empty()) {
        resetPeak();
        t0 = Clock::now();
        const auto s = synthesis::SynthesizedStructure::synthesize(structure, best);
        const double synthWall = since(t0);
        t0 = Clock::now();
        const auto one = s.solve(speeds, solve);
        const double single = synthWall + since(t0);
        t0 = Clock::now();
        int notConverged = 0;
        for (int i = 0; i < steps; ++i) {
          std::vector<double> sp(speeds);
          for (double& v : sp) v *= static_cast<double>(i) / std::max(1, steps - 1);
          notConverged += s.solve(sp, solve).result.status != eigen::SolveStatus::Converged;
        }
        const double sweep = synthWall + since(t0);
        Row r = modelRow("sweep", s, synthWall, sweep - synthWall);
        r.note = std::to_string(steps) + " speeds / one speed = " + std::to_string(sweep / single) + " (one: " +
                 std::to_string(single) + " s); not converged " + std::to_string(notConverged);
        r.mem = peak(*comm);
        rows.push_back(r);
        if (root) std::cout << "sweep: " << r.note << '\n';
        if (doTruth && truthModel->size() <= truthSweepMaxDofs) {
          const auto& truth = *truthModel;
          Teuchos::ParameterList ts = solve;
          ts.set("Solver", std::string("Sparse"));
          t0 = Clock::now();
          for (int i = 0; i < steps; ++i) {
            std::vector<double> sp(speeds);
            for (double& v : sp) v *= static_cast<double>(i) / std::max(1, steps - 1);
            truth.solve(sp, ts);
          }
          const double tsweep = truthSynth + since(t0);
          Row t = base;
          t.what = "sweep";
          t.strategy = "Full";
          t.reducedDofs = truth.size();
          t.synth = truthSynth;
          t.solve = tsweep - truthSynth;
          t.pipeline = tsweep;
          t.note = std::to_string(steps) + " speeds / one speed = " + std::to_string(tsweep / truthSeconds);
          rows.push_back(t);
          if (root) std::cout << "truth sweep: " << t.note << '\n';
        }
        flush();
      }
    }
    if (root) std::cout << "\nwrote " << csvPath << '\n';
    if (root && doPlot) {
      const auto png = std::filesystem::path(csvPath).replace_extension(".png").string();
      const std::string cmd = std::string(CMS_PYTHON) + " '" + drivers::dataFile("plot_results.py").string() +
                              "' rotor '" + csvPath + "' '" + png + "'";
      if (std::system(cmd.c_str()) == 0) std::cout << "plotted " << png << '\n';
      else std::cout << "no plot: " << cmd << " failed\n";
    }
    return ExitSuccess;
  });
}
