// bench_rotor: the speed/accuracy trade of component-mode synthesis on a
// rotating assembly of solid meshes, at several mesh sizes (issue #6,
// doc/benchmarks.md "Speed and accuracy at scale").
//
// The structure is drivers/bench/rotor/rotor.yaml: a steel hub (C) clamped on
// its bore, spinning at 200 rad/s, three plate blades (E) tied to it by
// RigidFit attachments, 10-node tetrahedra meshed by Gmsh with the size h of
// each run ("Mesh Parameters"). After 1. the options, for each h:
//   2. assemble the substructures (with the centrifugal prestress);
//   3. the floor: one CHOLMOD factorisation of the full K(Omega);
//   4. the truth: the full model by the sparse path, lowest --modes;
//   5. every strategy at every count through analysis::StrategyComparison
//      (the loop of `cms compare`): bases, synthesis and solve times, the
//      pipeline's own peak memory, errors against the truth;
//   6. on several ranks, the most accurate model with each substructure
//      distributed over all ranks instead of whole on one;
//   7. the sweep: --steps speeds from 0 to nominal with that model (no
//      re-projection), and with the truth up to --truth-sweep-max-dofs.
// One CSV row per measurement (--csv); --plot draws error against time per
// size (plot_results.py rotor). doc/benchmarks.md has the measured runs.
//
// Sample runs (1 and 2 ranks give the parallel speed-up per phase):
//   bench_rotor --h=0.03,0.015 --csv=rotor.csv --plot
//   bench_rotor --h=0.0052 --no-truth --no-floor --steps=0   # the reduced pipeline's memory alone
//   bench_rotor --h=0.0052 --counts=16 --steps=0 --reduced-first   # timed as a user's first run
//   bench_rotor --h=0.009 --no-truth --no-floor --steps=0 --assemble-copies   # what turning copies saves
//   bench_rotor --h=0.009 --counts=16 --steps=0 --reduced-first --estimates   # and what its estimates add
//   mpiexec -n 2 bench_rotor --h=0.03,0.015,0.009,0.0052 --csv=rotor-np2.csv
#include <algorithm>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>

#include <Teuchos_Array.hpp>
#include <Teuchos_CommandLineProcessor.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_Core.hpp>
#include <Tpetra_CrsMatrix.hpp>

#include "CommandLine.hpp"
#include "DriverBoundary.hpp"
#include "RotorBenchTable.hpp"  // the rows, their CSV columns and console line; PeakMemoryWindow
#include "cms/analysis/StrategyComparison.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/core/Stopwatch.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/core/Program.hpp"

namespace {

using namespace cms;
using drivers::Row;

struct Options {
  std::string scene, csv = "bench_rotor.csv";
  std::vector<double> sizes;
  std::vector<int> counts;
  std::vector<std::string> strategies;
  int modes = 20, steps = 101;
  double truthSweepMaxDofs = 3e4;
  bool plot = false, truth = true, floor = true, reducedFirst = false;
  bool turnCopies = true;  ///< false: every copy assembled on its own (the cost turning saves)
  bool estimates = false;  ///< time each reduced row's error estimates too (outside its pipeline)
};

/// The benchmark at one mesh size, its phases in order (steps 2-7 above).
class SizeRun {
public:
  SizeRun(const Options& o, double h, const Teuchos::RCP<const Teuchos::Comm<int>>& comm, std::vector<Row>& rows)
      : o_(o), comm_(comm), root_(comm->getRank() == 0), memory_(*comm), rows_(rows), base_{h} {}
  void run() {
    assemble();
    if (o_.reducedFirst) {  // as a user's run: the first reduction right after the assembly
      const std::size_t first = rows_.size();
      strategies();
      floorAndTruth();
      errorsByOrder(first);
    } else {
      floorAndTruth();
      flush();
      strategies();
    }
    if (comm_->getSize() > 1 && best_) distributedSchedule();
    if (o_.steps > 0 && best_) sweep();
    flush();
  }

private:
  /// A row of this size; the CSV rewritten whole after every phase (rank 0).
  Row row(const char* what, const std::string& strategy) const { return base_.with(what, strategy); }
  void flush() const { if (root_) writeCsv(o_.csv, rows_, comm_->getSize()); }
  /// Every row: its memory window's peak, and one console line.
  void add(Row r) {
    r.mem = memory_.peak();
    if (root_) printRow(std::cout, r);
    rows_.push_back(std::move(r));
  }

