// cms: run a scene — a structure of substructures with rotating parts — by
// component-mode synthesis (doc/user-guide.md, "The cms driver").
//
//   cms modes [SCENE]     the lowest modes at the scene's speeds, each with its
//                         residual, estimated error and missing-mode check (modes.cpp)
//   cms campbell [SCENE]  a speed sweep: tracked modes, critical speeds (campbell.cpp)
//   cms compare [SCENE]   every reduction strategy against the truth (compare.cpp)
//   cms truncate [SCENE]  vector counts for an accuracy, from the estimates (truncate.cpp)
//
// `cms <subcommand> --help` lists that subcommand's options. Without SCENE
// the built-in spacecraft runs. Results go to --output (default
// ./cms-results, or the scene's "Output" directory), only when the run
// succeeded.
//
// Exit codes (drivers/DriverBoundary.hpp, the one table of outcomes): 0
// success, 2 bad input (scene, options), 3 numerical breakdown, 4 a solve
// did not converge or an accuracy was not reached, 5 internal error.
//
// Sample runs:
//   cms modes
//   cms modes drivers/scenes/spacecraft.yaml --output=/tmp/sc
//   mpiexec -n 2 cms compare --counts=2,4,8
//   cms campbell --steps=41 --max-factor=3 --orders=1,2
//   cms truncate --accuracy=1e-4
#include <iostream>
#include <map>
#include <string>

#include <Teuchos_DefaultComm.hpp>
#include <Teuchos_GlobalMPISession.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include "../DriverBoundary.hpp"
#include "Command.hpp"
#include "cms/core/BlasThreads.hpp"
#include "cms/core/Program.hpp"

namespace cms::drivers {
int modes(int argc, char* argv[]);
int campbell(int argc, char* argv[]);
int compare(int argc, char* argv[]);
int truncate(int argc, char* argv[]);
}  // namespace cms::drivers

int main(int argc, char* argv[]) {
  using namespace cms;
  cms::hugePageHeap(argv);      // the heap on transparent huge pages (re-executes once)
  cms::singletonMpiDefaults();  // a lone process: no daemon, no fabric probing
  Teuchos::GlobalMPISession mpi(&argc, &argv, nullptr);
  const bool root = Teuchos::DefaultComm<int>::getComm()->getRank() == 0;
  cms::shareCoresWithBlas(*Teuchos::DefaultComm<int>::getComm());  // each rank's BLAS on its share of the cores
  const std::map<std::string, int (*)(int, char*[])> subcommands{
      {"modes", drivers::modes}, {"campbell", drivers::campbell}, {"compare", drivers::compare},
      {"truncate", drivers::truncate}};
  const int code = drivers::reportErrors("cms", root, [&]() -> int {
    // 1. The subcommand.
    const std::string command = argc > 1 ? argv[1] : "";
    if (command == "--version") {
      if (root) std::cout << "cms " << CMS_VERSION << '\n';
      return ExitSuccess;
    }
    const auto it = subcommands.find(command);
    if (it == subcommands.end()) {
      if (root)
        std::cout << "usage: cms modes|compare|campbell|truncate [SCENE] [options]   (cms <subcommand> --help: its options)\n"
                     "  modes     the structure's lowest modes at the scene's speeds, with their accuracy\n"
                     "  compare   every reduction strategy against the truth model\n"
                     "  campbell  a speed sweep with modes tracked by MAC and critical speeds\n"
                     "  truncate  vectors added where they help most, to a requested accuracy\n"
                     "  SCENE     a YAML scene (default: the built-in spacecraft,\n"
                     "            <prefix>/share/cms/scenes/spacecraft.yaml)\n";
      return command.empty() || command == "--help" || command == "-h" ? ExitSuccess : ExitInputError;
    }
    // 2. Run it; --timers prints the phases' times.
    const int code = it->second(argc, argv);
    bool timers = false;
    for (int i = 2; i < argc; ++i) timers = timers || std::string(argv[i]) == "--timers";
    if (timers) Teuchos::TimeMonitor::summarize(std::cout);
    return code;
  });
  if (code != ExitSuccess) drivers::removeCreatedOutputIfEmpty();
  return code;
}
