#include "cms/core/BlasThreads.hpp"

#include <dlfcn.h>
#if defined(__linux__)
#include <sched.h>
#endif

#include <algorithm>
#include <cstdlib>
#include <thread>

#include "cms/core/DistributedDirectSolver.hpp"

namespace cms {

namespace {

// OpenBLAS's controls, looked up in the process (the BLAS cms linked is
// whichever Debian alternative libblas.so.3 points to).
using SetThreads = void (*)(int);
using GetThreads = int (*)();

SetThreads setter() {
  static const auto f = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  return f;
}
GetThreads getter() {
  static const auto f = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  return f;
}

}  // namespace

int blasThreads() { return getter() != nullptr ? std::max(1, getter()()) : 1; }

bool setBlasThreads(int n) {
  if (setter() == nullptr || n < 1) return false;
  setter()(n);
  return true;
}

BlasThreadScope::BlasThreadScope(int n) : previous_(blasThreads()) { setBlasThreads(n); }

BlasThreadScope::~BlasThreadScope() { setBlasThreads(previous_); }

int usableCores() {
  const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
#if defined(__linux__)
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (sched_getaffinity(0, sizeof(mask), &mask) == 0) return std::max(1, std::min(hardware, CPU_COUNT(&mask)));
#endif
  return hardware;
}

int coresPerRank(int ranksOnThisNode) {
  const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return std::max(1, std::min(usableCores(), hardware / std::max(1, ranksOnThisNode)));
}

int shareCoresWithBlas(const Teuchos::Comm<int>& comm) {
  const int onNode = ranksOnNode(comm);  // collective: before any rank returns
  for (const char* chosen : {"OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS"})
    if (std::getenv(chosen) != nullptr) return blasThreads();
  setBlasThreads(coresPerRank(onNode));
  return blasThreads();
}

}  // namespace cms