  // 2. Assembly (meshing timed apart: Gmsh runs when the scene is read).
  void assemble() {
    memory_.open();
    Stopwatch t0;
    const auto sc = scene::Scene::read(o_.scene, {{"h", base_.h}});
    const double meshing = t0.seconds();
    t0.restart();
    auto d = sc.structure.withCopies();
    if (!o_.turnCopies)  // models withCopies did not make: the assembly assembles every copy (theory §15.2)
      for (auto& spec : d.substructures)
        if (spec.copy && spec.copy->index > 0 && spec.model)
          spec.model = std::make_shared<fem::FiniteElementModel>(*spec.model);
    structure_.emplace(synthesis::AssembledStructure::assemble(d, comm_));
    base_.assembly = t0.seconds();
    for (const auto& [name, n] : structure_->substructureDofs()) base_.physicalDofs += n;
    speeds_ = structure_->nominalSpeeds();
    solve_ = sc.solve;
    solve_.set("Number of Modes", o_.modes);
    Row r = row("assembly", "");
    r.note = "meshing " + std::to_string(meshing) + " s";
    for (auto n : structure_->notes()) {  // e.g. the copies turned (theory §15.2); the CSV takes no commas
      std::replace(n.begin(), n.end(), ',', ' ');
      r.note += "; " + n;
    }
    if (root_) {
      std::cout << "\nh = " << base_.h << " m: " << base_.physicalDofs << " DOFs; assembly " << base_.assembly
                << " s\n";
      for (const auto& n : structure_->notes()) std::cout << "note: " << n << '\n';
    }
    add(r);
  }

  // 3. The floor: one CHOLMOD factorisation of the full stiffness K(Omega),
  // and 4. the truth (skipped with --no-truth --no-floor: then the process
  // never holds a full model, and the strategies' peak memory is the reduced
  // pipeline's own, assembly included).
  void floorAndTruth() {
    if (!o_.truth && !o_.floor) return;
    memory_.open();
    const Stopwatch t0;
    truthModel_.emplace(synthesis::SynthesizedStructure::synthesize(*structure_, true));
    const double synth = t0.seconds();
    base_.truthDofs = truthModel_->size();
    if (o_.floor) {
      const auto sys = truthModel_->system(speeds_);
      SparseDirectSolver chol(sys.K, "CHOLMOD");
      const bool factored = chol.factor() == SparseDirectSolver::Outcome::Factored;
      auto bytes = [](const CrsMatrix& A) { return 12.0 * A.getGlobalNumEntries() + 8.0 * A.getGlobalNumRows(); };
      base_.floor = chol.factorSeconds();
      base_.fullMiB = (bytes(*sys.K) + bytes(*sys.M) + 8.0 * chol.factorNonzeros()) / (1024.0 * 1024.0);
      Row r = row("floor", "CHOLMOD");
      r.note = "nnz(L) " + std::to_string(chol.factorNonzeros()) + "; " + std::to_string(chol.factorFlops()) +
               " flop" + (factored ? "" : "; NOT FACTORED: " + chol.failure());
      add(r);
    }
    if (!o_.truth) return truthModel_.reset();  // the floor alone: no full model held from here on
    memory_.open();
    const Stopwatch t1;
    truthSolve_ = solve_;
    truthSolve_.set("Solver", std::string("Sparse"));
    truthModes_ = truthModel_->solve(speeds_, truthSolve_);
    base_.truth = truthSynth_ = synth;
    base_.truth += t1.seconds();
    Row r = row("truth", "Full");
    r.reducedDofs = base_.truthDofs, r.synth = synth, r.solve = truthModes_.seconds, r.pipeline = base_.truth;
    r.note = truthModes_.path + "; " + eigen::toString(truthModes_.result.status);
    // Whether its Sturm count confirmed the set, or why not (the CSV's note
    // column takes no commas).
    std::string reason = truthModes_.result.reason;
    std::replace(reason.begin(), reason.end(), ',', ';');
    std::replace(reason.begin(), reason.end(), '\n', ' ');
    if (!reason.empty()) r.note += "; " + reason;
    for (const auto& m : truthModes_.result.modes) r.hz.push_back(m.hz);
    add(r);
    CMS_INPUT_CHECK(static_cast<int>(truthModes_.result.modes.size()) < o_.modes,
                    "the truth gave " << truthModes_.result.modes.size() << " modes of " << o_.modes);
  }

