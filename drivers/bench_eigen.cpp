// bench_eigen: time the gyroscopic eigensolver paths against each other on
// systems of growing size, in one run (ratios, not absolute timings, are what
// this noisy 2-core machine can compare), with each path's accuracy.
//
// The structure is models::RotatingChain held at its ends (masses on springs in a
// frame spinning at half its first critical speed, so K > 0 and every path
// applies; its low modes are string-like and well separated): for each
// size it runs the dense Meirovitch path (up to --max-dense DOFs), Anasazi
// Block Krylov-Schur, LOBPCG and Block Davidson, and PARPACK, all asked for
// the same lowest --modes modes, and reports wall time, iterations, operator
// applications, the largest residual, the largest frequency difference from
// Block Krylov-Schur, and the process's peak resident memory so far.
//
// Sample runs:
//   bench_eigen                                  # 1e3 .. 1e6 DOFs
//   bench_eigen --max-dofs=100000 --csv=eig.csv
//   mpiexec -n 2 bench_eigen --max-dofs=1000000
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <vector>

#include <Teuchos_CommandLineProcessor.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Teuchos_Time.hpp>
#include <Tpetra_Core.hpp>

#include "DriverBoundary.hpp"
#include "cms/core/Error.hpp"
#include "cms/core/PeakMemory.hpp"
#include "cms/eigen/DenseGyroscopicSolver.hpp"
#include "cms/eigen/SparseGyroscopicSolver.hpp"
#include "cms/models/RotatingChain.hpp"
#include "cms/core/Program.hpp"

namespace {

struct Row {
  long long dofs;
  std::string path;
  double seconds, maxResidual, maxFreqDiff, peakMiB;
  int iterations, applies, modes;
  std::string status;
};
}  // namespace

int main(int argc, char* argv[]) {
  using namespace cms;
  using cms::peakRssMiB;
  cms::hugePageHeap(argv);      // the heap on transparent huge pages (re-executes once)
  cms::singletonMpiDefaults();  // a lone process: no daemon, no fabric probing
  Tpetra::ScopeGuard scope(&argc, &argv);
  const auto comm = Teuchos::DefaultComm<int>::getComm();
  const bool root = comm->getRank() == 0;
  return drivers::reportErrors("bench_eigen", root, [&]() -> int {
    // 1. Options.
    double maxDofs = 1e6;
    int maxDense = 2000, modes = 10;
    std::string csv = "bench_eigen.csv";
    double maxAllIterative = 2000;
    Teuchos::CommandLineProcessor clp(false, true);
    clp.setOption("max-dofs", &maxDofs, "largest system size");
    clp.setOption("max-dense", &maxDense, "largest size for the dense path");
    clp.setOption("modes", &modes, "modes per solve");
    clp.setOption("csv", &csv, "CSV output file");
    clp.setOption("max-all-iterative", &maxAllIterative,
                  "largest size at which LOBPCG and Block Davidson also run (they need far more "
                  "operator applications; doc/benchmarks.md)");
    if (clp.parse(argc, argv) != Teuchos::CommandLineProcessor::PARSE_SUCCESSFUL) return ExitInputError;
    if (root)
      std::cout << "bench_eigen: " << comm->getSize() << " rank(s), " << modes
                << " modes, sizes to " << maxDofs << " DOFs (dense to " << maxDense << ")"
                << std::endl;

    // 2. Sweep the sizes.
    std::vector<Row> rows;
    for (long long dofs : {1000LL, 2000LL, 10000LL, 100000LL, 1000000LL}) {
      if (dofs > maxDofs) break;
      models::RotatingChain chain;
      chain.nodes = dofs / 2;
      chain.support = models::RotatingChain::Support::Ends;
      chain.spin = chain.subcriticalSpin(0.5);
      const auto d = chain.distributed(comm);
      eigen::SparseGyroscopicSystem sys{d.M, d.G, d.K};
      std::vector<double> reference;
      auto record = [&](const std::string& path, const eigen::GyroscopicResult& r, double secs) {
        Row row{dofs, path, secs, r.maxResidual(), 0.0, peakRssMiB(), r.iterations,
                r.numOperatorApplies, static_cast<int>(r.modes.size()), eigen::toString(r.status)};
        for (std::size_t k = 0; k < r.modes.size() && k < reference.size(); ++k)
          row.maxFreqDiff = std::max(row.maxFreqDiff, std::abs(r.modes[k].omega - reference[k]) / reference[k]);
        rows.push_back(row);
        if (root)
          std::cout << std::setw(9) << dofs << "  " << std::left << std::setw(22) << path << std::right
                    << std::fixed << std::setprecision(3) << std::setw(10) << secs << " s  "
                    << std::scientific << std::setprecision(1) << "resid " << row.maxResidual
                    << "  vs BKS " << row.maxFreqDiff << "  " << row.status << std::endl
                    << std::defaultfloat;
      };
      std::vector<std::string> solvers = {"Block Krylov-Schur", "ARPACK"};
      if (dofs <= maxAllIterative) solvers.insert(solvers.end(), {"LOBPCG", "Block Davidson"});
      for (const auto& es : solvers) {
        Teuchos::ParameterList p;
        p.set("Eigensolver", es);
        p.set("Number of Modes", modes);
        Teuchos::Time t("solve", true);
        const auto r = eigen::SparseGyroscopicSolver(p).solve(sys);
        const double secs = t.stop();
        if (es == "Block Krylov-Schur")
          for (const auto& m : r.modes) reference.push_back(m.omega);
        record(es, r, secs);
      }
      if (dofs <= maxDense) {
        // Both reductions of the skew factor (theory §2): the skew
        // tridiagonal form (the default) and the general bidiagonal form.
        const auto dd = chain.dense();
        for (const std::string reduction : {"Skew Tridiagonal", "Bidiagonal"}) {
          Teuchos::ParameterList p;
          p.set("Number of Modes", modes);
          p.set("Reduction", reduction);
          Teuchos::Time t("dense", true);
          const auto r = eigen::DenseGyroscopicSolver(p).solve({dd.M, dd.G, dd.K});
          record(reduction == "Bidiagonal" ? "dense Meirovitch (bidiagonal)" : "dense Meirovitch", r, t.stop());
        }
      }
    }

    // 3. The table as CSV (rank 0).
    if (root) {
      std::ofstream out(csv);
      CMS_INPUT_CHECK(!out, "bench_eigen: cannot write " << csv);
      out << "dofs,ranks,path,seconds,iterations,operator_applies,modes,max_residual,"
             "max_rel_freq_diff_vs_bks,peak_rss_mib,status\n";
      for (const auto& r : rows)
        out << r.dofs << "," << comm->getSize() << ",\"" << r.path << "\"," << r.seconds << ","
            << r.iterations << "," << r.applies << "," << r.modes << "," << r.maxResidual << ","
            << r.maxFreqDiff << "," << r.peakMiB << "," << r.status << "\n";
      std::cout << "wrote " << csv << "\n";
    }
    return ExitSuccess;
  });
}
