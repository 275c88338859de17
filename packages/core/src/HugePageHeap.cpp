#include "cms/core/HugePageHeap.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#if defined(__linux__) && defined(__GLIBC__)
#include <fcntl.h>
#include <gnu/libc-version.h>
#include <malloc.h>
#include <unistd.h>
#endif

namespace cms {

namespace {
#if defined(__linux__) && defined(__GLIBC__)
constexpr const char* kExecutedOnce = "CMS_HUGE_PAGES_EXECUTED";

/// The value of `name` in the environment block `envp`, or nullptr. The
/// block is passed explicitly: from the executable's .preinit_array this
/// runs before libc has set `environ` (getenv there found nothing, and the
/// process executed itself for ever).
const char* lookup(char** envp, const char* name) {
  const std::size_t n = std::strlen(name);
  for (char** e = envp; e != nullptr && *e != nullptr; ++e)
    if (std::strncmp(*e, name, n) == 0 && (*e)[n] == '=') return *e + n + 1;
  return nullptr;
}

/// The first line of a small file, with POSIX calls only (no iostreams:
/// libstdc++'s initialisers have not run yet from .preinit_array).
std::string firstLine(const char* path) {
  const int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";
  char buffer[256];
  const ssize_t got = read(fd, buffer, sizeof(buffer) - 1);
  close(fd);
  if (got <= 0) return "";
  std::string line(buffer, static_cast<std::size_t>(got));
  return line.substr(0, line.find('\n'));
}

std::string skippedIn(char** envp) {
  if (const char* opt = lookup(envp, "CMS_HUGE_PAGES"); opt != nullptr && std::strcmp(opt, "0") == 0)
    return "CMS_HUGE_PAGES=0";
  // The tunable exists from glibc 2.35 (older ones ignore it).
  int major = 0, minor = 0;
  if (std::sscanf(gnu_get_libc_version(), "%d.%d", &major, &minor) != 2 || major < 2 || (major == 2 && minor < 35))
    return std::string("glibc ") + gnu_get_libc_version() + " has no glibc.malloc.hugetlb";
  const std::string modes = firstLine("/sys/kernel/mm/transparent_hugepage/enabled");
  if (modes.find("[always]") == std::string::npos && modes.find("[madvise]") == std::string::npos)
    return "transparent huge pages are off (" + (modes.empty() ? std::string("no THP") : modes) + ")";
  // Under valgrind /proc/self/exe is valgrind's own tool.
  if (const char* pre = lookup(envp, "LD_PRELOAD"); pre != nullptr && std::strstr(pre, "vgpreload") != nullptr)
    return "under valgrind";
  return "";
}

/// Executes /proc/self/exe again with `envp` plus glibc.malloc.hugetlb=1
/// in GLIBC_TUNABLES, unless the tunable is there already or a reason skips
/// it. Returns only when it did not (or the exec failed: the process then
/// goes on as it is).
void reexecute(char** argv, char** envp) {
  const char* given = lookup(envp, "GLIBC_TUNABLES");
  const std::string tunables = given != nullptr ? given : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos) return;  // chosen already, by us or the user
  // Executed once already, yet the tunable is gone (a loader that drops
  // GLIBC_TUNABLES, as glibc does for set-user-ID programs): once only.
  if (lookup(envp, kExecutedOnce) != nullptr) return;
  if (!skippedIn(envp).empty()) return;
  const std::string with =
      "GLIBC_TUNABLES=" + (tunables.empty() ? std::string() : tunables + ":") + "glibc.malloc.hugetlb=1";
  std::vector<char*> env;
  for (char** e = envp; e != nullptr && *e != nullptr; ++e)
    if (std::strncmp(*e, "GLIBC_TUNABLES=", 15) != 0) env.push_back(*e);
  env.push_back(const_cast<char*>(with.c_str()));
  std::string once = std::string(kExecutedOnce) + "=1";
  env.push_back(once.data());
  env.push_back(nullptr);
  execve("/proc/self/exe", argv, env.data());
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

std::string hugePageHeapSkipped() {
#if defined(__linux__) && defined(__GLIBC__)
  return skippedIn(environ);
#else
  return "not Linux with glibc";
#endif
}

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
