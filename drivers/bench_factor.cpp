// bench_factor: the factorisation of the rotor's whole stiffness K(Omega),
// gathered to rank 0 (CHOLMOD, as every SparseDirectSolver method before
// issue 18) against distributed across the ranks (MUMPS,
// DistributedDirectSolver), and the truth's sparse eigensolve by each
// ("Sparse Solver" -> "Direct Solver"). doc/benchmarks.md, "Distributed
// factorisations".
//
// For each --h: read drivers/bench/rotor/rotor.yaml with that mesh size,
// assemble, synthesize the truth (every basis Full), then per method in
// --methods: factor K(Omega) (time, entries of the factor, peak resident
// memory per rank over the factorisation alone), solve a block of --rhs
// right-hand sides (time, normwise backward error); with --truth, solve the
// truth for the lowest --modes by the sparse path with "Direct Solver" =
// CHOLMOD and MUMPS and report the time and the largest relative difference
// of the frequencies. With --reduce=Basis:vectors, every substructure
// reduced so on the Distributed schedule (each over every rank) with
// "Reduction" -> "Direct Solver" CHOLMOD and MUMPS: the bases' time, peak
// memory and the largest relative difference of the reduced frequencies.
//
//   bench_factor --h=0.009
//   mpiexec -n 2 bench_factor --h=0.009 --truth
//   mpiexec -n 4 --oversubscribe bench_factor --h=0.009     # 4 ranks on 2 cores: oversubscribed
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>

#include <Teuchos_CommandLineProcessor.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_Core.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_MultiVector.hpp>

#include "CommandLine.hpp"
#include "DriverBoundary.hpp"
#include "cms/core/DistributedDirectSolver.hpp"
#include "cms/core/PeakMemory.hpp"
#include "cms/core/SparseDirectSolver.hpp"
#include "cms/core/Stopwatch.hpp"
#include "cms/scene/Scene.hpp"
#include "cms/synthesis/SynthesizedStructure.hpp"
#include "cms/core/Program.hpp"

namespace {

using namespace cms;

/// max_j ||b_j - A x_j|| / (||A||_F ||x_j||).
double backwardError(const CrsMatrix& A, const MultiVector& B, const MultiVector& X) {
  MultiVector R(B.getMap(), B.getNumVectors());
  A.apply(X, R);
  R.update(1.0, B, -1.0);
  Teuchos::Array<double> r(B.getNumVectors()), x(B.getNumVectors());
  R.norm2(r());
  X.norm2(x());
  double worst = 0.0;
  for (std::size_t j = 0; j < r.size(); ++j) worst = std::max(worst, r[j] / (A.getFrobeniusNorm() * x[j]));
  return worst;
}

}  // namespace