  // 5. Every strategy at every count (analysis::StrategyComparison), each in
  // its own memory window; the most accurate (without a truth: the last)
  // model is kept for 6. and 7.
  void strategies() {
    Teuchos::ParameterList study;
    study.set("Strategies", Teuchos::Array<std::string>(o_.strategies));
    study.set("Counts", Teuchos::Array<int>(o_.counts));
    // The pipeline is timed without the estimates; --estimates times them
    // apart, after the solve (theory §11.8: what `cms modes` adds to it).
    study.set("Error Estimates", o_.estimates);
    double bestError = 1e300;
    const analysis::SolvedTruth truth{truthModel_ ? &*truthModel_ : nullptr, &truthModes_, base_.truth};
    analysis::StrategyHooks hooks{[&](const std::string&, int) { memory_.open(); }, {}};
    hooks.onResult = [&](const analysis::StrategyRow* s, const analysis::StrategyOutcome* o) {
      Row r = row("reduced", s ? s->basis : o->basis);
      r.vectors = s ? s->vectors : o->vectors;
      r.reducedDofs = s ? s->dofs : o->dofs;
      if (o) r.note = (o->failed ? std::string("FAILED (") + eigen::toString(o->status) + "): " : "skipped: ") + o->why;
      if (s) {
        r.reduce = s->basesSeconds, r.synth = s->reduceSeconds - s->basesSeconds, r.solve = s->solveSeconds;
        r.pipeline = s->reduceSeconds + s->solveSeconds, r.hz = s->hz, r.note = s->path;
        if (!s->adopted.empty()) {  // theory §11.4: the assembly's factorisation reused
          r.note += "; prestress factorisation adopted by";
          for (const auto& name : s->adopted) r.note += " " + name;
        }
        if (o_.estimates) {
          std::ostringstream os;
          os << "; error estimates " << s->estimateSeconds << " s after the pipeline (largest " << s->estimate << ")";
          r.note += os.str();
        }
        if (s->compared)
          r.maxError = s->accuracy.maxRelativeError, r.meanError = s->accuracy.meanRelativeError,
          r.worstMac = s->accuracy.worstMac;
        if (!s->compared || r.maxError < bestError) bestError = r.maxError, best_ = *s;
      }
      add(r);
      flush();
    };
    analysis::StrategyComparison(*structure_, solve_, study).run(truth, hooks);
  }

  // 5b. With --reduced-first the strategies ran before the truth, and no
  // reduced model was kept for it (a reduced model keeps its factors for
  // its error estimates: beside the truth's they would raise its peak). Each
  // row's k-th frequency is compared with the truth's k-th instead of the
  // mode paired by shape: a missing or surplus mode then shows as a large
  // error rather than being matched away; worst MAC is not available (-1).
  void errorsByOrder(std::size_t first) {
    std::vector<double> truthHz;
    for (const auto& m : truthModes_.result.modes) truthHz.push_back(m.hz);
    for (std::size_t i = first; i < rows_.size(); ++i) {
      Row& r = rows_[i];
      r.truth = base_.truth, r.floor = base_.floor, r.truthDofs = base_.truthDofs, r.fullMiB = base_.fullMiB;
      if (r.what != "reduced" || r.hz.empty() || truthHz.empty()) continue;
      const std::size_t n = std::min({r.hz.size(), truthHz.size(), static_cast<std::size_t>(o_.modes)});
      double worst = 0, sum = 0;
      for (std::size_t k = 0; k < n; ++k) {
        const double e = std::abs(r.hz[k] / truthHz[k] - 1.0);
        worst = std::max(worst, e), sum += e;
      }
      r.maxError = worst, r.meanError = sum / static_cast<double>(n);
      r.note += "; errors by order (k-th frequency against the truth's k-th; reduced before the truth)";
      if (root_) printRow(std::cout, r);
    }
  }

  /// The most accurate model synthesised again, and the wall seconds it took.
  std::pair<synthesis::SynthesizedStructure, double> bestModel(synthesis::ReductionSchedule schedule) const {
    const Stopwatch t0;
    auto s = synthesis::SynthesizedStructure::synthesize(
        *structure_, synthesis::sameReduction(*structure_, best_->basis, best_->vectors), schedule);
    return {std::move(s), t0.seconds()};
  }
  /// Its row (wall seconds of the synthesis, bases included, and of the solves).
  Row modelRow(const char* what, const synthesis::SynthesizedStructure& m, double synthWall, double solve) const {
    Row r = row(what, best_->basis);
    r.vectors = best_->vectors, r.reducedDofs = m.size(), r.reduce = m.basesSeconds();
    r.synth = synthWall - r.reduce, r.solve = solve, r.pipeline = synthWall + solve;
    return r;
  }

