#include "cms/core/HugePageHeap.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#if defined(__linux__) && defined(__GLIBC__)
#include <gnu/libc-version.h>
#include <unistd.h>
#endif

namespace cms {

std::string hugePageHeapSkipped() {
#if defined(__linux__) && defined(__GLIBC__)
  if (const char* opt = std::getenv("CMS_HUGE_PAGES"); opt != nullptr && std::strcmp(opt, "0") == 0)
    return "CMS_HUGE_PAGES=0";
  // The tunable exists from glibc 2.35 (older ones ignore it).
  int major = 0, minor = 0;
  if (std::sscanf(gnu_get_libc_version(), "%d.%d", &major, &minor) != 2 || major < 2 || (major == 2 && minor < 35))
    return std::string("glibc ") + gnu_get_libc_version() + " has no glibc.malloc.hugetlb";
  std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(thp, modes);
  if (modes.find("[always]") == std::string::npos && modes.find("[madvise]") == std::string::npos)
    return "transparent huge pages are off (" + (modes.empty() ? std::string("no THP") : modes) + ")";
  // Under valgrind /proc/self/exe is valgrind's own tool.
  if (const char* pre = std::getenv("LD_PRELOAD"); pre != nullptr && std::strstr(pre, "vgpreload") != nullptr)
    return "under valgrind";
  return "";
#else
  return "not Linux with glibc";
#endif
}

void hugePageHeap(char** argv) {
#if defined(__linux__) && defined(__GLIBC__)
  const char* given = std::getenv("GLIBC_TUNABLES");
  const std::string tunables = given != nullptr ? given : "";
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos) return;  // chosen already, by us or the user
  if (!hugePageHeapSkipped().empty()) return;
  const std::string with = tunables.empty() ? "glibc.malloc.hugetlb=1" : tunables + ":glibc.malloc.hugetlb=1";
  setenv("GLIBC_TUNABLES", with.c_str(), 1);
  execv("/proc/self/exe", argv);
  // The exec failed: go on as we are (the variable stays for children).
#else
  (void)argv;
#endif
}

}  // namespace cms