int main(int argc, char* argv[]) {
  cms::hugePageHeap(argv);      // the heap on transparent huge pages (re-executes once)
  cms::singletonMpiDefaults();  // a lone process: no daemon, no fabric probing
  Tpetra::ScopeGuard scope(&argc, &argv);
  const auto comm = Teuchos::DefaultComm<int>::getComm();
  const bool root = comm->getRank() == 0;
  return drivers::reportErrors("bench_factor", root, [&]() -> int {
    std::string scenePath, sizes = "0.009", methods = "CHOLMOD,MUMPS-LDLT";
    int rhs = 20, modes = 20;
    bool truth = false;
    std::string reduce;
    Teuchos::CommandLineProcessor clp(false, true);
    clp.setDocString("One factorisation of the rotor's K(Omega): gathered CHOLMOD against distributed MUMPS.");
    clp.setOption("scene", &scenePath, "scene with \"Mesh Parameters/h\" (default: the rotor of bench_rotor)");
    clp.setOption("h", &sizes, "comma-separated mesh sizes (m), one run each");
    clp.setOption("methods", &methods, "comma-separated SparseDirectSolver methods: CHOLMOD, MUMPS-LDLT, MUMPS, KLU2");
    clp.setOption("rhs", &rhs, "right-hand sides solved as one block after each factorisation");
    clp.setOption("truth", "no-truth", &truth, "also solve the truth with Direct Solver CHOLMOD and MUMPS");
    clp.setOption("modes", &modes, "lowest modes of the truth solve");
    clp.setOption("reduce", &reduce, "Basis:vectors (e.g. Craig-Bampton:12): reduce on the Distributed schedule with "
                                     "Direct Solver CHOLMOD and MUMPS");
    if (clp.parse(argc, argv) != Teuchos::CommandLineProcessor::PARSE_SUCCESSFUL) return ExitInputError;
    if (scenePath.empty()) scenePath = drivers::dataFile("bench/rotor/rotor.yaml").string();
    CMS_INPUT_CHECK(rhs < 1, "--rhs = " << rhs << " must be at least 1");
    const auto methodList = drivers::commaList(methods);
    for (const auto& m : methodList)
      CMS_INPUT_CHECK(!SparseDirectSolver::isKnownMethod(m), "--methods: unknown method \"" << m << "\"");
    if (root) std::cout << "bench_factor: " << scenePath << ", " << comm->getSize() << " rank(s)\n";
    PeakMemoryWindow memory(*comm);
    for (double h : drivers::positiveNumbers(sizes, "--h")) {
      const auto sc = scene::Scene::read(scenePath, {{"h", h}});
      const auto structure = synthesis::AssembledStructure::assemble(sc.structure, comm);
      const auto full = synthesis::SynthesizedStructure::synthesize(structure, true);
      const auto speeds = structure.nominalSpeeds();
      const auto sys = full.system(speeds);
      if (root)
        std::cout << "\nh = " << h << " m: truth " << full.size() << " DOFs, nnz(K) " << sys.K->getGlobalNumEntries()
                  << "\n  method       factor s  solve s (" << rhs << " rhs)  factor entries  backward err"
                  << "  peak MiB max/rank (sum)  base MiB\n";
      for (const auto& m : methodList) {
        memory.open();
        MultiVector B(sys.K->getRowMap(), rhs), X(sys.K->getRowMap(), rhs);
        B.randomize();
        double factorSeconds = 0.0, entries = 0.0, solveSeconds = 0.0, err = 0.0;
        std::string note;
        if (m.rfind("MUMPS", 0) == 0) {
          // DistributedDirectSolver itself (SparseDirectSolver adds a probe
          // solve to its factor time): the analysis and the ordering too.
          DistributedDirectSolver solver(sys.K,
                                         m == "MUMPS" ? DistributedDirectSolver::Kind::General
                                                      : DistributedDirectSolver::Kind::Symmetric,
                                         "K(Omega)");
          solver.factor();
          factorSeconds = solver.factorSeconds();
          entries = solver.factorEntries();
          Stopwatch t;
          solver.solve(B, X);
          solveSeconds = t.seconds();
          note = "  analysis " + std::to_string(solver.analysisSeconds()) + " s, ordering INFOG(7) = " +
                 std::to_string(solver.ordering()) + ", MUMPS's own MB max " +
                 std::to_string(solver.factorMemoryMaxMB()) + " sum " + std::to_string(solver.factorMemoryTotalMB());
        } else {
          SparseDirectSolver solver(sys.K, m);
          const auto out = solver.factor();
          factorSeconds = solver.factorSeconds();
          entries = solver.factorNonzeros();
          if (out == SparseDirectSolver::Outcome::Factored) {
            Stopwatch t;
            solver.solve(B, X);
            solveSeconds = t.seconds();
          } else {
            note = "  NOT FACTORED: " + solver.failure();
          }
        }
        if (solveSeconds > 0.0) err = backwardError(*sys.K, B, X);
        const auto peak = memory.peak();
        if (root)
          std::cout << "  " << std::left << std::setw(12) << m << std::right << std::setw(9) << std::setprecision(3)
                    << factorSeconds << std::setw(9) << solveSeconds << std::setw(24) << std::setprecision(4)
                    << entries << std::setw(14) << std::setprecision(2) << err << std::setw(12)
                    << std::setprecision(5) << peak.max << " (" << peak.sum << ")" << std::setw(10) << peak.base
                    << note << '\n';
      }
      if (!reduce.empty()) {
        const auto colon = reduce.find(':');
        CMS_INPUT_CHECK(colon == std::string::npos, "--reduce = \"" << reduce << "\": expected Basis:vectors");
        const std::string basis = reduce.substr(0, colon);
        const int vectors = drivers::positiveIntegers(reduce.substr(colon + 1), "--reduce")[0];
        std::vector<double> reference;
        for (const char* direct : {"CHOLMOD", "MUMPS"}) {
          auto lists = synthesis::sameReduction(structure, basis, vectors);
          for (auto& l : lists) l.set("Direct Solver", std::string(direct));
          memory.open();
          const Stopwatch t;
          const auto model = synthesis::SynthesizedStructure::synthesize(structure, lists,
                                                                         synthesis::ReductionSchedule::Distributed);
          const double seconds = t.seconds();
          const auto peak = memory.peak();
          Teuchos::ParameterList p = sc.solve;
          p.set("Number of Modes", modes);
          const auto result = model.solve(speeds, p);
          std::vector<double> hz;
          for (const auto& mode : result.result.modes) hz.push_back(mode.hz);
          if (reference.empty()) reference = hz;
          double worst = 0.0;
          for (std::size_t k = 0; k < std::min(hz.size(), reference.size()); ++k)
            worst = std::max(worst, std::abs(hz[k] - reference[k]) / reference[k]);
          if (root)
            std::cout << "  " << basis << " " << vectors << ", Distributed schedule, Direct Solver " << std::left
                      << std::setw(8) << direct << std::right << ": synthesis " << seconds << " s (bases "
                      << model.basesSeconds() << " s), " << model.size() << " coordinates, peak MiB " << peak.max
                      << " (" << peak.sum << "), max |f - f_CHOLMOD| / f = " << worst << '\n';
        }
      }
      if (!truth) continue;
      std::vector<double> reference;
      for (const char* direct : {"CHOLMOD", "MUMPS"}) {
        memory.open();
        Teuchos::ParameterList p = sc.solve;
        p.set("Solver", std::string("Sparse"));
        p.set("Number of Modes", modes);
        p.sublist("Sparse Solver").set("Direct Solver", std::string(direct));
        const Stopwatch t;
        const auto result = full.solve(speeds, p);
        const double seconds = t.seconds();
        const auto peak = memory.peak();
        double worst = 0.0;
        std::vector<double> hz;
        for (const auto& mode : result.result.modes) hz.push_back(mode.hz);
        if (reference.empty()) reference = hz;
        for (std::size_t k = 0; k < std::min(hz.size(), reference.size()); ++k)
          worst = std::max(worst, std::abs(hz[k] - reference[k]) / reference[k]);
        if (root)
          std::cout << "  truth, Direct Solver " << std::left << std::setw(8) << direct << std::right << seconds
                    << " s, " << hz.size() << " modes, " << eigen::toString(result.result.status)
                    << ", max |f - f_CHOLMOD| / f = " << worst << ", peak MiB " << peak.max << " (" << peak.sum
                    << "); " << result.result.solver << '\n';
      }
    }
    return ExitSuccess;
  });
}
