// What a cms program's main does around its own steps: MPI started and
// finished, every exception turned into one message on rank 0 and an exit
// code (ProgramBoundary.hpp), and the options declared once each with a
// help string, parsed, and printed back on rank 0 so that every output
// records how it was made (as MFEM's examples do). The examples
// (examples/ex*.cpp), built against the installed library, start this way.
#pragma once

#include <cstdlib>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <Teuchos_CommandLineProcessor.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_Core.hpp>

#include "cms/core/BlasThreads.hpp"
#include "cms/core/HugePageHeap.hpp"
#include "cms/core/ProgramBoundary.hpp"

namespace cms {

using CommPtr = Teuchos::RCP<const Teuchos::Comm<int>>;

/// Before MPI starts: a program started without a launcher (no mpiexec,
/// srun: a "singleton") gets Open MPI's defaults for a lone process unless
/// the environment already sets them: no helper daemon
/// (ess_singleton_isolated) and the ob1 messaging layer instead of probing
/// UCX and libfabric, which a single process never uses. MPI_Init alone
/// took 0.45 s by default and 0.05 s so (doc/benchmarks.md, "Process
/// start"), a fifth of a small scene's whole run. Nor does it need the
/// plugins hwloc loads to find devices (PCI, OpenGL and OpenCL devices) or
/// read XML topologies with libxml2: they bring libX11, libOpenCL, libxml2
/// and ICU, ~15 ms of the loader's time in every start (doc/benchmarks.md,
/// "Fewer sparse products, one start, freed blocks kept");
/// HWLOC_PLUGINS_BLACKLIST leaves them unloaded (hwloc's built-in XML
/// reader remains). Nor hwloc's reading of every PCI, block and network
/// device from /sys (its linuxio component; the cores and caches come from
/// its linux component): HWLOC_COMPONENTS=-linuxio, `cms --help` 98 to 80
/// ms, 20 runs each (doc/benchmarks.md, "Libraries from the working
/// directory, hwloc's devices, ..."). Nor the transports to
/// other processes, the collectives' algorithms for many ranks or one-sided
/// communication across nodes: the components Open MPI opens for them
/// (tcp, vader, sm; tuned, han, adapt, ...; rdma) are left unopened
/// (btl self; coll self, basic and libnbc; osc sm): 4-5 ms of a start,
/// `cms-engine --version` 92 to 88 ms, medians of 15. A launched run is
/// left alone: a cluster's launcher and its fabric choose there.
inline void singletonMpiDefaults() {
  for (const char* launched : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "SLURM_PROCID"})
    if (std::getenv(launched) != nullptr) return;
  setenv("OMPI_MCA_ess_singleton_isolated", "1", /*overwrite*/ 0);
  setenv("OMPI_MCA_pml", "ob1", 0);
  setenv("OMPI_MCA_btl", "self", 0);
  setenv("OMPI_MCA_coll", "self,basic,libnbc", 0);
  setenv("OMPI_MCA_osc", "sm", 0);
  setenv("HWLOC_PLUGINS_BLACKLIST", "hwloc_pci.so,hwloc_gl.so,hwloc_opencl.so,hwloc_xml_libxml.so", 0);
  setenv("HWLOC_COMPONENTS", "-linuxio", 0);
}

/// Runs `body(comm, root)` between MPI's start (hugePageHeap,
/// singletonMpiDefaults, then
/// Tpetra::ScopeGuard, then shareCoresWithBlas) and end
/// inside reportErrors(program, ...): returns body's exit code, or the code
/// of the exception it threw, with its message printed on rank 0. `argc`
/// and `argv` are those of main, as MPI leaves them.
template <class Body>
int runProgram(const char* program, int& argc, char**& argv, Body&& body) {
  hugePageHeap(argv);
  singletonMpiDefaults();
  Tpetra::ScopeGuard mpi(&argc, &argv);
  const CommPtr comm = Teuchos::DefaultComm<int>::getComm();
  shareCoresWithBlas(*comm);  // each rank's BLAS on its share of the cores
  const bool root = comm->getRank() == 0;
  return reportErrors(program, root, [&]() -> int { return body(comm, root); });
}

/// A program's options: each declared once with its help string
/// (Teuchos::CommandLineProcessor underneath; an unknown option is an
/// error), and after parsing printed back as the command line that
/// reproduces the run.
class ProgramOptions {
public:
  /// `program`: the name printed back; `doc`: what it computes, for --help.
  ProgramOptions(std::string program, const std::string& doc) : program_(std::move(program)), clp_(false, true) {
    clp_.setDocString(doc.c_str());
  }

  /// --name=value into *value (int, double or std::string); *value is the
  /// default --help shows. `value` must outlive parse().
  template <class T>
  void add(const char* name, T* value, const char* help) {
    clp_.setOption(name, value, help);
    echo_.push_back([name, value](std::ostream& os) { os << " --" << name << "=" << *value; });
  }

  /// Parses argv[1..]. Returns the exit code when the program ends here
  /// (--help printed: ExitSuccess; an unknown or malformed option, which
  /// Teuchos names: ExitInputError), nothing when it goes on, after
  /// printing "<program> --name=value ... on <n> rank(s)" on rank 0.
  std::optional<int> parse(int argc, char* argv[], const Teuchos::Comm<int>& comm) {
    switch (clp_.parse(argc, argv)) {
      case Teuchos::CommandLineProcessor::PARSE_SUCCESSFUL: break;
      case Teuchos::CommandLineProcessor::PARSE_HELP_PRINTED: return ExitSuccess;
      default: return ExitInputError;
    }
    if (comm.getRank() == 0) {
      std::cout << program_;
      for (const auto& echo : echo_) echo(std::cout);
      std::cout << " on " << comm.getSize() << " rank(s)\n";
    }
    return std::nullopt;
  }

private:
  std::string program_;
  Teuchos::CommandLineProcessor clp_;
  std::vector<std::function<void(std::ostream&)>> echo_;
};

}  // namespace cms