  // 6. The most accurate model with each substructure distributed over all
  // ranks instead of whole on one: the schedules' times and frequencies.
  void distributedSchedule() {
    memory_.open();
    const auto [a, wall] = bestModel(synthesis::ReductionSchedule::Distributed);
    const auto ma = a.solve(speeds_, solve_);
    double diff = 0;
    for (std::size_t i = 0; i < std::min(ma.result.modes.size(), best_->hz.size()); ++i)
      diff = std::max(diff, std::abs(ma.result.modes[i].hz / best_->hz[i] - 1.0));
    Row r = modelRow("distributed-schedule", a, wall, ma.seconds);
    r.note = "max rel. frequency difference from the concurrent schedule " + std::to_string(diff) +
             " (concurrent reduce " + std::to_string(best_->basesSeconds) + " s)";
    add(r);
  }

  // 7. The sweep: one model, --steps speeds from 0 to nominal, no
  // re-projection; and the truth's, if it is small enough.
  double sweepSeconds(const synthesis::SynthesizedStructure& m, const Teuchos::ParameterList& p,
                      int& notConverged, std::vector<double>* hz = nullptr, std::string* path = nullptr) const {
    const Stopwatch t0;
    std::vector<std::vector<double>> speeds;
    for (int i = 0; i < o_.steps; ++i) {
      speeds.push_back(speeds_);
      for (double& v : speeds.back()) v *= static_cast<double>(i) / std::max(1, o_.steps - 1);
    }
    // As cms campbell solves its grid: on the cores left to each rank.
    const auto all = m.solveMany(speeds, p);
    const double seconds = t0.seconds();
    if (path && !all.empty()) *path = all.front().path;
    for (const auto& s : all) {
      notConverged += s.result.status != eigen::SolveStatus::Converged;
      if (hz)
        for (const auto& mode : s.result.modes) hz->push_back(mode.hz);
    }
    return seconds;
  }
  void sweep() {
    memory_.open();
    const auto [s, synthWall] = bestModel(synthesis::ReductionSchedule::Concurrent);
    const Stopwatch t0;
    s.solve(speeds_, solve_);
    const double single = synthWall + t0.seconds();
    int notConverged = 0;
    std::vector<double> hz, hzBidiagonal;
    std::string path;
    Row r = modelRow("sweep", s, synthWall, sweepSeconds(s, solve_, notConverged, &hz, &path));
    r.note = std::to_string(o_.steps) + " speeds / one speed = " + std::to_string(r.pipeline / single) + " (one: " +
             std::to_string(single) + " s); not converged " + std::to_string(notConverged);
    add(r);
    // The same sweep with the dense path's general bidiagonalisation of its
    // skew factor (theory §2): the skew tridiagonal form's gain, and that
    // both give the same frequencies.
    if (path.rfind("dense", 0) == 0) {
      Teuchos::ParameterList bp(solve_);
      bp.sublist("Dense Solver").set("Reduction", "Bidiagonal");
      int nc = 0;
      Row b = modelRow("sweep-bidiagonal", s, synthWall, sweepSeconds(s, bp, nc, &hzBidiagonal));
      double diff = 0.0;
      for (std::size_t i = 0; i < std::min(hz.size(), hzBidiagonal.size()); ++i)
        diff = std::max(diff, std::abs(hzBidiagonal[i] / hz[i] - 1.0));
      std::ostringstream note;
      note << o_.steps << " speeds / one speed = " << b.pipeline / single << "; not converged " << nc
           << "; max rel. frequency difference from the skew sweep " << std::setprecision(2) << diff
           << (hz.size() == hzBidiagonal.size() ? "" : " (different mode counts)");
      b.note = note.str();
      add(b);
    }
    if (!truthModel_ || truthModel_->size() > o_.truthSweepMaxDofs) return;
    Row t = row("sweep", "Full");
    t.reducedDofs = base_.truthDofs, t.synth = truthSynth_;
    t.solve = sweepSeconds(*truthModel_, truthSolve_, notConverged);
    t.pipeline = truthSynth_ + t.solve;
    t.note = std::to_string(o_.steps) + " speeds / one speed = " + std::to_string(t.pipeline / base_.truth);
    add(t);
  }

