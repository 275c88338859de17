// The environment that puts a process's heap on transparent huge pages
// (cms/core/HugePageHeap.hpp): libc only, no Trilinos, so that the cms
// launcher (drivers/cms/launcher.cpp) builds it too.
#include "cms/core/HugePageHeap.hpp"

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#if defined(__linux__) && defined(__GLIBC__)
#include <fcntl.h>
#include <gnu/libc-version.h>
#include <unistd.h>
#endif

namespace cms {

#if defined(__linux__) && defined(__GLIBC__)
namespace {
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
}  // namespace

std::string hugePageHeapSkippedIn(char** envp) {
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

bool withHugePageTunable(char** envp, HugePageEnvironment& out) {
  const char* given = lookup(envp, "GLIBC_TUNABLES");
  const std::string tunables = given != nullptr ? given : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos) return false;  // chosen already, by us or the user
  // Executed once already, yet the tunable is gone (a loader that drops
  // GLIBC_TUNABLES, as glibc does for set-user-ID programs): once only.
  if (lookup(envp, kExecutedOnce) != nullptr) return false;
  if (!hugePageHeapSkippedIn(envp).empty()) return false;
  out.tunables = "GLIBC_TUNABLES=" + (tunables.empty() ? std::string() : tunables + ":") + "glibc.malloc.hugetlb=1";
  out.marker = std::string(kExecutedOnce) + "=1";
  out.block.clear();
  for (char** e = envp; e != nullptr && *e != nullptr; ++e)
    if (std::strncmp(*e, "GLIBC_TUNABLES=", 15) != 0) out.block.push_back(*e);
  out.block.push_back(out.tunables.data());
  out.block.push_back(out.marker.data());
  out.block.push_back(nullptr);
  return true;
}
#else
std::string hugePageHeapSkippedIn(char**) { return "not Linux with glibc"; }
bool withHugePageTunable(char**, HugePageEnvironment&) { return false; }
#endif

}  // namespace cms
