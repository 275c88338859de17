#include "cms/core/HugePageHeap.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#if defined(__linux__) && defined(__GLIBC__)
#include <malloc.h>
#include <unistd.h>
#endif

namespace cms {

namespace {
#if defined(__linux__) && defined(__GLIBC__)
/// Executes /proc/self/exe again with `envp` plus the heap's tunable
/// (withHugePageTunable), unless it needs none. Returns only when it did
/// not (or the exec failed: the process then goes on as it is).
void reexecute(char** argv, char** envp) {
  HugePageEnvironment env;
  if (withHugePageTunable(envp, env)) execve("/proc/self/exe", argv, env.block.data());
}
#endif
}  // namespace

std::string freedBlocksKeptSkipped() {
#if defined(__linux__) && defined(__GLIBC__)
  const char* given = std::getenv("GLIBC_TUNABLES");
  if (given != nullptr && (std::strstr(given, "glibc.malloc.mmap_threshold") != nullptr ||
                           std::strstr(given, "glibc.malloc.trim_threshold") != nullptr))
    return "GLIBC_TUNABLES sets the thresholds";
  if (const char* opt = std::getenv("CMS_KEEP_FREED"); opt != nullptr && std::strcmp(opt, "0") == 0)
    return "CMS_KEEP_FREED=0";
  return "";
#else
  return "not Linux with glibc";
#endif
}

std::string hugePageHeapSkipped() { return hugePageHeapSkippedIn(environ); }

void hugePageHeap(char** argv) {
#if defined(__linux__) && defined(__GLIBC__)
  reexecute(argv, environ);
  // Blocks up to kKeptBlockBytes come from the heap and stay there when
  // freed, for the next allocation to reuse (HugePageHeap.hpp). glibc's own
  // rule raises its threshold to the largest block freed so far, up to 32
  // MiB, and trims at twice that: the same rule with a higher ceiling.
  if (freedBlocksKeptSkipped().empty()) {
    mallopt(M_MMAP_THRESHOLD, static_cast<int>(kKeptBlockBytes));
    mallopt(M_TRIM_THRESHOLD, static_cast<int>(2 * kKeptBlockBytes));
  }
#else
  (void)argv;
#endif
}

}  // namespace cms

#if defined(__linux__) && defined(__GLIBC__)
namespace {
/// The executable's .preinit_array runs before any shared library's
/// initialisers (OpenBLAS's thread pool, Open MPI's, Kokkos', Teuchos'):
/// executed again from here, the first start costs the loader's relocations
/// only (the second start cost ~50 ms from main). It comes with this object
/// into every program that calls hugePageHeap, whose own call in main then
/// finds the tunable set. A shared library's .preinit_array is ignored, so
/// this acts in executables only; glibc passes argc, argv and envp.
void hugePageHeapBeforeLibraries(int, char** argv, char** envp) { cms::reexecute(argv, envp); }
}  // namespace
__attribute__((section(".preinit_array"), used)) static void (*const cmsHugePageHeapPreinit)(int, char**, char**) =
    hugePageHeapBeforeLibraries;
#endif