  const Options& o_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  bool root_;
  PeakMemoryWindow memory_;
  std::vector<Row>& rows_;
  Row base_;  ///< what every row of this size repeats
  std::optional<synthesis::AssembledStructure> structure_;
  std::vector<double> speeds_;
  Teuchos::ParameterList solve_, truthSolve_;
  std::optional<synthesis::SynthesizedStructure> truthModel_;
  synthesis::StructureModes truthModes_;
  double truthSynth_ = 0;
  std::optional<analysis::StrategyRow> best_;  ///< the most accurate strategy
};

}  // namespace

int main(int argc, char* argv[]) {
  cms::hugePageHeap(argv);      // the heap on transparent huge pages (re-executes once)
  cms::singletonMpiDefaults();  // a lone process: no daemon, no fabric probing
  Tpetra::ScopeGuard scope(&argc, &argv);
  const auto comm = Teuchos::DefaultComm<int>::getComm();
  const bool root = comm->getRank() == 0;
  return drivers::reportErrors("bench_rotor", root, [&]() -> int {
    // 1. Options.
    Options o;
    std::string sizes = "0.03,0.015", strategies = "Admissible,Modes,Craig-Bampton", counts = "6,12,24";
    Teuchos::CommandLineProcessor clp(false, true);
    clp.setDocString("Speed/accuracy trade of reduction strategies against the truth and one CHOLMOD factorisation.");
    clp.setOption("scene", &o.scene, "scene whose meshed substructures take \"Mesh Parameters/h\" (default: the "
                                     "rotor, <prefix>/share/cms/bench/rotor/rotor.yaml)");
    clp.setOption("h", &sizes, "comma-separated mesh sizes (m), one run each");
    clp.setOption("strategies", &strategies, "comma-separated bases: Admissible, Modes, Craig-Bampton, Guyan");
    clp.setOption("counts", &counts, "comma-separated vectors per substructure");
    clp.setOption("modes", &o.modes, "lowest modes solved and compared");
    clp.setOption("steps", &o.steps, "speeds of the sweep (0 for none)");
    clp.setOption("truth-sweep-max-dofs", &o.truthSweepMaxDofs, "sweep the truth too up to this size");
    clp.setOption("truth", "no-truth", &o.truth, "solve the truth (errors need it)");
    clp.setOption("floor", "no-floor", &o.floor, "factor the full stiffness once (the floor)");
    clp.setOption("reduced-first", "truth-first", &o.reducedFirst,
                  "run the strategies right after the assembly, before the floor and the truth, as a user's run "
                  "does (its first reduction adopts the prestress solves' factorisations); errors then pair "
                  "frequencies by order");
    clp.setOption("turn-copies", "assemble-copies", &o.turnCopies,
                  "copies take their prototype's matrices turned, or are each assembled (to measure the saving)");
    clp.setOption("estimates", "no-estimates", &o.estimates,
                  "also time each reduced row's error estimates (theory 11.8), apart from its pipeline (in the note)");
    clp.setOption("csv", &o.csv, "output CSV file");
    clp.setOption("plot", "no-plot", &o.plot, "also draw CSV -> PNG with plot_results.py");
    if (clp.parse(argc, argv) != Teuchos::CommandLineProcessor::PARSE_SUCCESSFUL) return ExitInputError;
    if (o.scene.empty()) o.scene = drivers::dataFile("bench/rotor/rotor.yaml").string();
    o.sizes = drivers::positiveNumbers(sizes, "--h");
    o.counts = drivers::positiveIntegers(counts, "--counts");
    o.strategies = drivers::commaList(strategies);
    CMS_INPUT_CHECK(o.modes < 1, "--modes = " << o.modes << " must be at least 1");
    if (root) {  // checked before the first (long) run: no partial output
      std::ofstream probe(o.csv, std::ios::app);
      CMS_INPUT_CHECK(!probe, o.csv << ": cannot be written");
      std::cout << "bench_rotor: " << o.scene << ", " << comm->getSize() << " rank(s), lowest " << o.modes
                << " modes\n";
    }

    // 2.-7. Each size in turn.
    std::vector<Row> rows;
    for (double h : o.sizes) SizeRun(o, h, comm, rows).run();
    if (root) std::cout << "\nwrote " << o.csv << '\n';
    if (root && o.plot) drivers::plotCsv("rotor", o.csv);
    return ExitSuccess;
  });
}
