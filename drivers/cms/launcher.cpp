// cms: the command users run. It starts cms-engine, the scene-driven driver
// beside it (main.cpp: modes, campbell, compare, truncate), with the same
// arguments and its environment plus the heap's tunable
// (cms/core/HugePageHeap.hpp), so that the engine starts once.
//
// Why a launcher: glibc reads GLIBC_TUNABLES only when a process starts,
// so an engine started without the tunable executes itself again from its
// .preinit_array, after the loader has mapped and relocated its 56 shared
// libraries (Trilinos, Open MPI, MUMPS, OpenBLAS): ~40 ms of a start, a
// tenth of a small scene's run (doc/benchmarks.md, "Fewer sparse products,
// one start, freed blocks kept").
// This program maps glibc alone (its C++ runtime is linked in statically:
// drivers/CMakeLists.txt). cms-engine run directly still
// works as before: it executes itself again.
//
//   cms modes drivers/bench/bar-hex64.yaml
//   mpiexec -n 2 cms modes            (each rank: launcher, then engine, one PID)
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include <unistd.h>

#include "cms/core/HugePageHeap.hpp"

int main(int argc, char* argv[]) {
  (void)argc;
  // 1. The engine: cms-engine in this executable's own directory (build/drivers,
  //    or <prefix>/bin), whatever the PATH or the name it was started by.
  //    Without /proc (a container or chroot that mounts none), the
  //    directory of the path it was started by; started by a bare name
  //    from the PATH there is none to go by, and it refuses rather than run
  //    a "cms-engine" of the working directory
  //    (tests/check_launcher_without_proc.py).
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
  std::string path;
  if (n > 0) path.assign(self, static_cast<std::size_t>(n));
  else if (argv[0] != nullptr && std::strchr(argv[0], '/') != nullptr) path = argv[0];
  if (path.empty()) {
    std::fprintf(stderr,
                 "cms: cannot find its own directory to start cms-engine beside it: /proc/self/exe cannot be read "
                 "(%s) and it was started by a bare name (%s); start it by its path, or run cms-engine directly\n",
                 std::strerror(errno), argv[0] != nullptr ? argv[0] : "");
    return 5;
  }
  const std::string engine = path.substr(0, path.rfind('/') + 1) + "cms-engine";
  // 2. Its environment: this one, plus the heap's tunable unless it is there
  //    or a reason skips it (CMS_HUGE_PAGES=0, no THP, glibc < 2.35).
  cms::HugePageEnvironment env;
  char** block = cms::withHugePageTunable(environ, env) ? env.block.data() : environ;
  execve(engine.c_str(), argv, block);
  // 3. Reached only if the engine could not be started: an installation
  //    without it. Exit code 5, as for an internal error (Error.hpp).
  std::fprintf(stderr, "cms: cannot start the engine %s: %s (it is installed beside cms; a build makes both)\n",
               engine.c_str(), std::strerror(errno));
  return 5;
}
